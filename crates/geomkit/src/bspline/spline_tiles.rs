//! Tiles for interpolating splines of any degree in SciPy's representation (issue 22: "the
//! same O(N) banded solves, parallel chunks and tiles as the cubic"): [`SplineTiler`]
//! solves the system of [`super::make_interp_spline`] in windows of `tile_size`
//! coefficients, each with a halo of rows on both sides whose solution is discarded, from
//! nothing but the window's own data points — so a caller can stream the points of any N
//! through it in memory of a few tiles (the CLI's `interpolate curve --tile T --degree k`
//! on a .npy) — and [`make_interp_spline_tiled`] runs the same tiles in parallel.
//!
//! Why it is exact: the influence of one row of the collocation system on the coefficients
//! decays like λ^d with the distance d (λ the largest root modulus of the B-spline
//! collocation symbol: 0.17 for k = 2, 0.27 for 3, 0.43 for 5, 0.54 for 7 on uniform data),
//! so the halo's artificial ends (coefficients beyond held at zero) change the owned ones by
//! about λ^h relative; the halo is at least [`MIN_SPLINE_HALO`] = 64 rows
//! (0.54^64 < 1e-17). Systems without decay are refused by the tiler: even degrees on knots
//! at the data (SciPy's knots for derivative end conditions; the collocation matrix of a
//! quadratic there is (1/2, 1/2) bidiagonal, whose inverse does not decay), and periodic
//! ends (they couple the two ends). [`make_interp_spline_tiled`] solves those whole instead,
//! and checks the rows next to every seam: where they do not hold to rounding it solves
//! the whole system (refined), so its result is always the global one.
//!
//! ```
//! use geomkit::bspline::{make_interp_spline, make_interp_spline_tiled, SplineOptions, TileOptions};
//! use geomkit::progress::Progress;
//! let x: Vec<f64> = (0..3000).map(|i| i as f64 + 0.3 * (i as f64).sin()).collect();
//! let y: Vec<f64> = x.iter().map(|v| (0.01 * v).cos()).collect();
//! let opts = SplineOptions::new(5);
//! let whole = make_interp_spline(&x, &y, 1, &opts).unwrap();
//! let tiled = make_interp_spline_tiled(&x, &y, 1, &opts,
//!     &TileOptions::default().with_tile_size(500), &Progress::none()).unwrap();
//! assert_eq!(whole.knots(), tiled.knots());
//! for (a, b) in whole.control_flat().iter().zip(tiled.control_flat()) {
//!     assert!((a - b).abs() <= 1e-13);
//! }
//! ```

use super::curve::BsplineCurve;
use super::spline::{
    check_data, interp, interp_spline_parts, max_abs, resolve_end, seams_hold, OpenSystem,
    AMPLIFIED_TILES, TILE_HALO,
};
use super::tiles::TileOptions;
use super::{EndSpec, SplineEnds, SplineOptions};
use crate::par::*;
use crate::progress::Progress;
use crate::{Error, Result};
use std::ops::Range;

/// The fewest halo rows a tile of [`SplineTiler`] solves on each side (whatever
/// [`TileOptions::halo`] says): enough for the slowest decay, degree 7's.
pub const MIN_SPLINE_HALO: usize = TILE_HALO;

/// How the knots follow from x (the rules of [`super::make_interp_spline`]'s module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KnotRule {
    /// Not-a-knot, odd degree: the inner x.
    NotAKnotOdd,
    /// Not-a-knot, even degree: the inner midpoints.
    NotAKnotEven,
    /// Derivative conditions: every x, the ends k + 1 fold.
    Augmented,
}

/// One tile of a [`SplineTiler`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SplineTilePlan {
    /// Data points (x and y) the tile reads.
    pub read: Range<usize>,
    /// Coefficients (global indices) it produces.
    pub write: Range<usize>,
    /// Knots (global indices) it produces: the tiles' ranges follow one another and cover
    /// all the knots of the curve ([`SplineTiler::n_knots`]).
    pub knots: Range<usize>,
    /// The system's rows solved (owned rows and halos).
    rows: Range<usize>,
}

/// What one tile of a [`SplineTiler`] produces.
#[derive(Debug, Clone, PartialEq)]
pub struct SplineTile {
    /// The coefficients of the tile's `write` range, row-major (`dim` per coefficient).
    pub coefficients: Vec<f64>,
    /// The knots of the tile's `knots` range.
    pub knots: Vec<f64>,
}

