//! Bad formulas, in every command that reads them: `compose piecewise` (pieces in x or t),
//! `compose patches` (explicit and parametric formula patches), `compose ruled` (curves in
//! t), and `eval` / `render` of a saved formula file. Constants too long to keep exact and
//! out of the range of f64 (the issue's `1.5^100000*x`, `(2^1048576)^1048576`,
//! `(7e-4000)^100*x`, `((2.5)^-1)^100**3`), exact constants outside f64, divisions by zero,
//! unknown names, nesting too deep, printed formulas too long.

use crate::{case, Case};

/// `prefix`, `open` `times` times, `middle`, `close` `times` times, `suffix`, as bytes of
/// length `N` (a deeply nested formula as a constant).
const fn nest<const N: usize>(parts: [&str; 5], times: usize) -> [u8; N] {
    let mut out = [0u8; N];
    let mut at = 0;
    let mut part = 0;
    while part < 5 {
        let bytes = parts[part].as_bytes();
        let repeat = if part == 1 || part == 3 { times } else { 1 };
        let mut r = 0;
        while r < repeat {
            let mut i = 0;
            while i < bytes.len() {
                out[at] = bytes[i];
                at += 1;
                i += 1;
            }
            r += 1;
        }
        part += 1;
    }
    assert!(at == N, "N must be the nested text's length");
    out
}

