//! Issue 21 regressions of the expression engine: exact constants are bounded
//! (`MAX_EXACT_BITS`), every walk of a graph is iterative (100 000 levels built through the
//! API), printers refuse constants the target cannot hold and texts longer than
//! `MAX_PRINT_BYTES`.

use geomkit_expr::{
    parse, BigInt, BigRational, Const, ExprError, Format, Graph, Id, Node, ParseErrorKind, Tape,
    MAX_EXACT_BITS, MAX_PRINT_BYTES,
};

/// The parse error of `text`: its kind and the text of its span.
fn parse_error(text: &str) -> (ParseErrorKind, String, String) {
    match parse(&mut Graph::new(), text) {
        Err(ExprError::Parse(e)) => (e.kind.clone(), e.snippet(text).to_string(), e.to_string()),
        other => panic!("{text}: {other:?}"),
    }
}

/// Each of these overflowed the stack (`1.5^100000*x`: num-rational's recursive Hash), asked
/// for 34 GB (`(2^1048576)^1048576`) or ran for seconds to minutes before; now each is an
/// error naming the constant's sub-expression, at once.
#[test]
fn constants_out_of_range_are_refused_naming_the_subexpression() {
    let cases = [
        // (formula, span, overflow)
        ("1.5^100000*x", "1.5^100000", true),
        ("(2^1048576)^1048576", "2^1048576", true),
        ("(7e-4000)^100*x", "7e-4000", false),
        ("((2.5)^-1)^100**3", "((2.5)^-1)^100**3", false),
        ("1e1300 * x", "1e1300", true),
        ("u + 0.5e-2000", "0.5e-2000", false),
        ("x / 2^5000", "2^5000", true),
        ("(3/7)^-5000 + x", "(3/7)^-5000", true),
        // A product, a quotient and a sum of constants each within the limit.
        ("(2^4000*x)*(2^4000*y)", "(2^4000*x)*(2^4000*y)", true),
        ("u - 1/2^4095/2^4095", "1/2^4095/2^4095", false),
        ("2^4095 + 2^4095", "2^4095 + 2^4095", true),
        (
            "sin(u) * (2^4095 + 2^4095 + u)",
            "2^4095 + 2^4095 + u",
            true,
        ),
    ];
    for (text, span, overflow) in cases {
        let (kind, snippet, message) = parse_error(text);
        let expected = ParseErrorKind::ConstantOutOfRange {
            text: span.to_string(),
            overflow,
        };
        assert_eq!(kind, expected, "{text}");
        assert_eq!(snippet, span, "{text}");
        assert!(
            message.starts_with("constant out of range at byte"),
            "{message}"
        );
        assert!(message.contains("more than 4096 bits"), "{message}");
    }
    let (_, _, message) = parse_error("(7e-4000)^100*x");
    assert_eq!(
        message,
        "constant out of range at byte 1: `7e-4000` is too long to keep exact (more than 4096 \
         bits) and below the smallest f64 (about 4.9e-324)"
    );
}

