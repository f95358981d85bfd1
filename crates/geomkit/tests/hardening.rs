//! Regressions of bad or extreme input (issue 21): each case once panicked, overflowed or
//! aborted; now each gives a result that is checked, or a clear error.

use geomkit::bezier::{ApproxOptions, BezierCurve};
use geomkit::bspline::{CurveInterpolator, EndCondition};
use geomkit::geom::Curve;
use geomkit::Error;

/// A degree-9 curve in the plane.
fn nonic() -> BezierCurve {
    BezierCurve::new(
        [0., 3., -1., 4., 0., 2., 1., 5., 0., 1.]
            .iter()
            .enumerate()
            .map(|(i, &y)| vec![i as f64, y])
            .collect(),
    )
    .unwrap()
}

/// Reduction to degree 4 with C^4 at one end only fixes all five points from that end
/// (`--continuity -,4` used to abort with "capacity overflow"): the quartic shares the
/// curve's derivatives of orders 0 to 4 there, and fixing the other end gives the mirror.
#[test]
fn approximate_reduction_fixing_every_point_from_one_end() {
    let c = nonic();
    let at_end = c
        .reduce_degree_approx(4, &ApproxOptions::default().with_continuity(None, Some(4)))
        .unwrap();
    let scale = 5.0;
    for order in 0..=4 {
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        c.derivative_into(1.0, order, &mut a).unwrap();
        at_end.curve.derivative_into(1.0, order, &mut b).unwrap();
        // Derivatives of order k scale like n^k.
        let tol = 1e-12 * scale * 9f64.powi(order as i32);
        assert!(
            (a[0] - b[0]).abs() <= tol && (a[1] - b[1]).abs() <= tol,
            "order {order}: {a:?} {b:?}"
        );
    }
    // The mirror: the reversed curve reduced with C^4 at its start is the reversed quartic.
    let reversed = BezierCurve::new(c.points().into_iter().rev().collect()).unwrap();
    let at_start = reversed
        .reduce_degree_approx(4, &ApproxOptions::default().with_continuity(Some(4), None))
        .unwrap();
    let mirrored: Vec<Vec<f64>> = at_start.curve.points().into_iter().rev().collect();
    for (p, q) in mirrored.iter().zip(at_end.curve.points()) {
        assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
    }
    assert!((at_start.l2_error - at_end.l2_error).abs() < 1e-12);
    // One more fixed point than the quartic has is refused.
    assert!(matches!(
        c.reduce_degree_approx(
            4,
            &ApproxOptions::default().with_continuity(Some(0), Some(4))
        ),
        Err(Error::ContinuityTooHigh { .. })
    ));
}

/// No parameters for a closed curve (a `usize` underflow before): too few points.
#[test]
fn interpolator_at_no_parameters_is_an_error() {
    for end in [EndCondition::Periodic, EndCondition::NotAKnot] {
        assert!(
            matches!(
                CurveInterpolator::at(&[], &end),
                Err(Error::TooFewPoints { got: 0, .. })
            ),
            "{end:?}"
        );
    }
}

/// A NaN parameter gives NaN coordinates (it indexed outside the knot spans and panicked):
/// one rule for every B-spline evaluation that cannot return an error; the batches refuse
/// it by name.
#[test]
fn bspline_evaluation_at_nan_is_nan() {
    use geomkit::bspline::{BsplineCurve, BsplineSurface};
    use geomkit::geom::{BatchOptions, Surface};
    let c = BsplineCurve::new(
        2,
        vec![0.0, 0.0, 0.0, 1.0, 3.0, 3.0, 3.0],
        vec![
            vec![0.0, 0.0],
            vec![1.0, 2.0],
            vec![3.0, 1.0],
            vec![4.0, 0.0],
        ],
    )
    .unwrap();
    assert!(c.eval(f64::NAN).iter().all(|x| x.is_nan()));
    let mut d = [0.0; 2];
    c.eval_derivative(f64::NAN, 1, &mut d);
    assert!(d.iter().all(|x| x.is_nan()), "{d:?}");
    assert!(matches!(
        Curve::eval_batch(
            &c,
            &[0.5, f64::NAN],
            &mut [0.0; 4],
            &BatchOptions::default()
        ),
        Err(Error::NonFinite { index: 1, .. })
    ));
    let knots = vec![0.0, 0.0, 0.0, 1.0, 3.0, 3.0, 3.0];
    let net: Vec<f64> = (0..16).map(|k| k as f64).collect();
    let s = BsplineSurface::from_flat((2, 2), knots.clone(), knots, 4, 4, 1, net).unwrap();
    let mut p = [0.0];
    s.eval_derivative(f64::NAN, 0.5, 1, 0, &mut p);
    assert!(p[0].is_nan());
    assert!(Surface::eval(&s, 0.5, f64::NAN)[0].is_nan());
}