const fn text(bytes: &'static [u8]) -> &'static str {
    match std::str::from_utf8(bytes) {
        Ok(s) => s,
        Err(_) => panic!("ASCII"),
    }
}

const PIECES: &str = r#"{"type":"piecewise","knots":[0,1],"pieces":[""#;
const END: &str = r#""]}"#;

/// A piece nested 1000 parentheses deep.
const PARENS: [&str; 5] = [PIECES, "(", "x", ")", END];
const PARENS_LEN: usize = PIECES.len() + 1000 * 2 + 1 + END.len();
const PARENS_BYTES: [u8; PARENS_LEN] = nest(PARENS, 1000);
const DEEP_PARENS: &str = text(&PARENS_BYTES);

/// `sign(sin(...(x)))`, 60 levels: C's `sign` names its argument twice, so the inline C
/// text would be 2^60 copies long.
const SIGNS: [&str; 5] = [PIECES, "sign(sin(", "x", "))", END];
const SIGNS_LEN: usize = PIECES.len() + 60 * 11 + 1 + END.len();
const SIGNS_BYTES: [u8; SIGNS_LEN] = nest(SIGNS, 60);
const DEEP_SIGNS: &str = text(&SIGNS_BYTES);

const PIECEWISE: &[&str] = &["compose", "piecewise", "p.json"];

/// The file `p.json` of a piecewise function of one piece on [0, 1], the formula given.
macro_rules! piece {
    ($formula:literal) => {
        &[(
            "p.json",
            concat!(
                r#"{"type":"piecewise","knots":[0,1],"pieces":[""#,
                $formula,
                r#""]}"#
            ),
        )]
    };
}

pub const CASES: &[Case] = &[
    // The issue's formulas: each was a stack overflow, 34 GB or a hang.
    case(
        piece!("1.5^100000*x"),
        PIECEWISE,
        &[
            "p.json",
            "piece 0",
            "`1.5^100000`",
            "more than 4096 bits",
            "above the largest f64",
        ],
    ),
    case(
        piece!("(2^1048576)^1048576 + x"),
        PIECEWISE,
        &["at byte 1", "`2^1048576`", "above the largest f64"],
    ),
    case(
        piece!("(7e-4000)^100*x"),
        PIECEWISE,
        &["`7e-4000`", "below the smallest f64"],
    ),
    case(
        piece!("((2.5)^-1)^100**3*x"),
        PIECEWISE,
        &["`((2.5)^-1)^100**3`", "below the smallest f64"],
    ),
    // Each way of building a constant: sum, product, quotient, negative power.
    case(
        piece!("x + 2^4095 + 2^4095"),
        PIECEWISE,
        &["`x + 2^4095 + 2^4095`", "too long to keep exact"],
    ),
    case(
        piece!("(2^4000*x)*(2^4000*x)"),
        PIECEWISE,
        &["`(2^4000*x)*(2^4000*x)`", "above the largest f64"],
    ),
    case(piece!("x/2^5000"), PIECEWISE, &["`2^5000`", "at byte 2"]),
    case(
        piece!("(3/7)^-5000 + x"),
        PIECEWISE,
        &["`(3/7)^-5000`", "above the largest f64"],
    ),
    case(
        piece!("1e5000*x"),
        PIECEWISE,
        &["byte 1", "an exponent of at most 4000"],
    ),
    // Exact, but outside the range of f64 the formula is evaluated in.
    case(
        piece!("1e400*x"),
        PIECEWISE,
        &["constant 1.0000e400", "outside the range of f64"],
    ),
    case(
        piece!("x*1e-400"),
        &[
            "compose",
            "piecewise",
            "p.json",
            "--format",
            "sympy",
            "-o",
            "f.json",
        ],
        &["constant 1.0000e-400", "outside the range of f64"],
    ),
    // Division by zero, unknown names, syntax.
    case(
        piece!("x/(1 - 1)"),
        PIECEWISE,
        &["piece 0", "division by exact zero"],
    ),
    case(
        piece!("1/(x - 1)"),
        PIECEWISE,
        &["inf", "x = 1", "not a finite number"],
    ),
    case(piece!("ln(x - 5)"), PIECEWISE, &["NaN", "x = 0"]),
    case(
        piece!("foo(x)"),
        PIECEWISE,
        &["a known function", "not `foo`"],
    ),
    case(
        piece!("x + y"),
        PIECEWISE,
        &["unknown variable `y`", "the variables are x", "byte 4"],
    ),
    case(
        piece!("x^1.5"),
        PIECEWISE,
        &["unsupported exponent", "only integer exponents"],
    ),
    case(
        piece!("x^2147483648"),
        PIECEWISE,
        &["unsupported exponent", "too large"],
    ),
    case(piece!(""), PIECEWISE, &["byte 0", "found end of input"]),
    case(piece!("x·2"), PIECEWISE, &["byte 1", "found `·`"]),
    case(
        &[("p.json", DEEP_PARENS)],
        PIECEWISE,
        &["nests deeper than 200 levels"],
    ),
    // Printed formulas too long: refused before anything is written, file or stdout.
    case(
        &[("p.json", DEEP_SIGNS)],
        &["compose", "piecewise", "p.json", "--format", "c"],
        &["coordinate f", "longer than 268435456 bytes"],
    ),
    case(
        &[("p.json", DEEP_SIGNS)],
        &["compose", "piecewise", "p.json", "-o", "f.json"],
        &["longer than 268435456 bytes"],
    ),
    // Composite curves, formula patches, ruled curves, saved formula files.
    case(
        &[(
            "p.json",
            r#"{"type":"piecewise","knots":[0,1],"pieces":[{"x":"t","y":"(7e-4000)^100*t"}]}"#,
        )],
        PIECEWISE,
        &["coordinate y", "`7e-4000`"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[["1.5^100000*x + y"]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["s.json", "patches[0][0]", "coordinate z", "`1.5^100000`"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_explicit","x_knots":[0,1],"y_knots":[0,1],"patches":[[{"z":"x + y*1e400"}]]}"#,
        )],
        &["compose", "patches", "s.json", "-o", "s.obj"],
        &["patches[0][0]", "constant 1.0000e400"],
    ),
    case(
        &[(
            "s.json",
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u","y":"v","z":"((2.5)^-1)^100**3*u"}]]}"#,
        )],
        &["compose", "patches", "s.json"],
        &["patches[0][0]", "coordinate z", "below the smallest f64"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","u":[0,1],"v":[0,1],"curves":[{"x":"cos(t)","y":"sin(t)","z":"(2^1048576)^1048576","t":[0,1]},{"point":[0,0,1]}]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["r.json", "curves[0]", "coordinate z", "`2^1048576`"],
    ),
    case(
        &[(
            "r.json",
            r#"{"type":"ruled","u":[0,1],"v":[0,1],"curves":[{"x":"cos(t)","y":"sin(s)","z":"1","t":[0,1]},{"point":[0,0,1]}]}"#,
        )],
        &["compose", "ruled", "r.json"],
        &["curves[0]", "coordinate y", "unknown variable `s`"],
    ),
    case(
        &[(
            "f.json",
            r#"{"type":"formula","what":"x","variables":["x"],"coordinates":["f"],"op_count":1,"formulas":{},"model":{"type":"piecewise","knots":[0,1],"pieces":["(7e-4000)^100*x"]}}"#,
        )],
        &["eval", "f.json", "--samples", "3"],
        &["f.json", "\"model\"", "`7e-4000`"],
    ),
    case(
        &[(
            "f.json",
            r#"{"type":"formula","what":"x","variables":["x"],"coordinates":["f"],"op_count":1,"formulas":{},"model":{"type":"piecewise","knots":[0,1],"pieces":["1.5^100000*x"]}}"#,
        )],
        &["render", "f.json", "-o", "f.svg"],
        &["f.json", "`1.5^100000`"],
    ),
];

#[test]
fn expr() {
    crate::check_all(CASES);
}
