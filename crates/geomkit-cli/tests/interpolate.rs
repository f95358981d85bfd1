//! End-to-end tests of `geomkit interpolate` and `geomkit eval`: CSV and .npy inputs, every
//! output format read back, bad inputs (one line naming the place, no file left behind), the
//! streaming tile solve against the in-memory one, surfaces from heights and from points.

mod common;

use common::{fails, max_abs_diff, npy_bytes, ok, write};
use serde_json::Value;
use std::fs;
use std::path::Path;

/// Reads a float64 .npy file: (shape, data).
fn read_npy(path: &Path) -> (Vec<usize>, Vec<f64>) {
    let bytes = fs::read(path).unwrap();
    assert_eq!(&bytes[..6], b"\x93NUMPY");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let inner = header
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape: Vec<usize> = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    let data: Vec<f64> = bytes[10 + len..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(shape.iter().product::<usize>(), data.len());
    (shape, data)
}

/// Parses CSV text with a header line into rows of numbers.
fn csv_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Six points of a plane trajectory, as CSV with a header.
const POINTS: &str = "x,y\n1,1\n3,4\n6,4.5\n8,2\n11,2.5\n13,5\n";
const POINTS_FLAT: [f64; 12] = [1.0, 1.0, 3.0, 4.0, 6.0, 4.5, 8.0, 2.0, 11.0, 2.5, 13.0, 5.0];

#[test]
fn curve_json_passes_through_the_points_read_back_by_eval() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "p.csv", POINTS);
    for (end, param) in [
        ("not-a-knot", "chord"),
        ("repeat", "uniform"),
        ("natural", "centripetal"),
        ("clamped", "chord"),
        ("outer", "uniform"),
        ("periodic", "chord"),
    ] {
        let json = ok(
            d,
            &[
                "interpolate",
                "curve",
                "p.csv",
                "--end",
                end,
                "--param",
                param,
            ],
        );
        let v: Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["type"], "bspline_curve");
        assert_eq!(v["degree"], 3);
        let t = numbers(&v["parameters"]);
        assert_eq!(t.len(), 6, "{end}");
        let at: String = std::iter::once("t\n".to_string())
            .chain(t.iter().map(|x| format!("{x:?}\n")))
            .collect();
        write(d, "m.json", &json);
        write(d, "t.csv", &at);
        let rows = csv_rows(&ok(d, &["eval", "m.json", "--at", "t.csv"]));
        let got: Vec<f64> = rows.iter().flat_map(|r| r[1..].to_vec()).collect();
        assert!(
            max_abs_diff(&got, &POINTS_FLAT) < 1e-13,
            "{end}/{param}: {got:?}"
        );
    }
    // The paper's repeated ends: N + 4 control points.
    let v: Value = serde_json::from_str(&ok(
        d,
        &["interpolate", "curve", "p.csv", "--end", "repeat"],
    ))
    .unwrap();
    assert_eq!(v["control_points"].as_array().unwrap().len(), 10);
}

#[test]
fn npy_input_gives_the_csv_result() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "p.csv", POINTS);
    fs::write(d.join("p.npy"), npy_bytes(&[6, 2], &POINTS_FLAT)).unwrap();
    let a = ok(d, &["interpolate", "curve", "p.csv"]);
    let b = ok(d, &["interpolate", "curve", "p.npy"]);
    assert_eq!(a, b);
    // 1-D points: a function of the parameter; blank-separated CSV without a header.
    write(d, "f.txt", "0\n1\n0\n2\n");
    fs::write(d.join("f.npy"), npy_bytes(&[4], &[0.0, 1.0, 0.0, 2.0])).unwrap();
    let a = ok(d, &["interpolate", "curve", "f.txt", "--param", "uniform"]);
    let b = ok(d, &["interpolate", "curve", "f.npy", "--param", "uniform"]);
    assert_eq!(a, b);
    // 3-D points separated by semicolons.
    write(d, "s.csv", "0;0;0\n1;2;1\n3;3;0\n4;0;2\n");
    let v: Value = serde_json::from_str(&ok(d, &["interpolate", "curve", "s.csv"])).unwrap();
    assert_eq!(v["control_points"][0].as_array().unwrap().len(), 3);
}

