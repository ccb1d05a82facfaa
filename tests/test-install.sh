#!/usr/bin/env bash
# What `meson install` puts in place works on its own: the build is staged with DESTDIR in a
# scratch directory; the README's example client (the text between its example markers) is
# built against the staged visclient.pc alone, no source tree on the include path; it runs
# against the staged visd and must print the visibility notice of its window. The README's libvis
# example is built against the staged vis.pc alone and must print what it says it does.
# Then a $HOME/.local install, by the README's own lines (see prefix_install below).
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
kill "$visd_pid" 2>/dev/null
wait "$visd_pid" 2>/dev/null
visd_pid=

# block MARKER: the text of the README's fenced block between the MARKER markers.
block() {
	sed -n "/<!-- $1: begin -->/,/<!-- $1: end -->/p" "$src/README.md" | sed '1,2d;$d' | sed '$d'
}

# readme_line PATTERN: the one backquoted command of the README that matches PATTERN (an ERE).
readme_line() {
	grep -oE "\`$1\`" "$src/README.md" | head -n 1 | tr -d '\`'
}

# A $HOME/.local install, as a newcomer follows the README: its install lines run as they stand
# (HOME a scratch directory, the build directory beside it rather than in the source tree), and
# with nothing more set, the programs are the ones on PATH, the README's by-hand lines work with
# them, both examples built by the README's own `cc` lines run with no LD_LIBRARY_PATH, and man,
# bash-completion and the user manager find the pages, the completion and the units. A build of
# its own (some 15 s on 2 cores), so not repeated under the sanitizers: the staged one above is.
prefix_install() {
	local home=$tmp/home cmd out id
	mkdir -p "$home" "$tmp/run" "$tmp/ex"
	chmod 700 "$tmp/run"
	block install >"$tmp/install.sh"
	grep -q '^meson install' "$tmp/install.sh" || fail "no install lines in README.md"
	export HOME=$home XDG_RUNTIME_DIR=$tmp/run
	unset VISD_SOCKET PKG_CONFIG_PATH LD_LIBRARY_PATH LIBRARY_PATH CPATH MANPATH XDG_DATA_HOME \
		XDG_DATA_DIRS XDG_CONFIG_HOME
	cd "$src" || fail "no source tree"
	# shellcheck disable=SC1090
	. <(sed "s|build-install|$tmp/build-install|g" "$tmp/install.sh") >"$tmp/prefix.log" 2>&1
	cd "$tmp/ex" || fail "no scratch directory"
	[ "$(command -v visd)" = "$home/.local/bin/visd" ] && [ "$(command -v visctl)" = \
		"$home/.local/bin/visctl" ] || fail "the README's install lines put no visd on PATH" \
		"($(command -v visd)): $(tail -n 20 "$tmp/prefix.log")"
	pass
	pkg-config --exists visclient vis || fail "pkg-config finds no visclient.pc after the README's lines"
	pass

	block "by hand" >"$tmp/by-hand.sh"
	[ "$(head -n 1 "$tmp/by-hand.sh" | cut -d'#' -f1 | tr -d ' ')" = 'visd&' ] ||
		fail "the README's by-hand lines do not start visd"
	visd 2>"$tmp/visd.log" &
	visd_pid=$!
	wait_progress "$visd_pid" test -S "$XDG_RUNTIME_DIR/visd-0" ||
		fail "the installed visd did not start ($progress_why): $(cat "$tmp/visd.log")"
	# The rest as it stands, but for a watch that ends after its first notice.
	# shellcheck disable=SC1090
	. <(sed '1d; s/ watch / watch --count 1 /' "$tmp/by-hand.sh") >"$tmp/by-hand.out" 2>&1
	out=$(cat "$tmp/by-hand.out")
	[ -n "${id:-}" ] && [[ "$out" =~ ^[0-9]+\ visibility\ $id\ unobscured ]] ||
		fail "the README's by-hand lines: window '${id:-}', watch printed '$out'"
	pass

	cmd=$(readme_line 'cc example\.c \$\(pkg-config --cflags --libs visclient\)')
	[ -n "$cmd" ] || fail "no cc line for the example in README.md"
	block example >example.c
	eval "$cmd" 2>"$tmp/cc.log" || fail "'$cmd' failed: $(cat "$tmp/cc.log")"
	out=$(timeout "$progress_stall" ./a.out 2>&1) || fail "the example, built by '$cmd': $out"
	[[ "$out" =~ ^window\ [0-9]+\ is\ unobscured$ ]] || fail "the example printed '$out'"
	ldd ./a.out | grep -qF "$home/.local/lib/libvisclient.so.2" ||
		fail "the example does not load the installed libvisclient: $(ldd ./a.out)"
	pass
	cmd=$(readme_line 'cc example\.c \$\(pkg-config --cflags --libs vis\)')
	[ -n "$cmd" ] || fail "no cc line for the libvis example in README.md"
	block "libvis example" >example.c
	eval "$cmd" 2>"$tmp/cc.log" || fail "'$cmd' failed: $(cat "$tmp/cc.log")"
	out=$(./a.out 2>&1)
	[ "$out" = "$want" ] || fail "the libvis example, built by '$cmd', printed '$out'"
	pass

	[ -f "$home/.local/share/bash-completion/completions/visctl" ] ||
		fail "visctl's completion is not where bash-completion looks for a user's"
	pass
	if [ -f "$home/.local/share/man/man1/visd.1" ] && command -v man >/dev/null; then
		[ "$(man -w visd 2>&1)" = "$home/.local/share/man/man1/visd.1" ] ||
			fail "man -w visd: '$(man -w visd 2>&1)', with PATH=$PATH"
		pass
	fi
	if command -v systemd-analyze >/dev/null; then
		[ -f "$home/.local/share/systemd/user/visd.socket" ] &&
			systemd-analyze --user unit-paths 2>/dev/null |
			grep -qxF "$home/.local/share/systemd/user" ||
			fail "the units are not where the user manager looks: $(find "$home" -name visd.socket)"
		pass
	fi
}

if [ "$sanitize" = none ]; then
	prefix_install
else
	echo "install: the \$HOME/.local install is checked without the sanitizers only"
fi
echo "install: $checks passed, 0 failed"
