"""geomkit.dask at scale (issue 24): a heights grid and a long series resampled by a
dask.distributed LocalCluster with a memory limit per worker, written to Zarr on local disk,
checked against in-memory solves of sampled windows, with the peak memory of every worker.

    bash bench/dask_scale.sh                 # the issue's sizes: 16384^2 -> 32768^2, 10^9 -> 2x
    bash bench/dask_scale.sh --n 2048 --series 4000000   # small, to see it work

Each job: (1) the input generated chunk by chunk (a smooth field plus noise, deterministic per
chunk) and written to Zarr; (2) timed: the input read from Zarr, the spline's coefficients
solved chunk by chunk with the halo, evaluated on the finer grid chunk by chunk and written
to Zarr (one dask graph, nothing gathered); (3) windows across chunk seams read back from the
output and compared with SciPy's make_interp_spline (not-a-knot, as geomkit's) solved in memory
over the window's neighbourhood (a margin of 160 points: 0.268^160 = 1e-91, the global solve
to the last bit), relative to max|reference|; (4) SciPy's time for the whole job in memory in
a child process (RectBivariateSpline(s=0) for the grid, make_interp_spline + BSpline for the
series) when its estimated memory fits in the available memory, else the estimate and why not.

Peak memory per worker: the largest RSS of each worker process, sampled every 0.2 s from
the client (psutil through Client.run), and the bytes each worker spilled to disk (the
workers' own metrics).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import dask
import dask.array as da
import distributed
import numpy as np
import psutil
import scipy
import scipy.interpolate as si
import zarr

import geomkit
import geomkit.dask as gd

HERE = Path(__file__).resolve().parent
MARGIN = 160  # points of neighbourhood around a checked window (0.268^160 = 1e-91)


def field(block: np.ndarray, block_info: dict | None = None) -> np.ndarray:
    """One chunk of the synthetic heights: smooth terrain plus noise seeded by the chunk."""
    info = block_info[None]
    loc = info["array-location"]
    idx = [np.arange(a, b, dtype=np.float64) for a, b in loc]
    seed = hash(tuple(a for a, _ in loc)) & 0xFFFFFFFF
    rng = np.random.default_rng(seed)
    if len(idx) == 1:
        (i,) = idx
        smooth = np.sin(i / 700.0) + 0.3 * np.cos(i / 53.0)
    else:
        i, j = idx
        smooth = np.sin(i[:, None] / 700.0) * np.cos(j[None, :] / 900.0) + 0.2 * np.sin(
            (i[:, None] + 2.0 * j[None, :]) / 97.0)
    return smooth + 0.01 * rng.standard_normal(smooth.shape)


class MemorySampler:
    """The largest RSS of each worker process and the most bytes each spilled to disk."""

    def __init__(self, client: distributed.Client, every: float = 0.2) -> None:
        self.client, self.every = client, every
        self.peak: dict[str, int] = {}
        self.spilled: dict[str, int] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        while not self._stop.is_set():
            try:
                rss = self.client.run(lambda: psutil.Process().memory_info().rss)
                for w, v in rss.items():
                    self.peak[w] = max(self.peak.get(w, 0), v)
                for w, info in self.client.scheduler_info()["workers"].items():
                    disk = info.get("metrics", {}).get("spilled_bytes", {}).get("disk", 0)
                    self.spilled[w] = max(self.spilled.get(w, 0), disk)
            except Exception:  # noqa: BLE001 (a worker restarting: keep sampling)
                pass
            self._stop.wait(self.every)

    def __enter__(self) -> MemorySampler:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


def gib(b: float) -> str:
    return f"{b / 2**30:.2f} GiB"


def seams(n: int, chunk: int, count: int, rng: np.random.Generator) -> list[int]:
    """Input indices at chunk seams (and the two true ends) to centre checked windows on."""
    inner = list(range(chunk, n, chunk))
    picks = list(rng.choice(inner, size=min(count, len(inner)), replace=False)) if inner else []
    return sorted({0, n - 1, *map(int, picks)})


def make_input(shape: tuple[int, ...], chunk: int, src: Path) -> float:
    """The synthetic input written to Zarr chunk by chunk; the seconds it took."""
    t0 = time.perf_counter()
    data = da.map_blocks(field, da.empty(shape, chunks=chunk, dtype=np.float64),
                         dtype=np.float64)
    da.to_zarr(data, str(src), overwrite=True)
    return time.perf_counter() - t0


def timed_write(client: distributed.Client, out: da.Array, dst: Path
                ) -> tuple[float, MemorySampler]:
    """The whole job (read, solve, evaluate, write) timed, the workers' memory sampled."""
    with MemorySampler(client) as mem:
        t0 = time.perf_counter()
        gd.to_zarr(out, str(dst), overwrite=True)
        wall = time.perf_counter() - t0
    return wall, mem


