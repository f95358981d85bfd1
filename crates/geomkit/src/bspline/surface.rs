//! Bicubic B-spline surfaces and their interpolation through an M×N grid of reference
//! points (spec/bspline-interpolation.md §3, formula (4)), solved separably: every row, then
//! every column, each a banded 1-D system factored once and applied to all rows in parallel.
//!
//! ```
//! use geomkit::bspline::{interpolate_surface, SurfaceInterpolationOptions};
//! // Heights z = x·y on a 5×4 grid, as points (x, y, z).
//! let grid: Vec<Vec<Vec<f64>>> = (0..5)
//!     .map(|i| (0..4).map(|j| vec![i as f64, j as f64, (i * j) as f64]).collect())
//!     .collect();
//! let fit = interpolate_surface(&grid, &SurfaceInterpolationOptions::default()).unwrap();
//! let p = fit.surface.eval(fit.params_u[2], fit.params_v[3]);
//! assert!((p[2] - 6.0).abs() < 1e-13);
//! ```

use super::curve::{
    basis_funs, basis_funs_derivs, detect_uniform_step, find_span, uniform_cubic_basis,
    uniform_span,
};
use super::interpolate::{knots_around, EndCondition, Parametrization, Solver1d};
use crate::geom::{check_point, BatchOptions, Surface};
use crate::par::*;
use crate::points::{check_eval_args, check_knots, flatten_grid, unit_normal, validate_points};
use crate::progress::Progress;
use crate::{Error, Result};

mod batch;
mod curvature;
pub(crate) use curvature::curvature_of;
pub use curvature::SurfaceCurvature;

/// A tensor-product B-spline surface S(u, v) = Σ_i Σ_j N_i(u) N_j(v) c_ij of degrees (p, q),
/// control net c_ij at (i * n_v + j) * dim.
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineSurface {
    degree: (usize, usize),
    dim: usize,
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    n_u: usize,
    n_v: usize,
    control: Vec<f64>,
    /// The reciprocal of the knot spacing per direction when uniform (spans by one
    /// multiplication, basis by formula (1) for cubics).
    inv_steps: (Option<f64>, Option<f64>),
}

