//! Surfaces to triangle meshes: a uniform grid, or an adaptive tensor grid refined until the
//! surface lies within a tolerance of the triangles; break lines always included.

use super::trimesh::{bounding_box, cross, dot, norm, sub, TriMesh};
use crate::geom::{linspace, Surface};
use crate::progress::Progress;
use crate::{Error, Result};

/// The most triangles a surface mesh may have by default ([`SurfaceOptions::max_triangles`]):
/// about 100 MB of mesh in memory and 150 MB of OBJ text, seconds of work.
pub const MAX_TRIANGLES: usize = 2_000_000;

/// Relative weld tolerance per axis: vertices closer than this fraction of the mesh's extent
/// along every axis are merged (plus [`NOISE_ULPS`] ulps of the largest coordinate).
const WELD_RELATIVE: f64 = 1e-9;

/// Rounding noise of evaluated coordinates, in units of f64's epsilon times the largest
/// |coordinate|: seams computed two ways (cos 0 and cos 2π) differ by a few of them.
const NOISE_ULPS: f64 = 16.0;

/// The default tolerance of adaptive sampling: this fraction of the model's extent along each
/// axis.
const DEFAULT_RELATIVE: f64 = 1e-3;

/// How a surface is sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Sampling {
    /// K × L equally spaced parameters (plus the break lines).
    Uniform(usize, usize),
    /// Refined until the surface at the midpoints of every grid cell's edges is within 3/4 of
    /// `tolerance` (absolute, in model units) of the edges, and at the cell's centre within
    /// 3/4 of it of the cell's two triangles, which keeps a surface that is quadratic over a
    /// triangle within `tolerance` of it everywhere (4/3 of the midpoint values at most).
    /// `None`: relative to the model's own scale, per axis: the deviation along each axis
    /// within 1/1000 of the model's extent along that axis (so a cone 1e9 high and 1 wide is
    /// still round). Stops at `max_samples` lines per direction or `max_triangles`; see
    /// [`tessellate_surface`] for what happens then.
    Adaptive {
        /// The largest allowed deviation.
        tolerance: Option<f64>,
    },
}

/// Options of [`tessellate_surface`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SurfaceOptions {
    /// Uniform or adaptive.
    pub sampling: Sampling,
    /// Faces further apart than this angle (degrees) keep separate normals (default 40).
    pub crease_degrees: f64,
    /// Grid lines per direction that adaptive sampling starts from (default 9).
    pub min_samples: usize,
    /// Most grid lines per direction adaptive sampling may reach (default 2049).
    pub max_samples: usize,
    /// Most triangles of the mesh (default [`MAX_TRIANGLES`]): the work budget.
    pub max_triangles: usize,
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions {
            sampling: Sampling::Adaptive { tolerance: None },
            crease_degrees: 40.0,
            min_samples: 9,
            max_samples: 2049,
            max_triangles: MAX_TRIANGLES,
        }
    }
}

impl SurfaceOptions {
    /// A uniform K × L grid.
    pub fn uniform(k: usize, l: usize) -> Self {
        SurfaceOptions {
            sampling: Sampling::Uniform(k, l),
            ..Self::default()
        }
    }

    /// Adaptive sampling to an absolute tolerance.
    pub fn adaptive(tolerance: f64) -> Self {
        SurfaceOptions {
            sampling: Sampling::Adaptive {
                tolerance: Some(tolerance),
            },
            ..Self::default()
        }
    }

    /// Sets the crease angle in degrees.
    pub fn with_crease_degrees(mut self, degrees: f64) -> Self {
        self.crease_degrees = degrees;
        self
    }

    /// Sets the triangle cap.
    pub fn with_max_triangles(mut self, max: usize) -> Self {
        self.max_triangles = max;
        self
    }
}

