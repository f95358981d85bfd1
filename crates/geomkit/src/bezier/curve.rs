//! Bézier curves in any dimension: formula (1) of spec/bezier-order.md, evaluated by de
//! Casteljau; the hodograph; conversion to and from the power form (2) with H_n (4), (5).

use crate::exact::ExactBezierCurve;
use crate::geom::{check_point, BatchOptions, Curve};
use crate::numeric::{binomial_f64, Dd};
pub(crate) use crate::points::{check_eval_args, flatten_points, validate_points};
use crate::Result;

/// Highest degree evaluated by [`eval_horner`] (its binomials are exact integers in u128 and
/// its powers stay far from underflow); above it, de Casteljau.
const HORNER_MAX_DEGREE: usize = 60;

/// The binomials C(n, i), i = 0..=n, exact integers rounded once to f64.
pub(crate) fn binomial_row(n: usize) -> Vec<f64> {
    let mut row = Vec::with_capacity(n + 1);
    let mut bc: u128 = 1;
    row.push(1.0);
    for i in 1..=n {
        bc = bc * (n - i + 1) as u128 / i as u128;
        row.push(bc as f64);
    }
    row
}

/// Evaluation in O(n) by the Bernstein–Horner scheme (Volk–Schumaker):
/// p(t) = Σ C(n,i) t^i (1-t)^(n-i) u_i accumulated by powers of (1-t), with the binomials of
/// [`binomial_row`]. Every term is a product of non-negative factors, so the result is as
/// accurate as de Casteljau's (O(n·eps) relative to Σ b_i |u_i|) in O(n) instead of O(n²).
#[inline]
pub(crate) fn eval_horner(pts: &[f64], dim: usize, binom: &[f64], t: f64, out: &mut [f64]) {
    let n = pts.len() / dim - 1;
    let s = 1.0 - t;
    for (o, p) in out.iter_mut().zip(&pts[..dim]) {
        *o = p * if n == 0 { 1.0 } else { s };
    }
    if n == 0 {
        return;
    }
    let mut tn = 1.0;
    for i in 1..n {
        tn *= t;
        let w = tn * binom[i];
        for (o, p) in out.iter_mut().zip(&pts[i * dim..(i + 1) * dim]) {
            *o = (*o + w * p) * s;
        }
    }
    let w = tn * t;
    for (o, p) in out.iter_mut().zip(&pts[n * dim..]) {
        *o += w * p;
    }
}

/// Lanes of [`eval_horner_block`].
const LANES: usize = 8;

/// [`eval_horner`] at LANES parameters at once (points of dimension `D`), written so that the
/// compiler vectorizes across the parameters.
#[inline]
fn eval_horner_block<const D: usize>(
    pts: &[f64],
    binom: &[f64],
    ts: &[f64; LANES],
    out: &mut [f64],
) {
    let n = pts.len() / D - 1;
    let mut s = [0.0; LANES];
    let mut tn = [1.0; LANES];
    let mut acc = [[0.0; LANES]; D];
    for l in 0..LANES {
        s[l] = 1.0 - ts[l];
    }
    for c in 0..D {
        for l in 0..LANES {
            acc[c][l] = pts[c] * s[l];
        }
    }
    for i in 1..n {
        let b = binom[i];
        let p = &pts[i * D..(i + 1) * D];
        let mut w = [0.0; LANES];
        for l in 0..LANES {
            tn[l] *= ts[l];
            w[l] = tn[l] * b;
        }
        for c in 0..D {
            for l in 0..LANES {
                acc[c][l] = (acc[c][l] + w[l] * p[c]) * s[l];
            }
        }
    }
    let p = &pts[n * D..];
    for l in 0..LANES {
        let w = tn[l] * ts[l];
        for c in 0..D {
            out[l * D + c] = acc[c][l] + w * p[c];
        }
    }
}

