/*
 * Input: the seat, keyboards and the pointer. Focus and raise on click; pointer move and resize
 * (a client's request, or Alt with the left or right button); keys: Alt+F4 closes the focused
 * view, Alt+Tab cycles through the views, Alt+Shift+Escape ends viscomp.
 */
#ifndef VISCOMP_INPUT_H
#define VISCOMP_INPUT_H

struct server;

/* Creates the seat and the cursor and listens for input devices. 0, or -1 (logged). */
int input_init(struct server *server);
void input_finish(struct server *server);

#endif
