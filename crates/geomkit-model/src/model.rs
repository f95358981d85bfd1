//! Files as geometry: [`AnyModel`] is what a [`ModelFile`] describes, checked by the library
//! (knots, weights, formulas, node sets), with errors at the JSON path of the value at fault.

use crate::error::{Error, Result};
use crate::numbers::{count, Net, Points};
use crate::sampled::{SampledCurve, SampledSurface};
use crate::schema::*;
use geomkit::bezier::{BezierCurve, BezierSurface, RationalBezierCurve, RationalBezierSurface};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::compose::{
    CompositeSurface, ExprPatch, Piecewise, PolyPatch, RuledCurve, RuledSurface, SurfaceKind,
};
use geomkit::exact::Rational;
use geomkit::pointcalc::{Factor, Hypersurface, Nodes, PointOptions};

/// A Bézier model: the input and output of `geomkit bezier`.
#[derive(Debug, Clone, PartialEq)]
pub enum BezierModel {
    /// A polynomial Bézier curve.
    Curve(BezierCurve),
    /// A rational Bézier curve.
    Rational(RationalBezierCurve),
    /// A tensor-product Bézier surface.
    Surface(BezierSurface),
    /// A rational tensor-product Bézier surface.
    RationalSurface(RationalBezierSurface),
}

/// A B-spline curve and, for an interpolating curve, the parameters of its reference points.
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineCurveModel {
    /// The curve.
    pub curve: BsplineCurve,
    /// Parameters of the reference points, if known.
    pub parameters: Option<Vec<f64>>,
}

/// A B-spline surface and, for an interpolating surface, the grid parameters of its
/// reference points (rows in u, columns in v).
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineSurfaceModel {
    /// The surface.
    pub surface: BsplineSurface,
    /// Parameters of the grid rows (u) and columns (v), if known.
    pub parameters: Option<(Vec<f64>, Vec<f64>)>,
}

/// A point-calculus k-factor model and the names of its responses.
#[derive(Debug, Clone)]
pub struct PointcalcModel {
    /// The model.
    pub model: Hypersurface,
    /// One name per response (coordinate of the values).
    pub response: Vec<String>,
}

/// A formula file: the formulas as printed, and the model they were made from.
#[derive(Debug, Clone)]
pub struct FormulaModel {
    /// The file (its `model` field moved out into [`FormulaModel::model`]).
    pub file: FormulaFile,
    /// The model the formula was made from, as geometry; `None` for files that carry none
    /// (written by geomkit before 0.1 for `compose piecewise`).
    pub model: Option<Box<AnyModel>>,
}

/// Any model a file can hold, as geometry.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum AnyModel {
    /// A Bézier curve or surface.
    Bezier(BezierModel),
    /// A B-spline curve.
    BsplineCurve(BsplineCurveModel),
    /// A B-spline surface.
    BsplineSurface(BsplineSurfaceModel),
    /// A composite surface of patches (a scene of `compose patches`).
    Composite(CompositeSurface),
    /// A piecewise-ruled surface (`compose ruled`, the bodies).
    Ruled(RuledSurface),
    /// A piecewise function or composite curve (`compose piecewise`).
    Piecewise(Piecewise),
    /// A formula file and its model.
    Formula(FormulaModel),
    /// A point-calculus model (`pointcalc fit`).
    Pointcalc(PointcalcModel),
    /// Samples of a point-equation curve, joined by straight segments.
    CurveSamples(SampledCurve),
    /// Samples of a point-equation surface, joined by bilinear cells.
    SurfaceSamples(SampledSurface),
}

impl BezierModel {
    /// What the model is, for messages: "Bézier curve of degree 5 in R^2 (6 control points)".
    pub fn describe(&self) -> String {
        match self {
            BezierModel::Curve(c) => format!(
                "Bézier curve of degree {} in R^{} ({} control points)",
                c.degree(),
                c.dim(),
                c.degree() + 1
            ),
            BezierModel::Rational(r) => format!(
                "rational Bézier curve of degree {} in R^{} ({} control points)",
                r.degree(),
                r.points().first().map_or(0, Vec::len),
                r.degree() + 1
            ),
            BezierModel::Surface(s) => surface_description("", s.degrees(), s.dim()),
            BezierModel::RationalSurface(s) => {
                surface_description("rational ", s.degrees(), s.dim())
            }
        }
    }

