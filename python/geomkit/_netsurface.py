"""`BSplineSurface` and `make_interp_surface`: the parametric bicubic B-spline surface through
an M x N grid of points of any dimension (method 2, ``geomkit interpolate surface``)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import aligned, contiguous, real_array, tile_size
from ._model import Drawable, register_kind
from ._progress import chunked, reporter

__all__ = ["BSplineSurface", "make_interp_surface"]

_ENDS = ("not-a-knot", "natural", "bessel", "periodic")
_PARAMS = ("chord", "centripetal", "uniform")


class BSplineSurface(Drawable):
    """A tensor-product B-spline surface S(u, v) with points of any dimension.

    Made by `make_interp_surface` (the bicubic surface through a grid of points) or read by
    `geomkit.load` from a ``bspline_surface`` model file whose points are not heights.

    Attributes
    ----------
    degrees : tuple of int
        Degrees (p, q) in u and v.
    params_u, params_v : ndarray or None
        The parameters of the grid rows and columns the surface passes through (None for a
        surface read from a file without them).
    """

    __slots__ = ("_core", "degrees", "params_u", "params_v", "_source")
    _core: _geomkit.Surface
    degrees: tuple[int, int]
    params_u: NDArray[np.float64] | None
    params_v: NDArray[np.float64] | None
    _source: _geomkit.Model | None

    def __init__(self) -> None:
        raise TypeError("make a BSplineSurface with geomkit.make_interp_surface or geomkit.load")

    @classmethod
    def _from_core(cls, core: _geomkit.Surface, params_u: NDArray[np.float64] | None,
                   params_v: NDArray[np.float64] | None) -> BSplineSurface:
        self = object.__new__(cls)
        self._core = core
        self.degrees = core.degrees
        self.params_u = params_u
        self.params_v = params_v
        self._source = None
        return self

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> Any:
        """A ``bspline_surface`` file: heights of degrees 1 to 7 as `RectBivariateSpline`,
        other surfaces as `BSplineSurface`."""
        from ._surface import RectBivariateSpline

        try:
            return RectBivariateSpline._from_model(model)
        except ValueError:
            params = _geomkit.surface_grid_parameters(model)
            pu, pv = (None, None) if params is None else (np.array(params[0]),
                                                           np.array(params[1]))
            self = cls._from_core(_geomkit.Surface.from_model_any(model), pu, pv)
            self._source = model  # saved as read (with the parameters of its points)
            return self

    def _model(self) -> _geomkit.Model:
        if self._source is not None:
            return self._source
        if self.params_u is None or self.params_v is None:
            return self._core.model()
        return self._core.model(self.params_u.tolist(), self.params_v.tolist())

    @property
    def dim(self) -> int:
        """The dimension of the points."""
        return self._core.dim

    @property
    def knots(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The knot vectors in u and v."""
        nu, nv = self._core.n_knots
        tu, tv = np.empty(nu), np.empty(nv)
        self._core.knots_into(tu, tv)
        return tu, tv

    @property
    def net(self) -> NDArray[np.float64]:
        """The control net, shape (rows, cols, dim)."""
        rows, cols = self._core.net_size
        out = np.empty(rows * cols * self.dim)
        self._core.coefficients_into(out)
        return out.reshape(rows, cols, self.dim)

    def __call__(self, u: ArrayLike, v: ArrayLike, grid: bool = True) -> NDArray[np.float64]:
        """Points of the surface.

        Parameters
        ----------
        u, v : array_like
            Parameters (finite). With ``grid=True`` 1-D arrays of the grid u x v; else
            arrays of one shape (or broadcasting to one), paired element by element.
        grid : bool, optional
            Evaluate on the grid u x v (default) or at the pairs (u[i], v[i]).

        Returns
        -------
        ndarray
            Shape (len(u), len(v), dim) on a grid, else the broadcast shape + (dim,).
            Outside the parameter domain the end patches continue.

        Raises
        ------
        ValueError
            For parameters that are not finite, or grid arguments that are not 1-D.

        Examples
        --------
        >>> import numpy as np, geomkit
        >>> u, v = np.meshgrid(np.arange(4.0), np.arange(5.0), indexing="ij")
        >>> pts = np.stack([u, v, u * v], axis=-1)
        >>> s = geomkit.make_interp_surface(pts, param="uniform")
        >>> bool(np.allclose(s(s.params_u, s.params_v), pts, atol=1e-12))
        True
        """
        if grid:
            us, vs = contiguous(u, "u"), contiguous(v, "v")
            if us.ndim != 1 or vs.ndim != 1:
                raise ValueError(f"a grid takes 1-D u and v: got shapes {us.shape} and "
                                 f"{vs.shape} (or pass grid=False)")
            out = np.empty((us.shape[0], vs.shape[0], self.dim))
            core = self._core
            chunked(us.shape[0],
                    lambda a, b: core.eval_points_into(us[a:b], vs, True, out[a:b]),
                    "BSplineSurface", per=vs.shape[0])
            return out
        ub, vb = np.broadcast_arrays(real_array(u, "u"), real_array(v, "v"))
        shape = ub.shape
        us, vs = contiguous(ub.reshape(-1), "u"), contiguous(vb.reshape(-1), "v")
        out = np.empty((us.shape[0], self.dim))
        core = self._core
        chunked(us.shape[0],
                lambda a, b: core.eval_points_into(us[a:b], vs[a:b], False, out[a:b]),
                "BSplineSurface")
        return out.reshape(shape + (self.dim,))

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_rebuild, (self.to_json(), self.params_u, self.params_v))

    def __repr__(self) -> str:
        rows, cols = self._core.net_size
        return (f"BSplineSurface(degrees={self.degrees}, dim={self.dim}, "
                f"{rows} x {cols} control points)")


