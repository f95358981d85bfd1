//! Change of degree of Bézier curves, up and down, keeping the shape (spec/bezier-order.md,
//! formulas (6)-(10)), done stably in f64:
//!
//! - **Elevation** to any n' > n in one step with the closed form (8),
//!   u'_j = Σ_i C(n,i) C(n'-n,j-i) / C(n',j) u_i: each new point is a convex combination whose
//!   weights are computed and accumulated in double-double, so each new point is within
//!   eps·max|u| of its exact value (tested for every n <= 100).
//! - **Real degree and degree defect** by a residual test: reduce by least squares on the
//!   elevation matrix, re-elevate, compare with a tolerance relative to max|u|
//!   ([`DEFAULT_TOLERANCE`]). Never through the power form.
//! - **Exact reduction** (when the defect allows): least squares on the elevation matrix
//!   (Householder QR) with iterative refinement of the residual in double-double.
//! - **Approximate reduction** (when it does not): best approximation in L2\[0,1\] (or the
//!   Chebyshev-weighted norm, near-best in L∞) with optional C^α / C^β continuity at the
//!   ends, and a guaranteed error report.
//! - The paper's unified formula (10) as written, in exact rationals rounded once, and the
//!   naive f64 evaluation of it, for comparison.
//!
//! ```
//! use geomkit::bezier::BezierCurve;
//! let quintic = BezierCurve::new(vec![
//!     vec![10., 0.], vec![22., 6.], vec![19., 12.], vec![11., 15.], vec![8., 12.], vec![20., 0.],
//! ]).unwrap();
//! let report = quintic.degree_report(None).unwrap();
//! assert_eq!((report.degree, report.real_degree, report.defect), (5, 3, 2));
//! let cubic = quintic.reduce_degree(3, None).unwrap();
//! let back = cubic.elevate_degree(5).unwrap();
//! assert!(back.points_flat().iter().zip(quintic.points_flat()).all(|(a, b)| (a - b).abs() < 1e-13));
//! ```

use super::bound::{deviation_bound, DeviationBound};
use super::curve::{de_casteljau, BezierCurve};
use crate::numeric::{bernstein_all, gauss_chebyshev, gauss_legendre, max_norm, Dd};
use crate::progress::Progress;
use crate::{Error, Result};
use nalgebra::DMatrix;

/// Default relative tolerance of the residual test: a curve is reducible to degree k when
/// re-elevating its least-squares reduction reproduces every control point within
/// `DEFAULT_TOLERANCE · max|u_i|`.
pub const DEFAULT_TOLERANCE: f64 = 1e-12;

/// The elevation matrix n -> n' by columns: column j holds the weights
/// w_ji = C(n,i) C(n'-n,j-i) / C(n',j) for i = first[j].. (double-double, correctly rounded),
/// stored contiguously in one buffer.
pub(crate) struct ElevationWeights {
    first: Vec<usize>,
    offset: Vec<usize>,
    w: Vec<Dd>,
}

impl ElevationWeights {
    /// First row index and weights of column j.
    #[inline]
    pub fn column(&self, j: usize) -> (usize, &[Dd]) {
        (self.first[j], &self.w[self.offset[j]..self.offset[j + 1]])
    }
}

/// Most weights an elevation matrix may hold: (n'+1)·(min(n, n'-n)+1) double-double
/// numbers, 16 bytes each (2^25: 512 MiB, about a second of work). Elevating a cubic to
/// degree 10^6 needs 4·10^6; a degree-1000 curve to 999 999 would need 10^9 (16 GB).
pub const MAX_ELEVATION_WEIGHTS: usize = 1 << 25;

/// Highest degree the residual test (real degree), exact reduction and approximate reduction
/// take: their least-squares problems cost O(n^3) (degree 1000: about 2 s, degree 2000:
/// 13 s on a 2-core machine).
pub const MAX_REDUCTION_DEGREE: usize = 1024;

/// Refuses a reduction of a curve of degree `n` above [`MAX_REDUCTION_DEGREE`].
pub(crate) fn check_reduction_degree(n: usize, operation: &str) -> Result<()> {
    if n > MAX_REDUCTION_DEGREE {
        return Err(Error::TooLarge {
            what: format!("{operation} needs O(n^3) work"),
            size: n as u128,
            unit: "degree",
            limit: MAX_REDUCTION_DEGREE as u128,
        });
    }
    Ok(())
}

