//! Banded linear systems in O(n): LU with partial pivoting for a band of kl sub- and ku
//! super-diagonals (LAPACK gbtrf/gbtrs in spirit), and cyclic systems by Sherman–Morrison.
//! Right-hand sides are row-major n × `cols` (one column per coordinate). No dense matrix
//! is ever formed.

use crate::par::*;
use crate::{Error, Result};

/// An n × n band matrix with `kl` sub- and `ku` super-diagonals. Row i stores columns
/// i-kl ..= i+ku+kl (the extra kl for fill-in from row exchanges).
#[derive(Debug, Clone)]
pub(crate) struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    width: usize,
    data: Vec<f64>,
}

impl BandMatrix {
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        let width = 2 * kl + ku + 1;
        BandMatrix {
            n,
            kl,
            ku,
            width,
            data: vec![0.0; n * width],
        }
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        debug_assert!(
            j + self.kl >= i && j <= i + self.ku + self.kl,
            "({i},{j}) outside band"
        );
        i * self.width + (j + self.kl - i)
    }

    /// Sets entry (i, j), which must lie within the band.
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            j + self.kl >= i && j <= i + self.ku,
            "({i},{j}) outside band"
        );
        let k = self.idx(i, j);
        self.data[k] = v;
    }

    /// Adds v to entry (i, j), which must lie within the band.
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            j + self.kl >= i && j <= i + self.ku,
            "({i},{j}) outside band"
        );
        let k = self.idx(i, j);
        self.data[k] += v;
    }

    /// Solves A X = B in place (B row-major n × cols), destroying A. Errors when A is
    /// singular to working precision.
    #[cfg(test)]
    pub fn solve(self, b: &mut [f64], cols: usize) -> Result<()> {
        self.factor()?.solve(b, cols);
        Ok(())
    }

    /// LU factorization with partial pivoting (row exchanges within the band). Errors when A
    /// is singular to working precision.
    pub fn factor(self) -> Result<BandLu> {
        let rel = f64::EPSILON * self.n as f64 * 1e-3;
        self.factor_below(rel)
    }

    /// [`BandMatrix::factor`] refusing pivots at most `rel` times the largest entry (0: only
    /// zero pivots; for callers that judge the solution by iterative refinement instead).
    pub fn factor_below(mut self, rel: f64) -> Result<BandLu> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let scale = self.data.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let tiny = scale * rel;
        let mut pivots = Vec::with_capacity(n);
        for k in 0..n {
            let last = (k + kl).min(n - 1);
            let mut piv = k;
            let mut best = self.data[self.idx(k, k)].abs();
            for r in k + 1..=last {
                let v = self.data[self.idx(r, k)].abs();
                if v > best {
                    best = v;
                    piv = r;
                }
            }
            if best.is_nan() || best <= tiny {
                return Err(Error::Numerical {
                    operation: "banded solve",
                    reason: "the interpolation system is singular",
                });
            }
            let jmax = (k + ku + kl).min(n - 1);
            if piv != k {
                for j in k..=jmax {
                    let (a, c) = (self.idx(k, j), self.idx(piv, j));
                    self.data.swap(a, c);
                }
            }
            pivots.push(piv);
            let pivot = self.data[self.idx(k, k)];
            for r in k + 1..=last {
                let at = self.idx(r, k);
                let l = self.data[at] / pivot;
                // Keep the multiplier where the eliminated entry was.
                self.data[at] = l;
                if l == 0.0 {
                    continue;
                }
                for j in k + 1..=jmax {
                    let v = self.data[self.idx(k, j)];
                    let t = self.idx(r, j);
                    self.data[t] -= l * v;
                }
            }
        }
        Ok(BandLu { a: self, pivots })
    }
}

