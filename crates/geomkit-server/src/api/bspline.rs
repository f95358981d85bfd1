//! `POST /api/bspline/interpolate`: a cubic B-spline through reference points
//! (spec/bspline-interpolation.md, [`geomkit::bspline::interpolate_curve_flat`]) with the
//! end condition and parametrization of the request, open or closed, answered with the
//! model file, the parameter of each point, samples for drawing and, in 2-D, the curvature
//! comb.

use super::{check_points, finite};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::http::header;
use axum::response::{IntoResponse, Response};
use geomkit::bspline::{
    interpolate_curve_flat, BsplineCurve, EndCondition, InterpolationOptions, Parametrization,
};
use geomkit::geom::{BatchOptions, Curve};
use geomkit_model::{AnyModel, BsplineCurveModel, ModelFile};
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// The request.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterpolateRequest {
    /// Reference points, each of the same dimension.
    pub points: Vec<Vec<f64>>,
    /// End condition: "not-a-knot" (default), "natural", "clamped", "bessel", "repeat",
    /// "outer", "periodic", or an object `{"kind": "clamped", "start": [..], "end": [..]}`,
    /// `{"kind": "outer", "offset": 0.5}`.
    #[serde(default)]
    pub end: Option<Value>,
    /// "uniform", "chord" (default) or "centripetal".
    #[serde(default)]
    pub parametrization: Option<String>,
    /// A closed curve (the periodic condition, C2 across the seam).
    #[serde(default)]
    pub closed: bool,
    /// Samples per knot span for drawing (default 12).
    #[serde(default)]
    pub samples_per_span: Option<usize>,
    /// Curvature comb: teeth per span (default 6; 0: none) and the length of a tooth per
    /// unit of curvature (default: the longest tooth 1/6 of the points' extent).
    #[serde(default)]
    pub comb: Option<CombRequest>,
    /// Only the drawing near one reference point (a drag): samples and comb teeth of the
    /// knot spans between the parameters of points `around - points` and `around + points`,
    /// without the model file. See [`WindowRequest`].
    #[serde(default)]
    pub window: Option<WindowRequest>,
}

/// A drawing window around one reference point: what a page needs to redraw while that
/// point is dragged. A moved point changes a cubic interpolant far from it only by rounding
/// (the interpolation system's inverse decays by a factor of about 2 − √3 ≈ 0.27 per span),
/// so the samples outside the window are the page's previous ones.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindowRequest {
    /// The index of the reference point that moved.
    pub around: usize,
    /// How many reference points on each side the window spans (default 40: 0.27^40 ≈
    /// 1e-23 of the move is left outside).
    #[serde(default)]
    pub points: Option<usize>,
}

/// Options of the curvature comb.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CombRequest {
    /// Teeth per knot span.
    #[serde(default)]
    pub per_span: Option<usize>,
    /// Tooth length per unit of curvature.
    #[serde(default)]
    pub scale: Option<f64>,
}

fn text_field<'a>(v: &'a Value, key: &str) -> Option<&'a str> {
    v.get(key).and_then(Value::as_str)
}

fn vector(v: &Value, key: &str, dim: usize) -> ApiResult<Option<Vec<f64>>> {
    match v.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(x) => {
            let vec: Option<Vec<f64>> = x
                .as_array()
                .map(|a| a.iter().filter_map(Value::as_f64).collect());
            match vec {
                Some(t) if t.len() == dim && t.iter().all(|x| x.is_finite()) => Ok(Some(t)),
                _ => Err(ApiError::bad_request(format!(
                    "end.{key} must be a tangent of {dim} finite numbers"
                ))
                .with("path", format!("end.{key}"))),
            }
        }
    }
}

