//! Point equations as formulas for symbolic systems and code (spec/point-calculus.md §4,
//! through the expression engine [`crate::expr`]).
//!
//! A cardinal function is written as c_j Π_(k≠j) (t - t_k) with the exact rational
//! c_j = 1 / Π_(k≠j) (t_j - t_k) and exact node positions, so rational nodes print exactly
//! (1/3, 9/2, ...); the source points' coordinates are f64 numbers. A hypersurface is written
//! factor by factor, M = Σ_i ℓ_i(x_1) (Σ_j ℓ_j(x_2) (...)), so its size is about the number of
//! source points.
//!
//! A formula has about (source points × nodes per factor) factors: at most
//! [`MAX_FORMULA_TERMS`] (10^7, some hundred megabytes of text), larger ones are refused
//! with [`Error::TooMany`] before anything is built.
//!
//! Every number of a formula is a finite f64 (the printers' targets compute in f64): a
//! coefficient c_j beyond f64 (nodes extremely close together, or spanning so much that
//! Π (t_j - t_k) overflows) or a folded product c_j · y_j beyond f64 (source values near
//! f64::MAX) is refused with [`Error::ResultOverflow`] naming it, never printed as infinity or
//! dropped as zero.
//!
//! ```
//! use geomkit::expr::{Format, Graph};
//! use geomkit::pointcalc::{cardinal_expr, Nodes};
//! let mut g = Graph::new();
//! let t = g.var("t");
//! let l = cardinal_expr(&mut g, &Nodes::paper_third(), 1, t).unwrap(); // C of equation (2)
//! let v = g.eval(l, &[("t", 0.5)]).unwrap();
//! assert!((v - 1.125).abs() < 1e-15); // 4.5 t t̄ at 1/2
//! ```

use super::equation::PointEquation;
use super::hypersurface::Hypersurface;
use super::nodes::Nodes;
use super::wide::short;
use crate::exact::{rational_to_f64, Rational};
use crate::expr::{Const, Graph, Id, Node};
use crate::{Error, Result};
use num_traits::One;

/// The most factors of a printed point equation: source values × numbers per value × nodes
/// of the innermost factor (each value is multiplied by a product of that many factors).
pub const MAX_FORMULA_TERMS: usize = 10_000_000;

/// Refuses formulas above [`MAX_FORMULA_TERMS`].
fn check_size(values: usize, nodes: usize) -> Result<()> {
    let size = values.saturating_mul(nodes);
    if size > MAX_FORMULA_TERMS {
        return Err(Error::TooMany {
            what: "factors in the formula (source values × nodes)",
            got: size,
            max: MAX_FORMULA_TERMS,
        });
    }
    Ok(())
}

/// The cardinal function ℓ_j of `nodes` in the variable `t`: c_j Π_(k≠j) (t - t_k), exact
/// for rational nodes ([`Nodes::is_rational`]), else with the f64 nodes and c_j rounded once
/// (so 0.1 prints as 0.1, not as its dyadic value). Errors: [`Error::ResultOverflow`] when c_j =
/// 1 / Π_(k≠j) (t_j - t_k) is beyond f64 or below its normal range (its f64 value would
/// print as infinity or drop the term).
pub fn cardinal_expr(g: &mut Graph, nodes: &Nodes, j: usize, t: Id) -> Result<Id> {
    cardinal(g, nodes, j, t, "nodes").map(|(id, _)| id)
}

