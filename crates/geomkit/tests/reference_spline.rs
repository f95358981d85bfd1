//! Interpolating splines of any degree against SciPy (issue 22): geomkit's
//! [`make_interp_spline`] compared with `scipy.interpolate.make_interp_spline(x, y, k,
//! bc_type)` for k = 1..7, every split of the derivative conditions between the ends (orders
//! from 1 up, and the highest ones), the aliases "natural" and "clamped", not-a-knot,
//! periodic, the fewest points each takes; uniform, uneven (one interval 1/50 of its
//! neighbours) and scaled (x ~ 1e3) data, 1-D and 3-D values. The data are in
//! `tests/data/spline_scipy.json`, written by `bench/make_reference_spline.py` (through
//! `bash bench/make_reference.sh`; pinned SciPy); the tests never run Python.
//!
//! What is compared: the knots t exactly (the same arithmetic: x copied, midpoints
//! (x_i + x_(i+1))/2, periodic spacings); the coefficients c and the values within 1e-12 of
//! the scale of the data and the coefficients (max |y|, max |c|: all conditions at one end
//! make coefficients up to 1e6 times the data, and rounding scales with them); derivatives of orders 1, 2 and k between the data points
//! within 1e-10 of their own largest magnitude. Both sides solve the same banded system with
//! partial pivoting, and agree to a few ulps where it is well conditioned; the margin covers
//! the high degrees, whose coefficients amplify rounding (the B-spline basis of degree 7 on
//! uneven knots has a condition number near 1e4), and the derivative rows, which geomkit
//! equilibrates and SciPy does not. A wrong row, knot or end shows at 1e-3 or more.

use geomkit::bspline::{make_interp_spline, EndSpec, SplineEnds, SplineOptions};
use geomkit::geom::Curve;
use serde_json::Value;

const DATA: &str = include_str!("data/spline_scipy.json");

fn floats(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(floats).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        _ => panic!("not a number: {v}"),
    }
}

fn end(v: &Value) -> EndSpec {
    match v {
        Value::String(s) if s == "not-a-knot" => EndSpec::NotAKnot,
        Value::String(s) if s == "natural" => EndSpec::natural(),
        Value::String(s) if s == "clamped" => EndSpec::clamped(),
        Value::Array(list) => EndSpec::Derivatives(
            list.iter()
                .map(|d| (d[0].as_u64().unwrap() as usize, floats(&d[1])))
                .collect(),
        ),
        _ => panic!("unknown end {v}"),
    }
}

