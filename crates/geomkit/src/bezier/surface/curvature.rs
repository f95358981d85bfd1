//! Gaussian and mean curvature of Bézier surfaces, polynomial and rational, from the first
//! and second fundamental forms (do Carmo, §3-3) — the formulas of
//! [`BsplineSurface::curvature`](crate::bspline::BsplineSurface::curvature):
//! K = (LN − M²) / (EG − F²), H = (EN − 2FM + GL) / (2(EG − F²)), with E, F, G from S_u, S_v
//! and L, M, N the second partials S_uu, S_uv, S_vv along the unit normal
//! n = S_u × S_v / |S_u × S_v|. A surface in R¹ is the height field z = f(u, v), drawn as its
//! graph (u, v, f). The partial derivatives are the hodographs of formula (11) of
//! spec/bezier-order.md (polynomial nets) and the quotient rule on the homogeneous net
//! (rational ones).
//!
//! ```
//! use geomkit::bezier::RationalBezierSurface;
//! // An octant of the sphere of radius 2: a quarter circle revolved by a quarter circle.
//! let h = std::f64::consts::FRAC_1_SQRT_2;
//! let profile = [([2.0, 0.0], 1.0), ([2.0, 2.0], h), ([0.0, 2.0], 1.0)]; // (r, z), weight
//! let turn = [([1.0, 0.0], 1.0), ([1.0, 1.0], h), ([0.0, 1.0], 1.0)]; // (x, y), weight
//! let net = profile.iter().map(|(p, _)| turn.iter().map(|(t, _)| vec![p[0] * t[0], p[0] * t[1], p[1]]).collect()).collect();
//! let weights = profile.iter().map(|(_, a)| turn.iter().map(|(_, b)| a * b).collect()).collect();
//! let s = RationalBezierSurface::new(net, weights).unwrap();
//! let k = s.curvature(0.3, 0.6).unwrap().unwrap();
//! assert!((k.gaussian - 0.25).abs() < 1e-13 && (k.mean.abs() - 0.5).abs() < 1e-13);
//! ```

use super::BezierSurface;
use crate::bezier::RationalBezierSurface;
use crate::bspline::{curvature_of, SurfaceCurvature};
use crate::Result;

impl BezierSurface {
    /// The Gaussian curvature K and the mean curvature H (signed with the normal S_u × S_v;
    /// a height field's upward normal) at (u, v), for a surface in R³ or a height field z =
    /// f(u, v) (a surface in R¹). `None` where the surface is singular (S_u × S_v = 0, e.g.
    /// a collapsed edge).
    ///
    /// Errors: a surface of dimension other than 1 or 3 ([`Error::WrongDimension`]);
    /// non-finite parameters ([`Error::NonFinite`]).
    ///
    /// ```
    /// use geomkit::bezier::BezierSurface;
    /// // The saddle z = u v: K = −1 / (1 + u² + v²)², H = −u v / (1 + u² + v²)^(3/2).
    /// let s = BezierSurface::new(vec![vec![vec![0.0], vec![0.0]], vec![vec![0.0], vec![1.0]]]).unwrap();
    /// let k = s.curvature(0.0, 0.0).unwrap().unwrap();
    /// assert_eq!((k.gaussian, k.mean), (-1.0, 0.0));
    /// ```
    pub fn curvature(&self, u: f64, v: f64) -> Result<Option<SurfaceCurvature>> {
        curvature_of(self, u, v)
    }
}

