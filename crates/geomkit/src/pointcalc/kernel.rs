//! Evaluation kernels of [`super::Hypersurface`]: [`LANES`] points at once, the points being
//! the inner (SIMD) dimension.
//!
//! For a block of points the cardinal functions of every factor are computed first, lane by
//! lane (one division per factor and point for n ≤ 16 nodes, the same operations as
//! [`Nodes::basis_into`], so the same values), then the source values are contracted with
//! them starting from the last (fastest-varying) factor: every source value is read once per
//! block and multiplied into all lanes (`Π n_i` multiply-adds per lane, then `Π_(i<k-1) n_i`,
//! ...). Rows of the last factor are unrolled by their number of levels (n ≤ 8) and 8 rows run
//! side by side so that the multiply-adds do not wait on each other.
//!
//! The multiply-adds are plain (`a · b + c`, two roundings) on baseline x86-64 and fused
//! (one rounding) where the CPU has AVX2 and FMA, chosen at run time by [`dispatch`] through
//! `pulp` (no `unsafe` here). A single point runs the same code with one lane, so batched and
//! single evaluation give the same bits on one machine.

use super::nodes::{Nodes, CANCEL, SMALL};

/// Most points per block of the batched evaluation (8 with AVX2+FMA or AVX-512, else 4).
pub(crate) const LANES: usize = 8;

/// Rows of the last factor contracted side by side.
const ROWS: usize = 8;

/// The multiply-add of the contractions.
pub(crate) trait Arith {
    /// acc[p] += a[p] · v for every lane p.
    fn madd_bcast<const L: usize>(acc: &mut [f64; L], a: &[f64; L], v: f64);
    /// acc[p] += a[p] · b[p] for every lane p.
    fn madd<const L: usize>(acc: &mut [f64; L], a: &[f64; L], b: &[f64; L]);
}

/// a · b + c with two roundings (any CPU).
pub(crate) struct Plain;

impl Arith for Plain {
    #[inline(always)]
    fn madd_bcast<const L: usize>(acc: &mut [f64; L], a: &[f64; L], v: f64) {
        for p in 0..L {
            acc[p] += a[p] * v;
        }
    }

    #[inline(always)]
    fn madd<const L: usize>(acc: &mut [f64; L], a: &[f64; L], b: &[f64; L]) {
        for p in 0..L {
            acc[p] += a[p] * b[p];
        }
    }
}

/// Fused multiply-add (one rounding); only run where the CPU has FMA (see [`dispatch`]),
/// elsewhere `mul_add` would be a slow library call.
#[cfg_attr(
    not(any(target_arch = "x86_64", target_arch = "aarch64")),
    allow(dead_code)
)]
pub(crate) struct Fused;

impl Arith for Fused {
    #[inline(always)]
    fn madd_bcast<const L: usize>(acc: &mut [f64; L], a: &[f64; L], v: f64) {
        for p in 0..L {
            acc[p] = a[p].mul_add(v, acc[p]);
        }
    }

    #[inline(always)]
    fn madd<const L: usize>(acc: &mut [f64; L], a: &[f64; L], b: &[f64; L]) {
        for p in 0..L {
            acc[p] = a[p].mul_add(b[p], acc[p]);
        }
    }
}

/// Work run with the best multiply-add of the CPU. `run` and everything it calls must be
/// `#[inline(always)]` so that it is compiled with the CPU features of [`dispatch`].
pub(crate) trait Job {
    /// The result.
    type Output;
    /// Runs with the multiply-add `A` and blocks of `L` points.
    fn run<A: Arith, const L: usize>(self) -> Self::Output;
}

