//! `geomkit interpolate curve|surface`: interpolating cubic B-splines through reference points
//! (spec/bspline-interpolation.md).
//!
//! Every command checks its options, reads and validates its input, computes, and only then
//! writes (atomically, see [`crate::output`]): a failing command leaves no output file. The
//! one exception to "compute first" is the streaming tile solve, which writes as it goes into
//! temporary files that are renamed into place only when everything succeeded.

use super::spline_tiles::stream_spline_tiles;
use crate::cli::{
    CurveArgs, Degrees, EndArg, FormArg, InterpolateCommand, ParamArg, Samples, SurfaceArgs, Vector,
};
use crate::cli::{MAX_CURVE_SAMPLES, MAX_SURFACE_SAMPLES};
use crate::model::{knots_sibling, write_bspline_curve_json, write_bspline_surface_json};
use crate::npy::NpyReader;
use crate::output::coordinate_names;
use crate::output::{commit_pair, AtomicFile, Destination, RowSink, TableFormat};
use crate::progress::Progress;
use crate::table::{extension, is_npy, Table};
use anyhow::{anyhow, bail, Context, Result};
use clap::ValueEnum;
use geomkit::bspline::{
    interpolate_curve_at_with_progress, interpolate_curve_flat_with_progress,
    interpolate_curve_tiled_with_progress, interpolate_heights_at_with_progress,
    interpolate_heights_with_progress, interpolate_surface_flat_with_progress,
    interpolate_surface_tiled_with_progress, last_repeats_first, make_interp_spline_tiled,
    make_interp_spline_with_progress, make_interp_surface_with_progress, parameters, BsplineCurve,
    BsplineSurface, CurveTiler, EndCondition, EndSpec, InterpolationOptions, Parametrization,
    SplineEnds, SplineOptions, SurfaceInterpolationOptions, TileOptions, TileSolution,
    MAX_SPLINE_DEGREE, MIN_SPLINE_HALO, MIN_TILE_SIZE,
};
use geomkit_plot::figures::{
    bspline_curve_figure, heightmap_svg, linspace, surface_svg, Layer, REFERENCE,
};
use geomkit_plot::svg::{palette, Stroke};
use std::path::Path;
use std::sync::mpsc;

/// Runs an `interpolate` subcommand.
pub fn run(command: InterpolateCommand) -> Result<()> {
    match command {
        InterpolateCommand::Curve(args) => curve(args),
        InterpolateCommand::Surface(args) => surface(args),
    }
}

/// Default number of samples of a curve written as .csv/.npy.
const DEFAULT_CURVE_SAMPLES: usize = 1001;
/// Default sample grid of a surface.
const DEFAULT_SURFACE_SAMPLES: usize = 101;
/// Most sample points of a surface grid (K·L).
const MAX_GRID_POINTS: usize = 100_000_000;
/// Most reference points drawn in an SVG.
const MAX_DRAWN_POINTS: usize = 20_000;
/// Rows of a surface sample grid evaluated at once when streaming it to a file.
const GRID_BLOCK: usize = 64;

/// The command-line name of an end condition ("not-a-knot").
fn end_name(end: EndArg) -> String {
    end.to_possible_value()
        .map_or_else(|| format!("{end:?}"), |v| v.get_name().to_string())
}

/// `--offset` only with `--end outer`, tangents only with `--end clamped`.
fn check_end_flags(end: EndArg, offset: bool, tangents: bool) -> Result<()> {
    if offset && end != EndArg::Outer {
        bail!("--offset applies to --end outer only");
    }
    if tangents && end != EndArg::Clamped {
        bail!("--start-tangent and --end-tangent apply to --end clamped only");
    }
    Ok(())
}

/// The end condition asked for; `offset` only with `outer`, tangents only with `clamped`.
fn end_condition(
    end: EndArg,
    offset: Option<f64>,
    start_tangent: Option<Vec<f64>>,
    end_tangent: Option<Vec<f64>>,
) -> Result<EndCondition> {
    check_end_flags(
        end,
        offset.is_some(),
        start_tangent.is_some() || end_tangent.is_some(),
    )?;
    Ok(match end {
        EndArg::Repeat => EndCondition::Repeat,
        EndArg::Natural => EndCondition::Natural,
        EndArg::Clamped => EndCondition::Clamped {
            start: start_tangent,
            end: end_tangent,
        },
        EndArg::Bessel => EndCondition::Bessel,
        EndArg::NotAKnot => EndCondition::NotAKnot,
        EndArg::Periodic => EndCondition::Periodic,
        EndArg::Outer => {
            let offset = offset.unwrap_or(1.0);
            if !(offset.is_finite() && offset > 0.0) {
                bail!("--offset must be finite and > 0 (got {offset})");
            }
            EndCondition::OuterPoints { offset }
        }
    })
}

/// The parametrization asked for: chord length by default, uniform with the paper's repeated
/// ends (which need it).
fn parametrization(param: Option<ParamArg>, ends: &[EndArg]) -> Result<Parametrization> {
    let repeat = ends.contains(&EndArg::Repeat);
    Ok(match param {
        None if repeat => Parametrization::Uniform,
        None => Parametrization::ChordLength,
        Some(ParamArg::Uniform) => Parametrization::Uniform,
        Some(ParamArg::Chord) if !repeat => Parametrization::ChordLength,
        Some(ParamArg::Centripetal) if !repeat => Parametrization::Centripetal,
        Some(p) => bail!(
            "--end repeat (the paper's repeated end points) needs uniform parameters, not \
             --param {}",
            p.to_possible_value()
                .map_or_else(String::new, |v| v.get_name().to_string())
        ),
    })
}

fn param_name(p: Parametrization) -> &'static str {
    match p {
        Parametrization::Uniform => "uniform",
        Parametrization::ChordLength => "chord length",
        Parametrization::Centripetal => "centripetal",
        _ => "other",
    }
}

/// What was fitted, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fit {
    Curve,
    Surface,
}

