//! Seams of a surface: the lines u = const and v = const where it may fail to be smooth
//! (its [`Surface::breaks`]: the knots of a composite surface's grid, the curves and polygon
//! vertices of a ruled surface, a B-spline's knots), each split at the breaks of the other
//! direction, and how smooth the surface is across each piece: C^k with the first
//! cross-derivative that jumps, found by comparing the one-sided derivatives
//! ∂^k S/∂u^k (u-lines) or ∂^k S/∂v^k (v-lines) on both sides at points along the piece.
//! This is the "continuity on the surface" of spec/composite-surfaces.md made visible: formula
//! (9) keeps the surface C^0 (it shifts patches that do not meet), so what is left to know is
//! the order of smoothness along each line.
//!
//! A surface whose opposite edges coincide (a closed body: u = u0 and u = u1 are the same
//! points) gets that line as a seam too, its two sides being the two edges.
//!
//! The comparison is sampled (a jump between the samples is missed) and each order's
//! tolerance is relative: `tolerance` times the larger of the largest derivative sampled and
//! (extent of the surface) / (width of the narrower neighbouring cell)^k, so rounding in the
//! one-sided derivatives (taken 10⁻⁹ of a cell width off the line) does not count.
//!
//! ```
//! use geomkit::compose::{bodies, seams, SeamOptions, Smoothness};
//! // The cube of Dolya's paper: every edge is a crease (C^0), nothing jumps.
//! let cube = bodies::cube().unwrap();
//! let found = seams(&cube, &SeamOptions::default()).unwrap();
//! assert!(!found.is_empty());
//! assert!(found.iter().all(|s| s.smoothness == Smoothness::C(0)));
//! ```

use crate::geom::Surface;
use crate::{Error, Result};

/// Options of [`seams`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SeamOptions {
    /// Highest order of derivative compared (default 3): a seam smooth up to it is
    /// [`Smoothness::Smooth`].
    pub max_order: usize,
    /// Points compared along each piece of a line (default 17, inside the piece).
    pub samples: usize,
    /// Relative tolerance of a jump (default 1e-6; see the module doc).
    pub tolerance: f64,
}

impl Default for SeamOptions {
    fn default() -> Self {
        SeamOptions {
            max_order: 3,
            samples: 17,
            tolerance: 1e-6,
        }
    }
}

impl SeamOptions {
    /// Sets [`SeamOptions::max_order`].
    pub fn with_max_order(mut self, max_order: usize) -> Self {
        self.max_order = max_order;
        self
    }

    /// Sets [`SeamOptions::samples`].
    pub fn with_samples(mut self, samples: usize) -> Self {
        self.samples = samples;
        self
    }

    /// Sets [`SeamOptions::tolerance`].
    pub fn with_tolerance(mut self, tolerance: f64) -> Self {
        self.tolerance = tolerance;
        self
    }
}

/// How smooth a surface is across a seam.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Smoothness {
    /// The two sides do not meet.
    Discontinuous,
    /// C^k and not C^(k+1): the (k+1)-th cross-derivative jumps.
    C(usize),
    /// No jump up to [`SeamOptions::max_order`].
    Smooth,
}

/// Which parameter is constant along a seam.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeamLine {
    /// u = value, running along v.
    U,
    /// v = value, running along u.
    V,
}

/// One piece of a seam line, between two breaks of the other direction.
#[derive(Debug, Clone, PartialEq)]
pub struct Seam {
    /// u-line or v-line.
    pub line: SeamLine,
    /// The constant parameter (for the closing seam of a closed surface: the domain's
    /// start, its other side being the end).
    pub value: f64,
    /// The piece: the other parameter runs over [from, to].
    pub from: f64,
    /// See `from`.
    pub to: f64,
    /// Whether this is the line where the surface closes on itself (u0 ~ u1 or v0 ~ v1).
    pub closing: bool,
    /// How smooth the surface is across the piece (in its parameters).
    pub smoothness: Smoothness,
    /// Whether the tangent plane is continuous across the piece (geometric continuity G1,
    /// which C1 implies): false on a crease, true where only the parametrization kinks
    /// (a C0 line inside a flat face). Points where the surface is singular (S_u × S_v = 0)
    /// are skipped.
    pub tangent_continuous: bool,
    /// The largest jump of the cross-derivative of each order 0..=checked (Euclidean
    /// norm), up to the first that exceeds its tolerance.
    pub jumps: Vec<f64>,
    /// The tolerance each of those was compared with.
    pub tolerances: Vec<f64>,
}