/// Runs `job` compiled for the CPU (checked once, then cached by `pulp`): with AVX-512,
/// fused multiply-adds in blocks of 8 points (one 512-bit register); with AVX2+FMA, fused in
/// blocks of 8 (two 256-bit registers: half the loads per multiply-add of 4); otherwise
/// plain multiply-adds in blocks of 4 (SSE2 has too few registers for 8).
pub(crate) fn dispatch<J: Job>(job: J) -> J::Output {
    #[cfg(target_arch = "x86_64")]
    {
        struct Run<J, const L: usize>(J);
        impl<J: Job, const L: usize> pulp::NullaryFnOnce for Run<J, L> {
            type Output = J::Output;
            #[inline(always)]
            fn call(self) -> J::Output {
                self.0.run::<Fused, L>()
            }
        }
        if let Some(v4) = pulp::x86::V4::try_new() {
            return v4.vectorize(Run::<J, 8>(job));
        }
        if let Some(v3) = pulp::x86::V3::try_new() {
            return v3.vectorize(Run::<J, 8>(job));
        }
        job.run::<Plain, 4>()
    }
    #[cfg(target_arch = "aarch64")]
    {
        job.run::<Fused, 4>()
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    {
        job.run::<Plain, 4>()
    }
}

/// The grid of a model as the kernels see it.
pub(crate) struct Grid<'a> {
    /// Nodes of every factor.
    pub nodes: Vec<&'a Nodes>,
    /// Levels of every factor.
    pub shape: Vec<usize>,
    /// Start of factor f's cardinal functions in the flat basis buffers (k + 1 entries).
    pub offsets: Vec<usize>,
    /// Source values, row-major over the factors, `dim` per cell.
    pub values: &'a [f64],
    /// Numbers per source point.
    pub dim: usize,
    /// Π_(i<f) n_i for every factor f: the sums left after contracting factors f.. (no
    /// divisions per block).
    before: Vec<usize>,
}

impl<'a> Grid<'a> {
    /// The view of the factors' nodes and the values.
    pub fn new(nodes: Vec<&'a Nodes>, values: &'a [f64], dim: usize) -> Self {
        let shape: Vec<usize> = nodes.iter().map(|n| n.len()).collect();
        let mut offsets = vec![0];
        for n in &shape {
            offsets.push(offsets[offsets.len() - 1] + n);
        }
        let mut before = vec![1];
        for n in &shape[..shape.len() - 1] {
            before.push(before[before.len() - 1] * n);
        }
        Grid {
            nodes,
            shape,
            offsets,
            values,
            dim,
            before,
        }
    }

    /// Rows of the last factor: the length of the work buffer.
    fn rows(&self) -> usize {
        self.before[self.shape.len() - 1]
    }
}

/// Lane-major buffers of one block width: the cardinal functions and the work rows.
type Lanes<const L: usize> = (Vec<[f64; L]>, Vec<[f64; L]>);

/// Reusable buffers of one worker, for the block widths 8, 4 and 1 (sized on first use).
pub(crate) struct Buffers {
    total: usize,
    rows: usize,
    lanes8: Lanes<8>,
    lanes4: Lanes<4>,
    lanes1: Lanes<1>,
    tmp: Vec<f64>,
}

impl Buffers {
    /// Buffers for `grid`.
    pub fn new(grid: &Grid) -> Self {
        Buffers {
            total: grid.offsets[grid.offsets.len() - 1],
            rows: grid.rows(),
            lanes8: Default::default(),
            lanes4: Default::default(),
            lanes1: Default::default(),
            tmp: Vec::new(),
        }
    }

    /// The bases, work rows and scratch of block width L (1, 4 or 8).
    fn lanes<const L: usize>(&mut self) -> (&mut [[f64; L]], &mut [[f64; L]], &mut Vec<f64>) {
        use std::any::Any;
        let (total, rows) = (self.total, self.rows);
        let pair: &mut Lanes<L> = if let Some(p) = (&mut self.lanes8 as &mut dyn Any).downcast_mut()
        {
            p
        } else if let Some(p) = (&mut self.lanes4 as &mut dyn Any).downcast_mut() {
            p
        } else {
            (&mut self.lanes1 as &mut dyn Any)
                .downcast_mut()
                .expect("block widths are 1, 4 and 8")
        };
        pair.0.resize(total, [0.0; L]);
        pair.1.resize(rows, [0.0; L]);
        (&mut pair.0, &mut pair.1, &mut self.tmp)
    }
}

