"""geomkit.BezierCurve / BezierSurface (issue 23, method 1: spec/bezier-order.md).

Independent references only: the paper's worked examples (exact numbers of the spec), the
elevation formula (8) and de Casteljau written here in exact rationals (fractions.Fraction),
NumPy computations (dense sampling, Gauss–Legendre least squares), and files the CLI wrote.
"""

import json
import pickle
import subprocess
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction
from math import comb
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import geomkit
from geomkit import BezierCurve, BezierSurface, degree_change_matrix, h_matrix
from geomkit._bezier import DegreeReport, Deviation, ReductionError, SurfaceDegreeReport

ROOT = Path(__file__).resolve().parents[2]
EPS = np.finfo(float).eps

# The paper's Example 2 (spec §3): a formally quintic curve of real degree 3.
QUINTIC = [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]


def F(s):
    """'a/b' -> Fraction; a matrix of such strings -> list of lists of Fractions."""
    if isinstance(s, str):
        return Fraction(s)
    return [[F(x) for x in row] for row in s]


def elevate_exact(points, n_new):
    """Formula (8) in exact rationals: u'_j = Σ_i C(n,i) C(n'-n,j-i) / C(n',j) u_i."""
    n = len(points) - 1
    dim = len(points[0])
    out = []
    for j in range(n_new + 1):
        row = [Fraction(0)] * dim
        for i in range(max(0, j - (n_new - n)), min(n, j) + 1):
            w = Fraction(comb(n, i) * comb(n_new - n, j - i), comb(n_new, j))
            row = [r + w * Fraction(p) for r, p in zip(row, points[i])]
        out.append(row)
    return out


def de_casteljau_exact(points, t):
    """p(t) by de Casteljau in exact rationals."""
    t = Fraction(t)
    work = [[Fraction(x) for x in p] for p in points]
    while len(work) > 1:
        work = [[(1 - t) * a + t * b for a, b in zip(p, q)] for p, q in zip(work, work[1:])]
    return work[0]


def de_casteljau(points, t):
    """p(t) by de Casteljau in NumPy, for arrays of parameters: shape t.shape + (dim,)."""
    t = np.asarray(t, dtype=float)[..., None, None]
    work = np.asarray(points, dtype=float)[None] * np.ones_like(t)
    while work.shape[-2] > 1:
        work = (1 - t) * work[..., :-1, :] + t * work[..., 1:, :]
    return work[..., 0, :]


def surface_exact(net, u, v):
    """p(u, v) of a tensor-product net: de Casteljau over the rows, then along v."""
    rows = [de_casteljau_exact(row_of_columns, u)
            for row_of_columns in np.asarray(net, dtype=object).transpose(1, 0, 2).tolist()]
    return de_casteljau_exact(rows, v)


def dense_distance(a, b, count=200_001):
    """max_t |a(t) - b(t)| and the L2 distance over [0, 1], sampled densely with NumPy."""
    t = np.linspace(0.0, 1.0, count)
    d = np.linalg.norm(de_casteljau(a, t) - de_casteljau(b, t), axis=-1)
    l2 = np.sqrt(np.trapezoid(d * d, t))
    return float(d.max()), float(t[d.argmax()]), float(l2)


# --- the paper's matrices and worked examples ---------------------------------------------


def test_example_1_matrices_are_the_papers():
    assert degree_change_matrix(2, 3).tolist() == F(
        [["1", "1/3", "0", "0"], ["0", "2/3", "2/3", "0"], ["0", "0", "1/3", "1"]])
    assert degree_change_matrix(3, 4).tolist() == F(
        [["1", "1/4", "0", "0", "0"], ["0", "3/4", "1/2", "0", "0"],
         ["0", "0", "1/2", "3/4", "0"], ["0", "0", "0", "1/4", "1"]])
    assert degree_change_matrix(3, 5).tolist() == F(
        [["1", "2/5", "1/10", "0", "0", "0"], ["0", "3/5", "3/5", "3/10", "0", "0"],
         ["0", "0", "3/10", "3/5", "3/5", "0"], ["0", "0", "0", "1/10", "2/5", "1"]])
    assert h_matrix(5).tolist() == [
        [1, -5, 10, -10, 5, -1], [0, 5, -20, 30, -20, 5], [0, 0, 10, -30, 30, -10],
        [0, 0, 0, 10, -20, 10], [0, 0, 0, 0, 5, -5], [0, 0, 0, 0, 0, 1]]
    assert all(isinstance(x, Fraction) for x in degree_change_matrix(3, 5).ravel())


@pytest.mark.parametrize("n, n_new", [(0, 4), (1, 7), (4, 9), (6, 6), (10, 31)])
def test_elevation_matrix_is_the_closed_form(n, n_new):
    m = degree_change_matrix(n, n_new)
    for i in range(n + 1):
        for j in range(n_new + 1):
            expected = (Fraction(comb(n, i) * comb(n_new - n, j - i), comb(n_new, j))
                        if 0 <= j - i <= n_new - n else 0)
            assert m[i, j] == expected
    rounded = degree_change_matrix(n, n_new, exact=False)
    assert rounded.dtype == np.float64
    assert rounded.tolist() == [[float(x) for x in row] for row in m]


def test_example_2_the_quintic_of_real_degree_3():
    q = BezierCurve(QUINTIC)
    # S_5 = U_5 H_5, exactly the paper's (two zero columns).
    assert q.power_coefficients().T.tolist() == [[10, 60, -150, 100, 0, 0],
                                                 [0, 30, 0, -30, 0, 0]]
    s_exact = (np.array(QUINTIC, dtype=object).T.dot(h_matrix(5))).tolist()
    assert s_exact == [[10, 60, -150, 100, 0, 0], [0, 30, 0, -30, 0, 0]]
    report = q.degree_report()
    assert isinstance(report, DegreeReport)
    assert (report.degree, report.real_degree, report.defect) == (5, 3, 2)
    assert report.residual <= report.tolerance == 1e-12
    assert report.rejected_residual > 1e-3
    assert q.real_degree_exact() == 3
    # The paper's H_5 E H_3^-1.
    paper = F([["1", "-2/3", "1", "-4"], ["0", "5/3", "-10/3", "15"], ["0", "0", "10/3", "-20"],
               ["0", "0", "0", "10"], ["0", "0", "0", "0"], ["0", "0", "0", "0"]])
    assert degree_change_matrix(5, 3).tolist() == paper
    # The cubic U_3 = U_5 · M, in exact rationals here; it elevates back exactly.
    cubic_exact = [[sum(Fraction(QUINTIC[i][k]) * paper[i][j] for i in range(6))
                    for k in range(2)] for j in range(4)]
    assert elevate_exact(cubic_exact, 5) == [[Fraction(x) for x in p] for p in QUINTIC]
    assert q.change_degree_exact(3).tolist() == cubic_exact
    # The stable f64 paths agree with it to rounding.
    for cubic in (q.reduce(3), q.change_degree(3), q.change_degree_paper(3)):
        assert cubic.degree == 3
        np.testing.assert_allclose(cubic.points, np.array(cubic_exact, dtype=float),
                                   rtol=0, atol=64 * EPS * 30)
        np.testing.assert_allclose(cubic.elevate(5).points, QUINTIC, rtol=0, atol=1e-12)
    np.testing.assert_allclose(q.paper_formula_f64(3), np.array(cubic_exact, dtype=float),
                               rtol=0, atol=1e-12)


