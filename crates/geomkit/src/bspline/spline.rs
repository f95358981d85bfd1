//! Interpolating B-splines of any degree k = 0..=7 through data (x_i, y_i), in SciPy's
//! representation (spec/bspline-interpolation.md §6; issue 22): the knots t and
//! coefficients c of `scipy.interpolate.make_interp_spline(x, y, k, t, bc_type)`, with its
//! knot placement, its end conditions (a list of derivative conditions at each end, the
//! aliases "natural" and "clamped", periodic) and its errors, worded so that its phrases
//! appear ("Shapes of x", "Expect x to not have duplicates", ...).
//!
//! The method: with nt = len(t) - k - 1 coefficients, n interpolation conditions
//! s(x_i) = y_i and nt - n derivative conditions at the ends form a banded system (at most k
//! sub- and k super-diagonals: each row holds the k + 1 B-splines that are nonzero at its
//! point), solved by LU with partial pivoting in O(n k^2), as SciPy's LAPACK `gbsv`. The
//! derivative rows are formed in units of the end interval (SciPy's rows exactly when it is
//! near 1; on data spaced 1e-50 apart SciPy's entries ~ 1/h^k overflow). Small systems, and
//! those whose coefficients come out far above the data (conditions all at one end: badly
//! conditioned), are refined by iterative refinement with residuals in doubled precision;
//! where that does not converge the system is refused, not answered without digits. Large
//! systems are solved in overlapping windows in parallel, checked at the seams
//! ([`make_interp_spline`]'s notes; `solve_tiled`).
//!
//! Knots (none given):
//! - no end conditions: not-a-knot, t = [x_0]*(k+1) + x[(k+1)/2 .. n-(k+1)/2] +
//!   [x_(n-1)]*(k+1) for odd k; for even k the midpoints (x_i + x_(i+1))/2 in place of the
//!   x (from the k/2-th midpoint on; FITPACK's and SciPy's choice);
//! - derivative conditions: t = [x_0]*k + x + [x_(n-1)]*k (k - 1 conditions in all);
//! - periodic: the x (even k: the midpoints inside) continued by the spacings of the other
//!   end (SciPy's `_periodic_knots`); n - 1 free coefficients, the first and last k
//!   coefficients repeating them. Solved as a cyclic band (corner blocks by the Woodbury
//!   formula, as SciPy) or, for few points, densely.
//!
//! Degree 0 is SciPy's step function (c = y, knots x and x_(n-1) once more). A difference
//! from SciPy, on purpose: "bessel" is an extra end condition (the first derivative of the parabola
//! through the three points nearest the end), which geomkit's cubic interpolation offers too.
//! Smoothing (s > 0) and complex values are out of scope.
//!
//! ```
//! use geomkit::bspline::{make_interp_spline, EndSpec, SplineEnds, SplineOptions};
//! use geomkit::geom::Curve;
//! let x = [0.0, 1.0, 2.5, 3.0, 4.0, 6.0];
//! let y = [1.0, 0.0, 2.0, 1.5, -1.0, 0.5];
//! // A quintic, clamped at the left (zero slope and curvature), natural at the right.
//! let ends = SplineEnds::Open {
//!     left: EndSpec::Derivatives(vec![(1, vec![0.0]), (2, vec![0.0])]),
//!     right: EndSpec::Derivatives(vec![(2, vec![0.0]), (3, vec![0.0])]),
//! };
//! let s = make_interp_spline(&x, &y, 1, &SplineOptions::new(5).with_ends(ends)).unwrap();
//! assert_eq!(s.knots().len(), x.len() + 2 * 5);
//! for (xi, yi) in x.iter().zip(y) {
//!     assert!((s.eval(*xi)[0] - yi).abs() < 1e-13);
//! }
//! ```

use super::banded::BandMatrix;
use super::curve::{basis_funs, basis_funs_derivs, find_span, BsplineCurve};
use super::interpolate::bessel_tangent;
use super::locate::with_avx2;
use super::scipy_cubic;
use super::surface::transpose;
use crate::par::*;
use crate::progress::Progress;
use crate::{Error, Result};

mod collocation;

use collocation::{Solution, Spare};

/// The highest degree [`make_interp_spline`] takes (the B-spline curves' own limit).
pub const MAX_SPLINE_DEGREE: usize = 7;

/// Conditions at one end of an open interpolating spline: one half of SciPy's `bc_type`.
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub enum EndSpec {
    /// No condition at this end (SciPy's `None`); with none at either end and no knots
    /// given, the not-a-knot knots.
    #[default]
    NotAKnot,
    /// Derivatives of the given orders (0..=k) with their values: one value per coordinate,
    /// or one for all coordinates (SciPy's `[(order, value), ...]`).
    Derivatives(Vec<(usize, Vec<f64>)>),
    /// The first derivative of the parabola through the three points nearest the end
    /// (Bessel's estimate; with two points the chord's slope).
    Bessel,
}

impl EndSpec {
    /// A zero second derivative (SciPy's "natural").
    pub fn natural() -> Self {
        EndSpec::Derivatives(vec![(2, vec![0.0])])
    }

    /// A zero first derivative (SciPy's "clamped").
    pub fn clamped() -> Self {
        EndSpec::Derivatives(vec![(1, vec![0.0])])
    }
}

/// The end conditions of [`make_interp_spline`] (SciPy's `bc_type`).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SplineEnds {
    /// An open curve with conditions at its left (first) and right (last) ends.
    Open {
        /// At x_0.
        left: EndSpec,
        /// At x_(n-1).
        right: EndSpec,
    },
    /// A periodic curve: y_(n-1) equals y_0 (within SciPy's `allclose`: 1e-5 relative,
    /// 1e-15 absolute) and the derivatives up to order k - 1 are continuous across the ends.
    Periodic,
}

impl Default for SplineEnds {
    fn default() -> Self {
        SplineEnds::Open {
            left: EndSpec::NotAKnot,
            right: EndSpec::NotAKnot,
        }
    }
}

impl SplineEnds {
    /// The same condition at both ends.
    pub fn both(end: EndSpec) -> Self {
        SplineEnds::Open {
            left: end.clone(),
            right: end,
        }
    }
}

/// Options of [`make_interp_spline`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct SplineOptions {
    /// Degree k (0..=7; default 3).
    pub degree: usize,
    /// End conditions (default: not-a-knot).
    pub ends: SplineEnds,
    /// Knots (SciPy's `t`), or `None` for the default placement of the module docs.
    pub knots: Option<Vec<f64>>,
}

impl Default for SplineOptions {
    fn default() -> Self {
        SplineOptions::new(3)
    }
}

impl SplineOptions {
    /// Degree k, not-a-knot ends, default knots.
    pub fn new(degree: usize) -> Self {
        SplineOptions {
            degree,
            ends: SplineEnds::default(),
            knots: None,
        }
    }

    /// Sets the end conditions.
    pub fn with_ends(mut self, ends: SplineEnds) -> Self {
        self.ends = ends;
        self
    }

    /// Sets the knots.
    pub fn with_knots(mut self, knots: Vec<f64>) -> Self {
        self.knots = Some(knots);
        self
    }
}

/// The interpolating B-spline of degree k through (x_i, y_i) (`y` row-major, `dim`
/// coordinates per point) in SciPy's representation: the knots and coefficients of
/// `make_interp_spline(x, y, k, t, bc_type)` (to rounding). The result evaluates beyond
/// [x_0, x_(n-1)] by its end polynomials; a periodic one repeats with the period
/// x_(n-1) - x_0 (evaluate at x_0 + (x - x_0) mod period, as SciPy's `extrapolate='periodic'`).
///
/// Errors ([`Error::Interpolation`] unless said): y of the wrong length for x ("Shapes of
/// x"), non-finite x or y ([`Error::NonFinite`]), fewer than 2 points, repeated or
/// decreasing x, a degree above 7, knots or end conditions with degree 0, knots that are
/// not sorted, too few, or do not cover x, end conditions of the wrong number for the knots ("The number of derivatives at
/// boundaries does not match"), derivative orders above k, values of the wrong dimension,
/// periodic ends whose first and last y differ or with given knots, a singular system
/// (knots that do not suit x: the Schoenberg–Whitney condition), and one too
/// ill-conditioned for f64 (iterative refinement does not converge).
pub fn make_interp_spline(
    x: &[f64],
    y: &[f64],
    dim: usize,
    options: &SplineOptions,
) -> Result<BsplineCurve> {
    make_interp_spline_with_progress(x, y, dim, options, &Progress::none())
}

