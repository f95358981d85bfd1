//! Every model file the commands write, as something to draw and mesh: a curve (with its
//! control polygon and reference points) or a surface (with its control net or source
//! points).

use super::shaded::{Overlay, Scene};
use crate::commands::compose::SurfaceModel;
use crate::figures::{add_polygon, View};
use crate::model::{parse_any_model, read_any_model, AnyModel, Model};
use crate::svg::{palette, Axes, Figure, Stroke};
use crate::table::extension;
use anyhow::{anyhow, bail, Context, Result};
use geomkit::bezier::BezierSurface;
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::geom::{Curve, Surface};
use geomkit::mesh::{
    tessellate_curve, tessellate_surface, CurveOptions, Polyline, SurfaceOptions, TriMesh,
};
use geomkit::pointcalc::{Nodes, PointEquation, PointSurface};
use serde_json::Value;
use std::path::Path;

/// A control net lifted to R^3: rows, columns, row-major points.
pub type Net = (usize, usize, Vec<[f64; 3]>);

/// A drawable, meshable model.
pub enum Shape {
    /// A curve.
    Curve {
        /// The curve.
        curve: Box<dyn Curve>,
        /// Control polygon and the parameter abscissa of each vertex (for 1-D graphs).
        control: Option<(Vec<Vec<f64>>, Vec<f64>)>,
        /// Reference points (t, point) the curve passes through.
        references: Vec<(f64, Vec<f64>)>,
    },
    /// A surface.
    Surface {
        /// The surface.
        surface: Box<dyn Surface>,
        /// Its control net in R^3, if it has one.
        net: Option<Net>,
        /// Points it passes through, in R^3.
        references: Vec<[f64; 3]>,
    },
}

/// A model read from a file, with a description.
pub struct Loaded {
    /// "Bézier surface of degrees (3, 3) in R^3 (4×4 net)".
    pub what: String,
    /// The model.
    pub shape: Shape,
}

/// A point of dimension 1, 2 or 3 in R^3 (1-D: `lift1` gives the abscissae).
fn to3(p: &[f64]) -> [f64; 3] {
    match p.len() {
        1 => [0.0, 0.0, p[0]],
        2 => [p[0], p[1], 0.0],
        _ => [p[0], p[1], p[2]],
    }
}

/// A net of dimension `dim` (row-major flat) in R^3; heights get the abscissae (us, vs).
fn net3(flat: &[f64], dim: usize, rows: usize, cols: usize, us: &[f64], vs: &[f64]) -> Net {
    let pts = flat
        .chunks_exact(dim)
        .enumerate()
        .map(|(k, p)| {
            if dim == 1 {
                [us[k / cols], vs[k % cols], p[0]]
            } else {
                to3(p)
            }
        })
        .collect();
    (rows, cols, pts)
}

fn greville(knots: &[f64], degree: usize, count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| knots[i + 1..=i + degree].iter().sum::<f64>() / degree as f64)
        .collect()
}

fn uniform(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.0
            }
        })
        .collect()
}

/// The shape of a Bézier surface: the surface and its net.
pub fn bezier_surface(s: BezierSurface) -> Shape {
    let (n, m) = s.degrees();
    let net = net3(
        s.net_flat(),
        s.dim(),
        n + 1,
        m + 1,
        &uniform(n + 1),
        &uniform(m + 1),
    );
    Shape::Surface {
        surface: Box::new(s),
        net: Some(net),
        references: Vec::new(),
    }
}

/// The shape of a B-spline surface: the surface, its net (heights at Greville abscissae)
/// and the grid points it interpolates, when known.
pub fn bspline_surface(s: BsplineSurface, parameters: Option<(Vec<f64>, Vec<f64>)>) -> Shape {
    let (p, q) = s.degrees();
    let (a, b) = s.net_size();
    let (ku, kv) = s.knots();
    let net = net3(
        s.control_flat(),
        s.dim(),
        a,
        b,
        &greville(ku, p, a),
        &greville(kv, q, b),
    );
    let references = match parameters {
        Some((us, vs)) => {
            let mut out = vec![0.0; us.len() * vs.len() * s.dim()];
            match s.eval_grid(&us, &vs, &mut out) {
                Ok(()) => net3(&out, s.dim(), us.len(), vs.len(), &us, &vs).2,
                Err(_) => Vec::new(),
            }
        }
        None => Vec::new(),
    };
    Shape::Surface {
        surface: Box::new(s),
        net: Some(net),
        references,
    }
}

