//! The body view (`/api/body/view`) and the curvature colouring of Bézier surfaces
//! (`/api/surface/mesh`), against references that do not come from the code under test:
//! the single formula evaluated by the expression engine's tape at the seams' points, the
//! continuity report of the composite surface, the smoothness of splines at simple and
//! double knots (de Boor), hand-computed jumps of the patches, the geometry of the cube, and
//! the curvature of a sphere (K = 1/R², |H| = 1/R) and of the saddle z = uv in closed form.

mod common;

use axum::http::StatusCode;
use common::*;
use geomkit::compose::bodies;
use geomkit_server::{router, Config};
use serde_json::{json, Value};

fn app() -> axum::Router {
    router(Config::default())
}

async fn fails(app: &axum::Router, body: Value, status: StatusCode) -> Value {
    let a = send(app, "POST", "/api/body/view", Some(&body)).await;
    assert_eq!(a.status, status, "{}", String::from_utf8_lossy(&a.body));
    a.json()
}

fn seams(v: &Value) -> &Vec<Value> {
    v["seams"].as_array().unwrap()
}

/// (u, v) pairs of a seam.
fn params(seam: &Value) -> Vec<[f64; 2]> {
    points(&seam["params"])
        .into_iter()
        .map(|p| [p[0], p[1]])
        .collect()
}

#[tokio::test]
async fn the_cube_seams_are_creases_on_its_single_formula() {
    let r = ok(&app(), "/api/body/view", json!({"body": {"kind": "cube"}})).await;
    let all = seams(&r);
    assert!(!all.is_empty());
    // The formula is C0 across every line (its parameters kink at every polygon vertex and
    // every curve); 12 of them are the cube's edges, where the faces meet at right angles
    // (creases), 8 run from the caps' centres to the corners inside the flat top and bottom.
    for s in all {
        assert_eq!(s["smoothness"], "C0", "{}", s["label"]);
        assert_eq!(s["order"], 0);
        assert!(s["label"].as_str().unwrap().contains("C0"));
    }
    assert_eq!(
        r["legend"],
        json!([{"smoothness": "C0", "crease": true, "count": 12},
               {"smoothness": "C0", "crease": false, "count": 8}])
    );
    // The seam polylines lie on the single formula, evaluated by the expression engine.
    let formula = bodies::cube().unwrap().formula().unwrap();
    for s in all {
        let uv = params(s);
        let us: Vec<f64> = uv.iter().map(|p| p[0]).collect();
        let vs: Vec<f64> = uv.iter().map(|p| p[1]).collect();
        let mut want = vec![0.0; uv.len() * 3];
        formula.eval_batch(&[&us, &vs], &mut want).unwrap();
        let got = numbers(&s["points"]);
        assert_eq!(got.len(), want.len());
        for (a, b) in got.iter().zip(&want) {
            assert!((a - b).abs() < 1e-12, "{} vs {b} on {}", a, s["label"]);
        }
        // A crease is on an edge of the cube [-1, 1]³ (two coordinates at ±1); the others
        // lie in the top or bottom face, on a diagonal (|x| = |y|, z = ±1).
        for p in got.chunks_exact(3) {
            let at_faces = p.iter().filter(|x| (x.abs() - 1.0).abs() < 1e-12).count();
            if s["crease"] == true {
                assert!(at_faces >= 2, "{p:?} is not on an edge of the cube");
            } else {
                assert!(
                    (p[2].abs() - 1.0).abs() < 1e-12 && (p[0].abs() - p[1].abs()).abs() < 1e-12,
                    "{p:?}"
                );
            }
        }
    }
    // The mesh: triangles index its vertices, which lie on the cube's surface.
    let pos = numbers(&r["mesh"]["positions"]);
    let nor = numbers(&r["mesh"]["normals"]);
    let tri: Vec<u64> = r["mesh"]["triangles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    assert_eq!(pos.len(), nor.len());
    assert!(tri.len() >= 36 && tri.len().is_multiple_of(3));
    assert!(tri.iter().all(|&i| (i as usize) < pos.len() / 3));
    for p in pos.chunks_exact(3) {
        let m = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!((m - 1.0).abs() < 1e-12, "{p:?} is not on the cube");
    }
    // The body's ruled model file comes back, to save or export.
    assert_eq!(r["model"]["type"], "ruled");
}

#[tokio::test]
async fn a_composite_whose_patches_jump_is_marked_where_its_report_says() {
    // The example of docs/formats.md: z = u v on [0, 1], then v (1 - u) on [1, 2]: they meet
    // at u = 1 (z = v) with slopes v and -v: a crease (C0).
    let meet = json!({
        "type": "composite_surface", "u_knots": [0, 1, 2], "v_knots": [0, 1],
        "patches": [
            [{"bezier": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]}],
            [{"x": "1 + u", "y": "v", "z": "v*(1 - u)", "domain": [[0, 1], [0, 1]]}]
        ]
    });
    let r = ok(&app(), "/api/body/view", json!({"model": meet})).await;
    assert_eq!(seams(&r).len(), 1);
    let s = &seams(&r)[0];
    assert_eq!(
        (&s["line"], &s["value"], &s["smoothness"]),
        (&json!("u"), &json!(1.0), &json!("C0"))
    );
    // The normals (-v, -1, 1) and (v, -1, 1) differ off v = 0: the tangent plane turns.
    assert_eq!(s["crease"], true);
    // The slope jump across u = 1: |v - (-v)| = 2v, largest at v = 1 (sampled inside).
    let j1 = s["jumps"][1].as_f64().unwrap();
    assert!(j1 > 1.8 && j1 <= 2.0 + 1e-9, "{j1}");
    assert_eq!(r["continuity"]["continuous"], true);
    // Lifted by 0.5: the patches jump by 0.5 along the whole line; the report says so and
    // the seam is marked discontinuous with that jump.
    let mut gap = meet.clone();
    gap["patches"][1][0]["z"] = json!("v*(1 - u) + 0.5");
    let r = ok(&app(), "/api/body/view", json!({"model": gap})).await;
    let s = &seams(&r)[0];
    assert_eq!(s["smoothness"], "discontinuous");
    assert!((s["patch_jump"].as_f64().unwrap() - 0.5).abs() < 1e-12);
    assert!(
        s["label"].as_str().unwrap().contains("jump by 0.5"),
        "{}",
        s["label"]
    );
    assert_eq!(r["continuity"]["continuous"], false);
    assert!((r["continuity"]["max_jump"].as_f64().unwrap() - 0.5).abs() < 1e-12);
}

