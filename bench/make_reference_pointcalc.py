#!/usr/bin/env python3
"""Reference data for geomkit's point-calculus tests (method 4, spec/point-calculus.md).

Writes crates/geomkit/tests/data/pointcalc_scipy.json (committed; the Rust test
crates/geomkit/tests/pointcalc_reference.rs reads it and never runs Python): for several node
sets (the paper's three placements, Chebyshev points of both kinds, equispaced, irregular) and
data of dimension 1-3, SciPy's BarycentricInterpolator(x, y) evaluated at 61 parameters (every
node, points next to nodes, a uniform fill of the node interval) and its first and second
derivatives (.derivative(t, der=1|2)) at 15 parameters between the nodes; and the exact value of the
interpolant at the 61 parameters (fractions.Fraction on the exact f64 inputs, rounded once),
which tells whose rounding error a difference is.

Run (uses the pinned bench/requirements.txt in bench/.venv):
    bash bench/make_reference.sh --help >/dev/null   # creates bench/.venv if missing
    bench/.venv/bin/python bench/make_reference_pointcalc.py [--out-dir DIR]
Deterministic: same versions, same bytes. Numbers are written with repr() (exact round trip).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import random
from fractions import Fraction
from pathlib import Path

import numpy as np
import scipy
from scipy.interpolate import BarycentricInterpolator

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SEED = 20240521


def cheb1(n, a, b):
    # the same formula as geomkit's NodePreset::ChebyshevFirst
    m = n - 1
    return [(a + b) / 2 + (b - a) / 2 * math.sin(math.pi * (2 * j - m) / (2 * n)) for j in range(n)]


def cheb2(n, a, b):
    m = n - 1
    inner = [(a + b) / 2 + (b - a) / 2 * math.sin(math.pi * (2 * j - m) / (2 * m)) for j in range(n)]
    inner[0], inner[-1] = a, b
    return inner


def equi(n, a, b):
    return [a + (b - a) * (j / (n - 1)) for j in range(n - 1)] + [b]


def data(x, dim, rng):
    c = [rng.uniform(0.5, 2.0) for _ in range(dim)]
    return [[math.sin(c[d] * xi + d) + 0.3 * math.cos(3.0 * xi * c[d]) for d in range(dim)] for xi in x]


def params(x, rng):
    a, b = x[0], x[-1]
    ts = list(x)
    for xi in x[1:-1]:
        ts += [xi + 1e-9 * (b - a), xi - 1e-7 * (b - a)]
    while len(ts) < 61:
        ts.append(rng.uniform(a, b))
    return ts[:61]


def between(x, rng):
    a, b = x[0], x[-1]
    return [rng.uniform(a, b) for _ in range(15)]


def exact(x, y, ts):
    """The interpolant at the f64 parameters in exact rationals, rounded once."""
    xf = [Fraction(v) for v in x]
    yf = [[Fraction(v) for v in p] for p in y]
    out = []
    for t in ts:
        t = Fraction(t)
        acc = [Fraction(0)] * len(yf[0])
        for j, xj in enumerate(xf):
            lj = Fraction(1)
            for k, xk in enumerate(xf):
                if k != j:
                    lj *= (t - xk) / (xj - xk)
            acc = [a + lj * v for a, v in zip(acc, yf[j])]
        out.append([float(a) for a in acc])
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out-dir", default=str(ROOT / "crates/geomkit/tests/data"))
    args = ap.parse_args()
    rng = random.Random(SEED)
    sets = [
        ("paper {0,1/2,1}", [0.0, 0.5, 1.0], 2),
        ("paper {0,1/3,1}", [0.0, 1 / 3, 1.0], 2),
        ("paper {0,2/3,1}", [0.0, 2 / 3, 1.0], 3),
        ("chebyshev1 n=12 on [-1,3]", cheb1(12, -1.0, 3.0), 1),
        ("chebyshev2 n=7 on [0,1]", cheb2(7, 0.0, 1.0), 2),
        ("chebyshev2 n=40 on [-2,2]", cheb2(40, -2.0, 2.0), 1),
        ("equispaced n=6 on [0,5]", equi(6, 0.0, 5.0), 1),
        ("irregular n=9", sorted(rng.uniform(-1.0, 1.0) for _ in range(9)), 3),
    ]
    cases = []
    for name, x, dim in sets:
        y = data(x, dim, rng)
        bi = BarycentricInterpolator(np.array(x), np.array(y))
        ts = params(x, rng)
        dts = between(x, rng)
        cases.append(
            {
                "name": name,
                "nodes": x,
                "points": y,
                "t": ts,
                "values": bi(np.array(ts)).tolist(),
                "exact": exact(x, y, ts),
                "dt": dts,
                "d1": bi.derivative(np.array(dts), der=1).tolist(),
                "d2": bi.derivative(np.array(dts), der=2).tolist(),
            }
        )
    out = {
        "generator": "bench/make_reference_pointcalc.py",
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "cases": cases,
    }
    path = Path(args.out_dir) / "pointcalc_scipy.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
