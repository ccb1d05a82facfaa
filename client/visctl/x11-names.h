/*
 * X's own names for X windows, for `visctl states --x11 --names`: visd knows a mirrored window
 * only by its XID (its external tag), so visctl asks the X server itself, as xwininfo -tree does.
 * Built with xcb where it is found (meson's x11 option); without it every call fails, saying so.
 */
#ifndef VISCTL_X11_NAMES_H
#define VISCTL_X11_NAMES_H

#include <stddef.h>
#include <stdint.h>

/*
 * One window's name and class as X has them: name from _NET_WM_NAME, else WM_NAME; instance and
 * class_name, WM_CLASS's two strings. NULL where the window has no such property (or is gone).
 */
struct x11_name {
	char *name;
	char *instance;
	char *class_name;
};

/*
 * Reads the names of n windows from the X display (NULL: $DISPLAY) into names[0 … n-1], with one
 * round trip for all of them. Returns 0, or -1 with a reason in err (no xcb in this build, no
 * display); the caller frees the strings with x11_names_finish() either way.
 */
int x11_names_read(const char *display, const uint32_t *xids, size_t n, struct x11_name *names,
		   char *err, size_t err_len);

/* Frees the strings of n names (a NULL names is a no-op). */
void x11_names_finish(struct x11_name *names, size_t n);

#endif
