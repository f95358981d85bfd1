//! `POST /api/body/view`: a body or composite surface in 3-D with its seams marked — what
//! the editor's body tab draws.
//!
//! - The mesh: the model crate's tessellation ([`geomkit_model::Loaded::tessellate`],
//!   adaptive to 1/1000 of the size by default, creases kept as split normals), as flat
//!   positions, normals and triangle indices.
//! - The seams: [`geomkit::compose::seams`] — every grid line, curve or polygon vertex line
//!   where the surface may fail to be smooth, split at the other direction's lines, with the
//!   order of smoothness across it (C^k, smooth, or discontinuous), sampled as a polyline on
//!   the surface. For a composite surface the continuity report of spec/composite-surfaces.md
//!   decides which pieces are discontinuous: its patches jump there and formula (9) shifts
//!   them to join.
//!
//! Models: Dolya's bodies (`body`), composite surfaces (parametric in R³ or explicit z(x, y)),
//! ruled surfaces, B-spline and Bézier surfaces (R³ or height fields), formula files with
//! their model. A height field (a surface in R¹) is drawn as its graph (u, v, z).

use super::formula::{body, BodyRequest};
use super::{finite, model_json, read_model};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::Json;
use geomkit::compose::{seams, GridLine, Seam, SeamLine, SeamOptions, Smoothness, SurfaceKind};
use geomkit::geom::{linspace, Surface};
use geomkit_model::{AnyModel, BezierModel, Loaded, ModelFile, Sampling, Tessellation};
use serde::Deserialize;
use serde_json::{json, Value};

/// Most seam pieces the view classifies (a 70 × 70 grid of cells has about 10 000).
pub const MAX_SEAM_PIECES: usize = 20_000;

/// `{"model": M}` or `{"body": B}`, `"tolerance"`, `"seam_samples"`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewRequest {
    /// A model file.
    #[serde(default)]
    pub model: Option<Value>,
    /// One of the paper's bodies (as `/api/formula`).
    #[serde(default)]
    pub body: Option<BodyRequest>,
    /// Largest deviation of the mesh from the surface, in model units (default: 1/1000 of
    /// the model's extent along each axis).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Points of each seam piece's polyline (default 33, 2 to 2000).
    #[serde(default)]
    pub seam_samples: Option<usize>,
}

