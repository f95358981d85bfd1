//! The 3-D view's endpoints (`/api/surface/*`) against references written here: tensor de
//! Casteljau and de Boor, the normals and curvatures of quadrics in closed form, the
//! shifted Legendre polynomials for the best L2 approximation, and SciPy's
//! `RectBivariateSpline` values kept in crates/geomkit/tests/data/bspline_scipy.json.

mod common;

use axum::http::StatusCode;
use common::*;
use geomkit_server::{router, Config};
use serde_json::{json, Value};

fn app() -> axum::Router {
    router(Config::default())
}

/// p(u, v) of a net by de Casteljau in u (rows as points) then in v.
fn tensor_de_casteljau(net: &[Vec<Vec<f64>>], u: f64, v: f64) -> Vec<f64> {
    let cols: Vec<Vec<f64>> = (0..net[0].len())
        .map(|j| {
            let column: Vec<Vec<f64>> = net.iter().map(|row| row[j].clone()).collect();
            de_casteljau(&column, u)
        })
        .collect();
    de_casteljau(&cols, v)
}

fn net_of(v: &Value) -> Vec<Vec<Vec<f64>>> {
    v.as_array().unwrap().iter().map(points).collect()
}

/// Point k of a flat [x, y, z, ...] array.
fn at(flat: &[f64], k: usize) -> &[f64] {
    &flat[3 * k..3 * k + 3]
}

async fn fails(app: &axum::Router, path: &str, body: Value, status: StatusCode) -> Value {
    let a = send(app, "POST", path, Some(&body)).await;
    assert_eq!(
        a.status,
        status,
        "{path}: {}",
        String::from_utf8_lossy(&a.body)
    );
    a.json()
}

#[tokio::test]
async fn mesh_of_a_bilinear_patch_has_exact_points_and_normals() {
    let s =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    let m = ok(
        &app(),
        "/api/surface/mesh",
        json!({"model": s, "samples": 5}),
    )
    .await;
    let (us, vs) = (numbers(&m["u"]), numbers(&m["v"]));
    let (pos, nor) = (numbers(&m["positions"]), numbers(&m["normals"]));
    assert_eq!((m["rows"].as_u64(), pos.len()), (Some(5), 75));
    for (a, &u) in us.iter().enumerate() {
        for (b, &v) in vs.iter().enumerate() {
            let k = a * 5 + b;
            assert!(dist(at(&pos, k), &[u, v, u * v]) < 1e-15);
            // S_u × S_v = (1, 0, v) × (0, 1, u) = (−v, −u, 1).
            let len = (1.0 + u * u + v * v).sqrt();
            assert!(dist(at(&nor, k), &[-v / len, -u / len, 1.0 / len]) < 1e-15);
        }
    }
    assert_eq!(m["net"]["rows"], 2);
    assert_eq!(numbers(&m["net"]["points"]).len(), 12);
    assert!(m["values"].is_null());
}

#[tokio::test]
async fn mesh_of_a_20x20_net_is_de_casteljau() {
    // A wavy 20×20 net (degrees 19, 19).
    let net: Vec<Vec<Vec<f64>>> = (0..20)
        .map(|i| {
            (0..20)
                .map(|j| {
                    let (x, y) = (i as f64 / 19.0, j as f64 / 19.0);
                    vec![
                        x,
                        y,
                        (3.0 * x).sin() * (2.0 * y).cos() + 0.1 * ((i * j) % 3) as f64,
                    ]
                })
                .collect()
        })
        .collect();
    let m = ok(
        &app(),
        "/api/surface/mesh",
        json!({"model": {"type": "bezier_surface", "net": net}, "samples": 9}),
    )
    .await;
    let (us, vs, pos) = (numbers(&m["u"]), numbers(&m["v"]), numbers(&m["positions"]));
    for a in 0..9 {
        for b in 0..9 {
            let want = tensor_de_casteljau(&net, us[a], vs[b]);
            assert!(dist(at(&pos, a * 9 + b), &want) < 1e-13, "({a}, {b})");
        }
    }
}

