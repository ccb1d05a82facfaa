#!/bin/sh
# The man pages must not drift from the programs: every option that `visd --help`, `visctl --help`
# and `visctl COMMAND --help` print must be documented in visd.1.scd or visctl.1.scd, and every
# option those pages document must be printed by that --help, the other way round. Options are
# matched exactly. What --help prints: each token that starts with "--" and a letter, or is "-"
# and one letter, outside `backquotes` (which quote other command lines: `ulimit -n`, `visctl
# stress --help`). What a page documents: the *-x* and *--long* terms of its option lists (lines
# that start with "*-"): all of visd.1.scd's; in visctl.1.scd, those of "# OPTIONS" (the global
# options, which every command's help may also name) and those of each command's "## COMMAND"
# subsection. -h and --help are checked by running them: both must print the same usage and exit
# 0. Every command `visctl --help` lists needs its subsection, and every subsection its command.
# libvisclient.3.scd must document each function visclient.h exports (*name*( terms), and no other;
# libvis.3.scd each function of vis.h, beside it. Where viscomp is built (VISCOMP and VISCOMPCTL
# given), viscomp.1.scd documents the options `viscomp --help` prints and no other, and
# viscompctl.1.scd its options under "# OPTIONS" and, under "# COMMANDS", a *COMMAND* term for
# each command `viscompctl --help` lists (and none other), with the options the help gives it.
# Usage: check-man.sh VISD VISCTL MAN-DIR VISCLIENT-H [VISCOMP VISCOMPCTL]
set -u
visd=${1:?usage: check-man.sh VISD VISCTL MAN-DIR VISCLIENT-H}
visctl=${2:?}
man=${3:?}
header=${4:?}
viscomp=${5:-}
viscompctl=${6:-}
T=$(mktemp -d "${TMPDIR:-/tmp}/check-man.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

failed=0
checked=0
fail() {
	echo "FAIL: $*"
	failed=$((failed + 1))
}

# The option tokens of a text on stdin, one a line, sorted; `quoted command lines` left out.
help_options() {
	sed 's/`[^`]*`//g' | tr -c 'A-Za-z0-9-' '\n' |
		grep -E '^(--[A-Za-z][A-Za-z0-9-]*|-[A-Za-z])$' | sort -u
}

# The options a piece of a page on stdin documents: the *-x* and *--long* of its term lines.
man_options() {
	grep '^\*-' | grep -oE '\*--?[A-Za-z][A-Za-z0-9-]*' | sed 's/^\*//' |
		grep -E '^(--[A-Za-z][A-Za-z0-9-]*|-[A-Za-z])$' | sort -u
}

# The lines of FILE from the heading HEADING (a whole line) to the next heading of any level.
section() {
	awk -v h="$2" '$0 == h { on = 1; next } on && /^#/ { exit } on' "$1"
}

# run_help WHO OUT ARGS...: runs ARGS with --help and with -h into OUT; both must exit 0 and
# print the same.
run_help() {
	who=$1 out=$2
	shift 2
	checked=$((checked + 1))
	if ! "$@" --help >"$out" 2>"$T/err"; then
		fail "\`$who --help\` failed: $(head -n 3 "$T/err")"
	elif ! "$@" -h >"$T/h" 2>"$T/err"; then
		fail "\`$who -h\` failed: $(head -n 3 "$T/err")"
	elif ! cmp -s "$out" "$T/h"; then
		fail "\`$who -h\` and \`$who --help\` print different texts"
	elif [ ! -s "$out" ]; then
		fail "\`$who --help\` prints nothing"
	fi
}

# compare PAGE WHO HELP-OPTIONS DOCUMENTED ALLOWED: every option in HELP-OPTIONS must be in
# ALLOWED (what the page documents where WHO's options may be), and every option in DOCUMENTED
# (what the page documents for WHO) must be in HELP-OPTIONS, but -h and --help, which run_help ran.
compare() {
	page=$1 who=$2
	for o in $(comm -23 "$3" "$5"); do
		fail "$page: $o is printed by \`$who --help\` but not documented (no *$o* term)"
	done
	for o in $(comm -23 "$4" "$3"); do
		case $o in
		-h | --help) ;;
		*) fail "$page: $o is documented for \`$who\` but \`$who --help\` does not print it" ;;
		esac
	done
	checked=$((checked + 1))
}

# visd: one page, one option list.
page=$man/visd.1.scd
run_help visd "$T/visd.help" "$visd"
help_options <"$T/visd.help" >"$T/visd.opts"
man_options <"$page" >"$T/visd.doc"
compare "$page" visd "$T/visd.opts" "$T/visd.doc" "$T/visd.doc"

# visctl: the global options, then each command.
page=$man/visctl.1.scd
run_help visctl "$T/visctl.help" "$visctl"
section "$page" '# OPTIONS' | man_options >"$T/global.doc"
[ -s "$T/global.doc" ] || fail "$page: no options under '# OPTIONS'"
grep -v '^  visctl ' "$T/visctl.help" | help_options >"$T/global.opts"
compare "$page" visctl "$T/global.opts" "$T/global.doc" "$T/global.doc"

