//! `geomkit pointcalc ...`: point equations (spec/point-calculus.md): multi-factor models
//! through experimental points (fit, eval, shares, optimize, formula) and curves and surfaces
//! through source points (curve, surface).
//!
//! Every command reads and validates its input, computes, and only then writes its output
//! (atomically): a failing command leaves no output file. Warnings (a large Lebesgue
//! constant) go to standard error as `warning: ...` lines.

use crate::cli::{
    FitArgs, FormulaArgs, OptimizeArgs, PcCurveArgs, PcEvalArgs, PcSurfaceArgs, PointcalcCommand,
    SharesArgs,
};
use crate::model::json_number;
use crate::output::{write_stdout, Destination};
use anyhow::{anyhow, bail, Context, Result};
use geomkit::exact::Rational;
use geomkit::expr::Graph;
use geomkit::geom::Surface;
use geomkit::pointcalc::{
    optimize, Goal, Hypersurface, NodePreset, Nodes, OptimizeOptions, PointEquation, PointOptions,
    PointSurface, PrintedSurface, Warning,
};
use geomkit_model::{AnyModel, PointcalcModel};
use geomkit_plot::figures::{linspace, point_curves_svg, surface_svg, Layer};
use geomkit_plot::svg::{palette, Stroke};
use serde::Deserialize;
use std::io::Write as _;
use std::path::Path;

/// Runs a `pointcalc` subcommand.
pub fn run(command: PointcalcCommand) -> Result<()> {
    match command {
        PointcalcCommand::Fit(args) => fit(args),
        PointcalcCommand::Eval(args) => eval(args),
        PointcalcCommand::Shares(args) => shares(args),
        PointcalcCommand::Optimize(args) => optimize_cmd(args),
        PointcalcCommand::Formula(args) => formula(args),
        PointcalcCommand::Curve(args) => curve(args),
        PointcalcCommand::Surface(args) => surface(args),
    }
}

// ---------------------------------------------------------------------------------------------
// node specifications

/// Parses a node specification for `count` points (see `--nodes`).
pub fn parse_nodes(spec: &str, count: Option<usize>) -> Result<Nodes> {
    let s = spec.trim();
    let nodes = match s {
        "half" => Nodes::paper_half(),
        "third" => Nodes::paper_third(),
        "two-thirds" => Nodes::paper_two_thirds(),
        _ if s.contains(':') => {
            let parts: Vec<&str> = s.split(':').collect();
            let preset = match parts[0] {
                "cheb1" | "chebyshev1" => NodePreset::ChebyshevFirst,
                "cheb2" | "chebyshev2" => NodePreset::ChebyshevSecond,
                "equi" | "equispaced" => NodePreset::Equispaced,
                p => bail!("unknown node preset '{p}' (cheb1, cheb2, equi)"),
            };
            let n: usize = parts[1]
                .parse()
                .map_err(|_| anyhow!("'{}' is not a node count", parts[1]))?;
            let num = |i: usize, default: f64| -> Result<f64> {
                parts.get(i).map_or(Ok(default), |x| {
                    x.parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| {
                            anyhow!("'{x}' is not a finite number (in node preset '{s}')")
                        })
                })
            };
            if parts.len() != 2 && parts.len() != 4 {
                bail!("node preset '{s}': use NAME:N or NAME:N:LO:HI");
            }
            Nodes::preset(preset, n, num(2, 0.0)?, num(3, 1.0)?)?
        }
        _ => {
            let items: Vec<&str> = s.split(',').map(str::trim).collect();
            if items.iter().any(|x| x.contains('/')) {
                let exact = items
                    .iter()
                    .map(|x| parse_rational(x))
                    .collect::<Result<Vec<_>>>()?;
                Nodes::from_rationals(exact)?
            } else {
                let v = items
                    .iter()
                    .map(|x| {
                        x.parse::<f64>()
                            .map_err(|_| anyhow!("'{x}' is not a number (in nodes '{s}')"))
                    })
                    .collect::<Result<Vec<_>>>()?;
                Nodes::new(v)?
            }
        }
    };
    if let Some(n) = count {
        if nodes.len() != n {
            bail!("nodes '{s}' give {} nodes for {n} points", nodes.len());
        }
    }
    Ok(nodes)
}

