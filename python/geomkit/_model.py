"""Model files and the common behaviour of every model object of the package.

Every class of the package that describes geometry (Bézier curves and surfaces, B-splines,
composite formulas, point-calculus models, ...) derives from `Drawable` and implements
``_model()``, its `geomkit._geomkit.Model` (the model file of the CLI plus its geometry).
`Drawable` gives them ``describe``, ``to_json``, ``save`` (and, later in this module, meshes
and pictures). `load` / `loads` read a model file back into the class of its kind, as
registered with `register_kind`; a kind no class claims loads as a plain `Model`.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from typing import Any

from . import _geomkit

_LOADERS: dict[str, Callable[[_geomkit.Model], Any]] = {}


def register_kind(kind: str, factory: Callable[[_geomkit.Model], Any]) -> None:
    """Makes `load` return ``factory(model)`` for model files whose ``"type"`` is `kind`."""
    _LOADERS[kind] = factory


class Drawable:
    """What every model object can do; subclasses implement ``_model()``."""

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

    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes the model file to `path`, atomically (a failed write leaves no file).

        Raises
        ------
        ValueError
            If a number of the model is not finite.
        OSError
            If the file cannot be written.
        """
        _write_atomic(os.fspath(path), self.to_json().encode("utf-8"))


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

    Raises
    ------
    ValueError
        If the file is not a model file (the message names the file and the JSON path).
    OSError
        If the file cannot be read.
    """
    path = os.fspath(path)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    try:
        return loads(text)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


def _write_atomic(path: str, data: bytes) -> None:
    """Writes `data` to `path` through a temporary file in the same directory."""
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, prefix=".geomkit-", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
