//! Tiled interpolation for inputs too large for one solve (spec/bspline-interpolation.md §5,
//! §6). The influence of one reference point on the control points decays like
//! (2 - √3)^k ≈ 0.268^k with the distance k (uniform parameters), so a tile solved with a halo
//! of h extra points on each side and an arbitrary condition at its artificial ends has
//! interior control points equal to the global solve's within 0.268^h relative — for the
//! default h = 32 about 5·10^-19, far below rounding. Tiles are independent: they run in
//! parallel, and [`CurveTiler`] streams them (memory of a few tiles for any N).
//!
//! The paper's own fragments average the shared points instead; [`paper_fragments_averaged`]
//! reproduces that, and its error does not vanish however wide the overlap.
//!
//! ```
//! use geomkit::bspline::{interpolate_curve_flat, interpolate_curve_tiled, InterpolationOptions, TileOptions};
//! let pts: Vec<f64> = (0..5000).flat_map(|i| { let t = i as f64 * 0.01; [t.cos(), t.sin() * t] }).collect();
//! let opts = InterpolationOptions::default();
//! let global = interpolate_curve_flat(2, &pts, &opts).unwrap();
//! let tiled = interpolate_curve_tiled(2, &pts, &opts, &TileOptions::default().with_tile_size(700)).unwrap();
//! let err = global.curve().control_flat().iter().zip(tiled.curve().control_flat())
//!     .map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
//! assert!(err < 1e-13);
//! ```

use super::curve::BsplineCurve;
use super::interpolate::{
    knots_around, knots_around_parameters, CurveInterpolation, EndCondition, InterpolationOptions,
    Params, Solver1d,
};
use crate::par::*;
use crate::points::validate_points;
use crate::progress::Progress;
use crate::{Error, Result};
use std::ops::Range;

/// The fewest points per tile the front ends accept (the CLI's `--tile`, the Python
/// package's `tile=`): with a halo of 0 a tile of one point would be a single point, too few
/// for any solve. [`TileOptions::with_tile_size`] itself takes any size from 1.
pub const MIN_TILE_SIZE: usize = 2;

/// Tile sizes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct TileOptions {
    /// Reference points owned by one tile (default 65 536).
    pub tile_size: usize,
    /// Extra points solved on each side and discarded (default 32; the tiles of any degree,
    /// [`super::SplineTiler`], take at least [`super::MIN_SPLINE_HALO`]).
    pub halo: usize,
}

impl Default for TileOptions {
    fn default() -> Self {
        TileOptions {
            tile_size: 1 << 16,
            halo: 32,
        }
    }
}

impl TileOptions {
    /// Sets the number of points a tile owns (>= 1).
    pub fn with_tile_size(mut self, n: usize) -> Self {
        self.tile_size = n.max(1);
        self
    }

    /// Sets the halo width.
    pub fn with_halo(mut self, h: usize) -> Self {
        self.halo = h;
        self
    }
}

/// One tile: which reference points it reads and which control points it produces.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TilePlan {
    /// Reference points to read (owned points plus halos).
    pub read: Range<usize>,
    /// Control points (global indices) this tile writes.
    pub write: Range<usize>,
}

/// Plans and solves the tiles of an open interpolating curve through N points; the control
/// points of all tiles together equal those of [`super::interpolate_curve_flat`] (N + 2 of
/// them), and the knots are those of the global curve.
#[derive(Debug, Clone)]
pub struct CurveTiler {
    n: usize,
    dim: usize,
    options: InterpolationOptions,
    tiles: TileOptions,
}

impl CurveTiler {
    /// A tiler for `n` points of `dim` coordinates. Errors: end conditions that are not local
    /// (periodic, the paper's repeat: solve those globally, they are O(N) too), n < 2.
    pub fn new(
        n: usize,
        dim: usize,
        options: &InterpolationOptions,
        tiles: &TileOptions,
    ) -> Result<Self> {
        if matches!(options.end, EndCondition::Periodic | EndCondition::Repeat) {
            return Err(Error::InvalidOption {
                option: "tiled end condition",
                reason: "tiles take natural, clamped, bessel, not-a-knot or outer-points ends",
            });
        }
        if n < 2 {
            return Err(Error::TooFewPoints {
                what: "reference points",
                got: n,
                min: 2,
            });
        }
        Ok(CurveTiler {
            n,
            dim,
            options: options.clone(),
            tiles: *tiles,
        })
    }

