"""The point calculus of the Python package (spec/point-calculus.md, issue 23 method 4):
PointModel, point_curve / PointCurve, point_surface / PointSurface and their model files.

The references are independent of geomkit: the spec's worked examples typed in as exact
fractions (equations (1)-(3), the geomatrix (9) and its caution), Lagrange interpolation
written out in Python with `fractions.Fraction`, the printed formulas run by Python and by
SymPy, a dense NumPy grid search for the optimum, and files written by the CLI.
"""

import doctest
import json
import pickle
import subprocess
from fractions import Fraction as F
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import sympy
from hypothesis import given
from hypothesis import strategies as st

import geomkit
from geomkit import _geomkit, _pointcalc

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "geomkit"


def lagrange(nodes, j, t):
    """The cardinal function L_j(t) of `nodes`, exactly (Fractions in, Fraction out)."""
    out = F(1)
    for k, x in enumerate(nodes):
        if k != j:
            out *= (t - x) / (nodes[j] - x)
    return out


def _cli(*args, cwd):
    if not CLI.is_file():
        pytest.fail(f"{CLI} is missing: build it with cargo build --release -p geomkit-cli")
    return subprocess.run([str(CLI), *map(str, args)], cwd=cwd, check=True,
                          capture_output=True, text=True).stdout


# --- the spec's worked examples ------------------------------------------------------------

# Equations (1)-(3) of the spec as printed (t̄ = 1 - t): the shares of A, C, B.
PAPER = {
    "half": (F(1, 2), lambda t: [(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)]),
    "third": (F(1, 3), lambda t: [(1 - t) * (1 - 3 * t), F(9, 2) * t * (1 - t),
                                  F(1, 2) * t * (3 * t - 1)]),
    "two-thirds": (F(2, 3), lambda t: [F(1, 2) * (1 - t) * (2 - 3 * t), F(9, 2) * t * (1 - t),
                                       t * (3 * t - 2)]),
}


@pytest.mark.parametrize("name", sorted(PAPER))
def test_equations_1_to_3_of_the_spec(name):
    t_c, shares = PAPER[name]
    a, c, b = np.array([0.0, 0.0]), np.array([1.0, 3.0]), np.array([4.0, -1.0])
    curve = geomkit.point_curve([a, c, b], nodes=name)
    assert curve.exact_nodes == (F(0), t_c, F(1))
    for t in [F(0), F(1, 8), F(1, 4), t_c, F(1, 2), F(3, 4), F(1), F(-1, 2), F(3, 2)]:
        want = shares(t)
        assert sum(want) == 1
        got = curve.shares(float(t))
        np.testing.assert_allclose(got, [float(w) for w in want], rtol=0, atol=1e-15)
        point = [float(sum(w * F(p[d]) for w, p in zip(want, (a, c, b)))) for d in range(2)]
        np.testing.assert_allclose(curve(float(t)), point, rtol=0, atol=1e-14)
    # Through A, C and B, exactly.
    assert curve(0.0).tolist() == a.tolist()
    assert curve(float(t_c)).tolist() == c.tolist()
    assert curve(1.0).tolist() == b.tolist()
    # The module's own example: equation (1) at t = 1/4 is 4 · 1/4 · 3/4.
    assert geomkit.point_curve([0.0, 1.0, 0.0], nodes="half")(0.25).tolist() == [0.75]


def printed_geomatrix(u, v):
    """The geomatrix (9) of the spec exactly as printed: a[i][j] for i, j = 1..3."""
    ub, vb = 1 - u, 1 - v
    return [
        [ub * (1 - 3 * u) * vb * (1 - 3 * v), F(9, 2) * u * ub * vb * (1 - 2 * v),
         F(1, 2) * u * (3 * u - 1) * F(1, 2) * vb * (2 - 3 * v)],
        [ub * (1 - 2 * u) * F(9, 2) * v * vb, 4 * u * ub * 4 * v * vb,
         u * (2 * u - 1) * F(9, 2) * v * vb],
        [F(1, 2) * ub * (2 - 3 * u) * F(1, 2) * v * (3 * v - 1), F(9, 2) * u * ub * v * (2 * v - 1),
         u * (3 * u - 2) * v * (3 * v - 2)],
    ]


