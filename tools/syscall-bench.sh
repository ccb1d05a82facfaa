#!/usr/bin/env bash
# visd's system calls and CPU under the notice fan-out: `visctl stress -c 100 -n 100 --count 2000`
# (100 subscribers of every window, each syncing after every operation) against a fresh visd of
# each build given, builds alternating run after run so that they share the machine's state.
# Each run is twice: once plain (visd's CPU per operation, the latencies), once under
# `strace -c -f -p VISD` (its system calls by kind; strace slows visd, so not for timing).
#   tools/syscall-bench.sh [--runs R] [--count N] [-c CLIENTS] [-n WINDOWS] [--perf]
#                          [--profile] [--out DIR] [BUILD...]
#   BUILD        a build directory with daemon/visd and client/visctl/visctl (default:
#                build-release); the first is the reference of the CPU ratio
#   --runs R     runs of each build (default 3); medians are reported
#   --count N    operations a run (default 2000); -c, -n: subscribers and windows (100, 100)
#   --perf       count with `perf stat` on the syscall tracepoints too, which does not slow visd
#   --profile    one more run of each under `perf record`: the top symbols, kernel and user
#   --out DIR    keep each run's CSV, strace and perf output there (default: a temporary directory)
# Exit status: 0 every run passed visctl stress's check, 1 otherwise, 2 usage.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() {
	sed -n '6,15s/^# \{0,1\}//p' "$0" >&2
	exit 2
}

runs=3 count=2000 clients=100 windows=100 perf=0 profile=0 out= builds=()
while [ $# -gt 0 ]; do
	case $1 in
	--runs) [ $# -gt 1 ] || usage; runs=$2; shift ;;
	--count) [ $# -gt 1 ] || usage; count=$2; shift ;;
	-c) [ $# -gt 1 ] || usage; clients=$2; shift ;;
	-n) [ $# -gt 1 ] || usage; windows=$2; shift ;;
	--perf) perf=1 ;;
	--profile) profile=1 ;;
	--out) [ $# -gt 1 ] || usage; out=$2; shift ;;
	-*) usage ;;
	*) builds+=("$1") ;;
	esac
	shift
