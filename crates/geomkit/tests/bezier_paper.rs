//! The worked examples of Nikulin (2011), spec/bezier-order.md, reproduced exactly.

mod common;

use common::bernstein;
use geomkit::bezier::{BezierCurve, BezierSurface, Direction};
use geomkit::exact::{
    degree_change_matrix, elevation_matrix, h_inverse, h_matrix, ExactBezierCurve, ExactMatrix,
    Rational,
};
use geomkit::Error;

fn q(p: i64, d: i64) -> Rational {
    Rational::new(p.into(), d.into())
}

fn matrix(rows: &[&[(i64, i64)]]) -> ExactMatrix {
    let rows: Vec<Vec<(i64, i64)>> = rows.iter().map(|r| r.to_vec()).collect();
    ExactMatrix::from_rows(&rows).unwrap()
}

/// The classic one-step elevation (6), exactly.
fn classic_step(n: usize) -> ExactMatrix {
    let mut rows = vec![vec![(0i64, 1i64); n + 2]; n + 1];
    for i in 0..=n + 1 {
        // u'_i = i/(n+1) u_(i-1) + (1 - i/(n+1)) u_i
        if i >= 1 {
            rows[i - 1][i] = (i as i64, n as i64 + 1);
        }
        if i <= n {
            rows[i][i] = (n as i64 + 1 - i as i64, n as i64 + 1);
        }
    }
    ExactMatrix::from_rows(&rows).unwrap()
}

#[test]
fn example1_two_to_three() {
    let want = matrix(&[
        &[(1, 1), (1, 3), (0, 1), (0, 1)],
        &[(0, 1), (2, 3), (2, 3), (0, 1)],
        &[(0, 1), (0, 1), (1, 3), (1, 1)],
    ]);
    assert_eq!(degree_change_matrix(2, 3), want);
    assert_eq!(classic_step(2), want);
}

#[test]
fn example1_three_to_four() {
    let want = matrix(&[
        &[(1, 1), (1, 4), (0, 1), (0, 1), (0, 1)],
        &[(0, 1), (3, 4), (1, 2), (0, 1), (0, 1)],
        &[(0, 1), (0, 1), (1, 2), (3, 4), (0, 1)],
        &[(0, 1), (0, 1), (0, 1), (1, 4), (1, 1)],
    ]);
    assert_eq!(degree_change_matrix(3, 4), want);
    assert_eq!(classic_step(3), want);
}

#[test]
fn example1_three_to_five_in_one_step() {
    let want = matrix(&[
        &[(1, 1), (2, 5), (1, 10), (0, 1), (0, 1), (0, 1)],
        &[(0, 1), (3, 5), (3, 5), (3, 10), (0, 1), (0, 1)],
        &[(0, 1), (0, 1), (3, 10), (3, 5), (3, 5), (0, 1)],
        &[(0, 1), (0, 1), (0, 1), (1, 10), (2, 5), (1, 1)],
    ]);
    assert_eq!(degree_change_matrix(3, 5), want);
    // Two classic steps give the same matrix.
    assert_eq!(classic_step(3).mul(&classic_step(4)).unwrap(), want);
    assert_eq!(elevation_matrix(3, 5).unwrap(), want);
    assert!(elevation_matrix(5, 3).is_err());
}

#[test]
fn example1_h5_as_printed() {
    let want = matrix(&[
        &[(1, 1), (-5, 1), (10, 1), (-10, 1), (5, 1), (-1, 1)],
        &[(0, 1), (5, 1), (-20, 1), (30, 1), (-20, 1), (5, 1)],
        &[(0, 1), (0, 1), (10, 1), (-30, 1), (30, 1), (-10, 1)],
        &[(0, 1), (0, 1), (0, 1), (10, 1), (-20, 1), (10, 1)],
        &[(0, 1), (0, 1), (0, 1), (0, 1), (5, 1), (-5, 1)],
        &[(0, 1), (0, 1), (0, 1), (0, 1), (0, 1), (1, 1)],
    ]);
    assert_eq!(h_matrix(5), want);
    // The inverse printed in Example 1 (first row all ones, (H_5^-1)_ij = C(j,i)/C(5,i)).
    let inv = h_inverse(5);
    assert_eq!(inv.get(0, 5), &q(1, 1));
    assert_eq!(inv.get(1, 2), &q(2, 5));
    assert_eq!(inv.get(2, 4), &q(6, 10));
    assert_eq!(
        h_matrix(5).mul(&inv).unwrap(),
        geomkit::exact::e_matrix(6, 6)
    );
}

