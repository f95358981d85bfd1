//! The library's one error type.

use thiserror::Error;

/// Everything that can go wrong in geomkit. Every variant names what is wrong and where.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum Error {
    /// An input that must hold something was empty.
    #[error("{what} is empty")]
    Empty {
        /// What was empty ("control points", "net", ...).
        what: &'static str,
    },
    /// Too few points for the requested construction.
    #[error("too few {what}: got {got}, need at least {min}")]
    TooFewPoints {
        /// What was counted.
        what: &'static str,
        /// How many were given.
        got: usize,
        /// The least number that works.
        min: usize,
    },
    /// A NaN or infinite number in the input.
    #[error("{what} {index} is not a finite number")]
    NonFinite {
        /// What held it ("control point", "weight", "parameter", ...).
        what: &'static str,
        /// Its index (for nets: the flattened row-major index of the point).
        index: usize,
    },
    /// Points of different dimensions were mixed.
    #[error("{what} {index} has {got} coordinates, expected {expected}")]
    DimensionMismatch {
        /// What had the wrong dimension.
        what: &'static str,
        /// Its index.
        index: usize,
        /// The dimension of the first point.
        expected: usize,
        /// The dimension found.
        got: usize,
    },
    /// Points with zero coordinates.
    #[error("{what} have no coordinates (dimension 0)")]
    ZeroDimension {
        /// What was zero-dimensional.
        what: &'static str,
    },
    /// A control net whose rows have different lengths.
    #[error("control net row {row} has {got} points, expected {expected}")]
    RaggedNet {
        /// The row index i.
        row: usize,
        /// Length of row 0.
        expected: usize,
        /// Length of this row.
        got: usize,
    },
    /// Exact reduction was asked below the real degree.
    #[error(
        "cannot reduce exactly to degree {requested}: the real degree is {real_degree} \
         (degree defect {defect}); use an approximate reduction"
    )]
    DegreeDefectTooSmall {
        /// The real degree found by the residual test.
        real_degree: usize,
        /// The degree asked for.
        requested: usize,
        /// Formal degree minus real degree.
        defect: usize,
    },
    /// Exact reduction of a surface was asked below its real degree in one direction.
    #[error(
        "cannot reduce the surface exactly to degree {requested} in {direction}: the real \
         {direction}-degree is {real_degree} (degree defect {defect})"
    )]
    SurfaceDefectTooSmall {
        /// "u" (the paper's t, index i) or "v" (τ, index j).
        direction: &'static str,
        /// The real degree in that direction.
        real_degree: usize,
        /// The degree asked for.
        requested: usize,
        /// Formal minus real degree in that direction.
        defect: usize,
    },
    /// A requested degree that makes no sense for the operation.
    #[error("invalid target degree {requested} for a curve of degree {degree}: {reason}")]
    InvalidDegree {
        /// The current (formal) degree.
        degree: usize,
        /// The requested degree.
        requested: usize,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// A weight of a rational curve that is not strictly positive.
    #[error("weight {index} is {value}; weights must be finite and > 0")]
    InvalidWeight {
        /// Index of the weight.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The number of weights differs from the number of control points.
    #[error("{got} weights for {expected} control points")]
    WeightCount {
        /// Number of control points.
        expected: usize,
        /// Number of weights given.
        got: usize,
    },
    /// Endpoint continuity constraints that over-determine the reduced curve.
    #[error(
        "continuity C{start} at t=0 and C{end} at t=1 fix {fixed} control points, \
         but a degree-{degree} curve has only {available}"
    )]
    ContinuityTooHigh {
        /// Order at t = 0.
        start: usize,
        /// Order at t = 1.
        end: usize,
        /// Control points the constraints fix.
        fixed: usize,
        /// Target degree.
        degree: usize,
        /// Control points of the target curve.
        available: usize,
    },
    /// A tolerance that is negative or not finite.
    #[error("tolerance {value} must be finite and >= 0")]
    InvalidTolerance {
        /// The value given.
        value: f64,
    },
    /// A caller's output buffer of the wrong length.
    #[error("output buffer has length {got}, expected {expected}")]
    BufferSize {
        /// The length needed.
        expected: usize,
        /// The length given.
        got: usize,
    },
    /// An index outside of its range.
    #[error("{what} index {index} out of range (there are {len})")]
    IndexOutOfRange {
        /// What was indexed.
        what: &'static str,
        /// The index.
        index: usize,
        /// How many there are.
        len: usize,
    },
    /// An operation needs points of a particular dimension.
    #[error("{operation} needs points of dimension {expected}, got {got}")]
    WrongDimension {
        /// The operation.
        operation: &'static str,
        /// The dimension it needs.
        expected: usize,
        /// The dimension given.
        got: usize,
    },
    /// Two consecutive reference points coincide where the parametrization needs distinct ones.
    #[error(
        "reference points {index} and {next} coincide: chord-length and centripetal \
         parameters need distinct consecutive points (remove the duplicate or use uniform)",
        next = index + 1
    )]
    RepeatedPoint {
        /// Index of the first of the two points.
        index: usize,
    },
    /// An option value that cannot be used here.
    #[error("invalid {option}: {reason}")]
    InvalidOption {
        /// The option.
        option: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// Given parameters that are not finite and strictly increasing, or of the wrong count.
    #[error("invalid parameter {index}: {reason}")]
    InvalidParameter {
        /// Index of the offending parameter.
        index: usize,
        /// Why.
        reason: &'static str,
    },
    /// A knot vector that is not valid.
    #[error("invalid knot vector at knot {index}: {reason}")]
    InvalidKnots {
        /// Index of the offending knot.
        index: usize,
        /// Why.
        reason: &'static str,
    },
    /// A numerical computation failed (singular system, no convergence).
    #[error("numerical failure in {operation}: {reason}")]
    Numerical {
        /// The operation.
        operation: &'static str,
        /// What happened.
        reason: &'static str,
    },
}

/// Result with the library's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