/// What [`tessellate_surface_report`] did besides the mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct MeshReport {
    /// The surface closes on itself (each side of its parameter rectangle collapses to a
    /// point or meets the opposite side), so its mesh is watertight (checked).
    pub closed: bool,
    /// Adaptive refinement stopped at the cap (triangles or lines per direction) before the
    /// tolerance was met everywhere.
    pub capped: bool,
    /// Adaptive: the largest deviation (model units) between the surface and the mesh at the
    /// checks (edge midpoints and cell centres, times 4/3 as in [`Sampling::Adaptive`]).
    pub deviation: Option<f64>,
    /// Adaptive: the same, per axis relative to the model's extent along it (the measure of
    /// the default tolerance, 1e-3).
    pub relative_deviation: Option<f64>,
    /// The weld tolerance per axis.
    pub weld: [f64; 3],
}

/// Sorted union of `values` and the `breaks` inside [a, b]; values closer than a tiny
/// fraction of the range to a break are replaced by it. O((n + m) log(n + m)).
pub(crate) fn with_breaks(mut values: Vec<f64>, breaks: &[f64], (a, b): (f64, f64)) -> Vec<f64> {
    let close = (b / 2.0 - a / 2.0).abs() * 2e-9;
    values.sort_by(f64::total_cmp);
    let mut extra = Vec::new();
    for &x in breaks {
        if x.is_finite() && x >= a && x <= b {
            // The nearest value: at the insertion point or just before it.
            let p = values.partition_point(|&y| y < x);
            let near = [p.checked_sub(1), Some(p)]
                .into_iter()
                .flatten()
                .filter(|&i| i < values.len())
                .min_by(|&i, &j| (values[i] - x).abs().total_cmp(&(values[j] - x).abs()));
            match near {
                Some(i) if (values[i] - x).abs() <= close => values[i] = x,
                _ => extra.push(x),
            }
        }
    }
    values.extend(extra);
    values.sort_by(f64::total_cmp);
    values.dedup();
    values
}

/// The surface's points on a grid, lifted to R^3.
fn grid3(s: &dyn Surface, us: &[f64], vs: &[f64]) -> Result<Vec<[f64; 3]>> {
    let d = s.dim();
    let mut raw = vec![0.0; us.len() * vs.len() * d];
    s.eval_grid(us, vs, &mut raw)?;
    let mut out = Vec::with_capacity(us.len() * vs.len());
    for (k, p) in raw.chunks_exact(d).enumerate() {
        let q = match d {
            1 => [us[k / vs.len()], vs[k % vs.len()], p[0]],
            2 => [p[0], p[1], 0.0],
            _ => [p[0], p[1], p[2]],
        };
        if q.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                what: "surface point",
                index: k,
            });
        }
        out.push(q);
    }
    Ok(out)
}

/// Grid lines in u and v and the points on them.
type Grid = (Vec<f64>, Vec<f64>, Vec<[f64; 3]>);

fn midpoints(xs: &[f64]) -> Vec<f64> {
    xs.windows(2).map(|w| 0.5 * w[0] + 0.5 * w[1]).collect()
}

fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|k| 0.5 * a[k] + 0.5 * b[k])
}

/// p minus its nearest point on the segment [a, b] (a point when a = b).
fn offset_from_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let s = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    sub(p, [a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]])
}

/// The shorter of two vectors.
fn shorter(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    if norm(b) < norm(a) {
        b
    } else {
        a
    }
}

/// p minus its nearest point on the triangle abc (on its edges when it is degenerate).
fn offset_from_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let n = cross(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    if nn > 0.0 {
        // p projects inside when it is on the inner side of all three edges.
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(x, y)| dot(cross(sub(y, x), sub(p, x)), n) >= 0.0);
        if inside {
            let f = dot(n, sub(p, a)) / nn;
            return n.map(|x| x * f);
        }
    }
    shorter(
        shorter(offset_from_segment(p, a, b), offset_from_segment(p, b, c)),
        offset_from_segment(p, c, a),
    )
}

