# Unmodified X applications on a private desktop, for tests/test-realapps.sh and
# tools/realapps-bench.sh (sourced; POSIX sh, after tests/progress.sh): a private Xvfb, openbox,
# a compositing manager, visd and visd-x11 from a build, a cover (tests/x11-cover) and the
# applications. The caller sets $build (the build directory), $dir (a scratch directory it
# removes) and fail MESSAGE [LOG], and calls ra_cleanup on exit.
#
# The applications' work is measured per line of output, never per second of a guess: each
# Alacritty runs a writer that prints a line every 10 ms and writes its count to a file, and a
# span is "until the writer printed N more lines", waited for with wait_progress. Alacritty's CPU
# time over a span (utime + stime of /proc/PID/stat, every thread's) is what it spent drawing
# those lines: much while it draws, next to nothing once it knows it is covered.
ra_width=800
ra_height=600
bridge=${BRIDGE:-$build/bridge/x11/visd-x11}
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl
cover=$build/tests/x11-cover
xpid= wpid= cmpid= vpid= bpid= kpid= app_pid= lock_pid= tick_pid=
ra_n=0

# Ends every process the desktop started, the last started first.
ra_cleanup() {
	exec 4>&- 5<&- 2>/dev/null
	for pid in $tick_pid $lock_pid $app_pid $kpid $bpid $vpid $cmpid $wpid $xpid; do
		kill "$pid" 2>/dev/null
	done
	for pid in $tick_pid $lock_pid $app_pid $kpid $bpid $vpid $cmpid $wpid $xpid; do
		wait "$pid" 2>/dev/null
	done
}

# Seconds since boot in hundredths, in $ra_cs.
ra_clock() {
	read -r ra_up _ </proc/uptime
	ra_cs=${ra_up%.*}${ra_up#*.}
}

# Xvfb, openbox on it, and the cover (its commands on fd 4, its answers on fd 5).
ra_start_x() {
	exec 3>"$dir/display"
	Xvfb -displayfd 3 -screen 0 ${ra_width}x${ra_height}x24 -nolisten tcp -noreset \
		>"$dir/xvfb.log" 2>&1 &
	xpid=$!
	exec 3>&-
	wait_progress "$xpid" test -s "$dir/display" ||
		fail "Xvfb did not start ($progress_why):" "$dir/xvfb.log"
	DISPLAY=:$(head -n 1 "$dir/display")
	export DISPLAY
	openbox --sm-disable >"$dir/openbox.log" 2>&1 &
	wpid=$!
	wait_progress "$wpid $xpid" ra_wm_ready ||
		fail "openbox did not take the screen ($progress_why):" "$dir/openbox.log"
	mkfifo "$dir/cover.in" "$dir/cover.out" || fail "mkfifo failed"
	"$cover" <"$dir/cover.in" >"$dir/cover.out" 2>"$dir/cover.log" &
	kpid=$!
	exec 4>"$dir/cover.in" 5<"$dir/cover.out"
}

# Whether openbox has taken the screen (it sets _NET_SUPPORTING_WM_CHECK then).
ra_wm_ready() {
	xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q 'window id'
}

# One command to the cover; its answer in $answer ("ok", a window, or "error").
ra_cover() {
	echo "$*" >&4
	read -r answer <&5 || fail "x11-cover died:" "$dir/cover.log"
	[ "$answer" != error ] || fail "x11-cover refused $*:" "$dir/cover.log"
}

# A compositing manager (picom or xcompmgr), once it owns _NET_WM_CM_S0.
ra_start_cm() {
	case $1 in
	picom) picom --backend xrender --config /dev/null >"$dir/cm.log" 2>&1 & ;;
	*) xcompmgr >"$dir/cm.log" 2>&1 & ;;
	esac
	cmpid=$!
	wait_progress "$cmpid $xpid" ra_cm_ready || fail "$1 did not start ($progress_why):" "$dir/cm.log"
}

# Whether a compositing manager owns _NET_WM_CM_S0.
ra_cm_ready() {
	ra_cover cm
	[ "$answer" != 0x0 ]
}

# Ends the compositing manager.
ra_stop_cm() {
	kill "$cmpid"
	wait "$cmpid" 2>/dev/null
	cmpid=
}

# A fresh visd and visd-x11 (with $SEND_EVENTS as its --send-events, auto unless set).
ra_start_bridge() {
	ra_stop_bridge
	ra_n=$((ra_n + 1))
	sock=$dir/visd$ra_n
	"$visd" --socket "$sock" --screen ${ra_width}x${ra_height} 2>"$dir/visd$ra_n.log" &
	vpid=$!
	wait_progress "$vpid" test -S "$sock" || fail "visd did not start ($progress_why):" "$dir/visd$ra_n.log"
	blog=$dir/bridge$ra_n.log
	"$bridge" --display "$DISPLAY" -s "$sock" --send-events "${SEND_EVENTS:-auto}" 2>"$blog" &
	bpid=$!
}

# Ends visd-x11 and its visd, where they run.
ra_stop_bridge() {
	[ -n "$bpid" ] || return 0
	kill "$bpid" "$vpid"
	wait "$bpid" "$vpid" 2>/dev/null
	bpid= vpid=
}

# visd's state of X window $1 (as visctl states --x11 names it), in $state.
ra_state() {
	state=$("$visctl" -s "$sock" states --x11 2>/dev/null | sed -n "s/^$1 //p")
	[ "$state" = "$2" ]
}

