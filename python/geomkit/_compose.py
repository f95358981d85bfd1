"""Single analytic formulas of composite curves and surfaces (method 3,
spec/composite-surfaces.md; P.G. Dolya, 2005): closed bodies and piecewise-ruled surfaces
(formula (2)), composite surfaces of patches (formulas (3)-(11)), piecewise functions and
composite curves (section 5), built from the ramp P(t, a, w) = (w + |t - a| - |t - a - w|)/(2w)
of formula (1).

Each object prints its one formula in the eleven syntaxes of geomkit's expression engine
(`formula`), gives it to SymPy (`to_sympy`), evaluates it compiled over NumPy arrays with the
GIL released (`evaluator`: the answer to ``sympy.lambdify``), reports its continuity, and is
a model file of the CLI (`save`, `geomkit.load`, pickling).
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Mapping, Sequence
from typing import Any, Literal, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import aligned, contiguous, index, real_array
from ._model import Drawable, Model, _write_atomic, register_kind
from ._progress import chunked

__all__ = [
    "Body",
    "CompositeSurface",
    "ContinuityReport",
    "Evaluator",
    "Jump",
    "Piecewise",
    "RuledReport",
    "RuledSurface",
    "body",
]

#: The syntaxes of `formula`, in geomkit-expr's order.
FORMATS: tuple[str, ...] = tuple(_geomkit.formula_formats())

_Method = Literal["tape", "cells"]
_C = TypeVar("_C", bound="_Composite")


@dataclasses.dataclass(frozen=True)
class Jump:
    """The largest jump between two neighbouring patches (or pieces) along a shared edge.

    Attributes
    ----------
    line : {'u', 'v'}
        The direction of the grid line: ``'u'`` for u = u_index (x = x_index of an explicit
        surface, the breakpoint x_index of a piecewise formula), ``'v'`` for v = v_index.
    index : int
        The index of the grid line (the knot).
    cell : int
        The cell along the line (j for a u-line, i for a v-line; 0 for a piecewise formula).
    max_jump : float
        The largest Euclidean distance between the two patches on the edge (sampled).
    at : float
        The parameter along the line where it occurs (the breakpoint for a piecewise formula).
    """

    line: str
    index: int
    cell: int
    max_jump: float
    at: float


@dataclasses.dataclass(frozen=True)
class ContinuityReport:
    """The continuity conditions of spec/composite-surfaces.md section 3 (r_ij(u_(i+1), v) =
    r_(i+1)j(u_(i+1), v), ...) checked on every shared edge, or at every breakpoint.

    Attributes
    ----------
    max_jump : float
        The largest jump (0 for a single patch).
    tolerance : float
        Jumps up to this are rounding (64 epsilon times the largest coordinate sampled).
    continuous : bool
        Whether every jump is within the tolerance (the formula then reproduces every patch;
        otherwise it matches the first patch and shifts the others to stay attached).
    statement : str
        A sentence for users, as the CLI prints it.
    jumps : tuple of Jump
        One entry per shared edge (u-lines first) or breakpoint.
    """

    max_jump: float
    tolerance: float
    continuous: bool
    statement: str
    jumps: tuple[Jump, ...]


@dataclasses.dataclass(frozen=True)
class RuledReport:
    """The consistency checks of a piecewise-ruled surface (formula (2)), as the CLI's
    ``compose ruled`` prints them.

    Attributes
    ----------
    v : tuple of float
        The values v_k of the curves.
    open_curves : tuple of (int, float)
        The curves whose ends do not meet (index, distance between the ends).
    ends_are_points : bool
        Whether the first and the last curve are points.
    closed_body : bool
        Every curve closed and both ends points: the surface bounds a body.
    max_difference : float
        The largest difference between the compiled formula (2) and the structural evaluator
        on the sampled points of the domain.
    samples : int
        Points per direction of that comparison.
    """

    v: tuple[float, ...]
    open_curves: tuple[tuple[int, float], ...]
    ends_are_points: bool
    closed_body: bool
    max_difference: float
    samples: int


class Evaluator:
    """The compiled evaluator of a single formula: ``f(u, v)`` (``f(t)``, ``f(x)``) over NumPy
    arrays with NumPy broadcasting, the GIL released — the answer to ``sympy.lambdify``.

    Made by `CompositeSurface.evaluator` and its siblings. ``method='tape'`` evaluates the
    single formula itself, compiled by geomkit-expr (``Tape::eval_batch``), on blocks of
    points in parallel; ``method='cells'`` the structural evaluator (the cell or piece of each
    point, O(1) per point), equal to the formula within rounding.

    Parameters
    ----------
    *args : array_like
        One array per variable (`variables`), broadcast together.

    Returns
    -------
    tuple of ndarray, or ndarray
        One float64 array of the broadcast shape per coordinate (`coordinates`); a function
        (one coordinate) returns its array alone.

    Raises
    ------
    TypeError
        For a wrong number of arguments, complex or non-numeric values.
    ValueError
        For NaN or infinite values with ``method='cells'`` (the tape follows f64 and returns
        NaN there), and for shapes that do not broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> import geomkit
    >>> f = geomkit.body("cube").evaluator()
    >>> x, y, z = f(np.array([0.5, 1.5]), 1.5)
    >>> x.tolist(), y.tolist(), z.tolist()
    ([0.0, -1.0], [1.0, 0.0], [0.0, 0.0])
    """

    def __init__(self, inner: _geomkit.Composite, method: _Method, threads: int,
                 owner: Any = None) -> None:
        self._inner = inner
        self._owner = owner
        self._method = method
        self._threads = threads
        self._variables = tuple(inner.variables)
        self._dim = inner.dim

    @property
    def variables(self) -> tuple[str, ...]:
        """The names of the arguments, in order."""
        return self._variables

    def __call__(self, *args: ArrayLike) -> Any:
        if len(args) != len(self._variables):
            raise TypeError(
                f"the formula takes {len(self._variables)} arguments "
                f"({', '.join(self._variables)}), got {len(args)}"
            )
        arrays = [real_array(a, name) for a, name in zip(args, self._variables)]
        try:
            shape = np.broadcast_shapes(*(a.shape for a in arrays))
        except ValueError as e:
            raise ValueError(f"the arguments do not broadcast together: {e}") from None
        flat = [
            aligned(np.broadcast_to(a, shape)).reshape(-1) for a in arrays
        ]
        n = flat[0].size
        out = np.empty((self._dim, n), dtype=np.float64)
        run = self._inner.eval_into if self._method == "tape" else self._inner.eval_cells_into

        def step(a: int, b: int) -> None:
            if (a, b) == (0, n):
                run(flat, out, self._threads)
                return
            part = np.empty((self._dim, b - a))
            run([x[a:b] for x in flat], part, self._threads)
            out[:, a:b] = part

        chunked(n, step, "Evaluator")
        results = tuple(out[k].reshape(shape) for k in range(self._dim))
        return results[0] if self._dim == 1 else results

    def __reduce__(self) -> tuple[Any, ...]:
        # Pickled as the formula it evaluates (the compiled tape is rebuilt on unpickling).
        return (_evaluator, (self._owner, self._method, self._threads or None))

    def __repr__(self) -> str:
        return f"<geomkit.Evaluator f({', '.join(self._variables)}), method={self._method!r}>"


def _float_literals(tokens: list[Any], local_dict: Any, global_dict: Any) -> list[Any]:
    """A SymPy parser transformation: decimal literals as the exact f64 they denote
    (``Float('0.1', precision=53)``), not SymPy's decimal reading of the text."""
    from tokenize import NAME, NUMBER, OP, STRING

    out: list[Any] = []
    for toknum, tokval in tokens:
        if toknum == NUMBER and any(c in tokval for c in ".eE") and not tokval.startswith("0x"):
            out += [(NAME, "Float"), (OP, "("), (STRING, repr(tokval)), (OP, ","),
                    (NAME, "precision"), (OP, "="), (NUMBER, "53"), (OP, ")")]
        else:
            out.append((toknum, tokval))
    return out