#[test]
fn every_curve_output_format() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "p.csv", POINTS);
    ok(d, &["interpolate", "curve", "p.csv", "-o", "m.json"]);
    // Samples as CSV and .npy: the same points, from the first to the last reference point.
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "p.csv",
            "-o",
            "s.csv",
            "--samples",
            "101",
        ],
    );
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "p.csv",
            "-o",
            "s.npy",
            "--samples",
            "101",
        ],
    );
    let text = fs::read_to_string(d.join("s.csv")).unwrap();
    assert!(text.starts_with("x,y\n"));
    let rows = csv_rows(&text);
    let (shape, data) = read_npy(&d.join("s.npy"));
    assert_eq!(shape, [101, 2]);
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    assert_eq!(flat, data);
    assert!(max_abs_diff(&data[..2], &POINTS_FLAT[..2]) < 1e-12);
    assert!(max_abs_diff(&data[200..], &POINTS_FLAT[10..]) < 1e-12);
    // ... equal to the model evaluated directly.
    let direct = csv_rows(&ok(d, &["eval", "m.json", "--samples", "101"]));
    let direct: Vec<f64> = direct.iter().flat_map(|r| r[1..].to_vec()).collect();
    assert!(max_abs_diff(&direct, &data) < 1e-12);
    // eval writes .npy with the parameter column first.
    ok(d, &["eval", "m.json", "--samples", "101", "-o", "e.npy"]);
    let (shape, e) = read_npy(&d.join("e.npy"));
    assert_eq!(shape, [101, 3]);
    assert_eq!(e[1..3], direct[..2]);
    // Control points and knots as a pair, read back by eval.
    for ext in ["csv", "npy"] {
        let out = format!("c.{ext}");
        ok(
            d,
            &["interpolate", "curve", "p.csv", "--control", "-o", &out],
        );
        assert!(d.join(format!("c.knots.{ext}")).is_file());
        let again = csv_rows(&ok(d, &["eval", &out, "--samples", "101"]));
        let again: Vec<f64> = again.iter().flat_map(|r| r[1..].to_vec()).collect();
        assert_eq!(again, direct, "{ext}");
    }
    let (shape, _) = read_npy(&d.join("c.npy"));
    assert_eq!(shape, [8, 2]);
    let (shape, _) = read_npy(&d.join("c.knots.npy"));
    assert_eq!(shape, [12]);
    // A picture.
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "p.csv",
            "--end",
            "repeat",
            "-o",
            "c.svg",
        ],
    );
    let svg = fs::read_to_string(d.join("c.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("control polygon, 10 points") && svg.contains("reference points (6)"));
    assert!(!svg.contains("NaN"));
    // Bézier models evaluate too, on [0, 1].
    write(
        d,
        "b.json",
        r#"{"type":"bezier_curve","points":[[0,0],[1,2],[2,0]]}"#,
    );
    let rows = csv_rows(&ok(d, &["eval", "b.json", "--samples", "3"]));
    assert_eq!(
        rows,
        [
            vec![0.0, 0.0, 0.0],
            vec![0.5, 1.0, 1.0],
            vec![1.0, 2.0, 0.0]
        ]
    );
}

#[test]
fn bad_inputs_name_the_place_and_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: [(&str, &str, &[&str], &str); 9] = [
        (
            "word.csv",
            "x,y\n0,0\n1,2\n3,abc\n",
            &[],
            "word.csv:4:2: \"abc\" is not a number",
        ),
        (
            "ragged.csv",
            "0,0\n1,2\n3,4,5\n",
            &[],
            "ragged.csv:3: 3 columns but line 1 has 2",
        ),
        (
            "nan.csv",
            "0,0\n1,nan\n",
            &[],
            "nan.csv:2:2: \"nan\" is not a finite number",
        ),
        ("empty.csv", "1,\n", &[], "empty.csv:1:2: empty cell"),
        (
            "closed1.csv",
            "0,0\n0,0\n",
            &["--end", "periodic"],
            "too few points for --end periodic: got 1, need at least 2",
        ),
        (
            "one.csv",
            "0,0\n",
            &[],
            "too few points for --end not-a-knot: got 1, need at least 2",
        ),
        (
            "dup.csv",
            "0,0\n1,2\n# same again\n1,2\n",
            &[],
            "dup.csv: lines 2 and 4 hold the same point",
        ),
        ("words.csv", "x,y\n", &[], "words.csv: no numbers"),
        (
            "tangent.csv",
            POINTS,
            &["--end", "clamped", "--start-tangent", "1,2,3"],
            "--start-tangent has 3 coordinates",
        ),
    ];
    for (name, text, extra, want) in cases {
        write(d, name, text);
        for out in ["o.json", "o.csv", "o.npy", "o.svg"] {
            let mut args = vec!["interpolate", "curve", name, "-o", out];
            args.extend_from_slice(extra);
            let err = fails(d, &args, Some(out));
            assert!(err.contains(want), "{err} does not say {want:?}");
        }
    }
    // .npy inputs: non-finite values by index, wrong shapes, truncation.
    fs::write(
        d.join("inf.npy"),
        npy_bytes(&[3, 2], &[0.0, 0.0, 1.0, f64::INFINITY, 2.0, 0.0]),
    )
    .unwrap();
    let err = fails(
        d,
        &["interpolate", "curve", "inf.npy", "-o", "o.json"],
        Some("o.json"),
    );
    assert!(err.contains("inf.npy: element [1, 1] is inf"), "{err}");
    fs::write(d.join("cube.npy"), npy_bytes(&[2, 2, 2], &[0.0; 8])).unwrap();
    let err = fails(d, &["interpolate", "curve", "cube.npy"], None);
    assert!(
        err.contains("shape (N, d)") && err.contains("(2, 2, 2)"),
        "{err}"
    );
    let mut short = npy_bytes(&[3, 2], &[0.0; 6]);
    short.truncate(short.len() - 4);
    fs::write(d.join("short.npy"), short).unwrap();
    let err = fails(d, &["interpolate", "curve", "short.npy"], None);
    assert!(err.contains("short.npy") && err.contains("(3, 2)"), "{err}");
    // An existing output keeps its contents.
    write(d, "keep.json", "old");
    fails(
        d,
        &["interpolate", "curve", "word.csv", "-o", "keep.json"],
        None,
    );
    assert_eq!(fs::read_to_string(d.join("keep.json")).unwrap(), "old");
    // Misuse of options.
    write(d, "p.csv", POINTS);
    for (args, want) in [
        (
            &["interpolate", "curve", "p.csv", "-o", "o.txt"][..],
            "cannot tell the output format",
        ),
        (
            &[
                "interpolate",
                "curve",
                "p.csv",
                "--end",
                "repeat",
                "--param",
                "chord",
            ],
            "needs uniform",
        ),
        (
            &[
                "interpolate",
                "curve",
                "p.csv",
                "--tile",
                "100",
                "--end",
                "periodic",
            ],
            "--tile takes",
        ),
        (&["interpolate", "curve", "p.csv", "--control"], "--control"),
        (
            &[
                "interpolate",
                "curve",
                "p.csv",
                "--samples",
                "1",
                "-o",
                "o.csv",
            ],
            "--samples",
        ),
        (
            &["interpolate", "curve", "p.csv", "--offset", "0.5"],
            "--end outer",
        ),
        (&["eval", "p.csv", "--samples", "3"], "knots"),
        (
            &["interpolate", "curve", "missing.csv"],
            "cannot read missing.csv",
        ),
    ] {
        let err = fails(d, args, None);
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

#[test]
fn given_parameters_like_make_interp_spline() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "pts.csv", "0,1\n1,3\n2,2\n3,0\n4,1\n");
    write(d, "x.csv", "0\n0.5\n2\n2.5\n4\n");
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "pts.csv",
            "--params",
            "x.csv",
            "-o",
            "f.json",
        ],
    );
    let rows = csv_rows(&ok(d, &["eval", "f.json", "--at", "x.csv"]));
    let want = [[0.0, 1.0], [1.0, 3.0], [2.0, 2.0], [3.0, 0.0], [4.0, 1.0]];
    assert_eq!(rows.len(), 5);
    for (row, w) in rows.iter().zip(want) {
        assert!(max_abs_diff(&row[1..], &w) < 1e-14, "{row:?}");
    }
    write(d, "bad.csv", "0\n0.5\n2\n2\n4\n");
    let err = fails(
        d,
        &[
            "interpolate",
            "curve",
            "pts.csv",
            "--params",
            "bad.csv",
            "-o",
            "g.json",
        ],
        Some("g.json"),
    );
    assert!(
        err.contains("bad.csv") && err.contains("strictly increasing"),
        "{err}"
    );
    write(d, "two.csv", "0,1\n1,2\n");
    let err = fails(
        d,
        &["interpolate", "curve", "pts.csv", "--params", "two.csv"],
        None,
    );
    assert!(err.contains("one parameter per line"), "{err}");
}

