# Waits that follow progress instead of guessing the machine's speed, for the shell suites (sourced;
# POSIX sh). tests/progress.h is the same for the C ones: a wait names the processes doing the
# work; it goes on while they use CPU time, and gives up when one of them is gone, when they have
# used less than $progress_min ticks of it (10 ms each) in $progress_stall seconds (a hang), or
# after $progress_ceiling seconds in all.
#
#   wait_progress PIDS COMMAND [ARG...]
# runs COMMAND every 50 ms until it succeeds (0), or gives up (1) with $progress_why saying why.
# PIDS is a space-separated list (an empty one: the stall interval is a plain timeout). Safe
# under set -eu.
progress_stall=${progress_stall:-60}
progress_ceiling=${progress_ceiling:-1800}
progress_min=10
progress_why=

# Seconds since boot, whole (no process started).
progress_now() {
	read -r progress_up _ </proc/uptime
	progress_up=${progress_up%.*}
}

# The clock ticks the processes have used, summed, in $progress_ticks; 1 when one is gone.
progress_cpu() {
	progress_ticks=0
	for progress_pid in $1; do
		{ read -r progress_stat </proc/"$progress_pid"/stat; } 2>/dev/null || progress_stat=
		progress_fields "$progress_pid" "${progress_stat##*) }" || return 1
	done
	return 0
}

# Adds the CPU time of one /proc/PID/stat's fields after the name; 1 for a process gone.
# shellcheck disable=SC2086
progress_fields() {
	progress_gone=$1
	set -- $2
	case ${1:-Z} in Z | X) progress_why="process $progress_gone is gone"; return 1 ;; esac
	progress_ticks=$((progress_ticks + ${12} + ${13}))
}

# Whether process $1 is gone (exited, a zombie not yet reaped): for wait_progress PID progress_gone PID.
progress_gone() {
	! progress_cpu "$1"
}

wait_progress() {
	progress_pids=$1
	shift
	progress_why= progress_last=
	progress_now
	progress_start=$progress_up progress_moved=$progress_up
	while :; do
		"$@" && return 0
		# One gone: the command once more, for what it did before it went.
		progress_cpu "$progress_pids" || { "$@" && return 0; return 1; }
		progress_now
		if [ -z "$progress_last" ] ||
			[ "$progress_ticks" -ge $((progress_last + progress_min)) ]; then
			progress_last=$progress_ticks progress_moved=$progress_up
		fi
		if [ $((progress_up - progress_moved)) -ge "$progress_stall" ]; then
			progress_why="no progress for $progress_stall s (under $progress_min ticks of CPU"
			progress_why="$progress_why time used by $progress_pids)"
			return 1
		fi
		if [ $((progress_up - progress_start)) -ge "$progress_ceiling" ]; then
			progress_why="still working after $progress_ceiling s"
			return 1
		fi
		sleep 0.05
	done
}
