#!/bin/bash
# visd-x11's faults, on a private Xvfb with openbox: windows destroyed while the bridge reads them
# (x11-churn), a window manager replaced and killed, twenty thousand windows, then visd going
# away and the X server going away (exit status 1, a line naming the peer), and bad command
# lines. After each disturbance the bridge checks its mirror against a fresh read of X's tree
# (SIGUSR1) and must find it exact, never having resynchronized.
# Usage: test-x11-faults.sh BUILD-DIR. Exits 77 (skipped) without visd-x11, Xvfb or openbox.
build=${1:?usage: test-x11-faults.sh BUILD-DIR}
bridge=$build/bridge/x11/visd-x11
churn=$build/tests/x11-churn
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl

[ -x "$bridge" ] || { echo "$bridge not built: skipped"; exit 77; }
for prog in Xvfb openbox xprop; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed: skipped"; exit 77; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-x11-faults.XXXXXX") || exit 1
xpid= wpid= vpid= bpid= cpid= churn_pid=
cleanup() {
	for pid in $churn_pid $cpid $bpid $wpid $vpid $xpid; do kill "$pid" 2>/dev/null; done
	for pid in $churn_pid $cpid $bpid $wpid $vpid $xpid; do wait "$pid" 2>/dev/null; done
	[ -n "${KEEP:-}" ] && echo "kept $dir" || rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-x11-faults: FAIL: $1"
	[ -n "${2:-}" ] && sed 's/^/  | /' "$2"
	exit 1
}
ok() { echo "test-x11-faults: ok: $1"; }

# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"

# -noreset: X resets when its last client leaves, and a client that connects meanwhile fails
# ("Failed to open the display": xprop, then openbox at once, raced it).
start_x() {
	exec 3>"$dir/display"
	Xvfb -displayfd 3 -screen 0 800x600x24 -nolisten tcp -noreset >"$dir/xvfb.log" 2>&1 &
	xpid=$!
	exec 3>&-
	wait_progress "$xpid" test -s "$dir/display" ||
		fail "Xvfb did not start ($progress_why)" "$dir/xvfb.log"
	export DISPLAY=:$(head -n 1 "$dir/display")
}

# openbox sets _NET_SUPPORTING_WM_CHECK once it owns the screen. The property is removed first:
# a new openbox may get the XIDs of a killed one, and so the same value.
wm_check() { xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q 'window id'; }
start_wm() {
	xprop -root -remove _NET_SUPPORTING_WM_CHECK 2>/dev/null
	openbox --sm-disable "$@" >>"$dir/openbox.log" 2>&1 &
	wpid=$!
	wait_progress "$wpid $xpid" wm_check || { cat "$dir/xvfb.log"
		fail "openbox did not take the screen ($progress_why)" "$dir/openbox.log"; }
}

start_visd() {
	rm -f "$dir/sock"
	"$visd" --socket "$dir/sock" --screen 800x600 "$@" 2>"$dir/visd.log" &
	vpid=$!
	wait_progress "$vpid" test -S "$dir/sock" ||
		fail "visd did not start ($progress_why)" "$dir/visd.log"
}

start_bridge() {
	: >"$dir/bridge.log"
	"$bridge" -s "$dir/sock" ${BRIDGE_VERBOSE:--v} 2>"$dir/bridge.log" &
	bpid=$!
	wait_progress "$bpid $vpid $xpid" grep -q 'mirrored' "$dir/bridge.log" ||
		fail "visd-x11 did not start ($progress_why)" "$dir/bridge.log"
}

# The bridge reads the tree again; its mirror must have been exact all along.
check_mirror() {
	local what=$1 n
	sleep 0.3 # X's last events on their way
	n=$(grep -c '^visd-x11: checked:' "$dir/bridge.log")
	kill -USR1 "$bpid"
	more_checks() { [ "$(grep -c '^visd-x11: checked:' "$dir/bridge.log")" -gt "$n" ]; }
	# Twenty thousand windows under the sanitizers on a busy machine take minutes: the bridge
	# reads X's tree, visd takes the windows, and X answers while any of them works.
	wait_progress "$bpid $vpid $xpid" more_checks ||
		fail "$what: visd-x11 did not answer SIGUSR1 ($progress_why)" "$dir/bridge.log"
	grep -q 'drifted\|resynchroniz' "$dir/bridge.log" &&
		fail "$what: the mirror drifted" "$dir/bridge.log"
	ok "$what: $(grep '^visd-x11: checked:' "$dir/bridge.log" | tail -n 1 | sed 's/^visd-x11: checked: //')"
}

