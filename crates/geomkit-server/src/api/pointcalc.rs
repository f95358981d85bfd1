//! `POST /api/pointcalc/*`: point-calculus models (spec/point-calculus): a k-factor model
//! through a full grid of experimental points, the shares of the source points at a point,
//! and the certified optimum (branch and bound on Bernstein bounds).

use super::{check_points, model_json, read_model};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::{AppState, Limits};
use axum::extract::State;
use axum::Json;
use geomkit::pointcalc::{
    optimize, Factor, Goal, Hypersurface, Nodes, OptimizeOptions, PointOptions,
};
use geomkit_model::{AnyModel, PointcalcModel};
use serde::Deserialize;
use serde_json::{json, Value};

/// One factor of a fit: its name and levels (the nodes).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FactorRequest {
    /// Name (a variable of the formula).
    pub name: String,
    /// Levels, strictly increasing.
    pub nodes: Vec<f64>,
}

/// `{"factors": [...], "response": ["y"], "values": [...]}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitRequest {
    /// The factors, slowest first.
    pub factors: Vec<FactorRequest>,
    /// Names of the responses (default `["y"]`).
    #[serde(default)]
    pub response: Option<Vec<String>>,
    /// The responses of every grid cell, row-major over the factors (factor 0 slowest),
    /// one number per response.
    pub values: Vec<f64>,
    /// Refuse (instead of warning about) node sets with a large Lebesgue constant.
    #[serde(default)]
    pub strict: bool,
}

/// `POST /api/pointcalc/fit` → `{"model", "what", "warnings"}`.
pub async fn fit(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<FitRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let response = req.response.unwrap_or_else(|| vec!["y".to_string()]);
        let dim = response.len();
        if dim == 0 {
            return Err(
                ApiError::bad_request("response must name at least one response")
                    .with("path", "response"),
            );
        }
        check_points("values", req.values.len() / dim, &limits)?;
        let mut cells = 1usize;
        let mut factors = Vec::with_capacity(req.factors.len());
        for (i, f) in req.factors.into_iter().enumerate() {
            cells = cells.saturating_mul(f.nodes.len());
            check_points("factors", cells, &limits)?;
            let nodes = Nodes::new(f.nodes).map_err(|e| {
                ApiError::geometry(&format!("factors[{i}].nodes"), e)
                    .with("path", format!("factors[{i}].nodes"))
            })?;
            factors.push(Factor::new(f.name, nodes));
        }
        let options = PointOptions::default().with_strict(req.strict);
        let model = Hypersurface::new(factors, dim, req.values, &options)
            .map_err(|e| ApiError::geometry("fit", e))?;
        let warnings: Vec<String> = model.warnings().iter().map(|w| w.to_string()).collect();
        let m = PointcalcModel { model, response };
        let what = AnyModel::Pointcalc(m.clone()).describe();
        Ok(Json(json!({
            "model": model_json(&m.to_file())?,
            "what": what,
            "warnings": warnings,
        })))
    })
    .await
}

pub(crate) fn pointcalc_of(value: &Value, limits: &Limits) -> ApiResult<PointcalcModel> {
    match read_model("model", value, limits)? {
        AnyModel::Pointcalc(m) => Ok(m),
        other => Err(ApiError::unprocessable(format!(
            "model is a {}; this endpoint takes a pointcalc-model",
            other.describe()
        ))
        .with("path", "model")),
    }
}

/// `{"model": M, "at": [x1, ..., xk]}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SharesRequest {
    /// A `pointcalc-model` file.
    pub model: Value,
    /// The point: one value per factor.
    pub at: Vec<f64>,
}

/// `POST /api/pointcalc/shares` → `{"value": [..], "shares": [{"levels": [..], "share"}],
/// "sum"}`: the share of every source point in the model's value at `at` (they sum to 1).
pub async fn shares(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<SharesRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let m = pointcalc_of(&req.model, &state.config.limits)?;
        let geometry = |e| ApiError::geometry("at", e).with("path", "at");
        let shares = m.model.shares(&req.at).map_err(geometry)?;
        let value = m.model.eval(&req.at).map_err(geometry)?;
        let items: Vec<Value> = shares
            .iter()
            .enumerate()
            .map(|(i, s)| json!({"levels": m.model.cell_levels(i), "share": s}))
            .collect();
        Ok(Json(json!({
            "value": value,
            "response": m.response,
            "shares": items,
            "sum": shares.iter().sum::<f64>(),
        })))
    })
    .await
}

/// `{"model": M, "goal": "max" | "min", "tolerance": T}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OptimumRequest {
    /// A `pointcalc-model` file of one response.
    pub model: Value,
    /// "max" (default) or "min".
    #[serde(default)]
    pub goal: Option<String>,
    /// Relative tolerance of the certificate (default 1e-9).
    #[serde(default)]
    pub tolerance: Option<f64>,
}

/// `POST /api/pointcalc/optimum` → `{"at", "value", "bound", "gap", "certified", "boxes"}`:
/// the best point of the model's box; `bound` is certified (no point does better).
pub async fn optimum(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<OptimumRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let m = pointcalc_of(&req.model, &state.config.limits)?;
        let goal = match req.goal.as_deref().unwrap_or("max") {
            "max" => Goal::Max,
            "min" => Goal::Min,
            other => {
                return Err(ApiError::bad_request(format!(
                    "goal must be \"max\" or \"min\" (got \"{other}\")"
                ))
                .with("path", "goal"))
            }
        };
        let mut options = OptimizeOptions::default();
        if let Some(t) = req.tolerance {
            if !(t.is_finite() && t > 0.0) {
                return Err(
                    ApiError::bad_request("tolerance must be a finite number > 0")
                        .with("path", "tolerance"),
                );
            }
            options = options.with_tolerance(t);
        }
        let best =
            optimize(&m.model, goal, &options).map_err(|e| ApiError::geometry("optimum", e))?;
        Ok(Json(json!({
            "at": best.at,
            "value": best.value,
            "bound": best.bound,
            "gap": best.gap,
            "certified": best.certified,
            "boxes": best.boxes,
        })))
    })
    .await
}
