//! `geomkit render` and `geomkit mesh` on every model type: PNG size and content, SVG layers,
//! mesh counts per format, errors without half-written files.

mod common;

use common::{fails, geomkit, ok_stderr};

const SURFACE: &str = r#"{"type":"bezier_surface","net":[
 [[0,0,0],[0,1,0.5],[0,2,0]],[[1,0,0.5],[1,1,2],[1,2,0.5]],[[2,0,0],[2,1,0.5],[2,2,0]]]}"#;
const CURVE: &str =
    r#"{"type":"bezier_curve","points":[[10,0],[22,6],[19,12],[11,15],[8,12],[20,0]]}"#;
const RATIONAL: &str =
    r#"{"type":"bezier_curve","points":[[1,0],[1,1],[0,1]],"weights":[1,0.7071067811865476,1]}"#;
const SCENE: &str = r#"{"type":"composite_surface","u_knots":[0,1,2],"v_knots":[0,1],"patches":[
 [{"bezier":[[[0,0,0],[0,1,0]],[[1,0,1],[1,1,1]]]}],
 [{"bezier":[[[1,0,1],[1,1,1]],[[2,0,0],[2,1,0]]]}]]}"#;
const MODEL2: &str = r#"{"type":"pointcalc-model","factors":[
 {"name":"a","nodes":[0,0.5,1]},{"name":"b","nodes":[0,0.5,1]}],"response":["y"],
 "values":[0,1,0,1,3,1,0,1,0]}"#;

