"""xarray: a DataArray interpolated along named dimensions with the exact-through-data cubic
spline, chunked and parallel (`geomkit.dask` underneath).

What ``DataArray.interp(method="cubic")`` does through SciPy for arrays in memory, for
DataArrays held as dask arrays of any size: the spline through every data value (the
coefficients of each chunk solved with a halo, equal to the global solve within rounding),
evaluated on the new coordinates chunk by chunk. Importing this module registers the
accessor ``.geomkit`` on DataArrays:

>>> import numpy as np, xarray as xr
>>> import geomkit.xarray
>>> t = np.linspace(0.0, 10.0, 101)
>>> arr = xr.DataArray(np.sin(t), dims="t", coords={"t": t}, attrs={"units": "m"}).chunk(25)
>>> fine = arr.geomkit.interp(t=np.linspace(0.0, 10.0, 1001))
>>> fine.attrs["units"], fine.sizes["t"]
('m', 1001)
>>> bool(abs(float(fine.sel(t=5.0)) - np.sin(5.0)) < 1e-5)
True

Coordinates of type datetime64 are interpolated as nanoseconds from the first one. Datasets:
`interp_dataset` and ``Dataset.geomkit.interp`` interpolate every data variable that has one
of the dimensions.
"""

from __future__ import annotations

from collections.abc import Hashable, Mapping
from typing import Any

import dask.array as da
import numpy as np
import xarray as xr
from numpy.typing import NDArray

from . import dask as gdask
from ._arrays import real_array

# Unannotated functions of dask and xarray, called through these aliases (mypy --strict).
_da: Any = da
_xr: Any = xr

__all__ = ["GeomkitAccessor", "GeomkitDatasetAccessor", "interp", "interp_dataset"]


def _numeric(values: Any, origin: Any, dim: Hashable) -> NDArray[np.float64]:
    """Coordinates as float64 (datetime64 as nanoseconds from `origin`)."""
    arr = np.asarray(values)
    if arr.dtype.kind == "M":
        if origin is None:
            raise TypeError(f"{dim!r}: datetime coordinates for a dimension whose own "
                            "coordinate is not a datetime")
        out: NDArray[np.float64] = ((arr - origin) / np.timedelta64(1, "ns")).astype(np.float64)
        return out
    if origin is not None:
        raise TypeError(f"{dim!r}: the dimension's coordinate is a datetime, give datetimes")
    return np.asarray(real_array(arr, f"coordinate {dim!r}"), dtype=np.float64)


