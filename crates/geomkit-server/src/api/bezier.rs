//! `POST /api/bezier/*`: the change of order of spec/bezier-order.md on Bézier curves and
//! surfaces — the degree report (real degree and defect), elevation, exact reduction (or the
//! library's refusal with the real degree), the best approximation of lower degree with its
//! L2 error, L∞ bound and error band, and the paper's hand edits (insert / remove a vertex).
//!
//! Rational (weighted) curves take the degree report, elevation and exact reduction;
//! approximate reduction and edits are for polynomial curves.

use super::{check_degree, check_points, finite, model_json, read_model, rows};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::{AppState, Limits};
use axum::extract::State;
use axum::Json;
use geomkit::bezier::{ApproxOptions, BezierCurve, DegreeReport, ReductionNorm};
use geomkit::geom::{linspace, Curve};
use geomkit_model::{AnyModel, BezierModel};
use serde::Deserialize;
use serde_json::{json, Value};

/// A target degree: `n` for curves, `[n, m]` for surfaces.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(untagged)]
pub enum Degrees {
    /// One degree (curves).
    One(usize),
    /// Degrees in u and v (surfaces).
    Two([usize; 2]),
}

/// `{"model": M, "to": n | [n, m], "tolerance": T}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChangeRequest {
    /// A `bezier_curve` or `bezier_surface` file.
    pub model: Value,
    /// Target degree (not for `degree`).
    #[serde(default)]
    pub to: Option<Degrees>,
    /// Relative tolerance of the real-degree test (default 1e-12).
    #[serde(default)]
    pub tolerance: Option<f64>,
}

fn bezier_of(value: &Value, limits: &Limits) -> ApiResult<BezierModel> {
    match read_model("model", value, limits)? {
        AnyModel::Bezier(b) => Ok(b),
        other => Err(ApiError::unprocessable(format!(
            "model is a {}; this endpoint takes a bezier_curve or bezier_surface",
            other.describe()
        ))
        .with("path", "model")),
    }
}

fn tolerance(t: Option<f64>) -> ApiResult<Option<f64>> {
    match t {
        Some(t) if !(t.is_finite() && t > 0.0 && t < 1.0) => Err(ApiError::bad_request(format!(
            "tolerance must be a number in (0, 1) (got {t})"
        ))
        .with("path", "tolerance")),
        t => Ok(t),
    }
}

fn report_json(r: &DegreeReport) -> Value {
    json!({
        "degree": r.degree,
        "real_degree": r.real_degree,
        "defect": r.defect,
        "residual": r.residual,
        "rejected_residual": r.rejected_residual,
        "tolerance": r.tolerance,
    })
}

/// The degree report of any Bézier model (per direction `u`, `v` for surfaces).
fn degree_of(model: &BezierModel, tol: Option<f64>) -> ApiResult<Value> {
    let geometry = |e| ApiError::geometry("model", e);
    Ok(match model {
        BezierModel::Curve(c) => report_json(&c.degree_report(tol).map_err(geometry)?),
        BezierModel::Rational(r) => {
            let mut v = report_json(&r.degree_report(tol).map_err(geometry)?);
            v["homogeneous"] = json!(true);
            v
        }
        BezierModel::Surface(s) => {
            let r = s.degree_report(tol).map_err(geometry)?;
            json!({"u": report_json(&r.u), "v": report_json(&r.v)})
        }
        BezierModel::RationalSurface(s) => {
            let r = s.degree_report(tol).map_err(geometry)?;
            json!({"u": report_json(&r.u), "v": report_json(&r.v), "homogeneous": true})
        }
    })
}

/// `POST /api/bezier/degree {"model": M, "tolerance": T}` → `{"degree", "real_degree",
/// "defect", "residual", "rejected_residual", "tolerance"}` (per direction for surfaces).
pub async fn degree(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ChangeRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let model = bezier_of(&req.model, &state.config.limits)?;
        degree_of(&model, tolerance(req.tolerance)?).map(Json)
    })
    .await
}

