"""Point calculus (spec/point-calculus.md, method 4): point equations of curves, surfaces and
k-factor models through experimental points, computed by geomkit's Rust library.

- `PointModel`: a model of one or more responses over k factors through a full grid of
  experimental points (``geomkit pointcalc fit``), its values (``eval``), the share of every
  experimental point in a modeled point (``shares``), the certified optimum (``optimize``),
  its formula in 11 syntaxes (``formula``);
- `point_curve` / `PointCurve`: M(t) = sum_i L_i(t) A_i through source points
  (``geomkit pointcalc curve``), equations (1)-(3) of the spec for three points;
- `point_surface` / `PointSurface`: surfaces through a net of source points, rows first then
  across, or the paper's geomatrix (9) as printed (``geomkit pointcalc surface``);
- `PointCurveSamples`, `PointSurfaceSamples`: the sample files those commands write, as
  `geomkit.load` returns them.

Node sets (a factor's levels, a curve's nodes) are given as in the CLI's ``--nodes``: an
array of positions; exact rationals (`fractions.Fraction`, ``"1/3"``, or the string
``"0,1/3,1"``), kept exact in formulas; a preset ``"cheb1:N[:LO:HI]"``, ``"cheb2:N..."``,
``"equi:N..."``; or one of the paper's ``"half"``, ``"third"``, ``"two-thirds"``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Union, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import aligned, contiguous, index, real_array, real_scalar
from ._model import Drawable, register_kind
from ._progress import chunked

__all__ = [
    "Optimum",
    "PointCurve",
    "PointCurveSamples",
    "PointModel",
    "PointSurface",
    "PointSurfaceSamples",
    "point_curve",
    "point_surface",
]

F64 = NDArray[np.float64]
NodeSpec = Union[str, ArrayLike, Sequence[Union[Fraction, str, int, float]]]
# A node set in a form that rebuilds it exactly (pickling): ("paper", name),
# ("preset", kind, n, lo, hi), ("exact", ("p/q", ...)) or ("values", (x, ...)).
_Spec = tuple[Any, ...]

_FORMATS = ("maple", "mathematica", "sympy", "numpy", "matlab", "latex", "c", "rust", "glsl",
            "js", "desmos")
_PRESETS = {"cheb1": "cheb1", "chebyshev1": "cheb1", "cheb2": "cheb2", "chebyshev2": "cheb2",
            "equi": "equi", "equispaced": "equi"}
_PAPER = ("half", "third", "two-thirds")


# --------------------------------------------------------------------------------------------
# node sets


def _spec_of_string(text: str, what: str) -> _Spec:
    """The CLI's node specification string as a normalized spec."""
    s = text.strip()
    if s in _PAPER:
        return ("paper", s)
    if ":" in s:
        parts = s.split(":")
        kind = _PRESETS.get(parts[0])
        if kind is None:
            raise ValueError(f"{what}: unknown node preset {parts[0]!r} (cheb1, cheb2, equi)")
        if len(parts) not in (2, 4):
            raise ValueError(f"{what}: node preset {s!r}: use NAME:N or NAME:N:LO:HI")
        try:
            n = int(parts[1])
        except ValueError:
            raise ValueError(f"{what}: {parts[1]!r} is not a node count") from None
        bounds = [0.0, 1.0]
        for i, x in enumerate(parts[2:]):
            try:
                bounds[i] = float(x)
            except ValueError:
                raise ValueError(f"{what}: {x!r} is not a number (in {s!r})") from None
            if not np.isfinite(bounds[i]):
                raise ValueError(f"{what}: {x!r} is not a finite number (in {s!r})")
        if n < 1:
            raise ValueError(f"{what}: a node set has at least 1 node, got {n}")
        return ("preset", kind, n, bounds[0], bounds[1])
    items = [x.strip() for x in s.split(",")]
    if any("/" in x for x in items):
        return ("exact", tuple(items))
    try:
        return ("values", tuple(float(x) for x in items))
    except ValueError:
        raise ValueError(f"{what}: {s!r} is not a node list (numbers or fractions "
                         "separated by commas), a preset or half/third/two-thirds") from None


def _spec(nodes: NodeSpec, what: str) -> _Spec:
    """A node set argument as a normalized spec (see the module docs for the forms)."""
    if isinstance(nodes, str):
        return _spec_of_string(nodes, what)
    if isinstance(nodes, Sequence) and not isinstance(nodes, (bytes, bytearray)) and any(
        isinstance(x, (Fraction, str)) for x in nodes
    ):
        exact: list[str] = []
        for x in nodes:
            if isinstance(x, Fraction):
                exact.append(f"{x.numerator}/{x.denominator}")
            elif isinstance(x, str):
                exact.append(x)
            elif isinstance(x, (int, np.integer)) and not isinstance(x, bool):
                exact.append(str(int(x)))
            else:
                exact.append(repr(real_scalar(x, what)))
        return ("exact", tuple(exact))
    values = real_array(cast(ArrayLike, nodes), what)
    if values.ndim != 1:
        raise ValueError(f"{what}: nodes must be one-dimensional, got shape {values.shape}")
    return ("values", tuple(float(x) for x in values))


def _build(spec: _Spec) -> _geomkit.PointNodes:
    """The compiled node set of a normalized spec (the library's checks: ValueError)."""
    kind = spec[0]
    if kind == "paper":
        return _geomkit.PointNodes.paper(spec[1])
    if kind == "preset":
        return _geomkit.PointNodes.preset(spec[1], spec[2], spec[3], spec[4])
    if kind == "exact":
        return _geomkit.PointNodes.exact(list(spec[1]))
    return _geomkit.PointNodes(np.array(spec[1], dtype=np.float64))


def _nodes(nodes: NodeSpec, what: str) -> tuple[_geomkit.PointNodes, _Spec]:
    """A node set argument as compiled nodes and the spec that rebuilds them."""
    spec = _spec(nodes, what)
    try:
        return _build(spec), spec
    except ValueError as e:
        raise ValueError(f"{what}: {e}") from None


def _default_spec(n: int) -> _Spec:
    """The CLI's default nodes: equally spaced exact j/(n-1) (one node: 0)."""
    if n <= 1:
        return ("values", (0.0,))
    return ("exact", tuple(f"{j}/{n - 1}" for j in range(n)))


def _values(nodes: _geomkit.PointNodes) -> F64:
    out = np.empty(nodes.count)
    nodes.values_into(out)
    return out


def _exact(nodes: _geomkit.PointNodes) -> tuple[Fraction, ...] | None:
    exact = nodes.exact_values()
    return None if exact is None else tuple(Fraction(x) for x in exact)


def _format(fmt: str) -> str:
    if not isinstance(fmt, str):
        raise TypeError(f"fmt must be a str, got {type(fmt).__name__}")
    return fmt


def _lebesgue_limit(limit: float | None) -> float | None:
    return None if limit is None else real_scalar(limit, "lebesgue_limit")


def _is_dataframe(obj: Any) -> bool:
    """A pandas DataFrame (checked without importing pandas)."""
    return type(obj).__name__ == "DataFrame" and type(obj).__module__.startswith("pandas")


