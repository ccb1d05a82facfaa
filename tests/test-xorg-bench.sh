#!/bin/sh
# The smoke run of tools/xorg-bench.sh (--quick) on this build: visd and X.Org must end every
# replay in the same states. Skipped (exit 77) where Xvfb is not installed.
# Usage: test-xorg-bench.sh XORG-BENCH.SH BUILD-DIR OUT-DIR
command -v Xvfb >/dev/null 2>&1 || { echo "Xvfb not installed: skipped"; exit 77; }
exec "$1" --quick --build "$2" --out "$3"
