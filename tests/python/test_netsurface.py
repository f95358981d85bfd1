"""geomkit.make_interp_surface / BSplineSurface: the parametric bicubic surface through an
M x N grid of points, against SciPy's RectBivariateSpline and parameters computed here."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from scipy.interpolate import RectBivariateSpline as ScipyRBS

import geomkit


def wavy_grid(m: int = 7, n: int = 9, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u, v = np.meshgrid(np.cumsum(rng.uniform(0.5, 1.5, m)), np.cumsum(rng.uniform(0.5, 1.5, n)),
                       indexing="ij")
    return np.stack([u, v, np.sin(u) * np.cos(0.7 * v) + 0.1 * u], axis=-1)


@pytest.mark.parametrize("param", ["chord", "centripetal", "uniform"])
@pytest.mark.parametrize("bc", ["not-a-knot", "natural", "bessel"])
def test_passes_through_every_point(param: str, bc: str) -> None:
    pts = wavy_grid()
    s = geomkit.make_interp_surface(pts, bc_type=bc, param=param)
    got = s(s.params_u, s.params_v)
    assert got.shape == pts.shape
    assert np.abs(got - pts).max() <= 1e-13 * np.abs(pts).max()
    assert s.degrees == (3, 3) and s.dim == 3


def test_uniform_heights_equal_scipy_rect_bivariate_spline() -> None:
    # With parameters 0, 1, 2, ... and points (i, j, z_ij), x(u, v) = u and y = v exactly,
    # and z is the not-a-knot tensor interpolant: FITPACK's s = 0 spline on arange grids.
    m, n = 8, 11
    rng = np.random.default_rng(5)
    z = rng.standard_normal((m, n))
    i, j = np.meshgrid(np.arange(m, dtype=float), np.arange(n, dtype=float), indexing="ij")
    s = geomkit.make_interp_surface(np.stack([i, j, z], axis=-1), param="uniform")
    ref = ScipyRBS(np.arange(m, dtype=float), np.arange(n, dtype=float), z, s=0)
    u = rng.uniform(0, m - 1, 200)
    v = rng.uniform(0, n - 1, 200)
    got = s(u, v, grid=False)
    assert np.abs(got[:, 0] - u).max() < 1e-12 and np.abs(got[:, 1] - v).max() < 1e-12
    assert np.abs(got[:, 2] - ref.ev(u, v)).max() < 1e-12
    us, vs = np.linspace(0, m - 1, 13), np.linspace(0, n - 1, 17)
    assert np.abs(s(us, vs)[:, :, 2] - ref(us, vs)).max() < 1e-12


def test_chord_parameters_are_the_averaged_chord_lengths() -> None:
    pts = wavy_grid()
    s = geomkit.make_interp_surface(pts, param="chord")
    for axis, got in ((0, s.params_u), (1, s.params_v)):
        lines = np.moveaxis(pts, axis, 0)  # lines[i]: the i-th grid line across this axis
        chords = np.linalg.norm(np.diff(lines, axis=0), axis=-1)
        cum = np.vstack([np.zeros(chords.shape[1]), np.cumsum(chords, axis=0)])
        want = (lines.shape[0] - 1) * (cum / cum[-1]).mean(axis=1)
        assert np.abs(got - want).max() < 1e-12


def test_periodic_direction_closes_smoothly() -> None:
    t = np.linspace(0, 2 * np.pi, 17)[:-1]
    z = np.linspace(0, 2, 5)
    ring = np.stack(np.broadcast_arrays(np.cos(t)[None, :], np.sin(t)[None, :], z[:, None]),
                    axis=-1)
    s = geomkit.make_interp_surface(ring, bc_type=("not-a-knot", "periodic"))
    assert np.abs(s(s.params_u, s.params_v) - ring).max() < 1e-12
    period = 16.0  # uniform spacing: chord parameters 0..16 over the closed direction
    us = np.linspace(0, 4, 9)
    a, b = s(us, np.array([0.0, 1e-7])), s(us, np.array([period, period + 1e-7]))
    assert np.abs(a - b).max() < 1e-12
    # A circle through 16 points: within 1e-4 of radius 1 between them.
    r = np.hypot(*np.moveaxis(s(us, np.linspace(0, period, 161))[:, :, :2], -1, 0))
    assert np.abs(r - 1).max() < 1e-4


def test_save_load_pickle_and_mesh(tmp_path) -> None:  # type: ignore[no-untyped-def]
    s = geomkit.make_interp_surface(wavy_grid())
    path = tmp_path / "s.json"
    s.save(path)
    back = geomkit.load(path)
    assert isinstance(back, geomkit.BSplineSurface)
    assert np.array_equal(back.net, s.net)
    assert all(np.array_equal(a, b) for a, b in zip(back.knots, s.knots))
    again = pickle.loads(pickle.dumps(s))
    assert np.array_equal(again.params_u, s.params_u)
    uv = np.linspace(0, 6, 7), np.linspace(0, 8, 5)
    assert np.array_equal(again(*uv), s(*uv))
    # The file has the grid parameters, as the CLI's `interpolate surface` writes them.
    assert np.array_equal(back.params_u, s.params_u)
    # Meshed: vertices on the surface's bounding box of dense samples.
    dense = s(np.linspace(0, 6, 61), np.linspace(0, 8, 81)).reshape(-1, 3)
    mesh = s.mesh(tolerance=1e-3)
    lo, hi = dense.min(axis=0), dense.max(axis=0)
    assert np.all(mesh.vertices >= lo - 1e-3) and np.all(mesh.vertices <= hi + 1e-3)
    # A height surface file still loads as SciPy's class.
    h = geomkit.RectBivariateSpline(np.arange(5.0), np.arange(6.0), np.ones((5, 6)))
    h.save(tmp_path / "h.json")
    assert isinstance(geomkit.load(tmp_path / "h.json"), geomkit.RectBivariateSpline)


@pytest.mark.parametrize(
    "points, kwargs, message",
    [
        (np.zeros((4, 5)), {}, "shape (M, N, dim)"),
        (np.full((4, 5, 3), np.nan), {}, "finite"),
        (wavy_grid(), {"bc_type": "clamped"}, "bc_type 'clamped'"),
        (wavy_grid(), {"param": "arc"}, "param 'arc'"),
        (np.zeros((1, 5, 3)), {}, ""),
    ],
)
def test_bad_input_is_a_value_error(points: np.ndarray, kwargs: dict[str, str],
                                    message: str) -> None:
    with pytest.raises(ValueError, match=None if not message else message.replace("(", r"\(")
                       .replace(")", r"\)")):
        geomkit.make_interp_surface(points, **kwargs)


def test_bad_parameters_are_value_errors() -> None:
    s = geomkit.make_interp_surface(wavy_grid())
    with pytest.raises(ValueError):
        s(np.array([np.nan]), np.array([1.0]))
    with pytest.raises(ValueError, match="1-D"):
        s(np.zeros((2, 2)), np.zeros(3))
    with pytest.raises(TypeError):
        geomkit.BSplineSurface()


# --- tiles (tile=T: geomkit.bspline::interpolate_surface_tiled) -----------------------------
def big_grid(m: int = 150, n: int = 130, seed: int = 8) -> np.ndarray:
    """An m x n grid of 3-D points on uneven grid lines (chord parameters differ per line)."""
    rng = np.random.default_rng(seed)
    u = np.cumsum(rng.uniform(0.5, 1.5, m))[:, None] + 0.05 * rng.normal(size=(m, n))
    v = np.cumsum(rng.uniform(0.5, 1.5, n))[None, :] + 0.05 * rng.normal(size=(m, n))
    return np.stack([u, v, np.sin(0.3 * u) * np.cos(0.2 * v) + 0.01 * u * v], axis=-1)


@pytest.mark.parametrize("param", ["chord", "centripetal", "uniform"])
@pytest.mark.parametrize("bc", ["not-a-knot", "natural", "bessel", ("natural", "not-a-knot")])
def test_tiles_equal_the_whole_solve(param: str, bc: str | tuple[str, str]) -> None:
    """Blocks of 40 x 40 points on a 150 x 130 grid (4 x 4 blocks, seams both ways, the
    default halo of 32 lines): the same parameters and knots (computed once for the grid),
    a net within 64 eps of the data's scale (rounding: the halo's error is ~0.27^32; the
    largest differences, up to ~30 eps, sit at not-a-knot corners, whose control points
    extrapolate), passing through every point."""
    pts = big_grid()
    whole = geomkit.make_interp_surface(pts, bc_type=bc, param=param)
    tiled = geomkit.make_interp_surface(pts, bc_type=bc, param=param, tile=40)
    assert tiled.params_u is not None and whole.params_u is not None
    assert tiled.params_v is not None and whole.params_v is not None
    assert np.array_equal(tiled.params_u, whole.params_u)
    assert np.array_equal(tiled.params_v, whole.params_v)
    assert all(np.array_equal(a, b) for a, b in zip(tiled.knots, whole.knots))
    scale = np.abs(pts).max()
    assert tiled.net.shape == whole.net.shape == (152, 132, 3)
    assert np.abs(tiled.net - whole.net).max() <= 64 * np.finfo(float).eps * scale
    got = tiled(tiled.params_u, tiled.params_v)
    assert np.abs(got - pts).max() <= 1e-13 * scale


def test_tiles_match_scipy_rect_bivariate_spline() -> None:
    """Where the forms coincide (uniform parameters, points (i, j, z_ij), not-a-knot ends: z
    is FITPACK's s = 0 interpolant on arange grids), the tiled surface against SciPy's
    RectBivariateSpline, with blocks of 16 points on a 70 x 55 grid."""
    m, n = 70, 55
    rng = np.random.default_rng(12)
    z = np.cumsum(rng.standard_normal((m, n)), axis=0) * 0.3
    i, j = np.meshgrid(np.arange(m, dtype=float), np.arange(n, dtype=float), indexing="ij")
    s = geomkit.make_interp_surface(np.stack([i, j, z], axis=-1), param="uniform", tile=16)
    ref = ScipyRBS(np.arange(m, dtype=float), np.arange(n, dtype=float), z, s=0)
    u, v = rng.uniform(0, m - 1, 2000), rng.uniform(0, n - 1, 2000)
    got = s(u, v, grid=False)
    scale = max(1.0, np.abs(z).max())
    assert np.abs(got[:, 0] - u).max() < 1e-12 * m and np.abs(got[:, 1] - v).max() < 1e-12 * n
    assert np.abs(got[:, 2] - ref.ev(u, v)).max() < 1e-12 * scale
    us, vs = np.linspace(0, m - 1, 31), np.linspace(0, n - 1, 23)
    assert np.abs(s(us, vs)[:, :, 2] - ref(us, vs)).max() < 1e-12 * scale


def test_tiles_any_dimension_and_sizes() -> None:
    """2-D and 5-D points; blocks of 2 (the smallest) and larger than the grid (one block)."""
    rng = np.random.default_rng(4)
    for dim in (2, 5):
        pts = np.cumsum(rng.uniform(0.2, 1.0, (60, 45, dim)), axis=0)
        whole = geomkit.make_interp_surface(pts, param="centripetal")
        scale = np.abs(pts).max()
        for tile in (2, 23, 10**6, 10**30):
            tiled = geomkit.make_interp_surface(pts, param="centripetal", tile=tile)
            assert np.abs(tiled.net - whole.net).max() <= 64 * np.finfo(float).eps * scale


@pytest.mark.parametrize("bc", ["periodic", ("not-a-knot", "periodic"), ("periodic", "natural")])
def test_tiles_refuse_periodic_ends(bc: str | tuple[str, str]) -> None:
    t = np.linspace(0, 2 * np.pi, 17)[:-1]
    ring = np.stack(np.broadcast_arrays(np.cos(t)[None, :], np.sin(t)[None, :],
                                        np.linspace(0, 1, 16)[:, None]), axis=-1)
    with pytest.raises(ValueError, match="invalid tiled end condition: tiles take natural, "
                                         "clamped, bessel, not-a-knot or outer-points ends"):
        geomkit.make_interp_surface(ring, bc_type=bc, tile=8)


@pytest.mark.parametrize("tile, error, match", [
    (0, ValueError, r"tile must be at least 2 points \(got 0\)"),
    (1, ValueError, r"tile must be at least 2 points \(got 1\)"),
    (-3, ValueError, "tile must be at least 2"),
    (8.0, TypeError, "tile must be an integer"),
    ("8", TypeError, "tile must be an integer"),
    (False, TypeError, "tile must be an integer"),
])
def test_bad_tiles(tile: object, error: type[Exception], match: str) -> None:
    with pytest.raises(error, match=match):
        geomkit.make_interp_surface(wavy_grid(), tile=tile)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        geomkit.make_interp_surface(wavy_grid(), "not-a-knot", "chord", 8)  # type: ignore[misc]
    # The grid's own errors keep their words with tiles.
    with pytest.raises(ValueError, match="finite"):
        geomkit.make_interp_surface(np.full((4, 5, 3), np.nan), tile=2)
