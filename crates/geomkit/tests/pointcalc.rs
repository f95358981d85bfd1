//! Method 4 (spec/point-calculus.md): the paper's equations exactly, interpolation properties,
//! accuracy, surfaces through nine points, k-factor models, shares.

use geomkit::exact::Rational;
use geomkit::geom::Curve;
use geomkit::pointcalc::{
    printed_geomatrix, printed_geomatrix_exact, Factor, Hypersurface, NodePreset, Nodes,
    PointEquation, PointOptions, PointSurface, PrintedSurface,
};
use num_traits::{One, Zero};
use proptest::prelude::*;

fn q(p: i64, d: i64) -> Rational {
    Rational::new(p.into(), d.into())
}

/// Power coefficients of a product of polynomials (coefficient lists, lowest first).
fn product(factors: &[Vec<Rational>]) -> Vec<Rational> {
    let mut out = vec![Rational::one()];
    for f in factors {
        let mut next = vec![Rational::zero(); out.len() + f.len() - 1];
        for (i, a) in out.iter().enumerate() {
            for (j, b) in f.iter().enumerate() {
                next[i + j] += a * b;
            }
        }
        out = next;
    }
    out
}

#[test]
fn equations_1_to_3_have_the_printed_coefficients() {
    // t̄ = 1 - t, written as coefficient lists.
    let tbar = vec![q(1, 1), q(-1, 1)];
    let t = vec![q(0, 1), q(1, 1)];
    let c = |x: Rational| vec![x];
    let lin = |a: i64, b: i64| vec![q(a, 1), q(b, 1)]; // a + b t
    let printed: [(Nodes, [Vec<Rational>; 3]); 3] = [
        // (1) M = A t̄(1 - 2t) + C 4tt̄ + B t(2t - 1)
        (
            Nodes::paper_half(),
            [
                product(&[tbar.clone(), lin(1, -2)]),
                product(&[c(q(4, 1)), t.clone(), tbar.clone()]),
                product(&[t.clone(), lin(-1, 2)]),
            ],
        ),
        // (2) M = A t̄(1 - 3t) + C 4.5tt̄ + B 0.5t(3t - 1)
        (
            Nodes::paper_third(),
            [
                product(&[tbar.clone(), lin(1, -3)]),
                product(&[c(q(9, 2)), t.clone(), tbar.clone()]),
                product(&[c(q(1, 2)), t.clone(), lin(-1, 3)]),
            ],
        ),
        // (3) M = A 0.5t̄(2 - 3t) + C 4.5tt̄ + B t(3t - 2)
        (
            Nodes::paper_two_thirds(),
            [
                product(&[c(q(1, 2)), tbar.clone(), lin(2, -3)]),
                product(&[c(q(9, 2)), t.clone(), tbar.clone()]),
                product(&[t.clone(), lin(-2, 3)]),
            ],
        ),
    ];
    for (nodes, want) in printed {
        assert_eq!(nodes.cardinal_polynomials(), want.to_vec());
    }
}

#[test]
fn b_functions_are_one_at_their_node_and_zero_at_the_others() {
    let sets = [
        Nodes::paper_half(),
        Nodes::paper_third(),
        Nodes::paper_two_thirds(),
        Nodes::preset(NodePreset::ChebyshevFirst, 17, -2.0, 5.0).unwrap(),
        Nodes::new(vec![-1.0, 0.001, 0.002, 3.0, 1e3]).unwrap(),
    ];
    for nodes in &sets {
        let exact = nodes.exact_values();
        for (i, &t) in nodes.values().iter().enumerate() {
            let l = nodes.basis(t);
            for (j, v) in l.iter().enumerate() {
                assert_eq!(*v, if i == j { 1.0 } else { 0.0 });
            }
            let le = nodes.basis_exact(&exact[i]);
            for (j, v) in le.iter().enumerate() {
                assert_eq!(*v, if i == j { q(1, 1) } else { q(0, 1) });
            }
        }
    }
}

#[test]
fn exact_weights_sum_to_one() {
    for nodes in [Nodes::paper_third(), Nodes::paper_two_thirds()] {
        for t in [q(1, 7), q(-3, 2), q(5, 4)] {
            let s: Rational = nodes.basis_exact(&t).iter().sum();
            assert_eq!(s, q(1, 1));
        }
    }
}

