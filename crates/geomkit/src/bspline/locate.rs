//! Knot spans and cubic basis values for batches of parameters, shared by the batched curve
//! and surface evaluations. Spans: one multiplication on uniform knots, a bucket table over
//! the domain for large batches on other knots, a binary search otherwise; always
//! [`find_span`](super::curve::find_span)'s span. Basis values: lane by lane over a block of parameters, which
//! vectorizes (on non-uniform knots the six reciprocals of the cubic Cox–de Boor recursion
//! then cost about as much as a uniform basis).

use std::sync::OnceLock;

use super::curve::{basis_funs_cubic, domain_spans, uniform_cubic_basis, uniform_span};

/// Parameters per block of the batched cubic kernels: first the spans of all of them,
/// touching the memory each will read, then their basis values, then the evaluations.
/// Unsorted parameters make every access a cache miss; issued together the misses overlap
/// instead of queueing one per point.
pub(super) const BLOCK: usize = 64;

/// The most knots a sorted block may cross for [`CubicLanes::locate_sorted`] (a count per
/// knot and lane beyond that would cost more than the table's lookup).
const SORTED_SPANS: usize = 16;

/// Runs `kernel` compiled for the CPU's AVX2 where it has it (checked once by `pulp`), else
/// as it is. The batched kernels use no fused multiply-adds, so they give the same bits
/// either way, in wider instructions. To be compiled for AVX2, the kernel and the closure
/// that calls it must be `#[inline(always)]` (`with_avx2(#[inline(always)] || kernel(..))`).
#[inline(always)]
pub(super) fn with_avx2(kernel: impl FnOnce()) {
    #[cfg(target_arch = "x86_64")]
    if let Some(v3) = pulp::x86::V3::try_new() {
        return v3.vectorize(kernel);
    }
    kernel()
}

/// [`with_avx2`], preferring AVX-512 where the CPU has it (the same bits: no fused
/// multiply-adds either way). Measured for the cubic evaluation kernel on an AMD EPYC with
/// AVX-512: 11 % faster on one thread (10^7 sorted points); the other kernels keep AVX2.
#[inline(always)]
pub(super) fn with_avx512(kernel: impl FnOnce()) {
    #[cfg(target_arch = "x86_64")]
    if let Some(v4) = pulp::x86::V4::try_new() {
        return v4.vectorize(kernel);
    }
    with_avx2(kernel)
}

/// Brings the cache line of a value closer ahead of its use: a prefetch request, which does
/// not wait for the line (x86-64), else a read of the value folded into `touched`.
#[derive(Clone, Copy)]
pub(super) struct Prefetcher {
    #[cfg(target_arch = "x86_64")]
    sse: Option<pulp::core_arch::x86::Sse>,
}

impl Prefetcher {
    pub(super) fn new() -> Self {
        Prefetcher {
            #[cfg(target_arch = "x86_64")]
            sse: pulp::core_arch::x86::Sse::try_new(),
        }
    }

    #[inline(always)]
    pub(super) fn touch(self, x: &f64, touched: &mut u64) {
        #[cfg(target_arch = "x86_64")]
        if let Some(sse) = self.sse {
            let line = std::ptr::from_ref(x).cast();
            return sse._mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(line);
        }
        *touched ^= x.to_bits();
    }
}

/// Finds knot spans for batches of parameters along one direction.
///
/// Non-uniform knots and large batches use a bucket table over the domain: t falls in bucket
/// b = floor((t - start)·inv_width), which is monotone in t, so every interior knot in an
/// earlier bucket is <= t and every knot in a later one > t. A bucket stores the span that
/// count gives and how many knots it holds itself (usually at most one): the span is then
/// one comparison away, without a branch that unsorted parameters would mispredict, and
/// equal to [`find_span`](super::curve::find_span)'s.
pub(super) struct Locator<'a> {
    pub(super) knots: &'a [f64],
    degree: usize,
    n_control: usize,
    /// First and last span of the domain.
    pub(super) lo: usize,
    pub(super) hi: usize,
    /// Uniform knots: the reciprocal of the spacing (the span by one multiplication).
    pub(super) inv_step: Option<f64>,
    /// The number of buckets (0: no table).
    buckets: usize,
    /// The buckets, built by the first lookup that needs them (the narrow blocks' searches
    /// never do): base span | knots in the bucket << [`COUNT_SHIFT`] (saturated at [`MANY`]).
    table: OnceLock<Vec<u32>>,
    start: f64,
    inv_width: f64,
}

