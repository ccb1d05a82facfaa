#!/usr/bin/env bash
# visd against X.Org, side by side: the same operations on both, measured the same way. For each
# cell of scenes random, cascade, tiles × windows 100, 1,000, 10,000 (100,000 with --huge) ×
# subscribers 1, 10, 100:
#  (a) visd: visctl stress --scene K -n N -c S against a fresh visd --screen 3840x2160, one
#      operation at a time, recording its operations (--record); that run is visd's measurement:
#      latency from an operation to its last notice, p50 and p99, operations a second, visd's CPU
#      an operation;
#  (b) X.Org: a fresh Xvfb of the same screen (-displayfd, -nolisten tcp, no window manager,
#      no screen saver, no root background) and tests/xorg-replay, which replays the record: the
#      windows as override-redirect top-level windows, S connections selecting VisibilityNotify
#      on every window, each operation timed to the last VisibilityNotify it causes.
# Both replays must end in the same states: visctl stress checks visd's against its model, whose
# final states end the record, and xorg-replay checks X's against those.
# The operations (the mix move=40,resize=15,raise=15,lower=10,restack=5,map=10: no batches,
# borders, shapes or opaque regions, which X cannot replay one request each), a cell: 10,000, or
# 5,000 with 100 subscribers, 3,000 at 10,000 windows, 200 at 100,000. The default matrix takes
# about four minutes on a 2-core machine; --huge adds about 25 (X takes 0.1-0.2 s an operation at
# 100,000 windows, and minutes to map and unmap them).
#   tools/xorg-bench.sh [--quick] [--huge] [--scenes LIST] [--out DIR] [--build DIR]
#   --quick      windows 100, 1,000 × subscribers 1, 10 for each scene, 200 operations a cell:
#                a smoke run
#   --huge       adds 100,000 windows to the matrix
#   --scenes LIST  the desktops, comma-separated kinds of visctl stress --scene (default
#                random,cascade,tiles)
#   --out DIR    where xorg-bench.csv goes (default: the build directory)
#   --build DIR  the build whose visd, visctl and tests/xorg-replay run, as it is (default:
#                build-release, installed and built first by tools/dev.sh release)
# Exit status: 0 every cell's replays passed and ended in the same states, 1 otherwise (or Xvfb
# or tests/xorg-replay missing), 2 usage or a --build without visd and visctl.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
	sed -n '/^#   tools\/xorg-bench.sh \[/,/^#  *build-release/s/^# \{0,1\}//p' "$0" >&2
	exit 2
}

quick=0
huge=0
scenes=random,cascade,tiles
out=
bin=
while [ $# -gt 0 ]; do
	case $1 in
	--quick) quick=1 ;;
	--huge) huge=1 ;;
	--scenes) [ $# -gt 1 ] || usage; scenes=$2; shift ;;
	--out) [ $# -gt 1 ] || usage; out=$2; shift ;;
	--build) [ $# -gt 1 ] || usage; bin=$2; shift ;;
	*) usage ;;
	esac
	shift
done
# The scenes are checked before anything is built or started.
IFS=, read -r -a kinds <<<"$scenes"
[ ${#kinds[@]} -gt 0 ] || usage
for k in "${kinds[@]}"; do
	case $k in
	random | uniform | grid | cascade | tiles | nested) ;;
	*)
		echo "xorg-bench: --scenes: '$k' is not random, uniform, grid, cascade, tiles or" \
			"nested" >&2
		exit 2
		;;
	esac
done
if ! command -v Xvfb >/dev/null 2>&1; then
	echo "xorg-bench: Xvfb is not installed: install the xvfb Debian package" \
		"(apt-get install xvfb, or tools/dev.sh install xvfb)" >&2
	exit 1
fi
if [ -z "$bin" ]; then
	"$root/tools/dev.sh" release
	bin=$root/build-release
fi
[ -d "$bin" ] || { echo "xorg-bench: --build $bin: no such directory" >&2; exit 2; }
bin=$(cd "$bin" && pwd)
out=${out:-$bin}
visd=$bin/daemon/visd
visctl=$bin/client/visctl/visctl
replay=$bin/tests/xorg-replay
[ -x "$visd" ] && [ -x "$visctl" ] ||
	{ echo "xorg-bench: no visd or visctl built in $bin (a meson build directory?)" >&2; exit 2; }
