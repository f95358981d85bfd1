//! `geomkit mesh` and the mesh outputs of `geomkit compose body`: tolerances and sample
//! counts out of range or beyond the work caps, models whose mesh is empty or leaks, body
//! options beyond what f64 resolves, formats that cannot hold the mesh.

use crate::{case, Case};

/// A saddle-shaped Bézier surface of size 2.
const SURFACE: (&str, &str) = (
    "s.json",
    r#"{"type":"bezier_surface","net":[[[0,0,0],[0,1,0.5],[0,2,0]],
 [[1,0,0.5],[1,1,2],[1,2,0.5]],[[2,0,0],[2,1,0.5],[2,2,0]]]}"#,
);
/// A surface all of whose points coincide.
const POINT: (&str, &str) = (
    "pt.json",
    r#"{"type":"bezier_surface","net":[[[1,2,3],[1,2,3]],[[1,2,3],[1,2,3]]]}"#,
);
const CURVE: (&str, &str) = (
    "c.json",
    r#"{"type":"bezier_curve","points":[[0,0],[1,2],[2,0]]}"#,
);

#[rustfmt::skip]
pub const CASES: &[Case] = &[
    // --tolerance: not a positive finite number, below f64's resolution, beyond the cap.
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "0"], &["--tolerance", "0", "> 0"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "-1"], &["--tolerance", "-1"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "nan"], &["--tolerance", "nan"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "inf"], &["--tolerance", "inf"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "1e-300"], &["s.json", "--tolerance 1e-300", "resolve"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.glb", "--tolerance", "1e-13"], &["--tolerance 1e-13", "out of reach", "2000000 triangles", "at least"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--tolerance", "1", "--samples", "4"], &["--tolerance", "--samples"]),
    // --samples: below 2, above 32768 per direction, above the triangle or point cap.
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--samples", "0"], &["--samples 0", "2 to 32768"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--samples", "100000x100000"], &["--samples 100000x100000", "32768"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.stl", "--samples", "2000"], &["--samples 2000", "7992002 triangles", "cap of 2000000"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--samples", "abc"], &["--samples", "abc"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "o.obj", "--samples", "99999999999999999999999"], &["--samples", "99999999999999999999999"]),
    case(&[CURVE], &["mesh", "c.json", "-o", "c.obj", "--samples", "100000000000"], &["c.json", "--samples 100000000000", "cap of 1000000"]),
    case(&[CURVE], &["mesh", "c.json", "-o", "c.obj", "--samples", "1"], &["c.json", "--samples 1", "at least 2"]),
    // Models and formats that cannot give the mesh.
    case(&[CURVE], &["mesh", "c.json", "-o", "c.stl"], &["STL", "triangles only"]),
    case(&[POINT], &["mesh", "pt.json", "-o", "pt.obj"], &["pt.json", "empty", "(1, 2, 3)"]),
    case(&[POINT], &["mesh", "pt.json", "-o", "pt.ply", "--samples", "5x5"], &["pt.json", "empty", "collapsed"]),
    case(&[("notes.txt", "hello\n")], &["mesh", "notes.txt", "-o", "n.obj"], &["notes.txt", "json"]),
    case(&[("e.json", "")], &["mesh", "e.json", "-o", "e.obj"], &["e.json"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "s.xyz"], &["s.xyz", ".obj, .stl, .ply or .glb"]),
    case(&[SURFACE], &["mesh", "s.json", "-o", "s.obj", "--obj-normals", "weird"], &["--obj-normals", "weird", "per-vertex"]),
    // compose body: sizes whose mesh f64 cannot hold, counts beyond the limits.
    case(&[], &["compose", "body", "cylinder", "--radius", "1e-308", "-o", "b.obj"], &["radius", "1e-308", "underflows"]),
    case(&[], &["compose", "body", "cylinder", "--radius", "1e308", "-o", "b.stl"], &["radius", "1e308"]),
    case(&[], &["compose", "body", "cylinder", "--height", "1e-300", "-o", "b.glb"], &["height", "1e-300", "not watertight"]),
    case(&[], &["compose", "body", "box", "--size", "1e-300,1,1", "-o", "b.ply"], &["box", "1e-300", "too thin or too small"]),
    case(&[], &["compose", "body", "pyramid", "--side", "1e-320", "-o", "b.stl"], &["side", "1e-320", "underflows"]),
    case(&[], &["compose", "body", "prism", "--ngon", "100000000", "-o", "b.obj"], &["--ngon", "100000000", "10000"]),
    case(&[], &["compose", "body", "prism", "--ngon", "2"], &["--ngon", "2", "3..=10000"]),
    case(&[], &["compose", "body", "pyramid", "--ngon", "-5", "-o", "b.obj"], &["--ngon", "-5"]),
    case(&[], &["compose", "body", "cube", "--samples", "4000x4000", "-o", "b.obj"], &["--samples 4000x4000", "cap of 2000000"]),
    case(&[], &["compose", "body", "cube", "--samples", "1", "-o", "b.obj"], &["--samples", "1"]),
    case(&[], &["compose", "body", "box", "--size", "1,1", "-o", "b.obj"], &["--size", "three sizes"]),
    case(&[], &["compose", "body", "box", "--size", "0,1,1", "-o", "b.obj"], &["size", "0"]),
    case(&[], &["compose", "body", "cone", "--height", "nan", "-o", "b.obj"], &["height", "nan"]),
    case(&[], &["compose", "body", "frustum", "--top-radius", "-1", "-o", "b.obj"], &["top radius", "-1"]),
    case(&[], &["compose", "body", "prism", "--polygon", "0,0;1,1;1,0;0,1", "-o", "b.obj"], &["polygon", "not simple"]),
    case(&[], &["compose", "body", "cube", "-o", "b.obj", "--obj-normals", "bogus"], &["--obj-normals", "bogus"]),
];

#[test]
fn mesh() {
    crate::check_all(CASES);
}
