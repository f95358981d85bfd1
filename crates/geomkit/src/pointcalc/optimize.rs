//! Global optimum of a modeled scalar response over the factors' box (spec/point-calculus.md
//! §4, "decision support").
//!
//! 1. Start from the best experimental point (its value is exactly the model's) and refine it
//!    locally by projected gradient steps with the barycentric derivatives.
//! 2. Branch and bound with Bernstein bounds: on a sub-box, the tensor polynomial is written in
//!    the tensor Bernstein basis (each cardinal function's Bernstein coefficients on the
//!    sub-interval are a product of linear factors, multiplied with degree-raising convex
//!    combinations); the largest coefficient bounds the polynomial on the box from above
//!    (convex hull property). Boxes whose bound is not above the best value found are
//!    dropped; the box with the largest bound is split in half along its widest factor and
//!    the model is evaluated at the centres of the halves (refined locally when they improve).
//! 3. Stop when the largest remaining bound is within the tolerance of the best value: the
//!    true optimum lies in [value, bound] (up to rounding: each bound carries a margin of
//!    64 ε Σ n_i max |b|), or when the box budget or the work budget runs out (then
//!    `certified` is false).
//!
//! The search runs on the values scaled by a power of two to |v| < 1 (exact), so source
//! values up to f64::MAX neither overflow the Bernstein coefficients nor the range; value,
//! bound and gap are scaled back at the end, and refused ([`Error::ResultOverflow`]) if they are
//! beyond f64. A certified result always has a finite bound.
//!
//! Limits: at most [`OptimizeOptions::max_boxes`] boxes (4000) and
//! [`OptimizeOptions::max_work`] operations (10^9: one box costs about
//! Π n_i · Σ n_i + Σ n_i³ / 2, one evaluation Π n_i); a model one box of which costs more
//! than the work budget is refused ([`Error::TooMany`]).
//!
//! ```
//! use geomkit::pointcalc::{optimize, Factor, Goal, Hypersurface, Nodes, OptimizeOptions};
//! // y = -(a - 0.3)² - (b - 0.6)² on a 3×3 grid: a quadratic, modeled exactly.
//! let f = |x: &[f64], out: &mut [f64]| out[0] = -(x[0] - 0.3).powi(2) - (x[1] - 0.6).powi(2);
//! let factors = vec![Factor::new("a", Nodes::paper_half()), Factor::new("b", Nodes::paper_half())];
//! let model = Hypersurface::from_fn(factors, 1, f, &Default::default()).unwrap();
//! let best = optimize(&model, Goal::Max, &OptimizeOptions::default()).unwrap();
//! assert!(best.certified && best.value.abs() < 1e-9);
//! assert!((best.at[0] - 0.3).abs() < 1e-4 && (best.at[1] - 0.6).abs() < 1e-4);
//! ```

use super::hypersurface::Hypersurface;
use crate::{Error, Result};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Largest or smallest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    /// The largest modeled response.
    Max,
    /// The smallest modeled response.
    Min,
}

/// Options of [`optimize`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct OptimizeOptions {
    /// Stop when bound - value <= tolerance × (range of the source values) [1e-9].
    pub tolerance: f64,
    /// Most boxes examined \[4000\].
    pub max_boxes: usize,
    /// Most operations (multiply-adds of the Bernstein bounds and the evaluations) before
    /// the search stops uncertified \[10^9, a few seconds\].
    pub max_work: u64,
}

impl Default for OptimizeOptions {
    fn default() -> Self {
        OptimizeOptions {
            tolerance: 1e-9,
            max_boxes: 4000,
            max_work: 1_000_000_000,
        }
    }
}

impl OptimizeOptions {
    /// Sets the relative tolerance.
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }

    /// Sets the box budget.
    pub fn with_max_boxes(mut self, max_boxes: usize) -> Self {
        self.max_boxes = max_boxes;
        self
    }

    /// Sets the work budget (operations).
    pub fn with_max_work(mut self, max_work: u64) -> Self {
        self.max_work = max_work;
        self
    }
}

