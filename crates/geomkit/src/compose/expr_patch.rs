//! Patches, curve pieces and curves given as formulas (spec/composite-surfaces.md §2-§5):
//! coordinates as expressions of the engine ([`crate::expr`]) in one or two variables, on a
//! box domain of their own that a composite maps linearly onto its cell (the paper's change
//! of variables).
//!
//! ```
//! use geomkit::compose::ExprPatch;
//! let p = ExprPatch::parse(&[("z", "sin(x) * cos(y)")], &["x", "y"], None).unwrap();
//! assert_eq!(p.eval(&[0.0, 1.0]).unwrap(), vec![0.0]);
//! let e = ExprPatch::parse(&[("z", "x + * y")], &["x", "y"], None).unwrap_err();
//! assert_eq!(e.to_string(), "coordinate z: parse error at byte 4: expected a number, a name or `(`, found `*`");
//! ```

use super::formula::{coef, int_const, num, Hints};
use super::grid::show;
use super::poly::PolyPatch;
use crate::expr::{parse_with_variables, Const, Func, Graph, Id, Node, Tape};
use crate::{Error, Result};
use std::collections::HashMap;

/// Samples per variable of the finiteness check ([`ExprPatch::check_finite`]).
const FINITE_SAMPLES: usize = 9;

/// Coordinates given as expressions in one or two variables (a curve piece r(t), a patch
/// r(u, v) or a height z(x, y)), with an optional domain of their own: one interval per
/// variable. Without a domain, the cell it is placed on is its domain.
#[derive(Debug, Clone)]
pub struct ExprPatch {
    graph: Graph,
    roots: Vec<Id>,
    names: Vec<String>,
    texts: Vec<String>,
    vars: Vec<String>,
    domain: Option<Vec<(f64, f64)>>,
    tape: Tape,
    /// The polynomial patch it was made from ([`ExprPatch::from_poly`]).
    poly: Option<Box<PolyPatch>>,
}

impl PartialEq for ExprPatch {
    fn eq(&self, other: &Self) -> bool {
        self.names == other.names
            && self.texts == other.texts
            && self.vars == other.vars
            && self.domain == other.domain
    }
}

/// An error of coordinate `name` that the message says (no parse error inside).
fn expression_error(name: &str, message: String) -> Error {
    Error::Expression {
        what: format!("coordinate {name}"),
        message,
        parse: None,
    }
}

/// An engine error of coordinate `name`, keeping a parse error's span.
fn engine_error(name: &str, e: crate::expr::ExprError) -> Error {
    Error::expression(format!("coordinate {name}"), e)
}

impl ExprPatch {
    /// Parses `coords` = `[(name, formula), ...]` (infix syntax of [`crate::expr::parse`]) as
    /// functions of `vars`, on `domain` (one interval per variable) or, with `None`, on
    /// whatever cell it is placed on.
    ///
    /// Errors: [`Error::Expression`] naming the coordinate for a formula that does not parse
    /// or that uses a variable other than `vars` (with the [`crate::expr::ParseError`] and
    /// its span in the formula's text as `parse`; an unknown name is refused even where it
    /// would cancel, as in `u + w - w`), or that divides by an exact zero; [`Error::Empty`] without coordinates; [`Error::PatchCount`] for a
    /// domain with a number of intervals other than the number of variables;
    /// [`Error::InvalidShape`] for an interval that is not finite and increasing.
    pub fn parse(
        coords: &[(&str, &str)],
        vars: &[&str],
        domain: Option<Vec<(f64, f64)>>,
    ) -> Result<Self> {
        let mut graph = Graph::new();
        let mut roots = Vec::with_capacity(coords.len());
        for (name, text) in coords {
            let e =
                parse_with_variables(&mut graph, text, vars).map_err(|e| engine_error(name, e))?;
            roots.push(e);
        }
        let texts = coords.iter().map(|c| c.1.to_string()).collect();
        let names = coords.iter().map(|c| c.0.to_string()).collect();
        Self::new(graph, roots, names, texts, vars, domain)
    }

