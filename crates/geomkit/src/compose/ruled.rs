//! Piecewise-ruled surfaces over a family of curves, formula (2) of
//! spec/composite-surfaces.md: R(u, v) = r_0(u) + Σ_k (r_k(u) - r_(k-1)(u)) P(v, v_(k-1),
//! v_k - v_(k-1)), each curve first reparametrized onto the common interval [u0, u1].
//!
//! The formula is written in the equivalent grouped form R = Σ_k r_k(u) w_k(v) with the hat
//! weights w_k = P_k - P_(k+1): curves (or coordinates) that are equal, or equal up to a
//! factor, share one term, and the weights collapse to sums of |v - v_k|. For the cube this
//! gives exactly the paper's formula.
//!
//! ```
//! use geomkit::compose::{RuledCurve, RuledSurface};
//! // A square ruled between two points: a double pyramid.
//! let sq = RuledCurve::polygon(vec![[1., 0., 0.], [0., 1., 0.], [-1., 0., 0.], [0., -1., 0.]]).unwrap();
//! let s = RuledSurface::new(
//!     vec![RuledCurve::Point([0., 0., 1.]), sq, RuledCurve::Point([0., 0., -1.])],
//!     vec![0., 1., 2.], (0., 4.)).unwrap();
//! assert_eq!(s.eval(0.0, 0.5), vec![0.5, 0.0, 0.5]);
//! ```

use super::expr_patch::ExprPatch;
use super::formula::{abs_sum_expr, check_terms, konst, num, variable_bound, Formula, Hints};
use super::grid::{check_increasing, Axis};
use super::linear::{exact, AbsSum};
use crate::exact::Rational;
use crate::expr::{Const, Graph, Id};
use crate::geom::{check_point, Curve, Surface};
use crate::{Error, Result};
use num_traits::One;

/// The largest |coordinate| of a curve of a ruled surface: half of f64::MAX, so that the
/// differences r_k(u) - r_(k-1)(u) of formula (2) stay finite.
pub const MAX_RULED_COORDINATE: f64 = f64::MAX / 2.0;

/// One curve of the family, with its own parameter interval.
#[derive(Debug, Clone, PartialEq)]
pub enum RuledCurve {
    /// A single point (a degenerate curve: the apex of a cone, the centre of a cap).
    Point([f64; 3]),
    /// A polyline through the vertices, parameter k at vertex k; closed polylines return to
    /// the first vertex at parameter `len` (the paper's squares: u from 0 to 4).
    Polyline {
        /// The vertices.
        vertices: Vec<[f64; 3]>,
        /// Whether the last edge returns to the first vertex.
        closed: bool,
    },
    /// The circle c + r (cos τ, sin τ, 0), τ from 0 to 2π.
    Circle {
        /// Centre.
        center: [f64; 3],
        /// Radius (> 0).
        radius: f64,
    },
    /// A curve given as formulas x(t), y(t), z(t) on its domain [t0, t1]
    /// (see [`RuledCurve::formula`]).
    Expr(Box<ExprPatch>),
}

impl RuledCurve {
    /// A closed polygon. Errors: fewer than 2 vertices, non-finite coordinates, equal
    /// consecutive vertices.
    pub fn polygon(vertices: Vec<[f64; 3]>) -> Result<Self> {
        check_vertices(&vertices, 2)?;
        Ok(RuledCurve::Polyline {
            vertices,
            closed: true,
        })
    }

    /// An open polyline. Errors as [`RuledCurve::polygon`].
    pub fn polyline(vertices: Vec<[f64; 3]>) -> Result<Self> {
        check_vertices(&vertices, 2)?;
        Ok(RuledCurve::Polyline {
            vertices,
            closed: false,
        })
    }

