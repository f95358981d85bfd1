//! # geomkit-model
//!
//! Every file format of the geomkit tools in one place, for every front end (the CLI, the
//! Python package, the editor's server):
//!
//! - [`schema`]: one serde-derived struct per file `"type"` (Bézier and B-spline curves and
//!   surfaces, composite scenes, ruled surfaces, piecewise functions and polylines, formula
//!   files, point-calculus models, curve and surface samples), unknown fields rejected,
//!   versioned ([`schema::FORMAT_VERSION`]); [`ModelFile`] is any of them.
//! - [`AnyModel`]: what a file describes, as library geometry, checked by the library;
//!   [`AnyModel::describe`] says what it is.
//! - [`Loaded`]: a model as one curve or one surface to draw or mesh, with its control
//!   polygon or net and the points it passes through; [`Loaded::tessellate`].
//! - [`parse`], [`load`], [`to_json`], [`write_json`]: text and files. Errors ([`Error`]) name
//!   the file, the JSON path of the value at fault and the line and column, in one line:
//!
//! ```
//! let text = r#"{"type": "bezier_curve", "points": [[0, 0], [1, "2"]]}"#;
//! let err = geomkit_model::parse(text).unwrap_err();
//! assert_eq!(err.path(), Some("points[1][1]"));
//! assert_eq!(err.position(), Some((1, 51)));
//! assert!(err.to_string().starts_with("points[1][1] is the string \"2\""));
//!
//! let model = geomkit_model::parse(r#"{"type": "bezier_curve", "points": [[0, 0], [1, 2]]}"#)
//!     .unwrap();
//! assert_eq!(model.describe(), "Bézier curve of degree 1 in R^2 (2 control points)");
//! ```
//!
//! The formats are documented with an example each in the repository's `docs/formats.md`.

mod error;
mod json;
mod model;
mod numbers;
mod sampled;
pub mod schema;
pub mod shape;
pub mod step;

pub use error::{Error, ErrorKind, Result};
pub use model::{
    ruled_file, AnyModel, BezierModel, BsplineCurveModel, BsplineSurfaceModel, FormulaModel,
    PointcalcModel,
};
pub use numbers::{Net, Points};
pub use sampled::{SampledCurve, SampledSurface};
pub use schema::ModelFile;
pub use shape::{Loaded, Sampling, Shape, Tessellation};

use std::io::Write;
use std::path::Path;

/// Reads a file's schema from JSON text, without building its geometry.
///
/// Errors: [`ErrorKind::Syntax`] for text that is not JSON, [`ErrorKind::Schema`] (with the
/// JSON path, line and column) for JSON that is not a model file.
pub fn parse_file(text: &str) -> Result<ModelFile> {
    let mut de = serde_json::Deserializer::from_str(text);
    let file: ModelFile = serde_path_to_error::deserialize(&mut de)
        .map_err(|e| Error::from_json(e).with_snippet(text))?;
    de.end()
        .map_err(|e| Error::from_json_at(String::new(), e))?;
    Ok(file)
}

/// Reads a model from JSON text: [`parse_file`], then [`AnyModel::from_file`].
pub fn parse(text: &str) -> Result<AnyModel> {
    AnyModel::from_file(parse_file(text)?)
}

/// Reads a model file; errors name the file.
pub fn load(path: &Path) -> Result<AnyModel> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse(&text).map_err(|e| e.in_file(path))
}

/// Writes a file as JSON in the layout of the tools (one point per line, one net row per
/// line, ending with a newline), streamed into `w`.
///
/// Errors: the writer's, and `InvalidData` for a number that is not finite (a result that
/// overflowed): JSON has no NaN or infinity, and a model file never holds `null` for one.
pub fn write_json(file: &ModelFile, w: &mut dyn Write) -> std::io::Result<()> {
    let mut ser = serde_json::Serializer::with_formatter(&mut *w, json::Layout::new());
    serde_path_to_error::serialize(file, &mut ser).map_err(|e| {
        // With the JSON path of the value (to its innermost object or array).
        let message = format!("{} (in \"{}\")", e.inner(), e.path());
        match e.inner().io_error_kind() {
            Some(kind) => std::io::Error::new(kind, message),
            None => std::io::Error::other(message),
        }
    })?;
    w.write_all(b"\n")
}

/// [`write_json`] into a string.
///
/// Errors: a number that is not finite ([`ErrorKind::Model`]).
pub fn to_json(file: &ModelFile) -> Result<String> {
    let mut out = Vec::new();
    write_json(file, &mut out).map_err(|e| Error::model("", e.to_string()))?;
    Ok(String::from_utf8(out).expect("serde_json writes UTF-8"))
}