def _columns(df: Any, names: Sequence[str], what: str) -> F64:
    """The columns `names` of a DataFrame as an (n, len(names)) C-contiguous float64 array."""
    have = [str(c) for c in df.columns]
    missing = [n for n in names if n not in have]
    if missing:
        shown = ", ".join(have[:20]) + (", ..." if len(have) > 20 else "")
        raise ValueError(f"{what}: no column {missing[0]!r} in the DataFrame (columns: {shown})")
    cols = [real_array(df[n].to_numpy(), f"{what}: column {n!r}") for n in names]
    for n, c in zip(names, cols):
        if c.ndim != 1:
            raise ValueError(f"{what}: column {n!r} is not one column (a repeated name?)")
    return aligned(np.stack(cols, axis=1) if cols else np.empty((len(df), 0)))


def _response_names(names: Any, r: int) -> list[str]:
    """The names of r responses: given, or ``y`` / ``y1, y2, ...``."""
    if names is None:
        return ["y"] if r == 1 else [f"y{i + 1}" for i in range(r)]
    out = _names(names, "response_names")
    if len(out) != r:
        raise ValueError(f"{len(out)} response names for {r} responses")
    return out


def _names(names: Any, what: str) -> list[str]:
    if isinstance(names, str):
        return [names]
    out = list(names)
    for n in out:
        if not isinstance(n, str):
            raise TypeError(f"{what} must be names (str), got {type(n).__name__}")
    return out


# --------------------------------------------------------------------------------------------
# k-factor models


@dataclass(frozen=True)
class Optimum:
    """The certified optimum of a `PointModel` (`PointModel.optimize`).

    Attributes
    ----------
    value : float
        The modeled response at `location` (the best point found).
    location : ndarray, shape (k,)
        The factor values of the best point, in the model's factor order.
    bound : float
        The certified bound: no point of the factors' box does better than this.
    gap : float
        ``abs(bound - value)``: the optimum lies in ``[value, bound]`` (maximum) or
        ``[bound, value]`` (minimum).
    certified : bool
        Whether the gap reached the tolerance within the search budgets.
    boxes : int
        Boxes the branch and bound examined.
    factors : tuple of str
        The factor names, the order of `location`.
    """

    value: float
    location: F64
    bound: float
    gap: float
    certified: bool
    boxes: int
    factors: tuple[str, ...]

    @property
    def at(self) -> dict[str, float]:
        """The location as ``{factor name: value}``."""
        return {n: float(x) for n, x in zip(self.factors, self.location)}