/// The surface a model draws as, with the names of its parameters.
fn surface_of(model: &AnyModel) -> ApiResult<(&dyn Surface, [&'static str; 2])> {
    let uv = ["u", "v"];
    let s: (&dyn Surface, _) = match model {
        AnyModel::Composite(s) => match s.kind() {
            SurfaceKind::Parametric => (s, uv),
            SurfaceKind::Explicit => (s, ["x", "y"]),
        },
        AnyModel::Ruled(s) => (s, uv),
        AnyModel::BsplineSurface(m) => (&m.surface, uv),
        AnyModel::Bezier(BezierModel::Surface(s)) => (s, uv),
        AnyModel::Bezier(BezierModel::RationalSurface(s)) => (s, uv),
        AnyModel::Formula(f) => match &f.model {
            Some(m) => return surface_of(m),
            None => {
                return Err(ApiError::unprocessable(
                    "this formula file carries no model: nothing to draw in 3-D",
                )
                .with("path", "model"))
            }
        },
        other => {
            return Err(ApiError::unprocessable(format!(
                "model is a {}; the body view draws composite surfaces, ruled surfaces and \
                 bodies, B-spline and Bézier surfaces",
                other.describe()
            ))
            .with("path", "model"))
        }
    };
    let dim = s.0.dim();
    if dim != 3 && dim != 1 {
        return Err(ApiError::unprocessable(format!(
            "model is a surface in R^{dim}; the body view draws surfaces in R^3 and height \
             fields (R^1)"
        ))
        .with("path", "model"));
    }
    Ok(s)
}

/// The name of a smoothness in the answer and the legend.
fn smoothness_name(s: Smoothness) -> String {
    match s {
        Smoothness::Discontinuous => "discontinuous".into(),
        Smoothness::C(k) => format!("C{k}"),
        Smoothness::Smooth => "smooth".into(),
    }
}

/// The point of the surface drawn at (u, v): a height field's graph (u, v, z).
fn drawn_point(s: &dyn Surface, u: f64, v: f64) -> [f64; 3] {
    let p = s.eval(u, v);
    match p.len() {
        1 => [u, v, p[0]],
        _ => [p[0], p[1], p[2]],
    }
}

/// The patches' jump on a composite surface's seam piece, when its continuity report says
/// they do not meet there (`None`: they do, or the model has no report).
fn report_jump(model: &AnyModel, seam: &Seam) -> Option<f64> {
    let AnyModel::Composite(c) = model else {
        return None;
    };
    let report = c.continuity();
    let (ku, kv) = c.knots();
    report
        .jumps
        .iter()
        .filter(|j| j.max_jump > report.tolerance)
        .find(|j| match (j.line, seam.line) {
            (GridLine::U(i), SeamLine::U) => ku[i] == seam.value && kv[j.cell] == seam.from,
            (GridLine::V(k), SeamLine::V) => kv[k] == seam.value && ku[j.cell] == seam.from,
            _ => false,
        })
        .map(|j| j.max_jump)
}

/// The answer for a model: mesh, seams, legend.
pub fn view(model: &AnyModel, tolerance: Option<f64>, seam_samples: usize) -> ApiResult<Value> {
    let (surface, names) = surface_of(model)?;
    // Each seam piece costs 17 × 4 × 2 derivatives: refuse grids with more than
    // MAX_SEAM_PIECES of them before computing anything long.
    let (bu, bv) = surface.breaks();
    let pieces = (bu.len() + 1) * (bv.len() + 2) + (bv.len() + 1) * (bu.len() + 2);
    if pieces > MAX_SEAM_PIECES {
        return Err(ApiError::too_large(format!(
            "model has {} × {} grid lines: about {pieces} seam pieces to classify, the body \
             view marks at most {MAX_SEAM_PIECES}",
            bu.len(),
            bv.len()
        ))
        .with("path", "model"));
    }
    let loaded = Loaded::from_model(model.clone()).map_err(|e| ApiError::model("model", e))?;
    let mesh = match loaded
        .tessellate(Sampling::Tolerance(tolerance))
        .map_err(|e| ApiError::geometry("mesh", e))?
    {
        Tessellation::Mesh(m) => m,
        Tessellation::Polyline(_) => {
            return Err(ApiError::unprocessable("model is a curve, not a surface"))
        }
    };
    let (positions, normals, triangles) = mesh.split_vertices();
    let positions: Vec<f64> = positions.into_iter().flatten().collect();
    let normals: Vec<f64> = normals.into_iter().flatten().collect();
    let triangles: Vec<u32> = triangles.into_iter().flatten().collect();
    finite("the mesh", &positions)?;
    let found =
        seams(surface, &SeamOptions::default()).map_err(|e| ApiError::geometry("seams", e))?;
    let mut out = Vec::with_capacity(found.len());
    let mut legend: Vec<((Smoothness, bool), usize)> = Vec::new();
    for seam in &found {
        let jump = report_jump(model, seam);
        let smoothness = if jump.is_some() {
            Smoothness::Discontinuous
        } else {
            seam.smoothness
        };
        let crease = smoothness == Smoothness::C(0) && !seam.tangent_continuous;
        let (across, along) = match seam.line {
            SeamLine::U => (names[0], names[1]),
            SeamLine::V => (names[1], names[0]),
        };
        let ts = linspace(seam.from, seam.to, seam_samples);
        let params: Vec<[f64; 2]> = ts
            .iter()
            .map(|&t| match seam.line {
                SeamLine::U => [seam.value, t],
                SeamLine::V => [t, seam.value],
            })
            .collect();
        let points: Vec<f64> = params
            .iter()
            .flat_map(|&[u, v]| drawn_point(surface, u, v))
            .collect();
        finite("a seam", &points)?;
        let place = format!(
            "{across} = {} ({along} from {} to {})",
            short(seam.value),
            short(seam.from),
            short(seam.to)
        );
        let label = match (smoothness, jump) {
            (Smoothness::Discontinuous, Some(j)) => format!(
                "{place}: the patches jump by {} here; the single formula shifts them to join \
                 (its surface is C0)",
                short(j)
            ),
            (Smoothness::Discontinuous, None) => format!("{place}: discontinuous"),
            (Smoothness::C(0), _) if crease => format!(
                "{place}: C0, a crease (the tangent plane turns; the derivative across jumps \
                 by {})",
                short(seam.jumps[1])
            ),
            (Smoothness::C(0), _) => format!(
                "{place}: C0 in the parameters (the derivative across jumps by {}), but the \
                 tangent plane is continuous (G1)",
                short(seam.jumps[1])
            ),
            (Smoothness::C(k), _) => format!(
                "{place}: C{k} (derivative {} across the line jumps by {})",
                k + 1,
                short(seam.jumps[k + 1])
            ),
            (Smoothness::Smooth, _) => format!(
                "{place}: smooth (no jump in the derivatives up to order {})",
                seam.jumps.len() - 1
            ),
        };
        match legend.iter_mut().find(|(s, _)| *s == (smoothness, crease)) {
            Some((_, n)) => *n += 1,
            None => legend.push(((smoothness, crease), 1)),
        }
        out.push(json!({
            "line": if seam.line == SeamLine::U { "u" } else { "v" },
            "name": across,
            "value": seam.value,
            "from": seam.from,
            "to": seam.to,
            "closing": seam.closing,
            "smoothness": smoothness_name(smoothness),
            "order": match smoothness { Smoothness::C(k) => Some(k), _ => None },
            "crease": crease,
            "jumps": seam.jumps,
            "tolerances": seam.tolerances,
            "patch_jump": jump,
            "label": label,
            "params": params,
            "points": points,
        }));
    }
    // Worst first: discontinuous, creases, C0, C1, ..., smooth.
    legend.sort_by_key(|((s, crease), _)| (*s, !crease));
    let legend: Vec<Value> = legend
        .into_iter()
        .map(|((s, crease), count)| {
            json!({"smoothness": smoothness_name(s), "crease": crease, "count": count})
        })
        .collect();
    let continuity = match model {
        AnyModel::Composite(c) => json!({
            "continuous": c.continuity().is_continuous(),
            "max_jump": c.continuity().max_jump,
            "tolerance": c.continuity().tolerance,
        }),
        _ => Value::Null,
    };
    Ok(json!({
        "what": model.describe(),
        "parameters": names,
        "mesh": {
            "positions": positions,
            "normals": normals,
            "triangles": triangles,
        },
        "seams": out,
        "legend": legend,
        "continuity": continuity,
    }))
}

/// A number for a label: up to 4 significant digits.
fn short(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{:.*}", (3 - a.log10().floor() as i32).max(0) as usize, x);
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.2e}")
    }
}

