//! `geomkit eval`: any saved model (every type the tools write: Bézier, B-spline, composite
//! and ruled surfaces, piecewise formulas, formula files through their model, point-calculus
//! models and samples) evaluated on uniform samples of its parameter domain or at parameters
//! read from a file. One output row per point: the parameter(s), then the coordinates.

use crate::cli::{ExtrapolateArg, ModelEvalArgs, Orders, Samples};
use crate::cli::{MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES};
use crate::model::{read_any_model, AnyModel, BezierModel};
use crate::output::coordinate_names;
use crate::output::{Destination, RowSink, TableFormat};
use crate::progress::Progress;
use crate::table::{extension, Table};
use anyhow::{bail, Context, Result};
use geomkit::bspline::{BsplineCurve, BsplineSurface, Extrapolate};
use geomkit::compose::SurfaceKind;
use geomkit::geom::{BatchOptions, Curve, Surface};
use geomkit_model::PointcalcModel;
use geomkit_plot::figures::linspace;
use std::path::Path;

/// Parameters evaluated at once.
const BLOCK: usize = 1 << 16;
/// Most points of a surface sample grid.
const MAX_GRID_POINTS: usize = 100_000_000;

/// A model seen as something to evaluate, with the names of its columns.
enum Target<'a> {
    Curve {
        curve: &'a dyn Curve,
        /// The parameter's column.
        param: &'a str,
        /// The coordinates' columns.
        coords: Vec<String>,
    },
    Surface {
        surface: &'a dyn Surface,
        /// The parameters' columns: x, y for an explicit composite z(x, y).
        params: [&'static str; 2],
        /// The coordinates' columns.
        coords: Vec<String>,
        /// Whether parameters must lie in the domain: the structural evaluators of `compose`
        /// extend beyond their knots (formula (9)); the others are defined on it only.
        checks_domain: bool,
    },
    /// A point-calculus model: one column per factor, one per response.
    Factors(&'a PointcalcModel),
}

/// A curve named t, x, y, ...
fn plain_curve(curve: &dyn Curve) -> Target<'_> {
    Target::Curve {
        curve,
        param: "t",
        coords: coordinate_names(curve.dim()),
    }
}

/// A surface named u, v, x, y, ...
fn plain_surface(surface: &dyn Surface, checks_domain: bool) -> Target<'_> {
    Target::Surface {
        surface,
        params: ["u", "v"],
        coords: coordinate_names(surface.dim()),
        checks_domain,
    }
}

