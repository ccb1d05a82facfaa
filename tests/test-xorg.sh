#!/bin/sh
# Runs test-xorg against a private Xvfb (a real X.Org server) on a small screen, so that many
# edges coincide; skipped (exit 77) where Xvfb is not installed.
test_xorg=$1
visd=${2:-}
command -v Xvfb >/dev/null 2>&1 || { echo "Xvfb not installed: skipped"; exit 77; }
dir=$(mktemp -d) || exit 1
exec 3>"$dir/display"
Xvfb -displayfd 3 -screen 0 48x32x24 -nolisten tcp -noreset >"$dir/log" 2>&1 &
xpid=$!
vpid=
trap 'kill $xpid $vpid 2>/dev/null; wait $xpid $vpid 2>/dev/null; rm -rf "$dir"' EXIT
# wait_progress PIDS COMMAND: COMMAND until it succeeds, while the processes named work.
. "$(dirname "$0")/progress.sh"
wait_progress "$xpid" test -s "$dir/display" ||
	{ echo "Xvfb did not start ($progress_why):"; cat "$dir/log"; exit 1; }
display=$(head -n 1 "$dir/display")
# A visd with the same screen, for the trees made in both.
set --
if [ -n "$visd" ]; then
	"$visd" --socket "$dir/visd" --screen 48x32 2>"$dir/visd.log" &
	vpid=$!
	wait_progress "$vpid" test -S "$dir/visd" ||
		{ echo "visd did not start ($progress_why):"; cat "$dir/visd.log"; exit 1; }
	set -- --visd "$dir/visd"
fi
DISPLAY=":$display" "$test_xorg" --count 400 "$@"
