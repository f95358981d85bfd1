//! `POST /api/formula`: the single analytic formula of spec/composite-surfaces.md of a model
//! or of one of the paper's bodies, printed in one of the 11 syntaxes, with the continuity
//! report (which patches or pieces join, and the largest jump where they do not).
//!
//! Models: composite surfaces (parametric or explicit), B-spline surfaces (their cells as
//! patches), Bézier surfaces (one patch), ruled surfaces, piecewise functions and composite
//! curves, B-spline and polynomial Bézier curves (their spans as pieces), rational Bézier
//! curves (the homogeneous curve's polynomials divided by the weight's), point-calculus
//! models (the point equation: one formula per response over the factors), and formula
//! files (their stored text).

use super::{model_json, read_model};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::Json;
use geomkit::bezier::BezierCurve;
use geomkit::bspline::BsplineCurve;
use geomkit::compose::{
    bodies, CompositeSurface, ContinuityReport, Formula, GridLine, Piecewise, RuledSurface,
    SurfaceKind,
};
use geomkit::expr::{Format, Graph};
use geomkit_model::{AnyModel, BezierModel, ModelFile};
use serde::Deserialize;
use serde_json::{json, Value};

/// The request: a model, or a body of the paper by its parameters.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FormulaRequest {
    /// A model file.
    #[serde(default)]
    pub model: Option<Value>,
    /// A body: `{"kind": "cube" | "box" | "pyramid" | "cone" | "cylinder" | "prism" |
    /// "frustum", "height", "radius", "top_radius", "size": [a, b, c], "side", "ngon"}`.
    #[serde(default)]
    pub body: Option<BodyRequest>,
    /// The syntax: maple (default), mathematica, sympy, numpy, matlab, latex, c, rust,
    /// glsl, js, desmos.
    #[serde(default)]
    pub format: Option<String>,
    /// Print a program (shared subexpressions as definitions) instead of one expression.
    #[serde(default)]
    pub program: bool,
}

/// One of the paper's bodies.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyRequest {
    /// Which body.
    pub kind: String,
    /// Height (default 2).
    #[serde(default)]
    pub height: Option<f64>,
    /// Radius of the base or circumscribed circle (default 1).
    #[serde(default)]
    pub radius: Option<f64>,
    /// Top radius of a frustum (default radius / 2).
    #[serde(default)]
    pub top_radius: Option<f64>,
    /// Sides of a box (default 2, 2, 2).
    #[serde(default)]
    pub size: Option<[f64; 3]>,
    /// Side of a square pyramid (default 2).
    #[serde(default)]
    pub side: Option<f64>,
    /// Sides of the regular polygon of a prism or pyramid (default 6 for a prism).
    #[serde(default)]
    pub ngon: Option<usize>,
}

/// The syntax named in a request.
pub fn format_of(name: Option<&str>) -> ApiResult<Format> {
    let name = name.unwrap_or("maple");
    Format::from_name(name).ok_or_else(|| {
        ApiError::bad_request(format!(
            "format \"{name}\" is not one of {}",
            Format::ALL.map(Format::name).join(", ")
        ))
        .with("path", "format")
    })
}

/// One of the paper's bodies as its ruled surface and a description ("cube (Dolya's body)").
pub fn body(b: &BodyRequest) -> ApiResult<(RuledSurface, String)> {
    let h = b.height.unwrap_or(2.0);
    let r = b.radius.unwrap_or(1.0);
    if b.ngon.is_some_and(|n| n > 10_000) {
        return Err(ApiError::too_large("body.ngon is at most 10000").with("path", "body.ngon"));
    }
    let polygon = || bodies::regular_polygon(b.ngon.unwrap_or(6), r);
    let built = match b.kind.as_str() {
        "cube" => bodies::cube(),
        "box" => {
            let [x, y, z] = b.size.unwrap_or([2.0; 3]);
            bodies::rectangular_box(x, y, z)
        }
        "pyramid" if b.ngon.is_some() => polygon().and_then(|p| bodies::pyramid(&p, h)),
        "pyramid" => bodies::square_pyramid(b.side.unwrap_or(2.0), h),
        "cone" => bodies::cone(r, h),
        "cylinder" => bodies::cylinder(r, h),
        "prism" => polygon().and_then(|p| bodies::prism(&p, h)),
        "frustum" => bodies::frustum(r, b.top_radius.unwrap_or(r / 2.0), h),
        other => {
            return Err(ApiError::bad_request(format!(
                "body.kind \"{other}\" is not one of cube, box, pyramid, cone, cylinder, prism, \
                 frustum"
            ))
            .with("path", "body.kind"))
        }
    };
    let s = built.map_err(|e| ApiError::geometry("body", e))?;
    Ok((s, format!("{} (Dolya's body)", b.kind)))
}

/// A continuity report as JSON (`u`/`v` or `x`/`y` lines).
fn report_json(r: &ContinuityReport, statement: String) -> Value {
    let jumps: Vec<Value> = r
        .jumps
        .iter()
        .map(|j| {
            let (line, index) = match j.line {
                GridLine::U(i) => ("u", i),
                GridLine::V(k) => ("v", k),
            };
            json!({"line": line, "index": index, "cell": j.cell, "max_jump": j.max_jump, "at": j.at})
        })
        .collect();
    json!({
        "continuous": r.is_continuous(),
        "max_jump": r.max_jump,
        "tolerance": r.tolerance,
        "statement": statement,
        "jumps": jumps,
    })
}

