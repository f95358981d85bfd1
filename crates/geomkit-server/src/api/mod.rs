//! The JSON API (documented for scripts in `docs/serve-api.md`). Every endpoint takes a JSON
//! body (POST) and answers JSON, except the exports (the file's bytes) and the file routes.
//! Handlers are thin: parse the request, call the model crate and the library on the
//! blocking pool, answer.
//!
//! | endpoint | what |
//! |---|---|
//! | `GET /api/version` | the version, the limits, the formula syntaxes |
//! | `POST /api/describe` | what a model file is |
//! | `POST /api/samples` | points to draw: curve polyline with parameters, surface grid, control polygon / net, reference points |
//! | `POST /api/bezier/degree` | formal and real degree, defect, residuals |
//! | `POST /api/bezier/elevate` | degree elevation (exact) |
//! | `POST /api/bezier/reduce` | exact reduction, or 422 with the library's reason |
//! | `POST /api/bezier/approximate` | best approximation of lower degree, L2 error, L∞ bound, error band |
//! | `POST /api/bezier/edit` | insert or remove a control point, with how far the curve moved |
//! | `POST /api/bspline/interpolate` | a B-spline through points, its samples and curvature comb |
//! | `POST /api/formula` | a model's single formula in one of 11 syntaxes + continuity report |
//! | `POST /api/pointcalc/fit`, `/shares`, `/optimum` | point-calculus models |
//! | `POST /api/pointcalc/grid` | a point-calculus model along one factor or over two (contours) |
//! | `POST /api/export` | SVG, PNG, STL, GLB, OBJ or formula text of a model |
//! | `POST /api/surface/mesh`, `/edit`, `/approximate`, `/heights` | the 3-D view: shaded meshes with curvature or error colouring, row/column edits, best L2 approximation of surfaces, height fields ([`surface`]) |
//! | `POST /api/body/view` | a body or composite surface in 3-D: its mesh and its seams, each with its smoothness (C^k, smooth, discontinuous) as a polyline on the surface ([`body`]) |
//! | `GET /api/files`, `GET`/`PUT /api/files/{name}` | model files in the `--dir` folder |

pub mod bezier;
pub mod body;
pub mod bspline;
pub mod export;
pub mod files;
pub mod formula;
pub mod model;
pub mod pointcalc;
pub mod pointcalc_view;
pub mod surface;

use crate::error::{ApiError, ApiResult};
use crate::{AppState, Limits};
use axum::routing::{get, post};
use axum::Router;
use geomkit_model::{AnyModel, ModelFile};
use serde_json::Value;

/// The API's routes.
pub fn routes() -> Router<AppState> {
    Router::new()
        .route("/api/version", get(model::version))
        .route("/api/describe", post(model::describe))
        .route("/api/samples", post(model::samples))
        .route("/api/bezier/degree", post(bezier::degree))
        .route("/api/bezier/elevate", post(bezier::elevate))
        .route("/api/bezier/reduce", post(bezier::reduce))
        .route("/api/bezier/approximate", post(bezier::approximate))
        .route("/api/bezier/edit", post(bezier::edit))
        .route("/api/bspline/interpolate", post(bspline::interpolate))
        .route("/api/formula", post(formula::formula))
        .route("/api/pointcalc/fit", post(pointcalc::fit))
        .route("/api/pointcalc/shares", post(pointcalc::shares))
        .route("/api/pointcalc/optimum", post(pointcalc::optimum))
        .route("/api/pointcalc/grid", post(pointcalc_view::grid))
        .route("/api/export", post(export::export))
        .route("/api/surface/mesh", post(surface::mesh_handler))
        .route("/api/surface/edit", post(surface::edit))
        .route("/api/surface/approximate", post(surface::approximate))
        .route("/api/surface/heights", post(surface::heights))
        .route("/api/body/view", post(body::view_handler))
        .route("/api/files", get(files::list))
        .route("/api/files/{name}", get(files::open).put(files::save))
}

