"""`RectBivariateSpline`: SciPy's interpolating (s = 0) spline over a rectangular grid,
computed by geomkit's Rust library with FITPACK's knots and SciPy's semantics."""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import contiguous, index, real_scalar
from ._model import Drawable
from ._progress import chunked, reporter

__all__ = ["RectBivariateSpline"]

# Orders above every degree, passed on as this: the library refuses them in its words,
# where a larger Python integer would only overflow on the way to Rust.
_MAX_ORDER = 2**62


class RectBivariateSpline(Drawable):
    """The interpolating bivariate spline over a rectangular grid, as
    ``scipy.interpolate.RectBivariateSpline(x, y, z, s=0)``.

    Parameters
    ----------
    x, y : array_like, shapes (mx,), (my,)
        Grid coordinates, strictly increasing and finite.
    z : array_like, shape (mx, my)
        Heights ``z[i, j]`` at ``(x[i], y[j])``.
    bbox : array_like of 4 floats or None, optional
        SciPy's boundary of the approximation domain; only the data's own range
        (``[x[0], x[-1], y[0], y[-1]]``, or None entries) is supported.
    kx, ky : int, optional
        Degrees, 1 to 7 (default 3). ``mx > kx`` and ``my > ky`` points are needed.
    s : float, optional
        Must be 0 (or None): the interpolating spline. Smoothing is out of scope.
    maxit : int, optional
        Accepted for SciPy's signature (FITPACK's smoothing iterations); unused.

    Attributes
    ----------
    tck : tuple
        FITPACK's ``(tx, ty, c)``: knots in x and y, coefficients (row-major, x first).
    degrees : tuple of int
        ``(kx, ky)``.
    fp : float
        The residual sum of squares: 0.0 (an interpolant).

    Raises
    ------
    ValueError
        For data that do not make the spline (geomkit's message, SciPy's phrases: "x must
        be strictly increasing", "x dimension of z must have same number of elements as
        x", ...), ``s != 0`` and a `bbox` other than the data's range.
    TypeError
        For degrees that are not integers and values that are not real numbers.

    Notes
    -----
    The knots are FITPACK's for s = 0 (not-a-knot in each direction), the coefficients
    solve the interpolation conditions exactly (to rounding). Evaluation and integration
    follow FITPACK: outside the domain the surface is clamped to its boundary, and
    integrals count only the part inside it. The GIL is released during the build and
    every evaluation; the object is immutable and safe to share between threads.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import RectBivariateSpline
    >>> x, y = np.arange(5.0), np.arange(6.0)
    >>> s = RectBivariateSpline(x, y, np.add.outer(x**2, y))
    >>> bool(abs(s(1.5, 2.5)[0, 0] - 4.75) < 1e-12)
    True
    """

    __slots__ = ("_core", "_tck", "degrees", "_source")
    _source: _geomkit.Model | None
    _core: _geomkit.Surface
    _tck: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None
    degrees: tuple[int, int]

    def __init__(
        self,
        x: ArrayLike,
        y: ArrayLike,
        z: ArrayLike,
        bbox: Sequence[float | None] | NDArray[Any] = [None] * 4,
        kx: int = 3,
        ky: int = 3,
        s: float | None = 0,
        maxit: int = 20,
    ) -> None:
        x = contiguous(x, "x").reshape(-1)
        y = contiguous(y, "y").reshape(-1)
        z = contiguous(z, "z")
        box = np.ravel(np.asarray(bbox, dtype=object))
        if box.shape != (4,):
            raise ValueError(f"bbox shape should be (4,), got {box.shape}")
        if s is not None:
            s = real_scalar(s, "s")
            if not s >= 0.0:
                raise ValueError("s should be s >= 0.0")
            if s != 0.0:
                raise ValueError(
                    f"s={s}: smoothing is out of scope of geomkit; RectBivariateSpline "
                    "builds the interpolating spline (s=0)"
                )
        kx, ky = index(kx, "kx"), index(ky, "ky")
        if kx < 0 or ky < 0:
            raise ValueError(f"degrees kx={kx}, ky={ky} must be from 1 to 7")
        if z.ndim != 2:
            raise ValueError(f"z must be a 2-D array of shape (len(x), len(y)), got shape "
                             f"{z.shape}")
        ends = [x[0], x[-1], y[0], y[-1]] if x.size and y.size else [None] * 4
        for given, end, name in zip(box.tolist(), ends, ("xb", "xe", "yb", "ye")):
            if given is not None and real_scalar(given, "bbox") != end:
                raise ValueError(
                    f"bbox {name}={given}: only the data's range is supported "
                    f"({name}={end}, or None); FITPACK's wider boxes are not"
                )
        report = reporter(z.size, "RectBivariateSpline")
        try:
            self._core = _geomkit.make_interp_surface_heights(x, y, z, kx, ky, report)
        finally:
            if report is not None:
                report.close()
        self._tck = None
        self.degrees = (kx, ky)
        self._source = None

    @classmethod
    def _from_tck(cls, tck: Any, degrees: Any) -> RectBivariateSpline:
        """A spline from FITPACK's ``(tx, ty, c)`` and ``(kx, ky)`` (checked)."""
        tx, ty, c = (contiguous(a, name) for a, name in zip(tck[:3], ("tx", "ty", "c")))
        kx, ky = (index(d, "degree") for d in degrees)
        if tx.ndim != 1 or ty.ndim != 1:
            raise ValueError("knots tx and ty must be one-dimensional")
        shape = (tx.shape[0] - kx - 1, ty.shape[0] - ky - 1)
        if min(shape) < 1 or c.size != shape[0] * shape[1]:
            raise ValueError(
                f"tck: {c.size} coefficients for {tx.shape[0]} x {ty.shape[0]} knots of "
                f"degrees ({kx}, {ky}): expected {max(shape[0], 0) * max(shape[1], 0)}"
            )
        self = object.__new__(cls)
        self._core = _geomkit.Surface(tx, ty, c.reshape(shape), kx, ky)
        self._tck = None
        self.degrees = (kx, ky)
        self._source = None
        return self

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> RectBivariateSpline:
        """The spline of a ``bspline_surface`` model file of heights (degrees 1 to 7)."""
        self = object.__new__(cls)
        self._core = _geomkit.Surface.from_model(model)
        self._tck = None
        self.degrees = self._core.degrees
        self._source = model  # saved as read (with the parameters of its points)
        return self

    def _model(self) -> _geomkit.Model:
        return self._source if self._source is not None else self._core.model()

    @property
    def fp(self) -> float:
        """The residual sum of squares: 0.0 (an interpolant)."""
        return 0.0

    @property
    def tck(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """FITPACK's ``(tx, ty, c)`` (read-only arrays)."""
        if self._tck is None:
            nx, ny = self._core.n_knots
            tx, ty = np.empty(nx), np.empty(ny)
            self._core.knots_into(tx, ty)
            rows, cols = self._core.net_size
            c = np.empty(rows * cols)
            self._core.coefficients_into(c)
            for a in (tx, ty, c):
                a.flags.writeable = False
            self._tck = (tx, ty, c)
        return self._tck

    def get_knots(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The knots ``(tx, ty)`` in x and y.

        Returns
        -------
        tuple of ndarray
            Each with ``k + 1`` end knots at the data's ends and the interior knots between.
        """
        return self.tck[:2]

    def get_coeffs(self) -> NDArray[np.float64]:
        """The spline coefficients, row-major with x first (FITPACK's layout).

        Returns
        -------
        ndarray, shape ((len(tx) - kx - 1) * (len(ty) - ky - 1),)
        """
        return self.tck[2]

    def get_residual(self) -> float:
        """The weighted sum of squared residuals: 0.0 for the interpolating spline.

        Returns
        -------
        float
        """
        return self.fp

    def partial_derivative(self, dx: int, dy: int) -> RectBivariateSpline:
        """The spline of the partial derivative of orders `dx`, `dy` (degrees
        ``(kx - dx, ky - dy)``), as SciPy's ``partial_derivative``.

        Parameters
        ----------
        dx, dy : int
            Orders, 0 <= dx < kx and 0 <= dy < ky.

        Returns
        -------
        RectBivariateSpline
            `self` for orders (0, 0); otherwise a derived spline (its ``fp`` and
            ``get_residual`` raise AttributeError, as SciPy's ``_DerivedBivariateSpline``):
            the coefficient rows differentiated as B-spline curves in x, then the columns
            in y (the library's ``BsplineCurve::derivative_nu``, FITPACK's ``pardtc``).

        Raises
        ------
        ValueError
            Negative orders, or orders not below the degrees.
        """
        dx, dy = _order(dx, "dx"), _order(dy, "dy")
        if (dx, dy) == (0, 0):
            return self
        kx, ky = self.degrees
        if dx >= kx or dy >= ky:
            raise ValueError(f"order of derivative must be less than degree of spline: "
                             f"(dx, dy) = ({dx}, {dy}), degrees ({kx}, {ky})")
        tx, ty, c = self.tck
        rows, cols = self._core.net_size
        # Rows of the net as one curve in x with `cols` numbers per coefficient, then the
        # columns as one curve in y.
        along_x = _geomkit.Curve(kx, tx, c.reshape(rows, cols)).derivative(dx)
        tx2, cx = _curve_arrays(along_x)
        along_y = _geomkit.Curve(ky, ty, np.ascontiguousarray(cx.T)).derivative(dy)
        ty2, cy = _curve_arrays(along_y)
        return _DerivedBivariateSpline._from_tck((tx2, ty2, cy.T), (kx - dx, ky - dy))

    def __call__(self, x: ArrayLike, y: ArrayLike, dx: int = 0, dy: int = 0,
                 grid: bool = True) -> NDArray[np.float64]:
        """Values or partial derivatives on a grid or at points.

        Parameters
        ----------
        x, y : array_like
            With ``grid=True`` the grid's coordinates (each non-decreasing, flattened);
            otherwise points ``(x[i], y[i])``, broadcast against each other.
        dx, dy : int, optional
            Derivative orders in x and y, below the degree in that direction when either is
            nonzero (FITPACK's rule; default 0).
        grid : bool, optional
            Grid (default) or points.

        Returns
        -------
        ndarray
            Shape ``(x.size, y.size)`` on a grid, the broadcast shape at points.

        Raises
        ------
        ValueError
            Grid coordinates that decrease somewhere (or NaN among several), derivative
            orders FITPACK refuses, shapes that do not broadcast.
        """
        dx, dy = _order(dx, "dx"), _order(dy, "dy")
        if grid:
            xs = contiguous(np.asarray(x).reshape(-1), "x")
            ys = contiguous(np.asarray(y).reshape(-1), "y")
            on_grid = np.empty((xs.shape[0], ys.shape[0]))
            core = self._core
            chunked(xs.shape[0],
                    lambda a, b: core.eval_into(xs[a:b], ys, dx, dy, True, on_grid[a:b]),
                    "RectBivariateSpline", per=ys.shape[0])
            return on_grid
        xb, yb = np.broadcast_arrays(np.asarray(x), np.asarray(y))
        shape = xb.shape
        xs = contiguous(xb.reshape(-1), "x")
        ys = contiguous(yb.reshape(-1), "y")
        out = np.empty(xs.shape[0])
        core = self._core
        chunked(xs.shape[0],
                lambda a, b: core.eval_into(xs[a:b], ys[a:b], dx, dy, False, out[a:b]),
                "RectBivariateSpline")
        return out.reshape(shape)

    def ev(self, xi: ArrayLike, yi: ArrayLike, dx: int = 0, dy: int = 0) -> NDArray[np.float64]:
        """Values or partial derivatives at the points ``(xi[i], yi[i])``.

        Parameters
        ----------
        xi, yi : array_like
            Coordinates, broadcast against each other.
        dx, dy : int, optional
            Derivative orders (see `__call__`).

        Returns
        -------
        ndarray
            The broadcast shape of `xi` and `yi`.
        """
        return self.__call__(xi, yi, dx=dx, dy=dy, grid=False)

    def integral(self, xa: float, xb: float, ya: float, yb: float) -> float:
        """The integral over ``[xa, xb] x [ya, yb]`` (closed form; FITPACK's ``dblint``).

        Parameters
        ----------
        xa, xb, ya, yb : float
            Limits; reversed ones give the negative, per direction. Only the part inside
            the domain counts.

        Returns
        -------
        float
        """
        limits = [real_scalar(v, n) for v, n in zip((xa, xb, ya, yb), ("xa", "xb", "ya", "yb"))]
        return self._core.integral(*limits)

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_rebuild, (type(self), self.tck, self.degrees))

    def __repr__(self) -> str:
        (x0, x1), (y0, y1) = (
            (float(t[k]), float(t[-k - 1])) for t, k in zip(self.tck[:2], self.degrees)
        )
        rows, cols = self._core.net_size
        return (f"RectBivariateSpline(kx={self.degrees[0]}, ky={self.degrees[1]}, on "
                f"[{x0!r}, {x1!r}] x [{y0!r}, {y1!r}], {rows} x {cols} coefficients)")


def _order(value: Any, name: str) -> int:
    order = index(value, name)
    if order < 0:
        raise ValueError(f"{name}={order}: derivative orders must be >= 0")
    return min(order, _MAX_ORDER)


def _rebuild(cls: type[RectBivariateSpline], tck: Any, degrees: Any) -> RectBivariateSpline:
    """Unpickling: the spline from its tck."""
    return cls._from_tck(tck, degrees)


def _curve_arrays(core: _geomkit.Curve) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The knots and coefficients (n, dim) of a compiled curve."""
    t = np.empty(core.n_knots)
    c = np.empty((core.n_coefficients, core.dim))
    core.knots_into(t)
    core.coefficients_into(c)
    return t, c


class _DerivedBivariateSpline(RectBivariateSpline):
    """A partial derivative of a `RectBivariateSpline` (`partial_derivative`): evaluates as
    one, but has no residual (SciPy's ``_DerivedBivariateSpline``)."""

    __slots__ = ()
    _why = ("is unavailable: this spline is the partial derivative of another one, not "
            "built from data")

    @property
    def fp(self) -> float:
        """Raises AttributeError (no data were interpolated)."""
        raise AttributeError(f'attribute "fp" {self._why}')

    def get_residual(self) -> float:
        """Raises AttributeError (no data were interpolated)."""
        raise AttributeError(f'method "get_residual" {self._why}')

