"""geomkit.make_interp_spline against scipy.interpolate.make_interp_spline: knots, coefficients
and values for every degree 0..7, every bc_type form, y of several shapes with `axis`; the
errors (ValueError with SciPy's phrases, TypeError for wrong types)."""

import numpy as np
import pytest
import scipy.interpolate as si
from conftest import assert_near
from hypothesis import given
from hypothesis import strategies as st

import geomkit

RNG = np.random.default_rng(20261204)


def data(n, trailing=(), seed=0):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.2, 1.5, n))
    y = rng.normal(size=(n,) + trailing) * 3.0
    return x, y


def compare(x, y, k, *, rel=1e-10, **kw):
    """The spline of geomkit and SciPy's on the same arguments: t, c, k, extrapolate, axis
    and values (with derivatives) inside and beyond the data."""
    ours = geomkit.make_interp_spline(x, y, k=k, **kw)
    theirs = si.make_interp_spline(x, y, k=k, **kw)
    assert isinstance(ours, geomkit.BSpline)
    assert (ours.k, ours.extrapolate, ours.axis) == (theirs.k, theirs.extrapolate, theirs.axis)
    assert_near(ours.t, theirs.t, rel=1e-15, what="t")
    assert_near(ours.c, theirs.c, rel=rel, what="c")
    span = x[-1] - x[0]
    xx = np.linspace(x[0] - 0.3 * span, x[-1] + 0.3 * span, 201)
    for nu in range(min(k, 2) + 1):
        assert_near(ours(xx, nu), theirs(xx, nu), rel=rel * 10 ** nu, what=f"nu={nu}")
    return ours, theirs


@pytest.mark.parametrize("k", range(8))
@pytest.mark.parametrize("trailing", [(), (3,), (2, 2)])
def test_not_a_knot_every_degree(k, trailing):
    x, y = data(12, trailing, seed=k)
    ours, _ = compare(x, y, k)
    assert_near(ours(x), y, rel=1e-12, what="interpolates")
    compare(x, y, k, bc_type="not-a-knot")


