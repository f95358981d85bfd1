//! Interpolating cubic B-spline curves (spec/bspline-interpolation.md).

mod common;

use common::Rng;
use geomkit::bspline::{
    interpolate_curve, interpolate_curve_at, interpolate_curve_flat, paper_dense_inner_points,
    parameters, BsplineCurve, CurveInterpolator, EndCondition, InterpolationOptions,
    Parametrization,
};
use geomkit::geom::{BatchOptions, Curve};
use geomkit::Error;

fn wiggly(n: usize, dim: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Rng(seed | 1);
    (0..n)
        .map(|i| {
            let mut p: Vec<f64> = (0..dim).map(|_| rng.uniform()).collect();
            p[0] += 1.5 * i as f64;
            p
        })
        .collect()
}

fn all_ends() -> Vec<EndCondition> {
    vec![
        EndCondition::Natural,
        EndCondition::Clamped {
            start: None,
            end: None,
        },
        EndCondition::Bessel,
        EndCondition::Clamped {
            start: Some(vec![1.0, 0.5, 0.0]),
            end: Some(vec![0.0, -1.0, 2.0]),
        },
        EndCondition::NotAKnot,
        EndCondition::Periodic,
    ]
}

fn residual(points: &[Vec<f64>], fit: &geomkit::bspline::CurveInterpolation) -> f64 {
    let scale = points.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    points
        .iter()
        .zip(fit.parameters())
        .map(|(p, &t)| {
            let q = fit.curve().eval(t);
            p.iter()
                .zip(&q)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn passes_through_every_point_for_every_end_and_parametrization() {
    for n in [2usize, 3, 4, 5, 8, 50, 1000] {
        for end in all_ends() {
            for param in common::PARAMETRIZATIONS {
                if end == EndCondition::Periodic && n < 3 {
                    continue;
                }
                let pts = wiggly(n, 3, n as u64 * 7 + 3);
                let opts = InterpolationOptions::default()
                    .with_end(end.clone())
                    .with_parametrization(param);
                let fit = interpolate_curve(&pts, &opts)
                    .unwrap_or_else(|e| panic!("{n} {end:?} {param:?}: {e}"));
                let r = residual(&pts, &fit);
                assert!(r <= 1e-14, "n={n} {end:?} {param:?}: residual {r:e}");
            }
        }
        let pts = wiggly(n, 2, 5);
        let opts = InterpolationOptions::default()
            .with_end(EndCondition::Repeat)
            .with_parametrization(Parametrization::Uniform);
        let fit = interpolate_curve(&pts, &opts).unwrap();
        assert!(residual(&pts, &fit) <= 1e-14);
        assert_eq!(fit.curve().n_control(), n + 4);
        assert!(fit.curve().is_uniform());
    }
}

fn derivative_at(c: &BsplineCurve, t: f64, k: usize) -> Vec<f64> {
    let mut out = vec![0.0; 3];
    c.eval_derivative(t, k, &mut out);
    out
}

#[test]
fn end_conditions_hold() {
    let pts = wiggly(9, 3, 42);
    for param in [Parametrization::Uniform, Parametrization::ChordLength] {
        let o = InterpolationOptions::default().with_parametrization(param);
        let natural = interpolate_curve(&pts, &o.clone().with_end(EndCondition::Natural)).unwrap();
        let (a, b) = natural.curve().domain();
        for t in [a, b] {
            assert!(derivative_at(natural.curve(), t, 2)
                .iter()
                .all(|v| v.abs() < 1e-12));
        }
        let tangents = EndCondition::Clamped {
            start: Some(vec![1.0, 0.5, 0.0]),
            end: Some(vec![0.0, -1.0, 2.0]),
        };
        let clamped = interpolate_curve(&pts, &o.clone().with_end(tangents)).unwrap();
        let d0 = derivative_at(clamped.curve(), a, 1);
        let d1 = derivative_at(clamped.curve(), clamped.curve().domain().1, 1);
        assert!((d0[0] - 1.0).abs() < 1e-12 && (d0[1] - 0.5).abs() < 1e-12 && d0[2].abs() < 1e-12);
        assert!(d1[0].abs() < 1e-12 && (d1[1] + 1.0).abs() < 1e-12 && (d1[2] - 2.0).abs() < 1e-12);
        // Not-a-knot: third derivative continuous across the second and next-to-last knots.
        let nak = interpolate_curve(&pts, &o.clone().with_end(EndCondition::NotAKnot)).unwrap();
        for &t in [nak.parameters()[1], nak.parameters()[7]].iter() {
            let h = 1e-7 * (b - a);
            let l = derivative_at(nak.curve(), t - h, 3);
            let r = derivative_at(nak.curve(), t + h, 3);
            for k in 0..3 {
                assert!(
                    (l[k] - r[k]).abs() < 1e-9 * (1.0 + l[k].abs()),
                    "{l:?} {r:?}"
                );
            }
        }
    }
}

#[test]
fn periodic_curve_is_c2_across_the_seam() {
    // An isoline: 12 points around an ellipse, the closing point given or not.
    let mut pts: Vec<Vec<f64>> = (0..12)
        .map(|i| {
            let a = i as f64 * std::f64::consts::TAU / 12.0;
            vec![3.0 * a.cos() + 0.2 * (3.0 * a).sin(), 2.0 * a.sin()]
        })
        .collect();
    for closing in [false, true] {
        if closing {
            pts.push(pts[0].clone());
        }
        let fit = interpolate_curve(
            &pts,
            &InterpolationOptions::default().with_end(EndCondition::Periodic),
        )
        .unwrap();
        assert_eq!(fit.parameters().len(), 12);
        let (a, b) = fit.curve().domain();
        for k in 0..3 {
            let mut s = [0.0; 2];
            let mut e = [0.0; 2];
            fit.curve().eval_derivative(a, k, &mut s);
            fit.curve().eval_derivative(b, k, &mut e);
            for c in 0..2 {
                assert!(
                    (s[c] - e[c]).abs() < 1e-12 * (1.0 + s[c].abs()),
                    "derivative {k}: {s:?} vs {e:?}"
                );
            }
        }
    }
}

/// The paper's 4-point system: 4 k*_1 + k*_2 = 6 k_1 - k_0, k*_1 + 4 k*_2 = 6 k_2 - k_3.
#[test]
fn paper_four_point_system_and_dense_route_agree() {
    let pts = vec![
        vec![0.0, 0.0],
        vec![1.0, 2.0],
        vec![3.0, 2.5],
        vec![4.0, 0.0],
    ];
    let dense = paper_dense_inner_points(&pts).unwrap();
    for c in 0..2 {
        let (k0, k1, k2, k3) = (pts[0][c], pts[1][c], pts[2][c], pts[3][c]);
        let (a, b) = (dense[0][c], dense[1][c]);
        assert!((4.0 * a + b - (6.0 * k1 - k0)).abs() < 1e-14);
        assert!((a + 4.0 * b - (6.0 * k2 - k3)).abs() < 1e-14);
    }
    let opts = InterpolationOptions::default()
        .with_end(EndCondition::Repeat)
        .with_parametrization(Parametrization::Uniform);
    for n in [4usize, 6, 30, 300] {
        let pts = wiggly(n, 3, n as u64);
        let fit = interpolate_curve(&pts, &opts).unwrap();
        let dense = paper_dense_inner_points(&pts).unwrap();
        let banded = fit.curve().control_points();
        for (d, b) in dense.iter().zip(&banded[3..]) {
            for c in 0..3 {
                assert!((d[c] - b[c]).abs() < 1e-13, "n={n}");
            }
        }
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let o = InterpolationOptions::default();
    assert!(matches!(
        interpolate_curve(&[vec![1.0, 2.0]], &o),
        Err(Error::TooFewPoints { got: 1, min: 2, .. })
    ));
    let dup = vec![
        vec![0.0, 0.0],
        vec![1.0, 1.0],
        vec![1.0, 1.0],
        vec![2.0, 0.0],
    ];
    assert_eq!(
        interpolate_curve(&dup, &o).unwrap_err(),
        Error::RepeatedPoint { index: 1 }
    );
    // Uniform parameters accept repeated points (the curve stops there).
    let u = o.clone().with_parametrization(Parametrization::Uniform);
    assert!(interpolate_curve(&dup, &u).is_ok());
    let nan = vec![vec![0.0, 0.0], vec![f64::NAN, 1.0]];
    assert!(matches!(
        interpolate_curve(&nan, &o),
        Err(Error::NonFinite { index: 1, .. })
    ));
    // Periodic through two distinct points (as SciPy): closed, through both.
    let tri = vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![0.0, 0.0]];
    let loop2 = interpolate_curve(&tri, &o.clone().with_end(EndCondition::Periodic)).unwrap();
    let (a, b) = loop2.curve().domain();
    for (t, p) in [
        (a, [0.0, 0.0]),
        (loop2.parameters()[1], [1.0, 0.0]),
        (b, [0.0, 0.0]),
    ] {
        let q = loop2.curve().eval(t);
        assert!(
            (q[0] - p[0]).abs() < 1e-15 && (q[1] - p[1]).abs() < 1e-15,
            "{t}: {q:?}"
        );
    }
    let one = vec![vec![1.0, 0.0], vec![1.0, 0.0]];
    assert!(matches!(
        interpolate_curve(&one, &o.clone().with_end(EndCondition::Periodic)),
        Err(Error::TooFewPoints { got: 1, min: 2, .. })
    ));
    assert!(matches!(
        interpolate_curve(&tri, &o.clone().with_end(EndCondition::Repeat)),
        Err(Error::InvalidOption { .. })
    ));
    let bad_tangent = EndCondition::Clamped {
        start: Some(vec![1.0]),
        end: None,
    };
    assert!(matches!(
        interpolate_curve(&tri, &o.with_end(bad_tangent)),
        Err(Error::DimensionMismatch {
            what: "start tangent",
            ..
        })
    ));
}

#[test]
fn tiles_equal_the_global_solve() {
    use geomkit::bspline::{interpolate_curve_flat, interpolate_curve_tiled, TileOptions};
    let n = 100_000;
    let mut rng = Rng(77);
    let pts: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64 * 1e-3;
            [
                t.cos() * 50.0 + rng.uniform(),
                t.sin() * 30.0 + rng.uniform(),
                rng.uniform(),
            ]
        })
        .collect();
    let scale = pts.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for param in common::PARAMETRIZATIONS {
        for end in [
            EndCondition::NotAKnot,
            EndCondition::Natural,
            EndCondition::Clamped {
                start: None,
                end: None,
            },
            EndCondition::Bessel,
        ] {
            let opts = InterpolationOptions::default()
                .with_end(end.clone())
                .with_parametrization(param);
            let global = interpolate_curve_flat(3, &pts, &opts).unwrap();
            let tiled = interpolate_curve_tiled(
                3,
                &pts,
                &opts,
                &TileOptions::default().with_tile_size(4096),
            )
            .unwrap();
            assert_eq!(global.curve().knots(), tiled.curve().knots());
            let err = global
                .curve()
                .control_flat()
                .iter()
                .zip(tiled.curve().control_flat())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(
                err <= 4.0 * f64::EPSILON * scale,
                "{param:?} {end:?}: {err:e}"
            );
        }
    }
}

#[test]
fn paper_averaged_fragments_do_not_converge() {
    use geomkit::bspline::paper_fragments_averaged;
    let n = 400;
    let pts: Vec<f64> = (0..n)
        .flat_map(|i| [i as f64, (i as f64 * 0.3).sin() * 5.0])
        .collect();
    let exact = paper_fragments_averaged(2, &pts, n, 0).unwrap();
    let mut errors = Vec::new();
    for overlap in [2usize, 8, 16, 32] {
        let avg = paper_fragments_averaged(2, &pts, 100, overlap).unwrap();
        let err = avg
            .iter()
            .zip(&exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        errors.push(err);
    }
    // The error stays near 1% of the data (amplitude 5), however wide the overlap.
    assert!(errors.iter().all(|&e| e > 0.02), "{errors:?}");
    assert!(errors[3] > 0.9 * errors[1], "{errors:?}");
}

/// Batched evaluation (span hints, bucket table, specialized kernels) gives the values of
/// single-point evaluation bit for bit, sorted or not, at knots and outside the domain.
#[test]
fn batched_evaluation_equals_single_points() {
    let mut rng = Rng(17);
    for dim in [1usize, 2, 3, 4] {
        let pts: Vec<Vec<f64>> = (0..300)
            .map(|_| (0..dim).map(|_| 5.0 * rng.uniform()).collect())
            .collect();
        for param in [Parametrization::Uniform, Parametrization::ChordLength] {
            let fit = interpolate_curve(
                &pts,
                &InterpolationOptions::default().with_parametrization(param),
            )
            .unwrap();
            let (a, b) = fit.curve().domain();
            let mut ts: Vec<f64> = (0..5000)
                .map(|_| (a + b) / 2.0 + (b - a + 2.0) / 2.0 * rng.uniform())
                .collect();
            ts.extend(fit.curve().knots().iter().copied());
            // Far outside: the span index is clamped before it is converted.
            ts.extend([a - 1e12, a - 1e6, b + 1e6, b + 1e12]);
            for sorted in [false, true] {
                if sorted {
                    ts.sort_by(f64::total_cmp);
                }
                let mut got = vec![0.0; ts.len() * dim];
                fit.curve().eval_many_par(&ts, &mut got).unwrap();
                for (t, g) in ts.iter().zip(got.chunks_exact(dim)) {
                    assert_eq!(
                        g,
                        fit.curve().eval(*t).as_slice(),
                        "dim {dim} {param:?} t={t}"
                    );
                }
                // The sequential batch runs the same kernels.
                let mut seq = vec![0.0; ts.len() * dim];
                fit.curve()
                    .eval_batch(&ts, &mut seq, &BatchOptions::sequential())
                    .unwrap();
                assert_eq!(seq, got, "dim {dim} {param:?}");
            }
        }
    }
}

/// The bucket table of batched evaluation on very uneven knots: clusters where one bucket
/// holds many knots, a repeated interior knot, and long empty stretches; the spans must be
/// those of single-point evaluation, bit for bit.
#[test]
fn batched_evaluation_on_uneven_knots() {
    let mut rng = Rng(5);
    let mut knots = vec![0.0; 4];
    knots.extend((1..40).map(|k| 1e-6 * k as f64)); // a cluster
    knots.extend([0.3, 0.5, 0.5, 0.5]); // a knot of multiplicity 3
    knots.extend((1..200).map(|k| 0.6 + 0.002 * k as f64));
    knots.extend([1.0; 4]);
    let n_c = knots.len() - 4;
    let control: Vec<Vec<f64>> = (0..n_c)
        .map(|_| vec![rng.uniform(), rng.uniform()])
        .collect();
    let curve = BsplineCurve::new(3, knots.clone(), control).unwrap();
    for count in [2000usize, 50_000] {
        let mut ts: Vec<f64> = (0..count).map(|_| 0.6 * rng.uniform() + 0.5).collect();
        ts.extend(knots.iter().copied());
        ts.extend([-1.0, 2.0, 1e-7, 0.5 - 1e-17]);
        // Unsorted, then sorted (the kernel's path without touch rounds).
        for sorted in [false, true] {
            if sorted {
                ts.sort_by(f64::total_cmp);
            }
            let mut got = vec![0.0; ts.len() * 2];
            curve.eval_many_par(&ts, &mut got).unwrap();
            for (t, g) in ts.iter().zip(got.chunks_exact(2)) {
                assert_eq!(g, curve.eval(*t).as_slice(), "t={t} sorted={sorted}");
            }
            let mut seq = vec![0.0; ts.len() * 2];
            curve
                .eval_batch(&ts, &mut seq, &BatchOptions::sequential())
                .unwrap();
            assert_eq!(seq, got);
        }
    }
}

/// Far from the origin (parameters up to 1e5) the span polynomials must still be formed in
/// local coordinates: samples at exactly representable parameters k/8 against direct
/// evaluation, within the reported bound.
#[test]
fn forward_differences_far_from_the_origin() {
    let n = 100_000;
    let flat: Vec<f64> = (0..n)
        .flat_map(|i| {
            let x = i as f64 * 0.1;
            [x.sin(), (0.7 * x).cos(), 0.001 * x]
        })
        .collect();
    let opts = InterpolationOptions::default().with_parametrization(Parametrization::Uniform);
    let fit = interpolate_curve_flat(3, &flat, &opts).unwrap();
    assert_eq!(fit.curve().domain(), (0.0, (n - 1) as f64));
    let ts: Vec<f64> = (0..8 * (n - 1) + 1).map(|k| k as f64 / 8.0).collect();
    fd_against_direct(fit.curve(), &ts);
}

/// Samples `ts.len()` uniform parameters by forward differences and checks them against
/// direct evaluation at `ts` (the same parameters): within the reported bound plus the
/// direct evaluation's own rounding (a few eps of the scale). Returns (bound, scale).
fn fd_against_direct(curve: &BsplineCurve, ts: &[f64]) -> (f64, f64) {
    let count = ts.len();
    let mut fd = vec![0.0; count * 3];
    let report = curve.sample_uniform_fd(count, &mut fd).unwrap();
    let mut direct = vec![0.0; count * 3];
    curve.eval_many_par(ts, &mut direct).unwrap();
    let err = fd
        .iter()
        .zip(&direct)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(
        err <= report.bound + 8.0 * f64::EPSILON * scale,
        "{count} samples: {err:e} > {:e}",
        report.bound
    );
    (report.bound, scale)
}

#[test]
fn forward_differences_stay_within_their_bound() {
    let pts = wiggly(200, 3, 9);
    for param in [Parametrization::Uniform, Parametrization::ChordLength] {
        let fit = interpolate_curve(
            &pts,
            &InterpolationOptions::default().with_parametrization(param),
        )
        .unwrap();
        for count in [2usize, 7, 1000, 200_001] {
            let (a, b) = fit.curve().domain();
            let ts: Vec<f64> = (0..count)
                .map(|k| a + k as f64 * (b - a) / (count - 1) as f64)
                .collect();
            let (bound, scale) = fd_against_direct(fit.curve(), &ts);
            assert!(bound < 1e-9 * scale, "{param:?} {count}: bound {bound:e}");
        }
    }
    let fit = interpolate_curve(&pts, &InterpolationOptions::default()).unwrap();
    assert!(fit.curve().sample_uniform_fd(1, &mut [0.0; 3]).is_err());
    assert!(fit.curve().sample_uniform_fd(3, &mut [0.0; 3]).is_err());
}

/// Derivative end rows scale like 1/h^k: with tiny chord steps they must not make the
/// system look singular (they are equilibrated).
#[test]
fn tiny_parameter_steps_are_fine() {
    let n = 3000;
    let pts: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64 * 1e-7;
            [t, (t * 1e6).sin() * 1e-6]
        })
        .collect();
    for end in [
        EndCondition::NotAKnot,
        EndCondition::Natural,
        EndCondition::Clamped {
            start: None,
            end: None,
        },
        EndCondition::Bessel,
    ] {
        let opts = InterpolationOptions::default().with_end(end.clone());
        let fit = geomkit::bspline::interpolate_curve_flat(2, &pts, &opts)
            .unwrap_or_else(|e| panic!("{end:?}: {e}"));
        let scale = pts.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (i, &t) in fit.parameters().iter().enumerate().step_by(97) {
            let q = fit.curve().eval(t);
            assert!(
                (q[0] - pts[2 * i]).abs() <= 1e-13 * scale
                    && (q[1] - pts[2 * i + 1]).abs() <= 1e-13 * scale
            );
        }
    }
}

