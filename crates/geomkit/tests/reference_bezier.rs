//! Method 1 against other implementations: geomkit's Bézier elevation, evaluation and power
//! form compared with exact rational results (Python's `fractions.Fraction`) and with the
//! `bezier` package, kept in `tests/data/bezier_reference.json`.
//!
//! Regenerate the data with `bash bench/make_reference.sh` (pinned versions in
//! `bench/requirements.txt`; the file records them). The tests never run Python.

mod common;

use common::max_abs_diff;
use geomkit::bezier::BezierCurve;
use geomkit::exact::{degree_change_matrix, ExactBezierCurve, Rational};
use geomkit::geom::{BatchOptions, Curve};
use serde_json::Value;

const DATA: &str = include_str!("data/bezier_reference.json");

fn data() -> Value {
    serde_json::from_str(DATA).expect("bezier_reference.json is valid JSON")
}

fn num(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

fn arr(v: &Value) -> &[Value] {
    v.as_array().expect("an array")
}

/// Rows of numbers, flattened row-major.
fn flat(v: &Value) -> Vec<f64> {
    arr(v).iter().flat_map(|r| arr(r).iter().map(num)).collect()
}

/// Rows of "p/q" strings, flattened row-major.
fn rationals(v: &Value) -> Vec<Rational> {
    arr(v)
        .iter()
        .flat_map(|r| arr(r).iter())
        .map(|s| {
            let s = s.as_str().expect("a \"p/q\" string");
            s.parse::<Rational>().expect("a rational")
        })
        .collect()
}

/// Parses Python's `float.hex()` ("-0x1.8p+3", "0x0.0p+0"): exact for normal numbers.
fn parse_hex(s: &str) -> f64 {
    let (sign, s) = match s.strip_prefix('-') {
        Some(rest) => (-1.0, rest),
        None => (1.0, s),
    };
    let s = s.strip_prefix("0x").expect("0x prefix");
    let (mantissa, exp) = s.split_once('p').expect("p exponent");
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let digits = u64::from_str_radix(&format!("{int}{frac}"), 16).expect("hex digits");
    let exp: i32 = exp.parse().expect("exponent");
    // digits < 2^53, so the conversion and the power-of-two scaling are exact.
    sign * digits as f64 * 2f64.powi(exp - 4 * frac.len() as i32)
}

struct Case {
    name: String,
    curve: BezierCurve,
    json: Value,
}

fn cases() -> Vec<Case> {
    let d = data();
    arr(&d["curves"])
        .iter()
        .map(|c| {
            let dim = c["dim"].as_u64().unwrap() as usize;
            let curve = BezierCurve::from_flat(dim, flat(&c["points"])).unwrap();
            assert_eq!(curve.degree() as u64, c["degree"].as_u64().unwrap());
            Case {
                name: c["name"].as_str().unwrap().to_string(),
                curve,
                json: c.clone(),
            }
        })
        .collect()
}

#[test]
fn data_file_is_complete_and_parsed_exactly() {
    let d = data();
    assert_eq!(d["generator"], "bash bench/make_reference.sh");
    for lib in ["python", "bezier", "numpy"] {
        assert!(d["versions"][lib].is_string(), "version of {lib}");
    }
    let cases = cases();
    let mut names: Vec<(usize, usize)> = cases
        .iter()
        .map(|c| (c.curve.dim(), c.curve.degree()))
        .collect();
    names.sort_unstable();
    assert_eq!(
        names,
        [
            (2, 3),
            (2, 7),
            (2, 20),
            (2, 40),
            (3, 3),
            (3, 7),
            (3, 20),
            (3, 40)
        ]
    );
    // serde_json (with float_roundtrip) must give every input bit for bit: compare with the
    // float.hex() strings written next to the decimal ones.
    for c in &cases {
        let hex: Vec<f64> = arr(&c.json["points_hex"])
            .iter()
            .flat_map(|r| arr(r).iter().map(|s| parse_hex(s.as_str().unwrap())))
            .collect();
        let parsed = c.curve.points_flat();
        assert_eq!(hex.len(), parsed.len());
        for (h, p) in hex.iter().zip(parsed) {
            assert_eq!(h.to_bits(), p.to_bits(), "{}: {h:e} vs {p:e}", c.name);
        }
    }
    assert_eq!(parse_hex("0x1.8000000000000p+3"), 12.0);
    assert_eq!(parse_hex("-0x1.0000000000000p-2"), -0.25);
    assert_eq!(parse_hex("0x0.0p+0"), 0.0);
}

/// Elevation to n+1, n+5 and 2n in one step (closed form (8) in double-double). The stored
/// exact results are the Fraction values rounded once to f64; geomkit promises every new
/// control point within eps·max|u_i| of its exact value, so it may differ from the rounded
/// one by that much (in practice it rounds correctly almost everywhere). The `bezier`
/// package elevates by one per call: after up to 40 calls it drifts by a few ulps, so it is
/// compared with a looser 1e-14 relative.
#[test]
fn elevation_matches_exact_fractions_and_bezier_package() {
    let eps = f64::EPSILON;
    for c in cases() {
        let scale = c.curve.scale();
        for e in arr(&c.json["elevations"]) {
            let target = e["target"].as_u64().unwrap() as usize;
            let got = c.curve.elevate_degree(target).unwrap();
            assert_eq!(got.degree(), target);
            let exact = flat(&e["exact"]);
            let peer = flat(&e["bezier_chain"]);
            let d_exact = max_abs_diff(got.points_flat(), &exact) / scale;
            let d_peer = max_abs_diff(got.points_flat(), &peer) / scale;
            let peer_exact = max_abs_diff(&peer, &exact) / scale;
            eprintln!(
                "{} -> {target}: |geomkit - exact| = {d_exact:.2e}, |geomkit - bezier| = \
                 {d_peer:.2e}, |bezier - exact| = {peer_exact:.2e} (relative to max|P|)",
                c.name
            );
            assert!(
                d_exact <= eps,
                "{} -> {target}: {d_exact:e} from exact",
                c.name
            );
            assert!(
                d_peer <= 1e-14,
                "{} -> {target}: {d_peer:e} from bezier",
                c.name
            );
        }
    }
}

/// Evaluation (Bernstein–Horner in O(n), error O(n·eps) relative to Σ b_i |u_i| <= max|u|)
/// at the 21 stored parameters, one by one (`eval`) and batched (`eval_batch`, blocks of 8),
/// against the exact value at the f64 parameter (rounded once) and `bezier`'s
/// `evaluate_multi` (itself within ~1e-15 of exact).
#[test]
fn evaluation_matches_exact_fractions_and_bezier_package() {
    let d = data();
    let ts: Vec<f64> = arr(&d["eval_parameters"]).iter().map(num).collect();
    assert_eq!(ts.len(), 21);
    for c in cases() {
        let scale = c.curve.scale();
        let dim = c.curve.dim();
        let exact = flat(&c.json["eval_exact"]);
        let peer = flat(&c.json["eval_bezier"]);
        let one: Vec<f64> = ts.iter().flat_map(|&t| c.curve.eval(t)).collect();
        let mut many = vec![0.0; ts.len() * dim];
        c.curve
            .eval_batch(&ts, &mut many, &BatchOptions::sequential())
            .unwrap();
        for (what, got) in [("eval", &one), ("eval_batch", &many)] {
            let d_exact = max_abs_diff(got, &exact) / scale;
            let d_peer = max_abs_diff(got, &peer) / scale;
            eprintln!(
                "{} {what}: |geomkit - exact| = {d_exact:.2e}, |geomkit - bezier| = \
                 {d_peer:.2e} (relative to max|P|)",
                c.name
            );
            assert!(
                d_exact <= 4e-15,
                "{} {what}: {d_exact:e} from exact",
                c.name
            );
            assert!(d_peer <= 1e-14, "{} {what}: {d_peer:e} from bezier", c.name);
        }
        // The end points are the end control points exactly.
        let n = c.curve.degree();
        assert_eq!(&one[..dim], c.curve.point(0));
        assert_eq!(&one[20 * dim..], c.curve.point(n));
    }
}

/// Exact power coefficients S = U·H (formula (5)) of the degree-7 curves.
#[test]
fn exact_power_coefficients_match_fractions() {
    let mut seen = 0;
    for c in cases() {
        let Some(want) = c.json.get("power_exact") else {
            continue;
        };
        seen += 1;
        let exact = ExactBezierCurve::from_f64(c.curve.dim(), c.curve.points_flat()).unwrap();
        let got = exact.to_power();
        let want = rationals(want);
        assert_eq!(got.len(), want.len(), "{}", c.name);
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            assert_eq!(
                g,
                w,
                "{}: coefficient {} coordinate {}",
                c.name,
                k / c.curve.dim(),
                k % c.curve.dim()
            );
        }
        // The f64 power form loses digits to cancellation, but at degree 7 only a few.
        let f = c.curve.to_power();
        let s_scale = want
            .iter()
            .map(|q| geomkit::exact::rational_to_f64(q).abs())
            .fold(0.0, f64::max);
        let rounded: Vec<f64> = want.iter().map(geomkit::exact::rational_to_f64).collect();
        let d = max_abs_diff(&f, &rounded) / s_scale;
        eprintln!("{} f64 to_power: {d:.2e} relative to max|s_j|", c.name);
        assert!(d <= 1e-13, "{}: f64 power form {d:e} from exact", c.name);
    }
    assert_eq!(seen, 2, "degree-7 curves in 2-D and 3-D");
}

