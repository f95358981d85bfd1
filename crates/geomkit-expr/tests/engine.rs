//! Simplification, exactness, substitute, diff, eval and errors of the expression engine.

use geomkit_expr::{fixtures, parse, ExprError, Format, Graph, Id, ParseErrorKind, Tape};

fn p(g: &mut Graph, s: &str) -> Id {
    parse(g, s).unwrap()
}

fn pp(g: &mut Graph, s: &str, f: Format) -> String {
    let e = p(g, s);
    g.print(e, f).unwrap()
}

#[test]
fn hash_consing_shares_equal_expressions() {
    let mut g = Graph::new();
    let a = p(&mut g, "abs(u - 1)*v + 3");
    let b = p(&mut g, "3 + v*abs(-1 + u)");
    assert_eq!(a, b);
    // |1 - u| is |u - 1|: the sign is normalized.
    assert_eq!(p(&mut g, "abs(1 - u)"), p(&mut g, "abs(u - 1)"));
    let u = g.var("u");
    assert_eq!(g.var("u"), u);
    let len = g.len();
    p(&mut g, "abs(u - 1)*v + 3");
    assert_eq!(g.len(), len, "rebuilding adds no node");
}

#[test]
fn constant_folding_is_exact() {
    let mut g = Graph::new();
    assert_eq!(pp(&mut g, "1/3 + 2/3", Format::Maple), "1");
    assert_eq!(pp(&mut g, "0.1 + 0.2 - 0.3", Format::Maple), "0");
    assert_eq!(pp(&mut g, "sqrt(9/4) + abs(-2)^3", Format::Maple), "19/2");
    assert_eq!(pp(&mut g, "(2/3)^-2", Format::Sympy), "Rational(9, 4)");
    // f64 constants fold in f64.
    let a = g.num(0.1);
    let b = g.num(0.2);
    let s = g.add(a, b);
    assert_eq!(g.as_const(s).unwrap().to_f64(), 0.1 + 0.2);
}

#[test]
fn identities_fold_only_where_safe() {
    let mut g = Graph::new();
    let u = g.var("u");
    assert_eq!(p(&mut g, "u + 0"), u);
    assert_eq!(p(&mut g, "1*u"), u);
    assert_eq!(p(&mut g, "-(-u)"), u);
    assert_eq!(pp(&mut g, "u*u*u/u^2*2", Format::Maple), "2*u^3/u^2");
    assert_eq!(pp(&mut g, "abs(u) - abs(u)", Format::Maple), "0");
    assert_eq!(pp(&mut g, "0*sin(u)", Format::Maple), "0");
    // 0·(1/u) and 1/u − 1/u are NaN at u = 0: not folded.
    let e = p(&mut g, "0/u");
    assert!(g.eval(e, &[("u", 0.0)]).unwrap().is_nan());
    let e = p(&mut g, "1/u - 1/u");
    assert!(g.eval(e, &[("u", 0.0)]).unwrap().is_nan());
    assert_eq!(g.eval(e, &[("u", 2.0)]).unwrap(), 0.0);
    // Like terms are collected, sums stay flat.
    assert_eq!(
        pp(&mut g, "2*u + 3*u - (u - v) + (v + 1) - 1", Format::Maple),
        "4*u + 2*v"
    );
}

#[test]
fn ramp_is_exactly_zero_and_one_at_its_knots() {
    let mut g = Graph::new();
    let e = p(&mut g, "(w + abs(t - a) - abs(t - a - w)) / (2*w)");
    let a = p(&mut g, "3/7");
    let w = p(&mut g, "5/11");
    let e = g.substitute(e, "a", a);
    let e = g.substitute(e, "w", w);
    let at_a = g.substitute(e, "t", a);
    let end = p(&mut g, "3/7 + 5/11");
    let at_end = g.substitute(e, "t", end);
    assert_eq!(g.print(at_a, Format::Sympy).unwrap(), "0");
    assert_eq!(g.print(at_end, Format::Sympy).unwrap(), "1");
    assert!((g.eval(e, &[("t", 3.0 / 7.0 + 0.5 * 5.0 / 11.0)]).unwrap() - 0.5).abs() < 1e-15);
}

