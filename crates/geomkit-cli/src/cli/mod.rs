//! The command line: clap derive types. Each method adds a subcommand group here and its
//! implementation in `commands/`.

mod compose;
mod pointcalc;
mod render;
mod serve;
mod step;

pub use compose::*;
pub use pointcalc::*;
pub use render::*;
pub use serve::*;
pub use step::*;

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

/// Most samples of a curve (rows of the CSV).
pub const MAX_CURVE_SAMPLES: usize = 100_000_000;
/// Most samples per direction of a surface (the CSV has the square of it).
pub const MAX_SURFACE_SAMPLES: usize = 10_000;

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
    /// Interpolating cubic B-splines: a curve or a surface through given points.
    #[command(subcommand)]
    Interpolate(InterpolateCommand),
    /// Evaluate a saved model (Bézier or B-spline, curve or surface) on uniform samples of its
    /// domain or at given parameters.
    Eval(ModelEvalArgs),
    /// Point equations (point BN-calculus): k-factor models through experimental points with
    /// shares and optimum; curves and surfaces through source points.
    #[command(subcommand)]
    Pointcalc(PointcalcCommand),
    /// Single analytic formulas (spec/composite-surfaces.md): closed bodies and composite
    /// surfaces as one formula in Maple, Mathematica, SymPy, ... syntax.
    #[command(subcommand)]
    Compose(ComposeCommand),
    /// A picture of any model: PNG or SVG (shaded 3-D view of surfaces with the control net,
    /// curves with control polygon and reference points).
    Render(RenderArgs),
    /// A mesh of any model: OBJ, STL, PLY or glTF binary (surfaces as triangles with
    /// normals, closed bodies watertight; curves as polylines).
    Mesh(MeshArgs),
    /// Run every method's demo: pictures, model files, index.html and a table of checks.
    Demo(DemoArgs),
    /// The editor in the browser: a local server of the page and a JSON API
    /// (docs/serve-api.md) on 127.0.0.1.
    Serve(ServeArgs),
    /// Exact geometry to STEP (ISO 10303-21, AP214/AP242): curves, surfaces, composite
    /// surfaces and closed bodies as B-spline entities that CAD systems read.
    Export(ExportArgs),
    /// The B-spline and Bézier curves and surfaces of a STEP file as model files.
    Import(ImportArgs),
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
    #[arg(
        long,
        value_name = "A,B",
        value_parser = parse_continuity,
        requires = "approx",
        allow_hyphen_values = true
    )]
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

/// `geomkit interpolate ...`
#[derive(Debug, Subcommand)]
pub enum InterpolateCommand {
    /// A B-spline curve through points, cubic or of any degree 1..7 (spec/bspline-interpolation.md
    /// §2, §6; SciPy's make_interp_spline).
    #[command(long_about = CURVE_ABOUT)]
    Curve(CurveArgs),
    /// A bicubic B-spline surface through a grid of points or heights (§3).
    #[command(long_about = SURFACE_ABOUT)]
    Surface(SurfaceArgs),
}

const CURVE_ABOUT: &str = "\
A B-spline curve through points (spec/bspline-interpolation.md §2, §6): the paper's cubic, or
any degree 1..7 with SciPy's make_interp_spline conditions, knots and coefficients (--degree,
--left/--right, --form scipy; SciPy's x are --params).

IN holds one point per row: a CSV file (2 or 3 columns, or any number d >= 1; an optional
header line; commas, semicolons, tabs or blanks) or a NumPy .npy float64 array of shape (N, d).

OUT by extension: .json (the model, with the parameters of the reference points), .csv or .npy
(--samples points evaluated uniformly over the parameter domain by forward differences),
.svg (the curve, its control polygon and the reference points). Default: the JSON model on
standard output.

With --control, a .csv/.npy OUT = NAME.EXT receives the control points instead (one per row)
and the sibling file NAME.knots.EXT the knot vector (one knot per row); `geomkit eval
NAME.EXT` reads the pair back as a B-spline curve. Two forms (--form):
  - extended (cubics with one --end, the default there): N+2 control points for open curves,
    the knots the parameters of the N points with three more at each end, spaced like the
    end intervals;
  - scipy (any degree, per-end conditions): exactly SciPy's make_interp_spline(x, y, k,
    bc_type) t and c: the end knots k+1-fold (not-a-knot: N control points; derivative
    conditions: N + k - 1), periodic knots continued by the other end's spacings.
The same curve on the points' interval either way.

