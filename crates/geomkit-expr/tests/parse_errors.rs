//! Parse errors keep their place: a catalogue of bad formulas whose spans are checked against
//! the text itself (`&text[span]`), with line and column against a counter written here
//! independently of the crate's; and a property test that for any text the span lies within
//! it on char boundaries and that parsing never panics.

use geomkit_expr::{
    line_column, parse, parse_with_variables, render_caret, Expected, ExprError, Graph, ParseError,
    ParseErrorKind,
};
use proptest::prelude::*;

/// Line and column (1-based, the column in chars) of byte `at`, by walking the chars.
fn reference_line_column(text: &str, at: usize) -> (usize, usize) {
    let (mut line, mut column) = (1, 1);
    for (i, c) in text.char_indices() {
        if i >= at {
            break;
        }
        if c == '\n' {
            line += 1;
            column = 1;
        } else {
            column += 1;
        }
    }
    (line, column)
}

fn parse_error(text: &str, variables: Option<&[&str]>) -> ParseError {
    let mut g = Graph::new();
    let r = match variables {
        None => parse(&mut g, text),
        Some(v) => parse_with_variables(&mut g, text, v),
    };
    match r {
        Err(ExprError::Parse(e)) => *e,
        Err(e) => panic!("{text:?}: not a parse error: {e}"),
        Ok(_) => panic!("{text:?} parsed"),
    }
}

/// One bad formula: the text, the variables (if restricted), what the span must cover, where
/// it starts, its line and column, and the kind.
struct Case {
    text: &'static str,
    variables: Option<&'static [&'static str]>,
    snippet: &'static str,
    start: usize,
    line_column: (usize, usize),
    kind: ParseErrorKind,
}

fn case(
    text: &'static str,
    snippet: &'static str,
    start: usize,
    line_column: (usize, usize),
    kind: ParseErrorKind,
) -> Case {
    Case {
        text,
        variables: None,
        snippet,
        start,
        line_column,
        kind,
    }
}

impl Case {
    /// The case parsed with [`parse_with_variables`].
    fn only(self, variables: &'static [&'static str]) -> Case {
        Case {
            variables: Some(variables),
            ..self
        }
    }
}

fn unclosed(open: usize, function: Option<&str>) -> ParseErrorKind {
    ParseErrorKind::UnclosedParen {
        open,
        function: function.map(str::to_string),
    }
}