    /// The model as a file, with the error report of an approximate reduction.
    pub fn to_file(&self, error: Option<ReductionError>) -> ModelFile {
        match self {
            BezierModel::Curve(c) => ModelFile::BezierCurve(BezierCurveFile {
                points: Points {
                    dim: c.dim(),
                    flat: c.points_flat().to_vec(),
                },
                weights: None,
                error,
            }),
            BezierModel::Rational(r) => ModelFile::BezierCurve(BezierCurveFile {
                points: Points::from_rows(&r.points()),
                weights: Some(r.weights()),
                error,
            }),
            BezierModel::Surface(s) => ModelFile::BezierSurface(BezierSurfaceFile {
                net: net_file(s.degrees(), s.dim(), s.net_flat()),
                weights: None,
            }),
            BezierModel::RationalSurface(s) => ModelFile::BezierSurface(BezierSurfaceFile {
                net: net_file(s.degrees(), s.dim(), s.net_flat()),
                weights: Some(s.weights()),
            }),
        }
    }
}

impl BezierModel {
    /// The degrees (n, m) of a (rational) surface; `None` for curves.
    pub fn surface_degrees(&self) -> Option<(usize, usize)> {
        match self {
            BezierModel::Surface(s) => Some(s.degrees()),
            BezierModel::RationalSurface(s) => Some(s.degrees()),
            BezierModel::Curve(_) | BezierModel::Rational(_) => None,
        }
    }

    /// Formula (14) on a (rational) surface: the same surface of degrees (n, m), each
    /// direction elevated or exactly reduced with `tolerance`; `None` for curves.
    pub fn change_surface_degree(
        &self,
        n: usize,
        m: usize,
        tolerance: Option<f64>,
    ) -> Option<geomkit::Result<BezierModel>> {
        match self {
            BezierModel::Surface(s) => {
                Some(s.change_degree(n, m, tolerance).map(BezierModel::Surface))
            }
            BezierModel::RationalSurface(s) => Some(
                s.change_degree(n, m, tolerance)
                    .map(BezierModel::RationalSurface),
            ),
            BezierModel::Curve(_) | BezierModel::Rational(_) => None,
        }
    }
}

/// "Bézier surface of degrees (3, 2) in R^3 (4×3 net)", `kind` before it.
fn surface_description(kind: &str, (n, m): (usize, usize), dim: usize) -> String {
    format!(
        "{kind}Bézier surface of degrees ({n}, {m}) in R^{dim} ({}×{} net)",
        n + 1,
        m + 1
    )
}

/// The file form of a net of degrees (n, m).
fn net_file((n, m): (usize, usize), dim: usize, flat: &[f64]) -> Net {
    Net {
        rows: n + 1,
        cols: m + 1,
        dim,
        flat: flat.to_vec(),
    }
}

impl BsplineCurveModel {
    /// The model as a file.
    pub fn to_file(&self) -> ModelFile {
        Self::file_of(&self.curve, self.parameters.as_deref())
    }

    /// The file of `curve` with the parameters of its reference points.
    pub fn file_of(curve: &BsplineCurve, parameters: Option<&[f64]>) -> ModelFile {
        ModelFile::BsplineCurve(BsplineCurveFile {
            degree: curve.degree(),
            knots: curve.knots().to_vec(),
            control_points: Points {
                dim: curve.dim(),
                flat: curve.control_flat().to_vec(),
            },
            parameters: parameters.map(<[f64]>::to_vec),
        })
    }
}

impl BsplineSurfaceModel {
    /// The model as a file.
    pub fn to_file(&self) -> ModelFile {
        let parameters = self.parameters.as_ref();
        Self::file_of(&self.surface, parameters.map(|(u, v)| (&u[..], &v[..])))
    }

