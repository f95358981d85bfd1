//! Interpolating cubic B-spline curves through reference points (spec/bspline-interpolation.md
//! §2 and §6): the paper's method with its repeated end points, and the end conditions and
//! parametrizations users expect, all solved as banded systems in O(N).
//!
//! Formulation: for parameters t_0 < ... < t_(N-1) the curve is a cubic B-spline on the knots
//! t_i, extended by three knots beyond each end, with N+2 control points c_0..c_(N+1) (the
//! paper's p_(-1)..p_N). Interpolation at t_i couples c_i, c_(i+1), c_(i+2) (for uniform
//! parameters: (p_(i-1) + 4 p_i + p_(i+1)) / 6 = k_i, the paper's rows); the end condition
//! adds one row at each end. Ordered [start row, interpolation rows, end row] the open system
//! is tridiagonal plus its two end rows: Thomas sweeps and a rank-2 Woodbury correction
//! (`tridiag.rs`; in parallel for uniform parameters), O(N) time and, for uniform parameters,
//! no memory besides the output. Periodic curves have N control unknowns in a cyclic system.
//!
//! ```
//! use geomkit::bspline::{interpolate_curve, EndCondition, InterpolationOptions, Parametrization};
//! use geomkit::geom::Curve;
//! let pts = vec![vec![0., 0.], vec![1., 2.], vec![3., 3.], vec![4., 0.], vec![6., 1.]];
//! let opts = InterpolationOptions::default().with_end(EndCondition::Natural);
//! let fit = interpolate_curve(&pts, &opts).unwrap();
//! for (p, t) in pts.iter().zip(fit.parameters()) {
//!     let q = fit.curve().eval(*t);
//!     assert!((q[0] - p[0]).abs() < 1e-14 && (q[1] - p[1]).abs() < 1e-14);
//! }
//! ```

use super::banded::{BandLu, BandMatrix, CyclicLu};
use super::curve::{basis_funs, basis_funs_derivs, cubic_basis_at_knot, BsplineCurve};
use super::tridiag::TridiagSystem;
use crate::par::*;
use crate::points::flatten_points;
use crate::progress::Progress;
use crate::{Error, Result};

/// How the ends of an open interpolating curve are determined.
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub enum EndCondition {
    /// The paper's "multiple points": the first and last reference points are tripled as
    /// control points (N + 4 control points), the N - 2 inner control points solve the
    /// tridiagonal system (2). Uniform parametrization only. The curve starts and ends with
    /// zero speed, and the reference points sit at parameters 0, 2, 3, ..., N-1, N+1.
    Repeat,
    /// Zero second derivative at both ends.
    Natural,
    /// Given first derivatives dc/dt at the ends, zero where `None` (SciPy's "clamped":
    /// `bc_type=([(1, start)], [(1, end)])`, zero by default).
    Clamped {
        /// Tangent at the start, or `None` for zero.
        start: Option<Vec<f64>>,
        /// Tangent at the end, or `None` for zero.
        end: Option<Vec<f64>>,
    },
    /// First derivatives at the ends estimated from the parabola through the first / last
    /// three points (Bessel's condition; with two points the chord). Until issue 22 this was
    /// `Clamped` without tangents; "clamped" now means SciPy's zero slope.
    Bessel,
    /// The third derivative is continuous at the second and the next-to-last knots (SciPy's
    /// default). With 3 points: the parabola; with 2: the line.
    #[default]
    NotAKnot,
    /// The paper's surface boundary (§3), for curves too: one extra control point just
    /// outside each end, extrapolated `offset` times the first / last interval beyond the end
    /// point (k_0 + offset·(k_0 - k_1)); the N inner control points solve the tridiagonal
    /// system. For a surface this gives the paper's (M+2)×(N+2) net.
    OuterPoints {
        /// Distance of the extra points, as a fraction of the end interval (> 0).
        offset: f64,
    },
    /// A closed C2 curve (isolines). A last point equal to the first (within SciPy's
    /// `allclose`: 1e-5 relative) is dropped; at least 2 distinct points.
    Periodic,
}

/// How parameters are assigned to the reference points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Parametrization {
    /// t_i = i (the paper).
    Uniform,
    /// t_(i+1) - t_i = |k_(i+1) - k_i|.
    #[default]
    ChordLength,
    /// t_(i+1) - t_i = |k_(i+1) - k_i|^(1/2): no cusps or self-intersections inside a span.
    Centripetal,
}

/// Options of [`interpolate_curve`].
#[derive(Debug, Clone, PartialEq, Default)]
#[non_exhaustive]
pub struct InterpolationOptions {
    /// End condition (default not-a-knot).
    pub end: EndCondition,
    /// Parametrization (default chord length).
    pub parametrization: Parametrization,
}

impl InterpolationOptions {
    /// Sets the end condition.
    pub fn with_end(mut self, end: EndCondition) -> Self {
        self.end = end;
        self
    }

    /// Sets the parametrization.
    pub fn with_parametrization(mut self, p: Parametrization) -> Self {
        self.parametrization = p;
        self
    }
}

/// An interpolating curve and the parameters at which it passes through each reference point.
/// The parameters are not stored twice: except for the paper's repeated ends they are the
/// curve's inner knots, knots\[3..3 + N\] (as for SciPy's `make_interp_spline`, whose x are
/// its knots), which for 10^7 points in 3-D saves 80 of 400 MB.
#[derive(Debug, Clone, PartialEq)]
pub struct CurveInterpolation {
    curve: BsplineCurve,
    params: Params,
}

/// Where the parameters of a [`CurveInterpolation`] are.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Params {
    /// The curve's knots in this range.
    Knots(std::ops::Range<usize>),
    /// Their own values.
    Own(Vec<f64>),
}

impl Params {
    /// The parameters, given the knots they may lie in.
    fn of<'a>(&'a self, knots: &'a [f64]) -> &'a [f64] {
        match self {
            Params::Knots(r) => &knots[r.clone()],
            Params::Own(t) => t,
        }
    }
}

impl CurveInterpolation {
    /// `params` in the knots of `curve` must be in range (the constructors of this module
    /// and `tiles.rs` build both).
    pub(crate) fn new(curve: BsplineCurve, params: Params) -> Self {
        debug_assert!(match &params {
            Params::Knots(r) => r.end <= curve.knots().len(),
            Params::Own(_) => true,
        });
        CurveInterpolation { curve, params }
    }

    /// The cubic B-spline.
    pub fn curve(&self) -> &BsplineCurve {
        &self.curve
    }

    /// parameters()\[i\]: the curve passes through reference point i there (N values; for
    /// periodic curves without the closing one).
    pub fn parameters(&self) -> &[f64] {
        self.params.of(self.curve.knots())
    }

    /// The curve, the parameters dropped.
    pub fn into_curve(self) -> BsplineCurve {
        self.curve
    }
}

