//! `geomkit mesh MODEL -o OUT.obj|.stl|.ply|.glb [--tolerance T | --samples KxL] [--ascii]`.

use crate::cli::Samples;
use crate::model::load_shape as load;
use crate::output::write_atomic;
use crate::table::extension;
use anyhow::{bail, Result};
use clap::Args;
use geomkit::mesh;
use geomkit_model::{Sampling, Tessellation};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `mesh`.
#[derive(Debug, Args)]
pub struct MeshArgs {
    /// The model: any JSON model the other commands write (Bézier, rational, B-spline,
    /// composite scene, point-calculus model), or control points .csv/.npy with their knots.
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output: .obj (with normals), .stl (binary; --ascii for text), .ply (binary) or .glb
    /// (glTF binary). Curves become polylines (.obj, .ply, .glb).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Adaptive sampling: the largest distance between the model and the mesh, in model
    /// units [default: 1/1000 of the model's size].
    #[arg(
        long,
        value_name = "T",
        conflicts_with = "samples",
        allow_negative_numbers = true
    )]
    pub tolerance: Option<f64>,
    /// Uniform sampling instead: K×L grid for surfaces (break lines added), K points for
    /// curves.
    #[arg(long, value_name = "KxL", value_parser = crate::cli::parse_samples)]
    pub samples: Option<Samples>,
    /// ASCII STL instead of binary.
    #[arg(long)]
    pub ascii: bool,
}

/// Runs `geomkit mesh`.
pub fn run(args: MeshArgs) -> Result<()> {
    let ext = extension(&args.output).unwrap_or_default();
    if !matches!(ext.as_str(), "obj" | "stl" | "ply" | "glb") {
        bail!(
            "cannot tell the mesh format of {}: name it .obj, .stl, .ply or .glb",
            args.output.display()
        );
    }
    if let Some(t) = args.tolerance {
        if !(t.is_finite() && t > 0.0) {
            bail!("--tolerance {t} must be finite and > 0");
        }
    }
    let sampling = match args.samples {
        Some(Samples(k, l)) => Sampling::Samples(k, l.unwrap_or(k)),
        None => Sampling::Tolerance(args.tolerance),
    };
    let loaded = load(&args.model)?;
    let t = loaded.tessellate(sampling)?;
    let mut buf = Vec::new();
    write_mesh(&t, &ext, args.ascii, &mut buf)?;
    write_atomic(&args.output, &buf)?;
    let _ = writeln!(std::io::stderr(), "{}", mesh_summary(&args.output, &t));
    Ok(())
}

/// "OUT: V vertices, T triangles, closed, volume X" (or the polyline's size).
pub fn mesh_summary(path: &Path, t: &Tessellation) -> String {
    match t {
        Tessellation::Mesh(m) => format!(
            "{}: {} vertices, {} triangles{}",
            path.display(),
            m.positions().len(),
            m.triangles().len(),
            if m.is_watertight() {
                format!(", closed, volume {}", m.volume())
            } else {
                String::new()
            }
        ),
        Tessellation::Polyline(p) => format!("{}: polyline of {} points", path.display(), p.len()),
    }
}

/// Writes a tessellation in the format named by `ext`.
pub fn write_mesh(t: &Tessellation, ext: &str, ascii: bool, w: &mut Vec<u8>) -> Result<()> {
    match (t, ext) {
        (Tessellation::Mesh(m), "obj") => mesh::write_obj(m, w)?,
        (Tessellation::Mesh(m), "stl") if ascii => mesh::write_stl_ascii(m, w)?,
        (Tessellation::Mesh(m), "stl") => mesh::write_stl_binary(m, w)?,
        (Tessellation::Mesh(m), "ply") => mesh::write_ply(m, w)?,
        (Tessellation::Mesh(m), "glb") => mesh::write_glb(m, w)?,
        (Tessellation::Polyline(p), "obj") => mesh::write_obj_polyline(p, w)?,
        (Tessellation::Polyline(p), "ply") => mesh::write_ply_polyline(p, w)?,
        (Tessellation::Polyline(p), "glb") => mesh::write_glb_polyline(p, w)?,
        (Tessellation::Polyline(_), "stl") => {
            bail!("STL holds triangles only: write a curve as .obj, .ply or .glb")
        }
        (_, other) => bail!("unknown mesh format .{other}"),
    }
    Ok(())
}
