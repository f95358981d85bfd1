//! Fuzzing of the point calculus (issue 21): random node sets (huge and tiny spreads, offsets
//! near ±1e308, near-duplicate nodes), source values (up to ±f64::MAX), evaluation points
//! (inside, outside, ±1e308, ±f64::MAX). Property: no panic, and every result is an error or
//! finite; shares that are finite sum to 1 within their rounding; a certified optimum has a
//! finite bound on the right side of its value; formulas hold finite numbers only.

#[path = "common/fuzz.rs"]
mod fuzz;

use geomkit::expr::{Format, Graph};
use geomkit::geom::{BatchOptions, Curve};
use geomkit::pointcalc::{
    optimize, Factor, Goal, Hypersurface, Nodes, OptimizeOptions, PointEquation, PointOptions,
    PointSurface,
};
use proptest::prelude::*;

/// Sorted node positions, up to 6: an offset, a scale and gaps (some near-duplicate).
fn node_positions() -> impl Strategy<Value = Vec<f64>> {
    node_positions_up_to(6)
}

/// [`node_positions`], up to `most` of them (above 16 the kernels divide per node).
fn node_positions_up_to(most: usize) -> impl Strategy<Value = Vec<f64>> {
    let offset = prop_oneof![
        Just(0.0),
        -10.0..10.0f64,
        Just(1e308),
        Just(-1e308),
        Just(-f64::MAX),
        Just(1e-310),
    ];
    let scale = prop_oneof![
        Just(1.0),
        Just(1e-300),
        Just(1e-320),
        Just(1e150),
        Just(1e300),
        Just(1e-8),
        0.01..100.0f64,
    ];
    let gap = prop_oneof![
        4 => 0.01..1.0f64,
        1 => Just(1e-15),
        1 => Just(1e-300),
        1 => Just(1e10),
    ];
    (offset, scale, prop::collection::vec(gap, 0..most)).prop_map(|(offset, scale, gaps)| {
        let mut x = vec![offset];
        for g in gaps {
            x.push(x[x.len() - 1] + scale * g);
        }
        x
    })
}

/// A number as source values come: ordinary, zero, tiny, huge, f64::MAX.
fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -10.0..10.0f64,
        1 => Just(0.0),
        1 => Just(1e-300),
        1 => Just(1.7e308),
        1 => Just(-1.7e308),
        1 => Just(f64::MAX),
        1 => -1e300..1e300f64,
    ]
}

/// An evaluation parameter: a fraction of the node span (inside and around it), or an
/// absolute value up to ±f64::MAX.
#[derive(Debug, Clone, Copy)]
enum At {
    Span(f64),
    Abs(f64),
}

fn at() -> impl Strategy<Value = At> {
    prop_oneof![
        4 => (-0.5..1.5f64).prop_map(At::Span),
        1 => prop_oneof![Just(0.0), Just(1.0)].prop_map(At::Span),
        1 => prop_oneof![
            Just(1e308),
            Just(-1e308),
            Just(f64::MAX),
            Just(-f64::MAX),
            Just(1e154),
            Just(5e-324),
            -1e6..1e6f64,
        ]
        .prop_map(At::Abs),
    ]
}

fn place(at: At, nodes: &Nodes) -> f64 {
    match at {
        At::Abs(t) => t,
        At::Span(u) => {
            let (lo, hi) = nodes.domain();
            let t = lo + (hi - lo) * u;
            if t.is_finite() {
                t
            } else {
                lo
            }
        }
    }
}

/// Factors built from positions (the ones `Nodes::new` accepts).
fn factors(sets: &[Vec<f64>]) -> Option<Vec<Factor>> {
    sets.iter()
        .enumerate()
        .map(|(f, x)| {
            Nodes::new(x.clone())
                .ok()
                .map(|n| Factor::new(format!("x{f}"), n))
        })
        .collect()
}

/// Σ shares = 1 within the rounding of the shares themselves.
fn sums_to_one(shares: &[f64], n: usize) -> bool {
    let sum: f64 = shares.iter().sum();
    let size: f64 = shares.iter().map(|v| v.abs()).sum();
    (sum - 1.0).abs() <= 64.0 * (n + 4) as f64 * f64::EPSILON * size.max(1.0)
}