/// Below the limit constants stay exact; beyond it (and within the range of f64) they are
/// the nearest f64.
#[test]
fn long_constants_become_their_nearest_f64() {
    let mut g = Graph::new();
    let coef = |g: &Graph, e: Id| match g.node(e) {
        Node::Mul(c, _) => c.clone(),
        n => panic!("{n:?}"),
    };
    // 3^2000 has 3170 bits: exact.
    let e = parse(&mut g, "1.5^2000*x").unwrap();
    assert!(matches!(coef(&g, e), Const::Rat(_)));
    let e = parse(&mut g, "2^4000/2^3999*x").unwrap();
    assert_eq!(g.print(e, Format::Maple).unwrap(), "2*x");
    // 300 · 21 bits: beyond the limit, the f64 power.
    let e = parse(&mut g, "(1234567/1234568)^300*x").unwrap();
    let Const::Float(c) = coef(&g, e) else {
        panic!()
    };
    // The exact value rounded is 0.9997570294431528; a power computed in f64 is within
    // about |n|·2^-53.
    assert!((c - 0.9997570294431528).abs() < 300.0 * f64::EPSILON, "{c}");
    assert_eq!(g.print(e, Format::Maple).unwrap(), format!("{c:?}*x"));
    // A literal of 3000 digits (its denominator 10^3000 has 9966 bits): its f64.
    let third = format!("0.{}", "3".repeat(3000));
    let e = parse(&mut g, &third).unwrap();
    assert_eq!(g.as_const(e), Some(&Const::Float(1.0 / 3.0)));
    // Trailing zeros do not count: 0.5000…0 is exactly 1/2.
    let half = format!("0.5{}", "0".repeat(5000));
    let e = parse(&mut g, &half).unwrap();
    assert_eq!(g.print(e, Format::Maple).unwrap(), "1/2");
    // Through the API: a rational beyond the limit is its f64, a zero denominator given raw
    // is an f64 infinity (refused when evaluated), nothing panics.
    let big = BigInt::from(3).pow(10_000u32);
    let r = g.rat(BigRational::new(big.clone() + 1, big));
    assert_eq!(g.as_const(r), Some(&Const::Float(1.0)));
    let inf = g.rat(BigRational::new_raw(1.into(), 0.into()));
    assert_eq!(g.as_const(inf), Some(&Const::Float(f64::INFINITY)));
    let x = g.var("x");
    let raw = Const::Rat(BigRational::new_raw(0.into(), 0.into()));
    let e = g.lin(&[(raw, x)]);
    assert!(matches!(
        g.eval(e, &[("x", 1.0)]),
        Err(ExprError::NonFiniteConstant { .. })
    ));
    assert_eq!(MAX_EXACT_BITS, 4096);
}

/// Exact constants outside the range of f64 print exactly where the target is exact and are
/// refused where it computes in f64 (and by the evaluators): `1e400` would be infinity
/// there, `1e-400` zero.
#[test]
fn exact_constants_outside_f64_are_refused_where_f64_computes() {
    let mut g = Graph::new();
    for (text, value) in [("1e400*x", "1.0000e400"), ("x/1e400", "1.0000e-400")] {
        let e = parse(&mut g, text).unwrap();
        for f in Format::ALL {
            let printed = g.print(e, f);
            match f {
                Format::Maple | Format::Mathematica | Format::Sympy | Format::Latex => {
                    assert!(printed.unwrap().contains("10000000000"), "{f:?}")
                }
                _ => assert_eq!(
                    printed,
                    Err(ExprError::ConstantOutOfRange {
                        value: value.into()
                    }),
                    "{f:?}"
                ),
            }
        }
        let err = g.eval(e, &[("x", 1.0)]).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "constant {value} of the expression is outside the range of f64 (magnitudes \
                 from about 4.9e-324 to 1.8e308)"
            )
        );
        assert!(Tape::new(&g, &[e], &["x"]).is_err());
    }
    // Numerator and denominator beyond f64, the value within: the nearest f64 where the
    // target computes in f64 (the C literal 1000…0.0 would be infinity).
    let e = parse(&mut g, "(10^400 + 1)/10^400 * x + (10^400 + 3)/(3*10^400)").unwrap();
    assert_eq!(g.print(e, Format::C).unwrap(), "1.0*x + 0.3333333333333333");
}

/// Division by a folded constant whose reciprocal overflows (atan(1e-320) is subnormal):
/// the tape divides, as `Graph::eval` and the printed code do (v·(1/x) gave 0·inf = NaN at
/// v = 0 where they give 0; found by fuzz_formulas_from_the_grammar).
#[test]
fn tapes_divide_by_constants_whose_reciprocal_overflows() {
    let mut g = Graph::new();
    for text in ["v/atan(1.0e-320) + u", "u - 2*v/atan(1.0e-160)^2"] {
        let e = parse(&mut g, text).unwrap();
        let tape = Tape::new(&g, &[e], &["u", "v"]).unwrap();
        let (u, v) = ([-2.0, -2.0, 1.0], [0.0, 1.0, -1e-300]);
        let mut out = [0.0; 3];
        tape.eval_batch(&[&u, &v], &mut [&mut out]).unwrap();
        for i in 0..3 {
            let want = g.eval(e, &[("u", u[i]), ("v", v[i])]).unwrap();
            assert_eq!(out[i].to_bits(), want.to_bits(), "{text} at v = {}", v[i]);
        }
        assert_eq!(out[0], -2.0, "{text}");
    }
}

