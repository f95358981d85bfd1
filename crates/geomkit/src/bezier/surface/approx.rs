//! Best L2 approximation of a Bézier surface by one of lower degrees (the approximate half of
//! the order change (14) of spec/bezier-order.md, for when the defect (16) is too small for
//! an exact reduction).
//!
//! The best approximation in L2(\[0,1\]²) from the tensor-product space P_n ⊗ P_m is the
//! orthogonal projection onto it, and that projection is the product of the projections of
//! each direction: every row (as a curve whose "points" are the rows) is projected onto
//! degree n in u, then every column onto degree m in v. Each 1-D projection is a weighted
//! least-squares problem on N+1 Gauss–Legendre nodes, exact because the integrands have
//! degree <= 2N.
//!
//! ```
//! use geomkit::bezier::BezierSurface;
//! // z = u³·v³ (a bicubic with every net point 0 but the last) to degrees (2, 2).
//! let mut net = vec![vec![vec![0.0]; 4]; 4];
//! net[3][3] = vec![1.0];
//! let s = BezierSurface::new(net).unwrap();
//! let r = s.reduce_degree_approx(2, 2).unwrap();
//! assert_eq!(r.surface.degrees(), (2, 2));
//! // The error is the part of u³v³ orthogonal to P2 ⊗ P2 (shifted Legendre polynomials).
//! let exact = (1.0 / 49.0 - (1.0 / 7.0 - 1.0 / 2800.0_f64).powi(2)).sqrt();
//! assert!((r.l2_error - exact).abs() < 1e-14);
//! assert!(r.linf.upper_bound >= r.linf.max_found);
//! ```

use super::{BezierSurface, Direction};
use crate::bezier::bound::DeviationBound;
use crate::bezier::curve::split_flat;
use crate::bezier::degree::least_squares;
use crate::numeric::gauss_legendre;
use crate::{Error, Result};

/// An approximate reduction of a surface with its error report.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceApproxReduction {
    /// The surface of the lower degrees.
    pub surface: BezierSurface,
    /// sqrt(∫∫_\[0,1\]² |p(u,v) − q(u,v)|² du dv), exact up to rounding (tensor Gauss–Legendre
    /// with N+1 × M+1 nodes).
    pub l2_error: f64,
    /// How far apart the two surfaces are: the largest distance found on a 65×65 grid and a
    /// guaranteed upper bound by the convex hull property of the difference surface, cut
    /// into 8 × 8 patches by de Casteljau subdivision (each patch is bounded by its largest
    /// net point; a few percent above the maximum on smooth errors).
    pub linf: DeviationBound,
}

impl BezierSurface {
    /// The best approximation in L2(\[0,1\]²) of degrees (`n_new`, `m_new`), each at most the
    /// current degree (equal keeps that direction as it is), with its L2 error and an L∞
    /// bound. A surface whose real degrees are within the target comes back unchanged up to
    /// rounding (error ~0).
    ///
    /// Errors: a target degree above the current one ([`Error::InvalidDegree`]), a
    /// least-squares solve that fails, a non-finite result.
    pub fn reduce_degree_approx(
        &self,
        n_new: usize,
        m_new: usize,
    ) -> Result<SurfaceApproxReduction> {
        let (n, m) = self.degrees();
        for (have, want) in [(n, n_new), (m, m_new)] {
            if want > have {
                return Err(Error::InvalidDegree {
                    degree: have,
                    requested: want,
                    reason: "an approximate reduction needs degrees at most the current ones",
                });
            }
        }
        let (rows, width) = self.as_curve(Direction::U);
        let in_u = self.rebuild(Direction::U, &l2_project(&rows, width, n_new)?, n_new + 1)?;
        let (cols, width) = in_u.as_curve(Direction::V);
        let surface = in_u.rebuild(Direction::V, &l2_project(&cols, width, m_new)?, m_new + 1)?;
        let l2_error = l2_distance(self, &surface)?;
        let mut linf = self.deviation_from(&surface)?;
        // Tighter: the difference surface cut into 8 × 8 patches, each bounded by its net.
        let elevated = surface.change_degree(n, m, None)?;
        let diff: Vec<f64> = self
            .net
            .iter()
            .zip(&elevated.net)
            .map(|(a, b)| a - b)
            .collect();
        let diff = BezierSurface::from_flat(n + 1, m + 1, self.dim, diff)?;
        let slack = 4.0 * f64::EPSILON * (n + m + 2) as f64 * self.scale().max(elevated.scale());
        let pieces = subdivided_bound(&diff, 8)? + slack;
        linf.upper_bound = linf.upper_bound.min(pieces).max(linf.max_found);
        Ok(SurfaceApproxReduction {
            surface,
            l2_error,
            linf,
        })
    }
}

