//! Timing driver of the side-by-side comparison of method 4 with SciPy
//! (`bash bench/compare_pointcalc.sh`): k-factor point-equation models against
//! RegularGridInterpolator, point-equation curves against BarycentricInterpolator.
//!
//! Usage: `pointcalc-compare CASE POINTS` with CASE one of
//! - `grid3x3` — 3 factors × 3 levels {0, 1/2, 1}, f(x) = e^(-x_0) sin(2 x_1) + x_2²;
//! - `grid5x7` — 5 factors × 7 Chebyshev levels (second kind) on [-1, 1],
//!   f(x) = exp(-|x|²/2) cos(x_0 + x_1 + ... + x_4);
//! - `runge160` — a curve through the Runge function 1/(1 + 25t²) at 160 Chebyshev points
//!   (second kind) on [-1, 1].
//!
//! The driver samples f at the nodes, times the setup (building the model from the node
//! values: the median of many), then the evaluation at POINTS pseudo-random points of the box
//! (sequential and parallel over all cores), and reports the largest error against f at those
//! points. Prints one JSON object (with `isa`: the instruction set of the evaluation kernels,
//! chosen at run time).

use geomkit::pointcalc::{Factor, Hypersurface, NodePreset, Nodes, PointEquation, PointOptions};
use std::hint::black_box;
use std::time::Instant;

/// SplitMix64 numbers in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Median seconds of `f` over repeated batches (at least `min_total` seconds in all).
fn time_median(mut f: impl FnMut(), min_total: f64) -> f64 {
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 5 || (start.elapsed().as_secs_f64() < min_total && times.len() < 10_000) {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn f3(x: &[f64]) -> f64 {
    (-x[0]).exp() * (2.0 * x[1]).sin() + x[2] * x[2]
}

fn f5(x: &[f64]) -> f64 {
    let r2: f64 = x.iter().map(|v| v * v).sum();
    let s: f64 = x.iter().sum();
    (-0.5 * r2).exp() * s.cos()
}

fn grid_case(name: &str, factors: Vec<Factor>, f: fn(&[f64]) -> f64, points: usize) -> String {
    let k = factors.len();
    let domain: Vec<(f64, f64)> = factors.iter().map(|f| f.nodes().domain()).collect();
    // The node values, sampled once (not timed): the experiment.
    let template = Hypersurface::from_fn(
        factors.clone(),
        1,
        |x, o| o[0] = f(x),
        &PointOptions::default(),
    )
    .expect("valid model");
    let values = template.values().to_vec();
    let setup = time_median(
        || {
            let m = Hypersurface::new(
                black_box(factors.clone()),
                1,
                black_box(values.clone()),
                &PointOptions::default(),
            )
            .expect("valid");
            black_box(m);
        },
        0.5,
    );
    let model = template;
    let mut rng = Rng(42);
    let xs: Vec<f64> = (0..points * k)
        .map(|i| {
            let (a, b) = domain[i % k];
            a + (b - a) * rng.next()
        })
        .collect();
    let mut out = vec![0.0; points];
    let eval_par = time_median(|| model.eval_many(&xs, &mut out).expect("ok"), 1.0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let eval_seq =
        pool.install(|| time_median(|| model.eval_many(&xs, &mut out).expect("ok"), 1.0));
    model.eval_many(&xs, &mut out).expect("ok");
    let max_err = xs
        .chunks_exact(k)
        .zip(&out)
        .map(|(x, y)| (y - f(x)).abs())
        .fold(0.0, f64::max);
    format!(
        "{{\"case\":\"{name}\",\"points\":{points},\"setup_s\":{setup:e},\"eval_seq_s\":{eval_seq:e},\
         \"eval_par_s\":{eval_par:e},\"threads\":{},\"max_err\":{max_err:e},\"isa\":\"{}\"}}",
        rayon::current_num_threads(),
        geomkit::pointcalc::evaluation_isa()
    )
}

fn runge(points: usize) -> String {
    let runge = |t: f64| 1.0 / (1.0 + 25.0 * t * t);
    let nodes = Nodes::preset(NodePreset::ChebyshevSecond, 160, -1.0, 1.0).expect("nodes");
    let pts: Vec<Vec<f64>> = nodes.values().iter().map(|&t| vec![runge(t)]).collect();
    let setup = time_median(
        || {
            let n = Nodes::new(black_box(nodes.values().to_vec())).expect("nodes");
            black_box(PointEquation::new(n, black_box(pts.clone())).expect("eq"));
        },
        0.5,
    );
    let eq = PointEquation::new(nodes, pts).expect("eq");
    let mut rng = Rng(7);
    let ts: Vec<f64> = (0..points).map(|_| -1.0 + 2.0 * rng.next()).collect();
    let mut out = vec![0.0; points];
    let eval_seq = time_median(|| eq.eval_params(&ts, &mut out).expect("ok"), 1.0);
    let max_err = ts
        .iter()
        .zip(&out)
        .map(|(t, y)| (y - runge(*t)).abs())
        .fold(0.0, f64::max);
    format!(
        "{{\"case\":\"runge160\",\"points\":{points},\"setup_s\":{setup:e},\"eval_seq_s\":{eval_seq:e},\
         \"max_err\":{max_err:e}}}"
    )
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (case, points) = match args.as_slice() {
        [_, case, points] => (case.as_str(), points.parse::<usize>().expect("POINTS")),
        _ => {
            eprintln!("usage: pointcalc-compare grid3x3|grid5x7|runge160 POINTS");
            std::process::exit(2);
        }
    };
    let line = match case {
        "grid3x3" => {
            let factors = (0..3)
                .map(|i| Factor::new(format!("x{i}"), Nodes::paper_half()))
                .collect();
            grid_case(case, factors, f3, points)
        }
        "grid5x7" => {
            let nodes = Nodes::preset(NodePreset::ChebyshevSecond, 7, -1.0, 1.0).expect("nodes");
            let factors = (0..5)
                .map(|i| Factor::new(format!("x{i}"), nodes.clone()))
                .collect();
            grid_case(case, factors, f5, points)
        }
        "runge160" => runge(points),
        _ => {
            eprintln!("unknown case {case}");
            std::process::exit(2);
        }
    };
    println!("{line}");
}
