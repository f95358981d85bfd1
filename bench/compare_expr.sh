#!/usr/bin/env bash
# Side-by-side comparison of the expression engine with SymPy + NumPy lambdify(cse=True).
#
#   bash bench/compare_expr.sh [CASE...]     # default: cube bilinear:10 bicubic:10
#
# Creates bench/.venv if missing, installs bench/requirements.txt (pinned) into it, builds
# the driver (cargo build --release -p geomkit-bench --bin expr-compare, target dir
# $CARGO_TARGET_DIR or /tmp/target-expr), runs bench/compare_expr.py, which writes
# bench/RESULTS-expr.md and bench/results/expr/ (git-ignored).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
venv="$here/.venv"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-/tmp/target-expr}"

if [ ! -x "$venv/bin/python" ]; then
    "${PYTHON:-python3}" -m venv "$venv"
fi
stamp="$venv/.requirements.installed"
if ! cmp -s "$here/requirements.txt" "$stamp"; then
    "$venv/bin/python" -m pip install --disable-pip-version-check -q -r "$here/requirements.txt"
    cp "$here/requirements.txt" "$stamp"
fi

cargo build --release -q -p geomkit-bench --bin expr-compare --manifest-path "$here/../Cargo.toml"
EXPR_DRIVER="$CARGO_TARGET_DIR/release/expr-compare" exec "$venv/bin/python" "$here/compare_expr.py" "$@"