class PointModel(Drawable):
    """A point-calculus model of one or more responses over k factors through a full grid of
    experimental points (spec/point-calculus.md §4; ``geomkit pointcalc fit``).

    M(x) = sum over the cells c of s_c(x) y_c, with the shares s_c(x) = prod_f L^(f)_(c_f)(x_f)
    the products of each factor's cardinal (Lagrange, barycentric) functions at its levels:
    the model passes through every experimental point exactly, and the shares sum to 1.

    Build it with `PointModel.fit` (levels and a grid of responses),
    `PointModel.from_records` (a table of experiments) or `PointModel.from_dataframe`, or
    read one with `geomkit.load`.

    Attributes
    ----------
    factors : tuple of str
        The factor names, in order.
    responses : tuple of str
        The response names.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import PointModel
    >>> a, b = [0.0, 0.5, 1.0], [0.0, 1.0]
    >>> m = PointModel.fit({"a": a, "b": b}, np.add.outer(np.square(a), b))
    >>> float(m.eval([0.25, 0.5])[0])
    0.5625
    """

    _core: _geomkit.PointcalcModel

    def __init__(self, core: _geomkit.PointcalcModel) -> None:
        if not isinstance(core, _geomkit.PointcalcModel):
            raise TypeError("PointModel is built by PointModel.fit, from_records, "
                            "from_dataframe or geomkit.load")
        self._core = core

    # --- construction --------------------------------------------------------------------

    @classmethod
    def fit(
        cls,
        factors: Mapping[str, NodeSpec] | Sequence[NodeSpec],
        response: ArrayLike,
        *,
        factor_names: Sequence[str] | None = None,
        response_names: Sequence[str] | str | None = None,
        strict: bool = False,
        lebesgue_limit: float | None = None,
    ) -> PointModel:
        """The model through a grid of responses at the levels of every factor.

        Parameters
        ----------
        factors : mapping of name to levels, or sequence of levels
            The levels (nodes) of each factor, in order: arrays of distinct finite numbers,
            exact rationals (`fractions.Fraction` or strings ``"1/3"``), or the CLI's node
            specifications (``"cheb2:5:0:1"``, ``"0,1/3,1"``, ``"third"``). At most 5000
            levels per factor.
        response : array_like, shape (n_1, ..., n_k) or (n_1, ..., n_k, r)
            The response(s) at every combination of levels: ``response[i, j, ...]`` at
            (level i of factor 1, level j of factor 2, ...); a last axis of r responses.
            At most 10^8 numbers.
        factor_names : sequence of str, optional
            Names of the factors when `factors` is a sequence (default ``x1, x2, ...``).
        response_names : sequence of str or str, optional
            Names of the responses (default ``y`` or ``y1, y2, ...``).
        strict : bool, optional
            Fail instead of warning when a factor's Lebesgue constant exceeds the limit.
        lebesgue_limit : float, optional
            The limit (default: the library's for the number of levels).

        Returns
        -------
        PointModel

        Raises
        ------
        ValueError
            For a response grid of another shape, NaN or infinite responses, duplicate or
            non-finite levels, repeated names, too many numbers.
        TypeError
            For values that are not real numbers.

        Examples
        --------
        >>> from fractions import Fraction
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0, Fraction(1, 3), 1]}, [1.0, 2.0, 0.0])
        >>> m.levels["t"].tolist()
        [0.0, 0.3333333333333333, 1.0]
        """
        if isinstance(factors, Mapping):
            names = [str(n) for n in factors]
            level_specs = list(factors.values())
            if factor_names is not None:
                raise ValueError("factor_names: the names are the keys of the factors mapping")
        else:
            if isinstance(factors, (str, bytes)):
                raise TypeError("factors must be a mapping or a sequence of level sets")
            level_specs = list(factors)
            names = (_names(factor_names, "factor_names") if factor_names is not None
                     else [f"x{i + 1}" for i in range(len(level_specs))])
            if len(names) != len(level_specs):
                raise ValueError(f"{len(names)} factor names for {len(level_specs)} factors")
        if not level_specs:
            raise ValueError("no factors: a model has at least one factor")
        built = [_nodes(s, f"factor {n!r}")[0] for n, s in zip(names, level_specs)]
        shape = tuple(b.count for b in built)
        values = real_array(response, "response")
        if values.shape == shape:
            r = 1
        elif values.ndim == len(shape) + 1 and values.shape[:-1] == shape:
            r = values.shape[-1]
        else:
            raise ValueError(
                f"response has shape {values.shape}; the levels make a grid of shape {shape} "
                f"(or {shape + ('r',)} for r responses)")
        responses = _response_names(response_names, r)
        _check_finite(values, "response")
        flat = aligned(values).reshape(-1)
        core = _geomkit.PointcalcModel.from_grid(
            names, built, responses, flat, bool(strict), _lebesgue_limit(lebesgue_limit))
        return cls(core)

    @classmethod
    def from_records(
        cls,
        x: ArrayLike,
        y: ArrayLike,
        *,
        factor_names: Sequence[str] | None = None,
        response_names: Sequence[str] | str | None = None,
        nodes: Mapping[str, NodeSpec] | None = None,
        strict: bool = False,
        lebesgue_limit: float | None = None,
    ) -> PointModel:
        """The model through a table of experiments, as ``geomkit pointcalc fit`` reads its
        CSV: one row per experiment, the factor values then the response(s).

        The factor columns must take a full grid of levels: every combination of the levels
        present, exactly once. Each factor's levels are the distinct values of its column,
        or the nodes given for it in `nodes` (the data matched to them within 1e-9 of their
        span, e.g. 0.3333333333 to the exact 1/3).

        Parameters
        ----------
        x : array_like, shape (n, k)
            The factor values of every experiment.
        y : array_like, shape (n,) or (n, r)
            The response(s) of every experiment.
        factor_names, response_names : sequence of str, optional
            Names (default ``x1, ...`` and ``y`` or ``y1, ...``).
        nodes : mapping of factor name to node specification, optional
            Explicit nodes of some factors (the CLI's ``--nodes``).
        strict, lebesgue_limit
            As for `PointModel.fit`.

        Returns
        -------
        PointModel

        Raises
        ------
        ValueError
            For records that do not make a full grid (a missing or repeated cell, a level
            not among the given nodes), NaN or infinite values, shapes that do not match.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> x = [[0, 0], [0, 1], [1, 0], [1, 1]]
        >>> m = PointModel.from_records(x, [0.0, 1.0, 2.0, 3.0], factor_names=["a", "b"])
        >>> m.shape, m.values[..., 0].tolist()
        ((2, 2), [[0.0, 1.0], [2.0, 3.0]])
        """
        xs = real_array(x, "x")
        ys = real_array(y, "y")
        if xs.ndim != 2:
            raise ValueError(f"x must be a 2-D array (experiments, factors), got shape {xs.shape}")
        if ys.ndim == 1:
            ys = ys[:, None]
        if ys.ndim != 2 or ys.shape[0] != xs.shape[0]:
            raise ValueError(f"y has shape {real_array(y, 'y').shape}, expected ({xs.shape[0]},) "
                             f"or ({xs.shape[0]}, r)")
        k, r = xs.shape[1], ys.shape[1]
        names = (_names(factor_names, "factor_names") if factor_names is not None
                 else [f"x{i + 1}" for i in range(k)])
        if len(names) != k:
            raise ValueError(f"{len(names)} factor names for {k} factor columns")
        responses = _response_names(response_names, r)
        return cls._records(names, responses, np.hstack([xs, ys]), nodes, strict, lebesgue_limit)

    @classmethod
    def from_dataframe(
        cls,
        df: Any,
        factors: Sequence[str],
        response: Sequence[str] | str,
        *,
        nodes: Mapping[str, NodeSpec] | None = None,
        strict: bool = False,
        lebesgue_limit: float | None = None,
    ) -> PointModel:
        """The model through the experiments of a pandas DataFrame (one row each), as
        ``geomkit pointcalc fit --factors ... --response ...`` over a CSV file.

        Parameters
        ----------
        df : pandas.DataFrame
            The experiments.
        factors : sequence of str
            The factor columns (they must take a full grid of levels).
        response : sequence of str or str
            The response column(s).
        nodes, strict, lebesgue_limit
            As for `PointModel.from_records`.

        Returns
        -------
        PointModel
            The same model, bit for bit, as `from_records` over the same numbers.

        Raises
        ------
        ValueError
            For a column the DataFrame does not have, a column named twice, and as
            `from_records`.
        TypeError
            For `df` other than a DataFrame and columns that are not numbers.

        Examples
        --------
        >>> import pandas as pd
        >>> from geomkit import PointModel
        >>> df = pd.DataFrame({"a": [0, 0, 1, 1], "b": [0, 1, 0, 1], "y": [0, 1, 2, 3.5]})
        >>> m = PointModel.from_dataframe(df, factors=["a", "b"], response=["y"])
        >>> float(m.eval(df[["a", "b"]])[3, 0])
        3.5
        """
        if not _is_dataframe(df):
            raise TypeError(f"from_dataframe() takes a pandas DataFrame, not {type(df).__name__}")
        names = _names(factors, "factors")
        responses = _names(response, "response")
        seen: set[str] = set()
        for c in names + responses:
            if c in seen:
                raise ValueError(f"column {c!r} is named twice in factors/response")
            seen.add(c)
        table = _columns(df, names + responses, "from_dataframe")
        return cls._records(names, responses, table, nodes, strict, lebesgue_limit)

    @classmethod
    def _records(cls, names: list[str], responses: list[str], table: F64,
                 nodes: Mapping[str, NodeSpec] | None, strict: bool,
                 lebesgue_limit: float | None) -> PointModel:
        given: list[_geomkit.PointNodes | None] = [None] * len(names)
        for name, spec in (nodes or {}).items():
            if name not in names:
                raise ValueError(f"nodes: {name!r} is not one of the factors ({', '.join(names)})")
            given[names.index(name)] = _nodes(spec, f"nodes for {name!r}")[0]
        if table.shape[0] == 0:
            raise ValueError("no experiments: the table is empty")
        _check_finite(table, "records")
        core = _geomkit.PointcalcModel.from_records(
            names, aligned(table), given, responses, bool(strict),
            _lebesgue_limit(lebesgue_limit))
        return cls(core)

    @classmethod
    def _from_model(cls, model: _geomkit.Model) -> PointModel:
        return cls(_geomkit.PointcalcModel.from_model(model))

    def _model(self) -> _geomkit.Model:
        return self._core.to_model()

    def __reduce__(self) -> tuple[Any, ...]:
        return (_point_model_from_json, (self.to_json(),))

    def __repr__(self) -> str:
        levels = ", ".join(f"{n}: {s}" for n, s in zip(self.factors, self.shape))
        return f"<geomkit.PointModel of {', '.join(self.responses)} over {levels} levels>"

    # --- what it is ----------------------------------------------------------------------

    @property
    def factors(self) -> tuple[str, ...]:
        """The factor names, in order (the columns of `eval`'s points)."""
        return tuple(self._core.factor_names)

    @property
    def responses(self) -> tuple[str, ...]:
        """The response names (the columns of `eval`'s results)."""
        return tuple(self._core.response)

    @property
    def shape(self) -> tuple[int, ...]:
        """The number of levels of every factor (the grid of experimental points)."""
        return tuple(self._core.shape)

    @property
    def levels(self) -> dict[str, F64]:
        """The levels (nodes) of every factor: ``{name: increasing array}``."""
        return {n: _values(self._core.nodes(i)) for i, n in enumerate(self.factors)}

    @property
    def exact_levels(self) -> dict[str, tuple[Fraction, ...] | None]:
        """The levels as exact fractions for the factors given exact nodes, else None."""
        return {n: _exact(self._core.nodes(i)) for i, n in enumerate(self.factors)}

    @property
    def values(self) -> F64:
        """The responses at the grid, shape ``shape + (len(responses),)``."""
        out = np.empty(int(np.prod(self.shape)) * len(self.responses))
        self._core.values_into(out)
        return out.reshape(self.shape + (len(self.responses),))

    @property
    def warnings(self) -> tuple[str, ...]:
        """The fit's warnings (a factor with a large Lebesgue constant)."""
        return tuple(self._core.warnings)

    # --- evaluation ----------------------------------------------------------------------

    def _points(self, x: Any, what: str) -> F64:
        if _is_dataframe(x):
            return _columns(x, self.factors, what)
        if isinstance(x, Mapping):
            missing = [n for n in self.factors if n not in x]
            if missing:
                raise ValueError(f"{what}: no value for factor {missing[0]!r}")
            return aligned(np.stack(
                [real_array(x[n], f"{what}: {n}").reshape(-1) for n in self.factors], axis=1))
        return contiguous(x, what)

    def eval(self, x: Any) -> F64:
        """The modeled responses M(x) (spec §4: the point equation of the hypersurface).

        Parameters
        ----------
        x : array_like, shape (n, k) or (k,); or a pandas DataFrame; or a mapping
            The points: rows of factor values in the order of `factors`; a DataFrame (or a
            mapping of arrays) with a column per factor name, in any order. For a model of
            one factor, shape (n,) is n points and a number is one.

        Returns
        -------
        ndarray, shape (n, len(responses)), or (len(responses),) for one point (shape (k,),
        or a number for one factor)

        Raises
        ------
        ValueError
            For points of another width, NaN or infinite values, a point so far outside
            the levels that its response is beyond float64 or lost to rounding, and a
            DataFrame without a factor's column.

        Notes
        -----
        Evaluated in SIMD blocks with the GIL released; at an experimental point the result
        is exactly its response.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0.0, 0.5, 1.0]}, [0.0, 1.0, 0.0])
        >>> m.eval([[0.25], [0.5]]).ravel().tolist()
        [0.75, 1.0]
        """
        xs = self._points(x, "x")
        k = len(self.factors)
        # One point: (k,) values, or a number for a one-factor model (where (n,) are n points).
        single = xs.ndim == 1 and (k > 1 or np.ndim(x) == 0)
        if xs.ndim == 1:
            xs = xs.reshape(1, -1) if single else xs.reshape(-1, 1)
        if xs.ndim != 2 or xs.shape[1] != k:
            raise ValueError(f"x has shape {xs.shape}; expected (n, {k}) rows of the factors "
                             f"{', '.join(self.factors)}")
        _check_finite(xs, "x")
        out = np.empty((xs.shape[0], len(self.responses)))
        rows, core = aligned(xs), self._core
        chunked(rows.shape[0], lambda a, b: core.eval_into(rows[a:b], out[a:b]), "PointModel")
        return out[0] if single else out

    def __call__(self, x: Any) -> F64:
        """The same as `eval`.

        Parameters
        ----------
        x : array_like or DataFrame
            As for `eval`.
        """
        return self.eval(x)

    def shares(self, x: Any) -> F64:
        """The share of every experimental point in the modeled point M(x): the
        function-parameters of the point equation (spec §1, §4).

        Parameters
        ----------
        x : array_like, shape (k,), or a mapping ``{factor name: value}``
            One point.

        Returns
        -------
        ndarray, shape `shape`
            ``shares[i, j, ...]`` is the share of the experiment at (level i of the first
            factor, level j of the second, ...); they sum to 1 (to rounding), and at an
            experimental point they are 1 there and 0 elsewhere.

        Raises
        ------
        ValueError
            For a point of another length, NaN or infinite values, a share beyond float64.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0.0, 0.5, 1.0]}, [3.0, 1.0, 2.0])
        >>> m.shares([0.25]).tolist()
        [0.375, 0.75, -0.125]
        """
        if isinstance(x, Mapping):
            missing = [n for n in self.factors if n not in x]
            if missing:
                raise ValueError(f"x: no value for factor {missing[0]!r}")
            point = np.array([real_scalar(x[n], f"x: {n}") for n in self.factors])
        else:
            point = contiguous(x, "x").reshape(-1) if np.ndim(x) <= 1 else contiguous(x, "x")
        if point.shape != (len(self.factors),):
            raise ValueError(f"x has shape {point.shape}, expected ({len(self.factors)},): "
                             f"one value per factor ({', '.join(self.factors)})")
        _check_finite(point, "x")
        out = np.empty(int(np.prod(self.shape)))
        self._core.shares_into(aligned(point), out)
        return out.reshape(self.shape)

    def optimize(
        self,
        maximize: bool = True,
        *,
        response: str | None = None,
        tolerance: float = 1e-9,
        max_boxes: int = 4000,
        max_work: int = 10**9,
    ) -> Optimum:
        """The largest (or smallest) modeled response over the box of the factors' levels,
        global and certified (``geomkit pointcalc optimize``; spec §4, decision support).

        Branch and bound with Bernstein bounds of the polynomial model: the result's `bound`
        is a proven bound of the response over the whole box.

        Parameters
        ----------
        maximize : bool, optional
            The largest (default) or the smallest response.
        response : str, optional
            The response to optimize (required when the model has several).
        tolerance : float, optional
            Stop when ``gap <= tolerance * (range of the responses)`` (default 1e-9).
        max_boxes, max_work : int, optional
            The search budgets (boxes, operations); when they run out the result comes
            with ``certified=False`` and its (larger) gap.

        Returns
        -------
        Optimum

        Raises
        ------
        ValueError
            For an unknown response, several responses and none chosen, a negative or
            non-finite tolerance, a model too large for one box within the budget.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0.0, 0.5, 1.0]}, [0.0, 1.0, 0.0])
        >>> best = m.optimize()
        >>> best.value, best.location.tolist(), best.certified
        (1.0, [0.5], True)
        """
        core = self._core
        if response is not None:
            if response not in self.responses:
                raise ValueError(f"response {response!r} is not one of {', '.join(self.responses)}")
            if len(self.responses) > 1:
                j = self.responses.index(response)
                nodes = [core.nodes(i) for i in range(len(self.factors))]
                core = _geomkit.PointcalcModel.from_grid(
                    list(self.factors), nodes, [response],
                    aligned(self.values[..., j]).reshape(-1))
        tol = real_scalar(tolerance, "tolerance")
        boxes, work = index(max_boxes, "max_boxes"), index(max_work, "max_work")
        if boxes < 1 or work < 1:
            raise ValueError(f"max_boxes={boxes} and max_work={work} must be positive")
        at, value, bound, gap, examined, certified = core.optimize(
            bool(maximize), tol, boxes, min(work, 2**64 - 1))
        return Optimum(value=value, location=np.array(at), bound=bound, gap=gap,
                       certified=certified, boxes=examined, factors=self.factors)

    # --- changing the model without a solve (spec §4) -----------------------------------

    def _factor(self, name: str) -> int:
        if not isinstance(name, str):
            raise TypeError(f"factor must be a factor name (str), got {type(name).__name__}")
        if name not in self.factors:
            raise ValueError(f"{name!r} is not one of the factors ({', '.join(self.factors)})")
        return self.factors.index(name)

    def _level(self, name: str, level: int) -> int:
        n = self.shape[self._factor(name)]
        i = index(level, "level")
        if not 0 <= i < n:
            raise ValueError(f"level {i} of factor {name!r}: it has {n} levels (0 to {n - 1})")
        return i

    def fix(self, factor: str, value: float) -> PointModel:
        """The model with one factor fixed at a value and removed: the section of the
        hypersurface there, a model over the other factors (spec §4, fewer factors without
        rebuilding the model).

        Parameters
        ----------
        factor : str
            The factor's name.
        value : float
            Its value (any, also between or outside its levels).

        Returns
        -------
        PointModel
            Over the other factors: ``fix(f, x).eval(rest) == eval(with f = x)``.

        Raises
        ------
        ValueError
            For an unknown factor, the only factor, a non-finite value, a section beyond
            float64.

        Examples
        --------
        >>> import numpy as np
        >>> from geomkit import PointModel
        >>> a, b = [0.0, 0.5, 1.0], [0.0, 1.0]
        >>> m = PointModel.fit({"a": a, "b": b}, np.add.outer(np.square(a), b))
        >>> m.fix("a", 0.25).factors, m.fix("a", 0.25).eval([[0.5]]).tolist()
        (('b',), [[0.5625]])
        """
        f = self._factor(factor)
        return PointModel(self._core.fix_factor(f, real_scalar(value, "value")))

    def section(self, factor: str, level: int) -> PointModel:
        """The model with one factor removed by keeping one of its levels (the experiments
        at that level, as a model over the other factors).

        Parameters
        ----------
        factor : str
            The factor's name.
        level : int
            The index of the level kept (0 to ``shape[f] - 1``).

        Returns
        -------
        PointModel

        Raises
        ------
        ValueError
            For an unknown factor or level, the only factor.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"a": [0.0, 1.0], "b": [0.0, 1.0]}, [[1.0, 2.0], [3.0, 4.0]])
        >>> m.section("a", 1).values[..., 0].tolist()
        [3.0, 4.0]
        """
        f = self._factor(factor)
        return PointModel(self._core.remove_factor(f, self._level(factor, level)))

    def without_level(self, factor: str, level: int) -> PointModel:
        """The model without one level of a factor and its experiments (spec §4, fewer
        points without rebuilding: only that factor's nodes change).

        Parameters
        ----------
        factor : str
            The factor's name.
        level : int
            The index of the level removed.

        Returns
        -------
        PointModel

        Raises
        ------
        ValueError
            For an unknown factor or level, the factor's last level.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0.0, 0.5, 1.0]}, [0.0, 1.0, 0.0])
        >>> m.without_level("t", 1).levels["t"].tolist()
        [0.0, 1.0]
        """
        f = self._factor(factor)
        return PointModel(self._core.remove_level(f, self._level(factor, level)))

    def with_level(self, factor: str, value: float, responses: ArrayLike) -> PointModel:
        """The model with a new level of a factor and the responses of its experiments
        (spec §4, more points without rebuilding).

        Parameters
        ----------
        factor : str
            The factor's name.
        value : float
            The new level (not one of the factor's levels).
        responses : array_like
            The responses at the new level over the grid of the other factors: shape
            (the other factors' level counts) for one response, plus a last axis of r.

        Returns
        -------
        PointModel

        Raises
        ------
        ValueError
            For an unknown factor, a level already there, responses of another shape, NaN
            or infinite values.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0.0, 1.0]}, [0.0, 1.0])
        >>> m.with_level("t", 2.0, [4.0]).eval(1.5).tolist()
        [2.25]
        """
        f = self._factor(factor)
        rest = tuple(n for i, n in enumerate(self.shape) if i != f)
        r = len(self.responses)
        ys = real_array(responses, "responses")
        if ys.shape not in (rest + (r,), rest if r == 1 else None):
            want = rest + (r,) if r > 1 else rest
            raise ValueError(f"responses has shape {ys.shape}; the other factors make a grid "
                             f"of shape {want}")
        _check_finite(ys, "responses")
        return PointModel(self._core.add_level(f, real_scalar(value, "value"),
                                               aligned(ys).reshape(-1)))

    def formula(self, fmt: str = "numpy") -> str:
        """The model as one formula per response (``geomkit pointcalc formula``): the point
        equation written out with every experimental point and the exact levels.

        Parameters
        ----------
        fmt : str, optional
            The syntax: 'maple', 'mathematica', 'sympy', 'numpy' (default), 'matlab',
            'latex', 'c', 'rust', 'glsl', 'js', 'desmos'.

        Returns
        -------
        str
            A program in that syntax: its preamble, then one definition per response named
            after it with the factors as parameters (NumPy: ``y = lambda a, b: ...``).

        Raises
        ------
        ValueError
            For an unknown syntax, a formula of more than 10^7 factors, a coefficient
            beyond float64.

        Examples
        --------
        >>> from geomkit import PointModel
        >>> m = PointModel.fit({"t": [0, 1]}, [1.0, 3.0])
        >>> print(m.formula("sympy"), end="")
        from sympy import *
        t = symbols("t")
        y = 2.0*t + 1.0
        """
        return self._core.formula(_format(fmt))


