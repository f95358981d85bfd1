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

use super::expr_patch::{ExprPatch, Local};
use super::formula::{
    check_terms, coef_const, int_const, knot_hints, num, variable_bound, Formula, Hints,
};
use super::grid::{show, Axis};
use super::poly::PolyPatch;
use super::ramp::ramp;
use crate::bezier::BezierSurface;
use crate::bspline::BsplineSurface;
use crate::expr::{Const, Graph, Id, Tape};
use crate::geom::{check_pairs, check_point, BatchOptions, Surface};
use crate::par::*;
use crate::points::check_eval_args;
use crate::{Error, Result};

/// Samples per shared edge in the continuity report (both corners included).
pub const EDGE_SAMPLES: usize = 65;

/// Points evaluated per parallel task.
const PAR_CHUNK: usize = 4096;

/// A grid line shared by two cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
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
#[derive(Debug, Clone, PartialEq, Default)]
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
/// continuity report and its structural evaluator. Patches are polynomials ([`PolyPatch`],
/// from Bézier patches and B-spline cells) or formulas ([`ExprPatch`]).
#[derive(Debug, Clone)]
pub struct CompositeSurface {
    u: Axis,
    v: Axis,
    dim: usize,
    kind: SurfaceKind,
    /// Cell (i, j) at index i * m + j.
    cells: Cells,
    report: ContinuityReport,
}

/// The patches and what the structural evaluator runs on each cell.
#[derive(Debug, Clone)]
enum Cells {
    Poly {
        /// On cell [u_i, u_(i+1)] × [v_j, v_(j+1)], in local (s, t).
        patches: Vec<PolyPatch>,
        /// The polynomial formula (9) equals on each cell (patch plus shift).
        effective: Vec<PolyPatch>,
    },
    Expr {
        patches: Vec<ExprPatch>,
        /// Each patch's domain (its own, or its cell).
        domains: Vec<[(f64, f64); 2]>,
        /// What formula (9) equals on each cell, in the local variables `@s`, `@t`.
        effective: Vec<Tape>,
        /// The expressions of `effective`: one graph, `dim` roots per cell (for their
        /// symbolic derivatives).
        effective_exprs: Box<(Graph, Vec<Vec<Id>>)>,
    },
}

/// The grid of patches as one vector, row-major, after checking its shape.
fn flatten<T>(patches: Vec<Vec<T>>, n: usize, m: usize) -> Result<Vec<T>> {
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
    Ok(flat)
}

