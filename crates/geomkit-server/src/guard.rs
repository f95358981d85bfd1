//! The server's protections, as layers around every route:
//!
//! - [`local_only`]: a request whose `Host` is not a loopback name or address, or whose
//!   `Origin` (when the browser sends one) is not a page of a loopback host, is refused with
//!   403 — a web page elsewhere cannot reach the editor through DNS rebinding or a
//!   cross-site request.
//! - [`json_errors`]: every error answer is JSON, also those made by the framework itself
//!   (405 Method Not Allowed, 413 for a body over the limit, 404 for an unknown route).
//! - [`panic_response`]: the last resort for a bug, 500 JSON instead of a dropped connection.

use crate::error::json_error;
use axum::body::Body;
use axum::extract::Request;
use axum::http::{header, HeaderMap, StatusCode};
use axum::middleware::Next;
use axum::response::Response;
use std::any::Any;

/// Whether `host` (a Host header or the host of an Origin, with or without port) names this
/// machine: `localhost`, `*.localhost`, `127.x.x.x` or `[::1]`.
pub fn is_local_host(host: &str) -> bool {
    let host = host.trim();
    // Strip the port: "[::1]:8080", "127.0.0.1:80", "localhost".
    let name = if let Some(rest) = host.strip_prefix('[') {
        match rest.split_once(']') {
            Some((inside, tail)) if tail.is_empty() || is_port(tail) => inside,
            _ => return false,
        }
    } else {
        match host.rsplit_once(':') {
            Some((name, port)) if is_port(&format!(":{port}")) => name,
            Some(_) => return false,
            None => host,
        }
    };
    let name = name.to_ascii_lowercase();
    if name == "localhost" || name.ends_with(".localhost") || name == "::1" {
        return true;
    }
    match name.parse::<std::net::Ipv4Addr>() {
        Ok(ip) => ip.is_loopback(),
        Err(_) => false,
    }
}

fn is_port(tail: &str) -> bool {
    tail.strip_prefix(':')
        .is_some_and(|p| !p.is_empty() && p.len() <= 5 && p.bytes().all(|b| b.is_ascii_digit()))
}

/// Whether an `Origin` header names a page served from this machine (`http://localhost:8080`);
/// `null` (a sandboxed or file page) is refused.
pub fn is_local_origin(origin: &str) -> bool {
    let Some(rest) = origin
        .strip_prefix("http://")
        .or_else(|| origin.strip_prefix("https://"))
    else {
        return false;
    };
    !rest.contains('/') && is_local_host(rest)
}

/// Why a request is refused, or `None` when its Host and Origin are local.
pub fn refusal(headers: &HeaderMap) -> Option<String> {
    let host = match headers.get(header::HOST).map(|h| h.to_str()) {
        Some(Ok(h)) => h,
        Some(Err(_)) => return Some("the Host header is not text".into()),
        None => return Some("the request has no Host header".into()),
    };
    if !is_local_host(host) {
        return Some(format!(
            "Host \"{host}\" is not this machine: the editor answers only requests for \
             localhost or 127.0.0.1 (protection against DNS rebinding)"
        ));
    }
    if let Some(origin) = headers.get(header::ORIGIN) {
        let origin = origin.to_str().unwrap_or("(not text)");
        if !is_local_origin(origin) {
            return Some(format!(
                "Origin \"{origin}\" is not a page of this machine: the editor answers only \
                 its own pages"
            ));
        }
    }
    None
}

/// The layer of [`refusal`]: 403 JSON for a request from elsewhere.
pub async fn local_only(req: Request, next: Next) -> Response {
    match refusal(req.headers()) {
        Some(reason) => json_error(StatusCode::FORBIDDEN, &reason),
        None => next.run(req).await,
    }
}

/// The layer that makes every error answer JSON: an answer of status >= 400 whose body is
/// not JSON is replaced by `{"error": ...}` with the framework's text (or the status name).
pub async fn json_errors(req: Request, next: Next) -> Response {
    let path = req.uri().path().to_string();
    let response = next.run(req).await;
    let status = response.status();
    let is_json = response
        .headers()
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.starts_with("application/json"));
    if status.as_u16() < 400 || is_json {
        return response;
    }
    let body = axum::body::to_bytes(response.into_body(), 64 * 1024)
        .await
        .unwrap_or_default();
    let text = String::from_utf8_lossy(&body).trim().to_string();
    let message = match status {
        StatusCode::NOT_FOUND => {
            format!("no such page or endpoint: {path} (see docs/serve-api.md)")
        }
        StatusCode::METHOD_NOT_ALLOWED => {
            format!("{path} does not take this method (see docs/serve-api.md)")
        }
        _ if !text.is_empty() => text,
        _ => status
            .canonical_reason()
            .unwrap_or("request failed")
            .to_string(),
    };
    json_error(status, &message)
}

/// The answer to a panic caught by `CatchPanicLayer`: 500 JSON.
pub fn panic_response(_err: Box<dyn Any + Send + 'static>) -> Response<Body> {
    json_error(
        StatusCode::INTERNAL_SERVER_ERROR,
        "internal error: the server failed on this request; please report it",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts() {
        for h in [
            "localhost",
            "localhost:8080",
            "127.0.0.1",
            "127.0.0.1:1",
            "127.1.2.3:65535",
            "[::1]",
            "[::1]:9",
            "LOCALHOST:3",
            "app.localhost:80",
        ] {
            assert!(is_local_host(h), "{h}");
        }
        for h in [
            "",
            "example.com",
            "localhost.example.com",
            "127.0.0.1.nip.io",
            "10.0.0.1:80",
            "0.0.0.0:80",
            "[::2]:80",
            "localhost:http",
            "localhost:123456",
            "[::1]x",
            "evil.com:80",
        ] {
            assert!(!is_local_host(h), "{h}");
        }
        assert!(is_local_origin("http://localhost:8080"));
        assert!(is_local_origin("http://127.0.0.1:5"));
        assert!(!is_local_origin("null"));
        assert!(!is_local_origin("http://evil.com"));
        assert!(!is_local_origin("http://localhost:8080/path"));
        assert!(!is_local_origin("file://"));
    }
}