/// Interpolates reference points (each a vector of the same dimension >= 1). Errors: too few
/// points for the end condition, non-finite coordinates, coinciding consecutive points with
/// chord/centripetal parameters, wrong tangent dimension, the repeat condition with
/// non-uniform parameters.
pub fn interpolate_curve(
    points: &[Vec<f64>],
    options: &InterpolationOptions,
) -> Result<CurveInterpolation> {
    let (dim, flat) = flatten_points("reference points", points)?;
    interpolate_curve_flat(dim, &flat, options)
}

/// [`interpolate_curve`] on row-major points of `dim` coordinates.
pub fn interpolate_curve_flat(
    dim: usize,
    points: &[f64],
    options: &InterpolationOptions,
) -> Result<CurveInterpolation> {
    interpolate_curve_flat_with_progress(dim, points, options, &Progress::none())
}

/// [`interpolate_curve_flat`] reporting to `progress` ([`crate::progress`]). The units are
/// the points, twice: N once the parameters (and, for chord-length and centripetal ones,
/// the check of the points) are done, then N for the solve — reported per parallel chunk
/// of rows (about 8 000 points of 3-D) for open curves, at its end for periodic curves and
/// the paper's repeated ends (sequential O(N) solves). The same curve, bit for bit, as
/// without it; [`Error::Cancelled`] when the callback asks to stop, never a partial curve.
///
/// ```
/// use geomkit::bspline::{interpolate_curve_flat_with_progress, InterpolationOptions};
/// use geomkit::progress::Progress;
/// use std::ops::ControlFlow;
/// let pts: Vec<f64> = (0..100_000).flat_map(|i| [i as f64, (i as f64 * 1e-3).sin()]).collect();
/// let last = std::sync::Mutex::new((0, 0));
/// let report = |done: u64, total: u64| {
///     *last.lock().unwrap() = (done, total);
///     ControlFlow::Continue(())
/// };
/// let opts = InterpolationOptions::default();
/// let fit = interpolate_curve_flat_with_progress(2, &pts, &opts, &Progress::new(&report)).unwrap();
/// assert_eq!(*last.lock().unwrap(), (200_000, 200_000));
/// assert_eq!(fit.curve().n_control(), 100_002);
/// ```
pub fn interpolate_curve_flat_with_progress(
    dim: usize,
    points: &[f64],
    options: &InterpolationOptions,
    progress: &Progress,
) -> Result<CurveInterpolation> {
    // Chord lengths need finite points; other parametrizations leave the check to the solve.
    let validated = options.parametrization != Parametrization::Uniform;
    if validated {
        crate::points::validate_points("reference points", dim, points)?;
    } else {
        crate::points::check_shape("reference points", dim, points)?;
    }
    let mut n = points.len() / dim;
    let closed = options.end == EndCondition::Periodic;
    if closed && last_repeats_first(points, dim) {
        n -= 1;
    }
    let points = &points[..n * dim];
    if closed {
        check_distinct_periodic(n)?;
    }
    progress.add_total(2 * n as u64)?;
    if closed && n == 2 {
        let t = parameters(points, dim, options.parametrization, true)?;
        let fit = periodic_through_two(points, dim, &t)?;
        progress.finish()?;
        return Ok(fit);
    }
    let knots = knots_around_parameters(
        points,
        dim,
        options.parametrization,
        options.end == EndCondition::Periodic,
        0.0,
    )?;
    progress.advance(n as u64)?;
    let fit = Solver1d::new_single(knots, &options.end, options.parametrization)?
        .interpolate_reporting(points, dim, validated, progress)?;
    progress.finish()?;
    Ok(fit)
}

/// Interpolates row-major points at given parameters (SciPy's `make_interp_spline(x, y)`):
/// the curve passes through point i at `parameters[i]`. Open curves take N strictly increasing
/// finite parameters; periodic ones N+1, the last closing the curve (or N with a last point
/// equal to the first, which is dropped, as SciPy expects). Errors: as
/// [`interpolate_curve_flat`], parameters not finite or not increasing or of the wrong count,
/// and the paper's repeat condition (it fixes its own parameters).
///
/// ```
/// use geomkit::bspline::{interpolate_curve_at, EndCondition};
/// use geomkit::geom::Curve;
/// let x = [0.0, 0.5, 2.0, 2.5, 4.0];
/// let y = [1.0, 3.0, 2.0, 0.0, 1.0];
/// let fit = interpolate_curve_at(1, &y, &x, &EndCondition::NotAKnot).unwrap();
/// assert!((fit.curve().eval(2.0)[0] - 2.0).abs() < 1e-15);
/// ```
pub fn interpolate_curve_at(
    dim: usize,
    points: &[f64],
    parameters: &[f64],
    end: &EndCondition,
) -> Result<CurveInterpolation> {
    interpolate_curve_at_with_progress(dim, points, parameters, end, &Progress::none())
}

/// [`interpolate_curve_at`] reporting to `progress` ([`crate::progress`]), in the units of
/// [`interpolate_curve_flat_with_progress`] (N for the check of the parameters, N for the
/// solve). The same curve, bit for bit, as without it; [`Error::Cancelled`] when the
/// callback asks to stop.
pub fn interpolate_curve_at_with_progress(
    dim: usize,
    points: &[f64],
    parameters: &[f64],
    end: &EndCondition,
    progress: &Progress,
) -> Result<CurveInterpolation> {
    crate::points::check_shape("reference points", dim, points)?;
    if *end == EndCondition::Repeat {
        return Err(Error::InvalidOption {
            option: "end condition",
            reason: "the paper's repeated end points fix their own parameters",
        });
    }
    let mut n = points.len() / dim;
    let closed = *end == EndCondition::Periodic;
    let repeats_first = closed && last_repeats_first(points, dim);
    if repeats_first && parameters.len() == n {
        n -= 1;
    }
    if parameters.len() != if closed { n + 1 } else { n } {
        let fix = match (closed, repeats_first) {
            (false, _) => format!("give one per point ({n})"),
            (true, true) => format!(
                "the last point repeats the first, so give one per point ({n})",
                n = n
            ),
            (true, false) => format!(
                "periodic: give one per point and one more closing the curve ({}), or end the \
                 points with the first point again",
                n + 1
            ),
        };
        return Err(Error::Interpolation {
            reason: format!(
                "{} parameters for {} points: {fix}",
                parameters.len(),
                points.len() / dim
            ),
        });
    }
    progress.add_total(2 * n as u64)?;
    check_parameters(parameters, parameters.len())?;
    let points = &points[..n * dim];
    if closed {
        check_distinct_periodic(n)?;
    }
    let fit = if closed && n == 2 {
        periodic_through_two(points, dim, parameters)?
    } else {
        let knots = knots_around(parameters);
        progress.advance(n as u64)?;
        let solver = Solver1d::new_single(knots, end, Parametrization::ChordLength)?;
        solver.interpolate_reporting(points, dim, false, progress)?
    };
    progress.finish()?;
    Ok(fit)
}