/// [`make_interp_spline`] reporting to `progress` ([`crate::progress`]): the units are the
/// rows of the system (one per coefficient), reported per window of the parallel solve
/// (16 384 rows) or at once for a system solved whole. The same curve, bit for bit, as
/// without it; [`Error::Cancelled`] when the callback asks to stop.
pub fn make_interp_spline_with_progress(
    x: &[f64],
    y: &[f64],
    dim: usize,
    options: &SplineOptions,
    progress: &Progress,
) -> Result<BsplineCurve> {
    let c = interp_spline_parts(x, y, dim, options, progress)?;
    progress.finish()?;
    Ok(c)
}

/// [`make_interp_spline_with_progress`] without the final report.
pub(super) fn interp_spline_parts(
    x: &[f64],
    y: &[f64],
    dim: usize,
    options: &SplineOptions,
    progress: &Progress,
) -> Result<BsplineCurve> {
    let k = options.degree;
    let largest = check_data(x, y, dim)?;
    let n = x.len();
    let periodic = options.ends == SplineEnds::Periodic;
    if periodic {
        check_closed(y, dim)?;
    }
    if k > MAX_SPLINE_DEGREE {
        return Err(interp(format!(
            "degree {k} is not supported: give a degree from 0 to {MAX_SPLINE_DEGREE}"
        )));
    }
    let (left, right) = match &options.ends {
        SplineEnds::Open { left, right } => (left, right),
        SplineEnds::Periodic => (&EndSpec::NotAKnot, &EndSpec::NotAKnot),
    };
    let free = *left == EndSpec::NotAKnot && *right == EndSpec::NotAKnot;
    // SciPy's step function: c = y on the knots x + [x_(n-1)], y_i on [x_i, x_(i+1)).
    if k == 0 {
        if options.knots.is_some() || !free {
            return Err(interp(
                "Too much info for k=0: t and bc_type can only be None (a step function \
                 through the points has no end conditions or knots to give)"
                    .into(),
            ));
        }
        let t = knots_with_ends(x, 0, n + 1, |j, out| {
            let m = out.len().min(n - j);
            out[..m].copy_from_slice(&x[j..j + m]);
            out[m..].fill(x[n - 1]);
        });
        return trusted_made(x, 0, t, dim, crate::mem::copy_of(y));
    }
    if k == 3 && free && !periodic && options.knots.is_none() && n >= scipy_cubic::MIN_POINTS {
        // One unit: a few passes over the data, in parallel (under a second for 10^7).
        progress.add_total(1)?;
        if let Some(c) = scipy_cubic::not_a_knot_cubic(x, y, dim, AMPLIFIED_TILES * largest) {
            return Ok(c);
        }
    }
    let t = match &options.knots {
        Some(_) if periodic => {
            return Err(interp(
                "periodic splines make their own knots: give no knots with periodic ends".into(),
            ))
        }
        Some(t) => {
            check_knots(t, x, k)?;
            t.clone()
        }
        // SciPy's special case: the broken line through the points (closed when periodic).
        None if k == 1 && free => {
            let t = augmented_knots(x, 1);
            return trusted_made(x, 1, t, dim, crate::mem::copy_of(y));
        }
        None if periodic => periodic_knots(x, k),
        None if free => not_a_knot_knots(x, k),
        None => augmented_knots(x, k),
    };
    let c = if periodic {
        progress.add_total(1)?;
        let c = solve_periodic(x, y, dim, &t, k)?;
        check_finite_coefficients(&c, dim)?;
        progress.advance(1)?;
        c
    } else {
        let left = resolve_end(left, x, y, dim, k, true)?;
        let right = resolve_end(right, x, y, dim, k, false)?;
        solve_open(x, y, dim, &t, k, &left, &right, largest, progress)?
    };
    match options.knots.is_none() && !periodic {
        true => trusted_made(x, k, t, dim, c),
        false => trusted(k, t, dim, c),
    }
}

/// An error naming the first coefficient of `c` (points of `dim` numbers) that is not
/// finite, if one is not.
fn check_finite_coefficients(c: &[f64], dim: usize) -> Result<()> {
    match crate::points::first_non_finite(c) {
        Some(i) => Err(Error::Overflow {
            what: format!("interpolating spline coefficient {}", i / dim),
            step: "it is not a finite number: the data or the end values are too large for \
                   f64 at this spacing"
                .into(),
        }),
        None => Ok(()),
    }
}

/// The curve of coefficients checked finite here: only its knots are checked (their span
/// must fit f64), not the coefficients again (a pass over 10^7 points costs as much as the
/// degree-1 interpolation itself).
fn trusted(k: usize, t: Vec<f64>, dim: usize, c: Vec<f64>) -> Result<BsplineCurve> {
    crate::points::check_knots(&t, k, c.len() / dim)?;
    Ok(BsplineCurve::from_trusted(k, t, dim, c))
}

/// [`trusted`] for knots made here from x (checked: finite, strictly increasing) by copying
/// x and its ends ([`augmented_knots`], odd [`not_a_knot_knots`], k = 0 and 1) or by
/// midpoints of neighbours (even [`not_a_knot_knots`]): those knots are finite, sorted,
/// of the right count and span a finite interval whenever |x| < f64::MAX / 2 at both ends
/// (no midpoint or difference overflows), and are not checked again then (a pass over
/// them).
fn trusted_made(x: &[f64], k: usize, t: Vec<f64>, dim: usize, c: Vec<f64>) -> Result<BsplineCurve> {
    if x[0].abs().max(x[x.len() - 1].abs()) < f64::MAX / 2.0 {
        Ok(BsplineCurve::from_trusted(k, t, dim, c))
    } else {
        trusted(k, t, dim, c)
    }
}

/// The interpolating tensor-product spline of degrees (kx, ky) through heights z over the
/// grid x × y (`z` a row-major `rows × cols` matrix, `z[i * cols + j]` at (x_i, y_j)): SciPy's
/// `RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=0)`, whose FITPACK knots for s = 0 are the
/// not-a-knot knots of [`not_a_knot_knots`] in each direction; the coefficients solve the
/// two directions one after the other ([`make_interp_spline`] of x through the rows of z
/// as ny-dimensional points, then of y through the result's transpose), so C = A_x^-1 Z
/// A_y^-T exactly as the interpolation conditions ask. Errors in SciPy's words: "x must be
/// strictly increasing" (also y), "x dimension of z must have same number of elements as
/// x" (rows != len(x); also y and cols), non-finite values, fewer than k + 1 points in a
/// direction, and a z of other than rows × cols values ([`Error::BufferSize`]).
///
/// ```
/// use geomkit::bspline::make_interp_surface;
/// let (x, y) = ([0.0, 1.0, 2.0, 3.5], [0.0, 0.5, 1.0, 2.0, 3.0]);
/// let z: Vec<f64> = x.iter().flat_map(|a| y.iter().map(move |b| a * a - b)).collect();
/// let s = make_interp_surface(&x, &y, &z, (4, 5), (3, 2)).unwrap();
/// assert_eq!(s.degrees(), (3, 2));
/// assert!((s.eval(3.5, 2.0)[0] - (3.5 * 3.5 - 2.0)).abs() < 1e-13);
/// ```
pub fn make_interp_surface(
    x: &[f64],
    y: &[f64],
    z: &[f64],
    (rows, cols): (usize, usize),
    (kx, ky): (usize, usize),
) -> Result<super::BsplineSurface> {
    make_interp_surface_with_progress(x, y, z, (rows, cols), (kx, ky), &Progress::none())
}

