//! End-to-end tests of `geomkit pointcalc ...`: fit / eval / shares / optimize / formula on a
//! 3-factor experiment, curves and surfaces, and bad input (one error line naming the row,
//! non-zero exit, no output file).

mod common;

use common::{fails, geomkit, ok, stderr, write};
use serde_json::Value;
use std::fs;
use std::path::Path;

/// y = b·ln(a/10) + c b² - 0.01 a c on a 3×3×3 grid: quadratic in b and linear in c, so the
/// model is exact in b and c.
fn response(a: f64, b: f64, c: f64) -> f64 {
    b * (a / 10.0).ln() + c * b * b - 0.01 * a * c
}

fn experiments() -> String {
    let mut s = String::from("run,a,b,c,y\n");
    let mut run = 0;
    for a in [10.0, 20.0, 40.0] {
        for b in [0.1, 0.5, 0.9] {
            for c in [-1.0, 0.0, 1.0] {
                run += 1;
                s.push_str(&format!("{run},{a},{b},{c},{}\n", response(a, b, c)));
            }
        }
    }
    s
}

fn fitted(dir: &Path) {
    write(dir, "exp.csv", &experiments());
    ok(
        dir,
        &[
            "pointcalc",
            "fit",
            "exp.csv",
            "--factors",
            "a,b,c",
            "--response",
            "y",
            "-o",
            "model.json",
        ],
    );
}

#[test]
fn fit_eval_passes_through_the_experiments() {
    let dir = tempfile::tempdir().unwrap();
    fitted(dir.path());
    let model: Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("model.json")).unwrap()).unwrap();
    assert_eq!(model["type"], "pointcalc-model");
    assert_eq!(model["values"].as_array().unwrap().len(), 27);
    write(dir.path(), "at.csv", "c,b,a\n1,0.9,40\n0.5,0.3,15\n");
    let out = ok(dir.path(), &["pointcalc", "eval", "model.json", "at.csv"]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "a,b,c,y");
    let first: Vec<f64> = lines[1].split(',').map(|x| x.parse().unwrap()).collect();
    assert_eq!(first[..3], [40.0, 0.9, 1.0]);
    assert_eq!(first[3], response(40.0, 0.9, 1.0)); // an experimental point: exact
    let second: Vec<f64> = lines[2].split(',').map(|x| x.parse().unwrap()).collect();
    // Exact in b and c; in a a quadratic through ln(1), ln(2), ln(4): close to ln(1.5).
    assert!((second[3] - response(15.0, 0.3, 0.5)).abs() < 0.01);
}

#[test]
fn shares_sum_to_one_and_optimize_finds_the_corner() {
    let dir = tempfile::tempdir().unwrap();
    fitted(dir.path());
    let out = ok(
        dir.path(),
        &[
            "pointcalc",
            "shares",
            "model.json",
            "--at",
            "a=15,b=0.3,c=0.5",
        ],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    let shares = v["shares"].as_array().unwrap();
    assert_eq!(shares.len(), 27);
    let sum: f64 = shares.iter().map(|s| s["share"].as_f64().unwrap()).sum();
    assert!((sum - 1.0).abs() < 1e-14);
    assert_eq!(shares[0]["point"]["a"], 10.0);
    assert_eq!(shares[26]["point"]["c"], 1.0);
    let out = ok(
        dir.path(),
        &["pointcalc", "optimize", "model.json", "--max"],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["at"]["a"], 40.0);
    assert_eq!(v["at"]["b"], 0.9);
    assert_eq!(v["at"]["c"], 1.0);
    assert_eq!(v["value"].as_f64().unwrap(), response(40.0, 0.9, 1.0));
    assert_eq!(v["certified"], true);
    let out = ok(
        dir.path(),
        &["pointcalc", "optimize", "model.json", "--min"],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    assert!(v["value"].as_f64().unwrap() <= response(10.0, 0.9, -1.0) + 1e-12);
}

#[test]
fn formula_output() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "pts.json", "[[0,0],[1,2],[3,0]]");
    let out = ok(
        dir.path(),
        &[
            "pointcalc",
            "formula",
            "pts.json",
            "--nodes",
            "0,1/3,1",
            "--format",
            "sympy",
        ],
    );
    // Pasteable into Python: the import, the symbol, then the definitions.
    assert!(
        out.starts_with("from sympy import *\nt = symbols(\"t\")\nx = "),
        "{out}"
    );
    assert!(out.contains("Rational(1, 3)"), "{out}");
    fitted(dir.path());
    // The C output compiles as it is and gives `pointcalc eval`'s values.
    let out = ok(
        dir.path(),
        &["pointcalc", "formula", "model.json", "--format", "c"],
    );
    assert!(
        out.starts_with("#include <math.h>\ndouble y(double a, double b, double c) { return "),
        "{out}"
    );
    write(dir.path(), "at.csv", "a,b,c\n40,0.9,1\n15,0.3,0.5\n");
    let want: Vec<f64> = ok(dir.path(), &["pointcalc", "eval", "model.json", "at.csv"])
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse().unwrap())
        .collect();
    let main = format!(
        "{out}#include <stdio.h>\nint main(void) {{ printf(\"%.17g %.17g\\n\", y(40, 0.9, 1), y(15, 0.3, 0.5)); return 0; }}\n"
    );
    write(dir.path(), "y.c", &main);
    let cc = std::process::Command::new("/usr/bin/cc")
        .args(["-O1", "-o", "y", "y.c", "-lm"])
        .current_dir(dir.path())
        .status()
        .expect("a C compiler at /usr/bin/cc");
    assert!(cc.success(), "{main}");
    let run = std::process::Command::new(dir.path().join("y"))
        .output()
        .unwrap();
    let got: Vec<f64> = String::from_utf8(run.stdout)
        .unwrap()
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(got.len(), 2);
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-12 * w.abs().max(1.0), "{g} vs {w}");
    }
    // A usage error (clap's: exit code 2, with a hint line).
    let bad = geomkit(
        dir.path(),
        &["pointcalc", "formula", "model.json", "--format", "cobol"],
    );
    assert_eq!(bad.status.code(), Some(2));
    assert!(stderr(&bad).contains("unknown --format \"cobol\""));
}

