//! Composite surfaces from patches on an orthogonal grid: formulas (3)-(9) (parametric) and
//! (10)-(11) (explicit) of spec/composite-surfaces.md, the continuity report, the literal
//! single formula evaluated in f64 and the structural evaluator.
//!
//! The structural evaluator locates the cell of (u, v) (one division on uniform knots, a
//! binary search otherwise) and evaluates one polynomial there: the patch itself plus what
//! formula (9) adds when the patches do not meet — the edge terms of the cells before it in
//! its row and column. It therefore equals the single formula everywhere, outside the grid
//! (points map onto the boundary) and where continuity fails (patches shifted to stay
//! attached), not only where the patches are continuous.
//!
//! ```
//! use geomkit::bezier::BezierSurface;
//! use geomkit::compose::CompositeSurface;
//! // Two bilinear patches meeting along u = 1.
//! let a = BezierSurface::new(vec![vec![vec![0., 0., 0.], vec![0., 1., 0.]],
//!                                 vec![vec![1., 0., 0.], vec![1., 1., 1.]]]).unwrap();
//! let b = BezierSurface::new(vec![vec![vec![1., 0., 0.], vec![1., 1., 1.]],
//!                                 vec![vec![2., 0., 0.], vec![2., 1., 0.]]]).unwrap();
//! let s = CompositeSurface::from_bezier(vec![0., 1., 2.], vec![0., 1.], &[vec![a], vec![b]]).unwrap();
//! assert!(s.continuity().is_continuous());
//! let p = s.eval(1.5, 0.5);
//! assert!((p[0] - 1.5).abs() < 1e-15 && (p[2] - 0.25).abs() < 1e-15);
//! assert!((s.eval_formula(1.5, 0.5)[2] - 0.25).abs() < 1e-15);
//! ```

use super::formula::{coef, num, Formula};
use super::grid::Axis;
use super::poly::PolyPatch;
use super::ramp::ramp;
use crate::bezier::BezierSurface;
use crate::bspline::BsplineSurface;
use crate::expr::{Const, Graph, Id};
use crate::points::check_eval_args;
use crate::{Error, Result};
use rayon::prelude::*;

/// Samples per shared edge in the continuity report (both corners included).
pub const EDGE_SAMPLES: usize = 65;

/// Points evaluated per parallel task.
const PAR_CHUNK: usize = 4096;

/// A grid line shared by two cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridLine {
    /// u = u_i, between cells (i-1, j) and (i, j).
    U(usize),
    /// v = v_j, between cells (i, j-1) and (i, j).
    V(usize),
}

/// The largest jump between the two patches along one shared edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jump {
    /// The grid line.
    pub line: GridLine,
    /// The index of the cell along the line (j for a u-line, i for a v-line).
    pub cell: usize,
    /// Largest Euclidean distance between the two patches on the edge (sampled).
    pub max_jump: f64,
    /// The parameter along the line where it occurs (v for a u-line, u for a v-line).
    pub at: f64,
}

/// For every shared grid line, the largest jump between neighbours (sampled at
/// [`EDGE_SAMPLES`] points per edge, corners included), and whether formula (9) reproduces
/// the patches or shifts them.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuityReport {
    /// One entry per shared edge (cell side), u-lines first.
    pub jumps: Vec<Jump>,
    /// The largest of all jumps (0 for a single patch).
    pub max_jump: f64,
    /// Jumps up to this are rounding: 64 ε times the largest coordinate sampled.
    pub tolerance: f64,
}

impl ContinuityReport {
    /// Whether every jump is within the tolerance.
    pub fn is_continuous(&self) -> bool {
        self.max_jump <= self.tolerance
    }

    /// The worst edge, if any.
    pub fn worst(&self) -> Option<&Jump> {
        self.jumps
            .iter()
            .max_by(|a, b| a.max_jump.total_cmp(&b.max_jump))
    }

