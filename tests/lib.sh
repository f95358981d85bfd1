# Shared helpers of the test scripts (tests/e2e, tests/printers, tests/scipy run.sh); sourced.
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

# A Python venv at $1 (created with ${PYTHON:-python3} when missing) with the pinned
# requirements file $2 installed, again whenever the file changes (the copy kept as the
# stamp file $3).
venv_with() {
    local venv=$1 requirements=$2 stamp=$3
    if [ ! -x "$venv/bin/python" ]; then
        say "creating the venv $venv"
        "${PYTHON:-python3}" -m venv "$venv" || die "python3 -m venv failed (apt-get install python3-venv?)"
    fi
    if ! cmp -s "$requirements" "$stamp"; then
        say "pip install -r $requirements"
        "$venv/bin/python" -m pip install --disable-pip-version-check -q -r "$requirements" ||
            die "pip install -r $requirements failed"
        cp "$requirements" "$stamp"
    fi
}

# Builds the release abi3 wheel of the Python package (python/, crates/geomkit-py) into the
# directory $2 with the venv $1's maturin and installs it into that venv (--force-reinstall
# --no-deps: the package as a user installs it, never the source tree). Needs $root.
install_wheel() {
    local venv=$1 wheels=$2 wheel
    rm -f "$wheels"/geomkit-*.whl
    say "maturin build --release (python/, crates/geomkit-py)"
    (cd "$root/python" && "$venv/bin/maturin" build --release --quiet --out "$wheels") ||
        die "maturin build --release failed"
    wheel=$(ls "$wheels"/geomkit-*-abi3-*.whl) || die "no abi3 wheel in $wheels"
    "$venv/bin/python" -m pip install --disable-pip-version-check -q --force-reinstall --no-deps \
        "$wheel" || die "pip install $wheel failed"
}
