#!/usr/bin/env bash
# tools/dev.sh says why a build failed: on a copy of the source tree, a compile error and a
# dependency that pkg-config cannot find must each stop it with exit status 1, the step named,
# the cause shown and the log's path given (it used to print nothing and exit 1).
# With BUILD-DIR, the demo runs on that build's programs (`tools/dev.sh demo BUILD-DIR`) and every
# line it prints must be labelled: a '== ' heading or, under one, an indented line; each engine's
# time names the engine (the first line used to be a bare `compute_ms=0.137`). `tools/dev.sh test`
# says what it runs before it runs it (its builds print nothing, and meson a test only when it
# ends: the silence read as a hang), and names the build that failed. The demo leaves nothing
# behind when its reader stops reading or Ctrl-C stops it.
# Usage: test-devsh.sh [BUILD-DIR]
set -u
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
checks=0
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$src/tests/progress.sh"

fail() {
	echo "test-devsh: $*" >&2
	exit 1
}

# A copy of the tracked source files in $tmp/$1.
copy() {
	mkdir -p "$tmp/$1"
	if git -C "$src" rev-parse --git-dir >/dev/null 2>&1; then
		(cd "$src" && git ls-files -z | xargs -0 tar cf -) | tar xf - -C "$tmp/$1"
	else
		(cd "$src" && tar cf - --exclude='./build*' .) | tar xf - -C "$tmp/$1"
	fi
}

# Expects the last run to have exited 1 with every pattern in its stderr.
expect() {
	local what=$1 rc=$2
	shift 2
	[ "$rc" -eq 1 ] || fail "$what: exit status $rc, not 1; stderr: $(cat "$tmp/err")"
	for p in "$@"; do
		grep -qF -- "$p" "$tmp/err" || fail "$what: stderr lacks '$p':
$(cat "$tmp/err")"
		checks=$((checks + 1))
	done
}

if [ -n "$build" ]; then
	"$src/tools/dev.sh" demo "$build" >"$tmp/demo" 2>"$tmp/err" ||
		fail "tools/dev.sh demo $build: exit status $?; stderr: $(cat "$tmp/err")"
	bad=$(grep -vnE '^(== .|   [^ ])' "$tmp/demo")
	[ -z "$bad" ] || fail "the demo printed unlabelled lines (neither '== ' headings nor indented):
$bad"
	checks=$((checks + 1))
	engines=$(grep -cE '^   (auto|gmv|gmv-heap|region) +compute_ms=[0-9]+\.[0-9]+$' "$tmp/demo")
	if [ "$engines" -ne 8 ] || [ "$(grep -c compute_ms= "$tmp/demo")" -ne 8 ]; then
		fail "the demo's engine times are not one 'ENGINE compute_ms=…' line per engine and scene:
$(grep compute_ms= "$tmp/demo")"
	fi
	checks=$((checks + 1))
	# It says why the sweep is slower on the desktop (it once printed the times alone), and
	# shows where it wins: the grid.
	grep -qF 'region, the union of the windows above as X.Org computes it, wins on a desktop' \
		"$tmp/demo" && grep -qF "the paper's worst case, a grid" "$tmp/demo" &&
		grep -qF 'region takes quadratic time, where the sweep stays O(n log n)' "$tmp/demo" ||
		fail "the demo does not say where the sweep wins and where region does: $(cat "$tmp/demo")"
	checks=$((checks + 1))
	grep -qF '(the same states as visctl compute on the scene file)' "$tmp/demo" ||
		fail "the demo's daemon states differ from visctl compute's: $(cat "$tmp/demo" "$tmp/err")"
	checks=$((checks + 1))

	# However the demo ends, it leaves no visd and no scratch directory behind: a reader that
	# stops reading (SIGPIPE once visd and the watch run), and Ctrl-C (SIGINT to the process
	# group, with visd and the watch started with SIGINT ignored, as a script's background jobs
	# are). Its scratch directories go to a TMPDIR of the test's own.
	# left_behind WHAT: fails when anything is left in $tmp/dt or a process names it.
	left_behind() {
		local left
		left=$(ls -A "$tmp/dt")
		[ -z "$left" ] || fail "$1 left $left in TMPDIR"
		left=$(pgrep -af -- "$tmp/dt/") && fail "$1 left processes running: $left"
		checks=$((checks + 1))
	}
	mkdir "$tmp/dt"
	TMPDIR=$tmp/dt "$src/tools/dev.sh" demo "$build" 2>/dev/null | head -n 8 >/dev/null
	left_behind "tools/dev.sh demo | head -n 8"
	# Cut where visd has just started and the shell itself writes the next line.
	TMPDIR=$tmp/dt "$src/tools/dev.sh" demo "$build" 2>/dev/null | sed '/^== the daemon/q' \
		>"$tmp/cut"
	grep -q '^== the daemon' "$tmp/cut" || fail "the demo cut short printed: $(cat "$tmp/cut")"
	left_behind "the demo cut short once visd ran (SIGPIPE)"
	set -m # the demo in a process group of its own, with SIGINT at its default, as in a terminal
	for try in 1 2 3 4 5; do
		TMPDIR=$tmp/dt "$src/tools/dev.sh" demo "$build" >"$tmp/int" 2>&1 &
		demo_pid=$!
		running() { compgen -G "$tmp/dt/*/visd-0" >/dev/null; }
		wait_progress "$demo_pid" running || fail "the demo's visd did not start ($progress_why)"
		kill -INT -- "-$demo_pid"
		wait "$demo_pid"
		rc=$?
		# The demo may have ended before the signal came: try again.
		grep -q 'notices in all' "$tmp/int" || break
	done
	set +m
	[ "$rc" -eq 130 ] || fail "the demo interrupted exited $rc, not 130 (try $try): $(cat "$tmp/int")"
	left_behind "the demo interrupted (SIGINT)"
fi

copy broken
echo '#error broken on purpose' >>"$tmp/broken/daemon/log.c"
(cd "$tmp/broken" && tools/dev.sh release) >/dev/null 2>"$tmp/err"
expect "a compile error" $? "dev.sh: building build-release (ninja -C build-release) failed" \
	"broken on purpose" "build-release/dev-build.log"
(cd "$tmp/broken" && tools/dev.sh test) >"$tmp/out" 2>"$tmp/err"
expect "tools/dev.sh test on a compile error" $? "dev.sh: building build (ninja -C build) failed" \
	"broken on purpose"
grep -qE '^dev.sh: 1/4: building build .*about [0-9]+ (s|min)' "$tmp/out" ||
	fail "tools/dev.sh test did not announce its first build with its time: $(cat "$tmp/out")"
checks=$((checks + 1))

copy nodeps
mkdir -p "$tmp/empty"
(cd "$tmp/nodeps" && PKG_CONFIG_LIBDIR=$tmp/empty PKG_CONFIG_PATH= tools/dev.sh release) \
	>/dev/null 2>"$tmp/err"
expect "a missing dependency" $? "dev.sh: configuring build-release" "failed" \
	"build-release/dev-setup.log" "pixman-1"

echo "devsh: $checks passed, 0 failed"
