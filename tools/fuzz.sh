#!/usr/bin/env bash
# Fuzzes the libFuzzer targets of tests/fuzz (codec, scene, client) for a given time:
#   tools/fuzz.sh TARGET SECONDS [LIBFUZZER-OPTION...]   one target
#   tools/fuzz.sh all SECONDS [LIBFUZZER-OPTION...]      each in turn, SECONDS each
# Installs clang and its fuzzer runtime when missing, builds build-fuzz/ (CC=clang, -Dfuzz=true,
# ASan+UBSan) and runs each target on a scratch copy of its committed corpus, fuzz-out/TARGET/
# corpus, which keeps growing from run to run. Findings (crash-*, leak-*, timeout-*, oom-*) land
# in fuzz-out/TARGET/; reproduce one with build-fuzz/tests/fuzz/fuzz-TARGET FILE. Fold new
# coverage back into the committed corpus, keeping it small, with
#   build-fuzz/tests/fuzz/fuzz-TARGET -merge=1 tests/fuzz/corpus/TARGET fuzz-out/TARGET/corpus
# One fuzzer process at a time, one job: the machine is shared.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGETS=(codec scene client)

usage() {
	echo "usage: tools/fuzz.sh codec|scene|client|all SECONDS [LIBFUZZER-OPTION...]" >&2
	exit 2
}

# Whether clang links a libFuzzer target (the runtime is a package of its own on Debian).
links_fuzzer() {
	local tmp rc=0
	tmp=$(mktemp -d)
	echo 'int LLVMFuzzerTestOneInput(const char *d, unsigned long n) { return d && n; }' \
		>"$tmp/t.c"
	clang -fsanitize=fuzzer,address,undefined -o "$tmp/t" "$tmp/t.c" 2>/dev/null || rc=1
	rm -rf "$tmp"
	return $rc
}

# Installs what the build needs, and clang with its fuzzer runtime (a package of its own).
install_missing() {
	tools/dev.sh install
	tools/dev.sh install clang
	if ! links_fuzzer; then
		tools/dev.sh install "libclang-rt-$(clang -dumpversion | cut -d. -f1)-dev"
		links_fuzzer || { echo "fuzz.sh: clang cannot link libFuzzer targets" >&2; exit 1; }
	fi
}

# Runs one target for the given seconds; returns libFuzzer's status.
fuzz() {
	local target=$1 seconds=$2
	shift 2
	local out=fuzz-out/$target
	mkdir -p "$out/corpus"
	cp -n tests/fuzz/corpus/"$target"/* "$out/corpus/"
	echo "== fuzz-$target for ${seconds}s on $out/corpus ($(find "$out/corpus" -type f | wc -l) inputs)"
	local rc=0
	UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
		"build-fuzz/tests/fuzz/fuzz-$target" -max_total_time="$seconds" -print_final_stats=1 \
		-artifact_prefix="$out/" "$@" "$out/corpus" || rc=$?
	local found=()
	mapfile -t found < <(find "$out" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' \
		-o -name 'timeout-*' -o -name 'oom-*' \) | sort)
	if [ ${#found[@]} -gt 0 ]; then
		echo "== fuzz-$target: findings (reproduce with build-fuzz/tests/fuzz/fuzz-$target FILE):"
		printf '   %s\n' "${found[@]}"
	fi
	echo "== fuzz-$target: status $rc; new inputs in $out/corpus"
	return $rc
}

[ $# -ge 2 ] || usage
target=$1 seconds=$2
shift 2
case "$seconds" in '' | *[!0-9]*) usage ;; esac
case "$target" in
all) targets=("${TARGETS[@]}") ;;
codec | scene | client) targets=("$target") ;;
*) usage ;;
esac

install_missing
[ -f build-fuzz/build.ninja ] ||
	CC=clang meson setup build-fuzz -Dfuzz=true -Db_sanitize=address,undefined -Db_lundef=false \
		--buildtype=debugoptimized >/dev/null
ninja -C build-fuzz "${targets[@]/#/tests/fuzz/fuzz-}" >/dev/null

status=0
for t in "${targets[@]}"; do
	fuzz "$t" "$seconds" "$@" || status=1
done
exit $status