const EXAMPLE2: [[f64; 2]; 6] = [
    [10.0, 0.0],
    [22.0, 6.0],
    [19.0, 12.0],
    [11.0, 15.0],
    [8.0, 12.0],
    [20.0, 0.0],
];

fn example2() -> BezierCurve {
    BezierCurve::new(EXAMPLE2.iter().map(|p| p.to_vec()).collect()).unwrap()
}

#[test]
fn example2_power_coefficients_and_defect_exact() {
    let flat: Vec<f64> = EXAMPLE2.iter().flatten().copied().collect();
    let c = ExactBezierCurve::from_f64(2, &flat).unwrap();
    let s = c.to_power();
    let want = [10, 0, 60, 30, -150, 0, 100, -30, 0, 0, 0, 0];
    assert_eq!(s, want.iter().map(|&v| q(v, 1)).collect::<Vec<_>>());
    assert_eq!(c.real_degree(), 3);
    let cubic = c.change_degree(3).unwrap();
    let want = [
        q(10, 1),
        q(0, 1),
        q(30, 1),
        q(10, 1),
        q(0, 1),
        q(20, 1),
        q(20, 1),
        q(0, 1),
    ];
    assert_eq!(cubic.points(), &want);
    assert_eq!(cubic.change_degree(5).unwrap(), c);
    assert!(matches!(
        c.change_degree(2),
        Err(Error::DegreeDefectTooSmall {
            real_degree: 3,
            requested: 2,
            defect: 2
        })
    ));
}

#[test]
fn example2_in_f64() {
    let c = example2();
    let report = c.degree_report(None).unwrap();
    assert_eq!(
        (report.degree, report.real_degree, report.defect),
        (5, 3, 2)
    );
    assert!(report.rejected_residual.unwrap() > 1e-3, "{report:?}");
    let cubic = c.reduce_degree(3, None).unwrap();
    let want = [10.0, 0.0, 30.0, 10.0, 0.0, 20.0, 20.0, 0.0];
    for (a, b) in cubic.points_flat().iter().zip(want) {
        assert!((a - b).abs() <= 1e-13 * 22.0, "{a} vs {b}");
    }
    let back = cubic.elevate_degree(5).unwrap();
    for (a, b) in back.points_flat().iter().zip(c.points_flat()) {
        assert!((a - b).abs() <= 1e-13, "{a} vs {b}");
    }
    match c.reduce_degree(2, None) {
        Err(Error::DegreeDefectTooSmall {
            real_degree: 3,
            requested: 2,
            defect: 2,
        }) => {}
        other => panic!("{other:?}"),
    }
    // The paper's formula (10) with the exact matrix rounded once gives the same cubic.
    let paper = c.change_degree_paper(3).unwrap();
    for (a, b) in paper.points_flat().iter().zip(want) {
        assert!((a - b).abs() <= 1e-13 * 22.0);
    }
}

