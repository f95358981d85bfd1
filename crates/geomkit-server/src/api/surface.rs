//! `POST /api/surface/*`: what the editor's 3-D view draws and edits.
//!
//! - `mesh`: a shaded grid of a Bézier (rational too) or B-spline surface in R³, or of a
//!   height field z(x, y): positions, unit normals, and a value per vertex to colour by
//!   (Gaussian or mean curvature, or the distance to a reference
//!   surface: the error of an approximation), with the control net.
//! - `edit`: insert or remove a row (u) or column (v) of a Bézier net, with weights for
//!   rational nets (Fig. 4 of spec/bezier-order.md), and how far the surface moved.
//! - `approximate`: the best L2 approximation of lower degrees of a polynomial Bézier
//!   surface, its L2 error and L∞ bound, and its mesh coloured by the distance to the
//!   original.
//! - `heights`: the bicubic B-spline through a grid of heights (spec
//!   bspline-interpolation.md §3) with its mesh and curvature.
//!
//! Flat arrays (`[x0, y0, z0, x1, ...]`) keep the answers small and quick to upload to the
//! GPU. Every number comes from the library; this module only arranges them.

use super::bspline::end_condition;
use super::{check_points, finite, model_json, read_model};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::{AppState, Limits};
use axum::extract::State;
use axum::Json;
use geomkit::bezier::{BezierSurface, Direction, RationalBezierSurface};
use geomkit::bspline::{interpolate_heights_at, BsplineSurface, EndCondition};
use geomkit::geom::{linspace, Surface};
use geomkit_model::{AnyModel, BezierModel, BsplineSurfaceModel};
use serde::Deserialize;
use serde_json::{json, Value};

/// A surface the 3-D view draws.
enum Drawn<'a> {
    Bezier(&'a BezierSurface),
    Rational(&'a RationalBezierSurface),
    Bspline(&'a BsplineSurface),
}

impl Drawn<'_> {
    fn of(model: &AnyModel) -> ApiResult<Drawn<'_>> {
        let d = match model {
            AnyModel::Bezier(BezierModel::Surface(s)) => Drawn::Bezier(s),
            AnyModel::Bezier(BezierModel::RationalSurface(s)) => Drawn::Rational(s),
            AnyModel::BsplineSurface(m) => Drawn::Bspline(&m.surface),
            other => {
                return Err(ApiError::unprocessable(format!(
                    "model is a {}; the 3-D view draws bezier_surface and bspline_surface files",
                    other.describe()
                ))
                .with("path", "model"))
            }
        };
        let dim = d.surface().dim();
        let heights = matches!(d, Drawn::Bspline(_) | Drawn::Bezier(_)) && dim == 1;
        if dim != 3 && !heights {
            return Err(ApiError::unprocessable(format!(
                "model is a surface in R^{dim}; the 3-D view draws surfaces in R^3 and height \
                 fields (B-spline or polynomial Bézier surfaces in R^1)"
            ))
            .with("path", "model"));
        }
        Ok(d)
    }

    fn surface(&self) -> &dyn Surface {
        match self {
            Drawn::Bezier(s) => *s,
            Drawn::Rational(s) => *s,
            Drawn::Bspline(s) => *s,
        }
    }

    /// Positions (x, y, z) and unit normals on the grid `us` × `vs` (a height field z(u, v)
    /// as the graph (u, v, z)). A singular point (collapsed edge) gets a zero normal.
    fn grid(&self, us: &[f64], vs: &[f64]) -> ApiResult<(Vec<f64>, Vec<f64>)> {
        let s = self.surface();
        let dim = s.dim();
        let count = us.len() * vs.len();
        let geometry = |e| ApiError::geometry("mesh", e);
        let mut values = vec![0.0; count * dim];
        s.eval_grid(us, vs, &mut values).map_err(geometry)?;
        // Partial derivatives (as 3-D vectors) where they are cheap as whole grids.
        let partials =
            |du: &BezierSurface, dv: &BezierSurface| -> ApiResult<(Vec<f64>, Vec<f64>)> {
                let (mut a, mut b) = (vec![0.0; count * dim], vec![0.0; count * dim]);
                du.eval_grid(us, vs, &mut a).map_err(geometry)?;
                dv.eval_grid(us, vs, &mut b).map_err(geometry)?;
                Ok((a, b))
            };
        let bezier_partials = match self {
            Drawn::Bezier(s) => Some(partials(
                &s.derivative(Direction::U),
                &s.derivative(Direction::V),
            )?),
            _ => None,
        };
        let mut positions = Vec::with_capacity(count * 3);
        let mut normals = Vec::with_capacity(count * 3);
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let k = a * vs.len() + b;
                // The partial derivatives S_u, S_v of the drawn (3-D) surface.
                let (d1, d2) = match (&bezier_partials, self) {
                    (Some((pu, pv)), _) => (
                        lift(&pu[k * dim..(k + 1) * dim], [1.0, 0.0]),
                        lift(&pv[k * dim..(k + 1) * dim], [0.0, 1.0]),
                    ),
                    (None, Drawn::Bspline(s)) => {
                        let (mut x, mut y) = ([0.0; 3], [0.0; 3]);
                        s.eval_derivative(u, v, 1, 0, &mut x[..dim]);
                        s.eval_derivative(u, v, 0, 1, &mut y[..dim]);
                        (lift(&x[..dim], [1.0, 0.0]), lift(&y[..dim], [0.0, 1.0]))
                    }
                    (None, Drawn::Rational(s)) => {
                        // A normal is all the shading needs (S_u × S_v ∥ n).
                        let n = s.normal(u, v).map_err(geometry)?.unwrap_or([0.0; 3]);
                        ([0.0; 3], n)
                    }
                    (None, Drawn::Bezier(_)) => unreachable!("partials computed above"),
                };
                let p = &values[k * dim..(k + 1) * dim];
                if dim == 1 {
                    positions.extend_from_slice(&[u, v, p[0]]);
                } else {
                    positions.extend_from_slice(p);
                }
                let n = if matches!(self, Drawn::Rational(_)) {
                    d2
                } else {
                    unit_cross(d1, d2)
                };
                normals.extend_from_slice(&n);
            }
        }
        finite("the surface's mesh", &positions)?;
        Ok((positions, normals))
    }

    /// The control net as 3-D points (a height field's net over its Greville abscissae is
    /// not drawn: `None`) and the weights of a rational net.
    fn net(&self) -> Option<Value> {
        let (rows, cols, flat, weights) = match self {
            Drawn::Bezier(s) if s.dim() == 3 => {
                let (n, m) = s.degrees();
                (n + 1, m + 1, s.net_flat().to_vec(), None)
            }
            Drawn::Rational(s) => {
                let (n, m) = s.degrees();
                (
                    n + 1,
                    m + 1,
                    s.net_flat().to_vec(),
                    Some(s.weights_flat().to_vec()),
                )
            }
            Drawn::Bspline(s) if s.dim() == 3 => {
                let (a, b) = s.net_size();
                (a, b, s.control_flat().to_vec(), None)
            }
            _ => return None,
        };
        Some(json!({"rows": rows, "cols": cols, "points": flat, "weights": weights}))
    }
}

