//! Regressions of bad or extreme input of the point calculus (issue 21): each case once
//! returned NaN or infinity as a result, panicked, aborted on an allocation, or ran without
//! bound; now each gives a finite result that is checked, or a clear error naming the step.

use geomkit::expr::{Format, Graph};
use geomkit::geom::{Curve, Surface};
use geomkit::pointcalc::{
    optimize, Factor, Goal, Hypersurface, NodePreset, Nodes, OptimizeOptions, PointEquation,
    PointOptions, PointSurface,
};
use geomkit::Error;

/// A one-factor model through `values` at `nodes`.
fn model(nodes: &[f64], values: &[f64]) -> Hypersurface {
    let factors = vec![Factor::new("a", Nodes::new(nodes.to_vec()).unwrap())];
    Hypersurface::new(factors, 1, values.to_vec(), &PointOptions::default()).unwrap()
}

/// A two-factor model over {0, 1, 2}² with y = a + 2b (linear: exact anywhere).
fn plane() -> Hypersurface {
    let level = || Nodes::new(vec![0.0, 1.0, 2.0]).unwrap();
    let factors = vec![Factor::new("a", level()), Factor::new("b", level())];
    Hypersurface::from_fn(
        factors,
        1,
        |x, o| o[0] = x[0] + 2.0 * x[1],
        &PointOptions::default(),
    )
    .unwrap()
}

fn overflow(r: geomkit::Result<impl std::fmt::Debug>, words: &str) {
    match r {
        Err(Error::ResultOverflow { what }) => assert!(what.contains(words), "{what}"),
        other => panic!("expected an overflow naming {words:?}, got {other:?}"),
    }
}

/// Source values near f64::MAX inside the nodes: the partial sums of the kernels overflowed
/// (`pointcalc eval` printed inf); the result is representable and now comes out right.
#[test]
fn huge_values_inside_the_nodes_evaluate_finite() {
    let big = 1.7e308;
    let m = model(&[0.0, 0.5, 1.0], &[big, big, big]);
    for t in [0.1, 0.25, 0.8] {
        let v = m.eval(&[t]).unwrap()[0];
        assert!((v - big).abs() <= 1e-15 * big, "{t}: {v}");
    }
    let mut out = [0.0; 3];
    m.eval_many(&[0.1, 0.25, 0.8], &mut out).unwrap();
    assert!(
        out.iter().all(|v| (v - big).abs() <= 1e-15 * big),
        "{out:?}"
    );
    // Curves and surfaces through such points too.
    let eq = PointEquation::new(
        Nodes::paper_half(),
        vec![vec![big, -big], vec![big, -big], vec![big, -big]],
    )
    .unwrap();
    let p = eq.eval(0.25);
    assert!((p[0] - big).abs() <= 1e-15 * big && (p[1] + big).abs() <= 1e-15 * big);
    let net = vec![vec![vec![big]; 3]; 3];
    let s = PointSurface::tensor(Nodes::paper_half(), Nodes::paper_half(), net).unwrap();
    let mut grid = [0.0; 4];
    s.eval_grid(&[0.25, 0.75], &[0.25, 0.75], &mut grid)
        .unwrap();
    assert!(
        grid.iter().all(|v| (v - big).abs() <= 1e-15 * big),
        "{grid:?}"
    );
    assert!((Surface::eval(&s, 0.3, 0.6)[0] - big).abs() <= 1e-15 * big);
    // A response beyond f64 is refused, naming the point.
    // y(1/4) = 1.25 · 1.7e308 between the first two levels.
    let m = model(&[0.0, 0.5, 1.0], &[big, big, -big]);
    overflow(m.eval(&[0.25]), "the modeled value at a=0.25");
}

