#!/usr/bin/env python3
"""Side-by-side comparison of geomkit's interpolating cubic B-splines (method 2,
spec/bspline-interpolation.md) with SciPy: make_interp_spline (curves), BSpline.__call__
(curve evaluation), RectBivariateSpline (height surfaces, its grid and scattered
evaluation). Speed (median time per call, same run, same machine), peak memory of the build
(fresh process per case), accuracy (interpolation residual; agreement of the two libraries
at check points), each against the goals of the issue.

Run it through `bash bench/compare_bspline.sh` (creates bench/.venv, installs
bench/requirements.txt, builds the Rust driver). Directly:

    bench/.venv/bin/python bench/compare_bspline.py --rust-bin target/release/bspline-compare

Options: --quick (small sizes, few samples; smoke test), --out FILE (Markdown, default
bench/RESULTS-bspline.md), --raw FILE (all numbers as JSON, default
bench/results/compare_bspline.json), --from-raw FILE (no measuring: re-render the Markdown
of an earlier raw JSON).

Both sides generate the same inputs from a seed (no data files): the fixtures of
crates/geomkit-bench/src/lib.rs (SplitMix64 numbers, a rational parametrization of the
circle; only + - * /, so numpy reproduces them bit for bit; checked on every case through
the driver's `input_sample`). Every measurement runs in its own process: the geomkit
driver (`bspline-compare CASE`) and this script in worker mode (`--worker CASE`). Peak
memory: write 5 to /proc/self/clear_refs (resets the peak RSS), read VmRSS, build once,
read VmHWM.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent

SEED_CURVE = 1
SEED_SURFACE = 3
SEED_PARAMS = 5

# Sizes and timing knobs. The full run takes ~6-8 min on 2 cores; --quick well under 1 min.
FULL = dict(
    curve_n=[100_000, 1_000_000, 10_000_000],
    eval_n=100_000,            # control points of the evaluated curves (~N)
    eval_uniform=10_000_000,   # uniform samples over the domain
    eval_random=1_000_000,     # random parameters (sorted / unsorted), geomkit
    scipy_unsorted=100_000,    # SciPy's unsorted evaluation is O(N) per point: fewer points
    surfaces=[1024, 4096],     # n x n heights; evaluated on an n x n grid too
    scattered=1_000_000,       # scattered surface points, geomkit
    scipy_scattered=200_000,   # RectBivariateSpline.ev: fewer points
    check=4096,
    spline_n=[1_000_000, 10_000_000], spline_k=[1, 2, 5],  # any degree (issue 22)
    samples=15, min_batch=0.02, max_seconds=4.0,
)
QUICK = dict(
    curve_n=[10_000, 100_000],
    eval_n=10_000, eval_uniform=1_000_000, eval_random=100_000, scipy_unsorted=20_000,
    surfaces=[256, 512], scattered=100_000, scipy_scattered=20_000,
    check=1024,
    spline_n=[100_000], spline_k=[1, 2, 5],
    samples=3, min_batch=0.005, max_seconds=0.5,
)

# The issue's goals and its SciPy figures (measured earlier on this machine, SciPy 1.17).
GOALS = dict(build_speedup=25.0, build_temp_ratio=0.25, uniform_eval=300e6,
             arbitrary_eval=80e6, surface_speedup=10.0, surface_residual=1e-14,
             grid_eval=300e6, scattered_eval=50e6, agreement=1e-12)
ISSUE_SCIPY = dict(build_1e7="2.8 s, +1.4 GB peak", uniform_eval="13–18 M pts/s",
                   unsorted_eval="0.06 M pts/s (N = 1e5)", rbs_build="1.59 s (4096²)",
                   rbs_grid="~68 M pts/s", rbs_ev="0.24 M pts/s")

# ---------------------------------------------------------------------------- fixtures
# Mirrors of crates/geomkit-bench/src/lib.rs: same formulas, same operation order.

GAMMA = np.uint64(0x9E3779B97F4A7C15)
NOISE = 1e-3
HELIX_PERIODS = (64, 4099)
HEIGHT_PERIODS = (257, 263, 61)


def fixture_at(seed: int, k: np.ndarray) -> np.ndarray:
    """SplitMix64 number k of the sequence seeded with `seed`, in [-1, 1) (Fixture::at)."""
    z = np.uint64(seed) + (k.astype(np.uint64) + np.uint64(1)) * GAMMA
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return (z >> np.uint64(11)).astype(np.float64) / float(1 << 52) - 1.0


def circle_point(i: np.ndarray, period: int):
    u = ((i.astype(np.uint64) % np.uint64(period)).astype(np.float64) + 0.5) / float(period)
    w = 2.0 * u - 1.0
    s = w / (1.0 - w * w)
    s2 = s * s
    return (1.0 - s2) / (1.0 + s2), 2.0 * s / (1.0 + s2)


def helix_points(n: int, seed: int) -> np.ndarray:
    i = np.arange(n, dtype=np.uint64)
    x1, y1 = circle_point(i, HELIX_PERIODS[0])
    _, y2 = circle_point(i, HELIX_PERIODS[1])
    r = fixture_at(seed, np.arange(3 * n, dtype=np.uint64)).reshape(n, 3)
    out = np.empty((n, 3))
    out[:, 0] = x1 + NOISE * r[:, 0]
    out[:, 1] = y1 + NOISE * r[:, 1]
    out[:, 2] = 0.5 * y2 + NOISE * r[:, 2]
    return out


def height_grid(rows: int, cols: int, seed: int) -> np.ndarray:
    i = np.arange(rows, dtype=np.uint64)[:, None]
    j = np.arange(cols, dtype=np.uint64)[None, :]
    xi, _ = circle_point(i, HEIGHT_PERIODS[0])
    _, yj = circle_point(j, HEIGHT_PERIODS[1])
    _, yd = circle_point(i + j, HEIGHT_PERIODS[2])
    r = fixture_at(seed, np.arange(rows * cols, dtype=np.uint64)).reshape(rows, cols)
    return xi * yj + 0.25 * yd + NOISE * r


def random_params(count: int, a: float, b: float, seed: int) -> np.ndarray:
    return a + (b - a) * ((fixture_at(seed, np.arange(count, dtype=np.uint64)) + 1.0) * 0.5)


def chord_params(points: np.ndarray) -> np.ndarray:
    """geomkit's chord-length parameters (numeric::distance: the root of the sum of squares,
    summed in coordinate order; scaled by the largest coordinate difference only when that
    sum is not finite or below 2^-900, which these fixtures never reach), accumulated in
    order."""
    d = np.diff(points, axis=0)
    s = d[:, 0] * d[:, 0]
    for c in range(1, points.shape[1]):
        s = s + d[:, c] * d[:, c]
    assert np.all(np.isfinite(s) & (s >= 2.0 ** -900)), "fixture outside the plain range"
    step = np.sqrt(s)
    return np.concatenate([[0.0], np.cumsum(step)])


# ---------------------------------------------------------------------------- timing


def time_call(f, samples: int, min_batch: float, max_seconds: float, first=None):
    """The scheme of the Rust driver: one first call (or its duration `first` if the caller
    made it), then `samples` batches of `inner` calls (a batch >= min_batch s), at least 3,
    the case kept under ~max_seconds; GC off during the batches. Returns dict of seconds
    per call."""
    result = None
    if first is None:
        t0 = time.perf_counter()
        result = f()
        first = time.perf_counter() - t0
    first = max(first, 1e-9)
    inner = int(min(max(math.ceil(min_batch / first), 1), 10_000_000))
    samples = max(3, min(samples, int(max_seconds / (first * inner))))
    times = []
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(samples):
            t0 = time.perf_counter()
            for _ in range(inner):
                f()
            times.append((time.perf_counter() - t0) / inner)
    finally:
        if gc_was_enabled:
            gc.enable()
    return result, dict(first_s=first, median_s=statistics.median(times), min_s=min(times),
                        samples=samples, calls_per_sample=inner)


def status_bytes(field: str):
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(field):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return None


def measured_first_call(f, output_bytes):
    """(result, seconds, memory dict) of one call between a peak reset and a peak read."""
    gc.collect()
    try:
        Path("/proc/self/clear_refs").write_text("5")
        reset = True
    except OSError:
        reset = False
    rss0 = status_bytes("VmRSS")
    t0 = time.perf_counter()
    result = f()
    secs = time.perf_counter() - t0
    hwm, rss1 = status_bytes("VmHWM"), status_bytes("VmRSS")
    out = output_bytes(result)
    if not reset or rss0 is None or hwm is None:
        return result, secs, dict(output_bytes=out, error="no /proc/self/clear_refs or status")
    return result, secs, dict(rss_before_bytes=rss0, peak_extra_bytes=max(hwm - rss0, 0),
                              rss_after_extra_bytes=max(rss1 - rss0, 0), output_bytes=out)


# ---------------------------------------------------------------------------- SciPy worker


def check_input(sample, flat: np.ndarray):
    """True when the geomkit driver's input rows equal ours bit for bit."""
    if sample is None:
        return None
    rows = flat.reshape(len(flat), -1)
    return all(rows[i].tolist() == v for i, v in zip(sample["index"], sample["values"]))


