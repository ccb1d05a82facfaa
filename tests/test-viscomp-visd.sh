#!/bin/sh
# viscomp when the visd it mirrors into (--visd) goes away and comes back. A headless viscomp
# (1280x720) with weston-simple-shm A covered by an opaque wl-hostile window C, and
# weston-simple-shm W, a witness in view:
#   1. visd's tree says of each window what viscompctl says (state and place);
#   2. visd is killed (SIGKILL): viscomp lives, logs it, and goes on throttling: A covered
#      commits nothing while W draws 60 frames; uncovered it draws, covered again it stops. The
#      scene changes meanwhile (W moves);
#   3. while visd is away viscomp tries to connect again with a growing wait: at least 4
#      attempts logged, each at least the wait the one before announced after it (no busy
#      loop: the log's own timestamps, which a loaded machine can only stretch);
#   4. a new visd on the same socket: viscomp connects again on its own and mirrors the whole
#      scene: visd's tree holds exactly A, C, W and the outside, each where and as viscompctl
#      says, W at its new place; a change after it (C moved off A) reaches visd too;
#   5. again with SIGTERM, C killed while visd is away: the new visd never sees C;
# at the end every client goes, visd holds only the outside, viscomp exits 0 (under ASan: no
# report). Waits follow progress (tests/progress.sh).
# Usage: test-viscomp-visd.sh BUILD-DIR. Exits 77 (skipped) where viscomp is not built.
set -u
build=${1:?usage: test-viscomp-visd.sh BUILD-DIR}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl
hostile=$build/tests/wl-hostile
[ -x "$viscomp" ] || { echo "$viscomp not built: skipped"; exit 77; }
for prog in "$viscompctl" "$visd" "$visctl" "$hostile"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done
command -v weston-simple-shm >/dev/null 2>&1 ||
	{ echo "weston-simple-shm not installed (tools/dev.sh install)"; exit 1; }

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-viscomp-visd.XXXXXX") || exit 1
chmod 700 "$dir"
dpid= vpid= apid= wpid= cpid=
cleanup() {
	for pid in $apid $wpid $cpid $vpid $dpid; do
		kill -9 "$pid" 2>/dev/null
	done
	for pid in $apid $wpid $cpid $vpid $dpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-viscomp-visd: $1"
	echo "--- viscomp's log:"
	tail -n 30 "$dir/viscomp.log"
	exit 1
}

# A wait whose processes stay busy (a client drawing) gives up after 5 minutes, not meson's 10.
progress_ceiling=${progress_ceiling:-300}
. "$(dirname "$0")/viscomp-env.sh"
viscomp_env "$dir"

is_state() {
	[ "$(json_field "$1" state)" = "$2" ]
}

commits_past() {
	n=$(json_field "$1" commits_total)
	[ -n "$n" ] && [ "$n" -gt "$2" ]
}

frames_past() {
	n=$(json_field "$1" frames_total)
	[ -n "$n" ] && [ "$n" -gt "$2" ]
}

tree() {
	"$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null
}

# visd's "X Y STATE" of the window of process PID (each of these clients has one surface).
visd_of() {
	tree | awk -v tag="2:0x$(printf %x "$1")" \
		'index($NF, tag) == 1 && length($NF) == length(tag) + 8 { print $3, $4, $8; exit }'
}

# Whether visd says of process PID what viscompctl says.
agrees() {
	v=$(visd_of "$1")
	[ -n "$v" ] && [ "$v" = "$(json_field "$1" x) $(json_field "$1" y) $(json_field "$1" state)" ]
}

# Whether visd holds exactly $1 windows (the outside included) and agrees on each process after.
mirrored() {
	n=$1
	shift
	[ "$(tree | grep -c .)" -eq "$n" ] || return 1
	for pid in "$@"; do
		agrees "$pid" || return 1
	done
}

check_mirror() {
	what=$1
	shift
	wait_progress "$vpid $dpid" mirrored "$@" ||
		fail "$what: visd differs: $(tree | tr '\n' ';'), viscompctl: $(ctl list | tr '\n' ';')"
}

