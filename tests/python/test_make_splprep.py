"""geomkit.make_splprep against scipy.interpolate.make_splprep (s = 0): the parameters u, the
knots, coefficients and values for 2-D and 3-D points and degrees 1..5, given u, ub/ue; the
boundary conditions (which SciPy's make_splprep ignores at s = 0) against
scipy.interpolate.make_interp_spline on SciPy's u; geomkit's param keyword against NumPy; the
refusals."""

import numpy as np
import pytest
import scipy.interpolate as si
from conftest import assert_near

import geomkit


def points(m, ndim, seed=0):
    rng = np.random.default_rng(seed)
    return [rng.normal(size=m) * 3.0 for _ in range(ndim)]


def closed_curve(m, ndim):
    phi = np.linspace(0.0, 2.0 * np.pi, m)
    xs = [np.cos(phi) * 2.0, np.sin(phi) + 0.3 * np.cos(2 * phi), 0.5 * np.sin(3 * phi)]
    xs = [xj.copy() for xj in xs[:ndim]]
    for xj in xs:
        xj[-1] = xj[0]  # exactly closed
    return xs


def same_spline(ours, theirs, u, *, rel=1e-12):
    """t equal, c and values (with derivatives, inside and beyond [u0, u1]) within rel."""
    assert isinstance(ours, geomkit.BSpline)
    assert (ours.k, ours.axis) == (theirs.k, theirs.axis)
    assert ours.extrapolate == theirs.extrapolate
    assert np.array_equal(ours.t, theirs.t), "t"
    assert_near(ours.c, theirs.c, rel=rel, what="c")
    uu = np.linspace(u[0] - 0.2, u[-1] + 0.2, 157)
    for nu in range(min(ours.k, 2) + 1):
        assert_near(ours(uu, nu), theirs(uu, nu), rel=rel * 10 ** nu, what=f"nu={nu}")


@pytest.mark.parametrize("ndim", [2, 3])
@pytest.mark.parametrize("k", [1, 2, 3, 4, 5])
def test_default_u_as_scipy(k, ndim):
    x = points(17, ndim, seed=k + 10 * ndim)
    ours, u = geomkit.make_splprep(x, k=k)
    theirs, su = si.make_splprep(x, k=k)
    assert np.array_equal(u, su), "u: SciPy's chord length, the same bits"
    assert ours.c.shape == (17, ndim)
    same_spline(ours, theirs, u)
    assert_near(ours(u), np.asarray(x), rel=1e-12, what="interpolates")


@pytest.mark.parametrize("k", [1, 3, 5])
def test_2d_array_input_as_scipy(k):
    x = np.asarray(points(11, 3, seed=k))
    ours, u = geomkit.make_splprep(x, k=k)
    theirs, su = si.make_splprep(x, k=k)
    assert np.array_equal(u, su)
    same_spline(ours, theirs, u)


@pytest.mark.parametrize("ndim", [2, 3])
@pytest.mark.parametrize("k", [1, 2, 3, 4, 5])
def test_given_u_as_scipy(k, ndim):
    x = points(12, ndim, seed=k)
    given = np.cumsum(np.random.default_rng(k).uniform(0.1, 2.0, 12)) - 3.0
    ours, u = geomkit.make_splprep(x, u=given, k=k)
    theirs, su = si.make_splprep(x, u=given, k=k)
    assert np.array_equal(u, given)
    same_spline(ours, theirs, given)


def test_ub_ue_as_scipy():
    """At s = 0 SciPy's ub, ue do not change the spline; geomkit's neither (and checks them)."""
    x = points(10, 2, seed=3)
    ours, u = geomkit.make_splprep(x, ub=-0.5, ue=1.5)
    theirs, su = si.make_splprep(x, ub=-0.5, ue=1.5)
    assert np.array_equal(u, su)
    same_spline(ours, theirs, u)
    ours, u = geomkit.make_splprep(x, ub=0.0, ue=1.0)
    same_spline(ours, theirs, u)
    with pytest.raises(ValueError, match="ub"):
        geomkit.make_splprep(x, ub=0.25)
    with pytest.raises(ValueError, match="ue"):
        geomkit.make_splprep(x, ue=0.75)