def _point_model_from_json(text: str) -> PointModel:
    return PointModel._from_model(_geomkit.parse_model(text))


def _check_finite(a: F64, what: str) -> None:
    if not np.all(np.isfinite(a)):
        bad = np.argwhere(~np.isfinite(a))[0]
        where = tuple(int(i) for i in bad)
        raise ValueError(f"{what}: the value at index {where} is {a[where]} (not a finite "
                         "number)")


# --------------------------------------------------------------------------------------------
# curves and surfaces


def _points_2d(points: ArrayLike, what: str) -> F64:
    """Points as an (n, dim) array; a 1-D array is n points of dimension 1."""
    arr = contiguous(points, what)
    if arr.ndim == 1:
        arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise ValueError(f"{what} must be an (n, dim) array of points, got shape {arr.shape}")
    if arr.shape[0] == 0 or arr.shape[1] == 0:
        raise ValueError(f"{what}: no points (shape {arr.shape})")
    _check_finite(arr, what)
    return aligned(arr)


class PointCurve(Drawable):
    """A point-equation curve M(t) = sum_i L_i(t) A_i through source points A_i at nodes t_i
    (spec §2; ``geomkit pointcalc curve``). For three points at {0, 1/2, 1}, {0, 1/3, 1} and
    {0, 2/3, 1} it is the paper's equation (1), (2), (3).

    Parameters
    ----------
    points : array_like, shape (n, dim) or (n,)
        The source points, one per node (any dimension; 1-D: numbers).
    nodes : node specification, optional
        The nodes (see the module docs): default equally spaced exact j/(n-1), as the CLI.
    strict : bool, optional
        Fail instead of warning when the Lebesgue constant is large.
    lebesgue_limit : float, optional
        The limit (default: the library's for n nodes).
    samples : int, optional
        Samples of its model file (``pointcalc curve --samples``), 2 to 10^6 (default 201).

    Raises
    ------
    ValueError
        For NaN or infinite points, a node count other than the point count, duplicate
        nodes, a large Lebesgue constant when strict.

    Examples
    --------
    >>> from geomkit import PointCurve
    >>> c = PointCurve([[0.0, 0.0], [1.0, 2.0], [2.0, 0.0]], nodes="half")
    >>> c(0.25).tolist()
    [0.5, 1.5]
    """

    def __init__(self, points: ArrayLike, nodes: NodeSpec | None = None, *,
                 strict: bool = False, lebesgue_limit: float | None = None,
                 samples: int = 201) -> None:
        pts = _points_2d(points, "points")
        spec = _default_spec(pts.shape[0]) if nodes is None else _spec(nodes, "nodes")
        self._init(pts, spec, bool(strict), _lebesgue_limit(lebesgue_limit),
                   index(samples, "samples"))

    def _init(self, pts: F64, spec: _Spec, strict: bool, limit: float | None,
              samples: int) -> None:
        if not 2 <= samples <= 1_000_000:
            raise ValueError(f"samples must be between 2 and 1000000, got {samples}")
        try:
            built = _build(spec)
        except ValueError as e:
            raise ValueError(f"nodes: {e}") from None
        self._core = _geomkit.PointCurve(built, pts, strict, limit)
        self._spec, self._limit, self._samples = spec, limit, samples

    def _model(self) -> _geomkit.Model:
        return self._core.samples_model(self._samples)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild_curve, (self.points, self._spec, self._limit, self._samples))

    def __repr__(self) -> str:
        return (f"<geomkit.PointCurve in R^{self.dim} through {len(self.nodes)} points, "
                f"nodes {self.nodes.tolist()}>")

    @property
    def dim(self) -> int:
        """Coordinates per point."""
        return self._core.dim

    @property
    def nodes(self) -> F64:
        """The nodes t_i, increasing."""
        return _values(self._core.nodes)

    @property
    def exact_nodes(self) -> tuple[Fraction, ...] | None:
        """The nodes as exact fractions, when given exactly (as the default ones are)."""
        return _exact(self._core.nodes)

    @property
    def points(self) -> F64:
        """The source points A_i, shape (n, dim)."""
        out = np.empty((self._core.nodes.count, self.dim))
        self._core.points_into(out)
        return out

    @property
    def domain(self) -> tuple[float, float]:
        """The node interval (first node, last node)."""
        t = self.nodes
        return (float(t[0]), float(t[-1]))

    @property
    def lebesgue_constant(self) -> float:
        """The Lebesgue constant of the nodes: how much the curve can amplify errors of the
        source points (max over the node interval of sum_i abs(L_i(t)))."""
        return self._core.nodes.lebesgue_constant()

    @property
    def warnings(self) -> tuple[str, ...]:
        """Warnings of the construction (a large Lebesgue constant)."""
        return tuple(self._core.warnings)

    def __call__(self, t: ArrayLike) -> F64:
        """The points M(t).

        Parameters
        ----------
        t : array_like
            Parameters of any shape (outside the node interval the curve extrapolates).

        Returns
        -------
        ndarray, shape ``t.shape + (dim,)``

        Raises
        ------
        ValueError
            For NaN or infinite parameters, a point beyond float64.

        Examples
        --------
        >>> from geomkit import point_curve
        >>> point_curve([[0.0, 0.0], [1.0, 1.0]])([0.0, 0.25]).tolist()
        [[0.0, 0.0], [0.25, 0.25]]
        """
        ts = real_array(t, "t")
        out = np.empty((ts.size, self.dim))
        flat, core = aligned(ts.reshape(-1)), self._core
        chunked(flat.shape[0], lambda a, b: core.eval_into(flat[a:b], out[a:b]), "PointCurve")
        return out.reshape(ts.shape + (self.dim,))

    def eval(self, t: ArrayLike) -> F64:
        """The same as calling the curve.

        Parameters
        ----------
        t : array_like
            Parameters of any shape.

        Returns
        -------
        ndarray, shape ``t.shape + (dim,)``
        """
        return self(t)

    def shares(self, t: ArrayLike) -> F64:
        """The share of every source point in M(t): the b-functions L_i(t) (spec §2).

        Parameters
        ----------
        t : array_like
            Parameters of any shape.

        Returns
        -------
        ndarray, shape ``t.shape + (n,)``
            They sum to 1; at node t_j they are 1 at j and 0 elsewhere.

        Raises
        ------
        ValueError
            For NaN or infinite parameters.

        Examples
        --------
        >>> from geomkit import PointCurve
        >>> PointCurve([0.0, 1.0, 0.0], nodes="half").shares(0.25).tolist()
        [0.375, 0.75, -0.125]
        """
        ts = real_array(t, "t")
        _check_finite(ts, "t")
        n = self._core.nodes.count
        out = np.empty((ts.size, n))
        self._core.nodes.basis_into(aligned(ts.reshape(-1)), out)
        return out.reshape(ts.shape + (n,))

    def formula(self, fmt: str = "numpy") -> str:
        """The curve as one formula per coordinate in t (``geomkit pointcalc formula``).

        Parameters
        ----------
        fmt : str, optional
            The syntax, as for `PointModel.formula` (default 'numpy'); the definitions are
            named x, y, z, x3, ...

        Returns
        -------
        str

        Raises
        ------
        ValueError
            For an unknown syntax, a coefficient beyond float64.

        Examples
        --------
        >>> from geomkit import PointCurve
        >>> print(PointCurve([0.0, 1.0, 0.0], nodes="half").formula("sympy"), end="")
        from sympy import *
        t = symbols("t")
        x = -4.0*t*(t - 1)
        """
        return self._core.formula(_format(fmt))


