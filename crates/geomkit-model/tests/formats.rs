//! The file formats: every example of docs/formats.md reads (one per type), every type
//! round-trips through the writer (property tests, 256 cases each), geometry round-trips
//! where a model can be written back, and bad files give one line with the file, the JSON
//! path and the line and column.

use geomkit::geom::Curve;
use geomkit_model::schema::*;
use geomkit_model::{
    parse, parse_file, to_json, AnyModel, BezierModel, ErrorKind, ModelFile, Net, Points,
};
use proptest::prelude::*;
use std::collections::BTreeSet;

/// The ```json blocks of docs/formats.md.
fn format_page_examples() -> Vec<String> {
    let page = include_str!("../../../docs/formats.md");
    page.split("```json\n")
        .skip(1)
        .map(|block| block.split("```").next().unwrap().to_string())
        .collect()
}

#[test]
fn every_example_of_the_formats_page_reads_and_every_type_has_one() {
    let mut types = BTreeSet::new();
    for text in format_page_examples() {
        let file = parse_file(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        types.insert(file.type_name());
        // Geometry too: the library accepts every example.
        let model = AnyModel::from_file(file.clone()).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert!(!model.describe().is_empty());
        // Written in the tools' layout and read back: the same file.
        assert_eq!(
            parse_file(&to_json(&file).unwrap()).unwrap(),
            file,
            "{text}"
        );
    }
    let all: BTreeSet<&str> = TYPES.iter().copied().collect();
    assert_eq!(types, all, "docs/formats.md lacks an example of some type");
}

#[test]
fn examples_mean_what_the_page_says() {
    let examples = format_page_examples();
    let model = |type_name: &str| {
        let text = examples
            .iter()
            .find(|t| parse_file(t).unwrap().type_name() == type_name)
            .unwrap();
        parse(text).unwrap()
    };
    // Example 2 of the Bézier paper: B(1/2) = Σ C(5,i)/32 P_i = (480/32, 360/32).
    let AnyModel::Bezier(BezierModel::Curve(c)) = model("bezier_curve") else {
        panic!("not a curve")
    };
    let p = c.eval(0.5);
    assert!(
        (p[0] - 15.0).abs() < 1e-13 && (p[1] - 11.25).abs() < 1e-13,
        "{p:?}"
    );
    // The point-calculus model passes through its values at the grid of levels.
    let AnyModel::Pointcalc(m) = model("pointcalc-model") else {
        panic!("not a model")
    };
    let y = m.model.eval(&[75.0, 1.0 / 3.0]).unwrap();
    assert!((y[0] - 5.0).abs() < 1e-13, "{y:?}");
    // The hat function of the formula file's model: 0, 1, 0 at its knots.
    let AnyModel::Formula(f) = model("formula") else {
        panic!("not a formula file")
    };
    let Some(AnyModel::Piecewise(p)) = f.model.as_deref() else {
        panic!("no piecewise model")
    };
    assert_eq!(
        [p.eval(0.0)[0], p.eval(1.0)[0], p.eval(2.0)[0]],
        [0.0, 1.0, 0.0]
    );
    // Bilinear surface samples: the centre of the first cell is the mean of its corners.
    let AnyModel::SurfaceSamples(s) = model("pointcalc-surface-samples") else {
        panic!("not samples")
    };
    let mut out = [0.0; 3];
    s.eval_into(0.5, 0.25, &mut out);
    assert_eq!(out, [0.5, 0.25, 0.75]);
}

/// Text of `file` read back as a file, and its error if any.
fn reads_back(file: &ModelFile) -> Result<(), TestCaseError> {
    let text = to_json(file).unwrap();
    let back = parse_file(&text).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
    prop_assert_eq!(&back, file, "{}", text);
    Ok(())
}

fn real() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        prop::num::f64::NORMAL,
        prop::num::f64::SUBNORMAL,
        Just(0.0),
        Just(f64::MAX),
        Just(-f64::MIN_POSITIVE),
    ]
}

fn reals(len: impl Into<prop::collection::SizeRange>) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(real(), len)
}