/// The sum over j of |B_j^(nu)(t)| (the basis of `s`'s knots): how much an error e in every
/// coefficient can move the derivative of order nu at t.
fn basis_sum(s: &geomkit::bspline::BsplineCurve, t: f64, nu: usize) -> f64 {
    let n = s.n_control();
    let mut total = 0.0;
    let mut out = [0.0];
    for j in 0..n {
        let mut unit = vec![0.0; n];
        unit[j] = 1.0;
        let b = geomkit::bspline::BsplineCurve::from_flat(s.degree(), s.knots().to_vec(), 1, unit)
            .unwrap();
        b.eval_derivative(t, nu, &mut out);
        total += out[0].abs();
    }
    total
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

#[test]
fn every_degree_and_end_condition_matches_scipy() {
    let data: Value = serde_json::from_str(DATA).unwrap();
    let sets = &data["sets"];
    let cases = data["cases"].as_array().unwrap();
    assert!(cases.len() >= 300, "{} cases", cases.len());
    let mut worst = (0.0f64, String::new());
    let (mut refused, mut better) = (Vec::new(), Vec::new());
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let set = &sets[case["set"].as_str().unwrap()];
        let (k, dim) = (
            case["k"].as_u64().unwrap() as usize,
            case["dim"].as_u64().unwrap() as usize,
        );
        let npts = case["npts"].as_u64().map(|n| n as usize);
        let mut x = floats(&set["x"]);
        let mut y = floats(&set[format!("y{dim}").as_str()]);
        if let Some(n) = npts {
            x.truncate(n);
            y.truncate(n * dim);
        }
        let periodic = case["ends"] == "periodic";
        let ends = if periodic {
            let n = x.len();
            let first = y[..dim].to_vec();
            y[(n - 1) * dim..].copy_from_slice(&first);
            SplineEnds::Periodic
        } else {
            SplineEnds::Open {
                left: end(&case["ends"][0]),
                right: end(&case["ends"][1]),
            }
        };
        let result = make_interp_spline(&x, &y, dim, &SplineOptions::new(k).with_ends(ends));
        let c_scipy = floats(&case["c"]);
        // SciPy's own error against the exact solution, where it is above 1e-13 (relative
        // to max |c|): then the exact coefficients are in the file too.
        let scipy_error = case["scipy_error"].as_f64().unwrap_or(0.0);
        let s = match result {
            Ok(s) => s,
            // Refused as singular: only where SciPy's answer has lost most of its digits.
            Err(e) if scipy_error > 1e-6 => {
                let text = e.to_string();
                assert!(
                    text.contains("singular") || text.contains("ill-conditioned"),
                    "{name}: {e}"
                );
                refused.push((name.to_string(), scipy_error));
                continue;
            }
            Err(e) => panic!("{name}: {e}"),
        };
        assert_eq!(s.knots(), floats(&case["t"]).as_slice(), "{name}: knots");
        assert_eq!(
            s.control_flat().len(),
            c_scipy.len(),
            "{name}: coefficients"
        );
        // Coefficients: within 1e-12 of max |c| of SciPy's, or, where SciPy is off by more,
        // at least as close as SciPy to the exact ones.
        let (reference, allowed) = match case.get("c_exact") {
            Some(exact) => (floats(exact), scipy_error.max(1e-12)),
            None => (c_scipy.clone(), 1e-12),
        };
        let scale = max_abs(&reference).max(max_abs(&y));
        let mut own_error = 0.0f64;
        for (i, (a, b)) in s.control_flat().iter().zip(&reference).enumerate() {
            let err = (a - b).abs() / scale;
            own_error = own_error.max(err);
            assert!(
                err <= allowed,
                "{name}: c[{i}] = {a}, reference {b} ({err:.1e} > {allowed:.1e})"
            );
        }
        if scipy_error > 1e-13 {
            better.push((name.to_string(), own_error, scipy_error));
        }
        if own_error > worst.0 {
            worst = (own_error, name.to_string());
        }
        // Values and derivatives against SciPy's: the two coefficient errors, carried by the
        // basis (sum of |B_j^(nu)(t)|, 1 for values inside), plus evaluation rounding.
        let c_gap = (own_error + scipy_error) * scale;
        let (at, derivs_at) = match npts {
            Some(_) => (floats(&case["at"]), floats(&case["at"])),
            None => {
                let mut at = floats(&set["eval_t"]);
                if periodic {
                    at.truncate(at.len() - 2);
                }
                (at, floats(&set["deriv_t"]))
            }
        };
        let want = floats(&case["eval"]);
        for (i, &t) in at.iter().enumerate() {
            let got = s.eval(t);
            let tol = 1e-12 * scale + 2.0 * c_gap * basis_sum(&s, t, 0);
            for c in 0..dim {
                let w = want[i * dim + c];
                assert!(
                    (got[c] - w).abs() <= tol,
                    "{name}: s({t})[{c}] = {}, SciPy {w}",
                    got[c]
                );
            }
        }
        let orders = case["deriv_orders"].as_array().unwrap();
        for (o, want) in orders.iter().zip(case["derivs"].as_array().unwrap()) {
            let nu = o.as_u64().unwrap() as usize;
            let want = floats(want);
            let own = max_abs(&want);
            let mut got = vec![0.0; dim];
            for (i, &t) in derivs_at.iter().enumerate() {
                s.eval_derivative(t, nu, &mut got);
                let tol = 1e-10 * own + 2.0 * c_gap * basis_sum(&s, t, nu);
                for c in 0..dim {
                    let w = want[i * dim + c];
                    assert!(
                        (got[c] - w).abs() <= tol,
                        "{name}: s^({nu})({t})[{c}] = {}, SciPy {w}",
                        got[c]
                    );
                }
            }
        }
    }
    // SciPy has lost every digit where geomkit refuses; where it keeps some, geomkit keeps
    // as many or more.
    eprintln!("refused (SciPy's relative error): {refused:?}");
    eprintln!("SciPy inexact (geomkit's error, SciPy's): {better:?}");
    assert!(refused.iter().all(|(_, e)| *e > 1e-3), "{refused:?}");
    eprintln!("largest coefficient error: {:.2e} ({})", worst.0, worst.1);
}

