//! `geomkit eval`: any saved model (Bézier or B-spline, curve or surface) evaluated on
//! uniform samples of its parameter domain or at parameters read from a file. One output row
//! per point: the parameter(s), then the coordinates.

use super::bezier::{coordinate_names, MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES};
use crate::cli::{ModelEvalArgs, Samples};
use crate::figures::linspace;
use crate::model::{read_any_model, AnyModel, Model};
use crate::output::{Destination, RowSink, TableFormat};
use crate::progress::Progress;
use crate::table::{extension, Table};
use anyhow::{bail, Result};
use geomkit::bezier::BezierSurface;
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::geom::{BatchOptions, Curve};
use std::path::Path;

/// Parameters evaluated at once.
const BLOCK: usize = 1 << 16;
/// Most points of a surface sample grid.
const MAX_GRID_POINTS: usize = 100_000_000;

/// A model seen as something to evaluate.
enum Target<'a> {
    Curve {
        curve: &'a dyn Curve,
        bspline: Option<&'a BsplineCurve>,
        domain: (f64, f64),
    },
    Surface(SurfaceRef<'a>),
}

#[derive(Clone, Copy)]
enum SurfaceRef<'a> {
    Bezier(&'a BezierSurface),
    Bspline(&'a BsplineSurface),
}

impl SurfaceRef<'_> {
    fn dim(self) -> usize {
        match self {
            SurfaceRef::Bezier(s) => s.dim(),
            SurfaceRef::Bspline(s) => s.dim(),
        }
    }

    fn domain(self) -> ((f64, f64), (f64, f64)) {
        match self {
            SurfaceRef::Bezier(_) => ((0.0, 1.0), (0.0, 1.0)),
            SurfaceRef::Bspline(s) => s.domain(),
        }
    }

    fn grid(self, us: &[f64], vs: &[f64], out: &mut [f64]) -> geomkit::Result<()> {
        match self {
            SurfaceRef::Bezier(s) => s.eval_grid(us, vs, out),
            SurfaceRef::Bspline(s) => s.eval_grid(us, vs, out),
        }
    }

    fn point(self, u: f64, v: f64, out: &mut [f64]) {
        match self {
            SurfaceRef::Bezier(s) => out.copy_from_slice(&s.eval(u, v)),
            SurfaceRef::Bspline(s) => s.eval_into(u, v, out),
        }
    }
}

fn target(model: &AnyModel) -> Target<'_> {
    match model {
        AnyModel::Bezier(Model::Curve(c)) => Target::Curve {
            curve: c,
            bspline: None,
            domain: (0.0, 1.0),
        },
        AnyModel::Bezier(Model::Rational(r)) => Target::Curve {
            curve: r,
            bspline: None,
            domain: (0.0, 1.0),
        },
        AnyModel::Bezier(Model::Surface(s)) => Target::Surface(SurfaceRef::Bezier(s)),
        AnyModel::BsplineCurve(m) => Target::Curve {
            curve: &m.curve,
            bspline: Some(&m.curve),
            domain: m.curve.domain(),
        },
        AnyModel::BsplineSurface(m) => Target::Surface(SurfaceRef::Bspline(&m.surface)),
    }
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
    if let Some(done) = super::compose::eval_if_surface(&args)? {
        return Ok(done);
    }
    let model = read_any_model(&args.model)?;
    let progress = Progress::start();
    let dest = Destination::from_option(args.output.as_deref());
    let name = args.model.display().to_string();
    match (target(&model), args.samples, args.at.as_deref()) {
        (Target::Curve { .. }, Some(Samples(_, Some(_))), _) => {
            bail!("{name} is a curve: give --samples K (KxL is for surfaces)")
        }
        (
            Target::Curve {
                curve,
                bspline,
                domain,
            },
            Some(Samples(k, None)),
            _,
        ) => {
            if !(2..=MAX_CURVE_SAMPLES).contains(&k) {
                bail!("--samples must be from 2 to {MAX_CURVE_SAMPLES} (got {k})");
            }
            let ts = linspace(domain.0, domain.1, k);
            write_curve(&dest, format, curve, bspline, &ts, &progress)
        }
        (
            Target::Curve {
                curve,
                bspline,
                domain,
            },
            None,
            Some(at),
        ) => {
            let params = read_params(at, 1, "a curve takes one column (t)", &progress)?;
            check_domain(&params, 0, domain, "t")?;
            write_curve(&dest, format, curve, bspline, &params.data, &progress)
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
            let (du, dv) = s.domain();
            check_domain(&params, 0, du, "u")?;
            check_domain(&params, 1, dv, "v")?;
            write_surface_points(&dest, format, s, &params.data, &progress)
        }
        (_, None, None) => bail!("give --samples or --at"),
    }
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
    curve: &dyn Curve,
    bspline: Option<&BsplineCurve>,
    ts: &[f64],
    progress: &Progress,
) -> Result<()> {
    let d = curve.dim();
    let mut header = vec!["t".to_string()];
    header.extend(coordinate_names(d));
    progress.phase("evaluating", ts.len() as u64);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[ts.len(), d + 1], &header)?;
        let mut points = vec![0.0; BLOCK * d];
        let mut rows = Vec::with_capacity(BLOCK * (d + 1));
        for block in ts.chunks(BLOCK) {
            let pts = &mut points[..block.len() * d];
            match bspline {
                Some(b) => b.eval_many_par(block, pts),
                None => curve.eval_batch(block, pts, &BatchOptions::sequential()),
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
    let d = s.dim();
    let ((u0, u1), (v0, v1)) = s.domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
    let mut header = vec!["u".to_string(), "v".to_string()];
    header.extend(coordinate_names(d));
    progress.phase("evaluating", k as u64);
    let block_rows = (BLOCK / l).max(1);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[k * l, d + 2], &header)?;
        let mut points = vec![0.0; block_rows * l * d];
        let mut rows = Vec::with_capacity(block_rows * l * (d + 2));
        for block in us.chunks(block_rows) {
            let pts = &mut points[..block.len() * l * d];
            s.grid(block, &vs, pts).map_err(std::io::Error::other)?;
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
    let d = s.dim();
    let n = uv.len() / 2;
    let mut header = vec!["u".to_string(), "v".to_string()];
    header.extend(coordinate_names(d));
    progress.phase("evaluating", n as u64);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, d + 2], &header)?;
        let mut rows = Vec::with_capacity(BLOCK * (d + 2));
        let mut p = vec![0.0; d];
        for block in uv.chunks(2 * BLOCK) {
            rows.clear();
            for q in block.chunks_exact(2) {
                s.point(q[0], q[1], &mut p);
                rows.extend_from_slice(q);
                rows.extend_from_slice(&p);
            }
            sink.push(w, &rows)?;
            progress.inc((block.len() / 2) as u64);
        }
        sink.finish()
    })
}
