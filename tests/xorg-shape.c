/* Random bounding shapes for X windows (xorg-shape.h). */
#include "xorg-shape.h"

uint32_t xorg_random_shape(struct vis_rng *rng, uint32_t w, uint32_t h, uint32_t border,
			   xcb_rectangle_t r[2], bool *past_box)
{
	int16_t b = (int16_t)border;
	uint16_t bw = (uint16_t)(w + 2 * border), bh = (uint16_t)(h + 2 * border);
	*past_box = false;
	switch (vis_rng_below(rng, 4)) {
	case 0:
		return 0;
	case 1:
		r[0] = (xcb_rectangle_t){ (int16_t)-b, (int16_t)-b, bw, (uint16_t)(bh / 2 ? bh / 2 : 1) };
		r[1] = (xcb_rectangle_t){ (int16_t)-b, (int16_t)(-b + bh / 2),
					  (uint16_t)(bw / 2 ? bw / 2 : 1), (uint16_t)(bh - bh / 2) };
		return 2;
	case 2:
		r[0] = (xcb_rectangle_t){ (int16_t)-b, (int16_t)-b, (uint16_t)((bw + 1) / 2),
					  (uint16_t)((bh + 1) / 2) };
		return 1;
	default:
		r[0] = (xcb_rectangle_t){ (int16_t)-b, (int16_t)-b, bw, bh };
		r[1] = (xcb_rectangle_t){ (int16_t)(w / 2), (int16_t)(h / 2), bw, bh };
		*past_box = true;
		return 2;
	}
}
