//! `geomkit export` and `geomkit import` (STEP, ISO 10303-21): a round trip through the
//! binary evaluates to the same numbers; OCCT-written files import; bad input is one line
//! naming the file and the entity, and leaves no file behind.

mod common;

use common::{fails, ok, ok_stderr, write};
use std::fs;

const CURVE: &str =
    r#"{"type": "bezier_curve", "points": [[0, 0, 0], [1, 2, 0.1], [3, 0, 1], [4, 1.5, 2]]}"#;

fn fixture(name: &str) -> String {
    format!(
        "{}/../geomkit-model/tests/fixtures/step/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn export_then_import_evaluates_to_the_same_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "c.json", CURVE);
    let msg = ok_stderr(d, &["export", "c.json", "-o", "c.step"]);
    assert!(
        msg.starts_with("wrote c.step: Bézier curve of degree 3 in R^3 (4 control points) as STEP"),
        "{msg}"
    );
    let msg = ok_stderr(d, &["import", "c.step", "-o", "back.json"]);
    assert!(
        msg.starts_with("wrote back.json: Bézier curve of degree 3"),
        "{msg}"
    );
    let a = ok(d, &["eval", "c.json", "--samples", "17"]);
    let b = ok(d, &["eval", "back.json", "--samples", "17"]);
    assert_eq!(a, b);
    // A file in metres: imported as written, with a note.
    let metres = fs::read_to_string(d.join("c.step"))
        .unwrap()
        .replace("SI_UNIT(.MILLI.,.METRE.)", "SI_UNIT($,.METRE.)");
    write(d, "m.step", &metres);
    let msg = ok_stderr(d, &["import", "m.step", "-o", "m.json"]);
    assert!(
        msg.contains("note: lengths are in the file's unit (METRE), as written"),
        "{msg}"
    );
    // The same model gives the same bytes.
    ok_stderr(d, &["export", "c.json", "-o", "again.step"]);
    assert_eq!(
        fs::read(d.join("c.step")).unwrap(),
        fs::read(d.join("again.step")).unwrap()
    );
}

#[test]
fn a_body_exports_as_a_closed_solid() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok_stderr(d, &["compose", "body", "cube", "-o", "cube.json"]);
    ok_stderr(
        d,
        &["export", "cube.json", "-o", "cube.stp", "--schema", "ap242"],
    );
    let text = fs::read_to_string(d.join("cube.stp")).unwrap();
    assert!(text.contains("MANIFOLD_SOLID_BREP('cube',"));
    assert!(text.contains("CLOSED_SHELL("));
    // Six faces, twelve edges, eight vertices: shared, never duplicated.
    assert_eq!(text.matches("ADVANCED_FACE(").count(), 6);
    assert_eq!(text.matches("EDGE_CURVE(").count(), 12);
    assert_eq!(text.matches("VERTEX_POINT(").count(), 8);
    assert!(text.contains("AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF"));
}

#[test]
fn occt_files_import_into_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let msg = ok_stderr(d, &["import", &fixture("occt_box.step"), "-o", "box"]);
    let files: Vec<String> = {
        let mut v: Vec<String> = fs::read_dir(d.join("box"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(files.len(), 6, "{files:?}");
    assert!(
        files.iter().all(|f| f.starts_with("bezier_surface-")),
        "{files:?}"
    );
    assert_eq!(msg.lines().count(), 6, "{msg}");
    let msg = ok_stderr(
        d,
        &["import", &fixture("occt_bspline_surface.step"), "-o", "s"],
    );
    assert!(
        msg.contains("B-spline surface of degrees (3, 3) in R^3 (6×5 net)"),
        "{msg}"
    );
    assert!(msg.contains("skipped: 4 edge curves of faces"), "{msg}");
    // Several models need a folder.
    let err = fails(
        d,
        &["import", &fixture("occt_box.step"), "-o", "one.json"],
        Some("one.json"),
    );
    assert!(err.contains("holds 6 models: give a folder"), "{err}");
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "c.json", CURVE);
    write(
        d,
        "f.json",
        r#"{"type": "piecewise", "knots": [-1, 0, 1], "pieces": ["-x", "x^2"]}"#,
    );
    let err = fails(
        d,
        &["export", "f.json", "-o", "f.step", "--tolerance", "0"],
        Some("f.step"),
    );
    assert!(
        err.starts_with("error: f.json: cannot export: the tolerance 0 must be finite and > 0"),
        "{err}"
    );
    let err = fails(d, &["export", "c.json", "-o", "c.iges"], Some("c.iges"));
    assert!(err.contains("name it .step or .stp"), "{err}");
    // A truncated file, a dangling reference, a cycle, a wrong parameter count, nothing usable.
    ok_stderr(d, &["export", "c.json", "-o", "c.step"]);
    let full = fs::read_to_string(d.join("c.step")).unwrap();
    write(d, "cut.step", &full[..full.len() * 2 / 3]);
    let head = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n";
    let tail = "ENDSEC;\nEND-ISO-10303-21;\n";
    let body = |s: &str| format!("{head}#1=CARTESIAN_POINT('',(0.,0.,0.));\n{s}{tail}");
    write(
        d,
        "dangling.step",
        &body("#2=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#7),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);\n"),
    );
    write(
        d,
        "cycle.step",
        &body("#2=VERTEX_POINT('',#3);\n#3=EDGE_CURVE('',#2,#2,#4,.T.);\n#4=LINE('',#1,#3);\n"),
    );
    write(
        d,
        "count.step",
        &body("#2=CARTESIAN_POINT('',(1.,0.,0.));\n#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);\n"),
    );
    write(d, "nothing.step", &body(""));
    write(d, "mesh.stl", "solid x\nendsolid x\n");
    let cases = [
        ("cut.step", "cut.step: line "),
        (
            "dangling.step",
            "dangling.step: #2: refers to #7, which is not in the file",
        ),
        (
            "cycle.step",
            "cycle.step: #2: is part of a cycle of references (#2 -> #3 -> #2)",
        ),
        (
            "count.step",
            "count.step: #3: B_SPLINE_CURVE_WITH_KNOTS has 8 parameters, expected 9",
        ),
        (
            "nothing.step",
            "nothing.step: no B-spline or Bézier curve or surface to import",
        ),
        (
            "mesh.stl",
            "mesh.stl: line 1: expected 'ISO-10303-21;' (this is not a STEP file)",
        ),
        ("missing.step", "cannot read missing.step"),
    ];
    for (file, want) in cases {
        let err = fails(d, &["import", file, "-o", "out"], Some("out"));
        assert!(err.contains(want), "{file}: {err}");
    }
}
