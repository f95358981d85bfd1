//! Fuzzing of the Bézier operations (issue 21): random curves, rational curves and
//! surfaces (polynomial and rational) with coordinates from 1e-300 to f64::MAX, through every operation. Property: no
//! panic; each result is an error or finite; the real-degree test and the exact reduction
//! agree; evaluation on [0, 1] stays within the control points' bounding box (convex hull).

#[path = "common/fuzz.rs"]
mod fuzz;

use geomkit::bezier::{
    ApproxOptions, BezierCurve, BezierSurface, Direction, RationalBezierCurve,
    RationalBezierSurface, ReductionNorm,
};
use geomkit::geom::{Curve, Surface};
use proptest::prelude::*;

/// Coordinates at every magnitude: ordinary, tiny, huge, near f64::MAX, zeros and repeats.
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0..10.0f64,
        1 => (-1.0..1.0f64).prop_map(|x| x * 1e-300),
        1 => (-1.0..1.0f64).prop_map(|x| x * 1e300),
        1 => prop::sample::select(vec![0.0, -0.0, f64::MAX, -f64::MAX, 1.7e308, f64::MIN_POSITIVE, 5e-324]),
    ]
}

/// Control points: degree 0..=`max_degree`, dimension 1..=3, sometimes a curve elevated
/// from a lower degree (so that it has a real degree defect).
fn curve(max_degree: usize) -> impl Strategy<Value = BezierCurve> {
    (1usize..=3, 0..=max_degree, 0usize..4).prop_flat_map(move |(dim, n, extra)| {
        prop::collection::vec(coord(), dim * (n + 1)).prop_map(move |flat| {
            let c = BezierCurve::from_flat(dim, flat).expect("finite points");
            // A real degree below the formal one.
            c.elevate_degree(c.degree() + extra)
                .expect("small elevation")
        })
    })
}

fn tolerance() -> impl Strategy<Value = Option<f64>> {
    prop::sample::select(vec![None, Some(0.0), Some(1e-12), Some(1e-6), Some(0.5)])
}

/// The box around the control points, widened by a rounding slack.
fn contains(points: &[Vec<f64>], p: &[f64]) -> bool {
    (0..p.len()).all(|k| {
        let (lo, hi) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
                (l.min(q[k]), h.max(q[k]))
            });
        // Relative rounding, plus the granularity of subnormal numbers.
        let slack = 1e-9 * lo.abs().max(hi.abs()) + 4.0 * f64::MIN_POSITIVE;
        p[k] >= lo - slack && p[k] <= hi + slack
    })
}

/// An exact reduction whose control points exceed f64 (reduction is not a convex
/// combination: a point can be twice the largest input), refused as such.
fn overflows<T>(r: &Result<T, geomkit::Error>) -> bool {
    matches!(r, Err(geomkit::Error::Numerical { reason, .. }) if reason.contains("overflows"))
}

