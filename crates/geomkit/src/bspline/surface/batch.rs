//! Scattered evaluation of surfaces in batches ([`BsplineSurface::eval_many_par`]).
//!
//! Points go through a kernel in blocks of [`BLOCK`]: first the knot spans of all of them in
//! u and in v, then the memory every evaluation will read is touched (so that cache misses
//! overlap instead of queueing one per point), then the basis values of the whole block,
//! direction by direction, lane by lane (vectorized: the six reciprocals of the cubic
//! Cox–de Boor recursion on non-uniform knots cost no more than a uniform basis), and last
//! the contraction with the net. Large batches on nets larger than the caches are first
//! grouped by blocks of spans in u ([`BsplineSurface::eval_grouped`]), and the net rows a
//! group needs are then read in order, once, the next ones prefetched while it evaluates.

use super::BsplineSurface;
use crate::bspline::locate::{with_avx2, CubicLanes, Locator, Prefetcher, BLOCK};
use crate::par::*;

/// Scattered points on nets larger than this (a core's L2 cache) touch what they read
/// before evaluating.
const PIECES_MIN_NET_BYTES: usize = 512 << 10;
/// Scattered batches from this many points on are grouped by span.
const GROUPED_MIN_POINTS: usize = 1 << 14;
/// ... on nets of at least this size (smaller ones stay in the caches anyway).
const GROUPED_MIN_NET_BYTES: usize = 4 << 20;
/// ... and the net rows of one group of spans take about this much: well inside a core's
/// L2 cache with the points and the tables beside them, so that a group of points reads
/// only cached rows, and few enough groups that sorting points into them streams.
const GROUP_BYTES: usize = 256 << 10;
/// Points sorted together by group, in their own region (16 bytes each).
const SORT_CHUNK: usize = 1 << 15;

/// Net rows requested ahead of the points being evaluated (points grouped by span in u) ...
const ROWS_AHEAD: usize = 6;
/// ... a few cache lines per point evaluated, so that the requests spread over the
/// arithmetic instead of stalling it in bursts.
const LINES_PER_POINT: usize = 5;

/// One chunk of points of [`BsplineSurface::eval_grouped`], sorted by group of spans in u.
struct SortedChunk {
    /// Where each group starts in `pairs` (one entry more than there are groups).
    start: Vec<u32>,
    /// The points (u, v), group by group.
    pairs: Vec<[f64; 2]>,
    /// Where each of the chunk's points went in `pairs`.
    pos: Vec<u32>,
}

/// How a block touches the net before evaluating.
#[derive(Clone, Copy)]
enum Touch {
    /// Not at all (nets that stay in a core's cache).
    Nothing,
    /// The four row pieces each point reads (scattered points).
    Pieces,
    /// The net in order (points grouped by span in u): the rows a block needs are read if
    /// not yet requested, and [`ROWS_AHEAD`] more are requested (prefetched on x86-64) a
    /// few lines per point evaluated; `next` is the first net value not yet requested.
    Rows { next: usize },
}