def test_printed_geomatrix_9_and_the_specs_caution():
    net = np.arange(9.0).reshape(3, 3) ** 2 - 7.0
    printed = geomkit.point_surface(net, printed=True)
    for u, v in [(F(1, 2), F(1, 2)), (F(1, 5), F(2, 7)), (F(3, 4), F(1, 8)), (F(0), F(1))]:
        a = printed_geomatrix(u, v)
        got = printed.shares(float(u), float(v))
        for i in range(3):
            np.testing.assert_allclose(got[i], [float(x) for x in a[i]], rtol=0, atol=1e-15)
        want = float(sum(a[i][j] * F(net[i, j]) for i in range(3) for j in range(3)))
        np.testing.assert_allclose(printed(float(u), float(v)), [want], rtol=1e-15)
    # "sum a_ij(u, v) != 1 (1.156 at u = v = 1/2), and a_11(1/2, 1/2) = 1/16".
    half = printed_geomatrix(F(1, 2), F(1, 2))
    assert sum(map(sum, half)) == F(37, 32)  # 1.15625
    assert half[0][0] == F(1, 16)
    ones = geomkit.point_surface(np.ones((3, 3)), printed=True)
    assert ones(0.5, 0.5).tolist() == [1.15625]
    # Rows first, then across (each row with its own nodes) keeps both: the shares sum to 1
    # and the surface passes through the centre point.
    rows = geomkit.point_surface(np.ones((3, 3)), row_nodes=["third", "half", "two-thirds"])
    assert rows(0.5, 0.5).tolist() == [1.0]
    centre = np.zeros((3, 3))
    centre[1, 1] = 1.0
    assert geomkit.point_surface(centre, row_nodes="third;half;two-thirds")(0.5, 0.5) == 1.0
    assert geomkit.point_surface(centre, printed=True)(0.5, 0.5) == 1.0 + 0.0  # a_22 = 1
    assert abs(printed.shares(0.5, 0.5)[0][0] - 0.0625) < 1e-16  # but A_11 counts 1/16


def test_rows_then_across_against_lagrange():
    """Rows of different lengths and nodes, then across: M(u, v) = Σ_i L_i(v) M_i(u)."""
    net = [[[0.0, 1.0], [2.0, 0.5], [1.0, 1.0]],
           [[3.0, 0.0], [1.0, 2.0]],
           [[0.0, 0.0], [1.0, 1.0], [2.0, 4.0], [3.0, 9.0]]]
    row_nodes = [[F(0), F(1, 3), F(1)], [F(0), F(1)], [F(0), F(1, 4), F(1, 2), F(1)]]
    across = [F(0), F(2, 5), F(1)]
    s = geomkit.point_surface(net, row_nodes=row_nodes, across=across)
    assert not s.regular and s.dim == 2
    for u, v in [(F(1, 7), F(3, 5)), (F(1, 2), F(1, 2)), (F(9, 10), F(1, 10))]:
        want = [sum(lagrange(across, i, v) * lagrange(row_nodes[i], j, u) * F(p[d])
                    for i, row in enumerate(net) for j, p in enumerate(row)) for d in range(2)]
        np.testing.assert_allclose(s(float(u), float(v)), [float(w) for w in want], atol=1e-14)
        shares = s.shares(float(u), float(v))
        assert abs(sum(x.sum() for x in shares) - 1.0) < 1e-14
    # Through every source point, exactly.
    for i, row in enumerate(net):
        for j, p in enumerate(row):
            assert s(float(row_nodes[i][j]), float(across[i])).tolist() == p
    grid = s.grid([0.0, 0.5, 1.0], [0.25, 0.75])
    assert grid.shape == (3, 2, 2)
    np.testing.assert_array_equal(grid[1, 0], s(0.5, 0.25))


# --- k-factor models -----------------------------------------------------------------------

def _model_3d():
    """A 3-factor model of two responses over exact, float and Chebyshev levels."""
    a = [F(0), F(1, 3), F(1)]
    b = [-1.0, 0.5, 2.0, 3.0]
    c = "cheb2:3:0:2"
    levels_c = [0.0, 1.0, 2.0]
    rng = np.random.default_rng(7)
    values = rng.normal(size=(3, 4, 3, 2))
    return geomkit.PointModel.fit({"a": a, "b": b, "c": c}, values,
                                  response_names=["y", "z"]), (a, b, levels_c), values


def test_model_passes_through_every_experimental_point_exactly():
    m, (a, b, c), values = _model_3d()
    assert m.factors == ("a", "b", "c") and m.responses == ("y", "z")
    assert m.shape == (3, 4, 3)
    assert m.exact_levels["a"] == tuple(a) and m.exact_levels["b"] is None
    np.testing.assert_array_equal(m.values, values)
    cells = np.array([[float(x), y, z] for x in a for y in b for z in m.levels["c"]])
    assert np.allclose(m.levels["c"], c, atol=1e-15)
    assert np.array_equal(m.eval(cells), values.reshape(-1, 2))