/// [`make_interp_surface`] reporting to `progress` ([`crate::progress`]): the units are the
/// rows of the system along x, then the rows of the net solved along y (reported per block
/// of rows). The same surface, bit for bit, as without it; [`Error::Cancelled`] when the
/// callback asks to stop.
pub fn make_interp_surface_with_progress(
    x: &[f64],
    y: &[f64],
    z: &[f64],
    (rows, cols): (usize, usize),
    (kx, ky): (usize, usize),
    progress: &Progress,
) -> Result<super::BsplineSurface> {
    for (name, v) in [("x", x), ("y", y)] {
        if let Some(index) = crate::points::first_non_finite(v) {
            return Err(Error::NonFinite { what: name, index });
        }
        if let Some(i) = (1..v.len()).find(|&i| v[i] <= v[i - 1]) {
            return Err(interp(format!(
                "{name} must be strictly increasing: {name}[{i}] = {} after {name}[{}] = {}",
                v[i],
                i - 1,
                v[i - 1]
            )));
        }
    }
    let (nx, ny) = (x.len(), y.len());
    if z.len() != rows * cols {
        return Err(Error::BufferSize {
            expected: rows * cols,
            got: z.len(),
        });
    }
    for (name, n, got) in [("x", nx, rows), ("y", ny, cols)] {
        if got != n {
            return Err(interp(format!(
                "{name} dimension of z must have same number of elements as {name}: z is \
                 {rows} × {cols}, {name} has {n}"
            )));
        }
    }
    for (name, n, k) in [("x", nx, kx), ("y", ny, ky)] {
        if n <= k {
            return Err(interp(format!(
                "{n} values of {name} are too few for degree {k}: give at least {}, or lower \
                 the degree",
                k + 1
            )));
        }
    }
    if (kx, ky) == (3, 3) && nx >= 8 && ny >= 8 && nx * ny >= scipy_cubic::MIN_POINTS {
        progress.add_total(1)?;
        if let Some(s) = scipy_cubic::not_a_knot_bicubic(x, y, z, AMPLIFIED_TILES * max_abs(z)) {
            progress.finish()?;
            return Ok(s);
        }
    }
    // Along x: the rows of z as points of ny coordinates.
    let sx = interp_spline_parts(x, z, ny, &SplineOptions::new(kx), progress)?;
    let ncx = sx.n_control();
    progress.add_total(ncx as u64)?;
    let (tx, cx) = sx.into_parts();
    // Along y: every row of that net, in place (no transposes), else the transposed net as
    // points of ncx coordinates.
    let (ty, net) = match solve_along_rows(y, ky, cx, progress)? {
        AlongRows::Solved(ty, net) => (ty, net),
        AlongRows::Untouched(cx) => transposed_along_y(y, ky, &cx, ncx, progress)?,
        AlongRows::Refine => {
            let sx = make_interp_spline(x, z, ny, &SplineOptions::new(kx))?;
            progress.check()?;
            transposed_along_y(y, ky, sx.control_flat(), ncx, progress)?
        }
    };
    let ncy = net.len() / ncx;
    let s = super::BsplineSurface::from_flat((kx, ky), tx, ty, ncx, ncy, 1, net)?;
    progress.finish()?;
    Ok(s)
}

/// The second direction of [`make_interp_surface`] through [`make_interp_spline`]: the net
/// `cx` (ncx rows of ny numbers) transposed, interpolated along y as points of ncx
/// coordinates, and transposed back. Returns the knots and the net (ncx × ncy).
fn transposed_along_y(
    y: &[f64],
    ky: usize,
    cx: &[f64],
    ncx: usize,
    progress: &Progress,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let t = transpose(cx, ncx, y.len(), 1);
    let sy = make_interp_spline(y, &t, ncx, &SplineOptions::new(ky))?;
    progress.advance(ncx as u64)?;
    drop(t);
    let net = transpose(sy.control_flat(), sy.n_control(), ncx, 1);
    Ok((sy.into_parts().0, net))
}

/// What [`solve_along_rows`] did.
enum AlongRows {
    /// The knots along y and the net, solved.
    Solved(Vec<f64>, Vec<f64>),
    /// Not this case: the net, as given.
    Untouched(Vec<f64>),
    /// Solved but amplified (or overflowed): the net needs the refined general path, and is
    /// lost.
    Refine,
}

/// The second direction of [`make_interp_surface`] row by row: the not-a-knot system along
/// y factored once, each row of `net` (ny numbers) solved in place with it, rows in
/// parallel. The same operations on every number as [`make_interp_spline`] of the
/// transposed net (the same pivots, each coordinate solved alone), so the same bits; for
/// the cases where that solves the whole system once without refining it (degrees 2 to 7,
/// at most [`TILED_ROWS`] points, more than [`REFINE_ALWAYS`] numbers, coefficients within
/// [`AMPLIFIED`] times the data).
fn solve_along_rows(
    y: &[f64],
    k: usize,
    mut net: Vec<f64>,
    progress: &Progress,
) -> Result<AlongRows> {
    let n = y.len();
    if !(2..=MAX_SPLINE_DEGREE).contains(&k) || n > TILED_ROWS || net.len() <= REFINE_ALWAYS {
        return Ok(AlongRows::Untouched(net));
    }
    let t = not_a_knot_knots(y, k);
    // The matrix depends on the abscissae and knots only.
    let zeros = vec![0.0; n];
    let sys = OpenSystem::new(y, &zeros, 1, &t, k, &[], &[])?;
    let (a, _) = sys.window(0, sys.nt)?;
    let lu = a.factor_below(0.0).map_err(|_| singular())?;
    let scale = max_abs(&net);
    // Blocks of rows, one progress report each (each row is solved alone: same bits).
    let block = (REPORT_ROWS / n).max(1);
    net.par_chunks_mut(n * block).try_for_each(|rows| {
        rows.chunks_mut(n).for_each(|row| lu.solve(row, 1));
        progress.advance((rows.len() / n) as u64)
    })?;
    if max_abs(&net) > AMPLIFIED * scale {
        return Ok(AlongRows::Refine);
    }
    Ok(AlongRows::Solved(t, net))
}

/// Numbers of a net solved between two progress reports of [`solve_along_rows`].
const REPORT_ROWS: usize = 1 << 16;

/// The not-a-knot knots of degree k for the points x (module docs; SciPy's `_not_a_knot`).
/// For n < k + 1 points the inner part is empty (the knots then need end conditions).
pub fn not_a_knot_knots(x: &[f64], k: usize) -> Vec<f64> {
    let n = x.len();
    if k % 2 == 1 {
        let h = k.div_ceil(2);
        let inner = if n > 2 * h { &x[h..n - h] } else { &[] };
        knots_with_ends(x, k + 1, inner.len(), |j, out| {
            out.copy_from_slice(&inner[j..j + out.len()]);
        })
    } else {
        let h = k / 2;
        // Midpoints m_i = (x_i + x_(i+1))/2, i = h .. n - 1 - h.
        let count = (n - 1).saturating_sub(h).saturating_sub(h);
        knots_with_ends(x, k + 1, count, |j, out| {
            for (i, m) in (h + j..).zip(out) {
                *m = (x[i] + x[i + 1]) / 2.0;
            }
        })
    }
}

/// The knots for derivative end conditions: every x, the ends k + 1 fold (SciPy's
/// `_augknt`).
pub fn augmented_knots(x: &[f64], k: usize) -> Vec<f64> {
    knots_with_ends(x, k, x.len(), |j, out| {
        out.copy_from_slice(&x[j..j + out.len()]);
    })
}

/// Knots: x[0] `ends` times, `inner` knots from `fill(j, out)` (knots j.. into `out`), x's
/// last `ends` times. Long knot vectors are filled in parallel blocks.
fn knots_with_ends(
    x: &[f64],
    ends: usize,
    inner: usize,
    fill: impl Fn(usize, &mut [f64]) + Sync,
) -> Vec<f64> {
    const BLOCK: usize = 1 << 16;
    let mut t = crate::mem::zeros(inner + 2 * ends);
    let (head, rest) = t.split_at_mut(ends);
    let (body, tail) = rest.split_at_mut(inner);
    head.fill(x[0]);
    tail.fill(x[x.len() - 1]);
    if inner <= BLOCK {
        fill(0, body);
    } else {
        body.par_chunks_mut(BLOCK)
            .enumerate()
            .for_each(|(b, out)| fill(b * BLOCK, out));
    }
    t
}

/// The knots of a periodic spline of degree k through x (n + 2k knots; SciPy's
/// `_periodic_knots`): x itself (even k: the midpoints of x in place of its inner points)
/// at k.., continued beyond each end by the spacings of the other end.
pub fn periodic_knots(x: &[f64], k: usize) -> Vec<f64> {
    let n = x.len();
    let mut xc = x.to_vec();
    if k.is_multiple_of(2) {
        for i in 1..n - 1 {
            xc[i] = x[i] - (x[i] - x[i - 1]) / 2.0;
        }
    }
    let dx: Vec<f64> = xc.windows(2).map(|w| w[1] - w[0]).collect();
    let mut t = vec![0.0; n + 2 * k];
    t[k..k + n].copy_from_slice(&xc);
    let len = t.len();
    for i in 0..k {
        t[k - i - 1] = t[k - i] - dx[n - 2 - i % (n - 1)];
        t[len - k + i] = t[len - k + i - 1] + dx[i % (n - 1)];
    }
    t
}