    /// The file of `s` with the grid parameters of its reference points.
    pub fn file_of(s: &BsplineSurface, parameters: Option<(&[f64], &[f64])>) -> ModelFile {
        let (p, q) = s.degrees();
        let (ku, kv) = s.knots();
        let (rows, cols) = s.net_size();
        let (pu, pv) = parameters.map(|(u, v)| (u.to_vec(), v.to_vec())).unzip();
        ModelFile::BsplineSurface(BsplineSurfaceFile {
            degree: [p, q],
            knots_u: ku.to_vec(),
            knots_v: kv.to_vec(),
            net: Net {
                rows,
                cols,
                dim: s.dim(),
                flat: s.control_flat().to_vec(),
            },
            parameters_u: pu,
            parameters_v: pv,
        })
    }
}

impl PointcalcModel {
    /// The model as a file (exact levels as rationals where the nodes are).
    pub fn to_file(&self) -> ModelFile {
        Self::file_of(&self.model, &self.response)
    }

    /// The file of `model` with the names of its responses.
    pub fn file_of(model: &Hypersurface, response: &[String]) -> ModelFile {
        let factors = model
            .factors()
            .iter()
            .map(|f| FactorFile {
                name: f.name().to_string(),
                nodes: f.nodes().values().to_vec(),
                exact: f.nodes().is_rational().then(|| {
                    f.nodes()
                        .exact_values()
                        .iter()
                        .map(|r| r.to_string())
                        .collect()
                }),
            })
            .collect();
        ModelFile::PointcalcModel(PointcalcModelFile {
            factors,
            response: response.to_vec(),
            values: model.values().to_vec(),
        })
    }
}

impl AnyModel {
    /// What the model is, for messages and pictures.
    pub fn describe(&self) -> String {
        match self {
            AnyModel::Bezier(m) => m.describe(),
            AnyModel::BsplineCurve(m) => format!(
                "B-spline curve of degree {} in R^{} ({} control points)",
                m.curve.degree(),
                m.curve.dim(),
                m.curve.n_control()
            ),
            AnyModel::BsplineSurface(m) => {
                let (p, q) = m.surface.degrees();
                let (a, b) = m.surface.net_size();
                format!(
                    "B-spline surface of degrees ({p}, {q}) in R^{} ({a}×{b} net)",
                    m.surface.dim()
                )
            }
            AnyModel::Composite(s) => {
                let (a, b) = s.cells();
                format!("composite surface of {a}×{b} patches in R^{}", s.dim())
            }
            AnyModel::Ruled(s) => format!("ruled surface over {} curves", s.curves().len()),
            AnyModel::Piecewise(p) => {
                let pieces = p.knots().len().saturating_sub(1);
                if p.dim() == 1 {
                    format!("piecewise function of {}", count(pieces, "piece"))
                } else {
                    format!(
                        "composite curve in R^{} of {}",
                        p.dim(),
                        count(pieces, "piece")
                    )
                }
            }
            AnyModel::Formula(f) => match &f.model {
                Some(m) => format!("formula of a {}", m.describe()),
                None => format!("formula of {}", f.file.what),
            },
            AnyModel::Pointcalc(m) => {
                let names: Vec<&str> = m.model.factors().iter().map(Factor::name).collect();
                format!(
                    "point-calculus model of {} over {}",
                    m.response.join(", "),
                    names.join(", ")
                )
            }
            AnyModel::CurveSamples(c) => {
                format!("point-equation curve in R^{}, {} samples", c.dim(), c.len())
            }
            AnyModel::SurfaceSamples(s) => {
                let (a, b) = s.grid_size();
                format!("point-equation surface in R^{}, {a}×{b} samples", s.dim())
            }
        }
    }

