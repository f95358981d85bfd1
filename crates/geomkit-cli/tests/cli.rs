//! End-to-end tests of the `geomkit` binary: run it in temporary directories and check its
//! output, exit codes, error lines and the files it leaves (or does not leave) behind.

mod common;

use common::{fails, geomkit, max_abs_diff, ok, stderr, stdout, write};
use serde_json::Value;
use std::fs;

/// The paper's Example 2: formal degree 5, real degree 3.
const EXAMPLE2: &str =
    r#"{"type":"bezier_curve","points":[[10,0],[22,6],[19,12],[11,15],[8,12],[20,0]]}"#;
/// Its cubic, exactly.
const EXAMPLE2_CUBIC: [[f64; 2]; 4] = [[10.0, 0.0], [30.0, 10.0], [0.0, 20.0], [20.0, 0.0]];
/// A bicubic net (a skewed dome).
const BICUBIC: &str = r#"{"type":"bezier_surface","net":[
    [[0,0,0],[0.3,2,1.2],[0.6,4,0.8],[0.9,6,0.2]],
    [[2,0,1],[2.3,2,3],[2.6,4,2.6],[2.9,6,1.4]],
    [[4,0,0.6],[4.3,2,2.8],[4.6,4,3.2],[4.9,6,1]],
    [[6,0,0.2],[6.3,2,0.8],[6.6,4,1.4],[6.9,6,0.4]]]}"#;

fn points(json: &Value) -> Vec<Vec<f64>> {
    json["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            p.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

#[test]
fn degree_json_of_example2() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    let out = ok(dir.path(), &["bezier", "degree", "ex2.json", "--json"]);
    assert_eq!(out, "{\"degree\":5,\"real_degree\":3,\"defect\":2}\n");
}

#[test]
fn degree_human_output_shows_residuals_and_tolerance() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    let out = ok(
        dir.path(),
        &["bezier", "degree", "ex2.json", "--tolerance", "1e-10"],
    );
    for want in [
        "formal degree       5",
        "real degree         3",
        "degree defect       2",
        "residual",
        "rejected residual",
        "tolerance           1e-10",
    ] {
        assert!(out.contains(want), "missing {want:?} in\n{out}");
    }
}

#[test]
fn surface_degree_json_after_change() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "bicubic.json", BICUBIC);
    ok(
        dir.path(),
        &[
            "bezier",
            "change",
            "bicubic.json",
            "--to",
            "4,3",
            "-o",
            "s43.json",
        ],
    );
    let out = ok(dir.path(), &["bezier", "degree", "s43.json", "--json"]);
    assert_eq!(
        out,
        "{\"degree\":[4,3],\"real_degree\":[3,3],\"defect\":[1,0]}\n"
    );
    let human = ok(dir.path(), &["bezier", "degree", "s43.json"]);
    assert!(
        human.contains("degree defect       1           0"),
        "{human}"
    );
    // Reduce back and compare with the bicubic net.
    let reduced: Value = serde_json::from_str(&ok(
        dir.path(),
        &["bezier", "reduce", "s43.json", "--to", "3,3"],
    ))
    .unwrap();
    let original: Value = serde_json::from_str(BICUBIC).unwrap();
    let flat = |v: &Value| -> Vec<f64> {
        v["net"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|row| row.as_array().unwrap().iter())
            .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect()
    };
    let (a, b) = (flat(&reduced), flat(&original));
    assert_eq!(a.len(), b.len());
    assert!(a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12));
}

#[test]
fn elevate_and_reduce_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let cubic = serde_json::json!({"type": "bezier_curve", "points": EXAMPLE2_CUBIC});
    write(dir.path(), "cubic.json", &cubic.to_string());
    ok(
        dir.path(),
        &[
            "bezier",
            "elevate",
            "cubic.json",
            "--to",
            "5",
            "-o",
            "q.json",
        ],
    );
    let quintic: Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("q.json")).unwrap()).unwrap();
    let example2 = [
        [10.0, 0.0],
        [22.0, 6.0],
        [19.0, 12.0],
        [11.0, 15.0],
        [8.0, 12.0],
        [20.0, 0.0],
    ];
    assert!(max_abs_diff(&points(&quintic).concat(), &example2.concat()) < 1e-13);
    let back: Value = serde_json::from_str(&ok(
        dir.path(),
        &["bezier", "reduce", "q.json", "--to", "3"],
    ))
    .unwrap();
    assert!(max_abs_diff(&points(&back).concat(), &EXAMPLE2_CUBIC.concat()) < 1e-13);
    // The unified command goes both ways.
    let via_change: Value = serde_json::from_str(&ok(
        dir.path(),
        &["bezier", "change", "q.json", "--to", "3"],
    ))
    .unwrap();
    assert!(max_abs_diff(&points(&via_change).concat(), &EXAMPLE2_CUBIC.concat()) < 1e-13);
}

