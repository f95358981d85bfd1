//! Pictures of curves and surfaces built on [`crate::svg`]: a curve with its old and new
//! control polygons (the paper's Fig. 1 and 2), and surfaces as a wireframe of iso-curves with
//! their control nets in a fixed axonometric view (Fig. 4 and 5); interpolating B-spline
//! curves with their control polygons and reference points, and height fields as a shaded
//! map with contour lines.
//!
//! Points of dimension 2 are drawn as they are, dimension 3 in the axonometric view, and
//! dimension 1 as the graph of the function (control point i at abscissa i/n, which is exact
//! for Bézier functions since Σ b_ni(t) i/n = t).

use crate::svg::{palette, Axes, Cell, Figure, Label, Placement, Stroke};
use crate::Result;
use geomkit::bezier::BezierSurface;
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::compose::Piecewise;
use geomkit::geom::Curve;
use geomkit::geom::Surface;
use geomkit::pointcalc::PointEquation;

/// Points of `surface` on the grid `us` × `vs` (row-major) as drawn: heights z(u, v) (1-D
/// points) become (u, v, z); 2- and 3-D points stay. Returns (points, their dimension).
fn drawn_grid(surface: &dyn Surface, us: &[f64], vs: &[f64]) -> Result<(Vec<f64>, usize)> {
    let d = surface.dim();
    let mut grid = vec![0.0; us.len() * vs.len() * d];
    surface.eval_grid(us, vs, &mut grid)?;
    if d != 1 {
        return Ok((grid, d));
    }
    let lifted = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .zip(&grid)
        .flat_map(|((u, v), &z)| [u, v, z])
        .collect();
    Ok((lifted, 3))
}

pub use geomkit::geom::linspace;

/// A fixed axonometric view: the viewer looks from `azimuth` (about the z axis, from the x
/// axis) and `elevation` (above the xy plane); z is up on the page.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Degrees.
    pub azimuth: f64,
    /// Degrees.
    pub elevation: f64,
}

impl Default for View {
    fn default() -> Self {
        View {
            azimuth: 35.0,
            elevation: 25.0,
        }
    }
}

impl View {
    /// Page coordinates (right, up) of a point in R^3 (R^2 points get z = 0).
    pub fn project(&self, p: &[f64]) -> [f64; 2] {
        let (a, e) = (self.azimuth.to_radians(), self.elevation.to_radians());
        let (x, y, z) = (
            p[0],
            p.get(1).copied().unwrap_or(0.0),
            p.get(2).copied().unwrap_or(0.0),
        );
        // Viewer direction d = (cos e cos a, cos e sin a, sin e); right = z × d normalized,
        // up = d × right.
        let right = [-a.sin(), a.cos(), 0.0];
        let up = [-e.sin() * a.cos(), -e.sin() * a.sin(), e.cos()];
        [
            x * right[0] + y * right[1] + z * right[2],
            x * up[0] + y * up[1] + z * up[2],
        ]
    }
}

/// How control points and curve points of some dimension become page points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Dimension 1: the graph (t, x(t)).
    Graph,
    /// Dimension 2: as is.
    Plane,
    /// Dimension 3: axonometric.
    Axonometric(View),
}

impl Projection {
    /// The projection for points of dimension `dim`; errors above 3.
    pub fn for_dim(dim: usize) -> Result<Self> {
        Ok(match dim {
            1 => Projection::Graph,
            2 => Projection::Plane,
            3 => Projection::Axonometric(View::default()),
            d => {
                return Err(crate::Error::Unsupported(format!(
                    "cannot draw points of dimension {d} (SVG output needs 1-, 2- or 3-D points)"
                )))
            }
        })
    }

    /// Control polygon on the page.
    pub fn polygon(&self, points: &[Vec<f64>]) -> Vec<[f64; 2]> {
        let n = points.len().saturating_sub(1).max(1) as f64;
        points
            .iter()
            .enumerate()
            .map(|(i, p)| self.point(i as f64 / n, p))
            .collect()
    }