/// A reusable interpolator gives the curves of `interpolate_curve` / `interpolate_curve_at`
/// for every frame it solves, into the caller's buffer, for every end condition, small and
/// large (the parallel one-pass path); bad frames are errors that name the point.
#[test]
fn reusable_interpolator_matches_one_shot_interpolation() {
    let mut rng = Rng(41);
    let ends = [
        EndCondition::NotAKnot,
        EndCondition::Natural,
        EndCondition::Clamped {
            start: None,
            end: Some(vec![1.0, -2.0]),
        },
        EndCondition::Periodic,
        EndCondition::Repeat,
    ];
    for n in [5usize, 40, 70_000] {
        for end in &ends {
            let solver = CurveInterpolator::uniform(n, end).unwrap();
            assert_eq!(solver.n_points(), n);
            let mut control = vec![0.0; solver.n_control() * 2];
            for _frame in 0..2 {
                let pts: Vec<f64> = (0..2 * n).map(|_| 3.0 * rng.uniform()).collect();
                solver.solve_into(&pts, 2, &mut control).unwrap();
                let options = InterpolationOptions::default()
                    .with_end(end.clone())
                    .with_parametrization(Parametrization::Uniform);
                let once = interpolate_curve_flat(2, &pts, &options).unwrap();
                assert_eq!(solver.knots(), once.curve().knots(), "{end:?}");
                assert_eq!(solver.parameters(), once.parameters(), "{end:?}");
                let err = control
                    .iter()
                    .zip(once.curve().control_flat())
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(err <= 1e-14 * 3.0, "n={n} {end:?}: {err:e}");
                // And it interpolates.
                let curve = BsplineCurve::from_flat(3, solver.knots().to_vec(), 2, control.clone())
                    .unwrap();
                for i in (0..n).step_by(n / 5 + 1) {
                    let p = curve.eval(solver.parameters()[i]);
                    assert!(
                        (p[0] - pts[2 * i]).abs() < 1e-13 && (p[1] - pts[2 * i + 1]).abs() < 1e-13
                    );
                }
            }
        }
    }
    // At given, uneven parameters.
    let t: Vec<f64> = (0..50).map(|i| (i as f64).powf(1.3)).collect();
    let y: Vec<f64> = t.iter().map(|x| x.sin()).collect();
    let solver = CurveInterpolator::at(&t, &EndCondition::NotAKnot).unwrap();
    let mut control = vec![0.0; solver.n_control()];
    solver.solve_into(&y, 1, &mut control).unwrap();
    let once = interpolate_curve_at(1, &y, &t, &EndCondition::NotAKnot).unwrap();
    let err = control
        .iter()
        .zip(once.curve().control_flat())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(err < 1e-14, "{err:e}");
    // Bad input.
    let solver = CurveInterpolator::uniform(70_000, &EndCondition::NotAKnot).unwrap();
    let mut pts = vec![0.5; 140_000];
    let mut out = vec![0.0; solver.n_control() * 2];
    assert!(matches!(
        solver.solve_into(&pts[1..], 2, &mut out),
        Err(Error::BufferSize { .. })
    ));
    assert!(matches!(
        solver.solve_into(&pts, 2, &mut out[1..]),
        Err(Error::BufferSize { .. })
    ));
    pts[2 * 31_337 + 1] = f64::NAN;
    match solver.solve_into(&pts, 2, &mut out) {
        Err(Error::NonFinite { index, .. }) => assert_eq!(index, 31_337),
        other => panic!("{other:?}"),
    }
    assert!(CurveInterpolator::at(&[0.0, 1.0, 1.0], &EndCondition::Natural).is_err());
    assert!(CurveInterpolator::uniform(1, &EndCondition::NotAKnot).is_err());
}

