//! A B-spline curve of degree <= 3 as piecewise cubic polynomials in power form (one record
//! of Taylor coefficients per knot span, SciPy's `PPoly.from_spline`): for many evaluations
//! at arbitrary parameters, where the B-spline form's knots, basis and control points cost
//! more reads and arithmetic than one record and three multiply-adds per coordinate.
//! Not in the paper (spec/bspline-interpolation.md): its pieces are the polynomials whose
//! Taylor coefficients the forward differences of §4 start from, here kept for evaluation at
//! arbitrary parameters.

use super::curve::{domain_spans, BsplineCurve};
use super::locate::{Prefetcher, BLOCK};
use crate::geom::{check_point, BatchOptions, Curve};
use crate::par::*;
use crate::points::check_eval_args;
use crate::{Error, Result};
use bytemuck::{Pod, Zeroable};

/// One cache line of a record (records start on a line: a 3-D cubic's 14 numbers then take
/// two lines, never three).
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
#[repr(C, align(64))]
struct Line([f64; 8]);

/// A bucket of the span table: the piece its lower end falls in (`base`), its first own knot
/// (`bound`, +∞ without one) and whether it holds more than one knot (16 bytes: one line).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
struct Bucket {
    bound: f64,
    base: u32,
    many: u32,
}

/// Where the parameters' spans come from.
#[derive(Debug, Clone, PartialEq)]
enum Spans {
    /// Uniform knots: span = floor((t - start)·inv_step).
    Uniform { start: f64, inv_step: f64 },
    /// Buckets of equal width over the domain: t falls in bucket floor((t - start)·inv_width).
    Table {
        start: f64,
        inv_width: f64,
        buckets: Vec<Bucket>,
    },
}

/// A B-spline curve of degree <= 3 as one cubic polynomial per knot span, in power form
/// about the span's left knot t_s:
///
/// p(t) = c_0 + c_1 (t - t_s) + c_2 (t - t_s)^2 + c_3 (t - t_s)^3 on [t_s, t_(s+1)),
///
/// with c_k = p^(k)(t_s)/k! (the Taylor coefficients that forward differencing starts from;
/// zero above the degree), evaluated by Horner's rule. The first and last span extend past
/// the domain as the B-spline's do.
///
/// This is the form for large batches at arbitrary parameters: each point reads one bucket
/// of a span table (none on uniform knots) and one record (two cache lines up to 3-D), where
/// the B-spline form reads the table, six knots and four control points and computes the
/// basis (six reciprocals on non-uniform knots). It costs 16 numbers per span in 3-D (the
/// B-spline curve: 4), plus two 16-byte table buckets per span on non-uniform knots.
/// Values agree with the B-spline's within a few ulps of its largest control point
/// (tested: 8·eps·max|P| on interpolated curves, 64·eps on random knot vectors); not bit
/// for bit, as the arithmetic differs. Outside the domain the end cubics extrapolate, and
/// the rounding grows with their values.
///
/// # Example
/// ```
/// use geomkit::geom::Curve;
/// use geomkit::bspline::{interpolate_curve, InterpolationOptions, Parametrization};
///
/// let points = vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![3.0, 2.5], vec![4.0, 0.0]];
/// let opts = InterpolationOptions::default().with_parametrization(Parametrization::ChordLength);
/// let curve = interpolate_curve(&points, &opts)?.into_curve();
/// let pp = curve.to_piecewise()?;
/// let ts = [0.3, 4.2, 1.7];
/// let mut out = vec![0.0; 6];
/// pp.eval_many_par(&ts, &mut out)?;
/// for (t, p) in ts.iter().zip(out.chunks(2)) {
///     let q = curve.eval(*t);
///     assert!((p[0] - q[0]).abs() < 1e-14 && (p[1] - q[1]).abs() < 1e-14);
/// }
/// # Ok::<(), geomkit::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseCurve {
    dim: usize,
    degree: usize,
    /// Per span: t_s, t_(s+1), then c_0..c_3 (each `dim` coordinates), zero-padded to whole
    /// lines.
    records: Vec<Line>,
    /// Index of the last piece.
    last: usize,
    spans: Spans,
}

/// Offset of the coefficients in a record.
const COEFFS: usize = 2;