    /// A curve given as formulas `coords` = `[x(t), y(t), z(t)]` in the variable `t` on
    /// [t0, t1]. Errors: [`Error::Expression`] for a formula that does not parse (with the
    /// position) or is not finite on a sample of [t0, t1]; [`Error::InvalidShape`] unless
    /// t0 < t1 (both finite).
    ///
    /// ```
    /// use geomkit::compose::RuledCurve;
    /// let c = RuledCurve::formula(["cos(t)", "sin(t)", "t/10"], (0.0, 6.0)).unwrap();
    /// assert_eq!(c.eval(0.0), [1.0, 0.0, 0.0]);
    /// assert!(RuledCurve::formula(["t", "t", "ln(t)"], (0.0, 1.0)).is_err());
    /// ```
    pub fn formula(coords: [&str; 3], t: (f64, f64)) -> Result<Self> {
        let named = [("x", coords[0]), ("y", coords[1]), ("z", coords[2])];
        let e = ExprPatch::parse(&named, &["t"], Some(vec![t]))?;
        e.check_finite(&[t])?;
        Ok(RuledCurve::Expr(Box::new(e)))
    }

    /// The curve's own parameter interval.
    pub fn interval(&self) -> (f64, f64) {
        match self {
            RuledCurve::Expr(e) => e.domain().map_or((0.0, 1.0), |d| d[0]),
            RuledCurve::Point(_) => (0.0, 1.0),
            RuledCurve::Polyline { vertices, closed } => {
                (0.0, (vertices.len() - usize::from(!closed)) as f64)
            }
            RuledCurve::Circle { .. } => (0.0, std::f64::consts::TAU),
        }
    }

    /// The largest |coordinate| of the curve: of its point or vertices, centre plus radius
    /// for a circle, the largest sampled (9 points) for a formula curve.
    fn magnitude(&self) -> f64 {
        let max = |ps: &[[f64; 3]]| {
            ps.iter().flatten().fold(
                0.0f64,
                |m, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
            )
        };
        match self {
            RuledCurve::Point(p) => max(&[*p]),
            RuledCurve::Polyline { vertices, .. } => max(vertices),
            RuledCurve::Circle { center, radius } => max(&[*center]) + radius,
            RuledCurve::Expr(_) => {
                let (t0, t1) = self.interval();
                let ps: Vec<[f64; 3]> = (0..9)
                    .map(|i| self.eval(super::expr_patch::local_to_param(i as f64 / 8.0, t0, t1)))
                    .collect();
                max(&ps)
            }
        }
    }

    fn vertices_closed(&self) -> Vec<[f64; 3]> {
        match self {
            RuledCurve::Polyline { vertices, closed } => {
                let mut v = vertices.clone();
                if *closed {
                    v.push(vertices[0]);
                }
                v
            }
            _ => vec![],
        }
    }

    /// The point at the curve's own parameter τ (polylines clamp τ to their interval, like
    /// the ramp does).
    pub fn eval(&self, tau: f64) -> [f64; 3] {
        match self {
            RuledCurve::Expr(e) => {
                let p = e.eval(&[tau]).expect("one parameter");
                [p[0], p[1], p[2]]
            }
            RuledCurve::Point(p) => *p,
            RuledCurve::Circle { center, radius } => [
                center[0] + radius * tau.cos(),
                center[1] + radius * tau.sin(),
                center[2],
            ],
            RuledCurve::Polyline { vertices, closed } => {
                // Vertex k of the closed list without building it (O(1) per point: a copy of
                // the vertices here made meshing quadratic in a polygon's size).
                let n = vertices.len() + usize::from(*closed);
                let v = |k: usize| vertices[k % vertices.len()];
                let last = (n - 1) as f64;
                let t = tau.clamp(0.0, last);
                let k = (t.floor() as usize).min(n - 2);
                let f = t - k as f64;
                let (a, b) = (v(k), v(k + 1));
                [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))
            }
        }
    }
}

fn check_vertices(vertices: &[[f64; 3]], min: usize) -> Result<()> {
    if vertices.len() < min {
        return Err(Error::TooFewPoints {
            what: "polyline vertices",
            got: vertices.len(),
            min,
        });
    }
    if let Some(index) = vertices
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(Error::NonFinite {
            what: "vertex",
            index,
        });
    }
    if let Some(index) = vertices.windows(2).position(|w| w[0] == w[1]) {
        return Err(Error::InvalidShape {
            what: "polyline",
            reason: format!("vertices {index} and {} coincide", index + 1),
        });
    }
    Ok(())
}