@pytest.mark.parametrize("bc_type", [None, "not-a-knot"])
def test_bc_not_a_knot_as_make_splprep(bc_type):
    x = points(9, 3, seed=7)
    ours, u = geomkit.make_splprep(x, bc_type=bc_type)
    theirs, su = si.make_splprep(x, bc_type=bc_type)
    same_spline(ours, theirs, u)


@pytest.mark.parametrize("ndim", [2, 3])
@pytest.mark.parametrize("k", [1, 2, 3, 4, 5])
def test_periodic_closed_curve(k, ndim):
    """SciPy 1.17's make_splprep accepts 'periodic' but builds a not-a-knot spline at s = 0;
    geomkit's is SciPy's make_interp_spline(u, x.T, bc_type='periodic', axis=1) on SciPy's u."""
    x = closed_curve(15, ndim)
    ours, u = geomkit.make_splprep(x, k=k, bc_type="periodic")
    _, su = si.make_splprep(x, k=k, bc_type="periodic")
    assert np.array_equal(u, su)
    theirs = si.make_interp_spline(su, np.asarray(x), k=k, bc_type="periodic", axis=1)
    same_spline(ours, theirs, u)
    # periodic: values and derivatives up to k - 1 equal at the two ends
    for nu in range(k):
        assert_near(ours(u[-1], nu), ours(u[0], nu), rel=1e-9, what=f"ends nu={nu}")


@pytest.mark.parametrize("bc_type", [
    "natural", "clamped", ([(1, [1.0, -2.0, 0.5])], [(2, [0.0, 0.0, 0.0])]),
])
def test_derivative_ends_as_make_interp_spline(bc_type):
    x = points(13, 3, seed=5)
    ours, u = geomkit.make_splprep(x, k=3, bc_type=bc_type)
    _, su = si.make_splprep(x, k=3)
    theirs = si.make_interp_spline(su, np.asarray(x), k=3, bc_type=bc_type, axis=1)
    same_spline(ours, theirs, u)


def test_centripetal_and_uniform_u():
    x = points(20, 3, seed=11)
    ours, u = geomkit.make_splprep(x, param="centripetal")
    p = np.asarray(x).T
    d = np.sqrt(np.linalg.norm(np.diff(p, axis=0), axis=1))
    expected = np.concatenate([[0.0], np.cumsum(d)]) / np.sum(d)
    assert_near(u, expected, rel=1e-15, what="centripetal u")
    assert (u[0], u[-1]) == (0.0, 1.0)
    theirs, _ = si.make_splprep(x, u=u)
    same_spline(ours, theirs, u)
    ours, u = geomkit.make_splprep(x, param="uniform", k=5)
    assert_near(u, np.arange(20) / 19, rel=1e-15, what="uniform u")
    theirs, _ = si.make_splprep(x, u=u, k=5)
    same_spline(ours, theirs, u)