/// The L2\[0,1\] projection of the Bézier curve `q` (points of `dim` numbers) onto degree `m`:
/// min Σ_r w_r |q(t_r) − p(t_r)|² over N+1 Gauss–Legendre nodes, which is the continuous
/// problem exactly (every integrand has degree <= 2N).
fn l2_project(q: &[f64], dim: usize, m: usize) -> Result<Vec<f64>> {
    let big_n = q.len() / dim - 1;
    if m >= big_n {
        return Ok(q.to_vec());
    }
    let (nodes, weights) = gauss_legendre(big_n + 1);
    let mut p = vec![0.0; (m + 1) * dim];
    let free: Vec<usize> = (0..=m).collect();
    least_squares(
        q,
        dim,
        m,
        (&nodes, &weights),
        &mut p,
        &free,
        "approximate surface reduction",
    )?;
    if let Some(index) = p.iter().position(|v| !v.is_finite()) {
        return Err(Error::NonFinite {
            what: "reduced net point",
            index: index / dim,
        });
    }
    Ok(p)
}

/// A guaranteed bound on max |d(u, v)| over \[0,1\]² of the surface `d`: cut into
/// `pieces` × `pieces` patches by de Casteljau subdivision, each lies in the convex hull of
/// its net, so the largest net point norm of all bounds it (converging to the maximum as
/// O(1/pieces²)).
fn subdivided_bound(d: &BezierSurface, pieces: usize) -> Result<f64> {
    let (rows, cols) = (d.rows, d.cols);
    let mut best = 0.0f64;
    for strip in split_into(&d.as_curve(Direction::U).0, cols * d.dim, pieces) {
        let s = BezierSurface::from_flat(rows, cols, d.dim, strip)?;
        for patch in split_into(&s.as_curve(Direction::V).0, rows * d.dim, pieces) {
            for p in patch.chunks_exact(d.dim) {
                best = best.max(p.iter().map(|x| x * x).sum::<f64>().sqrt());
            }
        }
    }
    Ok(best)
}

/// The control points of a Bézier curve (points of `dim` numbers) on \[k/p, (k+1)/p\] for
/// every k < p.
fn split_into(points: &[f64], dim: usize, p: usize) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(p);
    let mut rest = points.to_vec();
    for k in 0..p - 1 {
        let (left, right) = split_flat(&rest, dim, 1.0 / (p - k) as f64);
        out.push(left);
        rest = right;
    }
    out.push(rest);
    out
}

