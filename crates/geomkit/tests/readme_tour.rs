//! The README's library tour is `examples/tour.rs`: this test runs it (every step asserts
//! what it claims) and checks that the README quotes it word for word.

#[path = "../examples/tour.rs"]
mod tour;

/// The lines between the markers, without their common indentation.
fn tour_text(source: &str) -> String {
    let start = source.find("// README-TOUR-START\n").expect("start marker") + 21;
    let end = source.find("    // README-TOUR-END").expect("end marker");
    source[start..end]
        .lines()
        .map(|l| l.strip_prefix("    ").unwrap_or(l))
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn the_tour_runs() {
    tour::main().expect("the tour runs");
}

#[test]
fn the_readme_quotes_the_tour() {
    let example = include_str!("../examples/tour.rs");
    let readme = include_str!("../../../README.md");
    let uses_start = example.find("\nuse ").expect("use lines") + 1;
    let uses_end = uses_start + example[uses_start..].find("\n\n").expect("blank line");
    let body = format!(
        "{}\n\n{}",
        &example[uses_start..uses_end],
        tour_text(example)
    );
    assert!(
        readme.contains(&body),
        "README.md's Library section must hold crates/geomkit/examples/tour.rs between its \
         markers, unindented:\n{body}"
    );
}