impl BandMatrix {
    /// The residual B - A X (row-major n × cols) in doubled precision: each product exact
    /// (a fused multiply-add gives its rounding error) and the sums compensated (TwoSum),
    /// rounded once at the end. What iterative refinement needs to recover the digits an
    /// ill-conditioned solve loses.
    pub fn residual(&self, x: &[f64], b: &[f64], cols: usize) -> Vec<f64> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let mut out = vec![0.0; n * cols];
        for i in 0..n {
            let (lo, hi) = (i.saturating_sub(kl), (i + ku).min(n - 1));
            for c in 0..cols {
                let (mut s, mut err) = (b[i * cols + c], 0.0);
                for j in lo..=hi {
                    let a = self.data[self.idx(i, j)];
                    let p = -a * x[j * cols + c];
                    let pe = (-a).mul_add(x[j * cols + c], -p);
                    let t = s + p;
                    let z = t - s;
                    err += (s - (t - z)) + (p - z) + pe;
                    s = t;
                }
                out[i * cols + c] = s + err;
            }
        }
        out
    }
}

/// The LU factors of a [`BandMatrix`]; solves any number of right-hand sides.
#[derive(Debug, Clone)]
pub(crate) struct BandLu {
    a: BandMatrix,
    pivots: Vec<usize>,
}

impl BandLu {
    /// Solves in place for B row-major n × cols. Wide right-hand sides (a surface's rows as
    /// points of thousands of coordinates) are solved in bands of [`WIDE_BAND`] columns in
    /// parallel: the same operations on every number, so the same bits.
    pub fn solve(&self, b: &mut [f64], cols: usize) {
        debug_assert_eq!(b.len(), self.a.n * cols);
        if cols < 2 * WIDE_BAND || b.len() < WIDE_MIN {
            self.solve_rows(&mut FlatRows { b, cols });
            return;
        }
        // Band j: the columns [j·WIDE_BAND, (j+1)·WIDE_BAND) of every row.
        let mut bands: Vec<Vec<&mut [f64]>> = (0..cols.div_ceil(WIDE_BAND))
            .map(|_| Vec::with_capacity(self.a.n))
            .collect();
        for row in b.chunks_exact_mut(cols) {
            for (band, part) in bands.iter_mut().zip(row.chunks_mut(WIDE_BAND)) {
                band.push(part);
            }
        }
        bands.par_iter_mut().for_each(|rows| self.solve_rows(rows));
    }

    /// [`BandLu::solve`] on the rows of B.
    fn solve_rows(&self, rows: &mut impl Rows) {
        let a = &self.a;
        let (n, kl, ku) = (a.n, a.kl, a.ku);
        for k in 0..n {
            let piv = self.pivots[k];
            if piv != k {
                rows.swap(k, piv);
            }
            for r in k + 1..=(k + kl).min(n - 1) {
                let l = a.data[a.idx(r, k)];
                if l != 0.0 {
                    rows.sub_scaled(r, k, l);
                }
            }
        }
        for k in (0..n).rev() {
            for j in k + 1..=(k + ku + kl).min(n - 1) {
                let v = a.data[a.idx(k, j)];
                if v != 0.0 {
                    rows.sub_scaled(k, j, v);
                }
            }
            rows.divide(k, a.data[a.idx(k, k)]);
        }
    }
}

/// The rows of a right-hand side, as [`BandLu::solve_rows`] changes them.
trait Rows {
    /// Exchanges rows i < j.
    fn swap(&mut self, i: usize, j: usize);
    /// Row `dst` -= `factor` · row `src` (dst != src).
    fn sub_scaled(&mut self, dst: usize, src: usize, factor: f64);
    /// Row r /= d.
    fn divide(&mut self, r: usize, d: f64);
}

/// Row `dst` and row `src` (!= dst) of rows of `len` numbers in `b`.
fn two_rows(b: &mut [f64], len: usize, dst: usize, src: usize) -> (&mut [f64], &[f64]) {
    if dst > src {
        let (lo, hi) = b.split_at_mut(dst * len);
        (&mut hi[..len], &lo[src * len..(src + 1) * len])
    } else {
        let (lo, hi) = b.split_at_mut(src * len);
        (&mut lo[dst * len..(dst + 1) * len], &hi[..len])
    }
}

