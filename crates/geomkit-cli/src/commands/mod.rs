//! Implementations of the subcommands, one file per method.

pub mod bezier;
pub mod compose;
pub mod eval;
pub mod formula;
pub mod interpolate;
pub mod mesh;
pub mod piecewise;
pub mod pointcalc;
pub mod render;
pub mod serve;
mod spline_tiles;
pub mod step;
