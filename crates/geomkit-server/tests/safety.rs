//! The server as a local server: requests from elsewhere refused (DNS rebinding, cross-site
//! pages), limits on bodies and models answered with 4xx JSON, no file outside the named
//! folder, atomic saves, every error JSON.

mod common;

use axum::body::Body;
use axum::http::{Request, StatusCode};
use common::*;
use geomkit_server::{router, Config, Limits};
use serde_json::json;

fn app() -> axum::Router {
    router(Config::default())
}

fn get(host: Option<&str>, origin: Option<&str>, path: &str) -> Request<Body> {
    let mut r = Request::builder().uri(path);
    if let Some(h) = host {
        r = r.header("host", h);
    }
    if let Some(o) = origin {
        r = r.header("origin", o);
    }
    r.body(Body::empty()).unwrap()
}

#[tokio::test]
async fn foreign_hosts_and_origins_are_refused() {
    let app = app();
    for host in [
        "evil.example",
        "127.0.0.1.nip.io:8765",
        "10.0.0.2:8765",
        "0.0.0.0",
    ] {
        let a = raw(&app, get(Some(host), None, "/api/version")).await;
        assert_eq!(a.status, StatusCode::FORBIDDEN, "{host}");
        assert!(a.json()["error"]
            .as_str()
            .unwrap()
            .contains("DNS rebinding"));
    }
    // The page itself too.
    assert_eq!(
        raw(&app, get(Some("attacker.test"), None, "/"))
            .await
            .status,
        403
    );
    // No Host at all.
    assert_eq!(raw(&app, get(None, None, "/api/version")).await.status, 403);
    for origin in [
        "http://evil.example",
        "null",
        "http://localhost.evil.example:8765",
    ] {
        let a = raw(
            &app,
            get(Some("localhost:8765"), Some(origin), "/api/version"),
        )
        .await;
        assert_eq!(a.status, StatusCode::FORBIDDEN, "{origin}");
        a.json();
    }
    for (host, origin) in [
        ("localhost:8765", Some("http://localhost:8765")),
        ("127.0.0.1:1", None),
        ("[::1]:80", Some("http://[::1]:80")),
    ] {
        let a = raw(&app, get(Some(host), origin, "/api/version")).await;
        assert_eq!(a.status, 200, "{host}");
    }
}

#[tokio::test]
async fn the_page_and_its_assets_only() {
    let app = app();
    let page = send(&app, "GET", "/", None).await;
    assert_eq!(page.status, 200);
    assert!(page.content_type.starts_with("text/html"));
    let html = String::from_utf8(page.body).unwrap();
    // Every asset the page names is served, from the binary.
    for name in ["app.js", "style.css", "icon.svg"] {
        assert!(html.contains(&format!("/assets/{name}")), "{name}");
        let a = send(&app, "GET", &format!("/assets/{name}"), None).await;
        assert_eq!(a.status, 200, "{name}");
    }
    // No CDN, no remote URL in any asset: it works offline.
    for a in geomkit_server::assets::ASSETS
        .iter()
        .map(|a| a.body)
        .chain([geomkit_server::assets::INDEX])
    {
        for remote in ["https://", "http://", "//cdn"] {
            let hits: Vec<&str> = a
                .match_indices(remote)
                .map(|(i, _)| &a[i..(i + 40).min(a.len())])
                .collect();
            assert!(
                hits.iter()
                    .all(|h| h.starts_with("http://www.w3.org/2000/svg")),
                "{hits:?}"
            );
        }
    }
    for path in [
        "/assets/../Cargo.toml",
        "/assets/..%2F..%2FCargo.toml",
        "/assets/%2Fetc%2Fpasswd",
        "/Cargo.toml",
        "/assets/",
        "/etc/passwd",
    ] {
        let a = send(&app, "GET", path, None).await;
        assert_eq!(a.status, 404, "{path}");
        a.json();
    }
}

