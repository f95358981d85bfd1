//! The B-spline calculus (issue 22) against SciPy 1.17: `BSpline(t, c, k)(x, nu,
//! extrapolate)`, `.derivative(nu)`, `.antiderivative(nu)`, `.integrate(a, b, extrapolate)`,
//! `.insert_knot(x, m)` and `RectBivariateSpline`'s grid evaluation, `ev` and `integral`,
//! kept in `tests/data/bspline_calculus_scipy.json` (its generator,
//! `bench/make_reference_calculus.py`, lists the cases: degrees 0 to 7, clamped and
//! non-clamped uneven knots, 1-D and 3-D coefficients, repeated interior knots, periodic
//! interpolants, surfaces of degrees (3, 3), (1, 2), (5, 4)). Regenerate it with
//! `bash bench/make_reference.sh`; the tests never run Python.
//!
//! Tolerance: 1e-12 relative, each block of numbers against its own scale, the largest
//! magnitude SciPy gives in that block: the values of one derivative order in one
//! extrapolation mode of one case (so a derivative is measured against the size of that
//! derivative, which grows like |c|/h^ν and, outside the base interval, with the distance:
//! the rounding of every term scales with it, not with the values), the coefficients of one
//! derivative or antiderivative curve, the integrals of one case in one mode. Evaluation
//! and the curve operations run SciPy's own recursions in SciPy's order, so they agree bit
//! for bit (observed: every curve value, derivative, coefficient and integral with `Extend`
//! and `Periodic`); the integrals with `Nan` come from FITPACK's `splint` in SciPy
//! (integrals of the basis functions; geomkit goes through the antiderivative: observed
//! 1e-15), the surfaces from FITPACK's `bispev`, `parder` and `dblint` (which sum in
//! another order and differentiate the coefficients first; observed up to 1.2e-14 for the
//! (5, 4) surface, whose coefficients are larger than its values). A wrong interval at a
//! knot, a wrong end rule or a slip in a formula shows at 1e-3 or more. Knots that SciPy
//! copies or shifts (derivative, antiderivative, insertion) must be equal bit for bit.
//!
//! Where SciPy gives no usable number the test checks geomkit's documented choice instead:
//! `integrate(a, b, Nan)` over a range outside the base interval is 0 (SciPy's FITPACK path
//! for 1-D coefficients gives 0, but crashes the interpreter for k >= 6, and its path for
//! n-D coefficients gives NaN: the data hold null there).

use geomkit::bspline::{BsplineCurve, BsplineSurface, Extrapolate};
use geomkit::Error;
use serde_json::Value;

const DATA: &str = include_str!("data/bspline_calculus_scipy.json");

/// Relative to each block's scale (see the module docs).
const TOLERANCE: f64 = 1e-12;

fn data() -> Value {
    serde_json::from_str(DATA).expect("bspline_calculus_scipy.json is valid JSON")
}

fn arr(v: &Value) -> &[Value] {
    v.as_array().expect("an array")
}

fn int(v: &Value) -> usize {
    v.as_u64().expect("an integer") as usize
}

/// Numbers, null as NaN.
fn nums(v: &Value) -> Vec<f64> {
    arr(v)
        .iter()
        .map(|x| x.as_f64().unwrap_or(f64::NAN))
        .collect()
}

/// The largest finite magnitude (1 if none is above 0: blocks of zeros compare absolutely).
fn scale(want: &[f64]) -> f64 {
    let m = want
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if m > 0.0 {
        m
    } else {
        1.0
    }
}

/// `got` equals `want` within TOLERANCE·scale(want), NaN where `want` is NaN; returns the
/// largest relative difference.
fn check(what: &str, got: &[f64], want: &[f64]) -> f64 {
    assert_eq!(got.len(), want.len(), "{what}: lengths");
    let s = scale(want);
    let mut worst = 0.0f64;
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        if w.is_nan() {
            assert!(g.is_nan(), "{what} [{i}]: {g}, SciPy NaN");
            continue;
        }
        let rel = (g - w).abs() / s;
        assert!(
            rel <= TOLERANCE,
            "{what} [{i}]: {g} vs SciPy {w} (relative {rel:.1e})"
        );
        worst = worst.max(rel);
    }
    worst
}