/// The elevation matrix n -> n', or [`Error::TooLarge`] when it would hold more than
/// [`MAX_ELEVATION_WEIGHTS`] weights.
pub(crate) fn elevation_weights(n: usize, n_new: usize) -> Result<ElevationWeights> {
    let m = n_new - n;
    let count = (n_new as u128 + 1) * (n.min(m) as u128 + 1);
    if count > MAX_ELEVATION_WEIGHTS as u128 {
        return Err(Error::TooLarge {
            what: format!("elevating degree {n} to {n_new}"),
            size: count,
            unit: "weight count",
            limit: MAX_ELEVATION_WEIGHTS as u128,
        });
    }
    let mut first = Vec::with_capacity(n_new + 1);
    let mut offset = Vec::with_capacity(n_new + 2);
    let mut w: Vec<Dd> = Vec::with_capacity((n_new + 1) * (n.min(m) + 1));
    offset.push(0);
    for j in 0..=n_new {
        let i0 = j.saturating_sub(m);
        let i1 = n.min(j);
        let start = w.len();
        if m == 1 {
            // Elevation by one, formula (6): weights j/(n+1) and (n+1-j)/(n+1).
            let np1 = (n + 1) as f64;
            if j > 0 {
                w.push(Dd::from_f64(j as f64).div_f64(np1));
            }
            if j <= n {
                w.push(Dd::from_f64((n + 1 - j) as f64).div_f64(np1));
            }
            first.push(i0);
            offset.push(w.len());
            continue;
        }
        // Unnormalized weights by the ratio recurrence, then divide by their sum
        // (Vandermonde: Σ_i C(n,i) C(m,j-i) = C(n',j)), which avoids under/overflow.
        let mut cur = Dd::from_f64(1.0);
        let mut total = Dd::ZERO;
        for i in i0..=i1 {
            if i > i0 {
                let num = ((n - i + 1) * (j - i + 1)) as f64;
                let den = (i * (m + i - j)) as f64;
                cur = cur.mul_f64(num).div_f64(den);
                if cur.hi > 1e200 {
                    let s = 2f64.powi(-600);
                    cur = cur.mul_f64(s);
                    total = total.mul_f64(s);
                    w[start..].iter_mut().for_each(|x| *x = x.mul_f64(s));
                }
            }
            w.push(cur);
            total = total.add(cur);
        }
        let inv = Dd::from_f64(1.0).div(total);
        w[start..].iter_mut().for_each(|x| *x = x.mul(inv));
        first.push(i0);
        offset.push(w.len());
    }
    Ok(ElevationWeights { first, offset, w })
}

/// Elevates row-major control points (`dim` each) to degree `n_new` >= n with the closed
/// form (8), accumulating in double-double.
pub(crate) fn elevate_flat(pts: &[f64], dim: usize, n_new: usize) -> Result<Vec<f64>> {
    elevate_flat_reporting(pts, dim, n_new, &Progress::none())
}

/// Multiply-adds of [`elevate_flat_reporting`] between two reports.
const ELEVATION_WORK_PER_REPORT: usize = 1 << 18;

/// [`elevate_flat`] reporting its n_new + 1 output points to `progress` (a report once
/// every [`ELEVATION_WORK_PER_REPORT`] multiply-adds or so; the caller announced the
/// total). Cancelled: [`Error::Cancelled`].
pub(crate) fn elevate_flat_reporting(
    pts: &[f64],
    dim: usize,
    n_new: usize,
    progress: &Progress,
) -> Result<Vec<f64>> {
    let n = pts.len() / dim - 1;
    if n_new == n {
        progress.advance((n_new + 1) as u64)?;
        return Ok(pts.to_vec());
    }
    let weights = elevation_weights(n, n_new)?;
    // The double-double products split their factors (Veltkamp: x·(2^27+1)), which
    // overflows for |x| above about 2^996: such points are elevated at 2^-64 of their size
    // (exact) and scaled back; the result is a convex combination, so it fits.
    let largest = pts.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest > 2f64.powi(960) {
        let small: Vec<f64> = pts.iter().map(|x| x * 2f64.powi(-64)).collect();
        let mut out = elevate_flat_reporting(&small, dim, n_new, progress)?;
        out.iter_mut().for_each(|x| *x *= 2f64.powi(64));
        return Ok(out);
    }
    let mut out = vec![0.0; (n_new + 1) * dim];
    // Output points and multiply-adds since the last report.
    let (mut rows, mut work) = (0, 0);
    for j in 0..=n_new {
        let (i0, w) = weights.column(j);
        for k in 0..dim {
            let mut acc = Dd::ZERO;
            for (r, wi) in w.iter().enumerate() {
                acc = acc.fma(*wi, pts[(i0 + r) * dim + k]);
            }
            out[j * dim + k] = acc.to_f64();
        }
        (rows, work) = (rows + 1, work + w.len() * dim);
        if work >= ELEVATION_WORK_PER_REPORT {
            progress.advance(rows)?;
            (rows, work) = (0, 0);
        }
    }
    progress.advance(rows)?;
    Ok(out)
}