def test_power_form_round_trip_is_h_inverse():
    rng = np.random.default_rng(21)
    s = rng.integers(-40, 40, size=(7, 2)) / 8.0
    n = len(s) - 1
    # U = S H_n^-1 with (H_n^-1)_ij = C(j,i) / C(n,i), in exact rationals.
    exact = [[sum(Fraction(s[i][k]) * Fraction(comb(j, i), comb(n, i)) for i in range(j + 1))
              for k in range(2)] for j in range(n + 1)]
    c = BezierCurve.from_power(s)
    np.testing.assert_allclose(c.points, np.array(exact, dtype=float), rtol=0,
                               atol=4 * EPS * np.abs(np.array(exact, dtype=float)).max())
    np.testing.assert_allclose(c.power_coefficients(), s, rtol=0, atol=1e-12)
    t = np.linspace(0, 1, 9)
    np.testing.assert_allclose(c(t), np.polynomial.polynomial.polyval(t, s).T, rtol=0,
                               atol=1e-12)
    with pytest.raises(ValueError):
        BezierCurve.from_power([[np.inf]])


def test_reduction_below_the_real_degree_names_it():
    q = BezierCurve(QUINTIC)
    with pytest.raises(ValueError, match=r"the real degree is 3 \(degree defect 2\); use "
                                         "reduce_approx"):
        q.reduce(2)
    with pytest.raises(ValueError, match="the real degree is 3"):
        q.change_degree(1)
    with pytest.raises(ValueError, match="real degree"):
        q.change_degree_exact(2)
    # The paper's formula goes on regardless: the truncation of the power form at t = 0,
    # whose power coefficients are the first three of S_5.
    truncated = q.change_degree_paper(2)
    np.testing.assert_allclose(truncated.power_coefficients(),
                               q.power_coefficients()[:3], rtol=0, atol=1e-12)
    # A larger tolerance accepts what the default refuses.
    bent = np.array(QUINTIC, dtype=float)
    bent[2, 1] += 1e-9
    with pytest.raises(ValueError, match="real degree is 5"):
        BezierCurve(bent).reduce(3)
    assert BezierCurve(bent).reduce(3, tolerance=1e-8).degree == 3


# --- exact elevation and evaluation --------------------------------------------------------


@pytest.mark.parametrize("n, n_new, dim", [(0, 3, 1), (1, 2, 2), (3, 5, 3), (5, 17, 2),
                                           (12, 40, 4)])
def test_elevation_is_the_exact_formula_rounded(n, n_new, dim):
    rng = np.random.default_rng(n * 100 + n_new)
    pts = rng.integers(-1000, 1000, size=(n + 1, dim)) / 64.0  # exact dyadic values
    exact = elevate_exact(pts.tolist(), n_new)
    ours = BezierCurve(pts).elevate(n_new).points
    scale = np.abs(pts).max()
    for row, ex in zip(ours, exact):
        for x, e in zip(row, ex):
            assert abs(Fraction(x) - e) <= Fraction(2 * EPS * scale)
    assert BezierCurve(pts).change_degree_exact(n_new).tolist() == exact
    paper = BezierCurve(pts).change_degree_paper(n_new).points
    np.testing.assert_allclose(paper, np.array(exact, dtype=float), rtol=0,
                               atol=4 * EPS * scale)


def test_evaluation_is_de_casteljau():
    rng = np.random.default_rng(3)
    for n, dim in [(0, 2), (1, 1), (3, 2), (7, 3), (20, 2), (75, 2)]:
        pts = rng.integers(-50, 50, size=(n + 1, dim)) / 8.0
        c = BezierCurve(pts)
        ts = [0.0, 0.125, 0.3, 0.5, 0.71875, 1.0, -0.25, 1.5]
        values = c(ts)
        assert values.shape == (len(ts), dim)
        for t, v in zip(ts, values):
            exact = de_casteljau_exact(pts.tolist(), Fraction(t))
            bound = 64 * (n + 1) * EPS * np.abs(pts).max() * max(1.0, abs(t) + abs(1 - t)) ** n
            assert max(abs(Fraction(x) - e) for x, e in zip(v, exact)) <= bound
        # any shape of t, and a scalar
        grid = np.linspace(0, 1, 12).reshape(3, 4)
        assert c(grid).shape == (3, 4, dim)
        np.testing.assert_allclose(c(grid), de_casteljau(pts, grid), rtol=0,
                                   atol=1e-12 * max(1.0, np.abs(pts).max()))
        assert c(0.5).shape == (dim,)


def test_derivatives_are_the_hodographs():
    pts = np.array([[0.0, 1.0], [2.0, 3.0], [5.0, -1.0], [4.0, 4.0]])
    c = BezierCurve(pts)
    # p' = 3 Σ b_2i Δu_i, p'' = 6 Σ b_1i Δ²u_i, p''' = 6 Δ³u_0: exact rationals.
    d1 = [[3 * Fraction(b - a) for a, b in zip(p, q)] for p, q in zip(pts, pts[1:])]
    d2 = [[2 * (b - a) for a, b in zip(p, q)] for p, q in zip(d1, d1[1:])]
    assert c.derivative().points.tolist() == d1
    assert c.derivative(2).points.tolist() == d2
    for t in (0.0, 0.375, 1.0):
        assert c(t, nu=1).tolist() == [float(x) for x in de_casteljau_exact(d1, t)]
        assert c(t, nu=2).tolist() == [float(x) for x in de_casteljau_exact(d2, t)]
    assert c(0.3, nu=4).tolist() == [0.0, 0.0]
    assert c(0.3, nu=10**30).tolist() == [0.0, 0.0]
    assert c.derivative(9).points.tolist() == [[0.0, 0.0]]


