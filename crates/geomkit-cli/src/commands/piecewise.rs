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

use super::formula::{formula_json, formula_line, formula_text};
use crate::cli::{FormulaOutput, PiecewiseArgs};
use crate::output::Destination;
use crate::table::extension;
use anyhow::{bail, Context, Result};
use geomkit::compose::Piecewise;
use geomkit_model::{AnyModel, ModelFile};
use geomkit_plot::figures::piecewise_svg;
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

/// Runs `geomkit compose piecewise`.
pub fn run(args: PiecewiseArgs) -> Result<()> {
    let (p, model) = read_pieces(&args.pieces)?;
    let out: &FormulaOutput = &args.out;
    let format = out.format;
    let dest = Destination::from_option(out.output.as_deref());
    let statement = p.statement();
    let file = args.pieces.display().to_string();
    let warn = || {
        let mut err = std::io::stderr();
        for w in p.warnings() {
            let _ = writeln!(err, "warning: {file}: {w}");
        }
    };
    if args.report_json {
        let mut s = serde_json::to_string_pretty(&report_json(&p))?;
        s.push('\n');
        dest.write(s.as_bytes())?;
        warn();
        return Ok(());
    }
    let n = p.knots().len() - 1;
    let what = if p.dim() == 1 {
        format!("piecewise function of {n} pieces")
    } else {
        format!("composite curve of {n} pieces")
    };
    let f = p.formula().with_context(|| file.clone())?;
    match out.output.as_deref().map(extension) {
        None => dest.write(formula_text(&f, format, out.program)?.as_bytes())?,
        Some(Some(e)) if e == "txt" => {
            dest.write(formula_text(&f, format, out.program)?.as_bytes())?
        }
        Some(Some(e)) if e == "json" => {
            let json = formula_json(&f, &what, Some(report_json(&p)), Some(model))?;
            dest.write(json.as_bytes())?
        }
        Some(Some(e)) if e == "svg" => {
            dest.write(piecewise_svg(&p, &what, &formula_line(&f)?)?.as_bytes())?
        }
        _ => bail!(
            "cannot tell the output format of {}: name it .json, .svg or .txt",
            out.output.as_deref().unwrap_or(Path::new("")).display()
        ),
    }
    let _ = writeln!(std::io::stderr(), "continuity: {statement}");
    warn();
    Ok(())
}
