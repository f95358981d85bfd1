"""`make_splprep`: the interpolating parametric B-spline curve through points of any dimension,
as ``scipy.interpolate.make_splprep`` with ``s=0`` (SciPy 1.17), on top of geomkit's
`make_interp_spline`."""

from __future__ import annotations

from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._arrays import tile_size
from ._bspline import BSpline, make_interp_spline

__all__ = ["make_splprep"]

_PARAMS = ("chord", "centripetal", "uniform")


def _parameters(x: NDArray[np.float64], param: str) -> NDArray[np.float64]:
    """The default parameters of the points x (shape (m, ndim)), normalized to [0, 1].

    'chord' is SciPy's computation, operation for operation (so the same bits):
    ``v[i] = v[i-1] + |x[i] - x[i-1]|``, ``u = v / v[-1]``; 'centripetal' sums the square
    roots of the chord lengths instead; 'uniform' is ``i / (m - 1)``.
    """
    m = x.shape[0]
    if param == "uniform":
        return np.linspace(0.0, 1.0, m)
    steps = np.sqrt(np.sum((x[1:, :] - x[:-1, :]) ** 2, axis=1))
    if param == "centripetal":
        steps = np.sqrt(steps)
    v = np.cumsum(steps)
    if not v[-1] > 0.0:
        raise ValueError(
            "make_splprep: all points coincide, the curve has no length to parametrize by"
        )
    return np.concatenate([[0.0], v / v[-1]])


