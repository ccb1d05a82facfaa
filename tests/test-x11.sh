#!/bin/sh
# visd-x11 against a real X desktop: a private Xvfb, openbox as the window manager, a visd on a
# private socket and the bridge between them; x11-desk then drives the desktop (its windows,
# xlogo, xeyes, xterm) for two seeds and, at every quiet point, compares X's own VisibilityNotify
# states with `visctl states --x11`, and visd's with a brute force over X's tree. Then a
# compositing manager (xcompmgr, else picom) takes the screen: seed 3 under it, where what the
# clients were told (X's word or the bridge's synthetic event) must be visd's state, X's own word
# must be wrong somewhere, and a bystander connection must get no VisibilityNotify; then short
# runs with a fresh visd and bridge under --send-events never and always; then, where both are
# installed, picom replaces xcompmgr for a short run of its own. After each run the
# bridge checks its mirror (SIGUSR1) and must not have drifted. Usage: test-x11.sh BUILD-DIR.
# Exits 77 (skipped) where the bridge is not built or Xvfb or openbox is missing; the compositor
# part is skipped (with a note) where neither compositor is installed.
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
xpid= wpid= vpid= bpid= cpid= watch_pid=
cleanup() {
	for pid in $watch_pid $bpid $cpid $wpid $vpid $xpid; do
		kill "$pid" 2>/dev/null
	done
	for pid in $watch_pid $bpid $cpid $wpid $vpid $xpid; do
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

# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"

# -noreset: X resets when its last client leaves, and a client that connects meanwhile fails
# ("Failed to open the display": xprop, then openbox at once, raced it).
exec 3>"$dir/display"
Xvfb -displayfd 3 -screen 0 ${width}x${height}x24 -nolisten tcp -noreset >"$dir/xvfb.log" 2>&1 &
xpid=$!
exec 3>&-
wait_progress "$xpid" test -s "$dir/display" ||
	fail "Xvfb did not start ($progress_why):" "$dir/xvfb.log"
display=:$(head -n 1 "$dir/display")

# openbox sets _NET_SUPPORTING_WM_CHECK once it owns WM_S0 (and x11-desk waits for the owner).
DISPLAY=$display openbox --sm-disable >"$dir/openbox.log" 2>&1 &
wpid=$!
wm_ready() {
	DISPLAY=$display xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q 'window id'
}
wait_progress "$wpid $xpid" wm_ready || { cat "$dir/xvfb.log"
	fail "openbox did not take the screen ($progress_why):" "$dir/openbox.log"; }

# visd's screen is X's, so that what lies past the root is off the screen for both. Each visd
# (N: 1, 2, …) gets a bridge of its own, started with the arguments given.
n=0
start_bridge() {
	if [ -n "$bpid" ]; then
		kill "$bpid" "$vpid"
		wait "$bpid" "$vpid" 2>/dev/null
	fi
	n=$((n + 1))
	sock=$dir/visd$n
	"$visd" --socket "$sock" --screen ${width}x${height} 2>"$dir/visd$n.log" &
	vpid=$!
	wait_progress "$vpid" test -S "$sock" ||
		fail "visd did not start ($progress_why):" "$dir/visd$n.log"
	log=$dir/bridge$n.log
	"$bridge" --display "$display" -s "$sock" "$@" 2>"$log" &
	bpid=$!
}

# The bridge checks its mirror against X's tree (SIGUSR1): it must not have drifted.
checks() {
	grep -c 'checked:' "$log"
}
checked_again() {
	test "$(checks)" -gt "$before"
}
check_bridge() {
	before=$(checks)
	kill -USR1 "$bpid"
	wait_progress "$bpid $vpid $xpid" checked_again ||
		fail "visd-x11 did not check its mirror ($progress_why):" "$log"
	if grep -q -e drifted -e resynchronizing "$log"; then
		fail "visd-x11's mirror drifted:" "$log"
	fi
}

# Runs x11-desk with the arguments, its summary kept in $dir/desk.out; fails the test on failure.
status=0
desk() {
	"$x11_desk" --display "$display" --check "$visctl -s $sock states --x11" "$@" \
		--working "$bpid" --working "$vpid" --working "$wpid" ${cpid:+--working "$cpid"} \
		>"$dir/desk.out" || status=1
	cat "$dir/desk.out"
	kill -0 "$bpid" 2>/dev/null || fail "visd-x11 died:" "$log"
	kill -0 "$vpid" 2>/dev/null || fail "visd died:" "$dir/visd$n.log"
	check_bridge
}

# A figure of x11-desk's summary: the number just before the words (e.g. "times").
figure() {
	sed -n "s/.* \([0-9]*\) $1.*/\1/p" "$dir/desk.out" | head -n 1
}
# The number just after the words (e.g. "bystander got").
after() {
	sed -n "s/.*$1 \([0-9]*\).*/\1/p" "$dir/desk.out" | head -n 1
}

# visctl watch --x11 saw every change as a chain: each window (named by its XID, 0x…, as
# everything the bridge mirrors is) went from the state its last line gave (or from none, when it
# was not viewable in between), and its last line gives the state visd has now, for the windows
# still there.
check_watch() {
	"$visctl" -s "$sock" states --x11 >"$dir/states.out" || fail "visctl states --x11 failed"
	# A window of visd's own, gone with its client: once watch prints its end, it has printed
	# every notice before it.
	probe=$("$visctl" -s "$sock" create 0 0 1 1) || fail "visctl create failed"
	wait_progress "$watch_pid $vpid" grep -q "^[0-9]* stack destroy $probe " "$dir/watch.out" ||
		fail "visctl watch --x11 did not see the probe's end ($progress_why)" "$dir/watch.out"
	kill -INT "$watch_pid"
	wait "$watch_pid" 2>/dev/null
	watch_pid=
	awk -v states="$dir/states.out" '
		BEGIN { while ((getline l < states) > 0) { split(l, f, " "); now[f[1]] = f[2] } }
		$2 != "visibility" { next }
		{ lines++ }
		$3 !~ /^0x/ { print "not named by its XID: " $0; bad++; next }
		# "none": it was not viewable meanwhile (no notice says so), or is new.
		($3 in last) && $5 != last[$3] && $5 != "none" && $5 != "initial" {
			print "from " $5 ", but its last line said " last[$3] ": " $0; bad++
		}
		{ last[$3] = $4 }
		END {
			for (x in now) if (x in last && last[x] != now[x]) {
				print x ": watch last said " last[x] ", visd says " now[x]; bad++
			}
			print lines " visibility lines"
			exit bad > 0
		}' "$dir/watch.out" >"$dir/watch.check" || fail "visctl watch --x11:" "$dir/watch.check"
	echo "test-x11: visctl watch --x11: $(tail -n 1 "$dir/watch.check"), each from its last state"
}

start_bridge
# A subscriber by X window IDs all along the first two seeds.
"$visctl" -s "$sock" watch --x11 >"$dir/watch.out" 2>"$dir/watch.err" &
watch_pid=$!
for seed in 1 2; do
	echo "test-x11: seed $seed"
	desk --seed $seed --steps 200
done
check_watch

# Under a compositing manager.
if command -v xcompmgr >/dev/null 2>&1; then
	DISPLAY=$display xcompmgr >"$dir/cm.log" 2>&1 &
	cpid=$!
elif command -v picom >/dev/null 2>&1; then
	DISPLAY=$display picom --backend xrender >"$dir/cm.log" 2>&1 &
	cpid=$!
else
	echo "test-x11: neither xcompmgr nor picom is installed: no run under a compositor"
fi
if [ -n "$cpid" ]; then
	# x11-desk --compositor waits until the compositor owns _NET_WM_CM_S0.
	echo "test-x11: seed 3 under a compositing manager"
	desk --seed 3 --steps 200 --compositor
	wrong=$(figure 'times')
	[ "${wrong:-0}" -gt 0 ] || { echo "test-x11: X's own states were never wrong under the compositor"; status=1; }
	[ "$(after 'bystander got')" = 0 ] || { echo "test-x11: the bystander got VisibilityNotify"; status=1; }

	for mode in never always; do
		echo "test-x11: seed 4 under a compositing manager, --send-events $mode"
		start_bridge --send-events $mode
		desk --seed 4 --steps 30 --compositor --send-events $mode
		synthetic=$(sed -n 's/.*(\([0-9]*\) synthetic).*/\1/p' "$dir/desk.out")
		changes=$(figure 'states')
		case $mode in
		never) [ "$synthetic" = 0 ] || { echo "test-x11: synthetic events under never"; status=1; } ;;
		always) [ "$synthetic" -ge "$changes" ] ||
			{ echo "test-x11: $synthetic synthetic events for $changes changes"; status=1; } ;;
		esac
	done
fi

# picom, the compositor most desktops run now (xrender: Xvfb has no GL), when both are there.
if [ -n "$cpid" ] && command -v picom >/dev/null 2>&1 && command -v xcompmgr >/dev/null 2>&1; then
	# The bridge first: picom's composite overlay window, which QueryTree leaves out of X's tree,
	# comes to it as a CreateNotify and a MapNotify over the whole screen, and must hide nothing.
	kill "$cpid"
	wait "$cpid" 2>/dev/null
	start_bridge
	DISPLAY=$display picom --backend xrender --config /dev/null >"$dir/picom.log" 2>&1 &
	cpid=$!
	echo "test-x11: seed 5 under picom"
	desk --seed 5 --steps 40 --compositor
	[ "$(after 'bystander got')" = 0 ] || { echo "test-x11: the bystander got VisibilityNotify"; status=1; }
fi
[ $status = 0 ] || { echo "test-x11: the bridge's log:"; cat "$log"; }
exit $status
