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

use super::formula::{formula_json, formula_line, formula_text};
use crate::cli::{BodyArgs, BodyKind, ComposeCommand, PatchesArgs, RuledArgs, SurfaceOutput};
use crate::output::{mesh_summary, short as num, write_mesh_to, Destination};
use crate::table::extension;
use anyhow::{bail, Context, Result};
use geomkit::compose::{
    bodies, CompositeSurface, Formula, GridLine, RuledCurve, RuledSurface, SurfaceKind,
};
use geomkit::geom::Surface;
use geomkit_model::{AnyModel, ModelFile};
use geomkit_model::{Loaded, Sampling, Shape};
use geomkit_plot::figures::linspace;
use geomkit_plot::svg_to_png;
use geomkit_plot::{picture_svg, PictureOptions};
use serde_json::{json, Value};
use std::io::Write;
use std::path::Path;

/// Runs `geomkit compose ...`.
pub fn run(command: ComposeCommand) -> Result<()> {
    match command {
        ComposeCommand::Body(args) => run_body(args),
        ComposeCommand::Patches(args) => run_patches(args),
        ComposeCommand::Ruled(args) => run_ruled(args),
        ComposeCommand::Piecewise(args) => super::piecewise::run(args),
    }
}

fn polygon_of(args: &BodyArgs) -> Result<Vec<[f64; 2]>> {
    if let Some(p) = &args.polygon {
        return Ok(p.0.clone());
    }
    // --ngon is at most 10000 (clap checks it).
    let n = args.ngon.map_or(6, |n| n as usize);
    Ok(bodies::regular_polygon(n, args.radius.unwrap_or(1.0))?)
}

/// The body of `args` and a description.
pub fn build_body(args: &BodyArgs) -> Result<(RuledSurface, String)> {
    let h = args.height.unwrap_or(2.0);
    let r = args.radius.unwrap_or(1.0);
    let (hs, rs) = (num(h), num(r));
    Ok(match args.body {
        BodyKind::Cube => (bodies::cube()?, "the paper's cube (±1, ±1, ±1)".into()),
        BodyKind::Box => {
            let [a, b, c] = args.size.unwrap_or([2.0; 3]);
            (
                bodies::rectangular_box(a, b, c)?,
                format!("box {}×{}×{}", num(a), num(b), num(c)),
            )
        }
        BodyKind::Pyramid => {
            if args.ngon.is_some() || args.polygon.is_some() {
                (
                    bodies::pyramid(&polygon_of(args)?, h)?,
                    format!("pyramid of height {hs}"),
                )
            } else {
                let a = args.side.unwrap_or(2.0);
                (
                    bodies::square_pyramid(a, h)?,
                    format!("square pyramid, side {}, height {hs}", num(a)),
                )
            }
        }
        BodyKind::Cone => (
            bodies::cone(r, h)?,
            format!("cone, radius {rs}, height {hs}"),
        ),
        BodyKind::Cylinder => (
            bodies::cylinder(r, h)?,
            format!("cylinder with caps, radius {rs}, height {hs}"),
        ),
        BodyKind::Prism => (
            bodies::prism(&polygon_of(args)?, h)?,
            format!("prism of height {hs}"),
        ),
        BodyKind::Frustum => {
            let r1 = args.top_radius.unwrap_or(r / 2.0);
            (
                bodies::frustum(r, r1, h)?,
                format!("frustum, radii {rs} and {}, height {hs}", num(r1)),
            )
        }
    })
}

fn run_body(args: BodyArgs) -> Result<()> {
    let (body, what) = build_body(&args).with_context(|| body_options(&args))?;
    write_ruled(&body, &what, &args.out).with_context(|| body_options(&args))
}

/// A number of an option for a message: plain when short, else scientific.
fn show(x: f64) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// The body and the shape options given, for an error: "compose body box --size 1e308,1,1".
fn body_options(args: &BodyArgs) -> String {
    let mut out = format!("compose body {}", format!("{:?}", args.body).to_lowercase());
    let mut opt = |name: &str, value: Option<String>| {
        if let Some(v) = value {
            out.push_str(&format!(" --{name} {v}"));
        }
    };
    opt(
        "size",
        args.size
            .map(|[a, b, c]| format!("{},{},{}", show(a), show(b), show(c))),
    );
    opt("height", args.height.map(show));
    opt("radius", args.radius.map(show));
    opt("top-radius", args.top_radius.map(show));
    opt("side", args.side.map(show));
    opt("ngon", args.ngon.map(|n| n.to_string()));
    opt(
        "polygon",
        args.polygon.as_ref().map(|p| {
            p.0.iter()
                .map(|[x, y]| format!("{},{}", show(*x), show(*y)))
                .collect::<Vec<_>>()
                .join(";")
        }),
    );
    out
}

