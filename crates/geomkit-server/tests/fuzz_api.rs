//! Fuzzing of the JSON API: random and mutated JSON bodies to every endpoint. Property: the
//! answer is never 5xx and always JSON (or, for a successful export, the file).

mod common;
#[path = "../../geomkit/tests/common/fuzz.rs"]
mod fuzz;

use common::*;
use geomkit_server::{router, Config};
use proptest::prelude::*;
use serde_json::{json, Value};

const ENDPOINTS: &[&str] = &[
    "/api/describe",
    "/api/samples",
    "/api/bezier/degree",
    "/api/bezier/elevate",
    "/api/bezier/reduce",
    "/api/bezier/approximate",
    "/api/bezier/edit",
    "/api/bspline/interpolate",
    "/api/formula",
    "/api/pointcalc/fit",
    "/api/pointcalc/shares",
    "/api/pointcalc/optimum",
    "/api/export",
    "/api/pointcalc/grid",
    "/api/surface/mesh",
    "/api/surface/edit",
    "/api/surface/approximate",
    "/api/surface/heights",
    "/api/body/view",
];

/// Valid requests (endpoint, body), the seeds of the mutations.
fn seeds() -> Vec<(&'static str, Value)> {
    let curve = json!({"type": "bezier_curve", "points": [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]]});
    let pc = json!({"type": "pointcalc-model", "factors": [{"name": "a", "nodes": [0, 1, 2]}], "response": ["y"], "values": [1, 3, 2]});
    let surface =
        json!({"type": "bezier_surface", "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]});
    vec![
        ("/api/samples", json!({"model": curve, "samples": 20})),
        ("/api/bezier/reduce", json!({"model": curve, "to": 3})),
        (
            "/api/bezier/approximate",
            json!({"model": curve, "to": 2, "norm": "chebyshev", "continuity": [1, null], "samples": 10}),
        ),
        (
            "/api/bezier/edit",
            json!({"model": curve, "insert": {"index": 1, "point": [1, 2]}}),
        ),
        ("/api/bezier/edit", json!({"model": curve, "remove": 2})),
        ("/api/export", json!({"model": curve, "format": "svg"})),
        (
            "/api/bspline/interpolate",
            json!({"points": [[0, 0], [1, 2], [3, 1], [4, 4]], "end": "natural", "parametrization": "centripetal", "comb": {"per_span": 2}}),
        ),
        (
            "/api/bspline/interpolate",
            json!({"points": [[0, 0], [1, 2], [3, 1]], "closed": true}),
        ),
        (
            "/api/formula",
            json!({"body": {"kind": "prism", "ngon": 5}, "format": "latex"}),
        ),
        (
            "/api/pointcalc/fit",
            json!({"factors": [{"name": "a", "nodes": [0, 1]}, {"name": "b", "nodes": [0, 1]}], "values": [1, 2, 3, 4]}),
        ),
        ("/api/pointcalc/shares", json!({"model": pc, "at": [0.5]})),
        (
            "/api/pointcalc/optimum",
            json!({"model": pc, "goal": "min"}),
        ),
        (
            "/api/export",
            json!({"model": surface, "format": "stl", "samples": 3}),
        ),
        (
            "/api/pointcalc/grid",
            json!({"model": pc, "at": [0.5], "free": [0], "samples": 7, "contours": 3}),
        ),
        (
            "/api/bspline/interpolate",
            json!({"points": [[0, 0], [1, 2], [3, 1], [4, 4], [6, 0]], "samples_per_span": 2, "window": {"around": 2, "points": 1}, "comb": {"per_span": 1, "scale": 0.5}}),
        ),
        ("/api/surface/mesh", json!({"model": surface, "samples": 4})),
        (
            "/api/surface/edit",
            json!({"model": surface, "insert": {"direction": "u", "index": 1, "points": [[0, 0, 1], [0, 1, 1]]}}),
        ),
        (
            "/api/surface/approximate",
            json!({"model": surface, "to": [0, 1], "samples": 3}),
        ),
        (
            "/api/surface/heights",
            json!({"z": [[0, 1, 0], [1, 2, 1], [0, 1, 0]], "samples": 3, "colour": "mean"}),
        ),
        (
            "/api/body/view",
            json!({"body": {"kind": "pyramid", "ngon": 5}, "seam_samples": 3, "tolerance": 0.1}),
        ),
    ]
}

fn leaf() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|x| json!(x)),
        prop_oneof![
            Just(0.0),
            Just(-0.0),
            Just(1e308),
            Just(-1e308),
            Just(5e-324),
            Just(1e-300),
            any::<f64>()
        ]
        .prop_filter_map("finite", |x: f64| serde_json::Number::from_f64(x)
            .map(Value::Number)),
        prop_oneof![
            Just(0u64),
            Just(1),
            Just(2),
            Just(3),
            Just(400),
            Just(401),
            Just(100_000),
            Just(u64::MAX)
        ]
        .prop_map(|x| json!(x)),
        "[a-z_]{0,12}".prop_map(Value::String),
        prop_oneof![
            Just("bezier_curve"),
            Just("bspline_curve"),
            Just("bezier_surface"),
            Just("pointcalc-model"),
            Just("ruled"),
            Just("composite_surface")
        ]
        .prop_map(|s| json!(s)),
    ]
}