impl BsplineSurface {
    /// The knots in u and v and the net, moved out.
    pub(crate) fn into_parts(self) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        (self.knots_u, self.knots_v, self.control)
    }

    /// A surface from its degrees (each 1..=7), knots in u and v, and a row-major net of
    /// `n_u × n_v` control points with `dim` coordinates.
    pub fn from_flat(
        degree: (usize, usize),
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        n_u: usize,
        n_v: usize,
        dim: usize,
        control: Vec<f64>,
    ) -> Result<Self> {
        for p in [degree.0, degree.1] {
            if p == 0 || p > 7 {
                return Err(Error::InvalidOption {
                    option: "degree",
                    reason: "B-spline degree must be between 1 and 7",
                });
            }
        }
        validate_points("control net", dim, &control)?;
        if control.len() != n_u * n_v * dim {
            return Err(Error::BufferSize {
                expected: n_u * n_v * dim,
                got: control.len(),
            });
        }
        if n_u <= degree.0 || n_v <= degree.1 {
            return Err(Error::TooFewPoints {
                what: "control net rows or columns",
                got: n_u.min(n_v),
                min: degree.0.max(degree.1) + 1,
            });
        }
        check_knots(&knots_u, degree.0, n_u)?;
        check_knots(&knots_v, degree.1, n_v)?;
        Ok(Self::from_trusted(
            degree, knots_u, knots_v, n_u, n_v, dim, control,
        ))
    }

    /// [`BsplineSurface::from_flat`] for parts the library computed itself (a net from a
    /// solve that checked it is finite, knots it built): no pass over the net.
    pub(crate) fn from_trusted(
        degree: (usize, usize),
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        n_u: usize,
        n_v: usize,
        dim: usize,
        control: Vec<f64>,
    ) -> Self {
        debug_assert_eq!(control.len(), n_u * n_v * dim);
        debug_assert!(check_knots(&knots_u, degree.0, n_u).is_ok());
        debug_assert!(check_knots(&knots_v, degree.1, n_v).is_ok());
        let inv = |h: Option<f64>| h.map(|h| 1.0 / h);
        let inv_steps = (
            inv(detect_uniform_step(&knots_u)),
            inv(detect_uniform_step(&knots_v)),
        );
        BsplineSurface {
            degree,
            dim,
            knots_u,
            knots_v,
            n_u,
            n_v,
            control,
            inv_steps,
        }
    }

    /// Degrees (p, q).
    pub fn degrees(&self) -> (usize, usize) {
        self.degree
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Knots in u and in v.
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (&self.knots_u, &self.knots_v)
    }

    /// Net size (n_u, n_v).
    pub fn net_size(&self) -> (usize, usize) {
        (self.n_u, self.n_v)
    }

    /// The control net, row-major.
    pub fn control_flat(&self) -> &[f64] {
        &self.control
    }

    /// Parameter domains ((u0, u1), (v0, v1)).
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (
            (self.knots_u[self.degree.0], self.knots_u[self.n_u]),
            (self.knots_v[self.degree.1], self.knots_v[self.n_v]),
        )
    }

    #[inline(always)]
    fn basis_u(&self, u: f64) -> (usize, [f64; 8]) {
        axis_basis(&self.knots_u, self.degree.0, self.n_u, self.inv_steps.0, u)
    }

    #[inline(always)]
    fn basis_v(&self, v: f64) -> (usize, [f64; 8]) {
        axis_basis(&self.knots_v, self.degree.1, self.n_v, self.inv_steps.1, v)
    }

    /// Writes S(u, v) into `out` (length dim).
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let su = axis_span(&self.knots_u, self.degree.0, self.n_u, self.inv_steps.0, u);
        let sv = axis_span(&self.knots_v, self.degree.1, self.n_v, self.inv_steps.1, v);
        self.eval_spans_into(su, sv, u, v, out);
    }

    /// [`BsplineSurface::eval_into`] on the spans su, sv that hold u and v.
    fn eval_spans_into(&self, su: usize, sv: usize, u: f64, v: f64, out: &mut [f64]) {
        let (p, q) = self.degree;
        let bu = axis_basis_on(&self.knots_u, p, self.inv_steps.0, su, u);
        let bv = axis_basis_on(&self.knots_v, q, self.inv_steps.1, sv, v);
        out.iter_mut().for_each(|o| *o = 0.0);
        let d = self.dim;
        for a in 0..=p {
            let row = (su - p + a) * self.n_v;
            for b in 0..=q {
                let w = bu[a] * bv[b];
                let c = &self.control[(row + sv - q + b) * d..(row + sv - q + b + 1) * d];
                for (o, x) in out.iter_mut().zip(c) {
                    *o += w * x;
                }
            }
        }
        if out.iter().any(|o| !o.is_finite()) {
            let terms = (0..=p).flat_map(|a| {
                (0..=q).map(move |b| {
                    let k = ((su - p + a) * self.n_v + sv - q + b) * d;
                    (bu[a] * bv[b], &self.control[k..k + d])
                })
            });
            super::curve::resum_overflowed(terms, out);
        }
    }

    /// S(u, v).
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(u, v, &mut out);
        out
    }

    /// ∂^(ku+kv) S / ∂u^ku ∂v^kv at (u, v), into `out`.
    pub fn eval_derivative(&self, u: f64, v: f64, ku: usize, kv: usize, out: &mut [f64]) {
        let (p, q) = self.degree;
        out.iter_mut().for_each(|o| *o = 0.0);
        if ku > p || kv > q {
            return;
        }
        let su = find_span(&self.knots_u, p, self.n_u, u);
        let sv = find_span(&self.knots_v, q, self.n_v, v);
        let du = basis_funs_derivs(&self.knots_u, su, u, p, ku);
        let dv = basis_funs_derivs(&self.knots_v, sv, v, q, kv);
        let d = self.dim;
        for a in 0..=p {
            for b in 0..=q {
                let w = du[ku][a] * dv[kv][b];
                let k = ((su - p + a) * self.n_v + sv - q + b) * d;
                for (o, x) in out.iter_mut().zip(&self.control[k..k + d]) {
                    *o += w * x;
                }
            }
        }
    }

    /// Evaluates on the grid `us` × `vs` (point (a, b) at `(a * vs.len() + b) * dim`), in
    /// parallel over rows. Each row contracts the net in u once; each point then costs
    /// (q+1)·dim multiply-adds. Errors: wrong buffer length, non-finite parameters.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_eval_args("parameter u", us, us.len() * vs.len(), d, out)?;
        check_eval_args("parameter v", vs, us.len() * vs.len(), d, out)?;
        if vs.is_empty() {
            return Ok(());
        }
        let (p, q) = self.degree;
        let vb: Vec<(usize, [f64; 8])> = vs.iter().map(|&v| self.basis_v(v)).collect();
        if (p, q, d) == (3, 3, 1) {
            self.eval_grid_bicubic_scalar(us, &vb, out);
            return Ok(());
        }
        let row_len = self.n_v * d;
        out.par_chunks_mut(vs.len() * d)
            .zip(us.par_iter())
            .for_each_init(
                || vec![0.0; row_len],
                |row, (chunk, &u)| {
                    let (su, bu) = self.basis_u(u);
                    row.iter_mut().for_each(|x| *x = 0.0);
                    for a in 0..=p {
                        let src = &self.control[(su - p + a) * row_len..(su - p + a + 1) * row_len];
                        for (r, s) in row.iter_mut().zip(src) {
                            *r += bu[a] * s;
                        }
                    }
                    for ((sv, bv), o) in vb.iter().zip(chunk.chunks_exact_mut(d)) {
                        o.iter_mut().for_each(|x| *x = 0.0);
                        for b in 0..=q {
                            let c = &row[(sv - q + b) * d..(sv - q + b + 1) * d];
                            for (x, y) in o.iter_mut().zip(c) {
                                *x += bv[b] * y;
                            }
                        }
                    }
                },
            );
        Ok(())
    }

    /// [`BsplineSurface::eval_grid`] for bicubic height surfaces: per output row, four net
    /// rows combined into one (vectorized), then four terms per point.
    fn eval_grid_bicubic_scalar(&self, us: &[f64], vb: &[(usize, [f64; 8])], out: &mut [f64]) {
        let n_v = self.n_v;
        out.par_chunks_mut(vb.len())
            .zip(us.par_iter())
            .for_each_init(
                || vec![0.0; n_v],
                |row, (chunk, &u)| {
                    let (su, bu) = self.basis_u(u);
                    let net = &self.control[(su - 3) * n_v..(su + 1) * n_v];
                    let (r0, rest) = net.split_at(n_v);
                    let (r1, rest) = rest.split_at(n_v);
                    let (r2, r3) = rest.split_at(n_v);
                    for ((((x, a), b), c), e) in row.iter_mut().zip(r0).zip(r1).zip(r2).zip(r3) {
                        *x = bu[0] * a + bu[1] * b + bu[2] * c + bu[3] * e;
                    }
                    for ((sv, bv), o) in vb.iter().zip(chunk.iter_mut()) {
                        let r = &row[sv - 3..sv + 1];
                        *o = bv[0] * r[0] + bv[1] * r[1] + bv[2] * r[2] + bv[3] * r[3];
                    }
                },
            );
    }

    /// The unit normal of a surface in R^3 (Su × Sv normalized); `Ok(None)` where it is
    /// degenerate.
    pub fn normal(&self, u: f64, v: f64) -> Result<Option<[f64; 3]>> {
        if self.dim != 3 {
            return Err(Error::WrongDimension {
                operation: "surface normal",
                expected: 3,
                got: self.dim,
            });
        }
        let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
        self.eval_derivative(u, v, 1, 0, &mut a);
        self.eval_derivative(u, v, 0, 1, &mut b);
        Ok(unit_normal(&a, &b))
    }
}