/// Plans and solves the tiles of [`super::make_interp_spline`]'s open system for n points
/// (module docs): tile by tile, each from its own points only, in any order.
#[derive(Debug, Clone)]
pub struct SplineTiler {
    n: usize,
    dim: usize,
    k: usize,
    rule: KnotRule,
    left: EndSpec,
    right: EndSpec,
    /// Conditions at each end, and coefficients in all.
    nl: usize,
    nt: usize,
    tile: usize,
    halo: usize,
}

impl SplineTiler {
    /// A tiler for `n` points of `dim` coordinates with the degree and end conditions of
    /// `options`. Errors ([`Error::InvalidOption`] unless said): periodic ends, given knots,
    /// degree 0 (a step function: nothing to solve) or above 7, even degrees with end
    /// derivative conditions (no decay: module docs), fewer than 2 points
    /// ([`Error::TooFewPoints`]), too few points for the degree, and end conditions of the
    /// wrong number ([`Error::Interpolation`], as the global solve).
    pub fn new(n: usize, dim: usize, options: &SplineOptions, tiles: &TileOptions) -> Result<Self> {
        let k = options.degree;
        let (left, right) = match &options.ends {
            SplineEnds::Open { left, right } => (left.clone(), right.clone()),
            _ => {
                return Err(Error::InvalidOption {
                    option: "tiled end condition",
                    reason: "periodic ends couple the whole curve: solve them without tiles \
                             (that is O(N) too)",
                })
            }
        };
        if options.knots.is_some() {
            return Err(Error::InvalidOption {
                option: "tiled knots",
                reason: "tiles place SciPy's default knots; solve given knots without tiles",
            });
        }
        if !(1..=super::MAX_SPLINE_DEGREE).contains(&k) {
            return Err(Error::InvalidOption {
                option: "tiled degree",
                reason: "tiles solve degrees 1 to 7 (degree 0 is the data itself)",
            });
        }
        if n < 2 {
            return Err(Error::TooFewPoints {
                what: "data points",
                got: n,
                min: 2,
            });
        }
        if dim == 0 {
            return Err(Error::ZeroDimension { what: "values y" });
        }
        let count = |e: &EndSpec| match e {
            EndSpec::NotAKnot => 0,
            EndSpec::Bessel => 1,
            EndSpec::Derivatives(list) => list.len(),
        };
        let (nl, nr) = (count(&left), count(&right));
        let rule = match (nl + nr, k % 2) {
            (0, 1) => KnotRule::NotAKnotOdd,
            (0, _) => KnotRule::NotAKnotEven,
            (_, 1) => KnotRule::Augmented,
            _ => {
                return Err(Error::InvalidOption {
                    option: "tiled end condition",
                    reason: "an even degree with end derivative conditions has its knots at \
                             the data, where the influence of a point does not decay: tiles \
                             cannot hold; solve it without tiles, or use not-a-knot ends",
                })
            }
        };
        let nt = match rule {
            KnotRule::Augmented => n + k - 1,
            _ => n,
        };
        if nt != n + nl + nr {
            return Err(interp(format!(
                "The number of derivatives at boundaries does not match: expected {}, got \
                 {nl}+{nr} ({nt} coefficients for degree {k}, {n} points)",
                nt - n
            )));
        }
        if n <= k {
            return Err(interp(format!(
                "{n} points are too few for degree {k} in tiles: give at least {}",
                k + 1
            )));
        }
        Ok(SplineTiler {
            n,
            dim,
            k,
            rule,
            left,
            right,
            nl,
            nt,
            tile: tiles.tile_size.max(1),
            halo: tiles.halo.max(MIN_SPLINE_HALO),
        })
    }

    /// Coefficients of the curve (SciPy's `len(c)`).
    pub fn n_coefficients(&self) -> usize {
        self.nt
    }

    /// Knots of the curve (SciPy's `len(t)`: coefficients + k + 1).
    pub fn n_knots(&self) -> usize {
        self.nt + self.k + 1
    }

    /// The degree.
    pub fn degree(&self) -> usize {
        self.k
    }