pub(super) fn interp(reason: String) -> Error {
    Error::Interpolation { reason }
}

/// x finite, strictly increasing, one per point of y; y finite; at least 2 points. Returns
/// the largest magnitude in y (found on the same pass).
pub(super) fn check_data(x: &[f64], y: &[f64], dim: usize) -> Result<f64> {
    if dim == 0 {
        return Err(Error::ZeroDimension { what: "values y" });
    }
    if !y.len().is_multiple_of(dim) {
        return Err(interp(format!(
            "y has {} numbers, not a whole number of points of {dim} coordinates",
            y.len()
        )));
    }
    if x.len() != y.len() / dim {
        return Err(interp(format!(
            "Shapes of x ({},) and y ({}, {dim}) are incompatible: give one x per point",
            x.len(),
            y.len() / dim
        )));
    }
    if x.len() < 2 {
        return Err(Error::TooFewPoints {
            what: "data points",
            got: x.len(),
            min: 2,
        });
    }
    let (largest, finite) = scan(y);
    if finite && crate::points::finite_and_sorted(x, true) {
        return Ok(largest);
    }
    if let Some(i) = crate::points::first_non_finite(x) {
        return Err(Error::NonFinite {
            what: "x",
            index: i,
        });
    }
    if !finite {
        let i = crate::points::first_non_finite(y).expect("a number that is not finite");
        return Err(Error::NonFinite {
            what: "y",
            index: i / dim,
        });
    }
    if let Some(i) = (1..x.len()).find(|&i| x[i] == x[i - 1]) {
        return Err(interp(format!(
            "Expect x to not have duplicates: x[{}] = x[{i}] = {}; remove or merge the \
             repeated point",
            i - 1,
            x[i]
        )));
    }
    if let Some(i) = (1..x.len()).find(|&i| x[i] < x[i - 1]) {
        return Err(interp(format!(
            "Expect x to be a 1D strictly increasing sequence: x[{i}] = {} < x[{}] = {}; \
             sort the points by x",
            x[i],
            i - 1,
            x[i - 1]
        )));
    }
    Ok(largest)
}

/// SciPy's check of periodic data: `allclose(y[0], y[-1], atol=1e-15)` (rtol 1e-5).
fn check_closed(y: &[f64], dim: usize) -> Result<()> {
    if super::last_repeats_first(y, dim) {
        return Ok(());
    }
    let n = y.len() / dim;
    let (first, last) = (&y[..dim], &y[(n - 1) * dim..]);
    Err(interp(format!(
        "First and last points does not match while periodic case expected: y[0] = {first:?}, \
         y[{}] = {last:?}; end the data with the first point again (to within 1e-5 relative)",
        n - 1
    )))
}

/// Given knots: finite, sorted, at least n + k + 1, with x inside [t_k, t_(len-k)].
fn check_knots(t: &[f64], x: &[f64], k: usize) -> Result<()> {
    if let Some(i) = crate::points::first_non_finite(t) {
        return Err(Error::NonFinite {
            what: "knot",
            index: i,
        });
    }
    if let Some(i) = (1..t.len()).find(|&i| t[i] < t[i - 1]) {
        return Err(interp(format!(
            "Expect t to be a 1-D sorted array_like: knot {i} = {} < knot {} = {}",
            t[i],
            i - 1,
            t[i - 1]
        )));
    }
    let n = x.len();
    if t.len() < n + k + 1 {
        return Err(interp(format!(
            "Got {} knots, need at least {} (n + k + 1 for {n} points of degree {k})",
            t.len(),
            n + k + 1
        )));
    }
    if x[0] < t[k] || x[n - 1] > t[t.len() - k] {
        return Err(interp(format!(
            "Out of bounds w/ x: x spans [{}, {}], the knots' base interval [t[{k}], t[{}]] \
             is [{}, {}]",
            x[0],
            x[n - 1],
            t.len() - k,
            t[k],
            t[t.len() - k]
        )));
    }
    Ok(())
}

/// The derivative conditions of one end, values expanded to `dim` and checked.
pub(super) fn resolve_end(
    end: &EndSpec,
    x: &[f64],
    y: &[f64],
    dim: usize,
    k: usize,
    at_left: bool,
) -> Result<Vec<(usize, Vec<f64>)>> {
    let side = if at_left { "left" } else { "right" };
    let at = if at_left { x[0] } else { x[x.len() - 1] };
    Ok(match end {
        EndSpec::NotAKnot => Vec::new(),
        EndSpec::Bessel => {
            let n = x.len();
            let m = n.min(3);
            if at_left {
                vec![(1, bessel_tangent(&y[..m * dim], dim, &x[..m]))]
            } else {
                let pts: Vec<f64> = y[(n - m) * dim..]
                    .chunks_exact(dim)
                    .rev()
                    .flatten()
                    .copied()
                    .collect();
                let t: Vec<f64> = x[n - m..].iter().rev().map(|v| -v).collect();
                let d = bessel_tangent(&pts, dim, &t);
                vec![(1, d.iter().map(|v| -v).collect())]
            }
        }
        EndSpec::Derivatives(list) => list
            .iter()
            .map(|(order, value)| {
                if *order > k {
                    return Err(interp(format!(
                        "Bad boundary conditions at {at} ({side} end): derivative order \
                         {order} is above the degree {k}; give orders 0..={k}"
                    )));
                }
                let v = match value.len() {
                    1 => vec![value[0]; dim],
                    d if d == dim => value.clone(),
                    d => {
                        return Err(interp(format!(
                            "the {side} end's derivative of order {order} has {d} values: \
                             give one per coordinate ({dim}) or one for all"
                        )))
                    }
                };
                if v.iter().any(|a| !a.is_finite()) {
                    return Err(interp(format!(
                        "the {side} end's derivative of order {order} is not a finite number"
                    )));
                }
                Ok((*order, v))
            })
            .collect::<Result<_>>()?,
    })
}

/// The open system: nleft derivative rows at x_0, the n interpolation rows, nright
/// derivative rows at x_(n-1); banded with at most k sub- and super-diagonals. Large systems
/// are solved in overlapping windows in parallel ([`solve_tiled`]).
pub(super) fn solve_open(
    x: &[f64],
    y: &[f64],
    dim: usize,
    t: &[f64],
    k: usize,
    left: &[(usize, Vec<f64>)],
    right: &[(usize, Vec<f64>)],
    largest_y: f64,
    progress: &Progress,
) -> Result<Vec<f64>> {
    let n = x.len();
    let nt = t.len() - k - 1;
    let (nl, nr) = (left.len(), right.len());
    if nt != n + nl + nr {
        let fix = if nt > n + nl + nr {
            "add end conditions (e.g. \"natural\" or \"clamped\" at both ends), or lower the \
             degree"
        } else {
            "remove end conditions"
        };
        return Err(interp(format!(
            "The number of derivatives at boundaries does not match: expected {}, got {nl}+{nr} \
             ({nt} coefficients for degree {k} on these knots, {n} points): {fix}",
            nt as isize - n as isize
        )));
    }
    let sys = OpenSystem::new(x, y, dim, t, k, left, right)?;
    progress.add_total(nt as u64)?;
    if nt > TILED_ROWS {
        let (c, (big, finite)) = solve_tiled(&sys, TILE_ROWS, TILE_HALO, progress)?;
        // Ill-conditioned (coefficients far above the data), or without decay (the seams
        // do not hold): the whole system, refined.
        let scale = sys.ends_scale().max(largest_y);
        if finite && big <= AMPLIFIED_TILES * scale && seams_hold(&sys, &c, TILE_ROWS)? {
            return Ok(c);
        }
    }
    let c = solve_refined(|| sys.window(0, nt), dim)?;
    check_finite_coefficients(&c, dim)?;
    progress.advance(nt as u64)?;
    Ok(c)
}

/// Windowed coefficients more than this many times the data mark a system too
/// ill-conditioned to keep them (rounding grows with them): the whole system is then solved
/// and refined. (Uneven data make quadratics' coefficients ~16 times the data.)
pub(super) const AMPLIFIED_TILES: f64 = 1e3;