#[test]
fn approximate_reduction_reports_its_error() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    for extra in [&[][..], &["--continuity", "0,0"], &["--norm", "chebyshev"]] {
        let mut args = vec!["bezier", "reduce", "ex2.json", "--to", "2", "--approx"];
        args.extend_from_slice(extra);
        let json: Value = serde_json::from_str(&ok(dir.path(), &args)).unwrap();
        assert_eq!(json["type"], "bezier_curve");
        assert_eq!(points(&json).len(), 3);
        let l2 = json["error"]["l2"].as_f64().expect("error.l2");
        let linf = json["error"]["linf_bound"]
            .as_f64()
            .expect("error.linf_bound");
        assert!(l2 > 0.0 && linf >= l2, "l2 {l2}, linf {linf}");
        if extra.first() == Some(&"--continuity") {
            let p = points(&json);
            assert!(max_abs_diff(&p[..1].concat(), &[10.0, 0.0]) < 1e-12);
            assert!(max_abs_diff(&p[2..].concat(), &[20.0, 0.0]) < 1e-12);
        }
    }
    // The output with its error report reads back as a curve.
    ok(
        dir.path(),
        &[
            "bezier", "reduce", "ex2.json", "--to", "2", "--approx", "-o", "a.json",
        ],
    );
    ok(dir.path(), &["bezier", "degree", "a.json"]);
}

#[test]
fn eval_writes_csv() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    ok(
        dir.path(),
        &[
            "bezier",
            "eval",
            "ex2.json",
            "--samples",
            "11",
            "-o",
            "pts.csv",
        ],
    );
    let csv = fs::read_to_string(dir.path().join("pts.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 12);
    assert_eq!(lines[0], "x,y");
    assert_eq!(lines[1], "10.0,0.0");
    assert_eq!(lines[11], "20.0,0.0");

    write(dir.path(), "bicubic.json", BICUBIC);
    let csv = ok(
        dir.path(),
        &["bezier", "eval", "bicubic.json", "--samples", "5"],
    );
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 26);
    assert_eq!(lines[0], "u,v,x,y,z");
    assert_eq!(lines[1], "0.0,0.0,0.0,0.0,0.0");
    assert_eq!(lines[25], "1.0,1.0,6.9,6.0,0.4");
}

#[test]
fn svg_output_draws_both_polygons() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    ok(
        dir.path(),
        &[
            "bezier", "reduce", "ex2.json", "--to", "3", "-o", "fig2.svg",
        ],
    );
    let svg = fs::read_to_string(dir.path().join("fig2.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("old polygon, degree 5") && svg.contains("new polygon, degree 3"));
    write(dir.path(), "bicubic.json", BICUBIC);
    ok(
        dir.path(),
        &[
            "bezier",
            "elevate",
            "bicubic.json",
            "--to",
            "4,5",
            "-o",
            "s.svg",
        ],
    );
    let svg = fs::read_to_string(dir.path().join("s.svg")).unwrap();
    assert!(svg.contains("new net, degrees (4, 5)"));
}

#[test]
fn bad_input_gives_one_line_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: [(&str, &str, &str); 8] = [
        (
            "nan.json",
            r#"{"type":"bezier_curve","points":[[0,0],[1,"NaN"],[2,0]]}"#,
            "points[1][1] is the string \"NaN\"",
        ),
        (
            "huge.json",
            r#"{"type":"bezier_curve","points":[[0,0],[1,1e999]]}"#,
            "number out of range",
        ),
        (
            "ragged.json",
            r#"{"type":"bezier_surface","net":[[[0,0,0],[1,0,0]],[[0,1,0]]]}"#,
            "ragged net: row 1 has 1 point but row 0 has 2",
        ),
        (
            "empty.json",
            r#"{"type":"bezier_curve","points":[]}"#,
            "\"points\" is empty",
        ),
        (
            "type.json",
            r#"{"type":"nurbs_curve","points":[[0,0]]}"#,
            "unknown type \"nurbs_curve\"",
        ),
        (
            "broken.json",
            r#"{"type":"bezier_curve","points":[[0,0]"#,
            "invalid JSON",
        ),
        (
            "weights.json",
            r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1,0]}"#,
            "weight 1 is 0",
        ),
        (
            "dims.json",
            r#"{"type":"bezier_curve","points":[[0,0],[1,1,1]]}"#,
            "points[1] has 3 coordinates but the first point has 2",
        ),
    ];
    for (name, text, want) in cases {
        write(d, name, text);
        for args in [
            vec!["bezier", "elevate", name, "--to", "7", "-o", "out.json"],
            vec!["bezier", "degree", name],
            vec!["bezier", "eval", name, "--samples", "3", "-o", "out.csv"],
        ] {
            let err = fails(
                d,
                &args,
                args.last().filter(|a| a.starts_with("out")).copied(),
            );
            assert!(err.contains(name), "{err} does not name the file");
            assert!(err.contains(want), "{err} does not say {want:?}");
        }
    }
}

