#!/usr/bin/env python3
"""Reference data for geomkit's integration tests, computed by other libraries.

Writes two deterministic JSON files into crates/geomkit/tests/data/ (committed; the Rust
tests read them with include_str! and never run Python):

- bezier_reference.json (method 1, spec/bezier-order.md): fixed pseudo-random Bézier curves
  (2-D and 3-D, degrees 3, 7, 20, 40) with
  (a) exact degree elevation to n+1, n+5, 2n by the closed form
      C(n,i) C(N-n,j-i) / C(N,j) in fractions.Fraction on the exact values of the f64
      inputs, rounded once to f64 (float(Fraction) rounds correctly);
  (b) the `bezier` package's chain of Curve.elevate() calls to the same degrees;
  (c) evaluation at 21 fixed parameters by `bezier`'s Curve.evaluate_multi and the exact
      value at the f64 parameter (Fractions, rounded once);
  (d) for n = 7 the exact power coefficients S = U·H (formula (5)) as "p/q" strings;
  (e) the paper's Example 2 with its exact S_5, the exact matrix H_5 E H_3^-1 and the exact
      cubic.
- bspline_scipy.json (method 2, spec/bspline-interpolation.md): SciPy's
  make_interp_spline(x, y, k=3, bc_type=...) for not-a-knot, natural, clamped (first
  derivative 0 at both ends, SciPy's meaning of "clamped") and periodic ends on data sets
  with uniform x = 0..N-1, non-uniform (given) x, and chord-length / centripetal x computed
  exactly as geomkit computes them; values at 80 (200 for the 50-point set) parameters
  (every data site, both sides of every interior site, uniform fill), first and second
  derivatives at 20 (one data set has a last interval 1/100 of the one before it); and
  RectBivariateSpline(x, y, z, kx=3, ky=3, s=0) on a 12×9 grid of heights with uniform,
  mildly non-uniform and random coordinates: values on a 30×30 grid, partial derivatives
  at 10 points.

Run through `bash bench/make_reference.sh` (creates bench/.venv from the pinned
bench/requirements.txt). Directly: `bench/.venv/bin/python bench/make_reference.py
[--out-dir DIR]`.

Numbers are written with repr(), which round-trips every f64 exactly; the Bézier control
points are also kept as float.hex() strings so a test can check that its JSON parser rounds
correctly.
"""

from __future__ import annotations

import argparse
import math
import platform
import random
import sys
from fractions import Fraction
from math import comb
from pathlib import Path

import numpy as np
import scipy
from scipy.interpolate import RectBivariateSpline, make_interp_spline

import bezier

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
COMMAND = "bash bench/make_reference.sh"
SEED = 20110101


def versions():
    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "bezier": bezier.__version__,
    }


# ---------------------------------------------------------------------------- JSON output


