//! Evaluation of B-spline curves on uniform samples by forward differences (spec
//! §4: each next point of a cubic piece with three additions per coordinate), restarted at
//! every knot span so that the drift stays bounded, and in parallel over spans.
//!
//! Drift bound: within a span, with u the unit roundoff (eps/2), after j steps from exact
//! starting differences the value differs from exact evaluation by at most
//! u·(j·F + j²/2·D1 + j³/6·D2) + 4·eps·F, where F, D1, D2 bound |p|, |Δp|, |Δ²p| over the
//! span ([`FdReport::bound`] is that bound at the longest span run). Restarting per span
//! keeps j below the samples per span.

use super::curve::{basis_funs_derivs, cubic_basis_at_knot, BsplineCurve};
use super::locate::{with_avx512, CubicLanes, Locator, Prefetcher, BLOCK};
use super::narrow::Narrow;
use crate::geom::Curve;
use crate::par::*;
use crate::points::{all_finite, check_buffer, check_eval_args, check_finite};
use crate::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};

/// Samples first..end fall in knot span `span`.
#[derive(Debug, Clone, Copy)]
struct SpanRun {
    span: usize,
    first: usize,
    end: usize,
}

/// What a forward-differenced sampling did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FdReport {
    /// Longest run of steps without a restart.
    pub max_steps: usize,
    /// A bound on |forward-differenced - exact| over all samples (absolute).
    pub bound: f64,
}

impl BsplineCurve {
    /// Evaluates the curve (degree <= 3) at `count` >= 2 uniformly spaced parameters over its
    /// domain into `out` (count × dim, row-major) by forward differences restarted at each
    /// span, in parallel over spans (spans with fewer than 8 samples, and whole samplings
    /// with fewer than 8 samples per span, are evaluated directly: there the differences
    /// cost more than they save, and the reported bound covers only differenced runs). Errors: degree above 3, count < 2, wrong buffer length.
    pub fn sample_uniform_fd(&self, count: usize, out: &mut [f64]) -> Result<FdReport> {
        let d = self.dim();
        let p = self.degree();
        if p > 3 {
            return Err(Error::InvalidOption {
                option: "degree",
                reason: "forward differencing is implemented for degree <= 3",
            });
        }
        if count < 2 {
            return Err(Error::TooFewPoints {
                what: "samples",
                got: count,
                min: 2,
            });
        }
        if out.len() != count * d {
            return Err(Error::BufferSize {
                expected: count * d,
                got: out.len(),
            });
        }
        let (a, b) = self.domain();
        let step = (b - a) / (count - 1) as f64;
        let knots = self.knots();
        let n_c = self.n_control();
        if count < 8 * (n_c - p) {
            // Fewer than 8 samples per span: direct evaluation is cheaper than differences.
            out.par_chunks_mut(4096 * d)
                .enumerate()
                .for_each(|(block, chunk)| {
                    for (k, row) in chunk.chunks_exact_mut(d).enumerate() {
                        let i = block * 4096 + k;
                        let t = if i + 1 == count {
                            b
                        } else {
                            a + i as f64 * step
                        };
                        self.eval_into(t, row);
                    }
                });
            return Ok(FdReport {
                max_steps: 0,
                bound: 0.0,
            });
        }
        // Sample index where each span starts: first k with t_k >= knot[s].
        let first_index = |s: usize| -> usize {
            if s <= p {
                return 0;
            }
            let k = ((knots[s] - a) / step).ceil();
            (k.max(0.0) as usize).min(count)
        };
        let spans: Vec<SpanRun> = (p..n_c)
            .map(|s| SpanRun {
                span: s,
                first: first_index(s),
                end: if s + 1 == n_c {
                    count
                } else {
                    first_index(s + 1)
                },
            })
            .filter(|r| r.end > r.first)
            .collect();
        // Split the output into the disjoint runs of the spans.
        let mut runs: Vec<(SpanRun, &mut [f64])> = Vec::with_capacity(spans.len());
        let mut rest = out;
        let mut at = 0;
        for run in spans {
            let (_, tail) = rest.split_at_mut((run.first - at) * d);
            let (chunk, tail) = tail.split_at_mut((run.end - run.first) * d);
            runs.push((run, chunk));
            rest = tail;
            at = run.end;
        }
        // Spans in groups, so that short spans do not each pay for a parallel task.
        let reports: Vec<FdReport> = runs
            .par_chunks_mut(256)
            .map(|group| {
                let mut scratch = vec![0.0; 8 * d];
                group.iter_mut().fold(
                    FdReport {
                        max_steps: 0,
                        bound: 0.0,
                    },
                    |m, (r, chunk)| {
                        let rep = self.fd_run(r.span, a, step, r.first, r.end, chunk, &mut scratch);
                        FdReport {
                            max_steps: m.max_steps.max(rep.max_steps),
                            bound: m.bound.max(rep.bound),
                        }
                    },
                )
            })
            .collect();
        Ok(reports.into_iter().fold(
            FdReport {
                max_steps: 0,
                bound: 0.0,
            },
            |m, r| FdReport {
                max_steps: m.max_steps.max(r.max_steps),
                bound: m.bound.max(r.bound),
            },
        ))
    }