/// A piecewise-ruled surface: curves r_0..r_n at v_0 < ... < v_n over the common parameter
/// interval [u0, u1].
#[derive(Debug, Clone, PartialEq)]
pub struct RuledSurface {
    curves: Vec<RuledCurve>,
    v: Axis,
    u_range: (f64, f64),
}

/// f = content · primitive ([`AbsSum::content`]) when both print and evaluate well: the
/// content an exact short rational and every coefficient of the primitive a normal f64 of
/// moderate size; else (1, f). (Data near 1e-300 gave a content that rounded to 0 in f64
/// and wiped the coordinate out, or primitives with integers beyond f64.)
fn factored(f: &AbsSum) -> (Rational, AbsSum) {
    let (content, prim) = f.content();
    let moderate = |q: &Rational| {
        let x = crate::exact::rational_to_f64(q).abs();
        x == 0.0 || (1e-200..1e200).contains(&x)
    };
    let short = matches!(konst(&content), Const::Rat(_)) && moderate(&content);
    let coefs = std::iter::once(prim.constant_term())
        .chain(std::iter::once(prim.slope()))
        .chain(prim.terms().flat_map(|(k, c)| [k, c]));
    if short && coefs.into_iter().all(moderate) {
        (content, prim)
    } else {
        (Rational::one(), f.clone())
    }
}

/// One coordinate of one curve, as a function of u.
enum Coord {
    Constant(Rational),
    Linear(AbsSum),
    Expr(Id),
}

impl RuledSurface {
    /// The surface over `curves` at the values `v` (strictly increasing, one per curve),
    /// with every curve reparametrized onto `u_range`. Errors: fewer than 2 curves, a count
    /// of v values other than the number of curves, v not strictly increasing, an empty or
    /// non-finite u range, a circle radius that is not > 0.
    pub fn new(curves: Vec<RuledCurve>, v: Vec<f64>, u_range: (f64, f64)) -> Result<Self> {
        if curves.len() < 2 {
            return Err(Error::TooFewPoints {
                what: "curves of a ruled surface",
                got: curves.len(),
                min: 2,
            });
        }
        if v.len() != curves.len() {
            return Err(Error::PatchCount {
                what: format!("v values for {} curves", curves.len()),
                expected: curves.len(),
                got: v.len(),
            });
        }
        check_increasing("v values", &v)?;
        check_increasing("u range", &[u_range.0, u_range.1])?;
        for c in &curves {
            match c {
                RuledCurve::Circle { center, radius } => {
                    if !(radius.is_finite() && *radius > 0.0) {
                        return Err(Error::InvalidShape {
                            what: "circle",
                            reason: format!("radius {radius} must be finite and > 0"),
                        });
                    }
                    if center.iter().any(|x| !x.is_finite()) {
                        return Err(Error::NonFinite {
                            what: "circle centre",
                            index: 0,
                        });
                    }
                }
                RuledCurve::Point(p) => {
                    if p.iter().any(|x| !x.is_finite()) {
                        return Err(Error::NonFinite {
                            what: "point",
                            index: 0,
                        });
                    }
                }
                RuledCurve::Polyline { vertices, .. } => check_vertices(vertices, 2)?,
                RuledCurve::Expr(e) => {
                    if e.dim() != 3 || e.vars().len() != 1 {
                        return Err(Error::InvalidShape {
                            what: "curve",
                            reason: format!(
                                "a curve of a ruled surface has 3 coordinates in 1 variable, \
                                 not {} in {}",
                                e.dim(),
                                e.vars().len()
                            ),
                        });
                    }
                    let (t0, t1) = c.interval();
                    e.check_finite(&[(t0, t1)])?;
                }
            }
        }
        for (k, c) in curves.iter().enumerate() {
            if c.magnitude().is_nan() || c.magnitude() > MAX_RULED_COORDINATE {
                return Err(Error::Overflow {
                    what: format!("curve {k} of the ruled surface"),
                    step: format!(
                        "its coordinates exceed f64::MAX/2 = {MAX_RULED_COORDINATE:.3e} in \
                         absolute value (the differences between neighbouring curves would \
                         overflow f64)"
                    ),
                });
            }
        }
        Ok(RuledSurface {
            curves,
            v: Axis::new("v values", v)?,
            u_range,
        })
    }

