//! Node sets of one parameter and their cardinal ("b-") functions in the barycentric form
//! (spec/point-calculus.md §2, §4).
//!
//! The cardinal function of node j is the Lagrange polynomial ℓ_j(t) = Π_(k≠j) (t - t_k) /
//! (t_j - t_k): 1 at its node, 0 at the others, and Σ_j ℓ_j(t) = 1. It is evaluated by the
//! second ("true") barycentric form ℓ_j(t) = (w_j / (t - t_j)) / Σ_k w_k / (t - t_k) with the
//! weights w_j = 1 / Π_(k≠j) (t_j - t_k) (Berrut & Trefethen, SIAM Review 46, 2004), which is
//! forward stable on the node interval for node sets with a small Lebesgue constant; at a node
//! the node's own function is exactly 1 and the others exactly 0. Outside the node interval
//! the product form is used (stable there). Derivatives follow Schneider & Werner (1986),
//! written so that they keep their accuracy next to a node.
//!
//! ```
//! use geomkit::pointcalc::Nodes;
//! let nodes = Nodes::paper_third(); // {0, 1/3, 1}: the paper's equation (2)
//! let mut l = [0.0; 3];
//! nodes.basis_into(0.5, &mut l);
//! // (2): A t̄(1 - 3t) + C 4.5 t t̄ + B 0.5 t(3t - 1) at t = 1/2
//! assert!((l[0] + 0.25).abs() < 1e-15 && (l[1] - 1.125).abs() < 1e-15);
//! assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-15);
//! ```

use super::wide::{ldexp, split};
use crate::exact::{rational_from_f64, rational_to_f64, Rational};
use crate::numeric::Dd;
use crate::{Error, Result};
use num_traits::{One, Zero};

/// Node presets of [`Nodes::preset`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NodePreset {
    /// Equally spaced, both ends included (Lebesgue constant grows like 2^n: keep n small).
    Equispaced,
    /// Chebyshev points of the first kind (roots of T_n), ends not included.
    ChebyshevFirst,
    /// Chebyshev points of the second kind (extrema of T_(n-1)), ends included.
    ChebyshevSecond,
}

/// Node sets up to this size evaluate the barycentric form with one division.
pub(crate) const SMALL: usize = 16;

/// The second barycentric form's sum Σ_k w_k / (t - t_k) is used while it keeps at least 20
/// of its 53 bits: |Σ| >= CANCEL · Σ |·|, that is where the Lebesgue function at t is below
/// 2^20 (always for Chebyshev-like nodes). Beyond, the sum has cancelled (nodes far from
/// evenly spread, rounded weights) and the product form, accurate share by share, is used.
pub(crate) const CANCEL: f64 = 1.0 / 1048576.0;

/// Samples per node interval of the Lebesgue constant estimate (then refined): more for
/// small sets, fewer for large ones (where the cost is n per sample and the intervals many).
fn lebesgue_samples(n: usize) -> usize {
    if n <= 32 {
        24
    } else {
        8
    }
}

/// A node set t_0 < t_1 < ... < t_(n-1) of one parameter with its barycentric weights.
///
/// Nodes given as rationals ([`Nodes::from_rationals`], the paper's presets) keep their exact
/// values for [`Nodes::cardinal_polynomials`]; f64 nodes are exact dyadic rationals anyway.
#[derive(Debug, Clone, PartialEq)]
pub struct Nodes {
    values: Vec<f64>,
    exact: Option<Vec<Rational>>,
    weights: Vec<f64>,
    /// The true weights 1 / Π_(k≠j) (t_j - t_k) are `weights[j] · m · 2^e` for
    /// `scale = (m, e)` (for the product form, which needs them unscaled).
    scale: (f64, i64),
}

impl Nodes {
    /// The most nodes of one node set: building a set costs O(n²) (the weights in
    /// double-double and the Lebesgue constant estimate, about 1.5 s at the limit), and
    /// the tensor grids, formulas and optimum search of the point calculus grow faster still.
    /// Larger sets are refused with [`Error::TooMany`].
    pub const MAX_LEN: usize = 5_000;

    /// Nodes at the given positions. Errors: no nodes, more than [`Nodes::MAX_LEN`]
    /// ([`Error::TooMany`]), a non-finite node, nodes not strictly increasing
    /// ([`Error::InvalidNodes`] names the node), differences that overflow f64, or weights
    /// that span more than the f64 range (nodes so unevenly spaced, or so many equispaced
    /// ones, that interpolation through them amplifies rounding beyond 1e300).
    ///
    /// ```
    /// use geomkit::pointcalc::Nodes;
    /// assert!(Nodes::new(vec![0.0, 0.3, 1.0]).is_ok());
    /// assert!(Nodes::new(vec![0.0, 0.3, 0.3]).is_err());
    /// assert!(Nodes::new(vec![0.0; Nodes::MAX_LEN + 1]).is_err());
    /// ```
    pub fn new(values: Vec<f64>) -> Result<Self> {
        check_increasing("nodes", &values)?;
        let (weights, scale) = barycentric_weights(&values)?;
        Ok(Nodes {
            values,
            exact: None,
            weights,
            scale,
        })
    }

