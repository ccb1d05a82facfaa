#!/usr/bin/env bash
# visctl's live subcommands against a real visd on a private socket: the daemon's states equal
# `visctl compute` on the same scene; scripts, watch, exit codes; visd's own start-up errors.
# Usage: test-live.sh VISD VISCTL PROJECT-VERSION
set -uo pipefail
visd=$1
visctl=$2
version=$3
dir=$(mktemp -d /tmp/visd-live-XXXXXX)
sock=$dir/sock
pid=
cleanup() {
	[ -n "$pid" ] && kill "$pid" 2>/dev/null
	rm -rf "$dir"
}
trap cleanup EXIT
failures=0
fail() {
	echo "FAIL: $*" >&2
	failures=$((failures + 1))
}
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"
# Waits for a socket to appear at $2, as long as the process $1 (visd) works.
wait_socket() { wait_progress "$1" test -S "$2"; }

"$visd" --socket "$sock" --screen 3840x2160 2>"$dir/visd.log" &
pid=$!
wait_socket "$pid" "$sock"
[ -S "$sock" ] || { echo "visd did not start" >&2; cat "$dir/visd.log" >&2; exit 1; }
v() { "$visctl" -s "$sock" "$@"; }

# The key property, through the command line: load a scene, read the states back. Shaped and
# translucent scenes go through load's second batch, which gives the windows their looks; at 60
# windows, several of their states depend on those looks.
for spec in "random 300 7" "tiles 300 7" "cascade 300 7" "shaped 60 4" "shaped 60 10" \
	"translucent 60 9" "translucent 60 10"; do
	set -- $spec
	kind=$1
	"$visctl" gen $kind "$2" "$3" >"$dir/scene" || fail "gen $kind"
	v load --retain --json "$dir/scene" |
		sed 's/^{"scene_id":\([0-9]*\),"window":\([0-9]*\)}$/\1 \2/' >"$dir/map" ||
		fail "load --json $kind"
	[ "$(wc -l <"$dir/map")" -eq "$2" ] || fail "load $kind printed $(wc -l <"$dir/map") lines"
	"$visctl" compute "$dir/scene" >"$dir/want.scene-ids" || fail "compute $kind"
	awk 'NR == FNR { id[$1] = $2; next } { print id[$1], $2 }' "$dir/map" "$dir/want.scene-ids" |
		sort -n >"$dir/want"
	v --role observer states | sort -n >"$dir/got.all"
	# Earlier scenes' windows are still there (retained): compare only this scene's.
	awk 'NR == FNR { mine[$2] = 1; next } ($1 in mine)' "$dir/map" "$dir/got.all" >"$dir/got"
	cmp -s "$dir/want" "$dir/got" || fail "$kind: daemon states differ from visctl compute"
	# Clear the screen for the next scene.
	cut -d' ' -f2 "$dir/map" | sed 's/^/destroy /' >"$dir/clear"
	v --role manager script "$dir/clear" || fail "clearing $kind"
done
[ -z "$(v --role observer states)" ] || fail "windows left after clearing"

# Looks through the command line: create --border and --input-only, border, shape, opaque (in a
# script's batch too), read back by tree; states as visctl compute has them for the same scene.
cat >"$dir/looks.script" <<'EOF2'
create 100 100 200 100 --map --retain
create 150 120 50 50 --map --retain --border 3
create 0 0 400 400 --map --retain --input-only
create 300 100 100 100 --map --retain
batch-begin
shape @4 0,0,50,100
opaque @1 10,10,180,80
batch-commit
border @4 2
EOF2
v script "$dir/looks.script" >"$dir/ids" 2>"$dir/err" || fail "looks script: $(cat "$dir/err")"
read -r w1 w2 w3 w4 < <(cut -d' ' -f1 "$dir/ids" | tr '\n' ' ')
v --role observer tree >"$dir/tree"
grep -qx "$w1 0 100 100 200 100 mapped [a-z-]* retained 0 translucent -" "$dir/tree" &&
	grep -qx "$w2 0 150 120 50 50 mapped [a-z-]* retained 3 - -" "$dir/tree" &&
	grep -qx "$w3 0 0 0 400 400 mapped none retained 0 input-only -" "$dir/tree" &&
	grep -qx "$w4 0 300 100 100 100 mapped [a-z-]* retained 2 shaped -" "$dir/tree" ||
	fail "looks script: the tree says $(cat "$dir/tree")"
printf 'window 1 100 100 200 100\nopaque 10,10,180,80\nwindow 2 150 120 50 50\nborder 3\n' \
	>"$dir/looks.scene"
printf 'window 3 0 0 400 400\ninput-only\nwindow 4 300 100 100 100\nborder 2\nshape 0,0,50,100\n' \
	>>"$dir/looks.scene"
"$visctl" compute "$dir/looks.scene" | awk -v a="$w1" -v b="$w2" -v c="$w4" \
	'{ id = $1 == 1 ? a : $1 == 2 ? b : c; print id, $2 }' | sort -n >"$dir/want"