/// Evaluation at points `xs` (k numbers each) into `out` (dim each): blocks of L points, the rest one by one (the same operations per lane).
pub(crate) struct EvalPoints<'a, 'b> {
    pub grid: &'b Grid<'a>,
    pub xs: &'b [f64],
    pub out: &'b mut [f64],
    pub buffers: &'b mut Buffers,
}

impl Job for EvalPoints<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<A: Arith, const L: usize>(self) -> Self::Output {
        let EvalPoints {
            grid,
            xs,
            out,
            buffers: buf,
        } = self;
        let (k, d) = (grid.shape.len(), grid.dim);
        let blocks = xs.len() / k / L;
        if blocks > 0 {
            let (bases, work, tmp) = buf.lanes::<L>();
            for (x, o) in xs.chunks_exact(L * k).zip(out.chunks_exact_mut(L * d)) {
                eval_block::<A, L>(grid, x, bases, work, tmp, o);
            }
        }
        let done = blocks * L;
        if done * k < xs.len() {
            let (bases, work, tmp) = buf.lanes::<1>();
            for (x, o) in xs[done * k..]
                .chunks_exact(k)
                .zip(out[done * d..].chunks_exact_mut(d))
            {
                eval_block::<A, 1>(grid, x, bases, work, tmp, o);
            }
        }
    }
}

/// L points: their cardinal functions, then the contraction per component.
#[inline(always)]
fn eval_block<A: Arith, const L: usize>(
    grid: &Grid,
    xs: &[f64],
    bases: &mut [[f64; L]],
    work: &mut [[f64; L]],
    tmp: &mut Vec<f64>,
    out: &mut [f64],
) {
    let k = grid.shape.len();
    for f in 0..k {
        let t: [f64; L] = std::array::from_fn(|p| xs[p * k + f]);
        basis_lanes(
            grid.nodes[f],
            t,
            &mut bases[grid.offsets[f]..grid.offsets[f + 1]],
            tmp,
        );
    }
    let d = grid.dim;
    for c in 0..d {
        let r = contract::<A, L>(grid, bases, work, c);
        for p in 0..L {
            out[p * d + c] = r[p];
        }
    }
}

/// Σ over the grid of values[cell · dim + c] · Π_f bases_f[i_f] for L points.
#[inline(always)]
pub(crate) fn contract<A: Arith, const L: usize>(
    grid: &Grid,
    bases: &[[f64; L]],
    work: &mut [[f64; L]],
    c: usize,
) -> [f64; L] {
    let k = grid.shape.len();
    let last = &bases[grid.offsets[k - 1]..grid.offsets[k]];
    let mut reduce = k - 1;
    if k >= 2 && last.len() <= 8 && grid.shape[k - 2] == last.len() {
        // The last two factors in one pass: every row of the last factor goes straight into
        // its group's sum over the previous factor (nothing written per row).
        let prev = &bases[grid.offsets[k - 2]..grid.offsets[k - 1]];
        let work = &mut work[..grid.before[k - 2]];
        if grid.dim == 1 {
            innermost_pair::<A, L>(Source::scalar(grid.values), last, prev, work);
        } else {
            innermost_pair::<A, L>(Source::new(grid, c), last, prev, work);
        }
        reduce = k - 2;
    } else {
        let work = &mut work[..grid.before[k - 1]];
        if grid.dim == 1 {
            innermost::<A, L>(Source::scalar(grid.values), last, work);
        } else {
            innermost::<A, L>(Source::new(grid, c), last, work);
        }
    }
    for f in (0..reduce).rev() {
        let b = &bases[grid.offsets[f]..grid.offsets[f + 1]];
        let work = &mut work[..grid.before[f + 1]];
        match b.len() {
            2 => reduce_fixed::<A, 2, L>(b, work),
            3 => reduce_fixed::<A, 3, L>(b, work),
            4 => reduce_fixed::<A, 4, L>(b, work),
            5 => reduce_fixed::<A, 5, L>(b, work),
            6 => reduce_fixed::<A, 6, L>(b, work),
            7 => reduce_fixed::<A, 7, L>(b, work),
            8 => reduce_fixed::<A, 8, L>(b, work),
            _ => reduce_any::<A, L>(b, work),
        }
    }
    work[0]
}

