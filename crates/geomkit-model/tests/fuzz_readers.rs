//! Fuzzing of the file readers (issue 21): the examples of docs/formats.md (one per file
//! type) mutated (numbers replaced by extremes, bytes flipped, cut, duplicated) and read.
//! Property: no panic; a file that reads gives a model that describes itself and
//! tessellates to finite points or refuses, and what parses writes back to the same file.

#[path = "../../geomkit/tests/common/fuzz.rs"]
mod fuzz;

use geomkit_model::{parse_file, to_json, AnyModel, Loaded, Sampling, Tessellation};
use proptest::prelude::*;

/// The ```json blocks of docs/formats.md.
fn examples() -> Vec<String> {
    include_str!("../../../docs/formats.md")
        .split("```json\n")
        .skip(1)
        .map(|block| block.split("```").next().unwrap().to_string())
        .collect()
}

/// Replaces the `which`-th number of `text` by `by`.
fn replace_number(text: &str, which: usize, by: &str) -> String {
    let bytes = text.as_bytes();
    let mut starts = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let number_start = (bytes[i].is_ascii_digit() || bytes[i] == b'-')
            && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric() && bytes[i - 1] != b'.');
        if number_start {
            let mut j = i + 1;
            while j < bytes.len() && (bytes[j].is_ascii_digit() || b".eE+-".contains(&bytes[j])) {
                j += 1;
            }
            starts.push((i, j));
            i = j;
        } else {
            i += 1;
        }
    }
    match starts.get(which % starts.len().max(1)) {
        Some(&(a, b)) => format!("{}{}{}", &text[..a], by, &text[b..]),
        None => text.to_string(),
    }
}

/// A mutation of an example.
#[derive(Debug, Clone)]
enum Mutation {
    Number(usize, &'static str),
    Flip(usize, u8),
    Cut(usize),
    Repeat(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let extremes = vec![
        "1e308",
        "-1.7976931348623157e308",
        "1e-320",
        "0",
        "-0",
        "1e999",
        "3.5",
        "-1",
        "1000000000",
        "18446744073709551616",
        "2",
        "0.5",
        "1e-300",
        "[]",
        "null",
        "\"x\"",
    ];
    prop_oneof![
        4 => (any::<usize>(), prop::sample::select(extremes)).prop_map(|(i, s)| Mutation::Number(i, s)),
        1 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
        1 => any::<usize>().prop_map(Mutation::Cut),
        1 => (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Mutation::Repeat(i, j)),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let len = text.len().max(1);
    match m {
        Mutation::Number(i, by) => replace_number(text, *i, by),
        Mutation::Flip(_, _) if text.is_empty() => String::new(),
        Mutation::Flip(i, b) => {
            let mut bytes = text.as_bytes().to_vec();
            bytes[i % len] = *b;
            String::from_utf8_lossy(&bytes).into_owned()
        }
        Mutation::Cut(i) => String::from_utf8_lossy(&text.as_bytes()[..i % len]).into_owned(),
        Mutation::Repeat(i, j) => {
            let (a, b) = ((i % len).min(j % len), (i % len).max(j % len));
            let bytes = text.as_bytes();
            let mut out = bytes[..b].to_vec();
            out.extend_from_slice(&bytes[a..]);
            String::from_utf8_lossy(&out).into_owned()
        }
    }
}

fn finite(t: &Tessellation) -> bool {
    match t {
        Tessellation::Polyline(p) => p.points().iter().all(|x| x.is_finite()),
        Tessellation::Mesh(m) => m.positions().iter().flatten().all(|x| x.is_finite()),
    }
}

proptest! {
    #![proptest_config(fuzz::config(96))]

    #[test]
    fn fuzz_model_readers(
        which in any::<usize>(),
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let all = examples();
        let mut text = all[which % all.len()].clone();
        for m in &mutations {
            text = apply(&text, m);
        }
        let Ok(file) = parse_file(&text) else { return Ok(()) };
        // What parses writes back to the same file (or refuses a non-finite number).
        if let Ok(json) = to_json(&file) {
            prop_assert_eq!(parse_file(&json).unwrap(), file.clone(), "{}", json);
        }
        let Ok(model) = AnyModel::from_file(file) else { return Ok(()) };
        prop_assert!(!model.describe().is_empty());
        let Ok(loaded) = Loaded::from_model(model) else { return Ok(()) };
        for sampling in [Sampling::Samples(5, 4), Sampling::Tolerance(None)] {
            if let Ok(t) = loaded.tessellate(sampling) {
                prop_assert!(finite(&t), "{}", text);
            }
        }
    }
}