done
[ ${#builds[@]} -gt 0 ] || builds=("$root/build-release")
command -v strace >/dev/null || { echo "syscall-bench: strace is not installed" >&2; exit 2; }
if [ $perf = 1 ] || [ $profile = 1 ]; then
	command -v perf >/dev/null || { echo "syscall-bench: perf is not installed" >&2; exit 2; }
fi
for b in "${builds[@]}"; do
	[ -x "$b/daemon/visd" ] && [ -x "$b/client/visctl/visctl" ] ||
		{ echo "syscall-bench: no visd or visctl in $b" >&2; exit 2; }
done

tmp=$(mktemp -d /tmp/visd-syscalls-XXXXXX)
chmod 700 "$tmp"
out=${out:-$tmp}
mkdir -p "$out"
visd_pid= tracer_pid=
cleanup() {
	[ -n "$tracer_pid" ] && kill -INT "$tracer_pid" 2>/dev/null
	[ -n "$visd_pid" ] && kill "$visd_pid" 2>/dev/null && wait "$visd_pid" 2>/dev/null
	rm -rf "$tmp"
}
trap cleanup EXIT

# Starts a fresh visd of build $1 on a private socket.
start_visd() {
	rm -f "$tmp/sock"
	"$1/daemon/visd" --socket "$tmp/sock" 2>"$tmp/visd.log" &
	visd_pid=$!
	for _ in $(seq 100); do [ -S "$tmp/sock" ] && break; sleep 0.05; done
	[ -S "$tmp/sock" ] || { echo "syscall-bench: visd did not start" >&2; cat "$tmp/visd.log" >&2; exit 1; }
}

stop_visd() {
	kill "$visd_pid"
	wait "$visd_pid" 2>/dev/null || true
	visd_pid=
}

# Runs the stress of build $1 into the CSV file $2; a failed check fails the benchmark.
stress() {
	if ! "$1/client/visctl/visctl" -s "$tmp/sock" stress -c "$clients" -n "$windows" \
		--count "$count" --seed 1 --csv --quiet >"$2"; then
		echo "syscall-bench: FAILED: visctl stress on $1 (status above)" >&2
		failed=1
	fi
}

# Waits until strace is attached to visd, or a second.
await_strace() {
	for _ in $(seq 100); do
		[ "$(awk '/^TracerPid:/ { print $2 }' "/proc/$visd_pid/status")" != 0 ] && return
		sleep 0.01
	done
}

failed=0
for r in $(seq "$runs"); do
	for i in "${!builds[@]}"; do
		b=${builds[$i]}
		echo "syscall-bench: run $r of $runs, $b" >&2
		start_visd "$b"
		stress "$b" "$out/plain-$i-$r.csv"
		stop_visd

		start_visd "$b"
		strace -c -f -p "$visd_pid" -o "$out/strace-$i-$r.txt" 2>/dev/null &
		tracer_pid=$!
		await_strace
		stress "$b" "$out/traced-$i-$r.csv"
		kill -INT "$tracer_pid"
		wait "$tracer_pid" || true
		tracer_pid=
		stop_visd

		if [ $perf = 1 ]; then
			start_visd "$b"
			events=raw_syscalls:sys_enter
			for s in read readv write writev epoll_wait epoll_ctl ioctl; do
				events+=",syscalls:sys_enter_$s"
			done
			perf stat -x, -e "$events" -p "$visd_pid" -o "$out/perf-$i-$r.txt" 2>/dev/null &
			tracer_pid=$!
			sleep 0.3
			stress "$b" "$out/perfed-$i-$r.csv"
			kill -INT "$tracer_pid"
			wait "$tracer_pid" || true
			tracer_pid=
			stop_visd
		fi
	done
done

cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
echo "visctl stress -c $clients -n $windows --count $count --seed 1, $runs runs of each build, alternating"
echo "${cpu:-unknown CPU}, $(nproc) CPUs, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end; $(date -u '+%Y-%m-%d %H:%M UTC')"

# The table: one line a build, medians over its runs. Syscalls as strace -c counts them over the
# whole run (set-up included); "writes" are write, writev, sendmsg and sendto together.
for i in "${!builds[@]}"; do
	for r in $(seq "$runs"); do
		# strace -c: "% time  seconds  usecs/call  calls  [errors]  syscall", calls the 4th field.
		awk -v b="$i" -v r="$r" '$NF ~ /^[a-z_0-9]+$/ && $4 ~ /^[0-9]+$/ && $NF != "total" {
			print b, r, "strace", $NF, $4 }' "$out/strace-$i-$r.txt"
		[ $perf = 1 ] && awk -F, -v b="$i" -v r="$r" '$3 ~ /sys_enter/ {
			n = $3; sub(/.*sys_enter_?/, "", n); if (n == "") n = "all"; print b, r, "perf", n, $1 }' \
			"$out/perf-$i-$r.txt"
		awk -F, -v b="$i" -v r="$r" 'NR == 1 { for (k = 1; k <= NF; k++) col[$k] = k; next }
			{ print b, r, "plain", "ops", $col["ops"]; print b, r, "plain", "cpu", $col["daemon_cpu_s"]
			  print b, r, "plain", "p50", $col["p50_us"]; print b, r, "plain", "p99", $col["p99_us"] }' \
			"$out/plain-$i-$r.csv"
	done
done >"$tmp/values"