/// A ruled surface's formula, model, mesh or picture, as `out` asks.
fn write_ruled(body: &RuledSurface, what: &str, out: &SurfaceOutput) -> Result<()> {
    let f = body.formula()?;
    let model = geomkit_model::ruled_file(body).map(ModelFile::Ruled);
    let subtitle = formula_line(&f)?;
    write_surface(
        Box::new(body.clone()),
        &f,
        what,
        &subtitle,
        None,
        model,
        out,
    )
}

/// Writes a surface's single formula `f` as `out` asks, by the extension of the output:
/// none or .txt the formula, .json the formula in every syntax plus `extra`, .obj/.stl/.ply/
/// .glb the mesh `geomkit mesh` writes, .png/.svg the shaded picture of `geomkit render`.
fn write_surface(
    surface: Box<dyn Surface>,
    f: &Formula,
    what: &str,
    subtitle: &str,
    continuity: Option<Value>,
    model: Option<ModelFile>,
    out: &SurfaceOutput,
) -> Result<()> {
    let o = &out.formula;
    let format = o.format;
    let dest = Destination::from_option(o.output.as_deref());
    let Some(path) = o.output.as_deref() else {
        return dest.write(formula_text(f, format, o.program)?.as_bytes());
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
        "txt" => dest.write(formula_text(f, format, o.program)?.as_bytes()),
        "json" => dest.write(formula_json(f, what, continuity, model)?.as_bytes()),
        ext @ ("obj" | "stl" | "ply" | "glb") => {
            let sampling = match out.samples {
                Some((k, l)) => Sampling::Samples(k, l),
                None => Sampling::Tolerance(None),
            };
            // Errors name the body with its options (`what`) and --samples.
            let option = match out.samples {
                Some((k, l)) => format!("--samples {k}x{l}"),
                None => String::new(),
            };
            let t = super::mesh::tessellate(&loaded(), sampling, what, &option)?;
            write_mesh_to(&dest, &t, ext, false, out.obj_normals)
                .with_context(|| what.to_string())?;
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
    let s = match geomkit_model::load(&args.curves)? {
        AnyModel::Ruled(s) => s,
        other => bail!(
            "{}: this is a {}; `compose ruled` takes a \"ruled\" file",
            args.curves.display(),
            other.describe()
        ),
    };
    let file = || args.curves.display().to_string();
    let report = ruled_report(&s).with_context(file)?;
    let what = format!("ruled surface over {} curves", s.curves().len());
    write_ruled(&s, &what, &args.out).with_context(file)?;
    let _ = writeln!(std::io::stderr(), "ruled: {report}");
    Ok(())
}

/// A scene, or a saved B-spline surface as its cells, and its file.
fn read_scene(path: &Path) -> Result<(CompositeSurface, ModelFile)> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file = geomkit_model::parse_file(&text).map_err(|e| e.in_file(path))?;
    let surface = match AnyModel::from_file(file.clone()).map_err(|e| e.in_file(path))? {
        AnyModel::Composite(s) => s,
        AnyModel::BsplineSurface(m) => CompositeSurface::from_bspline(&m.surface)
            .with_context(|| path.display().to_string())?,
        other => bail!(
            "{}: this is a {}; `compose patches` takes a \"composite_surface\", \
             \"composite_explicit\" or \"bspline_surface\" file",
            path.display(),
            other.describe()
        ),
    };
    Ok((surface, file))
}

/// The continuity report as JSON text.
pub fn report_json(s: &CompositeSurface) -> String {
    format!(
        "{}\n",
        serde_json::to_string_pretty(&report_value(s)).expect("serializable")
    )
}

/// The continuity report.
fn report_value(s: &CompositeSurface) -> Value {
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
    json!({
        "max_jump": r.max_jump,
        "tolerance": r.tolerance,
        "continuous": r.is_continuous(),
        "statement": r.statement(names.0, names.1, (uk, vk)),
        "jumps": jumps,
    })
}

fn run_patches(args: PatchesArgs) -> Result<()> {
    let (s, file) = read_scene(&args.scene)?;
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
    let f = s
        .formula()
        .with_context(|| args.scene.display().to_string())?;
    let continuity = report_value(&s);
    write_surface(
        Box::new(s),
        &f,
        &what,
        &statement,
        Some(continuity),
        Some(file),
        &args.out,
    )?;
    let _ = writeln!(std::io::stderr(), "continuity: {statement}");
    Ok(())
}
