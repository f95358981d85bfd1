//! End-to-end tests of `geomkit compose` and `geomkit eval` on composite scenes.

mod common;

use common::{fails, geomkit, ok, run_ok, text, write};
use serde_json::Value;
use std::fs;
use std::path::Path;

/// Runs `geomkit compose SUB FILE -o OUT` on each (file text, wanted message): one line
/// `error: ...` containing the message, non-zero exit, no OUT left behind.
fn assert_bad_inputs<S: AsRef<str>>(dir: &Path, sub: &str, out_file: &str, cases: &[(S, &str)]) {
    for (k, (json, want)) in cases.iter().enumerate() {
        let name = format!("bad{k}.json");
        write(dir, &name, json.as_ref());
        let err = fails(
            dir,
            &["compose", sub, &name, "-o", out_file],
            Some(out_file),
        );
        assert!(err.contains(want), "{err}");
    }
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
        let out = run_ok(dir.path(), &["compose", "body", "cube", "--format", f]);
        insta::assert_snapshot!(format!("cube_{f}"), text(&out.stdout));
    }
}

#[test]
fn bodies_write_meshes_pictures_and_json() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = run_ok(
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
    // The welded mesh of `geomkit mesh`: 9 angles (the seam welded: 8) on 5 rows, the two
    // cap centres single vertices; closed, its volume the inscribed octagonal prism's.
    let obj = fs::read_to_string(d.join("c.obj")).unwrap();
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        8 * 5 + 2
    );
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 80);
    let octagon = 2.0 * 2f64.sqrt() * 4.0;
    let err = text(&out.stderr);
    let volume: f64 = err
        .trim()
        .rsplit_once("volume ")
        .unwrap_or_else(|| panic!("no volume in {err}"))
        .1
        .parse()
        .unwrap();
    assert!((volume - octagon).abs() < 1e-12 * octagon, "{err}");
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
    run_ok(d, &["compose", "body", "pyramid", "-o", "p.svg"]);
    assert!(fs::read_to_string(d.join("p.svg"))
        .unwrap()
        .contains("<svg"));
    run_ok(
        d,
        &["compose", "body", "prism", "--ngon", "5", "-o", "p.json"],
    );
    let v: Value = serde_json::from_str(&fs::read_to_string(d.join("p.json")).unwrap()).unwrap();
    assert_eq!(v["formulas"].as_object().unwrap().len(), 11);
    assert!(v["op_count"].as_u64().unwrap() > 0);
    assert_eq!(v["model"]["type"], "ruled");
}

/// A body's JSON carries its model: `mesh`, `render` and `eval` read it back, and the
/// mesh and picture formats come straight out of `compose body` too.
#[test]
fn body_files_mesh_render_and_evaluate() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    run_ok(d, &["compose", "body", "cube", "-o", "cube.json"]);
    let out = run_ok(d, &["mesh", "cube.json", "-o", "cube.stl"]);
    let err = text(&out.stderr);
    assert!(err.contains("closed, volume 8"), "{err}");
    for file in ["direct.stl", "direct.ply", "direct.glb"] {
        let out = run_ok(d, &["compose", "body", "cube", "-o", file]);
        assert!(text(&out.stderr).contains("closed, volume 8"), "{file}");
    }
    for file in ["cube.png", "cube.svg"] {
        run_ok(d, &["render", "cube.json", "-o", file]);
        run_ok(d, &["compose", "body", "cone", "-o", file]);
    }
    assert!(fs::read(d.join("cube.png"))
        .unwrap()
        .starts_with(b"\x89PNG"));
    // The structural evaluator on a 5×4 grid: every point on the cube, the poles included.
    let out = run_ok(d, &["eval", "cube.json", "--samples", "5x4"]);
    let rows: Vec<Vec<f64>> = text(&out.stdout)
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 20);
    for r in &rows {
        let m = r[2].abs().max(r[3].abs()).max(r[4].abs());
        assert!((m - 1.0).abs() < 1e-15, "{r:?}");
    }
    // u = 1, v = 1: the corner (-1, 1, 1) of the top square; u = 2, v = 2: (-1, -1, -1).
    assert!(rows.contains(&vec![1.0, 1.0, -1.0, 1.0, 1.0]), "{rows:?}");
    assert!(rows.contains(&vec![2.0, 2.0, -1.0, -1.0, -1.0]), "{rows:?}");
    let out = geomkit(d, &["compose", "body", "cube", "-o", "cube.step"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("name it .txt, .json, .obj, .stl, .ply, .glb, .png or .svg"));
    assert!(!d.join("cube.step").exists());
    // The formula file of a piecewise function carries its pieces: eval reads it back, at
    // the breakpoints exactly (the hat 0 -> 1 -> 0).
    write(
        d,
        "f.json",
        r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x","2 - x"]}"#,
    );
    run_ok(d, &["compose", "piecewise", "f.json", "-o", "pf.json"]);
    let out = ok(d, &["eval", "pf.json", "--samples", "5"]);
    assert!(out.starts_with("x,f\n"), "{out}");
    let rows: Vec<Vec<f64>> = out
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(
        rows,
        vec![
            vec![0.0, 0.0],
            vec![0.5, 0.5],
            vec![1.0, 1.0],
            vec![1.5, 0.5],
            vec![2.0, 0.0]
        ]
    );
    // A formula file without a model (written by hand or by an older geomkit) says so.
    let formula: Value =
        serde_json::from_str(&fs::read_to_string(d.join("pf.json")).unwrap()).unwrap();
    let mut bare = formula.as_object().unwrap().clone();
    bare.remove("model");
    write(d, "bare.json", &Value::Object(bare).to_string());
    let err = fails(d, &["mesh", "bare.json", "-o", "pf.obj"], Some("pf.obj"));
    assert!(
        err.contains("bare.json: this formula file carries no model"),
        "{err}"
    );
}

