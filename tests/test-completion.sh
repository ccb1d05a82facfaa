#!/usr/bin/env bash
# visctl's bash completion, sourced into this shell and called as readline would call it (it
# needs none of bash-completion's helpers): the commands are those `visctl --help` lists, each
# command's options those its --help prints, and a few values and file names complete.
# Usage: test-completion.sh VISCTL COMPLETION-FILE
set -u
visctl=${1:?usage: test-completion.sh VISCTL COMPLETION-FILE}
# shellcheck source=/dev/null
source "${2:?usage: test-completion.sh VISCTL COMPLETION-FILE}" || exit 1
T=$(mktemp -d "${TMPDIR:-/tmp}/visctl-completion.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

failed=0
passed=0

# comp WORD...: the completions, sorted, one a line, of the command line WORD... (the last word is
# the one being completed; an '=' is a word of its own, as readline splits it by default).
comp() {
	COMP_WORDS=("$@")
	COMP_CWORD=$(($# - 1))
	COMP_LINE="$*"
	COMP_POINT=${#COMP_LINE}
	COMPREPLY=()
	_visctl
	printf '%s\n' "${COMPREPLY[@]}" | sed '/^$/d' | sort
}

# expect WHAT EXPECTED WORD...: the completions of WORD... must be EXPECTED (words, any order).
expect() {
	local what=$1 want got
	want=$(printf '%s\n' $2 | sort)
	shift 2
	got=$(comp "$@")
	if [ "$got" = "$want" ]; then
		passed=$((passed + 1))
	else
		failed=$((failed + 1))
		echo "FAIL: $what: \`$*\` completes to [$(echo $got)], expected [$(echo $want)]"
	fi
}

# The option tokens of a help text (as check-man.sh reads them), one a line.
options() {
	sed 's/`[^`]*`//g' | tr -c 'A-Za-z0-9-' '\n' | grep -E '^(--[A-Za-z][A-Za-z0-9-]*|-[A-Za-z])$' |
		sort -u
}

"$visctl" --help >"$T/help" || exit 1
commands=$(sed -n 's/^  visctl \([a-z][a-z-]*\).*/\1/p' "$T/help")
expect "commands" "$commands help" visctl ""
expect "commands from a prefix" "resize region repaint raise" visctl r
expect "commands after global options" "script shape snapshot stack states stress sync" visctl -s /tmp/x \
	--role observer s
global=$(grep -v '^  visctl ' "$T/help" | options)
got=$(comp visctl -)
for o in $global; do
	if grep -qx -- "$o" <<<"$got"; then
		passed=$((passed + 1))
	else
		failed=$((failed + 1))
		echo "FAIL: global option $o, which \`visctl --help\` prints, does not complete"
	fi
done

# Each command's options are exactly those its --help prints (less the global ones), and --help.
for c in $commands; do
	"$visctl" "$c" --help | options | grep -vxF -e -s -e --socket -e --role >"$T/want"
	want=$( (cat "$T/want"; echo --help) | sort -u)
	expect "options of $c" "$want" visctl "$c" -
done

expect "--role values" "client manager observer" visctl --role ""
expect "--role=" "observer" visctl --role = ob
expect "--engine=" "gmv gmv-heap" visctl compute --engine = gm
expect "--engine VALUE" "auto brute gmv gmv-heap region" visctl compute --engine ""
expect "--engines list" "auto,gmv auto,gmv-heap" visctl bench --engines auto,g
expect "gen kinds" "cascade" visctl gen c
expect "stack mode" "above" visctl stack 7 a
expect "no completion for IDs" "" visctl map ""
expect "no completion for XIDs" "" visctl create 0 0 1 1 --x11 ""
expect "lookup's --x11 takes its XID" "" visctl lookup --x11 ""

mkdir "$T/scenes" && touch "$T/scenes/desk.scene" "$T/other"
expect "SCENE is a file" "$T/scenes/desk.scene" visctl compute --time "$T/scenes/d"
expect "SCENE after --engine VALUE" "$T/scenes" visctl compute --engine gmv "$T/sc"
expect "script FILE" "$T/other" visctl script "$T/o"
expect "--svg FILE" "$T/other" visctl snapshot --svg "$T/o"
expect "--svg=FILE" "$T/other" visctl snapshot --svg = "$T/o"
expect "--record FILE" "$T/other" visctl stress -c 4 --record "$T/o"
expect "stress --scene KIND" "tiles" visctl stress --scene t
expect "-s SOCKET" "$T/other" visctl -s "$T/o"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
