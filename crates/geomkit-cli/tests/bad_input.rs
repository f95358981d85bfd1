//! The bad-input catalogue (issue 21): commands over every part of the CLI with input that
//! must be refused. Each case runs in a fresh folder holding its input files and a file the
//! run must not touch, under a memory and CPU-time limit, and must exit with code 1 (an
//! error) or 2 (a usage error) and exactly one line `error: ...` on stderr naming what is
//! wrong (the words the case lists: the option, the file, the value), nothing on stdout,
//! and every file of the folder as it was (no output, not even a partial one).
//!
//! Cases live in one table per area (`bad_input/*.rs`); each area is one test that runs all
//! its cases and reports every failure at once.

mod common;

mod bad_input {
    pub mod basics;
    pub mod bezier;
    pub mod compose;
    pub mod eval;
    pub mod expr;
    pub mod interpolate;
    pub mod mesh;
    pub mod pointcalc;
}

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// One bad input: files to write (name, contents), the command's arguments, and the words
/// its error line must contain (option names, file names, values).
pub struct Case {
    /// Files written into the case's folder first: (name, contents).
    pub files: &'static [(&'static str, &'static str)],
    /// The arguments after `geomkit`.
    pub args: &'static [&'static str],
    /// Words the error line must contain (case-insensitive).
    pub names: &'static [&'static str],
}

/// A case on one line: files, arguments, words of the error.
pub const fn case(
    files: &'static [(&'static str, &'static str)],
    args: &'static [&'static str],
    names: &'static [&'static str],
) -> Case {
    Case { files, args, names }
}

/// Address space and CPU time a refusal may use: a command that starts a huge allocation or
/// a long computation before refusing fails the case (killed, or aborted by the allocator).
const MEMORY_LIMIT_BYTES: u64 = 3 << 30;
const CPU_SECONDS: u64 = 20;

/// A file every case's folder holds that no command may change.
const KEEP: (&str, &str) = ("keep.json", "{\"precious\": true}\n");

/// Every file of `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                fs::read(e.path()).unwrap_or_default(),
            )
        })
        .collect()
}

/// Runs one case; `Err` says how it fell short.
fn run(case: &Case) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in case.files.iter().chain([&KEEP]) {
        fs::write(dir.path().join(name), text).unwrap();
    }
    let before = snapshot(dir.path());
    let start = Instant::now();
    let out = Command::new("prlimit")
        .arg(format!("--as={MEMORY_LIMIT_BYTES}"))
        .arg(format!("--cpu={CPU_SECONDS}"))
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_geomkit"))
        .args(case.args)
        .current_dir(dir.path())
        .output()
        .expect("prlimit runs the geomkit binary");
    let took = start.elapsed();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    let mut faults = Vec::new();
    match out.status.code() {
        Some(1 | 2) => {}
        code => faults.push(format!("exit {code:?} (a signal when None)")),
    }
    if err.lines().count() != 1 || !err.starts_with("error: ") {
        faults.push("stderr is not one line `error: ...`".to_string());
    }
    let lower = err.to_lowercase();
    for name in case.names {
        if !lower.contains(&name.to_lowercase()) {
            faults.push(format!("the error does not name {name:?}"));
        }
    }
    if !out.stdout.is_empty() {
        faults.push(format!(
            "stdout not empty: {:?}",
            String::from_utf8_lossy(&out.stdout)
        ));
    }
    if snapshot(dir.path()) != before {
        faults.push("the folder changed".to_string());
    }
    if took > Duration::from_secs(CPU_SECONDS) {
        faults.push(format!("took {took:?}"));
    }
    if faults.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "geomkit {}: {}\n    stderr: {}",
            case.args.join(" "),
            faults.join("; "),
            err.trim_end()
        ))
    }
}

/// Runs every case of a table; panics listing all that fell short.
pub fn check_all(cases: &[Case]) {
    let failures: Vec<String> = cases.iter().filter_map(|c| run(c).err()).collect();
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs mishandled:\n  {}",
        failures.len(),
        cases.len(),
        failures.join("\n  ")
    );
}

/// The number of cases in all tables (the issue asks for at least 100).
#[test]
fn the_catalogue_covers_every_command() {
    let total: usize = [
        bad_input::basics::CASES.len(),
        bad_input::bezier::CASES.len(),
        bad_input::compose::CASES.len(),
        bad_input::eval::CASES.len(),
        bad_input::expr::CASES.len(),
        bad_input::interpolate::CASES.len(),
        bad_input::mesh::CASES.len(),
        bad_input::pointcalc::CASES.len(),
    ]
    .iter()
    .sum();
    assert!(total >= 100, "{total} cases");
}