/// Whether the last of the row-major points repeats the first, within SciPy's `allclose`
/// (1e-5 relative, 1e-15 absolute): periodic data may close themselves so (SciPy's test of
/// periodic `make_interp_spline` data). False for fewer than two points.
///
/// ```
/// use geomkit::bspline::last_repeats_first;
/// assert!(last_repeats_first(&[1.0, 2.0, 5.0, 6.0, 1.0, 2.000001], 2));
/// assert!(!last_repeats_first(&[1.0, 2.0, 5.0, 6.0, 1.0, 2.1], 2));
/// ```
pub fn last_repeats_first(points: &[f64], dim: usize) -> bool {
    let n = points.len() / dim.max(1);
    n >= 2
        && points[..dim]
            .iter()
            .zip(&points[(n - 1) * dim..])
            .all(|(a, b)| (a - b).abs() <= 1e-15 + 1e-5 * b.abs())
}

/// A periodic curve needs two distinct points (SciPy's least).
fn check_distinct_periodic(n: usize) -> Result<()> {
    if n < 2 {
        return Err(Error::TooFewPoints {
            what: "distinct reference points (periodic)",
            got: n,
            min: 2,
        });
    }
    Ok(())
}

/// A periodic cubic through two distinct points (as SciPy accepts): too few for the cyclic
/// tridiagonal system, solved as SciPy does ([`super::make_interp_spline`]), whose periodic
/// cubic has this module's representation (three knots beyond each end continued by the
/// period, N + 3 control points).
fn periodic_through_two(points: &[f64], dim: usize, t: &[f64]) -> Result<CurveInterpolation> {
    let mut y = points.to_vec();
    y.extend_from_slice(&points[..dim]);
    let options = super::SplineOptions::new(3).with_ends(super::SplineEnds::Periodic);
    let curve = super::make_interp_spline(t, &y, dim, &options)?;
    Ok(CurveInterpolation::new(curve, Params::Own(t[..2].to_vec())))
}

/// `want` finite, strictly increasing parameters.
fn check_parameters(parameters: &[f64], want: usize) -> Result<()> {
    if parameters.len() != want {
        return Err(Error::InvalidParameter {
            index: parameters.len().min(want),
            reason: "need one parameter per point (periodic: plus the closing one)",
        });
    }
    if let Some(index) = crate::points::first_non_finite(parameters) {
        return Err(Error::NonFinite {
            what: "parameter",
            index,
        });
    }
    let found = crate::points::first_index(parameters.len().saturating_sub(1), |i| {
        parameters[i + 1] <= parameters[i]
    });
    if let Some(i) = found {
        return Err(Error::InvalidParameter {
            index: i + 1,
            reason: "parameters must be strictly increasing",
        });
    }
    Ok(())
}

/// Points from which [`CurveInterpolator::at`] solves in parallel chunks instead of by a
/// stored factorization.
const PARALLEL_SOLVE: usize = 1 << 16;

/// A factored interpolation system for N points at fixed parameters with one end condition,
/// solved for any number of point sets without refactoring or allocating: curves that share
/// their parametrization (every frame of a time series, isolines sampled alike, the rows of
/// a grid) and large curves whose buffers the caller keeps. [`CurveInterpolator::solve_into`]
/// gives the control points of [`interpolate_curve`] / [`interpolate_curve_at`] for the
/// same parameters, within rounding; uniform parameters (the paper's case) take one pass
/// over the points, in parallel cache-sized chunks.
///
/// ```
/// use geomkit::bspline::{BsplineCurve, CurveInterpolator, EndCondition};
/// use geomkit::geom::Curve;
/// let solver = CurveInterpolator::uniform(5, &EndCondition::NotAKnot).unwrap();
/// let mut control = vec![0.0; solver.n_control() * 2];
/// for frame in 0..3 {
///     let points: Vec<f64> = (0..10).map(|k| (k * (frame + 1)) as f64).collect();
///     solver.solve_into(&points, 2, &mut control).unwrap();
///     let curve = BsplineCurve::from_flat(3, solver.knots().to_vec(), 2, control.clone()).unwrap();
///     let at = curve.eval(solver.parameters()[3]);
///     assert!((at[0] - points[6]).abs() < 1e-12 && (at[1] - points[7]).abs() < 1e-12);
/// }
/// ```
#[derive(Debug, Clone)]
pub struct CurveInterpolator {
    solver: Solver1d,
    n: usize,
}

impl CurveInterpolator {
    /// The system for N points at the parameters 0, 1, ..., N - 1 (the uniform
    /// parametrization; periodic curves close at N). Errors: too few points for the end
    /// condition, invalid end conditions (as [`interpolate_curve`]).
    pub fn uniform(n: usize, end: &EndCondition) -> Result<Self> {
        let count = if *end == EndCondition::Periodic {
            n + 1
        } else {
            n
        };
        let t: Vec<f64> = (0..count).map(|i| i as f64).collect();
        Ok(CurveInterpolator {
            solver: Solver1d::new(knots_around(&t), end, Parametrization::Uniform)?,
            n,
        })
    }

    /// The system for points at `parameters` (N finite, strictly increasing values; N + 1
    /// for periodic curves, the last closing the curve), as [`interpolate_curve_at`]. Open
    /// curves of 2^16 points or more keep no factorization: each solve rebuilds the rows
    /// from the knots and sweeps them in parallel chunks (as [`interpolate_curve_at`] does),
    /// which is faster than a stored factorization swept sequentially. Errors: as
    /// [`interpolate_curve_at`].
    pub fn at(parameters: &[f64], end: &EndCondition) -> Result<Self> {
        if *end == EndCondition::Repeat {
            return Err(Error::InvalidOption {
                option: "end condition",
                reason: "the paper's repeated end points fix their own parameters",
            });
        }
        check_parameters(parameters, parameters.len())?;
        // No parameters at all: the solver's own count check refuses them.
        let n = parameters
            .len()
            .saturating_sub(usize::from(*end == EndCondition::Periodic));
        // Large systems solve fastest in parallel chunks from their rows (a factorization
        // would be swept sequentially).
        let once = n >= PARALLEL_SOLVE;
        Ok(CurveInterpolator {
            solver: Solver1d::build(
                knots_around(parameters),
                end,
                Parametrization::ChordLength,
                once,
            )?,
            n,
        })
    }

    /// Number of points N a solve takes.
    pub fn n_points(&self) -> usize {
        self.n
    }

    /// Number of control points a solve gives.
    pub fn n_control(&self) -> usize {
        self.solver.n_control()
    }

    /// Knots of the curves (degree 3).
    pub fn knots(&self) -> &[f64] {
        &self.solver.knots
    }

    /// The parameter of each point.
    pub fn parameters(&self) -> &[f64] {
        self.solver.parameters()
    }

