//! B-spline calculus with SciPy's semantics: derivatives of any order and the three
//! extrapolation modes of `scipy.interpolate.BSpline`, its derivative and antiderivative
//! curves, definite integrals and knot insertion on [`BsplineCurve`]; the partial
//! derivatives, grid evaluation and integral of `RectBivariateSpline` (FITPACK's `parder`,
//! `bispev`, `dblint`) on [`BsplineSurface`]. Not in the paper (spec/bspline-interpolation.md):
//! this is the evaluation side of issue 22, so that a Python package can be a drop-in for
//! SciPy's (SciPy 1.17, `scipy/interpolate/_bsplines.py` and `_fitpack_impl.py`).
//!
//! A curve of degree k with n coefficients c_j on knots t_0 <= ... <= t_(n+k) has the
//! *base interval* \[t_k, t_n\] (geomkit's [`BsplineCurve::domain`]). The formulas:
//!
//! - **Evaluation** ([`BsplineCurve::eval_nu_many`]): s^(ν)(x) = Σ_(j=l-k..=l) c_j B_(j,k)^(ν)(x)
//!   on the knot interval l with t_l <= x < t_(l+1), searched among l = k..=n-1: below
//!   t_(k+1) it is k, from t_(n-1) on it is n-1 (so x = t_n takes the last interval, and at
//!   an interior knot the interval on its right: derivatives that jump there take their
//!   right-hand value). The basis derivatives come from de Boor's recursion as SciPy's
//!   `_deBoor_D` computes them, operation for operation. ν > k gives 0 (ν = k+1 NaN where
//!   x is NaN or, without extrapolation, outside; higher orders 0 even there, as SciPy).
//! - **Derivative curve** ([`BsplineCurve::derivative_nu`]), once per order:
//!   c'_j = (c_(j+1) - c_j)·k / (t_(j+k+1) - t_(j+1)), j < n-1, on the knots t_1..t_(n+k-1),
//!   degree k-1 (SciPy's `splder`).
//! - **Antiderivative** ([`BsplineCurve::antiderivative`]), once per order:
//!   C_0 = 0, C_(j+1) = Σ_(i<=j) c_i (t_(i+k+1) - t_i) / (k+1), on the knots
//!   t_0, t_0..t_(n+k), t_(n+k) (one more at each end), degree k+1 (SciPy's `splantider`);
//!   the B-spline sum is 0 at t_0.
//! - **Integral** ([`BsplineCurve::integrate`]): F(b) - F(a) with F the antiderivative.
//! - **Knot insertion** ([`BsplineCurve::insert_knot`], Boehm's algorithm): for x in the
//!   interval l, c'_i = α_i c_i + (1 - α_i) c_(i-1) with α_i = (x - t_i) / (t_(i+k) - t_i)
//!   for l-k < i <= l, the other coefficients shifted.
//!
//! SciPy's `BSpline` stores `c` with k+1 trailing zeros after `derivative()` and k+2 copies
//! of the last coefficient after `antiderivative()` (FITPACK's padding to `len(t)`); geomkit
//! keeps the n coefficients that the curve uses (a Python layer pads them back).
//!
//! ```
//! use geomkit::bspline::{BsplineCurve, Extrapolate};
//! // SciPy: BSpline([0, 0, 0, 0, 1, 2.5, 3, 3, 3, 3], [1, 2, -1, 3, 0.5, 2], 3)
//! let knots = vec![0., 0., 0., 0., 1., 2.5, 3., 3., 3., 3.];
//! let c = BsplineCurve::from_flat(3, knots, 1, vec![1., 2., -1., 3., 0.5, 2.])?;
//! let mut d = [0.0; 3];
//! // The first derivative at -1, at the knot 1 (right-hand side) and beyond the end.
//! c.eval_nu_many(&[-1.0, 1.0, 4.0], 1, Extrapolate::Extend, &mut d)?;
//! assert!((d[1] + 0.56).abs() < 1e-15);
//! // Outside [t_k, t_n]: NaN with `Nan`, and one period away with `Periodic`.
//! c.eval_nu_many(&[-1.0, 1.0, 4.0], 0, Extrapolate::Nan, &mut d)?;
//! assert!(d[0].is_nan() && d[2].is_nan());
//! // The antiderivative is 0 at t_0; the integral over [0, 3] is F(3) - F(0) = 3.5.
//! let f = c.antiderivative(1)?;
//! assert_eq!((f.degree(), f.n_control()), (4, 7));
//! assert!((c.integrate(0.0, 3.0, Extrapolate::Extend)[0] - 3.5).abs() < 1e-15);
//! // The third derivative is piecewise constant (degree 0); a fourth one SciPy refuses.
//! assert_eq!(c.derivative_nu(3)?.degree(), 0);
//! assert!(c.derivative_nu(4).is_err());
//! # Ok::<(), geomkit::Error>(())
//! ```

use super::curve::BsplineCurve;
use super::surface::BsplineSurface;
use crate::par::*;
use crate::{Error, Result};

/// What a B-spline gives outside its base interval \[t_k, t_n\]: SciPy's `extrapolate`
/// argument of `BSpline.__call__` and `BSpline.integrate`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Extrapolate {
    /// `extrapolate=True`: the first and last polynomial pieces continued (what geomkit's
    /// other evaluations do too). Integrals take the continued pieces.
    #[default]
    Extend,
    /// `extrapolate=False`: NaN outside \[t_k, t_n\]. Integrals count only the part of
    /// \[a, b\] inside it (0 when there is none).
    Nan,
    /// `extrapolate='periodic'`: x is first mapped to t_k + (x - t_k) mod (t_n - t_k)
    /// (NumPy's `%`, the remainder with the sign of the divisor), then evaluated as with
    /// `Nan`. Integrals count whole periods and the rest.
    Periodic,
}

/// Parameters per parallel task of the batched evaluations.
const CHUNK: usize = 4096;

/// Scratch for de Boor's recursion: 2(k+1) numbers, as SciPy's.
const SCRATCH: usize = 2 * (BsplineCurve::MAX_DEGREE + 2);

/// SciPy's (t, c, k) without its checks: knots, coefficients (n rows of d numbers, n =
/// `t.len() - k - 1`), degree.
#[derive(Clone, Copy)]
struct Tck<'a> {
    t: &'a [f64],
    c: &'a [f64],
    k: usize,
    d: usize,
}

impl<'a> Tck<'a> {
    fn of(curve: &'a BsplineCurve) -> Self {
        Tck {
            t: curve.knots(),
            c: curve.control_flat(),
            k: curve.degree(),
            d: curve.dim(),
        }
    }

    /// The number of coefficients n.
    fn n(&self) -> usize {
        self.t.len() - self.k - 1
    }

    /// The base interval \[t_k, t_n\].
    fn base(&self) -> (f64, f64) {
        (self.t[self.k], self.t[self.n()])
    }

