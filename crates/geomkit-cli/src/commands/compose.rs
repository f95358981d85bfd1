//! `geomkit compose`: single analytic formulas of spec/composite-surfaces.md — closed bodies
//! ruled over contours (formula (2)) and composite surfaces of patches (formulas (3)-(11)),
//! printed in eleven syntaxes, or drawn / meshed by the structural evaluator.
//!
//! Scene files (JSON):
//! - `{"type":"composite_surface","u_knots":[...],"v_knots":[...],"patches":[[P,...],...]}`,
//!   `patches[i][j]` on cell [u_i, u_(i+1)] × [v_j, v_(j+1)], P = `{"bezier":[[[x,y,z],...],...]}`
//!   (its [0, 1]² mapped onto the cell);
//! - `{"type":"composite_explicit","x_knots":[...],"y_knots":[...],"patches":[...]}` with
//!   1-D Bézier nets `{"bezier":[[[z],...],...]}`, formulas `"expr in x, y"` or
//!   `{"z":"expr","domain":[[x0,x1],[y0,y1]]}`;
//! - parametric patches may also be formulas `{"x":"expr","y":"expr","z":"expr"}` in u, v,
//!   optionally with `"domain":[[u0,u1],[v0,v1]]` mapped linearly onto the cell;
//! - a saved B-spline surface `{"type":"bspline_surface",...}` (e.g. from `geomkit interpolate
//!   surface -o fit.json`): its knot cells as polynomial patches, explicit z(x, y) for heights.

use super::mesh::{mesh_summary, write_mesh};
use crate::figures::{linspace, surface_svg, GridEval, Layer, SurfaceView};
use crate::output::{Destination, RowSink, TableFormat};
use crate::progress::Progress;
use crate::render::shape::{picture_svg, tessellate, Loaded, PictureOptions, Sampling, Shape};
use crate::render::svg_to_png;
use crate::svg::palette;
use crate::table::{extension, Table};
use anyhow::{anyhow, bail, Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use geomkit::bezier::BezierSurface;
use geomkit::compose::{
    bodies, CompositeSurface, ExprPatch, Formula, GridLine, PolyPatch, RuledCurve, RuledSurface,
    SurfaceKind,
};
use geomkit::expr::Format;
use geomkit::geom::Surface;
use serde_json::{json, Map, Value};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `geomkit compose ...`
#[derive(Debug, Subcommand)]
pub enum ComposeCommand {
    /// A closed body as one formula (the paper's cube, and box, pyramid, cone, cylinder,
    /// prism, frustum): formula text, or OUT .json (formulas and model), a watertight mesh
    /// (.obj, .stl, .ply, .glb) or a shaded picture (.png, .svg).
    Body(BodyArgs),
    /// A composite surface of patches (SCENE.json) as one formula (9)/(11), with its
    /// continuity report: formula text, or OUT like `compose body`.
    Patches(PatchesArgs),
    /// A piecewise-ruled surface over curves (CURVES.json) as one formula (2), with its
    /// consistency checks: formula text, or OUT like `compose body`.
    Ruled(RuledArgs),
    /// A piecewise function, composite curve or saved B-spline curve (PIECES.json) as one
    /// formula (spec §5), with the continuity report at its breakpoints; OUT .svg plots it.
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
    /// Box sizes A,B,C [default: 2,2,2].
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true)]
    pub size: Option<String>,
    /// Height [default: 2].
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    pub height: Option<f64>,
    /// Radius (circumradius of a regular polygon) [default: 1].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub radius: Option<f64>,
    /// Top radius of a frustum [default: radius/2].
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub top_radius: Option<f64>,
    /// Base side of a square pyramid [default: 2].
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub side: Option<f64>,
    /// Regular polygon with N vertices as the base of a prism or pyramid.
    #[arg(long, value_name = "N")]
    pub ngon: Option<usize>,
    /// Polygon "x,y;x,y;..." as the base of a prism or pyramid.
    #[arg(
        long,
        value_name = "X,Y;...",
        allow_hyphen_values = true,
        conflicts_with = "ngon"
    )]
    pub polygon: Option<String>,
    /// Output options.
    #[command(flatten)]
    pub out: SurfaceOutput,
}

/// Arguments of `compose patches`.
#[derive(Debug, Args)]
pub struct PatchesArgs {
    /// The scene (JSON), or a saved B-spline surface ({"type":"bspline_surface",...}, e.g.
    /// from `geomkit interpolate surface -o fit.json`: one patch per knot cell).
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
    /// Syntax of the formula.
    #[arg(long, value_name = "F", default_value = "maple")]
    pub format: String,
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
    /// A mesh on a uniform KxL sample grid (break lines added) [default: adaptive, within
    /// 1/1000 of the size].
    #[arg(long, value_name = "KxL")]
    pub samples: Option<String>,
}