proptest! {
    #![proptest_config(fuzz::config(256))]

    /// Cardinal functions anywhere: never NaN (±infinity only beyond f64), exactly δ at the
    /// nodes, and summing to 1 where finite.
    #[test]
    fn fuzz_cardinal_functions(x in node_positions_up_to(24), ats in prop::collection::vec(at(), 1..6)) {
        let Ok(nodes) = Nodes::new(x) else { return Ok(()) };
        let n = nodes.len();
        let lebesgue = nodes.lebesgue_constant();
        prop_assert!(lebesgue.is_finite() && lebesgue >= 1.0, "{lebesgue}");
        for a in ats {
            let t = place(a, &nodes);
            let l = nodes.basis(t);
            prop_assert!(l.iter().all(|v| !v.is_nan()), "t={t}: {l:?}");
            if let Some(k) = nodes.position(t) {
                for (j, v) in l.iter().enumerate() {
                    prop_assert_eq!(*v, if j == k { 1.0 } else { 0.0 });
                }
            }
            if l.iter().all(|v| v.is_finite()) {
                prop_assert!(sums_to_one(&l, n), "t={t}: {l:?}");
            }
        }
    }

    /// Models of one to three factors: evaluation, batches and shares are errors or finite;
    /// a batch gives the single points' values.
    #[test]
    fn fuzz_model_eval_and_shares(
        sets in prop::collection::vec(node_positions_up_to(18), 1..4),
        values in prop::collection::vec(value(), 1..300),
        ats in prop::collection::vec(prop::collection::vec(at(), 3), 1..5),
    ) {
        let Some(factors) = factors(&sets) else { return Ok(()) };
        let cells: usize = factors.iter().map(|f| f.nodes().len()).product();
        let values: Vec<f64> = (0..cells).map(|c| values[c % values.len()]).collect();
        let Ok(model) = Hypersurface::new(factors, 1, values, &PointOptions::default()) else {
            return Ok(());
        };
        let k = model.k();
        let points: Vec<Vec<f64>> = ats
            .iter()
            .map(|a| {
                (0..k).map(|f| place(a[f], model.factors()[f].nodes())).collect()
            })
            .collect();
        let mut singles = Vec::new();
        for x in &points {
            match model.eval(x) {
                Ok(v) => {
                    prop_assert!(v[0].is_finite(), "{x:?}: {v:?}");
                    singles.push(Some(v[0]));
                }
                Err(_) => singles.push(None),
            }
            if let Ok(s) = model.shares(x) {
                prop_assert!(s.iter().all(|v| v.is_finite()), "{x:?}: {s:?}");
                let n: usize = model.shape().iter().sum();
                prop_assert!(sums_to_one(&s, n * k), "{x:?}: {s:?}");
            }
            if let Ok(g) = model.gradient(x) {
                prop_assert!(g.iter().all(|v| v.is_finite()), "{x:?}: {g:?}");
            }
        }
        let flat: Vec<f64> = points.iter().flatten().copied().collect();
        let mut out = vec![0.0; points.len()];
        let batch = model.eval_many(&flat, &mut out);
        if singles.iter().all(Option::is_some) {
            prop_assert!(batch.is_ok(), "{batch:?}");
            for (o, s) in out.iter().zip(&singles) {
                prop_assert_eq!(Some(*o), *s);
            }
        } else {
            prop_assert!(batch.is_err());
        }
    }

    /// The optimum: an error, or finite value, bound and gap; the bound on the right side of
    /// the value; the value is the model's at the point found.
    #[test]
    fn fuzz_optimize(
        sets in prop::collection::vec(node_positions(), 1..3),
        values in prop::collection::vec(value(), 1..40),
        max in any::<bool>(),
    ) {
        let Some(factors) = factors(&sets) else { return Ok(()) };
        let cells: usize = factors.iter().map(|f| f.nodes().len()).product();
        let values: Vec<f64> = (0..cells).map(|c| values[c % values.len()]).collect();
        let Ok(model) = Hypersurface::new(factors, 1, values, &PointOptions::default()) else {
            return Ok(());
        };
        let goal = if max { Goal::Max } else { Goal::Min };
        let options = OptimizeOptions::default().with_max_boxes(60);
        let Ok(best) = optimize(&model, goal, &options) else { return Ok(()) };
        prop_assert!(best.value.is_finite() && best.bound.is_finite() && best.gap.is_finite(),
            "{best:?}");
        prop_assert!(best.at.iter().all(|x| x.is_finite()));
        let slack = 1e-9 * best.value.abs().max(f64::MIN_POSITIVE);
        if max {
            prop_assert!(best.bound >= best.value - slack, "{best:?}");
        } else {
            prop_assert!(best.bound <= best.value + slack, "{best:?}");
        }
        if let Ok(v) = model.eval(&best.at) {
            // The search evaluates the values scaled to |v| < 1 (where the fast kernels run),
            // this the values as they are: the two agree within the model's rounding, which
            // the Lebesgue constants amplify.
            let lebesgue: f64 =
                model.factors().iter().map(|f| f.nodes().lebesgue_constant()).product();
            let largest = model.values().iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let tolerance = 1e-13 * lebesgue * largest;
            prop_assert!((v[0] - best.value).abs() <= tolerance, "{best:?} {v:?}");
        }
    }

    /// Formulas of models and curves: an error, or numbers that are all finite (nothing
    /// prints as INFINITY or NaN).
    #[test]
    fn fuzz_formula(
        sets in prop::collection::vec(node_positions(), 1..3),
        values in prop::collection::vec(value(), 1..40),
    ) {
        let Some(factors) = factors(&sets) else { return Ok(()) };
        let cells: usize = factors.iter().map(|f| f.nodes().len()).product();
        let values: Vec<f64> = (0..cells).map(|c| values[c % values.len()]).collect();
        let Ok(model) = Hypersurface::new(factors, 1, values.clone(), &PointOptions::default())
        else {
            return Ok(());
        };
        let mut g = Graph::new();
        let vars: Vec<_> = (0..model.k()).map(|f| g.var(&format!("x{f}"))).collect();
        if let Ok(e) = model.to_expr(&mut g, &vars) {
            let text = g.print(e[0], Format::C).unwrap();
            prop_assert!(!text.contains("INFINITY") && !text.contains("NAN"), "{text}");
        }
        let nodes = model.factors()[0].nodes().clone();
        let points: Vec<Vec<f64>> =
            values[..nodes.len()].iter().map(|&v| vec![v, 1.0]).collect();
        let eq = PointEquation::new(nodes, points).unwrap();
        let t = g.var("t");
        if let Ok(e) = eq.to_expr(&mut g, t) {
            for c in e {
                let text = g.print(c, Format::Numpy).unwrap();
                prop_assert!(!text.contains("inf") && !text.contains("nan"), "{text}");
            }
        }
    }

    /// Curves and surfaces: samples are errors or finite; single points never NaN.
    #[test]
    fn fuzz_curves_and_surfaces(
        x in node_positions_up_to(24),
        across in node_positions(),
        values in prop::collection::vec(value(), 1..40),
        ats in prop::collection::vec(at(), 1..6),
    ) {
        let (Ok(nodes), Ok(across)) = (Nodes::new(x), Nodes::new(across)) else {
            return Ok(());
        };
        let (n, m) = (nodes.len(), across.len());
        let point = |i: usize| vec![values[i % values.len()], values[(i + 1) % values.len()]];
        let eq = PointEquation::new(nodes.clone(), (0..n).map(point).collect()).unwrap();
        let ts: Vec<f64> = ats.iter().map(|&a| place(a, &nodes)).collect();
        let mut out = vec![0.0; ts.len() * 2];
        let single = eq.eval_params(&ts, &mut out);
        if single.is_ok() {
            prop_assert!(out.iter().all(|v| v.is_finite()), "{ts:?}: {out:?}");
        }
        // The batch (parallel chunks) agrees: the same values, or an error too.
        let mut batch = vec![0.0; out.len()];
        let r = Curve::eval_batch(&eq, &ts, &mut batch, &BatchOptions::default());
        prop_assert_eq!(r.is_ok(), single.is_ok());
        if r.is_ok() {
            prop_assert_eq!(&batch, &out);
        }
        for &t in &ts {
            prop_assert!(eq.eval(t).iter().all(|v| !v.is_nan()), "{t}");
        }
        let net: Vec<Vec<Vec<f64>>> =
            (0..m).map(|i| (0..n).map(|j| point(i * n + j)).collect()).collect();
        let surface = PointSurface::tensor(nodes.clone(), across.clone(), net).unwrap();
        let vs: Vec<f64> = ats.iter().map(|&a| place(a, &across)).collect();
        let mut grid = vec![0.0; ts.len() * vs.len() * 2];
        if surface.eval_grid(&ts, &vs, &mut grid).is_ok() {
            prop_assert!(grid.iter().all(|v| v.is_finite()), "{grid:?}");
        }
    }

    /// Experimental records with duplicates, missing cells, NaN and huge values: an error or
    /// a model through them.
    #[test]
    fn fuzz_records(
        records in prop::collection::vec(
            prop::collection::vec(
                prop_oneof![
                    8 => (0..4u8).prop_map(f64::from),
                    1 => Just(f64::NAN),
                    1 => Just(1e-300),
                    1 => Just(1.7e308),
                ],
                3,
            ),
            0..20,
        ),
    ) {
        let names = vec!["a".to_string(), "b".to_string()];
        if let Ok(model) =
            Hypersurface::from_records(&names, &records, &[], &PointOptions::default())
        {
            prop_assert!(model.values().iter().all(|v| v.is_finite()));
            prop_assert_eq!(model.values().len(), records.len());
            for r in &records {
                prop_assert_eq!(model.eval(&r[..2]).unwrap(), vec![r[2]]);
            }
        }
    }
}
