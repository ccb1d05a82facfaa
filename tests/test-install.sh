#!/usr/bin/env bash
# What `meson install` puts in place works on its own: the build is staged with DESTDIR in a
# scratch directory; the README's example client (the text between its example markers) is
# built against the staged visclient.pc alone, no source tree on the include path; it runs
# against the staged visd and must print the visibility notice of its window. The README's libvis
# example is built against the staged vis.pc alone and must print what it says it does.
#
# usage: test-install.sh BUILD_DIR SANITIZE   (SANITIZE: meson's b_sanitize, e.g. none)
set -u
build=$1
sanitize=${2:-none}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
visd_pid=
trap '[ -n "$visd_pid" ] && kill "$visd_pid" 2>/dev/null; rm -rf "$tmp"' EXIT
checks=0

fail() {
	echo "test-install: $*" >&2
	exit 1
}

pass() {
	checks=$((checks + 1))
}

stage=$tmp/stage
DESTDIR=$stage meson install -C "$build" --no-rebuild >"$tmp/install.log" 2>&1 ||
	fail "meson install failed: $(tail -n 20 "$tmp/install.log")"

# Finds the one staged file at a path ending in $1.
staged() {
	local found
	found=$(find "$stage" -path "*/$1" | head -n 1)
	[ -n "$found" ] || fail "nothing staged at */$1"
	echo "$found"
}

visd=$(staged bin/visd)
pass
staged bin/visctl >/dev/null && pass
staged include/vis/visclient.h >/dev/null && pass
staged include/vis/protocol.h >/dev/null && pass
san=()
[ "$sanitize" = none ] || san=("-fsanitize=$sanitize")

# staged_lib NAME SONAME: the staged static and shared library NAME, the shared one's soname
# SONAME; prints the shared one's path (fails in the subshell of $(...): add || exit 1).
staged_lib() {
	local so soname
	staged "lib$1.a" >/dev/null
	so=$(staged "$2") || exit 1
	soname=$(readelf -d "$so" 2>/dev/null | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
	[ "$soname" = "$2" ] || fail "lib$1's soname is '$soname'"
	echo "$so"
}

# build_example MARKER CALL PKG OUT: the README's example between the MARKER markers, as a
# newcomer would copy it (it must call CALL), built against the staged PKG.pc alone into OUT.
build_example() {
	local pc flags
	sed -n "/<!-- $1: begin -->/,/<!-- $1: end -->/p" "$src/README.md" |
		sed '1,2d;$d' | sed '$d' >"$4.c"
	grep -q "$2" "$4.c" || fail "no $1 in README.md"
	pc=$(staged "pkgconfig/$3.pc") || exit 1
	flags=$(PKG_CONFIG_PATH=$(dirname "$pc") PKG_CONFIG_SYSROOT_DIR=$stage \
		pkg-config --cflags --libs "$3") || fail "pkg-config cannot read the staged $3.pc"
	case "$flags" in
	*"$src"*) fail "$3.pc points into the source tree: $flags" ;;
	esac
	# shellcheck disable=SC2086
	cc -std=c11 -Wall -Wextra -Werror "${san[@]}" -o "$4" "$4.c" $flags 2>"$tmp/cc.log" ||
		fail "the README's $1 does not build: $(cat "$tmp/cc.log")"
}

lib=$(staged_lib visclient libvisclient.so.2) || exit 1
pass
build_example example vis_client_connect visclient "$tmp/example"
pass

# libvis: the library, its headers and vis.pc; the README's compositor example must print what
# the README's text says it does, with the staged libvis.
staged include/vis/vis.h >/dev/null && pass
staged include/vis/common.h >/dev/null && pass
libvis=$(staged_lib vis libvis.so.0) || exit 1
pass
build_example "libvis example" vis_tree_create vis "$tmp/libvis-example"
pass
out=$(LD_LIBRARY_PATH=$(dirname "$libvis") "$tmp/libvis-example" 2>&1) ||
	fail "the libvis example failed: $out"
want='terminal is unobscured
draw desktop: 6 rectangles
draw terminal: 1 rectangles
draw editor: 1 rectangles'
[ "$out" = "$want" ] || fail "the libvis example printed '$out'"
pass
LD_LIBRARY_PATH=$(dirname "$libvis") ldd "$tmp/libvis-example" |
	grep -qF "$(dirname "$libvis")/libvis.so.0" || fail "the example did not load the staged libvis"
pass

"$visd" --socket "$tmp/sock" 2>"$tmp/visd.log" &
visd_pid=$!
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"
wait_progress "$visd_pid" test -S "$tmp/sock" ||
	fail "the staged visd did not start ($progress_why): $(cat "$tmp/visd.log")"
# A hang guard only (the example blocks on visd's answers): as long as a stall of visd's.
out=$(LD_LIBRARY_PATH=$(dirname "$lib") timeout "$progress_stall" "$tmp/example" "$tmp/sock" 2>&1)
rc=$?
[ $rc -eq 0 ] || fail "the example exited $rc: $out"
[[ "$out" =~ ^window\ [0-9]+\ is\ unobscured$ ]] || fail "the example printed '$out'"
pass
# It found the library it was built against, not another one on the system.
LD_LIBRARY_PATH=$(dirname "$lib") ldd "$tmp/example" | grep -qF "$(dirname "$lib")/libvisclient.so.2" ||
	fail "the example did not load the staged libvisclient"
pass
echo "install: $checks passed, 0 failed"