/// Node sets spanning the f64 range: their differences overflow the weights' products
/// (`expect` panicked); now a clear error, and a wide but representable set still works.
#[test]
fn nodes_whose_differences_overflow_are_refused() {
    use geomkit::pointcalc::{NodePreset, Nodes};
    let too_wide = |r: geomkit::Result<Nodes>| matches!(r, Err(Error::InvalidNodes { reason, .. }) if reason.contains("overflow"));
    assert!(too_wide(Nodes::new(vec![-1e308, 0.0, 1e308, f64::MAX])));
    // Presets over [-MAX, MAX]: the nodes are representable (no (b - a) overflow), but the
    // products of their differences are not.
    for preset in [
        NodePreset::Equispaced,
        NodePreset::ChebyshevFirst,
        NodePreset::ChebyshevSecond,
    ] {
        assert!(
            too_wide(Nodes::preset(preset, 5, -f64::MAX, f64::MAX)),
            "{preset:?}"
        );
    }
    let nodes = Nodes::new(vec![-1e308, -9e307, -8e307]).unwrap();
    assert!(too_wide(nodes.with_node(f64::MAX).map(|(n, _)| n)));
    // 1e300 apart is fine, and the cardinal functions still interpolate: l_j(x_k) = δ_jk.
    let wide = Nodes::new(vec![-1e300, 0.0, 1e300]).unwrap();
    for (k, &x) in wide.values().iter().enumerate() {
        let l = wide.basis(x);
        for (j, &v) in l.iter().enumerate() {
            assert_eq!(v, if j == k { 1.0 } else { 0.0 });
        }
    }
}

/// A 3×3 scene of Bézier patches with a corner near the end of the f64 range: the sums of
/// formula (9) overflow (an `expect` panicked); now a clear error. Ten times smaller, it
/// builds, and the structural evaluator returns the corner.
#[test]
fn composite_sums_that_overflow_are_refused() {
    use geomkit::bezier::BezierSurface;
    use geomkit::compose::{CompositeSurface, SurfaceKind};
    use geomkit::geom::Surface;
    let scene = |big: f64| {
        // Every patch has the big value at its far corner (1, 1) and 0 at the others:
        // formula (9) shifts each later patch by the jumps before it, which add up.
        let patch = |_: usize, _: usize| {
            let b = BezierSurface::new(vec![
                vec![vec![0.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]],
                vec![vec![1.0, 0.0, 0.0], vec![1.0, 1.0, big]],
            ])
            .unwrap();
            geomkit::compose::PolyPatch::from_bezier(&b)
        };
        let patches = (0..3)
            .map(|i| (0..3).map(|j| patch(i, j)).collect())
            .collect();
        let knots = vec![0.0, 1.0, 2.0, 3.0];
        CompositeSurface::from_poly(knots.clone(), knots, patches, SurfaceKind::Parametric)
    };
    let e = scene(1.7e308).unwrap_err();
    assert!(
        matches!(&e, Error::Overflow { what, .. } if what.starts_with("formula (9) at patch (")),
        "{e}"
    );
    let s = scene(1.0e307).unwrap();
    // The far corner of the last patch: its own value plus the jumps formula (9) adds.
    let p = Surface::eval(&s, 3.0, 3.0);
    assert!(p[2].is_finite() && p[2] >= 1.0e307, "{p:?}");
}