def test_split_pieces_are_reparametrized_halves():
    pts = np.array([[0.0, 0.0], [1.0, 3.0], [4.0, 2.0], [5.0, -1.0], [6.0, 1.0]])
    left, right = BezierCurve(pts).split(0.375)
    s = np.linspace(0, 1, 9)
    np.testing.assert_allclose(left(s), de_casteljau(pts, 0.375 * s), rtol=0, atol=1e-14)
    np.testing.assert_allclose(right(s), de_casteljau(pts, 0.375 + 0.625 * s), rtol=0,
                               atol=1e-14)
    with pytest.raises(ValueError, match="not a finite number"):
        BezierCurve(pts).split(np.nan)


# --- rational curves ----------------------------------------------------------------------


def rational_exact(points, weights, t):
    h = [[Fraction(x) * Fraction(w) for x in p] + [Fraction(w)] for p, w in zip(points, weights)]
    *num, den = de_casteljau_exact(h, t)
    return [x / den for x in num]


def test_rational_quarter_circle():
    w = [1.0, np.sqrt(0.5), 1.0]
    arc = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], weights=w)
    assert arc.is_rational and arc.weights.tolist() == w
    t = np.linspace(0, 1, 101)
    p = arc(t)
    np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), 1.0, rtol=0, atol=4 * EPS)
    for tt in (0.25, 0.5, 0.8125):
        exact = rational_exact([[1, 0], [1, 1], [0, 1]], w, tt)
        np.testing.assert_allclose(arc(tt), [float(x) for x in exact], rtol=0, atol=2 * EPS)
    # The same circle after elevation; the homogeneous curve has real degree 2.
    e = arc.elevate(6)
    assert e.degree == 6 and e.weights.shape == (7,)
    np.testing.assert_allclose(e(t), p, rtol=0, atol=1e-15)
    assert e.degree_report().real_degree == 2
    back = e.reduce(2)
    np.testing.assert_allclose(back.points, arc.points, rtol=0, atol=1e-14)
    np.testing.assert_allclose(back.weights, w, rtol=0, atol=1e-14)
    # Derivatives of a circle of unit radius: p' ⊥ p; against central differences.
    h = 1e-6
    for tt in (0.2, 0.6):
        d = arc(tt, nu=1)
        assert abs(np.dot(d, arc(tt))) < 1e-14 * np.linalg.norm(d)
        np.testing.assert_allclose(d, (arc(tt + h) - arc(tt - h)) / (2 * h), rtol=1e-8)
        np.testing.assert_allclose(arc(tt, nu=2), (arc(tt + h, nu=1) - arc(tt - h, nu=1)) /
                                   (2 * h), rtol=1e-7)
    left, right = arc.split(0.5)
    np.testing.assert_allclose(left(1.0), arc(0.5), rtol=0, atol=4 * EPS)
    np.testing.assert_allclose(right(0.5), arc(0.75), rtol=0, atol=4 * EPS)
    for op in (lambda: arc.reduce_approx(1), lambda: arc.derivative(),
               lambda: arc.remove_vertex(1), lambda: arc.power_coefficients(),
               lambda: arc.change_degree_paper(3)):
        with pytest.raises(ValueError, match="polynomial Bézier curves only"):
            op()
    with pytest.raises(ValueError, match="the real degree is 2 .*rational curve reduces "
                                         "exactly only"):
        arc.reduce(1)


# --- approximate reduction ----------------------------------------------------------------


def l2_best_exact_numpy(pts, m):
    """The L2[0,1]-best control points of degree m, by NumPy: least squares of Bernstein
    values at Gauss–Legendre nodes (exact for these polynomial integrands)."""
    x, w = np.polynomial.legendre.leggauss(len(pts) + m + 2)
    t, w = (x + 1) / 2, w / 2
    basis = np.array([[comb(m, i) * tt**i * (1 - tt) ** (m - i) for i in range(m + 1)]
                      for tt in t])
    target = de_casteljau(pts, t)
    sw = np.sqrt(w)[:, None]
    return np.linalg.lstsq(sw * basis, sw * target, rcond=None)[0]


def test_reduce_approx_is_the_l2_best_with_a_true_error_report():
    rng = np.random.default_rng(5)
    pts = rng.normal(size=(9, 2)) * 10
    c = BezierCurve(pts)
    for m in (2, 4, 7):
        red, err = c.reduce_approx(m)
        assert isinstance(err, ReductionError) and red.degree == m
        np.testing.assert_allclose(red.points, l2_best_exact_numpy(pts, m), rtol=0,
                                   atol=1e-9 * np.abs(pts).max())
        found, at, l2 = dense_distance(pts, red.points)
        assert err.l2 == pytest.approx(l2, rel=1e-6)
        # The report's maximum is attained; the bound holds and is tight (1% + slack).
        assert err.linf_found <= found * (1 + 1e-9)
        assert found <= err.linf_bound
        assert err.linf_bound <= 1.011 * found + 1e-9
        assert np.linalg.norm(de_casteljau(pts, err.at) - red(err.at)) == \
            pytest.approx(err.linf_found, rel=1e-12)
        assert red.reduction_error == ReductionError(err.l2, err.linf_bound)


def test_reduce_approx_continuity_and_chebyshev_norm():
    pts = np.array([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [3.0, 3.0], [4.0, 0.0], [5.0, 1.0]])
    c = BezierCurve(pts)
    red, err = c.reduce_approx(3, continuity=(1, 1))
    # C^1 at both ends: the ends and the first derivatives are the original's.
    for t in (0.0, 1.0):
        np.testing.assert_allclose(red(t), c(t), rtol=0, atol=1e-13)
        np.testing.assert_allclose(red(t, nu=1), c(t, nu=1), rtol=0, atol=1e-12)
    free, free_err = c.reduce_approx(3)
    assert free_err.l2 < err.l2  # constraints cost accuracy
    cheb, cheb_err = c.reduce_approx(3, norm="chebyshev")
    found_l2 = dense_distance(pts, free.points)[0]
    found_cheb = dense_distance(pts, cheb.points)[0]
    assert found_cheb < found_l2  # near-minimax beats L2 in the maximum norm here
    assert cheb_err.l2 >= free_err.l2  # and L2 is best in L2
    only_start, _ = c.reduce_approx(2, continuity=(2, None))
    for nu in range(3):
        np.testing.assert_allclose(only_start(0.0, nu=nu), c(0.0, nu=nu), rtol=1e-12, atol=1e-11)
    with pytest.raises(ValueError, match="continuity|fix"):
        c.reduce_approx(2, continuity=(2, 1))
    with pytest.raises(ValueError, match="lower degree"):
        c.reduce_approx(5)
    with pytest.raises(ValueError, match="norm"):
        c.reduce_approx(3, norm="max")
    with pytest.raises(TypeError):
        c.reduce_approx(3, continuity=1)


