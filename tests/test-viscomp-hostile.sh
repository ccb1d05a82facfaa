#!/bin/sh
# viscomp against clients that misbehave on purpose (tests/wl-hostile.c), beside a real one: a
# headless viscomp (1280x720) mirroring into a visd, and weston-simple-shm W, a witness out of
# the way that must keep getting frames throughout. In turn:
#   - no-ack: a toplevel commits a buffer without ever acking a configure: viscomp ends it with
#     xdg_surface's protocol error (unconfigured_buffer) and lists nothing of it;
#   - ack-once: a toplevel acks its first configure only, then ignores 50 resizes and draws on
#     at its frame pace: it keeps its size and its frames, viscomp keeps answering;
#   - flood: a client commits as fast as the socket takes it (100,000 a second and more on an
#     idle machine), never waiting for frame callbacks. Covered by an opaque window, it gets no
#     frame callback (its count stays put) while it commits FLOOD (default 50,000) times and W
#     draws on; nor does it make viscomp render a frame (with W stopped, none while it commits
#     20,000 times); uncovered, it gets them again;
#   - surfaces: one client with 1,000 toplevels, moved through viscompctl into a grid 30 wide:
#     the 660 on the output unobscured, the 30 across its bottom edge partially obscured, the
#     310 below it fully obscured, in viscompctl's list and in visd; then killed, all go;
#   - subsurfaces: a toplevel with a chain of subsurfaces 8 deep (each 100x100 at 20,20 from
#     its parent, so 6, 7 and 8 stick out of the 200x200 toplevel), covered by an opaque
#     window exactly over the toplevel: in viscompctl and in visd the toplevel and
#     subsurfaces 1–5 are fully obscured, 6–8 partially (not clipped to their parent); 6–8
#     keep getting frame callbacks, the others get none; uncovered, all draw again.
#   - churn: 2,000 toplevels created and destroyed as fast as viscomp configures them (one in
#     four before it does), and as many subsurfaces of a toplevel that stays, while visd is
#     stopped (its answers come after the surfaces went): what stays is all that viscompctl and
#     visd hold of it.
# After each client, viscompctl lists nothing of it and visd holds no window of it; at the end
# viscomp has the descriptors it had before any client, and exits 0 (under ASan: no report).
# Waits follow progress (tests/progress.sh). Usage: test-viscomp-hostile.sh BUILD-DIR. Exits 77
# (skipped) where viscomp is not built.
set -u
build=${1:?usage: test-viscomp-hostile.sh BUILD-DIR}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl
hostile=$build/tests/wl-hostile
flood=${FLOOD:-50000}
[ -x "$viscomp" ] || { echo "$viscomp not built: skipped"; exit 77; }
for prog in "$viscompctl" "$visd" "$visctl" "$hostile"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done
command -v weston-simple-shm >/dev/null 2>&1 ||
	{ echo "weston-simple-shm not installed (tools/dev.sh install)"; exit 1; }

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-viscomp-hostile.XXXXXX") || exit 1
chmod 700 "$dir"
dpid= vpid= wpid= hpid= cpid=
cleanup() {
	for pid in $hpid $cpid $wpid $vpid $dpid; do
		kill -9 "$pid" 2>/dev/null
	done
	for pid in $hpid $cpid $wpid $vpid $dpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-viscomp-hostile: $1"
	echo "--- viscomp's log:"
	tail -n 30 "$dir/viscomp.log"
	exit 1
}

# A wait whose processes stay busy (a client drawing) gives up after 5 minutes, not meson's 10.
progress_ceiling=${progress_ceiling:-300}
. "$(dirname "$0")/viscomp-env.sh"
viscomp_env "$dir"

alive() {
	kill -0 "$vpid" 2>/dev/null || fail "viscomp died"
}

# Whether viscompctl lists no window of process PID and visd holds none of its surfaces (their
# external IDs are 2:0x<pid in hex><8 hex digits>).
forgotten() {
	! ctl list 2>/dev/null | grep -q " pid=$1 " || return 1
	! "$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null |
		grep -q " 2:0x$(printf %x "$1")[0-9a-f]\{8\}\$"
}