/// The measure of adaptive refinement: a deviation vector is too far when its length exceeds
/// `absolute`, or (default tolerance) when along some axis k it exceeds `per_axis[k]`.
/// Vectors are in grid coordinates divided by `scale` (a power of two).
#[derive(Clone, Copy)]
struct Measure {
    absolute: Option<f64>,
    /// Half the extent of the model along each axis (model units; half, so that it cannot
    /// overflow), for relative deviations.
    half: [f64; 3],
}

impl Measure {
    /// (Euclidean length in model units, largest per-axis fraction of the extent) of a
    /// deviation `d` given in units of `scale`.
    fn of(&self, d: [f64; 3], scale: f64) -> (f64, f64) {
        let abs = norm(d) * scale;
        let rel = (0..3).fold(0.0f64, |m, k| {
            m.max(d[k].abs() * (scale * 0.5) / self.half[k])
        });
        (abs, rel)
    }

    fn far(&self, (abs, rel): (f64, f64)) -> bool {
        match self.absolute {
            Some(t) => abs > 0.75 * t,
            None => rel > 0.75 * DEFAULT_RELATIVE,
        }
    }
}

/// The largest deviations seen: (model units, relative).
#[derive(Default, Clone, Copy)]
struct Worst(f64, f64);

impl Worst {
    fn add(&mut self, (abs, rel): (f64, f64)) {
        self.0 = self.0.max(abs);
        self.1 = self.1.max(rel);
    }
}

/// Triangles of an nu × nv grid.
fn grid_triangles(nu: usize, nv: usize) -> usize {
    2usize
        .saturating_mul(nu.saturating_sub(1))
        .saturating_mul(nv.saturating_sub(1))
}

/// Refines `us` and `vs` until the surface at the midpoints of every cell's edges lies within
/// the measure of the edges' midpoints, and at its centre of the cell's two triangles, or
/// until the next refinement would pass `max` lines per direction or `max_triangles`.
/// Returns the grid, the largest deviations of the last round (times 4/3) and, when a cap
/// stopped it, which one.
fn adaptive_grid(
    s: &dyn Surface,
    mut us: Vec<f64>,
    mut vs: Vec<f64>,
    measure: Measure,
    (max, max_triangles): (usize, usize),
    progress: &Progress,
) -> Result<(Grid, Worst, Option<String>)> {
    loop {
        progress.add_total(1)?;
        let grid = grid3(s, &us, &vs)?;
        // Checks in coordinates divided by a power of two near the largest: no overflow.
        let scale = super::trimesh::scale_of(&grid);
        let scaled = |g: Vec<[f64; 3]>| -> Vec<[f64; 3]> {
            g.into_iter().map(|p| p.map(|x| x / scale)).collect()
        };
        let g = scaled(grid.clone());
        let (mu, mv) = (midpoints(&us), midpoints(&vs));
        let (nu, nv) = (us.len(), vs.len());
        let at = |i: usize, j: usize| g[i * nv + j];
        let mut split_u = vec![false; nu - 1];
        let mut split_v = vec![false; nv - 1];
        let mut worst = Worst::default();
        // Midpoints of u-edges (u half-way, v on grid lines).
        let eu = scaled(grid3(s, &mu, &vs)?);
        for i in 0..nu - 1 {
            for j in 0..nv {
                let m = measure.of(sub(eu[i * nv + j], mid(at(i, j), at(i + 1, j))), scale);
                worst.add(m);
                split_u[i] |= measure.far(m);
            }
        }
        let ev = scaled(grid3(s, &us, &mv)?);
        for j in 0..nv - 1 {
            for i in 0..nu {
                let m = measure.of(
                    sub(ev[i * (nv - 1) + j], mid(at(i, j), at(i, j + 1))),
                    scale,
                );
                worst.add(m);
                split_v[j] |= measure.far(m);
            }
        }
        // Cell centres against the two triangles that the triangulation will draw (split
        // along the shorter diagonal, as in `tessellate_surface`): comparing with the mean of
        // both diagonals' midpoints would miss the twist of the surface, which only the drawn
        // triangles carry.
        let ec = scaled(grid3(s, &mu, &mv)?);
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let (a, b, c, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                let q = ec[i * (nv - 1) + j];
                let off = if norm(sub(a, c)) <= norm(sub(b, e)) {
                    shorter(
                        offset_from_triangle(q, a, b, c),
                        offset_from_triangle(q, a, c, e),
                    )
                } else {
                    shorter(
                        offset_from_triangle(q, a, b, e),
                        offset_from_triangle(q, b, c, e),
                    )
                };
                let m = measure.of(off, scale);
                worst.add(m);
                if measure.far(m) && !split_u[i] && !split_v[j] {
                    split_u[i] = true;
                    split_v[j] = true;
                }
            }
        }
        progress.advance(1)?;
        let worst = Worst(worst.0 * 4.0 / 3.0, worst.1 * 4.0 / 3.0);
        let su = split_u.iter().filter(|&&b| b).count();
        let sv = split_v.iter().filter(|&&b| b).count();
        if su == 0 && sv == 0 {
            return Ok(((us, vs, grid), worst, None));
        }
        let fits = |nu: usize, nv: usize| {
            nu <= max.max(us.len())
                && nv <= max.max(vs.len())
                && grid_triangles(nu, nv) <= max_triangles
        };
        // Both directions if they fit, else the one that does (u first), else stop.
        let (any_u, any_v) = if fits(nu + su, nv + sv) {
            (su > 0, sv > 0)
        } else if su > 0 && fits(nu + su, nv) {
            (true, false)
        } else if sv > 0 && fits(nu, nv + sv) {
            (false, true)
        } else {
            let cap = if grid_triangles(nu + su.min(1), nv + sv.min(1)) > max_triangles
                || (nu < max && nv < max)
            {
                format!("{max_triangles} triangles")
            } else {
                format!("{max} grid lines per direction")
            };
            return Ok(((us, vs, grid), worst, Some(cap)));
        };
        let refine = |xs: &[f64], mids: &[f64], split: &[bool]| {
            let mut out = Vec::with_capacity(xs.len() * 2);
            for k in 0..xs.len() - 1 {
                out.push(xs[k]);
                if split[k] {
                    out.push(mids[k]);
                }
            }
            out.push(xs[xs.len() - 1]);
            out
        };
        if any_u {
            us = refine(&us, &mu, &split_u);
        }
        if any_v {
            vs = refine(&vs, &mv, &split_v);
        }
    }
}

