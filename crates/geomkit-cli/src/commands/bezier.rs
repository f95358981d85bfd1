//! `geomkit bezier ...`: real degree, elevation, reduction (exact or approximate), the
//! unified change of degree, and sampling (spec/bezier-order.md).
//!
//! Every command reads and validates its input, computes, and only then writes its output
//! (atomically, see [`crate::output`]): a failing command leaves no output file.

use crate::cli::{
    BezierCommand, ChangeArgs, Continuity, DegreeArgs, Degrees, ElevateArgs, EvalArgs, Norm,
    ReduceArgs, MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES,
};
use crate::model::{read_model, to_json, BezierModel, ErrorReport};
use crate::output::coordinate_names;
use crate::output::{write_stdout, Destination};
use anyhow::{bail, Context, Result};
use geomkit::bezier::{
    ApproxOptions, BezierSurface, DegreeReport, RationalBezierSurface, ReductionNorm,
    SurfaceDegreeReport,
};
use geomkit::geom::{Curve, Surface};
use geomkit_plot::figures::{curve_change_svg, surface_svg, Layer};
use geomkit_plot::svg::{palette, Stroke};
use std::path::{Path, PathBuf};

/// Runs a `bezier` subcommand.
pub fn run(command: BezierCommand) -> Result<()> {
    match command {
        BezierCommand::Degree(args) => degree(args),
        BezierCommand::Elevate(args) => elevate(args),
        BezierCommand::Reduce(args) => reduce(args),
        BezierCommand::Change(args) => change(args),
        BezierCommand::Eval(args) => eval(args),
    }
}

/// The context added to library errors: the input file's name.
fn file_context(path: &Path) -> impl Fn() -> String + '_ {
    move || path.display().to_string()
}

// ---------------------------------------------------------------------------------------------
// degree

fn degree(args: DegreeArgs) -> Result<()> {
    let model = read_model(&args.input)?;
    let ctx = file_context(&args.input);
    let tol = args.tolerance;
    let text = match &model {
        BezierModel::Curve(c) => curve_degree_text(
            &args,
            &model,
            &c.degree_report(tol).with_context(ctx)?,
            c.scale(),
        ),
        BezierModel::Rational(r) => {
            let report = r.degree_report(tol).with_context(ctx)?;
            curve_degree_text(&args, &model, &report, r.homogeneous().scale())
        }
        BezierModel::Surface(s) => surface_degree_text(
            &args,
            &model,
            &s.degree_report(tol).with_context(ctx)?,
            s.scale(),
        ),
        BezierModel::RationalSurface(s) => {
            let report = s.degree_report(tol).with_context(ctx)?;
            surface_degree_text(&args, &model, &report, s.homogeneous().scale())
        }
    };
    write_stdout(text.as_bytes())
}

/// The report of `bezier degree` for a surface (`scale`: max|u_ij| of the net the residuals
/// are relative to).
fn surface_degree_text(
    args: &DegreeArgs,
    model: &BezierModel,
    report: &SurfaceDegreeReport,
    scale: f64,
) -> String {
    let (u, v) = (report.u, report.v);
    if args.json {
        format!(
            "{{\"degree\":[{},{}],\"real_degree\":[{},{}],\"defect\":[{},{}]}}\n",
            u.degree, v.degree, u.real_degree, v.real_degree, u.defect, v.defect
        )
    } else {
        let row = |name: &str, a: String, b: String| {
            format!("{name:<20}{a:<12}{b}").trim_end().to_string() + "\n"
        };
        let mut t = format!("{}: {}\n", args.input.display(), model.describe());
        if matches!(model, BezierModel::RationalSurface(_)) {
            t += "(degrees of the homogeneous surface (w·u, w))\n";
        }
        t += &row("", "u".into(), "v".into());
        t += &row("formal degree", u.degree.to_string(), v.degree.to_string());
        t += &row(
            "real degree",
            u.real_degree.to_string(),
            v.real_degree.to_string(),
        );
        t += &row("degree defect", u.defect.to_string(), v.defect.to_string());
        t += &row("residual", sci(u.residual), sci(v.residual));
        t += &row(
            "rejected residual",
            u.rejected_residual.map_or("-".into(), sci),
            v.rejected_residual.map_or("-".into(), sci),
        );
        t += &format!(
            "{:<20}{} (relative to max|u_ij| = {})\n",
            "tolerance",
            short(u.tolerance),
            short(scale)
        );
        t += "residual: largest net-point distance after reducing to the real degree and \
              elevating back, relative to max|u_ij|; rejected residual: the same one \
              degree lower.\n";
        t
    }
}