/// Cache lines per record of a curve in dimension `d` (two up to 3-D).
#[inline(always)]
const fn record_lines(d: usize) -> usize {
    (COEFFS + 4 * d).div_ceil(8)
}

impl BsplineCurve {
    /// The curve as piecewise cubic polynomials ([`PiecewiseCurve`]), for fast evaluation
    /// at many arbitrary parameters. O(spans), in parallel. Errors: degree above 3, more
    /// than 2^32 - 1 spans.
    pub fn to_piecewise(&self) -> Result<PiecewiseCurve> {
        PiecewiseCurve::build(self, true)
    }
}

impl PiecewiseCurve {
    /// The form of `curve`, records built on the thread pool when `parallel`.
    pub(crate) fn build(curve: &BsplineCurve, parallel: bool) -> Result<Self> {
        let (d, p) = (curve.dim(), curve.degree());
        if p > 3 {
            return Err(Error::InvalidOption {
                option: "degree",
                reason: "the piecewise polynomial form is implemented for degree <= 3",
            });
        }
        let knots = curve.knots();
        let (lo, hi) = domain_spans(knots, p, curve.n_control());
        if hi - lo >= u32::MAX as usize {
            return Err(Error::InvalidOption {
                option: "knots",
                reason: "the piecewise polynomial form holds at most 2^32 - 1 knot spans",
            });
        }
        let stride = record_lines(d);
        let mut records = vec![Line::default(); (hi - lo + 1) * stride];
        let fill = |taylor: &mut Vec<f64>, (i, rec): (usize, &mut [Line])| {
            let rec: &mut [f64] = bytemuck::cast_slice_mut(rec);
            let s = lo + i;
            let (t0, t1) = (knots[s], knots[s + 1]);
            rec[0] = t0;
            rec[1] = t1;
            // Interior spans of zero width (repeated knots) hold no parameter: zero
            // coefficients.
            if t0 < t1 {
                curve.span_taylor(s, taylor);
                for (c, tc) in taylor.chunks_exact(4).enumerate() {
                    for (k, v) in tc.iter().enumerate() {
                        rec[COEFFS + k * d + c] = *v;
                    }
                }
            }
        };
        if parallel {
            records
                .par_chunks_mut(stride)
                .enumerate()
                .for_each_init(|| vec![0.0; 4 * d], fill);
        } else {
            let mut taylor = vec![0.0; 4 * d];
            for item in records.chunks_mut(stride).enumerate() {
                fill(&mut taylor, item);
            }
        }
        let spans = match curve.uniform_step() {
            Some(h) => Spans::Uniform {
                start: knots[lo],
                inv_step: 1.0 / h,
            },
            None => span_table(&knots[lo..=hi + 1]),
        };
        Ok(PiecewiseCurve {
            dim: d,
            degree: p,
            last: hi - lo,
            records,
            spans,
        })
    }

    /// Degree of the B-spline it came from (coefficients above it are zero).
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Parameter domain (that of the B-spline).
    pub fn domain(&self) -> (f64, f64) {
        (self.piece(0).0, self.piece(self.last).1)
    }

    /// Number of polynomial pieces (the B-spline's knot spans over its domain, zero-width
    /// ones included).
    pub fn n_pieces(&self) -> usize {
        self.last + 1
    }

    /// Piece `i` (< [`PiecewiseCurve::n_pieces`]): its interval [t_s, t_(s+1)) and its
    /// coefficients c_0..c_3 about t_s, `dim` each (c_k of coordinate j at `k*dim + j`),
    /// e.g. to write the curve as formulas. Zero-width pieces have zero coefficients.
    ///
    /// # Panics
    /// If `i` is out of range.
    pub fn piece(&self, i: usize) -> (f64, f64, &[f64]) {
        let rec = self.record(i);
        (rec[0], rec[1], &rec[COEFFS..COEFFS + 4 * self.dim])
    }

    #[inline(always)]
    fn record(&self, i: usize) -> &[f64] {
        let stride = record_lines(self.dim);
        bytemuck::cast_slice(&self.records[i * stride..(i + 1) * stride])
    }