/// Printers never write NaN or infinity as a number (`pointcalc formula` printed
/// `INFINITY`): every printer refuses a non-finite constant, wherever it stands.
#[test]
fn printers_refuse_non_finite_constants() {
    for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
        let mut g = Graph::new();
        let (u, v) = (g.var("u"), g.var("v"));
        let c = g.num(bad);
        let s = g.sin(u);
        let roots = [
            c,
            g.mul(c, u),
            g.add(u, c),
            g.lin(&[
                (Const::Float(bad), u),
                (Const::Rat(BigRational::from_integer(1.into())), v),
            ]),
            g.add(s, c),
        ];
        for &r in &roots {
            let root = g.sin(r);
            for f in Format::ALL {
                for result in [
                    g.print(root, f),
                    g.print_program(&[("x", root)], f),
                    g.print_function("x", &["u", "v"], &[root], f),
                    g.print_definition("x", &["u", "v"], root, f),
                ] {
                    assert!(
                        matches!(result, Err(ExprError::NonFiniteConstant { .. })),
                        "{bad} {f:?}: {result:?}"
                    );
                }
            }
            assert!(g.print_batch_rust("x", &["u", "v"], &[root]).is_err());
        }
    }
}

/// An inline print repeats shared sub-expressions: 60 nested `sign(sin(..))` print 2^60
/// copies in C (whose `sign` names its argument twice). It was written until memory ran
/// out; now it is refused before anything is written, and the program prints it short.
#[test]
fn exponentially_long_inline_prints_are_refused() {
    let mut text = "x".to_string();
    for _ in 0..60 {
        text = format!("sign(sin({text}))");
    }
    let mut g = Graph::new();
    let e = parse(&mut g, &text).unwrap();
    let err = g.print(e, Format::C).unwrap_err();
    assert_eq!(
        err,
        ExprError::PrintTooLong {
            max: MAX_PRINT_BYTES
        }
    );
    assert!(
        err.to_string().contains("longer than 268435456 bytes"),
        "{err}"
    );
    let program = g.print_program(&[("y", e)], Format::C).unwrap();
    assert!(program.len() < 10_000, "{}", program.len());
    // Maple names the argument once: linear.
    assert_eq!(
        g.print(e, Format::Maple).unwrap().len(),
        text.len() + 60 * 2
    );
    let mut text = "x".to_string();
    for _ in 0..20 {
        text = format!("(sin({text}) + 1)^4");
    }
    let e = parse(&mut g, &text).unwrap();
    assert!(matches!(
        g.print(e, Format::Js),
        Err(ExprError::PrintTooLong { .. })
    ));
    assert!(g.print_function("f", &["x"], &[e], Format::Js).is_ok());
}

const LEVELS: usize = 100_000;

/// `a_(k+1) = (a_k + 1)·u` (two levels each), `LEVELS` times: built in linear time (no
/// sum or product to flatten into the next).
fn deep_chain(g: &mut Graph) -> Id {
    let (u, one) = (g.var("u"), g.int(1));
    let mut a = g.var("v");
    for _ in 0..LEVELS {
        let s = g.add(a, one);
        a = g.mul(s, u);
    }
    a
}

/// `sin(cos(sin(...(u))))`, `LEVELS` calls.
fn deep_calls(g: &mut Graph) -> Id {
    let mut a = g.var("u");
    for k in 0..LEVELS {
        a = if k % 2 == 0 { g.sin(a) } else { g.cos(a) };
    }
    a
}