/// Options of [`interpolate_surface`].
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct SurfaceInterpolationOptions {
    /// End condition across the rows (along u, the first grid index).
    pub end_u: EndCondition,
    /// End condition along the rows (along v, the second grid index).
    pub end_v: EndCondition,
    /// Parametrization in both directions (chord-based ones averaged over the grid lines and
    /// scaled to the uniform domain [0, M-1] × [0, N-1]).
    pub parametrization: Parametrization,
}

impl SurfaceInterpolationOptions {
    /// Sets the same end condition in both directions.
    pub fn with_end(mut self, end: EndCondition) -> Self {
        self.end_u = end.clone();
        self.end_v = end;
        self
    }

    /// Sets the end conditions of each direction.
    pub fn with_ends(mut self, end_u: EndCondition, end_v: EndCondition) -> Self {
        self.end_u = end_u;
        self.end_v = end_v;
        self
    }

    /// Sets the parametrization.
    pub fn with_parametrization(mut self, p: Parametrization) -> Self {
        self.parametrization = p;
        self
    }
}

/// An interpolating surface and the grid parameters of the reference points.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceInterpolation {
    /// The bicubic B-spline surface.
    pub surface: BsplineSurface,
    /// Parameter of grid row i.
    pub params_u: Vec<f64>,
    /// Parameter of grid column j.
    pub params_v: Vec<f64>,
}

/// Interpolates a grid of reference points `grid[i][j]` (M rows of N points of one
/// dimension). Errors: empty or ragged grid, non-finite numbers, too few rows or columns for
/// an end condition, given tangents (a surface needs a tangent per boundary point: use
/// estimated ones), coinciding grid lines with chord parameters.
pub fn interpolate_surface(
    grid: &[Vec<Vec<f64>>],
    options: &SurfaceInterpolationOptions,
) -> Result<SurfaceInterpolation> {
    let (rows, cols, dim, flat) = flatten_grid("reference grid", grid)?;
    interpolate_surface_flat(rows, cols, dim, &flat, options)
}

