#!/usr/bin/env bash
# tools/dev.sh says why a build failed: on a copy of the source tree, a compile error and a
# dependency that pkg-config cannot find must each stop it with exit status 1, the step named,
# the cause shown and the log's path given (it used to print nothing and exit 1).
# With BUILD-DIR, the demo runs on that build's programs (`tools/dev.sh demo BUILD-DIR`) and every
# line it prints must be labelled: a '== ' heading or, under one, an indented line; each engine's
# time names the engine (the first line used to be a bare `compute_ms=0.137`). `tools/dev.sh test`
# says what it runs before it runs it (its builds print nothing, and meson a test only when it
# ends: the silence read as a hang), and names the build that failed.
# Usage: test-devsh.sh [BUILD-DIR]
set -u
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
checks=0

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
	if [ "$engines" -ne 4 ] || [ "$(grep -c compute_ms= "$tmp/demo")" -ne 4 ]; then
		fail "the demo's engine times are not one 'ENGINE compute_ms=…' line per engine:
$(grep compute_ms= "$tmp/demo")"
	fi
	checks=$((checks + 1))
	grep -qF '(the same states as visctl compute on the scene file)' "$tmp/demo" ||
		fail "the demo's daemon states differ from visctl compute's: $(cat "$tmp/demo" "$tmp/err")"
	checks=$((checks + 1))
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
