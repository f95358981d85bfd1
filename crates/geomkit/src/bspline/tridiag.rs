//! The O(N) solver of open interpolation systems. With the rows ordered [start condition,
//! interpolation at t_0..t_(N-1), end condition], the interpolation rows of a cubic B-spline
//! at its knots are tridiagonal (three basis functions are non-zero at a knot), so the
//! system is a tridiagonal T plus two end rows. T is solved by Thomas sweeps — without
//! pivoting, which is stable here: collocation matrices of B-splines are totally positive
//! (de Boor) — and the end rows by the Woodbury identity with the two columns T^-1 e_0 and
//! T^-1 e_(n-1), which decay geometrically away from their end and are kept only while above
//! rounding.
//!
//! Uniform parameters (the paper's case, heights over regular grids) give the constant rows
//! (1, 4, 1)/6 of formula (1): a Toeplitz T whose Thomas pivots converge to 2 + √3 within 30
//! rows (stored up to there, then constant): O(1) memory besides the output. There the
//! sweeps also run in parallel over chunks: the influence of a row decays like
//! (2 - √3)^k = 0.268^k, so a chunk started [`HALO`] rows early from zero and ended
//! [`HALO`] rows late equals the global sweeps to rounding (0.268^40 ≈ 1e-23).
//!
//! Other parameters (chord length, centripetal, given abscissae), solved once: a
//! partitioned LU ([`TridiagSystem::solve_general_into`]) — cache-sized chunks swept in
//! parallel by their own Thomas sweeps straight from the input, joined exactly by a reduced
//! band system of two unknowns per chunk (no halo, no assumption on how fast the influence
//! decays).

use super::banded::BandMatrix;
use crate::par::*;
use crate::progress::Progress;

/// Toeplitz pivots stored explicitly; beyond, they equal the limit to the last bit.
const STORED: usize = 64;

/// Rows a parallel chunk of the Toeplitz sweeps starts early / ends late.
const HALO: usize = 40;

/// Numbers per parallel chunk of the Toeplitz sweeps (rows × columns).
const CHUNK: usize = 3 << 16;

/// Numbers per chunk of [`TridiagSystem::solve_scaled_into`]: small enough that a chunk
/// swept forward is still in the core's cache when it is swept back.
const FUSED_CHUNK: usize = 3 << 13;

/// Entries of the decaying columns below this (relative to their first) are dropped.
const NEGLIGIBLE: f64 = 1e-40;

/// How T is solved.
#[derive(Debug, Clone)]
enum Tri {
    /// T = tridiag(1, 4, 1).
    Toeplitz { inv_pivot: Vec<f64>, inv_limit: f64 },
    /// A general tridiagonal T, factored: per row [m_r, 1/d_r, c_r/d_r] (forward
    /// multiplier, inverse pivot, upper entry over the pivot).
    General { factors: Vec<[f64; 3]> },
    /// A general T solved with its only right-hand side
    /// ([`TridiagSystem::solve_general_into`]): nothing kept but the decaying columns.
    Solved,
}

/// A tridiagonal T of order `n`, plus a rank-2 correction replacing its first and last rows.
#[derive(Debug, Clone)]
pub(crate) struct TridiagSystem {
    n: usize,
    tri: Tri,
    /// T^-1 e_0 (its leading entries), and T^-1 e_(n-1) from the last entry backwards.
    z: [Vec<f64>; 2],
    /// Correction rows: (first column, coefficients) to add to rows 0 and n-1 of T.
    rows: [(usize, Vec<f64>); 2],
    /// Inverse of the 2×2 capacitance matrix I + V^T Z.
    cap_inv: [[f64; 2]; 2],
}

impl TridiagSystem {
    /// The system whose rows 1..n-2 are (1, 4, 1) and whose rows 0 and n-1 are `start` and
    /// `end` (first column, coefficients). `None` when it is singular.
    pub fn toeplitz(n: usize, start: (usize, Vec<f64>), end: (usize, Vec<f64>)) -> Option<Self> {
        if n < 2 {
            return None;
        }
        let mut inv_pivot = Vec::with_capacity(STORED.min(n));
        let mut d = 4.0f64;
        for _ in 0..STORED.min(n) {
            inv_pivot.push(1.0 / d);
            d = 4.0 - 1.0 / d;
        }
        let tri = Tri::Toeplitz {
            inv_pivot,
            inv_limit: 1.0 / (2.0 + 3f64.sqrt()),
        };
        Self::with_end_rows(n, tri, start, end, [(0, 4.0), (1, 1.0)], [1.0, 4.0])
    }

    /// The system whose rows r = 1..n-2 are `inner(r)` = (r-1, r, r+1 entries) and whose
    /// rows 0 and n-1 are `start` and `end`. `None` when it is singular.
    pub fn general(
        n: usize,
        inner: impl Fn(usize) -> [f64; 3],
        start: (usize, Vec<f64>),
        end: (usize, Vec<f64>),
    ) -> Option<Self> {
        if n < 2 {
            return None;
        }
        // T's own rows 0 and n-1 are e_0 and e_(n-1): T stays totally positive.
        let mut factors = Vec::with_capacity(n);
        factors.push([0.0, 1.0, 0.0]);
        let mut prev_u = 0.0;
        for r in 1..n {
            let [a, b, c] = if r + 1 == n {
                [0.0, 1.0, 0.0]
            } else {
                inner(r)
            };
            // prev pivot d = 1/inv, prev upper = u·d: m = a/d_prev, d = b - m·c_prev
            //   = b - a·u_prev.
            let d = b - a * prev_u;
            if !(d.is_finite() && d.abs() > 1e-14 * (a.abs() + b.abs() + c.abs())) {
                return None;
            }
            let m = a * factors[r - 1][1];
            prev_u = c / d;
            factors.push([m, 1.0 / d, prev_u]);
        }
        Self::with_end_rows(
            n,
            Tri::General { factors },
            start,
            end,
            [(0, 1.0), (1, 0.0)],
            [0.0, 1.0],
        )
    }