def test_model_against_lagrange_and_its_shares():
    m, (a, b, c), values = _model_3d()
    levels = [a, [F(x) for x in b], [F(x) for x in m.levels["c"]]]
    for x in [(F(1, 5), F(1, 3), F(1, 2)), (F(2, 3), F(5, 2), F(7, 4)), (F(-1, 2), F(4), F(3))]:
        shares = m.shares([float(v) for v in x])
        want = np.empty(m.shape)
        for idx in np.ndindex(*m.shape):
            want[idx] = float(np.prod([lagrange(levels[f], idx[f], x[f]) for f in range(3)]))
        np.testing.assert_allclose(shares, want, rtol=1e-12, atol=1e-13)
        assert abs(shares.sum() - 1.0) < 1e-12
        point = m.eval([float(v) for v in x])
        np.testing.assert_allclose(point, np.tensordot(want, values, axes=3), rtol=1e-11,
                                   atol=1e-12)
    # The Kronecker delta at the nodes.
    for idx in [(0, 0, 0), (1, 2, 1), (2, 3, 2)]:
        x = [float(a[idx[0]]), b[idx[1]], m.levels["c"][idx[2]]]
        delta = np.zeros(m.shape)
        delta[idx] = 1.0
        assert np.array_equal(m.shares(x), delta)
    assert np.array_equal(m.shares({"c": 0.0, "a": 0.0, "b": -1.0}), np.eye(1, 36).reshape(3, 4, 3))


@given(st.lists(st.integers(2, 4), min_size=1, max_size=3), st.integers(0, 2**32 - 1))
def test_property_shares_sum_to_one_and_cells_are_exact(shape, seed):
    rng = np.random.default_rng(seed)
    levels = {f"f{i}": np.sort(rng.choice(np.arange(-20, 20) / 4, n, replace=False))
              for i, n in enumerate(shape)}
    values = rng.uniform(-5, 5, size=shape)
    m = geomkit.PointModel.fit(levels, values)
    x = rng.uniform(-6, 6, size=len(shape))
    assert abs(m.shares(x).sum() - 1.0) < 1e-9
    cells = np.array(np.meshgrid(*levels.values(), indexing="ij")).reshape(len(shape), -1).T
    assert np.array_equal(m.eval(cells)[:, 0], values.reshape(-1))


def test_formula_run_by_python_and_by_sympy_equals_eval():
    m, _, _ = _model_3d()
    rng = np.random.default_rng(3)
    x = rng.uniform(-0.5, 2.5, size=(50, 3))
    want = m.eval(x)
    scope = {}
    exec(m.formula("numpy"), scope)  # noqa: S102 - the printed program, by design
    for j, name in enumerate(m.responses):
        got = scope[name](x[:, 0], x[:, 1], x[:, 2])
        np.testing.assert_allclose(got, want[:, j], rtol=1e-10, atol=1e-10)
    # SymPy: the exact levels stay exact (Rational(1, 3)); evaluated with exact arguments.
    text = m.formula("sympy")
    assert "Rational(1, 3)" in text
    ns = {}
    exec(text, ns)  # noqa: S102
    a, b, c = sympy.symbols("a b c")
    for row, w in zip(x[:5], want[:5]):
        subs = {a: sympy.Rational(F(row[0])), b: sympy.Rational(F(row[1])),
                c: sympy.Rational(F(row[2]))}
        for j, name in enumerate(m.responses):
            assert abs(float(ns[name].subs(subs)) - w[j]) < 1e-10
    # Every printer of the CLI answers.
    for fmt in _pointcalc._FORMATS:
        assert "y" in m.formula(fmt) or "f_{y}" in m.formula(fmt)
    with pytest.raises(ValueError, match="unknown formula format"):
        m.formula("cobol")


def test_curve_and_surface_formulas_equal_eval():
    c = geomkit.point_curve([[0.0, 1.0, 2.0], [1.0, 2.0, 0.0], [3.0, 0.0, 1.0], [2.0, 2.0, 2.0]])
    assert c.exact_nodes == (F(0), F(1, 3), F(2, 3), F(1))
    ns = {}
    exec(c.formula("numpy"), ns)  # noqa: S102
    t = np.linspace(-0.5, 1.5, 41)
    got = np.stack([ns[k](t) for k in ("x", "y", "z")], axis=1)
    np.testing.assert_allclose(got, c(t), atol=1e-12)
    s = geomkit.point_surface([[[0.0], [1.0], [0.0]], [[2.0], [1.0]], [[0.5], [0.0], [3.0]]],
                              row_nodes=["third", "0,1", "two-thirds"])
    ns = {}
    exec(s.formula("numpy"), ns)  # noqa: S102
    u, v = np.meshgrid(np.linspace(0, 1, 7), np.linspace(0, 1, 5))
    np.testing.assert_allclose(ns["x"](u, v), s(u, v)[..., 0], atol=1e-12)
    with pytest.raises(ValueError, match="printed"):
        geomkit.point_surface(np.eye(3), printed=True).formula()