#[tokio::test]
async fn errors_are_json_with_4xx() {
    let app = app();
    let cases = [
        ("DELETE", "/api/samples", None, 405),
        ("GET", "/api/samples", None, 405),
        ("GET", "/api/nothing", None, 404),
        ("POST", "/api/samples", Some("{"), 400),
        ("POST", "/api/samples", Some("[]"), 400),
        ("POST", "/api/samples", Some(""), 400),
        ("POST", "/api/samples", Some(r#"{"model": 3}"#), 400),
        (
            "POST",
            "/api/samples",
            Some(r#"{"model": {"type": "teapot"}}"#),
            400,
        ),
        (
            "POST",
            "/api/samples",
            Some(r#"{"model": {"type": "bezier_curve", "points": [[0, 0], [1, 1e999]]}}"#),
            400,
        ),
        (
            "POST",
            "/api/samples",
            Some(r#"{"model": {"type": "bezier_curve", "points": [[0, 0]]}, "extra": 1}"#),
            400,
        ),
        (
            "POST",
            "/api/samples",
            Some(
                r#"{"model": {"type": "bezier_curve", "points": [[0, 0], [1, 2]]}, "samples": 1}"#,
            ),
            400,
        ),
        (
            "POST",
            "/api/bspline/interpolate",
            Some(r#"{"points": [[0, 0], [0, 0], [1, 1]]}"#),
            422,
        ),
        (
            "POST",
            "/api/bezier/elevate",
            Some(
                r#"{"model": {"type": "bezier_curve", "points": [[0, 0], [1, 2]]}, "to": [3, 3]}"#,
            ),
            400,
        ),
    ];
    for (method, path, body, status) in cases {
        let req = Request::builder()
            .method(method)
            .uri(path)
            .header("host", "localhost")
            .body(Body::from(body.unwrap_or("").to_string()))
            .unwrap();
        let a = raw(&app, req).await;
        assert_eq!(
            a.status.as_u16(),
            status,
            "{method} {path} {body:?}: {}",
            String::from_utf8_lossy(&a.body)
        );
        assert!(a.content_type.starts_with("application/json"), "{path}");
        assert!(!a.json()["error"].as_str().unwrap().is_empty());
    }
    // The JSON path of the value at fault.
    let a = send(
        &app,
        "POST",
        "/api/samples",
        Some(&json!({"model": {"type": "bezier_curve", "points": [[0, 0], [1, "2"]]}})),
    )
    .await;
    assert_eq!(a.json()["path"], "model.points[1][1]");
}

#[tokio::test]
async fn limits_answer_413() {
    let mut limits = Limits::default();
    limits.body_bytes = 4096;
    limits.points = 50;
    limits.bezier_degree = 20;
    let app = router(Config::default().with_limits(limits));
    let big: Vec<[f64; 2]> = (0..400).map(|i| [i as f64, 0.5]).collect();
    let a = send(
        &app,
        "POST",
        "/api/bspline/interpolate",
        Some(&json!({"points": big})),
    )
    .await;
    assert_eq!(a.status, 413);
    a.json();
    let many: Vec<[f64; 2]> = (0..60).map(|i| [i as f64, 0.5]).collect();
    let a = send(
        &app,
        "POST",
        "/api/bspline/interpolate",
        Some(&json!({"points": many})),
    )
    .await;
    assert_eq!(a.status, 413);
    assert!(a.json()["error"].as_str().unwrap().contains("at most 50"));
    let a = send(&app, "POST", "/api/bezier/elevate", Some(&json!({"model": {"type": "bezier_curve", "points": [[0, 0], [1, 1]]}, "to": 1_000_000_000u64}))).await;
    assert_eq!(a.status, 413);
    let a = send(&app, "POST", "/api/samples", Some(&json!({"model": {"type": "bezier_curve", "points": [[0, 0], [1, 1]]}, "samples": 10_000_000}))).await;
    assert_eq!(a.status, 400);
}

#[tokio::test]
async fn files_only_in_the_named_folder() {
    let dir = tempfile::tempdir().unwrap();
    let app = router(Config::default().with_dir(Some(dir.path().to_path_buf())));
    let model = json!({"type": "bezier_curve", "points": [[0, 0], [1, 2], [3, 1]]});
    let a = send(
        &app,
        "PUT",
        "/api/files/curve.json",
        Some(&json!({"model": model})),
    )
    .await;
    assert_eq!(a.status, 200, "{}", String::from_utf8_lossy(&a.body));
    // Written in the layout of the tools, read back by the model crate.
    let text = std::fs::read_to_string(dir.path().join("curve.json")).unwrap();
    assert_eq!(
        geomkit_model::parse(&text).unwrap().describe(),
        "Bézier curve of degree 2 in R^2 (3 control points)"
    );
    let list = send(&app, "GET", "/api/files", None).await.json();
    assert_eq!(list["files"][0]["name"], "curve.json");
    let opened = send(&app, "GET", "/api/files/curve.json", None)
        .await
        .json();
    assert_eq!(opened["model"]["points"][2], json!([3.0, 1.0]));
    // A model that does not check is not written at all.
    let bad = json!({"model": {"type": "bspline_curve", "degree": 3, "knots": [1, 0], "control_points": [[0, 0]]}});
    let a = send(&app, "PUT", "/api/files/bad.json", Some(&bad)).await;
    assert!(a.status.is_client_error());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    // Nothing outside the folder, whatever the name.
    let outside = dir.path().parent().unwrap().join("outside.json");
    for name in [
        "..%2Foutside.json",
        "%2Ftmp%2Foutside.json",
        ".hidden.json",
        "a%2Fb.json",
        "notes.txt",
        "..json",
    ] {
        let a = send(
            &app,
            "PUT",
            &format!("/api/files/{name}"),
            Some(&json!({"model": model})),
        )
        .await;
        assert!(a.status.is_client_error(), "{name}: {}", a.status);
        let a = send(&app, "GET", &format!("/api/files/{name}"), None).await;
        assert!(a.status.is_client_error(), "{name}");
    }
    assert!(!outside.exists());
    // Links are not followed.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/etc/hostname", dir.path().join("link.json")).unwrap();
        let a = send(&app, "GET", "/api/files/link.json", None).await;
        assert_eq!(a.status, 404);
    }
    // Without --dir: no file access.
    let a = send(&router(Config::default()), "GET", "/api/files", None).await;
    assert_eq!(a.status, 403);
}