fn bspline_curve(c: BsplineCurve, parameters: Option<Vec<f64>>) -> Shape {
    let d = c.dim();
    let control: Vec<Vec<f64>> = c
        .control_flat()
        .chunks_exact(d)
        .map(<[f64]>::to_vec)
        .collect();
    let abscissae = greville(c.knots(), c.degree(), c.n_control());
    let references = parameters
        .unwrap_or_default()
        .into_iter()
        .map(|t| (t, c.eval(t)))
        .collect();
    Shape::Curve {
        curve: Box::new(c),
        control: Some((control, abscissae)),
        references,
    }
}

/// The shape of a model of `geomkit bezier`/`interpolate`.
pub fn from_any(model: AnyModel) -> Loaded {
    let what = model.describe();
    let shape = match model {
        AnyModel::Bezier(Model::Curve(c)) => {
            let pts = c.points();
            let ts = uniform(pts.len());
            Shape::Curve {
                curve: Box::new(c),
                control: Some((pts, ts)),
                references: Vec::new(),
            }
        }
        AnyModel::Bezier(Model::Rational(c)) => {
            let pts = c.points();
            let ts = uniform(pts.len());
            Shape::Curve {
                curve: Box::new(c),
                control: Some((pts, ts)),
                references: Vec::new(),
            }
        }
        AnyModel::Bezier(Model::Surface(s)) => bezier_surface(s),
        AnyModel::BsplineCurve(m) => bspline_curve(m.curve, m.parameters),
        AnyModel::BsplineSurface(m) => bspline_surface(m.surface, m.parameters),
    };
    Loaded { what, shape }
}

/// A point-calculus model file (`pointcalc fit`): one factor is a curve, two factors a
/// surface (a, b, y(a, b)); one response.
fn pointcalc_model(v: &Value) -> Result<Loaded> {
    let factors = v
        .get("factors")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing \"factors\" of a pointcalc-model"))?;
    let values: Vec<f64> = v
        .get("values")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing \"values\" of a pointcalc-model"))?
        .iter()
        .enumerate()
        .map(|(k, x)| {
            x.as_f64()
                .ok_or_else(|| anyhow!("values[{k}] is not a number"))
        })
        .collect::<Result<_>>()?;
    let responses = v
        .get("response")
        .and_then(Value::as_array)
        .map_or(1, Vec::len);
    if responses != 1 {
        bail!("a pointcalc-model with {responses} responses cannot be drawn (one response only)");
    }
    let mut nodes = Vec::new();
    let mut names = Vec::new();
    for (k, f) in factors.iter().enumerate() {
        let vals: Vec<f64> = f
            .get("nodes")
            .and_then(Value::as_array)
            .ok_or_else(|| anyhow!("factors[{k}] has no \"nodes\""))?
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        names.push(
            f.get("name")
                .and_then(Value::as_str)
                .unwrap_or("?")
                .to_string(),
        );
        nodes.push(Nodes::new(vals).with_context(|| format!("factors[{k}]"))?);
    }
    match nodes.len() {
        1 => {
            let n = nodes.remove(0);
            if values.len() != n.len() {
                bail!("{} values for {} levels", values.len(), n.len());
            }
            let refs = n
                .values()
                .iter()
                .zip(&values)
                .map(|(&t, &y)| (t, vec![y]))
                .collect();
            let eq = PointEquation::new(n, values.iter().map(|&y| vec![y]).collect())?;
            Ok(Loaded {
                what: format!("point-calculus model of {} with one factor", names[0]),
                shape: Shape::Curve {
                    curve: Box::new(eq),
                    control: None,
                    references: refs,
                },
            })
        }
        2 => {
            let (a, b) = (nodes[0].clone(), nodes[1].clone());
            if values.len() != a.len() * b.len() {
                bail!("{} values for {}×{} levels", values.len(), a.len(), b.len());
            }
            // net[i][j] = (a_i, b_j, y_ij): the point equations reproduce the linear
            // coordinates exactly, so the surface is (a, b, y(a, b)).
            let net: Vec<Vec<Vec<f64>>> = a
                .values()
                .iter()
                .enumerate()
                .map(|(i, &x)| {
                    b.values()
                        .iter()
                        .enumerate()
                        .map(|(j, &y)| vec![x, y, values[i * b.len() + j]])
                        .collect()
                })
                .collect();
            let references = net.iter().flatten().map(|p| to3(p)).collect();
            let s = PointSurface::tensor(b, a, net)?;
            Ok(Loaded {
                what: format!("point-calculus model over {} and {}", names[0], names[1]),
                shape: Shape::Surface {
                    surface: Box::new(s),
                    net: None,
                    references,
                },
            })
        }
        k => bail!("a pointcalc-model with {k} factors cannot be drawn or meshed (1 or 2 only)"),
    }
}

