//! The piecewise polynomial form of B-spline curves (`PiecewiseCurve`) against the B-spline
//! form it comes from.

mod common;

use common::Rng;
use geomkit::bspline::{
    interpolate_curve, BsplineCurve, EndCondition, InterpolationOptions, Parametrization,
    PiecewiseCurve,
};
use geomkit::geom::{BatchOptions, Curve};
use geomkit::Error;

/// Largest |coordinate| of the control points: the scale of the curve's values.
fn scale(curve: &BsplineCurve) -> f64 {
    curve
        .control_flat()
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Evaluates `pp` at `ts` in parallel and checks it: the same bits sequentially and point by
/// point, and within `tol` of the B-spline. Returns the largest difference.
fn check(pp: &PiecewiseCurve, curve: &BsplineCurve, ts: &[f64], tol: f64, what: &str) -> f64 {
    let d = curve.dim();
    let mut got = vec![0.0; ts.len() * d];
    pp.eval_many_par(ts, &mut got).unwrap();
    let mut seq = vec![0.0; ts.len() * d];
    pp.eval_batch(ts, &mut seq, &BatchOptions::sequential())
        .unwrap();
    assert_eq!(seq, got, "{what}: sequential batch");
    let mut worst = 0.0f64;
    for (t, g) in ts.iter().zip(got.chunks_exact(d)) {
        assert_eq!(g, pp.eval(*t).as_slice(), "{what}: t={t} point by point");
        for (a, b) in g.iter().zip(curve.eval(*t)) {
            worst = worst.max((a - b).abs());
        }
    }
    assert!(worst <= tol, "{what}: {worst:e} > {tol:e}");
    worst
}

/// Random parameters over the domain and its ends, the knots, unsorted then sorted.
fn params(curve: &BsplineCurve, count: usize, rng: &mut Rng) -> Vec<f64> {
    let (a, b) = curve.domain();
    let mut ts: Vec<f64> = (0..count)
        .map(|_| a + (b - a) * (rng.uniform() + 1.0) / 2.0)
        .collect();
    ts.extend(
        curve
            .knots()
            .iter()
            .copied()
            .filter(|t| (a..=b).contains(t)),
    );
    ts.extend([a, b]);
    ts
}

#[test]
fn agrees_with_the_bspline_for_every_end_parametrization_and_dimension() {
    let mut rng = Rng(23);
    let mut worst = 0.0f64;
    for dim in [1usize, 2, 3, 5] {
        let pts: Vec<Vec<f64>> = (0..400)
            .map(|i| {
                let mut p: Vec<f64> = (0..dim).map(|_| 3.0 * rng.uniform()).collect();
                p[0] += i as f64 * (1.0 + rng.uniform());
                p
            })
            .collect();
        for param in common::PARAMETRIZATIONS {
            for end in [
                EndCondition::NotAKnot,
                EndCondition::Natural,
                EndCondition::Periodic,
            ] {
                let opts = InterpolationOptions::default()
                    .with_parametrization(param)
                    .with_end(end.clone());
                let curve = interpolate_curve(&pts, &opts).unwrap().into_curve();
                let pp = curve.to_piecewise().unwrap();
                assert_eq!(pp.dim(), dim);
                assert_eq!(pp.domain(), curve.domain());
                let mut ts = params(&curve, 20_000, &mut rng);
                let tol = 32.0 * f64::EPSILON * scale(&curve);
                for sorted in [false, true] {
                    if sorted {
                        ts.sort_by(f64::total_cmp);
                    }
                    let what = format!("dim {dim} {param:?} {end:?} sorted {sorted}");
                    worst = worst.max(check(&pp, &curve, &ts, tol, &what) / scale(&curve));
                }
            }
        }
    }
    // Not a test that passes by a wide tolerance only: the forms differ by a few ulps.
    assert!(worst > 0.0 && worst <= 8.0 * f64::EPSILON, "{worst:e}");
}

/// The span table on very uneven knots: a cluster of knots in one bucket, a knot of
/// multiplicity 3 (zero-width pieces), long empty stretches; parameters at and next to the
/// knots, and past both ends of the domain (the end pieces extend as the B-spline's do).
#[test]
fn uneven_knots_repeated_knots_and_extrapolation() {
    let mut rng = Rng(5);
    let mut knots = vec![0.0; 4];
    knots.extend((1..40).map(|k| 1e-6 * k as f64));
    knots.extend([0.3, 0.5, 0.5, 0.5]);
    knots.extend((1..200).map(|k| 0.6 + 0.002 * k as f64));
    knots.extend([1.0; 4]);
    let n_c = knots.len() - 4;
    let control: Vec<Vec<f64>> = (0..n_c)
        .map(|_| vec![rng.uniform(), rng.uniform()])
        .collect();
    let curve = BsplineCurve::new(3, knots.clone(), control).unwrap();
    let pp = curve.to_piecewise().unwrap();
    // Spans over the domain, the empty ones included; consecutive pieces share their ends.
    assert_eq!(pp.n_pieces(), n_c - 3);
    for i in 1..pp.n_pieces() {
        assert_eq!(pp.piece(i - 1).1, pp.piece(i).0);
    }
    let mut ts = params(&curve, 50_000, &mut rng);
    for &k in &knots {
        ts.extend([k - 1e-12, k + 1e-12, k.next_up(), k.next_down()]);
    }
    ts.extend([1e-7, 0.5 - 1e-17, 0.5]);
    let tol = 64.0 * f64::EPSILON * scale(&curve);
    for sorted in [false, true] {
        if sorted {
            ts.sort_by(f64::total_cmp);
        }
        check(&pp, &curve, &ts, tol, &format!("sorted {sorted}"));
    }
    // Outside the domain the end pieces' cubics grow (the first one spans 1e-6, so at -0.01
    // its values are ~1e12), and the rounding with them.
    let far = [-0.5, -0.01, -1e-9, 1.0 + 1e-9, 1.01, 1.3, 2.0];
    let big = far.iter().fold(0.0f64, |m, t| {
        m.max(curve.eval(*t).iter().fold(0.0f64, |m, v| m.max(v.abs())))
    });
    check(&pp, &curve, &far, 1e-12 * big, "far outside");
}

#[test]
fn lower_degrees_and_uniform_knots() {
    let mut rng = Rng(99);
    for degree in [1usize, 2, 3] {
        for uniform in [true, false] {
            let n_c = 500;
            let knots: Vec<f64> = if uniform {
                // Uniform throughout (no repeated end knots).
                (0..n_c + degree + 1)
                    .map(|k| k as f64 * 0.25 - 3.0)
                    .collect()
            } else {
                // Clamped ends, uneven steps between.
                let mut t = 0.0;
                let mut k = vec![0.0; degree + 1];
                for _ in 0..n_c - degree - 1 {
                    t += 0.05 + rng.uniform().abs();
                    k.push(t);
                }
                k.extend(vec![t + 1.0; degree + 1]);
                k
            };
            let control: Vec<f64> = (0..3 * n_c).map(|_| 10.0 * rng.uniform()).collect();
            let curve = BsplineCurve::from_flat(degree, knots, 3, control).unwrap();
            assert_eq!(curve.is_uniform(), uniform);
            let pp = curve.to_piecewise().unwrap();
            assert_eq!(pp.degree(), degree);
            // Coefficients above the degree are zero.
            for i in 0..pp.n_pieces() {
                assert!(pp.piece(i).2[3 * (degree + 1)..].iter().all(|c| *c == 0.0));
            }
            let mut ts = params(&curve, 10_000, &mut rng);
            let tol = 32.0 * f64::EPSILON * scale(&curve);
            for sorted in [false, true] {
                if sorted {
                    ts.sort_by(f64::total_cmp);
                }
                check(
                    &pp,
                    &curve,
                    &ts,
                    tol,
                    &format!("degree {degree} uniform {uniform}"),
                );
            }
        }
    }
}

#[test]
fn pieces_and_derivatives() {
    let mut rng = Rng(7);
    let pts: Vec<Vec<f64>> = (0..60)
        .map(|i| {
            vec![
                i as f64 + rng.uniform(),
                (i as f64 / 5.0).sin(),
                rng.uniform(),
            ]
        })
        .collect();
    let opts = InterpolationOptions::default().with_parametrization(Parametrization::ChordLength);
    let curve = interpolate_curve(&pts, &opts).unwrap().into_curve();
    let pp = curve.to_piecewise().unwrap();
    let s = scale(&curve);
    for i in 0..pp.n_pieces() {
        let (t0, t1, c) = pp.piece(i);
        assert!(t0 < t1);
        // c_0 is the value at the left end, and the cubic reaches the right end's value.
        let (p0, p1) = (curve.eval(t0), curve.eval(t1));
        let h = t1 - t0;
        for j in 0..3 {
            assert!((c[j] - p0[j]).abs() <= 4.0 * f64::EPSILON * s);
            let end = ((c[9 + j] * h + c[6 + j]) * h + c[3 + j]) * h + c[j];
            assert!((end - p1[j]).abs() <= 32.0 * f64::EPSILON * s, "piece {i}");
        }
    }
    let (a, b) = curve.domain();
    for k in 0..=4 {
        let mut worst = 0.0f64;
        let mut size = 0.0f64;
        for m in 0..2000 {
            let t = a + (b - a) * m as f64 / 1999.0;
            let (mut x, mut y) = ([0.0; 3], [0.0; 3]);
            pp.eval_derivative(t, k, &mut x);
            curve.eval_derivative(t, k, &mut y);
            for j in 0..3 {
                worst = worst.max((x[j] - y[j]).abs());
                size = size.max(y[j].abs());
            }
        }
        if k == 4 {
            assert_eq!(size, 0.0);
        }
        assert!(
            worst <= 1e-12 * size.max(s),
            "derivative {k}: {worst:e} of {size:e}"
        );
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let quartic =
        BsplineCurve::from_flat(4, (0..12).map(f64::from).collect(), 1, vec![0.0; 7]).unwrap();
    assert!(matches!(
        quartic.to_piecewise(),
        Err(Error::InvalidOption {
            option: "degree",
            ..
        })
    ));
    let curve =
        BsplineCurve::from_flat(3, (0..12).map(f64::from).collect(), 2, vec![1.0; 16]).unwrap();
    let pp = curve.to_piecewise().unwrap();
    let mut out = vec![0.0; 6];
    match pp.eval_many_par(&[4.0, f64::NAN, 5.0], &mut out) {
        Err(Error::NonFinite { index: 1, .. }) => {}
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        pp.eval_batch(&[4.0, 5.0], &mut out, &BatchOptions::sequential()),
        Err(Error::BufferSize {
            expected: 4,
            got: 6
        })
    ));
    // No parameters: nothing to do.
    pp.eval_many_par(&[], &mut []).unwrap();
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// Random knot vectors (steps spread over four decades, some knots repeated) and
    /// control points: the piecewise form agrees with the B-spline at random parameters.
    #[test]
    fn random_knots_agree(seed in 1u64..u64::MAX, n_c in 4usize..300, spread in 0.0f64..4.0) {
        let mut rng = Rng(seed | 1);
        let mut knots = vec![0.0; 4];
        let (mut t, mut repeats) = (0.0, 0);
        for _ in 0..n_c - 4 {
            // One knot in ten repeats the previous one, at most twice (multiplicity 3: the
            // curve stays continuous).
            if rng.uniform() > -0.8 || repeats == 2 {
                t += (spread * std::f64::consts::LN_10 * rng.uniform()).exp();
                repeats = 0;
            } else {
                repeats += 1;
            }
            knots.push(t);
        }
        let last = knots[knots.len() - 1] + 1.0;
        knots.extend([last; 4]);
        let control: Vec<f64> = (0..2 * n_c).map(|_| rng.uniform()).collect();
        let curve = BsplineCurve::from_flat(3, knots, 2, control).unwrap();
        let pp = curve.to_piecewise().unwrap();
        let ts = params(&curve, 3000, &mut rng);
        check(&pp, &curve, &ts, 64.0 * f64::EPSILON * scale(&curve), "random knots");
    }
}
