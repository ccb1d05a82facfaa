#!/bin/sh
# libvisclient must export exactly the functions its public header declares with VIS_EXPORT: the
# protocol library inside it and the private helpers stay hidden.
# Usage: check-exports.sh LIBVISCLIENT.so visclient.h
set -u
lib=${1:?usage: check-exports.sh LIB HEADER}
header=${2:?usage: check-exports.sh LIB HEADER}
T=$(mktemp -d "${TMPDIR:-/tmp}/check-exports.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

# Defined dynamic symbols, without the ones the linker adds to every shared object.
nm -D --defined-only "$lib" | awk '{ print $NF }' |
	grep -vxE '_init|_fini|_edata|_end|__bss_start' | sort -u >"$T/exported" || exit 1
# Declarations may span lines: join the header, then take the name before each '(' that follows
# VIS_EXPORT.
grep -v '^#' "$header" | tr '\n' ' ' | grep -oE 'VIS_EXPORT [^(;]*\(' |
	sed -E 's/.*[ *]([A-Za-z_][A-Za-z_0-9]*)\($/\1/' | sort -u >"$T/declared"

if [ ! -s "$T/declared" ]; then
	echo "no VIS_EXPORT declarations found in $header"
	exit 1
fi
if ! cmp -s "$T/exported" "$T/declared"; then
	echo "exported symbols differ from the header's (< exported only, > declared only):"
	diff "$T/exported" "$T/declared" | grep '^[<>]'
	exit 1
fi
echo "$(wc -l <"$T/exported") symbols, all declared"