# Kills process PID (SIGKILL) and waits until viscomp and visd have forgotten it.
kill_client() {
	kill -9 "$1" 2>/dev/null
	wait "$1" 2>/dev/null
	wait_progress "$vpid $dpid" forgotten "$1" || fail "$2: not forgotten: $progress_why"
}

# Whether the witness's total frames passed $1.
w_frames_past() {
	n=$(json_field "$wpid" frames_total)
	[ -n "$n" ] && [ "$n" -gt "$1" ]
}

# W gets 30 more frames: it goes on while whatever else happens.
check_witness() {
	f0=$(json_field "$wpid" frames_total)
	wait_progress "$vpid $wpid" w_frames_past $((f0 + 30)) ||
		fail "$1: the witness gets no frames: $progress_why"
}

# A wl-hostile's last report line (FILE): its fields into $commits, $frames (comma-separated,
# one a surface) and $ms.
report() {
	line=$(grep '^commits=' "$1" | tail -n 1)
	commits=$(echo "$line" | sed -n 's/.*commits=\([0-9]*\).*/\1/p')
	frames=$(echo "$line" | sed -n 's/.*frames=\([0-9,]*\).*/\1/p')
	ms=$(echo "$line" | sed -n 's/.*ms=\([0-9]*\).*/\1/p')
	[ -n "$commits" ]
}

# frame N: surface N's frames (from 0) of the last report() into $f.
frame() {
	f=$(echo "$frames" | cut -d, -f$(($1 + 1)))
}

# Whether the wl-hostile of FILE has said it is ready; its pid and surface IDs into $rpid, $sids.
ready() {
	line=$(grep '^ready ' "$1" | head -n 1)
	[ -n "$line" ] || return 1
	rpid=$(echo "$line" | sed -n 's/.*pid=\([0-9]*\).*/\1/p')
	sids=$(echo "$line" | sed -n 's/.*surfaces=\([0-9,]*\).*/\1/p')
}

# visd_state PID SURFACE: visd's state of the window of that wl_surface (object ID) of PID.
visd_state() {
	"$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null |
		awk -v tag="$(printf '2:0x%x%08x' "$1" "$2")" '$NF == tag { print $8; exit }'
}

"$visd" --socket "$dir/visd.sock" --screen 1280x720 2>"$dir/visd.log" &
dpid=$!
wait_progress "$dpid" test -S "$dir/visd.sock" || fail "visd did not start: $progress_why"
viscomp_start --headless 1280x720 --visd "$dir/visd.sock" ||
	fail "viscomp did not start: $progress_why"
fds=$(ls /proc/"$vpid"/fd | wc -l)

# The witness, at the right of the output, clear of every other window here.
weston-simple-shm >"$dir/w.log" 2>&1 &
wpid=$!
wait_progress "$vpid $wpid" listed "$wpid" || fail "W not listed: $progress_why"
ctl move "$id" 1000 100 || fail "move W"
check_witness "start"

# --- no-ack: a buffer committed with no configure acked is a protocol error.
"$hostile" --no-ack >"$dir/noack.out" 2>&1 &
hpid=$!
wait_progress "$vpid $hpid" progress_gone "$hpid" || fail "no-ack: not ended: $progress_why"
wait "$hpid"
status=$?
pid=$hpid hpid=
[ "$status" -eq 3 ] || fail "no-ack: exit status $status, not 3: $(cat "$dir/noack.out")"
grep -q '^protocol-error interface=xdg_surface code=3$' "$dir/noack.out" ||
	fail "no-ack: not xdg_surface's unconfigured_buffer: $(cat "$dir/noack.out")"
wait_progress "$vpid $dpid" forgotten "$pid" || fail "no-ack: not forgotten: $progress_why"
check_witness "no-ack"
echo "no-ack: $(tail -n 1 "$dir/noack.out"); viscomp and visd forgot it"

# --- ack-once: later configures never acked; the window keeps its size and draws on.
"$hostile" --ack-once >"$dir/ackonce.out" 2>&1 &
hpid=$!
wait_progress "$vpid $hpid" listed "$hpid" || fail "ack-once: not listed: $progress_why"
hid=$id
i=0
while [ "$i" -lt 50 ]; do
	ctl resize "$hid" $((300 + i)) 250 || fail "ack-once: resize $i"
	i=$((i + 1))
