#!/usr/bin/env bash
# The service benchmark: visctl stress against one visd over windows 100 … 100,000 × subscribers
# 1, 10, 100, and 1,000,000 windows × 1 subscriber (more would send each subscriber a million
# first notices). Each cell runs twice: closed loop (one operation at a time: exact latencies) and
# pipelined (256 in flight: throughput). Prints a table; writes service.csv (a `run` column, then
# visctl stress --csv's fields) and service.svg (visctl plot-service) into the output directory.
#   tools/service-bench.sh [--quick] [--out DIR] [--build DIR]
#   --quick      windows 100, 1,000 × subscribers 1, 10, few operations: a smoke test
#   --out DIR    where the CSV and SVG go (default: the build directory)
#   --build DIR  the build whose visd and visctl run, as it is (default: build-release, installed
#                and built first by tools/dev.sh release)
# Exit status: 0 every run passed visctl stress's check, 1 otherwise, 2 usage.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
	sed -n '6,10s/^# \{0,1\}//p' "$0" >&2
	exit 2
}

quick=0
out=
bin=
while [ $# -gt 0 ]; do
	case $1 in
	--quick) quick=1 ;;
	--out) [ $# -gt 1 ] || usage; out=$2; shift ;;
	--build) [ $# -gt 1 ] || usage; bin=$2; shift ;;
	*) usage ;;
	esac
	shift
done
if [ -z "$bin" ]; then
	"$root/tools/dev.sh" release
	bin=$root/build-release
fi
out=${out:-$bin}
visd=$bin/daemon/visd
visctl=$bin/client/visctl/visctl
[ -x "$visd" ] && [ -x "$visctl" ] || { echo "service-bench: no visd or visctl in $bin" >&2; exit 2; }
mkdir -p "$out"

# The operations of both runs: visctl stress's default mix, spelt out so the report can say it.
mix=move=40,resize=15,raise=15,lower=10,restack=5,map=10,batch=5
pipeline=256
if [ $quick = 1 ]; then
	windows=(100 1000)
	subscribers=(1 10)
else
	windows=(100 1000 10000 100000 1000000)
	subscribers=(1 10 100)
fi

# Operations of a cell's closed-loop run: enough for a p99.9 (10,000), fewer where each costs
# more (100 syncs confirm each with 100 subscribers; 100,000 windows take ms a recompute).
latency_count() {
	if [ $quick = 1 ]; then echo 500
	elif [ "$1" -ge 1000000 ]; then echo 2000
	elif [ "$1" -ge 100000 ]; then echo 1000
	elif [ "$2" -ge 100 ]; then echo 5000
	else echo 10000
	fi
}

# Operations of a cell's pipelined run: a few seconds' worth.
throughput_count() {
	if [ $quick = 1 ]; then echo 5000
	elif [ "$1" -ge 100000 ]; then echo 20000
	else echo 100000
	fi
}

tmp=$(mktemp -d /tmp/visd-bench-XXXXXX)
chmod 700 "$tmp"
sock=$tmp/visd
visd_pid=
cleanup() {
	[ -n "$visd_pid" ] && kill "$visd_pid" 2>/dev/null && wait "$visd_pid" 2>/dev/null
	rm -rf "$tmp"
}
trap cleanup EXIT

"$visd" --socket "$sock" --screen 3840x2160 --max-windows 1000000 2>"$tmp/visd.log" &
visd_pid=$!
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/../tests/progress.sh"
wait_progress "$visd_pid" test -S "$sock" || {
	echo "service-bench: visd did not start ($progress_why)" >&2
	cat "$tmp/visd.log" >&2
	exit 1
}

csv=$out/service.csv
failed=0
rm -f "$csv"

