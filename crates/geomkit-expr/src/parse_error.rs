//! The parser's structured error: where the mistake is (a byte span of the formula's text),
//! what kind of mistake it is, and what the parser expected there; plus the helpers an editor
//! needs to show it ([`line_column`], [`render_caret`]).
//!
//! ```
//! use geomkit_expr::{parse, render_caret, ExprError, Graph, ParseErrorKind};
//! let text = "2*(u + 1";
//! let err = parse(&mut Graph::new(), text).unwrap_err();
//! let ExprError::Parse(e) = err else { panic!() };
//! // The `)` is missing at the end of the text (an empty span there); the `(` it would
//! // close is at byte 2.
//! assert_eq!(e.span, 8..8);
//! assert_eq!(e.kind, ParseErrorKind::UnclosedParen { open: 2, function: None });
//! assert_eq!((e.line, e.column), (1, 9));
//! assert_eq!(render_caret(text, e.span.clone()), "2*(u + 1\n        ^");
//! ```

use std::fmt;
use std::ops::Range;

use crate::graph::MAX_EXACT_BITS;

/// The function names the parser knows, as the error message lists them.
const KNOWN_FUNCTIONS: &str =
    "abs, sign, sqrt, sin, cos, tan, exp, ln, atan, asin, acos, sinh, cosh, tanh";

/// Largest decimal exponent of a number literal (`1e4000`).
pub(crate) const MAX_DECIMAL_EXPONENT: i64 = 4000;

/// A formula that does not parse: where, what, and what was expected.
///
/// `span` is a byte range of the parsed text, always within it and on char boundaries
/// (`&text[e.span.clone()]` never panics); it is empty where something is missing (at the
/// end of the text for `u +`). Its start is the byte the message names. `line` and `column`
/// are those of the span's start (1-based; the column counts chars, not bytes).
///
/// The Display text is the message users see (`parse error at byte 4: expected a number, a
/// name or `(`, found `*``), with ` (line L, column C)` after the byte for a mistake below
/// the first line.
///
/// ```
/// use geomkit_expr::{parse, ExprError, Expected, Graph, ParseErrorKind};
/// let text = "u·v";
/// let Err(ExprError::Parse(e)) = parse(&mut Graph::new(), text) else { panic!() };
/// // `·` takes two bytes: the span covers both, the column counts one char.
/// assert_eq!(&text[e.span.clone()], "·");
/// assert_eq!(e.span, 1..3);
/// assert_eq!(e.kind, ParseErrorKind::UnexpectedChar('·'));
/// assert_eq!(e.expected, [Expected::Operator, Expected::End]);
/// assert_eq!(
///     e.to_string(),
///     "parse error at byte 1: expected an operator or the end of the formula, found `·`"
/// );
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct ParseError {
    /// Byte range of the mistake in the parsed text (empty where something is missing).
    pub span: Range<usize>,
    /// What went wrong.
    pub kind: ParseErrorKind,
    /// What the parser would have accepted at `span.start` (empty where that is not a
    /// question of syntax: an exponent, the nesting depth, an unknown variable).
    pub expected: Vec<Expected>,
    /// The char at `span.start`, `None` at the end of the text.
    pub found: Option<char>,
    /// Line of `span.start`, 1-based.
    pub line: usize,
    /// Column of `span.start` in chars, 1-based.
    pub column: usize,
}