/// Turns a library error of a fit into a message naming the input and the option at fault.
fn explain_fit(err: geomkit::Error, table: &Table, n: usize, fit: Fit, end: &str) -> anyhow::Error {
    let name = table.name();
    match (err, fit) {
        (geomkit::Error::TooFewPoints { got, min, .. }, Fit::Curve) => {
            anyhow!("{name}: too few points for --end {end}: got {got}, need at least {min}")
        }
        (geomkit::Error::TooFewPoints { got, min, .. }, Fit::Surface) => anyhow!(
            "{name}: too few grid rows or columns for --end {end}: got {got}, need at least {min}"
        ),
        (geomkit::Error::RepeatedPoint { index }, Fit::Curve) => {
            let next = if index + 1 >= n { 0 } else { index + 1 };
            anyhow!(
                "{name}: {} hold the same point; chord-length and centripetal parameters need \
                 distinct consecutive points (remove the duplicate or use --param uniform)",
                table.places(index, next)
            )
        }
        (geomkit::Error::RepeatedPoint { index }, Fit::Surface) => anyhow!(
            "{name}: grid lines {index} and {} coincide; chord-length and centripetal \
             parameters need distinct consecutive grid rows and columns (use --param uniform)",
            index + 1
        ),
        (other, _) => anyhow::Error::new(other).context(name),
    }
}

// ---------------------------------------------------------------------------------------------
// curve

/// What `interpolate curve -o` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CurveOutput {
    Json,
    Samples(TableFormat),
    Control(TableFormat),
    Svg,
}

fn table_format(path: &Path) -> Option<TableFormat> {
    match extension(path).as_deref() {
        Some("csv") => Some(TableFormat::Csv),
        Some("npy") => Some(TableFormat::Npy),
        _ => None,
    }
}

fn curve_output(args: &CurveArgs) -> Result<CurveOutput> {
    let Some(path) = args.output.as_deref() else {
        if args.control {
            bail!("--control writes control points to a .csv or .npy file: give -o OUT.csv|.npy");
        }
        return Ok(CurveOutput::Json);
    };
    let out = match (extension(path).as_deref(), table_format(path)) {
        (_, Some(f)) if args.control => CurveOutput::Control(f),
        (_, Some(f)) => CurveOutput::Samples(f),
        (Some("json"), _) => CurveOutput::Json,
        (Some("svg"), _) => CurveOutput::Svg,
        _ => bail!(
            "cannot tell the output format of {}: name it .json (the model), .csv or .npy \
             (points, or control points with --control) or .svg (a picture)",
            path.display()
        ),
    };
    if args.control && !matches!(out, CurveOutput::Control(_)) {
        bail!(
            "--control writes control points to a .csv or .npy file, not {}",
            path.display()
        );
    }
    if args.samples.is_some() && !matches!(out, CurveOutput::Samples(_)) {
        bail!(
            "--samples applies to sampled .csv/.npy output (not to {})",
            path.display()
        );
    }
    Ok(out)
}

fn curve(args: CurveArgs) -> Result<()> {
    let output = curve_output(&args)?;
    let samples = args.samples.unwrap_or(DEFAULT_CURVE_SAMPLES);
    if !(2..=MAX_CURVE_SAMPLES).contains(&samples) {
        bail!("--samples must be from 2 to {MAX_CURVE_SAMPLES} (got {samples})");
    }
    let degree = args.degree.unwrap_or(3);
    let per_end = args.left.is_some() || args.right.is_some() || args.knots.is_some();
    let scipy = match args.form {
        Some(FormArg::Scipy) => true,
        Some(FormArg::Extended) if degree != 3 || per_end => bail!(
            "--form extended is the paper's cubic with one --end: drop --degree {degree}, \
             --left, --right and --knots, or use --form scipy"
        ),
        Some(FormArg::Extended) => false,
        None => degree != 3 || per_end,
    };
    let progress = Progress::start();
    let (fit, table, about) = if scipy {
        match curve_scipy(&args, degree, output, &progress)? {
            Some(fit) => fit,
            // Streamed to its output.
            None => return Ok(()),
        }
    } else {
        match curve_extended(&args, output, &progress)? {
            Some(fit) => fit,
            // Streamed to its output.
            None => return Ok(()),
        }
    };
    let (curve, parameters) = (&fit.0, &fit.1[..]);
    let (n, dim) = (table.data.len() / curve.dim(), curve.dim());
    let dest = Destination::from_option(args.output.as_deref());
    match output {
        CurveOutput::Json => {
            progress.busy("writing");
            dest.write_with(|w| write_bspline_curve_json(w, curve, Some(parameters)))
        }
        CurveOutput::Samples(format) => {
            progress.busy("sampling");
            let mut points = vec![0.0; samples * dim];
            if (1..=3).contains(&curve.degree()) {
                curve
                    .sample_uniform_fd(samples, &mut points)
                    .context("forward-differenced sampling")?;
            } else {
                // In blocks, so that the bar moves (each point on its own: the same bits).
                let (a, b) = curve.domain();
                let ts = linspace(a, b, samples);
                progress.phase("sampling", samples as u64);
                for (t, out) in ts
                    .chunks(SAMPLE_BLOCK)
                    .zip(points.chunks_mut(SAMPLE_BLOCK * dim))
                {
                    curve.eval_many_par(t, out)?;
                    progress.inc(t.len() as u64);
                }
            }
            progress.phase("writing", samples as u64);
            dest.write_with(|w| {
                let mut sink = RowSink::start(w, format, &[samples, dim], &coordinate_names(dim))?;
                for rows in points.chunks(SAMPLE_BLOCK * dim) {
                    sink.push(w, rows)?;
                    progress.inc((rows.len() / dim) as u64);
                }
                sink.finish()
            })
        }
        CurveOutput::Control(format) => {
            progress.busy("writing");
            let out = args.output.as_deref().unwrap_or(Path::new(""));
            write_control_pair(out, format, curve)
        }
        CurveOutput::Svg => {
            if n > MAX_DRAWN_POINTS {
                bail!(
                    "{}: {n} points are too many to draw (at most {MAX_DRAWN_POINTS}); write \
                     .json, .csv or .npy instead",
                    table.name()
                );
            }
            let title = match curve.degree() {
                3 => format!("Interpolating cubic B-spline through {n} points"),
                k => format!("Interpolating B-spline of degree {k} through {n} points"),
            };
            let subtitle = format!(
                "{}: {about}, {} control points",
                file_name(&table.path),
                curve.n_control()
            );
            let fig = bspline_curve_figure(&title, &subtitle, curve, &table.data, parameters)?;
            dest.write(fig.render().as_bytes())
        }
    }
}

/// A fitted curve with the parameter of each input point.
type CurveFit = (BsplineCurve, Vec<f64>);

