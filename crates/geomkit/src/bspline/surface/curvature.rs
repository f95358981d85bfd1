//! Gaussian and mean curvature of B-spline surfaces, from the first and second fundamental
//! forms (do Carmo, §3-3):
//!
//! - a surface in R³, S(u, v): E = S_u·S_u, F = S_u·S_v, G = S_v·S_v, and with the unit normal
//!   n = S_u × S_v / |S_u × S_v|: L = S_uu·n, M = S_uv·n, N = S_vv·n; then
//!   K = (LN − M²) / (EG − F²) and H = (EN − 2FM + GL) / (2(EG − F²));
//! - a height field z = f(x, y) (a scalar surface, as `interpolate_heights` makes): the graph
//!   (x, y, f(x, y)), for which those become K = (f_xx f_yy − f_xy²) / (1 + f_x² + f_y²)² and
//!   H = ((1 + f_y²) f_xx − 2 f_x f_y f_xy + (1 + f_x²) f_yy) / (2 (1 + f_x² + f_y²)^(3/2)).
//!
//! H is signed with the normal S_u × S_v (for a height field: the upward normal, so a bowl
//! z = x² + y² has H > 0 at its bottom).
//!
//! ```
//! use geomkit::bspline::{interpolate_heights_at, EndCondition};
//! // z = (x² + y²) / 2 on a 6×6 grid: a not-a-knot cubic reproduces it exactly.
//! let xs: Vec<f64> = (0..6).map(|i| i as f64 - 2.5).collect();
//! let z: Vec<f64> = xs.iter().flat_map(|x| xs.iter().map(move |y| (x * x + y * y) / 2.0)).collect();
//! let s = interpolate_heights_at(&z, &xs, &xs, &EndCondition::NotAKnot).unwrap();
//! let k = s.curvature(0.0, 0.0).unwrap().unwrap();
//! assert!((k.gaussian - 1.0).abs() < 1e-12 && (k.mean - 1.0).abs() < 1e-12);
//! ```

use super::BsplineSurface;
use crate::geom::Surface;
use crate::{Error, Result};

/// The curvatures of a surface at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceCurvature {
    /// K = κ1·κ2, the Gaussian curvature.
    pub gaussian: f64,
    /// H = (κ1 + κ2) / 2, the mean curvature (signed with the normal S_u × S_v).
    pub mean: f64,
}

impl BsplineSurface {
    /// The Gaussian and mean curvature at (u, v), for a surface in R³ or a height field (a
    /// scalar surface z(x, y) with x = u, y = v). `None` where the surface is singular
    /// (S_u × S_v = 0, e.g. at a collapsed edge).
    ///
    /// Errors: a surface of dimension other than 1 or 3 ([`Error::WrongDimension`]);
    /// non-finite parameters ([`Error::NonFinite`]).
    pub fn curvature(&self, u: f64, v: f64) -> Result<Option<SurfaceCurvature>> {
        curvature_of(self, u, v)
    }
}

