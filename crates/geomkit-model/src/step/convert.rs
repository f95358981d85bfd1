//! Models as STEP content: the exact B-spline form of each kind of model.

use super::nurbs::{points3, NurbsCurve, NurbsSurface};
use super::write::{Content, FaceSpec};
use super::{StepError, StepResult};
use crate::{AnyModel, BezierModel};
use geomkit::bezier::{BezierSurface, RationalBezierSurface};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
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

/// What `model` is as STEP.
pub(crate) fn content(model: &AnyModel) -> StepResult<Content> {
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
        AnyModel::Composite(s) => super::bodies::composite(s)?,
        AnyModel::Ruled(s) => super::bodies::ruled(s)?,
        AnyModel::Formula(f) => match &f.model {
            Some(m) => content(m)?,
            None => {
                return Err(StepError::Unsupported(
                    "this formula file carries no model (written by an older geomkit): \
                     export the file it was made from"
                        .into(),
                ))
            }
        },
        other => {
            return Err(StepError::Unsupported(format!(
                "a {} has no exact B-spline form to write as STEP (exported are Bézier and \
                 B-spline curves and surfaces, composite surfaces of polynomial patches and \
                 the closed bodies)",
                other.describe()
            )))
        }
    })
}
