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
