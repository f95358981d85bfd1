#!/usr/bin/env python3
"""Side-by-side comparison of geomkit's Bézier degree change and evaluation with the
Python packages `bezier` and `geomdl`: speed (median time per call, same run, same
machine) and accuracy (max error against the exact answer computed with
fractions.Fraction, relative to max |P|).

Run it through `bash bench/compare_bezier.sh` (creates bench/.venv, installs
bench/requirements.txt, builds the Rust driver). Directly:

    bench/.venv/bin/python bench/compare_bezier.py --rust-bin target/release/bezier-compare

Options: --quick (fewer samples; smoke test), --out FILE (Markdown, default
bench/RESULTS.md), --raw FILE (all numbers as JSON, default bench/results/compare.json).
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import platform
import random
import statistics
import subprocess
import sys
import time
from fractions import Fraction
from math import comb
from pathlib import Path

import numpy as np

import bezier
import geomdl
from geomdl import BSpline, helpers

HERE = Path(__file__).resolve().parent
SEED = 20110101

# ---------------------------------------------------------------------------- timing


def time_call(f, samples: int, min_batch: float, max_seconds: float):
    """The same scheme as the Rust driver: one warm-up call (its result is returned), then
    `samples` batches of `inner` calls, `inner` chosen so a batch lasts >= min_batch
    seconds, at least 3 batches, the case kept under ~max_seconds. GC is off during the
    batches (as in timeit). Returns (result, median, min, samples, inner) per call."""
    t0 = time.perf_counter()
    result = f()
    first = max(time.perf_counter() - t0, 1e-9)
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
    return result, statistics.median(times), min(times), samples, inner


def python_noop_overhead(samples: int) -> float:
    """Median time of calling a Python function that does nothing (the floor of any
    Python-side call)."""

    def noop():
        return None

    return time_call(noop, samples, 0.005, 2.0)[1]


# ---------------------------------------------------------------------------- exact math


def fr_points(points):
    return [[Fraction(x) for x in p] for p in points]


def exact_elevate(points_fr, n_new):
    """Closed form (8): u'_j = sum_i C(n,i) C(n'-n, j-i) / C(n', j) u_i, exactly."""
    n = len(points_fr) - 1
    k = n_new - n
    dim = len(points_fr[0])
    out = []
    for j in range(n_new + 1):
        acc = [Fraction(0)] * dim
        for i in range(max(0, j - k), min(n, j) + 1):
            w = Fraction(comb(n, i) * comb(k, j - i), comb(n_new, j))
            acc = [a + w * u for a, u in zip(acc, points_fr[i])]
        out.append(acc)
    return out


def exact_eval(points_fr, t: float):
    """p(t) = sum_i C(n,i) t^i (1-t)^(n-i) u_i, exactly, for the float t."""
    n = len(points_fr) - 1
    tf = Fraction(t)
    a, b = tf.numerator, tf.denominator  # t = a/b, 1 - t = (b-a)/b
    dim = len(points_fr[0])
    acc = [Fraction(0)] * dim
    for i, u in enumerate(points_fr):
        w = comb(n, i) * a**i * (b - a) ** (n - i)
        acc = [s + w * x for s, x in zip(acc, u)]
    den = b**n
    return [s / den for s in acc]


def exact_least_squares_reduction(points_fr, n_new):
    """The exact least-squares reduction of the given (f64) points to degree n_new:
    argmin_X ||E X - Q|| with E the elevation matrix n_new -> n (normal equations solved
    exactly). For a rounded elevated curve this differs from the original points by the
    input rounding amplified by the conditioning of the problem: the floor no f64
    algorithm can beat without knowing the original."""
    big_n = len(points_fr) - 1
    k = big_n - n_new
    dim = len(points_fr[0])
    cols = range(n_new + 1)
    e = [[Fraction(comb(n_new, i) * comb(k, j - i), comb(big_n, j)) if 0 <= j - i <= k
          else Fraction(0) for i in cols] for j in range(big_n + 1)]
    a = [[sum(e[j][r] * e[j][c] for j in range(big_n + 1)) for c in cols] for r in cols]
    b = [[sum(e[j][r] * points_fr[j][c] for j in range(big_n + 1)) for c in range(dim)]
         for r in cols]
    m = n_new + 1
    for col in range(m):  # Gauss-Jordan; A is symmetric positive definite
        inv = 1 / a[col][col]
        a[col] = [x * inv for x in a[col]]
        b[col] = [x * inv for x in b[col]]
        for r in range(m):
            if r != col and a[r][col] != 0:
                f = a[r][col]
                a[r] = [x - f * y for x, y in zip(a[r], a[col])]
                b[r] = [x - f * y for x, y in zip(b[r], b[col])]
    return b


def max_norm(points) -> float:
    return max(math.sqrt(sum(float(x) ** 2 for x in p)) for p in points)


def rel_error(got, exact_fr, scale: float):
    """max_j |got_j - exact_j| / scale, the difference taken exactly. None: wrong shape or
    non-finite output."""
    if got is None or len(got) != len(exact_fr):
        return None
    worst = 0.0
    for g, e in zip(got, exact_fr):
        if len(g) != len(e):
            return None
        if any(x is None or not math.isfinite(x) for x in g):
            return math.inf
        d = math.sqrt(sum(float(Fraction(x) - y) ** 2 for x, y in zip(g, e)))
        worst = max(worst, d)
    return worst / scale


# ---------------------------------------------------------------------------- cases


def make_cases():
    """Each case: id, group, op, input points, target, exact answer (or the eval subset),
    and the peers' callables."""
    rng = random.Random(SEED)

    def rand_points(n, dim=2):
        return [[rng.uniform(-1.0, 1.0) for _ in range(dim)] for _ in range(n + 1)]

    cases = []
    # Elevation by one and by k (= n, i.e. to degree 2n).
    for n in (3, 5, 20, 50):
        pts = rand_points(n)
        exact = exact_elevate(fr_points(pts), n + 1)
        cases.append(dict(id=f"elevate {n}→{n + 1}", group="elevate1", op="elevate", n=n,
                          target=n + 1, points=pts, exact=exact))
    for n in (5, 20, 50):
        pts = rand_points(n)
        exact = exact_elevate(fr_points(pts), 2 * n)
        cases.append(dict(id=f"elevate {n}→{2 * n}", group="elevatek", op="elevate", n=n,
                          target=2 * n, points=pts, exact=exact))
    # Reduction of an exactly elevated curve (rounded once to f64): the exact answer is
    # the original points.
    for n in (3, 5, 20, 50):
        orig = rand_points(n)
        elevated = [[float(x) for x in p] for p in exact_elevate(fr_points(orig), n + 1)]
        cases.append(dict(id=f"reduce {n + 1}→{n}", group="reduce1", op="reduce", n=n + 1,
                          target=n, points=elevated, exact=fr_points(orig),
                          exact_ls=exact_least_squares_reduction(fr_points(elevated), n)))
    for n in (5, 20, 50):
        orig = rand_points(n)
        elevated = [[float(x) for x in p] for p in exact_elevate(fr_points(orig), 2 * n)]
        cases.append(dict(id=f"reduce {2 * n}→{n}", group="reducek", op="reduce", n=2 * n,
                          target=n, points=elevated, exact=fr_points(orig),
                          exact_ls=exact_least_squares_reduction(fr_points(elevated), n)))
    # Evaluation at 10^4 parameters k/9999; accuracy on 101 of them (every 100th + last).
    count = 10_000
    ts = [k / (count - 1) for k in range(count)]
    subset = list(range(0, count, 100)) + [count - 1]
    for n in (3, 5, 20, 50):
        pts = rand_points(n)
        pf = fr_points(pts)
        exact = [exact_eval(pf, ts[k]) for k in subset]
        cases.append(dict(id=f"eval n={n}, 10⁴ pts", group="eval", op="eval", n=n,
                          target=None, points=pts, params=ts, subset=subset, exact=exact))
    return cases


# ---------------------------------------------------------------------------- peers


def bezier_nodes(points):
    return np.asfortranarray(np.array(points, dtype=float).T)


def peer_runs(case):
    """(library label, zero-argument callable returning points as lists) for the peers."""
    n, pts, op = case["n"], case["points"], case["op"]
    runs = []
    if op == "elevate":
        k = case["target"] - n
        curve = bezier.Curve(bezier_nodes(pts), degree=n)

        def bz():
            c = curve
            for _ in range(k):
                c = c.elevate()
            return c.nodes

        label = "bezier `Curve.elevate()`" + ("" if k == 1 else f" ×{k}")
        runs.append((label, bz, lambda r: r.T.tolist()))
        runs.append((
            "geomdl `helpers.degree_elevation`" + ("" if k == 1 else f" (num={k}, one call)"),
            lambda: helpers.degree_elevation(n, pts, num=k), lambda r: r))
        if k > 1:
            def gd_chain():
                p, d = pts, n
                for _ in range(k):
                    p = helpers.degree_elevation(d, p)
                    d += 1
                return p

            runs.append((f"geomdl `helpers.degree_elevation` ×{k} (by one)", gd_chain,
                         lambda r: r))
    elif op == "reduce":
        k = n - case["target"]
        curve = bezier.Curve(bezier_nodes(pts), degree=n)

        def bz():
            c = curve
            for _ in range(k):
                c = c.reduce_()
            return c.nodes

        runs.append(("bezier `Curve.reduce_()`" + ("" if k == 1 else f" ×{k}"), bz,
                     lambda r: r.T.tolist()))

        def gd():
            p, d = pts, n
            for _ in range(k):
                p = helpers.degree_reduction(d, p)
                d -= 1
            return p

        runs.append(("geomdl `helpers.degree_reduction`" + ("" if k == 1 else f" ×{k}"), gd,
                     lambda r: r))
    elif op == "eval":
        ts = case["params"]
        ts_np = np.array(ts)
        curve = bezier.Curve(bezier_nodes(pts), degree=n)
        runs.append(("bezier `Curve.evaluate_multi`", lambda: curve.evaluate_multi(ts_np),
                     lambda r: r.T.tolist()))
        g = BSpline.Curve()
        g.degree = n
        g.ctrlpts = pts
        g.knotvector = [0.0] * (n + 1) + [1.0] * (n + 1)
        runs.append(("geomdl `BSpline.Curve.evaluate_list`", lambda: g.evaluate_list(ts),
                     lambda r: r))
    return runs


# ---------------------------------------------------------------------------- driver


def rust_cases(cases, samples, min_batch, max_seconds):
    out = []
    for i, c in enumerate(cases):
        base = dict(points=c["points"], samples=samples, min_batch_seconds=min_batch,
                    max_seconds=max_seconds)
        if c["op"] == "eval":
            out.append(dict(base, id=f"{i}/geomkit", op="eval", params=c["params"]))
        else:
            out.append(dict(base, id=f"{i}/geomkit", op=c["op"], target=c["target"]))
            out.append(dict(base, id=f"{i}/paper", op="paper_formula", target=c["target"]))
    return out


def run_rust(rust_bin, cases, samples, min_batch, max_seconds):
    payload = json.dumps({"cases": rust_cases(cases, samples, min_batch, max_seconds)})
    proc = subprocess.run([str(rust_bin), "-"], input=payload, capture_output=True,
                          text=True, check=True)
    return {r["id"]: r for r in json.loads(proc.stdout)["results"]}


def result_points(case, points):
    """The points compared with case['exact'] (for eval: the accuracy subset)."""
    if points is None:
        return None
    if case["op"] == "eval":
        if len(points) != len(case["params"]):
            return None
        return [points[k] for k in case["subset"]]
    return points


def short_error(e: BaseException) -> str:
    msg = str(e).replace("|", "/").replace("\n", " ")
    if len(msg) > 90:
        msg = msg[:87] + "..."
    return f"{type(e).__name__}: {msg}"


def measure(cases, rust_bin, samples, min_batch, max_seconds, log):
    log("  geomkit (all cases, one process)")
    rust = run_rust(rust_bin, cases, samples, min_batch, max_seconds)
    rows = []
    for i, case in enumerate(cases):
        scale = max_norm(case["points"] if case["op"] != "reduce" else
                         [[float(x) for x in p] for p in case["exact"]])

        def errors(pts):
            got = result_points(case, pts)
            out = dict(rel_err=rel_error(got, case["exact"], scale), rel_err_ls=None)
            if "exact_ls" in case:
                out["rel_err_ls"] = rel_error(got, case["exact_ls"], scale)
            return out

        def row(lib, ok, error, median, mn, s, inner, pts):
            err = errors(pts) if ok else dict(rel_err=None, rel_err_ls=None)
            return dict(case=case["id"], group=case["group"], lib=lib, ok=ok, error=error,
                        median=median, min=mn, samples=s, inner=inner, **err)

        entries = [("geomkit", rust[f"{i}/geomkit"])]
        if case["op"] != "eval":
            entries.append(("geomkit `paper_formula_f64` (naive f64 of (10))",
                            rust[f"{i}/paper"]))
        for label, r in entries:
            rows.append(row(label, r["ok"], r["error"], r["median_s"], r["min_s"],
                            r["samples"], r["calls_per_sample"],
                            r["points"] if r["ok"] else None))
        for label, f, to_points in peer_runs(case):
            log(f"  {case['id']}: {label}")
            try:
                res, med, mn, s, inner = time_call(f, samples, min_batch, max_seconds)
                rows.append(row(label, True, None, med, mn, s, inner, to_points(res)))
            except Exception as e:  # noqa: BLE001 - a peer's failure is a result
                rows.append(row(label, False, short_error(e), None, None, 0, 0, None))
        if "exact_ls" in case:
            floor = rel_error([[float(x) for x in p] for p in case["exact_ls"]],
                              case["exact"], scale)
            rows.append(dict(case=case["id"], group=case["group"], ok=True, error=None,
                             lib="*exact least squares of the f64 input (floor)*",
                             median=None, min=None, samples=0, inner=0, rel_err=floor,
                             rel_err_ls=0.0))
    return rows


# ---------------------------------------------------------------------------- report


def fmt_time(s):
    if s is None:
        return "—"
    for unit, f in (("s", 1.0), ("ms", 1e3), ("µs", 1e6), ("ns", 1e9)):
        if s * f >= 1.0:
            return f"{s * f:.3g} {unit}"
    return f"{s * 1e9:.3g} ns"


def fmt_err(e, ok):
    if not ok:
        return "—"
    if e is None:
        return "wrong output shape"
    if math.isinf(e):
        return "non-finite output"
    if e == 0.0:
        return "0 (exact)"
    return f"{e:.1e}"


GROUPS = [
    ("elevate1", "Elevation by one (n → n+1)",
     "Input: random points in [-1,1]², exact answer by the closed form in Fractions."),
    ("elevatek", "Elevation by k = n (n → 2n)",
     "geomkit elevates in one step. bezier only elevates by one, so it is called k times; "
     "geomdl's helper takes `num=k` (one call, closed form), its by-one chain is shown too."),
    ("reduce1", "Exact reduction by one of an elevated curve (n+1 → n)",
     "Input: a random degree-n curve elevated exactly and rounded once to f64. Errors are "
     "given against the original points and against the exact least-squares reduction of "
     "the rounded input (Fractions); the *floor* row is the distance between the two, i.e. "
     "the input rounding amplified by the conditioning, which no f64 method can beat. "
     "bezier's `reduce_` supports input degrees 1-4 only. geomdl 5.4.0's "
     "`helpers.degree_reduction` (Piegl-Tiller eqs. 5.41-5.42) is wrong for input degree >= 5: "
     "its backward loop `range(degree - 2, r1 + 2)` is empty, so the points between "
     "index r1+1 and degree-2 are never computed and stay (0, 0)."),
    ("reducek", "Exact reduction by k = n of an elevated curve (2n → n)",
     "geomkit reduces in one step; the peers reduce by one, k times. Columns as above."),
    ("eval", "Evaluation at 10⁴ parameters t = k/9999",
     "Error measured on 101 of the parameters against the exact value of the polynomial at "
     "the float t (Fractions); time per call for all 10⁴ points, and per point. Algorithms: "
     "geomkit `eval_many` the Bernstein-Horner (Volk-Schumaker) scheme, O(n) per point, "
     "8 parameters at a time (de Casteljau above degree 60); bezier (compiled) the VS "
     "(Volk-Schumaker) algorithm, O(n) per point, for up to 55 control points; geomdl "
     "Cox-de Boor basis functions in pure Python, called once per parameter by "
     "`evaluate_list`."),
]


def markdown(rows, meta):
    lines = []
    w = lines.append
    w("# Side-by-side: geomkit vs `bezier` vs `geomdl` (Bézier degree change, evaluation)")
    w("")
    w(f"Generated by `{meta['command']}` on {meta['date']}.")
    w("")
    w("## Machine and versions")
    w("")
    w(f"- {meta['cpu']}, {meta['cores']} cores, **shared and noisy** (other builds ran on it; "
      "treat differences below ~1.5× as noise).")
    w(f"- {meta['rustc']}; geomkit at `{meta['git']}` (`-dirty`: uncommitted changes in the "
      "tree), built with `cargo build --release -p geomkit-bench`.")
    w(f"- Python {meta['python']}; bezier {meta['bezier']} (compiled speedups: "
      f"{meta['bezier_speedup']}), geomdl {meta['geomdl']}, numpy {meta['numpy']}.")
    w("")
    w("## Method")
    w("")
    w("- **Time**: median time per call over "
      f"{meta['samples']} batches (fewer if a case would exceed ~{meta['max_seconds']:g} s; "
      f"at least 3); each batch repeats the call until it lasts ≥ {meta['min_batch'] * 1e3:g} ms. "
      "The same scheme in Rust (`std::time::Instant`) and Python (`time.perf_counter`, GC off "
      "during batches). Inputs are prepared outside the timed call in each library's own "
      "format (Rust `BezierCurve`; bezier `Curve` with a Fortran-ordered array; geomdl lists).")
    w(f"- **Python call overhead**: an empty Python function call costs "
      f"{fmt_time(meta['python_noop'])} here; the Python libraries pay this plus object "
      "creation and argument checks on every call, which dominates the small cases. "
      "geomkit is called from Rust directly (no FFI or process boundary inside the timing).")
    w("- **ratio** = peer time / geomkit time (>1: geomkit faster).")
    w("- **rel. error** = max over output points of |computed − exact| / max |P| "
      "(P = the input control points, or the original points for reductions); the exact "
      "answer is computed with `fractions.Fraction` from the float inputs. f64 round-off is "
      "1.1e-16.")
    w("- `geomkit paper_formula_f64` is the paper's formula (10) evaluated naively in f64 "
      "(S = U·H, then H'⁻¹), kept in geomkit for comparison only; it is not the default path.")
    w("")
    for key, title, note in GROUPS:
        group = [r for r in rows if r["group"] == key]
        if not group:
            continue
        w(f"## {title}")
        w("")
        w(note)
        w("")
        is_eval = key == "eval"
        is_reduce = key.startswith("reduce")
        if is_eval:
            w("| case | library (call) | median / call | per point | ratio | rel. error | note |")
            w("|---|---|---:|---:|---:|---:|---|")
        elif is_reduce:
            w("| case | library (call) | median / call | ratio | rel. error vs original "
              "| vs exact LS of input | note |")
            w("|---|---|---:|---:|---:|---:|---|")
        else:
            w("| case | library (call) | median / call | ratio | rel. error | note |")
            w("|---|---|---:|---:|---:|---|")
        base = {r["case"]: r["median"] for r in group if r["lib"] == "geomkit"}
        for r in group:
            b = base.get(r["case"])
            ratio = "—"
            if r["lib"] == "geomkit":
                ratio = "1"
            elif r["median"] is not None and b:
                ratio = f"{r['median'] / b:.3g}×"
            note = r["error"] or ""
            if r["ok"] and r["rel_err"] is not None and r["rel_err"] > 1e-6:
                note = note or "inaccurate"
            lib = f"**{r['lib']}**" if r["lib"] == "geomkit" else r["lib"]
            cells = [r["case"], lib, fmt_time(r["median"]) if r["median"] or not r["ok"] else ""]
            if is_eval:
                cells.append(fmt_time(r["median"] / 10_000) if r["median"] else "—")
            if r["median"] is None and r["ok"]:
                ratio = ""
            cells += [ratio, fmt_err(r["rel_err"], r["ok"])]
            if is_reduce:
                cells.append(fmt_err(r["rel_err_ls"], r["ok"]))
            cells.append(note)
            w("| " + " | ".join(cells) + " |")
        w("")
    return "\n".join(lines) + "\n"


def machine_meta(args):
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True,
                               check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rustc = "rustc (unknown version)"
    try:
        import bezier._speedup  # noqa: F401

        speedup = "yes"
    except ImportError:
        speedup = "no"
    try:
        rev = subprocess.run(["git", "-C", str(HERE), "describe", "--always", "--dirty"],
                             capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        rev = "unknown"
    return dict(cpu=cpu, cores=os.cpu_count(), rustc=rustc, git=rev,
                python=platform.python_version(), bezier=bezier.__version__,
                bezier_speedup=speedup, geomdl=geomdl.__version__, numpy=np.__version__,
                samples=args.samples, min_batch=args.min_batch,
                max_seconds=args.max_seconds,
                date=time.strftime("%Y-%m-%d %H:%M %Z"),
                command=args.command)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rust-bin", required=True, type=Path)
    ap.add_argument("--out", type=Path, default=HERE / "RESULTS.md")
    ap.add_argument("--raw", type=Path, default=HERE / "results" / "compare.json")
    ap.add_argument("--quick", action="store_true", help="few samples (smoke test)")
    ap.add_argument("--samples", type=int, default=15)
    ap.add_argument("--min-batch", type=float, default=0.005)
    ap.add_argument("--max-seconds", type=float, default=5.0)
    ap.add_argument("--command", default="bash bench/compare_bezier.sh",
                    help="the command line recorded in the report")
    args = ap.parse_args()
    if args.quick:
        args.samples, args.min_batch, args.max_seconds = 3, 0.001, 0.5

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    log("building cases and exact answers (fractions)...")
    cases = make_cases()
    log(f"timing {len(cases)} cases...")
    rows = measure(cases, args.rust_bin, args.samples, args.min_batch, args.max_seconds, log)
    meta = machine_meta(args)
    meta["python_noop"] = python_noop_overhead(args.samples)
    md = markdown(rows, meta)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(md)
    args.raw.parent.mkdir(parents=True, exist_ok=True)
    args.raw.write_text(json.dumps(dict(meta=meta, rows=rows), indent=1))
    print(md)
    log(f"wrote {args.out} and {args.raw}")


if __name__ == "__main__":
    main()
