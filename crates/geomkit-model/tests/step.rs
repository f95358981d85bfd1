//! STEP export and import: write -> read gives the same control points, weights and knots
//! bit for bit; the writer's text passes a structural check of ISO 10303-21 independent of
//! the crate's reader; files written by OpenCASCADE 7.9 (tests/fixtures/step, made by
//! `bash bench/compat_step.sh --fixtures`) read to OCCT's own numbers; bad files give one
//! line naming the entity.

use geomkit_model::schema::ModelFile;
use geomkit_model::step::{self, Schema, WriteOptions};
use geomkit_model::{parse, to_json, AnyModel};
use proptest::prelude::*;
use std::collections::BTreeSet;

fn fixture(name: &str) -> String {
    let path = format!("{}/tests/fixtures/step/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).unwrap()
}

/// The models of `text` as JSON (the whole file, so every number is compared).
fn round_trip(model_json: &str) -> (String, String) {
    let model = parse(model_json).unwrap();
    let text = step::write(&model, &WriteOptions::default()).unwrap();
    check_part21(&text);
    let back = step::read(&text).unwrap();
    assert_eq!(back.models.len(), 1, "{:?}", back.skipped);
    let before = to_json(&file_of(&model)).unwrap();
    let after = to_json(&back.models[0].file).unwrap();
    (before, after)
}

fn file_of(model: &AnyModel) -> ModelFile {
    match model {
        AnyModel::Bezier(b) => b.to_file(None),
        AnyModel::BsplineCurve(m) => m.to_file(),
        AnyModel::BsplineSurface(m) => m.to_file(),
        _ => panic!("not a curve or surface"),
    }
}

/// A structural check of ISO 10303-21 that shares nothing with the crate's reader: the
/// header's three records, then one instance per line `#N=...;` numbered 1, 2, 3, ..., every
/// name upper case, parentheses balanced outside strings, every reals with a decimal point,
/// every reference defined, the trailer.
fn check_part21(text: &str) {
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "ISO-10303-21;");
    assert_eq!(lines[1], "HEADER;");
    assert!(lines[2].starts_with("FILE_DESCRIPTION(("));
    assert!(lines[3].starts_with("FILE_NAME("));
    assert!(lines[4].starts_with("FILE_SCHEMA(('"));
    assert_eq!(lines[5], "ENDSEC;");
    assert_eq!(lines[6], "DATA;");
    assert_eq!(lines[lines.len() - 2], "ENDSEC;");
    assert_eq!(lines[lines.len() - 1], "END-ISO-10303-21;");
    let mut defined = BTreeSet::new();
    let mut used = BTreeSet::new();
    for (k, line) in lines[7..lines.len() - 2].iter().enumerate() {
        let (head, body) = line.split_once('=').expect("#N=");
        assert_eq!(head, format!("#{}", k + 1), "numbering at {line}");
        defined.insert(k + 1);
        assert!(body.ends_with(");"), "{line}");
        let mut depth = 0i32;
        let mut in_string = false;
        let chars: Vec<char> = body.chars().collect();
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            if in_string {
                if c == '\'' {
                    in_string = false;
                }
                i += 1;
                continue;
            }
            match c {
                '\'' => in_string = true,
                '(' => depth += 1,
                ')' => depth -= 1,
                '#' => {
                    let digits: String = chars[i + 1..]
                        .iter()
                        .take_while(|c| c.is_ascii_digit())
                        .collect();
                    used.insert(digits.parse::<usize>().unwrap());
                }
                c if c.is_ascii_lowercase() => panic!("lower case outside a string: {line}"),
                _ => {}
            }
            assert!(depth >= 0, "{line}");
            i += 1;
        }
        assert_eq!(depth, 0, "unbalanced: {line}");
        // Numbers: a token starting with a digit or a sign is an integer or has a '.'.
        for token in body.split([',', '(', ')']) {
            let t = token.trim();
            if t.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
                assert!(
                    t.parse::<i64>().is_ok() || t.contains('.'),
                    "a real without '.': {t} in {line}"
                );
            }
        }
    }
    assert!(used.is_subset(&defined), "references to missing instances");
}