#[test]
fn eval_checks_its_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(d, "p.csv", POINTS);
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "p.csv",
            "--param",
            "uniform",
            "-o",
            "m.json",
        ],
    );
    write(d, "t.csv", "0\n2.5\n9\n");
    let err = fails(
        d,
        &["eval", "m.json", "--at", "t.csv", "-o", "o.csv"],
        Some("o.csv"),
    );
    assert!(
        err.contains("t.csv: line 3: t = 9 is outside the domain [0, 5]"),
        "{err}"
    );
    write(d, "uv.csv", "0,0\n");
    let err = fails(d, &["eval", "m.json", "--at", "uv.csv"], None);
    assert!(err.contains("a curve takes one column"), "{err}");
    let err = fails(d, &["eval", "m.json", "--samples", "3x3"], None);
    assert!(err.contains("is a curve"), "{err}");
    // A B-spline model handed to `bezier` says where to go.
    let err = fails(d, &["bezier", "degree", "m.json"], None);
    assert!(err.contains("geomkit eval"), "{err}");
}

/// A smooth wiggly path of `n` points, flat.
fn path(n: usize) -> Vec<f64> {
    (0..n)
        .flat_map(|i| {
            let t = i as f64 * 0.01;
            [
                t + 0.3 * (7.0 * t).sin(),
                (3.0 * t).cos() * (1.0 + 0.01 * t),
            ]
        })
        .collect()
}

