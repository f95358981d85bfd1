//! `geomkit eval`: any saved model (every type the tools write: Bézier, B-spline, composite
//! and ruled surfaces, piecewise formulas, formula files through their model, point-calculus
//! models and samples) evaluated on uniform samples of its parameter domain or at parameters
//! read from a file. One output row per point: the parameter(s), then the coordinates.

use super::bezier::{coordinate_names, MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES};
use crate::cli::{ModelEvalArgs, Samples};
use crate::model::{read_any_model, AnyModel, BezierModel};
use crate::output::{Destination, RowSink, TableFormat};
use crate::progress::Progress;
use crate::table::{extension, Table};
use anyhow::{bail, Context, Result};
use geomkit::bezier::{BezierSurface, ParamCurve};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::compose::{CompositeSurface, Piecewise, RuledSurface, SurfaceKind};
use geomkit::mesh::SurfaceShape;
use geomkit_model::{PointcalcModel, SampledSurface};
use geomkit_plot::figures::linspace;
use std::path::Path;

/// Parameters evaluated at once.
const BLOCK: usize = 1 << 16;
/// Most points of a surface sample grid.
const MAX_GRID_POINTS: usize = 100_000_000;

/// A model seen as something to evaluate.
enum Target<'a> {
    Curve {
        curve: &'a dyn ParamCurve,
        bspline: Option<&'a BsplineCurve>,
        domain: (f64, f64),
        /// The parameter's column.
        param: &'a str,
        /// The coordinates' columns.
        coords: Vec<String>,
    },
    Surface(SurfaceRef<'a>),
    /// A point-calculus model: one column per factor, one per response.
    Factors(&'a PointcalcModel),
}

#[derive(Clone, Copy)]
enum SurfaceRef<'a> {
    Bezier(&'a BezierSurface),
    Bspline(&'a BsplineSurface),
    Composite(&'a CompositeSurface),
    Ruled(&'a RuledSurface),
    Samples(&'a SampledSurface),
}

impl SurfaceRef<'_> {
    fn shape(&self) -> &dyn SurfaceShape {
        match *self {
            SurfaceRef::Bezier(s) => s,
            SurfaceRef::Bspline(s) => s,
            SurfaceRef::Composite(s) => s,
            SurfaceRef::Ruled(s) => s,
            SurfaceRef::Samples(s) => s,
        }
    }

    /// Names of the parameter columns: x, y for an explicit composite z(x, y).
    fn params(&self) -> [&'static str; 2] {
        match self {
            SurfaceRef::Composite(s) if s.kind() == SurfaceKind::Explicit => ["x", "y"],
            _ => ["u", "v"],
        }
    }

    /// Names of the coordinate columns.
    fn coordinates(&self) -> Vec<String> {
        match self {
            SurfaceRef::Composite(s) if s.kind() == SurfaceKind::Explicit => vec!["z".into()],
            s => coordinate_names(s.shape().dim()),
        }
    }

    /// The structural evaluators of `compose` extend beyond their knots (formula (9)); the
    /// others are defined on their domain only.
    fn checks_domain(&self) -> bool {
        !matches!(self, SurfaceRef::Composite(_) | SurfaceRef::Ruled(_))
    }

    fn point(&self, u: f64, v: f64, out: &mut [f64]) -> geomkit::Result<()> {
        match *self {
            SurfaceRef::Bezier(s) => out.copy_from_slice(&s.eval(u, v)),
            SurfaceRef::Bspline(s) => s.eval_into(u, v, out),
            SurfaceRef::Composite(s) => s.eval_many(&[u, v], out)?,
            SurfaceRef::Ruled(s) => s.eval_into(u, v, out),
            SurfaceRef::Samples(s) => s.eval_into(u, v, out),
        }
        Ok(())
    }
}

/// A piecewise function or composite curve as a curve.
struct Pieces<'a>(&'a Piecewise);

impl ParamCurve for Pieces<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        self.0.eval_into(t, out)
    }
}

fn target<'a>(model: &'a AnyModel, pieces: &'a Option<Pieces<'a>>) -> Result<Target<'a>> {
    let curve = |curve: &'a dyn ParamCurve, domain| Target::Curve {
        curve,
        bspline: None,
        domain,
        param: "t",
        coords: coordinate_names(curve.dim()),
    };
    Ok(match model {
        AnyModel::Bezier(BezierModel::Curve(c)) => curve(c, (0.0, 1.0)),
        AnyModel::Bezier(BezierModel::Rational(r)) => curve(r, (0.0, 1.0)),
        AnyModel::Bezier(BezierModel::Surface(s)) => Target::Surface(SurfaceRef::Bezier(s)),
        AnyModel::BsplineCurve(m) => Target::Curve {
            curve: &m.curve,
            bspline: Some(&m.curve),
            domain: m.curve.domain(),
            param: "t",
            coords: coordinate_names(m.curve.dim()),
        },
        AnyModel::BsplineSurface(m) => Target::Surface(SurfaceRef::Bspline(&m.surface)),
        AnyModel::Composite(s) => Target::Surface(SurfaceRef::Composite(s)),
        AnyModel::Ruled(s) => Target::Surface(SurfaceRef::Ruled(s)),
        AnyModel::SurfaceSamples(s) => Target::Surface(SurfaceRef::Samples(s)),
        AnyModel::CurveSamples(c) => curve(c, c.domain()),
        AnyModel::Piecewise(p) => {
            let k = p.knots();
            Target::Curve {
                curve: pieces.as_ref().expect("made for piecewise models"),
                bspline: None,
                domain: (k[0], k[k.len() - 1]),
                param: p.var(),
                // A function's values are f, as in its formula.
                coords: match p.dim() {
                    1 => vec!["f".to_string()],
                    d => coordinate_names(d),
                },
            }
        }
        AnyModel::Pointcalc(m) => Target::Factors(m),
        AnyModel::Formula(f) => match &f.model {
            Some(m) => target(m, pieces)?,
            None => bail!(
                "this formula file carries no model (written by an older geomkit): evaluate \
                 the file it was made from"
            ),
        },
        other => bail!("a {} cannot be evaluated", other.describe()),
    })
}