#[test]
fn impossible_reduction_names_the_real_degree() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "ex2.json", EXAMPLE2);
    for out in ["out.json", "out.svg"] {
        let err = fails(
            dir.path(),
            &["bezier", "reduce", "ex2.json", "--to", "2", "-o", out],
            Some(out),
        );
        assert!(err.contains("real degree is 3"), "{err}");
        assert!(err.contains("--approx"), "{err}");
    }
    // An existing output file keeps its contents when a command fails.
    write(dir.path(), "keep.json", "old");
    fails(
        dir.path(),
        &[
            "bezier",
            "reduce",
            "ex2.json",
            "--to",
            "2",
            "-o",
            "keep.json",
        ],
        None,
    );
    assert_eq!(
        fs::read_to_string(dir.path().join("keep.json")).unwrap(),
        "old"
    );
    // Surfaces name the direction.
    write(dir.path(), "bicubic.json", BICUBIC);
    let err = fails(
        dir.path(),
        &[
            "bezier",
            "reduce",
            "bicubic.json",
            "--to",
            "2,3",
            "-o",
            "s.json",
        ],
        Some("s.json"),
    );
    assert!(err.contains("real u-degree is 3"), "{err}");
}

#[test]
fn misuse_gives_one_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "ex2.json", EXAMPLE2);
    write(d, "bicubic.json", BICUBIC);
    write(
        d,
        "line4d.json",
        r#"{"type":"bezier_curve","points":[[0,0,0,0],[1,1,1,1]]}"#,
    );
    let cases: [(&[&str], Option<&str>, &str); 9] = [
        (
            &["bezier", "degree", "missing.json"],
            None,
            "cannot read missing.json",
        ),
        (
            &["bezier", "elevate", "ex2.json", "--to", "3", "-o", "o.json"],
            Some("o.json"),
            "elevation needs",
        ),
        (
            &[
                "bezier", "elevate", "ex2.json", "--to", "6,6", "-o", "o.json",
            ],
            Some("o.json"),
            "one target degree",
        ),
        (
            &[
                "bezier",
                "elevate",
                "bicubic.json",
                "--to",
                "6",
                "-o",
                "o.json",
            ],
            Some("o.json"),
            "--to N,M",
        ),
        (
            &["bezier", "elevate", "ex2.json", "--to", "6", "-o", "o.txt"],
            Some("o.txt"),
            ".json",
        ),
        (
            &[
                "bezier",
                "reduce",
                "bicubic.json",
                "--to",
                "2,2",
                "--approx",
                "-o",
                "o.json",
            ],
            Some("o.json"),
            "curves only",
        ),
        (
            &[
                "bezier",
                "eval",
                "ex2.json",
                "--samples",
                "1",
                "-o",
                "o.csv",
            ],
            Some("o.csv"),
            "at least 2",
        ),
        // Computed first, then the picture fails: no file.
        (
            &[
                "bezier",
                "elevate",
                "line4d.json",
                "--to",
                "3",
                "-o",
                "o.svg",
            ],
            Some("o.svg"),
            "dimension 4",
        ),
        (
            &["bezier", "degree", "ex2.json", "--tolerance", "-1"],
            None,
            "tolerance -1",
        ),
    ];
    for (args, output, want) in cases {
        let err = fails(d, args, output);
        assert!(err.contains(want), "{args:?}: {err} does not say {want:?}");
    }
    // Usage errors exit with 2, in one line too: a value that does not parse, a missing
    // argument, an unknown command.
    for (args, want) in [
        (
            &["bezier", "reduce", "ex2.json", "--to", "2", "--norm", "l2"][..],
            "error: the following required arguments were not provided: --approx",
        ),
        (
            &["compose", "body", "cube", "--format", "fortran"],
            "error: invalid value 'fortran' for '--format <F>': unknown --format \"fortran\"",
        ),
        (&["pointcalc", "formula", "m.json"], "--format <FORMAT>"),
        (&["frob"], "error: unrecognized subcommand 'frob'"),
    ] {
        let out = geomkit(d, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = stderr(&out);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.contains(want) && err.ends_with("(see --help)\n"),
            "{args:?}: {err}"
        );
    }
}