    /// SciPy's `_find_interval`: the l in k..=n-1 with t_l <= x < t_(l+1) (k below t_(k+1),
    /// n-1 from t_(n-1) on); `None` for NaN, and outside \[t_k, t_n\] unless `extend`. Tries
    /// `hint` first (the previous point's interval: sorted batches cost O(1) a point).
    #[inline]
    fn interval(&self, x: f64, extend: bool, hint: usize) -> Option<usize> {
        let (t, k, n) = (self.t, self.k, self.n());
        if x.is_nan() || (!extend && (x < t[k] || x > t[n])) {
            return None;
        }
        if (k..n).contains(&hint)
            && (hint == k || t[hint] <= x)
            && (hint + 1 == n || x < t[hint + 1])
        {
            return Some(hint);
        }
        Some(k + t[k + 1..n].partition_point(|&v| v <= x))
    }

    /// The value (ν = 0) or ν-th derivative at x with SciPy's interval and extrapolation,
    /// into `out` (d numbers); `hint` as for [`Tck::interval`], updated.
    /// `scratch`: at least 2(k + 1) numbers.
    #[inline(always)]
    fn eval_into(
        &self,
        x: f64,
        nu: usize,
        mode: Extrapolate,
        hint: &mut usize,
        scratch: &mut [f64],
        out: &mut [f64],
    ) {
        let k = self.k;
        if nu > k + 1 {
            // SciPy: zero for every x, NaN and outside the base interval included (order
            // k + 1 runs its recursion: 0 where x has an interval, NaN where it has none).
            out.fill(0.0);
            return;
        }
        let x = match mode {
            Extrapolate::Periodic => {
                let (a, b) = self.base();
                a + py_mod(x - a, b - a)
            }
            _ => x,
        };
        let Some(l) = self.interval(x, mode == Extrapolate::Extend, *hint) else {
            out.fill(f64::NAN);
            return;
        };
        *hint = l;
        if nu > k || (k > 0 && self.t[l] == self.t[l + 1]) {
            // Order k + 1 (the polynomial pieces' derivative of order k + 1 vanishes), or
            // an empty end interval (an end knot repeated more than k + 1 times): every
            // basis function there is 0 (SciPy's values too; its derivatives of order k
            // there read stale scratch memory). Degree 0 is the exception: SciPy's
            // recursion has no step there and gives c_l (the step function of
            // make_interp_spline(k=0), whose last knot is doubled, keeps y_(n-1) at
            // x_(n-1) and beyond).
            out.fill(0.0);
            return;
        }
        let (h, hh) = scratch.split_at_mut(k + 1);
        de_boor_d(self.t, x, k, l, nu, h, hh);
        let d = self.d;
        for (jp, o) in out.iter_mut().enumerate() {
            let mut acc = 0.0;
            for (a, w) in h.iter().enumerate() {
                acc += self.c[(l + a - k) * d + jp] * w;
            }
            *o = acc;
        }
    }

    /// [`Tck::eval_into`] over a batch (rows of d numbers in `out`). Degrees 1, 2, 3 and 5
    /// in dimensions 1 to 3 run a copy of the loop compiled for them (loops unrolled, the same
    /// operations in the same order: the same bits).
    fn eval_batch(&self, xs: &[f64], nu: usize, mode: Extrapolate, out: &mut [f64]) {
        match (self.k, self.d) {
            (1, 1) => self.eval_batch_k::<1, 1>(xs, nu, mode, out),
            (1, 2) => self.eval_batch_k::<1, 2>(xs, nu, mode, out),
            (1, 3) => self.eval_batch_k::<1, 3>(xs, nu, mode, out),
            (2, 1) => self.eval_batch_k::<2, 1>(xs, nu, mode, out),
            (2, 2) => self.eval_batch_k::<2, 2>(xs, nu, mode, out),
            (2, 3) => self.eval_batch_k::<2, 3>(xs, nu, mode, out),
            (3, 1) => self.eval_batch_k::<3, 1>(xs, nu, mode, out),
            (3, 2) => self.eval_batch_k::<3, 2>(xs, nu, mode, out),
            (3, 3) => self.eval_batch_k::<3, 3>(xs, nu, mode, out),
            (5, 1) => self.eval_batch_k::<5, 1>(xs, nu, mode, out),
            (5, 2) => self.eval_batch_k::<5, 2>(xs, nu, mode, out),
            (5, 3) => self.eval_batch_k::<5, 3>(xs, nu, mode, out),
            _ => {
                let mut hint = self.k;
                let mut scratch = [0.0; SCRATCH];
                for (&x, o) in xs.iter().zip(out.chunks_exact_mut(self.d)) {
                    self.eval_into(x, nu, mode, &mut hint, &mut scratch, o);
                }
            }
        }
    }

    /// [`Tck::eval_batch`] for degree `K` and dimension `D`.
    fn eval_batch_k<const K: usize, const D: usize>(
        &self,
        xs: &[f64],
        nu: usize,
        mode: Extrapolate,
        out: &mut [f64],
    ) {
        let tck = Tck {
            k: K,
            d: D,
            ..*self
        };
        let mut hint = K;
        let mut scratch = [0.0; SCRATCH];
        for (&x, o) in xs.iter().zip(out.chunks_exact_mut(D)) {
            tck.eval_into(x, nu, mode, &mut hint, &mut scratch, o);
        }
    }

    /// F(b) - F(a) per coordinate, F evaluated with `mode`.
    fn difference(&self, a: f64, b: f64, mode: Extrapolate) -> Vec<f64> {
        let d = self.d;
        let mut v = vec![0.0; 2 * d];
        self.eval_batch(&[a, b], 0, mode, &mut v);
        (0..d).map(|i| v[d + i] - v[i]).collect()
    }