    /// Knot j of the curve from the data abscissae (`x(i)` gives x_i).
    fn knot(&self, j: usize, x: impl Fn(usize) -> f64) -> f64 {
        let (n, k) = (self.n, self.k);
        match self.rule {
            KnotRule::Augmented => {
                if j < k {
                    x(0)
                } else if j < k + n {
                    x(j - k)
                } else {
                    x(n - 1)
                }
            }
            KnotRule::NotAKnotOdd => {
                let h = k.div_ceil(2);
                let inner = n.saturating_sub(2 * h);
                if j <= k {
                    x(0)
                } else if j < k + 1 + inner {
                    x(j - k - 1 + h)
                } else {
                    x(n - 1)
                }
            }
            KnotRule::NotAKnotEven => {
                let h = k / 2;
                let inner = (n - 1).saturating_sub(h).saturating_sub(h);
                if j <= k {
                    x(0)
                } else if j < k + 1 + inner {
                    let i = j - k - 1 + h;
                    (x(i) + x(i + 1)) / 2.0
                } else {
                    x(n - 1)
                }
            }
        }
    }

    /// The tiles in order: tile w owns coefficients w·T .. (w+1)·T and the same knots (the
    /// last also the k + 1 after the coefficients).
    pub fn plan(&self) -> Vec<SplineTilePlan> {
        let (nt, k, n) = (self.nt, self.k, self.n);
        (0..nt.div_ceil(self.tile))
            .map(|w| {
                let (a0, a1) = (w * self.tile, ((w + 1) * self.tile).min(nt));
                let (r0, r1) = (
                    a0.saturating_sub(self.halo),
                    a1.saturating_add(self.halo).min(nt),
                );
                // A window's data and knots reach up to 3k + 2 rows beyond its rows: a window
                // that would stop nearer an end than that runs to the end itself (it would
                // read data before the first point, or end on the end's knots without its
                // conditions: tiles owning coefficients just beyond a halo's reach).
                let margin = 3 * k + 2;
                let r0 = if r0 < margin { 0 } else { r0 };
                let r1 = if nt - r1 < margin { nt } else { r1 };
                let (xb, xe) = self.local_x(r0, r1);
                // The x the local knots need: knot j reads x near j - k - 1 + h >= j - 2k - 1.
                let need0 = if r0 == 0 {
                    0
                } else {
                    (r0 - k).saturating_sub(2 * k + 2)
                };
                let knots = a0..if a1 == nt { nt + k + 1 } else { a1 };
                // Owned knots read x up to index < knots.end + 1.
                let read = need0.min(xb)..xe.max((knots.end + 1).min(n));
                SplineTilePlan {
                    read,
                    write: a0..a1,
                    knots,
                    rows: r0..r1,
                }
            })
            .collect()
    }

    /// The data points x[xb..xe] of the local system of rows r0..r1 (its first row, k rows
    /// before r0 unless r0 = 0, is data row xb, or the first row of the left end).
    fn local_x(&self, r0: usize, r1: usize) -> (usize, usize) {
        let k = self.k;
        let xb = if r0 == 0 { 0 } else { r0 - k - self.nl };
        let xe = if r1 == self.nt {
            self.n
        } else {
            (r1 + 2 * k + 2).min(self.n)
        };
        (xb, xe)
    }

    /// Solves one tile from its `read` points: `x` their abscissae, `y` their values
    /// (row-major). Errors: buffers of the wrong length ([`Error::BufferSize`]), non-finite
    /// or non-increasing x, non-finite y, an ill-conditioned window (coefficients far above
    /// the data: solve without tiles), and the global solve's errors.
    pub fn solve(&self, plan: &SplineTilePlan, x: &[f64], y: &[f64]) -> Result<SplineTile> {
        let (k, dim) = (self.k, self.dim);
        let read = &plan.read;
        if x.len() != read.len() || y.len() != read.len() * dim {
            return Err(Error::BufferSize {
                expected: read.len() * (1 + dim),
                got: x.len() + y.len(),
            });
        }
        check_data(x, y, dim)?;
        let at = |i: usize| x[i - read.start];
        let (r0, r1) = (plan.rows.start, plan.rows.end);
        let t_base = if r0 == 0 { 0 } else { r0 - k };
        let t_end = if r1 == self.nt {
            self.nt + k + 1
        } else {
            (r1 + 2 * k + 2).min(self.nt + k + 1)
        };
        let t: Vec<f64> = (t_base..t_end).map(|j| self.knot(j, at)).collect();
        let (xb, xe) = self.local_x(r0, r1);
        let (xl, yl) = (
            &x[xb - read.start..xe - read.start],
            &y[(xb - read.start) * dim..(xe - read.start) * dim],
        );
        let none = EndSpec::NotAKnot;
        let left = if r0 == 0 { &self.left } else { &none };
        let right = if r1 == self.nt { &self.right } else { &none };
        let left = resolve_end(left, xl, yl, dim, k, true)?;
        let right = resolve_end(right, xl, yl, dim, k, false)?;
        let sys = OpenSystem::new(xl, yl, dim, &t, k, &left, &right)?;
        let off = r0 - t_base;
        let (w0, w1) = (off, off + (r1 - r0));
        let b = match sys.collocation_only(w0, w1) {
            true => sys.solve_collocation(w0, w1)?,
            false => None,
        };
        let b = match b {
            Some(b) => b,
            None => {
                let (a, mut b) = sys.window(w0, w1)?;
                a.factor_below(0.0)
                    .map_err(|_| super::spline::singular())?
                    .solve(&mut b, dim);
                b
            }
        };
        let (a0, a1) = (plan.write.start - r0, plan.write.end - r0);
        let coefficients = b[a0 * dim..a1 * dim].to_vec();
        if max_abs(&coefficients) > AMPLIFIED_TILES * sys.rhs_scale()
            || crate::points::first_non_finite(&coefficients).is_some()
        {
            return Err(interp(format!(
                "the tile of coefficients {}..{} is ill-conditioned (coefficients far above \
                 the data, or not finite): solve without tiles, where the whole system is \
                 refined",
                plan.write.start, plan.write.end
            )));
        }
        let knots = plan.knots.clone().map(|j| self.knot(j, at)).collect();
        Ok(SplineTile {
            coefficients,
            knots,
        })
    }
}

