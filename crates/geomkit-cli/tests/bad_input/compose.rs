//! Bad input to `geomkit compose patches`, `ruled`, `piecewise` and the shape options of
//! `compose body` (the mesh options of `compose body` have their own table): files whose
//! numbers overflow or underflow the single formula, knots beyond f64, pieces not finite
//! at an end, wrong files, bad formats and sizes. Each error names the file, the option
//! or the patch, piece or curve, and what is wrong.

use crate::Case;

/// A bilinear patch with ±1.7e308 at its corners: its power-basis coefficients overflow.
const BIG_PATCH: &str = r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"bezier":[[[0,0,-1.7e308],[0,1,1.7e308]],[[1,0,1.7e308],[1,1,-1.7e308]]]}]]}"#;

/// Two flat patches at +1.7e308 and -1.7e308: their jump overflows.
const BIG_JUMP: &str = r#"{"type":"composite_surface","u_knots":[0,1,2],"v_knots":[0,1],"patches":[[{"bezier":[[[0,0,1.7e308],[0,1,1.7e308]],[[1,0,1.7e308],[1,1,1.7e308]]]}],[{"bezier":[[[0,0,-1.7e308],[0,1,-1.7e308]],[[1,0,-1.7e308],[1,1,-1.7e308]]]}]]}"#;

/// A B-spline surface with control points at ±f64::MAX.
const MAX_BSPLINE: &str = r#"{"type":"bspline_surface","degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],"net":[[[0,0,1.7976931348623157e308],[0,1,-1.7976931348623157e308]],[[1,0,-1.7976931348623157e308],[1,1,1.7976931348623157e308]]]}"#;

/// A B-spline curve with control points at ±f64::MAX.
const MAX_CURVE: &str = r#"{"type":"bspline_curve","degree":3,"knots":[0,0,0,0,1,1,1,1],"control_points":[[0,1.7976931348623157e308],[1,-1.7976931348623157e308],[2,1.7976931348623157e308],[3,-1.7976931348623157e308]]}"#;

/// A ruled surface over a polygon at ±1.7e308.
const BIG_RULED: &str = r#"{"type":"ruled","curves":[{"point":[0,0,1.7e308]},{"polygon":[[1.7e308,0,0],[-1.7e308,0,0],[0,1,0]]},{"point":[0,0,-1.7e308]}],"v":[0,1,2],"u":[0,3]}"#;

const CUBIC: &str = r#"{"type":"bezier_curve","points":[[0,0],[1,2],[2,2],[3,0]]}"#;

