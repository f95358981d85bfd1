//! Tessellation of every model type: closed bodies watertight with their exact volumes,
//! adaptive sampling within its tolerance, mesh vertices on the surface.

use geomkit::bezier::{BezierCurve, BezierSurface, RationalBezierCurve};
use geomkit::bspline::{interpolate_curve, interpolate_surface, BsplineSurface};
use geomkit::compose::{bodies, CompositeSurface};
use geomkit::geom::Surface;
use geomkit::mesh::{tessellate_curve, tessellate_surface, CurveOptions, SurfaceOptions, TriMesh};
use geomkit::pointcalc::{Nodes, PointEquation, PointSurface, PrintedSurface};
use proptest::prelude::*;
use std::f64::consts::PI;

fn check_closed(mesh: &TriMesh, volume: f64, what: &str) {
    assert!(mesh.is_watertight(), "{what}: not watertight");
    assert_eq!(mesh.boundary_edge_count(), 0, "{what}");
    let v = mesh.volume();
    assert!(
        (v - volume).abs() <= 1e-12 * volume.max(1.0),
        "{what}: volume {v}, expected {volume}"
    );
}

/// Volume of the prism over a regular n-gon inscribed in radius r.
fn ngon_area(n: usize, r: f64) -> f64 {
    n as f64 / 2.0 * r * r * (2.0 * PI / n as f64).sin()
}

#[test]
fn bodies_are_watertight_with_exact_volumes() {
    let uniform = SurfaceOptions::uniform(33, 13);
    check_closed(
        &tessellate_surface(&bodies::cube().unwrap(), &uniform).unwrap(),
        8.0,
        "cube",
    );
    check_closed(
        &tessellate_surface(&bodies::rectangular_box(1.0, 2.0, 3.0).unwrap(), &uniform).unwrap(),
        6.0,
        "box",
    );
    check_closed(
        &tessellate_surface(&bodies::square_pyramid(2.0, 3.0).unwrap(), &uniform).unwrap(),
        4.0,
        "pyramid",
    );
    // Circles sampled at k parameters over [0, 2π] (k - 1 segments): inscribed polygons.
    let k = 65;
    let round = SurfaceOptions::uniform(k, 9);
    check_closed(
        &tessellate_surface(&bodies::cone(1.0, 2.0).unwrap(), &round).unwrap(),
        ngon_area(k - 1, 1.0) * 2.0 / 3.0,
        "cone",
    );
    check_closed(
        &tessellate_surface(&bodies::cylinder(1.0, 2.0).unwrap(), &round).unwrap(),
        ngon_area(k - 1, 1.0) * 2.0,
        "cylinder",
    );
    let (r0, r1, h) = (1.0, 0.5, 2.0);
    let (a0, a1) = (ngon_area(k - 1, r0), ngon_area(k - 1, r1));
    check_closed(
        &tessellate_surface(&bodies::frustum(r0, r1, h).unwrap(), &round).unwrap(),
        h / 3.0 * (a0 + a1 + (a0 * a1).sqrt()),
        "frustum",
    );
    let hexagon: Vec<[f64; 2]> = (0..6)
        .map(|i| {
            let a = i as f64 * PI / 3.0;
            [a.cos(), a.sin()]
        })
        .collect();
    check_closed(
        &tessellate_surface(&bodies::prism(&hexagon, 1.5).unwrap(), &uniform).unwrap(),
        ngon_area(6, 1.0) * 1.5,
        "prism",
    );
}

#[test]
fn cube_mesh_counts_and_sharp_normals() {
    let m = tessellate_surface(&bodies::cube().unwrap(), &SurfaceOptions::uniform(5, 4)).unwrap();
    // u = 0..4 in steps of 1, v = 0..3: 2 poles + 2 squares of 4 vertices.
    assert_eq!(m.positions().len(), 10);
    // 4 cap triangles at each pole + 8 side triangles.
    assert_eq!(m.triangles().len(), 16);
    // Sharp edges: exactly the six axis directions.
    assert_eq!(m.normals().len(), 6);
    for n in m.normals() {
        assert_eq!(n.iter().map(|x| x.abs()).sum::<f64>(), 1.0, "{n:?}");
    }
    // Every corner normal is the face normal (flat faces).
    for (t, ni) in m.normal_indices().iter().enumerate() {
        for &k in ni {
            assert_eq!(m.normals()[k as usize], m.face_normal(t));
        }
    }
}

#[test]
fn adaptive_cube_stays_minimal() {
    // Flat faces need no refinement beyond the starting grid and the breaks.
    let opts = SurfaceOptions::adaptive(1e-6);
    let m = tessellate_surface(&bodies::cube().unwrap(), &opts).unwrap();
    check_closed(&m, 8.0, "adaptive cube");
}

