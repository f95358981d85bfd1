//! Shared fixtures of the geomkit benchmarks: deterministic test curves and nets (no
//! random-number dependency), used by the criterion benches (`benches/bezier.rs`,
//! `benches/bspline.rs`) and by the side-by-side timing drivers (`src/bin/bezier-compare.rs`,
//! `src/bin/bspline-compare.rs`).
//!
//! The B-spline fixtures ([`helix_points`], [`height_grid`], [`random_params`]) use only
//! `+ - * /` (correctly rounded in IEEE 754) on numbers from [`Fixture::at`], so
//! `bench/compare_bspline.py` rebuilds them bit for bit with numpy (same formulas, same
//! operation order) instead of passing gigabytes of data between the two sides.
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
        self.state = self.state.wrapping_add(GOLDEN_GAMMA);
        mix_to_unit(self.state)
    }

    /// The `k`-th number (0-based) of the sequence seeded with `seed`, without stepping
    /// through the ones before it: `Fixture::new(seed)` returns `Fixture::at(seed, 0)`,
    /// `Fixture::at(seed, 1)`, ... (SplitMix64 is counter-based, so numpy can vectorize it).
    pub fn at(seed: u64, k: u64) -> f64 {
        mix_to_unit(seed.wrapping_add(k.wrapping_add(1).wrapping_mul(GOLDEN_GAMMA)))
    }

    /// `count` numbers.
    pub fn take(&mut self, count: usize) -> Vec<f64> {
        (0..count).map(|_| self.next_f64()).collect()
    }
}

/// SplitMix64's increment.
const GOLDEN_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output function, mapped to [-1, 1) with 53 random bits.
#[inline]
fn mix_to_unit(state: u64) -> f64 {
    let mut z = state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
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

/// Point `i` of a closed curve walked `period` samples per turn: the rational
/// parametrization of the unit circle, x = (1 - s²)/(1 + s²), y = 2s/(1 + s²), with
/// s = w/(1 - w²), w = 2u - 1 ∈ (-1, 1), u = ((i mod period) + 0.5)/period (so one turn per
/// period, smooth across turns, no trigonometric functions: reproducible bit for bit).
#[inline]
pub fn circle_point(i: u64, period: u64) -> (f64, f64) {
    let u = ((i % period) as f64 + 0.5) / period as f64;
    let w = 2.0 * u - 1.0;
    let s = w / (1.0 - w * w);
    let s2 = s * s;
    ((1.0 - s2) / (1.0 + s2), 2.0 * s / (1.0 + s2))
}

/// Samples per turn of [`helix_points`] (fast winding) and of its slow height wave.
pub const HELIX_PERIODS: (u64, u64) = (64, 4099);

/// Amplitude of the noise added to [`helix_points`] and [`height_grid`].
pub const NOISE: f64 = 1e-3;

/// `n` points of a noisy helix-like curve in R³ (row-major, 3n numbers): point i is
/// (x1, y1, 0.5·y2) + 10⁻³·(r_3i, r_3i+1, r_3i+2), with (x1, y1) = [`circle_point`](i, 64),
/// (_, y2) = [`circle_point`](i, 4099) and r_k = [`Fixture::at`](seed, k). Bounded
/// (max |p| ≈ 1.1) for every n, about 17° of turn between neighbours.
pub fn helix_points(n: usize, seed: u64) -> Vec<f64> {
    let mut out = Vec::with_capacity(3 * n);
    for i in 0..n as u64 {
        let (x1, y1) = circle_point(i, HELIX_PERIODS.0);
        let (_, y2) = circle_point(i, HELIX_PERIODS.1);
        out.push(x1 + NOISE * Fixture::at(seed, 3 * i));
        out.push(y1 + NOISE * Fixture::at(seed, 3 * i + 1));
        out.push(0.5 * y2 + NOISE * Fixture::at(seed, 3 * i + 2));
    }
    out
}

/// Periods (in grid steps) of the waves of [`height_grid`]: rows, columns, diagonal.
pub const HEIGHT_PERIODS: (u64, u64, u64) = (257, 263, 61);

/// Heights on a `rows × cols` grid (row-major): z_ij = x(i, 257)·y(j, 263) +
/// 0.25·y(i + j, 61) + 10⁻³·r_(i·cols + j), with x, y from [`circle_point`] and r from
/// [`Fixture::at`](seed, ·). Smooth bumps plus noise, |z| ≤ 1.3.
pub fn height_grid(rows: usize, cols: usize, seed: u64) -> Vec<f64> {
    let mut out = Vec::with_capacity(rows * cols);
    for i in 0..rows as u64 {
        let (xi, _) = circle_point(i, HEIGHT_PERIODS.0);
        for j in 0..cols as u64 {
            let (_, yj) = circle_point(j, HEIGHT_PERIODS.1);
            let (_, yd) = circle_point(i + j, HEIGHT_PERIODS.2);
            out.push(xi * yj + 0.25 * yd + NOISE * Fixture::at(seed, i * cols as u64 + j));
        }
    }
    out
}

/// `count` parameters in [a, b]: a + (b - a)·((r_k + 1)·0.5), r_k = [`Fixture::at`](seed, k),
/// in generation order (unsorted).
pub fn random_params(count: usize, a: f64, b: f64, seed: u64) -> Vec<f64> {
    (0..count as u64)
        .map(|k| a + (b - a) * ((Fixture::at(seed, k) + 1.0) * 0.5))
        .collect()
}

/// `count` >= 2 equally spaced parameters over [a, b] as numpy's `linspace` (and geomkit's
/// `sample_uniform_fd`) computes them.
pub use geomkit::geom::uniform_params as linspace;