/// Samples of a curve evaluated or written between two steps of the bar.
const SAMPLE_BLOCK: usize = 1 << 16;

/// `--start-tangent` / `--end-tangent` of the points' dimension.
fn check_tangents(args: &CurveArgs, dim: usize, name: &str) -> Result<()> {
    for (flag, t) in [
        ("--start-tangent", &args.start_tangent),
        ("--end-tangent", &args.end_tangent),
    ] {
        if let Some(t) = t.as_ref().filter(|t| t.0.len() != dim) {
            bail!(
                "{flag} has {} coordinates but the points of {name} have {dim}",
                t.0.len()
            );
        }
    }
    Ok(())
}

/// Parameters from `--params FILE`: one column.
fn read_params(path: &Path, progress: &Progress) -> Result<Table> {
    let params = Table::read(path, progress)?;
    let (_, cols) = params.as_records()?;
    if cols != 1 {
        bail!(
            "{}: Expect x to be a 1D strictly increasing sequence: found {cols} columns; give \
             one parameter per line",
            params.name()
        );
    }
    Ok(params)
}

/// The paper's extended cubic (and the tiles); `None` when the tile solve streamed to the
/// output itself.
fn curve_extended(
    args: &CurveArgs,
    output: CurveOutput,
    progress: &Progress,
) -> Result<Option<(CurveFit, Table, String)>> {
    let end_text = end_name(args.end);
    let param = parametrization(args.param, &[args.end])?;
    let (start_tangent, end_tangent) = (
        args.start_tangent.as_ref().map(|v| v.0.clone()),
        args.end_tangent.as_ref().map(|v| v.0.clone()),
    );
    let end = end_condition(args.end, args.offset, start_tangent, end_tangent)?;
    let options = InterpolationOptions::default()
        .with_end(end)
        .with_parametrization(param);
    let tiles = match args.tile {
        None => None,
        Some(t) if t < MIN_TILE_SIZE => {
            bail!("--tile must be at least {MIN_TILE_SIZE} points (got {t})")
        }
        Some(_) if matches!(args.end, EndArg::Periodic | EndArg::Repeat) => bail!(
            "--tile takes natural, clamped, bessel, not-a-knot or outer ends (periodic and \
             repeat couple the whole curve; solve them without --tile, it is O(N) too)"
        ),
        Some(t) => Some(
            TileOptions::default()
                .with_tile_size(t)
                .with_halo(args.halo.unwrap_or(32)),
        ),
    };
    if let (Some(tiles), CurveOutput::Control(format), true) = (tiles, output, is_npy(&args.input))
    {
        let out = args.output.as_deref().unwrap_or(Path::new(""));
        stream_tiles(args, &options, &tiles, out, format, progress)?;
        return Ok(None);
    }

    let table = Table::read(&args.input, progress)?;
    let (n, dim) = table.as_records()?;
    check_tangents(args, dim, &table.name())?;
    let params = match &args.params {
        Some(_) if args.end == EndArg::Repeat => {
            bail!("--params cannot be used with --end repeat (it fixes its own parameters)")
        }
        Some(path) => Some(read_params(path, progress)?),
        None => None,
    };
    // The bar follows the library's hook (parameters, then the solve's chunks or tiles).
    progress.phase("solving", 0);
    let report = progress.reporter();
    let hook = geomkit::progress::Progress::new(&report);
    let fit = match (&tiles, &params) {
        (_, Some(params)) => {
            interpolate_curve_at_with_progress(dim, &table.data, &params.data, &options.end, &hook)
                .with_context(|| format!("{} with parameters from {}", table.name(), params.name()))
        }
        (Some(tiles), None) => {
            interpolate_curve_tiled_with_progress(dim, &table.data, &options, tiles, &hook)
                .map_err(|e| explain_fit(e, &table, n, Fit::Curve, &end_text))
        }
        (None, None) => interpolate_curve_flat_with_progress(dim, &table.data, &options, &hook)
            .map_err(|e| explain_fit(e, &table, n, Fit::Curve, &end_text)),
    }?;
    let parameters = fit.parameters().to_vec();
    let about = format!("end {end_text}, {} parameters", param_name(param));
    Ok(Some(((fit.into_curve(), parameters), table, about)))
}