    /// Writes the control points (`n_control() × dim`, row-major) of the cubic through
    /// `points` (`n_points() × dim`, row-major) into `control`. Errors: buffers of the wrong
    /// size, non-finite points (named by index), a given end tangent of the wrong
    /// dimension.
    pub fn solve_into(&self, points: &[f64], dim: usize, control: &mut [f64]) -> Result<()> {
        if dim == 0 || points.len() != self.n * dim {
            return Err(Error::BufferSize {
                expected: self.n * dim.max(1),
                got: points.len(),
            });
        }
        if control.len() != self.n_control() * dim {
            return Err(Error::BufferSize {
                expected: self.n_control() * dim,
                got: control.len(),
            });
        }
        self.solver.solve_checked(points, dim, control, false)
    }
}

/// Parameters t_0 = 0 < t_1 < ... (N values, or N+1 with the closing one for closed curves).
pub fn parameters(
    points: &[f64],
    dim: usize,
    kind: Parametrization,
    closed: bool,
) -> Result<Vec<f64>> {
    let mut t = vec![0.0; points.len() / dim + usize::from(closed)];
    fill_parameters(points, dim, kind, closed, 0.0, &mut t)?;
    Ok(t)
}

/// [`parameters`] of an open stretch of points starting at `t0` instead of 0: bit for bit
/// the values the whole sequence gets there when `t0` is its parameter at the stretch's
/// first point (so a stream of overlapping stretches sees the global parameters). Errors as
/// [`parameters`].
pub fn parameters_from(
    points: &[f64],
    dim: usize,
    kind: Parametrization,
    t0: f64,
) -> Result<Vec<f64>> {
    let mut t = vec![0.0; points.len() / dim];
    fill_parameters(points, dim, kind, false, t0, &mut t)?;
    Ok(t)
}

/// The knot vector of an interpolating curve with its parameters in place: the values of
/// [`parameters`] (starting at `t0`) at 3.., and three slots at each end that the solver
/// fills with the end knots. The parameters are never stored apart from the knots.
pub(crate) fn knots_around_parameters(
    points: &[f64],
    dim: usize,
    kind: Parametrization,
    closed: bool,
    t0: f64,
) -> Result<Vec<f64>> {
    let count = points.len() / dim + usize::from(closed);
    let mut knots = crate::mem::zeros(count + 6);
    fill_parameters(points, dim, kind, closed, t0, &mut knots[3..count + 3])?;
    Ok(knots)
}

/// [`knots_around_parameters`] for given parameters `t`.
pub(crate) fn knots_around(t: &[f64]) -> Vec<f64> {
    let mut knots = crate::mem::zeros(t.len() + 6);
    crate::points::par_copy(t, &mut knots[3..t.len() + 3]);
    knots
}

/// Writes [`parameters`] starting at `t0` instead of 0 into `t`: a stretch of points gets
/// exactly (bit for bit) the values the whole sequence gets when `t0` is its parameter there.
fn fill_parameters(
    points: &[f64],
    dim: usize,
    kind: Parametrization,
    closed: bool,
    t0: f64,
    t: &mut [f64],
) -> Result<()> {
    let n = points.len() / dim;
    let count = t.len();
    debug_assert_eq!(count, if closed { n + 1 } else { n });
    if kind == Parametrization::Uniform && t0.fract() == 0.0 && t0.abs() + (count as f64) < 2e15 {
        // Integers: t0 + i is exactly the running sum, and fills in parallel.
        t.par_iter_mut()
            .enumerate()
            .for_each(|(i, v)| *v = t0 + i as f64);
        return Ok(());
    }
    // The steps in parallel, then their running sum (the same additions in the same order
    // as a sequential loop: bit for bit). Step i > 0 is the distance from point i - 1 to
    // point i (point N closes a closed curve at point 0); each chunk also reports its first
    // zero step (a point equal to the one before).
    const CHUNK: usize = 1 << 14;
    let repeated = t
        .par_chunks_mut(CHUNK)
        .enumerate()
        .filter_map(|(k, part)| {
            let first = k * CHUNK;
            let (lo, hi) = (first.max(1), (first + part.len()).min(n));
            let inner = &mut part[lo - first..hi.max(lo) - first];
            match kind {
                Parametrization::Uniform => inner.fill(1.0),
                _ if lo < hi => {
                    crate::numeric::distances_into(&points[(lo - 1) * dim..hi * dim], dim, inner)
                }
                _ => {}
            }
            if first == 0 {
                part[0] = t0;
            }
            if first + part.len() == n + 1 {
                let d = crate::numeric::distance(&points[(n - 1) * dim..n * dim], &points[..dim]);
                part[n - first] = if kind == Parametrization::Uniform {
                    1.0
                } else {
                    d
                };
            }
            if kind == Parametrization::Centripetal {
                for v in &mut part[usize::from(first == 0)..] {
                    *v = v.sqrt();
                }
            }
            let zero = part.iter().enumerate().skip(usize::from(first == 0));
            zero.filter(|(_, v)| **v == 0.0)
                .map(|(j, _)| first + j - 1)
                .next()
        })
        .min();
    if let Some(index) = repeated {
        return Err(Error::RepeatedPoint { index });
    }
    for i in 1..count {
        t[i] += t[i - 1];
    }
    // The steps are >= 0 or NaN, so the sums only grow and a non-finite one stays so: the
    // last sum is finite exactly when all are.
    if t.last().is_some_and(|x| !x.is_finite()) {
        return Err(Error::NonFinite {
            what: "parameter of reference point",
            index: crate::points::first_non_finite(t).unwrap_or(count - 1),
        });
    }
    Ok(())
}

/// What the end rows of an open system ask for.
#[derive(Debug, Clone)]
enum EndRhs {
    /// Zero (natural, not-a-knot, clamped without a tangent).
    Zero,
    /// A given tangent.
    Given(Vec<f64>),
    /// Bessel's estimate from the data.
    Estimated,
    /// The end point extrapolated by this fraction of the end interval.
    Outer(f64),
}

#[derive(Debug, Clone)]
enum Kind {
    /// Open curve: rows [start, interp t_0..t_(N-1) (×`interp_scale`), end], tridiagonal
    /// plus the two end rows.
    Open {
        sys: TridiagSystem,
        start: EndRhs,
        end: EndRhs,
        /// Factors that equilibrated the two end rows (their right-hand sides get them too).
        scales: [f64; 2],
        /// 6 for uniform parameters (rows (1, 4, 1)), 1 otherwise (rows of basis values).
        interp_scale: f64,
    },
    /// Open curve with non-uniform parameters solved once (a curve, a tile): the rows are
    /// computed during the solve, which keeps N numbers instead of a factorization's 3N.
    OpenOnce {
        rows: [(usize, Vec<f64>); 2],
        start: EndRhs,
        end: EndRhs,
        scales: [f64; 2],
    },
    /// Periodic: N unknowns p_0..p_(N-1), control [p_(N-1) p_0 .. p_(N-1) p_0 p_1].
    Periodic { lu: CyclicLu },
    /// The paper's repeated ends: N-2 inner unknowns, control [k0 ×3, p*, k_(N-1) ×3].
    Repeat { lu: Option<BandLu> },
}