#[test]
fn cube_is_the_papers_formula() {
    let mut g = Graph::new();
    let [x, y, z] = fixtures::cube(&mut g);
    // Every point is on the cube surface: max(|x|, |y|, |z|) = 1.
    for i in 0..=80 {
        for j in 0..=60 {
            let (u, v) = (i as f64 * 0.05, j as f64 * 0.05);
            let at = [("u", u), ("v", v)];
            let (a, b, c) = (
                g.eval(x, &at).unwrap(),
                g.eval(y, &at).unwrap(),
                g.eval(z, &at).unwrap(),
            );
            let m = a.abs().max(b.abs()).max(c.abs());
            assert!((m - 1.0).abs() <= 1e-15, "({u}, {v}) -> ({a}, {b}, {c})");
        }
    }
    // The precedence case that breaks SymPy 1.14's rust_code: true value 0.
    assert_eq!(g.eval(x, &[("u", 0.5), ("v", 1.5)]).unwrap(), 0.0);
    assert_eq!(
        g.print(z, Format::Maple).unwrap(),
        "-abs(v - 1) + abs(v - 2)"
    );
}

#[test]
fn substitute_and_diff() {
    let mut g = Graph::new();
    let e = p(
        &mut g,
        "sin(u)*v^3 + abs(u - v) + sqrt(u^2 + 1) + exp(2*u)/v + atan(u*v) + ln(v)",
    );
    let du = g.diff(e, "u");
    let dv = g.diff(e, "v");
    for &(u, v) in &[(0.3, 1.7), (-1.2, 0.4), (2.0, 3.5)] {
        let f = |g: &Graph, e, u: f64, v: f64| g.eval(e, &[("u", u), ("v", v)]).unwrap();
        let h = 1e-6;
        let fd_u = (f(&g, e, u + h, v) - f(&g, e, u - h, v)) / (2.0 * h);
        let fd_v = (f(&g, e, u, v + h) - f(&g, e, u, v - h)) / (2.0 * h);
        assert!((f(&g, du, u, v) - fd_u).abs() < 1e-6 * fd_u.abs().max(1.0));
        assert!((f(&g, dv, u, v) - fd_v).abs() < 1e-6 * fd_v.abs().max(1.0));
    }
    // abs' = sign, exactly 0 at the kink.
    let a = p(&mut g, "abs(u - 1)");
    let da = g.diff(a, "u");
    assert_eq!(g.print(da, Format::Sympy).unwrap(), "sign(u - 1)");
    assert_eq!(g.eval(da, &[("u", 1.0)]).unwrap(), 0.0);
    // substitute keeps sharing and simplifies.
    let two = g.int(2);
    let s = g.substitute(e, "u", two);
    let v_only = g.variables(&[s]);
    assert_eq!(v_only, vec!["v".to_string()]);
    assert!(
        (g.eval(s, &[("v", 1.5)]).unwrap() - g.eval(e, &[("u", 2.0), ("v", 1.5)]).unwrap()).abs()
            < 1e-14
    );
}

#[test]
fn op_count_counts_shared_nodes_once() {
    let mut g = Graph::new();
    let a = p(&mut g, "abs(u - 1)");
    let e = p(&mut g, "abs(u - 1)*v + abs(u - 1)");
    // u - 1 (1), abs (1), *v (1), + (1)
    assert_eq!(g.op_count(&[e]), 4);
    assert_eq!(g.op_count(&[a, e]), 4);
}

