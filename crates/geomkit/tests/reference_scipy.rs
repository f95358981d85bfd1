//! Method 2 against SciPy: geomkit's interpolating cubic B-splines compared with
//! `scipy.interpolate.make_interp_spline(x, y, k=3, bc_type=...)` and
//! `RectBivariateSpline(x, y, z, kx=3, ky=3, s=0)`, kept in `tests/data/bspline_scipy.json`.
//!
//! Regenerate the data with `bash bench/make_reference.sh` (pinned versions in
//! `bench/requirements.txt`; the file records them). The tests never run Python.
//!
//! Mapping of SciPy's cases onto geomkit:
//! - data x are the curve parameters: `Parametrization::Uniform` (t_i = i) for x = 0..N-1,
//!   `ChordLength` / `Centripetal` for x computed in Python exactly as geomkit does, and
//!   [`interpolate_curve_at`] with x itself for every case (given parameters);
//! - bc_type not-a-knot / natural / periodic → `NotAKnot` / `Natural` / `Periodic` (SciPy's
//!   periodic data repeat the first point at the end; geomkit drops that closing point);
//! - SciPy's "clamped" is a zero FIRST derivative at both ends →
//!   `Clamped { start: Some(0), end: Some(0) }` (derivatives w.r.t. the parameter, as SciPy's
//!   are w.r.t. x);
//! - RectBivariateSpline with s = 0 interpolates on FITPACK's knots, which leave out the
//!   second and next-to-last coordinates: not-a-knot in both directions →
//!   `interpolate_heights(.., &NotAKnot)` (regular grid) and `interpolate_heights_at` (any).
//!
//! Tolerances. Both sides solve well-conditioned banded systems (different bases: geomkit's
//! knots extend beyond the ends, SciPy's are clamped), so values agree to a few ulps of the
//! data scale; 1e-12 relative to max|y| leaves a wide margin and still catches any formula
//! slip (wrong end row, shifted parameter), which shows at 1e-3 or more. Derivatives are
//! compared relative to the largest magnitude of that derivative over the sample points
//! (the natural scale |y|/h^k): differentiation divides the same rounding errors by the
//! spacing h once or twice, and SciPy's clamped-knot basis is not the same as ours, so
//! derivatives get 1e-10 (observed: at most 5e-15, except next to the short last interval
//! of `given12_short_end`: 4e-14 for the first and 3.5e-13 for the second derivative).
//!
//! Two cases guard the conditioning of the end rows: `given12_short_end` (the last interval
//! 1/100 of the one before it) and the surface `nonuniform_random` (x ends with 0.029 after
//! 0.453, y has 0.001 next to 0.314). With the not-a-knot row (a third-derivative jump,
//! entries ~ 1/h^3) left unscaled, partial pivoting picked it as a pivot and the values
//! were 6e-11 and 1e-12 from SciPy; SciPy itself is within 5e-15 and 3e-13 of the exact
//! rational interpolant there (checked once with Python's fractions).

use geomkit::bspline::{
    interpolate_curve_at, interpolate_curve_flat, interpolate_heights, interpolate_heights_at,
    BsplineCurve, BsplineSurface, EndCondition, InterpolationOptions, Parametrization,
};
use geomkit::geom::Curve;
use serde_json::Value;

const DATA: &str = include_str!("data/bspline_scipy.json");

/// Values: relative to max|y| (or max|z|).
const VALUE_TOLERANCE: f64 = 1e-12;
/// First and second derivatives: relative to the largest |derivative| sampled.
const DERIVATIVE_TOLERANCE: f64 = 1e-10;

fn data() -> Value {
    serde_json::from_str(DATA).expect("bspline_scipy.json is valid JSON")
}

