//! Models as STEP content: the exact B-spline form of each kind of model.

use super::approx::{self, absolute_tolerance, finite, Approximation, CurvePiece};
use super::nurbs::{points3, NurbsCurve, NurbsSurface};
use super::write::{Content, FaceSpec};
use super::{StepError, StepResult};
use crate::{AnyModel, BezierModel};
use geomkit::bezier::{BezierSurface, RationalBezierSurface};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::compose::Piecewise;
use geomkit::geom::Surface;

/// The clamped knot vector of one Bézier span of degree n on [0, 1].
pub(crate) fn bezier_knots(n: usize) -> Vec<f64> {
    let mut k = vec![0.0; n + 1];
    k.extend(std::iter::repeat_n(1.0, n + 1));
    k
}

pub(crate) fn bspline_curve(c: &BsplineCurve) -> StepResult<NurbsCurve> {
    if c.degree() == 0 {
        return Err(StepError::Unsupported(
            "a B-spline curve of degree 0 (a step function) is not a curve STEP can hold".into(),
        ));
    }
    let points = points3(c.control_flat(), c.dim(), "a B-spline curve")?;
    NurbsCurve::new(c.degree(), c.knots().to_vec(), points, None)
}

pub(crate) fn bspline_surface(s: &BsplineSurface) -> StepResult<NurbsSurface> {
    let (rows, cols) = s.net_size();
    let (ku, kv) = s.knots();
    Ok(NurbsSurface {
        degrees: s.degrees(),
        knots_u: ku.to_vec(),
        knots_v: kv.to_vec(),
        rows,
        cols,
        points: points3(s.control_flat(), s.dim(), "a B-spline surface")?,
        weights: None,
        bezier: false,
    })
}

pub(crate) fn bezier_surface(s: &BezierSurface) -> StepResult<NurbsSurface> {
    bezier_net(s.degrees(), s.net_flat(), s.dim(), None)
}

/// A rational Bézier surface: its Cartesian net and weights (the rational complex entity).
fn rational_bezier_surface(s: &RationalBezierSurface) -> StepResult<NurbsSurface> {
    bezier_net(
        s.degrees(),
        s.net_flat(),
        s.dim(),
        Some(s.weights_flat().to_vec()),
    )
}

fn bezier_net(
    (n, m): (usize, usize),
    flat: &[f64],
    dim: usize,
    weights: Option<Vec<f64>>,
) -> StepResult<NurbsSurface> {
    Ok(NurbsSurface {
        degrees: (n, m),
        knots_u: bezier_knots(n),
        knots_v: bezier_knots(m),
        rows: n + 1,
        cols: m + 1,
        points: points3(flat, dim, "a Bézier surface")?,
        weights,
        bezier: true,
    })
}

/// A (rational) Bézier curve of degree n on [0, 1].
pub(crate) fn bezier_curve(
    n: usize,
    points: Vec<[f64; 3]>,
    weights: Option<Vec<f64>>,
) -> StepResult<NurbsCurve> {
    let mut c = NurbsCurve::new(n, bezier_knots(n), points, weights)?;
    c.bezier = true;
    Ok(c)
}

/// A face over the whole domain of `surface`, bounded by its sides.
pub(crate) fn natural_face(surface: NurbsSurface) -> FaceSpec {
    FaceSpec {
        surface,
        bound: None,
        same_sense: true,
    }
}

/// A surface as one face: of an open shell, or, when its sides close it (each collapsed to a
/// point or the seam of its opposite side: the Mushroom), a solid with the face's normal
/// outwards.
fn surface_content(nurbs: NurbsSurface, s: &dyn Surface) -> StepResult<Content> {
    if !super::write::closes(&nurbs)? {
        return Ok(Content::Faces(vec![natural_face(nurbs)]));
    }
    let eval = |u: f64, v: f64| {
        let mut p = [0.0; 3];
        let mut q = vec![0.0; s.dim()];
        s.eval_into(u, v, &mut q);
        p[..q.len().min(3)].copy_from_slice(&q[..q.len().min(3)]);
        p
    };
    let outward = super::bodies::signed_volume(eval, s.domain(), (128, 128)) > 0.0;
    let mut face = natural_face(nurbs);
    face.same_sense = outward;
    Ok(Content::Solid(vec![face]))
}

/// What `model` is as STEP, and the pieces approximated within `tolerance` (relative) where
/// a formula has no exact B-spline form.
pub(crate) fn content(
    model: &AnyModel,
    tolerance: f64,
) -> StepResult<(Content, Vec<Approximation>)> {
    Ok(match model {
        AnyModel::Composite(s) => super::bodies::composite(s, tolerance)?,
        AnyModel::Ruled(s) => super::bodies::ruled(s, tolerance)?,
        AnyModel::Piecewise(p) => piecewise(p, tolerance)?,
        AnyModel::Formula(f) => match &f.model {
            Some(m) => content(m, tolerance)?,
            None => {
                return Err(StepError::Unsupported(
                    "this formula file carries no model (written by an older geomkit): \
                     export the file it was made from"
                        .into(),
                ))
            }
        },
        other => (exact(other)?, Vec::new()),
    })
}

