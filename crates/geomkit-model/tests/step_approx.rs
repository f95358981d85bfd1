//! STEP export of formulas without an exact B-spline form: each piece is written as the
//! interpolating B-spline of its samples, and the reported deviation is checked here against
//! the formula evaluated independently (Rust's f64 `sin`, `exp`, `sqrt`, not geomkit's
//! expression engine) at the B-spline read back from the file (geomkit's reader), on grids
//! much denser than the writer's check grid. Polynomial and rational inputs stay exact.

use geomkit_model::step::{self, WriteOptions};
use geomkit_model::{parse, AnyModel};

/// The B-spline surfaces of a STEP text, read back.
fn surfaces(text: &str) -> Vec<geomkit::bspline::BsplineSurface> {
    step::read(text)
        .unwrap()
        .models
        .into_iter()
        .map(|m| match AnyModel::from_file(m.file).unwrap() {
            AnyModel::BsplineSurface(s) => s.surface,
            other => panic!("not a B-spline surface: {}", other.describe()),
        })
        .collect()
}

/// The largest distance between `surface` and `formula` on an n × n grid of its domain.
fn max_distance(
    surface: &geomkit::bspline::BsplineSurface,
    formula: impl Fn(f64, f64) -> [f64; 3],
    n: usize,
) -> f64 {
    let ((u0, u1), (v0, v1)) = surface.domain();
    let mut worst = 0.0f64;
    for a in 0..n {
        for b in 0..n {
            let u = u0 + (u1 - u0) * a as f64 / (n - 1) as f64;
            let v = v0 + (v1 - v0) * b as f64 / (n - 1) as f64;
            let p = surface.eval(u, v);
            let q = formula(u, v);
            let d = (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>().sqrt();
            worst = worst.max(d);
        }
    }
    worst
}

const EXPLICIT: &str = r#"{"type": "composite_explicit", "x_knots": [0, 1, 2], "y_knots": [0, 1],
    "patches": [["sin(x) * exp(y)"], ["sqrt(1 + x^2 + y^2)"]]}"#;

#[test]
fn the_reported_deviation_bounds_the_distance_on_a_much_denser_grid() {
    let model = parse(EXPLICIT).unwrap();
    let out = step::export(&model, &WriteOptions::default()).unwrap();
    assert_eq!(out.approximations.len(), 2);
    let read = surfaces(&out.text);
    assert_eq!(read.len(), 2);
    let formulas: [&dyn Fn(f64, f64) -> [f64; 3]; 2] = [
        &|x: f64, y: f64| [x, y, x.sin() * y.exp()],
        &|x: f64, y: f64| [x, y, (1.0 + x * x + y * y).sqrt()],
    ];
    // The model's bounding box: x in [0, 2], y in [0, 1], z from 0 to sqrt(6).
    let diagonal = (4.0f64 + 1.0 + 6.0).sqrt();
    for ((a, s), f) in out.approximations.iter().zip(&read).zip(formulas) {
        assert!(a.deviation <= a.tolerance, "{a:?}");
        assert!(
            (a.tolerance - 1e-6 * diagonal).abs() < 1e-3 * a.tolerance,
            "tolerance {} for a diagonal {diagonal}",
            a.tolerance
        );
        // 601 × 601 points: ~37 per sample interval of a 17-sample grid (the writer checks 8).
        let dense = max_distance(s, f, 601);
        assert!(
            dense <= a.deviation * 1.02,
            "{}: {dense:e} on the dense grid, {:e} reported",
            a.piece,
            a.deviation
        );
        // And the deviation is a real measurement, not a loose bound.
        assert!(
            dense >= a.deviation * 0.9,
            "{}: {dense:e} vs {:e}",
            a.piece,
            a.deviation
        );
        // The B-spline passes through the samples: exact at the cell's corners.
        let ((u0, _), (v0, _)) = s.domain();
        let p = s.eval(u0, v0);
        let q = f(u0, v0);
        assert!((0..3).all(|c| (p[c] - q[c]).abs() < 1e-14), "{p:?} {q:?}");
    }
    // The header names each approximated piece and its deviation.
    let header = out.text.lines().nth(2).unwrap();
    assert!(header.contains("approximated patch (0, 0)"), "{header}");
    assert!(header.contains("approximated patch (1, 0)"), "{header}");
    assert!(!header.contains("'exact geometry"), "{header}");
}