done
commits_past() {
	n=$(json_field "$1" commits_total)
	[ -n "$n" ] && [ "$n" -gt "$2" ]
}
c0=$(json_field "$hpid" commits_total)
wait_progress "$vpid $hpid" commits_past "$hpid" $((c0 + 60)) ||
	fail "ack-once: does not draw after 50 resizes it never acked: $progress_why"
size="$(json_field "$hpid" width)x$(json_field "$hpid" height)"
[ "$size" = 200x200 ] || fail "ack-once: its window is $size, not the 200x200 it draws"
check_witness "ack-once"
kill_client "$hpid" "ack-once"
hpid=
echo "ack-once: 50 resizes never acked; it drew 60 more frames at $size; forgotten when killed"

# --- flood: covered, no frame callback however fast it commits.
"$hostile" --size 400x400 >"$dir/cover.out" 2>&1 &
cpid=$!
wait_progress "$vpid $cpid" listed "$cpid" || fail "cover: not listed: $progress_why"
cid=$id
"$hostile" --flood >"$dir/flood.out" 2>&1 &
hpid=$!
wait_progress "$vpid $hpid" listed "$hpid" || fail "flood: not listed: $progress_why"
hid=$id
ctl move "$hid" 100 100 || fail "flood: move"
ctl move "$cid" 0 0 || fail "cover: move"
ctl raise "$cid" || fail "cover: raise"
is_state() {
	[ "$(json_field "$1" state)" = "$2" ]
}
wait_progress "$vpid $hpid" is_state "$hpid" fully-obscured ||
	fail "flood: not covered: $(json_field "$hpid" state)"
# Answers sent before the cover came have reached it once its commits have gone on by 10,000.
report "$dir/flood.out" || fail "flood: no report"
flood_past() {
	report "$dir/flood.out" && [ "$commits" -ge "$1" ]
}
wait_progress "$vpid $hpid" flood_past $((commits + 10000)) || fail "flood: stopped: $progress_why"
c0=$commits f0=$frames ms0=$ms
w0=$(json_field "$wpid" frames_total)
t0=$(date +%s)
wait_progress "$vpid $hpid" flood_past $((c0 + flood)) || fail "flood: stopped: $progress_why"
[ "$frames" = "$f0" ] ||
	fail "flood: covered, it got frame callbacks: $f0 -> $frames over $((commits - c0)) commits"
ctl list >/dev/null || fail "flood: list does not answer"
w1=$(json_field "$wpid" frames_total)
rate=$(((commits - c0) * 1000 / (ms - ms0 + 1)))
[ "$w1" -gt "$w0" ] ||
	fail "flood: the witness got no frame while the flood ran $(($(date +%s) - t0)) s"
echo "flood: covered, $((commits - c0)) commits in $((ms - ms0)) ms ($rate a second)," \
	"frame callbacks $f0 -> $frames; the witness got $((w1 - w0)) frames meanwhile"
# Nor does the screen redraw for it: with W stopped (SIGSTOP), nothing else draws, and the
# output draws no frame (viscompctl outputs) while the flooder commits 20,000 times (after
# 20,000 for a frame W may have asked for before it stopped).
kill -STOP "$wpid"
output_frames() {
	ctl outputs | sed -n 's/.* frames=\([0-9]*\)$/\1/p'
}
wait_progress "$vpid $hpid" flood_past $((commits + 20000)) || fail "flood: stopped: $progress_why"
o0=$(output_frames) c0=$commits
wait_progress "$vpid $hpid" flood_past $((commits + 20000)) || fail "flood: stopped: $progress_why"
o1=$(output_frames)
kill -CONT "$wpid"
[ "$o1" -eq "$o0" ] ||
	fail "flood: covered, its $((commits - c0)) commits brought $((o1 - o0)) output frames"
echo "flood: covered, $((commits - c0)) commits with the witness stopped: output frames $o0 -> $o1"
ctl lower "$cid" || fail "cover: lower"
flood_frames_past() {
	report "$dir/flood.out" && [ "$frames" -gt "$1" ]
}
wait_progress "$vpid $hpid" flood_frames_past "$f0" ||
	fail "flood: uncovered, no frame callback: $progress_why"