# A covered: it commits nothing while W draws 60 frames.
check_throttled() {
	wait_progress "$vpid $apid" is_state "$apid" fully-obscured || fail "$1: A not covered"
	# A frame answered before the cover came may still be drawn: A's commits per second fall to 0.
	a_idle() {
		is_state "$apid" fully-obscured && [ "$(json_field "$apid" commits)" = 0 ]
	}
	wait_progress "$vpid $apid $wpid" a_idle || fail "$1: A does not stop: $progress_why"
	c0=$(json_field "$apid" commits_total) f0=$(json_field "$wpid" frames_total)
	wait_progress "$vpid $wpid" frames_past "$wpid" $((f0 + 60)) ||
		fail "$1: W does not draw: $progress_why"
	c1=$(json_field "$apid" commits_total)
	[ "$c1" -eq "$c0" ] || fail "$1: A committed $((c1 - c0)) times while covered"
}

visd_up() {
	"$visctl" -s "$dir/visd.sock" --role observer tree >/dev/null 2>&1
}

start_visd() {
	"$visd" --socket "$dir/visd.sock" --screen 1280x720 2>>"$dir/visd.log" &
	dpid=$!
	wait_progress "$dpid" visd_up ||
		fail "visd did not start: $progress_why"
}

start_visd
viscomp_start --headless 1280x720 --visd "$dir/visd.sock" ||
	fail "viscomp did not start: $progress_why"

weston-simple-shm >"$dir/a.log" 2>&1 &
apid=$!
wait_progress "$vpid $apid" listed "$apid" || fail "A not listed: $progress_why"
aid=$id
weston-simple-shm >"$dir/w.log" 2>&1 &
wpid=$!
wait_progress "$vpid $wpid" listed "$wpid" || fail "W not listed: $progress_why"
wid=$id
ctl move "$wid" 1000 100 || fail "move W"
"$hostile" --size 400x400 >"$dir/c.out" 2>&1 &
cpid=$!
wait_progress "$vpid $cpid" listed "$cpid" || fail "C not listed: $progress_why"
cid=$id
ctl move "$aid" 50 50 || fail "move A"
ctl move "$cid" 0 0 || fail "move C"
ctl raise "$cid" || fail "raise C"
check_throttled "start"
check_mirror "start" 4 "$apid" "$wpid" "$cpid"
echo "start: visd agrees: A $(visd_of "$apid"), W $(visd_of "$wpid"), C $(visd_of "$cpid")"

# --- 2. visd killed: viscomp goes on, and throttles on.
kill -9 "$dpid"
wait "$dpid" 2>/dev/null
dpid=
wait_progress "$vpid" grep -q 'visd mirror: .*; going on without it' "$dir/viscomp.log" ||
	fail "viscomp did not notice visd's end"
check_throttled "visd gone"
ctl move "$cid" 500 0 || fail "move C off A"
wait_progress "$vpid $apid" is_state "$apid" unobscured || fail "visd gone: A not uncovered"
c0=$(json_field "$apid" commits_total)
wait_progress "$vpid $apid" commits_past "$apid" $((c0 + 30)) ||
	fail "visd gone: A uncovered does not draw: $progress_why"
ctl move "$cid" 0 0 || fail "move C over A"
check_throttled "visd gone, covered again"
ctl move "$wid" 1000 400 || fail "move W"
echo "visd gone: viscomp lives; A covered commits nothing, uncovered draws, covered stops again"

