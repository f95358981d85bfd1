//! # geomkit-plot
//!
//! Pictures of geomkit models for every front end (the CLI, the demo gallery, the editor):
//!
//! - [`svg`]: a small SVG figure builder (axes, lines, dots, labels placed without overlap,
//!   legends) with the project's palette;
//! - [`figures`]: curves with their control polygons, degree-change comparisons, surface
//!   wireframes with their nets, height maps, the axonometric [`figures::View`];
//! - [`shaded`]: shaded 3-D views of triangle meshes (painter's order, two-sided lighting)
//!   with overlays of nets and points;
//! - [`picture_svg`]: the picture of any model file ([`geomkit_model::Loaded`]);
//! - [`svg_to_png`] (feature `png`, on by default): rasterized with an embedded font, so a
//!   picture looks the same on every machine.
//!
//! ```
//! use geomkit_plot::{picture_svg, PictureOptions};
//! let model = geomkit_model::parse(r#"{"type": "bezier_curve", "points": [[0, 0], [1, 2], [2, 0]]}"#)
//!     .unwrap();
//! let loaded = geomkit_model::Loaded::from_model(model).unwrap();
//! let svg = picture_svg(&loaded, "A parabola", "three control points", &PictureOptions::default())
//!     .unwrap();
//! assert!(svg.starts_with("<svg") && svg.contains("A parabola"));
//! ```

pub mod figures;
mod picture;
#[cfg(feature = "png")]
mod raster;
pub mod shaded;
pub mod svg;

pub use picture::{curve_svg, picture_svg, PictureOptions};
#[cfg(feature = "png")]
pub use raster::svg_to_png;

/// Why a picture could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The model cannot be drawn this way (points of a dimension other than 1, 2 or 3, a
    /// surface given where heights are needed).
    #[error("{0}")]
    Unsupported(String),
    /// The picture cannot be rasterized (a size out of range, SVG that does not parse).
    #[error("{0}")]
    Picture(String),
    /// The library's evaluation or tessellation failed.
    #[error(transparent)]
    Geometry(#[from] geomkit::Error),
}

/// A result of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