/// Least-squares reduction of row-major control points of degree N to degree `n_new` < N:
/// min ||E X - Q|| over X, E the (N+1)×(n'+1) elevation matrix. Returns X and the
/// **relative** residual: the largest Euclidean norm of E X - Q over points of `point_dim`
/// coordinates (a surface viewed as a curve has `dim` = (m+1)·r but `point_dim` = r),
/// divided by max|u_i| (0 for all-zero points).
///
/// The solve runs on the points scaled by a power of two that brings max|coordinate| into
/// [1/2, 1) (exact), so coordinates near f64::MAX neither overflow in the QR factorization
/// nor in the norms, and the real-degree test and the exact reduction see the same
/// residual whatever the data's magnitude.
pub(crate) fn reduce_least_squares(
    q: &[f64],
    dim: usize,
    point_dim: usize,
    n_new: usize,
) -> Result<(Vec<f64>, f64)> {
    let (mut x, relative, e) = least_squares_scaled(q, dim, point_dim, n_new)?;
    let (half, rest) = (e / 2, e - e / 2);
    x.iter_mut()
        .for_each(|v| *v = *v * 2f64.powi(half) * 2f64.powi(rest));
    if x.iter().any(|v| !v.is_finite()) {
        // A least-squares solution can exceed the data (it is not a convex combination).
        return Err(Error::Numerical {
            operation: "degree reduction",
            reason: "a reduced control point overflows f64",
        });
    }
    Ok((x, relative))
}

/// [`reduce_least_squares`] on the points scaled by 2^-e (returned), so that the largest
/// |coordinate| is in [1/2, 1): X in those units, and the relative residual (which the
/// real-degree test needs alone, even when X itself would overflow at the data's scale).
fn least_squares_scaled(
    q: &[f64],
    dim: usize,
    point_dim: usize,
    n_new: usize,
) -> Result<(Vec<f64>, f64, i32)> {
    let big_n = q.len() / dim - 1;
    check_reduction_degree(big_n, "a degree reduction")?;
    let largest = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if largest == 0.0 {
        return Ok((vec![0.0; (n_new + 1) * dim], 0.0, 0));
    }
    // 2^-e applied as two factors so that neither the scale nor its inverse overflows or
    // underflows (subnormal data: e down to -1073).
    let exp = largest.log2().floor() as i32 + 1;
    let (half, rest) = (exp / 2, exp - exp / 2);
    let q: Vec<f64> = q
        .iter()
        .map(|&x| x * 2f64.powi(-half) * 2f64.powi(-rest))
        .collect();
    let weights = elevation_weights(n_new, big_n)?;
    let mut e = DMatrix::<f64>::zeros(big_n + 1, n_new + 1);
    for j in 0..=big_n {
        let (i0, w) = weights.column(j);
        for (r, wi) in w.iter().enumerate() {
            e[(j, i0 + r)] = wi.hi;
        }
    }
    let qr = e.qr();
    let r = qr.r();
    if (0..=n_new).any(|i| r[(i, i)] == 0.0) {
        return Err(Error::Numerical {
            operation: "degree reduction",
            reason: "singular elevation matrix",
        });
    }
    let solve = |rhs: DMatrix<f64>| -> Result<DMatrix<f64>> {
        let mut rhs = rhs;
        qr.q_tr_mul(&mut rhs);
        let top = rhs.rows(0, n_new + 1).into_owned();
        r.solve_upper_triangular(&top).ok_or(Error::Numerical {
            operation: "degree reduction",
            reason: "triangular solve failed",
        })
    };
    // Residual Q - E X in double-double, as a (N+1)×dim matrix.
    let residual = |x: &DMatrix<f64>| {
        DMatrix::from_fn(big_n + 1, dim, |j, k| {
            let (i0, w) = weights.column(j);
            let mut acc = Dd::from_f64(q[j * dim + k]);
            for (r, wi) in w.iter().enumerate() {
                acc = acc.fma(
                    Dd {
                        hi: -wi.hi,
                        lo: -wi.lo,
                    },
                    x[(i0 + r, k)],
                );
            }
            acc.to_f64()
        })
    };
    let b = DMatrix::from_fn(big_n + 1, dim, |j, k| q[j * dim + k]);
    let mut x = solve(b)?;
    // Two steps of iterative refinement with the residual in extended precision.
    for _ in 0..2 {
        let res = residual(&x);
        x += solve(res)?;
    }
    let res = residual(&x).transpose();
    let scale = max_norm(&q, point_dim);
    let relative = max_norm(res.as_slice(), point_dim) / scale;
    // Entries below the accuracy floor eps·max|u| are zero within what the data determine
    // (refinement otherwise leaves noise like 1e-33 where the exact answer is 0).
    let floor = f64::EPSILON * scale;
    let mut out = vec![0.0; (n_new + 1) * dim];
    for i in 0..=n_new {
        for k in 0..dim {
            let v = x[(i, k)];
            out[i * dim + k] = if v.abs() < floor { 0.0 } else { v };
        }
    }
    Ok((out, relative, exp))
}