    /// A sentence for users: continuous, or where it is not and what the formula then does.
    pub fn statement(&self, u_name: &str, v_name: &str, knots: (&[f64], &[f64])) -> String {
        match self.worst() {
            None => "a single patch: nothing to join".to_string(),
            Some(_) if self.is_continuous() => format!(
                "continuous: the largest jump between neighbouring patches is {:.2e} \
                 (tolerance {:.2e}); the formula reproduces every patch",
                self.max_jump, self.tolerance
            ),
            Some(w) => {
                let bad = self
                    .jumps
                    .iter()
                    .filter(|j| j.max_jump > self.tolerance)
                    .count();
                let (place, along) = match w.line {
                    GridLine::U(i) => (
                        format!(
                            "{u_name} = {} between cells ({}, {}) and ({i}, {})",
                            knots.0[i],
                            i - 1,
                            w.cell,
                            w.cell
                        ),
                        format!("{v_name} = {}", w.at),
                    ),
                    GridLine::V(j) => (
                        format!(
                            "{v_name} = {} between cells ({}, {}) and ({}, {j})",
                            knots.1[j],
                            w.cell,
                            j - 1,
                            w.cell
                        ),
                        format!("{u_name} = {}", w.at),
                    ),
                };
                format!(
                    "NOT continuous: {bad} of {} shared edges jump, the largest by {:.3e} on \
                     {place} at {along}; the single formula (9) is still continuous: it \
                     matches patch (0, 0) and shifts the other patches to stay attached, so it \
                     differs from them there",
                    self.jumps.len(),
                    self.max_jump
                )
            }
        }
    }
}

/// Whether a surface is parametric (formulas (3)-(9), variables u, v) or a height field
/// z(x, y) (formulas (10)-(11)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceKind {
    /// r_ij(u, v), points in R^dim.
    Parametric,
    /// z_ij(x, y), one coordinate.
    Explicit,
}

/// A composite surface: knots u_0 < ... < u_n, v_0 < ... < v_m and a patch per cell, with its
/// continuity report and its structural evaluator.
#[derive(Debug, Clone)]
pub struct CompositeSurface {
    u: Axis,
    v: Axis,
    dim: usize,
    kind: SurfaceKind,
    /// patches[i * m + j] on cell [u_i, u_(i+1)] × [v_j, v_(j+1)], in local (s, t).
    patches: Vec<PolyPatch>,
    /// The polynomial formula (9) equals on each cell (patch plus shift).
    effective: Vec<PolyPatch>,
    report: ContinuityReport,
}

impl CompositeSurface {
    /// A composite surface from polynomial patches in local coordinates:
    /// `patches[i][j]` on cell [u_i, u_(i+1)] × [v_j, v_(j+1)] with (s, t) ∈ [0, 1]² mapped
    /// linearly onto it. Errors: knots not finite and strictly increasing (at least 2),
    /// wrong number of patch rows or patches in a row, patches of different dimensions.
    pub fn from_poly(
        u_knots: Vec<f64>,
        v_knots: Vec<f64>,
        patches: Vec<Vec<PolyPatch>>,
        kind: SurfaceKind,
    ) -> Result<Self> {
        let u = Axis::new("u knots", u_knots)?;
        let v = Axis::new("v knots", v_knots)?;
        let (n, m) = (u.cells(), v.cells());
        if patches.len() != n {
            return Err(Error::PatchCount {
                what: format!("patch rows for {} u knots", n + 1),
                expected: n,
                got: patches.len(),
            });
        }
        let mut flat = Vec::with_capacity(n * m);
        for (i, row) in patches.into_iter().enumerate() {
            if row.len() != m {
                return Err(Error::PatchCount {
                    what: format!("patches in row {i} for {} v knots", m + 1),
                    expected: m,
                    got: row.len(),
                });
            }
            flat.extend(row);
        }
        let dim = flat[0].dim();
        if let Some(k) = flat.iter().position(|p| p.dim() != dim) {
            return Err(Error::DimensionMismatch {
                what: "patch",
                index: k,
                expected: dim,
                got: flat[k].dim(),
            });
        }
        if kind == SurfaceKind::Explicit && dim != 1 {
            return Err(Error::WrongDimension {
                operation: "an explicit surface z(x, y)",
                expected: 1,
                got: dim,
            });
        }
        let effective = effective_patches(&flat, n, m);
        let mut s = CompositeSurface {
            u,
            v,
            dim,
            kind,
            patches: flat,
            effective,
            report: ContinuityReport {
                jumps: vec![],
                max_jump: 0.0,
                tolerance: 0.0,
            },
        };
        s.report = s.measure_continuity();
        Ok(s)
    }

