//! Every model type the tools write is read by `eval`, `mesh` and `render` through one reader
//! (the model crate), and a malformed file is refused alike by every command, in one line
//! naming the file, the JSON path and the problem.

mod common;

use common::{fails, ok, run_ok, write};
use std::path::Path;

/// Rows of a CSV on standard output, header first.
fn csv(out: &str) -> (String, Vec<Vec<f64>>) {
    let mut lines = out.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// y = 2a + b² - ab over a = 0, 1, 2 and b = 0, 1, 2, 3: quadratic in a (3 levels) and in b,
/// so the model is y itself.
fn y(a: f64, b: f64) -> f64 {
    2.0 * a + b * b - a * b
}

fn pointcalc_model(d: &Path) {
    let mut s = String::from("a,b,y\n");
    for a in [0.0, 1.0, 2.0] {
        for b in [0.0, 1.0, 2.0, 3.0] {
            s.push_str(&format!("{a},{b},{}\n", y(a, b)));
        }
    }
    write(d, "exp.csv", &s);
    run_ok(
        d,
        &[
            "pointcalc",
            "fit",
            "exp.csv",
            "--factors",
            "a,b",
            "--response",
            "y",
            "-o",
            "model.json",
        ],
    );
}

#[test]
fn eval_reads_a_point_calculus_model() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    pointcalc_model(d);
    // At given factor values: the model reproduces the quadratic (exact at the levels,
    // within rounding between them).
    write(d, "at.csv", "0,0\n2,3\n0.5,2.5\n1.75,0.25\n");
    let (header, rows) = csv(&ok(d, &["eval", "model.json", "--at", "at.csv"]));
    assert_eq!(header, "a,b,y");
    assert_eq!(rows.len(), 4);
    for r in &rows {
        assert!((r[2] - y(r[0], r[1])).abs() < 1e-13, "{r:?}");
    }
    assert_eq!(rows[1][2], y(2.0, 3.0));
    // A grid of K levels per factor over the factors' box.
    let (_, rows) = csv(&ok(d, &["eval", "model.json", "--samples", "3"]));
    assert_eq!(rows.len(), 9);
    assert_eq!(rows[0][..2], [0.0, 0.0]);
    assert_eq!(rows[8][..2], [2.0, 3.0]);
    assert_eq!(rows[5][..2], [1.0, 3.0]);
    for r in &rows {
        assert!((r[2] - y(r[0], r[1])).abs() < 1e-13, "{r:?}");
    }
    // Outside the box: refused, naming the value.
    write(d, "far.csv", "0,0\n5,1\n");
    let err = fails(d, &["eval", "model.json", "--at", "far.csv"], None);
    assert!(err.contains("a = 5 is outside the domain [0, 2]"), "{err}");
    // The same model meshes (two factors: the surface (a, b, y)).
    run_ok(
        d,
        &["mesh", "model.json", "-o", "m.obj", "--samples", "5x5"],
    );
}

#[test]
fn a_malformed_model_is_refused_by_every_command_alike() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The issue's case: `mesh` dropped the string, `pointcalc eval` refused the file.
    write(
        d,
        "bad.json",
        r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1,"oops"]}],"response":["y"],"values":[1,2,3,4]}"#,
    );
    write(d, "at.csv", "a\n0.5\n");
    let want = "bad.json: factors[0].nodes[3] is the string \"oops\"";
    for args in [
        &["mesh", "bad.json", "-o", "out.obj"][..],
        &["render", "bad.json", "-o", "out.svg"],
        &["eval", "bad.json", "--samples", "3"],
        &["pointcalc", "eval", "bad.json", "at.csv"],
        &["pointcalc", "formula", "bad.json", "--format", "sympy"],
    ] {
        let err = fails(d, args, Some("out.obj"));
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(err.contains("(line 1, column"), "{args:?}: {err}");
    }
    // An unknown field is refused, not dropped.
    write(
        d,
        "typo.json",
        r#"{"type":"ruled","v":[0,1],"curves":[{"point":[0,0,0]},{"circle":{"center":[0,0,1],"radius":1}}],"U":[0,2]}"#,
    );
    for args in [
        &["eval", "typo.json", "--samples", "3"][..],
        &["mesh", "typo.json", "-o", "t.obj"],
        &["compose", "ruled", "typo.json"],
    ] {
        let err = fails(d, args, Some("t.obj"));
        assert!(err.contains("unknown field \"U\""), "{args:?}: {err}");
    }
}

