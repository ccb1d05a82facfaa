#!/bin/sh
# What visd-x11 changes for unmodified applications under a compositing manager, measured: the
# scenarios of tests/test-realapps.sh (its desktop: tests/realapps.sh), each with visd-x11 and
# without, printed as a markdown table. Alacritty runs a writer printing a line every 10 ms; its
# share of a core is taken over 500 of those lines. i3lock: whether it raises itself over a
# window raised above it. Chromium, where installed (it is large: not in CI): a local page
# (file://) that counts requestAnimationFrame callbacks and writes, once a second, its
# document.visibilityState and the count into its title, read with xprop; its share of a core
# (every process of it) and its frames per second over 6 of those seconds.
# Usage: tools/realapps-bench.sh [BUILD-DIR] (default build); CM=xcompmgr for xcompmgr instead
# of picom; CHROMIUM=PROGRAM for another Chromium (default chromium, else chromium-browser).
build=${1:-build}
cm=${CM:-picom}
here=$(cd "$(dirname "$0")/.." && pwd)
for prog in Xvfb openbox "$cm" alacritty i3lock xwininfo xprop; do
	command -v "$prog" >/dev/null 2>&1 || { echo "realapps-bench: $prog is not installed" >&2; exit 1; }
done
chromium=${CHROMIUM:-}
if [ -z "$chromium" ]; then
	for prog in chromium chromium-browser; do
		command -v $prog >/dev/null 2>&1 && { chromium=$prog; break; }
	done
fi