    /// The geometry of a file: every check of the library, errors at the JSON path.
    pub fn from_file(file: ModelFile) -> Result<AnyModel> {
        Ok(match file {
            ModelFile::BezierCurve(f) => AnyModel::Bezier(bezier_curve(f)?),
            ModelFile::BezierSurface(f) => AnyModel::Bezier(bezier_surface(f)?),
            ModelFile::BsplineCurve(f) => AnyModel::BsplineCurve(bspline_curve(f)?),
            ModelFile::BsplineSurface(f) => AnyModel::BsplineSurface(bspline_surface(f)?),
            ModelFile::CompositeSurface(f) => AnyModel::Composite(composite(
                f.u_knots,
                f.v_knots,
                f.patches,
                SurfaceKind::Parametric,
            )?),
            ModelFile::CompositeExplicit(f) => AnyModel::Composite(composite(
                f.x_knots,
                f.y_knots,
                f.patches,
                SurfaceKind::Explicit,
            )?),
            ModelFile::Ruled(f) => AnyModel::Ruled(ruled(f)?),
            ModelFile::Piecewise(f) => AnyModel::Piecewise(piecewise(f)?),
            ModelFile::Polyline(f) => AnyModel::Piecewise(polyline(f, false)?),
            ModelFile::Polygon(f) => AnyModel::Piecewise(polyline(f, true)?),
            ModelFile::Formula(mut f) => {
                let model = match f.model.take() {
                    // A formula of `compose patches` over a saved B-spline surface: its
                    // cells, as the formula has them.
                    Some(m) => Some(Box::new(match *m {
                        ModelFile::BsplineSurface(s) => {
                            let s = bspline_surface(s).map_err(|e| e.under("model"))?;
                            AnyModel::Composite(
                                CompositeSurface::from_bspline(&s.surface)
                                    .map_err(|e| Error::geometry("model", e))?,
                            )
                        }
                        m => AnyModel::from_file(m).map_err(|e| e.under("model"))?,
                    })),
                    None => None,
                };
                AnyModel::Formula(FormulaModel { file: f, model })
            }
            ModelFile::PointcalcModel(f) => AnyModel::Pointcalc(pointcalc_model(f)?),
            ModelFile::PointcalcCurve(f) => AnyModel::CurveSamples(SampledCurve::new(
                f.samples.dim.saturating_sub(1),
                f.samples.rows().map(|r| r[0]).collect(),
                f.samples.rows().flat_map(|r| r[1..].to_vec()).collect(),
            )?),
            ModelFile::PointcalcSurfaceSamples(f) => {
                AnyModel::SurfaceSamples(SampledSurface::new(f.u, f.v, f.points)?)
            }
        })
    }
}

fn bezier_curve(f: BezierCurveFile) -> Result<BezierModel> {
    if f.points.is_empty() {
        return Err(Error::model(
            "points",
            "is empty: a curve needs at least one control point",
        ));
    }
    let Points { dim, flat } = f.points;
    let n = flat.len() / dim;
    match f.weights {
        None => BezierCurve::from_flat(dim, flat)
            .map(BezierModel::Curve)
            .map_err(|e| Error::geometry("points", e)),
        Some(w) => {
            if w.len() != n {
                return Err(Error::model(
                    "weights",
                    format!(
                        "{} weights for {n} control points (give one weight per point)",
                        w.len()
                    ),
                ));
            }
            let rows = flat.chunks_exact(dim).map(<[f64]>::to_vec).collect();
            RationalBezierCurve::new(rows, w)
                .map(BezierModel::Rational)
                .map_err(|e| Error::geometry("weights", e))
        }
    }
}

/// A net with at least one point.
fn check_net(net: &Net) -> Result<()> {
    if net.rows == 0 {
        return Err(Error::model(
            "net",
            "is empty: a surface needs at least one row of control points",
        ));
    }
    if net.cols == 0 {
        return Err(Error::model(
            "net[0]",
            "is empty: every row needs at least one control point",
        ));
    }
    Ok(())
}