def test_deviation_is_the_dense_maximum():
    a = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0], [4.0, 0.0]])
    b = np.array([[0.0, 0.1], [2.0, 1.5], [4.0, 0.2]])
    d = BezierCurve(a).deviation_from(BezierCurve(b))
    assert isinstance(d, Deviation)
    found, _, _ = dense_distance(a, b)
    assert d.max_found <= found * (1 + 1e-9) and found <= d.upper_bound
    assert d.upper_bound <= 1.011 * found + 1e-12
    with pytest.raises(ValueError, match="dimension"):
        BezierCurve(a).deviation_from(BezierCurve([[0.0], [1.0]]))
    with pytest.raises(TypeError):
        BezierCurve(a).deviation_from(a)


# --- hand edits -----------------------------------------------------------------------------


def test_vertex_edits_and_their_deviation():
    pts = np.array([[float(i), float(i % 3)] for i in range(9)])
    c = BezierCurve(pts)
    e = c.remove_vertex(3)
    assert e.index == 3 and e.curve.points.tolist() == np.delete(pts, 3, axis=0).tolist()
    found, _, _ = dense_distance(pts, e.curve.points)
    assert e.deviation.max_found <= found * (1 + 1e-9) <= e.deviation.upper_bound * (1 + 1e-9)
    mid = c.remove_middle_vertex()
    assert mid.index == 4 and mid.curve.degree == 7  # n = 8: m = 4
    odd = BezierCurve(pts[:8]).remove_middle_vertex()  # n = 7: vertex 3 or 4, the lesser move
    assert odd.index in (3, 4)
    other = BezierCurve(pts[:8]).remove_vertex(7 - odd.index)
    assert odd.deviation.upper_bound <= other.deviation.upper_bound
    ins = c.insert_vertex(9, [10.0, 5.0])
    assert ins.curve.degree == 9 and ins.curve.points[-1].tolist() == [10.0, 5.0]
    found, _, _ = dense_distance(pts, ins.curve.points)
    assert ins.deviation.max_found <= found * (1 + 1e-9) <= ins.deviation.upper_bound * (1 + 1e-9)
    with pytest.raises(ValueError, match="out of range|position"):
        c.remove_vertex(9)
    with pytest.raises(ValueError, match="position|range"):
        c.insert_vertex(11, [0.0, 0.0])
    with pytest.raises(ValueError):
        c.insert_vertex(0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError):
        c.insert_vertex(0, [np.nan, 0.0])
    with pytest.raises(ValueError):
        BezierCurve([[1.0]]).remove_vertex(0)


# --- surfaces -------------------------------------------------------------------------------


def elevate_net_exact(net, n_new, m_new):
    """Formula (14) for elevation, in exact rationals: rows then columns by formula (8)."""
    cols = [elevate_exact([[x for p in row for x in p] for row in
                           np.asarray(net, dtype=object)[:, j:j + 1].tolist()], n_new)
            for j in range(len(net[0]))]
    dim = len(net[0][0])
    rows = [[cols[j][i] for j in range(len(cols))] for i in range(n_new + 1)]
    return [[[Fraction(x) for x in p] for p in elevate_exact(row, m_new)] for row in
            [[r[j][:dim] for j in range(len(r))] for r in rows]]


def test_surface_evaluation_is_tensor_de_casteljau():
    rng = np.random.default_rng(8)
    net = rng.integers(-20, 20, size=(4, 3, 3)) / 4.0
    s = BezierSurface(net)
    assert s.degree == (3, 2) and s.dim == 3 and s.net.tolist() == net.tolist()
    u, v = [0.0, 0.25, 0.625, 1.0], [0.5, 0.875, 0.0]
    grid = s(u, v)
    assert grid.shape == (4, 3, 3)
    for a, uu in enumerate(u):
        for b, vv in enumerate(v):
            exact = surface_exact(net.tolist(), Fraction(uu), Fraction(vv))
            assert max(abs(Fraction(x) - e) for x, e in zip(grid[a, b], exact)) <= 64 * EPS * 5
    pairs = s(np.array(u)[:, None], np.array(v)[None, :], grid=False)
    np.testing.assert_array_equal(pairs, grid)
    assert s(0.5, [0.1, 0.2], grid=False).shape == (2, 3)
    # partial derivatives: hodographs in exact rationals
    du_net = [[[3 * (Fraction(b) - Fraction(a)) for a, b in zip(p, q)] for p, q in zip(r0, r1)]
              for r0, r1 in zip(net.tolist(), net.tolist()[1:])]
    assert s.derivative().net.tolist() == du_net
    np.testing.assert_allclose(s(0.3, 0.4, du=1)[0, 0],
                               [float(x) for x in surface_exact(du_net, Fraction(3, 10),
                                                                Fraction(2, 5))], atol=1e-13)
    h = 1e-6
    np.testing.assert_allclose(s(0.3, 0.4, du=1, dv=1)[0, 0],
                               (s(0.3 + h, 0.4 + h) - s(0.3 + h, 0.4 - h) - s(0.3 - h, 0.4 + h)
                                + s(0.3 - h, 0.4 - h))[0, 0] / (4 * h * h), rtol=1e-4)
    assert s(0.3, 0.4, du=9).tolist() == [[[0.0, 0.0, 0.0]]]
    with pytest.raises(ValueError, match="1-D"):
        s(np.ones((2, 2)), [0.5])
    with pytest.raises(ValueError, match="broadcast"):
        s([0.1, 0.2], [0.1, 0.2, 0.3], grid=False)
    with pytest.raises(ValueError):
        s([np.nan], [0.5])