    /// A point of the curve at parameter t on the page.
    pub fn point(&self, t: f64, p: &[f64]) -> [f64; 2] {
        match self {
            Projection::Graph => [t, p[0]],
            Projection::Plane => [p[0], p[1]],
            Projection::Axonometric(v) => v.project(p),
        }
    }

    /// `count` uniform samples of a curve on the page.
    pub fn curve(&self, curve: &dyn Curve, count: usize) -> Vec<[f64; 2]> {
        (0..count)
            .map(|k| {
                let t = k as f64 / (count - 1) as f64;
                self.point(t, &curve.eval(t))
            })
            .collect()
    }
}

fn centroid(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len().max(1) as f64;
    let s = points
        .iter()
        .fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
    [s[0] / n, s[1] / n]
}

/// Labels only for polygons small enough to read.
const MAX_LABELS: usize = 21;

/// Adds a control polygon: line, vertex dots, and labels `base`₀ … `base`ₙ on the side
/// chosen by `outward` (away from or toward the centroid of `reference`).
pub fn add_polygon(
    fig: &mut Figure,
    polygon: &[[f64; 2]],
    stroke: Stroke,
    vertex: &'static str,
    base: &str,
    outward: bool,
    reference: [f64; 2],
) {
    fig.line(polygon.to_vec(), stroke);
    fig.dots(polygon.to_vec(), 3.4, vertex);
    if polygon.len() <= MAX_LABELS {
        let items = polygon
            .iter()
            .enumerate()
            .map(|(i, p)| (*p, Label::new(base, i)))
            .collect();
        let placement = if outward {
            Placement::Away(reference)
        } else {
            Placement::Toward(reference)
        };
        fig.labels(items, vertex, placement);
    }
}

/// The curve-change picture: the old control polygon (dashed grey, u₀ … uₙ), the new one
/// (orange, u′₀ … u′ₙ′) and the curve. When `new_curve` is given (an approximation) both
/// curves are drawn, the old one faint.
pub fn curve_change_svg(
    title: &str,
    subtitle: &str,
    old: (&dyn Curve, &[Vec<f64>]),
    new: (Option<&dyn Curve>, &[Vec<f64>]),
) -> Result<String> {
    let proj = Projection::for_dim(old.0.dim())?;
    let old_poly = proj.polygon(old.1);
    let new_poly = proj.polygon(new.1);
    // After an exact change the polygon with more vertices lies inside the convex hull of the
    // other: label the outer one outward and the inner one inward, both relative to the outer
    // polygon's centroid, so that labels of shared end points do not collide.
    let old_outer = new.0.is_some() || new.1.len() >= old.1.len();
    let c = centroid(if old_outer { &old_poly } else { &new_poly });
    let axes = match proj {
        Projection::Axonometric(_) => Axes::Bare,
        Projection::Plane => Axes::Equal,
        Projection::Graph => Axes::Chart {
            x: "t (vertex i at i/n)".into(),
            y: "x".into(),
        },
    };
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    let old_n = old.1.len() - 1;
    let new_n = new.1.len() - 1;
    if let Some(new_curve) = new.0 {
        fig.line(proj.curve(old.0, 400), palette::GHOST);
        fig.legend(
            palette::GHOST,
            None,
            format!("original curve (degree {old_n})"),
        );
        add_polygon(
            &mut fig,
            &old_poly,
            palette::OLD_POLYGON,
            palette::OLD_VERTEX,
            "u",
            old_outer,
            c,
        );
        add_polygon(
            &mut fig,
            &new_poly,
            palette::NEW_POLYGON,
            palette::NEW_VERTEX,
            "u′",
            !old_outer,
            c,
        );
        fig.line(proj.curve(new_curve, 400), palette::CURVE);
        fig.legend(palette::CURVE, None, format!("new curve (degree {new_n})"));
    } else {
        add_polygon(
            &mut fig,
            &old_poly,
            palette::OLD_POLYGON,
            palette::OLD_VERTEX,
            "u",
            old_outer,
            c,
        );
        fig.line(proj.curve(old.0, 400), palette::CURVE);
        add_polygon(
            &mut fig,
            &new_poly,
            palette::NEW_POLYGON,
            palette::NEW_VERTEX,
            "u′",
            !old_outer,
            c,
        );
        fig.legend(palette::CURVE, None, "curve (unchanged)");
    }
    fig.legend(
        palette::OLD_POLYGON,
        Some(palette::OLD_VERTEX),
        format!("old polygon, degree {old_n}"),
    );
    fig.legend(
        palette::NEW_POLYGON,
        Some(palette::NEW_VERTEX),
        format!("new polygon, degree {new_n}"),
    );
    Ok(fig.render())
}