# -- the grid ---------------------------------------------------------------------------------
def grid_job(args: argparse.Namespace, client: distributed.Client, work: Path) -> dict:
    n, chunk, m = args.n, args.chunk, args.factor * args.n
    x = np.arange(n, dtype=np.float64)
    new = np.linspace(0.0, n - 1.0, m)
    src, dst = work / "grid-in.zarr", work / "grid-out.zarr"
    generate = make_input((n, n), chunk, src)
    out = gd.resample(da.from_zarr(str(src)), (x, x), (new, new), chunks=args.factor * chunk)
    wall, mem = timed_write(client, out, dst)

    # Windows across chunk seams against SciPy in memory over their neighbourhood.
    zin, zout = zarr.open_array(str(src), mode="r"), zarr.open_array(str(dst), mode="r")
    rng = np.random.default_rng(24)
    worst, checked = 0.0, 0
    rows, cols = seams(n, chunk, args.windows, rng), seams(n, chunk, args.windows, rng)
    for r, c in zip(rows, cols[::-1]):
        i0, i1 = max(r - 4, 0), min(r + 4, n - 1)
        j0, j1 = max(c - 4, 0), min(c + 4, n - 1)
        oi = np.flatnonzero((new >= i0) & (new <= i1))
        oj = np.flatnonzero((new >= j0) & (new <= j1))
        a, b = max(i0 - MARGIN, 0), min(i1 + 1 + MARGIN, n)
        p, q = max(j0 - MARGIN, 0), min(j1 + 1 + MARGIN, n)
        block = zin[a:b, p:q]
        along = si.make_interp_spline(x[a:b], block, k=3, axis=0)(new[oi])
        ref = si.make_interp_spline(x[p:q], along, k=3, axis=1)(new[oj])
        got = zout[oi[0]:oi[-1] + 1, oj[0]:oj[-1] + 1]
        worst = max(worst, float(np.abs(got - ref).max() / np.abs(ref).max()))
        checked += got.size
    return {
        "job": "grid", "n": n, "chunk": chunk, "out": m, "out_chunk": args.factor * chunk,
        "input_bytes": 8 * n * n, "output_bytes": 8 * m * m, "generate_s": generate,
        "wall_s": wall, "peak_rss": mem.peak, "spilled_disk": mem.spilled,
        "windows": len(rows), "points_checked": checked, "max_rel_diff": worst,
        "scipy": scipy_job(args, "grid", n, m),
    }


