//! Criterion benches of method 3, single formulas of composite surfaces
//! (spec/composite-surfaces.md): building and printing the formula of n×n bicubic composites,
//! the structural evaluator (points per second, up to 50×50 patches) and the formula through
//! the engine's tape on the same points.
//!
//! Run: `cargo bench -p geomkit-bench --bench compose -- --warm-up-time 1 --measurement-time 2`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use geomkit::bezier::BezierSurface;
use geomkit::compose::{bodies, CompositeSurface};
use geomkit::expr::Format;

/// An n×n composite of bicubic patches on uniform knots (deterministic, discontinuous).
fn composite(n: usize) -> CompositeSurface {
    let mut x = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let patches: Vec<Vec<BezierSurface>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let net = (0..4)
                        .map(|a| {
                            (0..4)
                                .map(|b| vec![(i * 3 + a) as f64, (j * 3 + b) as f64, rnd()])
                                .collect()
                        })
                        .collect();
                    BezierSurface::new(net).expect("finite net")
                })
                .collect()
        })
        .collect();
    let knots: Vec<f64> = (0..=n).map(|k| k as f64).collect();
    CompositeSurface::from_bezier(knots.clone(), knots, &patches).expect("valid grid")
}

fn grid_points(s: &CompositeSurface, k: usize) -> (Vec<f64>, Vec<f64>) {
    let ((u0, u1), (v0, v1)) = s.domain();
    let us = (0..k)
        .map(|a| u0 + (u1 - u0) * a as f64 / (k - 1) as f64)
        .collect();
    let vs = (0..k)
        .map(|b| v0 + (v1 - v0) * b as f64 / (k - 1) as f64)
        .collect();
    (us, vs)
}

/// Building the formula of an n×n bicubic composite and printing it (Maple, inline).
fn build_print(c: &mut Criterion) {
    let mut g = c.benchmark_group("compose_build_print");
    for n in [10usize, 20, 50] {
        let s = composite(n);
        g.bench_function(BenchmarkId::new("formula", n), |b| {
            b.iter(|| black_box(s.formula().expect("formula")))
        });
        let f = s.formula().expect("formula");
        g.bench_function(BenchmarkId::new("print_program_maple", n), |b| {
            b.iter(|| black_box(f.print_program(Format::Maple).unwrap()))
        });
    }
    g.finish();
}

/// The structural evaluator on a 1000×1000 grid (eval_grid, parallel rows) and on scattered
/// pairs (eval_many).
fn structural(c: &mut Criterion) {
    let mut g = c.benchmark_group("compose_structural");
    for n in [1usize, 10, 50] {
        let s = composite(n);
        let (us, vs) = grid_points(&s, 1000);
        let mut out = vec![0.0; us.len() * vs.len() * 3];
        g.throughput(Throughput::Elements((us.len() * vs.len()) as u64));
        g.bench_function(BenchmarkId::new("grid_1000x1000", n), |b| {
            b.iter(|| s.eval_grid(&us, &vs, &mut out).expect("grid"))
        });
        let uv: Vec<f64> = us
            .iter()
            .zip(vs.iter().rev())
            .flat_map(|(&u, &v)| [u, v])
            .collect();
        let uv: Vec<f64> = uv.iter().cycle().take(2 * 1_000_000).copied().collect();
        let mut out = vec![0.0; uv.len() / 2 * 3];
        g.bench_function(BenchmarkId::new("many_1e6", n), |b| {
            b.iter(|| s.eval_many(&uv, &mut out).expect("many"))
        });
    }
    g.finish();
}

/// The single formula through the engine's tape (what a user of the printed formula pays):
/// the cube and a 10×10 bicubic composite on 100 000 points.
fn formula_tape(c: &mut Criterion) {
    let mut g = c.benchmark_group("compose_formula_tape");
    let cube = bodies::cube().expect("cube").formula().expect("formula");
    let s = composite(10);
    let f10 = s.formula().expect("formula");
    let count = 100_000;
    for (name, f, (u1, v1)) in [
        ("cube", &cube, (4.0, 3.0)),
        ("bicubic_10x10", &f10, (10.0, 10.0)),
    ] {
        let us: Vec<f64> = (0..count).map(|k| u1 * (k % 317) as f64 / 316.0).collect();
        let vs: Vec<f64> = (0..count)
            .map(|k| v1 * (k / 317) as f64 / (count / 317) as f64)
            .collect();
        let mut out = vec![0.0; count * 3];
        g.throughput(Throughput::Elements(count as u64));
        g.bench_function(name, |b| {
            b.iter(|| f.eval_batch(&[&us, &vs], &mut out).expect("tape"))
        });
    }
    g.finish();
}

criterion_group!(benches, build_print, structural, formula_tape);
criterion_main!(benches);