/// The common dimension of the patches, checked; 1 for explicit surfaces.
fn common_dim(dims: impl Iterator<Item = usize>, kind: SurfaceKind) -> Result<usize> {
    let dims: Vec<usize> = dims.collect();
    let dim = dims[0];
    if let Some(k) = dims.iter().position(|&d| d != dim) {
        return Err(Error::DimensionMismatch {
            what: "patch",
            index: k,
            expected: dim,
            got: dims[k],
        });
    }
    if kind == SurfaceKind::Explicit && dim != 1 {
        return Err(Error::WrongDimension {
            operation: "an explicit surface z(x, y)",
            expected: 1,
            got: dim,
        });
    }
    Ok(dim)
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
        Self::assemble(
            u_knots,
            v_knots,
            patches,
            kind,
            PolyPatch::dim,
            |u, v, flat| {
                let m = v.cells();
                if let Some(k) = flat.iter().position(|p| !p.is_finite()) {
                    return Err(Error::Overflow {
                        what: format!("patch ({}, {})", k / m, k % m),
                        step: "its power-basis coefficients overflow f64: control points near \
                               the end of its range"
                            .into(),
                    });
                }
                let effective = effective_patches(&flat, u.cells(), m)?;
                Ok(Cells::Poly {
                    patches: flat,
                    effective,
                })
            },
        )
    }

    /// Checks the grid and the patches, builds the cells, measures continuity and, for
    /// formula patches, compiles the structural evaluator's tapes.
    fn assemble<T>(
        u_knots: Vec<f64>,
        v_knots: Vec<f64>,
        patches: Vec<Vec<T>>,
        kind: SurfaceKind,
        dim_of: fn(&T) -> usize,
        cells: impl FnOnce(&Axis, &Axis, Vec<T>) -> Result<Cells>,
    ) -> Result<Self> {
        let u = Axis::new("u knots", u_knots)?;
        let v = Axis::new("v knots", v_knots)?;
        let flat = flatten(patches, u.cells(), v.cells())?;
        let dim = common_dim(flat.iter().map(dim_of), kind)?;
        let cells = cells(&u, &v, flat)?;
        let mut s = CompositeSurface {
            u,
            v,
            dim,
            kind,
            cells,
            report: ContinuityReport::default(),
        };
        s.report = s.measure_continuity()?;
        let (tapes, exprs) = s.effective_tapes()?;
        if let Cells::Expr {
            effective,
            effective_exprs,
            ..
        } = &mut s.cells
        {
            *effective = tapes;
            **effective_exprs = exprs;
        }
        Ok(s)
    }

    /// A composite surface from patches given as formulas in two variables (`u`, `v`, or
    /// `x`, `y` for explicit surfaces z(x, y)): `patches[i][j]` on cell [u_i, u_(i+1)] ×
    /// [v_j, v_(j+1)]; a patch with a domain of its own has it mapped linearly onto its cell
    /// (the paper's change of variables), one without is defined on the cell itself.
    ///
    /// The continuity report is sampled ([`EDGE_SAMPLES`] per edge). The structural
    /// evaluator runs, on each cell, the patch plus the jumps formula (9) adds for the edges
    /// before it in its row and column that the report finds discontinuous (a constant for
    /// the corners), compiled to one tape per cell.
    ///
    /// Errors: as [`Self::from_poly`]; patches in other than two variables; a patch that
    /// is not finite somewhere on a 9×9 grid of its domain ([`Error::Expression`]).
    ///
    /// ```
    /// use geomkit::compose::{CompositeSurface, ExprPatch, SurfaceKind};
    /// let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    /// // sin(x) cos(y) in two cells, and a cell that jumps by 1 (shifted back by (11)).
    /// let s = CompositeSurface::from_expr(vec![0.0, 1.0, 2.0], vec![0.0, 1.0],
    ///     vec![vec![z("sin(x)*cos(y)")], vec![z("sin(x)*cos(y) + 1")]], SurfaceKind::Explicit).unwrap();
    /// assert!(!s.continuity().is_continuous());
    /// let want = 1.5f64.sin() * 0.5f64.cos();
    /// assert!((s.eval(1.5, 0.5)[0] - want).abs() < 1e-15);
    /// assert!((s.eval_formula(1.5, 0.5)[0] - want).abs() < 1e-15);
    /// ```
    pub fn from_expr(
        u_knots: Vec<f64>,
        v_knots: Vec<f64>,
        patches: Vec<Vec<ExprPatch>>,
        kind: SurfaceKind,
    ) -> Result<Self> {
        Self::assemble(
            u_knots,
            v_knots,
            patches,
            kind,
            ExprPatch::dim,
            |u, v, flat| {
                let m = v.cells();
                let mut domains = Vec::with_capacity(flat.len());
                for (k, p) in flat.iter().enumerate() {
                    if p.vars().len() != 2 {
                        return Err(Error::WrongDimension {
                            operation: "the variables of a surface patch",
                            expected: 2,
                            got: p.vars().len(),
                        });
                    }
                    let (i, j) = (k / m, k % m);
                    let d = match p.domain() {
                        Some(d) => [d[0], d[1]],
                        None => [
                            (u.knots()[i], u.knots()[i + 1]),
                            (v.knots()[j], v.knots()[j + 1]),
                        ],
                    };
                    p.check_finite(&d).map_err(|e| match e {
                        Error::Expression {
                            what,
                            message,
                            parse,
                        } => Error::Expression {
                            what: format!("patch ({i}, {j}) {what}"),
                            message,
                            parse,
                        },
                        e => e,
                    })?;
                    domains.push(d);
                }
                Ok(Cells::Expr {
                    patches: flat,
                    domains,
                    effective: Vec::new(),
                    effective_exprs: Box::new((Graph::new(), Vec::new())),
                })
            },
        )
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
        let (uc, vc, patches) = PolyPatch::from_bspline(s)?;
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

    /// The polynomial patch of cell (i, j), in local coordinates (`None` for formula
    /// patches).
    pub fn patch(&self, i: usize, j: usize) -> Option<&PolyPatch> {
        match &self.cells {
            Cells::Poly { patches, .. } => Some(&patches[i * self.v.cells() + j]),
            Cells::Expr { .. } => None,
        }
    }

    /// The formula patch of cell (i, j) (`None` for polynomial patches).
    pub fn expr_patch(&self, i: usize, j: usize) -> Option<&ExprPatch> {
        match &self.cells {
            Cells::Expr { patches, .. } => Some(&patches[i * self.v.cells() + j]),
            Cells::Poly { .. } => None,
        }
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

    /// Patch k (= i * m + j) at local coordinates, `dim` numbers per point into `out`.
    fn eval_local_many(&self, k: usize, ss: &[f64], ts: &[f64], out: &mut [f64]) {
        match &self.cells {
            Cells::Poly { patches, .. } => {
                for ((&s, &t), p) in ss.iter().zip(ts).zip(out.chunks_exact_mut(self.dim)) {
                    patches[k].eval_into(s, t, p);
                }
            }
            Cells::Expr {
                patches, domains, ..
            } => patches[k].eval_local_many(&domains[k], &[ss, ts], out),
        }
    }

    /// The structural evaluator: locate the cell, evaluate one polynomial (O(1) on uniform
    /// knots, O(log n + log m) otherwise) or one compiled formula. Equal to the single
    /// formula (9) within rounding, everywhere. `out` has length dim.
    #[inline]
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let (i, s) = self.u.locate(u);
        let (j, t) = self.v.locate(v);
        let k = i * self.v.cells() + j;
        match &self.cells {
            Cells::Poly { effective, .. } => effective[k].eval_into(s, t, out),
            Cells::Expr { effective, .. } => {
                let mut cols: Vec<&mut [f64]> = out.chunks_mut(1).collect();
                effective[k]
                    .eval_batch(&[&[s], &[t]], &mut cols)
                    .expect("one point, dim outputs");
            }
        }
    }

    /// [`Self::eval_into`] into a new vector.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(u, v, &mut out);
        out
    }

    /// Evaluates at the pairs `uv = [u0, v0, u1, v1, ...]` into `out` (dim numbers per
    /// point), in parallel for large batches (the [`Surface::eval_batch`] of the surface).
    /// Errors: odd `uv`, wrong buffer length, non-finite parameters.
    pub fn eval_many(&self, uv: &[f64], out: &mut [f64]) -> Result<()> {
        self.eval_pairs(uv, out, true)
    }

    /// [`Self::eval_many`], on the thread pool only when `parallel`.
    fn eval_pairs(&self, uv: &[f64], out: &mut [f64], parallel: bool) -> Result<()> {
        let d = self.dim;
        check_pairs(uv, d, out)?;
        if let Cells::Expr { effective, .. } = &self.cells {
            self.eval_expr_points(effective, uv, out, parallel);
            return Ok(());
        }
        crate::geom::for_each_point(parallel, uv, 2, out, d, |q, p| {
            self.eval_into(q[0], q[1], p)
        });
        Ok(())
    }

    /// Formula patches: the points grouped by cell, each cell's tape run once over its
    /// points (cells in parallel when `parallel`).
    fn eval_expr_points(&self, effective: &[Tape], uv: &[f64], out: &mut [f64], parallel: bool) {
        let d = self.dim;
        let m = self.v.cells();
        let mut by_cell: Vec<Vec<(usize, f64, f64)>> = vec![Vec::new(); effective.len()];
        for (idx, q) in uv.chunks_exact(2).enumerate() {
            let (i, s) = self.u.locate(q[0]);
            let (j, t) = self.v.locate(q[1]);
            by_cell[i * m + j].push((idx, s, t));
        }
        let cell = |(pts, tape): (&Vec<(usize, f64, f64)>, &Tape)| {
            let ss: Vec<f64> = pts.iter().map(|p| p.1).collect();
            let ts: Vec<f64> = pts.iter().map(|p| p.2).collect();
            let mut cols = vec![vec![0.0; pts.len()]; d];
            let mut refs: Vec<&mut [f64]> = cols.iter_mut().map(Vec::as_mut_slice).collect();
            tape.eval_batch(&[&ss, &ts], &mut refs)
                .expect("inputs and outputs of equal length");
            cols
        };
        let results: Vec<Vec<Vec<f64>>> = if parallel {
            by_cell
                .par_iter()
                .zip(effective.par_iter())
                .map(cell)
                .collect()
        } else {
            by_cell.iter().zip(effective).map(cell).collect()
        };
        for (pts, cols) in by_cell.iter().zip(&results) {
            for (r, &(idx, _, _)) in pts.iter().enumerate() {
                for k in 0..d {
                    out[idx * d + k] = cols[k][r];
                }
            }
        }
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
        let effective = match &self.cells {
            Cells::Poly { effective, .. } => effective,
            Cells::Expr { effective, .. } => {
                let uv: Vec<f64> = us
                    .iter()
                    .flat_map(|&u| vs.iter().flat_map(move |&v| [u, v]))
                    .collect();
                self.eval_expr_points(effective, &uv, out, true);
                return Ok(());
            }
        };
        let located: Vec<(usize, f64)> = vs.iter().map(|&v| self.v.locate(v)).collect();
        let m = self.v.cells();
        let row = |(u, o): (&f64, &mut [f64])| {
            let (i, s) = self.u.locate(*u);
            let cells = &effective[i * m..(i + 1) * m];
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
                // R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) + R_ij(u_i,v_j), terms present as in (9).
                let terms: [(f64, f64, f64, bool); 4] = [
                    (ss[i], ts[j], 1.0, true),
                    (0.0, ts[j], -1.0, i >= 1),
                    (ss[i], 0.0, -1.0, j >= 1),
                    (0.0, 0.0, 1.0, i >= 1 && j >= 1),
                ];
                for (s, t, sign, present) in terms {
                    if present {
                        self.eval_local_many(i * m + j, &[s], &[t], &mut tmp);
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
    /// patch's own domain), with the four terms of (9),
    /// `R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) + R_ij(u_i,v_j)`. For a polynomial patch they
    /// are collected symbolically: exactly Σ c_ab s^a t^b over a >= [i>=1], b >= [j>=1], the
    /// monomials shared by the coordinates. A formula patch is substituted: its variables
    /// replaced by a + (b - a) s_i and c + (d - c) t_j on its domain [a, b] × [c, d]; a
    /// formula patch that may be undefined for some finite argument (sqrt, ln, asin, acos,
    /// tan, a division) gets those arguments clamped in a form written with `sign` that
    /// stays in its domain also in f64 (equal in value; see [`Piecewise::formula`]). Knots
    /// and domains print as exact rationals (decimal inputs become their fractions).
    ///
    /// Errors: [`Error::Overflow`] naming the patch when a coefficient is not a finite f64
    /// or the terms could overflow f64 on the grid widened by its span (coordinates near the
    /// end of the f64 range); [`Error::Underflow`] naming the patch when a nonzero
    /// coefficient falls below the smallest normal f64 (values near 1e-300 over knots near
    /// 1e300).
    ///
    /// [`Piecewise::formula`]: super::Piecewise::formula
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
        let mut hints = Hints::default();
        let ss = ramps(&mut g, u, uk, &mut hints)?;
        let ts = ramps(&mut g, v, vk, &mut hints)?;
        let (n, m) = self.cells();
        let zero = g.int(0);
        let bounds = [
            (vars[0], variable_bound(uk[0], uk[n])),
            (vars[1], variable_bound(vk[0], vk[m])),
        ];
        let mut sums: Vec<Vec<Id>> = vec![Vec::with_capacity(n * m); self.dim];
        let mut cells: Vec<Vec<Id>> = Vec::with_capacity(n * m);
        for i in 0..n {
            for j in 0..m {
                let start = sums[0].len();
                let (a0, b0) = (usize::from(i >= 1), usize::from(j >= 1));
                match &self.cells {
                    Cells::Poly { patches, .. } => {
                        let p = &patches[i * m + j];
                        check_linear_terms(p, (a0, b0), (uk[i + 1] - uk[i], vk[j + 1] - vk[j]))
                            .map_err(|value| Error::Underflow {
                                what: format!("formula (9), the terms of patch ({i}, {j})"),
                                value,
                            })?;
                        for (k, sum) in sums.iter_mut().enumerate() {
                            sum.push(monomials(&mut g, p, k, (a0, b0), ss[i], ts[j]));
                        }
                    }
                    Cells::Expr {
                        patches, domains, ..
                    } => {
                        let (p, d) = (&patches[i * m + j], &domains[i * m + j]);
                        let s = Local::Cell {
                            x: u,
                            cell: (uk[i], uk[i + 1]),
                            ramp: ss[i],
                        };
                        let t = Local::Cell {
                            x: v,
                            cell: (vk[j], vk[j + 1]),
                            ramp: ts[j],
                        };
                        let zero = Local::Const(zero);
                        let terms = [
                            (s, t, 1, true),
                            (zero, t, -1, a0 == 1),
                            (s, zero, -1, b0 == 1),
                            (zero, zero, 1, a0 == 1 && b0 == 1),
                        ];
                        for (s, t, sign, present) in terms {
                            if present {
                                let r = p.place_clamped(&mut g, &[s, t], d, &mut hints);
                                for (k, sum) in sums.iter_mut().enumerate() {
                                    let term = g.scale(&int_const(sign), r[k]);
                                    sum.push(term);
                                }
                            }
                        }
                    }
                }
                cells.push(sums.iter().flat_map(|t| t[start..].to_vec()).collect());
            }
        }
        let roots: Vec<Id> = sums.iter().map(|terms| g.sum(terms)).collect();
        check_terms(&g, &roots, &bounds, &hints).map_err(|e| {
            e.in_groups(
                &g,
                &cells,
                |k| format!("formula (9), the terms of patch ({}, {})", k / m, k % m),
                "formula (9), the sum of the patches' terms",
            )
        })?;
        Ok(Formula {
            graph: g,
            roots,
            names,
            vars: vars.iter().map(|s| s.to_string()).collect(),
        })
    }

    /// Formula patches: per cell (p, q) the tape of the patch plus the jumps that formula
    /// (9) adds, E_pq(s, t) = r_pq(s, t) + Σ_(i<=p) U_iq(t) + Σ_(j<=q) V_pj(s) + c_pq with the
    /// u-jumps U_iq(t) = r_(i-1)q(1, t) - r_iq(0, t) and v-jumps V_pj(s) = r_p(j-1)(s, 1) -
    /// r_pj(s, 0) of the edges the report finds discontinuous, and the constant
    /// c_pq = Σ_(1<=i<=p, 1<=j<=q) (U_i(j-1)(1) - U_ij(0)).
    #[allow(clippy::type_complexity)]
    fn effective_tapes(&self) -> Result<(Vec<Tape>, (Graph, Vec<Vec<Id>>))> {
        let Cells::Expr {
            patches, domains, ..
        } = &self.cells
        else {
            return Ok((Vec::new(), (Graph::new(), Vec::new())));
        };
        let (n, m) = self.cells();
        let d = self.dim;
        let mut g = Graph::new();
        let (s, t) = (g.var("@s"), g.var("@t"));
        let (zero, one) = (g.int(0), g.int(1));
        let jumps: std::collections::HashSet<(GridLine, usize)> = self
            .report
            .jumps
            .iter()
            .filter(|j| j.max_jump > self.report.tolerance || j.max_jump.is_nan())
            .map(|j| (j.line, j.cell))
            .collect();
        // The local coordinates @s, @t in [0, 1] (or the constants 0 and 1), with the
        // arguments of partial patches clamped as in the single formula, so that the
        // evaluator never sees a + (b - a) 1 an ulp beyond b.
        let place = |g: &mut Graph, k: usize, x: Id, y: Id| {
            let local = |g: &Graph, id: Id| match g.as_const(id) {
                Some(_) => Local::Const(id),
                None => Local::Cell {
                    x: id,
                    cell: (0.0, 1.0),
                    ramp: id,
                },
            };
            let locals = [local(g, x), local(g, y)];
            patches[k].place_clamped(g, &locals, &domains[k], &mut Hints::default())
        };
        let corner = |k: usize, x: f64, y: f64| {
            let mut o = vec![0.0; d];
            self.eval_local_many(k, &[x], &[y], &mut o);
            o
        };
        // Numeric corner terms: prefix sums over i <= p, j <= q.
        let mut c = vec![vec![0.0; d]; (n + 1) * (m + 1)];
        for p in 1..n {
            for q in 1..m {
                let (a, b) = (
                    corner((p - 1) * m + q - 1, 1.0, 1.0),
                    corner(p * m + q - 1, 0.0, 1.0),
                );
                let (e, f) = (
                    corner((p - 1) * m + q, 1.0, 0.0),
                    corner(p * m + q, 0.0, 0.0),
                );
                for k in 0..d {
                    let x = (a[k] - b[k]) - (e[k] - f[k]);
                    let sum = x + c[p * (m + 1) + q + 1][k] + c[(p + 1) * (m + 1) + q][k]
                        - c[p * (m + 1) + q][k];
                    if !sum.is_finite() {
                        return Err(Error::Overflow {
                            what: format!("formula (9) at patch ({p}, {q})"),
                            step: "the sum of the corner jumps before it overflows f64: \
                                   coordinates near the end of its range"
                                .into(),
                        });
                    }
                    c[(p + 1) * (m + 1) + q + 1][k] = sum;
                }
            }
        }
        let mut tapes = Vec::with_capacity(n * m);
        let mut cell_roots = Vec::with_capacity(n * m);
        // Running sums of u-jumps along each row q (over i <= p) and v-jumps along columns.
        let mut u_sums: Vec<Vec<Id>> = vec![vec![zero; d]; m];
        for p in 0..n {
            let mut v_sum: Vec<Id> = vec![zero; d];
            for q in 0..m {
                if p >= 1 && jumps.contains(&(GridLine::U(p), q)) {
                    let a = place(&mut g, (p - 1) * m + q, one, t);
                    let b = place(&mut g, p * m + q, zero, t);
                    for k in 0..d {
                        let jump = g.sub(a[k], b[k]);
                        u_sums[q][k] = g.add(u_sums[q][k], jump);
                    }
                }
                if q >= 1 && jumps.contains(&(GridLine::V(q), p)) {
                    let a = place(&mut g, p * m + q - 1, s, one);
                    let b = place(&mut g, p * m + q, s, zero);
                    for k in 0..d {
                        let jump = g.sub(a[k], b[k]);
                        v_sum[k] = g.add(v_sum[k], jump);
                    }
                }
                let own = place(&mut g, p * m + q, s, t);
                let roots: Vec<Id> = (0..d)
                    .map(|k| {
                        let ck = g.num(c[(p + 1) * (m + 1) + q + 1][k]);
                        g.sum(&[own[k], u_sums[q][k], v_sum[k], ck])
                    })
                    .collect();
                tapes.push(
                    Tape::new(&g, &roots, &["@s", "@t"])
                        .map_err(|e| Error::expression(format!("patch ({p}, {q})"), e))?,
                );
                cell_roots.push(roots);
            }
        }
        Ok((tapes, (g, cell_roots)))
    }

    /// The continuity report. Errors: [`Error::Overflow`] naming the two patches when
    /// their jump overflows f64 (coordinates of opposite signs near the end of its range).
    fn measure_continuity(&self) -> Result<ContinuityReport> {
        let (n, m) = self.cells();
        let (uk, vk) = self.knots();
        let d = self.dim;
        let mut jumps = Vec::new();
        let mut scale = 0.0f64;
        let xs: Vec<f64> = (0..EDGE_SAMPLES)
            .map(|k| k as f64 / (EDGE_SAMPLES - 1) as f64)
            .collect();
        let (zeros, ones) = (vec![0.0; EDGE_SAMPLES], vec![1.0; EDGE_SAMPLES]);
        let (mut a, mut b) = (vec![0.0; EDGE_SAMPLES * d], vec![0.0; EDGE_SAMPLES * d]);
        let mut edge = |p: usize, q: usize, across_u: bool, lo: f64, hi: f64| {
            if across_u {
                self.eval_local_many(p, &ones, &xs, &mut a);
                self.eval_local_many(q, &zeros, &xs, &mut b);
            } else {
                self.eval_local_many(p, &xs, &ones, &mut a);
                self.eval_local_many(q, &xs, &zeros, &mut b);
            }
            let (mut worst, mut at) = (0.0f64, lo);
            for (k, (pa, pb)) in a.chunks_exact(d).zip(b.chunks_exact(d)).enumerate() {
                let dist = crate::numeric::distance(pa, pb);
                scale = pa.iter().chain(pb).fold(scale, |m, c| m.max(c.abs()));
                if dist > worst || dist.is_nan() {
                    worst = dist;
                    at = lo + xs[k] * (hi - lo);
                }
            }
            (worst, at)
        };
        for i in 1..n {
            for j in 0..m {
                let (max_jump, at) = edge((i - 1) * m + j, i * m + j, true, vk[j], vk[j + 1]);
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
                let (max_jump, at) = edge(i * m + j - 1, i * m + j, false, uk[i], uk[i + 1]);
                jumps.push(Jump {
                    line: GridLine::V(j),
                    cell: i,
                    max_jump,
                    at,
                });
            }
        }
        if let Some(j) = jumps.iter().find(|j| !j.max_jump.is_finite()) {
            let (a, b, line) = match j.line {
                GridLine::U(i) => ((i - 1, j.cell), (i, j.cell), format!("u = {}", show(uk[i]))),
                GridLine::V(k) => ((j.cell, k - 1), (j.cell, k), format!("v = {}", show(vk[k]))),
            };
            return Err(Error::Overflow {
                what: format!("patches {a:?} and {b:?}"),
                step: format!(
                    "the jump between them on {line} overflows f64: coordinates of opposite \
                     signs near the end of its range"
                ),
            });
        }
        let max_jump = jumps.iter().fold(0.0f64, |m, j| m.max(j.max_jump));
        // Polynomial cells are evaluated from power-basis coefficients: each side of an edge
        // is rounded by up to (p + q + 2)·ε·Σ|c_ab| (Horner), which is far above the values'
        // rounding where the coefficients cancel (the cells of a B-spline surface differ by
        // that much along edges where they are equal). 64·ε·scale covers both sides.
        if let Cells::Poly { patches, .. } = &self.cells {
            scale = patches.iter().fold(scale, |m, p| {
                let (a, b) = p.degrees();
                m.max(p.abs_sum() * (a + b + 2) as f64 / 32.0)
            });
        }
        Ok(ContinuityReport {
            jumps,
            max_jump,
            tolerance: 64.0 * f64::EPSILON * scale.max(f64::MIN_POSITIVE),
        })
    }
}

/// The polynomials formula (9) equals on each cell: with D_ij the patch minus its row a = 0
/// (for i >= 1) and column b = 0 (for j >= 1), i.e. R_ij(u,v) - R_ij(u_i,v) - R_ij(u,v_j) +
/// R_ij(u_i,v_j), cell (p, q) carries D_pq(s,t) + Σ_(i<p) D_iq(1,t) + Σ_(j<q) D_pj(s,1) +
/// Σ_(i<p, j<q) D_ij(1,1): the cells before it contribute their far edges (clamped P = 1).
///
/// Errors: [`Error::Overflow`] naming the patch when the sums overflow f64 (patches with
/// coordinates near the end of the f64 range).
fn effective_patches(patches: &[PolyPatch], n: usize, m: usize) -> Result<Vec<PolyPatch>> {
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
            let overflow = || Error::Overflow {
                what: format!("formula (9) at patch ({p}, {q})"),
                step: "the patch plus the edges and corners of the patches before it \
                       overflows f64: coordinates near the end of its range"
                    .into(),
            };
            let c = PolyPatch::new((0, 0), d, corner[p * (m + 1) + q].clone())
                .map_err(|_| overflow())?;
            e.add_scaled(&c, 1.0);
            if e.is_finite() {
                Ok(e)
            } else {
                Err(overflow())
            }
        })
        .collect()
}