fn num(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

fn arr(v: &Value) -> &[Value] {
    v.as_array().expect("an array")
}

fn list(v: &Value) -> Vec<f64> {
    arr(v).iter().map(num).collect()
}

/// Rows of numbers, flattened row-major.
fn flat(v: &Value) -> Vec<f64> {
    arr(v).iter().flat_map(|r| arr(r).iter().map(num)).collect()
}

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Largest |a_k - b_k| / scale.
fn rel_diff(a: &[f64], b: &[f64], scale: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    assert!(scale > 0.0);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// One SciPy curve case.
struct CurveCase {
    name: String,
    parametrization: String,
    bc_type: String,
    dim: usize,
    x: Vec<f64>,
    y: Vec<f64>,
    json: Value,
}

fn curve_cases() -> Vec<CurveCase> {
    arr(&data()["curves"])
        .iter()
        .map(|c| CurveCase {
            name: c["name"].as_str().unwrap().to_string(),
            parametrization: c["parametrization"].as_str().unwrap().to_string(),
            bc_type: c["bc_type"].as_str().unwrap().to_string(),
            dim: c["dim"].as_u64().unwrap() as usize,
            x: list(&c["x"]),
            y: flat(&c["y"]),
            json: c.clone(),
        })
        .collect()
}

/// geomkit's end condition for SciPy's bc_type.
fn end_condition(bc_type: &str, dim: usize) -> EndCondition {
    match bc_type {
        "not-a-knot" => EndCondition::NotAKnot,
        "natural" => EndCondition::Natural,
        // SciPy's "clamped": first derivative zero at both ends.
        "clamped" => EndCondition::Clamped {
            start: Some(vec![0.0; dim]),
            end: Some(vec![0.0; dim]),
        },
        "periodic" => EndCondition::Periodic,
        other => panic!("unknown bc_type {other}"),
    }
}

/// Largest relative differences (values, first, second derivatives) of `curve` from the
/// case's SciPy results.
fn compare_curve(curve: &impl Derivatives, case: &CurveCase) -> [f64; 3] {
    let d = case.dim;
    let ts = list(&case.json["eval_t"]);
    let want = flat(&case.json["eval"]);
    let mut got = vec![0.0; ts.len() * d];
    for (t, o) in ts.iter().zip(got.chunks_exact_mut(d)) {
        curve.derivative_at(*t, 0, o);
    }
    let values = rel_diff(&got, &want, max_abs(&case.y));
    let dts = list(&case.json["deriv_t"]);
    let mut out = [values, 0.0, 0.0];
    for (k, key) in [(1, "d1"), (2, "d2")] {
        let want = flat(&case.json[key]);
        let mut got = vec![0.0; dts.len() * d];
        for (t, o) in dts.iter().zip(got.chunks_exact_mut(d)) {
            curve.derivative_at(*t, k, o);
        }
        out[k] = rel_diff(&got, &want, max_abs(&want));
    }
    out
}

/// The k-th derivative of a curve (k = 0: the point).
trait Derivatives {
    fn derivative_at(&self, t: f64, k: usize, out: &mut [f64]);
}

impl Derivatives for BsplineCurve {
    fn derivative_at(&self, t: f64, k: usize, out: &mut [f64]) {
        if k == 0 {
            // The evaluation users call, not the derivative routine.
            self.eval_into(t, out);
        } else {
            self.eval_derivative(t, k, out);
        }
    }
}

fn check(name: &str, route: &str, diffs: [f64; 3]) {
    eprintln!(
        "{name} [{route}]: values {:.1e}, d1 {:.1e}, d2 {:.1e}",
        diffs[0], diffs[1], diffs[2]
    );
    assert!(
        diffs[0] <= VALUE_TOLERANCE,
        "{name} [{route}]: values differ from SciPy by {:e} relative",
        diffs[0]
    );
    for k in 1..=2 {
        assert!(
            diffs[k] <= DERIVATIVE_TOLERANCE,
            "{name} [{route}]: derivative {k} differs from SciPy by {:e} relative",
            diffs[k]
        );
    }
}

#[test]
fn data_file_covers_the_cases() {
    let d = data();
    assert_eq!(d["generator"], "bash bench/make_reference.sh");
    assert!(d["versions"]["scipy"].as_str().unwrap().starts_with("1."));
    let cases = curve_cases();
    for set in ["uniform6", "uniform50_sine", "given15", "chord20"] {
        for bc in ["not-a-knot", "natural", "clamped", "periodic"] {
            let n = cases
                .iter()
                .filter(|c| c.name == format!("{set}/{bc}"))
                .count();
            assert_eq!(n, 1, "{set}/{bc}");
        }
    }
    for c in &cases {
        let ts = list(&c.json["eval_t"]);
        // Every data site is among the evaluation parameters.
        assert!(c.x.iter().all(|x| ts.contains(x)), "{}", c.name);
        assert!(ts.len() >= 80 && list(&c.json["deriv_t"]).len() == 20);
        if c.bc_type == "periodic" {
            assert_eq!(c.y[..c.dim], c.y[c.y.len() - c.dim..], "{}", c.name);
        }
    }
    assert!(cases
        .iter()
        .any(|c| c.name == "given12_short_end/not-a-knot"));
    let surfaces: Vec<&str> = arr(&d["surfaces"])
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        surfaces,
        ["uniform", "nonuniform_mild", "nonuniform_random"]
    );
}

/// Through geomkit's own parametrizations: Uniform for x = 0..N-1, ChordLength /
/// Centripetal for x computed as geomkit does (checked: the parameters equal x bit for bit).
#[test]
fn curves_match_scipy_through_parametrizations() {
    let mut count = 0;
    for case in curve_cases() {
        let parametrization = match case.parametrization.as_str() {
            "uniform" => Parametrization::Uniform,
            "chord_length" => Parametrization::ChordLength,
            "centripetal" => Parametrization::Centripetal,
            _ => continue,
        };
        let end = end_condition(&case.bc_type, case.dim);
        let opts = InterpolationOptions::default()
            .with_end(end.clone())
            .with_parametrization(parametrization);
        let fit = interpolate_curve_flat(case.dim, &case.y, &opts).unwrap();
        // Periodic: the closing point is dropped, its parameter closes the domain.
        let n = fit.parameters().len();
        let closing = if end == EndCondition::Periodic { 1 } else { 0 };
        assert_eq!(n + closing, case.x.len(), "{}", case.name);
        assert_eq!(fit.parameters(), &case.x[..n], "{}: parameters", case.name);
        assert_eq!(
            fit.curve().domain(),
            (case.x[0], case.x[case.x.len() - 1]),
            "{}",
            case.name
        );
        check(
            &case.name,
            &format!("{parametrization:?}"),
            compare_curve(fit.curve(), &case),
        );
        count += 1;
    }
    assert_eq!(count, 13);
}

/// Through `interpolate_curve_at` with SciPy's x as the parameters, for every case
/// (uniform, given non-uniform, chord-length, centripetal).
#[test]
fn curves_match_scipy_at_given_parameters() {
    for case in curve_cases() {
        let end = end_condition(&case.bc_type, case.dim);
        let fit = interpolate_curve_at(case.dim, &case.y, &case.x, &end).unwrap();
        check(&case.name, "given x", compare_curve(fit.curve(), &case));
    }
}

/// geomkit's B-spline evaluation on SciPy's own knots and coefficients (clamped knots with
/// fourfold ends; periodic knots extended beyond the ends).
#[test]
fn scipy_bsplines_evaluate_alike() {
    let mut count = 0;
    for case in curve_cases() {
        let Some(knots) = case.json.get("scipy_knots") else {
            continue;
        };
        let control = flat(&case.json["scipy_coeffs"]);
        let curve = BsplineCurve::from_flat(3, list(knots), case.dim, control).unwrap();
        check(&case.name, "SciPy's knots", compare_curve(&curve, &case));
        count += 1;
    }
    assert_eq!(count, 7);
}

/// One RectBivariateSpline case.
struct SurfaceCase {
    name: String,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    json: Value,
}

fn surface_cases() -> Vec<SurfaceCase> {
    arr(&data()["surfaces"])
        .iter()
        .map(|s| SurfaceCase {
            name: s["name"].as_str().unwrap().to_string(),
            x: list(&s["x"]),
            y: list(&s["y"]),
            z: flat(&s["z"]),
            json: s.clone(),
        })
        .collect()
}

/// Largest relative differences (grid values; derivatives of orders (1,0), (0,1), (1,1),
/// (2,0), (0,2)) of `surface` from the case's SciPy results.
fn compare_surface(surface: &BsplineSurface, case: &SurfaceCase) -> [f64; 2] {
    let (ex, ey) = (list(&case.json["eval_x"]), list(&case.json["eval_y"]));
    let want = flat(&case.json["eval"]);
    let mut got = vec![0.0; ex.len() * ey.len()];
    surface.eval_grid(&ex, &ey, &mut got).unwrap();
    let values = rel_diff(&got, &want, max_abs(&case.z));
    // Single-point evaluation agrees with the grid.
    for (a, b) in [(0usize, 0usize), (5, 17), (29, 29)] {
        let p = surface.eval(ex[a], ey[b])[0];
        assert!((p - got[a * ey.len() + b]).abs() <= 1e-14 * max_abs(&case.z));
    }
    let pts: Vec<(f64, f64)> = arr(&case.json["deriv_points"])
        .iter()
        .map(|p| (num(&p[0]), num(&p[1])))
        .collect();
    let mut derivs = 0.0f64;
    for d in arr(&case.json["derivs"]) {
        let (ku, kv) = (
            d["order"][0].as_u64().unwrap() as usize,
            d["order"][1].as_u64().unwrap() as usize,
        );
        let want = list(&d["values"]);
        let got: Vec<f64> = pts
            .iter()
            .map(|&(u, v)| {
                let mut o = [0.0];
                surface.eval_derivative(u, v, ku, kv, &mut o);
                o[0]
            })
            .collect();
        derivs = derivs.max(rel_diff(&got, &want, max_abs(&want)));
    }
    [values, derivs]
}

fn check_surface(name: &str, route: &str, diffs: [f64; 2]) {
    eprintln!(
        "surface {name} [{route}]: values {:.1e}, derivatives {:.1e}",
        diffs[0], diffs[1]
    );
    assert!(
        diffs[0] <= VALUE_TOLERANCE,
        "surface {name} [{route}]: values differ from SciPy by {:e} relative",
        diffs[0]
    );
    assert!(
        diffs[1] <= DERIVATIVE_TOLERANCE,
        "surface {name} [{route}]: derivatives differ from SciPy by {:e} relative",
        diffs[1]
    );
}

/// RectBivariateSpline(s = 0) is the not-a-knot interpolant in both directions: the
/// regular grid (both routes), a mildly and a strongly non-uniform grid.
#[test]
fn heights_match_rect_bivariate_spline() {
    for case in surface_cases() {
        let (rows, cols) = (case.x.len(), case.y.len());
        assert_eq!((rows, cols), (12, 9));
        let s = interpolate_heights_at(&case.z, &case.x, &case.y, &EndCondition::NotAKnot).unwrap();
        check_surface(&case.name, "heights at x, y", compare_surface(&s, &case));
        if let (Some(origin), Some(spacing)) = (case.json.get("origin"), case.json.get("spacing")) {
            let s = interpolate_heights(
                &case.z,
                rows,
                cols,
                (num(&origin[0]), num(&origin[1])),
                (num(&spacing[0]), num(&spacing[1])),
                &EndCondition::NotAKnot,
            )
            .unwrap();
            check_surface(&case.name, "regular grid", compare_surface(&s, &case));
        }
    }
}

/// geomkit's surface evaluation on FITPACK's own knots and coefficients.
#[test]
fn fitpack_surfaces_evaluate_alike() {
    for case in surface_cases() {
        let (tx, ty) = (
            list(&case.json["scipy_knots_x"]),
            list(&case.json["scipy_knots_y"]),
        );
        let (nu, nv) = (tx.len() - 4, ty.len() - 4);
        let s =
            BsplineSurface::from_flat((3, 3), tx, ty, nu, nv, 1, list(&case.json["scipy_coeffs"]))
                .unwrap();
        check_surface(&case.name, "FITPACK's knots", compare_surface(&s, &case));
    }
}