fn curve_degree_text(
    args: &DegreeArgs,
    model: &BezierModel,
    r: &DegreeReport,
    scale: f64,
) -> String {
    if args.json {
        return format!(
            "{{\"degree\":{},\"real_degree\":{},\"defect\":{}}}\n",
            r.degree, r.real_degree, r.defect
        );
    }
    let row = |name: &str, value: String, note: String| {
        format!("{name:<20}{value:<12}{note}")
            .trim_end()
            .to_string()
            + "\n"
    };
    let homogeneous = matches!(model, BezierModel::Rational(_));
    let mut t = format!("{}: {}\n", args.input.display(), model.describe());
    if homogeneous {
        t += "(degrees of the homogeneous curve (w·u, w))\n";
    }
    t += &row("formal degree", r.degree.to_string(), String::new());
    t += &row("real degree", r.real_degree.to_string(), String::new());
    t += &row("degree defect", r.defect.to_string(), String::new());
    t += &row(
        "residual",
        sci(r.residual),
        format!(
            "reducing to degree {} and elevating back (accepted)",
            r.real_degree
        ),
    );
    t += &row(
        "rejected residual",
        r.rejected_residual.map_or("-".into(), sci),
        if r.real_degree > 0 {
            format!(
                "reducing to degree {} (above the tolerance)",
                r.real_degree - 1
            )
        } else {
            "(real degree 0: nothing below)".into()
        },
    );
    t += &row(
        "tolerance",
        short(r.tolerance),
        format!("relative to max|u_i| = {}", short(scale)),
    );
    t
}

/// A residual in scientific notation with two digits ("3.1e-17", "0").
fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:.1e}")
    }
}

/// A number rounded to 6 significant digits, in its shortest form ("1e-12", "22.8035").
fn short(x: f64) -> String {
    let x: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if x != 0.0 && (x.abs() < 1e-4 || x.abs() >= 1e6) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

// ---------------------------------------------------------------------------------------------
// elevate / reduce / change

/// What `-o` asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Format {
    Json,
    Svg,
}

fn output_format(path: Option<&Path>) -> Result<Format> {
    let Some(path) = path else {
        return Ok(Format::Json);
    };
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("json") => Ok(Format::Json),
        Some("svg") => Ok(Format::Svg),
        _ => bail!(
            "cannot tell the output format of {}: name it .json (the model) or .svg (a picture)",
            path.display()
        ),
    }
}

/// A finished degree change, ready to be written.
struct Change {
    input: PathBuf,
    operation: &'static str,
    old: BezierModel,
    new: BezierModel,
    error: Option<ErrorReport>,
}

/// Most control points a command will create: a guard against typos like `--to 1000000000`,
/// which would otherwise exhaust memory.
const MAX_POINTS: usize = 1_000_000;

fn check_size(to: Degrees) -> Result<()> {
    let points = match to {
        Degrees::One(n) => n.saturating_add(1),
        Degrees::Two(n, m) => n.saturating_add(1).saturating_mul(m.saturating_add(1)),
    };
    if points > MAX_POINTS {
        bail!("--to {to} is too large: it asks for {points} control points (at most {MAX_POINTS})");
    }
    Ok(())
}