/// Runs `geomkit compose ...`.
pub fn run(command: ComposeCommand) -> Result<()> {
    match command {
        ComposeCommand::Body(args) => run_body(args),
        ComposeCommand::Patches(args) => run_patches(args),
        ComposeCommand::Ruled(args) => run_ruled(args),
        ComposeCommand::Piecewise(args) => super::piecewise::run(args),
    }
}

pub fn format_of(name: &str) -> Result<Format> {
    Format::from_name(name).ok_or_else(|| {
        anyhow!(
            "unknown --format {name:?}: expected one of {}",
            Format::ALL.map(Format::name).join(", ")
        )
    })
}

/// "KxL" (or "K") → (K, L), each from 2 to 4000.
pub fn samples_of(text: &str) -> Result<(usize, usize)> {
    let parse = |x: &str| -> Result<usize> {
        match x.trim().parse::<usize>() {
            Ok(k) if (2..=4000).contains(&k) => Ok(k),
            _ => bail!("--samples: {x:?} is not a count from 2 to 4000"),
        }
    };
    match text.split_once(['x', 'X', ',']) {
        None => Ok((parse(text)?, parse(text)?)),
        Some((a, b)) => Ok((parse(a)?, parse(b)?)),
    }
}

fn numbers(text: &str, what: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|x| match x.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => bail!("{what}: {:?} is not a finite number", x.trim()),
        })
        .collect()
}

fn polygon_of(args: &BodyArgs) -> Result<Vec<[f64; 2]>> {
    if let Some(p) = &args.polygon {
        return p
            .split(';')
            .enumerate()
            .map(
                |(k, xy)| match numbers(xy, &format!("--polygon vertex {k}"))?.as_slice() {
                    [x, y] => Ok([*x, *y]),
                    _ => bail!("--polygon vertex {k}: give x,y"),
                },
            )
            .collect();
    }
    Ok(bodies::regular_polygon(
        args.ngon.unwrap_or(6),
        args.radius.unwrap_or(1.0),
    )?)
}

/// The body of `args` and a description.
pub fn build_body(args: &BodyArgs) -> Result<(RuledSurface, String)> {
    let h = args.height.unwrap_or(2.0);
    let r = args.radius.unwrap_or(1.0);
    Ok(match args.body {
        BodyKind::Cube => (bodies::cube()?, "the paper's cube (±1, ±1, ±1)".into()),
        BodyKind::Box => {
            let s = numbers(args.size.as_deref().unwrap_or("2,2,2"), "--size")?;
            let [a, b, c] = s[..] else {
                bail!("--size: give three sizes A,B,C (got {})", s.len())
            };
            (
                bodies::rectangular_box(a, b, c)?,
                format!("box {a}×{b}×{c}"),
            )
        }
        BodyKind::Pyramid => {
            if args.ngon.is_some() || args.polygon.is_some() {
                (
                    bodies::pyramid(&polygon_of(args)?, h)?,
                    format!("pyramid of height {h}"),
                )
            } else {
                let a = args.side.unwrap_or(2.0);
                (
                    bodies::square_pyramid(a, h)?,
                    format!("square pyramid, side {a}, height {h}"),
                )
            }
        }
        BodyKind::Cone => (bodies::cone(r, h)?, format!("cone, radius {r}, height {h}")),
        BodyKind::Cylinder => (
            bodies::cylinder(r, h)?,
            format!("cylinder with caps, radius {r}, height {h}"),
        ),
        BodyKind::Prism => (
            bodies::prism(&polygon_of(args)?, h)?,
            format!("prism of height {h}"),
        ),
        BodyKind::Frustum => {
            let r1 = args.top_radius.unwrap_or(r / 2.0);
            (
                bodies::frustum(r, r1, h)?,
                format!("frustum, radii {r} and {r1}, height {h}"),
            )
        }
    })
}

pub fn formula_text(f: &Formula, format: Format, program: bool) -> String {
    if program {
        f.print_program(format)
    } else {
        f.print(format)
    }
}

/// The formula in every syntax, with its size, as JSON.
pub fn formula_json(f: &Formula, what: &str, extra: Value) -> String {
    let mut printed = Map::new();
    for fmt in Format::ALL {
        printed.insert(fmt.name().into(), Value::String(f.print(fmt)));
    }
    let mut v = json!({
        "type": "formula",
        "what": what,
        "variables": f.vars,
        "coordinates": f.names,
        "op_count": f.op_count(),
        "formulas": printed,
    });
    if let (Value::Object(o), Value::Object(e)) = (&mut v, extra) {
        o.extend(e);
    }
    let mut s = serde_json::to_string_pretty(&v).expect("serializable");
    s.push('\n');
    s
}

