#!/usr/bin/env bash
# Independent check of geomkit's STEP export and import with OpenCASCADE (cadquery-ocp): every
# exported file transfers, is valid (BRepCheck_Analyzer), evaluates like geomkit at 1000
# parameters, bodies are closed solids of the exact volume; files written by OCCT (a B-spline
# surface, a Bézier curve, a box) import into geomkit and evaluate like OCCT.
#
#   bash bench/compat_step.sh                    # builds geomkit (release), prints a table
#   bash bench/compat_step.sh --fixtures DIR     # also writes the OCCT-made .step files to DIR
#
# Creates bench/.venv-step (git-ignored; the OCP wheel is a few hundred MB, ~20 s to install
# from PyPI) with bench/requirements-step.txt. Exit code 1 if any check fails.
# Environment: PYTHON (default python3) creates the venv; GEOMKIT: a geomkit binary to use
# instead of building one.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$here")"
venv="$here/.venv-step"

if [ ! -x "$venv/bin/python" ]; then
    echo "creating $venv" >&2
    "${PYTHON:-python3}" -m venv "$venv"
fi
stamp="$venv/.requirements.installed"
if ! cmp -s "$here/requirements-step.txt" "$stamp"; then
    echo "installing bench/requirements-step.txt into $venv" >&2
    "$venv/bin/python" -m pip install --disable-pip-version-check -q -r "$here/requirements-step.txt"
    cp "$here/requirements-step.txt" "$stamp"
fi

cd "$root"
if [ -z "${GEOMKIT:-}" ]; then
    cargo build --release -q -p geomkit-cli
    GEOMKIT="$(cargo metadata --format-version 1 --no-deps | "$venv/bin/python" -c \
        'import json,sys; print(json.load(sys.stdin)["target_directory"])')/release/geomkit"
fi
exec "$venv/bin/python" "$here/compat_step.py" "$GEOMKIT" "$@"
