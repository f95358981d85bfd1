//! Regressions of meshing on extreme input (issue 21): each case once panicked, overflowed,
//! ran unbounded, or returned an empty or leaking mesh as a success; now each gives a checked
//! mesh or a clear error.

use geomkit::bezier::{BezierCurve, BezierSurface};
use geomkit::compose::{bodies, RuledCurve, RuledSurface};
use geomkit::mesh::{
    tessellate_curve, tessellate_surface, tessellate_surface_report, write_glb, write_obj,
    write_stl_binary, CurveOptions, SurfaceOptions, TriMesh,
};
use geomkit::Error;
use std::f64::consts::TAU;

fn mesh_of(s: &RuledSurface) -> geomkit::Result<TriMesh> {
    tessellate_surface(s, &SurfaceOptions::default())
}

fn assert_closed(m: &TriMesh, volume: f64, rel: f64, what: &str) {
    assert!(m.is_watertight(), "{what}: not watertight");
    let v = m.volume();
    assert!(
        (v - volume).abs() <= rel * volume,
        "{what}: volume {v}, expected {volume}"
    );
    assert!(
        m.positions().iter().flatten().all(|x| x.is_finite()),
        "{what}"
    );
}

/// The weld grid's key was floor(x / tolerance) as i64, plus ±1 for the neighbours: past
/// 9.2e18 cells it saturated at i64::MAX and the + 1 overflowed (a panic in debug).
#[test]
fn weld_keys_do_not_overflow_for_far_coordinates() {
    let tris = vec![[0, 2, 3], [1, 2, 3]];
    let far = |x: f64, tol: f64| {
        TriMesh::new(
            vec![[x, 0., 0.], [x, 0., 0.], [0., x, 0.], [0., 0., x]],
            tris.clone(),
            tol,
            30.0,
        )
        .unwrap()
    };
    // 1e19 cells of width 1: the two equal points weld, the two triangles coincide.
    assert_eq!(far(1e19, 1.0).positions().len(), 4 - 1);
    assert_eq!(far(1e300, 1e-300).positions().len(), 3);
    assert_eq!(far(-f64::MAX, 5e-324).positions().len(), 3);
    // Beyond 2^60 cells, distinct floats are more than 2^7 tolerances apart: never welded.
    let x = 2f64.powi(70);
    let next = f64::from_bits(x.to_bits() + 1);
    let m = TriMesh::new(
        vec![[x, 0., 0.], [next, 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        tris.clone(),
        1.0,
        30.0,
    )
    .unwrap();
    assert_eq!(m.positions().len(), 4);
    // ... unless the tolerance covers the gap (2^18 here): then a near cell.
    let m = TriMesh::new(
        vec![[x, 0., 0.], [next, 0., 0.], [0., x, 0.], [0., 0., x]],
        tris,
        1e6,
        30.0,
    )
    .unwrap();
    assert_eq!(m.positions().len(), 3);
}

#[test]
fn per_axis_weld_keeps_thin_features() {
    let m = TriMesh::new_per_axis(
        vec![[0., 0., 0.], [1e-12, 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        vec![[0, 2, 3], [1, 2, 3]],
        [1e-15, 1e-9, 1e-9],
        30.0,
    )
    .unwrap();
    assert_eq!(m.positions().len(), 4);
    assert!(TriMesh::new_per_axis(vec![], vec![], [0.0, -1.0, 0.0], 30.0).is_err());
}

/// The weld was 1e-9 of the diagonal: the two 1e-9-apart faces of this box merged into a
/// leaking mesh of 23 vertices reported as a success.
#[test]
fn thin_box_is_watertight() {
    let m = mesh_of(&bodies::rectangular_box(1e-9, 1.0, 1.0).unwrap()).unwrap();
    assert_closed(&m, 1e-9, 1e-12, "box 1e-9,1,1");
    let m = mesh_of(&bodies::rectangular_box(1e-13, 1.0, 1.0).unwrap()).unwrap();
    assert_closed(&m, 1e-13, 1e-12, "box 1e-13,1,1");
    // Thinner than f64 resolves at its size (16 ulps of 0.5): an error, not a leaking mesh.
    let e = mesh_of(&bodies::rectangular_box(1e-300, 1.0, 1.0).unwrap()).unwrap_err();
    assert!(matches!(e, Error::MeshFailed { .. }), "{e}");
    assert!(
        e.to_string().contains("too thin or too small for f64"),
        "{e}"
    );
}

/// A weld of 1e3 (1e-9 of the diagonal) merged everything: 0 vertices, exit 0.
#[test]
fn long_box_is_watertight() {
    let m = mesh_of(&bodies::rectangular_box(1.0, 1.0, 1e12).unwrap()).unwrap();
    assert_closed(&m, 1e12, 1e-12, "box 1,1,1e12");
}

/// Weld 1 and chord tolerance 1e6 (from the diagonal) for a circle of radius 1: a leaking
/// 9-vertex mesh. Per axis, the base stays round (1e-3 of its width) and closed.
#[test]
fn tall_cone_is_watertight_and_round() {
    let cone = bodies::cone(1.0, 1e9).unwrap();
    let (m, report) = tessellate_surface_report(&cone, &SurfaceOptions::default()).unwrap();
    assert!(report.closed && !report.capped);
    assert!(report.relative_deviation.unwrap() <= 1e-3, "{report:?}");
    // The base circle's vertices (the cap has rings inside it).
    let n = m
        .positions()
        .iter()
        .filter(|p| p[2] == 0.0 && (p[0].hypot(p[1]) - 1.0).abs() < 1e-12)
        .count();
    assert!(n > 40, "{n} points on the base circle");
    let area = n as f64 / 2.0 * (TAU / n as f64).sin();
    assert_closed(&m, area * 1e9 / 3.0, 1e-9, &format!("cone 1,1e9, {n}-gon"));
}

/// The circle is below the z-axis' f64 resolution: the mesh encloses no volume (was 0
/// vertices, exit 0).
#[test]
fn needle_cylinder_is_an_error() {
    let e = mesh_of(&bodies::cylinder(1e-308, 2.0).unwrap()).unwrap_err();
    assert!(matches!(e, Error::MeshFailed { .. }), "{e}");
    assert!(e.to_string().contains("too thin or too small"), "{e}");
}

#[test]
fn surface_whose_points_coincide_is_an_error() {
    let p = vec![1.0, 2.0, 3.0];
    let s = BezierSurface::new(vec![vec![p.clone(), p.clone()], vec![p.clone(), p]]).unwrap();
    let e = tessellate_surface(&s, &SurfaceOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        "the mesh is empty: every sampled point of the surface is (1, 2, 3)"
    );
    let e = tessellate_surface(&s, &SurfaceOptions::uniform(5, 5)).unwrap_err();
    assert!(matches!(e, Error::MeshFailed { check: "empty", .. }), "{e}");
    assert!(
        e.to_string()
            .starts_with("the mesh is empty: all 32 triangles collapsed"),
        "{e}"
    );
}

/// A cylinder of radius 1e307: the squared diagonal overflowed, the weld tolerance was
/// infinite ("tolerance inf must be finite"). Now a closed mesh in f64; the f32 formats
/// refuse it instead of writing infinities. (Of height 2 it would be an error: thinner than
/// f64 resolves at its size.)
#[test]
fn huge_cylinder_meshes_in_f64_and_f32_formats_refuse_it() {
    let r = 1e307;
    let circle = |z: f64| RuledCurve::Circle {
        center: [0.0, 0.0, z],
        radius: r,
    };
    let h = 1e306;
    let s = RuledSurface::new(
        vec![
            RuledCurve::Point([0.0, 0.0, h]),
            circle(h),
            circle(-h),
            RuledCurve::Point([0.0, 0.0, -h]),
        ],
        vec![0.0, 1.0, 2.0, 3.0],
        (0.0, TAU),
    )
    .unwrap();
    let m = mesh_of(&s).unwrap();
    assert!(m.is_watertight());
    let v = m.volume();
    assert!(v.is_infinite() && v > 0.0, "{v}");
    // Normals are unit vectors (the cross products were infinite).
    for n in m.normals() {
        assert!(
            (n.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12,
            "{n:?}"
        );
    }
    write_obj(&m, Vec::new()).unwrap();
    for e in [
        write_stl_binary(&m, Vec::new()).unwrap_err(),
        write_glb(&m, Vec::new()).unwrap_err(),
    ] {
        assert!(e.to_string().contains("beyond f32's range"), "{e}");
    }
    // Below f32's resolution: a prism 1e-6 wide at x = 1000 would collapse in STL.
    let base = [
        [1000.0, 0.0],
        [1000.0 + 1e-6, 0.0],
        [1000.0 + 1e-6, 1.0],
        [1000.0, 1.0],
    ];
    let thin = mesh_of(&bodies::prism(&base, 1.0).unwrap()).unwrap();
    assert_closed(&thin, 1e-6, 1e-6, "prism 1e-6 wide at x = 1000");
    let e = write_stl_binary(&thin, Vec::new()).unwrap_err();
    assert!(
        e.to_string().contains("collapses when rounded to f32"),
        "{e}"
    );
}

fn saddle() -> BezierSurface {
    // Net x = i, y = j over the heights below (the test surface of tests/render.rs).
    let z = [[0., 0.5, 0.], [0.5, 2., 0.5], [0., 0.5, 0.]];
    let net = (0..3)
        .map(|i| (0..3).map(|j| vec![i as f64, j as f64, z[i][j]]).collect())
        .collect();
    BezierSurface::new(net).unwrap()
}

/// `mesh --tolerance 1e-300` refined to 2049 × 2049 lines (58 s, 1.5 GB): below the
/// resolution of f64 at the model's size it is refused before any refinement.
#[test]
fn tolerance_below_resolution_is_refused_at_once() {
    let e = tessellate_surface(&saddle(), &SurfaceOptions::adaptive(1e-300)).unwrap_err();
    let Error::ToleranceBelowResolution {
        tolerance,
        resolution,
    } = e
    else {
        panic!("{e}")
    };
    assert_eq!(tolerance, 1e-300);
    assert_eq!(resolution, 16.0 * f64::EPSILON * 2.0);
}

/// A reachable-in-f64 tolerance that the triangle cap stops short of: an error naming the
/// deviation reached; the default tolerance stopped by the cap returns the mesh, reported.
#[test]
fn triangle_cap_bounds_adaptive_refinement() {
    let opts = SurfaceOptions::adaptive(1e-9).with_max_triangles(5000);
    let e = tessellate_surface(&saddle(), &opts).unwrap_err();
    let Error::ToleranceOutOfReach {
        tolerance,
        reached,
        ref cap,
    } = e
    else {
        panic!("{e}")
    };
    assert_eq!((tolerance, cap.as_str()), (1e-9, "5000 triangles"));
    assert!(reached > 1e-9 && reached < 1e-2, "{reached}");
    // The reached deviation is reachable within the cap.
    let m = tessellate_surface(
        &saddle(),
        &SurfaceOptions::adaptive(reached).with_max_triangles(5000),
    )
    .unwrap();
    assert!(m.triangles().len() <= 5000);

    let opts = SurfaceOptions::default().with_max_triangles(200);
    let (m, report) = tessellate_surface_report(&saddle(), &opts).unwrap();
    assert!(report.capped && !report.closed);
    assert!(m.triangles().len() <= 200);
    assert!(report.relative_deviation.unwrap() > 1e-3, "{report:?}");
}

#[test]
fn uniform_grid_above_the_cap_is_an_error() {
    let e = tessellate_surface(&saddle(), &SurfaceOptions::uniform(2000, 2000)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "a 2000 × 2000 sample grid (2000 × 2000 with the break lines) gives 7992002 triangles, \
         above the cap of 2000000"
    );
}

#[test]
fn polyline_caps() {
    let c = BezierCurve::new(vec![vec![0., 0.], vec![1., 2.], vec![2., 0.]]).unwrap();
    let mut opts = CurveOptions::default();
    opts.min_segments = usize::MAX - 1;
    let e = tessellate_curve(&c, &opts).unwrap_err();
    assert!(
        matches!(e, Error::MeshTooLarge { unit: "points", .. }),
        "{e}"
    );
    let mut opts = CurveOptions::default().with_tolerance(1e-12);
    opts.max_points = 100;
    let e = tessellate_curve(&c, &opts).unwrap_err();
    let Error::ToleranceOutOfReach { reached, .. } = e else {
        panic!("{e}")
    };
    assert!(reached > 1e-12 && reached < 1e-2, "{reached}");
    // The default tolerance gets at most max_points.
    opts.tolerance = None;
    opts.max_points = 20;
    assert!(tessellate_curve(&c, &opts).unwrap().len() <= 20);
}

/// A 10000-gon checks in O(k) (star-shaped about its centroid and winding once); above the
/// limit the polygon is refused before anything is built.
#[test]
fn polygon_limits() {
    let p = bodies::regular_polygon(bodies::MAX_POLYGON_VERTICES, 1.0).unwrap();
    let c = bodies::check_polygon(&p).unwrap();
    assert!(c[0].abs() < 1e-12 && c[1].abs() < 1e-12, "{c:?}");
    let e = bodies::regular_polygon(bodies::MAX_POLYGON_VERTICES + 1, 1.0).unwrap_err();
    assert!(e.to_string().contains("at most 10000"), "{e}");
    // Scaled per axis: 1e-300 × 1 and 1e100 × 1e-300 rectangles are simple; coordinates
    // beyond the bodies' size limit of 1e100 are refused.
    for (a, b) in [(1e-300, 1.0), (1e100, 1e-300)] {
        let r = [[a, b], [-a, b], [-a, -b], [a, -b]];
        assert_eq!(bodies::check_polygon(&r).unwrap(), [0.0, 0.0]);
    }
    let r = [[1e300, 1.0], [-1e300, 1.0], [-1e300, -1.0], [1e300, -1.0]];
    let e = bodies::check_polygon(&r).unwrap_err();
    assert!(e.to_string().contains("1e100"), "{e}");
    // A polygon winding twice about its centroid is not simple.
    let twice: Vec<[f64; 2]> = (0..7)
        .map(|k| {
            let a = 2.0 * TAU * k as f64 / 7.0;
            [a.cos(), a.sin()]
        })
        .collect();
    let e = bodies::check_polygon(&twice).unwrap_err();
    assert!(e.to_string().contains("not simple"), "{e}");
}

/// Corner normals at a pole of many faces: one smooth sector (the old pairwise test was
/// quadratic in the faces around a vertex), sharp edges kept at the base.
#[test]
fn pyramid_over_a_many_gon() {
    let p = bodies::regular_polygon(2000, 1.0).unwrap();
    let m = tessellate_surface(
        &bodies::pyramid(&p, 1.0).unwrap(),
        &SurfaceOptions::uniform(3, 3),
    )
    .unwrap();
    assert!(m.is_watertight());
    // The base is flat: one normal, straight down.
    assert!(m.normals().contains(&[0.0, 0.0, -1.0]));
}
