//! Surfaces to triangle meshes: a uniform grid, or an adaptive tensor grid refined until the
//! surface lies within a tolerance of the triangles; break lines always included.

use super::trimesh::{bounding_box, cross, dot, norm, sub, TriMesh};
use crate::geom::{linspace, Surface};
use crate::{Error, Result};

/// How a surface is sampled.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Sampling {
    /// K × L equally spaced parameters (plus the break lines).
    Uniform(usize, usize),
    /// Refined until the surface at the midpoints of every grid cell's edges is within 3/4 of
    /// `tolerance` (absolute, in model units) of the edges, and at the cell's centre within
    /// 3/4 of it of the cell's two triangles, which keeps a surface that is quadratic over a
    /// triangle within `tolerance` of it everywhere (4/3 of the midpoint values at most);
    /// `None`: 1/1000 of the diagonal of the bounding box. Stops at `max_samples`.
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
}

impl Default for SurfaceOptions {
    fn default() -> Self {
        SurfaceOptions {
            sampling: Sampling::Adaptive { tolerance: None },
            crease_degrees: 40.0,
            min_samples: 9,
            max_samples: 2049,
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
}

/// Sorted union of `values` and the `breaks` inside [a, b]; values closer than a tiny
/// fraction of the range to a break are replaced by it.
pub(crate) fn with_breaks(mut values: Vec<f64>, breaks: &[f64], (a, b): (f64, f64)) -> Vec<f64> {
    let close = (b - a).abs() * 1e-9;
    for &x in breaks {
        if x.is_finite() && x >= a && x <= b {
            match values.iter().position(|&y| (y - x).abs() <= close) {
                Some(p) => values[p] = x,
                None => values.push(x),
            }
        }
    }
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
    xs.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
}

fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        0.5 * (a[0] + b[0]),
        0.5 * (a[1] + b[1]),
        0.5 * (a[2] + b[2]),
    ]
}

/// Distance from `p` to the segment [a, b] (a point when a = b).
fn distance_to_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let s = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(
        p,
        [a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]],
    ))
}

/// Distance from `p` to the triangle abc (to its edges when it is degenerate).
fn distance_to_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let n = cross(sub(b, a), sub(c, a));
    let nn = dot(n, n);
    if nn > 0.0 {
        // p projects inside when it is on the inner side of all three edges.
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(x, y)| dot(cross(sub(y, x), sub(p, x)), n) >= 0.0);
        if inside {
            return dot(n, sub(p, a)).abs() / nn.sqrt();
        }
    }
    distance_to_segment(p, a, b)
        .min(distance_to_segment(p, b, c))
        .min(distance_to_segment(p, c, a))
}

/// Refines `us` and `vs` until the surface at the midpoints of every cell's edges lies within
/// `tol` of the edges' midpoints, and at its centre within `tol` of the cell's two triangles.
fn adaptive_grid(
    s: &dyn Surface,
    mut us: Vec<f64>,
    mut vs: Vec<f64>,
    tol: f64,
    max: usize,
) -> Result<Grid> {
    loop {
        let grid = grid3(s, &us, &vs)?;
        let (mu, mv) = (midpoints(&us), midpoints(&vs));
        let (nu, nv) = (us.len(), vs.len());
        let at = |i: usize, j: usize| grid[i * nv + j];
        let mut split_u = vec![false; nu - 1];
        let mut split_v = vec![false; nv - 1];
        // Midpoints of u-edges (u half-way, v on grid lines).
        let eu = grid3(s, &mu, &vs)?;
        for i in 0..nu - 1 {
            split_u[i] =
                (0..nv).any(|j| norm(sub(eu[i * nv + j], mid(at(i, j), at(i + 1, j)))) > tol);
        }
        let ev = grid3(s, &us, &mv)?;
        for j in 0..nv - 1 {
            split_v[j] =
                (0..nu).any(|i| norm(sub(ev[i * (nv - 1) + j], mid(at(i, j), at(i, j + 1)))) > tol);
        }
        // Cell centres against the two triangles that the triangulation will draw (split
        // along the shorter diagonal, as in `tessellate_surface`): comparing with the mean of
        // both diagonals' midpoints would miss the twist of the surface, which only the drawn
        // triangles carry.
        let ec = grid3(s, &mu, &mv)?;
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let (a, b, c, e) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                let q = ec[i * (nv - 1) + j];
                let off = if norm(sub(a, c)) <= norm(sub(b, e)) {
                    distance_to_triangle(q, a, b, c).min(distance_to_triangle(q, a, c, e))
                } else {
                    distance_to_triangle(q, a, b, e).min(distance_to_triangle(q, b, c, e))
                };
                if off > tol && !split_u[i] && !split_v[j] {
                    split_u[i] = true;
                    split_v[j] = true;
                }
            }
        }
        let room_u = us.len() + split_u.iter().filter(|&&b| b).count() <= max;
        let room_v = vs.len() + split_v.iter().filter(|&&b| b).count() <= max;
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
        let any_u = room_u && split_u.contains(&true);
        let any_v = room_v && split_v.contains(&true);
        if !any_u && !any_v {
            return Ok((us, vs, grid));
        }
        if any_u {
            us = refine(&us, &mu, &split_u);
        }
        if any_v {
            vs = refine(&vs, &mv, &split_v);
        }
    }
}

