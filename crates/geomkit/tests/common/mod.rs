//! Shared helpers for the integration tests.
#![allow(dead_code, missing_docs)]

use geomkit::bezier::BezierCurve;
use geomkit::bspline::Parametrization;
use geomkit::compose::CompositeSurface;
use geomkit::geom::Curve;

mod numbers;
#[allow(unused_imports)]
pub use numbers::max_abs_diff;

/// Every parametrization of interpolation, for tests that loop over them.
pub const PARAMETRIZATIONS: [Parametrization; 3] = [
    Parametrization::Uniform,
    Parametrization::ChordLength,
    Parametrization::Centripetal,
];

/// b_ni(t), straight from the definition (independent of the library's evaluators).
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    let binom = (0..i).fold(1.0, |acc, k| acc * (n - k) as f64 / (k + 1) as f64);
    binom * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

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

/// Largest difference between the printed formula (tape), the literal formula, the
/// structural evaluator point by point and in batches, and the scale of the values.
pub fn disagreement(s: &CompositeSurface, us: &[f64], vs: &[f64]) -> (f64, f64) {
    let d = s.dim();
    let f = s.formula().unwrap();
    let (mut pu, mut pv, mut uv) = (Vec::new(), Vec::new(), Vec::new());
    for &u in us {
        for &v in vs {
            pu.push(u);
            pv.push(v);
            uv.extend([u, v]);
        }
    }
    let mut printed = vec![0.0; pu.len() * d];
    f.eval_batch(&[&pu, &pv], &mut printed).unwrap();
    let mut many = vec![0.0; pu.len() * d];
    s.eval_many(&uv, &mut many).unwrap();
    let mut grid = vec![0.0; pu.len() * d];
    s.eval_grid(us, vs, &mut grid).unwrap();
    let (mut worst, mut scale) = (0.0f64, 1.0f64);
    for k in 0..pu.len() {
        let literal = s.eval_formula(pu[k], pv[k]);
        let one = s.eval(pu[k], pv[k]);
        for c in 0..d {
            let x = literal[c];
            scale = scale.max(x.abs());
            for y in [printed[k * d + c], many[k * d + c], grid[k * d + c], one[c]] {
                worst = worst.max((x - y).abs());
            }
        }
    }
    (worst, scale)
}