    /// SciPy's `BSpline.integrate(a, b, extrapolate)` per coordinate.
    fn integrate(&self, a: f64, b: f64, mode: Extrapolate) -> Vec<f64> {
        let d = self.d;
        let (mut a, mut b, sign) = if b < a { (b, a, -1.0) } else { (a, b, 1.0) };
        let (ts, te) = self.base();
        if mode == Extrapolate::Nan {
            if a.is_nan() || b.is_nan() {
                return vec![f64::NAN; d];
            }
            a = a.max(ts);
            b = b.min(te);
            if a >= b {
                // No part inside: 0 (SciPy's FITPACK path for 1-D coefficients; its path for
                // n-D coefficients evaluates the antiderivative outside: NaN).
                return vec![0.0 * sign; d];
            }
        }
        let (ta, ca, ka) = antiderivative_raw(self.t, self.c, self.k, d, 1);
        let f = Tck {
            t: &ta,
            c: &ca,
            k: ka,
            d,
        };
        let mut integral = match mode {
            Extrapolate::Periodic => {
                let period = te - ts;
                let (periods, rest) = py_divmod(b - a, period);
                let mut integral = if periods > 0.0 {
                    let mut whole = f.difference(ts, te, Extrapolate::Nan);
                    whole.iter_mut().for_each(|v| *v *= periods);
                    whole
                } else {
                    vec![0.0; d]
                };
                let a = ts + py_mod(a - ts, period);
                let b = a + rest;
                let mut add = |p: f64, q: f64| {
                    for (s, v) in integral
                        .iter_mut()
                        .zip(f.difference(p, q, Extrapolate::Nan))
                    {
                        *s += v;
                    }
                };
                if b <= te {
                    add(a, b);
                } else {
                    add(a, te);
                    add(ts, ts + b - te);
                }
                integral
            }
            // Nan: a and b are inside now.
            _ => f.difference(a, b, Extrapolate::Extend),
        };
        integral.iter_mut().for_each(|v| *v *= sign);
        integral
    }
}

/// SciPy's `_deBoor_D`: the k+1 basis functions B_(l-k..=l, k) at x (ν = 0) or their ν-th
/// derivatives (ν <= k), into `h[..=k]`, on a non-empty interval l (t_l < t_(l+1));
/// `hh` is scratch of k numbers. First k-ν steps of the Cox–de Boor recursion, then ν
/// steps of the derivative recursion B' = j (B_i / (t_(i+j) - t_i) - B_(i+1) / ...).
#[inline(always)]
fn de_boor_d(t: &[f64], x: f64, k: usize, l: usize, nu: usize, h: &mut [f64], hh: &mut [f64]) {
    h[0] = 1.0;
    for j in 1..=k - nu {
        hh[..j].copy_from_slice(&h[..j]);
        h[0] = 0.0;
        for n in 1..=j {
            // On a non-empty interval, t_(l+n) >= t_(l+1) > t_l >= t_(l+n-j): no division
            // by zero (SciPy tests for it; here it cannot happen).
            let (xb, xa) = (t[l + n], t[l + n - j]);
            let w = hh[n - 1] / (xb - xa);
            h[n - 1] += w * (xb - x);
            h[n] = w * (x - xa);
        }
    }
    for j in k - nu + 1..=k {
        hh[..j].copy_from_slice(&h[..j]);
        h[0] = 0.0;
        for n in 1..=j {
            let (xb, xa) = (t[l + n], t[l + n - j]);
            let w = j as f64 * hh[n - 1] / (xb - xa);
            h[n - 1] -= w;
            h[n] = w;
        }
    }
}

/// The last step of [`BsplineSurface::eval_partial_grid`] for heights (dimension 1) of
/// degree `Q` in y: Σ_b by\[b\]·row\[ly - Q + b\] at every y, in the same order as the
/// general loop (the same bits), compiled for the degree.
fn combine_heights<const Q: usize>(
    row: &[f64],
    ybasis: &[Option<(usize, [f64; 8])>],
    out: &mut [f64],
) {
    for (yb, o) in ybasis.iter().zip(out.iter_mut()) {
        *o = match yb {
            Some((ly, by)) => {
                let c = &row[ly - Q..=*ly];
                let mut z = 0.0;
                for b in 0..=Q {
                    z += by[b] * c[b];
                }
                z
            }
            None => f64::NAN,
        };
    }
}

/// NumPy's (and Python's) float remainder `a % b`: C's fmod, moved into the sign of b.
#[inline]
fn py_mod(a: f64, b: f64) -> f64 {
    py_divmod(a, b).1
}

/// Python's `divmod(a, b)` on floats (CPython's `_float_div_mod`, NumPy's `npy_divmod`):
/// the floored quotient, snapped to the nearest integer, and the remainder with the sign
/// of b.
fn py_divmod(a: f64, b: f64) -> (f64, f64) {
    let mut m = a % b;
    let mut div = (a - m) / b;
    if m != 0.0 {
        if (b < 0.0) != (m < 0.0) {
            m += b;
            div -= 1.0;
        }
    } else {
        m = 0.0f64.copysign(b);
    }
    let q = if div != 0.0 {
        let f = div.floor();
        if div - f > 0.5 {
            f + 1.0
        } else {
            f
        }
    } else {
        0.0f64.copysign(a / b)
    };
    (q, m)
}

/// SciPy's `splantider((t, c, k), nu)` on n coefficients of d numbers: knots, the n + nu
/// coefficients the curve uses (without FITPACK's padding), degree k + nu.
fn antiderivative_raw(
    t: &[f64],
    c: &[f64],
    k: usize,
    d: usize,
    nu: usize,
) -> (Vec<f64>, Vec<f64>, usize) {
    let (mut t, mut c, mut k) = (t.to_vec(), c.to_vec(), k);
    for _ in 0..nu {
        let n = t.len() - k - 1;
        let mut next = vec![0.0; (n + 1) * d];
        let mut acc = vec![0.0; d];
        for j in 0..n {
            let dt = t[j + k + 1] - t[j];
            for (i, s) in acc.iter_mut().enumerate() {
                *s += c[j * d + i] * dt;
                next[(j + 1) * d + i] = *s / (k + 1) as f64;
            }
        }
        let (first, last) = (t[0], t[t.len() - 1]);
        t.insert(0, first);
        t.push(last);
        c = next;
        k += 1;
    }
    (t, c, k)
}

