//! Small numerical kernels shared by the methods: double-double arithmetic for correctly
//! rounded weights and compensated dot products, Gauss quadrature nodes, the Bernstein basis.

/// An unevaluated sum `hi + lo` with `|lo| <= ulp(hi)/2` (double-double, about 106 bits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dd {
    pub hi: f64,
    pub lo: f64,
}

#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

#[inline]
fn quick_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

#[inline]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

impl Dd {
    pub const ZERO: Dd = Dd { hi: 0.0, lo: 0.0 };

    #[inline]
    pub fn from_f64(x: f64) -> Dd {
        Dd { hi: x, lo: 0.0 }
    }

    #[inline]
    pub fn add(self, o: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = quick_two_sum(s, e + t);
        let (hi, lo) = quick_two_sum(s, e + f);
        Dd { hi, lo }
    }

    #[inline]
    pub fn mul(self, o: Dd) -> Dd {
        let (p, e) = two_prod(self.hi, o.hi);
        let e = e + (self.hi * o.lo + self.lo * o.hi);
        let (hi, lo) = quick_two_sum(p, e);
        Dd { hi, lo }
    }

    /// Division by a double (cheaper than [`Dd::div`]).
    #[inline]
    pub fn div_f64(self, b: f64) -> Dd {
        let q1 = self.hi / b;
        let (p, e) = two_prod(q1, b);
        let r = (self.hi - p - e + self.lo) / b;
        let (hi, lo) = quick_two_sum(q1, r);
        Dd { hi, lo }
    }

    #[inline]
    pub fn mul_f64(self, b: f64) -> Dd {
        let (p, e) = two_prod(self.hi, b);
        let (hi, lo) = quick_two_sum(p, e + self.lo * b);
        Dd { hi, lo }
    }

    #[inline]
    pub fn div(self, o: Dd) -> Dd {
        let q1 = self.hi / o.hi;
        let r = self.add(o.mul_f64(-q1));
        let q2 = r.hi / o.hi;
        let r = r.add(o.mul_f64(-q2));
        let q3 = r.hi / o.hi;
        let (hi, lo) = quick_two_sum(q1, q2);
        Dd { hi, lo }.add(Dd::from_f64(q3))
    }