/// sqrt(∫∫ |a − b|²) over \[0,1\]², by tensor Gauss–Legendre exact for the degrees of `a`
/// (the higher ones).
fn l2_distance(a: &BezierSurface, b: &BezierSurface) -> Result<f64> {
    let (n, m) = a.degrees();
    let (gu, wu) = gauss_legendre(n + 1);
    let (gv, wv) = gauss_legendre(m + 1);
    let d = a.dim();
    let mut pa = vec![0.0; gu.len() * gv.len() * d];
    let mut pb = pa.clone();
    a.eval_grid(&gu, &gv, &mut pa)?;
    b.eval_grid(&gu, &gv, &mut pb)?;
    let mut sum = 0.0;
    for (i, w_u) in wu.iter().enumerate() {
        for (j, w_v) in wv.iter().enumerate() {
            let at = (i * gv.len() + j) * d;
            let sq: f64 = (0..d).map(|c| (pa[at + c] - pb[at + c]).powi(2)).sum();
            sum += w_u * w_v * sq;
        }
    }
    Ok(sum.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// u³ on [0,1] minus its best quadratic: the shifted Legendre P̃3 / 20, with
    /// P̃3(u) = 20u³ − 30u² + 12u − 1 (independent of the Bernstein basis).
    fn cubic_residual(u: f64) -> f64 {
        (20.0 * u.powi(3) - 30.0 * u * u + 12.0 * u - 1.0) / 20.0
    }

    fn monomial_surface() -> BezierSurface {
        let mut net = vec![vec![vec![0.0]; 4]; 4];
        net[3][3] = vec![1.0];
        BezierSurface::new(net).unwrap()
    }

    #[test]
    fn u3v3_reduces_to_the_legendre_projection() {
        let r = monomial_surface().reduce_degree_approx(2, 2).unwrap();
        for &(u, v) in &[(0.0_f64, 0.0_f64), (0.3, 0.7), (1.0, 0.5), (0.9, 0.1)] {
            let want = (u.powi(3) - cubic_residual(u)) * (v.powi(3) - cubic_residual(v));
            let got = r.surface.eval(u, v)[0];
            assert!((got - want).abs() < 1e-14, "({u}, {v}): {got} vs {want}");
        }
        let l2 = (1.0 / 49.0 - (1.0 / 7.0 - 1.0 / 2800.0_f64).powi(2)).sqrt();
        assert!((r.l2_error - l2).abs() < 1e-15, "{} vs {l2}", r.l2_error);
        // The largest |u³v³ − p| on the grid is at a corner (1, 1): 1 − (1 − 1/20)².
        let corner = 1.0 - (1.0 - 1.0 / 20.0_f64).powi(2);
        assert!((r.linf.max_found - corner).abs() < 1e-14);
        assert!(r.linf.upper_bound >= corner);
        // The subdivided bound is within a few percent of the maximum (it is at the corner:
        // the error there is a vertex of a sub-net).
        assert!(r.linf.upper_bound <= 1.05 * corner, "{:?}", r.linf);
    }

    #[test]
    fn one_direction_only() {
        let r = monomial_surface().reduce_degree_approx(3, 1).unwrap();
        assert_eq!(r.surface.degrees(), (3, 1));
        // Best linear approximation of v³: 0.9 v − 0.2 (projection on 1, v: Legendre).
        let want = |u: f64, v: f64| u.powi(3) * (0.9 * v - 0.2);
        for &(u, v) in &[(0.2_f64, 0.4_f64), (1.0, 1.0), (0.5, 0.0)] {
            assert!((r.surface.eval(u, v)[0] - want(u, v)).abs() < 1e-14);
        }
    }

    #[test]
    fn a_surface_of_lower_real_degree_stays() {
        // A bilinear patch elevated to (4, 3) goes back to (1, 1) with no error.
        let s = BezierSurface::new(vec![
            vec![vec![0., 0., 0.], vec![0., 1., 0.]],
            vec![vec![1., 0., 0.], vec![1., 1., 1.]],
        ])
        .unwrap();
        let e = s.change_degree(4, 3, None).unwrap();
        let r = e.reduce_degree_approx(1, 1).unwrap();
        assert!(r.l2_error < 1e-15);
        for (a, b) in r.surface.net_flat().iter().zip(s.net_flat()) {
            assert!((a - b).abs() < 1e-14);
        }
    }

    #[test]
    fn a_higher_target_is_refused() {
        let err = monomial_surface().reduce_degree_approx(4, 2).unwrap_err();
        assert!(matches!(
            err,
            Error::InvalidDegree {
                degree: 3,
                requested: 4,
                ..
            }
        ));
    }
}