#[test]
fn fit_with_exact_nodes_keeps_them_exact() {
    let dir = tempfile::tempdir().unwrap();
    // Levels written as rounded decimals, matched to the exact nodes 0, 1/3, 1.
    let mut csv = String::from("u,v,z\n");
    for u in ["0", "0.3333333333333333", "1"] {
        for v in ["0", "1"] {
            let z = u.parse::<f64>().unwrap() * 2.0 + v.parse::<f64>().unwrap();
            csv.push_str(&format!("{u},{v},{z}\n"));
        }
    }
    write(dir.path(), "e.csv", &csv);
    ok(
        dir.path(),
        &[
            "pointcalc",
            "fit",
            "e.csv",
            "--factors",
            "u,v",
            "--response",
            "z",
            "--nodes",
            "u=0,1/3,1",
            "-o",
            "m.json",
        ],
    );
    let model: Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("m.json")).unwrap()).unwrap();
    assert_eq!(
        model["factors"][0]["exact"],
        serde_json::json!(["0", "1/3", "1"])
    );
    let out = ok(
        dir.path(),
        &["pointcalc", "formula", "m.json", "--format", "maple"],
    );
    assert!(out.contains("1/3"), "{out}");
    // A level that is not one of the given nodes names its line.
    write(
        dir.path(),
        "e2.csv",
        "u,v,z\n0,0,1\n0.5,0,2\n1,0,3\n0,1,1\n0.5,1,2\n1,1,3\n",
    );
    let err = fails(
        dir.path(),
        &[
            "pointcalc",
            "fit",
            "e2.csv",
            "--factors",
            "u,v",
            "--response",
            "z",
            "--nodes",
            "u=0,1/3,1",
        ],
        None,
    );
    assert!(
        err.contains("e2.csv line 3: level u=0.5 is not one of the nodes"),
        "{err}"
    );
}