#[test]
fn spans_of_a_catalogue_of_bad_formulas() {
    use ParseErrorKind::*;
    // An exponent's reason is not compared.
    let exponent = || BadExponent {
        reason: String::new(),
    };
    let cases = [
        case("(u+1", "", 4, (1, 5), unclosed(0, None)),
        case("2*(u + 1", "", 8, (1, 9), unclosed(2, None)),
        case("(u v", "v", 3, (1, 4), unclosed(0, None)),
        case("u + 1)", ")", 5, (1, 6), UnmatchedCloseParen),
        case("u**", "", 3, (1, 4), UnexpectedEnd),
        case("sin(", "", 4, (1, 5), UnexpectedEnd),
        case("sin(u", "", 5, (1, 6), unclosed(3, Some("sin"))),
        case(
            "sin u",
            "u",
            4,
            (1, 5),
            CallWithoutParen {
                function: "sin".into(),
            },
        ),
        case("u + * v", "*", 4, (1, 5), UnexpectedChar('*')),
        case("2..3", ".", 2, (1, 3), BadNumber),
        case(".", ".", 0, (1, 1), BadNumber),
        case("1e", "", 2, (1, 3), BadNumber),
        case("1e+", "+", 2, (1, 3), BadNumber),
        case("2*1e5000", "e5000", 3, (1, 4), BadNumber),
        case(
            "foo(u) + 1",
            "foo",
            0,
            (1, 1),
            UnknownFunction { name: "foo".into() },
        ),
        case("u·v", "·", 1, (1, 2), UnexpectedChar('·')),
        case("ü+1", "ü", 0, (1, 1), UnexpectedChar('ü')),
        case("1 + ü", "ü", 4, (1, 5), UnexpectedChar('ü')),
        case("π·ü + (u", "π", 0, (1, 1), UnexpectedChar('π')),
        case("u + (v ·w)", "·", 7, (1, 8), unclosed(4, None)),
        case("u^v", "^v", 1, (1, 2), exponent()),
        case("u ** (v + 1) + 2", "** (v + 1)", 2, (1, 3), exponent()),
        case("u +\n  v *\n  (w", "", 14, (3, 5), unclosed(12, None)),
        case("u +\n  ü * v", "ü", 6, (2, 3), UnexpectedChar('ü')),
        case("sin(u)\n+ 𝛼", "𝛼", 9, (2, 3), UnexpectedChar('𝛼')),
        case("u\r\n  + )", ")", 7, (2, 5), UnexpectedChar(')')),
    ];
    let unknown = |name: &str, known: &[&str]| UnknownVariable {
        name: name.into(),
        known: known.iter().map(|v| v.to_string()).collect(),
    };
    let with_variables = [
        case("u + w", "w", 4, (1, 5), unknown("w", &["u", "v"])).only(&["u", "v"]),
        case("ü·0 + sin(uu)", "", 0, (1, 1), UnexpectedChar('ü')).only(&["u"]),
        case("sin(ü)\n * (u + pi*wv)", "", 4, (1, 5), UnexpectedChar('ü')).only(&["u"]),
        case(
            "u\n * (v + pi*wv - wv)",
            "wv",
            13,
            (2, 12),
            unknown("wv", &["u", "v"]),
        )
        .only(&["u", "v"]),
    ];
    for c in cases.iter().chain(&with_variables) {
        let e = parse_error(c.text, c.variables);
        let text = c.text;
        // The span is where the case says, read from the text itself.
        assert_eq!(e.span.start, c.start, "{text:?}: {e}");
        let snippet = if c.snippet.is_empty() && e.span.start < text.len() {
            // A one-char span: the char there.
            &text[c.start..c.start + text[c.start..].chars().next().unwrap().len_utf8()]
        } else {
            c.snippet
        };
        assert_eq!(&text[e.span.clone()], snippet, "{text:?}: {e}");
        assert_eq!(e.snippet(text), snippet);
        assert_eq!(e.found, text[e.span.start..].chars().next(), "{text:?}");
        // Line and column: the case's, the independent counter's and the helper's agree.
        assert_eq!((e.line, e.column), c.line_column, "{text:?}: {e}");
        assert_eq!(reference_line_column(text, e.span.start), c.line_column);
        assert_eq!(line_column(text, e.span.start), c.line_column);
        // The kind (an exponent's reason aside), with an unclosed `(` really a `(`.
        match (&e.kind, &c.kind) {
            (BadExponent { .. }, BadExponent { .. }) => {}
            (k, want) => assert_eq!(k, want, "{text:?}: {e}"),
        }
        if let UnclosedParen { open, .. } = e.kind {
            assert_eq!(&text[open..open + 1], "(", "{text:?}");
        }
        // The message names the byte, and the line below the first.
        let place = if e.line > 1 {
            format!("at byte {} (line {}, column {})", c.start, e.line, e.column)
        } else {
            format!("at byte {}", c.start)
        };
        assert!(e.to_string().contains(&place), "{text:?}: {e}");
    }
}

