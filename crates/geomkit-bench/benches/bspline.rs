//! Criterion benches of method 2, interpolating cubic B-splines
//! (spec/bspline-interpolation.md): the kernels at small sizes. The large sizes and the
//! comparison with SciPy are in `bash bench/compare_bspline.sh`.
//!
//! Run: `cargo bench -p geomkit-bench --bench bspline -- --warm-up-time 1 --measurement-time 2`
//! (about 1-2 min; one group: append a filter, e.g. `-- curve_build`).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use geomkit::bspline::{
    interpolate_curve_flat, interpolate_curve_tiled, interpolate_heights, BsplineCurve,
    EndCondition, InterpolationOptions, Parametrization, TileOptions,
};
use geomkit::geom::{BatchOptions, Curve};
use geomkit_bench::{height_grid, helix_points, linspace, random_params};

fn options(p: Parametrization) -> InterpolationOptions {
    InterpolationOptions::default()
        .with_end(EndCondition::NotAKnot)
        .with_parametrization(p)
}

fn curve(n: usize, p: Parametrization) -> BsplineCurve {
    interpolate_curve_flat(3, &helix_points(n, 1), &options(p))
        .expect("distinct points")
        .into_curve()
}

/// Curve interpolation through N 3-D points, not-a-knot: uniform parameters (Toeplitz fast
/// path), chord length (banded LU), and tiled (uniform, default tiles of 65 536 points).
fn curve_build(c: &mut Criterion) {
    let mut g = c.benchmark_group("curve_build");
    for n in [10_000usize, 100_000] {
        let points = helix_points(n, 1);
        g.throughput(Throughput::Elements(n as u64));
        for (name, p) in [
            ("uniform", Parametrization::Uniform),
            ("chord", Parametrization::ChordLength),
        ] {
            let opts = options(p);
            g.bench_with_input(BenchmarkId::new(name, n), &points, |b, pts| {
                b.iter(|| interpolate_curve_flat(3, black_box(pts), &opts).unwrap())
            });
        }
        let opts = options(Parametrization::Uniform);
        let tiles = TileOptions::default().with_tile_size(16_384);
        g.bench_with_input(BenchmarkId::new("tiled_16k", n), &points, |b, pts| {
            b.iter(|| interpolate_curve_tiled(3, black_box(pts), &opts, &tiles).unwrap())
        });
    }
    g.finish();
}

/// Evaluation of a 10^4-point curve at 10^5 parameters: forward differences on uniform
/// samples; `eval_many_par` on sorted and unsorted random parameters, and that of the
/// piecewise polynomial form (`to_piecewise`, also timed); the sequential
/// `eval_many` (sorted) for reference. Uniform knots (span by division) and chord-length
/// knots (binary search).
fn curve_eval(c: &mut Criterion) {
    let mut g = c.benchmark_group("curve_eval");
    let m = 100_000usize;
    g.throughput(Throughput::Elements(m as u64));
    for (name, p) in [
        ("uniform", Parametrization::Uniform),
        ("chord", Parametrization::ChordLength),
    ] {
        let crv = curve(10_000, p);
        let (a, b) = crv.domain();
        let mut out = vec![0.0; 3 * m];
        g.bench_function(BenchmarkId::new(format!("{name}_knots"), "fd_1e5"), |bch| {
            bch.iter(|| black_box(&crv).sample_uniform_fd(m, &mut out).unwrap())
        });
        let unsorted = random_params(m, a, b, 7);
        let mut sorted = unsorted.clone();
        sorted.sort_by(f64::total_cmp);
        let pp = crv.to_piecewise().unwrap();
        for (kind, ts) in [
            ("par_sorted_1e5", &sorted),
            ("par_unsorted_1e5", &unsorted),
            ("pp_sorted_1e5", &sorted),
            ("pp_unsorted_1e5", &unsorted),
        ] {
            g.bench_function(BenchmarkId::new(format!("{name}_knots"), kind), |bch| {
                bch.iter(|| {
                    if kind.starts_with("pp") {
                        black_box(&pp).eval_many_par(black_box(ts), &mut out)
                    } else {
                        black_box(&crv).eval_many_par(black_box(ts), &mut out)
                    }
                    .unwrap()
                })
            });
        }
        // Per piece, then back to per parameter.
        g.throughput(Throughput::Elements(pp.n_pieces() as u64));
        g.bench_function(
            BenchmarkId::new(format!("{name}_knots"), "to_piecewise"),
            |bch| bch.iter(|| black_box(&crv).to_piecewise().unwrap()),
        );
        g.throughput(Throughput::Elements(m as u64));
        g.bench_function(
            BenchmarkId::new(format!("{name}_knots"), "seq_sorted_1e5"),
            |bch| {
                bch.iter(|| {
                    black_box(&crv)
                        .eval_batch(
                            black_box(&sorted),
                            &mut out,
                            &BatchOptions::sequential().with_bit_exact(true),
                        )
                        .unwrap()
                })
            },
        );
    }
    g.finish();
}

/// Heights on a 256² grid: interpolation (not-a-knot, separable solves) and `eval_grid` on a
/// 256² grid of parameters.
fn surface(c: &mut Criterion) {
    let mut g = c.benchmark_group("surface");
    let n = 256usize;
    let z = height_grid(n, n, 3);
    let h = 1.0 / (n - 1) as f64;
    g.throughput(Throughput::Elements((n * n) as u64));
    g.bench_function("heights_build/256x256", |b| {
        b.iter(|| {
            interpolate_heights(
                black_box(&z),
                n,
                n,
                (0.0, 0.0),
                (h, h),
                &EndCondition::NotAKnot,
            )
            .unwrap()
        })
    });
    let s = interpolate_heights(&z, n, n, (0.0, 0.0), (h, h), &EndCondition::NotAKnot).unwrap();
    let ((u0, u1), (v0, v1)) = s.domain();
    let (us, vs) = (linspace(u0, u1, n), linspace(v0, v1, n));
    let mut out = vec![0.0; n * n];
    g.bench_function("eval_grid/256x256", |b| {
        b.iter(|| {
            black_box(&s)
                .eval_grid(black_box(&us), &vs, &mut out)
                .unwrap()
        })
    });
    g.finish();
}

/// The bench group (in a module: `criterion_group!` generates an undocumented `pub fn`).
#[allow(missing_docs)]
mod group {
    use super::*;
    criterion_group!(benches, curve_build, curve_eval, surface);
}
criterion_main!(group::benches);