def _rebuild_curve(points: F64, spec: _Spec, limit: float | None, samples: int) -> PointCurve:
    c = PointCurve.__new__(PointCurve)
    c._init(points, spec, False, limit, samples)
    return c


def point_curve(points: ArrayLike, nodes: NodeSpec | None = None, *, strict: bool = False,
                lebesgue_limit: float | None = None, samples: int = 201) -> PointCurve:
    """The point-equation curve through source points (``geomkit pointcalc curve``).

    Parameters
    ----------
    points : array_like, shape (n, dim) or (n,)
        The source points.
    nodes : node specification, optional
        The nodes (default: equally spaced exact j/(n-1)); ``"half"``, ``"third"``,
        ``"two-thirds"`` give the paper's equations (1)-(3).
    strict, lebesgue_limit, samples
        As for `PointCurve`.

    Returns
    -------
    PointCurve

    Raises
    ------
    ValueError
        As `PointCurve`.

    Examples
    --------
    >>> from geomkit import point_curve
    >>> point_curve([[0.0], [1.0], [0.0]], nodes="third")(1 / 3).tolist()
    [1.0]
    """
    return PointCurve(points, nodes, strict=strict, lebesgue_limit=lebesgue_limit,
                      samples=samples)


def _net_rows(net: Any) -> list[F64]:
    """A net as rows of points, each (m_i, dim); a regular array (rows, cols[, dim])."""
    try:
        arr = real_array(net, "net")
        regular = arr.dtype.kind == "f"
    except (TypeError, ValueError):
        regular = False
    if regular:
        if arr.ndim == 2:
            arr = arr[:, :, None]
        if arr.ndim != 3:
            raise ValueError(f"net must have shape (rows, cols, dim) or (rows, cols), got "
                             f"{arr.shape}")
        rows = [aligned(r) for r in arr]
    else:
        if isinstance(net, (str, bytes)) or not isinstance(net, Sequence):
            raise TypeError(f"net must be an array or a sequence of rows, not "
                            f"{type(net).__name__}")
        rows = [_points_2d(r, f"net row {i}") for i, r in enumerate(net)]
    if not rows:
        raise ValueError("net: no rows")
    for i, r in enumerate(rows):
        if r.shape[0] == 0 or r.shape[1] == 0:
            raise ValueError(f"net row {i}: no points")
        _check_finite(r, f"net row {i}")
    return rows


