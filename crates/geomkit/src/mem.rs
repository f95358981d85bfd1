//! Large output buffers.

/// `len` zeros for a large result that the caller's threads then fill.
pub(crate) fn zeros(len: usize) -> Vec<f64> {
    vec![0.0; len]
}