fn curve_of(case: &Value) -> BsplineCurve {
    let (k, dim) = (int(&case["k"]), int(&case["dim"]));
    BsplineCurve::from_flat(k, nums(&case["t"]), dim, nums(&case["c"])).expect("SciPy's spline")
}

fn name(case: &Value) -> &str {
    case["name"].as_str().expect("a name")
}

/// Every curve case with its spline and name.
fn curves(data: &Value) -> impl Iterator<Item = (&Value, BsplineCurve, &str)> {
    arr(&data["curves"])
        .iter()
        .map(|case| (case, curve_of(case), name(case)))
}

fn eval(c: &BsplineCurve, x: &[f64], nu: usize, mode: Extrapolate) -> Vec<f64> {
    let mut out = vec![0.0; x.len() * c.dim()];
    c.eval_nu_many(x, nu, mode, &mut out)
        .expect("matching buffer");
    out
}

#[test]
fn evaluation_matches_scipy_in_every_mode() {
    let data = data();
    let mut worst = 0.0f64;
    for (case, c, n) in curves(&data) {
        let x = nums(&case["x"]);
        let extend = arr(&case["extend"]);
        assert_eq!(extend.len(), c.degree() + 2, "{n}: orders 0..=k+1");
        for (nu, want) in extend.iter().enumerate() {
            let got = eval(&c, &x, nu, Extrapolate::Extend);
            worst = worst.max(check(&format!("{n} nu={nu} extend"), &got, &nums(want)));
        }
        let got = eval(&c, &x, 0, Extrapolate::Nan);
        worst = worst.max(check(&format!("{n} nan"), &got, &nums(&case["nan"])));
        for (nu, want) in arr(&case["periodic_nu"]).iter().zip(arr(&case["periodic"])) {
            let nu = int(nu);
            let got = eval(&c, &x, nu, Extrapolate::Periodic);
            worst = worst.max(check(&format!("{n} nu={nu} periodic"), &got, &nums(want)));
        }
    }
    assert!(worst <= TOLERANCE);
}

#[test]
fn derivative_and_antiderivative_curves_match_scipy() {
    let data = data();
    for (case, c, n) in curves(&data) {
        for d in arr(&case["derivatives"]) {
            let nu = int(&d["nu"]);
            match (c.derivative_nu(nu), d["error"].as_str()) {
                (Ok(got), None) => {
                    assert_eq!(got.degree(), c.degree() - nu, "{n} derivative {nu}");
                    assert_eq!(got.knots(), nums(&d["t"]), "{n} derivative {nu}: knots");
                    check(
                        &format!("{n} derivative {nu}"),
                        got.control_flat(),
                        &nums(&d["c"]),
                    );
                }
                (Err(e), Some(msg)) => {
                    let expected = if msg.starts_with("Order of derivative") {
                        matches!(e, Error::DerivativeOrder { .. })
                    } else {
                        matches!(e, Error::NotDifferentiable { order, .. } if order == nu)
                    };
                    assert!(expected, "{n} derivative {nu}: {e} where SciPy says {msg}");
                }
                (got, want) => panic!("{n} derivative {nu}: {got:?}, SciPy {want:?}"),
            }
        }
        for a in arr(&case["antiderivatives"]) {
            let nu = int(&a["nu"]);
            let got = c.antiderivative(nu).expect("degree within the cap");
            assert_eq!(got.degree(), c.degree() + nu);
            assert_eq!(got.knots(), nums(&a["t"]), "{n} antiderivative {nu}: knots");
            check(
                &format!("{n} antiderivative {nu}"),
                got.control_flat(),
                &nums(&a["c"]),
            );
        }
    }
}