/// The end condition of a request.
pub fn end_condition(end: Option<&Value>, closed: bool, dim: usize) -> ApiResult<EndCondition> {
    if closed {
        return Ok(EndCondition::Periodic);
    }
    let Some(end) = end else {
        return Ok(EndCondition::NotAKnot);
    };
    let kind = match end {
        Value::String(s) => s.as_str(),
        Value::Object(_) => text_field(end, "kind").unwrap_or(""),
        _ => "",
    };
    Ok(match kind {
        "not-a-knot" => EndCondition::NotAKnot,
        "natural" => EndCondition::Natural,
        "bessel" => EndCondition::Bessel,
        "repeat" => EndCondition::Repeat,
        "periodic" => EndCondition::Periodic,
        "clamped" => EndCondition::Clamped {
            start: vector(end, "start", dim)?,
            end: vector(end, "end", dim)?,
        },
        "outer" => {
            let offset = end.get("offset").and_then(Value::as_f64).unwrap_or(1.0);
            EndCondition::OuterPoints { offset }
        }
        _ => {
            return Err(ApiError::bad_request(
                "end must be one of \"not-a-knot\", \"natural\", \"clamped\", \"bessel\", \
                 \"repeat\", \"outer\", \"periodic\" (or {\"kind\": ...} with its options)",
            )
            .with("path", "end"))
        }
    })
}

/// The parametrization of a request.
pub fn parametrization(p: Option<&str>) -> ApiResult<Parametrization> {
    Ok(match p.unwrap_or("chord") {
        "uniform" => Parametrization::Uniform,
        "chord" => Parametrization::ChordLength,
        "centripetal" => Parametrization::Centripetal,
        other => {
            return Err(ApiError::bad_request(format!(
                "parametrization must be \"uniform\", \"chord\" or \"centripetal\" (got \
                 \"{other}\")"
            ))
            .with("path", "parametrization"))
        }
    })
}

/// The domain's ends and the breaks inside it.
pub fn span_ends(curve: &dyn Curve) -> Vec<f64> {
    let (a, b) = curve.domain();
    let mut ends = vec![a];
    ends.extend(curve.breaks());
    ends.push(b);
    ends
}

/// Parameters `per_span` per span of `breaks` (the span ends), closing with the last end.
fn span_params_of(breaks: &[f64], per_span: usize) -> Vec<f64> {
    let mut ts = Vec::with_capacity(breaks.len() * per_span + 1);
    for w in breaks.windows(2) {
        for i in 0..per_span {
            ts.push(w[0] + (w[1] - w[0]) * i as f64 / per_span as f64);
        }
    }
    ts.extend(breaks.last());
    ts
}

/// Points stored flat (`dim` numbers each), written as JSON rows `[[x, y], ...]` without
/// building a row per point.
#[derive(Debug, Clone, Copy)]
pub struct Rows<'a> {
    /// The coordinates, point after point.
    pub flat: &'a [f64],
    /// Numbers per point.
    pub dim: usize,
}

impl Serialize for Rows<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.flat.chunks_exact(self.dim.max(1)))
    }
}

/// The curvature comb of a plane curve (see [`comb`]), as the API writes it.
#[derive(Debug, Serialize)]
pub struct Comb {
    /// The parameters of the teeth.
    pub t: Vec<f64>,
    /// The curve at `t`, flat (x, y).
    #[serde(serialize_with = "plane_rows")]
    pub base: Vec<f64>,
    /// The signed curvature at `t`.
    pub curvature: Vec<f64>,
    /// The tips of the teeth, flat (x, y).
    #[serde(serialize_with = "plane_rows")]
    pub tip: Vec<f64>,
    /// Tooth length per unit of curvature.
    pub scale: f64,
    /// The largest |curvature| of the teeth.
    pub max_curvature: f64,
    /// In a window: the index of the first tooth in the whole curve's list.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub first: Option<usize>,
    /// In a window: the teeth of the whole curve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub total: Option<usize>,
}

fn plane_rows<S: serde::Serializer>(flat: &[f64], s: S) -> Result<S::Ok, S::Error> {
    Rows { flat, dim: 2 }.serialize(s)
}

