//! Formulas without an exact B-spline form (square roots, sines, exponentials, ... in the
//! patches of a composite surface, the curves of a ruled surface or the pieces of a
//! composite curve) as the nearest exact-through-points B-spline: the piece is sampled on a
//! uniform grid of its parameters, the samples are interpolated by the library's cubic
//! B-spline interpolation (`geomkit::bspline::interpolate_surface_flat` /
//! `interpolate_curve_at`, not-a-knot ends, the samples' own parameters), and the grid is
//! refined (n -> 2n - 1 samples per direction) until the largest distance between the
//! formula and the B-spline, measured on a check grid [`CHECK`] times denser than the
//! samples, is at most the tolerance.
//!
//! The B-spline passes through every sample exactly (up to rounding) and has the formula's
//! parameters: the face of a patch on the cell [u_i, u_(i+1)] × [v_j, v_(j+1)] evaluates at
//! (u, v) within the reported deviation of the formula at (u, v). Pieces that share an edge
//! (neighbouring cells of a composite surface, consecutive strips of a ruled surface) share
//! the sample count along it, so that their boundary curves are the same curve and the
//! faces are sewn.

use super::nurbs::{NurbsCurve, NurbsSurface};
use super::split;
use super::{StepError, StepResult};
use geomkit::bspline::{
    interpolate_curve_at, interpolate_surface_flat, BsplineSurface, EndCondition, Parametrization,
    SurfaceInterpolationOptions,
};
use geomkit::geom::Curve;

/// Check points per sample interval and direction: the deviation is the largest distance
/// measured at the samples and at 1/8, 2/8, ..., 7/8 of each interval in between (64 points
/// per cell of a surface's sample grid).
pub const CHECK: usize = 8;

/// Samples per direction a piece starts with (then 9, 17, 33, 65, 129, ...).
const FIRST: usize = 5;

/// The most samples per direction of a surface piece (129 × 129; its check grid is 1025 ×
/// 1025 points).
pub const MAX_SURFACE_SAMPLES: usize = 129;

/// The most samples of a curve piece.
pub const MAX_CURVE_SAMPLES: usize = 4097;

/// One piece of a model written as an interpolating B-spline instead of exactly: which
/// piece, how many samples it interpolates and how far it is from the formula.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Approximation {
    /// The piece, as messages name it: `patch (0, 1)`, `strip 2 (v in [1, 2])`, `piece 3`.
    pub piece: String,
    /// Samples interpolated per direction: `[u, v]` for a surface, `[t]` for a curve.
    pub samples: Vec<usize>,
    /// The largest distance between the formula and the B-spline on the check grid
    /// ([`CHECK`] points per sample interval and direction), in the model's units.
    pub deviation: f64,
    /// The tolerance it was refined to, in the model's units (the relative tolerance times
    /// the diagonal of the model's bounding box).
    pub tolerance: f64,
}

impl Approximation {
    /// One line: "patch (0, 1): a 17 x 17-point interpolating B-spline, max deviation
    /// 3.1e-7 (tolerance 2.8e-6)".
    pub fn describe(&self) -> String {
        let grid: Vec<String> = self.samples.iter().map(|n| n.to_string()).collect();
        format!(
            "{}: a {}-point interpolating B-spline, max deviation {:.2e} (tolerance {:.2e})",
            self.piece,
            grid.join(" x "),
            self.deviation,
            self.tolerance
        )
    }
}

/// A point of a piece at its parameters, or an error naming the piece and the point.
pub(crate) type SurfaceEval<'a> = Box<dyn Fn(f64, f64) -> StepResult<[f64; 3]> + 'a>;

/// A point of a curve piece at its parameter.
pub(crate) type CurveEval<'a> = Box<dyn Fn(f64) -> StepResult<[f64; 3]> + 'a>;

/// A surface piece to approximate on its parameter rectangle. Pieces of the same u group
/// take the same samples in u (they share edges u = const), likewise v groups.
pub(crate) struct SurfacePiece<'a> {
    pub name: String,
    pub domain: ((f64, f64), (f64, f64)),
    pub group: (usize, usize),
    pub eval: SurfaceEval<'a>,
}

/// A curve piece on its parameter interval.
pub(crate) struct CurvePiece<'a> {
    pub name: String,
    pub domain: (f64, f64),
    pub eval: CurveEval<'a>,
}

