//! Fuzzing of the STEP reader (issue 26): OCCT-written files and geomkit-written ones (a body,
//! a rational curve) mutated (references redirected, numbers replaced, bytes flipped, cut)
//! and read. Property: no panic; what reads gives checked model files that export again.

#[path = "../../geomkit/tests/common/fuzz.rs"]
mod fuzz;

use geomkit_model::step::{self, WriteOptions};
use geomkit_model::AnyModel;
use proptest::prelude::*;

fn texts() -> Vec<String> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/step/");
    let mut out: Vec<String> = [
        "occt_bezier_curve.step",
        "occt_box.step",
        "occt_bspline_surface.step",
    ]
    .iter()
    .map(|f| std::fs::read_to_string(format!("{dir}{f}")).unwrap())
    .collect();
    let cone = AnyModel::Ruled(geomkit::compose::bodies::cone(1.0, 2.0).unwrap());
    out.push(step::write(&cone, &WriteOptions::default()).unwrap());
    let rational = geomkit_model::parse(
        r#"{"type": "bezier_curve", "points": [[1, 0, 0], [1, 1, 0], [0, 1, 1]], "weights": [1, 0.5, 1]}"#,
    )
    .unwrap();
    out.push(step::write(&rational, &WriteOptions::default()).unwrap());
    out
}

/// One change of a file's text.
#[derive(Debug, Clone)]
enum Edit {
    /// The k-th `#N` becomes `#M`.
    Reference(usize, u64),
    /// The k-th digit becomes another character.
    Digit(usize, char),
    /// A byte replaced.
    Byte(usize, u8),
    /// The text cut at a position.
    Truncate(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        3 => (any::<usize>(), 0u64..400).prop_map(|(k, m)| Edit::Reference(k, m)),
        3 => (any::<usize>(), prop::sample::select(vec!['0', '9', '.', '-', 'E', ',', ')', '(', '$', '*', '\'']))
            .prop_map(|(k, c)| Edit::Digit(k, c)),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(k, b)| Edit::Byte(k, b)),
        1 => any::<usize>().prop_map(Edit::Truncate),
    ]
}

fn edited(text: &str, e: &Edit) -> String {
    let bytes = text.as_bytes();
    let n = bytes.len().max(1);
    match e {
        Edit::Reference(k, m) => {
            let refs: Vec<usize> = text.match_indices('#').map(|(i, _)| i).collect();
            let Some(&at) = refs.get(k % refs.len().max(1)) else {
                return text.to_string();
            };
            let end = at
                + 1
                + text[at + 1..]
                    .chars()
                    .take_while(char::is_ascii_digit)
                    .count();
            format!("{}#{m}{}", &text[..at], &text[end..])
        }
        Edit::Digit(k, c) => {
            let digits: Vec<usize> = (0..bytes.len())
                .filter(|&i| bytes[i].is_ascii_digit())
                .collect();
            let Some(&at) = digits.get(k % digits.len().max(1)) else {
                return text.to_string();
            };
            format!("{}{c}{}", &text[..at], &text[at + 1..])
        }
        Edit::Byte(k, b) => {
            let mut v = bytes.to_vec();
            if !v.is_empty() {
                v[k % n] = *b;
            }
            String::from_utf8_lossy(&v).into_owned()
        }
        Edit::Truncate(k) => String::from_utf8_lossy(&bytes[..k % n]).into_owned(),
    }
}

proptest! {
    #![proptest_config(fuzz::config(64))]

    #[test]
    fn fuzz_step_reader(which in any::<usize>(), edits in prop::collection::vec(edit(), 1..4)) {
        let all = texts();
        let mut text = all[which % all.len()].clone();
        for e in &edits {
            text = edited(&text, e);
        }
        let Ok(import) = step::read(&text) else { return Ok(()) };
        prop_assert!(!import.models.is_empty());
        for m in import.models {
            // Checked on import: the model builds, and writes as STEP or refuses.
            let model = AnyModel::from_file(m.file).unwrap();
            let _ = step::write(&model, &WriteOptions::default());
        }
    }
}