fn parse_rational(x: &str) -> Result<Rational> {
    if let Ok(r) = x.parse::<Rational>() {
        return Ok(r);
    }
    let f: f64 = x
        .parse()
        .map_err(|_| anyhow!("'{x}' is not a number or fraction"))?;
    geomkit::exact::rational_from_f64(f).ok_or_else(|| anyhow!("'{x}' is not finite"))
}

/// Equally spaced exact nodes j/(n-1) (one node: 0).
fn default_nodes(n: usize) -> Result<Nodes> {
    if n == 1 {
        return Ok(Nodes::new(vec![0.0])?);
    }
    let d = (n - 1) as i64;
    Ok(Nodes::from_rationals(
        (0..n as i64)
            .map(|j| Rational::new(j.into(), d.into()))
            .collect(),
    )?)
}

fn warn(warnings: &[Warning]) {
    let mut err = std::io::stderr();
    for w in warnings {
        let _ = writeln!(err, "warning: {w}");
    }
}

fn options(strict: bool) -> PointOptions {
    PointOptions::default().with_strict(strict)
}

// ---------------------------------------------------------------------------------------------
// model files

/// The model file of `pointcalc fit`.
pub fn model_json(model: &Hypersurface, response: &[String]) -> Result<String> {
    Ok(geomkit_model::to_json(&PointcalcModel::file_of(
        model, response,
    ))?)
}

/// Reads a model file of `pointcalc fit`.
fn read_model(path: &Path) -> Result<(Hypersurface, Vec<String>)> {
    match geomkit_model::load(path)? {
        AnyModel::Pointcalc(m) => Ok((m.model, m.response)),
        other => bail!(
            "{}: this is a {}, not a \"{MODEL_TYPE}\" (the output of `pointcalc fit`)",
            path.display(),
            other.describe()
        ),
    }
}

const MODEL_TYPE: &str = "pointcalc-model";

// ---------------------------------------------------------------------------------------------
// CSV with a header

struct NamedCsv {
    name: String,
    columns: Vec<String>,
    /// (line number, cells)
    rows: Vec<(usize, Vec<String>)>,
}

impl NamedCsv {
    fn read(path: &Path) -> Result<NamedCsv> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {name}"))?;
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (_, header) = lines
            .next()
            .ok_or_else(|| anyhow!("{name}: empty file (expected a header line)"))?;
        let sep = [',', ';', '\t']
            .into_iter()
            .find(|c| header.contains(*c))
            .unwrap_or(',');
        let split = |l: &str| -> Vec<String> {
            l.split(sep)
                .map(|c| c.trim().trim_matches('"').trim().to_string())
                .collect()
        };
        let columns = split(header);
        let mut rows = Vec::new();
        for (line, l) in lines {
            let cells = split(l);
            if cells.len() != columns.len() {
                bail!(
                    "{name} line {line}: {} cells, but the header has {}",
                    cells.len(),
                    columns.len()
                );
            }
            rows.push((line, cells));
        }
        if rows.is_empty() {
            bail!("{name}: no data lines after the header");
        }
        Ok(NamedCsv {
            name,
            columns,
            rows,
        })
    }

    /// The numbers of `columns` in every row; errors name the line and column.
    fn numbers(&self, columns: &[String]) -> Result<Vec<Vec<f64>>> {
        // Header positions by name (the first of a repeated name), looked up once each.
        let mut position = std::collections::HashMap::with_capacity(self.columns.len());
        for (i, c) in self.columns.iter().enumerate() {
            position.entry(c.as_str()).or_insert(i);
        }
        let idx = columns
            .iter()
            .map(|want| {
                position.get(want.as_str()).copied().ok_or_else(|| {
                    let mut known: Vec<&str> =
                        self.columns.iter().take(20).map(String::as_str).collect();
                    if self.columns.len() > 20 {
                        known.push("...");
                    }
                    anyhow!(
                        "{}: no column '{want}' in the header (columns: {})",
                        self.name,
                        known.join(", ")
                    )
                })
            })
            .collect::<Result<Vec<_>>>()?;
        self.rows
            .iter()
            .map(|(line, cells)| {
                idx.iter()
                    .map(|&i| {
                        let cell = &cells[i];
                        match cell.parse::<f64>() {
                            Ok(x) if x.is_finite() => Ok(x),
                            _ => Err(anyhow!(
                                "{} line {line}: column '{}': {cell:?} is not a finite number",
                                self.name,
                                self.columns[i]
                            )),
                        }
                    })
                    .collect()
            })
            .collect()
    }
}

