//! Method 2: interpolating B-spline curves and surfaces through reference points,
//! spec/bspline-interpolation.md (Hoang Thai Ho): the paper's cubics, and any degree in
//! SciPy's representation.
//!
//! - [`BsplineCurve`]: B-splines of any degree on any knots; uniform knots evaluate by the
//!   paper's matrix form (1) with the span found by one multiplication.
//! - [`interpolate_curve`]: the paper's method (repeated end points) and natural, clamped,
//!   not-a-knot and periodic end conditions; uniform, chord-length and centripetal
//!   parameters; banded O(N) solves.
//! - [`make_interp_spline`], [`make_interp_surface`]: any degree 0..=7 with SciPy's knots,
//!   end conditions per end and coefficients (`make_interp_spline`, `RectBivariateSpline`
//!   with s = 0), refined where SciPy loses digits.
//! - [`PiecewiseCurve`]: a curve of degree <= 3 as one cubic polynomial per span, for fast
//!   evaluation of large batches at arbitrary parameters.
//! - [`BsplineSurface`], [`interpolate_surface`], [`interpolate_heights`]: bicubic surfaces
//!   through M×N grids, separable solves (rows, then columns) in parallel.
//! - [`Extrapolate`] and the calculus of [`BsplineCurve`] and [`BsplineSurface`] with
//!   SciPy's semantics (`BSpline`, `RectBivariateSpline`): derivatives of any order,
//!   derivative and antiderivative curves, integrals, knot insertion.
//! - [`interpolate_curve_tiled`], [`CurveTiler`]: tiles with halos, equal to the global solve
//!   within rounding, parallel and streamable; [`SplineTiler`], [`make_interp_spline_tiled`]:
//!   the same for SciPy's representation of any degree 1..=7; [`paper_fragments_averaged`]: the paper's
//!   averaged fragments, for comparison.

mod banded;
mod calculus;
mod curve;
mod interpolate;
mod locate;
mod narrow;
mod piecewise;
mod sample;
mod scipy_cubic;
mod spline;
mod spline_tiles;
mod surface;
mod tiles;
mod tridiag;

pub(crate) use surface::curvature_of;
pub use surface::SurfaceCurvature;

pub use calculus::Extrapolate;
pub use curve::BsplineCurve;
pub use interpolate::{
    interpolate_curve, interpolate_curve_at, interpolate_curve_at_with_progress,
    interpolate_curve_flat, interpolate_curve_flat_with_progress, last_repeats_first,
    paper_dense_inner_points, parameters, parameters_from, CurveInterpolation, CurveInterpolator,
    EndCondition, InterpolationOptions, Parametrization,
};
pub use piecewise::PiecewiseCurve;
pub use sample::FdReport;
pub use spline::{
    augmented_knots, make_interp_spline, make_interp_spline_with_progress, make_interp_surface,
    make_interp_surface_with_progress, not_a_knot_knots, periodic_knots, EndSpec, SplineEnds,
    SplineOptions, MAX_SPLINE_DEGREE,
};
pub use spline_tiles::{
    make_interp_spline_tiled, SplineTile, SplineTilePlan, SplineTiler, MIN_SPLINE_HALO,
};
pub use surface::{
    interpolate_heights, interpolate_heights_at, interpolate_heights_at_with_progress,
    interpolate_heights_with_progress, interpolate_surface, interpolate_surface_flat,
    interpolate_surface_flat_with_progress, BsplineSurface, SurfaceInterpolation,
    SurfaceInterpolationOptions,
};
pub use tiles::{
    interpolate_curve_tiled, interpolate_curve_tiled_with_progress, interpolate_surface_tiled,
    interpolate_surface_tiled_with_progress, paper_fragments_averaged, CurveTiler, TileOptions,
    TilePlan, TileSolution, MIN_TILE_SIZE,
};
