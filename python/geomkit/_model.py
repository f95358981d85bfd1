"""Model files and the common behaviour of every model object of the package.

Every class of the package that describes geometry (Bézier curves and surfaces, B-splines,
composite formulas, point-calculus models, ...) derives from `Drawable` and implements
``_model()``, its `geomkit._geomkit.Model` (the model file of the CLI plus its geometry).
`Drawable` gives them ``describe``, ``to_json``, ``save``, meshes (``mesh``, ``write``) and
pictures (``render``, ``svg``, ``png`` and Jupyter's ``_repr_svg_`` / ``_repr_png_``), all
through the model crate and the library exactly as the CLI's ``geomkit mesh`` and ``geomkit
render`` make them. `load` / `loads` read a model file back into the class of its kind, as
registered with `register_kind`; a kind no class claims loads as a plain `Model`.

A surface's mesh is a `Mesh` (vertices, faces, normals, the mesher's `MeshReport`), a curve's
a `Polyline` (points and their parameters); both write OBJ, PLY and glTF binary (a `Mesh` STL
too) with the library's writers, atomically.
"""

from __future__ import annotations

import json
import math
import operator
import os
import re
import tempfile
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit
from ._arrays import contiguous
from ._progress import reporter

_LOADERS: dict[str, Callable[[_geomkit.Model], Any]] = {}


def register_kind(kind: str, factory: Callable[[_geomkit.Model], Any]) -> None:
    """Makes `load` return ``factory(model)`` for model files whose ``"type"`` is `kind`."""
    _LOADERS[kind] = factory


