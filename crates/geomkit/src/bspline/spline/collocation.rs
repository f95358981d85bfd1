//! [`OpenSystem::solve_collocation`]'s kernel: windows of the collocation matrix solved by
//! Gaussian elimination without pivoting, in blocks of rows. A block first walks its rows'
//! knot intervals, then computes their basis values lane by lane (the loops of the Cox–de
//! Boor recursion over a block of points, which vectorize: the same operations as
//! [`basis_funs`] per point, so the same bits), then eliminates row by
//! row. A row away from the window's edges has all its k + 1 entries inside the window and
//! its first entry at a fixed offset d = l − r from the diagonal (its knot interval l minus
//! its row r, 0 ≤ d ≤ k): the elimination is compiled once per (k, d), with every index a
//! constant, so the row stays in registers. The forward substitution (reading the points'
//! values straight from y) and the back substitution (writing the rows a window owns
//! straight into the result) run the windows of a task in lockstep: each row waits for the
//! row before it, so two windows' chains overlap. The whole kernel is compiled for AVX2 where the
//! CPU has it ([`with_avx2`]); it uses no fused multiply-adds, so the bits are the same
//! either way.

use super::{check_band, find_span_from, OpenSystem, TP_PIVOT};
use crate::bspline::curve::{basis_funs, find_span};
use crate::bspline::locate::with_avx2;
use crate::Result;

/// Rows per block.
const LANES: usize = 64;

/// Entries of U's rows kept per row: the reciprocal of the pivot, then the k entries right
/// of the diagonal (k <= 7).
const W: usize = 8;

impl OpenSystem<'_> {
    /// [`OpenSystem::solve_collocation`] of S windows of degree K (1..=7) at once, their
    /// rows interleaved: each row's elimination waits for the row before it (the
    /// reciprocal of its pivot), so one window's rows run one after the other at the
    /// latency of that chain, while the rows of two windows overlap.
    pub(super) fn solve_collocation_k<const K: usize, const S: usize>(
        &self,
        windows: [(usize, usize); S],
        outs: [Solution<'_>; S],
        spare: &mut Spare,
    ) -> Result<[bool; S]> {
        let mut answer = Ok([false; S]);
        with_avx2(
            #[inline(always)]
            || answer = self.collocation_blocks::<K, S>(windows, outs, spare),
        );
        answer
    }

    #[inline(always)]
    fn collocation_blocks<const K: usize, const S: usize>(
        &self,
        windows: [(usize, usize); S],
        mut outs: [Solution<'_>; S],
        spare: &mut Spare,
    ) -> Result<[bool; S]> {
        let dim = self.dim;
        let mut ws = windows.map(|(r0, r1)| Window::new(r0, r1, dim, spare));
        while ws.iter().any(Window::pending) {
            for w in &mut ws {
                w.n = 0;
                if w.pending() {
                    w.prepare::<K>(self)?;
                }
            }
            let n = ws.iter().map(|w| w.n).max().unwrap_or(0);
            for lane in 0..n {
                for w in &mut ws {
                    if lane < w.n && !w.failed {
                        w.eliminate::<K>(lane);
                    }
                }
            }
            match dim {
                1 => forward::<K, 1, S>(&mut ws, self.y, self.nl),
                2 => forward::<K, 2, S>(&mut ws, self.y, self.nl),
                3 => forward::<K, 3, S>(&mut ws, self.y, self.nl),
                _ => ws
                    .iter_mut()
                    .for_each(|w| w.forward_any::<K>(self.y, self.nl, dim)),
            }
        }
        let solved = ws.each_ref().map(|w| !w.failed);
        match dim {
            1 => backward::<K, 1, S>(&ws, &mut outs),
            2 => backward::<K, 2, S>(&ws, &mut outs),
            3 => backward::<K, 3, S>(&ws, &mut outs),
            _ => ws
                .iter_mut()
                .zip(&mut outs)
                .filter(|(w, _)| !w.failed)
                .for_each(|(w, to)| backward_any(K, &w.u, &mut w.b, to, dim)),
        }
        for w in ws {
            spare.u.push(w.u);
            spare.b.push(w.b);
        }
        Ok(solved)
    }
}

/// Where a window's solution goes: its rows `rows` (counted from the window's first row)
/// into `out`, the rest (the halo) dropped.
pub(in crate::bspline) struct Solution<'a> {
    pub(in crate::bspline) rows: std::ops::Range<usize>,
    pub(in crate::bspline) out: &'a mut [f64],
}

