"""`BSpline` and `make_interp_spline`: SciPy's names, signatures, attributes and semantics
(``scipy.interpolate``, SciPy 1.17), computed by geomkit's Rust library."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import (
    aligned,
    contiguous,
    extrapolate_value,
    index,
    mode,
    real_array,
    real_scalar,
    tile_size,
)
from ._model import Drawable, register_kind
from ._progress import chunked, reporter

try:  # NumPy >= 2
    from numpy.lib.array_utils import normalize_axis_index
except ImportError:  # NumPy 1.x
    from numpy.core.multiarray import normalize_axis_index  # type: ignore[no-redef]

__all__ = ["BSpline", "make_interp_spline"]

# insert_knot's limit on m: beyond it the knots would not fit in memory, and the insertions
# (one at a time, as SciPy's) would take O(m^2) time on the way.
_MAX_INSERTIONS = 10**6
# Orders above every degree, passed on as this: the library refuses them in its words,
# where a larger Python integer would only overflow on the way to Rust.
_LARGEST_ORDER = 2**62


class BSpline(Drawable):
    """A univariate spline in the B-spline basis, as ``scipy.interpolate.BSpline``.

    .. math:: S(x) = \\sum_{j=0}^{n-1} c_j B_{j, k; t}(x)

    with the B-spline basis functions :math:`B_{j, k; t}` of degree `k` on the knots `t`.

    Parameters
    ----------
    t : array_like, shape (n + k + 1,)
        Knots, non-decreasing and finite.
    c : array_like, shape (>= n, ...)
        Spline coefficients (real). Coefficients beyond the first n are kept in `c` and
        not used, as in SciPy.
    k : int
        Degree, 0 to 15.
    extrapolate : bool or 'periodic', optional
        Whether to continue the first and last polynomial pieces beyond the base interval
        ``t[k] .. t[n]`` (True), give NaN there (False), or repeat the base interval
        ('periodic'). Default True.
    axis : int, optional
        The interpolation axis of `c` (default 0). As in SciPy, `c` is stored with that
        axis moved to the front, and results put the evaluation points' axes there.

    Attributes
    ----------
    t : ndarray
        Knots (read-only).
    c : ndarray
        Coefficients, the interpolation axis first (read-only).
    k : int
        Degree.
    extrapolate : bool or 'periodic'
        The default of `__call__` and `integrate`.
    axis : int
        The interpolation axis.

    Raises
    ------
    ValueError
        For knots, coefficients and degree that do not make a spline (geomkit's message,
        SciPy's wording for the shapes).
    TypeError
        For a degree that is not an integer, complex or non-numeric values.

    Notes
    -----
    Unlike SciPy's, a geomkit ``BSpline`` is immutable: `t` and `c` are read-only arrays, so
    one spline may be evaluated from many threads at once (the GIL is released during every
    evaluation). Complex coefficients and coefficients that are not finite are refused.
    ``to_scipy()`` and ``from_scipy()`` convert to and from SciPy's class.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import BSpline
    >>> b = BSpline([0, 1, 2, 3, 4], [0.0, 1.0, 0.0], 1)
    >>> b([1.5, 2.0, 2.5]).tolist()
    [0.5, 1.0, 0.5]
    >>> float(b.integrate(1, 3))
    1.0
    """

    __slots__ = ("_core", "_knots", "_coefs", "k", "extrapolate", "axis", "_trailing", "_pad",
                 "_source")
    _source: _geomkit.Model | None

    def __init__(
        self,
        t: ArrayLike,
        c: ArrayLike,
        k: int,
        extrapolate: bool | str = True,
        axis: int = 0,
    ) -> None:
        c = real_array(c, "c")
        axis = _normalize_axis(axis, c.ndim)
        self._setup(t, np.moveaxis(c, axis, 0), k, extrapolate, axis)

    @classmethod
    def construct_fast(
        cls,
        t: ArrayLike,
        c: ArrayLike,
        k: int,
        extrapolate: bool | str = True,
        axis: int = 0,
    ) -> BSpline:
        """A spline from knots and coefficients whose interpolation axis is already first.

        SciPy's ``construct_fast`` skips the checks; geomkit's checks the values all the
        same (the compiled module never sees an invalid spline) and only skips moving the
        axis, as SciPy's does.

        Parameters
        ----------
        t, c, k, extrapolate, axis
            As for `BSpline`, but `c` has shape ``(n, ...)`` whatever `axis` is.

        Returns
        -------
        BSpline
        """
        self = object.__new__(cls)
        c = real_array(c, "c")
        self._setup(t, c, k, extrapolate, _normalize_axis(axis, max(c.ndim, 1)))
        return self

    def _setup(self, t: ArrayLike, c: NDArray[np.float64], k: Any, extrapolate: Any,
               axis: int) -> None:
        k = index(k, "k")
        t = contiguous(t, "t")
        if k < 0:
            raise ValueError("Spline order cannot be negative.")
        if t.ndim != 1:
            raise ValueError("Knot vector must be one-dimensional.")
        if c.ndim < 1:
            raise ValueError("Coefficients must be at least 1-dimensional.")
        n = t.shape[0] - k - 1
        if n < k + 1:
            raise ValueError(f"Need at least {2 * k + 2} knots for degree {k}")
        if c.shape[0] < n:
            raise ValueError("Knots, coefficients and degree are inconsistent.")
        trailing = c.shape[1:]
        # The core's copy is the spline's only storage: `t` and `c` are made from it when
        # read (the caller's arrays are neither kept nor frozen). Coefficients beyond the
        # n the spline uses are kept as SciPy keeps them, in a read-only copy.
        rows = aligned(c[:n]).reshape(n, math.prod(trailing))
        core = _geomkit.Curve(k, t, rows)
        extra = _frozen(np.array(c, dtype=np.float64)) if c.shape[0] > n else None
        self._init(core, extrapolate_value(extrapolate), axis, trailing, None, extra, None)

    def _init(self, core: _geomkit.Curve, extrapolate: bool | str, axis: int,
              trailing: tuple[int, ...], t: NDArray[np.float64] | None,
              c: NDArray[np.float64] | None, pad: str | None) -> None:
        self._core = core
        self.k = core.degree
        self.extrapolate = extrapolate
        self.axis = axis
        self._trailing = trailing
        self._knots = t
        self._coefs = c
        self._pad = pad
        self._source = None

    @classmethod
    def _from_core(cls, core: _geomkit.Curve, extrapolate: bool | str, axis: int,
                   trailing: tuple[int, ...], pad: str | None = None) -> BSpline:
        self = object.__new__(cls)
        self._init(core, extrapolate, axis, trailing, None, None, pad)
        return self

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> BSpline:
        """The spline of a ``bspline_curve`` model file (coefficients of shape (n,) for a
        curve of dimension 1, else (n, dim))."""
        core = _geomkit.Curve.from_model(model)
        self = cls._from_core(core, True, 0, () if core.dim == 1 else (core.dim,))
        self._source = model  # saved as read (with the parameters of its points)
        return self

    def _model(self) -> _geomkit.Model:
        return self._source if self._source is not None else self._core.model()

    # -- SciPy's attributes ---------------------------------------------------------------
    @property
    def t(self) -> NDArray[np.float64]:
        """Knots, shape (n + k + 1,) (a read-only array)."""
        if self._knots is None:
            t = np.empty(self._core.n_knots)
            self._core.knots_into(t)
            self._knots = _frozen(t)
        return self._knots

    @property
    def c(self) -> NDArray[np.float64]:
        """Coefficients, shape (n, ...) with the interpolation axis first (read-only).

        After `derivative` and `antiderivative` they are padded to ``len(t)`` as SciPy
        pads them (zeros, or copies of the last coefficient)."""
        if self._coefs is None:
            core = self._core
            c = np.empty((core.n_coefficients, core.dim))
            core.coefficients_into(c)
            extra = core.n_knots - core.n_coefficients
            if self._pad == "zeros":
                c = np.concatenate([c, np.zeros((extra, core.dim))])
            elif self._pad == "last":
                c = np.concatenate([c, np.repeat(c[-1:], extra, axis=0)])
            self._coefs = _frozen(c.reshape((c.shape[0],) + self._trailing))
        return self._coefs

    # SciPy's private names of the two (some of SciPy's own tests read them).
    _t = t
    _c = c

    @property
    def tck(self) -> tuple[NDArray[np.float64], NDArray[np.float64], int]:
        """``(t, c, k)``, as SciPy's."""
        return self.t, self.c, self.k

    # -- evaluation and calculus ----------------------------------------------------------
    def __call__(self, x: ArrayLike, nu: int = 0,
                 extrapolate: bool | str | None = None) -> NDArray[np.float64]:
        """Values or derivatives of the spline at `x`.

        Parameters
        ----------
        x : array_like
            Points, of any shape (NaN gives NaN).
        nu : int, optional
            Derivative order, >= 0 (default 0: values). Above the degree the derivative is 0.
        extrapolate : bool or 'periodic', optional
            As the constructor's; default `self.extrapolate`.

        Returns
        -------
        ndarray
            Shape: the interpolation axis of `c` replaced by the shape of `x` (SciPy's).

        Raises
        ------
        ValueError
            For a negative `nu`.
        """
        ext = self.extrapolate if extrapolate is None else extrapolate_value(extrapolate)
        nu = index(nu, "nu")
        if nu < 0:
            raise ValueError(f"Cannot do derivative order nu={nu}: give nu >= 0 (or use "
                             "antiderivative)")
        x = np.asarray(x)
        x_shape, x_ndim = x.shape, x.ndim
        xs = contiguous(x.reshape(-1), "x")
        values = np.empty((xs.shape[0], self._core.dim))
        # Orders above k + 1 all give 0 (no overflow of a huge nu on the way to Rust).
        nu_k, how, core = min(nu, self.k + 2), mode(ext), self._core
        chunked(xs.shape[0], lambda a, b: core.eval_into(xs[a:b], nu_k, how, values[a:b]),
                "BSpline")
        out: NDArray[np.float64] = values.reshape(x_shape + self._trailing)
        if self.axis != 0:
            order = list(range(out.ndim))
            order = (order[x_ndim:x_ndim + self.axis] + order[:x_ndim]
                     + order[x_ndim + self.axis:])
            out = out.transpose(order)
        return out

    def derivative(self, nu: int = 1) -> BSpline:
        """The derivative spline of order `nu` (degree k - nu; SciPy's ``splder``).

        Parameters
        ----------
        nu : int, optional
            Order, 0 to k (default 1); a negative order is the antiderivative of order
            -nu (SciPy's ``splder``).

        Returns
        -------
        BSpline
            With the same `extrapolate` and `axis`.

        Raises
        ------
        ValueError
            `nu` above the degree, or knots repeated where the derivative would jump by a
            Dirac delta ("not differentiable nu times").
        """
        nu = index(nu, "nu")
        if nu < 0:
            return self.antiderivative(-nu)
        core = self._core.derivative(min(nu, _LARGEST_ORDER))
        return BSpline._from_core(core, self.extrapolate, self.axis, self._trailing, "zeros")

    def antiderivative(self, nu: int = 1) -> BSpline:
        """The antiderivative spline of order `nu` (degree k + nu, zero at ``t[0]``;
        SciPy's ``splantider``).

        Parameters
        ----------
        nu : int, optional
            Order (default 1); a negative order is the derivative of order -nu.

        Returns
        -------
        BSpline
            With the same `axis`; `extrapolate` 'periodic' becomes False (SciPy's choice:
            the antiderivative of a periodic spline is not periodic).

        Raises
        ------
        ValueError
            A degree k + nu above 15.
        """
        nu = index(nu, "nu")
        if nu < 0:
            return self.derivative(-nu)
        core = self._core.antiderivative(min(nu, _LARGEST_ORDER))
        ext = False if self.extrapolate == "periodic" else self.extrapolate
        return BSpline._from_core(core, ext, self.axis, self._trailing, "last")

    def integrate(self, a: float, b: float,
                  extrapolate: bool | str | None = None) -> NDArray[np.float64]:
        """The definite integral of the spline over ``[a, b]`` (closed form, exact to rounding).

        Parameters
        ----------
        a, b : float
            Limits; ``b < a`` gives the negative.
        extrapolate : bool or 'periodic', optional
            True integrates the continued end pieces, False only the part inside the base
            interval ``t[k] .. t[n]``, 'periodic' whole periods plus the rest. Default
            `self.extrapolate`.

        Returns
        -------
        ndarray
            Shape ``c.shape[1:]`` (a 0-d array for a scalar spline), as SciPy's.

        Notes
        -----
        With ``extrapolate=False`` and ``[a, b]`` wholly outside the base interval the result
        is 0 for every shape of `c` (SciPy gives NaN for multi-dimensional `c` there).
        """
        ext = self.extrapolate if extrapolate is None else extrapolate_value(extrapolate)
        out = np.empty(self._core.dim)
        self._core.integrate_into(real_scalar(a, "a"), real_scalar(b, "b"), mode(ext), out)
        return out.reshape(self._trailing)

    def insert_knot(self, x: float, m: int = 1) -> BSpline:
        """The same spline with the knot `x` inserted `m` times (Boehm's algorithm).

        Parameters
        ----------
        x : float
            The new knot, inside the base interval ``t[k] .. t[n]``.
        m : int, optional
            Its multiplicity (default 1).

        Returns
        -------
        BSpline
            n + m coefficients; a periodic spline (``extrapolate='periodic'``) keeps its
            periodic knots and coefficients (FITPACK's ``insert`` with ``iopt=1``).

        Raises
        ------
        ValueError
            `x` outside the base interval or NaN, ``m <= 0`` or above 10**6, or a knot
            repeated so often that the coefficients would divide by zero.
        """
        x = real_scalar(x, "x")
        m = index(m, "m")
        if m <= 0:
            raise ValueError(f"`m` must be positive, got m = {m}.")
        if m > _MAX_INSERTIONS:
            raise ValueError(f"`m` = {m} insertions: at most {_MAX_INSERTIONS} (each one "
                             "copies the knots and coefficients)")
        core = self._core.insert_knot(x, m, self.extrapolate == "periodic")
        return BSpline._from_core(core, self.extrapolate, self.axis, self._trailing, self._pad)

    # -- conversions ----------------------------------------------------------------------
    def to_scipy(self) -> Any:
        """This spline as a ``scipy.interpolate.BSpline`` (SciPy is imported here only).

        Returns
        -------
        scipy.interpolate.BSpline
            With copies of `t` and `c` (writable, as SciPy's), the same `k`,
            `extrapolate` and `axis`.
        """
        from scipy.interpolate import (  # type: ignore[import-untyped, unused-ignore]
            BSpline as SciPyBSpline,
        )

        return SciPyBSpline.construct_fast(
            self.t.copy(), self.c.copy(), self.k, extrapolate=self.extrapolate, axis=self.axis
        )

    @classmethod
    def from_scipy(cls, spl: Any) -> BSpline:
        """A geomkit ``BSpline`` from a ``scipy.interpolate.BSpline`` (checked as the
        constructor checks).

        Parameters
        ----------
        spl : scipy.interpolate.BSpline
            Or anything with SciPy's attributes ``t``, ``c``, ``k``, ``extrapolate``, ``axis``.

        Returns
        -------
        BSpline
        """
        return cls.construct_fast(spl.t, spl.c, spl.k, spl.extrapolate, spl.axis)

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_rebuild, (self.t, self.c, self.k, self.extrapolate, self.axis))

    def __repr__(self) -> str:
        t = self.t
        return (
            f"BSpline(k={self.k}, {t.shape[0]} knots on [{float(t[self.k])!r}, "
            f"{float(t[t.shape[0] - self.k - 1])!r}], c of shape {self.c.shape}, "
            f"extrapolate={self.extrapolate!r}, axis={self.axis})"
        )


