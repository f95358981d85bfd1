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
    assert!(too_wide(Nodes::new(vec![-9.0, 0.0, 1e308, f64::MAX])));
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
    let nodes = Nodes::new(vec![-9.0, 0.0, 1.0]).unwrap();
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
