//! Bad input of `geomkit pointcalc`: every subcommand (fit, eval, shares, optimize, formula,
//! curve, surface) and every option that takes a number, a count or a file.

use crate::Case;

/// A 3×3 grid of experiments, y = a + 2b + ab.
const EXPERIMENTS: &str = "a,b,y\n0,0,0\n0,1,2\n0,2,4\n1,0,1\n1,1,4\n1,2,7\n2,0,2\n2,1,6\n2,2,10\n";
/// The model of [`EXPERIMENTS`].
const MODEL: &str = r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1,2]},{"name":"b","nodes":[0,1,2]}],"response":["y"],"values":[0,2,4,1,4,7,2,6,10]}"#;
/// Two responses.
const VECTOR_MODEL: &str = r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1]}],"response":["y","z"],"values":[1,2,3,4]}"#;
/// Values whose interpolant overshoots f64 between the levels (1.25 · 1.7e308 at a = 1/4).
const HUGE_MODEL: &str = r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1]}],"response":["y"],"values":[1.7e308,1.7e308,-1.7e308]}"#;
/// Levels 1e-170 apart: the formula's coefficients 1 / Π (t_j - t_k) are beyond f64.
const CLOSE_MODEL: &str = r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1e-170,2e-170]}],"response":["y"],"values":[1,2,3]}"#;
/// A curve's source points near f64::MAX (it overshoots between them).
const HUGE_POINTS: &str = "[[1.7e308],[1.7e308],[-1.7e308]]";
/// A 3×3 net in R^3.
const NET: &str = "[[[0,0,0],[1,0,1],[2,0,0]],[[0,1,1],[1,1,2],[2,1,1]],[[0,2,0],[1,2,1],[2,2,0]]]";
const CUBIC: &str = r#"{"type": "bezier_curve", "points": [[0,0],[1,2],[2,2],[3,0]]}"#;

/// `pointcalc fit` of [`EXPERIMENTS`] with `--nodes SPEC`, whose error names `names`.
macro_rules! fit_nodes {
    ($spec:literal, $names:expr) => {
        Case {
            files: &[("e.csv", EXPERIMENTS)],
            args: &[
                "pointcalc",
                "fit",
                "e.csv",
                "--factors",
                "a,b",
                "--response",
                "y",
                "--nodes",
                $spec,
            ],
            names: $names,
        }
    };
}