fn target(to: Option<Degrees>, model: &BezierModel, limits: &Limits) -> ApiResult<Degrees> {
    let Some(to) = to else {
        return Err(ApiError::bad_request("missing \"to\": the target degree").with("path", "to"));
    };
    let highest = match to {
        Degrees::One(n) => n,
        Degrees::Two([n, m]) => n.max(m),
    };
    check_degree("to", highest, limits)?;
    match (model, to) {
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::One(n)) => {
            Err(ApiError::bad_request(format!(
                "a surface needs a degree per direction: \"to\": [n, m] (got {n})"
            ))
            .with("path", "to"))
        }
        (BezierModel::Curve(_) | BezierModel::Rational(_), Degrees::Two([n, m])) => {
            Err(ApiError::bad_request(format!(
                "a curve takes one degree: \"to\": n (got [{n}, {m}])"
            ))
            .with("path", "to"))
        }
        _ => Ok(to),
    }
}

/// The answer of a change: the new model, its description and degree report.
fn changed(new: BezierModel, tol: Option<f64>) -> ApiResult<Json<Value>> {
    let report = degree_of(&new, tol)?;
    Ok(Json(json!({
        "model": model_json(&new.to_file(None))?,
        "what": new.describe(),
        "degree": report,
    })))
}

/// `POST /api/bezier/elevate {"model": M, "to": n | [n, m]}` → `{"model", "what",
/// "degree"}`: the same curve or surface of the higher degree (closed form (8)).
pub async fn elevate(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ChangeRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = bezier_of(&req.model, &limits)?;
        let to = target(req.to, &model, &limits)?;
        let geometry = |e| ApiError::geometry("elevate", e);
        let new = match (&model, to) {
            (BezierModel::Curve(c), Degrees::One(n)) => {
                BezierModel::Curve(c.elevate_degree(n).map_err(geometry)?)
            }
            (BezierModel::Rational(r), Degrees::One(n)) => {
                BezierModel::Rational(r.elevate_degree(n).map_err(geometry)?)
            }
            (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::Two([n, m])) => {
                check_points("to", (n + 1) * (m + 1), &limits)?;
                change_surface(&model, [n, m], true, None)?.map_err(geometry)?
            }
            _ => unreachable!("checked by target()"),
        };
        changed(new, None)
    })
    .await
}

/// Formula (14) on a (rational) surface, elevating (`up`) or reducing both degrees; a 422
/// when a target goes the other way. The library's error, if any, is for the caller to map.
fn change_surface(
    model: &BezierModel,
    [n, m]: [usize; 2],
    up: bool,
    tol: Option<f64>,
) -> ApiResult<Result<BezierModel, geomkit::Error>> {
    let (a, b) = model.surface_degrees().unwrap_or((0, 0));
    let wrong_way = if up { n < a || m < b } else { n > a || m > b };
    if wrong_way {
        let (verb, noun, cmp) = if up {
            ("elevate", "elevation", ">=")
        } else {
            ("reduce", "reduction", "<=")
        };
        return Err(ApiError::unprocessable(format!(
            "cannot {verb} degrees ({a}, {b}) to ({n}, {m}): {noun} needs degrees {cmp} the \
             current ones"
        )));
    }
    Ok(model
        .change_surface_degree(n, m, tol)
        .expect("called for surfaces only"))
}

/// The library's refusal of an exact reduction as a 422 naming the real degree.
fn refusal(err: geomkit::Error) -> ApiError {
    match err {
        geomkit::Error::DegreeDefectTooSmall {
            real_degree,
            requested,
            defect,
        } => ApiError::unprocessable(format!(
            "cannot reduce exactly to degree {requested}: the real degree is {real_degree} \
             (degree defect {defect}); the best approximation of degree {requested} is \
             /api/bezier/approximate"
        ))
        .with("reason", "real_degree")
        .with("real_degree", real_degree)
        .with("defect", defect)
        .with("requested", requested),
        geomkit::Error::SurfaceDefectTooSmall {
            direction,
            real_degree,
            requested,
            defect,
        } => ApiError::unprocessable(format!(
            "cannot reduce exactly to degree {requested} in {direction}: the real \
             {direction}-degree is {real_degree} (degree defect {defect}); the best \
             approximation is /api/surface/approximate"
        ))
        .with("reason", "real_degree")
        .with("direction", direction)
        .with("real_degree", real_degree)
        .with("defect", defect)
        .with("requested", requested),
        other => ApiError::geometry("reduce", other),
    }
}

