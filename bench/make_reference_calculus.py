#!/usr/bin/env python3
"""Reference data for geomkit's B-spline calculus (issue 22), computed by SciPy.

Writes crates/geomkit/tests/data/bspline_calculus_scipy.json (deterministic; committed; read
by crates/geomkit/tests/reference_calculus.rs, which never runs Python):

- curves: scipy.interpolate.BSpline(t, c, k) for k = 0..7 on clamped and non-clamped
  (strictly increasing, uneven) knots, with 1-D and 3-D coefficients, two with a repeated
  interior knot (derivatives that jump there), and three periodic interpolants
  (make_interp_spline(..., bc_type='periodic'), k = 2, 3, 5). For each:
  (a) b(x, nu, extrapolate) at every distinct knot of the base interval, a point inside,
      one just below the end, three beyond both ends (up to 2.3 periods away) and NaN:
      every nu = 0..k+1 with extrapolate=True, nu = 0 with False, with 'periodic' nu = 0
      (nu in {0, 1, k} for the periodic splines);
  (b) b.derivative(nu).t/.c for nu = 1, k, k+1 (or the error SciPy raises), and
      b.antiderivative(nu).t/.c for nu = 1 (and 2 for k = 3); `c` cut to the
      len(t) - k - 1 coefficients the spline uses (SciPy pads it to len(t));
  (c) b.integrate(a, b, extrapolate) for ranges inside, crossing either end, beyond
      the end, reversed, and spanning several periods. With extrapolate=False
      every coordinate is integrated as a 1-D spline (SciPy's FITPACK splint path: the part
      inside the base interval, 0 if none; SciPy's path for n-D coefficients evaluates the
      antiderivative outside the base interval instead and gives NaN there). For k >= 6
      splint crashes (see nan_integral): the n-D path, NaN (null) where [a, b] misses
      the base interval;
  (d) b.insert_knot(x, m).t/.c: k times between knots, twice at an interior knot, once at
      t_n for k <= 3 (periodic splines: with extrapolate='periodic'), and outside t_n (an
      error).
  Knots and coefficients are rounded to 3 decimals (short inputs; outputs in full).
- surfaces: RectBivariateSpline(x, y, z, kx, ky, s=0) for (kx, ky) = (3, 3), (1, 2),
  (5, 4) on uneven grids: its tck; s(x, y, dx, dy, grid=True) on sorted x, y reaching
  beyond the domain (FITPACK clamps them to it); s.ev(x, y, dx, dy) at scattered points
  (NaN included); s.integral(xa, xb, ya, yb) inside, across and beyond the domain, reversed.

NaN is written as null. Numbers with repr() (exact round trip). Run through
`bash bench/make_reference.sh`, or directly with
`bench/.venv/bin/python bench/make_reference_calculus.py [--out-dir DIR]`.
"""

from __future__ import annotations

import argparse
import math
import platform
from pathlib import Path

import numpy as np
import scipy
from scipy.interpolate import BSpline, RectBivariateSpline, make_interp_spline

from make_reference import dump

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
COMMAND = "bash bench/make_reference.sh"
SEED = 20220622


