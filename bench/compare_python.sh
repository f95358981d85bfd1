#!/usr/bin/env bash
# geomkit from Python against SciPy, and against the Rust call it wraps (issue 23, "Speed"):
# make_interp_spline (N = 10^7 and 10^6, 3-D), BSpline.__call__ (10^7 sorted points),
# RectBivariateSpline 4096^2 (build, grid evaluation), the binding's overhead, agreement.
#
#   bash bench/compare_python.sh            # full run (a few minutes on 2 cores), writes bench/RESULTS-python.md
#   bash bench/compare_python.sh --quick    # smoke test (small sizes, < 1 min once built)
#
# 1. The venv bench/.venv-py (git-ignored): created when missing, tests/python/requirements.txt
#    (the pinned maturin, NumPy 2.4.6, SciPy 1.17.1, ...) installed whenever that file changes.
# 2. `maturin build --release` of python/ (crates/geomkit-py), the abi3 wheel installed into the
#    venv (--force-reinstall --no-deps): the benchmark imports the installed package, as a
#    user would. Then `cargo build --release -p geomkit-bench --bin bspline-compare`.
# 3. bench/compare_python.py: one process per case, the Markdown report to stdout and
#    bench/RESULTS-python.md, raw numbers in bench/results/compare_python.json (git-ignored).
#
# Environment: PYTHON (default python3) creates the venv; CARGO_BUILD_JOBS as for cargo.
# Extra arguments go to compare_python.py (--quick, --note TEXT, --out FILE, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
here=$root/bench

tag=compare_python
# shellcheck source=../tests/lib.sh
source "$root/tests/lib.sh"

# --- 1. the venv --------------------------------------------------------------------------
venv=$here/.venv-py
venv_with "$venv" "$root/tests/python/requirements.txt" "$venv/.requirements.installed"

# --- 2. the wheel and the Rust driver ------------------------------------------------------
target_dir="$(cargo metadata --format-version 1 --no-deps |
    "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
wheels=$target_dir/wheels-bench
install_wheel "$venv" "$wheels"
cargo build --release -p geomkit-bench --bin bspline-compare >&2 ||
    die "cargo build --release -p geomkit-bench failed"

# --- 3. the comparison ---------------------------------------------------------------------
# From bench/, so that `import geomkit` is the installed wheel, never the source tree
# python/geomkit (compare_python.py imports the fixtures of compare_bspline.py beside it).
cd "$here"
exec "$venv/bin/python" "$here/compare_python.py" \
    --rust-bin "$target_dir/release/bspline-compare" \
    --out "$here/RESULTS-python.md" \
    --command "bash bench/compare_python.sh${*:+ $*}" \
    "$@"
