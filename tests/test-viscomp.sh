#!/bin/sh
# viscomp with real, unmodified clients: a headless viscomp (one 1280x720 output, pixman,
# mirroring its model into a visd with --visd), two
# weston-simple-shm (A, which the test covers, and W, a witness that stays in view and keeps
# drawing) and foot (the cover, opaque). Through viscompctl, the test covers A with foot, partly
# and wholly, raises and lowers A, and reads `viscompctl list --json`:
#   - partly covered, A keeps drawing (its commits go on);
#   - wholly covered (or lowered below foot), A gets no frame callback: its commits per second
#     fall to 0, its commits stop, and its process uses no more CPU time (/proc/PID/stat) while
#     W draws 120 frames;
#   - uncovered (or raised), A draws again; off the output, it stops as when covered;
#   - uncovered, A's frame callback is sent within the first two output frames viscomp handles
#     after the command (viscompctl stats: max_frames of every uncover), even while A is stopped
#     (SIGSTOP), and A commits again;
#   - under a cover with a client-side shadow (tests/wl-hostile --shadow: translucent in a margin,
#     its opaque region the buffer inset by it), A keeps drawing while the margin alone lies over
#     part of it, though the cover's buffer covers it wholly; under the opaque inside, it stops;
#   - what grim takes of the screen (screencopy) shows it: foot where it covers A, A where
#     nothing does, the background where nothing is;
#   - visd, which viscomp mirrors its windows into, says A's state as viscompctl does each time.
# Every wait follows progress (tests/progress.sh): it fails only when a process is gone or the
# processes named used under 100 ms of CPU time in 60 s. The figures go to the log.
# Usage: test-viscomp.sh BUILD-DIR. Exits 77 (skipped) where viscomp is not built.
set -u
build=${1:?usage: test-viscomp.sh BUILD-DIR}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl
hostile=$build/tests/wl-hostile
[ -x "$viscomp" ] || { echo "$viscomp not built: skipped"; exit 77; }
for prog in "$viscompctl" "$visd" "$visctl" "$hostile"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done
for prog in weston-simple-shm foot grim; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed (tools/dev.sh install)"; exit 1; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-viscomp.XXXXXX") || exit 1
chmod 700 "$dir"
dpid= vpid= apid= wpid= fpid= spid=
cleanup() {
	[ -z "$apid" ] || kill -CONT "$apid" 2>/dev/null # stopped, it would not end
	for pid in $spid $fpid $apid $wpid $vpid $dpid; do
		kill "$pid" 2>/dev/null
	done
	for pid in $spid $fpid $apid $wpid $vpid $dpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-viscomp: $1"
	echo "--- viscomp's log:"
	tail -n 30 "$dir/viscomp.log"
	echo "--- viscompctl list:"
	ctl list 2>&1
	exit 1
}

. "$(dirname "$0")/viscomp-env.sh"
viscomp_env "$dir"

# CPU time (clock ticks) process PID has used.
cpu() {
	awk '{ print $14 + $15 }' /proc/"$1"/stat
}

# The same in microseconds, from the scheduler's nanoseconds where the kernel keeps them
# (/proc/PID/schedstat), else from the ticks: a client drawing at 60 Hz uses ~10 ms a second,
# about one tick, which the ticks alone show too coarsely.
cpu_us() {
	if [ -r /proc/"$1"/schedstat ]; then
		awk '{ printf "%d\n", $1 / 1000 }' /proc/"$1"/schedstat
	else
		echo $(($(cpu "$1") * 1000000 / $(getconf CLK_TCK)))
	fi
}

# shot NAME: a picture of the screen into $dir/NAME.ppm (grim, through screencopy).
shot() {
	grim -t ppm "$dir/$1.ppm" 2>"$dir/grim.log" || fail "grim: $(cat "$dir/grim.log")"
}

# pixel NAME X Y: "R G B" at X, Y of $dir/NAME.ppm (P6, 255, no comments: grim's).
pixel() {
	header=$(head -n 3 "$dir/$1.ppm" | wc -c)
	width=$(sed -n '2{s/ .*//p;q}' "$dir/$1.ppm")
	od -An -tu1 -j $((header + ($3 * width + $2) * 3)) -N 3 "$dir/$1.ppm" |
		awk '{ print $1, $2, $3 }'
}

