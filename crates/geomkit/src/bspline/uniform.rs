//! The fast path for uniform parameters (the paper's case, and heights over regular grids):
//! the interpolation rows are the constant (1, 4, 1)/6 of formula (1), so the system is a
//! symmetric Toeplitz tridiagonal matrix T plus two end rows. We solve T by Thomas sweeps
//! whose pivots converge to 2 + √3 within 30 rows (stored up to there, then constant), and
//! the end rows by the Woodbury identity with the two decaying columns T^-1 e_0 and
//! T^-1 e_(n-1), which vanish below rounding after ~40 entries (0.268^k). Memory: O(1)
//! besides the output; time: two sweeps of two multiply-adds per coordinate.

/// Pivots stored explicitly; beyond, they equal the limit to the last bit.
const STORED: usize = 64;

/// Entries of the decaying columns kept (0.268^80 ≈ 1e-46 relative).
const KEEP: usize = 80;

/// T = tridiag(1, 4, 1) of order `n`, plus a rank-2 correction of its first and last rows.
#[derive(Debug, Clone)]
pub(crate) struct UniformSystem {
    n: usize,
    inv_pivot: Vec<f64>,
    inv_limit: f64,
    /// T^-1 e_0 (first KEEP entries, or all n), and by symmetry T^-1 e_(n-1) reversed.
    z: Vec<f64>,
    /// Correction rows: (first column, coefficients) replacing rows 0 and n-1 of T.
    rows: [(usize, Vec<f64>); 2],
    /// Inverse of the 2×2 capacitance matrix I + V^T Z.
    cap_inv: [[f64; 2]; 2],
}

impl UniformSystem {
    /// The system whose rows 1..n-2 are (1, 4, 1) and whose rows 0 and n-1 are `start` and
    /// `end` (first column, coefficients). `None` when it is singular.
    pub fn new(n: usize, start: (usize, Vec<f64>), end: (usize, Vec<f64>)) -> Option<Self> {
        if n < 2 {
            return None;
        }
        let mut inv_pivot = Vec::with_capacity(STORED.min(n));
        let mut d = 4.0f64;
        for _ in 0..STORED.min(n) {
            inv_pivot.push(1.0 / d);
            d = 4.0 - 1.0 / d;
        }
        let inv_limit = 1.0 / (2.0 + 3f64.sqrt());
        let mut sys = UniformSystem {
            n,
            inv_pivot,
            inv_limit,
            z: Vec::new(),
            rows: [(0, Vec::new()), (0, Vec::new())],
            cap_inv: [[1.0, 0.0], [0.0, 1.0]],
        };
        // z = T^-1 e_0 on a system truncated to `m` rows (exact to rounding: the tail is
        // below 0.268^KEEP).
        let m = n.min(2 * KEEP);
        let mut z = vec![0.0; m];
        z[0] = 1.0;
        let trunc = UniformSystem {
            n: m,
            ..sys.clone()
        };
        trunc.solve_t(&mut z, 1);
        z.truncate(KEEP.min(n));
        sys.z = z;
        // V rows: the end rows minus T's own first / last rows.
        let sub = |(first, mut c): (usize, Vec<f64>), t_row: &[(usize, f64)]| {
            // Make the coefficient vector cover T's entries too.
            let lo = t_row.iter().map(|e| e.0).min().unwrap_or(first).min(first);
            let hi = t_row
                .iter()
                .map(|e| e.0)
                .max()
                .unwrap_or(first)
                .max(first + c.len() - 1);
            let mut full = vec![0.0; hi - lo + 1];
            for (k, v) in c.drain(..).enumerate() {
                full[first + k - lo] += v;
            }
            for &(j, v) in t_row {
                full[j - lo] -= v;
            }
            (lo, full)
        };
        sys.rows = [
            sub(start, &[(0, 4.0), (1, 1.0)]),
            sub(end, &[(n - 2, 1.0), (n - 1, 4.0)]),
        ];
        // Capacitance C = I + V^T Z, Z = [T^-1 e_0, T^-1 e_(n-1)].
        let mut c = [[1.0, 0.0], [0.0, 1.0]];
        for (a, (first, coeffs)) in sys.rows.iter().enumerate() {
            for (k, v) in coeffs.iter().enumerate() {
                let j = first + k;
                c[a][0] += v * sys.z0(j);
                c[a][1] += v * sys.z1(j);
            }
        }
        let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
        let scale = c.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        if det.is_nan() || det.abs() <= 1e-13 * scale * scale {
            return None;
        }
        sys.cap_inv = [
            [c[1][1] / det, -c[0][1] / det],
            [-c[1][0] / det, c[0][0] / det],
        ];
        Some(sys)
    }

