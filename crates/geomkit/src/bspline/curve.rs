//! B-spline curves of any degree on any non-decreasing knot vector, with a fast path for
//! uniform knots (the paper's matrix form (1) of spec/bspline-interpolation.md).

use crate::geom::{check_point, BatchOptions, Curve};
use crate::points::check_eval_args;
use crate::points::{check_knots, flatten_points, validate_points};
use crate::{Error, Result};

/// A B-spline curve c(t) = Σ_j N_(j,p)(t) c_j over the domain \[knots\[p\], knots\[n_c\]\]
/// (n_c control points, n_c + p + 1 knots). Evaluation outside the domain extends the end
/// polynomial pieces.
///
/// ```
/// use geomkit::bspline::BsplineCurve;
/// use geomkit::geom::Curve;
/// // The uniform cubic B-spline of the paper: one segment over four control points.
/// let c = BsplineCurve::new(3, vec![-3., -2., -1., 0., 1., 2., 3., 4.],
///     vec![vec![0., 0.], vec![1., 2.], vec![3., 2.], vec![4., 0.]]).unwrap();
/// assert_eq!(c.domain(), (0.0, 1.0));
/// // r(0) = (p0 + 4 p1 + p2) / 6
/// let p = c.eval(0.0);
/// assert!((p[0] - 7.0 / 6.0).abs() < 1e-15 && (p[1] - 10.0 / 6.0).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineCurve {
    degree: usize,
    dim: usize,
    knots: Vec<f64>,
    control: Vec<f64>,
    /// Knot spacing when the knots are uniform (span located by one division).
    uniform_step: Option<f64>,
}

/// Index of the knot span [knots[s], knots[s+1]) holding t, clamped to the domain spans
/// p ..= n_c - 1; the first of them for t = NaN.
#[inline]
pub(crate) fn find_span(knots: &[f64], degree: usize, n_control: usize, t: f64) -> usize {
    let (lo, hi) = domain_spans(knots, degree, n_control);
    if t >= knots[hi] {
        return hi;
    }
    // Also NaN: it evaluates the first span, so NaN in gives NaN out (never an index out of
    // the domain's spans).
    if t.is_nan() || t <= knots[lo] {
        return lo;
    }
    // Binary search for the last knot <= t within [lo, hi].
    let slice = &knots[lo..=hi];
    lo + slice.partition_point(|&k| k <= t) - 1
}

/// The first and last non-empty knot spans of the domain (end knots repeated more than p+1
/// times leave empty spans at its ends, where the basis would divide by zero).
#[inline]
pub(crate) fn domain_spans(knots: &[f64], degree: usize, n_control: usize) -> (usize, usize) {
    let (mut lo, mut hi) = (degree, n_control - 1);
    while hi > lo && knots[hi] == knots[hi + 1] {
        hi -= 1;
    }
    while lo < hi && knots[lo] == knots[lo + 1] {
        lo += 1;
    }
    (lo, hi)
}

/// The p+1 nonzero basis functions N_(s-p..=s, p)(t) on span s (NURBS Book A2.2), written to
/// `out`; `left`/`right` are scratch of length p+1.
#[inline(always)]
pub(crate) fn basis_funs(knots: &[f64], span: usize, t: f64, degree: usize, out: &mut [f64]) {
    if degree == 3 {
        out[..4].copy_from_slice(&basis_funs_cubic(knots, span, t));
    } else {
        basis_funs_any(knots, span, t, degree, out);
    }
}

/// [`basis_funs`] for any degree (the book's loops), with scratch for degrees up to 7 or,
/// above, up to [`BsplineCurve::MAX_DEGREE`].
#[inline(always)]
fn basis_funs_any(knots: &[f64], span: usize, t: f64, degree: usize, out: &mut [f64]) {
    if degree < 8 {
        basis_funs_sized::<8>(knots, span, t, degree, out)
    } else {
        basis_funs_sized::<{ BsplineCurve::MAX_DEGREE + 1 }>(knots, span, t, degree, out)
    }
}