@pytest.mark.parametrize("uniform", [False, True])
def test_long_cubic_not_a_knot(uniform):
    """From 2**16 points the default cubic is solved in the extended form and converted to
    SciPy's basis (crates/geomkit/src/bspline/scipy_cubic.rs): the same knots, the same
    coefficients to rounding, ends and seams included."""
    n = (1 << 16) + 11
    x, y = data(n, (3,), seed=5)
    if uniform:
        x = np.arange(n, dtype=np.float64) * 0.25 - 7.0
    ours, theirs = compare(x, y, 3, rel=1e-12)
    assert_near(ours(x), y, rel=1e-13, what="at the data")
    for part in (slice(0, 8), slice(n - 8, n), slice(n // 2 - 4, n // 2 + 4)):
        assert_near(ours.c[part], theirs.c[part], rel=1e-13, what=f"c[{part}]")


@pytest.mark.parametrize("bc", ["natural", "clamped", ("natural", "clamped"),
                                ("clamped", None), (None, "natural")])
def test_named_conditions_cubic(bc):
    if bc in (("clamped", None), (None, "natural")):
        # One condition for the two the cubic needs: SciPy's and geomkit's refusal alike.
        x, y = data(9)
        with pytest.raises(ValueError, match="The number of derivatives at boundaries"):
            geomkit.make_interp_spline(x, y, k=3, bc_type=bc)
        with pytest.raises(ValueError):
            si.make_interp_spline(x, y, k=3, bc_type=bc)
        return
    for trailing in [(), (2,), (2, 3)]:
        x, y = data(9, trailing, seed=3)
        compare(x, y, 3, bc_type=bc)


def derivative_conditions(k, trailing, seed):
    """k - 1 conditions split between the ends, orders 1.., values of one data point's shape."""
    rng = np.random.default_rng(seed)
    nl = k // 2
    nr = k - 1 - nl
    left = [(o, rng.normal(size=trailing)) for o in range(1, nl + 1)]
    right = [(o, rng.normal(size=trailing)) for o in range(1, nr + 1)]
    return (left or None, right or None)


@pytest.mark.parametrize("k", range(2, 8))
@pytest.mark.parametrize("trailing", [(), (3,)])
def test_derivative_conditions_every_degree(k, trailing):
    x, y = data(10, trailing, seed=10 + k)
    compare(x, y, k, rel=1e-9, bc_type=derivative_conditions(k, trailing, k))


def test_derivative_conditions_scalar_values():
    x, y = data(8, (2,), seed=4)
    # A scalar value for all coordinates (SciPy wants one per coordinate).
    ours = geomkit.make_interp_spline(x, y, k=3, bc_type=([(1, 0.5)], [(2, 0.0)]))
    theirs = si.make_interp_spline(
        x, y, k=3, bc_type=([(1, np.full(2, 0.5))], [(2, np.zeros(2))]))
    assert_near(ours.c, theirs.c)
    # Two conditions per end of a quintic, vector values.
    compare(x, y, 5, rel=1e-9, bc_type=([(1, [1.0, -1.0]), (2, [0.0, 0.5])],
                                        [(1, [0.0, 0.0]), (2, [1.0, 1.0])]))


@pytest.mark.parametrize("k", range(2, 8))
@pytest.mark.parametrize("trailing", [(), (2,)])
def test_periodic_every_degree(k, trailing):
    n = 14
    x = np.linspace(0.0, 2.0 * np.pi, n) + np.r_[0, RNG.uniform(-0.05, 0.05, n - 2), 0]
    y = np.cos(x) if not trailing else np.c_[np.cos(x), np.sin(2 * x)]
    y[-1] = y[0]
    ours, theirs = compare(x, y, k, bc_type="periodic")
    assert ours.extrapolate == "periodic"
    xx = np.linspace(-10, 10, 101)
    assert_near(ours(xx), theirs(xx), rel=1e-10, what="periodic extrapolation")


@pytest.mark.parametrize("k", [0, 1])
def test_periodic_low_degree_extrapolates(k):
    """SciPy's k = 0 and k = 1 interpolants (its special cases) take extrapolate=True even
    with bc_type='periodic'; geomkit's the same (compare checks the attribute)."""
    x = np.linspace(0.0, 2.0 * np.pi, 9)
    y = np.cos(x)
    y[-1] = y[0]
    ours, _ = compare(x, y, k, bc_type="periodic")
    assert ours.extrapolate is True


@pytest.mark.parametrize("axis", [0, 1, 2, -1, -2])
def test_axis(axis):
    rng = np.random.default_rng(7)
    shape = [3, 4, 2]
    n = 9
    shape[axis] = n
    y = rng.normal(size=shape)
    x = np.sort(rng.uniform(0, 5, n))
    for k, bc in [(3, None), (3, "natural"), (5, None), (1, None), (0, None)]:
        ours, theirs = compare(x, y, k, bc_type=bc, axis=axis)
        xs = np.array([[0.5, 1.5], [2.5, 6.0]])
        assert_near(ours(xs), theirs(xs), what="2-D points with axis")
        assert ours(xs).shape == theirs(xs).shape


def test_given_knots():
    x, y = data(10, (2,), seed=5)
    for k in (2, 3, 4):
        t = si.make_interp_spline(x, y, k=k).t
        compare(x, y, k, t=t)
    # Knots with derivative conditions: SciPy's augmented knots for the cubic.
    t = np.r_[[x[0]] * 3, x, [x[-1]] * 3]
    compare(x, y, 3, t=t, bc_type="natural")


def test_input_layouts_are_converted_once():
    x, y = data(11, (3,), seed=6)
    base = geomkit.make_interp_spline(x, y)
    yf = np.asfortranarray(y)
    xs = np.repeat(x, 2)[::2]  # not contiguous
    assert not xs.flags.c_contiguous and yf.flags.f_contiguous
    other = geomkit.make_interp_spline(xs, yf)
    assert np.array_equal(base.c, other.c)
    # Integer, float32 and list inputs.
    xi = np.arange(8)
    ints = geomkit.make_interp_spline(xi, xi**2)
    assert_near(ints.c, si.make_interp_spline(xi, xi**2).c)
    lists = geomkit.make_interp_spline(list(range(8)), [float(v) ** 2 for v in range(8)])
    assert np.array_equal(lists.c, ints.c)
    f32 = geomkit.make_interp_spline(x.astype(np.float32), y.astype(np.float32))
    assert_near(f32.c, si.make_interp_spline(x.astype(np.float32), y.astype(np.float32)).c)


@given(st.integers(1, 5), st.integers(8, 30), st.integers(0, 2**32 - 1))
def test_random_data_match_scipy(k, n, seed):
    x, y = data(n, (2,), seed=seed)
    compare(x, y, k, rel=1e-8)


# --- errors -------------------------------------------------------------------------------
@pytest.mark.parametrize("args, kwargs, match", [
    (([0, 1, 1, 2], [1, 2, 3, 4]), {}, "Expect x to not have duplicates"),
    (([0, 2, 1, 3], [1, 2, 3, 4]), {}, "Expect x to be a 1D strictly increasing sequence"),
    (([0, 1, 2, 3], [1, 2, 3]), {}, "Shapes of x"),
    (([[0, 1], [2, 3]], [1, 2]), {}, "Expect x to be a 1D strictly increasing sequence"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": "periodic"},
     "First and last points does not match while periodic case expected"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([(1, 0)], [(1, 0), (2, 0)])},
     "The number of derivatives at boundaries does not match"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([(6, 0)], [(1, 0)])}, "at 0"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([(1, 0)], [(-6, 0)])},
     "Bad boundary conditions at 5"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": "typo"}, "Unknown boundary condition"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": 5}, "Unknown boundary condition"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([1, 2], None)},
     "Derivatives, `bc_type`, should be specified as a pair"),
    ((np.arange(6), np.arange(6.0)), {"k": -1}, "Expect non-negative k"),
    ((np.arange(6), np.arange(6.0)), {"k": 8}, "degree 8 is not supported"),
    ((np.arange(6), np.arange(6.0)), {"k": 0, "bc_type": "natural"}, "Too much info for k=0"),
    ((np.arange(6), np.arange(6.0)), {"bc_type": "periodic", "t": np.arange(10.0)},
     "periodic"),
    ((np.arange(6.0), np.arange(6.0)), {"t": np.arange(5.0)}, "knots"),
    (([0.0, np.nan, 2, 3, 4], np.arange(5.0)), {}, "not a finite number"),
    ((np.arange(5.0), [0, 1, np.inf, 3, 4]), {}, "not a finite number"),
    (([], []), {}, "too few data points: got 0"),
    (([0.0], [1.0]), {}, "too few data points: got 1"),
    ((np.arange(5.0), 1.0), {}, "axis 0 is out of bounds"),  # NumPy's AxisError
    ((np.arange(5.0), np.zeros((5, 0))), {}, "no coordinates"),
])
def test_bad_values_are_value_errors(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        geomkit.make_interp_spline(*args, **kwargs)


@pytest.mark.parametrize("args, kwargs", [
    ((np.arange(6), np.arange(6.0)), {"k": 2.5}),
    ((np.arange(6), np.arange(6.0)), {"k": "3"}),
    ((np.arange(6), np.arange(6.0) + 1j), {}),
    ((np.arange(6), ["a", "b", "c", "d", "e", "f"]), {}),
    ((np.arange(6), [object()] * 6), {}),
    ((np.arange(6), np.arange(6.0)), {"axis": 0.5}),
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([(1.5, 0)], [(1, 0)])}),
    # SciPy 1.17 refuses float orders too (a TypeError in its basis evaluation).
    ((np.arange(6), np.arange(6.0)), {"bc_type": ([(1.0, 0)], [(1, 0)])}),
])
def test_wrong_types_are_type_errors(args, kwargs):
    with pytest.raises(TypeError):
        geomkit.make_interp_spline(*args, **kwargs)


