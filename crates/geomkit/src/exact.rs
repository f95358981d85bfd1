//! Exact rational arithmetic for the paper's matrices (spec/bezier-order.md, (4), (5), (8)-(10)).
//!
//! The matrices H_n, H_n^-1, the elevation matrices and the unified degree-change matrix
//! H_n E_(n+1,n'+1) H_n'^-1 are computed exactly as [`BigRational`]s; [`ExactMatrix::to_f64`]
//! rounds each entry once (correctly rounded).
//!
//! ```
//! use geomkit::exact::degree_change_matrix;
//! use num_rational::BigRational;
//! let k = degree_change_matrix(2, 3);
//! assert_eq!(k.get(1, 1), &BigRational::new(2.into(), 3.into()));
//! ```

use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// Exact rational number used throughout.
pub type Rational = BigRational;

/// The big integer type of [`Rational`]'s numerator and denominator.
pub use num_bigint::BigInt;

/// A dense matrix of exact rationals, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactMatrix {
    rows: usize,
    cols: usize,
    data: Vec<Rational>,
}

impl ExactMatrix {
    /// The rows × cols zero matrix.
    pub fn zeros(rows: usize, cols: usize) -> Self {
        ExactMatrix {
            rows,
            cols,
            data: vec![Rational::zero(); rows * cols],
        }
    }

    /// Builds a matrix from rows of (numerator, denominator) pairs. Errors: ragged rows, a
    /// zero denominator.
    pub fn from_rows<T: Into<BigInt> + Clone>(rows: &[Vec<(T, T)>]) -> crate::Result<Self> {
        let r = rows.len();
        let c = rows.first().map_or(0, Vec::len);
        let mut m = ExactMatrix::zeros(r, c);
        for (i, row) in rows.iter().enumerate() {
            if row.len() != c {
                return Err(crate::Error::RaggedNet {
                    row: i,
                    expected: c,
                    got: row.len(),
                });
            }
            for (j, (p, q)) in row.iter().enumerate() {
                let q: BigInt = q.clone().into();
                if q.is_zero() {
                    return Err(crate::Error::InvalidOption {
                        option: "matrix entry",
                        reason: "zero denominator",
                    });
                }
                m.data[i * c + j] = Rational::new(p.clone().into(), q);
            }
        }
        Ok(m)
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Entry (i, j).
    pub fn get(&self, i: usize, j: usize) -> &Rational {
        &self.data[i * self.cols + j]
    }

    fn set(&mut self, i: usize, j: usize, v: Rational) {
        self.data[i * self.cols + j] = v;
    }

    /// Matrix product; `None` when the inner dimensions differ.
    pub fn mul(&self, other: &ExactMatrix) -> Option<ExactMatrix> {
        if self.cols != other.rows {
            return None;
        }
        let mut out = ExactMatrix::zeros(self.rows, other.cols);
        for i in 0..self.rows {
            for k in 0..self.cols {
                let a = self.get(i, k);
                if a.is_zero() {
                    continue;
                }
                for j in 0..other.cols {
                    let b = other.get(k, j);
                    if !b.is_zero() {
                        let v = out.get(i, j) + a * b;
                        out.set(i, j, v);
                    }
                }
            }
        }
        Some(out)
    }

    /// Each entry rounded once to the nearest f64, row-major.
    pub fn to_f64(&self) -> Vec<f64> {
        self.data.iter().map(rational_to_f64).collect()
    }
}

impl std::fmt::Display for ExactMatrix {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for i in 0..self.rows {
            let row: Vec<String> = (0..self.cols).map(|j| self.get(i, j).to_string()).collect();
            writeln!(f, "[{}]", row.join(" "))?;
        }
        Ok(())
    }
}

/// Correctly rounded f64 of an exact rational (±inf if out of range).
pub fn rational_to_f64(q: &Rational) -> f64 {
    q.to_f64().unwrap_or(if q.is_negative() {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    })
}

/// The exact value of a finite f64 (a dyadic rational). `None` for NaN or infinity.
pub fn rational_from_f64(x: f64) -> Option<Rational> {
    Rational::from_float(x)
}

/// Exact binomial coefficient C(n, k) (0 when k > n).
pub fn binomial(n: usize, k: usize) -> BigInt {
    if k > n {
        return BigInt::zero();
    }
    let k = k.min(n - k);
    let mut c = BigInt::one();
    for i in 0..k {
        c = c * BigInt::from(n - i) / BigInt::from(i + 1);
    }
    c
}

