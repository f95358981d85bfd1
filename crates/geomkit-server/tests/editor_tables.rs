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
