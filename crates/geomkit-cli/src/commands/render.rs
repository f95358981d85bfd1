//! `geomkit render MODEL -o OUT.png|OUT.svg [--view AZ,EL] [--size WxH] [--no-net]`.

use crate::model::load_shape as load;
use crate::output::write_atomic;
use crate::table::extension;
use anyhow::{bail, Result};
use clap::Args;
use geomkit_plot::figures::View;
use geomkit_plot::svg_to_png;
use geomkit_plot::{picture_svg, PictureOptions};
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

/// Runs `geomkit render`.
pub fn run(args: RenderArgs) -> Result<()> {
    let png = match extension(&args.output).as_deref() {
        Some("png") => true,
        Some("svg") => false,
        _ => bail!(
            "cannot tell the picture format of {}: name it .png or .svg",
            args.output.display()
        ),
    };
    let loaded = load(&args.model)?;
    let mut opts = PictureOptions {
        net: !args.no_net,
        ..PictureOptions::default()
    };
    if let Some(v) = args.view {
        opts.view = v;
    }
    if let Some((w, h)) = args.size {
        opts.size = (w as f64, h as f64);
    }
    let title = args.title.clone().unwrap_or_else(|| {
        args.model
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    });
    let svg = picture_svg(&loaded, &title, &loaded.what, &opts)?;
    if png {
        write_atomic(&args.output, &svg_to_png(&svg, 2.0, args.size)?)
    } else {
        write_atomic(&args.output, svg.as_bytes())
    }
}