/// A surface layer of a surface picture.
pub enum Layer<'a> {
    /// Wireframe of `count` u- and v-iso-curves, 64 samples each.
    Wireframe {
        /// The surface.
        surface: &'a dyn Surface,
        /// Iso-curves per direction.
        count: usize,
        /// Line style.
        stroke: Stroke,
        /// Legend text.
        legend: String,
    },
    /// The control net: lines along rows and columns, vertex dots, corner labels.
    Net {
        /// The surface whose net is drawn.
        surface: &'a BezierSurface,
        /// Line style.
        stroke: Stroke,
        /// Vertex colour.
        vertex: &'static str,
        /// Label base of the corners ("u" → u₀₀, u₆₀, ...), if any.
        corners: Option<&'static str>,
        /// Legend text.
        legend: String,
    },
    /// Points (row-major, `dim` coordinates each), joined along the rows and columns of a
    /// `grid` (rows, cols) when a stroke is given (a control net), else dots only.
    Points {
        /// The points.
        points: &'a [f64],
        /// Their dimension (2 or 3).
        dim: usize,
        /// Rows and columns, for the net lines.
        grid: Option<(usize, usize)>,
        /// Net line style, if lines are drawn.
        stroke: Option<Stroke>,
        /// Dot colour.
        vertex: &'static str,
        /// Dot radius in pixels.
        radius: f64,
        /// Legend text.
        legend: String,
    },
}

/// The wireframe of one surface (`lines` iso-curves each way, heights drawn as (u, v, z)) in
/// the fixed axonometric view: the picture of a structural evaluator.
pub fn wireframe_svg(
    surface: &dyn Surface,
    title: &str,
    subtitle: &str,
    lines: usize,
) -> Result<String> {
    surface_svg(
        title,
        subtitle,
        &[Layer::Wireframe {
            surface,
            count: lines,
            stroke: palette::CURVE.with_opacity(0.8),
            legend: "structural evaluator".into(),
        }],
    )
}