#[tokio::test]
async fn an_explicit_composite_is_drawn_as_its_graph() {
    // z = x y on [0, 1]², then the 1-D Bézier patch 1 - s + 2 s t on [1, 2]: at x = 1 they
    // differ by |1 - y| (largest 1 at y = 0): discontinuous; the seam's points are on the
    // graph (x, y, z) of the formula.
    let m = json!({
        "type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
        "patches": [["x*y"], [{"bezier": [[[1], [1]], [[0], [2]]]}]]
    });
    let r = ok(
        &app(),
        "/api/body/view",
        json!({"model": m.clone(), "seam_samples": 5}),
    )
    .await;
    assert_eq!(r["parameters"], json!(["x", "y"]));
    let s = &seams(&r)[0];
    assert_eq!(s["name"], "x");
    assert_eq!(s["smoothness"], "discontinuous");
    assert!((s["patch_jump"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    let f = ok(&app(), "/api/formula", json!({"model": m})).await;
    assert_eq!(f["continuity"]["continuous"], false);
    for (p, uv) in numbers(&s["points"]).chunks_exact(3).zip(params(s)) {
        assert_eq!((p[0], p[1]), (uv[0], uv[1]));
    }
}

#[tokio::test]
async fn spline_seams_have_the_smoothness_of_their_knots() {
    // Bicubic, a simple interior knot in u (C2 across it) and a double one in v (C1).
    let net: Vec<Vec<Vec<f64>>> = (0..5)
        .map(|i| {
            (0..6)
                .map(|j| vec![i as f64, j as f64, ((i * 7 + j * 3) % 5) as f64 * 0.3])
                .collect()
        })
        .collect();
    let m = json!({
        "type": "bspline_surface", "degree": [3, 3],
        "knots_u": [0, 0, 0, 0, 0.4, 1, 1, 1, 1],
        "knots_v": [0, 0, 0, 0, 0.5, 0.5, 1, 1, 1, 1],
        "net": net
    });
    let r = ok(&app(), "/api/body/view", json!({"model": m})).await;
    let by = |line: &str| -> Vec<String> {
        seams(&r)
            .iter()
            .filter(|s| s["line"] == line)
            .map(|s| s["smoothness"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(by("u"), ["C2", "C2"]);
    assert_eq!(by("v"), ["C1", "C1"]);
    assert_eq!(
        r["legend"],
        json!([{"smoothness": "C1", "crease": false, "count": 2},
               {"smoothness": "C2", "crease": false, "count": 2}])
    );
}

#[tokio::test]
async fn bad_requests_are_refused_with_their_reason() {
    let app = app();
    let curve = json!({"type": "bezier_curve", "points": [[0, 0], [1, 1]]});
    let e = fails(
        &app,
        json!({"model": curve}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(e["error"].as_str().unwrap().contains("body view"), "{e}");
    fails(&app, json!({}), StatusCode::BAD_REQUEST).await;
    let e = fails(
        &app,
        json!({"body": {"kind": "cube"}, "seam_samples": 1}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    assert_eq!(e["path"], "seam_samples");
    let e = fails(
        &app,
        json!({"body": {"kind": "cube"}, "tolerance": -1}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    assert_eq!(e["path"], "tolerance");
    fails(
        &app,
        json!({"body": {"kind": "sphere"}}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    // A bilinear spline on 100 × 100 cells: 20 200 seam pieces, over the limit of 20 000.
    let mut knots: Vec<f64> = (0..=100).map(f64::from).chain([0.0, 100.0]).collect();
    knots.sort_by(f64::total_cmp);
    let net: Vec<Vec<[f64; 3]>> = (0..101)
        .map(|i| (0..101).map(|j| [i as f64, j as f64, 0.0]).collect())
        .collect();
    let big = json!({"type": "bspline_surface", "degree": [1, 1], "knots_u": knots, "knots_v": knots, "net": net});
    let e = fails(&app, json!({"model": big}), StatusCode::PAYLOAD_TOO_LARGE).await;
    assert!(e["error"].as_str().unwrap().contains("20000"), "{e}");
}

/// An octant of the sphere of radius `r` as a rational biquadratic net.
fn octant(r: f64) -> Value {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let profile = [([r, 0.0], 1.0), ([r, r], h), ([0.0, r], 1.0)];
    let turn = [([1.0, 0.0], 1.0), ([1.0, 1.0], h), ([0.0, 1.0], 1.0)];
    let net: Vec<Vec<[f64; 3]>> = profile
        .iter()
        .map(|(p, _)| {
            turn.iter()
                .map(|(t, _)| [p[0] * t[0], p[0] * t[1], p[1]])
                .collect()
        })
        .collect();
    let weights: Vec<Vec<f64>> = profile
        .iter()
        .map(|(_, a)| turn.iter().map(|(_, b)| a * b).collect())
        .collect();
    json!({"type": "bezier_surface", "net": net, "weights": weights})
}

#[tokio::test]
async fn bezier_curvature_colouring_matches_the_sphere_and_the_saddle() {
    let app = app();
    let r = 2.5;
    for (colour, want) in [("gaussian", 1.0 / (r * r)), ("mean", 1.0 / r)] {
        let m = ok(
            &app,
            "/api/surface/mesh",
            json!({"model": octant(r), "samples": 9, "colour": colour}),
        )
        .await;
        let us = numbers(&m["u"]);
        let values = numbers(&m["values"]);
        for (k, val) in values.iter().enumerate() {
            if us[k / 9] == 1.0 {
                assert_eq!(*val, 0.0, "the pole is singular: drawn neutral");
            } else {
                assert!((val.abs() - want).abs() < 1e-11, "{colour} {val} vs {want}");
            }
        }
    }
    // (u, v, u v): K = -1/W², H = -u v / W^(3/2), W = 1 + u² + v².
    let saddle =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    for colour in ["gaussian", "mean"] {
        let m = ok(
            &app,
            "/api/surface/mesh",
            json!({"model": saddle, "samples": 5, "colour": colour}),
        )
        .await;
        let (us, vs, values) = (numbers(&m["u"]), numbers(&m["v"]), numbers(&m["values"]));
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let w = 1.0 + u * u + v * v;
                let want = if colour == "gaussian" {
                    -1.0 / (w * w)
                } else {
                    -u * v / w.powf(1.5)
                };
                assert!(
                    (values[a * 5 + b] - want).abs() < 1e-14,
                    "{colour} at ({u}, {v})"
                );
            }
        }
        assert_eq!(m["colour"], colour);
    }
}

#[tokio::test]
async fn a_rational_bezier_curve_has_a_formula_on_its_circle() {
    // The quarter circle: (1, 0), (1, 1), (0, 1) with weights 1, 1/√2, 1; its formula, run
    // on the engine's tape, is on x² + y² = 1 and ends at the end points.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let m =
        json!({"type": "bezier_curve", "points": [[1, 0], [1, 1], [0, 1]], "weights": [1, h, 1]});
    let f = ok(
        &app(),
        "/api/formula",
        json!({"model": m, "format": "sympy"}),
    )
    .await;
    assert_eq!(f["coordinates"], json!(["x", "y"]));
    let model =
        geomkit_model::AnyModel::from_file(geomkit_model::parse_file(&m.to_string()).unwrap())
            .unwrap();
    let (formula, _) = geomkit_server::api::formula::model_formula(model).unwrap();
    let ts: Vec<f64> = (0..=20).map(|i| i as f64 / 20.0).collect();
    let mut out = vec![0.0; ts.len() * 2];
    formula.eval_batch(&[&ts], &mut out).unwrap();
    for p in out.chunks_exact(2) {
        assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15, "{p:?}");
    }
    assert_eq!((out[0], out[1]), (1.0, 0.0));
    assert!(out[40].abs() < 1e-15 && (out[41] - 1.0).abs() < 1e-15);
}
