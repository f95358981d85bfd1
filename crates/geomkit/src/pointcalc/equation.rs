//! Point equations of curves M(t) = Σ_i f_i(t) A_i (spec/point-calculus.md §2, equations
//! (1)-(3) and their generalization to any nodes and any number of source points).
//!
//! The function-parameters f_i are the cardinal functions of the nodes ([`Nodes`]); they sum
//! to 1, so the equation does not depend on the coordinate system, and f_i(t) is the share of
//! source point A_i in the point M(t).
//!
//! ```
//! use geomkit::geom::Curve;
//! use geomkit::pointcalc::{Nodes, PointEquation};
//! // Equation (2): C at t = 1/3.
//! let eq = PointEquation::new(Nodes::paper_third(), vec![
//!     vec![0.0, 0.0], vec![1.0, 2.0], vec![3.0, 0.0],
//! ]).unwrap();
//! assert_eq!(eq.eval(1.0 / 3.0), vec![1.0, 2.0]); // passes through C exactly
//! let shares = eq.shares(0.5);
//! assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-15);
//! ```

use super::nodes::Nodes;
use super::wide::{combine_wide, short};
use crate::exact::Rational;
use crate::geom::{check_point, BatchOptions, Curve};
use crate::points::{check_eval_args, flatten_points, validate_points};
use crate::{Error, Result};

/// How node sets with a large Lebesgue constant are treated.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[non_exhaustive]
pub struct PointOptions {
    /// The Lebesgue limit; `None`: [`Nodes::default_lebesgue_limit`].
    pub lebesgue_limit: Option<f64>,
    /// Error ([`Error::LebesgueTooLarge`]) instead of a warning above the limit.
    pub strict: bool,
}

impl PointOptions {
    /// Sets the Lebesgue limit.
    pub fn with_lebesgue_limit(mut self, limit: f64) -> Self {
        self.lebesgue_limit = Some(limit);
        self
    }

    /// Errors instead of warning when the Lebesgue constant is above the limit.
    pub fn with_strict(mut self, strict: bool) -> Self {
        self.strict = strict;
        self
    }
}

/// A warning attached to a result: it was built, but the user should know.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Warning {
    /// The Lebesgue constant of a node set is large: the interpolant can oscillate between
    /// the nodes and amplifies errors in the source points up to this factor.
    LargeLebesgue {
        /// Which node set ("nodes", "factor b", "row 2").
        what: String,
        /// The estimated Lebesgue constant.
        value: f64,
        /// The limit.
        limit: f64,
    },
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Warning::LargeLebesgue { what, value, limit } => write!(
                f,
                "the Lebesgue constant of {what} is {} (limit {}): the interpolant may \
                 oscillate between nodes; Chebyshev nodes avoid this",
                super::lebesgue_text(*value),
                super::lebesgue_text(*limit)
            ),
        }
    }
}

/// Checks a node set's Lebesgue constant against the options: `Ok(None)` below the limit, a
/// warning above it, an error above it when strict.
pub(crate) fn check_lebesgue(
    what: &str,
    nodes: &Nodes,
    options: &PointOptions,
) -> Result<Option<Warning>> {
    let limit = options
        .lebesgue_limit
        .unwrap_or_else(|| nodes.default_lebesgue_limit());
    if !limit.is_finite() || limit < 1.0 {
        return Err(Error::InvalidOption {
            option: "Lebesgue limit",
            reason: "must be finite and >= 1",
        });
    }
    // 3 nodes: closed form-free but cheap; large sets only when they could exceed the limit.
    let value = nodes.lebesgue_constant();
    if value <= limit {
        return Ok(None);
    }
    if options.strict {
        return Err(Error::LebesgueTooLarge {
            what: what.into(),
            value,
            limit,
        });
    }
    Ok(Some(Warning::LargeLebesgue {
        what: what.into(),
        value,
        limit,
    }))
}

/// A point equation of a curve through source points A_i at nodes t_i.
#[derive(Debug, Clone, PartialEq)]
pub struct PointEquation {
    nodes: Nodes,
    dim: usize,
    points: Vec<f64>,
    warnings: Vec<Warning>,
}

impl PointEquation {
    /// The equation through `points` (one per node, any dimension) with default options.
    /// Errors: mixed dimensions, non-finite coordinates, a point count different from the
    /// node count.
    pub fn new(nodes: Nodes, points: Vec<Vec<f64>>) -> Result<Self> {
        PointEquation::with_options(nodes, points, &PointOptions::default())
    }

    /// As [`PointEquation::new`], with options (Lebesgue limit and strictness).
    pub fn with_options(
        nodes: Nodes,
        points: Vec<Vec<f64>>,
        options: &PointOptions,
    ) -> Result<Self> {
        let (dim, data) = flatten_points("source points", &points)?;
        PointEquation::from_flat(nodes, dim, data, options)
    }

