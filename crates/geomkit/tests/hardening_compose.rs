//! Regressions of bad or extreme input to the single formulas of spec/composite-surfaces.md
//! (issue 21): each case once gave a formula with a coefficient that is not a finite f64
//! (printed `undefined` or `infinity`, or a 309-digit integer that C reads as inf), a NaN
//! that spread over the whole formula, or a message that did not say where; now each gives
//! a checked result or an [`Error::Overflow`] naming the patch, piece or step.

use geomkit::bezier::BezierSurface;
use geomkit::compose::{
    CompositeSurface, ExprPatch, Piecewise, RuledCurve, RuledSurface, SurfaceKind,
};
use geomkit::expr::Format;
use geomkit::Error;

/// The formula of `f` at x by the engine's tape (the f64 evaluation of the printed formula).
fn tape(p: &Piecewise, x: f64) -> f64 {
    let f = p.formula().unwrap();
    let mut out = [0.0];
    f.eval_batch(&[&[x]], &mut out).unwrap();
    out[0]
}

/// `Error::Overflow` whose place starts with `what`.
fn overflow_at(e: &Error, what: &str) -> bool {
    matches!(e, Error::Overflow { what: w, .. } if w.starts_with(what))
}

/// A bilinear patch with ±1.7e308 at its corners: its power-basis coefficient b00 - b01 -
/// b10 + b11 overflows. The error names the patch (it blamed formula (9)'s sums).
#[test]
fn patch_whose_power_coefficients_overflow_is_named() {
    let big = 1.7e308;
    let b = BezierSurface::new(vec![
        vec![vec![0.0, 0.0, -big], vec![0.0, 1.0, big]],
        vec![vec![1.0, 0.0, big], vec![1.0, 1.0, -big]],
    ])
    .unwrap();
    let e = CompositeSurface::from_bezier(vec![0.0, 1.0], vec![0.0, 1.0], &[vec![b]]).unwrap_err();
    assert!(overflow_at(&e, "patch (0, 0)"), "{e}");
    assert!(e.to_string().contains("power-basis coefficients"), "{e}");
}

/// Two constant patches at +1.7e308 and -1.7e308: the formula is fine (the second is
/// shifted onto the first), but their jump does not fit f64 and the report said `inf`
/// (serde_json wrote it as null). Now the jump is named.
#[test]
fn jump_that_overflows_is_named() {
    let flat = |z: f64| {
        BezierSurface::new(vec![
            vec![vec![0.0, 0.0, z], vec![0.0, 1.0, z]],
            vec![vec![1.0, 0.0, z], vec![1.0, 1.0, z]],
        ])
        .unwrap()
    };
    let e = CompositeSurface::from_bezier(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        &[vec![flat(1.7e308)], vec![flat(-1.7e308)]],
    )
    .unwrap_err();
    assert!(overflow_at(&e, "patches (0, 0) and (1, 0)"), "{e}");
    assert!(e.to_string().contains("u = 1"), "{e}");
}

/// Knots spanning more than f64::MAX/2 (their ramps' 2w and |x - x_i| overflow), and an
/// interval narrower than the smallest normal f64 (1/(2w) overflows): refused by name.
#[test]
fn knots_beyond_f64_are_refused() {
    let e = Piecewise::function(vec![-1.7e308, 0.0, 1.7e308], &["x", "1"]).unwrap_err();
    assert!(overflow_at(&e, "knots from -1.7e308 to 1.7e308"), "{e}");
    // Twice as wide: the knots pass (span <= f64::MAX/2), but the terms of the formula
    // (|x - x_i|/2 on the knots' interval widened by its span) could overflow.
    let wide = Piecewise::function(vec![-4e307, 0.0, 4e307], &["x/4e307", "2*x/4e307"]).unwrap();
    let e = wide.formula().unwrap_err();
    assert!(overflow_at(&e, "the single formula, piece"), "{e}");
    let e = Piecewise::function(vec![0.0, 1e-310, 1.0], &["x", "1"]).unwrap_err();
    assert!(overflow_at(&e, "knots 0 and 1"), "{e}");
    assert!(e.to_string().contains("1/(2w)"), "{e}");
    // Wide but within the limits: the formula holds finite coefficients only, and its
    // terms stay finite a span beyond the knots.
    let p = Piecewise::function(vec![-2e307, 0.0, 2e307], &["x/2e307", "2*x/2e307"]).unwrap();
    for (x, want) in [(2e307, 2.0), (-2e307, -1.0), (1e307, 1.0), (6e307, 2.0)] {
        assert!(
            (tape(&p, x) - want).abs() <= 1e-15,
            "x = {x}: {}",
            tape(&p, x)
        );
    }
}