/// Evaluates at every parameter of `ts` by the Horner scheme, blocks of LANES parameters at a
/// time for dimensions 1 to 4.
fn eval_horner_many(pts: &[f64], dim: usize, ts: &[f64], out: &mut [f64]) {
    let n = pts.len() / dim - 1;
    let binom = binomial_row(n);
    let blocks = if n >= 1 && (1..=4).contains(&dim) {
        ts.len() / LANES
    } else {
        0
    };
    for b in 0..blocks {
        let tb: &[f64; LANES] = ts[b * LANES..(b + 1) * LANES]
            .try_into()
            .expect("block of LANES");
        let ob = &mut out[b * LANES * dim..(b + 1) * LANES * dim];
        match dim {
            1 => eval_horner_block::<1>(pts, &binom, tb, ob),
            2 => eval_horner_block::<2>(pts, &binom, tb, ob),
            3 => eval_horner_block::<3>(pts, &binom, tb, ob),
            _ => eval_horner_block::<4>(pts, &binom, tb, ob),
        }
    }
    for k in blocks * LANES..ts.len() {
        eval_horner(pts, dim, &binom, ts[k], &mut out[k * dim..(k + 1) * dim]);
    }
}

/// De Casteljau evaluation of the Bézier curve with control points `pts` (row-major,
/// `dim` per point) at `t`, using `work` as scratch (same length as `pts`).
pub(crate) fn de_casteljau(pts: &[f64], dim: usize, t: f64, work: &mut [f64], out: &mut [f64]) {
    work.copy_from_slice(pts);
    let n = pts.len() / dim - 1;
    let s = 1.0 - t;
    for r in 1..=n {
        for i in 0..=(n - r) {
            for k in 0..dim {
                work[i * dim + k] = s * work[i * dim + k] + t * work[(i + 1) * dim + k];
            }
        }
    }
    out.copy_from_slice(&work[..dim]);
}

/// Horner's terms C(n,i) t^i u_i overflow for coordinates near f64::MAX although the
/// point, a convex combination, does not: points that came out non-finite at finite t are
/// evaluated again by de Casteljau (never for ordinary data: one pass over `out`).
fn horner_overflow_fallback(pts: &[f64], dim: usize, ts: &[f64], out: &mut [f64]) {
    let mut work = Vec::new();
    for (t, o) in ts.iter().zip(out.chunks_exact_mut(dim)) {
        if t.is_finite() && o.iter().any(|x| !x.is_finite()) {
            work.resize(pts.len(), 0.0);
            de_casteljau(pts, dim, *t, &mut work, o);
        }
    }
}

/// p(t) by de Casteljau (most accurate) up to degree 60, above by [`eval_bernstein_sum`]
/// (O(sqrt n) instead of O(n^2)).
pub(crate) fn eval_accurate(pts: &[f64], dim: usize, t: f64, out: &mut [f64]) {
    if pts.len() / dim <= HORNER_MAX_DEGREE + 1 {
        let mut work = pts.to_vec();
        de_casteljau(pts, dim, t, &mut work, out);
    } else {
        eval_bernstein_sum(pts, dim, t, out);
    }
}

/// p(t) for high degrees: Σ b_ni(t) u_i with the Bernstein values built outward from the
/// largest one, b_n,i+1 / b_ni = (n-i)/(i+1) · t/(1-t), and divided by their sum (1 in exact
/// arithmetic). The terms fall off like a Gaussian of width sqrt(n t (1-t)): those below
/// 2^-80 of the largest are dropped, so a point costs O(sqrt(n)) instead of de Casteljau's
/// O(n^2) (degree 10^6: about 10^4 operations instead of 10^12). Every term is positive, so
/// the error is O(eps·√n)·max|u|. t outside (0, 1) goes to de Casteljau.
fn eval_bernstein_sum(pts: &[f64], dim: usize, t: f64, out: &mut [f64]) {
    let n = pts.len() / dim - 1;
    if !(t > 0.0 && t < 1.0) {
        if t == 0.0 || t == 1.0 {
            let i = if t == 0.0 { 0 } else { n };
            out.copy_from_slice(&pts[i * dim..(i + 1) * dim]);
        } else {
            let mut work = pts.to_vec();
            de_casteljau(pts, dim, t, &mut work, out);
        }
        return;
    }
    bernstein_sum(pts, dim, t, 1.0, out);
    if out.iter().any(|x| !x.is_finite()) {
        // Coordinates near f64::MAX: the unnormalized sum overflowed; sum u/2^64 instead.
        bernstein_sum(pts, dim, t, 2f64.powi(-64), out);
        out.iter_mut().for_each(|o| *o *= 2f64.powi(64));
    }
}

