#!/usr/bin/env bash
# tools/dev.sh says why a build failed: on a copy of the source tree, a compile error and a
# dependency that pkg-config cannot find must each stop it with exit status 1, the step named,
# the cause shown and the log's path given (it used to print nothing and exit 1).
set -u
src=$(cd "$(dirname "$0")/.." && pwd)
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

copy broken
echo '#error broken on purpose' >>"$tmp/broken/daemon/log.c"
(cd "$tmp/broken" && tools/dev.sh release) >/dev/null 2>"$tmp/err"
expect "a compile error" $? "dev.sh: building build-release (ninja -C build-release) failed" \
	"broken on purpose" "build-release/dev-build.log"

copy nodeps
mkdir -p "$tmp/empty"
(cd "$tmp/nodeps" && PKG_CONFIG_LIBDIR=$tmp/empty PKG_CONFIG_PATH= tools/dev.sh release) \
	>/dev/null 2>"$tmp/err"
expect "a missing dependency" $? "dev.sh: configuring build-release" "failed" \
	"build-release/dev-setup.log" "pixman-1"

echo "devsh: $checks passed, 0 failed"