#[test]
fn patches_formula_report_and_eval() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "ok.json", &scene(0.0));
    write(d, "jump.json", &scene(0.5));
    let out = run_ok(d, &["compose", "patches", "ok.json"]);
    let formula = text(&out.stdout);
    assert!(
        formula.starts_with("x := (u, v) -> ") && formula.contains("abs(u - 1)"),
        "{formula}"
    );
    assert!(text(&out.stderr).contains("continuous"));
    let out = run_ok(d, &["compose", "patches", "jump.json", "--report-json"]);
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["max_jump"].as_f64().unwrap(), 0.5);
    assert_eq!(r["continuous"], Value::Bool(false));
    assert_eq!(r["jumps"][0]["line"], "u");
    assert!(r["statement"].as_str().unwrap().contains("shifts"));
    // geomkit eval: the structural evaluator, equal to the formula (the second patch shifted
    // down by the jump 0.5 at v = 0).
    let out = run_ok(d, &["eval", "jump.json", "--samples", "3x2"]);
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
            "patches[0][0]: coordinate x: parse error at byte 2: expected a number, a name or `(`",
        ),
        (
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u","y":"v","z":"ln(u)"}]]}"#.into(),
            vec![],
            "patch (0, 0) coordinate z: the value -inf at u = 0, v = 0 is not a finite number",
        ),
        (
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u","y":"v","z":"w"}]]}"#.into(),
            vec![],
            "unknown variable `w` (the variables are u, v)",
        ),
        (
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u","y":"v","z":"0","domain":[[1,0],[0,1]]}]]}"#.into(),
            vec![],
            "interval 0 [1, 0] must be finite with start < end",
        ),
    ];
    let cases: Vec<(&String, &str)> = cases.iter().map(|(s, _, w)| (s, *w)).collect();
    assert_bad_inputs(d, "patches", "out.obj", &cases);
    let out = geomkit(
        d,
        &["compose", "body", "cone", "--radius", "0", "-o", "c.obj"],
    );
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("radius = 0 must be finite, > 0 and at most 1e100"));
    assert!(!d.join("c.obj").exists());
    let out = geomkit(d, &["compose", "body", "cube", "--format", "fortran"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("unknown --format"));
}

/// A smooth patch next to one on its own domain, and an explicit scene that jumps.
const EXPR_SCENE: &str = r#"{"type":"composite_surface","u_knots":[0,1,2],"v_knots":[0,1],"patches":[
    [{"x":"u","y":"v","z":"u*v"}],
    [{"x":"u + 1","y":"v","z":"v*(2 - u)^2","domain":[[0,1],[0,1]]}]]}"#;