    /// A polynomial patch as an expression Σ c_ab u^a v^b in `vars` on [0, 1]² (its local
    /// coordinates), so that polynomial and expression patches mix in one composite.
    pub fn from_poly(p: &PolyPatch, names: &[&str], vars: [&str; 2]) -> Result<Self> {
        let mut graph = Graph::new();
        let (u, v) = (graph.var(vars[0]), graph.var(vars[1]));
        let (deg_a, deg_b) = p.degrees();
        let mut roots = Vec::with_capacity(p.dim());
        for k in 0..p.dim() {
            let mut terms = Vec::new();
            for a in 0..=deg_a {
                for b in 0..=deg_b {
                    let c = coef(&mut graph, p.coefficient(a, b)[k]);
                    terms.push(graph.prod(&[(c, 1), (u, a as i32), (v, b as i32)]));
                }
            }
            roots.push(graph.sum(&terms));
        }
        let names: Vec<String> = (0..p.dim())
            .map(|k| names.get(k).map_or(format!("x{k}"), |s| s.to_string()))
            .collect();
        let texts = roots
            .iter()
            .zip(&names)
            .map(|(&r, name)| {
                graph
                    .print(r, crate::expr::Format::Sympy)
                    .map_err(|e| engine_error(name, e))
            })
            .collect::<Result<_>>()?;
        let mut e = Self::new(graph, roots, names, texts, &vars, Some(vec![(0.0, 1.0); 2]))?;
        e.poly = Some(Box::new(p.clone()));
        Ok(e)
    }

    /// A curve piece Σ_a c_a s^a in `var` on \[0, 1\] (its local parameter), the power
    /// coefficients row-major (`coef_rows[a * names.len() + k]` for coordinate k), so that
    /// polynomial curve pieces (the spans of a B-spline) mix with formula pieces.
    pub(crate) fn from_power(coef_rows: &[f64], names: &[String], var: &str) -> Result<Self> {
        let dim = names.len();
        let mut graph = Graph::new();
        let s = graph.var(var);
        let roots: Vec<Id> = (0..dim)
            .map(|k| {
                let terms: Vec<Id> = coef_rows
                    .chunks_exact(dim)
                    .enumerate()
                    .map(|(a, row)| {
                        let c = coef(&mut graph, row[k]);
                        graph.prod(&[(c, 1), (s, a as i32)])
                    })
                    .collect();
                graph.sum(&terms)
            })
            .collect();
        let texts = roots
            .iter()
            .zip(names)
            .map(|(&r, name)| {
                graph
                    .print(r, crate::expr::Format::Sympy)
                    .map_err(|e| engine_error(name, e))
            })
            .collect::<Result<_>>()?;
        Self::new(
            graph,
            roots,
            names.to_vec(),
            texts,
            &[var],
            Some(vec![(0.0, 1.0)]),
        )
    }

    fn new(
        graph: Graph,
        roots: Vec<Id>,
        names: Vec<String>,
        texts: Vec<String>,
        vars: &[&str],
        domain: Option<Vec<(f64, f64)>>,
    ) -> Result<Self> {
        if roots.is_empty() {
            return Err(Error::Empty {
                what: "patch coordinates",
            });
        }
        for (name, &r) in names.iter().zip(&roots) {
            if let Some(bad) = graph
                .variables(&[r])
                .into_iter()
                .find(|x| !vars.contains(&x.as_str()))
            {
                return Err(expression_error(
                    name,
                    format!(
                        "unknown variable `{bad}` (the variables are {})",
                        vars.join(", ")
                    ),
                ));
            }
        }
        if let Some(d) = &domain {
            check_domain(d, vars.len())?;
        }
        let tape = Tape::new(&graph, &roots, vars).map_err(|e| engine_error(&names[0], e))?;
        Ok(ExprPatch {
            graph,
            roots,
            names,
            texts,
            vars: vars.iter().map(|s| s.to_string()).collect(),
            domain,
            tape,
            poly: None,
        })
    }

    /// The polynomial patch it was made from by [`ExprPatch::from_poly`] (its Bézier net
    /// too, when it has one), so that exact forms survive a composite that mixes polynomial
    /// and formula patches; `None` for parsed formulas.
    pub fn poly(&self) -> Option<&PolyPatch> {
        self.poly.as_deref()
    }