#[test]
fn polynomials_of_lower_degree_are_reproduced() {
    // p(t) = Σ c_k t^k of degree n - 1 on n Chebyshev / paper / irregular nodes.
    let poly = |c: &[f64], t: f64| c.iter().rev().fold(0.0, |acc, ck| acc * t + ck);
    let cases: Vec<(Nodes, Vec<f64>)> = vec![
        (Nodes::paper_third(), vec![0.3, -1.2, 2.5]),
        (
            Nodes::preset(NodePreset::ChebyshevSecond, 12, -1.0, 1.0).unwrap(),
            (0..12)
                .map(|k| ((k * 7 % 5) as f64 - 2.0) / (k + 1) as f64)
                .collect(),
        ),
        (
            Nodes::preset(NodePreset::ChebyshevFirst, 9, 2.0, 4.0).unwrap(),
            vec![1.0, -0.5, 0.25, 0.1, -0.05, 0.01, 0.002, -0.001, 0.0005],
        ),
    ];
    for (nodes, c) in cases {
        let points: Vec<Vec<f64>> = nodes.values().iter().map(|&t| vec![poly(&c, t)]).collect();
        let eq = PointEquation::new(nodes.clone(), points).unwrap();
        let (a, b) = nodes.domain();
        let scale = (0..=200)
            .map(|k| poly(&c, a + (b - a) * k as f64 / 200.0).abs())
            .fold(0.0, f64::max);
        for k in 0..=200 {
            let t = a + (b - a) * k as f64 / 200.0;
            let err = (eq.eval(t)[0] - poly(&c, t)).abs();
            assert!(
                err <= 1e-13 * scale,
                "n = {}, t = {t}: {err:e}",
                nodes.len()
            );
        }
    }
}

