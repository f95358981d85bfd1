"""Interpolating cubic splines of chunked Dask arrays: grids and series larger than memory.

Heights on a regular or rectilinear grid, or long series and curves, held as a chunked
``dask.array``; the spline's coefficients computed chunk by chunk (each chunk read with a
halo of `depth` neighbours on each side), and the spline evaluated on another rectilinear
grid chunk by chunk. Nothing is gathered in one place: every task reads its chunk, the halo
of its neighbours, and writes its own block. The same code runs on the threads of one
process, on a ``distributed.LocalCluster``, or on a multi-machine cluster (only the
``Client`` address changes).

Why a halo gives the global spline
----------------------------------
The B-spline coefficients of the interpolant solve a banded (tridiagonal for the cubic)
system. A wrong condition at an artificial end changes the solution by an amount that
decays geometrically away from that end: by ``2 - sqrt(3) = 0.268`` per data point on
uniform coordinates (0.268^32 = 5e-19 for the default ``depth=32``), more slowly on strongly
irregular ones. Each chunk is therefore solved together with `depth` points of its
neighbours on each side, with the true end conditions (not-a-knot, natural, clamped,
periodic) at the true ends of the array only and a natural end at the artificial ends, and
keeps the coefficients of its own points. Before building the graph, the decay over every
halo is bounded from the coordinates themselves (the ratios of the Thomas recursion of the
collocation system, started from the worst case; a row that is not diagonally dominant
counts as no decay): when the bound does not reach 2**-53 = eps / 2 (a wrong end value, a
few times the size of the data at most, then reaches the kept coefficients at the level of
one unit of rounding; the tests measure the whole within 4 eps max|z|), the call raises a
ValueError that names the depth needed, or takes it with ``depth="auto"``. Chunks smaller
than the halo are fine: a task reads as many neighbouring chunks as its halo covers (no
rechunking).

The representation (SciPy's)
----------------------------
Along each interpolated axis, the knots and coefficients are those of
``scipy.interpolate.make_interp_spline(x, y, k=3, bc_type=...)``, so that
``scipy.interpolate.BSpline(t, c.compute(), 3)`` is the same spline:

- not-a-knot: n coefficients, coefficient i belongs to the chunk of data point i, so the
  coefficient array has the chunks of the data;
- natural, clamped and periodic: n + 2 coefficients, coefficient i + 1 belongs to data
  point i, and the two extra ones sit in the first and the last chunk (their chunks are one
  longer). A periodic spline's last three coefficients repeat its first three (SciPy's).

Examples
--------
>>> import numpy as np, dask.array as da
>>> import geomkit.dask as gd
>>> x, y = np.linspace(0, 4, 200), np.linspace(-1, 1, 150)
>>> z = da.from_array(np.sin(x)[:, None] * np.cos(y)[None, :], chunks=(64, 50))
>>> spline = gd.make_interp_grid((x, y), z)
>>> spline.c.chunks
((64, 64, 64, 8), (50, 50, 50))
>>> fine = spline(np.linspace(0, 4, 399), np.linspace(-1, 1, 299))
>>> fine.shape
(399, 299)
>>> exact = np.sin(100 / 398 * 4) * np.cos(-1 + 100 / 149)
>>> bool(abs(float(fine[100, 100].compute()) - exact) < 1e-6)
True
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Union

import dask.array as da
import numpy as np
from dask.highlevelgraph import HighLevelGraph
from numpy.typing import ArrayLike, NDArray

from ._arrays import index, real_array, real_scalar
from ._bspline import BSpline
from ._bspline import make_interp_spline as _solve

# dask.array's functions are not annotated: called through this alias (mypy --strict).
_da: Any = da

__all__ = [
    "ChunkedSpline",
    "Regular",
    "make_interp_grid",
    "make_interp_spline",
    "required_depth",
    "resample",
    "to_zarr",
]

# The degree: exact-through-data cubic splines.
_K = 3
# The certified decay over a halo: 2**-53 = eps / 2. The error an artificial end makes in
# its first coefficient is a few times max|z| at most (|c| <= 3 max|z| for cubic
# interpolation at uniform knots), and one more row of decay (0.27) lies between the halo
# and the kept coefficients: they are off by about eps max|z| at most, on top of the
# solve's own rounding (the tests measure the whole within 4 eps max|z|).
_DECAY = 2.0**-53
# Parts of chunks with fewer values than this travel with the whole chunk (no task of
# their own): 128 KiB of float64.
_CUT_MIN = 1 << 14
# Iterations of the bound of the decay ratios (each a valid bound; converged after ~20).
_BOUND_STEPS = 24
_ENDS = ("not-a-knot", "natural", "clamped", "periodic")

Coordinates = Union["Regular", ArrayLike]


@dataclass(frozen=True)
class Regular:
    """Regular coordinates ``start + i * step`` for ``i = 0 .. size - 1``, never stored.

    For axes too long to hold their coordinates in memory (a 10^9-point series: 8 GB of
    coordinates, and as many knots): tasks compute the coordinates they need.

    Parameters
    ----------
    start : float
        The first coordinate.
    step : float
        The spacing, > 0.
    size : int
        The number of points, >= 1.

    Raises
    ------
    ValueError
        A step that is not positive and finite, a start that is not finite, a negative size.

    Examples
    --------
    >>> from geomkit.dask import Regular
    >>> Regular(0.0, 0.5, 5).to_numpy().tolist()
    [0.0, 0.5, 1.0, 1.5, 2.0]
    >>> Regular.linspace(0.0, 1.0, 3).step
    0.5
    """

    start: float
    step: float
    size: int

    def __post_init__(self) -> None:
        object.__setattr__(self, "start", real_scalar(self.start, "Regular start"))
        object.__setattr__(self, "step", real_scalar(self.step, "Regular step"))
        object.__setattr__(self, "size", index(self.size, "Regular size"))
        if not math.isfinite(self.start):
            raise ValueError(f"Regular: start must be finite, got {self.start}")
        if not (math.isfinite(self.step) and self.step > 0):
            raise ValueError(f"Regular: step must be positive and finite, got {self.step}")
        if self.size < 1:
            raise ValueError(f"Regular: size must be >= 1, got {self.size}")

    @classmethod
    def linspace(cls, start: float, stop: float, num: int) -> Regular:
        """The coordinates of ``numpy.linspace(start, stop, num)`` (num >= 2)."""
        num = index(num, "num")
        if num < 2:
            raise ValueError(f"Regular.linspace: num must be >= 2, got {num}")
        return cls(start, (real_scalar(stop, "stop") - real_scalar(start, "start")) / (num - 1),
                   num)

    def __len__(self) -> int:
        return self.size

    def at(self, i: NDArray[np.int64]) -> NDArray[np.float64]:
        """The coordinates of the indices `i` (any integers; no bounds check)."""
        return self.start + i.astype(np.float64) * self.step

    def to_numpy(self) -> NDArray[np.float64]:
        """All the coordinates as an array."""
        return self.at(np.arange(self.size, dtype=np.int64))


class _Coords:
    """One axis' coordinates, stored (a checked array) or `Regular`."""

    __slots__ = ("x", "regular", "n", "first", "last", "_extended")

    def __init__(self, coords: Any, name: str) -> None:
        self._extended: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
        if isinstance(coords, Regular):
            self.regular: Regular | None = coords
            self.x: NDArray[np.float64] | None = None
            self.n = coords.size
        else:
            if isinstance(coords, da.Array):
                raise TypeError(f"{name}: give coordinates as a NumPy array or "
                                "geomkit.dask.Regular (a dask array would be computed by every "
                                "task)")
            x = np.ascontiguousarray(real_array(coords, name))
            if x.ndim != 1:
                raise ValueError(f"{name} must be 1-D, got shape {x.shape}")
            if not np.isfinite(x).all():
                bad = int(np.flatnonzero(~np.isfinite(x))[0])
                raise ValueError(f"{name}: non-finite coordinate {x[bad]} at index {bad}")
            if x.shape[0] > 1 and not (np.diff(x) > 0).all():
                bad = int(np.flatnonzero(np.diff(x) <= 0)[0])
                raise ValueError(f"{name} must be strictly increasing: {name}[{bad}] = "
                                 f"{x[bad]!r} >= {name}[{bad + 1}] = {x[bad + 1]!r}")
            self.regular, self.x, self.n = None, x, x.shape[0]
        ends = self.at(np.array([0, max(self.n - 1, 0)], dtype=np.int64))
        self.first, self.last = float(ends[0]), float(ends[1])

    def at(self, i: NDArray[np.int64]) -> NDArray[np.float64]:
        if self.regular is not None:
            return self.regular.at(i)
        assert self.x is not None
        return self.x[i]

    def extended(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The coordinates of a periodic axis one period below and above, at the indices of
        the data points 0 .. n - 2 (SciPy's `_periodic_knots`: steps added one by one)."""
        assert self.x is not None
        if self._extended is None:
            x = self.x
            steps = np.diff(x)
            above = np.cumsum(np.concatenate([[x[-1]], steps[:-1]]))
            # x[0] - steps[-1] - steps[-2] - ..., reversed: entry r is period - r steps down.
            below = np.cumsum(np.concatenate([[x[0]], -steps[::-1]]))[::-1][:-1]
            self._extended = (below, above)
        return self._extended

    def floor_index(self, v: float) -> int:
        """The largest i with x[i] <= v (-1 below the first)."""
        if self.regular is not None:
            return math.floor((v - self.regular.start) / self.regular.step)
        assert self.x is not None
        return int(np.searchsorted(self.x, v, side="right")) - 1


class _Line:
    """The coordinates of the virtual data indices [lo, hi) of one axis, for one task: a
    `Regular` (tiny) or the coordinates themselves (a window, not the whole axis)."""

    __slots__ = ("regular", "lo", "x")

    def __init__(self, coords: _Coords, period: int, span: float, lo: int, hi: int) -> None:
        self.regular, self.lo = coords.regular, lo
        self.x = None if self.regular is not None else _virtual(coords, period, span,
                                                                np.arange(lo, hi))

    def at(self, i: NDArray[np.int64]) -> NDArray[np.float64]:
        if self.regular is not None:
            return self.regular.at(i)
        assert self.x is not None
        return self.x[i - self.lo]


def _virtual(coords: _Coords, period: int, span: float,
             i: NDArray[np.int64]) -> NDArray[np.float64]:
    """Coordinates of virtual indices: data index i, or for a periodic axis (period = n - 1
    points, `span` = x[n-1] - x[0]) i mod period shifted by whole periods."""
    if period == 0:
        return coords.at(i)
    q, r = np.divmod(i, period)
    out = coords.at(r) + q * span
    if coords.x is not None:
        # The first period on either side as SciPy's periodic knots are made (the steps of
        # the other end added one by one), so that the knots are SciPy's bits.
        below, above = coords.extended()
        out = np.where(q == 1, above[r], out)
        out = np.where(q == -1, below[r], out)
    return out


@dataclass(frozen=True)
class _Ends:
    """The end conditions of one axis: a name, or one (order, value) derivative condition."""

    left: str | tuple[int, float]
    right: str | tuple[int, float]

    @property
    def periodic(self) -> bool:
        return self.left == "periodic"

    @property
    def not_a_knot(self) -> bool:
        return self.left == "not-a-knot"


def _side(side: Any, bc: Any, axis: int) -> str | tuple[int, float]:
    """One side of a (left, right) pair: 'natural', 'clamped' or SciPy's [(order, value)]
    with one derivative condition of order 1 or 2 and a real value."""
    if isinstance(side, str):
        if side in ("natural", "clamped"):
            return side
    elif isinstance(side, (list, tuple)) and len(side) == 1:
        try:
            order, value = side[0]
        except (TypeError, ValueError):
            pass
        else:
            order = index(order, f"bc_type derivative order (axis {axis})")
            value = real_scalar(value, f"bc_type derivative value (axis {axis})")
            if order not in (1, 2) or not math.isfinite(value):
                raise ValueError(f"bc_type {bc!r} (axis {axis}): a cubic takes one derivative "
                                 "of order 1 or 2 per end, with a finite value")
            return (order, value)
    raise ValueError(f"bc_type {bc!r} (axis {axis}): each side of a (left, right) pair is "
                     "'natural', 'clamped' or [(order, value)] (not-a-knot and periodic hold "
                     "at both ends)")


def _ends(bc: Any, axis: int) -> _Ends:
    """One axis' `bc_type`: None / a name / a (left, right) pair of sides (`_side`)."""
    if bc is None:
        return _Ends("not-a-knot", "not-a-knot")
    if isinstance(bc, str):
        if bc not in _ENDS:
            raise ValueError(f"bc_type {bc!r} (axis {axis}): expected one of {_ENDS}, or a "
                             "(left, right) pair of 'natural' / 'clamped' / [(order, value)]")
        return _Ends(bc, bc)
    if isinstance(bc, tuple) and len(bc) == 2:
        return _Ends(_side(bc[0], bc, axis), _side(bc[1], bc, axis))
    raise TypeError(f"bc_type (axis {axis}) must be None, a string or a (left, right) pair, "
                    f"got {type(bc).__name__}")


_CONDITION: dict[str, list[tuple[int, float]] | None] = {
    "not-a-knot": None, "natural": [(2, 0.0)], "clamped": [(1, 0.0)],
}


def _condition(side: str | tuple[int, float]) -> list[tuple[int, float]] | None:
    """A side as the compiled module's make_interp_spline takes it."""
    return [side] if isinstance(side, tuple) else _CONDITION[side]


class _Axis:
    """The plan of one interpolated axis: SciPy's knots T of the global spline (as a
    function of their index), the coefficients each chunk owns, the window each reads."""

    def __init__(self, coords: _Coords, ends: _Ends, chunks: tuple[int, ...], axis: int,
                 name: str) -> None:
        n = coords.n
        if n < 4:
            raise ValueError(f"{name}: a cubic spline needs at least 4 points along axis "
                             f"{axis}, got {n}")
        self.coords, self.ends, self.axis, self.n, self.name = coords, ends, axis, n, name
        self.period = n - 1 if ends.periodic else 0
        self.span = coords.last - coords.first
        # Data point i sits at knot index i + s (T[m] = x[m - s] inside).
        self.s = 2 if ends.not_a_knot else 3
        self.nc = n if ends.not_a_knot else n + 2
        self.data_chunks = chunks
        bounds = np.concatenate([[0], np.cumsum(chunks)]).astype(np.int64)
        self.data_bounds = bounds
        extra = 0 if ends.not_a_knot else 1
        owned = [(int(a) + extra, int(e) + extra) for a, e in zip(bounds[:-1], bounds[1:])]
        owned[0] = (0, owned[0][1])
        owned[-1] = (owned[-1][0], self.nc)
        self.owned = owned
        self.coef_chunks = tuple(e - a for a, e in owned)
        self._ratios: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    def x(self, i: NDArray[np.int64]) -> NDArray[np.float64]:
        return _virtual(self.coords, self.period, self.span, i)

    def window(self, block: int, depth: int) -> tuple[int, int]:
        """Virtual data indices [p, q) that block `block` reads."""
        a, e = int(self.data_bounds[block]), int(self.data_bounds[block + 1])
        p, q = a - depth, e + depth
        if not self.period:
            p, q = max(p, 0), min(q, self.n)
        return p, q

    def real(self, p: int, q: int) -> list[tuple[int, int]]:
        """The data index runs [r0, r1) of the virtual range [p, q), in order."""
        if not self.period:
            return [(p, q)]
        runs, i = [], p
        while i < q:
            r = i % self.period
            take = min(q - i, self.period - r)
            runs.append((r, r + take))
            i += take
        return runs

    def knots(self, line: _Line | None, m0: int, m1: int) -> NDArray[np.float64]:
        """Global knots T[m0:m1] (`line` must cover their data indices)."""
        m = np.arange(m0, m1, dtype=np.int64)
        if self.period:
            i = m - self.s
            return line.at(i) if line is not None else self.x(i)
        i = np.clip(m - self.s, 0, self.n - 1)
        i[m <= _K] = 0
        i[m >= self.nc] = self.n - 1
        return line.at(i) if line is not None else self.x(i)

    def span_of(self, v: float) -> int:
        """The knot span m (T[m] <= v < T[m+1], within [3, nc - 1]) of the global spline."""
        return min(max(self.coords.floor_index(v) + self.s, _K), self.nc - 1)

    def decay_bound(self, depth: int) -> float:
        """The largest bound, over the artificial ends of all windows, of the factor by which
        a wrong end condition is damped before it reaches the first kept coefficient."""
        worst = 0.0
        if self.coords.regular is not None:
            q = _uniform_ratio()
            cuts = [(p, q_) for p, q_ in (self.window(b, depth)
                                          for b in range(len(self.data_chunks)))]
            for p, q_ in cuts:
                for true in (p == 0 and not self.period, q_ == self.n and not self.period):
                    if not true:
                        worst = max(worst, q ** max(depth - 1, 0))
            return worst
        if self._ratios is None:
            self._ratios = _ratios(self)
        rightward, leftward = self._ratios
        for b in range(len(self.data_chunks)):
            p, q_ = self.window(b, depth)
            a, e = int(self.data_bounds[b]), int(self.data_bounds[b + 1])
            if not (p == 0 and not self.period):
                worst = max(worst, _product(self, rightward, p + 1, a))
            if not (q_ == self.n and not self.period):
                worst = max(worst, _product(self, leftward, e, q_ - 1))
        return worst


def _uniform_ratio() -> float:
    """The bound of the decay ratio on uniform coordinates (-> 2 - sqrt(3))."""
    a, b, c = 1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0
    q = 1.0
    for _ in range(_BOUND_STEPS):
        q = a / (b - c * q)
    return q


def _ratios(ax: _Axis) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Bounds of the decay ratios of the collocation system at every data point (indexed by
    data index; 1 where a row is not an interior one): rightward |e_(i+1) / e_i| and
    leftward |e_(i-1) / e_i| of a homogeneous solution."""
    n = ax.n
    i = np.arange(n, dtype=np.int64)
    x = {d: ax.x(i + d) if ax.period else ax.coords.at(np.clip(i + d, 0, n - 1))
         for d in (-2, -1, 0, 1, 2)}
    with np.errstate(divide="ignore", invalid="ignore"):
        # Cubic B-splines at the knot x_i: the left, centre and right values of row i.
        a = (x[1] - x[0]) ** 2 / ((x[1] - x[-1]) * (x[1] - x[-2]))
        c = (x[0] - x[-1]) ** 2 / ((x[1] - x[-1]) * (x[2] - x[-1]))
    b = 1.0 - a - c
    interior = np.isfinite(a) & np.isfinite(c) & (b > a + c)
    if not ax.period:
        interior &= (i >= 2) & (i <= n - 3)
    a, b, c = (np.where(interior, v, 0.0) for v in (a, b, c))
    b = np.where(interior, b, 1.0)
    right = np.ones(n)
    left = np.ones(n)
    for _ in range(_BOUND_STEPS):
        # The ratio at row i bounded from the bound at its neighbour (wrapping when periodic).
        nxt = np.roll(right, -1) if ax.period else np.append(right[1:], 1.0)
        prv = np.roll(left, 1) if ax.period else np.insert(left[:-1], 0, 1.0)
        right = np.where(interior, a / np.maximum(b - c * nxt, 1e-300), 1.0)
        left = np.where(interior, c / np.maximum(b - a * prv, 1e-300), 1.0)
    return np.minimum(right, 1.0), np.minimum(left, 1.0)


def _product(ax: _Axis, ratio: NDArray[np.float64], p: int, q: int) -> float:
    """The product of `ratio` over the virtual data indices [p, q)."""
    if q <= p:
        return 1.0
    i = np.arange(p, q, dtype=np.int64)
    if ax.period:
        i = i % ax.period
    return float(np.exp(np.sum(np.log(np.maximum(ratio[i], 1e-300)))))


class _Local:
    """One window's solve along one axis (picklable and small: it goes into the task). The
    knots and abscissas of a `Regular` axis are made in the task (a window of a 10^9-point
    series holds millions), those of a stored axis here (the task gets the window only)."""

    __slots__ = ("axis", "p", "q", "left_true", "right_true", "left", "right", "offset",
                 "plan", "arrays")

    def __init__(self, ax: _Axis, p: int, q: int) -> None:
        self.left_true = p == 0 and not ax.period
        self.right_true = q == ax.n and not ax.period
        ends = ax.ends
        self.left = _condition(ends.left) if self.left_true else _CONDITION["natural"]
        self.right = _condition(ends.right) if self.right_true else _CONDITION["natural"]
        self.offset = 0 if self.left_true else p + ax.s - _K
        self.axis, self.p, self.q = ax.axis, p, q
        regular = ax.coords.regular is not None
        self.plan = _light(ax) if regular else None
        self.arrays = None if regular else self._arrays(ax)

    def _arrays(self, ax: _Axis) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The window's knots and abscissas."""
        p, q, s = self.p, self.q, ax.s
        line = _Line(ax.coords, ax.period, ax.span, p, q)
        m0 = 0 if self.left_true else p + s + 1
        m1 = ax.nc + _K + 1 if self.right_true else q - 1 + s
        parts = []
        if not self.left_true:
            parts.append(np.repeat(line.at(np.array([p])), _K + 1))
        parts.append(ax.knots(line, m0, m1))
        if not self.right_true:
            parts.append(np.repeat(line.at(np.array([q - 1])), _K + 1))
        return np.concatenate(parts), line.at(np.arange(p, q, dtype=np.int64))

    def solve(self, w: NDArray[np.float64], keep: tuple[int, int]) -> NDArray[np.float64]:
        if self.arrays is not None:
            t, x = self.arrays
        else:
            assert self.plan is not None
            t, x = self._arrays(self.plan)
        spline = _solve(x, w, k=_K, t=t, bc_type=(self.left, self.right),
                        axis=self.axis)
        c = np.moveaxis(spline.c, 0, self.axis)
        take = [slice(None)] * c.ndim
        take[self.axis] = slice(keep[0] - self.offset, keep[1] - self.offset)
        return c[tuple(take)]


# -- gathering a block from the chunks it needs ----------------------------------------------
Segment = tuple[int, int, int]  # (chunk index, start, stop) inside that chunk


def _segments(bounds: NDArray[np.int64], runs: Sequence[tuple[int, int]]) -> list[Segment]:
    """The runs of indices [r0, r1) as pieces of the chunks with boundaries `bounds`."""
    out = []
    for r0, r1 in runs:
        i = r0
        while i < r1:
            b = int(np.searchsorted(bounds, i, side="right")) - 1
            stop = min(r1, int(bounds[b + 1]))
            out.append((b, i - int(bounds[b]), stop - int(bounds[b])))
            i = stop
    return out


def _gather_layer(layer: dict[Any, Any], name: str, src: da.Array, out_index: tuple[int, ...],
                  per_axis: Sequence[list[Segment]], fn: Any, *args: Any) -> None:
    """Adds to `layer` the task of the output block `out_index`: `fn(assembled, *args)`,
    where `assembled` is the array of the segments `per_axis` of `src`'s chunks (C order).

    A piece that is a whole chunk is read as it is; a part of a chunk (a halo, the few
    coefficient rows of a neighbour) is cut by a task of its own, which the scheduler runs
    where the chunk is: only the part travels to the block's worker. (Small chunks, below
    `_CUT_MIN` values, or parts of more than half a chunk travel whole: a task costs more.)"""
    keys, cut = [], []
    for p, combo in enumerate(np.ndindex(*(len(s) for s in per_axis))):
        segs = [per_axis[d][j] for d, j in enumerate(combo)]
        key = (src.name, *(seg[0] for seg in segs))
        size = math.prod(src.chunks[d][seg[0]] for d, seg in enumerate(segs))
        part_size = math.prod(seg[2] - seg[1] for seg in segs)
        whole = size < _CUT_MIN or 2 * part_size > size
        if not whole:
            part = (name + "-part", *out_index, p)
            layer[part] = (_part, key, [(seg[1], seg[2]) for seg in segs])
            key = part
        keys.append(key)
        cut.append(not whole)
    layout = [[(s[1], s[2]) for s in segs] for segs in per_axis]
    layer[(name, *out_index)] = (_assemble_then, keys, cut, layout, fn, *args)


def _part(chunk: NDArray[Any], bounds: list[tuple[int, int]]) -> NDArray[Any]:
    """A part of a chunk (a copy: the chunk itself may then be released)."""
    return np.array(chunk[tuple(slice(a, b) for a, b in bounds)])


def _row(chunk: NDArray[Any], row: int, axis: int) -> NDArray[Any]:
    """One row of a chunk along `axis` (a copy, the axis kept)."""
    return np.take(chunk, [row], axis=axis)


def _assemble_then(pieces: list[NDArray[Any]], cut: list[bool],
                   layout: list[list[tuple[int, int]]], fn: Any, *args: Any) -> Any:
    return fn(_assemble(pieces, cut, layout), *args)


def _assemble(pieces: list[NDArray[Any]], cut: list[bool],
              layout: list[list[tuple[int, int]]]) -> NDArray[np.float64]:
    """One array from the pieces (C order over the segments of each axis; those `cut`
    already are their segment, the others whole chunks)."""
    sizes = [[e - s for s, e in segs] for segs in layout]
    starts = [np.concatenate([[0], np.cumsum(sz)]).astype(int) for sz in sizes]
    out = np.empty([int(sum(sz)) for sz in sizes])
    for piece, was_cut, combo in zip(pieces, cut, np.ndindex(*(len(s) for s in layout))):
        src = (tuple(slice(None) for _ in combo) if was_cut
               else tuple(slice(*layout[d][j]) for d, j in enumerate(combo)))
        dst = tuple(slice(starts[d][j], starts[d][j + 1]) for d, j in enumerate(combo))
        out[dst] = piece[src]
    return out


# -- the solve --------------------------------------------------------------------------------
def _solve_block(window: NDArray[np.float64], locals_: list[_Local],
                 keeps: list[tuple[int, int]], where: _Where,
                 ends: list[NDArray[np.float64]], checks: list[tuple[int, int]]
                 ) -> NDArray[np.float64]:
    if not np.isfinite(window).all():
        raise ValueError(_nonfinite_message(window, where))
    for j, (axis, last) in enumerate(checks):
        # A periodic axis: the first and the last data (SciPy's test and words).
        first_, last_ = np.take(ends[2 * j], 0, axis), np.take(ends[2 * j + 1], last, axis)
        if not np.allclose(first_, last_, atol=1e-15):
            raise ValueError(f"{where.name}: first and last points does not match while "
                             f"periodic case expected (axis {axis}, largest difference "
                             f"{float(np.max(np.abs(first_ - last_)))})")
    w = window
    for loc, keep in zip(locals_, keeps):
        w = loc.solve(w, keep)
    # The batch axes are passed through; the solved axes were cut to the kept range.
    return np.ascontiguousarray(w)


@dataclass(frozen=True)
class _Where:
    """What a task needs to name a chunk of the input in an error: the input's name, the
    chunk boundaries of every axis, and the (chunk index, start, stop) segments read."""

    name: str
    bounds: tuple[tuple[int, ...], ...]
    segments: tuple[tuple[Segment, ...], ...]


def _nonfinite_message(window: NDArray[np.float64], where: _Where) -> str:
    """The first non-finite value of `window`: its chunk, the chunk's index ranges, and the
    value's index in the whole input."""
    pos = np.unravel_index(int(np.flatnonzero(~np.isfinite(window))[0]), window.shape)
    chunk, glob, ranges = [], [], []
    for d, p in enumerate(pos):
        acc = 0
        for b, s0, s1 in where.segments[d]:
            if p < acc + (s1 - s0):
                lo, hi = where.bounds[d][b], where.bounds[d][b + 1]
                chunk.append(b)
                glob.append(lo + s0 + int(p) - acc)
                ranges.append(f"{lo}..{hi - 1}")
                break
            acc += s1 - s0
    return (f"{where.name}: non-finite value {window[pos]} in chunk {tuple(chunk)} (indices "
            f"{' x '.join(ranges)}) at index {tuple(glob)}: interpolation needs finite values "
            "(fill or drop them first)")


# -- the model --------------------------------------------------------------------------------
class _EvalAxis:
    """One output block's evaluation along one axis (small and picklable: the knots and new
    coordinates are computed in the task for `Regular` axes, sliced here otherwise).

    `runs` are the coefficient ranges the block reads, in order: one, or on a periodic axis
    two when the block's coordinates cross the end of a period (the end of the coefficients,
    then their start)."""

    __slots__ = ("axis", "t", "plan", "runs", "new", "new_regular", "u", "v", "nu", "period")

    def __init__(self, ax: _Axis, runs: list[tuple[int, int]], new: _Coords, u: int, v: int,
                 nu: int, period: tuple[float, float, int] | None) -> None:
        self.axis, self.runs, self.u, self.v, self.nu = ax.axis, runs, u, v, nu
        self.period = period
        regular = ax.coords.regular is not None
        self.t = None if regular else [ax.knots(None, r0, r1 + _K + 1) for r0, r1 in runs]
        self.plan = _light(ax) if regular else None
        self.new_regular = new.regular
        self.new = None if new.regular is not None else new.at(np.arange(u, v, dtype=np.int64))

    def evaluate(self, c: NDArray[np.float64]) -> NDArray[np.float64]:
        if self.t is not None:
            knots = self.t
        else:
            assert self.plan is not None
            knots = [self.plan.knots(None, r0, r1 + _K + 1) for r0, r1 in self.runs]
        if self.new is not None:
            xs = self.new
        else:
            assert self.new_regular is not None
            xs = self.new_regular.at(np.arange(self.u, self.v, dtype=np.int64))
        groups = [xs]
        if self.period is not None:
            first, span, q0 = self.period
            q, xs = _wrap(xs, first, span)
            if len(self.runs) == 2:
                cut = int(np.searchsorted(q, q0, side="right"))
                groups = [xs[:cut], xs[cut:]]
            else:
                groups = [xs]
        parts, start = [], 0
        for (r0, r1), t, points in zip(self.runs, knots, groups):
            block = np.take(c, np.arange(start, start + r1 - r0), axis=self.axis)
            start += r1 - r0
            parts.append(BSpline.construct_fast(
                t, np.moveaxis(block, self.axis, 0), _K, True, self.axis)(
                    points, nu=self.nu))
        out: NDArray[np.float64] = (parts[0] if len(parts) == 1
                                    else np.concatenate(parts, axis=self.axis))
        return out


def _wrap(v: NDArray[np.float64], first: float, span: float
          ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The period index of each coordinate of a periodic axis and the coordinate moved into
    the base period (the same operations when planning and in the task)."""
    q = np.floor((v - first) / span)
    return q, first + ((v - first) - q * span)


def _light(ax: _Axis) -> _Axis:
    """A copy of a `Regular` axis' plan without its per-chunk lists (for tasks)."""
    light = object.__new__(_Axis)
    light.__dict__.update({k: v for k, v in ax.__dict__.items()
                           if k not in ("owned", "data_bounds", "data_chunks", "coef_chunks",
                                        "_ratios")})
    return light


def _knot_block(m: NDArray[np.int64], plan: _Axis) -> NDArray[np.float64]:
    """The global knots of the indices `m` (consecutive) of a `Regular` axis."""
    if m.size == 0:
        return np.empty(0)
    return plan.knots(None, int(m[0]), int(m[-1]) + 1)


def _evaluate_block(c: NDArray[np.float64], evals: list[_EvalAxis]) -> NDArray[np.float64]:
    for e in evals:
        c = e.evaluate(c)
    return np.ascontiguousarray(c)


class ChunkedSpline:
    """A tensor-product interpolating cubic spline whose coefficients are a chunked dask array.

    Made by `make_interp_grid` / `make_interp_spline`. Along each interpolated axis the knots
    and coefficients are SciPy's (``make_interp_spline(x, y, k=3, bc_type)``), so a spline
    small enough to compute is ``scipy.interpolate.BSpline(t[0], c.compute(), 3)`` in 1-D
    and the coefficients of ``RectBivariateSpline``-style tensor products in 2-D.

    Attributes
    ----------
    c : dask.array.Array
        The coefficients (the control net of a grid): the shape of the data with each
        interpolated axis of n points holding n (not-a-knot) or n + 2 (natural, clamped,
        periodic) coefficients; chunks those of the data, plus one in the first and the last
        chunk of an axis with n + 2.
    t : tuple of ndarray or dask.array.Array
        The knot vector of each interpolated axis (a lazy dask array for `Regular`
        coordinates, whose knots may not fit in memory).
    k : int
        The degree, 3.
    axes : tuple of int
        The interpolated axes of `c` (the others are carried along: batch axes).
    bc_type : tuple of (left, right)
        The end conditions of each interpolated axis: names, or (order, value) pairs.
    depth : int
        The halo each chunk was solved with.
    """

    def __init__(self, c: da.Array, plans: tuple[_Axis, ...], depth: int) -> None:
        self.c = c
        self._plans = plans
        self.k = _K
        self.axes = tuple(p.axis for p in plans)
        self.bc_type = tuple((p.ends.left, p.ends.right) for p in plans)
        self.depth = depth

    @property
    def t(self) -> tuple[NDArray[np.float64] | da.Array, ...]:
        out: list[NDArray[np.float64] | da.Array] = []
        for p in self._plans:
            if p.coords.regular is None:
                out.append(p.knots(None, 0, p.nc + _K + 1))
            else:
                m = _da.arange(p.nc + _K + 1, chunks=1 << 22, dtype=np.int64)
                out.append(_da.map_blocks(_knot_block, m, _light(p), dtype=np.float64,
                                          meta=np.empty((0,))))
        return tuple(out)

    def __call__(self, *xi: Coordinates, chunks: int | Sequence[int | None] | None = None,
                 nu: int | Sequence[int] = 0, name: str | None = None) -> da.Array:
        """The spline on the rectilinear grid ``xi[0] x xi[1] x ...``, lazily, chunk by chunk.

        Each output block reads only the coefficients of the knot spans its coordinates fall
        in (plus the 3 neighbours a cubic needs, and one more on each side): no gather.
        Outside the data's range the end polynomials continue (SciPy's ``extrapolate=True``);
        a periodic axis takes coordinates anywhere and repeats its period (SciPy's
        ``extrapolate='periodic'``: longitudes from -180 on data from 0 to 360, say).

        Parameters
        ----------
        *xi : array_like or Regular
            The new coordinates of each interpolated axis, in the order of `axes`: strictly
            increasing, finite (finer, coarser, any rectilinear grid).
        chunks : int or sequence of int, optional
            The output chunk size along each interpolated axis (one int for all). Default:
            as many chunks as the coefficients have along that axis, of equal size.
        nu : int or sequence of int, optional
            The order of the partial derivative along each interpolated axis (one int for
            all; default 0: values). Slopes of a terrain: ``nu=(1, 0)`` and ``nu=(0, 1)``.
        name : str, optional
            The dask name prefix of the result.

        Returns
        -------
        dask.array.Array
            Shape: that of `c` with each interpolated axis replaced by ``len(xi[d])``; the
            batch axes keep their chunks.

        Raises
        ------
        ValueError
            The wrong number of coordinate arrays, coordinates that are not strictly
            increasing or finite, bad chunks, negative derivative orders.
        TypeError
            Coordinates that are not real numbers.
        """
        if len(xi) != len(self._plans):
            raise ValueError(f"give one coordinate array per interpolated axis {self.axes}: "
                             f"got {len(xi)}")
        if chunks is None or isinstance(chunks, int):
            sizes: list[int | None] = [chunks] * len(xi)
        else:
            sizes = list(chunks)
            if len(sizes) != len(xi):
                raise ValueError(f"chunks: one size per interpolated axis, got {chunks!r}")
        orders = [nu] * len(xi) if isinstance(nu, int) else list(nu)
        if len(orders) != len(xi):
            raise ValueError(f"nu: one derivative order per interpolated axis, got {nu!r}")
        orders = [index(o, "nu") for o in orders]
        if any(o < 0 for o in orders):
            raise ValueError(f"nu: derivative orders must be >= 0, got {nu!r}")
        c = self.c
        out_chunks = list(c.chunks)
        segs: dict[int, list[tuple[list[Segment], _EvalAxis]]] = {}
        for d, (plan, coords, size, order) in enumerate(zip(self._plans, xi, sizes, orders)):
            new = _Coords(coords, f"xi[{d}]")
            m = new.n
            if size is None:
                size = max(1, math.ceil(m / len(plan.coef_chunks)))
            size = index(size, "chunks")
            if size < 1:
                raise ValueError(f"chunks must be >= 1, got {size}")
            block_sizes = tuple(min(size, m - u) for u in range(0, m, size))
            bounds = np.concatenate([[0], np.cumsum(c.chunks[plan.axis])]).astype(np.int64)
            entries = []
            u = 0
            for bs in block_sizes:
                v = u + bs
                ends = new.at(np.array([u, v - 1], dtype=np.int64))
                period = None
                if plan.period:
                    # Coordinates anywhere: moved into the base period; a block crossing
                    # the end of a period reads the coefficients of both ends.
                    q, ends = _wrap(ends, plan.coords.first, plan.span)
                    period = (plan.coords.first, plan.span, int(q[0]))
                lo = max(plan.span_of(float(ends[0])) - _K - 1, 0)
                hi = min(plan.span_of(float(ends[1])) + 2, plan.nc)
                if period is None or q[1] == q[0]:
                    runs = [(lo, hi)]
                elif q[1] == q[0] + 1:
                    runs = [(lo, plan.nc), (0, hi)]
                else:
                    runs = [(0, plan.nc)]
                entries.append((_segments(bounds, runs),
                                _EvalAxis(plan, runs, new, u, v, order, period)))
                u = v
            segs[plan.axis] = entries
            out_chunks[plan.axis] = block_sizes
        name = (name or "geomkit-eval") + "-" + _token(c.name, xi, sizes, orders)
        layer: dict[Any, Any] = {}
        for out_index in np.ndindex(*(len(ch) for ch in out_chunks)):
            per_axis, evals = [], []
            for d, b in enumerate(out_index):
                if d in segs:
                    seg, ev = segs[d][b]
                    per_axis.append(seg)
                    evals.append(ev)
                else:
                    per_axis.append([(b, 0, c.chunks[d][b])])
            _gather_layer(layer, name, c, out_index, per_axis, _evaluate_block, evals)
        graph = HighLevelGraph.from_collections(name, layer, dependencies=[_any(c)])
        out: da.Array = _da.Array(graph, name, tuple(out_chunks), dtype=np.float64,
                                  meta=np.empty((0,) * c.ndim))
        return out

    def __repr__(self) -> str:
        return (f"ChunkedSpline(k=3, axes={self.axes}, bc_type={self.bc_type}, "
                f"c: shape {self.c.shape}, chunks {self.c.chunksize}, depth={self.depth})")


def _any(x: Any) -> Any:
    """`x` typed as Any (dask's unannotated methods, mypy --strict)."""
    return x


def _token(*parts: Any) -> str:
    from dask.base import tokenize

    return str(tokenize(*[p if not isinstance(p, Regular) else (p.start, p.step, p.size)
                          for p in parts]))


def _depth(depth: Any, plans: Sequence[_Axis]) -> int:
    """The checked halo: an integer >= 1 whose decay is certified on every axis, or the
    smallest such with 'auto'."""
    if isinstance(depth, str):
        if depth != "auto":
            raise ValueError(f"depth must be a positive integer or 'auto', got {depth!r}")
        return int(max(_needed(p) for p in plans))
    if isinstance(depth, bool):
        raise TypeError("depth must be an integer, got bool")
    depth = index(depth, "depth")
    if depth < 1:
        raise ValueError(f"depth must be >= 1, got {depth}")
    for p in plans:
        bound = p.decay_bound(depth)
        if bound > _DECAY:
            raise ValueError(
                f"depth={depth} is too small for axis {p.axis} ({p.name}): a halo of "
                f"{depth} points damps the artificial ends only to {bound:.1e} (needed "
                f"{_DECAY:.1e} for the global solve within rounding); use depth >= "
                f"{_needed(p)} or depth='auto'")
    return int(depth)


def _needed(p: _Axis) -> int:
    """The smallest certified depth of one axis (the halo grows until the bound holds)."""
    cap = 4 * p.n + 8
    lo, hi = 1, 1
    while p.decay_bound(hi) > _DECAY:
        lo, hi = hi + 1, 2 * hi
        if hi > cap:
            raise ValueError(f"axis {p.axis} ({p.name}): no halo damps the artificial ends "
                             "enough (coordinates too irregular); use one chunk along it")
    while lo < hi:
        mid = (lo + hi) // 2
        if p.decay_bound(mid) > _DECAY:
            lo = mid + 1
        else:
            hi = mid
    return hi


def _bc_list(bc_type: Any, axes: Sequence[int]) -> list[_Ends]:
    if isinstance(bc_type, Mapping):
        unknown = set(bc_type) - set(axes)
        if unknown:
            raise ValueError(f"bc_type names axes {sorted(unknown)} that are not interpolated "
                             f"(axes {tuple(axes)})")
        return [_ends(bc_type.get(a), a) for a in axes]
    if isinstance(bc_type, list):
        if len(bc_type) != len(axes):
            raise ValueError(f"bc_type: a list gives one condition per axis {tuple(axes)}, "
                             f"got {len(bc_type)}")
        return [_ends(b, a) for b, a in zip(bc_type, axes)]
    return [_ends(bc_type, a) for a in axes]


def _as_dask(values: Any, name: str) -> da.Array:
    if not isinstance(values, da.Array):
        values = _da.from_array(real_array(values, name), chunks="auto")
    kind = values.dtype.kind
    if kind == "c":
        raise TypeError(f"{name}: complex values are not supported (interpolate the real and "
                        f"imaginary parts separately), got dtype {values.dtype}")
    if kind not in "biuf":
        raise TypeError(f"{name} must hold real numbers, got dtype {values.dtype}")
    out: da.Array = values.astype(np.float64) if values.dtype != np.float64 else values
    return out


def make_interp_grid(points: Sequence[Coordinates], values: Any,
                     axes: Sequence[int] | None = None, bc_type: Any = None,
                     depth: int | str = 32, name: str = "values") -> ChunkedSpline:
    """The interpolating cubic spline of a chunked grid (tensor product over `axes`).

    Every chunk of `values` is solved with a halo of `depth` points of its neighbours on each
    side of each interpolated axis (read from as many neighbouring chunks as that takes); the
    coefficients it keeps equal those of the global solve within 4 eps max|z| (the decay over
    the halo is bounded from the coordinates before anything runs; see the module's notes).

    Parameters
    ----------
    points : sequence of array_like or Regular
        The coordinates of each interpolated axis: strictly increasing and finite, of the
        length of that axis (`Regular` for axes whose coordinates should not be stored).
    values : dask.array.Array or array_like
        The data (real; a NumPy array is wrapped with dask's automatic chunks). Any number of
        axes: those not in `axes` are batch axes (independent splines).
    axes : sequence of int, optional
        The interpolated axes, one per entry of `points` (default ``0 .. len(points) - 1``).
    bc_type : None, str, (str, str), list or dict, optional
        End conditions: None or 'not-a-knot' (default), 'natural', 'clamped' (zero first
        derivative), 'periodic' (``values`` equal at both ends; derivatives continuous
        across), or a (left, right) pair whose sides are 'natural', 'clamped' or SciPy's
        ``[(order, value)]`` (one derivative of order 1 or 2, the same value for every
        line of the grid: ``([(1, 0.5)], [(2, 0.0)])``). One for all axes, or a list (one
        per axis) or a dict ``{axis: bc}``.
    depth : int or 'auto', optional
        The halo in data points (default 32: 0.268^32 = 5e-19 on uniform coordinates).
        'auto' takes the smallest halo the bound certifies.
    name : str, optional
        The name of `values` in error messages.

    Returns
    -------
    ChunkedSpline
        Its coefficients `c` (a lazy dask array) and knots `t`.

    Raises
    ------
    ValueError
        Coordinates that are not strictly increasing or finite or not of the axis' length,
        fewer than 4 points along an axis, repeated or out-of-range axes, an unknown end
        condition, a depth below 1 or too small to certify (the message gives the depth
        needed). When computed: a non-finite value, naming its chunk, the chunk's index
        ranges and the value's index.
    TypeError
        Non-real values, a depth that is not an integer.

    Examples
    --------
    >>> import numpy as np, dask.array as da
    >>> from geomkit.dask import make_interp_grid
    >>> x = np.linspace(0, 1, 100)
    >>> z = da.from_array(np.add.outer(x**2, x), chunks=30)
    >>> s = make_interp_grid((x, x), z, bc_type="natural")
    >>> s.c.shape, s.c.chunks[0]
    ((102, 102), (31, 30, 30, 11))
    """
    values = _as_dask(values, name)
    if isinstance(points, (np.ndarray, Regular)) or not isinstance(points, Sequence):
        raise TypeError("points must be a sequence (tuple or list) of coordinate arrays, one "
                        "per interpolated axis")
    if axes is None:
        axes = tuple(range(len(points)))
    axes = tuple(index(a, "axes") for a in axes)
    if len(axes) != len(points):
        raise ValueError(f"{len(points)} coordinate arrays for the axes {axes}")
    if not axes:
        raise ValueError("give the coordinates of at least one axis")
    norm = []
    for a in axes:
        if not -values.ndim <= a < values.ndim:
            raise ValueError(f"axis {a} is out of range for {name} of {values.ndim} dimensions")
        norm.append(a % values.ndim)
    if len(set(norm)) != len(norm):
        raise ValueError(f"repeated axes {axes}")
    ends = _bc_list(bc_type, norm)
    plans = []
    for d, (a, coords, e) in enumerate(zip(norm, points, ends)):
        coord = _Coords(coords, f"points[{d}]")
        if coord.n != values.shape[a]:
            raise ValueError(f"points[{d}] has {coord.n} coordinates, {name} has "
                             f"{values.shape[a]} along axis {a}")
        plans.append(_Axis(coord, e, values.chunks[a], a, f"points[{d}]"))
    h = _depth(depth, plans)
    bounds = tuple(tuple(int(v) for v in np.concatenate([[0], np.cumsum(ch)]))
                   for ch in values.chunks)
    out_name = "geomkit-interp-" + _token(values.name, points, bc_type, h, tuple(norm))
    by_axis = {p.axis: p for p in plans}
    windows = {p.axis: [p.window(b, h) for b in range(len(p.data_chunks))] for p in plans}
    locs = {p.axis: [_Local(p, *w) for w in windows[p.axis]] for p in plans}
    layer: dict[Any, Any] = {}
    for out_index in np.ndindex(*values.numblocks):
        per_axis, locals_, keeps = [], [], []
        for d, b in enumerate(out_index):
            if d in by_axis:
                p = by_axis[d]
                per_axis.append(_segments(np.asarray(bounds[d], dtype=np.int64),
                                          p.real(*windows[d][b])))
                locals_.append(locs[d][b])
                keeps.append(p.owned[b])
            else:
                per_axis.append([(b, 0, values.chunks[d][b])])
        where = _Where(name, bounds, tuple(tuple(s) for s in per_axis))
        end_keys: list[tuple[Any, ...]] = []
        checks: list[tuple[int, int]] = []
        for p in plans:
            # The chunks holding the first and the last data (zero-size chunks skipped).
            first = int(np.searchsorted(p.data_bounds, 0, side="right")) - 1
            last = int(np.searchsorted(p.data_bounds, p.n - 1, side="right")) - 1
            if p.period and out_index[p.axis] == 0:
                # The first block of a periodic axis (whose coefficients are always used:
                # the last ones repeat them) checks y[0] == y[-1] over its slab. (Tasks of
                # their own cut the two rows where the chunks are.)
                at = list(out_index)
                row = p.n - 1 - int(p.data_bounds[last])
                for side, (block, row) in enumerate(((first, 0), (last, row))):
                    at[p.axis] = block
                    key = (out_name + "-end", *out_index, p.axis, side)
                    layer[key] = (_row, (values.name, *at), row, p.axis)
                    end_keys.append(key)
                checks.append((p.axis, 0))
        _gather_layer(layer, out_name, values, out_index, per_axis, _solve_block,
                      locals_, keeps, where, end_keys, checks)
    chunks = tuple(by_axis[d].coef_chunks if d in by_axis else ch
                   for d, ch in enumerate(values.chunks))
    graph = HighLevelGraph.from_collections(out_name, layer, dependencies=[_any(values)])
    c = _da.Array(graph, out_name, chunks, dtype=np.float64, meta=np.empty((0,) * values.ndim))
    for p in plans:
        if p.period:
            # SciPy's periodic layout, exactly: the last k coefficients are the first k (the
            # last chunk's own solve gives them within rounding of the knots' magnitude).
            head = [slice(None)] * c.ndim
            body = [slice(None)] * c.ndim
            head[p.axis], body[p.axis] = slice(0, _K), slice(0, p.nc - _K)
            c = _da.concatenate([c[tuple(body)], c[tuple(head)]], axis=p.axis).rechunk(chunks)
    return ChunkedSpline(c, tuple(plans), h)


def make_interp_spline(x: Coordinates, y: Any, bc_type: Any = None, axis: int = 0,
                       depth: int | str = 32) -> ChunkedSpline:
    """The interpolating cubic spline of a long series or curve chunked along its length
    (SciPy's ``make_interp_spline(x, y, k=3, bc_type, axis)`` for dask arrays).

    Parameters
    ----------
    x : array_like or Regular
        The abscissas (times, parameters), strictly increasing.
    y : dask.array.Array or array_like
        The values: axis `axis` of length ``len(x)``, chunked along it; any other axes (the
        coordinates of a curve's points, several series) are carried along.
    bc_type, depth
        As for `make_interp_grid`.
    axis : int, optional
        The interpolation axis (default 0).

    Returns
    -------
    ChunkedSpline
        ``c`` with SciPy's layout along `axis`; ``t[0]`` SciPy's knots.

    Raises
    ------
    ValueError, TypeError
        As `make_interp_grid`.

    Examples
    --------
    >>> import numpy as np, dask.array as da
    >>> from geomkit.dask import Regular, make_interp_spline
    >>> y = da.sin(da.arange(1000, chunks=128) * 0.01)
    >>> s = make_interp_spline(Regular(0.0, 0.01, 1000), y)
    >>> v = s(Regular(0.0, 0.005, 1999)).compute()
    >>> bool(np.abs(v - np.sin(np.arange(1999) * 0.005)).max() < 1e-8)
    True
    """
    return make_interp_grid((x,), y, axes=(axis,), bc_type=bc_type, depth=depth, name="y")


def resample(values: Any, points: Sequence[Coordinates], new_points: Sequence[Coordinates],
             axes: Sequence[int] | None = None, bc_type: Any = None,
             depth: int | str = 32, chunks: int | Sequence[int | None] | None = None
             ) -> da.Array:
    """A grid or series resampled on new rectilinear coordinates through its interpolating
    cubic spline: dask array in, dask array out, lazily (the one-call path).

    ``make_interp_grid(points, values, axes, bc_type, depth)(*new_points, chunks=chunks)``.

    Parameters
    ----------
    values : dask.array.Array or array_like
        The data, chunked along any axes.
    points : sequence of array_like or Regular
        The coordinates of the interpolated axes.
    new_points : sequence of array_like or Regular
        The new coordinates of the same axes (finer, coarser, anywhere; strictly increasing).
    axes, bc_type, depth
        As for `make_interp_grid`.
    chunks : int or sequence of int, optional
        The output chunk sizes of the interpolated axes (default: as many chunks as the input).

    Returns
    -------
    dask.array.Array
        Write it with `to_zarr` (chunk by chunk) when it does not fit in memory.

    Examples
    --------
    >>> import numpy as np, dask.array as da
    >>> from geomkit.dask import resample
    >>> x = np.linspace(0, 1, 50)
    >>> z = da.from_array(np.outer(np.cos(x), x**2), chunks=16)
    >>> out = resample(z, (x, x), (np.linspace(0, 1, 99), np.linspace(0, 1, 20)))
    >>> out.shape
    (99, 20)
    """
    spline = make_interp_grid(points, values, axes=axes, bc_type=bc_type, depth=depth)
    return spline(*new_points, chunks=chunks)


def required_depth(points: Sequence[Coordinates], chunks: Sequence[int | Sequence[int]],
                   bc_type: Any = None) -> int:
    """The smallest halo whose decay the bound certifies for these coordinates and chunks.

    Parameters
    ----------
    points : sequence of array_like or Regular
        The coordinates of each interpolated axis.
    chunks : sequence of int or sequence of int
        The chunk size (or the chunk sizes) along each of those axes.
    bc_type : optional
        As for `make_interp_grid`.

    Returns
    -------
    int
        29 for uniform coordinates split in chunks (0.268^28 < 2**-53 over the 28 rows
        between an artificial end and the first kept coefficient; depth 32 has margin),
        more for irregular ones; 1 when nothing is split.

    Examples
    --------
    >>> from geomkit.dask import Regular, required_depth
    >>> required_depth([Regular(0.0, 1.0, 10_000)], [1000])
    29
    """
    if len(chunks) != len(points):
        raise ValueError(f"chunks: one entry per coordinate array, got {len(chunks)}")
    ends = _bc_list(bc_type, list(range(len(points))))
    plans = []
    for d, (coords, ch, e) in enumerate(zip(points, chunks, ends)):
        coord = _Coords(coords, f"points[{d}]")
        if isinstance(ch, int):
            sizes = tuple(min(ch, coord.n - u) for u in range(0, coord.n, max(ch, 1)))
        else:
            sizes = tuple(index(v, "chunks") for v in ch)
        if sum(sizes) != coord.n:
            raise ValueError(f"chunks of axis {d} cover {sum(sizes)} points, not {coord.n}")
        plans.append(_Axis(coord, e, sizes, d, f"points[{d}]"))
    return max(_needed(p) for p in plans)


def to_zarr(array: da.Array, url: Any, component: str | None = None, overwrite: bool = False,
            chunks: int | Sequence[int] | None = None, **kwargs: Any) -> Any:
    """Writes a (lazy) result to a Zarr store chunk by chunk: each task computes its block and
    writes it, so the whole array never exists in memory.

    Zarr wants regular chunks (all equal but the last): irregular ones (a spline's
    coefficients) are rechunked to the first chunk's size (or `chunks`), locally.

    Parameters
    ----------
    array : dask.array.Array
    url : str or store
        A path, URL or Zarr store (as ``dask.array.to_zarr``).
    component : str, optional
        The array's path inside the store.
    overwrite : bool, optional
        Replace an existing array (default False: an existing array is an error).
    chunks : int or sequence of int, optional
        The chunks of the stored array.
    **kwargs
        Passed on to ``dask.array.to_zarr`` (e.g. ``compute=False`` for a delayed write).

    Returns
    -------
    The value of ``dask.array.to_zarr``.
    """
    if not isinstance(array, da.Array):
        raise TypeError(f"to_zarr writes a dask array, got {type(array).__name__}")
    arr: Any = array
    if chunks is not None:
        arr = arr.rechunk(chunks)
    elif any(len(set(ch[:-1])) > 1 or (len(ch) > 1 and ch[-1] > ch[0])
             for ch in arr.chunks):
        arr = arr.rechunk(tuple(max(ch) for ch in arr.chunks))
    return _da.to_zarr(arr, url, component=component, overwrite=overwrite, **kwargs)