    /// `self + w * x` where `w` is double-double and `x` a double.
    #[inline]
    pub fn fma(self, w: Dd, x: f64) -> Dd {
        let (p, e) = two_prod(w.hi, x);
        let (s, f) = two_sum(self.hi, p);
        let lo = self.lo + e + f + w.lo * x;
        let (hi, lo) = quick_two_sum(s, lo);
        Dd { hi, lo }
    }

    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// Binomial coefficient C(n, k) as f64 (exact while it is below 2^53, correctly rounded
/// to a few ulps beyond).
pub(crate) fn binomial_f64(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    let mut c = Dd::from_f64(1.0);
    for i in 0..k {
        c = c.mul_f64((n - i) as f64).div(Dd::from_f64((i + 1) as f64));
    }
    c.to_f64()
}

/// All Bernstein basis functions b_{n,i}(t), i = 0..=n, written into `out` (length n+1),
/// by the triangular de Casteljau scheme (only convex combinations for t in [0,1]).
pub(crate) fn bernstein_all(n: usize, t: f64, out: &mut [f64]) {
    debug_assert_eq!(out.len(), n + 1);
    let s = 1.0 - t;
    out[0] = 1.0;
    for j in 1..=n {
        let mut saved = 0.0;
        for k in 0..j {
            let temp = out[k];
            out[k] = saved + s * temp;
            saved = t * temp;
        }
        out[j] = saved;
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] with `k` points (exact for polynomials of
/// degree <= 2k-1). Newton iteration on the three-term recurrence.
pub(crate) fn gauss_legendre(k: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; k];
    let mut weights = vec![0.0; k];
    let kf = k as f64;
    for i in 0..k.div_ceil(2) {
        // Tricomi's initial guess for the i-th largest root on [-1, 1].
        let theta = std::f64::consts::PI * (4.0 * i as f64 + 3.0) / (4.0 * kf + 2.0);
        let mut x = (1.0 - (kf - 1.0) / (8.0 * kf * kf * kf)) * theta.cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre_and_derivative(k, x);
            dp = d;
            let dx = p / d;
            x -= dx;
            if dx.abs() <= 1e-16 * x.abs().max(1e-300) {
                let (_, d) = legendre_and_derivative(k, x);
                dp = d;
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        // Map [-1, 1] -> [0, 1]: t = (1 + x) / 2, weight / 2.
        nodes[i] = 0.5 * (1.0 - x);
        nodes[k - 1 - i] = 0.5 * (1.0 + x);
        weights[i] = 0.5 * w;
        weights[k - 1 - i] = 0.5 * w;
    }
    (nodes, weights)
}

fn legendre_and_derivative(k: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if k == 0 {
        return (1.0, 0.0);
    }
    for j in 2..=k {
        let jf = j as f64;
        let p2 = ((2.0 * jf - 1.0) * x * p1 - (jf - 1.0) * p0) / jf;
        p0 = p1;
        p1 = p2;
    }
    let d = k as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

/// Gauss–Chebyshev (first kind) nodes on [0, 1] with equal weights: the quadrature for
/// the weight 1/sqrt(t(1-t)), exact for polynomials of degree <= 2k-1 times that weight.
pub(crate) fn gauss_chebyshev(k: usize) -> (Vec<f64>, Vec<f64>) {
    let nodes = (0..k)
        .map(|q| {
            let x = (std::f64::consts::PI * (2 * q + 1) as f64 / (2 * k) as f64).cos();
            0.5 * (1.0 - x)
        })
        .collect();
    (nodes, vec![std::f64::consts::PI / k as f64; k])
}

/// Largest Euclidean norm among the `dim`-dimensional points stored row-major in `data`.
/// Scaled so that coordinates near the overflow limit (1e200 and up) do not overflow.
pub(crate) fn max_norm(data: &[f64], dim: usize) -> f64 {
    data.chunks_exact(dim).map(norm).fold(0.0, f64::max)
}

/// Euclidean norm, scaled (hypot-like) so that squares cannot overflow or underflow.
pub(crate) fn norm(v: &[f64]) -> f64 {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * v.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// Euclidean distance between two points: the plain root of the sum of squares when that
/// sum neither overflowed nor came near underflow (then it is as accurate as the scaled
/// form, and much faster), else scaled like [`norm`].
pub(crate) fn distance(a: &[f64], b: &[f64]) -> f64 {
    let s = match a.len().min(b.len()) {
        2 => sum_sq::<2>(a[..2].try_into().unwrap(), b[..2].try_into().unwrap()),
        3 => sum_sq::<3>(a[..3].try_into().unwrap(), b[..3].try_into().unwrap()),
        _ => a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum(),
    };
    root_of_sum_sq(s, a, b)
}

/// [`distance`] from each point of `points` (`dim` coordinates each) to the next, into
/// `out` (one fewer than the points): the same values, points of 2 and 3 coordinates in a
/// loop without bounds checks.
pub(crate) fn distances_into(points: &[f64], dim: usize, out: &mut [f64]) {
    fn fixed<const N: usize>(points: &[f64], out: &mut [f64]) {
        let pairs = points.chunks_exact(N).zip(points[N..].chunks_exact(N));
        for (o, (a, b)) in out.iter_mut().zip(pairs) {
            let (a, b): (&[f64; N], &[f64; N]) = (a.try_into().unwrap(), b.try_into().unwrap());
            *o = root_of_sum_sq(sum_sq(a, b), a, b);
        }
    }
    debug_assert_eq!(out.len() + 1, points.len() / dim);
    match dim {
        2 => fixed::<2>(points, out),
        3 => fixed::<3>(points, out),
        _ => {
            for (i, o) in out.iter_mut().enumerate() {
                *o = distance(
                    &points[i * dim..(i + 1) * dim],
                    &points[(i + 1) * dim..(i + 2) * dim],
                );
            }
        }
    }
}

/// Above 2^-900 a square lost to underflow (< 2^-1022) changes a sum of squares by < 2^-122
/// of itself.
const SAFE_SUM_SQ: f64 = f64::from_bits((1023 - 900) << 52);

/// Sum of squared differences of fixed size, unrolled (the same additions in the same order).
#[inline(always)]
fn sum_sq<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    (0..N).fold(0.0, |s, k| s + (a[k] - b[k]) * (a[k] - b[k]))
}

/// The distance from its sum of squares `s`: the plain root, or [`scaled_distance`] when
/// `s` overflowed or came near underflow.
#[inline(always)]
fn root_of_sum_sq(s: f64, a: &[f64], b: &[f64]) -> f64 {
    if s.is_finite() && s >= SAFE_SUM_SQ {
        s.sqrt()
    } else {
        scaled_distance(a, b)
    }
}

/// [`distance`] scaled by the largest coordinate difference (sums of squares that overflow
/// or come near underflow); NaN if a difference is (`f64::max` would drop it).
#[cold]
fn scaled_distance(a: &[f64], b: &[f64]) -> f64 {
    if a.iter().zip(b).any(|(x, y)| (x - y).is_nan()) {
        return f64::NAN;
    }
    let m = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * a
        .iter()
        .zip(b)
        .map(|(x, y)| ((x - y) / m) * ((x - y) / m))
        .sum::<f64>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_neither_overflow_nor_underflow() {
        assert_eq!(distance(&[0.0, 0.0], &[3.0, 4.0]), 5.0);
        assert_eq!(distance(&[1e300, 0.0], &[-2e300, 4e300]), 5e300);
        let tiny = distance(&[0.0, 0.0], &[3e-310, 4e-310]);
        assert!((tiny - 5e-310).abs() <= 1e-323, "{tiny:e}");
        assert_eq!(distance(&[1.0], &[1.0]), 0.0);
        assert!(distance(&[f64::NAN, 0.0], &[0.0, 1.0]).is_nan());
        // One coordinate: the NaN must not be lost as the largest difference.
        assert!(distance(&[f64::NAN], &[0.0]).is_nan());
        assert!(distance(&[f64::INFINITY], &[f64::INFINITY]).is_nan());
    }

    #[test]
    fn binomials_exact_in_range() {
        assert_eq!(binomial_f64(5, 2), 10.0);
        assert_eq!(binomial_f64(50, 25), 126_410_606_437_752.0);
        assert_eq!(binomial_f64(3, 4), 0.0);
    }

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        for k in [1usize, 2, 5, 17, 64, 201] {
            let (x, w) = gauss_legendre(k);
            let deg = 2 * k - 1;
            let integral: f64 = x.iter().zip(&w).map(|(t, w)| w * t.powi(deg as i32)).sum();
            let exact = 1.0 / (deg as f64 + 1.0);
            assert!(
                (integral - exact).abs() < 1e-14,
                "k={k}: {integral} vs {exact}"
            );
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn gauss_chebyshev_integrates_weighted_polynomials() {
        // ∫_0^1 t / sqrt(t(1-t)) dt = π/2.
        let (x, w) = gauss_chebyshev(7);
        let s: f64 = x.iter().zip(&w).map(|(t, w)| w * t).sum();
        assert!((s - std::f64::consts::FRAC_PI_2).abs() < 1e-14);
    }

    #[test]
    fn double_double_division_is_accurate() {
        let third = Dd::from_f64(1.0).div(Dd::from_f64(3.0));
        let back = third.mul_f64(3.0);
        assert!((back.hi - 1.0).abs() + back.lo.abs() < 1e-30);
        let seventh = Dd::from_f64(1.0).div_f64(7.0).mul(Dd::from_f64(7.0));
        assert!((seventh.hi - 1.0).abs() + seventh.lo.abs() < 1e-30);
    }

    #[test]
    fn norms_do_not_overflow() {
        assert!((norm(&[3e200, 4e200]) / 5e200 - 1.0).abs() < 4.0 * f64::EPSILON);
        assert!((distance(&[3e200, 0.0], &[0.0, -4e200]) / 5e200 - 1.0).abs() < 4.0 * f64::EPSILON);
        assert_eq!(max_norm(&[0.0, 0.0, 1e-200, 0.0], 2), 1e-200);
    }

    #[test]
    fn bernstein_partition_of_unity() {
        let mut b = vec![0.0; 11];
        bernstein_all(10, 0.3, &mut b);
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        assert!((b[0] - 0.7f64.powi(10)).abs() < 1e-16);
    }
}
