//! Bézier surfaces: the eight order-change problems of (14), defects (16), derivatives.

mod common;

use common::{bernstein, Rng};
use geomkit::bezier::{BezierSurface, Direction, RationalBezierCurve, RationalBezierSurface};
use geomkit::geom::{Curve, Surface};
use geomkit::Error;

fn random_surface(n: usize, m: usize, seed: u64) -> BezierSurface {
    let mut rng = Rng(seed | 1);
    let net = (0..=n)
        .map(|i| {
            (0..=m)
                .map(|j| {
                    vec![
                        i as f64 + 0.3 * rng.uniform(),
                        j as f64 + 0.3 * rng.uniform(),
                        rng.uniform(),
                    ]
                })
                .collect()
        })
        .collect();
    BezierSurface::new(net).unwrap()
}

fn grid_distance(a: &BezierSurface, b: &BezierSurface) -> f64 {
    let ts: Vec<f64> = (0..=24).map(|k| k as f64 / 24.0).collect();
    let mut pa = vec![0.0; 25 * 25 * 3];
    let mut pb = pa.clone();
    a.eval_grid(&ts, &ts, &mut pa).unwrap();
    b.eval_grid(&ts, &ts, &mut pb).unwrap();
    common::max_abs_diff(&pa, &pb)
}

/// Every combination of n' <,=,> n with m' <,=,> m (the identity included) on a surface of
/// real degrees (2, 3) stored on a (5, 6) net keeps the surface.
#[test]
fn all_eight_order_change_problems() {
    let base = random_surface(2, 3, 11);
    let s = base.change_degree(5, 6, None).unwrap();
    assert_eq!(s.degree_report(None).unwrap().defects(), (3, 3));
    for n_new in [3usize, 5, 8] {
        for m_new in [4usize, 6, 9] {
            let t = s.change_degree(n_new, m_new, None).unwrap();
            assert_eq!(t.degrees(), (n_new, m_new));
            let d = grid_distance(&s, &t);
            assert!(d < 1e-13 * s.scale(), "({n_new},{m_new}): {d:e}");
            // The paper's formula (14) with rounded exact matrices agrees (low degrees).
            let p = s.change_degree_paper(n_new, m_new).unwrap();
            assert!(grid_distance(&s, &p) < 1e-11 * s.scale());
        }
    }
    // Below the real degree in u: an error naming u; the paper's formula truncates instead.
    match s.change_degree(1, 6, None) {
        Err(Error::SurfaceDefectTooSmall {
            direction: "u",
            real_degree: 2,
            requested: 1,
            defect: 3,
        }) => {}
        other => panic!("{other:?}"),
    }
    let truncated = s.change_degree_paper(1, 6).unwrap();
    assert!(grid_distance(&s, &truncated) > 1e-3);
}

#[test]
fn surface_grid_matches_pointwise_and_corners() {
    let s = random_surface(4, 3, 5);
    let us = [0.0, 0.25, 1.0];
    let vs = [0.0, 0.6, 1.0];
    let mut out = vec![0.0; 9 * 3];
    s.eval_grid(&us, &vs, &mut out).unwrap();
    for (a, &u) in us.iter().enumerate() {
        for (b, &v) in vs.iter().enumerate() {
            let p = s.eval(u, v);
            assert_eq!(&out[(a * 3 + b) * 3..(a * 3 + b + 1) * 3], &p[..]);
        }
    }
    assert_eq!(s.eval(0.0, 0.0), s.point(0, 0));
    assert_eq!(s.eval(1.0, 1.0), s.point(4, 3));
    assert!(matches!(
        s.eval_grid(&us, &vs, &mut [0.0; 3]),
        Err(Error::BufferSize { .. })
    ));
    assert!(matches!(
        s.eval_grid(&[f64::NAN], &vs, &mut [0.0; 9]),
        Err(Error::NonFinite {
            what: "parameter u",
            index: 0
        })
    ));
}