fn points(dim: std::ops::Range<usize>, n: std::ops::Range<usize>) -> impl Strategy<Value = Points> {
    // An empty list has no dimension.
    (dim, n).prop_flat_map(|(dim, n)| {
        let dim = if n == 0 { 0 } else { dim };
        reals(dim * n).prop_map(move |flat| Points { dim, flat })
    })
}

fn net() -> impl Strategy<Value = Net> {
    (1..4usize, 1..4usize, 1..4usize).prop_flat_map(|(rows, cols, dim)| {
        reals(rows * cols * dim).prop_map(move |flat| Net {
            rows,
            cols,
            dim,
            flat,
        })
    })
}

/// Any text: formulas, names, descriptions (escapes and non-ASCII included).
fn text() -> impl Strategy<Value = String> {
    prop_oneof![Just("sin(u)*v^2 - 1/3".to_string()), ".*", "[a-z]{1,8}",]
}

fn interval() -> impl Strategy<Value = [f64; 2]> {
    (real(), real()).prop_map(|(a, b)| [a, b])
}

fn patch() -> impl Strategy<Value = Patch> {
    prop_oneof![
        text().prop_map(Patch::Formula),
        net().prop_map(|n| Patch::Object(PatchObject {
            bezier: Some(n),
            ..PatchObject::default()
        })),
        (
            text(),
            text(),
            prop::option::of(text()),
            prop::option::of(prop::collection::vec(interval(), 0..3))
        )
            .prop_map(|(x, y, z, domain)| Patch::Object(PatchObject {
                bezier: None,
                x: Some(x),
                y: Some(y),
                z,
                domain,
            })),
    ]
}

fn patches() -> impl Strategy<Value = Vec<Vec<Patch>>> {
    prop::collection::vec(prop::collection::vec(patch(), 0..3), 0..3)
}

fn point3() -> impl Strategy<Value = Points3> {
    (real(), real(), real()).prop_map(|(x, y, z)| Points3([x, y, z]))
}

fn ruled_curve() -> impl Strategy<Value = RuledCurveFile> {
    let none = RuledCurveFile::default;
    prop_oneof![
        point3().prop_map(move |p| RuledCurveFile {
            point: Some(p),
            ..none()
        }),
        prop::collection::vec(point3(), 0..4).prop_map(move |p| RuledCurveFile {
            polygon: Some(p),
            ..none()
        }),
        prop::collection::vec(point3(), 0..4).prop_map(move |p| RuledCurveFile {
            polyline: Some(p),
            ..none()
        }),
        (point3(), real()).prop_map(move |(center, radius)| RuledCurveFile {
            circle: Some(Circle { center, radius }),
            ..none()
        }),
        (text(), text(), prop::option::of(text()), interval()).prop_map(move |(x, y, z, t)| {
            RuledCurveFile {
                x: Some(x),
                y: Some(y),
                z,
                t: Some(t),
                ..none()
            }
        }),
    ]
}

fn piece() -> impl Strategy<Value = Piece> {
    prop_oneof![
        text().prop_map(Piece::Function),
        (
            text(),
            text(),
            prop::option::of(text()),
            prop::option::of(interval())
        )
            .prop_map(|(x, y, z, domain)| Piece::Curve(CurvePiece { x, y, z, domain })),
    ]
}

fn pointcalc_model() -> impl Strategy<Value = PointcalcModelFile> {
    let factor = (
        text(),
        reals(0..4),
        prop::option::of(prop::collection::vec("-?[0-9]{1,3}/[1-9]", 0..4)),
    )
        .prop_map(|(name, nodes, exact)| FactorFile { name, nodes, exact });
    (
        prop::collection::vec(factor, 0..3),
        prop::collection::vec(text(), 0..3),
        reals(0..10),
    )
        .prop_map(|(factors, response, values)| PointcalcModelFile {
            factors,
            response,
            values,
        })
}