echo "flood: uncovered, frame callbacks again ($f0 -> $frames)"
kill_client "$hpid" "flood"
hpid=
kill_client "$cpid" "cover"
cpid=

# --- 1,000 toplevels in a grid, 30 a row of 32x32: rows 0–21 on the output, 22 across its
# bottom edge (704 … 736 of 720), 23–33 below it.
"$hostile" --surfaces 1000 >"$dir/surfaces.out" 2>&1 &
hpid=$!
n_listed() {
	[ "$(ctl list 2>/dev/null | grep -c " pid=$1 ")" -eq "$2" ]
}
wait_progress "$vpid $hpid" n_listed "$hpid" 1000 ||
	fail "surfaces: $(ctl list | grep -c " pid=$hpid ") listed, not 1000: $progress_why"
ctl list | grep " pid=$hpid " | awk '{ print $1 }' | sort -n >"$dir/ids"
k=0
while read -r wid; do
	ctl move "$wid" $((k % 30 * 32)) $((k / 30 * 32)) || fail "surfaces: move $wid"
	k=$((k + 1))
done <"$dir/ids"
# The states expected, by ID.
awk '{ k = NR - 1; s = "fully-obscured"; if (k < 690) s = "partially-obscured"
	if (k < 660) s = "unobscured"; print $1, s }' "$dir/ids" >"$dir/expected"
grid_right() {
	ctl list 2>/dev/null | grep " pid=$hpid " | awk '{ print $1, $4 }' | sort -n >"$dir/states"
	cmp -s "$dir/states" "$dir/expected"
}
wait_progress "$vpid" grid_right ||
	fail "surfaces: states differ: $(diff "$dir/expected" "$dir/states" | head -5)"
# visd: the same states (the surfaces' IDs are the toplevels' in creation order).
wait_progress "$dpid $vpid" ready "$dir/surfaces.out" || fail "surfaces: not ready"
visd_counts() {
	"$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null |
		grep " 2:0x$(printf %x "$hpid")[0-9a-f]\{8\}\$" | awk '{ print $8 }' | sort | uniq -c |
		awk '{ printf "%s=%s ", $2, $1 }'
}
visd_right() {
	[ "$(visd_counts)" = "fully-obscured=310 partially-obscured=30 unobscured=660 " ]
}
wait_progress "$dpid $vpid" visd_right || fail "surfaces: visd says $(visd_counts)"
check_witness "surfaces"
t0=$(date +%s%N)
ctl list --json >/dev/null || fail "surfaces: list --json"
t1=$(date +%s%N)
echo "surfaces: 1000 toplevels in a grid: 660 unobscured, 30 partially, 310 fully obscured" \
	"(visd: $(visd_counts)); list --json in $(((t1 - t0) / 1000000)) ms"
kill_client "$hpid" "surfaces"
hpid=

# --- a subsurface chain 8 deep under a cover exactly over its toplevel.
"$hostile" --subsurfaces 8 >"$dir/sub.out" 2>&1 &
hpid=$!
wait_progress "$vpid $hpid" listed "$hpid" || fail "subsurfaces: not listed: $progress_why"
hid=$id
wait_progress "$vpid $hpid" ready "$dir/sub.out" || fail "subsurfaces: not ready"
"$hostile" >"$dir/cover.out" 2>&1 &
cpid=$!
wait_progress "$vpid $cpid" listed "$cpid" || fail "cover: not listed: $progress_why"
cid=$id
ctl move "$hid" 100 100 || fail "subsurfaces: move"
ctl move "$cid" 100 100 || fail "cover: move"
ctl raise "$cid" || fail "cover: raise"
# visd's states of the surfaces 0 (the toplevel) … 8.
sub_visd() {
	for sid in $(echo "$sids" | tr , ' '); do
		printf ' %s' "$(visd_state "$hpid" "$sid")"
	done
}
# The expected states of surface 0 (the toplevel) … 8.
expect_sub() {
	if [ "$1" -ge 6 ]; then echo partially-obscured; else echo fully-obscured; fi
}
sub_states() {
	is_state "$hpid" fully-obscured || return 1
	s=0
	for sid in $(echo "$sids" | tr , ' '); do
		[ "$(visd_state "$hpid" "$sid")" = "$(expect_sub "$s")" ] || return 1
		s=$((s + 1))
	done
}
wait_progress "$vpid $dpid" sub_states ||
	fail "subsurfaces: viscompctl says $(json_field "$hpid" state); visd:$(sub_visd)"
