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
    format_of, formula_json, formula_line, formula_text, number_list, read_json, FormulaOutput,
    PiecewiseArgs,
};
use crate::figures::linspace;
use crate::output::Destination;
use crate::svg::{palette, Axes, Figure};
use crate::table::extension;
use anyhow::{anyhow, bail, Context, Result};
use geomkit::compose::{ExprPatch, Piecewise};
use serde_json::{json, Value};
use std::io::Write;
use std::path::Path;

/// Parses a pieces file (see the module docs).
pub fn parse_pieces(v: &Value) -> Result<Piecewise> {
    let ty = v.get("type").and_then(Value::as_str).unwrap_or("");
    match ty {
        "polyline" | "polygon" => {
            let pts = v
                .get("points")
                .and_then(Value::as_array)
                .ok_or_else(|| anyhow!("missing or non-array \"points\""))?;
            let points = pts
                .iter()
                .enumerate()
                .map(|(k, p)| number_list(Some(p), &format!("points[{k}]")))
                .collect::<Result<Vec<_>>>()?;
            let knots = match v.get("knots") {
                None => None,
                Some(k) => Some(number_list(Some(k), "knots")?),
            };
            Ok(Piecewise::polyline(points, knots, ty == "polygon")?)
        }
        "piecewise" => {
            let knots = number_list(v.get("knots"), "knots")?;
            let pieces = v
                .get("pieces")
                .and_then(Value::as_array)
                .ok_or_else(|| anyhow!("missing or non-array \"pieces\""))?;
            if pieces.iter().all(Value::is_string) {
                let texts: Vec<&str> = pieces.iter().filter_map(Value::as_str).collect();
                return Ok(Piecewise::function(knots, &texts)?);
            }
            let parsed = pieces
                .iter()
                .enumerate()
                .map(|(i, p)| curve_piece(p).with_context(|| format!("pieces[{i}]")))
                .collect::<Result<Vec<_>>>()?;
            Ok(Piecewise::from_pieces(knots, parsed, "t")?)
        }
        "bspline_curve" => {
            let obj = v.as_object().expect("a value with a \"type\" is an object");
            Ok(Piecewise::from_bspline(
                &crate::model::parse_bspline_curve(obj)?.curve,
            )?)
        }
        other => bail!(
            "\"type\" must be \"piecewise\", \"polyline\", \"polygon\" or \"bspline_curve\", \
             found {other:?}"
        ),
    }
}

/// A curve piece `{"x":"..","y":"..","z":"..","domain":[t0,t1]}`.
fn curve_piece(p: &Value) -> Result<ExprPatch> {
    let o = p.as_object().ok_or_else(|| {
        anyhow!("expected a formula in x, or {{\"x\": \"..\", \"y\": \"..\"}} in t")
    })?;
    let mut coords = Vec::new();
    for n in ["x", "y", "z"] {
        match o.get(n) {
            Some(Value::String(t)) => coords.push((n, t.as_str())),
            Some(_) => bail!("\"{n}\" must be a formula string"),
            None if n == "z" => {}
            None => bail!("missing \"{n}\": a curve piece has x and y (and z) as formulas in t"),
        }
    }
    let domain = match o.get("domain") {
        None => None,
        Some(d) => match number_list(Some(d), "domain")?[..] {
            [a, b] => Some(vec![(a, b)]),
            _ => bail!("\"domain\" must be [t0, t1]"),
        },
    };
    Ok(ExprPatch::parse(&coords, &["t"], domain)?)
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
    let v = read_json(&args.pieces)?;
    let p = parse_pieces(&v).with_context(|| args.pieces.display().to_string())?;
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
            dest.write(formula_json(&f, &what, json!({"continuity": report_json(&p)})).as_bytes())?
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
