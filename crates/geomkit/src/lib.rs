//! # geomkit
//!
//! Geometric modeling of curves and surfaces, implementing four published methods faithfully
//! and then better (see the repository's `spec/`):
//!
//! 1. [`bezier`]: Bézier curves and surfaces and the unified change of their order (degree),
//!    up and down, keeping the shape.
//! 2. [`bspline`]: interpolating cubic B-spline curves through reference points.
//!
//! Every model tessellates with [`mesh`] (adaptive polylines, triangle meshes with normals,
//! watertight closed bodies) and writes OBJ, STL, PLY and glTF binary to any `io::Write`.
//!
//! The library does no I/O; every operation on user input returns [`Result`] and never
//! panics on bad input (non-finite numbers, too few points, wrong shapes).
//!
//! ```
//! use geomkit::bezier::{BezierCurve, ParamCurve};
//! let c = BezierCurve::new(vec![vec![0.0, 0.0], vec![1.0, 1.0], vec![2.0, 0.0]]).unwrap();
//! let e = c.elevate_degree(7).unwrap();
//! assert!((e.eval(0.3)[1] - c.eval(0.3)[1]).abs() < 1e-15);
//! ```

pub mod bezier;
pub mod bspline;
pub mod compose;
mod error;
pub mod exact;
pub mod mesh;
mod numeric;
pub mod pointcalc;
mod points;

pub use error::{Error, Result};
/// The expression engine (crate `geomkit-expr`): hash-consed DAG, parser, printers, tape.
pub use geomkit_expr as expr;