/// A model file of a request (the JSON of `docs/formats.md`), read by the model crate and
/// checked against the limits. `field` names it in errors ("model").
pub fn read_model(field: &str, value: &Value, limits: &Limits) -> ApiResult<AnyModel> {
    let file = read_file(field, value)?;
    let model = AnyModel::from_file(file).map_err(|e| ApiError::model(field, e))?;
    check_size(field, &model, limits)?;
    Ok(model)
}

/// The schema of a model file, without building its geometry.
pub fn read_file(field: &str, value: &Value) -> ApiResult<ModelFile> {
    if !value.is_object() {
        return Err(ApiError::bad_request(format!(
            "{field} must be a model file: a JSON object with a \"type\" (see docs/formats.md)"
        ))
        .with("path", field));
    }
    // The model crate reads text (its errors carry JSON paths); a Value prints compactly.
    let text = value.to_string();
    geomkit_model::parse_file(&text).map_err(|e| ApiError::model(field, e))
}

/// A model as the JSON of its file, or a 422 for a result that overflowed.
pub fn model_json(file: &ModelFile) -> ApiResult<Value> {
    let text = geomkit_model::to_json(file).map_err(|e| {
        ApiError::unprocessable(format!("the result cannot be written as a model file: {e}"))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| ApiError::unprocessable(format!("the result is not valid JSON: {e}")))
}

/// Refuses models over the limits (413).
pub fn check_size(field: &str, model: &AnyModel, limits: &Limits) -> ApiResult<()> {
    use geomkit_model::BezierModel;
    let (points, degree) = match model {
        AnyModel::Bezier(BezierModel::Curve(c)) => (c.degree() + 1, c.degree()),
        AnyModel::Bezier(BezierModel::Rational(c)) => (c.degree() + 1, c.degree()),
        AnyModel::Bezier(b @ (BezierModel::Surface(_) | BezierModel::RationalSurface(_))) => {
            let (n, m) = b.surface_degrees().unwrap_or((0, 0));
            ((n + 1) * (m + 1), n.max(m))
        }
        AnyModel::BsplineCurve(m) => (m.curve.n_control(), 0),
        AnyModel::BsplineSurface(m) => {
            let (a, b) = m.surface.net_size();
            (a * b, 0)
        }
        AnyModel::Pointcalc(m) => (m.model.values().len() / m.model.dim().max(1), 0),
        AnyModel::CurveSamples(c) => (c.len(), 0),
        AnyModel::SurfaceSamples(s) => {
            let (a, b) = s.grid_size();
            (a * b, 0)
        }
        _ => (0, 0),
    };
    check_points(field, points, limits)?;
    check_degree(field, degree, limits)
}

/// 413 when `count` points exceed the limit.
pub fn check_points(field: &str, count: usize, limits: &Limits) -> ApiResult<()> {
    if count > limits.points {
        return Err(ApiError::too_large(format!(
            "{field} has {count} points: the server takes at most {} (a limit of geomkit serve)",
            limits.points
        ))
        .with("path", field));
    }
    Ok(())
}

/// 413 when a Bézier degree exceeds the limit.
pub fn check_degree(field: &str, degree: usize, limits: &Limits) -> ApiResult<()> {
    if degree > limits.bezier_degree {
        return Err(ApiError::too_large(format!(
            "{field}: degree {degree} is over the server's limit of {} for Bézier curves and \
             surfaces",
            limits.bezier_degree
        ))
        .with("path", field));
    }
    Ok(())
}

/// Rows of `dim` numbers as JSON arrays.
pub fn rows(flat: &[f64], dim: usize) -> Vec<Vec<f64>> {
    flat.chunks_exact(dim.max(1)).map(<[f64]>::to_vec).collect()
}

/// Checks that every number of a result is finite (JSON has no NaN): 422 otherwise.
pub fn finite(what: &str, values: &[f64]) -> ApiResult<()> {
    match values.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ApiError::unprocessable(format!(
            "{what}: value {i} is not finite (the computation overflowed f64)"
        ))),
    }
}

/// A body of one model file: `{"model": M}`.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelBody {
    /// The model file.
    pub model: Value,
}