    /// The piece holding t (the first or last for t outside the domain).
    #[inline(always)]
    fn piece_of(&self, t: f64) -> usize {
        match &self.spans {
            Spans::Uniform { start, inv_step } => {
                ((t - start) * inv_step).max(0.0).min(self.last as f64) as usize
            }
            Spans::Table {
                start,
                inv_width,
                buckets,
            } => {
                let b = bucket_of(t, *start, *inv_width, buckets.len());
                self.piece_in_bucket(t, buckets[b])
            }
        }
    }

    /// The piece holding t, which falls in bucket `b`: the bucket's base piece, or the next
    /// one when t has reached the bucket's only knot (no branch); past several knots, the
    /// pieces' ends decide.
    #[inline(always)]
    fn piece_in_bucket(&self, t: f64, b: Bucket) -> usize {
        let mut i = b.base as usize + usize::from(t >= b.bound);
        if b.many != 0 {
            while i < self.last && t >= self.record(i)[1] {
                i += 1;
            }
        }
        i.min(self.last)
    }

    /// Horner's rule on a piece's record `rec` at t, D coordinates (D = 0: `self.dim`).
    #[inline(always)]
    fn horner<const D: usize>(&self, rec: &[f64], t: f64, out: &mut [f64]) {
        let d = if D == 0 { self.dim } else { D };
        let rec = &rec[..COEFFS + 4 * d];
        let x = t - rec[0];
        let c = &rec[COEFFS..];
        for (j, o) in out[..d].iter_mut().enumerate() {
            *o = ((c[3 * d + j] * x + c[2 * d + j]) * x + c[d + j]) * x + c[j];
        }
    }

    /// Derivative `k` (0 to 3; higher ones are zero) at t into `out` (`dim` entries), from
    /// the piece holding t. Panics if `out` is shorter than `dim`.
    pub fn eval_derivative(&self, t: f64, k: usize, out: &mut [f64]) {
        if k == 0 {
            return self.eval_into(t, out);
        }
        let d = self.dim;
        let rec = self.record(self.piece_of(t));
        let x = t - rec[0];
        let c = |m: usize, j: usize| rec[COEFFS + m * d + j];
        for (j, o) in out[..d].iter_mut().enumerate() {
            *o = match k {
                1 => (3.0 * c(3, j) * x + 2.0 * c(2, j)) * x + c(1, j),
                2 => 6.0 * c(3, j) * x + 2.0 * c(2, j),
                3 => 6.0 * c(3, j),
                _ => 0.0,
            };
        }
    }

    /// Evaluates at arbitrary parameters (sorted or not) into `out` (row-major), in
    /// parallel over chunks of 4096. Block by block, the spans of 64 parameters are found
    /// first and their records requested, so that unsorted parameters' cache misses
    /// overlap. The values of [`Curve::eval_into`], bit for bit. Errors: wrong buffer
    /// length, non-finite parameters.
    pub fn eval_many_par(&self, ts: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_eval_args("parameter", ts, ts.len(), d, out)?;
        self.eval_many_with(ts, out, true);
        Ok(())
    }

    /// The batch kernel over checked arguments, in parallel chunks of 4096 when
    /// `parallel`.
    pub(crate) fn eval_many_with(&self, ts: &[f64], out: &mut [f64], parallel: bool) {
        let kernel = self.kernel();
        if parallel {
            out.par_chunks_mut(4096 * self.dim)
                .zip(ts.par_chunks(4096))
                .for_each(|(o, t)| kernel(self, t, o));
        } else {
            kernel(self, ts, out);
        }
    }

    fn kernel(&self) -> fn(&PiecewiseCurve, &[f64], &mut [f64]) {
        match self.dim {
            1 => |pp, t, o| pp.eval_blocks::<1>(t, o),
            2 => |pp, t, o| pp.eval_blocks::<2>(t, o),
            3 => |pp, t, o| pp.eval_blocks::<3>(t, o),
            _ => |pp, t, o| pp.eval_blocks::<0>(t, o),
        }
    }