fn target(model: &AnyModel) -> Result<Target<'_>> {
    Ok(match model {
        AnyModel::Bezier(BezierModel::Curve(c)) => plain_curve(c),
        AnyModel::Bezier(BezierModel::Rational(r)) => plain_curve(r),
        AnyModel::Bezier(BezierModel::Surface(s)) => plain_surface(s, true),
        AnyModel::Bezier(BezierModel::RationalSurface(s)) => plain_surface(s, true),
        AnyModel::BsplineCurve(m) => plain_curve(&m.curve),
        AnyModel::BsplineSurface(m) => plain_surface(&m.surface, true),
        AnyModel::Composite(s) if s.kind() == SurfaceKind::Explicit => Target::Surface {
            surface: s,
            params: ["x", "y"],
            coords: vec!["z".into()],
            checks_domain: false,
        },
        AnyModel::Composite(s) => plain_surface(s, false),
        AnyModel::Ruled(s) => plain_surface(s, false),
        AnyModel::SurfaceSamples(s) => plain_surface(s, true),
        AnyModel::CurveSamples(c) => plain_curve(c),
        AnyModel::Piecewise(p) => Target::Curve {
            curve: p,
            param: p.var(),
            // A function's values are f, as in its formula.
            coords: match p.dim() {
                1 => vec!["f".to_string()],
                d => coordinate_names(d),
            },
        },
        AnyModel::Pointcalc(m) => Target::Factors(m),
        AnyModel::Formula(f) => match &f.model {
            Some(m) => target(m)?,
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
    let name = args.model.display().to_string();
    let target = target(&model).with_context(|| name.clone())?;
    let progress = Progress::start();
    let dest = Destination::from_option(args.output.as_deref());
    if args.nu.is_some() || args.extrapolate.is_some() {
        return match (&model, args.nu) {
            (AnyModel::BsplineCurve(m), None | Some(Orders(_, None))) => {
                write_bspline_nu(&dest, format, &m.curve, &args, &name, &progress)
            }
            (AnyModel::BsplineCurve(_), Some(_)) => {
                bail!("{name} is a curve: give one derivative order (--nu N)")
            }
            (AnyModel::BsplineSurface(m), Some(Orders(du, Some(dv)))) => {
                if args.extrapolate.is_some() {
                    bail!(
                        "{name}: --extrapolate applies to B-spline curves (surfaces are                          evaluated on their domain)"
                    );
                }
                write_bspline_partial(&dest, format, &m.surface, (du, dv), &args, &name)
            }
            (AnyModel::BsplineSurface(_), _) => {
                bail!("{name} is a surface: give both derivative orders (--nu DU,DV)")
            }
            _ => bail!("{name}: --nu and --extrapolate apply to B-spline curves and surfaces"),
        };
    }
    match (target, args.samples, args.at.as_deref()) {
        (Target::Curve { .. }, Some(Samples(_, Some(_))), _) => {
            bail!("{name} is a curve: give --samples K (KxL is for surfaces)")
        }
        (
            Target::Curve {
                curve,
                param,
                coords,
            },
            Some(Samples(k, None)),
            _,
        ) => {
            if !(2..=MAX_CURVE_SAMPLES).contains(&k) {
                bail!("--samples must be from 2 to {MAX_CURVE_SAMPLES} (got {k})");
            }
            let (a, b) = curve.domain();
            let ts = linspace(a, b, k);
            write_curve(&dest, format, curve, (param, &coords), &ts, &progress)
        }
        (
            Target::Curve {
                curve,
                param,
                coords,
            },
            None,
            Some(at),
        ) => {
            let params = read_params(at, 1, "a curve takes one column (t)", &progress)?;
            check_domain(&params, 0, curve.domain(), "t")?;
            write_curve(
                &dest,
                format,
                curve,
                (param, &coords),
                &params.data,
                &progress,
            )
        }
        (
            Target::Surface {
                surface,
                params,
                coords,
                ..
            },
            Some(Samples(k, l)),
            _,
        ) => {
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
            let header = header(&params, &coords);
            write_surface_grid(&dest, format, surface, &header, (k, l), &progress)
        }
        (
            Target::Surface {
                surface,
                params,
                coords,
                checks_domain,
            },
            None,
            Some(at),
        ) => {
            let table = read_params(at, 2, "a surface takes two columns (u, v)", &progress)?;
            if checks_domain {
                let (du, dv) = surface.domain();
                check_domain(&table, 0, du, "u")?;
                check_domain(&table, 1, dv, "v")?;
            }
            let header = header(&params, &coords);
            write_surface_points(&dest, format, surface, &header, &table.data, &progress)
        }
        (Target::Factors(m), samples, at) => {
            write_factors(&dest, format, m, samples, at, &progress)
        }
        (_, None, None) => bail!("give --samples or --at"),
    }
}

/// The parameters' then the coordinates' names.
fn header(params: &[&str], coords: &[String]) -> Vec<String> {
    params
        .iter()
        .map(|p| p.to_string())
        .chain(coords.iter().cloned())
        .collect()
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

/// `--nu` / `--extrapolate` on a B-spline curve ([`BsplineCurve::eval_nu_many`], SciPy's
/// semantics): columns t and the derivative's coordinates (dNx, dNy, ... for nu = N > 0).
fn write_bspline_nu(
    dest: &Destination,
    format: TableFormat,
    curve: &BsplineCurve,
    args: &ModelEvalArgs,
    name: &str,
    progress: &Progress,
) -> Result<()> {
    let nu = args.nu.map_or(0, |o| o.0);
    let mode = args.extrapolate.unwrap_or(ExtrapolateArg::None);
    let ts = match (args.samples, args.at.as_deref()) {
        (Some(Samples(k, None)), _) => {
            if !(2..=MAX_CURVE_SAMPLES).contains(&k) {
                bail!("--samples must be from 2 to {MAX_CURVE_SAMPLES} (got {k})");
            }
            let (a, b) = curve.domain();
            linspace(a, b, k)
        }
        (Some(_), _) => bail!("{name} is a curve: give --samples K (KxL is for surfaces)"),
        (None, Some(at)) => {
            let params = read_params(at, 1, "a curve takes one column (t)", progress)?;
            if mode == ExtrapolateArg::None {
                check_domain(&params, 0, curve.domain(), "t")?;
            }
            params.data
        }
        (None, None) => bail!("give --samples or --at"),
    };
    let extrapolate = match mode {
        ExtrapolateArg::Periodic => Extrapolate::Periodic,
        _ => Extrapolate::Extend,
    };
    let d = curve.dim();
    let mut values = vec![0.0; ts.len() * d];
    curve.eval_nu_many(&ts, nu, extrapolate, &mut values)?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        bail!(
            "{name}: the derivative of order {nu} at t = {} is not a finite number (it \
             overflows f64)",
            ts[i / d]
        );
    }
    let coords: Vec<String> = coordinate_names(d)
        .into_iter()
        .map(|c| if nu == 0 { c } else { format!("d{nu}{c}") })
        .collect();
    let mut header = vec!["t".to_string()];
    header.extend(coords);
    progress.busy("writing");
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[ts.len(), d + 1], &header)?;
        let mut rows = Vec::with_capacity(ts.len() * (d + 1));
        for (t, p) in ts.iter().zip(values.chunks_exact(d)) {
            rows.push(*t);
            rows.extend_from_slice(p);
        }
        sink.push(w, &rows)?;
        sink.finish()
    })
}