/// [`cardinal_expr`] and the f64 value of c_j; `what` names the node set in errors.
fn cardinal(g: &mut Graph, nodes: &Nodes, j: usize, t: Id, what: &str) -> Result<(Id, f64)> {
    let mut factors = Vec::with_capacity(nodes.len());
    let coefficient;
    if nodes.is_rational() {
        let x = nodes.exact_values();
        let mut c = Rational::one();
        for (k, xk) in x.iter().enumerate() {
            if k != j {
                c /= &x[j] - xk;
                let node = g.rat(xk.clone());
                factors.push(g.sub(t, node));
            }
        }
        coefficient = rational_to_f64(&c);
        factors.push(g.rat(c));
    } else {
        let x = nodes.values();
        let mut p = 1.0;
        for (k, &xk) in x.iter().enumerate() {
            if k != j {
                p *= x[j] - xk;
                let node = g.num(xk);
                factors.push(g.sub(t, node));
            }
        }
        let c = 1.0 / p;
        // The product left the f64 range on the way: the true weight, with an exponent of
        // its own (1 / p rounded once where it is representable).
        coefficient = if p.is_normal() && c.is_normal() {
            c
        } else {
            nodes.true_weight(j)
        };
        factors.push(g.num(coefficient));
    }
    if !coefficient.is_normal() {
        // c_j beyond f64, or so small that its reciprocal Π (t_j - t_k) is.
        let step = if coefficient.abs() > 1.0 {
            "the coefficient 1/Π(t_j - t_k) of the cardinal function"
        } else {
            "the product Π(t_j - t_k) (the reciprocal of the coefficient) of the cardinal \
             function"
        };
        return Err(Error::ResultOverflow {
            what: format!(
                "{step} of node {j} (t={}) of {what}, in the formula (nodes too close together \
                 or spanning too much; rescale them)",
                short(nodes.values()[j])
            ),
        });
    }
    Ok((g.product(&factors), coefficient))
}

/// Σ_j ℓ_j(t) y_j for per-node expressions `ys` (`what` names the node set; `at` describes
/// the other factors' levels of the ys, for errors).
fn combine(
    g: &mut Graph,
    nodes: &Nodes,
    t: Id,
    ys: &[Id],
    what: &str,
    at: &dyn Fn(usize) -> String,
) -> Result<Id> {
    let mut terms = Vec::with_capacity(ys.len());
    for (j, &y) in ys.iter().enumerate() {
        let (l, c) = cardinal(g, nodes, j, t, what)?;
        // A number y is folded into the coefficient: c · y must be a finite, non-vanishing f64.
        if let Some(v) = g.as_const(y).map(Const::to_f64) {
            let cy = c * v;
            if v != 0.0 && !cy.is_normal() {
                let step = if cy.abs() > 1.0 {
                    format!("the coefficient c_j · y = {} · {}", short(c), short(v))
                } else {
                    format!(
                        "1 / (c_j · y) = 1 / ({} · {}) (the coefficient would vanish)",
                        short(c),
                        short(v)
                    )
                };
                return Err(Error::ResultOverflow {
                    what: format!(
                        "{step} of source point {} in the formula (rescale the response)",
                        at(j)
                    ),
                });
            }
        }
        terms.push(g.mul(l, y));
    }
    Ok(g.sum(&terms))
}

/// Refuses an expression holding a number that is not a finite f64 (a product or sum of
/// coefficients that the graph folded beyond f64).
fn check_numbers(g: &Graph, root: Id, what: &dyn Fn() -> String) -> Result<()> {
    let finite = |c: &Const| c.to_f64().is_finite();
    for id in g.reachable(&[root]) {
        let ok = match g.node(id) {
            Node::Const(c) | Node::Mul(c, _) => finite(c),
            Node::Add(c, ts) => finite(c) && ts.iter().all(|(k, _)| finite(k)),
            _ => true,
        };
        if !ok {
            return Err(Error::ResultOverflow {
                what: format!(
                    "a coefficient of {} (the cardinal functions' coefficients times the \
                     source values; rescale the response)",
                    what()
                ),
            });
        }
    }
    Ok(())
}

impl PointEquation {
    /// The point equation as one expression per coordinate, in the variable `t`. Errors:
    /// [`Error::TooMany`] above [`MAX_FORMULA_TERMS`]; [`Error::ResultOverflow`] for a number of
    /// the formula beyond f64 (see the module documentation).
    pub fn to_expr(&self, g: &mut Graph, t: Id) -> Result<Vec<Id>> {
        check_size(self.points_flat().len(), self.nodes().len())?;
        (0..self.dim())
            .map(|d| {
                let ys: Vec<Id> = (0..self.nodes().len())
                    .map(|i| g.num(self.point(i)[d]))
                    .collect();
                let at = |j: usize| format!("{j} (coordinate {d})");
                let e = combine(g, self.nodes(), t, &ys, "the nodes", &at)?;
                check_numbers(g, e, &|| format!("coordinate {d}"))?;
                Ok(e)
            })
            .collect()
    }
}

