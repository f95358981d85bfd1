//! The library's one error type.

use geomkit_expr::{ExprError, ParseError};
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
    /// A row of a rational surface's weights whose length is not the net's row length.
    #[error("row {row} of the weights has {got} weights for {expected} control points")]
    WeightRow {
        /// The row index i.
        row: usize,
        /// The net's row length.
        expected: usize,
        /// The length of this row of weights.
        got: usize,
    },
    /// A weight of a rational surface's net that is not strictly positive.
    #[error("weight ({row}, {col}) of the net is {value}; weights must be finite and > 0")]
    InvalidNetWeight {
        /// Its row i.
        row: usize,
        /// Its column j.
        col: usize,
        /// Its value.
        value: f64,
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
    /// A request whose work or memory exceeds a documented limit (refused before starting).
    #[error("{what}: the {unit} {size} is above the limit of {limit}")]
    TooLarge {
        /// What was asked, with its numbers (e.g. "elevating degree 1000 to 999999").
        what: String,
        /// The size it would take.
        size: u128,
        /// What `size` counts ("weight count", "degree").
        unit: &'static str,
        /// The limit.
        limit: u128,
    },
    /// An option value that cannot be used here.
    #[error("invalid {option}: {reason}")]
    InvalidOption {
        /// The option.
        option: &'static str,
        /// Why.
        reason: &'static str,
    },
    /// Interpolation data, knots or end conditions that do not make an interpolating spline
    /// (the cases of SciPy's `make_interp_spline`, worded so that its phrases appear: "Shapes
    /// of x", "x to not have duplicates", "Expect x to be a 1D strictly increasing
    /// sequence", "The number of derivatives at boundaries does not match"), with what to
    /// change.
    #[error("{reason}")]
    Interpolation {
        /// What is wrong, where, and what to change.
        reason: String,
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
    /// A ramp width w of P(t, a, w) (spec/composite-surfaces.md formula (1)) that is not > 0.
    #[error("ramp width w = {value} of {what} must be finite and > 0")]
    RampWidth {
        /// Where the width came from ("ramp", "knot interval 3", ...).
        what: String,
        /// The width given.
        value: f64,
    },
    /// A grid of patches (or a list of pieces) of the wrong size.
    #[error("{what}: expected {expected}, got {got}")]
    PatchCount {
        /// What was counted ("patch rows", "patches in row 2", "pieces").
        what: String,
        /// How many the knots call for.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// A number of a single-formula construction (spec/composite-surfaces.md) that overflows
    /// f64: a coefficient, a sum of jumps, a bound on the formula's terms. The inputs are
    /// too near the end of the f64 range for the formula to be written or evaluated.
    #[error("{what}: {step}")]
    Overflow {
        /// Where ("patch (1, 0)", "piece 2", "u knots 0 and 1 (0 and 1e-310)").
        what: String,
        /// What overflowed, and why ("its power-basis coefficients overflow f64: ...").
        step: String,
    },
    /// A nonzero coefficient of a single formula that underflows f64 (a subnormal number or
    /// zero: it would keep too few digits, or none), from inputs spanning more orders of
    /// magnitude than f64 holds (values near 1e-300 over knots near 1e300).
    #[error(
        "{what}: its coefficient {value} underflows f64 (nonzero, below the smallest normal \
         f64 2.2e-308, it keeps too few digits or none)"
    )]
    Underflow {
        /// Where, as for [`Error::Overflow`].
        what: String,
        /// The coefficient, approximately ("5.000e-608").
        value: String,
    },
    /// A formula that does not parse or evaluate, with the place of the problem.
    ///
    /// For a formula that does not parse (or names a variable it may not use), `parse` holds
    /// the engine's structured error: the byte span of the mistake in that formula's text,
    /// its kind and what was expected, for an editor to underline. It is a field rather than
    /// the error's `source()` because the message already says it: a cause chain printed
    /// with `{:#}` would say it twice.
    ///
    /// ```
    /// use geomkit::compose::ExprPatch;
    /// use geomkit::expr::ParseErrorKind;
    /// use geomkit::Error;
    /// let z = "sin(x) * (y + 1";
    /// let err = ExprPatch::parse(&[("z", z)], &["x", "y"], None).unwrap_err();
    /// assert_eq!(
    ///     err.to_string(),
    ///     "coordinate z: parse error at byte 15: expected `)`, found end of input"
    /// );
    /// let Error::Expression { what, parse: Some(e), .. } = &err else { panic!("{err}") };
    /// assert_eq!(what, "coordinate z");
    /// assert_eq!(e.span, 15..15);
    /// assert!(matches!(e.kind, ParseErrorKind::UnclosedParen { open: 9, .. }));
    /// assert_eq!(err.parse_error().map(|e| e.column), Some(16));
    /// ```
    #[error("{what}: {message}")]
    Expression {
        /// Which formula ("patch \[1\]\[0\] x", "piece 2").
        what: String,
        /// The expression engine's message (with the position); for a parse error, the
        /// Display of `parse`.
        message: String,
        /// The parse error with its span in the formula's text, if the formula did not
        /// parse; `None` for an error of evaluation (a value that is not finite, a shape).
        parse: Option<Box<ParseError>>,
    },
    /// Parameters of a shape that do not make one (a size <= 0, a self-intersecting polygon).
    #[error("invalid {what}: {reason}")]
    InvalidShape {
        /// The shape or parameter ("box size", "polygon").
        what: &'static str,
        /// Why.
        reason: String,
    },
    /// A numerical computation failed (singular system, no convergence).
    #[error("numerical failure in {operation}: {reason}")]
    Numerical {
        /// The operation.
        operation: &'static str,
        /// What happened.
        reason: &'static str,
    },
    /// Interpolation nodes that are not finite and strictly increasing (spec/point-calculus.md).
    #[error("invalid node {index} of {what}: {reason}")]
    InvalidNodes {
        /// Which node set ("nodes", "factor b", "row 2").
        what: String,
        /// Index of the offending node.
        index: usize,
        /// Why.
        reason: &'static str,
    },
    /// A node set whose Lebesgue constant exceeds the limit (interpolation amplifies data
    /// errors by up to that factor), when strictness was asked for.
    #[error(
        "the Lebesgue constant of {what} is {}, above the limit {} \
         (use Chebyshev nodes, fewer nodes, or a larger limit)",
        crate::pointcalc::lebesgue_text(*value),
        crate::pointcalc::lebesgue_text(*limit)
    )]
    LebesgueTooLarge {
        /// Which node set.
        what: String,
        /// The estimated Lebesgue constant.
        value: f64,
        /// The limit.
        limit: f64,
    },
    /// Experimental records that do not form a full grid of factor levels.
    #[error("record {record}: {reason}")]
    GridRecord {
        /// Index of the record (0-based, in the order given).
        record: usize,
        /// What is wrong.
        reason: String,
    },
    /// Experimental records that leave cells of the grid of factor levels empty.
    #[error(
        "the factor levels do not form a grid: no record for {cell} ({missing} cells missing)"
    )]
    MissingCell {
        /// The first missing cell ("a=1, b=2").
        cell: String,
        /// How many cells are missing.
        missing: usize,
    },
    /// A number of source points (or values) that does not match the nodes.
    #[error("{what}: {got} given, the nodes need {expected}")]
    PointCount {
        /// What was counted ("points", "points of row 2", "values").
        what: String,
        /// How many the nodes need.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// A factor name that the model does not have.
    #[error("unknown factor '{name}'")]
    UnknownFactor {
        /// The name given.
        name: String,
    },
    /// A result (or a step of its computation that cannot be avoided) whose magnitude is
    /// beyond f64 (about 1.8e308): refused rather than returned as an infinity or NaN.
    #[error("{what} overflows f64 (its magnitude is beyond 1.8e308)")]
    ResultOverflow {
        /// The result or step, with where ("the share of point 3 (a=0, b=1) at a=1e308, b=0").
        what: String,
    },
    /// A result whose rounding error bound exceeds both the result and the scale of the
    /// data (extrapolating far outside the nodes): it would have no correct digit.
    #[error(
        "{what} is lost to rounding: this far outside the nodes the interpolant amplifies \
         rounding errors to {}, more than the result itself (evaluate closer to the \
         nodes' span)",
        crate::pointcalc::magnitude_text(*error)
    )]
    LostToRounding {
        /// The result, with where.
        what: String,
        /// The bound of its rounding error.
        error: f64,
    },
    /// A count above a documented limit (nodes per node set, cells of a grid, ...).
    #[error("too many {what}: {got}, at most {max}")]
    TooMany {
        /// What was counted.
        what: &'static str,
        /// How many were asked for (`usize::MAX` when the count itself overflows).
        got: usize,
        /// The limit.
        max: usize,
    },
    /// A derivative that a curve or surface type cannot give (see
    /// [`crate::geom::Curve::derivative_into`] and [`crate::geom::Surface::derivative_into`]).
    #[error("the derivative of order {order} of {what} is not available: {reason}")]
    UnsupportedDerivative {
        /// The type ("this curve" for the trait's default, ...).
        what: &'static str,
        /// The order asked for: "3" for a curve, "(1, 2)" for ∂³/∂u∂v² of a surface.
        order: String,
        /// Why, and what the type can give instead.
        reason: &'static str,
    },
    /// A derivative order a B-spline operation does not take: above the degree for a
    /// derivative curve (SciPy's `BSpline.derivative`), or not below the degree in a
    /// direction for FITPACK's surface derivatives (SciPy's `RectBivariateSpline`).
    #[error("derivative order {order} of a B-spline of degree {degree}: {reason}")]
    DerivativeOrder {
        /// The order asked for.
        order: usize,
        /// The degree (in the direction concerned).
        degree: usize,
        /// Which rule, and what gives the other orders.
        reason: &'static str,
    },
    /// A B-spline whose knots make a derivative curve of the order asked jump by a Dirac
    /// delta (SciPy's `splder` refuses these too: "not differentiable n times").
    #[error(
        "the B-spline is not differentiable {order} times: knot {index} is repeated \
         {multiplicity} times, where a derivative of order {order} allows at most \
         degree + 1 - order = {allowed}",
        allowed = degree + 1 - order
    )]
    NotDifferentiable {
        /// The derivative order asked for.
        order: usize,
        /// The degree of the B-spline.
        degree: usize,
        /// Index of the first of the coinciding knots.
        index: usize,
        /// How many knots coincide there.
        multiplicity: usize,
    },
    /// A knot that cannot be inserted into a B-spline (SciPy's `BSpline.insert_knot`).
    #[error("cannot insert a knot at {x}: {reason}")]
    KnotInsertion {
        /// The knot asked for.
        x: f64,
        /// Why.
        reason: &'static str,
    },
    /// Adaptive meshing reached its work cap (triangles, points or grid lines) before the
    /// requested tolerance: `reached` is the largest deviation measured at the cap.
    #[error(
        "tolerance {tolerance:e} is out of reach within {cap}: the finest mesh within the cap \
         deviates up to {reached:.2e} from the model; ask for a tolerance of at least {reached:.2e}"
    )]
    ToleranceOutOfReach {
        /// The tolerance asked for.
        tolerance: f64,
        /// The largest deviation (model units) at the checks when the cap stopped refinement.
        reached: f64,
        /// The cap ("2000000 triangles").
        cap: String,
    },
    /// A meshing tolerance below the resolution of f64 at the model's size: no mesh can be
    /// checked to it.
    #[error(
        "tolerance {tolerance:e} is below what f64 coordinates resolve at this model's size \
         (about {resolution:.1e}): no mesh can be checked to it"
    )]
    ToleranceBelowResolution {
        /// The tolerance asked for.
        tolerance: f64,
        /// The smallest deviation the model's coordinates can show.
        resolution: f64,
    },
    /// A mesh or polyline that would exceed its size cap.
    #[error("{what} gives {count} {unit}, above the cap of {max}")]
    MeshTooLarge {
        /// What was asked ("a 4000 × 4000 sample grid").
        what: String,
        /// How many it gives.
        count: usize,
        /// "triangles" or "points".
        unit: &'static str,
        /// The cap.
        max: usize,
    },
    /// A mesh that cannot keep its promises: empty, or a closed surface whose mesh leaks.
    #[error("the mesh is {check}: {reason}")]
    MeshFailed {
        /// What failed ("empty", "not watertight").
        check: &'static str,
        /// Why, with the numbers.
        reason: String,
    },
    /// A long job stopped because its progress callback asked it to
    /// ([`crate::progress::Progress`]); nothing was returned.
    #[error("cancelled")]
    Cancelled,
    /// An error of the expression engine (parse error with its position, unknown
    /// variable, division by exact zero, ...).
    #[error(transparent)]
    Expr(#[from] ExprError),
}

impl Error {
    /// The structured parse error inside, if this is one: a formula that does not parse
    /// ([`Error::Expression`] with `parse`, or [`Error::Expr`] of a parse error). Its span
    /// is a byte range of that formula's text.
    pub fn parse_error(&self) -> Option<&ParseError> {
        match self {
            Error::Expression { parse, .. } => parse.as_deref(),
            Error::Expr(ExprError::Parse(e)) => Some(e),
            _ => None,
        }
    }

    /// An [`Error::Expression`] of the formula `what` from an engine error, keeping a parse
    /// error's structure.
    pub(crate) fn expression(what: String, e: ExprError) -> Self {
        match e {
            ExprError::Parse(p) => Error::Expression {
                what,
                message: p.to_string(),
                parse: Some(p),
            },
            e => Error::Expression {
                what,
                message: e.to_string(),
                parse: None,
            },
        }
    }
}

/// Result with the library's [`enum@Error`].
pub type Result<T> = std::result::Result<T, Error>;