    /// Number of coordinates.
    pub fn dim(&self) -> usize {
        self.roots.len()
    }

    /// The variables, in order.
    pub fn vars(&self) -> &[String] {
        &self.vars
    }

    /// Coordinate names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The formulas as given.
    pub fn texts(&self) -> &[String] {
        &self.texts
    }

    /// The patch's own domain, if it has one.
    pub fn domain(&self) -> Option<&[(f64, f64)]> {
        self.domain.as_deref()
    }

    /// The point at parameters `params` (one per variable), by the engine's tape.
    /// Errors: [`Error::Expression`] for a wrong number of parameters.
    pub fn eval(&self, params: &[f64]) -> Result<Vec<f64>> {
        let inputs: Vec<&[f64]> = params.iter().map(std::slice::from_ref).collect();
        let mut out = vec![0.0; self.dim()];
        {
            let mut cols: Vec<&mut [f64]> = out.chunks_mut(1).collect();
            self.tape
                .eval_batch(&inputs, &mut cols)
                .map_err(|e| engine_error(&self.names[0], e))?;
        }
        Ok(out)
    }

    /// The `order`-th derivative of a patch in one variable (a curve piece), by the engine's
    /// symbolic derivative ([`crate::expr::Graph::diff`]), as a patch on the same domain.
    /// Errors: [`Error::Expression`] if the derivative does not compile.
    pub(crate) fn derivative(&self, order: usize) -> Result<ExprPatch> {
        let var = self.vars[0].clone();
        let mut graph = self.graph.clone();
        let mut roots = self.roots.clone();
        for _ in 0..order {
            roots = roots.iter().map(|&r| graph.diff(r, &var)).collect();
        }
        let vars: Vec<&str> = self.vars.iter().map(String::as_str).collect();
        let texts = self
            .texts
            .iter()
            .map(|t| format!("d^{order}/d{var}^{order} ({t})"))
            .collect();
        ExprPatch::new(
            graph,
            roots,
            self.names.clone(),
            texts,
            &vars,
            self.domain.clone(),
        )
    }

    /// Evaluates at local coordinates (each in [0, 1], mapped linearly onto `domain`):
    /// `locals[k][i]` is local variable k at point i; `out` receives `dim` numbers per point.
    pub(crate) fn eval_local_many(
        &self,
        domain: &[(f64, f64)],
        locals: &[&[f64]],
        out: &mut [f64],
    ) {
        let n = locals.first().map_or(0, |x| x.len());
        let params: Vec<Vec<f64>> = locals
            .iter()
            .zip(domain)
            .map(|(l, &(a, b))| l.iter().map(|&s| local_to_param(s, a, b)).collect())
            .collect();
        let inputs: Vec<&[f64]> = params.iter().map(Vec::as_slice).collect();
        let d = self.dim();
        let mut cols = vec![vec![0.0; n]; d];
        {
            let mut refs: Vec<&mut [f64]> = cols.iter_mut().map(Vec::as_mut_slice).collect();
            self.tape
                .eval_batch(&inputs, &mut refs)
                .expect("inputs shaped by the caller");
        }
        for (i, p) in out.chunks_exact_mut(d).enumerate() {
            for (k, x) in p.iter_mut().enumerate() {
                *x = cols[k][i];
            }
        }
    }

    /// The coordinates imported into `dst` with each variable k replaced by `args[k]`.
    pub(crate) fn place(&self, dst: &mut Graph, args: &[Id]) -> Vec<Id> {
        let subs: Vec<(&str, Id)> = self
            .vars
            .iter()
            .map(String::as_str)
            .zip(args.iter().copied())
            .collect();
        import(dst, &self.graph, &self.roots, &subs)
    }