/// A picture of surfaces in the fixed axonometric view (azimuth 35°, elevation 25°).
/// Surfaces must be 2- or 3-D.
pub fn surface_svg(title: &str, subtitle: &str, layers: &[Layer<'_>]) -> Result<String> {
    let view = View::default();
    let mut fig = Figure::new(title, Axes::Bare).subtitle(subtitle);
    for layer in layers {
        let dim = match layer {
            // Heights are drawn as (u, v, z).
            Layer::Wireframe { surface, .. } => match surface.dim() {
                1 => 3,
                d => d,
            },
            Layer::Net { surface, .. } => surface.dim(),
            Layer::Points { dim, .. } => *dim,
        };
        if !(2..=3).contains(&dim) {
            return Err(crate::Error::Unsupported(format!(
                "cannot draw a surface in R^{dim} (SVG output needs 2- or 3-D points)"
            )));
        }
    }
    for layer in layers {
        match layer {
            Layer::Wireframe {
                surface,
                count,
                stroke,
                legend,
            } => {
                let k = 64;
                let ((u0, u1), (v0, v1)) = surface.domain();
                let (fine_u, fine_v) = (linspace(u0, u1, k), linspace(v0, v1, k));
                let (iso_u, iso_v) = (linspace(u0, u1, *count), linspace(v0, v1, *count));
                // u-iso-curves (u fixed, v running) and v-iso-curves.
                let (grid, d) = drawn_grid(*surface, &iso_u, &fine_v)?;
                for line in grid.chunks_exact(k * d) {
                    fig.line(
                        line.chunks_exact(d).map(|p| view.project(p)).collect(),
                        *stroke,
                    );
                }
                let (grid, d) = drawn_grid(*surface, &fine_u, &iso_v)?;
                for b in 0..iso_v.len() {
                    let pts = (0..k)
                        .map(|a| {
                            let o = (a * iso_v.len() + b) * d;
                            view.project(&grid[o..o + d])
                        })
                        .collect();
                    fig.line(pts, *stroke);
                }
                fig.legend(*stroke, None, legend.clone());
            }
            Layer::Net {
                surface,
                stroke,
                vertex,
                corners,
                legend,
            } => {
                let (n, m) = surface.degrees();
                let p = |i: usize, j: usize| view.project(surface.point(i, j));
                for i in 0..=n {
                    fig.line((0..=m).map(|j| p(i, j)).collect(), *stroke);
                }
                for j in 0..=m {
                    fig.line((0..=n).map(|i| p(i, j)).collect(), *stroke);
                }
                let all: Vec<[f64; 2]> = (0..=n)
                    .flat_map(|i| (0..=m).map(move |j| (i, j)))
                    .map(|(i, j)| p(i, j))
                    .collect();
                let c = centroid(&all);
                fig.dots(all, 2.6, vertex);
                if let Some(base) = corners {
                    let mut items = Vec::new();
                    for (i, j) in [(0, 0), (n, 0), (0, m), (n, m)] {
                        let label = Label::new(base, format!("{i}{j}"));
                        if !items.iter().any(|(_, l): &([f64; 2], Label)| *l == label) {
                            items.push((p(i, j), label));
                        }
                    }
                    fig.labels(items, vertex, Placement::Away(c));
                }
                fig.legend(*stroke, Some(vertex), legend.clone());
            }
            Layer::Points {
                points,
                dim,
                grid,
                stroke,
                vertex,
                radius,
                legend,
            } => {
                let page: Vec<[f64; 2]> =
                    points.chunks_exact(*dim).map(|p| view.project(p)).collect();
                if let (Some((rows, cols)), Some(stroke)) = (grid, stroke) {
                    for row in page.chunks_exact(*cols) {
                        fig.line(row.to_vec(), *stroke);
                    }
                    for j in 0..*cols {
                        fig.line((0..*rows).map(|i| page[i * cols + j]).collect(), *stroke);
                    }
                }
                fig.dots(page, *radius, vertex);
                let key = stroke.unwrap_or(Stroke::solid(vertex, 0.0));
                fig.legend(key, Some(vertex), legend.clone());
            }
        }
    }
    Ok(fig.render())
}

/// The usual surface picture: a 16×16 wireframe in the curve colour and its control net.
pub fn surface_with_net<'a>(
    surface: &'a BezierSurface,
    net_stroke: Stroke,
    vertex: &'static str,
) -> [Layer<'a>; 2] {
    let (n, m) = surface.degrees();
    [
        Layer::Wireframe {
            surface,
            count: 16,
            stroke: Stroke::solid(palette::CURVE.color, 1.0),
            legend: format!("surface, degrees ({n}, {m})"),
        },
        Layer::Net {
            surface,
            stroke: net_stroke,
            vertex,
            corners: Some("u"),
            legend: format!("control net, {}×{}", n + 1, m + 1),
        },
    ]
}

/// Greville abscissae of a B-spline: where control point i sits along the parameter axis.
fn greville(curve: &BsplineCurve) -> Vec<f64> {
    let p = curve.degree();
    let k = curve.knots();
    (0..curve.n_control())
        .map(|i| k[i + 1..=i + p].iter().sum::<f64>() / p as f64)
        .collect()
}

