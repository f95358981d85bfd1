//! Tessellation of every model type: closed bodies watertight with their exact volumes,
//! adaptive sampling within its tolerance, mesh vertices on the surface.

use geomkit::bezier::{BezierCurve, BezierSurface, RationalBezierCurve};
use geomkit::bspline::{interpolate_curve, interpolate_surface, BsplineSurface};
use geomkit::compose::{bodies, CompositeSurface};
use geomkit::geom::{Curve, Surface};
use geomkit::mesh::{
    tessellate_curve, tessellate_surface, CurveOptions, Polyline, SurfaceOptions, TriMesh,
};
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
    // The cube is the ruled surface through the top centre, the top square, the bottom square
    // and the bottom centre (v = 0, 1, 2, 3, u in [0, 4], one side of the squares per unit of
    // u). Adaptive sampling starts from 9 lines per direction plus the break lines: u = 0, 0.5,
    // ..., 4 (the breaks u = 1, 2, 3 are among them) and v = 0, 0.375, ..., 3 plus the breaks
    // v = 1, 2: 9 × 11 lines, 8 × 10 cells. Every cell is a bilinear patch of a flat face, so
    // the surface at the midpoints of its edges and at its centre is exactly the interpolation
    // of its corners and nothing is refined, at any tolerance. 2 triangles per cell (160),
    // less one per cell of the two rows at the poles, where two corners weld into one:
    // 160 - 2 × 8 = 144 triangles. Vertices: 2 poles + 9 rings of 8 (the seam u = 0 ~ 4
    // welds) = 74, and 74 - 216 + 144 = 2 (Euler).
    let cube = bodies::cube().unwrap();
    for tol in [1e-1, 1e-6, 1e-12] {
        let m = tessellate_surface(&cube, &SurfaceOptions::adaptive(tol)).unwrap();
        check_closed(&m, 8.0, "adaptive cube");
        assert_eq!(m.triangles().len(), 144, "tolerance {tol}");
        assert_eq!(m.positions().len(), 74, "tolerance {tol}");
        // All vertices on the cube's surface: a coordinate of ±1, the others within [-1, 1].
        for p in m.positions() {
            assert!(p.iter().all(|x| x.abs() <= 1.0 + 1e-15), "{p:?}");
            assert!(p.iter().any(|x| (x.abs() - 1.0).abs() <= 1e-15), "{p:?}");
        }
    }
}

/// The degree-(2,2) Bézier bump over [0, 2]²: x = 2u and y = 2v (the net's x and y are
/// equally spaced), z = 4·(2u(1-u))·(2v(1-v)) (the one non-zero height is 4 at the centre).
fn bump() -> BezierSurface {
    BezierSurface::new(vec![
        vec![vec![0., 0., 0.], vec![0., 1., 0.], vec![0., 2., 0.]],
        vec![vec![1., 0., 0.], vec![1., 1., 4.], vec![1., 2., 0.]],
        vec![vec![2., 0., 0.], vec![2., 1., 0.], vec![2., 2., 0.]],
    ])
    .unwrap()
}

/// Height of [`bump`] over (x, y): with u = x/2, v = y/2, 16 u(1-u) v(1-v) = x(2-x) y(2-y).
fn bump_height(x: f64, y: f64) -> f64 {
    x * (2.0 - x) * y * (2.0 - y)
}

/// Distance from `p` to the bump z = x(2-x) y(2-y), (x, y) in [0, 2]²: Newton's method on the
/// squared distance from the point below `p`, then the vertical distance as a cap (the surface
/// point below `p` is one candidate).
fn distance_to_bump(p: [f64; 3]) -> f64 {
    let (mut x, mut y) = (p[0], p[1]);
    for _ in 0..20 {
        let f = bump_height(x, y) - p[2];
        let (fx, fy) = (
            (2.0 - 2.0 * x) * y * (2.0 - y),
            x * (2.0 - x) * (2.0 - 2.0 * y),
        );
        let (fxx, fyy, fxy) = (
            -2.0 * y * (2.0 - y),
            -2.0 * x * (2.0 - x),
            (2.0 - 2.0 * x) * (2.0 - 2.0 * y),
        );
        let (gx, gy) = (x - p[0] + f * fx, y - p[1] + f * fy);
        let (hxx, hyy, hxy) = (
            1.0 + fx * fx + f * fxx,
            1.0 + fy * fy + f * fyy,
            fx * fy + f * fxy,
        );
        let det = hxx * hyy - hxy * hxy;
        if det <= 0.0 {
            break;
        }
        x = (x - (hyy * gx - hxy * gy) / det).clamp(0.0, 2.0);
        y = (y - (hxx * gy - hxy * gx) / det).clamp(0.0, 2.0);
    }
    let d = |x: f64, y: f64| {
        ((x - p[0]).powi(2) + (y - p[1]).powi(2) + (bump_height(x, y) - p[2]).powi(2)).sqrt()
    };
    d(x, y).min(d(p[0], p[1]))
}

