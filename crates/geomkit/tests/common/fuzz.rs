//! The fuzz tests' shared settings (issue 21). Every fuzz test is a proptest named `fuzz_*`
//! whose property is "no panic, and the result is an error or finite": `cargo test` runs a
//! few cases each; `.ci/fuzz` runs many more (`PROPTEST_CASES`). Failures shrink to a
//! minimal case saved in the file's `.proptest-regressions` (committed: the corpus, replayed
//! first on every run).
#![allow(dead_code)]

use proptest::test_runner::Config;

/// `PROPTEST_CASES` when set, else `default` (a count that keeps `cargo test` fast).
pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The configuration of a fuzz test: `cases(default)` cases, failures saved beside the file.
pub fn config(default: u32) -> Config {
    Config {
        cases: cases(default),
        ..Config::default()
    }
}