#[test]
fn adaptive_sphere_like_surface_is_within_tolerance() {
    // A degree-(2,2) Bézier bump: refining the tolerance 8 times refines the mesh, and the
    // inscribed mesh's area grows towards the surface's.
    let s = BezierSurface::new(vec![
        vec![vec![0., 0., 0.], vec![0., 1., 0.], vec![0., 2., 0.]],
        vec![vec![1., 0., 0.], vec![1., 1., 4.], vec![1., 2., 0.]],
        vec![vec![2., 0., 0.], vec![2., 1., 0.], vec![2., 2., 0.]],
    ])
    .unwrap();
    let tol = 1e-3;
    let coarse = tessellate_surface(&s, &SurfaceOptions::adaptive(tol)).unwrap();
    let fine = tessellate_surface(&s, &SurfaceOptions::adaptive(tol / 8.0)).unwrap();
    assert!(fine.triangles().len() > 2 * coarse.triangles().len());
    assert!(coarse.area() <= fine.area() + 1e-12);
    assert!(fine.area() - coarse.area() < 1e-2 * fine.area());
    assert_eq!(coarse.boundary_edge_count() % 2, 0);
}

#[test]
fn every_model_type_tessellates_onto_its_surface() {
    let net = vec![
        vec![vec![0., 0., 0.], vec![0., 1., 1.], vec![0., 2., 0.]],
        vec![vec![1., 0., 1.], vec![1., 1., 2.], vec![1., 2., 1.]],
        vec![vec![2., 0., 0.], vec![2., 1., 1.], vec![2., 2., 0.]],
    ];
    let bez = BezierSurface::new(net.clone()).unwrap();
    let pts: Vec<Vec<Vec<f64>>> = (0..5)
        .map(|i| {
            (0..6)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    vec![x, y, (x * 0.7).sin() * (y * 0.5).cos()]
                })
                .collect()
        })
        .collect();
    let bsp: BsplineSurface = interpolate_surface(&pts, &Default::default())
        .unwrap()
        .surface;
    let comp = CompositeSurface::from_bspline(&bsp).unwrap();
    let nodes = || Nodes::new(vec![0.0, 0.5, 1.0]).unwrap();
    let pcs = PointSurface::rows_then_across(vec![nodes(), nodes(), nodes()], nodes(), net.clone())
        .unwrap();
    let printed = PrintedSurface::new(net).unwrap();
    let shapes: [(&str, &dyn Surface); 5] = [
        ("bezier", &bez),
        ("bspline", &bsp),
        ("composite", &comp),
        ("pointcalc", &pcs),
        ("printed", &printed),
    ];
    for (name, s) in shapes {
        for opts in [SurfaceOptions::uniform(12, 9), SurfaceOptions::default()] {
            let m = tessellate_surface(s, &opts).unwrap();
            assert!(m.triangles().len() >= 2 * 11 * 8, "{name}");
            assert!(!m.is_watertight(), "{name}: an open patch");
            // The mesh corners are surface points.
            let ((u0, u1), (v0, v1)) = s.domain();
            for (u, v) in [(u0, v0), (u1, v1)] {
                let mut p = vec![0.0; 3];
                s.eval_grid(&[u], &[v], &mut p).unwrap();
                assert!(
                    m.positions()
                        .iter()
                        .any(|q| (0..3).all(|k| (q[k] - p[k]).abs() <= 1e-12)),
                    "{name}: corner ({u}, {v}) missing"
                );
            }
            // Unit normals.
            for n in m.normals() {
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                assert!((len - 1.0).abs() < 1e-12, "{name}");
            }
        }
    }
}

#[test]
fn height_fields_and_plane_surfaces_are_lifted_to_3d() {
    let heights =
        BezierSurface::new(vec![vec![vec![0.], vec![1.]], vec![vec![2.], vec![3.]]]).unwrap();
    let m = tessellate_surface(&heights, &SurfaceOptions::uniform(3, 3)).unwrap();
    // z = 2u + v over the unit square: (u, v, z).
    for p in m.positions() {
        assert!((p[2] - (2.0 * p[0] + p[1])).abs() < 1e-15);
    }
    let flat = BezierSurface::new(vec![
        vec![vec![0., 0.], vec![0., 1.]],
        vec![vec![1., 0.], vec![1., 1.]],
    ])
    .unwrap();
    let m = tessellate_surface(&flat, &SurfaceOptions::uniform(4, 4)).unwrap();
    assert!((m.area() - 1.0).abs() < 1e-15);
    assert!(m.positions().iter().all(|p| p[2] == 0.0));
}

