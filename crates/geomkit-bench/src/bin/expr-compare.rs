//! Timing driver of `bench/compare_expr.sh` (method 3's expression engine).
//!
//! `expr-compare CASE OUT_DIR` with CASE one of `cube`, `bilinear:N`, `bicubic:N` (an N×N
//! composite of formula (9), random patches from `geomkit::expr::fixtures::random_coef`
//! with seed 1) prints one JSON object:
//! `{"case", "build_s", "print_s" (SymPy + C + Rust function text), "ops", "tape_ops",
//! "tape_build_s", "points", "tape_pts_per_s", "compiled_pts_per_s", "compile_s",
//! "samples": [[u, v, x, y, z], ...]}` and writes `OUT_DIR/<case>.sympy.py` (the SymPy
//! program, parsed back by `compare_expr.py`). The compiled path: the engine's
//! `print_batch_rust` output compiled by `rustc -O -C target-cpu=native` into a timing
//! program (generated Rust, no unsafe, no JIT). Set `EXPR_NO_COMPILE=1` to skip it.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

use geomkit::expr::{fixtures, Format, Graph, Id, Tape};

fn build(case: &str, g: &mut Graph) -> Vec<Id> {
    if case == "cube" {
        return fixtures::cube(g).to_vec();
    }
    let (kind, n) = case.split_once(':').expect("case kind:N");
    let n: usize = n.parse().expect("N");
    let d = if kind == "bilinear" { 1 } else { 3 };
    let coef = fixtures::random_coef(1, (n, n), (d, d), 3);
    let k = fixtures::uniform_knots(n);
    fixtures::composite_poly(g, &k, &k, (d, d), 3, coef)
}

fn grid(case: &str) -> (Vec<f64>, Vec<f64>) {
    let (nu, nv, su, sv) = if case == "cube" {
        (1000, 1000, 4.0, 3.0)
    } else {
        let n: f64 = case.split_once(':').unwrap().1.parse().unwrap();
        (500, 400, n, n)
    };
    let mut u = Vec::with_capacity(nu * nv);
    let mut v = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            u.push(su * i as f64 / (nu - 1) as f64);
            v.push(sv * j as f64 / (nv - 1) as f64);
        }
    }
    (u, v)
}