/// `--nu DU,DV` on a B-spline surface ([`BsplineSurface::eval_partial_grid`] on `--samples`,
/// [`BsplineSurface::eval_partial_many`] at `--at`: RectBivariateSpline's `__call__` and
/// `ev`): columns u, v and the partial derivative's coordinates (dDU_DVx, ...; the plain
/// names for 0,0).
fn write_bspline_partial(
    dest: &Destination,
    format: TableFormat,
    surface: &BsplineSurface,
    (du, dv): (usize, usize),
    args: &ModelEvalArgs,
    name: &str,
) -> Result<()> {
    let (p, q) = surface.degrees();
    if (du, dv) != (0, 0) && (du >= p || dv >= q) {
        bail!(
            "{name}: --nu {du},{dv} is not available on a surface of degrees {p},{q}: each              order must be below the degree in its direction (RectBivariateSpline's rule)"
        );
    }
    let ((u0, u1), (v0, v1)) = surface.domain();
    let uv: Vec<f64> = match (args.samples, args.at.as_deref()) {
        (Some(Samples(k, l)), _) => {
            let l = l.unwrap_or(k);
            if ![k, l].iter().all(|c| (2..=MAX_SURFACE_SAMPLES).contains(c))
                || k * l > MAX_GRID_POINTS
            {
                bail!(
                    "--samples {k}x{l}: each count from 2 to {MAX_SURFACE_SAMPLES}, at most \
                     {MAX_GRID_POINTS} points"
                );
            }
            let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
            us.iter()
                .flat_map(|&u| vs.iter().flat_map(move |&v| [u, v]))
                .collect()
        }
        (None, Some(at)) => {
            let progress = Progress::start();
            let table = read_params(at, 2, "a surface takes two columns (u, v)", &progress)?;
            check_domain(&table, 0, (u0, u1), "u")?;
            check_domain(&table, 1, (v0, v1), "v")?;
            table.data
        }
        (None, None) => bail!("give --samples or --at"),
    };
    let n = uv.len() / 2;
    let d = surface.dim();
    let mut values = vec![0.0; n * d];
    match args.samples {
        Some(Samples(k, l)) => {
            let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l.unwrap_or(k)));
            surface.eval_partial_grid(&us, &vs, du, dv, &mut values)?;
        }
        None => {
            let (us, vs): (Vec<f64>, Vec<f64>) = uv.chunks_exact(2).map(|p| (p[0], p[1])).unzip();
            surface.eval_partial_many(&us, &vs, du, dv, &mut values)?;
        }
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        bail!(
            "{name}: the partial derivative {du},{dv} at (u, v) = ({}, {}) is not a finite \
             number (it overflows f64)",
            uv[2 * (i / d)],
            uv[2 * (i / d) + 1]
        );
    }
    let mut header = vec!["u".to_string(), "v".to_string()];
    header.extend(coordinate_names(d).into_iter().map(|c| {
        if (du, dv) == (0, 0) {
            c
        } else {
            format!("d{du}_{dv}{c}")
        }
    }));
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, d + 2], &header)?;
        let mut rows = Vec::with_capacity(n * (d + 2));
        for (p, x) in uv.chunks_exact(2).zip(values.chunks_exact(d)) {
            rows.extend_from_slice(p);
            rows.extend_from_slice(x);
        }
        sink.push(w, &rows)?;
        sink.finish()
    })
}