def worker(case):
    from scipy.interpolate import RectBivariateSpline, make_interp_spline

    knobs = dict(samples=case["samples"], min_batch=case["min_batch"],
                 max_seconds=case["max_seconds"])
    op = case["op"]
    out = dict(op=op, variant=case.get("variant"), ok=True)
    if op in ("curve_build", "curve_eval"):
        n = case["n"]
        pts = helix_points(n, SEED_CURVE)
        x = np.arange(n, dtype=np.float64) if case["variant"] == "uniform" else chord_params(pts)
        out["input_identical"] = check_input(case.get("input_sample"), pts)
        if case["variant"] == "chord" and "check_params" in case:
            # The driver's first two check parameters are x[0] and x[N-1]: equal bit for bit
            # when the accumulated chord lengths are.
            out["input_identical"] = out["input_identical"] and \
                case["check_params"][:2] == [float(x[0]), float(x[-1])]
        scale = float(np.abs(pts).max())
        out["max_abs_p"] = scale
        if op == "curve_build":
            spl, first, mem = measured_first_call(
                lambda: make_interp_spline(x, pts, k=3),
                lambda s: int(s.t.nbytes + s.c.nbytes))
            _, t = time_call(lambda: make_interp_spline(x, pts, k=3), first=first, **knobs)
            t.update(items=n, items_per_s=n / t["median_s"])
            out.update(time=t, memory=mem)
            out["residual_rel"] = float(np.abs(spl(x) - pts).max()) / scale
            cp = np.array(case["check_params"])
            out["check_values"] = spl(cp).tolist()
        else:
            spl = make_interp_spline(x, pts, k=3)
            a, b = float(spl.t[3]), float(spl.t[-4])
            kinds = []
            for k in case["kinds"]:
                m = k["count"]
                if k["params"] == "uniform":
                    ts = np.linspace(a, b, m)
                else:
                    ts = random_params(k["full_count"], a, b, k["param_seed"])
                    if k["params"] == "sorted":
                        ts = np.sort(ts)
                    ts = ts[:m]
                t = None
                if not k.get("no_time"):
                    _, t = time_call(lambda: spl(ts), **knobs)
                    t.update(items=m, items_per_s=m / t["median_s"])
                vals = {key: spl(np.array(cp)).tolist()
                        for key, cp in k.get("check_params", {}).items()}
                kinds.append(dict(params=k["params"], count=m, time=t, check_values=vals))
            out["kinds"] = kinds
    elif op == "surface":
        r = c = case["size"]
        z = height_grid(r, c, SEED_SURFACE)
        out["input_identical"] = check_input(case.get("input_sample"), z.reshape(-1))
        dx, dy = 1.0 / (r - 1), 1.0 / (c - 1)
        xs = np.arange(r, dtype=np.float64) * dx
        ys = np.arange(c, dtype=np.float64) * dy
        build = lambda: RectBivariateSpline(xs, ys, z, kx=3, ky=3, s=0)  # noqa: E731
        spl, first, mem = measured_first_call(
            build, lambda s: int(sum(np.asarray(a).nbytes for a in s.tck)))
        _, t = time_call(build, first=first, **knobs)
        t.update(items=r * c, items_per_s=r * c / t["median_s"])
        scale = float(np.abs(z).max())
        out.update(time=t, memory=mem, max_abs_z=scale)
        out["residual_rel"] = float(np.abs(spl(xs, ys) - z).max()) / scale
        g = case["grid_eval"]
        gu, gv = np.linspace(xs[0], xs[-1], g), np.linspace(ys[0], ys[-1], g)
        _, t = time_call(lambda: spl(gu, gv), **knobs)
        t.update(items=g * g, items_per_s=g * g / t["median_s"])
        out["grid_eval"] = dict(g=g, time=t)
        m = case["scattered"]
        su = random_params(m, xs[0], xs[-1], case["param_seed"])
        sv = random_params(m, ys[0], ys[-1], case["param_seed"] + 1)
        _, t = time_call(lambda: spl.ev(su, sv), **knobs)
        t.update(items=m, items_per_s=m / t["median_s"])
        out["scattered"] = dict(count=m, time=t)
        chk = case["check_scattered"]
        out["check_scattered"] = spl.ev(np.array(chk["u"]), np.array(chk["v"])).tolist()
        cg = case["check_grid"]
        out["check_grid"] = spl(np.array(cg["u"]), np.array(cg["v"])).tolist()
    elif op == "spline_build":
        # Any degree (issue 22): the helix at its chord-length parameters, not-a-knot.
        n, k = case["n"], case["degree"]
        pts = helix_points(n, SEED_CURVE)
        x = chord_params(pts)
        spl, first, mem = measured_first_call(
            lambda: make_interp_spline(x, pts, k=k), lambda s: int(s.t.nbytes + s.c.nbytes))
        _, t = time_call(lambda: make_interp_spline(x, pts, k=k), first=first, **knobs)
        t.update(items=n, items_per_s=n / t["median_s"])
        scale = float(np.abs(pts).max())
        out.update(time=t, memory=mem, residual_rel=float(np.abs(spl(x) - pts).max()) / scale)
    else:
        out.update(ok=False, error=f"unknown op {op}")
    return out


