//! Rational Bézier curves: p(t) = Σ w_i b_ni(t) u_i / Σ w_i b_ni(t). Their order changes
//! through homogeneous coordinates (w_i u_i, w_i) ∈ R^(r+1), where the curve is polynomial and
//! everything of [`super::degree`] applies unchanged.
//!
//! ```
//! use geomkit::bezier::RationalBezierCurve;
//! use geomkit::geom::Curve;
//! // A quarter of the unit circle.
//! let arc = RationalBezierCurve::new(
//!     vec![vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]],
//!     vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
//! ).unwrap();
//! let p = arc.elevate_degree(5).unwrap().eval(0.3);
//! assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
//! ```

use super::curve::{eval_accurate, flatten_points, BezierCurve};
use super::degree::DegreeReport;
use crate::geom::{check_point, Curve};
use crate::progress::Progress;
use crate::{Error, Result};

/// A rational Bézier curve with positive weights.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalBezierCurve {
    /// Homogeneous control points (w_i u_i, w_i), dimension r + 1.
    homogeneous: BezierCurve,
    /// The Cartesian control points u_i as given (row-major, dimension r): kept, so that
    /// [`RationalBezierCurve::points`] gives back the very numbers a curve was made from
    /// (u_i w_i / w_i may differ from u_i in the last bit).
    points: Vec<f64>,
    /// The weights as given (the homogeneous points may hold them scaled by a power of two).
    weights: Vec<f64>,
}

fn check_weights(weights: &[f64]) -> Result<()> {
    match weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        Some(index) => Err(Error::InvalidWeight {
            index,
            value: weights[index],
        }),
        None => Ok(()),
    }
}

/// The homogeneous points (w_i u_i, w_i) of Cartesian points `flat` (dimension `dim`) and
/// their weights (checked finite and positive; one per point, the count is the caller's). When some
/// w_i·u_i would overflow or underflow f64, the weights are first scaled by the power of two
/// that brings the largest into (1/2, 1] (exact; a common factor does not change a rational
/// curve or surface), so that every w_i u_i is at most |u_i| and the largest products keep
/// their digits.
pub(super) fn homogeneous_flat(flat: &[f64], dim: usize, weights: &[f64]) -> Result<Vec<f64>> {
    check_weights(weights)?;
    let lost = flat.chunks_exact(dim).zip(weights).any(|(p, w)| {
        p.iter().any(|x| {
            let y = (x * w).abs();
            !y.is_finite() || (*x != 0.0 && y < f64::MIN_POSITIVE)
        })
    });
    let largest_weight = weights.iter().fold(0.0f64, |m, &w| m.max(w));
    let factor = if lost {
        2f64.powi(-(largest_weight.log2().ceil() as i32))
    } else {
        1.0
    };
    let mut h = Vec::with_capacity(weights.len() * (dim + 1));
    for (p, w) in flat.chunks_exact(dim).zip(weights) {
        let w = w * factor;
        if w == 0.0 {
            return Err(Error::Numerical {
                operation: "rational Bézier weights",
                reason: "the weights span too many orders of magnitude for control points \
                         this large (some w_i·u_i overflows f64, and scaling the weights \
                         down makes the smallest 0)",
            });
        }
        h.extend(p.iter().map(|x| x * w));
        h.push(w);
    }
    Ok(h)
}

/// The Cartesian points and weights of homogeneous points (last coordinate the weight, checked
/// positive): (points (w u)/w row-major, weights). A quotient past f64::MAX by rounding only (a
/// point of f64::MAX itself, w·u rounded) is f64::MAX; one that truly exceeds f64 is an
/// error.
pub(super) fn split_homogeneous(h: &[f64], d: usize) -> Result<(Vec<f64>, Vec<f64>)> {
    let weights: Vec<f64> = h.chunks_exact(d).map(|p| p[d - 1]).collect();
    check_weights(&weights)?;
    let mut points = Vec::with_capacity(weights.len() * (d - 1));
    for p in h.chunks_exact(d) {
        let w = p[d - 1];
        for x in &p[..d - 1] {
            let mut q = x / w;
            if q.is_infinite() {
                if (x * 0.5 / w).abs() > f64::MAX * 0.5 * (1.0 + 8.0 * f64::EPSILON) {
                    return Err(Error::Numerical {
                        operation: "rational Bézier control points",
                        reason: "a control point (w·u)/w overflows f64",
                    });
                }
                q = f64::MAX.copysign(*x);
            }
            points.push(q);
        }
    }
    Ok((points, weights))
}

