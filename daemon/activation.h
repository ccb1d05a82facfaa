/*
 * Socket activation: the listening sockets a service manager (systemd, systemd-socket-activate)
 * passes to visd, by the rules of sd_listen_fds(3), read by hand so that visd needs no libsystemd.
 */
#ifndef VISD_ACTIVATION_H
#define VISD_ACTIVATION_H

#include <sys/un.h>

/* The first descriptor passed (SD_LISTEN_FDS_START); the others follow it. */
#define ACTIVATION_FDS_START 3

/* One socket passed, checked to be a listening Unix stream socket. */
struct activation_socket {
	int fd; /* non-blocking and close-on-exec once taken; -1: none passed */
	/* The socket's file, from getsockname; "" for an abstract or unnamed socket, which has none. */
	char path[sizeof(((struct sockaddr_un *)0)->sun_path) + 1];
	/* For logs: the path, "@NAME" for an abstract socket, "(unnamed)". */
	char name[sizeof(((struct sockaddr_un *)0)->sun_path) + 2];
};

/*
 * What was passed. One socket is the main one. A second is the restricted socket
 * (--restricted-socket's), and LISTEN_FDNAMES must name it "restricted", whichever comes first;
 * more than two are refused.
 */
struct activation {
	struct activation_socket main, restricted;
};

/*
 * Takes the sockets passed to this process, if LISTEN_PID names it: checks LISTEN_FDS,
 * LISTEN_FDNAMES and every descriptor, then unsets the three variables (whatever they said), so
 * that no child takes them for its own. A LISTEN_PID of another process, or none, means nothing
 * was passed to visd. Returns 1 with a->main set, 0 when nothing was passed, or -1 after logging
 * what was wrong, naming the variable and the descriptor.
 */
int activation_take(struct activation *a);

#endif
