"""geomkit.BSpline against scipy.interpolate.BSpline on the same knots and coefficients:
evaluation (any x shape, nu, the three extrapolation modes, axis), derivative,
antiderivative, integrate, insert_knot, the conversions, pickling, threads, bad input."""

import pickle
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import scipy.interpolate as si
from conftest import assert_near
from hypothesis import given
from hypothesis import strategies as st

import geomkit


def random_spline(k, trailing=(), n=None, seed=0, clamped=True):
    """SciPy's BSpline of degree k on random distinct inner knots (clamped ends or not)."""
    rng = np.random.default_rng(seed)
    n = n or k + 6
    if clamped:
        inner = np.sort(rng.uniform(0.5, 9.5, n - k - 1))
        t = np.r_[[0.0] * (k + 1), inner, [10.0] * (k + 1)]
    else:
        t = np.sort(rng.uniform(0, 10, n + k + 1))
    c = rng.normal(size=(n,) + trailing)
    return t, c


def both(t, c, k, **kw):
    return geomkit.BSpline(t, c, k, **kw), si.BSpline(t, c, k, **kw)


POINTS = np.r_[np.linspace(-3, 13, 161), [0.0, 10.0, np.nan]]


@pytest.mark.parametrize("k", range(8))
@pytest.mark.parametrize("clamped", [True, False])
@pytest.mark.parametrize("extrapolate", [True, False, "periodic"])
def test_evaluation_every_degree_order_and_mode(k, clamped, extrapolate):
    t, c = random_spline(k, (2,), seed=k, clamped=clamped)
    ours, theirs = both(t, c, k, extrapolate=extrapolate)
    for nu in range(k + 3):
        assert_near(ours(POINTS, nu), theirs(POINTS, nu), rel=1e-11 * 10**nu,
                    what=f"k={k} nu={nu}")
    # The mode given per call overrides the spline's.
    for mode in (True, False, "periodic"):
        assert_near(ours(POINTS, 0, mode), theirs(POINTS, 0, mode), rel=1e-11, what=str(mode))


@pytest.mark.parametrize("x", [2.5, np.float64(7.0), [], [[1.0, 2.0], [3.0, 11.0]],
                               np.linspace(0, 10, 24).reshape(2, 3, 4)])
@pytest.mark.parametrize("trailing", [(), (3,), (2, 2)])
def test_result_shapes(x, trailing):
    t, c = random_spline(3, trailing, seed=1)
    ours, theirs = both(t, c, 3)
    got, want = ours(x), theirs(x)
    assert isinstance(got, np.ndarray) and got.shape == want.shape
    assert_near(got, want)


@pytest.mark.parametrize("axis", [0, 1, 2, -1])
def test_axis(axis):
    rng = np.random.default_rng(3)
    k, n = 3, 9
    shape = [2, 3, 4]
    shape[axis] = n
    c = rng.normal(size=shape)
    t = np.r_[[0.0] * 4, np.sort(rng.uniform(1, 9, n - 4)), [10.0] * 4]
    ours, theirs = both(t, c, k, axis=axis)
    assert ours.axis == theirs.axis and ours.c.shape == theirs.c.shape
    x = np.array([[0.5, 3.0, 9.5], [1.0, 2.0, 12.0]])
    assert_near(ours(x), theirs(x))
    assert_near(ours(x, 2), theirs(x, 2))
    assert_near(ours.integrate(1, 8), theirs.integrate(1, 8))