/// Where a bucket's knot count sits in its table entry (spans must fit below).
const COUNT_SHIFT: u32 = 28;
/// Spans below this have indices that convert from f64 through i32, which vectorizes.
const LANE_INDEX_MAX: usize = i32::MAX as usize;
/// Saturated knot count: search on from the base span.
const MANY: u32 = 15;

impl<'a> Locator<'a> {
    /// A locator for `count` parameters on `knots` of a B-spline of `degree` with
    /// `n_control` control points; `inv_step` is the reciprocal of the spacing of uniform
    /// knots.
    pub(super) fn new(
        knots: &'a [f64],
        degree: usize,
        n_control: usize,
        inv_step: Option<f64>,
        count: usize,
    ) -> Self {
        let (lo, hi) = domain_spans(knots, degree, n_control);
        let mut loc = Locator {
            knots,
            degree,
            n_control,
            lo,
            hi,
            inv_step,
            buckets: 0,
            table: OnceLock::new(),
            start: knots[lo],
            inv_width: 0.0,
        };
        let spans = hi - lo + 1;
        // Building the table costs O(spans): worth it from batches of spans/8 points on.
        if inv_step.is_some()
            || count < 1024
            || spans < 16
            || 8 * count < spans
            || hi >= 1 << COUNT_SHIFT
        {
            return loc;
        }
        // Twice as many buckets as spans (fewer for small batches): most buckets then hold
        // at most one knot even where the spans are uneven.
        loc.buckets = (2 * spans).min(4 * count);
        let (a, b) = (knots[lo], knots[hi + 1]);
        loc.inv_width = loc.buckets as f64 / (b - a);
        loc
    }

    /// The bucket table (empty: none), built on the first call.
    #[inline(always)]
    pub(super) fn table(&self) -> &[u32] {
        if self.buckets == 0 {
            return &[];
        }
        self.table.get_or_init(|| {
            let mut table = vec![0; self.buckets];
            for &k in &self.knots[self.lo + 1..=self.hi] {
                table[self.bucket(k)] += 1;
            }
            let mut base = self.lo as u32;
            for e in &mut table {
                let here = *e;
                *e = base | (here.min(MANY) << COUNT_SHIFT);
                base += here;
            }
            table
        })
    }

    /// The bucket of t (clamped to the table).
    #[inline(always)]
    pub(super) fn bucket(&self, t: f64) -> usize {
        // Clamped first, truncation is floor; NaN converts to 0 (through i64, as in
        // `uniform_span`).
        let b = ((t - self.start) * self.inv_width).clamp(0.0, (self.buckets - 1) as f64);
        b as i64 as usize
    }

    /// The span holding t (clamped to the domain) from its bucket's table entry `e`.
    ///
    /// A bucket with at most one knot of its own needs no branch: when it has none, the
    /// next knot lies in a later bucket, so it is > t and the comparison adds 0 (the span
    /// is capped at the last one for t at or past the domain's end).
    #[inline(always)]
    pub(super) fn span_in_bucket(&self, t: f64, e: u32) -> usize {
        let k = self.knots;
        let base = (e & ((1 << COUNT_SHIFT) - 1)) as usize;
        if e >> COUNT_SHIFT <= 1 {
            return (base + usize::from(t >= k[base + 1])).min(self.hi);
        }
        let mut s = base;
        while s < self.hi && t >= k[s + 1] {
            s += 1;
        }
        s
    }

    /// The span holding t (clamped to the domain; the first for NaN): by one multiplication
    /// on uniform knots, from the bucket table when there is one, else searched from
    /// `hint` ([`Locator::span_near`]).
    #[inline(always)]
    pub(super) fn span(&self, t: f64, hint: usize) -> usize {
        if let Some(inv) = self.inv_step {
            return uniform_span(self.knots[0], inv, self.degree, self.n_control, t);
        }
        let table = self.table();
        if !table.is_empty() {
            return self.span_in_bucket(t, table[self.bucket(t)]);
        }
        self.span_near(t, hint)
    }

    /// The span holding t (clamped to the domain; the first for NaN), [`find_span`](super::curve::find_span)'s, by
    /// a search outward from `hint` in steps that double, then a binary search: two reads
    /// when `hint` holds t, O(log d) for a span d spans away, and no bucket table.
    #[inline(always)]
    pub(super) fn span_near(&self, t: f64, hint: usize) -> usize {
        let (k, lo, hi) = (self.knots, self.lo, self.hi);
        if t.is_nan() {
            return lo;
        }
        let (mut a, mut b) = (hint.clamp(lo, hi), hint.clamp(lo, hi));
        let mut step = 1;
        if a == lo || k[a] <= t {
            // Up: k[a] <= t (or a = lo) throughout, until t < k[b + 1] or b = hi.
            while b < hi && k[b + 1] <= t {
                a = b + 1;
                b = (b + step).min(hi);
                step *= 2;
            }
        } else {
            // Down: t < k[b + 1] throughout, until k[a] <= t or a = lo.
            while a > lo && k[a] > t {
                b = a - 1;
                a = a.saturating_sub(step).max(lo);
                step *= 2;
            }
        }
        // The last span in [a, b] whose first knot is <= t.
        a + k[a + 1..=b].partition_point(|&x| x <= t)
    }