    /// Nodes at exact rational positions (kept exact for [`Nodes::cardinal_polynomials`];
    /// evaluation uses their correctly rounded f64 values). Errors as [`Nodes::new`], and two
    /// rationals that round to the same f64.
    pub fn from_rationals(values: Vec<Rational>) -> Result<Self> {
        check_len(values.len())?;
        if let Some(index) = values.windows(2).position(|w| w[1] <= w[0]) {
            return Err(Error::InvalidNodes {
                what: "nodes".into(),
                index: index + 1,
                reason: "nodes must be strictly increasing",
            });
        }
        let floats: Vec<f64> = values.iter().map(rational_to_f64).collect();
        let mut nodes = Nodes::new(floats)?;
        nodes.exact = Some(values);
        Ok(nodes)
    }

    /// Three nodes {0, t_C, 1} (the paper's b-curves through A, C, B) with t_C exact.
    /// Errors unless 0 < t_C < 1.
    pub fn three_point(t_c: Rational) -> Result<Self> {
        Nodes::from_rationals(vec![Rational::zero(), t_c, Rational::one()])
    }

    /// {0, 1/2, 1}: equation (1) of the spec.
    pub fn paper_half() -> Self {
        Nodes::three_point(ratio(1, 2)).expect("valid nodes")
    }

    /// {0, 1/3, 1}: equation (2) of the spec.
    pub fn paper_third() -> Self {
        Nodes::three_point(ratio(1, 3)).expect("valid nodes")
    }

    /// {0, 2/3, 1}: equation (3) of the spec.
    pub fn paper_two_thirds() -> Self {
        Nodes::three_point(ratio(2, 3)).expect("valid nodes")
    }