/// Far outside the nodes the shares grow like x^(n-1): `pointcalc eval` at 1e308 printed NaN
/// and -inf. A result beyond f64 is an overflow; one that rounding swamps is refused; a
/// moderate extrapolation is still right.
#[test]
fn extrapolation_is_finite_or_refused() {
    let m = plane();
    assert_eq!(m.eval(&[3.0, 1.0]).unwrap(), vec![5.0]);
    let v = m.eval(&[1e5, 1.0]).unwrap()[0];
    assert!((v - 100_002.0).abs() < 1e-6, "{v}");
    // y = a + 2b at a = 1e154: the terms of ±1e308 cancel to 1e154, below their rounding.
    assert!(matches!(
        m.eval(&[1e154, 1.0]),
        Err(Error::LostToRounding { what, error }) if what.contains("a=1e154") && error > 1e290
    ));
    let mut out = [0.0; 3];
    let far = m.eval_many(&[1.0, 1.0, 2.0, 0.0, 1e308, 0.0], &mut out);
    assert!(
        matches!(far, Err(Error::LostToRounding { ref what, .. }) if what.contains("a=1e308")),
        "{far:?}"
    );
    // y = t², exactly a parabola: 1e400 at t = 1e200.
    let parabola = model(&[0.0, 1.0, 2.0], &[0.0, 1.0, 4.0]);
    overflow(parabola.eval(&[1e200]), "a=1e200");
    let v = parabola.eval(&[-1e100]).unwrap()[0];
    assert!((v - 1e200).abs() <= 1e-13 * 1e200, "{v}");
    // Curves: the sample refuses, the infallible evaluation is ±infinity (never NaN).
    let eq =
        PointEquation::new(Nodes::paper_half(), vec![vec![0.0], vec![0.25], vec![1.0]]).unwrap();
    let mut o = [0.0];
    overflow(eq.eval_params(&[1e200], &mut o), "t=1e200");
    assert_eq!(eq.eval(1e200)[0], f64::INFINITY);
}

/// Shares far outside the nodes: `pointcalc shares` printed `null` for every share.
#[test]
fn shares_beyond_f64_are_refused_by_name() {
    let m = plane();
    overflow(
        m.shares(&[1e308, 0.0]),
        "the share of point 0 (a=0, b=0) at a=1e308, b=0",
    );
    overflow(m.shares(&[1e100, 1e100]), "share of point");
    // Each share representable: they are, and they sum to 1 within their rounding.
    let s = m.shares(&[1e100, 1.0]).unwrap();
    assert!(s.iter().all(|v| v.is_finite()));
    let sum: f64 = s.iter().sum();
    let scale: f64 = s.iter().map(|v| v.abs()).sum();
    assert!((sum - 1.0).abs() <= 1e-15 * scale, "{sum} {scale}");
    assert_eq!(s[4], -1e200);
}

/// Source values near f64::MAX: the Bernstein bounds overflowed and `pointcalc optimize`
/// printed `"bound": null` with `"certified": true`. Now the search runs on scaled values.
#[test]
fn optimum_of_huge_values_has_a_finite_certified_bound() {
    let m = model(&[0.0, 0.5, 1.0], &[1e308, 1.5e308, 1e308]);
    let best = optimize(&m, Goal::Max, &OptimizeOptions::default()).unwrap();
    assert!(best.certified && best.bound.is_finite(), "{best:?}");
    // y = 1e308 (1 + 4t(1 - t)/2): the largest value 1.5e308 at t = 1/2.
    assert!((best.value - 1.5e308).abs() <= 1e-12 * 1.5e308, "{best:?}");
    assert!(best.bound >= best.value && best.bound <= 1.5e308 * (1.0 + 1e-8));
    let low = optimize(&m, Goal::Min, &OptimizeOptions::default()).unwrap();
    assert!(low.certified && low.bound.is_finite() && low.value == 1e308);
    // A largest value beyond f64 (the interpolant overshoots 1.7e308) is refused.
    let m = model(&[0.0, 0.5, 1.0], &[1.7e308, 1.7e308, -1.7e308]);
    overflow(
        optimize(&m, Goal::Max, &OptimizeOptions::default()),
        "largest",
    );
}

/// Bernstein coefficients beyond f64 (nodes 1e-200 apart in two factors: coefficients of
/// 1e200 each, their products 1e400) bound nothing: NaN bounds were dropped by the
/// comparisons; now a clear error.
#[test]
fn optimum_whose_bernstein_bound_overflows_is_refused() {
    let close = || Nodes::new(vec![0.0, 1e-200, 1.0]).unwrap();
    let factors = vec![Factor::new("a", close()), Factor::new("b", close())];
    let values = vec![1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0];
    let m = Hypersurface::new(factors, 1, values, &PointOptions::default()).unwrap();
    overflow(
        optimize(&m, Goal::Max, &OptimizeOptions::default()),
        "Bernstein",
    );
    // A model one box of which costs more than the work budget is refused before any box.
    let small = OptimizeOptions::default().with_max_work(10);
    assert!(matches!(
        optimize(&m, Goal::Max, &small),
        Err(Error::TooMany { max: 10, .. })
    ));
}