class _Composite(Drawable):
    """What every single formula of method 3 can do (the base of the public classes)."""

    #: The syntaxes of `formula`, in geomkit-expr's order.
    FORMATS: tuple[str, ...] = FORMATS

    _inner: _geomkit.Composite

    @classmethod
    def _wrap(cls: type[_C], inner: _geomkit.Composite) -> _C:
        obj = cls.__new__(cls)
        obj._inner = inner
        return obj

    # -- what it is ---------------------------------------------------------------------
    @property
    def variables(self) -> tuple[str, ...]:
        """The variables of the formula, in order: ('u', 'v'), ('x', 'y'), ('t',), ('x',)."""
        return tuple(self._inner.variables)

    @property
    def coordinates(self) -> tuple[str, ...]:
        """The coordinates of the formula: ('x', 'y', 'z'), ('z',), ('f',), ..."""
        return tuple(self._inner.coordinates)

    @property
    def dim(self) -> int:
        """The number of coordinates."""
        return self._inner.dim

    @property
    def op_count(self) -> int:
        """Operations of the formula's DAG after sharing (the cost of one evaluation)."""
        return self._inner.op_count

    @property
    def domain(self) -> tuple[tuple[float, float], ...]:
        """The parameter domain: ((u0, u1), (v0, v1)) of a surface, ((x0, xn),) of a
        piecewise formula. Outside it the formula holds the boundary values (P clamps)."""
        return tuple((a, b) for a, b in self._inner.domain)

    # -- the formula ----------------------------------------------------------------------
    def formula(self, fmt: str = "sympy", program: bool = False) -> str:
        """The single formula as text in the syntax `fmt`, as the CLI's ``--format`` prints it.

        Parameters
        ----------
        fmt : str, optional
            One of `FORMATS` ('maple', 'mathematica', 'sympy', 'numpy', 'matlab', 'latex',
            'c', 'rust', 'glsl', 'js', 'desmos'; aliases 'octave', 'python', 'javascript',
            'wolfram', 'tex'). Default 'sympy'.
        program : bool, optional
            Print common subexpressions once, in temporaries t0, t1, ... (the CLI's
            ``--program``). Default False: one inline definition per coordinate.

        Returns
        -------
        str
            The text, with the lines the target needs first (SymPy's import and symbols,
            NumPy's import, C's ``#include <math.h>``).

        Raises
        ------
        ValueError
            For an unknown format (the message lists them), a constant the target cannot
            hold or a text longer than 256 MiB.
        TypeError
            If `fmt` is not a string.

        Examples
        --------
        >>> import geomkit
        >>> print(geomkit.body("cube").formula("sympy").splitlines()[-1])
        z = -Abs(v - 1) + Abs(v - 2)
        """
        if not isinstance(fmt, str):
            raise TypeError(f"fmt must be a format name (str), got {type(fmt).__name__}")
        return self._inner.print(fmt, bool(program))

    def formulas(self, program: bool = False) -> dict[str, str]:
        """The formula in every syntax of `FORMATS` (the ``formulas`` of the CLI's formula
        file).

        Parameters
        ----------
        program : bool, optional
            As in `formula`.

        Returns
        -------
        dict of str to str
            ``{format name: text}``.

        Examples
        --------
        >>> import geomkit
        >>> sorted(geomkit.body("cube").formulas())[:3]
        ['c', 'desmos', 'glsl']
        """
        return {f: self.formula(f, program) for f in FORMATS}

    def to_sympy(self) -> tuple[Any, ...]:
        """The formula as SymPy expressions, one per coordinate, parsed from the 'sympy'
        print (rationals exact, decimal constants as the exact f64 they denote).

        SymPy is imported only here. The symbols are ``sympy.Symbol(name)`` for the names of
        `variables`.

        Returns
        -------
        tuple of sympy.Expr
            One expression per coordinate (`coordinates`).

        Raises
        ------
        ImportError
            If SymPy is not installed.

        Examples
        --------
        >>> import geomkit
        >>> x, y, z = geomkit.body("cube").to_sympy()
        >>> z
        Abs(v - 2) - Abs(v - 1)
        """
        try:
            import sympy  # type: ignore[import-untyped, import-not-found, unused-ignore]
            from sympy.parsing.sympy_parser import (  # type: ignore[import-untyped, import-not-found, unused-ignore]
                parse_expr,
                standard_transformations,
            )
        except ImportError as e:
            raise ImportError(
                "to_sympy() needs SymPy, which is not installed: pip install sympy"
            ) from e
        names = self.coordinates
        local = {v: sympy.Symbol(v) for v in self.variables}
        namespace: dict[str, Any] = {}
        exec("from sympy import *", namespace)
        transformations = (_float_literals, *standard_transformations)
        exprs: dict[str, Any] = {}
        for line in self.formula("sympy").splitlines():
            name, sep, rhs = line.partition(" = ")
            if sep and name in names and name not in exprs:
                exprs[name] = parse_expr(rhs, local_dict=dict(local), global_dict=namespace,
                                         transformations=transformations)
        return tuple(exprs[n] for n in names)

    def evaluator(self, method: _Method = "tape", threads: int | None = None) -> Evaluator:
        """The compiled evaluator of the single formula over NumPy arrays (`Evaluator`).

        Parameters
        ----------
        method : {'tape', 'cells'}, optional
            'tape' (default): the single formula, compiled by geomkit-expr (the same formula
            `formula` prints); 'cells': the structural evaluator (each point's cell or piece,
            O(1) per point), equal to the formula within rounding.
        threads : int, optional
            Parts to evaluate in parallel, on a pool of one thread per core (default: one
            part per core; 1: on the calling thread).

        Returns
        -------
        Evaluator
            ``f(*variables)`` returning one array per coordinate.

        Raises
        ------
        ValueError
            For an unknown method, threads < 1, or a formula the engine refuses.

        Examples
        --------
        >>> import numpy as np
        >>> import geomkit
        >>> f = geomkit.body("cube").evaluator()
        >>> [float(c) for c in f(0.0, 1.0)]
        [1.0, 1.0, 1.0]
        """
        if method not in ("tape", "cells"):
            raise ValueError(f"method={method!r}: expected 'tape' or 'cells'")
        n = 0 if threads is None else index(threads, "threads")
        if threads is not None and n < 1:
            raise ValueError(f"threads={n}: expected at least 1")
        if method == "tape":
            self._inner.op_count  # builds the formula now: its errors here, not at the call
        return Evaluator(self._inner, method, n, self)

    def lambdify(self, threads: int | None = None) -> Evaluator:
        """``evaluator(method='tape')``: the compiled single formula, named after SymPy's
        ``lambdify``, which it replaces.

        Parameters
        ----------
        threads : int, optional
            Parts to evaluate in parallel, on a pool of one thread per core (default: one
            part per core; 1: on the calling thread).

        Returns
        -------
        Evaluator

        Examples
        --------
        >>> import geomkit
        >>> geomkit.body("cube").lambdify()(4.0, 2.0)[2].item()
        -1.0
        """
        return self.evaluator("tape", threads)

    # -- model files ----------------------------------------------------------------------
    def _model(self) -> _geomkit.Model:
        return self._inner.model()

    def formula_file(self, what: str | None = None) -> str:
        """The formula file the CLI writes with ``-o OUT.json`` (``geomkit compose ... -o
        f.json``): the formula in every syntax, its size, the continuity report and the
        model it was made from, which ``geomkit eval``, ``mesh`` and ``render`` read back.

        Parameters
        ----------
        what : str, optional
            What the formula describes (default: `describe`, or the ``what`` of the formula
            file this object was read from).

        Returns
        -------
        str
            The JSON text, in the CLI's layout.

        Raises
        ------
        ValueError
            If a formula cannot be printed in every syntax, or a number is not finite.

        Examples
        --------
        >>> import json
        >>> import geomkit
        >>> f = json.loads(geomkit.body("cube").formula_file())
        >>> f["type"], f["variables"], f["op_count"], f["model"]["type"]
        ('formula', ['u', 'v'], 32, 'ruled')
        """
        model = json.loads(self._inner.model().to_json())
        described = self.describe()
        if model.get("type") == "formula":  # made from a formula file: its what and model
            described = model.get("what", described)
            model = model.get("model")
        file: dict[str, Any] = {
            "type": "formula",
            "what": described if what is None else str(what),
            "variables": list(self.variables),
            "coordinates": list(self.coordinates),
            "op_count": self.op_count,
            "formulas": self.formulas(),
        }
        report = self._inner.continuity()
        if report is not None:
            max_jump, tolerance, continuous, statement, jumps = report
            piecewise = len(self.variables) == 1
            file["continuity"] = {
                "max_jump": max_jump, "tolerance": tolerance, "continuous": continuous,
                "statement": statement,
                "jumps": [{"at": at, "max_jump": jump} if piecewise else
                          {"line": line, "index": i, "cell": cell, "max_jump": jump, "at": at}
                          for line, i, cell, jump, at in jumps],
            }
        if model is not None:
            file["model"] = model
        return _geomkit.parse_model(json.dumps(file, allow_nan=False)).to_json()

    def save_formula(self, path: str | os.PathLike[str], what: str | None = None) -> None:
        """Writes `formula_file` to `path` (atomically), as ``geomkit compose ... -o
        path.json`` does; `geomkit.load` reads it back into this class.

        Parameters
        ----------
        path : str or os.PathLike
            The file.
        what : str, optional
            What the formula describes (default: `describe`).

        Raises
        ------
        ValueError
            As `formula_file`.
        OSError
            If the file cannot be written.

        Examples
        --------
        >>> import os, tempfile
        >>> import geomkit
        >>> path = os.path.join(tempfile.mkdtemp(), "cube.json")
        >>> geomkit.body("cube").save_formula(path)
        >>> geomkit.load(path).formula("maple") == geomkit.body("cube").formula("maple")
        True
        """
        _write_atomic(os.fspath(path), self.formula_file(what).encode("utf-8"))

    def __reduce__(self) -> tuple[Any, ...]:
        return (_from_json, (self.to_json(),))

    def __repr__(self) -> str:
        return f"<geomkit.{type(self).__name__}: {self.describe()}>"