/// Evaluations on a grid, for pictures and meshes (structural evaluators).
pub struct GridView<'a> {
    dim: usize,
    domain: ((f64, f64), (f64, f64)),
    grid: Box<GridEval<'a>>,
}

impl SurfaceView for GridView<'_> {
    fn view_dim(&self) -> usize {
        self.dim.max(2)
    }
    fn view_domain(&self) -> ((f64, f64), (f64, f64)) {
        self.domain
    }
    fn view_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> geomkit::Result<()> {
        if self.dim == 1 {
            // Heights z(x, y) drawn as (x, y, z).
            let mut z = vec![0.0; us.len() * vs.len()];
            (self.grid)(us, vs, &mut z)?;
            for (a, &u) in us.iter().enumerate() {
                for (b, &v) in vs.iter().enumerate() {
                    let k = a * vs.len() + b;
                    out[k * 3..k * 3 + 3].copy_from_slice(&[u, v, z[k]]);
                }
            }
            return Ok(());
        }
        (self.grid)(us, vs, out)
    }
}

pub fn ruled_view(s: &RuledSurface) -> GridView<'_> {
    GridView {
        dim: 3,
        domain: s.domain(),
        grid: Box::new(|us, vs, out| s.eval_grid(us, vs, out)),
    }
}

pub fn composite_view(s: &CompositeSurface) -> GridView<'_> {
    GridView {
        dim: s.dim(),
        domain: s.domain(),
        grid: Box::new(|us, vs, out| s.eval_grid(us, vs, out)),
    }
}

/// A wireframe picture.
pub fn picture(view: &GridView<'_>, title: &str, subtitle: &str, lines: usize) -> Result<String> {
    surface_svg(
        title,
        subtitle,
        &[Layer::Wireframe {
            surface: view,
            count: lines,
            stroke: palette::CURVE.with_opacity(0.8),
            legend: "structural evaluator".into(),
        }],
    )
}

fn run_body(args: BodyArgs) -> Result<()> {
    let (body, what) = build_body(&args)?;
    write_ruled(&body, &what, &args.out)
}

/// A ruled surface's formula, model, mesh or picture, as `out` asks.
fn write_ruled(body: &RuledSurface, what: &str, out: &SurfaceOutput) -> Result<()> {
    let f = body.formula()?;
    let model = ruled_json(body).map_or(json!({}), |m| json!({ "model": m }));
    let subtitle = formula_line(&f);
    write_surface(Box::new(body.clone()), &f, what, &subtitle, model, out)
}

/// The first line of the Maple formula, shortened to 140 characters (a picture's subtitle).
pub fn formula_line(f: &Formula) -> String {
    let first = f.print(Format::Maple);
    let line = first.lines().next().unwrap_or_default();
    if line.chars().count() > 140 {
        line.chars().take(137).collect::<String>() + "..."
    } else {
        line.to_string()
    }
}

/// Writes a surface's single formula `f` as `out` asks, by the extension of the output:
/// none or .txt the formula, .json the formula in every syntax plus `extra`, .obj/.stl/.ply/
/// .glb the mesh `geomkit mesh` writes, .png/.svg the shaded picture of `geomkit render`.
fn write_surface(
    surface: Box<dyn Surface>,
    f: &Formula,
    what: &str,
    subtitle: &str,
    extra: Value,
    out: &SurfaceOutput,
) -> Result<()> {
    let o = &out.formula;
    let format = format_of(&o.format)?;
    let dest = Destination::from_option(o.output.as_deref());
    let Some(path) = o.output.as_deref() else {
        return dest.write(formula_text(f, format, o.program).as_bytes());
    };
    let loaded = || Loaded {
        what: what.to_string(),
        shape: Shape::Surface {
            surface,
            net: None,
            references: Vec::new(),
        },
    };
    match extension(path).unwrap_or_default().as_str() {
        "txt" => dest.write(formula_text(f, format, o.program).as_bytes()),
        "json" => dest.write(formula_json(f, what, extra).as_bytes()),
        ext @ ("obj" | "stl" | "ply" | "glb") => {
            let sampling = match out.samples.as_deref() {
                Some(text) => {
                    let (k, l) = samples_of(text)?;
                    Sampling::Samples(k, l)
                }
                None => Sampling::Tolerance(None),
            };
            let t = tessellate(&loaded(), sampling)?;
            let mut buf = Vec::new();
            write_mesh(&t, ext, false, &mut buf)?;
            dest.write(&buf)?;
            let _ = writeln!(std::io::stderr(), "{}", mesh_summary(path, &t));
            Ok(())
        }
        ext @ ("png" | "svg") => {
            let svg = picture_svg(&loaded(), what, subtitle, &PictureOptions::default())?;
            if ext == "png" {
                dest.write(&svg_to_png(&svg, 2.0, None)?)
            } else {
                dest.write(svg.as_bytes())
            }
        }
        _ => bail!(
            "cannot tell the output format of {}: name it .txt, .json, .obj, .stl, .ply, .glb, \
             .png or .svg",
            path.display()
        ),
    }
}

