//! Bad input common to every command: missing, malformed and wrong-typed files, unknown
//! options, unwritable outputs.

use crate::{case, Case};

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";

pub const CASES: &[Case] = &[
    case(
        &[],
        &["bezier", "degree", "missing.json"],
        &["missing.json"],
    ),
    case(
        &[("c.json", "{\"points\": [[0,0],[1,2],[2,2],[3,0]]")],
        &["bezier", "degree", "c.json"],
        &["c.json", "line 1"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "five",
            "-o",
            "keep.json",
        ],
        &["--to", "five"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "2",
            "-o",
            "keep.json",
        ],
        &["2"],
    ),
];

#[test]
fn basics() {
    crate::check_all(CASES);
}