v --role observer states | sort -n >"$dir/got"
cmp -s "$dir/want" "$dir/got" || fail "looks: daemon states $(cat "$dir/got"), compute's $(cat "$dir/want")"
[ "$(v --role observer look "$w4" | tr '\n' ';')" = "shape 0,0,50,100;opaque all;" ] &&
	[ "$(v --role observer look "$w1" | tr '\n' ';')" = "shape box;opaque 10,10,180,80;" ] &&
	v --role observer look --json "$w4" |
	python3 -c 'import json, sys; o = json.load(sys.stdin); assert o["shaped"] and o["shape"] == [[0, 0, 50, 100]] and o["opaque"] == "all", o' ||
	fail "look: $(v --role observer look "$w4" | tr '\n' ';')"
v shape "$w1" 0,0,0,5 2>"$dir/err"
[ $? -eq 2 ] && grep -q "rectangle 1 '0,0,0,5' is not X,Y,W,H" "$dir/err" || fail "shape with W 0: $(cat "$dir/err")"
v --role manager opaque "$w3" none 2>"$dir/err"
[ $? -eq 1 ] && grep -q "input-only" "$dir/err" || fail "opaque on an input-only window: $(cat "$dir/err")"
v --role manager border "$w3" 2 2>"$dir/err"
[ $? -eq 1 ] && grep -q "input-only" "$dir/err" || fail "border on an input-only window: $(cat "$dir/err")"
printf 'destroy %s\n' "$w1" "$w2" "$w3" "$w4" | v --role manager script - || fail "clearing the looks"

# A scene made for another screen: refused, its states would not be compute's; --any-screen.
printf 'screen 100 100\nwindow 1 0 0 150 50\n' >"$dir/small.scene"
v load "$dir/small.scene" >"$dir/out" 2>"$dir/err"
rc=$?
[ $rc -eq 1 ] && [ ! -s "$dir/out" ] && grep -q "screen is 100x100, the daemon's 3840x2160" "$dir/err" ||
	fail "load of a 100x100 scene: exit $rc, $(cat "$dir/err")"
out=$(printf 'load --any-screen %s\nstates\n' "$dir/small.scene" | v script - 2>"$dir/err")
[ "$(echo "$out" | sed -n 2p | cut -d' ' -f2)" = unobscured ] ||
	fail "load --any-screen: '$out', $(cat "$dir/err")"

# A plain client's new connection owns nothing and sees nothing: watch refuses at once (it would
# wait forever), states and repaint say so on stderr; with windows of its own, no warning.
timeout "$progress_stall" "$visctl" -s "$sock" watch --count 1 >/dev/null 2>"$dir/err"
rc=$?
[ $rc -eq 2 ] && grep -q "owns no windows" "$dir/err" ||
	fail "watch as a client without windows: exit $rc, $(cat "$dir/err")"
for cmd in "states" "repaint 0 0 100 100"; do
	# shellcheck disable=SC2086
	out=$(v $cmd 2>"$dir/err")
	[ $? -eq 0 ] && [ -z "$out" ] && grep -q "warning: this connection owns no windows" "$dir/err" ||
		fail "$cmd as a client without windows: '$out', $(cat "$dir/err")"
done
printf 'create 0 0 10 10
states
' | v script - >/dev/null 2>"$dir/err"
[ ! -s "$dir/err" ] || fail "states with an unmapped window of its own warned: $(cat "$dir/err")"

# A script: one connection, its windows gone with it unless retained.
cat >"$dir/script" <<'SCRIPT'
# a window, a child, and a query
create 0 0 100 100 --map
states
SCRIPT
out=$(v script "$dir/script") || fail "script failed"
[ "$(echo "$out" | wc -l)" -eq 2 ] && [ "$(echo "$out" | sed -n 2p | cut -d' ' -f2)" = unobscured ] ||
	fail "script output: $out"
[ -z "$(v --role observer states)" ] || fail "a script's windows outlived it"
printf 'create 0 0 10 10\nmap 999999\n' >"$dir/bad-script"
v script "$dir/bad-script" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "bad-script:2:" "$dir/err" || fail "a failing script line: $(cat "$dir/err")"

# A script names its own windows with @N (the N-th create) and holds changes in a batch.
cat >"$dir/script" <<'SCRIPT'
create 0 0 100 100 --map
create 50 50 100 100 --map
batch-begin
move @1 60 60
raise @1
batch-commit
states
SCRIPT
out=$(v script "$dir/script") || fail "batch script failed"
# The creates print @1's and @2's IDs; states come in ascending ID, which is no creation order.
state_of() { echo "$out" | awk -v id="$(echo "$out" | sed -n "$1p")" 'NR > 2 && $1 == id { print $2 }'; }
[ "$(state_of 1) $(state_of 2)" = "unobscured partially-obscured" ] ||
	fail "batch script states: $out"