class CompositeSurface(_Composite):
    """A composite surface of patches over an orthogonal grid as one formula (formulas
    (3)-(9) of spec/composite-surfaces.md; (10)-(11) for an explicit surface z(x, y)):

    .. math:: R(u, v) = R_{00} + \\sum_i (R_{i0} - R_{i0}(u_i, v)) + \\sum_j (R_{0j} -
              R_{0j}(u, v_j)) + \\sum_{i,j \\ge 1} (R_{ij} - R_{ij}(u_i, v) - R_{ij}(u, v_j)
              + R_{ij}(u_i, v_j))

    with each patch R_ij clamped to its cell by the ramp of formula (1).

    Parameters
    ----------
    scene : dict or str
        A scene as the CLI's ``geomkit compose patches`` reads it (a dict, or its JSON
        text): ``{"type": "composite_surface", "u_knots": [...], "v_knots": [...],
        "patches": [[P, ...], ...]}`` with ``P = {"bezier": net}`` or formulas ``{"x": "..",
        "y": "..", "z": "..", "domain": [[u0, u1], [v0, v1]]}``; ``{"type":
        "composite_explicit", "x_knots": ..., "y_knots": ..., "patches": ...}``; a saved
        ``"bspline_surface"``; or a formula file of one of them.

    Raises
    ------
    ValueError
        For a scene that is not one (the message names the JSON path at fault), a formula
        that does not parse, NaN or infinite numbers.
    TypeError
        If `scene` is neither a dict nor a str.

    Examples
    --------
    >>> import geomkit
    >>> s = geomkit.CompositeSurface({
    ...     "type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
    ...     "patches": [["x*y"], ["y + (x - 1)^2*y"]]})
    >>> s.continuity().continuous
    True
    >>> float(s.evaluator()(1.5, 1.0))
    1.25
    """

    def __init__(self, scene: Mapping[str, Any] | str) -> None:
        inner = _inner_of(scene, "scene")
        if inner.kind not in ("surface", "explicit"):
            raise ValueError(
                f"this scene makes a {inner.kind} formula: "
                "CompositeSurface takes a \"composite_surface\", \"composite_explicit\" or "
                "\"bspline_surface\" scene"
            )
        self._inner = inner

    @classmethod
    def from_bezier(
        cls, u_knots: ArrayLike, v_knots: ArrayLike, nets: ArrayLike
    ) -> CompositeSurface:
        """A composite surface of Bézier patches, each on [0, 1]^2 mapped onto its cell.

        Parameters
        ----------
        u_knots : array_like, shape (n + 1,)
            Grid lines in u, strictly increasing.
        v_knots : array_like, shape (m + 1,)
            Grid lines in v, strictly increasing.
        nets : array_like, shape (n, m, p + 1, q + 1, dim)
            ``nets[i, j]``: the control net of the Bézier patch on the cell [u_i, u_(i+1)]
            x [v_j, v_(j+1)]. ``dim = 1`` gives an explicit surface z(x, y).

        Returns
        -------
        CompositeSurface

        Raises
        ------
        ValueError
            For shapes that do not match, knots not increasing, NaN or infinite numbers.

        Examples
        --------
        >>> import numpy as np
        >>> import geomkit
        >>> net = np.zeros((1, 1, 2, 2, 3))
        >>> net[0, 0] = [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]
        >>> s = geomkit.CompositeSurface.from_bezier([0, 1], [0, 1], net)
        >>> [float(c) for c in s.evaluator()(0.5, 0.5)]
        [0.5, 0.5, 0.25]
        """
        uk = _vector(u_knots, "u_knots")
        vk = _vector(v_knots, "v_knots")
        a = contiguous(nets, "nets")
        if a.ndim != 5:
            raise ValueError(
                f"nets must have shape (n, m, p + 1, q + 1, dim), got shape {a.shape}"
            )
        n, m = a.shape[:2]
        if (n, m) != (uk.size - 1, vk.size - 1):
            raise ValueError(
                f"nets has {n} x {m} patches, the knots make "
                f"{uk.size - 1} x {vk.size - 1} cells"
            )
        if min(a.shape[2:]) == 0:
            raise ValueError(f"nets has an empty net: shape {a.shape}")
        patches = [[{"bezier": a[i, j].tolist()} for j in range(m)] for i in range(n)]
        if a.shape[4] == 1:
            scene: dict[str, Any] = {"type": "composite_explicit", "x_knots": uk.tolist(),
                                     "y_knots": vk.tolist(), "patches": patches}
        else:
            scene = {"type": "composite_surface", "u_knots": uk.tolist(),
                     "v_knots": vk.tolist(), "patches": patches}
        return cls(scene)

    @classmethod
    def from_bspline(
        cls,
        knots_u: ArrayLike,
        knots_v: ArrayLike,
        net: ArrayLike,
        degree: tuple[int, int] = (3, 3),
    ) -> CompositeSurface:
        """The composite surface of a B-spline surface's cells: one polynomial patch per
        non-empty knot span pair (the CLI's ``compose patches`` of a saved
        ``"bspline_surface"``). The single formula equals the B-spline surface on its domain.

        Parameters
        ----------
        knots_u, knots_v : array_like
            The knot vectors (``len(knots_u) = rows + p + 1``).
        net : array_like, shape (rows, cols, dim)
            Control points; ``dim = 1`` (heights) gives an explicit surface z(x, y).
        degree : (int, int), optional
            Degrees (p, q), each 1 to 7. Default (3, 3).

        Returns
        -------
        CompositeSurface

        Raises
        ------
        ValueError
            For knots and net that do not make a B-spline surface (the library's message).

        Examples
        --------
        >>> import numpy as np
        >>> import geomkit
        >>> k = [0, 0, 1, 1]
        >>> net = np.array([[[0.0], [1.0]], [[1.0], [2.0]]])
        >>> s = geomkit.CompositeSurface.from_bspline(k, k, net, degree=(1, 1))
        >>> float(s.evaluator()(0.25, 0.5))
        0.75
        """
        ku = _vector(knots_u, "knots_u")
        kv = _vector(knots_v, "knots_v")
        a = contiguous(net, "net")
        if a.ndim != 3:
            raise ValueError(f"net must have shape (rows, cols, dim), got shape {a.shape}")
        p, q = (index(d, "degree") for d in degree)
        return cls({"type": "bspline_surface", "degree": [p, q], "knots_u": ku.tolist(),
                    "knots_v": kv.tolist(), "net": a.tolist()})

    @classmethod
    def from_spline(cls, spline: Any) -> CompositeSurface:
        """The explicit composite surface z(x, y) of a fitted spline of heights: one
        polynomial patch per knot cell (see `from_bspline`).

        Parameters
        ----------
        spline : geomkit.RectBivariateSpline or scipy.interpolate.RectBivariateSpline
            Any object with ``get_knots()``, ``get_coeffs()`` and ``degrees`` (FITPACK's tck),
            degrees 1 to 7.

        Returns
        -------
        CompositeSurface

        Raises
        ------
        TypeError
            For an object without those.
        ValueError
            For knots and coefficients that do not make a spline surface.

        Examples
        --------
        >>> import numpy as np
        >>> import geomkit
        >>> x = np.linspace(0.0, 1.0, 5)
        >>> spl = geomkit.RectBivariateSpline(x, x, np.add.outer(x, x**2))
        >>> s = geomkit.CompositeSurface.from_spline(spl)
        >>> round(float(s.evaluator()(0.5, 0.5)), 12)
        0.75
        """
        try:
            tx, ty = spline.get_knots()
            c = spline.get_coeffs()
            kx, ky = spline.degrees
        except (AttributeError, TypeError, ValueError):
            raise TypeError(
                "expected a spline surface with get_knots(), get_coeffs() and degrees, got "
                f"{type(spline).__name__}"
            ) from None
        tx, ty = _vector(tx, "knots"), _vector(ty, "knots")
        rows, cols = tx.size - index(kx, "degree") - 1, ty.size - index(ky, "degree") - 1
        cc = real_array(c, "coefficients").reshape(-1)
        if rows < 1 or cols < 1 or cc.size != rows * cols:
            raise ValueError(
                f"{cc.size} coefficients do not fit knots of sizes {tx.size}, {ty.size} and "
                f"degrees ({kx}, {ky})"
            )
        return cls.from_bspline(tx, ty, cc.reshape(rows, cols, 1), degree=(kx, ky))

    @property
    def kind(self) -> str:
        """'surface' (parametric, in u, v) or 'explicit' (z in x, y)."""
        return self._inner.kind

    @property
    def knots(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The grid lines (u_knots, v_knots) (x, y for an explicit surface)."""
        u, v = self._inner.knots
        return np.array(u), np.array(v)

    def continuity(self) -> ContinuityReport:
        """The continuity conditions of formula (9) checked on every shared edge.

        Returns
        -------
        ContinuityReport

        Examples
        --------
        >>> import geomkit
        >>> s = geomkit.CompositeSurface({"type": "composite_explicit", "x_knots": [0, 1, 2],
        ...     "y_knots": [0, 1], "patches": [["0"], ["1"]]})
        >>> r = s.continuity()
        >>> r.continuous, r.max_jump, r.jumps[0].line
        (False, 1.0, 'u')
        """
        return _report(self._inner)


class RuledSurface(_Composite):
    """A piecewise-ruled surface over curves r_0, ..., r_n at v_0 < ... < v_n as one
    formula (formula (2) of spec/composite-surfaces.md):

    .. math:: R(u, v) = r_0(u) + \\sum_{k=1}^{n} (r_k(u) - r_{k-1}(u)) P(v, v_{k-1},
              v_k - v_{k-1})

    Parameters
    ----------
    curves : sequence of dict
        The curves as the CLI's ``"ruled"`` file has them: ``{"point": [x, y, z]}``,
        ``{"polygon": [[x, y, z], ...]}``, ``{"polyline": [...]}``, ``{"circle": {"center":
        [x, y, z], "radius": r}}``, or formulas ``{"x": "..", "y": "..", "z": "..", "t": [t0,
        t1]}`` in t.
    v : array_like
        The value v_k of each curve, strictly increasing.
    u : (float, float), optional
        The parameter range every curve is mapped onto. Default (0, 1).

    Raises
    ------
    ValueError
        For curves or values that do not make a ruled surface (the JSON path at fault).
    TypeError
        For arguments of the wrong type.

    Examples
    --------
    >>> import geomkit
    >>> square = [[1, 1, 0], [-1, 1, 0], [-1, -1, 0], [1, -1, 0]]
    >>> s = geomkit.RuledSurface([{"point": [0, 0, 1]}, {"polygon": square}], [0, 1], u=(0, 4))
    >>> [float(c) for c in s.evaluator()(0.0, 1.0)]
    [1.0, 1.0, 0.0]
    """

    def __init__(
        self,
        curves: Sequence[Mapping[str, Any]],
        v: ArrayLike,
        u: tuple[float, float] = (0.0, 1.0),
    ) -> None:
        if isinstance(curves, (str, bytes)) or not isinstance(curves, Sequence):
            raise TypeError(f"curves must be a list of dicts, got {type(curves).__name__}")
        vv = _vector(v, "v")
        uu = _vector(u, "u")
        inner = _inner_of(
            {"type": "ruled", "u": uu.tolist(), "v": vv.tolist(), "curves": list(curves)},
            "curves",
        )
        self._inner = inner

    @property
    def v(self) -> NDArray[np.float64]:
        """The values v_k of the curves."""
        return np.array(self._inner.knots[0])

    def report(self, samples: int = 41) -> RuledReport:
        """The consistency checks of the ruled surface: which curves are closed, whether it
        bounds a body, and the compiled formula (2) against the structural evaluator.

        Parameters
        ----------
        samples : int, optional
            Points per direction of the comparison (2 to 2000). Default 41, as the CLI.

        Returns
        -------
        RuledReport

        Raises
        ------
        ValueError
            For `samples` out of range.

        Examples
        --------
        >>> import geomkit
        >>> r = geomkit.body("cube").report()
        >>> r.closed_body, r.v, r.max_difference < 1e-15
        (True, (0.0, 1.0, 2.0, 3.0), True)
        """
        n = index(samples, "samples")
        result = self._inner.ruled_report(n)
        assert result is not None
        v, open_curves, ends, worst = result
        return RuledReport(
            v=tuple(v),
            open_curves=tuple((k, g) for k, g in open_curves),
            ends_are_points=ends,
            closed_body=ends and not open_curves,
            max_difference=worst,
            samples=n,
        )


class Body(RuledSurface):
    """A closed body as one formula: a piecewise-ruled surface (formula (2)) over a point,
    one or two contours and a point — the CLI's ``geomkit compose body``.

    Parameters
    ----------
    name : str
        'cube' (the paper's, vertices (+-1, +-1, +-1)), 'box', 'pyramid', 'cone', 'cylinder'
        (with both caps), 'prism' or 'frustum'.
    size : (float, float, float), optional
        Box sizes (default (2, 2, 2)).
    height : float, optional
        Height (default 2).
    radius : float, optional
        Radius, or circumradius of a regular polygon (default 1).
    top_radius : float, optional
        Top radius of a frustum (default radius / 2).
    side : float, optional
        Base side of a square pyramid (default 2).
    ngon : int, optional
        A regular polygon of `ngon` vertices (3 to 10000) as the base of a prism or pyramid
        (a prism's default: 6).
    polygon : array_like, shape (k, 2), optional
        A simple polygon, star-shaped about its centroid, as the base of a prism or pyramid.

    Attributes
    ----------
    name : str
        The body.
    params : dict
        The options given.

    Raises
    ------
    ValueError
        For an unknown body, sizes not finite, > 0 and at most 1e100, a bad polygon.
    TypeError
        For an unknown option or a value of the wrong type.

    Examples
    --------
    >>> import geomkit
    >>> cube = geomkit.Body("cube")
    >>> print(cube.formula("maple").splitlines()[2])
    z := (u, v) -> -abs(v - 1) + abs(v - 2);
    """

    def __init__(self, name: str, **params: Any) -> None:
        if not isinstance(name, str):
            raise TypeError(f"name must be a str, got {type(name).__name__}")
        known = {"size", "height", "radius", "top_radius", "side", "ngon", "polygon"}
        unknown = sorted(set(params) - known)
        if unknown:
            raise TypeError(
                f"unknown option {unknown[0]!r} of a body: expected {', '.join(sorted(known))}"
            )
        args: dict[str, Any] = {}
        for key, value in params.items():
            if value is None:
                continue
            if key == "size":
                s = _vector(value, "size")
                if s.size != 3:
                    raise ValueError(f"size must hold 3 numbers (a, b, c), got {s.size}")
                args[key] = [float(x) for x in s]
            elif key == "ngon":
                args[key] = index(value, "ngon")
                if args[key] < 0:
                    raise ValueError(f"ngon = {args[key]}: expected 3 to 10000 vertices")
            elif key == "polygon":
                p = real_array(value, "polygon")
                if p.ndim != 2 or p.shape[1] != 2:
                    raise ValueError(f"polygon must have shape (k, 2), got shape {p.shape}")
                args[key] = [(float(a), float(b)) for a, b in p]
            else:
                args[key] = _scalar(value, key)
        self._inner = _geomkit.body(name, **args)
        self._name = name
        self._params = dict(params)

    @property
    def name(self) -> str:
        """The body ('cube', 'box', ...)."""
        return self._name

    @property
    def params(self) -> dict[str, Any]:
        """The options given (a copy)."""
        return dict(self._params)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_body, (self._name, self._params))

    def __repr__(self) -> str:
        opts = "".join(f", {k}={v!r}" for k, v in self._params.items())
        return f"geomkit.body({self._name!r}{opts})"


def body(name: str, **params: Any) -> Body:
    """A closed body as one formula (`Body`): the CLI's ``geomkit compose body``.

    Parameters
    ----------
    name : str
        'cube', 'box', 'pyramid', 'cone', 'cylinder', 'prism' or 'frustum'.
    **params
        The options of `Body` (size, height, radius, top_radius, side, ngon, polygon).

    Returns
    -------
    Body

    Raises
    ------
    ValueError
        For an unknown body or bad sizes.
    TypeError
        For an unknown option.

    Examples
    --------
    >>> import geomkit
    >>> cyl = geomkit.body("cylinder", radius=2.0, height=1.0)
    >>> round(float(cyl.evaluator()(0.0, 1.0)[0]), 12)
    2.0
    """
    return Body(name, **params)


class Piecewise(_Composite):
    """A piecewise function f(x) or composite curve r(t) as one continuous formula
    (spec/composite-surfaces.md section 5):

    .. math:: F(x) = F_0(x) + \\sum_{i=1}^{n-1} (F_i(x) - F_i(x_i)),\\quad
              F_i(x) = f_i(x_i + (x_{i+1} - x_i) P(x, x_i, x_{i+1} - x_i))

    Parameters
    ----------
    knots : array_like, shape (n + 1,)
        Breakpoints x_0 < ... < x_n.
    pieces : sequence
        One piece per interval: formulas in x (str) for a function, or dicts ``{"x": "..",
        "y": "..", "z": "..", "domain": [t0, t1]}`` in t for a curve (``z`` and ``domain``
        optional; the domain is mapped onto the knot interval).

    Raises
    ------
    ValueError
        For knots not strictly increasing, a count of pieces other than len(knots) - 1, a
        formula that does not parse or is not finite at the ends of its interval.
    TypeError
        For arguments of the wrong type.

    Examples
    --------
    >>> import geomkit
    >>> f = geomkit.Piecewise([-1, 0, 1, 2], ["-x", "x", "1"])
    >>> f.evaluator()([-0.5, 0.5, 3.0]).tolist()
    [0.5, 0.5, 1.0]
    """

    def __init__(self, knots: ArrayLike, pieces: Sequence[str | Mapping[str, Any]]) -> None:
        if isinstance(pieces, (str, bytes)) or not isinstance(pieces, Sequence):
            raise TypeError(f"pieces must be a list, got {type(pieces).__name__}")
        k = _vector(knots, "knots")
        self._inner = _inner_of(
            {"type": "piecewise", "knots": k.tolist(), "pieces": list(pieces)}, "pieces"
        )

    @classmethod
    def polyline(
        cls, points: ArrayLike, knots: ArrayLike | None = None, closed: bool = False
    ) -> Piecewise:
        """A polyline (a closed polygon with `closed`) as one piecewise-linear formula.

        Parameters
        ----------
        points : array_like, shape (k, dim)
            The vertices; one coordinate per point gives a function.
        knots : array_like, optional
            The parameter of each vertex (default 0, 1, 2, ...; a polygon has one more, for
            its closing edge).
        closed : bool, optional
            Close the polygon. Default False.

        Returns
        -------
        Piecewise

        Raises
        ------
        ValueError
            For too few points, knots not increasing or of the wrong count.

        Examples
        --------
        >>> import geomkit
        >>> sq = geomkit.Piecewise.polyline([[1, 1], [-1, 1], [-1, -1], [1, -1]], closed=True)
        >>> [float(c) for c in sq.evaluator()(4.0)]
        [1.0, 1.0]
        """
        p = real_array(points, "points")
        if p.ndim != 2:
            raise ValueError(f"points must have shape (k, dim), got shape {p.shape}")
        scene: dict[str, Any] = {"type": "polygon" if closed else "polyline",
                                 "points": p.tolist()}
        if knots is not None:
            scene["knots"] = _vector(knots, "knots").tolist()
        return cls._wrap(_inner_of(scene, "points"))

    @classmethod
    def from_bspline(cls, spline: Any) -> Piecewise:
        """A B-spline as one polynomial piece per knot span (the CLI's ``compose
        piecewise`` of a saved ``"bspline_curve"``).

        Parameters
        ----------
        spline : geomkit.BSpline or scipy.interpolate.BSpline
            Any object with SciPy's ``t``, ``c`` (shape (n,) for a function, (n, dim) for a
            curve) and ``k`` (1 to 7).

        Returns
        -------
        Piecewise

        Raises
        ------
        ValueError
            For knots and coefficients that do not make a B-spline.
        TypeError
            For an object without ``t``, ``c``, ``k``.

        Examples
        --------
        >>> import numpy as np
        >>> import geomkit
        >>> x = np.linspace(0.0, 1.0, 6)
        >>> s = geomkit.make_interp_spline(x, x**3)
        >>> f = geomkit.Piecewise.from_bspline(s)
        >>> round(float(f.evaluator()(0.5)), 12)
        0.125
        """
        try:
            t, c, k = spline.t, spline.c, spline.k
        except AttributeError:
            raise TypeError(
                f"expected a B-spline with t, c and k, got {type(spline).__name__}"
            ) from None
        tt = _vector(t, "t")
        kk = index(k, "k")
        cc = real_array(c, "c")
        n = tt.size - kk - 1
        if n < 1 or cc.ndim not in (1, 2) or cc.shape[0] < n:
            raise ValueError(
                f"c of shape {cc.shape} does not fit {tt.size} knots of degree {kk}"
            )
        rows = cc[:n].reshape(n, -1)
        return cls._wrap(_inner_of({"type": "bspline_curve", "degree": kk,
                                    "knots": tt.tolist(),
                                    "control_points": rows.tolist()}, "spline"))

    @property
    def kind(self) -> str:
        """'function' (f in x) or 'curve' (in t)."""
        return self._inner.kind

    @property
    def knots(self) -> NDArray[np.float64]:
        """The breakpoints."""
        return np.array(self._inner.knots[0])

    @property
    def warnings(self) -> tuple[str, ...]:
        """Pieces not finite somewhere inside their interval (the formula is not either)."""
        return tuple(self._inner.warnings())

    def continuity(self) -> ContinuityReport:
        """The jumps between neighbouring pieces at the breakpoints.

        Returns
        -------
        ContinuityReport

        Examples
        --------
        >>> import geomkit
        >>> r = geomkit.Piecewise([0, 1, 2], ["x", "x + 1"]).continuity()
        >>> r.continuous, r.max_jump, r.jumps[0].at
        (False, 1.0, 1.0)
        """
        return _report(self._inner)


# -- helpers ------------------------------------------------------------------------------
def _vector(a: ArrayLike, name: str) -> NDArray[np.float64]:
    """A 1-D float64 array of finite numbers."""
    v = real_array(a, name)
    if v.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {v.shape}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} holds NaN or infinite values")
    return v


def _scalar(value: Any, name: str) -> float:
    """A real number argument."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(
        value, (int, float, np.integer, np.floating)
    ):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__}")
    return float(value)


