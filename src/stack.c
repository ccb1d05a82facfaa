#include "stack.h"

const char *vis_state_name(enum vis_state state)
{
	switch (state) {
	case VIS_UNOBSCURED:
		return "unobscured";
	case VIS_PARTIALLY_OBSCURED:
		return "partially-obscured";
	case VIS_FULLY_OBSCURED:
		return "fully-obscured";
	case VIS_NO_STATE:
		return "none";
	}
	return "invalid";
}

static struct vis_box screen_box(const struct vis_stack *stack)
{
	struct vis_box s = { 0, 0, stack->screen_w, stack->screen_h };
	return s;
}

struct vis_box vis_stack_clip(const struct vis_stack *stack, size_t i)
{
	struct vis_box b = vis_rect_box(stack->rects[i]);
	return stack->has_screen ? vis_box_intersect(b, screen_box(stack)) : b;
}

bool vis_stack_on_screen(const struct vis_stack *stack, size_t i)
{
	return !stack->has_screen ||
	       vis_box_contains(screen_box(stack), vis_rect_box(stack->rects[i]));
}
