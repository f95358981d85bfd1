//! Composite surfaces of formula patches (spec/composite-surfaces.md §3-4): the printed
//! formula (9)/(11) (through the engine's tape), the literal formula in f64 and the
//! structural evaluator agree on dense grids including every knot line and points outside,
//! for smooth surfaces split into cells and for patches that do not meet (shifted by (9)).

mod common;

use common::{disagreement, Rng};
use geomkit::compose::{CompositeSurface, ExprPatch, PolyPatch, SurfaceKind};
use geomkit::Error;
use proptest::prelude::*;

fn random_knots(rng: &mut Rng, n: usize) -> Vec<f64> {
    let mut k = vec![rng.uniform() * 3.0 - 1.0];
    for _ in 0..n {
        let last = k[k.len() - 1];
        k.push(last + 0.6 + rng.uniform() * 0.5);
    }
    k
}

/// Every knot, quarter points of every cell, and points outside.
fn dense(knots: &[f64]) -> Vec<f64> {
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    let mut xs = vec![a - 1.0, b + 0.5, b];
    for w in knots.windows(2) {
        for f in [0.0, 0.25, 0.5, 0.75] {
            xs.push(w[0] + f * (w[1] - w[0]));
        }
    }
    xs
}

fn patch(x: &str, y: &str, z: &str) -> ExprPatch {
    ExprPatch::parse(&[("x", x), ("y", y), ("z", z)], &["u", "v"], None).unwrap()
}

#[test]
fn smooth_surface_split_into_cells_is_reproduced() {
    let mut rng = Rng(7);
    let (uk, vk) = (random_knots(&mut rng, 5), random_knots(&mut rng, 4));
    let rows: Vec<Vec<ExprPatch>> = (0..5)
        .map(|_| {
            (0..4)
                .map(|_| patch("u", "v", "sin(u)*cos(2*v) + exp(u/3)"))
                .collect()
        })
        .collect();
    let s =
        CompositeSurface::from_expr(uk.clone(), vk.clone(), rows, SurfaceKind::Parametric).unwrap();
    assert!(
        s.continuity().is_continuous(),
        "{:?}",
        s.continuity().max_jump
    );
    let (worst, scale) = disagreement(&s, &dense(&uk), &dense(&vk));
    assert!(worst <= 1e-12 * scale, "{worst:e}");
    // Inside the domain the composite is the surface itself.
    for (u, v) in [(uk[0] + 0.3, vk[0] + 0.2), (uk[2], vk[1]), (uk[5], vk[4])] {
        let p = s.eval(u, v);
        let z = u.sin() * (2.0 * v).cos() + (u / 3.0).exp();
        assert!((p[0] - u).abs() < 1e-14 && (p[1] - v).abs() < 1e-14);
        assert!((p[2] - z).abs() < 1e-14, "{u} {v}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Random (discontinuous) biquadratic patches as formulas, n, m from 1 to 4: the formula
    /// shifts them by (9); formula patches agree with the same polynomials as PolyPatch.
    #[test]
    fn shifted_formula_patches_match_the_formula_and_the_polynomial_path(
        n in 1usize..=4, m in 1usize..=4, seed in 1u64..u64::MAX
    ) {
        let mut rng = Rng(seed | 1);
        let (uk, vk) = (random_knots(&mut rng, n), random_knots(&mut rng, m));
        let polys: Vec<Vec<PolyPatch>> = (0..n)
            .map(|_| (0..m).map(|_| {
                let c = (0..27).map(|_| rng.uniform() * 4.0 - 2.0).collect();
                PolyPatch::new((2, 2), 3, c).unwrap()
            }).collect())
            .collect();
        let exprs: Vec<Vec<ExprPatch>> = polys
            .iter()
            .map(|r| r.iter().map(|p| ExprPatch::from_poly(p, &["x", "y", "z"], ["u", "v"]).unwrap()).collect())
            .collect();
        let s = CompositeSurface::from_expr(uk.clone(), vk.clone(), exprs, SurfaceKind::Parametric).unwrap();
        let poly = CompositeSurface::from_poly(uk.clone(), vk.clone(), polys, SurfaceKind::Parametric).unwrap();
        if n * m > 1 {
            prop_assert!(!s.continuity().is_continuous());
        }
        prop_assert!((s.continuity().max_jump - poly.continuity().max_jump).abs() < 1e-12);
        let (us, vs) = (dense(&uk), dense(&vk));
        let (worst, scale) = disagreement(&s, &us, &vs);
        prop_assert!(worst <= 1e-12 * scale, "{worst:e} at scale {scale}");
        for &u in &us {
            for &v in &vs {
                let (a, b) = (s.eval(u, v), poly.eval(u, v));
                for c in 0..3 {
                    prop_assert!((a[c] - b[c]).abs() <= 1e-12 * scale);
                }
            }
        }
    }
}

#[test]
fn own_domains_are_mapped_onto_the_cells() {
    // A quarter cylinder given on its own domain (angle, height), placed on the cell [1, 2] ×
    // [0, 1], next to a plane on [0, 1] × [0, 1] that meets it along u = 1.
    let plane =
        ExprPatch::parse(&[("x", "1"), ("y", "u - 1"), ("z", "v")], &["u", "v"], None).unwrap();
    let cyl = ExprPatch::parse(
        &[("x", "cos(u)"), ("y", "sin(u)"), ("z", "v/10")],
        &["u", "v"],
        Some(vec![(0.0, std::f64::consts::FRAC_PI_2), (0.0, 10.0)]),
    )
    .unwrap();
    let s = CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![plane], vec![cyl]],
        SurfaceKind::Parametric,
    )
    .unwrap();
    assert!(
        s.continuity().is_continuous(),
        "{}",
        s.continuity().max_jump
    );
    let p = s.eval(1.5, 0.5);
    let a = std::f64::consts::FRAC_PI_4;
    assert!((p[0] - a.cos()).abs() < 1e-15 && (p[1] - a.sin()).abs() < 1e-15);
    assert!((p[2] - 0.5).abs() < 1e-15);
    let (worst, scale) = disagreement(&s, &dense(&[0.0, 1.0, 2.0]), &dense(&[0.0, 1.0]));
    assert!(worst <= 1e-12 * scale, "{worst:e}");
    let printed = s
        .formula()
        .unwrap()
        .print(geomkit::expr::Format::Maple)
        .unwrap();
    assert!(
        printed.contains("cos(") && !printed.contains("Pi"),
        "{printed}"
    );
}

