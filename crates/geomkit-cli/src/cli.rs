//! The command line: clap derive types. Each method adds a subcommand group here and its
//! implementation in `commands/`.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// geomkit: geometric modeling of curves and surfaces.
#[derive(Debug, Parser)]
#[command(name = "geomkit", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Top-level commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Bézier curves and surfaces: real degree, elevation, reduction, evaluation.
    #[command(subcommand)]
    Bezier(BezierCommand),
    /// Run every method's demo: pictures, model files, index.html and a table of checks.
    Demo(DemoArgs),
}

/// `geomkit bezier ...`
#[derive(Debug, Subcommand)]
pub enum BezierCommand {
    /// Formal degree, real degree and degree defect (per direction for surfaces).
    Degree(DegreeArgs),
    /// Elevate the degree; the shape is unchanged.
    Elevate(ElevateArgs),
    /// Reduce the degree: exactly (only down to the real degree) or, for curves, by the best
    /// approximation (--approx).
    Reduce(ReduceArgs),
    /// Change the degree in one step (the paper's unified formula (10)/(14)): elevate or
    /// reduce exactly, per direction for surfaces.
    Change(ChangeArgs),
    /// Sample points as CSV (a K×K grid with u,v columns for surfaces).
    Eval(EvalArgs),
}

/// Arguments of `bezier degree`.
#[derive(Debug, Args)]
pub struct DegreeArgs {
    /// Input curve or surface (JSON).
    pub input: PathBuf,
    /// Print `{"degree":..,"real_degree":..,"defect":..}` (pairs for surfaces).
    #[arg(long)]
    pub json: bool,
    /// Relative tolerance of the real-degree test (default 1e-12).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
}

/// Target degree(s): `N` for curves, `N,M` for surfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Degrees {
    /// One degree (curves).
    One(usize),
    /// Degrees in u and v (surfaces).
    Two(usize, usize),
}

impl std::fmt::Display for Degrees {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Degrees::One(n) => write!(f, "{n}"),
            Degrees::Two(n, m) => write!(f, "{n},{m}"),
        }
    }
}

fn parse_degrees(s: &str) -> Result<Degrees, String> {
    let parse = |x: &str| {
        x.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{x}' is not a degree (a non-negative integer)"))
    };
    match s.split_once(',') {
        None => Ok(Degrees::One(parse(s)?)),
        Some((a, b)) => Ok(Degrees::Two(parse(a)?, parse(b)?)),
    }
}

/// Continuity orders at t = 0 and t = 1 (`None`: free).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Continuity(pub Option<usize>, pub Option<usize>);

fn parse_continuity(s: &str) -> Result<Continuity, String> {
    let parse = |x: &str| match x.trim() {
        "-" | "free" | "none" => Ok(None),
        x => x
            .parse::<usize>()
            .map(Some)
            .map_err(|_| format!("'{x}' is not a continuity order (an integer, or '-' for free)")),
    };
    match s.split_once(',') {
        None => {
            let a = parse(s)?;
            Ok(Continuity(a, a))
        }
        Some((a, b)) => Ok(Continuity(parse(a)?, parse(b)?)),
    }
}

/// Arguments of `bezier elevate`.
#[derive(Debug, Args)]
pub struct ElevateArgs {
    /// Input curve or surface (JSON).
    pub input: PathBuf,
    /// Target degree: N for curves, N,M for surfaces.
    #[arg(long, value_name = "N[,M]", value_parser = parse_degrees)]
    pub to: Degrees,
    /// Output file: .json (the new model) or .svg (a picture); default: JSON to stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// Arguments of `bezier change`.
#[derive(Debug, Args)]
pub struct ChangeArgs {
    /// Input curve or surface (JSON).
    pub input: PathBuf,
    /// Target degree: N for curves, N,M for surfaces.
    #[arg(long, value_name = "N[,M]", value_parser = parse_degrees)]
    pub to: Degrees,
    /// Relative tolerance of the exact-reduction test (default 1e-12).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// Output file: .json (the new model) or .svg (a picture); default: JSON to stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// The norm of an approximate reduction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Norm {
    /// Least squares over [0, 1].
    L2,
    /// Chebyshev-weighted least squares: near-best in the maximum norm.
    Chebyshev,
}

/// Arguments of `bezier reduce`.
#[derive(Debug, Args)]
pub struct ReduceArgs {
    /// Input curve or surface (JSON).
    pub input: PathBuf,
    /// Target degree: N for curves, N,M for surfaces.
    #[arg(long, value_name = "N[,M]", value_parser = parse_degrees)]
    pub to: Degrees,
    /// Best approximation of the lower degree instead of an exact reduction (curves only);
    /// adds "error":{"l2":..,"linf_bound":..} to the JSON.
    #[arg(long)]
    pub approx: bool,
    /// With --approx: C^A continuity at t=0 and C^B at t=1 ("1,1"; "-" leaves an end free).
    #[arg(long, value_name = "A,B", value_parser = parse_continuity, requires = "approx")]
    pub continuity: Option<Continuity>,
    /// With --approx: the norm minimized.
    #[arg(long, value_enum, requires = "approx")]
    pub norm: Option<Norm>,
    /// Relative tolerance of the exact-reduction test (default 1e-12).
    #[arg(
        long,
        value_name = "T",
        allow_negative_numbers = true,
        conflicts_with = "approx"
    )]
    pub tolerance: Option<f64>,
    /// Output file: .json (the new model) or .svg (a picture); default: JSON to stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// Arguments of `bezier eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Input curve or surface (JSON).
    pub input: PathBuf,
    /// Number of uniform samples over [0, 1] (per direction for surfaces), at least 2.
    #[arg(long, value_name = "K")]
    pub samples: usize,
    /// Output CSV file; default: stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// Arguments of `demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR", default_value = "geomkit-demo")]
    pub out: PathBuf,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_degrees_and_continuity() {
        assert_eq!(parse_degrees("5"), Ok(Degrees::One(5)));
        assert_eq!(parse_degrees("3,6"), Ok(Degrees::Two(3, 6)));
        assert!(parse_degrees("-1").is_err());
        assert!(parse_degrees("3,x").is_err());
        assert_eq!(parse_continuity("1,2"), Ok(Continuity(Some(1), Some(2))));
        assert_eq!(parse_continuity("1"), Ok(Continuity(Some(1), Some(1))));
        assert_eq!(parse_continuity("-,0"), Ok(Continuity(None, Some(0))));
        assert!(parse_continuity("a,b").is_err());
    }

    #[test]
    fn clap_definition_is_valid() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