/// Relative residual of reducing to degree `k`: max control-point distance between the
/// input and its re-elevated least-squares reduction, divided by max|u_i|.
pub(crate) fn relative_residual(q: &[f64], dim: usize, point_dim: usize, k: usize) -> Result<f64> {
    let n = q.len() / dim - 1;
    if k >= n {
        return Ok(0.0);
    }
    Ok(least_squares_scaled(q, dim, point_dim, k)?.1)
}

pub(crate) fn check_tolerance(tolerance: Option<f64>) -> Result<f64> {
    let t = tolerance.unwrap_or(DEFAULT_TOLERANCE);
    if !t.is_finite() || t < 0.0 {
        return Err(Error::InvalidTolerance { value: t });
    }
    Ok(t)
}

/// The real degree of row-major control points: the least k whose relative residual is
/// <= tolerance (binary search: the residual does not increase with k).
pub(crate) fn real_degree_flat(
    q: &[f64],
    dim: usize,
    point_dim: usize,
    tolerance: f64,
) -> Result<DegreeReport> {
    let n = q.len() / dim - 1;
    check_reduction_degree(n, "the real-degree test")?;
    // Invariant: residual(hi) <= tolerance, residual(k) > tolerance for every k < lo.
    let (mut lo, mut hi) = (0usize, n);
    let mut res_hi = 0.0;
    let mut last_failure = None;
    while lo < hi {
        let mid = (lo + hi) / 2;
        let r = relative_residual(q, dim, point_dim, mid)?;
        if r <= tolerance {
            hi = mid;
            res_hi = r;
        } else {
            lo = mid + 1;
            last_failure = Some((mid, r));
        }
    }
    let real = hi;
    let rejected_residual = match last_failure {
        Some((k, r)) if k + 1 == real => Some(r),
        _ if real > 0 => Some(relative_residual(q, dim, point_dim, real - 1)?),
        _ => None,
    };
    Ok(DegreeReport {
        degree: n,
        real_degree: real,
        defect: n - real,
        residual: res_hi,
        rejected_residual,
        tolerance,
    })
}

/// Result of the residual test for the real degree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DegreeReport {
    /// Formal degree n.
    pub degree: usize,
    /// Real degree n*: the least degree the curve reduces to within the tolerance.
    pub real_degree: usize,
    /// Degree defect d = n - n*.
    pub defect: usize,
    /// Relative residual of the reduction to the real degree (<= tolerance).
    pub residual: f64,
    /// Relative residual of the reduction to one degree below the real degree (> tolerance);
    /// `None` when the real degree is 0. The gap between the two residuals shows how clear
    /// the decision is.
    pub rejected_residual: Option<f64>,
    /// The relative tolerance used.
    pub tolerance: f64,
}

/// Which norm an approximate reduction minimizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ReductionNorm {
    /// Best approximation in L2[0, 1]: min ∫ |p(t) - q(t)|² dt.
    #[default]
    L2,
    /// Best approximation in the Chebyshev-weighted norm ∫ |p - q|² / sqrt(t(1-t)) dt:
    /// a near-best L∞ (minimax) approximation.
    Chebyshev,
}