    /// Forward differences over samples k0..k1 inside span s (direct evaluation for runs
    /// shorter than 8 samples, where setting up the differences costs more than it saves).
    /// `scratch` holds at least 8·dim numbers.
    #[allow(clippy::too_many_arguments)]
    fn fd_run(
        &self,
        s: usize,
        a: f64,
        step: f64,
        k0: usize,
        k1: usize,
        out: &mut [f64],
        scratch: &mut [f64],
    ) -> FdReport {
        let d = self.dim();
        let len = k1 - k0;
        if len < 8 {
            for (k, row) in (k0..k1).zip(out.chunks_exact_mut(d)) {
                self.eval_into(a + k as f64 * step, row);
            }
            return FdReport {
                max_steps: 0,
                bound: 0.0,
            };
        }
        let t_s = self.knots()[s];
        // The span's Taylor coefficients at its left knot, in the local x = t - t_s (never in
        // absolute t: at t ~ 1e6 a parameter carries only ~1e-10 of relative precision), then
        // shifted to the first sample.
        let (taylor, state) = scratch.split_at_mut(4 * d);
        self.span_taylor(s, taylor);
        let u0 = a + k0 as f64 * step - t_s;
        let (h, h2, h3) = (step, step * step, step * step * step);
        let (mut f_max, mut d1_max, mut d2_max) = (0.0f64, 0.0f64, 0.0f64);
        let lenf = len as f64;
        let x = lenf * h;
        for (c, st) in taylor.chunks_exact(4).zip(state.chunks_exact_mut(4)) {
            let (c0, c1, c2, c3) = (c[0], c[1], c[2], c[3]);
            let q0 = ((c3 * u0 + c2) * u0 + c1) * u0 + c0;
            let q1 = (3.0 * c3 * u0 + 2.0 * c2) * u0 + c1;
            let q2 = 3.0 * c3 * u0 + c2;
            let q3 = c3;
            let d1 = q3 * h3 + q2 * h2 + q1 * h;
            let d2 = 6.0 * q3 * h3 + 2.0 * q2 * h2;
            let d3s = 6.0 * q3 * h3;
            st.copy_from_slice(&[q0, d1, d2, d3s]);
            f_max = f_max.max(q0.abs() + q1.abs() * x + q2.abs() * x * x + q3.abs() * x * x * x);
            d1_max = d1_max.max(d1.abs() + d2.abs() * lenf + d3s.abs() * lenf * lenf);
            d2_max = d2_max.max(d2.abs() + d3s.abs() * lenf);
        }
        match d {
            1 => fd_steps::<1>(state, out),
            2 => fd_steps::<2>(state, out),
            3 => fd_steps::<3>(state, out),
            _ => {
                for row in out.chunks_exact_mut(d) {
                    for (o, st) in row.iter_mut().zip(state.chunks_exact_mut(4)) {
                        *o = st[0];
                        st[0] += st[1];
                        st[1] += st[2];
                        st[2] += st[3];
                    }
                }
            }
        }
        let j = len as f64;
        let unit = f64::EPSILON / 2.0;
        // Drift of the recurrence, plus the error of the starting differences (a few eps of
        // the values: the Taylor coefficients are sums of at most four products).
        FdReport {
            max_steps: len,
            bound: unit * (j * f_max + j * j / 2.0 * d1_max + j * j * j / 6.0 * d2_max)
                + 16.0 * f64::EPSILON * f_max,
        }
    }