#[test]
fn streaming_tiles_equal_the_in_memory_solve() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 200_000;
    let points = path(n);
    fs::write(d.join("big.npy"), npy_bytes(&[n, 2], &points)).unwrap();
    let scale = points.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for param in ["chord", "uniform", "centripetal"] {
        ok(
            d,
            &[
                "interpolate",
                "curve",
                "big.npy",
                "--param",
                param,
                "--control",
                "-o",
                "g.npy",
            ],
        );
        ok(
            d,
            &[
                "interpolate",
                "curve",
                "big.npy",
                "--param",
                param,
                "--tile",
                "7000",
                "--control",
                "-o",
                "s.npy",
            ],
        );
        let (gs, g) = read_npy(&d.join("g.npy"));
        let (ss, s) = read_npy(&d.join("s.npy"));
        assert_eq!(gs, [n + 2, 2]);
        assert_eq!(ss, gs);
        let err = max_abs_diff(&g, &s);
        assert!(err <= 4.0 * f64::EPSILON * scale, "{param}: {err}");
        // Same knots, bit for bit (the tiles chain the global parameters).
        assert_eq!(
            read_npy(&d.join("g.knots.npy")),
            read_npy(&d.join("s.knots.npy"))
        );
    }
    // Streaming to CSV with another end condition and a small halo still matches closely.
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "big.npy",
            "--end",
            "natural",
            "--tile",
            "50000",
            "--control",
            "-o",
            "s.csv",
        ],
    );
    ok(
        d,
        &[
            "interpolate",
            "curve",
            "big.npy",
            "--end",
            "natural",
            "-o",
            "g.json",
        ],
    );
    let g: Value = serde_json::from_str(&fs::read_to_string(d.join("g.json")).unwrap()).unwrap();
    let g: Vec<f64> = g["control_points"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(numbers)
        .collect();
    let s: Vec<f64> = csv_rows(&fs::read_to_string(d.join("s.csv")).unwrap())
        .into_iter()
        .flatten()
        .collect();
    assert!(max_abs_diff(&g, &s) <= 4.0 * f64::EPSILON * scale);
    // A duplicate point deep inside a tile is reported by its row.
    let mut dup = points.clone();
    dup[2 * 123_457] = dup[2 * 123_456];
    dup[2 * 123_457 + 1] = dup[2 * 123_456 + 1];
    fs::write(d.join("dup.npy"), npy_bytes(&[n, 2], &dup)).unwrap();
    let err = fails(
        d,
        &[
            "interpolate",
            "curve",
            "dup.npy",
            "--tile",
            "7000",
            "--control",
            "-o",
            "x.npy",
        ],
        Some("x.npy"),
    );
    assert!(
        err.contains("rows 123456 and 123457 hold the same point"),
        "{err}"
    );
    assert!(!d.join("x.knots.npy").exists());
}

/// Heights z = sin(x/3)·cos(y/4)·3 on a 9×7 grid.
fn heights(rows: usize, cols: usize) -> Vec<f64> {
    (0..rows * cols)
        .map(|k| {
            let (i, j) = ((k / cols) as f64, (k % cols) as f64);
            3.0 * (i / 3.0).sin() * (j / 4.0).cos()
        })
        .collect()
}

#[test]
fn surface_from_heights() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (r, c) = (9, 7);
    let z = heights(r, c);
    let csv: String = z
        .chunks(c)
        .map(|row| {
            row.iter()
                .map(|x| format!("{x:?}"))
                .collect::<Vec<_>>()
                .join(",")
                + "\n"
        })
        .collect();
    write(d, "h.csv", &csv);
    fs::write(d.join("h.npy"), npy_bytes(&[r, c], &z)).unwrap();
    let args = ["--heights", "--dx", "0.5", "--dy", "2", "--x0", "-1"];
    let mut a = vec!["interpolate", "surface", "h.csv"];
    a.extend_from_slice(&args);
    let json = ok(d, &a);
    a[2] = "h.npy";
    assert_eq!(ok(d, &a), json);
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["type"], "bspline_surface");
    assert_eq!(v["net"].as_array().unwrap().len(), r + 2);
    assert_eq!(
        v["net"][0][0].as_array().unwrap().len(),
        1,
        "heights have 1-D net points"
    );
    // Evaluated at the grid coordinates, the surface gives the heights back.
    write(d, "h.json", &json);
    let (xs, ys) = (numbers(&v["parameters_u"]), numbers(&v["parameters_v"]));
    assert_eq!(xs[1], -0.5);
    assert_eq!(ys[1], 2.0);
    let uv: String = std::iter::once("u,v\n".to_string())
        .chain(
            xs.iter()
                .flat_map(|x| ys.iter().map(move |y| format!("{x:?},{y:?}\n"))),
        )
        .collect();
    write(d, "uv.csv", &uv);
    let rows = csv_rows(&ok(d, &["eval", "h.json", "--at", "uv.csv"]));
    let got: Vec<f64> = rows.iter().map(|row| row[2]).collect();
    assert!(max_abs_diff(&got, &z) < 1e-13);
    // A sample grid has columns x,y,z over the whole grid.
    a.extend_from_slice(&["-o", "g.csv", "--samples", "5x3"]);
    ok(d, &a);
    let text = fs::read_to_string(d.join("g.csv")).unwrap();
    assert!(text.starts_with("x,y,z\n"));
    let rows = csv_rows(&text);
    assert_eq!(rows.len(), 15);
    assert_eq!(rows[0][..2], [-1.0, 0.0]);
    assert_eq!(rows[14][..2], [3.0, 12.0]);
    assert!((rows[14][2] - z[r * c - 1]).abs() < 1e-13);
    let n = a.len();
    a[n - 3] = "g.npy";
    ok(d, &a);
    let (shape, data) = read_npy(&d.join("g.npy"));
    assert_eq!(shape, [5, 3, 3]);
    assert_eq!(data, rows.concat());
    // Mesh and picture.
    a[n - 3] = "g.obj";
    ok(d, &a);
    let obj = fs::read_to_string(d.join("g.obj")).unwrap();
    let count = |p: &str| obj.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!((count("v "), count("vn "), count("f ")), (15, 15, 16));
    // Normals of a height field point up.
    assert!(obj
        .lines()
        .filter(|l| l.starts_with("vn "))
        .all(|l| { l.split(' ').nth(3).unwrap().parse::<f64>().unwrap() > 0.0 }));
    ok(
        d,
        &[
            "interpolate",
            "surface",
            "h.csv",
            "--heights",
            "-o",
            "h.svg",
        ],
    );
    let svg = fs::read_to_string(d.join("h.svg")).unwrap();
    assert!(svg.contains("<rect") && svg.contains("contour lines") && !svg.contains("NaN"));
}