/// Runs `geomkit eval`.
pub fn run(args: ModelEvalArgs) -> Result<()> {
    let format = match args.output.as_deref() {
        None => TableFormat::Csv,
        Some(p) => match extension(p).as_deref() {
            Some("csv") => TableFormat::Csv,
            Some("npy") => TableFormat::Npy,
            _ => bail!(
                "cannot tell the output format of {}: name it .csv or .npy",
                p.display()
            ),
        },
    };
    let model = read_any_model(&args.model)?;
    let pieces = match model.geometry() {
        Some(AnyModel::Piecewise(p)) => Some(Pieces(p)),
        _ => None,
    };
    let name = args.model.display().to_string();
    let target = target(&model, &pieces).with_context(|| name.clone())?;
    let progress = Progress::start();
    let dest = Destination::from_option(args.output.as_deref());
    match (target, args.samples, args.at.as_deref()) {
        (Target::Curve { .. }, Some(Samples(_, Some(_))), _) => {
            bail!("{name} is a curve: give --samples K (KxL is for surfaces)")
        }
        (
            Target::Curve {
                curve,
                bspline,
                domain,
                param,
                coords,
            },
            Some(Samples(k, None)),
            _,
        ) => {
            if !(2..=MAX_CURVE_SAMPLES).contains(&k) {
                bail!("--samples must be from 2 to {MAX_CURVE_SAMPLES} (got {k})");
            }
            let ts = linspace(domain.0, domain.1, k);
            let columns = (param, &coords[..]);
            write_curve(&dest, format, curve, bspline, columns, &ts, &progress)
        }
        (
            Target::Curve {
                curve,
                bspline,
                domain,
                param,
                coords,
            },
            None,
            Some(at),
        ) => {
            let params = read_params(at, 1, "a curve takes one column (t)", &progress)?;
            check_domain(&params, 0, domain, "t")?;
            let columns = (param, &coords[..]);
            write_curve(
                &dest,
                format,
                curve,
                bspline,
                columns,
                &params.data,
                &progress,
            )
        }
        (Target::Surface(s), Some(Samples(k, l)), _) => {
            let l = l.unwrap_or(k);
            for c in [k, l] {
                if !(2..=MAX_SURFACE_SAMPLES).contains(&c) {
                    bail!(
                        "--samples: each count must be from 2 to {MAX_SURFACE_SAMPLES} (got \
                         {k}x{l})"
                    );
                }
            }
            if k * l > MAX_GRID_POINTS {
                bail!("--samples {k}x{l} is too many points (at most {MAX_GRID_POINTS})");
            }
            write_surface_grid(&dest, format, s, (k, l), &progress)
        }
        (Target::Surface(s), None, Some(at)) => {
            let params = read_params(at, 2, "a surface takes two columns (u, v)", &progress)?;
            if s.checks_domain() {
                let (du, dv) = s.shape().domain();
                check_domain(&params, 0, du, "u")?;
                check_domain(&params, 1, dv, "v")?;
            }
            write_surface_points(&dest, format, s, &params.data, &progress)
        }
        (Target::Factors(m), samples, at) => {
            write_factors(&dest, format, m, samples, at, &progress)
        }
        (_, None, None) => bail!("give --samples or --at"),
    }
}