    /// The tiles in order.
    pub fn plan(&self) -> Vec<TilePlan> {
        plan_tiles(self.n, &self.tiles)
    }

    /// Solves one tile from its `read` points (row-major). `t_start` is the parameter of
    /// the first read point in the whole sequence (0 for the first tile; for the next ones
    /// take it from an earlier tile's [`TileSolution::parameters`], which overlap): the tile
    /// then sees exactly the global parameters and reproduces the global solve.
    pub fn solve(&self, plan: &TilePlan, points: &[f64], t_start: f64) -> Result<TileSolution> {
        let d = self.dim;
        let mut control = Vec::new();
        let solver = self.solve_tile(plan, points, t_start, false, &mut control)?;
        let (w0, w1) = (
            plan.write.start - plan.read.start,
            plan.write.end - plan.read.start,
        );
        Ok(TileSolution {
            control: control[w0 * d..w1 * d].to_vec(),
            parameters: solver.parameters().to_vec(),
        })
    }

    /// [`CurveTiler::solve`] into `control` (resized to all N + 2 control points of the
    /// tile, so that a caller can reuse it from tile to tile), with the points already
    /// checked if `validated`; returns the tile's system (its knots and parameters).
    fn solve_tile(
        &self,
        plan: &TilePlan,
        points: &[f64],
        t_start: f64,
        validated: bool,
        control: &mut Vec<f64>,
    ) -> Result<Solver1d> {
        let d = self.dim;
        if !validated {
            validate_points("reference points", d, points)?;
        }
        let (lo, hi) = (plan.read.start, plan.read.end);
        if points.len() != (hi - lo) * d {
            return Err(Error::BufferSize {
                expected: (hi - lo) * d,
                got: points.len(),
            });
        }
        let local_n = hi - lo;
        // At artificial ends any condition will do: its influence decays through the halo.
        let end = |real: bool| {
            if real {
                self.options.end.clone()
            } else {
                EndCondition::Natural
            }
        };
        let (start_end, finish_end) = (end(lo == 0), end(hi == self.n));
        let knots =
            knots_around_parameters(points, d, self.options.parametrization, false, t_start)?;
        let solver = Solver1d::new_mixed(knots, &start_end, &finish_end)?;
        debug_assert_eq!(solver.n_control(), local_n + 2);
        control.clear();
        control.resize(solver.n_control() * d, 0.0);
        solver.solve_checked(points, d, control, true)?;
        Ok(solver)
    }
}

/// What one tile produces.
#[derive(Debug, Clone, PartialEq)]
pub struct TileSolution {
    /// Control points of the tile's `write` range, row-major.
    pub control: Vec<f64>,
    /// Parameters of the tile's `read` points.
    pub parameters: Vec<f64>,
}

/// Tiles of `n` points (open ends): each owns `tile_size` points and reads a halo around them.
fn plan_tiles(n: usize, tiles: &TileOptions) -> Vec<TilePlan> {
    let (size, h) = (tiles.tile_size.max(1), tiles.halo);
    (0..n.div_ceil(size))
        .map(|k| {
            let (a, b) = (k * size, ((k + 1) * size).min(n));
            // Data point i is centred on control point i + 1; the ends own c_0 / c_(N+1).
            let w0 = if a == 0 { 0 } else { a + 1 };
            let w1 = if b == n { n + 2 } else { b + 1 };
            TilePlan {
                read: a.saturating_sub(h)..b.saturating_add(h).min(n),
                write: w0..w1,
            }
        })
        .collect()
}

/// Interpolates a rows × cols × dim grid (row-major) in square blocks of
/// `tiles.tile_size` points a side with a halo of `tiles.halo` points, in parallel over
/// rows of blocks: the tensor-product inverse is the product of two decaying 1-D inverses,
/// so each block's interior equals the global [`super::interpolate_surface_flat`] within
/// rounding. Parameters are computed once for the whole grid. Errors: periodic or repeat
/// ends (solve those globally), and as the global solve.
pub fn interpolate_surface_tiled(
    rows: usize,
    cols: usize,
    dim: usize,
    grid: &[f64],
    options: &super::SurfaceInterpolationOptions,
    tiles: &TileOptions,
) -> Result<super::SurfaceInterpolation> {
    let none = Progress::none();
    interpolate_surface_tiled_with_progress(rows, cols, dim, grid, options, tiles, &none)
}