#[test]
fn curves_and_surfaces_round_trip_bit_for_bit() {
    let third = 1.0f64 / 3.0;
    let cases = [
        r#"{"type": "bezier_curve", "points": [[0, 0, 0], [0.1, 0.2, 0.30000000000000004], [3, 1e-300, -2.5e300], [4, 1, 2]]}"#.to_string(),
        r#"{"type": "bezier_curve", "points": [[1, 0, 0], [1, 1, 0], [0, 1, 0]], "weights": [1, 0.7071067811865476, 1]}"#.to_string(),
        r#"{"type": "bezier_surface", "net": [[[0, 0, 0], [1, 0, 1]], [[0, 1, 1], [1, 1, 0.1]], [[0, 2, 0], [1, 2, 3]]]}"#.to_string(),
        // A rational Bézier surface: a quarter cylinder (the rational complex entity).
        r#"{"type": "bezier_surface", "net": [[[1, 0, 0], [1, 0, 2]], [[1, 1, 0], [1, 1, 2]], [[0, 1, 0], [0, 1, 2]]], "weights": [[1, 1], [0.7071067811865476, 0.7071067811865476], [1, 1]]}"#.to_string(),
        // Clamped, and the paper's extended (unclamped) knots.
        format!(r#"{{"type": "bspline_curve", "degree": 2, "knots": [0, 0, 0, {third}, 1, 1, 1], "control_points": [[0, 0, 0], [1, 2, 0], [2, 0.1, 1], [3, 1, 0]]}}"#),
        r#"{"type": "bspline_curve", "degree": 3, "knots": [-3, -2, -1, 0, 1, 2, 3, 4, 5], "control_points": [[0, 0, 0], [1, 2, 0], [2, 0.1, 1], [3, 1, 0], [4, 4, 4]]}"#.to_string(),
        format!(r#"{{"type": "bspline_surface", "degree": [1, 2], "knots_u": [0, 0, {third}, 1, 1], "knots_v": [-1, -0.5, 0, 0.5, 1, 1.5], "net": [[[0,0,0],[0,1,0],[0,2,1]], [[1,0,0],[1,1,0.5],[1,2,1]], [[2,0,1],[2,1,2],[2,2,0.25]]]}}"#),
    ];
    for case in &cases {
        let (before, after) = round_trip(case);
        assert_eq!(before, after, "{case}");
    }
}

#[test]
fn plane_curves_are_written_at_z_0() {
    let model = parse(r#"{"type": "bezier_curve", "points": [[0, 0], [1, 2], [3, 1]]}"#).unwrap();
    let text = step::write(&model, &WriteOptions::default()).unwrap();
    assert!(text.contains("CARTESIAN_POINT('',(1.0,2.0,0.0))"));
    let back = step::read(&text).unwrap();
    let json = to_json(&back.models[0].file).unwrap();
    assert!(json.contains("[1.0, 2.0, 0.0]"), "{json}");
}

#[test]
fn the_same_model_gives_the_same_bytes_and_states_units() {
    let model =
        parse(r#"{"type": "bezier_surface", "net": [[[0,0,0],[1,0,1]],[[0,1,1],[1,1,0]]]}"#)
            .unwrap();
    let a = step::write(&model, &WriteOptions::default()).unwrap();
    let b = step::write(&model, &WriteOptions::default()).unwrap();
    assert_eq!(a, b);
    assert!(a.contains("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));"));
    assert!(a.contains("SI_UNIT(.MILLI.,.METRE.)"));
    assert!(a.contains("UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-7)"));
    assert!(a.contains("MANIFOLD_SURFACE_SHAPE_REPRESENTATION"));
    let c = step::write(
        &model,
        &WriteOptions::default()
            .with_schema(Schema::Ap242)
            .with_timestamp("2026-12-04T12:00:00"),
    )
    .unwrap();
    assert!(c.contains("AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF"));
    assert!(c.contains("'2026-12-04T12:00:00'"));
    check_part21(&c);
}

#[test]
fn closed_surfaces_share_one_seam_edge_and_collapsed_sides_have_none() {
    // A degree-1 "cylinder" around z: the first and last columns equal (closed in v), the
    // top row collapsed to one point (a cone's apex).
    let net = r#"{"type": "bezier_surface", "net": [
        [[1,0,0],[0,1,0],[-1,0,0],[0,-1,0],[1,0,0]],
        [[0,0,2],[0,0,2],[0,0,2],[0,0,2],[0,0,2]]]}"#;
    let model = parse(net).unwrap();
    let text = step::write(&model, &WriteOptions::default()).unwrap();
    // Two edges: the bottom (closed) curve and the seam, used twice.
    assert_eq!(text.matches("EDGE_CURVE(").count(), 2, "{text}");
    assert_eq!(text.matches("ORIENTED_EDGE(").count(), 3, "{text}");
    assert!(
        text.contains(",.F.,.T.,.F.,(2,2),(5,5)"),
        "v_closed set: {text}"
    );
}

#[test]
fn periodic_interpolated_curves_are_marked_closed() {
    let pts: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let t = k as f64 * std::f64::consts::TAU / 8.0;
            [t.cos(), t.sin(), 0.0]
        })
        .collect();
    let rows: Vec<Vec<f64>> = pts.iter().map(|p| p.to_vec()).collect();
    let c = geomkit::bspline::interpolate_curve(
        &rows,
        &geomkit::bspline::InterpolationOptions::default()
            .with_end(geomkit::bspline::EndCondition::Periodic),
    )
    .unwrap();
    let model = AnyModel::BsplineCurve(geomkit_model::BsplineCurveModel {
        curve: c.curve().clone(),
        parameters: None,
    });
    let text = step::write(&model, &WriteOptions::default()).unwrap();
    assert!(
        text.contains(".UNSPECIFIED.,.T.,.F."),
        "closed_curve: {text}"
    );
    // One vertex: the curve starts and ends there.
    assert_eq!(text.matches("VERTEX_POINT(").count(), 1);
}