fn surface_report(s: &CompositeSurface) -> Value {
    let names = match s.kind() {
        SurfaceKind::Parametric => ("u", "v"),
        SurfaceKind::Explicit => ("x", "y"),
    };
    report_json(
        s.continuity(),
        s.continuity().statement(names.0, names.1, s.knots()),
    )
}

/// The single formula of a curve given as a B-spline: its spans as pieces.
fn curve_formula(c: &BsplineCurve) -> ApiResult<(Formula, Value)> {
    let p = Piecewise::from_bspline(c).map_err(|e| ApiError::geometry("formula", e))?;
    let f = p.formula().map_err(|e| ApiError::geometry("formula", e))?;
    Ok((f, report_json(p.continuity(), p.statement())))
}

/// A polynomial Bézier curve as the B-spline of one span (knots 0 and 1, each n + 1 times).
pub fn bezier_as_bspline(c: &BezierCurve) -> ApiResult<BsplineCurve> {
    let n = c.degree();
    let knots: Vec<f64> = (0..2 * (n + 1))
        .map(|i| if i <= n { 0.0 } else { 1.0 })
        .collect();
    BsplineCurve::new(n, knots, c.points()).map_err(|e| ApiError::geometry("formula", e))
}

/// The formula of a model and its continuity report.
pub fn model_formula(model: AnyModel) -> ApiResult<(Formula, Value)> {
    let geometry = |e| ApiError::geometry("formula", e);
    match model {
        AnyModel::Composite(s) => {
            let report = surface_report(&s);
            Ok((s.formula().map_err(geometry)?, report))
        }
        AnyModel::BsplineSurface(m) => {
            let s = CompositeSurface::from_bspline(&m.surface).map_err(geometry)?;
            let report = surface_report(&s);
            Ok((s.formula().map_err(geometry)?, report))
        }
        AnyModel::Bezier(BezierModel::Surface(b)) => {
            let s = CompositeSurface::from_bezier(vec![0.0, 1.0], vec![0.0, 1.0], &[vec![b]])
                .map_err(geometry)?;
            let report = surface_report(&s);
            Ok((s.formula().map_err(geometry)?, report))
        }
        AnyModel::Bezier(BezierModel::Curve(c)) => curve_formula(&bezier_as_bspline(&c)?),
        AnyModel::Bezier(BezierModel::Rational(c)) => {
            // p = A / w: the polynomial formulas of the homogeneous curve (A, w), divided.
            let (mut f, report) = curve_formula(&bezier_as_bspline(c.homogeneous())?)?;
            let d = f.roots.len() - 1;
            let w = f.roots[d];
            for i in 0..d {
                f.roots[i] = f.graph.div(f.roots[i], w);
            }
            f.roots.truncate(d);
            f.names.truncate(d);
            Ok((f, report))
        }
        AnyModel::BsplineCurve(m) => curve_formula(&m.curve),
        AnyModel::Piecewise(p) => {
            let report = report_json(p.continuity(), p.statement());
            Ok((p.formula().map_err(geometry)?, report))
        }
        AnyModel::Ruled(s) => Ok((s.formula().map_err(geometry)?, Value::Null)),
        AnyModel::Pointcalc(m) => {
            // The point equation of spec/point-calculus.md: one formula per response in the
            // factors' names (what `geomkit pointcalc formula` prints).
            let mut graph = Graph::new();
            let vars: Vec<String> = m
                .model
                .factors()
                .iter()
                .map(|f| f.name().to_string())
                .collect();
            let ids: Vec<_> = vars.iter().map(|v| graph.var(v)).collect();
            let roots = m.model.to_expr(&mut graph, &ids).map_err(geometry)?;
            let formula = Formula {
                graph,
                roots,
                names: m.response,
                vars,
            };
            Ok((formula, Value::Null))
        }
        AnyModel::Formula(f) => match f.model {
            Some(m) => model_formula(*m),
            None => Err(ApiError::unprocessable(
                "this formula file carries no model: its formulas are in the file itself",
            )),
        },
        other => Err(ApiError::unprocessable(format!(
            "no single formula for a {} here",
            other.describe()
        ))
        .with("path", "model")),
    }
}

/// `POST /api/formula {"model": M | "body": B, "format": "maple", "program": false}` →
/// `{"what", "format", "formula", "variables", "coordinates", "op_count", "continuity",
/// "model"}` (`model`: the body's `ruled` file, to draw or export; null for a model).
pub async fn formula(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<FormulaRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let format = format_of(req.format.as_deref())?;
        let (f, what, continuity, file) =
            match (&req.model, &req.body) {
                (Some(m), None) => {
                    let model = read_model("model", m, &state.config.limits)?;
                    let what = model.describe();
                    let (f, c) = model_formula(model)?;
                    (f, what, c, Value::Null)
                }
                (None, Some(b)) => {
                    let (s, what) = body(b)?;
                    let f = s.formula().map_err(|e| ApiError::geometry("formula", e))?;
                    let file = match geomkit_model::ruled_file(&s) {
                        Some(r) => model_json(&ModelFile::Ruled(r))?,
                        None => Value::Null,
                    };
                    (f, what, Value::Null, file)
                }
                _ => return Err(ApiError::bad_request(
                    "give one of \"model\" (a model file) or \"body\" ({\"kind\": \"cube\", ...})",
                )),
            };
        let text = if req.program {
            f.print_program(format)
        } else {
            f.print(format)
        }
        .map_err(|e| ApiError::geometry("formula", e))?;
        Ok(Json(json!({
            "what": what,
            "format": format.name(),
            "formula": text,
            "variables": f.vars,
            "coordinates": f.names,
            "op_count": f.op_count(),
            "continuity": continuity,
            "model": file,
        })))
    })
    .await
}