With --tile, the points are solved in tiles with halos (equal to the global solve within
rounding), in either form and any degree 1..7 (the scipy form: open ends; even degrees with
not-a-knot ends only, since on knots at the data their solve does not decay); with --tile, a
.npy IN and --control, the solve streams: tiles are read from IN and written to OUT one
after the other, so any N runs in the memory of a few tiles. A long solve shows a progress
bar on stderr when it is a terminal (never in pipes).";

const SURFACE_ABOUT: &str = "\
A bicubic B-spline surface through a grid of points or heights (spec/bspline-interpolation.md
§3).

IN is either
  - points: a CSV file of R*C rows of d coordinates (x,y,z), row-major (--rows, --cols), or a
    .npy array of shape (R, C, d) (or (R*C, d) with --rows/--cols);
  - heights (--heights): a CSV matrix of R lines of C numbers, or a .npy array of shape (R, C):
    z[i][j] is the height at x = X0 + i*DX, y = Y0 + j*DY (row i along x, column j along y).

OUT by extension: .json (the model; a height field has 1-D net points [z] and knots in x and
y), .csv or .npy (a K×L grid of points uniform over the parameter domain, row-major; columns
x,y,z for heights; .npy shape (K, L, columns)), .obj (the K×L grid triangulated, with normals
for 3-D points and heights), .svg (a wireframe, or for heights a shaded height map with
contour lines). Default: the JSON model on standard output.

With --tile, a grid of points is solved in square blocks of N×N points with halos, in
parallel (equal to the global solve within rounding; natural, clamped, bessel, not-a-knot or
outer ends, since periodic and repeat couple the whole grid). A long solve shows a progress
bar on stderr when it is a terminal (never in pipes).";

/// End conditions of an open interpolating curve (or of a surface's grid lines).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EndArg {
    /// The paper's repeated end points (uniform parameters only).
    Repeat,
    /// Zero second derivative at both ends.
    Natural,
    /// Given first derivatives (--start-tangent, --end-tangent), zero by default (SciPy's
    /// "clamped").
    Clamped,
    /// First derivatives estimated from the parabola through the three end points (Bessel).
    Bessel,
    /// Continuous third derivative at the second and next-to-last points.
    NotAKnot,
    /// A closed C2 curve (a last point equal to the first is dropped).
    Periodic,
    /// The paper's outer points: one extra control point beyond each end (--offset).
    Outer,
}

/// What `eval --extrapolate` does beyond a B-spline curve's domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExtrapolateArg {
    /// Parameters beyond the domain are an error.
    None,
    /// The end polynomials continued (SciPy's extrapolate=True).
    Extend,
    /// Wrapped into the domain (SciPy's extrapolate='periodic').
    Periodic,
}

/// The representation of an interpolating curve (`--form`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FormArg {
    /// The paper's: three knots beyond each end, N+2 control points (cubics).
    Extended,
    /// SciPy's make_interp_spline: the end knots k+1-fold, its knots and coefficients.
    Scipy,
}

/// The condition at one end of a curve (`--left`, `--right`).
#[derive(Debug, Clone, PartialEq)]
pub struct EndSpecArg {
    /// The condition.
    pub spec: geomkit::bspline::EndSpec,
    /// The first negative derivative order given, if any: refused where the end's x is
    /// known, in SciPy's words ("Bad boundary conditions at X").
    pub negative_order: Option<i64>,
}

/// Parses `not-a-knot`, `natural`, `clamped`, `bessel` or `ORDER:VALUE[;ORDER:VALUE...]`.
pub fn parse_end_spec(s: &str) -> Result<EndSpecArg, String> {
    use geomkit::bspline::EndSpec;
    let t = s.trim();
    let named = |spec| EndSpecArg {
        spec,
        negative_order: None,
    };
    Ok(match t {
        "not-a-knot" | "none" => named(EndSpec::NotAKnot),
        "natural" => named(EndSpec::natural()),
        "clamped" => named(EndSpec::clamped()),
        "bessel" => named(EndSpec::Bessel),
        _ => {
            let mut negative_order = None;
            let mut list = Vec::new();
            for d in t.split([';', '+']) {
                let (order, value) = d.split_once(':').ok_or_else(|| {
                    format!(
                        "'{d}' is not an end condition: expected not-a-knot, natural, clamped, \
                         bessel or ORDER:VALUE (e.g. 1:0.5,2 or 2:0)"
                    )
                })?;
                let order = order
                    .trim()
                    .parse::<i64>()
                    .map_err(|_| format!("'{order}' is not a derivative order (0, 1, 2, ...)"))?;
                let value = parse_vector(value)?.0;
                match usize::try_from(order) {
                    Ok(o) => list.push((o, value)),
                    Err(_) => {
                        negative_order.get_or_insert(order);
                    }
                }
            }
            EndSpecArg {
                spec: EndSpec::Derivatives(list),
                negative_order,
            }
        }
    })
}

