/*
 * X's names for X windows (x11-names.h): GetProperty requests for every window sent at once,
 * then their replies, on a connection of its own that lives for one call.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "x11-names.h"

#ifdef VISCTL_HAVE_XCB
#include <xcb/xcb.h>

/* The properties read per window, in the order their requests go out. */
enum { NET_WM_NAME, WM_NAME, WM_CLASS, N_PROPS };

/* A copy of len bytes as a string (NULL when memory runs out). */
static char *copy(const char *v, size_t len)
{
	char *s = malloc(len + 1);
	if (s) {
		memcpy(s, v, len);
		s[len] = '\0';
	}
	return s;
}

/*
 * A property's value (8-bit items), or NULL when the window lacks it (or is gone); WM_CLASS's
 * is split at its NUL into the instance (the value) and the class (*second).
 */
static char *value(xcb_connection_t *x, xcb_get_property_cookie_t cookie, char **second)
{
	xcb_get_property_reply_t *r = xcb_get_property_reply(x, cookie, NULL);
	char *s = NULL;
	if (r && r->type != XCB_ATOM_NONE && r->format == 8) {
		const char *v = xcb_get_property_value(r);
		size_t len = (size_t)xcb_get_property_value_length(r);
		const char *nul = second ? memchr(v, '\0', len) : NULL;
		s = copy(v, nul ? (size_t)(nul - v) : len);
		if (nul) {
			size_t rest = len - (size_t)(nul + 1 - v);
			const char *end = memchr(nul + 1, '\0', rest);
			*second = copy(nul + 1, end ? (size_t)(end - nul - 1) : rest);
		}
	}
	free(r);
	return s;
}

int x11_names_read(const char *display, const uint32_t *xids, size_t n, struct x11_name *names,
		   char *err, size_t err_len)
{
	memset(names, 0, n * sizeof(*names));
	xcb_connection_t *x = xcb_connect(display, NULL);
	if (xcb_connection_has_error(x)) {
		const char *d = display ? display : getenv("DISPLAY");
		if (d && !*d)
			d = NULL;
		snprintf(err, err_len, "--names: cannot connect to the X display %s%s%s",
			 d ? "'" : "(DISPLAY is not set)", d ? d : "", d ? "'" : "");
		xcb_disconnect(x);
		return -1;
	}
	static const char net_wm_name[] = "_NET_WM_NAME";
	xcb_intern_atom_reply_t *a = xcb_intern_atom_reply(
		x, xcb_intern_atom(x, 1, sizeof(net_wm_name) - 1, net_wm_name), NULL);
	xcb_atom_t props[N_PROPS] = { a ? a->atom : XCB_ATOM_NONE, XCB_ATOM_WM_NAME,
				      XCB_ATOM_WM_CLASS };
	free(a);
	if (n > SIZE_MAX / N_PROPS / sizeof(xcb_get_property_cookie_t)) {
		snprintf(err, err_len, "too many windows");
		xcb_disconnect(x);
		return -1;
	}
	xcb_get_property_cookie_t *c = malloc(n * N_PROPS * sizeof(*c) + 1);
	if (!c) {
		snprintf(err, err_len, "out of memory");
		xcb_disconnect(x);
		return -1;
	}
	/* Every request first, then every reply: one round trip, not one a window. */
	for (size_t i = 0; i < n; i++)
		for (int p = 0; p < N_PROPS; p++)
			if (props[p] != XCB_ATOM_NONE) /* _NET_WM_NAME: none where no one set it */
				c[i * N_PROPS + p] = xcb_get_property(
					x, 0, xids[i], props[p], XCB_GET_PROPERTY_TYPE_ANY, 0, 4096);
	for (size_t i = 0; i < n; i++) {
		const xcb_get_property_cookie_t *ci = c + i * N_PROPS;
		char *net = props[NET_WM_NAME] != XCB_ATOM_NONE ? value(x, ci[NET_WM_NAME], NULL) : NULL;
		char *wm = value(x, ci[WM_NAME], NULL);
		names[i].name = net ? net : wm;
		if (net)
			free(wm);
		names[i].instance = value(x, ci[WM_CLASS], &names[i].class_name);
	}
	free(c);
	xcb_disconnect(x);
	return 0;
}
#else
int x11_names_read(const char *display, const uint32_t *xids, size_t n, struct x11_name *names,
		   char *err, size_t err_len)
{
	(void)display;
	(void)xids;
	memset(names, 0, n * sizeof(*names));
	snprintf(err, err_len, "--names: this visctl was built without xcb, and cannot ask X for names");
	return -1;
}
#endif

void x11_names_finish(struct x11_name *names, size_t n)
{
	if (!names)
		return;
	for (size_t i = 0; i < n; i++) {
		free(names[i].name);
		free(names[i].instance);
		free(names[i].class_name);
	}
}
