#!/usr/bin/env python3
"""From Python (issue 23, section "Speed"): geomkit's package against SciPy in the same venv,
and against the Rust call it wraps (the binding's overhead).

Wall time from Python including the conversion of the arrays (the call as a user makes it,
its result a new NumPy array / spline object), median of repeated calls, each case in its
own process (this script in worker mode, `--worker CASE`, for both packages; the Rust driver
`bspline-compare CASE` for the Rust side), peak RSS of the first call (peak reset through
/proc/self/clear_refs, as bench/compare_bspline.py does) and of the whole process.

Cases (full sizes; --quick divides them for a smoke test):

- `make_interp_spline(x, y)`, y of shape (N, 3), k = 3, default bc (not-a-knot), x the
  chord-length parameters: N = 10^7 and 10^6 (geomkit, SciPy, Rust `spline_build`);
- `BSpline.__call__` on 10^7 (and 10^6) sorted random points of the 10^6-point spline
  (geomkit, SciPy, Rust `curve_eval` kind `par`, the same spline and parameters);
- `RectBivariateSpline(x, y, z, s=0)` on 4096^2 heights: the build and `spl(xs, ys)` on a
  4096^2 grid (geomkit, SciPy).

Agreement: max |geomkit - SciPy| / max |SciPy| over the values at check points (the spline
at midpoints between data parameters; every k-th evaluated point; a sub-grid of the grid).
Overhead of the binding: median(Python) / median(Rust) - 1.

Run it through `bash bench/compare_python.sh` (venv, wheel, driver). Options: --quick,
--out FILE (default bench/RESULTS-python.md), --raw FILE (default
bench/results/compare_python.json), --from-raw FILE (re-render), --note TEXT (a line for
the report, e.g. that the machine was busy).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from compare_bspline import (  # noqa: E402  (the shared fixtures and timing scheme)
    SEED_CURVE,
    SEED_PARAMS,
    SEED_SURFACE,
    chord_params,
    height_grid,
    helix_points,
    machine_info,
    measured_first_call,
    random_params,
    run_json,
    time_call,
)

FULL = dict(build_n=[10_000_000, 1_000_000], eval_n=1_000_000,
            eval_m=[10_000_000, 1_000_000], surface=4096, check=4096,
            samples=9, min_batch=0.02, max_seconds=6.0, rounds=5)
QUICK = dict(build_n=[100_000, 10_000], eval_n=10_000, eval_m=[100_000, 10_000],
             surface=256, check=512, samples=3, min_batch=0.005, max_seconds=0.3, rounds=1)

# The targets.
GOALS = dict(build=10.0, eval=10.0, rbs_build=5.0, rbs_grid=3.0, overhead=0.10)


# ---------------------------------------------------------------------------- worker


def process_peak():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def worker(case):
    lib = case["lib"]
    if lib == "geomkit":
        from importlib.metadata import version as dist_version

        import geomkit as m
        version = dist_version("geomkit")
    else:
        import scipy
        import scipy.interpolate as m
        version = scipy.__version__
    knobs = dict(samples=case["samples"], min_batch=case["min_batch"],
                 max_seconds=case["max_seconds"])
    op, check = case["op"], case["check"]
    out = dict(lib=lib, version=version, op=op, ok=True)
    if op == "build":
        n = case["n"]
        pts = helix_points(n, SEED_CURVE)
        x = chord_params(pts)
        build = lambda: m.make_interp_spline(x, pts)  # noqa: E731
        spl, first, mem = measured_first_call(build, lambda s: int(s.t.nbytes + s.c.nbytes))
        _, t = time_call(build, first=first, **knobs)
        step = max(n // check, 1)
        mid = 0.5 * (x[:-1:step] + x[1::step])
        out.update(n=n, time=t, memory=mem, values=np.asarray(spl(mid)).tolist())
    elif op == "eval":
        n, cnt = case["n"], case["m"]
        pts = helix_points(n, SEED_CURVE)
        spl = m.make_interp_spline(chord_params(pts), pts)
        a, b = float(spl.t[3]), float(spl.t[-4])
        ts = np.sort(random_params(cnt, a, b, SEED_PARAMS))
        vals, first, mem = measured_first_call(lambda: spl(ts), lambda v: int(v.nbytes))
        _, t = time_call(lambda: spl(ts), first=first, **knobs)
        step = max(cnt // check, 1)
        out.update(n=n, m=cnt, domain=[a, b], time=t, memory=mem,
                   values=np.asarray(vals)[::step].tolist())
    elif op == "rbs":
        r = case["size"]
        z = height_grid(r, r, SEED_SURFACE)
        xs = np.arange(r, dtype=np.float64) * (1.0 / (r - 1))
        build = lambda: m.RectBivariateSpline(xs, xs, z, s=0)  # noqa: E731
        spl, first, mem = measured_first_call(build, lambda s: 0)
        _, t = time_call(build, first=first, **knobs)
        g = np.linspace(0.0, 1.0, r)
        grid, gfirst, gmem = measured_first_call(lambda: spl(g, g), lambda v: int(v.nbytes))
        _, gt = time_call(lambda: spl(g, g), first=gfirst, **knobs)
        step = max(r // 64, 1)
        out.update(size=r, time=t, memory=mem, grid_time=gt, grid_memory=gmem,
                   values=np.asarray(grid)[::step, ::step].tolist())
    else:
        out.update(ok=False, error=f"unknown op {op}")
    out["process_peak_bytes"] = process_peak()
    return out


# ---------------------------------------------------------------------------- driver


def run_py(case, log, label):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(case, f)
        path = f.name
    try:
        return run_json([sys.executable, str(Path(__file__).resolve()), "--worker", path],
                        f"{case['lib']:<8} {label}", log)
    finally:
        os.unlink(path)


def agreement(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return None
    return float(np.abs(a - b).max()) / float(np.abs(b).max())


def rust_kind_time(rust, kind):
    """The median time of the Rust driver's evaluation `kind` (None when it did not run)."""
    return next((k["time"]["median_s"] for k in rust["kinds"] if k.get("kind") == kind), None)


