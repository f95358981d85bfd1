//! `geomkit interpolate curve --tile T --degree k` (issue 22: tiles for every degree): the
//! streaming solve of a .npy into --control files against the whole-curve solve of the same
//! command without --tile (itself checked against SciPy in `interpolate.rs`), the in-memory
//! tiles of the other outputs, and the refusals (one line, no file left behind).

mod common;

use common::{fails, max_abs_diff, npy_bytes, ok};
use std::fs;
use std::path::Path;

/// A float64 .npy file's data.
fn npy_data(path: &Path) -> Vec<f64> {
    let bytes = fs::read(path).unwrap();
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    bytes[10 + len..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// n points of a 3-D helix with uneven steps.
fn helix(n: usize) -> Vec<f64> {
    (0..n)
        .flat_map(|i| {
            let t = i as f64 * 0.01 + 0.004 * (i as f64 * 0.7).sin();
            [t.cos() * 3.0, t.sin() * 3.0, 0.2 * t]
        })
        .collect()
}

fn run(d: &Path, extra: &[&str], out: &str) -> (Vec<f64>, Vec<f64>) {
    let mut args = vec!["interpolate", "curve", "big.npy", "--control", "-o", out];
    args.extend_from_slice(extra);
    ok(d, &args);
    let knots = out.replace(".npy", ".knots.npy");
    (npy_data(&d.join(out)), npy_data(&d.join(knots)))
}

#[test]
fn streamed_tiles_of_every_degree_equal_the_whole_solve() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 30_000;
    let points = helix(n);
    fs::write(d.join("big.npy"), npy_bytes(&[n, 3], &points)).unwrap();
    let cases: &[&[&str]] = &[
        &["--degree", "1"],
        &["--degree", "2"],
        &["--degree", "2", "--param", "uniform"],
        &["--degree", "4", "--param", "centripetal"],
        &["--degree", "5"],
        &["--degree", "5", "--left", "1:0.5;2:0", "--right", "2:0;3:1"],
        &["--degree", "3", "--form", "scipy", "--end", "natural"],
        &["--degree", "3", "--form", "scipy", "--end", "clamped"],
        &[
            "--degree", "3", "--form", "scipy", "--left", "bessel", "--right", "1:0,1,0",
        ],
        &[
            "--degree",
            "7",
            "--left",
            "1:0;2:0;3:0",
            "--right",
            "1:0;2:0;3:0",
        ],
        &["--degree", "6"],
    ];
    for case in cases {
        let (g, gk) = run(d, case, "g.npy");
        let mut tiled = case.to_vec();
        tiled.extend(["--tile", "4000"]);
        let (s, sk) = run(d, &tiled, "s.npy");
        assert_eq!(gk, sk, "{case:?}: knots");
        assert_eq!(g.len(), s.len(), "{case:?}");
        let scale = g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let err = max_abs_diff(&g, &s);
        assert!(err <= 1e-12 * scale, "{case:?}: {err:e}");
        // In memory (a JSON model): the same tiles.
        ok(
            d,
            &[
                &["interpolate", "curve", "big.npy", "-o", "t.json"],
                &tiled[..],
            ]
            .concat(),
        );
        let t: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(d.join("t.json")).unwrap()).unwrap();
        let c: Vec<f64> = t["control_points"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect();
        assert_eq!(c, s, "{case:?}: in memory and streamed");
    }
}

#[test]
fn tiles_that_cannot_hold_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 2_000;
    fs::write(d.join("big.npy"), npy_bytes(&[n, 3], &helix(n))).unwrap();
    let base = [
        "interpolate",
        "curve",
        "big.npy",
        "--control",
        "-o",
        "x.npy",
    ];
    for (extra, phrase) in [
        (
            &["--degree", "2", "--tile", "500", "--left", "clamped"][..],
            "does not decay",
        ),
        (
            &["--degree", "5", "--tile", "1"][..],
            "--tile must be at least 2",
        ),
        (
            &["--degree", "5", "--tile", "500", "--end", "periodic"][..],
            "--tile takes open ends",
        ),
        (&["--degree", "0", "--tile", "500"][..], "degrees 1 to 7"),
        (
            &["--degree", "5", "--tile", "500", "--end", "natural"][..],
            "does not match",
        ),
    ] {
        let err = fails(d, &[&base[..], extra].concat(), Some("x.npy"));
        assert!(err.contains(phrase), "{extra:?}: {err}");
        assert!(!d.join("x.knots.npy").exists(), "{extra:?}");
    }
}