#[tokio::test]
async fn a_rational_quarter_cylinder_stays_on_the_cylinder() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let s = json!({"type": "bezier_surface",
        "net": [[[1, 0, 0], [1, 0, 2]], [[1, 1, 0], [1, 1, 2]], [[0, 1, 0], [0, 1, 2]]],
        "weights": [[1, 1], [w, w], [1, 1]]});
    let m = ok(
        &app(),
        "/api/surface/mesh",
        json!({"model": s, "samples": 7}),
    )
    .await;
    let (pos, nor) = (numbers(&m["positions"]), numbers(&m["normals"]));
    for k in 0..49 {
        let p = at(&pos, k);
        assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15, "point {k}: {p:?}");
        // The normal is radial: ±(x, y, 0).
        let n = at(&nor, k);
        assert!(n[2].abs() < 1e-15 && (n[0] * p[1] - n[1] * p[0]).abs() < 1e-15);
        assert!((n[0].hypot(n[1]) - 1.0).abs() < 1e-14);
    }
    assert_eq!(numbers(&m["net"]["weights"]).len(), 6);
}

#[tokio::test]
async fn rows_and_columns_are_inserted_and_removed() {
    let app = app();
    let net = json!([
        [[0, 0, 0], [0, 1, 0], [0, 2, 0]],
        [[1, 0, 0], [1, 1, 2], [1, 2, 0]],
        [[2, 0, 0], [2, 1, 0], [2, 2, 0]]
    ]);
    let s = json!({"type": "bezier_surface", "net": net});
    let r = ok(
        &app,
        "/api/surface/edit",
        json!({"model": s, "insert": {"direction": "u", "index": 1, "points": [[0.5, 0, 1], [0.5, 1, 1], [0.5, 2, 1]]}}),
    )
    .await;
    let got = net_of(&r["model"]["net"]);
    assert_eq!(r["degrees"], json!([3, 2]));
    assert_eq!(
        got[1],
        vec![
            vec![0.5, 0.0, 1.0],
            vec![0.5, 1.0, 1.0],
            vec![0.5, 2.0, 1.0]
        ]
    );
    assert_eq!(got[0], net_of(&net)[0]);
    assert_eq!(got[2], net_of(&net)[1]);
    // How far it moved: at least the distance at one parameter, by de Casteljau.
    let moved = dist(
        &tensor_de_casteljau(&got, 0.3, 0.5),
        &tensor_de_casteljau(&net_of(&net), 0.3, 0.5),
    );
    let d = &r["deviation"];
    assert!(d["upper_bound"].as_f64().unwrap() >= moved);
    assert!(d["upper_bound"].as_f64().unwrap() >= d["max_found"].as_f64().unwrap());
    // Column 1 removed: the columns 0 and 2 remain.
    let r = ok(
        &app,
        "/api/surface/edit",
        json!({"model": s, "remove": {"direction": "v", "index": 1}}),
    )
    .await;
    let got = net_of(&r["model"]["net"]);
    assert_eq!(r["degrees"], json!([2, 1]));
    for (i, row) in got.iter().enumerate() {
        assert_eq!(
            row,
            &vec![net_of(&net)[i][0].clone(), net_of(&net)[i][2].clone()]
        );
    }
    // A rational net takes the weights of the new line.
    let rational = json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]],
        "weights": [[1, 2], [3, 4]]});
    let r = ok(
        &app,
        "/api/surface/edit",
        json!({"model": rational, "insert": {"direction": "v", "index": 2, "points": [[0, 2, 0], [1, 2, 0]], "weights": [5, 6]}}),
    )
    .await;
    assert_eq!(
        points(&r["model"]["weights"]),
        vec![vec![1.0, 2.0, 5.0], vec![3.0, 4.0, 6.0]]
    );
    assert!(r["deviation"].is_null());
    // Mistakes: no line, an index out of range, a line of the wrong length.
    fails(
        &app,
        "/api/surface/edit",
        json!({"model": s}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    let e = fails(
        &app,
        "/api/surface/edit",
        json!({"model": s, "remove": {"direction": "u", "index": 3}}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(e["error"].as_str().unwrap().contains("3"), "{e}");
    fails(
        &app,
        "/api/surface/edit",
        json!({"model": s, "insert": {"direction": "u", "index": 0, "points": [[0, 0, 0]]}}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
}

/// u³ minus its best quadratic on [0, 1]: the shifted Legendre P̃3(u) / 20.
fn legendre_residual(u: f64) -> f64 {
    (20.0 * u.powi(3) - 30.0 * u * u + 12.0 * u - 1.0) / 20.0
}

#[tokio::test]
async fn best_l2_approximation_of_a_surface() {
    // x = u, y = v (real degree 1), z = u³v³: to degrees (2, 2).
    let net: Vec<Vec<Vec<f64>>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    vec![
                        i as f64 / 3.0,
                        j as f64 / 3.0,
                        f64::from(u8::from(i == 3 && j == 3)),
                    ]
                })
                .collect()
        })
        .collect();
    let s = json!({"type": "bezier_surface", "net": net});
    let r = ok(
        &app(),
        "/api/surface/approximate",
        json!({"model": s, "to": [2, 2], "samples": 5}),
    )
    .await;
    let l2 = (1.0 / 49.0 - (1.0 / 7.0 - 1.0 / 2800.0_f64).powi(2)).sqrt();
    assert!((r["l2_error"].as_f64().unwrap() - l2).abs() < 1e-14);
    let corner = 1.0 - 0.95_f64 * 0.95;
    assert!(r["linf_bound"].as_f64().unwrap() >= corner);
    assert!((r["linf_found"].as_f64().unwrap() - corner).abs() < 1e-13);
    let reduced = net_of(&r["model"]["net"]);
    assert_eq!((reduced.len(), reduced[0].len()), (3, 3));
    let mesh = &r["mesh"];
    let (us, vs, pos) = (
        numbers(&mesh["u"]),
        numbers(&mesh["v"]),
        numbers(&mesh["positions"]),
    );
    let values = numbers(&mesh["values"]);
    for a in 0..5 {
        for b in 0..5 {
            let (u, v) = (us[a], vs[b]);
            let q = (u.powi(3) - legendre_residual(u)) * (v.powi(3) - legendre_residual(v));
            let k = a * 5 + b;
            assert!(dist(at(&pos, k), &[u, v, q]) < 1e-14, "({u}, {v})");
            assert!((values[k] - (u.powi(3) * v.powi(3) - q).abs()).abs() < 1e-14);
        }
    }
    let app = app();
    // Up is not an approximation; a rational net is refused with the reason.
    fails(
        &app,
        "/api/surface/approximate",
        json!({"model": s, "to": [3, 4]}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    fails(
        &app,
        "/api/surface/approximate",
        json!({"model": s, "to": [3, 3]}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    let rational = json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]], "weights": [[1, 2], [3, 4]]});
    let e = fails(
        &app,
        "/api/surface/approximate",
        json!({"model": rational, "to": [0, 1]}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(e["error"].as_str().unwrap().contains("weights"));
}

/// Tensor de Boor of a scalar B-spline surface file at (x, y).
fn de_boor_surface(model: &Value, x: f64, y: f64) -> f64 {
    let (ku, kv) = (numbers(&model["knots_u"]), numbers(&model["knots_v"]));
    let net = net_of(&model["net"]);
    let rows: Vec<Vec<f64>> = net.iter().map(|row| de_boor(3, &kv, row, y)).collect();
    de_boor(3, &ku, &rows, x)[0]
}

#[tokio::test]
async fn a_refused_surface_reduction_names_its_reason() {
    // Degree 2 in u with a real u-degree of 2 (z = u² row by row), 1 in v.
    let s = json!({"type": "bezier_surface",
        "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0]], [[2, 0, 1], [2, 1, 1]]]});
    let e = fails(
        &app(),
        "/api/bezier/reduce",
        json!({"model": s, "to": [1, 1]}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert_eq!(e["reason"], "real_degree");
    assert_eq!(e["direction"], "u");
    assert_eq!(
        (
            e["real_degree"].as_u64(),
            e["requested"].as_u64(),
            e["defect"].as_u64()
        ),
        (Some(2), Some(1), Some(0))
    );
    assert!(
        e["error"].as_str().unwrap().contains("real u-degree is 2"),
        "{e}"
    );
}

#[tokio::test]
async fn heights_of_a_quadric_with_their_curvature() {
    // z = a x² + b xy + c y²: the not-a-knot bicubic reproduces it, so K and H are exact.
    let (a, b, c) = (0.3, -0.2, 0.5);
    let xs: Vec<f64> = (0..7).map(|i| -1.5 + 0.5 * i as f64).collect();
    let ys: Vec<f64> = (0..5).map(|j| -1.0 + 0.5 * j as f64).collect();
    let f = |x: f64, y: f64| a * x * x + b * x * y + c * y * y;
    let z: Vec<Vec<f64>> = xs
        .iter()
        .map(|&x| ys.iter().map(|&y| f(x, y)).collect())
        .collect();
    let app = app();
    for colour in ["gaussian", "mean"] {
        let r = ok(
            &app,
            "/api/surface/heights",
            json!({"z": z, "x": xs, "y": ys, "samples": 5, "colour": colour}),
        )
        .await;
        assert_eq!(r["model"]["type"], "bspline_surface");
        for (i, &x) in xs.iter().enumerate() {
            for (j, &y) in ys.iter().enumerate() {
                assert!((de_boor_surface(&r["model"], x, y) - z[i][j]).abs() < 1e-13);
            }
        }
        let m = &r["mesh"];
        let (us, vs, pos, values) = (
            numbers(&m["u"]),
            numbers(&m["v"]),
            numbers(&m["positions"]),
            numbers(&m["values"]),
        );
        assert_eq!((us[0], us[4], vs[0], vs[4]), (-1.5, 1.5, -1.0, 1.0));
        for (p, &x) in us.iter().enumerate() {
            for (q, &y) in vs.iter().enumerate() {
                let k = p * 5 + q;
                assert!(dist(at(&pos, k), &[x, y, f(x, y)]) < 1e-13);
                let (fx, fy) = (2.0 * a * x + b * y, b * x + 2.0 * c * y);
                let w = 1.0 + fx * fx + fy * fy;
                let want = if colour == "gaussian" {
                    (4.0 * a * c - b * b) / (w * w)
                } else {
                    ((1.0 + fy * fy) * 2.0 * a - 2.0 * fx * fy * b + (1.0 + fx * fx) * 2.0 * c)
                        / (2.0 * w.powf(1.5))
                };
                assert!((values[k] - want).abs() < 1e-11, "{colour} at ({x}, {y})");
            }
        }
        let range = numbers(&m["range"]);
        assert!(range[0] <= range[1]);
    }
}

#[tokio::test]
async fn heights_match_scipy_rect_bivariate_spline() {
    let data: Value =
        serde_json::from_str(include_str!("../../geomkit/tests/data/bspline_scipy.json")).unwrap();
    let app = app();
    for case in data["surfaces"].as_array().unwrap() {
        let r = ok(
            &app,
            "/api/surface/heights",
            json!({"z": case["z"], "x": case["x"], "y": case["y"], "samples": 3}),
        )
        .await;
        let (ex, ey) = (numbers(&case["eval_x"]), numbers(&case["eval_y"]));
        let want = points(&case["eval"]);
        let scale = want.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, &x) in ex.iter().enumerate().step_by(7) {
            for (j, &y) in ey.iter().enumerate().step_by(5) {
                let got = de_boor_surface(&r["model"], x, y);
                assert!(
                    (got - want[i][j]).abs() <= 1e-12 * scale,
                    "{}: ({x}, {y})",
                    case["name"]
                );
            }
        }
    }
}

#[tokio::test]
async fn mistakes_are_clear_errors() {
    let app = app();
    let curve = json!({"type": "bezier_curve", "points": [[0, 0], [1, 1]]});
    let e = fails(
        &app,
        "/api/surface/mesh",
        json!({"model": curve}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(
        e["error"].as_str().unwrap().contains("bezier_surface"),
        "{e}"
    );
    let planar = json!({"type": "bezier_surface", "net": [[[0, 0], [0, 1]], [[1, 0], [1, 1]]]});
    let e = fails(
        &app,
        "/api/surface/mesh",
        json!({"model": planar}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    assert!(e["error"].as_str().unwrap().contains("R^2"), "{e}");
    let s =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    fails(
        &app,
        "/api/surface/mesh",
        json!({"model": s, "colour": "distance"}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    fails(
        &app,
        "/api/surface/mesh",
        json!({"model": s, "samples": 1}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    fails(
        &app,
        "/api/surface/mesh",
        json!({"model": s, "colour": "pink"}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    let e = fails(
        &app,
        "/api/surface/heights",
        json!({"z": [[1, 2], [3]]}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    assert_eq!(e["path"], "z[1]");
    let e = fails(
        &app,
        "/api/surface/heights",
        json!({"z": [[1, 2], [3, 4]], "x": [0, 1, 2]}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    assert_eq!(e["path"], "x");
    fails(
        &app,
        "/api/surface/heights",
        json!({"z": [[1, 2], [3, 4]], "x": [1, 0]}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
    fails(
        &app,
        "/api/surface/heights",
        json!({"z": [[1, 2], [3, 4]], "end": "periodic"}),
        StatusCode::BAD_REQUEST,
    )
    .await;
    fails(
        &app,
        "/api/surface/heights",
        json!({"z": []}),
        StatusCode::UNPROCESSABLE_ENTITY,
    )
    .await;
}
