//! Pictures of every model: curves with their control polygons, reference points and labels,
//! surfaces as a shaded 3-D view (camera azimuth/elevation) with the control net, as SVG and
//! as PNG (the SVG rasterized by resvg with the embedded DejaVu Sans font, so no system font
//! or library is needed).

mod raster;
pub mod shaded;
pub mod shape;

pub use raster::svg_to_png;
