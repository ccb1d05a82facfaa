#!/bin/bash
# viscomp against sway: what frame callbacks only where pixels can be seen save, and what viscomp
# costs when nothing is covered. On a headless output (OUTPUT, default 1280x1024, pixman), N
# unmodified clients of one size (CLIENT, below) are arranged two ways:
#   stacked  exactly on top of each other, so that N - 1 are wholly covered;
#   tiled    side by side in rows from the top-left corner, none covering another (CLIENT's
#            250x250 windows: 20 fit on 1280x1024, which is why that is the default output).
# Then, for RUN_SECONDS, the CPU time of the compositor and of the clients is measured
# (/proc/PID/schedstat), and, under viscomp, the commits of the covered clients (viscompctl).
# sway 1.7 (the same wlroots 0.15) floats them at the same spots, without borders or title bars
# (viscomp draws none); it answers the frame callbacks of covered surfaces too.
# sway refuses to run as root, so both compositors and their clients run as nobody
# (setpriv), in a private runtime directory. For each N, each arrangement, the two compositors
# run one after the other, and REPEAT times over (the order swapped every other time), so that
# the machine's load falls on both alike; with REPEAT > 1 a summary gives each cell's range.
# The client: CLIENT (default weston-presentation-shm, which draws on frame callbacks and lives
# under both; weston-simple-shm aborts under sway 1.7 headless, "Both buffers busy": sway keeps
# its first buffer locked for a transaction that waits for the client to take the size sway
# configured, which simple-shm never does, and answers the frame callback meanwhile).
# Usage: tools/viscomp-bench.sh [BUILD-DIR] [N...] (default build-release, 1 4 16;
# RUN_SECONDS=10 a run; ARRANGE="stacked tiled"; REPEAT=1; OUTPUT=1280x1024).
#        tools/viscomp-bench.sh --latency [BUILD-DIR] [CYCLES] (default 200): two clients at
# one spot raised in turn, each raise covering one and uncovering the other, CYCLES times; prints
# viscompctl stats: how long from the command's arrival to the first frame callback withheld
# (covered) or sent (uncovered), and what each output frame's libvis work cost.
#        tools/viscomp-bench.sh --frame [BUILD-DIR] [N...] (default 10 100): N clients where
# viscomp places them (its cascade), the top one then moved 8 pixels a step, 20 ms apart, for
# MOVES steps (default 300); prints viscompctl stats' frame line over the moves: libvis's time in each
# output frame (its update and the repaint sets of the damage), in process.
# Installs sway when missing (tools/dev.sh install). Prints a table.
set -u
cd "$(dirname "$0")/.." || exit 1
mode=saving
case ${1:-} in
--latency | --frame)
	mode=${1#--}
	shift
	;;
esac
build=${1:-build-release}
shift || true
sizes=("$@")
if [ "$mode" = latency ]; then
	cycles=${1:-200}
	sizes=()
elif [ ${#sizes[@]} -eq 0 ]; then
	[ "$mode" = frame ] && sizes=(10 100) || sizes=(1 4 16)
fi
seconds=${RUN_SECONDS:-10}
client=${CLIENT:-weston-presentation-shm}
read -r -a arrangements <<<"${ARRANGE:-stacked tiled}"
repeat=${REPEAT:-1}
output=${OUTPUT:-1280x1024}
out_w=${output%x*} out_h=${output#*x}
tile=250 # CLIENT's windows' size: the tiled arrangement's pitch
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
for prog in "$viscomp" "$viscompctl"; do
	[ -x "$prog" ] || { echo "viscomp-bench: $prog is not built" >&2; exit 1; }
done
for a in "${arrangements[@]}"; do
	case $a in stacked | tiled) ;; *) echo "viscomp-bench: ARRANGE: stacked or tiled, not $a" >&2; exit 1 ;; esac
done
[ "$mode" = saving ] && for n in "${sizes[@]}"; do
	[ $((((n + out_w / tile - 1) / (out_w / tile)) * tile)) -le "$out_h" ] ||
		{ echo "viscomp-bench: $n windows of ${tile}x$tile do not fit side by side on $output" >&2; exit 1; }
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
# The spot of client i (0-based) in arrangement $1: "X Y".
spot() {
	local cols=$((out_w / tile))
	if [ "$1" = stacked ]; then
		echo 100 100
	else
		echo $(($2 % cols * tile)) $((($2 / cols) * tile))
	fi
}
# The sum of the commits_total of viscomp's windows but the top one (the covered ones, stacked).
covered_commits() {
	"$viscompctl" list --json | tail -n +2 |
		sed -n 's/.*"commits_total":\([0-9]*\).*/\1/p' | awk '{ s += $1 } END { print s + 0 }'
}

# start KIND ARRANGE RUN: starts the compositor KIND in the directory RUN; sets cpid and display.
start() {
	local kind=$1 run=$3 f
	mkdir -m 700 "$run" && chown nobody:nogroup "$run"
	export XDG_RUNTIME_DIR=$run
	if [ "$kind" = viscomp ]; then
		"${as_nobody[@]}" "$viscomp" --headless "$output" -v >"$run/log" 2>&1 &
	else
		cat >"$run/sway.conf" <<-EOF
			output HEADLESS-1 resolution $output position 0 0
			default_border none
			default_floating_border none
			for_window [app_id=".*"] floating enable, move position 100 100
		EOF
		WLR_BACKENDS=headless WLR_RENDERER=pixman WLR_LIBINPUT_NO_DEVICES=1 \
			"${as_nobody[@]}" sway -c "$run/sway.conf" >"$run/log" 2>&1 &
	fi
	cpid=$!
	pids+=("$cpid")
	wait_for socket_in "$run" ||
		{ echo "viscomp-bench: $kind did not start" >&2; cat "$run/log" >&2; exit 1; }
	for f in "$run"/wayland-?; do [ -S "$f" ] && display=$(basename "$f") && break; done
	export VISCOMP_SOCKET=$run/viscomp-$display.sock
}

# place KIND PID X Y: waits for the client's window and puts it at X, Y (on top, under viscomp:
# a new window is).
place() {
	local kind=$1 pid=$2 x=$3 y=$4 id
	if [ "$kind" = viscomp ]; then
		wait_for sh -c "$viscompctl list | grep -q ' pid=$pid '" ||
			{ echo "viscomp-bench: no window" >&2; exit 1; }
		id=$("$viscompctl" list | awk -v p="pid=$pid" '$7 == p { print $1 }')
		"$viscompctl" move "$id" "$x" "$y" >/dev/null
	else
		wait_for sh -c "SWAYSOCK=\$(ls $XDG_RUNTIME_DIR/sway-ipc.*.sock) ${as_nobody[*]} \
			swaymsg '[pid=$pid] move position $x $y' >/dev/null 2>&1" ||
			{ echo "viscomp-bench: no window" >&2; exit 1; }
	fi
}

# run KIND ARRANGE N R: starts the compositor KIND with N clients arranged, measures, prints a row
# (R: the repetition).
run() {
	local kind=$1 arrange=$2 n=$3 run=$dir/$1-$2-$3-$4 cpid display clients=() i
	start "$kind" "$arrange" "$run"
	for ((i = 0; i < n; i++)); do
		WAYLAND_DISPLAY=$display "${as_nobody[@]}" "$client" >/dev/null 2>&1 &
		clients+=($!)
		pids+=($!)
		# shellcheck disable=SC2046 # X Y
		place "$kind" $! $(spot "$arrange" "$i")
	done
	sleep 2 # settled: every client drew, the covered ones stopped (or not)
	local covered=0
	[ "$arrange" = stacked ] && covered=$((n - 1))
	local c0 k0 cov0=0 covered0=0
	c0=$(cpu_us "$cpid")
	k0=$(cpu_us "${clients[@]}")
	[ "$covered" -gt 0 ] && cov0=$(cpu_us "${clients[@]:0:covered}")
	[ "$kind" = viscomp ] && [ "$covered" -gt 0 ] && covered0=$(covered_commits)
	sleep "$seconds"
	local c1 k1 cov1=0 covered1=0 cov_ms=- covered_rate=-
	c1=$(cpu_us "$cpid")
	k1=$(cpu_us "${clients[@]}")
	if [ "$covered" -gt 0 ]; then
		cov1=$(cpu_us "${clients[@]:0:covered}")
		cov_ms=$(awk -v a="$cov0" -v b="$cov1" -v s="$seconds" 'BEGIN { printf "%.1f", (b - a) / s / 1000 }')
		if [ "$kind" = viscomp ]; then
			covered1=$(covered_commits)
			covered_rate=$(awk -v a="$covered0" -v b="$covered1" -v s="$seconds" \
				'BEGIN { printf "%.1f", (b - a) / s }')
		fi
	fi
	awk -v kind="$kind" -v arr="$arrange" -v n="$n" -v cov="$covered" -v s="$seconds" \
		-v c=$((c1 - c0)) -v k=$((k1 - k0)) -v covms="$cov_ms" -v cc="$covered_rate" \
		-v dead="$(gone "${clients[@]}")" \
		'BEGIN {
		printf "%-8s %-8s %3d %8d %10.1f %13.1f %13s %17s%s\n", kind, arr, n, cov, c / s / 1000,
			k / s / 1000, covms, cc, (dead > 0 ? "  (" dead " clients died)" : "") }' |
		tee -a "$dir/rows"
	kill -0 "$cpid" 2>/dev/null || { echo "viscomp-bench: $kind died" >&2; tail "$run/log" >&2; }
	for p in "${clients[@]}"; do kill "$p" 2>/dev/null; done
	kill "$cpid" 2>/dev/null
	wait 2>/dev/null
	pids=()
}

# latency: two clients at one spot, raised in turn; prints viscompctl stats.
latency() {
	local run=$dir/latency cpid display a b k
	start viscomp stacked "$run"
	WAYLAND_DISPLAY=$display "${as_nobody[@]}" "$client" >/dev/null 2>&1 &
	a=$!
	pids+=("$a")
	place viscomp "$a" 100 100
	WAYLAND_DISPLAY=$display "${as_nobody[@]}" "$client" >/dev/null 2>&1 &
	b=$!
	pids+=("$b")
	place viscomp "$b" 100 100
	sleep 1
	for ((k = 0; k < cycles; k++)); do
		"$viscompctl" raise 1 >/dev/null
		sleep 0.1
		"$viscompctl" raise 2 >/dev/null
		sleep 0.1
	done
	"$viscompctl" stats
	echo "($client x 2 on $output, $cycles cycles of raise 1, raise 2 (0.1 s apart); $(nproc) CPUs:" \
		"$(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo); $(date -u +%F))"
}

# frame N: N clients as viscomp places them, the top one moved MOVES steps; prints the frame line.
frame() {
	local n=$1 run=$dir/frame-$1 cpid display k moves=${MOVES:-300}
	start viscomp stacked "$run"
	for ((k = 0; k < n; k++)); do
		WAYLAND_DISPLAY=$display "${as_nobody[@]}" "$client" >/dev/null 2>&1 &
		pids+=($!)
	done
	wait_for sh -c "[ \$($viscompctl list | wc -l) -eq $n ]" ||
		{ echo "viscomp-bench: not $n windows" >&2; exit 1; }
	sleep 2
	"$viscompctl" stats --reset >/dev/null
	for ((k = 0; k < moves; k++)); do
		"$viscompctl" move "$n" $((32 + k % 100 * 8)) $((32 + k % 50 * 8)) >/dev/null
		sleep 0.02 # about one move a frame
	done
	printf '%5d windows, %s\n' "$n" "$("$viscompctl" stats | grep '^frame')"
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
	wait 2>/dev/null
	pids=()
}

case $mode in
latency)
	latency
	exit 0
	;;