#[test]
fn bad_requests_are_errors() {
    let cube = bodies::cube().unwrap();
    assert!(tessellate_surface(&cube, &SurfaceOptions::uniform(1, 5)).is_err());
    assert!(tessellate_surface(&cube, &SurfaceOptions::adaptive(0.0)).is_err());
    assert!(tessellate_surface(&cube, &SurfaceOptions::adaptive(f64::NAN)).is_err());
    let s4 = BezierSurface::new(vec![vec![vec![0.; 4]; 2]; 2]).unwrap();
    let e = tessellate_surface(&s4, &SurfaceOptions::default()).unwrap_err();
    assert!(e.to_string().contains("got 4"), "{e}");
}

#[test]
fn curves_of_every_type() {
    let c = BezierCurve::new(vec![
        vec![0., 0.],
        vec![1., 2.],
        vec![3., -1.],
        vec![4., 0.],
    ])
    .unwrap();
    let r = RationalBezierCurve::new(
        vec![vec![1., 0.], vec![1., 1.], vec![0., 1.]],
        vec![1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0],
    )
    .unwrap();
    let pts: Vec<Vec<f64>> = (0..7).map(|i| vec![i as f64, (i as f64).sin()]).collect();
    let b = interpolate_curve(&pts, &Default::default())
        .unwrap()
        .into_curve();
    let pe = PointEquation::new(
        Nodes::new(vec![0.0, 0.5, 1.0]).unwrap(),
        vec![vec![0., 0.], vec![1., 1.], vec![2., 0.]],
    )
    .unwrap();
    let tol = 1e-4;
    let opts = CurveOptions::default().with_tolerance(tol);
    // The quarter circle: chord sagitta r(1 - cos(θ/2)) <= tol.
    let arc = tessellate_curve(&r, &opts).unwrap();
    for k in 0..arc.len() {
        let p = arc.point(k);
        assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0).abs() < 1e-14);
    }
    for k in 0..arc.len() - 1 {
        let (a, b) = (arc.point(k), arc.point(k + 1));
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let sag = 1.0 - (mid[0] * mid[0] + mid[1] * mid[1]).sqrt();
        assert!(sag <= tol * 1.01, "segment {k}: sagitta {sag}");
    }
    for line in [
        tessellate_curve(&c, &opts).unwrap(),
        tessellate_curve(&b, &opts).unwrap(),
        tessellate_curve(&pe, &opts).unwrap(),
    ] {
        assert!(line.len() > 17);
        assert!(line.params().windows(2).all(|w| w[0] < w[1]));
    }
    // B-spline knots are among the parameters.
    let line = tessellate_curve(&b, &opts).unwrap();
    for &k in b.knots() {
        let (t0, t1) = b.domain();
        if k >= t0 && k <= t1 {
            assert!(line.params().contains(&k), "knot {k}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Boxes of any size are watertight with volume a·b·c and area 2(ab + bc + ca), on any
    /// grid.
    #[test]
    fn boxes_have_exact_volume(a in 0.1f64..10.0, b in 0.1f64..10.0, c in 0.1f64..10.0,
                               k in 2usize..20, l in 2usize..9) {
        let body = bodies::rectangular_box(a, b, c).unwrap();
        let m = tessellate_surface(&body, &SurfaceOptions::uniform(k, l)).unwrap();
        prop_assert!(m.is_watertight());
        let vol = a * b * c;
        prop_assert!((m.volume() - vol).abs() <= 1e-12 * vol);
        let area = 2.0 * (a * b + b * c + c * a);
        prop_assert!((m.area() - area).abs() <= 1e-12 * area);
    }

    /// Random Bézier surfaces: the adaptive mesh's vertices are surface points and the
    /// triangles are consistently oriented (no edge traversed twice in one direction).
    #[test]
    fn random_surfaces_mesh_consistently(seed in proptest::collection::vec(-2.0f64..2.0, 27)) {
        let net: Vec<Vec<Vec<f64>>> = (0..3).map(|i| (0..3).map(|j| {
            let k = (i * 3 + j) * 3;
            vec![i as f64 + 0.2 * seed[k], j as f64 + 0.2 * seed[k + 1], seed[k + 2]]
        }).collect()).collect();
        let s = BezierSurface::new(net).unwrap();
        let m = tessellate_surface(&s, &SurfaceOptions::adaptive(1e-3)).unwrap();
        let mut seen = std::collections::HashSet::new();
        for t in m.triangles() {
            for e in 0..3 {
                prop_assert!(seen.insert((t[e], t[(e + 1) % 3])));
            }
        }
    }
}