/// [`eval_bernstein_sum`] for t in (0, 1), the points multiplied by `shrink`.
fn bernstein_sum(pts: &[f64], dim: usize, t: f64, shrink: f64, out: &mut [f64]) {
    let n = pts.len() / dim - 1;
    let ratio = t / (1.0 - t);
    let mode = ((n as f64 * t).round() as usize).min(n);
    let cutoff = 2f64.powi(-80);
    out.fill(0.0);
    let add = |i: usize, b: f64, out: &mut [f64]| {
        for (o, u) in out.iter_mut().zip(&pts[i * dim..(i + 1) * dim]) {
            *o += b * (u * shrink);
        }
    };
    let mut total = 1.0;
    add(mode, 1.0, out);
    let mut b = 1.0;
    for i in mode..n {
        b *= (n - i) as f64 / (i + 1) as f64 * ratio;
        if b < cutoff {
            break;
        }
        total += b;
        add(i + 1, b, out);
    }
    b = 1.0;
    for i in (1..=mode).rev() {
        b *= i as f64 / (n - i + 1) as f64 / ratio;
        if b < cutoff {
            break;
        }
        total += b;
        add(i - 1, b, out);
    }
    out.iter_mut().for_each(|o| *o /= total);
}

/// A Bézier curve p(t) = Σ b_ni(t) u_i, t ∈ [0, 1], with control points u_0..u_n in R^dim
/// (formula (1)). As a [`Curve`]: domain [0, 1], no breaks, derivatives of every order from
/// the hodographs, batches by the blocked Bernstein–Horner scheme.
///
/// ```
/// use geomkit::bezier::BezierCurve;
/// use geomkit::geom::Curve;
/// let c = BezierCurve::new(vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![2.0, 0.0]]).unwrap();
/// assert_eq!(c.eval(0.5), vec![1.0, 1.0]);
/// assert_eq!(c.derivative().eval(0.0), vec![2.0, 4.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BezierCurve {
    dim: usize,
    points: Vec<f64>,
}

impl BezierCurve {
    /// A curve from its control points. Errors: no points, points of different dimensions,
    /// dimension 0, a non-finite coordinate (naming the point).
    pub fn new(points: Vec<Vec<f64>>) -> Result<Self> {
        let (dim, points) = flatten_points("control points", &points)?;
        Ok(BezierCurve { dim, points })
    }

    /// A curve from row-major control points with `dim` coordinates each.
    pub fn from_flat(dim: usize, points: Vec<f64>) -> Result<Self> {
        validate_points("control points", dim, &points)?;
        Ok(BezierCurve { dim, points })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Formal degree n.
    pub fn degree(&self) -> usize {
        self.points.len() / self.dim - 1
    }

    /// Control point `i`.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.points[i * self.dim..(i + 1) * self.dim]
    }

    /// All control points, row-major.
    pub fn points_flat(&self) -> &[f64] {
        &self.points
    }

    /// Control points as one vector per point.
    pub fn points(&self) -> Vec<Vec<f64>> {
        self.points
            .chunks_exact(self.dim)
            .map(<[f64]>::to_vec)
            .collect()
    }

    /// Largest Euclidean norm of a control point (the scale that tolerances are relative to).
    pub fn scale(&self) -> f64 {
        crate::numeric::max_norm(&self.points, self.dim)
    }