    /// Adds the Woodbury part: the decaying columns, the correction rows (the wanted end rows
    /// minus T's own, `t_first` = T's row 0 as (column, value) and `t_last` = T's row n-1
    /// entries at columns n-2, n-1), and the capacitance matrix.
    fn with_end_rows(
        n: usize,
        tri: Tri,
        start: (usize, Vec<f64>),
        end: (usize, Vec<f64>),
        t_first: [(usize, f64); 2],
        t_last: [f64; 2],
    ) -> Option<Self> {
        let probe = TridiagSystem {
            n,
            tri,
            z: [Vec::new(), Vec::new()],
            rows: [(0, Vec::new()), (0, Vec::new())],
            cap_inv: [[1.0, 0.0], [0.0, 1.0]],
        };
        let z = [probe.decaying_column(true), probe.decaying_column(false)];
        Self::with_columns(n, probe.tri, z, start, end, t_first, t_last)
    }

    /// [`TridiagSystem::with_end_rows`] with the decaying columns `z` given.
    fn with_columns(
        n: usize,
        tri: Tri,
        z: [Vec<f64>; 2],
        start: (usize, Vec<f64>),
        end: (usize, Vec<f64>),
        t_first: [(usize, f64); 2],
        t_last: [f64; 2],
    ) -> Option<Self> {
        let mut sys = TridiagSystem {
            n,
            tri,
            z,
            rows: [(0, Vec::new()), (0, Vec::new())],
            cap_inv: [[1.0, 0.0], [0.0, 1.0]],
        };
        let sub = |(first, c): (usize, Vec<f64>), t_row: [(usize, f64); 2]| {
            let lo = first.min(t_row[0].0);
            let hi = (first + c.len() - 1).max(t_row[1].0);
            let mut full = vec![0.0; hi - lo + 1];
            for (k, v) in c.iter().enumerate() {
                full[first + k - lo] += v;
            }
            for (j, v) in t_row {
                full[j - lo] -= v;
            }
            (lo, full)
        };
        sys.rows = [
            sub(start, t_first),
            sub(end, [(n - 2, t_last[0]), (n - 1, t_last[1])]),
        ];
        // Capacitance C = I + V^T Z, Z = [T^-1 e_0, T^-1 e_(n-1)].
        let mut c = [[1.0, 0.0], [0.0, 1.0]];
        for (a, (first, coeffs)) in sys.rows.iter().enumerate() {
            for (k, v) in coeffs.iter().enumerate() {
                c[a][0] += v * sys.z_at(0, first + k);
                c[a][1] += v * sys.z_at(1, first + k);
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

    /// T^-1 e_0 (`first`) or T^-1 e_(n-1) (stored from the last entry backwards), up to
    /// where it falls below rounding.
    fn decaying_column(&self, first: bool) -> Vec<f64> {
        let n = self.n;
        match &self.tri {
            Tri::Toeplitz { .. } => {
                // Persymmetric: both columns are the same. Solve on a truncated system: the
                // tail is below 0.268^80 ≈ 1e-46.
                let m = n.min(160);
                let mut z = vec![0.0; m];
                z[0] = 1.0;
                let trunc = TridiagSystem {
                    n: m,
                    tri: self.tri.clone(),
                    z: [Vec::new(), Vec::new()],
                    rows: [(0, Vec::new()), (0, Vec::new())],
                    cap_inv: [[1.0, 0.0], [0.0, 1.0]],
                };
                trunc.solve_t(&mut z, 1, 1.0);
                z.truncate(80.min(n));
                z
            }
            Tri::General { factors } if first => {
                // Forward: y_0 = 1, y_r = -m_r y_(r-1) until negligible; backward from there.
                let mut y = vec![1.0];
                for f in &factors[1..] {
                    let next = -f[0] * y[y.len() - 1];
                    if next.abs() < NEGLIGIBLE {
                        break;
                    }
                    y.push(next);
                }
                let mut x_next = 0.0;
                for r in (0..y.len()).rev() {
                    y[r] = factors[r][1] * y[r] - factors[r][2] * x_next;
                    x_next = y[r];
                }
                y
            }
            Tri::General { factors } => {
                // e_(n-1) passes the forward sweep unchanged; backward x_r = -u_r x_(r+1).
                let mut z = vec![factors[n - 1][1]];
                for r in (0..n - 1).rev() {
                    let next = -factors[r][2] * z[z.len() - 1];
                    if next.abs() < NEGLIGIBLE * z[0].abs() {
                        break;
                    }
                    z.push(next);
                }
                z
            }
            Tri::Solved => unreachable!("a solved system has its columns"),
        }
    }

    /// Entry j of T^-1 e_0 (`which` = 0) or T^-1 e_(n-1) (`which` = 1).
    #[inline]
    fn z_at(&self, which: usize, j: usize) -> f64 {
        let k = if which == 0 { j } else { self.n - 1 - j };
        self.z[which].get(k).copied().unwrap_or(0.0)
    }

    /// Inverse Toeplitz pivot of row r.
    #[inline]
    fn inv(inv_pivot: &[f64], inv_limit: f64, r: usize) -> f64 {
        if r < inv_pivot.len() {
            inv_pivot[r]
        } else {
            inv_limit
        }
    }

    /// Solves T x = b in place (b row-major n × cols), where rows 1..n-1 of `b` hold the
    /// right-hand side divided by `scale` (multiplied back during the forward sweep: no pass
    /// of its own). Returns whether every entry of the solution is finite.
    fn solve_t(&self, b: &mut [f64], cols: usize, scale: f64) -> bool {
        let n = self.n;
        // The factor of row r of b.
        let sc = |r: usize| if r == 0 || r + 1 == n { 1.0 } else { scale };
        let mut finite = true;
        match &self.tri {
            Tri::Toeplitz {
                inv_pivot,
                inv_limit,
            } => {
                let inv = |r| Self::inv(inv_pivot, *inv_limit, r);
                let chunks = (n * cols / CHUNK).min(n / (8 * HALO));
                if chunks >= 2 && crate::par::current_num_threads() > 1 {
                    return toeplitz_par(b, cols, n, chunks, &inv, &sc);
                }
                for r in 1..n {
                    let (l, f) = (inv(r - 1), sc(r));
                    let (prev, cur) = b[(r - 1) * cols..(r + 1) * cols].split_at_mut(cols);
                    for (x, p) in cur.iter_mut().zip(prev.iter()) {
                        *x = f * *x - l * p;
                    }
                }
                let last = inv(n - 1);
                for x in &mut b[(n - 1) * cols..n * cols] {
                    *x *= last;
                    finite &= x.is_finite();
                }
                for r in (0..n - 1).rev() {
                    let i = inv(r);
                    let (cur, next) = b[r * cols..(r + 2) * cols].split_at_mut(cols);
                    for (x, nx) in cur.iter_mut().zip(next.iter()) {
                        *x = (*x - nx) * i;
                        finite &= x.is_finite();
                    }
                }
            }
            Tri::Solved => unreachable!("a solved system has no factors"),
            Tri::General { factors } => {
                for r in 1..n {
                    let (m, f) = (factors[r][0], sc(r));
                    let (prev, cur) = b[(r - 1) * cols..(r + 1) * cols].split_at_mut(cols);
                    for (x, p) in cur.iter_mut().zip(prev.iter()) {
                        *x = f * *x - m * p;
                    }
                }
                let last = factors[n - 1][1];
                for x in &mut b[(n - 1) * cols..n * cols] {
                    *x *= last;
                    finite &= x.is_finite();
                }
                for r in (0..n - 1).rev() {
                    let [_, i, u] = factors[r];
                    let (cur, next) = b[r * cols..(r + 2) * cols].split_at_mut(cols);
                    for (x, nx) in cur.iter_mut().zip(next.iter()) {
                        *x = *x * i - u * nx;
                        finite &= x.is_finite();
                    }
                }
            }
        }
        finite
    }

    /// Solves the full system in place (b row-major n × cols) for the right-hand side whose
    /// rows 1..n-1 are `scale` times those of `b` (the scaling done on the way, with no pass
    /// of its own). Returns whether every entry of the solution is finite.
    pub fn solve_scaled(&self, b: &mut [f64], cols: usize, scale: f64) -> bool {
        let finite = self.solve_t(b, cols, scale);
        self.correct(b, cols);
        finite && self.ends_finite(b, cols)
    }

    /// Whether the rows the Woodbury correction changed are finite.
    fn ends_finite(&self, b: &[f64], cols: usize) -> bool {
        let n = self.n;
        let reach = self.z[0].len().max(self.z[1].len()).min(n);
        b[..reach * cols].iter().all(|x| x.is_finite())
            && b[(n - reach) * cols..].iter().all(|x| x.is_finite())
    }

    /// The Woodbury step: turns T^-1 b (in `b`) into the solution of the full system.
    fn correct(&self, b: &mut [f64], cols: usize) {
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
            for (j, zj) in self.z[0].iter().enumerate() {
                b[j * cols + c] -= zj * g0;
            }
            for (k, zk) in self.z[1].iter().enumerate() {
                b[(n - 1 - k) * cols + c] -= zk * g1;
            }
        }
    }
}

impl TridiagSystem {
    /// The inverse pivots of a Toeplitz system by row (`caller` names the solve that needs
    /// one).
    fn toeplitz_inv(&self, caller: &str) -> impl Fn(usize) -> f64 + Sync + '_ {
        let Tri::Toeplitz {
            inv_pivot,
            inv_limit,
        } = &self.tri
        else {
            unreachable!("{caller} on a Toeplitz system only")
        };
        move |r| Self::inv(inv_pivot, *inv_limit, r)
    }

    /// Whether T is the Toeplitz tridiag(1, 4, 1) ([`TridiagSystem::solve_scaled_into`]
    /// applies).
    pub fn is_toeplitz(&self) -> bool {
        matches!(self.tri, Tri::Toeplitz { .. })
    }

    /// Solves a Toeplitz system ([`TridiagSystem::toeplitz`]) for the right-hand side
    /// b = [first; scale · interior; last] (one row, n - 2 rows, one row of `cols`), writing
    /// the solution to `out` (n × cols) in one pass: chunks of rows that fit the cache are
    /// swept forward from the input and back in place, in parallel, each starting [`HALO`]
    /// rows early from zero and ending [`HALO`] rows late (as [`TridiagSystem::solve_scaled`] does
    /// for large systems; a single chunk is the sequential solve). The input is read once and
    /// the output written once, with no copy of b. Returns whether every entry of the
    /// solution is finite.
    #[cfg(test)]
    pub fn solve_scaled_into(
        &self,
        first: &[f64],
        interior: &[f64],
        last: &[f64],
        scale: f64,
        out: &mut [f64],
        cols: usize,
    ) -> bool {
        let none = Progress::none();
        self.solve_scaled_into_reporting(first, interior, last, scale, out, cols, &none)
    }

    /// [`TridiagSystem::solve_scaled_into`] reporting each chunk's rows to `progress`; once
    /// it is cancelled the remaining chunks are skipped (`out` is then garbage: the caller
    /// checks `progress`).
    pub(crate) fn solve_scaled_into_reporting(
        &self,
        first: &[f64],
        interior: &[f64],
        last: &[f64],
        scale: f64,
        out: &mut [f64],
        cols: usize,
        progress: &Progress,
    ) -> bool {
        let inv = self.toeplitz_inv("solve_scaled_into");
        let n = self.n;
        debug_assert_eq!(interior.len(), (n - 2) * cols);
        debug_assert_eq!(out.len(), n * cols);
        // Row r of b, scaled, into `row`.
        let rhs = |r: usize, row: &mut [f64]| {
            if r == 0 {
                row.copy_from_slice(first);
            } else if r + 1 == n {
                row.copy_from_slice(last);
            } else {
                for (x, p) in row.iter_mut().zip(&interior[(r - 1) * cols..r * cols]) {
                    *x = scale * p;
                }
            }
        };
        let rows = (FUSED_CHUNK / cols).max(8 * HALO);
        let parallel = n > 2 * rows && crate::par::current_num_threads() > 1;
        let chunk = if parallel { rows } else { n };
        let finite = out
            .par_chunks_mut(chunk * cols)
            .enumerate()
            .map(|(k, part)| {
                let lo = k * chunk;
                let hi = lo + part.len() / cols;
                if progress.is_cancelled() {
                    return true;
                }
                let mut y = vec![0.0; cols];
                let mut b = vec![0.0; cols];
                // Forward from HALO rows before the chunk (from row 0 near the start, so
                // that the early pivots are the exact ones), over the chunk into `part`,
                // and HALO rows past it into `tail`.
                let s = if lo <= HALO + STORED { 0 } else { lo - HALO };
                let e = (hi + HALO).min(n);
                let step = |r: usize, y: &mut [f64], b: &mut [f64]| {
                    rhs(r, b);
                    let l = if r == 0 { 0.0 } else { inv(r - 1) };
                    for (v, x) in y.iter_mut().zip(b.iter()) {
                        *v = x - l * *v;
                    }
                };
                for r in s..lo {
                    step(r, &mut y, &mut b);
                }
                for (r, row) in (lo..hi).zip(part.chunks_exact_mut(cols)) {
                    step(r, &mut y, &mut b);
                    row.copy_from_slice(&y);
                }
                let mut tail = vec![0.0; (e - hi) * cols];
                for (r, row) in (hi..e).zip(tail.chunks_exact_mut(cols)) {
                    step(r, &mut y, &mut b);
                    row.copy_from_slice(&y);
                }
                // Backward from the end of the tail (from zero; exact at the true end).
                let mut x_next = vec![0.0; cols];
                for (r, row) in (hi..e).zip(tail.chunks_exact(cols)).rev() {
                    let i = inv(r);
                    for (xn, yv) in x_next.iter_mut().zip(row) {
                        *xn = (yv - *xn) * i;
                    }
                }
                let mut finite = true;
                for (r, row) in (lo..hi).zip(part.chunks_exact_mut(cols)).rev() {
                    let i = inv(r);
                    for (xn, v) in x_next.iter_mut().zip(row.iter_mut()) {
                        *v = (*v - *xn) * i;
                        *xn = *v;
                        finite &= v.is_finite();
                    }
                }
                let _ = progress.advance((hi - lo) as u64);
                finite
            })
            .filter(|&finite| !finite)
            .count()
            == 0;
        self.correct(out, cols);
        finite && self.ends_finite(out, cols)
    }

    /// [`TridiagSystem::solve_scaled`] for B right-hand sides of one column each that live
    /// in separate rows (the rows of a grid), sequentially: the B rows are swept side by side
    /// (B independent latency chains) without being transposed into one system. Row i has
    /// the end values `firsts[i]`, `lasts[i]` and the interior `rows[i]` (n - 2 numbers,
    /// scaled by `scale`), and its solution goes to `outs[i]` (n numbers). The same
    /// operations as [`TridiagSystem::solve_scaled`] on the transposed rows: the same bits.
    /// Returns whether every entry of the solutions is finite.
    pub fn solve_rows_into<const B: usize>(
        &self,
        firsts: [f64; B],
        rows: [&[f64]; B],
        lasts: [f64; B],
        scale: f64,
        outs: &mut [&mut [f64]; B],
    ) -> bool {
        let mut finite = match &self.tri {
            Tri::Toeplitz { .. } => {
                let inv = self.toeplitz_inv("solve_rows_into");
                let sweeps = RowSweeps::<_, _, true> {
                    forward: |r: usize| inv(r - 1),
                    backward: |r: usize| [inv(r), 1.0],
                };
                sweeps.run(self.n, firsts, rows, lasts, scale, outs)
            }
            Tri::General { factors } => {
                let sweeps = RowSweeps::<_, _, false> {
                    forward: |r: usize| factors[r][0],
                    backward: |r: usize| [factors[r][1], factors[r][2]],
                };
                sweeps.run(self.n, firsts, rows, lasts, scale, outs)
            }
            Tri::Solved => unreachable!("a solved system has no factors"),
        };
        for out in outs.iter_mut() {
            self.correct(out, 1);
            finite &= self.ends_finite(out, 1);
        }
        finite
    }

    /// Solves the system of [`TridiagSystem::general`] for the right-hand side
    /// b = [first; interior; last] (one row, n - 2 rows, one row of `cols`), writing the
    /// solution to `out` (n × cols) in one pass and keeping no factorization: a partitioned
    /// LU (SPIKE). T is cut into chunks of rows that fit the cache; each chunk, in parallel,
    /// is swept forward from the input and back in place by its own Thomas sweeps, which
    /// also give its two spikes (the chunk's solutions for its couplings to the neighbour
    /// rows, kept while above rounding: they decay like the decaying columns). The chunks'
    /// first and last unknowns then solve a reduced band system of two rows per chunk, and
    /// the spikes correct the rows they reach. Exact in exact arithmetic (no halo
    /// approximation); the local pivots exist because every contiguous principal minor of
    /// a totally positive matrix is positive. `None` when the system is singular, else
    /// whether every entry of the solution is finite.
    #[cfg(test)]
    pub fn solve_general_into<'a>(
        n: usize,
        inner: &(impl Fn(usize) -> [f64; 3] + Sync),
        start: (usize, Vec<f64>),
        end: (usize, Vec<f64>),
        first: &'a [f64],
        interior: &'a [f64],
        last: &'a [f64],
        out: &mut [f64],
        cols: usize,
    ) -> Option<bool> {
        let none = Progress::none();
        let (b, c) = ((first, interior, last), cols);
        Self::solve_general_into_reporting(n, inner, start, end, b, out, c, &none)
    }

