//! Shared helpers for the integration tests.
#![allow(dead_code, missing_docs)]

use geomkit::bezier::BezierCurve;
use geomkit::bspline::Parametrization;
use geomkit::geom::Curve;

/// Every parametrization of interpolation, for tests that loop over them.
pub const PARAMETRIZATIONS: [Parametrization; 3] = [
    Parametrization::Uniform,
    Parametrization::ChordLength,
    Parametrization::Centripetal,
];

/// Deterministic xorshift generator of numbers in [-1, 1).
pub struct Rng(pub u64);

impl Rng {
    /// The next number in [-1, 1).
    pub fn uniform(&mut self) -> f64 {
        let x = &mut self.0;
        *x ^= *x << 13;
        *x ^= *x >> 7;
        *x ^= *x << 17;
        (*x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// A pseudo-random curve of degree `n` in R^dim with coordinates in [-1, 1).
pub fn random_curve(n: usize, dim: usize, seed: u64) -> BezierCurve {
    let mut rng = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    BezierCurve::from_flat(dim, (0..dim * (n + 1)).map(|_| rng.uniform()).collect()).unwrap()
}

/// max over `count` uniform parameters of |a(t) - b(t)|.
pub fn sampled_distance(a: &impl Curve, b: &impl Curve, count: usize) -> f64 {
    let pa = a.sample_uniform(count);
    let pb = b.sample_uniform(count);
    let d = a.dim();
    pa.chunks_exact(d)
        .zip(pb.chunks_exact(d))
        .map(|(x, y)| {
            x.iter()
                .zip(y)
                .map(|(p, q)| (p - q) * (p - q))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// Largest coordinate difference between two point arrays.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