/// What kind of mistake a [`ParseError`] is.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParseErrorKind {
    /// A char that cannot stand here (`*` in `u + * v`, `·` in `u·v`).
    UnexpectedChar(char),
    /// The text ends where more must follow (`u +`, `u**`, `sin(`).
    UnexpectedEnd,
    /// A `(` whose `)` is missing: `open` is the byte offset of that `(`, `function` the name
    /// before it for a call (`sin(u`).
    UnclosedParen {
        /// Byte offset of the unclosed `(`.
        open: usize,
        /// The function called, if the `(` opens a call.
        function: Option<String>,
    },
    /// A `)` that closes nothing (`u + 1)`).
    UnmatchedCloseParen,
    /// A function name not followed by `(` (`sin u`).
    CallWithoutParen {
        /// The function.
        function: String,
    },
    /// A name followed by `(` that is not a known function (`foo(u)`); the span is the
    /// name.
    UnknownFunction {
        /// The name.
        name: String,
    },
    /// A variable outside the list given to [`crate::parse_with_variables`]; the span is
    /// its first occurrence.
    UnknownVariable {
        /// The name.
        name: String,
        /// The variables allowed.
        known: Vec<String>,
    },
    /// A malformed number literal: `.` alone, `2..3`, `1e` without digits, an exponent
    /// above 4000.
    BadNumber,
    /// An exponent that is not an integer constant (only integer powers and `^(1/2)`
    /// exist); the span runs from the `^` (or `**`) to the end of the exponent.
    BadExponent {
        /// Why the exponent is not accepted.
        reason: String,
    },
    /// The formula nests deeper than [`crate::MAX_DEPTH`].
    TooDeep {
        /// The limit.
        max: usize,
    },
    /// A constant (a literal such as `7e-4000`, a power such as `1.5^100000`, a product or
    /// sum of constants) is too long to keep exact ([`crate::MAX_EXACT_BITS`]) and beyond
    /// the range of `f64`; the span is the sub-expression whose value it is.
    ConstantOutOfRange {
        /// The text of the sub-expression (its first 40 chars and `...` when longer).
        text: String,
        /// Above the largest `f64` (about 1.8e308) in magnitude; else below the smallest
        /// (about 4.9e-324), where it would round to zero.
        overflow: bool,
    },
}

/// One item the parser would have accepted where it stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Expected {
    /// A number literal.
    Number,
    /// A variable or function name.
    Name,
    /// `(`.
    OpenParen,
    /// `)`.
    CloseParen,
    /// A binary operator (`+ - * / ^ **`).
    Operator,
    /// The end of the formula.
    End,
    /// A digit of a number literal.
    Digit,
    /// The digits of a number's decimal exponent (`1e-3`).
    ExponentDigits,
    /// A decimal exponent of at most 4000.
    SmallExponent,
    /// One of the known function names.
    Function,
}

impl fmt::Display for Expected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expected::Number => f.write_str("a number"),
            Expected::Name => f.write_str("a name"),
            Expected::OpenParen => f.write_str("`(`"),
            Expected::CloseParen => f.write_str("`)`"),
            Expected::Operator => f.write_str("an operator"),
            Expected::End => f.write_str("the end of the formula"),
            Expected::Digit => f.write_str("a digit"),
            Expected::ExponentDigits => f.write_str("digits of the exponent"),
            Expected::SmallExponent => {
                write!(f, "an exponent of at most {MAX_DECIMAL_EXPONENT}")
            }
            Expected::Function => write!(f, "a known function ({KNOWN_FUNCTIONS})"),
        }
    }
}

impl ParseError {
    /// An error at `span` of `text`, with line and column computed from the text.
    pub(crate) fn new(
        text: &str,
        span: Range<usize>,
        kind: ParseErrorKind,
        expected: Vec<Expected>,
    ) -> Self {
        let (line, column) = line_column(text, span.start);
        ParseError {
            found: text.get(span.start..).and_then(|s| s.chars().next()),
            span,
            kind,
            expected,
            line,
            column,
        }
    }