#[test]
fn explicit_patches_that_jump_are_shifted_by_formula_11() {
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None).unwrap();
    // z = x y on the left cells, x y + 3 on the right: (11) keeps the left value and
    // shifts the right cells down by 3; in y the cells meet.
    let s = CompositeSurface::from_expr(
        vec![0.0, 0.5, 1.0],
        vec![0.0, 0.25, 1.0],
        vec![vec![z("x*y"), z("x*y")], vec![z("x*y + 3"), z("x*y + 3")]],
        SurfaceKind::Explicit,
    )
    .unwrap();
    let r = s.continuity();
    assert!(!r.is_continuous());
    assert!((r.max_jump - 3.0).abs() < 1e-15);
    assert_eq!(
        r.jumps.iter().filter(|j| j.max_jump > r.tolerance).count(),
        2
    );
    for (x, y) in [(0.75f64, 0.5f64), (0.5, 0.25), (1.0, 1.0), (2.0, -1.0)] {
        let want = x.clamp(0.0, 1.0) * y.clamp(0.0, 1.0);
        assert!((s.eval(x, y)[0] - want).abs() < 1e-15, "{x} {y}");
        assert!((s.eval_formula(x, y)[0] - want).abs() < 1e-15, "{x} {y}");
    }
    let (worst, scale) = disagreement(&s, &dense(&[0.0, 0.5, 1.0]), &dense(&[0.0, 0.25, 1.0]));
    assert!(worst <= 1e-12 * scale, "{worst:e}");
    assert!(s
        .formula()
        .unwrap()
        .print(geomkit::expr::Format::Maple)
        .unwrap()
        .starts_with("z := (x, y) -> "));
}