/// H_n of formula (4): h_ij = (-1)^(j-i) C(n,j) C(j,i) for i <= j, so that B_n(t) = H_n T_n(t)
/// and S_n = U_n H_n (5).
pub fn h_matrix(n: usize) -> ExactMatrix {
    let mut h = ExactMatrix::zeros(n + 1, n + 1);
    for j in 0..=n {
        let cnj = binomial(n, j);
        for i in 0..=j {
            let mut v = &cnj * binomial(j, i);
            if (j - i) % 2 == 1 {
                v = -v;
            }
            h.set(i, j, Rational::from_integer(v));
        }
    }
    h
}

/// The closed-form inverse of H_n: (H_n^-1)_ij = C(j,i) / C(n,i) for i <= j.
pub fn h_inverse(n: usize) -> ExactMatrix {
    let mut h = ExactMatrix::zeros(n + 1, n + 1);
    for i in 0..=n {
        let cni = binomial(n, i);
        for j in i..=n {
            h.set(i, j, Rational::new(binomial(j, i), cni.clone()));
        }
    }
    h
}

/// E_(rows, cols): zeros with ones on the main diagonal.
pub fn e_matrix(rows: usize, cols: usize) -> ExactMatrix {
    let mut e = ExactMatrix::zeros(rows, cols);
    for i in 0..rows.min(cols) {
        e.set(i, i, Rational::one());
    }
    e
}

/// The unified degree-change matrix of formula (10), exactly as the paper writes it:
/// `H_n E_(n+1,n'+1) H_(n')^-1`, an (n+1)×(n'+1) matrix with U_(n') = U_n · matrix.
///
/// For n' >= n this is the elevation matrix (8), equal to the closed form
/// C(n,i) C(n'-n, j-i) / C(n',j). For n' < n it is exact only when the degree defect is at
/// least n - n'; otherwise applying it **truncates the power form at t = 0** (drops the
/// power coefficients s_(n'+1..n)), which is not a good approximation — use
/// [`crate::bezier::BezierCurve::reduce_degree_approx`] for that.
pub fn degree_change_matrix(n: usize, n_new: usize) -> ExactMatrix {
    let prod = h_matrix(n)
        .mul(&e_matrix(n + 1, n_new + 1))
        .and_then(|m| m.mul(&h_inverse(n_new)));
    prod.expect("dimensions agree by construction")
}

/// Closed-form elevation matrix (8): (K)_ij = C(n,i) C(n'-n, j-i) / C(n',j), (n+1)×(n'+1).
/// Errors with [`crate::Error::InvalidDegree`] when n' < n.
pub fn elevation_matrix(n: usize, n_new: usize) -> crate::Result<ExactMatrix> {
    if n_new < n {
        return Err(crate::Error::InvalidDegree {
            degree: n,
            requested: n_new,
            reason: "elevation needs a degree >= the current one",
        });
    }
    let mut k = ExactMatrix::zeros(n + 1, n_new + 1);
    for j in 0..=n_new {
        let den = binomial(n_new, j);
        for i in j.saturating_sub(n_new - n)..=n.min(j) {
            k.set(
                i,
                j,
                Rational::new(binomial(n, i) * binomial(n_new - n, j - i), den.clone()),
            );
        }
    }
    Ok(k)
}

/// A Bézier curve with exact rational control points, for exact results on request.
///
/// ```
/// use geomkit::exact::ExactBezierCurve;
/// // The paper's Example 2: a formally quintic curve of real degree 3.
/// let c = ExactBezierCurve::from_f64(2, &[10.,0., 22.,6., 19.,12., 11.,15., 8.,12., 20.,0.]).unwrap();
/// assert_eq!(c.real_degree(), 3);
/// let cubic = c.change_degree(3).unwrap();
/// assert_eq!(cubic.change_degree(5).unwrap(), c);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ExactBezierCurve {
    dim: usize,
    points: Vec<Rational>,
}

impl ExactBezierCurve {
    /// A curve from exact points stored row-major (`dim` coordinates per point).
    pub fn new(dim: usize, points: Vec<Rational>) -> crate::Result<Self> {
        if dim == 0 {
            return Err(crate::Error::ZeroDimension {
                what: "control points",
            });
        }
        if points.is_empty() {
            return Err(crate::Error::Empty {
                what: "control points",
            });
        }
        if !points.len().is_multiple_of(dim) {
            return Err(crate::Error::DimensionMismatch {
                what: "control point",
                index: points.len() / dim,
                expected: dim,
                got: points.len() % dim,
            });
        }
        Ok(ExactBezierCurve { dim, points })
    }