/// `POST /api/bezier/reduce {"model": M, "to": n | [n, m], "tolerance": T}`: the exact
/// reduction, possible down to the real degree; below it a 422 with `real_degree`,
/// `defect` and `requested`.
pub async fn reduce(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ChangeRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = bezier_of(&req.model, &limits)?;
        let to = target(req.to, &model, &limits)?;
        let tol = tolerance(req.tolerance)?;
        let new = match (&model, to) {
            (BezierModel::Curve(c), Degrees::One(n)) => {
                BezierModel::Curve(c.reduce_degree(n, tol).map_err(refusal)?)
            }
            (BezierModel::Rational(r), Degrees::One(n)) => {
                BezierModel::Rational(r.reduce_degree(n, tol).map_err(refusal)?)
            }
            (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::Two([n, m])) => {
                change_surface(&model, [n, m], false, tol)?.map_err(refusal)?
            }
            _ => unreachable!("checked by target()"),
        };
        changed(new, tol)
    })
    .await
}

/// `{"model": M, "to": n, "norm": "l2" | "chebyshev", "continuity": [a, b], "samples": K}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ApproxRequest {
    /// A polynomial `bezier_curve`.
    pub model: Value,
    /// The lower degree.
    pub to: usize,
    /// The norm minimized (default l2).
    #[serde(default)]
    pub norm: Option<String>,
    /// C^a at t = 0 and C^b at t = 1 (`null`: free).
    #[serde(default)]
    pub continuity: Option<[Option<usize>; 2]>,
    /// Samples of the error band (default 200).
    #[serde(default)]
    pub samples: Option<usize>,
}

fn polynomial_curve(value: &Value, limits: &Limits, what: &str) -> ApiResult<BezierCurve> {
    match bezier_of(value, limits)? {
        BezierModel::Curve(c) => Ok(c),
        other => Err(ApiError::unprocessable(format!(
            "model is a {}; {what} is for polynomial Bézier curves",
            other.describe()
        ))
        .with("path", "model")),
    }
}

/// `POST /api/bezier/approximate`: the best approximation of degree `to` (L2, or the
/// Chebyshev-weighted near-minimax), its exact L2 error, a guaranteed L∞ bound (with the
/// largest distance actually found and where), and the error band: samples of both curves,
/// their distance and, in 2-D, the reduced curve offset by ± the bound along its normal
/// (the original lies inside).
pub async fn approximate(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ApproxRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let curve = polynomial_curve(&req.model, &limits, "approximate reduction")?;
        if req.to >= curve.degree() {
            return Err(ApiError::unprocessable(format!(
                "approximate reduction goes to a lower degree: to = {} but the curve has \
                 degree {}",
                req.to,
                curve.degree()
            ))
            .with("path", "to"));
        }
        let norm = match req.norm.as_deref().unwrap_or("l2") {
            "l2" => ReductionNorm::L2,
            "chebyshev" => ReductionNorm::Chebyshev,
            other => {
                return Err(ApiError::bad_request(format!(
                    "norm must be \"l2\" or \"chebyshev\" (got \"{other}\")"
                ))
                .with("path", "norm"))
            }
        };
        let [start, end] = req.continuity.unwrap_or([None, None]);
        let options = ApproxOptions::default()
            .with_continuity(start, end)
            .with_norm(norm);
        let r = curve
            .reduce_degree_approx(req.to, &options)
            .map_err(|e| ApiError::geometry("approximate", e))?;
        let k = req.samples.unwrap_or(200);
        if !(2..=limits.samples).contains(&k) {
            return Err(ApiError::bad_request(format!(
                "samples must be between 2 and {} (got {k})",
                limits.samples
            ))
            .with("path", "samples"));
        }
        let band = error_band(&curve, &r.curve, r.linf.upper_bound, k)?;
        let new = BezierModel::Curve(r.curve);
        Ok(Json(json!({
            "model": model_json(&new.to_file(Some(geomkit_model::schema::ReductionError {
                l2: r.l2_error,
                linf_bound: r.linf.upper_bound,
            })))?,
            "what": new.describe(),
            "l2_error": r.l2_error,
            "linf_bound": r.linf.upper_bound,
            "linf_found": r.linf.max_found,
            "linf_at": r.linf.at,
            "band": band,
        })))
    })
    .await
}