#[test]
fn surface_from_point_rows() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (r, c) = (6, 5);
    let z = heights(r, c);
    let mut csv = String::from("x,y,z\n");
    let mut flat = Vec::new();
    for (k, h) in z.iter().enumerate() {
        let (x, y) = ((k / c) as f64 * 1.5, (k % c) as f64 + 0.1 * (k / c) as f64);
        csv += &format!("{x:?},{y:?},{h:?}\n");
        flat.extend_from_slice(&[x, y, *h]);
    }
    write(d, "g.csv", &csv);
    fs::write(d.join("g.npy"), npy_bytes(&[r, c, 3], &flat)).unwrap();
    let json = ok(
        d,
        &[
            "interpolate",
            "surface",
            "g.csv",
            "--rows",
            "6",
            "--cols",
            "5",
        ],
    );
    assert_eq!(
        ok(d, &["interpolate", "surface", "g.csv", "--cols", "5"]),
        json
    );
    assert_eq!(ok(d, &["interpolate", "surface", "g.npy"]), json);
    let v: Value = serde_json::from_str(&json).unwrap();
    write(d, "s.json", &json);
    let (us, vs) = (numbers(&v["parameters_u"]), numbers(&v["parameters_v"]));
    let uv: String = us
        .iter()
        .flat_map(|u| vs.iter().map(move |v| format!("{u:?},{v:?}\n")))
        .collect();
    write(d, "uv.csv", &uv);
    let rows = csv_rows(&ok(d, &["eval", "s.json", "--at", "uv.csv"]));
    let got: Vec<f64> = rows.iter().flat_map(|row| row[2..].to_vec()).collect();
    assert!(max_abs_diff(&got, &flat) < 1e-13);
    // The paper's boundary: an (M+2)×(N+2) net, and a mixed periodic direction.
    let v: Value = serde_json::from_str(&ok(
        d,
        &[
            "interpolate",
            "surface",
            "g.npy",
            "--end",
            "outer",
            "--offset",
            "0.5",
        ],
    ))
    .unwrap();
    assert_eq!(v["net"].as_array().unwrap().len(), r + 2);
    assert_eq!(v["net"][0].as_array().unwrap().len(), c + 2);
    ok(
        d,
        &[
            "interpolate",
            "surface",
            "g.npy",
            "--end-v",
            "natural",
            "--end-u",
            "clamped",
        ],
    );
    // Outputs.
    ok(
        d,
        &[
            "interpolate",
            "surface",
            "g.npy",
            "-o",
            "s.obj",
            "--samples",
            "4",
        ],
    );
    let obj = fs::read_to_string(d.join("s.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 18);
    ok(d, &["interpolate", "surface", "g.npy", "-o", "s.svg"]);
    assert!(fs::read_to_string(d.join("s.svg"))
        .unwrap()
        .contains("control net 8×7"));
    ok(d, &["eval", "s.json", "--samples", "3x4", "-o", "e.npy"]);
    assert_eq!(read_npy(&d.join("e.npy")).0, [12, 5]);
    // Grid size mismatches.
    for (args, want) in [
        (
            &[
                "interpolate",
                "surface",
                "g.csv",
                "--rows",
                "4",
                "--cols",
                "5",
                "-o",
                "o.json",
            ][..],
            "g.csv: --rows 4 × --cols 5 = 20 grid points, but the file has 30 points (lines)",
        ),
        (
            &[
                "interpolate",
                "surface",
                "g.csv",
                "--rows",
                "7",
                "-o",
                "o.json",
            ],
            "do not divide",
        ),
        (
            &["interpolate", "surface", "g.csv", "-o", "o.json"],
            "--rows and --cols",
        ),
        (
            &[
                "interpolate",
                "surface",
                "g.npy",
                "--rows",
                "5",
                "-o",
                "o.json",
            ],
            "does not match",
        ),
        (
            &[
                "interpolate",
                "surface",
                "g.npy",
                "--heights",
                "-o",
                "o.json",
            ],
            "heights need a matrix",
        ),
        (
            &[
                "interpolate",
                "surface",
                "g.npy",
                "--end",
                "repeat",
                "--param",
                "chord",
                "-o",
                "o.json",
            ],
            "needs uniform",
        ),
    ] {
        let err = fails(d, args, Some("o.json"));
        assert!(err.contains(want), "{args:?}: {err}");
    }
    let two = "0,0,0\n1,0,0\n0,1,0\n1,1,1\n";
    write(d, "two.csv", two);
    let err = fails(
        d,
        &[
            "interpolate",
            "surface",
            "two.csv",
            "--rows",
            "2",
            "--end",
            "periodic",
            "-o",
            "o.obj",
        ],
        Some("o.obj"),
    );
    assert!(err.contains("too few"), "{err}");
}

/// All the numbers of a JSON value (nested arrays flattened, in order).
fn all_numbers(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(items) => items.iter().flat_map(all_numbers).collect(),
        Value::Number(x) => vec![x.as_f64().unwrap()],
        _ => panic!("not a number: {v}"),
    }
}