/// [`interpolate_surface_tiled`] reporting to `progress` ([`crate::progress`]) as each block
/// solves (units: the grid rows each block reads, halo included, solved along v — reported
/// per block of rows — then as many for its solve along u). The same surface, bit for bit,
/// as without it; [`Error::Cancelled`] when the callback asks to stop.
pub fn interpolate_surface_tiled_with_progress(
    rows: usize,
    cols: usize,
    dim: usize,
    grid: &[f64],
    options: &super::SurfaceInterpolationOptions,
    tiles: &TileOptions,
    progress: &Progress,
) -> Result<super::SurfaceInterpolation> {
    for end in [&options.end_u, &options.end_v] {
        if matches!(end, EndCondition::Periodic | EndCondition::Repeat) {
            return Err(Error::InvalidOption {
                option: "tiled end condition",
                reason: "tiles take natural, clamped, bessel, not-a-knot or outer-points ends",
            });
        }
    }
    validate_points("reference grid", dim, grid)?;
    if grid.len() != rows * cols * dim {
        return Err(Error::BufferSize {
            expected: rows * cols * dim,
            got: grid.len(),
        });
    }
    let (tu, tv) = super::surface::grid_parameters_both(grid, rows, cols, dim, options)?;
    let (nu, nv) = (rows + 2, cols + 2);
    let (plan_u, plan_v) = (plan_tiles(rows, tiles), plan_tiles(cols, tiles));
    let rows_read: usize = plan_u.iter().map(|p| p.read.len()).sum();
    progress.add_total(2 * (rows_read * plan_v.len()) as u64)?;
    let mut control = crate::mem::zeros(nu * nv * dim);
    // Split the net into the disjoint row bands that each row of blocks writes.
    let mut bands: Vec<(&TilePlan, &mut [f64])> = Vec::with_capacity(plan_u.len());
    let mut rest = control.as_mut_slice();
    for pu in &plan_u {
        let (band, tail) = rest.split_at_mut(pu.write.len() * nv * dim);
        bands.push((pu, band));
        rest = tail;
    }
    let natural = EndCondition::Natural;
    bands
        .into_par_iter()
        .try_for_each(|(pu, band)| -> Result<()> {
            let ru = &pu.read;
            let end_u0 = if ru.start == 0 {
                &options.end_u
            } else {
                &natural
            };
            let end_u1 = if ru.end == rows {
                &options.end_u
            } else {
                &natural
            };
            let sys_u = Solver1d::new_mixed(knots_around(&tu[ru.clone()]), end_u0, end_u1)?;
            for pv in &plan_v {
                let rv = &pv.read;
                let end_v0 = if rv.start == 0 {
                    &options.end_v
                } else {
                    &natural
                };
                let end_v1 = if rv.end == cols {
                    &options.end_v
                } else {
                    &natural
                };
                let sys_v = Solver1d::new_mixed(knots_around(&tv[rv.clone()]), end_v0, end_v1)?;
                let (m, n) = (ru.len(), rv.len());
                let mut block = Vec::with_capacity(m * n * dim);
                for i in ru.clone() {
                    block.extend_from_slice(
                        &grid[(i * cols + rv.start) * dim..(i * cols + rv.end) * dim],
                    );
                }
                let local = super::surface::separable_with_progress(
                    &block, m, n, dim, &sys_u, &sys_v, progress,
                )?;
                let net = local.surface.control_flat();
                let lnv = n + 2;
                for (bi, gi) in pu.write.clone().enumerate() {
                    let li = gi - ru.start;
                    let src = (li * lnv + pv.write.start - rv.start) * dim;
                    let dst = (bi * nv + pv.write.start) * dim;
                    let len = pv.write.len() * dim;
                    band[dst..dst + len].copy_from_slice(&net[src..src + len]);
                }
            }
            Ok(())
        })?;
    progress.finish()?;
    let knots = |t: &[f64]| super::interpolate::open_knots(t);
    Ok(super::SurfaceInterpolation {
        surface: super::BsplineSurface::from_flat(
            (3, 3),
            knots(&tu),
            knots(&tv),
            nu,
            nv,
            dim,
            control,
        )?,
        params_u: tu,
        params_v: tv,
    })
}

/// Interpolates in parallel tiles; equal to [`super::interpolate_curve_flat`] within rounding
/// (see the module docs). Same errors as [`CurveTiler::new`] and the global solve.
pub fn interpolate_curve_tiled(
    dim: usize,
    points: &[f64],
    options: &InterpolationOptions,
    tiles: &TileOptions,
) -> Result<CurveInterpolation> {
    interpolate_curve_tiled_with_progress(dim, points, options, tiles, &Progress::none())
}

