//! The ramp function P(t, a, w) of formula (1) of spec/composite-surfaces.md, in f64 and in
//! exact rationals, and the short rationals that turn decimal inputs into exact coefficients.
//!
//! ```
//! use geomkit::compose::ramp;
//! assert_eq!(ramp(-1.0, 0.0, 2.0), 0.0);
//! assert_eq!(ramp(1.0, 0.0, 2.0), 0.5);
//! assert_eq!(ramp(5.0, 0.0, 2.0), 1.0);
//! ```

use crate::exact::{rational_from_f64, rational_to_f64, Rational};
use crate::{Error, Result};
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};

/// P(t, a, w) = (w + |t - a| - |t - a - w|) / (2w), formula (1), exactly as written: 0 for
/// t <= a, 1 for t >= a + w, (t - a)/w in between. Unchecked: w must be > 0 (see
/// [`ramp_checked`]).
#[inline]
pub fn ramp(t: f64, a: f64, w: f64) -> f64 {
    (w + (t - a).abs() - (t - a - w).abs()) / (2.0 * w)
}

/// [`ramp`] with its argument checked. Errors: [`Error::RampWidth`] when w is not finite and
/// > 0, [`Error::NonFinite`] for a non-finite t or a.
///
/// ```
/// use geomkit::compose::ramp_checked;
/// assert!(ramp_checked(0.5, 0.0, 0.0).is_err());
/// assert_eq!(ramp_checked(0.5, 0.0, 1.0).unwrap(), 0.5);
/// ```
pub fn ramp_checked(t: f64, a: f64, w: f64) -> Result<f64> {
    check_width("ramp", w)?;
    for (index, x) in [t, a].into_iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFinite {
                what: "ramp argument",
                index,
            });
        }
    }
    Ok(ramp(t, a, w))
}

/// Checks a ramp width: finite and > 0.
pub(crate) fn check_width(what: &str, w: f64) -> Result<()> {
    if w.is_finite() && w > 0.0 {
        Ok(())
    } else {
        Err(Error::RampWidth {
            what: what.to_string(),
            value: w,
        })
    }
}

/// P(t, a, w) in exact rational arithmetic: exactly 0 at t = a and exactly 1 at t = a + w.
/// Errors: [`Error::RampWidth`] when w <= 0.
///
/// ```
/// use geomkit::compose::ramp_exact;
/// use geomkit::exact::Rational;
/// let q = |n: i64, d: i64| Rational::new(n.into(), d.into());
/// assert_eq!(ramp_exact(&q(13, 10), &q(1, 10), &q(12, 10)).unwrap(), q(1, 1));
/// assert_eq!(ramp_exact(&q(1, 3), &q(0, 1), &q(2, 3)).unwrap(), q(1, 2));
/// ```
pub fn ramp_exact(t: &Rational, a: &Rational, w: &Rational) -> Result<Rational> {
    if !w.is_positive() {
        return Err(Error::RampWidth {
            what: "ramp".into(),
            value: rational_to_f64(w),
        });
    }
    let d = t - a;
    let two = Rational::from_integer(BigInt::from(2));
    Ok((w + d.abs() - (&d - w).abs()) / (two * w))
}

/// The rational with the smallest denominator among the continued-fraction convergents of x
/// that rounds back to exactly x: 0.1 gives 1/10, 2.5 gives 5/2, π gives 245850922/78256779.
/// Decimal inputs thereby become the rationals the user meant, and formulas built from them
/// print with exact coefficients. `None` for NaN or infinity.
///
/// ```
/// use geomkit::compose::simplest_rational;
/// assert_eq!(simplest_rational(0.1).unwrap().to_string(), "1/10");
/// assert_eq!(simplest_rational(-2.5).unwrap().to_string(), "-5/2");
/// ```
pub fn simplest_rational(x: f64) -> Option<Rational> {
    let exact = rational_from_f64(x)?;
    if exact.is_integer() {
        return Some(exact);
    }
    // Convergents h_k / k_k of the continued fraction of |x|.
    let negative = exact.is_negative();
    let mut rest = exact.abs();
    let (mut h0, mut h1) = (BigInt::zero(), BigInt::one());
    let (mut k0, mut k1) = (BigInt::one(), BigInt::zero());
    loop {
        let a = rest.floor().to_integer();
        let h2 = &a * &h1 + &h0;
        let k2 = &a * &k1 + &k0;
        let mut q = Rational::new(h2.clone(), k2.clone());
        if negative {
            q = -q;
        }
        if rational_to_f64(&q) == x {
            return Some(q);
        }
        let frac = &rest - Rational::from_integer(a);
        if frac.is_zero() {
            return Some(exact);
        }
        rest = frac.recip();
        (h0, h1, k0, k1) = (h1, h2, k1, k2);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_is_zero_linear_one() {
        for (t, want) in [(-3.0, 0.0), (1.0, 0.0), (2.0, 0.5), (3.0, 1.0), (9.0, 1.0)] {
            assert_eq!(ramp(t, 1.0, 2.0), want, "t = {t}");
        }
        assert!(ramp_checked(0.0, 0.0, -1.0).is_err());
        assert!(ramp_checked(0.0, 0.0, f64::NAN).is_err());
        assert!(ramp_checked(f64::INFINITY, 0.0, 1.0).is_err());
    }

    #[test]
    fn exact_ramp_hits_knots_exactly() {
        let a = simplest_rational(0.1).unwrap();
        let w = simplest_rational(0.2).unwrap();
        let end = &a + &w;
        assert!(ramp_exact(&a, &a, &w).unwrap().is_zero());
        assert!(ramp_exact(&end, &a, &w).unwrap().is_one());
        assert!(ramp_exact(&a, &a, &Rational::zero()).is_err());
    }

    #[test]
    fn simplest_rationals_round_trip() {
        for x in [
            0.1,
            1.0 / 3.0,
            -7.25,
            1e-7,
            123456.789,
            std::f64::consts::PI,
        ] {
            let q = simplest_rational(x).unwrap();
            assert_eq!(rational_to_f64(&q), x);
        }
        assert_eq!(simplest_rational(1.0 / 3.0).unwrap().to_string(), "1/3");
        assert!(simplest_rational(f64::NAN).is_none());
    }
}
