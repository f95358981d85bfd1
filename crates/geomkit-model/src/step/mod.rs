//! STEP (ISO 10303-21 clear text, AP214 or AP242) export and import of the exact geometry:
//! Bézier and B-spline curves and surfaces, rational ones, and the closed bodies.
//!
//! [`write`] turns a model into an exchange structure:
//!
//! - curves (Bézier, rational Bézier, B-spline of degree >= 1) as
//!   `B_SPLINE_CURVE_WITH_KNOTS` (the rational complex entity with `RATIONAL_B_SPLINE_CURVE`
//!   for weights), each the geometry of an `EDGE_CURVE` between its end vertices, in an
//!   `EDGE_BASED_WIREFRAME_MODEL`;
//! - surfaces (Bézier, B-spline) as `B_SPLINE_SURFACE_WITH_KNOTS`, each an `ADVANCED_FACE`
//!   bounded by its four boundary curves (left out where a side collapses to a point; one
//!   seam edge used twice where opposite sides coincide, with `u_closed`/`v_closed` set), in
//!   an `OPEN_SHELL` of a `SHELL_BASED_SURFACE_MODEL`; composite surfaces as the set of
//!   their patches sewn along shared edges (one `EDGE_CURVE` and its `VERTEX_POINT`s where
//!   patches meet);
//! - the closed bodies (cube, box, prism, pyramid, cone, cylinder, frustum) as a
//!   `MANIFOLD_SOLID_BREP` of a `CLOSED_SHELL` with shared edges and vertices: plane faces as
//!   degree-1 B-spline surfaces, circles as rational quadratic B-splines (exact up to the
//!   rounding of √2/2).
//!
//! Knots are written as STEP takes them: distinct values and multiplicities, geomkit's full
//! knot vector as stored (clamped or not; end knots repeated more than p + 1 times are
//! dropped with the control points they leave without influence). Every real is written
//! with the shortest digits that read back to the same `f64`, so [`read`] of [`write`] gives
//! the same control points, weights and knots bit for bit. The length unit is the
//! millimetre (geomkit's numbers unchanged), the uncertainty [`WriteOptions::uncertainty`].
//! The same model gives the same bytes (the header's time stamp is fixed unless given).
//!
//! Formulas without an exact B-spline form (formula patches of composite surfaces, ruled
//! surfaces over formula curves, composite curves of formula pieces) are written as the
//! nearest exact-through-points B-spline within [`WriteOptions::tolerance`]; [`export`]
//! reports each such piece and its measured deviation ([`Approximation`]), also in the
//! file's header.
//!
//! [`read`] takes the B-spline and Bézier curve and surface entities of a file (simple and
//! complex instances, rational ones of several spans split into rational Bézier pieces by
//! knot insertion) and plane faces bounded by straight edges, and gives each as a model
//! file; the curves that only bound faces are the faces' edges and are not given
//! separately; trimmed faces are reported ([`Import::trimmed`]).
//!
//! ```
//! use geomkit_model::step;
//! let model = geomkit_model::parse(
//!     r#"{"type": "bezier_curve", "points": [[0, 0, 0], [1, 2, 0], [3, 0, 1]]}"#).unwrap();
//! let text = step::write(&model, &step::WriteOptions::default()).unwrap();
//! assert!(text.contains("B_SPLINE_CURVE_WITH_KNOTS"));
//! let back = step::read(&text).unwrap();
//! assert_eq!(back.models.len(), 1);
//! assert_eq!(back.models[0].file.type_name(), "bezier_curve");
//! ```

mod approx;
mod bodies;
mod convert;
mod nurbs;
mod part21;
mod read;
mod split;
mod write;

pub use approx::{Approximation, CHECK, MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES};
pub use read::{read, Import, Imported, TrimmedFace};

use crate::AnyModel;

/// An error of reading or writing STEP: one line naming the entity (`#123`) or the line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// The text is not a well-formed exchange structure.
    #[error("line {line}: {message}")]
    Syntax {
        /// Line of the error, 1-based.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// An entity instance is not what its references or type require.
    #[error("#{id}: {message}")]
    Entity {
        /// The entity number.
        id: u64,
        /// What is wrong.
        message: String,
    },
    /// A model or entity kind that cannot be written, or a file with nothing to read.
    #[error("{0}")]
    Unsupported(String),
}

impl StepError {
    /// A syntax error inside instance `#id`: the message names it.
    fn at(self, id: u64) -> StepError {
        match self {
            StepError::Syntax { line, message } => StepError::Syntax {
                line,
                message: format!("#{id}: {message}"),
            },
            other => other,
        }
    }
}

/// The result of the STEP functions.
pub type StepResult<T> = std::result::Result<T, StepError>;

/// The application protocol named in the header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Schema {
    /// AP214, `AUTOMOTIVE_DESIGN` (read by every STEP reader).
    #[default]
    Ap214,
    /// AP242, `AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF`.
    Ap242,
}