proptest! {
    #![proptest_config(fuzz::config(48))]

    #[test]
    fn fuzz_bezier_curve_operations(
        c in curve(12),
        t in prop_oneof![0.0..=1.0f64, Just(0.0), Just(1.0), Just(0.5)],
        outside in prop_oneof![Just(f64::NAN), Just(-0.5), Just(1.5), Just(1e300)],
        up in 0usize..30,
        down in 0usize..14,
        tol in tolerance(),
        cont in (prop::option::of(0usize..4), prop::option::of(0usize..4)),
        chebyshev in any::<bool>(),
    ) {
        let points = c.points();
        let p = c.eval(t);
        prop_assert!(p.iter().all(|x| x.is_finite()), "eval({t}) = {p:?}");
        prop_assert!(contains(&points, &p), "eval({t}) = {p:?} outside the hull");
        let _ = c.eval(outside);
        let mut d = vec![0.0; c.dim()];
        let _ = c.derivative_into(t, 1 + up % 3, &mut d);

        let e = c.elevate_degree(c.degree() + up).unwrap();
        prop_assert!(e.points_flat().iter().all(|x| x.is_finite()));

        match c.degree_report(tol) {
            Ok(report) => {
                prop_assert_eq!(report.degree, c.degree());
                prop_assert_eq!(report.defect, report.degree - report.real_degree);
                // The exact reduction agrees with the test, at the real degree and below.
                let back = c.reduce_degree(report.real_degree, tol);
                prop_assert!(back.is_ok() || overflows(&back), "real degree {} but {back:?}", report.real_degree);
                if report.real_degree > 0 {
                    prop_assert!(c.reduce_degree(report.real_degree - 1, tol).is_err());
                }
            }
            Err(e) => prop_assert!(false, "degree report failed: {e}"),
        }
        if let Ok(r) = c.change_degree(down, tol) {
            prop_assert!(r.points_flat().iter().all(|x| x.is_finite()));
        }
        let norm = if chebyshev { ReductionNorm::Chebyshev } else { ReductionNorm::L2 };
        let options = ApproxOptions::default().with_continuity(cont.0, cont.1).with_norm(norm);
        if let Ok(a) = c.reduce_degree_approx(down, &options) {
            prop_assert!(a.curve.points_flat().iter().all(|x| x.is_finite()));
            prop_assert!(!a.l2_error.is_nan() && !a.linf.upper_bound.is_nan());
        }
        let _ = c.deviation_from(&e);
    }

    #[test]
    fn fuzz_rational_curves(
        c in curve(8),
        weights in prop::collection::vec(
            prop_oneof![0.01..100.0f64, Just(1e-300), Just(1e300), Just(f64::MAX), Just(0.0), Just(-1.0)],
            1..12,
        ),
        t in 0.0..=1.0f64,
        up in 0usize..10,
    ) {
        let points = c.points();
        let w: Vec<f64> = (0..points.len()).map(|i| weights[i % weights.len()]).collect();
        if let Ok(r) = RationalBezierCurve::new(points.clone(), w) {
            let p = r.eval(t);
            prop_assert!(p.iter().all(|x| x.is_finite()), "eval({t}) = {p:?}");
            prop_assert!(contains(&points, &p), "eval({t}) = {p:?} outside the hull");
            if let Ok(e) = r.elevate_degree(r.degree() + up) {
                prop_assert!(e.weights().iter().all(|w| w.is_finite() && *w > 0.0));
            }
            let _ = r.degree_report(None);
            let _ = r.reduce_degree(r.degree().saturating_sub(1), None);
        }
    }

    #[test]
    fn fuzz_bezier_surfaces(
        (rows, cols, dim) in (1usize..5, 1usize..5, 1usize..4),
        values in prop::collection::vec(coord(), 48),
        (u, v) in (0.0..=1.0f64, 0.0..=1.0f64),
        targets in (0usize..7, 0usize..7),
        tol in tolerance(),
    ) {
        let net: Vec<f64> = (0..rows * cols * dim).map(|i| values[i % values.len()]).collect();
        let s = BezierSurface::from_flat(rows, cols, dim, net).unwrap();
        let p = s.eval(u, v);
        prop_assert!(p.iter().all(|x| x.is_finite()), "eval({u}, {v}) = {p:?}");
        let report = s.degree_report(tol).unwrap();
        // Reducing u first perturbs the net by up to the tolerance, which may change the
        // v test's verdict: the two agree for tight tolerances only.
        if tol.unwrap_or(0.0) <= 1e-12 {
            let back = s.change_degree(report.u.real_degree, report.v.real_degree, tol);
            prop_assert!(back.is_ok() || overflows(&back), "{report:?}: {back:?}");
        }
        if let Ok(c) = s.change_degree(targets.0, targets.1, tol) {
            prop_assert!(c.net_flat().iter().all(|x| x.is_finite()));
        }
        let _ = s.normal(u, v);
    }

    #[test]
    fn fuzz_rational_surfaces(
        (rows, cols, dim) in (1usize..4, 1usize..4, 1usize..4),
        values in prop::collection::vec(coord(), 27),
        weights in prop::collection::vec(
            prop_oneof![0.01..100.0f64, Just(1e-300), Just(1e300), Just(f64::MAX), Just(0.0), Just(-1.0), Just(f64::NAN)],
            1..10,
        ),
        (u, v) in (0.0..=1.0f64, 0.0..=1.0f64),
        targets in (0usize..6, 0usize..6),
        orders in (0usize..3, 0usize..3),
    ) {
        let net: Vec<f64> = (0..rows * cols * dim).map(|i| values[i % values.len()]).collect();
        let w: Vec<f64> = (0..rows * cols).map(|i| weights[i % weights.len()]).collect();
        if let Ok(s) = RationalBezierSurface::from_flat(rows, cols, dim, net.clone(), w) {
            let points: Vec<Vec<f64>> = net.chunks_exact(dim).map(<[f64]>::to_vec).collect();
            let p = s.eval(u, v);
            prop_assert!(p.iter().all(|x| x.is_finite()), "eval({u}, {v}) = {p:?}");
            prop_assert!(contains(&points, &p), "eval({u}, {v}) = {p:?} outside the hull");
            let mut d = vec![0.0; dim];
            let _ = s.derivative_into(u, v, orders, &mut d);
            let _ = s.degree_report(None);
            if let Ok(c) = s.change_degree(targets.0, targets.1, None) {
                prop_assert!(c.weights_flat().iter().all(|w| w.is_finite() && *w > 0.0));
                prop_assert!(c.net_flat().iter().all(|x| x.is_finite()));
            }
            if let Ok(r) = s.remove_line(Direction::U, 0) {
                prop_assert_eq!(r.degrees().0 + 1, s.degrees().0);
            }
            let _ = s.normal(u, v);
        }
    }
}