    /// [`TridiagSystem::solve_general_into`] reporting each chunk's rows to `progress`;
    /// once it is cancelled the remaining chunks are skipped and the answer is `None` (the
    /// caller checks `progress` first).
    pub(crate) fn solve_general_into_reporting<'a>(
        n: usize,
        inner: &(impl Fn(usize) -> [f64; 3] + Sync),
        start: (usize, Vec<f64>),
        end: (usize, Vec<f64>),
        (first, interior, last): (&'a [f64], &'a [f64], &'a [f64]),
        out: &mut [f64],
        cols: usize,
        progress: &Progress,
    ) -> Option<bool> {
        if n < 2 {
            return None;
        }
        debug_assert_eq!(interior.len(), (n - 2) * cols);
        debug_assert_eq!(out.len(), n * cols);
        // T's own rows 0 and n-1 are e_0 and e_(n-1): T stays totally positive.
        let row = |r: usize| {
            if r == 0 || r + 1 == n {
                [0.0, 1.0, 0.0]
            } else {
                inner(r)
            }
        };
        let rhs = |r: usize| -> &'a [f64] {
            if r == 0 {
                first
            } else if r + 1 == n {
                last
            } else {
                &interior[(r - 1) * cols..r * cols]
            }
        };
        let rows = (FUSED_CHUNK / cols).max(64);
        let chunks = if crate::par::current_num_threads() > 1 {
            (n / rows).max(1)
        } else {
            1
        };
        let bounds: Vec<(usize, usize)> = (0..chunks)
            .map(|k| (k * n / chunks, (k + 1) * n / chunks))
            .collect();
        let mut parts: Vec<&mut [f64]> = Vec::with_capacity(chunks);
        let mut rest = &mut *out;
        for &(lo, hi) in &bounds {
            let (part, tail) = rest.split_at_mut((hi - lo) * cols);
            parts.push(part);
            rest = tail;
        }
        let spikes: Vec<Spikes> = parts
            .into_par_iter()
            .zip(bounds.par_iter())
            .map_init(Vec::new, |u, (part, &(lo, hi))| {
                if progress.is_cancelled() {
                    return None;
                }
                // Unrolled for the common dimensions.
                let spikes = match cols {
                    1 => sweep_chunk::<1>(part, lo, hi, &row, &rhs, cols, u),
                    2 => sweep_chunk::<2>(part, lo, hi, &row, &rhs, cols, u),
                    3 => sweep_chunk::<3>(part, lo, hi, &row, &rhs, cols, u),
                    _ => sweep_chunk::<0>(part, lo, hi, &row, &rhs, cols, u),
                };
                let _ = progress.advance((hi - lo) as u64);
                spikes
            })
            .collect::<Option<_>>()?;
        let mut finite = spikes.iter().all(|s| s.finite);
        if chunks > 1 {
            finite &= join_chunks(out, &bounds, &spikes, cols)?;
        }
        let reversed = |r: usize| {
            let [a, b, c] = row(n - 1 - r);
            [c, b, a]
        };
        let z = [decaying(n, &row), decaying(n, &reversed)];
        let sys = Self::with_columns(
            n,
            Tri::Solved,
            z,
            start,
            end,
            [(0, 1.0), (1, 0.0)],
            [0.0, 1.0],
        )?;
        sys.correct(out, cols);
        Some(finite && sys.ends_finite(out, cols))
    }
}