class Drawable:
    """What every model object can do; subclasses implement ``_model()``."""

    __slots__ = ()

    def _model(self) -> _geomkit.Model:
        raise NotImplementedError

    def describe(self) -> str:
        """What the model is, e.g. ``"Bézier curve of degree 5 in R^2 (6 control points)"``."""
        return self._model().describe()

    def to_json(self) -> str:
        """The model file (the format the CLI reads and writes) as JSON text.

        Raises
        ------
        ValueError
            If a number of the model is not finite (JSON has no NaN or infinity).
        """
        return self._model().to_json()

    def save(self, path: str | os.PathLike[str], *, tolerance: float = 1e-6) -> None:
        """Writes the model to `path`, atomically (a failed write leaves no file): the model
        file (JSON, what the CLI reads), or a STEP file for a path ending in ``.step`` /
        ``.stp`` (`to_step`, named after the file, with `tolerance`; approximated pieces
        are warned about with `StepApproximationWarning`).

        Raises
        ------
        ValueError
            If a number of the model is not finite, or (STEP) the model has no exact
            B-spline form.
        OSError
            If the file cannot be written.
        """
        target = _path(path)
        stem, ext = os.path.splitext(os.path.basename(target))
        if ext.lower() in _STEP_SUFFIXES:
            data = self.to_step(name=stem or "geomkit", tolerance=tolerance)
        else:
            data = self.to_json()
        _write_atomic(target, data.encode("utf-8"))

    def to_step(
        self,
        name: str = "geomkit",
        schema: Literal["ap214", "ap242"] = "ap214",
        tolerance: float = 1e-6,
    ) -> str:
        """The model as a STEP file (ISO 10303-21 text) with its exact geometry, as ``geomkit
        export`` writes it: curves as ``B_SPLINE_CURVE_WITH_KNOTS`` edges (the rational
        complex entity for weights), surfaces as faces bounded by their sides, composite
        surfaces as faces sewn along shared edges, closed bodies as a ``MANIFOLD_SOLID_BREP``
        (planes as degree-1 B-spline surfaces, circles as rational quadratics). Every real
        is written with the shortest digits that read back to the same float; the same
        model gives the same text.

        Formulas without an exact B-spline form (sqrt, sin, exp, ... in composite patches,
        ruled curves, composite curves) are written as interpolating cubic B-splines refined
        until their largest deviation from the formula is at most `tolerance` times the
        diagonal of the model's bounding box; each such piece is warned about
        (`StepApproximationWarning`, naming it and its deviation) and listed by
        `step_export`.

        Parameters
        ----------
        name : str, optional
            The product's name in the file.
        schema : {"ap214", "ap242"}, optional
            The application protocol (AP214 is read by every STEP reader).
        tolerance : float, optional
            The relative tolerance of approximated formulas (default 1e-6).

        Returns
        -------
        str

        Raises
        ------
        ValueError
            For a model with no B-spline form (point-calculus models, samples), points of a
            dimension other than 2 or 3, an unknown schema, a tolerance that is not finite
            and > 0 or that a formula cannot reach (a singular derivative).

        Examples
        --------
        >>> import geomkit
        >>> text = geomkit.BezierCurve([[0, 0, 0], [1, 2, 0], [3, 1, 1]]).to_step()
        >>> text.startswith("ISO-10303-21;") and "B_SPLINE_CURVE_WITH_KNOTS" in text
        True
        """
        export = self.step_export(name, schema, tolerance)
        for a in export.approximations:
            warnings.warn(f"approximated {a}", StepApproximationWarning, stacklevel=2)
        return export.text

    def step_export(
        self,
        name: str = "geomkit",
        schema: Literal["ap214", "ap242"] = "ap214",
        tolerance: float = 1e-6,
    ) -> StepExport:
        """`to_step`'s text and the report of what is approximated, without warnings.

        Returns
        -------
        StepExport
            ``text`` and ``approximations`` (one `StepApproximation` per piece written as
            an interpolating B-spline; empty when the file is exact).

        Examples
        --------
        >>> import geomkit
        >>> s = geomkit.loads('{"type": "composite_explicit", "x_knots": [0, 1], '
        ...                   '"y_knots": [0, 1], "patches": [["sin(x) * exp(y)"]]}')
        >>> out = s.step_export()
        >>> a = out.approximations[0]
        >>> a.piece, a.deviation <= a.tolerance
        ('patch (0, 0)', True)
        """
        if not isinstance(name, str):
            raise TypeError(f"name must be a str, not {type(name).__name__}")
        if not isinstance(schema, str):
            raise TypeError(f"schema must be a str, not {type(schema).__name__}")
        if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)):
            raise TypeError(f"tolerance must be a float, not {type(tolerance).__name__}")
        text, report = _geomkit.step_write(self._model(), name, schema, float(tolerance))
        return StepExport(text, [StepApproximation(p, tuple(n), d, t) for p, n, d, t in report])

    def mesh(
        self, tolerance: float | None = None, samples: int | tuple[int, int] | None = None
    ) -> Mesh | Polyline:
        """Tessellates the model, as ``geomkit mesh`` does: a surface to triangles, a curve to
        a polyline.

        Adaptive sampling (the default) refines until the mesh is within `tolerance` of the
        model, checked at edge midpoints and cell centres for a surface and at the quarter
        points of every segment for a curve; `samples` samples uniformly instead (break
        lines of piecewise models added). The GIL is released while tessellating.

        Parameters
        ----------
        tolerance : float, optional
            The largest distance between the model and the mesh, in model units, finite and
            > 0. Default: 1/1000 of the model's extent per axis for a surface (work capped
            at 2 000 000 triangles: the default tolerance stopped by the cap gives the mesh,
            with ``report.capped`` set), 1/2000 of the diagonal for a curve.
        samples : int or (int, int), optional
            Uniform samples instead: K (a curve's points; a surface's K x K grid) or (K, L)
            (a surface's grid), each at least 2. Not together with `tolerance`.

        Returns
        -------
        Mesh or Polyline
            A `Mesh` for a surface (closed bodies watertight), a `Polyline` for a curve.

        Raises
        ------
        ValueError
            For a tolerance that is not finite and > 0 or out of reach within the caps,
            samples below 2 or beyond the caps, both options, and a model that is neither
            one curve nor one surface (e.g. a point-calculus model of 3 factors).
        TypeError
            For a tolerance or samples that are not numbers.

        Examples
        --------
        >>> import geomkit
        >>> quad = geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}')
        >>> line = quad.mesh(samples=5)
        >>> line.points.tolist()
        [[0.0, 0.0], [0.5, 0.75], [1.0, 1.0], [1.5, 0.75], [2.0, 0.0]]
        """
        t, k = _sampling(tolerance, samples)
        report = reporter(-1, "mesh")
        try:
            return _wrap(self._model().tessellate(t, k, report))
        finally:
            if report is not None:
                report.close()

    def write(
        self,
        path: str | os.PathLike[str],
        *,
        tolerance: float | None = None,
        samples: int | tuple[int, int] | None = None,
        ascii: bool = False,
        obj_normals: ObjNormals = "auto",
    ) -> None:
        """Meshes the model (`mesh`) and writes the mesh to `path`, as ``geomkit mesh -o``.

        The format is the extension's: ``.obj`` (with normals as `obj_normals` says),
        ``.stl`` (binary, or text with `ascii`), ``.ply`` (binary, per-vertex normals) or
        ``.glb`` (glTF binary, z up turned to glTF's y up). A curve becomes a polyline
        (``.obj``, ``.ply``, ``.glb``). The file is written atomically: an error leaves no
        file (and an existing file as it was).

        Parameters
        ----------
        path : str or os.PathLike
            The mesh file: ``*.obj``, ``*.stl``, ``*.ply`` or ``*.glb``.
        tolerance, samples
            As for `mesh`.
        ascii : bool, optional
            Text STL instead of binary.
        obj_normals : {"auto", "indexed", "per-vertex", "none"}, optional
            OBJ normals: ``"auto"`` (one ``vn`` per ``v`` on a smooth surface, none on a body
            with sharp edges: every reader takes it, closed bodies stay watertight),
            ``"indexed"`` (``f v//vn``: sharp creases on shared positions; meshio refuses
            it), ``"per-vertex"`` (vertices split at creases), ``"none"``.

        Raises
        ------
        ValueError
            For an unknown extension (the message lists the formats), a curve written as
            STL, and the errors of `mesh`.
        OSError
            If the file cannot be written.

        Examples
        --------
        >>> import os, tempfile, geomkit
        >>> quad = geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}')
        >>> path = os.path.join(tempfile.mkdtemp(), "quad.obj")
        >>> quad.write(path, samples=3)
        >>> [line for line in open(path) if line.startswith("l")]
        ['l 1 2 3\\n']
        """
        target, fmt = _mesh_path(path)
        _check_mesh_options(fmt, ascii, obj_normals)
        _write_mesh(self.mesh(tolerance, samples), target, fmt, ascii, obj_normals)

    def svg(
        self,
        *,
        view: View = (35.0, 25.0),
        size: Size | None = None,
        net: bool = True,
        title: str = "",
    ) -> str:
        """The picture of the model as SVG text, as ``geomkit render -o OUT.svg`` draws it.

        A curve with its control polygon and the points it passes through (1-D curves as
        graphs over the parameter, 3-D ones in the axonometric view), a surface shaded in
        3-D with its control net and reference points. The subtitle says what the model is
        (`describe`).

        Parameters
        ----------
        view : (float, float) or str, optional
            Camera azimuth and elevation in degrees (elevation within -90..90), or
            ``"AZ,EL"`` as the CLI's ``--view``. Default (35, 25).
        size : (int, int) or str, optional
            Width and height in pixels of a shaded surface picture, each 16 to 8192, or
            ``"WxH"``. Default 720 x 540 (curve pictures size themselves).
        net : bool, optional
            Draw the control net or polygon (the CLI's ``--no-net`` is ``net=False``).
        title : str, optional
            The title above the picture.

        Returns
        -------
        str
            SVG text.

        Raises
        ------
        ValueError
            For a view or size out of range, and a model that cannot be drawn (neither one
            curve nor one surface, points of a dimension other than 1, 2 or 3).
        TypeError
            For options of the wrong type.

        Examples
        --------
        >>> import geomkit
        >>> quad = geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}')
        >>> quad.svg(title="A parabola").startswith("<svg")
        True
        """
        v, s = _view(view), _size(size)
        return self._model().picture_svg(_title(title), v, s, _flag(net, "net"))

    def png(
        self,
        *,
        view: View = (35.0, 25.0),
        size: Size | None = None,
        net: bool = True,
        title: str = "",
        scale: float = 2.0,
    ) -> bytes:
        """The picture of the model as PNG bytes, as ``geomkit render -o OUT.png`` draws it.

        The SVG picture (see `svg`) rasterized with an embedded font on white: at `scale`
        times its own size, or fitted into `size` (aspect kept, centred).

        Parameters
        ----------
        view, net, title
            As for `svg`.
        size : (int, int) or str, optional
            The PNG's width and height in pixels, each 16 to 8192 (also the size of a shaded
            surface picture), or ``"WxH"``. Default: `scale` times the SVG's size.
        scale : float, optional
            Pixels per SVG unit when `size` is not given, > 0 and at most 16. Default 2.

        Returns
        -------
        bytes
            A PNG file.

        Raises
        ------
        ValueError
            As for `svg`, and for a scale out of range.

        Examples
        --------
        >>> import geomkit
        >>> quad = geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}')
        >>> quad.png(size=(320, 240))[:8]
        b'\\x89PNG\\r\\n\\x1a\\n'
        """
        v, s = _view(view), _size(size)
        k = _real(scale, "scale")
        return self._model().picture_png(_title(title), v, s, _flag(net, "net"), k)

    def render(
        self,
        path: str | os.PathLike[str],
        *,
        view: View = (35.0, 25.0),
        size: Size | None = None,
        net: bool = True,
        title: str | None = None,
        scale: float = 2.0,
    ) -> None:
        """Writes the picture of the model to `path`, PNG or SVG by its extension, as
        ``geomkit render MODEL -o OUT.png|OUT.svg``; atomically (an error leaves no file).

        Parameters
        ----------
        path : str or os.PathLike
            ``*.png`` or ``*.svg``.
        view, size, net, scale
            As for `svg` and `png` (`scale` applies to PNG only).
        title : str, optional
            The title. Default: the picture file's name without its extension.

        Raises
        ------
        ValueError
            For another extension (the message lists the formats), and as `svg` / `png`.
        OSError
            If the file cannot be written.

        Examples
        --------
        >>> import os, tempfile, geomkit
        >>> quad = geomkit.loads('{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}')
        >>> path = os.path.join(tempfile.mkdtemp(), "quad.svg")
        >>> quad.render(path, view=(30, 20), title="A parabola")
        >>> "A parabola" in open(path, encoding="utf-8").read()
        True
        """
        target = _path(path)
        ext = os.path.splitext(target)[1].lower()
        if ext not in _PICTURE_FORMATS:
            raise ValueError(
                f"cannot tell the picture format of {target!r}: name it "
                + " or ".join(_PICTURE_FORMATS)
            )
        if title is None:
            title = os.path.splitext(os.path.basename(target))[0]
        if ext == ".png":
            data = self.png(view=view, size=size, net=net, title=title, scale=scale)
        else:
            data = self.svg(view=view, size=size, net=net, title=title).encode("utf-8")
        _write_atomic(target, data)

    def _repr_svg_(self) -> str | None:
        """Jupyter's picture of a curve (SVG: sharp at any zoom, small); None for a surface,
        which shows as PNG (`_repr_png_`), and for a model that cannot be drawn."""
        try:
            if self._model().shape != "curve":
                return None
            return self.svg()
        except ValueError:
            return None

    def _repr_png_(self) -> bytes | None:
        """Jupyter's picture of a surface (PNG, 480 x 360: a shaded view has thousands of
        triangles, too many for SVG in a notebook); None for a curve (`_repr_svg_`) and for
        a model that cannot be drawn."""
        try:
            if self._model().shape != "surface":
                return None
            return self.png(size=_REPR_SIZE)
        except ValueError:
            return None


