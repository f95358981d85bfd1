"""geomkit.dask and geomkit.xarray (issue 24): chunked interpolation against SciPy on the
whole array in memory, computed by a real dask.distributed cluster (two worker processes).

The references are independent: SciPy's make_interp_spline (knots and coefficients along
each axis), SciPy's BSpline evaluation, RectBivariateSpline and xarray's own
interp(method="cubic") on the whole array; geomkit's in-memory solve only for the periodic
coefficients (where SciPy's are the same to rounding, checked too). Chunked = in memory
within 4 eps max|z| ("EPS4" below).
"""

from __future__ import annotations

import subprocess
import sys

import dask
import dask.array as da
import distributed
import numpy as np
import pytest
import scipy.interpolate as si
import xarray as xr
import zarr

import geomkit
import geomkit.dask as gd
import geomkit.xarray

EPS = np.finfo(float).eps
BCS = [None, "natural", "clamped", "periodic"]


def near(a, b, scale, ulps=4.0):
    """max|a - b| <= ulps * eps * scale (scale: max|z| of the data)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape, (a.shape, b.shape)
    err = float(np.max(np.abs(a - b))) if a.size else 0.0
    assert err <= ulps * EPS * scale, f"{err / (EPS * scale):.2f} eps max|z| (> {ulps})"


@pytest.fixture(scope="module")
def client():
    """A real cluster: two worker processes of one thread (what runs on a laptop or, with
    another address, on many machines)."""
    with distributed.LocalCluster(processes=True, n_workers=2, threads_per_worker=1,
                                  dashboard_address=None, memory_limit="1GiB") as cluster:
        with distributed.Client(cluster) as c:
            yield c


def dyadic_coordinates(rng, n):
    """Rectilinear coordinates with steps k/8 (k = 4..12): every difference of two
    coordinates is exact, so SciPy's periodic knots (steps added one by one) and geomkit's
    give the same bits and the comparison measures the solve alone."""
    return np.concatenate([[0.0], np.cumsum(rng.integers(4, 13, n - 1) / 8.0)])


def series(rng, n, bc, trailing=()):
    x = dyadic_coordinates(rng, n)
    y = np.sin(x / 3.0).reshape((n,) + (1,) * len(trailing)) * np.ones(trailing)
    y = y + 0.1 * rng.standard_normal((n,) + trailing)
    if bc == "periodic":
        y[-1] = y[0]
    return x, y


def reference_1d(x, y, bc):
    """SciPy's spline; for periodic ends also asserted against the periodic system solved in
    80-bit long double (`periodic_truth`), the in-memory cyclic solves of SciPy and geomkit
    being a few eps apart themselves."""
    ref = si.make_interp_spline(x, y, k=3, bc_type=bc)
    if bc == "periodic":
        near(ref.c, periodic_truth(ref.t, y.reshape(y.shape[0], -1)).reshape(ref.c.shape),
             np.abs(y).max(), ulps=8)
    return ref


def periodic_truth(t, y, dtype=float):
    """The periodic cubic interpolant's coefficients on SciPy's knots `t` in long double
    (Gaussian elimination with pivoting on the n - 1 cyclic collocation rows; the cubic
    B-splines at a simple knot by their closed form), returned as `dtype`."""
    L = np.longdouble
    t = np.asarray(t, dtype=L)
    m = y.shape[0] - 1
    a = np.zeros((m, m), dtype=L)
    for i in range(m):
        xi = t[i + 3]
        left = (t[i + 4] - xi) ** 2 / ((t[i + 4] - t[i + 2]) * (t[i + 4] - t[i + 1]))
        right = (xi - t[i + 2]) ** 2 / ((t[i + 4] - t[i + 2]) * (t[i + 5] - t[i + 2]))
        for j, v in ((i, left), (i + 1, 1 - left - right), (i + 2, right)):
            a[i, j % m] += v
    aug = np.concatenate([a, np.asarray(y[:m], dtype=L)], axis=1)
    for k in range(m):
        piv = k + int(np.argmax(np.abs(aug[k:, k])))
        aug[[k, piv]] = aug[[piv, k]]
        aug[k + 1:] -= np.outer(aug[k + 1:, k] / aug[k, k], aug[k])
    sol = np.zeros((m, y.shape[1]), dtype=L)
    for k in range(m - 1, -1, -1):
        sol[k] = (aug[k, m:] - aug[k, k + 1:m] @ sol[k + 1:]) / aug[k, k]
    return np.concatenate([sol, sol[:3]]).astype(dtype)


# -- 1-D series ------------------------------------------------------------------------------
@pytest.mark.parametrize("bc", BCS)
# Odd, smaller than the halo, larger, irregular with chunks of 1 and 2 points, and with
# empty chunks (at the ends too).
@pytest.mark.parametrize("chunk", [7, 20, 97, ((1, 5, 40, 3, 100, 2, 150),),
                                   ((0, 150, 0, 150, 1, 0),)])
def test_series_equals_global_solve(client, bc, chunk):
    rng = np.random.default_rng(24 + len(str(chunk)))
    x, y = series(rng, 301, bc)
    ref = reference_1d(x, y, bc)
    spline = gd.make_interp_spline(x, da.from_array(y, chunks=chunk), bc_type=bc)
    assert spline.depth == 32 and spline.bc_type == (((bc or "not-a-knot"),) * 2,)
    np.testing.assert_array_equal(spline.t[0], ref.t)  # SciPy's knots, bit for bit
    c = spline.c.compute()
    near(c, ref.c, np.abs(y).max(), ulps=8 if bc == "periodic" else 4)
    if bc == "periodic":
        near(c, periodic_truth(ref.t, y[:, None])[:, 0], np.abs(y).max())
    else:
        near(c, geomkit.make_interp_spline(x, y, k=3, bc_type=bc).c, np.abs(y).max())
    # The layout: n coefficients with the data's chunks (not-a-knot), n + 2 with one more in
    # the first and the last chunk (the others).
    chunks = da.from_array(y, chunks=chunk).chunks[0]
    if bc is None:
        assert spline.c.chunks[0] == chunks
    else:
        assert spline.c.chunks[0] == (chunks[0] + 1,) + chunks[1:-1] + (chunks[-1] + 1,)
    if bc == "periodic":
        np.testing.assert_array_equal(c[-3:], c[:3])
    # Finer and coarser, inside the data's range, against SciPy's evaluation.
    for m in (1201, 57):
        new = np.linspace(x[0], x[-1], m)
        near(spline(new, chunks=31).compute(), ref(new), np.abs(y).max())


def test_series_with_trailing_axes_and_axis(client):
    """A curve in R^3 chunked along its length, the length on axis 1."""
    rng = np.random.default_rng(7)
    x, y = series(rng, 500, "natural", trailing=(3,))
    y = np.ascontiguousarray(y.T)  # (3, 500)
    arr = da.from_array(y, chunks=(2, 45))
    spline = gd.make_interp_spline(x, arr, bc_type="natural", axis=1)
    ref = si.make_interp_spline(x, y, k=3, bc_type="natural", axis=1)
    assert spline.c.chunks[0] == (2, 1)  # the batch axis keeps its chunks
    near(spline.c.compute(), np.moveaxis(ref.c, 0, 1), np.abs(y).max())
    new = np.sort(rng.uniform(x[0], x[-1], 777))
    near(spline(new).compute(), ref(new), np.abs(y).max())


def test_series_regular_coordinates_resampled_2x(client):
    """`Regular` coordinates (never stored; the 10^9-point case of the benchmark)."""
    n = 4000
    xs = gd.Regular(-3.0, 0.25, n)
    x = xs.to_numpy()
    y = np.cos(x / 11.0) + 0.3 * np.sin(x)
    ref = si.make_interp_spline(x, y, k=3)
    spline = gd.make_interp_spline(xs, da.from_array(y, chunks=613))
    np.testing.assert_array_equal(spline.t[0].compute(), ref.t)
    new = gd.Regular(-3.0, 0.125, 2 * n - 1)
    out = gd.resample(da.from_array(y, chunks=613), [xs], [new], chunks=1000)
    assert out.chunks[0][0] == 1000
    near(out.compute(), ref(new.to_numpy()), np.abs(y).max())


@pytest.mark.parametrize("chunk", [1000, 97, 13])
def test_periodic_evaluation_anywhere(client, chunk):
    """A periodic axis repeats its period (SciPy's extrapolate='periodic'): output chunks
    inside one period, across the end of one (both ends' coefficients), over several."""
    rng = np.random.default_rng(8)
    x, y = series(rng, 120, "periodic")
    ref = si.make_interp_spline(x, y, k=3, bc_type="periodic")
    span = x[-1] - x[0]
    spline = gd.make_interp_spline(x, da.from_array(y, chunks=23), bc_type="periodic")
    new = np.linspace(x[0] - 0.7 * span, x[-1] + 1.6 * span, 1000)
    near(spline(new, chunks=chunk).compute(), ref(new, extrapolate="periodic"),
         np.abs(y).max())
    near(spline(new, chunks=chunk, nu=1).compute(), ref(new, nu=1, extrapolate="periodic"),
         np.abs(ref(x, nu=1)).max(), ulps=64)


def test_extrapolation_continues_the_end_pieces(client):
    rng = np.random.default_rng(3)
    x, y = series(rng, 200, None)
    ref = si.make_interp_spline(x, y, k=3)
    new = np.linspace(x[0] - 1.0, x[-1] + 1.0, 301)
    got = gd.make_interp_spline(x, da.from_array(y, chunks=50))(new).compute()
    # Outside, the cubic end pieces amplify the coefficients' rounding (a few steps out).
    near(got, ref(new), np.abs(ref(new)).max(), ulps=64)


# -- 2-D grids -------------------------------------------------------------------------------
def grid(rng, nx, ny, bc):
    x = dyadic_coordinates(rng, nx)
    y = -2.0 + np.arange(ny) / 32.0
    z = np.sin(x[:, None] / 5.0) * np.cos(y[None, :]) + 0.05 * rng.standard_normal((nx, ny))
    if bc == "periodic":
        z[-1, :] = z[0, :]
        z[:, -1] = z[:, 0]
    return x, y, z


def tensor_reference(x, y, z, bc, module=si):
    """Coefficients of the tensor-product spline on the whole grid in memory: the 1-D solve
    along x, then along y (SciPy's, or geomkit's with module=geomkit)."""
    along_x = module.make_interp_spline(x, z, k=3, bc_type=bc, axis=0)
    both = module.make_interp_spline(y, along_x.c, k=3, bc_type=bc, axis=1)
    return along_x.t, both.t, np.moveaxis(both.c, 0, 1)


def tensor_eval(tx, ty, c, nx, ny):
    return si.BSpline(ty, si.BSpline(tx, c, 3, axis=0)(nx), 3, axis=1)(ny)


@pytest.mark.parametrize("bc", BCS)
def test_grid_equals_global_solve(client, bc):
    """Odd chunks, some smaller than the halo, rectilinear x, each end condition."""
    rng = np.random.default_rng(11)
    x, y, z = grid(rng, 97, 131, bc)
    tx, ty, cref = tensor_reference(x, y, z, bc)
    spline = gd.make_interp_grid((x, y), da.from_array(z, chunks=(23, 17)), bc_type=bc)
    c = spline.c.compute()
    scale = np.abs(z).max()
    # The same two-pass solve in memory (geomkit's): 4 eps (8 for the cyclic solves, whose
    # own rounding is a few eps). SciPy's, whose banded solves round on their own in both
    # passes (up to 9 eps from geomkit's in memory on these data): 16 eps.
    near(c, tensor_reference(x, y, z, bc, geomkit)[2], scale, 8 if bc == "periodic" else 4)
    near(c, cref, scale, ulps=16)
    if bc == "periodic":
        # Both passes of the cyclic solve in long double: the chunked result within 4 eps.
        along_x = periodic_truth(tx, z, dtype=np.longdouble)
        near(c, periodic_truth(ty, along_x.T, dtype=np.longdouble).T.astype(float), scale)
    np.testing.assert_array_equal(spline.t[0], tx)
    np.testing.assert_array_equal(spline.t[1], ty)
    # Finer along x, coarser along y, and an irregular grid.
    irregular = (np.sort(rng.uniform(x[0], x[-1], 50)), np.sort(rng.uniform(y[0], y[-1], 70)))
    for nx, ny in ((np.linspace(x[0], x[-1], 301), np.linspace(y[0], y[-1], 40)), irregular):
        near(spline(nx, ny, chunks=(37, 19)).compute(), tensor_eval(tx, ty, cref, nx, ny),
             scale, ulps=16)


def test_grid_partial_derivatives(client):
    """Slopes and the mixed derivative of a chunked grid against SciPy's BSpline of the
    in-memory coefficients."""
    rng = np.random.default_rng(12)
    x, y, z = grid(rng, 70, 90, None)
    tx, ty, cref = tensor_reference(x, y, z, None)
    spline = gd.make_interp_grid((x, y), da.from_array(z, chunks=(19, 26)))
    nx, ny = np.linspace(x[0], x[-1], 123), np.linspace(y[0], y[-1], 77)
    for nu in ((1, 0), (0, 1), (1, 1), (2, 0), (0, 3)):
        ref = si.BSpline(ty, si.BSpline(tx, cref, 3, axis=0)(nx, nu=nu[0]), 3, axis=1)(
            ny, nu=nu[1])
        got = spline(nx, ny, nu=nu).compute()
        # Each derivative divides by the steps (1/8 to 12/8 along x, 1/32 along y).
        near(got, ref, np.abs(ref).max(), ulps=64)
    with pytest.raises(ValueError, match="derivative orders must be >= 0"):
        spline(nx, ny, nu=(-1, 0))


def test_grid_against_rect_bivariate_spline(client):
    """SciPy's FITPACK interpolating surface (s=0: not-a-knot knots) on the whole grid."""
    rng = np.random.default_rng(5)
    x, y, z = grid(rng, 120, 90, None)
    rbs = si.RectBivariateSpline(x, y, z, s=0)
    nx, ny = np.linspace(x[0], x[-1], 239), np.linspace(y[0], y[-1], 179)
    got = gd.resample(da.from_array(z, chunks=(31, 29)), (x, y), (nx, ny)).compute()
    # FITPACK's Givens solve rounds more than a banded LU: 64 eps, still 14 digits.
    near(got, rbs(nx, ny), np.abs(z).max(), ulps=64)


def test_batch_axis_and_mixed_end_conditions(client):
    """A stack of grids (time, y, x): each interpolated, the batch axis carried along."""
    rng = np.random.default_rng(9)
    x, y, z = grid(rng, 60, 70, None)
    stack = np.stack([z, 2.0 * z + 1.0, -z])
    stack[:, :, -1] = stack[:, :, 0]
    arr = da.from_array(stack, chunks=(2, 25, 21))
    bc = {1: ("natural", "clamped"), 2: "periodic"}
    spline = gd.make_interp_grid((x, y), arr, axes=(1, 2), bc_type=bc)
    assert spline.bc_type == (("natural", "clamped"), ("periodic", "periodic"))
    # SciPy's c has the interpolation axis first: (nx + 2, 3, ny), then (ny + 2, 3, nx + 2).
    along = si.make_interp_spline(x, stack, k=3, bc_type=("natural", "clamped"), axis=1)
    both = si.make_interp_spline(y, np.moveaxis(along.c, 0, 1), k=3, bc_type="periodic",
                                 axis=2)
    cref = np.moveaxis(both.c, 0, 2)
    near(spline.c.compute(), cref, np.abs(stack).max(), ulps=8)
    assert spline.c.chunks[0] == (2, 1)


def test_derivative_values_at_the_ends(client):
    """SciPy's [(order, value)] sides: a series, and a grid along x (the same value for
    every line of the grid)."""
    rng = np.random.default_rng(13)
    x, y = series(rng, 260, None)
    bc = ([(1, 0.5)], [(2, -0.3)])
    ref = si.make_interp_spline(x, y, k=3, bc_type=bc)
    spline = gd.make_interp_spline(x, da.from_array(y, chunks=41), bc_type=bc)
    assert spline.bc_type == (((1, 0.5), (2, -0.3)),)
    near(spline.c.compute(), ref.c, np.abs(y).max())
    near(spline(x[[0, -1]], nu=1).compute()[0], 0.5, 1.0)
    near(spline(x[[0, -1]], nu=2).compute()[1], -0.3, np.abs(ref(x, nu=2)).max(), ulps=64)
    gx, gy, z = grid(rng, 80, 60, None)
    side = [(1, 0.2)]
    ref2 = si.make_interp_spline(gx, z, k=3, bc_type=([(1, np.full(60, 0.2))], "natural"))
    got = gd.make_interp_grid((gx,), da.from_array(z, chunks=(23, 30)),
                              bc_type=(side, "natural")).c.compute()
    near(got, ref2.c, np.abs(z).max())
    with pytest.raises(ValueError, match="one derivative of order 1 or 2"):
        gd.make_interp_spline(x, da.from_array(y, chunks=41), bc_type=([(3, 0.0)], "natural"))
    with pytest.raises(ValueError, match="each side of a"):
        gd.make_interp_spline(x, da.from_array(y, chunks=41), bc_type=("natural", None))


# -- errors ----------------------------------------------------------------------------------
def test_nan_names_its_chunk(client):
    z = np.ones((60, 50))
    z[37, 12] = np.nan
    spline = gd.make_interp_grid((np.arange(60.0), np.arange(50.0)),
                                 da.from_array(z, chunks=(20, 25)))
    with pytest.raises(ValueError, match=r"non-finite value nan in chunk \(1, 0\) "
                                         r"\(indices 20\.\.39 x 0\.\.24\) at index \(37, 12\)"):
        spline.c.compute()
    y = np.arange(100.0)
    y[99] = np.inf
    with pytest.raises(ValueError, match=r"chunk \(3,\) \(indices 90\.\.99\)"):
        gd.make_interp_spline(np.arange(100.0), da.from_array(y, chunks=30)).c.compute()


# The last point alone in its chunk (whose coefficients all repeat the first ones), empty
# chunks at the ends.
@pytest.mark.parametrize("chunks", [9, ((39, 1),), ((0, 20, 20, 0),)])
def test_periodic_needs_equal_ends(client, chunks):
    y = np.sin(np.arange(40.0))
    with pytest.raises(ValueError, match="first and last points does not match"):
        gd.make_interp_spline(np.arange(40.0), da.from_array(y, chunks=chunks),
                              bc_type="periodic").c.compute()


def test_bad_arguments():
    z = da.zeros((40, 30), chunks=10)
    x, y = np.arange(40.0), np.arange(30.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        gd.make_interp_grid((x[::-1], y), z)
    with pytest.raises(ValueError, match="has 39 coordinates"):
        gd.make_interp_grid((x[1:], y), z)
    with pytest.raises(ValueError, match="non-finite coordinate"):
        gd.make_interp_grid((np.where(x == 5, np.nan, x), y), z)
    with pytest.raises(ValueError, match="2 coordinate arrays for the axes"):
        gd.make_interp_grid((x, y), z, axes=(0,))
    with pytest.raises(ValueError, match="at least 4 points"):
        gd.make_interp_spline(np.arange(3.0), da.zeros(3, chunks=2))
    with pytest.raises(ValueError, match="bc_type 'cubic'"):
        gd.make_interp_grid((x, y), z, bc_type="cubic")
    with pytest.raises(ValueError, match="depth must be >= 1"):
        gd.make_interp_grid((x, y), z, depth=0)
    with pytest.raises(TypeError, match="depth must be an integer"):
        gd.make_interp_grid((x, y), z, depth=2.5)
    with pytest.raises(ValueError, match=r"depth=8 is too small .* use depth >= 29"):
        gd.make_interp_grid((x, y), z, depth=8)
    with pytest.raises(TypeError, match="complex"):
        gd.make_interp_grid((x, y), z.astype(complex))
    spline = gd.make_interp_grid((x, y), z)
    with pytest.raises(ValueError, match="strictly increasing"):
        spline(np.array([0.0, 2.0, 1.0]), y)
    with pytest.raises(ValueError, match="one coordinate array per interpolated axis"):
        spline(x)


def test_halo_certificate():
    """Uniform coordinates need 29 points of halo for 2**-53 (0.268 per point); strongly
    irregular ones more, and depth='auto' takes it."""
    assert gd.required_depth([gd.Regular(0.0, 1.0, 10_000)], [1000]) == 29
    assert gd.required_depth([np.arange(100.0)], [100]) == 1  # one chunk: no artificial end
    rng = np.random.default_rng(1)
    x = np.cumsum(rng.choice([1.0, 3.0], 400))
    need = gd.required_depth([x], [50])
    assert need > 32
    y = np.sin(x)
    spline = gd.make_interp_spline(x, da.from_array(y, chunks=50), depth="auto")
    assert spline.depth == need
    with pytest.raises(ValueError, match=f"use depth >= {need}"):
        gd.make_interp_spline(x, da.from_array(y, chunks=50), depth=need - 1)
    c = spline.c.compute(scheduler="synchronous")
    near(c, geomkit.make_interp_spline(x, y).c, np.abs(y).max())
    near(c, si.make_interp_spline(x, y).c, np.abs(y).max(), ulps=8)


def test_import_geomkit_does_not_import_dask():
    code = ("import sys, geomkit; assert 'dask' not in sys.modules and 'xarray' not in "
            "sys.modules; geomkit.dask.Regular; assert 'dask' in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)


# -- xarray and Zarr -------------------------------------------------------------------------
def test_xarray_round_trip(client, tmp_path):
    rng = np.random.default_rng(2)
    x, y, z = grid(rng, 80, 64, None)
    stack = np.stack([z, z**2])
    arr = xr.DataArray(
        stack, dims=("band", "y", "x"), name="height",
        coords={"band": ["a", "b"], "y": ("y", x, {"units": "km"}), "x": y,
                "row": ("y", np.arange(80))},
        attrs={"units": "m", "source": "test"},
    ).chunk({"band": 1, "y": 21, "x": 15})
    ny, nx = np.linspace(x[0], x[-1], 159), np.linspace(y[0], y[-1], 33)
    out = arr.geomkit.interp(y=ny, x=nx)
    assert isinstance(out.data, da.Array)
    assert out.dims == ("band", "y", "x") and out.name == "height"
    assert out.attrs == {"units": "m", "source": "test"}
    assert out.y.attrs == {"units": "km"} and "row" not in out.coords
    assert list(out.band.values) == ["a", "b"]
    np.testing.assert_array_equal(out.y.values, ny)
    # xarray's own cubic interpolation (SciPy's not-a-knot spline) on the data in memory,
    # one dimension after the other: the tensor-product spline. (Both at once, xarray calls
    # SciPy's interpn, whose "cubic" is another interpolant: 4e-5 away on these data.)
    ref = arr.compute().interp(y=ny, method="cubic").interp(x=nx, method="cubic")
    near(out.values, ref.values, np.abs(stack).max())
    # xarray's own Zarr writer takes the lazy result chunk by chunk (regular chunks).
    # (The string coordinate "band" left out: Zarr 3 has no specified string type yet.)
    out.drop_vars("band").to_dataset().to_zarr(str(tmp_path / "out.zarr"), consolidated=False)
    back = xr.open_zarr(str(tmp_path / "out.zarr"), consolidated=False)["height"]
    assert back.attrs == out.attrs and back.y.attrs == {"units": "km"}
    np.testing.assert_array_equal(back.values, out.values)
    # The function and the accessor agree; end conditions by dimension name.
    nat = geomkit.xarray.interp(arr, {"y": ny}, bc_type={"y": "natural"})
    natref = si.make_interp_spline(x, stack, k=3, bc_type="natural", axis=1)(ny)
    near(nat.values, natref, np.abs(stack).max())


def test_xarray_datetime_series(client):
    t = np.arange("2024-01-01", "2024-03-01", dtype="datetime64[D]").astype("datetime64[ns]")
    values = np.cos(np.arange(t.size) / 4.0)
    arr = xr.DataArray(values, dims="time", coords={"time": t}).chunk(16)
    new = np.arange(t[0], t[-1], np.timedelta64(6, "h"))
    out = arr.geomkit.interp(time=new)
    assert out.time.dtype == np.dtype("datetime64[ns]")
    hours = (new - t[0]) / np.timedelta64(1, "D")
    ref = si.make_interp_spline(np.arange(t.size, dtype=float), values)(hours)
    near(out.values, ref, 1.0)


def test_zarr_write_read_back(client, tmp_path):
    rng = np.random.default_rng(4)
    x, y, z = grid(rng, 90, 70, None)
    nx, ny = np.linspace(x[0], x[-1], 179), np.linspace(y[0], y[-1], 139)
    out = gd.resample(da.from_array(z, chunks=(30, 25)), (x, y), (nx, ny), chunks=(64, 50))
    gd.to_zarr(out, str(tmp_path / "fine.zarr"))
    stored = zarr.open_array(str(tmp_path / "fine.zarr"), mode="r")
    assert stored.shape == (179, 139) and stored.chunks == (64, 50)
    tx, ty, cref = tensor_reference(x, y, z, None)
    near(stored[:], tensor_eval(tx, ty, cref, nx, ny), np.abs(z).max())
    # Irregular chunks (the coefficients) are made regular for Zarr.
    spline = gd.make_interp_grid((x, y), da.from_array(z, chunks=(30, 25)), bc_type="natural")
    gd.to_zarr(spline.c, str(tmp_path / "c.zarr"))
    c = zarr.open_array(str(tmp_path / "c.zarr"), mode="r")
    assert c.chunks == (31, 26)
    np.testing.assert_array_equal(c[:], spline.c.compute())


def test_docstring_examples():
    """The examples of geomkit.dask and geomkit.xarray run (local threads, no cluster)."""
    import doctest

    with dask.config.set(scheduler="threads"):
        for module in (gd, geomkit.xarray):
            result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
            assert result.failed == 0 and result.attempted > 0, module.__name__


def test_xarray_dataset_and_errors(client):
    rng = np.random.default_rng(6)
    x, y, z = grid(rng, 50, 40, None)
    ds = xr.Dataset(
        {"height": (("y", "x"), z, {"units": "m"}), "profile": ("y", z[:, 0]),
         "band_mean": ("band", [1.0, 2.0]), "name": ((), "dem")},
        coords={"y": x, "x": y, "band": ["a", "b"]}, attrs={"crs": "EPSG:32633"},
    ).chunk({"y": 17, "x": 13})
    ny = np.linspace(x[0], x[-1], 77)
    out = ds.geomkit.interp(y=ny)
    assert out.attrs == {"crs": "EPSG:32633"} and out["height"].attrs == {"units": "m"}
    assert out["height"].dims == ("y", "x") and out.sizes["y"] == 77
    np.testing.assert_array_equal(out["band_mean"].values, [1.0, 2.0])
    assert str(out["name"].values) == "dem"
    ref = si.make_interp_spline(x, z, k=3, axis=0)(ny)
    near(out["height"].values, ref, np.abs(z).max())
    near(out["profile"].values, ref[:, 0], np.abs(z).max())
    # A NaN is named with the DataArray's name, its chunk and its index.
    bad = ds["height"].copy(data=np.where(np.arange(z.size).reshape(z.shape) == 700, np.nan,
                                          z)).chunk({"y": 17, "x": 13})
    with pytest.raises(ValueError, match=r"DataArray 'height': non-finite value nan in chunk "
                                         r"\(1, 1\) \(indices 17\.\.33 x 13\.\.25\) at index "
                                         r"\(17, 20\)"):
        bad.geomkit.interp(y=ny).compute()
    with pytest.raises(ValueError, match="'z' is not a dimension"):
        ds["height"].geomkit.interp(z=[1.0, 2.0])
    with pytest.raises(ValueError, match="must be strictly increasing"):
        ds["height"].geomkit.interp(y=ny[[0, 2, 1]])


def test_xarray_decreasing_coordinates(client):
    """Latitudes from 90 to -90, new ones in either order: xarray's own cubic interpolation
    (SciPy's interp1d sorts them) on the data in memory."""
    lat = np.linspace(90.0, -90.0, 73)
    lon = np.arange(0.0, 360.0, 5.0)
    rng = np.random.default_rng(10)
    values = np.cos(np.radians(lat))[:, None] * np.sin(np.radians(lon))[None, :]
    values = values + 0.01 * rng.standard_normal(values.shape)
    arr = xr.DataArray(values, dims=("lat", "lon"), coords={"lat": lat, "lon": lon},
                       name="t2m").chunk({"lat": 20, "lon": 25})
    for new_lat in (np.linspace(89.0, -89.0, 100), np.linspace(-89.0, 89.0, 100)):
        out = arr.geomkit.interp(lat=new_lat)
        np.testing.assert_array_equal(out.lat.values, new_lat)
        ref = arr.compute().interp(lat=new_lat, method="cubic")
        near(out.values, ref.values, np.abs(values).max())


def test_graph_reads_only_neighbours():
    """No gather: a solve task reads its own chunk whole and, from the chunks its halo
    reaches, only the halo (cut by a task of its own where that chunk is); an evaluation
    task its coefficient chunk and the few rows and columns of its neighbours it needs."""
    from dask.core import get_dependencies

    x = np.arange(800.0)
    z = da.zeros((800, 800), chunks=160)
    spline = gd.make_interp_grid((x, x), z)
    out = spline(np.linspace(0, 799, 1599), np.linspace(0, 799, 1599), chunks=320)
    graph = dict(out.__dask_graph__())
    for name, chunk_name in ((spline.c.name, z.name), (out.name, spline.c.name)):
        tasks = [k for k in graph if isinstance(k, tuple) and k[0] == name]
        assert len(tasks) == 25
        for key in tasks:
            deps = get_dependencies(graph, key)
            whole = [d for d in deps if d[0] == chunk_name]
            parts = [d for d in deps if d[0] == name + "-part"]
            assert len(whole) == 1 and len(whole) + len(parts) == len(deps) <= 9
            for part in parts:  # each part cut from one chunk
                assert [d[0] for d in get_dependencies(graph, part)] == [chunk_name]
    # A window of the result needs only the tasks of its neighbourhood (the graph culled).
    (window,) = dask.optimize(out[400:410, 1200:1210])
    assert len(dict(window.__dask_graph__())) < len(graph) / 3
    result = out.compute(scheduler="synchronous")
    assert result.shape == (1599, 1599) and not result.any()