    /// The span holding t: from the bucket table when it is built already (no
    /// search however far t lies from `hint`), else by [`Locator::span_near`] from `hint`.
    #[inline(always)]
    pub(super) fn span_from(&self, t: f64, hint: usize) -> usize {
        match self.table.get() {
            Some(table) => self.span_in_bucket(t, table[self.bucket(t)]),
            None => self.span_near(t, hint),
        }
    }
}

/// The knot spans and cubic basis values of a block of parameters along one direction
/// (structure of arrays, lane i for the block's point i), kept from block to block of a run
/// (filling them afresh would cost more than the evaluation).
pub(super) struct CubicLanes {
    pub(super) x: [f64; BLOCK],
    pub(super) span: [usize; BLOCK],
    pub(super) basis: [[f64; BLOCK]; 4],
    /// The knots of each lane's span that its basis reads.
    window: [[f64; BLOCK]; 6],
}

impl CubicLanes {
    pub(super) fn new() -> Self {
        CubicLanes {
            x: [0.0; BLOCK],
            span: [0; BLOCK],
            basis: [[0.0; BLOCK]; 4],
            window: [[0.0; BLOCK]; 6],
        }
    }

    /// The spans of the first `n` lanes, in rounds whose memory reads do not depend on
    /// each other, so that their cache misses overlap: the bucket table entries first,
    /// then (from each entry's base span) the knot the span depends on and, through
    /// `near`, what the evaluation on the base span will read; `touched` folds what was
    /// read. Without `touch` (sorted parameters, whose reads are the previous lane's or
    /// next to them; knots that stay in the caches) the table entry gives the span at once.
    #[inline(always)]
    pub(super) fn locate(
        &mut self,
        loc: &Locator,
        n: usize,
        touch: bool,
        touched: &mut u64,
        near: impl Fn(usize) -> u64,
    ) {
        let (xs, spans) = (&self.x[..n], &mut self.span[..n]);
        // Empty on uniform knots (no buckets there).
        let table = loc.table();
        if let Some(inv) = loc.inv_step.filter(|_| loc.hi < LANE_INDEX_MAX) {
            // `uniform_span` lane by lane, in a loop that vectorizes: max/min send NaN to
            // the first span as its clamp does, and the floor of the clamped value, an
            // integer below 2^31, is read from the low bits of its sum with 2^52 (an `as`
            // conversion saturates, which compiles to one scalar conversion per lane).
            const TWO_52: f64 = 4_503_599_627_370_496.0;
            let (k0, lo, hi) = (loc.knots[0], loc.lo as f64, loc.hi as f64);
            for (s, &x) in spans.iter_mut().zip(xs) {
                let f = ((x - k0) * inv).max(lo).min(hi).floor();
                *s = ((f + TWO_52).to_bits() - TWO_52.to_bits()) as usize;
            }
        } else if !table.is_empty() && !touch {
            for (s, &x) in spans.iter_mut().zip(xs) {
                *s = loc.span_in_bucket(x, table[loc.bucket(x)]);
            }
        } else if !table.is_empty() {
            // In rounds of independent reads.
            for (s, &x) in spans.iter_mut().zip(xs) {
                *s = loc.bucket(x);
                *touched ^= u64::from(table[*s]);
            }
            for &b in spans.iter() {
                let base = (table[b] & ((1 << COUNT_SHIFT) - 1)) as usize;
                *touched ^= loc.knots[base + 1].to_bits() ^ near(base);
            }
            for (s, &x) in spans.iter_mut().zip(xs) {
                *s = loc.span_in_bucket(x, table[*s]);
            }
        } else {
            let mut hint = loc.lo;
            for (s, &x) in spans.iter_mut().zip(xs) {
                *s = loc.span(x, hint);
                hint = *s;
            }
        }
    }

