//! The editor's second part (issue 25) against independent references: the drawing window
//! of a dragged B-spline point against de Boor's algorithm on the whole curve's model
//! (written in `common`), point-calculus grids against the polynomials they reproduce and
//! the point-calculus spec's worked examples, rational Bézier curves against the exact
//! quotient computed here.

mod common;

use common::*;
use geomkit_server::{router, Config};
use serde_json::{json, Value};

fn app() -> axum::Router {
    router(Config::default())
}

/// A long wavy polyline's points (the editor's frame-rate test shape).
fn wave(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let x = i as f64 / 100.0;
            [x, (i as f64 / 37.0).sin() + 0.3 * (i as f64 / 7.0).sin()]
        })
        .collect()
}

#[tokio::test]
async fn a_drag_window_is_the_whole_curve_near_the_point() {
    let app = app();
    let mut pts = wave(600);
    let base = json!({"points": pts, "samples_per_span": 3, "comb": {"per_span": 2}});
    let full = ok(&app, "/api/bspline/interpolate", base.clone()).await;
    // The point 300 moves: the whole curve again, and the window around it.
    pts[300][1] += 0.7;
    let mut moved = base.clone();
    moved["points"] = json!(pts);
    let after = ok(&app, "/api/bspline/interpolate", moved.clone()).await;
    moved["window"] = json!({"around": 300, "points": 40});
    moved["comb"]["scale"] = full["comb"]["scale"].clone();
    let w = ok(&app, "/api/bspline/interpolate", moved).await;
    assert!(w["model"].is_null());
    let m = &after["model"];
    let (knots, control) = (numbers(&m["knots"]), points(&m["control_points"]));
    let degree = m["degree"].as_u64().unwrap() as usize;
    let spans = w["window"]["spans"].as_u64().unwrap() as usize;
    let (first, last) = (
        w["window"]["first_span"].as_u64().unwrap() as usize,
        w["window"]["last_span"].as_u64().unwrap() as usize,
    );
    assert!(first < last && last <= spans);
    let s = &w["samples"];
    assert_eq!(s["first"].as_u64().unwrap() as usize, first * 3);
    assert_eq!(s["total"].as_u64().unwrap() as usize, spans * 3 + 1);
    assert_eq!(numbers(&after["samples"]["t"]).len(), spans * 3 + 1);
    let (ts, drawn) = (numbers(&s["t"]), points(&s["points"]));
    assert_eq!(ts.len(), (last - first) * 3 + 1);
    // The window's samples are the moved curve (de Boor on its model) ...
    for (t, p) in ts.iter().zip(&drawn) {
        assert!(dist(p, &de_boor(degree, &knots, &control, *t)) < 1e-12);
    }
    // ... and cover the parameters of points 260..=340 (40 on each side).
    let params = numbers(&after["parameters"]);
    assert!(ts[0] <= params[260] && *ts.last().unwrap() >= params[340]);
    // Outside the window the moved curve is the old one to rounding (in space: the
    // parameters of chord length shift everywhere, the drawn points do not).
    let old = points(&full["samples"]["points"]);
    let new = points(&after["samples"]["points"]);
    let first_sample = first * 3;
    let outside = (0..first_sample)
        .chain(first_sample + drawn.len()..new.len())
        .map(|i| dist(&old[i], &new[i]))
        .fold(0.0, f64::max);
    assert!(
        outside < 1e-9,
        "outside the window the curve moved by {outside}"
    );
    // The comb's teeth of the window are those of the whole answer at the same places.
    let c = &w["comb"];
    let at = c["first"].as_u64().unwrap() as usize;
    assert_eq!(c["total"].as_u64().unwrap() as usize, spans * 2 + 1);
    let (tips, all_tips) = (points(&c["tip"]), points(&after["comb"]["tip"]));
    // Same scale only if the whole answer's default scale is unchanged: compare curvature.
    let (k, all_k) = (
        numbers(&c["curvature"]),
        numbers(&after["comb"]["curvature"]),
    );
    for (i, ki) in k.iter().enumerate() {
        assert!((ki - all_k[at + i]).abs() <= 1e-9 * (1.0 + ki.abs()));
    }
    assert_eq!(tips.len(), k.len());
    assert!(all_tips.len() > at + tips.len() - 1);
}