def interp(obj: xr.DataArray, coords: Mapping[Hashable, Any] | None = None, *,
           bc_type: Any = None, depth: int | str = 32, chunks: int | None = None,
           **coords_kwargs: Any) -> xr.DataArray:
    """`obj` interpolated along the named dimensions onto new coordinates (lazily, in chunks).

    Parameters
    ----------
    obj : xarray.DataArray
        The data: dask-backed (its chunks are kept) or in memory (then chunked with dask's
        automatic chunks). Each interpolated dimension needs a strictly monotonic 1-D
        coordinate (numbers or datetime64; decreasing ones, such as latitudes from 90 to -90,
        too), or none (then 0, 1, 2, ...).
    coords : mapping of dimension name to array_like, optional
        The new coordinates of each interpolated dimension (1-D, strictly monotonic).
    bc_type : str, (str, str) or dict, optional
        End conditions as in `geomkit.dask.make_interp_grid`: one for all dimensions, or a
        dict keyed by dimension name.
    depth : int or 'auto', optional
        The halo of each chunk (default 32).
    chunks : int, optional
        The output chunk size along the interpolated dimensions (default: the input's number
        of chunks).
    **coords_kwargs
        The new coordinates as keywords (``x=..., y=...``).

    Returns
    -------
    xarray.DataArray
        The same dimensions in the same order, the name and attrs of `obj`; the interpolated
        dimensions on the new coordinates (with their coordinates' attrs), the other
        dimensions and coordinates unchanged (coordinates that vary along an interpolated
        dimension are dropped). Backed by a lazy dask array.

    Raises
    ------
    ValueError
        Unknown dimensions, coordinates that are not 1-D, finite and strictly monotonic,
        and everything `geomkit.dask.make_interp_grid` refuses (a non-finite value names
        its chunk when computed).
    TypeError
        A non-DataArray, non-numeric data or coordinates.
    """
    if not isinstance(obj, xr.DataArray):
        raise TypeError(f"interp takes an xarray.DataArray, got {type(obj).__name__}")
    new = dict(coords or {})
    overlap = set(new) & set(coords_kwargs)
    if overlap:
        raise ValueError(f"dimensions given twice: {sorted(map(str, overlap))}")
    new.update(coords_kwargs)
    if not new:
        raise ValueError("give the new coordinates of at least one dimension (dim=values)")
    dims = list(new)
    for dim in dims:
        if dim not in obj.dims:
            raise ValueError(f"{dim!r} is not a dimension of the DataArray (dims {obj.dims})")
    axes = [obj.get_axis_num(dim) for dim in dims]
    points, new_points, out_coords, flip = [], [], {}, []
    for axis, dim in zip(axes, dims):
        if dim in obj.coords:
            old = np.asarray(obj.coords[dim].values)
        else:
            old = np.arange(obj.sizes[dim], dtype=np.float64)
        origin = old[0] if old.dtype.kind == "M" and old.size else None
        target = new[dim]
        if isinstance(target, xr.DataArray):
            if target.ndim != 1:
                raise ValueError(f"{dim!r}: new coordinates must be 1-D, got dims {target.dims}")
            target = target.values
        target = np.asarray(target)
        if target.ndim != 1:
            raise ValueError(f"{dim!r}: new coordinates must be 1-D, got shape {target.shape}")
        here, there = _numeric(old, origin, dim), _numeric(target, origin, dim)
        if here.size > 1 and here[0] > here[-1]:
            # Decreasing coordinates (latitudes from 90 to -90): the same spline in -x.
            here, there = -here, -there
        if there.size > 1 and there[0] > there[-1]:
            # New coordinates the other way: evaluated increasing, the result turned back.
            there = there[::-1]
            flip.append(axis)
        points.append(here)
        new_points.append(there)
        attrs = obj.coords[dim].attrs if dim in obj.coords else {}
        out_coords[dim] = xr.Variable(dim, target, attrs=dict(attrs))
    if isinstance(bc_type, Mapping):
        unknown = set(bc_type) - set(dims)
        if unknown:
            raise ValueError(f"bc_type names dimensions that are not interpolated: "
                             f"{sorted(map(str, unknown))}")
        bc: Any = {ax: bc_type.get(dim) for ax, dim in zip(axes, dims)}
    else:
        bc = bc_type
    data = obj.data
    if not isinstance(data, da.Array):
        data = _da.from_array(real_array(np.asarray(data), "data"), chunks="auto")
    spline = gdask.make_interp_grid(points, data, axes=axes, bc_type=bc, depth=depth,
                                    name=f"DataArray {obj.name!r}" if obj.name else "DataArray")
    result = spline(*new_points, chunks=chunks)
    if flip:
        result = result[tuple(slice(None, None, -1) if ax in flip else slice(None)
                              for ax in range(result.ndim))]
    kept = {name: var.variable for name, var in obj.coords.items()
            if not set(var.dims) & set(dims)}
    kept.update(out_coords)
    return xr.DataArray(result, dims=obj.dims, coords=kept, name=obj.name,
                        attrs=dict(obj.attrs))