    /// The text of the span in `text` (the text that was parsed), or `""` if `text` is not
    /// that text and the span does not fit it.
    pub fn snippet<'t>(&self, text: &'t str) -> &'t str {
        text.get(self.span.clone()).unwrap_or("")
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = self.span.start;
        let place = if self.line > 1 {
            format!("byte {at} (line {}, column {})", self.line, self.column)
        } else {
            format!("byte {at}")
        };
        match &self.kind {
            ParseErrorKind::BadExponent { reason } => {
                return write!(f, "unsupported exponent at {place}: {reason}");
            }
            ParseErrorKind::TooDeep { max } => {
                return write!(f, "formula nests deeper than {max} levels at {place}");
            }
            ParseErrorKind::ConstantOutOfRange { text, overflow } => {
                let range = if *overflow {
                    "above the largest f64 (about 1.8e308)"
                } else {
                    "below the smallest f64 (about 4.9e-324)"
                };
                return write!(
                    f,
                    "constant out of range at {place}: `{text}` is too long to keep exact \
                     (more than {MAX_EXACT_BITS} bits) and {range}"
                );
            }
            ParseErrorKind::UnknownVariable { name, known } => {
                return write!(
                    f,
                    "unknown variable `{name}` (the variables are {}) at {place}",
                    known.join(", ")
                );
            }
            _ => {}
        }
        write!(f, "parse error at {place}: expected ")?;
        let n = self.expected.len();
        for (i, e) in self.expected.iter().enumerate() {
            let sep = match i {
                0 => "",
                _ if i + 1 == n => " or ",
                _ => ", ",
            };
            write!(f, "{sep}{e}")?;
        }
        match &self.kind {
            ParseErrorKind::CallWithoutParen { function } => {
                write!(f, " after the function name `{function}`")?;
            }
            ParseErrorKind::UnclosedParen {
                function: Some(function),
                ..
            } => write!(f, " closing `{function}(`")?,
            ParseErrorKind::UnknownFunction { name } => write!(f, ", not `{name}`")?,
            _ => {}
        }
        match self.found {
            None => f.write_str(", found end of input"),
            Some(c) => write!(f, ", found `{c}`"),
        }
    }
}

impl std::error::Error for ParseError {}

/// Line and column (both 1-based; the column counts chars) of byte `offset` of `text`.
///
/// Lines end at `\n` (a `\r` before it counts as the last char of its line). An offset past
/// the end is taken as the end; an offset inside a multi-byte char as that char.
///
/// ```
/// use geomkit_expr::line_column;
/// let text = "u +\n  ü * (v";
/// assert_eq!(line_column(text, 0), (1, 1));
/// assert_eq!(line_column(text, 4), (2, 1));
/// // `ü` is bytes 6..8; `*` at byte 9 is the fifth char of line 2.
/// assert_eq!(line_column(text, 9), (2, 5));
/// assert_eq!(line_column(text, text.len()), (2, 9));
/// ```
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() + 1;
    (line, before[line_start..].chars().count() + 1)
}

/// The line of `text` that holds `span.start`, and under it a line of `^` marking the span
/// (one per char, at least one; a span running past the line's end is cut there), for an
/// error shown in a terminal or a log:
///
/// ```text
/// 2*(u + 1
///         ^
/// ```
///
/// Offsets are clamped to the text and to char boundaries, as in [`line_column`].
///
/// ```
/// use geomkit_expr::render_caret;
/// assert_eq!(render_caret("u + foo(v)", 4..7), "u + foo(v)\n    ^^^");
/// assert_eq!(render_caret("a +\nü·b", 6..8), "ü·b\n ^");
/// ```
pub fn render_caret(text: &str, span: Range<usize>) -> String {
    let floor = |mut i: usize| {
        i = i.min(text.len());
        while !text.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    let start = floor(span.start);
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let line = text[line_start..line_end].trim_end_matches('\r');
    let end = floor(span.end).clamp(start, (line_start + line.len()).max(start));
    let pad = text[line_start..start].chars().count();
    let width = text[start..end].chars().count().max(1);
    format!("{line}\n{}{}", " ".repeat(pad), "^".repeat(width))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expected_items_join_like_a_sentence() {
        let e = ParseError::new(
            "u + * v",
            4..5,
            ParseErrorKind::UnexpectedChar('*'),
            vec![Expected::Number, Expected::Name, Expected::OpenParen],
        );
        assert_eq!(
            e.to_string(),
            "parse error at byte 4: expected a number, a name or `(`, found `*`"
        );
        let e = ParseError::new("u\n+", 3..3, ParseErrorKind::UnexpectedEnd, vec![]);
        assert_eq!((e.line, e.column, e.found), (2, 2, None));
    }

    #[test]
    fn offsets_inside_chars_and_past_the_end_are_clamped() {
        assert_eq!(line_column("ü", 1), (1, 1));
        assert_eq!(line_column("ü", 99), (1, 2));
        assert_eq!(line_column("", 0), (1, 1));
        assert_eq!(render_caret("ü", 1..99), "ü\n^");
        assert_eq!(render_caret("ab\r\ncd", 1..9), "ab\n ^");
        assert_eq!(render_caret("", 0..0), "\n^");
    }
}