/// `POST /api/body/view`: `{"what", "parameters", "mesh": {"positions", "normals",
/// "triangles"}, "seams": [...], "legend": [{"smoothness", "crease", "count"}],
/// "continuity", "model"}`
/// (`model`: a body's `ruled` file; null for a model given).
pub async fn view_handler(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ViewRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let samples = req.seam_samples.unwrap_or(33);
        if !(2..=2000).contains(&samples) {
            return Err(ApiError::bad_request(format!(
                "seam_samples must be between 2 and 2000 (got {samples})"
            ))
            .with("path", "seam_samples"));
        }
        if let Some(t) = req.tolerance {
            if !(t.is_finite() && t > 0.0) {
                return Err(ApiError::bad_request(format!(
                    "tolerance must be a finite number > 0 (got {t})"
                ))
                .with("path", "tolerance"));
            }
        }
        let (model, file) =
            match (&req.model, &req.body) {
                (Some(m), None) => (read_model("model", m, &state.config.limits)?, Value::Null),
                (None, Some(b)) => {
                    let (s, _) = body(b)?;
                    let file = match geomkit_model::ruled_file(&s) {
                        Some(r) => model_json(&ModelFile::Ruled(r))?,
                        None => Value::Null,
                    };
                    (AnyModel::Ruled(s), file)
                }
                _ => return Err(ApiError::bad_request(
                    "give one of \"model\" (a model file) or \"body\" ({\"kind\": \"cube\", ...})",
                )),
            };
        let mut answer = view(&model, req.tolerance, samples)?;
        answer["model"] = file;
        if let (Some(b), Some(o)) = (&req.body, answer.as_object_mut()) {
            o.insert("what".into(), json!(format!("{} (Dolya's body)", b.kind)));
        }
        Ok(Json(answer))
    })
    .await
}
