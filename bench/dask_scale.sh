#!/usr/bin/env bash
# geomkit.dask at scale (issue 24): a LocalCluster of 2 workers with a memory limit each
# resamples a 16384^2 heights grid to 32768^2 and a 10^9-point series to 2x, Zarr to Zarr on
# local disk; windows across chunk seams checked against SciPy in memory; wall time, peak
# memory per worker, SciPy's time where it fits in memory (bench/dask_scale.py).
#
#   bash bench/dask_scale.sh                                     # the issue's sizes (long: disk
#                                                                # ~30 GB, memory 2 x 3 GB)
#   bash bench/dask_scale.sh --n 2048 --chunk 512 --series 4000000 --series-chunk 500000
#                                                                # small: to see it work
#
# 1. The venv bench/.venv-py (git-ignored; the one of compare_python.sh): created when
#    missing, tests/python/requirements.txt (NumPy, SciPy, dask, distributed, zarr, ... pinned)
#    installed whenever that file changes.
# 2. `maturin build --release` of python/, the abi3 wheel installed into the venv.
# 3. bench/dask_scale.py with the arguments given (--n, --chunk, --series, --series-chunk,
#    --memory-limit, --workers, --windows, --jobs grid,series, --no-scipy, --keep): the
#    Markdown rows to stdout (paste them into bench/RESULTS-dask.md), raw numbers in
#    bench/results/dask_scale.json (git-ignored).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
here=$root/bench

tag=dask_scale
# shellcheck source=../tests/lib.sh
source "$root/tests/lib.sh"

venv=$here/.venv-py
venv_with "$venv" "$root/tests/python/requirements.txt" "$venv/.requirements.installed"
target_dir="$(cargo metadata --format-version 1 --no-deps |
    "$venv/bin/python" -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')"
install_wheel "$venv" "$target_dir/wheels-bench"

# From bench/, so that `import geomkit` is the installed wheel, not the source tree.
cd "$here"
exec "$venv/bin/python" "$here/dask_scale.py" "$@"