/// Options of [`BezierCurve::reduce_degree_approx`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct ApproxOptions {
    /// C^α continuity at t = 0: derivatives 0..=α equal the original's. `None`: free.
    pub start_continuity: Option<usize>,
    /// C^β continuity at t = 1. `None`: free.
    pub end_continuity: Option<usize>,
    /// The norm minimized.
    pub norm: ReductionNorm,
}

impl ApproxOptions {
    /// Sets C^α continuity at t = 0 and C^β at t = 1.
    pub fn with_continuity(mut self, start: Option<usize>, end: Option<usize>) -> Self {
        self.start_continuity = start;
        self.end_continuity = end;
        self
    }

    /// Sets the norm minimized.
    pub fn with_norm(mut self, norm: ReductionNorm) -> Self {
        self.norm = norm;
        self
    }
}

/// An approximate reduction with its error report.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproxReduction {
    /// The reduced curve.
    pub curve: BezierCurve,
    /// sqrt(∫_0^1 |p(t) - q(t)|² dt), exact up to rounding (Gauss–Legendre).
    pub l2_error: f64,
    /// Distance bound between the original and reduced curves over [0, 1].
    pub linf: DeviationBound,
}

/// Control points fixed by C^α continuity at t = 0 of a degree-m reduction of `q` (degree N):
/// Δ^k p_0 = (N!/(N-k)!)·((m-k)!/m!) Δ^k q_0, then p_k = Σ_i C(k,i) Δ^i p_0.
fn end_points(q: &[f64], dim: usize, m: usize, alpha: usize) -> Vec<f64> {
    let big_n = q.len() / dim - 1;
    // Forward differences Δ^k q_0 for k <= alpha.
    let mut diffs = Vec::with_capacity((alpha + 1) * dim);
    let mut work: Vec<f64> = q[..(alpha + 1).min(big_n + 1) * dim].to_vec();
    let mut rho = 1.0;
    for k in 0..=alpha {
        diffs.extend(work[..dim].iter().map(|v| v * rho));
        let len = work.len() / dim;
        for i in 0..len.saturating_sub(1) {
            for c in 0..dim {
                work[i * dim + c] = work[(i + 1) * dim + c] - work[i * dim + c];
            }
        }
        work.truncate(len.saturating_sub(1) * dim);
        rho *= (big_n - k) as f64 / (m - k) as f64;
    }
    let mut p = vec![0.0; (alpha + 1) * dim];
    for k in 0..=alpha {
        let mut binom = 1.0;
        for i in 0..=k {
            for c in 0..dim {
                p[k * dim + c] += binom * diffs[i * dim + c];
            }
            binom = binom * (k - i) as f64 / (i + 1) as f64;
        }
    }
    p
}

fn reversed(q: &[f64], dim: usize) -> Vec<f64> {
    q.chunks_exact(dim).rev().flatten().copied().collect()
}

/// The degree-m points `p` at `free` (the others fixed as given) that minimize the
/// quadrature Σ w_r |Q(t_r) − P(t_r)|² over the nodes and weights `rule`, Q the degree-N
/// points `q` (`dim` numbers each): weighted least squares by SVD. Errors name `operation`.
pub(crate) fn least_squares(
    q: &[f64],
    dim: usize,
    m: usize,
    (nodes, weights): (&[f64], &[f64]),
    p: &mut [f64],
    free: &[usize],
    operation: &'static str,
) -> Result<()> {
    let k = nodes.len();
    let mut a = DMatrix::<f64>::zeros(k, free.len());
    let mut rhs = DMatrix::<f64>::zeros(k, dim);
    let mut basis = vec![0.0; m + 1];
    let mut work = vec![0.0; q.len()];
    let mut qt = vec![0.0; dim];
    for (row, (&t, &w)) in nodes.iter().zip(weights).enumerate() {
        let sw = w.sqrt();
        bernstein_all(m, t, &mut basis);
        de_casteljau(q, dim, t, &mut work, &mut qt);
        for c in 0..dim {
            let fixed: f64 = (0..=m)
                .filter(|i| !free.contains(i))
                .map(|i| basis[i] * p[i * dim + c])
                .sum();
            rhs[(row, c)] = sw * (qt[c] - fixed);
        }
        for (col, &i) in free.iter().enumerate() {
            a[(row, col)] = sw * basis[i];
        }
    }
    let x = a
        .svd(true, true)
        .solve(&rhs, 0.0)
        .map_err(|_| Error::Numerical {
            operation,
            reason: "least-squares solve failed",
        })?;
    for (col, &i) in free.iter().enumerate() {
        for c in 0..dim {
            p[i * dim + c] = x[(col, c)];
        }
    }
    Ok(())
}

