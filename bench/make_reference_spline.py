"""Reference data for geomkit's interpolating splines of any degree (issue 22):
scipy.interpolate.make_interp_spline(x, y, k, bc_type=...) for k = 1..7, every kind of end
condition pair (none / not-a-knot, periodic, derivative lists split between the ends, the
string aliases), uniform and uneven x, 1-D and 3-D values, and the fewest points each
degree takes.

Writes crates/geomkit/tests/data/spline_scipy.json (read by
crates/geomkit/tests/reference_spline.rs; the tests never run Python). Run through
`bash bench/make_reference.sh` (pinned versions in bench/requirements.txt; recorded in the
file). Deterministic: the same versions and CPU give the same bytes.
"""

import functools
import json
import math
from fractions import Fraction
import pathlib
import random
import sys

import numpy as np
import scipy
from scipy.interpolate import make_interp_spline

SEED = 20261204
OUT = pathlib.Path(__file__).resolve().parent.parent / "crates/geomkit/tests/data/spline_scipy.json"


def rows(a):
    a = np.asarray(a, dtype=float)
    if a.ndim == 1:
        return [float(v) for v in a]
    return [[float(v) for v in r] for r in a.reshape(a.shape[0], -1)]


def data_sets(rng):
    """(name, x) pairs: uniform, uneven (with a short interval), a wide range."""
    uniform = [float(i) for i in range(13)]
    uneven = sorted(rng.uniform(0.0, 5.0) for _ in range(12))
    uneven = [0.0] + uneven + [5.0]
    # One interval 1/50 of its neighbours.
    uneven[7] = uneven[6] + 0.02 * (uneven[8] - uneven[6])
    scaled = [1e3 * (1.0 + 0.4 * i + 0.05 * math.sin(3.1 * i)) for i in range(11)]
    return [("uniform13", uniform), ("uneven14", uneven), ("scaled11", scaled)]


def values(rng, x, dim):
    out = []
    for i, v in enumerate(x):
        s = (v - x[0]) / (x[-1] - x[0])
        row = [math.sin(4.0 * s + c) + 0.3 * rng.uniform(-1, 1) for c in range(dim)]
        out.append(row)
    return np.array(out, dtype=float)


def derivative_splits(k, rng, dim):
    """End condition pairs with k - 1 derivative conditions in all: every split between the
    ends, orders 1.. at each end (and one split with the highest orders), values random or
    zero."""
    total = k - 1
    pairs = []
    for nl in range(total + 1):
        nr = total - nl
        for high in (False, True) if dim == 1 else (False,):
            if high and (nl == 0 and nr == 0):
                continue

            def orders(m):
                return list(range(k - m, k)) if high else list(range(1, m + 1))

            def spec(m):
                if m == 0:
                    return None
                return [(o, [round(rng.uniform(-2, 2), 3) for _ in range(dim)]) for o in orders(m)]

            pairs.append((f"split{nl}{nr}{'h' if high else ''}", (spec(nl), spec(nr))))
    return pairs


def as_bc(pair):
    def one(end):
        if end is None or isinstance(end, str):
            return end
        return [(o, np.array(v)) for o, v in end]

    return (one(pair[0]), one(pair[1]))


def as_json_end(end):
    if end is None:
        return "not-a-knot"
    if isinstance(end, str):
        return end
    return [[o, v] for o, v in end]


def exact_coefficients(x, y, k, t, ends, rational=False):
    """The exact solution of the interpolation system of an open spline (x, y, t and the
    end values read exactly from their floats), rounded to f64: the reference that says
    how far SciPy's own coefficients are from the true ones (systems with all conditions at
    one end are ill-conditioned)."""
    t = [Fraction(v) for v in t]
    nt = len(t) - k - 1

    @functools.lru_cache(maxsize=None)
    def basis(j, p, u, nu):
        if nu == 0 and p == 0:
            if t[j] <= u < t[j + 1]:
                return Fraction(1)
            # The last non-empty interval is closed at the right end of the base interval.
            last = max(i for i in range(nt) if t[i] < t[i + 1])
            return Fraction(1) if (j == last and u == t[j + 1]) else Fraction(0)
        out = Fraction(0)
        if nu == 0:
            if t[j + p] != t[j]:
                out += (u - t[j]) / (t[j + p] - t[j]) * basis(j, p - 1, u, 0)
            if t[j + p + 1] != t[j + 1]:
                out += (t[j + p + 1] - u) / (t[j + p + 1] - t[j + 1]) * basis(j + 1, p - 1, u, 0)
            return out
        if t[j + p] != t[j]:
            out += Fraction(p) / (t[j + p] - t[j]) * basis(j, p - 1, u, nu - 1)
        if t[j + p + 1] != t[j + 1]:
            out -= Fraction(p) / (t[j + p + 1] - t[j + 1]) * basis(j + 1, p - 1, u, nu - 1)
        return out

    dim = len(y[0])
    xs = [Fraction(v) for v in x]

    def conds(end):
        if end == "not-a-knot":
            return []
        if end == "natural":
            return [(2, [0.0] * dim)]
        if end == "clamped":
            return [(1, [0.0] * dim)]
        return [(o, v if len(v) == dim else v * dim) for o, v in end]

    rows = []
    for o, v in conds(ends[0]):
        rows.append([basis(j, k, xs[0], o) for j in range(nt)] + [Fraction(a) for a in v])
    for i, xi in enumerate(xs):
        rows.append([basis(j, k, xi, 0) for j in range(nt)] + [Fraction(a) for a in y[i]])
    for o, v in conds(ends[1]):
        rows.append([basis(j, k, xs[-1], o) for j in range(nt)] + [Fraction(a) for a in v])
    n = nt
    for col in range(n):
        piv = next(r for r in range(col, n) if rows[r][col] != 0)
        rows[col], rows[piv] = rows[piv], rows[col]
        for r in range(n):
            if r != col and rows[r][col] != 0:
                f = rows[r][col] / rows[col][col]
                rows[r] = [a - f * b for a, b in zip(rows[r], rows[col])]
    exact = [[rows[i][n + d] / rows[i][i] for d in range(dim)] for i in range(n)]
    if rational:
        return exact
    return np.array([[float(v) for v in r] for r in exact])