/// A ruled surface as the JSON `compose ruled` reads (the "model" of a formula file), or
/// `None` when a curve is a formula in another variable than t.
pub fn ruled_json(s: &RuledSurface) -> Option<Value> {
    let curves = s
        .curves()
        .iter()
        .map(|c| {
            Some(match c {
                RuledCurve::Point(p) => json!({ "point": p }),
                RuledCurve::Polyline { vertices, closed } if *closed => {
                    json!({ "polygon": vertices })
                }
                RuledCurve::Polyline { vertices, .. } => json!({ "polyline": vertices }),
                RuledCurve::Circle { center, radius } => {
                    json!({ "circle": { "center": center, "radius": radius } })
                }
                RuledCurve::Expr(e) if e.vars() == ["t"] && e.texts().len() == 3 => {
                    let (t0, t1) = c.interval();
                    let t = e.texts();
                    json!({ "x": t[0], "y": t[1], "z": t[2], "t": [t0, t1] })
                }
                _ => return None,
            })
        })
        .collect::<Option<Vec<Value>>>()?;
    let ((u0, u1), _) = s.domain();
    Some(json!({ "type": "ruled", "u": [u0, u1], "v": s.v_values(), "curves": curves }))
}

/// Reads a JSON file.
pub fn read_json(path: &Path) -> Result<Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).map_err(|e| anyhow!("{}: invalid JSON: {e}", path.display()))
}

/// `[x, y, z]` points of a JSON array.
fn points3(v: &Value, place: &str) -> Result<Vec<[f64; 3]>> {
    let arr = v
        .as_array()
        .ok_or_else(|| anyhow!("{place} must be an array of points [x, y, z]"))?;
    arr.iter()
        .enumerate()
        .map(
            |(k, p)| match number_list(Some(p), &format!("{place}[{k}]"))?[..] {
                [x, y, z] => Ok([x, y, z]),
                _ => bail!("{place}[{k}] must be a point [x, y, z]"),
            },
        )
        .collect()
}

/// One curve of a ruled-surface file.
fn ruled_curve(c: &Value) -> Result<RuledCurve> {
    if let Some(p) = c.get("point") {
        return Ok(RuledCurve::Point(points3(&json!([p]), "point")?[0]));
    }
    if let Some(p) = c.get("polygon") {
        return Ok(RuledCurve::polygon(points3(p, "polygon")?)?);
    }
    if let Some(p) = c.get("polyline") {
        return Ok(RuledCurve::polyline(points3(p, "polyline")?)?);
    }
    if let Some(circle) = c.get("circle") {
        let center = points3(&json!([circle.get("center")]), "circle.center")?[0];
        let radius = circle
            .get("radius")
            .and_then(Value::as_f64)
            .ok_or_else(|| anyhow!("\"circle\" needs a numeric \"radius\""))?;
        return Ok(RuledCurve::Circle { center, radius });
    }
    let text = |n: &str| -> Result<&str> {
        match c.get(n) {
            None if n == "z" => Ok("0"),
            None => bail!("missing \"{n}\": give x, y, z as formulas in t and \"t\":[t0,t1], or \"point\", \"polygon\", \"polyline\""),
            Some(t) => t.as_str().ok_or_else(|| anyhow!("\"{n}\" must be a formula string")),
        }
    };
    let coords = [text("x")?, text("y")?, text("z")?];
    let t = match number_list(c.get("t"), "t")?[..] {
        [t0, t1] => (t0, t1),
        _ => bail!("\"t\" must be [t0, t1]"),
    };
    Ok(RuledCurve::formula(coords, t)?)
}