/// A picture of an interpolating B-spline curve: the curve (blue), its control polygon
/// (orange, p₀ … labelled when short) and the reference points (dark dots). 2-D points are
/// drawn as they are, 3-D in the axonometric view, 1-D as the graph over the parameter
/// (control points at their Greville abscissae).
pub fn bspline_curve_figure(
    title: &str,
    subtitle: &str,
    curve: &BsplineCurve,
    points: &[f64],
    parameters: &[f64],
) -> Result<Figure> {
    let proj = Projection::for_dim(curve.dim())?;
    let axes = match proj {
        Projection::Axonometric(_) => Axes::Bare,
        Projection::Plane => Axes::Equal,
        Projection::Graph => Axes::Chart {
            x: "t".into(),
            y: "x".into(),
        },
    };
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    let mut control: Vec<[f64; 2]> = curve
        .control_flat()
        .chunks_exact(curve.dim())
        .zip(greville(curve))
        .map(|(p, t)| proj.point(t, p))
        .collect();
    // A periodic curve repeats its first `degree` control points at the end: draw the
    // distinct ones as a closed polygon (except for graphs, where they sit elsewhere on t).
    let (d, p, n) = (curve.dim(), curve.degree(), curve.n_control());
    let flat = curve.control_flat();
    let closed = n >= 2 * p && flat[..p * d] == flat[(n - p) * d..];
    if closed && proj != Projection::Graph {
        control.truncate(n - p);
        control.push(control[0]);
    }
    let refs: Vec<[f64; 2]> = points
        .chunks_exact(curve.dim())
        .zip(parameters)
        .map(|(p, &t)| proj.point(t, p))
        .collect();
    let distinct = &control[..control.len() - usize::from(closed && proj != Projection::Graph)];
    fig.line(control.clone(), palette::NEW_POLYGON);
    fig.dots(distinct.to_vec(), 3.4, palette::NEW_VERTEX);
    if distinct.len() <= MAX_LABELS {
        // Coinciding points (the paper's repeated end points) share one label "p₀,₁,₂".
        let mut items: Vec<([f64; 2], Vec<usize>)> = Vec::new();
        for (i, p) in distinct.iter().enumerate() {
            match items.last_mut() {
                Some((q, ids)) if q == p => ids.push(i),
                _ => items.push((*p, vec![i])),
            }
        }
        let items = items
            .into_iter()
            .map(|(p, ids)| {
                let sub: Vec<String> = ids.iter().map(ToString::to_string).collect();
                (p, Label::new("p", sub.join(",")))
            })
            .collect();
        fig.labels(
            items,
            palette::NEW_VERTEX,
            Placement::Away(centroid(distinct)),
        );
    }
    fig.line(curve_on_page(proj, curve), palette::CURVE);
    fig.dots(refs, 4.2, REFERENCE);
    fig.legend(palette::CURVE, None, "interpolating cubic B-spline");
    fig.legend(
        palette::NEW_POLYGON,
        Some(palette::NEW_VERTEX),
        if closed {
            format!("closed control polygon, {} points", n - p)
        } else {
            format!("control polygon, {n} points")
        },
    );
    fig.legend(
        Stroke::solid(REFERENCE, 0.0),
        Some(REFERENCE),
        format!("reference points ({})", points.len() / curve.dim()),
    );
    Ok(fig)
}

/// Colour of reference points.
pub const REFERENCE: &str = "#222222";

/// A B-spline curve sampled on the page: 40 samples per knot span, 200 to 20 000.
pub fn curve_on_page(proj: Projection, curve: &BsplineCurve) -> Vec<[f64; 2]> {
    let (a, b) = curve.domain();
    let spans = curve.n_control().saturating_sub(curve.degree()).max(1);
    let count = (40 * spans).clamp(200, 20_000);
    linspace(a, b, count)
        .into_iter()
        .map(|t| proj.point(t, &curve.eval(t)))
        .collect()
}