def test_surface_normals():
    # p(u, v) = (u, v, u v) on a bilinear net, elevated: n ∝ (-v, -u, 1).
    s = BezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]).elevate((3, 2))
    u, v = np.linspace(0, 1, 5), np.linspace(0, 1, 4)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    expected = np.stack([-vv, -uu, np.ones_like(uu)], axis=-1)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    np.testing.assert_allclose(s.normal(u, v), expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(s.normal(uu, vv, grid=False), expected, rtol=0, atol=1e-14)
    # A collapsed edge (all of row 0 one point): ∂p/∂v vanishes at u = 0.
    cone = BezierSurface([[[0, 0, 1]] * 3, [[1, 0, 0], [1, 1, 0], [0, 1, 0]]])
    n = cone.normal([0.0, 0.5], [0.5])
    assert np.isnan(n[0, 0]).all() and np.isfinite(n[1, 0]).all()
    with pytest.raises(ValueError, match="dimension|R\\^3|expected 3"):
        BezierSurface(np.zeros((2, 2, 2))).normal(0.5, 0.5)
    with pytest.raises(ValueError, match="finite"):
        s.normal([np.inf], [0.5])


def test_surface_fig5_and_the_eight_problems():
    """The paper's Fig. 5 situation: a (4, 3) surface on a 5×4 net whose S has a zero
    bottom row (real u-degree 3), reduced to a 4×4 net, then t-degree 3 and τ-degree 6."""
    rng = np.random.default_rng(13)
    base = rng.integers(-30, 30, size=(4, 4, 3)).astype(float)
    net_exact = elevate_net_exact(base.tolist(), 4, 3)
    net = np.array(net_exact, dtype=float)
    s = BezierSurface(net)
    report = s.degree_report()
    assert isinstance(report, SurfaceDegreeReport)
    assert (report.degree, report.real_degree, report.defect) == ((4, 3), (3, 3), (1, 0))
    reduced = s.reduce((3, 3))
    np.testing.assert_allclose(reduced.net, base, rtol=0, atol=1e-12)
    both = s.change_degree((3, 6))  # reduce in u and elevate in v at once
    np.testing.assert_allclose(both.net, np.array(elevate_net_exact(base.tolist(), 3, 6),
                                                  dtype=float), rtol=0, atol=1e-12)
    u = np.linspace(0, 1, 7)
    for target in [(5, 3), (4, 5), (3, 2 + 1), (6, 6), (3, 4), (5, 3)]:
        np.testing.assert_allclose(s.change_degree(target)(u, u), s(u, u), rtol=0, atol=1e-11)
    with pytest.raises(ValueError, match="in v: the real v-degree is 3"):
        s.change_degree((4, 2))
    with pytest.raises(ValueError, match="elevation needs degrees"):
        s.elevate((3, 4))
    with pytest.raises(ValueError, match="reduction needs degrees"):
        s.reduce((5, 3))
    paper = s.change_degree_paper((3, 6))
    np.testing.assert_allclose(paper.net, both.net, rtol=0, atol=1e-10)
    with pytest.raises(TypeError):
        s.change_degree(3)
    with pytest.raises(ValueError):
        s.change_degree((3, 3, 3))


def test_surface_rows_and_columns():
    net = np.arange(24.0).reshape(3, 4, 2)
    s = BezierSurface(net)
    row = [[9.0, 9.0]] * 4
    assert s.insert_row(1, row).net.tolist() == np.insert(net, 1, row, axis=0).tolist()
    col = [[7.0, 7.0]] * 3
    assert s.insert_column(4, col).net.tolist() == np.insert(net, 4, col, axis=1).tolist()
    assert s.remove_row(2).net.tolist() == net[:2].tolist()
    assert s.remove_column(0).net.tolist() == net[:, 1:].tolist()
    with pytest.raises(ValueError):
        s.insert_row(1, col)  # 3 points for a row of 4
    with pytest.raises(ValueError):
        s.remove_row(3)
    with pytest.raises(ValueError):
        BezierSurface(net[:1]).remove_row(0)
    d = s.deviation_from(s.insert_row(1, row))
    assert d.max_found > 0 and d.upper_bound >= d.max_found


# --- model files, the CLI, pickling ----------------------------------------------------------


def test_model_file_round_trip(tmp_path):
    c = BezierCurve(QUINTIC)
    assert json.loads(c.to_json()) == {"type": "bezier_curve", "points": QUINTIC}
    assert c.describe() == "Bézier curve of degree 5 in R^2 (6 control points)"
    c.save(tmp_path / "q.json")
    back = geomkit.load(tmp_path / "q.json")
    assert isinstance(back, BezierCurve) and back == c
    arc = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], weights=[1.0, 0.5**0.5, 1.0])
    assert geomkit.loads(arc.to_json()) == arc
    red, err = c.reduce_approx(2)
    doc = json.loads(red.to_json())
    assert doc["error"] == {"l2": err.l2, "linf_bound": err.linf_bound}
    assert geomkit.loads(red.to_json()).reduction_error == ReductionError(err.l2,
                                                                        err.linf_bound)
    s = BezierSurface(np.arange(12.0).reshape(2, 3, 2))
    assert json.loads(s.to_json())["type"] == "bezier_surface"
    assert geomkit.loads(s.to_json()) == s
    with pytest.raises(TypeError, match="not a Bézier curve"):
        BezierCurve._from_model(s._model())


CLI = ROOT / "target" / "release" / "geomkit"


@pytest.mark.skipif(not CLI.is_file(), reason="the CLI is not built (cargo build --release)")
def test_files_the_cli_writes(tmp_path):
    src = tmp_path / "quintic.json"
    src.write_text(json.dumps({"type": "bezier_curve", "points": QUINTIC}))

    def cli(*args):
        out = tmp_path / "out.json"
        subprocess.run([str(CLI), "bezier", *args, str(src), "-o", str(out)], check=True,
                       capture_output=True)
        return geomkit.load(out)

    q = BezierCurve(QUINTIC)
    assert cli("elevate", "--to", "9") == q.elevate(9)
    assert cli("reduce", "--to", "3") == q.reduce(3)
    approx = cli("reduce", "--to", "2", "--approx", "--continuity", "0,0")
    red, err = q.reduce_approx(2, continuity=(0, 0))
    assert approx == red
    assert approx.reduction_error == ReductionError(err.l2, err.linf_bound)
    degree = subprocess.run([str(CLI), "bezier", "degree", "--json", str(src)], check=True,
                            capture_output=True, text=True).stdout
    r = q.degree_report()
    assert json.loads(degree) == {"degree": r.degree, "real_degree": r.real_degree,
                                  "defect": r.defect}
    arc = BezierCurve([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], weights=[1.0, 0.5**0.5, 1.0])
    arc.save(src)
    assert cli("elevate", "--to", "5") == arc.elevate(5)
    src.write_text(json.dumps({"type": "bezier_surface",
                               "net": np.arange(18.0).reshape(3, 2, 3).tolist()}))
    s = cli("elevate", "--to", "4,3")
    assert isinstance(s, BezierSurface)
    assert s == BezierSurface(np.arange(18.0).reshape(3, 2, 3)).elevate((4, 3))