/// Systems of more rows than this are solved in windows ([`solve_tiled`]).
const TILED_ROWS: usize = 1 << 16;
/// Rows a window owns.
const TILE_ROWS: usize = 1 << 14;
/// Rows solved on each side of a window and discarded: the influence of a row on the
/// coefficients decays like λ^d with the distance d, λ the largest root modulus of the
/// B-spline collocation symbol (0.17 for k = 2, 0.27 for 3, 0.43 for 5, 0.54 for 7 on
/// uniform data); 0.54^64 < 1e-17.
pub(super) const TILE_HALO: usize = 64;

/// The rows of an open interpolation system ([`solve_open`]), produced for any window.
pub(super) struct OpenSystem<'a> {
    x: &'a [f64],
    y: &'a [f64],
    dim: usize,
    t: &'a [f64],
    k: usize,
    nt: usize,
    nl: usize,
    /// The derivative rows (left, then right): first column, entries, right-hand side.
    ends: Vec<(usize, [f64; 8], Vec<f64>)>,
}

impl<'a> OpenSystem<'a> {
    pub(super) fn new(
        x: &'a [f64],
        y: &'a [f64],
        dim: usize,
        t: &'a [f64],
        k: usize,
        left: &[(usize, Vec<f64>)],
        right: &[(usize, Vec<f64>)],
    ) -> Result<Self> {
        let (n, nt) = (x.len(), t.len() - k - 1);
        let mut ends = Vec::with_capacity(left.len() + right.len());
        // Derivative rows in the units of the end interval h (scaled by 2^(e ν) with 2^e
        // the power of two nearest h: exact, and for h near 1 SciPy's rows bit for bit):
        // formed on the knots scaled by 2^-e, where d/dx = 2^-e d/dx'. Unscaled, entries
        // ~ 1/h^ν overflow for h = 1e-50 and decide the pivots for h = 1e-5; scaled by
        // their largest entry instead, they let partial pivoting pick rows that lose digits
        // in the ill-conditioned systems of conditions all at one end.
        for (first_row, at, h, conds) in [
            (0, x[0], x[1] - x[0], left),
            (left.len() + n, x[n - 1], x[n - 1] - x[n - 2], right),
        ] {
            let l = find_span(t, k, nt, at);
            let e = (h.log2().round() as i32).clamp(-1000, 1000);
            let s = 2f64.powi(-e);
            // t[l-k ..= l+k+1] scaled; |t|/h < 2^53, so no scaled knot overflows.
            let local: Vec<f64> = t[l - k..=l + k + 1].iter().map(|v| v * s).collect();
            for (r, (order, value)) in conds.iter().enumerate() {
                check_band(first_row + r, l, k, || format!("the end condition at {at}"))?;
                let ders = basis_funs_derivs(&local, k, at * s, k, *order);
                let rhs = value
                    .iter()
                    .map(|v| (0..*order).fold(*v, |acc, _| acc * 2f64.powi(e)))
                    .collect();
                ends.push((l - k, ders[*order], rhs));
            }
        }
        Ok(OpenSystem {
            x,
            y,
            dim,
            t,
            k,
            nt,
            nl: left.len(),
            ends,
        })
    }

    /// The largest right-hand side entry (data and derivative values).
    pub(super) fn rhs_scale(&self) -> f64 {
        self.ends_scale().max(max_abs(self.y))
    }

    /// The largest derivative value of the end conditions.
    fn ends_scale(&self) -> f64 {
        self.ends.iter().fold(0.0, |m, e| m.max(max_abs(&e.2)))
    }

    /// Row r: its first column and k + 1 entries, its right-hand side written to `rhs`;
    /// `span` carries the knot interval of the previous data row (a walk from it; a search
    /// when `None`).
    fn row(
        &self,
        r: usize,
        span: &mut Option<usize>,
        rhs: &mut [f64],
    ) -> Result<(usize, [f64; 8])> {
        let (k, n) = (self.k, self.x.len());
        if r < self.nl || r >= self.nl + n {
            let e = &self.ends[if r < self.nl { r } else { r - n }];
            rhs.copy_from_slice(&e.2);
            return Ok((e.0, e.1));
        }
        self.data_row(r, k, span, rhs)
    }

    /// [`OpenSystem::row`] of data row r, for degree `k` (= self.k; a compile-time constant
    /// in [`OpenSystem::solve_collocation_k`], which measured a little faster than the
    /// run-time degree: k = 2, 10^6 points, two threads, three runs each 47-58 against 55-74
    /// ms).
    #[inline(always)]
    fn data_row(
        &self,
        r: usize,
        k: usize,
        span: &mut Option<usize>,
        rhs: &mut [f64],
    ) -> Result<(usize, [f64; 8])> {
        let dim = self.dim;
        let i = r - self.nl;
        let xi = self.x[i];
        // The knot interval t_l <= x_i < t_(l+1) (at the right end the last non-empty one).
        let l = match *span {
            None => find_span(self.t, k, self.nt, xi),
            Some(from) => find_span_from(self.t, k, self.nt, xi, from),
        };
        *span = Some(l);
        check_band(r, l, k, || format!("x[{i}] = {xi}"))?;
        let mut basis = [0.0f64; 8];
        basis_funs(self.t, l, xi, k, &mut basis[..=k]);
        rhs.copy_from_slice(&self.y[i * dim..(i + 1) * dim]);
        Ok((l - k, basis))
    }

    /// Whether the residual of row r for the coefficients `c` is within rounding (64 ε of
    /// the sizes it sums): the check of the seams of [`solve_tiled`].
    fn row_holds(&self, r: usize, c: &[f64]) -> Result<bool> {
        let dim = self.dim;
        let mut rhs = vec![0.0; dim];
        let (first, e) = self.row(r, &mut None, &mut rhs)?;
        Ok((0..dim).all(|d| {
            let (mut sum, mut size) = (-rhs[d], rhs[d].abs());
            for (j, a) in e[..=self.k].iter().enumerate() {
                let v = a * c[(first + j) * dim + d];
                sum += v;
                size += v.abs();
            }
            sum.abs() <= 64.0 * f64::EPSILON * size
        }))
    }

    /// Rows r0..r1 and their columns r0..r1 (entries beyond dropped: those coefficients
    /// held at zero, the windows' artificial ends) as a band matrix as narrow as the rows
    /// allow, with the right-hand sides. Errors: a data point whose knot interval does not
    /// suit its row ([`check_band`]).
    pub(super) fn window(&self, r0: usize, r1: usize) -> Result<(BandMatrix, Vec<f64>)> {
        let (k, dim) = (self.k, self.dim);
        let m = r1 - r0;
        // Each row's entries and the columns lo..=hi of its nonzero ones inside the window.
        let mut rows: Vec<(usize, usize, usize, [f64; 8])> = Vec::with_capacity(m);
        let mut rhs = vec![0.0; m * dim];
        let (mut l, mut kl, mut ku) = (None, 0, 0);
        for r in r0..r1 {
            let (first, e) = self.row(r, &mut l, &mut rhs[(r - r0) * dim..(r - r0 + 1) * dim])?;
            let (mut lo, mut hi) = (first.max(r0), (first + k).min(r1 - 1));
            while lo < hi && e[lo - first] == 0.0 {
                lo += 1;
            }
            while hi > lo && e[hi - first] == 0.0 {
                hi -= 1;
            }
            // The narrowest band holding the nonzero entries inside the window.
            if lo <= hi {
                kl = kl.max(r.saturating_sub(lo));
                ku = ku.max(hi.saturating_sub(r));
            }
            rows.push((first, lo, hi, e));
        }
        let mut a = BandMatrix::zeros(m, kl, ku);
        for (r, &(first, lo, hi, e)) in (r0..r1).zip(&rows) {
            for c in lo..=hi {
                a.set(r - r0, c - r0, e[c - first]);
            }
        }
        Ok((a, rhs))
    }
}