[ -x "$replay" ] || { echo "xorg-bench: no tests/xorg-replay built in $bin: it is built where" \
	"xcb and xcb-shape are found (install libxcb1-dev and libxcb-shape0-dev, then build again)" >&2; exit 1; }
mkdir -p "$out"
out=$(cd "$out" && pwd)

screen=3840x2160
mix=move=40,resize=15,raise=15,lower=10,restack=5,map=10
if [ $quick = 1 ]; then
	windows=(100 1000)
	subscribers=(1 10)
else
	windows=(100 1000 10000)
	[ $huge = 1 ] && windows+=(100000)
	subscribers=(1 10 100)
fi

# Operations of a cell: enough for a p99, fewer where each costs more (a round trip on every
# subscriber confirms each; 10,000 and 100,000 windows take X milliseconds an operation).
count() {
	if [ $quick = 1 ]; then echo 200
	elif [ "$1" -ge 100000 ]; then echo 200
	elif [ "$1" -ge 10000 ]; then echo 3000
	elif [ "$2" -ge 100 ]; then echo 5000
	else echo 10000
	fi
}

tmp=$(mktemp -d /tmp/visd-xorg-bench-XXXXXX)
chmod 700 "$tmp"
visd_pid=
x_pid=
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/../tests/progress.sh"
# Stops the server a cell started, if it runs: SIGTERM, then SIGKILL once it stops working
# without exiting (an X server still busy with a client's windows reads its signal only when it
# is done).
stop() {
	local pid=$1
	[ -n "$pid" ] || return 0
	kill "$pid" 2>/dev/null || true
	wait_progress "$pid" progress_gone "$pid" || true
	kill -9 "$pid" 2>/dev/null || true
	wait "$pid" 2>/dev/null || true
}
cleanup() {
	stop "$visd_pid"
	stop "$x_pid"
	rm -rf "$tmp"
}
trap cleanup EXIT

# Starts a fresh visd on the screen; 0, or 1 after showing its log.
start_visd() {
	rm -f "$tmp/visd"
	"$visd" --socket "$tmp/visd" --screen "$screen" 2>"$tmp/visd.log" &
	visd_pid=$!
	wait_progress "$visd_pid" test -S "$tmp/visd" && return 0
	echo "xorg-bench: visd did not start ($progress_why):" >&2
	cat "$tmp/visd.log" >&2
	return 1
}

# Starts a fresh Xvfb on the screen; sets display. 0, or 1 after showing its log.
start_x() {
	: >"$tmp/display"
	exec 3>"$tmp/display"
	Xvfb -displayfd 3 -screen 0 "${screen}x24" -nolisten tcp -noreset -s 0 -background none \
		>"$tmp/x.log" 2>&1 &
	x_pid=$!
	exec 3>&-
	if wait_progress "$x_pid" test -s "$tmp/display"; then
		display=$(head -n 1 "$tmp/display")
		return 0
	fi
	echo "xorg-bench: Xvfb did not start ($progress_why):" >&2
	cat "$tmp/x.log" >&2
	return 1
}

# Reads field $2 of a one-row CSV file $1 (header, row) by its name.
field() {
	awk -F, -v f="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == f) c = i; next }
		NR == 2 && c { print $c }' "$1"
}

csv=$out/xorg-bench.csv
echo "scene,windows,subscribers,ops,visd_p50_us,x_p50_us,visd_p99_us,x_p99_us,visd_ops_per_s,x_ops_per_s,visd_cpu_us_per_op,x_cpu_us_per_op,visd_notices,x_notices,x_ops_without_notices,visd_ok,x_ok,same_states" \
	>"$csv"
