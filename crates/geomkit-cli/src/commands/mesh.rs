//! `geomkit mesh MODEL -o OUT.obj|.stl|.ply|.glb [--tolerance T | --samples KxL] [--ascii]`.

use crate::cli::MeshArgs;
use crate::cli::Samples;
use crate::model::load_shape as load;
use crate::output::{mesh_summary, write_atomic, write_mesh};
use crate::table::extension;
use anyhow::{bail, Result};
use geomkit_model::Sampling;
use std::io::Write;

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
