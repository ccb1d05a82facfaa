#!/bin/sh
# A library (libvisclient, libvis) must export exactly the functions its public header declares
# with VIS_EXPORT: the protocol library or core inside it and the private helpers stay hidden. And
# each must carry a symbol version from the library's version script (visclient.map, libvis.map):
# a function exported unversioned would bind old programs to whatever comes next under its name.
# Usage: check-exports.sh LIB.so HEADER.h
set -u
lib=${1:?usage: check-exports.sh LIB HEADER}
header=${2:?usage: check-exports.sh LIB HEADER}
T=$(mktemp -d "${TMPDIR:-/tmp}/check-exports.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT

# Defined dynamic symbols as NAME@@VERSION (NAME alone when unversioned), without the ones the
# linker adds to every shared object and the version nodes themselves (absolute symbols).
nm -D --defined-only "$lib" | awk '$2 != "A" { print $NF }' |
	grep -vE '^(_init|_fini|_edata|_end|__bss_start)(@|$)' | sort -u >"$T/versioned" || exit 1
sed 's/@.*//' "$T/versioned" | sort -u >"$T/exported"
if grep -v '@' "$T/versioned" >"$T/unversioned"; then
	echo "exported without a symbol version (the version script must name them):"
	cat "$T/unversioned"
	exit 1
fi
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
nodes=$(sed 's/.*@@*//' "$T/versioned" | sort -u | paste -sd ' ')
echo "$(wc -l <"$T/exported") symbols, all declared and versioned ($nodes)"