    /// The coordinates in `dst` at local coordinates `locals` (expressions with values in
    /// [0, 1]): variable k replaced by a_k + (b_k - a_k) locals[k] on `domain` (exact
    /// rationals for decimal bounds, so local 0 and 1 give exactly a_k and b_k).
    pub(crate) fn place_local(
        &self,
        dst: &mut Graph,
        locals: &[Id],
        domain: &[(f64, f64)],
    ) -> Vec<Id> {
        let args: Vec<Id> = locals
            .iter()
            .zip(domain)
            .map(|(&l, &(a, b))| {
                let (a, b) = (num(dst, a), num(dst, b));
                let w = dst.sub(b, a);
                let wl = dst.mul(w, l);
                dst.add(a, wl)
            })
            .collect();
        self.place(dst, &args)
    }

    /// Whether a formula of the patch's coordinates may be undefined for some finite value
    /// of a variable: it takes a square root, a logarithm, an arc sine or cosine, a tangent,
    /// divides by an expression or raises one to a negative power. Such a patch, placed
    /// by [`Self::place_clamped`], gets arguments clamped exactly into its domain.
    pub(crate) fn is_partial(&self) -> bool {
        self.graph
            .reachable(&self.roots)
            .into_iter()
            .any(|id| match self.graph.node(id) {
                Node::Fun(f, _) => matches!(
                    f,
                    Func::Sqrt | Func::Ln | Func::Asin | Func::Acos | Func::Tan
                ),
                Node::Mul(_, fs) => fs.iter().any(|&(_, e)| e < 0),
                _ => false,
            })
    }

    /// The patch's coordinates in `dst` for a composite's single formula, each variable k
    /// at `locals[k]`: a constant local coordinate (0 for the edge terms of formula (9)),
    /// placed exactly, or the local coordinate of x on a cell [x_i, x_(i+1)].
    ///
    /// A total patch (see [`Self::is_partial`]) is placed the paper's way, its variable
    /// a + (b - a) P on its domain [a, b] with the ramp P(x, x_i, x_(i+1) - x_i). A partial
    /// one gets its variable clamped so that it stays in [a, b] also in f64, where the
    /// rounding of P's |.| terms may put a + (b - a) P an ulp outside (and far from a narrow
    /// cell, cancellation makes P itself wrong), and `sqrt(x)` on [0, 1] would give NaN for
    /// every x: with q = (x - x_i)/(x_(i+1) - x_i), m = max(q, 0) = |q| (1/2 + sign(q)/2)
    /// and r = max(1 - m, 0) = |1 - m| (1/2 + sign(1 - m)/2), exact in f64 given q, the
    /// variable is y = b - w r: equal to a + (b - a) P in exact arithmetic (the same
    /// formula in value), and in f64 monotone in r ∈ [0, 1] from exactly b to b - w, where
    /// w is b - a, rounded down when rounding to nearest would put b - w below a. It is
    /// wrapped as |y| (-|y| for b <= 0, sign(y) |y| across 0), equal to y in f64 and a node
    /// the engine does not merge into the patch's own sums (which would round it again).
    /// Hints for [`super::formula::check_terms`]: m and r in [0, 1].
    pub(crate) fn place_clamped(
        &self,
        dst: &mut Graph,
        locals: &[Local],
        domain: &[(f64, f64)],
        hints: &mut Hints,
    ) -> Vec<Id> {
        let partial = self.is_partial();
        let exact = |dst: &mut Graph, l: Id, (a, b): (f64, f64)| {
            let (na, nb) = (num(dst, a), num(dst, b));
            let w = dst.sub(nb, na);
            let wl = dst.mul(w, l);
            dst.add(na, wl)
        };
        let mut args: Vec<Id> = locals
            .iter()
            .zip(domain)
            .map(|(local, &d)| match *local {
                Local::Const(c) => exact(dst, c, d),
                Local::Cell { ramp, .. } if !partial => exact(dst, ramp, d),
                Local::Cell { x, cell, .. } => clamped_argument(dst, x, cell, d, hints),
            })
            .collect();
        let placed = self.place(dst, &args);
        if dst.undefined_constant(&placed).is_none() {
            return placed;
        }
        // The decimals of the patch and of its domain, exact, can put a function beyond its
        // domain at a constant argument where f64 does not (asin((x - 2.005)/0.004999999999999893)
        // on [2, 2.01] is asin(-1.00000000000002) at x = 2 exactly, and asin(-1) in f64, as
        // the construction checked): such arguments are the f64 values of the parameters.
        for ((arg, local), &(a, b)) in args.iter_mut().zip(locals).zip(domain) {
            if let Local::Const(c) = *local {
                let s = dst.as_const(c).map_or(0.0, Const::to_f64);
                *arg = dst.num(local_to_param(s, a, b));
            }
        }
        self.place(dst, &args)
    }

