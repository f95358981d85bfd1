//! Exact piecewise-linear functions of one variable written the paper's way, as a constant
//! plus a combination of |t - c| terms (spec/composite-surfaces.md §1 and §5): what sums of
//! ramps P(t, a, w) with linear pieces collapse to. Polygons and the v-weights of ruled
//! surfaces are built from them, so their formulas print like the paper's cube:
//! `1 - |u| + |u-1| + |u-2| - |u-3|`.

use super::ramp::simplest_rational;
use crate::exact::{rational_to_f64, Rational};
use crate::{Error, Result};
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, Zero};
use std::collections::BTreeMap;

/// Bits of the common denominator above which [`AbsSum::content`] divides by the first
/// coefficient instead.
const CONTENT_BITS: u64 = 256;

/// f(t) = constant + slope·t + Σ_k coef_k |t - knot_k| with exact rational numbers.
///
/// ```
/// use geomkit::compose::AbsSum;
/// use geomkit::exact::Rational;
/// let q = |n: i64| Rational::from_integer(n.into());
/// // P(t, 0, 2) = 1/2 + |t|/4 - |t - 2|/4
/// let p = AbsSum::ramp(&q(0), &q(2)).unwrap();
/// assert_eq!(p.eval(1.0), 0.5);
/// assert_eq!(p.eval_exact(&q(2)), q(1));
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct AbsSum {
    constant: Rational,
    slope: Rational,
    terms: BTreeMap<Rational, Rational>,
}

impl AbsSum {
    /// The constant function c.
    pub fn constant(c: Rational) -> Self {
        AbsSum {
            constant: c,
            ..AbsSum::default()
        }
    }

    /// The ramp P(t, a, w) = 1/2 + |t - a|/(2w) - |t - a - w|/(2w) (formula (1)). Errors:
    /// [`Error::RampWidth`] when w <= 0.
    pub fn ramp(a: &Rational, w: &Rational) -> Result<Self> {
        if !w.is_positive() {
            return Err(Error::RampWidth {
                what: "ramp".into(),
                value: rational_to_f64(w),
            });
        }
        let half = Rational::new(BigInt::one(), BigInt::from(2));
        let c = Rational::one() / (w * Rational::from_integer(BigInt::from(2)));
        let mut f = AbsSum::constant(half);
        f.add_term(a.clone(), c.clone());
        f.add_term(a + w, -c);
        Ok(f)
    }

    /// The composite linear function through (knots\[i\], values\[i\]) by the 1-D formula of §5:
    /// values\[0\] + Σ_i (values\[i+1\] - values\[i\]) P(t, knots\[i\], knots\[i+1\] - knots\[i\]);
    /// constant beyond the ends. Errors: lengths differ or below 1, knots not increasing.
    pub fn through(knots: &[Rational], values: &[Rational]) -> Result<Self> {
        if knots.len() != values.len() {
            return Err(Error::PatchCount {
                what: "values for the knots of a polyline".into(),
                expected: knots.len(),
                got: values.len(),
            });
        }
        let first = values.first().ok_or(Error::Empty {
            what: "polyline values",
        })?;
        let mut f = AbsSum::constant(first.clone());
        for i in 0..knots.len() - 1 {
            let w = &knots[i + 1] - &knots[i];
            if !w.is_positive() {
                return Err(Error::InvalidKnots {
                    index: i + 1,
                    reason: "knots must be strictly increasing",
                });
            }
            let jump = &values[i + 1] - &values[i];
            if !jump.is_zero() {
                f.add_scaled(&AbsSum::ramp(&knots[i], &w)?, &jump);
            }
        }
        Ok(f)
    }

    /// Adds coef·|t - knot|, dropping the term if it cancels: O(log n) (a `retain` over all
    /// terms here made every polygon's formula quadratic in its vertex count).
    fn add_term(&mut self, knot: Rational, coef: Rational) {
        use std::collections::btree_map::Entry;
        match self.terms.entry(knot) {
            Entry::Vacant(e) => {
                if !coef.is_zero() {
                    e.insert(coef);
                }
            }
            Entry::Occupied(mut e) => {
                *e.get_mut() += coef;
                if e.get().is_zero() {
                    e.remove();
                }
            }
        }
    }

    /// self += factor · other.
    pub fn add_scaled(&mut self, other: &AbsSum, factor: &Rational) {
        self.constant += &other.constant * factor;
        self.slope += &other.slope * factor;
        for (k, c) in &other.terms {
            self.add_term(k.clone(), c * factor);
        }
    }

    /// factor · self.
    pub fn scaled(&self, factor: &Rational) -> AbsSum {
        let mut out = AbsSum::default();
        out.add_scaled(self, factor);
        out
    }

    /// f(a + b t): the same function after the change of variable t -> a + b t (b > 0), so
    /// |a + b t - c| = b |t - (c - a)/b|.
    pub fn reparametrized(&self, a: &Rational, b: &Rational) -> AbsSum {
        let mut out = AbsSum::constant(&self.constant + &self.slope * a);
        out.slope = &self.slope * b;
        for (k, c) in &self.terms {
            out.add_term((k - a) / b, c * b);
        }
        out
    }