printf 'create 0 0 10 10\nbatch-begin\nmove @1 5 5\nmap 999999\nbatch-commit\n' >"$dir/bad-script"
v script "$dir/bad-script" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "bad-script:5: batch from line 2: map: window: no such window" "$dir/err" ||
	fail "a failing request in a batch: $(cat "$dir/err")"
for bad in 'move @1 1 1' 'batch-commit' 'batch-begin\nstates' 'batch-begin\nbatch-begin' \
	'batch-begin'; do
	printf "$bad\n" >"$dir/bad-script"
	v script "$dir/bad-script" >/dev/null 2>"$dir/err"
	[ $? -eq 2 ] && grep -q "bad-script:[12]: " "$dir/err" || fail "script '$bad': $(cat "$dir/err")"
done
[ -z "$(v --role observer states)" ] || fail "a script's windows outlived it"

# Daemon errors: exit 1, naming the request and the reason.
v map 999999 2>"$dir/err"
[ $? -eq 1 ] && grep -q "map" "$dir/err" && grep -q "no such window" "$dir/err" ||
	fail "map of a missing window: $(cat "$dir/err")"
# A window another connection made is hidden from a plain client: the error says it may be
# another connection's, and which role sees (observer) and changes (manager) it; with a role,
# the bare error. In a script, the script's connection is named.
other=$(v create 0 0 10 10 --map --retain)
v raise "$other" 2>"$dir/err"
[ $? -eq 1 ] && grep -qF "raise $other: window: no such window $other (it may be another connection's: each visctl is a new connection, a plain client, which sees only its own windows; --role observer reads every window, --role manager changes them)" "$dir/err" ||
	fail "raise of another connection's window: $(cat "$dir/err")"
printf 'raise %s\n' "$other" >"$dir/other-script"
v script "$dir/other-script" 2>"$dir/err"
[ $? -eq 1 ] && grep -qF "other-script:1: raise $other: window: no such window $other (it may be another connection's: this script's connection is a plain client" "$dir/err" ||
	fail "a script's raise of another connection's window: $(cat "$dir/err")"
v --role manager raise 999999 2>"$dir/err"
[ $? -eq 1 ] && ! grep -q "another connection" "$dir/err" ||
	fail "a manager's missing window: $(cat "$dir/err")"
v --role manager destroy "$other" || fail "the manager did not destroy another connection's window"
"$visctl" -s "$dir/nothing" states 2>"$dir/err"
[ $? -eq 1 ] && grep -q "$dir/nothing" "$dir/err" || fail "no daemon: $(cat "$dir/err")"
# A refused connection says what is at the path and whether a visd runs for it (holds the
# path's .lock), not a bare "Connection refused": a regular file; the socket a killed visd left;
# that socket while something holds the lock, as a visd starting there does.
: >"$dir/plain"
"$visctl" -s "$dir/plain" states 2>"$dir/err"
[ $? -eq 1 ] && grep -qF "cannot connect to $dir/plain: Connection refused: it is a regular file, not a socket; no visd holds its .lock, so none runs for this path (a new one replaces what is there)" "$dir/err" ||
	fail "a regular file at the socket's path: $(cat "$dir/err")"
"$visd" --socket "$dir/crashed" 2>/dev/null &
cpid=$!
wait_socket "$cpid" "$dir/crashed"
kill -KILL "$cpid"
wait "$cpid" 2>/dev/null
"$visctl" -s "$dir/crashed" states 2>"$dir/err"
[ $? -eq 1 ] && grep -qF "cannot connect to $dir/crashed: Connection refused: the socket there has no listener: the visd that made it has gone (killed or crashed); no visd holds its .lock, so none runs for this path" "$dir/err" ||
	fail "a killed visd's socket: $(cat "$dir/err")"
if command -v flock >/dev/null; then
	# The lock is held by fd 9 of the subshell, which becomes the sleep: killing it frees it.
	(flock 9 && exec sleep 600) 9>"$dir/crashed.lock" >/dev/null 2>&1 &
	fpid=$!
	held() { grep -q "FLOCK.*:$(stat -c %i "$dir/crashed.lock") " /proc/locks; }
	wait_progress "$fpid" held
	"$visctl" -s "$dir/crashed" states 2>"$dir/err"
	[ $? -eq 1 ] && grep -qF "the visd that made it has gone (killed or crashed); yet a visd holds its .lock: one runs for this path" "$dir/err" ||
		fail "a stale socket with its lock held: $(cat "$dir/err")"
	kill "$fpid"
	wait "$fpid" 2>/dev/null
fi

# snapshot --svg: every window the observer sees, children at their absolute place, each in the
# state the daemon gives it; a client draws only its own.
"$visctl" gen random 30 7 >"$dir/scene"
v load --retain "$dir/scene" >"$dir/map" || fail "load for snapshot"
parent=$(v --role manager create 100 100 400 300 --map --retain) &&
	child=$(v --role manager create 10 20 50 40 --parent "$parent" --map --retain) ||
	fail "create for snapshot"
