"""geomkit: geometric modeling at Rust speed.

This first part of the Python package (issue 23, part 1) gives SciPy's interpolating
B-splines, with SciPy's names, signatures, attributes and semantics, computed by geomkit's
Rust library with the GIL released:

- `make_interp_spline` (``scipy.interpolate.make_interp_spline``): degrees 0 to 7, every
  ``bc_type`` form, any shape of ``y`` with ``axis``;
- `BSpline` (``scipy.interpolate.BSpline``): evaluation with derivatives and the three
  extrapolation modes, ``derivative``, ``antiderivative``, ``integrate``, ``insert_knot``,
  ``to_scipy`` / ``from_scipy``, pickling;
- `RectBivariateSpline` (``scipy.interpolate.RectBivariateSpline`` with ``s=0``):
  grid and point evaluation with partial derivatives, ``ev``, ``integral``,
  ``get_knots``, ``get_coeffs``, pickling;
- `make_splprep` (``scipy.interpolate.make_splprep`` with ``s=0``): the interpolating
  parametric curve through points of any dimension, plus geomkit's ``param`` keyword
  ('chord', 'centripetal', 'uniform').

Not yet here (the rest of issue 23): Bézier curves and surfaces, composite formulas, point
calculus, meshes and pictures, model files.

Examples
--------
>>> import numpy as np
>>> import geomkit
>>> x = np.linspace(0.0, 2.0 * np.pi, 9)
>>> s = geomkit.make_interp_spline(x, np.sin(x), k=5, bc_type="periodic")
>>> bool(np.allclose(s(x), np.sin(x), atol=1e-15))
True
"""

from ._bspline import BSpline, make_interp_spline
from ._model import Drawable, Model, load, loads
from ._pointcalc import (Optimum, PointCurve, PointCurveSamples, PointModel, PointSurface,
                         PointSurfaceSamples, point_curve, point_surface)
from ._splprep import make_splprep
from ._surface import RectBivariateSpline

__all__ = [
    "BSpline",
    "Drawable",
    "Model",
    "Optimum",
    "PointCurve",
    "PointCurveSamples",
    "PointModel",
    "PointSurface",
    "PointSurfaceSamples",
    "RectBivariateSpline",
    "load",
    "loads",
    "make_interp_spline",
    "make_splprep",
    "point_curve",
    "point_surface",
]