fn value() -> impl Strategy<Value = Value> {
    leaf().prop_recursive(4, 48, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::vec(
                (
                    prop_oneof![
                        Just("model".to_string()),
                        Just("points".to_string()),
                        Just("to".to_string()),
                        Just("type".to_string()),
                        Just("samples".to_string()),
                        "[a-z]{1,8}"
                    ],
                    inner
                ),
                0..5
            )
            .prop_map(|kv| Value::Object(kv.into_iter().collect())),
        ]
    })
}

/// Replaces the node at a pseudo-random position of `v` (chosen by `pick`) with `by`.
fn mutate(v: &mut Value, pick: &mut u64, by: &Value) -> bool {
    *pick = pick
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    if *pick >> 61 == 0 {
        *v = by.clone();
        return true;
    }
    match v {
        Value::Array(a) if !a.is_empty() => {
            let i = (*pick >> 33) as usize % a.len();
            mutate(&mut a[i], pick, by)
        }
        Value::Object(o) if !o.is_empty() => {
            let i = (*pick >> 33) as usize % o.len();
            let key = o.keys().nth(i).unwrap().clone();
            mutate(o.get_mut(&key).unwrap(), pick, by)
        }
        _ => {
            *v = by.clone();
            true
        }
    }
}

fn check(path: &str, body: &[u8]) -> Result<(), TestCaseError> {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let app = router(Config::default());
    let req = axum::http::Request::builder()
        .method("POST")
        .uri(path)
        .header("host", "localhost")
        .body(axum::body::Body::from(body.to_vec()))
        .unwrap();
    let a = runtime.block_on(raw(&app, req));
    prop_assert!(
        a.status.as_u16() < 500,
        "{path} {}: {}",
        a.status,
        String::from_utf8_lossy(&a.body)
    );
    if a.status.is_success() && path == "/api/export" {
        return Ok(());
    }
    let v: Value = serde_json::from_slice(&a.body)
        .map_err(|e| TestCaseError::fail(format!("{path}: not JSON: {e}")))?;
    if !a.status.is_success() {
        prop_assert!(v["error"]
            .as_str()
            .is_some_and(|s| !s.is_empty() && !s.contains('\n')));
    }
    Ok(())
}

proptest! {
    #![proptest_config(fuzz::config(48))]

    #[test]
    fn fuzz_api_random_bodies(which in 0..ENDPOINTS.len(), body in value()) {
        check(ENDPOINTS[which], body.to_string().as_bytes())?;
    }

    #[test]
    fn fuzz_api_mutated_bodies(which in 0..ENDPOINTS.len(), seed in 0..64usize, pick in any::<u64>(), by in value(), cut in any::<u16>()) {
        let seeds = seeds();
        let mut body = seeds[seed % seeds.len()].1.clone();
        let mut p = pick;
        mutate(&mut body, &mut p, &by);
        let text = body.to_string();
        check(ENDPOINTS[which], text.as_bytes())?;
        // Cut anywhere: never 5xx either.
        let at = cut as usize % (text.len() + 1);
        check(ENDPOINTS[which], &text.as_bytes()[..at])?;
    }
}

/// Every seed is a valid request of its endpoint (so that mutations start from deep inside
/// the handlers, not from an early refusal).
#[test]
fn seeds_answer_200() {
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    let app = router(Config::default());
    for (path, seed) in seeds() {
        let a = runtime.block_on(send(&app, "POST", path, Some(&seed)));
        let text = String::from_utf8_lossy(&a.body);
        assert_eq!(a.status, 200, "{path} {seed}: {text}");
    }
}