# The background viscomp clears to, (0.18, 0.20, 0.22) in output.c.
background="46 51 56"

# Whether A's total commits passed $1.
a_commits_past() {
	n=$(json_field "$apid" commits_total)
	[ -n "$n" ] && [ "$n" -gt "$1" ]
}

# Whether the witness's total frames passed $1.
w_frames_past() {
	n=$(json_field "$wpid" frames_total)
	[ -n "$n" ] && [ "$n" -gt "$1" ]
}

# A's state in visd: its one window (weston-simple-shm has one surface) carries the external ID
# wayland (2) : pid << 32 | the surface's object ID.
visd_state() {
	"$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null |
		awk -v tag="$(printf '2:0x%x' "$1")" \
			'index($NF, tag) == 1 && length($NF) == length(tag) + 8 { print $8; exit }'
}

# Whether visd says of A what viscompctl says.
visd_agrees() {
	v=$(visd_state "$apid")
	[ -n "$v" ] && [ "$v" = "$(json_field "$apid" state)" ]
}

# Named: visd alone, whose work it is (viscomp sends at every frame, and W keeps it busy).
check_visd() {
	wait_progress "$dpid" visd_agrees ||
		fail "$1: visd says A is $(visd_state "$apid"), viscompctl $(json_field "$apid" state)"
}

# Whether A's state is $1 and its commits in the last second $2 (any: '').
a_is() {
	[ "$(json_field "$apid" state)" = "$1" ] || return 1
	[ -z "${2:-}" ] || [ "$(json_field "$apid" commits)" = "$2" ]
}

"$visd" --socket "$dir/visd.sock" --screen 1280x720 2>"$dir/visd.log" &
dpid=$!
wait_progress "$dpid" test -S "$dir/visd.sock" || fail "visd did not start: $progress_why"
viscomp_start --headless 1280x720 --visd "$dir/visd.sock" ||
	fail "viscomp did not start: $progress_why"

# A first, then W out of its way, then foot beside them, overlapping neither.
weston-simple-shm >"$dir/a.log" 2>&1 &
apid=$!
wait_progress "$vpid $apid" listed "$apid" || fail "A not listed: $progress_why"
aid=$id
weston-simple-shm >"$dir/w.log" 2>&1 &
wpid=$!
wait_progress "$vpid $wpid" listed "$wpid" || fail "W not listed: $progress_why"
wid=$id
ctl move "$wid" 1000 450 || fail "move W"
foot -o 'colors.alpha=1.0' sleep 100000 >"$dir/foot.log" 2>&1 &
fpid=$!
wait_progress "$vpid $fpid" listed "$fpid" || fail "foot not listed: $progress_why"
fid=$id
ctl move "$fid" 290 0 || fail "move foot"
ctl raise "$fid" || fail "raise foot"
ctl list >"$dir/list.txt" || fail "list"
[ "$(wc -l <"$dir/list.txt")" -eq 3 ] || fail "list: not 3 windows: $(cat "$dir/list.txt")"
read -r top _ <"$dir/list.txt"
[ "$top" = "$fid" ] || fail "list: foot ($fid) is not on top: $(cat "$dir/list.txt")"

# A's box: foot covers it wholly at 0,0 (700x500 over 250x250) and partly at A's middle.
ax=$(json_field "$apid" x) ay=$(json_field "$apid" y)
aw=$(json_field "$apid" width) ah=$(json_field "$apid" height)
fw=$(json_field "$fpid" width) fh=$(json_field "$fpid" height)
{ [ "$fw" -gt "$((ax + aw))" ] && [ "$fh" -gt "$((ay + ah))" ]; } ||
	fail "foot (${fw}x$fh) too small to cover A at $ax,$ay ${aw}x$ah"