/// A polyline from 1.7e308 to -1.7e308: the formula had the constant 2.55e308, beyond f64
/// (printed as a 309-digit integer, `inf` in C). Now the points are named.
#[test]
fn polyline_whose_differences_overflow_is_refused() {
    let e = Piecewise::polyline(
        vec![vec![0.0, 1.7e308], vec![1.0, -1.7e308], vec![2.0, 0.0]],
        None,
        false,
    )
    .unwrap_err();
    assert!(overflow_at(&e, "polyline points 0 and 1"), "{e}");
    // Values that fit but whose formula terms would not: the bound on |terms| refuses it.
    let e = Piecewise::polyline(
        vec![vec![8e307], vec![-8e307], vec![8e307], vec![-8e307]],
        None,
        false,
    )
    .unwrap()
    .formula()
    .unwrap_err();
    assert!(overflow_at(&e, "the single formula, coordinate f"), "{e}");
}

/// A ruled surface over a polygon at ±1.7e308: its formula printed coefficients of 4e307
/// whose products overflowed (formula vs evaluator: `inf`). Now refused by curve.
#[test]
fn ruled_surface_beyond_f64_is_refused() {
    let big = 1.7e308;
    let e = RuledSurface::new(
        vec![
            RuledCurve::Point([0.0, 0.0, big]),
            RuledCurve::polygon(vec![[big, 0.0, 0.0], [-big, 0.0, 0.0], [0.0, 1.0, 0.0]]).unwrap(),
            RuledCurve::Point([0.0, 0.0, -big]),
        ],
        vec![0.0, 1.0, 2.0],
        (0.0, 3.0),
    )
    .unwrap_err();
    assert!(overflow_at(&e, "curve 0 of the ruled surface"), "{e}");
    // Within the limit, the formula's terms are bounded and it builds.
    let s = RuledSurface::new(
        vec![
            RuledCurve::Point([0.0, 0.0, 1e300]),
            RuledCurve::polygon(vec![[1e300, 0.0, 0.0], [-1e300, 0.0, 0.0], [0.0, 1.0, 0.0]])
                .unwrap(),
            RuledCurve::Point([0.0, 0.0, -1e300]),
        ],
        vec![0.0, 1.0, 2.0],
        (0.0, 3.0),
    )
    .unwrap();
    let f = s.formula().unwrap();
    let mut out = [0.0; 3];
    f.eval_batch(&[&[0.5], &[1.0]], &mut out).unwrap();
    assert_eq!(out, [0.0, 0.0, 0.0]);
}

/// `sqrt(x - 0.1)` on [0.1, 0.3] and `sqrt(0.7 - x)` on [0.3, 0.7]: the f64 rounding of the
/// ramps put the square roots' arguments an ulp below 0 (a NaN at x = -99.9 and beyond
/// 1e10, and NaN at 0.3 + for 0.1 + 0.2 > 0.3). Their arguments are now clamped in a form
/// that holds in f64: the formula is finite everywhere, and equal to the piecewise
/// evaluation within what the square root makes of one rounding (sqrt(ε) near its zero).
#[test]
fn pieces_undefined_beyond_their_interval_do_not_poison_the_formula() {
    let p = Piecewise::function(vec![0.1, 0.3, 0.7], &["sqrt(x - 0.1)", "sqrt(0.7 - x)"]).unwrap();
    assert!(p.warnings().is_empty());
    let xs = [
        -1e10, -99.9, -3.0, 0.0, 0.099, 0.1, 0.2, 0.3, 0.5, 0.7, 0.701, 1.7, 17.0, 1e10,
    ];
    for x in xs {
        let (a, b) = (tape(&p, x), p.eval(x)[0]);
        assert!(a.is_finite(), "x = {x}: {a}");
        assert!((a - b).abs() <= 2e-8, "x = {x}: formula {a}, eval {b}");
    }
    // Beyond the knots: the ends held, F(x_0) = 0 and F(x_n) = sqrt(0.2) - sqrt(0.4).
    assert_eq!(p.eval(-99.9)[0], 0.0);
    assert!((tape(&p, -99.9)).abs() <= 2e-8);
    let end = 0.2f64.sqrt() - 0.4f64.sqrt();
    assert!((tape(&p, 17.0) - end).abs() <= 1e-15);
    // The clamp is written with sign(); printed in every syntax with finite numbers only.
    let maple = p.formula().unwrap().print(Format::Maple).unwrap();
    assert!(maple.contains("signum("), "{maple}");
    for fmt in Format::ALL {
        let text = p.formula().unwrap().print(fmt).unwrap();
        for bad in ["undefined", "infinity", "inf,", "NaN", "nan"] {
            assert!(!text.contains(bad), "{fmt:?}: {text}");
        }
    }
    // Pieces defined everywhere keep the paper's form.
    let q = Piecewise::function(vec![0.0, 1.0, 2.0], &["x^2", "2*x - 1"]).unwrap();
    assert!(!q
        .formula()
        .unwrap()
        .print(Format::Maple)
        .unwrap()
        .contains("signum"));
}

