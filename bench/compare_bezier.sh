#!/usr/bin/env bash
# Side-by-side comparison of geomkit's Bézier degree change / evaluation with the Python
# packages `bezier` and `geomdl` (speed and accuracy against exact Fractions).
#
#   bash bench/compare_bezier.sh            # full run (~3-5 min on 2 cores), writes bench/RESULTS.md
#   bash bench/compare_bezier.sh --quick    # smoke test (few samples)
#
# Creates bench/.venv (git-ignored) if missing and installs bench/requirements.txt into it
# (again whenever that file changes), builds the Rust driver with
# `cargo build --release -p geomkit-bench`, runs bench/compare_bezier.py, prints the Markdown
# table and writes it to bench/RESULTS.md (raw numbers: bench/results/compare.json).
# Environment: PYTHON (default python3) creates the venv.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
venv="$here/.venv"

if [ ! -x "$venv/bin/python" ]; then
    echo "creating $venv" >&2
    "${PYTHON:-python3}" -m venv "$venv"
fi
stamp="$venv/.requirements.installed"
if ! cmp -s "$here/requirements.txt" "$stamp"; then
    echo "installing bench/requirements.txt into $venv" >&2
    "$venv/bin/python" -m pip install --disable-pip-version-check -q -r "$here/requirements.txt"
    cp "$here/requirements.txt" "$stamp"
fi

cd "$root"
cargo build --release -p geomkit-bench --bin bezier-compare >&2
target_dir="$(cargo metadata --format-version 1 --no-deps \
    | "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"

exec "$venv/bin/python" "$here/compare_bezier.py" \
    --rust-bin "$target_dir/release/bezier-compare" \
    --out "$here/RESULTS.md" \
    --command "bash bench/compare_bezier.sh${*:+ $*}" \
    "$@"
