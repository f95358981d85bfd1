//! Arguments of `geomkit compose`.

use clap::{Args, Subcommand, ValueEnum};
use geomkit::expr::Format;
use std::path::PathBuf;

/// `geomkit compose ...`
#[derive(Debug, Subcommand)]
pub enum ComposeCommand {
    /// A closed body as one formula (the paper's cube, and box, pyramid, cone, cylinder,
    /// prism, frustum): formula text, or OUT .json (formulas and model), a watertight mesh
    /// (.obj, .stl, .ply, .glb) or a shaded picture (.png, .svg).
    Body(BodyArgs),
    /// A composite surface of patches (SCENE.json) as one formula (9)/(11), with its
    /// continuity report: formula text, or OUT like `compose body`.
    ///
    /// Limits: knots finite and increasing, spanning at most f64::MAX/2 (8.99e307) in each
    /// direction, every interval at least 2.2e-308 (the smallest normal f64) wide. A scene
    /// whose patch coefficients, jumps between patches, or formula terms overflow f64 (control
    /// points near ±1.8e308) is refused with the patch named: the formula never holds a
    /// number that is not finite, nor a nonzero one below 2.2e-308 (values near 1e-300 over
    /// knots near 1e300). A patch given as a formula must be finite on its cell (sampled on
    /// a 9×9 grid); one with sqrt, ln, asin, acos, tan or a division gets its arguments
    /// clamped with sign() so that they stay in its cell in floating point too.
    Patches(PatchesArgs),
    /// A piecewise-ruled surface over curves (CURVES.json) as one formula (2), with its
    /// consistency checks: formula text, or OUT like `compose body`.
    ///
    /// Limits: v values and the u range finite and increasing, spanning at most f64::MAX/2;
    /// curve coordinates at most f64::MAX/2 (8.99e307) in absolute value; a formula whose
    /// coefficients or terms overflow f64, or whose nonzero coefficients fall below
    /// 2.2e-308, is refused with the coordinate named.
    Ruled(RuledArgs),
    /// A piecewise function, composite curve or saved B-spline curve (PIECES.json) as one
    /// formula (spec §5), with the continuity report at its breakpoints; OUT .svg plots it.
    ///
    /// Convention (the paper's formula, which the printed formula and `geomkit eval` follow
    /// alike): F = f_0 on [x_0, x_1] and, on each later [x_i, x_(i+1)], f_i plus the jumps at
    /// the breakpoints before it. So F is continuous and has one value at every breakpoint
    /// (both neighbours give it; where the pieces jump, the report says so and the later
    /// pieces are shifted to stay attached: the formula does not reproduce a jump). Beyond
    /// the knots F is constant: F(x_0) to the left, F(x_n) to the right.
    ///
    /// Each piece is evaluated on its own closed interval only (its argument is clamped
    /// there). Pieces with sqrt, ln, asin, acos, tan or a division get that clamp written
    /// with sign(), so that it holds in floating point too (a rounding an ulp outside would
    /// make sqrt(x) on [0, 1] NaN for every x). A piece must be finite at both ends of its
    /// interval (its value there enters the formula at every x); a piece that is not
    /// finite inside its interval (at one of 7 samples) gives a `warning:` line: the
    /// formula is not finite there either, and only there.
    ///
    /// Limits: knots finite and increasing, spanning at most f64::MAX/2 (8.99e307), every
    /// interval at least 2.2e-308 wide. Refused with the piece named: polyline points whose
    /// differences overflow, and a formula whose coefficients or terms overflow f64 (on the
    /// knots' interval widened by its span) or whose nonzero coefficients fall below
    /// 2.2e-308 (values near 1e-300 over knots near 1e300).
    Piecewise(PiecewiseArgs),
}

/// The bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BodyKind {
    /// The paper's cube with vertices (±1, ±1, ±1).
    Cube,
    /// A box of sizes --size A,B,C centred at the origin.
    Box,
    /// A pyramid of height --height over a square of side --side (or a regular --ngon of
    /// circumradius --radius).
    Pyramid,
    /// A cone of base --radius and --height, base included.
    Cone,
    /// A cylinder of --radius and --height with both caps.
    Cylinder,
    /// A prism of --height over a regular --ngon of circumradius --radius (or --polygon).
    Prism,
    /// A frustum of bottom --radius, top --top-radius and --height with both caps.
    Frustum,
}

