#!/usr/bin/env bash
# The two set-up commands of the README:
#   tools/dev.sh demo   install what is missing, build (release), run the main job
#   tools/dev.sh demo BUILD-DIR   the demo alone, on the programs already built in BUILD-DIR
#                       (installing and building nothing; tests/test-devsh.sh runs it so)
#   tools/dev.sh test   install what is missing, build, run every suite, then again under ASan+UBSan
#   tools/dev.sh release  install what is missing, configure (once) and build build-release
#   tools/dev.sh install [PACKAGE...]   install what is missing of these Debian packages (default:
#                       the build's), as the other tools do (tools/fuzz.sh)
set -euo pipefail
called_from=$PWD
cd "$(dirname "$0")/.."
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. tests/progress.sh
# A signal ends the script through `exit`, so that the EXIT trap (the demo's: its visd, its
# watch and its scratch directory) runs however it ends: Ctrl-C, a kill, or a reader that stops
# reading (`tools/dev.sh demo | head`), which would otherwise kill the shell outright by SIGPIPE.
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP
trap 'exit 141' PIPE

# scdoc: the man pages (man/); systemd: systemd-socket-activate for the socket activation test,
# systemd-analyze to verify the user units (tests/test-activate.sh, tests/check-units.sh);
# xcb-xfixes for visd-x11, and the X desktop its tests run (tests/test-x11.sh): openbox, xcompmgr,
# picom, xlogo and xeyes (x11-apps), xterm, xprop (x11-utils); abigail-tools: abidiff, for the
# libraries' ABI against their baselines (tests/check-abi.sh); viscomp, the Wayland compositor
# (compositor/): wlroots 0.15 and what its headers need (libwayland-dev with wayland-scanner,
# wayland-protocols, libxkbcommon-dev), and the real clients its tests run (tests/test-viscomp.sh,
# tests/test-viscomp-pixels.sh): weston's demo clients, foot (with a monospace font:
# fonts-dejavu-core), grim, and xdotool, which clicks and types into viscomp nested in Xvfb
# (tests/test-viscomp-input.sh); the unmodified
# X applications the real-application test covers (tests/test-realapps.sh): alacritty, which
# opens EGL at run time without depending on it (libegl1, libegl-mesa0), and i3lock.
PACKAGES=(gcc meson ninja-build pkg-config libpixman-1-dev libevent-dev libxcb1-dev libxcb-shape0-dev xvfb
	libxml2-utils
	scdoc systemd abigail-tools
	libxcb-xfixes0-dev openbox xcompmgr picom x11-apps xterm x11-utils
	libwlroots-dev libwayland-dev wayland-protocols libxkbcommon-dev weston foot fonts-dejavu-core grim
	xdotool
	alacritty libegl1 libegl-mesa0 i3lock)