#[test]
fn messages_stay_what_users_saw() {
    let cases = [
        (
            "(u+1",
            "parse error at byte 4: expected `)`, found end of input",
        ),
        (
            "sin(u",
            "parse error at byte 5: expected `)` closing `sin(`, found end of input",
        ),
        (
            "sin u",
            "parse error at byte 4: expected `(` after the function name `sin`, found `u`",
        ),
        (
            "u**",
            "parse error at byte 3: expected a number, a name or `(`, found end of input",
        ),
        (
            "2..3",
            "parse error at byte 2: expected an operator or the end of the formula, found `.`",
        ),
        (".", "parse error at byte 0: expected a digit, found `.`"),
        (
            "1e+",
            "parse error at byte 2: expected digits of the exponent, found `+`",
        ),
        (
            "1e5000",
            "parse error at byte 1: expected an exponent of at most 4000, found `e`",
        ),
        (
            "foo(u)",
            "parse error at byte 0: expected a known function (abs, sign, sqrt, sin, cos, tan, \
             exp, ln, atan, asin, acos, sinh, cosh, tanh), not `foo`, found `f`",
        ),
        (
            "u^v",
            "unsupported exponent at byte 1: exponents must be integer constants (or 1/2 for sqrt)",
        ),
        (
            "u^1.5",
            "unsupported exponent at byte 1: only integer exponents and 1/2 are supported",
        ),
        (
            "u +\n  * v",
            "parse error at byte 6 (line 2, column 3): expected a number, a name or `(`, \
             found `*`",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(parse_error(text, None).to_string(), want, "{text:?}");
    }
    let deep = format!("{}u{}", "(".repeat(300), ")".repeat(300));
    let e = parse_error(&deep, None);
    assert_eq!(
        e.to_string(),
        "formula nests deeper than 200 levels at byte 200"
    );
    assert_eq!(e.kind, ParseErrorKind::TooDeep { max: 200 });
    assert_eq!(&deep[e.span.clone()], "(");
    let e = parse_error("u + w", Some(&["u", "v"]));
    assert_eq!(
        e.to_string(),
        "unknown variable `w` (the variables are u, v) at byte 4"
    );
    assert!(e.expected.is_empty());
    assert_eq!(
        parse_error("u + * v", None).expected,
        [Expected::Number, Expected::Name, Expected::OpenParen]
    );
}

#[test]
fn an_editor_underlines_the_span() {
    let text = "u +\n  v * (w";
    let e = parse_error(text, None);
    assert_eq!(e.span, 12..12);
    assert_eq!(render_caret(text, e.span.clone()), "  v * (w\n        ^");
    let text = "1 + foo(ü)";
    let e = parse_error(text, None);
    assert_eq!(render_caret(text, e.span), "1 + foo(ü)\n    ^^^");
    let text = "ü·v";
    let e = parse_error(text, None);
    assert_eq!(render_caret(text, e.span), "ü·v\n^");
    assert_eq!(render_caret("u +\nü·v", 6..8), "ü·v\n ^");
}

/// Text near the formulas: operators, digits, names, brackets, whitespace and newlines, and
/// chars of two, three and four bytes.
fn formula_like() -> impl Strategy<Value = String> {
    proptest::collection::vec(
        prop_oneof![
            prop::sample::select(vec![
                "u", "v", "w", "1", "2.5", ".", "e", "e-", "+", "-", "*", "**", "/", "^", "(", ")",
                " ", "\n", "\r\n", "\t", "sin(", "abs", "pi", "1e5000", "·", "ü", "π", "€", "𝛼",
                "\u{0}", "\u{301}",
            ])
            .prop_map(str::to_string),
            any::<char>().prop_map(String::from),
        ],
        0..24,
    )
    .prop_map(|parts| parts.concat())
}

fn check_span(text: &str, r: Result<geomkit_expr::Id, ExprError>) -> Result<(), TestCaseError> {
    let e = match r {
        Ok(_) => return Ok(()),
        Err(ExprError::Parse(e)) => e,
        Err(e) => return Err(TestCaseError::fail(format!("{text:?}: {e}"))),
    };
    let s = e.span.clone();
    prop_assert!(
        s.start <= s.end && s.end <= text.len(),
        "{:?}: {:?}",
        text,
        s
    );
    prop_assert!(text.is_char_boundary(s.start) && text.is_char_boundary(s.end));
    prop_assert_eq!(e.found, text[s.start..].chars().next());
    // Empty exactly where something is missing at the end.
    prop_assert_eq!(s.is_empty(), s.start == text.len());
    prop_assert_eq!((e.line, e.column), reference_line_column(text, s.start));
    let message = e.to_string();
    prop_assert!(
        message.contains(&format!("at byte {}", s.start)),
        "{}",
        message
    );
    let caret = render_caret(text, s);
    prop_assert!(caret.lines().last().is_some_and(|l| l.ends_with('^')));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn spans_lie_in_the_text_on_char_boundaries(text in formula_like()) {
        let mut g = Graph::new();
        check_span(&text, parse(&mut g, &text))?;
        check_span(&text, parse_with_variables(&mut g, &text, &["u", "v"]))?;
    }

    #[test]
    fn any_string_parses_or_fails_without_panic(text in any::<String>()) {
        let mut g = Graph::new();
        check_span(&text, parse(&mut g, &text))?;
    }

    #[test]
    fn line_column_agrees_with_walking_the_chars(text in formula_like(), at in 0usize..200) {
        let mut at = at.min(text.len());
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        prop_assert_eq!(line_column(&text, at), reference_line_column(&text, at));
    }
}
