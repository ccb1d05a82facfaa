/*
 * What libvis (vis/vis.h) and libvisclient (vis/visclient.h) share, defined once so that a
 * program can include both: the export mark of their public functions and the rectangle.
 */
#ifndef VIS_COMMON_H
#define VIS_COMMON_H

#include <stdint.h>

#if defined(__GNUC__)
#define VIS_EXPORT __attribute__((visibility("default")))
#else
#define VIS_EXPORT
#endif

/*
 * A rectangle: x, y inclusive, x + width, y + height exclusive. About a window (shapes, opaque
 * regions, visible regions, exposures, the parts of a repaint) it is in window coordinates:
 * relative to the window's inside's top-left corner, its border at negative coordinates
 * (PROTOCOL.md, "Window coordinates"); a damaged area of the screen is in screen coordinates.
 */
struct vis_rect32 {
	int32_t x, y;
	uint32_t width, height;
};

#endif