/// A point-calculus model at the rows of `--at` (one column per factor) or on a grid of K
/// levels per factor (`--samples K`) over the factors' box.
fn write_factors(
    dest: &Destination,
    format: TableFormat,
    m: &PointcalcModel,
    samples: Option<Samples>,
    at: Option<&Path>,
    progress: &Progress,
) -> Result<()> {
    let model = &m.model;
    let k = model.k();
    let xs = match (samples, at) {
        (Some(Samples(n, l)), _) => {
            if l.is_some_and(|l| l != n) || !(2..=MAX_SURFACE_SAMPLES).contains(&n) {
                bail!("--samples: give one count K from 2 to {MAX_SURFACE_SAMPLES} (K per factor)");
            }
            let total = (n as f64).powi(k as i32);
            if total > MAX_GRID_POINTS as f64 {
                bail!(
                    "--samples {n} over {k} factors is {total:.0} points (at most \
                     {MAX_GRID_POINTS}); give --at"
                );
            }
            let axes: Vec<Vec<f64>> = model
                .domain()
                .iter()
                .map(|&(a, b)| linspace(a, b, n))
                .collect();
            let count = n.pow(k as u32);
            let mut xs = Vec::with_capacity(count * k);
            for i in 0..count {
                let mut rest = i;
                let start = xs.len();
                xs.resize(start + k, 0.0);
                for f in (0..k).rev() {
                    xs[start + f] = axes[f][rest % n];
                    rest /= n;
                }
            }
            xs
        }
        (None, Some(at)) => {
            let what = format!("the model takes one column per factor ({k})");
            let params = read_params(at, k, &what, progress)?;
            for (f, &range) in model.domain().iter().enumerate() {
                check_domain(&params, f, range, model.factors()[f].name())?;
            }
            params.data
        }
        (None, None) => bail!("give --samples or --at"),
    };
    let n = xs.len() / k;
    let d = model.dim();
    let mut values = vec![0.0; n * d];
    model.eval_many(&xs, &mut values)?;
    let header: Vec<String> = model
        .factors()
        .iter()
        .map(|f| f.name().to_string())
        .chain(m.response.iter().cloned())
        .collect();
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, k + d], &header)?;
        let mut rows = Vec::with_capacity(n * (k + d));
        for (x, y) in xs.chunks_exact(k).zip(values.chunks_exact(d)) {
            rows.extend_from_slice(x);
            rows.extend_from_slice(y);
        }
        sink.push(w, &rows)?;
        sink.finish()
    })
}

fn read_params(path: &Path, cols: usize, what: &str, progress: &Progress) -> Result<Table> {
    let table = Table::read(path, progress)?;
    let (_, c) = table.as_records()?;
    if c != cols {
        bail!(
            "{}: {} column(s) of parameters, but {what}",
            table.name(),
            c
        );
    }
    Ok(table)
}