/// Printed formulas held INFINITY (a folded coefficient c_j · y_j beyond f64, or c_j itself)
/// or silently dropped terms whose coefficient underflowed to 0.
#[test]
fn formulas_never_print_infinity_or_drop_terms() {
    let mut g = Graph::new();
    let a = g.var("a");
    let big = model(&[0.0, 0.5, 1.0], &[1.7e308, 1e308, 1.7e308]);
    overflow(
        big.to_expr(&mut g, &[a]),
        "c_j · y = 2 · 1.7e308 of source point a=0",
    );
    let close = model(&[0.0, 1e-170, 2e-170], &[1.0, 2.0, 3.0]);
    overflow(close.to_expr(&mut g, &[a]), "coefficient 1/Π(t_j - t_k)");
    // 1 / ((0 - 1e200)(0 - 2e200)) is below f64: the terms vanished ("0" was printed).
    let wide = model(&[0.0, 1e200, 2e200], &[1.0, 2.0, 3.0]);
    overflow(wide.to_expr(&mut g, &[a]), "the product Π(t_j - t_k)");
    // Within range, the formula is right.
    let fine = model(&[0.0, 1e-100, 1.0], &[1.0, 2.0, 3.0]);
    let e = fine.to_expr(&mut g, &[a]).unwrap()[0];
    assert!(!g.print(e, Format::C).unwrap().contains("INFINITY"));
    let v = g.eval(e, &[("a", 0.5)]).unwrap();
    assert!(
        (v - fine.eval(&[0.5]).unwrap()[0]).abs() <= 1e-12 * v.abs(),
        "{v}"
    );
}

/// Absurd node counts: `--nodes cheb1:100000000` allocated and then ran O(n²) without end.
#[test]
fn node_counts_above_the_limit_are_refused() {
    let too_many = |r: geomkit::Result<Nodes>| matches!(r, Err(Error::TooMany { got, max: Nodes::MAX_LEN, .. }) if got > Nodes::MAX_LEN);
    assert!(too_many(Nodes::preset(
        NodePreset::ChebyshevFirst,
        100_000_000,
        0.0,
        1.0
    )));
    assert!(too_many(Nodes::preset(
        NodePreset::Equispaced,
        usize::MAX,
        0.0,
        1.0
    )));
    let values: Vec<f64> = (0..=Nodes::MAX_LEN).map(|i| i as f64).collect();
    assert!(too_many(Nodes::new(values.clone())));
    let full = Nodes::new(values[..Nodes::MAX_LEN].to_vec());
    // (Equispaced at the limit: its weights span beyond f64, refused for that.)
    assert!(matches!(full, Err(Error::InvalidNodes { reason, .. }) if reason.contains("span")));
    let cheb = Nodes::preset(NodePreset::ChebyshevSecond, Nodes::MAX_LEN, 0.0, 1.0).unwrap();
    assert!(too_many(cheb.with_node(2.0).map(|(n, _)| n)));
}

/// Grids implied by records or factors past memory: `vec![None; cells]` of 8·10^9 cells
/// aborted, and a product of level counts overflowed usize.
#[test]
fn grids_past_memory_are_refused_before_allocating() {
    let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
    // 2000 records with distinct values in each factor (Chebyshev levels, permuted): a grid
    // of 8·10^9 cells, 2000 of them given.
    let level = |i: usize| (std::f64::consts::PI * (i as f64 + 0.5) / 2000.0).cos();
    let records: Vec<Vec<f64>> = (0..2000)
        .map(|i| vec![level(i), level(i * 7 % 2000), level(i * 13 % 2000), 1.0])
        .collect();
    match Hypersurface::from_records(&names, &records, &[], &PointOptions::default()) {
        Err(Error::MissingCell { cell, missing }) => {
            assert_eq!(missing, 2000usize.pow(3) - 2000);
            let low = level(1999);
            assert_eq!(cell, format!("a={low}, b={low}, c={low}"));
        }
        other => panic!("{other:?}"),
    }
    let nodes = Nodes::preset(NodePreset::ChebyshevFirst, 4000, 0.0, 1.0).unwrap();
    let factors: Vec<Factor> = (0..6)
        .map(|f| Factor::new(format!("x{f}"), nodes.clone()))
        .collect();
    let r = Hypersurface::from_fn(factors, 1, |_, o| o[0] = 1.0, &PointOptions::default());
    assert!(matches!(
        r,
        Err(Error::TooMany {
            max: Hypersurface::MAX_VALUES,
            ..
        })
    ));
}

