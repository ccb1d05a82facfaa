#!/bin/sh
# The smoke run of tools/xorg-bench.sh (--quick) on this build: visd and X.Org must end every
# replay in the same states. Skipped (exit 77) where Xvfb is not installed; an unknown scene is
# refused first, before anything is built or started.
# Usage: test-xorg-bench.sh XORG-BENCH.SH BUILD-DIR OUT-DIR
err=$("$1" --scenes random,shaped --build "$2" --out "$3" 2>&1 >/dev/null)
rc=$?
if [ "$rc" -ne 2 ] || ! printf '%s\n' "$err" | grep -q "'shaped' is not random"; then
	echo "xorg-bench --scenes random,shaped: status $rc, '$err'" >&2
	exit 1
fi
command -v Xvfb >/dev/null 2>&1 || { echo "Xvfb not installed: skipped"; exit 77; }
exec "$1" --quick --build "$2" --out "$3"