fn median(mut t: Vec<f64>) -> f64 {
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    t[t.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("cube");
    let out_dir = Path::new(
        args.get(2)
            .map(String::as_str)
            .unwrap_or("bench/results/expr"),
    );
    std::fs::create_dir_all(out_dir).unwrap();
    let tag = case.replace(':', "_");

    let t = Instant::now();
    let mut g = Graph::new();
    let roots = build(case, &mut g);
    let build_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let sympy = g
        .print_function("f", &["u", "v"], &roots, Format::Sympy)
        .unwrap();
    let c = g
        .print_function("f", &["u", "v"], &roots, Format::C)
        .unwrap();
    let rust = g
        .print_function("f", &["u", "v"], &roots, Format::Rust)
        .unwrap();
    let print_s = t.elapsed().as_secs_f64();
    std::fs::write(out_dir.join(format!("{tag}.sympy.py")), &sympy).unwrap();

    let t = Instant::now();
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    let tape_build_s = t.elapsed().as_secs_f64();

    let (u, v) = grid(case);
    let n = u.len();
    let mut out = vec![vec![0.0; n]; roots.len()];
    let mut times = Vec::new();
    for _ in 0..5 {
        let t = Instant::now();
        let mut o: Vec<&mut [f64]> = out.iter_mut().map(|x| x.as_mut_slice()).collect();
        tape.eval_batch(&[&u, &v], &mut o).unwrap();
        times.push(t.elapsed().as_secs_f64());
    }
    let tape_pts = n as f64 / median(times);
    let checksum: f64 = out.iter().map(|o| o.iter().sum::<f64>()).sum();

    let samples: Vec<[f64; 5]> = (0..200)
        .map(|i| {
            let k = (i * 7919) % n;
            [u[k], v[k], out[0][k], out[1][k], out[2][k]]
        })
        .collect();

    let (compiled_pts, compile_s, compiled_checksum) =
        if std::env::var_os("EXPR_NO_COMPILE").is_some() {
            (f64::NAN, f64::NAN, f64::NAN)
        } else {
            compiled(&g, &roots, case, out_dir, &tag)
        };

    let mut json = String::new();
    let _ = write!(
        json,
        "{{\"case\": \"{case}\", \"build_s\": {build_s:e}, \"print_s\": {print_s:e}, \"print_bytes\": {{\"sympy\": {}, \"c\": {}, \"rust\": {}}}, \"ops\": {}, \"tape_ops\": {}, \"tape_registers\": {}, \"tape_build_s\": {tape_build_s:e}, \"points\": {n}, \"tape_pts_per_s\": {tape_pts:e}, \"checksum\": {checksum:e}, \"compiled_pts_per_s\": {}, \"compile_s\": {}, \"compiled_checksum\": {}, \"samples\": [",
        sympy.len(),
        c.len(),
        rust.len(),
        g.op_count(&roots),
        tape.len(),
        tape.registers(),
        js(compiled_pts),
        js(compile_s),
        js(compiled_checksum),
    );
    for (i, s) in samples.iter().enumerate() {
        let sep = if i == 0 { "" } else { ", " };
        let _ = write!(
            json,
            "{sep}[{:?}, {:?}, {:?}, {:?}, {:?}]",
            s[0], s[1], s[2], s[3], s[4]
        );
    }
    json.push_str("]}");
    println!("{json}");
}

fn js(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

/// Generated Rust: the batched function compiled with rustc into a timing program that
/// evaluates the same grid and prints `points_per_second checksum`.
fn compiled(g: &Graph, roots: &[Id], case: &str, dir: &Path, tag: &str) -> (f64, f64, f64) {
    let mut src = String::from("#![allow(clippy::all, unused_parens, unused_variables)]\n");
    src.push_str(&g.print_batch_rust("f", &["u", "v"], roots).unwrap());
    let (su, sv, nu, nv) = if case == "cube" {
        (4.0, 3.0, 1000, 1000)
    } else {
        let n: f64 = case.split_once(':').unwrap().1.parse().unwrap();
        (n, n, 500, 400)
    };
    let _ = write!(
        src,
        r#"
fn main() {{
    let (nu, nv) = ({nu}usize, {nv}usize);
    let mut u = Vec::new();
    let mut v = Vec::new();
    for i in 0..nu {{ for j in 0..nv {{ u.push({su:?} * i as f64 / (nu - 1) as f64); v.push({sv:?} * j as f64 / (nv - 1) as f64); }} }}
    let n = u.len();
    let (mut x, mut y, mut z) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut times = Vec::new();
    for _ in 0..5 {{
        let t = std::time::Instant::now();
        f(&u, &v, &mut x, &mut y, &mut z);
        times.push(t.elapsed().as_secs_f64());
    }}
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let s: f64 = x.iter().sum::<f64>() + y.iter().sum::<f64>() + z.iter().sum::<f64>();
    println!("{{:e}} {{:e}}", n as f64 / times[2], s);
}}
"#
    );
    let rs = dir.join(format!("{tag}_compiled.rs"));
    std::fs::write(&rs, &src).unwrap();
    let exe = dir.join(format!("{tag}_compiled"));
    let t = Instant::now();
    let st = Command::new("rustc")
        .args([
            "--edition",
            "2021",
            "-C",
            "opt-level=3",
            "-C",
            "target-cpu=native",
            "-o",
        ])
        .arg(&exe)
        .arg(&rs)
        .status()
        .unwrap();
    let compile_s = t.elapsed().as_secs_f64();
    assert!(st.success(), "rustc failed on {}", rs.display());
    let out = Command::new(&exe).output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let mut it = text.split_whitespace().map(|x| x.parse::<f64>().unwrap());
    (it.next().unwrap(), compile_s, it.next().unwrap())
}