/// Any degree in SciPy's representation ([`make_interp_spline`]): x the parameters (given or
/// from the points), conditions from --end, overridden per end by --left / --right.
fn curve_scipy(
    args: &CurveArgs,
    degree: usize,
    output: CurveOutput,
    progress: &Progress,
) -> Result<Option<(CurveFit, Table, String)>> {
    if degree > MAX_SPLINE_DEGREE {
        bail!("--degree must be from 0 to {MAX_SPLINE_DEGREE} (got {degree})");
    }
    let tiles = match args.tile {
        None => None,
        Some(t) if t < MIN_TILE_SIZE => {
            bail!("--tile must be at least {MIN_TILE_SIZE} points (got {t})")
        }
        Some(_) if args.end == EndArg::Periodic => bail!(
            "--tile takes open ends (periodic couples the whole curve; solve it without \
             --tile, it is O(N) too)"
        ),
        Some(_) if args.knots.is_some() => {
            bail!("--tile places SciPy's default knots; drop --knots or --tile")
        }
        Some(_) if degree == 0 => {
            bail!("--tile solves degrees 1 to 7 (degree 0 is the data itself); drop --tile")
        }
        Some(t) => Some(
            TileOptions::default()
                .with_tile_size(t)
                .with_halo(args.halo.unwrap_or(MIN_SPLINE_HALO)),
        ),
    };
    let end_text = end_name(args.end);
    if matches!(args.end, EndArg::Repeat | EndArg::Outer) {
        bail!(
            "--end {end_text} is the paper's cubic in the extended form; with --form scipy, \
             --degree, --left or --right use not-a-knot, natural, clamped, bessel or periodic"
        );
    }
    check_end_flags(
        args.end,
        args.offset.is_some(),
        args.start_tangent.is_some() || args.end_tangent.is_some(),
    )?;
    let periodic = args.end == EndArg::Periodic;
    if periodic && (args.left.is_some() || args.right.is_some()) {
        bail!("--left and --right set the ends of an open curve, not of --end periodic");
    }
    let param = parametrization(args.param, &[args.end])?;
    let base = |tangent: &Option<Vector>| match args.end {
        EndArg::Natural => EndSpec::natural(),
        EndArg::Clamped => EndSpec::Derivatives(vec![(
            1,
            tangent.as_ref().map_or(vec![0.0], |t| t.0.clone()),
        )]),
        EndArg::Bessel => EndSpec::Bessel,
        _ => EndSpec::NotAKnot,
    };
    let ends = if periodic {
        SplineEnds::Periodic
    } else {
        SplineEnds::Open {
            left: args
                .left
                .clone()
                .map_or_else(|| base(&args.start_tangent), |a| a.spec),
            right: args
                .right
                .clone()
                .map_or_else(|| base(&args.end_tangent), |a| a.spec),
        }
    };
    if let (Some(tiles), CurveOutput::Control(format), true, None) =
        (&tiles, output, is_npy(&args.input), &args.params)
    {
        if let Some(order) = [&args.left, &args.right]
            .into_iter()
            .find_map(|a| a.as_ref().and_then(|a| a.negative_order))
        {
            bail!("Bad boundary conditions: derivative order {order} is below 0; give orders 0..={degree}");
        }
        let out = args.output.as_deref().unwrap_or(Path::new(""));
        let options = SplineOptions::new(degree).with_ends(ends);
        stream_spline_tiles(&args.input, param, &options, tiles, out, format, progress)?;
        return Ok(None);
    }
    let table = Table::read(&args.input, progress)?;
    let (n, dim) = table.as_records()?;
    check_tangents(args, dim, &table.name())?;
    progress.busy("solving");
    // Periodic data end with the first point again (SciPy's y[-1] == y[0]); added here when
    // the points do not close themselves (to within SciPy's allclose).
    let data = &table.data;
    let closed = last_repeats_first(data, dim);
    let (x, source) = match &args.params {
        Some(path) => {
            let params = read_params(path, progress)?;
            let name = format!("{} with parameters from {}", table.name(), params.name());
            (params.data, name)
        }
        None => {
            let x = parameters(data, dim, param, periodic && !closed)
                .map_err(|e| explain_fit(e, &table, n, Fit::Curve, &end_text))?;
            (x, table.name())
        }
    };
    // Negative derivative orders, refused in SciPy's words now that the ends' x are known.
    for (arg, at, side) in [
        (&args.left, x.first(), "left"),
        (&args.right, x.last(), "right"),
    ] {
        if let (Some(order), Some(at)) = (arg.as_ref().and_then(|a| a.negative_order), at) {
            bail!(
                "{source}: Bad boundary conditions at {at} ({side} end): derivative order \
                 {order} is below 0; give orders 0..={degree}"
            );
        }
    }
    // N + 1 parameters of periodic data that do not close themselves: the last closes the
    // curve at the first point. Any other count is the library's to refuse ("Shapes of x").
    let y: std::borrow::Cow<[f64]> = if periodic && !closed && x.len() == n + 1 {
        let mut y = data.clone();
        y.extend_from_slice(&data[..dim]);
        y.into()
    } else {
        data.as_slice().into()
    };
    let mut options = SplineOptions::new(degree).with_ends(ends);
    if let Some(path) = &args.knots {
        let knots = Table::read(path, progress)?;
        let (_, cols) = knots.as_records()?;
        if cols != 1 {
            bail!(
                "{}: expected one knot per line, found {cols} columns",
                knots.name()
            );
        }
        options = options.with_knots(knots.data);
    }
    progress.phase("solving", 0);
    let report = progress.reporter();
    let hook = geomkit::progress::Progress::new(&report);
    let curve = match &tiles {
        Some(tiles) => make_interp_spline_tiled(&x, &y, dim, &options, tiles, &hook),
        None => make_interp_spline_with_progress(&x, &y, dim, &options, &hook),
    }
    .with_context(|| source.clone())?;
    let about = match &args.params {
        Some(_) => format!("degree {degree}, SciPy's form, end {end_text}, given parameters"),
        None => format!(
            "degree {degree}, SciPy's form, end {end_text}, {} parameters",
            param_name(param)
        ),
    };
    let mut x = x;
    x.truncate(n);
    Ok(Some(((curve, x), table, about)))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Writes a curve's control points to `out` and its knots to the sibling file, both
/// atomically (the knots are renamed into place first; if the control points then fail, the
/// knots file is removed again).
fn write_control_pair(out: &Path, format: TableFormat, curve: &BsplineCurve) -> Result<()> {
    let dim = curve.dim();
    let mut control = AtomicFile::create(out)?;
    let mut knots = AtomicFile::create(&knots_sibling(out))?;
    let what = |p: &Path| format!("cannot write {}", p.display());
    {
        let w = control.writer();
        let mut sink = RowSink::start(w, format, &[curve.n_control(), dim], &coordinate_names(dim))
            .with_context(|| what(out))?;
        sink.push(w, curve.control_flat())
            .and_then(|()| sink.finish())
            .with_context(|| what(out))?;
    }
    {
        let w = knots.writer();
        let mut sink = RowSink::start(w, format, &[curve.knots().len()], &["knot".to_string()])
            .with_context(|| what(out))?;
        sink.push(w, curve.knots())
            .and_then(|()| sink.finish())
            .with_context(|| what(out))?;
    }
    commit_pair(control, knots)
}

/// Owned reference points of a tile, from its write range (see `CurveTiler::plan`: data point
/// i is centred on control point i + 1, the ends own c_0 and c_(N+1)).
fn owned(write: &std::ops::Range<usize>, n: usize) -> (usize, usize) {
    let a = if write.start == 0 { 0 } else { write.start - 1 };
    let b = if write.end == n + 2 { n } else { write.end - 1 };
    (a, b)
}

/// The streaming tile solve: a reader thread reads each tile's points from the .npy input
/// (seek), this thread solves the tiles in order (each starting at the parameter the previous
/// tile computed for its first point, so that parameters and knots are bit for bit those of
/// the global solve), and a writer thread appends control points and knots to temporary files
/// renamed into place at the end. Memory: a few tiles.
fn stream_tiles(
    args: &CurveArgs,
    options: &InterpolationOptions,
    tiles: &TileOptions,
    out: &Path,
    format: TableFormat,
    progress: &Progress,
) -> Result<()> {
    let mut reader = NpyReader::open(&args.input)?;
    let name = args.input.display().to_string();
    let (n, dim) = match reader.header.shape[..] {
        [n] => (n, 1),
        [n, d] if d > 0 => (n, d),
        _ => bail!(
            "{name}: expected an array of shape (N, d) (one point per row), found {}",
            reader.header.shape_text()
        ),
    };
    check_tangents(args, dim, &name)?;
    let end_text = end_name(args.end);
    let tiler = CurveTiler::new(n, dim, options, tiles).map_err(|e| match e {
        geomkit::Error::TooFewPoints { got, min, .. } => {
            anyhow!("{name}: too few points for --end {end_text}: got {got}, need at least {min}")
        }
        other => anyhow::Error::new(other).context(name.clone()),
    })?;
    let plan = tiler.plan();
    let mut control = AtomicFile::create(out)?;
    let mut knots = AtomicFile::create(&knots_sibling(out))?;
    let wrote = |e: std::io::Error| {
        anyhow::Error::new(e).context(format!("cannot write {}", out.display()))
    };
    let mut control_sink = RowSink::start(
        control.writer(),
        format,
        &[n + 2, dim],
        &coordinate_names(dim),
    )
    .map_err(wrote)?;
    let mut knot_sink =
        RowSink::start(knots.writer(), format, &[n + 6], &["knot".to_string()]).map_err(wrote)?;
    progress.phase("solving", n as u64);

    let (solved, written) = std::thread::scope(|scope| {
        let plan = &plan;
        let (to_solver, from_reader) = mpsc::sync_channel::<Result<Vec<f64>>>(2);
        let (to_writer, from_solver) = mpsc::sync_channel::<(usize, TileSolution)>(2);
        scope.spawn(move || {
            for p in plan {
                let points = reader.read_range(p.read.start * dim..p.read.end * dim);
                let failed = points.is_err();
                if to_solver.send(points).is_err() || failed {
                    break;
                }
            }
        });
        let writer = scope.spawn(move || -> Result<(AtomicFile, AtomicFile)> {
            // The last two parameters written: the end knots continue their interval.
            let mut last = [0.0f64; 2];
            for (k, solution) in from_solver {
                let p = &plan[k];
                control_sink
                    .push(control.writer(), &solution.control)
                    .map_err(wrote)?;
                let (a, b) = owned(&p.write, n);
                let t = &solution.parameters[a - p.read.start..b - p.read.start];
                if k == 0 {
                    // As the global solve: t_0 - k·h0 with h0 = t_1 - t_0 (tiles hold >= 2 points).
                    let t_all = &solution.parameters;
                    let h0 = t_all[1] - t_all[0];
                    let lead: Vec<f64> = (1..=3).rev().map(|k| t_all[0] - k as f64 * h0).collect();
                    knot_sink.push(knots.writer(), &lead).map_err(wrote)?;
                }
                knot_sink.push(knots.writer(), t).map_err(wrote)?;
                for &v in t {
                    last = [last[1], v];
                }
                progress.inc((b - a) as u64);
            }
            let h1 = last[1] - last[0];
            let tail: Vec<f64> = (1..=3).map(|k| last[1] + k as f64 * h1).collect();
            knot_sink.push(knots.writer(), &tail).map_err(wrote)?;
            control_sink.finish().map_err(wrote)?;
            knot_sink.finish().map_err(wrote)?;
            Ok((control, knots))
        });
        let solved = (|| -> Result<()> {
            let mut t_start = 0.0;
            for (k, p) in plan.iter().enumerate() {
                let points = from_reader
                    .recv()
                    .map_err(|_| anyhow!("internal error: the reader stopped"))??;
                let solution = tiler.solve(p, &points, t_start).map_err(|e| match e {
                    geomkit::Error::RepeatedPoint { index } => anyhow!(
                        "{name}: rows {} and {} hold the same point; chord-length and \
                         centripetal parameters need distinct consecutive points (remove the \
                         duplicate or use --param uniform)",
                        p.read.start + index,
                        p.read.start + index + 1
                    ),
                    other => anyhow::Error::new(other).context(name.clone()),
                })?;
                if let Some(next) = plan.get(k + 1) {
                    t_start = solution.parameters[next.read.start - p.read.start];
                }
                if to_writer.send((k, solution)).is_err() {
                    // The writer failed; its error is reported below.
                    break;
                }
            }
            Ok(())
        })();
        drop(to_writer);
        drop(from_reader);
        let written = writer
            .join()
            .unwrap_or_else(|_| Err(anyhow!("internal error: the writer panicked")));
        (solved, written)
    });
    solved?;
    let (control, knots) = written?;
    commit_pair(control, knots)
}

// ---------------------------------------------------------------------------------------------
// surface

/// What `interpolate surface -o` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SurfaceOutput {
    Json,
    Samples(TableFormat),
    Obj,
    Svg,
}