/// The seams of a surface and their smoothness (see the module doc).
///
/// Errors: `samples` < 1 or a tolerance that is not finite and > 0
/// ([`Error::InvalidOption`]); the surface's derivatives' errors (a type that has none
/// beyond order 0 answers [`Error::Unsupported`]).
pub fn seams(surface: &dyn Surface, options: &SeamOptions) -> Result<Vec<Seam>> {
    if options.samples == 0 {
        return Err(Error::InvalidOption {
            option: "samples",
            reason: "at least one point per seam piece",
        });
    }
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(Error::InvalidOption {
            option: "tolerance",
            reason: "must be finite and > 0",
        });
    }
    let ((u0, u1), (v0, v1)) = surface.domain();
    let (bu, bv) = surface.breaks();
    let lines_u = interior(&bu, u0, u1);
    let lines_v = interior(&bv, v0, v1);
    let extent = extent(surface, (u0, u1), (v0, v1))?;
    let mut out = Vec::new();
    for line in [SeamLine::U, SeamLine::V] {
        let ((a0, a1), (b0, b1), across, along) = match line {
            SeamLine::U => ((u0, u1), (v0, v1), &lines_u, &lines_v),
            SeamLine::V => ((v0, v1), (u0, u1), &lines_v, &lines_u),
        };
        // The pieces along the line: between the other direction's breaks.
        let mut cuts = vec![b0];
        cuts.extend(along.iter().copied());
        cuts.push(b1);
        // Every interior line, and the closing line when the edges coincide.
        let mut candidates: Vec<(f64, f64, f64, bool)> = Vec::new();
        for (k, &c) in across.iter().enumerate() {
            let left = c - if k == 0 { a0 } else { across[k - 1] };
            let right = across.get(k + 1).copied().unwrap_or(a1) - c;
            candidates.push((c, c, left.min(right), false));
        }
        if closes(surface, line, (a0, a1), (b0, b1), extent)? {
            let first = across.first().copied().unwrap_or(a1) - a0;
            let last = a1 - across.last().copied().unwrap_or(a0);
            candidates.push((a0, a1, first.min(last), true));
        }
        for (start, end, width, closing) in candidates {
            for piece in cuts.windows(2) {
                let (from, to) = (piece[0], piece[1]);
                if to <= from {
                    continue;
                }
                let (smoothness, jumps, tolerances) = classify(
                    surface,
                    line,
                    (start, end),
                    (from, to),
                    width,
                    extent,
                    options,
                )?;
                let tangent_continuous = match smoothness {
                    Smoothness::Discontinuous => false,
                    Smoothness::C(0) => tangent_plane_continuous(
                        surface,
                        line,
                        (start, end),
                        (from, to),
                        width,
                        options,
                    )?,
                    _ => true,
                };
                out.push(Seam {
                    line,
                    value: start,
                    from,
                    to,
                    closing,
                    smoothness,
                    tangent_continuous,
                    jumps,
                    tolerances,
                });
            }
        }
    }
    Ok(out)
}

/// The breaks strictly inside (a, b), sorted, without repeats.
fn interior(breaks: &[f64], a: f64, b: f64) -> Vec<f64> {
    let gap = 1e-12 * (b - a).abs().max(f64::MIN_POSITIVE);
    let mut v: Vec<f64> = breaks
        .iter()
        .copied()
        .filter(|&x| x.is_finite() && x > a + gap && x < b - gap)
        .collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|x, y| (*x - *y).abs() <= gap);
    v
}