/// A piecewise function f(x) (its graph (x, f(x), 0)) or composite curve as one edge per
/// piece: polylines exactly (degree 1), formula pieces as interpolating B-splines.
fn piecewise(p: &Piecewise, tolerance: f64) -> StepResult<(Content, Vec<Approximation>)> {
    let dim = p.dim();
    if dim > 3 {
        return Err(StepError::Unsupported(format!(
            "a composite curve in R^{dim}: STEP geometry lives in R^3"
        )));
    }
    let point = |x: f64| -> [f64; 3] {
        let v = p.eval(x);
        match dim {
            1 => [x, v[0], 0.0],
            2 => [v[0], v[1], 0.0],
            _ => [v[0], v[1], v[2]],
        }
    };
    let knots = p.knots();
    if let Some(values) = p.vertices() {
        // A polyline: exact, one degree-1 edge per segment.
        let curves = knots
            .windows(2)
            .zip(values.windows(2))
            .map(|(k, v)| {
                let at = |x: f64, q: &[f64]| match dim {
                    1 => [x, q[0], 0.0],
                    2 => [q[0], q[1], 0.0],
                    _ => [q[0], q[1], q[2]],
                };
                NurbsCurve::new(
                    1,
                    vec![k[0], k[0], k[1], k[1]],
                    vec![at(k[0], &v[0]), at(k[1], &v[1])],
                    None,
                )
            })
            .collect::<StepResult<Vec<_>>>()?;
        return Ok((Content::Curves(curves), Vec::new()));
    }
    let var = p.var().to_string();
    let pieces: Vec<CurvePiece<'_>> = knots
        .windows(2)
        .enumerate()
        .map(|(i, k)| {
            let name = format!("piece {i} ({var} in [{}, {}])", k[0], k[1]);
            let label = name.clone();
            let var = var.clone();
            // The piece's own formula up to its end (the next piece starts there).
            let eval = move |x: f64| {
                let x = x.clamp(k[0], k[1]);
                finite(&label, &format!("{var} = {x}"), point(x))
            };
            CurvePiece {
                name,
                domain: (k[0], k[1]),
                eval: Box::new(eval),
            }
        })
        .collect();
    let absolute = absolute_tolerance(tolerance, &[], &pieces)?;
    let (curves, approximations) = approx::curves(&pieces, absolute)?.into_iter().unzip();
    Ok((Content::Curves(curves), approximations))
}

/// The exact B-spline form of a Bézier or B-spline curve or surface.
fn exact(model: &AnyModel) -> StepResult<Content> {
    Ok(match model {
        AnyModel::Bezier(BezierModel::Curve(c)) => {
            if c.degree() == 0 {
                return Err(StepError::Unsupported(
                    "a Bézier curve of degree 0 is a single point, not a curve".into(),
                ));
            }
            let points = points3(c.points_flat(), c.dim(), "a Bézier curve")?;
            Content::Curves(vec![bezier_curve(c.degree(), points, None)?])
        }
        AnyModel::Bezier(BezierModel::Rational(r)) => {
            let rows = r.points();
            let dim = rows.first().map_or(0, Vec::len);
            let flat: Vec<f64> = rows.concat();
            let points = points3(&flat, dim, "a rational Bézier curve")?;
            if r.degree() == 0 {
                return Err(StepError::Unsupported(
                    "a Bézier curve of degree 0 is a single point, not a curve".into(),
                ));
            }
            Content::Curves(vec![bezier_curve(r.degree(), points, Some(r.weights()))?])
        }
        AnyModel::Bezier(BezierModel::Surface(s)) => surface_content(bezier_surface(s)?, s)?,
        AnyModel::Bezier(BezierModel::RationalSurface(s)) => {
            surface_content(rational_bezier_surface(s)?, s)?
        }
        AnyModel::BsplineCurve(m) => Content::Curves(vec![bspline_curve(&m.curve)?]),
        AnyModel::BsplineSurface(m) => surface_content(bspline_surface(&m.surface)?, &m.surface)?,
        other => {
            return Err(StepError::Unsupported(format!(
                "a {} has no B-spline form to write as STEP (exported are Bézier and \
                 B-spline curves and surfaces, composite surfaces, ruled surfaces and bodies, \
                 composite curves and piecewise functions)",
                other.describe()
            )))
        }
    })
}