fn surface_output(args: &SurfaceArgs) -> Result<SurfaceOutput> {
    let Some(path) = args.output.as_deref() else {
        return Ok(SurfaceOutput::Json);
    };
    let out = match (extension(path).as_deref(), table_format(path)) {
        (_, Some(f)) => SurfaceOutput::Samples(f),
        (Some("json"), _) => SurfaceOutput::Json,
        (Some("obj"), _) => SurfaceOutput::Obj,
        (Some("svg"), _) => SurfaceOutput::Svg,
        _ => bail!(
            "cannot tell the output format of {}: name it .json (the model), .csv or .npy \
             (a sample grid), .obj (a mesh) or .svg (a picture)",
            path.display()
        ),
    };
    if args.samples.is_some() && matches!(out, SurfaceOutput::Json | SurfaceOutput::Svg) {
        bail!(
            "--samples applies to .csv, .npy and .obj output (not to {})",
            path.display()
        );
    }
    Ok(out)
}

/// A grid of reference points read from a file.
struct Grid {
    table: Table,
    rows: usize,
    cols: usize,
    dim: usize,
}

fn read_grid(args: &SurfaceArgs, progress: &Progress) -> Result<Grid> {
    let table = Table::read(&args.input, progress)?;
    let name = table.name();
    if args.heights {
        let (rows, cols) = match table.shape[..] {
            [r, c] | [r, c, 1] => (r, c),
            _ => bail!(
                "{name}: heights need a matrix (R lines of C numbers, or .npy shape (R, C)), \
                 found shape {}",
                table.shape_text()
            ),
        };
        return Ok(Grid {
            table,
            rows,
            cols,
            dim: 1,
        });
    }
    let (rows, cols, dim) = match table.shape[..] {
        [r, c, d] => {
            for (flag, given, have) in [("--rows", args.rows, r), ("--cols", args.cols, c)] {
                if given.is_some_and(|g| g != have) {
                    bail!(
                        "{name}: {flag} {} does not match the array's shape {}",
                        given.unwrap_or(0),
                        table.shape_text()
                    );
                }
            }
            (r, c, d)
        }
        [n, d] => {
            let what = if table.is_npy() {
                "rows"
            } else {
                "points (lines)"
            };
            let (r, c) = match (args.rows, args.cols) {
                (Some(r), Some(c)) => (r, c),
                (Some(r), None) if r > 0 && n % r == 0 => (r, n / r),
                (None, Some(c)) if c > 0 && n % c == 0 => (n / c, c),
                (Some(g), None) | (None, Some(g)) => bail!(
                    "{name}: {n} {what} do not divide into {} of {g}",
                    if args.rows.is_some() {
                        "--rows"
                    } else {
                        "--cols"
                    }
                ),
                (None, None) if table.is_npy() => bail!(
                    "{name} has shape {}: a matrix of heights? add --heights; points of a \
                     grid? give --rows and --cols",
                    table.shape_text()
                ),
                (None, None) => bail!(
                    "{name}: give the grid size with --rows and --cols ({n} points of {d} \
                     coordinates), or --heights for a matrix of heights"
                ),
            };
            if r.checked_mul(c) != Some(n) {
                bail!(
                    "{name}: --rows {r} × --cols {c} = {} grid points, but the file has {n} {what}",
                    r.saturating_mul(c)
                );
            }
            (r, c, d)
        }
        _ => bail!(
            "{name}: expected points (R*C rows of d coordinates, or .npy shape (R, C, d)), \
             found shape {}",
            table.shape_text()
        ),
    };
    if dim == 0 {
        bail!("{name}: the points have no coordinates");
    }
    Ok(Grid {
        table,
        rows,
        cols,
        dim,
    })
}

