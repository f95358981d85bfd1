//! Shared fixtures of the geomkit benchmarks: deterministic test curves and nets (no
//! random-number dependency), used by the criterion benches (`benches/bezier.rs`) and by
//! the side-by-side timing driver (`src/bin/bezier-compare.rs`).
//!
//! This crate is never tested: it has no test targets, so `cargo test --workspace` does
//! not build its dev-dependency criterion (see `Cargo.toml`).

use geomkit::bezier::{BezierCurve, BezierSurface};

/// A small deterministic generator (SplitMix64) of numbers in [-1, 1).
#[derive(Debug, Clone)]
pub struct Fixture {
    state: u64,
}

impl Fixture {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Fixture { state: seed }
    }

    /// Next number, uniform in [-1, 1) with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// `count` numbers.
    pub fn take(&mut self, count: usize) -> Vec<f64> {
        (0..count).map(|_| self.next_f64()).collect()
    }
}

/// A curve of `degree` in R^`dim` with control points uniform in [-1, 1)^dim.
pub fn random_curve(degree: usize, dim: usize, seed: u64) -> BezierCurve {
    BezierCurve::from_flat(dim, Fixture::new(seed).take((degree + 1) * dim)).expect("finite points")
}

/// A curve of formal degree `degree` and real degree `real` < `degree`: a random curve of
/// degree `real` elevated (so it reduces exactly back to `real`).
pub fn elevated_curve(real: usize, degree: usize, dim: usize, seed: u64) -> BezierCurve {
    random_curve(real, dim, seed)
        .elevate_degree(degree)
        .expect("elevation to a higher degree")
}

/// A surface of degrees (n, m) in R^`dim` with net points uniform in [-1, 1)^dim.
pub fn random_surface(n: usize, m: usize, dim: usize, seed: u64) -> BezierSurface {
    BezierSurface::from_flat(
        n + 1,
        m + 1,
        dim,
        Fixture::new(seed).take((n + 1) * (m + 1) * dim),
    )
    .expect("finite net")
}

/// `count` >= 2 parameters k / (count - 1), k = 0..count.
pub fn uniform_params(count: usize) -> Vec<f64> {
    let count = count.max(2);
    (0..count).map(|k| k as f64 / (count - 1) as f64).collect()
}