/// [`interpolate_curve_tiled`] reporting to `progress` ([`crate::progress`]) once per tile
/// (units: control points). The same curve, bit for bit, as without it;
/// [`Error::Cancelled`] when the callback asks to stop.
pub fn interpolate_curve_tiled_with_progress(
    dim: usize,
    points: &[f64],
    options: &InterpolationOptions,
    tiles: &TileOptions,
    progress: &Progress,
) -> Result<CurveInterpolation> {
    validate_points("reference points", dim, points)?;
    let n = points.len() / dim;
    let tiler = CurveTiler::new(n, dim, options, tiles)?;
    let plan = tiler.plan();
    progress.add_total((n + 2) as u64)?;
    let mut knots = knots_around_parameters(points, dim, options.parametrization, false, 0.0)?;
    // Each tile writes its range of the control points straight into the result (the
    // ranges follow one another): no copy of the whole curve, only a few tiles of scratch.
    let mut control = crate::mem::zeros((n + 2) * dim);
    let mut ranges: Vec<&mut [f64]> = Vec::with_capacity(plan.len());
    let mut rest = control.as_mut_slice();
    for p in &plan {
        let (here, tail) = std::mem::take(&mut rest).split_at_mut(p.write.len() * dim);
        ranges.push(here);
        rest = tail;
    }
    // One scratch buffer of a tile's control points per worker, reused.
    plan.par_iter()
        .zip(ranges.into_par_iter())
        .try_for_each_init(Vec::new, |control, (p, out)| {
            let pts = &points[p.read.start * dim..p.read.end * dim];
            tiler.solve_tile(p, pts, knots[3 + p.read.start], true, control)?;
            let w0 = p.write.start - p.read.start;
            out.copy_from_slice(&control[w0 * dim..w0 * dim + out.len()]);
            progress.advance(p.write.len() as u64)
        })?;
    progress.finish()?;
    super::interpolate::fill_open_ends(&mut knots);
    // The tiles' solves checked their control points (finite); the knots are the global
    // curve's.
    Ok(CurveInterpolation::new(
        BsplineCurve::from_trusted(3, knots, dim, control),
        Params::Knots(3..n + 3),
    ))
}

/// The paper's fragments (§5): fragments of `fragment` points overlapping by `overlap`, each
/// solved by the paper's scheme (its first and last reference points kept as control
/// points, the inner ones from system (2)), and every control point shared by fragments
/// averaged. Returns the N control points p_0..p_(N-1) of the paper's numbering (compare
/// with the global solve: p_0 = k_0, p_(N-1) = k_(N-1), inner from system (2)). Errors:
/// fragment < 3, overlap >= fragment.
pub fn paper_fragments_averaged(
    dim: usize,
    points: &[f64],
    fragment: usize,
    overlap: usize,
) -> Result<Vec<f64>> {
    validate_points("reference points", dim, points)?;
    if fragment < 3 || overlap >= fragment {
        return Err(Error::InvalidOption {
            option: "fragments",
            reason: "need fragment >= 3 points and overlap < fragment",
        });
    }
    let n = points.len() / dim;
    let mut sum = vec![0.0; n * dim];
    let mut count = vec![0usize; n];
    let step = fragment - overlap;
    let mut s = 0;
    loop {
        let e = (s + fragment).min(n);
        let inner = paper_inner(&points[s * dim..e * dim], dim)?;
        for (k, i) in (s..e).enumerate() {
            let src = if k == 0 || i == e - 1 {
                &points[i * dim..(i + 1) * dim]
            } else {
                &inner[(k - 1) * dim..k * dim]
            };
            for c in 0..dim {
                sum[i * dim + c] += src[c];
            }
            count[i] += 1;
        }
        if e == n {
            break;
        }
        s += step;
    }
    for (i, c) in count.iter().enumerate() {
        for v in &mut sum[i * dim..(i + 1) * dim] {
            *v /= *c as f64;
        }
    }
    Ok(sum)
}

/// The inner control points of the paper's scheme for one set of points.
pub(crate) fn paper_inner(points: &[f64], dim: usize) -> Result<Vec<f64>> {
    let n = points.len() / dim;
    let t: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let system = Solver1d::new(
        knots_around(&t),
        &EndCondition::Repeat,
        super::Parametrization::Uniform,
    )?;
    let mut out = vec![0.0; system.n_control() * dim];
    system.solve(points, dim, &mut out)?;
    Ok(out[3 * dim..(n + 1) * dim].to_vec())
}