// ---------------------------------------------------------------------------------------------
// fit, eval, shares, optimize, formula

fn fit(args: FitArgs) -> Result<()> {
    let csv = NamedCsv::read(&args.input)?;
    let mut columns = args.factors.clone();
    columns.extend(args.response.iter().cloned());
    let mut seen = std::collections::HashSet::with_capacity(columns.len());
    for c in &columns {
        if !seen.insert(c) {
            bail!("column '{c}' is named twice in --factors/--response");
        }
    }
    let records = csv.numbers(&columns)?;
    let mut given: Vec<Option<Nodes>> = vec![None; args.factors.len()];
    if let Some(spec) = &args.nodes {
        for part in spec.split(';').filter(|p| !p.trim().is_empty()) {
            let (name, nodes) = part
                .split_once('=')
                .ok_or_else(|| anyhow!("--nodes: '{part}' is not NAME=NODES"))?;
            let f = args
                .factors
                .iter()
                .position(|x| x == name.trim())
                .ok_or_else(|| anyhow!("--nodes: '{}' is not one of --factors", name.trim()))?;
            given[f] = Some(
                parse_nodes(nodes, None).with_context(|| format!("--nodes for {}", name.trim()))?,
            );
        }
    }
    let model = Hypersurface::from_records(&args.factors, &records, &given, &options(args.strict))
        .map_err(|e| match e {
            geomkit::Error::GridRecord { record, reason } => {
                // "(also record N)" names the other record: as a line of the file.
                let reason = match reason.split_once("(also record ") {
                    Some((head, tail)) => {
                        let n: usize = tail.trim_end_matches(')').parse().unwrap_or(0);
                        let line = csv.rows.get(n).map_or(0, |r| r.0);
                        format!("{head}(also line {line})")
                    }
                    None => reason,
                };
                anyhow!("{} line {}: {reason}", csv.name, csv.rows[record].0)
            }
            e => anyhow!(e).context(csv.name.clone()),
        })?;
    warn(model.warnings());
    Destination::from_option(args.output.as_deref())
        .write(model_json(&model, &args.response)?.as_bytes())
}

fn eval(args: PcEvalArgs) -> Result<()> {
    let (model, response) = read_model(&args.model)?;
    let csv = NamedCsv::read(&args.at)?;
    let names: Vec<String> = model.factors().iter().map(|f| f.name().into()).collect();
    let rows = csv.numbers(&names)?;
    let xs: Vec<f64> = rows.iter().flatten().copied().collect();
    let mut out = vec![0.0; rows.len() * model.dim()];
    if let Err(e) = model.eval_many(&xs, &mut out) {
        // The first point that fails, by its line (a result beyond f64, or extrapolated so far
        // that rounding swamps it).
        for (x, (line, _)) in rows.iter().zip(&csv.rows) {
            if let Err(e) = model.eval(x) {
                bail!("{} line {line}: {e}", csv.name);
            }
        }
        return Err(anyhow!(e).context(csv.name.clone()));
    }
    let mut text = names.join(",");
    for r in &response {
        text.push(',');
        text.push_str(r);
    }
    text.push('\n');
    for (x, y) in rows.iter().zip(out.chunks_exact(model.dim())) {
        let cells: Vec<String> = x.iter().chain(y).map(|v| format!("{v}")).collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    Destination::from_option(args.output.as_deref()).write(text.as_bytes())
}

/// Parses "a=1,b=2" into the model's factor order.
fn parse_at(model: &Hypersurface, at: &str) -> Result<Vec<f64>> {
    let mut x = vec![None; model.k()];
    for part in at.split(',').filter(|p| !p.trim().is_empty()) {
        let (name, value) = part
            .split_once('=')
            .ok_or_else(|| anyhow!("--at: '{part}' is not NAME=VALUE"))?;
        let f = model.factor_index(name.trim())?;
        let v: f64 = value
            .trim()
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| {
                anyhow!(
                    "--at: {}: '{}' is not a finite number",
                    name.trim(),
                    value.trim()
                )
            })?;
        x[f] = Some(v);
    }
    x.iter()
        .enumerate()
        .map(|(f, v)| {
            v.ok_or_else(|| anyhow!("--at: no value for factor '{}'", model.factors()[f].name()))
        })
        .collect()
}