/// Rows of numbers at `name`, all of one length.
fn rows(v: &Value, name: &str) -> Result<Vec<Vec<f64>>> {
    let arr = v
        .get(name)
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing array \"{name}\""))?;
    let rows: Vec<Vec<f64>> = arr
        .iter()
        .enumerate()
        .map(|(k, r)| {
            r.as_array()
                .ok_or_else(|| anyhow!("{name}[{k}] is not an array"))?
                .iter()
                .map(|x| {
                    x.as_f64()
                        .ok_or_else(|| anyhow!("{name}[{k}] holds a non-number"))
                })
                .collect()
        })
        .collect::<Result<_>>()?;
    if let Some(k) = rows
        .iter()
        .position(|r| r.len() != rows[0].len() || r.is_empty())
    {
        bail!(
            "{name}[{k}] has {} numbers, {name}[0] has {}",
            rows[k].len(),
            rows[0].len()
        );
    }
    Ok(rows)
}

fn numbers(v: &Value, name: &str) -> Result<Vec<f64>> {
    v.get(name)
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing array \"{name}\""))?
        .iter()
        .enumerate()
        .map(|(k, x)| {
            x.as_f64()
                .ok_or_else(|| anyhow!("{name}[{k}] is not a number"))
        })
        .collect()
}

/// Samples (t, x, ...) joined by straight segments: the polyline through them.
struct SampledCurve {
    ts: Vec<f64>,
    dim: usize,
    points: Vec<f64>,
}

impl Curve for SampledCurve {
    fn dim(&self) -> usize {
        self.dim
    }
    fn domain(&self) -> (f64, f64) {
        (self.ts[0], self.ts[self.ts.len() - 1])
    }
    fn breaks(&self) -> Vec<f64> {
        self.ts.clone()
    }
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        let n = self.ts.len();
        let k = self.ts.partition_point(|&x| x <= t).clamp(1, n - 1) - 1;
        let (t0, t1) = (self.ts[k], self.ts[k + 1]);
        let f = if t1 > t0 {
            ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (a, b) = (
            &self.points[k * self.dim..],
            &self.points[(k + 1) * self.dim..],
        );
        for c in 0..self.dim {
            out[c] = a[c] + f * (b[c] - a[c]);
        }
    }
}

/// `pointcalc curve -o X.json`: samples [t, x, y, ...] of the curve.
fn sampled_curve(v: &Value) -> Result<Loaded> {
    let samples = rows(v, "samples")?;
    if samples.len() < 2 || samples[0].len() < 2 {
        bail!("a pointcalc-curve needs at least 2 samples [t, x, ...]");
    }
    let ts: Vec<f64> = samples.iter().map(|r| r[0]).collect();
    if let Some(k) = ts.windows(2).position(|w| w[1] <= w[0]) {
        bail!("samples[{}]: t must increase", k + 1);
    }
    let dim = samples[0].len() - 1;
    let points = samples.iter().flat_map(|r| r[1..].to_vec()).collect();
    Ok(Loaded {
        what: format!("point-equation curve in R^{dim}, {} samples", ts.len()),
        shape: Shape::Curve {
            curve: Box::new(SampledCurve { ts, dim, points }),
            control: None,
            references: Vec::new(),
        },
    })
}

/// A grid of samples joined bilinearly.
struct SampledSurface {
    us: Vec<f64>,
    vs: Vec<f64>,
    dim: usize,
    points: Vec<f64>,
}

impl Surface for SampledSurface {
    fn dim(&self) -> usize {
        self.dim
    }
    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        // Finite parameters of a trait caller: the grid of one point cannot fail.
        let _ = self.eval_grid(&[u], &[v], out);
    }
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (
            (self.us[0], self.us[self.us.len() - 1]),
            (self.vs[0], self.vs[self.vs.len() - 1]),
        )
    }
    fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> geomkit::Result<()> {
        let locate = |xs: &[f64], x: f64| {
            let k = xs.partition_point(|&y| y <= x).clamp(1, xs.len() - 1) - 1;
            let f = ((x - xs[k]) / (xs[k + 1] - xs[k])).clamp(0.0, 1.0);
            (k, f)
        };
        let (d, nv) = (self.dim, self.vs.len());
        let p = |i: usize, j: usize, c: usize| self.points[(i * nv + j) * d + c];
        for (a, &u) in us.iter().enumerate() {
            let (i, f) = locate(&self.us, u);
            for (b, &v) in vs.iter().enumerate() {
                let (j, g) = locate(&self.vs, v);
                for c in 0..d {
                    out[(a * vs.len() + b) * d + c] = (1.0 - f) * (1.0 - g) * p(i, j, c)
                        + f * (1.0 - g) * p(i + 1, j, c)
                        + (1.0 - f) * g * p(i, j + 1, c)
                        + f * g * p(i + 1, j + 1, c);
                }
            }
        }
        Ok(())
    }
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        (self.us.clone(), self.vs.clone())
    }
}