# Drawing: A's commits go on by 60 (a second at 60 Hz) while unobscured.
check_draws() {
	what=$1
	c0=$(json_field "$apid" commits_total) t0=$(cpu "$apid") u0=$(cpu_us "$apid")
	wait_progress "$vpid $apid" a_commits_past $((c0 + 60)) ||
		fail "$what: A does not draw: $progress_why"
	check_visd "$what"
	echo "$what: A $(json_field "$apid" state) (visd: $(visd_state "$apid")), commits/s $(json_field "$apid" commits)," \
		"CPU $t0 -> $(cpu "$apid") ticks, +$(($(cpu_us "$apid") - u0)) us over 60 commits"
}

# Not drawing: A's commits per second fall to 0; then, while W draws 120 frames, A commits
# nothing, and its CPU time grows by at most a tick (stat) and a millisecond (schedstat; it
# uses ~10 ms a second drawing).
check_stopped() {
	what=$1
	wait_progress "$vpid $apid $wpid" a_is fully-obscured 0 ||
		fail "$what: A still $(json_field "$apid" state), $(json_field "$apid" commits) commits/s: $progress_why"
	c0=$(json_field "$apid" commits_total) t0=$(cpu "$apid") u0=$(cpu_us "$apid")
	f0=$(json_field "$wpid" frames_total)
	wait_progress "$vpid $wpid" w_frames_past $((f0 + 120)) ||
		fail "$what: W does not draw: $progress_why"
	c1=$(json_field "$apid" commits_total) t1=$(cpu "$apid") u1=$(cpu_us "$apid")
	[ "$c1" -eq "$c0" ] || fail "$what: A committed $((c1 - c0)) times while covered"
	[ "$t1" -le $((t0 + 1)) ] || fail "$what: A used $((t1 - t0)) ticks of CPU while covered"
	[ "$u1" -le $((u0 + 1000)) ] || fail "$what: A used $((u1 - u0)) us of CPU while covered"
	check_visd "$what"
	echo "$what: A fully-obscured (visd: $(visd_state "$apid")), commits/s 0, commits $c0 -> $c1," \
		"CPU $t0 -> $t1 ticks," \
		"+$((u1 - u0)) us while W drew 120 frames"
}

# The latencies from here on are A's alone: the clients' placement above may have covered and
# uncovered one that had no frame callback pending, whose first callback then waits for it.
ctl stats --reset >/dev/null || fail "stats --reset before the steps"
check_draws "uncovered"

ctl move "$fid" $((ax + aw / 2)) $((ay + ah / 2)) || fail "move foot over A's corner"
wait_progress "$vpid $apid" a_is partially-obscured || fail "A not partially obscured"
check_draws "partly covered"

ctl move "$fid" 0 0 || fail "move foot over A"
check_stopped "covered"

# Covered, A's middle shows foot's body, as foot's body beside A does; the corner nobody covers
# shows the background.
shot covered
cx=$((ax + aw / 2)) cy=$((ay + ah / 2))
foot_body=$(pixel covered $((ax + aw + 40)) "$cy")
[ "$(pixel covered "$cx" "$cy")" = "$foot_body" ] ||
	fail "screen: A's middle is $(pixel covered "$cx" "$cy") under foot, foot is $foot_body"
[ "$(pixel covered 1275 715)" = "$background" ] ||
	fail "screen: the background is $(pixel covered 1275 715), not $background"
echo "screen, covered: A's middle $(pixel covered "$cx" "$cy") = foot's body $foot_body;" \
	"background $background"

ctl move "$fid" 290 0 || fail "move foot away"
wait_progress "$vpid $apid" a_is unobscured || fail "A not unobscured again"
check_draws "uncovered again"

# Uncovered, A's pixels show again: its middle row is neither foot's body nor the background.
shot uncovered
a_row=
for dx in 0 10 20 30 40 50 60; do
	a_row="$a_row/$(pixel uncovered $((ax + aw / 4 + dx)) "$cy")"
done
case $a_row in
*"/$foot_body/$foot_body/$foot_body/"* | *"/$background/$background/$background/"*)
	fail "screen: A's middle row is $a_row after foot left" ;;
esac
echo "screen, uncovered: A's middle row $a_row"