    /// The constant term.
    pub fn constant_term(&self) -> &Rational {
        &self.constant
    }

    /// The coefficient of t.
    pub fn slope(&self) -> &Rational {
        &self.slope
    }

    /// The |t - knot| terms as (knot, coefficient), knots increasing.
    pub fn terms(&self) -> impl Iterator<Item = (&Rational, &Rational)> {
        self.terms.iter()
    }

    /// Whether f is constant.
    pub fn is_constant(&self) -> bool {
        self.slope.is_zero() && self.terms.is_empty()
    }

    /// Whether f is identically zero.
    pub fn is_zero(&self) -> bool {
        self.is_constant() && self.constant.is_zero()
    }

    /// f(t) in f64 (coefficients rounded once).
    pub fn eval(&self, t: f64) -> f64 {
        let mut acc = rational_to_f64(&self.constant) + rational_to_f64(&self.slope) * t;
        for (k, c) in &self.terms {
            acc += rational_to_f64(c) * (t - rational_to_f64(k)).abs();
        }
        acc
    }

    /// f(t) exactly.
    pub fn eval_exact(&self, t: &Rational) -> Rational {
        let mut acc = &self.constant + &self.slope * t;
        for (k, c) in &self.terms {
            acc += c * (t - k).abs();
        }
        acc
    }

    /// f = content · primitive, the primitive part with coprime integer coefficients and its
    /// first term (constant, then t, then the |t - c| by increasing c) positive. The zero
    /// function gives (0, 0). When the coefficients' denominators have a common multiple of
    /// more than 256 bits, the primitive part has first coefficient 1 instead (f and c·f
    /// still share it): linear work instead of cubic.
    pub fn content(&self) -> (Rational, AbsSum) {
        let coefs: Vec<&Rational> = std::iter::once(&self.constant)
            .chain(std::iter::once(&self.slope))
            .chain(self.terms.values())
            .filter(|c| !c.is_zero())
            .collect();
        let Some(first) = coefs.first() else {
            return (Rational::zero(), AbsSum::default());
        };
        let mut num = BigInt::zero();
        let mut den = BigInt::one();
        for c in &coefs {
            num = num.gcd(c.numer());
            den = den.lcm(c.denom());
            if den.bits() > CONTENT_BITS {
                // Unrelated denominators (a polygon's rounded cosines): the lcm would grow
                // with every term and each division by it cost as much, cubic in the count.
                // The first coefficient is a content as canonical for the grouping.
                let content = (*first).clone();
                return (content.clone(), self.scaled(&content.recip()));
            }
        }
        let mut content = Rational::new(num, den);
        if first.is_negative() {
            content = -content;
        }
        let inv = content.recip();
        (content, self.scaled(&inv))
    }
}

/// The exact rational of a finite f64 input, chosen short ([`simplest_rational`]).
pub(crate) fn exact(what: &'static str, index: usize, x: f64) -> Result<Rational> {
    simplest_rational(x).ok_or(Error::NonFinite { what, index })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::new(n.into(), d.into())
    }

    #[test]
    fn square_side_collapses_to_the_papers_coordinate() {
        // x of the square (1,1), (-1,1), (-1,-1), (1,-1), (1,1) at u = 0..4.
        let knots: Vec<Rational> = (0..5).map(|k| q(k, 1)).collect();
        let xs = [1, -1, -1, 1, 1].map(|x| q(x, 1));
        let f = AbsSum::through(&knots, &xs).unwrap();
        assert_eq!(*f.constant_term(), q(1, 1));
        let terms: Vec<(Rational, Rational)> =
            f.terms().map(|(k, c)| (k.clone(), c.clone())).collect();
        assert_eq!(
            terms,
            vec![
                (q(0, 1), q(-1, 1)),
                (q(1, 1), q(1, 1)),
                (q(2, 1), q(1, 1)),
                (q(3, 1), q(-1, 1))
            ]
        );
        for (k, x) in xs.iter().enumerate() {
            assert_eq!(f.eval_exact(&q(k as i64, 1)), *x);
        }
    }

    #[test]
    fn content_and_reparametrization() {
        let f = AbsSum::ramp(&q(0, 1), &q(1, 1)).unwrap().scaled(&q(1, 1));
        let mut g = f.clone();
        g.add_scaled(&AbsSum::ramp(&q(2, 1), &q(1, 1)).unwrap(), &q(-1, 1));
        let (c, prim) = g.content();
        assert_eq!(c, q(1, 2));
        assert!(prim.constant_term().is_zero());
        assert_eq!(prim.terms().count(), 4);
        let r = f.reparametrized(&q(1, 1), &q(2, 1));
        for t in [-1.0, 0.0, -0.25, 0.5] {
            assert_eq!(r.eval(t), f.eval(1.0 + 2.0 * t));
        }
        assert!(AbsSum::ramp(&q(0, 1), &q(0, 1)).is_err());
    }
}