#[test]
fn bad_formula_patches_are_errors() {
    let e =
        ExprPatch::parse(&[("x", "u"), ("y", "v"), ("z", "sin(u")], &["u", "v"], None).unwrap_err();
    assert_eq!(
        e.to_string(),
        "coordinate z: parse error at byte 5: expected `)` closing `sin(`, found end of input"
    );
    let ok = || patch("u", "v", "0");
    let e = CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![ok()]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            Error::PatchCount {
                expected: 2,
                got: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = CompositeSurface::from_expr(
        vec![0.0, 1.0],
        vec![0.0, 1.0],
        vec![vec![patch("u", "v", "sqrt(u - 1/2)")]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("patch (0, 0) coordinate z: the value NaN at u = 0, v = 0"),
        "{e}"
    );
    let flat = ExprPatch::parse(&[("x", "u"), ("y", "v")], &["u", "v"], None).unwrap();
    let e = CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![ok()], vec![flat]],
        SurfaceKind::Parametric,
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::DimensionMismatch { index: 1, .. }),
        "{e}"
    );
    let e = CompositeSurface::from_expr(
        vec![0.0, 1.0],
        vec![0.0, 1.0],
        vec![vec![ok()]],
        SurfaceKind::Explicit,
    )
    .unwrap_err();
    assert!(matches!(e, Error::WrongDimension { .. }), "{e}");
}

