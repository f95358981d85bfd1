//! Curves to polylines, sampled adaptively to a tolerance.

use super::surface::with_breaks;
use crate::geom::{linspace, Curve};
use crate::progress::Progress;
use crate::{Error, Result};

/// Options of [`tessellate_curve`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct CurveOptions {
    /// Largest distance (model units) between the curve and the polyline, checked at the
    /// quarter points of every segment; `None`: 1/2000 of the diagonal of the bounding box.
    pub tolerance: Option<f64>,
    /// Segments the sampling starts from before refining (default 16).
    pub min_segments: usize,
    /// Most points of the polyline (default 1 000 000).
    pub max_points: usize,
}

impl Default for CurveOptions {
    fn default() -> Self {
        CurveOptions {
            tolerance: None,
            min_segments: 16,
            max_points: 1_000_000,
        }
    }
}

impl CurveOptions {
    /// Adaptive sampling to an absolute tolerance.
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = Some(tolerance);
        self
    }
}

/// A polyline: points of dimension `dim` at increasing parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline {
    dim: usize,
    params: Vec<f64>,
    points: Vec<f64>,
}

impl Polyline {
    /// A polyline of `params.len()` points of dimension `dim` (`points` row-major) at
    /// strictly increasing, finite `params` (a saved [`tessellate_curve`] result, or one's
    /// own).
    ///
    /// Errors: `dim` 0, a length of `points` other than `dim * params.len()`
    /// ([`Error::InvalidShape`]), a number that is not finite ([`Error::NonFinite`]),
    /// parameters that do not increase ([`Error::InvalidShape`]).
    ///
    /// ```
    /// use geomkit::mesh::Polyline;
    /// let p = Polyline::new(2, vec![0.0, 1.0], vec![0.0, 0.0, 1.0, 2.0]).unwrap();
    /// assert_eq!(p.point(1), &[1.0, 2.0]);
    /// assert!(Polyline::new(2, vec![1.0, 0.0], vec![0.0; 4]).is_err());
    /// ```
    pub fn new(dim: usize, params: Vec<f64>, points: Vec<f64>) -> Result<Self> {
        if dim == 0 || Some(points.len()) != dim.checked_mul(params.len()) {
            return Err(Error::InvalidShape {
                what: "polyline",
                reason: format!(
                    "{} numbers are not {} points of dimension {dim}",
                    points.len(),
                    params.len()
                ),
            });
        }
        if let Some(index) = params.iter().position(|t| !t.is_finite()) {
            return Err(Error::NonFinite {
                what: "polyline parameter",
                index,
            });
        }
        if let Some(index) = points.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                what: "polyline point",
                index: index / dim,
            });
        }
        if let Some(k) = params.windows(2).position(|w| w[0] >= w[1]) {
            return Err(Error::InvalidShape {
                what: "polyline",
                reason: format!("parameters {k} and {} do not increase", k + 1),
            });
        }
        Ok(Polyline {
            dim,
            params,
            points,
        })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// The parameters of the points.
    pub fn params(&self) -> &[f64] {
        &self.params
    }
    /// The points, row-major.
    pub fn points(&self) -> &[f64] {
        &self.points
    }
    /// Point k.
    pub fn point(&self, k: usize) -> &[f64] {
        &self.points[k * self.dim..(k + 1) * self.dim]
    }
    /// Number of points.
    pub fn len(&self) -> usize {
        self.params.len()
    }
    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }
    /// The points in R^3 (dimension 1 as the graph (t, x(t), 0), 2 with z = 0, above 3 the
    /// first three coordinates).
    pub fn points3(&self) -> Vec<[f64; 3]> {
        (0..self.len())
            .map(|k| {
                let p = self.point(k);
                match self.dim {
                    1 => [self.params[k], p[0], 0.0],
                    2 => [p[0], p[1], 0.0],
                    _ => [p[0], p[1], p[2]],
                }
            })
            .collect()
    }
}