# Runs visctl stress with the arguments after the run's name, appending its CSV row to service.csv
# under that name (and the header, the first time). A failed run is reported and counted.
run() {
	local name=$1
	shift
	if ! "$visctl" -s "$sock" stress "$@" --seed 1 --mix "$mix" --csv --quiet \
		>"$tmp/run.csv"; then
		echo "service-bench: FAILED: visctl stress $* (status above)" >&2
		failed=1
		return
	fi
	[ -f "$csv" ] || sed -n '1s/^/run,/p' "$tmp/run.csv" >"$csv"
	sed -n "2s/^/$name,/p" "$tmp/run.csv" >>"$csv"
}

for n in "${windows[@]}"; do
	for c in "${subscribers[@]}"; do
		[ "$n" -lt 1000000 ] || [ "$c" -eq 1 ] || continue
		echo "service-bench: $n windows, $c subscriber$([ "$c" -eq 1 ] || echo s)" >&2
		run latency -n "$n" -c "$c" --count "$(latency_count "$n" "$c")" --duration 60
		run throughput -n "$n" -c "$c" --count "$(throughput_count "$n")" --duration 60 \
			--pipeline $pipeline
		kill -0 "$visd_pid" 2>/dev/null || { echo "service-bench: visd died" >&2; exit 1; }
	done
done
[ -f "$csv" ] || { echo "service-bench: no run passed" >&2; exit 1; }

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
note="${cpu:-unknown CPU}, $(nproc) CPUs · $(date -u '+%Y-%m-%d %H:%M UTC') · $(basename "$bin") · seed 1"
echo "visctl stress on one visd: $note"
echo "mix $mix; latency: closed loop (one operation at a time); throughput: --pipeline $pipeline"
# The table: each cell's closed-loop latencies, pipelined rates, and visd's CPU (% of the run)
# and resident memory at the end of each run.
awk -F, '
NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
{
	k = $col["windows"] SUBSEP $col["clients"]
	if (!(k in seen)) { seen[k] = 1; order[++n] = k }
	for (f in col) v[$1, k, f] = $col[f]
}
END {
	printf "%7s %5s | %6s %7s %7s %7s %7s %8s | %6s %9s %9s | %5s %5s %7s\n", "windows",
		"subs", "ops", "p50", "p90", "p99", "p99.9", "max µs", "ops", "changes/s",
		"notices/s", "cpu%", "cpu%", "rss MiB"
	printf "%13s | %-47s | %-26s | %5s %5s\n", "", "closed loop", "pipelined", "lat", "pipe"
	for (i = 1; i <= n; i++) {
		k = order[i]
		split(k, wc, SUBSEP)
		printf "%7d %5d | %6s %7s %7s %7s %7s %8s | %6s %9s %9s | %5s %5s %7.1f\n", wc[1], wc[2],
			v["latency", k, "ops"], v["latency", k, "p50_us"], v["latency", k, "p90_us"],
			v["latency", k, "p99_us"], v["latency", k, "p999_us"],
			v["latency", k, "max_us"], v["throughput", k, "ops"],
			v["throughput", k, "changes_per_s"], v["throughput", k, "notices_per_s"],
			v["latency", k, "daemon_cpu_pct"], v["throughput", k, "daemon_cpu_pct"],
			v["throughput", k, "daemon_rss_kb"] / 1024
	}
	k = 1000 SUBSEP 100
	if (k in seen) {
		p99 = v["latency", k, "p99_us"]; cps = v["throughput", k, "changes_per_s"]
		printf "floor: p99 <= 500 us closed loop at 1,000 windows x 100 subscribers: %s us, %s\n",
			p99, (p99 != "" && p99 + 0 <= 500) ? "met" : "not met"
		printf "floor: >= 50,000 changes/s pipelined at 1,000 windows x 100 subscribers: %s, %s\n",
			cps, (cps != "" && cps + 0 >= 50000) ? "met" : "not met"
	}
}' "$csv"
"$visctl" plot-service --note "$note" "$csv" "$out/service.svg" || failed=1
echo "wrote $csv and $out/service.svg"
exit $failed