/// A terrain colour map from low (deep blue) through green and brown to high (white).
const TERRAIN: [(f64, [f64; 3]); 6] = [
    (0.0, [38.0, 70.0, 140.0]),
    (0.18, [74.0, 150.0, 200.0]),
    (0.35, [92.0, 168.0, 96.0]),
    (0.6, [200.0, 190.0, 110.0]),
    (0.82, [150.0, 105.0, 70.0]),
    (1.0, [250.0, 250.0, 250.0]),
];

/// Legend swatches of [`TERRAIN`]: low, middle, high.
const TERRAIN_KEYS: [&str; 3] = ["#26468c", "#c8be6e", "#fafafa"];

/// The colour of level `x` in [0, 1], quantized to `levels` steps.
fn terrain_color(x: f64, levels: usize) -> String {
    let x = ((x.clamp(0.0, 1.0) * levels as f64)
        .floor()
        .min(levels as f64 - 1.0)
        + 0.5)
        / levels as f64;
    let k = TERRAIN
        .iter()
        .position(|s| s.0 >= x)
        .unwrap_or(TERRAIN.len() - 1)
        .max(1);
    let ((x0, c0), (x1, c1)) = (TERRAIN[k - 1], TERRAIN[k]);
    let w = ((x - x0) / (x1 - x0)).clamp(0.0, 1.0);
    let c: Vec<u8> = (0..3)
        .map(|i| (c0[i] + w * (c1[i] - c0[i])).round() as u8)
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// Contour segments of level `h` on a grid of values `z` (rows × cols) at coordinates
/// `xs` (rows) and `ys` (cols), by marching squares (saddles split by the cell centre).
pub fn contour_segments(z: &[f64], xs: &[f64], ys: &[f64], h: f64) -> Vec<[[f64; 2]; 2]> {
    let (rows, cols) = (xs.len(), ys.len());
    let mut out = Vec::new();
    let at = |i: usize, j: usize| z[i * cols + j];
    for i in 0..rows.saturating_sub(1) {
        for j in 0..cols.saturating_sub(1) {
            // Corners counter-clockwise: (i,j), (i+1,j), (i+1,j+1), (i,j+1).
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let v = c.map(|(a, b)| at(a, b) - h);
            let mut cross = Vec::with_capacity(4);
            for e in 0..4 {
                let (p, q) = (e, (e + 1) % 4);
                if (v[p] < 0.0) != (v[q] < 0.0) {
                    let w = v[p] / (v[p] - v[q]);
                    let (pa, pb) = c[p];
                    let (qa, qb) = c[q];
                    cross.push([
                        xs[pa] + w * (xs[qa] - xs[pa]),
                        ys[pb] + w * (ys[qb] - ys[pb]),
                    ]);
                }
            }
            match cross.len() {
                2 => out.push([cross[0], cross[1]]),
                4 => {
                    let centre = v.iter().sum::<f64>() / 4.0;
                    if (centre < 0.0) == (v[0] < 0.0) {
                        out.push([cross[0], cross[3]]);
                        out.push([cross[1], cross[2]]);
                    } else {
                        out.push([cross[0], cross[1]]);
                        out.push([cross[2], cross[3]]);
                    }
                }
                _ => {}
            }
        }
    }
    out
}

/// A height field z(x, y) as a map: `cells` × `cells` coloured rectangles (a terrain colour
/// map quantized to 48 steps, runs of equal colour merged) and `levels` contour lines. The
/// surface must be 1-D (heights); x runs to the right, y up.
pub fn heightmap_svg(
    title: &str,
    subtitle: &str,
    surface: &BsplineSurface,
    cells: usize,
    levels: usize,
) -> Result<String> {
    if surface.dim() != 1 {
        return Err(crate::Error::Unsupported(
            "a height map needs a surface of heights (1-D points)".into(),
        ));
    }
    let field = HeightField {
        domain: surface.domain(),
        grid: &|xs, ys, z| surface.eval_grid(xs, ys, z),
    };
    Ok(heightmap_figure(title, subtitle, &field, cells, levels, Axes::Equal)?.render())
}

/// A grid evaluator `grid(xs, ys, out)`, out row-major by x.
pub type GridEval<'a> = dyn Fn(&[f64], &[f64], &mut [f64]) -> geomkit::Result<()> + 'a;

/// Heights z(x, y) over a box, evaluated on grids.
pub struct HeightField<'a> {
    /// ((x0, x1), (y0, y1)).
    pub domain: ((f64, f64), (f64, f64)),
    /// The evaluator.
    pub grid: &'a GridEval<'a>,
}

