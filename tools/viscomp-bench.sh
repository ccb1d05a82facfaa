#!/bin/bash
# viscomp against sway: what frame callbacks only where pixels can be seen save. On a headless
# 1280x720 output (pixman), N unmodified clients of one size (CLIENT, below) are
# stacked exactly on top of each other, so that N - 1 are wholly covered; then, for RUN_SECONDS, the
# CPU time of the compositor and of the clients is measured (/proc/PID/schedstat), and, under
# viscomp, the commits of the covered clients (viscompctl). sway 1.7 (the same wlroots 0.15)
# places them floating at the same spot; it answers the frame callbacks of covered surfaces too.
# sway refuses to run as root, so both compositors and their clients run as nobody
# (setpriv), in a private runtime directory.
# The client: CLIENT (default weston-presentation-shm, which draws on frame callbacks and lives
# under both; weston-simple-shm aborts under sway 1.7 headless, "Both buffers busy": sway keeps
# its first buffer locked for a transaction that waits for the client to take the size sway
# configured, which simple-shm never does, and answers the frame callback meanwhile).
# Usage: tools/viscomp-bench.sh [BUILD-DIR] [N...] (default build-release, 1 2 5 10; RUN_SECONDS=10
# a run).
# Installs sway when missing (tools/dev.sh install). Prints a table.
set -u
cd "$(dirname "$0")/.." || exit 1
build=${1:-build-release}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1 2 5 10)
seconds=${RUN_SECONDS:-10}
client=${CLIENT:-weston-presentation-shm}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
for prog in "$viscomp" "$viscompctl"; do
	[ -x "$prog" ] || { echo "viscomp-bench: $prog is not built" >&2; exit 1; }
done
tools/dev.sh install sway weston >&2 || exit 1

dir=$(mktemp -d "${TMPDIR:-/tmp}/viscomp-bench.XXXXXX") || exit 1
chmod 755 "$dir"
pids=()
cleanup() {
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
	wait 2>/dev/null
	rm -rf "$dir"
}
trap cleanup EXIT
as_nobody=(setpriv --reuid=nobody --regid=nogroup --clear-groups --)
wait_for() {
	for _ in $(seq 1200); do "$@" && return 0; sleep 0.05; done
	return 1
}
# Whether a Wayland socket is in directory $1 (sway takes wayland-1 when it can, viscomp
# wayland-0).
socket_in() {
	local f
	for f in "$1"/wayland-?; do [ -S "$f" ] && return 0; done
	return 1
}
# CPU time of processes, in microseconds, summed; those gone count 0 (the row says how many).
cpu_us() {
	local sum=0 p
	for p in "$@"; do
		[ -r /proc/"$p"/schedstat ] || continue
		sum=$((sum + $(awk '{ printf "%d", $1 / 1000 }' /proc/"$p"/schedstat)))
	done
	echo "$sum"
}
# How many of the processes are gone.
gone() {
	local n=0 p
	for p in "$@"; do kill -0 "$p" 2>/dev/null || n=$((n + 1)); done
	echo "$n"
}