ctl move "$fid" 0 0 || fail "move foot over A again"
check_stopped "covered again"
ctl raise "$aid" || fail "raise A"
wait_progress "$vpid $apid" a_is unobscured || fail "A raised, not unobscured"
check_draws "raised over foot"
ctl lower "$aid" || fail "lower A"
check_stopped "lowered under foot"

# Off every output, A is as covered as under foot; back on, it draws again.
ctl raise "$aid" || fail "raise A again"
ctl move "$aid" -400 "$ay" || fail "move A off the output"
check_stopped "off the output"
ctl move "$aid" "$ax" "$ay" || fail "move A back"
wait_progress "$vpid $apid" a_is unobscured || fail "A back, not unobscured"
check_draws "back on the output"

# stats: each output frame's libvis time, and the latency of every cover and uncover above
# (foot moved over A, A lowered, A moved off the output; and back): counted, not timed.
# A line: NAME count=N median_us=M p99_us=P max_us=X, and on cover and uncover max_frames=F.
stat_head='count=\([0-9]*\) median_us=[0-9.]* p99_us=[0-9.]* max_us=[0-9.]*'
stat_count() {
	sed -n "s/^$1 $stat_head\( max_frames=[0-9]*\)\{0,1\}\$/\1/p" "$dir/stats.txt"
}
# The output frames the slowest of the line's latencies took.
stat_frames() {
	sed -n "s/^$1 $stat_head max_frames=\([0-9]*\)\$/\2/p" "$dir/stats.txt"
}
# Uncovered, A's frame callback went out within the first two output frames viscomp handled
# after the command (1: the first). Counted in viscomp's frames, which no slow client delays: A
# was stopped with its callback pending, and viscomp sends it in the first frame whose update
# sees A visible. (A cover's frames are not checked: the first frame in which A has a callback
# pending to withhold depends on how fast A answered the last one.)
check_uncover_frames() {
	f=$(stat_frames uncover)
	[ -n "$f" ] && [ "$f" -ge 1 ] && [ "$f" -le 2 ] && return 0
	lines=$(tr '\n' ';' <"$dir/stats.txt")
	fail "$1: A's frame callback not within the first 2 output frames after the uncover: $lines"
}
ctl stats >"$dir/stats.txt" || fail "stats"
[ "$(wc -l <"$dir/stats.txt")" -eq 3 ] || fail "stats: not 3 lines: $(cat "$dir/stats.txt")"
[ "$(stat_count frame)" -gt 0 ] 2>/dev/null || fail "stats: no frame: $(cat "$dir/stats.txt")"
[ "$(stat_count cover)" -ge 3 ] 2>/dev/null || fail "stats: under 3 covers: $(cat "$dir/stats.txt")"
[ "$(stat_count uncover)" -ge 3 ] 2>/dev/null ||
	fail "stats: under 3 uncovers: $(cat "$dir/stats.txt")"
check_uncover_frames "stats"
ctl stats --json 2>/dev/null && fail "stats --json succeeded"
echo "stats: $(tr '\n' ';' <"$dir/stats.txt")"
ctl stats --reset >/dev/null || fail "stats --reset"
ctl stats >"$dir/stats.txt" || fail "stats after --reset"
[ "$(stat_count cover)" -eq 0 ] 2>/dev/null && [ "$(stat_count uncover)" -eq 0 ] 2>/dev/null ||
	fail "stats: latencies left after --reset: $(cat "$dir/stats.txt")"

# A cover with a client-side shadow: wl-hostile --shadow, not a real client, because the test
# must know where the opaque region lies. foot sets its opaque region to the whole window or
# none (colors.alpha); weston's toolkit clients (weston-terminal, …) inset theirs by their
# theme's margin and corner radius, figures of the theme, and only for opaque widgets. Its
# buffer is A's box grown by the margin on every side, so that its opaque inside can lie
# exactly over A. foot goes out of the way first; away from A, S lies over foot alone.
margin=32
ctl move "$fid" 290 0 || fail "move foot away"
"$hostile" --shadow "$margin" --size $((aw + 2 * margin))x$((ah + 2 * margin)) \
	>"$dir/shadow.log" 2>&1 &