fn bezier_surface(f: BezierSurfaceFile) -> Result<BezierModel> {
    let n = f.net;
    check_net(&n)?;
    let Some(w) = f.weights else {
        return BezierSurface::from_flat(n.rows, n.cols, n.dim, n.flat)
            .map(BezierModel::Surface)
            .map_err(|e| Error::geometry("net", e));
    };
    if w.len() != n.rows {
        return Err(Error::model(
            "weights",
            format!(
                "has {} for a net of {} (give one row of weights per row of the net)",
                count(w.len(), "row"),
                count(n.rows, "row")
            ),
        ));
    }
    if let Some(i) = w.iter().position(|r| r.len() != n.cols) {
        return Err(Error::model(
            format!("weights[{i}]"),
            format!(
                "has {} for a net of {} per row (give one weight per control point)",
                count(w[i].len(), "weight"),
                count(n.cols, "point")
            ),
        ));
    }
    // Check the net first, so that its errors say "net".
    BezierSurface::from_flat(n.rows, n.cols, n.dim, n.flat.clone())
        .map_err(|e| Error::geometry("net", e))?;
    RationalBezierSurface::from_flat(n.rows, n.cols, n.dim, n.flat, w.concat())
        .map(BezierModel::RationalSurface)
        .map_err(|e| Error::geometry("weights", e))
}

/// A B-spline surface degree (1..=7) at `path`.
fn degree(p: usize, path: &str) -> Result<usize> {
    degree_in(p, path, 1, 7)
}

/// A degree from `lo` to `hi` at `path`.
fn degree_in(p: usize, path: &str, lo: usize, hi: usize) -> Result<usize> {
    if (lo..=hi).contains(&p) {
        Ok(p)
    } else {
        Err(Error::model(
            path,
            format!("must be an integer from {lo} to {hi}, found {p}"),
        ))
    }
}

fn bspline_curve(f: BsplineCurveFile) -> Result<BsplineCurveModel> {
    // Curves: step functions (degree 0, SciPy's k = 0) to antiderivatives of degree 15.
    let p = degree_in(f.degree, "degree", 0, BsplineCurve::MAX_DEGREE)?;
    if f.control_points.is_empty() {
        return Err(Error::model("control_points", "is empty"));
    }
    let c = f.control_points;
    let curve =
        BsplineCurve::from_flat(p, f.knots, c.dim, c.flat).map_err(|e| Error::geometry("", e))?;
    Ok(BsplineCurveModel {
        curve,
        parameters: f.parameters,
    })
}

fn bspline_surface(f: BsplineSurfaceFile) -> Result<BsplineSurfaceModel> {
    let degrees = (
        degree(f.degree[0], "degree[0]")?,
        degree(f.degree[1], "degree[1]")?,
    );
    let n = f.net;
    check_net(&n)?;
    let parameters = match (f.parameters_u, f.parameters_v) {
        (Some(u), Some(v)) => Some((u, v)),
        (None, None) => None,
        _ => {
            return Err(Error::model(
                "",
                "give both \"parameters_u\" and \"parameters_v\" or neither",
            ))
        }
    };
    let surface =
        BsplineSurface::from_flat(degrees, f.knots_u, f.knots_v, n.rows, n.cols, n.dim, n.flat)
            .map_err(|e| Error::geometry("", e))?;
    Ok(BsplineSurfaceModel {
        surface,
        parameters,
    })
}

/// One patch of a scene, as read.
enum ScenePatch {
    Poly(PolyPatch),
    Expr(Box<ExprPatch>),
}

/// The coordinates and variables of a scene's formulas.
fn scene_names(kind: SurfaceKind) -> (&'static [&'static str], [&'static str; 2]) {
    match kind {
        SurfaceKind::Explicit => (&["z"], ["x", "y"]),
        SurfaceKind::Parametric => (&["x", "y", "z"], ["u", "v"]),
    }
}

