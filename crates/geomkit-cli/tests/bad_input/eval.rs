//! `geomkit eval` and `geomkit render`: models that cannot be evaluated or drawn, parameter
//! files, sample counts, picture options.

use crate::Case;

const CUBIC: &str = "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,2],[2,2],[3,0]]}";
const WIDE_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 2, \"knots\": [-1.7e308,-1.7e308,-1.7e308,0,1.7e308,1.7e308,1.7e308], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const DECREASING_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,2,1,3,3], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const FEW_KNOTS: &str = "{\"type\": \"bspline_curve\", \"degree\": 3, \"knots\": [0,0,1,1], \"control_points\": [[0,0],[1,1],[2,0],[3,1]]}";
const NAN_KNOT: &str = "{\"type\": \"bspline_curve\", \"degree\": 1, \"knots\": [0,0,NaN,1], \"control_points\": [[0,0],[1,1]]}";
const NEWER: &str = "{\"type\": \"bezier_curve\", \"version\": 99, \"points\": [[0,0],[1,1]]}";
const UNKNOWN_FIELD: &str =
    "{\"type\": \"bezier_curve\", \"points\": [[0,0],[1,1]], \"colour\": 3}";

pub const CASES: &[Case] = &[
    Case {
        files: &[("b.json", WIDE_KNOTS)],
        args: &["eval", "b.json", "--samples", "5"],
        names: &["b.json", "knot", "span"],
    },
    Case {
        files: &[("b.json", WIDE_KNOTS)],
        args: &["eval", "b.json", "--samples", "5", "-o", "o.csv"],
        names: &["b.json", "knot"],
    },
    Case {
        files: &[("b.json", WIDE_KNOTS)],
        args: &["render", "b.json", "-o", "r.svg"],
        names: &["b.json", "knot"],
    },
    Case {
        files: &[("b.json", WIDE_KNOTS)],
        args: &["mesh", "b.json", "-o", "m.obj"],
        names: &["b.json", "knot"],
    },
    Case {
        files: &[("b.json", DECREASING_KNOTS)],
        args: &["eval", "b.json", "--samples", "5"],
        names: &["b.json", "non-decreasing"],
    },
    Case {
        files: &[("b.json", FEW_KNOTS)],
        args: &["eval", "b.json", "--samples", "5"],
        names: &["b.json", "knots"],
    },
    Case {
        files: &[("b.json", NAN_KNOT)],
        args: &["eval", "b.json", "--samples", "5"],
        names: &["b.json", "line 1 column 54"],
    },
    Case {
        files: &[("c.json", NEWER)],
        args: &["eval", "c.json", "--samples", "5"],
        names: &["c.json", "version"],
    },
    Case {
        files: &[("c.json", UNKNOWN_FIELD)],
        args: &["eval", "c.json", "--samples", "5"],
        names: &["c.json", "colour"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["eval", "c.json", "--samples", "5x5"],
        names: &["--samples"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["eval", "c.json", "--samples", "1000000000000"],
        names: &["--samples"],
    },
    Case {
        files: &[("c.json", CUBIC), ("t.csv", "t\n0.5\nnan\n")],
        args: &["eval", "c.json", "--at", "t.csv"],
        names: &["t.csv"],
    },
    Case {
        files: &[("c.json", CUBIC), ("t.csv", "u,v\n0.5,0.5\n")],
        args: &["eval", "c.json", "--at", "t.csv"],
        names: &["t.csv"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["eval", "c.json", "--at", "missing.csv"],
        names: &["missing.csv"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["eval", "c.json", "--samples", "5", "-o", "o.txt"],
        names: &["o.txt"],
    },
    Case {
        files: &[("p.csv", "x,y\n0,0\n1,1\n")],
        args: &["eval", "p.csv", "--samples", "5"],
        names: &["p.csv", "knots"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["render", "c.json", "-o", "r.jpg"],
        names: &["r.jpg"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["render", "c.json", "-o", "r.svg", "--size", "0x100"],
        names: &["--size"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["render", "c.json", "-o", "r.png", "--size", "100000x100000"],
        names: &["--size"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["render", "c.json", "-o", "r.svg", "--view", "nan,10"],
        names: &["--view"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["render", "c.json", "-o", "r.svg", "--view", "10"],
        names: &["--view"],
    },
    Case {
        files: &[("c.json", "")],
        args: &["render", "c.json", "-o", "r.svg"],
        names: &["c.json"],
    },
    Case {
        files: &[("c.json", "\u{feff}{}")],
        args: &["render", "c.json", "-o", "r.svg"],
        names: &["c.json"],
    },
];

#[test]
fn eval_and_render() {
    crate::check_all(CASES);
}