class Model(Drawable):
    """A model of a kind no class of the package represents (e.g. point-equation samples).

    Parameters
    ----------
    model : geomkit._geomkit.Model
        The compiled model.
    """

    def __init__(self, model: _geomkit.Model) -> None:
        self._inner = model

    def _model(self) -> _geomkit.Model:
        return self._inner

    @property
    def kind(self) -> str:
        """The model file's ``"type"``."""
        return self._inner.kind

    def __repr__(self) -> str:
        return f"<geomkit.Model: {self.describe()}>"


def loads(text: str) -> Any:
    """Reads a model from the JSON text of a model file (any ``"type"`` the CLI writes).

    Returns
    -------
    The object of the file's kind (e.g. `geomkit.BezierCurve`), or a `Model`.

    Raises
    ------
    ValueError
        If the text is not a model file, naming the JSON path, line and column at fault.
    """
    if not isinstance(text, str):
        raise TypeError(f"loads() takes the JSON text as str, not {type(text).__name__}")
    model = _geomkit.parse_model(text)
    factory = _LOADERS.get(model.kind)
    return factory(model) if factory is not None else Model(model)


def load(path: str | os.PathLike[str]) -> Any:
    """Reads a model file written by the CLI, the editor or `Drawable.save`.

    Any JSON model file (every ``"type"`` of docs/formats.md), a B-spline curve's
    control points as CSV or ``.npy`` (one point per row) with its knots in the sibling
    ``NAME.knots.EXT``, as ``geomkit interpolate curve --control -o NAME.EXT`` writes them
    (the degree is len(knots) - len(points) - 1), or a STEP file (``.step`` / ``.stp``)
    that holds exactly one curve or surface (`read_step` reads every one of a file).

    Raises
    ------
    ValueError
        If the file is not a model file (the message names the file and the JSON path, or
        the STEP entity), or a STEP file holds no or several curves and surfaces.
    OSError
        If the file cannot be read.
    """
    path = _path(path)
    if os.path.splitext(path)[1].lower() in _STEP_SUFFIXES:
        found = read_step(path)
        if len(found.models) != 1:
            raise ValueError(
                f"{path}: the STEP file holds {len(found.models)} curves and surfaces; "
                "geomkit.read_step(path) reads each of them"
            )
        return found.models[0].model
    if os.path.splitext(path)[1].lower() in (".csv", ".npy"):
        text = _control_pair_json(path)
    else:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    try:
        return loads(text)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