/// K and H of any surface in R³ or height field (R¹) at (u, v) from its partial derivatives
/// up to order 2 ([`Surface::derivative_into`]); `None` where S_u × S_v vanishes. Errors:
/// those of [`BsplineSurface::curvature`], and the surface's derivatives'.
pub(crate) fn curvature_of(s: &dyn Surface, u: f64, v: f64) -> Result<Option<SurfaceCurvature>> {
    for (index, t) in [u, v].into_iter().enumerate() {
        if !t.is_finite() {
            return Err(Error::NonFinite {
                what: "curvature parameter",
                index,
            });
        }
    }
    let d = s.dim();
    if d != 1 && d != 3 {
        return Err(Error::WrongDimension {
            operation: "surface curvature (a surface in R^3 or a height field)",
            expected: 3,
            got: d,
        });
    }
    let mut parts = [[0.0; 3]; 5];
    for (k, order) in [(1, 0), (0, 1), (2, 0), (1, 1), (0, 2)]
        .into_iter()
        .enumerate()
    {
        s.derivative_into(u, v, order, &mut parts[k][..d])?;
    }
    let [su, sv, suu, suv, svv] = if d == 1 {
        // The graph (x, y, f): S_x = (1, 0, f_x), S_y = (0, 1, f_y), S_xx = (0, 0, f_xx)…
        let f = |k: usize| parts[k][0];
        [
            [1.0, 0.0, f(0)],
            [0.0, 1.0, f(1)],
            [0.0, 0.0, f(2)],
            [0.0, 0.0, f(3)],
            [0.0, 0.0, f(4)],
        ]
    } else {
        parts
    };
    Ok(fundamental_forms(su, sv, suu, suv, svv))
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// K and H from the partial derivatives; `None` when S_u × S_v vanishes.
fn fundamental_forms(
    su: [f64; 3],
    sv: [f64; 3],
    suu: [f64; 3],
    suv: [f64; 3],
    svv: [f64; 3],
) -> Option<SurfaceCurvature> {
    let cross = [
        su[1] * sv[2] - su[2] * sv[1],
        su[2] * sv[0] - su[0] * sv[2],
        su[0] * sv[1] - su[1] * sv[0],
    ];
    let len = dot(cross, cross).sqrt();
    let scale = dot(su, su).max(dot(sv, sv));
    if len.is_nan() || len <= 1e-14 * scale || !len.is_finite() {
        return None;
    }
    let n = [cross[0] / len, cross[1] / len, cross[2] / len];
    let (e, f, g) = (dot(su, su), dot(su, sv), dot(sv, sv));
    let (l, m, nn) = (dot(suu, n), dot(suv, n), dot(svv, n));
    // EG − F² = |S_u × S_v|² (Lagrange's identity), without the cancellation.
    let det = len * len;
    let gaussian = (l * nn - m * m) / det;
    let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
    (gaussian.is_finite() && mean.is_finite()).then_some(SurfaceCurvature { gaussian, mean })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::SurfaceInterpolationOptions;
    use crate::bspline::{interpolate_heights_at, interpolate_surface, EndCondition};

    /// The graph of z = a x² + b xy + c y² has, by the closed forms of the module doc,
    /// K = (4ac − b²)/W², H = ((1 + f_y²) 2a − 2 f_x f_y b + (1 + f_x²) 2c)/(2 W^(3/2)).
    fn quadric(a: f64, b: f64, c: f64, x: f64, y: f64) -> (f64, f64) {
        let (fx, fy) = (2.0 * a * x + b * y, b * x + 2.0 * c * y);
        let w = 1.0 + fx * fx + fy * fy;
        let k = (4.0 * a * c - b * b) / (w * w);
        let h = ((1.0 + fy * fy) * 2.0 * a - 2.0 * fx * fy * b + (1.0 + fx * fx) * 2.0 * c)
            / (2.0 * w.powf(1.5));
        (k, h)
    }

    #[test]
    fn heights_of_a_quadric() {
        let (a, b, c) = (0.3, -0.2, 0.5);
        let xs: Vec<f64> = (0..7).map(|i| -1.5 + 0.5 * i as f64).collect();
        let ys: Vec<f64> = (0..6).map(|j| -1.0 + 0.4 * j as f64).collect();
        let z: Vec<f64> = xs
            .iter()
            .flat_map(|&x| ys.iter().map(move |&y| a * x * x + b * x * y + c * y * y))
            .collect();
        let s = interpolate_heights_at(&z, &xs, &ys, &EndCondition::NotAKnot).unwrap();
        for &(x, y) in &[(0.0, 0.0), (0.7, -0.3), (-1.2, 0.9), (1.5, 1.0)] {
            let got = s.curvature(x, y).unwrap().unwrap();
            let (k, h) = quadric(a, b, c, x, y);
            assert!(
                (got.gaussian - k).abs() < 1e-11,
                "K at ({x}, {y}): {got:?} vs {k}"
            );
            assert!(
                (got.mean - h).abs() < 1e-11,
                "H at ({x}, {y}): {got:?} vs {h}"
            );
        }
    }

    #[test]
    fn a_parametric_paraboloid_in_r3() {
        // (x, y, x² + y²) on a 6×6 grid: not-a-knot bicubic reproduces it; K = 4/W², H =
        // (2 + 4x² + 4y² ... ) — by the graph formula with a = c = 1, b = 0.
        let xs: Vec<f64> = (0..6).map(|i| -1.0 + 0.4 * i as f64).collect();
        let grid: Vec<Vec<Vec<f64>>> = xs
            .iter()
            .map(|&x| xs.iter().map(|&y| vec![x, y, x * x + y * y]).collect())
            .collect();
        let opts = SurfaceInterpolationOptions::default()
            .with_parametrization(crate::bspline::Parametrization::Uniform);
        let fit = interpolate_surface(&grid, &opts).unwrap();
        // Uniform parameters 0..5 map to x = -1 + 0.4 u.
        for &(u, v) in &[(0.0, 0.0), (2.5, 2.5), (1.2, 4.1)] {
            let (x, y) = (-1.0 + 0.4 * u, -1.0 + 0.4 * v);
            let got = fit.surface.curvature(u, v).unwrap().unwrap();
            let (k, h) = quadric(1.0, 0.0, 1.0, x, y);
            assert!((got.gaussian - k).abs() < 1e-10, "{got:?} vs {k}");
            assert!((got.mean - h).abs() < 1e-10, "{got:?} vs {h}");
        }
    }

    #[test]
    fn a_curve_in_the_plane_is_refused() {
        let grid: Vec<Vec<Vec<f64>>> = (0..4)
            .map(|i| (0..4).map(|j| vec![i as f64, j as f64]).collect())
            .collect();
        let fit = interpolate_surface(&grid, &SurfaceInterpolationOptions::default()).unwrap();
        assert!(matches!(
            fit.surface.curvature(0.5, 0.5),
            Err(Error::WrongDimension { got: 2, .. })
        ));
        assert!(fit.surface.curvature(f64::NAN, 0.5).is_err());
    }
}