/// `pointcalc surface -o X.json`: a u × v grid of samples.
fn sampled_surface(v: &Value) -> Result<Loaded> {
    let (us, vs) = (numbers(v, "u")?, numbers(v, "v")?);
    let points = rows(v, "points")?;
    if us.len() < 2 || vs.len() < 2 || points.len() != us.len() * vs.len() {
        bail!(
            "a pointcalc-surface-samples needs u and v with at least 2 values each and \
             u × v points ({} × {} given, {} points)",
            us.len(),
            vs.len(),
            points.len()
        );
    }
    for (name, xs) in [("u", &us), ("v", &vs)] {
        if let Some(k) = xs.windows(2).position(|w| w[1] <= w[0]) {
            bail!("{name}[{}] must be greater than the previous value", k + 1);
        }
    }
    let dim = points[0].len();
    Ok(Loaded {
        what: format!(
            "point-equation surface in R^{dim}, {}×{} samples",
            us.len(),
            vs.len()
        ),
        shape: Shape::Surface {
            surface: Box::new(SampledSurface {
                us,
                vs,
                dim,
                points: points.concat(),
            }),
            net: None,
            references: Vec::new(),
        },
    })
}

/// Reads any model file: Bézier and B-spline JSON (and control-point CSV/.npy pairs),
/// composite scenes, point-calculus models and the curve/surface samples of `pointcalc
/// curve|surface` (joined by straight segments / bilinear cells).
pub fn load(path: &Path) -> Result<Loaded> {
    if matches!(extension(path).as_deref(), Some("npy" | "csv")) {
        return Ok(from_any(read_any_model(path)?));
    }
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse(&text).with_context(|| path.display().to_string())
}

/// Parses a model from JSON text (see [`load`]).
pub fn parse(text: &str) -> Result<Loaded> {
    let v: Value = serde_json::from_str(text).map_err(|e| anyhow!("invalid JSON: {e}"))?;
    if let Some(model) = SurfaceModel::from_json(&v) {
        let model = model?;
        return Ok(Loaded {
            what: model.describe(),
            shape: Shape::Surface {
                surface: model.into_shape(),
                net: None,
                references: Vec::new(),
            },
        });
    }
    match v.get("type").and_then(Value::as_str) {
        Some("pointcalc-model") => pointcalc_model(&v),
        Some("pointcalc-curve") => sampled_curve(&v),
        Some("pointcalc-surface-samples") => sampled_surface(&v),
        _ => Ok(from_any(parse_any_model(text)?)),
    }
}

/// How to tessellate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampling {
    /// Adaptive to an absolute tolerance (None: 1/1000 of the size for surfaces, 1/2000 for
    /// curves).
    Tolerance(Option<f64>),
    /// K × L uniform samples (curves: K).
    Samples(usize, usize),
}

/// A tessellated model.
pub enum Tessellation {
    /// A curve.
    Polyline(Polyline),
    /// A surface.
    Mesh(TriMesh),
}

/// Tessellates a loaded model.
pub fn tessellate(loaded: &Loaded, sampling: Sampling) -> Result<Tessellation> {
    Ok(match &loaded.shape {
        Shape::Curve { curve, .. } => {
            let mut opts = CurveOptions::default();
            match sampling {
                Sampling::Tolerance(t) => opts.tolerance = t,
                Sampling::Samples(k, _) => {
                    if k < 2 {
                        bail!("--samples: a curve needs at least 2 samples, got {k}");
                    }
                    // Uniform: no refinement beyond K - 1 segments.
                    opts.min_segments = k - 1;
                    opts.tolerance = Some(f64::MAX);
                }
            }
            Tessellation::Polyline(tessellate_curve(curve.as_ref(), &opts)?)
        }
        Shape::Surface { surface, .. } => {
            let opts = match sampling {
                Sampling::Tolerance(Some(t)) => SurfaceOptions::adaptive(t),
                Sampling::Tolerance(None) => SurfaceOptions::default(),
                Sampling::Samples(k, l) => SurfaceOptions::uniform(k, l),
            };
            Tessellation::Mesh(tessellate_surface(surface.as_ref(), &opts)?)
        }
    })
}