impl BsplineCurve {
    /// Values (`nu` = 0) or derivatives of order `nu` at the parameters `t`, into `out`
    /// (row-major, `t.len() * dim` numbers), as SciPy's `BSpline(t, c, k)(x, nu,
    /// extrapolate)`: the knot interval of each x is the l in k..=n-1 with
    /// t_l <= x < t_(l+1) (at an interior knot the interval on its right, at t_n the last
    /// one); `nu` above the degree gives 0; outside \[t_k, t_n\] see [`Extrapolate`].
    ///
    /// NaN and infinite parameters are not errors (as in SciPy): NaN gives NaN, ±∞ what the
    /// arithmetic gives (NaN or ±∞), except that `nu` >= k + 2 gives 0 everywhere, NaN and
    /// outside the base interval included (SciPy's shortcut; `nu` = k + 1 still gives NaN
    /// there).
    /// Where an end knot is repeated more than k+1 times the interval at that end is empty
    /// and the value there 0 (as SciPy's; geomkit's [`crate::geom::Curve::eval`] takes the
    /// nearest non-empty interval instead). Large batches run in parallel, in chunks of
    /// 4096 parameters; each takes O(k²) operations and the chunk's first parameter a binary
    /// search (sorted parameters then reuse the previous interval).
    ///
    /// Errors: `out` of the wrong length.
    ///
    /// ```
    /// use geomkit::bspline::{BsplineCurve, Extrapolate};
    /// // SciPy's `BSpline.basis_element([0, 1, 2])`: x on [0, 1], 2 - x on [1, 2].
    /// let b = BsplineCurve::from_flat(1, vec![-1., 0., 1., 2., 3.], 1, vec![0., 1., 0.])?;
    /// let mut out = [0.0; 3];
    /// b.eval_nu_many(&[0.5, 1.0, 2.5], 1, Extrapolate::Extend, &mut out)?;
    /// assert_eq!(out, [1.0, -1.0, -1.0]);
    /// b.eval_nu_many(&[-0.5, 1.5, 2.5], 0, Extrapolate::Periodic, &mut out)?;
    /// assert_eq!(out, [0.5, 0.5, 0.5]);
    /// # Ok::<(), geomkit::Error>(())
    /// ```
    pub fn eval_nu_many(
        &self,
        t: &[f64],
        nu: usize,
        extrapolate: Extrapolate,
        out: &mut [f64],
    ) -> Result<()> {
        let d = self.dim();
        if Some(out.len()) != t.len().checked_mul(d) {
            return Err(Error::BufferSize {
                expected: t.len().saturating_mul(d),
                got: out.len(),
            });
        }
        let tck = Tck::of(self);
        zip_chunks(t.len() > CHUNK, out, CHUNK * d, t, CHUNK, |o, xs| {
            tck.eval_batch(xs, nu, extrapolate, o)
        });
        Ok(())
    }

    /// The derivative curve of order `nu` (degree k - nu; `nu` = 0 gives the curve), with
    /// SciPy's knots and coefficients (`BSpline.derivative(nu)`, FITPACK's `splder`; see the
    /// notes of `bspline/calculus.rs` for the formula). Its values are the curve's derivatives of
    /// order `nu` ([`BsplineCurve::eval_nu_many`]) wherever those exist.
    ///
    /// Errors: `nu` above the degree ([`Error::DerivativeOrder`]); knots that coincide k+1-s
    /// times at step s (an interior knot where a lower derivative already jumps, so this
    /// one would hold a Dirac delta: [`Error::NotDifferentiable`], SciPy's "not
    /// differentiable n times"); coefficients beyond f64 ([`Error::ResultOverflow`]).
    pub fn derivative_nu(&self, nu: usize) -> Result<BsplineCurve> {
        let (d, k0) = (self.dim(), self.degree());
        if nu > k0 {
            return Err(Error::DerivativeOrder {
                order: nu,
                degree: k0,
                reason: "a derivative curve takes orders 0 to the degree (SciPy's \
                         BSpline.derivative); eval_nu_many gives 0 above it",
            });
        }
        let (mut t, mut c, mut k) = (self.knots().to_vec(), self.control_flat().to_vec(), k0);
        for step in 0..nu {
            let n = t.len() - k - 1;
            let mut next = Vec::with_capacity((n - 1) * d);
            for j in 0..n - 1 {
                let dt = t[j + k + 1] - t[j + 1];
                if dt == 0.0 {
                    let value = t[j + 1];
                    let all = self.knots();
                    let first = all.iter().position(|&v| v == value).unwrap_or(0);
                    return Err(Error::NotDifferentiable {
                        order: nu,
                        degree: k0,
                        index: first,
                        multiplicity: all.iter().filter(|&&v| v == value).count(),
                    });
                }
                for i in 0..d {
                    next.push((c[(j + 1) * d + i] - c[j * d + i]) * k as f64 / dt);
                }
            }
            if next.iter().any(|v| !v.is_finite()) {
                return Err(Error::ResultOverflow {
                    what: format!(
                        "the coefficients of the derivative curve of order {}",
                        step + 1
                    ),
                });
            }
            t = t[1..t.len() - 1].to_vec();
            c = next;
            k -= 1;
        }
        Ok(BsplineCurve::from_trusted(k, t, d, c))
    }

    /// The antiderivative curve of order `nu` (degree k + nu, one knot more at each end per
    /// order, zero at t_0 as a B-spline sum), with SciPy's knots and coefficients
    /// (`BSpline.antiderivative(nu)`, FITPACK's `splantider`; formula in the notes
    /// of `bspline/calculus.rs`). Its derivative of order `nu` is the curve on the base interval and,
    /// extended, beyond it; SciPy's antiderivative of a periodic spline drops the periodic
    /// extrapolation (evaluate it with [`Extrapolate::Nan`] to match).
    ///
    /// Errors: a degree above [`BsplineCurve::MAX_DEGREE`] ([`Error::InvalidDegree`]),
    /// coefficients beyond f64 ([`Error::ResultOverflow`]).
    pub fn antiderivative(&self, nu: usize) -> Result<BsplineCurve> {
        let k = self.degree();
        if k + nu > Self::MAX_DEGREE {
            return Err(Error::InvalidDegree {
                degree: k,
                requested: k.saturating_add(nu),
                reason: "B-spline curves hold degrees 0 to 15 (BsplineCurve::MAX_DEGREE)",
            });
        }
        let (t, c, k) = antiderivative_raw(self.knots(), self.control_flat(), k, self.dim(), nu);
        if c.iter().any(|v| !v.is_finite()) {
            return Err(Error::ResultOverflow {
                what: format!("the coefficients of the antiderivative of order {nu}"),
            });
        }
        Ok(BsplineCurve::from_trusted(k, t, self.dim(), c))
    }

    /// The integral of the curve over \[a, b\], per coordinate, as SciPy's
    /// `BSpline.integrate(a, b, extrapolate)`: F(b) - F(a) with F the antiderivative, the
    /// negative for b < a. [`Extrapolate::Extend`] integrates the continued end pieces;
    /// [`Extrapolate::Nan`] only the part of \[a, b\] inside the base interval \[t_k, t_n\]
    /// (0 if none: SciPy gives 0 for 1-D coefficients, and NaN for n-D ones, whose path
    /// evaluates the antiderivative outside); [`Extrapolate::Periodic`] ⌊(b-a)/P⌋ whole
    /// periods P = t_n - t_k plus the rest, from a mapped into the base interval (wrapping
    /// around its end). Exact up to rounding (closed form, no quadrature); works for every
    /// degree up to [`BsplineCurve::MAX_DEGREE`].
    ///
    /// Non-finite limits are not errors (as in SciPy): NaN gives NaN; ±∞ gives NaN or ±∞,
    /// except with `Nan`, where they are clipped to the base interval.
    ///
    /// ```
    /// use geomkit::bspline::{BsplineCurve, Extrapolate};
    /// // SciPy's BSpline.basis_element([0, 1, 2]).integrate(-1, 1, extrapolate=...)
    /// let b = BsplineCurve::from_flat(1, vec![-1., 0., 1., 2., 3.], 1, vec![0., 1., 0.])?;
    /// assert!(b.integrate(-1.0, 1.0, Extrapolate::Extend)[0].abs() < 1e-15);
    /// assert!((b.integrate(-1.0, 1.0, Extrapolate::Nan)[0] - 0.5).abs() < 1e-15);
    /// # Ok::<(), geomkit::Error>(())
    /// ```
    pub fn integrate(&self, a: f64, b: f64, extrapolate: Extrapolate) -> Vec<f64> {
        Tck::of(self).integrate(a, b, extrapolate)
    }

