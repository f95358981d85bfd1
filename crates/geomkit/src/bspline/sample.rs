//! Evaluation of B-spline curves on uniform samples by forward differences (spec
//! §4: each next point of a cubic piece with three additions per coordinate), restarted at
//! every knot span so that the drift stays bounded, and in parallel over spans.
//!
//! Drift bound: within a span, with u the unit roundoff (eps/2), after j steps from exact
//! starting differences the value differs from exact evaluation by at most
//! u·(j·F + j²/2·D1 + j³/6·D2) + 4·eps·F, where F, D1, D2 bound |p|, |Δp|, |Δ²p| over the
//! span ([`FdReport::bound`] is that bound at the longest span run). Restarting per span
//! keeps j below the samples per span.

use super::curve::BsplineCurve;
use crate::bezier::ParamCurve;
use crate::points::check_eval_args;
use crate::{Error, Result};
use rayon::prelude::*;

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
        let knots = self.knots();
        let (t_s, t_e) = (knots[s], knots[s + 1]);
        // The span's cubic from its values at four equally spaced points (Newton form), as
        // Taylor coefficients in x = t - t_s.
        let g = (t_e - t_s) / 3.0;
        let (vals, state) = scratch.split_at_mut(4 * d);
        for k in 0..4 {
            // Evaluate inside the span (the last point at its right end belongs to it too).
            let t = if k == 3 { t_e } else { t_s + k as f64 * g };
            let row = &mut vals[k * d..(k + 1) * d];
            self.eval_span_into(s, t, row);
        }
        let u0 = a + k0 as f64 * step - t_s;
        let (h, h2, h3) = (step, step * step, step * step * step);
        let (mut f_max, mut d1_max, mut d2_max) = (0.0f64, 0.0f64, 0.0f64);
        for c in 0..d {
            let f = [vals[c], vals[d + c], vals[2 * d + c], vals[3 * d + c]];
            let (d10, d11, d12) = (f[1] - f[0], f[2] - f[1], f[3] - f[2]);
            let (d20, d21) = (d11 - d10, d12 - d11);
            let d3 = d21 - d20;
            // In the step variable σ = x / g.
            let s3 = d3 / 6.0;
            let s2 = d20 / 2.0 - d3 / 2.0;
            let s1 = d10 - d20 / 2.0 + d3 / 3.0;
            let (c0, c1, c2, c3) = (f[0], s1 / g, s2 / (g * g), s3 / (g * g * g));
            // Shift to u0: q(x) = poly(u0 + x).
            let q0 = ((c3 * u0 + c2) * u0 + c1) * u0 + c0;
            let q1 = (3.0 * c3 * u0 + 2.0 * c2) * u0 + c1;
            let q2 = 3.0 * c3 * u0 + c2;
            let q3 = c3;
            let d1 = q3 * h3 + q2 * h2 + q1 * h;
            let d2 = 6.0 * q3 * h3 + 2.0 * q2 * h2;
            let d3s = 6.0 * q3 * h3;
            state[4 * c..4 * c + 4].copy_from_slice(&[q0, d1, d2, d3s]);
            let lenf = len as f64;
            let x = lenf * h;
            f_max = f_max.max(q0.abs() + q1.abs() * x + q2.abs() * x * x + q3.abs() * x * x * x);
            d1_max = d1_max.max(d1.abs() + d2.abs() * lenf + d3s.abs() * lenf * lenf);
            d2_max = d2_max.max(d2.abs() + d3s.abs() * lenf);
        }
        for row in out.chunks_exact_mut(d) {
            for (o, st) in row.iter_mut().zip(state.chunks_exact_mut(4)) {
                *o = st[0];
                st[0] += st[1];
                st[1] += st[2];
                st[2] += st[3];
            }
        }
        let j = len as f64;
        let unit = f64::EPSILON / 2.0;
        // Drift of the recurrence, plus the error of the fitted starting polynomial (a few
        // eps of the values; the Newton fit at four points amplifies by at most 10).
        FdReport {
            max_steps: len,
            bound: unit * (j * f_max + j * j / 2.0 * d1_max + j * j * j / 6.0 * d2_max)
                + 16.0 * f64::EPSILON * f_max,
        }
    }

    /// Evaluates at arbitrary parameters (sorted or not) into `out`; for uniform knots the
    /// span is found by one division, otherwise by binary search. In parallel over blocks.
    /// Errors: wrong buffer length, non-finite parameters.
    pub fn eval_many_par(&self, ts: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim();
        check_eval_args("parameter", ts, ts.len(), d, out)?;
        out.par_chunks_mut(4096 * d)
            .zip(ts.par_chunks(4096))
            .for_each(|(o, t)| {
                for (oo, tt) in o.chunks_exact_mut(d).zip(t) {
                    self.eval_into(*tt, oo);
                }
            });
        Ok(())
    }
}