@pytest.mark.parametrize("k", range(8))
def test_derivative_and_antiderivative(k):
    t, c = random_spline(k, (2,), seed=20 + k)
    ours, theirs = both(t, c, k, extrapolate="periodic")
    for nu in range(k + 1):
        d, e = ours.derivative(nu), theirs.derivative(nu)
        assert d.k == e.k and d.extrapolate == e.extrapolate and d.axis == e.axis
        assert_near(d.t, e.t, rel=0, what="derivative knots")
        assert_near(d.c, e.c, rel=1e-11 * 10**nu, what=f"derivative c, nu={nu}")
        assert_near(d(POINTS), e(POINTS), rel=1e-10 * 10**nu, what=f"derivative nu={nu}")
    for nu in (1, 2):
        a, b = ours.antiderivative(nu), theirs.antiderivative(nu)
        assert a.k == b.k and a.extrapolate == b.extrapolate is False
        assert_near(a.t, b.t, rel=0, what="antiderivative knots")
        assert_near(a.c, b.c, rel=1e-12, what=f"antiderivative c, nu={nu}")
        assert_near(a(POINTS), b(POINTS), rel=1e-11, what=f"antiderivative nu={nu}")
    # Negative orders swap the two (SciPy's splder / splantider).
    assert_near(ours.derivative(-1).c, theirs.derivative(-1).c, rel=1e-12)
    if k >= 1:
        assert_near(ours.antiderivative(-1).c, theirs.antiderivative(-1).c, rel=1e-11)


def test_derivative_errors():
    t, c = random_spline(3, seed=2)
    with pytest.raises(ValueError, match="derivative order 4 of a B-spline of degree 3"):
        geomkit.BSpline(t, c, 3).derivative(4)
    with pytest.raises(ValueError, match="derivative order 10 of a B-spline of degree 3"):
        geomkit.BSpline(t, c, 3).derivative(10)
    with pytest.raises(ValueError, match="derivative order"):
        geomkit.BSpline(t, c, 3).derivative(10**30)
    with pytest.raises(ValueError, match="degree"):
        geomkit.BSpline(t, c, 3).antiderivative(10**30)
    # An interior knot of multiplicity k: the derivative of order 2 jumps there, so the
    # third one would hold a Dirac delta.
    t2 = np.r_[[0.0] * 4, 5.0, 5.0, 5.0, [10.0] * 4]
    with pytest.raises(ValueError, match="not differentiable"):
        geomkit.BSpline(t2, np.arange(7.0), 3).derivative(3)
    with pytest.raises(ValueError, match="not differentiable"):
        si.BSpline(t2, np.arange(7.0), 3).derivative(3)
    with pytest.raises(ValueError, match="degree"):
        geomkit.BSpline(t, c, 3).antiderivative(13)


@pytest.mark.parametrize("k", [0, 1, 3, 5])
@pytest.mark.parametrize("extrapolate", [True, False, "periodic"])
def test_integrate(k, extrapolate):
    t, c = random_spline(k, seed=30 + k)
    ours, theirs = both(t, c, k, extrapolate=extrapolate)
    for a, b in [(0, 10), (2.5, 7.25), (7.25, 2.5), (-4, 3), (-25, 31), (12, 15), (-3, -1),
                 (4, 4)]:
        got, want = ours.integrate(a, b), theirs.integrate(a, b)
        assert isinstance(got, np.ndarray) and got.shape == want.shape == ()
        assert_near(got, want, rel=1e-11, what=f"[{a}, {b}] {extrapolate}")
    t, c = random_spline(k, (3,), seed=40 + k)
    ours, theirs = both(t, c, k, extrapolate=extrapolate)
    for a, b in [(0, 10), (2.5, 7.25), (-25, 31), (8, -2)]:
        assert_near(ours.integrate(a, b), theirs.integrate(a, b), rel=1e-11)


def test_integrate_outside_the_base_interval_without_extrapolation():
    t, c = random_spline(3, (2,), seed=3)
    ours, theirs = both(t, c, 3, extrapolate=False)
    # SciPy: 0 for 1-D coefficients (FITPACK's splint), NaN for n-D ones; geomkit: 0.
    assert np.array_equal(ours.integrate(12, 15), [0.0, 0.0])
    assert np.isnan(theirs.integrate(12, 15)).all()
    assert float(geomkit.BSpline(t, c[:, 0], 3, extrapolate=False).integrate(12, 15)) == \
        float(si.BSpline(t, c[:, 0], 3, extrapolate=False).integrate(12, 15)) == 0.0


