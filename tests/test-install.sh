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
staged libvisclient.a >/dev/null && pass
lib=$(staged libvisclient.so.2)
pass
soname=$(readelf -d "$lib" 2>/dev/null | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ "$soname" = libvisclient.so.2 ] || fail "libvisclient's soname is '$soname'"
pass
pc=$(staged pkgconfig/visclient.pc)
pass

# The README's example, as a newcomer would copy it.
sed -n '/<!-- example: begin -->/,/<!-- example: end -->/p' "$src/README.md" |
	sed '1,2d;$d' | sed '$d' >"$tmp/example.c"
grep -q 'vis_client_connect' "$tmp/example.c" || fail "no example client in README.md"
flags=$(PKG_CONFIG_PATH=$(dirname "$pc") PKG_CONFIG_SYSROOT_DIR=$stage \
	pkg-config --cflags --libs visclient) || fail "pkg-config cannot read the staged visclient.pc"
case "$flags" in
*"$src"*) fail "visclient.pc points into the source tree: $flags" ;;
esac
san=()
[ "$sanitize" = none ] || san=("-fsanitize=$sanitize")
# shellcheck disable=SC2086
cc -std=c11 -Wall -Wextra -Werror "${san[@]}" -o "$tmp/example" "$tmp/example.c" $flags \
	2>"$tmp/cc.log" || fail "the README's example does not build: $(cat "$tmp/cc.log")"
pass

# libvis: the library, its header and vis.pc, and the README's compositor example built against
# the staged vis.pc alone, which must print what the README's text says it does.
staged include/vis/vis.h >/dev/null && pass
staged include/vis/common.h >/dev/null && pass
staged libvis.a >/dev/null && pass
libvis=$(staged libvis.so.0)
soname=$(readelf -d "$libvis" 2>/dev/null | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
[ "$soname" = libvis.so.0 ] || fail "libvis's soname is '$soname'"
pass
vis_pc=$(staged pkgconfig/vis.pc)
sed -n '/<!-- libvis example: begin -->/,/<!-- libvis example: end -->/p' "$src/README.md" |
	sed '1,2d;$d' | sed '$d' >"$tmp/libvis-example.c"
grep -q 'vis_tree_create' "$tmp/libvis-example.c" || fail "no libvis example in README.md"
flags=$(PKG_CONFIG_PATH=$(dirname "$vis_pc") PKG_CONFIG_SYSROOT_DIR=$stage \
	pkg-config --cflags --libs vis) || fail "pkg-config cannot read the staged vis.pc"
case "$flags" in
*"$src"*) fail "vis.pc points into the source tree: $flags" ;;
esac
# shellcheck disable=SC2086
cc -std=c11 -Wall -Wextra -Werror "${san[@]}" -o "$tmp/libvis-example" "$tmp/libvis-example.c" \
	$flags 2>"$tmp/cc.log" || fail "the README's libvis example does not build: $(cat "$tmp/cc.log")"
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