/// A fitted surface, with the parameters of the grid rows and columns; heights keep their
/// grid coordinates as parameters.
struct SurfaceFit {
    surface: BsplineSurface,
    params_u: Vec<f64>,
    params_v: Vec<f64>,
    heights: bool,
}

fn surface(args: SurfaceArgs) -> Result<()> {
    let output = surface_output(&args)?;
    let Samples(k, l) = args
        .samples
        .unwrap_or(Samples(DEFAULT_SURFACE_SAMPLES, None));
    let l = l.unwrap_or(k);
    for s in [k, l] {
        if !(2..=MAX_SURFACE_SAMPLES).contains(&s) {
            bail!("--samples: each count must be from 2 to {MAX_SURFACE_SAMPLES} (got {k}x{l})");
        }
    }
    if k * l > MAX_GRID_POINTS {
        bail!("--samples {k}x{l} is too many points (at most {MAX_GRID_POINTS})");
    }
    let (end_u, end_v) = (
        args.end_u.unwrap_or(args.end),
        args.end_v.unwrap_or(args.end),
    );
    let ends_text = if end_u == end_v {
        end_name(end_u)
    } else {
        format!("{} (u), {} (v)", end_name(end_u), end_name(end_v))
    };
    let param = parametrization(args.param, &[end_u, end_v])?;
    let (cond_u, cond_v) = (
        end_condition(
            end_u,
            args.offset.filter(|_| end_u == EndArg::Outer),
            None,
            None,
        )?,
        end_condition(
            end_v,
            args.offset.filter(|_| end_v == EndArg::Outer),
            None,
            None,
        )?,
    );
    if args.offset.is_some() && end_u != EndArg::Outer && end_v != EndArg::Outer {
        bail!("--offset applies to --end outer only");
    }
    let tiles = match args.tile {
        None => None,
        Some(t) if t < MIN_TILE_SIZE => {
            bail!("--tile must be at least {MIN_TILE_SIZE} points (got {t})")
        }
        Some(_)
            if [end_u, end_v]
                .iter()
                .any(|e| matches!(e, EndArg::Periodic | EndArg::Repeat)) =>
        {
            bail!(
                "--tile takes natural, clamped, bessel, not-a-knot or outer ends (periodic and \
                 repeat couple the whole grid; solve them without --tile, it is O(N) too)"
            )
        }
        Some(t) => Some(
            TileOptions::default()
                .with_tile_size(t)
                .with_halo(args.halo.unwrap_or(TileOptions::default().halo)),
        ),
    };
    let spacing = (args.dx.unwrap_or(1.0), args.dy.unwrap_or(1.0));
    let origin = (args.x0.unwrap_or(0.0), args.y0.unwrap_or(0.0));
    if args.heights {
        if !(spacing.0.is_finite() && spacing.1.is_finite() && spacing.0 > 0.0 && spacing.1 > 0.0) {
            bail!("--dx and --dy must be finite and > 0");
        }
        if !(origin.0.is_finite() && origin.1.is_finite()) {
            bail!("--x0 and --y0 must be finite");
        }
        if matches!(end_u, EndArg::Periodic | EndArg::Repeat) {
            bail!("heights over a grid take natural, clamped, bessel, not-a-knot or outer ends");
        }
    }

    // SciPy's form (RectBivariateSpline, any degrees): heights, not-a-knot ends only.
    let degrees = match args.degree {
        None => (3, 3),
        Some(Degrees::One(k)) => (k, k),
        Some(Degrees::Two(k, l)) => (k, l),
    };
    let scipy = match args.form {
        Some(FormArg::Scipy) => true,
        Some(FormArg::Extended) if degrees != (3, 3) => {
            bail!("--form extended is the paper's bicubic: drop --degree, or use --form scipy")
        }
        Some(FormArg::Extended) => false,
        None => args.degree.is_some(),
    };
    if scipy {
        if !args.heights {
            bail!(
                "--form scipy and --degree take heights (--heights): SciPy's RectBivariateSpline"
            );
        }
        for k in [degrees.0, degrees.1] {
            if !(1..=MAX_SPLINE_DEGREE).contains(&k) {
                bail!("--degree must be from 1 to {MAX_SPLINE_DEGREE} (got {k})");
            }
        }
        if end_u != EndArg::NotAKnot || end_v != EndArg::NotAKnot {
            bail!(
                "--form scipy surfaces have not-a-knot ends (RectBivariateSpline's); drop \
                 --end {ends_text}"
            );
        }
    }
    let progress = Progress::start();
    let grid = read_grid(&args, &progress)?;
    let (rows, cols) = (grid.rows, grid.cols);
    let explain = |e: geomkit::Error| explain_fit(e, &grid.table, rows, Fit::Surface, &ends_text);
    let fit = if args.heights {
        let coords = |file: &Option<std::path::PathBuf>, n: usize, o: f64, h: f64| match file {
            Some(path) => read_params(path, &progress).map(|t| Some(t.data)),
            None if scipy => Ok(Some((0..n).map(|i| o + i as f64 * h).collect())),
            None => Ok(None),
        };
        let xs = coords(&args.x, rows, origin.0, spacing.0)?;
        let ys = coords(&args.y, cols, origin.1, spacing.1)?;
        let data = &grid.table.data;
        // The bar follows the library's hook (blocks of grid rows, then the other direction).
        progress.phase("solving", 0);
        let report = progress.reporter();
        let hook = geomkit::progress::Progress::new(&report);
        let surface = match (&xs, &ys) {
            (Some(xs), Some(ys)) if scipy => {
                make_interp_surface_with_progress(xs, ys, data, (rows, cols), degrees, &hook)
                    .with_context(|| grid.table.name())?
            }
            (None, None) => {
                let end = &cond_u;
                interpolate_heights_with_progress(data, rows, cols, origin, spacing, end, &hook)
                    .map_err(explain)?
            }
            _ => {
                let regular = |n: usize, o: f64, h: f64| (0..n).map(|i| o + i as f64 * h).collect();
                let xs = xs
                    .clone()
                    .unwrap_or_else(|| regular(rows, origin.0, spacing.0));
                let ys = ys
                    .clone()
                    .unwrap_or_else(|| regular(cols, origin.1, spacing.1));
                interpolate_heights_at_with_progress(data, &xs, &ys, &cond_u, &hook)
                    .with_context(|| grid.table.name())?
            }
        };
        let (params_u, params_v) = (
            xs.unwrap_or_else(|| (0..rows).map(|i| origin.0 + i as f64 * spacing.0).collect()),
            ys.unwrap_or_else(|| (0..cols).map(|j| origin.1 + j as f64 * spacing.1).collect()),
        );
        SurfaceFit {
            surface,
            params_u,
            params_v,
            heights: true,
        }
    } else {
        let options = SurfaceInterpolationOptions::default()
            .with_ends(cond_u, cond_v)
            .with_parametrization(param);
        progress.phase("solving", 0);
        let report = progress.reporter();
        let hook = geomkit::progress::Progress::new(&report);
        let data = &grid.table.data;
        let fit = match &tiles {
            Some(tiles) => interpolate_surface_tiled_with_progress(
                rows, cols, grid.dim, data, &options, tiles, &hook,
            ),
            None => {
                interpolate_surface_flat_with_progress(rows, cols, grid.dim, data, &options, &hook)
            }
        }
        .map_err(explain)?;
        SurfaceFit {
            surface: fit.surface,
            params_u: fit.params_u,
            params_v: fit.params_v,
            heights: false,
        }
    };
    let dest = Destination::from_option(args.output.as_deref());
    match output {
        SurfaceOutput::Json => {
            progress.busy("writing");
            dest.write_with(|w| {
                write_bspline_surface_json(w, &fit.surface, Some((&fit.params_u, &fit.params_v)))
            })
        }
        SurfaceOutput::Samples(format) => {
            write_sample_grid(&dest, format, &fit.surface, fit.heights, (k, l), &progress)
        }
        SurfaceOutput::Obj => write_obj(&dest, &fit.surface, (k, l), &progress),
        SurfaceOutput::Svg => {
            let svg = surface_picture(&fit, &grid, &ends_text, param)?;
            dest.write(svg.as_bytes())
        }
    }
}

