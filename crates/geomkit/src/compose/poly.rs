//! Polynomial patches in local coordinates: the form every Bézier patch and every cell of a
//! B-spline surface takes inside a composite surface (spec/composite-surfaces.md §3: "each
//! patch's own domain mapped onto its cell"), in the power basis of (s, t) ∈ [0, 1]².

use crate::bezier::BezierSurface;
use crate::bspline::BsplineSurface;
use crate::numeric::binomial_f64;
use crate::{Error, Result};

/// A tensor-product polynomial patch r(s, t) = Σ_a Σ_b c_ab s^a t^b of degrees (p, q) in R^dim,
/// with local coordinates (s, t) ∈ [0, 1]²; `c_ab` at `(a * (q + 1) + b) * dim`.
///
/// ```
/// use geomkit::bezier::BezierSurface;
/// use geomkit::compose::PolyPatch;
/// let b = BezierSurface::new(vec![
///     vec![vec![0.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]],
///     vec![vec![1.0, 0.0, 0.0], vec![1.0, 1.0, 1.0]],
/// ]).unwrap();
/// let p = PolyPatch::from_bezier(&b);
/// assert_eq!(p.eval(0.5, 0.5), b.eval(0.5, 0.5));
/// ```
#[derive(Debug, Clone)]
pub struct PolyPatch {
    degree: (usize, usize),
    dim: usize,
    coef: Vec<f64>,
    /// The Bézier net the patch was made from ([`PolyPatch::from_bezier`]), kept exact.
    bezier_net: Option<Vec<f64>>,
}

/// Patches are equal when their polynomials are (the net they came from aside).
impl PartialEq for PolyPatch {
    fn eq(&self, other: &Self) -> bool {
        self.degree == other.degree && self.dim == other.dim && self.coef == other.coef
    }
}

impl PolyPatch {
    /// A patch from its power-basis coefficients. Errors: dimension 0, wrong length,
    /// non-finite coefficients.
    pub fn new(degree: (usize, usize), dim: usize, coef: Vec<f64>) -> Result<Self> {
        crate::points::validate_points("patch coefficients", dim, &coef)?;
        let expected = (degree.0 + 1) * (degree.1 + 1) * dim;
        if coef.len() != expected {
            return Err(Error::BufferSize {
                expected,
                got: coef.len(),
            });
        }
        Ok(PolyPatch {
            degree,
            dim,
            coef,
            bezier_net: None,
        })
    }

    /// The zero patch.
    pub(crate) fn zero(degree: (usize, usize), dim: usize) -> Self {
        PolyPatch {
            degree,
            dim,
            coef: vec![0.0; (degree.0 + 1) * (degree.1 + 1) * dim],
            bezier_net: None,
        }
    }

    /// The Bézier patch in the power basis of its parameters (the same surface on [0, 1]²).
    pub fn from_bezier(b: &BezierSurface) -> Self {
        let (n, m) = b.degrees();
        let dim = b.dim();
        let cu = bernstein_to_power(n);
        let cv = bernstein_to_power(m);
        let mut coef = vec![0.0; (n + 1) * (m + 1) * dim];
        // First in v (rows), then in u.
        let mut tmp = vec![0.0; (n + 1) * (m + 1) * dim];
        for i in 0..=n {
            for b_ in 0..=m {
                for j in 0..=m {
                    let w = cv[b_ * (m + 1) + j];
                    if w != 0.0 {
                        for k in 0..dim {
                            tmp[(i * (m + 1) + b_) * dim + k] += w * b.point(i, j)[k];
                        }
                    }
                }
            }
        }
        for a in 0..=n {
            for i in 0..=n {
                let w = cu[a * (n + 1) + i];
                if w != 0.0 {
                    for x in 0..(m + 1) * dim {
                        coef[a * (m + 1) * dim + x] += w * tmp[i * (m + 1) * dim + x];
                    }
                }
            }
        }
        PolyPatch {
            degree: (n, m),
            dim,
            coef,
            bezier_net: Some(b.net_flat().to_vec()),
        }
    }

