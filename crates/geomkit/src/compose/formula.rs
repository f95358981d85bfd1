//! Building the single formulas as expressions of the engine ([`crate::expr`]): the ramp (1),
//! piecewise-linear sums, and the printable [`Formula`] every construction returns.

use super::linear::AbsSum;
use super::ramp::check_width;
use crate::exact::{rational_to_f64, Rational};
use crate::expr::{Const, Format, Func, Graph, Id, Node};
use crate::{Error, Result};
use num_bigint::BigInt;
use std::collections::HashMap;

/// Denominators up to this print as exact rationals; longer ones (rationals standing for
/// irrational inputs such as cos(2π/5)) as decimals.
const MAX_DENOMINATOR: u64 = 1_000_000;

/// The engine constant for an exact rational: exact when its denominator is short (or its
/// f64 would underflow), else the nearest f64.
pub(crate) fn konst(q: &Rational) -> Const {
    let x = rational_to_f64(q);
    // A rational whose f64 would underflow stays exact: [`check_terms`] then sees it (as a
    // float it would be 0, and its term would silently vanish).
    if q.denom() <= &BigInt::from(MAX_DENOMINATOR) || x.abs() < f64::MIN_POSITIVE {
        Const::Rat(q.clone())
    } else {
        Const::Float(x)
    }
}

/// The constant node of a rational.
pub(crate) fn konst_id(g: &mut Graph, q: &Rational) -> Id {
    g.constant(konst(q))
}

/// A patch coefficient: an exact integer when it is one, else the f64 (fast: no rational
/// search for the many coefficients of large composites).
pub(crate) fn coef(g: &mut Graph, x: f64) -> Id {
    g.constant(coef_const(x))
}

/// The exact integer constant n.
pub(crate) fn int_const(n: i64) -> Const {
    Const::Rat(Rational::from_integer(n.into()))
}

/// The constant of [`coef`].
pub(crate) fn coef_const(x: f64) -> Const {
    if x.fract() == 0.0 && x.abs() < 9.0e15 {
        int_const(x as i64)
    } else {
        Const::Float(x)
    }
}

/// The engine constant of an f64 input: its short rational ([`super::simplest_rational`]) when
/// that is exact and short, else the f64 itself.
pub(crate) fn num(g: &mut Graph, x: f64) -> Id {
    match super::ramp::simplest_rational(x) {
        Some(q) => konst_id(g, &q),
        None => g.num(x),
    }
}

/// P(t, a, w) of formula (1) as an expression in the node `t`, with a and w read as short
/// rationals (exact when the inputs are decimals): `1/2 + |t - a|/(2w) - |t - a - w|/(2w)`.
/// Errors: [`Error::RampWidth`] when w <= 0, [`Error::NonFinite`] for a non-finite a.
///
/// ```
/// use geomkit::compose::ramp_expr;
/// use geomkit::expr::{Format, Graph};
/// let mut g = Graph::new();
/// let t = g.var("t");
/// let p = ramp_expr(&mut g, t, 0.0, 2.0).unwrap();
/// assert_eq!(g.eval(p, &[("t", 1.0)]).unwrap(), 0.5);
/// assert!(ramp_expr(&mut g, t, 0.0, 0.0).is_err());
/// ```
pub fn ramp_expr(g: &mut Graph, t: Id, a: f64, w: f64) -> Result<Id> {
    check_width("ramp", w)?;
    let a = super::linear::exact("ramp start", 0, a)?;
    let w = super::linear::exact("ramp width", 0, w)?;
    Ok(abs_sum_expr(g, &AbsSum::ramp(&a, &w)?, t))
}

/// An [`AbsSum`] as an expression in the node `t`: constant + slope·t + Σ c_k |t - k|.
pub fn abs_sum_expr(g: &mut Graph, f: &AbsSum, t: Id) -> Id {
    let mut terms: Vec<(Const, Id)> = Vec::new();
    let one = g.int(1);
    terms.push((konst(f.constant_term()), one));
    if !num_traits::Zero::is_zero(f.slope()) {
        terms.push((konst(f.slope()), t));
    }
    for (k, c) in f.terms() {
        let shift = konst(&-k.clone());
        let d = g.lin(&[
            (Const::Rat(Rational::from_integer(1.into())), t),
            (shift, one),
        ]);
        let a = g.abs(d);
        terms.push((konst(c), a));
    }
    g.lin(&terms)
}

/// The largest bound on the sum of the absolute values of a formula's terms that
/// [`check_terms`] accepts: half of f64::MAX, so that the rounding of a sum of terms (each
/// within the bound) cannot reach infinity either.
pub(crate) const MAX_TERMS_BOUND: f64 = f64::MAX / 2.0;