/// `x -= f · p`, element by element.
#[inline]
fn sub_scaled(x: &mut [f64], p: &[f64], f: f64) {
    for (x, p) in x.iter_mut().zip(p) {
        *x -= f * p;
    }
}

/// B row-major, rows of `cols` numbers.
struct FlatRows<'a> {
    b: &'a mut [f64],
    cols: usize,
}

impl Rows for FlatRows<'_> {
    fn swap(&mut self, i: usize, j: usize) {
        let cols = self.cols;
        let (lo, hi) = self.b.split_at_mut(j * cols);
        lo[i * cols..(i + 1) * cols].swap_with_slice(&mut hi[..cols]);
    }

    fn sub_scaled(&mut self, dst: usize, src: usize, factor: f64) {
        let (x, p) = two_rows(self.b, self.cols, dst, src);
        sub_scaled(x, p, factor);
    }

    fn divide(&mut self, r: usize, d: f64) {
        for x in &mut self.b[r * self.cols..(r + 1) * self.cols] {
            *x /= d;
        }
    }
}

impl Rows for Vec<&mut [f64]> {
    fn swap(&mut self, i: usize, j: usize) {
        let (head, tail) = self.split_at_mut(j);
        head[i].swap_with_slice(tail[0]);
    }

    fn sub_scaled(&mut self, dst: usize, src: usize, factor: f64) {
        let (x, p) = if dst > src {
            let (head, tail) = self.split_at_mut(dst);
            (&mut *tail[0], &*head[src])
        } else {
            let (head, tail) = self.split_at_mut(src);
            (&mut *head[dst], &*tail[0])
        };
        sub_scaled(x, p, factor);
    }

    fn divide(&mut self, r: usize, d: f64) {
        for x in self[r].iter_mut() {
            *x /= d;
        }
    }
}

/// Columns of a band of a wide right-hand side ([`BandLu::solve`]): 2 KiB of each row, so
/// that the rows a step touches stay in the first-level cache.
const WIDE_BAND: usize = 256;

/// Right-hand sides of fewer numbers are solved on the calling thread.
const WIDE_MIN: usize = 1 << 16;

/// A cyclic tridiagonal system
/// lower[i] x[i-1] + diag[i] x[i] + upper[i] x[i+1] = b[i] with indices taken mod n
/// (lower[0] couples x[n-1], upper[n-1] couples x[0]), n >= 3, factored once for
/// Sherman–Morrison solves over a banded LU.
#[derive(Debug, Clone)]
pub(crate) struct CyclicLu {
    lu: BandLu,
    z: Vec<f64>,
    v_last: f64,
    denom: f64,
}

impl CyclicLu {
    pub fn new(lower: &[f64], diag: &[f64], upper: &[f64]) -> Result<Self> {
        let n = diag.len();
        debug_assert!(n >= 3);
        // A = T + u v^T with u = (gamma, 0, ..., 0, upper[n-1]), v = (1, 0, ..., 0, lower[0]/gamma).
        let gamma = -diag[0];
        let v_last = lower[0] / gamma;
        let mut t = BandMatrix::zeros(n, 1, 1);
        for i in 0..n {
            let mut d = diag[i];
            if i == 0 {
                d -= gamma;
            }
            if i == n - 1 {
                d -= upper[n - 1] * v_last;
            }
            t.set(i, i, d);
            if i > 0 {
                t.set(i, i - 1, lower[i]);
            }
            if i + 1 < n {
                t.set(i, i + 1, upper[i]);
            }
        }
        let lu = t.factor()?;
        let mut z = vec![0.0; n];
        z[0] = gamma;
        z[n - 1] = upper[n - 1];
        lu.solve(&mut z, 1);
        let denom = 1.0 + z[0] + v_last * z[n - 1];
        if denom == 0.0 || !denom.is_finite() {
            return Err(Error::Numerical {
                operation: "cyclic solve",
                reason: "the periodic interpolation system is singular",
            });
        }
        Ok(CyclicLu {
            lu,
            z,
            v_last,
            denom,
        })
    }