# Waits until visd's state of window $1 is $2 (the bridge then tells the window's clients).
ra_wait_state() {
	[ -n "$bpid" ] || return 0
	wait_progress "$bpid $vpid $xpid" ra_state "$1" "$2" ||
		fail "visd never said $2 of $1 (its state: ${state:-none}; $progress_why):" "$blog"
}

# The window named $1 (its title) in $win: a child of the frame's, as xwininfo -tree shows it.
ra_find() {
	win=$(xwininfo -root -tree 2>/dev/null | sed -n "s/^ *\(0x[0-9a-f]*\) \"$1\".*/\1/p" | head -n 1)
	[ -n "$win" ]
}

# The count the writer named $1 has reached, in $lines (0 before it starts). It writes its
# count into two files by turns, so that one holds a count while the other is being rewritten.
ra_lines() {
	ra_odd= ra_even=
	{ read -r ra_odd <"$dir/count.$1.1"; } 2>/dev/null
	{ read -r ra_even <"$dir/count.$1.0"; } 2>/dev/null
	lines=${ra_odd:-0}
	[ "${ra_even:-0}" -le "$lines" ] || lines=$ra_even
}

# Whether the writer named $1 has printed $2 lines.
ra_reached() {
	ra_lines "$1"
	[ "$lines" -ge "$2" ]
}

# The writer's loop: a line every 10 ms, its count in $0.1 and $0.0 by turns.
ra_writer='i=0; while :; do i=$((i + 1)); echo "line $i"; echo $i >"$0.$((i % 2))"; sleep 0.01; done'

# Alacritty titled $1 running the writer $1; its pid in $app_pid, its window in $app_win, once
# its writer has printed a line. Mesa's llvmpipe draws for it (Xvfb has no GL of its own).
ra_start_alacritty() {
	: >"$dir/alacritty.yml"
	rm -f "$dir/count.$1".*
	LIBGL_ALWAYS_SOFTWARE=1 WINIT_X11_SCALE_FACTOR=1 alacritty --config-file "$dir/alacritty.yml" \
		--title "$1" -e sh -c "$ra_writer" "$dir/count.$1" >"$dir/alacritty.$1.log" 2>&1 &
	app_pid=$!
	app_name=$1
	wait_progress "$app_pid $xpid" ra_app_ready ||
		fail "Alacritty did not start ($progress_why):" "$dir/alacritty.$1.log"
}

# Whether Alacritty's window is there and its writer has printed.
ra_app_ready() {
	ra_find "$app_name" && app_win=$win && ra_reached "$app_name" 1
}

# Ends Alacritty (its writer goes with its terminal).
ra_stop_app() {
	kill "$app_pid"
	wait "$app_pid" 2>/dev/null
	app_pid=
}

# A writer alone, as a clock of progress for what has nothing to measure (ra_span_of_ticks).
ra_start_ticker() {
	rm -f "$dir/count.ticker".*
	sh -c "$ra_writer" "$dir/count.ticker" >/dev/null &
	tick_pid=$!
}

# Alacritty's CPU time over its writer's next $1 lines, after $2 lines (0: none) of settling:
# the clock ticks (10 ms) in $ticks, the share of a core in $pct (percent).
ra_span() {
	ra_lines "$app_name"
	wait_progress "$app_pid $xpid" ra_reached "$app_name" $((lines + $2)) ||
		fail "the writer in Alacritty stopped ($progress_why):" "$dir/alacritty.$app_name.log"
	ra_lines "$app_name"
	progress_cpu "$app_pid" || fail "Alacritty died:" "$dir/alacritty.$app_name.log"
	ra_t0=$progress_ticks
	ra_clock
	ra_c0=$ra_cs
	wait_progress "$app_pid $xpid" ra_reached "$app_name" $((lines + $1)) ||
		fail "the writer in Alacritty stopped ($progress_why):" "$dir/alacritty.$app_name.log"
	progress_cpu "$app_pid" || fail "Alacritty died:" "$dir/alacritty.$app_name.log"
	ticks=$((progress_ticks - ra_t0))
	ra_clock
	pct=$((ticks * 1000 / (ra_cs - ra_c0 + 1)))
	pct=$((pct / 10)).$((pct % 10))
}

# i3lock (not forking), once its window is up and on top: its pid in $lock_pid, window $lock_win.
ra_start_i3lock() {
	i3lock -n -c 203040 >"$dir/i3lock.log" 2>&1 &
	lock_pid=$!
	wait_progress "$lock_pid $xpid" ra_lock_on_top || fail "i3lock did not start ($progress_why):" "$dir/i3lock.log"
}

# Whether i3lock's window is the topmost viewable one (it is found on the first call).
ra_lock_on_top() {
	if [ -z "$lock_win" ]; then
		lock_win=$(xwininfo -root -children 2>/dev/null |
			sed -n 's/^ *\(0x[0-9a-f]*\) "i3lock".*/\1/p' | head -n 1)
		[ -n "$lock_win" ] || return 1
	fi
	ra_cover top
	[ "$answer" = "$lock_win" ]
}

# Ends i3lock.
ra_stop_i3lock() {
	kill "$lock_pid"
	wait "$lock_pid" 2>/dev/null
	lock_pid= lock_win=
}