# -- the series -------------------------------------------------------------------------------
def series_job(args: argparse.Namespace, client: distributed.Client, work: Path) -> dict:
    n, chunk = args.series, args.series_chunk
    xs = gd.Regular(0.0, 1.0, n)
    new = gd.Regular(0.0, 0.5, 2 * n - 1)
    src, dst = work / "series-in.zarr", work / "series-out.zarr"
    generate = make_input((n,), chunk, src)
    out = gd.resample(da.from_zarr(str(src)), [xs], [new], chunks=2 * chunk)
    wall, mem = timed_write(client, out, dst)

    yin, yout = zarr.open_array(str(src), mode="r"), zarr.open_array(str(dst), mode="r")
    rng = np.random.default_rng(24)
    worst, checked = 0.0, 0
    for s in seams(n, chunk, args.windows, rng):
        lo, hi = max(s - 64, 0), min(s + 64, n - 1)
        # Output point k sits at k / 2: the points in [lo, hi].
        k0, k1 = 2 * lo, 2 * hi + 1
        a, b = max(lo - MARGIN, 0), min(hi + 1 + MARGIN, n)
        xa = xs.at(np.arange(a, b))
        ref = si.make_interp_spline(xa, yin[a:b], k=3)(new.at(np.arange(k0, k1)))
        got = yout[k0:k1]
        worst = max(worst, float(np.abs(got - ref).max() / np.abs(ref).max()))
        checked += got.size
    return {
        "job": "series", "n": n, "chunk": chunk, "out": 2 * n - 1, "out_chunk": 2 * chunk,
        "input_bytes": 8 * n, "output_bytes": 8 * (2 * n - 1), "generate_s": generate,
        "wall_s": wall, "peak_rss": mem.peak, "spilled_disk": mem.spilled,
        "windows": len(seams(n, chunk, args.windows, np.random.default_rng(24))),
        "points_checked": checked, "max_rel_diff": worst,
        "scipy": scipy_job(args, "series", n, 2 * n - 1),
    }


# -- SciPy in memory, in a child process -------------------------------------------------------
def scipy_need(job: str, n: int, m: int) -> int:
    """Bytes SciPy's in-memory job needs at least: input, coefficients, output, and the
    solver's work arrays (the banded LU of make_interp_spline: 7 rows of n; FITPACK's surface
    work arrays about 4 n^2 for RectBivariateSpline on a grid)."""
    if job == "grid":
        return 8 * (n * n + n * n + 4 * n * n + m * m)
    return 8 * (n + n + 7 * n + m + m)


