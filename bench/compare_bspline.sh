#!/usr/bin/env bash
# Side-by-side comparison of geomkit's interpolating cubic B-splines (method 2) with SciPy:
# make_interp_spline / BSpline.__call__ / RectBivariateSpline (speed, peak memory, accuracy),
# against the goals of the issue.
#
#   bash bench/compare_bspline.sh            # full run (~6-8 min on 2 cores), writes bench/RESULTS-bspline.md
#   bash bench/compare_bspline.sh --quick    # smoke test (small sizes, < 1 min)
#
# Creates bench/.venv (git-ignored) if missing and installs bench/requirements.txt into it
# (again whenever that file changes), builds the Rust driver with
# `cargo build --release -p geomkit-bench --bin bspline-compare`, runs
# bench/compare_bspline.py (one process per case on each side), prints the Markdown tables
# and writes them to bench/RESULTS-bspline.md (raw numbers: bench/results/compare_bspline.json).
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
cargo build --release -p geomkit-bench --bin bspline-compare >&2
target_dir="$(cargo metadata --format-version 1 --no-deps \
    | "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"

exec "$venv/bin/python" "$here/compare_bspline.py" \
    --rust-bin "$target_dir/release/bspline-compare" \
    --out "$here/RESULTS-bspline.md" \
    --command "bash bench/compare_bspline.sh${*:+ $*}" \
    "$@"