fn point_object(model: &Hypersurface, x: &[f64]) -> String {
    let items: Vec<String> = model
        .factors()
        .iter()
        .zip(x)
        .map(|(f, v)| format!("{}:{}", json_string(f.name()), json_number(*v)))
        .collect();
    format!("{{{}}}", items.join(","))
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).expect("string")
}

fn shares(args: SharesArgs) -> Result<()> {
    let (model, _) = read_model(&args.model)?;
    let x = parse_at(&model, &args.at)?;
    let shares = model.shares(&x).context("--at")?;
    let items: Vec<String> = shares
        .iter()
        .enumerate()
        .map(|(c, s)| {
            format!(
                "{{\"point\":{},\"share\":{}}}",
                point_object(&model, &model.cell_levels(c)),
                json_number(*s)
            )
        })
        .collect();
    write_stdout(format!("{{\"shares\":[{}]}}\n", items.join(",")).as_bytes())
}

fn optimize_cmd(args: OptimizeArgs) -> Result<()> {
    let (model, response) = read_model(&args.model)?;
    let name = args.model.display();
    if model.dim() != 1 {
        bail!(
            "{name}: the model has {} responses ({}): --max/--min search one; fit a model \
             with a single --response column (e.g. `pointcalc fit ... --response {}`)",
            model.dim(),
            response.join(", "),
            response.first().map_or("Y", String::as_str)
        );
    }
    let goal = if args.max { Goal::Max } else { Goal::Min };
    let mut opts = OptimizeOptions::default();
    if let Some(t) = args.tolerance {
        if !t.is_finite() || t < 0.0 {
            bail!("--tolerance must be a finite number >= 0, got {t}");
        }
        opts = opts.with_tolerance(t);
    }
    let best = optimize(&model, goal, &opts).with_context(|| name.to_string())?;
    if !best.certified {
        warn_text(&format!(
            "the box or work budget ran out: the optimum is within {} of the value (not certified to the tolerance)",
            json_number(best.gap)
        ));
    }
    write_stdout(
        format!(
            "{{\"at\":{},\"value\":{},\"bound\":{},\"gap\":{},\"certified\":{}}}\n",
            point_object(&model, &best.at),
            json_number(best.value),
            json_number(best.bound),
            json_number(best.gap),
            best.certified
        )
        .as_bytes(),
    )
}

fn warn_text(text: &str) {
    let _ = writeln!(std::io::stderr(), "warning: {text}");
}

fn formula(args: FormulaArgs) -> Result<()> {
    let mut g = Graph::new();
    let text = std::fs::read_to_string(&args.model)
        .with_context(|| format!("cannot read {}", args.model.display()))?;
    let is_model = serde_json::from_str::<serde_json::Value>(&text)
        .map(|v| v.get("type").and_then(|t| t.as_str()) == Some(MODEL_TYPE))
        .unwrap_or(false);
    // (name, parameters, expression) of every printed coordinate or response.
    let (params, lines): (Vec<String>, Vec<(String, _)>) = if is_model {
        let (model, response) = read_model(&args.model)?;
        let params: Vec<String> = model
            .factors()
            .iter()
            .map(|f| f.name().to_string())
            .collect();
        let vars: Vec<_> = params.iter().map(|p| g.var(p)).collect();
        let exprs = model
            .to_expr(&mut g, &vars)
            .with_context(|| args.model.display().to_string())?;
        (params, response.into_iter().zip(exprs).collect())
    } else {
        let eq = read_curve(&args.model, args.nodes.as_deref(), false)?;
        let t = g.var("t");
        let exprs = eq
            .to_expr(&mut g, t)
            .with_context(|| args.model.display().to_string())?;
        let names = ["x", "y", "z"];
        let lines = exprs
            .into_iter()
            .enumerate()
            .map(|(d, e)| (names.get(d).map_or(format!("x{d}"), |s| s.to_string()), e))
            .collect();
        (vec!["t".to_string()], lines)
    };
    let params: Vec<&str> = params.iter().map(String::as_str).collect();
    let mut out = g.print_preamble(&params, args.format);
    for (name, e) in lines {
        out.push_str(&g.print_definition(&name, &params, e, args.format)?);
        out.push('\n');
    }
    write_stdout(out.as_bytes())
}