# ---------------------------------------------------------------------------- driver


def run_json(cmd, log_label, log):
    log(f"  {log_label}")
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{log_label}: exit {proc.returncode}\n{proc.stderr[-2000:]}")
    res = json.loads(proc.stdout)
    res["wall_s"] = time.perf_counter() - t0
    return res


def run_rust(rust_bin, case, log, label):
    return run_json([str(rust_bin), json.dumps(case)], f"geomkit  {label}", log)


def run_scipy(case, log, label):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(case, f)
        path = f.name
    try:
        return run_json([sys.executable, str(Path(__file__).resolve()), "--worker", path],
                        f"SciPy    {label}", log)
    finally:
        os.unlink(path)


def agreement(a, b, scale):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return None
    return float(np.abs(a - b).max()) / scale


def measure(cfg, rust_bin, log):
    knobs = dict(samples=cfg["samples"], min_batch_seconds=cfg["min_batch"],
                 max_seconds=cfg["max_seconds"])
    py_knobs = dict(samples=cfg["samples"], min_batch=cfg["min_batch"],
                    max_seconds=cfg["max_seconds"])
    res = dict(curve_build=[], curve_eval=[], surface=[], spline_build=[])
    # --- any degree (issue 22)
    for n in cfg["spline_n"]:
        for k in cfg["spline_k"]:
            gk = run_rust(rust_bin, dict(op="spline_build", variant="", n=n, degree=k,
                                         seed=SEED_CURVE, **knobs), log,
                          f"spline build k={k} N={n:.0e}")
            tiled = run_rust(rust_bin, dict(op="spline_build", variant="tiled", n=n, degree=k,
                                            seed=SEED_CURVE, **knobs), log,
                             f"spline build tiled k={k} N={n:.0e}")
            sp = run_scipy(dict(op="spline_build", n=n, degree=k, **py_knobs), log,
                           f"make_interp_spline k={k} N={n:.0e}")
            res["spline_build"].append(dict(n=n, k=k, geomkit=gk, geomkit_tiled=tiled,
                                            scipy=sp))
    # --- curve builds
    for n in cfg["curve_n"]:
        gk = {}
        for v in ("uniform", "into", "tiled", "chord", "at"):
            gk[v] = run_rust(rust_bin, dict(op="curve_build", variant=v, n=n, seed=SEED_CURVE,
                                            check=cfg["check"], **knobs), log,
                             f"curve build {v:8s} N={n:.0e}")
        sp = {}
        for v, src in (("uniform", "uniform"), ("at", "at")):
            sp[v] = run_scipy(dict(op="curve_build", variant="uniform" if v == "uniform"
                                   else "chord", n=n, check_params=gk[src]["check_params"],
                                   input_sample=gk[src].get("input_sample"), **py_knobs),
                              log, f"make_interp_spline {v:8s} N={n:.0e}")
        for v in gk:
            ref = sp["uniform" if v in ("uniform", "into", "tiled") else "at"]
            if gk[v].get("ok"):
                gk[v]["agreement_rel"] = agreement(gk[v]["check_values"], ref["check_values"],
                                                   gk[v]["max_abs_p"])
            gk[v].pop("check_values", None)
            gk[v].pop("check_params", None)
        for v in sp:
            sp[v].pop("check_values", None)
        res["curve_build"].append(dict(n=n, geomkit=gk, scipy=sp))
    # --- curve evaluation
    n = cfg["eval_n"]
    mu, mr = cfg["eval_uniform"], cfg["eval_random"]
    for v in ("uniform", "chord"):
        kinds = [dict(kind="fd", params="uniform", count=mu),
                 dict(kind="par", params="uniform", count=mu),
                 dict(kind="par", params="sorted", count=mr, param_seed=SEED_PARAMS),
                 dict(kind="par", params="unsorted", count=mr, param_seed=SEED_PARAMS),
                 dict(kind="pp", params="sorted", count=mr, param_seed=SEED_PARAMS),
                 dict(kind="pp", params="unsorted", count=mr, param_seed=SEED_PARAMS),
                 dict(kind="seq", params="sorted", count=mr, param_seed=SEED_PARAMS)]
        gk = run_rust(rust_bin, dict(op="curve_eval", variant=v, n=n, seed=SEED_CURVE,
                                     check=cfg["check"], kinds=kinds, **knobs), log,
                      f"curve eval {v} knots, N={n:.0e}")
        # SciPy: one call per parameter set; the check values of every geomkit kind.
        checks = {p: {} for p in ("uniform", "sorted", "unsorted")}
        for i, k in enumerate(gk["kinds"]):
            if k.get("ok"):
                checks[k["params"]][str(i)] = k["check_params"]
        sp_kinds = [dict(params="uniform", count=mu, check_params=checks["uniform"]),
                    dict(params="sorted", count=mr, full_count=mr, param_seed=SEED_PARAMS,
                         check_params=checks["sorted"]),
                    dict(params="unsorted", count=min(cfg["scipy_unsorted"], mr),
                         full_count=mr, param_seed=SEED_PARAMS,
                         check_params=checks["unsorted"])]
        sp = run_scipy(dict(op="curve_eval", variant=v, n=n, kinds=sp_kinds,
                            input_sample=gk.get("input_sample"), **py_knobs), log,
                       f"BSpline.__call__ ({v} x), N={n:.0e}")
        by_params = {k["params"]: k for k in sp["kinds"]}
        for i, k in enumerate(gk["kinds"]):
            if not k.get("ok"):
                continue
            ref = by_params[k["params"]]["check_values"].get(str(i))
            k["agreement_rel"] = agreement(k["check_values"], ref, gk["max_abs_p"])
            k.pop("check_values")
            k.pop("check_params")
        for k in sp["kinds"]:
            k.pop("check_values")
        res["curve_eval"].append(dict(variant=v, n=n, geomkit=gk, scipy=sp))
    # --- accuracy of the forward differences at exactly representable parameters: uniform
    # knots 0..N-1 and 8 samples per span, t_k = k/8 (no rounding of the parameters, so any
    # difference from the direct evaluation is the differencing's own error).
    res["fd_exact"] = []
    for n in (cfg["eval_n"], 10 * cfg["eval_n"]):
        cnt = 8 * (n - 1) + 1
        kinds = [dict(kind="fd", params="uniform", count=cnt),
                 dict(kind="par", params="uniform", count=cnt)]
        gk = run_rust(rust_bin, dict(op="curve_eval", variant="uniform", n=n, seed=SEED_CURVE,
                                     check=cfg["check"], kinds=kinds, samples=3,
                                     min_batch_seconds=cfg["min_batch"], max_seconds=0.5),
                      log, f"forward differences at t = k/8, N={n:.0e}")
        checks = {str(i): k["check_params"] for i, k in enumerate(gk["kinds"]) if k.get("ok")}
        sp = run_scipy(dict(op="curve_eval", variant="uniform", n=n,
                            kinds=[dict(params="uniform", count=cnt, no_time=True,
                                        check_params=checks)],
                            input_sample=gk.get("input_sample"), **py_knobs),
                       log, f"BSpline.__call__ at t = k/8, N={n:.0e}")
        vals = sp["kinds"][0]["check_values"]
        for i, k in enumerate(gk["kinds"]):
            if k.get("ok"):
                exact = all(x * 8 == round(x * 8) for x in k["check_params"])
                k["params_exact"] = exact
                k["agreement_rel"] = agreement(k["check_values"], vals[str(i)], gk["max_abs_p"])
                k.pop("check_values")
                k.pop("check_params")
        sp["kinds"][0].pop("check_values")
        res["fd_exact"].append(dict(n=n, count=cnt, geomkit=gk, scipy=sp))
    # --- surfaces
    for size in cfg["surfaces"]:
        gk = {}
        for v in ("heights", "heights_at"):
            gk[v] = run_rust(rust_bin, dict(op="surface", variant=v, rows=size, cols=size,
                                            seed=SEED_SURFACE, grid_eval=size,
                                            scattered=cfg["scattered"],
                                            param_seed=SEED_PARAMS, check=cfg["check"],
                                            **knobs), log, f"surface {v:10s} {size}²")
        ref = gk["heights"]
        sp = run_scipy(dict(op="surface", size=size, grid_eval=size,
                            scattered=cfg["scipy_scattered"], param_seed=SEED_PARAMS,
                            check_scattered=ref["check_scattered"],
                            check_grid=dict(u=ref["check_grid"]["u"], v=ref["check_grid"]["v"]),
                            input_sample=ref.get("input_sample"), **py_knobs),
                       log, f"RectBivariateSpline {size}²")
        for v in gk:
            g = gk[v]
            if g.get("ok"):
                g["agreement_scattered_rel"] = agreement(
                    g["check_scattered"]["values"], sp["check_scattered"], g["max_abs_z"])
                g["agreement_grid_rel"] = agreement(
                    g["check_grid"]["values"], sp["check_grid"], g["max_abs_z"])
            g.pop("check_scattered", None)
            g.pop("check_grid", None)
        sp.pop("check_scattered")
        sp.pop("check_grid")
        res["surface"].append(dict(size=size, geomkit=gk, scipy=sp))
    # --- residual probe: the largest grid plus one node, so that the spacing 1/(n-1) is a
    # power of two and the nodes i/(n-1) are exactly equally spaced doubles.
    res["residual_probe"] = []
    for size in (max(cfg["surfaces"]), max(cfg["surfaces"]) + 1):
        r = run_rust(rust_bin, dict(op="surface", variant="heights_at", rows=size, cols=size,
                                    seed=SEED_SURFACE, grid_eval=16, scattered=16,
                                    param_seed=SEED_PARAMS, check=1, samples=1,
                                    min_batch_seconds=0.0, max_seconds=0.0),
                     log, f"surface residual probe {size}²")
        res["residual_probe"].append(dict(size=size, residual_rel=r.get("residual_rel"),
                                          residual_at=r.get("residual_at")))
    return res


