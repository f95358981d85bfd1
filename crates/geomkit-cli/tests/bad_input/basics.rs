//! Bad input common to every command: missing, malformed and wrong-typed files, unknown
//! options, unwritable outputs.

use crate::Case;

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";

pub const CASES: &[Case] = &[
    Case {
        files: &[],
        args: &["bezier", "degree", "missing.json"],
        names: &["missing.json"],
    },
    Case {
        files: &[("c.json", "{\"points\": [[0,0],[1,2],[2,2],[3,0]]")],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json", "line 1"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "five",
            "-o",
            "keep.json",
        ],
        names: &["--to", "five"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "2",
            "-o",
            "keep.json",
        ],
        names: &["2"],
    },
];

#[test]
fn basics() {
    crate::check_all(CASES);
}