    /// The curves.
    pub fn curves(&self) -> &[RuledCurve] {
        &self.curves
    }

    /// The values v_k.
    pub fn v_values(&self) -> &[f64] {
        self.v.knots()
    }

    /// Parameter domain ((u0, u1), (v_0, v_n)).
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        let v = self.v.knots();
        (self.u_range, (v[0], v[v.len() - 1]))
    }

    /// τ_k(u) = τ0 + (τ1 - τ0)(u - u0)/(u1 - u0): curve k's own parameter at u.
    fn tau(&self, k: usize, u: f64) -> f64 {
        let (t0, t1) = self.curves[k].interval();
        let (u0, u1) = self.u_range;
        t0 + (t1 - t0) * (u - u0) / (u1 - u0)
    }

    /// The structural evaluator: the two curves around v (clamped to [v_0, v_n]) and the
    /// straight line between them, O(log n).
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let (p, lambda) = self.v.locate(v);
        let a = self.curves[p].eval(self.tau(p, u));
        let b = self.curves[p + 1].eval(self.tau(p + 1, u));
        for c in 0..3 {
            out[c] = a[c] + lambda * (b[c] - a[c]);
        }
    }

    /// [`Self::eval_into`] into a new vector.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; 3];
        self.eval_into(u, v, &mut out);
        out
    }

    /// Evaluates on the grid `us` × `vs` (point (a, b) at `out[(a * vs.len() + b) * 3 ..]`).
    /// Errors: wrong buffer length, non-finite parameters.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        crate::points::check_eval_args("parameter u", us, us.len() * vs.len(), 3, out)?;
        crate::points::check_eval_args("parameter v", vs, 0, 3, &[])?;
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let k = (a * vs.len() + b) * 3;
                self.eval_into(u, v, &mut out[k..k + 3]);
            }
        }
        Ok(())
    }

    /// Formula (2) in f64, literally: r_0(u) + Σ_k (r_k(u) - r_(k-1)(u)) P(v, v_(k-1), Δv_k).
    pub fn eval_formula(&self, u: f64, v: f64) -> Vec<f64> {
        let vk = self.v.knots();
        let mut out = self.curves[0].eval(self.tau(0, u)).to_vec();
        for k in 1..self.curves.len() {
            let p = super::ramp(v, vk[k - 1], vk[k] - vk[k - 1]);
            let a = self.curves[k - 1].eval(self.tau(k - 1, u));
            let b = self.curves[k].eval(self.tau(k, u));
            for c in 0..3 {
                out[c] += (b[c] - a[c]) * p;
            }
        }
        out
    }

    /// The single formula (2) with the ramps written out by (1), grouped by curve (see the
    /// module docs): x, y, z in u, v.
    ///
    /// Errors: [`Error::Overflow`] naming the coordinate when a coefficient is not a finite
    /// f64 or the terms could overflow f64 on the domain widened by its span;
    /// [`Error::Underflow`] when a nonzero coefficient falls below the smallest normal f64.
    pub fn formula(&self) -> Result<Formula> {
        let mut g = Graph::new();
        let u = g.var("u");
        let v = g.var("v");
        let vk: Vec<Rational> = self
            .v
            .knots()
            .iter()
            .enumerate()
            .map(|(k, &x)| exact("v value", k, x))
            .collect::<Result<_>>()?;
        let n = self.curves.len();
        // Hat weights w_k = P_k - P_(k+1), P_0 = 1, P_n+1 = 0.
        let mut ramps = vec![AbsSum::constant(Rational::one())];
        for k in 1..n {
            ramps.push(AbsSum::ramp(&vk[k - 1], &(&vk[k] - &vk[k - 1]))?);
        }
        ramps.push(AbsSum::default());
        let weights: Vec<AbsSum> = (0..n)
            .map(|k| {
                let mut w = ramps[k].clone();
                w.add_scaled(&ramps[k + 1], &-Rational::one());
                w
            })
            .collect();
        let (u0, u1) = (
            exact("u range", 0, self.u_range.0)?,
            exact("u range", 1, self.u_range.1)?,
        );
        let mut roots = Vec::with_capacity(3);
        for c in 0..3 {
            let mut constant = AbsSum::default();
            // (key, weight): curves whose coordinate is the same function share one weight.
            let mut linear: Vec<(AbsSum, AbsSum)> = Vec::new();
            let mut exprs: Vec<(Id, AbsSum)> = Vec::new();
            for (k, w) in weights.iter().enumerate() {
                match self.coordinate(&mut g, k, c, u, &u0, &u1)? {
                    Coord::Constant(q) => constant.add_scaled(w, &q),
                    Coord::Linear(f) => {
                        let (content, prim) = factored(&f);
                        match linear.iter_mut().find(|(key, _)| *key == prim) {
                            Some((_, acc)) => acc.add_scaled(w, &content),
                            None => linear.push((prim, w.scaled(&content))),
                        }
                    }
                    Coord::Expr(id) => match exprs.iter_mut().find(|(key, _)| *key == id) {
                        Some((_, acc)) => acc.add_scaled(w, &Rational::one()),
                        None => exprs.push((id, w.clone())),
                    },
                }
            }
            let mut terms: Vec<Id> = Vec::new();
            if !constant.is_zero() {
                terms.push(abs_sum_expr(&mut g, &constant, v));
            }
            let keyed: Vec<(Id, AbsSum)> = linear
                .into_iter()
                .map(|(key, w)| (abs_sum_expr(&mut g, &key, u), w))
                .chain(exprs)
                .collect();
            for (f, w) in keyed {
                if w.is_zero() {
                    continue;
                }
                let (content, prim) = factored(&w);
                let wv = abs_sum_expr(&mut g, &prim, v);
                let cid = g.constant(konst(&content));
                terms.push(g.product(&[cid, f, wv]));
            }
            roots.push(g.sum(&terms));
        }
        let ((u0f, u1f), (v0f, v1f)) = self.domain();
        let bounds = [
            ("u", variable_bound(u0f, u1f)),
            ("v", variable_bound(v0f, v1f)),
        ];
        let groups: Vec<Vec<Id>> = roots.iter().map(|&r| vec![r]).collect();
        check_terms(&g, &roots, &bounds, &Hints::default()).map_err(|e| {
            e.in_groups(
                &g,
                &groups,
                |c| format!("formula (2), coordinate {}", ["x", "y", "z"][c]),
                "formula (2)",
            )
        })?;
        Ok(Formula {
            graph: g,
            roots,
            names: vec!["x".into(), "y".into(), "z".into()],
            vars: vec!["u".into(), "v".into()],
        })
    }

    /// Coordinate c of curve k as a function of u.
    fn coordinate(
        &self,
        g: &mut Graph,
        k: usize,
        c: usize,
        u: Id,
        u0: &Rational,
        u1: &Rational,
    ) -> Result<Coord> {
        let curve = &self.curves[k];
        let (t0, t1) = curve.interval();
        Ok(match curve {
            RuledCurve::Expr(e) => {
                // τ = t0 + (t1 - t0) (u - u0)/(u1 - u0).
                let u0c = g.constant(konst(&-u0.clone()));
                let inv = g.constant(konst(&(Rational::one() / (u1 - u0))));
                let shifted = g.add(u, u0c);
                let local = g.mul(inv, shifted);
                let coords = e.place_local(g, &[local], &[(t0, t1)]);
                let id = coords[c];
                match g.as_const(id) {
                    Some(Const::Rat(q)) => Coord::Constant(q.clone()),
                    Some(Const::Float(x)) => Coord::Constant(exact("curve coordinate", c, *x)?),
                    None => Coord::Expr(id),
                }
            }
            RuledCurve::Point(p) => Coord::Constant(exact("point coordinate", c, p[c])?),
            RuledCurve::Polyline { .. } => {
                let verts = curve.vertices_closed();
                let knots: Vec<Rational> = (0..verts.len())
                    .map(|i| Rational::from_integer((i as i64).into()))
                    .collect();
                let values: Vec<Rational> = verts
                    .iter()
                    .enumerate()
                    .map(|(i, p)| exact("vertex coordinate", i, p[c]))
                    .collect::<Result<_>>()?;
                // τ = t0 + (t1 - t0)(u - u0)/(u1 - u0) = a + b u.
                let t1q = exact("interval", 1, t1)?;
                let b = &t1q / (u1 - u0);
                let a = -(&b * u0);
                let f = AbsSum::through(&knots, &values)?.reparametrized(&a, &b);
                if f.is_constant() {
                    Coord::Constant(f.constant_term().clone())
                } else {
                    Coord::Linear(f)
                }
            }
            RuledCurve::Circle { center, radius } => {
                if c == 2 {
                    return Ok(Coord::Constant(exact("circle centre", 2, center[2])?));
                }
                // τ = 2π (u - u0)/(u1 - u0), printed with a symbolic π unless u spans 2π.
                let (u0f, u1f) = self.u_range;
                let tau = if u0f == 0.0 && u1f == t1 - t0 {
                    u
                } else {
                    let pi = g.pi();
                    let scale = g.constant(konst(&(Rational::from_integer(2.into()) / (u1 - u0))));
                    let shift = g.constant(konst(&-u0.clone()));
                    let d = g.add(u, shift);
                    g.product(&[pi, scale, d])
                };
                let trig = if c == 0 { g.cos(tau) } else { g.sin(tau) };
                let r = num(g, *radius);
                let m = g.mul(r, trig);
                let cc = num(g, center[c]);
                let e = if center[c] == 0.0 { m } else { g.add(cc, m) };
                Coord::Expr(e)
            }
        })
    }
}