/// The Thomas sweeps of [`TridiagSystem::solve_rows_into`]: `forward(r)` is row r's
/// forward multiplier (r >= 1) and `backward(r)` = [1/d_r, u_r] its backward factors,
/// applied as (y - x_(r+1)) / d_r when `UNIT_UPPER` (Toeplitz rows: u_r d_r = 1), else as
/// y / d_r - u_r x_(r+1) — the operations of [`TridiagSystem::solve_t`].
struct RowSweeps<F, G, const UNIT_UPPER: bool> {
    forward: F,
    backward: G,
}

impl<F: Fn(usize) -> f64, G: Fn(usize) -> [f64; 2], const UNIT_UPPER: bool>
    RowSweeps<F, G, UNIT_UPPER>
{
    /// Sweeps the B rows side by side; whether the results before the Woodbury step are
    /// finite.
    fn run<const B: usize>(
        &self,
        n: usize,
        firsts: [f64; B],
        rows: [&[f64]; B],
        lasts: [f64; B],
        scale: f64,
        outs: &mut [&mut [f64]; B],
    ) -> bool {
        let mut y = firsts;
        for i in 0..B {
            outs[i][0] = y[i];
        }
        for r in 1..n - 1 {
            let m = (self.forward)(r);
            for i in 0..B {
                y[i] = scale * rows[i][r - 1] - m * y[i];
                outs[i][r] = y[i];
            }
        }
        let m = (self.forward)(n - 1);
        for i in 0..B {
            outs[i][n - 1] = lasts[i] - m * y[i];
        }
        let mut finite = true;
        let mut x = [0.0; B];
        for r in (0..n).rev() {
            let [inv, u] = (self.backward)(r);
            for i in 0..B {
                x[i] = if UNIT_UPPER {
                    (outs[i][r] - x[i]) * inv
                } else {
                    outs[i][r] * inv - u * x[i]
                };
                outs[i][r] = x[i];
                finite &= x[i].is_finite();
            }
        }
        finite
    }
}

