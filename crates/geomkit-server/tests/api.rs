//! The JSON API against independent references: the paper's Example 2
//! (spec/bezier-order.md), elevation against formula (8) in exact rationals computed here,
//! interpolants through their points by de Boor's algorithm written here, curvature of a
//! circle, integrals by Simpson's rule, point-calculus models of polynomials they must
//! reproduce, and file formats read by their own magic numbers and sizes.

mod common;

use common::*;
use geomkit_server::{router, Config};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};
use serde_json::{json, Value};

/// Example 2 of spec/bezier-order.md: a quintic of real degree 3.
fn example2() -> Value {
    json!({"type": "bezier_curve", "points": [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]})
}

fn app() -> axum::Router {
    router(Config::default())
}

fn binomial(n: usize, k: usize) -> BigInt {
    (0..k).fold(BigInt::one(), |acc, i| {
        acc * BigInt::from(n - i) / BigInt::from(i + 1)
    })
}

/// Formula (8) of spec/bezier-order.md in exact rationals: the control points of the
/// elevation of integer points `p` (degree n) to degree n + r.
fn elevate_exact(p: &[[i64; 2]], r: usize) -> Vec<[BigRational; 2]> {
    let n = p.len() - 1;
    (0..=n + r)
        .map(|i| {
            let mut q = [BigRational::zero(), BigRational::zero()];
            for (j, pj) in p.iter().enumerate() {
                if j > i || i - j > r {
                    continue;
                }
                let w = BigRational::new(binomial(n, j) * binomial(r, i - j), binomial(n + r, i));
                for c in 0..2 {
                    q[c] += &w * BigRational::from_integer(BigInt::from(pj[c]));
                }
            }
            q
        })
        .collect()
}

#[tokio::test]
async fn elevation_matches_exact_rationals() {
    let app = app();
    let p = [[3, -7], [11, 5], [-2, 13], [8, 1], [0, -4]];
    for to in [5, 7, 12] {
        let v = ok(
            &app,
            "/api/bezier/elevate",
            json!({"model": {"type": "bezier_curve", "points": p}, "to": to}),
        )
        .await;
        let got = points(&v["model"]["points"]);
        let exact = elevate_exact(&p, to - 4);
        assert_eq!(got.len(), to + 1);
        for (g, e) in got.iter().zip(&exact) {
            for c in 0..2 {
                let e = e[c].to_f64().unwrap();
                // Within one rounding of the exact rational (the library's guarantee).
                assert!(
                    (g[c] - e).abs() <= 2.0 * f64::EPSILON * 13.0,
                    "{g:?} vs {e}"
                );
            }
        }
        assert_eq!(v["degree"]["degree"], to);
        assert_eq!(v["degree"]["real_degree"], 4);
    }
}

#[tokio::test]
async fn example_2_degree_reduction_and_refusal() {
    let app = app();
    let d = ok(&app, "/api/bezier/degree", json!({"model": example2()})).await;
    assert_eq!(
        (
            d["degree"].as_u64(),
            d["real_degree"].as_u64(),
            d["defect"].as_u64()
        ),
        (Some(5), Some(3), Some(2))
    );

    // The paper's cubic, exactly.
    let r = ok(
        &app,
        "/api/bezier/reduce",
        json!({"model": example2(), "to": 3}),
    )
    .await;
    let cubic = points(&r["model"]["points"]);
    let expected = [[10.0, 0.0], [30.0, 10.0], [0.0, 20.0], [20.0, 0.0]];
    for (g, e) in cubic.iter().zip(expected) {
        assert!(dist(g, &e) < 1e-12, "{g:?} vs {e:?}");
    }
    // It elevates back to the six points (exact rationals of formula (8)).
    let back = elevate_exact(&[[10, 0], [30, 10], [0, 20], [20, 0]], 2);
    let six = [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]];
    for (b, s) in back.iter().zip(six) {
        assert_eq!(b[0], BigRational::from_integer(s[0].into()));
        assert_eq!(b[1], BigRational::from_integer(s[1].into()));
    }

    // Below the real degree: 422 with the reason.
    let a = send(
        &app,
        "POST",
        "/api/bezier/reduce",
        Some(&json!({"model": example2(), "to": 2})),
    )
    .await;
    assert_eq!(a.status, 422);
    let e = a.json();
    assert_eq!(e["real_degree"], 3);
    assert_eq!(e["defect"], 2);
    assert_eq!(e["requested"], 2);
    assert!(
        e["error"].as_str().unwrap().contains("real degree is 3"),
        "{e}"
    );
}

