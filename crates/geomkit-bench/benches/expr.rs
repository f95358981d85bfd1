//! Criterion benches of the expression engine (crates/geomkit-expr): building and printing
//! a 10×10 bicubic composite of formula (9), compiling it to a tape, and tape evaluation
//! of the paper's cube and of the composite.

use criterion::{criterion_group, criterion_main, Criterion};
use geomkit::expr::{fixtures, Format, Graph, Id, Tape};
use std::hint::black_box;

fn bicubic(n: usize) -> (Graph, Vec<Id>) {
    let mut g = Graph::new();
    let coef = fixtures::random_coef(1, (n, n), (3, 3), 3);
    let k = fixtures::uniform_knots(n);
    let roots = fixtures::composite_poly(&mut g, &k, &k, (3, 3), 3, coef);
    (g, roots)
}

fn points(n: usize, su: f64, sv: f64) -> (Vec<f64>, Vec<f64>) {
    let u = (0..n).map(|i| su * fixtures::unit(2 * i as u64)).collect();
    let v = (0..n)
        .map(|i| sv * fixtures::unit(2 * i as u64 + 1))
        .collect();
    (u, v)
}

fn build_print(c: &mut Criterion) {
    let mut group = c.benchmark_group("expr_build_print");
    group.bench_function("build_bicubic_10x10", |b| b.iter(|| bicubic(black_box(10))));
    let (g, roots) = bicubic(10);
    group.bench_function("print_sympy_bicubic_10x10", |b| {
        b.iter(|| {
            g.print_function("f", &["u", "v"], black_box(&roots), Format::Sympy)
                .unwrap()
        })
    });
    group.bench_function("print_c_inline_bicubic_10x10", |b| {
        b.iter(|| {
            roots
                .iter()
                .map(|r| g.print(*r, Format::C).unwrap().len())
                .sum::<usize>()
        })
    });
    group.bench_function("tape_bicubic_10x10", |b| {
        b.iter(|| Tape::new(&g, black_box(&roots), &["u", "v"]).unwrap())
    });
    group.finish();
}

fn eval(c: &mut Criterion) {
    let mut group = c.benchmark_group("expr_tape_eval");
    let mut g = Graph::new();
    let cube = fixtures::cube(&mut g);
    let tape = Tape::new(&g, &cube, &["u", "v"]).unwrap();
    let n = 1 << 16;
    let (u, v) = points(n, 4.0, 3.0);
    let mut out = vec![vec![0.0; n]; 3];
    group.bench_function("cube_65536", |b| {
        b.iter(|| {
            let mut o: Vec<&mut [f64]> = out.iter_mut().map(|x| x.as_mut_slice()).collect();
            tape.eval_batch(&[&u, &v], &mut o).unwrap()
        })
    });
    let (g, roots) = bicubic(10);
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    let n = 1 << 12;
    let (u, v) = points(n, 10.0, 10.0);
    let mut out = vec![vec![0.0; n]; 3];
    group.bench_function("bicubic_10x10_4096", |b| {
        b.iter(|| {
            let mut o: Vec<&mut [f64]> = out.iter_mut().map(|x| x.as_mut_slice()).collect();
            tape.eval_batch(&[&u, &v], &mut o).unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, build_print, eval);
criterion_main!(benches);