/// Arguments of `compose body`.
#[derive(Debug, Args)]
pub struct BodyArgs {
    /// Which body.
    #[arg(value_enum)]
    pub body: BodyKind,
    /// Box sizes A,B,C, each finite, > 0 and at most 1e100 [default: 2,2,2].
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true, value_parser = parse_box_size)]
    pub size: Option<[f64; 3]>,
    /// Height, finite, > 0 and at most 1e100 [default: 2].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub height: Option<f64>,
    /// Radius (circumradius of a regular polygon), finite, > 0 and at most 1e100 [default: 1].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Top radius of a frustum, finite, > 0 and at most 1e100 [default: radius/2].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub top_radius: Option<f64>,
    /// Base side of a square pyramid, finite, > 0 and at most 1e100 [default: 2].
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub side: Option<f64>,
    /// Regular polygon with N vertices (3 to 10000) as the base of a prism or pyramid.
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u64).range(3..=10_000)
    )]
    pub ngon: Option<u64>,
    /// Polygon "x,y;x,y;..." as the base of a prism or pyramid: 3 to 10000 vertices, simple,
    /// star-shaped about its centroid, coordinates at most 1e100 in absolute value.
    #[arg(
        long,
        value_name = "X,Y;...",
        allow_hyphen_values = true,
        conflicts_with = "ngon",
        value_parser = parse_polygon
    )]
    pub polygon: Option<Polygon>,
    /// Output options.
    #[command(flatten)]
    pub out: SurfaceOutput,
}

/// Arguments of `compose patches`.
#[derive(Debug, Args)]
pub struct PatchesArgs {
    /// The scene (JSON), or a saved B-spline surface ({"type":"bspline_surface",...}, e.g.
    /// from `geomkit interpolate surface -o fit.json`: one patch per knot cell).
    /// Formulas: exact constants of up to 4096 bits (longer ones become their nearest f64,
    /// those beyond the range of f64 are an error), at most 200 nested levels.
    pub scene: PathBuf,
    /// Print the continuity report as JSON {"max_jump":..,"jumps":[..]} instead of the formula.
    #[arg(long)]
    pub report_json: bool,
    /// Output options, as for `compose body`.
    #[command(flatten)]
    pub out: SurfaceOutput,
}

/// Arguments of `compose ruled`.
#[derive(Debug, Args)]
pub struct RuledArgs {
    /// The curves (JSON): {"type":"ruled","curves":[C,...],"v":[...],"u":[u0,u1]} with C
    /// {"x":"expr","y":"expr","z":"expr","t":[t0,t1]} (formulas in t), {"point":[x,y,z]},
    /// {"polygon":[[x,y,z],...]}, {"polyline":[[x,y,z],...]} or
    /// {"circle":{"center":[x,y,z],"radius":r}}; "u" defaults to [0,1].
    /// Formulas: exact constants of up to 4096 bits (longer ones become their nearest f64,
    /// those beyond the range of f64 are an error), at most 200 nested levels.
    pub curves: PathBuf,
    /// Output options, as for `compose body`.
    #[command(flatten)]
    pub out: SurfaceOutput,
}

/// Arguments of `compose piecewise`.
#[derive(Debug, Args)]
pub struct PiecewiseArgs {
    /// The pieces (JSON): {"type":"piecewise","knots":[x0,...,xn],"pieces":["f0(x)",...]}
    /// for a function, pieces {"x":"expr","y":"expr"[,"z":..][,"domain":[t0,t1]]} in t
    /// for a composite curve, {"type":"polyline"|"polygon","points":[[x,y],...]
    /// [,"knots":[...]]}, or a saved B-spline curve ({"type":"bspline_curve",...}, e.g. from
    /// `geomkit interpolate curve -o fit.json`: one polynomial piece per knot span).
    /// Formulas: exact constants of up to 4096 bits (longer ones become their nearest f64,
    /// those beyond the range of f64 are an error), at most 200 nested levels.
    pub pieces: PathBuf,
    /// Print the continuity report as JSON instead of the formula.
    #[arg(long)]
    pub report_json: bool,
    /// Output options: OUT .json (formula in every syntax and the report), .svg (a plot of
    /// the function or the curve), .txt (the formula).
    #[command(flatten)]
    pub out: FormulaOutput,
}