def _rebuild(t: Any, c: Any, k: int, extrapolate: bool | str, axis: int) -> BSpline:
    """Unpickling: `BSpline.construct_fast`."""
    return BSpline.construct_fast(t, c, k, extrapolate, axis)


def _frozen(a: NDArray[np.float64]) -> NDArray[np.float64]:
    a.flags.writeable = False
    return a


def _normalize_axis(axis: Any, ndim: int) -> int:
    """NumPy's axis normalization (an AxisError, a ValueError, when out of range)."""
    return int(normalize_axis_index(index(axis, "axis"), ndim))


def _end(cond: Any, at: float, trailing: tuple[int, ...]) -> list[tuple[int, Any]] | None:
    """One end of SciPy's ``bc_type`` as the compiled module takes it: None (no condition)
    or [(order, 1-D float64 values), ...]."""
    if cond is None:
        return None
    if isinstance(cond, str):
        if cond == "clamped":
            return [(1, np.zeros(1))]
        if cond == "natural":
            return [(2, np.zeros(1))]
        raise ValueError(f"Unknown boundary condition : {cond}")
    try:
        pairs = [tuple(p) for p in cond]
        if not pairs or any(len(p) != 2 for p in pairs):
            raise TypeError
    except TypeError as e:
        raise ValueError(
            "Derivatives, `bc_type`, should be specified as a pair of "
            "iterables of pairs of (order, value)."
        ) from e
    out = []
    for order, value in pairs:
        order = index(order, "a derivative order of bc_type")
        if order < 0:
            raise ValueError(f"Bad boundary conditions at {at}: derivative order {order} is "
                             "below 0")
        values = contiguous(value, "a derivative value of bc_type").reshape(-1)
        size = math.prod(trailing)
        if values.shape[0] not in (1, size):
            raise ValueError(
                f"bc_type: the derivative of order {order} at {at} has {values.shape[0]} "
                f"values, the data {size} per point (shape {trailing})"
            )
        out.append((order, values))
    return out