fn wrong_arity(model: &BezierModel, to: Degrees) -> anyhow::Error {
    match (model, to) {
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), _) => anyhow::anyhow!(
            "a surface needs a target degree per direction: --to N,M (got --to {to})"
        ),
        _ => anyhow::anyhow!("a curve takes one target degree: --to N (got --to {to})"),
    }
}

fn elevate(args: ElevateArgs) -> Result<()> {
    let format = output_format(args.output.as_deref())?;
    check_size(args.to)?;
    let old = read_model(&args.input)?;
    let ctx = file_context(&args.input);
    let new = match (&old, args.to) {
        (BezierModel::Curve(c), Degrees::One(n)) if n >= c.degree() => BezierModel::Curve(
            with_bar(|p| c.change_degree_with_progress(n, None, p)).with_context(ctx)?,
        ),
        (BezierModel::Rational(r), Degrees::One(n)) if n >= r.degree() => BezierModel::Rational(
            with_bar(|p| r.change_degree_with_progress(n, None, p)).with_context(ctx)?,
        ),
        // Below the degree: the library's refusal.
        (BezierModel::Curve(c), Degrees::One(n)) => {
            BezierModel::Curve(c.elevate_degree(n).with_context(ctx)?)
        }
        (BezierModel::Rational(r), Degrees::One(n)) => {
            BezierModel::Rational(r.elevate_degree(n).with_context(ctx)?)
        }
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::Two(n, m)) => {
            let (a, b) = surface_degrees(&old);
            if n < a || m < b {
                bail!(
                    "{}: cannot elevate a surface of degrees ({a}, {b}) to ({n}, {m}): elevation \
                     needs degrees >= the current ones (use `bezier change` to mix)",
                    args.input.display()
                );
            }
            change_surface(&old, n, m, None).with_context(ctx)?
        }
        (model, to) => return Err(wrong_arity(model, to)),
    };
    write_change(
        Change {
            input: args.input,
            operation: "Degree elevation",
            old,
            new,
            error: None,
        },
        format,
        args.output.as_deref(),
    )
}

/// Turns the library's "defect too small" into a message that points to --approx (when
/// `approx_available`: polynomial curves).
fn explain_reduction(err: geomkit::Error, input: &Path, approx_available: bool) -> anyhow::Error {
    match err {
        geomkit::Error::DegreeDefectTooSmall {
            real_degree,
            requested,
            defect,
        } => {
            let hint = if approx_available {
                format!("use --approx for the best approximation of degree {requested}")
            } else {
                "a rational curve reduces exactly only".to_string()
            };
            anyhow::anyhow!(
                "{}: cannot reduce exactly to degree {requested}: the real degree is \
                 {real_degree} (degree defect {defect}); {hint}",
                input.display()
            )
        }
        other => anyhow::Error::new(other).context(input.display().to_string()),
    }
}