def test_optimum_against_a_dense_grid_search():
    a, b = np.linspace(0.0, 2.0, 4), np.array([-1.0, 0.0, 1.5])
    aa, bb = np.meshgrid(a, b, indexing="ij")
    values = np.sin(3 * aa) * np.cos(2 * bb) + 0.3 * aa
    m = geomkit.PointModel.fit({"a": a, "b": b}, values)
    ga, gb = np.meshgrid(np.linspace(0, 2, 801), np.linspace(-1, 1.5, 801), indexing="ij")
    dense = m.eval(np.stack([ga.ravel(), gb.ravel()], axis=1))[:, 0]
    for maximize, best in ((True, dense.max()), (False, dense.min())):
        opt = m.optimize(maximize)
        assert opt.certified and opt.factors == ("a", "b")
        assert 0.0 <= opt.location[0] <= 2.0 and -1.0 <= opt.location[1] <= 1.5
        assert m.eval(opt.location)[0] == opt.value
        assert opt.at == {"a": opt.location[0], "b": opt.location[1]}
        scale = np.ptp(values)
        if maximize:
            assert opt.bound >= opt.value >= best - 1e-12 * scale
            assert best <= opt.bound + 1e-12 * scale
        else:
            assert opt.bound <= opt.value <= best + 1e-12 * scale
            assert best >= opt.bound - 1e-12 * scale
        assert opt.gap == abs(opt.bound - opt.value) <= 1e-9 * scale
    two = geomkit.PointModel.fit({"a": a}, np.stack([a, -a], axis=1), response_names=["p", "q"])
    with pytest.raises(ValueError, match="2 responses"):
        two.optimize()
    assert two.optimize(response="q", maximize=True).value == 0.0
    assert two.optimize(response="p", maximize=True).value == 2.0
    with pytest.raises(ValueError, match="tolerance"):
        m.optimize(tolerance=-1.0)


def test_dataframe_and_array_paths_give_identical_bits():
    rng = np.random.default_rng(5)
    a, b = [0.1, 0.7, 1.3], [2.0, 3.0, 5.0, 8.0]
    rows = [(x, y) for y in b for x in a]
    rng.shuffle(rows)
    x = np.array(rows)
    y = np.stack([np.exp(x[:, 0]) * x[:, 1], x[:, 0] - x[:, 1] ** 2], axis=1)
    df = pd.DataFrame({"note": ["e"] * len(x), "b": x[:, 1], "a": x[:, 0],
                       "yield": y[:, 0], "cost": y[:, 1]})
    from_df = geomkit.PointModel.from_dataframe(df, factors=["a", "b"], response=["yield", "cost"])
    from_arrays = geomkit.PointModel.from_records(x, y, factor_names=["a", "b"],
                                                  response_names=["yield", "cost"])
    grid = geomkit.PointModel.fit({"a": a, "b": b},
                                  np.stack([np.exp(np.array(a))[:, None] * np.array(b),
                                            np.subtract.outer(a, np.square(b))], axis=2),
                                  response_names=["yield", "cost"])
    assert from_df.to_json() == from_arrays.to_json() == grid.to_json()
    at = pd.DataFrame({"b": rng.uniform(2, 8, 100), "a": rng.uniform(0, 1.5, 100)})
    by_df = from_df.eval(at)
    by_array = from_arrays.eval(at[["a", "b"]].to_numpy())
    assert by_df.shape == (100, 2) and np.array_equal(by_df, by_array)
    assert np.array_equal(from_df.eval({"a": at["a"], "b": at["b"]}), by_df)
    with pytest.raises(ValueError, match="no column 'c'"):
        geomkit.PointModel.from_dataframe(df, factors=["a", "c"], response="yield")
    with pytest.raises(ValueError, match="no column 'a'"):
        from_df.eval(at.rename(columns={"a": "x"}))
    with pytest.raises(ValueError, match="named twice"):
        geomkit.PointModel.from_dataframe(df, factors=["a", "b"], response=["a"])
    with pytest.raises(TypeError):
        geomkit.PointModel.from_dataframe(df, factors=["a", "note"], response=["yield"])
    with pytest.raises(TypeError, match="DataFrame"):
        geomkit.PointModel.from_dataframe(x, factors=["a"], response=["y"])