fn write_curve(
    dest: &Destination,
    format: TableFormat,
    curve: &dyn Curve,
    (param, coords): (&str, &[String]),
    ts: &[f64],
    progress: &Progress,
) -> Result<()> {
    let d = curve.dim();
    let mut header = vec![param.to_string()];
    header.extend_from_slice(coords);
    progress.phase("evaluating", ts.len() as u64);
    let options = BatchOptions::default();
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[ts.len(), d + 1], &header)?;
        let mut points = vec![0.0; BLOCK * d];
        let mut rows = Vec::with_capacity(BLOCK * (d + 1));
        for block in ts.chunks(BLOCK) {
            let pts = &mut points[..block.len() * d];
            curve
                .eval_batch(block, pts, &options)
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
    s: &dyn Surface,
    header: &[String],
    (k, l): (usize, usize),
    progress: &Progress,
) -> Result<()> {
    let d = s.dim();
    let ((u0, u1), (v0, v1)) = s.domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
    progress.phase("evaluating", k as u64);
    let block_rows = (BLOCK / l).max(1);
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[k * l, d + 2], header)?;
        let mut points = vec![0.0; block_rows * l * d];
        let mut rows = Vec::with_capacity(block_rows * l * (d + 2));
        for block in us.chunks(block_rows) {
            let pts = &mut points[..block.len() * l * d];
            s.eval_grid(block, &vs, pts)
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
    s: &dyn Surface,
    header: &[String],
    uv: &[f64],
    progress: &Progress,
) -> Result<()> {
    let d = s.dim();
    let n = uv.len() / 2;
    progress.phase("evaluating", n as u64);
    let options = BatchOptions::default();
    dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[n, d + 2], header)?;
        let mut points = vec![0.0; BLOCK * d];
        let mut rows = Vec::with_capacity(BLOCK * (d + 2));
        for block in uv.chunks(2 * BLOCK) {
            let pts = &mut points[..block.len() / 2 * d];
            s.eval_batch(block, pts, &options)
                .map_err(std::io::Error::other)?;
            rows.clear();
            for (q, p) in block.chunks_exact(2).zip(pts.chunks_exact(d)) {
                rows.extend_from_slice(q);
                rows.extend_from_slice(p);
            }
            sink.push(w, &rows)?;
            progress.inc((block.len() / 2) as u64);
        }
        sink.finish()
    })
}