def eval_points(x):
    """Points between the data (never at a knot), both ends, and 10% beyond each end."""
    x0, x1 = x[0], x[-1]
    inner = [x0 + (x1 - x0) * (j + 0.377) / 12.0 for j in range(12)]
    return [x0] + inner + [x1, x0 - 0.1 * (x1 - x0), x1 + 0.1 * (x1 - x0)]


def cases():
    """(data sets, cases): a case names its data set and dimension; periodic cases end
    with the first point again (y[-1] = y[0])."""
    rng = random.Random(SEED)
    sets = {}
    out = []
    for set_name, x in data_sets(rng):
        ts = eval_points(x)
        sets[set_name] = {"x": [float(v) for v in x], "eval_t": ts, "deriv_t": ts[1:-3:2]}
        for dim in (1, 3) if set_name != "scaled11" else (1,):
            y = values(rng, x, dim)
            sets[set_name][f"y{dim}"] = rows(y)
            for k in range(1, 8):
                bcs = [("not-a-knot", None)]
                if k == 3:
                    bcs += [("natural", "natural"), ("clamped", "clamped"),
                            ("clamped-natural", ("clamped", "natural"))]
                if k == 2:
                    bcs += [("clamped-none", ("clamped", None)), ("none-natural", (None, "natural"))]
                if k >= 2:
                    bcs += [(n, p) for n, p in derivative_splits(k, rng, dim)]
                bcs.append(("periodic", "periodic"))
                for bc_name, bc in bcs:
                    yy = y.copy()
                    if bc == "periodic":
                        yy[-1] = yy[0]
                    if isinstance(bc, tuple):
                        scipy_bc = as_bc(bc)
                        ends = [as_json_end(bc[0]), as_json_end(bc[1])]
                    else:
                        scipy_bc = bc
                        ends = "periodic" if bc == "periodic" else [as_json_end(bc)] * 2
                    spl = make_interp_spline(np.array(x), yy if dim > 1 else yy[:, 0], k=k,
                                             bc_type=scipy_bc)
                    # Outside, periodic splines wrap: values there only for open ones.
                    at = ts if spl.extrapolate != "periodic" else ts[:-2]
                    inner = sets[set_name]["deriv_t"]
                    # SciPy's own error: its coefficients against the exact solution,
                    # relative to their largest (open ends; periodic systems are well
                    # conditioned, and k = 1 copies y).
                    err, exact = 0.0, None
                    if bc != "periodic" and k > 1:
                        exact = exact_coefficients(x, yy, k, spl.t, ends)
                        c = np.asarray(spl.c, dtype=float).reshape(exact.shape)
                        err = float(np.abs(c - exact).max() / np.abs(exact).max())
                    extra = {"scipy_error": err, "c_exact": rows(exact)} if err > 1e-13 else {}
                    out.append({
                        "name": f"{set_name}/d{dim}/k{k}/{bc_name}",
                        **extra,
                        "set": set_name,
                        "k": k,
                        "dim": dim,
                        "ends": ends,
                        "t": [float(v) for v in spl.t],
                        "c": rows(spl.c),
                        "eval": rows(spl(np.array(at))),
                        "deriv_orders": orders(k),
                        "derivs": [rows(spl(np.array(inner), nu=nu)) for nu in orders(k)],
                    })
    # The fewest points: k + 1 for not-a-knot, and periodic curves through 2 distinct
    # points (3 with the closing one).
    few = [0.0, 0.7, 1.5, 2.0, 3.2, 4.1, 4.5, 5.9, 6.3]
    ts = [few[0] + (few[7] - few[0]) * (j + 0.31) / 12.0 for j in range(12)]
    sets["fewest"] = {"x": few, "y2": rows([[math.cos(v), math.sin(2 * v)] for v in few])}
    closed = [0.0, 1.0, 2.5]
    sets["closed3"] = {"x": closed, "y2": [[1.0, 0.0], [-1.0, 0.5], [1.0, 0.0]]}
    for k in range(2, 8):
        x = few[: k + 1]
        y = np.array(sets["fewest"]["y2"][: k + 1])
        spl = make_interp_spline(np.array(x), y, k=k)
        out.append(few_case(f"fewest/k{k}/not-a-knot", "fewest", k, [["not-a-knot"] * 2][0], spl,
                            [v for v in ts if v <= x[-1]], k + 1))
    for k in range(1, 8):
        y = np.array(sets["closed3"]["y2"])
        spl = make_interp_spline(np.array(closed), y, k=k, bc_type="periodic")
        out.append(few_case(f"closed3/k{k}/periodic", "closed3", k, "periodic", spl,
                            [2.5 * (j + 0.31) / 12.0 for j in range(12)], 3))
    return sets, out