/// Approximate reduction of row-major control points to degree m.
pub(crate) fn reduce_approx_flat(
    q: &[f64],
    dim: usize,
    m: usize,
    options: &ApproxOptions,
) -> Result<(Vec<f64>, f64, DeviationBound)> {
    let big_n = q.len() / dim - 1;
    check_reduction_degree(big_n, "an approximate reduction")?;
    if m >= big_n {
        return Err(Error::InvalidDegree {
            degree: big_n,
            requested: m,
            reason: "a reduction needs a lower degree",
        });
    }
    let fixed_start = options.start_continuity.map_or(0, |a| a + 1);
    let fixed_end = options.end_continuity.map_or(0, |b| b + 1);
    if fixed_start + fixed_end > m + 1 {
        return Err(Error::ContinuityTooHigh {
            start: options.start_continuity.unwrap_or(0),
            end: options.end_continuity.unwrap_or(0),
            fixed: fixed_start + fixed_end,
            degree: m,
            available: m + 1,
        });
    }
    let mut p = vec![0.0; (m + 1) * dim];
    if let Some(a) = options.start_continuity {
        p[..(a + 1) * dim].copy_from_slice(&end_points(q, dim, m, a));
    }
    if let Some(b) = options.end_continuity {
        let rev = reversed(&end_points(&reversed(q, dim), dim, m, b), dim);
        p[(m - b) * dim..].copy_from_slice(&rev);
    }
    // Free control points between the fixed ends (fixed_start + fixed_end <= m + 1 above, so
    // the range is never reversed: `m - fixed_end` would underflow when only the end is
    // fixed, all m + 1 points of it).
    let free: Vec<usize> = (fixed_start..m + 1 - fixed_end).collect();
    let k = big_n + 1;
    let (nodes, weights) = match options.norm {
        ReductionNorm::L2 => gauss_legendre(k),
        ReductionNorm::Chebyshev => gauss_chebyshev(k),
    };
    if !free.is_empty() {
        least_squares(
            q,
            dim,
            m,
            (&nodes, &weights),
            &mut p,
            &free,
            "approximate reduction",
        )?;
    }
    if let Some(index) = p.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            what: "reduced control point",
            index: index / dim,
        });
    }
    // L2 error by Gauss–Legendre with N+1 nodes (exact for the degree-2N integrand).
    let (gx, gw) = gauss_legendre(k);
    let mut work_q = vec![0.0; q.len()];
    let mut work_p = vec![0.0; p.len()];
    let (mut vq, mut vp) = (vec![0.0; dim], vec![0.0; dim]);
    let mut l2 = 0.0;
    for (&t, &w) in gx.iter().zip(&gw) {
        de_casteljau(q, dim, t, &mut work_q, &mut vq);
        de_casteljau(&p, dim, t, &mut work_p, &mut vp);
        l2 += w * vq
            .iter()
            .zip(&vp)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>();
    }
    let bound = deviation_bound(q, &p, dim)?;
    Ok((p, l2.sqrt(), bound))
}

/// Highest degree (current or requested) of the paper's formula (10)/(14) with its exact
/// matrices ([`BezierCurve::change_degree_paper`], `BezierSurface::change_degree_paper`).
/// The exact product H_n E H_(n')^-1 takes O(n^3) operations on big rationals of O(n)
/// digits: about 1 s at degree 100 on the project's machine, 2 s at 128, 45 s at 256; a typo
/// such as degree 10^7 would run for ever or exhaust memory.
pub const MAX_PAPER_DEGREE: usize = 100;

/// Refuses the paper's exact formula from degree `n` to `n_new` beyond
/// [`MAX_PAPER_DEGREE`] with [`Error::TooLarge`] (`what` names the operation).
pub fn check_paper_degree(n: usize, n_new: usize, what: &str) -> Result<()> {
    let largest = n.max(n_new);
    if largest > MAX_PAPER_DEGREE {
        return Err(Error::TooLarge {
            what: format!("{what} from degree {n} to {n_new}"),
            size: largest as u128,
            unit: "degree",
            limit: MAX_PAPER_DEGREE as u128,
        });
    }
    Ok(())
}

