//! Method 3: single analytic formulas for composite curves, piecewise-ruled surfaces and
//! composite surfaces, spec/composite-surfaces.md (P.G. Dolya, 2005; the Maple package
//! PSCFunctions).
//!
//! - [`ramp`], [`ramp_exact`]: the ramp P(t, a, w) of formula (1), in f64 and exactly.
//! - [`PolyPatch`]: polynomial patches (Bézier patches, B-spline cells) in local coordinates;
//!   [`ExprPatch`]: patches, curve pieces and curves given as formulas.
//! - [`Piecewise`]: piecewise functions and composite curves (§5), polylines and polygons.
//! - [`CompositeSurface`]: formulas (3)-(11) over an orthogonal grid of patches, its
//!   [`ContinuityReport`] and a structural evaluator equal to the single formula.
//!
//! Every single formula passes one check before it is returned (issue 21): its constants
//! are finite, normal f64 (or zero), and the absolute values of its terms add up to less
//! than f64::MAX/2 on its domain widened by its span, so that no printer is handed inf or
//! NaN and evaluating it in f64 cannot overflow; otherwise [`crate::Error::Overflow`] or
//! [`crate::Error::Underflow`] names the patch, piece or coordinate. The steps that compute
//! coefficients (power bases, B-spline cells, the sums of formula (9), the shifts after
//! jumps) refuse overflow where it happens. Limits: knots spanning at most
//! [`MAX_KNOT_SPAN`], intervals at least [`MIN_KNOT_WIDTH`] wide, ruled curves within
//! [`MAX_RULED_COORDINATE`], body sizes at most [`bodies::MAX_BODY_SIZE`].

pub mod bodies;
mod expr_patch;
mod formula;
mod grid;
mod linear;
mod piecewise;
mod poly;
mod ramp;
mod ruled;
mod seams;
mod surface;

pub use expr_patch::ExprPatch;
pub use formula::{abs_sum_expr, ramp_expr, Formula};
pub use grid::{MAX_KNOT_SPAN, MIN_KNOT_WIDTH};
pub use linear::AbsSum;
pub use piecewise::Piecewise;
pub use poly::PolyPatch;
pub use ramp::{ramp, ramp_checked, ramp_exact, simplest_rational};
pub use ruled::{RuledCurve, RuledSurface, MAX_RULED_COORDINATE};
pub use seams::{seams, Seam, SeamLine, SeamOptions, Smoothness};
pub use surface::{CompositeSurface, ContinuityReport, GridLine, Jump, SurfaceKind, EDGE_SAMPLES};