/// Parses a ruled-surface file (see [`RuledArgs`]).
pub fn parse_ruled(v: &Value) -> Result<RuledSurface> {
    let ty = v.get("type").and_then(Value::as_str).unwrap_or("");
    if ty != "ruled" {
        bail!("\"type\" must be \"ruled\", found {ty:?}");
    }
    let curves = v
        .get("curves")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing or non-array \"curves\""))?;
    let curves = curves
        .iter()
        .enumerate()
        .map(|(k, c)| ruled_curve(c).with_context(|| format!("curves[{k}]")))
        .collect::<Result<Vec<_>>>()?;
    let vs = number_list(v.get("v"), "v")?;
    if let Some(k) = vs.windows(2).position(|w| w[1] <= w[0]) {
        bail!(
            "\"v\" must be strictly increasing: v[{}] = {} after v[{k}] = {}",
            k + 1,
            vs[k + 1],
            vs[k]
        );
    }
    let u = match v.get("u") {
        None => (0.0, 1.0),
        Some(u) => match number_list(Some(u), "u")?[..] {
            [a, b] => (a, b),
            _ => bail!("\"u\" must be [u0, u1]"),
        },
    };
    Ok(RuledSurface::new(curves, vs, u)?)
}

/// The consistency checks of a ruled surface: which curves are closed, whether the
/// surface closes into a body, and formula (2) printed vs the structural evaluator.
pub fn ruled_report(s: &RuledSurface) -> Result<String> {
    let curves = s.curves();
    let mut open = Vec::new();
    let mut scale = 0.0f64;
    for (k, c) in curves.iter().enumerate() {
        let (t0, t1) = c.interval();
        let (a, b) = (c.eval(t0), c.eval(t1));
        scale = a.iter().chain(&b).fold(scale, |m, x| m.max(x.abs()));
        let gap = (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
        if gap > 1e-12 * scale.max(1.0) && !matches!(c, RuledCurve::Point(_)) {
            open.push(format!("{k} (gap {gap:.3e})"));
        }
    }
    let ends_are_points = matches!(curves[0], RuledCurve::Point(_))
        && matches!(curves[curves.len() - 1], RuledCurve::Point(_));
    let shape = match (open.is_empty(), ends_are_points) {
        (true, true) => "every curve closed and both ends points: a closed body".to_string(),
        (true, false) => "every curve closed: a tube, open at the first and last curve".into(),
        (false, _) => format!("open curves: {}", open.join(", ")),
    };
    let f = s.formula()?;
    let ((u0, u1), (v0, v1)) = s.domain();
    let k = 41;
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, k));
    let (pu, pv): (Vec<f64>, Vec<f64>) = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .unzip();
    let mut printed = vec![0.0; pu.len() * 3];
    f.eval_batch(&[&pu, &pv], &mut printed)?;
    let mut worst = 0.0f64;
    for (i, p) in printed.chunks_exact(3).enumerate() {
        let q = s.eval(pu[i], pv[i]);
        worst = (0..3).fold(worst, |w, c| w.max((p[c] - q[c]).abs()));
    }
    Ok(format!(
        "{} curves at v = {:?}; {shape}; formula (2) vs structural evaluator: largest \
         difference {worst:.2e} on {k}x{k} points; {} DAG operations",
        curves.len(),
        s.v_values(),
        f.op_count()
    ))
}

fn run_ruled(args: RuledArgs) -> Result<()> {
    let v = read_json(&args.curves)?;
    let s = parse_ruled(&v).with_context(|| args.curves.display().to_string())?;
    let report = ruled_report(&s)?;
    let what = format!("ruled surface over {} curves", s.curves().len());
    write_ruled(&s, &what, &args.out)?;
    let _ = writeln!(std::io::stderr(), "ruled: {report}");
    Ok(())
}

/// A surface model of `compose`: a composite scene, a ruled surface, or a formula file
/// (`compose ... -o OUT.json`) through the model it carries.
pub enum SurfaceModel {
    /// `{"type":"composite_surface"|"composite_explicit",...}`.
    Scene(CompositeSurface),
    /// `{"type":"ruled",...}`.
    Ruled(RuledSurface),
}

impl SurfaceModel {
    /// The model in a parsed JSON file, `None` when it is no `compose` surface.
    pub fn from_json(v: &Value) -> Option<Result<SurfaceModel>> {
        match v.get("type").and_then(Value::as_str)? {
            "composite_surface" | "composite_explicit" => {
                Some(parse_scene_value(v).map(SurfaceModel::Scene))
            }
            "ruled" => Some(parse_ruled(v).map(SurfaceModel::Ruled)),
            "formula" => Some(match v.get("model") {
                // The formula of `compose patches` over a saved B-spline surface: its cells.
                Some(m) if m.get("type").and_then(Value::as_str) == Some("bspline_surface") => {
                    parse_scene_value(m)
                        .map(SurfaceModel::Scene)
                        .context("model")
                }
                Some(m) => SurfaceModel::from_json(m)
                    .unwrap_or_else(|| Err(anyhow!("\"model\" is no composite or ruled surface")))
                    .context("model"),
                None => Err(anyhow!(
                    "this formula file carries no model (a formula of `compose piecewise`, \
                     or written by an older geomkit): mesh or draw the surface with \
                     `geomkit compose ... -o OUT.obj|.png`"
                )),
            }),
            _ => None,
        }
    }