/// A factored 1-D interpolation system for one set of parameters and one end condition:
/// solves any number of data rows (the rows and columns of a surface) without refactoring.
#[derive(Debug, Clone)]
pub(crate) struct Solver1d {
    /// Knots of the resulting cubic B-spline.
    pub knots: Vec<f64>,
    /// Parameters of the reference points.
    params: Params,
    kind: Kind,
}

impl Solver1d {
    /// Builds and factors the system for the parameters t in `knots` (from
    /// [`knots_around_parameters`] or [`knots_around`]: N values, N+1 for periodic curves
    /// the last closing the curve, at 3.., with three slots at each end for the end knots).
    pub fn new(knots: Vec<f64>, end: &EndCondition, param: Parametrization) -> Result<Self> {
        Self::build(knots, end, param, false)
    }

    /// Parameters of the reference points.
    pub fn parameters(&self) -> &[f64] {
        self.params.of(&self.knots)
    }

    fn build(
        knots: Vec<f64>,
        end: &EndCondition,
        param: Parametrization,
        single: bool,
    ) -> Result<Self> {
        let closed = *end == EndCondition::Periodic;
        let count = knots.len().saturating_sub(6);
        let n = if closed {
            count.saturating_sub(1)
        } else {
            count
        };
        let min = if closed { 3 } else { 2 };
        if n < min {
            return Err(Error::TooFewPoints {
                what: "reference points",
                got: n,
                min,
            });
        }
        match end {
            EndCondition::Repeat => {
                if param != Parametrization::Uniform {
                    return Err(Error::InvalidOption {
                        option: "end condition",
                        reason: "the paper's repeated end points need the uniform parametrization",
                    });
                }
                Self::repeat(n)
            }
            EndCondition::Periodic => Self::periodic(knots),
            _ => Self::open(knots, end, end, single),
        }
    }

    /// [`Solver1d::new`] for a system solved once ([`Solver1d::interpolate`]): non-uniform
    /// open systems then factor during the solve, keeping N numbers instead of 3N.
    pub fn new_single(knots: Vec<f64>, end: &EndCondition, param: Parametrization) -> Result<Self> {
        Self::build(knots, end, param, true)
    }

    /// Solves for `points` (N × dim) and moves the knots and parameters into the result
    /// (`validated`: as [`Solver1d::solve_checked`]).
    pub fn interpolate(
        self,
        points: &[f64],
        dim: usize,
        validated: bool,
    ) -> Result<CurveInterpolation> {
        self.interpolate_reporting(points, dim, validated, &Progress::none())
    }

    /// [`Solver1d::interpolate`] reporting the solve's rows to `progress` (N units; see
    /// [`Solver1d::solve_reporting`]).
    pub fn interpolate_reporting(
        self,
        points: &[f64],
        dim: usize,
        validated: bool,
        progress: &Progress,
    ) -> Result<CurveInterpolation> {
        let mut control = crate::mem::zeros(self.n_control() * dim);
        self.solve_checked_reporting(points, dim, &mut control, validated, progress)?;
        Ok(CurveInterpolation::new(
            BsplineCurve::from_trusted(3, self.knots, dim, control),
            self.params,
        ))
    }

    /// Number of control points of the result.
    pub fn n_control(&self) -> usize {
        self.knots.len() - 4
    }

    fn repeat(n: usize) -> Result<Self> {
        let m = n - 2;
        let lu = if m == 0 {
            None
        } else {
            let mut a = BandMatrix::zeros(m, 1, 1);
            for r in 0..m {
                a.set(r, r, 4.0);
                if r > 0 {
                    a.set(r, r - 1, 1.0);
                }
                if r + 1 < m {
                    a.set(r, r + 1, 1.0);
                }
            }
            Some(a.factor()?)
        };
        let mut parameters: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        parameters[0] = 0.0;
        parameters[n - 1] = n as f64 + 1.0;
        Ok(Solver1d {
            knots: (0..n + 8).map(|k| k as f64 - 3.0).collect(),
            params: Params::Own(parameters),
            kind: Kind::Repeat { lu },
        })
    }

    fn periodic(mut knots: Vec<f64>) -> Result<Self> {
        let n = knots.len() - 7;
        let period = knots[n + 3] - knots[3];
        for k in 1..=3 {
            knots[3 - k] = knots[n + 3 - k] - period;
            knots[n + 3 + k] = knots[3 + k] + period;
        }
        check_knot_span(&knots)?;
        let t = &knots[3..n + 4];
        let (mut lower, mut diag, mut upper) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut basis = [0.0; 4];
        for i in 0..n {
            basis_funs(&knots, 3 + i, t[i], 3, &mut basis);
            lower[i] = basis[0];
            diag[i] = basis[1];
            upper[i] = basis[2];
        }
        Ok(Solver1d {
            knots,
            kind: Kind::Periodic {
                lu: CyclicLu::new(&lower, &diag, &upper)?,
            },
            params: Params::Knots(3..n + 3),
        })
    }

    /// An open system with (possibly different) conditions at its two ends.
    pub(crate) fn new_mixed(
        knots: Vec<f64>,
        start: &EndCondition,
        end: &EndCondition,
    ) -> Result<Self> {
        let n = knots.len().saturating_sub(6);
        if n < 2 {
            return Err(Error::TooFewPoints {
                what: "reference points",
                got: n,
                min: 2,
            });
        }
        Self::open(knots, start, end, true)
    }