    /// The curve with the knot x inserted `m` times (Boehm's algorithm; formula in the
    /// notes of `bspline/calculus.rs`), as SciPy's `BSpline.insert_knot(x, m)`: the same curve on more
    /// knots, n + m coefficients. At x = t_n the knot goes before the end knots (SciPy's
    /// choice; the end interval of the result is then empty, where
    /// [`BsplineCurve::eval_nu_many`] gives 0 at t_n, as SciPy does).
    ///
    /// Errors ([`Error::KnotInsertion`]): x outside \[t_k, t_n\] or NaN; a knot that would
    /// then be repeated more than k+2 times where the curve would need a division by zero
    /// (SciPy returns NaN coefficients there). `m` = 0: [`Error::InvalidOption`].
    pub fn insert_knot(&self, x: f64, m: usize) -> Result<BsplineCurve> {
        self.insert_knot_with(x, m, false)
    }

    /// [`BsplineCurve::insert_knot`] of a periodic spline (SciPy's `insert_knot` when
    /// `extrapolate='periodic'`, FITPACK's `insert` with `iopt = 1`): the first and last k
    /// knots and coefficients are then kept periodic, t_(i+n-k) = t_i + P and
    /// c_(i+n-k) = c_i for the period P = t_n - t_k, as in the splines of
    /// `make_interp_spline(..., bc_type='periodic')`.
    ///
    /// Errors: those of [`BsplineCurve::insert_knot`]; fewer than k interior knots on both
    /// sides of x (FITPACK: "not enough internal knots"); knots that are not periodic to
    /// begin with, when the result's knots would not be non-decreasing.
    pub fn insert_knot_periodic(&self, x: f64, m: usize) -> Result<BsplineCurve> {
        self.insert_knot_with(x, m, true)
    }

    fn insert_knot_with(&self, x: f64, m: usize, periodic: bool) -> Result<BsplineCurve> {
        let tck = Tck::of(self);
        let (a, b) = tck.base();
        if x < a || x > b {
            return Err(Error::KnotInsertion {
                x,
                reason: "outside the base interval [t_k, t_n]",
            });
        }
        if m == 0 {
            return Err(Error::InvalidOption {
                option: "knot multiplicity m",
                reason: "must be positive",
            });
        }
        let (mut t, mut c) = (self.knots().to_vec(), self.control_flat().to_vec());
        for _ in 0..m {
            (t, c) = insert_once(x, &t, &c, tck.k, tck.d, periodic)?;
        }
        if c.iter().any(|v| !v.is_finite()) {
            return Err(Error::KnotInsertion {
                x,
                reason: "the knot would be repeated more than degree + 2 times: its \
                         coefficients divide by zero",
            });
        }
        if periodic {
            return BsplineCurve::from_flat(tck.k, t, tck.d, c).map_err(|_| Error::KnotInsertion {
                x,
                reason: "the knots are not periodic: the first and last k knots must be \
                         the ones next to the other end shifted by the period",
            });
        }
        Ok(BsplineCurve::from_trusted(tck.k, t, tck.d, c))
    }
}

/// One insertion of x (SciPy's `_insert`, a port of FITPACK's `insert`).
fn insert_once(
    x: f64,
    t: &[f64],
    c: &[f64],
    k: usize,
    d: usize,
    periodic: bool,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let tck = Tck { t, c, k, d };
    let Some(mut l) = tck.interval(x, false, k) else {
        return Err(Error::KnotInsertion {
            x,
            reason: "not a number, or outside the base interval [t_k, t_n]",
        });
    };
    // A knot of multiplicity above k + 1 at the end (SciPy's "super edge case").
    if t[l] == t[l + k + 1] {
        l = l.checked_sub(1).ok_or(Error::KnotInsertion {
            x,
            reason: "the knots at the start coincide more than degree + 1 times",
        })?;
    }
    if periodic && l < 2 * k && l + 1 + 2 * k >= t.len() {
        return Err(Error::KnotInsertion {
            x,
            reason: "a periodic spline needs at least k interior knots on one side of x \
                     (FITPACK: not enough internal knots)",
        });
    }
    let n = c.len() / d;
    let mut tt = Vec::with_capacity(t.len() + 1);
    tt.extend_from_slice(&t[..=l]);
    tt.push(x);
    tt.extend_from_slice(&t[l + 1..]);
    let mut cc = vec![0.0; (n + 1) * d];
    cc[(l + 1) * d..].copy_from_slice(&c[l * d..]);
    // i from l down to l - k + 1; SciPy reads c[i - 1] with Python's wrap-around at i = 0
    // (only when l = k - 1 above).
    for i in (l + 1).saturating_sub(k)..=l {
        let fac = (x - tt[i]) / (tt[i + k + 1] - tt[i]);
        let prev = if i == 0 { n - 1 } else { i - 1 };
        for j in 0..d {
            cc[i * d + j] = fac * c[i * d + j] + (1.0 - fac) * c[prev * d + j];
        }
    }
    // Python's cc[:l-k+1] = c[:l-k+1] (nothing when l - k + 1 <= 0).
    let keep = (l + 1).saturating_sub(k);
    cc[..keep * d].copy_from_slice(&c[..keep * d]);
    if periodic {
        let nt = tt.len();
        let nk = nt - k - 1;
        let n2k = nt - 2 * k - 1;
        let period = tt[nk] - tt[k];
        // NumPy evaluates each right-hand side before assigning (copy_within: memmove).
        if l + k >= nk {
            let left: Vec<f64> = tt[nk - k..nk].iter().map(|v| v - period).collect();
            tt[..k].copy_from_slice(&left);
            cc.copy_within(n2k * d..(n2k + k) * d, 0);
        }
        if l < 2 * k {
            let right: Vec<f64> = tt[k + 1..2 * k + 1].iter().map(|v| v + period).collect();
            tt[nt - k..].copy_from_slice(&right);
            cc.copy_within(0..k * d, n2k * d);
        }
    }
    Ok((tt, cc))
}

