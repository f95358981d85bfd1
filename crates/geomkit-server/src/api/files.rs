//! `/api/files`: the model files of the one folder the user named with `--dir`, and nothing
//! else. A name is one plain file name ending in `.json` (letters, digits, `.`, `-`, `_`,
//! spaces; no path separators, no leading dot); symbolic links are not followed; saving
//! checks the model first and writes atomically (a temporary file in the folder, then a
//! rename), so a failed save never leaves a half-written file.

use super::{read_model, ModelBody};
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::Json;
use serde_json::{json, Value};
use std::io::Write;
use std::path::PathBuf;

/// Largest model file opened (bytes).
const MAX_FILE_BYTES: u64 = 32 << 20;

/// Whether `name` is a plain model file name this API serves.
pub fn valid_name(name: &str) -> bool {
    name.len() <= 200
        && name.ends_with(".json")
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_' | ' '))
        && !name.contains("..")
}

fn folder(state: &AppState) -> ApiResult<PathBuf> {
    state.config.dir.clone().ok_or_else(|| {
        ApiError::new(
            StatusCode::FORBIDDEN,
            "no folder of model files: start the server with --dir FOLDER to open and save files",
        )
    })
}

fn checked(state: &AppState, name: &str) -> ApiResult<PathBuf> {
    let dir = folder(state)?;
    if !valid_name(name) {
        return Err(ApiError::bad_request(format!(
            "\"{name}\" is not a model file name: one name ending in .json, of letters, digits, \
             '.', '-', '_' and spaces (no folders)"
        )));
    }
    Ok(dir.join(name))
}

/// `GET /api/files` → `{"files": [{"name", "bytes"}]}`: the `.json` files of the folder.
pub async fn list(State(state): State<AppState>) -> ApiResult<Json<Value>> {
    let dir = folder(&state)?;
    blocking(move || {
        let entries = std::fs::read_dir(&dir)
            .map_err(|e| ApiError::unprocessable(format!("cannot read the folder: {e}")))?;
        let mut files: Vec<(String, u64)> = entries
            .filter_map(Result::ok)
            .filter_map(|e| {
                let name = e.file_name().into_string().ok()?;
                let meta = e.metadata().ok()?;
                (meta.is_file() && valid_name(&name)).then_some((name, meta.len()))
            })
            .collect();
        files.sort();
        let files: Vec<Value> = files
            .into_iter()
            .map(|(name, bytes)| json!({"name": name, "bytes": bytes}))
            .collect();
        Ok(Json(json!({ "files": files })))
    })
    .await
}

/// `GET /api/files/{name}` → `{"name", "what", "model"}`: a model file of the folder, read
/// and checked by the model crate.
pub async fn open(
    State(state): State<AppState>,
    Path(name): Path<String>,
) -> ApiResult<Json<Value>> {
    let path = checked(&state, &name)?;
    blocking(move || {
        let meta = std::fs::symlink_metadata(&path)
            .map_err(|_| ApiError::not_found(format!("no model file \"{name}\" in the folder")))?;
        if !meta.is_file() {
            return Err(ApiError::not_found(format!(
                "\"{name}\" is not a plain file (links are not followed)"
            )));
        }
        if meta.len() > MAX_FILE_BYTES {
            return Err(ApiError::too_large(format!(
                "\"{name}\" has {} bytes: the editor opens files up to {MAX_FILE_BYTES}",
                meta.len()
            )));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| ApiError::unprocessable(format!("cannot read \"{name}\": {e}")))?;
        let value: Value = serde_json::from_str(&text)
            .map_err(|e| ApiError::unprocessable(format!("\"{name}\" is not JSON: {e}")))?;
        let model = read_model(&name, &value, &state.config.limits)?;
        Ok(Json(
            json!({"name": name, "what": model.describe(), "model": value}),
        ))
    })
    .await
}

/// `PUT /api/files/{name} {"model": M}` → `{"name", "what", "bytes"}`: the model checked,
/// then written atomically in the layout of the tools.
pub async fn save(
    State(state): State<AppState>,
    Path(name): Path<String>,
    ApiJson(body): ApiJson<ModelBody>,
) -> ApiResult<Json<Value>> {
    let path = checked(&state, &name)?;
    blocking(move || {
        if let Ok(meta) = std::fs::symlink_metadata(&path) {
            if !meta.is_file() {
                return Err(ApiError::new(
                    StatusCode::CONFLICT,
                    format!("\"{name}\" exists and is not a plain file: not replaced"),
                ));
            }
        }
        let model = read_model("model", &body.model, &state.config.limits)?;
        let file = super::read_file("model", &body.model)?;
        let text = geomkit_model::to_json(&file).map_err(|e| ApiError::model("model", e))?;
        let dir = path.parent().expect("a file in the folder").to_path_buf();
        let write = || -> std::io::Result<()> {
            let mut tmp = tempfile::NamedTempFile::new_in(&dir)?;
            tmp.write_all(text.as_bytes())?;
            tmp.as_file().sync_all()?;
            tmp.persist(&path).map_err(|e| e.error)?;
            Ok(())
        };
        write().map_err(|e| ApiError::unprocessable(format!("cannot save \"{name}\": {e}")))?;
        Ok(Json(
            json!({"name": name, "what": model.describe(), "bytes": text.len()}),
        ))
    })
    .await
}