def _rebuild(text: str, params_u: Any, params_v: Any) -> BSplineSurface:
    core = _geomkit.Surface.from_model_any(_geomkit.parse_model(text))
    return BSplineSurface._from_core(core, params_u, params_v)


def make_interp_surface(points: ArrayLike, bc_type: str | tuple[str, str] = "not-a-knot",
                        param: str = "chord", *, tile: int | None = None) -> BSplineSurface:
    """The bicubic B-spline surface through an M x N grid of points (method 2, the CLI's
    ``geomkit interpolate surface``).

    Parameters
    ----------
    points : array_like, shape (M, N, dim)
        The grid: ``points[i, j]`` is passed at ``(params_u[i], params_v[j])``.
    bc_type : str or (str, str), optional
        End conditions, one for both directions or (across rows, along rows):
        'not-a-knot' (default), 'natural', 'bessel' (end tangents estimated by Bessel's
        method) or 'periodic' (a closed direction: the last row / column equal to the
        first is dropped, else the surface closes on its own).
    param : {'chord', 'centripetal', 'uniform'}, optional
        Parameters of the grid lines: chord lengths (default) or their square roots,
        averaged over all grid lines and scaled to [0, M-1] x [0, N-1], or 0, 1, 2, ...
    tile : int, optional
        Keyword-only: solve in square blocks of `tile` x `tile` grid points (at least
        ``geomkit.MIN_TILE_SIZE`` = 2), each with a halo of 32 grid lines on every side, in
        parallel (the CLI's ``interpolate surface --tile``): the same surface within
        rounding. Periodic ends couple the whole grid: refused with `tile` (ValueError).
        Default None: one solve.

    Returns
    -------
    BSplineSurface
        With the parameters of the grid rows and columns in ``params_u``, ``params_v``.

    Raises
    ------
    ValueError
        For a grid that is not 3-D, non-finite points, too few rows or columns for the end
        condition, coinciding grid lines with chord parameters, unknown names, a `tile`
        below 2 or with periodic ends.
    TypeError
        For points that are not real numbers, a `tile` that is not an integer.

    Examples
    --------
    >>> import numpy as np, geomkit
    >>> t = np.linspace(0, 2 * np.pi, 13)[:-1]
    >>> z = np.linspace(0, 1, 4)
    >>> ring = np.stack(np.broadcast_arrays(np.cos(t)[None, :], np.sin(t)[None, :],
    ...                                     z[:, None]), axis=-1)
    >>> s = geomkit.make_interp_surface(ring, bc_type=("not-a-knot", "periodic"))
    >>> p = s(s.params_u, s.params_v)
    >>> bool(np.abs(p - ring).max() < 1e-12)
    True
    >>> u, v = np.meshgrid(np.arange(200.0), np.arange(150.0), indexing="ij")
    >>> sheet = np.stack([u, v, np.sin(0.1 * u) * np.cos(0.07 * v)], axis=-1)
    >>> tiled = geomkit.make_interp_surface(sheet, tile=64)
    >>> bool(np.abs(tiled.net - geomkit.make_interp_surface(sheet).net).max() < 1e-12)
    True
    """
    grid = real_array(points, "points")
    if grid.ndim != 3:
        raise ValueError(f"points must be an M x N grid of points, shape (M, N, dim): got "
                         f"shape {grid.shape}")
    end_u, end_v = (bc_type, bc_type) if isinstance(bc_type, str) else tuple(bc_type)
    for name in (end_u, end_v):
        if name not in _ENDS:
            raise ValueError(f"bc_type {name!r}: expected one of {', '.join(_ENDS)}")
    if param not in _PARAMS:
        raise ValueError(f"param {param!r}: expected one of {', '.join(_PARAMS)}")
    tile = tile_size(tile)
    rows, cols, dim = grid.shape
    flat = aligned(grid.reshape(rows * cols, dim))
    report = reporter(flat.size, "make_interp_surface")
    try:
        core, pu, pv = _geomkit.interpolate_grid(flat, rows, cols, end_u, end_v, param,
                                                 report, tile)
    finally:
        if report is not None:
            report.close()
    return BSplineSurface._from_core(core, np.array(pu), np.array(pv))


register_kind("bspline_surface", BSplineSurface._from_model)
