#!/usr/bin/env bash
# Side-by-side comparison of geomkit's point equations (method 4) with SciPy's
# RegularGridInterpolator and BarycentricInterpolator, against the goals of issue 5.
#
#   bash bench/compare_pointcalc.sh            # full run (~2 min; RGI quintic setup alone ~40 s)
#   bash bench/compare_pointcalc.sh --quick    # smoke test (no quintic, fewer points)
#
# Creates bench/.venv (git-ignored) if missing and installs bench/requirements.txt into it
# (again whenever that file changes), builds the Rust driver with
# `cargo build --release -p geomkit-bench --bin pointcalc-compare`, runs
# bench/compare_pointcalc.py, prints the Markdown table and writes it to
# bench/RESULTS-pointcalc.md. Environment: PYTHON (default python3) creates the venv.
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
cargo build --release -p geomkit-bench --bin pointcalc-compare >&2
target_dir="$(cargo metadata --format-version 1 --no-deps \
    | "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"

exec "$venv/bin/python" "$here/compare_pointcalc.py" \
    --rust-bin "$target_dir/release/pointcalc-compare" \
    --command "bash bench/compare_pointcalc.sh${*:+ $*}" \
    "$@"