/// Buffers of finished windows, reused by the next windows on the same thread: fresh
/// memory for every window costs a page fault per 4 KB, a third of the time at 10^7
/// points.
#[derive(Default)]
pub(in crate::bspline) struct Spare {
    u: Vec<Vec<[f64; W]>>,
    b: Vec<Vec<f64>>,
}

/// An empty vector of capacity at least `n`: one of `spare`'s, else a new one.
fn reuse<T>(spare: &mut Vec<Vec<T>>, n: usize) -> Vec<T> {
    let mut v = spare.pop().unwrap_or_default();
    v.clear();
    v.reserve(n);
    v
}

/// A window of rows r0..r1 being eliminated, block by block.
struct Window {
    r0: usize,
    r1: usize,
    /// The first row of the current block, its number of rows.
    s0: usize,
    n: usize,
    /// U's rows (entry 0 the reciprocal of the diagonal, entry j column r + j) and the
    /// right-hand sides, both filled row by row (never zeroed first).
    u: Vec<[f64; W]>,
    b: Vec<f64>,
    lanes: Box<Lanes>,
    /// The knot interval of the last row prepared.
    span: Option<usize>,
    /// A pivot was not clearly positive: the caller pivots instead.
    failed: bool,
}

impl Window {
    fn new(r0: usize, r1: usize, dim: usize, spare: &mut Spare) -> Self {
        Window {
            r0,
            r1,
            s0: r0,
            n: 0,
            u: reuse(&mut spare.u, r1 - r0),
            b: reuse(&mut spare.b, (r1 - r0) * dim),
            lanes: Lanes::new(),
            span: None,
            failed: false,
        }
    }

    /// Whether rows remain to be eliminated.
    fn pending(&self) -> bool {
        !self.failed && self.r0 + self.u.len() < self.r1
    }

    /// The next block: its rows' knot intervals (a walk: the points increase) and basis
    /// values. Errors: a point whose knot interval does not suit its row.
    #[inline(always)]
    fn prepare<const K: usize>(&mut self, sys: &OpenSystem) -> Result<()> {
        self.s0 = self.r0 + self.u.len();
        self.n = LANES.min(self.r1 - self.s0);
        for (lane, r) in (self.s0..self.s0 + self.n).enumerate() {
            let i = r - sys.nl;
            let xi = sys.x[i];
            // The knot interval t_l <= x_i < t_(l+1) (at the right end the last non-empty
            // one).
            let l = match self.span {
                None => find_span(sys.t, K, sys.nt, xi),
                Some(from) => find_span_from(sys.t, K, sys.nt, xi, from),
            };
            self.span = Some(l);
            check_band(r, l, K, || format!("x[{i}] = {xi}"))?;
            self.lanes.x[lane] = xi;
            self.lanes.span[lane] = l;
        }
        self.lanes.basis::<K>(sys.t, self.n);
        Ok(())
    }

    /// Eliminates the block's row `lane` (its U row appended, its multipliers kept for
    /// [`Window::forward`]).
    #[inline(always)]
    fn eliminate<const K: usize>(&mut self, lane: usize) {
        let lanes = &mut *self.lanes;
        let e: [f64; W] = std::array::from_fn(|j| lanes.basis[j][lane]);
        let r = self.s0 + lane;
        let (i, d, m) = (r - self.r0, lanes.span[lane] - r, self.r1 - self.r0);
        let f = &mut lanes.factors[lane];
        let pivoted = if i >= K && i + K < m {
            eliminate_inner::<K>(d, &e, &mut self.u, f)
        } else {
            eliminate_edge(K, d, &e, &mut self.u, m, f)
        };
        self.failed |= !pivoted;
    }

