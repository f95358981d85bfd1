//! Timing driver of the side-by-side comparison (`bash bench/compare_bezier.sh`).
//!
//! Usage: `bezier-compare CASES.json` (or `-` for stdin). Prints one JSON document to stdout:
//! `{"geomkit_version": .., "results": [{"id", "op", "ok", "error", "median_s", "min_s",
//! "samples", "calls_per_sample", "points"}]}`, where `points` are the output control points
//! (elevate, reduce, paper_formula) or the evaluated points (eval), and the times are per
//! call, medians over `samples` batches of `calls_per_sample` calls each.
//!
//! A case: `{"id": str, "op": "elevate" | "reduce" | "paper_formula" | "eval",
//! "points": [[f64; dim]; n+1], "target": degree (elevate/reduce/paper_formula),
//! "params": [f64] (eval), "samples": 15, "min_batch_seconds": 0.005,
//! "max_seconds": 5.0, "tolerance": null}`.
//! `reduce` is the exact reduction `BezierCurve::reduce_degree` (residual test with the
//! tolerance, default 1e-12); `paper_formula` is `paper_formula_f64` (the paper's formula
//! (10) evaluated naively in f64, kept for comparison).

use std::hint::black_box;
use std::io::Read;
use std::time::Instant;

use geomkit::bezier::{paper_formula_f64, BezierCurve};
use geomkit::geom::{BatchOptions, Curve};
use serde::{Deserialize, Serialize};

#[derive(Debug, Deserialize)]
struct Input {
    cases: Vec<Case>,
}

#[derive(Debug, Deserialize)]
struct Case {
    id: String,
    op: String,
    points: Vec<Vec<f64>>,
    #[serde(default)]
    target: Option<usize>,
    #[serde(default)]
    params: Option<Vec<f64>>,
    #[serde(default)]
    samples: Option<usize>,
    #[serde(default)]
    min_batch_seconds: Option<f64>,
    #[serde(default)]
    max_seconds: Option<f64>,
    #[serde(default)]
    tolerance: Option<f64>,
}

#[derive(Debug, Serialize)]
struct Outcome {
    id: String,
    op: String,
    ok: bool,
    error: Option<String>,
    median_s: Option<f64>,
    min_s: Option<f64>,
    samples: usize,
    calls_per_sample: usize,
    points: Vec<Vec<f64>>,
}

#[derive(Debug, Serialize)]
struct Output {
    geomkit_version: &'static str,
    results: Vec<Outcome>,
}

/// Runs `f` once (warm-up, gives the result), then `samples` batches of `inner` calls,
/// `inner` chosen so that a batch lasts at least `min_batch` seconds. Returns the result
/// and (median, min, samples, inner) per call.
fn time_it<T>(
    mut f: impl FnMut() -> T,
    samples: usize,
    min_batch: f64,
    max_seconds: f64,
) -> (T, f64, f64, usize, usize) {
    let start = Instant::now();
    let result = black_box(f());
    let first = start.elapsed().as_secs_f64().max(1e-9);
    let inner = ((min_batch / first).ceil() as usize).clamp(1, 10_000_000);
    // Keep the whole case under max_seconds, but take at least 3 samples.
    let budget_samples = (max_seconds / (first * inner as f64)).floor() as usize;
    let samples = samples.min(budget_samples).max(3);
    let mut times = Vec::with_capacity(samples);
    for _ in 0..samples {
        let t0 = Instant::now();
        for _ in 0..inner {
            black_box(f());
        }
        times.push(t0.elapsed().as_secs_f64() / inner as f64);
    }
    times.sort_by(f64::total_cmp);
    let median = if samples % 2 == 1 {
        times[samples / 2]
    } else {
        0.5 * (times[samples / 2 - 1] + times[samples / 2])
    };
    (result, median, times[0], samples, inner)
}

fn run_case(case: &Case) -> Outcome {
    let mut out = Outcome {
        id: case.id.clone(),
        op: case.op.clone(),
        ok: false,
        error: None,
        median_s: None,
        min_s: None,
        samples: 0,
        calls_per_sample: 0,
        points: Vec::new(),
    };
    let samples = case.samples.unwrap_or(15).max(1);
    let min_batch = case.min_batch_seconds.unwrap_or(0.005);
    let max_seconds = case.max_seconds.unwrap_or(5.0);
    let curve = match BezierCurve::new(case.points.clone()) {
        Ok(c) => c,
        Err(e) => {
            out.error = Some(e.to_string());
            return out;
        }
    };
    let dim = curve.dim();
    let target = case.target;
    let need_target = || target.ok_or_else(|| format!("op {:?} needs \"target\"", case.op));
    let result: Result<(Vec<f64>, f64, f64, usize, usize), String> = match case.op.as_str() {
        "elevate" => need_target().and_then(|n| {
            let (r, med, min, s, i) =
                time_it(|| curve.elevate_degree(n), samples, min_batch, max_seconds);
            r.map(|c| (c.points_flat().to_vec(), med, min, s, i))
                .map_err(|e| e.to_string())
        }),
        "reduce" => need_target().and_then(|n| {
            let (r, med, min, s, i) = time_it(
                || curve.reduce_degree(n, case.tolerance),
                samples,
                min_batch,
                max_seconds,
            );
            r.map(|c| (c.points_flat().to_vec(), med, min, s, i))
                .map_err(|e| e.to_string())
        }),
        "paper_formula" => need_target().map(|n| {
            let (r, med, min, s, i) = time_it(
                || paper_formula_f64(&curve, n),
                samples,
                min_batch,
                max_seconds,
            );
            (r, med, min, s, i)
        }),
        "eval" => match &case.params {
            None => Err("op \"eval\" needs \"params\"".to_string()),
            Some(ts) => {
                let mut buf = vec![0.0; ts.len() * dim];
                let (r, med, min, s, i) = time_it(
                    || curve.eval_batch(ts, &mut buf, &BatchOptions::sequential()),
                    samples,
                    min_batch,
                    max_seconds,
                );
                r.map(|()| (buf.clone(), med, min, s, i))
                    .map_err(|e| e.to_string())
            }
        },
        other => Err(format!("unknown op {other:?}")),
    };
    match result {
        Ok((flat, med, min, s, i)) => {
            out.ok = true;
            out.median_s = Some(med);
            out.min_s = Some(min);
            out.samples = s;
            out.calls_per_sample = i;
            out.points = flat.chunks_exact(dim).map(<[f64]>::to_vec).collect();
        }
        Err(e) => out.error = Some(e),
    }
    out
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: bezier-compare CASES.json (or - for stdin)")?;
    let text = if path == "-" {
        let mut s = String::new();
        std::io::stdin().read_to_string(&mut s)?;
        s
    } else {
        std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?
    };
    let input: Input = serde_json::from_str(&text)?;
    let results = input.cases.iter().map(run_case).collect();
    let output = Output {
        geomkit_version: env!("CARGO_PKG_VERSION"),
        results,
    };
    serde_json::to_writer(std::io::stdout().lock(), &output)?;
    println!();
    Ok(())
}