    fn open(
        mut knots: Vec<f64>,
        start_cond: &EndCondition,
        end_cond: &EndCondition,
        single: bool,
    ) -> Result<Self> {
        let n = knots.len() - 6;
        fill_open_ends(&mut knots);
        check_knot_span(&knots)?;
        let nc = n + 2;
        // Derivative rows scale like 1/h^k: on parameters spaced 1e-120 or 1e120 apart they
        // overflow or underflow (a "singular" system). They are formed on the knots scaled
        // by a power of two (exact) that brings their span near 1, where d/ds = 2^e d/dt;
        // a given or estimated tangent (order 1) is scaled to match (`tangent_scale`).
        let e = ((knots[n + 5] - knots[0]).log2().floor() as i32).clamp(-1000, 1000);
        let s = 2f64.powi(-e);
        let tangent_scale = 2f64.powi(e);
        let t = [knots[3] * s, knots[n + 2] * s];
        // The rows at the ends read the scaled knots around their span only (a copy of all
        // of them was a pass and an allocation as large as the parameters).
        let deriv = |span: usize, at: f64, k: usize| -> Vec<f64> {
            let local: Vec<f64> = knots[span - 3..=span + 4].iter().map(|v| v * s).collect();
            basis_funs_derivs(&local, 3, at, 3, k)[k][..4].to_vec()
        };
        // Jump of the third derivative at the knot after span `left`.
        let jump = |left: usize| -> Vec<f64> {
            let at = knots[left + 1] * s;
            let l = deriv(left, at, 3);
            let r = deriv(left + 1, at, 3);
            let mut c = vec![0.0; 5];
            for k in 0..4 {
                c[k] += l[k];
                c[k + 1] -= r[k];
            }
            c
        };
        // One end row: (first column, coefficients, right-hand side).
        let row_for = |cond: &EndCondition, at_start: bool| -> Result<(usize, Vec<f64>, EndRhs)> {
            let (span, at, first) = if at_start {
                (3, t[0], 0)
            } else {
                (nc - 1, t[1], nc - 4)
            };
            Ok(match cond {
                EndCondition::Natural => (first, deriv(span, at, 2), EndRhs::Zero),
                EndCondition::NotAKnot if n == 2 => (first, deriv(span, at, 2), EndRhs::Zero),
                EndCondition::Clamped { start, end } => {
                    let given = if at_start { start } else { end };
                    let rhs = given.clone().map_or(EndRhs::Zero, EndRhs::Given);
                    (first, deriv(span, at, 1), rhs)
                }
                EndCondition::Bessel => (first, deriv(span, at, 1), EndRhs::Estimated),
                EndCondition::OuterPoints { offset } => {
                    if !(offset.is_finite() && *offset > 0.0) {
                        return Err(Error::InvalidOption {
                            option: "outer point offset",
                            reason: "must be finite and > 0",
                        });
                    }
                    (
                        if at_start { 0 } else { nc - 1 },
                        vec![1.0],
                        EndRhs::Outer(*offset),
                    )
                }
                // With 3 points both not-a-knot rows would name the same knot: the second
                // makes the single cubic a parabola instead.
                EndCondition::NotAKnot
                    if n == 3 && !at_start && *start_cond == EndCondition::NotAKnot =>
                {
                    (0, deriv(3, t[0], 3), EndRhs::Zero)
                }
                EndCondition::NotAKnot if at_start => (0, jump(3), EndRhs::Zero),
                EndCondition::NotAKnot => (nc - 5, jump(nc - 2), EndRhs::Zero),
                EndCondition::Repeat | EndCondition::Periodic => {
                    return Err(Error::InvalidOption {
                        option: "end condition",
                        reason: "repeat and periodic ends apply to both ends at once",
                    })
                }
            })
        };
        // Equilibrate the end rows: derivative rows scale like 1/h^k and would otherwise
        // dwarf the interpolation rows (bad pivots, false "singular" verdicts).
        let equilibrate = |(first, coeffs, rhs): (usize, Vec<f64>, EndRhs)| {
            let m = coeffs.iter().fold(0.0f64, |m, c| m.max(c.abs()));
            let f = if m > 0.0 && m.is_finite() {
                1.0 / m
            } else {
                1.0
            };
            let f_rhs = match rhs {
                EndRhs::Given(_) | EndRhs::Estimated => f * tangent_scale,
                _ => f,
            };
            (
                first,
                coeffs.iter().map(|c| c * f).collect::<Vec<f64>>(),
                rhs,
                f_rhs,
            )
        };
        let start = equilibrate(row_for(start_cond, true)?);
        let finish = equilibrate(row_for(end_cond, false)?);
        let end_rows = || ((start.0, start.1.clone()), (finish.0, finish.1.clone()));
        // Uniform on the scaled knots exactly when on the given ones (a power of two).
        let (sys, interp_scale) = match is_uniform(&knots[3..n + 3]) {
            true => (TridiagSystem::toeplitz(nc, end_rows().0, end_rows().1), 6.0),
            false => (None, 1.0),
        };
        if sys.is_none() && single {
            return Ok(Solver1d {
                knots,
                params: Params::Knots(3..n + 3),
                kind: Kind::OpenOnce {
                    rows: [(start.0, start.1), (finish.0, finish.1)],
                    start: start.2,
                    end: finish.2,
                    scales: [start.3, finish.3],
                },
            });
        }
        let (sys, interp_scale) = match sys {
            Some(sys) => (Some(sys), interp_scale),
            None => {
                let inner = |r: usize| interp_row(&knots, r);
                let (s0, s1) = end_rows();
                (TridiagSystem::general(nc, inner, s0, s1), 1.0)
            }
        };
        let sys = sys.ok_or(Error::Numerical {
            operation: "banded solve",
            reason: "the interpolation system is singular",
        })?;
        Ok(Solver1d {
            knots,
            params: Params::Knots(3..n + 3),
            kind: Kind::Open {
                sys,
                start: start.2,
                end: finish.2,
                scales: [start.3, finish.3],
                interp_scale,
            },
        })
    }

    /// The right-hand side of an end row (before equilibration). Errors: a given tangent of
    /// the wrong dimension or not finite.
    fn end_value(
        &self,
        rhs: &EndRhs,
        at_start: bool,
        points: &[f64],
        dim: usize,
    ) -> Result<Vec<f64>> {
        let n = points.len() / dim;
        let which = if at_start {
            "start tangent"
        } else {
            "end tangent"
        };
        Ok(match rhs {
            EndRhs::Zero => vec![0.0; dim],
            EndRhs::Given(v) => {
                if v.len() != dim {
                    return Err(Error::DimensionMismatch {
                        what: which,
                        index: 0,
                        expected: dim,
                        got: v.len(),
                    });
                }
                if v.iter().any(|x| !x.is_finite()) {
                    return Err(Error::NonFinite {
                        what: which,
                        index: 0,
                    });
                }
                v.clone()
            }
            EndRhs::Outer(f) => {
                let (e, nb) = if at_start { (0, 1) } else { (n - 1, n - 2) };
                (0..dim)
                    .map(|c| points[e * dim + c] + f * (points[e * dim + c] - points[nb * dim + c]))
                    .collect()
            }
            EndRhs::Estimated if at_start => bessel_tangent(points, dim, self.parameters()),
            EndRhs::Estimated => {
                // The last three points and parameters, reversed (t negated).
                let k = n.min(3);
                let rev_pts = reversed(&points[(n - k) * dim..], dim);
                let rev_t: Vec<f64> = self.parameters()[n - k..n]
                    .iter()
                    .rev()
                    .map(|v| -v)
                    .collect();
                bessel_tangent(&rev_pts, dim, &rev_t)
                    .iter()
                    .map(|v| -v)
                    .collect()
            }
        })
    }