    /// From row-major points of dimension `dim`.
    pub fn from_flat(
        nodes: Nodes,
        dim: usize,
        points: Vec<f64>,
        options: &PointOptions,
    ) -> Result<Self> {
        validate_points("source points", dim, &points)?;
        if points.len() / dim != nodes.len() {
            return Err(Error::PointCount {
                what: "source points".into(),
                expected: nodes.len(),
                got: points.len() / dim,
            });
        }
        let warnings = check_lebesgue("nodes", &nodes, options)?
            .into_iter()
            .collect();
        Ok(PointEquation {
            nodes,
            dim,
            points,
            warnings,
        })
    }

    /// The nodes.
    pub fn nodes(&self) -> &Nodes {
        &self.nodes
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Source point i.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.points[i * self.dim..(i + 1) * self.dim]
    }

    /// All source points, row-major.
    pub fn points_flat(&self) -> &[f64] {
        &self.points
    }

    /// Warnings found when building (a large Lebesgue constant).
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The parameter interval spanned by the nodes.
    pub fn domain(&self) -> (f64, f64) {
        self.nodes.domain()
    }

    /// The function-parameters f_i(t): the share of every source point in M(t); they sum to
    /// 1 (within rounding; exactly one 1 at a node).
    pub fn shares(&self, t: f64) -> Vec<f64> {
        self.nodes.basis(t)
    }

    /// The exact function-parameters at an exact parameter (exact rationals of the exact node
    /// positions); they sum to exactly 1.
    pub fn exact_shares(&self, t: &Rational) -> Vec<Rational> {
        self.nodes.basis_exact(t)
    }

    fn combine(&self, weights: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (w, p) in weights.iter().zip(self.points.chunks_exact(self.dim)) {
            for (o, x) in out.iter_mut().zip(p) {
                *o += w * x;
            }
        }
    }

    /// M(t) again where the plain evaluation did not give finite numbers (source points
    /// near f64::MAX whose partial sums overflow, or t far outside the nodes): shares as
    /// mantissas with one exponent, points scaled by a power of two, the sum scaled back
    /// last. ±infinity only where M(t) itself is beyond f64.
    fn eval_wide(&self, t: f64, out: &mut [f64]) {
        let mut l = vec![0.0; self.nodes.len()];
        let e = self.nodes.basis_wide(t, &mut l);
        combine_wide(&l, e, &self.points, out);
    }

    /// The first derivative dM/dt at `t`.
    pub fn derivative(&self, t: f64) -> Vec<f64> {
        self.derivatives(t)[1].clone()
    }

    /// The second derivative d²M/dt² at `t`.
    pub fn second_derivative(&self, t: f64) -> Vec<f64> {
        self.derivatives(t)[2].clone()
    }

    /// [M(t), M'(t), M''(t)] (Schneider–Werner barycentric derivatives, see
    /// [`Nodes::basis_derivatives`]).
    pub fn derivatives(&self, t: f64) -> [Vec<f64>; 3] {
        let n = self.nodes.len();
        let (mut l, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        self.nodes
            .basis_derivatives(t, &mut l, &mut d1, Some(&mut d2));
        let mut out = [
            vec![0.0; self.dim],
            vec![0.0; self.dim],
            vec![0.0; self.dim],
        ];
        self.combine(&l, &mut out[0]);
        self.combine(&d1, &mut out[1]);
        self.combine(&d2, &mut out[2]);
        out
    }

    /// Evaluates at every parameter of `ts` into `out` (`ts.len() * dim`), the nodes' basis
    /// buffer reused: the values of [`Curve::eval_into`]. Errors: wrong buffer length, a
    /// non-finite parameter; [`Error::ResultOverflow`] naming the first point beyond f64 (a
    /// parameter far outside the nodes, or source points near f64::MAX).
    pub fn eval_params(&self, ts: &[f64], out: &mut [f64]) -> Result<()> {
        check_eval_args("parameter", ts, ts.len(), self.dim, out)?;
        self.fill(ts, out);
        self.check_finite(ts, out)
    }

    /// M(t) at every parameter into `out` (checked lengths, finite parameters): the values of
    /// [`Curve::eval_into`], ±infinity where M(t) is beyond f64.
    fn fill(&self, ts: &[f64], out: &mut [f64]) {
        let mut l = vec![0.0; self.nodes.len()];
        for (t, o) in ts.iter().zip(out.chunks_exact_mut(self.dim)) {
            self.nodes.basis_into(*t, &mut l);
            self.combine(&l, o);
            if o.iter().any(|x| !x.is_finite()) {
                self.eval_wide(*t, o);
            }
        }
    }

    /// [`Error::ResultOverflow`] naming the first parameter whose point is not finite.
    fn check_finite(&self, ts: &[f64], out: &[f64]) -> Result<()> {
        match out
            .chunks_exact(self.dim)
            .position(|o| o.iter().any(|x| !x.is_finite()))
        {
            Some(i) => Err(Error::ResultOverflow {
                what: format!("the point of the curve at t={}", short(ts[i])),
            }),
            None => Ok(()),
        }
    }
}

/// M(t) = Σ f_i(t) A_i of spec/point-calculus.md §2 over the node interval.
impl Curve for PointEquation {
    fn dim(&self) -> usize {
        self.dim
    }