    /// `n` nodes of a preset on [a, b]. Errors: n = 0, n above [`Nodes::MAX_LEN`] (refused
    /// before anything is allocated), [a, b] not finite with a < b (a = b is allowed for
    /// n = 1).
    ///
    /// ```
    /// use geomkit::pointcalc::{Nodes, NodePreset};
    /// let c = Nodes::preset(NodePreset::ChebyshevSecond, 5, -1.0, 1.0).unwrap();
    /// let want = [-1.0, -(0.5f64.sqrt()), 0.0, 0.5f64.sqrt(), 1.0];
    /// assert!(c.values().iter().zip(want).all(|(x, w)| (x - w).abs() < 1e-15));
    /// ```
    pub fn preset(preset: NodePreset, n: usize, a: f64, b: f64) -> Result<Self> {
        if n == 0 {
            return Err(Error::Empty { what: "node set" });
        }
        check_len(n)?;
        if !a.is_finite() || !b.is_finite() || b < a || (b == a && n > 1) {
            return Err(Error::InvalidOption {
                option: "node interval",
                reason: "need finite a < b",
            });
        }
        if n == 1 {
            return Nodes::new(vec![0.5 * a + 0.5 * b]);
        }
        // Halves first: exact, and no overflow for intervals as wide as f64 (the same bits
        // as 0.5 (a + b) and 0.5 (b - a) wherever those do not overflow).
        let (mid, half) = (0.5 * a + 0.5 * b, 0.5 * b - 0.5 * a);
        let m = (n - 1) as f64;
        let pi = std::f64::consts::PI;
        let values: Vec<f64> = (0..n)
            .map(|j| match preset {
                NodePreset::Equispaced => {
                    if j == n - 1 {
                        b
                    } else {
                        let t = j as f64 / m;
                        if (b - a).is_finite() {
                            a + (b - a) * t
                        } else {
                            // An interval wider than f64: from the middle.
                            mid + half * (2.0 * t - 1.0)
                        }
                    }
                }
                // sin of symmetric angles: exactly symmetric, ends exactly ±1.
                NodePreset::ChebyshevFirst => {
                    let k = 2.0 * j as f64 - m;
                    mid + half * (pi * k / (2.0 * n as f64)).sin()
                }
                NodePreset::ChebyshevSecond => {
                    if j == 0 {
                        a
                    } else if j == n - 1 {
                        b
                    } else {
                        let k = 2.0 * j as f64 - m;
                        mid + half * (pi * k / (2.0 * m)).sin()
                    }
                }
            })
            .collect();
        Nodes::new(values).map_err(|e| match e {
            // Nodes that coincide in f64: an interval too narrow for n of them.
            Error::InvalidNodes { reason, .. } if reason.contains("increasing") => {
                Error::InvalidOption {
                    option: "node interval",
                    reason: "too narrow for this many distinct f64 nodes",
                }
            }
            e => e,
        })
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Always false: a node set has at least one node.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The node positions.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// The exact node positions (the given rationals, or the exact values of the f64 nodes).
    pub fn exact_values(&self) -> Vec<Rational> {
        match &self.exact {
            Some(e) => e.clone(),
            None => self
                .values
                .iter()
                .map(|&x| rational_from_f64(x).expect("finite"))
                .collect(),
        }
    }

    /// Whether the nodes were given as exact rationals.
    pub fn is_rational(&self) -> bool {
        self.exact.is_some()
    }

    /// The barycentric weights w_j ∝ 1 / Π_(k≠j) (t_j - t_k), scaled so that max |w_j| = 1
    /// (computed in double-double, correctly rounded up to an ulp).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The true barycentric weight 1 / Π_(k≠j) (t_j - t_k) of node j, rounded to f64
    /// (±infinity or 0 where it is beyond the f64 range).
    pub(crate) fn true_weight(&self, j: usize) -> f64 {
        ldexp(self.weights[j] * self.scale.0, self.scale.1)
    }

    /// The k-th derivatives of the cardinal functions at t, any order: orders 1 and 2 by
    /// [`Nodes::basis_derivatives`]; above, ℓ_j^(k)(t) = Σ_i ℓ_i(t) (D^k)_ij with the
    /// differentiation matrix D_ij = (w_j/w_i)/(t_i - t_j), D_ii = -Σ_(j≠i) D_ij (Berrut &
    /// Trefethen §9: the derivative of the interpolant of degree n - 1 is the interpolant
    /// of its values at the nodes), O(k n²); zero from order n on.
    pub(crate) fn basis_derivative(&self, t: f64, k: usize) -> Vec<f64> {
        let n = self.values.len();
        match k {
            0 => self.basis(t),
            _ if k >= n => vec![0.0; n],
            1 | 2 => {
                let (mut l, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                self.basis_derivatives(t, &mut l, &mut d1, Some(&mut d2));
                if k == 1 {
                    d1
                } else {
                    d2
                }
            }
            _ => {
                let (x, w) = (&self.values, &self.weights);
                let mut d = vec![0.0; n * n];
                for i in 0..n {
                    let mut diag = 0.0;
                    for j in (0..n).filter(|&j| j != i) {
                        let dij = (w[j] / w[i]) / (x[i] - x[j]);
                        d[i * n + j] = dij;
                        diag -= dij;
                    }
                    d[i * n + i] = diag;
                }
                let mut row = self.basis(t);
                for _ in 0..k {
                    let mut next = vec![0.0; n];
                    for (r, di) in row.iter().zip(d.chunks_exact(n)) {
                        for (nj, dij) in next.iter_mut().zip(di) {
                            *nj += r * dij;
                        }
                    }
                    row = next;
                }
                row
            }
        }
    }

    /// The node interval [t_0, t_(n-1)].
    pub fn domain(&self) -> (f64, f64) {
        (self.values[0], self.values[self.values.len() - 1])
    }

    /// Index of the node equal to `t`, if any.
    pub fn position(&self, t: f64) -> Option<usize> {
        self.values.iter().position(|&x| x == t)
    }

    /// The values ℓ_j(t) of all cardinal functions at `t` (the shares of the nodes), written
    /// to `out` (length [`Nodes::len`]). At a node: exactly 1 there and 0 elsewhere. `t` must
    /// be finite (NaN gives NaN).
    ///
    /// Inside the node interval the second barycentric form; outside it, and wherever the
    /// second form's sum cancels (the Lebesgue function above 2^20: nodes far from evenly
    /// spread) or leaves the f64 range, the product form Π_(k≠j) (t - t_k) /
    /// (t_j - t_k) computed with an exponent of its own, so the only non-finite values are
    /// ±infinity for a share whose true value is beyond f64 (far outside the nodes: ℓ_j grows
    /// like t^(n-1)), never NaN.
    pub fn basis_into(&self, t: f64, out: &mut [f64]) {
        let n = self.values.len();
        debug_assert_eq!(out.len(), n);
        if n == 1 {
            out[0] = 1.0;
            return;
        }
        if t < self.values[0] || t > self.values[n - 1] {
            self.basis_product(t, out);
            return;
        }
        if n <= SMALL && self.basis_small(t, out) {
            return;
        }
        let (mut sum, mut size) = (0.0, 0.0);
        for k in 0..n {
            let d = t - self.values[k];
            if d == 0.0 {
                out.fill(0.0);
                out[k] = 1.0;
                return;
            }
            let c = self.weights[k] / d;
            out[k] = c;
            sum += c;
            size += c.abs();
        }
        if !sum.is_normal() || sum.abs() < CANCEL * size {
            // t is within an f64 overflow of a node, or the sum cancelled.
            self.basis_product(t, out);
            return;
        }
        let inv = 1.0 / sum;
        out.iter_mut().for_each(|c| *c *= inv);
        if !out.iter().all(|c| c.is_finite()) {
            self.basis_product(t, out);
        }
    }

    /// The cardinal functions at `t` as mantissas with one exponent: ℓ_j(t) = out[j] · 2^E
    /// for the returned E, for every finite t (nothing overflows: each factor and product has
    /// an exponent of its own); max |out[j]| is in [0.5, 1). The product form ℓ_j(t) = W_j
    /// Π_(k≠j) (t - t_k) with the true weights W_j, O(n): every ℓ_j to a relative accuracy
    /// of about (n + 4) ε wherever t is.
    pub(crate) fn basis_wide(&self, t: f64, out: &mut [f64]) -> i64 {
        let n = self.values.len();
        if n == 1 {
            out[0] = 1.0;
            return 0;
        }
        if let Some(k) = self.position(t) {
            out.fill(0.0);
            out[k] = 1.0;
            return 0;
        }
        // t - t_k as (mantissa, exponent), halved first where the difference overflows.
        let diff = |xk: f64| -> (f64, i64) {
            let d = t - xk;
            if d.is_finite() {
                split(d)
            } else {
                let (m, e) = split(0.5 * t - 0.5 * xk);
                (m, e + 1)
            }
        };
        // L = Π_k (t - t_k).
        let (mut lm, mut le) = (1.0, 0i64);
        for &xk in &self.values {
            let (m, e) = diff(xk);
            let (pm, pe) = split(lm * m);
            lm = pm;
            le += e + pe;
        }
        let (sm, se) = self.scale;
        // ℓ_j = w_j · s · L / (t - t_j): mantissa and exponent.
        let share = |j: usize| -> (f64, i64) {
            let (dm, de) = diff(self.values[j]);
            let (wm, we) = split(self.weights[j]);
            let (vm, ve) = split(wm * sm * lm / dm);
            (vm, ve + we + se + le - de)
        };
        let mut emax = i64::MIN;
        for j in 0..n {
            emax = emax.max(share(j).1);
        }
        for (j, o) in out.iter_mut().enumerate() {
            let (m, e) = share(j);
            *o = ldexp(m, e - emax);
        }
        emax
    }

    /// The product form, used outside the node interval and where the second form fails:
    /// [`Nodes::basis_wide`] rounded to f64 (±infinity where a share is beyond f64).
    fn basis_product(&self, t: f64, out: &mut [f64]) {
        let e = self.basis_wide(t, out);
        out.iter_mut().for_each(|o| *o = ldexp(*o, e));
    }

    /// The second form multiplied through by Π_k (t - t_k): q_j = w_j Π_(k≠j) (t - t_k) by
    /// prefix and suffix products, ℓ_j = q_j / Σ q_k (one division instead of n; the same
    /// ratio of forward-stable sums). False (nothing written that matters) when the products
    /// leave the normal range; the caller then divides per node.
    #[inline]
    fn basis_small(&self, t: f64, out: &mut [f64]) -> bool {
        let n = self.values.len();
        let mut prefix = [1.0; SMALL + 1];
        for k in 0..n {
            prefix[k + 1] = prefix[k] * (t - self.values[k]);
        }
        if prefix[n] == 0.0 {
            // t is a node (or the product underflowed): decide per node.
            if let Some(k) = self.position(t) {
                out.fill(0.0);
                out[k] = 1.0;
                return true;
            }
            return false;
        }
        let mut suffix = 1.0;
        let (mut sum, mut size) = (0.0, 0.0);
        for k in (0..n).rev() {
            let q = self.weights[k] * prefix[k] * suffix;
            out[k] = q;
            sum += q;
            size += q.abs();
            suffix *= t - self.values[k];
        }
        if !sum.is_normal() || sum.abs() < CANCEL * size {
            return false;
        }
        let inv = 1.0 / sum;
        out.iter_mut().for_each(|q| *q *= inv);
        true
    }

    /// The cardinal functions at `t` as a new vector (see [`Nodes::basis_into`]).
    pub fn basis(&self, t: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.len()];
        self.basis_into(t, &mut out);
        out
    }

    fn nearest(&self, t: f64) -> usize {
        let mut best = 0;
        for k in 1..self.values.len() {
            if (t - self.values[k]).abs() < (t - self.values[best]).abs() {
                best = k;
            }
        }
        best
    }

    /// The cardinal functions and their first derivatives at `t`, and the second
    /// derivatives when `d2` is given (all buffers of length [`Nodes::len`]).
    ///
    /// Between nodes: the Schneider–Werner formulas in basis form, ℓ_j' = ℓ_j (σ_1 - r_j) with
    /// r_k = 1 / (t - t_k), σ_1 = Σ ℓ_k r_k, and ℓ_j'' = ℓ_j (2(σ_1² - σ_2) - 2σ_1 r_j + 2r_j²)
    /// with σ_2 = Σ ℓ_k r_k², where the large terms of the nearest node i cancel exactly on
    /// paper and are rewritten with 1 - ℓ_i = Σ_(k≠i) ℓ_k, and ℓ_i^(m) = -Σ_(k≠i) ℓ_k^(m). At a
    /// node: the rows of the differentiation matrices D_ij = (w_j/w_i)/(t_i - t_j),
    /// D⁽²⁾_ij = 2 D_ij (D_ii - 1/(t_i - t_j)) (Berrut & Trefethen §9).
    pub fn basis_derivatives(&self, t: f64, l: &mut [f64], d1: &mut [f64], d2: Option<&mut [f64]>) {
        let n = self.values.len();
        let x = &self.values;
        let w = &self.weights;
        if n == 1 {
            l[0] = 1.0;
            d1[0] = 0.0;
            if let Some(d2) = d2 {
                d2[0] = 0.0;
            }
            return;
        }
        let i = self.nearest(t);
        self.basis_into(t, l);
        let h = t - x[i];
        if h == 0.0 || !(1.0 / h).is_finite() {
            let xi = x[i];
            let mut dii = 0.0;
            for j in 0..n {
                if j != i {
                    d1[j] = (w[j] / w[i]) / (xi - x[j]);
                    dii -= d1[j];
                }
            }
            d1[i] = dii;
            if let Some(d2) = d2 {
                let mut s = 0.0;
                for j in 0..n {
                    if j != i {
                        d2[j] = 2.0 * d1[j] * (dii - 1.0 / (xi - x[j]));
                        s -= d2[j];
                    }
                }
                d2[i] = s;
            }
            return;
        }
        let ri = 1.0 / (t - x[i]);
        let (mut m, mut a, mut b) = (0.0, 0.0, 0.0);
        for k in 0..n {
            if k != i {
                let rk = 1.0 / (t - x[k]);
                m += l[k];
                a += l[k] * rk;
                b += l[k] * rk * rk;
            }
        }
        let li = l[i];
        let sigma1 = li * ri + a;
        let mut s1 = 0.0;
        for j in 0..n {
            if j != i {
                let rj = 1.0 / (t - x[j]);
                d1[j] = l[j] * (sigma1 - rj);
                s1 -= d1[j];
            }
        }
        d1[i] = s1;
        if let Some(d2) = d2 {
            // σ_1² - σ_2 = -ℓ_i m r_i² + 2 ℓ_i r_i A + A² - B, m = 1 - ℓ_i.
            let q = -li * m * ri * ri + 2.0 * li * ri * a + a * a - b;
            let mut s2 = 0.0;
            for j in 0..n {
                if j != i {
                    let rj = 1.0 / (t - x[j]);
                    d2[j] = l[j] * (2.0 * q - 2.0 * sigma1 * rj + 2.0 * rj * rj);
                    s2 -= d2[j];
                }
            }
            d2[i] = s2;
        }
    }

    /// Estimate of the Lebesgue constant Λ = max over [t_0, t_(n-1)] of Σ_j |ℓ_j(t)|: the
    /// factor by which interpolation can amplify errors in the data. Sampled at 24 points in
    /// every node interval (8 above 32 nodes; values above 1e8 again in the product form,
    /// which keeps its accuracy there), then refined by golden-section search around the
    /// largest sample (a lower bound, within about 1e-6 relative of the true maximum for
    /// n ≤ 1000).
    /// `f64::MAX` when it is beyond f64 (node sets whose weights differ by more than about
    /// 1e300).
    ///
    /// ```
    /// use geomkit::pointcalc::Nodes;
    /// assert!((Nodes::paper_half().lebesgue_constant() - 1.25).abs() < 1e-9);
    /// ```
    pub fn lebesgue_constant(&self) -> f64 {
        let n = self.values.len();
        if n <= 2 {
            return 1.0;
        }
        let mut buf = vec![0.0; n];
        let mut lebesgue = |t: f64| {
            self.basis_into(t, &mut buf);
            let sum = buf.iter().map(|v| v.abs()).sum::<f64>();
            if sum <= 1e8 {
                return sum;
            }
            // The second form loses digits like Λ ε: large values again in the product
            // form (each share to a relative (n + 4) ε), with an exponent of its own.
            let e = self.basis_wide(t, &mut buf);
            ldexp(buf.iter().map(|v| v.abs()).sum::<f64>(), e)
        };
        let samples = lebesgue_samples(n);
        let (mut best, mut best_t, mut best_k) = (1.0, self.values[0], 0);
        for k in 0..n - 1 {
            let (a, b) = (self.values[k], self.values[k + 1]);
            for s in 1..samples {
                let t = a + (b - a) * (s as f64 / samples as f64);
                let v = lebesgue(t);
                if v > best {
                    (best, best_t, best_k) = (v, t, k);
                }
            }
        }
        let h = (self.values[best_k + 1] - self.values[best_k]) / samples as f64;
        let (mut lo, mut hi) = (
            (best_t - h).max(self.values[best_k]),
            (best_t + h).min(self.values[best_k + 1]),
        );
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..40 {
            let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if lebesgue(c) > lebesgue(d) {
                hi = d;
            } else {
                lo = c;
            }
        }
        let value = best.max(lebesgue(0.5 * (lo + hi)));
        if value.is_finite() {
            value
        } else {
            f64::MAX
        }
    }

    /// The default Lebesgue limit for n nodes: 4 + (2/π) ln n, three above the near-optimal
    /// growth of Chebyshev nodes. Warns (or errors when strict) for three nodes with t_C below
    /// about 0.11 or above 0.89, and for 8 or more equispaced nodes; never for Chebyshev nodes.
    pub fn default_lebesgue_limit(&self) -> f64 {
        4.0 + 2.0 / std::f64::consts::PI * (self.len() as f64).ln()
    }

    /// The exact power-basis coefficients of every cardinal function:
    /// `result[j][k]` is the coefficient of t^k in ℓ_j(t) (exact rationals of the exact node
    /// positions). For the paper's nodes these are the printed equations (1)-(3).
    ///
    /// ```
    /// use geomkit::pointcalc::Nodes;
    /// use geomkit::exact::Rational;
    /// let p = Nodes::paper_half().cardinal_polynomials();
    /// // (1): C 4 t t̄ = 4t - 4t²
    /// let r = |n: i64| Rational::from_integer(n.into());
    /// assert_eq!(p[1], vec![r(0), r(4), r(-4)]);
    /// ```
    pub fn cardinal_polynomials(&self) -> Vec<Vec<Rational>> {
        let x = self.exact_values();
        let n = x.len();
        (0..n)
            .map(|j| {
                let mut poly = vec![Rational::one()];
                let mut denom = Rational::one();
                for (k, xk) in x.iter().enumerate() {
                    if k == j {
                        continue;
                    }
                    // poly *= (t - x_k)
                    let mut next = vec![Rational::zero(); poly.len() + 1];
                    for (d, c) in poly.iter().enumerate() {
                        next[d + 1] += c;
                        next[d] -= c * xk;
                    }
                    poly = next;
                    denom *= &x[j] - xk;
                }
                poly.into_iter().map(|c| c / &denom).collect()
            })
            .collect()
    }

    /// The exact cardinal functions at an exact parameter.
    pub fn basis_exact(&self, t: &Rational) -> Vec<Rational> {
        let x = self.exact_values();
        (0..x.len())
            .map(|j| {
                let mut v = Rational::one();
                for (k, xk) in x.iter().enumerate() {
                    if k != j {
                        v *= (t - xk) / (&x[j] - xk);
                    }
                }
                v
            })
            .collect()
    }

    /// The node set with node `index` removed (weights recomputed from the positions: the
    /// same positions always give the same weights). Errors: index out of range, removing
    /// the last node.
    pub fn without(&self, index: usize) -> Result<Nodes> {
        if index >= self.len() {
            return Err(Error::IndexOutOfRange {
                what: "level",
                index,
                len: self.len(),
            });
        }
        if self.len() == 1 {
            return Err(Error::TooFewPoints {
                what: "levels",
                got: 0,
                min: 1,
            });
        }
        let mut values = self.values.clone();
        values.remove(index);
        let exact = self.exact.as_ref().map(|e| {
            let mut e = e.clone();
            e.remove(index);
            e
        });
        let (weights, scale) = barycentric_weights(&values)?;
        Ok(Nodes {
            weights,
            scale,
            values,
            exact,
        })
    }

    /// The node set with a node at `value` added; returns it and the new node's index.
    /// Errors: non-finite value, a node already there, [`Nodes::MAX_LEN`] reached, and the
    /// errors of [`Nodes::new`] for the new set.
    pub fn with_node(&self, value: f64) -> Result<(Nodes, usize)> {
        check_len(self.len() + 1)?;
        if !value.is_finite() {
            return Err(Error::NonFinite {
                what: "node",
                index: self.len(),
            });
        }
        let index = self.values.partition_point(|&x| x < value);
        if self.values.get(index) == Some(&value) {
            return Err(Error::InvalidNodes {
                what: "nodes".into(),
                index,
                reason: "a node is already at this position",
            });
        }
        let mut values = self.values.clone();
        values.insert(index, value);
        let exact = self.exact.as_ref().map(|e| {
            let mut e = e.clone();
            e.insert(index, rational_from_f64(value).expect("finite"));
            e
        });
        let (weights, scale) = barycentric_weights(&values)?;
        Ok((
            Nodes {
                weights,
                scale,
                values,
                exact,
            },
            index,
        ))
    }
}

/// `p/q` as an exact rational.
pub(crate) fn ratio(p: i64, q: i64) -> Rational {
    Rational::new(p.into(), q.into())
}

/// Refuses node sets above [`Nodes::MAX_LEN`].
fn check_len(n: usize) -> Result<()> {
    if n > Nodes::MAX_LEN {
        return Err(Error::TooMany {
            what: "nodes in a node set",
            got: n,
            max: Nodes::MAX_LEN,
        });
    }
    Ok(())
}

/// Checks that `values` is non-empty, at most [`Nodes::MAX_LEN`] long, finite and strictly
/// increasing.
pub(crate) fn check_increasing(what: &str, values: &[f64]) -> Result<()> {
    if values.is_empty() {
        return Err(Error::Empty { what: "node set" });
    }
    check_len(values.len())?;
    if let Some(index) = values.iter().position(|x| !x.is_finite()) {
        return Err(Error::InvalidNodes {
            what: what.into(),
            index,
            reason: "not a finite number",
        });
    }
    if let Some(index) = values.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::InvalidNodes {
            what: what.into(),
            index: index + 1,
            reason: if values[index + 1] == values[index] {
                "duplicate node (nodes must be strictly increasing)"
            } else {
                "nodes must be strictly increasing"
            },
        });
    }
    Ok(())
}