def _scene_text(scene: Mapping[str, Any] | str, name: str) -> str:
    """The JSON text of a scene given as a dict or text."""
    if isinstance(scene, str):
        return scene
    if not isinstance(scene, Mapping):
        raise TypeError(
            f"{name} must be a dict or its JSON text, got {type(scene).__name__}"
        )
    try:
        return json.dumps(scene, allow_nan=False)
    except ValueError as e:
        raise ValueError(f"{name}: NaN and infinity are not numbers of a model file ({e})") \
            from None
    except TypeError as e:
        raise TypeError(f"{name}: {e}") from None


def _inner_of(scene: Mapping[str, Any] | str, name: str) -> _geomkit.Composite:
    """The compiled formula of a scene (dict or JSON text) through its model file."""
    return _geomkit.composite_from_model(_geomkit.parse_model(_scene_text(scene, name)))


def _report(inner: _geomkit.Composite) -> ContinuityReport:
    r = inner.continuity()
    assert r is not None
    max_jump, tolerance, continuous, statement, jumps = r
    return ContinuityReport(max_jump, tolerance, continuous, statement,
                            tuple(Jump(*j) for j in jumps))


_CLASSES: dict[str, type[_Composite]] = {
    "surface": CompositeSurface,
    "explicit": CompositeSurface,
    "ruled": RuledSurface,
    "function": Piecewise,
    "curve": Piecewise,
}


def _wrap_inner(inner: _geomkit.Composite) -> Any:
    return _CLASSES[inner.kind]._wrap(inner)


def _from_model(model: _geomkit.Model) -> Any:
    """The loader of `geomkit.load` for the kinds of this module."""
    try:
        inner = _geomkit.composite_from_model(model)
    except ValueError:
        if model.kind == "formula":  # a formula file without its model
            return Model(model)
        raise
    return _wrap_inner(inner)


def _from_json(text: str) -> Any:
    """Unpickles a composite formula from its model file."""
    return _from_model(_geomkit.parse_model(text))


def _evaluator(owner: _Composite, method: _Method, threads: int | None) -> Evaluator:
    """Unpickles an evaluator."""
    return owner.evaluator(method, threads)


def _body(name: str, params: dict[str, Any]) -> Body:
    """Unpickles a body."""
    return Body(name, **params)


for _kind in ("composite_surface", "composite_explicit", "ruled", "piecewise", "polyline",
              "polygon", "formula"):
    register_kind(_kind, _from_model)