#[test]
fn eval_reads_scenes_ruled_surfaces_pieces_and_samples() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An explicit scene of two patches, z = x y on [0, 1] and y + (x - 1)(1 - y) on [1, 2]
    // (they meet along x = 1, where both are y).
    write(
        d,
        "scene.json",
        r#"{"type":"composite_explicit","x_knots":[0,1,2],"y_knots":[0,1],"patches":[["x*y"],["y + (x - 1)*(1 - y)"]]}"#,
    );
    let (header, rows) = csv(&ok(d, &["eval", "scene.json", "--samples", "5x3"]));
    assert_eq!(header, "x,y,z");
    assert_eq!(rows.len(), 15);
    for r in &rows {
        let (x, yy) = (r[0], r[1]);
        let z = if x <= 1.0 {
            x * yy
        } else {
            yy + (x - 1.0) * (1.0 - yy)
        };
        assert!((r[2] - z).abs() < 1e-14, "{r:?}");
    }
    // A cone as a ruled file: apex, then a circle of radius 1 at z = 0.
    write(
        d,
        "cone.json",
        r#"{"type":"ruled","v":[0,1],"curves":[{"point":[0,0,2]},{"circle":{"center":[0,0,0],"radius":1}}]}"#,
    );
    let (header, rows) = csv(&ok(d, &["eval", "cone.json", "--samples", "9x5"]));
    assert_eq!(header, "u,v,x,y,z");
    for r in &rows {
        // On the cone: the distance from the axis is 1 - z/2.
        let rho = r[2].hypot(r[3]);
        assert!((rho - (1.0 - r[4] / 2.0)).abs() < 1e-14, "{r:?}");
    }
    // Curve samples of `pointcalc curve`: at the samples, the samples themselves.
    write(
        d,
        "samples.json",
        r#"{"type":"pointcalc-curve","nodes":[0,1],"lebesgue":1,"samples":[[0,0,0],[0.5,1,2],[2,3,3]]}"#,
    );
    write(d, "t.csv", "0\n0.5\n1.25\n2\n");
    let (header, rows) = csv(&ok(d, &["eval", "samples.json", "--at", "t.csv"]));
    assert_eq!(header, "t,x,y");
    assert_eq!(
        rows,
        [
            [0.0, 0.0, 0.0],
            [0.5, 1.0, 2.0],
            [1.25, 2.0, 2.5],
            [2.0, 3.0, 3.0]
        ]
    );
    // A polygon as a piecewise curve: its vertices at its knots.
    write(
        d,
        "square.json",
        r#"{"type":"polygon","points":[[1,1],[-1,1],[-1,-1],[1,-1]]}"#,
    );
    let (header, rows) = csv(&ok(d, &["eval", "square.json", "--samples", "5"]));
    assert_eq!(header, "t,x,y");
    assert_eq!(rows[1], [1.0, -1.0, 1.0]);
    assert_eq!(rows[4], [4.0, 1.0, 1.0]);
}

/// A reduction whose error report overflows (coordinates near the end of f64) was written
/// with `"l2": null` and exit 0; now it is one error line naming the file, and no file.
#[test]
fn results_that_overflow_are_refused_not_written_as_null() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "huge.json",
        r#"{"type":"bezier_curve","points":[[0,0],[1e308,1],[-1e308,2],[1e308,0],[0,1e308]]}"#,
    );
    let err = fails(
        d,
        &[
            "bezier",
            "reduce",
            "huge.json",
            "--to",
            "2",
            "--approx",
            "-o",
            "red.json",
        ],
        Some("red.json"),
    );
    assert!(
        err.contains("huge.json") && err.contains("approximate reduction overflows f64"),
        "{err}"
    );
    assert!(err.contains("L2 error inf"), "{err}");
}

#[test]
fn rational_bezier_surfaces_evaluate_mesh_and_change_degree() {
    // A quarter of the cylinder x² + y² = 1, 0 <= z <= 2 (rational quadratic in u).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    write(
        d,
        "cyl.json",
        &format!(
            "{{\"type\": \"bezier_surface\", \"net\": [[[1,0,0],[1,0,2]],[[1,1,0],[1,1,2]],\
             [[0,1,0],[0,1,2]]], \"weights\": [[1,1],[{h},{h}],[1,1]]}}"
        ),
    );
    run_ok(
        d,
        &[
            "bezier", "change", "--to", "4,3", "cyl.json", "-o", "e.json",
        ],
    );
    for file in ["cyl.json", "e.json"] {
        let (header, rows) = csv(&ok(d, &["eval", file, "--samples", "7x5"]));
        assert_eq!(header, "u,v,x,y,z");
        assert_eq!(rows.len(), 35);
        for r in rows {
            assert!((r[2].hypot(r[3]) - 1.0).abs() < 1e-15, "{file}: {r:?}");
            assert!((r[4] - 2.0 * r[1]).abs() < 1e-15, "{file}: {r:?}");
        }
    }
    let degree = ok(d, &["bezier", "degree", "--json", "e.json"]);
    assert_eq!(
        degree.trim(),
        "{\"degree\":[4,3],\"real_degree\":[2,1],\"defect\":[2,2]}"
    );
    run_ok(d, &["mesh", "e.json", "-o", "e.obj"]);
    let obj = std::fs::read_to_string(d.join("e.obj")).unwrap();
    for line in obj.lines().filter(|l| l.starts_with("v ")) {
        let v: Vec<f64> = line[2..].split(' ').map(|x| x.parse().unwrap()).collect();
        assert!((v[0].hypot(v[1]) - 1.0).abs() < 1e-14, "{line}");
    }
}