@pytest.mark.parametrize("k", [1, 2, 3, 5])
def test_insert_knot(k):
    t, c = random_spline(k, (2,), seed=50 + k, n=k + 8)
    ours, theirs = both(t, c, k)
    for x, m in [(4.2, 1), (4.2, 2), (float(t[k + 2]), 1), (0.0, 1), (10.0, 1)]:
        a, b = ours.insert_knot(x, m), theirs.insert_knot(x, m)
        assert_near(a.t, b.t, rel=0, what="knots")
        assert_near(a.c, b.c, rel=1e-12, what=f"c after insert {x} x{m}")
        inside = POINTS[(POINTS >= 0) & (POINTS < 10)]
        assert_near(a(inside), b(inside), rel=1e-11)


def test_insert_knot_periodic():
    x = np.linspace(0, 2 * np.pi, 12)
    y = np.c_[np.cos(x), np.sin(x)]
    ours = geomkit.make_interp_spline(x, y, k=3, bc_type="periodic")
    theirs = si.make_interp_spline(x, y, k=3, bc_type="periodic")
    for at in (0.3, 3.0, 6.0):
        a, b = ours.insert_knot(at), theirs.insert_knot(at)
        assert a.extrapolate == "periodic"
        assert_near(a.t, b.t, rel=1e-15)
        assert_near(a.c, b.c, rel=1e-12)
        assert_near(a(POINTS), b(POINTS), rel=1e-11)


def test_insert_knot_errors():
    t, c = random_spline(3, seed=4)
    b = geomkit.BSpline(t, c, 3)
    with pytest.raises(ValueError, match="cannot insert a knot at 11"):
        b.insert_knot(11.0)
    with pytest.raises(ValueError, match="`m` must be positive"):
        b.insert_knot(5.0, 0)
    with pytest.raises(ValueError):
        b.insert_knot(np.nan)
    with pytest.raises(ValueError, match="at most"):  # not an OverflowError, nor a hang
        b.insert_knot(5.0, 10**30)
    with pytest.raises(TypeError):
        b.insert_knot(5.0, 1.5)


def test_to_and_from_scipy():
    t, c = random_spline(4, (2, 3), seed=5)
    c = np.moveaxis(c, 0, 1)  # the interpolation axis second
    ours = geomkit.BSpline(t, c, 4, extrapolate="periodic", axis=1)
    spl = ours.to_scipy()
    assert isinstance(spl, si.BSpline)
    assert (spl.k, spl.extrapolate, spl.axis) == (4, "periodic", 1)
    assert np.array_equal(spl.t, ours.t) and np.array_equal(spl.c, ours.c)
    spl.c[0] = 0.0  # SciPy's arrays are its own copies
    assert not np.array_equal(spl.c, ours.c)
    back = geomkit.BSpline.from_scipy(si.BSpline(t, c, 4, extrapolate=False, axis=1))
    want = si.BSpline(t, c, 4, extrapolate=False, axis=1)
    assert (back.k, back.extrapolate, back.axis) == (4, False, 1)
    assert_near(back(POINTS), want(POINTS))
    # from a SciPy derivative, whose c is padded with zeros
    d = si.BSpline(t, c, 4, axis=1).derivative(2)
    assert_near(geomkit.BSpline.from_scipy(d)(POINTS), d(POINTS))