/// A derivative vector as 3-D: a height field's (f_u) becomes the graph's (1, 0, f_u).
fn lift(d: &[f64], plane: [f64; 2]) -> [f64; 3] {
    if d.len() == 1 {
        [plane[0], plane[1], d[0]]
    } else {
        [d[0], d[1], d[2]]
    }
}

fn unit_cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let len = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        [c[0] / len, c[1] / len, c[2] / len]
    } else {
        [0.0; 3]
    }
}

/// What a mesh's vertices are coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Colour {
    /// No colouring.
    #[default]
    None,
    /// Gaussian curvature K.
    Gaussian,
    /// Mean curvature H (signed with the normal S_u × S_v).
    Mean,
    /// Distance to the `reference` surface at the same (u, v).
    Distance,
}

/// Samples per direction of a request: default 33, at least 2, at most the square root of
/// the sample limit.
fn samples_per_direction(k: Option<usize>, limits: &Limits) -> ApiResult<usize> {
    let k = k.unwrap_or(33);
    let most = (limits.samples as f64).sqrt() as usize;
    if k < 2 || k > most {
        return Err(ApiError::bad_request(format!(
            "samples of a surface must be between 2 and {most} per direction (got {k})"
        ))
        .with("path", "samples"));
    }
    Ok(k)
}