failed=0
for k in "${kinds[@]}"; do
	for n in "${windows[@]}"; do
		for c in "${subscribers[@]}"; do
			ops=$(count "$n" "$c")
			echo "xorg-bench: $k, $n windows, $c subscriber$([ "$c" -eq 1 ] || echo s)," \
				"$ops operations" >&2
			rm -f "$tmp/record" "$tmp/visd.csv" "$tmp/x.csv"
			visd_ok=0
			x_ok=0
			if start_visd; then
				if "$visctl" -s "$tmp/visd" stress --scene "$k" -n "$n" -c "$c" \
					--count "$ops" --seed 1 --mix "$mix" --duration 300 \
					--record "$tmp/record" --csv --quiet >"$tmp/visd.csv"; then
					visd_ok=1
				else
					echo "xorg-bench: FAILED: visctl stress --scene $k -n $n -c $c" \
						"(status above)" >&2
				fi
			fi
			stop "$visd_pid"
			visd_pid=
			if [ -s "$tmp/record" ] && start_x; then
				if "$replay" -c "$c" --display ":$display" --pid "$x_pid" --csv --quiet \
					"$tmp/record" >"$tmp/x.csv"; then
					x_ok=1
				else
					echo "xorg-bench: FAILED: xorg-replay of $k, $n windows, $c subscribers" \
						"(status above)" >&2
				fi
			fi
			stop "$x_pid"
			x_pid=
			[ $visd_ok = 1 ] && [ $x_ok = 1 ] || failed=1
			v() { [ -s "$tmp/visd.csv" ] && field "$tmp/visd.csv" "$1" || true; }
			x() { [ -s "$tmp/x.csv" ] && field "$tmp/x.csv" "$1" || true; }
			# visd's CPU an operation from its share of the run (daemon_cpu_pct): daemon_cpu_s
			# has two decimals, too coarse for runs of a fraction of a second.
			vops=$(v ops)
			ops=${vops:-$ops} # as run: --duration may have cut it short
			vpct=$(v daemon_cpu_pct)
			vsec=$(v seconds)
			vcpu_op=
			[ -n "$vops" ] && [ -n "$vpct" ] && [ -n "$vsec" ] && vcpu_op=$(awk -v p="$vpct" \
				-v t="$vsec" -v n="$vops" 'BEGIN { printf "%.1f", n ? p / 100 * t * 1e6 / n : 0 }')
			# visd's notices of the operations: less the first state of every window that each
			# subscriber gets when it subscribes (X's count has no such events).
			vnotices=$(v notices)
			[ -n "$vnotices" ] && vnotices=$((vnotices - n * c))
			echo "$k,$n,$c,$ops,$(v p50_us),$(x p50_us),$(v p99_us),$(x p99_us),$(v ops_per_s),$(x ops_per_s),$vcpu_op,$(x server_cpu_us_per_op),$vnotices,$(x notices),$(x ops_without_notices),$visd_ok,$x_ok,$((visd_ok && x_ok))" \
				>>"$csv"
		done
	done
done

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
echo "visd against X.Org (Xvfb $(dpkg-query -W -f '${Version}' xvfb 2>/dev/null || echo '?')):" \
	"${cpu:-unknown CPU}, $(nproc) CPUs, $(date -u '+%Y-%m-%d %H:%M UTC'), $(basename "$bin")"
echo "screen $screen, seed 1, mix $mix; one operation at a time"
echo "latency: from an operation to its last notice (VisibilityNotify); cpu: the server's time an"
echo "operation; X/visd above 1 means visd is ahead for latency and cpu, behind for operations a second"
awk -F, '
function ratio(x, v) { return (x != "" && v != "" && v + 0 > 0) ? sprintf("%.2f", x / v) : "-" }
function cell(v, x) { return sprintf(" %8s %8s %6s", v == "" ? "-" : v, x == "" ? "-" : x, ratio(x, v)) }
NR == 1 {
	# Spelt out: awk may count the bytes of "µ" as two columns.
	printf "%-7s %7s %5s %5s | %-24s | %-24s | %-24s | %-24s | %s\n", "scene", "windows",
		"subs", "ops", "p50 latency, us", "p99 latency, us", "operations a second",
		"server cpu, us an op", "states"
	h = sprintf(" %8s %8s %6s", "visd", "X", "X/visd")
	printf "%27s |%s |%s |%s |%s |\n", "", h, h, h, h
	next
}
{
	printf "%-7s %7d %5d %5d |%s |%s |%s |%s | %s\n", $1, $2, $3, $4, cell($5, $6),
		cell($7, $8), cell($9, $10), cell($11, $12), $18 ? "same" : "FAILED"
	if ($13 != $14)
		notes = notes sprintf("note: %s, %d windows, %d subscribers: visd sent %s notices, X %s\n",
			$1, $2, $3, $13, $14)
}
END { printf "%s", notes }' "$csv"
echo "wrote $csv"
exit $failed
