#!/bin/sh
# Unmodified applications that act on VisibilityNotify, under a compositing manager, with
# visd-x11 and without: what the bridge changes for a user's own programs. On a private Xvfb with
# openbox and picom (tests/realapps.sh sets the desktop up), Alacritty runs a writer printing a
# line every 10 ms, and its CPU time per 300 lines says whether it draws:
#   without visd-x11, covered by a window: it draws on (X, redirected, says it is unobscured);
#   visd-x11 started late, under the cover: it stops; uncovered: it draws again; partly covered:
#   it draws; covered again: it stops; a second Alacritty started under the cover: it never
#   draws until uncovered.
# Every span it stops in must cost under a quarter of every span it draws in, in the same run
# (the same machine, the same load). Then i3lock: with visd-x11, covered by a window raised over
# it, it raises itself back; without visd-x11 it stays under the cover (for ten times the lines
# a ticker printed while it took with the bridge); visd-x11 started late: it raises itself.
# Then under xcompmgr, where installed, Alacritty's first four spans again.
# SEND_EVENTS=never runs the bridge without its synthetic events, where this test must fail
# (nothing is told); BRIDGE: another program of visd-x11's interface.
# Usage: test-realapps.sh BUILD-DIR. Exits 77 (skipped) where visd-x11 is not built or Xvfb,
# openbox, picom, alacritty, i3lock or xwininfo is missing.
build=${1:?usage: test-realapps.sh BUILD-DIR}
[ -x "${BRIDGE:-$build/bridge/x11/visd-x11}" ] || { echo "visd-x11 not built: skipped"; exit 77; }
for prog in Xvfb openbox picom alacritty i3lock xwininfo xprop; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed: skipped"; exit 77; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-realapps.XXXXXX") || exit 1
cleanup() {
	ra_cleanup
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-realapps: FAIL: $1"
	[ -n "${2:-}" ] && sed 's/^/  | /' "$2"
	exit 1
}

. "$(dirname "$0")/progress.sh"
. "$(dirname "$0")/realapps.sh"
for prog in "$visd" "$visctl" "$cover"; do
	[ -x "$prog" ] || fail "$prog not built"
done

span_lines=300 settle=30
status=0
# Records Alacritty's span: SCENARIO, WITH (the bridge: yes or no), EXPECT (draws or stops).
measure() {
	ra_span $span_lines $settle
	printf '%-9s %-42s %-5s %5s ticks %6s%%  %s\n' "$cm" "$1" "$2" "$ticks" "$pct" "$3"
	case $3 in
	draws) [ -n "$min_draws" ] && [ "$ticks" -ge "$min_draws" ] || min_draws=$ticks ;;
	stops) [ -n "$max_stops" ] && [ "$ticks" -le "$max_stops" ] || max_stops=$ticks ;;
	esac
}
# Every span Alacritty stops in under a quarter of every span it draws in, this run.
judge() {
	if [ "$min_draws" -gt $((4 * max_stops)) ]; then
		echo "test-realapps: $cm: spans drawing >= $min_draws ticks, stopped <= $max_stops"
	else
		echo "test-realapps: FAIL: $cm: a span drawing took $min_draws ticks, one stopped $max_stops"
		status=1
	fi
	min_draws= max_stops=
}

echo "test-realapps: Alacritty's CPU time per $span_lines lines printed (10 ms ticks, % of a core)"
ra_start_x
cm=picom
ra_start_cm picom

# Without the bridge, then the bridge started late, under the cover.
ra_start_alacritty realapps-a
measure "uncovered" no draws
ra_cover map 0 0 $ra_width $ra_height
measure "covered" no draws
ra_start_bridge
ra_wait_state "$app_win" fully-obscured
measure "covered, visd-x11 started late" yes stops
ra_cover unmap
ra_wait_state "$app_win" unobscured
measure "uncovered" yes draws
# A corner of its window.
geometry=$(xwininfo -id "$app_win" | sed -n 's/.*Absolute upper-left [XY]: *//p' | tr '\n' ' ')
ra_cover map $(echo "$geometry" | awk '{ print $1 + 20, $2 + 20, 100, 100 }')
ra_wait_state "$app_win" partially-obscured
measure "partly covered" yes draws
ra_cover map 0 0 $ra_width $ra_height
ra_wait_state "$app_win" fully-obscured
measure "covered" yes stops
ra_stop_app

# Started under the cover: told it is covered as it maps.
ra_start_alacritty realapps-b
ra_wait_state "$app_win" fully-obscured
measure "started covered" yes stops
ra_cover unmap
ra_wait_state "$app_win" unobscured
measure "then uncovered" yes draws
ra_stop_app
judge

# i3lock: covered, it raises itself back over the cover, with the bridge; a ticker's lines
# measure how long that took, and ten times as long (at least 100 lines) it must stay covered
# without the bridge.
ra_start_ticker
ra_start_i3lock
ra_lines ticker
from=$lines
ra_cover map 0 0 $ra_width $ra_height
if wait_progress "$lock_pid $bpid $vpid $xpid" ra_lock_on_top; then
	ra_lines ticker
	took=$((lines - from))
	echo "test-realapps: i3lock raised itself over the cover with visd-x11 ($took lines)"
else
	echo "test-realapps: FAIL: i3lock stayed under the cover with visd-x11 ($progress_why)"
	status=1 took=0
fi
ra_stop_bridge
ra_cover raise
[ "$answer" = ok ] && ! ra_lock_on_top || fail "i3lock is not under the raised cover"
wait_lines=$((10 * took))
[ $wait_lines -ge 100 ] || wait_lines=100
ra_lines ticker
wait_progress "$tick_pid $lock_pid $xpid" ra_reached ticker $((lines + wait_lines)) ||
	fail "the ticker stopped ($progress_why)"
if ra_lock_on_top; then
	echo "test-realapps: FAIL: i3lock raised itself without visd-x11"
	status=1
else
	echo "test-realapps: i3lock stayed under the cover without visd-x11 ($wait_lines lines)"
fi
ra_start_bridge
if wait_progress "$lock_pid $bpid $vpid $xpid" ra_lock_on_top; then
	echo "test-realapps: i3lock raised itself once visd-x11 started"
else
	echo "test-realapps: FAIL: i3lock stayed under the cover after visd-x11 started ($progress_why)"
	status=1
fi
ra_stop_i3lock
ra_stop_bridge
ra_cover unmap

# xcompmgr, shorter: the first four spans.
if command -v xcompmgr >/dev/null 2>&1; then
	ra_stop_cm
	cm=xcompmgr
	ra_start_cm xcompmgr
	ra_start_alacritty realapps-c
	measure "uncovered" no draws
	ra_cover map 0 0 $ra_width $ra_height
	measure "covered" no draws
	ra_start_bridge
	ra_wait_state "$app_win" fully-obscured
	measure "covered, visd-x11 started late" yes stops
	ra_cover unmap
	ra_wait_state "$app_win" unobscured
	measure "uncovered" yes draws
	ra_stop_app
	judge
else
	echo "test-realapps: xcompmgr not installed: no run under it"
fi
[ $status = 0 ] || { echo "test-realapps: the bridge's log:"; cat "$blog" 2>/dev/null; }
exit $status