/// The mesh of a model: `{"what", "rows", "cols", "u", "v", "positions", "normals",
/// "values", "range", "colour", "net"}`.
fn mesh(
    model: &AnyModel,
    k: usize,
    colour: Colour,
    reference: Option<&AnyModel>,
) -> ApiResult<Value> {
    let drawn = Drawn::of(model)?;
    let s = drawn.surface();
    let ((u0, u1), (v0, v1)) = s.domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, k));
    let (positions, normals) = drawn.grid(&us, &vs)?;
    let values = match colour {
        Colour::None => None,
        Colour::Gaussian | Colour::Mean => {
            let curvature = |u: f64, v: f64| match drawn {
                Drawn::Bezier(b) => b.curvature(u, v),
                Drawn::Rational(b) => b.curvature(u, v),
                Drawn::Bspline(b) => b.curvature(u, v),
            };
            let mut out = Vec::with_capacity(k * k);
            for &u in &us {
                for &v in &vs {
                    let c = curvature(u, v).map_err(|e| ApiError::geometry("curvature", e))?;
                    // A singular point has no curvature: 0 (drawn neutral).
                    out.push(c.map_or(0.0, |c| {
                        if colour == Colour::Gaussian {
                            c.gaussian
                        } else {
                            c.mean
                        }
                    }));
                }
            }
            Some(out)
        }
        Colour::Distance => {
            let Some(reference) = reference else {
                return Err(ApiError::bad_request(
                    "colour \"distance\" needs a \"reference\" model",
                )
                .with("path", "reference"));
            };
            let r = Drawn::of(reference).map_err(|e| e.with("path", "reference"))?;
            if r.surface().dim() != s.dim() || r.surface().domain() != s.domain() {
                return Err(ApiError::unprocessable(
                    "reference must be a surface of the same dimension and domain",
                )
                .with("path", "reference"));
            }
            let (theirs, _) = r.grid(&us, &vs)?;
            Some(
                positions
                    .chunks_exact(3)
                    .zip(theirs.chunks_exact(3))
                    .map(|(a, b)| {
                        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2))
                            .sqrt()
                    })
                    .collect::<Vec<f64>>(),
            )
        }
    };
    if let Some(v) = &values {
        finite("the colouring", v)?;
    }
    let range = values.as_ref().map(|v| {
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        [lo, hi]
    });
    Ok(json!({
        "what": model.describe(),
        "rows": k,
        "cols": k,
        "u": us,
        "v": vs,
        "positions": positions,
        "normals": normals,
        "values": values,
        "range": range,
        "colour": colour,
        "net": drawn.net(),
    }))
}

/// `{"model": M, "samples": K, "colour": "none" | "gaussian" | "mean" | "distance",
/// "reference": M2}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshRequest {
    /// A `bezier_surface` or `bspline_surface` file (in R³, or a height field).
    pub model: Value,
    /// Samples per direction (default 33).
    #[serde(default)]
    pub samples: Option<usize>,
    /// What to colour by.
    #[serde(default)]
    pub colour: Colour,
    /// The surface distances are measured to (`colour: "distance"`).
    #[serde(default)]
    pub reference: Option<Value>,
}

/// `POST /api/surface/mesh`: positions and unit normals on a K×K grid over the domain
/// (row-major, u slowest), a value per vertex to colour by with its range, and the control
/// net (with weights).
pub async fn mesh_handler(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<MeshRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = read_model("model", &req.model, &limits)?;
        let reference = match &req.reference {
            Some(r) => Some(read_model("reference", r, &limits)?),
            None => None,
        };
        let k = samples_per_direction(req.samples, &limits)?;
        mesh(&model, k, req.colour, reference.as_ref()).map(Json)
    })
    .await
}

/// A row or column of a net.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Line {
    /// A row (fixed i, along v): direction u.
    U,
    /// A column (fixed j, along u): direction v.
    V,
}

impl From<Line> for Direction {
    fn from(l: Line) -> Direction {
        match l {
            Line::U => Direction::U,
            Line::V => Direction::V,
        }
    }
}

/// A row or column to insert.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InsertLine {
    /// `"u"`: a row (m+1 points); `"v"`: a column (n+1 points).
    pub direction: Line,
    /// Its index in the new net.
    pub index: usize,
    /// Its points.
    pub points: Vec<Vec<f64>>,
    /// Its weights (rational nets; default 1 each).
    #[serde(default)]
    pub weights: Option<Vec<f64>>,
}

/// A row or column to remove.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RemoveLine {
    /// `"u"`: row `index`; `"v"`: column `index`.
    pub direction: Line,
    /// Which.
    pub index: usize,
}

/// `{"model": M, "insert": {...}}` or `{"model": M, "remove": {...}}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EditRequest {
    /// A `bezier_surface` file (weights allowed).
    pub model: Value,
    /// A row or column to insert.
    #[serde(default)]
    pub insert: Option<InsertLine>,
    /// A row or column to remove.
    #[serde(default)]
    pub remove: Option<RemoveLine>,
}