fn setup() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [
        ("s.json", SURFACE),
        ("c.json", CURVE),
        ("r.json", RATIONAL),
        ("scene.json", SCENE),
        ("pc.json", MODEL2),
    ] {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn png_pictures_of_every_model_type() {
    let dir = setup();
    let d = dir.path();
    for model in ["s.json", "c.json", "r.json", "scene.json", "pc.json"] {
        ok_stderr(d, &["render", model, "-o", "out.png", "--size", "400x300"]);
        let png = std::fs::read(d.join("out.png")).unwrap();
        assert_eq!(png_size(&png), (400, 300), "{model}");
        // A drawn picture compresses far worse than a blank one (~1 kB).
        assert!(png.len() > 8_000, "{model}: {} bytes", png.len());
    }
    // Without --size: twice the SVG's size.
    ok_stderr(d, &["render", "s.json", "-o", "big.png"]);
    assert_eq!(
        png_size(&std::fs::read(d.join("big.png")).unwrap()),
        (1440, 1080)
    );
}

#[test]
fn svg_surface_has_shaded_faces_net_and_view() {
    let dir = setup();
    let d = dir.path();
    ok_stderr(d, &["render", "s.json", "-o", "a.svg", "--view", "-60,40"]);
    let a = std::fs::read_to_string(d.join("a.svg")).unwrap();
    assert!(a.starts_with("<svg"));
    // 60×60 grid: 2·59² shaded triangles.
    assert_eq!(a.matches("<path ").count(), 2 * 59 * 59);
    assert!(a.contains("control net, 3×3"));
    ok_stderr(d, &["render", "s.json", "-o", "b.svg", "--no-net"]);
    let b = std::fs::read_to_string(d.join("b.svg")).unwrap();
    assert!(!b.contains("control net"));
    assert_ne!(a.matches("<path ").collect::<String>(), "");
    // The same picture from another camera (only --view changes): the control net's 9 dots
    // are where the view formula puts them, not where the other camera does (to the 0.1 px
    // the SVG rounds to, plus what that rounding does to the fitted scale and shift).
    ok_stderr(d, &["render", "s.json", "-o", "c.svg", "--view", "35,25"]);
    let c = std::fs::read_to_string(d.join("c.svg")).unwrap();
    assert_eq!(c.matches("<path ").count(), 2 * 59 * 59);
    assert_ne!(a, c);
    let (dots_a, dots_c) = (net_dots(&a), net_dots(&c));
    let net = net_points();
    assert!(camera_misfit(&net, (-60.0, 40.0), &dots_a) <= 0.15);
    assert!(camera_misfit(&net, (35.0, 25.0), &dots_c) <= 0.15);
    assert!(camera_misfit(&net, (35.0, 25.0), &dots_a) > 5.0);
    assert!(camera_misfit(&net, (-60.0, 40.0), &dots_c) > 5.0);
    // The point-calculus model shows its 9 experimental points.
    ok_stderr(d, &["render", "pc.json", "-o", "pc.svg"]);
    let pc = std::fs::read_to_string(d.join("pc.svg")).unwrap();
    assert!(pc.contains("9 points it passes through"));
    assert_eq!(pc.matches("<circle").count(), 9 + 1);
}

/// The control net of `SURFACE`, row by row.
fn net_points() -> Vec<[f64; 3]> {
    let model: serde_json::Value = serde_json::from_str(SURFACE).unwrap();
    let xyz = |p: &serde_json::Value| [0, 1, 2].map(|k| p[k].as_f64().unwrap());
    model["net"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|row| row.as_array().unwrap().iter().map(xyz))
        .collect()
}

/// Centres of the control net's dots (radius 2.8) in an SVG, in drawing order.
fn net_dots(svg: &str) -> Vec<[f64; 2]> {
    let attr = |line: &str, name: &str| -> f64 {
        let start = line.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        line[start..].split('"').next().unwrap().parse().unwrap()
    };
    svg.lines()
        .filter(|l| l.starts_with("<circle") && l.contains(r#"r="2.8""#))
        .map(|l| [attr(l, "cx"), attr(l, "cy")])
        .collect()
}

/// How far (px) `dots` are from the orthographic projection of `points` by a camera at
/// (azimuth, elevation) in degrees: page coordinates (p·right, p·up) with right = (-sin a,
/// cos a, 0) and up = (-sin e cos a, -sin e sin a, cos e), placed on the picture by the best
/// scale and shift (y down); the largest residual.
fn camera_misfit(points: &[[f64; 3]], (azimuth, elevation): (f64, f64), dots: &[[f64; 2]]) -> f64 {
    assert_eq!(points.len(), dots.len());
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    let page: Vec<[f64; 2]> = points
        .iter()
        .map(|p| {
            [
                -a.sin() * p[0] + a.cos() * p[1],
                -e.sin() * a.cos() * p[0] - e.sin() * a.sin() * p[1] + e.cos() * p[2],
            ]
        })
        .collect();
    let mean = |v: &[[f64; 2]], k: usize| v.iter().map(|q| q[k]).sum::<f64>() / v.len() as f64;
    let (q0, q1, x0, y0) = (mean(&page, 0), mean(&page, 1), mean(dots, 0), mean(dots, 1));
    // Least squares for x = s·q0 + tx, y = -s·q1 + ty.
    let (mut num, mut den) = (0.0, 0.0);
    for (q, p) in page.iter().zip(dots) {
        num += (q[0] - q0) * (p[0] - x0) - (q[1] - q1) * (p[1] - y0);
        den += (q[0] - q0).powi(2) + (q[1] - q1).powi(2);
    }
    let scale = num / den;
    assert!(scale > 0.0);
    page.iter()
        .zip(dots)
        .map(|(q, p)| {
            let x = x0 + scale * (q[0] - q0);
            let y = y0 - scale * (q[1] - q1);
            (x - p[0]).abs().max((y - p[1]).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn curve_svg_labels_the_control_polygon() {
    let dir = setup();
    let d = dir.path();
    ok_stderr(d, &["render", "c.json", "-o", "c.svg"]);
    let s = std::fs::read_to_string(d.join("c.svg")).unwrap();
    assert!(s.contains("control polygon, 6 points"));
    for k in 0..6 {
        assert!(s.contains(&format!(">{k}</tspan>")), "label p{k}");
    }
}

#[test]
fn meshes_in_every_format() {
    let dir = setup();
    let d = dir.path();
    let err = ok_stderr(d, &["mesh", "s.json", "-o", "s.obj", "--samples", "5x4"]);
    assert!(err.contains("20 vertices, 24 triangles"), "{err}");
    let obj = std::fs::read_to_string(d.join("s.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 20);
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 24);
    assert!(obj.lines().any(|l| l.starts_with("vn ")));

    ok_stderr(d, &["mesh", "s.json", "-o", "s.stl", "--samples", "5x4"]);
    assert_eq!(std::fs::read(d.join("s.stl")).unwrap().len(), 84 + 50 * 24);
    ok_stderr(
        d,
        &[
            "mesh",
            "s.json",
            "-o",
            "a.stl",
            "--samples",
            "5x4",
            "--ascii",
        ],
    );
    let a = std::fs::read_to_string(d.join("a.stl")).unwrap();
    assert_eq!(a.matches("facet normal").count(), 24);

    ok_stderr(d, &["mesh", "s.json", "-o", "s.ply", "--samples", "5x4"]);
    let ply = std::fs::read(d.join("s.ply")).unwrap();
    let head = String::from_utf8_lossy(&ply[..300]);
    // One normal per vertex: vertices on creases sharper than 40° are split.
    assert!(head.contains("element face 24"), "{head}");
    let nv: usize = head
        .split("element vertex ")
        .nth(1)
        .unwrap()
        .split('\n')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(nv >= 20, "{head}");

    ok_stderr(d, &["mesh", "scene.json", "-o", "scene.glb"]);
    let glb = std::fs::read(d.join("scene.glb")).unwrap();
    assert_eq!(&glb[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
        glb.len()
    );

    // Adaptive: a finer tolerance gives more triangles.
    let coarse = ok_stderr(d, &["mesh", "s.json", "-o", "c.obj", "--tolerance", "0.01"]);
    let fine = ok_stderr(
        d,
        &["mesh", "s.json", "-o", "f.obj", "--tolerance", "0.0001"],
    );
    let tris = |s: &str| -> usize {
        s.split(" vertices, ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!(tris(&fine) > 4 * tris(&coarse), "{coarse} / {fine}");

    // Curves are polylines.
    let err = ok_stderr(d, &["mesh", "r.json", "-o", "r.obj", "--samples", "9"]);
    assert!(err.contains("polyline of 9 points"), "{err}");
    ok_stderr(d, &["mesh", "r.json", "-o", "r.ply"]);
    ok_stderr(d, &["mesh", "r.json", "-o", "r.glb"]);
}

#[test]
fn sampled_point_calculus_outputs_mesh_through_their_samples() {
    let dir = setup();
    let d = dir.path();
    std::fs::write(
        d.join("pcc.json"),
        r#"{"type":"pointcalc-curve","nodes":[0,0.5,1],"lebesgue":1.25,"samples":[
 [0,0,0],[0.25,0.5,0.75],[0.5,1,1],[0.75,1.5,0.75],[1,2,0]]}"#,
    )
    .unwrap();
    std::fs::write(
        d.join("pcs.json"),
        r#"{"type":"pointcalc-surface-samples","u":[0,0.5,1],"v":[0,1],"points":[
 [0,0,0],[0,1,0],[1,0,1],[1,1,1],[2,0,0],[2,1,0]]}"#,
    )
    .unwrap();
    let err = ok_stderr(d, &["mesh", "pcc.json", "-o", "pcc.obj", "--samples", "5"]);
    assert!(err.contains("polyline of 5 points"), "{err}");
    let obj = std::fs::read_to_string(d.join("pcc.obj")).unwrap();
    assert!(obj.contains("v 1.5 0.75 0\n"), "{obj}");
    let err = ok_stderr(
        d,
        &["mesh", "pcs.json", "-o", "pcs.obj", "--samples", "2x2"],
    );
    // A 2×2 grid plus the sample lines (break lines): the 3×2 grid, 6 vertices, 4 triangles.
    assert!(err.contains("6 vertices, 4 triangles"), "{err}");
    ok_stderr(
        d,
        &["render", "pcs.json", "-o", "pcs.png", "--size", "200x200"],
    );
    std::fs::write(
        d.join("bad.json"),
        r#"{"type":"pointcalc-surface-samples","u":[0,1],"v":[0,1],"points":[[0,0,0]]}"#,
    )
    .unwrap();
    let e = fails(d, &["mesh", "bad.json", "-o", "bad.obj"], Some("bad.obj"));
    assert!(e.contains("1 points"), "{e}");
}

#[test]
fn bad_requests_fail_cleanly() {
    let dir = setup();
    let d = dir.path();
    let e = fails(d, &["mesh", "c.json", "-o", "c.stl"], Some("c.stl"));
    assert!(e.contains("STL holds triangles only"), "{e}");
    assert!(!d.join("c.stl").exists());
    let e = fails(d, &["mesh", "s.json", "-o", "s.xyz"], Some("s.xyz"));
    assert!(e.contains(".obj, .stl, .ply or .glb"), "{e}");
    let e = fails(
        d,
        &["mesh", "s.json", "-o", "s.obj", "--tolerance", "-1"],
        Some("s.obj"),
    );
    assert!(e.contains("--tolerance"), "{e}");
    let e = fails(d, &["render", "s.json", "-o", "s.jpg"], Some("s.jpg"));
    assert!(e.contains(".png or .svg"), "{e}");
    let e = fails(d, &["render", "missing.json", "-o", "m.png"], Some("m.png"));
    assert!(e.contains("cannot read missing.json"), "{e}");
    std::fs::write(
        d.join("bad.json"),
        r#"{"type":"bezier_surface","net":[[[0,0,"x"]]]}"#,
    )
    .unwrap();
    let e = fails(d, &["render", "bad.json", "-o", "bad.png"], Some("bad.png"));
    assert!(e.contains("bad.json"), "{e}");
    assert!(!d.join("bad.png").exists());
    // Usage errors of clap (exit code 2).
    let out = geomkit(d, &["render", "s.json", "-o", "s.png", "--view", "10,95"]);
    assert_eq!(out.status.code(), Some(2));
    let out = geomkit(d, &["render", "s.json", "-o", "s.png", "--size", "10x10"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn obj_normal_layouts() {
    let dir = setup();
    let d = dir.path();
    let count = |file: &str, prefix: &str| {
        std::fs::read_to_string(d.join(file))
            .unwrap()
            .lines()
            .filter(|l| l.starts_with(prefix))
            .count()
    };
    // A body with sharp edges: no normals by default (meshio reads it, positions shared),
    // six face normals when indexed, one per (split) vertex when per-vertex.
    ok_stderr(d, &["compose", "body", "cube", "-o", "cube.obj"]);
    assert_eq!(count("cube.obj", "vn "), 0);
    let shared = count("cube.obj", "v ");
    let err = ok_stderr(
        d,
        &[
            "compose",
            "body",
            "cube",
            "-o",
            "i.obj",
            "--obj-normals",
            "indexed",
        ],
    );
    assert!(err.contains("closed, volume 8"), "{err}");
    assert_eq!((count("i.obj", "v "), count("i.obj", "vn ")), (shared, 6));
    ok_stderr(
        d,
        &[
            "compose",
            "body",
            "cube",
            "-o",
            "p.obj",
            "--obj-normals",
            "per-vertex",
        ],
    );
    assert!(count("p.obj", "v ") > shared);
    assert_eq!(count("p.obj", "v "), count("p.obj", "vn "));
    // A smooth surface: one normal per vertex by default.
    ok_stderr(d, &["mesh", "s.json", "-o", "s.obj", "--samples", "5x4"]);
    assert_eq!((count("s.obj", "v "), count("s.obj", "vn ")), (20, 20));
}

/// Pictures of models whose coordinates reach f64::MAX: drawn scaled (tick labels with the
/// exponent), never a NaN or inf coordinate in the SVG; an approximate reduction whose
/// error overflows is refused, the picture not written.
#[test]
fn pictures_of_coordinates_near_f64_max_hold_finite_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    common::write(
        d,
        "c.json",
        r#"{"type":"bezier_curve","points":[[0,0],[1.7e308,1.7e308],[-1.7e308,-1.7e308]]}"#,
    );
    common::write(
        d,
        "s.json",
        r#"{"type":"bezier_surface","net":[[[0,0,0],[1.7e308,1,0]],[[0,1,-1.7e308],[1,1,1]]]}"#,
    );
    for args in [
        &["render", "c.json", "-o", "c.svg"][..],
        &["bezier", "elevate", "--to", "4", "c.json", "-o", "c4.svg"],
        &["render", "s.json", "-o", "s.svg"],
        &["bezier", "elevate", "--to", "3,3", "s.json", "-o", "s3.svg"],
    ] {
        ok_stderr(d, args);
        let svg = std::fs::read_to_string(d.join(args[args.len() - 1])).unwrap();
        let lower = svg.to_lowercase();
        assert!(!lower.contains("nan") && !lower.contains("inf"), "{args:?}");
    }
    let svg = std::fs::read_to_string(d.join("c.svg")).unwrap();
    assert!(
        svg.contains(">1.0e308<") || svg.contains(">1e308<"),
        "{svg}"
    );
    let e = fails(
        d,
        &[
            "bezier", "reduce", "--to", "1", "--approx", "c.json", "-o", "r.svg",
        ],
        Some("r.svg"),
    );
    assert!(e.contains("c.json") && e.contains("overflows f64"), "{e}");
}
