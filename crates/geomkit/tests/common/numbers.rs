//! Number comparisons shared by the integration tests of every crate (the CLI's tests include
//! this file from their own `common`). Standard library only.

/// Largest |a_k - b_k| of two equally long arrays (of coordinates: flatten points with
/// `concat()`).
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "arrays of different lengths");
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