/// work[j] = Σ_i b[i] · work[j·N + i] (lane by lane) for the N levels of a factor (`work`
/// holds a multiple of N sums).
#[inline(always)]
fn reduce_fixed<A: Arith, const N: usize, const L: usize>(b: &[[f64; L]], work: &mut [[f64; L]]) {
    let b: &[[f64; L]; N] = b.try_into().expect("N levels");
    reduce_any::<A, L>(b, work);
}

/// [`reduce_fixed`] for any number of levels.
#[inline(always)]
fn reduce_any<A: Arith, const L: usize>(b: &[[f64; L]], work: &mut [[f64; L]]) {
    let n = b.len();
    let mut j = 0;
    while (j + 1) * n <= work.len() {
        work[j] = lane_sum::<A, L>(b, &work[j * n..(j + 1) * n]);
        j += 1;
    }
}

/// Σ_i b[i] · group[i] lane by lane, in order.
#[inline(always)]
fn lane_sum<A: Arith, const L: usize>(b: &[[f64; L]], group: &[[f64; L]]) -> [f64; L] {
    let mut acc: [f64; L] = std::array::from_fn(|p| b[0][p] * group[0][p]);
    for i in 1..b.len() {
        A::madd(&mut acc, &b[i], &group[i]);
    }
    acc
}

/// [`row_sum`] of R consecutive rows of N levels (`block`: R · N · dim values), interleaved
/// so that the rows' multiply-adds do not wait on each other.
#[inline(always)]
fn rows_side_by_side<A: Arith, const N: usize, const R: usize, const L: usize>(
    b: &[[f64; L]; N],
    block: &[f64],
    dim: usize,
    c: usize,
) -> [[f64; L]; R] {
    let stride = N * dim;
    let mut acc: [[f64; L]; R] = std::array::from_fn(|r| {
        let v = block[r * stride + c];
        std::array::from_fn(|p| b[0][p] * v)
    });
    for i in 1..N {
        for r in 0..R {
            A::madd_bcast(&mut acc[r], &b[i], block[r * stride + i * dim + c]);
        }
    }
    acc
}

/// Σ_i b[i] · row[i·dim + c] (the value broadcast to the lanes), in order.
#[inline(always)]
fn row_sum<A: Arith, const L: usize>(
    b: &[[f64; L]],
    row: &[f64],
    dim: usize,
    c: usize,
) -> [f64; L] {
    let v = row[c];
    let mut acc: [f64; L] = std::array::from_fn(|p| b[0][p] * v);
    for i in 1..b.len() {
        A::madd_bcast(&mut acc, &b[i], row[i * dim + c]);
    }
    acc
}

/// Component c of the source values (`dim` per cell).
#[derive(Clone, Copy)]
struct Source<'a> {
    values: &'a [f64],
    dim: usize,
    c: usize,
}

impl<'a> Source<'a> {
    /// Component c of the grid's values.
    #[inline(always)]
    fn new(grid: &Grid<'a>, c: usize) -> Self {
        Source {
            values: grid.values,
            dim: grid.dim,
            c,
        }
    }

    /// One number per cell (the constants let the compiler drop the strides).
    #[inline(always)]
    fn scalar(values: &'a [f64]) -> Self {
        Source {
            values,
            dim: 1,
            c: 0,
        }
    }
}