# --- 3. the attempts, each at least the wait announced before it.
attempts() {
	[ "$(grep -c 'visd mirror: attempt [0-9]* failed' "$dir/viscomp.log")" -ge "$1" ]
}
wait_progress "$vpid" attempts 4 || fail "fewer than 4 attempts to connect again: $progress_why"
# "HH:MM:SS.mmm [INFO] ... attempt N failed; the next in M ms" -> ms since the start, M.
grep 'visd mirror: attempt [0-9]* failed' "$dir/viscomp.log" |
	sed -n 's/^\([0-9]*\):\([0-9]*\):\([0-9]*\)\.\([0-9]*\) .* the next in \([0-9]*\) ms$/\1 \2 \3 \4 \5/p' |
	awk '{ t = (($1 * 60 + $2) * 60 + $3) * 1000 + $4
	       if (NR > 1 && t - last < wait) {
		       print "attempt " NR " came " t - last " ms after the one before, not " wait
		       bad = 1
	       }
	       if (NR > 1 && $5 < wait) {
		       print "the wait shrank from " wait " to " $5 " ms"
		       bad = 1
	       }
	       last = t; wait = $5 }
	     END { exit bad }' >"$dir/backoff" || fail "$(cat "$dir/backoff")"
echo "visd gone: $(grep -c 'visd mirror: attempt [0-9]* failed' "$dir/viscomp.log") attempts so far," \
	"waits $(sed -n 's/.*the next in \([0-9]*\) ms$/\1/p' "$dir/viscomp.log" | tr '\n' ' ')ms"

# --- 4. visd back: the whole scene again, W at its new place, and changes after it.
start_visd
wait_progress "$dpid" grep -q 'visd mirror: connected again' "$dir/viscomp.log" ||
	fail "viscomp did not connect again: $progress_why"
check_mirror "visd back" 4 "$apid" "$wpid" "$cpid"
[ "$(visd_of "$wpid" | cut -d' ' -f1-2)" = "1000 400" ] || fail "visd back: W at $(visd_of "$wpid")"
ctl move "$cid" 500 0 || fail "move C off A"
check_mirror "visd back, C moved" 4 "$apid" "$wpid" "$cpid"
[ "$(visd_of "$apid" | cut -d' ' -f3)" = unobscured ] || fail "visd back: A $(visd_of "$apid")"
echo "visd back: $(grep 'visd mirror: connected again' "$dir/viscomp.log" | tail -n 1 | sed 's/.*\] //');" \
	"visd agrees: A $(visd_of "$apid"), W $(visd_of "$wpid"), C $(visd_of "$cpid")"
ctl move "$cid" 0 0 || fail "move C over A"

# --- 5. SIGTERM this time, and C goes while visd is away.
kill "$dpid"
wait "$dpid" 2>/dev/null
dpid=
ended() {
	[ "$(grep -c 'visd mirror: .*; going on without it' "$dir/viscomp.log")" -ge 2 ]
}
wait_progress "$vpid" ended || fail "viscomp did not notice visd's second end"
kill -9 "$cpid"
wait "$cpid" 2>/dev/null
cpid=
wait_progress "$vpid $apid" is_state "$apid" unobscured || fail "C gone: A not uncovered"
start_visd
reconnected_twice() {
	[ "$(grep -c 'visd mirror: connected again' "$dir/viscomp.log")" -ge 2 ]
}
wait_progress "$dpid" reconnected_twice || fail "viscomp did not connect again: $progress_why"
check_mirror "visd back again" 3 "$apid" "$wpid"
echo "visd back again: C, gone meanwhile, is not in it; A $(visd_of "$apid"), W $(visd_of "$wpid")"

# The end: the clients go, and so do their windows in visd.
for pid in $apid $wpid; do
	kill -9 "$pid" 2>/dev/null
	wait "$pid" 2>/dev/null
done
apid= wpid=
only_outside() {
	[ -z "$(ctl list 2>/dev/null)" ] && [ "$(tree | grep -c .)" -eq 1 ]
}
wait_progress "$vpid $dpid" only_outside || fail "windows left: $(tree | tr '\n' ';')"
kill "$vpid"
wait "$vpid"
status=$?
vpid=
[ "$status" -eq 0 ] || fail "viscomp exited with $status"
if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer\|runtime error' "$dir/viscomp.log"; then
	fail "sanitizer report"
fi
echo "test-viscomp-visd: ok"