/// The paper's Example 2: S_5 with two zero columns, the matrix H_5 E H_3^-1, the exact
/// cubic, and the f64 exact reduction reproducing it.
#[test]
fn example2_is_exact() {
    let d = data();
    let ex = &d["example2"];
    let pts = flat(&ex["points"]);
    let exact = ExactBezierCurve::from_f64(2, &pts).unwrap();
    assert_eq!(exact.to_power(), rationals(&ex["power_exact"]));
    assert_eq!(
        exact.real_degree() as u64,
        ex["real_degree"].as_u64().unwrap()
    );
    let m = degree_change_matrix(5, 3);
    let want_m = rationals(&ex["matrix_5_3_exact"]);
    for i in 0..6 {
        for j in 0..4 {
            assert_eq!(m.get(i, j), &want_m[i * 4 + j], "H_5 E H_3^-1 ({i},{j})");
        }
    }
    let cubic = exact.change_degree(3).unwrap();
    let want_cubic = rationals(&ex["cubic_exact"]);
    assert_eq!(cubic.points(), &want_cubic[..]);
    assert_eq!(cubic.change_degree(5).unwrap(), exact);
    // The f64 route: exact reduction within its tolerance, here bit for bit (integers).
    let curve = BezierCurve::from_flat(2, pts).unwrap();
    let reduced = curve.reduce_degree(3, None).unwrap();
    let want_f64: Vec<f64> = want_cubic
        .iter()
        .map(geomkit::exact::rational_to_f64)
        .collect();
    let d = max_abs_diff(reduced.points_flat(), &want_f64);
    assert!(
        d <= 1e-12 * curve.scale(),
        "f64 reduction {d:e} from the exact cubic"
    );
    assert_eq!(curve.degree_report(None).unwrap().real_degree, 3);
}