def test_one_factor_models_take_a_vector_of_points():
    m = geomkit.PointModel.fit({"t": [F(0), F(1, 3), F(1)]}, [1.0, 4.0, 0.0])
    t = np.array([0.0, 0.25, F(1, 3), 0.5])
    want = [float(sum(lagrange([F(0), F(1, 3), F(1)], j, F(x)) * y
                      for j, y in enumerate([1, 4, 0]))) for x in t]
    np.testing.assert_allclose(m.eval(t.astype(float))[:, 0], want, rtol=1e-15)
    assert m.eval(t.astype(float)).shape == (4, 1)
    assert m.eval(1 / 3).tolist() == [4.0]
    assert m(np.array([[0.0], [1.0]])).tolist() == [[1.0], [0.0]]


def test_exact_nodes_match_data_levels_as_the_cli():
    x = np.array([[0.0], [0.3333333333333], [1.0]])
    m = geomkit.PointModel.from_records(x, [1.0, 2.0, 0.0], factor_names=["t"],
                                        nodes={"t": "0,1/3,1"})
    assert m.exact_levels["t"] == (F(0), F(1, 3), F(1))
    with pytest.raises(ValueError, match="not one of the nodes"):
        geomkit.PointModel.from_records(x, [1.0, 2.0, 0.0], factor_names=["t"],
                                        nodes={"t": "0,1/2,1"})
    with pytest.raises(ValueError, match="not one of the factors"):
        geomkit.PointModel.from_records(x, [1.0, 2.0, 0.0], factor_names=["t"],
                                        nodes={"s": "half"})


# --- model files, pickling, the CLI --------------------------------------------------------

def test_round_trip_with_files_the_cli_writes(tmp_path):
    a, b = [0.0, 0.25, 1.0], [1.0, 2.0]
    rows = ["b,a,y,w"] + [f"{y},{x},{x * x - y / 3},{x + y}" for x in a for y in b]
    (tmp_path / "data.csv").write_text("\n".join(rows) + "\n")
    _cli("pointcalc", "fit", "data.csv", "--factors", "a,b", "--response", "y,w",
         "--nodes", "a=0,1/4,1", "-o", "m.json", cwd=tmp_path)
    loaded = geomkit.load(tmp_path / "m.json")
    assert isinstance(loaded, geomkit.PointModel)
    ours = geomkit.PointModel.fit(
        {"a": [F(0), F(1, 4), F(1)], "b": b},
        np.array([[[x * x - y / 3, x + y] for y in b] for x in a]), response_names=["y", "w"])
    assert json.loads(loaded.to_json()) == json.loads(ours.to_json())
    assert json.loads(ours.to_json()) == json.loads((tmp_path / "m.json").read_text())
    # The CLI's eval of our saved model: the same numbers, bit for bit.
    ours.save(tmp_path / "ours.json")
    at = np.array([[0.1, 1.5], [0.9, 0.2], [1.7, 3.0]])
    (tmp_path / "at.csv").write_text("a,b\n" + "\n".join(f"{p!r},{q!r}" for p, q in at.tolist()))
    out = _cli("pointcalc", "eval", "ours.json", "at.csv", cwd=tmp_path).split()
    assert out[0] == "a,b,y,w"
    cli = np.array([[float(v) for v in line.split(",")][2:] for line in out[1:]])
    assert np.array_equal(cli, ours.eval(at))
    # The CLI's shares and formulas of our saved model: the same numbers and text.
    cli_shares = json.loads(_cli("pointcalc", "shares", "ours.json", "--at", "b=1.25,a=0.5",
                                 cwd=tmp_path))["shares"]
    assert [s["share"] for s in cli_shares] == ours.shares({"a": 0.5, "b": 1.25}).ravel().tolist()
    assert cli_shares[1]["point"] == {"a": 0.0, "b": 2.0}
    for fmt in ("numpy", "sympy", "latex", "c"):
        assert _cli("pointcalc", "formula", "ours.json", "--format", fmt, cwd=tmp_path) == \
            ours.formula(fmt)
    # The optimum of the CLI and ours.
    single = geomkit.PointModel.fit({"a": [F(0), F(1, 4), F(1)], "b": b},
                                    np.array([[x * x - y / 3 for y in b] for x in a]))
    single.save(tmp_path / "single.json")
    cli_opt = json.loads(_cli("pointcalc", "optimize", "single.json", "--max", cwd=tmp_path))
    opt = single.optimize()
    assert (cli_opt["value"], cli_opt["bound"]) == (opt.value, opt.bound)