    /// The right-hand sides of the two end rows of an open system, equilibrated.
    fn open_ends(&self, points: &[f64], dim: usize) -> Result<[Vec<f64>; 2]> {
        let (start, end, scales) = match &self.kind {
            Kind::Open {
                start, end, scales, ..
            }
            | Kind::OpenOnce {
                start, end, scales, ..
            } => (start, end, scales),
            _ => unreachable!("open_ends on an open system only"),
        };
        let value = |rhs, at_start, scale: f64| -> Result<Vec<f64>> {
            let v = self.end_value(rhs, at_start, points, dim)?;
            Ok(v.iter().map(|x| x * scale).collect())
        };
        Ok([
            value(start, true, scales[0])?,
            value(end, false, scales[1])?,
        ])
    }

    /// Whether [`Solver1d::solve`] takes a one-pass path (Toeplitz, or general solved once),
    /// which detects non-finite input by its output instead of a pass of its own.
    pub fn solves_fused(&self) -> bool {
        self.is_toeplitz() || matches!(self.kind, Kind::OpenOnce { .. })
    }

    /// Whether the system is open with uniform parameters (the Toeplitz rows (1, 4, 1)/6).
    fn is_toeplitz(&self) -> bool {
        matches!(&self.kind, Kind::Open { sys, .. } if sys.is_toeplitz())
    }

    /// Whether [`Solver1d::solve_rows`] applies: open systems with a stored factorization.
    pub fn solves_rows(&self) -> bool {
        matches!(self.kind, Kind::Open { .. })
    }

    /// Whether [`Solver1d::solve_in_place`] applies: open systems whose end rows do not ask
    /// for a given tangent (of one point's dimension, not a whole row's).
    pub fn solves_in_place(&self) -> bool {
        matches!(&self.kind, Kind::Open { start, end, .. }
            if !matches!(start, EndRhs::Given(_)) && !matches!(end, EndRhs::Given(_)))
    }

    /// [`Solver1d::solve`] in place, for systems where [`Solver1d::solves_in_place`]: `buf`
    /// (`n_control() * dim`) holds the N points in its rows 1..=N and receives the control
    /// points.
    pub fn solve_in_place(&self, buf: &mut [f64], dim: usize) -> Result<()> {
        let Kind::Open {
            sys, interp_scale, ..
        } = &self.kind
        else {
            unreachable!("solve_in_place on an open system only")
        };
        let n = self.parameters().len();
        debug_assert_eq!(buf.len(), (n + 2) * dim);
        let ends = self.open_ends(&buf[dim..(n + 1) * dim], dim)?;
        buf[..dim].copy_from_slice(&ends[0]);
        buf[(n + 1) * dim..].copy_from_slice(&ends[1]);
        // Scaled and checked on the way: no passes of their own.
        if sys.solve_scaled(buf, dim, *interp_scale) {
            return Ok(());
        }
        check_solution(buf, dim)
    }

    /// [`Solver1d::solve`] of B rows of one coordinate at once (a grid's rows), for
    /// [`Solver1d::solves_rows`] systems: swept side by side, the same bits as one by one.
    /// Errors: as [`Solver1d::solve`].
    pub fn solve_rows<const B: usize>(
        &self,
        rows: [&[f64]; B],
        mut outs: [&mut [f64]; B],
    ) -> Result<()> {
        let Kind::Open {
            sys, interp_scale, ..
        } = &self.kind
        else {
            unreachable!("solve_rows on an open system only")
        };
        let mut firsts = [0.0; B];
        let mut lasts = [0.0; B];
        for (i, row) in rows.iter().enumerate() {
            let [f, l] = self.open_ends(row, 1)?;
            (firsts[i], lasts[i]) = (f[0], l[0]);
        }
        if sys.solve_rows_into(firsts, rows, lasts, *interp_scale, &mut outs) {
            return Ok(());
        }
        outs.iter().try_for_each(|out| check_solution(out, 1))
    }

    /// [`Solver1d::solve`] for points not known to be finite (`validated` false): the
    /// one-pass paths detect non-finite input by their output and only then look for the
    /// point to name; the others check the points first.
    pub fn solve_checked(
        &self,
        points: &[f64],
        dim: usize,
        out: &mut [f64],
        validated: bool,
    ) -> Result<()> {
        self.solve_checked_reporting(points, dim, out, validated, &Progress::none())
    }

    /// [`Solver1d::solve_checked`] reporting to `progress` ([`Solver1d::solve_reporting`]).
    fn solve_checked_reporting(
        &self,
        points: &[f64],
        dim: usize,
        out: &mut [f64],
        validated: bool,
        progress: &Progress,
    ) -> Result<()> {
        let validate = || crate::points::validate_points("reference points", dim, points);
        if !validated && !self.solves_fused() {
            validate()?;
        }
        self.solve_reporting(points, dim, out, progress)
            .or_else(|e| {
                if e == Error::Cancelled {
                    return Err(e);
                }
                if !validated {
                    validate()?;
                }
                Err(e)
            })
    }

    /// Control points (row-major, `n_control() * dim`) interpolating `points` (N × dim).
    /// Errors: a given tangent of the wrong dimension or not finite.
    pub fn solve(&self, points: &[f64], dim: usize, out: &mut [f64]) -> Result<()> {
        self.solve_reporting(points, dim, out, &Progress::none())
    }

    /// [`Solver1d::solve`] reporting its N + 2 rows to `progress`: per parallel chunk of rows
    /// for the one-pass open solves ([`Solver1d::solves_fused`]), at the end for the
    /// others. Cancelled: [`Error::Cancelled`] (the remaining chunks are skipped).
    pub fn solve_reporting(
        &self,
        points: &[f64],
        dim: usize,
        out: &mut [f64],
        progress: &Progress,
    ) -> Result<()> {
        let n = points.len() / dim;
        debug_assert_eq!(out.len(), self.n_control() * dim);
        progress.check()?;
        match &self.kind {
            Kind::Open {
                sys, interp_scale, ..
            } if sys.is_toeplitz() => {
                let ends = self.open_ends(points, dim)?;
                let (first, last, scale) = (&ends[0], &ends[1], *interp_scale);
                let finite =
                    sys.solve_scaled_into_reporting(first, points, last, scale, out, dim, progress);
                progress.check()?;
                if finite {
                    return Ok(());
                }
            }
            Kind::Open {
                sys, interp_scale, ..
            } => {
                let ends = self.open_ends(points, dim)?;
                out[dim..(n + 1) * dim].copy_from_slice(points);
                out[..dim].copy_from_slice(&ends[0]);
                out[(n + 1) * dim..].copy_from_slice(&ends[1]);
                if sys.solve_scaled(out, dim, *interp_scale) {
                    return Ok(());
                }
            }
            Kind::OpenOnce { rows, .. } => {
                let ends = self.open_ends(points, dim)?;
                let inner = |r: usize| interp_row(&self.knots, r);
                let finite = TridiagSystem::solve_general_into_reporting(
                    n + 2,
                    &inner,
                    rows[0].clone(),
                    rows[1].clone(),
                    (&ends[0], points, &ends[1]),
                    out,
                    dim,
                    progress,
                );
                progress.check()?;
                let finite = finite.ok_or(Error::Numerical {
                    operation: "banded solve",
                    reason: "the interpolation system is singular",
                })?;
                if finite {
                    return Ok(());
                }
            }
            Kind::Periodic { lu } => {
                let mut p = points.to_vec();
                lu.solve(&mut p, dim);
                for j in 0..n + 3 {
                    let i = (j + n - 1) % n;
                    out[j * dim..(j + 1) * dim].copy_from_slice(&p[i * dim..(i + 1) * dim]);
                }
            }
            Kind::Repeat { lu } => {
                let (first, last) = (&points[..dim], &points[(n - 1) * dim..]);
                for j in 0..3 {
                    out[j * dim..(j + 1) * dim].copy_from_slice(first);
                    out[(n + 1 + j) * dim..(n + 2 + j) * dim].copy_from_slice(last);
                }
                if let Some(lu) = lu {
                    let inner = &mut out[3 * dim..(n + 1) * dim];
                    for r in 0..n - 2 {
                        for c in 0..dim {
                            let mut v = 6.0 * points[(r + 1) * dim + c];
                            if r == 0 {
                                v -= first[c];
                            }
                            if r + 3 == n {
                                v -= last[c];
                            }
                            inner[r * dim + c] = v;
                        }
                    }
                    lu.solve(inner, dim);
                }
            }
        }
        // The sequential solves report at their end.
        progress.advance((n + 2) as u64)?;
        check_solution(out, dim)
    }
}