#[test]
fn integrals_match_scipy() {
    let data = data();
    for (case, c, n) in curves(&data) {
        let ranges = arr(&case["integrals"]);
        for (key, mode) in [
            ("extend", Extrapolate::Extend),
            ("nan", Extrapolate::Nan),
            ("periodic", Extrapolate::Periodic),
        ] {
            let mut got = Vec::new();
            let mut want = Vec::new();
            for r in ranges {
                let (a, b) = (r["a"].as_f64().unwrap(), r["b"].as_f64().unwrap());
                let value = c.integrate(a, b, mode);
                for (g, w) in value.into_iter().zip(nums(&r[key])) {
                    if w.is_nan() {
                        // SciPy's n-D path outside the base interval (see the module docs).
                        assert_eq!(mode, Extrapolate::Nan, "{n} {key} [{a}, {b}]");
                        assert_eq!(g, 0.0, "{n} {key} [{a}, {b}]: no part inside");
                        continue;
                    }
                    got.push(g);
                    want.push(w);
                }
            }
            check(&format!("{n} integrals {key}"), &got, &want);
        }
    }
}

#[test]
fn knot_insertion_matches_scipy() {
    let data = data();
    for (case, c, n) in curves(&data) {
        let periodic = case["periodic_spline"].as_bool().unwrap();
        for ins in arr(&case["insert_knot"]) {
            let (x, m) = (ins["x"].as_f64().unwrap(), int(&ins["m"]));
            let got = if periodic {
                c.insert_knot_periodic(x, m)
            } else {
                c.insert_knot(x, m)
            };
            match (got, ins["error"].as_str()) {
                (Ok(got), None) => {
                    let what = format!("{n} insert {x} x{m}");
                    assert_eq!(got.knots(), nums(&ins["t"]), "{what}: knots");
                    check(&what, got.control_flat(), &nums(&ins["c"]));
                }
                (Err(e), Some(_)) => {
                    assert!(
                        matches!(e, Error::KnotInsertion { .. }),
                        "{n} insert {x}: {e}"
                    )
                }
                (got, want) => panic!("{n} insert {x} x{m}: {got:?}, SciPy {want:?}"),
            }
        }
    }
}

fn surface_of(case: &Value) -> BsplineSurface {
    let (kx, ky) = (int(&case["kx"]), int(&case["ky"]));
    let (tx, ty) = (nums(&case["tx"]), nums(&case["ty"]));
    let (nx, ny) = (tx.len() - kx - 1, ty.len() - ky - 1);
    BsplineSurface::from_flat((kx, ky), tx, ty, nx, ny, 1, nums(&case["c"])).expect("FITPACK's")
}

#[test]
fn rect_bivariate_spline_semantics_match_scipy() {
    let data = data();
    for case in arr(&data["surfaces"]) {
        let s = surface_of(case);
        let n = name(case);
        let (gx, gy) = (nums(&case["grid_x"]), nums(&case["grid_y"]));
        for g in arr(&case["grid"]) {
            let (dx, dy) = (int(&g["dx"]), int(&g["dy"]));
            let mut out = vec![0.0; gx.len() * gy.len()];
            s.eval_partial_grid(&gx, &gy, dx, dy, &mut out).unwrap();
            check(&format!("{n} grid ({dx}, {dy})"), &out, &nums(&g["z"]));
        }
        let (ex, ey) = (nums(&case["ev_x"]), nums(&case["ev_y"]));
        for e in arr(&case["ev"]) {
            let (dx, dy) = (int(&e["dx"]), int(&e["dy"]));
            let mut out = vec![0.0; ex.len()];
            s.eval_partial_many(&ex, &ey, dx, dy, &mut out).unwrap();
            check(&format!("{n} ev ({dx}, {dy})"), &out, &nums(&e["z"]));
        }
        let (mut got, mut want) = (Vec::new(), Vec::new());
        for i in arr(&case["integrals"]) {
            let l = nums(&i["limits"]);
            got.push(s.integral(l[0], l[1], l[2], l[3])[0]);
            want.push(i["value"].as_f64().unwrap());
        }
        check(&format!("{n} integrals"), &got, &want);
        // FITPACK takes derivative orders below the degree only ("parder: 10").
        let (kx, ky) = s.degrees();
        let mut out = [0.0];
        for (dx, dy) in [(kx, 0), (0, ky)] {
            let e = s
                .eval_partial_many(&[0.5], &[0.5], dx, dy, &mut out)
                .unwrap_err();
            assert!(matches!(e, Error::DerivativeOrder { .. }), "{n}: {e}");
        }
    }
}