/// A function that jumps at its breakpoints: the convention (the paper's formula (§5)) is
/// one continuous function, later pieces shifted by the jumps before them, constant beyond
/// the knots. The formula and the evaluator agree on it at every breakpoint and outside.
#[test]
fn discontinuous_function_formula_and_eval_agree_at_breakpoints_and_outside() {
    let p = Piecewise::function(
        vec![-1.0, 0.0, 0.5, 2.0],
        &["x^2", "x + 3", "-2*x", "1/(x + 2)"],
    )
    .unwrap_err();
    // Four pieces for three intervals.
    assert!(matches!(p, Error::PatchCount { .. }), "{p}");
    let p = Piecewise::function(vec![-1.0, 0.0, 0.5, 2.0], &["x^2", "x + 3", "1/(x + 2)"]).unwrap();
    assert!(!p.continuity().is_continuous());
    // F = x^2 on [-1, 0]; x + 3 - 3 on [0, 0.5]; 1/(x + 2) - 1/2.5 + 0.5 on [0.5, 2].
    let want = |x: f64| match x {
        x if x <= -1.0 => 1.0,
        x if x <= 0.0 => x * x,
        x if x <= 0.5 => x,
        x if x <= 2.0 => 1.0 / (x + 2.0) - 0.4 + 0.5,
        _ => 0.25 - 0.4 + 0.5,
    };
    for x in [-7.0, -1.0, -0.5, 0.0, 0.25, 0.5, 1.0, 2.0, 9.0, 1e12] {
        let (e, f) = (p.eval(x)[0], tape(&p, x));
        assert!(
            (e - want(x)).abs() <= 1e-15,
            "x = {x}: eval {e}, want {}",
            want(x)
        );
        // At a breakpoint both neighbours give the one value.
        assert!(
            (f - e).abs() <= 1e-15 + 1e-16 * x.abs(),
            "x = {x}: formula {f}, eval {e}"
        );
    }
}

/// A piece that is not finite inside its interval is a warning (the function and its
/// formula are not finite there, and only there); at an end of its interval, whose value
/// enters the formula at every x, it is an error that says so.
#[test]
fn pieces_not_finite_inside_warn_at_an_end_refuse() {
    let p = Piecewise::function(vec![0.0, 1.0, 2.0], &["1/(x - 0.5)", "x"]).unwrap();
    assert_eq!(p.warnings().len(), 1);
    assert!(
        p.warnings()[0].starts_with("piece 0 coordinate f: the value inf at x = 0.5"),
        "{:?}",
        p.warnings()
    );
    // Elsewhere the formula is finite and equal to the pieces.
    assert!(
        (tape(&p, 1.5) - (1.5 - 1.0 + 2.0)).abs() <= 1e-12,
        "{}",
        tape(&p, 1.5)
    );
    let e = Piecewise::function(vec![0.0, 1.0, 2.0], &["ln(x)", "x"]).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("piece 0 coordinate f: the value -inf at x = 0"),
        "{e}"
    );
    assert!(e.to_string().contains("an end of its interval"), "{e}");
}

/// An explicit composite with square-root patches: the formula stays finite outside the
/// grid, where the ramps' rounding used to reach below the roots' zeros.
#[test]
fn partial_patches_of_a_surface_are_clamped_too() {
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    let s = CompositeSurface::from_expr(
        vec![0.0, 0.1, 0.3],
        vec![0.0, 1.0],
        vec![vec![z("sqrt(x)*y")], vec![z("sqrt(0.3 - x) + y")]],
        SurfaceKind::Explicit,
    )
    .unwrap();
    let f = s.formula().unwrap();
    for (x, y) in [
        (-99.9, 0.2),
        (-3.0, 0.5),
        (0.3, 1.0),
        (7.0, 2.0),
        (1e9, -1e9),
    ] {
        let mut out = [0.0];
        f.eval_batch(&[&[x], &[y]], &mut out).unwrap();
        let e = geomkit::geom::Surface::eval(&s, x, y)[0];
        assert!(
            out[0].is_finite() && (out[0] - e).abs() <= 2e-8,
            "({x}, {y}): {out:?} {e}"
        );
    }
}