/// Any file of a type without nested models.
fn simple_file() -> impl Strategy<Value = ModelFile> {
    prop_oneof![
        (
            points(1..5, 0..6),
            prop::option::of(reals(0..6)),
            prop::option::of((real(), real()))
        )
            .prop_map(
                |(points, weights, error)| ModelFile::BezierCurve(BezierCurveFile {
                    points,
                    weights,
                    error: error.map(|(l2, linf_bound)| ReductionError { l2, linf_bound }),
                })
            ),
        (net(), prop::option::of(0.1..10.0f64)).prop_map(|(net, w)| {
            ModelFile::BezierSurface(BezierSurfaceFile {
                weights: w.map(|w| vec![vec![w; net.cols]; net.rows]),
                net,
            })
        }),
        (
            0..9usize,
            reals(0..12),
            points(1..4, 0..8),
            prop::option::of(reals(0..5))
        )
            .prop_map(|(degree, knots, control_points, parameters)| {
                ModelFile::BsplineCurve(BsplineCurveFile {
                    degree,
                    knots,
                    control_points,
                    parameters,
                })
            }),
        (
            (0..9usize, 0..9usize),
            reals(0..9),
            reals(0..9),
            net(),
            prop::option::of((reals(0..4), reals(0..4)))
        )
            .prop_map(|((p, q), knots_u, knots_v, net, params)| {
                let (parameters_u, parameters_v) = params.unzip();
                ModelFile::BsplineSurface(BsplineSurfaceFile {
                    degree: [p, q],
                    knots_u,
                    knots_v,
                    net,
                    parameters_u,
                    parameters_v,
                })
            }),
        (reals(0..4), reals(0..4), patches()).prop_map(|(u_knots, v_knots, patches)| {
            ModelFile::CompositeSurface(CompositeFile {
                u_knots,
                v_knots,
                patches,
            })
        }),
        (reals(0..4), reals(0..4), patches()).prop_map(|(x_knots, y_knots, patches)| {
            ModelFile::CompositeExplicit(ExplicitFile {
                x_knots,
                y_knots,
                patches,
            })
        }),
        (
            prop::option::of(interval()),
            reals(0..4),
            prop::collection::vec(ruled_curve(), 0..4)
        )
            .prop_map(|(u, v, curves)| ModelFile::Ruled(RuledFile { u, v, curves })),
        (reals(0..4), prop::collection::vec(piece(), 0..4))
            .prop_map(|(knots, pieces)| ModelFile::Piecewise(PiecewiseFile { knots, pieces })),
        (
            points(1..3, 0..5),
            prop::option::of(reals(0..5)),
            any::<bool>()
        )
            .prop_map(|(points, knots, closed)| {
                let f = PolylineFile { points, knots };
                if closed {
                    ModelFile::Polygon(f)
                } else {
                    ModelFile::Polyline(f)
                }
            }),
        pointcalc_model().prop_map(ModelFile::PointcalcModel),
        (
            prop::option::of(reals(0..4)),
            prop::option::of(real()),
            points(2..4, 0..6)
        )
            .prop_map(|(nodes, lebesgue, samples)| {
                ModelFile::PointcalcCurve(CurveSamplesFile {
                    nodes,
                    lebesgue,
                    samples,
                })
            }),
        (reals(0..4), reals(0..4), points(1..4, 0..6)).prop_map(|(u, v, points)| {
            ModelFile::PointcalcSurfaceSamples(SurfaceSamplesFile { u, v, points })
        }),
    ]
}