#[test]
fn a_smaller_tolerance_takes_more_samples_and_keeps_its_bound() {
    let model = parse(EXPLICIT).unwrap();
    let coarse = step::export(&model, &WriteOptions::default().with_tolerance(1e-3)).unwrap();
    let fine = step::export(&model, &WriteOptions::default().with_tolerance(1e-9)).unwrap();
    for (c, f) in coarse.approximations.iter().zip(&fine.approximations) {
        assert!(c.samples[0] < f.samples[0], "{c:?} {f:?}");
        assert!(c.deviation <= c.tolerance && f.deviation <= f.tolerance);
        assert!(f.deviation < c.deviation);
    }
    let s = &surfaces(&fine.text)[0];
    let dense = max_distance(s, |x, y| [x, y, x.sin() * y.exp()], 301);
    assert!(dense <= fine.approximations[0].deviation * 1.02);
}

#[test]
fn neighbouring_formula_patches_are_sewn_along_their_shared_edge() {
    // A torus in two halves: the halves share two edges (u = 1 and the seam u = 0 = 2 is
    // not shared, the patches' own ends); the v direction closes each patch.
    let torus = r#"{"type": "composite_surface", "u_knots": [0, 3.141592653589793, 6.283185307179586], "v_knots": [0, 6.283185307179586],
        "patches": [[{"x": "cos(u)*(2+cos(v))", "y": "sin(u)*(2+cos(v))", "z": "sin(v)"}],
                    [{"x": "cos(u)*(2+cos(v))", "y": "sin(u)*(2+cos(v))", "z": "sin(v)"}]]}"#;
    let out = step::export(&parse(torus).unwrap(), &WriteOptions::default()).unwrap();
    assert_eq!(out.approximations.len(), 2);
    // Two faces with v closed (one seam each) and two edges u = π, u = 0 shared by both.
    assert_eq!(out.text.matches("ADVANCED_FACE(").count(), 2);
    assert_eq!(
        out.text.matches("EDGE_CURVE(").count(),
        4,
        "2 seams + 2 shared"
    );
    let f = |u: f64, v: f64| {
        [
            u.cos() * (2.0 + v.cos()),
            u.sin() * (2.0 + v.cos()),
            v.sin(),
        ]
    };
    for (a, s) in out.approximations.iter().zip(surfaces(&out.text)) {
        assert!(max_distance(&s, f, 301) <= a.deviation * 1.02);
    }
}

#[test]
fn ruled_bodies_over_formula_curves_are_closed_solids_within_the_tolerance() {
    let body = r#"{"type": "ruled", "u": [0, 1], "v": [0, 1, 2, 3], "curves": [
        {"point": [0, 0, 0]},
        {"x": "cos(t)", "y": "sin(t)", "z": "0.2*sin(3*t)", "t": [0, 6.283185307179586]},
        {"x": "0.5*cos(t)", "y": "0.5*sin(t)", "z": "1", "t": [0, 6.283185307179586]},
        {"point": [0, 0, 1]}]}"#;
    let out = step::export(&parse(body).unwrap(), &WriteOptions::default()).unwrap();
    assert!(out.text.contains("MANIFOLD_SOLID_BREP("));
    assert!(out.text.contains("CLOSED_SHELL("));
    assert_eq!(out.approximations.len(), 3);
    // Strip 2 lies between the two formula curves, linear in v.
    let tau = std::f64::consts::TAU;
    let strip2 = |u: f64, v: f64| {
        let t = u * tau;
        let a = [t.cos(), t.sin(), 0.2 * (3.0 * t).sin()];
        let b = [0.5 * t.cos(), 0.5 * t.sin(), 1.0];
        let l = v - 1.0;
        [
            a[0] + l * (b[0] - a[0]),
            a[1] + l * (b[1] - a[1]),
            a[2] + l * (b[2] - a[2]),
        ]
    };
    let s = &surfaces(&out.text)[1];
    assert_eq!(s.domain(), ((0.0, 1.0), (1.0, 2.0)));
    let a = &out.approximations[1];
    assert!(a.piece.starts_with("strip 2"), "{}", a.piece);
    assert!(max_distance(s, strip2, 1001) <= a.deviation * 1.02);
    // Faces share the curves between strips: 3 faces, the seam of each and the 2 rings.
    assert_eq!(out.text.matches("ADVANCED_FACE(").count(), 3);
    assert_eq!(out.text.matches("EDGE_CURVE(").count(), 5);
}