fn reduce(args: ReduceArgs) -> Result<()> {
    let format = output_format(args.output.as_deref())?;
    check_size(args.to)?;
    let old = read_model(&args.input)?;
    let input = args.input.as_path();
    let (new, error) = match (&old, args.to) {
        (BezierModel::Curve(c), Degrees::One(n)) if args.approx => {
            let Continuity(start, end) = args.continuity.unwrap_or(Continuity(None, None));
            let norm = match args.norm.unwrap_or(Norm::L2) {
                Norm::L2 => ReductionNorm::L2,
                Norm::Chebyshev => ReductionNorm::Chebyshev,
            };
            let options = ApproxOptions::default()
                .with_continuity(start, end)
                .with_norm(norm);
            let r = c
                .reduce_degree_approx(n, &options)
                .with_context(file_context(input))?;
            let report = ErrorReport {
                l2: r.l2_error,
                linf_bound: r.linf.upper_bound,
            };
            (BezierModel::Curve(r.curve), Some(report))
        }
        (BezierModel::Rational(_), Degrees::One(_)) if args.approx => bail!(
            "{}: approximate reduction is available for polynomial curves only (this curve has \
             weights); reduce it exactly, down to its real degree",
            input.display()
        ),
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), _) if args.approx => bail!(
            "{}: approximate reduction is available for curves only; surfaces reduce exactly \
             (drop --approx)",
            input.display()
        ),
        (BezierModel::Curve(c), Degrees::One(n)) => (
            BezierModel::Curve(
                c.reduce_degree(n, args.tolerance)
                    .map_err(|e| explain_reduction(e, input, true))?,
            ),
            None,
        ),
        (BezierModel::Rational(r), Degrees::One(n)) => (
            BezierModel::Rational(
                r.reduce_degree(n, args.tolerance)
                    .map_err(|e| explain_reduction(e, input, false))?,
            ),
            None,
        ),
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::Two(n, m)) => {
            let (a, b) = surface_degrees(&old);
            if n > a || m > b {
                bail!(
                    "{}: cannot reduce a surface of degrees ({a}, {b}) to ({n}, {m}): reduction \
                     needs degrees <= the current ones (use `bezier change` to mix)",
                    input.display()
                );
            }
            (
                change_surface(&old, n, m, args.tolerance).with_context(file_context(input))?,
                None,
            )
        }
        (model, to) => return Err(wrong_arity(model, to)),
    };
    let operation = if error.is_some() {
        "Approximate degree reduction"
    } else {
        "Exact degree reduction"
    };
    write_change(
        Change {
            input: args.input.clone(),
            operation,
            old,
            new,
            error,
        },
        format,
        args.output.as_deref(),
    )
}

fn change(args: ChangeArgs) -> Result<()> {
    let format = output_format(args.output.as_deref())?;
    check_size(args.to)?;
    let old = read_model(&args.input)?;
    let input = args.input.as_path();
    let tol = args.tolerance;
    let new = match (&old, args.to) {
        (BezierModel::Curve(c), Degrees::One(n)) => BezierModel::Curve(
            with_bar(|p| c.change_degree_with_progress(n, tol, p))
                .map_err(|e| explain_reduction(e, input, true))?,
        ),
        (BezierModel::Rational(r), Degrees::One(n)) => BezierModel::Rational(
            with_bar(|p| r.change_degree_with_progress(n, tol, p))
                .map_err(|e| explain_reduction(e, input, false))?,
        ),
        (BezierModel::Surface(_) | BezierModel::RationalSurface(_), Degrees::Two(n, m)) => {
            change_surface(&old, n, m, tol).with_context(file_context(input))?
        }
        (model, to) => return Err(wrong_arity(model, to)),
    };
    write_change(
        Change {
            input: args.input.clone(),
            operation: "Change of degree",
            old,
            new,
            error: None,
        },
        format,
        args.output.as_deref(),
    )
}

fn degrees_of(model: &BezierModel) -> String {
    match model {
        BezierModel::Curve(c) => c.degree().to_string(),
        BezierModel::Rational(r) => r.degree().to_string(),
        BezierModel::Surface(_) | BezierModel::RationalSurface(_) => {
            format!("{:?}", surface_degrees(model))
        }
    }
}

/// The degrees (n, m) of a (rational) surface; (0, 0) for curves.
fn surface_degrees(model: &BezierModel) -> (usize, usize) {
    model.surface_degrees().unwrap_or((0, 0))
}

/// Formula (14) on a (rational) surface: degrees (n, m), each direction elevated or exactly
/// reduced (with `tolerance`).
fn change_surface(
    model: &BezierModel,
    n: usize,
    m: usize,
    tolerance: Option<f64>,
) -> geomkit::Result<BezierModel> {
    with_bar(|p| match model {
        BezierModel::Surface(s) => s
            .change_degree_with_progress(n, m, tolerance, p)
            .map(BezierModel::Surface),
        BezierModel::RationalSurface(s) => s
            .change_degree_with_progress(n, m, tolerance, p)
            .map(BezierModel::RationalSurface),
        BezierModel::Curve(_) | BezierModel::Rational(_) => {
            unreachable!("called for surfaces only")
        }
    })
}