#[test]
fn partial_derivatives_and_normals() {
    // The paraboloid patch z = x^2 + y^2 over [0,1]^2 as a biquadratic surface.
    let net: Vec<Vec<Vec<f64>>> = (0..3)
        .map(|i| {
            (0..3)
                .map(|j| {
                    let (x, y) = (i as f64 / 2.0, j as f64 / 2.0);
                    // Control heights of x^2 in Bernstein form: 0, 0, 1 (per direction).
                    let z = [0.0, 0.0, 1.0][i] + [0.0, 0.0, 1.0][j];
                    vec![x, y, z]
                })
                .collect()
        })
        .collect();
    let s = BezierSurface::new(net).unwrap();
    let (u, v) = (0.3, 0.7);
    assert!((s.eval(u, v)[2] - (u * u + v * v)).abs() < 1e-15);
    let su = s.derivative(Direction::U).eval(u, v);
    let sv = s.derivative(Direction::V).eval(u, v);
    assert!((su[2] - 2.0 * u).abs() < 1e-15 && (sv[2] - 2.0 * v).abs() < 1e-15);
    let nrm = s.normal(u, v).unwrap().unwrap();
    let want = [-2.0 * u, -2.0 * v, 1.0];
    let len = (want[0] * want[0] + want[1] * want[1] + 1.0f64).sqrt();
    for k in 0..3 {
        assert!((nrm[k] - want[k] / len).abs() < 1e-15);
    }
    // A collapsed edge (all of row 0 in one point) has no normal there.
    let mut net = s.net();
    for p in net[0].iter_mut() {
        *p = vec![0.0, 0.0, 0.0];
    }
    let cone = BezierSurface::new(net).unwrap();
    assert_eq!(cone.normal(0.0, 0.5).unwrap(), None);
    let flat = BezierSurface::new(vec![vec![vec![0.0, 0.0], vec![1.0, 0.0]]]).unwrap();
    assert!(matches!(
        flat.normal(0.5, 0.5),
        Err(Error::WrongDimension {
            expected: 3,
            got: 2,
            ..
        })
    ));
}

#[test]
fn surface_rejects_bad_nets() {
    assert!(matches!(
        BezierSurface::new(vec![]),
        Err(Error::Empty { .. })
    ));
    assert!(matches!(
        BezierSurface::new(vec![vec![vec![0.0; 3]; 2], vec![vec![0.0; 3]; 1]]),
        Err(Error::RaggedNet {
            row: 1,
            expected: 2,
            got: 1
        })
    ));
    assert!(matches!(
        BezierSurface::new(vec![vec![vec![0.0; 3], vec![0.0, f64::INFINITY, 0.0]]]),
        Err(Error::NonFinite { index: 1, .. })
    ));
    assert!(matches!(
        BezierSurface::new(vec![vec![vec![0.0; 3], vec![0.0; 2]]]),
        Err(Error::DimensionMismatch { index: 1, .. })
    ));
}

#[test]
fn rational_curves_change_order_through_homogeneous_coordinates() {
    // A full circle as four rational quadratic quarter arcs: check one quarter at high degree.
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let arc = RationalBezierCurve::new(
        vec![vec![1.0, 0.0], vec![1.0, 1.0], vec![0.0, 1.0]],
        vec![1.0, w, 1.0],
    )
    .unwrap();
    for target in [3usize, 10, 40] {
        let e = arc.elevate_degree(target).unwrap();
        assert_eq!(e.degree(), target);
        for k in 0..=100 {
            let p = e.eval(k as f64 / 100.0);
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15, "degree {target}");
        }
        assert_eq!(e.degree_report(None).unwrap().real_degree, 2);
        let back = e.reduce_degree(2, None).unwrap();
        for (a, b) in back
            .points()
            .iter()
            .flatten()
            .zip([1.0, 0.0, 1.0, 1.0, 0.0, 1.0])
        {
            assert!((a - b).abs() < 1e-13);
        }
    }
    assert!(matches!(
        arc.reduce_degree(1, None),
        Err(Error::DegreeDefectTooSmall {
            real_degree: 2,
            requested: 1,
            ..
        })
    ));
}

/// An octant of the unit sphere as a rational biquadratic: the quarter circle of the meridian
/// (weights 1, 1/√2, 1) turned through 90° about z (the same weights), w_ij = w_i w_j.
fn sphere_octant() -> RationalBezierSurface {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let turn = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let meridian = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let w = [1.0, h, 1.0];
    let net = turn
        .iter()
        .map(|&(c, s)| {
            meridian
                .iter()
                .map(|&(r, z)| vec![r * c, r * s, z])
                .collect()
        })
        .collect();
    let weights = w
        .iter()
        .map(|a| w.iter().map(|b| a * b).collect())
        .collect();
    RationalBezierSurface::new(net, weights).unwrap()
}