v --role observer snapshot --svg "$dir/snap.svg" 2>"$dir/err" || fail "snapshot: $(cat "$dir/err")"
if command -v xmllint >/dev/null; then
	xmllint --noout "$dir/snap.svg" || fail "snapshot: not well-formed"
else
	[ "$(tail -n 1 "$dir/snap.svg")" = '</svg>' ] || fail "snapshot: no </svg> at the end"
fi
v --role observer states >"$dir/states"
[ "$(wc -l <"$dir/states")" -eq 32 ] || fail "snapshot: $(wc -l <"$dir/states") windows, not 32"
while read -r id state; do
	grep -qE "^<g><title>$id( \(child of [0-9]+\))?: .*, $state</title>$" "$dir/snap.svg" ||
		fail "snapshot: window $id ($state) is not drawn as such"
done <"$dir/states"
grep -qF "<title>$child (child of $parent): 110,120 50×40, unobscured</title>" "$dir/snap.svg" ||
	fail "snapshot: the child is not at its absolute place"
printf 'create 5 5 20 20 --map\nsnapshot --svg %s\n' "$dir/own.svg" | v script - >/dev/null ||
	fail "snapshot in a script"
[ "$(grep -c '<title>' "$dir/own.svg")" -eq 1 ] || fail "a client's snapshot shows others' windows"
v --role observer snapshot --svg "$dir/nodir/x.svg" 2>"$dir/err"
[ $? -eq 1 ] && grep -qF "snapshot: $dir/nodir/x.svg: cannot write" "$dir/err" ||
	fail "snapshot to an unwritable path: $(cat "$dir/err")"
{ cut -d' ' -f2 "$dir/map"; echo "$parent"; } | sed 's/^/destroy /' >"$dir/clear"
v --role manager script "$dir/clear" || fail "clearing the snapshot's windows"

# watch: notices as lines, and as JSON. A probe window tells when watch has subscribed.
await_line() { # PIDS FILE PATTERN: waits for a line while PIDS (the watch, visd) work
	wait_progress "$1" grep -qsE "$3" "$2"
}
"$visctl" -s "$sock" --role observer watch >"$dir/watch" &
wpid=$!
probe=$(v create 0 0 1 1 --retain) || fail "probe"
until [ -s "$dir/watch" ]; do v --role manager move "$probe" 1 1 && v --role manager move "$probe" 0 0; done
id=$(v create 10 10 50 50 --map --retain) || fail "create"
await_line "$wpid $pid" "$dir/watch" "^[0-9]+ visibility $id " || fail "watch saw no visibility of $id"
kill $wpid
wait $wpid
grep -qE "^[0-9]+ stack create $id 0 10,10,50,50 $probe$" "$dir/watch" &&
	grep -qE "^[0-9]+ stack map $id " "$dir/watch" &&
	grep -qE "^[0-9]+ visibility $id unobscured none$" "$dir/watch" &&
	grep -qE "^[0-9]+ exposure $id 0,0,50,50$" "$dir/watch" || fail "watch lines: $(cat "$dir/watch")"
awk '{ if ($1 != NR) bad = 1 } END { exit bad }' "$dir/watch" || fail "watch serials have gaps"
"$visctl" -s "$sock" --role observer watch --json "$id" >"$dir/watch.json" &
wpid=$!
until [ -s "$dir/watch.json" ]; do v --role manager resize "$id" 50 50 || break; done
v --role manager move "$id" 3800 2000 || fail "move"
await_line "$wpid $pid" "$dir/watch.json" "visibility" || fail "watch --json saw no visibility notice"
kill $wpid
wait $wpid
grep -q "\"notice\":\"visibility\",\"window\":$id,\"state\":\"partially-obscured\",\"previous\":\"unobscured\"" \
	"$dir/watch.json" || fail "watch --json: $(cat "$dir/watch.json")"
v --role manager destroy "$id" || fail "destroy"
v --role manager destroy "$probe" || fail "destroy probe"

# visctl stress: a short run passes its own check, and its JSON has every documented field.
[ -z "$(v --role observer states)" ] || fail "windows left before visctl stress"
v stress -c 3 -n 50 --count 2000 --seed 1 --json --record "$dir/rec" >"$dir/stress.json" \
	2>"$dir/err" || fail "visctl stress: $(cat "$dir/err")"
python3 - "$dir/stress.json" "$pid" <<'PY' || fail "visctl stress --json: $(cat "$dir/stress.json")"
import json, sys
d = json.load(open(sys.argv[1]))
fields = ("windows clients seed pipeline rate ops changes seconds ops_per_s changes_per_s notices "
	  "notices_per_s p50_us p90_us p99_us p999_us max_us mean_us daemon_pid daemon_cpu_s "
	  "daemon_cpu_pct daemon_rss_kb daemon_hwm_kb visctl_cpu_s mismatches scene ok kinds").split()