/// Columns of a sample grid: the coordinates, or x,y,z for a height field.
fn grid_columns(surface: &BsplineSurface, heights: bool) -> Vec<String> {
    if heights {
        vec!["x".into(), "y".into(), "z".into()]
    } else {
        coordinate_names(surface.dim())
    }
}

/// Evaluates the K×L grid uniform over the domain in blocks of rows, handing each block (its
/// u values, the v values and the points, row-major) to `each`.
fn for_grid_blocks(
    surface: &BsplineSurface,
    (k, l): (usize, usize),
    progress: &Progress,
    mut each: impl FnMut(&[f64], &[f64], &[f64]) -> Result<()>,
) -> Result<()> {
    let ((u0, u1), (v0, v1)) = surface.domain();
    let (us, vs) = (linspace(u0, u1, k), linspace(v0, v1, l));
    let d = surface.dim();
    progress.phase("writing", k as u64);
    let mut block = vec![0.0; GRID_BLOCK * l * d];
    for rows in us.chunks(GRID_BLOCK) {
        let out = &mut block[..rows.len() * l * d];
        surface.eval_grid(rows, &vs, out)?;
        each(rows, &vs, out)?;
        progress.inc(rows.len() as u64);
    }
    Ok(())
}

fn write_sample_grid(
    dest: &Destination,
    format: TableFormat,
    surface: &BsplineSurface,
    heights: bool,
    (k, l): (usize, usize),
    progress: &Progress,
) -> Result<()> {
    if format == TableFormat::Npy && *dest == Destination::Stdout {
        bail!("internal error: .npy output needs a file");
    }
    let columns = grid_columns(surface, heights);
    let c = columns.len();
    let d = surface.dim();
    let mut failure = None;
    let result = dest.write_with(|w| {
        let mut sink = RowSink::start(w, format, &[k, l, c], &columns)?;
        let mut row = Vec::with_capacity(GRID_BLOCK * l * c);
        let r = for_grid_blocks(surface, (k, l), progress, |us, vs, pts| {
            if heights {
                row.clear();
                for (a, &u) in us.iter().enumerate() {
                    for (b, &v) in vs.iter().enumerate() {
                        row.extend_from_slice(&[u, v, pts[(a * vs.len() + b) * d]]);
                    }
                }
                sink.push(w, &row)?;
            } else {
                sink.push(w, pts)?;
            }
            Ok(())
        });
        if let Err(e) = r {
            failure = Some(e);
            return Err(std::io::Error::other("evaluation failed"));
        }
        sink.finish()
    });
    match failure {
        Some(e) => Err(e),
        None => result,
    }
}

