//! Knot spans for batches of parameters, shared by the batched curve and surface
//! evaluations: one multiplication on uniform knots, a bucket table over the domain for
//! large batches on other knots, a binary search otherwise; always [`find_span`]'s span.

use super::curve::{domain_spans, find_span, uniform_span};

/// Finds knot spans for batches of parameters along one direction.
///
/// Non-uniform knots and large batches use a bucket table over the domain: t falls in bucket
/// b = floor((t - start)·inv_width), which is monotone in t, so every interior knot in an
/// earlier bucket is <= t and every knot in a later one > t. A bucket stores the span that
/// count gives and how many knots it holds itself (usually at most one): the span is then
/// one comparison away, without a branch that unsorted parameters would mispredict, and
/// equal to [`find_span`]'s.
pub(super) struct Locator<'a> {
    pub(super) knots: &'a [f64],
    degree: usize,
    n_control: usize,
    /// First and last span of the domain.
    pub(super) lo: usize,
    pub(super) hi: usize,
    /// Uniform knots: the reciprocal of the spacing (the span by one multiplication).
    pub(super) inv_step: Option<f64>,
    /// The buckets (empty: no table): base span | knots in the bucket << [`COUNT_SHIFT`]
    /// (saturated at [`MANY`]).
    pub(super) table: Vec<u32>,
    start: f64,
    inv_width: f64,
}

/// Where a bucket's knot count sits in its table entry (spans must fit below).
const COUNT_SHIFT: u32 = 28;
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
            table: Vec::new(),
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
        let buckets = (2 * spans).min(4 * count);
        let (a, b) = (knots[lo], knots[hi + 1]);
        loc.inv_width = buckets as f64 / (b - a);
        loc.table = vec![0; buckets];
        for j in lo + 1..=hi {
            let b = loc.bucket(knots[j]);
            loc.table[b] += 1;
        }
        let mut base = lo as u32;
        for e in &mut loc.table {
            let here = *e;
            *e = base | (here.min(MANY) << COUNT_SHIFT);
            base += here;
        }
        loc
    }

    /// The bucket of t (clamped to the table).
    #[inline(always)]
    pub(super) fn bucket(&self, t: f64) -> usize {
        // Clamped first, truncation is floor; NaN converts to 0 (through i64, as in
        // `uniform_span`).
        let b = ((t - self.start) * self.inv_width).clamp(0.0, (self.table.len() - 1) as f64);
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

    /// The span holding t (clamped to the domain), trying `hint` first when there is
    /// neither a uniform step nor a bucket table.
    #[inline(always)]
    pub(super) fn span(&self, t: f64, hint: usize) -> usize {
        if let Some(inv) = self.inv_step {
            return uniform_span(self.knots[0], inv, self.degree, self.n_control, t);
        }
        if !self.table.is_empty() {
            return self.span_in_bucket(t, self.table[self.bucket(t)]);
        }
        if self.holds(hint, t) {
            return hint;
        }
        find_span(self.knots, self.lo, self.hi + 1, t)
    }

    /// Whether span s holds t (the first and last span extend to ±∞).
    #[inline]
    fn holds(&self, s: usize, t: f64) -> bool {
        let k = self.knots;
        (s == self.lo || k[s] <= t) && (s == self.hi || t < k[s + 1])
    }
}