/// Half the extent of `points` along each axis (half, so that ±f64::MAX do not overflow),
/// and the largest |coordinate| along each.
fn half_extents(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let (lo, hi) = bounding_box(points);
    let half = [0, 1, 2].map(|k| hi[k] / 2.0 - lo[k] / 2.0);
    let big = [0, 1, 2].map(|k| lo[k].abs().max(hi[k].abs()));
    (half, big)
}

/// The weld tolerance per axis: [`WELD_RELATIVE`] of the extent along the axis plus
/// [`NOISE_ULPS`] ulps of the largest coordinate of any axis (rounding noise crosses axes:
/// r sin 2π is 2.4e-16 r along y however flat the points are along y).
fn weld_tolerance(points: &[[f64; 3]]) -> [f64; 3] {
    let (half, big) = half_extents(points);
    let noise = NOISE_ULPS * f64::EPSILON * big.iter().fold(0.0f64, |m, &b| m.max(b));
    half.map(|h| 2.0 * WELD_RELATIVE * h + noise)
}

/// Whether the grid's parameter rectangle closes on itself: each of its four sides either
/// collapses to one point (a pole) or meets the opposite side point by point (a seam),
/// within the weld tolerance.
fn closes(grid: &[[f64; 3]], nu: usize, nv: usize, weld: [f64; 3]) -> bool {
    let near = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() <= weld[k]);
    let at = |i: usize, j: usize| grid[i * nv + j];
    let u_side = |i: usize| (0..nv).all(|j| near(at(i, j), at(i, 0)));
    let v_side = |j: usize| (0..nu).all(|i| near(at(i, j), at(0, j)));
    let u_seam = (0..nv).all(|j| near(at(0, j), at(nu - 1, j)));
    let v_seam = (0..nu).all(|i| near(at(i, 0), at(i, nv - 1)));
    (u_seam || (u_side(0) && u_side(nu - 1))) && (v_seam || (v_side(0) && v_side(nv - 1)))
}

