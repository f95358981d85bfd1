#!/usr/bin/env bash
# The Python package's tests (issue 23): builds the extension once (maturin, release, an abi3
# wheel), installs the wheel into a venv and runs the pytest suite of tests/python, then
# SciPy's own test_bsplines.py / test_fitpack2.py with make_interp_spline and
# RectBivariateSpline answered by the package (tests/scipy/run.sh, GEOMKIT_SCIPY_SWAP=python).
#
#   bash tests/python/run.sh            # from anywhere; .ci/test calls it
#
# 1. The venv tests/python/.venv (git-ignored): created when missing, tests/python/requirements.txt
#    (the pinned maturin, NumPy, SciPy, pytest, hypothesis, mypy) installed whenever that file
#    changes.
# 2. `maturin build --release` of python/ (crates/geomkit-py): the one release build of the
#    extension, into target/wheels (cargo's incremental build: about 3 min from nothing at
#    -j1, 1-2 min after a change of the library, seconds when nothing changed); the wheel
#    installed into the venv (--force-reinstall --no-deps), so the tests import the installed
#    package, as a user would, not the source tree.
# 3. mypy --strict over python/geomkit (its annotations and the stub _geomkit.pyi), pytest
#    tests/python (SciPy as the reference), then the SciPy suite in package mode.
#
# Environment: PYTHON (default python3) creates the venv; CARGO_BUILD_JOBS as for cargo.
# Extra arguments go to the pytest run of tests/python (e.g. -k pickle).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
here=$root/tests/python

tag=python
# shellcheck source=../lib.sh
source "$root/tests/lib.sh"
start=$SECONDS

# --- 1. the venv --------------------------------------------------------------------------
venv=$here/.venv
venv_with "$venv" "$here/requirements.txt" "$venv/.requirements.installed"

# --- 2. the wheel -------------------------------------------------------------------------
wheels=$root/target/wheels
install_wheel "$venv" "$wheels"
say "built and installed the wheel in $((SECONDS - start)) s"

# --- 3. the tests -------------------------------------------------------------------------
# The annotations of python/geomkit against the stub of the compiled module, and NumPy's.
(cd "$root/python" && "$venv/bin/python" -m mypy --strict --cache-dir "$venv/.mypy_cache" geomkit) ||
    die "mypy --strict python/geomkit"
# From tests/python, so that `import geomkit` finds the installed package (not python/).
(cd "$here" && "$venv/bin/python" -m pytest -q -p no:cacheprovider "$@") ||
    die "pytest tests/python"
GEOMKIT_SCIPY_SWAP=python GEOMKIT_SCIPY_VENV=$venv bash "$root/tests/scipy/run.sh"
say "ok ($((SECONDS - start)) s in all)"