_STEP_SUFFIXES = (".step", ".stp")


class StepApproximationWarning(UserWarning):
    """A piece of a model written to STEP as an interpolating B-spline (a formula without an
    exact B-spline form), with its measured deviation."""


class StepApproximation(NamedTuple):
    """One piece of a STEP export written as an interpolating B-spline (`step_export`)."""

    piece: str
    """The piece: ``patch (0, 1)``, ``strip 2 (v in [1, 2])``, ``piece 3 (t in [2, 3])``."""
    samples: tuple[int, ...]
    """Samples interpolated per direction ((u, v) for a surface, (t,) for a curve)."""
    deviation: float
    """The largest distance between the formula and the B-spline, measured on a grid 8
    times denser than the samples, in the model's units."""
    tolerance: float
    """The tolerance it was refined to, in the model's units."""

    def __str__(self) -> str:
        grid = " x ".join(str(n) for n in self.samples)
        return (f"{self.piece}: a {grid}-point interpolating B-spline, max deviation "
                f"{self.deviation:.2e} (tolerance {self.tolerance:.2e})")


class StepExport(NamedTuple):
    """A STEP file's text and what of it is approximated (`step_export`)."""

    text: str
    """The ISO 10303-21 text."""
    approximations: list[StepApproximation]
    """The pieces written as interpolating B-splines; empty when the file is exact."""


class StepModel(NamedTuple):
    """One curve or surface of a STEP file (`read_step`)."""

    entity: int
    """The entity number (``#123``) it was read from."""
    type: str
    """The entity's type (``B_SPLINE_SURFACE_WITH_KNOTS``; a complex instance's records
    joined by ``+``)."""
    name: str
    """The entity's name in the file (may be empty)."""
    model: Any
    """The object of its kind (`geomkit.BSpline`, `geomkit.BezierSurface`, ...)."""
    note: str | None
    """What changed on the way, if anything (a trimming not kept, a reparametrization)."""


class StepImport(NamedTuple):
    """What a STEP file held (`read_step`)."""

    models: list[StepModel]
    """The curves and surfaces, in the order of their entity numbers."""
    skipped: str
    """The entities not imported, counted by reason (empty if none)."""
    length_unit: str | None
    """The file's length unit (``"MILLI METRE"``, ``"INCH"``, ...) when it names one: the
    coordinates are as written, in that unit."""


