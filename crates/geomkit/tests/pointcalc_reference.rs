//! Point equations against SciPy's BarycentricInterpolator (values ≤ 1e-14 of the data
//! scale; derivatives by their conditioning). Reference data: bench/make_reference_pointcalc.py.

use geomkit::geom::Curve;
use geomkit::pointcalc::{Nodes, PointEquation};
use serde_json::Value;

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(floats).collect()
}

#[test]
fn agrees_with_scipy_barycentric_interpolator() {
    let data: Value =
        serde_json::from_str(include_str!("data/pointcalc_scipy.json")).expect("valid JSON");
    let cases = data["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 8);
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let nodes = Nodes::new(floats(&case["nodes"])).unwrap();
        let points = rows(&case["points"]);
        let scale = points.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        let eq = PointEquation::new(nodes.clone(), points).unwrap();
        let width = nodes.domain().1 - nodes.domain().0;
        let lebesgue = nodes.lebesgue_constant();
        let exact = rows(&case["exact"]);
        let (mut to_exact, mut to_scipy, mut scipy_to_exact) = (0.0f64, 0.0f64, 0.0f64);
        for ((t, want), ex) in floats(&case["t"])
            .iter()
            .zip(rows(&case["values"]))
            .zip(&exact)
        {
            let got = eq.eval(*t);
            for ((g, w), e) in got.iter().zip(&want).zip(ex) {
                to_exact = to_exact.max((g - e).abs() / scale);
                to_scipy = to_scipy.max((g - w).abs() / scale);
                scipy_to_exact = scipy_to_exact.max((w - e).abs() / scale);
            }
        }
        println!(
            "{name}: Λ = {lebesgue:.2}, |geomkit - SciPy| {to_scipy:.1e}, |geomkit - exact| \
             {to_exact:.1e}, |SciPy - exact| {scipy_to_exact:.1e} (relative to the data)"
        );
        // Agreement with SciPy within 1e-14 of the data wherever the node set is well
        // conditioned; where it is not, both carry rounding errors of order Λ ε and geomkit's
        // is checked against the exact value instead.
        if lebesgue <= 10.0 {
            assert!(to_scipy <= 1e-14, "{name}: {to_scipy:e} from SciPy");
        }
        assert!(
            to_exact <= 4.0 * f64::EPSILON * lebesgue.max(1.0) * nodes.len() as f64,
            "{name}: {to_exact:e} from the exact interpolant"
        );
        // Derivatives lose accuracy like the differentiation matrix norm (~n² / width).
        let n = nodes.len() as f64;
        for (order, key) in [(1, "d1"), (2, "d2")] {
            let tol = 1e-13 * scale * (n * n / width).powi(order);
            for (t, want) in floats(&case["dt"]).iter().zip(rows(&case[key])) {
                let got = &eq.derivatives(*t)[order as usize];
                for (g, w) in got.iter().zip(&want) {
                    assert!(
                        (g - w).abs() <= tol,
                        "{name}: derivative {order} at {t}: {g} vs SciPy {w}"
                    );
                }
            }
        }
    }
}