# Frame callbacks: 6–8 go on (by 30), 0–5 stop. What was answered before the cover came has
# arrived once 8 has two more.
sub_past() {
	report "$dir/sub.out" && frame "$1" && [ "$f" -ge "$2" ]
}
report "$dir/sub.out" && frame 8
wait_progress "$vpid $hpid" sub_past 8 $((f + 2)) || fail "subsurfaces: 8 gets no frames"
report "$dir/sub.out"
before=$frames
for s in 6 7 8; do
	frame "$s"
	wait_progress "$vpid $hpid" sub_past "$s" $((f + 30)) ||
		fail "subsurfaces: $s sticks out but gets no frames: $progress_why"
done
report "$dir/sub.out"
for s in 0 1 2 3 4 5; do
	frame "$s"
	was=$(echo "$before" | cut -d, -f$((s + 1)))
	[ "$f" = "$was" ] || fail "subsurfaces: $s is covered but got frames: $before -> $frames"
done
echo "subsurfaces: covered, frames $before -> $frames (toplevel, 1 … 8); states in visd:" \
	"$(sub_visd)"
ctl lower "$cid" || fail "cover: lower"
for s in 0 1 2 3 4 5; do
	frame "$s"
	wait_progress "$vpid $hpid" sub_past "$s" $((f + 2)) ||
		fail "subsurfaces: $s uncovered gets no frames: $progress_why"
done
check_witness "subsurfaces"
kill_client "$hpid" "subsurfaces"
hpid=
kill_client "$cpid" "cover"
cpid=

# --- churn: 2,000 toplevels created and destroyed as fast as they are configured (one in four
# before), with a subsurface of the one that stays in the same turns. visd is stopped (SIGSTOP)
# meanwhile: viscomp's creates wait for answers that come, once it goes on, after their surfaces
# are gone.
kill -STOP "$dpid"
"$hostile" --churn 2000 >"$dir/churn.out" 2>&1 &
hpid=$!
wait_progress "$vpid $hpid" grep -q '^churned 2000$' "$dir/churn.out" ||
	fail "churn: did not finish: $progress_why: $(tail -n 1 "$dir/churn.out")"
kill -CONT "$dpid"
# What stays: its first toplevel in viscompctl; that and the last subsurface in visd.
churn_left() {
	[ "$(ctl list 2>/dev/null | grep -c " pid=$hpid ")" -eq 1 ] &&
		[ "$("$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null |
			grep -c " 2:0x$(printf %x "$hpid")[0-9a-f]\{8\}\$")" -eq 2 ]
}
wait_progress "$vpid $dpid" churn_left ||
	fail "churn: $(ctl list | grep -c " pid=$hpid ") windows listed;" \
		"visd holds $("$visctl" -s "$dir/visd.sock" --role observer tree | grep -c .)"
check_witness "churn"
kill_client "$hpid" "churn"
hpid=
echo "churn: 2000 toplevels and as many subsurfaces created and destroyed; one toplevel and one" \
	"subsurface left, in viscompctl and visd"

# The end: the witness goes; viscomp holds the descriptors it held before any client.
kill_client "$wpid" "witness"
wpid=
fds_back() {
	[ "$(ls /proc/"$vpid"/fd | wc -l)" -eq "$fds" ]
}
wait_progress "$vpid" fds_back || fail "viscomp has $(ls /proc/"$vpid"/fd | wc -l) descriptors, not $fds"
alive
kill "$vpid"
wait "$vpid"
status=$?
vpid=
[ "$status" -eq 0 ] || fail "viscomp exited with $status"
if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer\|runtime error' "$dir/viscomp.log"; then
	fail "sanitizer report"
fi
echo "test-viscomp-hostile: ok"