names=$(printf '%s\n' "${builds[@]}")
awk -v runs="$runs" -v perf="$perf" -v names="$names" '
function median(key,    n, a, k, t, i, j) {
	n = 0
	for (k = 1; k <= runs; k++) if ((key, k) in v) a[++n] = v[key, k]
	for (i = 2; i <= n; i++) for (j = i; j > 1 && a[j - 1] > a[j]; j--) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
	return n ? (n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2) : 0
}
{ v[$1 SUBSEP $3 SUBSEP $4, $2] = $5; if ($3 == "strace") kinds[$4] = 1; builds[$1] = 1 }
END {
	nb = split(names, name, "\n")
	split("read readv ioctl write writev epoll_ctl epoll_wait", shown, " ")
	for (s in shown) is_shown[shown[s]] = 1
	printf "%-4s %8s %8s %8s %8s %8s %9s %10s %6s %9s %9s | %9s %8s %7s %7s\n", "", "read", "readv",
		"ioctl", "write", "writev", "epoll_ctl", "epoll_wait", "other", "total", "per write",
		"cpu s", "ms/op", "p50 µs", "p99 µs"
	for (b = 0; b < nb; b++) {
		total = 0; writes = 0; other = 0
		for (k in kinds) {
			m = median(b SUBSEP "strace" SUBSEP k); total += m
			if (k ~ /^(write|writev|sendmsg|sendto)$/) writes += m
			if (!(k in is_shown)) other += m
		}
		cpu = median(b SUBSEP "plain" SUBSEP "cpu"); ops = median(b SUBSEP "plain" SUBSEP "ops")
		if (b == 0) ref = cpu / ops
		printf "%-4s", "[" b + 1 "]"
		for (s = 1; s <= 7; s++) printf (s < 6 ? " %8.0f" : s == 6 ? " %9.0f" : " %10.0f"), median(b SUBSEP "strace" SUBSEP shown[s])
		printf " %6.0f %9.0f %9.2f | %9.2f %8.3f %7.1f %7.1f\n", other, total,
			writes ? total / writes : 0, cpu, 1000 * cpu / ops, median(b SUBSEP "plain" SUBSEP "p50"),
			median(b SUBSEP "plain" SUBSEP "p99")
	}
	if (perf) {
		printf "\nthe same, counted by perf stat on the syscall tracepoints (visd not slowed):\n"
		printf "%-4s %8s %8s %8s %8s %8s %9s %10s %9s %9s\n", "", "read", "readv", "ioctl", "write",
			"writev", "epoll_ctl", "epoll_wait", "total", "per write"
		for (b = 0; b < nb; b++) {
			printf "%-4s", "[" b + 1 "]"
			for (s = 1; s <= 7; s++) printf (s < 6 ? " %8.0f" : s == 6 ? " %9.0f" : " %10.0f"), median(b SUBSEP "perf" SUBSEP shown[s])
			w = median(b SUBSEP "perf" SUBSEP "write") + median(b SUBSEP "perf" SUBSEP "writev")
			t = median(b SUBSEP "perf" SUBSEP "all")
			printf " %9.0f %9.2f\n", t, w ? t / w : 0
		}
	}
	printf "\n"
	for (b = 0; b < nb; b++) {
		cpu = median(b SUBSEP "plain" SUBSEP "cpu"); ops = median(b SUBSEP "plain" SUBSEP "ops")
		printf "[%d] %s: CPU per operation %.2fx the first build'"'"'s\n", b + 1, name[b + 1], cpu / ops / ref
	}
}' "$tmp/values"

if [ $profile = 1 ]; then
	for i in "${!builds[@]}"; do
		b=${builds[$i]}
		start_visd "$b"
		perf record -q -o "$out/perf-$i.data" -p "$visd_pid" 2>/dev/null &
		tracer_pid=$!
		sleep 0.3
		stress "$b" "$out/profiled-$i.csv"
		kill -INT "$tracer_pid"
		wait "$tracer_pid" || true
		tracer_pid=
		stop_visd
		# perf's cpu-clock event counts nanoseconds on the CPU.
		ns=$(perf report -i "$out/perf-$i.data" --stdio 2>/dev/null |
			awk '/^# Event count/ { n = $NF } END { printf "%.0f\n", n }')
		ops=$(awk -F, 'NR == 1 { for (k = 1; k <= NF; k++) col[$k] = k; next }
			{ print $col["ops"] }' "$out/profiled-$i.csv")
		echo
		echo "[$((i + 1))] $b: where visd's time goes (perf record): $((ns / 1000000)) ms on the" \
			"CPU for $ops operations; by object (µs an operation), then the top symbols"
		# awk reads to the end: an early exit would fail the pipeline (pipefail).
		perf report -i "$out/perf-$i.data" --no-children --sort dso --stdio 2>/dev/null |
			awk -v ns="$ns" -v ops="${ops:-1}" '!/^#/ && NF && n++ < 5 {
				p = $1; sub(/%/, "", p); printf "%s  %7.1f\n", $0, p / 100 * ns / 1000 / ops }'
		perf report -i "$out/perf-$i.data" --no-children --sort dso,sym --stdio 2>/dev/null |
			awk '!/^#/ && NF && n++ < 20'
	done
fi
exit $failed