impl RuledCurve {
    /// The `order`-th derivative with respect to the curve's own parameter τ: points have
    /// none (zero), circles every order (r (cos, sin)(τ + kπ/2), 0), polylines the slope of
    /// the edge holding τ (the edge on the right at a vertex, zero beyond the ends where τ
    /// is clamped) and zero from order 2 on, formula curves the engine's symbolic
    /// derivative. Errors: [`Error::Expression`] if that does not compile.
    fn derivative(&self, tau: f64, order: usize) -> Result<[f64; 3]> {
        if order == 0 {
            return Ok(self.eval(tau));
        }
        match self {
            RuledCurve::Point(_) => Ok([0.0; 3]),
            RuledCurve::Circle { radius, .. } => {
                let phase = tau + order as f64 * std::f64::consts::FRAC_PI_2;
                Ok([radius * phase.cos(), radius * phase.sin(), 0.0])
            }
            RuledCurve::Polyline { .. } => {
                let v = self.vertices_closed();
                let last = (v.len() - 1) as f64;
                if order > 1 || !(0.0..=last).contains(&tau) {
                    return Ok([0.0; 3]);
                }
                let k = (tau.floor() as usize).min(v.len() - 2);
                Ok([0, 1, 2].map(|c| v[k + 1][c] - v[k][c]))
            }
            RuledCurve::Expr(e) => {
                let p = e.derivative(order)?.eval(&[tau])?;
                Ok([p[0], p[1], p[2]])
            }
        }
    }
}