def test_refusals():
    x = points(8, 2)
    with pytest.raises(ValueError, match="smoothing"):
        geomkit.make_splprep(x, s=0.1)
    with pytest.raises(ValueError, match="smoothing"):
        geomkit.make_splprep(x, w=np.full(8, 2.0))
    with pytest.raises(ValueError, match="smoothing"):
        geomkit.make_splprep(x, nest=10)
    with pytest.raises(ValueError, match="interpolation only"):
        geomkit.make_splprep(x, t=np.r_[[0.0] * 4, [1.0] * 4])
    ours, _ = geomkit.make_splprep(x, w=np.ones(8))  # ones: the interpolant, accepted
    assert ours.c.shape == (8, 2)
    with pytest.raises(ValueError, match="equal lengths"):
        geomkit.make_splprep([np.arange(8.0), np.arange(7.0)])
    with pytest.raises(ValueError, match="not finite"):
        geomkit.make_splprep([np.r_[0.0, np.nan, 2, 3, 4], np.arange(5.0)])
    with pytest.raises(ValueError, match="strictly increasing"):  # a repeated point
        geomkit.make_splprep([np.r_[0.0, 1, 1, 2, 3], np.r_[0.0, 1, 1, 0, 2]])
    with pytest.raises(ValueError, match="coincide"):
        geomkit.make_splprep([np.ones(5), np.ones(5)])
    with pytest.raises(ValueError, match="shape"):
        geomkit.make_splprep(x, u=np.arange(7.0))
    with pytest.raises(ValueError, match="strictly increasing"):
        geomkit.make_splprep(x, u=np.r_[0.0, 1, np.nan, 3, 4, 5, 6, 7])
    with pytest.raises(ValueError, match="not both"):
        geomkit.make_splprep(x, u=np.arange(8.0), param="uniform")
    with pytest.raises(ValueError, match="param"):
        geomkit.make_splprep(x, param="foley")  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        geomkit.make_splprep(closed_curve(9, 2)[:1] + [np.arange(9.0)], bc_type="periodic")
    with pytest.raises(TypeError):
        geomkit.make_splprep(3.0)  # type: ignore[arg-type]


def test_docstring_example_runs():
    import doctest

    runner = doctest.DocTestRunner()
    for test in doctest.DocTestFinder().find(geomkit.make_splprep, "make_splprep", globs={}):
        runner.run(test)
    assert runner.tries >= 4 and runner.failures == 0


@pytest.mark.parametrize("k", [3, 4, 5])
@pytest.mark.parametrize("param", ["chord", "centripetal"])
def test_tiles_as_scipy(k, param):
    """tile=T (make_interp_spline's tiles): 1100 points of a 3-D curve in tiles of 200
    coefficients (six tiles), against SciPy's make_interp_spline on the same parameters
    (SciPy's make_splprep for chord lengths): the same knots, coefficients and values
    within rounding of the data's scale."""
    phi = np.linspace(0.0, 12.0 * np.pi, 1100)
    x = [np.cos(phi) * (2 + 0.1 * phi), np.sin(phi), 0.05 * phi + 0.2 * np.sin(3 * phi)]
    ours, u = geomkit.make_splprep(x, k=k, param=param, tile=200)
    whole, uw = geomkit.make_splprep(x, k=k, param=param)
    assert np.array_equal(u, uw)
    if param == "chord":
        theirs, su = si.make_splprep(x, k=k)
        assert np.array_equal(u, su)
    else:
        theirs = si.make_interp_spline(u, np.asarray(x), k=k, axis=1)
    assert np.array_equal(ours.t, theirs.t)
    assert_near(ours.c, theirs.c, rel=1e-11, what="c")
    uu = np.linspace(0.0, 1.0, 3001)
    assert_near(ours(uu), theirs(uu), rel=1e-11, what="values")
    assert_near(ours(u), np.asarray(x), rel=1e-11, what="interpolates")
    assert_near(ours.c, whole.c, rel=1e-12, what="untiled")


def test_tiles_periodic_and_refusals():
    """Periodic ends are solved whole (the library's tiler refuses them): SciPy's periodic
    interpolant on the same parameters; bad tiles as make_interp_spline's."""
    x = closed_curve(400, 2)
    ours, u = geomkit.make_splprep(x, k=5, bc_type="periodic", tile=64)
    theirs = si.make_interp_spline(u, np.asarray(x).T, k=5, bc_type="periodic")
    assert np.array_equal(ours.t, theirs.t)
    assert_near(ours.c, theirs.c, rel=1e-10, what="c")
    with pytest.raises(ValueError, match=r"tile must be at least 2 points \(got 1\)"):
        geomkit.make_splprep(x, tile=1)
    with pytest.raises(TypeError, match="tile must be an integer"):
        geomkit.make_splprep(x, tile=64.0)