def measure(cfg, rust_bin, log):
    knobs = dict(samples=cfg["samples"], min_batch=cfg["min_batch"],
                 max_seconds=cfg["max_seconds"], check=cfg["check"])
    rknobs = dict(samples=cfg["samples"], min_batch_seconds=cfg["min_batch"],
                  max_seconds=cfg["max_seconds"])
    res = dict(build=[], eval=[], rbs=None)

    def alternating(row, py_case, rust_case, rust_time, label):
        # The binding's overhead compares two processes' times on a noisy machine: each
        # side runs `rounds` times, alternately. The row keeps each side's middle run (by
        # time) and each side's fastest time.
        pys, rusts = [], []
        for _ in range(cfg["rounds"]):
            pys.append(run_py(py_case, log, label))
            rusts.append(run_json([str(rust_bin), json.dumps(rust_case)], f"rust     {label}",
                                  log))
        pys.sort(key=lambda r: r["time"]["median_s"])
        rusts.sort(key=rust_time)
        row.update(geomkit=pys[len(pys) // 2], rust=rusts[len(rusts) // 2],
                   geomkit_fastest_s=pys[0]["time"]["median_s"],
                   rust_fastest_s=rust_time(rusts[0]))

    for n in cfg["build_n"]:
        label = f"make_interp_spline N = {n:.0e}"
        row = dict(n=n, scipy=run_py(dict(lib="scipy", op="build", n=n, **knobs), log, label))
        alternating(
            row, dict(lib="geomkit", op="build", n=n, **knobs),
            dict(op="spline_build", variant="chord", n=n, seed=SEED_CURVE, degree=3, **rknobs),
            lambda r: r["time"]["median_s"], label)
        res["build"].append(row)
    n = cfg["eval_n"]
    for cnt in cfg["eval_m"]:
        label = f"BSpline.__call__ {cnt:.0e} sorted points, N = {n:.0e}"
        row = dict(n=n, m=cnt,
                   scipy=run_py(dict(lib="scipy", op="eval", n=n, m=cnt, **knobs), log, label))
        alternating(
            row, dict(lib="geomkit", op="eval", n=n, m=cnt, **knobs),
            dict(op="curve_eval", variant="chord", n=n, seed=SEED_CURVE, check=4,
                 kinds=[dict(kind=kind, params="sorted", count=cnt, param_seed=SEED_PARAMS)
                        for kind in ("nu", "par", "par_new")],
                 **rknobs),
            lambda r: rust_kind_time(r, "par_new"), label)
        res["eval"].append(row)
    r = cfg["surface"]
    label = f"RectBivariateSpline {r}^2"
    res["rbs"] = dict(size=r, **{lib: run_py(dict(lib=lib, op="rbs", size=r, **knobs), log,
                                             label) for lib in ("geomkit", "scipy")})
    return res


# ---------------------------------------------------------------------------- report


def fmt_time(s):
    if s is None:
        return "–"
    if s >= 1:
        return f"{s:.2f} s"
    if s >= 1e-3:
        return f"{s * 1e3:.1f} ms"
    return f"{s * 1e6:.0f} µs"


def fmt_bytes(b):
    if b is None:
        return "–"
    return f"{b / 2**20:.0f} MiB" if b < 2**30 else f"{b / 2**30:.2f} GiB"


def fmt_n(n):
    e = len(str(n)) - 1
    return f"10^{e}" if n == 10**e else f"{n:,}"


def fmt_err(e):
    return "–" if e is None else f"{e:.1e}"


def yes(ok):
    return "**yes**" if ok else "**no**"


def peak(r, key="memory"):
    return r.get(key, {}).get("peak_extra_bytes")


def markdown(res, meta):
    L = []
    L.append("# geomkit from Python against SciPy (issue 23, speed)\n")
    L.append(f"Command: `{meta['command']}`, {meta['date']}, geomkit at {meta['git']}. "
             f"Machine: {meta['cpu']}, {meta['cores']} cores, {meta['mem']}; Python "
             f"{meta['python']}, NumPy {meta['numpy']}, SciPy {meta['scipy']}, {meta['rustc']}. "
             "geomkit's package is the release abi3 wheel of `python/` installed into the "
             "same venv as SciPy; the Rust side is `bspline-compare` (release).\n")
    if meta.get("quick"):
        L.append("**--quick: small sizes and few samples, a smoke test; the numbers mean "
                 "nothing.**\n")
    if meta.get("note"):
        L.append(f"**{meta['note']}**\n")
    L.append("Wall time of one call from Python including the conversion of the arrays (the "
             "median of repeated calls; each case in its own process). geomkit uses all cores "
             "(rayon, GIL released), SciPy one. Peak: the extra RSS of the first call above "
             "the process's RSS before it (its result included), and the whole process's peak "
             "RSS (inputs included). Agreement: max |geomkit − SciPy| / max |SciPy| at check "
             "points (spline values at midpoints between data parameters; every k-th "
             "evaluated point; a 64² sub-grid of the grid). Overhead: Python / Rust − 1, the "
             "same operation on the same data through the Rust driver; the geomkit and Rust "
             f"processes of a case run alternately, {meta.get('rounds', 1)} of each: the "
             "comparison with SciPy shows geomkit's middle process (by time), the overhead "
             "each side's fastest (this machine has slow phases that last a whole process: "
             "there the first touch of a new 240 MB result costs about 25 ms instead of 7, "
             "for Rust and Python alike).\n")
    b0 = res["build"][0]
    e0 = res["eval"][0]
    rbs = res["rbs"]

    def ratio(row):
        return row["scipy"]["time"]["median_s"] / row["geomkit"]["time"]["median_s"]

    def py_fastest(row):
        return row.get("geomkit_fastest_s", row["geomkit"]["time"]["median_s"])

    def over(row, rust_s):
        return py_fastest(row) / rust_s - 1.0

    def rust_build(row):
        return row.get("rust_fastest_s", row["rust"]["time"]["median_s"])

    def rust_kind(row, kind):
        return rust_kind_time(row["rust"], kind)

    def rust_eval(row):
        # The kernel the package calls for a cubic in R^3 (values, extrapolating), into a new
        # buffer as the Python call's new array.
        return row.get("rust_fastest_s", rust_kind(row, "par_new"))

    rbs_ratio = rbs["scipy"]["time"]["median_s"] / rbs["geomkit"]["time"]["median_s"]
    grid_ratio = rbs["scipy"]["grid_time"]["median_s"] / rbs["geomkit"]["grid_time"]["median_s"]
    overheads = [over(r, rust_build(r)) for r in res["build"]] + \
        [over(r, rust_eval(r)) for r in res["eval"]]
    L.append("## Goals\n")
    L.append("| goal (issue 23) | target | measured | met |")
    L.append("|---|---|---|---|")
    L.append(f"| `make_interp_spline` N = {fmt_n(b0['n'])}, 3-D, vs SciPy | ≥ {GOALS['build']:.0f}× "
             f"| {ratio(b0):.1f}× | {yes(ratio(b0) >= GOALS['build'])} |")
    L.append(f"| `BSpline.__call__` {fmt_n(e0['m'])} sorted points vs SciPy | ≥ {GOALS['eval']:.0f}× "
             f"| {ratio(e0):.1f}× | {yes(ratio(e0) >= GOALS['eval'])} |")
    L.append(f"| `RectBivariateSpline` {rbs['size']}² build vs SciPy | ≥ {GOALS['rbs_build']:.0f}× "
             f"| {rbs_ratio:.1f}× | {yes(rbs_ratio >= GOALS['rbs_build'])} |")
    L.append(f"| its grid evaluation {rbs['size']}² vs SciPy | ≥ {GOALS['rbs_grid']:.0f}× "
             f"| {grid_ratio:.1f}× | {yes(grid_ratio >= GOALS['rbs_grid'])} |")
    L.append(f"| binding overhead (Python / Rust − 1), arrays ≥ 10^6 points | ≤ "
             f"{GOALS['overhead']:.0%} | {min(overheads):+.1%} to {max(overheads):+.1%} "
             f"(each below) | {yes(max(overheads) <= GOALS['overhead'])} |")
    L.append("")
    L.append("## Against SciPy\n")
    L.append("| case | geomkit | SciPy | SciPy / geomkit | peak extra geomkit / SciPy | "
             "process peak geomkit / SciPy | agreement |")
    L.append("|---|---|---|---|---|---|---|")
    rows = [(f"`make_interp_spline(x, y)` N = {fmt_n(r['n'])}, y (N, 3)", r)
            for r in res["build"]]
    rows += [(f"`spl(x)`, {fmt_n(r['m'])} sorted points, N = {fmt_n(r['n'])} spline", r)
             for r in res["eval"]]
    for label, r in rows:
        g, s = r["geomkit"], r["scipy"]
        L.append(f"| {label} | "
                 f"{fmt_time(g['time']['median_s'])} | {fmt_time(s['time']['median_s'])} | "
                 f"{ratio(r):.1f}× | {fmt_bytes(peak(g))} / {fmt_bytes(peak(s))} | "
                 f"{fmt_bytes(g['process_peak_bytes'])} / {fmt_bytes(s['process_peak_bytes'])} | "
                 f"{fmt_err(agreement(g['values'], s['values']))} |")
    g, s = rbs["geomkit"], rbs["scipy"]
    agree = fmt_err(agreement(g["values"], s["values"]))
    L.append(f"| `RectBivariateSpline(x, y, z, s=0)` {rbs['size']}² | "
             f"{fmt_time(g['time']['median_s'])} | {fmt_time(s['time']['median_s'])} | "
             f"{rbs_ratio:.1f}× | {fmt_bytes(peak(g))} / {fmt_bytes(peak(s))} | "
             f"{fmt_bytes(g['process_peak_bytes'])} / {fmt_bytes(s['process_peak_bytes'])} | "
             f"{agree} (grid values) |")
    L.append(f"| `spl(xs, ys)` {rbs['size']}² grid | {fmt_time(g['grid_time']['median_s'])} | "
             f"{fmt_time(s['grid_time']['median_s'])} | {grid_ratio:.1f}× | "
             f"{fmt_bytes(peak(g, 'grid_memory'))} / {fmt_bytes(peak(s, 'grid_memory'))} | "
             f"(same processes) | {agree} |")
    L.append("")
    L.append("## Binding overhead: Python against the Rust call\n")
    L.append("| case | Rust (`bspline-compare`) | Python (geomkit) | overhead | within "
             f"{GOALS['overhead']:.0%} |")
    L.append("|---|---|---|---|---|")
    for r in res["build"]:
        o = over(r, rust_build(r))
        L.append(f"| `make_interp_spline` N = {fmt_n(r['n'])} (op `spline_build`) | "
                 f"{fmt_time(rust_build(r))} | {fmt_time(py_fastest(r))} | "
                 f"{o:+.1%} | {yes(o <= GOALS['overhead'])} |")
    for r in res["eval"]:
        o = over(r, rust_eval(r))
        L.append(f"| evaluation, {fmt_n(r['m'])} sorted points (op `curve_eval`, kind "
                 f"`par_new`) | {fmt_time(rust_eval(r))} | {fmt_time(py_fastest(r))} | "
                 f"{o:+.1%} | {yes(o <= GOALS['overhead'])} |")
    L.append("")
    kinds = {kind: [(r["m"], rust_kind(r, kind)) for r in res["eval"]] for kind in ("par", "nu")}
    L.append("Kind `par_new` is `eval_many_par` into a new buffer each call (its allocation "
             "and the page faults of its first touch included, as in the Python call, which "
             "returns a new array; allocated by `geomkit::mem::zeros`, which advises huge pages "
             "as NumPy does for large arrays): the batched cubic kernel `BSpline.__call__` calls for the "
             "values of cubics in R^1 to R^3 (extrapolate=True). Into a buffer kept between "
             "calls (kind `par`) it takes "
             + ", ".join(f"{fmt_time(t)} ({fmt_n(m)} points)" for m, t in kinds["par"])
             + "; SciPy's recursion `eval_nu_many` (kind `nu`, the kernel of every other "
             "`nu` and degree: SciPy's values bit for bit) "
             + ", ".join(f"{fmt_time(t)} ({fmt_n(m)} points)" for m, t in kinds["nu"])
             + ".\n")
    L.append("The overhead is then the checks and the conversion of the arguments. The Rust "
             "build times only `make_interp_spline` (the chord-length parameters computed "
             "beforehand, as the Python x is).\n")
    return "\n".join(L)


def machine_meta(args):
    return dict(machine_info(), command=args.command, quick=args.quick, note=args.note)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worker", metavar="CASE_JSON_FILE")
    ap.add_argument("--rust-bin", default="target/release/bspline-compare")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(HERE / "RESULTS-python.md"))
    ap.add_argument("--raw", default=str(HERE / "results" / "compare_python.json"))
    ap.add_argument("--from-raw", metavar="FILE")
    ap.add_argument("--command", default="bash bench/compare_python.sh")
    ap.add_argument("--note", default="")
    args = ap.parse_args()
    if args.worker:
        json.dump(worker(json.loads(Path(args.worker).read_text())), sys.stdout)
        return

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    if args.from_raw:
        raw = json.loads(Path(args.from_raw).read_text())
        res, meta = raw["results"], raw["meta"]
    else:
        cfg = QUICK if args.quick else FULL
        t0 = time.perf_counter()
        res = measure(cfg, Path(args.rust_bin), log)
        meta = machine_meta(args)
        meta["seconds"] = time.perf_counter() - t0
        meta["rounds"] = cfg["rounds"]
        raw_path = Path(args.raw)
        raw_path.parent.mkdir(parents=True, exist_ok=True)
        raw_path.write_text(json.dumps(dict(meta=meta, config=cfg, results=res)))
        log(f"raw numbers: {raw_path} ({meta['seconds']:.0f} s in all)")
    md = markdown(res, meta)
    print(md)
    Path(args.out).write_text(md)


if __name__ == "__main__":
    main()