def test_pickle_and_repr():
    objs = [BezierCurve(QUINTIC), BezierCurve([[1.0, 0.0], [0.0, 1.0]], weights=[2.0, 0.5]),
            BezierCurve(QUINTIC).reduce_approx(2).curve,
            BezierSurface(np.arange(12.0).reshape(3, 2, 2))]
    for obj in objs:
        back = pickle.loads(pickle.dumps(obj))
        assert type(back) is type(obj) and back == obj
        assert back.to_json() == obj.to_json()
    assert repr(objs[0]) == "<geomkit.BezierCurve: degree 5 in R^2 (6 control points)>"
    assert repr(objs[1]).startswith("<geomkit.BezierCurve: rational degree 1")
    assert "reduction error L2" in repr(objs[2])
    assert repr(objs[3]) == "<geomkit.BezierSurface: degrees (2, 1) in R^2 (3×2 net)>"
    assert BezierCurve(QUINTIC) != BezierCurve(QUINTIC[:-1])
    assert BezierCurve([[0.0]]) != BezierCurve([[0.0]], weights=[1.0])


def test_arrays_are_read_only_copies():
    pts = np.array(QUINTIC, dtype=float)
    c = BezierCurve(pts)
    pts[0, 0] = 99.0  # the curve copied its input
    assert c.points[0, 0] == 10.0
    with pytest.raises(ValueError, match="read-only"):
        c.points[0, 0] = 1.0
    s = BezierSurface(np.zeros((2, 2, 1)))
    with pytest.raises(ValueError, match="read-only"):
        s.net[0, 0, 0] = 1.0
    # non-contiguous and integer input is converted
    assert BezierCurve(np.asfortranarray(pts[:, ::-1])).points.tolist() == pts[:, ::-1].tolist()


# --- bad input ------------------------------------------------------------------------------


@pytest.mark.parametrize("points, error", [
    ([], ValueError), (np.zeros((0, 2)), ValueError), (np.zeros((3, 0)), ValueError),
    (5.0, ValueError), ([1.0, 2.0], ValueError), (np.zeros((2, 2, 2)), ValueError),
    ([[0.0, np.nan]], ValueError), ([[0.0, np.inf]], ValueError),
    ([["a", "b"]], TypeError), ([[1j, 0.0]], TypeError), ([[object(), 1.0]], TypeError),
])
def test_bad_points(points, error):
    with pytest.raises(error):
        BezierCurve(points)


def test_bad_arguments():
    c = BezierCurve(QUINTIC)
    for weights, match in [([1.0] * 5, "6 control points"), ([1.0] * 5 + [0.0], "weight"),
                           ([1.0] * 5 + [-1.0], "weight"), ([1.0] * 5 + [np.nan], "weight"),
                           (np.ones((6, 1)), "1-D")]:
        with pytest.raises(ValueError, match=match):
            BezierCurve(QUINTIC, weights=weights)
    with pytest.raises(ValueError, match="not a finite number"):
        c([0.5, np.nan])
    with pytest.raises(TypeError):
        c("x")
    with pytest.raises(TypeError):
        c.elevate(6.0)
    with pytest.raises(ValueError, match=">= 0"):
        c.elevate(-1)
    with pytest.raises(ValueError):
        c.elevate(2**70)
    with pytest.raises(ValueError, match="limit"):
        c.elevate(10**9)  # the elevation matrix would not fit
    with pytest.raises(ValueError, match="elevation needs"):
        c.elevate(4)
    with pytest.raises(ValueError, match="tolerance"):
        c.reduce(3, tolerance=-1.0)
    with pytest.raises(TypeError):
        c.reduce(3, tolerance="small")
    with pytest.raises(ValueError, match="limit of 100"):
        c.change_degree_paper(10**6)
    with pytest.raises(ValueError, match="limit of 100"):
        c.paper_formula_f64(10**12)
    with pytest.raises(ValueError, match="limit of 100"):
        degree_change_matrix(300, 2)
    with pytest.raises(ValueError, match="limit of 100"):
        degree_change_matrix(2, 101)
    assert degree_change_matrix(100, 100)[50, 50] == 1  # the limit itself is served
    with pytest.raises(ValueError, match="limit"):
        BezierCurve(np.zeros((2000, 1))).degree_report()
    with pytest.raises(ValueError):
        BezierSurface(np.zeros((2, 2)))
    with pytest.raises(ValueError):
        BezierSurface(np.zeros((0, 2, 2)))
    with pytest.raises(ValueError, match="direction"):
        BezierSurface(np.zeros((2, 2, 1)))._core.derivative("w")


# --- properties, threads ------------------------------------------------------------------


@given(
    n=st.integers(0, 12), extra=st.integers(1, 20), dim=st.integers(1, 4),
    seed=st.integers(0, 2**32 - 1),
)
def test_elevate_then_reduce_gives_back_the_points(n, extra, dim, seed):
    pts = np.random.default_rng(seed).uniform(-100, 100, size=(n + 1, dim))
    c = BezierCurve(pts)
    e = c.elevate(n + extra)
    assert e.degree_report().real_degree <= n
    back = e.reduce(n)
    np.testing.assert_allclose(back.points, pts, rtol=0, atol=1e-11 * np.abs(pts).max())
    t = np.linspace(0, 1, 17)
    np.testing.assert_allclose(e(t), c(t), rtol=0, atol=1e-12 * np.abs(pts).max())


@given(
    n=st.integers(0, 6), m=st.integers(0, 6), up_u=st.integers(0, 5), up_v=st.integers(0, 5),
    seed=st.integers(0, 2**32 - 1),
)
def test_surface_elevate_then_reduce_gives_back_the_net(n, m, up_u, up_v, seed):
    net = np.random.default_rng(seed).uniform(-10, 10, size=(n + 1, m + 1, 3))
    s = BezierSurface(net)
    e = s.change_degree((n + up_u, m + up_v))
    assert e.degree_report().real_degree == s.degree_report().real_degree
    np.testing.assert_allclose(e.reduce((n, m)).net, net, rtol=0, atol=1e-11 * 10)
    u = np.linspace(0, 1, 5)
    np.testing.assert_allclose(e(u, u), s(u, u), rtol=0, atol=1e-12 * 10)