/// n parameters from a to b, the ends exact.
fn uniform(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            if k + 1 == n {
                b
            } else {
                a + (b - a) * (k as f64 / (n - 1) as f64)
            }
        })
        .collect()
}

/// The check parameters of `n` samples on [a, b]: [`CHECK`] per interval and the end; the
/// sample parameters are every [`CHECK`]-th.
fn check_params(a: f64, b: f64, n: usize) -> Vec<f64> {
    uniform(a, b, CHECK * (n - 1) + 1)
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// A formula's point checked finite, as an error naming the piece and the parameters.
pub(crate) fn finite(name: &str, at: &str, p: [f64; 3]) -> StepResult<[f64; 3]> {
    if p.iter().all(|x| x.is_finite()) {
        Ok(p)
    } else {
        Err(StepError::Unsupported(format!(
            "{name}: the formula is not finite at {at} ({:?}): no B-spline can pass through it",
            p
        )))
    }
}

/// The diagonal of the bounding box of the pieces, sampled 17 × 17 (17 per curve).
fn size(surfaces: &[SurfacePiece<'_>], curves: &[CurvePiece<'_>]) -> StepResult<f64> {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut take = |p: [f64; 3]| {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    };
    for s in surfaces {
        let ((u0, u1), (v0, v1)) = s.domain;
        for u in uniform(u0, u1, 17) {
            for v in uniform(v0, v1, 17) {
                take((s.eval)(u, v)?);
            }
        }
    }
    for c in curves {
        for t in uniform(c.domain.0, c.domain.1, 17) {
            take((c.eval)(t)?);
        }
    }
    Ok((0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt())
}

/// The absolute tolerance: `relative` times the size of the pieces (or `relative` itself for
/// a model of size 0).
pub(crate) fn absolute_tolerance(
    relative: f64,
    surfaces: &[SurfacePiece<'_>],
    curves: &[CurvePiece<'_>],
) -> StepResult<f64> {
    let d = size(surfaces, curves)?;
    Ok(if d > 0.0 { relative * d } else { relative })
}

/// One surface piece interpolated on nu × nv samples: the B-spline, the deviation and the
/// deviations along the sample lines (u error at v samples, v error at u samples).
struct SurfaceFit {
    counts: (usize, usize),
    surface: NurbsSurface,
    deviation: f64,
    along_u: f64,
    along_v: f64,
}

fn interp_err(name: &str, e: geomkit::Error) -> StepError {
    StepError::Unsupported(format!("{name}: cannot interpolate its samples: {e}"))
}

fn fit_surface(piece: &SurfacePiece<'_>, nu: usize, nv: usize) -> StepResult<SurfaceFit> {
    let ((u0, u1), (v0, v1)) = piece.domain;
    let (cu, cv) = (check_params(u0, u1, nu), check_params(v0, v1, nv));
    // The check grid's values hold the samples (every CHECK-th row and column).
    let mut want = Vec::with_capacity(cu.len() * cv.len() * 3);
    for &u in &cu {
        for &v in &cv {
            want.extend((piece.eval)(u, v)?);
        }
    }
    let mut grid = Vec::with_capacity(nu * nv * 3);
    for a in 0..nu {
        for b in 0..nv {
            let k = (a * CHECK * cv.len() + b * CHECK) * 3;
            grid.extend_from_slice(&want[k..k + 3]);
        }
    }
    let options = SurfaceInterpolationOptions::default()
        .with_end(EndCondition::NotAKnot)
        .with_parametrization(Parametrization::Uniform);
    let fit = interpolate_surface_flat(nu, nv, 3, &grid, &options)
        .map_err(|e| interp_err(&piece.name, e))?;
    // Parameters 0, 1, ..., n - 1 mapped onto the piece's own (an affine change of the
    // knots leaves the control points as they are).
    let rescale = |knots: &[f64], a: f64, b: f64, n: usize| -> Vec<f64> {
        let last = (n - 1) as f64;
        knots
            .iter()
            .map(|&k| {
                if k == 0.0 {
                    a
                } else if k == last {
                    b
                } else {
                    a + (b - a) * (k / last)
                }
            })
            .collect()
    };
    let (ku, kv) = fit.surface.knots();
    let (ku, kv) = (rescale(ku, u0, u1, nu), rescale(kv, v0, v1, nv));
    let cols = fit.surface.net_size().1;
    let degrees = fit.surface.degrees();
    // Clamped in both directions (the interpolation's knots reach beyond the ends): the
    // boundary curves are the net's first and last rows and columns, as CAD systems expect.
    let net = fit.surface.control_flat();
    let u_rows: Vec<Vec<f64>> = net.chunks_exact(cols * 3).map(<[f64]>::to_vec).collect();
    let (ku, u_rows) = split::clamp(degrees.0, &ku, &u_rows);
    let rows = u_rows.len();
    let columns: Vec<Vec<f64>> = (0..cols)
        .map(|j| {
            u_rows
                .iter()
                .flat_map(|r| r[3 * j..3 * j + 3].to_vec())
                .collect()
        })
        .collect();
    let (kv, columns) = split::clamp(degrees.1, &kv, &columns);
    let cols = columns.len();
    let mut control = vec![0.0; rows * cols * 3];
    for (j, col) in columns.iter().enumerate() {
        for i in 0..rows {
            control[(i * cols + j) * 3..(i * cols + j) * 3 + 3]
                .copy_from_slice(&col[3 * i..3 * i + 3]);
        }
    }
    let surface = BsplineSurface::from_flat(
        degrees,
        ku.clone(),
        kv.clone(),
        rows,
        cols,
        3,
        control.clone(),
    )
    .map_err(|e| interp_err(&piece.name, e))?;
    let mut got = vec![0.0; want.len()];
    surface
        .eval_grid(&cu, &cv, &mut got)
        .map_err(|e| interp_err(&piece.name, e))?;
    let (mut deviation, mut along_u, mut along_v) = (0.0f64, 0.0f64, 0.0f64);
    for a in 0..cu.len() {
        for b in 0..cv.len() {
            let k = (a * cv.len() + b) * 3;
            let d = dist(&want[k..k + 3], &got[k..k + 3]);
            if d.is_nan() {
                return Err(StepError::Unsupported(format!(
                    "{}: the interpolating B-spline is not finite at (u, v) = ({}, {})",
                    piece.name, cu[a], cv[b]
                )));
            }
            deviation = deviation.max(d);
            if b % CHECK == 0 {
                along_u = along_u.max(d);
            }
            if a % CHECK == 0 {
                along_v = along_v.max(d);
            }
        }
    }
    Ok(SurfaceFit {
        counts: (nu, nv),
        surface: NurbsSurface {
            degrees,
            knots_u: ku,
            knots_v: kv,
            rows,
            cols,
            points: control
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]])
                .collect(),
            weights: None,
            bezier: false,
        },
        deviation,
        along_u,
        along_v,
    })
}

fn refined(n: usize) -> usize {
    2 * n - 1
}

/// The pieces as interpolating B-spline surfaces within `tolerance` (absolute), refining
/// each group's sample count until every piece of it is within. Errors: a formula not finite
/// at a sample or check point, a piece still farther than the tolerance at
/// [`MAX_SURFACE_SAMPLES`] samples per direction (naming it and its deviation).
pub(crate) fn surfaces(
    pieces: &[SurfacePiece<'_>],
    tolerance: f64,
) -> StepResult<Vec<(NurbsSurface, Approximation)>> {
    let groups_u = pieces.iter().map(|p| p.group.0 + 1).max().unwrap_or(0);
    let groups_v = pieces.iter().map(|p| p.group.1 + 1).max().unwrap_or(0);
    let (mut nu, mut nv) = (vec![FIRST; groups_u], vec![FIRST; groups_v]);
    let mut fits: Vec<Option<SurfaceFit>> = pieces.iter().map(|_| None).collect();
    loop {
        for (piece, fit) in pieces.iter().zip(fits.iter_mut()) {
            let counts = (nu[piece.group.0], nv[piece.group.1]);
            if fit.as_ref().map(|f| f.counts) != Some(counts) {
                *fit = Some(fit_surface(piece, counts.0, counts.1)?);
            }
        }
        let (mut bump_u, mut bump_v) = (vec![false; groups_u], vec![false; groups_v]);
        for (piece, fit) in pieces.iter().zip(&fits) {
            let f = fit.as_ref().expect("every piece was fitted");
            if f.deviation <= tolerance {
                continue;
            }
            let (gu, gv) = piece.group;
            let can_u = refined(nu[gu]) <= MAX_SURFACE_SAMPLES;
            let can_v = refined(nv[gv]) <= MAX_SURFACE_SAMPLES;
            let mut want_u = f.along_u > tolerance / 4.0;
            let mut want_v = f.along_v > tolerance / 4.0;
            if !((want_u && can_u) || (want_v && can_v)) {
                // The error is in the cells' inside, or one direction is at its limit.
                want_u = true;
                want_v = true;
            }
            bump_u[gu] |= want_u && can_u;
            bump_v[gv] |= want_v && can_v;
        }
        if !bump_u.iter().chain(&bump_v).any(|&b| b) {
            break;
        }
        for (g, b) in bump_u.iter().enumerate() {
            if *b {
                nu[g] = refined(nu[g]);
            }
        }
        for (g, b) in bump_v.iter().enumerate() {
            if *b {
                nv[g] = refined(nv[g]);
            }
        }
    }
    pieces
        .iter()
        .zip(fits)
        .map(|(piece, fit)| {
            let f = fit.expect("every piece was fitted");
            let approximation = Approximation {
                piece: piece.name.clone(),
                samples: vec![f.counts.0, f.counts.1],
                deviation: f.deviation,
                tolerance,
            };
            if f.deviation > tolerance {
                return Err(not_reached(&approximation));
            }
            Ok((f.surface, approximation))
        })
        .collect()
}

fn not_reached(a: &Approximation) -> StepError {
    let grid: Vec<String> = a.samples.iter().map(|n| n.to_string()).collect();
    StepError::Unsupported(format!(
        "{}: the interpolating B-spline of {} samples is still {:.2e} from the formula, above \
         the tolerance {:.2e} (a singular derivative? give a larger tolerance)",
        a.piece,
        grid.join(" x "),
        a.deviation,
        a.tolerance
    ))
}

/// One curve piece interpolated at n samples: the B-spline and its deviation.
fn fit_curve(piece: &CurvePiece<'_>, n: usize) -> StepResult<(NurbsCurve, f64)> {
    let (a, b) = piece.domain;
    let check = check_params(a, b, n);
    let mut want = Vec::with_capacity(check.len() * 3);
    for &t in &check {
        want.extend((piece.eval)(t)?);
    }
    let mut points = Vec::with_capacity(n * 3);
    let mut params = Vec::with_capacity(n);
    for k in 0..n {
        params.push(check[k * CHECK]);
        points.extend_from_slice(&want[k * CHECK * 3..k * CHECK * 3 + 3]);
    }
    let fit = interpolate_curve_at(3, &points, &params, &EndCondition::NotAKnot)
        .map_err(|e| interp_err(&piece.name, e))?;
    let curve = fit.curve();
    let mut deviation = 0.0f64;
    let mut got = [0.0; 3];
    for (k, &t) in check.iter().enumerate() {
        curve.eval_into(t, &mut got);
        let d = dist(&want[k * 3..k * 3 + 3], &got);
        if d.is_nan() {
            return Err(StepError::Unsupported(format!(
                "{}: the interpolating B-spline is not finite at t = {t}",
                piece.name
            )));
        }
        deviation = deviation.max(d);
    }
    let rows: Vec<Vec<f64>> = curve
        .control_flat()
        .chunks_exact(3)
        .map(<[f64]>::to_vec)
        .collect();
    let (knots, rows) = split::clamp(curve.degree(), curve.knots(), &rows);
    let control: Vec<[f64; 3]> = rows.iter().map(|p| [p[0], p[1], p[2]]).collect();
    let nurbs = NurbsCurve::new(curve.degree(), knots, control, None)?;
    Ok((nurbs, deviation))
}

/// The pieces as interpolating B-spline curves within `tolerance` (absolute), each refined
/// on its own. Errors: as [`surfaces`], at [`MAX_CURVE_SAMPLES`].
pub(crate) fn curves(
    pieces: &[CurvePiece<'_>],
    tolerance: f64,
) -> StepResult<Vec<(NurbsCurve, Approximation)>> {
    pieces
        .iter()
        .map(|piece| {
            let mut n = FIRST;
            loop {
                let (curve, deviation) = fit_curve(piece, n)?;
                let approximation = Approximation {
                    piece: piece.name.clone(),
                    samples: vec![n],
                    deviation,
                    tolerance,
                };
                if deviation <= tolerance {
                    return Ok((curve, approximation));
                }
                if refined(n) > MAX_CURVE_SAMPLES {
                    return Err(not_reached(&approximation));
                }
                n = refined(n);
            }
        })
        .collect()
}