#[tokio::test]
async fn approximate_reduction_error_report_holds() {
    let app = app();
    let v = ok(
        &app,
        "/api/bezier/approximate",
        json!({"model": example2(), "to": 2, "samples": 401}),
    )
    .await;
    let reduced = points(&v["model"]["points"]);
    assert_eq!(reduced.len(), 3);
    let orig = points(&example2()["points"]);
    // Distances on a fine grid by de Casteljau: never above the bound, and the bound within
    // 1% (+ rounding) of what is attained.
    let mut most = 0.0f64;
    let k = 4001;
    let mut integral = 0.0;
    for i in 0..k {
        let t = i as f64 / (k - 1) as f64;
        let d = dist(&de_casteljau(&orig, t), &de_casteljau(&reduced, t));
        most = most.max(d);
        // Simpson's rule for the L2 error.
        let w = if i == 0 || i == k - 1 {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        integral += w * d * d;
    }
    let l2 = (integral / (3.0 * (k - 1) as f64)).sqrt();
    let bound = v["linf_bound"].as_f64().unwrap();
    assert!(most <= bound * (1.0 + 1e-12), "{most} > {bound}");
    assert!(
        bound <= most * 1.011 + 1e-9,
        "bound {bound} far above {most}"
    );
    assert!(
        (v["l2_error"].as_f64().unwrap() - l2).abs() < 1e-8 * l2,
        "{} vs {l2}",
        v["l2_error"]
    );
    // The band: both curves sampled where they are, and the offsets at ± bound.
    let band = &v["band"];
    let ts = numbers(&band["t"]);
    let (o, r) = (points(&band["original"]), points(&band["reduced"]));
    let (up, lo) = (points(&band["upper"]), points(&band["lower"]));
    for i in (0..ts.len()).step_by(37) {
        assert!(dist(&o[i], &de_casteljau(&orig, ts[i])) < 1e-12);
        assert!(dist(&r[i], &de_casteljau(&reduced, ts[i])) < 1e-12);
        assert!((dist(&up[i], &r[i]) - bound).abs() < 1e-9 * bound);
        assert!((dist(&lo[i], &r[i]) - bound).abs() < 1e-9 * bound);
    }
    // Rational curves and surfaces are refused with a reason.
    let rational =
        json!({"type": "bezier_curve", "points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 0.7, 1]});
    let a = send(
        &app,
        "POST",
        "/api/bezier/approximate",
        Some(&json!({"model": rational, "to": 1})),
    )
    .await;
    assert_eq!(a.status, 422);
    assert!(a.json()["error"].as_str().unwrap().contains("polynomial"));
}

#[tokio::test]
async fn samples_of_a_bezier_curve_and_surface() {
    let app = app();
    let v = ok(
        &app,
        "/api/samples",
        json!({"model": example2(), "samples": 11}),
    )
    .await;
    let orig = points(&example2()["points"]);
    let ts = numbers(&v["t"]);
    let pts = points(&v["points"]);
    assert_eq!(ts.len(), 11);
    for (t, p) in ts.iter().zip(&pts) {
        assert!(dist(p, &de_casteljau(&orig, *t)) < 1e-12);
    }
    assert_eq!(points(&v["control"]), orig);
    // A bilinear surface: the grid is (u, v, u*v) exactly.
    let s =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    let v = ok(&app, "/api/samples", json!({"model": s, "samples": 5})).await;
    assert_eq!(v["kind"], "surface");
    let (us, vs) = (numbers(&v["u"]), numbers(&v["v"]));
    for (i, row) in v["points"].as_array().unwrap().iter().enumerate() {
        for (j, p) in points(row).iter().enumerate() {
            assert!(dist(p, &[us[i], vs[j], us[i] * vs[j]]) < 1e-15);
        }
    }
}

#[tokio::test]
async fn edits_insert_and_remove_vertices() {
    let app = app();
    let v = ok(
        &app,
        "/api/bezier/edit",
        json!({"model": example2(), "insert": {"index": 2, "point": [15, 9]}}),
    )
    .await;
    let pts = points(&v["model"]["points"]);
    assert_eq!(pts.len(), 7);
    assert_eq!(pts[2], vec![15.0, 9.0]);
    // The deviation report against the distance measured here.
    let orig = points(&example2()["points"]);
    let most = (0..=2000)
        .map(|i| i as f64 / 2000.0)
        .map(|t| dist(&de_casteljau(&orig, t), &de_casteljau(&pts, t)))
        .fold(0.0, f64::max);
    let bound = v["deviation"]["upper_bound"].as_f64().unwrap();
    assert!(
        most <= bound * (1.0 + 1e-12) && bound <= most * 1.011 + 1e-9,
        "{most} {bound}"
    );
    let v = ok(
        &app,
        "/api/bezier/edit",
        json!({"model": example2(), "remove": 5}),
    )
    .await;
    assert_eq!(points(&v["model"]["points"]), orig[..5].to_vec());
    let a = send(
        &app,
        "POST",
        "/api/bezier/edit",
        Some(&json!({"model": example2(), "remove": 9})),
    )
    .await;
    assert_eq!(a.status, 422);
}

#[tokio::test]
async fn interpolation_passes_through_its_points() {
    let app = app();
    let pts = vec![
        vec![0.0, 0.0],
        vec![2.0, 3.0],
        vec![5.0, 3.5],
        vec![7.0, 1.0],
        vec![10.0, 0.5],
        vec![12.0, 3.0],
    ];
    for end in ["not-a-knot", "natural", "clamped", "bessel", "outer"] {
        for param in ["uniform", "chord", "centripetal"] {
            let v = ok(
                &app,
                "/api/bspline/interpolate",
                json!({"points": pts, "end": end, "parametrization": param}),
            )
            .await;
            let m = &v["model"];
            let degree = m["degree"].as_u64().unwrap() as usize;
            let knots = numbers(&m["knots"]);
            let control = points(&m["control_points"]);
            for (p, t) in pts.iter().zip(numbers(&v["parameters"])) {
                let q = de_boor(degree, &knots, &control, t);
                assert!(dist(p, &q) < 1e-12, "{end} {param}: {p:?} vs {q:?}");
            }
            // The drawn samples are the curve.
            let ts = numbers(&v["samples"]["t"]);
            let drawn = points(&v["samples"]["points"]);
            assert_eq!(ts[0], knots[degree]);
            for i in (0..ts.len()).step_by(7) {
                assert!(dist(&drawn[i], &de_boor(degree, &knots, &control, ts[i])) < 1e-12);
            }
        }
    }
    // The paper's repeated ends need uniform parameters: the library's refusal.
    let a = send(
        &app,
        "POST",
        "/api/bspline/interpolate",
        Some(&json!({"points": pts, "end": "repeat", "parametrization": "chord"})),
    )
    .await;
    assert_eq!(a.status, 422, "{}", String::from_utf8_lossy(&a.body));
    let a = send(
        &app,
        "POST",
        "/api/bspline/interpolate",
        Some(&json!({"points": pts, "end": "sideways"})),
    )
    .await;
    assert_eq!(a.status, 400);
    assert_eq!(a.json()["path"], "end");
}

#[tokio::test]
async fn closed_curve_through_a_circle_has_its_curvature() {
    let app = app();
    let r = 2.0;
    let n = 64;
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let v = ok(
        &app,
        "/api/bspline/interpolate",
        json!({"points": pts, "closed": true, "comb": {"per_span": 3, "scale": 1.0}}),
    )
    .await;
    let drawn = points(&v["samples"]["points"]);
    assert!(dist(&drawn[0], drawn.last().unwrap()) < 1e-12, "closed");
    for p in &drawn {
        assert!((p[0].hypot(p[1]) - r).abs() < 2e-4, "{p:?} off the circle");
    }
    // Counter-clockwise circle: curvature +1/r; teeth of length |κ|·scale pointing outwards.
    let comb = &v["comb"];
    let base = points(&comb["base"]);
    let tip = points(&comb["tip"]);
    for (k, (b, t)) in numbers(&comb["curvature"])
        .iter()
        .zip(base.iter().zip(&tip))
    {
        assert!((k - 1.0 / r).abs() < 2e-3, "curvature {k}");
        assert!((t[0].hypot(t[1]) - (b[0].hypot(b[1]) + k)).abs() < 1e-9);
    }
}

#[tokio::test]
async fn formulas_in_every_syntax_with_continuity() {
    let app = app();
    let v = send(&app, "GET", "/api/version", None).await.json();
    let formats: Vec<String> = v["formats"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().to_string())
        .collect();
    assert_eq!(formats.len(), 11);
    let line = json!({"type": "bezier_curve", "points": [[0, 1], [2, 5]]});
    for f in &formats {
        let r = ok(&app, "/api/formula", json!({"model": line, "format": f})).await;
        assert!(!r["formula"].as_str().unwrap().is_empty(), "{f}");
        assert_eq!(r["continuity"]["continuous"], true);
    }
    // The printed JavaScript of the line, evaluated by the formula's own terms: x(t) = 2t,
    // y(t) = 1 + 4t on [0, 1]; check through the model crate's expression parser.
    let r = ok(
        &app,
        "/api/formula",
        json!({"model": line, "format": "maple"}),
    )
    .await;
    let text = r["formula"].as_str().unwrap();
    let mut g = geomkit::expr::Graph::new();
    for (row, want) in text.lines().zip([|t: f64| 2.0 * t, |t: f64| 1.0 + 4.0 * t]) {
        let body = row.split("->").nth(1).unwrap().trim().trim_end_matches(';');
        let e = geomkit::expr::parse(&mut g, body).unwrap();
        for t in [0.0, 0.25, 0.7, 1.0] {
            assert!(
                (g.eval(e, &[("t", t)]).unwrap() - want(t)).abs() < 1e-12,
                "{row} at {t}"
            );
        }
    }
    // A composite scene whose patches do not join: the jump reported where it is.
    let scene = json!({"type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
        "patches": [["1"], ["2"]]});
    let r = ok(
        &app,
        "/api/formula",
        json!({"model": scene, "format": "sympy"}),
    )
    .await;
    let c = &r["continuity"];
    assert_eq!(c["continuous"], false);
    assert!((c["max_jump"].as_f64().unwrap() - 1.0).abs() < 1e-12, "{c}");
    // A body: a formula and its ruled file.
    let r = ok(
        &app,
        "/api/formula",
        json!({"body": {"kind": "cone"}, "format": "c"}),
    )
    .await;
    assert_eq!(r["model"]["type"], "ruled");
    let a = send(
        &app,
        "POST",
        "/api/formula",
        Some(&json!({"model": line, "format": "cobol"})),
    )
    .await;
    assert_eq!(a.status, 400);
    assert!(a.json()["error"].as_str().unwrap().contains("desmos"));
}

#[tokio::test]
async fn point_calculus_reproduces_a_polynomial_and_certifies_its_maximum() {
    let app = app();
    // f(a, b) = 1 + 2a + 3b + ab on nodes {0, 1, 2} × {0, 1}: of degree < node count per
    // factor, so the point equation reproduces it everywhere.
    let f = |a: f64, b: f64| 1.0 + 2.0 * a + 3.0 * b + a * b;
    let (na, nb) = ([0.0, 1.0, 2.0], [0.0, 1.0]);
    let values: Vec<f64> = na
        .iter()
        .flat_map(|&a| nb.iter().map(move |&b| f(a, b)))
        .collect();
    let v = ok(&app, "/api/pointcalc/fit", json!({"factors": [{"name": "a", "nodes": na}, {"name": "b", "nodes": nb}], "values": values})).await;
    let model = v["model"].clone();
    let s = ok(
        &app,
        "/api/pointcalc/shares",
        json!({"model": model, "at": [0.5, 0.25]}),
    )
    .await;
    assert!((s["value"][0].as_f64().unwrap() - f(0.5, 0.25)).abs() < 1e-13);
    assert!((s["sum"].as_f64().unwrap() - 1.0).abs() < 1e-14);
    assert_eq!(s["shares"].as_array().unwrap().len(), 6);
    let o = ok(
        &app,
        "/api/pointcalc/optimum",
        json!({"model": model, "goal": "max"}),
    )
    .await;
    assert_eq!(o["certified"], true);
    assert!((o["value"].as_f64().unwrap() - 10.0).abs() < 1e-9);
    assert!(dist(&numbers(&o["at"]), &[2.0, 1.0]) < 1e-6);
    let a = send(
        &app,
        "POST",
        "/api/pointcalc/fit",
        Some(&json!({"factors": [{"name": "a", "nodes": [0, 1]}], "values": [1]})),
    )
    .await;
    assert_eq!(a.status, 422);
}

#[tokio::test]
async fn exports_are_real_files() {
    let app = app();
    let surface =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    let svg = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": example2(), "format": "svg"})),
    )
    .await;
    assert_eq!(svg.status, 200);
    assert_eq!(svg.content_type, "image/svg+xml");
    assert!(String::from_utf8_lossy(&svg.body).contains("<svg"));
    let png = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": surface, "format": "png"})),
    )
    .await;
    assert_eq!(&png.body[..8], b"\x89PNG\r\n\x1a\n");
    // Binary STL: 80-byte header, u32 count, 50 bytes per triangle.
    let stl = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": surface, "format": "stl", "samples": 5})),
    )
    .await;
    let count = u32::from_le_bytes(stl.body[80..84].try_into().unwrap()) as usize;
    assert_eq!(count, 2 * 4 * 4);
    assert_eq!(stl.body.len(), 84 + 50 * count);
    let glb = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": surface, "format": "glb"})),
    )
    .await;
    assert_eq!(&glb.body[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(glb.body[8..12].try_into().unwrap()) as usize,
        glb.body.len()
    );
    let a = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": example2(), "format": "stl"})),
    )
    .await;
    assert_eq!(a.status, 422);
    let json_file = send(
        &app,
        "POST",
        "/api/export",
        Some(&json!({"model": example2(), "format": "json"})),
    )
    .await;
    let back: Value = serde_json::from_slice(&json_file.body).unwrap();
    assert_eq!(
        back["points"],
        json!([
            [10.0, 0.0],
            [22.0, 6.0],
            [19.0, 12.0],
            [11.0, 15.0],
            [8.0, 12.0],
            [20.0, 0.0]
        ])
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn concurrent_requests_all_answer() {
    let app = app();
    let mut tasks = Vec::new();
    for i in 0..16 {
        let app = app.clone();
        tasks.push(tokio::spawn(async move {
            let pts: Vec<[f64; 2]> = (0..2000)
                .map(|k| [k as f64, ((k * (i + 1)) as f64 * 0.01).sin()])
                .collect();
            ok(
                &app,
                "/api/bspline/interpolate",
                json!({"points": pts, "samples_per_span": 2}),
            )
            .await
        }));
    }
    for t in tasks {
        let v = t.await.unwrap();
        assert_eq!(v["parameters"].as_array().unwrap().len(), 2000);
    }
}