missing = [f for f in fields if f not in d]
assert not missing, missing
assert d["windows"] == 50 and d["clients"] == 3 and d["ops"] == 2000 and d["rate"] is None
assert d["ok"] is True and d["mismatches"] == 0 and d["notices"] > 0 and d["scene"] == "random"
assert d["changes"] > d["ops"]  # batches hold several changes
assert 0 < d["p50_us"] <= d["p90_us"] <= d["p99_us"] <= d["p999_us"] <= d["max_us"]
assert d["daemon_pid"] == int(sys.argv[2]) and d["daemon_rss_kb"] > 0
# visd is single-threaded: a share of the run over 100% is a measurement in clock ticks.
assert 0 <= d["daemon_cpu_pct"] <= 100.5, d["daemon_cpu_pct"]
assert sum(k["ops"] for k in d["kinds"].values()) == 2000
assert set(d["kinds"]) == {"move", "resize", "raise", "lower", "restack", "map", "batch"}
PY
[ -z "$(v --role observer states)" ] || fail "visctl stress left windows behind"
# The record replays with visctl script to the model's final states (listed at its end as
# '# @N STATE'; the script prints the N-th create's ID on its N-th line).
(cat "$dir/rec" && echo states) | v script - >"$dir/replay" || fail "replaying the record"
awk 'FNR == NR { if (/^# @[0-9]+ /) want[substr($2, 2)] = $3; next }
	FNR <= 50 { id[FNR] = $1; next }
	{ got[$1] = $2 }
	END { for (n in want) if (got[id[n]] != want[n]) { print "@" n, got[id[n]], want[n]; bad = 1 }
	      exit bad || length(want) == 0 }' "$dir/rec" "$dir/replay" >"$dir/err" ||
	fail "the replayed record ends in other states: $(head -3 "$dir/err")"
# A fixed rate, a pipeline, exposures, only some kinds, tiles; CSV is a header and one row. (At most
# 600 operations fall due in 0.3 s: fewer when the machine is slow, as no operation starts later.)
v stress -c 2 -n 30 -R 2000 --duration 0.3 --pipeline 4 --exposure --mix move,raise=2,batch \
	--batch-size 3 --scene tiles --csv >"$dir/stress.csv" 2>"$dir/err" ||
	fail "stress -R: $(cat "$dir/err")"
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; n = NF }
	NR == 2 { ok = NF == n && $col["ok"] == 1 && $col["rate"] == "2000.0" &&
		  $col["scene"] == "tiles" &&
		  $col["ops"] > 0 && $col["ops"] <= 600 }
	END { exit !(NR == 2 && ok) }' "$dir/stress.csv" || fail "stress --csv: $(cat "$dir/stress.csv")"
# The check can fail: a model that drifts from the daemon is caught.
VISCTL_STRESS_CORRUPT_MODEL=1 v stress -c 2 -n 30 --count 100 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "differences between visd and the model" "$dir/err" ||
	fail "a corrupt model passed: $(cat "$dir/err")"
# A daemon that never goes live recomputes through the tree: the same states and notices.
"$visd" --socket "$dir/through" --screen 3840x2160 --live-from 2147483647 2>"$dir/through.log" &
tpid=$!
wait_socket "$tpid" "$dir/through"
for k in random cascade tiles; do
	"$visctl" -s "$dir/through" stress -c 3 -n 200 --count 1000 --scene $k --seed 2 --quiet \
		>/dev/null 2>"$dir/err" || fail "stress --scene $k through the tree: $(cat "$dir/err")"
done
kill "$tpid"
wait "$tpid" 2>/dev/null
# --pid must be the visd serving the socket: not init, not a process that is gone.
v stress -n 10 --count 10 --pid 1 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q -- "--pid 1 is '.*', not visd" "$dir/err" || fail "stress --pid 1: $(cat "$dir/err")"
v stress -n 10 --count 10 --pid 999999 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q -- "--pid 999999: no such process" "$dir/err" ||
	fail "stress --pid 999999: $(cat "$dir/err")"
v stress -n 10 --count 10 --pid "$pid" >/dev/null 2>"$dir/err" || fail "stress --pid visd: $(cat "$dir/err")"
# It needs a daemon of its own and the manager role.
keep=$(v create 0 0 10 10 --retain) || fail "create"
v stress -n 10 --count 10 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "has 1 windows already" "$dir/err" ||
	fail "stress on a busy daemon: $(cat "$dir/err")"
v --role manager destroy "$keep" || fail "destroy"
# (The daemon may see the watch's hello before an earlier manager's end: start it again then.)
wpid=
manager_taken() {
	if [ -z "$wpid" ] || ! kill -0 "$wpid" 2>/dev/null; then
		"$visctl" -s "$sock" --role manager watch >/dev/null 2>&1 &
		wpid=$!
	fi
	! v --role manager sync 2>/dev/null
}
wait_progress "$pid" manager_taken || fail "a watch did not take the manager role ($progress_why)"
v stress -n 10 --count 10 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "needs the manager role" "$dir/err" ||
	fail "stress without the manager role: $(cat "$dir/err")"
kill $wpid
wait $wpid