def test_huge_degree_is_a_value_error_not_an_overflow():
    with pytest.raises(ValueError, match="not supported"):
        geomkit.make_interp_spline(np.arange(6), np.arange(6.0), k=10**30)


# --- tiles (tile=T: geomkit.bspline::make_interp_spline_tiled) ------------------------------
TILE = 256


def compare_tiled(x, y, k, *, tile=TILE, rel=1e-11, bc_type=None, axis=0):
    """geomkit's tiled spline against SciPy's make_interp_spline on the same data: SciPy's
    knots bit for bit, coefficients and values (with two derivatives) within `rel` of the
    data's scale. Returns (tiled, SciPy's)."""
    ours = geomkit.make_interp_spline(x, y, k=k, bc_type=bc_type, axis=axis, tile=tile)
    theirs = si.make_interp_spline(x, y, k=k, bc_type=bc_type, axis=axis)
    assert (ours.k, ours.extrapolate, ours.axis) == (theirs.k, theirs.extrapolate, theirs.axis)
    assert np.array_equal(ours.t, theirs.t), "t"
    assert_near(ours.c, theirs.c, rel=rel, what="c")
    xx = np.linspace(x[0], x[-1], 2001)
    for nu in range(min(k, 2) + 1):
        assert_near(ours(xx, nu), theirs(xx, nu), rel=rel * 10 ** nu, what=f"nu={nu}")
    return ours, theirs