/// The coefficients of `sys` from windows of `tile` rows, each solved with `halo` more rows
/// on each side (discarded), in parallel: equal to the whole system's solution within
/// rounding where the influence decays over the halo ([`TILE_HALO`]). Memory: a few windows'
/// bands, never the whole system's. Also returns [`scan`] of the coefficients (each part
/// scanned while it is in cache).
fn solve_tiled(
    sys: &OpenSystem,
    tile: usize,
    halo: usize,
    progress: &Progress,
) -> Result<(Vec<f64>, (f64, bool))> {
    let (nt, dim) = (sys.nt, sys.dim);
    let mut out = crate::mem::zeros(nt * dim);
    let chunk = WINDOWS * tile * dim;
    let mut scans = vec![(0.0, true); out.len().div_ceil(chunk)];
    // WINDOWS windows per task: their eliminations overlap
    // ([`OpenSystem::solve_collocations`]).
    out.par_chunks_mut(chunk)
        .zip(scans.par_iter_mut())
        .enumerate()
        .try_for_each_init(
            Spare::default,
            |spare, (w, (part, scanned))| -> Result<()> {
                let a0 = WINDOWS * w * tile;
                let a1 = a0 + part.len() / dim;
                solve_windows(sys, a0, a1, tile, halo, part, spare)?;
                *scanned = scan_block(part);
                progress.advance((a1 - a0) as u64)
            },
        )?;
    let scanned = scans
        .into_iter()
        .fold((0.0f64, true), |a, b| (a.0.max(b.0), a.1 && b.1));
    Ok((out, scanned))
}

/// Windows of [`solve_tiled`] solved together by one task.
const WINDOWS: usize = 2;

/// The coefficients a0..a1 of `sys` into `part`, in windows of `tile` rows (up to
/// [`WINDOWS`]), each from the window with `halo` more rows on each side; buffers from
/// `spare`.
fn solve_windows(
    sys: &OpenSystem,
    a0: usize,
    a1: usize,
    tile: usize,
    halo: usize,
    part: &mut [f64],
    spare: &mut Spare,
) -> Result<()> {
    let dim = sys.dim;
    let owned: [(usize, usize); WINDOWS] =
        std::array::from_fn(|w| ((a0 + w * tile).min(a1), (a0 + (w + 1) * tile).min(a1)));
    let rows = owned.map(|(a, b)| (a.saturating_sub(halo), (b + halo).min(sys.nt)));
    let fast: [bool; WINDOWS] = std::array::from_fn(|w| {
        owned[w].0 < owned[w].1 && sys.collocation_only(rows[w].0, rows[w].1)
    });
    let mut parts: [&mut [f64]; WINDOWS] = Default::default();
    let mut rest = part;
    for (w, p) in parts.iter_mut().enumerate() {
        let (head, tail) = rest.split_at_mut((owned[w].1 - owned[w].0) * dim);
        (*p, rest) = (head, tail);
    }
    let own = |w: usize| owned[w].0 - rows[w].0..owned[w].1 - rows[w].0;
    let mut solved = [false; WINDOWS];
    if fast == [true; WINDOWS] {
        let mut w = 0..WINDOWS;
        let outs = parts.each_mut().map(|out| Solution {
            rows: own(w.next().expect("one per window")),
            out,
        });
        solved = sys.solve_collocations(rows, outs, spare)?;
    } else {
        for w in (0..WINDOWS).filter(|&w| fast[w]) {
            let out = Solution {
                rows: own(w),
                out: &mut *parts[w],
            };
            solved[w] = sys.solve_collocations([rows[w]], [out], spare)?[0];
        }
    }
    for (w, out) in parts.into_iter().enumerate() {
        let ((a, b), (r0, r1)) = (owned[w], rows[w]);
        if a == b || solved[w] {
            continue;
        }
        let (m, mut s) = sys.window(r0, r1)?;
        m.factor_below(0.0)
            .map_err(|_| singular())?
            .solve(&mut s, dim);
        out.copy_from_slice(&s[(a - r0) * dim..(b - r0) * dim]);
    }
    Ok(())
}

/// A pivot below this fraction of its row's largest entry sends a window of
/// [`OpenSystem::solve_collocation`] back to the pivoting solve (in exact arithmetic the
/// pivots of a nonsingular totally positive matrix are positive; a tiny one means the
/// window is near singular, where pivoting is the safer judge).
const TP_PIVOT: f64 = 1e-8;

impl OpenSystem<'_> {
    /// Whether rows r0..r1 are all data rows (no end condition): a window of the
    /// collocation matrix.
    pub(super) fn collocation_only(&self, r0: usize, r1: usize) -> bool {
        r0 >= self.nl && r1 <= self.nl + self.x.len()
    }

    /// Solves the window r0..r1 of data rows ([`OpenSystem::window`]'s system) in one pass
    /// that assembles each row and eliminates it at once, then a back substitution: Gaussian
    /// elimination without pivoting, which is stable on the collocation matrix because it is
    /// totally positive (de Boor & Pinkus 1977: no growth of entries) and so is every square
    /// window of it. Its U has the band of the rows (k + 1 entries from the diagonal) and
    /// nothing else is stored. `None` when a pivot is not clearly positive
    /// ([`TP_PIVOT`]): the caller then pivots.
    pub(super) fn solve_collocation(&self, r0: usize, r1: usize) -> Result<Option<Vec<f64>>> {
        let mut out = vec![0.0; (r1 - r0) * self.dim];
        let to = Solution {
            rows: 0..r1 - r0,
            out: &mut out,
        };
        let [solved] = self.solve_collocations([(r0, r1)], [to], &mut Spare::default())?;
        Ok(solved.then_some(out))
    }

    /// [`OpenSystem::solve_collocation`] of several windows at once (faster than one after
    /// the other: their rows' eliminations overlap), each window's rows `outs[w].rows`
    /// written to `outs[w].out`, with buffers from `spare`; false for a window whose pivots
    /// failed (nothing written).
    pub(super) fn solve_collocations<const S: usize>(
        &self,
        windows: [(usize, usize); S],
        outs: [Solution<'_>; S],
        spare: &mut Spare,
    ) -> Result<[bool; S]> {
        match self.k {
            1 => self.solve_collocation_k::<1, S>(windows, outs, spare),
            2 => self.solve_collocation_k::<2, S>(windows, outs, spare),
            3 => self.solve_collocation_k::<3, S>(windows, outs, spare),
            4 => self.solve_collocation_k::<4, S>(windows, outs, spare),
            5 => self.solve_collocation_k::<5, S>(windows, outs, spare),
            6 => self.solve_collocation_k::<6, S>(windows, outs, spare),
            7 => self.solve_collocation_k::<7, S>(windows, outs, spare),
            _ => Ok([false; S]),
        }
    }
}

/// Whether the rows next to the seams of [`solve_tiled`]'s windows hold for `c` (within
/// each window the rows hold by construction; across a seam only where the influence
/// decayed over the halo, which it does not for systems without decay, such as even
/// degrees on knots at the data: an error of neighbouring windows shows there).
pub(super) fn seams_hold(sys: &OpenSystem, c: &[f64], tile: usize) -> Result<bool> {
    let k = sys.k;
    let seams: Vec<usize> = (1..sys.nt.div_ceil(tile)).map(|w| w * tile).collect();
    for s in seams {
        for r in s.saturating_sub(k + 1)..(s + k + 1).min(sys.nt) {
            if !sys.row_holds(r, c)? {
                return Ok(false);
            }
        }
    }
    Ok(true)
}

/// Coefficients more than this many times the right-hand side's largest entry mark an
/// ill-conditioned system (interpolation proper gives coefficients near the data), which
/// [`solve_refined`] then refines.
const AMPLIFIED: f64 = 8.0;

/// Systems with at most this many right-hand side entries are refined in any case.
const REFINE_ALWAYS: usize = 1 << 16;

/// Refinement steps at most.
const REFINE_STEPS: usize = 40;

/// Solves A X = B by banded LU with partial pivoting; for small systems, and where X came
/// out much larger than B (conditions all at one end: the system is ill-conditioned and a
/// solve loses up to log10(cond) digits), refines X by iterative refinement with residuals in doubled
/// precision ([`BandMatrix::residual`]) until the correction is below 1e-15 of X, which
/// recovers the digits lost while cond · ε < 1. A system beyond that (the correction does
/// not shrink) is refused as singular: an answer without correct digits is not returned.
///
/// `system` gives A and B; a large B is solved in place and asked for again only if X needs
/// refining (no copy of a right-hand side of 10^8 numbers in the usual case).
fn solve_refined(
    system: impl Fn() -> Result<(BandMatrix, Vec<f64>)>,
    dim: usize,
) -> Result<Vec<f64>> {
    let (a, b) = system()?;
    // Only exact zero pivots are refused here: refinement judges the rest.
    let lu = a.clone().factor_below(0.0).map_err(|_| singular())?;
    // Small systems are always refined (it costs less than the solve); large ones when
    // amplified.
    let (mut x, b) = if b.len() > REFINE_ALWAYS {
        let scale = max_abs(&b);
        let mut x = b;
        lu.solve(&mut x, dim);
        if max_abs(&x) <= AMPLIFIED * scale {
            return Ok(x);
        }
        (x, system()?.1)
    } else {
        let mut x = b.clone();
        lu.solve(&mut x, dim);
        (x, b)
    };
    let mut last = f64::INFINITY;
    for _ in 0..REFINE_STEPS {
        let mut d = a.residual(&x, &b, dim);
        lu.solve(&mut d, dim);
        for (v, e) in x.iter_mut().zip(&d) {
            *v += e;
        }
        let step = max_abs(&d);
        if step <= 1e-15 * max_abs(&x) {
            return Ok(x);
        }
        if step.is_nan() || step >= 0.5 * last {
            break;
        }
        last = step;
    }
    Err(interp(
        "the interpolation system is too ill-conditioned for f64 (iterative refinement does \
         not converge): conditions all at one end, or knots far from the points; split the \
         end conditions between the ends or lower the degree"
            .into(),
    ))
}

