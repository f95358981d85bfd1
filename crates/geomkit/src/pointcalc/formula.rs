//! Point equations as formulas for symbolic systems and code (spec/point-calculus.md §4,
//! through the expression engine [`crate::expr`]).
//!
//! A cardinal function is written as c_j Π_(k≠j) (t - t_k) with the exact rational
//! c_j = 1 / Π_(k≠j) (t_j - t_k) and exact node positions, so rational nodes print exactly
//! (1/3, 9/2, ...); the source points' coordinates are f64 numbers. A hypersurface is written
//! factor by factor, M = Σ_i ℓ_i(x_1) (Σ_j ℓ_j(x_2) (...)), so its size is about the number of
//! source points.
//!
//! ```
//! use geomkit::expr::{Format, Graph};
//! use geomkit::pointcalc::{cardinal_expr, Nodes};
//! let mut g = Graph::new();
//! let t = g.var("t");
//! let l = cardinal_expr(&mut g, &Nodes::paper_third(), 1, t); // C of equation (2)
//! let v = g.eval(l, &[("t", 0.5)]).unwrap();
//! assert!((v - 1.125).abs() < 1e-15); // 4.5 t t̄ at 1/2
//! ```

use super::equation::PointEquation;
use super::hypersurface::Hypersurface;
use super::nodes::Nodes;
use crate::exact::Rational;
use crate::expr::{Graph, Id};
use num_traits::One;

/// The cardinal function ℓ_j of `nodes` in the variable `t`: c_j Π_(k≠j) (t - t_k), exact
/// for rational nodes ([`Nodes::is_rational`]), else with the f64 nodes and c_j rounded once
/// (so 0.1 prints as 0.1, not as its dyadic value).
pub fn cardinal_expr(g: &mut Graph, nodes: &Nodes, j: usize, t: Id) -> Id {
    let mut factors = Vec::with_capacity(nodes.len());
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
        factors.push(g.num(1.0 / p));
    }
    g.product(&factors)
}

/// Σ_j ℓ_j(t) y_j for per-node expressions `ys`.
fn combine(g: &mut Graph, nodes: &Nodes, t: Id, ys: &[Id]) -> Id {
    let terms: Vec<Id> = ys
        .iter()
        .enumerate()
        .map(|(j, &y)| {
            let l = cardinal_expr(g, nodes, j, t);
            g.mul(l, y)
        })
        .collect();
    g.sum(&terms)
}

impl PointEquation {
    /// The point equation as one expression per coordinate, in the variable `t`.
    pub fn to_expr(&self, g: &mut Graph, t: Id) -> Vec<Id> {
        (0..self.dim())
            .map(|d| {
                let ys: Vec<Id> = (0..self.nodes().len())
                    .map(|i| g.num(self.point(i)[d]))
                    .collect();
                combine(g, self.nodes(), t, &ys)
            })
            .collect()
    }
}

impl Hypersurface {
    /// The model as one expression per response component, in the variables `vars` (one per
    /// factor, in factor order). Panics if `vars.len() != k` (a programming error).
    pub fn to_expr(&self, g: &mut Graph, vars: &[Id]) -> Vec<Id> {
        assert_eq!(vars.len(), self.k(), "one variable per factor");
        let shape = self.shape();
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
                    level = level
                        .chunks(n)
                        .map(|ys| combine(g, nodes, vars[f], ys))
                        .collect();
                }
                level[0]
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
        let e = eq.to_expr(&mut g, t);
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
        let e = m.to_expr(&mut g, &vars)[0];
        let x = [0.2, 0.7, 1.5];
        let v = g.eval(e, &[("a", x[0]), ("b", x[1]), ("c", x[2])]).unwrap();
        assert!((v - m.eval(&x).unwrap()[0]).abs() < 1e-13);
    }
}