/// Triangulates a surface.
///
/// The grid includes the surface's break lines; each cell is split along its shorter
/// diagonal into two triangles oriented like (∂/∂u × ∂/∂v); coincident vertices are welded
/// per axis within 1e-9 of the mesh's extent along that axis plus 16 ulps of its largest
/// coordinate (closing seams and collapsing poles without merging the two faces of a
/// 1e-9 × 1 × 1 box; features below 16 ulps of the model's size, an aspect ratio beyond
/// about 3e14, are merged), and a closed result is oriented outwards. See the
/// [module docs](super) for the normals.
///
/// The mesh keeps its promises or is an error ([`Error::MeshFailed`]): it has triangles, and
/// when the surface closes on itself (every side of its parameter rectangle collapses to a
/// point or meets the opposite side, as on the bodies) it is watertight. A model too thin or
/// too small for f64 at its own size (a cylinder of radius 1e-308 and height 2) is an error
/// rather than an empty or leaking mesh.
///
/// Work is bounded by `max_triangles` ([`MAX_TRIANGLES`] = 2 000 000 by default): a uniform
/// grid (with its break lines) above it is an error ([`Error::MeshTooLarge`]); adaptive
/// refinement stops before it. Stopped there, an explicit tolerance is an error naming the
/// deviation reached ([`Error::ToleranceOutOfReach`]: the caller asked for a guarantee the
/// mesh cannot give); with the default tolerance the mesh is returned and
/// [`tessellate_surface_report`] says it was capped and how far it deviates. A tolerance
/// below f64's resolution at the model's size (16 ulps of its largest coordinate) is refused
/// at once ([`Error::ToleranceBelowResolution`]).
///
/// Errors: also sample counts below 2 or above 2^15 per direction, a tolerance that is not
/// finite and > 0, a surface of dimension other than 1, 2 or 3 ([`Error::WrongDimension`]),
/// a non-finite surface point ([`Error::NonFinite`]).
///
/// ```
/// use geomkit::bezier::BezierSurface;
/// use geomkit::mesh::{tessellate_surface, SurfaceOptions};
/// let s = BezierSurface::new(vec![
///     vec![vec![0., 0., 0.], vec![0., 1., 0.]],
///     vec![vec![1., 0., 0.], vec![1., 1., 1.]],
/// ]).unwrap();
/// let m = tessellate_surface(&s, &SurfaceOptions::uniform(5, 5)).unwrap();
/// assert_eq!((m.positions().len(), m.triangles().len()), (25, 32));
/// assert_eq!(m.boundary_edge_count(), 16);
/// ```
pub fn tessellate_surface(s: &dyn Surface, options: &SurfaceOptions) -> Result<TriMesh> {
    tessellate_surface_report(s, options).map(|(mesh, _)| mesh)
}

/// [`tessellate_surface`] with its [`MeshReport`]: whether the surface closes, whether the
/// triangle cap stopped adaptive refinement, the deviation reached, the weld tolerance.
///
/// ```
/// use geomkit::compose::bodies;
/// use geomkit::mesh::{tessellate_surface_report, SurfaceOptions};
/// let cone = bodies::cone(1.0, 1e9).unwrap();
/// let (mesh, report) = tessellate_surface_report(&cone, &SurfaceOptions::default()).unwrap();
/// assert!(report.closed && mesh.is_watertight() && !report.capped);
/// assert!(report.relative_deviation.unwrap() <= 1e-3);
/// ```
pub fn tessellate_surface_report(
    s: &dyn Surface,
    options: &SurfaceOptions,
) -> Result<(TriMesh, MeshReport)> {
    tessellate_surface_with_progress(s, options, &Progress::none())
}

