//! Import of rational B-spline curves and surfaces of several spans as rational Bézier
//! pieces (knot insertion in homogeneous coordinates), checked against exact rationals (a
//! semicircle and a circle whose pieces are known in closed form), against OpenCASCADE's own
//! files (a circle and a sphere written by OCCT 7.9, tests/fixtures/step, made by
//! `bench/compat_step.py`'s `occt_files`): every piece on the circle / sphere, pieces meeting
//! end to end; and the trimmed-face report.

use geomkit::geom::{Curve, Surface};
use geomkit_model::schema::ModelFile;
use geomkit_model::step::{self, WriteOptions};
use geomkit_model::{AnyModel, BezierModel};

fn fixture(name: &str) -> String {
    let path = format!("{}/tests/fixtures/step/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).unwrap()
}

/// A STEP file of one rational B-spline curve of degree 2 (points in the plane z = 0).
fn rational_curve(
    points: &[(f64, f64)],
    weights: &[f64],
    knots: &[f64],
    mults: &[usize],
) -> String {
    let mut lines = Vec::new();
    for (k, (x, y)) in points.iter().enumerate() {
        lines.push(format!("#{}=CARTESIAN_POINT('',({x:?},{y:?},0.));", k + 1));
    }
    let refs: Vec<String> = (1..=points.len()).map(|k| format!("#{k}")).collect();
    let list = |v: Vec<String>| v.join(",");
    lines.push(format!(
        "#{}=(BOUNDED_CURVE()B_SPLINE_CURVE(2,({}),.UNSPECIFIED.,.F.,.F.)\
         B_SPLINE_CURVE_WITH_KNOTS(({}),({}),.UNSPECIFIED.)CURVE()\
         GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE(({}))\
         REPRESENTATION_ITEM('arc'));",
        points.len() + 1,
        list(refs),
        list(mults.iter().map(|m| m.to_string()).collect()),
        list(knots.iter().map(|k| format!("{k:?}")).collect()),
        list(weights.iter().map(|w| format!("{w:?}")).collect()),
    ));
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('','',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n{}\nENDSEC;\nEND-ISO-10303-21;\n",
        lines.join("\n")
    )
}

/// The pieces' (points, weights), in order.
fn pieces(text: &str) -> Vec<(Vec<f64>, Vec<f64>)> {
    let import = step::read(text).unwrap();
    import
        .models
        .iter()
        .map(|m| match &m.file {
            ModelFile::BezierCurve(b) => (b.points.flat.clone(), b.weights.clone().unwrap()),
            other => panic!("a rational Bézier curve, not {}", other.type_name()),
        })
        .collect()
}

#[test]
fn a_semicircle_of_two_spans_splits_into_its_exact_quarter_arcs() {
    // Two quarter arcs joined C1 in homogeneous space at the simple knot 1: weights 1, 1/2,
    // 1/2, 1. Inserting knot 1 (α = 1/2) gives the junction (0, 1) with weight 1/2, and
    // each quarter arc satisfies w1² / (w0 w2) = cos²(45°) = 1/2: exact, and dyadic.
    let text = rational_curve(
        &[(1.0, 0.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, 0.0)],
        &[1.0, 0.5, 0.5, 1.0],
        &[0.0, 1.0, 2.0],
        &[3, 1, 3],
    );
    let got = pieces(&text);
    assert_eq!(
        got,
        vec![
            (
                vec![1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0],
                vec![1.0, 0.5, 0.5]
            ),
            (
                vec![0.0, 1.0, 0.0, -1.0, 1.0, 0.0, -1.0, 0.0, 0.0],
                vec![0.5, 0.5, 1.0]
            ),
        ]
    );
    let import = step::read(&text).unwrap();
    assert_eq!(import.models[0].span, vec![0]);
    assert_eq!(import.models[1].span, vec![1]);
    assert!(import.models[1]
        .note
        .as_deref()
        .unwrap()
        .starts_with("span 2 of 2: t in [1, 2]"));
    assert!(import.skipped.is_empty(), "{:?}", import.skipped);
    // Every point of both pieces is on the unit circle.
    for m in &import.models {
        let AnyModel::Bezier(BezierModel::Rational(r)) =
            AnyModel::from_file(m.file.clone()).unwrap()
        else {
            panic!("rational Bézier");
        };
        for k in 0..=100 {
            let p = r.eval(k as f64 / 100.0);
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15, "{p:?}");
        }
    }
}

