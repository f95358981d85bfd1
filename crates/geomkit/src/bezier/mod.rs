//! Method 1: Bézier curves and surfaces and the unified change of their order (degree),
//! spec/bezier-order.md (Nikulin, 2011).
//!
//! - [`BezierCurve`]: formula (1), de Casteljau evaluation, hodograph, power form (2)-(5).
//! - [`degree`]: elevation (6)-(8), real degree and defect, exact and approximate reduction
//!   (9), the unified formula (10).
//! - [`RationalBezierCurve`]: weights; order change through homogeneous coordinates.
//! - [`BezierSurface`]: formulas (11)-(16), the eight order-change problems of (14).
//! - [`RationalBezierSurface`]: weights; order change (14) through homogeneous coordinates.
//! - [`edit`]: the paper's hand edits of control points (they change the shape; we say how much).

mod bound;
mod curve;
pub mod degree;
pub mod edit;
mod rational;
mod rational_surface;
mod surface;

pub use bound::DeviationBound;
pub use curve::BezierCurve;
pub use degree::{
    paper_formula_f64, ApproxOptions, ApproxReduction, DegreeReport, ReductionNorm,
    DEFAULT_TOLERANCE, MAX_ELEVATION_WEIGHTS, MAX_PAPER_DEGREE, MAX_REDUCTION_DEGREE,
};
pub use rational::RationalBezierCurve;
pub use rational_surface::RationalBezierSurface;
pub use surface::{BezierSurface, Direction, SurfaceApproxReduction, SurfaceDegreeReport};