/// The curvature comb of a plane curve at `ts`: base points, signed curvature
/// κ = (x'y'' - y'x'')/|c'|³ and teeth `base - scale·κ·n` (n the unit left normal, so the
/// teeth point away from the centre of curvature).
pub fn comb(curve: &BsplineCurve, ts: &[f64], scale: Option<f64>, extent: f64) -> ApiResult<Comb> {
    let (mut p, mut d1, mut d2) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    let mut base = Vec::with_capacity(2 * ts.len());
    let mut kappa = Vec::with_capacity(ts.len());
    let mut normal = Vec::with_capacity(ts.len());
    for &t in ts {
        curve.eval_into(t, &mut p);
        curve
            .derivative_into(t, 1, &mut d1)
            .and_then(|()| curve.derivative_into(t, 2, &mut d2))
            .map_err(|e| ApiError::geometry("comb", e))?;
        let speed = d1[0].hypot(d1[1]);
        let (k, n) = if speed > 0.0 {
            (
                (d1[0] * d2[1] - d1[1] * d2[0]) / speed.powi(3),
                [-d1[1] / speed, d1[0] / speed],
            )
        } else {
            (0.0, [0.0, 0.0])
        };
        base.extend_from_slice(&p);
        kappa.push(if k.is_finite() { k } else { 0.0 });
        normal.push(n);
    }
    let most = kappa.iter().fold(0.0f64, |m, k| m.max(k.abs()));
    let scale = match scale {
        Some(s) if s.is_finite() && s >= 0.0 => s,
        Some(s) => {
            return Err(ApiError::bad_request(format!(
                "comb.scale must be a finite number >= 0 (got {s})"
            ))
            .with("path", "comb.scale"))
        }
        None if most > 0.0 => extent / 6.0 / most,
        None => 0.0,
    };
    let tip: Vec<f64> = base
        .chunks_exact(2)
        .zip(&kappa)
        .zip(&normal)
        .flat_map(|((b, k), n)| [b[0] - scale * k * n[0], b[1] - scale * k * n[1]])
        .collect();
    finite("the comb", &tip)?;
    Ok(Comb {
        t: ts.to_vec(),
        base,
        curvature: kappa,
        tip,
        scale,
        max_curvature: most,
        first: None,
        total: None,
    })
}

/// The curve's samples as the API writes them.
#[derive(Debug, Serialize)]
struct Samples<'a> {
    t: &'a [f64],
    points: Rows<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    first: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    total: Option<usize>,
}

/// The knot spans of a window answer.
#[derive(Debug, Serialize)]
struct WindowAnswer {
    first_span: usize,
    last_span: usize,
    spans: usize,
}

/// The answer, written straight to JSON text (a 2000-point curve answers about 600 KB:
/// no tree of JSON values is built for it).
#[derive(Debug, Serialize)]
struct Answer<'a> {
    model: Option<&'a ModelFile>,
    #[serde(skip_serializing_if = "Option::is_none")]
    what: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    parameters: Option<&'a [f64]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    window: Option<WindowAnswer>,
    samples: Samples<'a>,
    comb: Option<Comb>,
}