/// What a chunk of [`TridiagSystem::solve_general_into`] gives besides its local solution:
/// its solutions for the coupling entries of its first and last rows.
struct Spikes {
    /// From the chunk's first row on: the local solution for the entry coupling its first
    /// row to the row before (empty for the first chunk).
    left: Vec<f64>,
    /// From the chunk's last row backwards: the same for its last row and the row after.
    right: Vec<f64>,
    /// Whether the local solution is finite.
    finite: bool,
}

/// The local Thomas sweeps of one chunk (rows lo..hi of T) into `part`, reading the rows'
/// right-hand sides from `rhs`; `f` is scratch for the chunk's factors. `C` is `cols` when
/// known at compile time (the sweeps then keep a row in registers), else 0. `None` on a
/// zero pivot.
fn sweep_chunk<'a, const C: usize>(
    part: &mut [f64],
    lo: usize,
    hi: usize,
    row: &impl Fn(usize) -> [f64; 3],
    rhs: &impl Fn(usize) -> &'a [f64],
    cols: usize,
    f: &mut Vec<[f64; 3]>,
) -> Option<Spikes> {
    let cols = if C > 0 { C } else { cols };
    let len = hi - lo;
    // The rows, then their factors [a_j, 1/d_j, u_j = c_j/d_j] (the row's coupling to the
    // row before the chunk left out): the pivot recurrence alone carries a division.
    f.clear();
    f.extend((lo..hi).map(row));
    let coupling_in = f[0][0];
    let coupling_out = f[len - 1][2];
    f[0][0] = 0.0;
    let (mut prev_u, mut ok) = (0.0, true);
    for e in f.iter_mut() {
        let [a, b, c] = *e;
        let d = b - a * prev_u;
        ok &= d.is_finite() && d.abs() > 1e-14 * (a.abs() + b.abs() + c.abs());
        // u = c/d directly: the recurrence waits for one division, not a division and a
        // product; 1/d is off its path.
        prev_u = c / d;
        *e = [a, 1.0 / d, prev_u];
    }
    if !ok {
        return None;
    }
    let mut finite = true;
    if C > 0 {
        let mut y = [0.0; C];
        for ((out, e), r) in part.chunks_exact_mut(C).zip(f.iter()).zip(lo..) {
            let src = rhs(r);
            for k in 0..C {
                y[k] = (src[k] - e[0] * y[k]) * e[1];
                out[k] = y[k];
            }
        }
        let mut x = [0.0; C];
        for (out, e) in part.chunks_exact_mut(C).zip(f.iter()).rev() {
            for k in 0..C {
                x[k] = out[k] - e[2] * x[k];
                out[k] = x[k];
                finite &= x[k].is_finite();
            }
        }
    } else {
        for j in 0..len {
            let (src, [a, inv, _]) = (rhs(lo + j), f[j]);
            let (prev, cur) = part[j.saturating_sub(1) * cols..(j + 1) * cols].split_at_mut(cols);
            if j == 0 {
                for (x, s) in prev.iter_mut().zip(src) {
                    *x = s * inv;
                }
            } else {
                for ((x, s), p) in cur.iter_mut().zip(src).zip(prev.iter()) {
                    *x = (s - a * p) * inv;
                }
            }
        }
        finite = part[(len - 1) * cols..].iter().all(|x| x.is_finite());
        for j in (0..len - 1).rev() {
            let uj = f[j][2];
            let (cur, next) = part[j * cols..(j + 2) * cols].split_at_mut(cols);
            for (x, nx) in cur.iter_mut().zip(next.iter()) {
                *x -= uj * nx;
                finite &= x.is_finite();
            }
        }
    }
    // The spikes: forward sweeps of coupling_in e_0 (decaying) and coupling_out e_last
    // (entering at the last row only), then backward.
    let mut left = Vec::new();
    if coupling_in != 0.0 {
        left.push(coupling_in * f[0][1]);
        for e in &f[1..] {
            let next = -e[0] * left[left.len() - 1] * e[1];
            if next.abs() < NEGLIGIBLE * left[0].abs() || next.is_nan() {
                break;
            }
            left.push(next);
        }
        let mut x_next = 0.0;
        for (w, e) in left.iter_mut().zip(f.iter()).rev() {
            *w -= e[2] * x_next;
            x_next = *w;
        }
    }
    let mut right = Vec::new();
    if coupling_out != 0.0 {
        right.push(coupling_out * f[len - 1][1]);
        for e in f[..len - 1].iter().rev() {
            let next = -e[2] * right[right.len() - 1];
            if next.abs() < NEGLIGIBLE * right[0].abs() || next.is_nan() {
                break;
            }
            right.push(next);
        }
    }
    Some(Spikes {
        left,
        right,
        finite,
    })
}