def read_step(path: str | os.PathLike[str]) -> StepImport:
    """Reads the B-spline and Bézier curves and surfaces of a STEP file (ISO 10303-21), as
    ``geomkit import`` does: B_SPLINE_CURVE_WITH_KNOTS, BEZIER_CURVE,
    B_SPLINE_SURFACE_WITH_KNOTS, BEZIER_SURFACE (simple and complex instances, rational
    Bézier curves and surfaces of one span, rational B-splines of several spans as one
    rational Bézier object per span: its `note` says which span and interval), faces on a
    PLANE as degree-1 patches; trimmed faces as their whole surface (the note says so). Files
    written by `Drawable.save` / ``geomkit export`` read back to the same control points,
    weights and knots bit for bit.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.step`` / ``.stp`` file.

    Returns
    -------
    StepImport
        The models (objects of their kinds), what was skipped, the length unit.

    Raises
    ------
    ValueError
        For a file that is not STEP, is truncated, has dangling or cyclic references or
        wrong parameters (the message names the entity, ``#12: ...``), or holds nothing
        geomkit reads.
    OSError
        If the file cannot be read.

    Examples
    --------
    >>> import os, tempfile, geomkit
    >>> c = geomkit.BezierCurve([[0, 0, 0], [1, 2, 0], [3, 1, 1]])
    >>> path = os.path.join(tempfile.mkdtemp(), "c.step")
    >>> c.save(path)
    >>> found = geomkit.read_step(path)
    >>> found.models[0].model == c
    True
    """
    path = _path(path)
    with open(path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    try:
        models, skipped, unit = _geomkit.step_read(text)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None
    out = []
    for entity, kind, name, core, note in models:
        factory = _LOADERS.get(core.kind)
        obj = factory(core) if factory is not None else Model(core)
        out.append(StepModel(entity, kind, name, obj, note))
    return StepImport(out, skipped, unit)


def _knots_sibling(path: str) -> str:
    """``NAME.knots.EXT``, the knots of the control points in ``NAME.EXT``."""
    stem, ext = os.path.splitext(path)
    return f"{stem}.knots{ext}"


def _read_table(path: str) -> NDArray[np.float64]:
    """A table of numbers as the CLI reads it: ``.npy`` (float64, 1-D or 2-D), or CSV with an
    optional header line, columns separated by commas, semicolons, tabs or blanks."""
    if path.lower().endswith(".npy"):
        loaded = np.load(path, allow_pickle=False)
        if loaded.dtype.kind not in "biuf" or loaded.ndim not in (1, 2):
            raise ValueError(f"{path}: expected a 1-D or 2-D array of numbers, got "
                             f"{loaded.dtype} of shape {loaded.shape}")
        arr: NDArray[np.float64] = np.asarray(loaded, dtype=np.float64)
        return arr[:, None] if arr.ndim == 1 else arr
    rows: list[list[float]] = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fields = [x for x in re.split(r"[,;\t ]+", line.strip()) if x]
            if not fields:
                continue
            try:
                rows.append([float(x) for x in fields])
            except ValueError:
                if rows or number > 1:
                    raise ValueError(f"{path}, line {number}: {line.strip()!r} is not a row "
                                     "of numbers") from None
                continue  # the header
            if len(rows[-1]) != len(rows[0]):
                raise ValueError(f"{path}, line {number}: {len(rows[-1])} columns, the first "
                                 f"row has {len(rows[0])}")
    if not rows:
        raise ValueError(f"{path}: no rows of numbers")
    return np.array(rows)


def _control_pair_json(path: str) -> str:
    """A B-spline curve's model file from its control points (CSV or ``.npy``, one per row)
    and its knots in ``NAME.knots.EXT``, as ``interpolate curve --control`` writes them."""
    knots_path = _knots_sibling(path)
    if not os.path.isfile(knots_path):
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no such file")
        raise ValueError(
            f"{path}: control points need their knots in {knots_path} (as `geomkit "
            "interpolate curve --control` writes them); models without a knots file are JSON"
        )
    control, knots = _read_table(path), _read_table(knots_path)
    if knots.shape[1] != 1:
        raise ValueError(f"{knots_path}: expected one knot per row, found {knots.shape[1]} "
                         "columns")
    n, k = len(control), len(knots)
    if k <= n + 1:
        raise ValueError(f"{knots_path}: {k} knots for {n} control points in {path} (need "
                         "control points + degree + 1)")
    if not (np.isfinite(control).all() and np.isfinite(knots).all()):
        raise ValueError(f"{path}: the control points and knots must be finite")
    return json.dumps({
        "type": "bspline_curve",
        "degree": k - n - 1,
        "knots": knots[:, 0].tolist(),
        "control_points": control.tolist(),
    })


ObjNormals = Literal["auto", "indexed", "per-vertex", "none"]
View = tuple[float, float] | str
Size = tuple[int, int] | str

_MESH_FORMATS = (".obj", ".stl", ".ply", ".glb")
_PICTURE_FORMATS = (".png", ".svg")
_OBJ_NORMALS = ("auto", "indexed", "per-vertex", "none")
# The picture Jupyter shows of a surface: modest, so that displaying a model stays cheap.
_REPR_SIZE = (480, 360)


@dataclass(frozen=True)
class MeshReport:
    """What the surface mesher did besides the mesh (``geomkit mesh`` prints the same).

    Attributes
    ----------
    closed : bool
        The surface closes on itself (each side of its parameter rectangle collapses to a
        point or meets the opposite side), so its mesh is watertight (checked).
    capped : bool
        Adaptive refinement stopped at the cap (2 000 000 triangles, or lines per
        direction) before the tolerance was met everywhere.
    deviation : float or None
        Adaptive sampling: the largest deviation, in model units, between the surface and
        the mesh at the checks (edge midpoints and cell centres, times 4/3); None for
        uniform samples.
    relative_deviation : float or None
        The same per axis relative to the model's extent along it (the measure of the
        default tolerance, 1e-3).
    weld : tuple of float
        The tolerance per axis below which vertices were merged.
    """

    closed: bool
    capped: bool
    deviation: float | None
    relative_deviation: float | None
    weld: tuple[float, float, float]


class Mesh:
    """A triangle mesh: the mesh of a surface (`Drawable.mesh`) or of your own arrays.

    Vertices are shared between faces (welded), so the mesh of a closed body is watertight;
    faces run counter-clockwise seen from outside a closed body.

    Parameters
    ----------
    vertices : array_like, shape (n, 3)
        The vertices' coordinates, finite.
    faces : array_like of int, shape (m, 3)
        Each face's three vertex indices (0 to n - 1).
    weld_tolerance : float, optional
        Vertices closer than this are merged (default 0: only equal ones).
    crease_angle : float, optional
        Degrees (0 to 180): normals are smooth across edges whose faces meet within this
        angle, sharp across the others (default 40, the mesher's).

    Attributes
    ----------
    vertices : ndarray, shape (n, 3)
    faces : ndarray of int64, shape (m, 3)
    normals : ndarray, shape (n, 3)
        One unit normal per vertex: the smooth normal (area-weighted mean of the face
        normals around it, within the crease angle), the normalized mean of its distinct
        normals where creases meet (the corner of a cube: (1, 1, 1)/sqrt(3)).
    face_normals : ndarray, shape (m, 3)
        The unit normal of each face (zero for a degenerate one).
    report : MeshReport or None
        The mesher's report (None for a mesh of arrays).

    Raises
    ------
    ValueError
        For arrays of other shapes, non-finite vertices, indices out of range, and a
        tolerance or angle out of range.
    TypeError
        For values that are not numbers (faces: not integers).

    Examples
    --------
    >>> import numpy as np, geomkit
    >>> square = geomkit.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    >>> square.area, square.normals[0].tolist()
    (1.0, [0.0, 0.0, 1.0])
    """

    _inner: _geomkit.Mesh
    _report: MeshReport | None
    _cache: dict[str, NDArray[Any]]

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        *,
        weld_tolerance: float = 0.0,
        crease_angle: float = 40.0,
    ) -> None:
        v = contiguous(vertices, "vertices")
        f = _indices(faces)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"vertices must have shape (n, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3:
            raise ValueError(f"faces must have shape (m, 3), got {f.shape}")
        weld = _real(weld_tolerance, "weld_tolerance")
        crease = _real(crease_angle, "crease_angle")
        self._set(_geomkit.Mesh(v, f, weld, crease), None)

    def _set(self, inner: _geomkit.Mesh, report: MeshReport | None) -> None:
        self._inner = inner
        self._report = report
        self._cache = {}

    @classmethod
    def _of(cls, inner: _geomkit.Mesh) -> Mesh:
        mesh = cls.__new__(cls)
        r = inner.report
        report = None
        if r is not None:
            closed, capped, deviation, relative, weld = r
            report = MeshReport(closed, capped, deviation, relative, (weld[0], weld[1], weld[2]))
        mesh._set(inner, report)
        return mesh

    def _array(self, name: str) -> NDArray[Any]:
        arr = self._cache.get(name)
        if arr is None:
            n, m = self._inner.counts
            if name == "faces":
                arr = np.empty((m, 3), dtype=np.int64)
                self._inner.faces_into(arr)
            else:
                arr = np.empty((m if name == "face_normals" else n, 3))
                getattr(self._inner, f"{name}_into")(arr)
            arr.flags.writeable = False
            self._cache[name] = arr
        return arr

    @property
    def vertices(self) -> NDArray[np.float64]:
        """The vertices, shape (n, 3) (read-only)."""
        return self._array("vertices")

    @property
    def faces(self) -> NDArray[np.int64]:
        """The faces' vertex indices, shape (m, 3) (read-only)."""
        return self._array("faces")

    @property
    def normals(self) -> NDArray[np.float64]:
        """One unit normal per vertex, shape (n, 3) (read-only)."""
        return self._array("normals")

    @property
    def face_normals(self) -> NDArray[np.float64]:
        """The unit normal of each face, shape (m, 3) (read-only)."""
        return self._array("face_normals")

    @property
    def report(self) -> MeshReport | None:
        """The surface mesher's report (None for a mesh of arrays)."""
        return self._report

    @property
    def area(self) -> float:
        """The sum of the faces' areas."""
        return self._inner.area()

    @property
    def volume(self) -> float:
        """The signed volume enclosed (divergence theorem; meaningful when watertight,
        positive for outward faces)."""
        return self._inner.volume()

    @property
    def is_watertight(self) -> bool:
        """Every edge is shared by exactly two faces, in opposite directions."""
        return self._inner.is_watertight()

    @property
    def bounds(self) -> NDArray[np.float64]:
        """The bounding box: [[xmin, ymin, zmin], [xmax, ymax, zmax]]."""
        return np.array(self._inner.bounding_box())

    def write(
        self,
        path: str | os.PathLike[str],
        *,
        ascii: bool = False,
        obj_normals: ObjNormals = "auto",
    ) -> None:
        """Writes the mesh to `path` by its extension (``.obj .stl .ply .glb``), atomically.

        See `Drawable.write` for the formats and options.

        Raises
        ------
        ValueError
            For an unknown extension (the message lists the formats), and coordinates
            beyond float32 in STL or glTF (use OBJ or PLY).
        OSError
            If the file cannot be written.

        Examples
        --------
        >>> import os, tempfile, geomkit
        >>> tri = geomkit.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> path = os.path.join(tempfile.mkdtemp(), "tri.stl")
        >>> tri.write(path)
        >>> os.path.getsize(path)  # 80 + 4 + 50 bytes per triangle
        134
        """
        target, fmt = _mesh_path(path)
        _check_mesh_options(fmt, ascii, obj_normals)
        _write_mesh(self, target, fmt, ascii, obj_normals)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_restore_mesh, (self.vertices, self.faces, self._report))

    def __repr__(self) -> str:
        n, m = self._inner.counts
        closed = ", watertight" if self.is_watertight else ""
        return f"<geomkit.Mesh: {n} vertices, {m} faces{closed}>"