/// `POST /api/bspline/interpolate`: `{"model", "what", "parameters", "samples": {"t",
/// "points"}, "comb": {...} | null}`.
pub async fn interpolate(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<InterpolateRequest>,
) -> ApiResult<Response> {
    blocking(move || {
        let limits = state.config.limits;
        check_points("points", req.points.len(), &limits)?;
        let dim = req.points.first().map_or(0, Vec::len);
        if dim == 0 {
            return Err(ApiError::bad_request(
                "points must be a non-empty list of points with at least one coordinate",
            )
            .with("path", "points"));
        }
        if let Some(i) = req.points.iter().position(|p| p.len() != dim) {
            return Err(ApiError::bad_request(format!(
                "points[{i}] has {} coordinates, points[0] has {dim}",
                req.points[i].len()
            ))
            .with("path", format!("points[{i}]")));
        }
        let flat: Vec<f64> = req.points.concat();
        let options = InterpolationOptions::default()
            .with_end(end_condition(req.end.as_ref(), req.closed, dim)?)
            .with_parametrization(parametrization(req.parametrization.as_deref())?);
        let fit = interpolate_curve_flat(dim, &flat, &options)
            .map_err(|e| ApiError::geometry("interpolate", e))?;
        let curve = fit.curve();
        let per_span = req.samples_per_span.unwrap_or(12);
        let spans = span_ends(curve).len() - 1;
        if per_span == 0 || per_span.saturating_mul(spans) > limits.samples {
            return Err(ApiError::bad_request(format!(
                "samples_per_span × {spans} spans must be between 1 and {} (got {per_span})",
                limits.samples
            ))
            .with("path", "samples_per_span"));
        }
        // The spans drawn: all, or those of the window (open curves; a window that wraps
        // around a closed curve's seam draws all).
        let ends = span_ends(curve);
        let window = match &req.window {
            Some(w) if !req.closed => Some(window_spans(w, fit.parameters(), &ends)?),
            _ => None,
        };
        let (first, last) = window.unwrap_or((0, spans));
        let ts = span_params_of(&ends[first..=last], per_span);
        let mut out = vec![0.0; ts.len() * dim];
        curve
            .eval_batch(&ts, &mut out, &BatchOptions::default())
            .map_err(|e| ApiError::geometry("samples", e))?;
        finite("the curve's samples", &out)?;
        let comb_req = req.comb.unwrap_or_default();
        let teeth = comb_req.per_span.unwrap_or(6);
        let comb = if dim == 2 && teeth > 0 {
            if teeth.saturating_mul(spans) > limits.samples {
                return Err(ApiError::bad_request("comb.per_span is too large")
                    .with("path", "comb.per_span"));
            }
            let extent = extent(&flat, dim);
            let mut c = comb(
                curve,
                &span_params_of(&ends[first..=last], teeth),
                comb_req.scale,
                extent,
            )?;
            if window.is_some() {
                c.first = Some(first * teeth);
                c.total = Some(spans * teeth + 1);
            }
            Some(c)
        } else {
            None
        };
        let windowed = window.is_some();
        let samples = Samples {
            t: &ts,
            points: Rows { flat: &out, dim },
            first: windowed.then_some(first * per_span),
            total: windowed.then_some(spans * per_span + 1),
        };
        let parameters = fit.parameters();
        let file;
        let answer = if windowed {
            Answer {
                model: None,
                what: None,
                parameters: None,
                window: Some(WindowAnswer {
                    first_span: first,
                    last_span: last,
                    spans,
                }),
                samples,
                comb,
            }
        } else {
            file = BsplineCurveModel::file_of(curve, Some(parameters));
            finite("the curve's knots", curve.knots())?;
            finite("the curve's control points", curve.control_flat())?;
            let what = AnyModel::BsplineCurve(BsplineCurveModel {
                curve: curve.clone(),
                parameters: None,
            })
            .describe();
            Answer {
                model: Some(&file),
                what: Some(what),
                parameters: Some(parameters),
                window: None,
                samples,
                comb,
            }
        };
        let body = serde_json::to_vec(&answer).map_err(|e| {
            ApiError::unprocessable(format!("the answer cannot be written as JSON: {e}"))
        })?;
        Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
    })
    .await
}

/// The knot spans `(first, last)` (span `first` up to the end of span `last - 1`) between
/// the parameters of reference points `around ± points` (the whole domain at the ends).
fn window_spans(w: &WindowRequest, parameters: &[f64], ends: &[f64]) -> ApiResult<(usize, usize)> {
    let n = parameters.len();
    if w.around >= n {
        return Err(ApiError::bad_request(format!(
            "window.around is {} but there are {n} points",
            w.around
        ))
        .with("path", "window.around"));
    }
    let reach = w.points.unwrap_or(40);
    let spans = ends.len() - 1;
    let first = if w.around <= reach {
        0
    } else {
        let lo = parameters[w.around - reach];
        // The last span starting at or before `lo`.
        ends[..spans]
            .partition_point(|&e| e <= lo)
            .saturating_sub(1)
    };
    let last = if w.around + reach >= n - 1 {
        spans
    } else {
        let hi = parameters[w.around + reach];
        // The first span end at or after `hi`.
        ends.partition_point(|&e| e < hi).clamp(first + 1, spans)
    };
    Ok((first, last.max(first + 1).min(spans)))
}

/// The largest side of the points' bounding box (1 when they coincide).
fn extent(flat: &[f64], dim: usize) -> f64 {
    let mut most = 0.0f64;
    for c in 0..dim {
        let it = flat.iter().skip(c).step_by(dim);
        let (lo, hi) = it.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
            (l.min(x), h.max(x))
        });
        most = most.max(hi - lo);
    }
    if most > 0.0 && most.is_finite() {
        most
    } else {
        1.0
    }
}