    /// The forward substitution of the block's right-hand sides for any dimension: the
    /// block's values of y appended to `b`, then substituted there.
    fn forward_any<const K: usize>(&mut self, y: &[f64], nl: usize, dim: usize) {
        if self.n == 0 || self.failed {
            return;
        }
        let i0 = self.s0 - nl;
        self.b.extend_from_slice(&y[i0 * dim..(i0 + self.n) * dim]);
        let rows = self.s0 - self.r0..self.s0 - self.r0 + self.n;
        for (i, f) in rows.zip(&self.lanes.factors) {
            let (done, rest) = self.b.split_at_mut(i * dim);
            for p in K.saturating_sub(i)..K {
                let y = &done[(i + p - K) * dim..(i + p - K + 1) * dim];
                for (x, y) in rest[..dim].iter_mut().zip(y) {
                    *x -= f[p] * y;
                }
            }
        }
    }
}

/// The knots and basis values of a block of rows (structure of arrays, lane i for the
/// block's row i).
struct Lanes {
    x: [f64; LANES],
    span: [usize; LANES],
    /// Lane i's knots t[l+1-k ..= l+k] (2k of them).
    window: [[f64; LANES]; 2 * W],
    /// Lane i's k + 1 nonzero basis values at x.
    basis: [[f64; LANES]; W],
    /// Lane i's multipliers: U's row i − K + p times factors[i][p] was subtracted from it.
    factors: [[f64; W]; LANES],
}

impl Lanes {
    fn new() -> Box<Self> {
        Box::new(Lanes {
            x: [0.0; LANES],
            span: [0; LANES],
            window: [[0.0; LANES]; 2 * W],
            basis: [[0.0; LANES]; W],
            factors: [[0.0; W]; LANES],
        })
    }

    /// The basis values of the first `n` lanes (whole blocks vectorize best: the lanes past
    /// n repeat lane n - 1).
    #[inline(always)]
    fn basis<const K: usize>(&mut self, t: &[f64], n: usize) {
        for i in n..LANES {
            self.x[i] = self.x[n - 1];
            self.span[i] = self.span[n - 1];
        }
        for (i, &l) in self.span.iter().enumerate() {
            for (q, w) in t[l + 1 - K..=l + K].iter().enumerate() {
                self.window[q][i] = *w;
            }
        }
        if K == 3 {
            // basis_funs' own cubic (reciprocals first): its bits.
            for i in 0..LANES {
                let w: [f64; 2 * W] = std::array::from_fn(|q| self.window[q][i]);
                let nb = cox_de_boor::<K>(&w, self.x[i]);
                for (r, v) in nb.into_iter().enumerate() {
                    self.basis[r][i] = v;
                }
            }
        } else {
            self.cox_de_boor_lanes::<K>();
        }
    }

    /// The loops of [`basis_funs`] (any degree but the cubic) with every step over all
    /// lanes at once: the same operations in the same order per lane (so the same bits), a
    /// lane per SIMD slot. (Point by point, the recursion's divisions and its chain of
    /// `saved` run one after the other.)
    #[inline(always)]
    fn cox_de_boor_lanes<const K: usize>(&mut self) {
        // For x in the window's interval K - 1: left[j] = x - w[K - j], right[j] = w[K - 1 + j] - x.
        let mut left = [[0.0f64; LANES]; W];
        let mut right = [[0.0f64; LANES]; W];
        let n = &mut self.basis;
        n[0] = [1.0; LANES];
        for j in 1..=K {
            for i in 0..LANES {
                left[j][i] = self.x[i] - self.window[K - j][i];
                right[j][i] = self.window[K - 1 + j][i] - self.x[i];
            }
            let mut saved = [0.0f64; LANES];
            for r in 0..j {
                for i in 0..LANES {
                    let temp = n[r][i] / (right[r + 1][i] + left[j - r][i]);
                    n[r][i] = saved[i] + right[r + 1][i] * temp;
                    saved[i] = left[j - r][i] * temp;
                }
            }
            n[j] = saved;
        }
    }
}

/// The k + 1 nonzero B-splines of degree K at x on the knot window w = t[l+1-K ..= l+K]
/// of x's knot interval l (the interval K − 1 of the window): [`basis_funs`], so its bits.
#[inline(always)]
fn cox_de_boor<const K: usize>(w: &[f64; 2 * W], x: f64) -> [f64; W] {
    let mut nb = [0.0f64; W];
    basis_funs(w, K - 1, x, K, &mut nb[..=K]);
    nb
}

