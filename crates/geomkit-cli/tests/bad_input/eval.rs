//! `geomkit eval` and `geomkit render`: models that cannot be evaluated or drawn, parameter
//! files, sample counts, picture options.

use crate::{case, Case};

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";
const WIDE_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 2, \"knots\": [-1.7e308,-1.7e308,-1.7e308,0,1.7e308,1.7e308,1.7e308], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const DECREASING_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,2,1,3,3], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const FEW_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 3, \"knots\": [0,0,1,1], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const NAN_KNOT: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,NaN,1], \"control_points\": [[0,0],[1,1]]}";
const NEWER: &str = "{\"type\": \"bezier_curve\", \"version\": 99, \"points\": [[0,0],[1,1]]}";
const UNKNOWN_FIELD: &str =
    "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,1]], \"colour\": 3}";

const LINE: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,1,2,2], \"control_points\": [[0,0],[1,1],[2,0]]}";

pub const CASES: &[Case] = &[
    // --nu and --extrapolate (issue 22).
    case(
        &[("c.json", CUBIC)],
        &["eval", "c.json", "--samples", "5", "--nu", "1"],
        &["c.json", "--nu", "B-spline curves"],
    ),
    case(
        &[("b.json", LINE), ("t.csv", "0.5\n3\n")],
        &["eval", "b.json", "--at", "t.csv", "--nu", "1"],
        &["t.csv", "t = 3", "outside the domain"],
    ),
    case(
        &[("b.json", LINE)],
        &[
            "eval",
            "b.json",
            "--samples",
            "5",
            "--extrapolate",
            "sideways",
        ],
        &["--extrapolate", "sideways"],
    ),
    case(
        &[("b.json", WIDE_KNOTS)],
        &["eval", "b.json", "--samples", "5"],
        &["b.json", "knot", "span"],
    ),
    case(
        &[("b.json", WIDE_KNOTS)],
        &["eval", "b.json", "--samples", "5", "-o", "o.csv"],
        &["b.json", "knot"],
    ),
    case(
        &[("b.json", WIDE_KNOTS)],
        &["render", "b.json", "-o", "r.svg"],
        &["b.json", "knot"],
    ),
    case(
        &[("b.json", WIDE_KNOTS)],
        &["mesh", "b.json", "-o", "m.obj"],
        &["b.json", "knot"],
    ),
    case(
        &[("b.json", DECREASING_KNOTS)],
        &["eval", "b.json", "--samples", "5"],
        &["b.json", "non-decreasing"],
    ),
    case(
        &[("b.json", FEW_KNOTS)],
        &["eval", "b.json", "--samples", "5"],
        &["b.json", "knots"],
    ),
    case(
        &[("b.json", NAN_KNOT)],
        &["eval", "b.json", "--samples", "5"],
        &["b.json", "line 1 column 54"],
    ),
    case(
        &[("c.json", NEWER)],
        &["eval", "c.json", "--samples", "5"],
        &["c.json", "version"],
    ),
    case(
        &[("c.json", UNKNOWN_FIELD)],
        &["eval", "c.json", "--samples", "5"],
        &["c.json", "colour"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["eval", "c.json", "--samples", "5x5"],
        &["--samples"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["eval", "c.json", "--samples", "1000000000000"],
        &["--samples"],
    ),
    case(
        &[("c.json", CUBIC), ("t.csv", "t\n0.5\nnan\n")],
        &["eval", "c.json", "--at", "t.csv"],
        &["t.csv"],
    ),
    case(
        &[("c.json", CUBIC), ("t.csv", "u,v\n0.5,0.5\n")],
        &["eval", "c.json", "--at", "t.csv"],
        &["t.csv"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["eval", "c.json", "--at", "missing.csv"],
        &["missing.csv"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["eval", "c.json", "--samples", "5", "-o", "o.txt"],
        &["o.txt"],
    ),
    case(
        &[("p.csv", "x,y\n0,0\n1,1\n")],
        &["eval", "p.csv", "--samples", "5"],
        &["p.csv", "knots"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["render", "c.json", "-o", "r.jpg"],
        &["r.jpg"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["render", "c.json", "-o", "r.svg", "--size", "0x100"],
        &["--size"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["render", "c.json", "-o", "r.png", "--size", "100000x100000"],
        &["--size"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["render", "c.json", "-o", "r.svg", "--view", "nan,10"],
        &["--view"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["render", "c.json", "-o", "r.svg", "--view", "10"],
        &["--view"],
    ),
    case(
        &[("c.json", "")],
        &["render", "c.json", "-o", "r.svg"],
        &["c.json"],
    ),
    case(
        &[("c.json", "\u{feff}{}")],
        &["render", "c.json", "-o", "r.svg"],
        &["c.json"],
    ),
];

#[test]
fn eval_and_render() {
    crate::check_all(CASES);
}