#[test]
fn demo_writes_an_index_of_existing_files() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("nested/demo");
    let out = geomkit(dir.path(), &["demo", "--out", out_dir.to_str().unwrap()]);
    let text = stdout(&out);
    assert!(
        out.status.success(),
        "demo failed:\n{text}\n{}",
        stderr(&out)
    );
    assert!(text.contains("all passed"), "{text}");
    assert!(!text.contains("FAIL"), "{text}");
    let index = fs::read_to_string(out_dir.join("index.html")).unwrap();
    let mut referenced = 0;
    for attr in ["src=\"", "href=\""] {
        for part in index.split(attr).skip(1) {
            let target = &part[..part.find('"').unwrap()];
            if target.starts_with('#') {
                continue;
            }
            assert!(
                out_dir.join(target).is_file(),
                "index.html references missing {target}"
            );
            referenced += 1;
        }
    }
    assert!(referenced >= 20, "only {referenced} files referenced");
    // The model files it writes are valid inputs.
    ok(
        dir.path(),
        &[
            "bezier",
            "degree",
            out_dir.join("fig2_degree5.json").to_str().unwrap(),
        ],
    );
}

#[test]
fn snapshots_of_help_and_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    insta::assert_snapshot!("bezier_help", ok(d, &["bezier", "--help"]));
    insta::assert_snapshot!("reduce_help", ok(d, &["bezier", "reduce", "--help"]));
    // Integer points whose elevation is exact in f64.
    write(
        d,
        "quad.json",
        r#"{"type":"bezier_curve","points":[[0,0],[3,6],[9,0]]}"#,
    );
    insta::assert_snapshot!(
        "elevate_json",
        ok(d, &["bezier", "elevate", "quad.json", "--to", "3"])
    );
}

/// Values that start with "-" in the forms `--help` documents are taken as values (clap
/// used to take them for options): `--continuity -,4` leaves the start free, `--nodes
/// -9,0,4` puts a node at -9.
#[test]
fn documented_values_starting_with_a_hyphen_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let nonic: Vec<String> = [0., 3., -1., 4., 0., 2., 1., 5., 0., 1.]
        .iter()
        .enumerate()
        .map(|(i, y)| format!("[{i},{y}]"))
        .collect();
    write(
        d,
        "d9.json",
        &format!(
            r#"{{"type":"bezier_curve","points":[{}]}}"#,
            nonic.join(",")
        ),
    );
    let out = ok(
        d,
        &[
            "bezier",
            "reduce",
            "d9.json",
            "--to",
            "4",
            "--approx",
            "--continuity",
            "-,4",
        ],
    );
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let p = v["points"].as_array().unwrap();
    assert_eq!(p.len(), 5);
    // C^4 at t = 1 fixes the end point itself.
    assert_eq!(p[4], serde_json::json!([9.0, 1.0]));
    write(d, "p3.json", "[[0,0],[1,2],[3,1]]");
    let out = ok(d, &["pointcalc", "curve", "p3.json", "--nodes", "-9,0,4"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["nodes"], serde_json::json!([-9.0, 0.0, 4.0]));
    assert_eq!(v["samples"][0], serde_json::json!([-9.0, 0.0, 0.0]));
}