/// Writes the Cartesian point of the homogeneous point `h` (last coordinate the weight w > 0)
/// into `out`: x / w, where a quotient past f64::MAX of a point inside its control points'
/// hull is rounding at coordinates of f64::MAX itself and is clamped there.
pub(super) fn project(h: &[f64], out: &mut [f64]) {
    let d = h.len();
    for (o, x) in out.iter_mut().zip(&h[..d - 1]) {
        *o = x / h[d - 1];
        if o.is_infinite() && x.is_finite() && h[d - 1] > 0.0 {
            *o = f64::MAX.copysign(*o);
        }
    }
}

impl RationalBezierCurve {
    /// A curve from control points and weights (finite, > 0, one per point). When some
    /// w_i·u_i would overflow or underflow f64, the homogeneous points hold the weights
    /// scaled by a common power of two (the same curve).
    pub fn new(points: Vec<Vec<f64>>, weights: Vec<f64>) -> Result<Self> {
        let (dim, flat) = flatten_points("control points", &points)?;
        if weights.len() != points.len() {
            return Err(Error::WeightCount {
                expected: points.len(),
                got: weights.len(),
            });
        }
        let h = homogeneous_flat(&flat, dim, &weights)?;
        Ok(RationalBezierCurve {
            homogeneous: BezierCurve::from_flat(dim + 1, h)?,
            points: flat,
            weights,
        })
    }

    /// The curve whose homogeneous control points are those of `h` (last coordinate the
    /// weight). Errors when a weight is not > 0.
    pub fn from_homogeneous(h: BezierCurve) -> Result<Self> {
        if h.dim() < 2 {
            return Err(Error::WrongDimension {
                operation: "rational curve from homogeneous points",
                expected: 2,
                got: h.dim(),
            });
        }
        let (points, weights) = split_homogeneous(h.points_flat(), h.dim())?;
        Ok(RationalBezierCurve {
            homogeneous: h,
            points,
            weights,
        })
    }

    /// Formal degree.
    pub fn degree(&self) -> usize {
        self.homogeneous.degree()
    }

    /// The homogeneous (polynomial) curve in R^(r+1).
    pub fn homogeneous(&self) -> &BezierCurve {
        &self.homogeneous
    }

    /// The weights: those the curve was made from by [`RationalBezierCurve::new`], bit for
    /// bit; the homogeneous points' last coordinates for a curve made from them.
    pub fn weights(&self) -> Vec<f64> {
        self.weights.clone()
    }

    /// The (Cartesian) control points: those the curve was made from by
    /// [`RationalBezierCurve::new`], bit for bit; (w_i u_i) / w_i for a curve made from
    /// homogeneous points.
    pub fn points(&self) -> Vec<Vec<f64>> {
        let d = self.homogeneous.dim() - 1;
        self.points.chunks_exact(d).map(<[f64]>::to_vec).collect()
    }

    /// Elevation to n' >= n (closed form (8) on homogeneous points): the curve is unchanged.
    pub fn elevate_degree(&self, n_new: usize) -> Result<Self> {
        Self::from_homogeneous(self.homogeneous.elevate_degree(n_new)?)
    }

    /// Real degree of the homogeneous curve (the rational curve's degree as a ratio of
    /// polynomials with this common denominator), by the residual test.
    pub fn degree_report(&self, tolerance: Option<f64>) -> Result<DegreeReport> {
        self.homogeneous.degree_report(tolerance)
    }

