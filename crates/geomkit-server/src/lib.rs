//! # geomkit-server
//!
//! `geomkit serve`: the editor in the browser. A local HTTP server (axum on tokio) with
//!
//! - a JSON API over the model crate and the library ([`api`], documented for scripts in
//!   the repository's `docs/serve-api.md`): describe and sample any model file, change the
//!   degree of Bézier curves (exactly, with the library's refusal, or by the best
//!   approximation with its error band), interpolate B-splines with curvature combs, print
//!   single formulas in the 11 syntaxes, fit point-calculus models, export SVG / PNG / STL /
//!   GLB / OBJ / formula, open and save model files in one folder, mesh bodies and
//!   composite surfaces with the seams of their formula classified by continuity;
//! - the editor page, every asset embedded in the binary ([`assets`]): no network at run
//!   time.
//!
//! It binds 127.0.0.1 by default and answers only requests whose `Host` and `Origin` are
//! local ([`guard`]); bodies are limited to [`Limits::body_bytes`] and models to
//! [`Limits`]; every error is a JSON body `{"error": "..."}` with a 4xx status, and a bug is
//! a 500 JSON answer, never a dropped connection. CPU work runs on tokio's blocking pool, so
//! requests are served concurrently.
//!
//! ```no_run
//! use geomkit_server::{Config, router};
//! # async fn f() -> std::io::Result<()> {
//! let app = router(Config::default());
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await?;
//! axum::serve(listener, app).await
//! # }
//! ```
//!
//! Errors of a request are described in `docs/serve-api.md`; [`run`] fails (with a message)
//! when the address cannot be bound or the folder does not exist.

pub mod api;
pub mod assets;
pub mod error;
pub mod guard;

use axum::extract::DefaultBodyLimit;
use axum::Router;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

/// The server's limits: requests beyond them are refused with 413 and a JSON error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct Limits {
    /// Largest request body in bytes (default 32 MiB).
    pub body_bytes: usize,
    /// Most points of a model or request: control points, reference points, net points,
    /// point-calculus cells (default 250 000).
    pub points: usize,
    /// Highest Bézier degree a request may hold or ask for (default 400).
    pub bezier_degree: usize,
    /// Most samples of a curve (default 200 000) and per direction of a surface (its square
    /// root, 447).
    pub samples: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            body_bytes: 32 << 20,
            points: 250_000,
            bezier_degree: 400,
            samples: 200_000,
        }
    }
}

/// What the server serves.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct Config {
    /// The folder whose model files the page may open and save (`--dir`); `None`: no file
    /// access at all.
    pub dir: Option<PathBuf>,
    /// The limits.
    pub limits: Limits,
}

impl Config {
    /// Sets the folder of model files.
    pub fn with_dir(mut self, dir: Option<PathBuf>) -> Self {
        self.dir = dir;
        self
    }

    /// Sets the limits.
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = limits;
        self
    }
}

/// The shared state of the handlers.
#[derive(Debug, Clone)]
pub struct AppState {
    /// The configuration.
    pub config: Arc<Config>,
}

/// The whole application: the API, the page, and the layers of [`guard`].
pub fn router(config: Config) -> Router {
    let body_limit = config.limits.body_bytes;
    let state = AppState {
        config: Arc::new(config),
    };
    Router::new()
        .merge(api::routes())
        .merge(assets::routes())
        .with_state(state)
        .layer(DefaultBodyLimit::max(body_limit))
        .layer(axum::middleware::from_fn(guard::json_errors))
        .layer(axum::middleware::from_fn(guard::local_only))
        .layer(tower_http::catch_panic::CatchPanicLayer::custom(
            guard::panic_response,
        ))
}

/// Options of [`run`] (`geomkit serve`).
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct ServeOptions {
    /// Address to bind (default 127.0.0.1:8765; port 0 picks a free port).
    pub addr: SocketAddr,
    /// Open the page in the default browser (`xdg-open`, `open` or `start`).
    pub open: bool,
    /// The server's configuration.
    pub config: Config,
}

impl Default for ServeOptions {
    fn default() -> Self {
        ServeOptions {
            addr: SocketAddr::from(([127, 0, 0, 1], 8765)),
            open: false,
            config: Config::default(),
        }
    }
}

/// Runs the server until the process is stopped. Prints `geomkit serve: http://ADDR/` on
/// stdout once it listens (scripts read the port from that line when they asked for 0).
///
/// Errors: the folder is missing or not a folder, the address cannot be bound.
pub fn run(options: ServeOptions) -> anyhow::Result<()> {
    use anyhow::Context;
    if let Some(dir) = &options.config.dir {
        if !dir.is_dir() {
            anyhow::bail!("--dir {}: not a folder", dir.display());
        }
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(options.addr)
            .await
            .with_context(|| format!("cannot listen on {}", options.addr))?;
        let addr = listener.local_addr()?;
        let url = format!("http://{addr}/");
        println!("geomkit serve: {url}");
        if let Some(dir) = &options.config.dir {
            println!("model files in {}", dir.display());
        }
        use std::io::Write;
        let _ = std::io::stdout().flush();
        if options.open {
            open_browser(&url);
        }
        axum::serve(listener, router(options.config))
            .await
            .context("the server stopped")
    })
}

/// Opens `url` in the default browser; a failure is only reported.
fn open_browser(url: &str) {
    let program = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(windows) {
        "explorer"
    } else {
        "xdg-open"
    };
    if let Err(e) = std::process::Command::new(program).arg(url).spawn() {
        eprintln!("geomkit serve: cannot open a browser ({program}: {e}); open {url} yourself");
    }
}