/// Eliminates row i (entries `e` from column i + d − K on) against U's rows above it and
/// appends its row of U: [`eliminate`] with the offset d a constant.
#[inline(always)]
fn eliminate_inner<const K: usize>(
    d: usize,
    e: &[f64; W],
    u: &mut Vec<[f64; W]>,
    f: &mut [f64; W],
) -> bool {
    match d {
        0 => eliminate::<K, 0>(e, u, f),
        1 => eliminate::<K, 1>(e, u, f),
        2 => eliminate::<K, 2>(e, u, f),
        3 => eliminate::<K, 3>(e, u, f),
        4 => eliminate::<K, 4>(e, u, f),
        5 => eliminate::<K, 5>(e, u, f),
        6 => eliminate::<K, 6>(e, u, f),
        _ => eliminate::<K, 7>(e, u, f),
    }
}

/// Row i of a window, all of whose k + 1 entries lie inside it (K <= i, i + K < rows):
/// the row over columns i − K ..= i + K is v[p] (column i − K + p), its entries at
/// v[D ..= D + K]; the entries left of the diagonal are eliminated by U's rows i − K + p
/// (p >= D: those left of the row's first entry are zero) with the multipliers f[p] (0
/// below D); U's rows 0..i are `u`, row i is appended. False when the pivot is not
/// clearly positive ([`TP_PIVOT`]).
#[inline(always)]
fn eliminate<const K: usize, const D: usize>(
    e: &[f64; W],
    u: &mut Vec<[f64; W]>,
    f: &mut [f64; W],
) -> bool {
    if D > K {
        return false; // no such row (check_band): keeps the index ranges below valid
    }
    let i = u.len();
    let mut v = [0.0f64; 2 * W];
    v[D..=D + K].copy_from_slice(&e[..=K]);
    let big = e[..=K].iter().fold(0.0f64, |m, a| m.max(a.abs()));
    f[..D].fill(0.0);
    for p in D..K {
        let uc = &u[i + p - K];
        f[p] = v[p] * uc[0];
        for j in 1..=K {
            v[p + j] -= f[p] * uc[j];
        }
    }
    push_pivot_row(K, &v, big, u)
}

/// [`eliminate`] for a row at a window's edge: entries outside the window dropped (those
/// coefficients held at zero, the window's artificial ends), any offset; `m` rows.
fn eliminate_edge(
    k: usize,
    d: usize,
    e: &[f64; W],
    u: &mut Vec<[f64; W]>,
    m: usize,
    f: &mut [f64; W],
) -> bool {
    let i = u.len();
    let mut v = [0.0f64; 2 * W];
    let mut big = 0.0f64;
    // Column i - k + p at v[p]; the row's entry j at p = d + j.
    for (j, &a) in e[..=k].iter().enumerate() {
        let p = d + j;
        if p + i >= k && p + i < m + k {
            v[p] = a;
            big = big.max(a.abs());
        }
    }
    f.fill(0.0);
    for p in k.saturating_sub(i)..k {
        let c = i + p - k;
        f[p] = v[p] * u[c][0];
        if f[p] != 0.0 {
            for j in 1..=k {
                v[p + j] -= f[p] * u[c][j];
            }
        }
    }
    push_pivot_row(k, &v, big, u)
}

/// The forward substitution of the current blocks of all windows (rows of DIM numbers), the
/// windows' rows in lockstep: each row waits for the row before it (a multiply and a
/// subtraction), so two windows' chains overlap. A row's right-hand side is its point's
/// value in `y` minus its multipliers times the K rows before it, which stay in registers
/// (a row's multiplier of a row before the window is zero); the result is appended to the
/// window's `b`.
#[inline(always)]
fn forward<const K: usize, const DIM: usize, const S: usize>(
    ws: &mut [Window; S],
    y: &[f64],
    nl: usize,
) {
    let mut prev = [[[0.0f64; DIM]; K]; S];
    for (w, prev) in ws.iter().zip(&mut prev) {
        let start = w.s0 - w.r0;
        for (p, row) in prev.iter_mut().enumerate() {
            if start + p >= K {
                let c = start + p - K;
                row.copy_from_slice(&w.b[c * DIM..(c + 1) * DIM]);
            }
        }
    }
    let n = ws.iter().map(|w| if w.failed { 0 } else { w.n }).max();
    for lane in 0..n.unwrap_or(0) {
        for (w, prev) in ws.iter_mut().zip(&mut prev) {
            if lane >= w.n || w.failed {
                continue;
            }
            let f = &w.lanes.factors[lane];
            let i = w.s0 + lane - nl;
            let mut v: [f64; DIM] = std::array::from_fn(|d| y[i * DIM + d]);
            for (fp, y) in f.iter().zip(prev.iter()) {
                for (v, y) in v.iter_mut().zip(y) {
                    *v -= fp * y;
                }
            }
            w.b.extend_from_slice(&v);
            for p in 1..K {
                prev[p - 1] = prev[p];
            }
            prev[K - 1] = v;
        }
    }
}