fn scene_patch(p: Patch, kind: SurfaceKind) -> Result<ScenePatch> {
    let explicit = kind == SurfaceKind::Explicit;
    let (names, vars) = scene_names(kind);
    let o =
        match p {
            Patch::Formula(z) if explicit => PatchObject {
                z: Some(z),
                ..PatchObject::default()
            },
            Patch::Formula(_) => return Err(Error::model(
                "",
                "a parametric patch is {\"x\": \"..\", \"y\": \"..\", \"z\": \"..\"} in u, v or \
                 {\"bezier\": [[[x,y,z],...],...]}; a lone formula is a patch z(x, y) of a \
                 \"composite_explicit\" scene",
            )),
            Patch::Object(o) => o,
        };
    if let Some(net) = o.bezier {
        if o.x.is_some() || o.y.is_some() || o.z.is_some() || o.domain.is_some() {
            return Err(Error::model(
                "",
                "a patch is either {\"bezier\": net} or formulas, not both",
            ));
        }
        check_net(&net).map_err(|e| e.under("bezier"))?;
        let b = BezierSurface::from_flat(net.rows, net.cols, net.dim, net.flat)
            .map_err(|e| Error::geometry("bezier", e))?;
        return Ok(ScenePatch::Poly(PolyPatch::from_bezier(&b)));
    }
    let texts: Vec<(&str, &str)> = [("x", &o.x), ("y", &o.y), ("z", &o.z)]
        .into_iter()
        .filter(|(n, _)| names.contains(n))
        .filter_map(|(n, t)| t.as_deref().map(|t| (n, t)))
        .collect();
    let complete = if explicit {
        o.z.is_some() && o.x.is_none() && o.y.is_none()
    } else {
        o.x.is_some() && o.y.is_some()
    };
    if !complete {
        return Err(Error::model(
            "",
            if explicit {
                "expected a formula in x, y, {\"z\": \"..\"} or {\"bezier\": [[[z],...],...]}"
            } else {
                "expected {\"x\": \"..\", \"y\": \"..\", \"z\": \"..\"} in u, v or {\"bezier\": \
                 [[[x,y,z],...],...]}"
            },
        ));
    }
    let domain = o
        .domain
        .map(|d| d.into_iter().map(|[a, b]| (a, b)).collect());
    ExprPatch::parse(&texts, &vars, domain)
        .map(|e| ScenePatch::Expr(Box::new(e)))
        .map_err(|e| Error::geometry("", e))
}

fn composite(
    uk: Vec<f64>,
    vk: Vec<f64>,
    rows: Vec<Vec<Patch>>,
    kind: SurfaceKind,
) -> Result<CompositeSurface> {
    let mut patches: Vec<Vec<ScenePatch>> = Vec::with_capacity(rows.len());
    for (i, row) in rows.into_iter().enumerate() {
        let mut out = Vec::with_capacity(row.len());
        for (j, p) in row.into_iter().enumerate() {
            out.push(scene_patch(p, kind).map_err(|e| e.under(&format!("patches[{i}][{j}]")))?);
        }
        patches.push(out);
    }
    let polys: Option<Vec<Vec<PolyPatch>>> = patches
        .iter()
        .map(|r| {
            r.iter()
                .map(|p| match p {
                    ScenePatch::Poly(p) => Some(p.clone()),
                    ScenePatch::Expr(_) => None,
                })
                .collect()
        })
        .collect();
    if let Some(polys) = polys {
        return CompositeSurface::from_poly(uk, vk, polys, kind)
            .map_err(|e| Error::geometry("", e));
    }
    let (names, vars) = scene_names(kind);
    let mut exprs = Vec::with_capacity(patches.len());
    for (i, row) in patches.into_iter().enumerate() {
        let mut out = Vec::with_capacity(row.len());
        for (j, p) in row.into_iter().enumerate() {
            out.push(match p {
                ScenePatch::Expr(e) => *e,
                ScenePatch::Poly(p) => ExprPatch::from_poly(&p, names, vars)
                    .map_err(|e| Error::geometry(format!("patches[{i}][{j}]"), e))?,
            });
        }
        exprs.push(out);
    }
    CompositeSurface::from_expr(uk, vk, exprs, kind).map_err(|e| Error::geometry("", e))
}