/// How parameters are assigned to the reference points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ParamArg {
    /// Equally spaced (the paper).
    Uniform,
    /// Spaced like the distances between consecutive points.
    Chord,
    /// Spaced like the square roots of those distances.
    Centripetal,
}

/// A vector given on the command line as "x,y[,z...]".
#[derive(Debug, Clone, PartialEq)]
pub struct Vector(pub Vec<f64>);

fn parse_vector(s: &str) -> Result<Vector, String> {
    s.split(',')
        .map(|x| match x.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("'{}' is not a finite number", x.trim())),
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Vector)
}

/// Sample counts: `K` (curves; K×K for surfaces) or `KxL` (surfaces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Samples(pub usize, pub Option<usize>);

impl std::fmt::Display for Samples {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.1 {
            None => write!(f, "{}", self.0),
            Some(l) => write!(f, "{}x{l}", self.0),
        }
    }
}

/// An OBJ normal layout by name (`--obj-normals`).
pub fn parse_obj_normals(s: &str) -> Result<geomkit::mesh::ObjNormals, String> {
    geomkit::mesh::ObjNormals::from_name(s.trim()).ok_or_else(|| {
        format!("unknown OBJ normals {s:?}: expected auto, indexed, per-vertex or none")
    })
}

/// Parses `K` or `KxL` sample counts.
pub fn parse_samples(s: &str) -> Result<Samples, String> {
    let parse = |x: &str| {
        x.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{x}' is not a sample count (a positive integer)"))
    };
    match s.split_once(['x', 'X', ',']) {
        None => Ok(Samples(parse(s)?, None)),
        Some((a, b)) => Ok(Samples(parse(a)?, Some(parse(b)?))),
    }
}

/// Derivative orders of `eval --nu`: `N` (curves) or `DU,DV` (surfaces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Orders(pub usize, pub Option<usize>);

/// Parses `N` or `DU,DV` derivative orders.
pub fn parse_orders(s: &str) -> Result<Orders, String> {
    let parse = |x: &str| {
        x.trim()
            .parse::<usize>()
            .map_err(|_| format!("'{x}' is not a derivative order (0, 1, 2, ...)"))
    };
    match s.split_once(',') {
        None => Ok(Orders(parse(s)?, None)),
        Some((a, b)) => Ok(Orders(parse(a)?, Some(parse(b)?))),
    }
}

