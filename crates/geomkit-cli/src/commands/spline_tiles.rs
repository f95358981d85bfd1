//! `geomkit interpolate curve --tile T` for SciPy's representation (any degree 1..7): the
//! streaming solve of [`SplineTiler`], reading each tile's points from a .npy input (seek),
//! computing their parameters from the previous tile's (bit for bit the global ones), and
//! appending the coefficients and knots to temporary files renamed into place only when
//! every tile succeeded. Memory: a few tiles, whatever N.

use crate::model::knots_sibling;
use crate::npy::NpyReader;
use crate::output::{commit_pair, coordinate_names, AtomicFile, RowSink, TableFormat};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Result};
use geomkit::bspline::TileOptions;
use geomkit::bspline::{parameters_from, Parametrization, SplineOptions, SplineTile, SplineTiler};
use std::path::Path;
use std::sync::mpsc;

/// Streams the tiles of `options` over the points of the .npy `input` into the control
/// points file `out` and its knots sibling.
pub(super) fn stream_spline_tiles(
    input: &Path,
    param: Parametrization,
    options: &SplineOptions,
    tiles: &TileOptions,
    out: &Path,
    format: TableFormat,
    progress: &Progress,
) -> Result<()> {
    let mut reader = NpyReader::open(input)?;
    let name = input.display().to_string();
    let (n, dim) = match reader.header.shape[..] {
        [n] => (n, 1),
        [n, d] if d > 0 => (n, d),
        _ => bail!(
            "{name}: expected an array of shape (N, d) (one point per row), found {}",
            reader.header.shape_text()
        ),
    };
    let tiler = SplineTiler::new(n, dim, options, tiles)
        .map_err(|e| anyhow::Error::new(e).context(format!("{name}: --tile")))?;
    let plan = tiler.plan();
    let mut control = AtomicFile::create(out)?;
    let mut knots = AtomicFile::create(&knots_sibling(out))?;
    let wrote = |e: std::io::Error| {
        anyhow::Error::new(e).context(format!("cannot write {}", out.display()))
    };
    let mut control_sink = RowSink::start(
        control.writer(),
        format,
        &[tiler.n_coefficients(), dim],
        &coordinate_names(dim),
    )
    .map_err(wrote)?;
    let mut knot_sink = RowSink::start(
        knots.writer(),
        format,
        &[tiler.n_knots()],
        &["knot".to_string()],
    )
    .map_err(wrote)?;
    progress.phase("solving", tiler.n_coefficients() as u64);

    let (solved, written) = std::thread::scope(|scope| {
        let plan = &plan;
        let (to_solver, from_reader) = mpsc::sync_channel::<Result<Vec<f64>>>(2);
        let (to_writer, from_solver) = mpsc::sync_channel::<SplineTile>(2);
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
            for tile in from_solver {
                control_sink
                    .push(control.writer(), &tile.coefficients)
                    .map_err(wrote)?;
                knot_sink.push(knots.writer(), &tile.knots).map_err(wrote)?;
                progress.inc((tile.coefficients.len() / dim) as u64);
            }
            control_sink.finish().map_err(wrote)?;
            knot_sink.finish().map_err(wrote)?;
            Ok((control, knots))
        });
        let solved = (|| -> Result<()> {
            // The parameter of the next tile's first point, from the tile before (tiles read
            // overlapping, increasing stretches).
            let mut t_start = 0.0;
            for (k, p) in plan.iter().enumerate() {
                let points = from_reader
                    .recv()
                    .map_err(|_| anyhow!("internal error: the reader stopped"))??;
                let x = parameters_from(&points, dim, param, t_start).map_err(|e| match e {
                    geomkit::Error::RepeatedPoint { index } => anyhow!(
                        "{name}: rows {} and {} hold the same point; chord-length and \
                         centripetal parameters need distinct consecutive points (remove the \
                         duplicate or use --param uniform)",
                        p.read.start + index,
                        p.read.start + index + 1
                    ),
                    other => anyhow::Error::new(other).context(name.clone()),
                })?;
                let tile = tiler
                    .solve(p, &x, &points)
                    .map_err(|e| anyhow::Error::new(e).context(format!("{name}: --tile")))?;
                if let Some(next) = plan.get(k + 1) {
                    t_start = x[next.read.start - p.read.start];
                }
                if to_writer.send(tile).is_err() {
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