/// Averaged parameters along the first index of a rows × cols × dim grid (closing value
/// included when `closed`), scaled to [0, count-1].
fn grid_parameters(
    grid: &[f64],
    rows: usize,
    cols: usize,
    dim: usize,
    kind: Parametrization,
    closed: bool,
) -> Result<Vec<f64>> {
    let count = if closed { rows + 1 } else { rows };
    if kind == Parametrization::Uniform {
        return Ok((0..count).map(|i| i as f64).collect());
    }
    let mut acc = vec![0.0; count];
    let mut lines = 0usize;
    let mut steps = vec![0.0; count];
    for j in 0..cols {
        let mut total = 0.0;
        for i in 1..count {
            let a = &grid[((i - 1) * cols + j) * dim..((i - 1) * cols + j + 1) * dim];
            let b = &grid[((i % rows) * cols + j) * dim..((i % rows) * cols + j + 1) * dim];
            let d = crate::numeric::distance(a, b);
            steps[i] = if kind == Parametrization::Centripetal {
                d.sqrt()
            } else {
                d
            };
            total += steps[i];
        }
        if total > 0.0 {
            lines += 1;
            let mut s = 0.0;
            for i in 1..count {
                s += steps[i] / total;
                acc[i] += s;
            }
        }
    }
    if lines == 0 {
        return Err(Error::RepeatedPoint { index: 0 });
    }
    let scale = (count - 1) as f64 / lines as f64;
    let t: Vec<f64> = acc.iter().map(|a| a * scale).collect();
    if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(Error::RepeatedPoint { index: i });
    }
    Ok(t)
}

/// The transpose of a row-major `rows × cols` array of points of `dim` numbers. In tiles
/// of 64 × 64 points (a tile's reads and writes stay in cache; a point-by-point transpose of
/// a 4096² grid misses the cache and the TLB on every read), bands of 64 output rows in
/// parallel.
pub(super) fn transpose(data: &[f64], rows: usize, cols: usize, dim: usize) -> Vec<f64> {
    const TILE: usize = 64;
    let mut out = vec![0.0; data.len()];
    if rows == 0 || cols == 0 || dim == 0 {
        return out;
    }
    // Output row j holds column j of `data`.
    out.par_chunks_mut(TILE * rows * dim)
        .enumerate()
        .for_each(|(band, dst)| {
            let j0 = band * TILE;
            let width = dst.len() / (rows * dim);
            for i0 in (0..rows).step_by(TILE) {
                for j in 0..width {
                    let row = &mut dst[j * rows * dim..(j + 1) * rows * dim];
                    for i in i0..(i0 + TILE).min(rows) {
                        let at = (i * cols + j0 + j) * dim;
                        row[i * dim..(i + 1) * dim].copy_from_slice(&data[at..at + dim]);
                    }
                }
            }
        });
    out
}

/// Solves every row of a rows × cols × dim array with one factored system (in parallel).
fn solve_rows(
    system: &Solver1d,
    data: &[f64],
    rows: usize,
    cols: usize,
    dim: usize,
) -> Result<Vec<f64>> {
    let nc = system.n_control();
    let mut out = vec![0.0; rows * nc * dim];
    out.par_chunks_mut(nc * dim)
        .zip(data.par_chunks(cols * dim))
        .try_for_each(|(o, row)| system.solve(row, dim, o))?;
    Ok(out)
}

fn closed_rows(grid: &[f64], rows: usize, cols: usize, dim: usize, end: &EndCondition) -> usize {
    let line = cols * dim;
    if *end == EndCondition::Periodic
        && rows >= 2
        && grid[..line] == grid[(rows - 1) * line..rows * line]
    {
        rows - 1
    } else {
        rows
    }
}

/// Parameters of both directions of an open (non-periodic) grid, as the global solve uses.
pub(crate) fn grid_parameters_both(
    grid: &[f64],
    rows: usize,
    cols: usize,
    dim: usize,
    options: &SurfaceInterpolationOptions,
) -> Result<(Vec<f64>, Vec<f64>)> {
    for count in [rows, cols] {
        if count < 2 {
            return Err(Error::TooFewPoints {
                what: "grid rows or columns",
                got: count,
                min: 2,
            });
        }
    }
    let p = options.parametrization;
    let tu = grid_parameters(grid, rows, cols, dim, p, false)?;
    let tv = grid_parameters(&transpose(grid, rows, cols, dim), cols, rows, dim, p, false)?;
    Ok((tu, tv))
}

