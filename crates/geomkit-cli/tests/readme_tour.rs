//! The README's CLI tour runs as written: every `geomkit ...` line of its block, in order, in
//! a folder holding the input files it names (made here), succeeds — or fails with the error
//! its comment announces — and the values its comments state hold.

mod common;

use common::{geomkit, npy_bytes, stderr, stdout, write};
use std::fs;
use std::path::Path;

/// The lines of the README's `## CLI tour` block, comments kept.
fn tour() -> Vec<String> {
    let readme = include_str!("../../../README.md");
    let start = readme.find("## CLI tour").expect("a CLI tour section");
    let block = &readme[start..];
    let body = block
        .split("```sh\n")
        .nth(1)
        .unwrap()
        .split("```")
        .next()
        .unwrap();
    body.lines().map(str::to_string).collect()
}

/// Words of a command line as a POSIX shell splits this README's lines: blanks separate,
/// double or single quotes group, `#` outside quotes starts a comment.
fn words(line: &str) -> (Vec<String>, String) {
    let (mut out, mut word, mut quote, mut any) = (Vec::new(), String::new(), None, false);
    for (k, c) in line.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '"' | '\'') => {
                quote = Some(c);
                any = true;
            }
            (None, '#') => {
                if any {
                    out.push(std::mem::take(&mut word));
                }
                return (out, line[k + 1..].trim().to_string());
            }
            (None, c) if c.is_whitespace() => {
                if any {
                    out.push(std::mem::take(&mut word));
                    any = false;
                }
            }
            (None, c) => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        out.push(word);
    }
    (out, String::new())
}

