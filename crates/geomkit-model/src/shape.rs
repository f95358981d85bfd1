//! Models as something to draw and mesh: a curve (with its control polygon and the points it
//! passes through) or a surface (with its control net or source points), and its
//! tessellation. Every front end draws and meshes through [`Loaded`].

use crate::error::{Error, Result};
use crate::model::{AnyModel, BezierModel, PointcalcModel};
use geomkit::bezier::{BezierSurface, RationalBezierSurface};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::geom::{Curve, Surface};
use geomkit::mesh::{
    tessellate_curve_with_progress, tessellate_surface_with_progress, CurveOptions, MeshReport,
    Polyline, SurfaceOptions, TriMesh,
};
use geomkit::pointcalc::{Nodes, PointEquation, PointSurface};

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
    let net = bezier_net(s.net_flat(), s.dim(), s.degrees());
    Shape::Surface {
        surface: Box::new(s),
        net: Some(net),
        references: Vec::new(),
    }
}

/// The shape of a rational Bézier surface: the surface and its (Cartesian) net.
pub fn rational_bezier_surface(s: RationalBezierSurface) -> Shape {
    let net = bezier_net(s.net_flat(), s.dim(), s.degrees());
    Shape::Surface {
        surface: Box::new(s),
        net: Some(net),
        references: Vec::new(),
    }
}