#[test]
fn curves_and_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "pts.json", r#"{"points":[[0,0],[1,2],[3,0]]}"#);
    ok(
        dir.path(),
        &[
            "pointcalc",
            "curve",
            "pts.json",
            "--nodes",
            "third",
            "-o",
            "c.svg",
        ],
    );
    assert!(fs::read_to_string(dir.path().join("c.svg"))
        .unwrap()
        .starts_with("<svg"));
    let out = ok(
        dir.path(),
        &[
            "pointcalc",
            "curve",
            "pts.json",
            "--nodes",
            "third",
            "--samples",
            "4",
        ],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    let s = v["samples"].as_array().unwrap();
    assert_eq!(s.len(), 4);
    // t = 1/3 is not a sample; t = 1 is B exactly.
    assert_eq!(s[3], serde_json::json!([1.0, 3.0, 0.0]));
    // A close C warns (Lebesgue constant) but succeeds; --strict fails.
    let warned = geomkit(
        dir.path(),
        &["pointcalc", "curve", "pts.json", "--nodes", "0,1/20,1"],
    );
    assert!(warned.status.success());
    assert!(stderr(&warned).starts_with("warning: the Lebesgue constant"));
    let strict = geomkit(
        dir.path(),
        &[
            "pointcalc",
            "curve",
            "pts.json",
            "--nodes",
            "0,1/20,1",
            "--strict",
            "-o",
            "s.json",
        ],
    );
    assert!(!strict.status.success());
    assert!(!dir.path().join("s.json").exists());

    let net = "[[[0,0,0],[1,0,0.5],[2,0,0]],[[0,1,0.5],[1,1,1.5],[2,1,0.3]],[[0,2,0],[1,2,0.6],[2,2,0.1]]]";
    write(dir.path(), "net.json", net);
    let out = ok(
        dir.path(),
        &[
            "pointcalc",
            "surface",
            "net.json",
            "--row-nodes",
            "third;half;two-thirds",
            "--across",
            "half",
            "--samples",
            "3",
        ],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    let pts = v["points"].as_array().unwrap();
    assert_eq!(pts.len(), 9);
    assert_eq!(pts[4], serde_json::json!([1.0, 1.0, 1.5])); // (1/2, 1/2): the centre point
    let out = ok(
        dir.path(),
        &[
            "pointcalc",
            "surface",
            "net.json",
            "--printed",
            "--samples",
            "3",
        ],
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_ne!(v["points"][4], serde_json::json!([1.0, 1.0, 1.5])); // misses it
    ok(
        dir.path(),
        &["pointcalc", "surface", "net.json", "-o", "s.svg"],
    );
    assert!(dir.path().join("s.svg").exists());
}

#[test]
fn bad_experiments_name_the_line_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            "a,b,y\n1,2,4\n1,x,5\n",
            "line 3: column 'b': \"x\" is not a finite number",
        ),
        (
            "a,b,y\n1,2,4\n1,3,5\n1,2,6\n2,2,1\n2,3,0\n",
            "line 4: duplicate cell a=1, b=2 (also line 2)",
        ),
        (
            "a,b,y\n1,2,4\n1,3,5\n2,2,1\n",
            "do not form a grid: no record for a=2, b=3",
        ),
        (
            "a,b,y\n1,2,4\n1,3\n",
            "line 3: 2 cells, but the header has 3",
        ),
        ("a,q,y\n1,2,4\n", "no column 'b' in the header"),
    ];
    for (text, want) in cases {
        write(dir.path(), "bad.csv", text);
        let err = fails(
            dir.path(),
            &[
                "pointcalc",
                "fit",
                "bad.csv",
                "--factors",
                "a,b",
                "--response",
                "y",
                "-o",
                "m.json",
            ],
            Some("m.json"),
        );
        assert!(err.contains(want), "{err} (want {want}, from {text:?})");
    }
    fitted(dir.path());
    let err = fails(
        dir.path(),
        &["pointcalc", "shares", "model.json", "--at", "a=1,b=2"],
        None,
    );
    assert!(err.contains("no value for factor 'c'"), "{err}");
    let err = fails(
        dir.path(),
        &[
            "pointcalc",
            "shares",
            "model.json",
            "--at",
            "a=1,b=2,c=3,d=4",
        ],
        None,
    );
    assert!(err.contains("unknown factor 'd'"), "{err}");
}

/// Responses near f64::MAX (issue 21): eval printed inf, optimize `"bound": null` with
/// `"certified": true`, formula INFINITY, curve samples null. Now the results are finite and
/// right, or refused with one error line naming the step.
#[test]
fn responses_near_the_f64_limit() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "m.json",
        r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1]}],"response":["y"],"values":[1e308,1.5e308,1e308]}"#,
    );
    write(d, "at.csv", "a\n0.25\n0.5\n");
    let out = ok(d, &["pointcalc", "eval", "m.json", "at.csv"]);
    // y(1/4) = 1e308 (1 + 0.5 · 4 · 1/4 · 3/4) = 1.375e308.
    let y: Vec<f64> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(
        (y[0] / 1.375e308 - 1.0).abs() < 1e-15 && y[1] == 1.5e308,
        "{out}"
    );
    let best: Value =
        serde_json::from_str(&ok(d, &["pointcalc", "optimize", "m.json", "--max"])).unwrap();
    assert_eq!(best["certified"], true);
    let (value, bound) = (
        best["value"].as_f64().unwrap(),
        best["bound"].as_f64().unwrap(),
    );
    assert!((value / 1.5e308 - 1.0).abs() < 1e-12 && bound >= value && bound.is_finite());
    let err = fails(
        d,
        &["pointcalc", "formula", "m.json", "--format", "c"],
        None,
    );
    assert!(err.contains("m.json") && err.contains("overflows"), "{err}");
    // Far outside the levels: the line of the point.
    write(d, "far.csv", "a\n0.5\n1e200\n");
    let err = fails(
        d,
        &["pointcalc", "eval", "m.json", "far.csv", "-o", "y.csv"],
        Some("y.csv"),
    );
    assert!(
        err.contains("far.csv line 3") && err.contains("a=1e200"),
        "{err}"
    );
}