    /// Exact reduction through homogeneous coordinates; errors as
    /// [`BezierCurve::reduce_degree`], or with [`Error::InvalidWeight`] if a reduced weight
    /// is not positive.
    pub fn reduce_degree(&self, n_new: usize, tolerance: Option<f64>) -> Result<Self> {
        Self::from_homogeneous(self.homogeneous.reduce_degree(n_new, tolerance)?)
    }

    /// Elevation when n' >= n, exact reduction otherwise (through homogeneous coordinates),
    /// reporting to `progress` as [`BezierCurve::change_degree_with_progress`] does. The
    /// same curve, bit for bit, as [`Self::elevate_degree`] / [`Self::reduce_degree`].
    pub fn change_degree_with_progress(
        &self,
        n_new: usize,
        tolerance: Option<f64>,
        progress: &Progress,
    ) -> Result<Self> {
        let h = self
            .homogeneous
            .change_degree_with_progress(n_new, tolerance, progress)?;
        Self::from_homogeneous(h)
    }
}

/// p(t) = Σ w_i b_ni(t) u_i / Σ w_i b_ni(t) on [0, 1] (de Casteljau on the homogeneous
/// points); derivatives of every order by the quotient rule on the homogeneous hodographs.
impl Curve for RationalBezierCurve {
    fn dim(&self) -> usize {
        self.homogeneous.dim() - 1
    }

    /// [0, 1].
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }

    fn eval_into(&self, t: f64, out: &mut [f64]) {
        let d = self.homogeneous.dim();
        let mut h = vec![0.0; d];
        eval_accurate(self.homogeneous.points_flat(), d, t, &mut h);
        project(&h, out);
    }

    /// Every order: with A(t) = Σ w_i b_ni(t) u_i and w(t) = Σ w_i b_ni(t) (the
    /// homogeneous curve and its hodographs), p^(k) = (A^(k) - Σ_(i=1..k) C(k,i) w^(i)
    /// p^(k-i)) / w.
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        let r = self.dim();
        check_point(&[t], r, out)?;
        let hd = r + 1;
        // Homogeneous derivatives H^(i), i = 0..=order.
        let mut h = vec![0.0; (order + 1) * hd];
        for (i, hi) in h.chunks_exact_mut(hd).enumerate() {
            self.homogeneous.derivative_into(t, i, hi)?;
        }
        let w = h[r];
        // p^(j) for j = 0..=order, each from the lower ones.
        let mut p = vec![0.0; (order + 1) * r];
        for j in 0..=order {
            let mut binom = 1.0;
            let mut acc = h[j * hd..j * hd + r].to_vec();
            for i in 1..=j {
                binom = binom * (j - i + 1) as f64 / i as f64;
                let wi = h[i * hd + r];
                for (a, q) in acc.iter_mut().zip(&p[(j - i) * r..(j - i + 1) * r]) {
                    *a -= binom * wi * q;
                }
            }
            for (o, a) in p[j * r..(j + 1) * r].iter_mut().zip(&acc) {
                *o = a / w;
            }
        }
        out.copy_from_slice(&p[order * r..]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_weights() {
        let pts = vec![vec![0.0], vec![1.0]];
        assert_eq!(
            RationalBezierCurve::new(pts.clone(), vec![1.0, -1.0]),
            Err(Error::InvalidWeight {
                index: 1,
                value: -1.0
            })
        );
        assert_eq!(
            RationalBezierCurve::new(pts, vec![1.0]),
            Err(Error::WeightCount {
                expected: 2,
                got: 1
            })
        );
    }

    #[test]
    fn elevated_circle_reduces_back() {
        let arc = RationalBezierCurve::new(
            vec![vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]],
            vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
        )
        .unwrap();
        let e = arc.elevate_degree(9).unwrap();
        assert_eq!(e.degree_report(None).unwrap().real_degree, 2);
        let back = e.reduce_degree(2, None).unwrap();
        for (a, b) in back.weights().iter().zip(arc.weights()) {
            assert!((a - b).abs() < 1e-15);
        }
    }
}
