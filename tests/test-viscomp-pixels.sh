#!/bin/sh
# viscomp's pixels: what grim takes of the screen (screencopy) is what the stacking says it is.
# A headless viscomp (pixman) with two outputs, 640x480 and 320x240 side by side (wlroots lays
# them out left to right, leaving a 320x240 hole under the small one that no output shows), shows
# six unmodified foot terminals, each a solid colour of its own: the background and the cursor
# in that colour, no text (foot runs sleep), no decorations (csd.preferred=none; viscomp offers
# no xdg-decoration), no user config (-c /dev/null). For STEPS steps (default 24) chosen from
# SEED (default 1, printed), the test moves (across the outputs, over the edges, into the hole,
# off the outputs), resizes, raises, lowers and buries windows (one moved inside another's box
# and put under it) through viscompctl, then:
#   - takes a shot and checks every pixel (viscomp-pixels, in C for speed): the colour of the
#     topmost window whose box (`viscompctl list --json`, top first) holds it, or the background;
#     a window with no pixel on top shows none of its colour; each window's libvis state
#     (list's) is what its pixels on top make it: none, fully-obscured; all, unobscured; the
#     hole and what lies outside the outputs cover what is there, as in viscomp's model;
#   - forces a full redraw (`viscompctl redraw`), takes a second shot, checks it the same way and
#     compares the two: the frame viscomp drew from its damage alone equals one drawn whole.
# A resize waits for the client's commit of the new size (progress-following, tests/progress.sh);
# only a window with a visible pixel is resized, since a hidden one gets no frame callbacks and
# foot draws on them, and never below 40x30 (foot takes no less than a cell's height). Moves and
# restacks take effect before viscompctl returns. On a failure the shots are kept in
# BUILD-DIR/tests/viscomp-pixels-failed/.
# Usage: test-viscomp-pixels.sh BUILD-DIR. Exits 77 (skipped) where viscomp is not built.
set -u
build=${1:?usage: test-viscomp-pixels.sh BUILD-DIR}
viscomp=$build/compositor/viscomp
viscompctl=$build/compositor/ctl/viscompctl
pixels=$build/tests/viscomp-pixels
steps=${STEPS:-24}
seed=${SEED:-1}
[ -x "$viscomp" ] || { echo "$viscomp not built: skipped"; exit 77; }
for prog in "$viscompctl" "$pixels"; do
	[ -x "$prog" ] || { echo "$prog not built"; exit 1; }
done
for prog in foot grim; do
	command -v $prog >/dev/null 2>&1 || { echo "$prog not installed (tools/dev.sh install)"; exit 1; }
done