/// The ramps P(x, x_i, x_(i+1) - x_i) of every cell of one direction, with their
/// magnitudes for [`check_terms`] in `hints`: P in [0, 1], and x - x_i, |x - x_i| as
/// [`knot_hints`] gives them.
pub(crate) fn ramps(g: &mut Graph, x: Id, knots: &[f64], hints: &mut Hints) -> Result<Vec<Id>> {
    knot_hints(g, x, knots, hints);
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
            let p = g.div(sum, den);
            hints.cap(p, 1.0);
            Ok(p)
        })
        .collect()
}

/// The monomials of degree 1 of a patch's terms in formula (9), c s or c t, are the only
/// ones the engine multiplies out: c times the ramp 1/2 + |x - x_i|/(2w) - ... gives the
/// coefficients c/2 and c/(2w), which must not underflow f64 (they would silently become
/// 0 or lose their digits). Errors: the first such coefficient, approximately.
fn check_linear_terms(
    p: &PolyPatch,
    (a0, b0): (usize, usize),
    (wu, wv): (f64, f64),
) -> std::result::Result<(), String> {
    let (deg_a, deg_b) = p.degrees();
    for (a, b, w) in [(1, 0, wu), (0, 1, wv)] {
        if a < a0 || b < b0 || a > deg_a || b > deg_b {
            continue;
        }
        for &c in p.coefficient(a, b) {
            for d in [1.0, w] {
                if c != 0.0 && (c / (2.0 * d)).abs() < f64::MIN_POSITIVE {
                    // c/(2d), written without computing it (it underflows).
                    let e = c.abs().log10() - (2.0 * d).log10();
                    let m = 10f64.powf(e - e.floor()).copysign(c);
                    return Err(format!("{m:.3}e{}", e.floor()));
                }
            }
        }
    }
    Ok(())
}

