//! Shared helpers of the API tests: requests through the router (tower's `oneshot`) and
//! independent references (de Casteljau, de Boor, exact rationals) written here, not taken
//! from the library.
#![allow(dead_code)]

use axum::body::Body;
use axum::http::{Request, StatusCode};
use axum::Router;
use serde_json::Value;
use tower::ServiceExt;

/// An answer: status, Content-Type and body bytes.
pub struct Answer {
    pub status: StatusCode,
    pub content_type: String,
    pub body: Vec<u8>,
}

impl Answer {
    /// The body as JSON (panics when it is not: every API answer but exports is JSON).
    pub fn json(&self) -> Value {
        serde_json::from_slice(&self.body).unwrap_or_else(|e| {
            panic!(
                "not JSON ({e}), status {}: {}",
                self.status,
                String::from_utf8_lossy(&self.body)
            )
        })
    }
}

/// Sends a request with a local Host header.
pub async fn send(app: &Router, method: &str, path: &str, body: Option<&Value>) -> Answer {
    let req = Request::builder()
        .method(method)
        .uri(path)
        .header("host", "127.0.0.1:8765")
        .header("content-type", "application/json");
    let req = match body {
        Some(v) => req.body(Body::from(v.to_string())).unwrap(),
        None => req.body(Body::empty()).unwrap(),
    };
    raw(app, req).await
}

/// Sends any request.
pub async fn raw(app: &Router, req: Request<Body>) -> Answer {
    let res = app.clone().oneshot(req).await.unwrap();
    let status = res.status();
    let content_type = res
        .headers()
        .get("content-type")
        .map(|v| v.to_str().unwrap().to_string())
        .unwrap_or_default();
    let body = axum::body::to_bytes(res.into_body(), usize::MAX)
        .await
        .unwrap()
        .to_vec();
    Answer {
        status,
        content_type,
        body,
    }
}

/// POST `body` to `path`, expecting 200, and the JSON answer.
pub async fn ok(app: &Router, path: &str, body: Value) -> Value {
    let a = send(app, "POST", path, Some(&body)).await;
    assert_eq!(
        a.status,
        StatusCode::OK,
        "{path}: {}",
        String::from_utf8_lossy(&a.body)
    );
    a.json()
}

/// A JSON array of arrays of numbers as rows.
pub fn points(v: &Value) -> Vec<Vec<f64>> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|p| {
            p.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// A JSON array of numbers.
pub fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// De Casteljau's algorithm (the reference evaluation of a Bézier curve).
pub fn de_casteljau(pts: &[Vec<f64>], t: f64) -> Vec<f64> {
    let mut work = pts.to_vec();
    for r in 1..pts.len() {
        for i in 0..pts.len() - r {
            for c in 0..work[i].len() {
                work[i][c] = (1.0 - t) * work[i][c] + t * work[i + 1][c];
            }
        }
    }
    work[0].clone()
}

/// De Boor's algorithm (the reference evaluation of a B-spline curve), t in the domain.
pub fn de_boor(degree: usize, knots: &[f64], control: &[Vec<f64>], t: f64) -> Vec<f64> {
    let n = control.len();
    // The span k with knots[k] <= t < knots[k+1], clamped to the last non-empty one.
    let mut k = degree;
    while k + 1 < n && knots[k + 1] <= t {
        k += 1;
    }
    let mut d: Vec<Vec<f64>> = (0..=degree)
        .map(|j| control[j + k - degree].clone())
        .collect();
    for r in 1..=degree {
        for j in (r..=degree).rev() {
            let i = j + k - degree;
            let denom = knots[i + degree + 1 - r] - knots[i];
            let alpha = if denom == 0.0 {
                0.0
            } else {
                (t - knots[i]) / denom
            };
            for c in 0..d[j].len() {
                d[j][c] = (1.0 - alpha) * d[j - 1][c] + alpha * d[j][c];
            }
        }
    }
    d[degree].clone()
}

/// Euclidean distance.
pub fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}