/// The errors of SciPy's `test_incompatible_x_y` and `test_broken_x` carry its phrases
/// (they match on them), and every error says what to change.
#[test]
fn errors_name_the_problem_as_scipy_does() {
    let fails = |x: &[f64], y: &[f64], o: SplineOptions| {
        make_interp_spline(x, y, 1, &o).unwrap_err().to_string()
    };
    let y6 = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
    for k in 1..=3 {
        let e = fails(
            &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
            &[0.0; 8],
            SplineOptions::new(k),
        );
        assert!(e.starts_with("Shapes of x (6,) and y (8, 1)"), "{e}");
        let e = fails(&[0.0, 1.0, 1.0, 2.0, 3.0, 4.0], &y6, SplineOptions::new(k));
        assert!(
            e.contains("x to not have duplicates") && e.contains("x[1] = x[2] = 1"),
            "{e}"
        );
        let e = fails(&[0.0, 2.0, 1.0, 3.0, 4.0, 5.0], &y6, SplineOptions::new(k));
        assert!(
            e.contains("Expect x to be a 1D strictly increasing") && e.contains("sort"),
            "{e}"
        );
    }
    let x6 = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
    // Cubic: two conditions in all; one given.
    let one = SplineEnds::Open {
        left: EndSpec::clamped(),
        right: EndSpec::NotAKnot,
    };
    let e = fails(&x6, &y6, SplineOptions::new(3).with_ends(one));
    assert!(
        e.contains("The number of derivatives at boundaries does not match: expected 2, got 1+0"),
        "{e}"
    );
    let high = SplineEnds::both(EndSpec::Derivatives(vec![(4, vec![0.0])]));
    let e = fails(&x6, &y6, SplineOptions::new(3).with_ends(high));
    assert!(
        e.contains("Bad boundary conditions at 0") && e.contains("orders 0..=3"),
        "{e}"
    );
    let e = fails(
        &x6,
        &y6,
        SplineOptions::new(3).with_ends(SplineEnds::Periodic),
    );
    assert!(
        e.contains("First and last points does not match while periodic"),
        "{e}"
    );
    let e = fails(&x6, &y6, SplineOptions::new(8));
    assert!(e.contains("degree 8 is not supported"), "{e}");
    let e = fails(
        &x6,
        &y6,
        SplineOptions::new(0).with_ends(SplineEnds::both(EndSpec::natural())),
    );
    assert!(e.contains("Too much info for k=0"), "{e}");
    // Degree 0 is SciPy's step function: y_i on [x_i, x_(i+1)).
    let steps = make_interp_spline(&x6, &y6, 1, &SplineOptions::new(0)).unwrap();
    assert_eq!(steps.knots(), &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 5.0]);
    assert_eq!(steps.eval(2.5)[0], 2.0);
    // Given knots: unsorted, too few, not covering x, not suiting x.
    let t = |v: &[f64]| SplineOptions::new(3).with_knots(v.to_vec());
    let e = fails(&x6, &y6, t(&[0., 0., 0., 0., 3., 2., 5., 5., 5., 5.]));
    assert!(e.contains("Expect t to be a 1-D sorted"), "{e}");
    let e = fails(&x6, &y6, t(&[0., 0., 0., 0., 5., 5., 5., 5.]));
    assert!(e.contains("Got 8 knots, need at least 10"), "{e}");
    let e = fails(&x6, &y6, t(&[1., 1., 1., 1., 2., 3., 5., 5., 5., 5.]));
    assert!(e.contains("Out of bounds w/ x"), "{e}");
    let e = fails(&x6, &y6, t(&[0., 0., 0., 0., 0.1, 0.2, 5., 5., 5., 5.]));
    assert!(
        e.contains("the knots do not suit x") && e.contains("Schoenberg"),
        "{e}"
    );
    // Non-finite data name the index.
    let e = fails(
        &x6,
        &[0.0, 1.0, f64::NAN, 3.0, 4.0, 5.0],
        SplineOptions::new(3),
    );
    assert_eq!(e, "y 2 is not a finite number");
}