def nulls(obj):
    """The data with NaN as None (make_reference.dump writes null; it refuses NaN)."""
    if isinstance(obj, dict):
        return {k: nulls(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [nulls(v) for v in obj]
    if isinstance(obj, (float, np.floating)) and math.isnan(obj):
        return None
    return obj


def flat(a):
    return [float(v) for v in np.asarray(a, dtype=float).ravel()]


def used(spl):
    """The coefficients the spline uses (rows), without FITPACK's padding."""
    n = len(spl.t) - spl.k - 1
    return flat(np.asarray(spl.c)[:n])


# ---------------------------------------------------------------------------- curves


def knots(rng, k, clamped, n_interior):
    """Uneven knots on [0, 3] (clamped: k+1-fold ends) or strictly increasing ones with
    the base interval inside them."""
    if clamped:
        inner = np.sort(rng.uniform(0.0, 3.0, n_interior))
        return np.r_[[0.0] * (k + 1), inner, [3.0] * (k + 1)]
    steps = rng.uniform(0.3, 1.2, n_interior + 2 * k + 1)
    return np.r_[0.0, np.cumsum(steps)] - 1.0


def eval_points(t, k):
    """Every distinct knot of the base interval, a point inside, one just below t_n,
    three outside (up to 2.3 periods away), NaN."""
    n = len(t) - k - 1
    a, b = t[k], t[n]
    p = b - a
    xs = set(float(v) for v in t[k:n + 1])
    inner = [a + p * 0.137]
    outside = [a - 0.3 * p, b + 0.4 * p, b + 2.3 * p, b - 1e-9 * p]
    xs.update(inner + outside)
    return sorted(xs) + [math.nan]


def integral_ranges(t, k):
    n = len(t) - k - 1
    a, b = float(t[k]), float(t[n])
    p = b - a
    return [
        (a + 0.1 * p, b - 0.2 * p),  # inside
        (a - 0.4 * p, a + 0.3 * p),  # across the start
        (b - 0.3 * p, b + 0.5 * p),  # across the end
        (b + 0.2 * p, b + 0.7 * p),  # after
        (b + 0.1 * p, a - 0.1 * p),  # reversed, over all of it
        (a - 1.3 * p, b + 2.6 * p),  # several periods
    ]


def one_d(spl, j):
    c = np.asarray(spl.c)
    return BSpline(spl.t, c if c.ndim == 1 else c[:, j], spl.k)


def nan_integral(spl, a, b):
    """spl.integrate(a, b, extrapolate=False) of a 1-D spline: FITPACK's splint for k <= 5;
    for k >= 6 splint overruns its fixed arrays (fpintb holds 6 B-spline values) and
    crashes the interpreter, so there the n-D path (coefficients as one column), which is
    NaN where [a, b] misses the base interval."""
    if spl.k <= 5:
        return float(spl.integrate(a, b, extrapolate=False))
    col = BSpline(spl.t, np.asarray(spl.c)[:, None], spl.k)
    return float(col.integrate(a, b, extrapolate=False)[0])


def curve_case(name, spl, periodic=False):
    t, k = np.asarray(spl.t), spl.k
    c = np.asarray(spl.c)
    dim = 1 if c.ndim == 1 else c.shape[1]
    xs = eval_points(t, k)
    xa = np.array(xs)
    case = {
        "name": name,
        "k": k,
        "dim": dim,
        "t": flat(t),
        "c": used(spl),
        "x": xs,
        "extend": [flat(spl(xa, nu=nu, extrapolate=True)) for nu in range(k + 2)],
        "nan": flat(spl(xa, nu=0, extrapolate=False)),
        "periodic_nu": sorted({0, 1, k}) if periodic else [0],
    }
    case["periodic"] = [flat(spl(xa, nu=nu, extrapolate="periodic"))
                        for nu in case["periodic_nu"]]
    derivs = []
    for nu in sorted({1, k, k + 1}):
        try:
            d = spl.derivative(nu)
            derivs.append({"nu": nu, "t": flat(d.t), "c": used(d)})
        except ValueError as e:
            derivs.append({"nu": nu, "error": str(e)})
    case["derivatives"] = derivs
    case["antiderivatives"] = [
        {"nu": nu, "t": flat(spl.antiderivative(nu).t), "c": used(spl.antiderivative(nu))}
        for nu in ((1, 2) if k == 3 else (1,))
    ]
    integrals = []
    for a, b in integral_ranges(t, k):
        with np.errstate(all="ignore"):
            nan = [nan_integral(one_d(spl, j), a, b) for j in range(dim)]
            integrals.append({
                "a": a, "b": b,
                "extend": flat(spl.integrate(a, b, extrapolate=True)),
                "nan": nan,
                "periodic": flat(spl.integrate(a, b, extrapolate="periodic")),
            })
    case["integrals"] = integrals
    n = len(t) - k - 1
    a, b = float(t[k]), float(t[n])
    interior = [float(v) for v in t[k + 1:n] if a < v < b]
    between = a + 0.4321 * (b - a)
    inserts = [(between, max(k, 1))]
    inserts.append((interior[len(interior) // 2], 2) if interior else (a, 1))
    if k <= 3:
        inserts.append((b, 1))
    ins = []
    base = BSpline(t, c, k, extrapolate="periodic") if periodic else spl
    for x, m in inserts:
        try:
            s2 = base.insert_knot(x, m)
            ins.append({"x": x, "m": m, "t": flat(s2.t), "c": used(s2)})
        except ValueError as e:
            ins.append({"x": x, "m": m, "error": str(e)})
    ins.append({"x": b + 0.01 * (b - a), "m": 1, "error": "outside"})
    case["periodic_spline"] = periodic
    case["insert_knot"] = ins
    return case


def curve_cases():
    rng = np.random.default_rng(SEED)
    cases = []
    for k in range(8):
        for clamped in (True, False):
            dim = 3 if (k, clamped) == (3, True) else 1
            t = np.round(knots(rng, k, clamped, 4), 3)
            n = len(t) - k - 1
            c = np.round(rng.uniform(-2.0, 2.0, (n, dim)) + np.arange(dim), 3)
            if dim == 1:
                c = c[:, 0]
            kind = "clamped" if clamped else "open"
            cases.append(curve_case(f"k{k}_{kind}_{dim}d", BSpline(t, c, k)))
    # Repeated interior knots: the first derivative of the quadratic and the second of the
    # cubic jump there (interval on the right); the cubic's triple knot stops derivative(2).
    t = np.r_[[0.0] * 3, 0.7, 1.4, 1.4, 2.2, [3.0] * 3]
    c = np.round(rng.uniform(-1, 1, 7), 3)
    cases.append(curve_case("k2_double_knot_1d", BSpline(t, c, 2)))
    t = np.r_[[0.0] * 4, 0.8, 1.5, 1.5, 1.5, 2.1, [3.0] * 4]
    c = np.round(rng.uniform(-1, 1, (9, 3)), 3)
    cases.append(curve_case("k3_triple_knot_3d", BSpline(t, c, 3)))
    # Periodic interpolants on uneven x.
    x = np.r_[0.0, np.round(np.sort(rng.uniform(0.2, 5.8, 7)), 3), 6.0]
    for k, dim in ((2, 1), (3, 1), (5, 1)):
        y = np.stack([np.sin(x * math.pi / 3 + j) + 0.3 * j for j in range(dim)], axis=1)
        y[-1] = y[0]
        spl = make_interp_spline(x, y if dim > 1 else y[:, 0], k=k, bc_type="periodic")
        cases.append(curve_case(f"k{k}_periodic_{dim}d", spl, periodic=True))
    return cases


# ---------------------------------------------------------------------------- surfaces


def surface_cases():
    rng = np.random.default_rng(SEED + 1)
    cases = []
    for kx, ky, nx, ny in ((3, 3, 9, 8), (1, 2, 7, 6), (5, 4, 9, 8)):
        x = np.r_[0.0, np.sort(rng.uniform(0.1, 3.9, nx - 2)), 4.0]
        y = np.r_[-1.0, np.sort(rng.uniform(-0.9, 1.9, ny - 2)), 2.0]
        z = np.sin(x[:, None]) * np.cos(1.3 * y[None, :]) + rng.uniform(-0.2, 0.2, (nx, ny))
        s = RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=0)
        tx, ty, c = s.tck
        gx = np.array(sorted([-0.7, 0.0, float(tx[kx + 1]), 1.9, 4.0, 4.6]))
        gy = np.array(sorted([-1.5, -1.0, 0.33, float(ty[ky + 1]), 2.0]))
        orders = sorted({(0, 0), (min(1, kx - 1), 0), (0, min(1, ky - 1)),
                         (min(1, kx - 1), min(1, ky - 1)), (kx - 1, ky - 1)})
        ex = [-0.5, 0.3, 1.7, 2.9, 4.0, 4.8, float(tx[kx + 2]), math.nan]
        ey = [0.1, -1.3, 1.1, 2.5, 2.0, -0.2, float(ty[ky + 1]), 0.5]
        grid, ev = [], []
        for dx, dy in orders:
            grid.append({"dx": dx, "dy": dy, "z": flat(s(gx, gy, dx=dx, dy=dy))})
            ev.append({"dx": dx, "dy": dy, "z": flat(s.ev(ex, ey, dx=dx, dy=dy))})
        ranges = [(0.3, 3.1, -0.5, 1.5), (-1.0, 5.0, -2.0, 3.0), (5.0, 6.0, 0.0, 1.0),
                  (3.1, 0.3, -0.5, 1.5), (2.0, 1.0, 1.5, 0.5), (1.0, 1.0, 0.0, 1.0)]
        integrals = [{"limits": list(r), "value": float(s.integral(*r))} for r in ranges]
        cases.append({
            "name": f"rect_{kx}{ky}_{nx}x{ny}",
            "kx": kx, "ky": ky,
            "tx": flat(tx), "ty": flat(ty), "c": flat(c),
            "grid_x": flat(gx), "grid_y": flat(gy), "grid": grid,
            "ev_x": ex, "ev_y": ey, "ev": ev,
            "integrals": integrals,
        })
    return cases


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out-dir", default=str(ROOT / "crates/geomkit/tests/data"))
    args = ap.parse_args()
    data = {
        "about": "SciPy's B-spline calculus (BSpline.__call__(x, nu, extrapolate), "
                 "derivative, antiderivative, integrate, insert_knot; RectBivariateSpline "
                 "grid/ev/integral). Coefficients row-major (n rows of dim); outputs "
                 "row-major per point; null is NaN. See bench/make_reference_calculus.py.",
        "generator": COMMAND,
        "versions": {"python": platform.python_version(), "numpy": np.__version__,
                     "scipy": scipy.__version__},
        "seed": SEED,
        "curves": curve_cases(),
        "surfaces": surface_cases(),
    }
    out = Path(args.out_dir) / "bspline_calculus_scipy.json"
    out.write_text(dump(nulls(data)) + "\n")
    print(f"wrote {out} ({out.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
