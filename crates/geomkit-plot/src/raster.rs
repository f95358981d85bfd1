//! SVG to PNG with resvg and the embedded DejaVu Sans font (assets/fonts): no system fonts
//! or libraries are needed, so a picture looks the same on every machine.

use crate::Result;
use resvg::{tiny_skia, usvg};
use std::sync::{Arc, OnceLock};

/// The font every picture's text is drawn with (Bitstream Vera license, see
/// assets/fonts/DejaVuSans-LICENSE.txt).
const FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

fn options() -> &'static usvg::Options<'static> {
    static OPTIONS: OnceLock<usvg::Options<'static>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_font_data(FONT.to_vec());
        let family = "DejaVu Sans";
        db.set_sans_serif_family(family);
        db.set_serif_family(family);
        db.set_monospace_family(family);
        db.set_cursive_family(family);
        db.set_fantasy_family(family);
        usvg::Options {
            font_family: "DejaVu Sans".into(),
            fontdb: Arc::new(db),
            ..usvg::Options::default()
        }
    })
}

/// Rasterizes SVG text to PNG bytes on a white background: at `scale` times the SVG's own
/// size, or fitted into `size` = (width, height) pixels (aspect kept, centred).
pub fn svg_to_png(svg: &str, scale: f64, size: Option<(u32, u32)>) -> Result<Vec<u8>> {
    let tree = usvg::Tree::from_str(svg, options())
        .map_err(|e| crate::Error::Picture(format!("invalid SVG: {e}")))?;
    let (sw, sh) = (tree.size().width() as f64, tree.size().height() as f64);
    let (w, h, k) = match size {
        Some((w, h)) => {
            if w == 0 || h == 0 || w > 16384 || h > 16384 {
                return Err(crate::Error::Picture(format!(
                    "picture size {w}x{h}: width and height must be from 1 to 16384"
                )));
            }
            (w, h, (w as f64 / sw).min(h as f64 / sh))
        }
        None => (
            (sw * scale).round().max(1.0) as u32,
            (sh * scale).round().max(1.0) as u32,
            scale,
        ),
    };
    let mut pixmap = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| crate::Error::Picture(format!("cannot allocate {w}x{h} pixels")))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    let (dx, dy) = ((w as f64 - sw * k) / 2.0, (h as f64 - sh * k) / 2.0);
    let transform =
        tiny_skia::Transform::from_row(k as f32, 0.0, 0.0, k as f32, dx as f32, dy as f32);
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    pixmap
        .encode_png()
        .map_err(|e| crate::Error::Picture(format!("cannot encode PNG: {e}")))
}