/// The input files the tour names, made small.
fn inputs(d: &Path) {
    write(
        d,
        "surface.json",
        r#"{"type":"bezier_surface","net":[[[0,0,0],[0,1,0.5],[0,2,0]],[[1,0,0.5],[1,1,2],[1,2,0.5]],[[2,0,0],[2,1,0.5],[2,2,0]]]}"#,
    );
    let track: String = (0..12)
        .map(|k| {
            let t = k as f64 * 0.5;
            format!("{},{}\n", t.cos() * (1.0 + t), t.sin() * 2.0)
        })
        .collect();
    write(d, "track.csv", &track);
    write(d, "x.csv", "0\n0.5\n1.5\n2\n3.5\n4\n");
    write(d, "y.csv", "1\n2\n0\n-1\n2\n3\n");
    let isoline: String = (0..10)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 10.0;
            format!("{},{}\n", 2.0 * a.cos(), a.sin())
        })
        .collect();
    write(d, "isoline.csv", &isoline);
    let huge: Vec<f64> = (0..3000)
        .flat_map(|k| [k as f64, (k as f64 * 0.01).sin()])
        .collect();
    fs::write(d.join("huge.npy"), npy_bytes(&[3000, 2], &huge)).unwrap();
    let heights: String = (0..6)
        .map(|i| {
            (0..7)
                .map(|j| ((i * j) as f64 * 0.1).sin().to_string())
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    write(d, "heights.csv", &heights);
    write(
        d,
        "scene.json",
        r#"{"type":"composite_surface","u_knots":[0,1,2],"v_knots":[0,1],"patches":[[{"bezier":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}],[{"x":"1 + u","y":"v","z":"v*(1 - u)"}]]}"#,
    );
    write(
        d,
        "curves.json",
        r#"{"type":"ruled","v":[0,1,2],"curves":[{"point":[0,0,-1]},{"circle":{"center":[0,0,0],"radius":1}},{"x":"0","y":"0","z":"1","t":[0,1]}]}"#,
    );
    write(
        d,
        "pieces.json",
        r#"{"type":"piecewise","knots":[-1,0,1,2],"pieces":["-x","x^2","2 - x"]}"#,
    );
    let mut runs = String::from("temp,time,dose,yield\n");
    for temp in [60.0, 75.0, 90.0] {
        for time in [1.0, 2.0, 3.0] {
            for dose in [0.5, 1.0, 1.5] {
                let y = 80.0 - (temp - 78.0f64).powi(2) / 20.0 + time - dose * dose;
                runs.push_str(&format!("{temp},{time},{dose},{y}\n"));
            }
        }
    }
    write(d, "runs.csv", &runs);
    write(d, "at.csv", "temp,time,dose\n75,2.5,1.2\n60,1,0.5\n");
    write(d, "points.json", "[[0,0],[1,2],[3,1]]");
}

#[test]
fn the_readme_cli_tour_runs_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    inputs(d);
    let mut ran = 0;
    for line in tour() {
        let (w, comment) = words(&line);
        match w.first().map(String::as_str) {
            None => continue,
            Some("echo") => {
                // echo 'JSON' > FILE
                assert_eq!((w.len(), w[2].as_str()), (4, ">"), "{line}");
                write(d, &w[3], &w[1]);
                continue;
            }
            Some("geomkit") => {}
            Some(other) => panic!("the tour runs geomkit and echo only, not {other}: {line}"),
        }
        if w[1] == "demo" {
            continue; // the whole gallery: tests/e2e/run.sh runs it
        }
        // The tour's later lines read files that earlier lines write: the fit of `compose
        // piecewise fit.json` and `compose patches surf.json` are written first.
        if w.iter().any(|a| a == "fit.json") && !d.join("fit.json").exists() {
            let out = geomkit(d, &["interpolate", "curve", "track.csv", "-o", "fit.json"]);
            assert!(out.status.success(), "{}", stderr(&out));
        }
        if w.iter().any(|a| a == "surf.json") && !d.join("surf.json").exists() {
            let out = geomkit(
                d,
                &[
                    "interpolate",
                    "surface",
                    "heights.csv",
                    "--heights",
                    "-o",
                    "surf.json",
                ],
            );
            assert!(out.status.success(), "{}", stderr(&out));
        }
        let args: Vec<&str> = w[1..].iter().map(String::as_str).collect();
        let out = geomkit(d, &args);
        ran += 1;
        if let Some(want) = comment.strip_prefix("error: ") {
            assert_eq!(out.status.code(), Some(1), "{line}");
            for part in want.split("...").map(str::trim).filter(|p| !p.is_empty()) {
                assert!(stderr(&out).contains(part), "{line}: {}", stderr(&out));
            }
            continue;
        }
        assert!(out.status.success(), "{line}: {}", stderr(&out));
        // Every output file named by -o exists and is not empty.
        if let Some(k) = args.iter().position(|a| *a == "-o") {
            let file = d.join(args[k + 1]);
            assert!(fs::metadata(&file).is_ok_and(|m| m.len() > 0), "{line}");
        }
        let text = stdout(&out);
        // The values the comments state.
        if comment.starts_with('{') && comment.ends_with('}') {
            let got: serde_json::Value = serde_json::from_str(&text).unwrap();
            let want: serde_json::Value = serde_json::from_str(&comment).unwrap();
            assert_eq!(got, want, "{line}");
        }
        if comment.starts_with("the cubic (10,0),(30,10),(0,20),(20,0)") {
            let got: serde_json::Value = serde_json::from_str(&text).unwrap();
            let points: Vec<Vec<f64>> = serde_json::from_value(got["points"].clone()).unwrap();
            let want = [[10.0, 0.0], [30.0, 10.0], [0.0, 20.0], [20.0, 0.0]];
            for (p, q) in points.iter().zip(want) {
                assert!(
                    (p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12,
                    "{p:?}"
                );
            }
            assert_eq!(points.len(), 4);
        }
        if comment.contains("\"error\":{\"l2\"") {
            let got: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert!(got["error"]["l2"].as_f64().unwrap() > 0.0, "{text}");
            assert!(
                got["error"]["linf_bound"].as_f64().unwrap()
                    >= got["error"]["l2"].as_f64().unwrap()
            );
        }
    }
    assert!(ran >= 30, "only {ran} commands in the tour");
}

#[test]
fn the_line_splitter_splits_as_a_shell_does() {
    let (w, c) = words(r#"geomkit compose body prism --polygon "0,0;2,0;1,1.5" -o p.stl   # mesh"#);
    assert_eq!(
        w,
        [
            "geomkit",
            "compose",
            "body",
            "prism",
            "--polygon",
            "0,0;2,0;1,1.5",
            "-o",
            "p.stl"
        ]
    );
    assert_eq!(c, "mesh");
    let (w, c) = words(r#"echo '{"a":[1, 2]}' > a.json"#);
    assert_eq!(w, ["echo", r#"{"a":[1, 2]}"#, ">", "a.json"]);
    assert_eq!(c, "");
}