pub(super) fn max_abs(v: &[f64]) -> f64 {
    scan(v).0
}

/// The largest magnitude of the finite numbers of `v`, and whether all are finite, in one
/// pass: sixteen lanes (SIMD maxima and sums of 0·x, NaN exactly for infinities and NaN;
/// four independent chains of each, compiled for AVX2 where the CPU has it) per chunk,
/// chunks in parallel; a pass over 10^7 points costs what reading them does.
fn scan(v: &[f64]) -> (f64, bool) {
    v.par_chunks(1 << 16)
        .map(scan_block)
        .reduce_with(|a, b| (a.0.max(b.0), a.1 && b.1))
        .unwrap_or((0.0, true))
}

/// [`scan`] of one block, on the calling thread.
fn scan_block(c: &[f64]) -> (f64, bool) {
    #[inline(always)]
    fn chunk(c: &[f64]) -> (f64, bool) {
        let (mut lanes, mut zeros) = ([0.0f64; 16], [0.0f64; 16]);
        let mut blocks = c.chunks_exact(16);
        for q in &mut blocks {
            for ((m, z), x) in lanes.iter_mut().zip(&mut zeros).zip(q) {
                *m = if x.abs() > *m { x.abs() } else { *m };
                *z += 0.0 * x;
            }
        }
        let rest = blocks.remainder();
        let m = rest
            .iter()
            .chain(&lanes)
            .fold(0.0f64, |m, x| if x.abs() > m { x.abs() } else { m });
        let z = rest.iter().chain(&zeros).fold(0.0, |a, x| a + 0.0 * x);
        (m, z == 0.0)
    }
    let mut out = (0.0, true);
    with_avx2(
        #[inline(always)]
        || out = chunk(c),
    );
    out
}

/// [`find_span`] for x at or after the knot interval `from` (the points increase: a walk
/// over the knots, O(n) for all points).
fn find_span_from(t: &[f64], k: usize, nt: usize, x: f64, from: usize) -> usize {
    if x >= t[nt] {
        return find_span(t, k, nt, x);
    }
    let mut l = from;
    while l + 1 < nt && t[l + 1] <= x {
        l += 1;
    }
    l
}

/// Row r of a system with k sub- and super-diagonals can hold the k + 1 B-splines of knot
/// interval l (columns l - k ..= l) when r <= l <= r + k; else the knots do not suit the
/// points (`what`: the row's point, for the message).
#[inline]
fn check_band(r: usize, l: usize, k: usize, what: impl FnOnce() -> String) -> Result<()> {
    if l < r || l > r + k {
        return Err(interp(format!(
            "the knots do not suit x: {} lies in the knot interval [t[{l}], t[{}]), which \
             puts its row outside the band of the collocation matrix (the Schoenberg–Whitney \
             condition fails); place about one knot per point",
            what(),
            l + 1
        )));
    }
    Ok(())
}

pub(super) fn singular() -> Error {
    interp(
        "the collocation matrix is singular: the knots do not suit x (the Schoenberg–Whitney \
         condition), or the end conditions repeat one another"
            .into(),
    )
}

/// Systems of at most this many unknowns are solved densely (periodic splines).
const DENSE_PERIODIC: usize = 64;

/// The periodic system (SciPy's `_make_periodic_spline`): n - 1 unknowns d_j, the
/// coefficients c_j = d_((j - k/2) mod (n - 1)); few points (n <= k) as SciPy, by the full
/// system with the k - 1 derivative continuity rows.
fn solve_periodic(x: &[f64], y: &[f64], dim: usize, t: &[f64], k: usize) -> Result<Vec<f64>> {
    let n = x.len();
    let nt = n + k - 1;
    if n <= k {
        return solve_periodic_full(x, y, dim, t, k);
    }
    let m = n - 1;
    let half = k / 2;
    let mut basis = [0.0f64; 8];
    // Row i: (column, value) of the cyclic matrix.
    let mut entries: Vec<(usize, usize, f64)> = Vec::with_capacity(m * (k + 1));
    let mut l = k;
    for (i, &xi) in x[..m].iter().enumerate() {
        l = find_span_from(t, k, nt, xi, l);
        basis_funs(t, l, xi, k, &mut basis[..=k]);
        for (r, v) in basis[..=k].iter().enumerate() {
            let j = (l - k + r) as isize - half as isize;
            entries.push((i, j.rem_euclid(m as isize) as usize, *v));
        }
    }
    let rhs = &y[..m * dim];
    let d = if m <= DENSE_PERIODIC {
        dense_solve(m, &entries, rhs, dim)?
    } else {
        cyclic_band_solve(m, k, &entries, rhs, dim)?
    };
    let mut c = vec![0.0; nt * dim];
    for j in 0..nt {
        let q = (j as isize - half as isize).rem_euclid(m as isize) as usize;
        c[j * dim..(j + 1) * dim].copy_from_slice(&d[q * dim..(q + 1) * dim]);
    }
    Ok(c)
}

/// SciPy's `_make_interp_per_full_matr`: rows 0..k-1 equate the derivatives of orders
/// 1..k-1 at x_0 and x_(n-1), rows k-1.. interpolate; dense (n <= k).
fn solve_periodic_full(x: &[f64], y: &[f64], dim: usize, t: &[f64], k: usize) -> Result<Vec<f64>> {
    let n = x.len();
    let nt = n + k - 1;
    let mut entries = Vec::new();
    for i in 0..k - 1 {
        let at0 = basis_funs_derivs(t, k, x[0], k, i + 1);
        for (j, v) in at0[i + 1][..=k].iter().enumerate() {
            entries.push((i, j, *v));
        }
        let at1 = basis_funs_derivs(t, nt, x[n - 1], k, i + 1);
        for (j, v) in at1[i + 1][..k].iter().enumerate() {
            entries.push((i, nt - k + j, -v));
        }
    }
    let mut basis = [0.0f64; 8];
    for (i, &xi) in x.iter().enumerate() {
        let l = if xi == t[k] {
            k
        } else {
            t.partition_point(|&v| v < xi) - 1
        };
        basis_funs(t, l, xi, k, &mut basis[..=k]);
        for (j, v) in basis[..=k].iter().enumerate() {
            entries.push((k - 1 + i, l - k + j, *v));
        }
    }
    let mut rhs = vec![0.0; nt * dim];
    rhs[(k - 1) * dim..].copy_from_slice(y);
    dense_solve(nt, &entries, &rhs, dim)
}

/// Solves the m × m system given by `entries` (row, column, value; repeated entries add)
/// for the row-major right-hand sides `rhs` (m × dim), by LU with partial pivoting.
fn dense_solve(
    m: usize,
    entries: &[(usize, usize, f64)],
    rhs: &[f64],
    dim: usize,
) -> Result<Vec<f64>> {
    let mut a = nalgebra::DMatrix::<f64>::zeros(m, m);
    for &(i, j, v) in entries {
        a[(i, j)] += v;
    }
    let b = nalgebra::DMatrix::from_row_slice(m, dim, rhs);
    let sol = a.lu().solve(&b).ok_or_else(singular)?;
    let mut out = vec![0.0; m * dim];
    for i in 0..m {
        for c in 0..dim {
            out[i * dim + c] = sol[(i, c)];
        }
    }
    Ok(out)
}