@pytest.mark.parametrize("k", range(1, 8))
@pytest.mark.parametrize("trailing", [(), (3,)])
def test_tiles_not_a_knot_every_degree(k, trailing):
    """N = 1337 points in tiles of 256 coefficients: six tiles, five seams, on uneven x;
    even degrees (knots at the midpoints) as odd ones."""
    x, y = data(1337, trailing, seed=100 + k)
    ours, theirs = compare_tiled(x, y, k)
    assert_near(ours(x), y, rel=1e-11, what="interpolates")
    # The untiled solve agrees as closely (both against SciPy above; here with each other).
    assert_near(ours.c, geomkit.make_interp_spline(x, y, k=k).c, rel=1e-12, what="untiled")


@pytest.mark.parametrize("k, bc", [
    (3, "natural"),
    (3, "clamped"),
    (3, ("natural", "clamped")),
    (1, None),
    (5, ([(1, 0.5), (2, -1.0)], [(1, 0.0), (2, 2.0)])),
    (3, ([(1, 0.5)], [(2, -1.0)])),
    (7, ([(1, 1.0), (2, 0.0), (3, 0.0)], [(1, -1.0), (2, 0.0), (3, 0.5)])),
])
@pytest.mark.parametrize("trailing", [(), (3,)])
def test_tiles_derivative_conditions_odd_degrees(k, bc, trailing):
    """The k - 1 conditions split evenly between the ends (piled at one end, the solution
    of a long system grows like a power of N, in SciPy as in geomkit: not for tiles)."""
    x, y = data(1200, trailing, seed=7 * k)
    if isinstance(bc, tuple) and trailing and not isinstance(bc[0], str):
        bc = tuple([(o, np.full(trailing, v)) for o, v in side] for side in bc)
    compare_tiled(x, y, k, bc_type=bc)


def test_tiles_uniform_x_axis_and_tile_sizes():
    """Uniform x (SciPy's x = arange), y with the interpolation axis in the middle, tiles
    from 2 points (each tile a halo of 64 rows around 2 coefficients) to more than N (one
    tile)."""
    rng = np.random.default_rng(31)
    n = 700
    x = np.arange(n, dtype=float) * 0.5 - 3.0
    y = rng.normal(size=(2, n, 2))
    for tile in (2, 97, 300, 10**6, 10**30):
        compare_tiled(x, y, 5, tile=tile, axis=1)
    compare_tiled(x, y, 4, tile=150, axis=1)


