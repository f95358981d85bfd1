"""Bézier curves and surfaces and the unified change of their degree (method 1 of geomkit,
spec/bezier-order.md: Nikulin, 2011), computed by geomkit's Rust library.

- `BezierCurve`: a curve in any dimension, polynomial or rational (weights), formula (1);
  evaluation and derivatives over arrays, split, power form (5) both ways; elevation (6)-(8), exact
  reduction (9), the unified change (10), the degree report (real degree, defect), the
  best approximation of a lower degree with its error report, the paper's formula (10) as
  written (exact matrices, or naive f64), exact rational results, and the paper's hand
  edits of the control polygon with how far they move the curve.
- `BezierSurface`: a tensor-product surface over an (n+1)×(m+1) net, formula (11); grid and
  point evaluation, partial derivatives, unit normals, the change of degree per direction (14)-(16), its
  degree report, and the manual change (13) of rows and columns.
- `degree_change_matrix`, `h_matrix`: the paper's matrices (4), (8), (10), exact as
  `fractions.Fraction` or rounded once to float.

Both classes are immutable, pickle, and convert to the model files the CLI reads and writes
(``geomkit.load`` gives them back).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal, NamedTuple, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import aligned, contiguous, index, real_array, real_scalar
from ._model import Drawable, register_kind
from ._progress import chunked, reporter

_T = TypeVar("_T")

__all__ = [
    "ApproxReduction",
    "BezierCurve",
    "BezierSurface",
    "DegreeReport",
    "Deviation",
    "Edit",
    "ReductionError",
    "SurfaceDegreeReport",
    "degree_change_matrix",
    "h_matrix",
]

# Degrees and indices above this are refused here with a ValueError (the library's limits are
# far lower; a larger Python integer would only overflow on the way to Rust).
_MAX_INT = 2**62
# Highest derivative order of a rational curve (its derivatives of every order are nonzero,
# and each costs memory in the order).
_MAX_RATIONAL_ORDER = 64


# --- reports --------------------------------------------------------------------------------


@dataclass(frozen=True)
class DegreeReport:
    """The degree of a curve (or of one direction of a surface) by the residual test.

    Attributes
    ----------
    degree : int
        The formal degree n (number of control points minus one).
    real_degree : int
        The real degree n*: the least degree the curve reduces to exactly, within the
        tolerance (spec §3: the number of nonzero columns of S_n = U_n H_n, decided stably).
    defect : int
        The degree defect d = n - n*.
    residual : float
        The relative residual of the reduction to the real degree (at most the tolerance):
        the largest control-point distance after reducing and elevating back, divided by
        max |u_i|.
    rejected_residual : float or None
        The same for one degree lower (above the tolerance); None when the real degree is 0.
    tolerance : float
        The relative tolerance used.
    """

    degree: int
    real_degree: int
    defect: int
    residual: float
    rejected_residual: float | None
    tolerance: float


@dataclass(frozen=True)
class SurfaceDegreeReport:
    """The degrees of a surface in u (rows of the net) and in v (columns), formula (16).

    Attributes
    ----------
    u, v : DegreeReport
        The report of each direction (all rows or columns decided jointly).
    """

    u: DegreeReport
    v: DegreeReport

    @property
    def degree(self) -> tuple[int, int]:
        """The formal degrees (n, m)."""
        return (self.u.degree, self.v.degree)

    @property
    def real_degree(self) -> tuple[int, int]:
        """The real degrees (n*, m*)."""
        return (self.u.real_degree, self.v.real_degree)

    @property
    def defect(self) -> tuple[int, int]:
        """The defects (d, δ)."""
        return (self.u.defect, self.v.defect)

    @property
    def residual(self) -> tuple[float, float]:
        """The accepted residuals in u and v."""
        return (self.u.residual, self.v.residual)


@dataclass(frozen=True)
class Deviation:
    """How far apart two curves (or surfaces) are over the parameter domain.

    Attributes
    ----------
    max_found : float
        The largest distance found at an evaluated parameter (a distance attained).
    at : float
        The parameter t where it is attained (for surfaces: its u).
    upper_bound : float
        A guaranteed upper bound of the largest distance (rigorous up to a rounding slack
        that is included).
    """

    max_found: float
    at: float
    upper_bound: float


@dataclass(frozen=True)
class ReductionError:
    """The error report of an approximate reduction.

    Attributes
    ----------
    l2 : float
        sqrt(∫_0^1 |p(t) - q(t)|² dt) between the original and the reduced curve.
    linf_bound : float
        A guaranteed bound of max_t |p(t) - q(t)|.
    linf_found : float or None
        The largest distance found (attained at `at`); None for a report read from a model
        file, which keeps the L2 error and the bound only.
    at : float or None
        Where `linf_found` is attained.
    """

    l2: float
    linf_bound: float
    linf_found: float | None = None
    at: float | None = None


class ApproxReduction(NamedTuple):
    """The result of `BezierCurve.reduce_approx`: ``curve, error = c.reduce_approx(3)``."""

    curve: BezierCurve
    error: ReductionError


@dataclass(frozen=True)
class Edit:
    """A hand edit of a control polygon (spec §3).

    Attributes
    ----------
    curve : BezierCurve
        The edited curve.
    index : int
        The index of the vertex removed or inserted.
    deviation : Deviation
        How far the curve moved over t ∈ [0, 1].
    """

    curve: BezierCurve
    index: int
    deviation: Deviation


def _report(t: tuple[int, int, int, float, float | None, float]) -> DegreeReport:
    return DegreeReport(*t)


def _deviation(t: tuple[float, float, float]) -> Deviation:
    return Deviation(*t)


# --- argument shaping -----------------------------------------------------------------------


def _degree(value: Any, name: str) -> int:
    """A degree or index argument: an int >= 0 (TypeError / ValueError otherwise)."""
    k = index(value, name)
    if k < 0:
        raise ValueError(f"{name} must be >= 0, got {k}")
    if k > _MAX_INT:
        raise ValueError(f"{name} = {k} is too large")
    return k


def _order(value: Any, name: str) -> int:
    """A derivative order: an int >= 0; orders above every degree are all alike (zero
    derivatives of polynomials), so a huge one is clipped rather than refused."""
    k = index(value, name)
    if k < 0:
        raise ValueError(f"{name} must be >= 0, got {k}")
    return min(k, _MAX_INT)


def _tolerance(tolerance: Any) -> float | None:
    """None or a real number (the library checks that it is finite and > 0)."""
    if tolerance is None:
        return None
    return real_scalar(tolerance, "tolerance")


def _two_degrees(to: Any) -> tuple[int, int]:
    """Target degrees (n', m') of a surface."""
    if isinstance(to, (str, bytes)) or not isinstance(to, Sequence | np.ndarray):
        raise TypeError(
            f"a surface takes one target degree per direction, to=(n, m); got {to!r}"
        )
    if len(to) != 2:
        raise ValueError(
            f"a surface takes one target degree per direction, to=(n, m); got {len(to)} values"
        )
    return (_degree(to[0], "to[0]"), _degree(to[1], "to[1]"))


def _reporting(call: Callable[[Any], _T], work: int) -> _T:
    """``call(progress)``: a degree change, with `progress` the callback of a bar inside
    ``geomkit.progress()`` when its `work` (multiply-adds, roughly) reaches the block's
    `min_points`, else None (the core then runs as before)."""
    report = reporter(work, "degree change")
    try:
        return call(report)
    finally:
        if report is not None:
            report.close()


def _surface_steps(us: NDArray[np.float64], vs: NDArray[np.float64], grid: bool,
                   out: NDArray[np.float64],
                   run: Any) -> None:
    """``run(u, v, out)`` over the grid u × v (`grid`: steps of rows of u, `out` of shape
    (len(u), len(v), ...)) or the pairs (steps of pairs), with a bar inside
    ``geomkit.progress()`` (`chunked`); every point is computed on its own, so the steps
    give the bits of one call."""
    if grid:
        chunked(us.shape[0], lambda a, b: run(us[a:b], vs, out[a:b]), "BezierSurface",
                per=vs.shape[0])
    else:
        chunked(us.shape[0], lambda a, b: run(us[a:b], vs[a:b], out[a:b]), "BezierSurface")


def _surface_parameters(
    u: ArrayLike, v: ArrayLike, grid: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[int, ...]]:
    """Surface parameters as two C-contiguous 1-D arrays and the shape of the result's
    points: on a grid (u and v 1-D, a scalar one value) (len(u), len(v)); at pairs, their
    broadcast shape (u and v broadcast and flattened)."""
    us, vs = real_array(u, "u"), real_array(v, "v")
    if grid:
        if us.ndim > 1 or vs.ndim > 1:
            raise ValueError(
                f"on a grid u and v must be 1-D, got shapes {us.shape} and {vs.shape} "
                "(use grid=False for pairs)"
            )
        us, vs = us.reshape(-1), vs.reshape(-1)
        shape: tuple[int, ...] = (us.shape[0], vs.shape[0])
    else:
        try:
            us, vs = np.broadcast_arrays(us, vs)
        except ValueError as e:
            raise ValueError(f"u and v do not broadcast together: {e}") from None
        shape = us.shape
        us, vs = us.reshape(-1), vs.reshape(-1)
    return aligned(us), aligned(vs), shape


def _points(points: ArrayLike, name: str, ndim: int) -> NDArray[np.float64]:
    """Control points as a C-contiguous float64 array of `ndim` dimensions, none empty."""
    a = contiguous(points, name)
    if a.ndim != ndim:
        shape = "(n + 1, dim)" if ndim == 2 else "(n + 1, m + 1, dim)"
        raise ValueError(f"{name} must have shape {shape}, got an array of shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"{name} must not be empty, got an array of shape {a.shape}")
    return a


def _frozen(a: NDArray[Any]) -> NDArray[Any]:
    a.flags.writeable = False
    return a


def _fractions(rows: int, cols: int, entries: list[tuple[str, str]]) -> NDArray[np.object_]:
    """Hexadecimal (numerator, denominator) pairs as an object array of Fractions."""
    out = np.empty(rows * cols, dtype=object)
    for k, (p, q) in enumerate(entries):
        out[k] = Fraction(int(p, 16), int(q, 16))
    return out.reshape(rows, cols)


def _matrix(
    exact_matrix: tuple[int, int, list[tuple[str, str]]], exact: bool
) -> NDArray[Any]:
    m = _fractions(*exact_matrix)
    if exact:
        return m
    # float(Fraction) is correctly rounded: the exact entries rounded once.
    return np.array([[float(x) for x in row] for row in m], dtype=np.float64).reshape(m.shape)


def degree_change_matrix(n: int, n_new: int, *, exact: bool = True) -> NDArray[Any]:
    """The paper's unified degree-change matrix H_n E_(n+1,n'+1) H_(n')^-1.

    Formula (10) of spec/bezier-order.md: U_(n') = U_n · M, with the control points as the
    columns of U. For n' >= n it is the elevation matrix (8), with entries
    C(n,i) C(n'-n, j-i) / C(n',j); for n' < n it reduces exactly only curves whose degree
    defect is at least n - n' (otherwise it truncates the power form at t = 0).

    Parameters
    ----------
    n : int
        The current degree, 0 to ``MAX_PAPER_DEGREE`` (100).
    n_new : int
        The new degree, 0 to 100.
    exact : bool, optional
        True (default): an object array of `fractions.Fraction`; False: float64 entries,
        each the exact value rounded once.

    Returns
    -------
    ndarray, shape (n + 1, n_new + 1)

    Raises
    ------
    ValueError
        For a negative degree or one above 100.
    TypeError
        For degrees that are not integers.

    Examples
    --------
    The paper's Example 1, degree 3 to 5 in one step:

    >>> from geomkit import degree_change_matrix
    >>> [str(x) for x in degree_change_matrix(3, 5)[1]]
    ['0', '3/5', '3/5', '3/10', '0', '0']
    """
    return _matrix(
        _geomkit.degree_change_matrix(_degree(n, "n"), _degree(n_new, "n_new")), exact
    )


def h_matrix(n: int, *, exact: bool = True) -> NDArray[Any]:
    """The matrix H_n of formula (4): h_ij = (-1)^(j-i) C(n,j) C(j,i), i <= j.

    It converts the Bernstein basis to powers, B_n(t) = H_n T_n(t), and control points to
    power coefficients, S_n = U_n H_n (5).

    Parameters
    ----------
    n : int
        The degree, 0 to 100.
    exact : bool, optional
        True (default): `fractions.Fraction` entries; False: float64.

    Returns
    -------
    ndarray, shape (n + 1, n + 1)

    Raises
    ------
    ValueError
        For a negative degree or one above 100.

    Examples
    --------
    >>> from geomkit import h_matrix
    >>> h_matrix(2, exact=False).tolist()
    [[1.0, -2.0, 1.0], [0.0, 2.0, -2.0], [0.0, 0.0, 1.0]]
    """
    return _matrix(_geomkit.h_matrix(_degree(n, "n")), exact)


# --- curves ---------------------------------------------------------------------------------


class BezierCurve(Drawable):
    """A Bézier curve in any dimension, polynomial or rational.

    .. math:: p(t) = \\sum_{i=0}^{n} b_{n,i}(t)\\, u_i, \\qquad
              b_{n,i}(t) = \\binom{n}{i} t^i (1 - t)^{n-i}, \\quad t \\in [0, 1]

    (formula (1) of spec/bezier-order.md); with weights, the rational curve
    :math:`p(t) = \\sum w_i b_{n,i}(t) u_i / \\sum w_i b_{n,i}(t)`.

    Parameters
    ----------
    points : array_like, shape (n + 1, dim)
        The control points u_0 .. u_n (finite).
    weights : array_like, shape (n + 1,), optional
        Weights (finite, > 0): a rational curve. Its degree changes through homogeneous
        coordinates (w_i u_i, w_i).

    Attributes
    ----------
    points : ndarray, shape (n + 1, dim)
        The control points (read-only).
    weights : ndarray or None
        The weights (read-only), None for a polynomial curve.
    degree : int
        The formal degree n.
    dim : int
        The dimension of the points.
    is_rational : bool
        Whether the curve has weights.
    reduction_error : ReductionError or None
        The error report of the approximate reduction that made the curve (kept in its
        model file), None otherwise.

    Raises
    ------
    ValueError
        For an empty array, a wrong shape, a number that is not finite, a weight that is
        not > 0 or a wrong number of weights.
    TypeError
        For values that are not real numbers.

    Examples
    --------
    The paper's Example 2: a quintic whose real degree is 3.

    >>> import numpy as np
    >>> from geomkit import BezierCurve
    >>> q = BezierCurve([[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]])
    >>> q.degree_report().real_degree
    3
    >>> cubic = q.reduce(3)
    >>> bool(np.allclose(cubic.elevate(5).points, q.points, rtol=0, atol=1e-13))
    True
    >>> q(0.5).tolist()
    [15.0, 11.25]
    """

    __slots__ = ("_core", "_points", "_weights")

    def __init__(self, points: ArrayLike, weights: ArrayLike | None = None) -> None:
        pts = _points(points, "points", 2)
        w = None
        if weights is not None:
            w = contiguous(weights, "weights")
            if w.ndim != 1:
                raise ValueError(f"weights must be 1-D, got an array of shape {w.shape}")
            if w.shape[0] != pts.shape[0]:
                raise ValueError(
                    f"{w.shape[0]} weights for {pts.shape[0]} control points "
                    "(give one weight per point)"
                )
        self._init(_geomkit.BezierCurveCore(pts, w))

    def _init(self, core: _geomkit.BezierCurveCore) -> None:
        self._core = core
        self._points: NDArray[np.float64] | None = None
        self._weights: NDArray[np.float64] | None = None

    @classmethod
    def _wrap(cls, core: _geomkit.BezierCurveCore) -> BezierCurve:
        self = object.__new__(cls)
        self._init(core)
        return self

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> BezierCurve:
        """The curve of a model of kind ``"bezier_curve"`` (`geomkit.load`)."""
        return cls._wrap(_geomkit.BezierCurveCore.from_model(model))

    def _model(self) -> _geomkit.Model:
        return self._core.to_model()

    # -- attributes ------------------------------------------------------------------------

    @property
    def points(self) -> NDArray[np.float64]:
        """The control points u_0 .. u_n, shape (n + 1, dim), read-only."""
        if self._points is None:
            p = np.empty((self._core.degree + 1, self._core.dim))
            self._core.points_into(p)
            self._points = _frozen(p)
        return self._points

    @property
    def weights(self) -> NDArray[np.float64] | None:
        """The weights of a rational curve, shape (n + 1,), read-only; None otherwise."""
        if not self._core.is_rational:
            return None
        if self._weights is None:
            w = np.empty(self._core.degree + 1)
            self._core.weights_into(w)
            self._weights = _frozen(w)
        return self._weights

    @property
    def degree(self) -> int:
        """The formal degree n."""
        return self._core.degree

    @property
    def dim(self) -> int:
        """The dimension of the points."""
        return self._core.dim

    @property
    def is_rational(self) -> bool:
        """Whether the curve has weights."""
        return self._core.is_rational

    @property
    def reduction_error(self) -> ReductionError | None:
        """The error report of the approximate reduction that made the curve, if any."""
        e = self._core.reduction_error
        return None if e is None else ReductionError(*e)

    # -- evaluation ------------------------------------------------------------------------

    def __call__(self, t: ArrayLike, nu: int = 0) -> NDArray[np.float64]:
        """The points (or derivatives of order `nu`) at the parameters `t`.

        Formula (1) by the Bernstein–Horner scheme (de Casteljau above degree 60), with the
        GIL released; rational curves by de Casteljau on the homogeneous points and the
        quotient rule for derivatives. Parameters outside [0, 1] extrapolate.

        Parameters
        ----------
        t : array_like
            Parameters of any shape (finite).
        nu : int, optional
            The derivative order (default 0, the points).

        Returns
        -------
        ndarray, shape ``t.shape + (dim,)``

        Raises
        ------
        ValueError
            For a parameter that is not finite, a negative order (or above 64 for a rational
            curve).
        TypeError
            For parameters that are not real numbers, an order that is not an integer.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> c = BezierCurve([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]])
        >>> c([0.0, 0.5]).tolist()
        [[0.0, 0.0], [1.0, 1.0]]
        >>> c(0.25, nu=1).tolist()
        [2.0, 2.0]
        """
        nu = _order(nu, "nu")
        if self._core.is_rational:
            if nu > _MAX_RATIONAL_ORDER:
                raise ValueError(
                    f"nu = {nu}: derivatives of a rational curve go up to order "
                    f"{_MAX_RATIONAL_ORDER}"
                )
        else:
            nu = min(nu, self._core.degree + 1)
        ts = real_array(t, "t")
        shape = ts.shape
        flat = aligned(ts.reshape(-1))
        out = np.empty((flat.shape[0], self._core.dim))
        core = self._core
        chunked(flat.shape[0], lambda a, b: core.eval_into(flat[a:b], nu, out[a:b]),
                "BezierCurve")
        return out.reshape(shape + (self._core.dim,))

    def derivative(self, nu: int = 1) -> BezierCurve:
        """The derivative curve (hodograph) of order `nu`, a Bézier curve of degree n - nu.

        p'(t) = n Σ b_(n-1,i)(t) (u_(i+1) - u_i).

        Parameters
        ----------
        nu : int, optional
            The order (default 1); above the degree, the zero curve of degree 0.

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            For a rational curve (its derivative is not a Bézier curve of the same kind;
            evaluate it with ``curve(t, nu=...)``) or a negative order.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[0.0], [1.0], [3.0]]).derivative().points.tolist()
        [[2.0], [4.0]]
        """
        nu = min(_order(nu, "nu"), self._core.degree + 1)
        core = self._core
        for _ in range(nu):
            core = core.derivative()
        return BezierCurve._wrap(core)

    def split(self, t: float) -> tuple[BezierCurve, BezierCurve]:
        """The two pieces of the curve over [0, t] and [t, 1] (de Casteljau).

        Parameters
        ----------
        t : float
            The split parameter (finite; outside [0, 1] the pieces extrapolate).

        Returns
        -------
        (BezierCurve, BezierCurve)
            Each of the same degree, reparametrized to [0, 1].

        Raises
        ------
        ValueError
            For a parameter that is not finite (or, for a rational curve, one that makes a
            weight <= 0).

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> left, right = BezierCurve([[0.0], [2.0]]).split(0.25)
        >>> left.points.tolist(), right.points.tolist()
        ([[0.0], [0.5]], [[0.5], [2.0]])
        """
        a, b = self._core.split(real_scalar(t, "t"))
        return BezierCurve._wrap(a), BezierCurve._wrap(b)

    def power_coefficients(self) -> NDArray[np.float64]:
        """The power form p(t) = Σ s_j t^j: S_n = U_n H_n (formula (5)), s_j = C(n,j) Δ^j u_0.

        Returns
        -------
        ndarray, shape (n + 1, dim)
            Row j is s_j.

        Raises
        ------
        ValueError
            For a rational curve.

        Examples
        --------
        The paper's Example 2: S_5 has two zero columns (here: rows).

        >>> from geomkit import BezierCurve
        >>> q = BezierCurve([[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]])
        >>> q.power_coefficients().T.tolist()
        [[10.0, 60.0, -150.0, 100.0, 0.0, 0.0], [0.0, 30.0, 0.0, -30.0, 0.0, 0.0]]
        """
        out = np.empty((self._core.degree + 1, self._core.dim))
        self._core.power_into(out)
        return out

    @classmethod
    def from_power(cls, coefficients: ArrayLike) -> BezierCurve:
        """The polynomial curve p(t) = Σ s_j t^j of the power-form coefficients.

        U_n = S_n H_n^-1 with the closed-form inverse (H_n^-1)_ij = C(j,i) / C(n,i)
        (formula (5)), accumulated in double-double.

        Parameters
        ----------
        coefficients : array_like, shape (n + 1, dim)
            Row j is s_j, the coefficient of t^j (finite).

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            For an empty array, a wrong shape or a number that is not finite.

        Examples
        --------
        p(t) = (t, t²):

        >>> from geomkit import BezierCurve
        >>> BezierCurve.from_power([[0, 0], [1, 0], [0, 1]]).points.tolist()
        [[0.0, 0.0], [0.5, 0.0], [1.0, 1.0]]
        """
        return cls._wrap(
            _geomkit.BezierCurveCore.from_power(_points(coefficients, "coefficients", 2))
        )

    # -- change of degree ------------------------------------------------------------------

    def elevate(self, to: int) -> BezierCurve:
        """The same curve with degree `to` >= n, in one step (closed form (8)).

        u'_j = Σ_i C(n,i) C(n'-n, j-i) / C(n',j) u_i, weights accumulated in double-double:
        each new point within eps·max|u| of its exact value.

        Parameters
        ----------
        to : int
            The new degree, >= the current one.

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            When `to` is below the degree, or the elevation matrix would be too large.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[0.0], [3.0], [6.0]]).elevate(3).points.ravel().tolist()
        [0.0, 2.0, 4.0, 6.0]
        """
        to = _degree(to, "to")
        return BezierCurve._wrap(_reporting(lambda p: self._core.elevate(to, p),
                                            (self.degree + 1) * (to + 1) * self.dim))

    def reduce(self, to: int, tolerance: float | None = None) -> BezierCurve:
        """The same curve with degree `to` <= n: exact reduction (formula (9), done stably).

        Least squares on the elevation matrix with iterative refinement; accepted when
        re-elevating reproduces every control point within ``tolerance · max|u_i|``
        (default 1e-12). Rational curves reduce through homogeneous coordinates.

        Parameters
        ----------
        to : int
            The new degree, at least the real degree (`degree_report`).
        tolerance : float, optional
            The relative tolerance of the residual test (default 1e-12).

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            When the degree defect does not allow it (the message names the real degree; use
            `reduce_approx` for the best approximation), when `to` is above the degree, or for
            a tolerance that is not finite and > 0.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[0.0], [2.0], [4.0], [6.0]]).reduce(1).points.ravel().tolist()
        [0.0, 6.0]
        """
        to, tol = _degree(to, "to"), _tolerance(tolerance)
        return BezierCurve._wrap(_reporting(lambda p: self._core.reduce(to, tol, p),
                                            (self.degree + 1) * (to + 1) * self.dim))

    def change_degree(self, to: int, tolerance: float | None = None) -> BezierCurve:
        """The unified change of degree, formula (10), done stably: `elevate` when `to` >= n,
        exact `reduce` otherwise.

        Parameters
        ----------
        to : int
            The new degree.
        tolerance : float, optional
            The relative tolerance of a reduction (default 1e-12).

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            As `elevate` and `reduce`.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[0.0], [1.0]]).change_degree(2).points.ravel().tolist()
        [0.0, 0.5, 1.0]
        """
        to, tol = _degree(to, "to"), _tolerance(tolerance)
        return BezierCurve._wrap(
            _reporting(lambda p: self._core.change_degree(to, tol, p),
                       (self.degree + 1) * (to + 1) * self.dim)
        )

    def degree_report(self, tolerance: float | None = None) -> DegreeReport:
        """The formal degree, real degree and degree defect, by the residual test (spec §3).

        The real degree is the least k whose reduction, elevated back, reproduces the
        control points within ``tolerance · max|u_i|``; never through the power form. For a
        rational curve: the degrees of its homogeneous curve.

        Parameters
        ----------
        tolerance : float, optional
            The relative tolerance (default 1e-12).

        Returns
        -------
        DegreeReport

        Raises
        ------
        ValueError
            For a tolerance that is not finite and > 0, or a degree above 1024.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> r = BezierCurve([[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]).degree_report()
        >>> (r.degree, r.real_degree, r.defect)
        (5, 3, 2)
        """
        return _report(self._core.degree_report(_tolerance(tolerance)))

    def reduction_residual(self, k: int) -> float:
        """The relative residual of the reduction to degree `k` (0 for k >= n): the largest
        control-point distance after reducing and elevating back, divided by max|u_i|.

        Parameters
        ----------
        k : int
            The degree.

        Returns
        -------
        float

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> round(BezierCurve([[0.0], [1.0], [0.0]]).reduction_residual(1), 12)
        0.666666666667
        """
        return self._core.reduction_residual(_degree(k, "k"))

    def reduce_approx(
        self,
        to: int,
        continuity: tuple[int | None, int | None] = (None, None),
        norm: Literal["l2", "chebyshev"] = "l2",
    ) -> ApproxReduction:
        """The best approximation of degree `to` < n, with its error report (spec §5).

        Minimizes ∫_0^1 |p(t) - q(t)|² dt ("l2") or the Chebyshev-weighted
        ∫ |p - q|² / sqrt(t(1-t)) dt ("chebyshev", near-best in L∞), keeping the derivatives
        0..α at t = 0 and 0..β at t = 1 when ``continuity=(α, β)`` asks for it.

        Parameters
        ----------
        to : int
            The new degree, below the current one.
        continuity : (int or None, int or None), optional
            C^α continuity at t = 0 and C^β at t = 1; None leaves that end free.
        norm : {"l2", "chebyshev"}, optional
            The norm minimized (default "l2").

        Returns
        -------
        ApproxReduction
            ``(curve, error)``: the reduced curve (which keeps the report for its model
            file) and a `ReductionError` with the L2 error (exact up to rounding), the
            guaranteed L∞ bound (at most 1% above the largest distance found, plus a
            rounding slack) and the largest distance found with its parameter.

        Raises
        ------
        ValueError
            When `to` is not below the degree, the continuity fixes more than to + 1 points,
            for an unknown norm, or for a rational curve.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> c = BezierCurve([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [3.0, 0.0]])
        >>> line, err = c.reduce_approx(1, continuity=(0, 0))
        >>> line.points.tolist()
        [[0.0, 0.0], [3.0, 0.0]]
        >>> err.linf_bound >= err.linf_found > 0
        True
        """
        if not isinstance(continuity, (tuple, list)) or len(continuity) != 2:
            raise TypeError(
                f"continuity must be a pair (alpha, beta) of int or None, got {continuity!r}"
            )
        start, end = (None if c is None else _degree(c, "continuity") for c in continuity)
        if not isinstance(norm, str):
            raise TypeError(f"norm must be 'l2' or 'chebyshev', got {norm!r}")
        core, l2, (found, at, bound) = self._core.reduce_approx(
            _degree(to, "to"), start, end, norm
        )
        return ApproxReduction(BezierCurve._wrap(core), ReductionError(l2, bound, found, at))

    def deviation_from(self, other: BezierCurve) -> Deviation:
        """How far this curve is from `other` over t ∈ [0, 1]: max_t |p(t) - q(t)|.

        Guaranteed bound by subdivision of the difference (convex hull property), both
        curves elevated to the common degree.

        Parameters
        ----------
        other : BezierCurve
            A polynomial curve of the same dimension (any degree).

        Returns
        -------
        Deviation

        Raises
        ------
        ValueError
            For curves of different dimensions, or rational ones.
        TypeError
            When `other` is not a `BezierCurve`.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> d = BezierCurve([[0.0], [0.0]]).deviation_from(BezierCurve([[0.0], [2.0], [0.0]]))
        >>> (d.max_found, d.at)
        (1.0, 0.5)
        """
        if not isinstance(other, BezierCurve):
            raise TypeError(f"other must be a BezierCurve, got {type(other).__name__}")
        return _deviation(self._core.deviation_from(other._core))

    # -- the paper's formula as written ----------------------------------------------------

    def change_degree_paper(self, to: int) -> BezierCurve:
        """The paper's formula (10) as written: U_(n') = U_n H_n E H_(n')^-1, with the exact
        matrix rounded once to f64.

        For `to` >= n this is the elevation (8); for `to` at least the real degree an exact
        reduction; below the real degree it **truncates the power form at t = 0** (not an
        approximation in any norm: see `reduce_approx`).

        Parameters
        ----------
        to : int
            The new degree (both degrees at most 100).

        Returns
        -------
        BezierCurve

        Raises
        ------
        ValueError
            For a rational curve, a degree above 100, or a result that overflows.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> q = BezierCurve([[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]])
        >>> q.change_degree_paper(3).points.round(12).tolist()
        [[10.0, 0.0], [30.0, 10.0], [-0.0, 20.0], [20.0, 0.0]]
        """
        return BezierCurve._wrap(self._core.change_degree_paper(_degree(to, "to")))

    def paper_formula_f64(self, to: int) -> NDArray[np.float64]:
        """The paper's formula (10) evaluated naively in f64, as a direct program of it would.

        S = U_n H_n (entries formed in f64), keep or pad n'+1 columns, multiply by
        H_(n')^-1. Kept for comparison: the power form is badly conditioned, and this loses
        every digit near degree 20-30 (`change_degree_paper` and `change_degree` do not).

        Parameters
        ----------
        to : int
            The new degree (both degrees at most 100).

        Returns
        -------
        ndarray, shape (to + 1, dim)
            The new control points (possibly not finite).

        Raises
        ------
        ValueError
            For a rational curve or a degree above 100.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[0.0], [3.0], [6.0]]).paper_formula_f64(3).ravel().tolist()
        [0.0, 2.0, 4.0, 6.0]
        """
        to = _degree(to, "to")
        if to > _geomkit.MAX_PAPER_DEGREE:
            # Refused by the compiled module too; checked first so as not to allocate.
            self._core.change_degree_paper(to)
        out = np.empty((to + 1, self._core.dim))
        self._core.paper_formula_f64_into(to, out)
        return out

    def real_degree_exact(self) -> int:
        """The real degree in exact arithmetic: n minus the number of zero power coefficients
        at the right end of S_n = U_n H_n, with the control points' exact (binary) values.

        Returns
        -------
        int

        Raises
        ------
        ValueError
            For a rational curve or a degree above 100.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> BezierCurve([[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]).real_degree_exact()
        3
        """
        return self._core.real_degree_exact()

    def change_degree_exact(self, to: int) -> NDArray[np.object_]:
        """Formula (10) in exact rational arithmetic on the exact values of the points.

        Parameters
        ----------
        to : int
            The new degree, at least `real_degree_exact()` (both degrees at most 100).

        Returns
        -------
        ndarray of fractions.Fraction, shape (to + 1, dim)

        Raises
        ------
        ValueError
            When `to` is below the exact real degree (the message names it), for a rational
            curve or a degree above 100.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> [str(x) for x in BezierCurve([[0.0], [1.0]]).change_degree_exact(3).ravel()]
        ['0', '1/3', '2/3', '1']
        """
        to = _degree(to, "to")
        entries = self._core.change_degree_exact(to)
        return _fractions(to + 1, self._core.dim, entries)

    # -- hand edits ------------------------------------------------------------------------

    def _edit(self, result: tuple[_geomkit.BezierCurveCore, int,
                                  tuple[float, float, float]]) -> Edit:
        core, i, dev = result
        return Edit(BezierCurve._wrap(core), i, _deviation(dev))

    def remove_vertex(self, index: int) -> Edit:
        """Removes control point `index` (spec §3: the degree drops by one and the shape
        changes), reporting how far the curve moved.

        Parameters
        ----------
        index : int
            0 to n.

        Returns
        -------
        Edit
            The new curve, the index, and how far the curve moved.

        Raises
        ------
        ValueError
            For an index out of range, removing the only point, or a rational curve.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> e = BezierCurve([[0.0], [1.0], [2.0]]).remove_vertex(1)
        >>> e.curve.points.ravel().tolist(), e.deviation.max_found
        ([0.0, 2.0], 0.0)
        """
        return self._edit(self._core.remove_vertex(_degree(index, "index")))

    def insert_vertex(self, index: int, point: ArrayLike) -> Edit:
        """Inserts `point` before control point `index` (index n + 1 appends); the degree
        rises by one and the shape changes.

        Parameters
        ----------
        index : int
            0 to n + 1.
        point : array_like, shape (dim,)
            The new control point (finite).

        Returns
        -------
        Edit
            The new curve, the index, and how far the curve moved.

        Raises
        ------
        ValueError
            For an index out of range, a point of another dimension or not finite, or a
            rational curve.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> e = BezierCurve([[0.0], [2.0]]).insert_vertex(1, [3.0])
        >>> e.curve.points.ravel().tolist(), e.deviation.max_found
        ([0.0, 3.0, 2.0], 1.0)
        """
        p = contiguous(point, "point")
        if p.ndim != 1:
            raise ValueError(f"point must be 1-D (dim,), got an array of shape {p.shape}")
        return self._edit(self._core.insert_vertex(_degree(index, "index"), p))

    def remove_middle_vertex(self) -> Edit:
        """Removes the middle vertex m = round(n/2), the one of least peak weight b_nm(m/n)
        (for odd n, the one of the two whose removal moves the curve less).

        Its removal still re-weights every other vertex; the `Edit` says how far the curve
        moved (not always the least of all removals).

        Returns
        -------
        Edit

        Raises
        ------
        ValueError
            For a curve of one point, or a rational curve.

        Examples
        --------
        >>> from geomkit import BezierCurve
        >>> e = BezierCurve([[0.0], [1.0], [4.0], [1.0], [0.0]]).remove_middle_vertex()
        >>> e.index, e.curve.degree
        (2, 3)
        """
        return self._edit(self._core.remove_middle_vertex())

    # -- Python protocol -------------------------------------------------------------------

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_curve_from_json, (self.to_json(),))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, BezierCurve):
            return NotImplemented
        w, v = self.weights, other.weights
        return (
            self.points.shape == other.points.shape
            and bool(np.array_equal(self.points, other.points))
            and (w is None) == (v is None)
            and (w is None or v is None or bool(np.array_equal(w, v)))
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        kind = "rational " if self.is_rational else ""
        extra = ""
        e = self.reduction_error
        if e is not None:
            extra = f", reduction error L2 {e.l2:.3g}, L∞ <= {e.linf_bound:.3g}"
        return (
            f"<geomkit.BezierCurve: {kind}degree {self.degree} in R^{self.dim} "
            f"({self.degree + 1} control points{extra})>"
        )


def _curve_from_json(text: str) -> BezierCurve:
    """Unpickling: the curve of its model file."""
    return BezierCurve._from_model(_geomkit.parse_model(text))


# --- surfaces -------------------------------------------------------------------------------


class BezierSurface(Drawable):
    """A tensor-product Bézier surface over an (n+1)×(m+1) net of points in any dimension,
    polynomial or rational.

    .. math:: p(u, v) = \\sum_{i=0}^{n} \\sum_{j=0}^{m} b_{n,i}(u)\\, b_{m,j}(v)\\, u_{ij},
              \\quad (u, v) \\in [0, 1]^2

    (formula (11) of spec/bezier-order.md; the paper's (t, τ) are (u, v)). With weights
    w_ij the surface is rational,
    p = Σ Σ w_ij b_{n,i}(u) b_{m,j}(v) u_ij / Σ Σ w_ij b_{n,i}(u) b_{m,j}(v); its degree
    changes through the homogeneous net (w_ij u_ij, w_ij), where it is polynomial, so the
    shape is kept exactly as for polynomial surfaces (quadrics such as spheres and
    cylinders stay exact).

    Parameters
    ----------
    net : array_like, shape (n + 1, m + 1, dim)
        The control net, ``net[i, j]`` the point u_ij (row i along u, column j along v).
    weights : array_like, shape (n + 1, m + 1), optional
        The weights w_ij of a rational surface (finite, > 0).

    Attributes
    ----------
    net : ndarray, shape (n + 1, m + 1, dim)
        The net (read-only).
    weights : ndarray, shape (n + 1, m + 1), or None
        The weights of a rational surface (read-only); None for a polynomial one.
    is_rational : bool
        Whether the surface has weights.
    degree : (int, int)
        The formal degrees (n, m).
    dim : int
        The dimension of the points.

    Raises
    ------
    ValueError
        For an empty net, a wrong shape or a number that is not finite.
    TypeError
        For values that are not real numbers.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import BezierSurface
    >>> s = BezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]])
    >>> s(0.5, 0.5).tolist()
    [[[0.5, 0.5, 0.25]]]
    >>> e = s.elevate((3, 2))
    >>> e.degree, e.degree_report().real_degree
    ((3, 2), (1, 1))

    A quarter cylinder of radius 1 (a rational quadratic in u) stays on the cylinder when
    its degrees change:

    >>> h = np.sqrt(0.5)
    >>> c = BezierSurface([[[1, 0, 0], [1, 0, 2]], [[1, 1, 0], [1, 1, 2]], [[0, 1, 0], [0, 1, 2]]],
    ...                   weights=[[1, 1], [h, h], [1, 1]])
    >>> p = c.elevate((5, 3))(np.linspace(0, 1, 7), [0.5])
    >>> bool(np.allclose(np.hypot(p[..., 0], p[..., 1]), 1.0, rtol=0, atol=1e-15))
    True
    >>> c.elevate((5, 3)).degree_report().real_degree
    (2, 1)
    """

    __slots__ = ("_core", "_net", "_weights")

    def __init__(self, net: ArrayLike, weights: ArrayLike | None = None) -> None:
        pts = _points(net, "net", 3)
        w = None
        if weights is not None:
            w = contiguous(weights, "weights")
            if w.shape != pts.shape[:2]:
                raise ValueError(
                    f"weights of shape {w.shape} for a net of shape {pts.shape[:2]} "
                    "(give one weight per point)"
                )
        self._init(_geomkit.BezierSurfaceCore(pts, w))

    def _init(self, core: _geomkit.BezierSurfaceCore) -> None:
        self._core = core
        self._net: NDArray[np.float64] | None = None
        self._weights: NDArray[np.float64] | None = None

    @classmethod
    def _wrap(cls, core: _geomkit.BezierSurfaceCore) -> BezierSurface:
        self = object.__new__(cls)
        self._init(core)
        return self

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> BezierSurface:
        """The surface of a model of kind ``"bezier_surface"`` (`geomkit.load`)."""
        return cls._wrap(_geomkit.BezierSurfaceCore.from_model(model))

    def _model(self) -> _geomkit.Model:
        return self._core.to_model()

    @property
    def net(self) -> NDArray[np.float64]:
        """The control net, shape (n + 1, m + 1, dim), read-only."""
        if self._net is None:
            n, m = self._core.degrees
            a = np.empty((n + 1, m + 1, self._core.dim))
            self._core.net_into(a)
            self._net = _frozen(a)
        return self._net

    @property
    def weights(self) -> NDArray[np.float64] | None:
        """The weights of a rational surface, shape (n + 1, m + 1), read-only; None
        otherwise."""
        if not self._core.is_rational:
            return None
        if self._weights is None:
            n, m = self._core.degrees
            w = np.empty((n + 1, m + 1))
            self._core.weights_into(w)
            self._weights = _frozen(w)
        return self._weights

    @property
    def is_rational(self) -> bool:
        """Whether the surface has weights."""
        return self._core.is_rational

    @property
    def degree(self) -> tuple[int, int]:
        """The formal degrees (n, m)."""
        return self._core.degrees

    @property
    def dim(self) -> int:
        """The dimension of the points."""
        return self._core.dim

    def _derived(self, du: int, dv: int) -> _geomkit.BezierSurfaceCore:
        n, m = self._core.degrees
        core = self._core
        for _ in range(min(du, n + 1)):
            core = core.derivative("u")
        for _ in range(min(dv, m + 1)):
            core = core.derivative("v")
        return core

    def __call__(self, u: ArrayLike, v: ArrayLike, grid: bool = True, du: int = 0,
                 dv: int = 0) -> NDArray[np.float64]:
        """The points (or partial derivatives ∂^(du+dv) p / ∂u^du ∂v^dv) of the surface.

        De Casteljau in u then in v (formula (11); on the homogeneous net, then divided by
        the weight, for a rational surface), with the GIL released; outside [0, 1]² the
        polynomial (or rational function) extrapolates. Derivatives of a rational surface
        by the quotient rule on the homogeneous partial derivatives.

        Parameters
        ----------
        u, v : array_like
            Parameters (finite). With ``grid=True`` (default) each is 1-D (a scalar counts as
            one value) and the result is on the grid u × v; with ``grid=False`` they
            broadcast together and the result is at the pairs (u, v).
        grid : bool, optional
            Grid or pairs.
        du, dv : int, optional
            Orders of the partial derivative (default 0, the points).

        Returns
        -------
        ndarray
            Shape ``(len(u), len(v), dim)`` on a grid, ``broadcast(u, v).shape + (dim,)``
            at pairs.

        Raises
        ------
        ValueError
            For parameters that are not finite or not 1-D on a grid, shapes that do not
            broadcast, negative orders.
        TypeError
            For parameters that are not real numbers.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]])
        >>> s([0.0, 1.0], [0.5]).ravel().tolist()
        [0.5, 2.5]
        >>> s([0.25, 0.5], [0.5, 0.25], grid=False).ravel().tolist()
        [1.0, 1.25]
        >>> float(s(0.3, 0.6, du=1)[0, 0, 0])
        2.0
        """
        du, dv = _order(du, "du"), _order(dv, "dv")
        us, vs, shape = _surface_parameters(u, v, grid)
        out = np.empty(shape + (self._core.dim,))
        if self._core.is_rational and du + dv > 0:
            own = self._core
            _surface_steps(us, vs, grid, out,
                           lambda a, b, o: own.partials_into(a, b, grid, du, dv, o))
            return out
        core = self._derived(du, dv)
        # The steps' calls written out here (not through `_surface_steps`): the GIL test
        # finds the compiled call on this method's lines.
        if grid:
            chunked(us.shape[0], lambda a, b: core.eval_grid_into(us[a:b], vs, out[a:b]),
                    "BezierSurface", per=vs.shape[0])
        else:
            flat = out.reshape(-1, self._core.dim)
            chunked(us.shape[0],
                    lambda a, b: core.eval_points_into(us[a:b], vs[a:b], flat[a:b]),
                    "BezierSurface")
        return out

    def normal(self, u: ArrayLike, v: ArrayLike, grid: bool = True) -> NDArray[np.float64]:
        """Unit normals n = (∂p/∂u × ∂p/∂v) / |∂p/∂u × ∂p/∂v| of a surface in R^3.

        Parameters
        ----------
        u, v : array_like
            Parameters (finite), on a grid (1-D each, default) or at pairs (``grid=False``,
            broadcast together), as for `__call__`.
        grid : bool, optional
            Grid or pairs.

        Returns
        -------
        ndarray
            Shape ``(len(u), len(v), 3)`` on a grid, ``broadcast(u, v).shape + (3,)`` at
            pairs; NaN where the partial derivatives are parallel or vanish (a degenerate
            point, e.g. a collapsed edge).

        Raises
        ------
        ValueError
            For a surface not in R^3, parameters that are not finite, shapes that do not
            fit.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]]])
        >>> s.normal(0.5, 0.5).tolist()
        [[[0.0, 0.0, 1.0]]]
        """
        us, vs, shape = _surface_parameters(u, v, grid)
        out = np.empty(shape + (3,))
        core = self._core
        _surface_steps(us, vs, grid, out, lambda a, b, o: core.normals_into(a, b, grid, o))
        return out

    def derivative(self, du: int = 1, dv: int = 0) -> BezierSurface:
        """The partial-derivative surface ∂^(du+dv) p / ∂u^du ∂v^dv, of degrees
        (n - du, m - dv) (zero above the degrees), of a polynomial surface (that of a
        rational one is not a Bézier surface of this kind: evaluate it with
        ``s(u, v, du=..., dv=...)``).

        Parameters
        ----------
        du, dv : int, optional
            The orders in u (default 1) and v (default 0).

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For a rational surface.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).derivative().net.ravel().tolist()
        [2.0, 2.0]
        """
        return BezierSurface._wrap(self._derived(_order(du, "du"), _order(dv, "dv")))

    # -- change of degree ------------------------------------------------------------------

    def _changed(self, n: int, m: int, tolerance: float | None) -> BezierSurface:
        """The change to degrees (n, m), with a bar inside ``geomkit.progress()``."""
        a, b = self.degree
        work = (a + 1) * (b + 1) * self.dim * (max(a, n) + max(b, m) + 2)
        return BezierSurface._wrap(
            _reporting(lambda p: self._core.change_degree(n, m, tolerance, p), work))

    def change_degree(self, to: tuple[int, int], tolerance: float | None = None
                      ) -> BezierSurface:
        """The same surface with degrees (n', m'): formula (14) done stably.

        Each direction is elevated (8) or exactly reduced independently, all rows or
        columns at once (every one of the paper's eight problems, e.g. elevate in u and
        reduce in v).

        Parameters
        ----------
        to : (int, int)
            The new degrees (n', m').
        tolerance : float, optional
            The relative tolerance of a reduction (default 1e-12).

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            When a reduction is impossible (the message names the direction and its real
            degree), or the degrees are too large.
        TypeError
            When `to` is not a pair of integers.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).change_degree((2, 1))
        >>> s.net[:, :, 0].tolist()
        [[0.0, 1.0], [1.0, 2.0], [2.0, 3.0]]
        """
        n, m = _two_degrees(to)
        return self._changed(n, m, _tolerance(tolerance))

    def elevate(self, to: tuple[int, int]) -> BezierSurface:
        """`change_degree` with both degrees >= the current ones (elevation (15)).

        Parameters
        ----------
        to : (int, int)
            The new degrees.

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            When a degree is below the current one.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> BezierSurface([[[0.0], [1.0]]]).elevate((1, 2)).degree
        (1, 2)
        """
        n, m = _two_degrees(to)
        a, b = self.degree
        if n < a or m < b:
            raise ValueError(
                f"cannot elevate a surface of degrees ({a}, {b}) to ({n}, {m}): elevation "
                "needs degrees >= the current ones (use change_degree to mix)"
            )
        return self._changed(n, m, None)

    def reduce(self, to: tuple[int, int], tolerance: float | None = None) -> BezierSurface:
        """`change_degree` with both degrees <= the current ones: exact reduction (16).

        Parameters
        ----------
        to : (int, int)
            The new degrees, at least the real degrees (`degree_report`).
        tolerance : float, optional
            The relative tolerance (default 1e-12).

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            When a degree is above the current one, or a defect does not allow the
            reduction (the message names the direction and its real degree).

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).elevate((4, 3))
        >>> s.reduce((1, 1)).net.ravel().tolist()
        [0.0, 1.0, 2.0, 3.0]
        """
        n, m = _two_degrees(to)
        a, b = self.degree
        if n > a or m > b:
            raise ValueError(
                f"cannot reduce a surface of degrees ({a}, {b}) to ({n}, {m}): reduction "
                "needs degrees <= the current ones (use change_degree to mix)"
            )
        return self._changed(n, m, _tolerance(tolerance))

    def change_degree_paper(self, to: tuple[int, int]) -> BezierSurface:
        """Formula (14) exactly as the paper writes it, with the exact matrices
        H_n E H_(n')^-1 rounded once: below a real degree it truncates the power form at
        (0, 0).

        Parameters
        ----------
        to : (int, int)
            The new degrees (all degrees at most 100).

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For a degree above 100, or a result that overflows.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> BezierSurface([[[0.0], [1.0]]]).change_degree_paper((0, 2)).net.ravel().tolist()
        [0.0, 0.5, 1.0]
        """
        n, m = _two_degrees(to)
        return BezierSurface._wrap(self._core.change_degree_paper(n, m))

    def degree_report(self, tolerance: float | None = None) -> SurfaceDegreeReport:
        """The formal degrees, real degrees and defects in u and v (formula (16)), by the
        residual test on all rows or columns jointly.

        Parameters
        ----------
        tolerance : float, optional
            The relative tolerance (default 1e-12).

        Returns
        -------
        SurfaceDegreeReport

        Raises
        ------
        ValueError
            For a tolerance that is not finite and > 0.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).elevate((3, 2))
        >>> r = s.degree_report()
        >>> r.degree, r.real_degree, r.defect
        ((3, 2), (1, 1), (2, 1))
        """
        u, v = self._core.degree_report(_tolerance(tolerance))
        return SurfaceDegreeReport(_report(u), _report(v))

    def deviation_from(self, other: BezierSurface) -> Deviation:
        """How far this surface is from `other` over [0, 1]²: the largest distance found on
        a 65×65 grid (`at` is its u) and a guaranteed upper bound (the largest difference of
        net points at common degrees).

        Parameters
        ----------
        other : BezierSurface
            A surface of the same dimension.

        Returns
        -------
        Deviation

        Raises
        ------
        ValueError
            For surfaces of different dimensions, or rational ones (polynomial surfaces
            only).
        TypeError
            When `other` is not a `BezierSurface`.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> a = BezierSurface([[[0.0], [0.0]], [[0.0], [0.0]]])
        >>> a.deviation_from(BezierSurface([[[1.0], [1.0]], [[1.0], [1.0]]])).max_found
        1.0
        """
        if not isinstance(other, BezierSurface):
            raise TypeError(f"other must be a BezierSurface, got {type(other).__name__}")
        return _deviation(self._core.deviation_from(other._core))

    # -- manual change (13) ----------------------------------------------------------------

    def _line(self, points: ArrayLike) -> NDArray[np.float64]:
        return _points(points, "points", 2)

    def _line_weights(self, weights: ArrayLike | None) -> NDArray[np.float64] | None:
        if weights is None:
            return None
        w = contiguous(weights, "weights")
        if w.ndim != 1:
            raise ValueError(f"weights must be 1-D, got an array of shape {w.shape}")
        return w

    def insert_row(self, index: int, points: ArrayLike, weights: ArrayLike | None = None
                   ) -> BezierSurface:
        """Inserts a row of the net (m + 1 points, along v) before row `index` (manual
        change (13): the degree in u rises by one and the shape changes).

        Parameters
        ----------
        index : int
            0 to n + 1.
        points : array_like, shape (m + 1, dim)
            The new row.
        weights : array_like, shape (m + 1,), optional
            Its weights: a polynomial surface given weights becomes rational (its own
            weights 1); a rational one given none takes weights 1.

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For an index out of range or a row of the wrong size or dimension.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).insert_row(1, [[5.0], [5.0]])
        >>> s.degree
        (2, 1)
        """
        return BezierSurface._wrap(
            self._core.insert_line(
                "u", _degree(index, "index"), self._line(points), self._line_weights(weights)
            )
        )

    def insert_column(self, index: int, points: ArrayLike, weights: ArrayLike | None = None
                      ) -> BezierSurface:
        """Inserts a column of the net (n + 1 points, along u) before column `index`
        (manual change (13): the degree in v rises by one and the shape changes).

        Parameters
        ----------
        index : int
            0 to m + 1.
        points : array_like, shape (n + 1, dim)
            The new column.
        weights : array_like, shape (n + 1,), optional
            Its weights, as for `insert_row`.

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For an index out of range or a column of the wrong size or dimension.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> s = BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).insert_column(2, [[4.0], [4.0]])
        >>> s.net[:, :, 0].tolist()
        [[0.0, 1.0, 4.0], [2.0, 3.0, 4.0]]
        """
        return BezierSurface._wrap(
            self._core.insert_line(
                "v", _degree(index, "index"), self._line(points), self._line_weights(weights)
            )
        )

    def remove_row(self, index: int) -> BezierSurface:
        """Removes row `index` of the net (manual change (13); the shape changes).

        Parameters
        ----------
        index : int
            0 to n.

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For an index out of range or removing the only row.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).remove_row(0).net.ravel().tolist()
        [2.0, 3.0]
        """
        return BezierSurface._wrap(self._core.remove_line("u", _degree(index, "index")))

    def remove_column(self, index: int) -> BezierSurface:
        """Removes column `index` of the net (manual change (13); the shape changes).

        Parameters
        ----------
        index : int
            0 to m.

        Returns
        -------
        BezierSurface

        Raises
        ------
        ValueError
            For an index out of range or removing the only column.

        Examples
        --------
        >>> from geomkit import BezierSurface
        >>> BezierSurface([[[0.0], [1.0]], [[2.0], [3.0]]]).remove_column(1).net.ravel().tolist()
        [0.0, 2.0]
        """
        return BezierSurface._wrap(self._core.remove_line("v", _degree(index, "index")))

    # -- Python protocol -------------------------------------------------------------------

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        return (_surface_from_json, (self.to_json(),))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, BezierSurface):
            return NotImplemented
        if self.is_rational != other.is_rational:
            return False
        sw, ow = self.weights, other.weights
        same_weights = sw is None or (ow is not None and bool(np.array_equal(sw, ow)))
        return (
            self.net.shape == other.net.shape
            and bool(np.array_equal(self.net, other.net))
            and same_weights
        )

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        n, m = self.degree
        kind = "rational, " if self.is_rational else ""
        return (
            f"<geomkit.BezierSurface: {kind}degrees ({n}, {m}) in R^{self.dim} "
            f"({n + 1}×{m + 1} net)>"
        )


def _surface_from_json(text: str) -> BezierSurface:
    """Unpickling: the surface of its model file."""
    return BezierSurface._from_model(_geomkit.parse_model(text))


register_kind("bezier_curve", BezierCurve._from_model)
register_kind("bezier_surface", BezierSurface._from_model)
