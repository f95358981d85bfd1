//! Errors as JSON: every failure of a request is a 4xx (or, for a bug, 500) response with the
//! body `{"error": "one line"}` and, where known, the JSON path of the value at fault
//! (`"path": "model.points[1][0]"`) and details of a refusal (the real degree of a curve that
//! cannot be reduced exactly).
//!
//! [`ApiJson`] reads a request body as JSON with the same kind of messages (the path of the
//! field at fault), [`blocking`] runs CPU work off the async workers.

use axum::extract::{FromRequest, Request};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::de::DeserializeOwned;
use serde_json::{json, Map, Value};

/// An error answer: a status, a one-line message and optional extra fields.
#[derive(Debug)]
pub struct ApiError {
    /// The HTTP status (4xx for the request's fault, 500 for a bug).
    pub status: StatusCode,
    /// One line saying what is wrong and where.
    pub message: String,
    /// Extra fields of the JSON body (`path`, `real_degree`, ...).
    pub extra: Map<String, Value>,
}

/// A handler's result.
pub type ApiResult<T> = Result<T, ApiError>;

impl ApiError {
    /// A 400 Bad Request.
    pub fn bad_request(message: impl Into<String>) -> Self {
        Self::new(StatusCode::BAD_REQUEST, message)
    }

    /// A 422 Unprocessable Entity: well-formed, but the geometry says no (the library's
    /// reason).
    pub fn unprocessable(message: impl Into<String>) -> Self {
        Self::new(StatusCode::UNPROCESSABLE_ENTITY, message)
    }

    /// A 413 Payload Too Large: a model or a request over the server's limits.
    pub fn too_large(message: impl Into<String>) -> Self {
        Self::new(StatusCode::PAYLOAD_TOO_LARGE, message)
    }

    /// A 404 Not Found.
    pub fn not_found(message: impl Into<String>) -> Self {
        Self::new(StatusCode::NOT_FOUND, message)
    }

    /// An error with any status.
    pub fn new(status: StatusCode, message: impl Into<String>) -> Self {
        let message: String = message.into();
        ApiError {
            status,
            message: message.replace(['\n', '\r'], " "),
            extra: Map::new(),
        }
    }

    /// Adds a field to the JSON body.
    pub fn with(mut self, key: &str, value: impl Into<Value>) -> Self {
        self.extra.insert(key.to_string(), value.into());
        self
    }

    /// The library's error: 422 with its message.
    pub fn geometry(context: &str, err: geomkit::Error) -> Self {
        if context.is_empty() {
            Self::unprocessable(err.to_string())
        } else {
            Self::unprocessable(format!("{context}: {err}"))
        }
    }

    /// A model file that did not read, under the request field `field` ("model"): 400 for
    /// JSON that is not a model file, 422 for a model the library refuses; `path` is the
    /// JSON path in the request.
    pub fn model(field: &str, err: geomkit_model::Error) -> Self {
        use geomkit_model::ErrorKind;
        let (status, path, message) = match err.kind() {
            ErrorKind::Schema { path, message, .. } => {
                (StatusCode::BAD_REQUEST, path.clone(), message.clone())
            }
            ErrorKind::Model { path, message, .. } => (
                StatusCode::UNPROCESSABLE_ENTITY,
                path.clone(),
                message.clone(),
            ),
            _ => (StatusCode::BAD_REQUEST, String::new(), err.to_string()),
        };
        let full = join(field, &path);
        let text = if ["is ", "has ", "must "]
            .iter()
            .any(|w| message.starts_with(w))
        {
            format!("{full} {message}")
        } else {
            format!("{full}: {message}")
        };
        Self::new(status, text).with("path", full)
    }
}

/// `a.b` or `a[1]`.
pub(crate) fn join(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (_, true) => a.to_string(),
        _ if b.starts_with('[') => format!("{a}{b}"),
        _ => format!("{a}.{b}"),
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let mut body = Map::new();
        body.insert("error".into(), Value::String(self.message));
        body.extend(self.extra);
        (self.status, Json(Value::Object(body))).into_response()
    }
}

/// A JSON request body, with errors as JSON naming the field at fault:
/// `to: invalid type: string "3", expected usize (line 1, column 30)`.
pub struct ApiJson<T>(pub T);

impl<T, S> FromRequest<S> for ApiJson<T>
where
    T: DeserializeOwned,
    S: Send + Sync,
{
    type Rejection = ApiError;

    async fn from_request(req: Request, state: &S) -> Result<Self, Self::Rejection> {
        let bytes = axum::body::Bytes::from_request(req, state)
            .await
            .map_err(|e| ApiError::new(e.status(), e.body_text()))?;
        parse_body(&bytes).map(ApiJson)
    }
}

/// Parses a request body: the JSON path of the value at fault in the message.
pub fn parse_body<T: DeserializeOwned>(bytes: &[u8]) -> ApiResult<T> {
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let value: T = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.inner();
        let message = if path == "." || inner.is_syntax() || inner.is_eof() {
            format!("request body: {inner}")
        } else {
            format!("{path}: {inner}")
        };
        let err = ApiError::bad_request(message);
        if path == "." || inner.is_syntax() || inner.is_eof() {
            err
        } else {
            err.with("path", path)
        }
    })?;
    de.end()
        .map_err(|e| ApiError::bad_request(format!("request body: {e}")))?;
    Ok(value)
}

/// Runs CPU work on the blocking pool (so that other requests go on), turning a panic into
/// a 500 JSON error instead of a dropped connection.
pub async fn blocking<T, F>(work: F) -> ApiResult<T>
where
    F: FnOnce() -> ApiResult<T> + Send + 'static,
    T: Send + 'static,
{
    match tokio::task::spawn_blocking(work).await {
        Ok(result) => result,
        Err(e) => Err(ApiError::new(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!(
                "internal error: the computation failed ({}); please report it",
                if e.is_panic() { "panic" } else { "cancelled" }
            ),
        )),
    }
}

/// `{"error": message}` with a status, for the layers that answer before a handler.
pub fn json_error(status: StatusCode, message: &str) -> Response {
    (status, Json(json!({ "error": message }))).into_response()
}
