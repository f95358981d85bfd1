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

/// The engine constant for an exact rational: exact when its denominator is short, else the
/// nearest f64.
pub(crate) fn konst(q: &Rational) -> Const {
    if q.denom() <= &BigInt::from(MAX_DENOMINATOR) {
        Const::Rat(q.clone())
    } else {
        Const::Float(rational_to_f64(q))
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

/// Where [`check_terms`] found an overflow: the node, and what overflowed there.
#[derive(Debug)]
pub(crate) struct TermsOverflow {
    /// The first node (in topological order) that failed.
    pub node: Id,
    /// Its coefficient, or the bound of its terms, for a message.
    pub step: String,
}

impl TermsOverflow {
    /// The error, at the place `what`.
    pub fn at(self, what: String) -> Error {
        Error::Overflow {
            what,
            step: self.step,
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
///   beyond f64::MAX reaches a target that computes in f64 (C, GLSL, NumPy);
/// - where it can be bounded, the sum of the absolute values of the terms of every node
///   (with the variables within `vars`: name and largest |value| on the domain) stays below
///   [`MAX_TERMS_BOUND`], so evaluating the formula in f64 on its domain cannot overflow,
///   whatever the order of the additions. `hints` give the magnitude of nodes known to be
///   smaller than their terms suggest (a ramp P is in [0, 1], |x - x_i| at most the span of
///   the knots: cancellation the terms cannot show), not judged themselves; functions
///   without a bound (exp, ln, tan, a division) leave their node unbounded, and unbounded
///   nodes are not judged.
///
/// Errors: the first node that fails, with the coefficient or the bound.
pub(crate) fn check_terms(
    g: &Graph,
    roots: &[Id],
    vars: &[(&str, f64)],
    hints: &HashMap<Id, f64>,
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
        if let Some(c) = consts.into_iter().find(|c| !c.to_f64().is_finite()) {
            return Err(TermsOverflow {
                node: id,
                step: format!("its coefficient {}", describe_const(c)),
            });
        }
        let b = match node {
            Node::Const(c) => Some(c.to_f64().abs()),
            Node::Pi => Some(std::f64::consts::PI),
            Node::Var(name) => vars.iter().find(|(v, _)| **v == **name).map(|v| v.1),
            Node::Add(c, ts) => ts.iter().try_fold(c.to_f64().abs(), |acc, (k, t)| {
                of(&bound, t).map(|b| acc + k.to_f64().abs() * b)
            }),
            Node::Mul(c, fs) => fs.iter().try_fold(c.to_f64().abs(), |acc, &(t, e)| {
                let b = of(&bound, &t)?;
                (e > 0).then(|| acc * b.powi(e))
            }),
            Node::Fun(f, a) => of(&bound, a).and_then(|b| match f {
                Func::Abs => Some(b),
                Func::Sqrt => Some(b.sqrt()),
                Func::Sign | Func::Sin | Func::Cos | Func::Tanh => Some(1.0),
                Func::Atan | Func::Asin => Some(std::f64::consts::FRAC_PI_2),
                Func::Acos => Some(std::f64::consts::PI),
                _ => None,
            }),
        };
        if let Some(&h) = hints.get(&id) {
            // The node's true magnitude: its terms cancel (or its variables are bounded
            // together) in a way the bound cannot see.
            bound.insert(id, Some(h));
            continue;
        }
        if let Some(b) = b {
            // A NaN bound (0 · inf) is an overflow too.
            if b.is_nan() || b >= MAX_TERMS_BOUND {
                return Err(TermsOverflow {
                    node: id,
                    step: format!(
                        "the sum of the absolute values of its terms on the domain (at most \
                         {b:.3e}, above f64::MAX/2)"
                    ),
                });
            }
        }
        bound.insert(id, b);
    }
    Ok(())
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
/// assert!(f.print(geomkit::expr::Format::Maple).starts_with("x := (u, v) -> "));
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
    /// temporaries.
    pub fn print(&self, f: Format) -> String {
        let vars: Vec<&str> = self.vars.iter().map(String::as_str).collect();
        let mut out = self.graph.print_preamble(&vars, f);
        for (name, &root) in self.names.iter().zip(&self.roots) {
            out.push_str(&self.graph.print_definition(name, &vars, root, f));
            out.push('\n');
        }
        out
    }

    /// The formula as a program with common subexpressions in temporaries, in format `f`.
    pub fn print_program(&self, f: Format) -> String {
        let outputs: Vec<(&str, Id)> = self
            .names
            .iter()
            .map(String::as_str)
            .zip(self.roots.iter().copied())
            .collect();
        self.graph.print_program(&outputs, f)
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