/// [`interpolate_surface`] on a row-major rows × cols × dim grid.
pub fn interpolate_surface_flat(
    rows: usize,
    cols: usize,
    dim: usize,
    grid: &[f64],
    options: &SurfaceInterpolationOptions,
) -> Result<SurfaceInterpolation> {
    interpolate_surface_flat_with_progress(rows, cols, dim, grid, options, &Progress::none())
}

/// [`interpolate_surface_flat`] reporting to `progress` ([`crate::progress`]): the units are
/// the grid rows solved along v (reported per block of rows), then as many for the solve
/// along u. The same surface, bit for bit, as without it; [`Error::Cancelled`] when the
/// callback asks to stop.
pub fn interpolate_surface_flat_with_progress(
    rows: usize,
    cols: usize,
    dim: usize,
    grid: &[f64],
    options: &SurfaceInterpolationOptions,
    progress: &Progress,
) -> Result<SurfaceInterpolation> {
    validate_points("reference grid", dim, grid)?;
    if grid.len() != rows * cols * dim {
        return Err(Error::BufferSize {
            expected: rows * cols * dim,
            got: grid.len(),
        });
    }
    for end in [&options.end_u, &options.end_v] {
        if let EndCondition::Clamped { start, end } = end {
            if start.is_some() || end.is_some() {
                return Err(Error::InvalidOption {
                    option: "surface end condition",
                    reason: "a surface needs a tangent per boundary point; use clamped (zero \
                             slope) or bessel (estimated tangents)",
                });
            }
        }
    }
    // Drop a closing row / column equal to the first one for periodic directions.
    let m = closed_rows(grid, rows, cols, dim, &options.end_u);
    let closed_cols = options.end_v == EndCondition::Periodic
        && cols >= 2
        && (0..m).all(|i| {
            let row = &grid[i * cols * dim..(i + 1) * cols * dim];
            row[..dim] == row[(cols - 1) * dim..]
        });
    let n = if closed_cols { cols - 1 } else { cols };
    let grid: std::borrow::Cow<[f64]> = if closed_cols {
        grid[..m * cols * dim]
            .chunks_exact(cols * dim)
            .flat_map(|row| &row[..n * dim])
            .copied()
            .collect::<Vec<f64>>()
            .into()
    } else {
        grid[..m * cols * dim].into()
    };
    for (count, end) in [(m, &options.end_u), (n, &options.end_v)] {
        let min = if *end == EndCondition::Periodic { 3 } else { 2 };
        if count < min {
            return Err(Error::TooFewPoints {
                what: "grid rows or columns",
                got: count,
                min,
            });
        }
    }
    let p = options.parametrization;
    let tu = grid_parameters(&grid, m, n, dim, p, options.end_u == EndCondition::Periodic)?;
    // Along v the lines are the columns (uniform parameters need no grid).
    let grid_t = match p {
        Parametrization::Uniform => Vec::new(),
        _ => transpose(&grid, m, n, dim),
    };
    let tv = grid_parameters(
        &grid_t,
        n,
        m,
        dim,
        p,
        options.end_v == EndCondition::Periodic,
    )?;
    let sys_u = Solver1d::new(knots_around(&tu), &options.end_u, p)?;
    let sys_v = Solver1d::new(knots_around(&tv), &options.end_v, p)?;
    progress.add_total(2 * m as u64)?;
    let s = separable_with_progress(&grid, m, n, dim, &sys_u, &sys_v, progress)?;
    progress.finish()?;
    Ok(s)
}

