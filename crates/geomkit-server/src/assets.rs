//! The editor page: every file embedded in the binary with `include_str!`, served from
//! memory. Nothing else on disk is ever served from these routes (a name not in [`ASSETS`]
//! is 404, whatever it contains: `..`, `%2e%2e`, absolute paths).

use crate::AppState;
use axum::extract::Path;
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;

/// One embedded file: its name under `/assets/`, MIME type and contents.
pub struct Asset {
    /// The name under `/assets/`.
    pub name: &'static str,
    /// Content-Type.
    pub mime: &'static str,
    /// The file.
    pub body: &'static str,
}

/// The page's files (plain JavaScript modules, no build step).
pub const ASSETS: &[Asset] = &[
    Asset {
        name: "app.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/app.js"),
    },
    Asset {
        name: "api.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/api.js"),
    },
    Asset {
        name: "view.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/view.js"),
    },
    Asset {
        name: "pointcalc.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/pointcalc.js"),
    },
    Asset {
        name: "view3d.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/view3d.js"),
    },
    Asset {
        name: "body3d.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/body3d.js"),
    },
    Asset {
        name: "surface.js",
        mime: "text/javascript; charset=utf-8",
        body: include_str!("../assets/surface.js"),
    },
    Asset {
        name: "style.css",
        mime: "text/css; charset=utf-8",
        body: include_str!("../assets/style.css"),
    },
    Asset {
        name: "icon.svg",
        mime: "image/svg+xml",
        body: include_str!("../assets/icon.svg"),
    },
];

/// The page itself.
pub const INDEX: &str = include_str!("../assets/index.html");

/// `/` and `/assets/{name}`.
pub fn routes() -> Router<AppState> {
    Router::new()
        .route("/", get(index))
        .route("/assets/{name}", get(asset))
}

/// Headers every page answer carries: no framing by other sites, no sniffing, and a
/// content security policy that allows only the page's own files.
fn page_headers() -> [(header::HeaderName, &'static str); 3] {
    [
        (header::X_FRAME_OPTIONS, "DENY"),
        (header::X_CONTENT_TYPE_OPTIONS, "nosniff"),
        (
            header::CONTENT_SECURITY_POLICY,
            "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; \
             script-src 'self'; connect-src 'self'; frame-ancestors 'none'",
        ),
    ]
}

async fn index() -> Response {
    (
        page_headers(),
        [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
        INDEX,
    )
        .into_response()
}

async fn asset(Path(name): Path<String>) -> Response {
    match ASSETS.iter().find(|a| a.name == name) {
        Some(a) => (
            page_headers(),
            [
                (header::CONTENT_TYPE, a.mime),
                (header::CACHE_CONTROL, "no-cache"),
            ],
            a.body,
        )
            .into_response(),
        None => {
            crate::error::ApiError::new(StatusCode::NOT_FOUND, format!("no asset named \"{name}\""))
                .into_response()
        }
    }
}