/// Fig. 5: a (4,3) surface whose S has one zero row reduces to (3,3), then changes to (3,6),
/// and the surface does not change.
#[test]
fn fig5_surface_order_change() {
    // Build a bicubic net, then elevate it to (4,3): S_(4,3) then has a zero bottom row.
    let cubic_net: Vec<Vec<Vec<f64>>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    vec![x, y, ((x - 1.5) * (y - 1.5)).sin() + 0.3 * x * y - 0.5 * y]
                })
                .collect()
        })
        .collect();
    let base = BezierSurface::new(cubic_net).unwrap();
    let s43 = base.change_degree(4, 3, None).unwrap();
    assert_eq!(s43.degrees(), (4, 3));
    let report = s43.degree_report(None).unwrap();
    assert_eq!(report.real_degrees(), (3, 3));
    assert_eq!(report.defects(), (1, 0));
    let s33 = s43.change_degree(3, 3, None).unwrap();
    let s36 = s43.change_degree(3, 6, None).unwrap();
    assert_eq!(s36.degrees(), (3, 6));
    for k in 0..=20 {
        for l in 0..=20 {
            let (u, v) = (k as f64 / 20.0, l as f64 / 20.0);
            let p = s43.eval(u, v);
            for other in [&s33, &s36] {
                let r = other.eval(u, v);
                let d: f64 = p
                    .iter()
                    .zip(&r)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(d < 1e-13, "({u},{v}): {d}");
            }
        }
    }
    // Reducing v below its real degree fails and names the direction.
    match s43.change_degree(3, 2, None) {
        Err(Error::SurfaceDefectTooSmall {
            direction: "v",
            real_degree: 3,
            requested: 2,
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}

/// Fig. 4: adding a row and removing the middle row of a 7×3 net change the surface.
#[test]
fn fig4_manual_changes_change_the_shape() {
    let net: Vec<Vec<Vec<f64>>> = (0..7)
        .map(|i| {
            (0..3)
                .map(|j| vec![i as f64, j as f64, ((i * j) % 3) as f64])
                .collect()
        })
        .collect();
    let s = BezierSurface::new(net).unwrap();
    let added = s
        .insert_line(
            Direction::U,
            7,
            &[
                vec![7.0, 0.0, 1.0],
                vec![7.0, 1.0, 2.0],
                vec![7.0, 2.0, 0.0],
            ],
        )
        .unwrap();
    let removed = s.remove_line(Direction::U, 3).unwrap();
    assert_eq!(added.degrees(), (7, 2));
    assert_eq!(removed.degrees(), (5, 2));
    for other in [&added, &removed] {
        let dev = s.deviation_from(other).unwrap();
        assert!(dev.max_found > 0.05, "{dev:?}");
        assert!(dev.upper_bound >= dev.max_found);
    }
    assert!(matches!(
        s.remove_line(Direction::V, 3),
        Err(Error::IndexOutOfRange {
            index: 3,
            len: 3,
            ..
        })
    ));
}

/// Σ_k b_nk(t) P_k by brute force.
fn brute_eval(points: &[Vec<f64>], t: f64) -> Vec<f64> {
    let n = points.len() - 1;
    let mut out = vec![0.0; points[0].len()];
    for (k, p) in points.iter().enumerate() {
        let b = bernstein(n, k, t);
        for (o, x) in out.iter_mut().zip(p) {
            *o += b * x;
        }
    }
    out
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// max_t |a(t) - b(t)| by brute force: 20001 uniform parameters, then a golden-section search
/// around the best one.
fn brute_max_distance(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let dist = |t: f64| {
        let (x, y) = (brute_eval(a, t), brute_eval(b, t));
        norm(&x.iter().zip(&y).map(|(p, q)| p - q).collect::<Vec<_>>())
    };
    let count = 20_000;
    let best = (0..=count)
        .map(|j| j as f64 / count as f64)
        .max_by(|s, t| dist(*s).total_cmp(&dist(*t)))
        .unwrap();
    let (mut lo, mut hi) = (
        (best - 1.0 / count as f64).max(0.0),
        (best + 1.0 / count as f64).min(1.0),
    );
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if dist(x1) < dist(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    dist(best).max(dist(0.5 * (lo + hi)))
}

/// A deviation report against the true maximum distance `truth`: `max_found` is attained (so at
/// most the truth), `upper_bound` is guaranteed (so at least it), and the two are within 1% of
/// each other (bezier/bound.rs).
fn assert_brackets(dev: &geomkit::bezier::DeviationBound, truth: f64, vertex: usize) {
    assert!(
        dev.max_found <= truth * (1.0 + 1e-12),
        "vertex {vertex}: {dev:?} vs {truth}"
    );
    assert!(
        dev.upper_bound >= truth,
        "vertex {vertex}: {dev:?} vs {truth}"
    );
    assert!(
        dev.upper_bound <= dev.max_found * 1.01 + 1e-12,
        "vertex {vertex}: {dev:?}"
    );
}

/// The paper's claim, made precise: the middle vertex m = round(n/2) is the one whose weight
/// b_nm(t) has the smallest peak, b_nm(m/n), so moving it moves the curve least. Checked
/// against a brute-force maximum of every Bernstein polynomial up to degree 30, and exactly at
/// n = 10 (C(10,5)/2^10) and n = 40 (C(40,20)/2^40).
#[test]
fn middle_vertex_has_the_smallest_peak_weight() {
    use geomkit::bezier::edit::middle_vertex_weight;
    for n in 1..=30usize {
        let peaks: Vec<f64> = (0..=n)
            .map(|i| {
                let dense = (0..=4000)
                    .map(|j| bernstein(n, i, j as f64 / 4000.0))
                    .fold(0.0, f64::max);
                let at_i_over_n = bernstein(n, i, i as f64 / n as f64);
                // b_ni peaks at t = i/n: no parameter of the dense grid does better.
                assert!(dense <= at_i_over_n * (1.0 + 1e-12), "n={n} i={i}");
                at_i_over_n
            })
            .collect();
        let smallest = peaks.iter().copied().fold(f64::INFINITY, f64::min);
        let m = n.div_ceil(2);
        assert!(
            (peaks[m] - smallest).abs() <= 1e-13 * smallest,
            "n={n}: the middle vertex {m} peaks at {}, another at {smallest}",
            peaks[m]
        );
        // Only the middle vertex (two of them for odd n) attains the smallest peak.
        for (i, p) in peaks.iter().enumerate() {
            if i != n / 2 && i != m {
                assert!(*p > smallest * (1.0 + 1e-9), "n={n} i={i}");
            }
        }
        assert!((middle_vertex_weight(n) - peaks[m]).abs() <= 1e-13 * peaks[m]);
    }
    // Exact values: C(10,5)/2^10 = 252/1024 and C(40,20)/2^40; the peak tends to zero like
    // sqrt(2/(πn)).
    assert_eq!(middle_vertex_weight(10), 252.0 / 1024.0);
    let w40 = 137_846_528_820.0 / 1_099_511_627_776.0;
    assert!(
        (middle_vertex_weight(40) - w40).abs() <= 1e-15,
        "{}",
        middle_vertex_weight(40)
    );
    for n in [100usize, 1000] {
        let ratio = middle_vertex_weight(n) / (2.0 / (std::f64::consts::PI * n as f64)).sqrt();
        assert!((ratio - 1.0).abs() < 0.5 / n as f64, "n={n}: {ratio}");
    }

    // What the peak weight means: moving vertex i by v moves the curve by exactly
    // max_t b_ni(t)·|v| = b_ni(i/n)·|v|, least for the middle vertex.
    let c = BezierCurve::new(
        (0..=10)
            .map(|i| vec![i as f64, ((i * 7) % 5) as f64])
            .collect(),
    )
    .unwrap();
    let v = [0.6, -0.8];
    for i in 0..=10 {
        let mut moved = c.points();
        moved[i][0] += v[0];
        moved[i][1] += v[1];
        let dev = c.deviation_from(&BezierCurve::new(moved).unwrap()).unwrap();
        let want = bernstein(10, i, i as f64 / 10.0);
        assert_brackets(&dev, want, i);
    }
}

/// Removing a vertex re-weights all the others, so the removal of the middle vertex is not
/// the one that moves the curve least. For each vertex of a degree-10 curve: the change is
/// Σ_k b_nk(t) δ_k with the δ_k of the module docs of bezier/edit.rs (checked against the two
/// curves evaluated by brute force), the library's measured deviation equals a brute-force
/// maximum over dense parameters, and both its guaranteed bound and that maximum stay below
/// max_k |δ_k|.
#[test]
fn removing_a_vertex_moves_the_curve_by_at_most_the_largest_delta() {
    let points: Vec<Vec<f64>> = (0..=10)
        .map(|i| vec![i as f64, ((i * 7) % 5) as f64])
        .collect();
    let c = BezierCurve::new(points.clone()).unwrap();
    let n = 10;
    let mut measured = Vec::new();
    for i in 0..=n {
        let edit = c.remove_vertex(i).unwrap();
        let mut rest = points.clone();
        rest.remove(i);
        assert_eq!(edit.curve.points(), rest);

        // P_k, and zero outside 0..=n (where its factor k/n or 1 - k/n is zero anyway).
        let p = |k: isize, d: usize| {
            usize::try_from(k)
                .ok()
                .and_then(|k| points.get(k))
                .map_or(0.0, |q| q[d])
        };
        let deltas: Vec<Vec<f64>> = (0..=n as isize)
            .map(|k| {
                let (a, b) = (k as f64 / n as f64, 1.0 - k as f64 / n as f64);
                (0..2)
                    .map(|d| match k.cmp(&(i as isize)) {
                        std::cmp::Ordering::Less => a * (p(k, d) - p(k - 1, d)),
                        std::cmp::Ordering::Greater => b * (p(k, d) - p(k + 1, d)),
                        std::cmp::Ordering::Equal => p(k, d) - a * p(k - 1, d) - b * p(k + 1, d),
                    })
                    .collect()
            })
            .collect();
        let bound = deltas.iter().map(|d| norm(d)).fold(0.0, f64::max);
        for j in 0..=200 {
            let t = j as f64 / 200.0;
            let (x, y, z) = (
                brute_eval(&points, t),
                brute_eval(&rest, t),
                brute_eval(&deltas, t),
            );
            for d in 0..2 {
                assert!((x[d] - y[d] - z[d]).abs() <= 1e-13, "i={i} t={t}");
            }
            assert!(norm(&z) <= bound + 1e-13);
        }

        let brute = brute_max_distance(&points, &rest);
        assert_brackets(&edit.deviation, brute, i);
        assert!(brute <= bound + 1e-13, "i={i}: {brute} > {bound}");
        measured.push(brute);
    }
    // Removing the middle vertex moves this curve 0.61, removing vertex 4 only 0.30 and vertex 6
    // 0.34: the middle vertex is the least influential by weight, not by removal.
    let middle = c.remove_middle_vertex().unwrap();
    assert_eq!(middle.index, 5);
    assert_eq!(middle.curve, c.remove_vertex(5).unwrap().curve);
    let rounded: Vec<f64> = measured
        .iter()
        .map(|d| (d * 100.0).round() / 100.0)
        .collect();
    assert_eq!(&rounded[4..=6], &[0.30, 0.61, 0.34], "{measured:?}");
    assert!(measured[5] > measured[4] && measured[5] > measured[6]);
}

/// The paper's exact formula refuses degrees whose exact matrices would take minutes (or
/// for ever) before starting, naming the degree and the limit.
#[test]
fn paper_formula_has_a_degree_limit() {
    let c = example2();
    let limit = geomkit::bezier::MAX_PAPER_DEGREE;
    assert_eq!(c.change_degree_paper(limit).unwrap().degree(), limit);
    let e = c.change_degree_paper(10_000_000).unwrap_err();
    assert!(
        matches!(
            e,
            Error::TooLarge {
                size: 10_000_000,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("above the limit of 100"), "{e}");
    let s =
        BezierSurface::new(vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]]).unwrap();
    assert!(matches!(
        s.change_degree_paper(2, limit + 1),
        Err(Error::TooLarge { .. })
    ));
}