    /// The kernel in dimension D (0: any) on one chunk of parameters.
    #[inline(always)]
    fn eval_blocks<const D: usize>(&self, ts: &[f64], out: &mut [f64]) {
        let d = if D == 0 { self.dim } else { D };
        let width = 8 * record_lines(d);
        let numbers: &[f64] = bytemuck::cast_slice(&self.records);
        let fetch = Prefetcher::new();
        let mut touched = 0u64;
        let mut pieces = [0usize; BLOCK];
        // Requests piece i's record lines, unless the block is sorted (its parameters read
        // the previous one's record or the next).
        let request = |i: usize, ahead: bool, touched: &mut u64| {
            if !ahead {
                return;
            }
            for line in numbers[i * width..(i + 1) * width].iter().step_by(8) {
                fetch.touch(line, touched);
            }
        };
        for (tb, ob) in ts.chunks(BLOCK).zip(out.chunks_mut(BLOCK * d)) {
            let pieces = &mut pieces[..tb.len()];
            let ahead = !tb.is_sorted();
            match &self.spans {
                Spans::Uniform { .. } => {
                    for (i, &t) in pieces.iter_mut().zip(tb) {
                        *i = self.piece_of(t);
                        request(*i, ahead, &mut touched);
                    }
                }
                Spans::Table {
                    start,
                    inv_width,
                    buckets,
                } => {
                    // Two rounds: the buckets first, then the pieces from them.
                    for (b, &t) in pieces.iter_mut().zip(tb) {
                        *b = bucket_of(t, *start, *inv_width, buckets.len());
                        fetch.touch(&buckets[*b].bound, &mut touched);
                    }
                    for (i, &t) in pieces.iter_mut().zip(tb) {
                        *i = self.piece_in_bucket(t, buckets[*i]);
                        request(*i, ahead, &mut touched);
                    }
                }
            }
            for ((&i, &t), o) in pieces.iter().zip(tb).zip(ob.chunks_exact_mut(d)) {
                self.horner::<D>(&numbers[i * width..], t, o);
            }
        }
        std::hint::black_box(touched);
    }
}

/// The B-spline's polynomial pieces (power form about each span's left knot); domain and
/// breaks those of the B-spline.
impl Curve for PiecewiseCurve {
    fn dim(&self) -> usize {
        self.dim
    }

    fn domain(&self) -> (f64, f64) {
        PiecewiseCurve::domain(self)
    }

    #[inline]
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        self.horner::<0>(self.record(self.piece_of(t)), t, out);
    }

    /// Every order ([`PiecewiseCurve::eval_derivative`]; zero above 3).
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim, out)?;
        self.eval_derivative(t, order, out);
        Ok(())
    }

    /// The ends of the pieces strictly inside the domain.
    fn breaks(&self) -> Vec<f64> {
        let mut b: Vec<f64> = (1..=self.last).map(|i| self.piece(i).0).collect();
        b.dedup();
        b
    }

    /// The kernel of [`PiecewiseCurve::eval_many_par`]: the values of
    /// [`Curve::eval_into`], bit for bit.
    fn eval_batch(&self, ts: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        check_eval_args("parameter", ts, ts.len(), self.dim, out)?;
        self.eval_many_with(ts, out, options.parallel());
        Ok(())
    }
}

/// The bucket of t (clamped to the table; NaN to bucket 0).
#[inline(always)]
fn bucket_of(t: f64, start: f64, inv_width: f64, len: usize) -> usize {
    ((t - start) * inv_width).clamp(0.0, (len - 1) as f64) as i64 as usize
}

/// The span table over the domain knots `k` (t_lo..=t_(hi+1)): twice as many buckets as
/// spans, so that most hold at most one knot even where the spans are uneven. Bucket
/// indices are monotone in t, so the knots of earlier buckets are <= t and those of later
/// ones > t.
fn span_table(k: &[f64]) -> Spans {
    let n = k.len() - 1;
    let len = 2 * n;
    let (start, end) = (k[0], k[n]);
    let inv_width = len as f64 / (end - start);
    let mut buckets = vec![
        Bucket {
            bound: f64::INFINITY,
            base: 0,
            many: 0,
        };
        len
    ];
    let mut counts = vec![0u32; len];
    for &x in &k[1..n] {
        let b = bucket_of(x, start, inv_width, len);
        if counts[b] == 0 {
            buckets[b].bound = x;
        }
        counts[b] += 1;
    }
    let mut base = 0u32;
    for (bucket, count) in buckets.iter_mut().zip(counts) {
        bucket.base = base;
        bucket.many = u32::from(count > 1);
        base += count;
    }
    Spans::Table {
        start,
        inv_width,
        buckets,
    }
}