def _restore_mesh(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], report: MeshReport | None
) -> Mesh:
    """Unpickles a `Mesh`: the same arrays (already welded, the mesher's crease angle)."""
    mesh = Mesh(vertices, faces)
    mesh._report = report
    return mesh


class Polyline:
    """A polyline: points at strictly increasing parameters; the mesh of a curve
    (`Drawable.mesh`) or of your own arrays.

    Parameters
    ----------
    points : array_like, shape (n, dim)
        The points, finite, of any dimension dim >= 1.
    parameters : array_like, shape (n,)
        The curve parameter of each point, finite and strictly increasing.

    Attributes
    ----------
    points : ndarray, shape (n, dim)
        The points, in the curve's dimension (read-only).
    parameters : ndarray, shape (n,)
        The curve parameter of each point (read-only).

    Raises
    ------
    ValueError
        For arrays of other shapes, values that are not finite, parameters that do not
        increase.
    TypeError
        For values that are not numbers.

    Examples
    --------
    >>> import geomkit
    >>> line = geomkit.loads('{"type": "bezier_curve", "points": [[0], [1]]}').mesh(samples=3)
    >>> line.parameters.tolist(), line.points.tolist()
    ([0.0, 0.5, 1.0], [[0.0], [0.5], [1.0]])
    >>> geomkit.Polyline([[0, 0], [1, 2]], [0, 1])
    <geomkit.Polyline: 2 points in R^2>
    """

    _inner: _geomkit.Mesh
    _points: NDArray[np.float64]
    _parameters: NDArray[np.float64]

    def __init__(self, points: ArrayLike, parameters: ArrayLike) -> None:
        p = contiguous(points, "points")
        t = contiguous(parameters, "parameters")
        if p.ndim != 2 or p.shape[1] == 0:
            raise ValueError(f"points must have shape (n, dim) with dim >= 1, got {p.shape}")
        if t.ndim != 1 or t.shape[0] != p.shape[0]:
            raise ValueError(
                f"parameters must have shape ({p.shape[0]},) (one per point), got {t.shape}"
            )
        self._set(_geomkit.mesh_polyline(p, t))

    @classmethod
    def _of(cls, inner: _geomkit.Mesh) -> Polyline:
        line = cls.__new__(cls)
        line._set(inner)
        return line

    def _set(self, inner: _geomkit.Mesh) -> None:
        n, dim = inner.polyline_shape
        points = np.empty((n, dim))
        parameters = np.empty(n)
        inner.points_into(points)
        inner.parameters_into(parameters)
        points.flags.writeable = False
        parameters.flags.writeable = False
        self._inner = inner
        self._points = points
        self._parameters = parameters

    @property
    def points(self) -> NDArray[np.float64]:
        """The points, shape (n, dim)."""
        return self._points

    @property
    def parameters(self) -> NDArray[np.float64]:
        """The curve parameter of each point, shape (n,)."""
        return self._parameters

    @property
    def dim(self) -> int:
        """The dimension of the points."""
        return int(self._points.shape[1])

    def write(self, path: str | os.PathLike[str]) -> None:
        """Writes the polyline to `path` by its extension (``.obj .ply .glb``), atomically.

        Points in R^3 as they are; 2-D ones in the plane z = 0; 1-D ones as the graph
        (t, x(t), 0) over the parameter; above 3-D the first three coordinates.

        Raises
        ------
        ValueError
            For ``.stl`` (triangles only) and unknown extensions (the message lists the
            formats).
        OSError
            If the file cannot be written.
        """
        target, fmt = _mesh_path(path)
        _check_mesh_options(fmt, False, "auto", curve=True)
        _write_mesh(self, target, fmt, False, "auto")

    def __len__(self) -> int:
        return int(self._points.shape[0])

    def __reduce__(self) -> tuple[Any, ...]:
        return (Polyline, (self._points, self._parameters))

    def __repr__(self) -> str:
        return f"<geomkit.Polyline: {len(self)} points in R^{self.dim}>"