spid=$!
wait_progress "$vpid $spid" listed "$spid" || fail "the shadowed cover S not listed: $progress_why"
sid=$id
ctl raise "$sid" || fail "raise S"
ctl move "$sid" 600 250 || fail "move S away"
wait_progress "$vpid $apid" a_is unobscured || fail "A not unobscured beside S"

# The margin alone over A's left 16 columns, the inside over the rest: S's buffer covers A
# wholly, its opaque region does not. A keeps drawing (a compositor that took the buffer for
# opaque would say A is fully obscured).
a_covered() {
	! a_is unobscured
}
ctl move "$sid" $((ax - margin + 16)) $((ay - margin)) || fail "move S's margin over A"
wait_progress "$vpid $apid" a_covered || fail "A not covered by S"
a_is partially-obscured ||
	fail "under S's margin: A is $(json_field "$apid" state), not partially-obscured"
check_draws "under the shadow's margin"

# The inside exactly over A: no pixel of A shows; A stops.
ctl move "$sid" $((ax - margin)) $((ay - margin)) || fail "move S's inside over A"
check_stopped "under the shadow's inside"

# Moved away: A's frame callback within two output frames, and A draws again. A is stopped
# (SIGSTOP) meanwhile, the slowest of clients: sending the callback is viscomp's part alone, so
# it must come as soon; A's commit just has to follow once A goes on.
uncover_timed() {
	"$viscompctl" stats >"$dir/stats.txt" && [ "$(stat_count uncover)" -ge 1 ] 2>/dev/null
}
ctl stats --reset >/dev/null || fail "stats --reset"
c0=$(json_field "$apid" commits_total)
kill -STOP "$apid"
ctl move "$sid" 600 250 || { kill -CONT "$apid"; fail "move S away again"; }
wait_progress "$vpid" uncover_timed
timed=$?
kill -CONT "$apid"
[ "$timed" -eq 0 ] || fail "stats: S moved away, no uncover timed: $(tr '\n' ';' <"$dir/stats.txt")"
check_uncover_frames "S moved away"
wait_progress "$vpid $apid" a_commits_past "$c0" ||
	fail "S moved away: A does not draw: $progress_why"
echo "S moved away: A's callback within $(stat_frames uncover) output frame(s), A commits again;" \
	"stats: $(tr '\n' ';' <"$dir/stats.txt")"
check_draws "S moved away"
kill "$spid"
wait "$spid" 2>/dev/null
spid=

# resize: foot takes the size asked (its cells permitting: it may round down).
foot_size() {
	w=$(json_field "$fpid" width) h=$(json_field "$fpid" height)
	[ "$w" -le 400 ] && [ "$w" -gt 350 ] && [ "$h" -le 300 ] && [ "$h" -gt 250 ]
}
ctl resize "$fid" 400 300 || fail "resize foot"
wait_progress "$vpid $fpid" foot_size ||
	fail "foot is $(json_field "$fpid" width)x$(json_field "$fpid" height) after resize 400 300"
echo "resize: foot asked for 400x300, is $(json_field "$fpid" width)x$(json_field "$fpid" height)"

# Errors are answered as errors; close ends foot's window and process.
ctl move 999999 0 0 2>/dev/null && fail "move of no window succeeded"
ctl frobnicate 2>/dev/null && fail "an unknown command succeeded"
ctl list a b c d e f g h i j k l m n o p q 2>/dev/null && fail "a 17-word line succeeded"
ctl list --yaml 2>/dev/null && fail "list --yaml succeeded"
ctl close "$fid" || fail "close foot"
wait_progress "$vpid $fpid" progress_gone "$fpid" || fail "foot did not exit on close"
wait "$fpid" 2>/dev/null
fpid=

kill "$vpid"
wait "$vpid"
status=$?
vpid=
[ "$status" -eq 0 ] || fail "viscomp exited with $status"
if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer\|runtime error' "$dir/viscomp.log"; then
	fail "sanitizer report"
fi
echo "test-viscomp: ok"
