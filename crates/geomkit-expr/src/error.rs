//! The expression engine's one error type.

use thiserror::Error;

use crate::parse_error::ParseError;

/// Everything that can go wrong in the expression engine. Every variant names what is wrong
/// and where.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ExprError {
    /// The text could not be parsed: the byte span of the mistake, its kind and what was
    /// expected ([`ParseError`]; boxed to keep the engine's results small).
    #[error(transparent)]
    Parse(Box<ParseError>),
    /// An evaluation or a tape needs a variable that was not given.
    #[error("unknown variable `{name}`: no value given for it")]
    UnknownVariable {
        /// The variable's name.
        name: String,
    },
    /// A variable was given twice.
    #[error("variable `{name}` is given twice")]
    DuplicateVariable {
        /// The variable's name.
        name: String,
    },
    /// The expression divides by a constant that is exactly zero.
    #[error("division by exact zero in the expression")]
    DivisionByZero,
    /// A constant of the expression is NaN or infinite.
    #[error("constant {value} of the expression is not a finite number")]
    NonFiniteConstant {
        /// The constant, as printed by Rust.
        value: String,
    },
    /// An exact constant of the expression is outside the range of `f64` (above about
    /// 1.8e308 or below about 4.9e-324 in magnitude, and not zero): evaluating it, or printing
    /// it for a target that computes in `f64`, would give infinity or zero.
    #[error(
        "constant {value} of the expression is outside the range of f64 (magnitudes from about \
         4.9e-324 to 1.8e308)"
    )]
    ConstantOutOfRange {
        /// The constant, approximately (`1.0000e400`).
        value: String,
    },
    /// A printed formula would be longer than [`crate::MAX_PRINT_BYTES`]: an inline print
    /// repeats every shared sub-expression where it occurs, so a DAG can print exponentially
    /// long.
    #[error(
        "the printed formula would be longer than {max} bytes (inline, shared \
         sub-expressions are repeated; a program with temporaries prints each once)"
    )]
    PrintTooLong {
        /// The limit, [`crate::MAX_PRINT_BYTES`].
        max: usize,
    },
    /// An input or output buffer of a batched evaluation has the wrong shape.
    #[error("{what}: got {got}, expected {expected}")]
    Shape {
        /// Which buffer ("inputs", "outputs", "input 2 length", ...).
        what: String,
        /// What was given.
        got: usize,
        /// What was expected.
        expected: usize,
    },
    /// An identifier that is not a valid variable name.
    #[error("invalid variable name `{name}`: {reason}")]
    InvalidName {
        /// The name.
        name: String,
        /// Why it is refused.
        reason: &'static str,
    },
}

/// The engine's result type.
pub type Result<T> = std::result::Result<T, ExprError>;

impl From<ParseError> for ExprError {
    fn from(e: ParseError) -> Self {
        ExprError::Parse(Box::new(e))
    }
}
