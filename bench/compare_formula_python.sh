#!/usr/bin/env bash
# geomkit's compiled evaluator of a single composite formula (method 3) from Python against
# SymPy's lambdify(cse=True) of the same formula (issue 23, "Speed"): the paper's cube and a
# 10 x 10 bicubic composite on 10^6 (u, v) points; goals >= 20x and >= 100x.
#
#   bash bench/compare_formula_python.sh           # full run, writes bench/RESULTS-formula-python.md
#   bash bench/compare_formula_python.sh --quick   # smoke test (10^4 points, 3 x 3 composite;
#                                                  # report in bench/results/, git-ignored)
#
# 1. The venv bench/.venv-py (git-ignored, shared with compare_python.sh): created when missing,
#    tests/python/requirements.txt (the pinned maturin, NumPy, SciPy, SymPy, ...) installed
#    whenever that file changes.
# 2. `maturin build --release` of python/ (crates/geomkit-py), the abi3 wheel installed into the
#    venv (--force-reinstall --no-deps): the benchmark imports the installed package, as a
#    user would.
# 3. bench/compare_formula_python.py: one process per library and evaluator, the Markdown report
#    to stdout and the report file, raw numbers in bench/results/compare_formula_python.json.
#
# Environment: PYTHON (default python3) creates the venv; CARGO_BUILD_JOBS as for cargo.
# Extra arguments go to compare_formula_python.py (--quick, --note TEXT, --out FILE, ...).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
here=$root/bench

tag=compare_formula_python
# shellcheck source=../tests/lib.sh
source "$root/tests/lib.sh"

# --- 1. the venv --------------------------------------------------------------------------
venv=$here/.venv-py
venv_with "$venv" "$root/tests/python/requirements.txt" "$venv/.requirements.installed"

# --- 2. the wheel --------------------------------------------------------------------------
target_dir="$(cargo metadata --format-version 1 --no-deps |
    "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
wheels=$target_dir/wheels-bench
install_wheel "$venv" "$wheels"

# --- 3. the comparison ---------------------------------------------------------------------
# From bench/, so that `import geomkit` is the installed wheel, never the source tree.
cd "$here"
exec "$venv/bin/python" "$here/compare_formula_python.py" \
    --command "bash bench/compare_formula_python.sh${*:+ $*}" \
    "$@"
