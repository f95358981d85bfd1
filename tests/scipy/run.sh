#!/usr/bin/env bash
# SciPy's own interpolation tests against geomkit (issue 22, acceptance): test_bsplines.py and
# test_fitpack2.py of the installed SciPy wheel, with make_interp_spline answered by `geomkit
# interpolate curve --form scipy` and RectBivariateSpline (s=0) by `geomkit interpolate
# surface --heights` (tests/scipy/swap.py, swapped in by the pytest plugin tests/scipy/plugin.py).
#
#   bash tests/scipy/run.sh            # from anywhere; .ci/test calls it after the Rust tests
#
# 1. The venv bench/.venv (git-ignored), as bench/make_reference.sh makes it: created when
#    missing, bench/requirements.txt (the pinned SciPy and NumPy) installed whenever that
#    file changes; then tests/scipy/requirements.txt (the pinned pytest) unless present.
# 2. The release CLI (cargo build --release -p geomkit-cli), unless GEOMKIT_BIN names one.
# 3. pytest over scipy.interpolate.tests.test_bsplines and .test_fitpack2: the tests that call
#    make_interp_spline or RectBivariateSpline run (the others are deselected), each through
#    the CLI (SciPy's BSpline and bispev evaluate the knots and coefficients). Those listed
#    in tests/scipy/expected.txt (gaps of issue 22, and tests that do not apply, with their
#    reasons) must fail; every other one must pass. A summary ends the output.
#
# Environment: PYTHON (default python3) creates the venv; GEOMKIT_BIN (default
# target/release/geomkit); GEOMKIT_SCIPY_SELECT=all runs the whole modules and checks that no
# deselected test calls a swapped function. Extra arguments go to pytest (e.g. -k periodic,
# --tb=long).
#
# GEOMKIT_SCIPY_SWAP=python: the second mode (issue 23): the two answered by the Python
# package (tests/scipy/swap_python.py), whose objects then do all the rest (geomkit's BSpline
# and RectBivariateSpline, not SciPy's); expected failures in tests/scipy/expected-python.txt.
# It runs in the venv GEOMKIT_SCIPY_VENV (default tests/python/.venv), which must hold the
# package: tests/python/run.sh builds and installs it there, then calls this mode.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
here=$root/tests/scipy

tag=scipy
# shellcheck source=../lib.sh
source "$root/tests/lib.sh"
start=$SECONDS

mode=${GEOMKIT_SCIPY_SWAP:-cli}
if [ "$mode" = python ]; then
    # --- 1-2. the Python package's venv (made by tests/python/run.sh) ---------------------
    venv=${GEOMKIT_SCIPY_VENV:-$root/tests/python/.venv}
    "$venv/bin/python" -c 'import geomkit' 2>/dev/null ||
        die "no geomkit package in $venv: run bash tests/python/run.sh (it installs it, then runs this)"
    what=$("$venv/bin/python" -c 'import geomkit; print(geomkit.__file__)')
else
    [ "$mode" = cli ] || die "GEOMKIT_SCIPY_SWAP=$mode: expected cli or python"
    # --- 1. the venv (bench/make_reference.sh's logic) ------------------------------------
    venv=$root/bench/.venv
    venv_with "$venv" "$root/bench/requirements.txt" "$venv/.requirements.installed"
    venv_with "$venv" "$here/requirements.txt" "$venv/.scipy-tests-requirements.installed"

    # --- 2. the CLI -----------------------------------------------------------------------
    if [ -z "${GEOMKIT_BIN:-}" ]; then
        cargo build --release --quiet -p geomkit-cli || die "cargo build --release -p geomkit-cli failed"
        export GEOMKIT_BIN=$root/target/release/geomkit
    fi
    [ -x "$GEOMKIT_BIN" ] || die "no geomkit binary at $GEOMKIT_BIN"
    what=$GEOMKIT_BIN
fi
versions=$("$venv/bin/python" -c 'import numpy, pytest, scipy
print(f"scipy {scipy.__version__}, numpy {numpy.__version__}, pytest {pytest.__version__}")')
say "$mode mode: $versions, $what"

# --- 3. SciPy's tests ---------------------------------------------------------------------
tests=$SECONDS
status=0
# NumPy only (no other array API backend); no cache directory in the work tree.
env -u SCIPY_ARRAY_API GEOMKIT_SCIPY_SWAP="$mode" PYTHONPATH="$here${PYTHONPATH:+:$PYTHONPATH}" \
    "$venv/bin/python" -m pytest -q -p no:cacheprovider -p plugin \
    -W ignore::pytest.PytestUnknownMarkWarning --tb=short -rN \
    --pyargs scipy.interpolate.tests.test_bsplines scipy.interpolate.tests.test_fitpack2 "$@" ||
    status=$?
[ "$status" -eq 0 ] ||
    die "SciPy's tests through geomkit, $mode mode (above: UNEXPECTED or SELECTION lines)"
say "ok ($((SECONDS - tests)) s of tests, $((SECONDS - start)) s in all)"