    #[inline]
    fn inv(&self, r: usize) -> f64 {
        if r < self.inv_pivot.len() {
            self.inv_pivot[r]
        } else {
            self.inv_limit
        }
    }

    /// Entry j of T^-1 e_0.
    #[inline]
    fn z0(&self, j: usize) -> f64 {
        self.z.get(j).copied().unwrap_or(0.0)
    }

    /// Entry j of T^-1 e_(n-1) (T is persymmetric).
    #[inline]
    fn z1(&self, j: usize) -> f64 {
        self.z0(self.n - 1 - j)
    }

    /// Solves T x = b in place (b row-major n × cols).
    fn solve_t(&self, b: &mut [f64], cols: usize) {
        let n = self.n;
        for r in 1..n {
            let l = self.inv(r - 1);
            let (prev, cur) = b[(r - 1) * cols..(r + 1) * cols].split_at_mut(cols);
            for (x, p) in cur.iter_mut().zip(prev.iter()) {
                *x -= l * p;
            }
        }
        let last = self.inv(n - 1);
        for x in &mut b[(n - 1) * cols..n * cols] {
            *x *= last;
        }
        for r in (0..n - 1).rev() {
            let inv = self.inv(r);
            let (cur, next) = b[r * cols..(r + 2) * cols].split_at_mut(cols);
            for (x, nx) in cur.iter_mut().zip(next.iter()) {
                *x = (*x - nx) * inv;
            }
        }
    }

    /// Solves the full system in place (b row-major n × cols).
    pub fn solve(&self, b: &mut [f64], cols: usize) {
        self.solve_t(b, cols);
        let n = self.n;
        for c in 0..cols {
            let mut w = [0.0; 2];
            for (a, (first, coeffs)) in self.rows.iter().enumerate() {
                w[a] = coeffs
                    .iter()
                    .enumerate()
                    .map(|(k, v)| v * b[(first + k) * cols + c])
                    .sum();
            }
            let g0 = self.cap_inv[0][0] * w[0] + self.cap_inv[0][1] * w[1];
            let g1 = self.cap_inv[1][0] * w[0] + self.cap_inv[1][1] * w[1];
            for (j, zj) in self.z.iter().enumerate() {
                b[j * cols + c] -= zj * g0;
                b[(n - 1 - j) * cols + c] -= zj * g1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense_check(n: usize, start: (usize, Vec<f64>), end: (usize, Vec<f64>)) {
        let sys = UniformSystem::new(n, start.clone(), end.clone()).unwrap();
        let x: Vec<f64> = (0..n)
            .map(|i| ((i * 7) % 5) as f64 - 1.5 + i as f64 * 0.01)
            .collect();
        let row = |r: usize| -> Vec<(usize, f64)> {
            if r == 0 {
                start
                    .1
                    .iter()
                    .enumerate()
                    .map(|(k, v)| (start.0 + k, *v))
                    .collect()
            } else if r == n - 1 {
                end.1
                    .iter()
                    .enumerate()
                    .map(|(k, v)| (end.0 + k, *v))
                    .collect()
            } else {
                vec![(r - 1, 1.0), (r, 4.0), (r + 1, 1.0)]
            }
        };
        let mut b: Vec<f64> = (0..n)
            .map(|r| row(r).iter().map(|(j, v)| v * x[*j]).sum())
            .collect();
        sys.solve(&mut b, 1);
        for (got, want) in b.iter().zip(&x) {
            assert!(
                (got - want).abs() < 1e-12 * (1.0 + want.abs()),
                "n={n}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn woodbury_matches_the_system() {
        for n in [2usize, 3, 5, 12, 100, 161, 1000] {
            dense_check(n, (0, vec![1.0]), (n - 1, vec![1.0]));
            // (Smaller n would make the two end rows identical, a singular system.)
            if n >= 4 {
                dense_check(n, (0, vec![1.0, -2.0, 1.0]), (n - 3, vec![1.0, -2.0, 1.0]));
            }
            if n >= 7 {
                dense_check(
                    n,
                    (0, vec![-1.0, 4.0, -6.0, 4.0, -1.0]),
                    (n - 5, vec![-1.0, 4.0, -6.0, 4.0, -1.0]),
                );
            }
        }
    }
}