/// The largest |x| [`check_terms`] assumes for a variable whose knots run from `lo` to
/// `hi`: the knots' interval widened by its span on each side (the formula is also meant
/// for points beyond the knots, where it holds the ends), at most f64::MAX.
pub(crate) fn variable_bound(lo: f64, hi: f64) -> f64 {
    (lo.abs().max(hi.abs()) + (hi - lo)).min(f64::MAX)
}

/// What [`check_terms`] may know of nodes beyond what their terms show.
#[derive(Debug, Default)]
pub(crate) struct Hints {
    /// The node's value, and every partial sum while computing it, is at most this:
    /// x - k (one subtraction) for x in the widened domain.
    trusted: HashMap<Id, f64>,
    /// The node's value is at most this, though its terms may be larger (a ramp P is in
    /// [0, 1]; its |x - x_i|/(2w) terms are judged as usual).
    capped: HashMap<Id, f64>,
}

impl Hints {
    /// `id`, and computing it, is at most `bound` in absolute value.
    pub fn trust(&mut self, id: Id, bound: f64) {
        self.trusted.insert(id, bound);
    }

    /// `id` is at most `bound` in absolute value (its terms are judged).
    pub fn cap(&mut self, id: Id, bound: f64) {
        self.capped.insert(id, bound);
    }
}

/// Hints for [`check_terms`]: x - k and |x - k| for every knot k are at most twice the span
/// of the knots for x in the widened domain of [`variable_bound`] (the nodes the ramps and
/// the |x - x_i| sums build).
pub(crate) fn knot_hints(g: &mut Graph, x: Id, knots: &[f64], hints: &mut Hints) {
    let span = knots[knots.len() - 1] - knots[0];
    for &k in knots {
        let a = num(g, k);
        let d = g.sub(x, a);
        let abs = g.abs(d);
        hints.trust(d, 2.0 * span);
        hints.trust(abs, 2.0 * span);
    }
}

/// Where [`check_terms`] found an overflow or underflow: the node, and what happened there.
#[derive(Debug)]
pub(crate) struct TermsOverflow {
    /// The first node (in topological order) that failed.
    pub node: Id,
    /// Its coefficient, or the bound of its terms, for a message ([`Error::Overflow`]).
    pub step: String,
    /// A nonzero coefficient that underflows f64 ([`Error::Underflow`]), if that is it.
    pub underflow: Option<String>,
}

impl TermsOverflow {
    /// The error, at the place `what`.
    pub fn at(self, what: String) -> Error {
        match self.underflow {
            Some(value) => Error::Underflow { what, value },
            None => Error::Overflow {
                what,
                step: self.step,
            },
        }
    }

    /// The error, named after the first of `groups` (expressions of `g`) that holds the
    /// failing node (`name(k)` for group k), or `rest` when none does (the node joins them).
    pub fn in_groups(
        self,
        g: &Graph,
        groups: &[Vec<Id>],
        name: impl Fn(usize) -> String,
        rest: &str,
    ) -> Error {
        let what = groups
            .iter()
            .position(|roots| g.reachable(roots).binary_search(&self.node).is_ok())
            .map_or_else(|| rest.to_string(), name);
        self.at(what)
    }
}