/// Barycentric weights 1 / Π_(k≠j) (x_j - x_k), scaled to max |w| = 1, and the scale of the
/// true weights (see [`Nodes`]): products of the differences in double-double with a
/// separate exponent (every factor and partial product brought to [0.5, 1) by exact powers
/// of two), so no product overflows or underflows, whatever the spacing.
fn barycentric_weights(x: &[f64]) -> Result<(Vec<f64>, (f64, i64))> {
    let n = x.len();
    if n == 1 {
        return Ok((vec![1.0], (1.0, 0)));
    }
    // (mantissa, exponent) of p_j = Π_(k≠j) (x_j - x_k), 0.5 <= |mantissa| < 1.
    let mut products: Vec<(Dd, i64)> = Vec::with_capacity(n);
    for j in 0..n {
        let mut p = Dd::from_f64(1.0);
        let mut e: i64 = 0;
        for k in 0..n {
            if k != j {
                let diff = Dd::from_f64(x[j]).add(Dd::from_f64(-x[k]));
                if !diff.hi.is_finite() {
                    // Differences near the end of the f64 range.
                    return Err(too_wide(j));
                }
                // Exact powers of two only where a factor or the product leaves
                // [2^-500, 2^500] (so the product stays normal, however many factors).
                let diff = if (TINY..HUGE).contains(&diff.hi.abs()) {
                    diff
                } else {
                    let (_, de) = split(diff.hi);
                    e += de;
                    scale_dd(diff, -de)
                };
                p = p.mul(diff);
                if !(TINY..HUGE).contains(&p.hi.abs()) {
                    let (_, pe) = split(p.hi);
                    e += pe;
                    p = scale_dd(p, -pe);
                }
            }
        }
        products.push((p, e));
    }
    // Normalized mantissas in [0.5, 1), so that (exponent, mantissa) orders |p_j|.
    for (p, e) in products.iter_mut() {
        let (_, pe) = split(p.hi);
        *e += pe;
        *p = scale_dd(*p, -pe);
    }
    // w_j = 1 / p_j; normalize by the largest |w_j| = the smallest |p_j|.
    let jmin = (0..n)
        .min_by(|&a, &b| {
            let (pa, ea) = products[a];
            let (pb, eb) = products[b];
            ea.cmp(&eb).then(pa.hi.abs().total_cmp(&pb.hi.abs()))
        })
        .expect("n > 1");
    let (mut pmin, emin) = products[jmin];
    if pmin.hi < 0.0 {
        pmin = pmin.mul_f64(-1.0);
    }
    let mut weights = Vec::with_capacity(n);
    for (j, (p, e)) in products.iter().enumerate() {
        // w_j = |p_min| / p_j, with |p_min| / |p_j| in (1/2, 2) times 2^(emin - e) <= 1.
        let w = ldexp(pmin.div(*p).hi, emin - e);
        if !w.is_normal() {
            return Err(Error::InvalidNodes {
                what: "nodes".into(),
                index: j,
                reason: "the barycentric weights of these nodes span more than the f64 range \
                         (nodes extremely unevenly spaced, or too many equispaced: \
                         interpolation through them would amplify rounding beyond 1e300; use \
                         Chebyshev nodes or fewer nodes)",
            });
        }
        weights.push(w);
    }
    // The true weights: w_j / |p_min| = w_j · (1 / |P_min|) · 2^(-emin).
    Ok((weights, (1.0 / pmin.hi, -emin)))
}