    /// The derivative curve (hodograph): degree n-1 with control points n (u_(i+1) - u_i).
    /// A constant curve (n = 0) gives the zero curve of degree 0.
    pub fn derivative(&self) -> BezierCurve {
        let n = self.degree();
        if n == 0 {
            return BezierCurve {
                dim: self.dim,
                points: vec![0.0; self.dim],
            };
        }
        let d = self.dim;
        let points = (0..n)
            .flat_map(|i| (0..d).map(move |k| (i, k)))
            .map(|(i, k)| n as f64 * (self.points[(i + 1) * d + k] - self.points[i * d + k]))
            .collect();
        BezierCurve { dim: d, points }
    }

    /// Power coefficients S_n = U_n H_n (5), computed as s_j = C(n,j) Δ^j u_0, row-major.
    ///
    /// The power basis is badly conditioned: above degree ~20 these f64 coefficients lose
    /// most digits to cancellation. Use [`crate::exact::ExactBezierCurve::to_power`] for exact ones.
    pub fn to_power(&self) -> Vec<f64> {
        let n = self.degree();
        let d = self.dim;
        let mut diff = self.points.clone();
        let mut s = vec![0.0; self.points.len()];
        for j in 0..=n {
            let c = binomial_f64(n, j);
            for k in 0..d {
                s[j * d + k] = c * diff[k];
            }
            for i in 0..(n - j) {
                for k in 0..d {
                    diff[i * d + k] = diff[(i + 1) * d + k] - diff[i * d + k];
                }
            }
        }
        s
    }

    /// The curve with power coefficients `s` (row-major, `dim` each): U_n = S_n H_n^-1 with
    /// the closed-form inverse (H_n^-1)_ij = C(j,i)/C(n,i), accumulated in double-double.
    pub fn from_power(dim: usize, s: &[f64]) -> Result<Self> {
        validate_points("power coefficients", dim, s)?;
        let n = s.len() / dim - 1;
        let mut points = vec![0.0; s.len()];
        for j in 0..=n {
            for k in 0..dim {
                let mut acc = Dd::ZERO;
                for i in 0..=j {
                    // (H^-1)_ij = C(j,i) / C(n,i)
                    let w = Dd::from_f64(binomial_f64(j, i)).div(Dd::from_f64(binomial_f64(n, i)));
                    acc = acc.fma(w, s[i * dim + k]);
                }
                points[j * dim + k] = acc.to_f64();
            }
        }
        Self::from_flat(dim, points)
    }

    /// The exact curve: every f64 control point taken as the dyadic rational it is. Use it
    /// for the exact real degree ([`ExactBezierCurve::real_degree`]) and exact order change.
    pub fn to_exact(&self) -> ExactBezierCurve {
        ExactBezierCurve::from_f64(self.dim, &self.points).expect("control points are finite")
    }

    /// Splits the curve at `t` into two Bézier curves of the same degree (de Casteljau): the
    /// pieces over [0, t] and [t, 1], each reparametrized to [0, 1] (for t outside [0, 1],
    /// the extrapolated pieces). Errors: [`crate::Error::NonFinite`] for a `t` that is not
    /// finite or control points that overflow (t far outside [0, 1]).
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// let c = BezierCurve::new(vec![vec![0.0], vec![2.0], vec![4.0]]).unwrap();
    /// let (a, b) = c.split(0.25).unwrap();
    /// assert_eq!(a.points(), vec![vec![0.0], vec![0.5], vec![1.0]]);
    /// assert_eq!(b.points(), vec![vec![1.0], vec![2.5], vec![4.0]]);
    /// assert!(c.split(f64::NAN).is_err());
    /// ```
    pub fn split(&self, t: f64) -> Result<(BezierCurve, BezierCurve)> {
        if !t.is_finite() {
            return Err(crate::Error::NonFinite {
                what: "split parameter",
                index: 0,
            });
        }
        let (l, r) = split_flat(&self.points, self.dim, t);
        Ok((
            BezierCurve::from_flat(self.dim, l)?,
            BezierCurve::from_flat(self.dim, r)?,
        ))
    }
}