/// Errors when a computed control point is not finite (overflow on extreme input).
/// The knots, with the three beyond each end, and their span must be finite: parameters
/// spread over more than f64's range (e.g. -1e308 to 1e308) would make the basis functions'
/// knot differences infinite and the curve NaN.
fn check_knot_span(knots: &[f64]) -> Result<()> {
    let span = knots[knots.len() - 1] - knots[0];
    if let Some(index) = crate::points::first_non_finite(knots) {
        return Err(Error::InvalidKnots {
            index,
            reason: "the parameters' spread overflows f64 (the knots beyond the ends are \
                     spaced like the end intervals): scale the parameters down",
        });
    }
    if !span.is_finite() {
        return Err(Error::InvalidKnots {
            index: knots.len() - 1,
            reason: "the knots span more than f64 can represent: scale the parameters down",
        });
    }
    Ok(())
}

fn check_solution(out: &[f64], dim: usize) -> Result<()> {
    match crate::points::first_non_finite(out) {
        Some(index) => Err(Error::NonFinite {
            what: "computed control point",
            index: index / dim,
        }),
        None => Ok(()),
    }
}

/// Row r = i + 1 of an open system interpolates at t_i = knots\[i + 3\]: the basis values
/// there on controls i, i+1, i+2.
#[inline(always)]
fn interp_row(k: &[f64], r: usize) -> [f64; 3] {
    cubic_basis_at_knot(k, r - 1)
}

/// Whether parameters are exactly equally spaced (all differences equal, as the integers of
/// the uniform parametrization are): then the rows are exactly (1, 4, 1)/6. Nearly uniform
/// parameters (a rounded spacing such as 1/4095) take the general rows of their actual knots,
/// so that the curve interpolates at exactly the given parameters.
fn is_uniform(t: &[f64]) -> bool {
    t.len() >= 2 && {
        let h = t[1] - t[0];
        t.windows(2).all(|w| w[1] - w[0] == h)
    }
}

/// Knots for an open curve: t_0..t_(N-1) with three more beyond each end, spaced like the
/// first / last interval (uniform parameters give uniform knots).
pub(crate) fn open_knots(t: &[f64]) -> Vec<f64> {
    let mut knots = knots_around(t);
    fill_open_ends(&mut knots);
    knots
}

/// Fills the three end knots at each end of [`knots_around`]'s vector for an open curve, as
/// [`open_knots`].
pub(crate) fn fill_open_ends(knots: &mut [f64]) {
    let n = knots.len() - 6;
    let (h0, h1) = (knots[4] - knots[3], knots[n + 2] - knots[n + 1]);
    for k in 1..=3 {
        knots[3 - k] = knots[3] - k as f64 * h0;
        knots[n + 2 + k] = knots[n + 2] + k as f64 * h1;
    }
}

/// Derivative at t[0] of the parabola through the first three points (or the chord for two).
pub(crate) fn bessel_tangent(points: &[f64], dim: usize, t: &[f64]) -> Vec<f64> {
    if t.len() == 2 || points.len() / dim == 2 {
        return (0..dim)
            .map(|c| (points[dim + c] - points[c]) / (t[1] - t[0]))
            .collect();
    }
    let (t0, t1, t2) = (t[0], t[1], t[2]);
    let w0 = (2.0 * t0 - t1 - t2) / ((t0 - t1) * (t0 - t2));
    let w1 = (t0 - t2) / ((t1 - t0) * (t1 - t2));
    let w2 = (t0 - t1) / ((t2 - t0) * (t2 - t1));
    (0..dim)
        .map(|c| w0 * points[c] + w1 * points[dim + c] + w2 * points[2 * dim + c])
        .collect()
}

fn reversed(points: &[f64], dim: usize) -> Vec<f64> {
    points.chunks_exact(dim).rev().flatten().copied().collect()
}

/// The paper's route for reference: the N-2 new points from the dense system (2)-(3) solved
/// by Gauss elimination (O(N^3) time, O(N^2) memory; N <= 2000). Same result as
/// [`EndCondition::Repeat`].
pub fn paper_dense_inner_points(points: &[Vec<f64>]) -> Result<Vec<Vec<f64>>> {
    let (dim, flat) = flatten_points("reference points", points)?;
    let n = points.len();
    if n > 2000 {
        return Err(Error::InvalidOption {
            option: "reference route",
            reason: "the dense Gauss route is kept for N <= 2000 only",
        });
    }
    let m = n.saturating_sub(2);
    if m == 0 {
        return Ok(Vec::new());
    }
    let m1 = nalgebra::DMatrix::from_fn(m, m, |r, c| match r.abs_diff(c) {
        0 => 4.0,
        1 => 1.0,
        _ => 0.0,
    });
    let m2 = nalgebra::DMatrix::from_fn(m, dim, |r, c| {
        let mut v = 6.0 * flat[(r + 1) * dim + c];
        if r == 0 {
            v -= flat[c];
        }
        if r + 1 == m {
            v -= flat[(n - 1) * dim + c];
        }
        v
    });
    let x = m1.lu().solve(&m2).ok_or(Error::Numerical {
        operation: "dense Gauss route",
        reason: "singular matrix",
    })?;
    Ok((0..m)
        .map(|r| (0..dim).map(|c| x[(r, c)]).collect())
        .collect())
}