impl BsplineSurface {
    /// Evaluates at scattered points (us\[k\], vs\[k\]) into `out` (row-major, `dim` per
    /// point), in parallel, bicubic surfaces of dimension 1 to 3 in vectorized blocks (see
    /// the module notes); spans are found as [`crate::bspline::BsplineCurve::eval_many_par`]
    /// finds them: by one multiplication on uniform knots, from a bucket table or a binary
    /// search otherwise. Large batches on nets larger than the caches are first grouped by
    /// blocks of spans in u (a counting sort), so that the points of one group read the
    /// same few rows of the net: the net then streams through the cache once instead of
    /// every point missing it (and the TLB) several times. Each point gives the same value,
    /// bit for bit, in any batch and in any order; it differs from
    /// [`BsplineSurface::eval_into`] only by the rounding of the summation order. Errors:
    /// `us` and `vs` of different lengths, wrong buffer length, non-finite parameters.
    ///
    /// ```
    /// use geomkit::bspline::{interpolate_heights, EndCondition};
    /// let z: Vec<f64> = (0..20).map(|k| ((k / 5) * (k % 5)) as f64).collect();
    /// let s = interpolate_heights(&z, 4, 5, (0.0, 0.0), (1.0, 1.0), &EndCondition::NotAKnot).unwrap();
    /// let mut out = [0.0; 2];
    /// s.eval_many_par(&[1.0, 2.5], &[3.0, 0.5], &mut out).unwrap();
    /// assert!((out[0] - 3.0).abs() < 1e-12 && (out[1] - 1.25).abs() < 1e-12);
    /// ```
    pub fn eval_many_par(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> crate::Result<()> {
        let d = self.dim;
        if us.len() != vs.len() {
            return Err(crate::Error::BufferSize {
                expected: us.len(),
                got: vs.len(),
            });
        }
        crate::points::check_eval_args("parameter u", us, us.len(), d, out)?;
        crate::points::check_eval_args("parameter v", vs, vs.len(), d, out)?;
        let n = us.len();
        let (lu, lv) = self.locators(n);
        if self.grouped(n) {
            self.eval_grouped(&lu, &lv, us, vs, out);
            return Ok(());
        }
        let touch = self.scattered_touch();
        out.par_chunks_mut(4096 * d)
            .zip(us.par_chunks(4096).zip(vs.par_chunks(4096)))
            .for_each(|(o, (us, vs))| {
                let pts = us.iter().zip(vs).map(|(&u, &v)| [u, v]);
                let mut touch = touch;
                self.eval_run(&lu, &lv, pts, o.chunks_exact_mut(d), &mut touch);
            });
        Ok(())
    }

    /// Whether a batch of `n` points is grouped by span: reading ahead every row of the net
    /// pays when each span in u has enough points.
    fn grouped(&self, n: usize) -> bool {
        let net_bytes = std::mem::size_of_val(&self.control[..]);
        n >= GROUPED_MIN_POINTS && n >= 32 * self.n_u && net_bytes >= GROUPED_MIN_NET_BYTES
    }

    /// How scattered points touch the net before evaluating.
    fn scattered_touch(&self) -> Touch {
        if std::mem::size_of_val(&self.control[..]) > PIECES_MIN_NET_BYTES {
            Touch::Pieces
        } else {
            Touch::Nothing
        }
    }

    /// [`BsplineSurface::eval_many_par`] at interleaved pairs `uv = [u0, v0, u1, v1, ...]`
    /// (the [`crate::geom::Surface::eval_batch`] of the surface), on the thread pool only
    /// when `parallel`: the same kernels, the same bits. Errors: as
    /// [`crate::geom::Surface::eval_batch`].
    pub(crate) fn eval_pairs(
        &self,
        uv: &[f64],
        out: &mut [f64],
        parallel: bool,
    ) -> crate::Result<()> {
        let d = self.dim;
        crate::geom::check_pairs(uv, d, out)?;
        let n = uv.len() / 2;
        if parallel && self.grouped(n) {
            let (us, vs): (Vec<f64>, Vec<f64>) = uv.chunks_exact(2).map(|q| (q[0], q[1])).unzip();
            let (lu, lv) = self.locators(n);
            self.eval_grouped(&lu, &lv, &us, &vs, out);
            return Ok(());
        }
        let (lu, lv) = self.locators(n);
        let touch = self.scattered_touch();
        let run = |o: &mut [f64], q: &[f64]| {
            let pts = q.chunks_exact(2).map(|p| [p[0], p[1]]);
            let mut touch = touch;
            self.eval_run(&lu, &lv, pts, o.chunks_exact_mut(d), &mut touch);
        };
        crate::par::zip_chunks(parallel && n > 4096, out, 4096 * d, uv, 8192, run);
        Ok(())
    }

    /// S(u, v) by the batch kernel (the value every batch gives at this point).
    pub(crate) fn eval_point_batched(&self, u: f64, v: f64, out: &mut [f64]) {
        let (lu, lv) = self.locators(1);
        let mut touch = Touch::Nothing;
        self.eval_run(
            &lu,
            &lv,
            std::iter::once([u, v]),
            std::iter::once(out),
            &mut touch,
        );
    }

    /// Span locators in u and v for `count` points: the spans of
    /// [`BsplineSurface::eval_into`] (one multiplication on uniform knots of cubics).
    fn locators(&self, count: usize) -> (Locator<'_>, Locator<'_>) {
        let (p, q) = self.degree;
        let (iu, iv) = self.inv_steps;
        (
            Locator::new(&self.knots_u, p, self.n_u, iu.filter(|_| p == 3), count),
            Locator::new(&self.knots_v, q, self.n_v, iv.filter(|_| q == 3), count),
        )
    }

    /// [`BsplineSurface::eval_many_par`] for large batches, in three parallel passes:
    /// 1. every chunk of [`SORT_CHUNK`] points is sorted by group of spans in u into a
    ///    [`SortedChunk`] (a counting sort whose writes stay within the chunk's buffers,
    ///    allocated and zeroed by the thread that then fills them, so in its cache: into
    ///    regions of one buffer zeroed ahead, the scattered writes missed the caches and a
    ///    chunk took ~0.9 ms instead of ~0.25);
    /// 2. runs of consecutive groups are evaluated in parallel, each reading its groups'
    ///    points from every chunk and the net rows they need in order (which the hardware
    ///    prefetches), and writing their values where the points were sorted to;
    /// 3. every point picks its value up from its chunk's region.
    fn eval_grouped(&self, lu: &Locator, lv: &Locator, us: &[f64], vs: &[f64], out: &mut [f64]) {
        let d = self.dim;
        let n = us.len();
        let row_bytes = self.n_v * d * std::mem::size_of::<f64>();
        // Spans per group: a power of two, found by a shift.
        let shift = (GROUP_BYTES / row_bytes)
            .saturating_sub(self.degree.0)
            .max(1)
            .ilog2();
        let groups = ((lu.hi - lu.lo) >> shift) + 1;
        let group = |u: f64| (lu.span(u, lu.lo) - lu.lo) >> shift;
        // 1. Chunk by chunk.
        let sorted: Vec<SortedChunk> = us
            .par_chunks(SORT_CHUNK)
            .zip(vs.par_chunks(SORT_CHUNK))
            .map(|(us, vs)| {
                let ids: Vec<u32> = us.iter().map(|&u| group(u) as u32).collect();
                let mut start = vec![0u32; groups + 1];
                for &g in &ids {
                    start[g as usize + 1] += 1;
                }
                for g in 0..groups {
                    start[g + 1] += start[g];
                }
                let mut next = start[..groups].to_vec();
                let mut pairs = vec![[0.0f64; 2]; us.len()];
                let pos = ids
                    .iter()
                    .zip(us.iter().zip(vs))
                    .map(|(&g, (&u, &v))| {
                        let k = &mut next[g as usize];
                        pairs[*k as usize] = [u, v];
                        *k += 1;
                        *k - 1
                    })
                    .collect();
                SortedChunk { start, pairs, pos }
            })
            .collect();
        // 2. The values, in the layout of `sorted`: one slice per (group, chunk), arranged
        // by group, then handed out in runs of groups with about equal numbers of points.
        let mut results = vec![0.0; n * d];
        let mut per_group: Vec<Vec<&mut [f64]>> = (0..groups)
            .map(|_| Vec::with_capacity(sorted.len()))
            .collect();
        for (chunk, mut rest) in sorted.iter().zip(results.chunks_mut(SORT_CHUNK * d)) {
            for (g, slices) in per_group.iter_mut().enumerate() {
                let len = (chunk.start[g + 1] - chunk.start[g]) as usize * d;
                let (here, tail) = std::mem::take(&mut rest).split_at_mut(len);
                slices.push(here);
                rest = tail;
            }
        }
        let target = n.div_ceil(8 * crate::par::current_num_threads()).max(1);
        let mut runs = Vec::new();
        let mut first = 0;
        while !per_group.is_empty() {
            let mut len = 0;
            let mut points = 0;
            while len < per_group.len() && points < target {
                points += per_group[len].iter().map(|s| s.len()).sum::<usize>() / d;
                len += 1;
            }
            runs.push((first, per_group.drain(..len).collect::<Vec<_>>()));
            first += len;
        }
        let sorted = &sorted;
        runs.into_par_iter().for_each(|(first, slices)| {
            // Group by group: its points from every chunk side by side, evaluated, and
            // the values put where the points came from.
            let mut touch = Touch::Rows { next: 0 };
            let (mut pts, mut vals) = (Vec::new(), Vec::new());
            for (g, slices) in (first..).zip(slices) {
                pts.clear();
                for chunk in sorted {
                    let (a, b) = (chunk.start[g] as usize, chunk.start[g + 1] as usize);
                    pts.extend_from_slice(&chunk.pairs[a..b]);
                }
                vals.resize(pts.len() * d, 0.0);
                self.eval_run(
                    lu,
                    lv,
                    pts.iter().copied(),
                    vals.chunks_exact_mut(d),
                    &mut touch,
                );
                let mut from = &vals[..];
                for s in slices {
                    let (here, rest) = from.split_at(s.len());
                    s.copy_from_slice(here);
                    from = rest;
                }
            }
        });
        // 3. Back to the input order.
        out.par_chunks_mut(SORT_CHUNK * d)
            .zip(sorted.par_iter())
            .zip(results.par_chunks(SORT_CHUNK * d))
            .for_each(|((out, chunk), values)| {
                for (o, &k) in out.chunks_exact_mut(d).zip(&chunk.pos) {
                    let k = k as usize * d;
                    o.copy_from_slice(&values[k..k + d]);
                }
            });
    }

    /// Evaluates the points `pts` into `outs` (one slice of dim values per point).
    fn eval_run<'o>(
        &self,
        lu: &Locator,
        lv: &Locator,
        pts: impl Iterator<Item = [f64; 2]>,
        outs: impl Iterator<Item = &'o mut [f64]>,
        touch: &mut Touch,
    ) {
        match (self.degree, self.dim) {
            ((3, 3), 1) => with_avx2(
                #[inline(always)]
                || self.eval_run_cubic::<1>(lu, lv, pts, outs, touch),
            ),
            ((3, 3), 2) => with_avx2(
                #[inline(always)]
                || self.eval_run_cubic::<2>(lu, lv, pts, outs, touch),
            ),
            ((3, 3), 3) => with_avx2(
                #[inline(always)]
                || self.eval_run_cubic::<3>(lu, lv, pts, outs, touch),
            ),
            _ => {
                let (mut hu, mut hv) = (lu.lo, lv.lo);
                for ([u, v], o) in pts.zip(outs) {
                    hu = lu.span(u, hu);
                    hv = lv.span(v, hv);
                    self.eval_spans_into(hu, hv, u, v, o);
                }
            }
        }
    }