pub const CASES: &[Case] = &[
    // compose patches
    Case {
        files: &[],
        args: &["compose", "patches", "missing.json", "-o", "out.json"],
        names: &["missing.json"],
    },
    Case {
        files: &[("s.json", BIG_PATCH)],
        args: &["compose", "patches", "s.json", "-o", "out.json"],
        names: &[
            "s.json",
            "patch (0, 0)",
            "power-basis coefficients",
            "overflow f64",
        ],
    },
    Case {
        files: &[("s.json", BIG_PATCH)],
        args: &["compose", "patches", "s.json", "--format", "c"],
        names: &["s.json", "patch (0, 0)", "overflow f64"],
    },
    Case {
        files: &[("s.json", BIG_JUMP)],
        args: &["compose", "patches", "s.json", "--report-json"],
        names: &["s.json", "patches (0, 0) and (1, 0)", "u = 1", "overflows"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[-1.7e308,1.7e308],"y_knots":[0,1],"patches":[["x*y"]]}"#,
        )],
        args: &["compose", "patches", "s.json", "-o", "out.obj"],
        names: &["s.json", "knots from -1.7e308 to 1.7e308", "span"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e-310],"y_knots":[0,1],"patches":[["x*y"]]}"#,
        )],
        args: &["compose", "patches", "s.json", "-o", "out.txt"],
        names: &["s.json", "1e-310", "1/(2w)", "smallest normal"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1,1],"y_knots":[0,1],"patches":[["x"],["y"]]}"#,
        )],
        args: &["compose", "patches", "s.json"],
        names: &["s.json", "knot 2", "strictly increasing"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1,2],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        args: &["compose", "patches", "s.json"],
        names: &["s.json", "patch rows", "expected 2, got 1"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[["1/(x - 0.5)"]]}"#,
        )],
        args: &["compose", "patches", "s.json", "-o", "out.svg"],
        names: &["s.json", "patch (0, 0)", "x = 0.5", "not a finite number"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e307],"y_knots":[0,1],"patches":[[{"bezier":[[[0],[0]],[[1e-300],[1e-300]]]}]]}"#,
        )],
        args: &["compose", "patches", "s.json"],
        names: &["s.json", "patch (0, 0)", "underflows"],
    },
    Case {
        files: &[("fit.json", MAX_BSPLINE)],
        args: &["compose", "patches", "fit.json", "-o", "out.json"],
        names: &["fit.json", "patch (0, 0)", "overflow f64"],
    },
    Case {
        files: &[("c.json", CUBIC)],
        args: &["compose", "patches", "c.json"],
        names: &["c.json", "compose patches", "composite_surface"],
    },
    Case {
        files: &[("s.json", "")],
        args: &["compose", "patches", "s.json"],
        names: &["s.json"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e999],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        args: &["compose", "patches", "s.json"],
        names: &["s.json"],
    },
    Case {
        files: &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        args: &["compose", "patches", "s.json", "-o", "out.xyz"],
        names: &["out.xyz", "output format"],
    },
    // compose ruled
    Case {
        files: &[("r.json", BIG_RULED)],
        args: &["compose", "ruled", "r.json", "-o", "out.obj"],
        names: &["r.json", "curve 0", "f64::MAX/2"],
    },
    Case {
        files: &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"circle":{"center":[0,0,0],"radius":1}}],"v":[1,0]}"#,
        )],
        args: &["compose", "ruled", "r.json"],
        names: &["r.json", "\"v\"", "strictly increasing"],
    },
    Case {
        files: &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"circle":{"center":[0,0,0],"radius":0}}],"v":[0,1]}"#,
        )],
        args: &["compose", "ruled", "r.json"],
        names: &["r.json", "radius"],
    },
    Case {
        files: &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"x":"t","y":"t","z":"ln(t)","t":[0,1]}],"v":[0,1]}"#,
        )],
        args: &["compose", "ruled", "r.json"],
        names: &["r.json", "coordinate z", "not a finite number"],
    },
    Case {
        files: &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"point":[0,0,0]}],"v":[0,1],"u":[1,1]}"#,
        )],
        args: &["compose", "ruled", "r.json"],
        names: &["r.json", "strictly increasing"],
    },
    // compose piecewise
    Case {
        files: &[(
            "p.json",
            r#"{"type":"polyline","points":[[0,1.7e308],[1,-1.7e308],[2,0]]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "-o", "out.json"],
        names: &["p.json", "polyline points 0 and 1", "overflows"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"polyline","points":[[1e-300],[-1e-300]],"knots":[0,1e307]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "--format", "c"],
        names: &["p.json", "coordinate f", "underflows"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[-1.7e308,0,1.7e308],"pieces":["x","1"]}"#,
        )],
        args: &["compose", "piecewise", "p.json"],
        names: &["p.json", "knots from -1.7e308 to 1.7e308", "span"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[-4e307,0,4e307],"pieces":["x/4e307","x/2e307"]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "-o", "out.svg"],
        names: &["p.json", "piece 0", "f64::MAX/2", "overflow f64"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["ln(x)","x"]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "-o", "out.json"],
        names: &["p.json", "piece 0", "x = 0", "an end of its interval"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x"]}"#,
        )],
        args: &["compose", "piecewise", "p.json"],
        names: &["p.json", "pieces for 3 knots", "expected 2, got 1"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x +* 2"]}"#,
        )],
        args: &["compose", "piecewise", "p.json"],
        names: &["p.json", "piece 0", "parse error"],
    },
    Case {
        files: &[("fit.json", MAX_CURVE)],
        args: &["compose", "piecewise", "fit.json"],
        names: &["fit.json", "span 0", "overflow f64"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x"]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "--format", "fortran"],
        names: &["--format", "fortran"],
    },
    Case {
        files: &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x"]}"#,
        )],
        args: &["compose", "piecewise", "p.json", "-o", "out.obj"],
        names: &["out.obj", "output format"],
    },
    // compose body: the shape options
    Case {
        files: &[],
        args: &["compose", "body", "box", "--size", "1e308,1,1"],
        names: &["--size", "1e308", "at most 1e100"],
    },
    Case {
        files: &[],
        args: &[
            "compose", "body", "box", "--size", "nan,1,1", "-o", "out.obj",
        ],
        names: &["--size", "nan"],
    },
    Case {
        files: &[],
        args: &["compose", "body", "box", "--size", "1,2"],
        names: &["--size", "three sizes"],
    },
    Case {
        files: &[],
        args: &[
            "compose", "body", "pyramid", "--side", "-1", "-o", "out.json",
        ],
        names: &["--side", "-1", "> 0"],
    },
    Case {
        files: &[],
        args: &["compose", "body", "frustum", "--top-radius", "0"],
        names: &["--top-radius", "top radius = 0"],
    },
    Case {
        files: &[],
        args: &["compose", "body", "cylinder", "--height", "inf"],
        names: &["--height", "inf"],
    },
    Case {
        files: &[],
        args: &["compose", "body", "prism", "--polygon", "1e308,0;0,1;-1,-1"],
        names: &["--polygon", "vertex 0", "1e100"],
    },
    Case {
        files: &[],
        args: &["compose", "body", "prism", "--polygon", "0,0;1,1"],
        names: &["--polygon", "too few"],
    },
];

#[test]
fn compose() {
    crate::check_all(CASES);
}
