# Shared helpers of the test scripts (tests/e2e/run.sh, tests/printers/run.sh); sourced.
# The sourcing script sets `tag` (the prefix of its messages) first.

say() { printf '%s: %s\n' "$tag" "$*" >&2; }
die() {
    say "FAILED: $*"
    exit 1
}

# Runs a command as root (directly, or through sudo when available).
as_root() {
    if [ "$(id -u)" = 0 ]; then
        "$@"
    elif command -v sudo >/dev/null; then
        sudo -n "$@"
    else
        die "need root (or sudo) to run: $*"
    fi
}

# apt-get install (after one apt-get update per run).
apt_updated=
apt_install() {
    if [ -z "$apt_updated" ]; then
        say "apt-get update"
        as_root apt-get update -qq || die "apt-get update failed"
        apt_updated=1
    fi
    say "apt-get install $*"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@" \
        >/dev/null || die "apt-get install $* failed"
}

# Node.js and npm from apt when either is missing.
need_node() {
    if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
        apt_install nodejs npm
    fi
}