def test_threads_give_the_same_bits():
    rng = np.random.default_rng(1)
    c = BezierCurve(rng.normal(size=(12, 3)))
    s = BezierSurface(rng.normal(size=(5, 6, 3)))
    t = rng.uniform(0, 1, 200_000)
    u = rng.uniform(0, 1, 300)
    one = (c(t), s(u, u))
    with ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda _: (c(t), s(u, u)), range(8)))
    for a, b in results:
        assert np.array_equal(a, one[0]) and np.array_equal(b, one[1])


def test_docstring_examples_run():
    import doctest

    import geomkit._bezier as module

    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 30 and result.failed == 0, result


def test_public_api_is_documented():
    import inspect

    public = [BezierCurve, BezierSurface, degree_change_matrix, h_matrix]
    for cls in (BezierCurve, BezierSurface):
        public += [getattr(cls, n) for n in vars(cls)
                   if (not n.startswith("_") or n == "__call__") and callable(getattr(cls, n))]
    for obj in public:
        doc = inspect.getdoc(obj) or ""
        assert "Examples\n--------" in doc, obj
        assert "Returns\n-------" in doc or "Parameters\n----------" in doc, obj
    assert {"BezierCurve", "BezierSurface", "degree_change_matrix", "h_matrix"} <= \
        set(geomkit.__all__)


def test_results_too_large_are_refused_not_allocated():
    wide = BezierCurve(np.zeros((2, 1000)))
    with pytest.raises(ValueError, match="a curve of degree 999999 in R\\^1000.*limit"):
        wide.elevate(999_999)  # 10^9 numbers: refused before the library allocates them
    net = BezierSurface(np.zeros((2, 1000, 3)))
    with pytest.raises(ValueError, match="a surface of degrees .*limit"):
        net.elevate((100_000, 999))
    with pytest.raises(ValueError, match="limit"):
        net.change_degree((2**40, 999))


def test_compiled_module_refuses_what_it_cannot_read():
    from geomkit import _geomkit

    pts = np.arange(12.0).reshape(6, 2)
    with pytest.raises(TypeError):
        _geomkit.BezierCurveCore(pts[::2])  # not contiguous
    with pytest.raises(TypeError):
        _geomkit.BezierCurveCore(pts.astype(np.float32))
    with pytest.raises(TypeError):
        _geomkit.BezierCurveCore(pts.ravel())
    core = _geomkit.BezierCurveCore(pts)
    with pytest.raises(ValueError, match="buffer"):
        core.eval_into(np.linspace(0, 1, 5), 0, np.empty((4, 2)))
    read_only = np.empty((5, 2))
    read_only.flags.writeable = False
    with pytest.raises(TypeError, match="not writeable"):
        core.eval_into(np.linspace(0, 1, 5), 0, read_only)
    with pytest.raises(OverflowError):
        core.elevate(-1)
    with pytest.raises(ValueError, match="norm"):
        core.reduce_approx(2, None, None, "l1")
    surface = _geomkit.BezierSurfaceCore(np.zeros((2, 3, 1)))
    with pytest.raises(ValueError, match="same length"):
        surface.eval_points_into(np.zeros(2), np.zeros(3), np.empty((2, 1)))
    with pytest.raises(ValueError, match="buffer"):
        surface.eval_grid_into(np.zeros(2), np.zeros(3), np.empty((2, 2, 1)))
    with pytest.raises(TypeError, match="not a Bézier surface"):
        _geomkit.BezierSurfaceCore.from_model(core.to_model())


def test_the_gil_is_released_during_evaluation():
    from test_package import _seen_inside

    rng = np.random.default_rng(2)
    c = BezierCurve(rng.normal(size=(40, 3)))
    t = rng.uniform(0, 1, 3_000_000)
    curve = _seen_inside(lambda: c(t), BezierCurve.__call__, "eval_into(")
    s = BezierSurface(rng.normal(size=(12, 12, 3)))
    u = np.linspace(0, 1, 1200)
    grid = _seen_inside(lambda: s(u, u), BezierSurface.__call__, "eval_grid_into(")
    assert min(curve, grid) > 20, (curve, grid)


# --- rational surfaces --------------------------------------------------------------------


def sphere_octant():
    """An octant of the unit sphere: the meridian's quarter circle (weights 1, 1/√2, 1)
    turned through 90° about z (the same weights), w_ij = w_i w_j."""
    h = np.sqrt(0.5)
    turn = [(1, 0), (1, 1), (0, 1)]
    meridian = [(1, 0), (1, 1), (0, 1)]
    net = [[[r * c, r * s, z] for r, z in meridian] for c, s in turn]
    w = np.array([1.0, h, 1.0])
    return BezierSurface(net, weights=np.outer(w, w))


def rational_surface_exact(net, weights, u, v):
    """Σ Σ w_ij b_i(u) b_j(v) u_ij / Σ Σ w_ij b_i(u) b_j(v) in exact rationals."""
    n, m = len(net) - 1, len(net[0]) - 1
    u, v = Fraction(u), Fraction(v)
    num = [Fraction(0)] * len(net[0][0])
    den = Fraction(0)
    for i in range(n + 1):
        for j in range(m + 1):
            b = (comb(n, i) * u**i * (1 - u) ** (n - i) * comb(m, j) * v**j * (1 - v) ** (m - j)
                 * Fraction(weights[i][j]))
            den += b
            num = [a + b * Fraction(x) for a, x in zip(num, net[i][j])]
    return [a / den for a in num]


def test_rational_surface_is_the_exact_quotient():
    rng = np.random.default_rng(5)
    net = rng.integers(-9, 10, size=(4, 3, 3)).astype(float)
    weights = rng.integers(1, 6, size=(4, 3)).astype(float) / 4
    s = BezierSurface(net, weights=weights)
    assert s.is_rational and s.degree == (3, 2)
    assert np.array_equal(s.weights, weights) and np.array_equal(s.net, net)
    us, vs = [0, 0.25, 0.625, 1], [0, 0.5, 0.875]
    got = s(us, vs)
    for a, u in enumerate(us):
        for b, v in enumerate(vs):
            want = np.array([float(x) for x in rational_surface_exact(net, weights, u, v)])
            assert np.allclose(got[a, b], want, rtol=0, atol=4 * EPS * np.abs(net).max())
    # Pairs give the grid's values.
    pairs = s([0.25, 0.625], [0.5, 0.875], grid=False)
    assert np.allclose(pairs, [got[1, 1], got[2, 2]], rtol=0, atol=1e-15)


