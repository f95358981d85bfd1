//! Criterion benches of tessellation and the mesh writers (geomkit::mesh).
//!
//! Run: `cargo bench -p geomkit-bench --bench mesh` (short run: append
//! `-- --warm-up-time 1 --measurement-time 2`).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use geomkit::bezier::BezierCurve;
use geomkit::compose::bodies;
use geomkit::mesh::{
    tessellate_curve, tessellate_surface, write_glb, write_obj, write_stl_binary, CurveOptions,
    SurfaceOptions,
};
use geomkit_bench::random_surface;

/// Uniform grids of the cube (welding, crease normals, watertight check) and of a bicubic
/// Bézier surface.
fn uniform(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh_uniform");
    let cube = bodies::cube().unwrap();
    let bez = random_surface(3, 3, 3, 1);
    for k in [65usize, 257] {
        g.throughput(Throughput::Elements((k * k) as u64));
        g.bench_with_input(BenchmarkId::new("cube", k), &k, |b, &k| {
            b.iter(|| tessellate_surface(black_box(&cube), &SurfaceOptions::uniform(k, k)).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("bezier3x3", k), &k, |b, &k| {
            b.iter(|| tessellate_surface(black_box(&bez), &SurfaceOptions::uniform(k, k)).unwrap())
        });
    }
    g.finish();
}

/// Adaptive sampling of a bicubic surface and of a quintic curve.
fn adaptive(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh_adaptive");
    let bez = random_surface(3, 3, 3, 2);
    for tol in [1e-3, 1e-4] {
        g.bench_with_input(BenchmarkId::new("bezier3x3", tol), &tol, |b, &tol| {
            b.iter(|| tessellate_surface(black_box(&bez), &SurfaceOptions::adaptive(tol)).unwrap())
        });
    }
    let curve = BezierCurve::new(vec![
        vec![10., 0.],
        vec![22., 6.],
        vec![19., 12.],
        vec![11., 15.],
        vec![8., 12.],
        vec![20., 0.],
    ])
    .unwrap();
    for tol in [1e-3, 1e-6] {
        g.bench_with_input(BenchmarkId::new("quintic", tol), &tol, |b, &tol| {
            b.iter(|| {
                tessellate_curve(
                    black_box(&curve),
                    &CurveOptions::default().with_tolerance(tol),
                )
                .unwrap()
            })
        });
    }
    g.finish();
}

/// Writers on a 257×257 cube mesh (~130k triangles) into memory.
fn writers(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh_write");
    let mesh =
        tessellate_surface(&bodies::cube().unwrap(), &SurfaceOptions::uniform(257, 257)).unwrap();
    g.throughput(Throughput::Elements(mesh.triangles().len() as u64));
    g.bench_function("obj", |b| {
        b.iter(|| {
            let mut v = Vec::new();
            write_obj(black_box(&mesh), &mut v).unwrap();
            v
        })
    });
    g.bench_function("stl_binary", |b| {
        b.iter(|| {
            let mut v = Vec::new();
            write_stl_binary(black_box(&mesh), &mut v).unwrap();
            v
        })
    });
    g.bench_function("glb", |b| {
        b.iter(|| {
            let mut v = Vec::new();
            write_glb(black_box(&mesh), &mut v).unwrap();
            v
        })
    });
    g.finish();
}

criterion_group!(benches, uniform, adaptive, writers);
criterion_main!(benches);