    /// The spans of the first `n` lanes when their parameters are sorted and the block
    /// crosses at most [`SORTED_SPANS`] knots (non-uniform knots): the first lane's span
    /// s0 looked up, then every lane's s0 plus the number of the knots k[s0 + 1..=s1] at
    /// or below its parameter (s1: the last lane's span), a count the compiler vectorizes
    /// over the lanes, where the table's lookups cost about a fifth of the evaluation:
    /// the span [`Locator::span`] finds (the last s <= s1 with k[s] <= x). `false`, with
    /// nothing written, when it does not apply.
    #[inline(always)]
    pub(super) fn locate_sorted(&mut self, loc: &Locator, n: usize) -> bool {
        if loc.inv_step.is_some() || n == 0 {
            return false;
        }
        let xs = &self.x[..n];
        // From the previous block's last span (lanes past n repeat it; lo at first).
        let s0 = loc.span_near(xs[0], self.span[BLOCK - 1]);
        let s1 = loc.span_near(xs[n - 1], s0);
        if s1 - s0 > SORTED_SPANS {
            return false;
        }
        let spans = &mut self.span[..n];
        spans.fill(s0);
        for &k in &loc.knots[s0 + 1..=s1] {
            for (s, &x) in spans.iter_mut().zip(xs) {
                *s += usize::from(k <= x);
            }
        }
        true
    }

    /// Whether the first `n` lanes' parameters are sorted (non-decreasing).
    #[inline(always)]
    pub(super) fn sorted(&self, n: usize) -> bool {
        self.x[..n].windows(2).all(|w| w[0] <= w[1])
    }

    /// The cubic basis values of the first `n` lanes on their spans: the operations of
    /// [`uniform_cubic_basis`] or [`basis_funs_cubic`], so the same bits, lane by lane.
    #[inline(always)]
    pub(super) fn basis(&mut self, loc: &Locator, n: usize) {
        let k = loc.knots;
        // Whole blocks vectorize best: the lanes past n repeat lane n - 1.
        for i in n..BLOCK {
            self.x[i] = self.x[n - 1];
            self.span[i] = self.span[n - 1];
        }
        match loc.inv_step {
            Some(inv) => {
                for (w, &s) in self.window[0].iter_mut().zip(&self.span) {
                    *w = k[s];
                }
                for i in 0..BLOCK {
                    let mut b = [0.0; 4];
                    uniform_cubic_basis((self.x[i] - self.window[0][i]) * inv, &mut b);
                    for (r, v) in b.into_iter().enumerate() {
                        self.basis[r][i] = v;
                    }
                }
            }
            None => {
                for (i, &s) in self.span.iter().enumerate() {
                    for (r, w) in k[s - 2..s + 4].iter().enumerate() {
                        self.window[r][i] = *w;
                    }
                }
                for i in 0..BLOCK {
                    let w: [f64; 6] = std::array::from_fn(|r| self.window[r][i]);
                    let b = basis_funs_cubic(&w, 2, self.x[i]);
                    for (r, v) in b.into_iter().enumerate() {
                        self.basis[r][i] = v;
                    }
                }
            }
        }
    }

    /// Requests through `fetch` the knots the basis of span `s` reads (none on uniform
    /// knots).
    #[inline(always)]
    pub(super) fn touch_knots(loc: &Locator, s: usize, fetch: Prefetcher, touched: &mut u64) {
        if loc.inv_step.is_none() {
            fetch.touch(&loc.knots[s - 2], touched);
            fetch.touch(&loc.knots[s + 3], touched);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::curve::find_span;
    use super::*;

    /// The search from a hint finds `find_span`'s span from every hint: knots of
    /// multiplicity 1 to 4 (a jump), parameters on knots, between them and beyond the
    /// domain at both ends.
    #[test]
    fn span_near_is_find_span_from_any_hint() {
        let mut knots = vec![0.0; 4];
        for i in 1..40 {
            let repeat = [1, 1, 2, 1, 3, 1, 4][i % 7];
            knots.extend(std::iter::repeat_n(i as f64 * 0.25, repeat));
        }
        knots.extend([10.0; 4]);
        let n_c = knots.len() - 4;
        let loc = Locator::new(&knots, 3, n_c, None, 0);
        let mut ts = vec![-1.0, 10.0, 11.0, 1e-300, f64::NAN];
        ts.extend(knots.iter().copied());
        ts.extend((0..500).map(|i| i as f64 * 0.0213));
        for &t in &ts {
            let want = find_span(&knots, 3, n_c, t);
            for hint in 0..n_c + 3 {
                assert_eq!(loc.span_near(t, hint), want, "t = {t}, hint = {hint}");
                assert_eq!(loc.span(t, hint), want, "t = {t}, hint = {hint}");
            }
        }
    }
}