def test_curve_and_surface_sample_files_are_the_clis(tmp_path):
    points = [[0.0, 0.0], [1.0, 2.0], [3.0, 1.0], [4.0, 4.0]]
    (tmp_path / "p.json").write_text(json.dumps(points))
    _cli("pointcalc", "curve", "p.json", "--nodes", "cheb2:4", "--samples", "33", "-o", "c.json",
         cwd=tmp_path)
    theirs = geomkit.load(tmp_path / "c.json")
    curve = geomkit.point_curve(points, nodes="cheb2:4", samples=33)
    assert _cli("pointcalc", "formula", "p.json", "--nodes", "cheb2:4", "--format", "maple",
                cwd=tmp_path) == curve.formula("maple")
    assert isinstance(theirs, geomkit.PointCurveSamples)
    assert json.loads(curve.to_json()) == json.loads(theirs.to_json())
    np.testing.assert_array_equal(theirs.points, curve(theirs.t))
    assert theirs.lebesgue_constant == curve.lebesgue_constant
    net = [[[0.0, 0.0, 1.0], [1.0, 0.0, 2.0], [2.0, 0.0, 0.0]],
           [[0.0, 1.0, 0.0], [2.0, 1.0, 1.0]],
           [[0.0, 2.0, 1.0], [1.0, 2.0, 3.0], [2.0, 2.0, 2.0]]]
    (tmp_path / "n.json").write_text(json.dumps({"net": net}))
    _cli("pointcalc", "surface", "n.json", "--row-nodes", "third;0,1;two-thirds",
         "--samples", "9", "-o", "s.json", cwd=tmp_path)
    theirs = geomkit.load(tmp_path / "s.json")
    surface = geomkit.point_surface(net, row_nodes=["third", [0, 1], "two-thirds"], samples=9)
    assert isinstance(theirs, geomkit.PointSurfaceSamples)
    assert json.loads(surface.to_json()) == json.loads(theirs.to_json())
    np.testing.assert_array_equal(theirs.points, surface.grid(theirs.u, theirs.v))
    surface.save(tmp_path / "ours.json")
    assert geomkit.load(tmp_path / "ours.json").describe() == \
        "point-equation surface in R^3, 9×9 samples"


def test_pickling_and_repr():
    m, _, _ = _model_3d()
    x = np.random.default_rng(1).uniform(0, 2, size=(20, 3))
    for obj in (m, geomkit.loads(m.to_json())):
        back = pickle.loads(pickle.dumps(obj))
        assert isinstance(back, geomkit.PointModel)
        assert np.array_equal(back.eval(x), m.eval(x))
        assert back.exact_levels == m.exact_levels
    assert repr(m) == "<geomkit.PointModel of y, z over a: 3, b: 4, c: 3 levels>"
    c = geomkit.point_curve([[0.0, 1.0], [2.0, 3.0], [1.0, 1.0]], nodes="two-thirds", samples=11)
    back = pickle.loads(pickle.dumps(c))
    t = np.linspace(-1, 2, 31)
    assert np.array_equal(back(t), c(t)) and back.exact_nodes == (F(0), F(2, 3), F(1))
    assert back.to_json() == c.to_json()
    assert repr(c) == "<geomkit.PointCurve in R^2 through 3 points, nodes [0.0, " \
        "0.6666666666666666, 1.0]>"
    for s in (geomkit.point_surface(np.eye(3), printed=True),
              geomkit.point_surface([[1.0, 2.0], [3.0, 4.0, 5.0]], across="cheb1:2")):
        back = pickle.loads(pickle.dumps(s))
        assert np.array_equal(back.grid(t, t), s.grid(t, t)) and back.printed == s.printed
        assert "geomkit.PointSurface in R^1" in repr(s)
    samples = geomkit.loads(c.to_json())
    assert pickle.loads(pickle.dumps(samples)).to_json() == samples.to_json()
    assert repr(samples) == "<geomkit.PointCurveSamples: point-equation curve in R^2, 11 samples>"


# --- bad input -----------------------------------------------------------------------------