/// `interpolate surface --tile T [--halo H]` against the one solve of the same grid: the
/// same knots and parameters, bit for bit (computed once for the whole grid), and a net
/// within 64·eps of the data's scale (rounding: ~12·eps seen near the ends, the same with
/// halos of 32 and 60), with blocks of 16 and 25 points
/// a side on a 75×60 grid of uneven 3-D points (20 and 12 blocks: seams in both directions),
/// for the default ends and mixed natural/bessel ones; the misuses refused in one line.
#[test]
fn surface_tiles_equal_the_global_solve() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (r, c) = (75, 60);
    let mut flat = Vec::with_capacity(r * c * 3);
    for i in 0..r {
        for j in 0..c {
            let (fi, fj) = (i as f64, j as f64);
            let (x, y) = (
                1.5 * fi + 0.2 * (0.7 * fi).sin(),
                fj + 0.15 * (0.5 * fj).cos() + 0.05 * fi,
            );
            flat.extend_from_slice(&[x, y, 3.0 * (x / 7.0).sin() * (y / 5.0).cos()]);
        }
    }
    let scale = flat.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    fs::write(d.join("g.npy"), npy_bytes(&[r, c, 3], &flat)).unwrap();
    for ends in [&[][..], &["--end-u", "natural", "--end-v", "bessel"]] {
        for tile in [&["--tile", "16"][..], &["--tile", "25", "--halo", "40"]] {
            let mut args = vec!["interpolate", "surface", "g.npy"];
            args.extend_from_slice(ends);
            let whole: Value = serde_json::from_str(&ok(d, &args)).unwrap();
            args.extend_from_slice(tile);
            let tiled: Value = serde_json::from_str(&ok(d, &args)).unwrap();
            for key in ["parameters_u", "parameters_v", "knots_u", "knots_v"] {
                assert_eq!(tiled[key], whole[key], "{args:?}: {key}");
            }
            let (a, b) = (all_numbers(&whole["net"]), all_numbers(&tiled["net"]));
            assert_eq!(a.len(), (r + 2) * (c + 2) * 3);
            assert_eq!(a.len(), b.len());
            let err = max_abs_diff(&a, &b);
            assert!(err <= 64.0 * f64::EPSILON * scale, "{args:?}: {err}");
        }
    }
    // Sampled output through the tiles: the grid of the whole solve within rounding.
    for (out, tile) in [("w.npy", &[][..]), ("t.npy", &["--tile", "30"][..])] {
        let mut args = vec![
            "interpolate",
            "surface",
            "g.npy",
            "--samples",
            "7x9",
            "-o",
            out,
        ];
        args.extend_from_slice(tile);
        ok(d, &args);
    }
    let ((ws, w), (ts, t)) = (read_npy(&d.join("w.npy")), read_npy(&d.join("t.npy")));
    assert_eq!(
        (ws.as_slice(), ts.as_slice()),
        (&[7, 9, 3][..], &[7, 9, 3][..])
    );
    assert!(max_abs_diff(&w, &t) <= 64.0 * f64::EPSILON * scale);
    // Misuses: one line, no output.
    for (extra, want) in [
        (
            &["--tile", "1"][..],
            "--tile must be at least 2 points (got 1)",
        ),
        (&["--tile", "0"], "--tile must be at least 2 points (got 0)"),
        (
            &["--tile", "16", "--end-v", "periodic"],
            "--tile takes natural, clamped",
        ),
        (
            &["--tile", "16", "--end", "repeat", "--param", "uniform"],
            "--tile takes",
        ),
    ] {
        let mut args = vec!["interpolate", "surface", "g.npy", "-o", "o.json"];
        args.extend_from_slice(extra);
        let err = fails(d, &args, Some("o.json"));
        assert!(err.contains(want), "{args:?}: {err}");
    }
    // Usage errors (exit code 2, one line): --halo needs --tile; heights take no tiles.
    write(d, "h.csv", "0,1,2\n1,2,3\n2,3,4\n");
    for args in [
        &["interpolate", "surface", "g.npy", "--halo", "8"][..],
        &[
            "interpolate",
            "surface",
            "h.csv",
            "--heights",
            "--tile",
            "8",
        ],
    ] {
        let out = common::geomkit(d, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = common::stderr(&out);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains("--tile"), "{args:?}: {err}");
    }
}

#[test]
fn help_snapshot() {
    let dir = tempfile::tempdir().unwrap();
    insta::assert_snapshot!(
        "interpolate_help",
        ok(dir.path(), &["interpolate", "--help"])
    );
}