    /// Checks that the patch is finite on a 9-point-per-variable grid of `domain`.
    /// Errors: [`Error::Expression`] naming the coordinate and the point.
    pub(crate) fn check_finite(&self, domain: &[(f64, f64)]) -> Result<()> {
        let k = FINITE_SAMPLES;
        let samples: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
        self.check_finite_at(domain, &samples)
    }

    /// Checks that the patch is finite at the local coordinates `samples` (each in [0, 1])
    /// of every variable (all combinations) on `domain`. Errors: [`Error::Expression`]
    /// naming the coordinate and the point.
    pub(crate) fn check_finite_at(&self, domain: &[(f64, f64)], samples: &[f64]) -> Result<()> {
        let k = samples.len();
        let total = k.pow(domain.len() as u32);
        let mut locals = vec![Vec::with_capacity(total); domain.len()];
        for idx in 0..total {
            let mut rest = idx;
            for l in locals.iter_mut() {
                l.push(samples[rest % k]);
                rest /= k;
            }
        }
        let refs: Vec<&[f64]> = locals.iter().map(Vec::as_slice).collect();
        let d = self.dim();
        let mut out = vec![0.0; total * d];
        self.eval_local_many(domain, &refs, &mut out);
        if let Some(pos) = out.iter().position(|x| !x.is_finite()) {
            let (i, c) = (pos / d, pos % d);
            let at: Vec<String> = self
                .vars
                .iter()
                .zip(&locals)
                .zip(domain)
                .map(|((v, l), &(a, b))| format!("{v} = {}", show(local_to_param(l[i], a, b))))
                .collect();
            return Err(expression_error(
                &self.names[c],
                format!(
                    "the value {} at {} is not a finite number",
                    out[pos],
                    at.join(", ")
                ),
            ));
        }
        Ok(())
    }
}

/// The parameter at local coordinate s ∈ [0, 1] on [a, b]: a + (b - a) s, exactly b at
/// s = 1 and never outside [a, b] (a + (b - a) rounds past b for a = 0.1, b = 0.3).
#[inline]
pub(crate) fn local_to_param(s: f64, a: f64, b: f64) -> f64 {
    if s >= 1.0 {
        b
    } else {
        (a + (b - a) * s).clamp(a, b)
    }
}

/// A local coordinate for [`ExprPatch::place_clamped`].
#[derive(Debug, Clone, Copy)]
pub(crate) enum Local {
    /// A constant in [0, 1] (a node of the destination graph).
    Const(Id),
    /// The variable `x` on the cell `cell` = (x_i, x_(i+1)), with its ramp P (the node).
    Cell { x: Id, cell: (f64, f64), ramp: Id },
}

/// The variable of a partial patch on its domain [a, b] for x on `cell`, clamped in a form
/// that holds in f64 ([`ExprPatch::place_clamped`]).
fn clamped_argument(
    dst: &mut Graph,
    x: Id,
    (xi, xj): (f64, f64),
    (a, b): (f64, f64),
    hints: &mut Hints,
) -> Id {
    let (nxi, nxj) = (num(dst, xi), num(dst, xj));
    let width = dst.sub(nxj, nxi);
    let shifted = dst.sub(x, nxi);
    let q = dst.div(shifted, width);
    let half = dst.rational(1, 2);
    let one = dst.int(1);
    let mut clamp_low = |dst: &mut Graph, v: Id| {
        // max(v, 0) = |v| (1/2 + sign(v)/2): a product of two factors, which the engine
        // keeps as it is (a sum would be flattened into its neighbours and rounded again).
        let sv = dst.sign(v);
        let hs = dst.mul(half, sv);
        let step = dst.add(half, hs);
        let av = dst.abs(v);
        let out = dst.mul(av, step);
        hints.cap(out, 1.0);
        out
    };
    let m = clamp_low(dst, q);
    let one_minus_m = dst.sub(one, m);
    let r = clamp_low(dst, one_minus_m);
    let nb = num(dst, b);
    let w = clamped_width(dst, a, b);
    let wr = dst.scale(&w, r);
    let y = dst.sub(nb, wr);
    let ay = dst.abs(y);
    if a >= 0.0 {
        ay
    } else if b <= 0.0 {
        dst.neg(ay)
    } else {
        let sy = dst.sign(y);
        dst.mul(sy, ay)
    }
}

