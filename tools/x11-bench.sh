#!/bin/bash
# visd-x11's benchmark: start-up time to mirror a desktop of N windows, and the time from an X
# event's arrival to the turn's end (the synthetic VisibilityNotify sent), on a private Xvfb
# without a window manager. tests/x11-churn makes N override-redirect windows (nested, bordered,
# shaped, some InputOnly), then changes its top-level windows one at a time, in two runs a size:
# drags (moves by up to 64 pixels, as a user drags a window) and jumps (moves anywhere on the
# screen, with a raise); the bridge runs with --send-events always, so that every change of a
# state is told, and reports its turn times at exit (-v). Usage: tools/x11-bench.sh [BUILD-DIR]
# [N...] (default build-release, 100 1000 10000; MOVES=500 a run). Prints a table.
set -u
build=${1:-build-release}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(100 1000 10000)
moves=${MOVES:-500}
for prog in "$build/bridge/x11/visd-x11" "$build/daemon/visd" "$build/tests/x11-churn"; do
	[ -x "$prog" ] || { echo "x11-bench: $prog is not built" >&2; exit 1; }
done
dir=$(mktemp -d "${TMPDIR:-/tmp}/x11-bench.XXXXXX") || exit 1
pids=()
cleanup() {
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
	wait 2>/dev/null
	rm -rf "$dir"
}
trap cleanup EXIT
wait_for() {
	for _ in $(seq 1200); do "$@" && return 0; sleep 0.05; done
	return 1
}

printf '%-8s %-5s %12s %8s %10s %10s %10s %10s\n' windows moves start-up/ms turns 'turn p50' \
	'turn p99' 'told p50' 'told p99'
for n in "${sizes[@]}"; do
for kind in drag jump; do
	exec 3>"$dir/display"
	Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp -noreset >/dev/null 2>&1 &
	xpid=$!
	exec 3>&-
	wait_for test -s "$dir/display" || { echo "x11-bench: Xvfb did not start" >&2; exit 1; }
	export DISPLAY=:$(head -n 1 "$dir/display")
	: >"$dir/display"
	drag=
	[ $kind = drag ] && drag=--drag
	"$build/tests/x11-churn" --windows "$n" --rounds 0 --seed 1 --hold --moves "$moves" $drag \
		>"$dir/churn.out" &
	cpid=$!
	pids=("$xpid" "$cpid")
	wait_for grep -q live "$dir/churn.out" || { echo "x11-bench: x11-churn failed" >&2; exit 1; }
	rm -f "$dir/sock"
	"$build/daemon/visd" --socket "$dir/sock" --screen 1920x1080 2>/dev/null &
	vpid=$!
	pids+=("$vpid")
	wait_for test -S "$dir/sock"
	"$build/bridge/x11/visd-x11" -s "$dir/sock" -v --send-events always --translucency off \
		2>"$dir/bridge.log" &
	bpid=$!
	pids+=("$bpid")
	wait_for grep -q mirrored "$dir/bridge.log"
	kill -USR1 "$cpid"
	wait_for grep -q 'moves done' "$dir/churn.out"
	sleep 0.3
	kill "$bpid"
	wait "$bpid" 2>/dev/null
	start=$(sed -n 's/.*mirrored [0-9]* windows in \([0-9.]*\) ms.*/\1/p' "$dir/bridge.log")
	turns=$(sed -n 's/.*: turns: \([0-9]*\), .*/\1/p' "$dir/bridge.log")
	tp=$(sed -n 's/.*: turns: .*p50 \([0-9]*\) µs, p99 \([0-9]*\) µs.*/\1 \2/p' "$dir/bridge.log")
	sp=$(sed -n 's/.*turns that sent synthetic events: .*p50 \([0-9]*\) µs, p99 \([0-9]*\) µs.*/\1 \2/p' \
		"$dir/bridge.log")
	read -r tp50 tp99 <<<"${tp:-- -}"
	read -r sp50 sp99 <<<"${sp:-- -}"
	printf '%-8s %-5s %12s %8s %10s %10s %10s %10s\n' "$n" $kind "$start" "$turns" "${tp50}µs" \
		"${tp99}µs" "${sp50}µs" "${sp99}µs"
	kill "$cpid" "$vpid" "$xpid" 2>/dev/null
	wait 2>/dev/null
	pids=()
done
done
