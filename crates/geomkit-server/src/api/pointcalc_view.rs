//! `POST /api/pointcalc/grid`: what the editor draws of a point-calculus model
//! (spec/point-calculus): the model along one factor (a curve) or over two (a grid of values
//! with contour lines), the other factors fixed at a point — the whole model for 1 or 2
//! factors, slices through a point for more.

use super::finite;
use super::pointcalc::pointcalc_of;
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::Json;
use geomkit_plot::figures::contour_segments;
use serde::Deserialize;
use serde_json::{json, Value};

/// `{"model", "at"?, "free"?, "samples"?, "contours"?, "response"?}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridRequest {
    /// A `pointcalc-model` file.
    pub model: Value,
    /// The point the slice passes through: one value per factor (default: the centre of
    /// the box of the nodes). The free factors' values are ignored.
    #[serde(default)]
    pub at: Option<Vec<f64>>,
    /// The factors that vary: one (a curve) or two (a map); default the first one or two.
    #[serde(default)]
    pub free: Option<Vec<usize>>,
    /// Samples per free factor over its nodes' range (default 201 for a curve, 41 for a
    /// map).
    #[serde(default)]
    pub samples: Option<usize>,
    /// Contour lines of a map (default 10; 0: none).
    #[serde(default)]
    pub contours: Option<usize>,
    /// Which response (default 0).
    #[serde(default)]
    pub response: Option<usize>,
}

/// `POST /api/pointcalc/grid` → `{"free", "at", "axes", "values", "range", "contours"}`:
/// `axes[a]` the samples of free factor `a`; `values` the model's response at them (a list
/// for one free factor, rows over `axes[0]` of columns over `axes[1]` for two); `range`
/// `[min, max]` of the values; `contours` (two free factors) `[{"level", "segments":
/// [[[x0, y0], [x1, y1]], ...]}]` by marching squares on the grid, in factor coordinates.
pub async fn grid(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<GridRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let m = pointcalc_of(&req.model, &limits)?;
        let model = &m.model;
        let k = model.k();
        let domain = model.domain();
        let free = req
            .free
            .unwrap_or_else(|| if k == 1 { vec![0] } else { vec![0, 1] });
        let bad_free = match free.as_slice() {
            [a] => *a >= k,
            [a, b] => *a >= k || *b >= k || a == b,
            _ => true,
        };
        if bad_free {
            return Err(ApiError::bad_request(format!(
                "free must be one or two different factor indices below {k} (got {free:?})"
            ))
            .with("path", "free"));
        }
        let mut at: Vec<f64> = match req.at {
            Some(at) => at,
            None => domain.iter().map(|(a, b)| (a + b) / 2.0).collect(),
        };
        if at.len() != k {
            return Err(ApiError::bad_request(format!(
                "at has {} values; the model has {k} factors",
                at.len()
            ))
            .with("path", "at"));
        }
        if let Some(i) = at.iter().position(|x| !x.is_finite()) {
            return Err(
                ApiError::bad_request(format!("at[{i}] is not a finite number"))
                    .with("path", format!("at[{i}]")),
            );
        }
        let response = req.response.unwrap_or(0);
        if response >= model.dim() {
            return Err(ApiError::bad_request(format!(
                "response {response}: the model has {} responses",
                model.dim()
            ))
            .with("path", "response"));
        }
        let (default, most) = if free.len() == 1 {
            (201, limits.samples)
        } else {
            (41, limits.samples.isqrt())
        };
        let n = req.samples.unwrap_or(default);
        if !(2..=most).contains(&n) {
            return Err(ApiError::bad_request(format!(
                "samples must be between 2 and {most} (got {n})"
            ))
            .with("path", "samples"));
        }
        let axes: Vec<Vec<f64>> = free
            .iter()
            .map(|&f| {
                let (a, b) = domain[f];
                (0..n)
                    .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
                    .collect()
            })
            .collect();
        // Every point of the slice, evaluated in one batch.
        let count = axes.iter().map(Vec::len).product::<usize>();
        let mut xs = Vec::with_capacity(count * k);
        for idx in 0..count {
            let (i, j) = (idx / n, idx % n);
            if free.len() == 1 {
                at[free[0]] = axes[0][idx];
            } else {
                at[free[0]] = axes[0][i];
                at[free[1]] = axes[1][j];
            }
            xs.extend_from_slice(&at);
        }
        let dim = model.dim();
        let mut out = vec![0.0; count * dim];
        model
            .eval_many(&xs, &mut out)
            .map_err(|e| ApiError::geometry("grid", e))?;
        let z: Vec<f64> = out.iter().skip(response).step_by(dim).copied().collect();
        finite("the model's values", &z)?;
        let lo = z.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = z.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        for (f, x) in free.iter().zip(&axes) {
            at[*f] = x[0];
        }
        if free.len() == 1 {
            return Ok(Json(json!({
                "free": free, "at": at, "axes": axes, "values": z, "range": [lo, hi],
                "contours": [],
            })));
        }
        let levels = req.contours.unwrap_or(10).min(100);
        let contours: Vec<Value> = (1..=levels)
            .filter(|_| hi > lo)
            .map(|l| {
                let h = lo + (hi - lo) * l as f64 / (levels + 1) as f64;
                json!({"level": h, "segments": contour_segments(&z, &axes[0], &axes[1], h)})
            })
            .collect();
        let rows: Vec<&[f64]> = z.chunks_exact(n).collect();
        Ok(Json(json!({
            "free": free, "at": at, "axes": axes, "values": rows, "range": [lo, hi],
            "contours": contours,
        })))
    })
    .await
}
