//! End-to-end tests of `geomkit compose` and `geomkit eval` on composite scenes.

use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn geomkit(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geomkit"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the geomkit binary runs")
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, text).unwrap();
    path
}

fn text(b: &[u8]) -> String {
    String::from_utf8(b.to_vec()).unwrap()
}

/// Two bilinear patches that meet along u = 1, and a third variant that jumps.
fn scene(jump: f64) -> String {
    format!(
        r#"{{"type":"composite_surface","u_knots":[0,1,2],"v_knots":[0,1],"patches":[
        [{{"bezier":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}}],
        [{{"bezier":[[[1,0,{jump}],[1,1,1]],[[2,0,0],[2,1,0]]]}}]]}}"#
    )
}

#[test]
fn cube_formula_snapshot_in_three_syntaxes() {
    let dir = tempfile::tempdir().unwrap();
    for f in ["maple", "mathematica", "latex"] {
        let out = geomkit(dir.path(), &["compose", "body", "cube", "--format", f]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        insta::assert_snapshot!(format!("cube_{f}"), text(&out.stdout));
    }
}

#[test]
fn bodies_write_meshes_pictures_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = geomkit(
        d,
        &[
            "compose",
            "body",
            "cylinder",
            "--radius",
            "2",
            "--height",
            "1",
            "-o",
            "c.obj",
            "--samples",
            "9x5",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let obj = fs::read_to_string(d.join("c.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 45);
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("f ")).count(),
        2 * 8 * 4
    );
    // Every vertex on the capped cylinder of radius 2, z in [-1/2, 1/2].
    for l in obj.lines().filter(|l| l.starts_with("v ")) {
        let p: Vec<f64> = l[2..].split(' ').map(|x| x.parse().unwrap()).collect();
        let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
        assert!(r <= 2.0 + 1e-12 && p[2].abs() <= 0.5 + 1e-15);
        assert!(
            (r - 2.0).abs() < 1e-12 || (p[2].abs() - 0.5).abs() < 1e-15,
            "{l}"
        );
    }
    let out = geomkit(d, &["compose", "body", "pyramid", "-o", "p.svg"]);
    assert!(out.status.success());
    assert!(fs::read_to_string(d.join("p.svg"))
        .unwrap()
        .contains("<svg"));
    let out = geomkit(
        d,
        &["compose", "body", "prism", "--ngon", "5", "-o", "p.json"],
    );
    assert!(out.status.success());
    let v: Value = serde_json::from_str(&fs::read_to_string(d.join("p.json")).unwrap()).unwrap();
    assert_eq!(v["formulas"].as_object().unwrap().len(), 11);
    assert!(v["op_count"].as_u64().unwrap() > 0);
}

#[test]
fn patches_formula_report_and_eval() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "ok.json", &scene(0.0));
    write(d, "jump.json", &scene(0.5));
    let out = geomkit(d, &["compose", "patches", "ok.json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let formula = text(&out.stdout);
    assert!(
        formula.starts_with("x(u, v) = ") && formula.contains("abs(u - 1)"),
        "{formula}"
    );
    assert!(text(&out.stderr).contains("continuous"));
    let out = geomkit(d, &["compose", "patches", "jump.json", "--report-json"]);
    assert!(out.status.success());
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["max_jump"].as_f64().unwrap(), 0.5);
    assert_eq!(r["continuous"], Value::Bool(false));
    assert_eq!(r["jumps"][0]["line"], "u");
    assert!(r["statement"].as_str().unwrap().contains("shifts"));
    // geomkit eval: the structural evaluator, equal to the formula (the second patch shifted
    // down by the jump 0.5 at v = 0).
    let out = geomkit(d, &["eval", "jump.json", "--samples", "3x2"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let rows: Vec<Vec<f64>> = text(&out.stdout)
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 6);
    assert_eq!(rows[2], vec![1.0, 0.0, 1.0, 0.0, 0.0]);
    assert_eq!(rows[4], vec![2.0, 0.0, 2.0, 0.0, -0.5]);
}

#[test]
fn bad_input_is_one_line_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: Vec<(String, Vec<&str>, &str)> = vec![
        (scene(0.0).replace("[0,1,2]", "[0,1,1]"), vec![], "strictly increasing"),
        (scene(0.0).replace("[0,1,2]", "[0,1,2,3]"), vec![], "patch rows"),
        (
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u+","y":"v","z":"0"}]]}"#.into(),
            vec![],
            "expression patches",
        ),
    ];
    for (k, (scene, _, want)) in cases.iter().enumerate() {
        let name = format!("bad{k}.json");
        write(d, &name, scene);
        let out = geomkit(d, &["compose", "patches", &name, "-o", "out.obj"]);
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("error: ") && err.contains(want), "{err}");
        assert!(!d.join("out.obj").exists());
    }
    let out = geomkit(
        d,
        &["compose", "body", "cone", "--radius", "0", "-o", "c.obj"],
    );
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("radius = 0 must be finite and > 0"));
    assert!(!d.join("c.obj").exists());
    let out = geomkit(d, &["compose", "body", "cube", "--format", "fortran"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("unknown --format"));
}