#[test]
fn a_full_circle_with_double_knots_keeps_the_files_points_and_weights() {
    // Two semicircles (as above) joined by a double knot at 2: four spans, four quarter arcs;
    // nothing is computed where the multiplicity is already p, and the rest are exact.
    let text = rational_curve(
        &[
            (1.0, 0.0),
            (1.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ],
        &[1.0, 0.5, 0.5, 1.0, 0.5, 0.5, 1.0],
        &[0.0, 1.0, 2.0, 3.0, 4.0],
        &[3, 1, 2, 1, 3],
    );
    let got = pieces(&text);
    assert_eq!(got.len(), 4);
    assert_eq!(
        got[2].0,
        vec![-1.0, 0.0, 0.0, -1.0, -1.0, 0.0, 0.0, -1.0, 0.0]
    );
    assert_eq!(got[2].1, vec![1.0, 0.5, 0.5]);
    assert_eq!(
        got[3].0,
        vec![0.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 0.0, 0.0]
    );
    assert_eq!(got[3].1, vec![0.5, 0.5, 1.0]);
    // Pieces meet end to end (first point of each = last point of the one before).
    for w in got.windows(2) {
        assert_eq!(w[0].0[6..9], w[1].0[0..3]);
    }
}

#[test]
fn occt_circle_of_several_rational_spans_imports_on_the_circle() {
    let import = step::read(&fixture("occt_rational_circle.step")).unwrap();
    // OCCT's circle: 7 poles, knots of multiplicity 2 (three arcs of 120°).
    assert_eq!(import.models.len(), 3, "{:?}", import.skipped);
    let centre = [1.0, -1.0, 0.5];
    let n = {
        let d: [f64; 3] = [0.3, -0.2, 1.0];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        [d[0] / l, d[1] / l, d[2] / l]
    };
    let mut ends = Vec::new();
    for m in &import.models {
        let AnyModel::Bezier(BezierModel::Rational(r)) =
            AnyModel::from_file(m.file.clone()).unwrap()
        else {
            panic!("rational Bézier");
        };
        for k in 0..=200 {
            let p = r.eval(k as f64 / 200.0);
            let d = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
            let radius = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            let height = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
            // OCCT writes 12 significant digits.
            assert!((radius - 2.0).abs() < 1e-11, "radius {radius}");
            assert!(height.abs() < 1e-11, "off the plane by {height}");
        }
        ends.push((r.eval(0.0), r.eval(1.0)));
    }
    for k in 0..3 {
        let (a, b) = (&ends[k].1, &ends[(k + 1) % 3].0);
        assert!((0..3).all(|c| (a[c] - b[c]).abs() < 1e-12), "{a:?} {b:?}");
    }
}

#[test]
fn occt_sphere_of_several_rational_spans_imports_as_patches_on_the_sphere() {
    let import = step::read(&fixture("occt_rational_sphere.step")).unwrap();
    // u: three spans of 120°, v: two of 90°.
    assert_eq!(import.models.len(), 6, "{:?}", import.skipped);
    let spans: Vec<Vec<usize>> = import.models.iter().map(|m| m.span.clone()).collect();
    assert_eq!(
        spans,
        vec![
            vec![0, 0],
            vec![0, 1],
            vec![1, 0],
            vec![1, 1],
            vec![2, 0],
            vec![2, 1]
        ]
    );
    let centre = [0.5, 0.25, -1.0];
    for m in &import.models {
        let AnyModel::Bezier(BezierModel::RationalSurface(s)) =
            AnyModel::from_file(m.file.clone()).unwrap()
        else {
            panic!("rational Bézier surface");
        };
        for a in 0..=20 {
            for b in 0..=20 {
                let mut p = [0.0; 3];
                s.eval_into(a as f64 / 20.0, b as f64 / 20.0, &mut p);
                let r = (0..3)
                    .map(|c| (p[c] - centre[c]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                assert!((r - 1.5).abs() < 1e-11, "radius {r}");
            }
        }
    }
}

#[test]
fn our_cylinders_rational_faces_read_back_as_quarter_patches() {
    // The cylinder body's side and discs: rational quadratic × linear surfaces of four spans.
    let cylinder = AnyModel::Ruled(geomkit::compose::bodies::cylinder(1.0, 2.0).unwrap());
    let text = step::write(&cylinder, &WriteOptions::default()).unwrap();
    let import = step::read(&text).unwrap();
    let side: Vec<_> = import.models.iter().filter(|m| m.span.len() == 2).collect();
    // The side and the two discs (collapsed to the axis on one side): 3 × 4 quarters.
    assert_eq!(side.len(), 12);
    for m in side {
        let ModelFile::BezierSurface(b) = &m.file else {
            panic!("a Bézier surface");
        };
        // The file's own numbers: weights 1, √2/2, 1 down each column.
        let w = b.weights.as_ref().unwrap();
        assert_eq!(w[1], vec![std::f64::consts::FRAC_1_SQRT_2; 2]);
    }
}

#[test]
fn trimmed_faces_are_reported_with_their_surfaces() {
    // The cube's caps are plane patches larger than the square they bound.
    let cube = AnyModel::Ruled(geomkit::compose::bodies::cube().unwrap());
    let text = step::write(&cube, &WriteOptions::default()).unwrap();
    let import = step::read(&text).unwrap();
    assert_eq!(import.trimmed.len(), 2, "{:?}", import.trimmed);
    for t in &import.trimmed {
        assert_eq!(t.loops, 1);
        let m = import.models.iter().find(|m| m.id == t.surface).unwrap();
        assert!(m.note.as_deref().unwrap().contains(&format!("#{}", t.face)));
    }
    // A face with a hole: a side face (untrimmed) given a second bound.
    let face = text
        .lines()
        .filter(|l| l.contains("ADVANCED_FACE("))
        .nth(1)
        .unwrap();
    let (id, _) = face.split_once('=').unwrap();
    let bound = face.split(",(#").nth(1).unwrap().split(')').next().unwrap();
    let holed = text.replace(
        face,
        &face.replace(&format!(",(#{bound})"), &format!(",(#{bound},#{bound})")),
    );
    let import = step::read(&holed).unwrap();
    let t = import
        .trimmed
        .iter()
        .find(|t| format!("#{}", t.face) == id)
        .expect("the holed face is reported");
    assert_eq!(t.loops, 2);
}