    /// The node interval.
    fn domain(&self) -> (f64, f64) {
        PointEquation::domain(self)
    }

    /// M(t) = Σ f_i(t) A_i; at a node exactly its source point. Where the plain sum leaves
    /// the f64 range it is computed again with the points scaled by a power of two (so the
    /// result is ±infinity only where M(t) itself is beyond f64, never NaN).
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        let n = self.nodes.len();
        if n <= 16 {
            let mut l = [0.0; 16];
            self.nodes.basis_into(t, &mut l[..n]);
            self.combine(&l[..n], out);
        } else {
            let l = self.nodes.basis(t);
            self.combine(&l, out);
        }
        if out.iter().any(|x| !x.is_finite()) {
            self.eval_wide(t, out);
        }
    }

    /// Every order: the cardinal functions' derivatives (barycentric formulas for orders 1
    /// and 2, as [`PointEquation::derivatives`]; powers of the differentiation matrix above),
    /// Σ f_i^(k)(t) A_i; the zero vector from order n on (a polynomial of degree n - 1).
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim, out)?;
        if order == 0 {
            self.eval_into(t, out);
        } else {
            self.combine(&self.nodes.basis_derivative(t, order), out);
        }
        Ok(())
    }

    /// [`PointEquation::eval_params`] (the basis buffer reused), in parallel chunks for
    /// large batches: the values of [`Curve::eval_into`], bit for bit. Errors as
    /// [`PointEquation::eval_params`] ([`Error::ResultOverflow`] for a point beyond f64).
    fn eval_batch(&self, ts: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        check_eval_args("parameter", ts, ts.len(), self.dim, out)?;
        let parallel = options.parallel() && ts.len() > 4096;
        crate::par::zip_chunks(parallel, out, 4096 * self.dim, ts, 4096, |o, t| {
            self.fill(t, o)
        });
        self.check_finite(ts, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pointcalc::NodePreset;

    #[test]
    fn passes_through_points_exactly() {
        let eq = PointEquation::new(
            Nodes::paper_two_thirds(),
            vec![
                vec![0.1, 0.2, 0.3],
                vec![1.7, -2.0, 0.0],
                vec![3.0, 1.0, 1e-300],
            ],
        )
        .unwrap();
        for (i, t) in eq.nodes().values().to_vec().into_iter().enumerate() {
            assert_eq!(eq.eval(t), eq.point(i));
        }
    }

    #[test]
    fn warns_and_errors_on_large_lebesgue() {
        let nodes = Nodes::preset(NodePreset::Equispaced, 12, 0.0, 1.0).unwrap();
        let pts: Vec<Vec<f64>> = (0..12).map(|i| vec![i as f64]).collect();
        let eq = PointEquation::new(nodes.clone(), pts.clone()).unwrap();
        assert!(matches!(eq.warnings()[0], Warning::LargeLebesgue { value, .. } if value > 50.0));
        let strict = PointOptions::default().with_strict(true);
        assert!(matches!(
            PointEquation::with_options(nodes, pts, &strict),
            Err(Error::LebesgueTooLarge { .. })
        ));
        let cheb = Nodes::preset(NodePreset::ChebyshevFirst, 12, 0.0, 1.0).unwrap();
        let pts: Vec<Vec<f64>> = (0..12).map(|i| vec![i as f64]).collect();
        assert!(PointEquation::new(cheb, pts).unwrap().warnings().is_empty());
    }

    #[test]
    fn rejects_wrong_counts() {
        let e = PointEquation::new(Nodes::paper_half(), vec![vec![0.0], vec![1.0]]);
        assert!(matches!(
            e,
            Err(Error::PointCount {
                expected: 3,
                got: 2,
                ..
            })
        ));
        let e = PointEquation::new(
            Nodes::paper_half(),
            vec![vec![0.0], vec![1.0], vec![f64::NAN]],
        );
        assert!(matches!(e, Err(Error::NonFinite { index: 2, .. })));
    }
}