    /// A composite surface from Bézier patches, each on [0, 1]² mapped onto its cell.
    pub fn from_bezier(
        u_knots: Vec<f64>,
        v_knots: Vec<f64>,
        patches: &[Vec<BezierSurface>],
    ) -> Result<Self> {
        let polys = patches
            .iter()
            .map(|row| row.iter().map(PolyPatch::from_bezier).collect())
            .collect();
        Self::from_poly(u_knots, v_knots, polys, SurfaceKind::Parametric)
    }

    /// The composite surface of a B-spline surface's cells: one polynomial patch per
    /// non-empty knot span pair, the grid its distinct knots (the single formula then equals
    /// the B-spline surface on its domain).
    pub fn from_bspline(s: &BsplineSurface) -> Result<Self> {
        let (uc, vc, patches) = PolyPatch::from_bspline(s);
        let m = vc.len() - 1;
        let rows = patches.chunks(m).map(<[PolyPatch]>::to_vec).collect();
        let kind = if s.dim() == 1 {
            SurfaceKind::Explicit
        } else {
            SurfaceKind::Parametric
        };
        Self::from_poly(uc, vc, rows, kind)
    }

    /// Knots (u, v).
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (self.u.knots(), self.v.knots())
    }

    /// Number of cells (n, m).
    pub fn cells(&self) -> (usize, usize) {
        (self.u.cells(), self.v.cells())
    }

    /// Dimension of the points (1 for explicit surfaces).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Parametric or explicit.
    pub fn kind(&self) -> SurfaceKind {
        self.kind
    }

    /// The patch of cell (i, j), in local coordinates.
    pub fn patch(&self, i: usize, j: usize) -> &PolyPatch {
        &self.patches[i * self.v.cells() + j]
    }

    /// The continuity report (computed once, at construction).
    pub fn continuity(&self) -> &ContinuityReport {
        &self.report
    }

    /// Parameter domain ((u_0, u_n), (v_0, v_m)).
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        let (u, v) = self.knots();
        ((u[0], u[u.len() - 1]), (v[0], v[v.len() - 1]))
    }

    /// The structural evaluator: locate the cell, evaluate one polynomial (O(1) on uniform
    /// knots, O(log n + log m) otherwise). Equal to the single formula (9) within rounding,
    /// everywhere. `out` has length dim.
    #[inline]
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let (i, s) = self.u.locate(u);
        let (j, t) = self.v.locate(v);
        self.effective[i * self.v.cells() + j].eval_into(s, t, out);
    }

    /// [`Self::eval_into`] into a new vector.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(u, v, &mut out);
        out
    }

    /// Evaluates at the pairs `uv = [u0, v0, u1, v1, ...]` into `out` (dim numbers per
    /// point), in parallel for large batches. Errors: odd `uv`, wrong buffer length,
    /// non-finite parameters.
    pub fn eval_many(&self, uv: &[f64], out: &mut [f64]) -> Result<()> {
        if !uv.len().is_multiple_of(2) {
            return Err(Error::BufferSize {
                expected: uv.len() + 1,
                got: uv.len(),
            });
        }
        let d = self.dim;
        check_eval_args("parameter", uv, uv.len() / 2, d, out)?;
        let run = |(pts, o): (&[f64], &mut [f64])| {
            for (q, p) in pts.chunks_exact(2).zip(o.chunks_exact_mut(d)) {
                self.eval_into(q[0], q[1], p);
            }
        };
        if uv.len() / 2 > PAR_CHUNK {
            uv.par_chunks(2 * PAR_CHUNK)
                .zip(out.par_chunks_mut(d * PAR_CHUNK))
                .for_each(run);
        } else {
            run((uv, out));
        }
        Ok(())
    }

    /// Evaluates on the grid `us` × `vs`: point (a, b) at `out[(a * vs.len() + b) * dim ..]`.
    /// Cells are located once per u and once per v; rows run in parallel. Errors: wrong
    /// buffer length, non-finite parameters.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_eval_args("parameter u", us, us.len() * vs.len(), d, out)?;
        if let Some(index) = vs.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                what: "parameter v",
                index,
            });
        }
        if vs.is_empty() {
            return Ok(());
        }
        let located: Vec<(usize, f64)> = vs.iter().map(|&v| self.v.locate(v)).collect();
        let m = self.v.cells();
        let row = |(u, o): (&f64, &mut [f64])| {
            let (i, s) = self.u.locate(*u);
            let cells = &self.effective[i * m..(i + 1) * m];
            for (&(j, t), p) in located.iter().zip(o.chunks_exact_mut(d)) {
                cells[j].eval_into(s, t, p);
            }
        };
        if us.len() * vs.len() > PAR_CHUNK {
            us.par_iter()
                .zip(out.par_chunks_mut(vs.len() * d))
                .for_each(row);
        } else {
            us.iter().zip(out.chunks_mut(vs.len() * d)).for_each(row);
        }
        Ok(())
    }

    /// The single formula (9) (or (11)) evaluated literally in f64, O(n m) per point: the
    /// reference the structural evaluator and the printed formulas are tested against.
    pub fn eval_formula(&self, u: f64, v: f64) -> Vec<f64> {
        let (uk, vk) = self.knots();
        let (n, m) = self.cells();
        let d = self.dim;
        let ss: Vec<f64> = (0..n).map(|i| ramp(u, uk[i], uk[i + 1] - uk[i])).collect();
        let ts: Vec<f64> = (0..m).map(|j| ramp(v, vk[j], vk[j + 1] - vk[j])).collect();
        let mut out = vec![0.0; d];
        let mut tmp = vec![0.0; d];
        for i in 0..n {
            for j in 0..m {
                let p = self.patch(i, j);
                // R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) + R_ij(u_i,v_j), terms present as in (9).
                let terms: [(f64, f64, f64, bool); 4] = [
                    (ss[i], ts[j], 1.0, true),
                    (0.0, ts[j], -1.0, i >= 1),
                    (ss[i], 0.0, -1.0, j >= 1),
                    (0.0, 0.0, 1.0, i >= 1 && j >= 1),
                ];
                for (s, t, sign, present) in terms {
                    if present {
                        p.eval_into(s, t, &mut tmp);
                        for k in 0..d {
                            out[k] += sign * tmp[k];
                        }
                    }
                }
            }
        }
        out
    }

    /// The single formula (9) (parametric: x, y, z in u, v) or (11) (explicit: z in x, y).
    /// Each patch enters through its local coordinates s_i = P(u, u_i, u_(i+1) - u_i) and
    /// t_j = P(v, v_j, v_(j+1) - v_j) (formula (3): the clamped arguments mapped onto the
    /// patch's own domain [0, 1]²), and the four terms of (9),
    /// `R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) + R_ij(u_i,v_j)`, are collected symbolically: for a polynomial patch they are
    /// exactly s^[i>=1] t^[j>=1] times a polynomial, printed in Horner form. Knots print as
    /// exact rationals (decimal inputs become their fractions).
    pub fn formula(&self) -> Result<Formula> {
        let mut g = Graph::new();
        let (names, vars): (Vec<&str>, [&str; 2]) = match self.kind {
            SurfaceKind::Parametric => (vec!["x", "y", "z"], ["u", "v"]),
            SurfaceKind::Explicit => (vec!["z"], ["x", "y"]),
        };
        let names: Vec<String> = if self.dim <= 3 {
            names[..self.dim].iter().map(|s| s.to_string()).collect()
        } else {
            (0..self.dim).map(|k| format!("x{k}")).collect()
        };
        let (uk, vk) = self.knots();
        let u = g.var(vars[0]);
        let v = g.var(vars[1]);
        let ss = ramps(&mut g, u, uk)?;
        let ts = ramps(&mut g, v, vk)?;
        let (n, m) = self.cells();
        let mut sums: Vec<Vec<Id>> = vec![Vec::with_capacity(n * m); self.dim];
        for i in 0..n {
            for j in 0..m {
                let p = self.patch(i, j);
                let (a0, b0) = (usize::from(i >= 1), usize::from(j >= 1));
                for (k, sum) in sums.iter_mut().enumerate() {
                    let h = horner2(&mut g, p, k, (a0, b0), ss[i], ts[j]);
                    let mut factors = vec![(h, 1)];
                    if a0 == 1 {
                        factors.push((ss[i], 1));
                    }
                    if b0 == 1 {
                        factors.push((ts[j], 1));
                    }
                    let term = g.prod(&factors);
                    sum.push(term);
                }
            }
        }
        let roots = sums.iter().map(|terms| g.sum(terms)).collect();
        Ok(Formula {
            graph: g,
            roots,
            names,
            vars: vars.iter().map(|s| s.to_string()).collect(),
        })
    }

    fn measure_continuity(&self) -> ContinuityReport {
        let (n, m) = self.cells();
        let (uk, vk) = self.knots();
        let d = self.dim;
        let mut jumps = Vec::new();
        let mut scale = 0.0f64;
        let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
        let mut edge = |p: &PolyPatch, q: &PolyPatch, across_u: bool, lo: f64, hi: f64| {
            let (mut worst, mut at) = (0.0f64, lo);
            for k in 0..EDGE_SAMPLES {
                let x = k as f64 / (EDGE_SAMPLES - 1) as f64;
                if across_u {
                    p.eval_into(1.0, x, &mut a);
                    q.eval_into(0.0, x, &mut b);
                } else {
                    p.eval_into(x, 1.0, &mut a);
                    q.eval_into(x, 0.0, &mut b);
                }
                let dist = crate::numeric::distance(&a, &b);
                scale = a.iter().chain(&b).fold(scale, |m, c| m.max(c.abs()));
                if dist > worst || dist.is_nan() {
                    worst = dist;
                    at = lo + x * (hi - lo);
                }
            }
            (worst, at)
        };
        for i in 1..n {
            for j in 0..m {
                let (max_jump, at) = edge(
                    self.patch(i - 1, j),
                    self.patch(i, j),
                    true,
                    vk[j],
                    vk[j + 1],
                );
                jumps.push(Jump {
                    line: GridLine::U(i),
                    cell: j,
                    max_jump,
                    at,
                });
            }
        }
        for j in 1..m {
            for i in 0..n {
                let (max_jump, at) = edge(
                    self.patch(i, j - 1),
                    self.patch(i, j),
                    false,
                    uk[i],
                    uk[i + 1],
                );
                jumps.push(Jump {
                    line: GridLine::V(j),
                    cell: i,
                    max_jump,
                    at,
                });
            }
        }
        let max_jump = jumps.iter().fold(0.0f64, |m, j| m.max(j.max_jump));
        ContinuityReport {
            jumps,
            max_jump,
            tolerance: 64.0 * f64::EPSILON * scale.max(f64::MIN_POSITIVE),
        }
    }
}