#[test]
fn expression_patches_formula_report_and_eval() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "s.json", EXPR_SCENE);
    let out = run_ok(d, &["compose", "patches", "s.json"]);
    insta::assert_snapshot!("expr_patches_maple", text(&out.stdout));
    assert!(
        text(&out.stderr).contains("NOT continuous"),
        "{}",
        text(&out.stderr)
    );
    // The second patch, on its own domain [0,1]², starts at z = 4v where the first ends at
    // z = v: a jump of 3 at v = 1, which (9) removes by shifting the second patch by -3v.
    let out = run_ok(d, &["compose", "patches", "s.json", "--report-json"]);
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["max_jump"].as_f64().unwrap(), 3.0);
    let out = geomkit(d, &["eval", "s.json", "--samples", "3x2"]);
    let rows: Vec<Vec<f64>> = text(&out.stdout)
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    // (u, v) = (2, 1): the second patch at its (1, 1), shifted by 1 - 4 = -3.
    assert_eq!(rows[5], vec![2.0, 1.0, 2.0, 1.0, -2.0]);
    assert_eq!(rows[3], vec![1.0, 1.0, 1.0, 1.0, 1.0]);
    let explicit = r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,0.5,1],"patches":[["x + y", {"z":"x + y"}]]}"#;
    write(d, "e.json", explicit);
    let out = run_ok(d, &["compose", "patches", "e.json", "--format", "sympy"]);
    insta::assert_snapshot!("expr_explicit_sympy", text(&out.stdout));
    assert!(text(&out.stderr).contains("continuous: "));
    run_ok(
        d,
        &[
            "compose",
            "patches",
            "e.json",
            "-o",
            "e.obj",
            "--samples",
            "3x3",
        ],
    );
    // Heights drawn as (x, y, z): the centre of the 3×3 grid is (0.5, 0.5, 1).
    let obj = fs::read_to_string(d.join("e.obj")).unwrap();
    let vertices: Vec<Vec<f64>> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split(' ').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(vertices.len(), 9, "{obj}");
    assert!(vertices.contains(&vec![0.5, 0.5, 1.0]), "{obj}");
}

const RULED: &str = r#"{"type":"ruled","u":[0,4],"v":[0,1,2,3],"curves":[
    {"point":[0,0,1]},
    {"x":"cos(t)","y":"sin(t)","z":"1","t":[0,6.283185307179586]},
    {"polygon":[[1,1,-1],[-1,1,-1],[-1,-1,-1],[1,-1,-1]]},
    {"point":[0,0,-1]}]}"#;

#[test]
fn ruled_formula_outputs_and_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "r.json", RULED);
    let out = run_ok(d, &["compose", "ruled", "r.json"]);
    insta::assert_snapshot!("ruled_maple", text(&out.stdout));
    let err = text(&out.stderr);
    assert!(err.contains("both ends points: a closed body"), "{err}");
    assert!(
        err.contains("formula (2) vs structural evaluator: largest difference"),
        "{err}"
    );
    for (file, want) in [
        ("r.obj", "v "),
        ("r.svg", "<svg"),
        ("r.json", "\"op_count\""),
    ] {
        run_ok(
            d,
            &["compose", "ruled", "r.json", "-o", file, "--samples", "9x4"],
        );
        assert!(fs::read_to_string(d.join(file)).unwrap().contains(want));
    }
    // The curves file itself is a model for `mesh`, `render` and `eval`; a circle given as
    // {"circle":..} is the same surface as the formula circle.
    let out = run_ok(d, &["mesh", "r.json", "-o", "r.stl"]);
    assert!(
        text(&out.stderr).contains("closed, volume"),
        "{}",
        text(&out.stderr)
    );
    run_ok(d, &["render", "r.json", "-o", "r.png"]);
    let circle = RULED.replace(
        r#"{"x":"cos(t)","y":"sin(t)","z":"1","t":[0,6.283185307179586]}"#,
        r#"{"circle":{"center":[0,0,1],"radius":1}}"#,
    );
    write(d, "c.json", &circle);
    let a = run_ok(d, &["eval", "r.json", "--samples", "7x7"]).stdout;
    let b = run_ok(d, &["eval", "c.json", "--samples", "7x7"]).stdout;
    let parse = |o: &[u8]| -> Vec<f64> {
        text(o)
            .lines()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .map(|x| x.parse::<f64>().unwrap())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let (a, b) = (parse(&a), parse(&b));
    assert_eq!(a.len(), 49 * 5);
    assert!(
        a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-15),
        "{a:?} {b:?}"
    );
    let bad = [
        (
            RULED.replace("[0,1,2,3]", "[0,1,1,3]"),
            "\"v\" must be strictly increasing: v[2] = 1 after v[1] = 1",
        ),
        (
            RULED.replace("[0,6.283185307179586]", "[1,1]"),
            "start < end",
        ),
        (
            RULED.replace("sin(t)", "sin(t"),
            "curves[1]: coordinate y: parse error at byte 5",
        ),
        (
            RULED.replace("\"z\":\"1\"", "\"z\":\"ln(t)\""),
            "is not a finite number",
        ),
        (
            RULED.replace("[0,1,2,3]", "[0,1,2]"),
            "v values for 4 curves: expected 4, got 3",
        ),
    ];
    assert_bad_inputs(d, "ruled", "bad.obj", &bad);
}

