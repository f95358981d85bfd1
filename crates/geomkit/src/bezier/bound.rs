//! Guaranteed bounds on the distance between two Bézier curves, by subdivision of their
//! difference (convex hull property). Used for error reports of approximate reduction and of
//! the paper's hand edits.

use super::curve::{de_casteljau, split_flat};
use super::degree::elevate_flat;
use crate::numeric::{distance, max_norm};
use crate::Result;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// How far apart two curves are, over t ∈ [0, 1], in the Euclidean norm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviationBound {
    /// The largest deviation found at an evaluated parameter (a value the curves attain).
    pub max_found: f64,
    /// Where `max_found` is attained.
    pub at: f64,
    /// A guaranteed upper bound on max_t |a(t) - b(t)| (rigorous up to a rounding slack of
    /// order (n+1)·eps·scale, which is included). At most 1% above `max_found` plus that
    /// slack unless the subdivision budget ran out.
    pub upper_bound: f64,
}

struct Piece {
    coeffs: Vec<f64>,
    upper: f64,
    t0: f64,
    t1: f64,
}

impl PartialEq for Piece {
    fn eq(&self, o: &Self) -> bool {
        self.upper == o.upper
    }
}
impl Eq for Piece {}
impl PartialOrd for Piece {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Piece {
    fn cmp(&self, o: &Self) -> Ordering {
        self.upper.total_cmp(&o.upper)
    }
}

/// Bounds max_t |a(t) - b(t)| for two Bézier curves given as row-major control points of the
/// same dimension (degrees may differ).
pub(crate) fn deviation_bound(a: &[f64], b: &[f64], dim: usize) -> Result<DeviationBound> {
    let (na, nb) = (a.len() / dim - 1, b.len() / dim - 1);
    let deg = na.max(nb);
    let ea = elevate_flat(a, dim, deg)?;
    let eb = elevate_flat(b, dim, deg)?;
    let diff: Vec<f64> = ea.iter().zip(&eb).map(|(x, y)| x - y).collect();
    let scale = max_norm(&ea, dim).max(max_norm(&eb, dim));
    let slack = 4.0 * f64::EPSILON * (deg + 1) as f64 * scale;
    let norm_at = |c: &[f64], t: f64| {
        let mut work = vec![0.0; c.len()];
        let mut out = vec![0.0; dim];
        de_casteljau(c, dim, t, &mut work, &mut out);
        distance(&out, &vec![0.0; dim])
    };
    let upper_of = |c: &[f64]| max_norm(c, dim);

    let mut best = (norm_at(&diff, 0.0), 0.0);
    for t in [1.0, 0.5] {
        let v = norm_at(&diff, t);
        if v > best.0 {
            best = (v, t);
        }
    }
    let mut heap = BinaryHeap::new();
    heap.push(Piece {
        upper: upper_of(&diff),
        coeffs: diff,
        t0: 0.0,
        t1: 1.0,
    });
    let mut splits = 0;
    loop {
        let top = heap.pop().expect("heap never empties");
        if top.upper <= best.0 * 1.01 || splits >= 4000 || top.t1 - top.t0 < 1e-12 {
            return Ok(DeviationBound {
                max_found: best.0,
                at: best.1,
                upper_bound: top.upper.max(best.0) + slack,
            });
        }
        splits += 1;
        let (l, r) = split_flat(&top.coeffs, dim, 0.5);
        let tm = 0.5 * (top.t0 + top.t1);
        for (c, t0, t1) in [(l, top.t0, tm), (r, tm, top.t1)] {
            let mid = norm_at(&c, 0.5);
            if mid > best.0 {
                best = (mid, 0.5 * (t0 + t1));
            }
            let end = distance(&c[..dim], &vec![0.0; dim]);
            if end > best.0 {
                best = (end, t0);
            }
            heap.push(Piece {
                upper: upper_of(&c),
                coeffs: c,
                t0,
                t1,
            });
        }
    }
}