/// The result of [`optimize`].
#[derive(Debug, Clone, PartialEq)]
pub struct Optimum {
    /// The factor values of the best point found.
    pub at: Vec<f64>,
    /// The modeled response there.
    pub value: f64,
    /// The certified bound: no point of the box does better than this (finite).
    pub bound: f64,
    /// |bound - value|.
    pub gap: f64,
    /// Boxes examined.
    pub boxes: usize,
    /// Whether the gap reached the tolerance within the budgets.
    pub certified: bool,
}

struct BoxItem {
    upper: f64,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl PartialEq for BoxItem {
    fn eq(&self, other: &Self) -> bool {
        self.upper == other.upper
    }
}
impl Eq for BoxItem {}
impl PartialOrd for BoxItem {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for BoxItem {
    fn cmp(&self, other: &Self) -> Ordering {
        self.upper.total_cmp(&other.upper)
    }
}

/// The global largest or smallest modeled response over the box of the factors' nodes
/// (see the module documentation). Errors: a model with vector source points (dim ≠ 1), an
/// invalid tolerance; [`Error::TooMany`] for a model one box of which costs more than
/// [`OptimizeOptions::max_work`]; [`Error::ResultOverflow`] when the optimum or its bound is beyond
/// f64 (source values near f64::MAX whose interpolant overshoots them, or nodes so uneven
/// that the Bernstein coefficients overflow).
pub fn optimize(model: &Hypersurface, goal: Goal, options: &OptimizeOptions) -> Result<Optimum> {
    if model.dim() != 1 {
        return Err(Error::WrongDimension {
            operation: "optimum search",
            expected: 1,
            got: model.dim(),
        });
    }
    if !options.tolerance.is_finite() || options.tolerance < 0.0 {
        return Err(Error::InvalidTolerance {
            value: options.tolerance,
        });
    }
    let shape = model.shape();
    let total_n: u64 = shape.iter().map(|&n| n as u64).sum();
    let cells = model.values().len() as u64;
    let box_cost = cells
        .saturating_mul(total_n)
        .saturating_add(shape.iter().map(|&n| (n as u64).pow(3) / 2).sum());
    if box_cost > options.max_work {
        return Err(Error::TooMany {
            what: "operations per box of the optimum search (cells × Σ levels + Σ levels³ / 2)",
            got: usize::try_from(box_cost).unwrap_or(usize::MAX),
            max: usize::try_from(options.max_work).unwrap_or(usize::MAX),
        });
    }
    // The search on values scaled to |v| < 1 by a power of two (exact), scaled back at the end.
    let largest = model.values().iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let e = super::wide::exponent(largest);
    let best = search(&model.scaled_by(e), goal, options, box_cost)?;
    let back = |v: f64| super::wide::ldexp(v, e);
    let name = match goal {
        Goal::Max => "largest",
        Goal::Min => "smallest",
    };
    let (value, bound, gap) = (back(best.value), back(best.bound), back(best.gap));
    if !value.is_finite() {
        return Err(Error::ResultOverflow {
            what: format!("the {name} modeled value"),
        });
    }
    if !bound.is_finite() || !gap.is_finite() {
        return Err(Error::ResultOverflow {
            what: format!(
                "the certified bound of the {name} modeled value (the Bernstein coefficients \
                 of the model on its box, or its distance to the value found)"
            ),
        });
    }
    Ok(Optimum {
        value,
        bound,
        gap,
        ..best
    })
}

/// [`optimize`] on a model with values |v| < 1 (no range or Bernstein coefficient overflows
/// there, unless the nodes are extremely uneven: then the bound is not finite and the result
/// not certified).
fn search(
    model: &Hypersurface,
    goal: Goal,
    options: &OptimizeOptions,
    box_cost: u64,
) -> Result<Optimum> {
    let work = std::cell::Cell::new(0u64);
    let eval_cost = model.values().len() as u64 + model.shape().iter().sum::<usize>() as u64;
    let exhausted = || work.get() > options.max_work;
    let sign = match goal {
        Goal::Max => 1.0,
        Goal::Min => -1.0,
    };
    let k = model.k();
    let domain = model.domain();
    let values: Vec<f64> = model.values().iter().map(|v| sign * v).collect();
    let (vmin, vmax) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let range = (vmax - vmin)
        .max(vmax.abs() * 1e-300)
        .max(f64::MIN_POSITIVE);
    let tolerance = options.tolerance * range;
    let to_x = |s: &[f64]| -> Vec<f64> {
        s.iter()
            .zip(&domain)
            .map(|(&s, &(a, b))| if s >= 1.0 { b } else { a + (b - a) * s })
            .collect()
    };
    // The modeled value at s in [0, 1]^k (-infinity once the work budget is spent: nothing
    // improves on it, so the local search stops).
    let g = |s: &[f64]| {
        if exhausted() {
            return f64::NEG_INFINITY;
        }
        work.set(work.get() + eval_cost);
        sign * model.eval(&to_x(s)).map(|v| v[0]).unwrap_or(f64::NAN)
    };

    // 1. The best experimental point, refined.
    let best_cell = values
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(c, _)| c)
        .unwrap_or(0);
    let cell_x = model.cell_levels(best_cell);
    let mut best_s: Vec<f64> = cell_x
        .iter()
        .zip(&domain)
        .map(|(&x, &(a, b))| if b > a { (x - a) / (b - a) } else { 0.0 })
        .collect();
    let mut best = values[best_cell];
    let grad_s = |s: &[f64]| -> Vec<f64> {
        work.set(work.get() + eval_cost * k as u64);
        let gx = model.gradient(&to_x(s)).unwrap_or_else(|_| vec![0.0; k]);
        gx.iter()
            .zip(&domain)
            .map(|(d, &(a, b))| sign * d * (b - a))
            .collect()
    };
    let refine = |s0: &[f64], v0: f64| -> (Vec<f64>, f64) { local_ascent(s0, v0, &g, &grad_s) };
    (best_s, best) = {
        let (s, v) = refine(&best_s, best);
        if v > best {
            (s, v)
        } else {
            (best_s, best)
        }
    };