fn bezier_surface_of(value: &Value, limits: &Limits) -> ApiResult<BezierModel> {
    match read_model("model", value, limits)? {
        AnyModel::Bezier(b @ (BezierModel::Surface(_) | BezierModel::RationalSurface(_))) => Ok(b),
        other => Err(ApiError::unprocessable(format!(
            "model is a {}; this endpoint takes a bezier_surface",
            other.describe()
        ))
        .with("path", "model")),
    }
}

/// `POST /api/surface/edit`: the paper's manual change (13) — a row or column inserted or
/// removed (the degree in that direction changes by one, and so does the shape); answers
/// `{"model", "what", "degrees", "deviation"}` (`deviation`: how far the surface moved,
/// `{"max_found", "upper_bound"}`, for polynomial nets; `null` for rational ones).
pub async fn edit(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<EditRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = bezier_surface_of(&req.model, &limits)?;
        let geometry = |e| ApiError::geometry("edit", e);
        let new = match (&req.insert, &req.remove, &model) {
            (Some(ins), None, _) => {
                let (n, m) = model.surface_degrees().unwrap_or((0, 0));
                check_points("insert", (n + 2) * (m + 2), &limits)?;
                super::check_degree("insert", n.max(m) + 1, &limits)?;
                if let Some(k) = ins
                    .points
                    .iter()
                    .flatten()
                    .chain(ins.weights.iter().flatten())
                    .position(|x| !x.is_finite())
                {
                    return Err(ApiError::bad_request(format!(
                        "insert: number {k} of the points and weights is not finite"
                    ))
                    .with("path", "insert"));
                }
                match &model {
                    BezierModel::Surface(s) => {
                        if ins.weights.is_some() {
                            return Err(ApiError::bad_request(
                                "insert.weights: the net has no weights (a polynomial surface)",
                            )
                            .with("path", "insert.weights"));
                        }
                        BezierModel::Surface(
                            s.insert_line(ins.direction.into(), ins.index, &ins.points)
                                .map_err(geometry)?,
                        )
                    }
                    BezierModel::RationalSurface(s) => {
                        let ones = vec![1.0; ins.points.len()];
                        let w = ins.weights.as_deref().unwrap_or(&ones);
                        BezierModel::RationalSurface(
                            s.insert_line(ins.direction.into(), ins.index, &ins.points, w)
                                .map_err(geometry)?,
                        )
                    }
                    _ => unreachable!("checked by bezier_surface_of"),
                }
            }
            (None, Some(rem), BezierModel::Surface(s)) => BezierModel::Surface(
                s.remove_line(rem.direction.into(), rem.index)
                    .map_err(geometry)?,
            ),
            (None, Some(rem), BezierModel::RationalSurface(s)) => BezierModel::RationalSurface(
                s.remove_line(rem.direction.into(), rem.index)
                    .map_err(geometry)?,
            ),
            _ => {
                return Err(ApiError::bad_request(
                    "give one of \"insert\": {\"direction\", \"index\", \"points\"} or \
                     \"remove\": {\"direction\", \"index\"}",
                ))
            }
        };
        let deviation = match (&model, &new) {
            (BezierModel::Surface(a), BezierModel::Surface(b)) => {
                let d = a.deviation_from(b).map_err(geometry)?;
                json!({"max_found": d.max_found, "upper_bound": d.upper_bound})
            }
            _ => Value::Null,
        };
        Ok(Json(json!({
            "model": model_json(&new.to_file(None))?,
            "what": new.describe(),
            "degrees": new.surface_degrees(),
            "deviation": deviation,
        })))
    })
    .await
}

/// `{"model": M, "to": [n, m], "samples": K}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ApproxRequest {
    /// A polynomial `bezier_surface`.
    pub model: Value,
    /// The lower degrees.
    pub to: [usize; 2],
    /// Samples per direction of the error mesh (default 33).
    #[serde(default)]
    pub samples: Option<usize>,
}