def scipy_job(args: argparse.Namespace, job: str, n: int, m: int) -> dict:
    need = scipy_need(job, n, m)
    available = psutil.virtual_memory().available
    if args.no_scipy:
        return {"ran": False, "why": "--no-scipy", "need_bytes": need}
    if need > 0.8 * available:
        return {"ran": False, "need_bytes": need, "available_bytes": available,
                "why": f"needs at least {gib(need)} in one process, {gib(available)} available"}
    work = Path(args.workdir)
    src = work / ("grid-in.zarr" if job == "grid" else "series-in.zarr")
    proc = subprocess.run(
        [sys.executable, __file__, "--scipy-child", job, "--scipy-src", str(src),
         "--factor", str(args.factor)],
        capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        return {"ran": False, "need_bytes": need,
                "why": f"the child failed: {proc.stderr.strip().splitlines()[-1:]}"}
    return {"ran": True, **json.loads(proc.stdout)}


def scipy_child(job: str, src: str, factor: int) -> None:
    """SciPy's whole job in memory (read, solve, evaluate, write to Zarr), its wall time
    (reading the input excluded) and the process's peak RSS."""
    data = zarr.open_array(src, mode="r")[:]
    n = data.shape[0]
    x = np.arange(n, dtype=np.float64)
    dst = src.replace("-in.zarr", "-scipy.zarr")
    t0 = time.perf_counter()
    if job == "grid":
        new = np.linspace(0.0, n - 1.0, factor * n)
        out = si.RectBivariateSpline(x, x, data, s=0)(new, new)
    else:
        new = np.arange(2 * n - 1) * 0.5
        out = si.make_interp_spline(x, data, k=3)(new)
    zarr.save_array(dst, out)
    wall = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    shutil.rmtree(dst, ignore_errors=True)
    print(json.dumps({"wall_s": wall, "peak_rss": peak}))


# -- the report -------------------------------------------------------------------------------
def report(results: list[dict], args: argparse.Namespace) -> str:
    lines = [
        "| job | input → output (chunks) | wall time | peak RSS per worker (limit "
        f"{args.memory_limit}) | spilled to disk | windows / points checked | max rel. diff "
        "| SciPy in memory |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        shape = (f"{r['n']}² → {r['out']}² ({r['chunk']}² → {r['out_chunk']}²)"
                 if r["job"] == "grid" else
                 f"{r['n']:,} → {r['out']:,} ({r['chunk']:,} → {r['out_chunk']:,})")
        limit = dask.utils.parse_bytes(args.memory_limit)
        within = all(v <= limit for v in r["peak_rss"].values())
        peaks = (", ".join(gib(v) for v in sorted(r["peak_rss"].values())) or "n/a") + (
            " (within the limit)" if within else " (**above the limit**)")
        spill = ", ".join(gib(v) for v in sorted(r["spilled_disk"].values())) or "0"
        s = r["scipy"]
        sc = (f"{s['wall_s']:.1f} s, peak {gib(s['peak_rss'])}" if s["ran"]
              else f"not run: {s['why']}")
        lines.append(
            f"| {r['job']} | {shape}, {gib(r['input_bytes'])} → {gib(r['output_bytes'])} | "
            f"{r['wall_s']:.1f} s (input generated in {r['generate_s']:.1f} s) | {peaks} | "
            f"{spill} | {r['windows']} / {r['points_checked']:,} | {r['max_rel_diff']:.1e} "
            f"({'≤' if r['max_rel_diff'] <= 1e-13 else '**>**'} 1e-13) | "
            f"{sc} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--n", type=int, default=16384, help="grid side (default 16384)")
    ap.add_argument("--chunk", type=int, default=2048, help="grid chunk side (default 2048)")
    ap.add_argument("--factor", type=int, default=2, help="upsampling factor (default 2)")
    ap.add_argument("--series", type=int, default=10**9, help="series length (default 1e9)")
    ap.add_argument("--series-chunk", type=int, default=1 << 22,
                    help="series chunk (default 2^22: a task solves 32 MB of data in about 170 MB)")
    ap.add_argument("--jobs", default="grid,series", help="grid, series or both (default)")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--memory-limit", default="3GB", help="per worker (default 3GB)")
    ap.add_argument("--windows", type=int, default=8, help="seams checked per job")
    ap.add_argument("--workdir", default=str(HERE / "results" / "dask-scale"),
                    help="Zarr stores (deleted at the end unless --keep)")
    ap.add_argument("--keep", action="store_true", help="keep the Zarr stores")
    ap.add_argument("--no-scipy", action="store_true", help="skip SciPy's in-memory run")
    ap.add_argument("--json", default=str(HERE / "results" / "dask_scale.json"))
    ap.add_argument("--scipy-child", help=argparse.SUPPRESS)
    ap.add_argument("--scipy-src", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.scipy_child:
        scipy_child(args.scipy_child, args.scipy_src, args.factor)
        return
    work = Path(args.workdir)
    work.mkdir(parents=True, exist_ok=True)
    results = []
    # Spilling is left on (dask's default): the report shows how much each worker spilled.
    with distributed.LocalCluster(n_workers=args.workers, threads_per_worker=1,
                                  processes=True, memory_limit=args.memory_limit,
                                  dashboard_address=None,
                                  local_directory=str(work / "dask-worker-space")) as cluster, \
            distributed.Client(cluster) as client:
        jobs = args.jobs.split(",")
        if "grid" in jobs:
            results.append(grid_job(args, client, work))
        if "series" in jobs:
            results.append(series_job(args, client, work))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    machine = (f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
               f"{gib(psutil.virtual_memory().total)}; Python {platform.python_version()}, "
               f"NumPy {np.__version__}, SciPy {scipy.__version__}, dask {dask.__version__}, "
               f"distributed {distributed.__version__}, zarr {zarr.__version__}, geomkit "
               f"{getattr(geomkit, '__version__', 'wheel')}")
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps({"machine": machine, "argv": sys.argv[1:],
                                           "results": results}, indent=1, default=str))
    print(f"Machine: {machine}\nCommand: `bash bench/dask_scale.sh {' '.join(sys.argv[1:])}`\n")
    print(report(results, args))


if __name__ == "__main__":
    main()
