//! `geomkit export` of formulas without an exact B-spline form (a `warning:` line per
//! approximated piece with its deviation, the same in the file's header, `--tolerance`), and
//! `geomkit import` of rational B-splines of several spans (one file per span) and of trimmed
//! faces (a `warning:` line per face).

mod common;

use common::{fails, ok_stderr, write};
use std::fs;

fn fixture(name: &str) -> String {
    format!(
        "{}/../geomkit-model/tests/fixtures/step/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

const SCENE: &str = r#"{"type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
    "patches": [["sin(x) * exp(y)"], ["sqrt(1 + x^2 + y^2)"]]}"#;

/// The deviations of the `warning: approximated` lines, in order.
fn deviations(msg: &str) -> Vec<(String, f64, f64)> {
    msg.lines()
        .filter_map(|l| l.strip_prefix("warning: approximated "))
        .map(|l| {
            let (piece, rest) = l.split_once(": a ").unwrap();
            let dev = rest.split("max deviation ").nth(1).unwrap();
            let (dev, tol) = dev.split_once(" (tolerance ").unwrap();
            let tol = tol.trim_end_matches(')');
            (
                piece.to_string(),
                dev.parse().unwrap(),
                tol.parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn formulas_export_with_a_warning_per_piece_and_the_tolerance_option() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "scene.json", SCENE);
    let msg = ok_stderr(d, &["export", "scene.json", "-o", "scene.step"]);
    let coarse = deviations(&msg);
    assert_eq!(
        coarse.iter().map(|c| c.0.as_str()).collect::<Vec<_>>(),
        ["patch (0, 0)", "patch (1, 0)"],
        "{msg}"
    );
    assert!(coarse.iter().all(|(_, dev, tol)| dev <= tol), "{msg}");
    let text = fs::read_to_string(d.join("scene.step")).unwrap();
    let header = text.lines().nth(2).unwrap();
    for line in msg.lines().filter(|l| l.starts_with("warning: ")) {
        let said = line.strip_prefix("warning: ").unwrap();
        assert!(header.contains(said), "{said} not in {header}");
    }
    // A hundred times smaller tolerance: every piece closer.
    let msg = ok_stderr(
        d,
        &[
            "export",
            "scene.json",
            "-o",
            "fine.step",
            "--tolerance",
            "1e-8",
        ],
    );
    let fine = deviations(&msg);
    for (c, f) in coarse.iter().zip(&fine) {
        assert!(f.2 < c.2 / 50.0 && f.1 <= f.2, "{c:?} {f:?}");
    }
    // Out of reach: sqrt(x) at 0, one line, no file.
    write(
        d,
        "root.json",
        r#"{"type": "composite_explicit", "x_knots": [0, 1], "y_knots": [0, 1], "patches": [["sqrt(x)"]]}"#,
    );
    let err = fails(
        d,
        &[
            "export",
            "root.json",
            "-o",
            "root.step",
            "--tolerance",
            "1e-12",
        ],
        Some("root.step"),
    );
    assert!(
        err.contains("patch (0, 0): the interpolating B-spline of 129 x 129 samples"),
        "{err}"
    );
}

#[test]
fn rational_splines_of_several_spans_import_as_one_file_per_span() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let msg = ok_stderr(
        d,
        &["import", &fixture("occt_rational_sphere.step"), "-o", "s"],
    );
    let mut files: Vec<String> = fs::read_dir(d.join("s"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files.len(), 6, "{files:?}");
    assert!(files[0].starts_with("bezier_surface-") && files[0].ends_with("-0-0.json"));
    assert!(files[5].ends_with("-2-1.json"), "{files:?}");
    assert!(msg.contains("span (3, 2) of 3 × 2"), "{msg}");
}

#[test]
fn trimmed_faces_are_a_warning_each() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok_stderr(d, &["compose", "body", "cube", "-o", "cube.json"]);
    ok_stderr(d, &["export", "cube.json", "-o", "cube.step"]);
    let msg = ok_stderr(d, &["import", "cube.step", "-o", "faces"]);
    let warnings: Vec<&str> = msg
        .lines()
        .filter(|l| l.starts_with("warning: face #"))
        .collect();
    assert_eq!(warnings.len(), 2, "{msg}");
    assert!(warnings[0].contains("is trimmed (its outline): imported as the whole surface #"));
}