    /// The exact values of f64 control points (each f64 is a dyadic rational).
    pub fn from_f64(dim: usize, points: &[f64]) -> crate::Result<Self> {
        let exact = points
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                rational_from_f64(x).ok_or(crate::Error::NonFinite {
                    what: "control point",
                    index: k / dim.max(1),
                })
            })
            .collect::<crate::Result<Vec<_>>>()?;
        Self::new(dim, exact)
    }

    /// Formal degree n (number of control points minus one).
    pub fn degree(&self) -> usize {
        self.points.len() / self.dim - 1
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Control points, row-major.
    pub fn points(&self) -> &[Rational] {
        &self.points
    }

    /// Power coefficients S_n = U_n H_n (5), row-major: coefficient j of coordinate k is at
    /// `j * dim + k`.
    pub fn to_power(&self) -> Vec<Rational> {
        let n = self.degree();
        let h = h_matrix(n);
        let mut s = vec![Rational::zero(); self.points.len()];
        for j in 0..=n {
            for i in 0..=j {
                let hij = h.get(i, j);
                for k in 0..self.dim {
                    s[j * self.dim + k] += &self.points[i * self.dim + k] * hij;
                }
            }
        }
        s
    }

    /// The real degree n*: the formal degree minus the number of zero power coefficients
    /// at the right end of S_n (exact, so no tolerance is needed).
    pub fn real_degree(&self) -> usize {
        let s = self.to_power();
        (0..=self.degree())
            .rev()
            .find(|&j| {
                s[j * self.dim..(j + 1) * self.dim]
                    .iter()
                    .any(|x| !x.is_zero())
            })
            .unwrap_or(0)
    }

    /// Applies the unified formula (10) exactly. Errors when n' < real degree (the formula
    /// would then truncate the power form; see [`Self::truncate_power_form`]).
    pub fn change_degree(&self, n_new: usize) -> crate::Result<Self> {
        let n = self.degree();
        if n_new < n {
            let real = self.real_degree();
            if n_new < real {
                return Err(crate::Error::DegreeDefectTooSmall {
                    real_degree: real,
                    requested: n_new,
                    defect: n - real,
                });
            }
        }
        Ok(self.truncate_power_form(n_new))
    }

    /// Formula (10) applied without any check: for n' below the real degree this is the
    /// truncation of the power form at t = 0 (a Taylor truncation, not a best approximation).
    pub fn truncate_power_form(&self, n_new: usize) -> Self {
        // For elevation the closed form (8) equals formula (10) and costs O(n n') entries.
        let n = self.degree();
        let m = if n_new >= n {
            elevation_matrix(n, n_new).expect("n' >= n here")
        } else {
            degree_change_matrix(n, n_new)
        };
        let mut out = vec![Rational::zero(); (n_new + 1) * self.dim];
        for i in 0..m.rows() {
            for j in 0..m.cols() {
                let mij = m.get(i, j);
                if mij.is_zero() {
                    continue;
                }
                for k in 0..self.dim {
                    out[j * self.dim + k] += &self.points[i * self.dim + k] * mij;
                }
            }
        }
        ExactBezierCurve {
            dim: self.dim,
            points: out,
        }
    }

    /// Control points rounded once to f64, row-major.
    pub fn to_f64(&self) -> Vec<f64> {
        self.points.iter().map(rational_to_f64).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(p: i64, d: i64) -> Rational {
        Rational::new(p.into(), d.into())
    }

    #[test]
    fn h_times_inverse_is_identity() {
        for n in [0usize, 1, 5, 12] {
            let p = h_matrix(n).mul(&h_inverse(n)).unwrap();
            assert_eq!(p, e_matrix(n + 1, n + 1));
        }
    }

    #[test]
    fn unified_formula_equals_closed_form_for_elevation() {
        for n in 0..7 {
            for m in n..n + 6 {
                assert_eq!(
                    degree_change_matrix(n, m),
                    elevation_matrix(n, m).unwrap(),
                    "{n}->{m}"
                );
            }
        }
    }

    #[test]
    fn example2_degree_change_matrix() {
        let m = degree_change_matrix(5, 3);
        let want = [
            [q(1, 1), q(-2, 3), q(1, 1), q(-4, 1)],
            [q(0, 1), q(5, 3), q(-10, 3), q(15, 1)],
            [q(0, 1), q(0, 1), q(10, 3), q(-20, 1)],
            [q(0, 1), q(0, 1), q(0, 1), q(10, 1)],
            [q(0, 1), q(0, 1), q(0, 1), q(0, 1)],
            [q(0, 1), q(0, 1), q(0, 1), q(0, 1)],
        ];
        for i in 0..6 {
            for j in 0..4 {
                assert_eq!(m.get(i, j), &want[i][j], "({i},{j})");
            }
        }
    }

    #[test]
    fn rounding_is_correct() {
        assert_eq!(rational_to_f64(&q(1, 3)), 1.0 / 3.0);
        assert_eq!(
            rational_from_f64(0.1).map(|r| rational_to_f64(&r)),
            Some(0.1)
        );
        assert!(rational_from_f64(f64::NAN).is_none());
    }
}