/// Triangulates a surface.
///
/// The grid includes the surface's break lines; each cell is split along its shorter
/// diagonal into two triangles oriented like (∂/∂u × ∂/∂v); coincident vertices are welded
/// within 1e-9 of the bounding box diagonal (closing seams and collapsing poles), and a closed
/// result is oriented outwards. See the [module docs](super) for the normals.
///
/// Errors: sample counts below 2 or above 2^15 per direction, a tolerance that is not finite
/// and > 0, a surface of dimension other than 1, 2 or 3 ([`Error::WrongDimension`]), a
/// non-finite surface point ([`Error::NonFinite`]).
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
    let d = s.dim();
    if !(1..=3).contains(&d) {
        return Err(Error::WrongDimension {
            operation: "tessellation of a surface",
            expected: 3,
            got: d,
        });
    }
    const MAX: usize = 1 << 15;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (bu, bv) = s.breaks();
    let (us, vs, grid) = match options.sampling {
        Sampling::Uniform(k, l) => {
            for n in [k, l] {
                if !(2..=MAX).contains(&n) {
                    return Err(Error::InvalidOption {
                        option: "sample count",
                        reason: "must be from 2 to 32768 per direction",
                    });
                }
            }
            let us = with_breaks(linspace(u0, u1, k), &bu, (u0, u1));
            let vs = with_breaks(linspace(v0, v1, l), &bv, (v0, v1));
            let grid = grid3(s, &us, &vs)?;
            (us, vs, grid)
        }
        Sampling::Adaptive { tolerance } => {
            let start = options.min_samples.clamp(2, MAX);
            let us = with_breaks(linspace(u0, u1, start), &bu, (u0, u1));
            let vs = with_breaks(linspace(v0, v1, start), &bv, (v0, v1));
            let tol = match tolerance {
                Some(t) if t.is_finite() && t > 0.0 => t,
                Some(t) => return Err(Error::InvalidTolerance { value: t }),
                None => {
                    let probe = grid3(s, &linspace(u0, u1, 33), &linspace(v0, v1, 33))?;
                    let (lo, hi) = bounding_box(&probe);
                    let diag = norm(sub(hi, lo));
                    if diag > 0.0 {
                        diag * 1e-3
                    } else {
                        1e-9
                    }
                }
            };
            // The checks run at 3/4 of the tolerance: where the surface is quadratic over a
            // triangle, its distance from the triangle is at most 4/3 of the largest one at
            // the midpoints of the triangle's edges (the quadratic Lagrange basis on a triangle).
            adaptive_grid(s, us, vs, 0.75 * tol, options.max_samples.clamp(2, MAX))?
        }
    };
    let (nu, nv) = (us.len(), vs.len());
    let mut triangles = Vec::with_capacity((nu - 1) * (nv - 1) * 2);
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
    let (lo, hi) = bounding_box(&grid);
    let weld = norm(sub(hi, lo)) * 1e-9;
    let mut mesh = TriMesh::new(grid, triangles, weld, options.crease_degrees)?;
    if mesh.is_watertight() && mesh.volume() < 0.0 {
        mesh.flip();
    }
    Ok(mesh)
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