/// [`basis_funs_any`] with scratch arrays of N > degree numbers.
#[inline(always)]
fn basis_funs_sized<const N: usize>(
    knots: &[f64],
    span: usize,
    t: f64,
    degree: usize,
    out: &mut [f64],
) {
    let mut left = [0.0f64; N];
    let mut right = [0.0f64; N];
    debug_assert!(degree < N);
    out[0] = 1.0;
    for j in 1..=degree {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

/// [`basis_funs`] for degree 3, unrolled, with the six knot differences it divides by
/// inverted first ([`cubic_span_inverses`]; the batched kernels compute them lane by lane,
/// which vectorizes).
#[inline(always)]
pub(crate) fn basis_funs_cubic(knots: &[f64], s: usize, t: f64) -> [f64; 4] {
    basis_funs_cubic_with(knots, s, t, &cubic_span_inverses(knots, s))
}

/// The reciprocals of the knot differences of the cubic Cox–de Boor recursion on span s:
/// 1/(k[s+1]-k[s]), 1/(k[s+1]-k[s-1]), 1/(k[s+2]-k[s]), 1/(k[s+1]-k[s-2]), 1/(k[s+2]-k[s-1]),
/// 1/(k[s+3]-k[s]).
#[inline(always)]
fn cubic_span_inverses(knots: &[f64], s: usize) -> [f64; 6] {
    let k = &knots[s - 2..s + 4];
    [
        1.0 / (k[3] - k[2]),
        1.0 / (k[3] - k[1]),
        1.0 / (k[4] - k[2]),
        1.0 / (k[3] - k[0]),
        1.0 / (k[4] - k[1]),
        1.0 / (k[5] - k[2]),
    ]
}

/// The cubic basis functions on controls i, i+1, i+2 at the knot k_(i+3) (the only ones
/// non-zero there), in closed form from k_(i+1)..k_(i+5): one step of the Cox–de Boor
/// recursion from the quadratic values at a knot, every term positive (the middle value is
/// not 1 minus the others, which would cancel when it is small).
#[inline(always)]
pub(crate) fn cubic_basis_at_knot(k: &[f64], i: usize) -> [f64; 3] {
    let (k1, k2, k3, k4, k5) = (k[i + 1], k[i + 2], k[i + 3], k[i + 4], k[i + 5]);
    let (before, after) = (k3 - k2, k4 - k3);
    let p = 1.0 / ((k4 - k1) * (k4 - k2));
    let q = 1.0 / ((k5 - k2) * (k4 - k2));
    if !(p.is_normal() && q.is_normal()) {
        // Knot differences near 1e±154 and beyond: their products overflow or underflow,
        // their ratios (each <= 1) do not.
        let (a, b) = (after / (k4 - k2), before / (k4 - k2));
        return [
            a * (after / (k4 - k1)),
            a * ((k3 - k1) / (k4 - k1)) + b * ((k5 - k3) / (k5 - k2)),
            b * (before / (k5 - k2)),
        ];
    }
    [
        after * after * p,
        (k3 - k1) * after * p + (k5 - k3) * before * q,
        before * before * q,
    ]
}

/// The cubic basis on span s at t (NURBS Book A2.2 unrolled) given the span's
/// [`cubic_span_inverses`].
#[inline(always)]
fn basis_funs_cubic_with(knots: &[f64], s: usize, t: f64, inv: &[f64; 6]) -> [f64; 4] {
    let k = &knots[s - 2..s + 4];
    let (l1, l2, l3) = (t - k[2], t - k[1], t - k[0]);
    let (r1, r2, r3) = (k[3] - t, k[4] - t, k[5] - t);
    let temp = inv[0];
    let (a0, a1) = (r1 * temp, l1 * temp);
    let temp = a0 * inv[1];
    let (b0, saved) = (r1 * temp, l2 * temp);
    let temp = a1 * inv[2];
    let (b1, b2) = (saved + r2 * temp, l1 * temp);
    let temp = b0 * inv[3];
    let (c0, saved) = (r1 * temp, l3 * temp);
    let temp = b1 * inv[4];
    let (c1, saved) = (saved + r2 * temp, l2 * temp);
    let temp = b2 * inv[5];
    [c0, c1, saved + r3 * temp, l1 * temp]
}

/// Basis functions and their derivatives up to order `nd` on span s (NURBS Book A2.3):
/// `ders[k][r]` = d^k/dt^k N_(s-p+r, p)(t) for k <= min(nd, p), r <= p (degree <= 7); the
/// other entries are 0. No allocation.
pub(crate) fn basis_funs_derivs(
    knots: &[f64],
    span: usize,
    t: f64,
    degree: usize,
    nd: usize,
) -> [[f64; 8]; 8] {
    basis_funs_derivs_sized::<8>(knots, span, t, degree, nd)
}

/// [`basis_funs_derivs`] in N×N arrays, for degrees p < N.
pub(crate) fn basis_funs_derivs_sized<const N: usize>(
    knots: &[f64],
    span: usize,
    t: f64,
    degree: usize,
    nd: usize,
) -> [[f64; N]; N] {
    let p = degree;
    debug_assert!(p < N);
    let nd = nd.min(p);
    let mut ndu = [[0.0f64; N]; N];
    let mut left = [0.0f64; N];
    let mut right = [0.0f64; N];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0f64; N]; N];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let mut a = [[0.0f64; N]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if (r as isize - 1) <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for k in 1..=nd {
        for v in ders[k][..=p].iter_mut() {
            *v *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}

/// The uniform cubic B-spline basis at local u ∈ [0, 1] of a span: the rows of the paper's
/// matrix M of formula (1), [u³ u² u 1]·M = [(1-u)³, 3u³-6u²+4, -3u³+3u²+3u+1, u³] / 6.
#[inline]
pub(crate) fn uniform_cubic_basis(u: f64, out: &mut [f64]) {
    let v = 1.0 - u;
    let u2 = u * u;
    let u3 = u2 * u;
    // Multiplied by the rounded 1/6 rather than divided by 6: a division costs as much as
    // the rest of the basis.
    const SIXTH: f64 = 1.0 / 6.0;
    out[0] = v * v * v * SIXTH;
    out[1] = (3.0 * u3 - 6.0 * u2 + 4.0) * SIXTH;
    out[2] = (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) * SIXTH;
    out[3] = u3 * SIXTH;
}

/// The span holding x on uniform knots of spacing 1/`inv_h` starting at `k0`, clamped to the
/// domain spans p ..= n_c - 1 (NaN goes to the first). Uniform-knot code multiplies by the
/// rounded 1/h (one more rounding, no division on the critical path); a point within
/// rounding of a knot may land in the neighbouring span, whose polynomial agrees there.
#[inline]
pub(crate) fn uniform_span(k0: f64, inv_h: f64, p: usize, n_c: usize, x: f64) -> usize {
    // Clamped to [p, n_c - 1] >= 0 first, truncation is floor (and needs no libm call);
    // NaN converts to 0. Through i64: a conversion to unsigned costs twice as much on x86.
    let s = ((x - k0) * inv_h).clamp(p as f64, (n_c - 1) as f64);
    (s as i64 as usize).max(p)
}

/// The spacing h of uniform knots, or `None`. Uniform means within 4 ulps *of h* of
/// k_0 + k·h, so that the uniform basis (formula (1)) differs from the Cox–de Boor basis of
/// the actual knots only by rounding: integer knots qualify, knots that carry the rounding
/// of a computed spacing such as i/4095 do not (there a deviation of ulp(x) is ~x/h ulps of
/// the spacing, which the uniform basis would turn into errors of that size).
pub(crate) fn detect_uniform_step(knots: &[f64]) -> Option<f64> {
    let n = knots.len();
    let h = (knots[n - 1] - knots[0]) / (n - 1) as f64;
    if h.is_nan() || h <= 0.0 {
        return None;
    }
    let tol = 4.0 * f64::EPSILON * h;
    let uniform = knots
        .iter()
        .enumerate()
        .all(|(k, &x)| (x - (knots[0] + k as f64 * h)).abs() <= tol);
    uniform.then_some(h)
}

impl BsplineCurve {
    /// The knots and the control points (row-major), moved out.
    pub(crate) fn into_parts(self) -> (Vec<f64>, Vec<f64>) {
        (self.knots, self.control)
    }

    /// The highest degree a curve may have. Degree 0 (piecewise constant: SciPy's `k = 0`,
    /// and what [`BsplineCurve::derivative_nu`] gives for the degree-th derivative) is the
    /// lowest; [`BsplineCurve::antiderivative`] raises the degree by one per order, up to
    /// this cap.
    pub const MAX_DEGREE: usize = 15;

    /// A curve of `degree` (0..=[`BsplineCurve::MAX_DEGREE`]) from its knots
    /// (non-decreasing, finite, n_c + degree + 1 of them, with a non-empty domain) and
    /// control points (all of one dimension, finite).
    pub fn new(degree: usize, knots: Vec<f64>, control: Vec<Vec<f64>>) -> Result<Self> {
        let (dim, flat) = flatten_points("control points", &control)?;
        Self::from_flat(degree, knots, dim, flat)
    }

    /// As [`BsplineCurve::new`] with row-major control points of `dim` coordinates each.
    pub fn from_flat(
        degree: usize,
        knots: Vec<f64>,
        dim: usize,
        control: Vec<f64>,
    ) -> Result<Self> {
        if degree > Self::MAX_DEGREE {
            return Err(Error::InvalidOption {
                option: "degree",
                reason: "B-spline curve degree must be between 0 and 15",
            });
        }
        validate_points("control points", dim, &control)?;
        let n_c = control.len() / dim;
        if n_c < degree + 1 {
            return Err(Error::TooFewPoints {
                what: "control points",
                got: n_c,
                min: degree + 1,
            });
        }
        check_knots(&knots, degree, n_c)?;
        let uniform_step = detect_uniform_step(&knots);
        Ok(BsplineCurve {
            degree,
            dim,
            knots,
            control,
            uniform_step,
        })
    }

    /// [`BsplineCurve::from_flat`] for parts built by this crate that are valid by
    /// construction (finite control points, valid knots): skips the validation passes.
    pub(crate) fn from_trusted(
        degree: usize,
        knots: Vec<f64>,
        dim: usize,
        control: Vec<f64>,
    ) -> Self {
        debug_assert!(check_knots(&knots, degree, control.len() / dim).is_ok());
        let uniform_step = detect_uniform_step(&knots);
        BsplineCurve {
            degree,
            dim,
            knots,
            control,
            uniform_step,
        }
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Control points, row-major.
    pub fn control_flat(&self) -> &[f64] {
        &self.control
    }

    /// Control points, one vector each.
    pub fn control_points(&self) -> Vec<Vec<f64>> {
        self.control
            .chunks_exact(self.dim)
            .map(<[f64]>::to_vec)
            .collect()
    }

    /// Number of control points.
    pub fn n_control(&self) -> usize {
        self.control.len() / self.dim
    }

    /// The parameter domain \[knots\[p\], knots\[n_c\]\].
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.n_control()])
    }

    /// Whether the knots are uniform (spans located by one division).
    pub fn is_uniform(&self) -> bool {
        self.uniform_step.is_some()
    }

    /// The knot spacing when the knots are uniform.
    #[inline]
    pub(crate) fn uniform_step(&self) -> Option<f64> {
        self.uniform_step
    }

    /// The knot span holding t (clamped to the domain).
    #[inline]
    pub(crate) fn span(&self, t: f64) -> usize {
        let (p, n_c) = (self.degree, self.n_control());
        match self.uniform_step {
            Some(h) => uniform_span(self.knots[0], 1.0 / h, p, n_c, t),
            None => find_span(&self.knots, p, n_c, t),
        }
    }

    /// The derivative curve (degree p-1; piecewise constant for degree 1). Coefficients over
    /// a knot repeated p+1 times (where the curve jumps) are 0, so the derivative curve
    /// leaves out the jump; [`BsplineCurve::derivative_nu`] refuses such knots as SciPy
    /// does. Errors for degree 0 (the derivative is zero between jumps: use
    /// [`BsplineCurve::eval_derivative`]).
    pub fn derivative(&self) -> Result<BsplineCurve> {
        let p = self.degree;
        if p == 0 {
            return Err(Error::InvalidOption {
                option: "degree",
                reason: "the derivative of a degree-0 B-spline is not a B-spline",
            });
        }
        let d = self.dim;
        let n_c = self.n_control();
        let mut q = Vec::with_capacity((n_c - 1) * d);
        for j in 0..n_c - 1 {
            let den = self.knots[j + p + 1] - self.knots[j + 1];
            for k in 0..d {
                let diff = self.control[(j + 1) * d + k] - self.control[j * d + k];
                q.push(if den > 0.0 {
                    p as f64 * diff / den
                } else {
                    0.0
                });
            }
        }
        BsplineCurve::from_flat(p - 1, self.knots[1..self.knots.len() - 1].to_vec(), d, q)
    }

    /// The k-th derivative at t (k = 0 is the point), into `out` (length dim).
    pub fn eval_derivative(&self, t: f64, k: usize, out: &mut [f64]) {
        let p = self.degree;
        out.iter_mut().for_each(|o| *o = 0.0);
        if k > p {
            return;
        }
        let s = self.span(t);
        if p < 8 {
            self.combine_derivs(s, k, &basis_funs_derivs(&self.knots, s, t, p, k), out);
        } else {
            let ders = basis_funs_derivs_sized::<{ Self::MAX_DEGREE + 1 }>(&self.knots, s, t, p, k);
            self.combine_derivs(s, k, &ders, out);
        }
    }

    /// Adds Σ_r ders\[k\]\[r\] c_(s-p+r) to `out`.
    #[inline]
    fn combine_derivs<const N: usize>(
        &self,
        s: usize,
        k: usize,
        ders: &[[f64; N]; N],
        out: &mut [f64],
    ) {
        let p = self.degree;
        for r in 0..=p {
            let w = ders[k][r];
            let row = &self.control[(s - p + r) * self.dim..(s - p + r + 1) * self.dim];
            for (o, c) in out.iter_mut().zip(row) {
                *o += w * c;
            }
        }
    }
}

impl BsplineCurve {
    /// Evaluates the polynomial piece of span `s` at t (also outside the span).
    #[inline]
    pub(crate) fn eval_span_into(&self, s: usize, t: f64, out: &mut [f64]) {
        if self.degree < 8 {
            self.eval_span_sized::<8>(s, t, out)
        } else {
            self.eval_span_sized::<{ Self::MAX_DEGREE + 1 }>(s, t, out)
        }
    }

    /// [`BsplineCurve::eval_span_into`] with a basis array of N > p numbers.
    #[inline]
    fn eval_span_sized<const N: usize>(&self, s: usize, t: f64, out: &mut [f64]) {
        let p = self.degree;
        let mut basis = [0.0f64; N];
        match self.uniform_step {
            Some(h) if p == 3 => uniform_cubic_basis((t - self.knots[s]) * (1.0 / h), &mut basis),
            _ => basis_funs(&self.knots, s, t, p, &mut basis[..=p]),
        }
        out.iter_mut().for_each(|o| *o = 0.0);
        let d = self.dim;
        for (r, w) in basis[..=p].iter().enumerate() {
            let row = &self.control[(s - p + r) * d..(s - p + r + 1) * d];
            for (o, c) in out.iter_mut().zip(row) {
                *o += w * c;
            }
        }
        if out.iter().any(|o| !o.is_finite()) {
            let terms = basis[..=p]
                .iter()
                .enumerate()
                .map(|(r, &w)| (w, &self.control[(s - p + r) * d..(s - p + r + 1) * d]));
            resum_overflowed(terms, out);
        }
    }
}

/// Recomputes the coordinates of `out` = Σ w·P over `terms` that came out infinite or NaN
/// although every P is finite: control points near ±f64::MAX, where a sum of weights
/// rounded a little above 1 overflows. Sums at a quarter of the scale (no partial sum
/// overflows), scales back, and where every weight is non-negative (inside the domain) clamps
/// to the range of the points, which holds the true value (the convex hull property) — so a
/// curve through f64::MAX evaluates to f64::MAX, not to infinity. Negative weights
/// (extrapolation) keep an infinity the true value may well reach; a NaN parameter stays NaN.
#[cold]
pub(crate) fn resum_overflowed<'a>(
    terms: impl Iterator<Item = (f64, &'a [f64])> + Clone,
    out: &mut [f64],
) {
    for (j, o) in out.iter_mut().enumerate() {
        if o.is_finite() {
            continue;
        }
        let (mut sum, mut lo, mut hi, mut convex) = (0.0, f64::INFINITY, f64::NEG_INFINITY, true);
        for (w, p) in terms.clone() {
            sum += w * (0.25 * p[j]);
            lo = lo.min(p[j]);
            hi = hi.max(p[j]);
            convex &= w >= 0.0;
        }
        let value = 4.0 * sum;
        *o = if convex && !value.is_nan() {
            value.clamp(lo, hi)
        } else {
            value
        };
    }
}

/// [`Curve::eval_batch`] of B-spline curves of degree <= 3 goes through the piecewise
/// polynomial form ([`BsplineCurve::to_piecewise`]) from this many parameters on ...
///
/// Measured (release, 2 threads, 3-D interpolating cubics, random and sorted parameters;
/// the form built per batch): it pays from ~2^14 parameters on 1 000 spans (1.4-1.6x,
/// 2x at 2^16) but not below 4 parameters per span on large curves (1 000 000 spans,
/// 4·2^20 parameters: 0.55-0.68x, the build streams 16 numbers per span) and only from
/// ~10 per span on 100 000 spans (1.0-1.2x, 1.3-1.5x at 40 per span).
const PIECEWISE_MIN_POINTS: usize = 1 << 16;
/// ... when there are at least this many parameters per knot span.
const PIECEWISE_POINTS_PER_SPAN: usize = 16;

/// The B-spline curve of spec/bspline-interpolation.md (formula (1) on uniform knots,
/// Cox–de Boor otherwise) on its domain \[knots\[p\], knots\[n_c\]\].
impl Curve for BsplineCurve {
    fn dim(&self) -> usize {
        self.dim
    }

    /// \[knots\[p\], knots\[n_c\]\].
    fn domain(&self) -> (f64, f64) {
        BsplineCurve::domain(self)
    }

    #[inline]
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        self.eval_span_into(self.span(t), t, out);
    }

    /// Every order (NURBS Book A2.3 on the span of t, as
    /// [`BsplineCurve::eval_derivative`]); zero above the degree. At a knot, the span on
    /// its right.
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim, out)?;
        if order == 0 {
            self.eval_into(t, out);
        } else {
            self.eval_derivative(t, order, out);
        }
        Ok(())
    }

    /// The distinct knots strictly inside the domain.
    fn breaks(&self) -> Vec<f64> {
        let (a, b) = BsplineCurve::domain(self);
        let mut k: Vec<f64> = self
            .knots
            .iter()
            .copied()
            .filter(|&x| x > a && x < b)
            .collect();
        k.dedup();
        k
    }

    /// The batch kernels of [`BsplineCurve::eval_many_par`] (spans from the previous
    /// point's or a bucket table, sorted parameters detected), the values of
    /// [`Curve::eval_into`] bit for bit; for curves of degree <= 3 and batches of at least
    /// 2^16 parameters and 16 per knot span, the piecewise-polynomial form
    /// ([`BsplineCurve::to_piecewise`], built for the batch): within 8·eps·max|P| of them
    /// on interpolated curves, 64·eps·max|P| on arbitrary knots (see [`crate::bspline::PiecewiseCurve`]),
    /// unless [`BatchOptions::bit_exact`].
    fn eval_batch(&self, ts: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        check_eval_args("parameter", ts, ts.len(), self.dim, out)?;
        let parallel = options.parallel();
        let spans = self.n_control() - self.degree;
        if self.degree <= 3
            && !options.bit_exact
            && ts.len() >= PIECEWISE_MIN_POINTS
            && ts.len() >= PIECEWISE_POINTS_PER_SPAN * spans
        {
            if let Ok(pp) = super::PiecewiseCurve::build(self, parallel) {
                pp.eval_many_with(ts, out, parallel);
                return Ok(());
            }
        }
        if parallel {
            self.eval_many_par(ts, out)
        } else {
            self.eval_many_seq(ts, out)
        }
    }

    /// Forward differences ([`BsplineCurve::sample_uniform_fd`]) for degree <= 3, with both
    /// end points evaluated exactly; other degrees evaluate every point.
    fn sample_uniform(&self, count: usize) -> Vec<f64> {
        let count = count.max(2);
        let d = self.dim;
        let mut out = vec![0.0; count * d];
        if self.degree <= 3 && self.sample_uniform_fd(count, &mut out).is_ok() {
            let (a, b) = BsplineCurve::domain(self);
            self.eval_into(a, &mut out[..d]);
            self.eval_into(b, &mut out[(count - 1) * d..]);
            return out;
        }
        let (a, b) = BsplineCurve::domain(self);
        let ts = crate::geom::uniform_params(a, b, count);
        self.eval_many_par(&ts, &mut out)
            .expect("finite parameters, matching buffer");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivative_curve_matches_basis_derivatives() {
        let knots = vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 1.0, 1.0, 1.0, 1.0];
        let c = BsplineCurve::new(
            3,
            knots,
            vec![
                vec![0.0, 0.0],
                vec![1.0, 2.0],
                vec![2.0, -1.0],
                vec![3.0, 0.5],
                vec![4.0, 1.0],
                vec![5.0, 0.0],
            ],
        )
        .unwrap();
        let d = c.derivative().unwrap();
        let dd = d.derivative().unwrap();
        for t in [0.0, 0.1, 0.3, 0.42, 0.77, 1.0] {
            let mut a = [0.0; 2];
            c.eval_derivative(t, 1, &mut a);
            let b = d.eval(t);
            assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
            c.eval_derivative(t, 2, &mut a);
            let b = dd.eval(t);
            assert!((a[0] - b[0]).abs() < 1e-11 && (a[1] - b[1]).abs() < 1e-11);
        }
        assert!(!c.is_uniform());
    }

    #[test]
    fn unrolled_cubic_basis_is_the_books() {
        let knots = [0.0, 0.1, 0.35, 0.4, 1.0, 1.7, 1.75, 3.0, 3.1, 4.0];
        for s in 3..6 {
            for k in 0..=20 {
                let t = knots[s] + (knots[s + 1] - knots[s]) * k as f64 / 20.0;
                let mut any = [0.0; 4];
                basis_funs_any(&knots, s, t, 3, &mut any);
                // Multiplying by reciprocals instead of dividing: within a few ulps.
                for (a, b) in basis_funs_cubic(&knots, s, t).iter().zip(any) {
                    assert!((a - b).abs() <= 4.0 * f64::EPSILON, "span {s}, t {t}");
                }
            }
        }
    }

    #[test]
    fn uniform_basis_matches_cox_de_boor() {
        let knots: Vec<f64> = (0..12).map(|k| k as f64 * 0.5 - 1.0).collect();
        for t in [0.5, 0.61, 1.0, 1.37, 2.49] {
            let s = find_span(&knots, 3, 8, t);
            let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
            basis_funs(&knots, s, t, 3, &mut a);
            uniform_cubic_basis((t - knots[s]) / 0.5, &mut b);
            for k in 0..4 {
                assert!((a[k] - b[k]).abs() < 1e-15, "{t}: {a:?} {b:?}");
            }
        }
    }

    /// Degree 0 (piecewise constant) and degrees 8..=15 (the larger basis scratch) through
    /// every evaluation path: single points, batches (the piecewise form for degree 0 on
    /// large batches), uniform samples, derivatives.
    #[test]
    fn degree_zero_and_high_degrees_evaluate_everywhere() {
        use crate::geom::BatchOptions;
        let knots: Vec<f64> = (0..=6)
            .map(|i| f64::from(i) * 0.5 + 0.01 * f64::from(i * i))
            .collect();
        let c =
            BsplineCurve::from_flat(0, knots.clone(), 1, vec![1., -2., 3., 0.5, 4., 7.]).unwrap();
        assert_eq!(c.eval(knots[2]), vec![3.0]); // right-continuous at a knot
        assert_eq!(c.eval(knots[6]), vec![7.0]);
        let ts: Vec<f64> = (0..1 << 17)
            .map(|i| knots[6] * f64::from(i) / f64::from(1 << 17))
            .collect();
        let mut batch = vec![0.0; ts.len()];
        c.eval_batch(&ts, &mut batch, &BatchOptions::default())
            .unwrap();
        for (t, b) in ts.iter().zip(&batch).step_by(101) {
            assert_eq!(c.eval(*t)[0], *b, "t = {t}");
        }
        let samples = c.sample_uniform(50);
        assert_eq!((samples[0], samples[49]), (1.0, 7.0));
        let mut d = [1.0];
        c.derivative_into(1.3, 1, &mut d).unwrap();
        assert_eq!(d, [0.0]);
        assert!(c.derivative().is_err());

        // Degree 12 on uniform knots: the derivative curves agree with the basis derivatives.
        let knots: Vec<f64> = (0..40).map(f64::from).collect();
        let control: Vec<f64> = (0..27).map(|i| f64::from((i * 7) % 11) - 5.0).collect();
        let c = BsplineCurve::from_flat(12, knots, 1, control).unwrap();
        let mut dc = c.clone();
        for order in 1..=12 {
            dc = dc.derivative().unwrap();
            for t in [12.0, 12.5, 20.25, 26.9, 27.0] {
                let mut a = [0.0];
                c.derivative_into(t, order, &mut a).unwrap();
                let b = dc.eval(t)[0];
                assert!(
                    (a[0] - b).abs() <= 1e-9 * b.abs().max(1.0),
                    "order {order} at {t}: {a:?} {b}"
                );
            }
        }
        assert_eq!(dc.degree(), 0);
        let mut out = vec![0.0; 3];
        c.eval_batch(&[12.0, 20.0, 27.0], &mut out, &BatchOptions::default())
            .unwrap();
        assert_eq!(out[1], c.eval(20.0)[0]);
        assert!(BsplineCurve::from_flat(16, vec![0.0; 34], 1, vec![0.0; 17]).is_err());
    }

    #[test]
    fn rejects_bad_knots() {
        let pts = vec![vec![0.0]; 4];
        // Empty spans at the ends of the domain are skipped, never evaluated (NaN).
        let c =
            BsplineCurve::new(2, vec![-1., -1., -1., 2., 2., 2., 2.], vec![vec![1.0]; 4]).unwrap();
        assert_eq!(c.eval(2.0), vec![1.0]);
        let c =
            BsplineCurve::new(2, vec![-1., -1., -1., -1., 2., 3., 3.], vec![vec![1.0]; 4]).unwrap();
        assert_eq!(c.eval(-1.0), vec![1.0]);
        assert!(BsplineCurve::new(3, vec![0.0; 7], pts.clone()).is_err());
        assert!(BsplineCurve::new(3, vec![0., 1., 2., 3., 2., 5., 6., 7.], pts.clone()).is_err());
        assert!(BsplineCurve::new(3, vec![0., 0., 0., 0., 0., 0., 0., 0.], pts).is_err());
    }
}