/// The reduced system of [`TridiagSystem::solve_general_into`]: with f_k, l_k the first and
/// last unknowns of chunk k, its solution is x_k = x'_k - left_k l_(k-1) - right_k f_(k+1),
/// whose first and last rows give a band system (2 sub- and super-diagonals) in
/// (f_0, l_0, f_1, l_1, ...). Solves it and corrects the rows the spikes reach. `None`
/// when it is singular, else whether the corrected rows are finite.
fn join_chunks(
    out: &mut [f64],
    bounds: &[(usize, usize)],
    spikes: &[Spikes],
    cols: usize,
) -> Option<bool> {
    let m = 2 * bounds.len();
    let mut a = BandMatrix::zeros(m, 2, 2);
    let mut ends = vec![0.0; m * cols];
    for (k, (&(lo, hi), s)) in bounds.iter().zip(spikes).enumerate() {
        let len = hi - lo;
        let left = |j: usize| s.left.get(j).copied().unwrap_or(0.0);
        let right = |j: usize| s.right.get(len - 1 - j).copied().unwrap_or(0.0);
        a.set(2 * k, 2 * k, 1.0);
        a.set(2 * k + 1, 2 * k + 1, 1.0);
        if k > 0 {
            a.set(2 * k, 2 * k - 1, left(0));
            a.set(2 * k + 1, 2 * k - 1, left(len - 1));
        }
        if k + 1 < bounds.len() {
            a.set(2 * k, 2 * k + 2, right(0));
            a.set(2 * k + 1, 2 * k + 2, right(len - 1));
        }
        ends[2 * k * cols..(2 * k + 1) * cols].copy_from_slice(&out[lo * cols..(lo + 1) * cols]);
        ends[(2 * k + 1) * cols..(2 * k + 2) * cols]
            .copy_from_slice(&out[(hi - 1) * cols..hi * cols]);
    }
    a.factor().ok()?.solve(&mut ends, cols);
    let mut finite = true;
    for (k, (&(lo, hi), s)) in bounds.iter().zip(spikes).enumerate() {
        if k > 0 {
            let before = &ends[(2 * k - 1) * cols..2 * k * cols];
            for (j, w) in s.left.iter().enumerate() {
                for (x, l) in out[(lo + j) * cols..(lo + j + 1) * cols]
                    .iter_mut()
                    .zip(before)
                {
                    *x -= w * l;
                    finite &= x.is_finite();
                }
            }
        }
        if k + 1 < bounds.len() {
            let after = &ends[(2 * k + 2) * cols..(2 * k + 3) * cols];
            for (j, v) in s.right.iter().enumerate() {
                let r = hi - 1 - j;
                for (x, f) in out[r * cols..(r + 1) * cols].iter_mut().zip(after) {
                    *x -= v * f;
                    finite &= x.is_finite();
                }
            }
        }
    }
    Some(finite)
}

/// T^-1 e_0 for the tridiagonal T with rows `row(r)` = (r-1, r, r+1 entries) and row 0 =
/// e_0, up to where it falls below rounding: forward while the sweep of e_0 is above
/// [`NEGLIGIBLE`], backward from there.
fn decaying(n: usize, row: &impl Fn(usize) -> [f64; 3]) -> Vec<f64> {
    let (mut u, mut z) = (vec![0.0], vec![1.0]);
    for r in 1..n {
        let [a, b, c] = row(r);
        let d = b - a * u[r - 1];
        let next = -a * z[r - 1] / d;
        if next.abs() < NEGLIGIBLE || next.is_nan() {
            break;
        }
        u.push(c / d);
        z.push(next);
    }
    let mut x_next = 0.0;
    for r in (0..z.len()).rev() {
        z[r] -= u[r] * x_next;
        x_next = z[r];
    }
    z
}

