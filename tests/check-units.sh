#!/bin/sh
# The systemd user units as built: visd.service runs the installed visd (meson's bindir), and
# visd.socket listens where visd and its clients look by default, $XDG_RUNTIME_DIR/visd-0 (%t is
# the runtime directory), for its owner only. Where systemd-analyze is installed, both must pass
# `systemd-analyze verify` without a word about them (it runs on copies whose ExecStart is this
# build's visd, since the installed one need not exist yet).
# Usage: check-units.sh VISD.SERVICE VISD.SOCKET BINDIR VISD
set -u
service=${1:?usage: check-units.sh SERVICE SOCKET BINDIR VISD}
socket=${2:?}
bindir=${3:?}
visd=${4:?}
failed=0
fail() {
	echo "FAIL: $*"
	failed=1
}
# has FILE LINE: FILE holds exactly LINE.
has() { grep -qxF -- "$2" "$1" || fail "$(basename "$1") lacks '$2'"; }

has "$service" "ExecStart=$bindir/visd"
[ "$(grep -c '^ExecStart=' "$service")" -eq 1 ] || fail "visd.service has more than one ExecStart"
has "$service" "NoNewPrivileges=yes"
has "$socket" "ListenStream=%t/visd-0"
has "$socket" "SocketMode=0600"
has "$socket" "WantedBy=sockets.target"
if grep -q '@[a-z]*@' "$service"; then fail "visd.service was not configured: $(grep '@' "$service")"; fi

if command -v systemd-analyze >/dev/null; then
	T=$(mktemp -d "${TMPDIR:-/tmp}/check-units.XXXXXX") || exit 1
	trap 'rm -rf "$T"' EXIT
	visd_abs=$(cd "$(dirname "$visd")" && pwd)/$(basename "$visd")
	sed "s|^ExecStart=.*|ExecStart=$visd_abs|" "$service" >"$T/visd.service"
	cp "$socket" "$T/visd.socket"
	# The system manager's scope: a user manager's needs a session bus that CI does not have.
	# Unknown keys are only warned about, so any word about the units fails too.
	if ! (cd "$T" && systemd-analyze verify --man=no ./visd.socket ./visd.service) >"$T/out" 2>&1 ||
		grep -q 'visd\.' "$T/out"; then
		fail "systemd-analyze verify: $(cat "$T/out")"
	fi
else
	echo "note: systemd-analyze is not installed; the units' syntax went unchecked"
fi
[ $failed -eq 0 ] && echo "units: every check passed"
exit $failed
