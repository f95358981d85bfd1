"""geomkit.RectBivariateSpline against scipy.interpolate.RectBivariateSpline (s=0): knots,
coefficients, grid and point evaluation with partial derivatives, ev, integral; errors,
pickling, threads."""

import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import scipy.interpolate as si
from conftest import assert_near
from hypothesis import given
from hypothesis import strategies as st

import geomkit


def grid(mx, my, seed=0):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.3, 1.2, mx))
    y = np.cumsum(rng.uniform(0.3, 1.2, my)) - 2.0
    z = np.sin(x)[:, None] * np.cos(y)[None, :] + rng.normal(scale=0.1, size=(mx, my))
    return x, y, z


def both(x, y, z, **kw):
    return geomkit.RectBivariateSpline(x, y, z, **kw), si.RectBivariateSpline(x, y, z, **kw)


@pytest.mark.parametrize("kx, ky", [(1, 1), (3, 3), (2, 4), (5, 1), (3, 5), (5, 5)])
def test_knots_coefficients_and_values(kx, ky):
    x, y, z = grid(9, 11, seed=kx * 10 + ky)
    ours, theirs = both(x, y, z, kx=kx, ky=ky)
    assert ours.degrees == theirs.degrees and ours.fp == theirs.fp == 0.0
    for a, b in zip(ours.get_knots(), theirs.get_knots()):
        assert_near(a, b, rel=1e-15, what="knots")
    # FITPACK's own coefficients are ~1e-10 off at degree 5 (the README's surface notes).
    assert_near(ours.get_coeffs(), theirs.get_coeffs(), rel=1e-8, what="coefficients")
    assert_near(ours(x, y), z, rel=1e-12, what="interpolates")
    xs = np.linspace(x[0] - 1, x[-1] + 1, 23)
    ys = np.linspace(y[0] - 1, y[-1] + 1, 19)
    for dx in range(kx):
        for dy in range(ky):
            assert_near(ours(xs, ys, dx=dx, dy=dy), theirs(xs, ys, dx=dx, dy=dy),
                        rel=1e-8 * 10 ** (dx + dy), what=f"grid dx={dx} dy={dy}")
    rng = np.random.default_rng(kx + ky)
    px = rng.uniform(x[0] - 1, x[-1] + 1, (4, 5))
    py = rng.uniform(y[0] - 1, y[-1] + 1, (4, 5))
    assert_near(ours(px, py, grid=False), theirs(px, py, grid=False), rel=1e-8)
    assert_near(ours.ev(px, py, dx=kx - 1), theirs.ev(px, py, dx=kx - 1), rel=1e-7)
    # Broadcasting of point coordinates.
    assert_near(ours.ev(px, 0.5), theirs.ev(px, 0.5), rel=1e-8)


def test_large_bicubic_grid():
    """From 2**16 heights the bicubic is solved in the extended form and changed to
    FITPACK's basis per direction (crates/geomkit/src/bspline/scipy_cubic.rs): the same
    knots, the same coefficients to rounding, edges and corners included."""
    x, y, z = grid(300, 231, seed=7)
    ours, theirs = both(x, y, z)
    for a, b in zip(ours.get_knots(), theirs.get_knots()):
        assert_near(a, b, rel=1e-15, what="knots")
    c, d = ours.get_coeffs().reshape(300, 231), theirs.get_coeffs().reshape(300, 231)
    assert_near(c, d, rel=1e-12, what="coefficients")
    for rows in (slice(0, 5), slice(-5, None)):
        for cols in (slice(0, 5), slice(-5, None)):
            assert_near(c[rows, cols], d[rows, cols], rel=1e-13, what="a corner")
    assert_near(ours(x, y), z, rel=1e-13, what="interpolates")
    xs, ys = np.linspace(x[0] - 1, x[-1] + 1, 97), np.linspace(y[0] - 1, y[-1] + 1, 89)
    assert_near(ours(xs, ys, dx=1, dy=1), theirs(xs, ys, dx=1, dy=1), rel=1e-11, what="d2/dxdy")


@pytest.mark.parametrize("kx, ky", [(1, 1), (3, 3), (2, 5)])
def test_integral(kx, ky):
    x, y, z = grid(8, 10, seed=3)
    ours, theirs = both(x, y, z, kx=kx, ky=ky)
    for limits in [(x[0], x[-1], y[0], y[-1]), (1.0, 3.0, -1.0, 2.0), (3.0, 1.0, -1.0, 2.0),
                   (-5.0, 50.0, -50.0, 50.0), (50.0, 60.0, 0.0, 1.0), (2.0, 2.0, 0.0, 1.0)]:
        got = ours.integral(*limits)
        assert isinstance(got, float)
        assert_near(got, theirs.integral(*limits), rel=1e-9, what=str(limits))