/// Σ_(a >= a0, b >= b0) c_ab s^a t^b for coordinate k: one sum over monomials, which the
/// coordinates of a patch share (fewer operations than Horner form, since the engine would
/// distribute every constant times a ramp over the ramp's two |.| terms).
fn monomials(g: &mut Graph, p: &PolyPatch, k: usize, (a0, b0): (usize, usize), s: Id, t: Id) -> Id {
    let (deg_a, deg_b) = p.degrees();
    let mut terms = Vec::with_capacity((deg_a + 1) * (deg_b + 1));
    for a in a0..=deg_a {
        for b in b0..=deg_b {
            let c = p.coefficient(a, b)[k];
            if c != 0.0 {
                let mono = g.prod(&[(s, a as i32), (t, b as i32)]);
                terms.push((coef_const(c), mono));
            }
        }
    }
    g.lin(&terms)
}

/// Formula (9) (explicit surfaces: (11)) of spec/composite-surfaces.md by its structural
/// evaluator, over the knots' rectangle.
impl Surface for CompositeSurface {
    crate::geom::forward_to_inherent!(CompositeSurface; dim, surface_domain, surface_eval_into, eval_grid);

    /// [`CompositeSurface::eval_many`]: the values of [`Surface::eval_into`], bit for bit.
    fn eval_batch(&self, uv: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        self.eval_pairs(uv, out, options.parallel())
    }

