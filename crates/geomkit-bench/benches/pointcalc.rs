//! Criterion benchmarks of method 4 (point equations): cardinal functions, curve evaluation,
//! k-factor model setup and evaluation (batched SIMD blocks, single points, shares), the
//! optimum search. `geomkit::pointcalc::evaluation_isa()` names the kernels' instruction set.
//!
//!     cargo bench -p geomkit-bench --bench pointcalc

use criterion::{criterion_group, criterion_main, Criterion};
use geomkit::pointcalc::{
    optimize, Factor, Goal, Hypersurface, NodePreset, Nodes, OptimizeOptions, PointEquation,
    PointOptions,
};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let cheb = Nodes::preset(NodePreset::ChebyshevSecond, 160, -1.0, 1.0).unwrap();
    let mut l = vec![0.0; 160];
    c.bench_function("basis 160 Chebyshev nodes", |b| {
        b.iter(|| cheb.basis_into(black_box(0.123), &mut l))
    });
    let pts: Vec<Vec<f64>> = cheb
        .values()
        .iter()
        .map(|t| vec![1.0 / (1.0 + 25.0 * t * t)])
        .collect();
    let eq = PointEquation::new(cheb.clone(), pts).unwrap();
    let ts: Vec<f64> = (0..10_000)
        .map(|i| -1.0 + 2.0 * i as f64 / 9999.0)
        .collect();
    let mut out = vec![0.0; ts.len()];
    c.bench_function("runge 160 nodes, 10k parameters", |b| {
        b.iter(|| eq.eval_params(black_box(&ts), &mut out).unwrap())
    });

    let factors: Vec<Factor> = (0..3)
        .map(|i| Factor::new(format!("x{i}"), Nodes::paper_half()))
        .collect();
    let f = |x: &[f64], o: &mut [f64]| o[0] = (-x[0]).exp() * (2.0 * x[1]).sin() + x[2] * x[2];
    let m3 = Hypersurface::from_fn(factors, 1, f, &PointOptions::default()).unwrap();
    let xs: Vec<f64> = (0..30_000).map(|i| (i as f64 * 0.618_034) % 1.0).collect();
    let mut out3 = vec![0.0; 10_000];
    c.bench_function("3x3x3 model, 10k points", |b| {
        b.iter(|| m3.eval_many(black_box(&xs), &mut out3).unwrap())
    });

    let nodes = Nodes::preset(NodePreset::ChebyshevSecond, 7, -1.0, 1.0).unwrap();
    let factors: Vec<Factor> = (0..5)
        .map(|i| Factor::new(format!("x{i}"), nodes.clone()))
        .collect();
    let g = |x: &[f64], o: &mut [f64]| {
        o[0] = (-0.5 * x.iter().map(|v| v * v).sum::<f64>()).exp() * x.iter().sum::<f64>().cos()
    };
    let m5 = Hypersurface::from_fn(factors.clone(), 1, g, &PointOptions::default()).unwrap();
    let values = m5.values().to_vec();
    c.bench_function("5x7 model setup", |b| {
        b.iter(|| {
            Hypersurface::new(
                black_box(factors.clone()),
                1,
                black_box(values.clone()),
                &PointOptions::default(),
            )
            .unwrap()
        })
    });
    let xs5: Vec<f64> = (0..5_000)
        .map(|i| ((i as f64 * 0.618_034) % 1.0) * 2.0 - 1.0)
        .collect();
    let mut out5 = vec![0.0; 1_000];
    c.bench_function("5x7 model, 1k points", |b| {
        b.iter(|| m5.eval_many(black_box(&xs5), &mut out5).unwrap())
    });
    c.bench_function("5x7 model, 1 point (eval)", |b| {
        b.iter(|| m5.eval(black_box(&xs5[..5])).unwrap())
    });
    c.bench_function("5x7 model, shares at 1 point", |b| {
        b.iter(|| m5.shares(black_box(&xs5[..5])).unwrap())
    });
    c.bench_function("3x3x3 optimum (max)", |b| {
        b.iter(|| optimize(&m3, Goal::Max, &OptimizeOptions::default()).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
