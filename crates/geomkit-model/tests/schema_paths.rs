//! Schema errors name the JSON path of the value at fault in `Error::path`, whether the
//! file's `"type"` comes first (read straight from the text) or later (read from a buffer):
//! front ends (the editor's server) underline the place from the path, never from the text.

use geomkit_model::{parse_file, ErrorKind};

/// The path and message of a schema error of `text`.
fn schema_error(text: &str) -> (String, String) {
    let err = parse_file(text).unwrap_err();
    match err.kind() {
        ErrorKind::Schema { path, message, .. } => (path.clone(), message.clone()),
        other => panic!("not a schema error: {other:?}"),
    }
}

#[test]
fn the_path_of_a_bad_number_whatever_the_place_of_type() {
    for text in [
        r#"{"type": "bezier_curve", "points": [[0, 0], [1, "a"]]}"#,
        r#"{"points": [[0, 0], [1, "a"]], "type": "bezier_curve"}"#,
    ] {
        let (path, message) = schema_error(text);
        assert_eq!(path, "points[1][1]", "{text}");
        assert!(message.starts_with("is the string \"a\""), "{message}");
        let shown = parse_file(text).unwrap_err().to_string();
        assert!(
            shown.starts_with("points[1][1] is the string \"a\""),
            "{shown}"
        );
    }
}

#[test]
fn nested_paths_of_a_file_with_type_last() {
    let text = r#"{"factors": [{"name": "a", "nodes": [0, "x"]}], "values": [1, 2],
        "type": "pointcalc-model"}"#;
    let (path, message) = schema_error(text);
    assert_eq!(path, "factors[0].nodes[1]");
    assert!(message.starts_with("is the string \"x\""), "{message}");
}

#[test]
fn document_level_errors_keep_an_empty_path_and_their_message() {
    // An unknown field of the document: the path is the document's.
    let (path, message) = schema_error(r#"{"points": [[0, 0]], "wat": 1, "type": "bezier_curve"}"#);
    assert_eq!(path, "");
    assert!(message.starts_with("unknown field \"wat\""), "{message}");
    // A message with a colon that is not a path stays whole.
    let (path, message) = schema_error(r#"{"points": [], "type": "no_such_type"}"#);
    assert_eq!(path, "");
    assert!(
        message.starts_with("unknown type \"no_such_type\": expected"),
        "{message}"
    );
}