/// Solves every row of a row-major grid (rows of `n` points of `dim`) into `out` (rows of
/// `sys.n_control()` points), in parallel. Open systems solve blocks of [`ROW_BLOCK`] rows
/// at once, so that the sweeps' latency chains run side by side: rows of one coordinate
/// (heights) where they lie ([`Solver1d::solve_rows`]), rows of points interleaved as one
/// system with ROW_BLOCK·dim right-hand sides.
fn solve_grid_rows(
    sys: &Solver1d,
    grid: &[f64],
    n: usize,
    dim: usize,
    out: &mut [f64],
    progress: &Progress,
) -> Result<()> {
    let nc = sys.n_control();
    if !sys.solves_in_place() {
        return out
            .par_chunks_mut(nc * dim)
            .zip(grid.par_chunks(n * dim))
            .try_for_each(|(o, row)| {
                sys.solve(row, dim, o)?;
                progress.advance(1)
            });
    }
    if dim == 1 && sys.solves_rows() {
        // Heights: blocks of rows swept side by side where they lie.
        return out
            .par_chunks_mut(ROW_BLOCK * nc)
            .zip(grid.par_chunks(ROW_BLOCK * n))
            .try_for_each(|(o, rows)| {
                if rows.len() == ROW_BLOCK * n {
                    let mut outs = o.chunks_exact_mut(nc);
                    let outs: [&mut [f64]; ROW_BLOCK] =
                        std::array::from_fn(|_| outs.next().expect("ROW_BLOCK rows"));
                    let rows = std::array::from_fn(|i| &rows[i * n..(i + 1) * n]);
                    sys.solve_rows(rows, outs)?;
                    return progress.advance(ROW_BLOCK as u64);
                }
                for (o, row) in o.chunks_exact_mut(nc).zip(rows.chunks_exact(n)) {
                    sys.solve_rows([row], [o])?;
                }
                progress.advance((rows.len() / n) as u64)
            });
    }
    out.par_chunks_mut(ROW_BLOCK * nc * dim)
        .zip(grid.par_chunks(ROW_BLOCK * n * dim))
        .try_for_each_init(Vec::new, |buf, (o, rows)| {
            let b = rows.len() / (n * dim);
            let w = b * dim;
            buf.clear();
            buf.resize(nc * w, 0.0);
            // Element by element: slices of `dim` numbers would be a memcpy call each.
            for (r, row) in rows.chunks_exact(n * dim).enumerate() {
                for (k, p) in row.chunks_exact(dim).enumerate() {
                    let at = (k + 1) * w + r * dim;
                    for (c, x) in p.iter().enumerate() {
                        buf[at + c] = *x;
                    }
                }
            }
            sys.solve_in_place(buf, w)?;
            for (r, row) in o.chunks_exact_mut(nc * dim).enumerate() {
                for (j, c) in row.chunks_exact_mut(dim).enumerate() {
                    let at = j * w + r * dim;
                    for (k, x) in c.iter_mut().enumerate() {
                        *x = buf[at + k];
                    }
                }
            }
            progress.advance(b as u64)
        })
}

/// Rows solved together by [`solve_grid_rows`].
const ROW_BLOCK: usize = 8;

/// The span holding x and the basis functions on it, along one direction.
#[inline(always)]
fn axis_basis(
    knots: &[f64],
    p: usize,
    n: usize,
    inv_step: Option<f64>,
    x: f64,
) -> (usize, [f64; 8]) {
    let s = axis_span(knots, p, n, inv_step, x);
    (s, axis_basis_on(knots, p, inv_step, s, x))
}

/// The basis functions of [`axis_basis`] on span s.
#[inline(always)]
fn axis_basis_on(knots: &[f64], p: usize, inv_step: Option<f64>, s: usize, x: f64) -> [f64; 8] {
    let mut b = [0.0; 8];
    match (inv_step, p) {
        (Some(inv), 3) => uniform_cubic_basis((x - knots[s]) * inv, &mut b[..4]),
        _ => basis_funs(knots, s, x, p, &mut b[..=p]),
    }
    b
}

/// The span of [`axis_basis`] (one multiplication on uniform cubic knots).
#[inline(always)]
fn axis_span(knots: &[f64], p: usize, n: usize, inv_step: Option<f64>, x: f64) -> usize {
    match (inv_step, p) {
        (Some(inv), 3) => uniform_span(knots[0], inv, p, n, x),
        _ => find_span(knots, p, n, x),
    }
}

/// The separable solve: rows along v, then along u, reporting the m rows along v and then
/// m units for the solve along u.
pub(crate) fn separable_with_progress(
    grid: &[f64],
    m: usize,
    n: usize,
    dim: usize,
    sys_u: &Solver1d,
    sys_v: &Solver1d,
    progress: &Progress,
) -> Result<SurfaceInterpolation> {
    let (nu, nv) = (sys_u.n_control(), sys_v.n_control());
    let width = nv * dim;
    let control = if sys_u.solves_in_place() {
        // Open in u: the rows' solutions go straight into rows 1..=m of the net, and the
        // columns are solved in place with whole rows as right-hand sides (no transposes).
        let mut control = vec![0.0; nu * width];
        let rows = &mut control[width..(m + 1) * width];
        solve_grid_rows(sys_v, grid, n, dim, rows, progress)?;
        sys_u.solve_in_place(&mut control, width)?;
        control
    } else {
        let r = solve_rows(sys_v, grid, m, n, dim)?;
        progress.advance(m as u64)?;
        let rt = transpose(&r, m, nv, dim);
        let ct = solve_rows(sys_u, &rt, nv, m, dim)?;
        transpose(&ct, nv, nu, dim)
    };
    progress.advance(m as u64)?;
    Ok(SurfaceInterpolation {
        surface: BsplineSurface::from_trusted(
            (3, 3),
            sys_u.knots.clone(),
            sys_v.knots.clone(),
            nu,
            nv,
            dim,
            control,
        ),
        params_u: sys_u.parameters().to_vec(),
        params_v: sys_v.parameters().to_vec(),
    })
}