    /// What it is, for messages and pictures.
    pub fn describe(&self) -> String {
        match self {
            SurfaceModel::Scene(s) => {
                let (a, b) = s.cells();
                format!("composite surface of {a}×{b} patches in R^{}", s.dim())
            }
            SurfaceModel::Ruled(s) => format!("ruled surface over {} curves", s.curves().len()),
        }
    }

    /// The surface, to mesh or draw.
    pub fn into_shape(self) -> Box<dyn Surface> {
        match self {
            SurfaceModel::Scene(s) => Box::new(s),
            SurfaceModel::Ruled(s) => Box::new(s),
        }
    }
}

/// A list of finite numbers at `place`.
pub fn number_list(v: Option<&Value>, place: &str) -> Result<Vec<f64>> {
    let arr = v
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing or non-array \"{place}\""))?;
    arr.iter()
        .enumerate()
        .map(|(k, x)| {
            x.as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| anyhow!("{place}[{k}] is not a finite number"))
        })
        .collect()
}

/// Parses a scene (see the module docs).
pub fn parse_scene(text: &str) -> Result<CompositeSurface> {
    let v: Value = serde_json::from_str(text).map_err(|e| anyhow!("invalid JSON: {e}"))?;
    parse_scene_value(&v)
}

/// [`parse_scene`] of parsed JSON.
pub fn parse_scene_value(v: &Value) -> Result<CompositeSurface> {
    let ty = v.get("type").and_then(Value::as_str).unwrap_or("");
    let (ku, kv) = match ty {
        "composite_surface" => ("u_knots", "v_knots"),
        "composite_explicit" => ("x_knots", "y_knots"),
        "bspline_surface" => {
            let obj = v.as_object().expect("a value with a \"type\" is an object");
            let m = crate::model::parse_bspline_surface(obj)?;
            return Ok(CompositeSurface::from_bspline(&m.surface)?);
        }
        other => bail!(
            "\"type\" must be \"composite_surface\", \"composite_explicit\" or \
             \"bspline_surface\", found {other:?}"
        ),
    };
    let uk = number_list(v.get(ku), ku)?;
    let vk = number_list(v.get(kv), kv)?;
    let rows = v
        .get("patches")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("missing or non-array \"patches\""))?;
    let explicit = ty == "composite_explicit";
    let mut patches: Vec<Vec<ScenePatch>> = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let row = row
            .as_array()
            .ok_or_else(|| anyhow!("patches[{i}] must be an array of patches"))?;
        let mut out = Vec::with_capacity(row.len());
        for (j, p) in row.iter().enumerate() {
            let place = format!("patches[{i}][{j}]");
            out.push(scene_patch(p, explicit).with_context(|| place)?);
        }
        patches.push(out);
    }
    let kind = if explicit {
        SurfaceKind::Explicit
    } else {
        SurfaceKind::Parametric
    };
    let polys: Option<Vec<Vec<PolyPatch>>> = patches
        .iter()
        .map(|r| {
            r.iter()
                .map(|p| match p {
                    ScenePatch::Poly(p) => Some(p.clone()),
                    ScenePatch::Expr(_) => None,
                })
                .collect()
        })
        .collect();
    if let Some(polys) = polys {
        return Ok(CompositeSurface::from_poly(uk, vk, polys, kind)?);
    }
    let vars = if explicit { ["x", "y"] } else { ["u", "v"] };
    let names: &[&str] = if explicit { &["z"] } else { &["x", "y", "z"] };
    let mut exprs = Vec::with_capacity(patches.len());
    for (i, row) in patches.into_iter().enumerate() {
        let mut out = Vec::with_capacity(row.len());
        for (j, p) in row.into_iter().enumerate() {
            out.push(match p {
                ScenePatch::Expr(e) => *e,
                ScenePatch::Poly(p) => ExprPatch::from_poly(&p, names, vars)
                    .with_context(|| format!("patches[{i}][{j}]"))?,
            });
        }
        exprs.push(out);
    }
    Ok(CompositeSurface::from_expr(uk, vk, exprs, kind)?)
}

