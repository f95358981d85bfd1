//! Bad input to `geomkit compose patches`, `ruled`, `piecewise` and the shape options of
//! `compose body` (the mesh options of `compose body` have their own table): files whose
//! numbers overflow or underflow the single formula, knots beyond f64, pieces not finite
//! at an end, wrong files, bad formats and sizes. Each error names the file, the option
//! or the patch, piece or curve, and what is wrong.

use crate::{case, Case};

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
    case(
        &[],
        &["compose", "patches", "missing.json", "-o", "out.json"],
        &["missing.json"],
    ),
    case(
        &[("s.json", BIG_PATCH)],
        &["compose", "patches", "s.json", "-o", "out.json"],
        &[
            "s.json",
            "patch (0, 0)",
            "power-basis coefficients",
            "overflow f64",
        ],
    ),
    case(
        &[("s.json", BIG_PATCH)],
        &["compose", "patches", "s.json", "--format", "c"],
        &["s.json", "patch (0, 0)", "overflow f64"],
    ),
    case(
        &[("s.json", BIG_JUMP)],
        &["compose", "patches", "s.json", "--report-json"],
        &["s.json", "patches (0, 0) and (1, 0)", "u = 1", "overflows"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[-1.7e308,1.7e308],"y_knots":[0,1],"patches":[["x*y"]]}"#,
        )],
        &["compose", "patches", "s.json", "-o", "out.obj"],
        &["s.json", "knots from -1.7e308 to 1.7e308", "span"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e-310],"y_knots":[0,1],"patches":[["x*y"]]}"#,
        )],
        &["compose", "patches", "s.json", "-o", "out.txt"],
        &["s.json", "1e-310", "1/(2w)", "smallest normal"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1,1],"y_knots":[0,1],"patches":[["x"],["y"]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["s.json", "knot 2", "strictly increasing"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1,2],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["s.json", "patch rows", "expected 2, got 1"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[["1/(x - 0.5)"]]}"#,
        )],
        &["compose", "patches", "s.json", "-o", "out.svg"],
        &["s.json", "patch (0, 0)", "x = 0.5", "not a finite number"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e307],"y_knots":[0,1],"patches":[[{"bezier":[[[0],[0]],[[1e-300],[1e-300]]]}]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["s.json", "patch (0, 0)", "underflows"],
    ),
    case(
        &[("fit.json", MAX_BSPLINE)],
        &["compose", "patches", "fit.json", "-o", "out.json"],
        &["fit.json", "patch (0, 0)", "overflow f64"],
    ),
    case(
        &[("c.json", CUBIC)],
        &["compose", "patches", "c.json"],
        &["c.json", "compose patches", "composite_surface"],
    ),
    case(
        &[("s.json", "")],
        &["compose", "patches", "s.json"],
        &["s.json"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1e999],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["s.json"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[["x"]]}"#,
        )],
        &["compose", "patches", "s.json", "-o", "out.xyz"],
        &["out.xyz", "output format"],
    ),
    // compose ruled
    case(
        &[("r.json", BIG_RULED)],
        &["compose", "ruled", "r.json", "-o", "out.obj"],
        &["r.json", "curve 0", "f64::MAX/2"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"circle":{"center":[0,0,0],"radius":1}}],"v":[1,0]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["r.json", "\"v\"", "strictly increasing"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"circle":{"center":[0,0,0],"radius":0}}],"v":[0,1]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["r.json", "radius"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"x":"t","y":"t","z":"ln(t)","t":[0,1]}],"v":[0,1]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["r.json", "coordinate z", "not a finite number"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","curves":[{"point":[0,0,1]},{"point":[0,0,0]}],"v":[0,1],"u":[1,1]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["r.json", "strictly increasing"],
    ),
    // compose piecewise
    case(
        &[(
            "p.json",
            r#"{"type":"polyline","points":[[0,1.7e308],[1,-1.7e308],[2,0]]}"#,
        )],
        &["compose", "piecewise", "p.json", "-o", "out.json"],
        &["p.json", "polyline points 0 and 1", "overflows"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"polyline","points":[[1e-300],[-1e-300]],"knots":[0,1e307]}"#,
        )],
        &["compose", "piecewise", "p.json", "--format", "c"],
        &["p.json", "coordinate f", "underflows"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[-1.7e308,0,1.7e308],"pieces":["x","1"]}"#,
        )],
        &["compose", "piecewise", "p.json"],
        &["p.json", "knots from -1.7e308 to 1.7e308", "span"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[-4e307,0,4e307],"pieces":["x/4e307","x/2e307"]}"#,
        )],
        &["compose", "piecewise", "p.json", "-o", "out.svg"],
        &["p.json", "piece 0", "f64::MAX/2", "overflow f64"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["ln(x)","x"]}"#,
        )],
        &["compose", "piecewise", "p.json", "-o", "out.json"],
        &["p.json", "piece 0", "x = 0", "an end of its interval"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x"]}"#,
        )],
        &["compose", "piecewise", "p.json"],
        &["p.json", "pieces for 3 knots", "expected 2, got 1"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x +* 2"]}"#,
        )],
        &["compose", "piecewise", "p.json"],
        &["p.json", "piece 0", "parse error"],
    ),
    case(
        &[("fit.json", MAX_CURVE)],
        &["compose", "piecewise", "fit.json"],
        &["fit.json", "span 0", "overflow f64"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x"]}"#,
        )],
        &["compose", "piecewise", "p.json", "--format", "fortran"],
        &["--format", "fortran"],
    ),
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":["x"]}"#,
        )],
        &["compose", "piecewise", "p.json", "-o", "out.obj"],
        &["out.obj", "output format"],
    ),
    // compose body: the shape options
    case(
        &[],
        &["compose", "body", "box", "--size", "1e308,1,1"],
        &["--size", "1e308", "at most 1e100"],
    ),
    case(
        &[],
        &[
            "compose", "body", "box", "--size", "nan,1,1", "-o", "out.obj",
        ],
        &["--size", "nan"],
    ),
    case(
        &[],
        &["compose", "body", "box", "--size", "1,2"],
        &["--size", "three sizes"],
    ),
    case(
        &[],
        &[
            "compose", "body", "pyramid", "--side", "-1", "-o", "out.json",
        ],
        &["--side", "-1", "> 0"],
    ),
    case(
        &[],
        &["compose", "body", "frustum", "--top-radius", "0"],
        &["--top-radius", "top radius = 0"],
    ),
    case(
        &[],
        &["compose", "body", "cylinder", "--height", "inf"],
        &["--height", "inf"],
    ),
    case(
        &[],
        &["compose", "body", "prism", "--polygon", "1e308,0;0,1;-1,-1"],
        &["--polygon", "vertex 0", "1e100"],
    ),
    case(
        &[],
        &["compose", "body", "prism", "--polygon", "0,0;1,1"],
        &["--polygon", "too few"],
    ),
];

#[test]
fn compose() {
    crate::check_all(CASES);
}