/// De Casteljau subdivision of row-major control points at `t`.
pub(crate) fn split_flat(pts: &[f64], dim: usize, t: f64) -> (Vec<f64>, Vec<f64>) {
    let n = pts.len() / dim - 1;
    let mut work = pts.to_vec();
    let mut left = vec![0.0; pts.len()];
    let mut right = vec![0.0; pts.len()];
    let s = 1.0 - t;
    left[..dim].copy_from_slice(&work[..dim]);
    right[n * dim..].copy_from_slice(&work[n * dim..]);
    for r in 1..=n {
        for i in 0..=(n - r) {
            for k in 0..dim {
                work[i * dim + k] = s * work[i * dim + k] + t * work[(i + 1) * dim + k];
            }
        }
        left[r * dim..(r + 1) * dim].copy_from_slice(&work[..dim]);
        right[(n - r) * dim..(n - r + 1) * dim]
            .copy_from_slice(&work[(n - r) * dim..(n - r + 1) * dim]);
    }
    (left, right)
}

impl BezierCurve {
    /// Evaluates at every parameter of `ts` on the calling thread by the blocked
    /// Bernstein–Horner scheme (the Bernstein sum from its largest term above degree 60);
    /// `ts` and `out` already checked.
    fn eval_many_unchecked(&self, ts: &[f64], out: &mut [f64]) {
        if self.degree() <= HORNER_MAX_DEGREE {
            eval_horner_many(&self.points, self.dim, ts, out);
            horner_overflow_fallback(&self.points, self.dim, ts, out);
        } else {
            for (t, o) in ts.iter().zip(out.chunks_exact_mut(self.dim)) {
                eval_bernstein_sum(&self.points, self.dim, *t, o);
            }
        }
    }
}

/// Formula (1) of spec/bezier-order.md; derivatives of order k from the k-th hodograph
/// n(n-1)..(n-k+1) Δ^k u_i (zero above the degree).
impl Curve for BezierCurve {
    fn dim(&self) -> usize {
        self.dim
    }