/// A cyclic band system: the entries within k of the diagonal form a band matrix B, the
/// wrapped ones (corner blocks) a low-rank part U V^T with one column of U per row that
/// holds any; A^-1 y = B^-1 y - Z (I + V^T Z)^-1 V^T B^-1 y with Z = B^-1 U (Woodbury).
fn cyclic_band_solve(
    m: usize,
    k: usize,
    entries: &[(usize, usize, f64)],
    rhs: &[f64],
    dim: usize,
) -> Result<Vec<f64>> {
    let mut band = BandMatrix::zeros(m, k, k);
    let mut corner: Vec<(usize, usize, f64)> = Vec::new();
    for &(i, j, v) in entries {
        if i.abs_diff(j) <= k {
            band.add(i, j, v);
        } else {
            corner.push((i, j, v));
        }
    }
    let lu = band.factor().map_err(|_| singular())?;
    let mut rows: Vec<usize> = corner.iter().map(|c| c.0).collect();
    rows.dedup();
    let r = rows.len();
    let mut u = rhs.to_vec();
    lu.solve(&mut u, dim);
    if r == 0 {
        return Ok(u);
    }
    // Z = B^-1 E_rows (m × r, row-major).
    let mut z = vec![0.0; m * r];
    for (a, &row) in rows.iter().enumerate() {
        z[row * r + a] = 1.0;
    }
    lu.solve(&mut z, r);
    // S = I + V^T Z (r × r) and V^T u (r × dim); V^T's row a holds the corner entries of
    // rows[a].
    let mut s = nalgebra::DMatrix::<f64>::identity(r, r);
    let mut w = nalgebra::DMatrix::<f64>::zeros(r, dim);
    for &(i, j, v) in &corner {
        let a = rows.binary_search(&i).expect("a corner row");
        for b in 0..r {
            s[(a, b)] += v * z[j * r + b];
        }
        for c in 0..dim {
            w[(a, c)] += v * u[j * dim + c];
        }
    }
    let sw = s.lu().solve(&w).ok_or_else(singular)?;
    for i in 0..m {
        for c in 0..dim {
            let mut acc = 0.0;
            for b in 0..r {
                acc += z[i * r + b] * sw[(b, c)];
            }
            u[i * dim + c] -= acc;
        }
    }
    Ok(u)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Windows of 200 rows with the default halo give the whole system's coefficients
    /// within 1e-14 of their scale, for every degree, on uneven data (spacings from 0.05 to
    /// 1.95, one interval 1/100 of its neighbours), with derivative conditions split
    /// between the ends and not-a-knot.
    #[test]
    fn surfaces_solved_row_by_row_have_the_bits_of_the_transposed_solve() {
        let (rows, cols) = (300, 250);
        let x: Vec<f64> = (0..rows).map(|i| (i as f64).powf(1.1)).collect();
        let y: Vec<f64> = (0..cols)
            .map(|j| j as f64 * 0.37 + (j % 3) as f64 * 0.05)
            .collect();
        let z: Vec<f64> = (0..rows * cols)
            .map(|k| {
                let (i, j) = ((k / cols) as f64, (k % cols) as f64);
                (0.05 * i).sin() * (0.07 * j).cos() + ((k * 2654435761) % 1000) as f64 * 1e-6
            })
            .collect();
        // (The bicubic of this size takes the extended form's path, `scipy_cubic.rs`; its
        // rows are checked here all the same.)
        for (kx, ky) in [(3, 3), (2, 5), (5, 2), (7, 4)] {
            let sx = make_interp_spline(&x, &z, cols, &SplineOptions::new(kx)).unwrap();
            let (ty, net) =
                transposed_along_y(&y, ky, sx.control_flat(), sx.n_control(), &Progress::none())
                    .unwrap();
            let AlongRows::Solved(t, along) =
                solve_along_rows(&y, ky, sx.control_flat().to_vec(), &Progress::none()).unwrap()
            else {
                panic!("({kx}, {ky}) not solved row by row");
            };
            assert_eq!(t, ty);
            if (kx, ky) != (3, 3) {
                let s = make_interp_surface(&x, &y, &z, (rows, cols), (kx, ky)).unwrap();
                assert_eq!(s.control_flat(), &along[..], "({kx}, {ky})");
            }
            let same = along
                .iter()
                .zip(&net)
                .all(|(a, b)| a.to_bits() == b.to_bits());
            assert!(same, "({kx}, {ky})");
        }
    }

    #[test]
    fn windows_equal_the_whole_system() {
        let mut seed = 7u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 3000;
        let mut x = vec![0.0];
        for i in 1..n {
            let h = if i == 1700 {
                0.01
            } else {
                0.05 + 1.9 * uniform()
            };
            x.push(x[i - 1] + h);
        }
        let y: Vec<f64> = x
            .iter()
            .flat_map(|&v| [(0.3 * v).sin() + 0.1 * uniform(), (0.01 * v * v).cos()])
            .collect();
        let mut refused = 0;
        for k in 2..=MAX_SPLINE_DEGREE {
            let split = (k - 1) / 2;
            let conds = |m: usize, v: f64| (1..=m).map(|o| (o, vec![v, -v])).collect::<Vec<_>>();
            for (left, right, t) in [
                (vec![], vec![], not_a_knot_knots(&x, k)),
                (
                    conds(split, 0.5),
                    conds(k - 1 - split, 0.25),
                    augmented_knots(&x, k),
                ),
            ] {
                let sys = OpenSystem::new(&x, &y, 2, &t, k, &left, &right).unwrap();
                let whole = solve_refined(|| sys.window(0, sys.nt), 2).unwrap();
                let (tiled, scanned) =
                    solve_tiled(&sys, 200, TILE_HALO, &Progress::none()).unwrap();
                assert_eq!(scanned, scan(&tiled), "k {k}: the parts' scans");
                // Every degree's not-a-knot system decays (even degrees: knots between the
                // data); derivative conditions on knots at the data do not for even degrees:
                // the seams show it, and the whole system is solved instead (as it is for
                // coefficients far above the data: here the short interval makes them so
                // for degree 7).
                if !seams_hold(&sys, &tiled, 200).unwrap() {
                    assert!(!right.is_empty() && k % 2 == 0, "k {k}: seams fail");
                    refused += 1;
                    continue;
                }
                if max_abs(&tiled) > AMPLIFIED_TILES * sys.rhs_scale() {
                    continue;
                }
                let scale = max_abs(&whole);
                let err = whole
                    .iter()
                    .zip(&tiled)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(err <= 1e-14 * scale, "k {k}: {err:e} (scale {scale:e})");
            }
        }
        assert_eq!(refused, 3, "even degrees with derivative conditions");
    }

    /// Windows of data rows solved without pivoting ([`OpenSystem::solve_collocation`])
    /// equal the pivoting band solve of the same window within rounding, for every degree,
    /// on uneven data with a 20x jump of the spacing.
    #[test]
    fn collocation_windows_need_no_pivoting() {
        let x: Vec<f64> = (0..2000)
            .map(|i| {
                let i = i as f64;
                i + 0.4 * (1.7 * i).sin() + if i > 900.0 { 19.0 * (i - 900.0) } else { 0.0 }
            })
            .collect();
        let y: Vec<f64> = x
            .iter()
            .flat_map(|&v| [(0.3 * v).sin(), 1.0 / (1.0 + v)])
            .collect();
        for k in 1..=MAX_SPLINE_DEGREE {
            let split = (k - 1) / 2;
            let conds = |m: usize| (1..=m).map(|o| (o, vec![1.0, -1.0])).collect::<Vec<_>>();
            for (left, right, t) in [
                (vec![], vec![], not_a_knot_knots(&x, k)),
                (conds(split), conds(k - 1 - split), augmented_knots(&x, k)),
            ] {
                let sys = OpenSystem::new(&x, &y, 2, &t, k, &left, &right).unwrap();
                for (r0, r1) in [(700, 1300), (10, 1990), (899, 902)] {
                    assert!(sys.collocation_only(r0, r1));
                    let fast = sys
                        .solve_collocation(r0, r1)
                        .unwrap()
                        .expect("positive pivots");
                    let (a, mut b) = sys.window(r0, r1).unwrap();
                    a.factor_below(0.0).unwrap().solve(&mut b, 2);
                    let scale = max_abs(&b);
                    let err = b
                        .iter()
                        .zip(&fast)
                        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    assert!(
                        err <= 1e-13 * scale,
                        "k {k} {r0}..{r1}: {err:e} of {scale:e}"
                    );
                }
            }
        }
    }
}