/// `POST /api/surface/approximate`: the best L2 approximation of degrees `to` (each at most
/// the current one, one of them lower), with `l2_error` = sqrt(∫∫ |p − q|²), `linf_bound`
/// (guaranteed) and `linf_found` (attained on a 65×65 grid), and `mesh`: the approximation
/// coloured by its distance to the original.
pub async fn approximate(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ApproxRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let model = bezier_surface_of(&req.model, &limits)?;
        let BezierModel::Surface(s) = &model else {
            return Err(ApiError::unprocessable(
                "approximate reduction is for polynomial Bézier surfaces (this one has weights)",
            )
            .with("path", "model"));
        };
        let (n, m) = s.degrees();
        let [a, b] = req.to;
        if a > n || b > m || (a, b) == (n, m) {
            return Err(ApiError::unprocessable(format!(
                "approximate reduction goes to lower degrees: to = [{a}, {b}] but the surface \
                 has degrees ({n}, {m})"
            ))
            .with("path", "to"));
        }
        let k = samples_per_direction(req.samples, &limits)?;
        let r = s
            .reduce_degree_approx(a, b)
            .map_err(|e| ApiError::geometry("approximate", e))?;
        let reduced = AnyModel::Bezier(BezierModel::Surface(r.surface));
        let mesh = mesh(
            &reduced,
            k,
            Colour::Distance,
            Some(&AnyModel::Bezier(model.clone())),
        )?;
        let AnyModel::Bezier(new) = &reduced else {
            unreachable!()
        };
        Ok(Json(json!({
            "model": model_json(&new.to_file(None))?,
            "what": new.describe(),
            "l2_error": r.l2_error,
            "linf_bound": r.linf.upper_bound,
            "linf_found": r.linf.max_found,
            "mesh": mesh,
        })))
    })
    .await
}

/// `{"z": [[...]], "x": [...], "y": [...], "end": E, "samples": K, "colour": C}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightsRequest {
    /// The heights, `z[i][j]` at (x\[i\], y\[j\]).
    pub z: Vec<Vec<f64>>,
    /// Increasing coordinates of the rows (default 0, 1, ...).
    #[serde(default)]
    pub x: Option<Vec<f64>>,
    /// Increasing coordinates of the columns (default 0, 1, ...).
    #[serde(default)]
    pub y: Option<Vec<f64>>,
    /// End condition (as `/api/bspline/interpolate`; default not-a-knot).
    #[serde(default)]
    pub end: Option<Value>,
    /// Samples per direction of the mesh (default 33).
    #[serde(default)]
    pub samples: Option<usize>,
    /// Colour by `"gaussian"` (default) or `"mean"` curvature, or `"none"`.
    #[serde(default)]
    pub colour: Option<Colour>,
}

/// `POST /api/surface/heights`: the bicubic B-spline height field z(x, y) through the grid
/// (`interpolate_heights_at`; not-a-knot is SciPy's `RectBivariateSpline(x, y, z, s=0)`),
/// answered as `{"model" (a bspline_surface file in R^1), "what", "mesh"}` with the mesh
/// coloured by curvature.
pub async fn heights(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<HeightsRequest>,
) -> ApiResult<Json<Value>> {
    blocking(move || {
        let limits = state.config.limits;
        let rows = req.z.len();
        let cols = req.z.first().map_or(0, Vec::len);
        check_points("z", rows * cols, &limits)?;
        if let Some(i) = req.z.iter().position(|r| r.len() != cols) {
            return Err(ApiError::bad_request(format!(
                "z[{i}] has {} heights, z[0] has {cols}: every row needs the same number",
                req.z[i].len()
            ))
            .with("path", format!("z[{i}]")));
        }
        let axis = |given: &Option<Vec<f64>>, count: usize, name: &str| -> ApiResult<Vec<f64>> {
            match given {
                None => Ok((0..count).map(|i| i as f64).collect()),
                Some(a) if a.len() == count => Ok(a.clone()),
                Some(a) => Err(ApiError::bad_request(format!(
                    "{name} has {} coordinates for {count} grid lines",
                    a.len()
                ))
                .with("path", name)),
            }
        };
        let xs = axis(&req.x, rows, "x")?;
        let ys = axis(&req.y, cols, "y")?;
        let end = end_condition(req.end.as_ref(), false, 1)?;
        if matches!(end, EndCondition::Periodic | EndCondition::Repeat) {
            return Err(ApiError::bad_request(
                "heights take the end conditions not-a-knot, natural, clamped, bessel or outer",
            )
            .with("path", "end"));
        }
        let flat: Vec<f64> = req.z.iter().flatten().copied().collect();
        let surface = interpolate_heights_at(&flat, &xs, &ys, &end)
            .map_err(|e| ApiError::geometry("heights", e))?;
        let model = AnyModel::BsplineSurface(BsplineSurfaceModel {
            surface,
            parameters: Some((xs, ys)),
        });
        let k = samples_per_direction(req.samples, &limits)?;
        let mesh = mesh(&model, k, req.colour.unwrap_or(Colour::Gaussian), None)?;
        let AnyModel::BsplineSurface(m) = &model else {
            unreachable!()
        };
        Ok(Json(json!({
            "model": model_json(&m.to_file())?,
            "what": model.describe(),
            "mesh": mesh,
        })))
    })
    .await
}