#[test]
fn formula_curves_in_ruled_surfaces_match_the_built_in_circle() {
    use geomkit::compose::{RuledCurve, RuledSurface};
    let tau = std::f64::consts::TAU;
    let build = |c: RuledCurve| {
        RuledSurface::new(
            vec![
                RuledCurve::Point([0.0, 0.0, 2.0]),
                c,
                RuledCurve::Point([0.0, 0.0, 0.0]),
            ],
            vec![0.0, 1.0, 2.5],
            (0.0, 1.0),
        )
        .unwrap()
    };
    let circle = build(RuledCurve::Circle {
        center: [0.0, 0.0, 0.5],
        radius: 1.5,
    });
    let formula =
        build(RuledCurve::formula(["1.5*cos(t)", "1.5*sin(t)", "1/2"], (0.0, tau)).unwrap());
    let f = formula.formula().unwrap();
    let (us, vs) = (dense(&[0.0, 0.5, 1.0]), dense(&[0.0, 1.0, 2.5]));
    let (pu, pv): (Vec<f64>, Vec<f64>) = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .unzip();
    let mut printed = vec![0.0; pu.len() * 3];
    f.eval_batch(&[&pu, &pv], &mut printed).unwrap();
    for (k, p) in printed.chunks_exact(3).enumerate() {
        let (a, b) = (circle.eval(pu[k], pv[k]), formula.eval(pu[k], pv[k]));
        let lit = formula.eval_formula(pu[k], pv[k]);
        for c in 0..3 {
            assert!((a[c] - b[c]).abs() < 1e-14, "{} {}", pu[k], pv[k]);
            assert!((p[c] - b[c]).abs() < 1e-14 && (lit[c] - b[c]).abs() < 1e-14);
        }
    }
    assert!(RuledCurve::formula(["t", "t", "t"], (1.0, 0.0)).is_err());
    let e = RuledCurve::formula(["t", "sqrt(t)", "0"], (-1.0, 1.0)).unwrap_err();
    assert!(
        e.to_string()
            .contains("coordinate y: the value NaN at t = -1"),
        "{e}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// Random discontinuous quadratic pieces: the printed formula, the literal formula (§5)
    /// and the structural evaluator agree at every knot, inside and outside.
    #[test]
    fn piecewise_formula_equals_structural(n in 1usize..=12, seed in 1u64..u64::MAX) {
        use geomkit::compose::Piecewise;
        let mut rng = Rng(seed | 1);
        let knots = random_knots(&mut rng, n);
        let texts: Vec<String> = (0..n)
            .map(|_| format!("{} + {}*x - {}*x^2", rng.uniform(), rng.uniform(), rng.uniform()))
            .collect();
        let refs: Vec<&str> = texts.iter().map(String::as_str).collect();
        let p = Piecewise::function(knots.clone(), &refs).unwrap();
        if n > 1 {
            prop_assert!(!p.continuity().is_continuous());
        }
        let xs = dense(&knots);
        let f = p.formula().unwrap();
        let mut printed = vec![0.0; xs.len()];
        f.eval_batch(&[&xs], &mut printed).unwrap();
        let scale = printed.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (k, &x) in xs.iter().enumerate() {
            let (a, b) = (p.eval(x)[0], p.eval_formula(x)[0]);
            prop_assert!((a - b).abs() <= 1e-12 * scale && (a - printed[k]).abs() <= 1e-12 * scale,
                "{x}: {a} {b} {}", printed[k]);
        }
    }
}

/// B-spline curves as one formula (`Piecewise::from_bspline`): interpolated cubics (open,
/// periodic, chord-length knots) and random splines of degrees 1, 2 and 5 with repeated
/// knots (empty spans skipped): the structural evaluator, the literal formula and the
/// printed formula equal the curve on its domain; interpolating cubics are continuous.
#[test]
fn bspline_curves_as_one_formula() {
    use geomkit::bspline::{
        interpolate_curve, BsplineCurve, EndCondition, InterpolationOptions, Parametrization,
    };
    use geomkit::compose::Piecewise;
    use geomkit::expr::Format;
    use geomkit::geom::Curve;
    let mut rng = Rng(99);
    let mut curves: Vec<(String, BsplineCurve)> = Vec::new();
    for dim in [1usize, 2, 3] {
        let pts: Vec<Vec<f64>> = (0..9)
            .map(|i| {
                (0..dim)
                    .map(|c| (i * (c + 2)) as f64 * 0.3 + rng.uniform())
                    .collect()
            })
            .collect();
        for (end, param) in [
            (EndCondition::NotAKnot, Parametrization::Uniform),
            (EndCondition::Natural, Parametrization::ChordLength),
            (EndCondition::Periodic, Parametrization::Centripetal),
        ] {
            let o = InterpolationOptions::default()
                .with_end(end.clone())
                .with_parametrization(param);
            let fit = interpolate_curve(&pts, &o).unwrap();
            let f = Piecewise::from_bspline(fit.curve()).unwrap();
            assert!(f.continuity().is_continuous(), "dim {dim} {end:?}");
            let n = fit.parameters().len();
            assert_eq!(f.knots()[..n], fit.parameters()[..], "dim {dim} {end:?}");
            curves.push((format!("interpolated dim {dim} {end:?}"), fit.into_curve()));
        }
    }
    for p in [1usize, 2, 3, 5] {
        let n = p + 7;
        let mut inner: Vec<f64> = (0..n - p - 2).map(|_| 1.0 + 1.9 * rng.uniform()).collect();
        inner.push(inner[0]); // a repeated knot: an empty span
        inner.sort_by(f64::total_cmp);
        let mut knots = vec![-1.0; p + 1];
        knots.extend(&inner);
        knots.extend(vec![3.0; p + 1]);
        let control: Vec<Vec<f64>> = (0..n).map(|_| vec![rng.uniform(), rng.uniform()]).collect();
        let c = BsplineCurve::new(p, knots, control).unwrap();
        if p == 1 {
            // A double knot of a polyline is a jump, which the continuous formula cannot be.
            let err = Piecewise::from_bspline(&c).unwrap_err();
            assert!(matches!(err, Error::InvalidKnots { .. }), "{err:?}");
            continue;
        }
        curves.push((format!("degree {p}"), c));
    }
    for (name, c) in &curves {
        let f = Piecewise::from_bspline(c).unwrap();
        let (a, b) = c.domain();
        let mut ts: Vec<f64> = (0..=400).map(|k| a + (b - a) * k as f64 / 400.0).collect();
        ts.extend(f.knots());
        let scale = c.control_flat().iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let formula = f.formula().unwrap();
        let mut printed = vec![0.0; ts.len() * c.dim()];
        formula.eval_batch(&[&ts], &mut printed).unwrap();
        for (k, &t) in ts.iter().enumerate() {
            let want = c.eval(t);
            for (i, got) in [f.eval(t), f.eval_formula(t)].iter().enumerate() {
                let err = common::max_abs_diff(got, &want);
                assert!(err <= 1e-13 * scale, "{name}, form {i}, t = {t}: {err:e}");
            }
            let err = common::max_abs_diff(&printed[k * c.dim()..(k + 1) * c.dim()], &want);
            assert!(err <= 1e-13 * scale, "{name}, printed, t = {t}: {err:e}");
        }
        assert!(
            formula.print(Format::Mathematica).unwrap().contains('t'),
            "{name}"
        );
    }
}