@_xr.register_dataarray_accessor("geomkit")
class GeomkitAccessor:
    """``DataArray.geomkit``: the exact-through-data cubic spline of a DataArray.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> import geomkit.xarray
    >>> arr = xr.DataArray(np.arange(20.0) ** 2, dims="x", coords={"x": np.arange(20.0)})
    >>> arr.geomkit.interp(x=[2.5, 3.5]).values.tolist()
    [6.25, 12.25]
    """

    def __init__(self, obj: xr.DataArray) -> None:
        self._obj = obj

    def interp(self, coords: Mapping[Hashable, Any] | None = None, *, bc_type: Any = None,
               depth: int | str = 32, chunks: int | None = None,
               **coords_kwargs: Any) -> xr.DataArray:
        """`geomkit.xarray.interp` of this DataArray (the same parameters)."""
        return interp(self._obj, coords, bc_type=bc_type, depth=depth, chunks=chunks,
                      **coords_kwargs)


def interp_dataset(ds: xr.Dataset, coords: Mapping[Hashable, Any] | None = None, *,
                   bc_type: Any = None, depth: int | str = 32, chunks: int | None = None,
                   **coords_kwargs: Any) -> xr.Dataset:
    """Every data variable of `ds` that has one of the named dimensions interpolated along
    those it has (`interp` of each); the other variables and the attrs kept.

    Parameters
    ----------
    ds : xarray.Dataset
    coords, bc_type, depth, chunks, **coords_kwargs
        As for `interp`; each variable takes the new coordinates of the dimensions it has.

    Returns
    -------
    xarray.Dataset
        The interpolated dimensions on their new coordinates; coordinates that vary along
        them dropped, as in `interp`.

    Raises
    ------
    ValueError, TypeError
        As `interp`; a non-numeric variable along an interpolated dimension is a TypeError
        naming it.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> import geomkit.xarray
    >>> x = np.arange(10.0)
    >>> ds = xr.Dataset({"a": ("x", x**2), "b": ("x", -x), "label": ((), "sq")},
    ...                 coords={"x": x})
    >>> out = ds.geomkit.interp(x=[1.5, 2.5])
    >>> out["a"].values.tolist(), out["b"].values.tolist(), str(out["label"].values)
    ([2.25, 6.25], [-1.5, -2.5], 'sq')
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"interp_dataset takes an xarray.Dataset, got {type(ds).__name__}")
    new = dict(coords or {})
    new.update(coords_kwargs)
    for dim in new:
        if dim not in ds.dims:
            raise ValueError(f"{dim!r} is not a dimension of the Dataset (dims "
                             f"{tuple(ds.dims)})")
    out = {}
    for name, var in ds.data_vars.items():
        mine = {dim: value for dim, value in new.items() if dim in var.dims}
        if not mine:
            out[name] = var.variable
            continue
        if var.dtype.kind not in "biuf":
            raise TypeError(f"data variable {name!r} ({var.dtype}) cannot be interpolated "
                            f"along {sorted(map(str, mine))}")
        bc = ({d: b for d, b in bc_type.items() if d in mine}
              if isinstance(bc_type, Mapping) else bc_type)
        out[name] = interp(var, mine, bc_type=bc, depth=depth, chunks=chunks).variable
    kept = {name: c.variable for name, c in ds.coords.items() if not set(c.dims) & set(new)}
    for dim, value in new.items():
        target = value.values if isinstance(value, xr.DataArray) else np.asarray(value)
        attrs = ds.coords[dim].attrs if dim in ds.coords else {}
        kept[dim] = xr.Variable(dim, target, attrs=dict(attrs))
    return xr.Dataset(out, coords=kept, attrs=dict(ds.attrs))


@_xr.register_dataset_accessor("geomkit")
class GeomkitDatasetAccessor:
    """``Dataset.geomkit``: `interp_dataset` as a method."""

    def __init__(self, obj: xr.Dataset) -> None:
        self._obj = obj

    def interp(self, coords: Mapping[Hashable, Any] | None = None, *, bc_type: Any = None,
               depth: int | str = 32, chunks: int | None = None,
               **coords_kwargs: Any) -> xr.Dataset:
        """`geomkit.xarray.interp_dataset` of this Dataset (the same parameters)."""
        return interp_dataset(self._obj, coords, bc_type=bc_type, depth=depth, chunks=chunks,
                              **coords_kwargs)
