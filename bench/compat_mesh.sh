#!/usr/bin/env bash
# Independent check of geomkit's mesh writers with trimesh, meshio and manifold3d: vertex/face
# counts, watertightness and volumes of the closed bodies (the cube's volume is 8) in every
# format, every OBJ read by meshio, and the --obj-normals layouts.
#
#   bash bench/compat_mesh.sh               # builds geomkit (release), runs the demo into a
#                                           # temporary folder, checks its meshes, prints a table
#
# Creates bench/.venv (git-ignored) if missing and installs bench/requirements.txt into it
# (again whenever that file changes). Exit code 1 if any check fails.
# Environment: PYTHON (default python3) creates the venv; GEOMKIT: a geomkit binary to use
# instead of building one.
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
if [ -z "${GEOMKIT:-}" ]; then
    cargo build --release -q -p geomkit-cli
    GEOMKIT="$(cargo metadata --format-version 1 --no-deps | "$venv/bin/python" -c \
        'import json,sys; print(json.load(sys.stdin)["target_directory"])')/release/geomkit"
fi
exec "$venv/bin/python" "$here/compat_mesh.py" "$GEOMKIT"
