//! Fuzzing the mesher (issue 21): random bodies and surfaces of tiny, huge and anisotropic
//! sizes, coincident points and random tolerances. Property: an error, or a mesh with finite
//! vertices, no triangle repeating a vertex or pointing past the vertices, within the
//! triangle cap, watertight and of positive volume for the closed bodies; the writers then
//! either refuse it or write it.

#[path = "common/fuzz.rs"]
mod fuzz;

use geomkit::bezier::BezierSurface;
use geomkit::compose::bodies;
use geomkit::compose::RuledSurface;
use geomkit::mesh::{
    tessellate_curve, tessellate_surface_report, write_glb, write_obj_with, write_ply,
    write_stl_binary, CurveOptions, ObjNormals, SurfaceOptions, TriMesh,
};
use proptest::prelude::*;

/// The cap used here (the default is 2 000 000): small enough for thousands of cases.
const CAP: usize = 4000;

/// Sizes from 1e-310 to 1e308, and the usual ones, with any sign.
fn size() -> impl Strategy<Value = f64> {
    prop_oneof![
        (0.1f64..10.0),
        (-310i32..=308, 1.0f64..10.0).prop_map(|(e, m)| m * 10f64.powi(e)),
        Just(f64::MAX),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(0.0),
        Just(-1.0),
    ]
}

/// Coordinates: mostly ordinary, sometimes huge, tiny or repeated.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -3.0f64..3.0,
        1 => (-310i32..=308, -9.0f64..9.0).prop_map(|(e, m)| m * 10f64.powi(e)),
        1 => Just(0.0),
        1 => Just(1e308),
    ]
}

fn sampling() -> impl Strategy<Value = SurfaceOptions> {
    prop_oneof![
        Just(SurfaceOptions::default()),
        (2usize..40, 2usize..40).prop_map(|(k, l)| SurfaceOptions::uniform(k, l)),
        (-320i32..=10, 1.0f64..10.0).prop_map(|(e, m)| SurfaceOptions::adaptive(m * 10f64.powi(e))),
    ]
    .prop_map(|o| o.with_max_triangles(CAP))
}

/// A body by kind (0..6) with sizes, or the error of its constructor.
fn body(kind: u8, a: f64, b: f64, c: f64, n: usize) -> geomkit::Result<RuledSurface> {
    match kind {
        0 => bodies::rectangular_box(a, b, c),
        1 => bodies::cylinder(a, b),
        2 => bodies::cone(a, b),
        3 => bodies::frustum(a, b, c),
        4 => bodies::square_pyramid(a, b),
        _ => bodies::prism(&bodies::regular_polygon(n, a)?, b),
    }
}

/// The property of every mesh; `closed`: it must be watertight with positive volume.
fn check(m: &TriMesh, closed: bool) {
    let nv = m.positions().len();
    assert!(m.positions().iter().flatten().all(|x| x.is_finite()));
    assert!(!m.triangles().is_empty());
    assert!(
        m.triangles().len() <= CAP,
        "{} triangles",
        m.triangles().len()
    );
    for t in m.triangles() {
        assert!(t.iter().all(|&i| (i as usize) < nv), "{t:?} of {nv}");
        assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "{t:?}");
    }
    assert!(m.normals().iter().flatten().all(|x| x.is_finite()));
    if closed {
        assert!(m.is_watertight());
        assert!(m.volume() > 0.0, "volume {}", m.volume());
    }
    // The writers write it or refuse it (f32 formats), never panic.
    for layout in [ObjNormals::Auto, ObjNormals::Indexed, ObjNormals::Vertex] {
        write_obj_with(m, layout, std::io::sink()).unwrap();
    }
    write_ply(m, std::io::sink()).unwrap();
    let _ = write_stl_binary(m, std::io::sink());
    let _ = write_glb(m, std::io::sink());
}

proptest! {
    #![proptest_config(fuzz::config(24))]

    #[test]
    fn fuzz_bodies(
        kind in 0u8..6,
        a in size(),
        b in size(),
        c in size(),
        n in 3usize..40,
        opts in sampling(),
    ) {
        if let Ok(s) = body(kind, a, b, c, n) {
            if let Ok((m, report)) = tessellate_surface_report(&s, &opts) {
                prop_assert!(report.closed, "a body closes");
                check(&m, true);
            }
        }
    }

    #[test]
    fn fuzz_surfaces(
        net in prop::collection::vec(prop::array::uniform3(coordinate()), 4..=9),
        coincide in prop::bool::ANY,
        opts in sampling(),
    ) {
        // A 2 × k net (k = len / 2), or every point the first one.
        let k = net.len() / 2;
        let pts: Vec<Vec<f64>> = net
            .iter()
            .map(|p| if coincide { net[0].to_vec() } else { p.to_vec() })
            .collect();
        let rows = vec![pts[..k].to_vec(), pts[k..2 * k].to_vec()];
        if let Ok(s) = BezierSurface::new(rows) {
            if let Ok((m, report)) = tessellate_surface_report(&s, &opts) {
                prop_assert!(!coincide);
                check(&m, report.closed);
            }
        }
    }

    #[test]
    fn fuzz_polylines(
        pts in prop::collection::vec(prop::array::uniform2(coordinate()), 2..6),
        tolerance in prop::option::of((-320i32..=10, 1.0f64..10.0)
            .prop_map(|(e, m)| m * 10f64.powi(e))),
        segments in prop_oneof![1usize..50, Just(usize::MAX - 1)],
    ) {
        let c = geomkit::bezier::BezierCurve::new(pts.iter().map(|p| p.to_vec()).collect());
        if let Ok(c) = c {
            let mut opts = CurveOptions::default();
            opts.tolerance = tolerance;
            opts.min_segments = segments;
            opts.max_points = 2000;
            if let Ok(p) = tessellate_curve(&c, &opts) {
                prop_assert!(p.len() >= 2 && p.len() <= 2000);
                prop_assert!(p.points().iter().all(|x| x.is_finite()));
            }
        }
    }
}