def make_interp_spline(
    x: ArrayLike,
    y: ArrayLike,
    k: int = 3,
    t: ArrayLike | None = None,
    bc_type: Any = None,
    axis: int = 0,
    check_finite: bool = True,
    *,
    tile: int | None = None,
) -> BSpline:
    """The interpolating B-spline through ``(x[i], y[i])``, as
    ``scipy.interpolate.make_interp_spline``.

    Parameters
    ----------
    x : array_like, shape (n,)
        Abscissas, strictly increasing and finite.
    y : array_like, shape (..., n, ...)
        Ordinates (real, finite), any number of trailing and leading axes.
    k : int, optional
        Degree, 0 to 7 (default 3: cubic).
    t : array_like, shape (nt + k + 1,), optional
        Knots. Default: not-a-knot knots (SciPy's, at the data or, for even k, their
        midpoints), ``x`` with k-fold end knots when `bc_type` gives derivatives, periodic
        knots for 'periodic'.
    bc_type : 2-tuple, str or None, optional
        Boundary conditions: None or 'not-a-knot' (default), 'natural' (zero second
        derivatives), 'clamped' (zero first derivatives), 'periodic' (``y[0] == y[-1]``
        within ``allclose``; derivatives up to k - 1 continuous across), or a pair
        ``(left, right)`` of lists of ``(order, value)``, each `value` of the shape of one
        data point (or a scalar for all coordinates), each side None, 'natural' or
        'clamped' alternatively.
    axis : int, optional
        The interpolation axis of `y` (default 0).
    check_finite : bool, optional
        Accepted for SciPy's signature; geomkit always refuses NaN and infinite data.
    tile : int, optional
        geomkit's addition (keyword-only): solve the system in tiles of `tile`
        coefficients (at least ``geomkit.MIN_TILE_SIZE`` = 2), each from its own data
        points with a halo of at least 64 rows on each side, in parallel: temporary memory
        of a few tiles per thread instead of the whole band, for very long data. The same
        knots, and coefficients equal to the untiled ones within rounding. Where tiles do
        not apply the whole system is solved instead (the same result as without `tile`):
        periodic ends, given knots `t`, degree 0, even degrees with derivative conditions
        (their solve does not decay), and systems whose rows at a seam do not hold to
        rounding. Default None: no tiles.

    Returns
    -------
    BSpline
        Of degree `k` with ``extrapolate=True`` (``'periodic'`` for periodic ends) and the
        given `axis`.

    Raises
    ------
    ValueError
        For data that do not make an interpolating spline (geomkit's message, with SciPy's
        phrases: "Shapes of x", "Expect x to not have duplicates", "Expect x to be a 1D
        strictly increasing sequence", "The number of derivatives at boundaries does not
        match", "First and last points does not match while periodic case expected", ...).
    TypeError
        For a degree or `tile` that is not an integer and values that are not real numbers.

    Notes
    -----
    The knots and coefficients are SciPy's (to rounding, and nearer the exact ones where
    SciPy loses digits); the banded system is solved in O(n k^2) with the GIL released.
    Smoothing and complex values are out of scope.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import make_interp_spline
    >>> x = np.linspace(0, 3, 7)
    >>> s = make_interp_spline(x, x**3, k=3)
    >>> bool(abs(s(1.25) - 1.25**3) < 1e-12)
    True
    >>> x = np.linspace(0, 30, 3000)
    >>> tiled = make_interp_spline(x, np.sin(x), k=5, tile=500)
    >>> bool(np.abs(tiled.c - make_interp_spline(x, np.sin(x), k=5).c).max() < 1e-13)
    True
    """
    # bc_type unpacked as SciPy unpacks it.
    periodic = isinstance(bc_type, str) and bc_type == "periodic"
    if bc_type is None or (isinstance(bc_type, str) and bc_type in ("not-a-knot", "periodic")):
        deriv_l = deriv_r = None
    elif isinstance(bc_type, str):
        deriv_l = deriv_r = bc_type
    else:
        try:
            deriv_l, deriv_r = bc_type
        except (TypeError, ValueError) as e:
            raise ValueError(f"Unknown boundary condition: {bc_type}") from e
    k = index(k, "k")
    if k < 0:
        raise ValueError("Expect non-negative k.")
    tile = tile_size(tile)
    if k > _geomkit.MAX_DEGREE:
        # The library's words; larger integers than Rust's would only overflow on the way.
        raise ValueError(f"degree {k} is not supported: give a degree from 0 to "
                         f"{_geomkit.MAX_SPLINE_DEGREE}")
    x = contiguous(x, "x")
    y = real_array(y, "y")
    axis = _normalize_axis(axis, y.ndim)
    y = np.moveaxis(y, axis, 0)
    if x.ndim != 1:
        raise ValueError(f"Expect x to be a 1D strictly increasing sequence: x has shape "
                         f"{x.shape}")
    if x.shape[0] != y.shape[0]:
        raise ValueError(f"Shapes of x {x.shape} and y {y.shape} are incompatible")
    trailing = y.shape[1:]
    ys = aligned(y.reshape(y.shape[0], math.prod(trailing)))
    first, last = (x[0], x[-1]) if x.shape[0] else (math.nan, math.nan)
    left = _end(deriv_l, first, trailing)
    right = _end(deriv_r, last, trailing)
    knots = None if t is None else contiguous(t, "t")
    if knots is not None and knots.ndim != 1:
        raise ValueError(f"Expect t to be a 1-D sorted array_like: t has shape {knots.shape}")
    report = reporter(ys.size, "make_interp_spline")
    try:
        core = _geomkit.make_interp_spline_curve(x, ys, k, knots, left, right, periodic,
                                                 report, tile)
    finally:
        if report is not None:
            report.close()
    # SciPy's k = 0 and k = 1 splines (its special cases) extrapolate=True even when periodic.
    extrapolate: bool | str = "periodic" if periodic and k >= 2 else True
    return BSpline._from_core(core, extrapolate, axis, trailing)


register_kind("bspline_curve", BSpline._from_model)
