//! Criterion benches of the Bézier order change (spec/bezier-order.md).
//!
//! Run: `cargo bench -p geomkit-bench` (short run: append
//! `-- --warm-up-time 1 --measurement-time 2`; one group: append a filter, e.g. `-- elevate`).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use geomkit::bezier::ApproxOptions;
use geomkit::geom::{BatchOptions, Curve};
use geomkit_bench::{elevated_curve, random_curve, random_surface, uniform_params};

/// Elevation n -> n' in one step (closed form (8)), 2-D and 3-D.
fn elevate(c: &mut Criterion) {
    let mut g = c.benchmark_group("elevate");
    for dim in [2usize, 3] {
        for (n, n_new) in [(3usize, 4usize), (10, 20), (50, 100)] {
            let curve = random_curve(n, dim, 1);
            g.bench_with_input(
                BenchmarkId::new(format!("{dim}d"), format!("{n}to{n_new}")),
                &curve,
                |b, curve| b.iter(|| black_box(curve).elevate_degree(black_box(n_new)).unwrap()),
            );
        }
    }
    g.finish();
}

/// Exact reduction of an elevated curve back to its real degree (least squares + residual
/// test).
fn reduce_exact(c: &mut Criterion) {
    let mut g = c.benchmark_group("reduce_exact");
    for (n, real) in [(20usize, 10usize), (50, 30)] {
        let curve = elevated_curve(real, n, 2, 2);
        g.bench_with_input(
            BenchmarkId::new("2d", format!("{n}to{real}")),
            &curve,
            |b, curve| b.iter(|| black_box(curve).reduce_degree(real, None).unwrap()),
        );
    }
    g.finish();
}

/// Real degree and defect by the residual test (binary search over reductions), for an
/// elevated curve (defect > 0) and a random one (defect 0).
fn degree_report(c: &mut Criterion) {
    let mut g = c.benchmark_group("degree_report");
    for (n, real) in [(20usize, 10usize), (50, 30)] {
        let elevated = elevated_curve(real, n, 2, 3);
        g.bench_with_input(
            BenchmarkId::new("2d_elevated", format!("n{n}_real{real}")),
            &elevated,
            |b, curve| b.iter(|| black_box(curve).degree_report(None).unwrap()),
        );
        let full = random_curve(n, 2, 4);
        g.bench_with_input(
            BenchmarkId::new("2d_random", format!("n{n}")),
            &full,
            |b, curve| b.iter(|| black_box(curve).degree_report(None).unwrap()),
        );
    }
    g.finish();
}

/// Best L2 approximation of a lower degree, with its error report.
fn reduce_approx(c: &mut Criterion) {
    let mut g = c.benchmark_group("reduce_approx");
    let options = ApproxOptions::default();
    for (n, m) in [(12usize, 5usize), (30, 10)] {
        let curve = random_curve(n, 2, 5);
        g.bench_with_input(
            BenchmarkId::new("2d_l2", format!("{n}to{m}")),
            &curve,
            |b, curve| {
                b.iter(|| {
                    black_box(curve)
                        .reduce_degree_approx(m, black_box(&options))
                        .unwrap()
                })
            },
        );
    }
    g.finish();
}

/// eval_many (de Casteljau) at 10^4 parameters.
fn eval(c: &mut Criterion) {
    let mut g = c.benchmark_group("eval_many");
    let ts = uniform_params(10_000);
    g.throughput(Throughput::Elements(ts.len() as u64));
    for n in [3usize, 20] {
        let curve = random_curve(n, 2, 6);
        let mut out = vec![0.0; ts.len() * 2];
        g.bench_function(BenchmarkId::new("2d_1e4pts", format!("n{n}")), |b| {
            b.iter(|| {
                black_box(&curve)
                    .eval_batch(black_box(&ts), &mut out, &BatchOptions::sequential())
                    .unwrap();
                black_box(&out);
            })
        });
    }
    g.finish();
}

/// Surface order change (14), both directions.
fn surface(c: &mut Criterion) {
    let mut g = c.benchmark_group("surface_change_degree");
    // The paper's Fig. 5 situation: a (4,3) net of 5x4 points whose real u-degree is 3;
    // reduce u to 3 and elevate v to 6 at once.
    let fig5 = random_surface(3, 3, 3, 7)
        .change_degree(4, 3, None)
        .expect("elevation");
    g.bench_function("3d_(4,3)to(3,6)", |b| {
        b.iter(|| black_box(&fig5).change_degree(3, 6, None).unwrap())
    });
    let big = random_surface(10, 10, 3, 8);
    g.bench_function("3d_(10,10)to(15,15)", |b| {
        b.iter(|| black_box(&big).change_degree(15, 15, None).unwrap())
    });
    g.finish();
}

/// The bench group (in a module: `criterion_group!` generates an undocumented `pub fn`).
#[allow(missing_docs)]
mod group {
    use super::*;
    criterion_group!(
        benches,
        elevate,
        reduce_exact,
        degree_report,
        reduce_approx,
        eval,
        surface
    );
}
criterion_main!(group::benches);