#[test]
fn rational_surfaces_change_order_keeping_the_sphere() {
    let octant = sphere_octant();
    let ts: Vec<f64> = (0..=20).map(|k| k as f64 / 20.0).collect();
    for (n, m) in [(2, 2), (5, 2), (3, 7), (9, 9)] {
        let e = octant.change_degree(n, m, None).unwrap();
        assert_eq!(e.degrees(), (n, m));
        assert_eq!(e.degree_report(None).unwrap().real_degrees(), (2, 2));
        let mut grid = vec![0.0; 21 * 21 * 3];
        e.eval_grid(&ts, &ts, &mut grid).unwrap();
        for p in grid.chunks_exact(3) {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((r - 1.0).abs() < 2e-15, "({n}, {m}): |p| = {r}");
        }
        // Exactly back to the biquadratic: the same weights and net.
        let back = e.change_degree(2, 2, None).unwrap();
        let scale = back.weights()[0][0];
        for (a, b) in back
            .weights()
            .iter()
            .flatten()
            .zip(octant.weights().iter().flatten())
        {
            assert!((a / scale - b).abs() < 1e-14, "({n}, {m})");
        }
        for (a, b) in back
            .net()
            .iter()
            .flatten()
            .flatten()
            .zip(octant.net().iter().flatten().flatten())
        {
            assert!((a - b).abs() < 1e-13, "({n}, {m})");
        }
    }
    assert!(matches!(
        octant
            .change_degree(2, 9, None)
            .unwrap()
            .change_degree(1, 9, None),
        Err(Error::SurfaceDefectTooSmall {
            direction: "u",
            real_degree: 2,
            requested: 1,
            ..
        })
    ));
}

/// Direct double sum Σ w b b u / Σ w b b with binomials (not de Casteljau).
fn rational_sum(net: &[Vec<Vec<f64>>], w: &[Vec<f64>], u: f64, v: f64) -> Vec<f64> {
    let (n, m) = (net.len() - 1, net[0].len() - 1);
    let dim = net[0][0].len();
    let mut num = vec![0.0; dim];
    let mut den = 0.0;
    for i in 0..=n {
        for j in 0..=m {
            let b = bernstein(n, i, u) * bernstein(m, j, v) * w[i][j];
            den += b;
            for (x, p) in num.iter_mut().zip(&net[i][j]) {
                *x += b * p;
            }
        }
    }
    num.iter().map(|x| x / den).collect()
}

#[test]
fn rational_surface_values_and_derivatives_against_the_sums() {
    let mut rng = common::Rng(77);
    let (n, m) = (4, 3);
    let net: Vec<Vec<Vec<f64>>> = (0..=n)
        .map(|i| {
            (0..=m)
                .map(|j| vec![i as f64, j as f64, rng.uniform()])
                .collect()
        })
        .collect();
    let w: Vec<Vec<f64>> = (0..=n)
        .map(|_| (0..=m).map(|_| 0.2 + 3.0 * rng.uniform().abs()).collect())
        .collect();
    let s = RationalBezierSurface::new(net.clone(), w.clone()).unwrap();
    assert_eq!(s.net(), net);
    assert_eq!(s.weights(), w);
    let d = 1e-4;
    for &(u, v) in &[(0.0, 0.0), (0.25, 0.8), (0.6, 0.1), (1.0, 1.0), (0.5, 0.5)] {
        let p = Surface::eval(&s, u, v);
        let q = rational_sum(&net, &w, u, v);
        assert!(common::max_abs_diff(&p, &q) < 1e-14, "value at ({u}, {v})");
        // First and mixed derivatives against fourth-order central differences of the sums.
        let f = |a: f64, b: f64| rational_sum(&net, &w, a, b);
        let diff = |g: &dyn Fn(f64) -> Vec<f64>| -> Vec<f64> {
            let (a, b, c, e) = (g(-2.0 * d), g(-d), g(d), g(2.0 * d));
            (0..3)
                .map(|k| (a[k] - 8.0 * b[k] + 8.0 * c[k] - e[k]) / (12.0 * d))
                .collect()
        };
        let du = diff(&|h| f(u + h, v));
        let dv = diff(&|h| f(u, v + h));
        let duv = diff(&|h| diff(&|k| f(u + h, v + k)));
        for (order, want) in [((1, 0), du), ((0, 1), dv), ((1, 1), duv)] {
            let mut got = [0.0; 3];
            s.derivative_into(u, v, order, &mut got).unwrap();
            assert!(
                common::max_abs_diff(&got, &want) < 1e-6,
                "{order:?} at ({u}, {v}): {got:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn rational_surface_with_huge_points_and_weights_stays_finite() {
    // w_ij u_ij overflows f64 unscaled: the homogeneous net holds the weights scaled.
    let big = 1.0e300;
    let s = RationalBezierSurface::new(
        vec![
            vec![vec![big, 0.0], vec![big, big]],
            vec![vec![-big, 0.0], vec![-big, big]],
        ],
        vec![vec![1e10, 1.0], vec![1.0, 1e10]],
    )
    .unwrap();
    let p = Surface::eval(&s, 0.5, 0.5);
    assert!(p.iter().all(|x| x.is_finite() && x.abs() <= big));
    assert_eq!(s.weights()[0][0], 1e10);
}
