//! Fuzzing of the B-spline side (issue 21): interpolation of random points (every end
//! condition and parametrization, at every magnitude, with duplicates), at given parameters
//! (spacings from 1e-200 to 1e200), in tiles, over grids and heights; B-splines from random
//! knots. Property: no panic; an error, or finite control points and a curve through its
//! points (relative to the data's scale), and evaluation that is finite inside the domain.

#[path = "common/fuzz.rs"]
mod fuzz;

use geomkit::bspline::{
    interpolate_curve_at, interpolate_curve_flat, interpolate_curve_tiled, interpolate_heights,
    interpolate_surface_flat, BsplineCurve, EndCondition, InterpolationOptions, Parametrization,
    SurfaceInterpolationOptions, TileOptions,
};
use geomkit::geom::Curve;
use proptest::prelude::*;

fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -10.0..10.0f64,
        1 => (-1.0..1.0f64).prop_map(|x| x * 1e-300),
        1 => (-1.0..1.0f64).prop_map(|x| x * 1e300),
        1 => prop::sample::select(vec![0.0, f64::MAX, -f64::MAX, 1e308, 5e-324]),
    ]
}

fn end() -> impl Strategy<Value = EndCondition> {
    prop_oneof![
        Just(EndCondition::NotAKnot),
        Just(EndCondition::Natural),
        Just(EndCondition::Periodic),
        Just(EndCondition::Repeat),
        Just(EndCondition::Clamped {
            start: None,
            end: None
        }),
        Just(EndCondition::Bessel),
        (coord(), coord()).prop_map(|(a, b)| EndCondition::Clamped {
            start: Some(vec![a]),
            end: Some(vec![b]),
        }),
        prop::sample::select(vec![1e-300, 1e-3, 1.0, 1e300, f64::MAX])
            .prop_map(|offset| EndCondition::OuterPoints { offset }),
    ]
}

fn parametrization() -> impl Strategy<Value = Parametrization> {
    prop::sample::select(vec![
        Parametrization::Uniform,
        Parametrization::ChordLength,
        Parametrization::Centripetal,
    ])
}

fn all_finite(x: &[f64]) -> bool {
    x.iter().all(|v| v.is_finite())
}