    pub fn solve(&self, b: &mut [f64], cols: usize) {
        let n = self.z.len();
        self.lu.solve(b, cols);
        for c in 0..cols {
            let f = (b[c] + self.v_last * b[(n - 1) * cols + c]) / self.denom;
            for i in 0..n {
                b[i * cols + c] -= f * self.z[i];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_solve_matches_known_solution() {
        // A 6x6 pentadiagonal system with a zero on the diagonal (needs pivoting).
        let n = 6;
        let mut a = BandMatrix::zeros(n, 2, 2);
        let dense = |i: usize, j: usize| -> f64 {
            if i == 2 && j == 2 {
                0.0
            } else if i.abs_diff(j) <= 2 {
                1.0 + (i * 3 + j * 5) as f64 % 7.0
            } else {
                0.0
            }
        };
        for i in 0..n {
            for j in i.saturating_sub(2)..=(i + 2).min(n - 1) {
                a.set(i, j, dense(i, j));
            }
        }
        let x: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| dense(i, j) * x[j]).sum())
            .collect();
        a.solve(&mut b, 1).unwrap();
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-13, "{got} vs {want}");
        }
    }

    #[test]
    fn wide_right_hand_sides_solve_in_bands_with_the_bits_of_one_pass() {
        // 300 rows, 2 sub- and 2 super-diagonals with pivoting (a zero diagonal entry),
        // 700 columns: bands of 256, 256 and 188 columns in parallel.
        let (n, cols) = (300, 700);
        let mut a = BandMatrix::zeros(n, 2, 2);
        for i in 0..n {
            for j in i.saturating_sub(2)..=(i + 2).min(n - 1) {
                let v = if i == j && i % 7 == 3 {
                    0.0
                } else {
                    1.0 + ((i * 7 + j * 13) % 11) as f64 / 3.0
                };
                a.set(i, j, v);
            }
        }
        let lu = a.factor().unwrap();
        let b: Vec<f64> = (0..n * cols)
            .map(|i| ((i * 2654435761) % 1000) as f64 / 7.0 - 70.0)
            .collect();
        assert!(b.len() >= WIDE_MIN && cols >= 2 * WIDE_BAND);
        let mut wide = b.clone();
        lu.solve(&mut wide, cols);
        // Column by column, each a right-hand side of its own (one pass, no bands).
        for c in [0, 1, 255, 256, 511, 512, 699] {
            let mut column: Vec<f64> = (0..n).map(|r| b[r * cols + c]).collect();
            lu.solve(&mut column, 1);
            for r in 0..n {
                assert_eq!(
                    wide[r * cols + c].to_bits(),
                    column[r].to_bits(),
                    "({r}, {c})"
                );
            }
        }
    }

    #[test]
    fn singular_band_is_an_error() {
        let mut a = BandMatrix::zeros(3, 1, 1);
        a.set(0, 0, 1.0);
        a.set(1, 1, 0.0);
        a.set(2, 2, 1.0);
        assert!(a.solve(&mut [1.0, 1.0, 1.0], 1).is_err());
    }

    #[test]
    fn cyclic_solve_matches_known_solution() {
        let n = 7;
        let lower = vec![1.0; n];
        let diag = vec![4.0; n];
        let upper = vec![1.0; n];
        let x: Vec<f64> = (0..n).map(|i| ((i * i) % 5) as f64).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| x[(i + n - 1) % n] + 4.0 * x[i] + x[(i + 1) % n])
            .collect();
        CyclicLu::new(&lower, &diag, &upper)
            .unwrap()
            .solve(&mut b, 1);
        for (got, want) in b.iter().zip(&x) {
            assert!((got - want).abs() < 1e-14);
        }
    }
}