# run KIND N: starts the compositor KIND with N clients stacked, measures, prints a row.
run() {
	local kind=$1 n=$2 run=$dir/$1-$2 cpid clients=() i
	mkdir -m 700 "$run" && chown nobody:nogroup "$run"
	export XDG_RUNTIME_DIR=$run
	if [ "$kind" = viscomp ]; then
		"${as_nobody[@]}" "$viscomp" --headless 1280x720 -v >"$run/log" 2>&1 &
	else
		cat >"$run/sway.conf" <<-EOF
			output HEADLESS-1 resolution 1280x720 position 0 0
			for_window [app_id=".*"] floating enable, move position 100 100
		EOF
		WLR_BACKENDS=headless WLR_RENDERER=pixman WLR_LIBINPUT_NO_DEVICES=1 \
			"${as_nobody[@]}" sway -c "$run/sway.conf" >"$run/log" 2>&1 &
	fi
	cpid=$!
	pids+=("$cpid")
	wait_for socket_in "$run" ||
		{ echo "viscomp-bench: $kind did not start" >&2; cat "$run/log" >&2; exit 1; }
	local display f
	for f in "$run"/wayland-?; do [ -S "$f" ] && display=$(basename "$f") && break; done
	for ((i = 0; i < n; i++)); do
		WAYLAND_DISPLAY=$display "${as_nobody[@]}" "$client" >/dev/null 2>&1 &
		clients+=($!)
		pids+=($!)
		if [ "$kind" = viscomp ]; then
			# Each new one on top of the others, at the same spot.
			wait_for sh -c "VISCOMP_SOCKET=$run/viscomp-$display.sock $viscompctl list |
				grep -q ' pid=$! '" || { echo "viscomp-bench: no window" >&2; exit 1; }
			VISCOMP_SOCKET=$run/viscomp-$display.sock "$viscompctl" move $((i + 1)) 100 100
		fi
	done
	sleep 2 # settled: every client drew, the covered ones stopped (or not)
	local c0 k0 covered0=0 covered1=0
	c0=$(cpu_us "$cpid")
	k0=$(cpu_us "${clients[@]}")
	local cov0
	cov0=$( [ "$n" -gt 1 ] && cpu_us "${clients[@]:0:n-1}" || echo 0)
	if [ "$kind" = viscomp ]; then
		covered0=$(VISCOMP_SOCKET=$run/viscomp-$display.sock "$viscompctl" list --json |
			tail -n +2 | sed -n 's/.*"commits_total":\([0-9]*\).*/\1/p' | awk '{ s += $1 } END { print s + 0 }')
	fi
	sleep "$seconds"
	local c1 k1 cov1
	c1=$(cpu_us "$cpid")
	k1=$(cpu_us "${clients[@]}")
	cov1=$( [ "$n" -gt 1 ] && cpu_us "${clients[@]:0:n-1}" || echo 0)
	local covered_commits=-
	if [ "$kind" = viscomp ]; then
		covered1=$(VISCOMP_SOCKET=$run/viscomp-$display.sock "$viscompctl" list --json |
			tail -n +2 | sed -n 's/.*"commits_total":\([0-9]*\).*/\1/p' | awk '{ s += $1 } END { print s + 0 }')
		covered_commits=$(awk -v a="$covered0" -v b="$covered1" -v s="$seconds" \
			'BEGIN { printf "%.1f", (b - a) / s }')
	fi
	awk -v kind="$kind" -v n="$n" -v s="$seconds" -v c=$((c1 - c0)) -v k=$((k1 - k0)) \
		-v cov=$((cov1 - cov0)) -v cc="$covered_commits" -v dead="$(gone "${clients[@]}")" \
		'BEGIN {
		printf "%-8s %3d %8d %14.1f %14.1f %16.1f %16s%s\n", kind, n, n - 1, c / s / 1000,
			k / s / 1000, cov / s / 1000, cc,
			(dead > 0 ? "  (" dead " clients died)" : "") }'
	kill -0 "$cpid" 2>/dev/null || { echo "viscomp-bench: $kind died" >&2; tail "$run/log" >&2; }
	for p in "${clients[@]}"; do kill "$p" 2>/dev/null; done
	kill "$cpid" 2>/dev/null
	wait 2>/dev/null
	pids=()
}

printf '%-8s %3s %8s %14s %14s %16s %16s\n' compositor N covered 'comp ms/s' 'clients ms/s' \
	'covered ms/s' 'covered commit/s'
for n in "${sizes[@]}"; do
	run viscomp "$n"
	run sway "$n"
done
echo "($client, $seconds s each; CPU time from /proc/PID/schedstat; $(nproc) CPUs:" \
	"$(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo); $(date -u +%F))"