/// The largest |coordinate| (the data's scale).
fn scale(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

proptest! {
    #![proptest_config(fuzz::config(64))]

    #[test]
    fn fuzz_interpolate_curves(
        dim in 1usize..=3,
        values in prop::collection::vec(coord(), 2..40),
        end in end(),
        param in parametrization(),
        tile in 1usize..8,
        halo in 0usize..4,
    ) {
        let n = (values.len() / dim).max(1);
        let points: Vec<f64> = (0..n * dim).map(|i| values[i % values.len()]).collect();
        // Tangents of the point's dimension.
        let end = match end {
            EndCondition::Clamped { start: Some(a), end: Some(b) } => EndCondition::Clamped {
                start: Some(vec![a[0]; dim]),
                end: Some(vec![b[0]; dim]),
            },
            e => e,
        };
        let options = InterpolationOptions::default().with_end(end).with_parametrization(param);
        if let Ok(fit) = interpolate_curve_flat(dim, &points, &options) {
            let c = fit.curve();
            prop_assert!(all_finite(c.control_flat()), "control points not finite");
            // Errors scale with the solution (huge given tangents make huge control points).
            let s = scale(&points).max(scale(c.control_flat()));
            if s < 1e300 && s > 1e-290 {
                for (i, &t) in fit.parameters().iter().enumerate() {
                    let p = c.eval(t);
                    for k in 0..dim {
                        let want = points[i * dim + k];
                        // Loose: random data can make ill-conditioned systems.
                        prop_assert!((p[k] - want).abs() <= 1e-6 * s, "point {i}: {p:?}");
                    }
                }
            }
        }
        let tiles = TileOptions::default().with_tile_size(tile).with_halo(halo);
        if let Ok(fit) = interpolate_curve_tiled(dim, &points, &options, &tiles) {
            prop_assert!(all_finite(fit.curve().control_flat()));
        }
    }

    #[test]
    fn fuzz_interpolate_at_parameters(
        y in prop::collection::vec(coord(), 2..20),
        steps in prop::collection::vec(
            prop_oneof![0.1..10.0f64, Just(1e-200), Just(1e200), Just(0.0), Just(1e308)],
            20,
        ),
        start in prop_oneof![Just(0.0), Just(-1e308), Just(1e300)],
        end in end(),
    ) {
        let mut x = vec![start];
        for s in steps.iter().take(y.len() - 1) {
            x.push(x[x.len() - 1] + s);
        }
        let end = match end {
            EndCondition::Clamped { start: Some(_), end: Some(_) } => {
                EndCondition::Clamped { start: Some(vec![1.0]), end: Some(vec![-1.0]) }
            }
            e => e,
        };
        if let Ok(fit) = interpolate_curve_at(1, &y, &x, &end) {
            prop_assert!(all_finite(fit.curve().control_flat()));
            prop_assert!(all_finite(fit.curve().knots()));
            for &t in fit.parameters() {
                prop_assert!(fit.curve().eval(t)[0].is_finite());
            }
        }
    }

    #[test]
    fn fuzz_interpolate_grids(
        (rows, cols, dim) in (1usize..7, 1usize..7, 1usize..=3),
        values in prop::collection::vec(coord(), 64),
        ends in (end(), end()),
        param in parametrization(),
        spacing in (prop_oneof![Just(1.0), Just(1e-300), Just(1e300), Just(0.0)],
                    prop_oneof![Just(0.5), Just(1e200)]),
    ) {
        let grid: Vec<f64> = (0..rows * cols * dim).map(|i| values[i % values.len()]).collect();
        let strip = |e: EndCondition| match e {
            EndCondition::Clamped { .. } => EndCondition::Clamped { start: None, end: None },
            e => e,
        };
        let options = SurfaceInterpolationOptions::default()
            .with_ends(strip(ends.0.clone()), strip(ends.1))
            .with_parametrization(param);
        if let Ok(fit) = interpolate_surface_flat(rows, cols, dim, &grid, &options) {
            prop_assert!(all_finite(fit.surface.control_flat()));
        }
        let heights: Vec<f64> = grid.iter().take(rows * cols).copied().collect();
        if let Ok(s) = interpolate_heights(&heights, rows, cols, (0.0, 0.0), spacing, &strip(ends.0)) {
            prop_assert!(all_finite(s.control_flat()));
            let ((u0, u1), (v0, v1)) = s.domain();
            prop_assert!(s.eval(0.5 * (u0 + u1), 0.5 * (v0 + v1))[0].is_finite());
        }
    }

    #[test]
    fn fuzz_bspline_from_knots(
        degree in 0usize..6,
        knots in prop::collection::vec(
            prop_oneof![-10.0..10.0f64, Just(1e308), Just(-1e308), Just(1e-300), Just(0.0)],
            1..16,
        ),
        control in prop::collection::vec(coord(), 1..16),
        t in prop_oneof![0.0..=1.0f64, Just(f64::NAN), Just(1e300)],
        order in 0usize..4,
    ) {
        let mut knots = knots;
        knots.sort_by(f64::total_cmp);
        let n = knots.len().saturating_sub(degree + 1);
        let control: Vec<Vec<f64>> = (0..n).map(|i| vec![control[i % control.len()]]).collect();
        if let Ok(c) = BsplineCurve::new(degree, knots, control) {
            let (a, b) = c.domain();
            let at = if t.is_finite() && t <= 1.0 { a + t * (b - a) } else { t };
            let p = c.eval(at);
            if (a..=b).contains(&at) {
                prop_assert!(all_finite(&p), "eval({at}) = {p:?} on [{a}, {b}]");
            }
            let mut d = vec![0.0];
            let _ = c.derivative_into(at, order, &mut d);
        }
    }
}

/// Control points at ±f64::MAX: the weighted sums overflow by rounding (weights summing to
/// a little over 1), the true values lie in the points' range (convex hull), and evaluation
/// gives them, not infinity; a NaN parameter still gives NaN.
#[test]
fn control_points_at_f64_max_evaluate_inside_their_range() {
    let mut knots = vec![
        -0.8372233415416261,
        -1e308,
        -1e308,
        1e-300,
        1e-300,
        -1e308,
        -1e308,
        -1e308,
        1e-300,
        1e-300,
        1e-300,
        -0.9040547403088014,
        1e-300,
    ];
    knots.sort_by(f64::total_cmp);
    let c = BsplineCurve::new(5, knots, vec![vec![f64::MAX]; 7]).unwrap();
    assert_eq!(c.eval(-0.4906756140124737), vec![f64::MAX]);
    assert!(c.eval(f64::NAN)[0].is_nan());
    let clamped = |n: usize| {
        let mut t = vec![0.0; 4];
        t.extend((1..n - 3).map(|i| i as f64 / (n - 3) as f64));
        t.extend([1.0; 4]);
        t
    };
    let control: Vec<f64> = (0..36)
        .flat_map(|i| [f64::MAX, -f64::MAX, if i % 2 == 0 { f64::MAX } else { 1.0 }])
        .collect();
    let s = geomkit::bspline::BsplineSurface::from_flat(
        (3, 3),
        clamped(6),
        clamped(6),
        6,
        6,
        3,
        control,
    )
    .unwrap();
    let near = |a: f64, b: f64| (a - b).abs() <= 16.0 * f64::EPSILON * b.abs();
    for i in 0..=50 {
        for j in 0..=50 {
            let (u, v) = (i as f64 / 50.0, j as f64 / 50.0);
            let p = s.eval(u, v);
            assert!(p.iter().all(|x| x.is_finite()), "({u}, {v}): {p:?}");
            assert!(
                near(p[0], f64::MAX) && near(p[1], -f64::MAX),
                "({u}, {v}): {p:?}"
            );
        }
    }
}