#[tokio::test]
async fn a_drag_window_near_the_ends_and_bad_windows() {
    let app = app();
    let pts = wave(50);
    let body = json!({"points": pts, "samples_per_span": 2, "window": {"around": 0, "points": 5}});
    let w = ok(&app, "/api/bspline/interpolate", body).await;
    assert_eq!(w["window"]["first_span"], 0);
    let body = json!({"points": pts, "window": {"around": 49}});
    let w = ok(&app, "/api/bspline/interpolate", body).await;
    assert_eq!(w["window"]["last_span"], w["window"]["spans"]);
    let bad = send(
        &app,
        "POST",
        "/api/bspline/interpolate",
        Some(&json!({"points": pts, "window": {"around": 50}})),
    )
    .await;
    assert_eq!(bad.status, 400);
    assert_eq!(bad.json()["path"], "window.around");
    // A closed curve draws all (no window).
    let closed = json!({"points": pts, "closed": true, "window": {"around": 3}});
    let w: Value = ok(&app, "/api/bspline/interpolate", closed).await;
    assert!(w["model"].is_object());
}

/// A point-calculus model of one or two factors through `values`.
async fn fit(app: &axum::Router, factors: Value, values: Vec<f64>) -> Value {
    let v = ok(
        app,
        "/api/pointcalc/fit",
        json!({"factors": factors, "values": values}),
    )
    .await;
    v["model"].clone()
}

fn shares_of(v: &Value) -> Vec<f64> {
    v["shares"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["share"].as_f64().unwrap())
        .collect()
}

#[tokio::test]
async fn shares_are_the_function_parameters_of_equations_1_to_3() {
    // spec/point-calculus.md §2: M = A·a(t) + C·c(t) + B·b(t) with C at t = 1/2, 1/3, 2/3;
    // the shares of the source points (A, C, B in node order) at t = 0.3 are those
    // function-parameters.
    let app = app();
    let t: f64 = 0.3;
    let tb = 1.0 - t;
    let equations: [(f64, [f64; 3]); 3] = [
        (
            0.5,
            [tb * (1.0 - 2.0 * t), 4.0 * t * tb, t * (2.0 * t - 1.0)],
        ),
        (
            1.0 / 3.0,
            [
                tb * (1.0 - 3.0 * t),
                4.5 * t * tb,
                0.5 * t * (3.0 * t - 1.0),
            ],
        ),
        (
            2.0 / 3.0,
            [
                0.5 * tb * (2.0 - 3.0 * t),
                4.5 * t * tb,
                t * (3.0 * t - 2.0),
            ],
        ),
    ];
    for (tc, expected) in equations {
        let model = fit(
            &app,
            json!([{"name": "t", "nodes": [0.0, tc, 1.0]}]),
            vec![1.0, 5.0, 2.0],
        )
        .await;
        let s = ok(
            &app,
            "/api/pointcalc/shares",
            json!({"model": model, "at": [t]}),
        )
        .await;
        let got = shares_of(&s);
        for (g, e) in got.iter().zip(expected) {
            assert!((g - e).abs() < 1e-14, "C at {tc}: {got:?} vs {expected:?}");
        }
        let value = expected[0] + 5.0 * expected[1] + 2.0 * expected[2];
        assert!((s["value"][0].as_f64().unwrap() - value).abs() < 1e-13);
    }
}