/// Interpolates heights z\[i\]\[j\] given over the regular grid x_i = x0 + i·dx, y_j = y0 + j·dy
/// (row-major, `rows × cols`): the result is a scalar surface z(x, y) with S(x_i, y_j) = z_ij.
/// Errors as [`interpolate_surface`], plus non-positive or non-finite spacing.
pub fn interpolate_heights(
    z: &[f64],
    rows: usize,
    cols: usize,
    origin: (f64, f64),
    spacing: (f64, f64),
    end: &EndCondition,
) -> Result<BsplineSurface> {
    interpolate_heights_with_progress(z, rows, cols, origin, spacing, end, &Progress::none())
}

/// [`interpolate_heights`] reporting to `progress` ([`crate::progress`]) in the units of
/// [`interpolate_surface_flat_with_progress`]: the grid rows solved along y (per block of
/// rows), then as many for the solve along x. The same surface, bit for bit, as without
/// it; [`Error::Cancelled`] when the callback asks to stop.
///
/// ```
/// use geomkit::bspline::{interpolate_heights_with_progress, EndCondition};
/// use geomkit::progress::Progress;
/// use std::ops::ControlFlow;
/// let z: Vec<f64> = (0..300 * 200).map(|k| ((k % 200) as f64 * 0.1).sin()).collect();
/// let stop = |_: u64, _: u64| ControlFlow::Break(());
/// let end = EndCondition::NotAKnot;
/// let e = interpolate_heights_with_progress(&z, 300, 200, (0.0, 0.0), (1.0, 1.0), &end,
///     &Progress::new(&stop));
/// assert_eq!(e.unwrap_err(), geomkit::Error::Cancelled);
/// ```
pub fn interpolate_heights_with_progress(
    z: &[f64],
    rows: usize,
    cols: usize,
    origin: (f64, f64),
    spacing: (f64, f64),
    end: &EndCondition,
    progress: &Progress,
) -> Result<BsplineSurface> {
    let (dx, dy) = spacing;
    if !(dx.is_finite()
        && dy.is_finite()
        && dx > 0.0
        && dy > 0.0
        && origin.0.is_finite()
        && origin.1.is_finite())
    {
        return Err(Error::InvalidOption {
            option: "grid spacing",
            reason: "origin must be finite and spacing finite and > 0",
        });
    }
    if *end == EndCondition::Periodic || *end == EndCondition::Repeat {
        return Err(Error::InvalidOption {
            option: "height end condition",
            reason:
                "heights over a grid take natural, clamped, bessel, not-a-knot or outer-points ends",
        });
    }
    let opts = SurfaceInterpolationOptions::default()
        .with_end(end.clone())
        .with_parametrization(Parametrization::Uniform);
    let fit = interpolate_surface_flat_with_progress(rows, cols, 1, z, &opts, progress)?;
    let s = fit.surface;
    let map = |k: &[f64], o: f64, h: f64| k.iter().map(|t| o + t * h).collect::<Vec<_>>();
    let (ku, kv) = (map(&s.knots_u, origin.0, dx), map(&s.knots_v, origin.1, dy));
    // (An extreme origin or spacing can overflow the mapped knots.)
    check_knots(&ku, s.degree.0, s.n_u)?;
    check_knots(&kv, s.degree.1, s.n_v)?;
    let mut mapped = BsplineSurface::from_trusted(s.degree, ku, kv, s.n_u, s.n_v, 1, s.control);
    // Uniform by construction: the solve used the exact rows (1, 4, 1)/6 of integer knots,
    // and evaluation must too (the mapped knots carry rounding of o + t·h).
    mapped.inv_steps = (Some(1.0 / dx), Some(1.0 / dy));
    Ok(mapped)
}

/// Interpolates heights z\[i\]\[j\] (row-major, `xs.len() × ys.len()`) given at the grid
/// (xs\[i\], ys\[j\]) with any strictly increasing coordinates (SciPy's
/// `RectBivariateSpline(x, y, z, s=0)` is the not-a-knot case): a scalar surface z(x, y).
/// Errors: coordinates not finite or not increasing, fewer than 2 per direction, a `z` of
/// the wrong length or with non-finite values, periodic or repeat ends.
pub fn interpolate_heights_at(
    z: &[f64],
    xs: &[f64],
    ys: &[f64],
    end: &EndCondition,
) -> Result<BsplineSurface> {
    interpolate_heights_at_with_progress(z, xs, ys, end, &Progress::none())
}