/// One patch of a scene file, as read.
enum ScenePatch {
    Poly(PolyPatch),
    Expr(Box<ExprPatch>),
}

/// `"domain": [[a, b], [c, d], ...]` of a formula patch or curve, if present.
pub fn domain_of(p: &Value, vars: usize) -> Result<Option<Vec<(f64, f64)>>> {
    let Some(d) = p.get("domain") else {
        return Ok(None);
    };
    let rows = d
        .as_array()
        .filter(|r| r.len() == vars)
        .ok_or_else(|| anyhow!("\"domain\" must be {vars} interval(s) [start, end]"))?;
    rows.iter()
        .enumerate()
        .map(
            |(k, r)| match number_list(Some(r), &format!("domain[{k}]"))?[..] {
                [a, b] => Ok((a, b)),
                _ => bail!("domain[{k}] must be [start, end]"),
            },
        )
        .collect::<Result<Vec<_>>>()
        .map(Some)
}

/// A patch `{"bezier": ...}`, `{"x": "..", "y": "..", "z": "..", "domain": ..}` or, for
/// explicit scenes, `"expr in x, y"` or `{"z": "..", "domain": ..}`.
fn scene_patch(p: &Value, explicit: bool) -> Result<ScenePatch> {
    if let Some(net) = p.get("bezier") {
        let net: Vec<Vec<Vec<f64>>> =
            serde_json::from_value(net.clone()).map_err(|e| anyhow!("bezier: {e}"))?;
        let b = BezierSurface::new(net).context("bezier")?;
        return Ok(ScenePatch::Poly(PolyPatch::from_bezier(&b)));
    }
    let (names, vars): (&[&str], [&str; 2]) = if explicit {
        (&["z"], ["x", "y"])
    } else {
        (&["x", "y", "z"], ["u", "v"])
    };
    let texts: Vec<(&str, &str)> = match p {
        Value::String(t) if explicit => vec![("z", t.as_str())],
        Value::Object(o) => names
            .iter()
            .filter_map(|&n| o.get(n).map(|t| (n, t)))
            .map(|(n, t)| {
                t.as_str()
                    .map(|t| (n, t))
                    .ok_or_else(|| anyhow!("\"{n}\" must be a formula string"))
            })
            .collect::<Result<_>>()?,
        _ => vec![],
    };
    let required = if explicit { 1 } else { 2 };
    if texts.len() < required || (!explicit && texts[..2].iter().map(|t| t.0).ne(["x", "y"])) {
        if explicit {
            bail!(
                "expected a formula in x, y, {{\"z\": \"..\"}} or {{\"bezier\": [[[z],...],...]}}"
            );
        }
        bail!("expected {{\"x\": \"..\", \"y\": \"..\", \"z\": \"..\"}} in u, v or {{\"bezier\": [[[x,y,z],...],...]}}");
    }
    let domain = domain_of(p, 2)?;
    Ok(ScenePatch::Expr(Box::new(ExprPatch::parse(
        &texts, &vars, domain,
    )?)))
}

/// The continuity report as JSON.
pub fn report_json(s: &CompositeSurface) -> String {
    let r = s.continuity();
    let jumps: Vec<Value> = r
        .jumps
        .iter()
        .map(|j| {
            let (dir, line) = match j.line {
                GridLine::U(i) => ("u", i),
                GridLine::V(k) => ("v", k),
            };
            json!({"line": dir, "index": line, "cell": j.cell, "max_jump": j.max_jump, "at": j.at})
        })
        .collect();
    let (uk, vk) = s.knots();
    let names = match s.kind() {
        SurfaceKind::Parametric => ("u", "v"),
        SurfaceKind::Explicit => ("x", "y"),
    };
    let v = json!({
        "max_jump": r.max_jump,
        "tolerance": r.tolerance,
        "continuous": r.is_continuous(),
        "statement": r.statement(names.0, names.1, (uk, vk)),
        "jumps": jumps,
    });
    format!(
        "{}\n",
        serde_json::to_string_pretty(&v).expect("serializable")
    )
}