impl Hypersurface {
    /// The model as one expression per response component, in the variables `vars` (one per
    /// factor, in factor order). Panics if `vars.len() != k` (a programming error). Errors:
    /// [`Error::TooMany`] above [`MAX_FORMULA_TERMS`]; [`Error::ResultOverflow`] for a number of
    /// the formula beyond f64 (see the module documentation).
    pub fn to_expr(&self, g: &mut Graph, vars: &[Id]) -> Result<Vec<Id>> {
        assert_eq!(vars.len(), self.k(), "one variable per factor");
        let shape = self.shape();
        check_size(self.values().len(), shape[shape.len() - 1])?;
        (0..self.dim())
            .map(|d| {
                // Innermost factor first: the values become sums over the last factor, ...
                let mut level: Vec<Id> = self
                    .values()
                    .iter()
                    .skip(d)
                    .step_by(self.dim())
                    .map(|&v| g.num(v))
                    .collect();
                for f in (0..self.k()).rev() {
                    let n = shape[f];
                    let nodes = self.factors()[f].nodes();
                    let what = format!("factor {}", self.factors()[f].name());
                    let mut next = Vec::with_capacity(level.len() / n);
                    let innermost = f + 1 == self.k();
                    for (group, ys) in level.chunks(n).enumerate() {
                        // The innermost factor's ys are the source values: cell group · n + j.
                        let at = |j: usize| {
                            if innermost {
                                self.describe_at(&self.cell_levels(group * n + j))
                            } else {
                                format!("group {group}, level {j} of {what}")
                            }
                        };
                        next.push(combine(g, nodes, vars[f], ys, &what, &at)?);
                    }
                    level = next;
                }
                check_numbers(g, level[0], &|| format!("the formula of response {d}"))?;
                Ok(level[0])
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::expr::Format;
    use crate::pointcalc::{Factor, PointOptions};

    #[test]
    fn formula_of_equation_1_evaluates_like_the_curve() {
        let eq = PointEquation::new(
            Nodes::paper_half(),
            vec![vec![0.0, 1.0], vec![2.0, 3.0], vec![4.0, -1.0]],
        )
        .unwrap();
        let mut g = Graph::new();
        let t = g.var("t");
        let e = eq.to_expr(&mut g, t).unwrap();
        for tt in [0.0, 0.3, 0.5, 0.9] {
            let want = eq.derivatives(tt)[0].clone();
            for d in 0..2 {
                let v = g.eval(e[d], &[("t", tt)]).unwrap();
                assert!((v - want[d]).abs() < 1e-14);
            }
        }
        assert!(g.print(e[0], Format::Maple).unwrap().contains('t'));
    }

    #[test]
    fn formula_of_a_three_factor_model() {
        let factors = vec![
            Factor::new("a", Nodes::paper_third()),
            Factor::new("b", Nodes::paper_half()),
            Factor::new("c", Nodes::new(vec![-1.0, 2.0]).unwrap()),
        ];
        let m = Hypersurface::from_fn(
            factors,
            1,
            |x, o| o[0] = x[0] * x[1] - x[2] + 0.5,
            &PointOptions::default(),
        )
        .unwrap();
        let mut g = Graph::new();
        let vars: Vec<Id> = ["a", "b", "c"].iter().map(|n| g.var(n)).collect();
        let e = m.to_expr(&mut g, &vars).unwrap()[0];
        let x = [0.2, 0.7, 1.5];
        let v = g.eval(e, &[("a", x[0]), ("b", x[1]), ("c", x[2])]).unwrap();
        assert!((v - m.eval(&x).unwrap()[0]).abs() < 1e-13);
    }
}