// ---------------------------------------------------------------------------------------------
// curves and surfaces

#[derive(Deserialize)]
#[serde(untagged)]
enum PointsFile {
    Bare(Vec<Vec<f64>>),
    Wrapped { points: Vec<Vec<f64>> },
}

#[derive(Deserialize)]
#[serde(untagged)]
enum NetFile {
    Bare(Vec<Vec<Vec<f64>>>),
    Wrapped { net: Vec<Vec<Vec<f64>>> },
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path, what: &str) -> Result<T> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {name}"))?;
    serde_json::from_str(&text).map_err(|e| anyhow!("{name}: not {what} ({e})"))
}

fn read_curve(path: &Path, nodes: Option<&str>, strict: bool) -> Result<PointEquation> {
    let points = match read_json::<PointsFile>(path, "a JSON array of points")? {
        PointsFile::Bare(p) | PointsFile::Wrapped { points: p } => p,
    };
    let nodes = match nodes {
        Some(spec) => parse_nodes(spec, Some(points.len())).context("--nodes")?,
        None => default_nodes(points.len().max(1)).with_context(|| path.display().to_string())?,
    };
    let eq = PointEquation::with_options(nodes, points, &options(strict))
        .with_context(|| path.display().to_string())?;
    Ok(eq)
}

/// The most samples of `pointcalc curve` (points of the curve).
pub const MAX_CURVE_SAMPLES: usize = 1_000_000;

/// The most samples per direction of `pointcalc surface` (K × K points of the surface).
pub const MAX_SURFACE_SAMPLES: usize = 1_000;

/// The most multiply-adds of the samples of `pointcalc curve` and `surface` (a few seconds).
pub const MAX_SAMPLE_WORK: usize = 2_000_000_000;

/// Refuses --samples whose evaluation would cost more than [`MAX_SAMPLE_WORK`].
fn check_sample_work(work: usize, k: usize) -> Result<()> {
    if work > MAX_SAMPLE_WORK {
        bail!(
            "--samples {k} is too many for these source points: about {work} multiply-adds, at \
             most {MAX_SAMPLE_WORK} (use fewer samples)"
        );
    }
    Ok(())
}

fn check_samples(samples: Option<usize>, default: usize, max: usize) -> Result<usize> {
    let k = samples.unwrap_or(default);
    if !(2..=max).contains(&k) {
        bail!("--samples must be between 2 and {max}, got {k}");
    }
    Ok(k)
}

