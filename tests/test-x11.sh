#!/bin/sh
# visd-x11 against a real X desktop: a private Xvfb, openbox as the window manager, a visd on a
# private socket and the bridge between them; x11-desk then drives the desktop (its windows,
# xlogo, xeyes, xterm) for two seeds and, at every quiet point, compares X's own VisibilityNotify
# states with `visctl states --x11`. Usage: test-x11.sh BUILD-DIR. Exits 77 (skipped) where the
# bridge is not built or Xvfb or openbox is missing.
build=${1:?usage: test-x11.sh BUILD-DIR}
bridge=$build/bridge/x11/visd-x11
x11_desk=$build/tests/x11-desk
visd=$build/daemon/visd
visctl=${VISCTL:-$build/client/visctl/visctl} # VISCTL: another program of visctl's interface
width=640
height=480

[ -x "$bridge" ] || { echo "$bridge not built: skipped"; exit 77; }
for prog in Xvfb openbox; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed: skipped"; exit 77; }
done
for prog in "$x11_desk" "$visd" "$visctl"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-x11.XXXXXX") || exit 1
xpid= wpid= vpid= bpid=
cleanup() {
	for pid in $bpid $wpid $vpid $xpid; do
		kill "$pid" 2>/dev/null
	done
	for pid in $bpid $wpid $vpid $xpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

# Shows a log and fails.
fail() {
	echo "test-x11: $1"
	[ -n "${2:-}" ] && cat "$2"
	exit 1
}

# Waits up to 10 s for the command to succeed.
wait_for() {
	for _ in $(seq 200); do
		"$@" && return 0
		sleep 0.05
	done
	return 1
}

exec 3>"$dir/display"
Xvfb -displayfd 3 -screen 0 ${width}x${height}x24 -nolisten tcp >"$dir/xvfb.log" 2>&1 &
xpid=$!
exec 3>&-
wait_for test -s "$dir/display" || fail "Xvfb did not start:" "$dir/xvfb.log"
display=:$(head -n 1 "$dir/display")

# openbox sets _NET_SUPPORTING_WM_CHECK once it owns WM_S0 (and x11-desk waits for the owner).
DISPLAY=$display openbox --sm-disable >"$dir/openbox.log" 2>&1 &
wpid=$!
wm_ready() {
	DISPLAY=$display xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q 'window id'
}
wait_for wm_ready || fail "openbox did not take the screen:" "$dir/openbox.log"

# visd's screen is X's, so that what lies past the root is off the screen for both.
sock=$dir/visd
"$visd" --socket "$sock" --screen ${width}x${height} 2>"$dir/visd.log" &
vpid=$!
wait_for test -S "$sock" || fail "visd did not start:" "$dir/visd.log"

"$bridge" --display "$display" -s "$sock" 2>"$dir/bridge.log" &
bpid=$!

status=0
for seed in 1 2; do
	echo "test-x11: seed $seed"
	"$x11_desk" --display "$display" --seed $seed --steps 200 \
		--check "$visctl -s $sock states --x11" || status=1
	kill -0 "$bpid" 2>/dev/null || fail "visd-x11 died:" "$dir/bridge.log"
	kill -0 "$vpid" 2>/dev/null || fail "visd died:" "$dir/visd.log"
done
[ $status = 0 ] || { echo "test-x11: the bridge's log:"; cat "$dir/bridge.log"; }
exit $status