frame)
	for n in "${sizes[@]}"; do frame "$n"; done
	echo "($client, top window moved ${MOVES:-300} steps of 8 pixels, 20 ms apart, by viscompctl; libvis's time per" \
		"output frame in µs; $(nproc) CPUs: $(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo);" \
		"$(date -u +%F))"
	exit 0
	;;
esac
printf '%-8s %-8s %3s %8s %10s %13s %13s %17s\n' compositor arrange N covered 'comp ms/s' \
	'clients ms/s' 'covered ms/s' 'covered commit/s'
for ((r = 0; r < repeat; r++)); do
	for n in "${sizes[@]}"; do
		for arrange in "${arrangements[@]}"; do
			if [ $((r % 2)) -eq 0 ]; then
				run viscomp "$arrange" "$n" "$r"
				run sway "$arrange" "$n" "$r"
			else
				run sway "$arrange" "$n" "$r"
				run viscomp "$arrange" "$n" "$r"
			fi
		done
	done
done
if [ "$repeat" -gt 1 ]; then
	echo
	echo "each cell's range over $repeat runs:"
	printf '%-8s %-8s %3s %8s %13s %13s %13s %17s\n' compositor arrange N covered 'comp ms/s' \
		'clients ms/s' 'covered ms/s' 'covered commit/s'
	awk '
	function span(lo, hi) { return lo == hi ? lo : lo "–" hi }
	{
		key = $1 " " $2 " " $3
		if (!(key in seen)) { seen[key] = 1; order[++nk] = key; cov[key] = $4 }
		for (f = 5; f <= 8; f++) {
			v = $f
			if (v == "-") { lo[key, f] = hi[key, f] = "-"; continue }
			if (!((key, f) in lo) || v + 0 < lo[key, f] + 0) lo[key, f] = v
			if (!((key, f) in hi) || v + 0 > hi[key, f] + 0) hi[key, f] = v
		}
	}
	END {
		for (i = 1; i <= nk; i++) {
			split(order[i], k, " ")
			printf "%-8s %-8s %3d %8d %13s %13s %13s %17s\n", k[1], k[2], k[3], cov[order[i]],
				span(lo[order[i], 5], hi[order[i], 5]), span(lo[order[i], 6], hi[order[i], 6]),
				span(lo[order[i], 7], hi[order[i], 7]), span(lo[order[i], 8], hi[order[i], 8])
		}
	}' "$dir/rows"
fi
echo "($client on $output, $seconds s each; CPU time from /proc/PID/schedstat; $(nproc) CPUs:" \
	"$(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo); $(date -u +%F))"
