//! `geomkit export` and `geomkit import`: exact geometry to and from STEP (ISO 10303-21).

use clap::{Args, ValueEnum};
use std::path::PathBuf;

/// The application protocol of an exported file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SchemaArg {
    /// AP214 (AUTOMOTIVE_DESIGN): read by every STEP reader.
    Ap214,
    /// AP242 (managed model based 3D engineering).
    Ap242,
}

/// Arguments of `geomkit export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The model: a Bézier or B-spline curve or surface (rational Bézier ones too), a
    /// composite surface, a ruled surface or closed body (`compose body`), a composite curve
    /// or piecewise function; formulas without an exact B-spline form are approximated
    /// (see --tolerance).
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Output: a .step or .stp file (ISO 10303-21 text), written atomically.
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// The application protocol named in the file.
    #[arg(long, value_enum, default_value = "ap214")]
    pub schema: SchemaArg,
    /// The product's name in the file [default: the model file's name without extension].
    #[arg(long)]
    pub name: Option<String>,
    /// Formulas without an exact B-spline form (sqrt, sin, exp, ... in composite patches,
    /// ruled curves, composite curves) are written as interpolating B-splines refined until
    /// their largest deviation from the formula is at most this times the diagonal of the
    /// model's bounding box; each is named in a `warning:` line with its deviation.
    #[arg(long, value_name = "REL", default_value_t = 1e-6)]
    pub tolerance: f64,
}

/// Arguments of `geomkit import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// A STEP file (.step, .stp): its B-spline and Bézier curves and surfaces are read.
    #[arg(value_name = "STEP")]
    pub input: PathBuf,
    /// Output: a folder (created if missing) that receives one model file per curve or
    /// surface, named KIND-N.json after the entity #N; or a .json file when the STEP file
    /// holds exactly one.
    #[arg(short, long, value_name = "DIR_OR_FILE")]
    pub output: PathBuf,
}
