#!/bin/sh
# A shared library must keep the ABI of its last release (the soname promises it): abidiff
# (Debian's abigail-tools) compares the library built with the baseline committed in tests/abi/,
# an abidw dump of the last release's, over the types of the public headers. Added functions pass
# (they come under a new symbol version: client/lib/visclient.map, src/libvis.map); any other
# change fails: a removed or changed function, a struct that grew or changed a field, a changed
# enum value, a symbol that lost its version. Skipped (77) without abidiff, or when the library
# has no debug information to read types from (a release build).
# At a release, the baseline is renewed from the library released:
#   abidw --no-corpus-path --no-comp-dir-path --short-locs --headers-dir include/vis \
#     --drop-private-types --out-file tests/abi/NAME-SOVERSION-baseline.xml BUILD/.../LIB
# Usage: check-abi.sh BASELINE.xml LIB.so HEADERS-DIR
set -u
base=${1:?usage: check-abi.sh BASELINE.xml LIB.so HEADERS-DIR}
lib=${2:?}
headers=${3:?}
if ! command -v abidiff >/dev/null; then
	echo "abidiff not found (Debian's abigail-tools): skipped"
	exit 77
fi
if ! readelf -S "$lib" | grep -q '\.debug_info'; then
	echo "$lib has no debug information: skipped"
	exit 77
fi
abidiff --no-added-syms --drop-private-types --headers-dir2 "$headers" "$base" "$lib"
status=$?
# abidiff's status: bit 1 an error, 2 a usage error, 4 an ABI change, 8 an incompatible one.
if [ "$status" -ne 0 ]; then
	echo "FAIL: $lib differs from the ABI of $base (abidiff status $status)"
	exit 1
fi
echo "$lib keeps the ABI of $base"