/// Elevating a degree-1000 curve to 999 999 (1e9 weights, 16 GB) is refused before any
/// allocation, naming the sizes; a cubic to degree 10^6 (4e6 weights) still works.
#[test]
fn elevation_beyond_the_weight_budget_is_refused() {
    use geomkit::bezier::MAX_ELEVATION_WEIGHTS;
    let big = BezierCurve::new((0..=1000).map(|i| vec![i as f64, 0.0]).collect()).unwrap();
    match big.elevate_degree(999_999) {
        Err(Error::TooLarge {
            what, size, limit, ..
        }) => {
            assert_eq!(what, "elevating degree 1000 to 999999");
            assert_eq!(size, 1_000_000 * 1001);
            assert_eq!(limit, MAX_ELEVATION_WEIGHTS as u128);
        }
        other => panic!("{other:?}"),
    }
    let cubic = BezierCurve::new(vec![vec![0.0], vec![1.0], vec![3.0], vec![4.0]]).unwrap();
    let high = cubic.elevate_degree(1_000_000).unwrap();
    // Control point j of the elevation is Σ_i C(3,i) C(n'-3,j-i) / C(n',j) u_i: the ends
    // stay, and the middle one is c(1/2) = (0 + 3 + 9 + 4)/8 = 2 up to O(1/n').
    let p = high.points_flat();
    assert_eq!((p[0], p[1_000_000]), (0.0, 4.0));
    assert!((p[500_000] - 2.0).abs() < 1e-5, "{}", p[500_000]);
    // And it evaluates (from its largest Bernstein terms: de Casteljau's O(n^2) took hours)
    // to the cubic.
    for t in [1e-9, 0.1, 0.5, 0.77, 1.0 - 1e-9, 1.0] {
        let (a, b) = (high.eval(t)[0], cubic.eval(t)[0]);
        assert!((a - b).abs() < 1e-12, "t {t}: {a} {b}");
    }
}

/// The real-degree test, the exact reduction and the residual take curves up to degree
/// MAX_REDUCTION_DEGREE (O(n^3) work); above it they refuse by name instead of running for
/// minutes (degree 3000: about 6 minutes).
#[test]
fn reductions_of_very_high_degrees_are_refused() {
    use geomkit::bezier::MAX_REDUCTION_DEGREE;
    let n = MAX_REDUCTION_DEGREE + 1;
    let c = BezierCurve::new((0..=n).map(|i| vec![(i % 7) as f64]).collect()).unwrap();
    let too_large = |r: Result<(), Error>| match r {
        Err(Error::TooLarge { size, .. }) => assert_eq!(size, n as u128),
        other => panic!("{other:?}"),
    };
    too_large(c.degree_report(None).map(|_| ()));
    too_large(c.reduce_degree(3, None).map(|_| ()));
    too_large(c.reduction_residual(3).map(|_| ()));
    too_large(
        c.reduce_degree_approx(3, &ApproxOptions::default())
            .map(|_| ()),
    );
}

