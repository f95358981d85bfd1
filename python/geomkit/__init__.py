"""geomkit: geometric modeling of curves and surfaces at Rust speed.

The four methods of geomkit's Rust library, with NumPy arrays in and out and the GIL
released during every computation over arrays:

1. Bézier change of degree (`BezierCurve`, rational too, and `BezierSurface`): elevation,
   exact reduction down to the real degree, the degree report, the best approximate
   reduction with its error report, the paper's matrices (`degree_change_matrix`,
   `h_matrix`, exact as fractions), vertex, row and column edits.
2. Interpolating B-splines, SciPy-shaped: `make_interp_spline` / `BSpline`,
   `RectBivariateSpline`, `make_splprep` with SciPy's names, signatures and semantics, and
   the parametric surface through an M x N grid of points (`make_interp_surface`,
   `BSplineSurface`).
3. Single analytic formulas of composite shapes: closed bodies (`body`), composite surfaces
   of patches, piecewise-ruled surfaces, piecewise functions and curves, printed in 11
   syntaxes (``.formula(fmt)``), as SymPy expressions (``.to_sympy()``) and as a compiled
   evaluator over NumPy arrays (``.evaluator()``).
4. Point calculus: k-factor models through experimental points (`PointModel`) with shares,
   certified optimum and formulas, and point-equation curves and surfaces.

Every model object is `Drawable`: ``.mesh()``, ``.write("x.glb")`` (also .stl, .obj,
.ply), ``.render("x.png")``, ``.svg()``, ``.png()``, its picture in Jupyter, and
``.save(path)`` to the model files of the CLI, which `load` reads back. Long evaluations
show a progress bar inside ``with geomkit.progress(): ...`` (tqdm's if installed).

Examples
--------
>>> import numpy as np
>>> import geomkit
>>> x = np.linspace(0.0, 2.0 * np.pi, 9)
>>> s = geomkit.make_interp_spline(x, np.sin(x), k=5, bc_type="periodic")
>>> bool(np.allclose(s(x), np.sin(x), atol=1e-15))
True
>>> geomkit.BezierCurve([[0, 0], [1, 2], [2, 0]]).elevate(4).degree
4
"""

from ._bezier import *  # noqa: F403
from ._bezier import __all__ as _bezier_all
from ._bspline import BSpline, make_interp_spline
from ._compose import *  # noqa: F403
from ._compose import __all__ as _compose_all
from ._geomkit import MIN_TILE_SIZE
from ._model import (
    Drawable,
    Mesh,
    MeshReport,
    Model,
    Polyline,
    StepApproximation,
    StepApproximationWarning,
    StepExport,
    StepImport,
    StepModel,
    load,
    loads,
    read_step,
)
from ._netsurface import BSplineSurface, make_interp_surface
from ._pointcalc import *  # noqa: F403
from ._pointcalc import __all__ as _pointcalc_all
from ._progress import progress
from ._splprep import make_splprep
from ._surface import RectBivariateSpline

__all__ = sorted(
    [
        "BSpline",
        "BSplineSurface",
        "Drawable",
        "MIN_TILE_SIZE",
        "Mesh",
        "MeshReport",
        "Model",
        "Polyline",
        "RectBivariateSpline",
        "StepApproximation",
        "StepApproximationWarning",
        "StepExport",
        "StepImport",
        "StepModel",
        "load",
        "loads",
        "make_interp_spline",
        "make_interp_surface",
        "make_splprep",
        "progress",
        "read_step",
        *_bezier_all,
        *_compose_all,
        *_pointcalc_all,
    ]
)


# --- geomkit.dask and geomkit.xarray (issue 24): submodules imported on first use, so that
# `import geomkit` never imports dask or xarray.
from typing import TYPE_CHECKING  # noqa: E402

if TYPE_CHECKING:
    from . import dask, xarray  # noqa: F401


def __getattr__(name: str) -> object:
    if name in ("dask", "xarray"):
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