#[test]
fn models_without_a_b_spline_form_are_refused() {
    let model = parse(r#"{"type": "bezier_curve", "points": [[0], [1]]}"#).unwrap();
    let err = step::write(&model, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("R^1"), "{err}");
}

#[test]
fn occt_bezier_curve_reads_to_its_poles() {
    let import = step::read(&fixture("occt_bezier_curve.step")).unwrap();
    assert_eq!(import.models.len(), 1);
    let m = &import.models[0];
    assert_eq!(m.id, 17);
    let ModelFile::BezierCurve(f) = &m.file else {
        panic!("{:?}", m.file)
    };
    // The poles OCCT was given (bench/compat_step.py).
    let want = [
        0.0, 0.0, 0.0, 1.0, 2.0, 0.5, 2.5, 2.0, -1.0, 4.0, 0.0, 0.0, 5.0, -1.0, 2.0, 6.0, 1.0, 1.0,
    ];
    assert_eq!(f.points.flat, want);
    assert!(f.weights.is_none());
    assert_eq!(import.length_unit.as_deref(), Some("MILLI METRE"));
    // The trimmed curve around it is counted, not imported twice.
    assert_eq!(import.skipped_summary(), "1 TRIMMED_CURVE (not imported)");
}

#[test]
fn occt_bspline_surface_reads_to_its_knots_and_poles() {
    let import = step::read(&fixture("occt_bspline_surface.step")).unwrap();
    assert_eq!(import.models.len(), 1, "{:?}", import.skipped);
    let ModelFile::BsplineSurface(f) = &import.models[0].file else {
        panic!()
    };
    assert_eq!(f.degree, [3, 3]);
    assert_eq!(
        f.knots_u,
        vec![0.0, 0.0, 0.0, 0.0, 0.4, 0.4, 1.0, 1.0, 1.0, 1.0]
    );
    assert_eq!(f.knots_v, vec![0.0, 0.0, 0.0, 0.0, 0.5, 2.0, 2.0, 2.0, 2.0]);
    assert_eq!((f.net.rows, f.net.cols, f.net.dim), (6, 5, 3));
    for i in 0..6 {
        for j in 0..5 {
            let (x, y) = (i as f64, j as f64);
            let want = [x * 1.5, y * 1.25, x.sin() * (0.7 * y).cos() + 0.1 * x * y];
            let got = &f.net.flat[(i * 5 + j) * 3..(i * 5 + j + 1) * 3];
            // OCCT writes 12 significant digits.
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() <= 1e-12 * want[c].abs().max(1.0),
                    "pole {i},{j}: {got:?}"
                );
            }
        }
    }
    // Its face is its natural boundary: nothing trimmed away.
    assert!(import.models[0].note.is_none());
    // Its four boundary curves are the face's edges.
    assert_eq!(import.skipped.get("edge curves of faces"), Some(&4));
}