/// The back substitution with U over the forward-substituted right-hand sides of the
/// windows that did not fail (rows of DIM numbers), the windows' rows in lockstep (from each
/// window's last row), the rows `outs[w].rows` of window w's solution written to
/// `outs[w].out`. The K rows after the current one stay in registers (U's entries in
/// columns past the window are zero). Each row subtracts the farthest row's term first: the
/// row just solved enters last, so the chain from one row to the next is one multiply, one
/// subtraction and the scaling, whatever K; two windows' chains overlap.
#[inline(always)]
fn backward<const K: usize, const DIM: usize, const S: usize>(
    ws: &[Window; S],
    outs: &mut [Solution; S],
) {
    let m = ws.each_ref().map(|w| if w.failed { 0 } else { w.u.len() });
    // next[w][j - 1]: the solution of window w's row i + j.
    let mut next = [[[0.0f64; DIM]; K]; S];
    for step in 0..m.iter().copied().max().unwrap_or(0) {
        for (((w, to), next), &m) in ws.iter().zip(outs.iter_mut()).zip(&mut next).zip(&m) {
            if step >= m {
                continue;
            }
            let i = m - 1 - step;
            let row = &w.u[i];
            let mut v: [f64; DIM] = std::array::from_fn(|d| w.b[i * DIM + d]);
            for (uj, y) in row[1..=K].iter().zip(next.iter()).rev() {
                for (v, y) in v.iter_mut().zip(y) {
                    *v -= uj * y;
                }
            }
            v.iter_mut().for_each(|v| *v *= row[0]);
            if to.rows.contains(&i) {
                let o = (i - to.rows.start) * DIM;
                to.out[o..o + DIM].copy_from_slice(&v);
            }
            for j in (1..K).rev() {
                next[j] = next[j - 1];
            }
            next[0] = v;
        }
    }
}

/// [`backward`] of one window for any dimension `dim`, in `b`, then the rows `to.rows`
/// copied out.
fn backward_any(k: usize, u: &[[f64; W]], b: &mut [f64], to: &mut Solution, dim: usize) {
    let m = u.len();
    for i in (0..m).rev() {
        let (head, tail) = b.split_at_mut((i + 1) * dim);
        let x = &mut head[i * dim..];
        let row = &u[i];
        for j in (1..=k.min(m - 1 - i)).rev() {
            for (x, y) in x.iter_mut().zip(&tail[(j - 1) * dim..j * dim]) {
                *x -= row[j] * y;
            }
        }
        x.iter_mut().for_each(|x| *x *= row[0]);
    }
    to.out
        .copy_from_slice(&b[to.rows.start * dim..to.rows.end * dim]);
}

/// U's row from the eliminated row v (diagonal at v[k]): the reciprocal of the pivot and
/// the k entries right of it, appended to `u`; false when the pivot is not clearly
/// positive. (Written entry by entry into its place: a row assembled on the stack and
/// copied would be read back wider than it was written, which stalls.)
#[inline(always)]
fn push_pivot_row(k: usize, v: &[f64; 2 * W], big: f64, u: &mut Vec<[f64; W]>) -> bool {
    let pivot = v[k];
    if pivot.is_nan() || pivot <= TP_PIVOT * big {
        return false;
    }
    u.push([0.0; W]);
    let row = u.last_mut().expect("just pushed");
    row[0] = 1.0 / pivot;
    #[allow(clippy::manual_memcpy)] // the entries one by one, as said above
    for j in 1..=k {
        row[j] = v[k + j];
    }
    true
}