def test_pickle_round_trip_keeps_every_bit():
    x = np.linspace(0, 3, 11)
    t6, c6 = random_spline(3, (2, 2), seed=6)
    for spline in [
        geomkit.make_interp_spline(x, np.c_[np.sin(x), np.cos(x)], k=5),
        geomkit.make_interp_spline(x, np.cos(2 * np.pi * x / 3), k=4, bc_type="periodic"),
        geomkit.BSpline(t6, np.moveaxis(c6, 0, 2), 3, axis=2),
        geomkit.make_interp_spline(x, np.sin(x)).derivative(2),
    ]:
        back = pickle.loads(pickle.dumps(spline))
        assert type(back) is geomkit.BSpline
        assert (back.k, back.extrapolate, back.axis) == (spline.k, spline.extrapolate,
                                                           spline.axis)
        assert np.array_equal(back.t, spline.t) and np.array_equal(back.c, spline.c)
        assert np.array_equal(back(POINTS), spline(POINTS), equal_nan=True)
        # and against SciPy
        assert_near(back(POINTS), spline.to_scipy()(POINTS))


def test_eight_threads_give_the_bits_of_one():
    rng = np.random.default_rng(8)
    x = np.sort(rng.uniform(0, 100, 2000))
    spline = geomkit.make_interp_spline(x, rng.normal(size=(2000, 3)), k=5)
    points = [rng.uniform(-5, 105, 200_000) for _ in range(16)]
    one = [spline(p, nu) for nu, p in enumerate(points[:4])] + [spline(p) for p in points[4:]]
    with ThreadPoolExecutor(8) as pool:
        futures = [pool.submit(spline, p, nu) for nu, p in enumerate(points[:4])]
        futures += [pool.submit(spline, p) for p in points[4:]]
        many = [f.result() for f in futures]
    for a, b in zip(one, many):
        assert np.array_equal(a, b)
    assert_near(one[1], spline.to_scipy()(points[1], 1), rel=1e-9)


