//! `GET /api/version`, `POST /api/describe`, `POST /api/samples`: any model file, described
//! and sampled for drawing through the model crate's [`Loaded`] shapes.

use super::{finite, read_model, rows};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::Json;
use geomkit::expr::Format;
use geomkit::geom::{linspace, BatchOptions, Curve};
use geomkit_model::{Loaded, Shape};
use serde::Deserialize;
use serde_json::{json, Value};

/// `GET /api/version`: `{"version", "limits", "formats"}`.
pub async fn version(State(state): State<AppState>) -> Json<Value> {
    let l = state.config.limits;
    Json(json!({
        "name": "geomkit serve",
        "version": env!("CARGO_PKG_VERSION"),
        "limits": {
            "body_bytes": l.body_bytes,
            "points": l.points,
            "bezier_degree": l.bezier_degree,
            "samples": l.samples,
        },
        "formats": Format::ALL.map(Format::name),
        "files": state.config.dir.is_some(),
    }))
}

/// A request that carries one model.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelRequest {
    /// The model file.
    pub model: Value,
    /// Samples of a curve, or per direction of a surface.
    #[serde(default)]
    pub samples: Option<usize>,
}

/// `POST /api/describe {"model": M}` → `{"what": "...", "type": "bezier_curve"}`.
pub async fn describe(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ModelRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = read_model("model", &req.model, &limits)?;
        let kind = req.model.get("type").cloned().unwrap_or(Value::Null);
        Ok(Json(json!({"what": model.describe(), "type": kind})))
    })
    .await
}

/// `POST /api/samples {"model": M, "samples": K}`: the drawing of a model.
pub async fn samples(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ModelRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = read_model("model", &req.model, &limits)?;
        let loaded = Loaded::from_model(model).map_err(|e| ApiError::model("model", e))?;
        sample_loaded(&loaded, req.samples, &limits).map(Json)
    })
    .await
}

/// Samples of a curve: `samples` uniform parameters over its domain, or by default 8 per
/// piece between breaks (at least 200).
pub fn curve_samples(
    curve: &dyn Curve,
    samples: Option<usize>,
    limits: &crate::Limits,
) -> ApiResult<(Vec<f64>, Vec<f64>)> {
    let (a, b) = curve.domain();
    let count = match samples {
        Some(k) => k,
        None => ((curve.breaks().len() + 1) * 8).clamp(200, limits.samples),
    };
    if count < 2 || count > limits.samples {
        return Err(ApiError::bad_request(format!(
            "samples must be between 2 and {} (got {count})",
            limits.samples
        ))
        .with("path", "samples"));
    }
    let ts = linspace(a, b, count);
    let mut out = vec![0.0; count * curve.dim()];
    curve
        .eval_batch(&ts, &mut out, &BatchOptions::default())
        .map_err(|e| ApiError::geometry("samples", e))?;
    finite("the curve's samples", &out)?;
    Ok((ts, out))
}

/// The JSON drawing of a loaded model.
pub fn sample_loaded(
    loaded: &Loaded,
    samples: Option<usize>,
    limits: &crate::Limits,
) -> ApiResult<Value> {
    match &loaded.shape {
        Shape::Curve {
            curve,
            control,
            references,
        } => {
            let d = curve.dim();
            let (ts, out) = curve_samples(curve.as_ref(), samples, limits)?;
            let (control, control_t) = match control {
                Some((pts, t)) => (json!(pts), json!(t)),
                None => (Value::Null, Value::Null),
            };
            let references: Vec<Value> = references
                .iter()
                .map(|(t, p)| json!({"t": t, "point": p}))
                .collect();
            Ok(json!({
                "kind": "curve",
                "what": loaded.what,
                "dim": d,
                "domain": curve.domain(),
                "t": ts,
                "points": rows(&out, d),
                "control": control,
                "control_t": control_t,
                "references": references,
            }))
        }
        Shape::Surface {
            surface,
            net,
            references,
        } => {
            let k = samples.unwrap_or(33);
            let most = (limits.samples as f64).sqrt() as usize;
            if k < 2 || k > most {
                return Err(ApiError::bad_request(format!(
                    "samples of a surface must be between 2 and {most} per direction (got {k})"
                ))
                .with("path", "samples"));
            }
            let ((u0, u1), (v0, v1)) = surface.domain();
            let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, k));
            let d = surface.dim();
            let mut out = vec![0.0; k * k * d];
            surface
                .eval_grid(&us, &vs, &mut out)
                .map_err(|e| ApiError::geometry("samples", e))?;
            finite("the surface's samples", &out)?;
            let grid: Vec<Vec<Vec<f64>>> =
                out.chunks_exact(k * d).map(|row| rows(row, d)).collect();
            let net = net
                .as_ref()
                .map(|(r, c, p)| json!({"rows": r, "cols": c, "points": p}));
            Ok(json!({
                "kind": "surface",
                "what": loaded.what,
                "dim": d,
                "u": us,
                "v": vs,
                "points": grid,
                "net": net,
                "references": references,
            }))
        }
    }
}
