//! Method 4: point equations of curves, surfaces and hypersurfaces in the point
//! Balyuba–Naidysh calculus, spec/point-calculus.md (Adoniev, Vereshchaga, Naidysh).
//!
//! - [`Nodes`]: node sets of a parameter (the paper's {0, 1/2, 1}, {0, 1/3, 1},
//!   {0, 2/3, 1}, any positions, Chebyshev and equispaced presets), their cardinal
//!   ("b-") functions in the barycentric form with derivatives, exact rational coefficients,
//!   the Lebesgue constant.
//! - [`PointEquation`]: curves M(t) = Σ f_i(t) A_i through points of any dimension,
//!   equations (1)-(3) and any number of points.
//! - [`PointSurface`]: surfaces through a net, rows first then across (each row with its own
//!   nodes), the tensor product; [`printed_geomatrix`]: the paper's (9) as printed.
//! - [`Hypersurface`]: k factors, each with its own levels; shares; adding and removing
//!   factors and levels without a solve; batched evaluation in SIMD blocks of points
//!   ([`evaluation_isa`] tells which instruction set it uses).
//! - [`optimize`]: the global largest / smallest modeled response with a certified bound.
//! - [`cardinal_expr`], `to_expr`: point equations as formulas (exact rational nodes) for the
//!   expression printers of [`crate::expr`].
//!
//! Results are finite or an error: a value, share, bound or formula coefficient beyond f64
//! is [`crate::Error::Overflow`] naming the step; a model value far outside the nodes whose
//! rounding error exceeds both it and the data is [`crate::Error::LostToRounding`]. No step
//! overflows on the way to a representable result (exponents of their own, values scaled by
//! powers of two). Limits ([`crate::Error::TooMany`]): [`Nodes::MAX_LEN`] nodes per set (5000),
//! [`Hypersurface::MAX_VALUES`] numbers per model (10^8), [`MAX_FORMULA_TERMS`] factors per
//! formula (10^7); [`optimize`] stops at 4000 boxes or 10^9 operations
//! ([`OptimizeOptions`]).
//!
//! ```
//! use geomkit::pointcalc::{Nodes, PointEquation};
//! use geomkit::geom::Curve;
//! // Equation (1): M = A t̄(1 - 2t) + C 4tt̄ + B t(2t - 1).
//! let eq = PointEquation::new(Nodes::paper_half(), vec![vec![0.0], vec![1.0], vec![0.0]]).unwrap();
//! assert_eq!(eq.eval(0.25)[0], 0.75); // 4 · 0.25 · 0.75
//! ```

mod equation;
mod formula;
mod hypersurface;
mod kernel;
mod nodes;
mod optimize;
mod surface;
mod wide;

pub use equation::{PointEquation, PointOptions, Warning};
pub use formula::{cardinal_expr, MAX_FORMULA_TERMS};
pub use hypersurface::{Factor, Hypersurface};
pub use kernel::evaluation_isa;
pub use nodes::{NodePreset, Nodes};
pub use optimize::{optimize, Goal, OptimizeOptions, Optimum};
pub use surface::{printed_geomatrix, printed_geomatrix_exact, PointSurface, PrintedSurface};

/// A magnitude for messages: "about 1.1e295", or "beyond 1e308" where f64 cannot hold it.
pub(crate) fn magnitude_text(value: f64) -> String {
    if value.is_finite() && value.abs() < f64::MAX {
        format!("about {value:.1e}")
    } else {
        "beyond 1e308".into()
    }
}

/// A Lebesgue constant or limit for messages: three decimals, in e-notation from 1e6 on, and
/// "beyond 1e308" for [`f64::MAX`] (a constant f64 cannot hold).
pub(crate) fn lebesgue_text(value: f64) -> String {
    if value >= f64::MAX {
        "beyond 1e308".into()
    } else if value >= 1e6 {
        format!("{value:.3e}")
    } else {
        format!("{value:.3}")
    }
}
