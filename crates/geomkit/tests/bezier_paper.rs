//! The worked examples of Nikulin (2011), spec/bezier-order.md, reproduced exactly.

use geomkit::bezier::{BezierCurve, BezierSurface, Direction};
use geomkit::exact::{
    degree_change_matrix, elevation_matrix, h_inverse, h_matrix, ExactBezierCurve, ExactMatrix,
    Rational,
};
use geomkit::geom::Curve;
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

#[test]
fn middle_vertex_is_least_influential() {
    let c = BezierCurve::new(
        (0..=10)
            .map(|i| vec![i as f64, ((i * 7) % 5) as f64])
            .collect(),
    )
    .unwrap();
    let middle = c.remove_middle_vertex().unwrap();
    assert_eq!(middle.index, 5);
    for i in [0usize, 1, 9, 10] {
        let other = c.remove_vertex(i).unwrap();
        assert!(other.deviation.max_found > middle.deviation.max_found * 0.0 + 1e-3);
    }
    // The weight bound b_nm(m/n) decreases with n.
    let w10 = geomkit::bezier::edit::middle_vertex_weight(10);
    let w40 = geomkit::bezier::edit::middle_vertex_weight(40);
    assert!(
        (w10 - 0.246_093_75).abs() < 1e-12 && w40 < w10,
        "{w10} {w40}"
    );
    let _ = c.eval(0.5);
}