/// The Toeplitz sweeps of [`TridiagSystem::solve_t`] in parallel over chunks of rows: each
/// chunk starts its forward sweep [`HALO`] rows early from zero (over a saved copy of those
/// rows, which the previous chunk overwrites) and continues it [`HALO`] rows past its end
/// into scratch, where its backward sweep starts from zero.
fn toeplitz_par(
    b: &mut [f64],
    cols: usize,
    n: usize,
    chunks: usize,
    inv: &(impl Fn(usize) -> f64 + Sync),
    sc: &(impl Fn(usize) -> f64 + Sync),
) -> bool {
    let bounds: Vec<(usize, usize)> = (0..chunks)
        .map(|k| (k * n / chunks, (k + 1) * n / chunks))
        .collect();
    // The original rows each chunk needs from its neighbours: [lo - HALO, lo) (from row 0
    // when that is near the start, so that the early pivots are the exact ones) and
    // [hi, hi + HALO).
    let halos: Vec<(usize, Vec<f64>, Vec<f64>)> = bounds
        .iter()
        .map(|&(lo, hi)| {
            let s = if lo <= HALO + STORED { 0 } else { lo - HALO };
            let e = (hi + HALO).min(n);
            (
                s,
                b[s * cols..lo * cols].to_vec(),
                b[hi * cols..e * cols].to_vec(),
            )
        })
        .collect();
    let mut parts: Vec<&mut [f64]> = Vec::with_capacity(chunks);
    let mut rest = b;
    for &(lo, hi) in &bounds {
        let (part, tail) = rest.split_at_mut((hi - lo) * cols);
        parts.push(part);
        rest = tail;
    }
    parts
        .into_par_iter()
        .zip(bounds.par_iter().zip(halos.par_iter()))
        .map(|(part, (&(lo, hi), (s, before, after)))| {
            let mut y = vec![0.0; cols];
            // Forward over the rows before the chunk (not stored).
            for (k, row) in before.chunks_exact(cols).enumerate() {
                let r = s + k;
                let (l, f) = (if r == 0 { 0.0 } else { inv(r - 1) }, sc(r));
                for (v, x) in y.iter_mut().zip(row) {
                    *v = f * x - l * *v;
                }
            }
            // Forward over the chunk, in place.
            for (k, row) in part.chunks_exact_mut(cols).enumerate() {
                let r = lo + k;
                let (l, f) = (if r == 0 { 0.0 } else { inv(r - 1) }, sc(r));
                for (v, x) in y.iter_mut().zip(row.iter_mut()) {
                    *x = f * *x - l * *v;
                    *v = *x;
                }
            }
            // Forward past the chunk into scratch, then backward from its end.
            let mut tail: Vec<f64> = after.clone();
            for (k, row) in tail.chunks_exact_mut(cols).enumerate() {
                let (l, f) = (inv(hi + k - 1), sc(hi + k));
                for (v, x) in y.iter_mut().zip(row.iter_mut()) {
                    *x = f * *x - l * *v;
                    *v = *x;
                }
            }
            let mut x_next = vec![0.0; cols];
            for (k, row) in tail.chunks_exact(cols).enumerate().rev() {
                let i = inv(hi + k);
                for (xn, yv) in x_next.iter_mut().zip(row) {
                    *xn = (yv - *xn) * i;
                }
            }
            let mut finite = true;
            for (k, row) in part.chunks_exact_mut(cols).enumerate().rev() {
                let i = inv(lo + k);
                for (xn, v) in x_next.iter_mut().zip(row.iter_mut()) {
                    *v = (*v - *xn) * i;
                    *xn = *v;
                    finite &= v.is_finite();
                }
            }
            finite
        })
        .filter(|&finite| !finite)
        .count()
        == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    type Row = (usize, Vec<f64>);

    fn dense_check(n: usize, start: Row, end: Row, inner: &(dyn Fn(usize) -> [f64; 3] + Sync)) {
        let x: Vec<f64> = (0..n)
            .map(|i| ((i * 7) % 5) as f64 - 1.5 + i as f64 * 0.01)
            .collect();
        let row = |r: usize| -> Vec<(usize, f64)> {
            let (first, c) = if r == 0 {
                start.clone()
            } else if r == n - 1 {
                end.clone()
            } else {
                (r - 1, inner(r).to_vec())
            };
            c.iter().enumerate().map(|(k, v)| (first + k, *v)).collect()
        };
        let b: Vec<f64> = (0..n)
            .map(|r| row(r).iter().map(|(j, v)| v * x[*j]).sum())
            .collect();
        let toeplitz = (1..n - 1).all(|r| inner(r) == [1.0, 4.0, 1.0]);
        let mut systems = vec![TridiagSystem::general(n, inner, start.clone(), end.clone())];
        if toeplitz {
            systems.push(TridiagSystem::toeplitz(n, start.clone(), end.clone()));
        }
        let mut solutions = Vec::new();
        for sys in systems {
            let mut got = b.clone();
            assert!(sys.unwrap().solve_scaled(&mut got, 1, 1.0));
            solutions.push(got);
        }
        let mut once = vec![0.0; n];
        let (first, interior, last) = (&b[..1], &b[1..n - 1], &b[n - 1..]);
        assert!(TridiagSystem::solve_general_into(
            n,
            &inner,
            start.clone(),
            end.clone(),
            first,
            interior,
            last,
            &mut once,
            1
        )
        .unwrap());
        solutions.push(once);
        for got in solutions {
            for (g, want) in got.iter().zip(&x) {
                assert!(
                    (g - want).abs() < 1e-12 * (1.0 + want.abs()),
                    "n={n}: {g} vs {want}"
                );
            }
        }
    }

    #[test]
    fn woodbury_matches_the_system() {
        let toeplitz = |_: usize| [1.0, 4.0, 1.0];
        let uneven = |r: usize| {
            let a = 0.1 + (r % 3) as f64 * 0.2;
            let c = 0.05 + (r % 5) as f64 * 0.1;
            [a, 1.0 - a - c, c]
        };
        for n in [2usize, 3, 5, 12, 100, 161, 1000] {
            for inner in [&toeplitz as &(dyn Fn(usize) -> [f64; 3] + Sync), &uneven] {
                dense_check(n, (0, vec![1.0]), (n - 1, vec![1.0]), inner);
                // (Smaller n would make the two end rows identical, a singular system.)
                if n >= 4 {
                    let d2 = vec![1.0, -2.0, 1.0];
                    dense_check(n, (0, d2.clone()), (n - 3, d2), inner);
                }
                if n >= 7 {
                    let d4 = vec![-1.0, 4.0, -6.0, 4.0, -1.0];
                    dense_check(n, (0, d4.clone()), (n - 5, d4), inner);
                }
            }
        }
    }

    /// The partitioned solve in many parallel chunks equals the factored sequential one, and
    /// flags non-finite solutions.
    #[test]
    fn partitioned_general_solve_equals_the_sequential_one() {
        let uneven = |r: usize| {
            let a = 0.05 + ((r * 7) % 11) as f64 * 0.03;
            let c = 0.1 + ((r * 3) % 5) as f64 * 0.05;
            [a, 1.0 - a - c, c]
        };
        let d4 = vec![-1.0, 4.0, -6.0, 4.0, -1.0];
        // Columns 3 and 1 take unrolled sweeps, 5 the general ones.
        for (n, cols) in [
            (3 * FUSED_CHUNK + 5, 3usize),
            (2 * FUSED_CHUNK + 1, 1),
            (FUSED_CHUNK + 7, 5),
        ] {
            let sys =
                TridiagSystem::general(n, uneven, (0, d4.clone()), (n - 5, d4.clone())).unwrap();
            let b: Vec<f64> = (0..n * cols).map(|i| ((i as f64) * 0.37).cos()).collect();
            let mut want = b.clone();
            assert!(sys.solve_scaled(&mut want, cols, 1.0));
            let mut got = vec![0.0; n * cols];
            let (first, interior, last) =
                (&b[..cols], &b[cols..(n - 1) * cols], &b[(n - 1) * cols..]);
            let solve = |interior: &[f64], got: &mut [f64]| {
                TridiagSystem::solve_general_into(
                    n,
                    &uneven,
                    (0, d4.clone()),
                    (n - 5, d4.clone()),
                    first,
                    interior,
                    last,
                    got,
                    cols,
                )
                .unwrap()
            };
            assert!(solve(interior, &mut got));
            // Two orders of elimination: rounding of the same order, not bit for bit.
            assert_close(&got, &want, n, 16.0);
            let mut bad = interior.to_vec();
            bad[n / 3 * cols] = f64::NAN;
            assert!(!solve(&bad, &mut got));
        }
    }

    /// got equals want within `ulps` ulps of want's largest entry.
    fn assert_close(got: &[f64], want: &[f64], n: usize, ulps: f64) {
        let scale = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = got
            .iter()
            .zip(want)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(err <= ulps * f64::EPSILON * scale, "n={n}: {err:e}");
    }

    /// The one-pass solve from the input equals copy-scale-then-solve, in one chunk and in
    /// many (parallel, from zero halos), with the Woodbury end rows, and flags non-finite
    /// solutions.
    #[test]
    fn one_pass_toeplitz_solve_equals_the_two_pass_one() {
        let d4 = vec![-1.0, 4.0, -6.0, 4.0, -1.0];
        for (n, cols) in [
            (7usize, 1usize),
            (300, 2),
            (3 * FUSED_CHUNK / 2 + 11, 3),
            (40_000, 1),
        ] {
            let sys = TridiagSystem::toeplitz(n, (0, d4.clone()), (n - 5, d4.clone())).unwrap();
            let interior: Vec<f64> = (0..(n - 2) * cols)
                .map(|i| ((i as f64) * 0.71).sin())
                .collect();
            let (first, last) = (vec![0.25; cols], vec![-0.5; cols]);
            let mut want = Vec::with_capacity(n * cols);
            want.extend_from_slice(&first);
            want.extend(interior.iter().map(|x| 6.0 * x));
            want.extend_from_slice(&last);
            assert!(sys.solve_scaled(&mut want, cols, 1.0));
            let mut got = vec![0.0; n * cols];
            assert!(sys.solve_scaled_into(&first, &interior, &last, 6.0, &mut got, cols));
            assert_close(&got, &want, n, 4.0);
            let mut bad = interior.clone();
            bad[(n / 2) * cols - 1] = f64::INFINITY;
            assert!(!sys.solve_scaled_into(&first, &bad, &last, 6.0, &mut got, cols));
        }
    }

    /// Scaling the interior rows during the forward sweep gives the solution of the scaled
    /// right-hand side (sequential and parallel Toeplitz, general systems), and non-finite
    /// solutions are flagged.
    #[test]
    fn scaled_solves_equal_solves_of_the_scaled_right_hand_side() {
        let d2 = vec![1.0, -2.0, 1.0];
        let uneven = |r: usize| {
            let a = 0.1 + (r % 3) as f64 * 0.2;
            [a, 1.0, 0.9 - a]
        };
        for (n, cols) in [(50usize, 2usize), (5 * CHUNK / 3 + 17, 3)] {
            let systems = [
                TridiagSystem::toeplitz(n, (0, d2.clone()), (n - 3, d2.clone())).unwrap(),
                TridiagSystem::general(n, uneven, (0, d2.clone()), (n - 3, d2.clone())).unwrap(),
            ];
            for sys in systems {
                let b: Vec<f64> = (0..n * cols).map(|i| ((i as f64) * 0.37).cos()).collect();
                let mut want: Vec<f64> = b
                    .iter()
                    .enumerate()
                    .map(|(i, x)| {
                        if i < cols || i >= (n - 1) * cols {
                            *x
                        } else {
                            6.0 * x
                        }
                    })
                    .collect();
                assert!(sys.solve_scaled(&mut want, cols, 1.0));
                let mut got = b.clone();
                assert!(sys.solve_scaled(&mut got, cols, 6.0));
                assert_close(&got, &want, n, 4.0);
                let mut bad = b.clone();
                bad[n / 2 * cols] = f64::NAN;
                assert!(!sys.solve_scaled(&mut bad, cols, 6.0));
            }
        }
    }

    #[test]
    fn parallel_toeplitz_sweeps_equal_the_sequential_ones() {
        let n = 5 * CHUNK / 3 + 17;
        let cols = 3;
        let b: Vec<f64> = (0..n * cols).map(|i| ((i as f64) * 0.37).sin()).collect();
        let sys = TridiagSystem::toeplitz(n, (0, vec![1.0]), (n - 1, vec![1.0])).unwrap();
        let Tri::Toeplitz {
            inv_pivot,
            inv_limit,
        } = &sys.tri
        else {
            unreachable!()
        };
        let inv = |r| TridiagSystem::inv(inv_pivot, *inv_limit, r);
        let mut par = b.clone();
        toeplitz_par(&mut par, cols, n, 7, &inv, &|_| 1.0);
        let mut seq = b;
        for r in 1..n {
            for c in 0..cols {
                seq[r * cols + c] -= inv(r - 1) * seq[(r - 1) * cols + c];
            }
        }
        for r in (0..n).rev() {
            for c in 0..cols {
                let next = if r + 1 < n {
                    seq[(r + 1) * cols + c]
                } else {
                    0.0
                };
                seq[r * cols + c] = (seq[r * cols + c] - next) * inv(r);
            }
        }
        let scale = seq.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = par
            .iter()
            .zip(&seq)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(err <= 2.0 * f64::EPSILON * scale, "{err:e}");
    }
}