# Installs the Debian packages given that are missing, asking apt only when something is.
install_missing() {
	local missing=()
	for p in "$@"; do
		dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' ||
			missing+=("$p")
	done
	[ ${#missing[@]} -eq 0 ] && return 0
	echo "dev.sh: installing ${missing[*]}" >&2
	local sudo=()
	[ "$(id -u)" -eq 0 ] || sudo=(sudo)
	"${sudo[@]}" apt-get update -qq
	DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq "${missing[@]}" >/dev/null
}

# Runs one step with its output in a log; on failure, shows the log's end, names the step and the
# whole log, and stops.
step() {
	local what=$1 log=$2
	shift 2
	if ! "$@" >"$log" 2>&1; then
		echo "dev.sh: $what failed; the end of its output:" >&2
		tail -n 30 "$log" >&2
		echo "dev.sh: $what failed (all of its output: $log)" >&2
		exit 1
	fi
}

# Configures (once) and builds one build directory, quietly unless a step fails.
build() {
	local dir=$1
	shift
	# Trees configured before client/ had a folder per part hold visctl where its folder goes.
	[ -f "$dir/client/visctl" ] && rm -f "$dir/client/visctl"
	mkdir -p "$dir"
	[ -f "$dir/build.ninja" ] ||
		step "configuring $dir (meson setup $dir $*)" "$dir/dev-setup.log" meson setup "$dir" "$@"
	step "building $dir (ninja -C $dir)" "$dir/dev-build.log" ninja -C "$dir"
}

# Stops what the demo started and removes its scratch directory (the EXIT trap): the watch first,
# so that it does not report visd's going; visd removes its socket and lock on SIGTERM. A wait
# for one that died of the signal fails (143), which under set -e would end the trap there,
# leaving visd and the directory behind: each step goes on whatever the last one returned.
demo_cleanup() {
	if [ -n "${watch_pid:-}" ] && kill "$watch_pid" 2>/dev/null; then
		wait "$watch_pid" 2>/dev/null || true
	fi
	if [ -n "${visd_pid:-}" ] && kill "$visd_pid" 2>/dev/null; then
		wait "$visd_pid" 2>/dev/null || true
	fi
	if [ -n "${demo_tmp:-}" ]; then
		rm -rf "$demo_tmp"
	fi
	return 0
}

# Runs the demo on the programs built in $1. Every line it prints is labelled: a '== ' heading,
# or under one, indented, a line that names what it shows (tests/test-devsh.sh checks it).
demo() {
	local bin=$1 tmp
	if [ ! -x "$bin/daemon/visd" ] || [ ! -x "$bin/client/visctl/visctl" ]; then
		echo "dev.sh: no visd or visctl built in $bin" >&2
		exit 1
	fi
	visd_pid=
	watch_pid=
	demo_tmp=
	trap demo_cleanup EXIT
	tmp=$(mktemp -d)
	demo_tmp=$tmp
	local sock=$tmp/visd-0
	local visctl=$bin/client/visctl/visctl
	v() { "$visctl" -s "$sock" "$@"; }
	# Each engine's time on a scene file, a line each.
	engine_times() {
		for e in auto gmv gmv-heap region; do
			printf '   %-9s ' "$e"
			"$visctl" compute --engine="$e" --time "$1" 2>&1 >/dev/null
		done
	}

	"$visctl" gen random 10000 1 >"$tmp/big.scene"
	echo "== offline: visctl compute on a generated desktop of 10,000 windows; windows by state:"
	"$visctl" compute "$tmp/big.scene" >"$tmp/big.out"
	awk '{ n[$2]++ } END { for (s in n) printf "   %-20s %d\n", s, n[s] }' "$tmp/big.out" | sort
	echo "== the time each engine takes on it (visctl compute --engine=E --time):"
	engine_times "$tmp/big.scene"
	echo "   (region, the union of the windows above as X.Org computes it, wins on a desktop: once"
	echo "   the union covers the screen, as a few maximized windows do, each window below costs"
	echo "   it almost nothing, while the sweep (gmv, gmv-heap) pays O(n log n) for any stack)"
	"$visctl" gen grid 1000 1 >"$tmp/grid.scene"
	echo "== the same on the paper's worst case, a grid of 500 bars over 500 (visctl gen grid 1000 1):"
	engine_times "$tmp/grid.scene"
	echo "   (every bar crosses every other: the union above gains a piece at every crossing and"
	echo "   region takes quadratic time, where the sweep stays O(n log n); auto runs region until"
	echo "   a forecast of its remaining work passes the sweep's cost, then hands over to gmv-heap)"

	echo "== the daemon: visd --socket $sock --screen 3840x2160"
	"$bin/daemon/visd" --socket "$sock" --screen 3840x2160 &
	visd_pid=$!
	wait_progress "$visd_pid" test -S "$sock" ||
		{ echo "dev.sh: visd did not start ($progress_why)" >&2; exit 1; }
	echo "== an observer watches every window: visctl --role observer watch"
	"$visctl" -s "$sock" --role observer watch >"$tmp/watch" &
	watch_pid=$!
	# It has subscribed once it reports a window of a client come and gone (its lines left out).
	probed() { v create 0 0 1 1 >/dev/null && [ -s "$tmp/watch" ]; }
	wait_progress "$watch_pid $visd_pid" probed ||
		{ echo "dev.sh: visctl watch did not subscribe ($progress_why)" >&2; exit 1; }
	local probes
	probes=$(wc -l <"$tmp/watch")
	"$visctl" gen random 200 1 >"$tmp/desk.scene"
	echo "== visctl load --retain: 200 windows created and mapped in one batch"
	v load --retain "$tmp/desk.scene" >"$tmp/map"
	echo "== visctl --role observer states, summed up:"
	v --role observer states | awk '{ n[$2]++ } END { for (s in n) printf "   %-20s %d\n", s, n[s] }' |
		sort
	"$visctl" compute "$tmp/desk.scene" >"$tmp/desk.out"
	awk 'NR == FNR { id[$1] = $2; next } { print id[$1], $2 }' "$tmp/map" "$tmp/desk.out" |
		sort -n >"$tmp/want"
	if v --role observer states | cmp -s - "$tmp/want"; then
		echo "   (the same states as visctl compute on the scene file)"
	else
		echo "   DIFFERENT from visctl compute on the scene file" >&2
	fi
	echo "== an application: its window, covered by a popup, then uncovered (visctl script)"
	cat >"$tmp/app" <<'SCRIPT'
create 100 100 640 480 --map --retain
SCRIPT
	local app
	app=$(v script "$tmp/app")
	v --role manager raise "$app"
	local popup
	popup=$(v create 50 50 800 600 --map --retain)
	v --role manager move "$popup" 3000 1500
	v --role manager destroy "$popup"
	seen() { grep -q " stack destroy $popup " "$tmp/watch"; }
	wait_progress "$watch_pid $visd_pid" seen ||
		{ echo "dev.sh: visctl watch did not see the popup go ($progress_why)" >&2; exit 1; }
	echo "== what the observer saw about them (serial, notice, window, …):"
	grep -E " ($app|$popup) " "$tmp/watch" | sed 's/^/   /'
	echo "== $(($(wc -l <"$tmp/watch") - probes)) notices in all; visctl watch --json prints JSON; see proto/PROTOCOL.md"
}

# Says what runs next and roughly how long it takes: builds print nothing, and meson prints a
# test's line only once it ends, so a long step would otherwise read as a hang.
announce() {
	echo "dev.sh: $*"
}

# The two passes, each announced with what it runs and about how long it takes on a 2-core
# machine (measured with the other engineers' test runs beside it, 2026-11-28); a loaded machine
# takes longer, and the suites' waits follow the programs' progress, not the clock
# (docs/TESTING.md, Waits).
run_tests() {
	announce "1/4: building build (meson setup the first time, then ninja: about 1 min from" \
		"scratch, seconds when up to date)"
	build build
	announce "2/4: every suite on build (meson test, in parallel, a line as each ends: about" \
		"2.5 min in all; the longest: x11 about 2 min, x11-faults 35 s, differential and" \
		"x11-order 20 s each)"
	meson test -C build --print-errorlogs
	# The sanitizer pass: b_lundef=false because the sanitizer runtimes resolve at run time.
	announce "3/4: building build-san, a second build of everything, with ASan and UBSan (about" \
		"1 min from scratch, seconds when up to date)"
	build build-san -Db_sanitize=address,undefined -Db_lundef=false --buildtype=debug
	announce "4/4: every suite again on build-san, under ASan and UBSan (about 15 min in all;" \
		"the longest: x11 about 11 min, x11-faults 5 min, differential 3 min, wtree, look," \
		"limits and seethrough about 1 min each)"
	UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 \
		meson test -C build-san --print-errorlogs --timeout-multiplier 4
}

# The release build links with link-time optimization: libvis's walks call the banded regions'
# operations (src/bands.c) window after window, across files; inlined, a 10-window frame of
# bench-libvis takes about 5% less time.
RELEASE=(--buildtype=release -Db_lto=true)

case "${1:-}" in
demo)
	if [ $# -gt 1 ]; then
		case $2 in /*) demo "$2" ;; *) demo "$called_from/$2" ;; esac
	else
		install_missing "${PACKAGES[@]}"
		build build-release "${RELEASE[@]}"
		demo build-release
	fi
	;;
test)
	install_missing "${PACKAGES[@]}"
	run_tests
	;;
release)
	install_missing "${PACKAGES[@]}"
	build build-release "${RELEASE[@]}"
	;;
install)
	shift
	[ $# -gt 0 ] || set -- "${PACKAGES[@]}"
	install_missing "$@"
	;;
*)
	echo "usage: tools/dev.sh demo [BUILD-DIR] | test | release | install [PACKAGE...]" >&2
	exit 2
	;;
esac