impl BsplineSurface {
    /// Partial derivatives ∂^(dx+dy) S / ∂x^dx ∂y^dy (`dx` = `dy` = 0: values) at the points
    /// (x\[i\], y\[i\]), into `out` (row-major, `x.len() * dim` numbers), as SciPy's
    /// `RectBivariateSpline.ev(x, y, dx, dy)` (FITPACK's `bispeu` and `pardeu`).
    ///
    /// FITPACK's semantics: a coordinate outside the domain is clamped to it first (the
    /// surface continues as its boundary values, and derivatives as those at the boundary,
    /// both constant across); NaN gives NaN; at an interior knot the interval on its right
    /// is taken, at the domain's upper end the last one. Derivative orders must be below
    /// the degree in each direction when either is nonzero (FITPACK's rule:
    /// 0 <= dx < kx, 0 <= dy < ky; [`BsplineSurface::eval_derivative`] gives every order).
    /// In parallel over chunks of 4096 points, O(kx² + ky² + kx·ky) per point.
    ///
    /// Errors: `x` and `y` of different lengths, `out` of the wrong length, derivative
    /// orders FITPACK refuses ([`Error::DerivativeOrder`]).
    pub fn eval_partial_many(
        &self,
        x: &[f64],
        y: &[f64],
        dx: usize,
        dy: usize,
        out: &mut [f64],
    ) -> Result<()> {
        if x.len() != y.len() {
            return Err(Error::InvalidParameter {
                index: x.len().min(y.len()),
                reason: "points (x[i], y[i]) need as many y as x coordinates",
            });
        }
        self.check_partial(x.len(), 1, dx, dy, out)?;
        let d = self.dim();
        let (ax, ay) = self.axes();
        out.par_chunks_mut(CHUNK * d)
            .zip(x.par_chunks(CHUNK))
            .zip(y.par_chunks(CHUNK))
            .for_each(|((o, xs), ys)| {
                let (mut hx, mut hy) = (ax.k, ay.k);
                for ((&u, &v), o) in xs.iter().zip(ys).zip(o.chunks_exact_mut(d)) {
                    match (ax.basis(u, dx, &mut hx), ay.basis(v, dy, &mut hy)) {
                        (Some((lx, bx)), Some((ly, by))) => self.combine(lx, &bx, ly, &by, o),
                        _ => o.fill(f64::NAN),
                    }
                }
            });
        Ok(())
    }

    /// Partial derivatives (as [`BsplineSurface::eval_partial_many`]) on the grid x × y,
    /// into `out` (point (i, j) at `(i * y.len() + j) * dim`), as SciPy's
    /// `RectBivariateSpline(x, y, dx=dx, dy=dy, grid=True)` (FITPACK's `bispev`, `parder`):
    /// x and y non-decreasing (equal neighbours allowed, as SciPy's check `diff >= 0`
    /// allows them), coordinates outside the domain clamped to it. Each grid row contracts
    /// the net once; rows run in parallel.
    ///
    /// Errors: x or y decreasing somewhere or NaN among two or more coordinates (SciPy's
    /// "x must be strictly increasing when `grid` is True"), `out` of the wrong length,
    /// derivative orders FITPACK refuses ([`Error::DerivativeOrder`]).
    ///
    /// ```
    /// use geomkit::bspline::BsplineSurface;
    /// // z = x·y as a bilinear surface on [0, 1]²: control values at the corners.
    /// let s = BsplineSurface::from_flat((1, 1), vec![0., 0., 1., 1.], vec![0., 0., 1., 1.],
    ///     2, 2, 1, vec![0., 0., 0., 1.])?;
    /// let mut z = [0.0; 4];
    /// s.eval_partial_grid(&[0.5, 2.0], &[0.5, 1.0], 0, 0, &mut z)?;
    /// // x = 2 is clamped to 1: z(1, y) = y.
    /// assert_eq!(z, [0.25, 0.5, 0.5, 1.0]);
    /// assert_eq!(s.integral(0.0, 1.0, 0.0, 2.0), vec![0.25]);
    /// # Ok::<(), geomkit::Error>(())
    /// ```
    pub fn eval_partial_grid(
        &self,
        x: &[f64],
        y: &[f64],
        dx: usize,
        dy: usize,
        out: &mut [f64],
    ) -> Result<()> {
        for (axis, v) in [("x", x), ("y", y)] {
            // NaN among two or more coordinates fails too (SciPy: np.diff(x) >= 0).
            let ordered = |w: &[f64]| w[1].partial_cmp(&w[0]).is_some_and(|o| o.is_ge());
            if let Some(i) = v.windows(2).position(|w| !ordered(w)) {
                return Err(Error::InvalidParameter {
                    index: i + 1,
                    reason: if axis == "x" {
                        "x must be non-decreasing (and not NaN) for a grid evaluation"
                    } else {
                        "y must be non-decreasing (and not NaN) for a grid evaluation"
                    },
                });
            }
        }
        self.check_partial(x.len(), y.len(), dx, dy, out)?;
        let d = self.dim();
        if y.is_empty() {
            return Ok(());
        }
        let (ax, ay) = self.axes();
        let mut hint = ay.k;
        let ybasis: Vec<Option<(usize, [f64; 8])>> =
            y.iter().map(|&v| ay.basis(v, dy, &mut hint)).collect();
        let (p, q) = self.degrees();
        let n_v = self.net_size().1;
        let row_len = n_v * d;
        let control = self.control_flat();
        out.par_chunks_mut(y.len() * d)
            .zip(x.par_iter())
            .for_each_init(
                || vec![0.0; row_len],
                |row, (chunk, &u)| {
                    let mut hx = ax.k;
                    let Some((lx, bx)) = ax.basis(u, dx, &mut hx) else {
                        chunk.fill(f64::NAN);
                        return;
                    };
                    row.fill(0.0);
                    for a in 0..=p {
                        let src = &control[(lx - p + a) * row_len..(lx - p + a + 1) * row_len];
                        for (r, s) in row.iter_mut().zip(src) {
                            *r += bx[a] * s;
                        }
                    }
                    match (q, d) {
                        (1, 1) => combine_heights::<1>(row, &ybasis, chunk),
                        (2, 1) => combine_heights::<2>(row, &ybasis, chunk),
                        (3, 1) => combine_heights::<3>(row, &ybasis, chunk),
                        (5, 1) => combine_heights::<5>(row, &ybasis, chunk),
                        _ => {
                            for (yb, o) in ybasis.iter().zip(chunk.chunks_exact_mut(d)) {
                                let Some((ly, by)) = yb else {
                                    o.fill(f64::NAN);
                                    continue;
                                };
                                o.fill(0.0);
                                for b in 0..=q {
                                    let c = &row[(ly - q + b) * d..(ly - q + b + 1) * d];
                                    for (z, w) in o.iter_mut().zip(c) {
                                        *z += by[b] * w;
                                    }
                                }
                            }
                        }
                    }
                },
            );
        Ok(())
    }