def _wrap(inner: _geomkit.Mesh) -> Mesh | Polyline:
    """The Python object of a compiled tessellation."""
    return Polyline._of(inner) if inner.kind == "polyline" else Mesh._of(inner)


def _path(path: Any) -> str:
    """A file path argument as str (TypeError for others)."""
    try:
        target = os.fspath(path)
    except TypeError:
        raise TypeError(f"path must be str or os.PathLike, not {type(path).__name__}") from None
    if not isinstance(target, str):
        raise TypeError("path must be str or os.PathLike[str], not bytes")
    return target


def _mesh_path(path: Any) -> tuple[str, str]:
    """The path and the mesh format of its extension (ValueError listing the formats)."""
    target = _path(path)
    ext = os.path.splitext(target)[1].lower()
    if ext not in _MESH_FORMATS:
        raise ValueError(
            f"cannot tell the mesh format of {target!r}: name it "
            + ", ".join(_MESH_FORMATS[:-1])
            + f" or {_MESH_FORMATS[-1]}"
        )
    return target, ext[1:]


def _check_mesh_options(fmt: str, ascii: Any, obj_normals: Any, curve: bool = False) -> None:
    _flag(ascii, "ascii")
    if not isinstance(obj_normals, str):
        raise TypeError(f"obj_normals must be a str, not {type(obj_normals).__name__}")
    if obj_normals not in _OBJ_NORMALS:
        raise ValueError(
            f"obj_normals={obj_normals!r}: expected one of " + ", ".join(map(repr, _OBJ_NORMALS))
        )
    if curve and fmt == "stl":
        raise ValueError("STL holds triangles only: write a curve as .obj, .ply or .glb")


