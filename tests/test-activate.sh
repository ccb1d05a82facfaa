#!/usr/bin/env bash
# Socket activation (sd_listen_fds(3)): visd started by systemd-socket-activate on the first
# connection serves the socket it is passed; its lock keeps a second daemon off the path; bad
# LISTEN_* variables and descriptors are refused with exit 1; the manager's socket stays after
# SIGTERM. Skipped (exit 77) where systemd-socket-activate (Debian's systemd package) is missing.
# Usage: test-activate.sh VISD VISCTL
set -uo pipefail
visd=$1
visctl=$2
if ! activate=$(command -v systemd-socket-activate); then
	echo "SKIP: systemd-socket-activate is not installed (Debian's systemd package)"
	exit 77
fi
dir=$(mktemp -d /tmp/visd-activate-XXXXXX)
pid=
cleanup() {
	[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null
	rm -rf "$dir"
}
trap cleanup EXIT
failures=0
fail() {
	echo "FAIL: $*" >&2
	failures=$((failures + 1))
}
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"
# Waits for a socket to appear at $2, as long as the process $1 (visd) works.
wait_socket() { wait_progress "$1" test -S "$2"; }
# Waits for a line matching $3 in the file $2, as long as the process $1 works.
wait_line() { wait_progress "$1" grep -qF -- "$3" "$2"; }
# A client that gives up: a daemon blocked in accept() must fail the test, not hang it. (A hang
# guard, as long as the stall interval of a wait: a working visd answers at once.)
v() { timeout "$progress_stall" "$visctl" "$@"; }
# Stops process $1 with SIGTERM and returns its exit status; if it stops working without exiting,
# it is killed and the status is 124: a daemon stuck in a blocking call must not hang the test.
stop() {
	kill "$1" 2>/dev/null
	if ! wait_progress "$1" progress_gone "$1"; then
		kill -9 "$1"
		wait "$1"
		return 124
	fi
	wait "$1"
}
# Whether fd $2 of process $1 is close-on-exec and non-blocking.
fd_flags_ok() {
	local flags
	flags=$(awk '/^flags:/ { print $2 }' "/proc/$1/fdinfo/$2") &&
		[ $((8#$flags & 8#02004000)) -eq $((8#02004000)) ]
}

# systemd-socket-activate passes on only a few variables: the sanitizers' options go by -E.
keep_env=()
for var in ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS; do
	[ -n "${!var:-}" ] && keep_env+=(-E "$var=${!var}")
done

# --- One socket: visd starts on the first connection and serves it ----------------------------
sock=$dir/sock
"$activate" "${keep_env[@]}" -l "$sock" "$visd" 2>"$dir/log" &
pid=$!
wait_socket "$pid" "$sock"
[ -S "$sock" ] || { echo "systemd-socket-activate did not listen" >&2; cat "$dir/log" >&2; exit 1; }
[ ! -e "$sock.lock" ] || fail "visd ran before any connection"
id=$(v -s "$sock" create 0 0 100 100 --map --retain) || fail "the first connection was not served"
[ "$(v -s "$sock" --role observer states)" = "$id unobscured" ] || fail "states after activation"
grep -qF "listening on $sock (socket activation)" "$dir/log" ||
	fail "no 'listening on $sock (socket activation)' in the log: $(cat "$dir/log")"
[ "$(readlink "/proc/$pid/exe")" = "$(readlink -f "$visd")" ] ||
	fail "the activated process is not visd: $(readlink "/proc/$pid/exe")"
fd_flags_ok "$pid" 3 || fail "the passed socket is not close-on-exec and non-blocking: $(cat "/proc/$pid/fdinfo/3")"
for n in 1 2 3 4 5; do
	v -s "$sock" sync || fail "connection $n after the first"
done
# The lock holds under activation: a second daemon on the path refuses, and leaves it alone.
# (Every visd that should refuse to start runs under a timeout, a hang guard: one that starts
# must not hang the test.)
timeout "$progress_stall" "$visd" --socket "$sock" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "another visd is serving '$sock'" "$dir/err" ||
	fail "a second visd on an activated socket: $(cat "$dir/err")"
VISD_SOCKET=$sock timeout "$progress_stall" "$visd" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "another visd" "$dir/err" || fail "a second visd by VISD_SOCKET: $(cat "$dir/err")"
[ "$(v -s "$sock" --role observer states)" = "$id unobscured" ] || fail "the first daemon lost its socket"
# SIGTERM: a clean exit; the socket is the manager's and stays, the lock goes.
stop "$pid" || fail "activated visd exited $? on SIGTERM"
pid=
[ -S "$sock" ] || fail "visd removed the socket the manager owns"
[ ! -e "$sock.lock" ] || fail "visd left its lock behind"

# --- Two sockets: the one LISTEN_FDNAMES calls 'restricted' is the restricted socket, wherever it
# comes; the other is the main one. -------------------------------------------------------------
main=$dir/main
restr=$dir/restr
"$activate" "${keep_env[@]}" -l "$restr" -l "$main" --fdname=restricted:visd.socket "$visd" 2>"$dir/log2" &
pid=$!
wait_socket "$pid" "$main"
v -s "$main" --role observer states >/dev/null 2>"$dir/err" ||
	fail "observer on the main socket passed second: $(cat "$dir/err" "$dir/log2")"
v -s "$restr" --role observer states >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "a role was given on the socket named 'restricted'"
v -s "$restr" states >/dev/null || fail "a client on the restricted socket"
wait_line "$pid" "$dir/log2" "restricted $restr (socket activation)"
grep -qF "listening on $main (socket activation) (screen 3840x2160), restricted $restr (socket activation)" \
	"$dir/log2" || fail "the log of two sockets: $(cat "$dir/log2")"
timeout "$progress_stall" "$visd" --socket "$dir/other" --restricted-socket "$restr" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "another visd is serving '$restr'" "$dir/err" ||
	fail "a second visd on the activated restricted socket: $(cat "$dir/err")"
[ ! -e "$dir/other" ] || fail "the refused daemon left its socket"
stop "$pid" || fail "visd with two sockets exited $? on SIGTERM"
pid=
[ -S "$main" ] && [ -S "$restr" ] || fail "visd removed a socket the manager owns"

# --- Bad descriptors and variables: exit 1, an error naming the variable and the descriptor ----
# pass.py KINDS VISD ARGS...: runs visd as the process LISTEN_PID names (unless the caller set
# LISTEN_PID) with, from fd 3 on, one descriptor of each kind in KINDS (comma-separated).
cat >"$dir/pass.py" <<'PY'
import os, socket, sys
kinds, argv = sys.argv[1].split(","), sys.argv[2:]
made = []
for i, kind in enumerate(kinds):
    path = os.path.join(os.path.dirname(sys.argv[0]), "fd%d" % i)
    if kind == "file":
        made.append(os.open(sys.argv[0], os.O_RDONLY))
        continue
    if kind == "closed":
        made.append(None)
        continue
    family = socket.AF_INET if kind == "tcp" else socket.AF_UNIX
    stype = socket.SOCK_DGRAM if kind == "dgram" else socket.SOCK_STREAM
    s = socket.socket(family, stype)
    s.bind(("127.0.0.1", 0) if kind == "tcp" else "\0" + path if kind == "abstract" else path)
    if kind in ("listening", "tcp", "abstract"):
        s.listen()
    made.append(s.detach())
moved = [os.dup(f) if f is not None else None for f in made]  # out of the way of 3, 4, ...
for f in made:
    if f is not None:
        os.close(f)
for i, f in enumerate(moved):
    if f is None:
        try:
            os.close(3 + i)
        except OSError:
            pass
    else:
        os.dup2(f, 3 + i, inheritable=True)
        os.close(f)
os.environ.setdefault("LISTEN_PID", str(os.getpid()))
os.execv(argv[0], argv)
PY
# refused WHAT MESSAGE ENV KINDS: visd, given ENV (VAR=VALUE words) and descriptors of KINDS, must
# exit 1 saying MESSAGE, without binding the --socket it is also given.
refused() {
	local what=$1 msg=$2 kinds=$4 rc
	# shellcheck disable=SC2086
	env $3 timeout "$progress_stall" python3 "$dir/pass.py" "$kinds" "$visd" --socket "$dir/bad" 2>"$dir/err"
	rc=$?
	[ $rc -eq 1 ] && grep -qF -- "$msg" "$dir/err" ||
		fail "$what: exit status $rc, want 1 and '$msg': $(cat "$dir/err")"
	[ ! -e "$dir/bad" ] || fail "$what: visd bound its --socket"
	rm -f "$dir"/fd[0-9]
}
refused "fd 3 a file" "LISTEN_FDS=1, but fd 3 is not a socket (a regular file)" LISTEN_FDS=1 file
refused "fd 3 closed" "LISTEN_FDS=1, but fd 3 is not open" LISTEN_FDS=1 closed
refused "fd 3 not listening" "LISTEN_FDS=1, but fd 3 is a socket that is not listening" \
	LISTEN_FDS=1 bound
refused "fd 3 a datagram socket" "LISTEN_FDS=1, but fd 3 is not a stream socket" LISTEN_FDS=1 dgram
refused "fd 3 a TCP socket" "LISTEN_FDS=1, but fd 3 is not a Unix socket" LISTEN_FDS=1 tcp
refused "LISTEN_FDS not a number" "LISTEN_FDS='abc' is not a number of sockets" LISTEN_FDS=abc \
	listening
refused "LISTEN_FDS=0" "LISTEN_FDS='0' is not a number of sockets" LISTEN_FDS=0 listening
refused "LISTEN_FDS negative" "LISTEN_FDS='-1' is not a number of sockets" LISTEN_FDS=-1 listening
refused "three sockets" "LISTEN_FDS=3, but visd takes at most 2 sockets" LISTEN_FDS=3 \
	listening,listening,listening
refused "two sockets, no names" "LISTEN_FDNAMES must name one of fd 3 and fd 4 'restricted'" \
	LISTEN_FDS=2 listening,listening
refused "two sockets, neither restricted" "but it is 'a:b'" "LISTEN_FDS=2 LISTEN_FDNAMES=a:b" \
	listening,listening
refused "two sockets, both restricted" "but it is 'restricted:restricted'" \
	"LISTEN_FDS=2 LISTEN_FDNAMES=restricted:restricted" listening,listening
refused "fd 4 a file" "LISTEN_FDS=2, but fd 4 is not a socket" \
	"LISTEN_FDS=2 LISTEN_FDNAMES=main:restricted" listening,file
refused "more names than sockets" "LISTEN_FDNAMES='a:b' names 2 sockets, but LISTEN_FDS=1" \
	"LISTEN_FDS=1 LISTEN_FDNAMES=a:b" listening
refused "only a restricted socket" "makes fd 3 the restricted socket" \
	"LISTEN_FDS=1 LISTEN_FDNAMES=restricted" listening
refused "LISTEN_PID not a number" "LISTEN_PID='abc' is not a process ID" \
	"LISTEN_PID=abc LISTEN_FDS=1" listening
refused "--socket elsewhere" "--socket $dir/bad, but the socket passed (fd 3) is $dir/fd0" \
	LISTEN_FDS=1 listening

# A LISTEN_PID of another process: not for visd, which binds its own socket as usual.
env LISTEN_PID=1 LISTEN_FDS=1 python3 "$dir/pass.py" file "$visd" --socket "$dir/own" \
	2>"$dir/log3" &
pid=$!
wait_socket "$pid" "$dir/own"
v -s "$dir/own" sync 2>"$dir/err" || fail "visd with another's LISTEN_PID: $(cat "$dir/err" "$dir/log3")"
stop "$pid" || fail "visd with another's LISTEN_PID exited $?"
pid=
grep -q "socket activation" "$dir/log3" && fail "another's LISTEN_PID was taken: $(cat "$dir/log3")"
[ ! -e "$dir/own" ] || fail "visd left the socket it bound itself"
# An abstract socket has no file, so no lock; its name is logged.
env LISTEN_FDS=1 python3 "$dir/pass.py" abstract "$visd" 2>"$dir/log4" &
pid=$!
wait_line "$pid" "$dir/log4" "listening on"
grep -qF "listening on @$dir/fd0 (socket activation)" "$dir/log4" ||
	fail "an abstract socket: $(cat "$dir/log4")"
stop "$pid" || fail "visd on an abstract socket exited $?"
pid=

if grep -hE "ERROR|runtime error|AddressSanitizer" "$dir"/log*; then fail "sanitizer reports"; fi
[ $failures -eq 0 ] && echo "activate: every check passed"
exit $((failures > 0))
