//! Fuzzing the expression engine (issue 21): random formula texts from a grammar (numbers
//! with huge and tiny exponents, long literals, powers up to the parser's limit, nesting,
//! every function and some unknown ones, known and unknown variables), the same texts with
//! random byte and char mutations, and random DAGs built through the API (any `f64`
//! including NaN and infinities, long exact rationals, huge integer powers, derivatives,
//! substitutions).
//!
//! Property: nothing panics and every case finishes in bounded time; a parse error's span
//! lies in the text on char boundaries; every printer returns text or one of the documented
//! refusals (a constant the target cannot hold, a text too long); when the expression
//! evaluates, the tape agrees with `Graph::eval` (both non-finite, or equal within
//! rounding), and when one refuses, so does the other.

#[path = "../../geomkit/tests/common/fuzz.rs"]
mod fuzz;

use std::time::{Duration, Instant};

use geomkit_expr::{
    parse, parse_with_variables, BigInt, BigRational, Const, ExprError, Format, Func, Graph, Id,
    Tape,
};
use proptest::prelude::*;

/// Far more than any case needs (a few milliseconds): a case this slow is a hang.
const HANG: Duration = Duration::from_secs(5);

const VARS: [&str; 3] = ["u", "v", "w"];

fn number() -> impl Strategy<Value = String> {
    let exponents = prop::sample::select(vec![
        "0",
        "1",
        "-1",
        "5",
        "-5",
        "300",
        "308",
        "309",
        "-300",
        "-308",
        "-320",
        "-324",
        "400",
        "-400",
        "1200",
        "1233",
        "1234",
        "-1300",
        "4000",
        "-4000",
        "4001",
        "99999999999999999999",
    ]);
    prop_oneof![
        (0u32..100).prop_map(|n| n.to_string()),
        (0u32..1000, 0u32..1000).prop_map(|(a, b)| format!("{a}.{b}")),
        (1u32..10, 0u32..100, exponents).prop_map(|(a, b, e)| format!("{a}.{b}e{e}")),
        // Long literals: up to 3000 digits, with or without a point.
        (1usize..3000, any::<bool>(), 0u8..10).prop_map(|(n, point, d)| {
            let digits = char::from(b'0' + d).to_string().repeat(n);
            if point {
                format!("0.{digits}1")
            } else {
                format!("1{digits}")
            }
        }),
        Just(".5".to_string()),
        Just("5.".to_string()),
    ]
}

fn exponent() -> impl Strategy<Value = String> {
    prop_oneof![
        (-4i64..6).prop_map(|n| if n < 0 {
            format!("({n})")
        } else {
            n.to_string()
        }),
        prop::sample::select(vec![
            "100",
            "1000",
            "4096",
            "100000",
            "1048576",
            "1048577",
            "-1048576",
            "2147483648",
            "(1/2)",
            "0.5",
            "u",
            "100**3",
            "(-1)",
            "2^20",
        ])
        .prop_map(str::to_string),
    ]
}

fn formula() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        prop::sample::select(vec!["u", "v", "w", "pi", "Pi", "x_1", "unknown"])
            .prop_map(str::to_string),
        number(),
    ];
    let functions = prop::sample::select(vec![
        "abs", "sign", "sqrt", "sin", "cos", "tan", "exp", "ln", "log", "atan", "arctan", "asin",
        "acos", "sinh", "cosh", "tanh", "Abs", "signum", "foo", "Sin",
    ]);
    leaf.prop_recursive(6, 64, 4, move |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec![" + ", " - ", "*", "/", " * ", "-"]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("{a}{op}{b}")),
            (
                inner.clone(),
                prop::sample::select(vec!["^", "**", " ^ "]),
                exponent()
            )
                .prop_map(|(a, op, e)| format!("({a}){op}{e}")),
            inner.clone().prop_map(|a| format!("-{a}")),
            inner.clone().prop_map(|a| format!("({a})")),
            (functions.clone(), inner).prop_map(|(f, a)| format!("{f}({a})")),
        ]
    })
}

/// One random edit of a text: insert, delete or replace a char, or repeat a slice.
#[derive(Clone, Debug)]
enum Edit {
    Insert(usize, char),
    Delete(usize),
    Replace(usize, char),
    Repeat(usize, usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let chars = prop_oneof![
        prop::sample::select(vec![
            '(', ')', '^', '*', '/', '+', '-', '.', 'e', 'E', '0', '9', ' ', '\n', ',', '·', 'é',
            '\u{0}', '𝑥'
        ]),
        any::<char>(),
    ];
    prop_oneof![
        (any::<usize>(), chars.clone()).prop_map(|(i, c)| Edit::Insert(i, c)),
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), chars).prop_map(|(i, c)| Edit::Replace(i, c)),
        (any::<usize>(), 1usize..20, 1usize..50).prop_map(|(i, n, k)| Edit::Repeat(i, n, k)),
    ]
}