/// Formula syntax and output file of every `compose` command.
#[derive(Debug, Args)]
pub struct FormulaOutput {
    /// Syntax of the formula. A printed formula is at most 256 MiB (inline, shared
    /// subexpressions are repeated: --program prints each once).
    #[arg(long, value_name = "F", default_value = "maple", value_parser = parse_format)]
    pub format: Format,
    /// Print with common subexpressions in temporaries.
    #[arg(long)]
    pub program: bool,
    /// Output file, its format by its extension (see the command's help); default: the
    /// formula on stdout.
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
}

/// Output options of the surface commands (`compose body`, `ruled`, `patches`): OUT .json
/// (the formula in every syntax and the model, which `geomkit mesh`, `render` and `eval`
/// read back), a watertight mesh where the surface is closed (.obj, .stl, .ply, .glb, as
/// `geomkit mesh` writes them), a shaded picture (.png, .svg) or .txt (the formula).
#[derive(Debug, Args)]
pub struct SurfaceOutput {
    /// Formula syntax and output file.
    #[command(flatten)]
    pub formula: FormulaOutput,
    /// A mesh on a uniform KxL sample grid (break lines added; at most 2000000 triangles)
    /// [default: adaptive, per axis within 1/1000 of the model's extent along it, at most
    /// 2000000 triangles]. A mesh that would be empty or, for a closed body, not watertight
    /// (a model too thin or too small for f64 at its own size) is an error.
    #[arg(long, value_name = "KxL", value_parser = parse_grid)]
    pub samples: Option<(usize, usize)>,
    /// Normals in OBJ output, as for `geomkit mesh`: auto, indexed, per-vertex or none.
    #[arg(long, value_name = "LAYOUT", default_value = "auto", value_parser = super::parse_obj_normals)]
    pub obj_normals: geomkit::mesh::ObjNormals,
}

/// The vertices of a `--polygon` (a type of its own: clap takes a `Vec` for a repeated
/// option).
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon(pub Vec<[f64; 2]>);

/// A formula syntax by name ("maple", "latex", ...).
pub fn parse_format(name: &str) -> Result<Format, String> {
    Format::from_name(name).ok_or_else(|| {
        format!(
            "unknown --format {name:?}: expected one of {}",
            Format::ALL.map(Format::name).join(", ")
        )
    })
}

/// "KxL" (or "K") → (K, L), each from 2 to 4000.
fn parse_grid(text: &str) -> Result<(usize, usize), String> {
    let parse = |x: &str| match x.trim().parse::<usize>() {
        Ok(k) if (2..=4000).contains(&k) => Ok(k),
        _ => Err(format!("{x:?} is not a count from 2 to 4000")),
    };
    match text.split_once(['x', 'X', ',']) {
        None => Ok((parse(text)?, parse(text)?)),
        Some((a, b)) => Ok((parse(a)?, parse(b)?)),
    }
}

/// Finite numbers separated by commas.
fn finite_numbers(text: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|x| match x.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("{:?} is not a finite number", x.trim())),
        })
        .collect()
}

/// "A,B,C": three finite sizes (their signs are the body's to judge).
fn parse_box_size(text: &str) -> Result<[f64; 3], String> {
    match finite_numbers(text)?[..] {
        [a, b, c] => Ok([a, b, c]),
        ref s => Err(format!("give three sizes A,B,C (got {})", s.len())),
    }
}

/// "x,y;x,y;...": the vertices of a polygon.
fn parse_polygon(text: &str) -> Result<Polygon, String> {
    text.split(';')
        .enumerate()
        .map(
            |(k, xy)| match finite_numbers(xy).map_err(|e| format!("vertex {k}: {e}"))?[..] {
                [x, y] => Ok([x, y]),
                _ => Err(format!("vertex {k}: give x,y")),
            },
        )
        .collect::<Result<_, _>>()
        .map(Polygon)
}