/// The figure of [`heightmap_svg`] for any height field, on `axes` (equal scales for
/// terrain, a chart for factors of different units), to draw more on.
pub fn heightmap_figure(
    title: &str,
    subtitle: &str,
    field: &HeightField<'_>,
    cells: usize,
    levels: usize,
    axes: Axes,
) -> Result<Figure> {
    let ((x0, x1), (y0, y1)) = field.domain;
    let cells = cells.max(2);
    // Values at the cell centres.
    let (hx, hy) = ((x1 - x0) / cells as f64, (y1 - y0) / cells as f64);
    let cx: Vec<f64> = (0..cells).map(|i| x0 + (i as f64 + 0.5) * hx).collect();
    let cy: Vec<f64> = (0..cells).map(|j| y0 + (j as f64 + 0.5) * hy).collect();
    let mut z = vec![0.0; cells * cells];
    (field.grid)(&cx, &cy, &mut z)?;
    // Contours on a finer grid through the corners.
    let fine = 2 * cells + 1;
    let (fx, fy) = (linspace(x0, x1, fine), linspace(y0, y1, fine));
    let mut zf = vec![0.0; fine * fine];
    (field.grid)(&fx, &fy, &mut zf)?;
    let (lo, hi) = zf
        .iter()
        .chain(&z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let span = if hi > lo { hi - lo } else { 1.0 };
    let steps = 48;
    let mut rects = Vec::new();
    // Columns of the picture are x (rows i), runs merged along y.
    for (i, &x) in cx.iter().enumerate() {
        let mut j = 0;
        while j < cells {
            let color = terrain_color((z[i * cells + j] - lo) / span, steps);
            let mut end = j + 1;
            while end < cells && terrain_color((z[i * cells + end] - lo) / span, steps) == color {
                end += 1;
            }
            rects.push(Cell {
                from: [x - 0.5 * hx, cy[j] - 0.5 * hy],
                to: [x + 0.5 * hx, cy[end - 1] + 0.5 * hy],
                fill: color,
            });
            j = end;
        }
    }
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    fig.rects(rects);
    let contour = Stroke::solid("#202020", 0.7).with_opacity(0.55);
    let mut segments = Vec::new();
    for k in 1..=levels {
        let h = lo + span * k as f64 / (levels + 1) as f64;
        segments.extend(contour_segments(&zf, &fx, &fy, h));
    }
    fig.segments(segments, contour);
    for (key, text) in TERRAIN_KEYS.iter().zip([
        format!("low {}", short_number(lo)),
        "middle".to_string(),
        format!("high {}", short_number(hi)),
    ]) {
        fig.legend(Stroke::solid(key, 9.0), None, text);
    }
    fig.legend(contour, None, format!("{levels} contour lines"));
    Ok(fig)
}

/// A number with 4 significant digits.
fn short_number(x: f64) -> String {
    let v: f64 = format!("{x:.3e}").parse().unwrap_or(x);
    format!("{v}")
}

/// The SVG of point-equation curves (dimension 1-3) through their source points.
pub fn point_curves_svg(
    title: &str,
    subtitle: &str,
    curves: &[(&PointEquation, String)],
) -> Result<String> {
    let dim = curves.first().map_or(2, |c| c.0.dim());
    let proj = Projection::for_dim(dim)?;
    let axes = if dim == 2 {
        Axes::Equal
    } else if dim == 1 {
        Axes::Chart {
            x: "t".into(),
            y: "x".into(),
        }
    } else {
        Axes::Bare
    };
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    for (k, (eq, legend)) in curves.iter().enumerate() {
        let (a, b) = eq.domain();
        let pts: Vec<[f64; 2]> = linspace(a, b, 400)
            .into_iter()
            .map(|t| proj.point(t, &eq.eval(t)))
            .collect();
        let stroke = Stroke::solid(palette::SERIES[k % palette::SERIES.len()], 2.2);
        fig.line(pts, stroke);
        fig.legend(stroke, None, legend.clone());
    }
    if let Some((eq, _)) = curves.first() {
        let dots: Vec<[f64; 2]> = (0..eq.nodes().len())
            .map(|i| proj.point(eq.nodes().values()[i], eq.point(i)))
            .collect();
        fig.dots(dots, 4.0, palette::OLD_VERTEX);
    }
    Ok(fig.render())
}

/// An SVG plot: the formula (through the tape) as a line, the breakpoints (structural
/// evaluator) as dots; a function as (x, f(x)) on a chart, a curve as (x(t), y(t)).
pub fn piecewise_svg(p: &Piecewise, title: &str, subtitle: &str) -> Result<String> {
    let f = p.formula()?;
    let k = p.knots();
    let (a, b) = (k[0], k[k.len() - 1]);
    let function = p.dim() == 1;
    let ts = if function {
        linspace(a - (b - a) / 8.0, b + (b - a) / 8.0, 801)
    } else {
        linspace(a, b, 801)
    };
    let d = p.dim();
    let mut out = vec![0.0; ts.len() * d];
    f.eval_batch(&[&ts], &mut out)?;
    let page = |t: f64, q: &[f64]| if function { [t, q[0]] } else { [q[0], q[1]] };
    let line: Vec<[f64; 2]> = ts
        .iter()
        .zip(out.chunks_exact(d))
        .map(|(&t, q)| page(t, q))
        .collect();
    let dots: Vec<[f64; 2]> = k.iter().map(|&t| page(t, &p.eval(t))).collect();
    let axes = if function {
        Axes::Chart {
            x: p.var().into(),
            y: "f".into(),
        }
    } else {
        Axes::Equal
    };
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    fig.line(line, palette::CURVE);
    fig.legend(palette::CURVE, None, "the single formula");
    fig.dots(dots, 3.5, palette::NEW_VERTEX);
    fig.legend(
        palette::NEW_POLYGON,
        Some(palette::NEW_VERTEX),
        "breakpoints (structural evaluator)",
    );
    Ok(fig.render())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_projects_z_up() {
        let v = View::default();
        let up = v.project(&[0.0, 0.0, 1.0]);
        assert!(up[0].abs() < 1e-15 && up[1] > 0.9);
        // The x axis points left-down on the page for azimuth 35°, y to the right.
        assert!(v.project(&[1.0, 0.0, 0.0])[0] < 0.0);
        assert!(v.project(&[0.0, 1.0, 0.0])[0] > 0.0);
    }

    #[test]
    fn contours_cross_where_the_level_is() {
        let xs = linspace(0.0, 1.0, 3);
        let z: Vec<f64> = (0..9).map(|k| (k / 3) as f64).collect();
        let segs = contour_segments(&z, &xs, &xs, 0.5);
        assert_eq!(segs.len(), 2);
        for s in segs {
            assert!((s[0][0] - 0.25).abs() < 1e-15 && (s[1][0] - 0.25).abs() < 1e-15);
        }
        assert_eq!(terrain_color(0.0, 48).len(), 7);
        assert_eq!(linspace(0.0, 3.0, 4), [0.0, 1.0, 2.0, 3.0]);
    }

    #[test]
    fn too_many_dimensions_is_an_error() {
        assert!(Projection::for_dim(4).is_err());
        assert!(Projection::for_dim(1).is_ok());
    }
}