    // 2. Branch and bound.
    let nodes_s: Vec<Vec<f64>> = model
        .factors()
        .iter()
        .zip(&domain)
        .map(|(f, &(a, b))| {
            f.nodes()
                .values()
                .iter()
                .map(|&x| if b > a { (x - a) / (b - a) } else { 0.0 })
                .collect()
        })
        .collect();
    let shape = model.shape();
    let total_n: usize = shape.iter().sum();
    let upper_of = |lo: &[f64], hi: &[f64]| -> f64 {
        work.set(work.get() + box_cost);
        let mut coefs = values.clone();
        for f in 0..k {
            let m = bernstein_matrix(&nodes_s[f], lo[f], hi[f]);
            mode_product(&mut coefs, &shape, f, &m);
        }
        // A coefficient that overflowed (±infinity, NaN) bounds nothing: +infinity keeps the
        // box (and the search uncertified), where NaN would be dropped by every comparison
        // (and ignored by f64::max).
        if coefs.iter().any(|c| !c.is_finite()) {
            return f64::INFINITY;
        }
        let (mx, amax) = coefs
            .iter()
            .fold((f64::NEG_INFINITY, 0.0f64), |(m, a), &c| {
                (m.max(c), a.max(c.abs()))
            });
        let upper = mx + 64.0 * f64::EPSILON * total_n as f64 * amax;
        if upper.is_finite() {
            upper
        } else {
            f64::INFINITY
        }
    };
    let mut heap = BinaryHeap::new();
    let (lo0, hi0) = (vec![0.0; k], vec![1.0; k]);
    let upper = upper_of(&lo0, &hi0);
    if !upper.is_finite() {
        // Nothing to refine: the Bernstein coefficients of the whole box overflow.
        return Err(Error::ResultOverflow {
            what: format!(
                "the Bernstein bound of the model on its box (degree {} in a factor: the \
                 Bernstein coefficients of high-degree cardinal functions grow like 2^n; use \
                 fewer levels or a smaller range of values)",
                shape.iter().max().map_or(0, |n| n.saturating_sub(1))
            ),
        });
    }
    heap.push(BoxItem {
        upper,
        lo: lo0,
        hi: hi0,
    });
    let mut boxes = 1;
    let mut bound;
    let mut certified = false;
    loop {
        let Some(item) = heap.pop() else {
            bound = best;
            certified = true;
            break;
        };
        bound = item.upper.max(best);
        if item.upper - best <= tolerance {
            certified = true;
            break;
        }
        // The two halves must fit in the work budget.
        let halves = work.get().saturating_add(box_cost.saturating_mul(2));
        if boxes >= options.max_boxes || halves > options.max_work {
            break;
        }
        // Split along the widest factor that has more than one level.
        let f = (0..k)
            .filter(|&f| shape[f] > 1)
            .max_by(|&a, &b| (item.hi[a] - item.lo[a]).total_cmp(&(item.hi[b] - item.lo[b])))
            .unwrap_or(0);
        let mid = 0.5 * (item.lo[f] + item.hi[f]);
        for (l, h) in [(item.lo[f], mid), (mid, item.hi[f])] {
            let mut lo = item.lo.clone();
            let mut hi = item.hi.clone();
            lo[f] = l;
            hi[f] = h;
            boxes += 1;
            let upper = upper_of(&lo, &hi);
            let centre: Vec<f64> = lo.iter().zip(&hi).map(|(a, b)| 0.5 * (a + b)).collect();
            let v = g(&centre);
            if v > best {
                let (s, v2) = refine(&centre, v);
                (best_s, best) = if v2 > v { (s, v2) } else { (centre, v) };
            }
            if upper > best + tolerance {
                heap.push(BoxItem { upper, lo, hi });
            }
        }
    }
    if let Some(top) = heap.peek() {
        bound = bound.max(top.upper);
    }
    // A NaN or infinite Bernstein bound certifies nothing.
    let certified = certified && bound.is_finite();
    Ok(Optimum {
        at: to_x(&best_s),
        value: sign * best,
        bound: sign * bound,
        gap: (bound - best).max(0.0),
        boxes,
        certified,
    })
}

/// Projected gradient ascent in [0, 1]^k with backtracking, from `s0` (value `v0`).
fn local_ascent(
    s0: &[f64],
    v0: f64,
    g: &dyn Fn(&[f64]) -> f64,
    grad: &dyn Fn(&[f64]) -> Vec<f64>,
) -> (Vec<f64>, f64) {
    let (mut s, mut v) = (s0.to_vec(), v0);
    let mut step = 0.25;
    for _ in 0..200 {
        let d = grad(&s);
        let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm.is_nan() || norm <= 0.0 || !norm.is_finite() {
            break;
        }
        let mut improved = false;
        while step > 1e-13 {
            let t: Vec<f64> = s
                .iter()
                .zip(&d)
                .map(|(x, dx)| (x + step * dx / norm).clamp(0.0, 1.0))
                .collect();
            let vt = g(&t);
            if vt > v {
                (s, v) = (t, vt);
                step *= 2.0;
                improved = true;
                break;
            }
            step *= 0.5;
        }
        if !improved {
            break;
        }
    }
    (s, v)
}

/// M[k][j]: the Bernstein coefficients (degree n-1 on [lo, hi]) of the cardinal functions of
/// nodes `s` (in [0, 1]), row-major n×n.
fn bernstein_matrix(s: &[f64], lo: f64, hi: f64) -> Vec<f64> {
    let n = s.len();
    let mut m = vec![0.0; n * n];
    // The coefficients of the product so far (degree p), raised in place to degree p + 1.
    let mut c = vec![0.0; n];
    for j in 0..n {
        // product of the linear factors (x - s_m) / (s_j - s_m), x = lo + (hi - lo) τ
        c[0] = 1.0;
        let mut p = 0; // degree of c
        for (mi, &sm) in s.iter().enumerate() {
            if mi == j {
                continue;
            }
            let den = s[j] - sm;
            let (q0, q1) = ((lo - sm) / den, (hi - sm) / den);
            let d = (p + 1) as f64;
            // next[kk] = (p+1-kk)/(p+1) c[kk] q0 + kk/(p+1) c[kk-1] q1, from the top down.
            c[p + 1] = c[p] * q1;
            for kk in (1..=p).rev() {
                c[kk] = (p + 1 - kk) as f64 / d * c[kk] * q0 + kk as f64 / d * c[kk - 1] * q1;
            }
            c[0] *= q0;
            p += 1;
        }
        for (kk, ck) in c.iter().enumerate() {
            m[kk * n + j] = *ck;
        }
    }
    m
}

/// values ← values ×_f M (mode-f product with the n×n matrix M, scalar values).
fn mode_product(values: &mut [f64], shape: &[usize], f: usize, m: &[f64]) {
    let n = shape[f];
    if n == 1 {
        return;
    }
    let outer: usize = shape[..f].iter().product();
    let inner: usize = shape[f + 1..].iter().product();
    let mut block = vec![0.0; n * inner];
    for o in 0..outer {
        let src = &mut values[o * n * inner..(o + 1) * n * inner];
        block.fill(0.0);
        for kk in 0..n {
            let out = &mut block[kk * inner..(kk + 1) * inner];
            for j in 0..n {
                let mkj = m[kk * n + j];
                if mkj != 0.0 {
                    for (o, v) in out.iter_mut().zip(&src[j * inner..(j + 1) * inner]) {
                        *o += mkj * v;
                    }
                }
            }
        }
        src.copy_from_slice(&block);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pointcalc::{Factor, NodePreset, Nodes};

    #[test]
    fn bernstein_matrix_reproduces_cardinals() {
        let s = [0.0, 0.2, 0.7, 1.0];
        let nodes = Nodes::new(s.to_vec()).unwrap();
        let (lo, hi) = (0.1, 0.6);
        let m = bernstein_matrix(&s, lo, hi);
        for tau in [0.0, 0.3, 1.0] {
            let x = lo + (hi - lo) * tau;
            let l = nodes.basis(x);
            for j in 0..4 {
                // Σ_k M[k][j] B_k^3(τ)
                let b = [
                    (1.0 - tau).powi(3),
                    3.0 * tau * (1.0 - tau).powi(2),
                    3.0 * tau * tau * (1.0 - tau),
                    tau.powi(3),
                ];
                let v: f64 = (0..4).map(|k| m[k * 4 + j] * b[k]).sum();
                assert!((v - l[j]).abs() < 1e-14, "{tau} {j}");
            }
        }
    }

    #[test]
    fn finds_interior_minimum_of_sixth_degree_model() {
        let f = |x: &[f64], out: &mut [f64]| {
            out[0] = (3.0 * x[0]).sin() * (2.0 * x[1]).cos() + 0.3 * x[2] * x[2] - 0.1 * x[2]
        };
        let factors: Vec<Factor> = ["a", "b", "c"]
            .iter()
            .map(|n| {
                Factor::new(
                    *n,
                    Nodes::preset(NodePreset::ChebyshevSecond, 7, -1.0, 1.0).unwrap(),
                )
            })
            .collect();
        let model = Hypersurface::from_fn(factors, 1, f, &Default::default()).unwrap();
        let opt = optimize(&model, Goal::Min, &OptimizeOptions::default()).unwrap();
        assert!(opt.certified, "{opt:?}");
        // brute force on a fine grid never beats the certified bound
        let mut lowest = f64::INFINITY;
        for i in 0..=40 {
            for j in 0..=40 {
                for l in 0..=40 {
                    let x = [
                        i as f64 / 20.0 - 1.0,
                        j as f64 / 20.0 - 1.0,
                        l as f64 / 20.0 - 1.0,
                    ];
                    lowest = lowest.min(model.eval(&x).unwrap()[0]);
                }
            }
        }
        assert!(
            opt.bound <= lowest + 1e-12 && opt.value <= lowest + 1e-12,
            "{opt:?} {lowest}"
        );
        assert!(opt.value - opt.bound <= 1e-8);
    }
}