/// Any file, formula files (with any other file as their model) included.
fn any_file() -> impl Strategy<Value = ModelFile> {
    prop_oneof![
        3 => simple_file(),
        1 => (
            text(),
            prop::collection::vec(text(), 0..3),
            prop::collection::btree_map("[a-z]{1,10}", text(), 0..4),
            any::<usize>(),
            prop::option::of(simple_file()),
        )
            .prop_map(|(what, variables, formulas, op_count, model)| {
                ModelFile::Formula(FormulaFile {
                    what,
                    coordinates: variables.clone(),
                    variables,
                    op_count,
                    formulas,
                    continuity: Some(serde_json::json!({"max_jump": 0.5, "continuous": false})),
                    model: model.map(Box::new),
                })
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// Every type: written in the tools' layout and read back, the same file (every f64 to
    /// the bit, every string).
    #[test]
    fn every_type_round_trips(file in any_file()) {
        reads_back(&file)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Geometry that can be written back: file -> geometry -> file is the identity.
    #[test]
    fn bezier_and_bspline_geometry_round_trip(
        dim in 1..4usize,
        n in 1..7usize,
        weights in prop::option::of(prop::collection::vec(0.1..10.0f64, 7)),
        seed in reals(7 * 3),
    ) {
        let flat: Vec<f64> = seed[..n * dim].iter().map(|x| x.clamp(-1e300, 1e300)).collect();
        let file = ModelFile::BezierCurve(BezierCurveFile {
            points: Points { dim, flat: flat.clone() },
            weights: weights.map(|w| w[..n].to_vec()),
            error: None,
        });
        let AnyModel::Bezier(m) = AnyModel::from_file(file.clone()).unwrap() else {
            panic!("not Bézier")
        };
        // Rational curves too: the points come back as given, not as (w·P)/w.
        prop_assert_eq!(m.to_file(None), file);
        // A uniform cubic B-spline over the same points (n + 4 knots).
        if n >= 4 {
            let knots: Vec<f64> = (0..n + 4).map(|k| k as f64 * 0.5).collect();
            let file = ModelFile::BsplineCurve(BsplineCurveFile {
                degree: 3,
                knots,
                control_points: Points { dim, flat },
                parameters: Some(vec![1.5, 2.0]),
            });
            let AnyModel::BsplineCurve(m) = AnyModel::from_file(file.clone()).unwrap() else {
                panic!("not a B-spline")
            };
            prop_assert_eq!(m.to_file(), file);
        }
    }
}

fn error(text: &str) -> geomkit_model::Error {
    parse(text).unwrap_err()
}

#[test]
fn errors_name_the_json_path_line_and_column() {
    let text = "{\"type\": \"bspline_curve\", \"degree\": 1,\n \"knots\": [0, 0, 1, \"a\"],\n \"control_points\": [[0], [1]]}";
    let e = error(text);
    assert_eq!(e.path(), Some("knots[3]"));
    // Line 2, column 23: the last character of the string "a" (bytes 20..23 of the line).
    assert_eq!(e.position(), Some((2, 23)));
    assert_eq!(&text.lines().nth(1).unwrap()[20..23], "\"a\"");
    assert_eq!(
        e.to_string(),
        "knots[3] is the string \"a\"; numbers must be finite JSON numbers (line 2, column 23)"
    );
    let e = e.in_file(std::path::Path::new("fit.json"));
    assert!(e
        .to_string()
        .starts_with("fit.json: knots[3] is the string"));

    // Nested: a patch of a composite scene, three levels down.
    let e = error(
        r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"bezier":[[[0,0,0],[1,0]]]}]]}"#,
    );
    assert_eq!(e.path(), Some("patches[0][0].bezier[0][1]"));
    assert!(matches!(e.kind(), ErrorKind::Schema { .. }));

    // Geometry: the library's verdict at the field.
    let e = error(r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1,-1]}"#);
    assert_eq!(e.path(), Some("weights"));
    assert!(matches!(
        e.kind(),
        ErrorKind::Model {
            source: Some(geomkit::Error::InvalidWeight { .. }),
            ..
        }
    ));
    // A formula keeps the parser's byte span.
    let e = error(
        r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[[{"x":"u","y":"v +* 2"}]]}"#,
    );
    assert_eq!(e.path(), Some("patches[0][0]"));
    let ErrorKind::Model {
        source: Some(src), ..
    } = e.kind()
    else {
        panic!("{e}")
    };
    let span = src.parse_error().expect("a parse error").span.clone();
    assert_eq!(&"v +* 2"[span], "*");
}