    /// The integral of the surface over \[xa, xb\] × \[ya, yb\], per coordinate, as SciPy's
    /// `RectBivariateSpline.integral` (FITPACK's `dblint`): only the part inside the domain
    /// counts (the surface is taken as 0 outside, not continued), reversed limits give the
    /// negative (per direction), NaN limits NaN, infinite ones are clipped. Closed form:
    /// the integral in x of each net row ([`BsplineCurve::integrate`] with
    /// [`Extrapolate::Nan`]), then in y.
    pub fn integral(&self, xa: f64, xb: f64, ya: f64, yb: f64) -> Vec<f64> {
        let (p, q) = self.degrees();
        let (ku, kv) = self.knots();
        let d = self.dim();
        let rows = Tck {
            t: ku,
            c: self.control_flat(),
            k: p,
            d: self.net_size().1 * d,
        }
        .integrate(xa, xb, Extrapolate::Nan);
        Tck {
            t: kv,
            c: &rows,
            k: q,
            d,
        }
        .integrate(ya, yb, Extrapolate::Nan)
    }

    /// Checks FITPACK's derivative orders and the output length for `points` points.
    fn check_partial(&self, nx: usize, ny: usize, dx: usize, dy: usize, out: &[f64]) -> Result<()> {
        let (p, q) = self.degrees();
        if (dx, dy) != (0, 0) {
            if dx >= p {
                return Err(Error::DerivativeOrder {
                    order: dx,
                    degree: p,
                    reason: "FITPACK's surface derivatives (SciPy's RectBivariateSpline) take \
                             orders below the degree in x; eval_derivative gives every order",
                });
            }
            if dy >= q {
                return Err(Error::DerivativeOrder {
                    order: dy,
                    degree: q,
                    reason: "FITPACK's surface derivatives (SciPy's RectBivariateSpline) take \
                             orders below the degree in y; eval_derivative gives every order",
                });
            }
        }
        let expected = nx.checked_mul(ny).and_then(|v| v.checked_mul(self.dim()));
        if expected != Some(out.len()) {
            return Err(Error::BufferSize {
                expected: expected.unwrap_or(usize::MAX),
                got: out.len(),
            });
        }
        Ok(())
    }

    /// The two directions as (knots, degree) views.
    fn axes(&self) -> (Axis<'_>, Axis<'_>) {
        let (ku, kv) = self.knots();
        let (p, q) = self.degrees();
        (Axis { t: ku, k: p }, Axis { t: kv, k: q })
    }

    /// Σ_a Σ_b bx\[a\]·by\[b\]·c_(lx-p+a, ly-q+b) into `out`, in FITPACK's order.
    #[inline]
    fn combine(&self, lx: usize, bx: &[f64; 8], ly: usize, by: &[f64; 8], out: &mut [f64]) {
        let (p, q) = self.degrees();
        let (n_v, d) = (self.net_size().1, self.dim());
        let control = self.control_flat();
        out.fill(0.0);
        for a in 0..=p {
            for b in 0..=q {
                let at = ((lx - p + a) * n_v + ly - q + b) * d;
                for (o, c) in out.iter_mut().zip(&control[at..at + d]) {
                    *o += c * bx[a] * by[b];
                }
            }
        }
    }
}

/// One direction of a surface: knots and degree (<= 7).
#[derive(Clone, Copy)]
struct Axis<'a> {
    t: &'a [f64],
    k: usize,
}