commands=$(sed -n 's/^  visctl \([a-z][a-z-]*\).*/\1/p' "$T/visctl.help")
[ -n "$commands" ] || fail "\`visctl --help\` lists no command"
for c in $commands; do
	if ! grep -qx "## $c" "$page"; then
		fail "$page: no '## $c' subsection for the command \`visctl $c\`"
		continue
	fi
	section "$page" "## $c" | man_options >"$T/$c.doc"
	sort -u "$T/$c.doc" "$T/global.doc" >"$T/$c.allowed"
	# The command's line in `visctl --help` may name only what its subsection documents.
	grep "^  visctl $c\( \|$\)" "$T/visctl.help" | help_options >"$T/$c.line"
	for o in $(comm -23 "$T/$c.line" "$T/$c.allowed"); do
		fail "$page: $o is printed for $c by \`visctl --help\`" \
			"but not documented (no *$o* term under '## $c')"
	done
	run_help "visctl $c" "$T/$c.help" "$visctl" "$c"
	help_options <"$T/$c.help" >"$T/$c.opts"
	compare "$page" "visctl $c" "$T/$c.opts" "$T/$c.doc" "$T/$c.allowed"
done
for s in $(sed -n 's/^## \([a-z][a-z-]*\)$/\1/p' "$page"); do
	echo "$commands" | grep -qx "$s" ||
		fail "$page: '## $s' names no command that \`visctl --help\` lists"
done

# libvisclient(3) and libvis(3): the exported functions, as check-exports.sh reads them from the
# headers.
check_api() {
	page=$1 header=$2
	grep -v '^#' "$header" | tr '\n' ' ' | grep -oE 'VIS_EXPORT [^(;]*\(' |
		sed -E 's/.*[ *]([A-Za-z_][A-Za-z_0-9]*)\($/\1/' | sort -u >"$T/api"
	grep '^\*vis_' "$page" | grep -oE '\*vis_[a-z0-9_]+\*\(' | sed -E 's/^\*(.*)\*\($/\1/' |
		sort -u >"$T/api.doc"
	[ -s "$T/api" ] || fail "$header: no VIS_EXPORT declarations found"
	for f in $(comm -23 "$T/api" "$T/api.doc"); do
		fail "$page: $f is exported by $header but not documented (no *$f*( term)"
	done
	for f in $(comm -13 "$T/api" "$T/api.doc"); do
		fail "$page: $f is documented but $header does not export it"
	done
	checked=$((checked + 1))
}
check_api "$man/libvisclient.3.scd" "$header"
check_api "$man/libvis.3.scd" "$(dirname "$header")/vis.h"

# viscomp: one page, one option list. viscompctl: the options, then the commands, whose lines
# in --help ("  list [--json]  ...") must each have a term "*list* [*--json*]" in the page.
if [ -n "$viscomp" ]; then
	page=$man/viscomp.1.scd
	run_help viscomp "$T/viscomp.help" "$viscomp"
	help_options <"$T/viscomp.help" >"$T/viscomp.opts"
	man_options <"$page" >"$T/viscomp.doc"
	compare "$page" viscomp "$T/viscomp.opts" "$T/viscomp.doc" "$T/viscomp.doc"

	page=$man/viscompctl.1.scd
	run_help viscompctl "$T/vcc.help" "$viscompctl"
	sed '/^commands:/,$d' "$T/vcc.help" | help_options >"$T/vcc.opts"
	section "$page" '# OPTIONS' | man_options >"$T/vcc.doc"
	compare "$page" viscompctl "$T/vcc.opts" "$T/vcc.doc" "$T/vcc.doc"
	sed -n '/^commands:/,$p' "$T/vcc.help" | sed -n 's/^  \([a-z][a-z-]*\).*/\1/p' >"$T/vcc.cmds"
	[ -s "$T/vcc.cmds" ] || fail "\`viscompctl --help\` lists no command"
	section "$page" '# COMMANDS' | sed -n 's/^\*\([a-z][a-z-]*\)\*.*/\1/p' >"$T/vcc.terms"
	for c in $(comm -23 "$(sort -u "$T/vcc.cmds" >"$T/a"; echo "$T/a")" \
		"$(sort -u "$T/vcc.terms" >"$T/b"; echo "$T/b")"); do
		fail "$page: no *$c* term under '# COMMANDS' for \`viscompctl $c\`"
	done
	for c in $(comm -13 "$T/a" "$T/b"); do
		fail "$page: *$c* names no command that \`viscompctl --help\` lists"
	done
	for c in $(cat "$T/a"); do
		sed -n "/^commands:/,\$ { /^  $c /p; }" "$T/vcc.help" | help_options >"$T/c.line"
		section "$page" '# COMMANDS' | grep "^\*$c\*" | grep -oE '\*--?[A-Za-z][A-Za-z0-9-]*' |
			sed 's/^\*//' | sort -u >"$T/c.doc"
		cmp -s "$T/c.line" "$T/c.doc" ||
			fail "$page: the options of *$c* ($(echo $(cat "$T/c.doc"))) are not those" \
				"\`viscompctl --help\` prints ($(echo $(cat "$T/c.line")))"
	done
	checked=$((checked + 1))
fi

if [ "$failed" -gt 0 ]; then
	echo "$failed differences between the man pages and the programs"
	exit 1
fi
echo "the man pages match visd's, visctl's, libvisclient's and libvis's${viscomp:+, viscomp's and viscompctl's}" \
	"$checked help texts and API lists"