dir=$(mktemp -d "${TMPDIR:-/tmp}/realapps-bench.XXXXXX") || exit 1
chrome_pid=
cleanup() {
	[ -n "$chrome_pid" ] && kill "$chrome_pid" 2>/dev/null && wait "$chrome_pid" 2>/dev/null
	ra_cleanup
	rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP PIPE

fail() {
	echo "realapps-bench: $1" >&2
	[ -n "${2:-}" ] && sed 's/^/  | /' "$2" >&2
	exit 1
}

. "$here/tests/progress.sh"
. "$here/tests/realapps.sh"
for prog in "$bridge" "$visd" "$visctl" "$cover"; do
	[ -x "$prog" ] || fail "$prog is not built"
done

# Results, a line each: APP|SCENARIO|with|without.
: >"$dir/rows"
row() {
	echo "$1|$2|$3|$4" >>"$dir/rows"
}
# Alacritty's share of a core over 500 lines, settled for 30, as a table cell in $cell.
alacritty_cell() {
	ra_span 500 30
	cell="$pct %"
}

# Alacritty: uncovered, partly covered, covered; then a second one started under the cover.
# WITH: yes or no; the cells in $c_unc $c_part $c_cov $c_start.
alacritty_pass() {
	[ "$1" = yes ] && ra_start_bridge
	ra_start_alacritty "bench-$1-a"
	alacritty_cell
	c_unc=$cell
	geometry=$(xwininfo -id "$app_win" | sed -n 's/.*Absolute upper-left [XY]: *//p' | tr '\n' ' ')
	ra_cover map $(echo "$geometry" | awk '{ print $1 + 20, $2 + 20, 100, 100 }')
	[ "$1" = yes ] && ra_wait_state "$app_win" partially-obscured
	alacritty_cell
	c_part=$cell
	ra_cover map 0 0 $ra_width $ra_height
	[ "$1" = yes ] && ra_wait_state "$app_win" fully-obscured
	alacritty_cell
	c_cov=$cell
	ra_stop_app
	ra_start_alacritty "bench-$1-b"
	[ "$1" = yes ] && ra_wait_state "$app_win" fully-obscured
	alacritty_cell
	c_start=$cell
	ra_stop_app
	ra_cover unmap
	ra_stop_bridge
}

ra_start_x
ra_start_cm "$cm"
echo "realapps-bench: Alacritty under $cm" >&2
alacritty_pass no
n_unc=$c_unc n_part=$c_part n_cov=$c_cov n_start=$c_start
alacritty_pass yes
row Alacritty uncovered "$c_unc" "$n_unc"
row Alacritty "partly covered" "$c_part" "$n_part"
row Alacritty covered "$c_cov" "$n_cov"
row Alacritty "started covered" "$c_start" "$n_start"
# The bridge started late, under the cover: before it, as without; after it.
ra_cover map 0 0 $ra_width $ra_height
ra_start_alacritty bench-late
alacritty_cell
c_before=$cell
ra_start_bridge
ra_wait_state "$app_win" fully-obscured
alacritty_cell
row Alacritty "covered, visd-x11 started late" "$cell" "$c_before (before it)"
ra_stop_app
ra_stop_bridge
ra_cover unmap

# i3lock: a window raised over it, without visd-x11 (for 300 lines of a ticker), then with it.
echo "realapps-bench: i3lock under $cm" >&2
ra_start_ticker
ra_start_i3lock
ra_cover map 0 0 $ra_width $ra_height
ra_lines ticker
wait_progress "$tick_pid $lock_pid $xpid" ra_reached ticker $((lines + 300)) || fail "the ticker stopped"
if ra_lock_on_top; then i_without="raises itself"; else i_without="stays covered"; fi
ra_start_bridge
ra_lines ticker
from=$lines
ra_clock
c0=$ra_cs
if wait_progress "$lock_pid $bpid $vpid $xpid" ra_lock_on_top; then
	ra_clock
	i_with="raises itself ($(((ra_cs - c0) * 10)) ms after visd-x11 starts)"
else
	i_with="stays covered"
fi
row i3lock "covered by a window raised over it" "$i_with" "$i_without"
ra_stop_i3lock
ra_stop_bridge
ra_cover unmap
kill "$tick_pid"
wait "$tick_pid" 2>/dev/null
tick_pid=

# Chromium: the page's title, "vis=STATE frames=F seq=S" (F the frames drawn so far, S the
# seconds), in $title; the window in $cwin.
cat >"$dir/page.html" <<'EOF'
<!doctype html><title>vis=loading frames=0 seq=0</title>
<body style="margin:0"><canvas id=c width=560 height=360></canvas><script>
let frames = 0, seq = 0, hue = 0;
const g = document.getElementById('c').getContext('2d');
function frame() {
	frames++;
	hue = (hue + 3) % 360;
	g.fillStyle = 'hsl(' + hue + ',80%,50%)';
	g.fillRect(0, 0, 560, 360);
	requestAnimationFrame(frame);
}
requestAnimationFrame(frame);
setInterval(function () {
	seq++;
	document.title = 'vis=' + document.visibilityState + ' frames=' + frames + ' seq=' + seq;
}, 1000);
</script>
EOF
chrome_title() {
	title=$(xprop -id "$cwin" WM_NAME 2>/dev/null | sed -n 's/^WM_NAME([^)]*) = "\(.*\)"$/\1/p')
	seq=$(echo "$title" | sed -n 's/.* seq=\([0-9]*\).*/\1/p')
	frames=$(echo "$title" | sed -n 's/.* frames=\([0-9]*\).*/\1/p')
	vis=$(echo "$title" | sed -n 's/^vis=\([a-z]*\) .*/\1/p')
	[ -n "$seq" ] && [ "$seq" -gt 0 ]
}
chrome_ready() {
	cwin=$(xwininfo -root -tree 2>/dev/null | sed -n 's/^ *\(0x[0-9a-f]*\) "vis=.*/\1/p' | head -n 1)
	[ -n "$cwin" ] && chrome_title
}
chrome_seq_at() {
	chrome_title && [ "$seq" -ge "$1" ]
}
# The CPU clock ticks of Chromium's every process (the browser and its descendants).
chrome_ticks() {
	all=$chrome_pid
	new=$chrome_pid
	while [ -n "$new" ]; do
		kids=
		for p in $new; do kids="$kids $(cat /proc/"$p"/task/*/children 2>/dev/null)"; done
		new=$(echo $kids)
		all="$all $new"
	done
	ctick=0
	for p in $all; do
		progress_cpu "$p" 2>/dev/null && ctick=$((ctick + progress_ticks))
	done
}
chrome_start() {
	rm -rf "$dir/profile"
	"$chromium" --no-sandbox --user-data-dir="$dir/profile" --no-first-run \
		--no-default-browser-check --ozone-platform=x11 --window-size=600,400 \
		--window-position=40,40 "file://$dir/page.html" >"$dir/chromium.log" 2>&1 &
	chrome_pid=$!
	wait_progress "$chrome_pid $xpid" chrome_ready || fail "Chromium did not start ($progress_why):" "$dir/chromium.log"
}
chrome_stop() {
	kill "$chrome_pid"
	wait "$chrome_pid" 2>/dev/null
	chrome_pid=
}
# Over the page's next 6 seconds (after 2 of settling): its state, frames a second and Chromium's
# share of a core, as a cell in $cell.
chrome_cell() {
	chrome_title
	wait_progress "$chrome_pid $xpid" chrome_seq_at $((seq + 2)) || fail "the page stopped ($progress_why)"
	chrome_title
	s0=$seq f0=$frames
	chrome_ticks
	t0=$ctick
	ra_clock
	c0=$ra_cs
	wait_progress "$chrome_pid $xpid" chrome_seq_at $((s0 + 6)) || fail "the page stopped ($progress_why)"
	chrome_ticks
	ra_clock
	cpct=$(((ctick - t0) * 1000 / (ra_cs - c0 + 1)))
	cell="$vis, $(((frames - f0) / (seq - s0))) rAF/s, $((cpct / 10)).$((cpct % 10)) %"
}
chrome_pass() {
	[ "$1" = yes ] && ra_start_bridge
	chrome_start
	chrome_cell
	h_unc=$cell
	ra_cover map 100 100 200 150
	[ "$1" = yes ] && ra_wait_state "$cwin" partially-obscured
	chrome_cell
	h_part=$cell
	ra_cover map 0 0 $ra_width $ra_height
	[ "$1" = yes ] && ra_wait_state "$cwin" fully-obscured
	chrome_cell
	h_cov=$cell
	chrome_stop
	chrome_start
	[ "$1" = yes ] && ra_wait_state "$cwin" fully-obscured
	chrome_cell
	h_start=$cell
	chrome_stop
	ra_cover unmap
	ra_stop_bridge
}
if [ -n "$chromium" ]; then
	echo "realapps-bench: Chromium ($($chromium --version 2>/dev/null)) under $cm" >&2
	chrome_pass no
	n_unc=$h_unc n_part=$h_part n_cov=$h_cov n_start=$h_start
	chrome_pass yes
	row Chromium uncovered "$h_unc" "$n_unc"
	row Chromium "partly covered" "$h_part" "$n_part"
	row Chromium covered "$h_cov" "$n_cov"
	row Chromium "started covered" "$h_start" "$n_start"
else
	chromium_note="Chromium is not installed: no Chromium rows."
fi

echo "Under $cm on Xvfb (${ra_width}x${ra_height}), $(date -u +%Y-%m-%d); % is the application's share of a core."
echo
echo "| application | scenario | with visd-x11 | without visd-x11 |"
echo "| --- | --- | --- | --- |"
awk -F'|' '{ printf "| %s | %s | %s | %s |\n", $1, $2, $3, $4 }' "$dir/rows"
[ -n "${chromium_note:-}" ] && { echo; echo "$chromium_note"; }
exit 0
