//! Pictures of curves and surfaces built on [`crate::svg`]: a curve with its old and new
//! control polygons (the paper's Fig. 1 and 2), and surfaces as a wireframe of iso-curves with
//! their control nets in a fixed axonometric view (Fig. 4 and 5).
//!
//! Points of dimension 2 are drawn as they are, dimension 3 in the axonometric view, and
//! dimension 1 as the graph of the function (control point i at abscissa i/n, which is exact
//! for Bézier functions since Σ b_ni(t) i/n = t).

use crate::svg::{palette, Axes, Figure, Label, Placement, Stroke};
use anyhow::{bail, Result};
use geomkit::bezier::{BezierSurface, ParamCurve};

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
                bail!("cannot draw points of dimension {d} (SVG output needs 1-, 2- or 3-D points)")
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
    pub fn curve(&self, curve: &dyn ParamCurve, count: usize) -> Vec<[f64; 2]> {
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
    old: (&dyn ParamCurve, &[Vec<f64>]),
    new: (Option<&dyn ParamCurve>, &[Vec<f64>]),
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
        surface: &'a BezierSurface,
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
}

/// A picture of surfaces in the fixed axonometric view (azimuth 35°, elevation 25°).
/// Surfaces must be 2- or 3-D.
pub fn surface_svg(title: &str, subtitle: &str, layers: &[Layer<'_>]) -> Result<String> {
    let view = View::default();
    let mut fig = Figure::new(title, Axes::Bare).subtitle(subtitle);
    for layer in layers {
        let s = match layer {
            Layer::Wireframe { surface, .. } | Layer::Net { surface, .. } => surface,
        };
        if !(2..=3).contains(&s.dim()) {
            bail!(
                "cannot draw a surface in R^{} (SVG output needs 2- or 3-D points)",
                s.dim()
            );
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
                let fine: Vec<f64> = (0..k).map(|a| a as f64 / (k - 1) as f64).collect();
                let iso: Vec<f64> = (0..*count)
                    .map(|a| a as f64 / (count - 1).max(1) as f64)
                    .collect();
                let d = surface.dim();
                let mut grid = vec![0.0; iso.len() * k * d];
                // u-iso-curves (u fixed, v running) and v-iso-curves.
                surface.eval_grid(&iso, &fine, &mut grid)?;
                for line in grid.chunks_exact(k * d) {
                    fig.line(
                        line.chunks_exact(d).map(|p| view.project(p)).collect(),
                        *stroke,
                    );
                }
                surface.eval_grid(&fine, &iso, &mut grid)?;
                for b in 0..iso.len() {
                    let pts = (0..k)
                        .map(|a| {
                            let o = (a * iso.len() + b) * d;
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
    fn too_many_dimensions_is_an_error() {
        assert!(Projection::for_dim(4).is_err());
        assert!(Projection::for_dim(1).is_ok());
    }
}