/// Every value of column `col` must lie in the domain.
fn check_domain(table: &Table, col: usize, (a, b): (f64, f64), name: &str) -> Result<()> {
    let (_, cols) = table.as_records()?;
    for (k, row) in table.data.chunks_exact(cols).enumerate() {
        let x = row[col];
        if !(a..=b).contains(&x) {
            bail!(
                "{}: {}: {name} = {x} is outside the domain [{a}, {b}]",
                table.name(),
                table.place(k)
            );
        }
    }
    Ok(())
}

fn write_curve(
    dest: &Destination,
    format: TableFormat,
    curve: &dyn ParamCurve,
    bspline: Option<&BsplineCurve>,
    (param, coords): (&str, &[String]),
    ts: &[f64],
    progress: &Progress,
) -> Result<()> {
    let d = curve.dim();
    let mut header = vec![param.to_string()];
    header.extend_from_slice(coords);
    progress.phase("evaluating", ts.len() as u64);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[ts.len(), d + 1], &header)?;
        let mut points = vec![0.0; BLOCK * d];
        let mut rows = Vec::with_capacity(BLOCK * (d + 1));
        for block in ts.chunks(BLOCK) {
            let pts = &mut points[..block.len() * d];
            match bspline {
                Some(b) => b.eval_many_par(block, pts),
                None => curve.eval_many(block, pts),
            }
            .map_err(std::io::Error::other)?;
            rows.clear();
            for (t, p) in block.iter().zip(pts.chunks_exact(d)) {
                rows.push(*t);
                rows.extend_from_slice(p);
            }
            sink.push(w, &rows)?;
            progress.inc(block.len() as u64);
        }
        sink.finish()
    })
}

fn write_surface_grid(
    dest: &Destination,
    format: TableFormat,
    s: SurfaceRef<'_>,
    (k, l): (usize, usize),
    progress: &Progress,
) -> Result<()> {
    let d = s.shape().dim();
    let ((u0, u1), (v0, v1)) = s.shape().domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
    let mut header: Vec<String> = s.params().map(String::from).into();
    header.extend(s.coordinates());
    progress.phase("evaluating", k as u64);
    let block_rows = (BLOCK / l).max(1);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[k * l, d + 2], &header)?;
        let mut points = vec![0.0; block_rows * l * d];
        let mut rows = Vec::with_capacity(block_rows * l * (d + 2));
        for block in us.chunks(block_rows) {
            let pts = &mut points[..block.len() * l * d];
            s.shape()
                .eval_grid(block, &vs, pts)
                .map_err(std::io::Error::other)?;
            rows.clear();
            for (a, &u) in block.iter().enumerate() {
                for (b, &v) in vs.iter().enumerate() {
                    rows.extend_from_slice(&[u, v]);
                    rows.extend_from_slice(&pts[(a * l + b) * d..(a * l + b + 1) * d]);
                }
            }
            sink.push(w, &rows)?;
            progress.inc(block.len() as u64);
        }
        sink.finish()
    })
}

fn write_surface_points(
    dest: &Destination,
    format: TableFormat,
    s: SurfaceRef<'_>,
    uv: &[f64],
    progress: &Progress,
) -> Result<()> {
    let d = s.shape().dim();
    let n = uv.len() / 2;
    let mut header: Vec<String> = s.params().map(String::from).into();
    header.extend(s.coordinates());
    progress.phase("evaluating", n as u64);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, d + 2], &header)?;
        let mut rows = Vec::with_capacity(BLOCK * (d + 2));
        let mut p = vec![0.0; d];
        for block in uv.chunks(2 * BLOCK) {
            rows.clear();
            for q in block.chunks_exact(2) {
                s.point(q[0], q[1], &mut p).map_err(std::io::Error::other)?;
                rows.extend_from_slice(q);
                rows.extend_from_slice(&p);
            }
            sink.push(w, &rows)?;
            progress.inc((block.len() / 2) as u64);
        }
        sink.finish()
    })
}
