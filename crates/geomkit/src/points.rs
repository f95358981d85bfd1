//! Validation of point arrays shared by all methods.

use crate::{Error, Result};

/// Checks a row-major point array: dimension >= 1, length a multiple of it, at least one
/// point, every number finite.
pub(crate) fn validate_points(what: &'static str, dim: usize, data: &[f64]) -> Result<()> {
    check_shape(what, dim, data)?;
    if let Some(k) = first_non_finite(data) {
        // One of `what`: "reference points" -> "reference point 7 is not a finite number".
        let one = match what {
            "control net" => "control net point",
            "reference grid" => "reference grid point",
            _ => what.strip_suffix('s').unwrap_or(what),
        };
        return Err(Error::NonFinite {
            what: one,
            index: k / dim,
        });
    }
    Ok(())
}

/// The checks of [`validate_points`] but finiteness: a dimension, points, whole points.
pub(crate) fn check_shape(what: &'static str, dim: usize, data: &[f64]) -> Result<()> {
    if dim == 0 {
        return Err(Error::ZeroDimension { what });
    }
    if data.is_empty() {
        return Err(Error::Empty { what });
    }
    if !data.len().is_multiple_of(dim) {
        return Err(Error::DimensionMismatch {
            what: "point",
            index: data.len() / dim,
            expected: dim,
            got: data.len() % dim,
        });
    }
    Ok(())
}

/// Copies `src` into `dst` (same length), large slices in parallel chunks: fresh memory
/// is then faulted in by every core.
pub(crate) fn par_copy(src: &[f64], dst: &mut [f64]) {
    const CHUNK: usize = 1 << 16;
    if src.len() >= 4 * CHUNK {
        use crate::par::*;
        dst.par_chunks_mut(CHUNK)
            .zip(src.par_chunks(CHUNK))
            .for_each(|(d, s)| d.copy_from_slice(s));
    } else {
        dst.copy_from_slice(src);
    }
}

/// The first i < `len` with `pred(i)`: in parallel chunks for large `len` (rayon's
/// per-item `position_first` costs more than most tests).
pub(crate) fn first_index(len: usize, pred: impl Fn(usize) -> bool + Sync) -> Option<usize> {
    const CHUNK: usize = 1 << 14;
    if len < 4 * CHUNK {
        return (0..len).find(|&i| pred(i));
    }
    use crate::par::*;
    (0..len.div_ceil(CHUNK))
        .into_par_iter()
        .find_map_first(|k| (k * CHUNK..((k + 1) * CHUNK).min(len)).find(|&i| pred(i)))
}

/// Index of the first non-finite number. Large inputs are first scanned in parallel by a
/// vectorizable test (0·x is NaN exactly for infinities and NaN, ±0 otherwise).
pub(crate) fn first_non_finite(data: &[f64]) -> Option<usize> {
    let suspect = |c: &[f64]| !all_finite(c);
    let any = if data.len() >= 1 << 16 {
        use crate::par::*;
        data.par_chunks(1 << 14).any(suspect)
    } else {
        suspect(data)
    };
    if any {
        data.iter().position(|x| !x.is_finite())
    } else {
        None
    }
}

/// Flattens `Vec<Vec<f64>>` points, checking that all have the same dimension.
pub(crate) fn flatten_points(what: &'static str, points: &[Vec<f64>]) -> Result<(usize, Vec<f64>)> {
    let first = points.first().ok_or(Error::Empty { what })?;
    let dim = first.len();
    let mut data = Vec::with_capacity(points.len() * dim);
    for (index, p) in points.iter().enumerate() {
        if p.len() != dim {
            return Err(Error::DimensionMismatch {
                what: "point",
                index,
                expected: dim,
                got: p.len(),
            });
        }
        data.extend_from_slice(p);
    }
    validate_points(what, dim, &data)?;
    Ok((dim, data))
}

/// Flattens a grid `grid[i][j]` of points of one dimension into (rows, cols, dim, row-major
/// data). Errors: empty grid or first row, ragged rows, mixed dimensions (naming the
/// flattened index), and whatever [`validate_points`] finds.
pub(crate) fn flatten_grid(
    what: &'static str,
    grid: &[Vec<Vec<f64>>],
) -> Result<(usize, usize, usize, Vec<f64>)> {
    let cols = grid.first().map_or(0, Vec::len);
    if cols == 0 {
        return Err(Error::Empty { what });
    }
    let dim = grid[0][0].len();
    let mut data = Vec::with_capacity(grid.len() * cols * dim);
    for (i, row) in grid.iter().enumerate() {
        if row.len() != cols {
            return Err(Error::RaggedNet {
                row: i,
                expected: cols,
                got: row.len(),
            });
        }
        for (j, p) in row.iter().enumerate() {
            if p.len() != dim {
                return Err(Error::DimensionMismatch {
                    what: "grid point",
                    index: i * cols + j,
                    expected: dim,
                    got: p.len(),
                });
            }
            data.extend_from_slice(p);
        }
    }
    validate_points(what, dim, &data)?;
    Ok((grid.len(), cols, dim, data))
}