/// Picture options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureOptions {
    /// Camera for 3-D.
    pub view: View,
    /// Size in px of a shaded surface picture (curve pictures size themselves).
    pub size: (f64, f64),
    /// Draw the control net or polygon.
    pub net: bool,
}

impl Default for PictureOptions {
    fn default() -> Self {
        PictureOptions {
            view: View::default(),
            size: (720.0, 540.0),
            net: true,
        }
    }
}

/// Samples per direction of the mesh of a shaded picture.
const PICTURE_SAMPLES: usize = 60;

/// The picture of a loaded model as SVG: a curve with its control polygon and reference
/// points, or a shaded surface with its net and reference points.
pub fn picture_svg(
    loaded: &Loaded,
    title: &str,
    subtitle: &str,
    opts: &PictureOptions,
) -> Result<String> {
    match &loaded.shape {
        Shape::Curve {
            curve,
            control,
            references,
        } => curve_svg(
            curve.as_ref(),
            control.as_ref().filter(|_| opts.net),
            references,
            title,
            subtitle,
            opts.view,
        ),
        Shape::Surface {
            surface,
            net,
            references,
        } => {
            let mesh = tessellate_surface(
                surface.as_ref(),
                &SurfaceOptions::uniform(PICTURE_SAMPLES, PICTURE_SAMPLES),
            )?;
            let mut scene = Scene::new(title, subtitle)
                .view(opts.view)
                .size(opts.size)
                .solid(&mesh);
            if let (Some((rows, cols, points)), true) = (net, opts.net) {
                scene = scene.overlay(Overlay::Net {
                    points: points.clone(),
                    rows: *rows,
                    cols: *cols,
                    color: palette::NEW_VERTEX,
                    legend: format!("control net, {rows}×{cols}"),
                });
            }
            if !references.is_empty() {
                scene = scene.overlay(Overlay::Points {
                    points: references.clone(),
                    color: "#222222",
                    radius: 2.4,
                    labels: Vec::new(),
                    legend: format!("{} points it passes through", references.len()),
                });
            }
            Ok(scene.render())
        }
    }
}

/// A curve picture: the adaptive polyline, the control polygon with labels, the reference
/// points. 1-D curves are graphs over the parameter, 3-D ones in the axonometric `view`.
pub fn curve_svg(
    curve: &dyn Curve,
    control: Option<&(Vec<Vec<f64>>, Vec<f64>)>,
    references: &[(f64, Vec<f64>)],
    title: &str,
    subtitle: &str,
    view: View,
) -> Result<String> {
    let dim = curve.dim();
    let page = |t: f64, p: &[f64]| -> [f64; 2] {
        match dim {
            1 => [t, p[0]],
            2 => [p[0], p[1]],
            _ => view.project(p),
        }
    };
    let axes = match dim {
        1 => Axes::Chart {
            x: "t".into(),
            y: "x".into(),
        },
        2 => Axes::Equal,
        3 => Axes::Bare,
        d => bail!("cannot draw a curve in R^{d} (pictures need 1-, 2- or 3-D points)"),
    };
    let line = tessellate_curve(curve, &CurveOptions::default())?;
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    let pts: Vec<[f64; 2]> = (0..line.len())
        .map(|k| page(line.params()[k], line.point(k)))
        .collect();
    if let Some((points, ts)) = control {
        let poly: Vec<[f64; 2]> = points.iter().zip(ts).map(|(p, &t)| page(t, p)).collect();
        let n = poly.len().max(1) as f64;
        let c = poly
            .iter()
            .fold([0.0, 0.0], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n]);
        add_polygon(
            &mut fig,
            &poly,
            palette::NEW_POLYGON,
            palette::NEW_VERTEX,
            "p",
            true,
            c,
        );
        fig.legend(
            palette::NEW_POLYGON,
            Some(palette::NEW_VERTEX),
            format!("control polygon, {} points", poly.len()),
        );
    }
    fig.line(pts, palette::CURVE);
    fig.legend(palette::CURVE, None, "curve");
    if !references.is_empty() {
        let dots: Vec<[f64; 2]> = references.iter().map(|(t, p)| page(*t, p)).collect();
        fig.dots(dots, 3.6, "#222222");
        fig.legend(
            Stroke::solid("#222222", 0.0),
            Some("#222222"),
            format!("{} points it passes through", references.len()),
        );
    }
    Ok(fig.render())
}