#[test]
fn bad_files_are_refused_with_clear_messages() {
    let cases = [
        (
            r#"{"type":"bezier_curve","points":[[0,0],[1,"NaN"]]}"#,
            "points[1][1] is the string \"NaN\"",
        ),
        (
            r#"{"points":[[0,0],[1,"NaN"]],"type":"bezier_curve"}"#,
            "points[1][1] is the string \"NaN\"",
        ),
        (
            r#"{"type":"bezier_curve","points":[[0,1e999]]}"#,
            "number out of range (every number must be a finite f64)",
        ),
        (
            r#"{"type":"bezier_curve","points":[]}"#,
            "\"points\" is empty",
        ),
        (r#"{"type":"bezier_curve"}"#, "missing field \"points\""),
        (r#"{"type":"circle"}"#, "unknown type \"circle\""),
        (r#"{"points":[]}"#, "missing field \"type\""),
        (r#"[1,2]"#, "expected a JSON object with a \"type\" field"),
        (
            r#"{"type":"bezier_curve","points":[[0,0],[1]]}"#,
            "points[1] has 1 coordinate but the first point has 2",
        ),
        (
            r#"{"type":"bezier_curve","points":[[0,0]],"weight":[1]}"#,
            "unknown field \"weight\", expected one of \"points\", \"weights\", \"error\"",
        ),
        (
            r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1]}"#,
            "1 weights for 2 control points",
        ),
        (
            r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1,-1]}"#,
            "weight 1 is -1",
        ),
        (
            r#"{"type":"bezier_surface","net":[[[0,0,0],[1,0,0]],[[0,1,0]]]}"#,
            "ragged net: row 1 has 1 point but row 0 has 2",
        ),
        (r#"{"type":"bezier_surface","net":[]}"#, "\"net\" is empty"),
        (
            r#"{"type":"bezier_surface","net":[[[0],[1]],[[2],[3]]],"weights":[[1,1]]}"#,
            "\"weights\" has 1 row for a net of 2 rows",
        ),
        (
            r#"{"type":"bezier_surface","net":[[[0],[1]],[[2],[3]]],"weights":[[1,1],[1]]}"#,
            "weights[1] has 1 weight for a net of 2 points per row",
        ),
        (
            r#"{"type":"bezier_surface","net":[[[0],[1]],[[2],[3]]],"weights":[[1,1],[1,-1]]}"#,
            "weight (1, 1) of the net is -1",
        ),
        (r#"{"type":"bezier_surface","net":[[]]}"#, "net[0] is empty"),
        ("{", "invalid JSON"),
        (
            r#"{"type":"bezier_curve","points":[[0,0]]} trailing"#,
            "invalid JSON: trailing characters",
        ),
        (
            r#"{"type":"bspline_curve","degree":16,"knots":[],"control_points":[[0]]}"#,
            "\"degree\" must be an integer from 0 to 15, found 16",
        ),
        (
            r#"{"type":"bspline_curve","degree":1,"knots":[0,1,2],"control_points":[[0],[1]]}"#,
            "invalid knot vector",
        ),
        (
            r#"{"type":"bspline_surface","degree":3,"knots_u":[],"knots_v":[],"net":[]}"#,
            "\"degree\": invalid type: integer `3`, expected an array of length 2",
        ),
        (
            r#"{"type":"bspline_surface","degree":[1,1],"knots_u":[0,0,1,1],"knots_v":[0,0,1,1],"net":[[[0],[1]],[[1],[2]]],"parameters_u":[0,1]}"#,
            "give both \"parameters_u\" and \"parameters_v\" or neither",
        ),
        // The issue's case: nodes holding a string were dropped by one reader, refused by
        // another; now refused, naming the place.
        (
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,0.5,1,"oops"]}],"response":["y"],"values":[1,2,3,4]}"#,
            "factors[0].nodes[3] is the string \"oops\"",
        ),
        (
            r#"{"type":"pointcalc-model","factors":[{"name":"a","nodes":[0,1],"exact":["0","x"]}],"response":["y"],"values":[1,2]}"#,
            "factors[0].exact[1] is \"x\", which is not a number or fraction",
        ),
        (
            r#"{"type":"ruled","v":[0,1],"curves":[{"point":[0,0]},{"point":[0,0,1]}]}"#,
            "curves[0].point has 2 coordinates but a point here is [x, y, z]",
        ),
        (
            r#"{"type":"ruled","v":[1,0],"curves":[{"point":[0,0,0]},{"point":[0,0,1]}]}"#,
            "\"v\" must be strictly increasing",
        ),
        (
            r#"{"type":"ruled","v":[0,1],"curves":[{"point":[0,0,0],"circle":{"center":[0,0,1],"radius":1}},{"point":[0,0,1]}]}"#,
            "curves[0]: give one of",
        ),
        (
            r#"{"type":"composite_surface","u_knots":[0,1],"v_knots":[0,1],"patches":[["u*v"]]}"#,
            "patches[0][0]: a parametric patch is",
        ),
        (
            r#"{"type":"piecewise","knots":[0,1,2],"pieces":["x",{"x":"t","y":"t"}]}"#,
            "pieces[0] is a formula in x, but other pieces are curves",
        ),
        (
            r#"{"type":"pointcalc-curve","samples":[[0,1],[0,2]]}"#,
            "samples[1] must have a greater t",
        ),
        (
            r#"{"type":"formula","what":"w","variables":[],"coordinates":[],"op_count":1,"formulas":{},"model":{"type":"bezier_curve","points":[[0,"1"]]}}"#,
            "model.points[0][1] is the string \"1\"",
        ),
        (
            r#"{"type":"bezier_curve","version":2,"points":[[0,0]]}"#,
            "format version 2, written by a newer geomkit; this one reads version 1",
        ),
        (
            r#"{"type":"bezier_curve","version":1,"points":[[0,0]],"version":0}"#,
            "\"version\" starts at 1",
        ),
    ];
    for (text, want) in cases {
        let e = error(text).to_string();
        assert!(e.contains(want), "{text}\n  gives: {e}\n  wants: {want}");
        assert!(!e.contains('\n'), "{e}");
    }
    // Version 1 stated, and "type" anywhere: read alike.
    let a = parse_file(r#"{"type":"bezier_curve","version":1,"points":[[0,0]]}"#).unwrap();
    let b = parse_file(r#"{"points":[[0,0]],"version":1,"type":"bezier_curve"}"#).unwrap();
    assert_eq!(a, b);
}

#[test]
fn the_layout_is_one_point_per_line_and_one_net_row_per_line() {
    let file = ModelFile::BezierSurface(BezierSurfaceFile {
        net: Net {
            rows: 2,
            cols: 2,
            dim: 3,
            flat: vec![
                0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1e-300,
            ],
        },
        weights: None,
    });
    assert_eq!(
        to_json(&file).unwrap(),
        "{\n  \"type\": \"bezier_surface\",\n  \"net\": [\n    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]],\n    [[1.0, 0.0, 0.0], [1.0, 1.0, 1e-300]]\n  ]\n}\n"
    );
    let file = ModelFile::BsplineCurve(BsplineCurveFile {
        degree: 1,
        knots: vec![0.0, 0.0, 1.0, 1.0],
        control_points: Points {
            dim: 2,
            flat: vec![0.1, 0.2, 0.3, 0.4],
        },
        parameters: None,
    });
    assert_eq!(
        to_json(&file).unwrap(),
        "{\n  \"type\": \"bspline_curve\",\n  \"degree\": 1,\n  \"knots\": [0.0, 0.0, 1.0, 1.0],\n  \"control_points\": [\n    [0.1, 0.2],\n    [0.3, 0.4]\n  ]\n}\n"
    );
}

/// A result that overflowed is refused, never written as `null` (which would read back as
/// no number at all).
#[test]
fn non_finite_numbers_are_not_written() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let file = ModelFile::BezierCurve(BezierCurveFile {
            points: Points {
                dim: 2,
                flat: vec![0.0, 1.0, 2.0, 3.0],
            },
            weights: None,
            error: Some(ReductionError {
                l2: bad,
                linf_bound: 1.0,
            }),
        });
        let e = to_json(&file).unwrap_err();
        assert!(
            e.to_string().starts_with("a result is not a finite number")
                && e.to_string().ends_with("(in \"error\")"),
            "{e}"
        );
        let mut sink = Vec::new();
        let e = geomkit_model::write_json(&file, &mut sink).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidData);
        assert!(!String::from_utf8_lossy(&sink).contains("null"));
    }
}