/// `text` with the edits applied (positions taken modulo the length, on char boundaries).
fn mutate(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        let at = |i: usize, n: usize| if n == 0 { 0 } else { i % n };
        match *e {
            Edit::Insert(i, c) => {
                let i = at(i, chars.len() + 1);
                chars.insert(i, c);
            }
            Edit::Delete(i) if !chars.is_empty() => {
                let i = at(i, chars.len());
                chars.remove(i);
            }
            Edit::Replace(i, c) if !chars.is_empty() => {
                let i = at(i, chars.len());
                chars[i] = c;
            }
            Edit::Repeat(i, n, k) if !chars.is_empty() => {
                let i = at(i, chars.len());
                let slice: Vec<char> = chars[i..(i + n).min(chars.len())].to_vec();
                for _ in 0..k {
                    chars.splice(i..i, slice.iter().copied());
                }
            }
            _ => {}
        }
    }
    chars.into_iter().collect()
}

/// Equal within rounding: both non-finite, or close relative to the magnitude.
fn agree(a: f64, b: f64) -> bool {
    if !a.is_finite() || !b.is_finite() {
        return !a.is_finite() && !b.is_finite() || a.abs() > 1e12 || b.abs() > 1e12;
    }
    (a - b).abs() <= 1e-6 * (1.0 + a.abs().max(b.abs()))
}

/// The refusals a printer may answer with.
fn printer_refusal(e: &ExprError) -> bool {
    matches!(
        e,
        ExprError::NonFiniteConstant { .. }
            | ExprError::ConstantOutOfRange { .. }
            | ExprError::PrintTooLong { .. }
    )
}

/// Every printer, `Graph::eval` and the tape on the roots of `g`: no panic, the documented
/// refusals only, and the tape agrees with `eval` at two points.
fn check_graph(g: &Graph, roots: &[Id]) -> Result<(), TestCaseError> {
    for f in Format::ALL {
        for r in roots {
            if let Err(e) = g.print(*r, f) {
                prop_assert!(printer_refusal(&e), "{f:?}: {e}");
            }
        }
        let outputs: Vec<(&str, Id)> = roots.iter().map(|r| ("out", *r)).collect();
        if let Err(e) = g.print_program(&outputs, f) {
            prop_assert!(printer_refusal(&e), "{f:?}: {e}");
        }
    }
    let points = [[0.5, -1.25, 3.0], [-2.0, 0.0, 1e-3]];
    let tape = Tape::new(g, roots, &VARS);
    for p in points {
        let at: Vec<(&str, f64)> = VARS.iter().copied().zip(p).collect();
        let evals: Vec<Result<f64, ExprError>> = roots.iter().map(|r| g.eval(*r, &at)).collect();
        let all_ok = evals.iter().all(Result::is_ok);
        prop_assert_eq!(
            all_ok,
            tape.is_ok(),
            "eval {:?} vs tape {:?}",
            evals,
            tape.as_ref().err()
        );
        if let Ok(tape) = &tape {
            let mut out = vec![[0.0]; roots.len()];
            let mut refs: Vec<&mut [f64]> = out.iter_mut().map(|o| &mut o[..]).collect();
            let inputs: Vec<[f64; 1]> = p.iter().map(|x| [*x]).collect();
            let inputs: Vec<&[f64]> = inputs.iter().map(|x| &x[..]).collect();
            tape.eval_batch(&inputs, &mut refs).unwrap();
            for (e, o) in evals.iter().zip(&out) {
                let want = *e.as_ref().unwrap();
                prop_assert!(agree(o[0], want), "tape {} vs eval {want}", o[0]);
            }
        }
    }
    Ok(())
}

/// Parses `text` both ways and checks what parses; errors have their span in the text.
fn check_text(text: &str) -> Result<(), TestCaseError> {
    let start = Instant::now();
    let mut g = Graph::new();
    for result in [
        parse(&mut g, text),
        parse_with_variables(&mut g, text, &VARS),
    ] {
        match result {
            Ok(e) => check_graph(&g, &[e])?,
            Err(ExprError::Parse(p)) => {
                prop_assert!(p.span.start <= p.span.end && p.span.end <= text.len());
                prop_assert!(text.is_char_boundary(p.span.start));
                prop_assert!(text.is_char_boundary(p.span.end));
                prop_assert!(!p.to_string().is_empty());
            }
            Err(e) => prop_assert!(false, "a parse error that is not ExprError::Parse: {e}"),
        }
    }
    prop_assert!(start.elapsed() < HANG, "{:?} for {text:?}", start.elapsed());
    Ok(())
}