/// The width b - a as the constant of [`ExprPatch::place_clamped`]: the exact rational of
/// the short rationals of a and b, unless its nearest f64 w makes b - w fall below a in f64
/// (w rounded up); then the f64 just below it, which does not.
fn clamped_width(g: &mut Graph, a: f64, b: f64) -> Const {
    let (qa, qb) = (num(g, a), num(g, b));
    let wid = g.sub(qb, qa);
    let exact = g.as_const(wid).cloned().unwrap_or(Const::Float(b - a));
    let (af, bf) = (
        g.as_const(qa).map_or(a, Const::to_f64),
        g.as_const(qb).map_or(b, Const::to_f64),
    );
    let mut w = exact.to_f64();
    if bf - w >= af {
        return exact;
    }
    while bf - w < af {
        w = next_down(w);
    }
    Const::Float(w)
}

/// The largest f64 below a positive finite x.
fn next_down(x: f64) -> f64 {
    f64::from_bits(x.to_bits() - 1)
}

/// One interval per variable, finite and increasing.
fn check_domain(domain: &[(f64, f64)], vars: usize) -> Result<()> {
    if domain.len() != vars {
        return Err(Error::PatchCount {
            what: "intervals of a patch domain (one per variable)".into(),
            expected: vars,
            got: domain.len(),
        });
    }
    for (k, &(a, b)) in domain.iter().enumerate() {
        if !(a.is_finite() && b.is_finite() && a < b) {
            return Err(Error::InvalidShape {
                what: "domain",
                reason: format!("interval {k} [{a}, {b}] must be finite with start < end"),
            });
        }
    }
    Ok(())
}