pub const CASES: &[Case] = &[
    // fit: the experiments' table.
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,NaN\n1,0,3\n1,1,4\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "line 3", "'y'", "NaN"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,2\ninf,0,3\n1,1,4\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "line 4", "'a'", "inf"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,\n1,0,3\n1,1,4\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "line 3", "'y'", "not a finite number"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,2\n0,1,2\n1,0,3\n1,1,4\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "line 4", "duplicate", "line 3"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,2,5\n1,0,3\n1,1,4\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "line 3", "4 cells", "header has 3"],
    },
    Case {
        files: &[("e.csv", "")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "empty"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "no data lines"],
    },
    Case {
        files: &[("e.csv", "a,b,y\n0,0,1\n0,1,2\n1,0,3\n")],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "y"],
        names: &["e.csv", "a=1, b=1", "1 cells missing"],
    },
    // 1000 experiments whose levels are all distinct: a grid of 10^9 cells (refused by
    // sorting the records, not by allocating the grid).
    Case {
        files: &[("e.csv", include_str!("pointcalc_sparse.csv"))],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b,c", "--response", "y"],
        names: &["e.csv", "do not form a grid", "999999000 cells missing"],
    },
    Case {
        files: &[("e.csv", EXPERIMENTS)],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "a"],
        names: &["'a'", "named twice"],
    },
    Case {
        files: &[("e.csv", EXPERIMENTS)],
        args: &["pointcalc", "fit", "e.csv", "--factors", "a,b", "--response", "q"],
        names: &["e.csv", "no column 'q'"],
    },
    // fit --nodes: counts, non-finite and unparsable values, spans beyond f64.
    fit_nodes!("a=cheb1:100000000", &["--nodes", "100000000", "at most 5000"]),
    fit_nodes!("a=cheb1:-3", &["--nodes", "'-3'", "node count"]),
    fit_nodes!("a=0,1/0,2", &["--nodes", "'1/0'"]),
    fit_nodes!("a=equi:3:0:NaN", &["--nodes", "'NaN'", "finite"]),
    fit_nodes!("a=cheb2:3:-1e308:1e308", &["--nodes", "overflow"]),
    fit_nodes!("a=equi:1200", &["--nodes", "weights", "span more than the f64 range"]),
    // eval: far outside the levels, non-finite and missing columns, wrong model files.
    Case {
        files: &[("m.json", MODEL), ("at.csv", "a,b\n1,1\n1e308,0\n")],
        args: &["pointcalc", "eval", "m.json", "at.csv", "-o", "out.csv"],
        names: &["at.csv", "line 3", "a=1e308"],
    },
    Case {
        files: &[("m.json", HUGE_MODEL), ("at.csv", "a\n0.5\n0.25\n")],
        args: &["pointcalc", "eval", "m.json", "at.csv", "-o", "out.csv"],
        names: &["at.csv", "line 3", "a=0.25", "overflows"],
    },
    Case {
        files: &[("m.json", MODEL), ("at.csv", "a,b\n1,NaN\n")],
        args: &["pointcalc", "eval", "m.json", "at.csv"],
        names: &["at.csv", "line 2", "'b'", "NaN"],
    },
    Case {
        files: &[("m.json", MODEL), ("at.csv", "a\n1\n")],
        args: &["pointcalc", "eval", "m.json", "at.csv"],
        names: &["at.csv", "no column 'b'"],
    },
    Case {
        files: &[("m.json", CUBIC), ("at.csv", "a,b\n1,1\n")],
        args: &["pointcalc", "eval", "m.json", "at.csv"],
        names: &["m.json", "pointcalc-model"],
    },
    // shares --at.
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "shares", "m.json", "--at", "a=1e308,b=0"],
        names: &["--at", "share of point 0", "a=1e308", "overflows"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "shares", "m.json", "--at", "a=nan,b=0"],
        names: &["--at", "'nan'", "finite"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "shares", "m.json", "--at", "a=1"],
        names: &["--at", "'b'"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "shares", "m.json", "--at", "a=1,c=2,b=0"],
        names: &["unknown factor 'c'"],
    },
    // optimize: responses, --tolerance, values beyond f64, broken model files.
    Case {
        files: &[("m.json", VECTOR_MODEL)],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "2 responses", "--response"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "optimize", "m.json", "--min", "--tolerance", "-1"],
        names: &["--tolerance", "-1"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "optimize", "m.json", "--min", "--tolerance", "NaN"],
        names: &["--tolerance", "NaN"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "optimize", "m.json", "--min", "--tolerance", "tiny"],
        names: &["--tolerance", "tiny"],
    },
    Case {
        files: &[("m.json", HUGE_MODEL)],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "largest", "overflows"],
    },
    Case {
        files: &[(
            "m.json",
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1],"exact":["0","1/0","1"]}],"response":["y"],"values":[1,2,3]}"#,
        )],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "factors[0].exact[1]", "1/0"],
    },
    Case {
        files: &[(
            "m.json",
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1/0,1]}],"response":["y"],"values":[1,2,3]}"#,
        )],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "1/0", "line 1"],
    },
    Case {
        files: &[(
            "m.json",
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1e999,2]}],"response":["y"],"values":[1,2,3]}"#,
        )],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "1e999", "finite"],
    },
    Case {
        files: &[(
            "m.json",
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1],"exact":["0","1/3","1"]}],"response":["y"],"values":[1,2,3]}"#,
        )],
        args: &["pointcalc", "optimize", "m.json", "--max"],
        names: &["m.json", "factors[0].exact[1]", "1/3", "0.5"],
    },
    Case {
        files: &[(
            "m.json",
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1]}],"response":[],"values":[]}"#,
        )],
        args: &["pointcalc", "optimize", "m.json", "--min"],
        names: &["m.json", "\"response\" is empty"],
    },
    // formula: coefficients beyond f64, counts, formats.
    Case {
        files: &[("m.json", HUGE_MODEL)],
        args: &["pointcalc", "formula", "m.json", "--format", "c"],
        names: &["m.json", "source point a=0", "overflows"],
    },
    Case {
        files: &[("m.json", CLOSE_MODEL)],
        args: &["pointcalc", "formula", "m.json", "--format", "numpy"],
        names: &["m.json", "node 0", "factor a", "overflows"],
    },
    Case {
        files: &[("p.json", "[[0],[1],[0]]")],
        args: &[
            "pointcalc",
            "formula",
            "p.json",
            "--format",
            "maple",
            "--nodes",
            "cheb1:100000000",
        ],
        names: &["--nodes", "at most 5000"],
    },
    Case {
        files: &[("m.json", MODEL)],
        args: &["pointcalc", "formula", "m.json", "--format", "fortran"],
        names: &["--format", "fortran"],
    },
    // curve: --samples, --nodes, points beyond f64.
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0]]")],
        args: &["pointcalc", "curve", "p.json", "--samples", "0"],
        names: &["--samples", "0"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0]]")],
        args: &["pointcalc", "curve", "p.json", "--samples", "99999999999"],
        names: &["--samples", "99999999999"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0]]")],
        args: &["pointcalc", "curve", "p.json", "--samples", "-5"],
        names: &["--samples", "-5"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0]]")],
        args: &["pointcalc", "curve", "p.json", "--nodes", "cheb2:100000000"],
        names: &["--nodes", "100000000", "at most 5000"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0],[3,3]]")],
        args: &["pointcalc", "curve", "p.json", "--nodes", "half"],
        names: &["--nodes", "3 nodes for 4 points"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,2],[2,0]]")],
        args: &["pointcalc", "curve", "p.json", "--nodes", "0,0.5,inf"],
        names: &["--nodes", "not a finite number"],
    },
    Case {
        files: &[("p.json", HUGE_POINTS)],
        args: &["pointcalc", "curve", "p.json", "-o", "c.json"],
        names: &["p.json", "the point of the curve at t=", "overflows"],
    },
    Case {
        files: &[("p.json", "[[1.7e308,0],[-1.7e308,1],[1.7e308,0]]")],
        args: &["pointcalc", "curve", "p.json", "-o", "c.svg"],
        names: &["p.json", "1.7e308", "SVG"],
    },
    Case {
        files: &[("p.json", "[]")],
        args: &["pointcalc", "curve", "p.json"],
        names: &["p.json", "empty"],
    },
    Case {
        files: &[("p.json", "[[0,0],[1,NaN],[2,0]]")],
        args: &["pointcalc", "curve", "p.json"],
        names: &["p.json", "line 1"],
    },
    // surface: --samples, --nodes, --row-nodes, --across, --printed, points beyond f64.
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--samples", "5000"],
        names: &["--samples", "5000", "1000"],
    },
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--samples", "1"],
        names: &["--samples", "1"],
    },
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--row-nodes", "half"],
        names: &["--row-nodes", "1 node sets for 3 rows"],
    },
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--row-nodes", "half;half;cheb1:99999999"],
        names: &["--row-nodes", "row 2", "at most 5000"],
    },
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--across", "cheb1:100000000"],
        names: &["--across", "at most 5000"],
    },
    Case {
        files: &[("n.json", NET)],
        args: &["pointcalc", "surface", "n.json", "--nodes", "equi:3:0:inf"],
        names: &["--nodes", "'inf'"],
    },
    Case {
        files: &[("n.json", "[[[0,0,0],[1,0,0]],[[0,1,0],[1,1,1]]]")],
        args: &["pointcalc", "surface", "n.json", "--printed"],
        names: &["n.json", "4 given", "need 9"],
    },
    Case {
        files: &[(
            "n.json",
            "[[[1.7e308],[1.7e308],[-1.7e308]],[[1.7e308],[1.7e308],[-1.7e308]],[[1.7e308],[1.7e308],[-1.7e308]]]",
        )],
        args: &["pointcalc", "surface", "n.json", "--printed", "-o", "s.json"],
        names: &["n.json", "the point of the surface at u=", "overflows"],
    },
    Case {
        files: &[("n.json", "[[[1e305,0,0],[1,0,0]],[[0,1,0],[1,1,1]]]")],
        args: &["pointcalc", "surface", "n.json", "-o", "s.svg"],
        names: &["n.json", "1e305", "SVG"],
    },
];

#[test]
fn pointcalc() {
    crate::check_all(CASES);
}