#[test]
fn composite_curves_of_formula_pieces_are_approximated_and_polylines_are_exact() {
    let curve = r#"{"type": "piecewise", "knots": [0, 1, 2],
        "pieces": [{"x": "t", "y": "sqrt(1 + t)", "z": "exp(t)"}, {"x": "t", "y": "sqrt(1 + t)", "z": "exp(t)"}]}"#;
    let out = step::export(&parse(curve).unwrap(), &WriteOptions::default()).unwrap();
    assert_eq!(out.approximations.len(), 2);
    let read = step::read(&out.text).unwrap();
    assert_eq!(read.models.len(), 2);
    for (m, a) in read.models.into_iter().zip(&out.approximations) {
        let AnyModel::BsplineCurve(c) = AnyModel::from_file(m.file).unwrap() else {
            panic!("a B-spline curve");
        };
        use geomkit::geom::Curve;
        let (t0, t1) = c.curve.domain();
        let mut worst = 0.0f64;
        for k in 0..=4000 {
            let t = t0 + (t1 - t0) * k as f64 / 4000.0;
            let p = c.curve.eval(t);
            let q = [t, (1.0 + t).sqrt(), t.exp()];
            worst = worst.max((0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt());
        }
        assert!(
            worst <= a.deviation * 1.02,
            "{worst:e} vs {:e}",
            a.deviation
        );
        assert!(a.deviation <= a.tolerance);
    }
    // A polyline: one exact degree-1 edge per segment, nothing approximated.
    let polyline = r#"{"type": "polyline", "points": [[0, 0], [0.1, 0.3], [1, 1]]}"#;
    let out = step::export(&parse(polyline).unwrap(), &WriteOptions::default()).unwrap();
    assert!(out.approximations.is_empty());
    let read = step::read(&out.text).unwrap();
    let pts: Vec<Vec<f64>> = read
        .models
        .iter()
        .flat_map(|m| match &m.file {
            geomkit_model::schema::ModelFile::BezierCurve(b) => b
                .points
                .flat
                .chunks(3)
                .map(<[f64]>::to_vec)
                .collect::<Vec<_>>(),
            geomkit_model::schema::ModelFile::BsplineCurve(b) => b
                .control_points
                .flat
                .chunks(3)
                .map(<[f64]>::to_vec)
                .collect(),
            _ => panic!("a curve"),
        })
        .collect();
    assert_eq!(
        pts,
        vec![
            vec![0.0, 0.0, 0.0],
            vec![0.1, 0.3, 0.0],
            vec![0.1, 0.3, 0.0],
            vec![1.0, 1.0, 0.0]
        ]
    );
}

