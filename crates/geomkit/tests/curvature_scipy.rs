//! Gaussian and mean curvature of interpolated height fields against SciPy: the closed forms
//! of a graph z = f(x, y) applied to the derivatives SciPy's
//! `RectBivariateSpline(x, y, z, s=0)` gives at the same points (f_x, f_y, f_xx, f_xy,
//! f_yy, kept in `tests/data/bspline_scipy.json`), compared with
//! `BsplineSurface::curvature` of geomkit's not-a-knot interpolant of the same grid.

use geomkit::bspline::{interpolate_heights_at, EndCondition};
use serde_json::Value;

const DATA: &str = include_str!("data/bspline_scipy.json");

fn list(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn curvature_of_heights_matches_scipy_derivatives() {
    let data: Value = serde_json::from_str(DATA).unwrap();
    for case in data["surfaces"].as_array().unwrap() {
        let (xs, ys) = (list(&case["x"]), list(&case["y"]));
        let z: Vec<f64> = case["z"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(list)
            .collect();
        let s = interpolate_heights_at(&z, &xs, &ys, &EndCondition::NotAKnot).unwrap();
        let deriv = |order: [u64; 2]| -> Vec<f64> {
            let d = case["derivs"]
                .as_array()
                .unwrap()
                .iter()
                .find(|d| d["order"][0] == order[0] && d["order"][1] == order[1])
                .expect("SciPy derivative of that order");
            list(&d["values"])
        };
        let (fx, fy) = (deriv([1, 0]), deriv([0, 1]));
        let (fxx, fxy, fyy) = (deriv([2, 0]), deriv([1, 1]), deriv([0, 2]));
        let points = case["deriv_points"].as_array().unwrap();
        let (mut worst_k, mut worst_h) = (0.0f64, 0.0f64);
        let (mut scale_k, mut scale_h) = (0.0f64, 0.0f64);
        for (i, p) in points.iter().enumerate() {
            let (x, y) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
            let w = 1.0 + fx[i] * fx[i] + fy[i] * fy[i];
            let k = (fxx[i] * fyy[i] - fxy[i] * fxy[i]) / (w * w);
            let h = ((1.0 + fy[i] * fy[i]) * fxx[i] - 2.0 * fx[i] * fy[i] * fxy[i]
                + (1.0 + fx[i] * fx[i]) * fyy[i])
                / (2.0 * w.powf(1.5));
            let got = s
                .curvature(x, y)
                .unwrap()
                .expect("a graph is never singular");
            worst_k = worst_k.max((got.gaussian - k).abs());
            worst_h = worst_h.max((got.mean - h).abs());
            scale_k = scale_k.max(k.abs());
            scale_h = scale_h.max(h.abs());
        }
        let name = case["name"].as_str().unwrap();
        eprintln!("{name}: K off by {worst_k:.1e} (max |K| {scale_k:.2}), H by {worst_h:.1e} (max |H| {scale_h:.2})");
        assert!(
            worst_k <= 1e-9 * scale_k.max(1.0),
            "{name}: K off by {worst_k}"
        );
        assert!(
            worst_h <= 1e-9 * scale_h.max(1.0),
            "{name}: H off by {worst_h}"
        );
    }
}