/// The largest coordinate of the surface on a 9 × 9 grid (at least the smallest normal).
fn extent(s: &dyn Surface, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> Result<f64> {
    let us = crate::geom::linspace(u0, u1, 9);
    let vs = crate::geom::linspace(v0, v1, 9);
    let mut out = vec![0.0; 81 * s.dim()];
    s.eval_grid(&us, &vs, &mut out)?;
    Ok(out.iter().fold(
        f64::MIN_POSITIVE,
        |m, x| if x.abs() > m { x.abs() } else { m },
    ))
}

/// The point or derivative of order (k along `line`'s cross direction) at (a, b) in the
/// line's coordinates (a across, b along).
fn partial(
    s: &dyn Surface,
    line: SeamLine,
    a: f64,
    b: f64,
    k: usize,
    out: &mut [f64],
) -> Result<()> {
    match line {
        SeamLine::U => s.derivative_into(a, b, (k, 0), out),
        SeamLine::V => s.derivative_into(b, a, (0, k), out),
    }
}

/// Whether the edge a = a0 coincides with a = a1 (a closed surface).
fn closes(
    s: &dyn Surface,
    line: SeamLine,
    (a0, a1): (f64, f64),
    (b0, b1): (f64, f64),
    extent: f64,
) -> Result<bool> {
    let d = s.dim();
    let (mut p, mut q) = (vec![0.0; d], vec![0.0; d]);
    for b in crate::geom::linspace(b0, b1, 9) {
        partial(s, line, a0, b, 0, &mut p)?;
        partial(s, line, a1, b, 0, &mut q)?;
        if distance(&p, &q) > 1e-9 * extent {
            return Ok(false);
        }
    }
    Ok(true)
}

fn distance(p: &[f64], q: &[f64]) -> f64 {
    p.iter()
        .zip(q)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

/// The smoothness across one piece: the line's two sides are a = `start` − δ (the cell
/// before) and a = `end` + δ (the cell after; `end` = `start` except on a closing line).
#[allow(clippy::type_complexity)]
fn classify(
    s: &dyn Surface,
    line: SeamLine,
    (start, end): (f64, f64),
    (from, to): (f64, f64),
    width: f64,
    extent: f64,
    options: &SeamOptions,
) -> Result<(Smoothness, Vec<f64>, Vec<f64>)> {
    let d = s.dim();
    let delta = 1e-9 * width;
    let closing = start != end;
    // The closing line: the side after the start, and the side before the end.
    let (after, before) = if closing {
        (start + delta, end - delta)
    } else {
        (start + delta, start - delta)
    };
    let n = options.samples;
    let along: Vec<f64> = (0..n)
        .map(|i| from + (to - from) * (i as f64 + 0.5) / n as f64)
        .collect();
    let (mut p, mut q) = (vec![0.0; d], vec![0.0; d]);
    let (mut jumps, mut tolerances) = (Vec::new(), Vec::new());
    for k in 0..=options.max_order {
        let (mut jump, mut size) = (0.0f64, 0.0f64);
        for &b in &along {
            partial(s, line, before, b, k, &mut p)?;
            partial(s, line, after, b, k, &mut q)?;
            if p.iter().chain(&q).any(|x| !x.is_finite()) {
                return Err(Error::NonFinite {
                    what: "seam derivative",
                    index: k,
                });
            }
            jump = jump.max(distance(&p, &q));
            size = size.max(norm(&p)).max(norm(&q));
        }
        let tolerance = options.tolerance * size.max(extent / width.powi(k as i32));
        jumps.push(jump);
        tolerances.push(tolerance);
        if jump > tolerance {
            let smoothness = match k {
                0 => Smoothness::Discontinuous,
                _ => Smoothness::C(k - 1),
            };
            return Ok((smoothness, jumps, tolerances));
        }
    }
    Ok((Smoothness::Smooth, jumps, tolerances))
}

/// The unit normal of the surface (a height field's graph) at (a, b) in the line's
/// coordinates; `None` where S_u × S_v vanishes.
fn unit_normal(s: &dyn Surface, line: SeamLine, a: f64, b: f64) -> Result<Option<[f64; 3]>> {
    let d = s.dim();
    let (mut su, mut sv) = ([0.0; 3], [0.0; 3]);
    let (u, v) = match line {
        SeamLine::U => (a, b),
        SeamLine::V => (b, a),
    };
    s.derivative_into(u, v, (1, 0), &mut su[..d])?;
    s.derivative_into(u, v, (0, 1), &mut sv[..d])?;
    if d == 1 {
        su = [1.0, 0.0, su[0]];
        sv = [0.0, 1.0, sv[0]];
    }
    let c = [
        su[1] * sv[2] - su[2] * sv[1],
        su[2] * sv[0] - su[0] * sv[2],
        su[0] * sv[1] - su[1] * sv[0],
    ];
    let len = norm(&c);
    let scale = norm(&su) * norm(&sv);
    Ok((len.is_finite() && len > 1e-9 * scale).then(|| c.map(|x| x / len)))
}

/// Whether the unit normals on both sides agree (within 1e-6 rad) along the piece.
fn tangent_plane_continuous(
    s: &dyn Surface,
    line: SeamLine,
    (start, end): (f64, f64),
    (from, to): (f64, f64),
    width: f64,
    options: &SeamOptions,
) -> Result<bool> {
    let delta = 1e-9 * width;
    let (after, before) = if start != end {
        (start + delta, end - delta)
    } else {
        (start + delta, start - delta)
    };
    let n = options.samples;
    for i in 0..n {
        let b = from + (to - from) * (i as f64 + 0.5) / n as f64;
        let (Some(p), Some(q)) = (
            unit_normal(s, line, before, b)?,
            unit_normal(s, line, after, b)?,
        ) else {
            continue;
        };
        if distance(&p, &q) > 1e-6 {
            return Ok(false);
        }
    }
    Ok(true)
}

fn norm(p: &[f64]) -> f64 {
    p.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bezier::BezierSurface;
    use crate::bspline::BsplineSurface;
    use crate::compose::{bodies, CompositeSurface};

    /// A bicubic B-spline surface on knots with one simple interior knot in u (0.4) and a
    /// double one in v (0.5): by the theory of splines (de Boor) it is C^2 across u = 0.4
    /// and C^1 across v = 0.5.
    fn spline() -> BsplineSurface {
        let ku = vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0];
        let kv = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        let (nu, nv) = (5, 6);
        let net: Vec<f64> = (0..nu)
            .flat_map(|i| {
                (0..nv).flat_map(move |j| {
                    let z = ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.4;
                    [i as f64, j as f64, z]
                })
            })
            .collect();
        BsplineSurface::from_flat((3, 3), ku, kv, nu, nv, 3, net).unwrap()
    }

    #[test]
    fn spline_seams_have_the_smoothness_of_their_knots() {
        let s = spline();
        let found = seams(&s, &SeamOptions::default()).unwrap();
        let u: Vec<_> = found.iter().filter(|x| x.line == SeamLine::U).collect();
        let v: Vec<_> = found.iter().filter(|x| x.line == SeamLine::V).collect();
        // u = 0.4 in two pieces (v split at 0.5), v = 0.5 in two pieces (u split at 0.4).
        assert_eq!(u.len(), 2);
        assert_eq!(v.len(), 2);
        assert!(u
            .iter()
            .all(|x| x.value == 0.4 && x.smoothness == Smoothness::C(2)));
        assert!(v
            .iter()
            .all(|x| x.value == 0.5 && x.smoothness == Smoothness::C(1)));
        assert_eq!(
            (u[0].from, u[0].to, u[1].from, u[1].to),
            (0.0, 0.5, 0.5, 1.0)
        );
    }

    #[test]
    fn composite_patches_meeting_at_a_crease_are_c0_and_smooth_continuations_smooth() {
        let a = BezierSurface::new(vec![
            vec![vec![0., 0., 0.], vec![0., 1., 0.]],
            vec![vec![1., 0., 0.], vec![1., 1., 1.]],
        ])
        .unwrap();
        let b = BezierSurface::new(vec![
            vec![vec![1., 0., 0.], vec![1., 1., 1.]],
            vec![vec![2., 0., 0.], vec![2., 1., 0.]],
        ])
        .unwrap();
        let s = CompositeSurface::from_bezier(
            vec![0., 1., 2.],
            vec![0., 1.],
            &[vec![a.clone()], vec![b]],
        )
        .unwrap();
        let found = seams(&s, &SeamOptions::default()).unwrap();
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].smoothness, Smoothness::C(0));
        assert_eq!((found[0].line, found[0].value), (SeamLine::U, 1.0));
        // A second patch continuing the first's plane z = u v smoothly: at u = 1 both have
        // S_u = (1, 0, v) and S_uu = 0, so nothing jumps up to order 3.
        let shifted = BezierSurface::new(vec![
            vec![vec![1., 0., 0.], vec![1., 1., 1.]],
            vec![vec![2., 0., 0.], vec![2., 1., 2.]],
        ])
        .unwrap();
        let s = CompositeSurface::from_bezier(
            vec![0., 1., 2.],
            vec![0., 1.],
            &[vec![a], vec![shifted]],
        )
        .unwrap();
        let found = seams(&s, &SeamOptions::default()).unwrap();
        assert_eq!(found[0].smoothness, Smoothness::Smooth);
    }

    #[test]
    fn closed_bodies_have_their_closing_line_and_cylinders_are_smooth_around() {
        let cyl = bodies::cylinder(1.0, 2.0).unwrap();
        let found = seams(&cyl, &SeamOptions::default()).unwrap();
        // Around (the closing u-line of the side): smooth; the rims (v-lines): creases.
        assert!(found
            .iter()
            .filter(|s| s.line == SeamLine::U)
            .all(|s| s.closing && s.smoothness == Smoothness::Smooth));
        let rims: Vec<_> = found.iter().filter(|s| s.line == SeamLine::V).collect();
        assert!(!rims.is_empty());
        assert!(rims.iter().any(|s| s.smoothness == Smoothness::C(0)));
        // The cube: the lines from the caps' centres to the corners lie inside the flat top
        // and bottom faces (C0 in the parameters, tangent plane continuous); the edges are
        // creases: 4 vertical ones (3 inner vertex lines and the closing line) and the 2
        // rims of 4 sides each.
        let cube = bodies::cube().unwrap();
        let found = seams(&cube, &SeamOptions::default()).unwrap();
        assert!(found.iter().any(|s| s.closing));
        let creases: Vec<_> = found.iter().filter(|s| !s.tangent_continuous).collect();
        let inside: Vec<_> = found.iter().filter(|s| s.tangent_continuous).collect();
        assert_eq!(creases.len(), 4 + 2 * 4);
        assert_eq!(inside.len(), 2 * 4);
        assert!(found.iter().all(|s| s.smoothness == Smoothness::C(0)));
    }

    #[test]
    fn bad_options_are_errors() {
        let s = spline();
        assert!(seams(&s, &SeamOptions::default().with_samples(0)).is_err());
        assert!(seams(&s, &SeamOptions::default().with_tolerance(f64::NAN)).is_err());
    }
}