/// work[g] = Σ_r prev[r] Σ_i last[i] · values[((g·m + r)·n + i)·dim + c] for every group g
/// of n rows (n ≤ 8 levels of both the previous and the last factor).
#[inline(always)]
fn innermost_pair<A: Arith, const L: usize>(
    src: Source,
    last: &[[f64; L]],
    prev: &[[f64; L]],
    work: &mut [[f64; L]],
) {
    match last.len() {
        1 => pair_fixed::<A, 1, L>(src, last, prev, work),
        2 => pair_fixed::<A, 2, L>(src, last, prev, work),
        3 => pair_fixed::<A, 3, L>(src, last, prev, work),
        4 => pair_fixed::<A, 4, L>(src, last, prev, work),
        5 => pair_fixed::<A, 5, L>(src, last, prev, work),
        6 => pair_fixed::<A, 6, L>(src, last, prev, work),
        7 => pair_fixed::<A, 7, L>(src, last, prev, work),
        _ => pair_fixed::<A, 8, L>(src, last, prev, work),
    }
}

/// [`innermost_pair`] for N levels (unrolled): the N rows of a group side by side, so that
/// their multiply-adds do not wait on each other, then their sum over the previous factor.
#[inline(always)]
fn pair_fixed<A: Arith, const N: usize, const L: usize>(
    src: Source,
    last: &[[f64; L]],
    prev: &[[f64; L]],
    work: &mut [[f64; L]],
) {
    let b: &[[f64; L]; N] = last.try_into().expect("N levels");
    let bp: &[[f64; L]; N] = prev.try_into().expect("N levels");
    let Source { values, dim, c } = src;
    let stride = N * dim;
    for (g, w) in work.iter_mut().enumerate() {
        let group = &values[g * N * stride..(g + 1) * N * stride];
        let acc = rows_side_by_side::<A, N, N, L>(b, group, dim, c);
        *w = lane_sum::<A, L>(bp, &acc);
    }
}

/// work[r] = Σ_i b[i] · values[(r·n + i)·dim + c] for every row r of the last factor.
#[inline(always)]
fn innermost<A: Arith, const L: usize>(src: Source, b: &[[f64; L]], work: &mut [[f64; L]]) {
    match b.len() {
        1 => rows_fixed::<A, 1, L>(src, b, work),
        2 => rows_fixed::<A, 2, L>(src, b, work),
        3 => rows_fixed::<A, 3, L>(src, b, work),
        4 => rows_fixed::<A, 4, L>(src, b, work),
        5 => rows_fixed::<A, 5, L>(src, b, work),
        6 => rows_fixed::<A, 6, L>(src, b, work),
        7 => rows_fixed::<A, 7, L>(src, b, work),
        8 => rows_fixed::<A, 8, L>(src, b, work),
        _ => rows_any::<A, L>(src, b, work),
    }
}

/// [`innermost`] for N levels: ROWS rows side by side, the sum over the levels unrolled.
#[inline(always)]
fn rows_fixed<A: Arith, const N: usize, const L: usize>(
    src: Source,
    b: &[[f64; L]],
    work: &mut [[f64; L]],
) {
    let b: &[[f64; L]; N] = b.try_into().expect("N levels");
    let Source { values, dim, c } = src;
    let stride = N * dim;
    let rows = work.len();
    let full = rows / ROWS * ROWS;
    for r0 in (0..full).step_by(ROWS) {
        let block = &values[r0 * stride..(r0 + ROWS) * stride];
        let acc = rows_side_by_side::<A, N, ROWS, L>(b, block, dim, c);
        work[r0..r0 + ROWS].copy_from_slice(&acc);
    }
    for r in full..rows {
        work[r] = row_sum::<A, L>(b, &values[r * stride..(r + 1) * stride], dim, c);
    }
}

/// [`innermost`] for any number of levels.
#[inline(always)]
fn rows_any<A: Arith, const L: usize>(src: Source, b: &[[f64; L]], work: &mut [[f64; L]]) {
    let Source { values, dim, c } = src;
    let stride = b.len() * dim;
    for (r, w) in work.iter_mut().enumerate() {
        *w = row_sum::<A, L>(b, &values[r * stride..(r + 1) * stride], dim, c);
    }
}