@pytest.mark.parametrize("kx, ky", [(3, 3), (2, 4), (1, 5), (5, 1)])
def test_partial_derivative(kx, ky):
    x, y, z = grid(9, 8, seed=9)
    ours, theirs = both(x, y, z, kx=kx, ky=ky)
    assert ours.partial_derivative(0, 0) is ours
    xs = np.linspace(x[0] - 0.5, x[-1] + 0.5, 17)
    ys = np.linspace(y[0] - 0.5, y[-1] + 0.5, 13)
    for dx in range(kx):
        for dy in range(ky):
            if (dx, dy) == (0, 0):
                continue
            a = ours.partial_derivative(dx, dy)
            assert a.degrees == (kx - dx, ky - dy)
            assert_near(a(xs, ys), theirs(xs, ys, dx=dx, dy=dy), rel=1e-8 * 10 ** (dx + dy))
            if kx <= ky:  # SciPy 1.17's pardtc wrapper checks dx < ky (not kx): kx > ky fails
                b = theirs.partial_derivative(dx, dy)
                for u, v in zip(a.tck, b.tck):
                    assert_near(u, v, rel=1e-8 * 10 ** (dx + dy), what="tck")
            with pytest.raises(AttributeError):
                a.fp
            with pytest.raises(AttributeError):
                a.get_residual()
            back = pickle.loads(pickle.dumps(a))
            assert type(back) is type(a) and np.array_equal(back(xs, ys), a(xs, ys))
    with pytest.raises(ValueError, match="less than degree"):
        ours.partial_derivative(kx, 0)
    with pytest.raises(ValueError, match=">= 0"):
        ours.partial_derivative(-1, 0)


def test_grid_edge_cases():
    x, y, z = grid(7, 6, seed=4)
    ours, theirs = both(x, y, z)
    assert ours([], y).shape == theirs([], y).shape == (0, 6)
    assert_near(ours(2.0, y), theirs(2.0, y))
    assert_near(ours([2.0, 2.0, 3.0], y), theirs([2.0, 2.0, 3.0], y))  # equal neighbours
    assert ours.ev([], []).shape == (0,)
    xs = np.repeat(x, 2)[::2]  # not contiguous
    assert not xs.flags.c_contiguous
    assert_near(ours(xs, y), theirs(x, y))


def test_input_layouts():
    x, y, z = grid(8, 9, seed=5)
    y32 = y.astype(np.float32)
    want = si.RectBivariateSpline(x, y32, z)
    zf = np.asfortranarray(z)
    ours = geomkit.RectBivariateSpline(list(x), y32, zf)
    assert_near(ours(x, y), want(x, y))
    ours = geomkit.RectBivariateSpline(np.arange(8), np.arange(9), z.tolist())
    assert_near(ours(x, y), si.RectBivariateSpline(np.arange(8), np.arange(9), z)(x, y))


@given(st.integers(4, 12), st.integers(4, 12), st.integers(1, 3), st.integers(0, 2**32 - 1))
def test_random_grids_match_scipy(mx, my, k, seed):
    x, y, z = grid(mx, my, seed=seed)
    ours, theirs = both(x, y, z, kx=k, ky=k)
    xs = np.sort(np.random.default_rng(seed).uniform(x[0] - 0.5, x[-1] + 0.5, 9))
    assert_near(ours(xs, y), theirs(xs, y), rel=1e-9)


def test_pickle_and_threads():
    x, y, z = grid(40, 50, seed=6)
    ours = geomkit.RectBivariateSpline(x, y, z, kx=3, ky=2)
    back = pickle.loads(pickle.dumps(ours))
    assert type(back) is geomkit.RectBivariateSpline and back.degrees == (3, 2)
    for a, b in zip(back.tck, ours.tck):
        assert np.array_equal(a, b)
    xs = np.linspace(x[0], x[-1], 300)
    ys = np.linspace(y[0], y[-1], 400)
    assert np.array_equal(back(xs, ys, dy=1), ours(xs, ys, dy=1))
    assert back.integral(1, 5, 0, 3) == ours.integral(1, 5, 0, 3)
    rng = np.random.default_rng(6)
    jobs = [(rng.uniform(0, 30, 50_000), rng.uniform(-2, 40, 50_000)) for _ in range(16)]
    one = [ours.ev(a, b) for a, b in jobs]
    with ThreadPoolExecutor(8) as pool:
        many = list(pool.map(lambda ab: ours.ev(*ab), jobs))
    for a, b in zip(one, many):
        assert np.array_equal(a, b)
    assert_near(one[0], si.RectBivariateSpline(x, y, z, kx=3, ky=2).ev(*jobs[0]), rel=1e-10)