/// The polynomials formula (9) equals on each cell: with D_ij the patch minus its row a = 0
/// (for i >= 1) and column b = 0 (for j >= 1), i.e. R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) +
/// R_ij(u_i,v_j), cell (p, q) carries D_pq(s,t) + Σ_(i<p) D_iq(1,t) + Σ_(j<q) D_pj(s,1) +
/// Σ_(i<p, j<q) D_ij(1,1): the cells before it contribute their far edges (clamped P = 1).
fn effective_patches(patches: &[PolyPatch], n: usize, m: usize) -> Vec<PolyPatch> {
    let d = patches[0].dim();
    let diff: Vec<PolyPatch> = (0..n * m)
        .map(|k| {
            let (i, j) = (k / m, k % m);
            let mut p = patches[k].clone();
            if i >= 1 {
                let edge = p.at_s(0.0);
                p.add_scaled(&edge, -1.0);
            }
            if j >= 1 {
                let edge = p.at_t(0.0);
                p.add_scaled(&edge, -1.0);
            }
            // For i, j >= 1 the second step subtracts R(s,0) - R(0,0): the corner is back.
            p
        })
        .collect();
    // Column sums in t (cells i < p of column q) and row sums in s (cells j < q of row p).
    let max_q = |q: usize| {
        (0..n)
            .map(|i| diff[i * m + q].degrees().1)
            .max()
            .unwrap_or(0)
    };
    let max_p = |p: usize| {
        (0..m)
            .map(|j| diff[p * m + j].degrees().0)
            .max()
            .unwrap_or(0)
    };
    let mut col_before = vec![PolyPatch::zero((0, 0), d); n * m];
    for q in 0..m {
        let mut acc = PolyPatch::zero((0, max_q(q)), d);
        for p in 0..n {
            col_before[p * m + q] = acc.clone();
            acc.add_scaled(&diff[p * m + q].at_s(1.0), 1.0);
        }
    }
    let mut row_before = vec![PolyPatch::zero((0, 0), d); n * m];
    for p in 0..n {
        let mut acc = PolyPatch::zero((max_p(p), 0), d);
        for q in 0..m {
            row_before[p * m + q] = acc.clone();
            acc.add_scaled(&diff[p * m + q].at_t(1.0), 1.0);
        }
    }
    // 2-D prefix sums of the far corners D_ij(1,1).
    let mut corner = vec![vec![0.0; d]; (n + 1) * (m + 1)];
    for p in 0..n {
        for q in 0..m {
            let c = diff[p * m + q].eval(1.0, 1.0);
            for k in 0..d {
                corner[(p + 1) * (m + 1) + q + 1][k] =
                    c[k] + corner[p * (m + 1) + q + 1][k] + corner[(p + 1) * (m + 1) + q][k]
                        - corner[p * (m + 1) + q][k];
            }
        }
    }
    (0..n * m)
        .map(|k| {
            let (p, q) = (k / m, k % m);
            let own = &diff[k];
            let deg = (
                own.degrees().0.max(row_before[k].degrees().0),
                own.degrees().1.max(col_before[k].degrees().1),
            );
            let mut e = own.padded(deg);
            e.add_scaled(&col_before[k], 1.0);
            e.add_scaled(&row_before[k], 1.0);
            let c = PolyPatch::new((0, 0), d, corner[p * (m + 1) + q].clone())
                .expect("finite corner sums");
            e.add_scaled(&c, 1.0);
            e
        })
        .collect()
}

