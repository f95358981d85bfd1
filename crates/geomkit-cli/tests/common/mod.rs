//! The CLI tests' shared harness: run the geomkit binary in a folder, expect success or a
//! one-line error that leaves no file behind, write input files, compare numbers.
#![allow(dead_code)]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

// One `max_abs_diff` for the whole workspace: the library's tests' copy, included.
#[path = "../../../geomkit/tests/common/numbers.rs"]
mod numbers;
#[allow(unused_imports)]
pub use numbers::max_abs_diff;

/// Runs `geomkit ARGS` in `dir`.
pub fn geomkit(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geomkit"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the geomkit binary runs")
}

/// Writes `text` to `dir/name`; returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    fs::write(&path, text).unwrap();
    path
}

/// Output bytes as text (they must be UTF-8).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).expect("UTF-8 output")
}

/// A run's standard output.
pub fn stdout(out: &Output) -> String {
    text(&out.stdout)
}

/// A run's standard error.
pub fn stderr(out: &Output) -> String {
    text(&out.stderr)
}

/// Runs `geomkit ARGS` in `dir` and asserts success (showing its stderr otherwise).
pub fn run_ok(dir: &Path, args: &[&str]) -> Output {
    let out = geomkit(dir, args);
    assert!(
        out.status.success(),
        "geomkit {args:?} failed: {}",
        stderr(&out)
    );
    out
}

/// Runs a successful command; returns its standard output.
pub fn ok(dir: &Path, args: &[&str]) -> String {
    stdout(&run_ok(dir, args))
}

/// Runs a successful command; returns its standard error (where the commands that write
/// files report what they wrote).
pub fn ok_stderr(dir: &Path, args: &[&str]) -> String {
    stderr(&run_ok(dir, args))
}

/// Runs a failing command and returns its one error line (without the newline): exit code 1,
/// one line starting with `error: ` on stderr, nothing on stdout, no file `output` (the
/// command's `-o`) and no other file left in `dir`.
pub fn fails(dir: &Path, args: &[&str], output: Option<&str>) -> String {
    let before = fs::read_dir(dir).unwrap().count();
    let out = geomkit(dir, args);
    assert_eq!(
        out.status.code(),
        Some(1),
        "geomkit {args:?}: {}",
        stderr(&out)
    );
    let err = stderr(&out);
    assert_eq!(err.lines().count(), 1, "not one line: {err:?}");
    assert!(err.starts_with("error: "), "{err:?}");
    assert_eq!(stdout(&out), "", "stdout of a failing {args:?}");
    if let Some(o) = output {
        assert!(!dir.join(o).exists(), "{o} was created by {args:?}");
    }
    assert_eq!(
        fs::read_dir(dir).unwrap().count(),
        before,
        "files left by {args:?}"
    );
    err.trim_end().to_string()
}

/// A float64 C-order .npy file, written by hand.
pub fn npy_bytes(shape: &[usize], data: &[f64]) -> Vec<u8> {
    let shape_text = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape_text}, }}");
    while (10 + dict.len() + 1) % 64 != 0 {
        dict.push(' ');
    }
    dict.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    for x in data {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out
}