/// Periodic data closed within SciPy's tolerance (not bit for bit), and a periodic curve
/// through two distinct points, as SciPy accepts them: the curve repeats with the period
/// (values and derivatives up to k - 1 equal at both ends).
#[test]
fn periodic_accepts_what_scipy_accepts() {
    let x = [0.0, 1.0, 2.5];
    let y = [1.0, -1.0, 1.0 + 1e-9];
    for k in 1..=7 {
        let s = make_interp_spline(
            &x,
            &y,
            1,
            &SplineOptions::new(k).with_ends(SplineEnds::Periodic),
        )
        .unwrap();
        assert!((s.eval(0.0)[0] - 1.0).abs() < 1e-14 && (s.eval(1.0)[0] + 1.0).abs() < 1e-14);
        let (mut a, mut b) = ([0.0], [0.0]);
        for nu in 0..k {
            s.eval_derivative(0.0, nu, &mut a);
            s.eval_derivative(2.5, nu, &mut b);
            // Within the data's own mismatch (1e-9): degree 1 (SciPy's broken line) and
            // n <= k (SciPy's full system) interpolate the last y as given.
            assert!(
                (a[0] - b[0]).abs() <= 2e-9 * a[0].abs().max(1.0),
                "k {k} nu {nu}: {a:?} {b:?}"
            );
        }
    }
}

/// `RectBivariateSpline(x, y, z, kx, ky, s=0)` of SciPy (FITPACK): degrees 1 to 5 in each
/// direction on an uneven 9 × 8 grid. FITPACK's knots equal geomkit's not-a-knot knots
/// bit for bit (odd degrees: the inner x; even: midpoints). geomkit's coefficients are within
/// 1e-12 of the exact ones (solved in rationals by the generator) relative to their scale;
/// FITPACK's are within 3e-13 of the data's scale up to degree 4 but 1e-10 off at degree 5,
/// so the values are compared with SciPy's within both errors.
#[test]
fn surfaces_of_any_degree_match_rect_bivariate_spline() {
    use geomkit::bspline::make_interp_surface;
    let data: Value = serde_json::from_str(DATA).unwrap();
    let s = &data["surfaces"];
    let (x, y, z) = (floats(&s["x"]), floats(&s["y"]), floats(&s["z"]));
    let scale = max_abs(&z);
    let cases = s["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 7);
    for case in cases {
        let kx = case["kx"].as_u64().unwrap() as usize;
        let ky = case["ky"].as_u64().unwrap() as usize;
        let surface = make_interp_surface(&x, &y, &z, (x.len(), y.len()), (kx, ky)).unwrap();
        let (tu, tv) = surface.knots();
        assert_eq!(tu, floats(&case["tx"]).as_slice(), "({kx}, {ky}) x knots");
        assert_eq!(tv, floats(&case["ty"]).as_slice(), "({kx}, {ky}) y knots");
        // Against the exact coefficients; FITPACK's own are up to 1e-10 off (degree 5).
        let c = floats(&case["c_exact"]);
        let scipy_error = case["scipy_error"].as_f64().unwrap();
        let err = surface
            .control_flat()
            .iter()
            .zip(&c)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        // Relative to the coefficients' scale too (up to 7000 times the data's at degree 5
        // on this uneven grid: rounding scales with them).
        let c_scale = max_abs(&c).max(scale);
        assert!(err <= 1e-12 * c_scale, "({kx}, {ky}): coefficients {err:e}");
        // Values against SciPy's: both coefficient errors (the basis sums to 1 inside).
        let tol = (2e-12 + 2.0 * scipy_error) * scale;
        for (p, want) in case["at"]
            .as_array()
            .unwrap()
            .iter()
            .zip(floats(&case["values"]))
        {
            let (u, v) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
            let got = surface.eval(u, v)[0];
            assert!(
                (got - want).abs() <= tol,
                "({kx}, {ky}) at ({u}, {v}): {got} vs {want}"
            );
        }
    }
    // SciPy's messages (test_fitpack2.py::TestRectBivariateSpline::test_invalid_input).
    let z25 = vec![1.0; 25];
    let line = [1.0, 2.0, 3.0, 4.0, 5.0];
    let e = make_interp_surface(&[6.0, 2.0, 3.0, 4.0, 5.0], &line, &z25, (5, 5), (3, 3));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("x must be strictly increasing"));
    let e = make_interp_surface(&line, &[2.0, 2.0, 3.0, 4.0, 5.0], &z25, (5, 5), (3, 3));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("y must be strictly increasing"));
    let e = make_interp_surface(&line, &line, &z25[..20], (4, 5), (3, 3));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("x dimension of z must have same number of elements as x"));
    let e = make_interp_surface(&line, &line, &z25[..20], (5, 4), (3, 3));
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("y dimension of z must have same number of elements as y"));
}