/// The cardinal functions of `nodes` at L parameters: `out[j][p]` = ℓ_j(t[p]), bit for bit
/// what [`Nodes::basis_into`] gives (the one-division product form lane by lane; lanes
/// outside the node interval, on a node or with products out of range go through
/// `basis_into` itself).
#[inline(always)]
pub(crate) fn basis_lanes<const L: usize>(
    nodes: &Nodes,
    t: [f64; L],
    out: &mut [[f64; L]],
    tmp: &mut Vec<f64>,
) {
    let n = nodes.len();
    if n == 1 {
        out[0] = [1.0; L];
        return;
    }
    if n > SMALL {
        for p in 0..L {
            basis_lane(nodes, t[p], p, out, tmp);
        }
        return;
    }
    match n {
        2 => basis_fixed::<2, L>(nodes, t, out, tmp),
        3 => basis_fixed::<3, L>(nodes, t, out, tmp),
        4 => basis_fixed::<4, L>(nodes, t, out, tmp),
        5 => basis_fixed::<5, L>(nodes, t, out, tmp),
        6 => basis_fixed::<6, L>(nodes, t, out, tmp),
        7 => basis_fixed::<7, L>(nodes, t, out, tmp),
        8 => basis_fixed::<8, L>(nodes, t, out, tmp),
        _ => basis_fixed::<SMALL, L>(nodes, t, out, tmp),
    }
}

/// [`basis_lanes`] for up to N nodes (exactly N when N < SMALL), unrolled: q_j = w_j Π_(i<j)
/// (t - t_i) Π_(i>j) (t - t_i), ℓ_j = q_j / Σ q_i, in the order of `Nodes::basis_small`.
#[inline(always)]
fn basis_fixed<const N: usize, const L: usize>(
    nodes: &Nodes,
    t: [f64; L],
    out: &mut [[f64; L]],
    tmp: &mut Vec<f64>,
) {
    let (x, w) = (nodes.values(), nodes.weights());
    let n = x.len().min(N);
    let mut prefix = [[1.0f64; L]; N];
    let mut run = [1.0f64; L];
    for j in 0..n {
        prefix[j] = run;
        let xj = x[j];
        for p in 0..L {
            run[p] *= t[p] - xj;
        }
    }
    let mut suffix = [1.0f64; L];
    let mut sum = [0.0f64; L];
    let mut size = [0.0f64; L];
    for j in (0..n).rev() {
        let (xj, wj) = (x[j], w[j]);
        for p in 0..L {
            let q = wj * prefix[j][p] * suffix[p];
            out[j][p] = q;
            sum[p] += q;
            size[p] += q.abs();
            suffix[p] *= t[p] - xj;
        }
    }
    let mut inv = [0.0f64; L];
    for p in 0..L {
        inv[p] = 1.0 / sum[p];
    }
    for o in out[..n].iter_mut() {
        for p in 0..L {
            o[p] *= inv[p];
        }
    }
    // Lanes outside the node interval, on a node, or with the sum out of the normal range
    // or cancelled (NaN fails every comparison) go through `basis_into`.
    let (lo, hi) = nodes.domain();
    let regular = |p: usize| {
        let a = sum[p].abs();
        (lo..=hi).contains(&t[p])
            && run[p] != 0.0
            && (f64::MIN_POSITIVE..f64::INFINITY).contains(&a)
            && a >= CANCEL * size[p]
    };
    let mut all = true;
    for p in 0..L {
        all &= regular(p);
    }
    if !all {
        for p in 0..L {
            if !regular(p) {
                basis_lane(nodes, t[p], p, out, tmp);
            }
        }
    }
}