def test_rational_surface_elevation_is_formula_8_on_the_homogeneous_net():
    rng = np.random.default_rng(8)
    net = rng.integers(-9, 10, size=(3, 2, 2)).astype(float)
    weights = rng.integers(1, 5, size=(3, 2)).astype(float)
    e = BezierSurface(net, weights=weights).elevate((4, 3))
    # Formula (8) in u on every column of the homogeneous net, then in v on every row.
    h = [[[Fraction(x) * Fraction(w) for x in p] + [Fraction(w)] for p, w in zip(row, wr)]
         for row, wr in zip(net.tolist(), weights.tolist())]
    cols = [elevate_exact([h[i][j] for i in range(3)], 4) for j in range(2)]
    rows = [elevate_exact([cols[j][i] for j in range(2)], 3) for i in range(5)]
    want_w = np.array([[float(p[-1]) for p in row] for row in rows])
    want_p = np.array([[[float(x / p[-1]) for x in p[:-1]] for p in row] for row in rows])
    assert np.allclose(e.weights, want_w, rtol=4 * EPS, atol=0)
    assert np.allclose(e.net, want_p, rtol=0, atol=16 * EPS * np.abs(net).max())
    assert e.degree_report().real_degree == (2, 1)
    back = e.reduce((2, 1))
    assert np.allclose(back.weights, weights, rtol=1e-13, atol=0)
    assert np.allclose(back.net, net, rtol=0, atol=1e-12)


def test_rational_surface_keeps_the_sphere_and_refuses_below_its_degree():
    octant = sphere_octant()
    t = np.linspace(0.0, 1.0, 33)
    for degrees in [(2, 2), (3, 5), (7, 4), (12, 12)]:
        e = octant.change_degree(degrees)
        assert e.degree == degrees
        p = e(t, t)
        assert np.abs(np.linalg.norm(p, axis=-1) - 1).max() < 4 * EPS
        # The normal is the radius, except at the pole v = 1 (a collapsed edge: NaN).
        n = e.normal(t, t)
        assert np.abs(np.abs(np.sum(n * p, axis=-1)[:, :-1]) - 1).max() < 1e-13
        assert np.isnan(n[:, -1]).all()
    with pytest.raises(ValueError, match="degree 1 in u: the real u-degree is 2"):
        octant.elevate((4, 4)).reduce((1, 4))
    with pytest.raises(ValueError, match="has weights"):
        octant.derivative()
    with pytest.raises(ValueError, match="polynomial"):
        octant.deviation_from(octant)


def test_rational_surface_partial_derivatives_are_sympys():
    sympy = pytest.importorskip("sympy")
    rng = np.random.default_rng(13)
    net = rng.integers(-5, 6, size=(3, 3, 2)).astype(float)
    weights = rng.integers(1, 5, size=(3, 3)).astype(float)
    s = BezierSurface(net, weights=weights)
    u, v = sympy.symbols("u v")
    b = [[sympy.binomial(2, i) * u**i * (1 - u) ** (2 - i) * sympy.binomial(2, j) * v**j
          * (1 - v) ** (2 - j) * sympy.Integer(int(weights[i, j])) for j in range(3)]
         for i in range(3)]
    den = sum(sum(row) for row in b)
    p = [sum(b[i][j] * sympy.Integer(int(net[i, j, k])) for i in range(3) for j in range(3))
         / den for k in range(2)]
    at = {u: sympy.Rational(3, 10), v: sympy.Rational(7, 10)}
    for du, dv in [(1, 0), (0, 1), (1, 1), (2, 0), (2, 3)]:
        want = np.array([float(sympy.diff(pk, u, du, v, dv).subs(at)) for pk in p])
        got = s(0.3, 0.7, du=du, dv=dv)[0, 0]
        assert np.allclose(got, want, rtol=1e-12, atol=1e-12), (du, dv)
        pairs = s([0.3], [0.7], grid=False, du=du, dv=dv)[0]
        assert np.array_equal(pairs, got)


def test_rational_surface_edits_files_and_the_cli(tmp_path):
    octant = sphere_octant()
    h = np.sqrt(0.5)
    t = octant.insert_column(1, [[2, 0, 1], [2, 2, 1], [0, 2, 1]], weights=[1, 0.5, 1])
    assert t.degree == (2, 3)
    assert np.array_equal(t.weights[:, 1], [1, 0.5, 1])
    assert t.remove_column(1) == octant
    # A polynomial surface given weights becomes rational, its own weights 1.
    p = BezierSurface(np.arange(12.0).reshape(2, 2, 3)).insert_row(1, [[0, 0, 0], [1, 1, 1]],
                                                                 weights=[2, 3])
    assert p.is_rational and np.array_equal(p.weights, [[1, 1], [2, 3], [1, 1]])
    # The file: net and weights; the CLI reads it and changes its degree as the package does.
    path = tmp_path / "octant.json"
    octant.save(path)
    data = json.loads(path.read_text())
    assert data["type"] == "bezier_surface"
    assert data["weights"] == octant.weights.tolist() and data["net"] == octant.net.tolist()
    assert np.allclose(data["weights"], [[1, h, 1], [h, 0.5, h], [1, h, 1]], rtol=EPS, atol=0)
    back = geomkit.load(path)
    assert back == octant
    out = tmp_path / "e.json"
    subprocess.run([str(CLI), "bezier", "elevate", "--to", "4,3", str(path), "-o", str(out)],
                   check=True, capture_output=True)
    assert geomkit.load(out) == octant.elevate((4, 3))
    degree = subprocess.run([str(CLI), "bezier", "degree", "--json", str(out)], check=True,
                            capture_output=True, text=True).stdout
    assert json.loads(degree) == {"degree": [4, 3], "real_degree": [2, 2], "defect": [2, 1]}
    # The mesh lies on the sphere.
    mesh = octant.mesh(tolerance=1e-4)
    r = np.linalg.norm(mesh.vertices, axis=1)
    assert mesh.faces.shape[0] > 8 and np.abs(r - 1).max() < 1e-14
    back = pickle.loads(pickle.dumps(octant))
    assert back == octant and "rational" in repr(back)


@pytest.mark.parametrize("weights, message", [
    ([[1, 1, 1], [1, -1, 1], [1, 1, 1]], r"weight \(1, 1\) of the net is -1"),
    ([[1, 1, 1], [1, 1, 1], [1, 1, np.nan]], r"weight \(2, 2\)"),
    ([[1, 1], [1, 1], [1, 1]], "shape"),
    ([1, 1, 1], "shape"),
])
def test_rational_surface_bad_weights(weights, message):
    net = np.zeros((3, 3, 3))
    with pytest.raises(ValueError, match=message):
        BezierSurface(net, weights=weights)
