//! `geomkit bezier ...`: degrees, tolerances, continuity, sample counts, and models that
//! are not Bézier curves or surfaces.

use crate::Case;

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";
const SURFACE: &str =
    "{\"type\": \"bezier_surface\", \"net\": [[[0,0,0],[1,0,1]],[[0,1,0],[1,1,1]]]}";
const RATIONAL: &str =
    "{\"type\": \"bezier_curve\", \"points\": [[1,0],[1,1],[0,1]], \"weights\": [1, 0, 1]}";
const NAN_POINT: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,NaN]]}";
const HUGE_POINT: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,1e999]]}";
const NO_POINTS: &str = "{\"type\": \"bezier_curve\", \"points\": []}";
const RAGGED: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2,3]]}";
const BSPLINE: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,1,1], \"control_points\": [[0,0],[1,1]]}";

pub const CASES: &[Case] = &[
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "degree", "c.json", "--tolerance", "-1"],
        names: &["tolerance", "-1"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "degree", "c.json", "--tolerance", "nan"],
        names: &["tolerance", "nan"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "degree", "c.json", "--tolerance", "inf"],
        names: &["tolerance", "inf"],
    },
    Case {
        files: &[("c.json", NAN_POINT)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json"],
    },
    Case {
        files: &[("c.json", HUGE_POINT)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json"],
    },
    Case {
        files: &[("c.json", NO_POINTS)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json", "points"],
    },
    Case {
        files: &[("c.json", RAGGED)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json", "points[1]"],
    },
    Case {
        files: &[("c.json", BSPLINE)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json", "B-spline"],
    },
    Case {
        files: &[("c.json", RATIONAL)],
        args: &["bezier", "degree", "c.json"],
        names: &["c.json", "weight"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "elevate", "c.json", "--to", "2", "-o", "e.json"],
        names: &["c.json", "2"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "1000000000",
            "-o",
            "e.json",
        ],
        names: &["--to", "1000000000"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "elevate", "c.json", "--to", "-3", "-o", "e.json"],
        names: &["-3"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "elevate", "c.json", "--to", "5,5", "-o", "e.json"],
        names: &["--to"],
    },
    Case {
        files: &[("s.json", SURFACE)],
        args: &["bezier", "elevate", "s.json", "--to", "5", "-o", "e.json"],
        names: &["--to"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "elevate", "c.json", "--to", "5", "-o", "e.txt"],
        names: &["e.txt"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "5",
            "-o",
            "missing/e.json",
        ],
        names: &["missing"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "reduce", "c.json", "--to", "1", "-o", "r.json"],
        names: &["c.json", "real degree", "--approx"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "reduce", "c.json", "--to", "5", "-o", "r.json"],
        names: &["c.json", "5"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "reduce",
            "c.json",
            "--to",
            "2",
            "--approx",
            "--continuity",
            "1,1",
            "-o",
            "r.json",
        ],
        names: &["continuity"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "reduce",
            "c.json",
            "--to",
            "2",
            "--approx",
            "--continuity",
            "x",
            "-o",
            "r.json",
        ],
        names: &["--continuity", "x"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "reduce",
            "c.json",
            "--to",
            "2",
            "--continuity",
            "0,0",
            "-o",
            "r.json",
        ],
        names: &["--approx"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier", "reduce", "c.json", "--to", "2", "--approx", "--norm", "max", "-o", "r.json",
        ],
        names: &["--norm", "max"],
    },
    Case {
        files: &[("s.json", SURFACE)],
        args: &[
            "bezier", "reduce", "s.json", "--to", "0,0", "--approx", "-o", "r.json",
        ],
        names: &["s.json", "surface"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &[
            "bezier",
            "change",
            "c.json",
            "--to",
            "1",
            "--tolerance",
            "-0.5",
            "-o",
            "r.json",
        ],
        names: &["tolerance"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "eval", "c.json", "--samples", "1"],
        names: &["--samples", "1"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "eval", "c.json", "--samples", "0"],
        names: &["--samples"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "eval", "c.json", "--samples", "100000000000"],
        names: &["--samples"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["bezier", "eval", "c.json", "--samples", "1e3"],
        names: &["--samples", "1e3"],
    },
];

#[test]
fn bezier() {
    crate::check_all(CASES);
}
