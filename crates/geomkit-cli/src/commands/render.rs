//! `geomkit render MODEL -o OUT.png|OUT.svg [--view AZ,EL] [--size WxH] [--no-net]`.

use crate::cli::RenderArgs;
use crate::model::load_shape as load;
use crate::output::write_atomic;
use crate::table::extension;
use anyhow::{bail, Context, Result};
use geomkit_plot::svg_to_png;
use geomkit_plot::{picture_svg, PictureOptions};

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
    let svg = picture_svg(&loaded, &title, &loaded.what, &opts)
        .with_context(|| format!("cannot draw {}", args.model.display()))?;
    if png {
        write_atomic(&args.output, &svg_to_png(&svg, 2.0, args.size)?)
    } else {
        write_atomic(&args.output, svg.as_bytes())
    }
}