/// Distance from `p` to the segment [a, b].
fn distance_to_segment(p: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let (mut ab2, mut ap_ab) = (0.0, 0.0);
    for k in 0..p.len() {
        ab2 += (b[k] - a[k]) * (b[k] - a[k]);
        ap_ab += (p[k] - a[k]) * (b[k] - a[k]);
    }
    let s = if ab2 > 0.0 {
        (ap_ab / ab2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..p.len())
        .map(|k| {
            let d = p[k] - (a[k] + s * (b[k] - a[k]));
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// Samples a curve as a polyline within a tolerance.
///
/// Starts from `min_segments` equal steps plus the break points, then bisects every segment
/// whose curve points at 1/4, 1/2 and 3/4 of its parameter interval lie further than the
/// tolerance from the segment (the three points catch an inflection that the midpoint alone
/// misses). Stops at `max_points` (1 000 000 by default) and at segments shorter than 1e-12
/// of the parameter range (a jump of a discontinuous curve).
///
/// Errors: a tolerance that is not finite and > 0, a non-finite curve point; more starting
/// points than `max_points` ([`Error::MeshTooLarge`]); an explicit tolerance that the
/// `max_points` cap stops short of ([`Error::ToleranceOutOfReach`], naming the deviation
/// reached; the default tolerance returns the capped polyline).
///
/// ```
/// use geomkit::bezier::BezierCurve;
/// use geomkit::mesh::{tessellate_curve, CurveOptions};
/// let c = BezierCurve::new(vec![vec![0., 0.], vec![1., 2.], vec![2., 0.]]).unwrap();
/// let p = tessellate_curve(&c, &CurveOptions::default().with_tolerance(1e-4)).unwrap();
/// // A parabola of curvature 1 at the top: segments of about sqrt(8e-4).
/// assert!(p.len() > 40 && p.len() < 200, "{}", p.len());
/// ```
pub fn tessellate_curve(curve: &dyn Curve, options: &CurveOptions) -> Result<Polyline> {
    tessellate_curve_with_progress(curve, options, &Progress::none())
}

/// Curve points evaluated between two reports of [`tessellate_curve_with_progress`] within
/// one window of the starting sampling (a long bisection still reports, and can be
/// cancelled, this often).
const EVALS_PER_REPORT: usize = 1 << 14;

/// [`tessellate_curve`] reporting to `progress` ([`crate::progress`]). The units are the
/// windows of the starting sampling (`min_segments` equal steps and the curve's breaks:
/// a B-spline of N knots has about N), reported as they are refined — at most about a
/// thousand reports, plus one per 16 384 curve points evaluated inside a window (the
/// same done count again), so that a long refinement can be cancelled. The same polyline,
/// bit for bit, as without it; [`Error::Cancelled`] when the callback asks to stop.
///
/// ```
/// use geomkit::bezier::BezierCurve;
/// use geomkit::mesh::{tessellate_curve_with_progress, CurveOptions};
/// use geomkit::progress::Progress;
/// use std::ops::ControlFlow;
/// let c = BezierCurve::new(vec![vec![0., 0.], vec![1., 2.], vec![2., 0.]]).unwrap();
/// let last = std::sync::Mutex::new((0, 0));
/// let report = |done: u64, total: u64| {
///     *last.lock().unwrap() = (done, total);
///     ControlFlow::Continue(())
/// };
/// let options = CurveOptions::default().with_tolerance(1e-4);
/// let p = tessellate_curve_with_progress(&c, &options, &Progress::new(&report)).unwrap();
/// assert_eq!(*last.lock().unwrap(), (16, 16)); // the 16 starting segments
/// assert!(p.len() > 40);
/// ```
pub fn tessellate_curve_with_progress(
    curve: &dyn Curve,
    options: &CurveOptions,
    progress: &Progress,
) -> Result<Polyline> {
    let d = curve.dim();
    let (a, b) = curve.domain();
    let eval = |t: f64, index: usize| -> Result<Vec<f64>> {
        let p = curve.eval(t);
        if p.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                what: "curve point",
                index,
            });
        }
        Ok(p)
    };
    let segments = options.min_segments.max(1);
    if segments >= options.max_points {
        return Err(Error::MeshTooLarge {
            what: format!("{segments} segments"),
            count: segments.saturating_add(1),
            unit: "points",
            max: options.max_points,
        });
    }
    let start = with_breaks(linspace(a, b, segments + 1), &curve.breaks(), (a, b));
    if start.len() > options.max_points {
        return Err(Error::MeshTooLarge {
            what: format!("{segments} segments and the curve's breaks"),
            count: start.len(),
            unit: "points",
            max: options.max_points,
        });
    }
    let tol = match options.tolerance {
        Some(t) if t.is_finite() && t > 0.0 => t,
        Some(t) => return Err(Error::InvalidTolerance { value: t }),
        None => {
            let probe: Vec<Vec<f64>> = linspace(a, b, 65)
                .iter()
                .enumerate()
                .map(|(k, &t)| eval(t, k))
                .collect::<Result<_>>()?;
            // Half extents, and the diagonal / 2000 scaled by the largest (no overflow).
            let half: Vec<f64> = (0..d)
                .map(|k| {
                    let lo = probe.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
                    let hi = probe.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
                    hi / 2.0 - lo / 2.0
                })
                .collect();
            let m = half.iter().fold(0.0f64, |m, &h| m.max(h));
            let diag = if m > 0.0 {
                m / 1000.0 * half.iter().map(|h| (h / m) * (h / m)).sum::<f64>().sqrt()
            } else {
                0.0
            };
            if diag > 0.0 {
                diag
            } else {
                1e-9
            }
        }
    };
    let mut params = Vec::new();
    let mut points: Vec<f64> = Vec::new();
    // Work stack of segments (t0, p0, t1, p1), processed left to right.
    let first = eval(start[0], 0)?;
    params.push(start[0]);
    points.extend_from_slice(&first);
    let budget = options.max_points;
    // The largest deviation left where the budget stopped the bisection.
    let mut capped = 0.0f64;
    // Segments still to draw after the current window: they each need a point.
    let mut later = start.len() - 1;
    let windows = start.len() - 1;
    progress.add_total(windows as u64)?;
    // Windows per report, windows refined since the last one, points evaluated since.
    let (step, mut pending, mut evals) = (windows.div_ceil(1024), 0, 0);
    for w in start.windows(2) {
        later -= 1;
        let mut stack = vec![(w[0], w[1])];
        while let Some((t0, t1)) = stack.pop() {
            evals += 4;
            if evals >= EVALS_PER_REPORT {
                progress.advance(0)?;
                evals = 0;
            }
            let p0 = points[points.len() - d..].to_vec();
            let p1 = eval(t1, params.len())?;
            let far = if t1 - t0 > (b - a) * 1e-12 {
                let mut worst = 0.0f64;
                for f in [0.25, 0.5, 0.75] {
                    let q = eval(t0 + f * (t1 - t0), params.len())?;
                    worst = worst.max(distance_to_segment(&q, &p0, &p1));
                }
                if worst > tol && params.len() + stack.len() + later + 2 > budget {
                    capped = capped.max(worst);
                    false
                } else {
                    worst > tol
                }
            } else {
                false
            };
            if far {
                let m = 0.5 * (t0 + t1);
                stack.push((m, t1));
                stack.push((t0, m));
            } else {
                params.push(t1);
                points.extend_from_slice(&p1);
            }
        }
        pending += 1;
        if pending == step {
            progress.advance(pending as u64)?;
            (pending, evals) = (0, 0);
        }
    }
    progress.finish()?;
    if let (Some(t), true) = (options.tolerance, capped > 0.0) {
        return Err(Error::ToleranceOutOfReach {
            tolerance: t,
            reached: capped,
            cap: format!("{budget} points"),
        });
    }
    Ok(Polyline {
        dim: d,
        params,
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::BezierCurve;

    #[test]
    fn polyline_is_within_tolerance_at_dense_samples() {
        let c = BezierCurve::new(vec![
            vec![0., 0.],
            vec![1., 3.],
            vec![2., -3.],
            vec![3., 0.],
        ])
        .unwrap();
        let tol = 1e-3;
        let p = tessellate_curve(&c, &CurveOptions::default().with_tolerance(tol)).unwrap();
        assert_eq!(p.params()[0], 0.0);
        assert_eq!(*p.params().last().unwrap(), 1.0);
        for k in 0..p.len() - 1 {
            let (t0, t1) = (p.params()[k], p.params()[k + 1]);
            for s in 1..10 {
                let q = c.eval(t0 + (t1 - t0) * s as f64 / 10.0);
                let dist = distance_to_segment(&q, p.point(k), p.point(k + 1));
                assert!(dist <= 1.5 * tol, "segment {k}: {dist}");
            }
        }
    }

    #[test]
    fn bad_tolerance_is_an_error() {
        let c = BezierCurve::new(vec![vec![0.], vec![1.]]).unwrap();
        let e = tessellate_curve(&c, &CurveOptions::default().with_tolerance(f64::NAN));
        assert!(matches!(e, Err(Error::InvalidTolerance { .. })));
    }
}
