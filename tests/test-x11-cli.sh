#!/bin/bash
# What visd-x11 and visctl say about X, on a bare Xvfb (no window manager): visd-x11 --version
# names the protocol as every program does; a second bridge on the same visd is refused the
# manager role, and says so once, with what holds it; `visctl states --x11 --names` prints each
# X window's name and class as xwininfo -tree does, escaped, and as JSON; --names needs --x11
# and a display. A few seconds: no desktop, no window manager.
# Usage: test-x11-cli.sh BUILD-DIR VERSION. Exits 77 (skipped) without visd-x11, Xvfb or xlogo.
set -u
build=${1:?usage: test-x11-cli.sh BUILD-DIR VERSION}
version=${2:?}
bridge=$build/bridge/x11/visd-x11
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl

[ -x "$bridge" ] || { echo "$bridge not built: skipped"; exit 77; }
for prog in Xvfb xlogo; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed: skipped"; exit 77; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-x11-cli.XXXXXX") || exit 1
xpid= vpid= bpid= lpid=
cleanup() {
	for pid in $lpid $bpid $vpid $xpid; do kill "$pid" 2>/dev/null; done
	for pid in $lpid $bpid $vpid $xpid; do wait "$pid" 2>/dev/null; done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE
checks=0

fail() {
	echo "test-x11-cli: FAIL: $1"
	[ -n "${2:-}" ] && sed 's/^/  | /' "$2"
	exit 1
}

# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"

proto=$("$visd" --version | sed -nE 's/^visd [^ ]+ \(protocol ([0-9]+)\)$/\1/p')
out=$("$bridge" --version)
[ "$out" = "visd-x11 $version (protocol $proto)" ] ||
	fail "visd-x11 --version: '$out', want 'visd-x11 $version (protocol $proto)'"
checks=$((checks + 1))

# --names is refused before anything connects: without --x11, and without a display.
"$visctl" -s "$dir/none" states --names >"$dir/out" 2>&1
[ $? -eq 2 ] && grep -qF "states: --names goes with --x11" "$dir/out" ||
	fail "states --names without --x11" "$dir/out"
checks=$((checks + 1))

exec 3>"$dir/display"
Xvfb -displayfd 3 -screen 0 800x600x24 -nolisten tcp -noreset >"$dir/xvfb.log" 2>&1 &
xpid=$!
exec 3>&-
wait_progress "$xpid" test -s "$dir/display" || fail "Xvfb did not start ($progress_why)" "$dir/xvfb.log"
export DISPLAY=:$(head -n 1 "$dir/display")
"$visd" --socket "$dir/sock" --screen 800x600 2>"$dir/visd.log" &
vpid=$!
wait_progress "$vpid" test -S "$dir/sock" || fail "visd did not start ($progress_why)" "$dir/visd.log"
"$bridge" -s "$dir/sock" -v 2>"$dir/bridge.log" &
bpid=$!
wait_progress "$bpid $vpid $xpid" grep -q 'mirrored' "$dir/bridge.log" ||
	fail "visd-x11 did not start ($progress_why)" "$dir/bridge.log"

# A second bridge: refused the manager role, said once (it was said twice), with what holds it.
"$bridge" -s "$dir/sock" >"$dir/out" 2>&1
rc=$?
[ $rc -eq 1 ] || fail "a second visd-x11 exited $rc, not 1" "$dir/out"
[ "$(grep -o 'the manager role is taken' "$dir/out" | wc -l)" -eq 1 ] &&
	grep -qF "(another visd-x11, or another manager, is connected to this visd" "$dir/out" ||
	fail "a second visd-x11's message" "$dir/out"
checks=$((checks + 1))

# A window with a name that needs escaping, and its class.
xlogo -name 'my "logo"' -geometry 100x100+10+10 >/dev/null 2>&1 &
lpid=$!
named() {
	"$visctl" -s "$dir/sock" states --x11 --names >"$dir/names" 2>"$dir/err" &&
		grep -q '"my \\"logo\\""' "$dir/names"
}
wait_progress "$lpid $bpid $vpid" named ||
	fail "states --x11 --names never named xlogo's window ($progress_why): $(cat "$dir/err")" \
		"$dir/names"
xid=$(xwininfo -name 'my "logo"' 2>/dev/null | sed -nE 's/.*Window id: (0x[0-9a-f]+).*/\1/p')
[ -n "$xid" ] || xid=$(sed -nE 's/^(0x[0-9a-f]+) .*"my.*/\1/p' "$dir/names")
grep -qxE "$xid (unobscured|partially-obscured|fully-obscured) \"my \\\\\"logo\\\\\"\" \\(\"my \\\\\"logo\\\\\"\" \"XLogo\"\\)" \
	"$dir/names" || fail "states --x11 --names: no line for $xid as xwininfo -tree has it" "$dir/names"
# Every line is XID STATE NAME CLASS; a window without a name or class says so.
grep -vqE '^0x[0-9a-f]+ [a-z-]+ ("([^"\\]|\\.)*"|\(has no name\)) \(("([^"\\]|\\.)*" "([^"\\]|\\.)*")?\)$' \
	"$dir/names" && fail "states --x11 --names: a line out of form" "$dir/names"
# The same windows as without --names, in the same order.
"$visctl" -s "$dir/sock" states --x11 >"$dir/plain" || fail "states --x11" "$dir/plain"
cut -d' ' -f1,2 "$dir/names" | cmp -s - "$dir/plain" ||
	fail "states --x11 --names lists other windows than states --x11" "$dir/names"
checks=$((checks + 1))
"$visctl" -s "$dir/sock" states --x11 --names --json >"$dir/json" ||
	fail "states --x11 --names --json" "$dir/json"
grep -qF "{\"x11\":\"$xid\"," "$dir/json" &&
	grep -qF ',"name":"my \"logo\"","class":["my \"logo\"","XLogo"]}' "$dir/json" ||
	fail "states --x11 --names --json: no object for $xid with its name and class" "$dir/json"
checks=$((checks + 1))
# No display: a runtime error naming it.
DISPLAY= "$visctl" -s "$dir/sock" states --x11 --names >"$dir/out" 2>&1
[ $? -eq 1 ] && grep -qF "states: --names: cannot connect to the X display" "$dir/out" ||
	fail "states --x11 --names without a display" "$dir/out"
checks=$((checks + 1))
echo "x11-cli: $checks passed, 0 failed"
