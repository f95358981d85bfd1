"""Argument shaping shared by the package's classes: every array goes to the compiled module
as a C-contiguous float64 NumPy array, converted once (no copy when it already is one)."""

from __future__ import annotations

import operator
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _geomkit

Mode = Literal["extend", "nan", "periodic"]

# Tiles larger than this are all of any data (passed on as this).
_LARGEST_TILE = 2**62

# SciPy's `extrapolate` values as the compiled module names them.
_MODES: dict[bool | str, Mode] = {True: "extend", False: "nan", "periodic": "periodic"}


def real_array(a: ArrayLike, name: str) -> NDArray[np.float64]:
    """`a` as a float64 array of its own shape (not necessarily contiguous).

    Raises
    ------
    TypeError
        For complex values (geomkit computes in real numbers), and for values that are not
        numbers (strings, dates, objects that do not convert to float).
    """
    arr = np.asarray(a)
    kind = arr.dtype.kind
    if kind == "c":
        raise TypeError(
            f"{name}: complex values are not supported (geomkit computes in real numbers; "
            f"interpolate the real and imaginary parts separately), got dtype {arr.dtype}"
        )
    if kind == "O":
        try:
            return arr.astype(np.float64)
        except (TypeError, ValueError) as e:
            raise TypeError(f"{name} must hold real numbers: {e}") from e
    if kind not in "biuf":
        raise TypeError(f"{name} must hold real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64, copy=False)


def contiguous(a: ArrayLike, name: str) -> NDArray[np.float64]:
    """`a` as a C-contiguous, aligned float64 array (the same array when it already is one)."""
    return aligned(real_array(a, name))


def aligned(a: ArrayLike) -> NDArray[Any]:
    """`a` as `np.ascontiguousarray` gives it (C-contiguous, at least 1-D) and also aligned, as
    the compiled module reads arrays (the same array when it already is; arrays unpickled
    from another process, e.g. a Dask worker's, may be views of unaligned buffers)."""
    out = np.require(a, requirements=["C", "A"])
    return out.reshape(1) if out.ndim == 0 else out


def index(value: Any, name: str) -> int:
    """An integer argument (SciPy's `operator.index`): a TypeError for floats and others."""
    try:
        return operator.index(value)
    except TypeError as e:
        raise TypeError(f"{name} must be an integer, got {type(value).__name__}") from e


def tile_size(tile: Any) -> int | None:
    """The `tile` keyword of the builders: None, or an integer of at least the library's
    ``MIN_TILE_SIZE`` (a TypeError for booleans, floats and others, a ValueError below)."""
    if tile is None:
        return None
    if isinstance(tile, (bool, np.bool_)):
        raise TypeError("tile must be an integer (points per tile), got bool")
    size = index(tile, "tile")
    if size < _geomkit.MIN_TILE_SIZE:
        raise ValueError(f"tile must be at least {_geomkit.MIN_TILE_SIZE} points (got {size})")
    # Beyond any data a tile is all of it; larger Python integers would only overflow on
    # the way to Rust.
    return min(size, _LARGEST_TILE)


def extrapolate_value(extrapolate: Any) -> bool | str:
    """SciPy's normalization of `extrapolate`: 'periodic' or a bool."""
    if isinstance(extrapolate, str):
        if extrapolate == "periodic":
            return "periodic"
        raise ValueError(
            f"extrapolate={extrapolate!r}: expected True, False or 'periodic'"
        )
    return bool(extrapolate)


def mode(extrapolate: bool | str) -> Mode:
    """The compiled module's name of a normalized `extrapolate`."""
    return _MODES[extrapolate]


def real_scalar(value: Any, name: str) -> float:
    """A real number argument (an integration limit, a knot): a TypeError for others."""
    if isinstance(value, (complex, np.complexfloating)):
        raise TypeError(f"{name}: complex values are not supported, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a real number, got {value!r}") from e