fn ruled_curve(c: RuledCurveFile) -> Result<RuledCurve> {
    let kinds = [
        c.point.is_some(),
        c.polygon.is_some(),
        c.polyline.is_some(),
        c.circle.is_some(),
        c.x.is_some() || c.y.is_some() || c.z.is_some() || c.t.is_some(),
    ];
    if kinds.iter().filter(|&&k| k).count() > 1 {
        return Err(Error::model(
            "",
            "give one of \"point\", \"polygon\", \"polyline\", \"circle\" or formulas x, y, z \
             in t",
        ));
    }
    let vertices = |v: Vec<Points3>| v.into_iter().map(|p| p.0).collect::<Vec<_>>();
    let curve = if let Some(p) = c.point {
        Ok(RuledCurve::Point(p.0))
    } else if let Some(p) = c.polygon {
        RuledCurve::polygon(vertices(p))
    } else if let Some(p) = c.polyline {
        RuledCurve::polyline(vertices(p))
    } else if let Some(circle) = c.circle {
        Ok(RuledCurve::Circle {
            center: circle.center.0,
            radius: circle.radius,
        })
    } else {
        let (Some(x), Some(y)) = (&c.x, &c.y) else {
            return Err(Error::model(
                "",
                format!(
                    "missing \"{}\": give x, y, z as formulas in t and \"t\":[t0,t1], or \
                     \"point\", \"polygon\", \"polyline\", \"circle\"",
                    if c.x.is_none() { "x" } else { "y" }
                ),
            ));
        };
        let Some([t0, t1]) = c.t else {
            return Err(Error::model("t", "is missing: give \"t\": [t0, t1]"));
        };
        RuledCurve::formula([x, y, c.z.as_deref().unwrap_or("0")], (t0, t1))
    };
    curve.map_err(|e| Error::geometry("", e))
}

fn ruled(f: RuledFile) -> Result<RuledSurface> {
    let curves = f
        .curves
        .into_iter()
        .enumerate()
        .map(|(k, c)| ruled_curve(c).map_err(|e| e.under(&format!("curves[{k}]"))))
        .collect::<Result<Vec<_>>>()?;
    if let Some(k) = f.v.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::model(
            "v",
            format!(
                "must be strictly increasing: v[{}] = {} after v[{k}] = {}",
                k + 1,
                f.v[k + 1],
                f.v[k]
            ),
        ));
    }
    let [u0, u1] = f.u.unwrap_or([0.0, 1.0]);
    RuledSurface::new(curves, f.v, (u0, u1)).map_err(|e| Error::geometry("", e))
}

/// A ruled surface as its file, or `None` when a curve is a formula in another variable
/// than t (bodies built in code).
pub fn ruled_file(s: &RuledSurface) -> Option<RuledFile> {
    let curves = s
        .curves()
        .iter()
        .map(|c| {
            let mut f = RuledCurveFile::default();
            let points = |v: &[[f64; 3]]| v.iter().map(|&p| Points3(p)).collect();
            match c {
                RuledCurve::Point(p) => f.point = Some(Points3(*p)),
                RuledCurve::Polyline { vertices, closed } if *closed => {
                    f.polygon = Some(points(vertices))
                }
                RuledCurve::Polyline { vertices, .. } => f.polyline = Some(points(vertices)),
                RuledCurve::Circle { center, radius } => {
                    f.circle = Some(Circle {
                        center: Points3(*center),
                        radius: *radius,
                    })
                }
                RuledCurve::Expr(e) if e.vars() == ["t"] && e.texts().len() == 3 => {
                    let (t0, t1) = c.interval();
                    let t = e.texts();
                    f.x = Some(t[0].clone());
                    f.y = Some(t[1].clone());
                    f.z = Some(t[2].clone());
                    f.t = Some([t0, t1]);
                }
                _ => return None,
            }
            Some(f)
        })
        .collect::<Option<Vec<_>>>()?;
    let ((u0, u1), _) = s.domain();
    Some(RuledFile {
        u: Some([u0, u1]),
        v: s.v_values().to_vec(),
        curves,
    })
}

