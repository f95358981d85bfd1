//! # geomkit-expr
//!
//! The expression engine behind geomkit's single-formula composite surfaces
//! (spec/composite-surfaces.md, method 3): a hash-consed expression DAG, an infix parser,
//! symbolic derivative and substitution, precedence-correct printers for eleven targets and
//! a batched evaluator.
//!
//! - [`Graph`]: the arena. Equal expressions get equal [`Id`]s. Constructors simplify while
//!   they build: exact rational constant folding (`f64` constants fold in `f64`), flat n-ary
//!   sums and products with operands sorted by id (so `a + b` and `b + a` share a node), like
//!   terms collected (`2x + 3x = 5x`; `x - x = 0` and `0·x = 0` only when `x` is defined for
//!   every finite input, so no NaN is hidden), equal bases combined (`x·x = x^2`, not
//!   `x/x = 1`), `-(-x) = x`, constants distributed over sums, `|−x| = |x|`,
//!   `|x|^2 = x^2`, `sqrt(x^2) = |x|`.
//! - [`parse`]: infix text (`^` powers, `abs sqrt sin ...`, `pi`), exact decimal literals;
//!   [`parse_with_variables`] also refuses names outside a list. A mistake is a
//!   [`ParseError`] with the byte span of the text to underline, its [`ParseErrorKind`] and
//!   what was [`Expected`]; [`line_column`] and [`render_caret`] show it.
//! - [`Graph::substitute`], [`Graph::diff`] (`abs' = sign`), [`Graph::op_count`],
//!   [`Graph::eval`].
//! - [`Graph::print`] (one inline expression), [`Graph::print_program`] and
//!   [`Graph::print_function`] (common-subexpression temporaries) in every [`Format`].
//! - [`Tape`]: the DAG compiled to a register program evaluated over blocks of
//!   [`tape::LANES`] points.
//!
//! Limits: exact constants have at most [`MAX_EXACT_BITS`] bits in numerator and
//! denominator (longer ones are rounded to `f64`, and the parser refuses those beyond the
//! range of `f64`); the parser nests at most [`MAX_DEPTH`] levels (graphs built through the
//! API have no depth limit: every walk is iterative); a printed text is at most
//! [`MAX_PRINT_BYTES`] long. Evaluation, the tape and the printers refuse NaN and infinite
//! constants ([`ExprError::NonFiniteConstant`]) and exact ones outside the range of `f64`
//! ([`ExprError::ConstantOutOfRange`]).
//!
//! ```
//! use geomkit_expr::{parse, Format, Graph, Tape};
//! let mut g = Graph::new();
//! // The ramp P(t, a, w) of formula (1), with a = 1/3 and w = 2/3 exact.
//! let p = parse(&mut g, "(w + abs(t - a) - abs(t - a - w)) / (2*w)").unwrap();
//! let a = g.rational(1, 3);
//! let w = g.rational(2, 3);
//! let p = g.substitute(p, "a", a);
//! let p = g.substitute(p, "w", w);
//! // Exactly 0 and 1 at the knots:
//! let knot = g.rational(1, 3);
//! let at = g.substitute(p, "t", knot);
//! assert_eq!(g.print(at, Format::Maple).unwrap(), "0");
//! assert_eq!(g.print(p, Format::Maple).unwrap(), "3*abs(t - 1/3)/4 - 3*abs(t - 1)/4 + 1/2");
//! let tape = Tape::new(&g, &[p], &["t"]).unwrap();
//! let mut out = [0.0; 3];
//! tape.eval_batch(&[&[0.0, 2.0 / 3.0, 5.0]], &mut [&mut out]).unwrap();
//! assert_eq!(out, [0.0, 0.5, 1.0]);
//! ```

mod error;
pub mod fixtures;
mod graph;
mod parse;
mod parse_error;
mod print;
pub mod tape;

pub use error::{ExprError, Result};
pub use graph::{Const, Func, Graph, Id, Node, MAX_EXACT_BITS};
pub use num_bigint::BigInt;
pub use num_rational::BigRational;
pub use parse::{parse, parse_with_variables, MAX_DEPTH};
pub use parse_error::{line_column, render_caret, Expected, ParseError, ParseErrorKind};
pub use print::{Format, MAX_PRINT_BYTES};
pub use tape::Tape;
