//! Arguments of `geomkit pointcalc`.

use super::parse_format;
use clap::{Args, Subcommand};
use geomkit::expr::Format;
use std::path::PathBuf;

const FIT_ABOUT: &str = "\
Fit a k-factor model through experimental points (spec/point-calculus.md §4).

EXPERIMENTS.csv has a header line naming the columns (commas, semicolons or tabs), then one
experiment per line. The factor columns (--factors) must take a full grid of levels: every
combination of the levels present, exactly once. Each factor's levels are its nodes; the
model passes through every experimental point (no system is solved).

--nodes a=0,1/3,1;b=... gives the nodes of some factors explicitly: exact rationals (kept
exact in formulas) or presets (cheb1:N:LO:HI, cheb2:N:LO:HI, equi:N:LO:HI); the data levels
are matched to them within 1e-9 of their span.

Limits: at most 5000 levels (nodes) per factor, and at most 10^8 numbers in the model's
grid (cells times responses).";

/// `geomkit pointcalc ...`
#[derive(Debug, Subcommand)]
pub enum PointcalcCommand {
    /// Fit a k-factor model through experimental points (a CSV grid of factor levels).
    #[command(long_about = FIT_ABOUT)]
    Fit(FitArgs),
    /// Evaluate a model at the factor values of a CSV file (prints them with the response).
    ///
    /// Outside the factors' levels the model extrapolates; a point so far out that the
    /// response is beyond f64, or that rounding errors exceed both the response and the data
    /// (no digit would be right), is refused with its line.
    Eval(PcEvalArgs),
    /// The share of every experimental point in the modeled point at given factor values.
    ///
    /// Far outside the levels the shares grow like x^(n-1); one beyond f64 is refused.
    Shares(SharesArgs),
    /// The largest or smallest modeled response over the factors' box (global, certified).
    ///
    /// Branch and bound with Bernstein bounds: at most 4000 boxes and about 10^9
    /// operations (then the result is printed with "certified": false and a warning); a model
    /// one box of which costs more than that (cells × Σ levels + Σ levels³ / 2) is refused.
    Optimize(OptimizeArgs),
    /// The model (or a curve from POINTS.json) as one formula per response.
    ///
    /// At most 10^7 factors (source values × nodes); every number of the formula is a
    /// finite f64 (a coefficient beyond f64 is refused, naming the node or source point).
    Formula(FormulaArgs),
    /// A point-equation curve through source points (JSON), as SVG or JSON samples.
    Curve(PcCurveArgs),
    /// A point-equation surface through a net of source points (JSON), as SVG or JSON.
    Surface(PcSurfaceArgs),
}

/// Arguments of `pointcalc fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// Experiments: CSV with a header.
    #[arg(value_name = "EXPERIMENTS.csv")]
    pub input: PathBuf,
    /// Factor columns, comma-separated.
    #[arg(long, value_name = "A,B,..", value_delimiter = ',', required = true)]
    pub factors: Vec<String>,
    /// Response column(s), comma-separated (several make a vector response).
    #[arg(long, value_name = "Y", value_delimiter = ',', required = true)]
    pub response: Vec<String>,
    /// Explicit nodes of some factors: "a=0,1/3,1;b=cheb2:5:0:1" (at most 5000 per factor).
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub nodes: Option<String>,
    /// Fail (instead of warning) when a factor's Lebesgue constant is large.
    #[arg(long)]
    pub strict: bool,
    /// Output model (JSON); default: standard output.
    #[arg(short, long, value_name = "MODEL.json")]
    pub output: Option<PathBuf>,
}

/// Arguments of `pointcalc eval`.
#[derive(Debug, Args)]
pub struct PcEvalArgs {
    /// The model (from `pointcalc fit`).
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,
    /// Factor values: CSV with a header naming the factor columns.
    #[arg(value_name = "AT.csv")]
    pub at: PathBuf,
    /// Output CSV; default: standard output.
    #[arg(short, long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
}