/// The expressions `roots` of `src` rebuilt in `dst` (simplified again by `dst`'s
/// constructors), with the variables named in `subs` replaced by the given nodes of `dst`.
pub(crate) fn import(dst: &mut Graph, src: &Graph, roots: &[Id], subs: &[(&str, Id)]) -> Vec<Id> {
    let mut map: HashMap<Id, Id> = HashMap::new();
    for id in src.reachable(roots) {
        let new = match src.node(id) {
            Node::Const(c) => dst.constant(c.clone()),
            Node::Pi => dst.pi(),
            Node::Var(name) => match subs.iter().find(|(v, _)| *v == &**name) {
                Some(&(_, by)) => by,
                None => dst.var(name),
            },
            Node::Add(c, ts) => {
                let cid = dst.constant(c.clone());
                let mut lin: Vec<(Const, Id)> =
                    ts.iter().map(|(k, t)| (k.clone(), map[t])).collect();
                lin.push((int_const(1), cid));
                dst.lin(&lin)
            }
            Node::Mul(c, fs) => {
                let cid = dst.constant(c.clone());
                let mut fl: Vec<(Id, i32)> = fs.iter().map(|(b, e)| (map[b], *e)).collect();
                fl.push((cid, 1));
                dst.prod(&fl)
            }
            Node::Fun(f, a) => dst.fun(*f, map[a]),
        };
        map.insert(id, new);
    }
    roots.iter().map(|r| map[r]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_errors_name_the_coordinate_and_the_variable() {
        let e = ExprPatch::parse(&[("x", "u"), ("y", "w + v")], &["u", "v"], None).unwrap_err();
        assert!(
            e.to_string().contains("coordinate y: unknown variable `w`"),
            "{e}"
        );
        let e = ExprPatch::parse(&[("x", "u/0")], &["u", "v"], None).unwrap_err();
        assert!(e.to_string().contains("division by exact zero"), "{e}");
        let e = ExprPatch::parse(&[("x", "u")], &["u", "v"], Some(vec![(0.0, 1.0)])).unwrap_err();
        assert!(
            matches!(
                e,
                Error::PatchCount {
                    expected: 2,
                    got: 1,
                    ..
                }
            ),
            "{e}"
        );
        let e = ExprPatch::parse(&[("x", "u")], &["u"], Some(vec![(1.0, 1.0)])).unwrap_err();
        assert!(e.to_string().contains("start < end"), "{e}");
        let p = ExprPatch::parse(&[("x", "ln(u)")], &["u"], None).unwrap();
        let e = p.check_finite(&[(0.0, 1.0)]).unwrap_err();
        assert!(e.to_string().contains("at u = 0 is not a finite"), "{e}");
        assert!(p.check_finite(&[(0.5, 1.0)]).is_ok());
    }

    #[test]
    fn parse_errors_keep_their_span_in_the_coordinate_text() {
        use crate::expr::ParseErrorKind;
        let y = "u·v + 1";
        let e = ExprPatch::parse(&[("x", "u"), ("y", y)], &["u", "v"], None).unwrap_err();
        assert_eq!(
            e.to_string(),
            "coordinate y: parse error at byte 1: expected an operator or the end of the \
             formula, found `·`"
        );
        let Error::Expression {
            what,
            parse: Some(p),
            ..
        } = &e
        else {
            panic!("{e:?}")
        };
        assert_eq!(what, "coordinate y");
        assert_eq!(&y[p.span.clone()], "·");
        // An unknown variable where it stands, even where it would cancel.
        let z = "u +\n w - w";
        let e = ExprPatch::parse(&[("z", z)], &["u", "v"], None).unwrap_err();
        let p = e.parse_error().unwrap();
        assert_eq!((&z[p.span.clone()], p.line, p.column), ("w", 2, 2));
        assert!(matches!(&p.kind, ParseErrorKind::UnknownVariable { name, .. } if name == "w"));
        assert_eq!(
            e.to_string(),
            "coordinate z: unknown variable `w` (the variables are u, v) at byte 5 (line 2, \
             column 2)"
        );
        // Errors that are not about the text carry no parse error.
        let p = ExprPatch::parse(&[("x", "ln(u)")], &["u"], None).unwrap();
        let e = p.check_finite(&[(0.0, 1.0)]).unwrap_err();
        assert!(matches!(e, Error::Expression { parse: None, .. }), "{e:?}");
        assert!(e.parse_error().is_none());
    }

    #[test]
    fn placing_maps_the_domain_and_poly_patches_agree() {
        let p = ExprPatch::parse(
            &[("z", "x^2 + 3*y")],
            &["x", "y"],
            Some(vec![(1.0, 3.0), (0.0, 0.5)]),
        )
        .unwrap();
        let mut g = Graph::new();
        let (s, t) = (g.var("s"), g.var("t"));
        let d = p.domain().unwrap().to_vec();
        let e = p.place_local(&mut g, &[s, t], &d)[0];
        assert_eq!(g.eval(e, &[("s", 0.5), ("t", 1.0)]).unwrap(), 4.0 + 1.5);
        let one = g.int(1);
        let corner = p.place_local(&mut g, &[one, one], &d)[0];
        assert_eq!(g.print(corner, crate::expr::Format::Maple).unwrap(), "21/2");
        let poly = PolyPatch::new((1, 2), 1, vec![1.0, 2.0, -0.5, 4.0, 0.25, 3.0]).unwrap();
        let q = ExprPatch::from_poly(&poly, &["z"], ["s", "t"]).unwrap();
        let mut out = [0.0];
        q.eval_local_many(&[(0.0, 1.0), (0.0, 1.0)], &[&[0.3], &[0.7]], &mut out);
        assert!((out[0] - poly.eval(0.3, 0.7)[0]).abs() < 1e-15);
        assert_eq!(q, q.clone());
    }
}