def test_repr():
    s = geomkit.RectBivariateSpline(np.arange(5.0), np.arange(4.0), np.ones((5, 4)),
                                    kx=3, ky=1)
    assert repr(s) == "RectBivariateSpline(kx=3, ky=1, on [0.0, 4.0] x [0.0, 3.0], 5 x 4 coefficients)"


# --- errors -------------------------------------------------------------------------------
X, Y, Z = grid(6, 7, seed=7)


@pytest.mark.parametrize("args, kwargs, match", [
    ((X[::-1], Y, Z), {}, "x must be strictly increasing"),
    ((X, np.r_[Y[:3], Y[2], Y[4:]], Z), {}, "y must be strictly increasing"),
    ((X[:5], Y, Z), {}, "x dimension of z must have same number of elements as x"),
    ((X, Y[:6], Z), {}, "y dimension of z must have same number of elements as y"),
    ((X, Y, Z), {"s": 1.0}, "smoothing is out of scope"),
    ((X, Y, Z), {"s": -1.0}, "s should be s >= 0.0"),
    ((X, Y, Z), {"bbox": [None] * 3}, r"bbox shape should be \(4,\)"),
    ((X, Y, Z), {"bbox": [X[0] - 1, None, None, None]}, "only the data's range"),
    ((X, Y, Z), {"kx": 6}, "too few for degree 6"),
    ((X, Y, Z), {"kx": 0}, "degree"),
    ((X, Y, Z.ravel()), {}, "2-D"),
    ((np.r_[X[:5], np.nan], Y, Z), {}, "not a finite number"),
    ((X, Y, np.where(Z > 0.5, np.inf, Z)), {}, "not a finite number"),
    (([], [], np.zeros((0, 0))), {}, ""),
])
def test_bad_values_are_value_errors(args, kwargs, match):
    with pytest.raises(ValueError, match=match or None):
        geomkit.RectBivariateSpline(*args, **kwargs)


def test_bbox_of_the_data_is_accepted():
    ours = geomkit.RectBivariateSpline(X, Y, Z, bbox=[X[0], X[-1], None, Y[-1]])
    assert_near(ours(X, Y), Z, rel=1e-12)


@pytest.mark.parametrize("args, kwargs", [
    ((X, Y, Z + 1j), {}),
    ((X, Y, Z), {"kx": 3.0}),
    ((X, ["a"] * 7, Z), {}),
    ((X, Y, Z), {"s": "zero"}),
])
def test_wrong_types_are_type_errors(args, kwargs):
    with pytest.raises(TypeError):
        geomkit.RectBivariateSpline(*args, **kwargs)


def test_bad_calls():
    s = geomkit.RectBivariateSpline(X, Y, Z, kx=3, ky=2)
    with pytest.raises(ValueError, match="x must be non-decreasing"):
        s(X[::-1], Y)
    with pytest.raises(ValueError, match="y must be non-decreasing"):
        s(X, [0.0, np.nan, 1.0])
    with pytest.raises(ValueError, match="derivative order 2 of a B-spline of degree 2"):
        s(X, Y, dy=2)
    with pytest.raises(ValueError, match="derivative orders must be >= 0"):
        s.ev(1.0, 1.0, dx=-1)
    with pytest.raises(ValueError, match="derivative order 5 of a B-spline of degree 3"):
        s.ev(1.0, 1.0, dx=5)
    with pytest.raises(ValueError, match="derivative order"):
        s.ev(1.0, 1.0, dx=10**30)
    with pytest.raises(ValueError):
        s.ev([1.0, 2.0], [1.0, 2.0, 3.0])  # shapes that do not broadcast
    with pytest.raises(TypeError):
        s.ev(1.0, 1.0, dx=0.5)
    with pytest.raises(TypeError):
        s.integral("a", 1, 2, 3)
    assert np.isnan(s.ev(np.nan, 1.0))
    assert np.isnan(s.integral(np.nan, 1.0, 0.0, 1.0))