/// `--degree`, `--left`/`--right` and `--form scipy` against SciPy's make_interp_spline
/// (the library's reference data, `geomkit/tests/data/spline_scipy.json`, written by SciPy
/// 1.17): the JSON model and the `--control` pair hold SciPy's knots exactly and its
/// coefficients within 1e-12 of their scale (the exact ones where SciPy's are not: three
/// conditions at one end), for a quintic with two conditions at each end, a quartic with all
/// three at one end, a periodic quartic in 3-D, the cubic's string aliases and a degree-7
/// curve on x ~ 1e3.
#[test]
fn scipy_form_matches_scipy() {
    let data: Value =
        serde_json::from_str(include_str!("../../geomkit/tests/data/spline_scipy.json")).unwrap();
    let floats = |v: &Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .flat_map(|r| match r {
                Value::Array(a) => a.iter().map(|x| x.as_f64().unwrap()).collect(),
                x => vec![x.as_f64().unwrap()],
            })
            .collect()
    };
    let end_arg = |v: &Value| -> String {
        match v {
            Value::String(s) => s.clone(),
            Value::Array(list) => list
                .iter()
                .map(|d| {
                    let vals: Vec<String> =
                        floats(&d[1]).iter().map(|x| format!("{x:?}")).collect();
                    format!("{}:{}", d[0], vals.join(","))
                })
                .collect::<Vec<_>>()
                .join(";"),
            _ => unreachable!(),
        }
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in [
        "uneven14/d3/k5/split22",
        "uniform13/d1/k4/split30h",
        "uneven14/d3/k4/periodic",
        "uniform13/d1/k3/clamped-natural",
        "scaled11/d1/k7/split33",
    ] {
        let case = data["cases"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap();
        let set = &data["sets"][case["set"].as_str().unwrap()];
        let dim = case["dim"].as_u64().unwrap() as usize;
        let x = floats(&set["x"]);
        let mut y = floats(&set[format!("y{dim}").as_str()]);
        let periodic = case["ends"] == "periodic";
        if periodic {
            let n = x.len();
            let first = y[..dim].to_vec();
            y[(n - 1) * dim..].copy_from_slice(&first);
        }
        let rows = |v: &[f64], w: usize| -> String {
            v.chunks(w)
                .map(|r| {
                    r.iter()
                        .map(|x| format!("{x:?}"))
                        .collect::<Vec<_>>()
                        .join(",")
                })
                .collect::<Vec<_>>()
                .join("\n")
        };
        write(d, "y.csv", &rows(&y, dim));
        write(d, "x.csv", &rows(&x, 1));
        let k = case["k"].to_string();
        let mut args: Vec<String> = ["interpolate", "curve", "y.csv", "--params", "x.csv"]
            .iter()
            .map(|s| s.to_string())
            .chain(["--degree".into(), k, "--form".into(), "scipy".into()])
            .collect();
        if periodic {
            args.extend(["--end".into(), "periodic".into()]);
        } else {
            args.extend(["--left".into(), end_arg(&case["ends"][0])]);
            args.extend(["--right".into(), end_arg(&case["ends"][1])]);
        }
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        let model: Value = serde_json::from_str(&ok(d, &argv)).unwrap();
        assert_eq!(floats(&model["knots"]), floats(&case["t"]), "{name}: knots");
        // Where SciPy itself is inexact (all conditions at one end), the exact solution.
        let want = floats(case.get("c_exact").unwrap_or(&case["c"]));
        let got = floats(&model["control_points"]);
        let scale = want.iter().chain(&y).fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            max_abs_diff(&got, &want) <= 1e-12 * scale,
            "{name}: {got:?} vs {want:?}"
        );
        // One parameter per input point.
        assert_eq!(floats(&model["parameters"]).len(), x.len(), "{name}");
        // The --control pair: the same knots and control points.
        let mut argv = argv.clone();
        argv.extend(["--control", "-o", "c.csv"]);
        ok(d, &argv);
        let knots: Vec<f64> = fs::read_to_string(d.join("c.knots.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.parse().unwrap())
            .collect();
        assert_eq!(knots, floats(&case["t"]), "{name}: knots file");
        // `eval --nu` against SciPy's BSpline(x, nu) between the data points.
        fs::write(d.join("fit.json"), ok(d, &argv[..argv.len() - 3])).unwrap();
        let at = floats(&set["deriv_t"]);
        write(d, "at.csv", &rows(&at, 1));
        // `eval` rows: t, then the coordinates.
        let coords = |text: &str| -> Vec<f64> {
            csv_rows(text)
                .into_iter()
                .flat_map(|r| r[1..].to_vec())
                .collect()
        };
        let orders = case["deriv_orders"].as_array().unwrap();
        for (o, want) in orders.iter().zip(case["derivs"].as_array().unwrap()) {
            let nu = o.to_string();
            let text = ok(d, &["eval", "fit.json", "--at", "at.csv", "--nu", &nu]);
            let got = coords(&text);
            let want = floats(want);
            let own = want.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(max_abs_diff(&got, &want) <= 1e-9 * own, "{name}: nu {nu}");
        }
        if periodic {
            // One period on, the same values (SciPy's extrapolate='periodic').
            let period = x[x.len() - 1] - x[0];
            let shifted: Vec<f64> = at.iter().map(|t| t + 2.0 * period).collect();
            write(d, "far.csv", &rows(&shifted, 1));
            let near = ok(d, &["eval", "fit.json", "--at", "at.csv", "--nu", "1"]);
            let far = ok(
                d,
                &[
                    "eval",
                    "fit.json",
                    "--at",
                    "far.csv",
                    "--nu",
                    "1",
                    "--extrapolate",
                    "periodic",
                ],
            );
            assert!(
                max_abs_diff(&coords(&near), &coords(&far)) <= 1e-9,
                "{name}: periodic"
            );
            let err = fails(d, &["eval", "fit.json", "--at", "far.csv"], None);
            assert!(err.contains("outside the domain"), "{err}");
        }
    }
}

/// `eval --nu DU,DV` on surfaces made by `interpolate surface --heights --form scipy` against
/// SciPy's `RectBivariateSpline(x, y, z, kx, ky, s=0)` (the library's reference data): `ev(x,
/// y, dx, dy)` at scattered points through `--at`, `__call__(gx, gy, dx, dy)` on the 5 x 4
/// grid of the domain through `--samples 5x4`, for seven degree pairs from (1, 1) to (5, 5);
/// orders FITPACK refuses and a curve's single order are refused.
#[test]
fn surface_partials_match_rect_bivariate_spline() {
    let data: Value =
        serde_json::from_str(include_str!("../../geomkit/tests/data/spline_scipy.json")).unwrap();
    let s = &data["surfaces"];
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let column = |v: &[f64]| v.iter().map(|x| format!("{x:?}\n")).collect::<String>();
    write(d, "x.csv", &column(&numbers(&s["x"])));
    write(d, "y.csv", &column(&numbers(&s["y"])));
    let z: String = s["z"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let r: Vec<String> = numbers(row).iter().map(|x| format!("{x:?}")).collect();
            r.join(",") + "\n"
        })
        .collect();
    write(d, "z.csv", &z);
    let mut checked = 0;
    for case in s["cases"].as_array().unwrap() {
        let (kx, ky) = (case["kx"].as_u64().unwrap(), case["ky"].as_u64().unwrap());
        let degrees = format!("{kx},{ky}");
        let fit = "interpolate surface z.csv --heights --x x.csv --y y.csv --form scipy --degree";
        let mut argv: Vec<&str> = fit.split(' ').collect();
        argv.push(&degrees);
        fs::write(d.join("s.json"), ok(d, &argv)).unwrap();
        let at: String = case["at"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                format!(
                    "{:?},{:?}\n",
                    p[0].as_f64().unwrap(),
                    p[1].as_f64().unwrap()
                )
            })
            .collect();
        write(d, "at.csv", &at);
        // The last column of each row (z); rows start with u, v.
        let z_of = |text: &str| -> Vec<f64> { csv_rows(text).iter().map(|r| r[2]).collect() };
        let values = z_of(&ok(d, &["eval", "s.json", "--at", "at.csv", "--nu", "0,0"]));
        assert!(
            max_abs_diff(&values, &numbers(&case["values"])) <= 1e-12,
            "{degrees}"
        );
        for p in case["partials"].as_array().unwrap() {
            let nu = format!("{},{}", p["dx"], p["dy"]);
            let want = numbers(&p["values"]);
            let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            let text = ok(d, &["eval", "s.json", "--at", "at.csv", "--nu", &nu]);
            assert!(
                text.starts_with(&format!("u,v,d{}_{}x", p["dx"], p["dy"])),
                "{text}"
            );
            let got = z_of(&text);
            assert!(
                max_abs_diff(&got, &want) <= 1e-10 * scale,
                "{degrees} ev {nu}: {got:?} vs {want:?}"
            );
            let want = numbers(&p["grid"]);
            let rows = csv_rows(&ok(d, &["eval", "s.json", "--samples", "5x4", "--nu", &nu]));
            // Row-major over u (5) then v (4): SciPy's grid=True layout.
            assert_eq!((rows[4][0], rows[4][1], rows[5][0]), (1.0, -1.0, 1.0));
            let got: Vec<f64> = rows.iter().map(|r| r[2]).collect();
            assert!(
                max_abs_diff(&got, &want) <= 1e-10 * scale,
                "{degrees} grid {nu}"
            );
            checked += 1;
        }
        let bad = format!("{kx},0");
        let err = fails(d, &["eval", "s.json", "--samples", "3", "--nu", &bad], None);
        assert!(err.contains("below the degree"), "{err}");
    }
    assert!(checked >= 20, "{checked} partials checked");
    let err = fails(d, &["eval", "s.json", "--samples", "3", "--nu", "1"], None);
    assert!(err.contains("both derivative orders"), "{err}");
    let err = fails(
        d,
        &[
            "eval",
            "s.json",
            "--samples",
            "3",
            "--nu",
            "0,0",
            "--extrapolate",
            "extend",
        ],
        None,
    );
    assert!(
        err.contains("--extrapolate applies to B-spline curves"),
        "{err}"
    );
}