    /// Taylor coefficients of the polynomial piece of span `s` at its left knot t_s:
    /// `out[4c + k]` is the coefficient of (t - t_s)^k of coordinate c. Uniform cubics take
    /// them from the matrix form (1); other knots from the derivatives at t_s (exact knot,
    /// no parameter rounding).
    pub(super) fn span_taylor(&self, s: usize, out: &mut [f64]) {
        let (d, p) = (self.dim(), self.degree());
        let control = self.control_flat();
        out.iter_mut().for_each(|o| *o = 0.0);
        if let (Some(h), 3) = (self.uniform_step(), p) {
            let q = |r: usize, c: usize| control[(s - 3 + r) * d + c];
            for (c, o) in out.chunks_exact_mut(4).enumerate() {
                let (p0, p1, p2, p3) = (q(0, c), q(1, c), q(2, c), q(3, c));
                o[0] = (p0 + 4.0 * p1 + p2) / 6.0;
                o[1] = (p2 - p0) / (2.0 * h);
                o[2] = (p0 - 2.0 * p1 + p2) / (2.0 * h * h);
                o[3] = (3.0 * (p1 - p2) + p3 - p0) / (6.0 * h * h * h);
            }
            return;
        }
        if p == 3 {
            // Non-uniform cubic: the value from the basis at the span's left knot k_s, the
            // derivatives from their control points on the span (de Boor's differences)
            // there, where the quadratic's first two basis functions are the non-zero ones.
            let k = &self.knots()[s - 2..s + 4];
            let (h_prev, h) = (k[2] - k[1], k[3] - k[2]);
            let inv_2 = 1.0 / (k[3] - k[1]);
            let [n0, n1, n2] = cubic_basis_at_knot(self.knots(), s - 3);
            let q = |r: usize, c: usize| control[(s - 3 + r) * d + c];
            for (c, o) in out.chunks_exact_mut(4).enumerate() {
                let (p0, p1, p2, p3) = (q(0, c), q(1, c), q(2, c), q(3, c));
                let d0 = 3.0 * (p1 - p0) / (k[3] - k[0]);
                let d1 = 3.0 * (p2 - p1) / (k[4] - k[1]);
                let d2 = 3.0 * (p3 - p2) / (k[5] - k[2]);
                let e0 = 2.0 * (d1 - d0) * inv_2;
                let e1 = 2.0 * (d2 - d1) / (k[4] - k[2]);
                o[0] = n0 * p0 + n1 * p1 + n2 * p2;
                o[1] = (h * d0 + h_prev * d1) * inv_2;
                o[2] = e0 / 2.0;
                o[3] = (e1 - e0) / (6.0 * h);
            }
            return;
        }
        let ders = basis_funs_derivs(self.knots(), s, self.knots()[s], p, p);
        let mut factorial = 1.0;
        for (k, row) in ders[..=p].iter().enumerate() {
            if k > 0 {
                factorial *= k as f64;
            }
            for (r, w) in row[..=p].iter().enumerate() {
                let point = &control[(s - p + r) * d..(s - p + r + 1) * d];
                for (c, v) in point.iter().enumerate() {
                    out[4 * c + k] += w * v / factorial;
                }
            }
        }
    }

    /// Evaluates at arbitrary parameters (sorted or not) into `out`; for uniform knots the
    /// span is found by one multiplication (by the reciprocal of the spacing), otherwise
    /// from a bucket table over the domain (built for large batches) or a binary search,
    /// after trying the previous point's span (sorted parameters cost O(1) each). In
    /// parallel over blocks; cubics of dimension 1 to 3 take a specialized kernel (with
    /// AVX-512, blocks of parameters within a few knot spans take their knots and control
    /// points from small tables). Same values, bit for bit, as [`Curve::eval_into`].
    /// Errors: wrong buffer length; a parameter that is not finite (the first is named;
    /// `out` then holds the values of some of the others, and is best not read).
    pub fn eval_many_par(&self, ts: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim();
        check_buffer(ts.len(), d, out)?;
        let locator = self.locator(ts.len());
        let kernel = self.batch_kernel();
        // Each chunk checks its own parameters before it evaluates them (a pass over memory
        // the chunk then reads from the cache, in parallel; a separate check would read all
        // parameters once more, on one thread).
        let non_finite = AtomicBool::new(false);
        out.par_chunks_mut(4096 * d)
            .zip(ts.par_chunks(4096))
            .for_each(|(o, t)| {
                if all_finite(t) {
                    kernel(self, &locator, t, o);
                } else {
                    non_finite.store(true, Ordering::Relaxed);
                }
            });
        if non_finite.into_inner() {
            check_finite("parameter", ts)?;
        }
        Ok(())
    }

    /// [`BsplineCurve::eval_many_par`] on the calling thread (the curve's
    /// [`Curve::eval_batch`] with [`crate::geom::Parallelism::Sequential`]): the same kernels,
    /// the same bits.
    pub(crate) fn eval_many_seq(&self, ts: &[f64], out: &mut [f64]) -> Result<()> {
        check_eval_args("parameter", ts, ts.len(), self.dim(), out)?;
        let locator = self.locator(ts.len());
        (self.batch_kernel())(self, &locator, ts, out);
        Ok(())
    }

