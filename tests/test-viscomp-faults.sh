#!/bin/sh
# viscomp's faults: clients that die at any time. A headless viscomp mirrors into a visd while,
# for ROUNDS rounds (default 40; seed SEED, default 1), the test starts a real client
# (weston-simple-shm, weston-simple-damage, weston-flower or foot, in turn), moves, raises and
# lowers windows at random through viscompctl, and kills a client with SIGKILL at random: often
# just after it started, before its window is mirrored, or while another covers it. viscomp must
# live through it all; at the end, with every client gone, viscompctl must list no window and
# visd hold none of viscomp's but the outside (no window leaked in the mirror), and viscomp must
# exit cleanly (under ASan: no report). Waits follow progress (tests/progress.sh).
# Usage: test-viscomp-faults.sh BUILD-DIR. Exits 77 (skipped) where viscomp is not built.
set -u
build=${1:?usage: test-viscomp-faults.sh BUILD-DIR}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
visd=$build/daemon/visd
visctl=$build/client/visctl/visctl
rounds=${ROUNDS:-40}
seed=${SEED:-1}
[ -x "$viscomp" ] || { echo "$viscomp not built: skipped"; exit 77; }
for prog in "$viscompctl" "$visd" "$visctl"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done
for prog in weston-simple-shm weston-simple-damage weston-flower foot; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed (tools/dev.sh install)"; exit 1; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-viscomp-faults.XXXXXX") || exit 1
chmod 700 "$dir"
dpid= vpid= clients=
cleanup() {
	for pid in $clients $vpid $dpid; do
		kill -9 "$pid" 2>/dev/null
	done
	for pid in $clients $vpid $dpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "test-viscomp-faults: seed $seed: $1 (rerun: SEED=$seed ROUNDS=$rounds $0 $build)"
	echo "--- viscomp's log:"
	tail -n 30 "$dir/viscomp.log"
	exit 1
}

. "$(dirname "$0")/viscomp-env.sh"
viscomp_env "$dir"

# The next number of a 31-bit LCG, in $r (0 … 2^31 - 1): the same seed, the same run.
r=$seed
next() {
	r=$(((r * 1103515245 + 12345) % 2147483648))
}

# pick N: a number 0 … N - 1 into $n.
pick() {
	next
	n=$((r / 65536 % $1))
}

ids() {
	"$viscompctl" list 2>/dev/null | awk '{ print $1 }'
}

alive() {
	kill -0 "$vpid" 2>/dev/null || fail "viscomp died"
}

# Whether viscompctl lists no window and visd holds only the outside.
all_gone() {
	[ -z "$(ids)" ] || return 1
	n=$("$visctl" -s "$dir/visd.sock" --role observer tree 2>/dev/null | grep -c .)
	[ "$n" -eq 1 ]
}

"$visd" --socket "$dir/visd.sock" --screen 1280x720 2>"$dir/visd.log" &
dpid=$!
wait_progress "$dpid" test -S "$dir/visd.sock" || fail "visd did not start: $progress_why"
viscomp_start --headless 1280x720 --visd "$dir/visd.sock" ||
	fail "viscomp did not start: $progress_why"

started=0 killed=0 ops=0 most=0
round=0
while [ "$round" -lt "$rounds" ]; do
	round=$((round + 1))
	case $((round % 4)) in
	0) weston-simple-shm >/dev/null 2>&1 & ;;
	1) weston-simple-damage >/dev/null 2>&1 & ;;
	2) weston-flower >/dev/null 2>&1 & ;;
	3) foot sleep 100000 >/dev/null 2>&1 & ;;
	esac
	pid=$!
	clients="$clients $pid"
	started=$((started + 1))
	# One in four may die before viscomp has seen much of it; the others once mapped.
	pick 4
	if [ "$n" -ne 0 ]; then
		wait_progress "$vpid $pid" listed "$pid" || alive
	fi
	pick 6
	moves=$n
	while [ "$moves" -gt 0 ]; do
		moves=$((moves - 1))
		# shellcheck disable=SC2046 # one ID a word
		set -- $(ids)
		[ $# -gt 0 ] || break
		[ $# -le "$most" ] || most=$#
		pick $#
		shift "$n"
		id=$1
		pick 4
		case $n in
		0) pick 1100; x=$n; pick 600; "$viscompctl" move "$id" "$x" "$n" >/dev/null 2>&1 ;;
		1) "$viscompctl" raise "$id" >/dev/null 2>&1 ;;
		2) "$viscompctl" lower "$id" >/dev/null 2>&1 ;;
		3) "$viscompctl" move "$id" 0 0 >/dev/null 2>&1 ;;
		esac
		ops=$((ops + 1))
	done
	# Kill one client in two, at random among those left.
	pick 2
	if [ "$n" -eq 0 ]; then
		# shellcheck disable=SC2086 # one pid a word
		set -- $clients
		pick $#
		shift "$n"
		victim=$1
		kill -9 "$victim" 2>/dev/null
		wait "$victim" 2>/dev/null
		clients=$(echo " $clients " | sed "s/ $victim / /")
		killed=$((killed + 1))
	fi
	alive
done

# The rest die too; then nothing may be left, here or in visd.
for pid in $clients; do
	kill -9 "$pid" 2>/dev/null
	wait "$pid" 2>/dev/null
	killed=$((killed + 1))
done
clients=
wait_progress "$vpid $dpid" all_gone ||
	fail "windows left: $(ids | tr '\n' ' '); visd: $("$visctl" -s "$dir/visd.sock" --role observer tree 2>&1 | head -5)"
alive
kill "$vpid"
wait "$vpid"
status=$?
vpid=
[ "$status" -eq 0 ] || fail "viscomp exited with $status"
if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer\|runtime error' "$dir/viscomp.log"; then
	fail "sanitizer report"
fi
echo "test-viscomp-faults: ok: $started clients started, $killed killed (SIGKILL), $ops window" \
	"operations, at most $most windows at once"