#[test]
fn polynomial_inputs_stay_exact_and_bezier_nets_of_composites_round_trip_bit_for_bit() {
    // Numbers with no short binary form: the power basis would round them.
    let net = r#"{"bezier": [[[0.1, 0.2, 0.3], [0.1, 1.7, 0.35]], [[1.3, 0.1, 1.0e-3], [1.1, 1.9, 0.7]], [[2.3, 0.1, 0.3], [2.1, 1.1, 1.7]]]}"#;
    let scene = format!(
        r#"{{"type": "composite_surface", "u_knots": [0, 1], "v_knots": [0, 1], "patches": [[{net}]]}}"#
    );
    let out = step::export(&parse(&scene).unwrap(), &WriteOptions::default()).unwrap();
    assert!(out.approximations.is_empty());
    assert!(out.text.lines().nth(2).unwrap().contains("'exact geometry"));
    let read = step::read(&out.text).unwrap();
    let geomkit_model::schema::ModelFile::BezierSurface(b) = &read.models[0].file else {
        panic!("a Bézier surface");
    };
    assert_eq!(
        b.net.flat,
        vec![
            0.1, 0.2, 0.3, 0.1, 1.7, 0.35, 1.3, 0.1, 1.0e-3, 1.1, 1.9, 0.7, 2.3, 0.1, 0.3, 2.1,
            1.1, 1.7
        ]
    );
    // A B-spline surface and the formula file of it: exact, nothing approximated.
    let surface = r#"{"type": "bspline_surface", "degree": [1, 1], "knots_u": [0, 0, 1, 1],
        "knots_v": [0, 0, 1, 1], "net": [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]]}"#;
    let out = step::export(&parse(surface).unwrap(), &WriteOptions::default()).unwrap();
    assert!(out.approximations.is_empty());
}

#[test]
fn bad_tolerances_and_singular_formulas_are_errors_naming_the_piece() {
    let model = parse(EXPLICIT).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let err = step::export(&model, &WriteOptions::default().with_tolerance(bad)).unwrap_err();
        assert!(err.to_string().contains("tolerance"), "{err}");
    }
    // sqrt(x) has an infinite slope at 0: no cubic interpolant of 129 samples comes within
    // 1e-12 of it.
    let root = r#"{"type": "composite_explicit", "x_knots": [0, 1], "y_knots": [0, 1], "patches": [["sqrt(x)"]]}"#;
    let err = step::export(
        &parse(root).unwrap(),
        &WriteOptions::default().with_tolerance(1e-12),
    )
    .unwrap_err()
    .to_string();
    assert!(err.starts_with("patch (0, 0):"), "{err}");
    assert!(err.contains("above the tolerance"), "{err}");
    // With a tolerance it can reach, it is written (uniform samples converge like
    // sqrt(h) at the singularity: 1.6e-2 at 129 samples).
    let out = step::export(
        &parse(root).unwrap(),
        &WriteOptions::default().with_tolerance(2e-2),
    )
    .unwrap();
    assert!(out.approximations[0].deviation <= out.approximations[0].tolerance);
}

#[test]
fn bezier_patches_among_formula_patches_stay_exact() {
    let scene = r#"{"type": "composite_surface", "u_knots": [0, 1, 2], "v_knots": [0, 1],
        "patches": [[{"bezier": [[[0.1, 0, 0.3], [0.1, 1, 0.7]], [[1, 0.1, 0.2], [1, 1, 1.3]]]}],
                    [{"x": "1 + u", "y": "v", "z": "0.2 + sin(u) * v", "domain": [[0, 1], [0, 1]]}]]}"#;
    let out = step::export(&parse(scene).unwrap(), &WriteOptions::default()).unwrap();
    assert_eq!(out.approximations.len(), 1);
    assert_eq!(out.approximations[0].piece, "patch (1, 0)");
    let read = step::read(&out.text).unwrap();
    let geomkit_model::schema::ModelFile::BezierSurface(b) = &read.models[0].file else {
        panic!("the Bézier patch first");
    };
    assert_eq!(
        b.net.flat,
        vec![0.1, 0.0, 0.3, 0.1, 1.0, 0.7, 1.0, 0.1, 0.2, 1.0, 1.0, 1.3]
    );
}