def _write_mesh(
    mesh: Mesh | Polyline, target: str, fmt: str, ascii: bool, obj_normals: str
) -> None:
    if isinstance(mesh, Polyline) and fmt == "stl":
        raise ValueError("STL holds triangles only: write a curve as .obj, .ply or .glb")
    _write_atomic(target, mesh._inner.encode(fmt, ascii, obj_normals))


def _real(value: Any, name: str) -> float:
    """A real number argument: TypeError for others (bool included), ValueError for NaN."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(
        value, (int, float, np.integer, np.floating)
    ):
        raise TypeError(f"{name} must be a real number, not {type(value).__name__}")
    x = float(value)
    if not math.isfinite(x):
        raise ValueError(f"{name}={x}: must be finite")
    return x


def _count(value: Any, name: str) -> int:
    """A sample count: an integer from 2 on."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be an integer, not bool")
    try:
        k = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be an integer, not {type(value).__name__}") from None
    if k < 2 or k > 2**62:
        raise ValueError(f"{name}={k}: a sample count must be at least 2")
    return k


def _sampling(tolerance: Any, samples: Any) -> tuple[float | None, tuple[int, int] | None]:
    """`mesh`'s options as the compiled module takes them."""
    if tolerance is not None and samples is not None:
        raise ValueError("give tolerance or samples, not both")
    t = None
    if tolerance is not None:
        t = _real(tolerance, "tolerance")
        if t <= 0:
            raise ValueError(f"tolerance={t}: must be > 0")
    k = None
    if samples is not None:
        if isinstance(samples, (tuple, list)):
            if len(samples) != 2:
                raise ValueError(f"samples must be K or (K, L), got {len(samples)} numbers")
            k = (_count(samples[0], "samples"), _count(samples[1], "samples"))
        else:
            n = _count(samples, "samples")
            k = (n, n)
    return t, k


def _flag(value: Any, name: str) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False, not {type(value).__name__}")
    return bool(value)


def _title(title: Any) -> str:
    if not isinstance(title, str):
        raise TypeError(f"title must be a str, not {type(title).__name__}")
    return title


def _pair(value: Any, name: str, sep: str) -> tuple[Any, Any]:
    if isinstance(value, str):
        parts = value.replace("X", "x").split(sep) if sep == "x" else value.split(sep)
        if len(parts) != 2:
            raise ValueError(f"{name}={value!r}: expected two numbers separated by {sep!r}")
        return parts[0].strip(), parts[1].strip()
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise TypeError(f"{name} must be a pair of numbers, not {value!r}")
    return value[0], value[1]


def _view(view: Any) -> tuple[float, float]:
    """A view (azimuth, elevation) in degrees, or "AZ,EL"."""
    a, e = _pair(view, "view", ",")
    if isinstance(view, str):
        try:
            a, e = float(a), float(e)
        except ValueError:
            raise ValueError(f"view={view!r}: expected AZ,EL in degrees") from None
    az, el = _real(a, "azimuth"), _real(e, "elevation")
    if abs(el) > 90:
        raise ValueError(f"elevation {el} must be within -90..90 degrees")
    return az, el


def _size(size: Any) -> tuple[int, int] | None:
    """A picture size (width, height) in pixels, or "WxH"; each 16 to 8192."""
    if size is None:
        return None
    w, h = _pair(size, "size", "x")
    if isinstance(size, str):
        try:
            w, h = int(w), int(h)
        except ValueError:
            raise ValueError(f"size={size!r}: expected WxH in pixels") from None
    out = []
    for x in (w, h):
        if isinstance(x, (bool, np.bool_)):
            raise TypeError("size must be a pair of integers, not bool")
        try:
            n = operator.index(x)
        except TypeError:
            raise TypeError(f"size must be a pair of integers, not {type(x).__name__}") from None
        if not 16 <= n <= 8192:
            raise ValueError(f"size {n}: width and height must be from 16 to 8192 pixels")
        out.append(n)
    return out[0], out[1]


def _indices(faces: ArrayLike) -> NDArray[np.int64]:
    """Face indices as a C-contiguous int64 array (TypeError for non-integers)."""
    arr = np.asarray(faces)
    if arr.size == 0 and arr.dtype.kind == "f":
        arr = arr.astype(np.int64)
    if arr.dtype.kind not in "iu":
        raise TypeError(f"faces must hold integers, got dtype {arr.dtype}")
    if arr.dtype.kind == "u" and arr.size and int(arr.max()) > np.iinfo(np.int64).max:
        raise ValueError("faces: an index beyond int64")
    return np.require(arr, dtype=np.int64, requirements=["C", "A"])


def _umask() -> int:
    """The process's umask, read without changing it where Linux tells it (os.umask can
    only be read by setting it, which races with other threads creating files)."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _write_atomic(path: str, data: bytes) -> None:
    """Writes `data` to `path` through a temporary file in the same directory."""
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=".geomkit-", suffix=".tmp")
    try:
        if hasattr(os, "fchmod"):  # mkstemp's 0o600 -> a plain open's 0o666 minus the umask
            os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