/// The ramps P(x, x_i, x_(i+1) - x_i) of every cell of one direction.
fn ramps(g: &mut Graph, x: Id, knots: &[f64]) -> Result<Vec<Id>> {
    knots
        .windows(2)
        .map(|w| {
            // The width from the exact knots, so that consecutive ramps share |x - x_i|.
            let a = num(g, w[0]);
            let b = num(g, w[1]);
            let width = g.sub(b, a);
            let wf = g.as_const(width).map_or(w[1] - w[0], Const::to_f64);
            super::ramp::check_width("knot interval", wf)?;
            let two = g.int(2);
            let t_a = g.sub(x, a);
            let t_b = g.sub(x, b);
            let abs_a = g.abs(t_a);
            let abs_b = g.abs(t_b);
            let diff = g.sub(abs_a, abs_b);
            let sum = g.add(width, diff);
            let den = g.mul(two, width);
            Ok(g.div(sum, den))
        })
        .collect()
}

/// Σ_(a >= a0, b >= b0) c_ab s^(a-a0) t^(b-b0) for coordinate k, Horner in t inside
/// Horner in s.
fn horner2(g: &mut Graph, p: &PolyPatch, k: usize, (a0, b0): (usize, usize), s: Id, t: Id) -> Id {
    let (deg_a, deg_b) = p.degrees();
    let one = g.int(1);
    let mut outer: Option<Id> = None;
    for a in (a0..=deg_a).rev() {
        let mut inner: Option<Id> = None;
        for b in (b0..=deg_b).rev() {
            let c = coef(g, p.coefficient(a, b)[k]);
            inner = Some(match inner {
                None => c,
                Some(h) => {
                    let th = g.mul(t, h);
                    g.add(c, th)
                }
            });
        }
        let r = inner.unwrap_or(one);
        outer = Some(match outer {
            None => r,
            Some(h) => {
                let sh = g.mul(s, h);
                g.add(r, sh)
            }
        });
    }
    outer.unwrap_or_else(|| g.int(0))
}