# --version: the program, meson's project version and the protocol's, the same for both.
out=$("$visd" --version) || fail "visd --version exited $?"
proto=$(echo "$out" | sed -nE 's/^visd [^ ]+ \(protocol ([0-9]+)\)$/\1/p')
[ -n "$proto" ] && [ "$out" = "visd $version (protocol $proto)" ] ||
	fail "visd --version: '$out', want 'visd $version (protocol N)'"
out=$("$visctl" --version) || fail "visctl --version exited $?"
[ "$out" = "visctl $version (protocol $proto)" ] ||
	fail "visctl --version: '$out', want 'visctl $version (protocol $proto)'"

# visd's own errors: a second daemon on the same socket, bad options.
"$visd" --socket "$sock" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "another visd" "$dir/err" || fail "second daemon: $(cat "$dir/err")"
"$visd" --screen 0x5 --socket "$dir/x" 2>/dev/null
[ $? -eq 2 ] || fail "visd --screen 0x5 was accepted"
# An option's error is one line, then the usage line and where the rest is: not the forty lines
# of --help that once buried it. A size out of range says so, not "want WxH".
"$visd" --screen 0x0 --socket "$dir/x" 2>"$dir/err"
[ $? -eq 2 ] && [ "$(head -n 1 "$dir/err")" = "visd: --screen '0x0': width and height must each be 1 to 2147483647 (WxH, e.g. 1920x1080)" ] ||
	fail "visd --screen 0x0: $(cat "$dir/err")"
"$visd" --screen 1920 --socket "$dir/x" 2>"$dir/err"
[ $? -eq 2 ] && grep -qx "visd: --screen '1920': want WxH, e.g. 1920x1080" "$dir/err" ||
	fail "visd --screen 1920: $(cat "$dir/err")"
for opt in "--bogus" "--screen 0x0" "--max-clients 0" "--owner-reserve 8 --max-clients 8"; do
	# shellcheck disable=SC2086
	"$visd" --socket "$dir/x" $opt 2>"$dir/err"
	[ "$(wc -l <"$dir/err")" -eq 3 ] && grep -qx "usage: visd .*" "$dir/err" &&
		grep -qxF "(visd --help lists every option)" "$dir/err" ||
		fail "visd $opt: not one line and the usage line: $(cat "$dir/err")"
done
env -u VISD_SOCKET -u XDG_RUNTIME_DIR "$visd" 2>"$dir/err"
[ $? -eq 2 ] && grep -q "VISD_SOCKET" "$dir/err" || fail "no socket path: $(cat "$dir/err")"
for opt in "--max-clients 0" "--max-depth 4097" "--max-pending 100" "--max-windows x" "--max-request" \
	"--owner-reserve 8 --max-clients 8" "--max-clients-per-uid 0" "--max-restricted-clients 0"; do
	# shellcheck disable=SC2086
	"$visd" --socket "$dir/x" $opt 2>"$dir/err"
	[ $? -eq 2 ] && grep -q -- "${opt%% *}" "$dir/err" || fail "visd $opt: $(cat "$dir/err")"
done
# A directory where another user could replace the socket is refused; a sticky one is not.
mkdir -m 777 "$dir/open"
chmod 777 "$dir/open"
"$visd" --socket "$dir/open/s" 2>"$dir/err"
[ $? -eq 1 ] && grep -q "lets other users replace" "$dir/err" || fail "open dir: $(cat "$dir/err")"
chmod 1777 "$dir/open"
"$visd" --socket "$dir/open/s" 2>"$dir/err" &
spid=$!
wait_socket "$spid" "$dir/open/s"
[ -S "$dir/open/s" ] || fail "a sticky directory was refused: $(cat "$dir/err")"
kill $spid
wait $spid || fail "visd in a sticky directory exited $?"
# The socket appears only once it answers (bound as SOCKET.new, renamed when listening), so a
# client may connect the moment it sees the path. A stale socket named SOCKET.new is replaced;
# anything else there (a file, another daemon's socket) is left alone for SOCKET.PID.new.
"$visd" --socket "$dir/pub.new" 2>/dev/null & # killed outright: leaves a stale socket there
npid=$!
wait_socket "$npid" "$dir/pub.new"
kill -9 $npid
wait $npid 2>/dev/null
[ -S "$dir/pub.new" ] || fail "no stale socket to test with"
echo keep >"$dir/kept.new"
"$visd" --socket "$dir/live.new" 2>/dev/null &
livepid=$!
wait_socket "$livepid" "$dir/live.new"
for name in pub kept live; do
	"$visd" --socket "$dir/$name" 2>"$dir/err" &
	npid=$!
	wait_socket "$npid" "$dir/$name"
	"$visctl" -s "$dir/$name" states >/dev/null 2>"$dir/err.c" ||
		fail "$name: refused as the socket appeared: $(cat "$dir/err.c" "$dir/err")"
	kill $npid
	wait $npid || fail "visd --socket $dir/$name exited $?"
