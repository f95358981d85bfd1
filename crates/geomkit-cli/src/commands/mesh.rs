//! `geomkit mesh MODEL -o OUT.obj|.stl|.ply|.glb [--tolerance T | --samples KxL] [--ascii]
//! [--obj-normals auto|indexed|per-vertex|none]`.

use crate::cli::MeshArgs;
use crate::cli::Samples;
use crate::model::load_shape as load;
use crate::output::{mesh_summary, short, write_mesh_to, Destination, MESH_FORMATS};
use crate::table::extension;
use anyhow::{anyhow, bail, Result};
use geomkit::Error;
use geomkit_model::{Loaded, Sampling, Tessellation};
use std::io::Write;

/// Runs `geomkit mesh`.
pub fn run(args: MeshArgs) -> Result<()> {
    let ext = extension(&args.output).unwrap_or_default();
    if !MESH_FORMATS.contains(&ext.as_str()) {
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
    let option = match (&args.samples, args.tolerance) {
        (Some(s), _) => format!("--samples {s}"),
        (None, Some(t)) => format!("--tolerance {}", short(t)),
        (None, None) => String::new(),
    };
    let loaded = load(&args.model)?;
    let t = tessellate(
        &loaded,
        sampling,
        &args.model.display().to_string(),
        &option,
    )?;
    let dest = Destination::File(args.output.clone());
    write_mesh_to(&dest, &t, &ext, args.ascii, args.obj_normals)?;
    let _ = writeln!(std::io::stderr(), "{}", mesh_summary(&args.output, &t));
    Ok(())
}

/// Tessellates `loaded` for a command: errors name the model (`name`) and, for an error of
/// the sampling, the option as given (`option`: "--tolerance 1e-300", "--samples 5x4", or
/// empty for the defaults); a mesh that the triangle cap stopped short of the default
/// tolerance comes with a warning on stderr naming the deviation reached.
pub fn tessellate(
    loaded: &Loaded,
    sampling: Sampling,
    name: &str,
    option: &str,
) -> Result<Tessellation> {
    // A bar on a terminal for a long mesh (nothing in pipes).
    let meshed = {
        let bar = crate::progress::Progress::start();
        bar.phase("meshing", 0);
        let report = bar.reporter();
        let hook = geomkit::progress::Progress::new(&report);
        loaded.tessellate_with_progress(sampling, &hook)
    };
    let (t, report) = meshed.map_err(|e| {
        let of_sampling = matches!(
            e,
            Error::ToleranceOutOfReach { .. }
                | Error::ToleranceBelowResolution { .. }
                | Error::InvalidTolerance { .. }
                | Error::MeshTooLarge { .. }
                | Error::InvalidOption { .. }
        );
        match (of_sampling, option.is_empty()) {
            (true, false) => anyhow!("{name}: {option}: {e}"),
            _ => anyhow!("{name}: {e}"),
        }
    })?;
    if let Some(r) = report.filter(|r| r.capped) {
        let _ = writeln!(
            std::io::stderr(),
            "warning: {name}: adaptive meshing stopped at the cap of {} triangles before the \
             default tolerance (1/1000 of the model's extent per axis) was met: the mesh \
             deviates up to {:.2e} of the extent ({:.2e} in model units); pass --samples KxL \
             or a larger --tolerance for a mesh that meets its tolerance",
            geomkit::mesh::MAX_TRIANGLES,
            r.relative_deviation.unwrap_or(0.0),
            r.deviation.unwrap_or(0.0),
        );
    }
    Ok(t)
}