    /// [0, 1].
    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }

    fn eval_into(&self, t: f64, out: &mut [f64]) {
        debug_assert_eq!(out.len(), self.dim);
        if self.degree() <= HORNER_MAX_DEGREE {
            eval_horner(&self.points, self.dim, &binomial_row(self.degree()), t, out);
            horner_overflow_fallback(&self.points, self.dim, &[t], out);
        } else {
            eval_bernstein_sum(&self.points, self.dim, t, out);
        }
    }

    /// Every order: the k-th hodograph at t (the zero vector above the degree).
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim, out)?;
        if order > self.degree() {
            out.fill(0.0);
            return Ok(());
        }
        let mut h = std::borrow::Cow::Borrowed(self);
        for _ in 0..order {
            h = std::borrow::Cow::Owned(h.derivative());
        }
        h.eval_into(t, out);
        Ok(())
    }

    /// The blocked Horner scheme, in parallel chunks for large batches: the values of
    /// [`Curve::eval_into`], bit for bit.
    fn eval_batch(&self, ts: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        let d = self.dim;
        check_eval_args("parameter", ts, ts.len(), d, out)?;
        if options.parallel() && ts.len() > 4096 {
            crate::par::zip_chunks(true, out, 4096 * d, ts, 4096, |o, t| {
                self.eval_many_unchecked(t, o)
            });
        } else {
            self.eval_many_unchecked(ts, out);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;

    #[test]
    fn rejects_bad_input() {
        assert_eq!(
            BezierCurve::new(vec![]),
            Err(Error::Empty {
                what: "control points"
            })
        );
        assert_eq!(
            BezierCurve::new(vec![vec![0.0, 1.0], vec![f64::NAN, 0.0]]),
            Err(Error::NonFinite {
                what: "control point",
                index: 1
            })
        );
        assert!(matches!(
            BezierCurve::new(vec![vec![0.0, 1.0], vec![0.0]]),
            Err(Error::DimensionMismatch { index: 1, .. })
        ));
        let c = BezierCurve::new(vec![vec![0.0], vec![1.0]]).unwrap();
        let o = BatchOptions::default();
        assert!(c.eval_batch(&[0.5], &mut [0.0; 2], &o).is_err());
        assert!(c.eval_batch(&[f64::INFINITY], &mut [0.0], &o).is_err());
    }

    #[test]
    fn power_form_of_example2() {
        let c = BezierCurve::new(vec![
            vec![10.0, 0.0],
            vec![22.0, 6.0],
            vec![19.0, 12.0],
            vec![11.0, 15.0],
            vec![8.0, 12.0],
            vec![20.0, 0.0],
        ])
        .unwrap();
        let s = c.to_power();
        assert_eq!(
            s,
            vec![10.0, 0.0, 60.0, 30.0, -150.0, 0.0, 100.0, -30.0, 0.0, 0.0, 0.0, 0.0]
        );
        let back = BezierCurve::from_power(2, &s).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn horner_matches_de_casteljau() {
        for n in [0usize, 1, 2, 7, 30, 60] {
            let pts: Vec<f64> = (0..2 * (n + 1))
                .map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0)
                .collect();
            let mut work = pts.clone();
            for t in [0.0, 1e-9, 0.25, 0.5, 0.5000001, 0.9, 1.0] {
                let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
                eval_horner(&pts, 2, &binomial_row(n), t, &mut a);
                de_casteljau(&pts, 2, t, &mut work, &mut b);
                assert!(
                    (a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14,
                    "n={n} t={t}"
                );
            }
        }
    }

    /// The Bernstein sum from its largest term against de Casteljau (degrees 61..4000, which
    /// stays affordable here), inside, at and outside [0, 1].
    #[test]
    fn bernstein_sum_matches_de_casteljau() {
        for n in [61usize, 200, 1000, 4000] {
            let pts: Vec<f64> = (0..2 * (n + 1))
                .map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0)
                .collect();
            let mut work = pts.clone();
            for t in [
                0.0,
                1e-300,
                1e-9,
                0.25,
                0.5,
                0.5000001,
                0.9,
                1.0 - 1e-12,
                1.0,
                -1e-3,
            ] {
                let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
                eval_bernstein_sum(&pts, 2, t, &mut a);
                de_casteljau(&pts, 2, t, &mut work, &mut b);
                let tol = 1e-14 * (n as f64).sqrt() * 2.0;
                assert!(
                    (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol,
                    "n={n} t={t}: {a:?} {b:?}"
                );
            }
        }
    }

    #[test]
    fn blocked_horner_matches_single() {
        for dim in 1..=5 {
            for n in [1usize, 3, 20] {
                let pts: Vec<f64> = (0..dim * (n + 1))
                    .map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0)
                    .collect();
                let ts: Vec<f64> = (0..19).map(|k| k as f64 / 18.0).collect();
                let mut many = vec![0.0; 19 * dim];
                eval_horner_many(&pts, dim, &ts, &mut many);
                let binom = binomial_row(n);
                for (k, t) in ts.iter().enumerate() {
                    let mut one = vec![0.0; dim];
                    eval_horner(&pts, dim, &binom, *t, &mut one);
                    assert_eq!(
                        &many[k * dim..(k + 1) * dim],
                        &one[..],
                        "dim {dim} n {n} t {t}"
                    );
                }
            }
        }
    }

    #[test]
    fn split_halves_match_curve() {
        let c = BezierCurve::new(vec![
            vec![0.0, 0.0],
            vec![1.0, 3.0],
            vec![3.0, -1.0],
            vec![4.0, 0.5],
        ])
        .unwrap();
        let (l, r) = c.split(0.3).unwrap();
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            let a = l.eval(s);
            let b = c.eval(0.3 * s);
            assert!(crate::numeric::distance(&a, &b) < 1e-14);
            let a = r.eval(s);
            let b = c.eval(0.3 + 0.7 * s);
            assert!(crate::numeric::distance(&a, &b) < 1e-14);
        }
    }
}
