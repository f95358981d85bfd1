//! Validation of point arrays shared by all methods.

use crate::{Error, Result};

/// Checks a row-major point array: dimension >= 1, length a multiple of it, at least one
/// point, every number finite.
pub(crate) fn validate_points(what: &'static str, dim: usize, data: &[f64]) -> Result<()> {
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
    if let Some(k) = data.iter().position(|x| !x.is_finite()) {
        return Err(Error::NonFinite {
            what: "control point",
            index: k / dim,
        });
    }
    Ok(())
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
