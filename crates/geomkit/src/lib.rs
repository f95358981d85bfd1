//! # geomkit
//!
//! Geometric modeling of curves and surfaces, implementing four published methods faithfully
//! and then better (see the repository's `spec/`):
//!
//! 1. [`bezier`]: Bézier curves and surfaces and the unified change of their order (degree),
//!    up and down, keeping the shape.
//! 2. [`bspline`]: interpolating cubic B-spline curves through reference points.
//!
//! Every curve and surface implements the shared capability traits of [`geom`]
//! ([`geom::Curve`], [`geom::Surface`]): domain, evaluation into a caller's buffer, one batch
//! entry point that picks the type's fastest kernel, derivatives and break points.
//!
//! Every model tessellates with [`mesh`] (adaptive polylines, triangle meshes with normals,
//! watertight closed bodies) and writes OBJ, STL, PLY and glTF binary to any `io::Write`.
//!
//! The `parallel` cargo feature (on by default) runs large batches, solves and grids on
//! rayon's thread pool; without it the crate builds without rayon and every kernel runs on
//! the calling thread, with the same values.
//!
//! The library does no I/O; every operation on user input returns [`Result`] and never
//! panics on bad input (non-finite numbers, too few points, wrong shapes).
//!
//! ```
//! use geomkit::bezier::BezierCurve;
//! use geomkit::geom::Curve;
//! let c = BezierCurve::new(vec![vec![0.0, 0.0], vec![1.0, 1.0], vec![2.0, 0.0]]).unwrap();
//! let e = c.elevate_degree(7).unwrap();
//! assert!((e.eval(0.3)[1] - c.eval(0.3)[1]).abs() < 1e-15);
//! ```

pub mod bezier;
pub mod bspline;
pub mod compose;
mod error;
pub mod exact;
pub mod geom;
pub mod mem;
pub mod mesh;
mod numeric;
mod par;
pub mod pointcalc;
mod points;
pub mod progress;

pub use error::{Error, Result};
/// The expression engine (crate `geomkit-expr`): hash-consed DAG, parser, printers, tape.
pub use geomkit_expr as expr;