/// The one check every single formula of this module passes before it is handed out
/// (issue 21), on the expressions `roots` of `g`, in one pass over the DAG:
/// - every constant is a finite f64: no printer ever sees inf or NaN, and no exact rational
///   beyond f64::MAX reaches a target that computes in f64 (C, GLSL, NumPy); and a normal
///   one, or zero: a nonzero constant below the smallest normal f64 keeps too few digits
///   (it comes from inputs spanning more orders of magnitude than f64 holds);
/// - where it can be bounded, the sum of the absolute values of the terms of every node
///   (with the variables within `vars`: name and largest |value|, see [`variable_bound`]) stays below
///   [`MAX_TERMS_BOUND`], so evaluating the formula in f64 on its domain cannot overflow,
///   whatever the order of the additions. `hints` give the magnitude of nodes known to be
///   smaller than their terms suggest ([`Hints`]: a ramp P is in [0, 1], |x - x_i| at most
///   twice the span of the knots: cancellation the terms cannot show); functions
///   without a bound (exp, ln, tan, a division) leave their node unbounded, and unbounded
///   nodes are not judged;
/// - no part that depends on no variable is undefined ([`Graph::undefined_constant`]:
///   `asin` of a constant beyond 1, which would make the formula NaN everywhere).
///
/// Errors: the first node that fails, with the coefficient or the bound.
pub(crate) fn check_terms(
    g: &Graph,
    roots: &[Id],
    vars: &[(&str, f64)],
    hints: &Hints,
) -> std::result::Result<(), TermsOverflow> {
    let mut bound: HashMap<Id, Option<f64>> = HashMap::new();
    let of = |bound: &HashMap<Id, Option<f64>>, id: &Id| bound.get(id).copied().flatten();
    for id in g.reachable(roots) {
        let node = g.node(id);
        let consts: Vec<&Const> = match node {
            Node::Const(c) | Node::Mul(c, _) => vec![c],
            Node::Add(c, ts) => std::iter::once(c).chain(ts.iter().map(|t| &t.0)).collect(),
            _ => Vec::new(),
        };
        if let Some(c) = consts.iter().find(|c| !c.to_f64().is_finite()) {
            return Err(TermsOverflow {
                node: id,
                step: format!("its coefficient {} overflows f64", describe_const(c)),
                underflow: None,
            });
        }
        if let Some(c) = consts
            .iter()
            .find(|c| !c.is_zero() && c.to_f64().abs() < f64::MIN_POSITIVE)
        {
            return Err(TermsOverflow {
                node: id,
                step: String::new(),
                underflow: Some(approximately(c)),
            });
        }
        // The bound of the node, and the partial bounds the evaluation meets on the way
        // (known terms of a sum, the constant and the positive powers of a product, each of
        // which the tape computes whole): all must stay below MAX_TERMS_BOUND.
        let mut partial = Vec::new();
        let b = match node {
            Node::Const(c) => Some(c.to_f64().abs()),
            Node::Pi => Some(std::f64::consts::PI),
            Node::Var(name) => vars.iter().find(|(v, _)| **v == **name).map(|v| v.1),
            Node::Add(c, ts) => {
                let mut known = c.to_f64().abs();
                let mut all = true;
                for (k, t) in ts.iter() {
                    match of(&bound, t) {
                        Some(b) => known += k.to_f64().abs() * b,
                        None => all = false,
                    }
                }
                partial.push(known);
                all.then_some(known)
            }
            Node::Mul(c, fs) => {
                let mut constant = c.to_f64().abs();
                let mut powers = 1.0f64;
                let mut all = true;
                for &(t, e) in fs.iter() {
                    match (g.node(t), of(&bound, &t)) {
                        (Node::Const(_) | Node::Pi, Some(b)) => constant *= b.powi(e),
                        (_, Some(b)) if e > 0 => powers *= b.powi(e),
                        _ => all = false,
                    }
                }
                partial.extend([constant, powers]);
                all.then_some(constant * powers)
            }
            Node::Fun(f, a) => of(&bound, a).and_then(|b| match f {
                Func::Abs => Some(b),
                Func::Sqrt => Some(b.sqrt()),
                Func::Sign | Func::Sin | Func::Cos | Func::Tanh => Some(1.0),
                Func::Atan | Func::Asin => Some(std::f64::consts::FRAC_PI_2),
                Func::Acos => Some(std::f64::consts::PI),
                _ => None,
            }),
        };
        if let Some(b) = b
            .into_iter()
            .chain(partial)
            .find(|b| b.is_nan() || *b >= MAX_TERMS_BOUND)
        {
            return Err(TermsOverflow {
                node: id,
                step: format!(
                    "the absolute values of its terms add up to {b:.3e} on its domain (a span \
                     beyond the knots included), above f64::MAX/2: evaluating it could \
                     overflow f64"
                ),
                underflow: None,
            });
        }
        let b = match (b, hints.capped.get(&id)) {
            (Some(b), Some(&h)) => Some(b.min(h)),
            (None, Some(&h)) => Some(h),
            (b, None) => b,
        };
        bound.insert(id, b);
    }
    if let Some(node) = g.undefined_constant(roots) {
        return Err(TermsOverflow {
            node,
            step: format!(
                "it evaluates to {} whatever the variables (a function of a constant outside \
                 its domain)",
                g.eval(node, &[]).unwrap_or(f64::NAN)
            ),
            underflow: None,
        });
    }
    Ok(())
}

/// A constant for a message, approximately, also beyond the range of f64: "5.000e-608".
fn approximately(c: &Const) -> String {
    match c {
        Const::Rat(r) if !num_traits::Zero::is_zero(r) => {
            // r = m 10^e with m in [1, 10): e from the digits, m from r / 10^e in f64.
            let digits = |x: &BigInt| x.to_string().trim_start_matches('-').len() as i32;
            let mut e = digits(r.numer()) - digits(r.denom());
            let ten = |k: i32| BigInt::from(10).pow(k.unsigned_abs());
            let scaled = |e: i32| {
                if e >= 0 {
                    r / Rational::from_integer(ten(e))
                } else {
                    r * Rational::from_integer(ten(e))
                }
            };
            let mut m = rational_to_f64(&scaled(e));
            if m.abs() < 1.0 {
                e -= 1;
                m = rational_to_f64(&scaled(e));
            }
            format!("{m:.3}e{e}")
        }
        c => format!("{:e}", c.to_f64()),
    }
}