    /// Every order: what formula (9) equals on the cell of (u, v) (patch plus the shifts),
    /// differentiated in its local coordinates s = (u - u_i)/Δu_i, t = (v - v_j)/Δv_j and
    /// scaled by 1/Δu_i^ku · 1/Δv_j^kv (at a knot, the cell on the right; inside the
    /// domain). Polynomial patches in closed form, formula patches by the engine's symbolic
    /// derivative. Errors: [`Error::Expression`] if a symbolic derivative does not
    /// compile.
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim, out)?;
        if (ku, kv) == (0, 0) {
            self.eval_into(u, v, out);
            return Ok(());
        }
        let (i, s) = self.u.locate(u);
        let (j, t) = self.v.locate(v);
        let k = i * self.v.cells() + j;
        match &self.cells {
            Cells::Poly { effective, .. } => effective[k].partial_into(s, t, (ku, kv), out),
            Cells::Expr {
                effective_exprs, ..
            } => {
                let (graph, roots) = effective_exprs.as_ref();
                let mut g = graph.clone();
                let mut r = roots[k].clone();
                for (var, order) in [("@s", ku), ("@t", kv)] {
                    for _ in 0..order {
                        r = r.iter().map(|&e| g.diff(e, var)).collect();
                    }
                }
                let what = || format!("derivative of patch ({i}, {j})");
                let tape =
                    Tape::new(&g, &r, &["@s", "@t"]).map_err(|e| Error::expression(what(), e))?;
                let mut cols: Vec<&mut [f64]> = out.chunks_mut(1).collect();
                tape.eval_batch(&[&[s], &[t]], &mut cols)
                    .map_err(|e| Error::expression(what(), e))?;
            }
        }
        let (uk, vk) = self.knots();
        let scale = (uk[i + 1] - uk[i]).powi(-(ku as i32)) * (vk[j + 1] - vk[j]).powi(-(kv as i32));
        out.iter_mut().for_each(|x| *x *= scale);
        Ok(())
    }

    /// The knots in u and v.
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        let (ku, kv) = self.knots();
        (ku.to_vec(), kv.to_vec())
    }
}