/// One curve of a ruled surface (spec/composite-surfaces.md formula (2)) on its own
/// parameter interval.
impl Curve for RuledCurve {
    /// 3.
    fn dim(&self) -> usize {
        3
    }

    /// [`RuledCurve::interval`].
    fn domain(&self) -> (f64, f64) {
        self.interval()
    }

    fn eval_into(&self, t: f64, out: &mut [f64]) {
        out.copy_from_slice(&self.eval(t));
    }

    /// Points: zero; circles: every order; polylines: the edge's slope, then zero; formula
    /// curves: the symbolic derivative. Errors: [`Error::Expression`] if that does not
    /// compile.
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], 3, out)?;
        out.copy_from_slice(&self.derivative(t, order)?);
        Ok(())
    }

    /// The inner vertices of polylines (their parameters 1, 2, ...).
    fn breaks(&self) -> Vec<f64> {
        match self {
            RuledCurve::Polyline { .. } => {
                let (_, t1) = self.interval();
                (1..t1 as usize).map(|k| k as f64).collect()
            }
            _ => Vec::new(),
        }
    }
}

/// Formula (2) of spec/composite-surfaces.md by its structural evaluator.
impl Surface for RuledSurface {
    /// 3.
    fn dim(&self) -> usize {
        3
    }