#[test]
fn piecewise_functions_polygons_and_curves() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "f.json",
        r#"{"type":"piecewise","knots":[-1,0,1],"pieces":["-x","x^2"]}"#,
    );
    let out = run_ok(d, &["compose", "piecewise", "f.json"]);
    insta::assert_snapshot!("piecewise_maple", text(&out.stdout));
    assert!(text(&out.stderr).contains("continuous: "));
    run_ok(d, &["compose", "piecewise", "f.json", "-o", "f.svg"]);
    assert!(fs::read_to_string(d.join("f.svg"))
        .unwrap()
        .contains("<svg"));
    write(
        d,
        "sq.json",
        r#"{"type":"polygon","points":[[1,1],[-1,1],[-1,-1],[1,-1]]}"#,
    );
    let out = run_ok(
        d,
        &["compose", "piecewise", "sq.json", "--format", "mathematica"],
    );
    insta::assert_snapshot!("polygon_mathematica", text(&out.stdout));
    write(
        d,
        "c.json",
        r#"{"type":"piecewise","knots":[0,1,2],"pieces":[{"x":"t","y":"0"},{"x":"1 + t","y":"t","domain":[0,1]}]}"#,
    );
    let out = run_ok(d, &["compose", "piecewise", "c.json", "--report-json"]);
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["continuous"], Value::Bool(true));
    run_ok(d, &["compose", "piecewise", "c.json", "-o", "c.json.json"]);
    let v: Value =
        serde_json::from_str(&fs::read_to_string(d.join("c.json.json")).unwrap()).unwrap();
    assert_eq!(v["variables"], serde_json::json!(["t"]));
    let bad = [
        (
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x"]}"#,
            "pieces for 3 knots: expected 2, got 1",
        ),
        (
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x +* 2"]}"#,
            "piece 0 coordinate f: parse error at byte 3",
        ),
        (
            r#"{"type":"piecewise","knots":[0,1],"pieces":["sqrt(x - 2)"]}"#,
            "not a finite number",
        ),
        (r#"{"type":"polyline","points":[[0,0]]}"#, "polyline points"),
        (r#"{"type":"spline"}"#, "unknown type \"spline\""),
        (
            r#"{"type":"bspline_curve","degree":1,"knots":[0,0,1,1,2,2],"control_points":[[0,0],[1,0],[1,1],[2,1]]}"#,
            "repeated degree + 1 times",
        ),
    ];
    assert_bad_inputs(d, "piecewise", "bad.svg", &bad);
}

/// The convention of a piecewise function that jumps (issue 21): one continuous function,
/// the later pieces shifted by the jumps before them, constant beyond the knots; `geomkit
/// eval` gives it at the breakpoints.
/// A piece not finite inside its interval is one `warning:` line; `sqrt` at the ends of
/// its interval prints with its clamp and never as NaN.
#[test]
fn piecewise_jumps_warnings_and_clamped_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "j.json",
        r#"{"type":"piecewise","knots":[0,1,2,3],"pieces":["x","x + 2","5"]}"#,
    );
    let out = run_ok(d, &["compose", "piecewise", "j.json", "-o", "jf.json"]);
    assert!(text(&out.stderr).contains("NOT continuous: 2 of 2 breakpoints jump"));
    // (`geomkit eval` refuses points beyond the domain; the library's evaluator and the
    // formula hold the ends there, tests/hardening_compose.rs.)
    write(d, "at.csv", "0\n0.5\n1\n1.5\n2\n2.5\n3\n");
    let rows = ok(d, &["eval", "jf.json", "--at", "at.csv"]);
    let f: Vec<f64> = rows
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(f, vec![0.0, 0.5, 1.0, 1.5, 2.0, 2.0, 2.0]);
    write(
        d,
        "w.json",
        r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x","1/(x - 1.5)"]}"#,
    );
    let out = run_ok(d, &["compose", "piecewise", "w.json"]);
    let err = text(&out.stderr);
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(
        warnings,
        vec![
            "warning: w.json: piece 1 coordinate f: the value inf at x = 1.5 is not a finite \
             number; the single formula is not finite there either (only there)"
        ]
    );
    write(
        d,
        "s.json",
        r#"{"type":"piecewise","knots":[0.1,0.3,0.7],"pieces":["sqrt(x - 0.1)","sqrt(0.7 - x)"]}"#,
    );
    for format in ["maple", "c", "numpy", "glsl"] {
        let out = run_ok(d, &["compose", "piecewise", "s.json", "--format", format]);
        let formula = text(&out.stdout);
        assert!(formula.contains("sqrt"), "{formula}");
        for bad in ["nan", "NaN", "inf", "undefined"] {
            assert!(!formula.contains(bad), "{format}: {formula}");
        }
    }
}