def make_splprep(
    x: ArrayLike,
    *,
    w: ArrayLike | None = None,
    u: ArrayLike | None = None,
    ub: float | None = None,
    ue: float | None = None,
    k: int = 3,
    s: float = 0,
    t: ArrayLike | None = None,
    nest: int | None = None,
    bc_type: Any = None,
    param: Literal["chord", "centripetal", "uniform"] = "chord",
    tile: int | None = None,
) -> tuple[BSpline, NDArray[np.float64]]:
    """The interpolating parametric B-spline curve through points in any dimension, as
    ``scipy.interpolate.make_splprep`` with ``s=0``.

    Parameters
    ----------
    x : array_like, shape (ndim, m)
        The points, SciPy's layout: ``x[j]`` is coordinate ``j`` of all ``m`` points
        (typically a list of ``ndim`` 1-D arrays). Finite.
    w : array_like, shape (m,), optional
        Weights; only None or all ones (weights do not change an interpolant). Any other
        value raises ValueError: smoothing is out of geomkit's scope.
    u : array_like, shape (m,), optional
        The parameters of the points, strictly increasing; used as given. Default: computed
        by `param`.
    ub, ue : float, optional
        Accepted for SciPy's signature. As in SciPy with ``s=0`` they do not change the
        spline (its base interval is ``[u[0], u[-1]]``); geomkit checks that
        ``ub <= u[0]`` and ``ue >= u[-1]``.
    k : int, optional
        Degree, 0 to 7 (default 3).
    s : float, optional
        Only 0 (interpolation); smoothing (``s > 0``) is out of scope: ValueError.
    t, nest : optional
        Only None (as SciPy with ``s=0``): ValueError otherwise.
    bc_type : optional
        Boundary conditions, every form of `make_interp_spline`: None or 'not-a-knot'
        (default), 'periodic' (the first and last points equal), 'natural', 'clamped' or a
        pair of lists of ``(order, value)``. SciPy 1.17 accepts only None, 'not-a-knot' and
        'periodic' here and, with ``s=0``, builds a not-a-knot spline whatever `bc_type`
        says; geomkit applies it.
    param : {'chord', 'centripetal', 'uniform'}, optional
        geomkit's addition (SciPy has no such keyword): how `u` is computed when not given,
        each normalized to ``[0, 1]``. 'chord' (default, SciPy's): cumulative chord length;
        'centripetal': cumulative square roots of the chord lengths (Lee's centripetal
        parametrization, which keeps sharp turns from overshooting); 'uniform': ``i / (m - 1)``.
    tile : int, optional
        geomkit's addition: solve in tiles of `tile` coefficients (at least 2), as
        `make_interp_spline`'s `tile` (the same spline within rounding; periodic ends and
        the other cases tiles do not take are solved whole). Default None: no tiles.

    Returns
    -------
    spl : BSpline
        Degree `k`, coefficients of shape ``(n, ndim)``, ``axis=1`` so that
        ``spl(u)`` has the shape of `x` (``spl(u) == x`` to rounding).
    u : ndarray, shape (m,)
        The parameters of the points.

    Raises
    ------
    ValueError
        For ``s != 0``, weights other than ones, `t` or `nest` (smoothing is out of scope);
        NaN or infinite points; coordinates of different lengths; parameters that are not
        strictly increasing (e.g. repeated consecutive points with chord length); an unknown
        `param`, or `param` other than 'chord' together with `u`; a `tile` below 2; and what
        `make_interp_spline` refuses.
    TypeError
        For points that are not real numbers, a `param` that is not a string, a `tile` that
        is not an integer.

    Examples
    --------
    >>> import numpy as np
    >>> import geomkit
    >>> phi = np.linspace(0.0, 2.0 * np.pi, 13)
    >>> spl, u = geomkit.make_splprep([np.cos(phi), np.sin(phi)], bc_type="periodic")
    >>> spl.c.shape, float(u[0]), float(u[-1])
    ((15, 2), 0.0, 1.0)
    >>> bool(np.allclose(spl(u), [np.cos(phi), np.sin(phi)], atol=1e-14))
    True
    >>> spl, u = geomkit.make_splprep([np.cos(phi), np.sin(phi)], param="centripetal", k=5)
    >>> bool(np.allclose(spl(u), [np.cos(phi), np.sin(phi)], atol=1e-14))
    True
    """
    if s != 0:
        raise ValueError(
            f"make_splprep: s = {s}: smoothing (s != 0) is out of geomkit's scope; "
            "only interpolation, s = 0"
        )
    if t is not None or nest is not None:
        raise ValueError(
            "make_splprep: t and nest are for smoothing, out of geomkit's scope; "
            "s==0 is for interpolation only"
        )
    if isinstance(param, str) and param not in _PARAMS:
        raise ValueError(f"make_splprep: param must be one of {_PARAMS}, got {param!r}")
    if not isinstance(param, str):
        raise TypeError(f"make_splprep: param must be a string, got {type(param).__name__}")
    tile = tile_size(tile)

    try:
        points = np.stack([np.asarray(xj) for xj in x], axis=1)  # type: ignore[union-attr]
    except TypeError as e:
        raise TypeError(f"make_splprep: x must be a sequence of 1-D arrays ({e})") from e
    except ValueError as e:
        raise ValueError(f"make_splprep: the coordinates of x must have equal lengths ({e})") from e
    if points.ndim != 2:
        raise ValueError(
            f"make_splprep: x must be ndim 1-D arrays of m values, got shape {points.T.shape}"
        )
    if np.iscomplexobj(points) or not np.issubdtype(points.dtype, np.number):
        raise TypeError(f"make_splprep: x must be real numbers, got dtype {points.dtype}")
    points = points.astype(np.float64, copy=False)
    if not np.all(np.isfinite(points)):
        i = int(np.argmin(np.all(np.isfinite(points), axis=1)))
        raise ValueError(f"make_splprep: point {i} is not finite (NaN or infinite)")
    m = points.shape[0]
    if m < 2:
        raise ValueError(f"make_splprep: at least 2 points are needed, got {m}")

    if w is not None:
        weights = np.asarray(w, dtype=np.float64)
        if weights.shape != (m,) or not np.all(weights == 1.0):
            raise ValueError(
                "make_splprep: weights other than ones are for smoothing, out of geomkit's "
                "scope (an interpolant does not depend on them)"
            )

    if u is None:
        params = _parameters(points, param)
    else:
        if param != "chord":
            raise ValueError("make_splprep: give u or param, not both")
        params = np.asarray(u, dtype=np.float64)
        if params.shape != (m,):
            raise ValueError(
                f"make_splprep: u has shape {params.shape}, the points are {m}: expected ({m},)"
            )
    if ub is not None and not float(ub) <= params[0]:
        raise ValueError(f"make_splprep: ub = {ub} must be <= u[0] = {params[0]}")
    if ue is not None and not float(ue) >= params[-1]:
        raise ValueError(f"make_splprep: ue = {ue} must be >= u[-1] = {params[-1]}")
    if not np.all(params[1:] > params[:-1]):
        i = int(np.argmin(params[1:] > params[:-1]))
        raise ValueError(
            f"make_splprep: the parameters must be strictly increasing: u[{i}] = {params[i]} "
            f">= u[{i + 1}] = {params[i + 1]} (repeated points?)"
        )
    spline = make_interp_spline(params, points.T, k=k, bc_type=bc_type, axis=1, tile=tile)
    return spline, params