def test_bad_input_is_a_clear_error():
    fit = geomkit.PointModel.fit
    with pytest.raises(ValueError, match="not a finite number"):
        fit({"a": [0.0, 1.0]}, [1.0, np.nan])
    with pytest.raises(ValueError, match="grid of shape"):  # ragged: levels and grid differ
        fit({"a": [0.0, 1.0], "b": [0.0, 1.0, 2.0]}, np.ones((2, 2)))
    with pytest.raises(ValueError):  # duplicate levels
        fit({"a": [0.0, 1.0, 1.0]}, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError):
        fit({"a": [0.0, np.inf]}, [1.0, 2.0])
    with pytest.raises(ValueError, match="no factors"):
        fit({}, [1.0])
    with pytest.raises(TypeError):
        fit({"a": [0.0, 1.0]}, ["x", "y"])
    with pytest.raises(ValueError, match="2 response names"):
        fit({"a": [0.0, 1.0]}, [1.0, 2.0], response_names=["p", "q"])
    with pytest.raises(ValueError, match="named twice"):
        fit({"a": [0.0, 1.0]}, [[1.0, 2.0], [3.0, 4.0]], response_names=["p", "p"])
    with pytest.raises(ValueError):  # more than 5000 levels
        fit({"a": "cheb1:5001"}, np.ones(5001))
    with pytest.raises(ValueError, match="unknown node preset"):
        fit({"a": "cheb9:3"}, np.ones(3))
    records = geomkit.PointModel.from_records
    with pytest.raises(ValueError, match="duplicate cell"):
        records([[0, 0], [0, 1], [1, 0], [0, 1]], [1.0, 2, 3, 4])
    with pytest.raises(ValueError, match="missing|no experiment|cell"):
        records([[0, 0], [0, 1], [1, 0]], [1.0, 2, 3])
    with pytest.raises(ValueError, match="not a finite number"):
        records([[0, 0], [1, 1]], [1.0, np.nan])
    with pytest.raises(ValueError):
        records([[0, 0], [1, 1]], [1.0, 2.0, 3.0])
    m = fit({"a": [0.0, 1.0], "b": [0.0, 1.0]}, np.ones((2, 2)))
    with pytest.raises(ValueError, match="expected \\(n, 2\\)"):
        m.eval(np.ones((3, 3)))
    with pytest.raises(ValueError, match="not a finite number"):
        m.eval([[0.0, np.nan]])
    with pytest.raises(ValueError):
        m.eval(np.ones(()))
    with pytest.raises(TypeError):
        m.eval([["a", "b"]])
    with pytest.raises(ValueError, match="beyond|rounding"):
        m.eval([[1e300, 1e300]])
    assert m.eval(np.ones((0, 2))).shape == (0, 1)
    # Non-contiguous and other dtypes are converted.
    xs = np.arange(12.0).reshape(3, 4)[:, ::2]
    assert np.array_equal(m.eval(xs), m.eval(np.ascontiguousarray(xs)))
    assert np.array_equal(m.eval(np.array([[0, 1]], dtype=np.int32)), [[1.0]])
    with pytest.raises(ValueError, match="expected \\(2,\\)"):
        m.shares([0.5])
    with pytest.raises(ValueError):
        geomkit.point_curve([[0.0], [np.nan]])
    with pytest.raises(ValueError):
        geomkit.point_curve([[0.0], [1.0]], nodes="half")
    with pytest.raises(ValueError, match="no points"):
        geomkit.point_curve(np.empty((0, 2)))
    with pytest.raises(ValueError, match="not finite|finite"):
        geomkit.point_curve([0.0, 1.0])(np.nan)
    with pytest.raises(ValueError):
        geomkit.point_surface(np.ones((2, 2)), printed=True)
    with pytest.raises(ValueError, match="not both"):
        geomkit.point_surface(np.ones((2, 2)), nodes="0,1", row_nodes=["0,1", "0,1"])
    with pytest.raises(ValueError, match="samples"):
        geomkit.point_curve([0.0, 1.0], samples=1)


def test_strict_lebesgue_and_warnings():
    levels = np.linspace(0, 1, 40)
    m = geomkit.PointModel.fit({"a": levels}, np.sin(levels))
    assert m.warnings and "Lebesgue constant of factor a" in m.warnings[0]
    with pytest.raises(ValueError, match="Lebesgue"):
        geomkit.PointModel.fit({"a": levels}, np.sin(levels), strict=True)
    assert not geomkit.PointModel.fit({"a": "cheb1:40"}, np.ones(40), strict=True).warnings
    c = geomkit.point_curve(np.ones(40))
    assert c.warnings and c.lebesgue_constant > 1e6