#[test]
fn errors_name_what_and_where() {
    let mut g = Graph::new();
    let err = parse(&mut g, "2*(u + 1").unwrap_err();
    assert_eq!(
        err.to_string(),
        "parse error at byte 8: expected `)`, found end of input"
    );
    let span = |err: ExprError| match err {
        ExprError::Parse(e) => (e.span.clone(), e.kind.clone()),
        e => panic!("{e}"),
    };
    let open = ParseErrorKind::UnclosedParen {
        open: 2,
        function: None,
    };
    assert_eq!(span(err), (8..8, open));
    let err = parse(&mut g, "foo(u)").unwrap_err();
    assert_eq!(span(err).0, 0..3);
    let (at, kind) = span(parse(&mut g, "u^v").unwrap_err());
    assert_eq!(at, 1..3);
    assert!(
        matches!(kind, ParseErrorKind::BadExponent { .. }),
        "{kind:?}"
    );
    let (_, kind) = span(parse(&mut g, "u^1.5").unwrap_err());
    assert!(
        matches!(kind, ParseErrorKind::BadExponent { .. }),
        "{kind:?}"
    );
    assert_eq!(pp(&mut g, "u^(1/2)", Format::Maple), "sqrt(u)");
    let deep = format!("{}u{}", "(".repeat(1000), ")".repeat(1000));
    let (_, kind) = span(parse(&mut g, &deep).unwrap_err());
    assert_eq!(kind, ParseErrorKind::TooDeep { max: 200 });
    let e = p(&mut g, "u + w");
    assert_eq!(
        g.eval(e, &[("u", 1.0)]),
        Err(ExprError::UnknownVariable { name: "w".into() })
    );
    assert!(matches!(
        Tape::new(&g, &[e], &["u"]),
        Err(ExprError::UnknownVariable { .. })
    ));
    let e = p(&mut g, "u/0");
    assert_eq!(g.eval(e, &[("u", 1.0)]), Err(ExprError::DivisionByZero));
    assert_eq!(
        Tape::new(&g, &[e], &["u"]).unwrap_err(),
        ExprError::DivisionByZero
    );
    let nan = g.num(f64::NAN);
    let u = g.var("u");
    let e = g.add(u, nan);
    assert!(matches!(
        g.eval(e, &[("u", 1.0)]),
        Err(ExprError::NonFiniteConstant { .. })
    ));
    let tape = Tape::new(&g, &[u], &["u"]).unwrap();
    let err = tape
        .eval_batch(&[&[1.0, 2.0]], &mut [&mut [0.0; 3]])
        .unwrap_err();
    assert!(
        matches!(
            err,
            ExprError::Shape {
                got: 3,
                expected: 2,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn composite_formula_equals_its_patches() {
    let mut g = Graph::new();
    let (n, m) = (3, 4);
    let coef = fixtures::random_coef(7, (n, m), (3, 3), 3);
    let uk = fixtures::uniform_knots(n);
    let vk = fixtures::uniform_knots(m);
    let roots = fixtures::composite_poly(&mut g, &uk, &vk, (3, 3), 3, &coef);
    let ukf: Vec<f64> = (0..=n).map(|i| i as f64).collect();
    let vkf: Vec<f64> = (0..=m).map(|i| i as f64).collect();
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    let pts: Vec<(f64, f64)> = (0..=4 * n + 2)
        .flat_map(|i| {
            (0..=4 * m + 2).map(move |j| (i as f64 * 0.25 - 0.25, j as f64 * 0.25 - 0.25))
        })
        .collect();
    let us: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let vs: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let mut out = vec![vec![0.0; pts.len()]; 3];
    {
        let mut o: Vec<&mut [f64]> = out.iter_mut().map(|v| v.as_mut_slice()).collect();
        tape.eval_batch(&[&us, &vs], &mut o).unwrap();
    }
    for (k, &(u, v)) in pts.iter().enumerate() {
        let want = fixtures::composite_poly_literal(&ukf, &vkf, (3, 3), 3, &coef, (u, v));
        for c in 0..3 {
            let at = [("u", u), ("v", v)];
            assert!(
                (g.eval(roots[c], &at).unwrap() - want[c]).abs() < 1e-12,
                "({u}, {v})"
            );
            assert!((out[c][k] - want[c]).abs() < 1e-12, "({u}, {v})");
        }
    }
}

#[test]
fn bicubic_composite_costs_at_most_75_operations_per_patch() {
    let mut g = Graph::new();
    let n = 10;
    let coef = fixtures::random_coef(3, (n, n), (3, 3), 3);
    let k = fixtures::uniform_knots(n);
    let roots = fixtures::composite_poly(&mut g, &k, &k, (3, 3), 3, &coef);
    let per_patch = g.op_count(&roots) as f64 / (n * n) as f64;
    assert!(
        per_patch <= 75.0,
        "{per_patch} operations per bicubic patch"
    );
}

/// The tape's sums (chains of up to four terms per instruction), fused pairs, and roots
/// that are written in place, copied (read again later, or the same as another root),
/// variables or constants, over three blocks and a ragged tail: every value exact (small
/// integers), against the same sums in integer arithmetic.
#[test]
fn tape_roots_sums_and_fused_pairs_are_exact() {
    let mut g = Graph::new();
    // Nine terms: chained over three sums; abs(u - i) fuses into one instruction.
    let s = p(
        &mut g,
        "5 + abs(u) - 2*abs(u-1) + 3*abs(u-2) - abs(u-3) + abs(u-4) + 4*abs(u-5) - abs(u-6) \
         + 2*v - 3*abs(v-2)",
    );
    let prod = p(&mut g, "(u*v)/2"); // u·v then ·0.5: fused
    let later = g.add(s, prod); // reads root s after it is complete
    let u = p(&mut g, "u");
    let seven = p(&mut g, "7");
    let roots = [s, prod, u, seven, s, later];
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    let n = 2 * geomkit_expr::tape::LANES + 37;
    let us: Vec<f64> = (0..n).map(|i| (i % 13) as f64 - 6.0).collect();
    let vs: Vec<f64> = (0..n).map(|i| (i % 7) as f64 * 2.0).collect();
    let mut out = vec![vec![f64::NAN; n]; roots.len()];
    let mut rows: Vec<&mut [f64]> = out.iter_mut().map(|r| r.as_mut_slice()).collect();
    tape.eval_batch(&[&us, &vs], &mut rows).unwrap();
    for i in 0..n {
        let (a, b) = ((i % 13) as i64 - 6, (i % 7) as i64 * 2);
        let k = [1, -2, 3, -1, 1, 4, -1];
        let want_s = 5 + (0..7).map(|j| k[j] * (a - j as i64).abs()).sum::<i64>() + 2 * b
            - 3 * (b - 2).abs();
        let want_prod = a * b; // b is even: a·b/2 is exact
        let want = [
            want_s as f64,
            want_prod as f64 / 2.0,
            a as f64,
            7.0,
            want_s as f64,
            want_s as f64 + want_prod as f64 / 2.0,
        ];
        for (r, w) in want.iter().enumerate() {
            assert_eq!(out[r][i], *w, "root {r} at point {i}");
        }
    }
}

/// Sums of absolute values of one variable (the papers' ramps), each one instruction that
/// reads the variable alone, with inner coefficients, signs, a constant, an absolute
/// value that is also a root of its own, and sums too long for one instruction: exact
/// integers against integer arithmetic.
#[test]
fn tape_sums_of_absolute_values_are_exact() {
    let mut g = Graph::new();
    let texts = [
        "abs(2*u - 3) - 3*abs(u + 1) + abs(-u + 2) + 4",
        "abs(u) + abs(u-1) - abs(u-2)",
        "abs(u-1)",
        "abs(u) + abs(u-1) + abs(u-2) + abs(u-3) - 2*abs(u-4)",
        "abs(v - 1) - abs(u - 1)",
        "abs(u*v - 1) + abs(u*v + 2) - abs(u*v - 3)",
        "abs(u*u + 1) - abs(v + 3) + abs(u*u - 2)",
    ];
    let roots: Vec<Id> = texts.iter().map(|t| p(&mut g, t)).collect();
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    let n = geomkit_expr::tape::LANES + 5;
    let us: Vec<f64> = (0..n).map(|i| (i % 11) as f64 - 5.0).collect();
    let vs: Vec<f64> = (0..n).map(|i| (i % 3) as f64).collect();
    let mut out = vec![vec![f64::NAN; n]; roots.len()];
    let mut rows: Vec<&mut [f64]> = out.iter_mut().map(|r| r.as_mut_slice()).collect();
    tape.eval_batch(&[&us, &vs], &mut rows).unwrap();
    for i in 0..n {
        let (u, v) = ((i % 11) as i64 - 5, (i % 3) as i64);
        let want = [
            (2 * u - 3).abs() - 3 * (u + 1).abs() + (2 - u).abs() + 4,
            u.abs() + (u - 1).abs() - (u - 2).abs(),
            (u - 1).abs(),
            u.abs() + (u - 1).abs() + (u - 2).abs() + (u - 3).abs() - 2 * (u - 4).abs(),
            (v - 1).abs() - (u - 1).abs(),
            (u * v - 1).abs() + (u * v + 2).abs() - (u * v - 3).abs(),
            (u * u + 1).abs() - (v + 3).abs() + (u * u - 2).abs(),
        ];
        for (r, w) in want.iter().enumerate() {
            assert_eq!(out[r][i], *w as f64, "{} at u = {u}, v = {v}", texts[r]);
        }
    }
}

/// Programs as short as the formulas allow: the paper's cube in 6 instructions (each of
/// its four sums of |t − a| one instruction reading t alone, each scaled product one),
/// where an instruction per operation of the formula is 32.
#[test]
fn tape_of_the_cube_is_six_instructions() {
    let mut g = Graph::new();
    let roots = fixtures::cube(&mut g);
    let tape = Tape::new(&g, &roots, &["u", "v"]).unwrap();
    assert_eq!(tape.len(), 6);
}