/// Runs a change of degree with a bar on a terminal (shown after a second) that follows the
/// library's progress hook: the new control points (rows, then columns of a net).
fn with_bar<T>(job: impl FnOnce(&geomkit::progress::Progress) -> T) -> T {
    let bar = crate::progress::Progress::start();
    bar.phase("changing", 0);
    let report = bar.reporter();
    job(&geomkit::progress::Progress::new(&report))
}

fn write_change(change: Change, format: Format, output: Option<&Path>) -> Result<()> {
    if let Some(e) = &change.error {
        // The JSON writer refuses non-finite numbers; the picture's caption must not print
        // them either.
        if !(e.l2.is_finite() && e.linf_bound.is_finite()) {
            bail!(
                "{}: the error of the approximate reduction overflows f64 (L2 error {:.3e}, \
                 bound {:.3e}): control points this large cannot be reduced approximately; \
                 scale the curve down first",
                change.input.display(),
                e.l2,
                e.linf_bound
            );
        }
    }
    let contents = match format {
        Format::Json => to_json(&change.new, change.error.as_ref())?,
        Format::Svg => change_svg(&change)?,
    };
    Destination::from_option(output).write(contents.as_bytes())
}

/// The picture of a change: the curve with the old and new control polygons, or the surface
/// with the old and new control nets.
fn change_svg(change: &Change) -> Result<String> {
    let title = format!(
        "{}: {} → {}",
        change.operation,
        degrees_of(&change.old),
        degrees_of(&change.new)
    );
    let mut subtitle = change
        .input
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Some(e) = &change.error {
        subtitle += &format!(
            " — L2 error {:.3e}, max distance ≤ {:.3e}",
            e.l2, e.linf_bound
        );
    }
    match (&change.old, &change.new) {
        (BezierModel::Curve(a), BezierModel::Curve(b)) => {
            let new_curve: Option<&dyn Curve> = change.error.map(|_| b as &dyn Curve);
            Ok(curve_change_svg(
                &title,
                &subtitle,
                (a, &a.points()),
                (new_curve, &b.points()),
            )?)
        }
        (BezierModel::Rational(a), BezierModel::Rational(b)) => Ok(curve_change_svg(
            &title,
            &subtitle,
            (a, &a.points()),
            (None, &b.points()),
        )?),
        (BezierModel::Surface(a), BezierModel::Surface(b)) => {
            surface_change_svg(&title, &subtitle, b, a, b)
        }
        (BezierModel::RationalSurface(a), BezierModel::RationalSurface(b)) => {
            surface_change_svg(&title, &subtitle, b, &net_of(a)?, &net_of(b)?)
        }
        _ => bail!("internal error: the model kind changed"),
    }
}

/// The net of a rational surface for drawing (its Cartesian points; the layer draws points
/// and lines only).
fn net_of(s: &RationalBezierSurface) -> Result<BezierSurface> {
    let (n, m) = s.degrees();
    Ok(BezierSurface::from_flat(
        n + 1,
        m + 1,
        s.dim(),
        s.net_flat().to_vec(),
    )?)
}

/// The surface `surface` with its old and new nets.
fn surface_change_svg(
    title: &str,
    subtitle: &str,
    surface: &dyn Surface,
    old: &BezierSurface,
    new: &BezierSurface,
) -> Result<String> {
    let (n, m) = old.degrees();
    let (n2, m2) = new.degrees();
    Ok(surface_svg(
        title,
        subtitle,
        &[
            Layer::Wireframe {
                surface,
                count: 16,
                stroke: Stroke::solid(palette::CURVE.color, 1.0),
                legend: "surface (unchanged)".into(),
            },
            Layer::Net {
                surface: old,
                stroke: palette::OLD_POLYGON,
                vertex: palette::OLD_VERTEX,
                corners: None,
                legend: format!("old net, degrees ({n}, {m})"),
            },
            Layer::Net {
                surface: new,
                stroke: palette::NEW_POLYGON,
                vertex: palette::NEW_VERTEX,
                corners: Some("u′"),
                legend: format!("new net, degrees ({n2}, {m2})"),
            },
        ],
    )?)
}