dir=$(mktemp -d "${TMPDIR:-/tmp}/test-viscomp-pixels.XXXXXX") || exit 1
chmod 700 "$dir"
vpid='' clients=''
cleanup() {
	for pid in $clients $vpid; do
		kill "$pid" 2>/dev/null
	done
	for pid in $clients $vpid; do
		wait "$pid" 2>/dev/null
	done
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

step=start
fail() {
	echo "test-viscomp-pixels: seed $seed, step $step: $1 (rerun: SEED=$seed STEPS=$steps $0 $build)"
	kept=$build/tests/viscomp-pixels-failed
	if ls "$dir"/*.ppm >/dev/null 2>&1 && mkdir -p "$kept"; then
		cp "$dir"/*.ppm "$dir"/windows.txt "$kept"/ 2>/dev/null
		echo "the shots: $kept"
	fi
	echo "--- viscomp's log:"
	tail -n 20 "$dir/viscomp.log"
	echo "--- viscompctl list:"
	ctl list 2>&1
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

# The windows, top first, one a line: ID X Y W H STATE PID (from list --json).
windows() {
	num='\(-\{0,1\}[0-9]*\)'
	re=".*\"id\":$num,.*\"pid\":$num,\"x\":$num,\"y\":$num,\"width\":$num,\"height\":$num"
	ctl list --json | sed -n "s/$re,\"state\":\"\([a-z-]*\)\".*/\1 \3 \4 \5 \6 \7 \2/p"
}

# window ID: its line's fields into wx, wy, ww, wh, wstate, wpid; 1 when it is not listed.
window() {
	# shellcheck disable=SC2046 # the line's fields, as words
	set -- "$1" $(windows | grep "^$1 ")
	[ $# -eq 8 ] || return 1
	wx=$3 wy=$4 ww=$5 wh=$6 wstate=$7 wpid=$8
}

# Whether window $1 is $2 x $3 (its client committed that size).
sized() {
	window "$1" && [ "$ww" -eq "$2" ] && [ "$wh" -eq "$3" ]
}

# resize ID W H, then wait for the client's commit of it.
resize() {
	ctl resize "$1" "$2" "$3" || fail "resize $1 $2 $3"
	window "$1" || fail "window $1 gone"
	# The client's progress alone: polling keeps viscomp busy, whether foot draws or not.
	wait_progress "$wpid" sized "$1" "$2" "$3" ||
		fail "window $1 is ${ww}x$wh, not $2x$3, after resize: $progress_why"
}

# shot NAME: a picture of the screen into $dir/NAME.ppm.
shot() {
	grim -t ppm "$dir/$1.ppm" 2>"$dir/grim.log" || fail "grim: $(cat "$dir/grim.log")"
}

# check NAME: every pixel of $dir/NAME.ppm against the windows listed (with their colours).
check() {
	"$pixels" check "$dir/$1.ppm" "$background" <"$dir/windows.txt" >"$dir/check.txt" ||
		fail "$1: $(cat "$dir/check.txt")"
}

# check_step: the shot of the windows as listed now, then the one after a full redraw: both
# right, and equal.
check_step() {
	windows >"$dir/list.txt" || fail "list"
	echo "$hole" >"$dir/windows.txt"
	while read -r id x y w h state pid; do
		eval "echo $id $x $y $w $h \$color_$id $state" >>"$dir/windows.txt"
	done <"$dir/list.txt"
	[ "$(wc -l <"$dir/list.txt")" -eq "$nwin" ] || fail "not $nwin windows listed"
	shot damage
	check damage
	ctl redraw || fail "redraw"
	shot whole
	check whole
	"$pixels" same "$dir/damage.ppm" "$dir/whole.ppm" >"$dir/same.txt" ||
		fail "the frame drawn from damage differs from a full redraw: $(cat "$dir/same.txt")"
	hidden=$(awk '$6 == "fully-obscured" { printf " %s", $1 }' "$dir/list.txt")
	echo "step $step: ok; fully obscured:${hidden:- none}"
}

# The background viscomp clears to, (0.18, 0.20, 0.22) in output.c.
background=2e3338

viscomp_start --headless 640x480,320x240 || fail "viscomp did not start: $progress_why"

# The layout: the outputs in the order wlroots made them, left to right, 960x480 in all. The
# hole is under the small one: at 640,240 when the large one came first, at 0,240 when it came
# second; the empty desktop says which (grim leaves the hole black), then must show the
# background everywhere else.
shot empty
[ "$(sed -n 2p "$dir/empty.ppm")" = "960 480" ] ||
	fail "the shot is $(sed -n 2p "$dir/empty.ppm"), not 960x480"
if [ "$(od -An -tx1 -j $((15 + (400 * 960 + 100) * 3)) -N 3 "$dir/empty.ppm" | tr -d ' ')" = \
	"$background" ]; then
	hole_x=640
else
	hole_x=0
fi
hole="0 $hole_x 240 320 240 - outside"
echo "$hole" >"$dir/windows.txt"
check empty

# Six windows, each its colour (color_ID), at a random place and size.
colors="ff0000 00ff00 0000ff ffff00 ff00ff 00ffff"
ids=
for color in $colors; do
	foot -c /dev/null -o csd.preferred=none -o colors.alpha=1.0 -o "colors.background=$color" \
		-o "cursor.color=$color $color" sleep 1000000 >"$dir/foot-$color.log" 2>&1 &
	pid=$!
	clients="$clients $pid"
	wait_progress "$vpid $pid" listed "$pid" || fail "foot ($color) not listed: $progress_why"
	eval "color_$id=$color"
	ids="$ids $id"
	pick 320 && w=$((40 + n))
	pick 250 && h=$((30 + n))
	resize "$id" "$w" "$h"
	pick 600 && x=$n
	pick 220 && y=$n
	ctl move "$id" "$x" "$y" || fail "move $id"
done
# shellcheck disable=SC2086 # the colours, as words
set -- $colors
nwin=$#

# any: a window's ID into $a, chosen at random.
any() {
	pick "$nwin"
	# shellcheck disable=SC2086 # the IDs, as words
	set -- $ids
	shift "$n"
	a=$1
}

# visible ID: when no pixel of the window can be seen (it is resized next), raises it, and moves
# its corner onto an output if that is not enough.
visible() {
	window "$1" || fail "window $1 gone"
	[ "$wstate" = fully-obscured ] || return 0
	ctl raise "$1" || fail "raise $1"
	window "$1"
	if [ "$wstate" = fully-obscured ]; then
		ctl move "$1" 300 200 || fail "move $1"
		window "$1"
	fi
	[ "$wstate" != fully-obscured ] || fail "window $1 raised and on an output, yet $wstate"
}

echo "test-viscomp-pixels: seed $seed, $steps steps, $nwin windows on outputs 640x480 and" \
	"320x240, the hole at $hole_x,240"
step="0: the windows placed"
check_step
s=0
while [ "$s" -lt "$steps" ]; do
	s=$((s + 1))
	any
	pick 10
	case $n in
	0 | 1 | 2)
		pick 1000 && x=$((n - 100))
		pick 540 && y=$((n - 80))
		step="$s: move $a $x $y"
		ctl move "$a" "$x" "$y" || fail "move" ;;
	3 | 4)
		pick 320 && w=$((40 + n))
		pick 250 && h=$((30 + n))
		step="$s: resize $a $w $h"
		visible "$a"
		resize "$a" "$w" "$h" ;;
	5 | 6)
		step="$s: raise $a"
		ctl raise "$a" || fail "raise" ;;
	7)
		step="$s: lower $a"
		ctl lower "$a" || fail "lower" ;;
	8)
		# Bury a under another, b: b grown to hold a when a does not fit (shrinking a
		# instead would soon go below the size foot can take), a moved inside b's box and
		# lowered; then it can show no pixel.
		keep=$a b=$a
		while [ "$b" = "$keep" ]; do
			any
			b=$a
		done
		a=$keep
		step="$s: bury $a under $b"
		window "$a" || fail "window $a gone"
		aw=$ww ah=$wh
		window "$b" || fail "window $b gone"
		if [ "$aw" -gt "$ww" ] || [ "$ah" -gt "$wh" ]; then
			visible "$b"
			resize "$b" $((aw > ww ? aw : ww)) $((ah > wh ? ah : wh))
		fi
		bx=$wx by=$wy bw=$ww bh=$wh
		window "$a"
		pick $((bw - ww + 1)) && x=$((bx + n))
		pick $((bh - wh + 1)) && y=$((by + n))
		ctl move "$a" "$x" "$y" || fail "move"
		ctl lower "$a" || fail "lower"
		window "$a"
		[ "$wstate" = fully-obscured ] || fail "$a inside $b's box and lowered, yet $wstate" ;;
	9)
		# Off the outputs, right or left, or into the hole: covered by what no output
		# shows.
		window "$a" || fail "window $a gone"
		pick 3
		if [ "$n" -eq 2 ] && [ "$ww" -le 320 ] && [ "$wh" -le 240 ]; then
			pick $((320 - ww + 1)) && x=$((hole_x + n))
			pick $((240 - wh + 1)) && y=$((240 + n))
		elif [ "$n" -eq 1 ]; then
			x=$((-ww)) y=$wy
		else
			x=960 y=$wy
		fi
		step="$s: move $a off the outputs to $x,$y"
		ctl move "$a" "$x" "$y" || fail "move"
		window "$a"
		[ "$wstate" = fully-obscured ] || fail "$a off the outputs, yet $wstate" ;;
	esac

	check_step
done

step=end
kill "$vpid"
wait "$vpid"
status=$?
vpid=
[ "$status" -eq 0 ] || fail "viscomp exited with $status"
if grep -q 'ERROR: AddressSanitizer\|ERROR: LeakSanitizer\|runtime error' "$dir/viscomp.log"; then
	fail "sanitizer report"
fi
echo "test-viscomp-pixels: ok"