/// [`super::make_interp_spline`] in the tiles of [`SplineTiler`] (module docs), run in
/// parallel: the same knots, and coefficients equal to the global solve's within rounding.
/// Where the tiler refuses (periodic, given knots, even degrees with derivative ends,
/// degree 0) or the rows at a seam do not hold to rounding, the whole system is solved
/// instead — the result is always the global one. Reports to `progress` per tile (units:
/// coefficients). Errors: those of [`super::make_interp_spline`], and [`Error::Cancelled`].
pub fn make_interp_spline_tiled(
    x: &[f64],
    y: &[f64],
    dim: usize,
    options: &SplineOptions,
    tiles: &TileOptions,
    progress: &Progress,
) -> Result<BsplineCurve> {
    check_data(x, y, dim)?;
    let n = x.len();
    let whole = || -> Result<BsplineCurve> {
        let c = interp_spline_parts(x, y, dim, options, progress)?;
        progress.finish()?;
        Ok(c)
    };
    let Ok(tiler) = SplineTiler::new(n, dim, options, tiles) else {
        return whole();
    };
    let plan = tiler.plan();
    progress.add_total(tiler.nt as u64)?;
    let mut c = vec![0.0; tiler.nt * dim];
    let mut t = vec![0.0; tiler.n_knots()];
    let mut parts: Vec<(&SplineTilePlan, &mut [f64], &mut [f64])> = Vec::with_capacity(plan.len());
    let (mut rest_c, mut rest_t) = (c.as_mut_slice(), t.as_mut_slice());
    for p in &plan {
        let (here_c, tail_c) = std::mem::take(&mut rest_c).split_at_mut(p.write.len() * dim);
        let (here_t, tail_t) = std::mem::take(&mut rest_t).split_at_mut(p.knots.len());
        parts.push((p, here_c, here_t));
        (rest_c, rest_t) = (tail_c, tail_t);
    }
    let solved = parts.into_par_iter().try_for_each(|(p, out_c, out_t)| {
        let r = &p.read;
        let tile = tiler.solve(p, &x[r.clone()], &y[r.start * dim..r.end * dim])?;
        out_c.copy_from_slice(&tile.coefficients);
        out_t.copy_from_slice(&tile.knots);
        progress.advance(p.write.len() as u64)
    });
    match solved {
        Err(Error::Cancelled) => return Err(Error::Cancelled),
        Err(_) => return whole(),
        Ok(()) => {}
    }
    // The seams: every row next to one must hold for the tiled coefficients.
    let (left, right) = match &options.ends {
        SplineEnds::Open { left, right } => (left, right),
        _ => return whole(),
    };
    let left = resolve_end(left, x, y, dim, tiler.k, true)?;
    let right = resolve_end(right, x, y, dim, tiler.k, false)?;
    let sys = OpenSystem::new(x, y, dim, &t, tiler.k, &left, &right)?;
    if !seams_hold(&sys, &c, tiler.tile)? {
        return whole();
    }
    progress.finish()?;
    crate::points::check_knots(&t, tiler.k, tiler.nt)?;
    Ok(BsplineCurve::from_trusted(tiler.k, t, dim, c))
}
