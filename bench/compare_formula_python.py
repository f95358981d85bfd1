#!/usr/bin/env python3
"""From Python (issue 23, section "Speed"): geomkit's compiled evaluator of a single
composite formula (method 3) against SymPy's ``lambdify(cse=True)`` of the same formula, in
the same venv.

For each surface, the same 10^6 random (u, v) points (seeded, in the domain) are evaluated
by

- geomkit ``obj.evaluator()(u, v)``: the single formula compiled by geomkit-expr
  (``Tape::eval_batch``), on every core (and once on one thread);
- geomkit ``obj.evaluator("cells")(u, v)``: the structural evaluator (each point's cell,
  O(1) per point), equal to the formula within rounding;
- SymPy ``lambdify((u, v), expr, modules="numpy", cse=True)`` of ``obj.to_sympy()``, one
  function per coordinate, NumPy doing the arithmetic.

Wall time from Python including the conversion of the arrays (the call as a user makes it,
its result new NumPy arrays), median of repeated calls (the timing scheme of
bench/compare_bspline.py), each library in its own process; the one-off costs (geomkit: the
object and its tape; SymPy: to_sympy and lambdify) reported beside. Agreement: max |geomkit -
SymPy| / max |SymPy| over every evaluated point.

Cases: the paper's cube (geomkit.body("cube")) and a 10 x 10 bicubic composite (the cells of
a uniform bicubic B-spline surface with a 13 x 13 random net, CompositeSurface.from_bspline).
The issue's goals: >= 20x SymPy on the cube, >= 100x on the 10 x 10 composite.

Run it through `bash bench/compare_formula_python.sh` (venv, wheel). Options: --quick (10^4
points, a 3 x 3 composite; the report goes to bench/results/, git-ignored), --out FILE
(default bench/RESULTS-formula-python.md), --raw FILE
(default bench/results/compare_formula_python.json), --from-raw FILE (re-render), --note TEXT.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from compare_bspline import (  # noqa: E402  (the shared timing scheme and machine facts)
    machine_info,
    measured_first_call,
    run_json,
    time_call,
)

FULL = dict(points=1_000_000, cells=10, samples=7, min_batch=0.05, max_seconds=20.0)
QUICK = dict(points=10_000, cells=3, samples=3, min_batch=0.005, max_seconds=0.5)

SEED_NET = 20261204
SEED_POINTS = 4

# The targets: geomkit's evaluation at least this many times faster than SymPy's.
GOALS = dict(cube=20.0, composite=100.0)


# ---------------------------------------------------------------------------- fixtures


def make_object(case, cells):
    """The geomkit object of a case (built the same way in every process)."""
    import geomkit

    if case == "cube":
        return geomkit.body("cube")
    n = cells + 3  # a uniform bicubic B-spline surface with n x n control points: cells^2 cells
    knots = np.concatenate([[0.0] * 3, np.arange(cells + 1.0), [float(cells)] * 3])
    net = np.random.default_rng(SEED_NET).uniform(-1.0, 1.0, size=(n, n, 3))
    net[:, :, 0] += np.arange(n)[:, None]
    net[:, :, 1] += np.arange(n)[None, :]
    return geomkit.CompositeSurface.from_bspline(knots, knots, net, degree=(3, 3))


def points(obj, count):
    rng = np.random.default_rng(SEED_POINTS)
    (u0, u1), (v0, v1) = obj.domain
    return rng.uniform(u0, u1, count), rng.uniform(v0, v1, count)


# ---------------------------------------------------------------------------- worker


def worker(case):
    from importlib.metadata import version as dist_version

    knobs = dict(samples=case["samples"], min_batch=case["min_batch"],
                 max_seconds=case["max_seconds"])
    t0 = time.perf_counter()
    obj = make_object(case["case"], case["cells"])
    u, v = points(obj, case["points"])
    out = dict(case=case["case"], lib=case["lib"], method=case.get("method"),
               threads=case.get("threads"), points=case["points"], ok=True,
               op_count=obj.op_count)
    if case["lib"] == "geomkit":
        out["version"] = dist_version("geomkit")
        f = obj.evaluator(case["method"], case.get("threads"))
        f(u[:1], v[:1])  # the tape is compiled here
        out["setup_s"] = time.perf_counter() - t0
    else:
        import sympy

        out["version"] = sympy.__version__
        t1 = time.perf_counter()
        exprs = obj.to_sympy()
        t2 = time.perf_counter()
        syms = sympy.symbols(obj.variables)
        fs = [sympy.lambdify(syms, e, modules="numpy", cse=True) for e in exprs]
        t3 = time.perf_counter()

        def f(a, b):
            return tuple(np.broadcast_to(g(a, b), a.shape) for g in fs)

        out.update(to_sympy_s=t2 - t1, lambdify_s=t3 - t2)
    vals, first, mem = measured_first_call(lambda: f(u, v),
                                           lambda r: int(sum(np.asarray(a).nbytes for a in r)))
    _, t = time_call(lambda: f(u, v), first=first, **knobs)
    out.update(time=t, memory=mem)
    # the values for the agreement, as a binary file (10^6 x 3 numbers are too many for JSON)
    path = case["values_path"]
    np.save(path, np.array([np.asarray(a, dtype=np.float64) for a in vals]))
    return out


# ---------------------------------------------------------------------------- driver


def run_case(case, log, label):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(case, f)
        path = f.name
    try:
        return run_json([sys.executable, str(Path(__file__).resolve()), "--worker", path],
                        label, log)
    finally:
        os.unlink(path)


def measure(cfg, log):
    knobs = {k: cfg[k] for k in ("points", "cells", "samples", "min_batch", "max_seconds")}
    res = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in ("cube", "composite"):
            name = "cube" if case == "cube" else f"{cfg['cells']}x{cfg['cells']} bicubic"
            runs = [dict(lib="sympy"),
                    dict(lib="geomkit", method="tape"),
                    dict(lib="geomkit", method="tape", threads=1),
                    dict(lib="geomkit", method="cells")]
            row = dict(case=case, name=name, runs=[])
            for k, r in enumerate(runs):
                values = str(Path(tmp) / f"{case}-{k}.npy")
                label = f"{name:<16} {r['lib']:<8} {r.get('method') or 'lambdify(cse=True)'}" \
                        + (f" threads={r['threads']}" if r.get("threads") else "")
                out = run_case(dict(case=case, values_path=values, **r, **knobs), log, label)
                out["values_path"] = values
                row["runs"].append(out)
            ref = np.load(row["runs"][0]["values_path"])
            scale = float(np.abs(ref).max())
            for out in row["runs"]:
                vals = np.load(out.pop("values_path"))
                out["agreement"] = float(np.abs(vals - ref).max()) / scale
            res.append(row)
    return res


# ---------------------------------------------------------------------------- report


def fmt_time(s):
    if s >= 1.0:
        return f"{s:.2f} s"
    if s >= 1e-3:
        return f"{s * 1e3:.1f} ms"
    return f"{s * 1e6:.0f} µs"


def markdown(res, meta):
    L = ["# Composite formulas from Python: geomkit's compiled evaluator vs SymPy lambdify", ""]
    L.append(f"Command: `{meta['command']}` ({meta['date']}; {meta['cpu']}, {meta['cores']} "
             f"cores, {meta['mem']}; Python {meta['python']}, NumPy {meta['numpy']}, "
             f"SymPy {meta.get('sympy', '?')}, geomkit {meta.get('geomkit', '?')}, "
             f"{meta['rustc']}, git {meta['git']})" + (" — **quick run, not a result**"
                                                       if meta.get("quick") else "") + ".")
    if meta.get("note"):
        L += ["", meta["note"]]
    L += ["", "Wall time of one call on the same random (u, v) points, arrays in and out, "
          "median of repeated calls; one-off costs beside it. Ratio: SymPy's median / ours.", "",
          "| surface | points | DAG ops | evaluator | median | one-off | × SymPy | goal | "
          "max rel. diff |",
          "|---|---:|---:|---|---:|---:|---:|---:|---:|"]
    for row in res:
        ref = row["runs"][0]["time"]["median_s"]
        goal = GOALS["cube" if row["case"] == "cube" else "composite"]
        for r in row["runs"]:
            med = r["time"]["median_s"]
            if r["lib"] == "sympy":
                what = "SymPy lambdify(cse=True), numpy"
                once = f"to_sympy {fmt_time(r['to_sympy_s'])} + lambdify " \
                       f"{fmt_time(r['lambdify_s'])}"
                ratio, met = "1", ""
            else:
                what = "geomkit " + ("tape" if r["method"] == "tape" else "cells") + \
                       (f", {r['threads']} thread" if r.get("threads") else
                        f", {meta['cores']} threads")
                once = fmt_time(r["setup_s"])
                x = ref / med
                ratio = f"{x:.1f}"
                met = f"{goal:.0f}× {'met' if x >= goal else 'not met'}"
            L.append(f"| {row['name']} | {r['points']:.0e} | {r['op_count']} | {what} | "
                     f"{fmt_time(med)} | {once} | {ratio} | {met} | {r['agreement']:.1e} |")
    L += ["", "geomkit tape: the single formula itself, compiled once by geomkit-expr and run "
          "over blocks of points (every core unless one thread is named). geomkit cells: the "
          "structural evaluator (the cell of each point, then its one patch), which the "
          "formula equals within rounding. SymPy: one lambdified function per coordinate of "
          "the formula geomkit prints, parsed by SymPy (`to_sympy`)."]
    return "\n".join(L) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worker", metavar="CASE_JSON_FILE")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", help="default bench/RESULTS-formula-python.md; with --quick "
                    "bench/results/compare_formula_python-quick.md (a smoke test is no result)")
    ap.add_argument("--raw", default=str(HERE / "results" / "compare_formula_python.json"))
    ap.add_argument("--from-raw", metavar="FILE")
    ap.add_argument("--command", default="bash bench/compare_formula_python.sh")
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
        res = measure(cfg, log)
        from importlib.metadata import version as dist_version

        meta = dict(machine_info(), command=args.command, quick=args.quick, note=args.note,
                    sympy=dist_version("sympy"), geomkit=dist_version("geomkit"))
        meta["seconds"] = time.perf_counter() - t0
        raw_path = Path(args.raw)
        raw_path.parent.mkdir(parents=True, exist_ok=True)
        raw_path.write_text(json.dumps(dict(meta=meta, config=cfg, results=res)))
        log(f"raw numbers: {raw_path} ({meta['seconds']:.0f} s in all)")
    md = markdown(res, meta)
    print(md)
    out = args.out or (HERE / "results" / "compare_formula_python-quick.md" if meta.get("quick")
                       else HERE / "RESULTS-formula-python.md")
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    Path(out).write_text(md)


if __name__ == "__main__":
    main()
