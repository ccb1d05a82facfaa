#!/bin/sh
# The visctl command line: exit statuses, error messages, output format, and agreement of the
# engines on generated scenes. Usage: test-cli.sh PATH-TO-VISCTL
set -u

V=${1:?usage: test-cli.sh PATH-TO-VISCTL}
T=$(mktemp -d "${TMPDIR:-/tmp}/visctl-cli.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT
trap 'exit 1' INT TERM HUP

passed=0
failed=0

pass() {
	passed=$((passed + 1))
}

fail() {
	failed=$((failed + 1))
	echo "FAIL: $*"
	if [ -s "$T/err" ]; then
		echo "  stderr:"
		sed 's/^/    /' "$T/err" | head -n 10
	fi
	if [ -s "$T/out" ]; then
		echo "  stdout:"
		sed 's/^/    /' "$T/out" | head -n 10
	fi
}

# scene NAME FORMAT: writes printf FORMAT (so \n, \r, \t work) to $T/NAME and prints the path.
scene() {
	printf "$2" >"$T/$1"
	echo "$T/$1"
}

# run ARGS...: runs visctl with stdout in $T/out, stderr in $T/err, the status in $rc.
run() {
	"$V" "$@" >"$T/out" 2>"$T/err"
	rc=$?
}

# expect_fail WHAT STATUS MESSAGE ARGS...: the command must exit STATUS, print nothing on stdout
# and say MESSAGE (a fixed string) on stderr.
expect_fail() {
	what=$1 status=$2 msg=$3
	shift 3
	run "$@"
	if [ "$rc" -ne "$status" ]; then
		fail "$what: exit status $rc, expected $status"
	elif [ -s "$T/out" ]; then
		fail "$what: wrote to stdout"
	elif ! grep -qF -- "$msg" "$T/err"; then
		fail "$what: stderr lacks '$msg'"
	else
		pass
	fi
}

# bad_scene WHAT CONTENT LINE REASON: compute must reject the scene with FILE:LINE: REASON.
bad_scene() {
	f=$(scene bad.scene "$2")
	expect_fail "$1" 2 "$f:$3: $4" compute "$f"
}

# expect_out WHAT EXPECTED ARGS...: the command must succeed and print exactly EXPECTED (printf).
expect_out() {
	what=$1
	printf "$2" >"$T/expected"
	shift 2
	run "$@"
	if [ "$rc" -ne 0 ]; then
		fail "$what: exit status $rc"
	elif ! cmp -s "$T/out" "$T/expected"; then
		fail "$what: unexpected output"
		echo "  expected:"
		sed 's/^/    /' "$T/expected" | head -n 10
	else
		pass
	fi
}

# --- bad scenes -------------------------------------------------------------------------------
bad_scene "unknown record" 'screen 10 10\nfoo 1 2\n' 2 "unknown record 'foo'"
bad_scene "missing field" '# c\nwindow 1 0 0 5\n' 2 "window: expected 5 fields (ID X Y W H), got 4"
bad_scene "extra field" 'window 1 0 0 5 5 5\n' 1 "window: expected 5 fields (ID X Y W H), got 6"
bad_scene "screen field count" 'screen 10\n' 1 "screen: expected 2 fields (W H), got 1"
bad_scene "non-number" '\n\nwindow 1 12a 0 5 5\n' 3 "window: X '12a' is not a number"
bad_scene "plus sign" 'window 1 +1 0 5 5\n' 1 "window: X '+1' is not a number"
bad_scene "hex" 'window 0x10 1 0 5 5\n' 1 "window: ID '0x10' is not a number"
bad_scene "X too large" 'window 1 2147483648 0 5 5\n' 1 \
	"window: X 2147483648 out of range -2147483648..2147483647"
bad_scene "Y too small" 'window 1 0 -2147483649 5 5\n' 1 \
	"window: Y -2147483649 out of range -2147483648..2147483647"
bad_scene "ID too large" 'window 4294967296 0 0 5 5\n' 1 \
	"window: ID 4294967296 out of range 0..4294967295"
bad_scene "W zero" 'window 1 0 0 0 5\n' 1 "window: W 0 out of range 1..2147483647"
bad_scene "H negative" 'window 1 0 0 5 -1\n' 1 "window: H -1 out of range 1..2147483647"
bad_scene "screen zero" 'screen 0 10\n' 1 "screen: W 0 out of range 1..2147483647"
bad_scene "duplicate ID" 'window 7 0 0 5 5\nwindow 8 0 0 5 5\nwindow 7 1 1 5 5\n' 3 \
	"duplicate window ID 7 (first on line 1)"
bad_scene "screen twice" 'screen 10 10\nscreen 10 10\n' 2 "screen given twice (first on line 1)"
bad_scene "screen after window" 'window 1 0 0 5 5\nscreen 10 10\n' 2 "screen after a window"
bad_scene "NUL byte" 'window 1 0 0 5 5\nwindow 2\0000 0 5 5\n' 2 "NUL byte in input"
bad_scene "error after CRLF lines" 'window 1 0 0 5 5\r\nwindow 2 0 0 5\r\n' 2 \
	"window: expected 5 fields (ID X Y W H), got 4"

# A bad scene on stdin is named <stdin>.
printf 'window 1 0 0 5 5\nbogus\n' >"$T/stdin.scene"
"$V" compute - <"$T/stdin.scene" >"$T/out" 2>"$T/err"
rc=$?
if [ "$rc" -eq 2 ] && [ ! -s "$T/out" ] && grep -qF "<stdin>:2: unknown record 'bogus'" "$T/err"
then pass; else fail "bad scene on stdin (status $rc)"; fi

# --- unreadable files and bad usage -----------------------------------------------------------
expect_fail "nonexistent file" 1 "visctl: $T/nope: cannot read: No such file or directory" \
	compute "$T/nope"
mkdir "$T/dir"
expect_fail "directory" 1 "visctl: $T/dir: cannot read: Is a directory" compute "$T/dir"
good=$(scene good.scene 'screen 100 100\nwindow 5 0 0 10 10\nwindow 2 5 5 10 10\nwindow 9 200 200 5 5\n')
# --json: the same records as objects, one a line.
json=$("$V" compute --json "$good") && text=$("$V" compute "$good") &&
	[ "$json" = "$(echo "$text" | sed 's/^\([0-9]*\) \(.*\)$/{"window":\1,"state":"\2"}/')" ] &&
	[ "$("$V" compute --json --visible "$good")" = "$("$V" compute --visible "$good" |
		sed 's/^.*$/{"window":&}/')" ] && pass || fail "compute --json: $json"
expect_fail "bad engine" 2 "unknown engine 'fast'" compute --engine=fast "$good"
expect_fail "bad engine, separate" 2 "unknown engine 'fast'" compute --engine fast "$good"
expect_fail "engine without name" 2 "--engine needs an engine name" compute "$good" --engine
expect_fail "unknown option" 2 "unknown option '--bogus'" compute --bogus "$good"
expect_fail "missing SCENE" 2 "missing SCENE" compute --visible
expect_fail "two SCENEs" 2 "unexpected argument" compute "$good" "$good"
expect_fail "no command" 2 "usage: visctl"
expect_fail "unknown command" 2 "unknown command 'frobnicate'" frobnicate
expect_fail "unknown global option" 2 "unknown option '--frob'" --frob
expect_fail "gen unknown kind" 2 "unknown kind 'spiral'" gen spiral 10 1
expect_fail "gen bad N" 2 "N '1x' is not a number" gen random 1x 1
expect_fail "gen N too large" 2 "N '100000001' is not a number" gen random 100000001 1
expect_fail "gen bad SEED" 2 "SEED '-1' is not a number" gen random 10 -1
expect_fail "gen SEED overflow" 2 "SEED '18446744073709551616'" gen random 10 18446744073709551616
expect_fail "gen missing H" 2 "expected KIND N SEED [W H]" gen random 10 1 100
expect_fail "gen W zero" 2 "W '0' is not a number" gen random 10 1 0 100
expect_fail "gen too few" 2 "expected KIND N SEED [W H]" gen random

run help
if [ "$rc" -eq 0 ] && grep -q "visctl compute" "$T/out"; then pass; else fail "help"; fi
run --help
if [ "$rc" -eq 0 ] && grep -q "visctl gen" "$T/out"; then pass; else fail "--help"; fi
run compute --help
if [ "$rc" -eq 0 ] && grep -q "usage: visctl compute" "$T/out"; then pass; else fail "compute --help"; fi

# --- live commands: usage errors come before connecting (the socket does not exist) -----------
N="$T/no-daemon"
live_usage() {
	what=$1 msg=$2
	shift 2
	expect_fail "$what" 2 "$msg" -s "$N" "$@"
}
live_usage "create too few" "create: expected X Y W H, got 3 arguments" create 1 2 3
live_usage "create bad X" "X 'a' is not a number from -2147483648 to 2147483647" create a 0 1 1
live_usage "create X too large" "X '2147483648' is not a number from -2147483648 to 2147483647" create 2147483648 0 1 1
live_usage "create bad W" "W '-1' is not a number from 1 to 2147483647" create 0 0 -1 1
live_usage "create unknown option" "unknown option '--frob'" create 0 0 1 1 --frob
live_usage "create --parent without ID" "--parent needs an ID" create 0 0 1 1 --parent
live_usage "create bad parent" "parent ID 'x' is not a number from 0 to 4294967295" create 0 0 1 1 --parent=x
live_usage "create usage line" "usage: visctl create X Y W H" create
live_usage "map without ID" "map: expected ID, got 0 arguments" map
live_usage "map bad ID" "ID 'x' is not a number from 0 to 4294967295" map x
live_usage "destroy ID too large" "ID '4294967296' is not a number from 0 to 4294967295" destroy 4294967296
live_usage "unmap two IDs" "expected ID, got 2 arguments" unmap 1 2
live_usage "raise option" "unknown option '--top'" raise --top 1
live_usage "lower without ID" "lower: expected ID" lower
live_usage "move too few" "move: expected ID X Y, got 2 arguments" move 1 2
live_usage "move bad Y" "Y '1.5' is not a number from -2147483648 to 2147483647" move 1 2 1.5
live_usage "create W too large" "W '99999999999' is not a number from 1 to 2147483647" create 0 0 99999999999 1
live_usage "create W past 2^31" "W '2147483648' is not a number from 1 to 2147483647" create 0 0 2147483648 1
live_usage "resize H zero" "H '0' is not a number from 1 to 2147483647" resize 1 2 0
live_usage "resize negative H" "H '-3' is not a number from 1 to 2147483647" resize 1 2 -3
live_usage "stack bad mode" "expected above or below, got 'beside'" stack 1 beside 2
live_usage "stack bad sibling" "ID 'top' is not a number from 0 to 4294967295" stack 1 above top
live_usage "states argument" "states: unexpected argument 'extra'" states extra
live_usage "tree argument" "tree: unexpected argument '1'" tree 1
live_usage "sync argument" "sync: unexpected argument 'now'" sync now
live_usage "region without ID" "region: expected ID, got 0 arguments" region
live_usage "repaint too few" "repaint: expected X Y W H, got 3 arguments" repaint 0 0 1
live_usage "snapshot without --svg" "snapshot: missing --svg FILE" snapshot
live_usage "snapshot --svg without FILE" "snapshot: --svg needs a FILE" snapshot --svg
live_usage "snapshot argument" "snapshot: unexpected argument 'x'" snapshot --svg "$T/s.svg" x
live_usage "load without SCENE" "load: missing SCENE" load
live_usage "load two SCENEs" "unexpected argument" load "$good" "$good"
live_usage "load unknown option" "unknown option '--map'" load --map "$good"
expect_fail "load missing file" 1 "visctl: $T/nope: cannot read: No such file or directory" \
	-s "$N" load "$T/nope"
f=$(scene bad-load.scene 'window 1 0 0 5 5\nwindow 2 0 0 5\n')
live_usage "load bad scene" "$f:2: window: expected 5 fields (ID X Y W H), got 4" load --retain "$f"
live_usage "watch --count 0" "N '0' is not a number from 1 to 4294967295" watch --count 0
live_usage "watch --count without N" "--count needs a number" watch --count
live_usage "watch bad ID" "ID 'x' is not a number from 1 to 4294967295" watch --json x
live_usage "watch ID 0" "ID '0' is not a number from 1 to 4294967295" watch 0
live_usage "watch unknown option" "unknown option '--all'" watch --all
# External IDs: --x11 takes an XID (hex or decimal, 1 to 0xffffffff), --external NS:TAG.
live_usage "create --x11 without XID" "--x11 needs an XID" create 0 0 1 1 --x11
live_usage "create --x11 bad XID" "XID 'zz' is not an X window ID from 0x1 to 0xffffffff" create 0 0 1 1 --x11 zz
live_usage "create --x11 XID 0" "XID '0x0' is not an X window ID" create 0 0 1 1 --x11 0x0
live_usage "create --x11 past 32 bits" "XID '0x100000000' is not an X window ID" create 0 0 1 1 --x11=0x100000000
live_usage "create --external without colon" "external ID '7' is not NS:TAG" create 0 0 1 1 --external 7
live_usage "create --external NS 0" "external ID '0:5' is not NS:TAG" create 0 0 1 1 --external 0:5
live_usage "create --external TAG past 64 bits" "external ID '2:0x10000000000000000' is not NS:TAG" create 0 0 1 1 --external 2:0x10000000000000000
live_usage "create two external IDs" "one external ID at most" create 0 0 1 1 --x11 5 --external 2:5
live_usage "lookup nothing" "lookup: expected --x11 XID or NS TAG, got 0 arguments" lookup
live_usage "lookup NS alone" "expected --x11 XID or NS TAG, got 1 arguments" lookup 1
live_usage "lookup NS 0" "NS '0' is not a number from 1 to 4294967295" lookup 0 5
live_usage "lookup bad TAG" "TAG '0xg' is not a 64-bit number" lookup 1 0xg
live_usage "lookup --x11 and more" "unexpected argument '5' after --x11" lookup --x11 0x1e00003 5
live_usage "lookup --x11 without XID" "--x11 needs an XID" lookup --x11
live_usage "lookup unknown option" "unknown option '--all'" lookup --all
live_usage "states --x11 argument" "states: unexpected argument 'x'" states --x11 x
live_usage "watch --x11 bad XID" "XID '12ab' is not an X window ID" watch --x11 12ab
live_usage "watch --x11 XID 0" "XID '0' is not an X window ID" watch 0 --x11
live_usage "script without FILE" "script: expected FILE|-, got 0 arguments" script
expect_fail "script missing file" 1 "visctl: $T/nope: cannot read" -s "$N" script "$T/nope"
f=$(scene bad1.script '# comment\n\nfrob 1\n')
live_usage "script unknown command" "$f:3: unknown command 'frob'" script "$f"
f=$(scene bad2.script '  # comment\nmap\n')
live_usage "script usage error" "$f:2: map: expected ID, got 0 arguments" script "$f"
f=$(scene bad3.script '# no global options\n-s /tmp/x sync\n')
live_usage "script global option" "$f:2: global options such as '-s'" script "$f"
f=$(scene bad4.script 'compute x\n')
live_usage "script offline command" "$f:1: 'compute' cannot be used in a script" script "$f"
live_usage "script stress" "$(scene bad5.script 'stress\n'):1: 'stress' cannot be used in a script" \
	script "$T/bad5.script"
live_usage "stress bad -c" "-c 'x' is not a number in 0..1000" stress -c x
live_usage "stress -c too many" "-c '1001' is not a number in 0..1000" stress -c 1001
live_usage "stress -n 0" "-n '0' is not a number in 1..1000000" stress -n 0
live_usage "stress --count 0" "--count '0' is not a positive number" stress --count 0
live_usage "stress bad duration" "--duration '-1' is not a positive number" stress --duration -1
live_usage "stress bad rate" "-R 'fast' is not a positive rate" stress -R fast
live_usage "stress --pipeline 0" "--pipeline '0' is not a number" stress --pipeline 0
live_usage "stress unknown kind" "--mix: unknown kind 'spin'" stress --mix move=1,spin=2
live_usage "stress bad weight" "--mix: weight 'x' is not a number" stress --mix move=x
live_usage "stress zero mix" "gives every kind weight 0" stress --mix move=0
live_usage "stress scene with looks" "--scene 'shaped' is not random, uniform, grid, cascade," \
	stress --scene shaped
live_usage "stress json and csv" "--json and --csv exclude each other" stress --json --csv
live_usage "stress unknown option" "unknown option '--frob'" stress --frob
live_usage "stress -c without value" "-c needs a value" stress -c
live_usage "stress argument" "unexpected argument 'now'" stress now
live_usage "stress record unwritable" "$T/no/such: cannot write" stress --record "$T/no/such"
printf 'visctl sync\n' | "$V" -s "$N" script - >"$T/out" 2>"$T/err"
rc=$?
if [ "$rc" -eq 2 ] && grep -qF "<stdin>:1: unknown command 'visctl'" "$T/err"; then pass
else fail "script from stdin (status $rc)"; fi
expect_fail "unknown role" 2 "unknown role 'admin'" --role admin states
expect_fail "-s without SOCKET" 2 "-s needs a value" -s
expect_fail "global options without command" 2 "usage: visctl" -s "$N"

# --- live commands without a daemon: exit 1, naming the socket --------------------------------
expect_fail "missing socket" 1 "$N" -s "$N" sync
expect_fail "missing socket, manager" 1 "$N" -s "$N" --role=manager states
expect_fail "snapshot without daemon" 1 "$N" -s "$N" snapshot --svg "$T/s.svg"
# The roles the usage names are the daemon's three (VIS_ROLE_*), each accepted: it once named
# observer|manager alone. stress, which takes its own roles, says which.
roles=$("$V" --help | sed -n 's/^usage: visctl .*--role \([a-z|]*\).*/\1/p')
if [ "$roles" = "client|observer|manager" ]; then pass
else fail "visctl --help names the roles '$roles', not client|observer|manager"; fi
for r in client observer manager; do
	expect_fail "missing socket, role $r" 1 "$N" -s "$N" --role "$r" sync
done
"$V" stress --help >"$T/out" 2>"$T/err"
if grep -q 'manager role' "$T/out" && grep -q 'observer role' "$T/out" &&
	grep -q 'ignores --role' "$T/out"; then pass
else fail "visctl stress --help does not name the roles it takes"; fi
env -u VISD_SOCKET -u XDG_RUNTIME_DIR "$V" sync >"$T/out" 2>"$T/err"
rc=$?
if [ "$rc" -eq 1 ] && grep -qF "set VISD_SOCKET or XDG_RUNTIME_DIR" "$T/err"; then pass
else fail "no socket variables (status $rc)"; fi
VISD_SOCKET="$N" "$V" sync >"$T/out" 2>"$T/err"
rc=$?
if [ "$rc" -eq 1 ] && grep -qF "$N" "$T/err"; then pass; else fail "VISD_SOCKET (status $rc)"; fi
expect_fail "stress without daemon" 1 "$N" -s "$N" stress
f=$(scene ok.script '# creates nothing before the failure\nmap 1\n')
expect_fail "script without daemon" 1 "$f:2: " -s "$N" script "$f"

# --- good scenes ------------------------------------------------------------------------------
states='2 unobscured\n5 partially-obscured\n9 fully-obscured\n'
expect_out "output in ascending ID order" "$states" compute "$good"
expect_out "--visible" '2\n5\n' compute --visible "$good"
expect_out "options after SCENE" '2\n5\n' compute "$good" --visible --engine brute
expect_out "-- ends options" "$states" compute --engine=region -- "$good"
expect_out "stdin" "$states" compute - <"$good"

run compute --time "$good"
if [ "$rc" -eq 0 ] && grep -qE '^compute_ms=[0-9]+\.[0-9]{3}$' "$T/err" &&
	[ "$(wc -l <"$T/err")" -eq 1 ] && [ "$(cat "$T/out")" = "$(printf "$states")" ]
then pass; else fail "--time"; fi

f=$(scene crlf.scene 'screen 100 100\r\nwindow 5 0 0 10 10\r\n\r\nwindow 2 5 5 10 10\r\nwindow 9 200 200 5 5\r\n')
expect_out "CRLF" "$states" compute "$f"
f=$(scene comments.scene '# a scene\n  \n\tscreen\t100 100 # the screen\nwindow 5 0 0 10 10#x\n# window 3 0 0 1 1\nwindow 2 5 5 10 10\n\nwindow 9 200 200 5 5')
expect_out "comments, blanks, tabs, no final newline" "$states" compute "$f"
f=$(scene empty.scene '')
expect_out "empty scene" '' compute "$f"
f=$(scene comment-only.scene '# nothing\n\n')
expect_out "comment-only scene" '' compute --visible "$f"
f=$(scene noscreen.scene 'window 3 -100 -100 50 50\nwindow 1 -90 -90 10 10\n')
expect_out "no screen, negative coordinates" '1 unobscured\n3 partially-obscured\n' compute "$f"

# A full disk is a runtime error (1), not bad input.
if [ -w /dev/full ]; then
	"$V" compute "$good" >/dev/full 2>"$T/err"
	rc=$?
	if [ "$rc" -eq 1 ] && grep -q "visctl: write error:" "$T/err"; then pass
	else fail "write error to /dev/full (status $rc)"; fi
fi

# --- pictures: compute --svg ------------------------------------------------------------------
# valid_svg FILE: well-formed XML (xmllint where installed; else the document's outline).
valid_svg() {
	if command -v xmllint >/dev/null 2>&1; then
		xmllint --noout "$1" 2>"$T/err"
		return
	fi
	head -n 1 "$1" | grep -q '^<?xml ' && grep -q '^<svg xmlns="http://www.w3.org/2000/svg"' "$1" &&
		[ "$(tail -n 1 "$1")" = '</svg>' ] &&
		[ "$(grep -c '<g[ >]' "$1")" -eq "$(grep -c '</g>' "$1")" ]
}

# The states on stdout are exactly those without --svg; the picture names every window.
run compute --svg "$T/good.svg" "$good"
if [ "$rc" -eq 0 ] && [ "$(cat "$T/out")" = "$(printf "$states")" ] && [ ! -s "$T/err" ]; then pass
else fail "compute --svg: status $rc or different output"; fi
if valid_svg "$T/good.svg"; then pass; else fail "compute --svg: not well-formed"; fi
# Window 9 lies far off the 100x100 screen: the note under the legend names it.
if grep -q '<title>5: 0,0 10×10, partially-obscured</title>' "$T/good.svg" &&
	grep -q '<title>2: 5,5 10×10, unobscured</title>' "$T/good.svg" &&
	grep -q 'Outside the picture: 9\.' "$T/good.svg"; then pass
else fail "compute --svg: windows missing from the picture"; fi
expect_out "--svg=FILE, --visible" '2\n5\n' compute --visible --svg="$T/good2.svg" "$good"

f=$(scene desk.scene 'screen 1000 600\nwindow 10 0 0 400 300\nwindow 12 250 150 50 50\nwindow 11 200 100 400 300\nwindow 13 700 300 200 200\nwindow 14 -100 500 300 200\n')
run compute --svg "$T/desk.svg" "$f"
ids_ok=true
for id in 10 11 12 13 14; do
	grep -q "<title>$id: " "$T/desk.svg" && grep -q ">$id</text>" "$T/desk.svg" || ids_ok=false
done
if [ "$rc" -eq 0 ] && valid_svg "$T/desk.svg" && $ids_ok; then pass
else fail "compute --svg: a label or tooltip is missing (status $rc)"; fi
# Window 12 is fully obscured: a dashed outline, no fill.
if grep -q '<rect class="f" ' "$T/desk.svg" && [ "$(grep -c '<path class="v' "$T/desk.svg")" -eq 4 ]
then pass; else fail "compute --svg: fills or outlines"; fi

expect_fail "--svg unwritable" 1 "visctl compute: $T/nodir/x.svg: cannot write: No such file or directory" \
	compute --svg "$T/nodir/x.svg" "$good"
expect_fail "--svg without FILE" 2 "--svg needs a FILE" compute "$good" --svg
expect_fail "--svg empty" 2 "empty --svg FILE" compute --svg= "$good"
if [ -w /dev/full ]; then
	"$V" compute --svg /dev/full "$good" >/dev/null 2>"$T/err"
	rc=$?
	if [ "$rc" -eq 1 ] && grep -qF "visctl compute: /dev/full: write error:" "$T/err"; then pass
	else fail "--svg to /dev/full (status $rc)"; fi
fi

# Huge scenes still give a valid file, without labels; fragmented ones without fills.
"$V" gen random 6000 1 >"$T/big.scene"
run compute --svg "$T/big.svg" "$T/big.scene"
if [ "$rc" -eq 0 ] && valid_svg "$T/big.svg" && grep -q '<!-- 6000 windows: no labels' "$T/big.svg" &&
	! grep -q '<text class="l' "$T/big.svg"; then pass
else fail "compute --svg on 6000 windows (status $rc)"; fi
"$V" gen grid 3000 1 >"$T/grid.scene"
run compute --svg "$T/grid.svg" "$T/grid.scene"
if [ "$rc" -eq 0 ] && valid_svg "$T/grid.svg" && grep -q 'Visible parts not drawn' "$T/grid.svg" &&
	! grep -q '<path class="v' "$T/grid.svg"; then pass
else fail "compute --svg on the 3000-window grid (status $rc)"; fi

# --- generated scenes: determinism and every engine agreeing with the brute force -------------
for kind in random uniform grid cascade tiles nested; do
	if ! "$V" gen "$kind" 150 7 >"$T/gen1" 2>"$T/err" || ! "$V" gen "$kind" 150 7 >"$T/gen2"; then
		fail "gen $kind failed"
		continue
	fi
	if cmp -s "$T/gen1" "$T/gen2" && [ "$(grep -c '^window ' "$T/gen1")" -eq 150 ]; then pass
	else fail "gen $kind: not deterministic or not 150 windows"; fi

	if ! "$V" compute --engine=brute "$T/gen1" >"$T/brute" 2>"$T/err"; then
		fail "compute --engine=brute on gen $kind"
		continue
	fi
	for engine in auto gmv gmv-heap region; do
		if "$V" compute --engine="$engine" "$T/gen1" >"$T/out" 2>"$T/err" &&
			cmp -s "$T/out" "$T/brute"; then pass
		else fail "engine $engine differs from brute on gen $kind 150 7"; fi
	done
done

"$V" gen random 3 5 1000 800 >"$T/out" 2>"$T/err"
if [ "$(head -n 1 "$T/out")" = "screen 1000 800" ]; then pass; else fail "gen with screen size"; fi
expect_out "gen 0 windows" 'screen 3840 2160\n' gen random 0 1

# --- visctl bench --family: scenes drawn from the family, every engine agreeing ----------------
run bench --family 6 --min-n 50 --max-n 400 --quick --seed 3 --csv "$T/family.csv"
if [ "$rc" -eq 0 ] && grep -q '^| auto | ' "$T/out" && grep -q '^| region | ' "$T/out" &&
	grep -q '^  gmv-heap: scene [0-9]*, .*n=[0-9]* ' "$T/out" &&
	[ "$(grep -c '^[0-9]*,"n=' "$T/family.csv")" -eq 6 ]; then pass
else fail "bench --family: status $rc, table or CSV wrong"; fi
expect_fail "bench --family 0" 2 "bad number '0'" bench --family 0
expect_fail "bench --min-n over --max-n" 2 "--min-n 500 is over --max-n 400" \
	bench --family 2 --min-n 500 --max-n 400
expect_fail "bench --family with --svg" 2 "--svg plots the kinds" \
	bench --family 2 --svg "$T/x.svg"

# --- visctl plot-service: the service benchmark's plot from a fixed CSV -----------------------
f=$(scene service.csv 'run,windows,clients,p50_us,p99_us,p999_us,ok\nlatency,1000,1,60.1,110.5,150.2,1\nthroughput,1000,1,900,1500,1600,1\nlatency,100,1,33.0,78.8,104.3,1\nlatency,100,10,36.4,191.5,216.8,1\nlatency,1000,10,60.4,217.1,244.2,1\n')
run plot-service --note "a <note> & more" "$f" "$T/service.svg"
if [ "$rc" -eq 0 ] && [ ! -s "$T/out" ] && valid_svg "$T/service.svg"; then pass
else fail "plot-service: status $rc or not well-formed"; fi
# Two panels of three lines (p50, p99, p99.9); the throughput row is not drawn.
if [ "$(grep -c '<polyline' "$T/service.svg")" -eq 6 ] &&
	grep -q '>10 subscribers<' "$T/service.svg" && grep -q 'a &lt;note&gt; &amp; more' "$T/service.svg" &&
	[ "$(grep -c '<circle' "$T/service.svg")" -eq 15 ]; then pass
else fail "plot-service: panels, lines or markers wrong"; fi
f=$(scene nocol.csv 'run,windows,p50_us,p99_us,p999_us\nlatency,100,1,2,3\n')
expect_fail "plot-service without clients" 2 "no column 'clients'" plot-service "$f" "$T/x.svg"
f=$(scene norows.csv 'run,windows,clients,p50_us,p99_us,p999_us\nthroughput,100,1,1,2,3\n')
expect_fail "plot-service without latency rows" 2 'no closed-loop ("latency") rows' \
	plot-service "$f" "$T/x.svg"
f=$(scene badrow.csv 'run,windows,clients,p50_us,p99_us,p999_us\nlatency,100,1,1,2,3\nlatency,0,1,1,2,3\n')
expect_fail "plot-service bad row" 2 "badrow.csv:3: bad windows, clients or latency" \
	plot-service "$f" "$T/x.svg"
expect_fail "plot-service missing SVG" 2 "usage: visctl plot-service" plot-service "$f"
expect_fail "plot-service unwritable" 1 "$T/nodir/x.svg: cannot write" \
	plot-service "$T/service.csv" "$T/nodir/x.svg"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
