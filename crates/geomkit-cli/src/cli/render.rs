//! Arguments of `geomkit render` and `geomkit mesh`.

use super::Samples;
use clap::Args;
use geomkit_plot::figures::View;
use std::path::PathBuf;

/// Arguments of `render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The model: any JSON model the other commands write (Bézier, rational, B-spline,
    /// composite scene, point-calculus model), or control points .csv/.npy with their knots.
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output picture: .png or .svg.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Camera azimuth and elevation in degrees [default: 35,25].
    #[arg(long, value_name = "AZ,EL", value_parser = parse_view, allow_hyphen_values = true)]
    pub view: Option<View>,
    /// Picture size in pixels [default: 720x540 for surfaces; curves size themselves, and a
    /// PNG is fitted into WxH].
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Leave out the control net / polygon.
    #[arg(long)]
    pub no_net: bool,
    /// Title [default: the file name].
    #[arg(long, value_name = "TEXT")]
    pub title: Option<String>,
}

/// "35,25" → a view; both finite, elevation within ±90°.
pub fn parse_view(s: &str) -> Result<View, String> {
    let (a, e) = s
        .split_once(',')
        .ok_or_else(|| format!("'{s}' is not AZ,EL (two angles in degrees)"))?;
    let num = |x: &str| match x.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("'{}' is not a finite angle", x.trim())),
    };
    let (azimuth, elevation) = (num(a)?, num(e)?);
    if elevation.abs() > 90.0 {
        return Err(format!(
            "elevation {elevation} must be within -90..90 degrees"
        ));
    }
    Ok(View { azimuth, elevation })
}

/// "800x600" → (800, 600), each from 16 to 8192.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WxH (e.g. 800x600)"))?;
    let num = |x: &str| match x.trim().parse::<u32>() {
        Ok(v) if (16..=8192).contains(&v) => Ok(v),
        _ => Err(format!(
            "'{}' is not a size from 16 to 8192 pixels",
            x.trim()
        )),
    };
    Ok((num(w)?, num(h)?))
}

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
    /// units [default: per axis 1/1000 of the model's extent along it]. Work is capped at
    /// 2000000 triangles for a surface (1000000 points for a curve): a tolerance the cap
    /// stops short of is an error naming the deviation reached there (ask for that); the
    /// default tolerance stopped by the cap writes the mesh with a warning. A tolerance below
    /// f64's resolution at the model's size (16 ulps of its largest coordinate) is refused.
    #[arg(
        long,
        value_name = "T",
        conflicts_with = "samples",
        allow_negative_numbers = true
    )]
    pub tolerance: Option<f64>,
    /// Uniform sampling instead: K×L grid for surfaces (break lines added; at most 2000000
    /// triangles), K points for curves (at most 1000000).
    #[arg(long, value_name = "KxL", value_parser = super::parse_samples)]
    pub samples: Option<Samples>,
    /// ASCII STL instead of binary.
    #[arg(long)]
    pub ascii: bool,
    /// Normals in OBJ: auto (one `vn` per `v` where the mesh is smooth, none where it has
    /// sharp edges: every reader, meshio included, takes it and a closed body stays
    /// watertight), indexed (`f v//vn`, sharp creases, shared positions: trimesh, Blender,
    /// OCCT; meshio refuses it), per-vertex (one `vn` per `v`, vertices split at creases:
    /// meshio reads the normals, watertight only after merging coincident vertices), none.
    #[arg(long, value_name = "LAYOUT", default_value = "auto", value_parser = super::parse_obj_normals)]
    pub obj_normals: geomkit::mesh::ObjNormals,
}