    /// The bicubic kernel of [`BsplineSurface::eval_run`] in dimension D, block by block
    /// (compiled for AVX2 through [`with_avx2`]).
    #[inline(always)]
    fn eval_run_cubic<'o, const D: usize>(
        &self,
        lu: &Locator,
        lv: &Locator,
        mut pts: impl Iterator<Item = [f64; 2]>,
        mut outs: impl Iterator<Item = &'o mut [f64]>,
        touch: &mut Touch,
    ) {
        let (mut bu, mut bv) = (CubicLanes::new(), CubicLanes::new());
        let row = self.n_v * D;
        let c = &self.control;
        let mut touched = 0u64;
        #[cfg(target_arch = "x86_64")]
        let sse = pulp::core_arch::x86::Sse::try_new();
        let fetch = Prefetcher::new();
        let mut ahead = 0;
        loop {
            let mut n = 0;
            for (i, [u, v]) in pts.by_ref().take(BLOCK).enumerate() {
                bu.x[i] = u;
                bv.x[i] = v;
                n = i + 1;
            }
            if n == 0 {
                break;
            }
            // The knots and span tables of a net's directions are small enough to stay in
            // the caches: no rounds that touch them ahead.
            bu.locate(lu, n, false, &mut touched, |_| 0);
            bv.locate(lv, n, false, &mut touched, |_| 0);
            match touch {
                Touch::Nothing => {}
                Touch::Pieces => {
                    for (&su, &sv) in bu.span[..n].iter().zip(&bv.span[..n]) {
                        for a in 0..4 {
                            let k = (su - 3 + a) * row + (sv - 3) * D;
                            touched ^= c[k].to_bits() ^ c[k + 4 * D - 1].to_bits();
                        }
                        CubicLanes::touch_knots(lu, su, fetch, &mut touched);
                        CubicLanes::touch_knots(lv, sv, fetch, &mut touched);
                    }
                }
                Touch::Rows { next } => {
                    // Rows the block needs and no earlier block requested: read now.
                    let (lo, hi) = bu.span[..n]
                        .iter()
                        .fold((usize::MAX, 0), |(a, b), &s| (a.min(s), b.max(s)));
                    let need = (hi + 1) * row;
                    if *next < need {
                        let first = (*next).max((lo - 3) * row);
                        for x in c[first..need].iter().step_by(8) {
                            touched ^= x.to_bits();
                        }
                        *next = need;
                    }
                    ahead = ((hi + 1 + ROWS_AHEAD) * row).min(c.len());
                }
            }
            bu.basis(lu, n);
            bv.basis(lv, n);
            // Per point: the four row pieces combined with the weights in u (whole pieces
            // at a time, which vectorizes), then their D-vectors with the weights in v.
            for (i, o) in outs.by_ref().take(n).enumerate() {
                #[cfg(target_arch = "x86_64")]
                if let (Touch::Rows { next }, Some(sse)) = (&mut *touch, sse) {
                    // A few lines of the rows ahead per point, requested without waiting.
                    for _ in 0..LINES_PER_POINT {
                        if *next < ahead {
                            let line = std::ptr::from_ref(&c[*next]).cast();
                            sse._mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(line);
                            *next += 8;
                        }
                    }
                }
                let (su, sv) = (bu.span[i], bv.span[i]);
                let piece = |a: usize| {
                    let k = (su - 3 + a) * row + (sv - 3) * D;
                    &c[k..k + 4 * D]
                };
                let mut comb = [0.0f64; 12];
                let comb = &mut comb[..4 * D];
                for (m, x) in comb.iter_mut().zip(piece(0)) {
                    *m = bu.basis[0][i] * x;
                }
                for a in 1..4 {
                    for (m, x) in comb.iter_mut().zip(piece(a)) {
                        *m += bu.basis[a][i] * x;
                    }
                }
                for (j, o) in o.iter_mut().enumerate().take(D) {
                    *o = bv.basis[0][i] * comb[j]
                        + bv.basis[1][i] * comb[D + j]
                        + bv.basis[2][i] * comb[2 * D + j]
                        + bv.basis[3][i] * comb[3 * D + j];
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = ahead;
        std::hint::black_box(touched);
    }
}