/// Largest distance from a mesh of [`bump`] to the surface, over the points of barycentric
/// coordinates (i, j, k)/8 of every triangle (corners, edge midpoints and points near the
/// centroid among them): (geometric distance, distance to the surface point at the same (u, v),
/// which is (x, y, bump_height(x, y)) since x = 2u and y = 2v on the mesh too).
fn bump_mesh_distance(m: &TriMesh) -> (f64, f64) {
    let n = 8;
    let (mut worst, mut worst_vertical) = (0.0f64, 0.0f64);
    for t in m.triangles() {
        let [a, b, c] = t.map(|k| m.positions()[k as usize]);
        for i in 0..=n {
            for j in 0..=n - i {
                let w = [i as f64, j as f64, (n - i - j) as f64].map(|x| x / n as f64);
                let p: [f64; 3] = std::array::from_fn(|k| w[0] * a[k] + w[1] * b[k] + w[2] * c[k]);
                worst = worst.max(distance_to_bump(p));
                worst_vertical = worst_vertical.max((p[2] - bump_height(p[0], p[1])).abs());
            }
        }
    }
    (worst, worst_vertical)
}

/// The adaptive mesh of the bump is within its tolerance of the surface, measured (not just
/// counted): 0.048, 0.0072 and 0.00066 at tolerances 0.1, 0.01 and 0.001 (before the centre of
/// each cell was checked against the triangles actually drawn, 0.0038 at 0.001). A finer
/// tolerance gives more triangles, a smaller distance, and an area growing towards the
/// surface's.
#[test]
fn adaptive_bump_is_within_tolerance() {
    let s = bump();
    let mut coarser: Option<(usize, f64, f64)> = None;
    for tol in [1e-1, 1e-2, 1e-3] {
        let m = tessellate_surface(&s, &SurfaceOptions::adaptive(tol)).unwrap();
        let (dist, vertical) = bump_mesh_distance(&m);
        let (count, area) = (m.triangles().len(), m.area());
        assert!(dist <= tol, "tolerance {tol}: distance {dist}");
        // Not trivially small: the mesh is as coarse as the tolerance allows.
        assert!(dist > tol / 4.0, "tolerance {tol}: distance {dist}");
        assert!(dist <= vertical + 1e-15);
        if let Some((count0, dist0, area0)) = coarser {
            assert!(count > 2 * count0, "{count} vs {count0}");
            assert!(dist < dist0 / 4.0, "{dist} vs {dist0}");
            assert!(area0 <= area + 1e-12 && area - area0 < 2.0 * tol * area);
        }
        coarser = Some((count, dist, area));
    }
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

/// Distance from `p` to the segment [a, b].
fn distance_to_segment(p: &[f64], a: &[f64], b: &[f64]) -> f64 {
    let ab: Vec<f64> = a.iter().zip(b).map(|(x, y)| y - x).collect();
    let len2: f64 = ab.iter().map(|x| x * x).sum();
    let dot: f64 = p
        .iter()
        .zip(a)
        .zip(&ab)
        .map(|((p, a), d)| (p - a) * d)
        .sum();
    let s = if len2 > 0.0 {
        (dot / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.iter()
        .zip(a)
        .zip(&ab)
        .map(|((p, a), d)| (p - a - s * d).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Largest distance from the curve to its polyline, measured at 64 parameters inside every
/// segment's parameter interval (to that segment, which bounds the distance to the polyline).
fn polyline_distance(curve: &dyn Curve, line: &Polyline) -> f64 {
    let mut worst = 0.0f64;
    for k in 0..line.len() - 1 {
        let (t0, t1) = (line.params()[k], line.params()[k + 1]);
        for j in 1..64 {
            let q = curve.eval(t0 + (t1 - t0) * j as f64 / 64.0);
            worst = worst.max(distance_to_segment(&q, line.point(k), line.point(k + 1)));
        }
    }
    worst
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
    // Measured, not counted: the distance from each curve to its polyline at dense parameters
    // is within the tolerance and near it (0.0096 and 0.000099 for the cubic Bézier at 0.01
    // and 0.0001); a finer tolerance gives more points and a smaller distance.
    let curves: [(&str, &dyn Curve); 3] = [("bezier", &c), ("bspline", &b), ("pointcalc", &pe)];
    for (name, curve) in curves {
        let mut coarser: Option<(usize, f64)> = None;
        for tol in [1e-2, 1e-4] {
            let line =
                tessellate_curve(curve, &CurveOptions::default().with_tolerance(tol)).unwrap();
            // 16 starting segments.
            assert!(line.len() >= 17, "{name}");
            assert!(line.params().windows(2).all(|w| w[0] < w[1]));
            let dist = polyline_distance(curve, &line);
            assert!(dist <= tol, "{name}, tolerance {tol}: {dist}");
            assert!(dist > tol / 4.0, "{name}, tolerance {tol}: {dist}");
            if let Some((len0, dist0)) = coarser {
                assert!(line.len() > len0 && dist < dist0 / 10.0, "{name}");
            }
            coarser = Some((line.len(), dist));
        }
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
    #![proptest_config(ProptestConfig::with_cases(256))]

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