impl RationalBezierSurface {
    /// [`BezierSurface::curvature`] of the rational surface p = A / w (its partial
    /// derivatives by the quotient rule). Errors as there.
    pub fn curvature(&self, u: f64, v: f64) -> Result<Option<SurfaceCurvature>> {
        curvature_of(self, u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Surface;
    use crate::Error;

    /// An octant of the sphere of radius `r` (the profile quarter circle from the equator
    /// to the pole, revolved by a quarter circle): a rational biquadratic patch.
    fn octant(r: f64) -> RationalBezierSurface {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let profile = [([r, 0.0], 1.0), ([r, r], h), ([0.0, r], 1.0)];
        let turn = [([1.0, 0.0], 1.0), ([1.0, 1.0], h), ([0.0, 1.0], 1.0)];
        let net = profile
            .iter()
            .map(|(p, _)| {
                turn.iter()
                    .map(|(t, _)| vec![p[0] * t[0], p[0] * t[1], p[1]])
                    .collect()
            })
            .collect();
        let weights = profile
            .iter()
            .map(|(_, a)| turn.iter().map(|(_, b)| a * b).collect())
            .collect();
        RationalBezierSurface::new(net, weights).unwrap()
    }

    #[test]
    fn a_sphere_has_k_one_over_r_squared_and_h_one_over_r() {
        for r in [0.5, 2.0, 7.0] {
            let s = octant(r);
            for &(u, v) in &[(0.1, 0.1), (0.5, 0.5), (0.9, 0.2), (0.3, 1.0), (0.0, 0.7)] {
                // On the sphere, so the evaluation is right too.
                let p = Surface::eval(&s, u, v);
                assert!(((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r).abs() < 1e-13 * r);
                let k = s.curvature(u, v).unwrap().unwrap();
                assert!(
                    (k.gaussian - 1.0 / (r * r)).abs() < 1e-12 / (r * r),
                    "{k:?}"
                );
                assert!((k.mean.abs() - 1.0 / r).abs() < 1e-12 / r, "{k:?}");
            }
            // The pole (u = 1) is a collapsed edge: no curvature there.
            assert_eq!(s.curvature(1.0, 0.5).unwrap(), None);
        }
    }

    /// The graph of z = x y: K = −1/W², H = −x y / W^(3/2), W = 1 + x² + y².
    fn saddle(x: f64, y: f64) -> (f64, f64) {
        let w = 1.0 + x * x + y * y;
        (-1.0 / (w * w), -x * y / w.powf(1.5))
    }

    #[test]
    fn the_saddle_in_r3_and_as_heights_matches_the_closed_form() {
        // (u, v, u v) over [0, 1]², once as a net in R³ (elevated to degrees (3, 2) so the
        // hodographs are not trivial) and once as a height field in R¹.
        let r3 = BezierSurface::new(vec![
            vec![vec![0.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]],
            vec![vec![1.0, 0.0, 0.0], vec![1.0, 1.0, 1.0]],
        ])
        .unwrap()
        .change_degree(3, 2, None)
        .unwrap();
        let r1 = BezierSurface::new(vec![vec![vec![0.0], vec![0.0]], vec![vec![0.0], vec![1.0]]])
            .unwrap();
        for &(u, v) in &[(0.0, 0.0), (0.25, 0.75), (1.0, 1.0), (0.6, 0.1)] {
            let (k, h) = saddle(u, v);
            for s in [&r3, &r1] {
                let c = s.curvature(u, v).unwrap().unwrap();
                assert!((c.gaussian - k).abs() < 1e-13, "{c:?} vs {k}");
                assert!((c.mean - h).abs() < 1e-13, "{c:?} vs {h}");
            }
        }
    }

    #[test]
    fn wrong_dimension_and_non_finite_parameters_are_errors() {
        let plane = BezierSurface::new(vec![
            vec![vec![0.0, 0.0], vec![0.0, 1.0]],
            vec![vec![1.0, 0.0], vec![1.0, 1.0]],
        ])
        .unwrap();
        assert!(matches!(
            plane.curvature(0.5, 0.5),
            Err(Error::WrongDimension { got: 2, .. })
        ));
        assert!(matches!(
            octant(1.0).curvature(f64::NAN, 0.5),
            Err(Error::NonFinite { index: 0, .. })
        ));
    }
}