def dump(obj, indent=0) -> str:
    """JSON with f64 as repr (exact round trip), dicts one key per line, lists of numbers on
    one line, lists of rows one row per line (readable diffs, deterministic bytes)."""
    pad = " " * indent
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [f'{pad} "{k}": {dump(v, indent + 1)}' for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(obj, (list, tuple)):
        if all(not isinstance(v, (list, tuple, dict)) for v in obj):
            return "[" + ",".join(dump(v) for v in obj) + "]"
        items = [pad + " " + dump(v, indent + 1) for v in obj]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    if isinstance(obj, bool):
        return "true" if obj else "false"
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        if not math.isfinite(x):
            raise ValueError("non-finite number in reference data")
        return repr(x)
    if isinstance(obj, (int, np.integer)):
        return str(int(obj))
    if isinstance(obj, str):
        return '"' + obj.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if obj is None:
        return "null"
    raise TypeError(type(obj))


def rows(a):
    """A 2-D array-like as a list of lists of Python floats."""
    return [[float(v) for v in r] for r in np.asarray(a, dtype=float)]


def hexes(a):
    return [[float(v).hex() for v in r] for r in np.asarray(a, dtype=float)]


def frac_str(q: Fraction) -> str:
    return f"{q.numerator}/{q.denominator}"


# ---------------------------------------------------------------------------- Bézier


def exact_elevate(pts, n_new):
    """Closed form (8): v_j = sum_i C(n,i) C(N-n,j-i) / C(N,j) u_i, in Fractions."""
    n, dim = len(pts) - 1, len(pts[0])
    k = n_new - n
    out = []
    for j in range(n_new + 1):
        acc = [Fraction(0)] * dim
        for i in range(max(0, j - k), min(n, j) + 1):
            w = Fraction(comb(n, i) * comb(k, j - i), comb(n_new, j))
            acc = [a + w * x for a, x in zip(acc, pts[i])]
        out.append(acc)
    return out


def exact_eval(pts, t: float):
    """sum_i C(n,i) t^i (1-t)^(n-i) u_i at the exact value of the f64 t, in Fractions."""
    n, dim = len(pts) - 1, len(pts[0])
    tf = Fraction(t)
    sf = 1 - tf
    acc = [Fraction(0)] * dim
    for i in range(n + 1):
        b = comb(n, i) * tf**i * sf ** (n - i)
        acc = [a + b * x for a, x in zip(acc, pts[i])]
    return acc


def h_matrix(n):
    """H_n of formula (4): h_ij = (-1)^(j-i) C(n,j) C(j,i) for i <= j."""
    return [[Fraction((-1) ** (j - i) * comb(n, j) * comb(j, i)) if i <= j else Fraction(0)
             for j in range(n + 1)] for i in range(n + 1)]


def h_inverse(n):
    """(H_n^-1)_ij = C(j,i) / C(n,i) for i <= j."""
    return [[Fraction(comb(j, i), comb(n, i)) if i <= j else Fraction(0)
             for j in range(n + 1)] for i in range(n + 1)]


def matmul(a, b):
    return [[sum((a[i][k] * b[k][j] for k in range(len(b))), Fraction(0))
             for j in range(len(b[0]))] for i in range(len(a))]


def power_coefficients(pts):
    """S = U·H (formula (5)) as rows: row j holds coefficient j of every coordinate (the
    layout of geomkit's to_power: index j*dim + k)."""
    n, dim = len(pts) - 1, len(pts[0])
    h = h_matrix(n)
    return [[sum((pts[i][k] * h[i][j] for i in range(n + 1)), Fraction(0)) for k in range(dim)]
            for j in range(n + 1)]


def to_float_rows(frs):
    return [[float(x) for x in r] for r in frs]


def bezier_reference():
    rng = random.Random(SEED)
    eval_ts = [k / 20 for k in range(21)]
    curves = []
    for dim in (2, 3):
        for n in (3, 7, 20, 40):
            # Coordinates in [-10, 10) with an offset, so the scale is not 1.
            pts = [[rng.uniform(-10.0, 10.0) + 3.0 * k for k in range(dim)]
                   for _ in range(n + 1)]
            pf = [[Fraction(x) for x in p] for p in pts]
            nodes = np.asfortranarray(np.array(pts, dtype=float).T)
            curve = bezier.Curve(nodes, degree=n, copy=True)
            targets = sorted({n + 1, n + 5, 2 * n})
            elevations = []
            c = curve
            for target in targets:
                while c.degree < target:
                    c = c.elevate()
                exact = exact_elevate(pf, target)
                elevations.append({
                    "target": target,
                    "exact": to_float_rows(exact),
                    "bezier_chain": rows(c.nodes.T),
                })
            entry = {
                "name": f"{dim}d_n{n}",
                "dim": dim,
                "degree": n,
                "points": pts,
                "points_hex": hexes(pts),
                "elevations": elevations,
                "eval_exact": to_float_rows([exact_eval(pf, t) for t in eval_ts]),
                "eval_bezier": rows(curve.evaluate_multi(np.array(eval_ts)).T),
            }
            if n == 7:
                entry["power_exact"] = [[frac_str(x) for x in r] for r in power_coefficients(pf)]
            curves.append(entry)

    # Example 2 of the paper (spec/bezier-order.md §3).
    ex2 = [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]
    ef = [[Fraction(x) for x in p] for p in ex2]
    s5 = power_coefficients(ef)
    # H_5 E_(6,4) H_3^-1
    e = [[Fraction(1) if i == j else Fraction(0) for j in range(4)] for i in range(6)]
    k53 = matmul(matmul(h_matrix(5), e), h_inverse(3))
    # U_3 = U_5 K with U as (n+1)×dim rows: u3_j = sum_i K_ij u5_i.
    cubic = [[sum((k53[i][j] * ef[i][c] for i in range(6)), Fraction(0)) for c in range(2)]
             for j in range(4)]
    assert exact_elevate(cubic, 5) == ef, "the cubic must elevate back to Example 2"
    assert all(x == 0 for r in s5[4:] for x in r), "Example 2 has real degree 3"
    example2 = {
        "points": [[float(x) for x in p] for p in ex2],
        "power_exact": [[frac_str(x) for x in r] for r in s5],
        "matrix_5_3_exact": [[frac_str(x) for x in r] for r in k53],
        "cubic_exact": [[frac_str(x) for x in r] for r in cubic],
        "real_degree": 3,
    }
    return {
        "about": "Bézier degree elevation and evaluation (spec/bezier-order.md) computed by the "
                 "`bezier` package and exactly with fractions.Fraction on the exact values of "
                 "the f64 inputs (rounded once to f64). Points are rows [x, y(, z)]. "
                 "power_exact: row j = power coefficient s_j of every coordinate (S = U·H, "
                 "formula (5)), exact \"p/q\". bezier_chain: Curve.elevate() applied "
                 "(target - degree) times. eval_*: one row per parameter of eval_parameters.",
        "generator": COMMAND,
        "versions": versions(),
        "seed": SEED,
        "eval_parameters": eval_ts,
        "curves": curves,
        "example2": example2,
    }


# ---------------------------------------------------------------------------- B-splines


def geomkit_distance(a, b):
    """crate::numeric::distance, operation for operation: sqrt(Σ (x-y)²) summed left to right
    from 0 when that sum is finite and >= 2^-900, else m·sqrt(Σ ((x-y)/m)²) with
    m = max |x-y|."""
    s = 0.0
    for x, y in zip(a, b):
        s += (x - y) * (x - y)
    if math.isfinite(s) and s >= 2.0 ** -900:
        return math.sqrt(s)
    m = 0.0
    for x, y in zip(a, b):
        m = max(m, abs(x - y))
    if m == 0.0 or not math.isfinite(m):
        return m
    s = 0.0
    for x, y in zip(a, b):
        q = (x - y) / m
        s += q * q
    return m * math.sqrt(s)


def geomkit_parameters(pts, centripetal=False):
    """Parametrization::ChordLength / Centripetal of geomkit (t_0 = 0,
    t_(i+1) = t_i + |p_(i+1) - p_i| (square root of it for centripetal)), bit for bit."""
    t = [0.0]
    for a, b in zip(pts[:-1], pts[1:]):
        d = geomkit_distance(a, b)
        t.append(t[-1] + (math.sqrt(d) if centripetal else d))
    return t


def eval_parameters(x, count):
    """Every data site, points just either side of each interior site (both polynomial
    pieces next to a knot), and uniform fill: `count` distinct parameters in [x0, x_end],
    sorted."""
    x = [float(v) for v in x]
    x0, x1 = x[0], x[-1]
    h = min(b - a for a, b in zip(x[:-1], x[1:]))
    base = set(x)
    for v in x[1:-1]:
        base.add(v - 1e-7 * h)
        base.add(v + 1e-7 * h)
    fill = max(count - len(base), 10)
    while True:
        ts = set(base)
        ts.update(x0 + (x1 - x0) * k / (fill + 1) for k in range(1, fill + 1))
        if len(ts) >= count:
            return sorted(ts)
        fill += count - len(ts)


def deriv_parameters(x, count=20):
    """count parameters: both ends, and interior points between the sites."""
    x0, x1 = float(x[0]), float(x[-1])
    return [x0] + [x0 + (x1 - x0) * (k + 0.37) / (count - 1) for k in range(count - 2)] + [x1]


BC_TYPES = [
    # (name in the JSON, SciPy's bc_type)
    ("not-a-knot", None),
    ("natural", "natural"),
    ("clamped", "clamped"),
    ("periodic", "periodic"),
]


def data_sets():
    """(name, parametrization, x, points, end conditions, evaluation count) with points
    rows of dimension d; the periodic variant appends the first point again (and one more
    parameter)."""
    rng = random.Random(SEED + 1)
    sets = []
    # (i) uniform x = 0..N-1: a 6-point 2-D trajectory like the paper's, and 50 noisy points
    # of a 3-D helix-like sine.
    all_bc = [b[0] for b in BC_TYPES]
    traj = [[0.0, 0.0, 0.0], [1.5, 2.0, 0.5], [3.0, 2.5, 1.5], [4.5, 0.5, 1.0],
            [6.0, 1.0, 0.25], [7.0, 3.0, 0.75]]
    sets.append(("uniform6", "uniform", [float(i) for i in range(6)], traj, all_bc, 80))
    sine = []
    for i in range(50):
        sine.append([math.sin(0.2 * i) + 0.05 * rng.uniform(-1, 1),
                     math.cos(0.13 * i) + 0.05 * rng.uniform(-1, 1)])
    sets.append(("uniform50_sine", "uniform", [float(i) for i in range(50)], sine, all_bc,
                 200))
    # (ii) non-uniform given x: sorted random in [0, 10], 2-D values.
    xs = sorted(rng.uniform(0.0, 10.0) for _ in range(15))
    xs[0], xs[-1] = 0.0, 10.0
    pts = [[math.sin(v) + 0.1 * rng.uniform(-1, 1), 0.2 * v * v + rng.uniform(-1, 1)]
           for v in xs]
    sets.append(("given15", "given", xs, pts, all_bc, 80))
    # A last interval 1/100 of the one before it (a short end interval, as near a dense
    # sampling's end): well-conditioned for SciPy.
    xs = sorted(rng.uniform(0.0, 9.0) for _ in range(11))
    xs[0], xs[-1] = 0.0, 9.0
    xs.append(xs[-1] + 0.01 * (xs[-1] - xs[-2]))
    pts = [[math.sin(1.7 * v) + 0.3 * v, math.cos(0.9 * v)] for v in xs]
    sets.append(("given12_short_end", "given", xs, pts, all_bc[:3], 80))
    # (iii) chord-length (and centripetal) parameters of a 2-D point set, as geomkit does.
    spiral = []
    for i in range(20):
        r = 1.0 + 0.3 * i + 0.2 * rng.uniform(-1, 1)
        a = 0.55 * i + 0.1 * rng.uniform(-1, 1)
        spiral.append([r * math.cos(a), r * math.sin(a)])
    sets.append(("chord20", "chord_length", None, spiral, all_bc, 80))
    sets.append(("centripetal20", "centripetal", None, spiral, ["not-a-knot"], 80))
    return sets


def curve_cases():
    cases = []
    for name, param, x, pts, bcs, count in data_sets():
        for bc_name, bc in BC_TYPES:
            if bc_name not in bcs:
                continue
            p = [list(r) for r in pts]
            xx = None if x is None else list(x)
            if bc == "periodic":
                p = p + [list(p[0])]
                if param == "uniform":
                    xx = [float(i) for i in range(len(p))]
                elif param == "given":
                    xx = xx + [xx[-1] + (xx[-1] - xx[0]) / (len(xx) - 1)]
            if param in ("chord_length", "centripetal"):
                xx = geomkit_parameters(p, centripetal=param == "centripetal")
            xa = np.array(xx, dtype=float)
            ya = np.array(p, dtype=float)
            spl = make_interp_spline(xa, ya, k=3, bc_type=bc)
            ts = eval_parameters(xa, count)
            dts = deriv_parameters(xa)
            case = {
                "name": f"{name}/{bc_name}",
                "data_set": name,
                "parametrization": param,
                "bc_type": bc_name,
                "dim": ya.shape[1],
                "x": [float(v) for v in xa],
                "y": rows(ya),
                "eval_t": ts,
                "eval": rows(spl(np.array(ts))),
                "deriv_t": dts,
                "d1": rows(spl(np.array(dts), nu=1)),
                "d2": rows(spl(np.array(dts), nu=2)),
            }
            if param == "given":
                # SciPy's own B-spline, to check geomkit's evaluation on its knots.
                case["scipy_knots"] = [float(v) for v in spl.t]
                case["scipy_coeffs"] = rows(spl.c)
            cases.append(case)
    return cases


def surface_cases():
    rng = random.Random(SEED + 2)
    nx, ny = 12, 9
    cases = []
    grids = {
        # x_i = x0 + i·dx exactly as geomkit's interpolate_heights maps its knots.
        "uniform": ([-1.5 + i * 0.25 for i in range(nx)], [2.0 + j * 0.5 for j in range(ny)],
                    (-1.5, 2.0), (0.25, 0.5)),
        # Mildly non-uniform: spacings within a factor ~2 of each other.
        "nonuniform_mild": ([-2.0 + 0.45 * i + 0.1 * math.sin(2.3 * i) for i in range(nx)],
                            [0.125 * j + 0.03 * math.cos(1.7 * j) for j in range(ny)],
                            None, None),
    }
    # Sorted random coordinates: spacings from 0.001 to 0.8 (x ends with a short interval).
    xs_nu = sorted(rng.uniform(-2.0, 3.0) for _ in range(nx))
    ys_nu = sorted(rng.uniform(0.0, 1.0) for _ in range(ny))
    grids["nonuniform_random"] = (xs_nu, ys_nu, None, None)
    for name, (xs, ys, origin, spacing) in grids.items():
        z = [[math.sin(1.3 * x) * math.cos(2.1 * y) + 0.3 * x * y + 0.05 * rng.uniform(-1, 1)
              for y in ys] for x in xs]
        xa, ya, za = np.array(xs), np.array(ys), np.array(z)
        spl = RectBivariateSpline(xa, ya, za, kx=3, ky=3, s=0)
        ex = np.linspace(xs[0], xs[-1], 30)
        ey = np.linspace(ys[0], ys[-1], 30)
        # Replace a few by data coordinates to hit knots and sites exactly.
        ex[7], ex[19], ey[4], ey[22] = xs[3], xs[8], ys[2], ys[6]
        ex.sort()
        ey.sort()
        tx, ty = spl.get_knots()
        pts = [(ex[3 * k + 1], ey[(7 * k) % 30]) for k in range(10)]
        derivs = []
        for (dx, dy) in [(1, 0), (0, 1), (1, 1), (2, 0), (0, 2)]:
            derivs.append({
                "order": [dx, dy],
                "values": [float(spl.ev(px, py, dx=dx, dy=dy)) for px, py in pts],
            })
        entry = {
            "name": name,
            "x": [float(v) for v in xs],
            "y": [float(v) for v in ys],
            "z": rows(za),
            "scipy_knots_x": [float(v) for v in tx],
            "scipy_knots_y": [float(v) for v in ty],
            "scipy_coeffs": [float(v) for v in spl.get_coeffs()],
            "eval_x": [float(v) for v in ex],
            "eval_y": [float(v) for v in ey],
            "eval": rows(spl(ex, ey)),
            "deriv_points": [[float(px), float(py)] for px, py in pts],
            "derivs": derivs,
        }
        if origin is not None:
            entry["origin"] = list(origin)
            entry["spacing"] = list(spacing)
        cases.append(entry)
    return cases


def bspline_reference():
    return {
        "about": "SciPy's interpolating cubic splines. curves: make_interp_spline(x, y, k=3, "
                 "bc_type=...) with bc_type not-a-knot (SciPy's default), natural (second "
                 "derivative 0 at both ends), clamped (SciPy's meaning: FIRST derivative 0 at "
                 "both ends, w.r.t. x) and periodic (y[0] == y[-1]: the first point repeated "
                 "at the end). parametrization says how x was made: uniform (x = 0..N-1), "
                 "given (sorted random), chord_length / centripetal (computed in Python "
                 "operation for operation as geomkit's Parametrization does, so x equals "
                 "geomkit's parameters bit for bit). eval / d1 / d2: rows at eval_t / "
                 "deriv_t. scipy_knots / scipy_coeffs (given x only): SciPy's BSpline (t, c). surfaces: "
                 "RectBivariateSpline(x, y, z, kx=3, ky=3, s=0); z[i][j] at (x[i], y[j]); "
                 "FITPACK's interpolation knots leave out x[1] and x[-2] (and y[1], y[-2]): "
                 "not-a-knot in both directions. eval[a][b] at (eval_x[a], eval_y[b]); "
                 "scipy_coeffs row-major (x index major), derivs at deriv_points.",
        "generator": COMMAND,
        "versions": versions(),
        "seed": SEED,
        "curves": curve_cases(),
        "surfaces": surface_cases(),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out-dir", type=Path, default=ROOT / "crates/geomkit/tests/data")
    args = ap.parse_args()
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for name, make in [("bezier_reference.json", bezier_reference),
                       ("bspline_scipy.json", bspline_reference)]:
        path = args.out_dir / name
        text = dump(make()) + "\n"
        path.write_text(text, encoding="utf-8")
        print(f"wrote {path.relative_to(ROOT) if path.is_relative_to(ROOT) else path} "
              f"({len(text.encode()) / 1024:.0f} KiB)", file=sys.stderr)


if __name__ == "__main__":
    main()