/// Arguments of `pointcalc shares`.
#[derive(Debug, Args)]
pub struct SharesArgs {
    /// The model.
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,
    /// The factor values: "a=1.5,b=2,c=0.3" (every factor).
    #[arg(long, value_name = "A=X,..", allow_hyphen_values = true)]
    pub at: String,
}

/// Arguments of `pointcalc optimize`.
#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("goal").required(true).args(["max", "min"])))]
pub struct OptimizeArgs {
    /// The model (scalar response).
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,
    /// The largest response.
    #[arg(long)]
    pub max: bool,
    /// The smallest response.
    #[arg(long)]
    pub min: bool,
    /// Relative tolerance of the certified gap (to the range of the data), a finite number
    /// >= 0 [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
}

/// Arguments of `pointcalc formula`.
#[derive(Debug, Args)]
pub struct FormulaArgs {
    /// A model from `pointcalc fit`, or source points of a curve (POINTS.json, with --nodes).
    #[arg(value_name = "MODEL.json")]
    pub model: PathBuf,
    /// Target syntax: maple, mathematica, sympy, numpy, matlab, latex, c, rust, glsl, js,
    /// desmos.
    #[arg(long, value_name = "FORMAT", value_parser = parse_format)]
    pub format: Format,
    /// For a curve: the nodes (as for `pointcalc curve`).
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub nodes: Option<String>,
}

/// Arguments of `pointcalc curve`.
#[derive(Debug, Args)]
pub struct PcCurveArgs {
    /// Source points: JSON array of points ([[x,y],...]) or {"points": [...]}.
    #[arg(value_name = "POINTS.json")]
    pub input: PathBuf,
    /// Nodes: "0,1/3,1", "cheb1:N[:LO:HI]", "cheb2:N", "equi:N", "half", "third",
    /// "two-thirds" [default: equally spaced j/(n-1), exact]; at most 5000 nodes.
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub nodes: Option<String>,
    /// Fail (instead of warning) when the Lebesgue constant is large.
    #[arg(long)]
    pub strict: bool,
    /// Samples over the node interval for JSON output, 2 to 1000000, and at most 2·10^9
    /// multiply-adds (samples × source numbers) [default: 201].
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub samples: Option<usize>,
    /// Output: .svg (a picture) or .json (nodes, Lebesgue constant, samples); default: JSON
    /// to standard output.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// Arguments of `pointcalc surface`.
#[derive(Debug, Args)]
pub struct PcSurfaceArgs {
    /// Net of source points: JSON [[[x,y,z],...],...] (rows of points) or {"net": ...}.
    #[arg(value_name = "POINTS.json")]
    pub input: PathBuf,
    /// Nodes along every row [default: equally spaced, exact]; at most 5000 per node set.
    #[arg(
        long,
        value_name = "SPEC",
        conflicts_with = "row_nodes",
        allow_hyphen_values = true
    )]
    pub nodes: Option<String>,
    /// Nodes of each row, separated by ';' ("third;half;two-thirds"); at most 5000 each.
    #[arg(long, value_name = "SPEC;SPEC;..", allow_hyphen_values = true)]
    pub row_nodes: Option<String>,
    /// Nodes across the rows [default: equally spaced, exact]; at most 5000.
    #[arg(long, value_name = "SPEC", allow_hyphen_values = true)]
    pub across: Option<String>,
    /// The paper's geomatrix (9) exactly as printed (3×3 nets only; not affine invariant).
    #[arg(long, conflicts_with_all = ["nodes", "row_nodes", "across"])]
    pub printed: bool,
    /// Samples per direction for JSON output (K × K points), 2 to 1000, and at most 2·10^9
    /// multiply-adds (K × source numbers + K² × rows) [default: 21].
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub samples: Option<usize>,
    /// Output: .svg or .json (a K×K grid of points); default: JSON to standard output.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}
