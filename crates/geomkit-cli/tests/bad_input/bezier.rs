//! `geomkit bezier ...`: degrees, tolerances, continuity, sample counts, and models that
//! are not Bézier curves or surfaces.

use crate::{case, Case};

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";
const SURFACE: &str =
    "{\"type\": \"bezier_surface\", \"net\": [[[0,0,0],[1,0,1]],[[0,1,0],[1,1,1]]]}";
const RATIONAL: &str =
    "{\"type\": \"bezier_curve\", \"points\": [[1,0],[1,1],[0,1]], \"weights\": [1, 0, 1]}";
const RATIONAL_SURFACE: &str = "{\"type\": \"bezier_surface\", \"net\": [[[1,0,0],[1,0,2]],[[1,1,0],[1,1,2]],[[0,1,0],[0,1,2]]], \"weights\": [[1,1],[0.7,0.7],[1,1]]}";
const BAD_SURFACE_WEIGHT: &str =
    "{\"type\": \"bezier_surface\", \"net\": [[[0],[1]],[[2],[3]]], \"weights\": [[1,1],[1,-2]]}";
const NAN_POINT: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,NaN]]}";
const HUGE_POINT: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,1e999]]}";
const NO_POINTS: &str = "{\"type\": \"bezier_curve\", \"points\": []}";
const RAGGED: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2,3]]}";
const BSPLINE: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,1,1], \"control_points\": [[0,0],[1,1]]}";

pub const CASES: &[Case] = &[
    case(
        &[("c.json", CUBIC)],
        &["bezier", "degree", "c.json", "--tolerance", "-1"],
        &["tolerance", "-1"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "degree", "c.json", "--tolerance", "nan"],
        &["tolerance", "nan"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "degree", "c.json", "--tolerance", "inf"],
        &["tolerance", "inf"],
    ),
    case(
        &[("c.json", NAN_POINT)],
        &["bezier", "degree", "c.json"],
        &["c.json"],
    ),
    case(
        &[("c.json", HUGE_POINT)],
        &["bezier", "degree", "c.json"],
        &["c.json"],
    ),
    case(
        &[("c.json", NO_POINTS)],
        &["bezier", "degree", "c.json"],
        &["c.json", "points"],
    ),
    case(
        &[("c.json", RAGGED)],
        &["bezier", "degree", "c.json"],
        &["c.json", "points[1]"],
    ),
    case(
        &[("c.json", BSPLINE)],
        &["bezier", "degree", "c.json"],
        &["c.json", "B-spline"],
    ),
    case(
        &[("c.json", RATIONAL)],
        &["bezier", "degree", "c.json"],
        &["c.json", "weight"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "elevate", "c.json", "--to", "2", "-o", "e.json"],
        &["c.json", "2"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "1000000000",
            "-o",
            "e.json",
        ],
        &["--to", "1000000000"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "elevate", "c.json", "--to", "-3", "-o", "e.json"],
        &["-3"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "elevate", "c.json", "--to", "5,5", "-o", "e.json"],
        &["--to"],
    ),
    case(
        &[("s.json", SURFACE)],
        &["bezier", "elevate", "s.json", "--to", "5", "-o", "e.json"],
        &["--to"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "elevate", "c.json", "--to", "5", "-o", "e.txt"],
        &["e.txt"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
            "bezier",
            "elevate",
            "c.json",
            "--to",
            "5",
            "-o",
            "missing/e.json",
        ],
        &["missing"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "reduce", "c.json", "--to", "1", "-o", "r.json"],
        &["c.json", "real degree", "--approx"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "reduce", "c.json", "--to", "5", "-o", "r.json"],
        &["c.json", "5"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
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
        &["continuity"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
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
        &["--continuity", "x"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
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
        &["--approx"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
            "bezier", "reduce", "c.json", "--to", "2", "--approx", "--norm", "max", "-o", "r.json",
        ],
        &["--norm", "max"],
    ),
    case(
        &[("s.json", SURFACE)],
        &[
            "bezier", "reduce", "s.json", "--to", "0,0", "--approx", "-o", "r.json",
        ],
        &["s.json", "surface"],
    ),
    case(
        &[("c.json", CUBIC)],
        &[
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
        &["tolerance"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "eval", "c.json", "--samples", "1"],
        &["--samples", "1"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "eval", "c.json", "--samples", "0"],
        &["--samples"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "eval", "c.json", "--samples", "100000000000"],
        &["--samples"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["bezier", "eval", "c.json", "--samples", "1e3"],
        &["--samples", "1e3"],
    ),
    case(
        &[("s.json", BAD_SURFACE_WEIGHT)],
        &["bezier", "degree", "s.json"],
        &["s.json", "weight (1, 1)", "-2"],
    ),
    case(
        &[("s.json", RATIONAL_SURFACE)],
        &[
            "bezier", "reduce", "--to", "1,1", "s.json", "-o", "out.json",
        ],
        &["s.json", "degree 1 in u", "real u-degree is 2"],
    ),
    case(
        &[("s.json", RATIONAL_SURFACE)],
        &[
            "bezier", "reduce", "--to", "2,1", "--approx", "s.json", "-o", "out.json",
        ],
        &["s.json", "approximate reduction", "curves only"],
    ),
    case(
        &[("s.json", RATIONAL_SURFACE)],
        &["bezier", "elevate", "--to", "3", "s.json", "-o", "out.json"],
        &["--to N,M", "--to 3"],
    ),
];

#[test]
fn bezier() {
    crate::check_all(CASES);
}