/// A vertex position on the page of an OBJ: 3-D points as they are, 2-D with z = 0, heights
/// as (u, v, z).
fn obj_position(p: &[f64], u: f64, v: f64) -> [f64; 3] {
    match p.len() {
        1 => [u, v, p[0]],
        2 => [p[0], p[1], 0.0],
        _ => [p[0], p[1], p[2]],
    }
}

/// The unit normal S_u × S_v at (u, v) of the surface as drawn by [`obj_position`].
fn obj_normal(surface: &BsplineSurface, u: f64, v: f64) -> [f64; 3] {
    let d = surface.dim();
    let (mut a, mut b) = (vec![0.0; d], vec![0.0; d]);
    surface.eval_derivative(u, v, 1, 0, &mut a);
    surface.eval_derivative(u, v, 0, 1, &mut b);
    // For heights (u, v, z(u, v)): S_u = (1, 0, z_u), S_v = (0, 1, z_v).
    let (su, sv) = (obj_position(&a, 1.0, 0.0), obj_position(&b, 0.0, 1.0));
    let n = [
        su[1] * sv[2] - su[2] * sv[1],
        su[2] * sv[0] - su[0] * sv[2],
        su[0] * sv[1] - su[1] * sv[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        [n[0] / len, n[1] / len, n[2] / len]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// The K×L grid as a Wavefront OBJ: vertices and normals row by row, then two triangles per
/// cell, counter-clockwise around S_u × S_v.
fn write_obj(
    dest: &Destination,
    surface: &BsplineSurface,
    (k, l): (usize, usize),
    progress: &Progress,
) -> Result<()> {
    let d = surface.dim();
    if d > 3 {
        bail!("cannot write an OBJ mesh of a surface in R^{d} (1-, 2- or 3-D points only)");
    }
    let mut failure = None;
    let result = dest.write_with(|w| {
        writeln!(
            w,
            "# geomkit {}: bicubic B-spline surface sampled on a {k}x{l} grid",
            env!("CARGO_PKG_VERSION")
        )?;
        let r = for_grid_blocks(surface, (k, l), progress, |us, vs, pts| {
            for (a, &u) in us.iter().enumerate() {
                for (b, &v) in vs.iter().enumerate() {
                    let p = obj_position(&pts[(a * vs.len() + b) * d..][..d], u, v);
                    let n = obj_normal(surface, u, v);
                    writeln!(w, "v {:?} {:?} {:?}", p[0], p[1], p[2])?;
                    writeln!(w, "vn {:?} {:?} {:?}", n[0], n[1], n[2])?;
                }
            }
            Ok(())
        });
        if let Err(e) = r {
            failure = Some(e);
            return Err(std::io::Error::other("evaluation failed"));
        }
        for i in 0..k - 1 {
            for j in 0..l - 1 {
                let a = i * l + j + 1;
                let (b, c, e) = (a + l, a + l + 1, a + 1);
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
                writeln!(w, "f {a}//{a} {c}//{c} {e}//{e}")?;
            }
        }
        Ok(())
    });
    match failure {
        Some(e) => Err(e),
        None => result,
    }
}

/// The SVG of a fitted surface: a height map for heights, else a wireframe with the control
/// net and the reference points.
fn surface_picture(
    fit: &SurfaceFit,
    grid: &Grid,
    ends: &str,
    param: Parametrization,
) -> Result<String> {
    let s = &fit.surface;
    let (nu, nv) = s.net_size();
    let name = file_name(&grid.table.path);
    if fit.heights || s.dim() == 1 {
        let title = format!("Height field through {}×{} heights", grid.rows, grid.cols);
        let sub = format!("{name}: bicubic B-spline, end {ends}, {nu}×{nv} net");
        let cells = 128;
        return Ok(heightmap_svg(&title, &sub, s, cells, 10)?);
    }
    if grid.rows * grid.cols > MAX_DRAWN_POINTS {
        bail!(
            "{}: {}×{} points are too many to draw (at most {MAX_DRAWN_POINTS}); write .json, \
             .csv, .npy or .obj instead",
            grid.table.name(),
            grid.rows,
            grid.cols
        );
    }
    let title = format!(
        "Interpolating bicubic B-spline through {}×{} points",
        grid.rows, grid.cols
    );
    let sub = format!(
        "{name}: end {ends}, {} parameters, {nu}×{nv} control net",
        param_name(param)
    );
    let wire = Stroke::solid(palette::CURVE.color, 1.0);
    let mut layers = vec![Layer::Wireframe {
        surface: s,
        count: grid.rows.max(grid.cols).clamp(8, 24),
        stroke: wire,
        legend: "surface".into(),
    }];
    if nu * nv <= 60 * 60 {
        layers.push(Layer::Points {
            points: s.control_flat(),
            dim: s.dim(),
            grid: Some((nu, nv)),
            stroke: Some(palette::NEW_POLYGON.with_opacity(0.6)),
            vertex: palette::NEW_VERTEX,
            radius: 1.8,
            legend: format!("control net {nu}×{nv}"),
        });
    }
    layers.push(Layer::Points {
        points: &grid.table.data,
        dim: s.dim(),
        grid: None,
        stroke: None,
        vertex: REFERENCE,
        radius: 2.4,
        legend: format!("reference points {}×{}", grid.rows, grid.cols),
    });
    Ok(surface_svg(&title, &sub, &layers)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parametrization_defaults() {
        assert_eq!(
            parametrization(None, &[EndArg::Natural]).unwrap(),
            Parametrization::ChordLength
        );
        assert_eq!(
            parametrization(None, &[EndArg::Repeat]).unwrap(),
            Parametrization::Uniform
        );
        assert!(parametrization(Some(ParamArg::Chord), &[EndArg::Repeat]).is_err());
        assert_eq!(end_name(EndArg::NotAKnot), "not-a-knot");
    }

    #[test]
    fn owned_points_of_a_plan() {
        let opts = InterpolationOptions::default();
        let tiler = CurveTiler::new(
            10,
            1,
            &opts,
            &TileOptions::default().with_tile_size(4).with_halo(2),
        )
        .unwrap();
        let owned: Vec<(usize, usize)> = tiler.plan().iter().map(|p| owned(&p.write, 10)).collect();
        assert_eq!(owned, [(0, 4), (4, 8), (8, 10)]);
    }
}
