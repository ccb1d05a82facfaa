/* What visctl's SVG writers share: the document's start and text escaping. Output through stdio. */
#ifndef VISCTL_SVG_H
#define VISCTL_SVG_H

#include <stdio.h>

/*
 * Starts a standalone SVG document of width × height user units (one per CSS pixel), with a white
 * background; the caller writes the content and "</svg>\n".
 */
void svg_begin(FILE *f, double width, double height);

/* Writes s as XML text or attribute content: &, <, > and " escaped. */
void svg_text(FILE *f, const char *s);

#endif