/// Formula (10) with the exact matrix H_n E H_(n')^-1 rounded once to f64, applied to
/// row-major points (accumulated in double-double); degrees up to [`MAX_PAPER_DEGREE`].
pub(crate) fn paper_change_flat(u: &[f64], dim: usize, n_new: usize) -> Result<Vec<f64>> {
    let n = u.len() / dim - 1;
    check_paper_degree(n, n_new, "the paper's formula (10)")?;
    let m = crate::exact::degree_change_matrix(n, n_new).to_f64();
    let mut out = vec![0.0; (n_new + 1) * dim];
    for j in 0..=n_new {
        for k in 0..dim {
            let mut acc = Dd::ZERO;
            for i in 0..=n {
                acc = acc.fma(Dd::from_f64(m[i * (n_new + 1) + j]), u[i * dim + k]);
            }
            out[j * dim + k] = acc.to_f64();
        }
    }
    Ok(out)
}

/// The paper's formula (10) evaluated naively in f64, as a direct program of it would:
/// S = U_n H_n, keep the first n'+1 columns (pad with zeros), then multiply by H_(n')^-1,
/// with every matrix entry formed in f64. Kept for comparison only: the power form is badly
/// conditioned and this loses all digits near degree 20-30.
pub fn paper_formula_f64(curve: &BezierCurve, n_new: usize) -> Vec<f64> {
    let n = curve.degree();
    let dim = curve.dim();
    let c = |a: usize, b: usize| crate::numeric::binomial_f64(a, b);
    let u = curve.points_flat();
    // S = U H, h_ij = (-1)^(j-i) C(n,j) C(j,i).
    let mut s = vec![0.0; (n_new + 1) * dim];
    for j in 0..=n.min(n_new) {
        for i in 0..=j {
            let sign = if (j - i) % 2 == 1 { -1.0 } else { 1.0 };
            let h = sign * c(n, j) * c(j, i);
            for k in 0..dim {
                s[j * dim + k] += u[i * dim + k] * h;
            }
        }
    }
    // U' = S H'^-1, (H'^-1)_ij = C(j,i) / C(n',i).
    let mut out = vec![0.0; (n_new + 1) * dim];
    for j in 0..=n_new {
        for i in 0..=j {
            let h = c(j, i) / c(n_new, i);
            for k in 0..dim {
                out[j * dim + k] += s[i * dim + k] * h;
            }
        }
    }
    out
}

impl BezierCurve {
    /// Elevates the degree to `n_new` >= n in one step with the closed form (8); the curve
    /// is unchanged and every new control point is within eps·max|u| of its exact value.
    /// Errors with [`Error::InvalidDegree`] when n' < n.
    pub fn elevate_degree(&self, n_new: usize) -> Result<BezierCurve> {
        let n = self.degree();
        if n_new < n {
            return Err(Error::InvalidDegree {
                degree: n,
                requested: n_new,
                reason: "elevation needs a degree >= the current one",
            });
        }
        BezierCurve::from_flat(
            self.dim(),
            elevate_flat(self.points_flat(), self.dim(), n_new)?,
        )
    }

    /// Formal degree, real degree and degree defect, by the residual test with a relative
    /// `tolerance` (default [`DEFAULT_TOLERANCE`]).
    pub fn degree_report(&self, tolerance: Option<f64>) -> Result<DegreeReport> {
        real_degree_flat(
            self.points_flat(),
            self.dim(),
            self.dim(),
            check_tolerance(tolerance)?,
        )
    }

    /// Relative residual of the reduction to degree `k`: the largest distance between a
    /// control point and its counterpart in the re-elevated least-squares reduction, divided
    /// by max|u_i|. Zero for k >= n. The residual test compares it with a tolerance.
    pub fn reduction_residual(&self, k: usize) -> Result<f64> {
        relative_residual(self.points_flat(), self.dim(), self.dim(), k)
    }

