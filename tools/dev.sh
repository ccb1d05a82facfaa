#!/usr/bin/env bash
# The two set-up commands of the README:
#   tools/dev.sh demo   install what is missing, build (release), run the main job
#   tools/dev.sh test   install what is missing, build, run every suite, then again under ASan+UBSan
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(gcc meson ninja-build pkg-config libpixman-1-dev libevent-dev libxcb1-dev xvfb)

# Installs the Debian packages that are missing, asking apt only when something is.
install_missing() {
	local missing=()
	for p in "${PACKAGES[@]}"; do
		dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' ||
			missing+=("$p")
	done
	[ ${#missing[@]} -eq 0 ] && return 0
	echo "dev.sh: installing ${missing[*]}" >&2
	local sudo=()
	[ "$(id -u)" -eq 0 ] || sudo=(sudo)
	"${sudo[@]}" apt-get update -qq
	DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq "${missing[@]}" >/dev/null
}

# Configures (once) and builds one build directory.
build() {
	local dir=$1
	shift
	[ -f "$dir/build.ninja" ] || meson setup "$dir" "$@" >/dev/null
	ninja -C "$dir" >/dev/null
}

demo() {
	build build-release --buildtype=release
	scene=$(mktemp --suffix=.scene)
	trap 'rm -f "$scene" "$scene.out"' EXIT
	build-release/client/visctl gen random 10000 1 >"$scene"
	echo "== a generated desktop: 10,000 windows on a 3840x2160 screen ($scene)"
	build-release/client/visctl compute --time "$scene" >"$scene.out"
	echo "== how many windows are in each state:"
	awk '{ n[$2]++ } END { for (s in n) printf "   %-20s %d\n", s, n[s] }' "$scene.out" | sort
	echo "== the windows that can be seen (ID STATE):"
	grep -v fully-obscured "$scene.out" | sed 's/^/   /'
	echo "== the same scene with every engine:"
	for e in auto gmv gmv-heap region; do
		printf '   %-9s ' "$e"
		build-release/client/visctl compute --engine="$e" --time "$scene" 2>&1 >/dev/null
	done
}

run_tests() {
	build build
	meson test -C build --print-errorlogs
	# The sanitizer pass: b_lundef=false because the sanitizer runtimes resolve at run time.
	build build-san -Db_sanitize=address,undefined -Db_lundef=false --buildtype=debug
	UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=1 \
		meson test -C build-san --print-errorlogs --timeout-multiplier 4
}

case "${1:-}" in
demo)
	install_missing
	demo
	;;
test)
	install_missing
	run_tests
	;;
*)
	echo "usage: tools/dev.sh demo|test" >&2
	exit 2
	;;
esac