#[tokio::test]
async fn nine_point_surface_shares_are_products_rows_first() {
    // §3, the construction that keeps the invariance: a_ij(u, v) = L_i(u)·L_j(v) with the
    // quadratic cardinal functions of equation (1) (nodes 0, 1/2, 1 in both directions).
    let app = app();
    let l = |t: f64| {
        [
            (1.0 - t) * (1.0 - 2.0 * t),
            4.0 * t * (1.0 - t),
            t * (2.0 * t - 1.0),
        ]
    };
    let nodes = [0.0, 0.5, 1.0];
    let values: Vec<f64> = (0..9).map(|i| (i * i) as f64 - 3.0).collect();
    let model = fit(
        &app,
        json!([{"name": "u", "nodes": nodes}, {"name": "v", "nodes": nodes}]),
        values,
    )
    .await;
    let (u, v) = (0.3, 0.8);
    let s = ok(
        &app,
        "/api/pointcalc/shares",
        json!({"model": model, "at": [u, v]}),
    )
    .await;
    let got = shares_of(&s);
    let (lu, lv) = (l(u), l(v));
    for i in 0..3 {
        for j in 0..3 {
            assert!((got[i * 3 + j] - lu[i] * lv[j]).abs() < 1e-14);
        }
    }
    assert!((s["sum"].as_f64().unwrap() - 1.0).abs() < 1e-14);
    // The printed geomatrix (9) is not this: its a_11(1/2, 1/2) is 1/16 and its sum 1.156
    // there; the product passes through the centre point: shares 0 but its own 1.
    let centre = ok(
        &app,
        "/api/pointcalc/shares",
        json!({"model": model, "at": [0.5, 0.5]}),
    )
    .await;
    let at_centre = shares_of(&centre);
    for (i, share) in at_centre.iter().enumerate() {
        assert_eq!(*share, if i == 4 { 1.0 } else { 0.0 }, "{at_centre:?}");
    }
}

#[tokio::test]
async fn grid_and_contours_of_a_bilinear_model() {
    // f(a, b) = 1 + 2a + 3b + ab on nodes {0, 1, 2} × {0, 1}: reproduced exactly; a contour
    // point of level h has f = h (f is linear along every grid edge, where marching squares
    // puts its points).
    let app = app();
    let f = |a: f64, b: f64| 1.0 + 2.0 * a + 3.0 * b + a * b;
    let (na, nb) = ([0.0, 1.0, 2.0], [0.0, 1.0]);
    let values: Vec<f64> = na
        .iter()
        .flat_map(|&a| nb.iter().map(move |&b| f(a, b)))
        .collect();
    let model = fit(
        &app,
        json!([{"name": "a", "nodes": na}, {"name": "b", "nodes": nb}]),
        values,
    )
    .await;
    let g = ok(
        &app,
        "/api/pointcalc/grid",
        json!({"model": model, "samples": 9, "contours": 5}),
    )
    .await;
    let (xs, ys) = (numbers(&g["axes"][0]), numbers(&g["axes"][1]));
    assert_eq!((xs.len(), ys.len()), (9, 9));
    assert_eq!((xs[0], xs[8], ys[0], ys[8]), (0.0, 2.0, 0.0, 1.0));
    let rows = g["values"].as_array().unwrap();
    for (i, row) in rows.iter().enumerate() {
        for (j, z) in numbers(row).iter().enumerate() {
            assert!((z - f(xs[i], ys[j])).abs() < 1e-13);
        }
    }
    assert_eq!(numbers(&g["range"]), vec![1.0, 10.0]);
    let contours = g["contours"].as_array().unwrap();
    assert_eq!(contours.len(), 5);
    for (l, c) in contours.iter().enumerate() {
        let h = c["level"].as_f64().unwrap();
        assert!((h - (1.0 + 9.0 * (l + 1) as f64 / 6.0)).abs() < 1e-13);
        let segments = c["segments"].as_array().unwrap();
        assert!(!segments.is_empty());
        for s in segments {
            for p in s.as_array().unwrap() {
                let p = numbers(p);
                assert!((f(p[0], p[1]) - h).abs() < 1e-12, "{p:?} on level {h}");
            }
        }
    }
}