/// Arguments of `interpolate curve`.
#[derive(Debug, Args)]
pub struct CurveArgs {
    /// Reference points: CSV (one point per line) or .npy of shape (N, d).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// End condition.
    #[arg(long, value_enum, default_value = "not-a-knot")]
    pub end: EndArg,
    /// Parametrization [default: chord; uniform with --end repeat].
    #[arg(long, value_enum)]
    pub param: Option<ParamArg>,
    /// Given parameters instead: a CSV or .npy with one strictly increasing value per point
    /// (periodic: optionally one more, closing the curve), like SciPy's make_interp_spline(x, y).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["param", "tile"])]
    pub params: Option<PathBuf>,
    /// With --end outer: the extra points lie F times the end interval beyond the end points
    /// [default: 1].
    #[arg(long, value_name = "F")]
    pub offset: Option<f64>,
    /// With --end clamped: the derivative dc/dt at the start ("x,y"); default: zero.
    #[arg(long, value_name = "X,Y,..", value_parser = parse_vector, allow_hyphen_values = true)]
    pub start_tangent: Option<Vector>,
    /// With --end clamped: the derivative dc/dt at the end ("x,y"); default: zero.
    #[arg(long, value_name = "X,Y,..", value_parser = parse_vector, allow_hyphen_values = true)]
    pub end_tangent: Option<Vector>,
    /// Degree k, 0 (steps) to 7 (SciPy's make_interp_spline k) [default: 3].
    #[arg(long, value_name = "K")]
    pub degree: Option<usize>,
    /// Condition at the first point, overriding --end there (SciPy's bc_type[0]): not-a-knot
    /// (none), natural, clamped, bessel, or derivatives "ORDER:VALUE[;ORDER:VALUE...]" with a
    /// VALUE per coordinate ("1:0.5,2" is dc/dt = (0.5, 2); one number is for every
    /// coordinate).
    #[arg(long, value_name = "COND", value_parser = parse_end_spec, allow_hyphen_values = true)]
    pub left: Option<EndSpecArg>,
    /// Condition at the last point, overriding --end there (SciPy's bc_type[1]); as --left.
    #[arg(long, value_name = "COND", value_parser = parse_end_spec, allow_hyphen_values = true)]
    pub right: Option<EndSpecArg>,
    /// Knots (SciPy's t) instead of the default placement: a CSV or .npy with one
    /// non-decreasing value per line, at least N + K + 1 of them (the scipy form).
    #[arg(long, value_name = "FILE", conflicts_with = "tile")]
    pub knots: Option<PathBuf>,
    /// Representation: extended (the paper's: three knots beyond each end, N+2 control
    /// points; cubics) or scipy (SciPy's make_interp_spline: end knots k+1-fold, N control
    /// points for not-a-knot) [default: extended for cubics with one --end, else scipy].
    #[arg(long, value_enum)]
    pub form: Option<FormArg>,
    /// Output file: .json, .csv, .npy or .svg; default: the JSON model to stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Points sampled for a .csv/.npy OUT, at least 2 [default: 1001].
    #[arg(long, value_name = "K")]
    pub samples: Option<usize>,
    /// Write the control points to a .csv/.npy OUT = NAME.EXT (and the knots to
    /// NAME.knots.EXT) instead of samples.
    #[arg(long)]
    pub control: bool,
    /// Solve in tiles of N points (with halos; streams a .npy IN to a --control .npy/.csv OUT).
    #[arg(long, value_name = "N")]
    pub tile: Option<usize>,
    /// With --tile: points solved on each side of a tile and discarded [default: 32; the
    /// scipy form at least 64].
    #[arg(long, value_name = "H", requires = "tile")]
    pub halo: Option<usize>,
}

/// Arguments of `interpolate surface`.
#[derive(Debug, Args)]
pub struct SurfaceArgs {
    /// Reference grid: CSV or .npy (see above).
    #[arg(value_name = "IN")]
    pub input: PathBuf,
    /// Grid rows R (points input).
    #[arg(long, value_name = "R")]
    pub rows: Option<usize>,
    /// Grid columns C (points input).
    #[arg(long, value_name = "C")]
    pub cols: Option<usize>,
    /// IN is a matrix of heights z[i][j] over a regular grid.
    #[arg(long, conflicts_with_all = ["rows", "cols"])]
    pub heights: bool,
    /// With --heights: grid spacing along x (rows) [default: 1].
    #[arg(
        long,
        value_name = "DX",
        requires = "heights",
        allow_negative_numbers = true
    )]
    pub dx: Option<f64>,
    /// With --heights: grid spacing along y (columns) [default: 1].
    #[arg(
        long,
        value_name = "DY",
        requires = "heights",
        allow_negative_numbers = true
    )]
    pub dy: Option<f64>,
    /// With --heights: x of row 0 [default: 0].
    #[arg(
        long,
        value_name = "X0",
        requires = "heights",
        allow_negative_numbers = true
    )]
    pub x0: Option<f64>,
    /// With --heights: y of column 0 [default: 0].
    #[arg(
        long,
        value_name = "Y0",
        requires = "heights",
        allow_negative_numbers = true
    )]
    pub y0: Option<f64>,
    /// With --heights: the x of the rows (CSV or .npy, one strictly increasing value per
    /// line) instead of --x0/--dx: any rectilinear grid (SciPy's RectBivariateSpline(x, y, z)).
    #[arg(long, value_name = "FILE", requires = "heights", conflicts_with_all = ["x0", "dx"])]
    pub x: Option<PathBuf>,
    /// With --heights: the y of the columns instead of --y0/--dy.
    #[arg(long, value_name = "FILE", requires = "heights", conflicts_with_all = ["y0", "dy"])]
    pub y: Option<PathBuf>,
    /// With --heights: degrees K (both directions) or KX,KY, 1 to 7, in SciPy's form
    /// (RectBivariateSpline(kx, ky, s=0): FITPACK's knots, not-a-knot ends) [default: 3].
    #[arg(long, value_name = "K[,L]", value_parser = parse_degrees, requires = "heights")]
    pub degree: Option<Degrees>,
    /// Representation: extended (the paper's bicubic, three knots beyond each end) or scipy
    /// (RectBivariateSpline's knots and coefficients; heights) [default: extended for the
    /// bicubic, scipy with --degree].
    #[arg(long, value_enum)]
    pub form: Option<FormArg>,
    /// End condition in both directions (--end-u / --end-v override one).
    #[arg(long, value_enum, default_value = "not-a-knot")]
    pub end: EndArg,
    /// End condition across the rows (along u, the first grid index).
    #[arg(long, value_enum, value_name = "END", conflicts_with = "heights")]
    pub end_u: Option<EndArg>,
    /// End condition along the rows (along v, the second grid index).
    #[arg(long, value_enum, value_name = "END", conflicts_with = "heights")]
    pub end_v: Option<EndArg>,
    /// Parametrization [default: chord; uniform with --end repeat]; heights are uniform.
    #[arg(long, value_enum, conflicts_with = "heights")]
    pub param: Option<ParamArg>,
    /// With --end outer: offset of the outer points, as a fraction of the end interval
    /// [default: 1].
    #[arg(long, value_name = "F")]
    pub offset: Option<f64>,
    /// Output file: .json, .csv, .npy, .obj or .svg; default: the JSON model to stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// Sample grid for .csv/.npy/.obj/.svg output: K×L points (K or KxL) [default: 101x101].
    #[arg(long, value_name = "KxL", value_parser = parse_samples)]
    pub samples: Option<Samples>,
    /// Solve in square blocks of N×N grid points (with halos, in parallel; points input).
    #[arg(long, value_name = "N", conflicts_with = "heights")]
    pub tile: Option<usize>,
    /// With --tile: grid lines solved on each side of a block and discarded [default: 32].
    #[arg(long, value_name = "H", requires = "tile")]
    pub halo: Option<usize>,
}

