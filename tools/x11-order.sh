#!/bin/bash
# What an unmodified X client sees of its window's visibility while visd-x11 runs: for each run,
# a private Xvfb (1280×720, no window manager), a visd on a private socket, the bridge with the
# run's --send-events mode and, for the cm- runs, xcompmgr; then tests/x11-order plays the client
# and the world that changes its window (x11-order.c says how), checks W's state in visd after
# every change (visctl states --x11), and prints a table per kind of change: the orders of events
# the client saw, the delays of X's first event and of the bridge's synthetic VisibilityNotify
# after the change, and how often the last word the client got was stale (which fails the run).
# Usage: tools/x11-order.sh [BUILD-DIR] [RUN...]; BUILD-DIR default build-release; a RUN is auto,
# always, never (no compositor) or cm-auto, cm-always, cm-never (xcompmgr), default auto always
# cm-auto. REPEAT=N cycles of changes a run (default 100), BURSTS=N bursts of changes sent without
# waiting, after which only the last word is checked (default 200); KEEP=1 keeps the logs'
# directory, BRIDGE_VERBOSE=-vvv logs every event the bridge reads (default -v).
# Exits 1 when a run fails (a stale last word, visd differing from the geometry, a program failing).
set -u
build=${1:-build-release}
shift || true
runs=("$@")
[ ${#runs[@]} -gt 0 ] || runs=(auto always cm-auto)
repeat=${REPEAT:-100}
bursts=${BURSTS:-200}
for prog in "$build/bridge/x11/visd-x11" "$build/daemon/visd" "$build/client/visctl/visctl" \
	"$build/tests/x11-order"; do
	[ -x "$prog" ] || { echo "x11-order: $prog is not built" >&2; exit 1; }
done
command -v Xvfb >/dev/null 2>&1 || { echo "x11-order: Xvfb is not installed" >&2; exit 1; }
for run in "${runs[@]}"; do
	case $run in
	auto | always | never) ;;
	cm-auto | cm-always | cm-never)
		command -v xcompmgr >/dev/null 2>&1 ||
			{ echo "x11-order: xcompmgr is not installed (run $run)" >&2; exit 1; } ;;
	*) echo "x11-order: unknown run '$run' (auto, always, never, cm-auto, cm-always, cm-never)" >&2
	   exit 2 ;;
	esac
done
dir=$(mktemp -d "${TMPDIR:-/tmp}/x11-order.XXXXXX") || exit 1
pids=()
stop() {
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
	for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
	pids=()
}
cleanup() {
	stop
	if [ -n "${KEEP:-}" ]; then echo "x11-order: logs in $dir" >&2; else rm -rf "$dir"; fi
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/../tests/progress.sh"
# Shows a log and stops.
fail() {
	echo "x11-order: $1" >&2
	[ -n "${2:-}" ] && tail -n 20 "$2" >&2
	exit 1
}

status=0
echo "x11-order: $(date -u +%F), $(nproc) cores, $(sed -n 's/^model name[[:space:]]*: //p' \
	/proc/cpuinfo | head -n 1), REPEAT=$repeat"
for run in "${runs[@]}"; do
	mode=${run#cm-}
	exec 3>"$dir/display"
	Xvfb -displayfd 3 -screen 0 1280x720x24 -nolisten tcp -noreset >"$dir/xvfb-$run.log" 2>&1 &
	pids=($!)
	xpid=$!
	exec 3>&-
	wait_progress "$xpid" test -s "$dir/display" ||
		fail "Xvfb did not start ($progress_why):" "$dir/xvfb-$run.log"
	display=:$(head -n 1 "$dir/display")
	: >"$dir/display"
	sock=$dir/sock-$run
	"$build/daemon/visd" --socket "$sock" --screen 1280x720 2>"$dir/visd-$run.log" &
	vpid=$!
	pids+=("$vpid")
	wait_progress "$vpid" test -S "$sock" ||
		fail "visd did not start ($progress_why):" "$dir/visd-$run.log"
	cm= cmpid=
	if [ "$run" != "$mode" ]; then
		DISPLAY=$display xcompmgr >"$dir/xcompmgr-$run.log" 2>&1 &
		cmpid=$!
		pids+=("$cmpid")
		cm=--compositor
	fi
	"$build/bridge/x11/visd-x11" --display "$display" -s "$sock" "${BRIDGE_VERBOSE:--v}" \
		--send-events "$mode" 2>"$dir/bridge-$run.log" &
	bpid=$!
	pids+=("$bpid")
	wait_progress "$bpid $vpid $xpid" grep -q mirrored "$dir/bridge-$run.log" ||
		fail "visd-x11 did not start ($progress_why):" "$dir/bridge-$run.log"
	echo
	echo "== run $run: ${cm:+xcompmgr, }visd-x11 --send-events $mode"
	"$build/tests/x11-order" --display "$display" --repeat "$repeat" --bursts "$bursts" $cm \
		--working "$bpid" --working "$vpid" ${cmpid:+--working "$cmpid"} \
		--check "$build/client/visctl/visctl -s $sock states --x11" || status=1
	kill -0 "$bpid" 2>/dev/null || { echo "x11-order: visd-x11 died" >&2; status=1; }
	kill "$bpid"
	wait "$bpid" 2>/dev/null
	grep 'synthetic events sent$' "$dir/bridge-$run.log"
	stop
done
exit $status