/// A Bézier net of degrees (n, m) drawn at uniform parameters.
fn bezier_net(flat: &[f64], dim: usize, (n, m): (usize, usize)) -> Net {
    net3(flat, dim, n + 1, m + 1, &uniform(n + 1), &uniform(m + 1))
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

/// A Bézier curve and its control polygon, vertex i at abscissa i/n (for 1-D graphs).
fn bezier_curve(points: Vec<Vec<f64>>, curve: Box<dyn Curve>) -> Shape {
    let ts = uniform(points.len());
    Shape::Curve {
        curve,
        control: Some((points, ts)),
        references: Vec::new(),
    }
}

impl Loaded {
    /// The shape of any model; errors for models that are neither one curve nor one surface
    /// (a point-calculus model of 3 or more factors, a formula file without its model).
    pub fn from_model(model: AnyModel) -> Result<Loaded> {
        let what = model.describe();
        let shape = match model {
            AnyModel::Bezier(BezierModel::Curve(c)) => bezier_curve(c.points(), Box::new(c)),
            AnyModel::Bezier(BezierModel::Rational(c)) => bezier_curve(c.points(), Box::new(c)),
            AnyModel::Bezier(BezierModel::Surface(s)) => bezier_surface(s),
            AnyModel::Bezier(BezierModel::RationalSurface(s)) => rational_bezier_surface(s),
            AnyModel::BsplineCurve(m) => bspline_curve(m.curve, m.parameters),
            AnyModel::BsplineSurface(m) => bspline_surface(m.surface, m.parameters),
            AnyModel::Composite(s) => plain_surface(Box::new(s)),
            AnyModel::Ruled(s) => plain_surface(Box::new(s)),
            AnyModel::Piecewise(p) => Shape::Curve {
                curve: Box::new(p),
                control: None,
                references: Vec::new(),
            },
            AnyModel::Formula(f) => match f.model {
                Some(m) => return Loaded::from_model(*m),
                None => return Err(Error::model(
                    "",
                    "this formula file carries no model (written by an older geomkit): mesh or \
                     draw it with `geomkit compose ... -o OUT.obj|.png`",
                )),
            },
            AnyModel::Pointcalc(m) => pointcalc_shape(&m)?,
            AnyModel::CurveSamples(c) => Shape::Curve {
                curve: Box::new(c),
                control: None,
                references: Vec::new(),
            },
            AnyModel::SurfaceSamples(s) => plain_surface(Box::new(s)),
        };
        Ok(Loaded { what, shape })
    }

    /// Tessellates the model: a polyline of a curve, a triangle mesh of a surface.
    ///
    /// Errors: fewer than 2 or more than 1 000 000 samples of a curve, and the tessellators'
    /// errors (a tolerance that is not finite and > 0 or out of reach within the caps,
    /// points of a dimension that cannot be meshed, a mesh that is empty or, for a surface
    /// that closes, not watertight; see [`geomkit::mesh::tessellate_surface`]).
    pub fn tessellate(&self, sampling: Sampling) -> geomkit::Result<Tessellation> {
        self.tessellate_report(sampling).map(|(t, _)| t)
    }

    /// [`Loaded::tessellate`] with the surface mesher's report (None for a curve): whether
    /// the triangle cap stopped adaptive refinement and the deviation it reached.
    pub fn tessellate_report(
        &self,
        sampling: Sampling,
    ) -> geomkit::Result<(Tessellation, Option<MeshReport>)> {
        self.tessellate_with_progress(sampling, &geomkit::progress::Progress::none())
    }

    /// [`Loaded::tessellate_report`] reporting the meshing to `progress`
    /// ([`geomkit::mesh::tessellate_surface_with_progress`] for a surface,
    /// [`geomkit::mesh::tessellate_curve_with_progress`] for a curve); `Error::Cancelled`
    /// when its callback asks to stop.
    pub fn tessellate_with_progress(
        &self,
        sampling: Sampling,
        progress: &geomkit::progress::Progress,
    ) -> geomkit::Result<(Tessellation, Option<MeshReport>)> {
        Ok(match &self.shape {
            Shape::Curve { curve, .. } => {
                let mut opts = CurveOptions::default();
                match sampling {
                    Sampling::Tolerance(t) => opts.tolerance = t,
                    Sampling::Samples(k, _) => {
                        if k < 2 {
                            return Err(geomkit::Error::InvalidOption {
                                option: "samples",
                                reason: "a curve needs at least 2 samples",
                            });
                        }
                        // Uniform: no refinement beyond K - 1 segments.
                        opts.min_segments = k - 1;
                        opts.tolerance = Some(f64::MAX);
                    }
                }
                (
                    Tessellation::Polyline(tessellate_curve_with_progress(
                        curve.as_ref(),
                        &opts,
                        progress,
                    )?),
                    None,
                )
            }
            Shape::Surface { surface, .. } => {
                let opts = match sampling {
                    Sampling::Tolerance(Some(t)) => SurfaceOptions::adaptive(t),
                    Sampling::Tolerance(None) => SurfaceOptions::default(),
                    Sampling::Samples(k, l) => SurfaceOptions::uniform(k, l),
                };
                let (mesh, report) =
                    tessellate_surface_with_progress(surface.as_ref(), &opts, progress)?;
                (Tessellation::Mesh(mesh), Some(report))
            }
        })
    }
}

/// A surface without a net or reference points.
fn plain_surface(surface: Box<dyn Surface>) -> Shape {
    Shape::Surface {
        surface,
        net: None,
        references: Vec::new(),
    }
}

/// A point-calculus model: one factor is a curve, two factors a surface (a, b, y(a, b));
/// one response.
fn pointcalc_shape(m: &PointcalcModel) -> Result<Shape> {
    let model = &m.model;
    if model.dim() != 1 {
        return Err(Error::model(
            "response",
            format!(
                "has {} responses: a pointcalc-model is drawn or meshed with one response",
                model.dim()
            ),
        ));
    }
    let values = model.values();
    let nodes: Vec<&Nodes> = model.factors().iter().map(|f| f.nodes()).collect();
    match nodes[..] {
        [n] => {
            let references = n
                .values()
                .iter()
                .zip(values)
                .map(|(&t, &y)| (t, vec![y]))
                .collect();
            let eq = PointEquation::new(n.clone(), values.iter().map(|&y| vec![y]).collect())
                .map_err(|e| Error::geometry("", e))?;
            Ok(Shape::Curve {
                curve: Box::new(eq),
                control: None,
                references,
            })
        }
        [a, b] => {
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
            let s = PointSurface::tensor(b.clone(), a.clone(), net)
                .map_err(|e| Error::geometry("", e))?;
            Ok(Shape::Surface {
                surface: Box::new(s),
                net: None,
                references,
            })
        }
        _ => Err(Error::model(
            "factors",
            format!(
                "has {} factors: a pointcalc-model is drawn or meshed with 1 or 2",
                nodes.len()
            ),
        )),
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