/// A quarter circle z = sqrt(0.09 - x^2) over the cells [-0.3, 0.1] and [0.1, 0.3]: the
/// structural evaluator placed the second cell's x at 0.1 + 0.2 · 1 = 0.30000000000000004
/// at its right edge, where 0.09 - x^2 < 0 (NaN at x = 0.3 and beyond). Its arguments are
/// now clamped like the formula's: 0 there, and the formula agrees.
#[test]
fn structural_evaluator_of_partial_patches_stays_in_the_cell() {
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    let s = CompositeSurface::from_expr(
        vec![-0.3, 0.1, 0.3],
        vec![0.0, 1.0],
        vec![vec![z("sqrt(0.09 - x^2)")], vec![z("sqrt(0.09 - x^2)")]],
        SurfaceKind::Explicit,
    )
    .unwrap();
    let f = s.formula().unwrap();
    for x in [-7.0, -0.3, 0.0, 0.1, 0.2, 0.3, 0.30000000000000004, 5.0] {
        let e = geomkit::geom::Surface::eval(&s, x, 0.5)[0];
        let want = (0.09 - x.clamp(-0.3, 0.3).powi(2)).max(0.0).sqrt();
        assert!(
            (e - want).abs() <= 2e-8,
            "x = {x}: evaluator {e}, want {want}"
        );
        let mut out = [0.0];
        f.eval_batch(&[&[x], &[0.5]], &mut out).unwrap();
        assert!(
            (out[0] - want).abs() <= 2e-8,
            "x = {x}: formula {}, want {want}",
            out[0]
        );
    }
}

/// asin((x - 2.005)/0.004999999999999893) on [2, 2.01]: with the decimals exact, the
/// argument at x = 2 is -1.00000000000002 and asin is undefined; in f64 it is exactly -1
/// (the patch is finite where the construction checks it). The formulas' constant terms
/// F(x_i) (piecewise) and the edge terms r(0, t), r(s, 0), r(0, 0) of formula (9) took the
/// exact value and were NaN everywhere (found by `fuzz_formula_patches`); they now take
/// the f64 parameter, and the formulas equal the clamped arc sine.
#[test]
fn decimals_an_ulp_outside_a_function_domain_do_not_poison_the_formula() {
    let f = "asin((x - 2.005)/0.004999999999999893)";
    let want = |x: f64| ((x.clamp(2.0, 2.01) - 2.005) / 0.004999999999999893).clamp(-1.0, 1.0);
    let xs: [f64; 9] = [-3.0, 0.5, 1.0, 2.0, 2.0025, 2.005, 2.0075, 2.01, 7.0];
    // Piecewise: x on [1, 2], then the arc sine shifted onto F(2) = 2.
    let p = Piecewise::function(vec![1.0, 2.0, 2.01], &["x", f]).unwrap();
    for x in xs {
        let w = if x <= 2.0 {
            x.clamp(1.0, 2.0)
        } else {
            2.0 + want(x).asin() + std::f64::consts::FRAC_PI_2
        };
        let got = tape(&p, x);
        assert!((got - w).abs() <= 1e-6, "x = {x}: formula {got}, want {w}");
    }
    // A surface whose second column of cells holds the arc sine: its edge terms at x = 2.
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    let s = CompositeSurface::from_expr(
        vec![1.0, 2.0, 2.01],
        vec![0.0, 1.0, 2.0],
        vec![
            vec![z("-pi/2 + y"), z("-pi/2 + y")],
            vec![z(&format!("{f} + y")), z(&format!("{f} + y"))],
        ],
        SurfaceKind::Explicit,
    )
    .unwrap();
    let formula = s.formula().unwrap();
    for x in xs {
        for y in [-1.0f64, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0] {
            let w = want(x).asin() + y.clamp(0.0, 2.0);
            let mut out = [0.0];
            formula.eval_batch(&[&[x], &[y]], &mut out).unwrap();
            let e = geomkit::geom::Surface::eval(&s, x, y)[0];
            assert!(
                (out[0] - w).abs() <= 1e-6 && (e - w).abs() <= 1e-6,
                "({x}, {y}): formula {}, evaluator {e}, want {w}",
                out[0]
            );
        }
    }
}