// ---------------------------------------------------------------------------------------------
// eval

/// A number for CSV: shortest round-trip form, exponent only for very large or small values.
fn csv_number(x: f64) -> String {
    format!("{x:?}")
}

fn eval(args: EvalArgs) -> Result<()> {
    if args.samples < 2 {
        bail!("--samples must be at least 2 (got {})", args.samples);
    }
    let model = read_model(&args.input)?;
    let k = args.samples;
    let most = match model {
        BezierModel::Surface(_) | BezierModel::RationalSurface(_) => MAX_SURFACE_SAMPLES,
        _ => MAX_CURVE_SAMPLES,
    };
    if k > most {
        bail!("--samples {k} is too many for this model (at most {most})");
    }
    let ts: Vec<f64> = (0..k).map(|a| a as f64 / (k - 1) as f64).collect();
    let dest = Destination::from_option(args.output.as_deref());
    match &model {
        BezierModel::Curve(_) | BezierModel::Rational(_) => {
            let curve: &dyn Curve = match &model {
                BezierModel::Curve(c) => c,
                BezierModel::Rational(r) => r,
                BezierModel::Surface(_) | BezierModel::RationalSurface(_) => {
                    unreachable!("matched above")
                }
            };
            let d = curve.dim();
            dest.write_with(|w| {
                writeln!(w, "{}", coordinate_names(d).join(","))?;
                let mut p = vec![0.0; d];
                for &t in &ts {
                    curve.eval_into(t, &mut p);
                    let row: Vec<String> = p.iter().map(|&x| csv_number(x)).collect();
                    writeln!(w, "{}", row.join(","))?;
                }
                Ok(())
            })
        }
        BezierModel::Surface(_) | BezierModel::RationalSurface(_) => {
            let s: &dyn Surface = match &model {
                BezierModel::Surface(s) => s,
                BezierModel::RationalSurface(s) => s,
                BezierModel::Curve(_) | BezierModel::Rational(_) => unreachable!("matched above"),
            };
            let d = s.dim();
            let mut row_buf = vec![0.0; k * d];
            dest.write_with(|w| {
                writeln!(w, "u,v,{}", coordinate_names(d).join(","))?;
                for &u in &ts {
                    s.eval_grid(&[u], &ts, &mut row_buf)
                        .map_err(std::io::Error::other)?;
                    for (v, p) in ts.iter().zip(row_buf.chunks_exact(d)) {
                        let coords: Vec<String> = p.iter().map(|&x| csv_number(x)).collect();
                        writeln!(
                            w,
                            "{},{},{}",
                            csv_number(u),
                            csv_number(*v),
                            coords.join(",")
                        )?;
                    }
                }
                Ok(())
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        assert_eq!(output_format(None).unwrap(), Format::Json);
        assert_eq!(
            output_format(Some(Path::new("a/b.SVG"))).unwrap(),
            Format::Svg
        );
        assert!(output_format(Some(Path::new("b.txt"))).is_err());
        assert_eq!(coordinate_names(2), ["x", "y"]);
        assert_eq!(coordinate_names(4), ["x1", "x2", "x3", "x4"]);
        assert_eq!(csv_number(10.0), "10.0");
        assert_eq!(sci(0.0), "0");
        assert_eq!(short(1e-12), "1e-12");
        assert_eq!(short(25.0), "25");
        assert_eq!(short(22.80350850198276), "22.8035");
    }
}