    crate::geom::forward_to_inherent!(RuledSurface; surface_domain, surface_eval_into, eval_grid);

    /// With S = a(u) + λ(v)(b(u) - a(u)) between the curves a, b around v:
    /// ∂^ku a/∂u^ku = a^(ku)(τ) (dτ/du)^ku, then kv = 0: a + λ(b - a), kv = 1:
    /// (b - a)/Δv, kv >= 2: zero (at a curve, the strip above it). Errors: those of the
    /// curves' derivatives.
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], 3, out)?;
        if kv >= 2 {
            out.fill(0.0);
            return Ok(());
        }
        let (p, lambda) = self.v.locate(v);
        let (u0, u1) = self.u_range;
        let side = |k: usize| -> Result<[f64; 3]> {
            let (t0, t1) = self.curves[k].interval();
            let scale = ((t1 - t0) / (u1 - u0)).powi(ku as i32);
            let d = self.curves[k].derivative(self.tau(k, u), ku)?;
            Ok(d.map(|x| x * scale))
        };
        let (a, b) = (side(p)?, side(p + 1)?);
        let vk = self.v.knots();
        for c in 0..3 {
            out[c] = if kv == 0 {
                a[c] + lambda * (b[c] - a[c])
            } else {
                (b[c] - a[c]) / (vk[p + 1] - vk[p])
            };
        }
        Ok(())
    }

    /// The v of every curve, and the u of every polyline vertex (each curve is mapped
    /// linearly onto the common u range).
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        let ((u0, u1), _) = RuledSurface::domain(self);
        let mut bu = Vec::new();
        for c in self.curves() {
            if let RuledCurve::Polyline { .. } = c {
                let (t0, t1) = c.interval();
                let segments = (t1 - t0).round() as usize;
                bu.extend((0..=segments).map(|k| u0 + (u1 - u0) * k as f64 / segments as f64));
            }
        }
        (bu, self.v_values().to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formula_literal_equals_structural() {
        let s = RuledSurface::new(
            vec![
                RuledCurve::Point([0.0, 0.0, 2.0]),
                RuledCurve::Circle {
                    center: [0.0, 0.0, 1.0],
                    radius: 1.5,
                },
                RuledCurve::polygon(vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
                    .unwrap(),
            ],
            vec![0.0, 0.5, 2.0],
            (0.0, 3.0),
        )
        .unwrap();
        for u in [-1.0, 0.0, 0.7, 1.5, 3.0, 4.0] {
            for v in [-1.0, 0.0, 0.25, 0.5, 1.3, 2.0, 3.0] {
                let a = s.eval(u, v);
                let b = s.eval_formula(u, v);
                for c in 0..3 {
                    assert!((a[c] - b[c]).abs() < 1e-14, "{u} {v}");
                }
            }
        }
        assert!(
            RuledSurface::new(vec![RuledCurve::Point([0.0; 3])], vec![0.0], (0.0, 1.0)).is_err()
        );
    }
}