fn curve(args: PcCurveArgs) -> Result<()> {
    let eq = read_curve(&args.input, args.nodes.as_deref(), args.strict)?;
    warn(eq.warnings());
    let k = check_samples(args.samples, 201, MAX_CURVE_SAMPLES)?;
    let dest = Destination::from_option(args.output.as_deref());
    if args
        .output
        .as_deref()
        .and_then(|p| p.extension())
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
    {
        // The figure's samples (400 over the node interval) and the source points.
        let (a, b) = eq.domain();
        let ts = linspace(a, b, 400);
        let mut drawn = vec![0.0; ts.len() * eq.dim()];
        eq.eval_params(&ts, &mut drawn)
            .with_context(|| args.input.display().to_string())?;
        check_svg_extent(&drawn, &args.input)?;
        check_svg_extent(eq.points_flat(), &args.input)?;
        let svg = point_curves_svg(
            "Point-equation curve",
            &format!("{} source points", eq.nodes().len()),
            &[(&eq, format!("M(t), nodes {:?}", eq.nodes().values()))],
        )?;
        return dest.write(svg.as_bytes());
    }
    check_sample_work(k.saturating_mul(eq.points_flat().len()), k)?;
    let (a, b) = eq.domain();
    let ts = linspace(a, b, k);
    let mut points = vec![0.0; k * eq.dim()];
    eq.eval_params(&ts, &mut points)
        .with_context(|| args.input.display().to_string())?;
    let samples: Vec<String> = ts
        .iter()
        .zip(points.chunks_exact(eq.dim()))
        .map(|(&t, p)| {
            let p: Vec<String> = std::iter::once(t)
                .chain(p.iter().copied())
                .map(json_number)
                .collect();
            format!("[{}]", p.join(","))
        })
        .collect();
    let nodes: Vec<String> = eq
        .nodes()
        .values()
        .iter()
        .map(|v| json_number(*v))
        .collect();
    let text = format!(
        "{{\"type\":\"pointcalc-curve\",\"nodes\":[{}],\"lebesgue\":{},\"samples\":[\n{}\n]}}\n",
        nodes.join(","),
        json_number(eq.nodes().lebesgue_constant()),
        samples.join(",\n")
    );
    dest.write(text.as_bytes())
}

/// The largest coordinate an SVG picture is laid out with: its layout computes with the
/// extent of the drawing (differences, paddings, scales), which must stay well inside f64.
const MAX_SVG_COORDINATE: f64 = 1e300;

/// Refuses SVG output of coordinates beyond [`MAX_SVG_COORDINATE`].
fn check_svg_extent(values: &[f64], input: &Path) -> Result<()> {
    if let Some(v) = values.iter().find(|v| v.abs() > MAX_SVG_COORDINATE) {
        bail!(
            "{}: a coordinate of {v:e} to draw: SVG output needs coordinates within ±1e300 (the \
             picture is laid out with their extent); rescale the points or write JSON",
            input.display()
        );
    }
    Ok(())
}

/// The surface of `pointcalc surface` (either kind).
pub enum AnySurface {
    /// Rows first, then across.
    Rows(PointSurface),
    /// The printed geomatrix (9).
    Printed(PrintedSurface),
}

impl AnySurface {
    fn view(&self) -> &dyn Surface {
        match self {
            AnySurface::Rows(s) => s,
            AnySurface::Printed(s) => s,
        }
    }
}

fn build_surface(args: &PcSurfaceArgs, net: Vec<Vec<Vec<f64>>>) -> Result<AnySurface> {
    if args.printed {
        return Ok(AnySurface::Printed(PrintedSurface::new(net)?));
    }
    let rows = net.len();
    let row_nodes: Vec<Nodes> = match (&args.row_nodes, &args.nodes) {
        (Some(spec), _) => {
            let specs: Vec<&str> = spec.split(';').collect();
            if specs.len() != rows {
                bail!("--row-nodes has {} node sets for {rows} rows", specs.len());
            }
            specs
                .iter()
                .zip(&net)
                .enumerate()
                .map(|(i, (s, row))| {
                    parse_nodes(s, Some(row.len())).with_context(|| format!("--row-nodes: row {i}"))
                })
                .collect::<Result<_>>()?
        }
        (None, Some(spec)) => net
            .iter()
            .map(|row| parse_nodes(spec, Some(row.len())).context("--nodes"))
            .collect::<Result<_>>()?,
        (None, None) => net
            .iter()
            .map(|row| default_nodes(row.len().max(1)))
            .collect::<Result<_>>()?,
    };
    let across = match &args.across {
        Some(spec) => parse_nodes(spec, Some(rows)).context("--across")?,
        None => default_nodes(rows.max(1))?,
    };
    let s = PointSurface::rows_then_across(row_nodes, across, net)?;
    warn(s.warnings());
    Ok(AnySurface::Rows(s))
}