fn piecewise(f: PiecewiseFile) -> Result<Piecewise> {
    if f.pieces.iter().all(|p| matches!(p, Piece::Function(_))) {
        let texts: Vec<&str> = f
            .pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Function(t) => Some(t.as_str()),
                Piece::Curve(_) => None,
            })
            .collect();
        return Piecewise::function(f.knots, &texts).map_err(|e| Error::geometry("", e));
    }
    let mut parsed = Vec::with_capacity(f.pieces.len());
    for (i, p) in f.pieces.into_iter().enumerate() {
        let place = format!("pieces[{i}]");
        let Piece::Curve(c) = p else {
            return Err(Error::model(
                place,
                "is a formula in x, but other pieces are curves {\"x\": .., \"y\": ..} in t: \
                 give every piece in one form",
            ));
        };
        let mut coords = vec![("x", c.x.as_str()), ("y", c.y.as_str())];
        if let Some(z) = &c.z {
            coords.push(("z", z));
        }
        let domain = c.domain.map(|[a, b]| vec![(a, b)]);
        parsed.push(
            ExprPatch::parse(&coords, &["t"], domain).map_err(|e| Error::geometry(place, e))?,
        );
    }
    Piecewise::from_pieces(f.knots, parsed, "t").map_err(|e| Error::geometry("", e))
}

fn polyline(f: PolylineFile, closed: bool) -> Result<Piecewise> {
    Piecewise::polyline(f.points.to_rows(), f.knots, closed).map_err(|e| Error::geometry("", e))
}

/// An exact node "1/3", "0.25" or "2".
fn rational(x: &str) -> Option<Rational> {
    x.parse::<Rational>()
        .ok()
        .or_else(|| geomkit::exact::rational_from_f64(x.parse().ok()?))
}

fn pointcalc_model(f: PointcalcModelFile) -> Result<PointcalcModel> {
    if f.response.is_empty() {
        return Err(Error::model(
            "response",
            "is empty: a model has at least one response name",
        ));
    }
    let mut factors = Vec::with_capacity(f.factors.len());
    for (k, factor) in f.factors.into_iter().enumerate() {
        let place = format!("factors[{k}]");
        let nodes = match &factor.exact {
            Some(e) => {
                if e.len() != factor.nodes.len() {
                    return Err(Error::model(
                        format!("{place}.exact"),
                        format!(
                            "has {} but \"nodes\" has {}",
                            count(e.len(), "value"),
                            factor.nodes.len()
                        ),
                    ));
                }
                let exact = e
                    .iter()
                    .enumerate()
                    .map(|(i, x)| {
                        let r = rational(x).ok_or_else(|| {
                            Error::model(
                                format!("{place}.exact[{i}]"),
                                format!("is {x:?}, which is not a number or fraction"),
                            )
                        })?;
                        // The exact level and its f64 value must be the same number.
                        let v = geomkit::exact::rational_to_f64(&r);
                        if v != factor.nodes[i] {
                            return Err(Error::model(
                                format!("{place}.exact[{i}]"),
                                format!(
                                    "is {x:?} ({v}), but \"nodes\"[{i}] is {}: they \
                                     must be the same level",
                                    factor.nodes[i]
                                ),
                            ));
                        }
                        Ok(r)
                    })
                    .collect::<Result<Vec<_>>>()?;
                Nodes::from_rationals(exact)
                    .map_err(|e| Error::geometry(format!("{place}.exact"), e))?
            }
            None => Nodes::new(factor.nodes)
                .map_err(|e| Error::geometry(format!("{place}.nodes"), e))?,
        };
        factors.push(Factor::new(factor.name, nodes));
    }
    let dim = f.response.len();
    let model =
        Hypersurface::new(factors, dim, f.values, &PointOptions::default()).map_err(|e| {
            let place = match &e {
                geomkit::Error::InvalidOption { .. } | geomkit::Error::Empty { .. } => "factors",
                _ => "values",
            };
            Error::geometry(place, e)
        })?;
    Ok(PointcalcModel {
        model,
        response: f.response,
    })
}