#[tokio::test]
async fn slices_of_a_three_factor_model() {
    // g(x, y, z) = x·y + z² + 1 on {0, 1} × {0, 1, 2} × {-1, 0, 1}: reproduced (degree below
    // the node counts); a slice along y through (0.5, ·, 0.25) is 0.5·y + 1.0625.
    let app = app();
    let g = |x: f64, y: f64, z: f64| x * y + z * z + 1.0;
    let (nx, ny, nz) = ([0.0, 1.0], [0.0, 1.0, 2.0], [-1.0, 0.0, 1.0]);
    let mut values = Vec::new();
    for &x in &nx {
        for &y in &ny {
            for &z in &nz {
                values.push(g(x, y, z));
            }
        }
    }
    let model = fit(
        &app,
        json!([{"name": "x", "nodes": nx}, {"name": "y", "nodes": ny}, {"name": "z", "nodes": nz}]),
        values,
    )
    .await;
    let s = ok(
        &app,
        "/api/pointcalc/grid",
        json!({"model": model, "at": [0.5, 7.0, 0.25], "free": [1], "samples": 5}),
    )
    .await;
    let ys = numbers(&s["axes"][0]);
    assert_eq!(ys, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
    for (y, v) in ys.iter().zip(numbers(&s["values"])) {
        assert!((v - g(0.5, *y, 0.25)).abs() < 1e-13);
    }
    // A map over (z, x) through y = 1.5.
    let m = ok(
        &app,
        "/api/pointcalc/grid",
        json!({"model": model, "at": [0.0, 1.5, 0.0], "free": [2, 0], "samples": 3, "contours": 0}),
    )
    .await;
    let (zs, xs) = (numbers(&m["axes"][0]), numbers(&m["axes"][1]));
    for (i, row) in m["values"].as_array().unwrap().iter().enumerate() {
        for (j, v) in numbers(row).iter().enumerate() {
            assert!((v - g(xs[j], 1.5, zs[i])).abs() < 1e-13);
        }
    }
    assert_eq!(m["contours"].as_array().unwrap().len(), 0);
    // Bad requests name their field.
    for (body, path) in [
        (json!({"model": model, "free": [0, 0]}), "free"),
        (json!({"model": model, "free": [3]}), "free"),
        (json!({"model": model, "at": [0.0, 1.0]}), "at"),
        (json!({"model": model, "samples": 1}), "samples"),
        (json!({"model": model, "response": 1}), "response"),
    ] {
        let a = send(&app, "POST", "/api/pointcalc/grid", Some(&body)).await;
        assert_eq!(a.status, 400, "{body}");
        assert_eq!(a.json()["path"], path);
    }
}

#[tokio::test]
async fn a_rational_quarter_circle_is_drawn_on_the_circle() {
    // Points (1, 0), (1, 1), (0, 1) with weights 1, 1/√2, 1: the exact quarter of the unit
    // circle; also after exact elevation (the weights are the page's rational curve).
    let app = app();
    let model = json!({"type": "bezier_curve", "points": [[1, 0], [1, 1], [0, 1]],
        "weights": [1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0]});
    let up = ok(
        &app,
        "/api/bezier/elevate",
        json!({"model": model, "to": 4}),
    )
    .await;
    assert_eq!(up["model"]["weights"].as_array().unwrap().len(), 5);
    for m in [model, up["model"].clone()] {
        let s = ok(&app, "/api/samples", json!({"model": m, "samples": 101})).await;
        for p in points(&s["points"]) {
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-14, "{p:?}");
        }
    }
    // Weight 2 on the middle point: the quotient (w0 b0 P0 + w1 b1 P1 + w2 b2 P2) / Σ w b,
    // here at t = 1/2: ((1, 0)/4 + 2 (1, 1)/2 + (0, 1)/4) / (1/4 + 1 + 1/4) = (5/6, 5/6).
    let heavy =
        json!({"type": "bezier_curve", "points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 2, 1]});
    let s = ok(&app, "/api/samples", json!({"model": heavy, "samples": 3})).await;
    let mid = &points(&s["points"])[1];
    assert!(dist(mid, &[5.0 / 6.0, 5.0 / 6.0]) < 1e-15);
}

#[tokio::test]
async fn the_point_equation_as_a_formula() {
    // Nodes 0, 1/2, 1 and values 1, 3, 2: the point equation of spec §2 (1) is the
    // polynomial 1 + 7t − 6t²; its Python (NumPy) text evaluated term by term is checked in
    // the editor's e2e test by a JavaScript engine; here the shape of the answer.
    let app = app();
    let model = fit(
        &app,
        json!([{"name": "t", "nodes": [0.0, 0.5, 1.0]}]),
        vec![1.0, 3.0, 2.0],
    )
    .await;
    let f = ok(
        &app,
        "/api/formula",
        json!({"model": model, "format": "js"}),
    )
    .await;
    assert_eq!(f["variables"], json!(["t"]));
    assert_eq!(f["coordinates"], json!(["y"]));
    assert!(f["op_count"].as_u64().unwrap() > 0);
    assert!(
        f["formula"].as_str().unwrap().contains("(t)"),
        "{}",
        f["formula"]
    );
}