/// Lane p of [`basis_lanes`] by [`Nodes::basis_into`].
#[cold]
fn basis_lane<const L: usize>(
    nodes: &Nodes,
    t: f64,
    p: usize,
    out: &mut [[f64; L]],
    tmp: &mut Vec<f64>,
) {
    tmp.resize(nodes.len(), 0.0);
    nodes.basis_into(t, tmp);
    for (o, v) in out.iter_mut().zip(tmp.iter()) {
        o[p] = *v;
    }
}

/// The instruction set the k-factor evaluation kernels run with on this CPU:
/// `"avx512"` (fused multiply-adds, blocks of 8 points), `"avx2+fma"` (fused, blocks of 8),
/// `"fma"` (aarch64), or `"baseline"` (plain multiply-adds, blocks of 4; what x86-64 without
/// AVX2 gets). Chosen at run time; results differ between them only by rounding.
///
/// ```
/// let isa = geomkit::pointcalc::evaluation_isa();
/// assert!(["avx512", "avx2+fma", "fma", "baseline"].contains(&isa));
/// ```
pub fn evaluation_isa() -> &'static str {
    #[cfg(target_arch = "x86_64")]
    {
        if pulp::x86::V4::try_new().is_some() {
            return "avx512";
        }
        if pulp::x86::V3::try_new().is_some() {
            return "avx2+fma";
        }
        "baseline"
    }
    #[cfg(target_arch = "aarch64")]
    {
        "fma"
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    {
        "baseline"
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pointcalc::{Factor, Hypersurface, NodePreset, PointOptions};

    /// Every block width with plain multiply-adds (the baseline path, whatever this CPU
    /// has) against one point at a time: the same operations per lane, so the same bits.
    #[test]
    fn every_block_width_matches_single_points() {
        for shape in [
            &[3usize][..],
            &[17],
            &[4, 4],
            &[3, 9],
            &[3, 3, 3],
            &[2, 5, 5],
            &[7, 7, 7],
            &[3, 5, 2, 7],
        ] {
            for dim in [1, 2] {
                let factors: Vec<Factor> = shape
                    .iter()
                    .enumerate()
                    .map(|(f, &n)| {
                        let nodes = Nodes::preset(NodePreset::ChebyshevFirst, n, -1.0, 2.0);
                        Factor::new(format!("x{f}"), nodes.unwrap())
                    })
                    .collect();
                let m = Hypersurface::from_fn(
                    factors,
                    dim,
                    |x, o| {
                        for (c, v) in o.iter_mut().enumerate() {
                            *v = (x.iter().sum::<f64>() * (c + 1) as f64).cos();
                        }
                    },
                    &PointOptions::default(),
                )
                .unwrap();
                let grid = Grid::new(
                    m.factors().iter().map(|f| f.nodes()).collect(),
                    m.values(),
                    dim,
                );
                let k = shape.len();
                let count = 19;
                let nodes0 = m.factors()[0].nodes().values();
                let xs: Vec<f64> = (0..count * k)
                    .map(|i| match i % 5 {
                        0 => nodes0[i % nodes0.len()],
                        1 => -1.7 + (i as f64 * 0.29) % 4.5,
                        _ => -1.0 + (i as f64 * 0.618) % 3.0,
                    })
                    .collect();
                let run = |l: usize| {
                    let mut out = vec![0.0; count * dim];
                    let mut buffers = Buffers::new(&grid);
                    let job = EvalPoints {
                        grid: &grid,
                        xs: &xs,
                        out: &mut out,
                        buffers: &mut buffers,
                    };
                    match l {
                        1 => job.run::<Plain, 1>(),
                        4 => job.run::<Plain, 4>(),
                        _ => job.run::<Plain, 8>(),
                    }
                    out
                };
                let single = run(1);
                assert_eq!(run(4), single, "{shape:?} dim {dim}");
                assert_eq!(run(8), single, "{shape:?} dim {dim}");
                let exact = m.eval(&xs[..k]).unwrap();
                assert!((single[0] - exact[0]).abs() < 1e-12, "{shape:?}");
            }
        }
    }
}
