//! The C and Rust printers' output is compiled (`/usr/bin/cc`, `rustc`) and run at 10^4
//! random points; every value matches `Graph::eval` within 1e-13 relative. Includes the
//! cube at (0.5, 1.5), where SymPy 1.14's `rust_code` output gives 2.875 instead of 0.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use geomkit_expr::{fixtures, parse, Format, Graph, Id};

const MIXED: &str = "sqrt(abs(u) + 1)*sin(v) + cos(u*v)^2 - tan(u/7) + exp(-v^2) + ln(1 + u^2) \
    + atan(u - v) + asin(v/10) - acos(u/5) + sign(u - 1/2)*sinh(u/3) + cosh(v/4) \
    + tanh(u)/(1 + v^2) + u^7 - 3*(1 + v^2)^-3 + pi*u/3 - abs(u - v)^3 + 0.1*u*v^5";

/// Roots: the cube (3), a 3×2 bicubic composite (3), a formula with every function (1).
fn cases(g: &mut Graph) -> Vec<Id> {
    let mut roots: Vec<Id> = fixtures::cube(g).to_vec();
    let coef = fixtures::random_coef(11, (3, 2), (3, 3), 3);
    let uk = fixtures::uniform_knots(3);
    let vk = fixtures::uniform_knots(2);
    roots.extend(fixtures::composite_poly(g, &uk, &vk, (3, 3), 3, coef));
    roots.push(parse(g, MIXED).unwrap());
    roots
}

fn points() -> Vec<(f64, f64)> {
    let mut pts = vec![(0.5, 1.5), (0.0, 0.0), (4.0, 3.0), (1.0, 1.0)];
    for i in 0..10_000 - pts.len() as u64 {
        pts.push((
            -0.5 + 5.0 * fixtures::unit(2 * i),
            -0.5 + 4.0 * fixtures::unit(2 * i + 1),
        ));
    }
    pts
}

fn input_text(pts: &[(f64, f64)]) -> String {
    let mut s = String::new();
    for (u, v) in pts {
        let _ = writeln!(s, "{u:?} {v:?}");
    }
    s
}

fn run(exe: &Path, input: &str) -> Vec<Vec<f64>> {
    // Through a file: writing all of stdin before reading stdout could fill both pipes.
    let path = exe.with_extension("in");
    std::fs::write(&path, input).unwrap();
    let out = Command::new(exe)
        .stdin(std::fs::File::open(&path).unwrap())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{} failed: {:?}",
        exe.display(),
        out.status
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| {
            l.split_whitespace()
                .map(|x| x.parse::<f64>().unwrap())
                .collect()
        })
        .collect()
}

fn check(g: &Graph, roots: &[Id], pts: &[(f64, f64)], got: &[Vec<f64>], what: &str) {
    assert_eq!(got.len(), pts.len(), "{what}: one line per point");
    for ((u, v), row) in pts.iter().zip(got) {
        assert_eq!(row.len(), roots.len());
        for (r, &x) in roots.iter().zip(row) {
            let want = g.eval(*r, &[("u", *u), ("v", *v)]).unwrap();
            let tol = 1e-13 * want.abs().max(1.0);
            assert!(
                (x - want).abs() <= tol,
                "{what} at ({u}, {v}): {x} vs eval {want}"
            );
        }
    }
    // The cube at (0.5, 1.5): exactly 0 (SymPy 1.14's rust_code gives 2.875).
    assert_eq!(got[0][0], 0.0, "{what}: cube x(0.5, 1.5)");
}

#[test]
fn c_output_compiles_and_matches_eval() {
    let mut g = Graph::new();
    let roots = cases(&mut g);
    let dir = tempfile::tempdir().unwrap();
    let mut src = String::from("#include <math.h>\n#include <stdio.h>\n\n");
    src.push_str(
        &g.print_function("f", &["u", "v"], &roots, Format::C)
            .unwrap(),
    );
    // The inline printer too, for every root.
    src.push_str("\nstatic void inline_f(double u, double v, double *out) {\n");
    for (i, r) in roots.iter().enumerate() {
        let _ = writeln!(src, "    out[{i}] = {};", g.print(*r, Format::C).unwrap());
    }
    src.push_str("}\n\n");
    let n = roots.len();
    let _ = write!(
        src,
        "int main(void) {{\n    double u, v, a[{n}], b[{n}];\n    while (scanf(\"%lf %lf\", &u, &v) == 2) {{\n        f(u, v, a);\n        inline_f(u, v, b);\n        for (int i = 0; i < {n}; i++) {{ if (a[i] != b[i] && !(fabs(a[i] - b[i]) <= 1e-13 * fmax(1.0, fabs(a[i])))) return 3; printf(\"%.17g \", a[i]); }}\n        printf(\"\\n\");\n    }}\n    return 0;\n}}\n"
    );
    let c = dir.path().join("f.c");
    std::fs::write(&c, &src).unwrap();
    let exe = dir.path().join("f");
    let st = Command::new("/usr/bin/cc")
        .args(["-O1", "-o"])
        .arg(&exe)
        .arg(&c)
        .arg("-lm")
        .status()
        .unwrap();
    assert!(st.success(), "cc failed on:\n{src}");
    let pts = points();
    let got = run(&exe, &input_text(&pts));
    check(&g, &roots, &pts, &got, "C");
}

#[test]
fn rust_output_compiles_and_matches_eval() {
    let mut g = Graph::new();
    let roots = cases(&mut g);
    let dir = tempfile::tempdir().unwrap();
    let mut src = String::from("#![allow(clippy::all, unused_parens)]\nuse std::io::BufRead;\n\n");
    src.push_str(
        &g.print_function("f", &["u", "v"], &roots, Format::Rust)
            .unwrap(),
    );
    let n = roots.len();
    src.push_str("\nfn inline_f(u: f64, v: f64) -> Vec<f64> {\n    vec![\n");
    for r in &roots {
        let _ = writeln!(src, "        {},", g.print(*r, Format::Rust).unwrap());
    }
    let _ = write!(
        src,
        "    ]\n}}\n\nfn main() {{\n    for line in std::io::stdin().lock().lines() {{\n        let line = line.unwrap();\n        let mut it = line.split_whitespace().map(|x| x.parse::<f64>().unwrap());\n        let (u, v) = (it.next().unwrap(), it.next().unwrap());\n        let a: [f64; {n}] = f(u, v);\n        let b = inline_f(u, v);\n        for i in 0..{n} {{ assert!(a[i] == b[i] || (a[i] - b[i]).abs() <= 1e-13 * a[i].abs().max(1.0)); print!(\"{{:?}} \", a[i]); }}\n        println!();\n    }}\n}}\n"
    );
    let rs = dir.path().join("f.rs");
    std::fs::write(&rs, &src).unwrap();
    let exe = dir.path().join("f");
    let out = Command::new("rustc")
        .args(["--edition", "2021", "-O", "-o"])
        .arg(&exe)
        .arg(&rs)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rustc failed: {}\n{src}",
        String::from_utf8_lossy(&out.stderr)
    );
    let pts = points();
    let got = run(&exe, &input_text(&pts));
    check(&g, &roots, &pts, &got, "Rust");
}