/// Checks the arguments of a batched evaluation: a buffer of `count * dim` numbers and finite
/// parameters (`what` names them in the error).
pub(crate) fn check_eval_args(
    what: &'static str,
    params: &[f64],
    count: usize,
    dim: usize,
    out: &[f64],
) -> Result<()> {
    check_buffer(count, dim, out)?;
    check_finite(what, params)
}

/// Checks that a batched evaluation's buffer holds `count * dim` numbers.
pub(crate) fn check_buffer(count: usize, dim: usize, out: &[f64]) -> Result<()> {
    if out.len() != count * dim {
        return Err(Error::BufferSize {
            expected: count * dim,
            got: out.len(),
        });
    }
    Ok(())
}

/// Checks that every parameter is finite, naming the first that is not (`what` names them).
pub(crate) fn check_finite(what: &'static str, params: &[f64]) -> Result<()> {
    if all_finite(params) {
        return Ok(());
    }
    let index = params.iter().position(|t| !t.is_finite()).unwrap_or(0);
    Err(Error::NonFinite { what, index })
}

/// The unit normal a × b / |a × b| of two tangent vectors in R^3, `None` where they are
/// parallel or vanish (|a × b| <= 1e-14 |a| |b|).
pub(crate) fn unit_normal(a: &[f64], b: &[f64]) -> Option<[f64; 3]> {
    let n = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let len = crate::numeric::norm(&n);
    let scale = crate::numeric::norm(a) * crate::numeric::norm(b);
    if len == 0.0 || len <= 1e-14 * scale {
        return None;
    }
    Some([n[0] / len, n[1] / len, n[2] / len])
}

/// Whether every number of `c` is finite: sums of 0·x (NaN exactly for infinities and
/// NaN) in eight independent lanes, which vectorize (one running sum would wait for each
/// addition in turn).
#[inline]
pub(crate) fn all_finite(c: &[f64]) -> bool {
    let mut lanes = [0.0f64; 8];
    let mut blocks = c.chunks_exact(8);
    for b in &mut blocks {
        for (z, x) in lanes.iter_mut().zip(b) {
            *z += 0.0 * x;
        }
    }
    let rest = blocks.remainder().iter().fold(0.0, |z, x| z + 0.0 * x);
    lanes.iter().sum::<f64>() + rest == 0.0
}

/// Whether every number of `v` is finite and none is below the one before (`strict`: each
/// above the one before): one vectorizable pass (0·x is NaN exactly for infinities and
/// NaN), in parallel blocks for long `v` (the searches that name the first offender run
/// only when it fails).
pub(crate) fn finite_and_sorted(v: &[f64], strict: bool) -> bool {
    const BLOCK: usize = 1 << 14;
    let block = |b: usize| {
        let c = &v[b * BLOCK..((b + 1) * BLOCK + 1).min(v.len())];
        let pairs = c[1..].iter().zip(c);
        let sorted = if strict {
            pairs.fold(true, |ok, (b, a)| ok & (b > a))
        } else {
            pairs.fold(true, |ok, (b, a)| ok & (b >= a))
        };
        sorted && all_finite(c)
    };
    let blocks = v.len().div_ceil(BLOCK);
    if blocks <= 4 {
        return (0..blocks).all(block);
    }
    use crate::par::*;
    (0..blocks).into_par_iter().all(block)
}

/// Checks a knot vector for `n` control points of `degree`: the right count, finite,
/// non-decreasing, and a non-empty domain [knots[p], knots[n]].
pub(crate) fn check_knots(knots: &[f64], degree: usize, n: usize) -> Result<()> {
    if knots.len() != n + degree + 1 {
        return Err(Error::InvalidKnots {
            index: knots.len().min(n + degree + 1),
            reason: "need (control points + degree + 1) knots",
        });
    }
    if !finite_and_sorted(knots, false) {
        if let Some(index) = knots.iter().position(|k| !k.is_finite()) {
            return Err(Error::NonFinite {
                what: "knot",
                index,
            });
        }
        if let Some(index) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(Error::InvalidKnots {
                index: index + 1,
                reason: "knots must be non-decreasing",
            });
        }
    }
    if knots[n] <= knots[degree] {
        return Err(Error::InvalidKnots {
            index: degree,
            reason: "the domain [knots[p], knots[n]] is empty",
        });
    }
    if !(knots[knots.len() - 1] - knots[0]).is_finite() {
        // Differences of knots (in every basis function) and parameter steps would be
        // infinite: NaN points instead of a curve.
        return Err(Error::InvalidKnots {
            index: knots.len() - 1,
            reason: "the knots span more than f64 can represent (last - first overflows): \
                     scale the knots down",
        });
    }
    Ok(())
}
