# What the viscomp tests share (sourced; POSIX sh): progress-following waits (progress.sh), a
# field of `viscompctl list --json` (json_field), a window listed (listed), viscompctl (ctl),
# viscomp started and its Wayland display taken (viscomp_start), and
# the environment viscomp and its clients run in, under the test's own directory $1: the Wayland
# sockets, viscompctl's control socket, and LeakSanitizer told of wlroots 0.15's own leak (its
# output globals are freed on a timer that the display's end never runs: wlr_global_destroy_safe).
# Needs $0 to be the test script beside it.
viscomp_here=$(cd "$(dirname "$0")" && pwd)
. "$viscomp_here/progress.sh"

viscomp_env() {
	viscomp_dir=$1
	export XDG_RUNTIME_DIR="$1"
	export VISCOMP_SOCKET="$1/control.sock"
	LSAN_OPTIONS="suppressions=$viscomp_here/viscomp-lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
	export LSAN_OPTIONS
}

# json_field PID FIELD: FIELD of the (first) window of process PID in `$viscompctl list --json`,
# or nothing.
json_field() {
	"$viscompctl" list --json 2>/dev/null | grep "\"pid\":$1," | head -n 1 |
		sed -n "s/.*\"$2\":\"\{0,1\}\([^,\"}]*\).*/\1/p"
}

# listed PID: whether a window of process PID is listed; its ID in $id then.
listed() {
	id=$(json_field "$1" id)
	[ -n "$id" ]
}

ctl() {
	"$viscompctl" "$@"
}

# viscomp_start [ARG...]: viscomp on the control socket, -v, logging to viscomp.log in the test's
# directory, in $vpid; once it tells its Wayland display, that is exported. 1 (and $progress_why)
# when it does not start.
viscomp_start() {
	"$viscomp" --control "$VISCOMP_SOCKET" -v "$@" >"$viscomp_dir/viscomp.log" 2>&1 &
	vpid=$!
	wait_progress "$vpid" grep -qs 'WAYLAND_DISPLAY=' "$viscomp_dir/viscomp.log" || return 1
	WAYLAND_DISPLAY=$(sed -n 's/.*WAYLAND_DISPLAY=\([^ ]*\).*/\1/p' "$viscomp_dir/viscomp.log")
	export WAYLAND_DISPLAY
}