    /// Exact reduction to degree `n_new` <= n: the curve of degree n' whose elevation
    /// reproduces these control points within `tolerance · max|u_i|` (default
    /// [`DEFAULT_TOLERANCE`]). Coordinates below eps·max|u_i| (the accuracy floor) are
    /// returned as 0. Errors with [`Error::DegreeDefectTooSmall`], naming the real
    /// degree, when the defect does not allow it.
    pub fn reduce_degree(&self, n_new: usize, tolerance: Option<f64>) -> Result<BezierCurve> {
        let n = self.degree();
        let tol = check_tolerance(tolerance)?;
        if n_new > n {
            return Err(Error::InvalidDegree {
                degree: n,
                requested: n_new,
                reason: "reduction needs a degree <= the current one",
            });
        }
        if n_new == n {
            return Ok(self.clone());
        }
        let dim = self.dim();
        let (x, res) = reduce_least_squares(self.points_flat(), dim, dim, n_new)?;
        if res > tol {
            let report = real_degree_flat(self.points_flat(), dim, dim, tol)?;
            return Err(Error::DegreeDefectTooSmall {
                real_degree: report.real_degree,
                requested: n_new,
                defect: report.defect,
            });
        }
        BezierCurve::from_flat(dim, x)
    }

    /// The unified operation of formula (10), done stably: elevation when n' >= n, exact
    /// reduction (with the residual test) when n' < n.
    pub fn change_degree(&self, n_new: usize, tolerance: Option<f64>) -> Result<BezierCurve> {
        if n_new >= self.degree() {
            self.elevate_degree(n_new)
        } else {
            self.reduce_degree(n_new, tolerance)
        }
    }

    /// [`BezierCurve::change_degree`] reporting to `progress` ([`crate::progress`]): the
    /// units are the n' + 1 new control points, reported as the elevation computes them
    /// (about once per 2^18 multiply-adds: a curve of degree 2000 elevated to 4000 in 3-D
    /// reports some 90 times), or all at the end of a reduction. The same curve, bit for
    /// bit, as without it; [`Error::Cancelled`] when the callback asks to stop.
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// use geomkit::progress::Progress;
    /// use std::ops::ControlFlow;
    /// let c = BezierCurve::new((0..400).map(|i| vec![i as f64, (i % 7) as f64]).collect()).unwrap();
    /// let stop = |_: u64, _: u64| ControlFlow::Break(());
    /// let e = c.change_degree_with_progress(900, None, &Progress::new(&stop));
    /// assert_eq!(e.unwrap_err(), geomkit::Error::Cancelled);
    /// ```
    pub fn change_degree_with_progress(
        &self,
        n_new: usize,
        tolerance: Option<f64>,
        progress: &Progress,
    ) -> Result<BezierCurve> {
        progress.add_total((n_new + 1) as u64)?;
        let c = if n_new >= self.degree() {
            let pts = elevate_flat_reporting(self.points_flat(), self.dim(), n_new, progress)?;
            BezierCurve::from_flat(self.dim(), pts)?
        } else {
            self.reduce_degree(n_new, tolerance)?
        };
        progress.finish()?;
        Ok(c)
    }

    /// Best approximation of degree `n_new` < n (see [`ApproxOptions`]), with the L2 error
    /// and a guaranteed L∞ bound (at most 1% above a deviation actually attained, plus a
    /// rounding slack). Errors: n' >= n, continuity fixing more than n'+1 points.
    pub fn reduce_degree_approx(
        &self,
        n_new: usize,
        options: &ApproxOptions,
    ) -> Result<ApproxReduction> {
        let dim = self.dim();
        let (p, l2, linf) = reduce_approx_flat(self.points_flat(), dim, n_new, options)?;
        Ok(ApproxReduction {
            curve: BezierCurve::from_flat(dim, p)?,
            l2_error: l2,
            linf,
        })
    }

    /// The paper's formula (10) with the exact matrix H_n E H_(n')^-1 rounded once to f64.
    /// For n' >= n this is the closed-form elevation; for n' below the real degree it is the
    /// **truncation of the power form at t = 0**, not an approximation in any norm.
    ///
    /// Errors with [`Error::NonFinite`] when the huge entries of the truncation overflow,
    /// [`Error::TooLarge`] for degrees above [`MAX_PAPER_DEGREE`].
    pub fn change_degree_paper(&self, n_new: usize) -> Result<BezierCurve> {
        BezierCurve::from_flat(
            self.dim(),
            paper_change_flat(self.points_flat(), self.dim(), n_new)?,
        )
    }

    /// Distance bound between this curve and `other` over t ∈ [0, 1]. Errors when the
    /// dimensions differ.
    pub fn deviation_from(&self, other: &BezierCurve) -> Result<DeviationBound> {
        if self.dim() != other.dim() {
            return Err(Error::WrongDimension {
                operation: "deviation",
                expected: self.dim(),
                got: other.dim(),
            });
        }
        deviation_bound(self.points_flat(), other.points_flat(), self.dim())
    }
}
