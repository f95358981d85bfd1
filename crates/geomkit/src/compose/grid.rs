//! The knots of one direction of a composite grid: validation and cell location (one
//! division for uniform knots, a binary search otherwise).

use crate::{Error, Result};

/// Strictly increasing knots x_0 < ... < x_n of one grid direction.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Axis {
    knots: Vec<f64>,
    /// (x_0, step) when the knots are uniform within rounding.
    uniform: Option<(f64, f64)>,
}

impl Axis {
    /// Checks the knots: at least 2, finite, strictly increasing.
    pub fn new(what: &'static str, knots: Vec<f64>) -> Result<Self> {
        check_increasing(what, &knots)?;
        let n = knots.len() - 1;
        let (a, b) = (knots[0], knots[n]);
        let step = (b - a) / n as f64;
        let tol = 4.0 * f64::EPSILON * a.abs().max(b.abs());
        let uniform = knots
            .iter()
            .enumerate()
            .all(|(i, &k)| (k - (a + i as f64 * step)).abs() <= tol)
            .then_some((a, step));
        Ok(Axis { knots, uniform })
    }

    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Number of cells n.
    pub fn cells(&self) -> usize {
        self.knots.len() - 1
    }

    /// The cell i holding x (clamped to 0..n) and the local coordinate (x - x_i)/(x_(i+1) - x_i)
    /// clamped to [0, 1]: points outside map onto the boundary, like P does.
    #[inline]
    pub fn locate(&self, x: f64) -> (usize, f64) {
        let k = &self.knots;
        let n = k.len() - 1;
        let mut i = match self.uniform {
            Some((a, h)) => {
                let f = ((x - a) / h).floor();
                if f.is_nan() || f < 0.0 {
                    0
                } else {
                    (f as usize).min(n - 1)
                }
            }
            None => k[1..n].partition_point(|&t| t <= x),
        };
        if i > 0 && x < k[i] {
            i -= 1;
        } else if i + 1 < n && x >= k[i + 1] {
            i += 1;
        }
        let s = ((x - k[i]) / (k[i + 1] - k[i])).clamp(0.0, 1.0);
        (i, s)
    }
}

/// A number for a message: plain when short, else in scientific notation (Rust prints
/// 1.7e308 with all its 309 digits).
pub(crate) fn show(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// b - a for a message, also where it overflows f64 (3.4e308 for 1.7e308 - -1.7e308).
fn difference(b: f64, a: f64) -> String {
    let d = b - a;
    if d.is_finite() {
        return show(d);
    }
    // A tenth of it fits: its mantissa, and the exponent one higher.
    let tenth = format!("{:e}", b / 10.0 - a / 10.0);
    match tenth.split_once('e').map(|(m, e)| (m, e.parse::<i32>())) {
        Some((m, Ok(e))) => format!("{m}e{}", e + 1),
        _ => tenth,
    }
}

/// The largest span x_n - x_0 of the knots of one direction: every difference |x - x_i| of
/// two points of the domain, and every 2w of a ramp P(x, x_i, w), then stays finite.
pub const MAX_KNOT_SPAN: f64 = f64::MAX / 2.0;

/// The smallest width x_(i+1) - x_i of a knot interval: the smallest normal f64, so that
/// the ramp's 1/(2w) stays finite and its local coordinate keeps full precision.
pub const MIN_KNOT_WIDTH: f64 = f64::MIN_POSITIVE;

/// At least 2 finite, strictly increasing knots, spanning at most [`MAX_KNOT_SPAN`], each
/// interval at least [`MIN_KNOT_WIDTH`] wide; errors name the first bad knot.
pub(crate) fn check_increasing(what: &'static str, knots: &[f64]) -> Result<()> {
    if knots.len() < 2 {
        return Err(Error::TooFewPoints {
            what,
            got: knots.len(),
            min: 2,
        });
    }
    if let Some(index) = knots.iter().position(|k| !k.is_finite()) {
        return Err(Error::NonFinite { what, index });
    }
    if let Some(index) = knots.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::InvalidKnots {
            index: index + 1,
            reason: "knots must be strictly increasing",
        });
    }
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    if b - a > MAX_KNOT_SPAN {
        return Err(Error::Overflow {
            what: format!("{what} from {} to {}", show(a), show(b)),
            step: format!(
                "their span {} is above f64::MAX/2 = {MAX_KNOT_SPAN:.3e} (differences of points \
                 in it would overflow f64)",
                difference(b, a)
            ),
        });
    }
    if let Some(i) = knots.windows(2).position(|w| w[1] - w[0] < MIN_KNOT_WIDTH) {
        return Err(Error::Overflow {
            what: format!(
                "{what} {i} and {} ({} and {})",
                i + 1,
                show(knots[i]),
                show(knots[i + 1])
            ),
            step: format!(
                "their width {:e} is below {MIN_KNOT_WIDTH:.3e}, the smallest normal f64 (the \
                 ramp's 1/(2w) would overflow f64)",
                knots[i + 1] - knots[i]
            ),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locates_cells_uniform_and_not() {
        let a = Axis::new("knots", vec![0.0, 0.1, 0.2, 0.30000000000000004]).unwrap();
        assert!(a.uniform.is_some());
        assert_eq!(a.locate(-1.0), (0, 0.0));
        assert_eq!(a.locate(0.1).0, 1);
        assert_eq!(a.locate(0.2).0, 2);
        assert_eq!(a.locate(5.0), (2, 1.0));
        let b = Axis::new("knots", vec![0.0, 1.0, 5.0]).unwrap();
        assert!(b.uniform.is_none());
        assert_eq!(b.locate(3.0), (1, 0.5));
        assert_eq!(b.locate(1.0), (1, 0.0));
        assert!(Axis::new("knots", vec![0.0, 0.0]).is_err());
        assert!(Axis::new("knots", vec![0.0]).is_err());
        assert!(Axis::new("knots", vec![0.0, f64::NAN]).is_err());
    }
}
