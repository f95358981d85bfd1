//! File formats of the CLI: every model file through the model crate (`geomkit-model`, its
//! schema and checks); here only what is the command line's own — a B-spline curve's control
//! points as CSV or `.npy` (one point per row) with its knots in the sibling file
//! `NAME.knots.EXT` (one knot per row), as `interpolate curve --control` writes them
//! ([`knots_sibling`]) — and the JSON of one number.

use crate::progress::Progress;
use crate::table::{extension, Table};
use anyhow::{bail, Context, Result};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
pub use geomkit_model::schema::ReductionError as ErrorReport;
pub use geomkit_model::{AnyModel, BezierModel, BsplineCurveModel, BsplineSurfaceModel, Loaded};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Reads a Bézier model from a JSON file; errors name the file and the place of the problem.
pub fn read_model(path: &Path) -> Result<BezierModel> {
    match geomkit_model::load(path)? {
        AnyModel::Bezier(m) => Ok(m),
        other => bail!(
            "{}: this is a {}; `geomkit bezier` commands take Bézier models (\"bezier_curve\", \
             \"bezier_surface\"); evaluate it with `geomkit eval`",
            path.display(),
            other.describe()
        ),
    }
}

/// Reads any model: a JSON file of any type, or a B-spline curve's control points (`.csv`,
/// `.npy`) with its knots in the sibling file ([`knots_sibling`]).
pub fn read_any_model(path: &Path) -> Result<AnyModel> {
    if matches!(extension(path).as_deref(), Some("npy" | "csv")) {
        return read_control_pair(path);
    }
    Ok(geomkit_model::load(path)?)
}

/// Reads any model (see [`read_any_model`]) as one curve or surface to draw or mesh.
pub fn load_shape(path: &Path) -> Result<Loaded> {
    Loaded::from_model(read_any_model(path)?).with_context(|| path.display().to_string())
}

/// The file holding the knots of the control points in `control`: `NAME.knots.EXT`.
pub fn knots_sibling(control: &Path) -> PathBuf {
    let stem = control
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = control
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    control.with_file_name(format!("{stem}.knots.{ext}"))
}

fn read_control_pair(path: &Path) -> Result<AnyModel> {
    let progress = Progress::hidden();
    let control = Table::read(path, &progress)?;
    let (n, dim) = control.as_records()?;
    let knots_path = knots_sibling(path);
    if !knots_path.is_file() {
        bail!(
            "{}: control points need their knots in {} (as `interpolate curve --control` \
             writes them); models without a knots file are JSON",
            path.display(),
            knots_path.display()
        );
    }
    let knots = Table::read(&knots_path, &progress)?;
    let (k, one) = knots.as_records()?;
    if one != 1 {
        bail!(
            "{}: expected one knot per row, found {} columns",
            knots_path.display(),
            one
        );
    }
    if k <= n + 1 {
        bail!(
            "{}: {k} knots for {n} control points in {} (need control points + degree + 1)",
            knots_path.display(),
            path.display()
        );
    }
    let curve = BsplineCurve::from_flat(k - n - 1, knots.data, dim, control.data)
        .with_context(|| format!("{} with {}", path.display(), knots_path.display()))?;
    Ok(AnyModel::BsplineCurve(BsplineCurveModel {
        curve,
        parameters: None,
    }))
}

/// One number as JSON (shortest representation that reads back to the same f64).
pub fn json_number(x: f64) -> String {
    serde_json::to_string(&x).unwrap_or_else(|_| "null".into())
}

/// The model as JSON text, one control point per line (readable and diff-friendly), with an
/// optional `"error"` object for approximate reductions. Ends with a newline.
pub fn to_json(model: &BezierModel, error: Option<&ErrorReport>) -> Result<String> {
    Ok(geomkit_model::to_json(&model.to_file(error.copied()))?)
}

/// Writes a B-spline curve as JSON (one control point per line), with the parameters of its
/// reference points if given.
pub fn write_bspline_curve_json(
    w: &mut dyn Write,
    curve: &BsplineCurve,
    parameters: Option<&[f64]>,
) -> io::Result<()> {
    geomkit_model::write_json(&BsplineCurveModel::file_of(curve, parameters), w)
}

/// Writes a B-spline surface as JSON (one net row per line), with the grid parameters of its
/// reference points if given.
pub fn write_bspline_surface_json(
    w: &mut dyn Write,
    surface: &BsplineSurface,
    parameters: Option<(&[f64], &[f64])>,
) -> io::Result<()> {
    geomkit_model::write_json(&BsplineSurfaceModel::file_of(surface, parameters), w)
}

/// [`write_bspline_curve_json`] into a string.
pub fn bspline_curve_json(curve: &BsplineCurve, parameters: Option<&[f64]>) -> Result<String> {
    Ok(geomkit_model::to_json(&BsplineCurveModel::file_of(
        curve, parameters,
    ))?)
}

/// [`write_bspline_surface_json`] into a string.
pub fn bspline_surface_json(
    surface: &BsplineSurface,
    parameters: Option<(&[f64], &[f64])>,
) -> Result<String> {
    Ok(geomkit_model::to_json(&BsplineSurfaceModel::file_of(
        surface, parameters,
    ))?)
}
