//! `POST /api/export`: a model as a file to download — a picture (SVG, PNG: geomkit-plot's
//! picture of `geomkit render`), a mesh (STL, GLB, OBJ, PLY: the library's writers, as
//! `geomkit mesh`), the model file itself (JSON) or its single formula (text).

use super::formula::{format_of, model_formula};
use super::read_model;
use crate::error::{blocking, ApiError, ApiJson, ApiResult};
use crate::AppState;
use axum::extract::State;
use axum::http::header;
use axum::response::{IntoResponse, Response};
use geomkit::mesh;
use geomkit_model::{Loaded, Sampling, Tessellation};
use geomkit_plot::{picture_svg, svg_to_png, PictureOptions};
use serde::Deserialize;
use serde_json::Value;

/// `{"model": M, "format": "svg", "title": "...", "syntax": "maple", "samples": K}`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExportRequest {
    /// The model file.
    pub model: Value,
    /// svg, png, stl, glb, obj, ply, json or formula.
    pub format: String,
    /// The picture's title (default: what the model is).
    #[serde(default)]
    pub title: Option<String>,
    /// The picture's subtitle (default "geomkit serve").
    #[serde(default)]
    pub subtitle: Option<String>,
    /// The formula's syntax (default maple).
    #[serde(default)]
    pub syntax: Option<String>,
    /// Mesh samples per direction (default: adaptive to 1/1000 of the size).
    #[serde(default)]
    pub samples: Option<usize>,
}

/// The bytes of an export, its MIME type and file extension.
pub fn export_bytes(
    req: &ExportRequest,
    limits: &crate::Limits,
) -> ApiResult<(Vec<u8>, &'static str)> {
    let format = req.format.to_ascii_lowercase();
    let model = read_model("model", &req.model, limits)?;
    let what = model.describe();
    let picture_error = |e: geomkit_plot::Error| ApiError::unprocessable(format!("picture: {e}"));
    match format.as_str() {
        "json" => {
            let file = super::read_file("model", &req.model)?;
            let text = geomkit_model::to_json(&file).map_err(|e| ApiError::model("model", e))?;
            Ok((text.into_bytes(), "application/json"))
        }
        "formula" => {
            let syntax = format_of(req.syntax.as_deref())?;
            let (f, _) = model_formula(model)?;
            let text = f
                .print(syntax)
                .map_err(|e| ApiError::geometry("formula", e))?;
            Ok((text.into_bytes(), "text/plain; charset=utf-8"))
        }
        "svg" | "png" => {
            let loaded = Loaded::from_model(model).map_err(|e| ApiError::model("model", e))?;
            let title = req.title.clone().unwrap_or_else(|| what.clone());
            let subtitle = req.subtitle.as_deref().unwrap_or("geomkit serve");
            let svg = picture_svg(&loaded, &title, subtitle, &PictureOptions::default())
                .map_err(picture_error)?;
            if format == "png" {
                let png = svg_to_png(&svg, 2.0, None).map_err(picture_error)?;
                Ok((png, "image/png"))
            } else {
                Ok((svg.into_bytes(), "image/svg+xml"))
            }
        }
        "stl" | "glb" | "obj" | "ply" => {
            let loaded = Loaded::from_model(model).map_err(|e| ApiError::model("model", e))?;
            let sampling = match req.samples {
                Some(k) if (2..=1000).contains(&k) => Sampling::Samples(k, k),
                Some(k) => {
                    return Err(ApiError::bad_request(format!(
                        "samples must be between 2 and 1000 (got {k})"
                    ))
                    .with("path", "samples"))
                }
                None => Sampling::Tolerance(None),
            };
            let t = loaded
                .tessellate(sampling)
                .map_err(|e| ApiError::geometry("mesh", e))?;
            let mut out = Vec::new();
            let written = match (&t, format.as_str()) {
                (Tessellation::Mesh(m), "stl") => mesh::write_stl_binary(m, &mut out),
                (Tessellation::Mesh(m), "glb") => mesh::write_glb(m, &mut out),
                (Tessellation::Mesh(m), "obj") => mesh::write_obj(m, &mut out),
                (Tessellation::Mesh(m), _) => mesh::write_ply(m, &mut out),
                (Tessellation::Polyline(_), "stl") => {
                    return Err(ApiError::unprocessable(
                        "STL holds triangles only: export a curve as GLB, OBJ or PLY",
                    ))
                }
                (Tessellation::Polyline(p), "glb") => mesh::write_glb_polyline(p, &mut out),
                (Tessellation::Polyline(p), "obj") => mesh::write_obj_polyline(p, &mut out),
                (Tessellation::Polyline(p), _) => mesh::write_ply_polyline(p, &mut out),
            };
            written.map_err(|e| ApiError::unprocessable(format!("mesh: {e}")))?;
            let mime = match format.as_str() {
                "stl" => "model/stl",
                "glb" => "model/gltf-binary",
                _ => "text/plain; charset=utf-8",
            };
            Ok((out, mime))
        }
        other => Err(ApiError::bad_request(format!(
            "format \"{other}\" is not one of svg, png, stl, glb, obj, ply, json, formula"
        ))
        .with("path", "format")),
    }
}

/// `POST /api/export`: the file's bytes with its Content-Type and a Content-Disposition
/// naming `model.EXT`.
pub async fn export(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ExportRequest>,
) -> ApiResult<Response> {
    blocking(move || {
        let (bytes, mime) = export_bytes(&req, &state.config.limits)?;
        let ext = match req.format.to_ascii_lowercase().as_str() {
            "formula" => "txt".to_string(),
            other => other.to_string(),
        };
        let disposition = format!("attachment; filename=\"model.{ext}\"");
        Ok((
            [
                (header::CONTENT_TYPE, mime.to_string()),
                (header::CONTENT_DISPOSITION, disposition),
            ],
            bytes,
        )
            .into_response())
    })
    .await
}