    /// The Bézier net the patch was made from by [`PolyPatch::from_bezier`], exactly as
    /// given (point (i, j) at `(i * (q + 1) + j) * dim`, i along s); `None` for patches made
    /// otherwise. The power-basis coefficients carry the rounding of the change of basis;
    /// the net does not.
    pub fn bezier_net(&self) -> Option<&[f64]> {
        self.bezier_net.as_deref()
    }

    /// Degrees (p, q) in s and t.
    pub fn degrees(&self) -> (usize, usize) {
        self.degree
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Coefficient c_ab (a slice of `dim` numbers).
    pub fn coefficient(&self, a: usize, b: usize) -> &[f64] {
        let k = (a * (self.degree.1 + 1) + b) * self.dim;
        &self.coef[k..k + self.dim]
    }

    fn coefficient_mut(&mut self, a: usize, b: usize) -> &mut [f64] {
        let k = (a * (self.degree.1 + 1) + b) * self.dim;
        &mut self.coef[k..k + self.dim]
    }

    /// Whether every coefficient is finite.
    pub(crate) fn is_finite(&self) -> bool {
        self.coef.iter().all(|c| c.is_finite())
    }

    /// Largest absolute coefficient (a scale for tolerances).
    pub fn scale(&self) -> f64 {
        self.coef.iter().fold(0.0, |m, c| m.max(c.abs()))
    }

    /// The largest Σ_ab |c_ab| over the coordinates: a bound of |r(s, t)| on the unit
    /// square and the scale of the rounding of its evaluation there (Horner's error is at
    /// most about (p + q + 2)·ε times it), which can be far above the values where the
    /// power-basis coefficients cancel.
    ///
    /// ```
    /// use geomkit::compose::PolyPatch;
    /// // r = (1 + 2s - 3t, -4st): coefficients c_00, c_01, c_10, c_11 per coordinate.
    /// let p = PolyPatch::new((1, 1), 2, vec![1.0, 0.0, -3.0, 0.0, 2.0, 0.0, 0.0, -4.0]).unwrap();
    /// assert_eq!(p.abs_sum(), 6.0);
    /// ```
    pub fn abs_sum(&self) -> f64 {
        (0..self.dim)
            .map(|k| {
                self.coef
                    .iter()
                    .skip(k)
                    .step_by(self.dim)
                    .map(|c| c.abs())
                    .sum()
            })
            .fold(0.0, f64::max)
    }

    /// r(s, t) into `out` (length dim), Horner in t inside Horner in s.
    #[inline]
    pub fn eval_into(&self, s: f64, t: f64, out: &mut [f64]) {
        match self.dim {
            1 => self.eval_fixed::<1>(s, t, out),
            2 => self.eval_fixed::<2>(s, t, out),
            3 => self.eval_fixed::<3>(s, t, out),
            _ => self.eval_any(s, t, out),
        }
    }

    /// [`Self::eval_into`] for points of dimension `D`: the coordinates side by side (the
    /// same operations in the same order, so the same bits, but independent chains).
    #[inline(always)]
    fn eval_fixed<const D: usize>(&self, s: f64, t: f64, out: &mut [f64]) {
        let q = self.degree.1;
        let mut acc = [0.0; D];
        for row in self.coef.chunks_exact((q + 1) * D).rev() {
            let mut r = [0.0; D];
            r.copy_from_slice(&row[q * D..(q + 1) * D]);
            for c in row[..q * D].chunks_exact(D).rev() {
                for k in 0..D {
                    r[k] = r[k] * t + c[k];
                }
            }
            for k in 0..D {
                acc[k] = acc[k] * s + r[k];
            }
        }
        out[..D].copy_from_slice(&acc);
    }

    fn eval_any(&self, s: f64, t: f64, out: &mut [f64]) {
        let (p, q) = self.degree;
        let d = self.dim;
        for k in 0..d {
            let mut acc = 0.0;
            for a in (0..=p).rev() {
                let row = &self.coef[a * (q + 1) * d..];
                let mut r = row[q * d + k];
                for b in (0..q).rev() {
                    r = r * t + row[b * d + k];
                }
                acc = acc * s + r;
            }
            out[k] = acc;
        }
    }

    /// The partial derivative ∂^(ks+kt) r / ∂s^ks ∂t^kt at (s, t) into `out` (length dim):
    /// Σ_(a>=ks, b>=kt) a!/(a-ks)! b!/(b-kt)! c_ab s^(a-ks) t^(b-kt), Horner in t inside
    /// Horner in s; zero above the degrees.
    pub(crate) fn partial_into(&self, s: f64, t: f64, (ks, kt): (usize, usize), out: &mut [f64]) {
        let (p, q) = self.degree;
        let d = self.dim;
        out[..d].fill(0.0);
        if ks > p || kt > q {
            return;
        }
        // a!/(a-k)! as a float (exact for the small degrees of patches).
        let falling = |a: usize, k: usize| ((a - k + 1)..=a).map(|x| x as f64).product::<f64>();
        for k in 0..d {
            let mut acc = 0.0;
            for a in (ks..=p).rev() {
                let row = &self.coef[a * (q + 1) * d..];
                let mut r = 0.0;
                for b in (kt..=q).rev() {
                    r = r * t + falling(b, kt) * row[b * d + k];
                }
                acc = acc * s + falling(a, ks) * r;
            }
            out[k] = acc;
        }
    }

    /// r(s, t).
    pub fn eval(&self, s: f64, t: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(s, t, &mut out);
        out
    }

    /// The patch with degrees raised to at least `degree` (zero coefficients added).
    pub(crate) fn padded(&self, degree: (usize, usize)) -> PolyPatch {
        let deg = (degree.0.max(self.degree.0), degree.1.max(self.degree.1));
        let mut out = PolyPatch::zero(deg, self.dim);
        for a in 0..=self.degree.0 {
            for b in 0..=self.degree.1 {
                out.coefficient_mut(a, b)
                    .copy_from_slice(self.coefficient(a, b));
            }
        }
        out
    }

    /// self += factor * other, where other's degrees are at most self's.
    pub(crate) fn add_scaled(&mut self, other: &PolyPatch, factor: f64) {
        for a in 0..=other.degree.0 {
            for b in 0..=other.degree.1 {
                let src = other.coefficient(a, b).to_vec();
                for (x, y) in self.coefficient_mut(a, b).iter_mut().zip(src) {
                    *x += factor * y;
                }
            }
        }
    }

    /// r(s0, t) as a patch of degree (0, q) (a curve in t); `s0` 0 or 1 in practice.
    pub(crate) fn at_s(&self, s0: f64) -> PolyPatch {
        let (p, q) = self.degree;
        let mut out = PolyPatch::zero((0, q), self.dim);
        for b in 0..=q {
            for k in 0..self.dim {
                let mut acc = 0.0;
                for a in (0..=p).rev() {
                    acc = acc * s0 + self.coefficient(a, b)[k];
                }
                out.coefficient_mut(0, b)[k] = acc;
            }
        }
        out
    }

    /// r(s, t0) as a patch of degree (p, 0) (a curve in s).
    pub(crate) fn at_t(&self, t0: f64) -> PolyPatch {
        let (p, q) = self.degree;
        let mut out = PolyPatch::zero((p, 0), self.dim);
        for a in 0..=p {
            for k in 0..self.dim {
                let mut acc = 0.0;
                for b in (0..=q).rev() {
                    acc = acc * t0 + self.coefficient(a, b)[k];
                }
                out.coefficient_mut(a, 0)[k] = acc;
            }
        }
        out
    }

    /// The patches of a B-spline surface, one per non-empty knot cell of its domain, with
    /// the cells' parameter bounds: `(u_cells, v_cells, patches)` where `patches[i * m + j]`
    /// lives on \[u_cells\[i\], u_cells\[i+1\]\] × \[v_cells\[j\], v_cells\[j+1\]\] (in local (s, t)).
    ///
    /// Errors: [`Error::Overflow`] naming the cell when its Bézier points (de Boor's
    /// triangle: combinations of the control points) overflow f64, for control points near
    /// the end of its range.
    pub fn from_bspline(s: &BsplineSurface) -> Result<(Vec<f64>, Vec<f64>, Vec<PolyPatch>)> {
        let (p, q) = s.degrees();
        let (ku, kv) = s.knots();
        let (nu, nv) = s.net_size();
        let dim = s.dim();
        let spans_u = spans(ku, p, nu);
        let spans_v = spans(kv, q, nv);
        let net = s.control_flat();
        let mut patches = Vec::with_capacity(spans_u.len() * spans_v.len());
        let row_len = nv * dim;
        for (iu, &su) in spans_u.iter().enumerate() {
            // Bézier rows of this u-span: each "point" is a whole row of the net.
            let rows_u = bezier_points_of_span(ku, p, su, &net[(su - p) * row_len..], row_len);
            for (iv, &sv) in spans_v.iter().enumerate() {
                let mut bez = Vec::with_capacity((p + 1) * (q + 1) * dim);
                for a in 0..=p {
                    let row = &rows_u[a * row_len..(a + 1) * row_len];
                    bez.extend(bezier_points_of_span(
                        kv,
                        q,
                        sv,
                        &row[(sv - q) * dim..],
                        dim,
                    ));
                }
                let b = BezierSurface::from_flat(p + 1, q + 1, dim, bez).map_err(|_| {
                    Error::Overflow {
                        what: format!("cell ({iu}, {iv}) of the B-spline surface"),
                        step: "its Bézier points (de Boor's triangle) overflow f64: control \
                               points near the end of its range"
                            .into(),
                    }
                })?;
                patches.push(PolyPatch::from_bezier(&b));
            }
        }
        let cells = |k: &[f64], sp: &[usize]| {
            let mut c: Vec<f64> = sp.iter().map(|&s| k[s]).collect();
            c.push(k[sp[sp.len() - 1] + 1]);
            c
        };
        Ok((cells(ku, &spans_u), cells(kv, &spans_v), patches))
    }
}

/// The indices s with knots[s] < knots[s+1] inside the domain [knots[p], knots[n]].
pub(super) fn spans(knots: &[f64], p: usize, n: usize) -> Vec<usize> {
    (p..n).filter(|&s| knots[s] < knots[s + 1]).collect()
}

/// The p+1 Bézier points of span s (knots[s] < knots[s+1]) of a degree-p B-spline whose
/// control points c_(s-p).. start at `ctrl` (points of `len` numbers): the blossoms
/// b_k = blossom(knots[s] (p-k times), knots[s+1] (k times)) by de Boor's triangle.
pub(super) fn bezier_points_of_span(
    knots: &[f64],
    p: usize,
    s: usize,
    ctrl: &[f64],
    len: usize,
) -> Vec<f64> {
    let mut out = Vec::with_capacity((p + 1) * len);
    let mut d = vec![0.0; (p + 1) * len];
    for k in 0..=p {
        d.copy_from_slice(&ctrl[..(p + 1) * len]);
        for r in 1..=p {
            let x = if r <= p - k { knots[s] } else { knots[s + 1] };
            for j in (r..=p).rev() {
                let i = s - p + j;
                let alpha = (x - knots[i]) / (knots[i + p + 1 - r] - knots[i]);
                for c in 0..len {
                    d[j * len + c] = (1.0 - alpha) * d[(j - 1) * len + c] + alpha * d[j * len + c];
                }
            }
        }
        out.extend_from_slice(&d[p * len..(p + 1) * len]);
    }
    out
}

/// The matrix M (row-major, (n+1)²) with power coefficient m_k = Σ_i M[k][i] b_i:
/// M[k][i] = C(n, k) C(k, i) (-1)^(k-i) for i <= k.
fn bernstein_to_power(n: usize) -> Vec<f64> {
    let mut m = vec![0.0; (n + 1) * (n + 1)];
    for k in 0..=n {
        for i in 0..=k {
            let sign = if (k - i) % 2 == 0 { 1.0 } else { -1.0 };
            m[k * (n + 1) + i] = sign * binomial_f64(n, k) * binomial_f64(k, i);
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fixed-dimension kernels do the generic loop's operations in its order: the same
    /// bits, for every degree and dimension 1 to 3.
    #[test]
    fn fixed_dimension_kernels_equal_the_generic_loop() {
        for dim in 1..=3 {
            for (p, q) in [(0, 0), (1, 3), (3, 3), (5, 2)] {
                let coef: Vec<f64> = (0..(p + 1) * (q + 1) * dim)
                    .map(|k| ((k * 37 % 11) as f64 - 5.0) / 3.0)
                    .collect();
                let patch = PolyPatch::new((p, q), dim, coef).unwrap();
                for (s, t) in [(0.0, 0.0), (0.3, 0.7), (1.0, 0.1), (0.9, 1.0)] {
                    let (mut a, mut b) = (vec![0.0; dim], vec![0.0; dim]);
                    patch.eval_into(s, t, &mut a);
                    patch.eval_any(s, t, &mut b);
                    assert_eq!(a, b, "dim {dim}, degrees ({p}, {q}) at ({s}, {t})");
                }
            }
        }
    }

    #[test]
    fn bezier_patch_in_power_basis_agrees() {
        let net: Vec<Vec<Vec<f64>>> = (0..4)
            .map(|i| {
                (0..3)
                    .map(|j| vec![i as f64, j as f64, ((i * 7 + j * 3) % 5) as f64])
                    .collect()
            })
            .collect();
        let b = BezierSurface::new(net).unwrap();
        let p = PolyPatch::from_bezier(&b);
        for (s, t) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.25), (1.0, 1.0)] {
            let (x, y) = (p.eval(s, t), b.eval(s, t));
            for k in 0..3 {
                assert!((x[k] - y[k]).abs() < 1e-13, "{s} {t}");
            }
        }
        let e = p.at_s(1.0);
        assert!((e.eval(0.0, 0.4)[2] - b.eval(1.0, 0.4)[2]).abs() < 1e-13);
        let e = p.at_t(0.0);
        assert!((e.eval(0.7, 0.0)[2] - b.eval(0.7, 0.0)[2]).abs() < 1e-13);
    }

    #[test]
    fn bspline_cells_reproduce_the_surface() {
        let (nu, nv, dim) = (6, 5, 3);
        let ctrl: Vec<f64> = (0..nu * nv * dim)
            .map(|k| ((k * 37 % 11) as f64) * 0.3 - 1.0)
            .collect();
        let ku = vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.5, 3.0, 3.0, 3.0, 3.0];
        let kv = vec![-1.0, -1.0, -1.0, 0.0, 2.0, 2.0, 2.0, 2.0];
        let s = BsplineSurface::from_flat((3, 2), ku, kv, nu, nv, dim, ctrl).unwrap();
        let (uc, vc, patches) = PolyPatch::from_bspline(&s).unwrap();
        assert_eq!(uc, vec![0.0, 0.5, 1.5, 3.0]);
        assert_eq!(vc, vec![-1.0, 0.0, 2.0]);
        for (i, w) in uc.windows(2).enumerate() {
            for (j, z) in vc.windows(2).enumerate() {
                // (The reference NaNs at v = 2 exactly: its last knot span there is empty.)
                for (a, b) in [(0.0, 0.0), (0.4, 0.9), (0.999, 0.999)] {
                    let u = w[0] + a * (w[1] - w[0]);
                    let v = z[0] + b * (z[1] - z[0]);
                    let want = s.eval(u, v);
                    let got = patches[i * 2 + j].eval(a, b);
                    for k in 0..dim {
                        assert!(
                            (want[k] - got[k]).abs() < 1e-12,
                            "cell {i},{j} at {a},{b}: {want:?} {got:?}"
                        );
                    }
                }
            }
        }
    }
}