@pytest.mark.parametrize("k, kw", [
    # even degrees with derivative ends: knots at the data, no decay
    (4, {"bc_type": ([(1, np.zeros(2)), (2, np.ones(2))], [(1, np.zeros(2))])}),
    (2, {"bc_type": ([(1, np.ones(2))], None)}),
    (5, {"bc_type": "periodic"}),         # periodic ends couple the whole curve
    (0, {}),                              # step function: nothing to solve
])
def test_tiles_fall_back_to_the_whole_solve(k, kw):
    """Where the library's tiler does not apply (its documentation: periodic ends, given
    knots, degree 0, even degrees with derivative conditions) the whole system is solved:
    still SciPy's spline."""
    x, y = data(900, (2,), seed=k + 40)
    if isinstance(kw.get("bc_type"), str):
        y[-1] = y[0]
    ours = geomkit.make_interp_spline(x, y, k=k, tile=128, **kw)
    theirs = si.make_interp_spline(x, y, k=k, **kw)
    assert ours.extrapolate == theirs.extrapolate
    assert_near(ours.t, theirs.t, rel=1e-15, what="t")
    assert_near(ours.c, theirs.c, rel=1e-10, what="c")
    # Given knots: SciPy's own.
    t = si.make_interp_spline(x, y, k=3).t
    assert_near(geomkit.make_interp_spline(x, y, k=3, t=t, tile=100).c,
                si.make_interp_spline(x, y, k=3, t=t).c, rel=1e-10, what="given t")


@pytest.mark.parametrize("tile, error, match", [
    (0, ValueError, "tile must be at least 2 points \\(got 0\\)"),
    (1, ValueError, "tile must be at least 2 points \\(got 1\\)"),
    (-64, ValueError, "tile must be at least 2"),
    (2.5, TypeError, "tile must be an integer"),
    (256.0, TypeError, "tile must be an integer"),
    ("256", TypeError, "tile must be an integer"),
    (True, TypeError, "tile must be an integer"),
    (np.float64(8), TypeError, "tile must be an integer"),
])
def test_bad_tiles(tile, error, match):
    x, y = data(50)
    with pytest.raises(error, match=match):
        geomkit.make_interp_spline(x, y, tile=tile)
    # NumPy integers are integers.
    assert np.array_equal(geomkit.make_interp_spline(x, y, tile=np.int64(16)).t,
                          si.make_interp_spline(x, y).t)


def test_tile_is_keyword_only_and_data_errors_keep_their_words():
    x, y = data(50)
    with pytest.raises(TypeError):
        geomkit.make_interp_spline(x, y, 3, None, None, 0, True, 16)  # type: ignore[misc]
    with pytest.raises(ValueError, match="Expect x to not have duplicates"):
        geomkit.make_interp_spline([0, 1, 1, 2, 3], np.arange(5.0), k=1, tile=2)
    with pytest.raises(ValueError, match="not a finite number"):
        geomkit.make_interp_spline(x, np.r_[y[:-1], np.nan], tile=8)
    with pytest.raises(ValueError, match="The number of derivatives at boundaries"):
        geomkit.make_interp_spline(x, y, k=5, bc_type="natural", tile=8)


def test_docstring_examples_of_the_builders_run():
    """The examples of make_interp_spline and make_interp_surface (tiles included)."""
    import doctest

    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner()
    attempted = 0
    for f in (geomkit.make_interp_spline, geomkit.make_interp_surface, geomkit.make_splprep):
        for test in finder.find(f, f.__name__, globs={}):
            result = runner.run(test)
            assert result.failed == 0, f.__name__
            attempted += result.attempted
    assert attempted >= 15