    /// The span locator for a batch of `count` parameters.
    fn locator(&self, count: usize) -> Locator<'_> {
        let inv_step = self.uniform_step().map(|h| 1.0 / h);
        Locator::new(
            self.knots(),
            self.degree(),
            self.n_control(),
            inv_step,
            count,
        )
    }

    /// The batch kernel for the curve's degree and dimension.
    fn batch_kernel(&self) -> fn(&BsplineCurve, &Locator, &[f64], &mut [f64]) {
        match (self.degree(), self.dim()) {
            (3, 1) => eval_cubic_best::<1>,
            (3, 2) => eval_cubic_best::<2>,
            (3, 3) => eval_cubic_best::<3>,
            _ => eval_general,
        }
    }
}

/// The forward-difference recurrence over `out` (rows of D coordinates) with the state held
/// in registers: per coordinate [value, Δ, Δ², Δ³].
#[inline]
fn fd_steps<const D: usize>(state: &[f64], out: &mut [f64]) {
    let mut st = [[0.0f64; 4]; D];
    for (c, s) in st.iter_mut().enumerate() {
        s.copy_from_slice(&state[4 * c..4 * c + 4]);
    }
    for row in out.chunks_exact_mut(D) {
        for (o, s) in row.iter_mut().zip(st.iter_mut()) {
            *o = s[0];
            s[0] += s[1];
            s[1] += s[2];
            s[2] += s[3];
        }
    }
}

/// [`eval_cubic`], compiled for AVX-512 or AVX2 where the CPU has them.
fn eval_cubic_best<const D: usize>(
    curve: &BsplineCurve,
    loc: &Locator,
    ts: &[f64],
    out: &mut [f64],
) {
    with_avx512(
        #[inline(always)]
        || eval_cubic::<D>(curve, loc, ts, out),
    )
}

/// [`BsplineCurve::eval_many_par`]'s kernel for cubics in dimension D, block by block
/// ([`CubicLanes`]).
#[inline(always)]
fn eval_cubic<const D: usize>(curve: &BsplineCurve, loc: &Locator, ts: &[f64], out: &mut [f64]) {
    let control = curve.control_flat();
    let mut lanes = CubicLanes::new();
    let fetch = Prefetcher::new();
    // Bits of what the touch phases read, folded by xor: one cycle each, where a sum of
    // floats would chain four (and convert the table's integers first).
    let mut touched = 0u64;
    let mut narrow = Narrow::new(loc);
    for (tb, ob) in ts.chunks(BLOCK).zip(out.chunks_mut(BLOCK * D)) {
        if let Ok(x) = tb.try_into() {
            if narrow.eval_cubic::<D>(loc, control, x, ob) {
                continue;
            }
        }
        let n = tb.len();
        lanes.x[..n].copy_from_slice(tb);
        // The span is the table's base span or the next one: their first control point.
        let near = |s: usize| control[(s - 3) * D].to_bits();
        // Sorted parameters read what the previous point read or what follows it: nothing
        // to touch ahead.
        let sorted = lanes.sorted(n);
        let touch = !sorted;
        if !(sorted && lanes.locate_sorted(loc, n)) {
            lanes.locate(loc, n, touch, &mut touched, near);
        }
        // Request the control points and knots each evaluation reads.
        if touch {
            for &s in &lanes.span[..n] {
                fetch.touch(&control[(s - 3) * D], &mut touched);
                fetch.touch(&control[(s + 1) * D - 1], &mut touched);
                CubicLanes::touch_knots(loc, s, fetch, &mut touched);
            }
        }
        lanes.basis(loc, n);
        for (i, o) in ob.chunks_exact_mut(D).enumerate() {
            let s = lanes.span[i];
            let c = &control[(s - 3) * D..(s + 1) * D];
            let mut acc = [0.0f64; D];
            for (b, row) in lanes.basis.iter().zip(c.chunks_exact(D)) {
                for (a, x) in acc.iter_mut().zip(row) {
                    *a += b[i] * x;
                }
            }
            o.copy_from_slice(&acc);
        }
    }
    std::hint::black_box(touched);
}

/// [`BsplineCurve::eval_many_par`]'s kernel for other degrees and dimensions.
fn eval_general(curve: &BsplineCurve, loc: &Locator, ts: &[f64], out: &mut [f64]) {
    let mut hint = loc.lo;
    for (&t, o) in ts.iter().zip(out.chunks_exact_mut(curve.dim())) {
        let s = loc.span(t, hint);
        hint = s;
        curve.eval_span_into(s, t, o);
    }
}