/// A cubic elevated to degree 5 with coordinates near f64::MAX: the real-degree test says 3
/// and the exact reduction to 3 succeeds and gives back the cubic (they used to disagree:
/// the residual's norms overflowed), whatever the magnitude (1e-300 .. 1e308).
#[test]
fn degree_report_and_reduction_agree_at_any_magnitude() {
    for scale in [1e-300, 1.0, 1e300, 4e307] {
        let cubic = BezierCurve::new(
            [[0.0, 1.0], [1.0, -1.0], [-1.0, 0.5], [1.0, 1.0]]
                .iter()
                .map(|p| vec![p[0] * scale, p[1] * scale])
                .collect(),
        )
        .unwrap();
        let quintic = cubic.elevate_degree(5).unwrap();
        let report = quintic.degree_report(None).unwrap();
        assert_eq!((report.real_degree, report.defect), (3, 2), "scale {scale}");
        let back = quintic.reduce_degree(3, None).unwrap();
        for (p, q) in back.points().iter().zip(cubic.points()) {
            for (a, b) in p.iter().zip(&q) {
                assert!((a - b).abs() <= 1e-13 * scale, "scale {scale}: {a} {b}");
            }
        }
        // One degree lower is refused by both, with the same real degree.
        match quintic.reduce_degree(2, None) {
            Err(Error::DegreeDefectTooSmall { real_degree, .. }) => assert_eq!(real_degree, 3),
            other => panic!("scale {scale}: {other:?}"),
        }
    }
}

/// Weights times control points near f64::MAX overflowed into an "infinite control point":
/// the weights are scaled by a common power of two instead (the same curve). A quarter
/// circle of radius 1e308 as a rational quadratic: every point at distance 1e308.
#[test]
fn rational_curves_near_the_largest_float() {
    use geomkit::bezier::RationalBezierCurve;
    let r = 1e308;
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = RationalBezierCurve::new(
        vec![vec![r, 0.0], vec![r, r], vec![0.0, r]],
        vec![4.0, 4.0 * w, 4.0],
    )
    .unwrap();
    for t in [0.0, 0.25, 0.5, 0.9, 1.0] {
        let p = arc.eval(t);
        let dist = (p[0] / r).hypot(p[1] / r);
        assert!((dist - 1.0).abs() < 1e-15, "t {t}: {p:?}");
    }
    assert_eq!(arc.points()[1], vec![r, r]);
    let e = arc.elevate_degree(4).unwrap();
    assert!(((e.eval(0.3)[0] - arc.eval(0.3)[0]) / r).abs() < 1e-15);
}

/// Parameters spread over more than f64's range (differences overflow) are refused by name
/// instead of giving a curve of NaN (the extended knots were infinite).
#[test]
fn parameters_whose_spread_overflows_are_refused() {
    use geomkit::bspline::interpolate_curve_at;
    let y = [0.0, 1.0, 0.0, 2.0];
    for x in [[-1e308, 0.0, 1e308, 1.5e308], [0.0, 1.0, 2.0, f64::MAX]] {
        match interpolate_curve_at(1, &y, &x, &EndCondition::NotAKnot) {
            Err(Error::InvalidKnots { reason, .. }) => {
                assert!(reason.contains("scale the parameters down"), "{reason}")
            }
            other => panic!("{x:?}: {other:?}"),
        }
    }
    // Wide but representable: fine, and exact at the data.
    let x = [-2e307, 0.0, 1e307, 2e307];
    let fit = interpolate_curve_at(1, &y, &x, &EndCondition::Natural).unwrap();
    assert!(fit.curve().eval(1e307)[0].abs() < 1e-14);
    assert!((fit.curve().eval(2e307)[0] - 2.0).abs() < 1e-14);
    // Spacings of 1e±200 (derivative rows like 1/h^3 overflowed or underflowed into a
    // "singular" system): points on a line with its slope as the clamped tangents give
    // the line itself, at every scale.
    for h in [1e-200, 1e-3, 1.0, 1e200] {
        let x = [0.0, h, 3.0 * h, 4.0 * h, 7.0 * h];
        let y = [1.0, 2.0, 4.0, 5.0, 8.0];
        let slope = vec![1.0 / h];
        let end = EndCondition::Clamped {
            start: Some(slope.clone()),
            end: Some(slope),
        };
        for end in [end, EndCondition::Natural, EndCondition::NotAKnot] {
            let fit = interpolate_curve_at(1, &y, &x, &end).unwrap();
            let v = fit.curve().eval(2.0 * h)[0];
            assert!((v - 3.0).abs() < 1e-14, "h {h}, {end:?}: {v}");
        }
    }
}