def orders(k):
    """The derivative orders compared: 1, 2 and k (the highest, piecewise constant)."""
    return sorted({1, min(2, k), k})


def few_case(name, set_name, k, ends, spl, ts, npts):
    """A case on the first `npts` points of a set."""
    return {
        "name": name, "set": set_name, "k": k, "dim": 2, "ends": ends, "npts": npts,
        "t": [float(v) for v in spl.t], "c": rows(spl.c), "at": ts,
        "eval": rows(spl(np.array(ts))), "deriv_orders": orders(k),
        "derivs": [rows(spl(np.array(ts), nu=nu)) for nu in orders(k)],
    }


def surface_cases():
    """RectBivariateSpline(x, y, z, kx, ky, s=0): FITPACK's knots and coefficients, values at
    scattered points, on an uneven grid."""
    from scipy.interpolate import RectBivariateSpline
    rng = random.Random(SEED + 7)
    x = sorted(rng.uniform(0.0, 4.0) for _ in range(7))
    x = [0.0] + x + [4.0]
    y = sorted(rng.uniform(-1.0, 1.0) for _ in range(6))
    y = [-1.0] + y + [1.0]
    z = [[math.sin(1.3 * a) * math.cos(2.0 * b) + 0.2 * rng.uniform(-1, 1) for b in y] for a in x]
    pts = [(rng.uniform(0.0, 4.0), rng.uniform(-1.0, 1.0)) for _ in range(12)]
    out = []
    for kx, ky in [(1, 1), (2, 3), (3, 3), (4, 2), (5, 5), (3, 1), (5, 4)]:
        spl = RectBivariateSpline(np.array(x), np.array(y), np.array(z), kx=kx, ky=ky, s=0)
        tx, ty = spl.get_knots()
        # The exact coefficients (both directions solved in rationals, rounded once):
        # FITPACK's are 1e-10 off for degree 5.
        c1 = exact_coefficients(x, z, kx, tx, ["not-a-knot"] * 2, rational=True)
        c1t = [list(col) for col in zip(*c1)]
        exact = np.array(exact_coefficients(y, c1t, ky, ty, ["not-a-knot"] * 2)).T
        err = float(np.abs(spl.get_coeffs().reshape(exact.shape) - exact).max()
                    / np.abs(np.array(z)).max())
        out.append({
            "c_exact": [float(v) for v in exact.ravel()],
            "scipy_error": err,
            "kx": kx, "ky": ky,
            "tx": [float(v) for v in tx], "ty": [float(v) for v in ty],
            "c": [float(v) for v in spl.get_coeffs()],
            "at": [list(p) for p in pts],
            "values": [float(spl.ev(a, b)) for a, b in pts],
            # Partial derivatives (FITPACK allows dx < kx, dy < ky) at the points, and on
            # the 5 x 4 grid of linspaces of the domain (spl(gx, gy, dx, dy, grid=True)).
            "partials": [
                {"dx": dx, "dy": dy,
                 "values": [float(spl.ev(a, b, dx=dx, dy=dy)) for a, b in pts],
                 "grid": [float(v) for v in spl(np.linspace(0.0, 4.0, 5),
                                                np.linspace(-1.0, 1.0, 4),
                                                dx=dx, dy=dy).ravel()]}
                for dx, dy in sorted({(1, 0), (0, 1), (1, 1), (kx - 1, ky - 1)})
                if dx < kx and dy < ky and (dx, dy) != (0, 0)
            ],
        })
    return {"x": x, "y": y, "z": z, "cases": out}


def main():
    data = {
        "about": "SciPy's make_interp_spline(x, y, k, bc_type) for k = 1..7: knots t, "
                 "coefficients c, values and derivatives. Generated by "
                 "bench/make_reference_spline.py.",
        "versions": {"python": sys.version.split()[0], "numpy": np.__version__,
                     "scipy": scipy.__version__},
    }
    data["sets"], data["cases"] = cases()
    data["surfaces"] = surface_cases()
    OUT.write_text(json.dumps(data, separators=(",", ":")) + "\n")
    print(f"wrote {OUT} ({len(data['cases'])} cases, {OUT.stat().st_size // 1024} KiB)")


if __name__ == "__main__":
    main()
