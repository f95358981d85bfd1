//! The paper's hand edits of a control polygon (spec/bezier-order.md §3): removing or adding a
//! vertex changes the degree *and the shape*; each edit reports how much the shape changed.
//!
//! What "the middle vertex m = round(n/2) has the least influence" means, precisely: its
//! Bernstein weight has the smallest peak, max_t b_nm(t) = b_nm(m/n) ≤ max_t b_ni(t) for every
//! i, and b_nm(m/n) → 0 like sqrt(2/(πn)) ([`middle_vertex_weight`]). So *moving* the middle
//! vertex by v moves the curve by at most b_nm(m/n)·|v|, less than moving any other vertex by v.
//! *Removing* a vertex is a different edit: the other n vertices are re-weighted by the degree
//! n-1 basis. Elevated back to degree n, the change C(t) - C'(t) = Σ_k b_nk(t) δ_k has
//! δ_k = (k/n)(P_k - P_(k-1)) for k < i, δ_i = P_i - (i/n) P_(i-1) - (1 - i/n) P_(i+1) and
//! δ_k = (1 - k/n)(P_k - P_(k+1)) for k > i, so it is at most max_k |δ_k|, a bound that
//! depends on every side of the polygon. Removing the middle vertex is therefore *not* always
//! the removal that moves the curve least (tests/bezier_paper.rs has a degree-10 curve where it
//! moves the curve 0.61 and removing vertex 4 only 0.30); [`EditResult::deviation`] reports the
//! actual change.
//!
//! ```
//! use geomkit::bezier::BezierCurve;
//! let c = BezierCurve::new((0..9).map(|i| vec![i as f64, (i % 3) as f64]).collect()).unwrap();
//! let edit = c.remove_middle_vertex().unwrap();
//! assert_eq!(edit.curve.degree(), 7);
//! assert!(edit.deviation.upper_bound >= edit.deviation.max_found);
//! ```

use super::bound::DeviationBound;
use super::curve::BezierCurve;
use crate::numeric::binomial_f64;
use crate::{Error, Result};

/// A hand-edited curve with how far it moved from the original.
#[derive(Debug, Clone, PartialEq)]
pub struct EditResult {
    /// The edited curve.
    pub curve: BezierCurve,
    /// Index of the vertex removed or inserted.
    pub index: usize,
    /// Distance between the original and edited curves over t ∈ [0, 1].
    pub deviation: DeviationBound,
}

/// Peak weight of the middle vertex m = round(n/2): max_t b_nm(t) = b_nm(m/n), the smallest
/// peak of the n + 1 Bernstein polynomials of degree n (≈ sqrt(2/(πn)) for large n).
pub fn middle_vertex_weight(n: usize) -> f64 {
    if n == 0 {
        return 1.0;
    }
    let m = n.div_ceil(2);
    let t = m as f64 / n as f64;
    binomial_f64(n, m) * t.powi(m as i32) * (1.0 - t).powi((n - m) as i32)
}

impl BezierCurve {
    /// Removes control point `index` (the curve loses one degree and changes shape).
    /// Errors: index out of range, or removing the only point.
    pub fn remove_vertex(&self, index: usize) -> Result<EditResult> {
        let n = self.degree();
        if index > n {
            return Err(Error::IndexOutOfRange {
                what: "control point",
                index,
                len: n + 1,
            });
        }
        if n == 0 {
            return Err(Error::TooFewPoints {
                what: "control points after removal",
                got: 0,
                min: 1,
            });
        }
        let d = self.dim();
        let mut pts = self.points_flat().to_vec();
        pts.drain(index * d..(index + 1) * d);
        let curve = BezierCurve::from_flat(d, pts)?;
        let deviation = self.deviation_from(&curve)?;
        Ok(EditResult {
            curve,
            index,
            deviation,
        })
    }

    /// Inserts `point` before control point `index` (index = n+1 appends).
    /// Errors: index out of range, wrong dimension, non-finite coordinates.
    pub fn insert_vertex(&self, index: usize, point: &[f64]) -> Result<EditResult> {
        let n = self.degree();
        let d = self.dim();
        if index > n + 1 {
            return Err(Error::IndexOutOfRange {
                what: "insertion position",
                index,
                len: n + 2,
            });
        }
        if point.len() != d {
            return Err(Error::DimensionMismatch {
                what: "inserted point",
                index,
                expected: d,
                got: point.len(),
            });
        }
        let mut pts = self.points_flat().to_vec();
        pts.splice(index * d..index * d, point.iter().copied());
        let curve = BezierCurve::from_flat(d, pts)?;
        let deviation = self.deviation_from(&curve)?;
        Ok(EditResult {
            curve,
            index,
            deviation,
        })
    }

    /// Removes the middle vertex m = round(n/2), the one of smallest peak weight (for odd n the
    /// one of the two middle vertices whose removal moves the curve less). Its removal still
    /// re-weights all other vertices and need not be the removal that moves the curve least
    /// (module docs); `deviation` says how far it moved.
    pub fn remove_middle_vertex(&self) -> Result<EditResult> {
        let n = self.degree();
        let a = self.remove_vertex(n / 2)?;
        if n.is_multiple_of(2) {
            return Ok(a);
        }
        let b = self.remove_vertex(n.div_ceil(2))?;
        Ok(if b.deviation.upper_bound < a.deviation.upper_bound {
            b
        } else {
            a
        })
    }
}
