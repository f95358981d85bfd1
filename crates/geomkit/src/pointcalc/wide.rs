//! Numbers with an exponent of their own: x = m · 2^e with an f64 mantissa and an i64
//! exponent, for the steps of the point calculus whose intermediate values (products of
//! node differences, shares far outside the nodes, sums of huge source values) leave the
//! f64 range while the result may not. Scaling by powers of two is exact, so a result
//! computed this way has the same rounding as the plain f64 computation would have had
//! without the overflow.

/// 2^k for -1022 <= k <= 1023 (exact, normal).
pub(crate) fn pow2(k: i64) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// x = m · 2^e with 0.5 <= |m| < 1; (x, 0) for zero and non-finite x.
pub(crate) fn split(x: f64) -> (f64, i64) {
    if x == 0.0 || !x.is_finite() {
        return (x, 0);
    }
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i64;
    if exponent == 0 {
        // Subnormal: scale into the normal range first (exact).
        let (m, e) = split(x * pow2(64));
        return (m, e - 64);
    }
    let m = f64::from_bits((bits & !(0x7ff << 52)) | (1022 << 52));
    (m, exponent - 1022)
}

/// The binary exponent e of x = m · 2^e, 0.5 <= |m| < 1 (0 for zero).
pub(crate) fn exponent(x: f64) -> i64 {
    split(x).1
}

/// m · 2^e rounded to f64 (once): ±infinity above the f64 range, gradual underflow below.
pub(crate) fn ldexp(m: f64, e: i64) -> f64 {
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let (m, me) = split(m);
    let e = me.saturating_add(e);
    if e > 1024 {
        return m.signum() * f64::INFINITY;
    }
    if e < -1080 {
        return m.signum() * 0.0;
    }
    if e >= -1021 {
        // 0.5 <= |m| < 1: m · 2 · 2^(e - 1), both factors exact, one rounding (none here).
        (m * 2.0) * pow2(e - 1)
    } else {
        // Subnormal result: one rounding, in the last step.
        (m * pow2(e + 600)) * pow2(-600)
    }
}

/// out = 2^e_w Σ_i w_i p_i (points `p` row-major, `out.len()` numbers each) with nothing
/// overflowing on the way: the points scaled by a power of two to |p| < 1 first, the sum
/// scaled back last (±infinity only where the result itself is beyond f64).
pub(crate) fn combine_wide(weights: &[f64], e_w: i64, points: &[f64], out: &mut [f64]) {
    let dim = out.len();
    let largest = points.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let e_p = exponent(largest);
    out.fill(0.0);
    for (w, p) in weights.iter().zip(points.chunks_exact(dim)) {
        for (o, x) in out.iter_mut().zip(p) {
            *o += w * ldexp(*x, -e_p);
        }
    }
    for o in out.iter_mut() {
        *o = ldexp(*o, e_w + e_p);
    }
}

/// A short text of a number for messages: plain between 1e-5 and 1e16, else in
/// e-notation ("1e308", not 309 digits).
pub(crate) fn short(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_and_ldexp_are_exact() {
        for x in [
            1.0,
            -3.5,
            f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            -1e-310,
            0.1,
            1e308,
        ] {
            let (m, e) = split(x);
            assert!((0.5..1.0).contains(&m.abs()), "{x}: {m}");
            assert_eq!(ldexp(m, e), x);
        }
        assert_eq!(ldexp(0.75, 1025), f64::INFINITY);
        assert_eq!(ldexp(-0.75, 1025), f64::NEG_INFINITY);
        assert_eq!(ldexp(0.5, 1024), 2f64.powi(1023));
        assert_eq!(ldexp(0.5, -1073), 5e-324);
        assert_eq!(ldexp(0.5, -2000), 0.0);
        assert_eq!(ldexp(3.0, i64::MAX), f64::INFINITY);
        assert_eq!(short(1e308), "1e308");
        assert_eq!(short(2.5), "2.5");
    }
}