/// An interpolated curve (method 2) saved as a model, then written as one formula.
#[test]
fn interpolated_curve_as_one_formula() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "pts.csv", "0,0\n1,2\n3,3\n4,0\n6,1\n");
    run_ok(d, &["interpolate", "curve", "pts.csv", "-o", "fit.json"]);
    let out = run_ok(d, &["compose", "piecewise", "fit.json", "--report-json"]);
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["continuous"], Value::Bool(true));
    let fit: Value =
        serde_json::from_str(&fs::read_to_string(d.join("fit.json")).unwrap()).unwrap();
    let breaks: Vec<f64> = r["jumps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j["at"].as_f64().unwrap())
        .collect();
    let params: Vec<f64> = fit["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert_eq!(
        breaks,
        params[1..params.len() - 1],
        "breakpoints = inner parameters"
    );
    run_ok(
        d,
        &["compose", "piecewise", "fit.json", "-o", "fit.formula.json"],
    );
    let v: Value =
        serde_json::from_str(&fs::read_to_string(d.join("fit.formula.json")).unwrap()).unwrap();
    assert_eq!(v["variables"], serde_json::json!(["t"]));
    let out = run_ok(
        d,
        &[
            "compose",
            "piecewise",
            "fit.json",
            "--format",
            "mathematica",
        ],
    );
    let m = text(&out.stdout);
    assert!(m.starts_with("x[t_] := ") && m.contains("y[t_] := "), "{m}");
}

/// An interpolated height surface (method 2) saved as a model, written as one formula, and
/// the formula file evaluated back at the grid nodes.
#[test]
fn interpolated_surface_as_one_formula() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let heights = [
        [0.0, 1.0, 2.0, 1.0],
        [1.0, 2.0, 3.0, 2.0],
        [0.0, 1.0, 1.0, 0.0],
    ];
    let csv: String = heights
        .iter()
        .map(|r| r.map(|z| z.to_string()).join(",") + "\n")
        .collect();
    write(d, "h.csv", &csv);
    run_ok(
        d,
        &[
            "interpolate",
            "surface",
            "h.csv",
            "--heights",
            "--dx",
            "0.5",
            "--dy",
            "1",
            "-o",
            "fit.json",
        ],
    );
    let out = run_ok(d, &["compose", "patches", "fit.json", "--report-json"]);
    let r: Value = serde_json::from_str(&text(&out.stdout)).unwrap();
    assert_eq!(r["continuous"], Value::Bool(true));
    let out = run_ok(d, &["compose", "patches", "fit.json", "--format", "maple"]);
    assert!(text(&out.stdout).starts_with("z := (x, y) -> "));
    run_ok(d, &["compose", "patches", "fit.json", "-o", "f.json"]);
    let nodes: String = (0..3)
        .flat_map(|i| (0..4).map(move |j| format!("{},{}\n", 0.5 * i as f64, j)))
        .collect();
    write(d, "at.csv", &nodes);
    let out = run_ok(d, &["eval", "f.json", "--at", "at.csv"]);
    let lines: Vec<String> = text(&out.stdout).lines().map(String::from).collect();
    assert_eq!(lines[0], "x,y,z");
    for (k, line) in lines[1..].iter().enumerate() {
        let z: f64 = line.rsplit(',').next().unwrap().parse().unwrap();
        let want = heights[k / 4][k % 4];
        assert!((z - want).abs() <= 1e-14, "node {k}: {z} vs {want}");
    }
}