#[test]
fn occt_box_reads_as_six_plane_patches_on_its_corners() {
    let import = step::read(&fixture("occt_box.step")).unwrap();
    assert_eq!(import.models.len(), 6);
    let mut corners = BTreeSet::new();
    for m in &import.models {
        let ModelFile::BezierSurface(f) = &m.file else {
            panic!()
        };
        assert_eq!((f.net.rows, f.net.cols), (2, 2));
        assert!(m.note.is_none(), "a rectangle face is its own patch");
        for p in f.net.flat.chunks_exact(3) {
            corners.insert(p.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
        }
    }
    // MakeBox(gp_Pnt(-1, -2, -0.5), 2, 4, 1.5).
    let mut want = BTreeSet::new();
    for x in [-1.0f64, 1.0] {
        for y in [-2.0f64, 2.0] {
            for z in [-0.5f64, 1.0] {
                want.insert(vec![x.to_bits(), y.to_bits(), z.to_bits()]);
            }
        }
    }
    assert_eq!(corners, want);
}

fn read_err(body: &str) -> String {
    let text = format!(
        "ISO-10303-21;\nHEADER;\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{body}ENDSEC;\nEND-ISO-10303-21;\n"
    );
    let err = step::read(&text).unwrap_err().to_string();
    assert!(!err.contains('\n'), "one line: {err}");
    err
}

const POINTS: &str = "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=CARTESIAN_POINT('',(1.,1.,0.));\n";

#[test]
fn bad_files_name_the_entity() {
    let cases = [
        // Dangling reference.
        (
            "#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#9),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);\n",
            "#3: refers to #9, which is not in the file",
        ),
        // Wrong parameter count.
        (
            "#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.UNSPECIFIED.,.F.,(2,2),(0.,1.));\n",
            "#3: B_SPLINE_CURVE_WITH_KNOTS has 7 parameters, expected 9",
        ),
        // Knots that do not fit.
        (
            "#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.UNSPECIFIED.,.F.,.F.,(2,1),(0.,1.),.UNSPECIFIED.);\n",
            "#3: the knot multiplicities sum to 3, but 2 control points of degree 1 need 4 knots",
        ),
        // A control point that is no point.
        (
            "#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#4),.UNSPECIFIED.,.F.,.F.,(2,2),(0.,1.),.UNSPECIFIED.);\n#4=DIRECTION('',(1.,0.,0.));\n",
            "#3: control point #4 is a DIRECTION, not a CARTESIAN_POINT",
        ),
        // Decreasing knots.
        (
            "#3=B_SPLINE_CURVE_WITH_KNOTS('',1,(#1,#2),.UNSPECIFIED.,.F.,.F.,(2,2),(1.,0.),.UNSPECIFIED.);\n",
            "#3: the knots must increase",
        ),
        // Nothing to import.
        (
            "#3=LINE('',#1,#4);\n#4=VECTOR('',#5,1.);\n#5=DIRECTION('',(1.,0.,0.));\n",
            "no B-spline or Bézier curve or surface to import (found: 1 LINE (not imported))",
        ),
    ];
    for (body, want) in cases {
        let err = read_err(&format!("{POINTS}{body}"));
        assert!(err.contains(want), "{body}: {err}");
    }
    // A cycle of references.
    let err = read_err(
        "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=VERTEX_POINT('',#3);\n#3=VERTEX_POINT('',#2);\n",
    );
    assert!(
        err.contains("cycle of references (#2 -> #3 -> #2)"),
        "{err}"
    );
}

#[test]
fn truncated_files_are_refused_wherever_they_stop() {
    let model =
        parse(r#"{"type": "bezier_surface", "net": [[[0,0,0],[1,0,1]],[[0,1,1],[1,1,0]]]}"#)
            .unwrap();
    let text = step::write(&model, &WriteOptions::default()).unwrap();
    // Every cut before the trailer is an error (never a panic, never a partial import).
    for cut in (0..text.len() - "END-ISO-10303-21;\n".len()).step_by(7) {
        let Some(part) = text.get(..cut) else {
            continue;
        };
        let err = step::read(part).unwrap_err().to_string();
        assert!(!err.contains('\n'), "{err}");
    }
    let err = step::read(&text[..text.len() / 2]).unwrap_err().to_string();
    assert!(err.starts_with("line "), "{err}");
    let cut = text.find("ENDSEC;\nEND-ISO").unwrap();
    let err = step::read(&text[..cut]).unwrap_err().to_string();
    assert!(err.contains("truncated"), "{err}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random B-spline curves (random knots, unclamped ends, any bits) round trip.
    #[test]
    fn random_bspline_curves_round_trip(
        degree in 1usize..6,
        extra in 0usize..6,
        steps in prop::collection::vec(0.0f64..3.0, 20),
        coords in prop::collection::vec(-1e6f64..1e6, 60),
    ) {
        let n = degree + 1 + extra;
        let mut knots = vec![0.0];
        for k in 0..n + degree {
            // Some steps repeat a knot (steps below 0.5 are zero).
            let s = if steps[k % steps.len()] < 0.5 { 0.0 } else { steps[k % steps.len()] };
            knots.push(knots[k] + s);
        }
        let control: Vec<Vec<f64>> = (0..n).map(|i| coords[3 * i..3 * i + 3].to_vec()).collect();
        // End knots repeated more than p + 1 times are dropped on writing (with the control
        // points they leave without influence): not this property's case.
        if knots[0] == knots[degree + 1] || knots[n + degree] == knots[n - 1] {
            return Ok(());
        }
        let Ok(curve) = geomkit::bspline::BsplineCurve::new(degree, knots, control) else {
            return Ok(());
        };
        let model = AnyModel::BsplineCurve(geomkit_model::BsplineCurveModel { curve, parameters: None });
        let Ok(text) = step::write(&model, &WriteOptions::default()) else {
            // Interior knots of multiplicity above p + 1 are refused.
            return Ok(());
        };
        let back = step::read(&text).unwrap();
        let before = to_json(&file_of(&model)).unwrap();
        let after = to_json(&back.models[0].file).unwrap();
        prop_assert_eq!(before, after);
    }
}

#[test]
fn closed_bezier_surfaces_are_solids_and_composites_are_sewn() {
    // A closed Bézier surface like the Mushroom: first and last rows collapsed to the poles,
    // first and last columns equal (a degree-2 × 4 "lens" around z).
    let ring = |r: f64, z: f64| -> String {
        let pts: Vec<String> = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0), (1.0, 0.0)]
            .iter()
            .map(|(x, y)| format!("[{}, {}, {z}]", r * x, r * y))
            .collect();
        format!("[{}]", pts.join(", "))
    };
    let net = format!(
        r#"{{"type": "bezier_surface", "net": [{}, {}, {}]}}"#,
        ring(0.0, 1.0),
        ring(2.0, 0.0),
        ring(0.0, -1.0)
    );
    let text = step::write(&parse(&net).unwrap(), &WriteOptions::default()).unwrap();
    assert!(text.contains("MANIFOLD_SOLID_BREP("), "{text}");
    assert!(text.contains("CLOSED_SHELL("));
    // Open: the same without the lower half.
    let open = format!(
        r#"{{"type": "bezier_surface", "net": [{}, {}]}}"#,
        ring(0.0, 1.0),
        ring(2.0, 0.0)
    );
    let text = step::write(&parse(&open).unwrap(), &WriteOptions::default()).unwrap();
    assert!(text.contains("OPEN_SHELL(") && !text.contains("CLOSED_SHELL("));
    // 2 × 2 bilinear patches of one 3 × 3 grid: 4 faces, 12 edges, 9 vertices.
    let p = |i: usize, j: usize| format!("[{i}, {j}, {}]", (i * j) as f64 * 0.25);
    let patch = |i: usize, j: usize| {
        format!(
            r#"{{"bezier": [[{}, {}], [{}, {}]]}}"#,
            p(i, j),
            p(i, j + 1),
            p(i + 1, j),
            p(i + 1, j + 1)
        )
    };
    let scene = format!(
        r#"{{"type": "composite_surface", "u_knots": [0, 1, 2], "v_knots": [0, 1, 2], "patches": [[{}, {}], [{}, {}]]}}"#,
        patch(0, 0),
        patch(0, 1),
        patch(1, 0),
        patch(1, 1)
    );
    let text = step::write(&parse(&scene).unwrap(), &WriteOptions::default()).unwrap();
    check_part21(&text);
    assert_eq!(text.matches("ADVANCED_FACE(").count(), 4);
    assert_eq!(text.matches("EDGE_CURVE(").count(), 12);
    assert_eq!(text.matches("VERTEX_POINT(").count(), 9);
    let back = step::read(&text).unwrap();
    assert!(back.models.iter().all(|m| m.note.is_none()));
}

#[test]
fn trimmed_faces_import_as_their_whole_surface_with_a_note() {
    // The cube's caps are plane patches larger than the square they bound.
    let cube = AnyModel::Ruled(geomkit::compose::bodies::cube().unwrap());
    let text = step::write(&cube, &WriteOptions::default()).unwrap();
    let back = step::read(&text).unwrap();
    assert_eq!(back.models.len(), 6);
    let notes = back.models.iter().filter(|m| m.note.is_some()).count();
    assert_eq!(notes, 2, "the two caps");
}