/// Arguments of `eval`.
#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("where").required(true).args(["samples", "at"])))]
pub struct ModelEvalArgs {
    /// The model: JSON (any type), or control points .csv/.npy with their .knots sibling.
    #[arg(value_name = "MODEL")]
    pub model: PathBuf,
    /// Uniform samples of the domain: K for curves, K or KxL for surfaces (at least 2 each).
    #[arg(long, value_name = "K[xL]", value_parser = parse_samples)]
    pub samples: Option<Samples>,
    /// Parameters to evaluate at: CSV or .npy with 1 column (t) for curves, 2 (u,v) for
    /// surfaces.
    #[arg(long, value_name = "PARAMS")]
    pub at: Option<PathBuf>,
    /// B-spline curves: the derivative of order NU instead of the point (SciPy's
    /// BSpline(t, nu); zero above the degree). B-spline surfaces: DU,DV, the partial
    /// derivative d^(DU+DV) S / du^DU dv^DV (RectBivariateSpline's dx, dy: each below the
    /// degree in its direction) [default: 0].
    #[arg(long, value_name = "NU|DU,DV", value_parser = parse_orders)]
    pub nu: Option<Orders>,
    /// B-spline curves: parameters beyond the domain: none (refused, the default), extend
    /// (the end polynomials continued: SciPy's extrapolate=True) or periodic (wrapped into
    /// the domain: extrapolate='periodic').
    #[arg(long, value_enum, value_name = "MODE")]
    pub extrapolate: Option<ExtrapolateArg>,
    /// Output: .csv (default: stdout) or .npy; one row per point, the parameter(s) then the
    /// coordinates (t,x,y,... or u,v,x,y,z,...).
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
        assert_eq!(parse_samples("12"), Ok(Samples(12, None)));
        assert_eq!(parse_samples("3x4"), Ok(Samples(3, Some(4))));
        assert!(parse_samples("3xa").is_err());
        assert_eq!(parse_vector("1,-2.5"), Ok(Vector(vec![1.0, -2.5])));
        assert!(parse_vector("1,nan").is_err());
        use geomkit::bspline::EndSpec;
        assert_eq!(parse_end_spec("natural").unwrap().spec, EndSpec::natural());
        assert_eq!(
            parse_end_spec("1:0.5,-2;2:0").unwrap().spec,
            EndSpec::Derivatives(vec![(1, vec![0.5, -2.0]), (2, vec![0.0])])
        );
        assert_eq!(parse_end_spec("1:0;-6:0").unwrap().negative_order, Some(-6));
        assert!(parse_end_spec("1=0").unwrap_err().contains("ORDER:VALUE"));
        assert!(parse_end_spec("x:0")
            .unwrap_err()
            .contains("derivative order"));
    }

    #[test]
    fn clap_definition_is_valid() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