#[test]
fn runge_function_on_160_chebyshev_nodes() {
    let runge = |t: f64| 1.0 / (1.0 + 25.0 * t * t);
    for preset in [NodePreset::ChebyshevFirst, NodePreset::ChebyshevSecond] {
        let nodes = Nodes::preset(preset, 160, -1.0, 1.0).unwrap();
        let points = nodes.values().iter().map(|&t| vec![runge(t)]).collect();
        let eq = PointEquation::new(nodes, points).unwrap();
        assert!(eq.warnings().is_empty());
        let worst = (0..=4000)
            .map(|k| {
                let t = -1.0 + 2.0 * k as f64 / 4000.0;
                (eq.eval(t)[0] - runge(t)).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst <= 1e-13, "{preset:?}: {worst:e}");
    }
}

#[test]
fn equispaced_runge_oscillates_and_warns() {
    let nodes = Nodes::preset(NodePreset::Equispaced, 21, -1.0, 1.0).unwrap();
    assert!(nodes.lebesgue_constant() > 1e4);
    let points = nodes
        .values()
        .iter()
        .map(|&t| vec![1.0 / (1.0 + 25.0 * t * t)])
        .collect();
    let eq = PointEquation::new(nodes, points).unwrap();
    assert_eq!(eq.warnings().len(), 1);
    assert!(eq.eval(0.975)[0].abs() > 10.0);
}

#[test]
fn three_point_lebesgue_warning_threshold() {
    // t_C = 0.1: Λ ≈ 5.05 > 4 + (2/π) ln 3 ≈ 4.70; t_C = 1/3: Λ = 5/3.
    let close = Nodes::three_point(q(1, 10)).unwrap();
    assert!((close.lebesgue_constant() - 5.05).abs() < 1e-6);
    assert!(close.lebesgue_constant() > close.default_lebesgue_limit());
    let third = Nodes::paper_third();
    assert!((third.lebesgue_constant() - 5.0 / 3.0).abs() < 1e-9);
    let strict = PointOptions::default().with_strict(true);
    let pts = vec![vec![0.0], vec![1.0], vec![0.0]];
    assert!(PointEquation::with_options(close, pts.clone(), &strict).is_err());
    assert!(PointEquation::with_options(third, pts, &strict).is_ok());
}

fn nine_points() -> Vec<Vec<Vec<f64>>> {
    (0..3)
        .map(|i| {
            (0..3)
                .map(|j| {
                    vec![
                        j as f64 + 0.1 * i as f64,
                        i as f64,
                        [[0.0, 0.4, 0.1], [0.5, 1.5, 0.3], [0.2, 0.6, 0.0]][i][j],
                    ]
                })
                .collect()
        })
        .collect()
}

#[test]
fn nine_point_surface_passes_through_all_points_for_every_placement() {
    let placements = [
        Nodes::paper_half(),
        Nodes::paper_third(),
        Nodes::paper_two_thirds(),
    ];
    let net = nine_points();
    let mut count = 0;
    for a in 0..3 {
        for b in 0..3 {
            for c in 0..3 {
                for across in &placements {
                    let rows = vec![
                        placements[a].clone(),
                        placements[b].clone(),
                        placements[c].clone(),
                    ];
                    let s =
                        PointSurface::rows_then_across(rows.clone(), across.clone(), net.clone())
                            .unwrap();
                    for i in 0..3 {
                        for j in 0..3 {
                            let (u, v) = (rows[i].values()[j], across.values()[i]);
                            assert_eq!(s.eval(u, v), net[i][j]);
                        }
                    }
                    for (u, v) in [(0.5, 0.5), (0.2, 0.9), (0.77, 0.1)] {
                        let sum: f64 = s.shares(u, v).iter().flatten().sum();
                        assert!((sum - 1.0).abs() < 1e-15);
                    }
                    count += 1;
                }
            }
        }
    }
    assert_eq!(count, 81);
}

#[test]
fn printed_geomatrix_is_not_affine_invariant() {
    let a = printed_geomatrix_exact(&q(1, 2), &q(1, 2));
    assert_eq!(a[0][0], q(1, 16));
    let sum: Rational = a.iter().flatten().sum();
    assert_eq!(sum, q(37, 32)); // 1.156..., not 1
    let f = printed_geomatrix(0.5, 0.5);
    assert_eq!(f.iter().flatten().sum::<f64>(), 1.15625);
    // So the printed surface misses the centre point; rows-then-across hits it.
    let net = nine_points();
    let printed = PrintedSurface::new(net.clone()).unwrap();
    let p = printed.eval(0.5, 0.5);
    // x = 1/16·0 + 1/64·2 + 1.1 + 1/64·0.2 + 1/16·2.2 = 1.271875 instead of 1.1 of A_22.
    assert!((p[0] - 1.271875).abs() < 1e-14, "{p:?}");
    let rows = vec![
        Nodes::paper_third(),
        Nodes::paper_half(),
        Nodes::paper_two_thirds(),
    ];
    let s = PointSurface::rows_then_across(rows, Nodes::paper_half(), net.clone()).unwrap();
    assert_eq!(s.eval(0.5, 0.5), net[1][1]);
}

#[test]
fn tensor_surface_equals_rows_then_across_with_shared_nodes() {
    let u = Nodes::preset(NodePreset::ChebyshevSecond, 4, 0.0, 1.0).unwrap();
    let v = Nodes::paper_third();
    let net: Vec<Vec<Vec<f64>>> = (0..3)
        .map(|i| {
            (0..4)
                .map(|j| vec![(i * j) as f64 * 0.3, (i + j) as f64])
                .collect()
        })
        .collect();
    let s = PointSurface::tensor(u.clone(), v.clone(), net.clone()).unwrap();
    // The same model as a 2-factor hypersurface with 2-D source points.
    let values: Vec<f64> = net.iter().flatten().flatten().copied().collect();
    let h = Hypersurface::new(
        vec![Factor::new("v", v), Factor::new("u", u)],
        2,
        values,
        &PointOptions::default(),
    )
    .unwrap();
    for (uu, vv) in [(0.1, 0.2), (0.6, 0.95), (1.0, 0.0)] {
        let a = s.eval(uu, vv);
        let b = h.eval(&[vv, uu]).unwrap();
        assert!((a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14);
    }
    let mut out = vec![0.0; 2 * 3 * 2];
    s.eval_grid(&[0.0, 0.5], &[0.0, 0.5, 1.0], &mut out)
        .unwrap();
    assert_eq!(&out[..2], &net[0][0][..]);
    assert!(s.eval_grid(&[0.0], &[f64::NAN], &mut [0.0; 2]).is_err());
}

fn three_factor_model() -> (Hypersurface, Vec<Vec<f64>>) {
    let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
    let mut records = Vec::new();
    for a in [10.0f64, 20.0, 40.0] {
        for b in [0.1, 0.5, 0.9, 1.0] {
            for c in [-1.0, 1.0] {
                records.push(vec![
                    a,
                    b,
                    c,
                    (a / 10.0).ln() * b + c * b * b - 0.01 * a * c,
                ]);
            }
        }
    }
    let model =
        Hypersurface::from_records(&names, &records, &[], &PointOptions::default()).unwrap();
    (model, records)
}

#[test]
fn k_factor_model_passes_through_every_experimental_point() {
    let (model, records) = three_factor_model();
    assert_eq!(model.shape(), vec![3, 4, 2]);
    for r in &records {
        assert_eq!(model.eval(&r[..3]).unwrap(), vec![r[3]]);
    }
    let mut out = vec![0.0; records.len()];
    let xs: Vec<f64> = records.iter().flat_map(|r| r[..3].to_vec()).collect();
    model.eval_many(&xs, &mut out).unwrap();
    for (o, r) in out.iter().zip(&records) {
        assert_eq!(*o, r[3]);
    }
}

#[test]
fn batched_evaluation_equals_single_points() {
    let (model, _) = three_factor_model();
    // 103 points (not a multiple of the 4-point blocks), some outside the box, some on nodes.
    let xs: Vec<f64> = (0..103 * 3)
        .map(|i| match i % 3 {
            0 => 5.0 + (i as f64 * 0.37) % 40.0,
            1 => (i as f64 * 0.053) % 1.1,
            _ => {
                if i % 7 == 0 {
                    1.0
                } else {
                    -1.2 + (i as f64 * 0.11) % 2.4
                }
            }
        })
        .collect();
    let mut out = vec![0.0; 103];
    model.eval_many(&xs, &mut out).unwrap();
    for (x, o) in xs.chunks_exact(3).zip(&out) {
        let want = model.eval(x).unwrap()[0];
        assert!(
            (o - want).abs() <= 1e-14 * want.abs().max(1.0),
            "{x:?}: {o} vs {want}"
        );
    }
}

#[test]
fn removing_a_level_and_adding_it_back_returns_the_same_model() {
    let (model, _) = three_factor_model();
    for factor in 0..3 {
        for level in 0..model.shape()[factor] {
            let value = model.factors()[factor].nodes().values()[level];
            let slice = model.level_slice(factor, level).unwrap();
            let smaller = model.remove_level(factor, level).unwrap();
            assert_eq!(smaller.shape()[factor], model.shape()[factor] - 1);
            let back = smaller.add_level(factor, value, &slice).unwrap();
            assert_eq!(back, model, "factor {factor}, level {level}");
        }
    }
}

#[test]
fn removing_and_adding_factors() {
    let (model, records) = three_factor_model();
    // Keep c = 1 (level 1): a 2-factor model equal to the 3-factor one at c = 1.
    let section = model.remove_factor(2, 1).unwrap();
    assert_eq!(section.k(), 2);
    let fixed = model.fix_factor(2, 1.0).unwrap();
    assert_eq!(section, fixed);
    for x in [[12.0, 0.3], [35.0, 0.95]] {
        let want = model.eval(&[x[0], x[1], 1.0]).unwrap()[0];
        assert!((section.eval(&x).unwrap()[0] - want).abs() < 1e-13);
    }
    // Add the factor back from its two sections.
    let slices = vec![
        model.level_slice(2, 0).unwrap(),
        model.level_slice(2, 1).unwrap(),
    ];
    let c = model.factors()[2].clone();
    let back = section.add_factor(2, c, &slices).unwrap();
    assert_eq!(back, model);
    assert!(model.add_level(0, 20.0, &[0.0; 8]).is_err()); // level already there
    assert!(model.remove_level(5, 0).is_err());
    assert!(model.factor_index("d").is_err());
    assert_eq!(records.len(), 24);
}

#[test]
fn shares_are_first_class_and_sum_to_one() {
    let (model, _) = three_factor_model();
    let x = [15.0, 0.7, 0.2];
    let shares = model.shares(&x).unwrap();
    assert_eq!(shares.len(), 24);
    assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    let combined: f64 = shares.iter().zip(model.values()).map(|(s, v)| s * v).sum();
    assert!((combined - model.eval(&x).unwrap()[0]).abs() < 1e-13);
    // At an experimental point its share is exactly 1.
    let at = model.cell_levels(5);
    let s = model.shares(&at).unwrap();
    assert_eq!(s[5], 1.0);
    assert_eq!(s.iter().filter(|v| **v != 0.0).count(), 1);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn weights_sum_to_one(
        gaps in prop::collection::vec(0.01f64..1.0, 2..12),
        start in -5.0f64..5.0,
        frac in 0.0f64..1.0,
    ) {
        let mut x = vec![start];
        for g in &gaps {
            x.push(x.last().unwrap() + g);
        }
        let nodes = Nodes::new(x.clone()).unwrap();
        let t = x[0] + frac * (x[x.len() - 1] - x[0]);
        let l = nodes.basis(t);
        let sum: f64 = l.iter().sum();
        let abs: f64 = l.iter().map(|v| v.abs()).sum();
        prop_assert!((sum - 1.0).abs() <= 8.0 * f64::EPSILON * abs * x.len() as f64);
    }

    #[test]
    fn curve_passes_through_its_points(
        pts in prop::collection::vec(prop::collection::vec(-100.0f64..100.0, 3), 2..9),
    ) {
        let n = pts.len();
        let nodes = Nodes::preset(NodePreset::ChebyshevSecond, n, 0.0, 1.0).unwrap();
        let eq = PointEquation::new(nodes.clone(), pts.clone()).unwrap();
        for (i, &t) in nodes.values().iter().enumerate() {
            prop_assert_eq!(eq.eval(t), pts[i].clone());
        }
    }

    #[test]
    fn affine_invariance(
        pts in prop::collection::vec(prop::collection::vec(-10.0f64..10.0, 2), 3..7),
        t in 0.0f64..1.0,
        shift in prop::collection::vec(-50.0f64..50.0, 2),
    ) {
        // Moving every source point by a vector moves M(t) by the same vector.
        let n = pts.len();
        let nodes = Nodes::preset(NodePreset::ChebyshevFirst, n, 0.0, 1.0).unwrap();
        let moved: Vec<Vec<f64>> = pts.iter().map(|p| vec![p[0] + shift[0], p[1] + shift[1]]).collect();
        let a = PointEquation::new(nodes.clone(), pts).unwrap().eval(t);
        let b = PointEquation::new(nodes, moved).unwrap().eval(t);
        for d in 0..2 {
            prop_assert!((b[d] - a[d] - shift[d]).abs() <= 1e-12 * (1.0 + shift[d].abs() + a[d].abs()));
        }
    }

    #[test]
    fn hypersurface_shares_sum_to_one(
        x in prop::collection::vec(0.0f64..1.0, 3),
    ) {
        let factors = vec![
            Factor::new("p", Nodes::paper_third()),
            Factor::new("q", Nodes::preset(NodePreset::ChebyshevSecond, 5, 0.0, 1.0).unwrap()),
            Factor::new("r", Nodes::paper_two_thirds()),
        ];
        let model = Hypersurface::from_fn(factors, 1, |x, o| o[0] = x[0] + x[1] * x[2], &PointOptions::default()).unwrap();
        let s = model.shares(&x).unwrap();
        prop_assert!((s.iter().sum::<f64>() - 1.0).abs() < 1e-13);
        // degree (2, 4, 2) model of a polynomial of degree (1, 1, 1): exact
        prop_assert!((model.eval(&x).unwrap()[0] - (x[0] + x[1] * x[2])).abs() < 1e-13);
    }
}