def test_compiled_module_refuses_what_it_cannot_read():
    nodes = _geomkit.PointNodes(np.array([0.0, 0.5, 1.0]))
    with pytest.raises(TypeError):
        _geomkit.PointNodes(np.array([0.0, 0.5, 1.0, 2.0])[::2])
    with pytest.raises(TypeError):
        _geomkit.PointCurve(nodes, np.ones((3, 1), dtype=np.float32))
    curve = _geomkit.PointCurve(nodes, np.ones((3, 2)))
    with pytest.raises(ValueError, match="buffer"):
        curve.eval_into(np.zeros(4), np.empty((3, 2)))
    m = _geomkit.PointcalcModel.from_grid(["a"], [nodes], ["y"], np.ones(3))
    with pytest.raises(ValueError, match="factor values"):
        m.eval_into(np.zeros((2, 2)), np.empty((2, 1)))
    with pytest.raises(ValueError, match="pointcalc-model"):
        _geomkit.PointcalcModel.from_model(curve.samples_model(5))
    # A grid of 1.25 * 10^11 numbers is refused before anything is allocated.
    big = _geomkit.PointNodes.preset("cheb1", 5000, 0.0, 1.0)
    with pytest.raises(ValueError, match="10\\^8|100000000|at most"):
        _geomkit.PointcalcModel.from_grid(["a", "b", "c"], [big] * 3, ["y"], np.ones(3))


def test_docstring_examples_run():
    result = doctest.testmod(_pointcalc, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 15 and result.failed == 0


def test_the_gil_is_released_during_evaluation():
    from test_package import _seen_inside

    rng = np.random.default_rng(2)
    m = geomkit.PointModel.fit({"a": "cheb1:30", "b": "cheb1:30", "c": "cheb1:30"},
                               rng.normal(size=(30, 30, 30)))
    x = rng.uniform(0, 1, size=(300_000, 3))
    seen = _seen_inside(lambda: m.eval(x), geomkit.PointModel.eval, "eval_into(")
    assert seen > 20, seen


def test_changing_factors_and_levels_without_a_solve():
    m, (a, b, c), values = _model_3d()
    rng = np.random.default_rng(9)
    rest = rng.uniform(-1, 3, size=(10, 2))
    # Fixing a factor: the section of the model there.
    fixed = m.fix("b", 1.25)
    assert fixed.factors == ("a", "c") and fixed.responses == ("y", "z")
    full = np.column_stack([rest[:, 0], np.full(10, 1.25), rest[:, 1]])
    np.testing.assert_allclose(fixed.eval(rest), m.eval(full), rtol=1e-12, atol=1e-12)
    # Keeping one level: its experiments.
    assert np.array_equal(m.section("a", 2).values, values[2])
    # Removing a level: the model through the other experiments, as if fitted without it.
    fewer = m.without_level("b", 1)
    refit = geomkit.PointModel.fit({"a": a, "b": [b[0], b[2], b[3]], "c": "cheb2:3:0:2"},
                                   values[:, [0, 2, 3]], response_names=["y", "z"])
    assert fewer.to_json() == refit.to_json()
    # Adding it back gives the model again.
    again = fewer.with_level("b", b[1], values[:, 1])
    x = rng.uniform(0, 2, size=(20, 3))
    np.testing.assert_allclose(again.eval(x), m.eval(x), rtol=1e-12, atol=1e-12)
    with pytest.raises(ValueError, match="not one of the factors"):
        m.fix("d", 0.0)
    with pytest.raises(ValueError, match="4 levels"):
        m.without_level("b", 4)
    with pytest.raises(ValueError, match="grid of shape"):
        fewer.with_level("b", 0.0, np.ones((3, 3)))
    with pytest.raises(ValueError):
        fewer.with_level("b", 2.0, values[:, 1])  # a level already there
    with pytest.raises(ValueError):
        geomkit.PointModel.fit({"t": [0.0, 1.0]}, [0.0, 1.0]).fix("t", 0.5)  # the only factor


@given(st.integers(1, 12), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_property_curves_pass_through_their_points_with_shares_summing_to_one(n, dim, seed):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-10, 10, size=(n, dim))
    nodes = np.sort(rng.choice(np.arange(-40, 40) / 8, n, replace=False))
    curve = geomkit.point_curve(points, nodes=nodes)
    assert np.array_equal(curve(nodes), points)
    t = rng.uniform(nodes[0] - 0.5, nodes[-1] + 0.5, size=7)
    shares = curve.shares(t)
    np.testing.assert_allclose(shares.sum(axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(curve(t), shares @ points,
                               atol=1e-9 * max(1.0, float(np.abs(shares).sum(axis=1).max()) * 10))