/// [`tessellate_surface_report`] reporting to `progress` ([`crate::progress`]): one unit
/// for the sample grid (adaptive refinement: one per round, each round adding its unit to
/// the total as it starts, since the number of rounds is not known ahead) and one for the
/// triangulation and welding. The same mesh, bit for bit, as without it;
/// [`Error::Cancelled`] when the callback asks to stop.
pub fn tessellate_surface_with_progress(
    s: &dyn Surface,
    options: &SurfaceOptions,
    progress: &Progress,
) -> Result<(TriMesh, MeshReport)> {
    let d = s.dim();
    if !(1..=3).contains(&d) {
        return Err(Error::WrongDimension {
            operation: "tessellation of a surface",
            expected: 3,
            got: d,
        });
    }
    const MAX: usize = 1 << 15;
    let cap = options.max_triangles;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (bu, bv) = s.breaks();
    // k × l equally spaced lines plus the breaks; more triangles than the cap is an error
    // whose subject `what` gives.
    let lines = |k: usize, l: usize, what: &dyn Fn(usize, usize) -> String| {
        let us = with_breaks(linspace(u0, u1, k), &bu, (u0, u1));
        let vs = with_breaks(linspace(v0, v1, l), &bv, (v0, v1));
        let (nu, nv) = (us.len(), vs.len());
        if grid_triangles(nu, nv) > cap {
            return Err(Error::MeshTooLarge {
                what: what(nu, nv),
                count: grid_triangles(nu, nv),
                unit: "triangles",
                max: cap,
            });
        }
        Ok((us, vs))
    };
    let (us, vs, grid, deviation) = match options.sampling {
        Sampling::Uniform(k, l) => {
            for n in [k, l] {
                if !(2..=MAX).contains(&n) {
                    return Err(Error::InvalidOption {
                        option: "sample count",
                        reason: "must be from 2 to 32768 per direction",
                    });
                }
            }
            let (us, vs) = lines(k, l, &|nu, nv| {
                format!("a {k} × {l} sample grid ({nu} × {nv} with the break lines)")
            })?;
            progress.add_total(1)?;
            let grid = grid3(s, &us, &vs)?;
            progress.advance(1)?;
            (us, vs, grid, None)
        }
        Sampling::Adaptive { tolerance } => {
            let start = options.min_samples.clamp(2, MAX);
            let (us, vs) = lines(start, start, &|nu, nv| {
                format!("the surface's break lines ({nu} × {nv} grid lines)")
            })?;
            let mut probe = grid3(s, &linspace(u0, u1, 33), &linspace(v0, v1, 33))?;
            probe.extend(grid3(s, &us, &vs)?);
            let (half, big) = half_extents(&probe);
            let widest = half.iter().fold(0.0f64, |m, &h| m.max(h));
            if widest == 0.0 {
                let p = probe[0];
                return Err(Error::MeshFailed {
                    check: "empty",
                    reason: format!(
                        "every sampled point of the surface is ({}, {}, {})",
                        p[0], p[1], p[2]
                    ),
                });
            }
            let resolution = NOISE_ULPS * f64::EPSILON * big.iter().fold(0.0f64, |m, &b| m.max(b));
            if let Some(t) = tolerance {
                if !(t.is_finite() && t > 0.0) {
                    return Err(Error::InvalidTolerance { value: t });
                }
                if t < resolution {
                    return Err(Error::ToleranceBelowResolution {
                        tolerance: t,
                        resolution,
                    });
                }
            }
            // Per-axis extents for the default tolerance, an axis along which the surface is
            // flat counting as 1e-12 of the widest (its rounding noise is not refined).
            let measure = Measure {
                absolute: tolerance,
                half: half.map(|h| h.max(widest * 1e-12)),
            };
            // The checks run at 3/4 of the tolerance: where the surface is quadratic over a
            // triangle, its distance from the triangle is at most 4/3 of the largest one at
            // the midpoints of the triangle's edges (the quadratic Lagrange basis on a triangle).
            let ((us, vs, grid), worst, capped) = adaptive_grid(
                s,
                us,
                vs,
                measure,
                (options.max_samples.clamp(2, MAX), cap),
                progress,
            )?;
            if let (Some(t), Some(cap)) = (tolerance, &capped) {
                return Err(Error::ToleranceOutOfReach {
                    tolerance: t,
                    reached: worst.0,
                    cap: cap.clone(),
                });
            }
            (us, vs, grid, Some((worst, capped.is_some())))
        }
    };
    progress.add_total(1)?;
    let (nu, nv) = (us.len(), vs.len());
    let mut triangles = Vec::with_capacity(grid_triangles(nu, nv));
    for i in 0..nu - 1 {
        for j in 0..nv - 1 {
            let a = (i * nv + j) as u32;
            let b = ((i + 1) * nv + j) as u32;
            let c = ((i + 1) * nv + j + 1) as u32;
            let e = (i * nv + j + 1) as u32;
            let p = |k: u32| grid[k as usize];
            if norm(sub(p(a), p(c))) <= norm(sub(p(b), p(e))) {
                triangles.push([a, b, c]);
                triangles.push([a, c, e]);
            } else {
                triangles.push([a, b, e]);
                triangles.push([b, c, e]);
            }
        }
    }
    let weld = weld_tolerance(&grid);
    let closed = closes(&grid, nu, nv, weld);
    let grid_count = triangles.len();
    let mut mesh = TriMesh::new_per_axis(grid, triangles, weld, options.crease_degrees)?;
    progress.advance(1)?;
    let weld_text = || {
        format!(
            "weld tolerance {:.1e}, {:.1e}, {:.1e} in x, y, z",
            weld[0], weld[1], weld[2]
        )
    };
    if mesh.triangles().is_empty() {
        return Err(Error::MeshFailed {
            check: "empty",
            reason: format!(
                "all {grid_count} triangles collapsed when coincident vertices were merged \
                 ({}): the model is too thin or too small for f64 at its own size",
                weld_text()
            ),
        });
    }
    if closed {
        if !mesh.is_watertight() {
            return Err(Error::MeshFailed {
                check: "not watertight",
                reason: format!(
                    "the surface closes on itself but {} edges of its mesh are not shared by \
                     exactly two triangles ({}): the model is too thin or too small for f64 at \
                     its own size",
                    mesh.unpaired_edge_count(),
                    weld_text()
                ),
            });
        }
        if mesh.volume() < 0.0 {
            mesh.flip();
        }
        // NaN cannot occur (finite positions); 0 is a collapsed body.
        if mesh.volume() <= 0.0 {
            return Err(Error::MeshFailed {
                check: "without volume",
                reason: format!(
                    "the surface closes on itself but its mesh encloses a volume of {:e} in \
                     f64 ({}): the model is too thin or too small for f64 at its own size",
                    mesh.volume(),
                    weld_text()
                ),
            });
        }
    }
    let report = MeshReport {
        closed,
        capped: deviation.is_some_and(|(_, c)| c),
        deviation: deviation.map(|(w, _)| w.0),
        relative_deviation: deviation.map(|(w, _)| w.1),
        weld,
    };
    progress.finish()?;
    Ok((mesh, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compose::bodies;

    #[test]
    fn breaks_are_merged_into_the_grid() {
        let xs = with_breaks(linspace(0.0, 4.0, 4), &[1.0, 2.0, 3.0, 9.0], (0.0, 4.0));
        assert_eq!(xs.len(), 7);
        assert!(xs.contains(&1.0) && xs.contains(&3.0));
    }

    #[test]
    fn cube_from_a_coarse_grid_keeps_its_edges() {
        let cube = bodies::cube().unwrap();
        // 3 samples in u miss u = 1 and 3: the breaks put them back.
        let m = tessellate_surface(&cube, &SurfaceOptions::uniform(3, 2)).unwrap();
        assert!(m.is_watertight());
        assert!((m.volume() - 8.0).abs() < 1e-12);
        assert!((m.area() - 24.0).abs() < 1e-12);
    }
}