/// Node spacings at the ends of the f64 range: subnormal differences were refused as an
/// "overflow" (the old rescaling overflowed), differences that fit f64 were refused when
/// their products did not; the weights of an ill-conditioned set were garbage (a clamp).
#[test]
fn node_weights_at_the_ends_of_the_f64_range() {
    let tiny = Nodes::new(vec![0.0, 1e-320, 2e-320]).unwrap();
    assert_eq!(tiny.basis(1e-320), vec![0.0, 1.0, 0.0]);
    let l = tiny.basis(0.5e-320);
    assert!((l.iter().sum::<f64>() - 1.0).abs() < 1e-15, "{l:?}");
    let huge = Nodes::new(vec![-9.0, 0.0, 1e308, f64::MAX]).unwrap();
    for (k, &x) in huge.values().iter().enumerate() {
        let l = huge.basis(x);
        assert!(l
            .iter()
            .enumerate()
            .all(|(j, &v)| v == if j == k { 1.0 } else { 0.0 }));
    }
    // Lebesgue constant of {0, 1e-300, 1}: about 5e299 (it was "inf").
    let lebesgue = Nodes::new(vec![0.0, 1e-300, 1.0])
        .unwrap()
        .lebesgue_constant();
    assert!((lebesgue / 5e299 - 1.0).abs() < 1e-3, "{lebesgue:e}");
    // Equispaced beyond about 1000 nodes: weights from 1 to C(n-1, n/2) > 2^1074.
    assert!(matches!(
        Nodes::preset(NodePreset::Equispaced, 1200, 0.0, 1.0),
        Err(Error::InvalidNodes { reason, .. }) if reason.contains("span more than the f64 range")
    ));
    assert!(Nodes::preset(NodePreset::Equispaced, 900, 0.0, 1.0).is_ok());
}

/// Shares inside ill-conditioned nodes: the second barycentric form's sum cancelled to
/// zero and gave NaN; the product form is used there.
#[test]
fn shares_never_nan_inside_ill_conditioned_nodes() {
    let nodes = Nodes::new(vec![0.0, 1e-300, 1.0]).unwrap();
    for t in [0.5, 1e-301, 0.999_999, 1e-299] {
        let l = nodes.basis(t);
        assert!(l.iter().all(|v| v.is_finite()), "{t}: {l:?}");
        let exact: Vec<f64> = (0..3)
            .map(|j| {
                let x = nodes.values();
                (0..3)
                    .filter(|&k| k != j)
                    .map(|k| (t - x[k]) / (x[j] - x[k]))
                    .product()
            })
            .collect();
        let scale = exact.iter().map(|v| v.abs()).fold(0.0, f64::max);
        for (a, b) in l.iter().zip(&exact) {
            assert!((a - b).abs() <= 1e-10 * scale, "{t}: {l:?} vs {exact:?}");
        }
    }
}

/// A batch of a curve's points with one beyond f64: `eval_batch` panicked on the `expect` of
/// its chunks once `eval_params` could refuse; now the same error.
#[test]
fn curve_batches_beyond_f64_are_refused() {
    use geomkit::geom::BatchOptions;
    let eq =
        PointEquation::new(Nodes::paper_half(), vec![vec![0.0], vec![0.25], vec![1.0]]).unwrap();
    let mut out = [0.0; 3];
    let r = Curve::eval_batch(&eq, &[0.5, 1e200, 2.0], &mut out, &BatchOptions::default());
    overflow(r, "t=1e200");
    Curve::eval_batch(&eq, &[0.5, 1e5, 2.0], &mut out, &BatchOptions::default()).unwrap();
    assert_eq!(out, [0.25, 1e10, 4.0]);
}