fn surface(args: PcSurfaceArgs) -> Result<()> {
    let net = match read_json::<NetFile>(&args.input, "a JSON net of points")? {
        NetFile::Bare(n) | NetFile::Wrapped { net: n } => n,
    };
    let flat: Vec<f64> = net.iter().flatten().flatten().copied().collect();
    let cols = net.iter().map(Vec::len).max().unwrap_or(0);
    let surface =
        build_surface(&args, net.clone()).with_context(|| args.input.display().to_string())?;
    let k = check_samples(args.samples, 21, MAX_SURFACE_SAMPLES)?;
    let dest = Destination::from_option(args.output.as_deref());
    let view = surface.view();
    let dim = view.dim();
    if args
        .output
        .as_deref()
        .and_then(|p| p.extension())
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"))
    {
        // The wireframe's samples (12 iso-lines of 64 points each way) and the source points.
        let ((u0, u1), (v0, v1)) = view.domain();
        for (us, vs) in [
            (linspace(u0, u1, 12), linspace(v0, v1, 64)),
            (linspace(u0, u1, 64), linspace(v0, v1, 12)),
        ] {
            let mut drawn = vec![0.0; us.len() * vs.len() * dim];
            view.eval_grid(&us, &vs, &mut drawn)
                .with_context(|| args.input.display().to_string())?;
            check_svg_extent(&drawn, &args.input)?;
        }
        check_svg_extent(&flat, &args.input)?;
        let regular = net.iter().all(|r| r.len() == cols);
        let svg = surface_svg(
            "Point-equation surface",
            if args.printed {
                "the geomatrix (9) as printed"
            } else {
                "rows first, then across"
            },
            &[
                Layer::Wireframe {
                    surface: view,
                    count: 12,
                    stroke: Stroke::solid(palette::CURVE.color, 1.0),
                    legend: "surface".into(),
                },
                Layer::Points {
                    points: &flat,
                    dim,
                    grid: regular.then_some((net.len(), cols)),
                    stroke: None,
                    vertex: palette::NEW_VERTEX,
                    radius: 3.5,
                    legend: "source points".into(),
                },
            ],
        )?;
        return dest.write(svg.as_bytes());
    }
    // Each row at every u, then K × K combinations across the rows.
    let rows = net.len();
    let work = k
        .saturating_mul(flat.len())
        .saturating_add(k.saturating_mul(k).saturating_mul(rows.saturating_mul(dim)));
    check_sample_work(work, k)?;
    let ((u0, u1), (v0, v1)) = view.domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, k));
    let mut out = vec![0.0; k * k * dim];
    view.eval_grid(&us, &vs, &mut out)
        .with_context(|| args.input.display().to_string())?;
    let pts: Vec<String> = out
        .chunks_exact(dim)
        .map(|p| {
            let c: Vec<String> = p.iter().map(|v| json_number(*v)).collect();
            format!("[{}]", c.join(","))
        })
        .collect();
    let text =
        format!(
        "{{\"type\":\"pointcalc-surface-samples\",\"u\":[{}],\"v\":[{}],\"points\":[\n{}\n]}}\n",
        us.iter().map(|v| json_number(*v)).collect::<Vec<_>>().join(","),
        vs.iter().map(|v| json_number(*v)).collect::<Vec<_>>().join(","),
        pts.join(",\n")
    );
    dest.write(text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_node_specs() {
        assert_eq!(parse_nodes("0,1/3,1", None).unwrap(), Nodes::paper_third());
        assert_eq!(parse_nodes("third", Some(3)).unwrap(), Nodes::paper_third());
        assert_eq!(parse_nodes("cheb2:5", None).unwrap().len(), 5);
        assert_eq!(
            parse_nodes("cheb1:4:-1:1", None).unwrap(),
            Nodes::preset(NodePreset::ChebyshevFirst, 4, -1.0, 1.0).unwrap()
        );
        assert!(parse_nodes("0,1,1", None).is_err());
        assert!(parse_nodes("0,x,1", None).is_err());
        assert!(parse_nodes("half", Some(4)).is_err());
        assert!(parse_nodes("cheb3:4", None).is_err());
    }
}
