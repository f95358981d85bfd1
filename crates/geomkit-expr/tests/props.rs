//! Property tests: random expressions evaluate equal through `Graph::eval`, the `Tape`, and
//! a round trip through the Maple printer and the parser (`parse(print(e))`).

use geomkit_expr::{parse, Format, Graph, Id, Tape};
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum E {
    U,
    V,
    Int(i8),
    Float(f64),
    Add(Box<E>, Box<E>),
    Sub(Box<E>, Box<E>),
    Mul(Box<E>, Box<E>),
    Div(Box<E>, Box<E>),
    Pow(Box<E>, i8),
    Neg(Box<E>),
    Abs(Box<E>),
    Sin(Box<E>),
    Atan(Box<E>),
    SqrtAbs(Box<E>),
}

fn expr() -> impl Strategy<Value = E> {
    let leaf = prop_oneof![
        Just(E::U),
        Just(E::V),
        (-5i8..6).prop_map(E::Int),
        (-3.0f64..3.0).prop_map(E::Float),
    ];
    leaf.prop_recursive(5, 40, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| E::Add(a.into(), b.into())),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| E::Sub(a.into(), b.into())),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| E::Mul(a.into(), b.into())),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| E::Div(a.into(), b.into())),
            (inner.clone(), -3i8..5).prop_map(|(a, n)| E::Pow(a.into(), n)),
            inner.clone().prop_map(|a| E::Neg(a.into())),
            inner.clone().prop_map(|a| E::Abs(a.into())),
            inner.clone().prop_map(|a| E::Sin(a.into())),
            inner.clone().prop_map(|a| E::Atan(a.into())),
            inner.prop_map(|a| E::SqrtAbs(a.into())),
        ]
    })
}

fn build(g: &mut Graph, e: &E) -> Id {
    match e {
        E::U => g.var("u"),
        E::V => g.var("v"),
        E::Int(n) => g.int(*n as i64),
        E::Float(x) => g.num(*x),
        E::Add(a, b) => {
            let (a, b) = (build(g, a), build(g, b));
            g.add(a, b)
        }
        E::Sub(a, b) => {
            let (a, b) = (build(g, a), build(g, b));
            g.sub(a, b)
        }
        E::Mul(a, b) => {
            let (a, b) = (build(g, a), build(g, b));
            g.mul(a, b)
        }
        E::Div(a, b) => {
            let (a, b) = (build(g, a), build(g, b));
            g.div(a, b)
        }
        E::Pow(a, n) => {
            let a = build(g, a);
            g.powi(a, *n as i32)
        }
        E::Neg(a) => {
            let a = build(g, a);
            g.neg(a)
        }
        E::Abs(a) => {
            let a = build(g, a);
            g.abs(a)
        }
        E::Sin(a) => {
            let a = build(g, a);
            g.sin(a)
        }
        E::Atan(a) => {
            let a = build(g, a);
            g.atan(a)
        }
        E::SqrtAbs(a) => {
            let a = build(g, a);
            let a = g.abs(a);
            g.sqrt(a)
        }
    }
}

/// Equal within rounding: both non-finite alike, or close relative to the magnitude.
fn close(a: f64, b: f64) -> bool {
    if !a.is_finite() || !b.is_finite() {
        return a.is_nan() == b.is_nan() || a.abs() > 1e12 || b.abs() > 1e12;
    }
    (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn eval_tape_and_printed_round_trip_agree(e in expr(), u in -2.0f64..2.0, v in -2.0f64..2.0) {
        let mut g = Graph::new();
        let id = build(&mut g, &e);
        let at = [("u", u), ("v", v)];
        let Ok(want) = g.eval(id, &at) else {
            // Division by an exact zero: the tape refuses it too.
            prop_assert!(Tape::new(&g, &[id], &["u", "v"]).is_err());
            return Ok(());
        };
        let tape = Tape::new(&g, &[id], &["u", "v"]).unwrap();
        let mut out = [0.0; 1];
        tape.eval_batch(&[&[u], &[v]], &mut [&mut out]).unwrap();
        prop_assert!(close(out[0], want), "tape {} vs eval {}", out[0], want);
        for f in [Format::Maple, Format::Mathematica] {
            let text = g.print(id, f).unwrap();
            let text = if f == Format::Mathematica {
                // Mathematica's brackets and float exponents back to the parser's syntax.
                text.replace('[', "(")
                    .replace(']', ")")
                    .replace("*^", "e")
                    .replace("ArcTan(", "atan(")
                    .replace("Sin(", "sin(")
                    .replace("Sqrt(", "sqrt(")
            } else {
                text
            };
            let mut g2 = Graph::new();
            let back = parse(&mut g2, &text).unwrap();
            let again = g2.eval(back, &at).unwrap();
            prop_assert!(close(again, want), "{f:?} `{text}`: {again} vs {want}");
        }
    }
}

/// A divisor that folds to 0 without being the constant 0 divides as f64 in the tape, as in
/// `Graph::eval` (found by the round-trip property: the tape used to refuse it).
#[test]
fn folded_zero_divisors_divide_alike() {
    let mut g = Graph::new();
    let id = parse(&mut g, "sin(u - v) / ((u - u) / sin(-1))").unwrap();
    let tape = Tape::new(&g, &[id], &["u", "v"]).unwrap();
    for (u, v) in [(0.0, 0.0), (0.5, -0.25)] {
        let want = g.eval(id, &[("u", u), ("v", v)]).unwrap();
        let mut out = [0.0; 1];
        tape.eval_batch(&[&[u], &[v]], &mut [&mut out]).unwrap();
        assert!(
            close(out[0], want),
            "({u}, {v}): tape {} vs eval {want}",
            out[0]
        );
    }
    let zero = parse(&mut g, "u / 0").unwrap();
    assert!(Tape::new(&g, &[zero], &["u"]).is_err());
}
