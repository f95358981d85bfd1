#!/usr/bin/env bash
# Reference data for geomkit's integration tests, computed by other libraries: the `bezier`
# package and exact fractions (Bézier), SciPy (interpolating cubic B-splines, and the
# barycentric interpolation of the point equations: make_reference_pointcalc.py; the B-spline
# calculus of issue 22: make_reference_calculus.py).
#
#   bash bench/make_reference.sh            # writes crates/geomkit/tests/data/*.json
#
# Creates bench/.venv (git-ignored) if missing and installs bench/requirements.txt into it
# (again whenever that file changes), then runs bench/make_reference.py, which writes
# bezier_reference.json and bspline_scipy.json, and make_reference_spline.py, which writes
# spline_scipy.json (any degree; deterministic: same versions and CPU, same bytes).
# The files are committed; the Rust tests (crates/geomkit/tests/reference_*.rs) read them
# and never run Python. Environment: PYTHON (default python3) creates the venv.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
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

"$venv/bin/python" "$here/make_reference.py" "$@"
"$venv/bin/python" "$here/make_reference_spline.py"
"$venv/bin/python" "$here/make_reference_calculus.py"
exec "$venv/bin/python" "$here/make_reference_pointcalc.py"