/// [`interpolate_heights_at`] reporting to `progress` ([`crate::progress`]): the rows of z
/// solved along y (per block of rows), then as many units for the solve along x. The same
/// surface, bit for bit, as without it; [`Error::Cancelled`] when the callback asks to stop.
pub fn interpolate_heights_at_with_progress(
    z: &[f64],
    xs: &[f64],
    ys: &[f64],
    end: &EndCondition,
    progress: &Progress,
) -> Result<BsplineSurface> {
    if *end == EndCondition::Periodic || *end == EndCondition::Repeat {
        return Err(Error::InvalidOption {
            option: "height end condition",
            reason:
                "heights over a grid take natural, clamped, bessel, not-a-knot or outer-points ends",
        });
    }
    validate_points("heights", 1, z)?;
    if z.len() != xs.len() * ys.len() {
        return Err(Error::BufferSize {
            expected: xs.len() * ys.len(),
            got: z.len(),
        });
    }
    for axis in [xs, ys] {
        if axis.len() < 2 {
            return Err(Error::TooFewPoints {
                what: "grid coordinates",
                got: axis.len(),
                min: 2,
            });
        }
        if let Some(index) = axis.iter().position(|t| !t.is_finite()) {
            return Err(Error::NonFinite {
                what: "grid coordinate",
                index,
            });
        }
        if let Some(i) = axis.windows(2).position(|w| w[1] <= w[0]) {
            return Err(Error::InvalidParameter {
                index: i + 1,
                reason: "grid coordinates must be strictly increasing",
            });
        }
    }
    let p = Parametrization::ChordLength;
    let sys_u = Solver1d::new(knots_around(xs), end, p)?;
    let sys_v = Solver1d::new(knots_around(ys), end, p)?;
    progress.add_total(2 * xs.len() as u64)?;
    let fit = separable_with_progress(z, xs.len(), ys.len(), 1, &sys_u, &sys_v, progress)?;
    progress.finish()?;
    Ok(fit.surface)
}

/// The distinct knots strictly inside (a, b).
fn inner_knots(knots: &[f64], (a, b): (f64, f64)) -> Vec<f64> {
    let mut k: Vec<f64> = knots.iter().copied().filter(|&x| x > a && x < b).collect();
    k.dedup();
    k
}

/// The tensor-product B-spline surface of spec/bspline-interpolation.md (bicubic on uniform
/// knots: formula (1) in each direction). Points are evaluated by the batch kernels of
/// [`BsplineSurface::eval_many_par`], so that [`Surface::eval_into`] and
/// [`Surface::eval_batch`] agree bit for bit (the inherent [`BsplineSurface::eval_into`]
/// sums in another order: within a few ulps).
impl Surface for BsplineSurface {
    crate::geom::forward_to_inherent!(BsplineSurface; dim, surface_domain, eval_grid);

    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        self.eval_point_batched(u, v, out)
    }

    /// The kernels of [`BsplineSurface::eval_many_par`] over interleaved pairs.
    fn eval_batch(&self, uv: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        self.eval_pairs(uv, out, options.parallel())
    }

    /// Every order ([`BsplineSurface::eval_derivative`], NURBS Book A2.3 in each direction;
    /// zero above the degrees; at a knot, the span on its right).
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim, out)?;
        if (ku, kv) == (0, 0) {
            self.eval_point_batched(u, v, out);
        } else {
            self.eval_derivative(u, v, ku, kv, out);
        }
        Ok(())
    }

    /// The distinct knots strictly inside the domain, in u and in v.
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        let (du, dv) = BsplineSurface::domain(self);
        (
            inner_knots(&self.knots_u, du),
            inner_knots(&self.knots_v, dv),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiled_transpose_equals_the_definition() {
        // Sizes across the 64-point tiles: partial tiles at both ends, points of 1 to 3.
        for (rows, cols, dim) in [(1, 1, 1), (70, 130, 1), (129, 65, 3), (64, 200, 2)] {
            let data: Vec<f64> = (0..rows * cols * dim).map(|i| i as f64).collect();
            let t = transpose(&data, rows, cols, dim);
            for i in 0..rows {
                for j in 0..cols {
                    for c in 0..dim {
                        assert_eq!(t[(j * rows + i) * dim + c], data[(i * cols + j) * dim + c]);
                    }
                }
            }
        }
    }
}