class PointSurface(Drawable):
    """A point-equation surface through a net of source points (spec §3;
    ``geomkit pointcalc surface``).

    Rows first, then across: row i is the curve M_i(u) = sum_j L_j^(i)(u) A_ij through its
    points at its own nodes, and M(u, v) = sum_i L_i(v) M_i(u); its geomatrix
    a_ij = L_i(v) L_j^(i)(u) sums to 1 and the surface passes through every source point.
    With ``printed=True``: the paper's geomatrix (9) exactly as printed (3×3 nets), which
    does neither (kept to show the difference).

    Parameters
    ----------
    net : array_like, shape (rows, cols, dim) or (rows, cols); or a sequence of rows
        The source points ``net[i][j]`` (row i, point j); rows may differ in length.
    nodes : node specification, optional
        The nodes along every row (default: equally spaced exact).
    row_nodes : sequence of node specifications, optional
        The nodes of each row (instead of `nodes`), e.g. ``["third", "half", "two-thirds"]``.
    across : node specification, optional
        The nodes across the rows, one per row (default: equally spaced exact).
    printed : bool, optional
        The paper's geomatrix (9) as printed (no nodes may be given).
    strict, lebesgue_limit
        As for `PointCurve`.
    samples : int, optional
        Samples per direction of its model file (``pointcalc surface --samples``), 2 to
        1000 (default 21).

    Raises
    ------
    ValueError
        For NaN or infinite points, node counts other than the point counts, nodes given
        both ways or with `printed`, a printed net other than 3×3.

    Examples
    --------
    >>> import numpy as np
    >>> from geomkit import PointSurface
    >>> net = np.arange(9.0).reshape(3, 3)
    >>> s = PointSurface(net)
    >>> s(0.5, 1.0).tolist()
    [7.0]
    """

    def __init__(self, net: Any, nodes: NodeSpec | None = None, *,
                 row_nodes: Sequence[NodeSpec] | None = None, across: NodeSpec | None = None,
                 printed: bool = False, strict: bool = False,
                 lebesgue_limit: float | None = None, samples: int = 21) -> None:
        rows = _net_rows(net)
        if printed:
            if nodes is not None or row_nodes is not None or across is not None:
                raise ValueError("printed=True is the paper's geomatrix (9) with its own "
                                 "nodes: nodes, row_nodes and across cannot be given")
            specs: list[_Spec] | None = None
            across_spec: _Spec | None = None
        else:
            if nodes is not None and row_nodes is not None:
                raise ValueError("give nodes (every row) or row_nodes (each row), not both")
            if row_nodes is not None:
                if isinstance(row_nodes, str):
                    row_nodes = row_nodes.split(";")
                row_list = list(row_nodes)
                if len(row_list) != len(rows):
                    raise ValueError(f"row_nodes has {len(row_list)} node sets for "
                                     f"{len(rows)} rows")
                specs = [_spec(s, f"row_nodes[{i}]") for i, s in enumerate(row_list)]
            elif nodes is not None:
                specs = [_spec(nodes, "nodes")] * len(rows)
            else:
                specs = [_default_spec(r.shape[0]) for r in rows]
            across_spec = (_default_spec(len(rows)) if across is None
                           else _spec(across, "across"))
        self._init(rows, specs, across_spec, bool(strict), _lebesgue_limit(lebesgue_limit),
                   index(samples, "samples"))

    def _init(self, rows: list[F64], specs: list[_Spec] | None, across: _Spec | None,
              strict: bool, limit: float | None, samples: int) -> None:
        if not 2 <= samples <= 1000:
            raise ValueError(f"samples must be between 2 and 1000, got {samples}")
        if specs is None or across is None:
            self._core = _geomkit.PointSurface.printed(rows)
        else:
            built = []
            for i, s in enumerate(specs):
                try:
                    built.append(_build(s))
                except ValueError as e:
                    raise ValueError(f"nodes of row {i}: {e}") from None
                if built[-1].count != rows[i].shape[0]:
                    raise ValueError(f"nodes of row {i}: {built[-1].count} nodes for "
                                     f"{rows[i].shape[0]} points")
            try:
                across_nodes = _build(across)
            except ValueError as e:
                raise ValueError(f"across: {e}") from None
            self._core = _geomkit.PointSurface.rows_then_across(
                built, across_nodes, rows, strict, limit)
        self._rows, self._specs, self._across = rows, specs, across
        self._limit, self._samples = limit, samples

    def _model(self) -> _geomkit.Model:
        return self._core.samples_model(self._samples)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild_surface,
                (self._rows, self._specs, self._across, self._limit, self._samples))

    def __repr__(self) -> str:
        kind = "the printed geomatrix (9)" if self.printed else "rows first, then across"
        sizes = "×".join(str(r.shape[0]) for r in self._rows[:1]) if self.regular else "ragged"
        return (f"<geomkit.PointSurface in R^{self.dim}, {len(self._rows)} rows"
                f"{' of ' + sizes if self.regular else ' (ragged)'} points, {kind}>")

    @property
    def printed(self) -> bool:
        """Whether this is the paper's geomatrix (9) as printed."""
        return self._specs is None

    @property
    def regular(self) -> bool:
        """Whether every row has the same number of points."""
        return len({r.shape[0] for r in self._rows}) == 1

    @property
    def net(self) -> list[F64]:
        """The source points: one (m_i, dim) array per row."""
        return [r.copy() for r in self._rows]

    @property
    def dim(self) -> int:
        """Coordinates per point."""
        return self._core.dim

    @property
    def domain(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((u0, u1), (v0, v1)): along the rows, across them."""
        return self._core.domain

    @property
    def warnings(self) -> tuple[str, ...]:
        """Warnings of the construction (large Lebesgue constants)."""
        return tuple(self._core.warnings)

    def __call__(self, u: ArrayLike, v: ArrayLike) -> F64:
        """The points M(u, v) at broadcast u and v.

        Parameters
        ----------
        u, v : array_like
            Parameters along and across the rows (broadcast together).

        Returns
        -------
        ndarray, shape ``broadcast(u, v).shape + (dim,)``

        Raises
        ------
        ValueError
            For NaN or infinite parameters, a point beyond float64.

        Examples
        --------
        >>> from geomkit import point_surface
        >>> point_surface([[0.0, 1.0], [2.0, 3.0]])([0.0, 0.5], 0.5)[:, 0].tolist()
        [1.0, 1.5]
        """
        uu, vv = np.broadcast_arrays(real_array(u, "u"), real_array(v, "v"))
        shape = uu.shape
        out = np.empty((uu.size, self.dim))
        us, vs, core = aligned(uu).reshape(-1), aligned(vv).reshape(-1), self._core
        chunked(us.shape[0], lambda a, b: core.eval_into(us[a:b], vs[a:b], out[a:b]),
                "PointSurface")
        return out.reshape(shape + (self.dim,))

    def grid(self, u: ArrayLike, v: ArrayLike) -> F64:
        """The points on the grid u × v.

        Parameters
        ----------
        u, v : array_like, 1-D
            Parameters along and across the rows.

        Returns
        -------
        ndarray, shape (len(u), len(v), dim)

        Raises
        ------
        ValueError
            For NaN or infinite parameters, a point beyond float64.

        Examples
        --------
        >>> import numpy as np
        >>> from geomkit import point_surface
        >>> s = point_surface(np.arange(9.0).reshape(3, 3))
        >>> s.grid([0.0, 1.0], [0.0, 0.5, 1.0])[..., 0].tolist()
        [[0.0, 3.0, 6.0], [2.0, 5.0, 8.0]]
        """
        uu = contiguous(u, "u").reshape(-1)
        vv = contiguous(v, "v").reshape(-1)
        out = np.empty(uu.size * vv.size * self.dim)
        row, core = vv.size * self.dim, self._core
        chunked(uu.size, lambda a, b: core.eval_grid_into(uu[a:b], vv, out[a * row:b * row]),
                "PointSurface", per=vv.size)
        return out.reshape(uu.size, vv.size, self.dim)

    def shares(self, u: float, v: float) -> list[F64]:
        """The geomatrix: the share a_ij(u, v) of every source point in M(u, v) (spec §3).

        Parameters
        ----------
        u, v : float
            One point of the parameter plane.

        Returns
        -------
        list of ndarray
            One array per row, ``shares[i][j]`` for point j of row i; they sum to 1 (not
            for the printed geomatrix).

        Raises
        ------
        ValueError
            For NaN or infinite parameters.

        Examples
        --------
        >>> import numpy as np
        >>> from geomkit import point_surface
        >>> a = point_surface(np.ones((3, 3)), printed=True).shares(0.5, 0.5)
        >>> round(float(a[0][0]), 15), float(sum(r.sum() for r in a))
        (0.0625, 1.15625)
        """
        rows = self._core.shares(real_scalar(u, "u"), real_scalar(v, "v"))
        return [np.array(r) for r in rows]

    def formula(self, fmt: str = "numpy") -> str:
        """The surface as one formula per coordinate in (u, v):
        M(u, v) = sum_i L_i(v) M_i(u), every row's point equation written out.

        Parameters
        ----------
        fmt : str, optional
            The syntax, as for `PointModel.formula` (default 'numpy'); definitions x, y, z.

        Returns
        -------
        str

        Raises
        ------
        ValueError
            For an unknown syntax, the printed geomatrix (no formula), a coefficient
            beyond float64.

        Examples
        --------
        >>> from geomkit import point_surface
        >>> print(point_surface([[0.0, 1.0], [2.0, 3.0]]).formula("sympy"), end="")
        from sympy import *
        u, v = symbols("u v")
        x = u*(-v + 1) + v*(u + 2.0)
        """
        return self._core.formula(_format(fmt))


def _rebuild_surface(rows: list[F64], specs: list[_Spec] | None, across: _Spec | None,
                     limit: float | None, samples: int) -> PointSurface:
    s = PointSurface.__new__(PointSurface)
    s._init(rows, specs, across, False, limit, samples)
    return s


def point_surface(net: Any, nodes: NodeSpec | None = None, *,
                  row_nodes: Sequence[NodeSpec] | None = None, across: NodeSpec | None = None,
                  printed: bool = False, strict: bool = False,
                  lebesgue_limit: float | None = None, samples: int = 21) -> PointSurface:
    """The point-equation surface through a net of source points
    (``geomkit pointcalc surface``).

    Parameters
    ----------
    net, nodes, row_nodes, across, printed, strict, lebesgue_limit, samples
        As for `PointSurface`.

    Returns
    -------
    PointSurface

    Raises
    ------
    ValueError
        As `PointSurface`.

    Examples
    --------
    >>> from geomkit import point_surface
    >>> net = [[[0.0], [1.0], [0.0]], [[1.0], [2.0], [1.0]], [[0.0], [1.0], [0.0]]]
    >>> s = point_surface(net, row_nodes=["third", "half", "two-thirds"])
    >>> s(1 / 3, 0.0).tolist()
    [1.0]
    """
    return PointSurface(net, nodes, row_nodes=row_nodes, across=across, printed=printed,
                        strict=strict, lebesgue_limit=lebesgue_limit, samples=samples)


# --------------------------------------------------------------------------------------------
# sample files


class _Samples(Drawable):
    def __init__(self, model: _geomkit.Model) -> None:
        if not isinstance(model, _geomkit.Model):
            raise TypeError(f"{type(self).__name__} is read with geomkit.load / loads")
        self._inner = model
        self._file: dict[str, Any] = json.loads(model.to_json())

    def _model(self) -> _geomkit.Model:
        return self._inner

    def __reduce__(self) -> tuple[Any, ...]:
        return (_samples_from_json, (self.to_json(),))

    def __repr__(self) -> str:
        return f"<geomkit.{type(self).__name__}: {self.describe()}>"


class PointCurveSamples(_Samples):
    """The samples of a point-equation curve: the file ``geomkit pointcalc curve -o X.json``
    writes (and `PointCurve.save`), as `geomkit.load` reads it.

    Parameters
    ----------
    model : geomkit._geomkit.Model
        The compiled model of a ``"pointcalc-curve"`` file.

    Examples
    --------
    >>> import geomkit
    >>> s = geomkit.loads(geomkit.point_curve([0.0, 1.0, 0.0], samples=5).to_json())
    >>> s.t.tolist(), s.points[:, 0].tolist()
    ([0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.75, 1.0, 0.75, 0.0])
    """

    @property
    def t(self) -> F64:
        """The parameters of the samples, increasing."""
        return np.array([r[0] for r in self._file["samples"]], dtype=np.float64)

    @property
    def points(self) -> F64:
        """The sampled points, shape (len(t), dim)."""
        return np.array([r[1:] for r in self._file["samples"]], dtype=np.float64)

    @property
    def nodes(self) -> F64 | None:
        """The nodes of the equation, if the file has them."""
        n = self._file.get("nodes")
        return None if n is None else np.array(n, dtype=np.float64)

    @property
    def lebesgue_constant(self) -> float | None:
        """The Lebesgue constant of the nodes, if the file has it."""
        x = self._file.get("lebesgue")
        return None if x is None else float(x)


class PointSurfaceSamples(_Samples):
    """The samples of a point-equation surface: the file ``geomkit pointcalc surface -o
    X.json`` writes (and `PointSurface.save`), as `geomkit.load` reads it.

    Parameters
    ----------
    model : geomkit._geomkit.Model
        The compiled model of a ``"pointcalc-surface-samples"`` file.

    Examples
    --------
    >>> import numpy as np, geomkit
    >>> s = geomkit.loads(geomkit.point_surface(np.eye(3), samples=3).to_json())
    >>> s.points.shape
    (3, 3, 1)
    """

    @property
    def u(self) -> F64:
        """The u of the grid (along the rows)."""
        return np.array(self._file["u"], dtype=np.float64)

    @property
    def v(self) -> F64:
        """The v of the grid (across the rows)."""
        return np.array(self._file["v"], dtype=np.float64)

    @property
    def points(self) -> F64:
        """The points, shape (len(u), len(v), dim)."""
        pts = np.array(self._file["points"], dtype=np.float64)
        return pts.reshape(len(self._file["u"]), len(self._file["v"]), -1)


def _samples_from_json(text: str) -> Any:
    from ._model import loads

    return loads(text)


register_kind("pointcalc-model", PointModel._from_model)
register_kind("pointcalc-curve", PointCurveSamples)
register_kind("pointcalc-surface-samples", PointSurfaceSamples)