/// Large curves at uneven parameters (solved in parallel chunks joined by a reduced system):
/// every end condition interpolates all points to rounding, the factored small-system route
/// agrees on a stretch, and a non-finite point is named.
#[test]
fn large_uneven_curves_interpolate_every_point() {
    let n = 120_000;
    let t: Vec<f64> = (0..n)
        .map(|i| i as f64 + 0.45 * ((i as f64) * 0.7).sin())
        .collect();
    let pts: Vec<f64> = (0..2 * n)
        .map(|k| {
            let x = t[k / 2];
            if k % 2 == 0 {
                (x * 0.01).cos() * 3.0
            } else {
                (x * 0.013).sin() + ((k * 7919) % 13) as f64 * 1e-3
            }
        })
        .collect();
    let ends = [
        EndCondition::NotAKnot,
        EndCondition::Natural,
        EndCondition::Clamped {
            start: Some(vec![0.5, -1.0]),
            end: None,
        },
    ];
    for end in &ends {
        let fit = interpolate_curve_at(2, &pts, &t, end).unwrap();
        let mut worst = 0.0f64;
        for i in 0..n {
            let p = fit.curve().eval(t[i]);
            worst = worst.max((p[0] - pts[2 * i]).abs().max((p[1] - pts[2 * i + 1]).abs()));
        }
        assert!(worst <= 1e-14 * 3.0, "{end:?}: {worst:e}");
        // The reusable system (same route for large N) gives the same control points.
        let solver = CurveInterpolator::at(&t, end).unwrap();
        let mut control = vec![0.0; solver.n_control() * 2];
        solver.solve_into(&pts, 2, &mut control).unwrap();
        assert_eq!(control, fit.curve().control_flat());
    }
    // A small system (factored, sequential) on the first 2000 points agrees with the large
    // one where the ends' influence has died out.
    let small = interpolate_curve_at(2, &pts[..4000], &t[..2000], &EndCondition::Natural).unwrap();
    let large = interpolate_curve_at(2, &pts, &t, &EndCondition::Natural).unwrap();
    let (a, b) = (small.curve().control_flat(), large.curve().control_flat());
    let err = (0..2000).fold(0.0f64, |m, k| m.max((a[k] - b[k]).abs()));
    assert!(err <= 1e-14 * 3.0, "{err:e}");
    let mut bad = pts.clone();
    bad[2 * 98_765] = f64::INFINITY;
    match interpolate_curve_at(2, &bad, &t, &EndCondition::NotAKnot) {
        Err(Error::NonFinite { index, .. }) => assert_eq!(index, 98_765),
        other => panic!("{other:?}"),
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// Uneven parameters over many parallel chunks: every point is interpolated to rounding
    /// (steps varying up to 400-fold), and where the system is well conditioned (steps
    /// varying up to 20-fold, as chord lengths of measured data do) the control points equal
    /// the one-chunk (sequential Thomas) solve of a one-thread pool to rounding. (With wilder
    /// steps random data needs control points 10^5 times the data, and the two elimination
    /// orders differ along directions that hardly move the curve at the data.)
    #[test]
    fn parallel_uneven_solves_equal_the_sequential_one(
        // 2 to 4 chunks of 8192 rows (tridiag.rs: FUSED_CHUNK / 3 coordinates).
        n in 17_000usize..40_000,
        seed in 1u64..u64::MAX,
        end in 0usize..4,
        spread in 0.5f64..3.0,
    ) {
        let mut rng = Rng(seed | 1);
        let mut t = vec![0.0];
        for _ in 1..n {
            let step = (spread * (2.0 * rng.uniform() - 1.0)).exp();
            t.push(t[t.len() - 1] + step);
        }
        let pts: Vec<f64> = (0..3 * n).map(|_| rng.uniform() - 0.5).collect();
        let end = [
            EndCondition::NotAKnot,
            EndCondition::Natural,
            EndCondition::Clamped { start: None, end: None },
            EndCondition::Bessel,
        ][end]
            .clone();
        let par = interpolate_curve_at(3, &pts, &t, &end).unwrap();
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let seq = one.install(|| interpolate_curve_at(3, &pts, &t, &end)).unwrap();
        let (a, b) = (par.curve().control_flat(), seq.curve().control_flat());
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if spread <= 1.5 {
            let err = a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            proptest::prop_assert!(err <= 64.0 * f64::EPSILON * scale, "{err:e} of {scale:e}");
        }
        let mut worst = 0.0f64;
        for i in 0..n {
            let p = par.curve().eval(t[i]);
            for c in 0..3 {
                worst = worst.max((p[c] - pts[3 * i + c]).abs());
            }
        }
        proptest::prop_assert!(
            worst <= 16.0 * f64::EPSILON * scale.max(1.0),
            "residual {worst:e}, control {scale:e}"
        );
    }
}

/// The distance of the library's parametrizations written out plainly: the root of the sum
/// of squares, or scaled by the largest difference when that sum overflowed or nearly
/// underflowed.
fn plain_distance(a: &[f64], b: &[f64]) -> f64 {
    let s = a.iter().zip(b).fold(0.0, |s, (x, y)| s + (x - y) * (x - y));
    if s.is_finite() && s >= 2f64.powi(-900) {
        return s.sqrt();
    }
    let m = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    let r = a
        .iter()
        .zip(b)
        .fold(0.0, |s, (x, y)| s + ((x - y) / m) * ((x - y) / m));
    m * r.sqrt()
}

#[test]
fn parameters_are_running_sums_bit_for_bit() {
    // Several chunks of the parallel pass, dimensions with and without their own loop, and
    // stretches whose sums of squares overflow (1e160) or nearly underflow (1e-170).
    let n = 40_000;
    for dim in [1, 2, 3, 5] {
        let mut pts: Vec<f64> = wiggly(n, dim, 7 + dim as u64).concat();
        for v in &mut pts[1000 * dim..1010 * dim] {
            *v *= 1e160;
        }
        for (k, v) in pts[30_000 * dim..30_010 * dim].iter_mut().enumerate() {
            *v = (1 + k) as f64 * 1e-170;
        }
        for kind in [Parametrization::ChordLength, Parametrization::Centripetal] {
            for closed in [false, true] {
                let t = parameters(&pts, dim, kind, closed).unwrap();
                assert_eq!(t.len(), n + usize::from(closed));
                let mut want = vec![0.0];
                for i in 1..t.len() {
                    let j = if i == n { 0 } else { i };
                    let d =
                        plain_distance(&pts[(i - 1) * dim..i * dim], &pts[j * dim..(j + 1) * dim]);
                    let step = if kind == Parametrization::Centripetal {
                        d.sqrt()
                    } else {
                        d
                    };
                    want.push(want[i - 1] + step);
                }
                assert_eq!(t, want, "dim {dim}, {kind:?}, closed {closed}");
            }
        }
        // Errors name the first offending point, wherever its chunk.
        let mut dup = pts.clone();
        for k in [35_000, 20_000] {
            let (a, b) = dup.split_at_mut(k * dim);
            b[..dim].copy_from_slice(&a[(k - 1) * dim..]);
        }
        let err = parameters(&dup, dim, Parametrization::ChordLength, false).unwrap_err();
        assert_eq!(err, Error::RepeatedPoint { index: 19_999 }, "dim {dim}");
        let mut bad = pts.clone();
        bad[25_000 * dim] = f64::INFINITY;
        bad[33_000 * dim] = f64::NAN;
        match parameters(&bad, dim, Parametrization::Centripetal, true) {
            Err(Error::NonFinite { index, .. }) => assert_eq!(index, 25_000, "dim {dim}"),
            other => panic!("{other:?}"),
        }
    }
}

/// An interior knot of multiplicity 4, where the curve jumps from 0 to 1: batched
/// evaluation of sorted parameters (blocks that cross a few knots, whose spans are counted
/// rather than looked up) takes the value on the right of the knot, as single-point
/// evaluation does, bit for bit.
#[test]
fn batched_sorted_evaluation_at_a_jump() {
    let mut knots = vec![0.0; 4];
    knots.extend((1..20).map(|k| k as f64 * 0.02));
    knots.extend([0.5; 4]);
    knots.extend((1..20).map(|k| 0.5 + k as f64 * 0.02));
    knots.extend([1.0; 4]);
    let n_c = knots.len() - 4;
    let control: Vec<Vec<f64>> = (0..n_c)
        .map(|i| vec![if i < n_c / 2 { 0.0 } else { 1.0 }])
        .collect();
    let curve = BsplineCurve::new(3, knots, control).unwrap();
    let ts: Vec<f64> = (0..=10_000).map(|i| i as f64 / 10_000.0).collect();
    let mut got = vec![0.0; ts.len()];
    curve.eval_many_par(&ts, &mut got).unwrap();
    for (t, g) in ts.iter().zip(&got) {
        assert_eq!(*g, curve.eval(*t)[0], "t = {t}");
    }
    assert_eq!(got[5000], 1.0, "the value at the jump is the right piece's");
    assert_eq!(got[4999], 0.0);
}

/// Blocks of 64 parameters within a few knot spans, which batched evaluation takes from
/// small tables of the block's knots and control points (AVX-512): every block crossing
/// 0 to 14 knots (the tables serve at most 10: wider blocks are split), sorted, shuffled or
/// sorted but for one parameter, around a knot of
/// multiplicity 3, at the first and last spans and beyond the domain, in dimensions 1 to 3
/// — the values of single-point evaluation, bit for bit.
#[test]
fn batched_evaluation_of_narrow_blocks() {
    let mut rng = Rng(23);
    let mut knots = vec![0.0; 4];
    let mut k = 0.0;
    for i in 0..60 {
        k += 0.5 + rng.uniform().abs();
        knots.push(k);
        if i == 30 {
            knots.extend([k, k]);
        }
    }
    let end = k + 1.0;
    knots.extend([end; 4]);
    let n_c = knots.len() - 4;
    let h = end / 60.0;
    for dim in [1usize, 2, 3] {
        let control: Vec<Vec<f64>> = (0..n_c)
            .map(|_| (0..dim).map(|_| rng.uniform()).collect())
            .collect();
        let curve = BsplineCurve::new(3, knots.clone(), control).unwrap();
        let mut ts = Vec::new();
        for block in 0..600 {
            let width = h * (block % 15) as f64 * (0.8 + 0.2 * rng.uniform().abs());
            let centre = match block % 10 {
                0 => 0.0,
                1 => end,
                2 => knots[4 + 31],
                _ => (1.2 * rng.uniform().abs() - 0.1) * end,
            };
            let mut b: Vec<f64> = (0..64)
                .map(|_| centre + width / 2.0 * rng.uniform())
                .collect();
            b[7] = knots[(4 + block % n_c).min(knots.len() - 1)];
            if block % 2 == 0 {
                b.sort_by(f64::total_cmp);
            }
            if block % 6 == 4 {
                // Sorted but for one late parameter past the last.
                b[60] = b[63] + h;
            }
            ts.extend(b);
        }
        let mut got = vec![0.0; ts.len() * dim];
        curve.eval_many_par(&ts, &mut got).unwrap();
        for (i, (t, g)) in ts.iter().zip(got.chunks_exact(dim)).enumerate() {
            assert_eq!(
                g,
                curve.eval(*t).as_slice(),
                "dim {dim} block {} t={t}",
                i / 64
            );
        }
        let mut seq = vec![0.0; ts.len() * dim];
        curve
            .eval_batch(&ts, &mut seq, &BatchOptions::sequential())
            .unwrap();
        assert_eq!(seq, got, "dim {dim}");
    }
}

/// Batched evaluation checks the parameters chunk by chunk, in parallel: the error names
/// the first that is not finite, whichever chunk finds one first.
#[test]
fn batched_evaluation_names_the_first_non_finite_parameter() {
    let pts = wiggly(50, 2, 3);
    let fit = interpolate_curve(&pts, &InterpolationOptions::default()).unwrap();
    let (a, b) = fit.curve().domain();
    let mut ts: Vec<f64> = (0..40_000)
        .map(|i| a + (b - a) * i as f64 / 40_000.0)
        .collect();
    ts[31_000] = f64::NAN;
    ts[9_000] = f64::NEG_INFINITY;
    ts[20_000] = f64::NAN;
    let mut out = vec![0.0; ts.len() * 2];
    match fit.curve().eval_many_par(&ts, &mut out) {
        Err(Error::NonFinite { index, .. }) => assert_eq!(index, 9_000),
        other => panic!("{other:?}"),
    }
}