fn run_patches(args: PatchesArgs) -> Result<()> {
    let text = std::fs::read_to_string(&args.scene)
        .with_context(|| format!("cannot read {}", args.scene.display()))?;
    let s = parse_scene(&text).with_context(|| args.scene.display().to_string())?;
    if args.report_json {
        let dest = Destination::from_option(args.out.formula.output.as_deref());
        return dest.write(report_json(&s).as_bytes());
    }
    let (uk, vk) = s.knots();
    let names = match s.kind() {
        SurfaceKind::Parametric => ("u", "v"),
        SurfaceKind::Explicit => ("x", "y"),
    };
    let statement = s.continuity().statement(names.0, names.1, (uk, vk));
    let (n, m) = s.cells();
    let what = format!("composite surface of {n}×{m} patches");
    let f = s.formula()?;
    let extra = json!({
        "continuity": serde_json::from_str::<Value>(&report_json(&s))?,
        "model": serde_json::from_str::<Value>(&text)?,
    });
    write_surface(Box::new(s), &f, &what, &statement, extra, &args.out)?;
    let _ = writeln!(std::io::stderr(), "continuity: {statement}");
    Ok(())
}

/// `geomkit eval` on a `compose` surface: a K×L grid of the domain or the (u, v) pairs of a
/// file, by the structural evaluator (equal to the single formula).
pub fn eval_surface(
    model: &SurfaceModel,
    samples: Option<(usize, usize)>,
    at: Option<&Path>,
    output: Option<&Path>,
) -> Result<()> {
    let format = match output.map(extension) {
        None => TableFormat::Csv,
        Some(Some(e)) if e == "csv" => TableFormat::Csv,
        Some(Some(e)) if e == "npy" => TableFormat::Npy,
        Some(_) => bail!("name the output .csv or .npy"),
    };
    let ((u0, u1), (v0, v1)) = match model {
        SurfaceModel::Scene(s) => s.domain(),
        SurfaceModel::Ruled(s) => s.domain(),
    };
    let uv: Vec<f64> = match (samples, at) {
        (Some((k, l)), _) => {
            let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
            us.iter()
                .flat_map(|&u| vs.iter().flat_map(move |&v| [u, v]))
                .collect()
        }
        (None, Some(p)) => {
            let t = Table::read(p, &Progress::hidden())?;
            let (_, c) = t.as_records()?;
            if c != 2 {
                bail!(
                    "{}: {c} column(s), but a surface takes two (u, v)",
                    t.name()
                );
            }
            t.data
        }
        (None, None) => bail!("give --samples or --at"),
    };
    let n = uv.len() / 2;
    let (d, names) = match model {
        SurfaceModel::Scene(s) if s.kind() == SurfaceKind::Explicit => (1, ["x", "y", "z"]),
        SurfaceModel::Scene(s) => (s.dim(), ["u", "v", "x"]),
        SurfaceModel::Ruled(_) => (3, ["u", "v", "x"]),
    };
    let mut pts = vec![0.0; n * d];
    match model {
        SurfaceModel::Scene(s) => s.eval_many(&uv, &mut pts)?,
        SurfaceModel::Ruled(s) => {
            if let Some(k) = uv.iter().position(|x| !x.is_finite()) {
                bail!("point {} of --at: {} is not finite", k / 2, uv[k]);
            }
            for (q, p) in uv.chunks_exact(2).zip(pts.chunks_exact_mut(3)) {
                s.eval_into(q[0], q[1], p);
            }
        }
    }
    let header: Vec<String> = names
        .iter()
        .map(|s| s.to_string())
        .chain(["y", "z"].iter().map(|s| s.to_string()))
        .take(2 + d)
        .collect();
    Destination::from_option(output).write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, d + 2], &header)?;
        let mut rows = Vec::with_capacity(n * (d + 2));
        for (q, p) in uv.chunks_exact(2).zip(pts.chunks_exact(d)) {
            rows.extend_from_slice(q);
            rows.extend_from_slice(p);
        }
        sink.push(w, &rows)?;
        sink.finish()
    })
}

/// `geomkit eval` hook: evaluates MODEL if it is a `compose` surface (`Some(())`), else
/// `None`.
pub fn eval_if_surface(args: &crate::cli::ModelEvalArgs) -> Result<Option<()>> {
    if extension(&args.model).as_deref() != Some("json") {
        return Ok(None);
    }
    let Ok(text) = std::fs::read_to_string(&args.model) else {
        return Ok(None);
    };
    let Ok(v) = serde_json::from_str::<Value>(&text) else {
        return Ok(None);
    };
    let Some(model) = SurfaceModel::from_json(&v) else {
        return Ok(None);
    };
    let model = model.with_context(|| args.model.display().to_string())?;
    let samples = args.samples.map(|s| (s.0, s.1.unwrap_or(s.0)));
    if let Some((k, l)) = samples {
        if !(2..=10_000).contains(&k) || !(2..=10_000).contains(&l) {
            bail!("--samples: each count must be from 2 to 10000 (got {k}x{l})");
        }
    }
    eval_surface(&model, samples, args.at.as_deref(), args.output.as_deref()).map(Some)
}