/// Options of [`write`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct WriteOptions {
    /// The product's and the shape's name.
    pub name: String,
    /// The header's description.
    pub description: String,
    /// The header's time stamp; `None`: the fixed `1970-01-01T00:00:00`, so that the same
    /// model gives the same bytes.
    pub timestamp: Option<String>,
    /// The application protocol.
    pub schema: Schema,
    /// The distance below which points are one point, stated in the file (default 1e-7,
    /// OCCT's `Precision::Confusion`).
    pub uncertainty: f64,
    /// The largest deviation allowed where a formula has no exact B-spline form and is
    /// written as an interpolating B-spline, relative to the diagonal of the model's
    /// bounding box (default 1e-6). See [`export`].
    pub tolerance: f64,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            name: "geomkit".into(),
            description: "exact geometry written by geomkit".into(),
            timestamp: None,
            schema: Schema::Ap214,
            uncertainty: 1e-7,
            tolerance: 1e-6,
        }
    }
}

impl WriteOptions {
    /// With the product's name.
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// With a time stamp in the header.
    pub fn with_timestamp(mut self, stamp: impl Into<String>) -> Self {
        self.timestamp = Some(stamp.into());
        self
    }

    /// With the application protocol.
    pub fn with_schema(mut self, schema: Schema) -> Self {
        self.schema = schema;
        self
    }

    /// With the uncertainty (finite, > 0).
    pub fn with_uncertainty(mut self, uncertainty: f64) -> Self {
        self.uncertainty = uncertainty;
        self
    }

    /// With the relative tolerance of approximated formulas (finite, > 0).
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// With the header's description.
    pub fn with_description(mut self, description: impl Into<String>) -> Self {
        self.description = description.into();
        self
    }
}

/// A STEP file and what of it is not exact.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Export {
    /// The ISO 10303-21 text.
    pub text: String,
    /// The pieces written as interpolating B-splines (formulas without an exact B-spline
    /// form), in the order of the model's pieces; empty when the file is exact.
    pub approximations: Vec<Approximation>,
}

/// The model as a STEP file (ISO 10303-21 text): [`export`]'s text.
///
/// Errors: as [`export`].
pub fn write(model: &AnyModel, options: &WriteOptions) -> StepResult<String> {
    export(model, options).map(|e| e.text)
}

/// The model as a STEP file, with the report of what is approximated. See the module
/// documentation for what each kind of model becomes.
///
/// Exact (up to the rounding of the model's own numbers) where the geometry is polynomial
/// or rational. Formulas without an exact B-spline form (the formula patches of composite
/// surfaces, ruled surfaces over formula curves, composite curves and piecewise functions
/// of formula pieces) are written as the nearest exact-through-points B-spline: each piece
/// (patch, strip, piece) is sampled on a uniform grid of its parameters, interpolated by
/// cubic B-splines with the same parameters, and the grid is refined until the largest
/// distance to the formula measured on a grid [`CHECK`] times denser is at most
/// [`WriteOptions::tolerance`] × the diagonal of the model's bounding box. Each such piece
/// is listed in [`Export::approximations`] with its deviation, and in the file's header
/// (`FILE_DESCRIPTION`).
///
/// Errors ([`StepError::Unsupported`]): a model with no B-spline form here (point-calculus
/// models, samples), points of a dimension other than 2 or 3, B-spline curves of degree 0,
/// an uncertainty or tolerance that is not finite and > 0, a formula not finite at a sample
/// point, or a piece whose interpolant is still farther than the tolerance at
/// [`MAX_SURFACE_SAMPLES`] ([`MAX_CURVE_SAMPLES`] for curves) samples per direction (a
/// singular derivative, such as `sqrt(u)` at 0: give a larger tolerance).
///
/// ```
/// use geomkit_model::step;
/// let model = geomkit_model::parse(r#"{"type": "composite_explicit",
///     "x_knots": [0, 1], "y_knots": [0, 1], "patches": [["sin(x) * exp(y)"]]}"#).unwrap();
/// let out = step::export(&model, &step::WriteOptions::default()).unwrap();
/// assert_eq!(out.approximations.len(), 1);
/// let a = &out.approximations[0];
/// assert!(a.deviation <= a.tolerance);
/// assert!(out.text.contains("approximated"));
/// ```
pub fn export(model: &AnyModel, options: &WriteOptions) -> StepResult<Export> {
    if !(options.uncertainty.is_finite() && options.uncertainty > 0.0) {
        return Err(StepError::Unsupported(format!(
            "the uncertainty {} must be finite and > 0",
            options.uncertainty
        )));
    }
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(StepError::Unsupported(format!(
            "the tolerance {} must be finite and > 0",
            options.tolerance
        )));
    }
    let (content, approximations) = convert::content(model, options.tolerance)?;
    let text = write::write(&content, options, &approximations)?;
    Ok(Export {
        text,
        approximations,
    })
}