# ---------------------------------------------------------------------------- report


def fmt_time(s):
    if s is None:
        return "—"
    for unit, f in (("s", 1.0), ("ms", 1e3), ("µs", 1e6), ("ns", 1e9)):
        if s * f >= 1.0:
            return f"{s * f:.3g} {unit}"
    return f"{s * 1e9:.3g} ns"


def fmt_rate(r):
    if r is None:
        return "—"
    if r >= 1e9:
        return f"{r / 1e9:.3g} G/s"
    if r >= 1e6:
        return f"{r / 1e6:.3g} M/s"
    return f"{r / 1e3:.3g} k/s"


def fmt_bytes(b):
    if b is None:
        return "—"
    for unit, f in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if abs(b) >= f:
            return f"{b / f:.3g} {unit}"
    return f"{b} B"


def fmt_err(e):
    if e is None:
        return "—"
    if e == 0.0:
        return "0"
    return f"{e:.1e}"


def fmt_n(n):
    e = int(round(math.log10(n)))
    return f"10^{e}" if 10 ** e == n else f"{n:,}"


def met(ok):
    return "**yes**" if ok else "no"


def med(r):
    return r["time"]["median_s"] if r and r.get("ok", True) and "time" in r else None


def rate(r):
    return r["time"]["items_per_s"] if r and "time" in r else None


def fmt_ratio(x):
    return "—" if x is None else f"{x:.2f}"


def temp_ratio(mem):
    """(peak extra - output) / output, or None."""
    if not mem or "peak_extra_bytes" not in mem or not mem.get("output_bytes"):
        return None
    return (mem["peak_extra_bytes"] - mem["output_bytes"]) / mem["output_bytes"]


BUILD_LABEL = {
    "uniform": ("`interpolate_curve_flat`, Uniform", "uniform"),
    "into": ("`CurveInterpolator::solve_into` (Uniform; set up once, the caller's buffer reused)",
             "uniform"),
    "tiled": ("`interpolate_curve_tiled`, Uniform (tiles of 65 536, parallel)", "uniform"),
    "at": ("`interpolate_curve_at(x)`, x = chord lengths given", "at"),
    "chord": ("`interpolate_curve_flat`, ChordLength (computes x too)", "at"),
}
SCIPY_BUILD = {"uniform": "`make_interp_spline(arange(N), y)`",
               "at": "`make_interp_spline(x, y)`, x = chord lengths"}


