//! `geomkit compose piecewise`: piecewise functions and composite curves as one formula
//! (spec/composite-surfaces.md §5), the continuity report at the breakpoints, a plot.
//!
//! Files (JSON):
//! - `{"type":"piecewise","knots":[x0,...,xn],"pieces":["f0 in x",...]}`: a function;
//! - `{"type":"piecewise","knots":[...],"pieces":[{"x":"..","y":"..","z":"..","domain":[t0,t1]},...]}`:
//!   a composite curve in t (`z` and `domain` optional: without a domain a piece is defined
//!   on its knot interval);
//! - `{"type":"polyline"|"polygon","points":[[x,y],...],"knots":[...]}` (`knots` optional,
//!   0, 1, 2, ... by default; one coordinate per point gives a function);
//! - `{"type":"bspline_curve",...}` (a saved model, e.g. from `geomkit interpolate curve
//!   -o fit.json`): one polynomial piece per knot span ([`Piecewise::from_bspline`]).

use super::compose::{
    format_of, formula_json, formula_line, formula_text, FormulaOutput, PiecewiseArgs,
};
use crate::output::Destination;
use crate::table::extension;
use anyhow::{bail, Context, Result};
use geomkit::compose::Piecewise;
use geomkit_model::{AnyModel, ModelFile};
use geomkit_plot::figures::linspace;
use geomkit_plot::svg::{palette, Axes, Figure};
use serde_json::{json, Value};
use std::io::Write;
use std::path::Path;

/// Reads a pieces file or a saved B-spline curve, and its file (the model of the formula
/// file).
fn read_pieces(path: &Path) -> Result<(Piecewise, ModelFile)> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let file = geomkit_model::parse_file(&text).map_err(|e| e.in_file(path))?;
    let pieces = match AnyModel::from_file(file.clone()).map_err(|e| e.in_file(path))? {
        AnyModel::Piecewise(p) => p,
        AnyModel::BsplineCurve(m) => {
            Piecewise::from_bspline(&m.curve).with_context(|| path.display().to_string())?
        }
        other => bail!(
            "{}: this is a {}; `compose piecewise` takes a \"piecewise\", \"polyline\", \
             \"polygon\" or \"bspline_curve\" file",
            path.display(),
            other.describe()
        ),
    };
    Ok((pieces, file))
}

/// The continuity report as JSON.
pub fn report_json(p: &Piecewise) -> Value {
    let r = p.continuity();
    let jumps: Vec<Value> = r
        .jumps
        .iter()
        .map(|j| json!({"at": j.at, "max_jump": j.max_jump}))
        .collect();
    json!({
        "max_jump": r.max_jump,
        "tolerance": r.tolerance,
        "continuous": r.is_continuous(),
        "statement": p.statement(),
        "jumps": jumps,
    })
}

/// Largest difference between the printed formula (through the engine's tape) and the
/// structural evaluator at `count` points spread over the knots widened by a quarter on
/// each side, plus every knot.
pub fn formula_vs_structural(p: &Piecewise, count: usize) -> Result<f64> {
    let f = p.formula()?;
    let k = p.knots();
    let (a, b) = (k[0], k[k.len() - 1]);
    let mut xs = linspace(a - (b - a) / 4.0, b + (b - a) / 4.0, count);
    xs.extend_from_slice(k);
    let d = p.dim();
    let mut out = vec![0.0; xs.len() * d];
    f.eval_batch(&[&xs], &mut out)?;
    let mut worst = 0.0f64;
    for (x, q) in xs.iter().zip(out.chunks_exact(d)) {
        let s = p.eval(*x);
        worst = (0..d).fold(worst, |w, c| w.max((s[c] - q[c]).abs()));
    }
    Ok(worst)
}

/// An SVG plot: the formula (through the tape) as a line, the breakpoints (structural
/// evaluator) as dots; a function as (x, f(x)) on a chart, a curve as (x(t), y(t)).
pub fn plot(p: &Piecewise, title: &str, subtitle: &str) -> Result<String> {
    let f = p.formula()?;
    let k = p.knots();
    let (a, b) = (k[0], k[k.len() - 1]);
    let function = p.dim() == 1;
    let ts = if function {
        linspace(a - (b - a) / 8.0, b + (b - a) / 8.0, 801)
    } else {
        linspace(a, b, 801)
    };
    let d = p.dim();
    let mut out = vec![0.0; ts.len() * d];
    f.eval_batch(&[&ts], &mut out)?;
    let page = |t: f64, q: &[f64]| if function { [t, q[0]] } else { [q[0], q[1]] };
    let line: Vec<[f64; 2]> = ts
        .iter()
        .zip(out.chunks_exact(d))
        .map(|(&t, q)| page(t, q))
        .collect();
    let dots: Vec<[f64; 2]> = k.iter().map(|&t| page(t, &p.eval(t))).collect();
    let axes = if function {
        Axes::Chart {
            x: p.var().into(),
            y: "f".into(),
        }
    } else {
        Axes::Equal
    };
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    fig.line(line, palette::CURVE);
    fig.legend(palette::CURVE, None, "the single formula");
    fig.dots(dots, 3.5, palette::NEW_VERTEX);
    fig.legend(
        palette::NEW_POLYGON,
        Some(palette::NEW_VERTEX),
        "breakpoints (structural evaluator)",
    );
    Ok(fig.render())
}

/// Runs `geomkit compose piecewise`.
pub fn run(args: PiecewiseArgs) -> Result<()> {
    let (p, file) = read_pieces(&args.pieces)?;
    let out: &FormulaOutput = &args.out;
    let format = format_of(&out.format)?;
    let dest = Destination::from_option(out.output.as_deref());
    let statement = p.statement();
    if args.report_json {
        let mut s = serde_json::to_string_pretty(&report_json(&p))?;
        s.push('\n');
        return dest.write(s.as_bytes());
    }
    let n = p.knots().len() - 1;
    let what = if p.dim() == 1 {
        format!("piecewise function of {n} pieces")
    } else {
        format!("composite curve of {n} pieces")
    };
    let f = p.formula()?;
    match out.output.as_deref().map(extension) {
        None => dest.write(formula_text(&f, format, out.program).as_bytes())?,
        Some(Some(e)) if e == "txt" => {
            dest.write(formula_text(&f, format, out.program).as_bytes())?
        }
        Some(Some(e)) if e == "json" => {
            let json = formula_json(&f, &what, Some(report_json(&p)), Some(file));
            dest.write(json.as_bytes())?
        }
        Some(Some(e)) if e == "svg" => {
            dest.write(plot(&p, &what, &formula_line(&f))?.as_bytes())?
        }
        _ => bail!(
            "cannot tell the output format of {}: name it .json, .svg or .txt",
            out.output.as_deref().unwrap_or(Path::new("")).display()
        ),
    }
    let _ = writeln!(std::io::stderr(), "continuity: {statement}");
    Ok(())
}