impl Axis<'_> {
    /// FITPACK's basis at x (clamped to the domain) with derivative order `nu` (<= k):
    /// the interval and the k+1 values; `None` for NaN. Zero on an empty end interval.
    #[inline]
    fn basis(&self, x: f64, nu: usize, hint: &mut usize) -> Option<(usize, [f64; 8])> {
        let tck = Tck {
            t: self.t,
            c: &[],
            k: self.k,
            d: 0,
        };
        let (a, b) = tck.base();
        let l = tck.interval(x.clamp(a, b), true, *hint)?;
        *hint = l;
        let mut out = [0.0; 8];
        if self.t[l] < self.t[l + 1] {
            let mut hh = [0.0; 8];
            de_boor_d(self.t, x.clamp(a, b), self.k, l, nu, &mut out, &mut hh);
        }
        Some((l, out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SciPy 1.17.1: `BSpline([0,0,0,0,1,2.5,3,3,3,3], [1,2,-1,3,0.5,2], 3)`.
    fn scipy_cubic() -> BsplineCurve {
        let t = vec![0., 0., 0., 0., 1., 2.5, 3., 3., 3., 3.];
        BsplineCurve::from_flat(3, t, 1, vec![1., 2., -1., 3., 0.5, 2.]).unwrap()
    }

    #[test]
    fn derivatives_and_extrapolation_match_scipy() {
        let c = scipy_cubic();
        let x = [-1.0, 0.0, 1.0, 2.5, 3.0, 4.0];
        // b(x, nu=nu) printed by SciPy (8 digits).
        let want: [[f64; 6]; 4] = [
            [-11.81333333, 1.0, 0.61333333, 1.42708333, 2.0, 56.08333333],
            [25.84, 3.0, -0.56, -1.8125, 9.0, 118.75],
            [-32.48, -13.2, 6.08, -7.75, 51.0, 168.5],
            [19.28, 19.28, -9.22, 117.5, 117.5, 117.5],
        ];
        let mut out = [0.0; 6];
        for (nu, w) in want.iter().enumerate() {
            c.eval_nu_many(&x, nu, Extrapolate::Extend, &mut out)
                .unwrap();
            for (a, b) in out.iter().zip(w) {
                assert!((a - b).abs() < 1e-7 * b.abs().max(1.0), "nu {nu}: {out:?}");
            }
        }
        // Order k + 1: 0, NaN outside without extrapolation; k + 2: 0 everywhere.
        c.eval_nu_many(&x, 4, Extrapolate::Nan, &mut out).unwrap();
        assert!(out[0].is_nan() && out[1..5] == [0.0; 4] && out[5].is_nan());
        c.eval_nu_many(&[f64::NAN, -1.0], 5, Extrapolate::Nan, &mut out[..2])
            .unwrap();
        assert_eq!(out[..2], [0.0; 2]);
        c.eval_nu_many(&[f64::NAN, -1.0, 3.0], 0, Extrapolate::Nan, &mut out[..3])
            .unwrap();
        assert!(out[0].is_nan() && out[1].is_nan() && out[2] == 2.0);
    }

    #[test]
    fn degree_zero_keeps_its_last_value_on_the_empty_end_interval() {
        // SciPy: BSpline([0, 1, 2, 3, 3], [1, 2, 3, 4], 0)(x, nu, extrapolate).
        let c =
            BsplineCurve::from_flat(0, vec![0., 1., 2., 3., 3.], 1, vec![1., 2., 3., 4.]).unwrap();
        let mut out = [0.0; 4];
        c.eval_nu_many(&[2.5, 3.0, 4.0, -1.0], 0, Extrapolate::Extend, &mut out)
            .unwrap();
        assert_eq!(out, [3.0, 4.0, 4.0, 1.0]);
        c.eval_nu_many(&[2.5, 3.0, 4.0, 3.5], 0, Extrapolate::Nan, &mut out)
            .unwrap();
        assert!(out[..2] == [3.0, 4.0] && out[2].is_nan() && out[3].is_nan());
        c.eval_nu_many(&[3.5, 3.0, 4.0, 2.0], 1, Extrapolate::Extend, &mut out)
            .unwrap();
        assert_eq!(out, [0.0; 4]);
        c.eval_nu_many(&[3.5], 0, Extrapolate::Periodic, &mut out[..1])
            .unwrap();
        assert_eq!(out[0], 1.0);
    }

    #[test]
    fn derivative_and_antiderivative_knots_match_scipy() {
        let c = scipy_cubic();
        let d = c.derivative_nu(1).unwrap();
        assert_eq!(d.knots(), &[0., 0., 0., 1., 2.5, 3., 3., 3.]);
        assert_eq!(d.control_flat(), &[3., -3.6, 4., -3.75, 9.]);
        let f = c.antiderivative(1).unwrap();
        assert_eq!(
            f.knots(),
            &[0., 0., 0., 0., 0., 1., 2.5, 3., 3., 3., 3., 3.]
        );
        assert_eq!(f.control_flat(), &[0., 0.25, 1.5, 0.75, 3., 3.25, 3.5]);
        let z = c.derivative_nu(3).unwrap();
        assert_eq!(
            (z.degree(), z.control_flat()),
            (0, &[19.28, -9.22, 117.5][..])
        );
        // An interior knot of multiplicity 3 in a cubic: once, not twice.
        let t = vec![0., 0., 0., 0., 1., 1., 1., 2., 2., 2., 2.];
        let r = BsplineCurve::from_flat(3, t, 1, (0..7).map(f64::from).collect()).unwrap();
        assert_eq!(r.derivative_nu(1).unwrap().control_flat(), &[3.0; 6]);
        let e = r.derivative_nu(2).unwrap_err();
        assert!(
            matches!(
                e,
                Error::NotDifferentiable {
                    order: 2,
                    index: 4,
                    multiplicity: 3,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn integrals_match_scipy() {
        let c = scipy_cubic();
        // b.integrate(a, b, extrapolate) printed by SciPy.
        for (a, b, ext, want) in [
            (5.0, 7.0, Extrapolate::Extend, 1709.0),
            (5.0, 7.0, Extrapolate::Nan, 0.0),
            (5.0, 7.0, Extrapolate::Periodic, 2.5375),
            (-1.0, 5.0, Extrapolate::Nan, 3.5),
            (-1.0, 5.0, Extrapolate::Periodic, 7.0),
            (2.0, 1.0, Extrapolate::Periodic, -0.9625),
            (-1.0, 1.0, Extrapolate::Extend, -2.4),
        ] {
            let got = c.integrate(a, b, ext)[0];
            assert!(
                (got - want).abs() < 1e-12 * want.abs().max(1.0),
                "{a} {b} {ext:?}: {got}"
            );
        }
        assert!(c.integrate(f64::NAN, 1.0, Extrapolate::Nan)[0].is_nan());
        let all = c.integrate(f64::NEG_INFINITY, f64::INFINITY, Extrapolate::Nan)[0];
        assert!((all - 3.5).abs() < 1e-15);
    }

    #[test]
    fn insertion_matches_scipy() {
        let c = scipy_cubic();
        let i = c.insert_knot(1.0, 2).unwrap();
        assert_eq!(
            i.knots(),
            &[0., 0., 0., 0., 1., 1., 1., 2.5, 3., 3., 3., 3.]
        );
        let want = [1., 2., 0.8, 0.61333333, 0.33333333, 3., 0.5, 2.];
        for (a, b) in i.control_flat().iter().zip(want) {
            assert!((a - b).abs() < 1e-8);
        }
        let e = c.insert_knot(3.1, 1).unwrap_err();
        assert_eq!(
            e.to_string(),
            "cannot insert a knot at 3.1: outside the base interval [t_k, t_n]"
        );
        assert!(c.insert_knot(f64::NAN, 1).is_err());
        assert!(c.insert_knot(1.0, 0).is_err());
        let end = c.insert_knot(3.0, 1).unwrap();
        assert_eq!(end.control_flat(), &[1., 2., -1., 3., 0.5, 2., 2.]);
    }

    #[test]
    fn grid_coordinates_as_scipy_checks_them() {
        // z = x·y on [0, 1]².
        let k = vec![0., 0., 1., 1.];
        let s =
            BsplineSurface::from_flat((1, 1), k.clone(), k, 2, 2, 1, vec![0., 0., 0., 1.]).unwrap();
        let mut z = [0.0; 2];
        // Equal neighbours pass SciPy's diff >= 0; decreasing ones and NaN among two do not.
        s.eval_partial_grid(&[0.5, 0.5], &[0.5], 0, 0, &mut z)
            .unwrap();
        assert_eq!(z, [0.25, 0.25]);
        for x in [[0.6, 0.5], [0.5, f64::NAN]] {
            let e = s.eval_partial_grid(&x, &[0.5], 0, 0, &mut z).unwrap_err();
            assert!(matches!(e, Error::InvalidParameter { index: 1, .. }), "{e}");
        }
        // One NaN coordinate alone gives NaN, as in ev; outside, the values at the border.
        s.eval_partial_grid(&[f64::NAN], &[0.5, 3.0], 0, 0, &mut z)
            .unwrap();
        assert!(z[0].is_nan() && z[1].is_nan());
        s.eval_partial_many(&[-1.0, 2.0], &[0.5, 3.0], 0, 0, &mut z)
            .unwrap();
        assert_eq!(z, [0.0, 1.0]);
        assert!(s
            .eval_partial_many(&[0.5], &[0.5], 1, 0, &mut z[..1])
            .is_err());
        assert!(s.eval_partial_many(&[0.5], &[], 0, 0, &mut z[..1]).is_err());
        assert!(s.integral(f64::NAN, 1.0, 0.0, 1.0)[0].is_nan());
        assert_eq!(s.integral(1.0, 0.0, 0.0, 1.0), vec![-0.25]);
    }

    #[test]
    fn python_divmod() {
        assert_eq!(py_divmod(7.0, 3.0), (2.0, 1.0));
        assert_eq!(py_divmod(-1.0, 3.0), (-1.0, 2.0));
        assert_eq!(py_mod(-0.0, 3.0).to_bits(), 0.0f64.to_bits());
        assert_eq!(py_mod(-1e-20, 3.0), 3.0);
        assert!(py_mod(f64::INFINITY, 3.0).is_nan());
    }
}