def markdown(res, meta, cfg):
    lines = []
    w = lines.append
    goals_rows = []

    def goal(name, measured, target, ok):
        goals_rows.append(f"| {name} | {measured} | {target} | {met(ok)} |")

    w("# Side-by-side: geomkit vs SciPy (interpolating cubic B-splines, method 2)")
    w("")
    w(f"Generated by `{meta['command']}` on {meta['date']}"
      + (" (**quick mode: small sizes, not the issue's sizes**)" if meta["quick"] else "") + ".")
    w("")
    w("## Machine and versions")
    w("")
    w(f"- {meta['cpu']}, {meta['cores']} cores, {meta['mem']} RAM, **shared and noisy** (other "
      "builds ran on it; times move by up to ±30 %, ratios below ~1.5× are noise).")
    dirty = " (`-dirty`: uncommitted changes in the tree)" if meta["git"].endswith("-dirty") else ""
    w(f"- {meta['rustc']}; geomkit at `{meta['git']}`{dirty}, `cargo build --release -p "
      f"geomkit-bench` (opt-level 3, no LTO, rayon on {meta['cores']} threads).")
    w(f"- Python {meta['python']}; SciPy {meta['scipy']}, numpy {meta['numpy']} "
      f"(BLAS/LAPACK: {meta['blas']}).")
    w("")
    w("## Method")
    w("")
    w("- **Inputs** (identical on both sides, generated from a seed by the fixtures of "
      "`crates/geomkit-bench/src/lib.rs`, mirrored in numpy; "
      f"bit-for-bit identity checked on every case: {meta['inputs_identical']}): "
      "curves: a noisy helix-like closed curve in R³ (64 points per turn, max |p| ≈ 1); "
      "surfaces: heights z_ij on an n×n grid, x_i = i/(n−1), smooth waves plus 10⁻³ noise. "
      "Ends: not-a-knot everywhere (SciPy's default for `make_interp_spline(k=3)`; "
      "`RectBivariateSpline(kx=ky=3, s=0)` is not-a-knot in both directions).")
    w(f"- **Time**: median time per call over up to {cfg['samples']} batches (at least 3; each "
      f"batch ≥ {cfg['min_batch'] * 1e3:g} ms, the case kept under ~{cfg['max_seconds']:g} s), "
      "after one first call; the same scheme in Rust and Python (GC off during batches). "
      "Each operation runs in a fresh process. geomkit evaluates into a preallocated "
      "output buffer (its API); SciPy allocates its result on every call (its API).")
    w("- **Peak memory** of a build: `/proc/self/clear_refs` ← 5 resets the peak RSS after "
      "the input exists; *peak extra* = VmHWM after the first build − VmRSS before it (the "
      "result is still alive, so this includes it). *output* = bytes of the result "
      "(geomkit: knots + control points, the parameters being the inner knots; SciPy: `t` + `c`; surfaces: both knot "
      "vectors + coefficients). *temporaries* = peak extra − output.")
    w("- **Residual**: max |s(x_i) − p_i| over **all** data points / max |p| (surfaces: all "
      "n² nodes). **Agreement**: max |geomkit − SciPy| / max |p| at check parameters "
      f"(curves: midpoints between data parameters at {cfg['check']} evenly spaced indices and "
      f"the ends; evaluations: every M/{cfg['check']}-th parameter; surfaces: "
      f"{cfg['check']} scattered points and a 64×64 sub-grid of the evaluation grid). "
      "geomkit's knots extend beyond the data ends, SciPy's are clamped: different bases "
      "of the same spline, so agreement is to rounding.")
    w("- **ratio** = SciPy time / geomkit time (> 1: geomkit faster).")
    w("")

    # ------------------------------------------------------------ curve build
    w("## Curve interpolation (3-D, not-a-knot)")
    w("")
    w("| N | geomkit call | geomkit | SciPy call | SciPy | ratio | geomkit pts/s | "
      "residual | agreement |")
    w("|---|---|---:|---|---:|---:|---:|---:|---:|")
    big = None
    for row in res["curve_build"]:
        n = row["n"]
        for v in ("uniform", "into", "tiled", "at", "chord"):
            g = row["geomkit"][v]
            label, src = BUILD_LABEL[v]
            s = row["scipy"][src]
            ratio = med(s) / med(g) if med(g) and med(s) else None
            w(f"| {fmt_n(n)} | {label} | {fmt_time(med(g))} | {SCIPY_BUILD[src]} | "
              f"{fmt_time(med(s))} | {f'{ratio:.3g}×' if ratio else '—'} | "
              f"{fmt_rate(rate(g))} | {fmt_err(g.get('residual_rel'))} | "
              f"{fmt_err(g.get('agreement_rel'))} |")
        if n == max(r["n"] for r in res["curve_build"]):
            big = row
    w("")
    w("SciPy's residual: " + ", ".join(
        f"N={fmt_n(r['n'])}: {fmt_err(r['scipy']['uniform'].get('residual_rel'))} (arange) / "
        f"{fmt_err(r['scipy']['at'].get('residual_rel'))} (chord x)"
        for r in res["curve_build"]) + ".")
    w("")
    w("### Peak memory of the build (fresh process, first call)")
    w("")
    w("| N | library, call | peak extra | output | temporaries | temporaries / output | "
      "first call |")
    w("|---|---|---:|---:|---:|---:|---:|")
    for row in res["curve_build"]:
        entries = [(f"geomkit {BUILD_LABEL[v][0]}", row["geomkit"][v])
                   for v in ("uniform", "into", "tiled", "at", "chord")]
        entries += [(f"SciPy {SCIPY_BUILD[v]}", row["scipy"][v]) for v in ("uniform", "at")]
        for label, r in entries:
            m = r.get("memory", {})
            tr = temp_ratio(m)
            w(f"| {fmt_n(row['n'])} | {label} | {fmt_bytes(m.get('peak_extra_bytes'))} | "
              f"{fmt_bytes(m.get('output_bytes'))} | "
              f"{fmt_bytes(m['peak_extra_bytes'] - m['output_bytes']) if tr is not None else '—'}"
              f" | {f'{tr:.2f}' if tr is not None else '—'} | {fmt_time(r['time']['first_s'])} |")
    w("")
    if big:
        for v in ("uniform", "into", "tiled", "at", "chord"):
            g = big["geomkit"][v]
            s = big["scipy"][BUILD_LABEL[v][1]]
            ratio = med(s) / med(g)
            goal(f"curve build N={fmt_n(big['n'])}, {BUILD_LABEL[v][0]} vs "
                 f"{SCIPY_BUILD[BUILD_LABEL[v][1]]}", f"{ratio:.3g}× ({fmt_time(med(g))} vs "
                 f"{fmt_time(med(s))})", f"≥ {GOALS['build_speedup']:g}×",
                 ratio >= GOALS["build_speedup"])
            tr = temp_ratio(g.get("memory"))
            if tr is not None:
                goal(f"… its temporary peak memory / output", f"{tr:.2f} "
                     f"({fmt_bytes(g['memory']['peak_extra_bytes'] - g['memory']['output_bytes'])}"
                     f" / {fmt_bytes(g['memory']['output_bytes'])})",
                     f"≤ {GOALS['build_temp_ratio']:g}", tr <= GOALS["build_temp_ratio"])
        w("Sub-steps of the geomkit build at N = " + fmt_n(big["n"]) + " (median of 3, "
          "outside the timed calls; profiling hints):")
        w("")
        w("| variant | build | `parameters()` | copy knots+control | "
          "copy + `BsplineCurve::from_flat` "
          "| `eval_many_par` at the N data parameters | copy of the input (memcpy floor) |")
        w("|---|---:|---:|---:|---:|---:|---:|")
        for v in ("uniform", "into", "tiled", "at", "chord"):
            g = big["geomkit"][v]
            sub = g.get("substeps", {})
            w(f"| {v} | {fmt_time(med(g))} | {fmt_time(sub.get('parameters_s'))} | "
              f"{fmt_time(sub.get('clone_knots_control_s'))} | "
              f"{fmt_time(sub.get('clone_and_from_flat_s'))} | "
              f"{fmt_time(sub.get('eval_many_par_at_data_s'))} | "
              f"{fmt_time(sub.get('copy_points_s'))} |")
        w("")

    # ------------------------------------------------------------ curve eval
    w("## Curve evaluation (3-D output)")
    w("")
    w("| curve (N) | parameters | geomkit call | geomkit | pts/s | SciPy `spl(x)` | SciPy pts/s | "
      "ratio (pts/s) | agreement | vs geomkit direct |")
    w("|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    kind_label = dict(fd="`sample_uniform_fd`", par="`eval_many_par`",
                      seq="`eval_many` (sequential)",
                      pp="`to_piecewise` once, then its `eval_many_par`")
    for row in res["curve_eval"]:
        gk, sp = row["geomkit"], row["scipy"]
        by_params = {k["params"]: k for k in sp["kinds"]}
        for k in gk["kinds"]:
            if not k.get("ok"):
                w(f"| {row['variant']} | — | {k.get('error')} |||||||")
                continue
            s = by_params[k["params"]]
            pname = {"uniform": f"{fmt_n(k['count'])} uniform",
                     "sorted": f"{fmt_n(k['count'])} random, sorted",
                     "unsorted": f"{fmt_n(k['count'])} random, unsorted"}[k["params"]]
            if s["count"] != k["count"]:
                pname += f" (SciPy: first {fmt_n(s['count'])})"
            r = rate(k) / rate(s)
            w(f"| {row['variant']} knots ({fmt_n(row['n'])}) | {pname} | {kind_label[k['kind']]} | "
              f"{fmt_time(med(k))} | {fmt_rate(rate(k))} | {fmt_time(med(s))} | "
              f"{fmt_rate(rate(s))} | {r:.3g}× | {fmt_err(k.get('agreement_rel'))} | "
              f"{fmt_err(k.get('vs_direct_rel'))} |")
            if k["kind"] == "fd":
                goal(f"uniform evaluation, {row['variant']} knots ({fmt_n(k['count'])} samples)",
                     f"{fmt_rate(rate(k))} ({r:.3g}× SciPy)",
                     f"≥ {GOALS['uniform_eval'] / 1e6:g} M pts/s",
                     rate(k) >= GOALS["uniform_eval"])
            if k["kind"] in ("par", "pp") and k["params"] != "uniform":
                form = "piecewise form, " if k["kind"] == "pp" else ""
                goal(f"arbitrary evaluation, {form}{k['params']}, {row['variant']} knots",
                     f"{fmt_rate(rate(k))} ({r:.3g}× SciPy)",
                     f"≥ {GOALS['arbitrary_eval'] / 1e6:g} M pts/s",
                     rate(k) >= GOALS["arbitrary_eval"])
        ff = gk.get("fill_floor")
        if ff:
            w(f"| {row['variant']} knots | *floor: filling a {fmt_n(ff['count'])}×3 buffer "
              f"({ff['threads']} threads)* | | {fmt_time(ff['seconds'])} | "
              f"{fmt_rate(ff['count'] / ff['seconds'])} | | | | | |")
    w("")
    for row in res["curve_eval"]:
        pb = row["geomkit"].get("piecewise_build")
        if pb:
            w(f"- `to_piecewise` on {row['variant']} knots ({fmt_n(row['n'])} points): "
              f"{fmt_time(pb['median_s'])} (once per curve; not in the rows above)")
    w("")
    w("*vs geomkit direct*: the same output against `eval_into` point by point (span by span "
      "de Boor) at the same parameters (the piecewise form: its own arithmetic, a few ulps). For `sample_uniform_fd` part of it is that the differences step "
      "by the exact h while the direct evaluation takes the rounded a + k·h (up to ulp(b)/2 "
      "in the parameter, times |c′|), but most of it is the differencing's own error, which "
      "grows with N even at exactly representable parameters (next table).")
    w("")
    for row in res["curve_eval"]:
        for k in row["geomkit"]["kinds"]:
            if k.get("ok") and k["kind"] == "fd" and k.get("fd_report"):
                w(f"- `sample_uniform_fd` on {row['variant']} knots: longest run "
                  f"{k['fd_report']['max_steps']} steps, reported drift bound "
                  f"{fmt_err(k['fd_report']['bound_rel'])} relative.")
    w("")

    if res.get("fd_exact"):
        w("### Accuracy of `sample_uniform_fd` at exactly representable parameters")
        w("")
        w("Uniform knots 0..N−1, 8(N−1)+1 samples: t_k = k/8 exactly, so the parameters carry "
          "no rounding and any difference from the direct evaluation (`eval_many_par`, which "
          "agrees with SciPy to ~1e-16) is the forward differencing's own error; "
          "*reported bound* is `FdReport::bound` / max |p|.")
        w("")
        w("| N | samples | `sample_uniform_fd` vs direct | vs SciPy | reported bound | "
          "`eval_many_par` vs SciPy | longest run |")
        w("|---|---:|---:|---:|---:|---:|---:|")
        for row in res["fd_exact"]:
            ks = {k["kind"]: k for k in row["geomkit"]["kinds"] if k.get("ok")}
            fd, par = ks.get("fd", {}), ks.get("par", {})
            rep = fd.get("fd_report") or {}
            flag = "" if fd.get("params_exact") else " (parameters not exact!)"
            w(f"| {fmt_n(row['n'])} | {row['count']:,} | "
              f"{fmt_err(fd.get('vs_direct_rel'))}{flag} | "
              f"{fmt_err(fd.get('agreement_rel'))} | {fmt_err(rep.get('bound_rel'))} | "
              f"{fmt_err(par.get('agreement_rel'))} | {rep.get('max_steps', '—')} |")
        w("")

    # ------------------------------------------------------------ surfaces
    w("## Height surfaces (not-a-knot, bicubic)")
    w("")
    w("| grid | operation | geomkit call | geomkit | SciPy | ratio | geomkit pts/s | SciPy pts/s |")
    w("|---|---|---|---:|---:|---:|---:|---:|")
    for row in res["surface"]:
        sz, sp = row["size"], row["scipy"]
        for v, label in (("heights", "`interpolate_heights`"),
                         ("heights_at", "`interpolate_heights_at(xs, ys)`")):
            g = row["geomkit"][v]
            r = med(sp) / med(g)
            w(f"| {sz}² | build | {label} | {fmt_time(med(g))} | {fmt_time(med(sp))} "
              f"(`RectBivariateSpline`) | {r:.3g}× | {fmt_rate(rate(g))} | {fmt_rate(rate(sp))} |")
            if sz == max(rr["size"] for rr in res["surface"]):
                goal(f"surface build {sz}², {label}", f"{r:.3g}× ({fmt_time(med(g))} vs "
                     f"{fmt_time(med(sp))})", f"≥ {GOALS['surface_speedup']:g}×",
                     r >= GOALS["surface_speedup"])
        g = row["geomkit"]["heights"]
        ge, se = g["grid_eval"], sp["grid_eval"]
        w(f"| {sz}² | grid eval {ge['g']}×{ge['g']} | `eval_grid` | {fmt_time(med(ge))} | "
          f"{fmt_time(med(se))} (`spl(x, y)`) | {rate(ge) / rate(se):.3g}× (pts/s) | "
          f"{fmt_rate(rate(ge))} | {fmt_rate(rate(se))} |")
        w(f"| {sz}² | *floor: filling {ge['g']}² numbers* | | {fmt_time(ge.get('fill_floor_s'))} "
          f"| | | {fmt_rate(ge['g'] ** 2 / ge['fill_floor_s']) if ge.get('fill_floor_s') else '—'}"
          " | |")
        for key, label in (("scattered_seq", "`eval_into` loop (1 thread)"),
                           ("scattered_threads",
                            f"`eval_many_par` (rayon, {g['scattered_threads']['threads']} threads)")):
            ke, ss = g[key], sp["scattered"]
            note = f" (SciPy: {fmt_n(ss['count'])})" if ss["count"] != ke["count"] else ""
            w(f"| {sz}² | scattered {fmt_n(ke['count'])}{note} | {label} | {fmt_time(med(ke))} | "
              f"{fmt_time(med(ss))} (`spl.ev`) | {rate(ke) / rate(ss):.3g}× (pts/s) | "
              f"{fmt_rate(rate(ke))} | {fmt_rate(rate(ss))} |")
        if sz == max(rr["size"] for rr in res["surface"]):
            goal(f"grid evaluation ({ge['g']}² points on the {sz}² surface)",
                 f"{fmt_rate(rate(ge))} ({rate(ge) / rate(se):.3g}× SciPy)",
                 f"≥ {GOALS['grid_eval'] / 1e6:g} M pts/s", rate(ge) >= GOALS["grid_eval"])
            best = max(rate(g["scattered_seq"]), rate(g["scattered_threads"]))
            goal(f"scattered evaluation ({sz}² surface; best of `eval_into` loop / `eval_many_par`)",
                 f"{fmt_rate(best)} ({best / rate(sp['scattered']):.3g}× SciPy)",
                 f"≥ {GOALS['scattered_eval'] / 1e6:g} M pts/s", best >= GOALS["scattered_eval"])
    w("")
    w("| grid | library, call | residual at all nodes | agreement (scattered / sub-grid) | "
      "peak extra | output | temporaries / output | first build |")
    w("|---|---|---:|---:|---:|---:|---:|---:|")
    for row in res["surface"]:
        sz = row["size"]
        for v, label in (("heights", "geomkit `interpolate_heights`"),
                         ("heights_at", "geomkit `interpolate_heights_at`")):
            g = row["geomkit"][v]
            m = g["memory"]
            tr = temp_ratio(m)
            w(f"| {sz}² | {label} | {fmt_err(g['residual_rel'])} | "
              f"{fmt_err(g.get('agreement_scattered_rel'))} / "
              f"{fmt_err(g.get('agreement_grid_rel'))} | "
              f"{fmt_bytes(m.get('peak_extra_bytes'))} | {fmt_bytes(m.get('output_bytes'))} | "
              f"{f'{tr:.2f}' if tr is not None else '—'} | {fmt_time(g['time']['first_s'])} |")
            if sz == max(rr["size"] for rr in res["surface"]):
                goal(f"surface residual {sz}², {label}", fmt_err(g["residual_rel"]),
                     f"≤ {GOALS['surface_residual']:g}",
                     g["residual_rel"] <= GOALS["surface_residual"])
        sp = row["scipy"]
        m = sp["memory"]
        tr = temp_ratio(m)
        w(f"| {sz}² | SciPy `RectBivariateSpline` | {fmt_err(sp['residual_rel'])} | | "
          f"{fmt_bytes(m.get('peak_extra_bytes'))} | {fmt_bytes(m.get('output_bytes'))} | "
          f"{f'{tr:.2f}' if tr is not None else '—'} | {fmt_time(sp['time']['first_s'])} |")
    w("")

    if res.get("residual_probe"):
        w("Residual against the grid spacing (`interpolate_heights_at`, x_i = i/(n−1)): the "
          "uniform fast path solves with the exact (1, 4, 1)/6 rows, while the surface is "
          "evaluated on the stored knots x_i, whose rounded spacings differ from 1/(n−1) by "
          "up to ~i·ε relative. With a power-of-two spacing the nodes are exactly uniform:")
        w("")
        w("| grid | spacing | residual at all nodes | worst node (i, j) |")
        w("|---|---|---:|---|")
        for p in res["residual_probe"]:
            n1 = p["size"] - 1
            exact = n1 & (n1 - 1) == 0
            w(f"| {p['size']}² | 1/{n1}{' (power of two)' if exact else ''} | "
              f"{fmt_err(p['residual_rel'])} | {tuple(p['residual_at'] or ())} |")
        w("")

    # ------------------------------------------------------------ agreement goal
    worst = 0.0
    for row in res["curve_build"]:
        for g in row["geomkit"].values():
            worst = max(worst, g.get("agreement_rel") or 0.0)
    for row in res["curve_eval"]:
        for k in row["geomkit"]["kinds"]:
            if k.get("ok") and k["kind"] != "fd":
                worst = max(worst, k.get("agreement_rel") or 0.0)
    for row in res["surface"]:
        for g in row["geomkit"].values():
            worst = max(worst, g.get("agreement_scattered_rel") or 0.0,
                        g.get("agreement_grid_rel") or 0.0)
    goal("agreement with SciPy (all builds, `eval_many_par`/`eval_many`, surfaces)",
         fmt_err(worst), f"≤ {GOALS['agreement']:g}", worst <= GOALS["agreement"])

    head = ["## Goals of the issue", "",
            "Measured in this run (largest sizes of the run"
            + ("; quick mode uses small sizes, so the build and surface rows do **not** test the "
               "issue's sizes" if meta["quick"] else "") + "). The issue's own SciPy figures for "
            "this machine: make_interp_spline N=10^7 " + ISSUE_SCIPY["build_1e7"]
            + "; BSpline uniform " + ISSUE_SCIPY["uniform_eval"] + ", unsorted "
            + ISSUE_SCIPY["unsorted_eval"] + "; RectBivariateSpline build "
            + ISSUE_SCIPY["rbs_build"] + ", grid " + ISSUE_SCIPY["rbs_grid"] + ", scattered "
            + ISSUE_SCIPY["rbs_ev"] + ".", "",
            "| goal | measured | target | met |", "|---|---|---|---|"] + goals_rows + [""]
    # ------------------------------------------------------------ any degree (issue 22)
    if res.get("spline_build"):
        lines += ["", "## Any degree (`make_interp_spline`, issue 22)", "",
                  "3-D helix at its chord-length parameters, not-a-knot ends; geomkit "
                  "`make_interp_spline` (SciPy's form), SciPy `make_interp_spline(x, y, k)`. "
                  "Goal: ≥ 10× SciPy for k = 1, 2, 5, temporary memory ≤ 0.25× the output.", "",
                  "| N | k | geomkit | geomkit tiles | SciPy | speed-up (tiles) | "
                  "temporary / output (geomkit, tiles) | residual (geomkit, tiles) |",
                  "|---|---|---:|---:|---:|---:|---:|---:|"]
        for row in res["spline_build"]:
            g, p = row["geomkit"], row["scipy"]
            t = row.get("geomkit_tiled") or {}
            if not (g.get("ok") and p.get("ok") and t.get("ok")):
                lines.append(f"| {fmt_n(row['n'])} | {row['k']} | failed | | | | | |")
                continue
            gm, pm, tm = med(g), med(p), med(t)
            lines.append(f"| {fmt_n(row['n'])} | {row['k']} | {fmt_time(gm)} | {fmt_time(tm)} | "
                         f"{fmt_time(pm)} | {pm / gm:.1f}× ({pm / tm:.1f}×) | "
                         f"{fmt_ratio(temp_ratio(g.get('memory')))}, "
                         f"{fmt_ratio(temp_ratio(t.get('memory')))} | "
                         f"{fmt_err(g.get('residual_rel'))}, {fmt_err(t.get('residual_rel'))} |")
        lines.append("")
    # Insert the goals after the method section.
    at = lines.index("## Curve interpolation (3-D, not-a-knot)")
    lines[at:at] = head
    return "\n".join(lines) + "\n"