/// One step of building a DAG through the API; indices refer to earlier nodes (modulo).
#[derive(Clone, Debug)]
enum Op {
    Var(usize),
    Num(f64),
    Rat(i64, u32, i64, u32),
    Add(usize, usize),
    Sub(usize, usize),
    Mul(usize, usize),
    Div(usize, usize),
    Powi(usize, i32),
    Scale(f64, usize),
    Fun(usize, usize),
    Diff(usize, usize),
    Subst(usize, usize, usize),
}

fn float() -> impl Strategy<Value = f64> {
    prop_oneof![
        -3.0f64..3.0,
        prop::sample::select(vec![
            0.0,
            -0.0,
            1.0,
            f64::MAX,
            -f64::MAX,
            f64::MIN_POSITIVE,
            5e-324,
            1e308,
            1e-300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ]),
        any::<f64>(),
    ]
}

fn op() -> impl Strategy<Value = Op> {
    let i = any::<usize>;
    prop_oneof![
        (0usize..3).prop_map(Op::Var),
        float().prop_map(Op::Num),
        (-9i64..10, 0u32..3000, 1i64..10, 0u32..3000).prop_map(|(a, b, c, d)| Op::Rat(a, b, c, d)),
        (i(), i()).prop_map(|(a, b)| Op::Add(a, b)),
        (i(), i()).prop_map(|(a, b)| Op::Sub(a, b)),
        (i(), i()).prop_map(|(a, b)| Op::Mul(a, b)),
        (i(), i()).prop_map(|(a, b)| Op::Div(a, b)),
        (
            i(),
            prop_oneof![
                -4i32..6,
                Just(1 << 20),
                Just(-(1 << 20)),
                Just(i32::MIN),
                Just(i32::MAX),
                any::<i32>()
            ]
        )
            .prop_map(|(a, n)| Op::Powi(a, n)),
        (float(), i()).prop_map(|(c, a)| Op::Scale(c, a)),
        (i(), i()).prop_map(|(a, f)| Op::Fun(a, f)),
        (i(), i()).prop_map(|(a, v)| Op::Diff(a, v)),
        (i(), i(), i()).prop_map(|(a, v, b)| Op::Subst(a, v, b)),
    ]
}

/// The DAG of `ops` (each op one node, built from earlier ones).
fn build(g: &mut Graph, ops: &[Op]) -> Vec<Id> {
    let mut ids: Vec<Id> = vec![g.var("u")];
    for op in ops {
        let pick = |k: usize| ids[k % ids.len()];
        let id = match *op {
            Op::Var(k) => g.var(VARS[k]),
            Op::Num(x) => g.num(x),
            Op::Rat(a, b, c, d) => {
                // a·7^b / (c·3^d): up to about 8400 and 4800 bits.
                let n = BigInt::from(a) * BigInt::from(7).pow(b);
                let m = BigInt::from(c) * BigInt::from(3).pow(d);
                g.rat(BigRational::new(n, m))
            }
            Op::Add(a, b) => g.add(pick(a), pick(b)),
            Op::Sub(a, b) => g.sub(pick(a), pick(b)),
            Op::Mul(a, b) => g.mul(pick(a), pick(b)),
            Op::Div(a, b) => g.div(pick(a), pick(b)),
            Op::Powi(a, n) => g.powi(pick(a), n),
            Op::Scale(c, a) => g.scale(&Const::Float(c), pick(a)),
            Op::Fun(a, f) => g.fun(Func::ALL[f % Func::ALL.len()], pick(a)),
            Op::Diff(a, v) => g.diff(pick(a), VARS[v % 3]),
            Op::Subst(a, v, b) => g.substitute(pick(a), VARS[v % 3], pick(b)),
        };
        ids.push(id);
    }
    ids
}

proptest! {
    #![proptest_config(fuzz::config(256))]

    #[test]
    fn fuzz_formulas_from_the_grammar(text in formula()) {
        check_text(&text)?;
    }

    #[test]
    fn fuzz_mutated_formulas(text in formula(), edits in prop::collection::vec(edit(), 1..6)) {
        check_text(&mutate(&text, &edits))?;
    }

    #[test]
    fn fuzz_dags_built_through_the_api(ops in prop::collection::vec(op(), 1..24)) {
        let start = Instant::now();
        let mut g = Graph::new();
        let ids = build(&mut g, &ops);
        let roots = [ids[ids.len() - 1], ids[ids.len() / 2]];
        check_graph(&g, &roots)?;
        prop_assert!(start.elapsed() < HANG, "{:?}", start.elapsed());
    }
}