def test_arrays_are_read_only():
    b = geomkit.BSpline(*random_spline(3, seed=7), 3)
    with pytest.raises(ValueError, match="read-only"):
        b.c[0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        b.t[0] = 1.0
    with pytest.raises(AttributeError):
        b.t = np.arange(10.0)


def test_the_callers_arrays_are_not_kept():
    t, c = random_spline(3, (2,), seed=12)
    b = geomkit.BSpline(t, c, 3)
    assert t.flags.writeable and c.flags.writeable  # not frozen
    before = b(POINTS)
    t[5] += 0.1
    c[:] = 0.0
    assert np.array_equal(b(POINTS), before, equal_nan=True)
    assert not np.shares_memory(b.c, c) and not np.shares_memory(b.t, t)
    # Coefficients beyond the n used are kept (a copy), as SciPy keeps them.
    t, c = random_spline(3, n=8, seed=13)
    longer = np.r_[c, 7.0, 8.0]
    ours, theirs = both(t, longer, 3)
    assert np.array_equal(ours.c, theirs.c) and not np.shares_memory(ours.c, longer)
    assert_near(ours(POINTS), theirs(POINTS))
    assert_near(ours.derivative()(POINTS), theirs.derivative()(POINTS))


def test_repr():
    b = geomkit.BSpline(np.arange(9.0), np.arange(5.0), 3)
    assert repr(b) == ("BSpline(k=3, 9 knots on [3.0, 5.0], c of shape (5,), "
                       "extrapolate=True, axis=0)")


def test_input_layouts():
    t, c = random_spline(3, (3,), seed=9)
    want = si.BSpline(t, c, 3)
    cf = np.asfortranarray(c)
    ts = np.repeat(t, 2)[::2]
    xs = np.repeat(POINTS, 2)[::2]
    assert_near(geomkit.BSpline(ts, cf, 3)(xs), want(xs))
    assert_near(geomkit.BSpline(list(t), c.tolist(), 3)(list(POINTS)), want(POINTS))
    assert_near(geomkit.BSpline(t, c.astype(np.float32), 3)(POINTS.astype(np.float32)),
                si.BSpline(t, c.astype(np.float32), 3)(POINTS.astype(np.float32)))


@given(st.integers(0, 7), st.integers(0, 2**32 - 1), st.sampled_from([True, False, "periodic"]))
def test_random_splines_match_scipy(k, seed, extrapolate):
    t, c = random_spline(k, (2,), seed=seed, clamped=bool(seed % 2))
    ours, theirs = both(t, c, k, extrapolate=extrapolate)
    rng = np.random.default_rng(seed)
    x = rng.uniform(-5, 15, 50)
    nu = int(rng.integers(0, k + 2))
    assert_near(ours(x, nu), theirs(x, nu), rel=1e-9 * 10**nu)


# --- bad input ------------------------------------------------------------------------------
@pytest.mark.parametrize("args, kwargs, match", [
    ((np.arange(10.0), np.ones(6), -1), {}, "Spline order cannot be negative"),
    ((np.ones((2, 5)), np.ones(6), 3), {}, "Knot vector must be one-dimensional"),
    ((np.arange(6.0), np.ones(6), 3), {}, "Need at least 8 knots for degree 3"),
    ((np.arange(10.0), np.ones(5), 3), {}, "Knots, coefficients and degree are inconsistent"),
    ((np.arange(10.0)[::-1], np.ones(6), 3), {}, "non-decreasing"),
    ((np.r_[[0.0] * 9, 1.0], np.ones(6), 3), {}, "domain"),
    ((np.r_[np.arange(9.0), np.nan], np.ones(6), 3), {}, "not a finite number"),
    ((np.arange(10.0), np.r_[np.ones(5), np.inf], 3), {}, "not a finite number"),
    ((np.arange(10.0), 1.0, 3), {}, "axis 0 is out of bounds"),
    ((np.arange(10.0), np.ones(6), 3), {"axis": 1}, "axis 1 is out of bounds"),
    ((np.arange(10.0), np.ones(6), 3), {"extrapolate": "sideways"}, "extrapolate"),
    ((np.arange(40.0), np.ones(20), 19), {}, "degree"),
    ((np.arange(10.0), np.ones((6, 0)), 3), {}, "no coordinates"),
])
def test_bad_values_are_value_errors(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        geomkit.BSpline(*args, **kwargs)


@pytest.mark.parametrize("args", [
    (np.arange(10.0), np.ones(6), 3.0),
    (np.arange(10.0), np.ones(6) + 1j, 3),
    (np.arange(10.0), ["a"] * 6, 3),
    (np.arange(10.0).astype("datetime64[s]"), np.ones(6), 3),
    ("abcdefghij", np.ones(6), 3),
])
def test_wrong_types_are_type_errors(args):
    with pytest.raises(TypeError):
        geomkit.BSpline(*args)


def test_bad_calls():
    b = geomkit.BSpline(*random_spline(3, seed=10), 3)
    with pytest.raises(ValueError, match="Cannot do derivative order nu=-1"):
        b(1.0, -1)
    with pytest.raises(TypeError):
        b(1.0, 1.5)
    with pytest.raises(TypeError):
        b(["a", "b"])
    with pytest.raises(TypeError):
        b(1.0 + 2j)
    with pytest.raises(ValueError, match="extrapolate"):
        b(1.0, extrapolate="sideways")
    with pytest.raises(TypeError):
        b.integrate("a", 2)
    # Huge orders are 0 as in SciPy, not an overflow.
    assert np.array_equal(b([1.0, np.nan], 10**30), [0.0, 0.0])
    # NaN, empty and 0-d points.
    assert np.isnan(b(np.nan))
    assert b([]).shape == (0,) and b(np.empty((0, 3))).shape == (0, 3)
    assert b(np.float64(2.0)).shape == ()
    # An output NumPy cannot allocate is its MemoryError, not a crash.
    wide = geomkit.BSpline(np.arange(8.0), np.ones((4, 1 << 20)), 3)
    with pytest.raises(MemoryError):
        wide(np.broadcast_to(1.0, (1 << 30,)))