done
for left in "$dir/pub.new" "$dir"/*.[0-9]*.new; do
	[ ! -e "$left" ] || fail "a temporary socket name was left behind: $left"
done
[ "$(cat "$dir/kept.new")" = keep ] || fail "a file named like the temporary socket was removed"
"$visctl" -s "$dir/live.new" states >/dev/null || fail "another daemon's socket was taken"
kill $livepid
wait $livepid || fail "visd --socket $dir/live.new exited $?"
# A client past --max-clients hears why, even when its hello meets a closed socket.
"$visd" --socket "$dir/lim" --max-clients 1 2>/dev/null &
lpid=$!
wait_socket "$lpid" "$dir/lim"
fds() { ls "/proc/$lpid/fd" | wc -l; }
before=$(fds)
accepted() { [ "$(fds)" -gt "$before" ]; }
"$visctl" -s "$dir/lim" --role observer watch >/dev/null &
wpid=$!
# The watch holds the one client slot once visd has accepted it.
wait_progress "$lpid $wpid" accepted ||
	fail "visd did not accept the watch ($progress_why)"
"$visctl" -s "$dir/lim" states 2>"$dir/err"
[ $? -eq 1 ] && grep -q "limit: too many clients.*--max-clients" "$dir/err" ||
	fail "past --max-clients: $(cat "$dir/err")"
kill $wpid $lpid
wait $lpid || fail "visd --max-clients 1 exited $?"
mode=$(stat -c %a "$sock")
[ $((8#$mode & 8#077)) -eq 0 ] || fail "the socket is open to others: mode $mode"

# docs/desktop.script names its windows by @N: it runs on a daemon that has windows already.
v create 0 0 5 5 --retain >/dev/null || fail "create before the desktop"
n_before=$(v --role observer tree | wc -l)
v script "$(dirname "$0")/../docs/desktop.script" >"$dir/out" 2>"$dir/err" ||
	fail "docs/desktop.script on a daemon with windows: $(cat "$dir/err")"
[ "$(v --role observer tree | wc -l)" -eq $((n_before + 26)) ] || fail "the desktop made no 26 windows"
# The queries' records: tree's columns, and --json objects with the same content.
v --role observer tree >"$dir/tree"
v --role observer tree --json >"$dir/tree.json"
python3 - "$dir/tree" "$dir/tree.json" <<'PY' || fail "tree and tree --json disagree"
import json, sys
text = [l.split() for l in open(sys.argv[1])]
objs = [json.loads(l) for l in open(sys.argv[2])]
assert len(text) == len(objs) > 26, (len(text), len(objs))
for t, o in zip(text, objs):
    assert len(t) == 12, t
    assert [int(x) for x in t[:6]] == [o[k] for k in ("window", "parent", "x", "y", "width", "height")], (t, o)
    assert (t[6] == "mapped") == o["mapped"] and t[7] == o["state"], (t, o)
    assert (t[8] == "retained") == o["retained"] and o["retained"], (t, o)
    assert int(t[9]) == o["border"], (t, o)
    look = [k for k in ("shaped", "translucent", "input-only") if o[k.replace("-", "_")]]
    assert t[10] == (",".join(look) or "-"), (t, o)
    ns, tag = o["namespace"], o["external"]
    assert t[11] == ("-" if ns == 0 else "x11:%#x" % tag if ns == 1 else "%d:%#x" % (ns, tag)), (t, o)
PY
for q in "states" "region $(head -n 1 "$dir/tree" | cut -d' ' -f1)" "repaint 0 0 1920 1080"; do
	# shellcheck disable=SC2086
	v --role observer $q --json | python3 -c 'import json, sys; [json.loads(l) for l in sys.stdin]' ||
		fail "$q --json is not JSON lines"
done
"$visctl" tree --help | grep -q "ID PARENT X Y W H MAPPED STATE RETAINED BORDER LOOK EXTERNAL" ||
	fail "tree --help: no columns"
"$visctl" region --help | grep -q "inside's top-left corner" || fail "region --help: no coordinates"
# External IDs: a manager's windows mirror X windows (and a private namespace's); a plain client
# may not give one; states --x11, lookup, tree and watch --x11 name them by XID. The observer
# role is what --x11 and lookup take without --role.
cat >"$dir/x11.script" <<'EOF2'
create 2000 1000 400 300 --map --retain --x11 0x1e00003
create 10 10 100 100 --map --retain --x11 0x1e00010 --parent @1
create 2300 1200 200 200 --map --retain --x11 0x400001
create 2000 1500 50 50 --map --retain --external 7:0xabc
EOF2
v --role manager script "$dir/x11.script" >"$dir/ids" 2>"$dir/err" || fail "x11 script: $(cat "$dir/err")"
read -r x1 x2 x3 x4 < <(tr '\n' ' ' <"$dir/ids")
v create 0 0 5 5 --x11 0x77 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "access: only the manager sets external IDs" "$dir/err" ||
	fail "create --x11 as a client: $(cat "$dir/err")"
v --role manager create 0 0 5 5 --x11 0x1e00003 >/dev/null 2>"$dir/err"
[ $? -eq 1 ] && grep -q "match: external ID 1:0x1e00003 is window $x1's" "$dir/err" ||
	fail "create with an X ID in use: $(cat "$dir/err")"
# XIDs in lowercase hex, ascending; only the X windows.
printf '0x400001 unobscured\n0x1e00003 partially-obscured\n0x1e00010 unobscured\n' >"$dir/want"
v states --x11 >"$dir/got" 2>"$dir/err" && cmp -s "$dir/want" "$dir/got" ||
	fail "states --x11: $(cat "$dir/got" "$dir/err")"
v states --x11 --json | head -n 1 | grep -qx "{\"x11\":\"0x400001\",\"window\":$x3,\"state\":\"unobscured\"}" ||
	fail "states --x11 --json: $(v states --x11 --json)"
[ "$(v lookup --x11 0x1e00010)" = "$x2" ] && [ "$(v lookup --x11 31457296)" = "$x2" ] &&
	[ "$(v lookup 7 0xabc)" = "$x4" ] && [ "$(v lookup 7 2748)" = "$x4" ] ||
	fail "lookup: $(v lookup --x11 0x1e00010 2>&1) $(v lookup 7 0xabc 2>&1)"
v --role client lookup --x11 0x1e00003 >"$dir/out" 2>"$dir/err"
[ $? -eq 1 ] && [ ! -s "$dir/out" ] && grep -q "window: no window carries external ID 1:0x1e00003" "$dir/err" ||
	fail "lookup as a client: $(cat "$dir/err")"
v --role observer tree >"$dir/tree"
grep -qx "$x2 $x1 10 10 100 100 mapped unobscured retained 0 - x11:0x1e00010" "$dir/tree" &&
	grep -qx "$x4 0 2000 1500 50 50 mapped [a-z-]* retained 0 - 7:0xabc" "$dir/tree" ||
	fail "tree's EXTERNAL column: $(cat "$dir/tree")"
# watch --x11 XID: the notices of that window, named by XID; watching all, every X window is.
"$visctl" -s "$sock" watch --x11 0x1e00010 --count 2 >"$dir/watch.one" 2>"$dir/err" &
wpid=$!
"$visctl" -s "$sock" watch --x11 >"$dir/watch.all" 2>&1 &
wapid=$!
await_line "$wpid $pid" "$dir/watch.one" "visibility 0x1e00010 unobscured initial" ||
	fail "watch --x11 XID: $(cat "$dir/watch.one" "$dir/err")"
wait_progress "$wapid $pid" test -s "$dir/watch.all" ||
	fail "watch --x11 printed no initial notice ($progress_why)"
v --role manager move "$x2" 20 20
wait "$wpid" || fail "watch --x11 XID: exit $?"
grep -qE "^[0-9]+ stack configure 0x1e00010 0x1e00003 20,20,100,100 0$" "$dir/watch.one" ||
	fail "watch --x11 XID: $(cat "$dir/watch.one")"
await_line "$wapid $pid" "$dir/watch.all" "stack configure 0x1e00010 0x1e00003 20,20,100,100" ||
	fail "watch --x11: $(cat "$dir/watch.all")"
grep -qE "^[0-9]+ visibility 0x400001 unobscured initial$" "$dir/watch.all" &&
	grep -qE "^[0-9]+ visibility $x4 [a-z-]+ initial$" "$dir/watch.all" ||
	fail "watch --x11 initial notices: $(cat "$dir/watch.all")"
kill "$wapid" 2>/dev/null
wait "$wapid" 2>/dev/null
v --role manager script <(printf 'destroy %s\n' "$x1" "$x3" "$x4") || fail "destroying the X windows"
v lookup --x11 0x1e00010 >/dev/null 2>&1 && fail "lookup of a destroyed child's XID found it"

# A script that fails half-way says which retained windows it leaves behind.
printf 'create 0 0 10 10 --retain\ncreate 5 5 10 10 --map\ncreate 0 0 5 5 --retain --parent @1\nmap 999999\n' \
	>"$dir/half.script"
v script "$dir/half.script" >"$dir/out" 2>"$dir/err"
rc=$?
ids=$(cut -d' ' -f1 "$dir/out" | tr '\n' ' ')
set -- $ids
[ $rc -eq 1 ] && grep -qx "$dir/half.script: the retained windows it made stay: @1=$1 @3=$3" "$dir/err" ||
	fail "a script failing half-way: exit $rc, $(cat "$dir/err")"

kill "$pid"
wait "$pid" || fail "visd exited $? on SIGTERM"
pid=
[ ! -e "$sock" ] && [ ! -e "$sock.lock" ] || fail "visd left its socket or lock behind"
if grep -qE "ERROR|runtime error" "$dir/visd.log"; then fail "visd log: $(cat "$dir/visd.log")"; fi
[ $failures -eq 0 ] && echo "live: every check passed"
exit $((failures > 0))