def machine_info():
    """The machine and versions of a run (shared by the side-by-side scripts)."""
    import scipy

    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = "?"
    try:
        kb = int(Path("/proc/meminfo").read_text().split()[1])
        mem = f"{kb / 2**20:.0f} GiB"
    except (OSError, ValueError, IndexError):
        pass
    try:
        rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True,
                               check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rustc = "rustc (unknown version)"
    try:
        rev = subprocess.run(["git", "-C", str(HERE), "describe", "--always", "--dirty"],
                             capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rev = "unknown"
    blas = "?"
    try:
        cfg = np.show_config(mode="dicts")
        blas = cfg["Build Dependencies"]["blas"]["name"]
    except Exception:  # noqa: BLE001 - informational only
        pass
    return dict(cpu=cpu, cores=os.cpu_count(), mem=mem, rustc=rustc, git=rev,
                python=platform.python_version(), scipy=scipy.__version__,
                numpy=np.__version__, blas=blas,
                date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()))


def machine_meta(args, res):
    flags = []
    for row in res["curve_build"]:
        flags += [r.get("input_identical") for r in row["scipy"].values()]
    for row in res["curve_eval"]:
        flags.append(row["scipy"].get("input_identical"))
    for row in res["surface"]:
        flags.append(row["scipy"].get("input_identical"))
    ident = ("yes, all cases" if flags and all(f is True for f in flags)
             else f"**NO** ({flags})")
    return dict(machine_info(), inputs_identical=ident, command=args.command,
                quick=args.quick)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rust-bin", type=Path)
    ap.add_argument("--out", type=Path, default=HERE / "RESULTS-bspline.md")
    ap.add_argument("--raw", type=Path, default=HERE / "results" / "compare_bspline.json")
    ap.add_argument("--quick", action="store_true", help="small sizes, few samples (smoke test)")
    ap.add_argument("--command", default="bash bench/compare_bspline.sh",
                    help="the command line recorded in the report")
    ap.add_argument("--from-raw", type=Path,
                    help="no measuring: re-render the Markdown of an earlier raw JSON")
    ap.add_argument("--worker", type=Path, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        json.dump(worker(json.loads(args.worker.read_text())), sys.stdout)
        print()
        return
    if args.from_raw:
        raw = json.loads(args.from_raw.read_text())
        md = markdown(raw["results"], raw["meta"], raw["config"])
        args.out.write_text(md)
        print(md)
        return
    if not args.rust_bin:
        ap.error("--rust-bin is required")
    cfg = QUICK if args.quick else FULL

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    t0 = time.perf_counter()
    log("timing (one process per case)...")
    res = measure(cfg, args.rust_bin, log)
    meta = machine_meta(args, res)
    meta["total_s"] = time.perf_counter() - t0
    md = markdown(res, meta, cfg)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(md)
    args.raw.parent.mkdir(parents=True, exist_ok=True)
    args.raw.write_text(json.dumps(dict(meta=meta, config=cfg, results=res), indent=1))
    print(md)
    log(f"wrote {args.out} and {args.raw} ({meta['total_s']:.0f} s)")


if __name__ == "__main__":
    main()