start_x
start_wm
start_visd
start_bridge
xlogo >/dev/null 2>&1 &
cpid=$!
sleep 0.5
check_mirror "start-up"

# Windows destroyed between their CreateNotify and the bridge's read, reparented, restacked.
"$churn" --windows 300 --rounds 20000 --seed 1 --hold >"$dir/churn.out" &
churn_pid=$!
wait_progress "$churn_pid $xpid" grep -qs 'live' "$dir/churn.out" ||
	fail "x11-churn did not finish ($progress_why)"
check_mirror "20,000 changes racing the bridge's reads"
"$visctl" -s "$dir/sock" states --x11 >"$dir/states" || fail "visctl states --x11 failed"
[ -s "$dir/states" ] || fail "visctl states --x11 printed nothing"

# A window manager replacing the running one: every frame destroyed, every client reframed.
old_wm=$wpid
start_wm --replace
wait "$old_wm" 2>/dev/null
check_mirror "openbox --replace"
# A window manager killed: X reparents its clients back to the root (the save-set).
kill -9 "$wpid"
wait "$wpid" 2>/dev/null
wpid=
check_mirror "openbox killed"
start_wm
check_mirror "openbox started again"

# Many windows at once.
kill "$churn_pid"
wait "$churn_pid" 2>/dev/null
"$churn" --windows 20000 --rounds 0 --seed 2 --hold >"$dir/churn.out" &
churn_pid=$!
wait_progress "$churn_pid $xpid" grep -qs 'live' "$dir/churn.out" ||
	fail "x11-churn did not create 20,000 windows ($progress_why)"
check_mirror "20,000 more windows"
kill "$churn_pid"
wait "$churn_pid" 2>/dev/null
check_mirror "20,000 windows gone with their client"
x_errors=$(grep -c 'X error' "$dir/bridge.log")
[ "$x_errors" -eq 0 ] || fail "the bridge logged X errors it should not have" "$dir/bridge.log"

# A peer gone ($1 says which): the bridge exits 1 with a line saying $2.
expect_gone() {
	local what=$1 line=$2 status
	wait "$bpid"
	status=$?
	bpid=
	[ $status = 1 ] || fail "$what: visd-x11 exited $status, not 1" "$dir/bridge.log"
	grep -q "$line" "$dir/bridge.log" || fail "$what: no line saying so" "$dir/bridge.log"
	ok "$what: exit 1, '$(grep "$line" "$dir/bridge.log")'"
}

kill "$vpid"
wait "$vpid" 2>/dev/null
vpid=
expect_gone "visd gone" 'visd closed the connection'

# visd refusing windows (its limit): the bridge stops rather than keep a partial mirror, at
# start-up and in a turn.
start_visd --max-windows 20
: >"$dir/bridge.log"
"$bridge" -s "$dir/sock" 2>"$dir/bridge.log" &
bpid=$!
expect_gone "visd refusing windows at start-up" 'visd refused create of window 0x'
grep -q 'stopping (see visd' "$dir/bridge.log" || fail "no advice on visd's limits" "$dir/bridge.log"
kill "$vpid"
wait "$vpid" 2>/dev/null
start_visd --max-windows 300
start_bridge
"$churn" --windows 400 --rounds 0 --seed 3 --hold >"$dir/churn.out" &
churn_pid=$!
expect_gone "visd refusing windows later" 'visd refused create of window 0x'
kill "$churn_pid" "$vpid"
wait "$churn_pid" "$vpid" 2>/dev/null

start_visd
start_bridge
kill "$xpid"
wait "$xpid" 2>/dev/null
xpid=
expect_gone "X gone" 'the X server closed the connection'
kill "$wpid" "$cpid" 2>/dev/null
wpid= cpid=

# Command lines.
expect() {
	local want=$1 pattern=$2
	shift 2
	"$bridge" "$@" >"$dir/out" 2>&1
	local got=$?
	[ $got = "$want" ] || fail "visd-x11 $*: exit $got, not $want" "$dir/out"
	grep -q -- "$pattern" "$dir/out" || fail "visd-x11 $*: no '$pattern'" "$dir/out"
}
expect 2 "takes auto, always or never" --send-events sometimes
expect 2 "takes auto, on or off" --translucency maybe
expect 2 "unexpected argument" extra
expect 1 "cannot connect to the X display" --display :9999 -s "$dir/sock"
start_x
expect 1 "cannot connect to visd" -s "$dir/no-such-socket"
expect 0 "visd-x11 " --version
ok "command lines"