/// A constant for a message: its f64 value, or the size of an exact rational too large for
/// f64.
fn describe_const(c: &Const) -> String {
    match c {
        Const::Rat(r) if r.to_string().len() > 40 => format!(
            "{} (an exact number of {} digits, beyond f64)",
            c.to_f64(),
            r.numer().to_string().trim_start_matches('-').len()
        ),
        c => format!("{}", c.to_f64()),
    }
}

/// A single formula: named coordinate expressions in a graph of their own, over variables.
///
/// ```
/// use geomkit::compose::bodies;
/// let f = bodies::cube().unwrap().formula().unwrap();
/// assert_eq!(f.names, vec!["x", "y", "z"]);
/// assert!(f.print(geomkit::expr::Format::Maple).unwrap().starts_with("x := (u, v) -> "));
/// ```
#[derive(Debug, Clone)]
pub struct Formula {
    /// The graph holding the expressions.
    pub graph: Graph,
    /// One expression per coordinate.
    pub roots: Vec<Id>,
    /// Coordinate names (`x`, `y`, `z`; `z` for explicit surfaces; `f` for functions).
    pub names: Vec<String>,
    /// Variables, in order (`u`, `v`; `x`, `y`; `t`; `x`).
    pub vars: Vec<String>,
}

impl Formula {
    /// Operations in the DAG after sharing (the engine's [`Graph::op_count`]).
    pub fn op_count(&self) -> usize {
        self.graph.op_count(&self.roots)
    }

    /// One definition per coordinate in format `f`, as the target accepts it pasted
    /// (Maple `x := (u, v) -> ...;`, Mathematica `x[u_, v_] := ...`, C `double x(double u,
    /// double v) { return ...; }`, ...: [`Graph::print_definition`]), after the lines the
    /// target needs first (SymPy's import and symbols, NumPy's import, C's `<math.h>`).
    /// Inline: shared subexpressions are repeated; see [`Formula::print_program`] for
    /// temporaries. Errors: [`Error::Expression`] naming the coordinate for a constant the
    /// target cannot hold or a text longer than [`crate::expr::MAX_PRINT_BYTES`]
    /// ([`Graph::print_definition`]).
    pub fn print(&self, f: Format) -> Result<String> {
        let vars: Vec<&str> = self.vars.iter().map(String::as_str).collect();
        let mut out = self.graph.print_preamble(&vars, f);
        for (name, &root) in self.names.iter().zip(&self.roots) {
            let text = self
                .graph
                .print_definition(name, &vars, root, f)
                .map_err(|e| Error::expression(format!("coordinate {name}"), e))?;
            out.push_str(&text);
            out.push('\n');
        }
        Ok(out)
    }

    /// The formula as a program with common subexpressions in temporaries, in format `f`.
    /// Errors: as [`Formula::print`] ([`Graph::print_program`]).
    pub fn print_program(&self, f: Format) -> Result<String> {
        let outputs: Vec<(&str, Id)> = self
            .names
            .iter()
            .map(String::as_str)
            .zip(self.roots.iter().copied())
            .collect();
        self.graph
            .print_program(&outputs, f)
            .map_err(|e| Error::expression("formula".into(), e))
    }

    /// Evaluates every coordinate at points given per variable (`inputs[k][i]`: variable k
    /// at point i) into `out` (point-major, `names.len()` numbers per point), by the engine's
    /// batched tape. Errors: [`Error::Expression`] for the engine's errors (shapes).
    pub fn eval_batch(&self, inputs: &[&[f64]], out: &mut [f64]) -> Result<()> {
        let vars: Vec<&str> = self.vars.iter().map(String::as_str).collect();
        let tape = crate::expr::Tape::new(&self.graph, &self.roots, &vars)
            .map_err(|e| Error::expression("formula".into(), e))?;
        let n = inputs.first().map_or(0, |x| x.len());
        let d = self.roots.len();
        if out.len() != n * d {
            return Err(Error::BufferSize {
                expected: n * d,
                got: out.len(),
            });
        }
        let mut cols = vec![vec![0.0; n]; d];
        {
            let mut refs: Vec<&mut [f64]> = cols.iter_mut().map(Vec::as_mut_slice).collect();
            tape.eval_batch(inputs, &mut refs)
                .map_err(|e| Error::expression("formula".into(), e))?;
        }
        for (i, p) in out.chunks_exact_mut(d).enumerate() {
            for k in 0..d {
                p[k] = cols[k][i];
            }
        }
        Ok(())
    }
}