/// Samples of the original and the reduced curve at `k` parameters, their distance, and in
/// 2-D the reduced curve offset by ± `bound` along its unit normal.
fn error_band(
    original: &BezierCurve,
    reduced: &BezierCurve,
    bound: f64,
    k: usize,
) -> ApiResult<Value> {
    let d = original.dim();
    let ts = linspace(0.0, 1.0, k);
    let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
    let (mut orig, mut red, mut dist) = (Vec::new(), Vec::new(), Vec::new());
    let (mut upper, mut lower) = (Vec::new(), Vec::new());
    let hodograph = reduced.derivative();
    let mut tangent = vec![0.0; d];
    for &t in &ts {
        original.eval_into(t, &mut a);
        reduced.eval_into(t, &mut b);
        dist.push(
            a.iter()
                .zip(&b)
                .map(|(x, y)| (x - y).powi(2))
                .sum::<f64>()
                .sqrt(),
        );
        if d == 2 {
            hodograph.eval_into(t, &mut tangent);
            let len = tangent[0].hypot(tangent[1]);
            let (nx, ny) = if len > 0.0 {
                (-tangent[1] / len, tangent[0] / len)
            } else {
                (0.0, 0.0)
            };
            upper.push(vec![b[0] + bound * nx, b[1] + bound * ny]);
            lower.push(vec![b[0] - bound * nx, b[1] - bound * ny]);
        }
        orig.extend_from_slice(&a);
        red.extend_from_slice(&b);
    }
    finite("the error band", &orig)?;
    finite("the error band", &red)?;
    Ok(json!({
        "t": ts,
        "original": rows(&orig, d),
        "reduced": rows(&red, d),
        "distance": dist,
        "upper": if d == 2 { json!(upper) } else { Value::Null },
        "lower": if d == 2 { json!(lower) } else { Value::Null },
    }))
}

/// `{"model": M, "insert": {"index": i, "point": [..]}}` or `{"model": M, "remove": i}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EditRequest {
    /// A polynomial `bezier_curve`.
    pub model: Value,
    /// Insert a control point at this index.
    #[serde(default)]
    pub insert: Option<Insert>,
    /// Remove the control point of this index.
    #[serde(default)]
    pub remove: Option<usize>,
}

/// A control point to insert.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Insert {
    /// Its index in the new polygon (0..=n+1).
    pub index: usize,
    /// The point.
    pub point: Vec<f64>,
}

/// `POST /api/bezier/edit`: the paper's hand edits (§3): a vertex inserted or removed (the
/// degree changes by one, and so does the shape) with how far the curve moved:
/// `{"model", "what", "index", "deviation": {"max_found", "at", "upper_bound"}, "degree"}`.
pub async fn edit(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<EditRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let curve = polynomial_curve(&req.model, &limits, "editing")?;
        let geometry = |e| ApiError::geometry("edit", e);
        let result = match (&req.insert, req.remove) {
            (Some(ins), None) => {
                check_degree("insert", curve.degree() + 1, &limits)?;
                if ins.point.iter().any(|x| !x.is_finite()) {
                    return Err(ApiError::bad_request("insert.point must be finite numbers")
                        .with("path", "insert.point"));
                }
                curve
                    .insert_vertex(ins.index, &ins.point)
                    .map_err(geometry)?
            }
            (None, Some(i)) => curve.remove_vertex(i).map_err(geometry)?,
            _ => {
                return Err(ApiError::bad_request(
                    "give one of \"insert\": {\"index\", \"point\"} or \"remove\": index",
                ))
            }
        };
        let new = BezierModel::Curve(result.curve);
        let report = degree_of(&new, None)?;
        Ok(Json(json!({
            "model": model_json(&new.to_file(None))?,
            "what": new.describe(),
            "index": result.index,
            "deviation": {
                "max_found": result.deviation.max_found,
                "at": result.deviation.at,
                "upper_bound": result.deviation.upper_bound,
            },
            "degree": report,
        })))
    })
    .await
}