/// Every walk of a graph 100 000 levels deep: printing (it recursed and overflowed the
/// stack at 10–20 thousand levels), evaluation, the tape, derivative, substitution,
/// counting, and dropping the graph.
#[test]
fn walks_of_graphs_100_000_levels_deep_do_not_recurse() {
    let mut g = Graph::new();
    let chain = deep_chain(&mut g);
    let calls = deep_calls(&mut g);
    assert_eq!(g.depth(chain) as usize, 2 * LEVELS + 1);
    assert_eq!(g.depth(calls) as usize, LEVELS + 1);
    for f in Format::ALL {
        let text = g.print(calls, f).unwrap();
        assert!(text.len() > 3 * LEVELS, "{f:?}");
    }
    for f in [Format::Maple, Format::C] {
        let text = g.print(chain, f).unwrap();
        assert!(text.len() > 5 * LEVELS, "{f:?}");
    }
    let program = g
        .print_program(&[("x", chain), ("y", calls)], Format::C)
        .unwrap();
    assert!(
        program.starts_with("const double x = "),
        "{}",
        &program[..40]
    );
    g.print_function("f", &["u", "v"], &[chain, calls], Format::Rust)
        .unwrap();
    // (v + 1)·u + 1)·u ... at u = 1/2, v = 0: the fixed point 1 of a → (a + 1)/2, from below.
    let at = [("u", 0.5), ("v", 0.0)];
    let want = g.eval(chain, &at).unwrap();
    assert!((want - 1.0).abs() < 1e-12, "{want}");
    let tape = Tape::new(&g, &[chain, calls], &["u", "v"]).unwrap();
    let mut out = [[0.0; 1]; 2];
    let [o0, o1] = &mut out;
    tape.eval_batch(&[&[0.5], &[0.0]], &mut [o0, o1]).unwrap();
    assert_eq!(out[0][0], want);
    assert_eq!(out[1][0], g.eval(calls, &at).unwrap());
    // d/du of the chain: d_(k+1) = d_k·u + a_k + 1, also linear in size.
    let d = g.diff(chain, "u");
    assert!(g.eval(d, &at).unwrap().is_finite());
    let w = g.var("w");
    let moved = g.substitute(chain, "v", w);
    assert_eq!(g.variables(&[moved]), ["u", "w"]);
    assert!(g.op_count(&[chain]) >= 2 * LEVELS);
    // The printed text is too deep for the parser (200 levels): an error, not a crash.
    let text = g.print(calls, Format::Maple).unwrap();
    let (kind, _, _) = parse_error(&text);
    assert_eq!(kind, ParseErrorKind::TooDeep { max: 200 });
    drop(g);
}

/// `x^i32::MIN` through the API: evaluating it negated the exponent, which overflowed (a
/// panic); the tape computed `x^(2^31)` instead. Now it is `x^(-2^30)·x^(-2^30)`.
#[test]
fn the_most_negative_exponent_evaluates() {
    let mut g = Graph::new();
    let x = g.var("x");
    let p = g.powi(x, i32::MIN);
    assert_eq!(
        g.print(p, Format::Maple).unwrap(),
        "1/(x^1073741824*x^1073741824)"
    );
    // 1.0000001^(-2^31) = exp(-2^31·ln(1.0000001)) ≈ 5.4e-94.
    let v = g.eval(p, &[("x", 1.0000001)]).unwrap();
    assert!(v > 5e-94 && v < 6e-94, "{v}");
    let tape = Tape::new(&g, &[p], &["x"]).unwrap();
    let mut out = [0.0];
    tape.eval_batch(&[&[1.0000001]], &mut [&mut out]).unwrap();
    assert_eq!(out[0], v);
    let d = g.diff(p, "x");
    assert!(g.eval(d, &[("x", 1.0000001)]).unwrap() < 0.0);
    let q = g.powi(p, -1);
    assert_eq!(
        g.print(q, Format::Maple).unwrap(),
        "x^1073741824*x^1073741824"
    );
}