/// The range in which the weights' products run without rescaling.
const TINY: f64 = 3.054936363499605e-151; // 2^-500
const HUGE: f64 = 3.273390607896142e150; // 2^500

/// d · 2^k for a double-double (both parts scaled exactly, as long as they stay normal).
fn scale_dd(d: Dd, k: i64) -> Dd {
    Dd {
        hi: ldexp(d.hi, k),
        lo: ldexp(d.lo, k),
    }
}

/// The error of node sets whose differences f64 cannot hold.
fn too_wide(index: usize) -> Error {
    Error::InvalidNodes {
        what: "nodes".into(),
        index,
        reason: "the differences between the nodes overflow f64 (the nodes span too much of \
                 the f64 range; rescale them)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_match_closed_forms() {
        // Chebyshev second kind: w_j ∝ (-1)^j δ_j, δ = 1/2 at the ends.
        let c = Nodes::preset(NodePreset::ChebyshevSecond, 9, -1.0, 1.0).unwrap();
        for (j, w) in c.weights().iter().enumerate() {
            let d = if j == 0 || j == 8 { 0.5 } else { 1.0 };
            let want = if j % 2 == 0 { d } else { -d };
            assert!((w - want).abs() < 1e-14, "{j}: {w} vs {want}");
        }
        // Equispaced: w_j ∝ (-1)^j C(n-1, j).
        let e = Nodes::preset(NodePreset::Equispaced, 5, 0.0, 1.0).unwrap();
        let want = [1.0, -4.0, 6.0, -4.0, 1.0].map(|v: f64| v / 6.0);
        for (w, v) in e.weights().iter().zip(want) {
            assert!((w - v).abs() < 1e-15);
        }
    }

    #[test]
    fn derivatives_near_and_at_nodes() {
        let nodes = Nodes::preset(NodePreset::ChebyshevFirst, 7, 0.0, 2.0).unwrap();
        let p = nodes.cardinal_polynomials();
        let poly = |c: &[Rational], t: f64, order: usize| -> f64 {
            let c: Vec<f64> = c.iter().map(rational_to_f64).collect();
            let mut s = 0.0;
            for (k, ck) in c.iter().enumerate().skip(order) {
                let f: f64 = (0..order).map(|m| (k - m) as f64).product();
                s += ck * f * t.powi((k - order) as i32);
            }
            s
        };
        let n = nodes.len();
        let (mut l, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let x1 = nodes.values()[1];
        for t in [x1, x1 + 1e-12, x1 - 1e-9, 0.37, 1.0, 2.0] {
            nodes.basis_derivatives(t, &mut l, &mut d1, Some(&mut d2));
            for j in 0..n {
                assert!((l[j] - poly(&p[j], t, 0)).abs() < 1e-12, "l {t} {j}");
                assert!((d1[j] - poly(&p[j], t, 1)).abs() < 1e-10, "d1 {t} {j}");
                assert!((d2[j] - poly(&p[j], t, 2)).abs() < 1e-8, "d2 {t} {j}");
            }
        }
    }

    #[test]
    fn remove_and_add_back_is_identical() {
        let nodes = Nodes::preset(NodePreset::ChebyshevFirst, 12, -3.0, 5.0).unwrap();
        let v = nodes.values()[4];
        let (back, index) = nodes.without(4).unwrap().with_node(v).unwrap();
        assert_eq!(index, 4);
        assert_eq!(back, nodes);
    }

    #[test]
    fn rejects_bad_nodes() {
        assert!(matches!(
            Nodes::new(vec![0.0, f64::NAN]),
            Err(Error::InvalidNodes { index: 1, .. })
        ));
        assert!(matches!(
            Nodes::new(vec![0.0, 1.0, 1.0]),
            Err(Error::InvalidNodes { index: 2, .. })
        ));
        assert!(Nodes::new(vec![]).is_err());
        assert!(Nodes::three_point(ratio(3, 2)).is_err());
        assert!(Nodes::preset(NodePreset::Equispaced, 3, 1.0, 0.0).is_err());
    }
}
