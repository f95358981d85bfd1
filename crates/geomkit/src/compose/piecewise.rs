//! The 1-D case of spec/composite-surfaces.md §5: a piecewise function or composite curve
//! with pieces f_i on [x_i, x_(i+1)] as one formula
//! F(x) = F_0(x) + Σ_(i>=1) (F_i(x) - F_i(x_i)), F_i(x) = f_i(x_i + (x_(i+1) - x_i) P(x, x_i,
//! x_(i+1) - x_i)), with the continuity report at the breakpoints and a structural
//! evaluator equal to the formula (a piece that does not meet its left neighbour is shifted
//! by the jump, as the formula does). Polylines and polygons are the linear case, written
//! the paper's way as sums of |x - x_i| ([`AbsSum::through`]).
//!
//! # The convention at breakpoints and beyond the knots
//! One rule, the paper's formula, which [`Piecewise::formula`], [`Piecewise::eval_formula`]
//! and the structural [`Piecewise::eval`] (and so `geomkit eval`) follow alike:
//! F = f_0 on [x_0, x_1] and, on each later [x_i, x_(i+1)], F = f_i + s_i with the shift
//! s_i = Σ_(k=1..i) (f_(k-1)(x_k) - f_k(x_k)), the jumps at the breakpoints before it. So F
//! is continuous and has one value at every breakpoint, which both neighbouring pieces give
//! (the interval of each piece is closed: no half-open choice is needed). Where the pieces
//! jump, the [`ContinuityReport`] says so and the formula does not reproduce the jump: it
//! keeps f_0 and shifts the later pieces to stay attached (the paper's formula is
//! continuous by construction: a sum of continuous ramps cannot jump). Beyond the knots F
//! is constant: F(x_0) for x < x_0, F(x_n) for x > x_n.
//!
//! Each piece is evaluated only on its own closed interval: the paper's argument
//! x_i + (x_(i+1) - x_i) P(x, x_i, x_(i+1) - x_i) is x clamped to it. In exact arithmetic
//! (a symbolic system) that holds as printed. In f64 the ramp's |.| terms round, and the
//! argument may leave the interval by an ulp (further for x far beyond the knots): harmless
//! for a polynomial, but `sqrt(x)` on [0, 1] would give NaN, and NaN spreads to every x
//! through the sum. So pieces that may be undefined for a finite argument (sqrt, ln, asin,
//! acos, tan, a division or negative power) get their argument written with `sign`, a form
//! equal in value that stays in the interval in f64 too ([`ExprPatch`]'s clamped placement;
//! the only difference from the paper: a longer formula for those pieces). A piece must be
//! finite at both ends of its interval (its value there enters the formula at every x): an
//! error otherwise. A piece not finite somewhere inside its interval (7 samples) is a
//! warning ([`Piecewise::warnings`]): the formula is not finite there either, and only there.
//!
//! Accuracy in f64: the formula and the evaluator agree to a few ulps of the values for
//! smooth pieces; for a piece with an infinite slope at an end of its interval (sqrt at
//! its zero, acos at ±1) one rounding of the ramp becomes about sqrt(ε) ≈ 1.5e-8 there.
//! Far beyond the knots the ramps' rounding grows like ε |x| / (smallest interval), so
//! the held end values drift by that much times the pieces' slopes.
//!
//! Limits: the knots span at most [`super::MAX_KNOT_SPAN`] (f64::MAX/2), each interval at
//! least [`super::MIN_KNOT_WIDTH`] (the smallest normal f64); a formula whose coefficients
//! or terms could overflow f64 on the knots' interval is refused ([`Error::Overflow`]
//! naming the piece), as are polylines whose consecutive points differ by more than f64
//! holds.
//!
//! ```
//! use geomkit::compose::Piecewise;
//! // |x| on [-1, 1] from two pieces, then a constant.
//! let f = Piecewise::function(vec![-1.0, 0.0, 1.0, 2.0], &["-x", "x", "1"]).unwrap();
//! assert!(f.continuity().is_continuous());
//! assert_eq!(f.eval(-0.5), vec![0.5]);
//! let text = f.formula().unwrap().print(geomkit::expr::Format::Maple).unwrap();
//! assert!(text.starts_with("f := (x) -> "), "{text}");
//! ```

use super::expr_patch::{ExprPatch, Local};
use super::formula::{abs_sum_expr, check_terms, knot_hints, variable_bound, Formula, Hints};
use super::grid::{show, Axis};
use super::linear::{exact, AbsSum};
use super::ramp::ramp;
use super::surface::{ramps, ContinuityReport, GridLine, Jump};
use crate::exact::Rational;
use crate::expr::{Graph, Id};
use crate::geom::{check_point, Curve};
use crate::{Error, Result};

/// A piecewise function (one coordinate, variable x) or composite curve (2 or more
/// coordinates, variable t) over knots x_0 < ... < x_n.
#[derive(Debug, Clone)]
pub struct Piecewise {
    axis: Axis,
    var: String,
    names: Vec<String>,
    pieces: Pieces,
    report: ContinuityReport,
    warnings: Vec<String>,
}

#[derive(Debug, Clone)]
enum Pieces {
    /// Formula pieces on their domains; `shifts[i]` = Σ_(k=1..i) (f_(k-1)(end) - f_k(start)).
    Expr {
        pieces: Vec<ExprPatch>,
        domains: Vec<(f64, f64)>,
        shifts: Vec<Vec<f64>>,
    },
    /// Values at the knots, linear in between.
    Linear { values: Vec<Vec<f64>> },
}

fn coordinate_names(dim: usize) -> Vec<String> {
    match dim {
        1 => vec!["f".into()],
        2 | 3 => ["x", "y", "z"][..dim]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        _ => (0..dim).map(|k| format!("x{k}")).collect(),
    }
}

impl Piecewise {
    /// A function with pieces given as formulas in x: `pieces[i]` on \[knots\[i\],
    /// knots[i+1]]. Errors: knots not finite and strictly increasing, a count of pieces
    /// other than knots - 1, [`Error::Expression`] naming the piece for a formula that does
    /// not parse (with the position) or is not finite on its interval.
    pub fn function(knots: Vec<f64>, pieces: &[&str]) -> Result<Self> {
        let parsed = pieces
            .iter()
            .enumerate()
            .map(|(i, p)| ExprPatch::parse(&[("f", p)], &["x"], None).map_err(|e| in_piece(e, i)))
            .collect::<Result<Vec<_>>>()?;
        Self::from_pieces(knots, parsed, "x")
    }

    /// Pieces given as formulas in one variable `var` (a function for one coordinate, a
    /// composite curve for more), each on its own domain mapped linearly onto \[knots\[i\],
    /// knots[i+1]] or, without one, defined there. Errors: as [`Self::function`]; pieces of
    /// different dimensions or in other than one variable.
    pub fn from_pieces(knots: Vec<f64>, pieces: Vec<ExprPatch>, var: &str) -> Result<Self> {
        let axis = Axis::new("knots", knots)?;
        check_count(&axis, pieces.len())?;
        let dim = pieces[0].dim();
        let mut domains = Vec::with_capacity(pieces.len());
        let mut warnings = Vec::new();
        for (i, p) in pieces.iter().enumerate() {
            if p.dim() != dim {
                return Err(Error::DimensionMismatch {
                    what: "piece",
                    index: i,
                    expected: dim,
                    got: p.dim(),
                });
            }
            if p.vars().len() != 1 {
                return Err(Error::WrongDimension {
                    operation: "the variables of a piece",
                    expected: 1,
                    got: p.vars().len(),
                });
            }
            let d = p
                .domain()
                .map_or((axis.knots()[i], axis.knots()[i + 1]), |d| d[0]);
            // Its ends enter the formula at every x (F_i(x_i) is a constant of it, and
            // beyond its interval its argument is held at an end): they must be finite.
            p.check_finite_at(&[d], &[0.0, 1.0])
                .map_err(|e| at_piece_end(in_piece(e, i)))?;
            // Inside, a non-finite value stays where it is: a warning.
            if let Err(e) = p.check_finite_at(&[d], &INTERIOR_SAMPLES) {
                warnings.push(format!(
                    "{}; the single formula is not finite there either (only there)",
                    in_piece(e, i)
                ));
            }
            domains.push(d);
        }
        let ends: Vec<(Vec<f64>, Vec<f64>)> = pieces
            .iter()
            .zip(&domains)
            .map(|(p, d)| {
                let mut out = vec![0.0; 2 * dim];
                p.eval_local_many(&[*d], &[&[0.0, 1.0]], &mut out);
                (out[..dim].to_vec(), out[dim..].to_vec())
            })
            .collect();
        let mut shifts = vec![vec![0.0; dim]];
        for i in 1..pieces.len() {
            let prev = shifts[i - 1].clone();
            let s: Vec<f64> = (0..dim)
                .map(|k| prev[k] + (ends[i - 1].1[k] - ends[i].0[k]))
                .collect();
            if s.iter().any(|x| !x.is_finite()) {
                return Err(Error::Overflow {
                    what: format!("piece {i}"),
                    step: "the shift formula §5 adds to it (the sum of the jumps at the \
                           breakpoints before it) overflows f64: values near the end of its \
                           range"
                        .into(),
                });
            }
            shifts.push(s);
        }
        let report = breakpoint_report(
            axis.knots(),
            ends.iter().map(|e| (e.0.as_slice(), e.1.as_slice())),
        )?;
        Ok(Piecewise {
            axis,
            var: var.into(),
            names: coordinate_names(dim),
            pieces: Pieces::Expr {
                pieces,
                domains,
                shifts,
            },
            report,
            warnings,
        })
    }

    /// The B-spline curve `c` on its domain as pieces in t: one polynomial per non-empty
    /// knot span (its Bézier segment by de Boor's triangle, in power form of the span's own
    /// parameter s = (t - t_i) / (t_(i+1) - t_i), well conditioned on \[0, 1\]), the knots
    /// its distinct knots there. The single formula then equals the curve on its domain:
    /// a curve interpolated through measured points (method 2) becomes one formula for a
    /// symbolic system. Continuity at the knots is that of the spline (C2 for the cubics
    /// of interpolation), up to rounding. Errors: [`Error::InvalidKnots`] for a knot inside
    /// the domain repeated degree + 1 times (the curve jumps there, and the formula of §5
    /// joins its pieces continuously).
    ///
    /// ```
    /// use geomkit::bspline::{interpolate_curve, InterpolationOptions};
    /// use geomkit::compose::Piecewise;
    /// let pts = vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![3.0, 3.0], vec![4.0, 0.0]];
    /// let fit = interpolate_curve(&pts, &InterpolationOptions::default()).unwrap();
    /// let f = Piecewise::from_bspline(fit.curve()).unwrap();
    /// assert_eq!(f.knots(), fit.parameters());
    /// let at = f.eval_formula(fit.parameters()[2]);
    /// assert!((at[0] - 3.0).abs() < 1e-13 && (at[1] - 3.0).abs() < 1e-13);
    /// ```
    pub fn from_bspline(c: &crate::bspline::BsplineCurve) -> Result<Self> {
        let (p, dim, knots) = (c.degree(), c.dim(), c.knots());
        let n = c.n_control();
        let inside = |i: usize| knots[p] < knots[i] && knots[i] < knots[n];
        if let Some(i) = (p + 1..n).find(|&i| knots[i + p] == knots[i] && inside(i)) {
            return Err(Error::InvalidKnots {
                index: i,
                reason: "a knot repeated degree + 1 times makes the curve jump there",
            });
        }
        let spans = super::poly::spans(knots, p, n);
        let names = coordinate_names(dim);
        let mut breaks: Vec<f64> = spans.iter().map(|&s| knots[s]).collect();
        breaks.extend(spans.last().map(|&s| knots[s + 1]));
        let pieces = spans
            .iter()
            .enumerate()
            .map(|(i, &s)| {
                let ctrl = &c.control_flat()[(s - p) * dim..];
                let bez = super::poly::bezier_points_of_span(knots, p, s, ctrl, dim);
                let overflow = |step: &str| Error::Overflow {
                    what: format!(
                        "span {i} [{}, {}] of the B-spline curve",
                        show(knots[s]),
                        show(knots[s + 1])
                    ),
                    step: format!("{step} overflow f64: control points near the end of its range"),
                };
                let bezier = crate::bezier::BezierCurve::from_flat(dim, bez)
                    .map_err(|_| overflow("its Bézier points (de Boor's triangle)"))?;
                let power = bezier.to_power();
                if power.iter().any(|x| !x.is_finite()) {
                    return Err(overflow("its power-form coefficients"));
                }
                ExprPatch::from_power(&power, &names, "s")
            })
            .collect::<Result<Vec<_>>>()?;
        Self::from_pieces(breaks, pieces, "t")
    }

    /// The polyline through `points` (each of the same dimension; a polygon when `closed`,
    /// back to the first point), point k at `knots[k]` (default k). One coordinate is a
    /// piecewise-linear function of x; more are a curve in t. Continuous by construction.
    /// Errors: fewer than 2 points, points of different dimensions or not finite, knots not
    /// finite and strictly increasing or not one per point.
    pub fn polyline(points: Vec<Vec<f64>>, knots: Option<Vec<f64>>, closed: bool) -> Result<Self> {
        if points.len() < 2 {
            return Err(Error::TooFewPoints {
                what: "polyline points",
                got: points.len(),
                min: 2,
            });
        }
        let dim = points[0].len();
        for (i, p) in points.iter().enumerate() {
            if p.len() != dim || dim == 0 {
                return Err(Error::DimensionMismatch {
                    what: "point",
                    index: i,
                    expected: dim.max(1),
                    got: p.len(),
                });
            }
            if let Some(c) = p.iter().position(|x| !x.is_finite()) {
                return Err(Error::NonFinite {
                    what: "point coordinate",
                    index: i * dim + c,
                });
            }
        }
        let mut values = points;
        if closed {
            values.push(values[0].clone());
        }
        let n = values.len();
        if let Some(i) =
            (0..n - 1).find(|&i| (0..dim).any(|c| !(values[i + 1][c] - values[i][c]).is_finite()))
        {
            return Err(Error::Overflow {
                what: format!(
                    "polyline points {i} and {}",
                    (i + 1) % (n - usize::from(closed))
                ),
                step: "the difference of their coordinates overflows f64: values near the end \
                       of its range"
                    .into(),
            });
        }
        let knots = knots.unwrap_or_else(|| (0..values.len()).map(|k| k as f64).collect());
        let axis = Axis::new("knots", knots)?;
        check_count(&axis, values.len() - 1)?;
        let ends = values
            .windows(2)
            .map(|w| (w[0].as_slice(), w[1].as_slice()));
        let report = breakpoint_report(axis.knots(), ends)?;
        Ok(Piecewise {
            axis,
            var: if dim == 1 { "x" } else { "t" }.into(),
            names: coordinate_names(dim),
            pieces: Pieces::Linear { values },
            report,
            warnings: Vec::new(),
        })
    }

    /// The knots x_0 < ... < x_n.
    pub fn knots(&self) -> &[f64] {
        self.axis.knots()
    }

    /// The variable (`x` for functions, `t` for curves).
    pub fn var(&self) -> &str {
        &self.var
    }

    /// Number of coordinates (1 for a function).
    pub fn dim(&self) -> usize {
        self.names.len()
    }

    /// The jumps between neighbouring pieces at the breakpoints x_1..x_(n-1)
    /// ([`GridLine::U`] i for breakpoint i).
    pub fn continuity(&self) -> &ContinuityReport {
        &self.report
    }

    /// A sentence for users: continuous, or where not and what the formula then does.
    pub fn statement(&self) -> String {
        let r = &self.report;
        match r.worst() {
            None => "a single piece: nothing to join".into(),
            Some(_) if r.is_continuous() => format!(
                "continuous: the largest jump at a breakpoint is {:.2e} (tolerance {:.2e}); \
                 the formula reproduces every piece",
                r.max_jump, r.tolerance
            ),
            Some(w) => format!(
                "NOT continuous: {} of {} breakpoints jump, the largest by {:.3e} at {} = {}; \
                 the single formula is still continuous: it matches piece 0 and shifts the \
                 later pieces to stay attached",
                r.jumps.iter().filter(|j| j.max_jump > r.tolerance).count(),
                r.jumps.len(),
                r.max_jump,
                self.var,
                w.at
            ),
        }
    }

    /// The structural evaluator: locate the piece, evaluate it (plus the shift formula §5
    /// adds after jumps). Equal to the single formula within rounding, everywhere; beyond
    /// the knots the ends are held (P clamps).
    pub fn eval_into(&self, x: f64, out: &mut [f64]) {
        let (i, s) = self.axis.locate(x);
        match &self.pieces {
            Pieces::Expr {
                pieces,
                domains,
                shifts,
            } => {
                pieces[i].eval_local_many(&[domains[i]], &[&[s]], out);
                for (o, sh) in out.iter_mut().zip(&shifts[i]) {
                    *o += sh;
                }
            }
            Pieces::Linear { values } => {
                for (k, o) in out.iter_mut().enumerate() {
                    *o = values[i][k] + s * (values[i + 1][k] - values[i][k]);
                }
            }
        }
    }

    /// The values at the knots of a polyline (`None` for formula pieces): the curve is
    /// linear between them.
    pub fn vertices(&self) -> Option<&[Vec<f64>]> {
        match &self.pieces {
            Pieces::Linear { values } => Some(values),
            Pieces::Expr { .. } => None,
        }
    }

    /// [`Self::eval_into`] into a new vector.
    pub fn eval(&self, x: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim()];
        self.eval_into(x, &mut out);
        out
    }

    /// The single formula of §5 evaluated literally in f64, O(n) per point (the reference).
    pub fn eval_formula(&self, x: f64) -> Vec<f64> {
        let k = self.axis.knots();
        let d = self.dim();
        let mut out = vec![0.0; d];
        match &self.pieces {
            Pieces::Expr {
                pieces, domains, ..
            } => {
                let mut tmp = vec![0.0; 2 * d];
                for (i, p) in pieces.iter().enumerate() {
                    let s = ramp(x, k[i], k[i + 1] - k[i]);
                    p.eval_local_many(&[domains[i]], &[&[s, 0.0]], &mut tmp);
                    for c in 0..d {
                        out[c] += tmp[c] - if i >= 1 { tmp[d + c] } else { 0.0 };
                    }
                }
            }
            Pieces::Linear { values } => {
                out.copy_from_slice(&values[0]);
                for i in 0..values.len() - 1 {
                    let s = ramp(x, k[i], k[i + 1] - k[i]);
                    for c in 0..d {
                        out[c] += (values[i + 1][c] - values[i][c]) * s;
                    }
                }
            }
        }
        out
    }

    /// The single formula: Σ_i (F_i(x) - [i>=1] F_i(x_i)) with the ramps (1) written out and
    /// the knots as exact rationals; polylines as constant + Σ c_i |x - x_i| per coordinate.
    ///
    /// A piece that may be undefined for some finite argument (a square root, a logarithm,
    /// an arc sine or cosine, a tangent, a division: `sqrt(x)` on \[0, 1\]) gets its argument
    /// clamped in a form that keeps it inside its interval also when the formula is
    /// evaluated in f64 (where the ramp's rounding may put x_i + (x_(i+1) - x_i) P an ulp
    /// outside, and NaN would spread to every x): equal in value to the paper's argument,
    /// written with `sign` (see the module docs). Other pieces are written the paper's way.
    ///
    /// Errors: [`Error::Overflow`] naming the piece (or the coordinate of a polyline) when a
    /// coefficient is not a finite f64 or the terms of the formula could overflow f64 on the
    /// knots' interval (values near the end of the f64 range).
    pub fn formula(&self) -> Result<Formula> {
        let mut g = Graph::new();
        let x = g.var(&self.var);
        let k = self.axis.knots();
        let bounds = [(self.var.as_str(), variable_bound(k[0], k[k.len() - 1]))];
        let mut hints = Hints::default();
        knot_hints(&mut g, x, k, &mut hints);
        let (roots, groups, name): (Vec<Id>, Vec<Vec<Id>>, &str) = match &self.pieces {
            Pieces::Expr {
                pieces, domains, ..
            } => {
                let ps = ramps(&mut g, x, k, &mut hints)?;
                let zero = g.int(0);
                let mut sums = vec![Vec::new(); self.dim()];
                let mut groups = Vec::with_capacity(pieces.len());
                for (i, p) in pieces.iter().enumerate() {
                    let d = [domains[i]];
                    let local = Local::Cell {
                        x,
                        cell: (k[i], k[i + 1]),
                        ramp: ps[i],
                    };
                    let at = p.place_clamped(&mut g, &[local], &d, &mut hints);
                    let start = p.place_clamped(&mut g, &[Local::Const(zero)], &d, &mut hints);
                    let mut group = Vec::with_capacity(self.dim());
                    for (c, sum) in sums.iter_mut().enumerate() {
                        let term = if i >= 1 {
                            g.sub(at[c], start[c])
                        } else {
                            at[c]
                        };
                        sum.push(term);
                        group.push(term);
                    }
                    groups.push(group);
                }
                let roots = sums.iter().map(|t| g.sum(t)).collect();
                (roots, groups, "piece")
            }
            Pieces::Linear { values } => {
                let knots: Vec<Rational> = k
                    .iter()
                    .enumerate()
                    .map(|(i, &k)| exact("knot", i, k))
                    .collect::<Result<_>>()?;
                let roots: Vec<Id> = (0..self.dim())
                    .map(|c| {
                        let vs: Vec<Rational> = values
                            .iter()
                            .enumerate()
                            .map(|(i, p)| exact("point coordinate", i, p[c]))
                            .collect::<Result<_>>()?;
                        Ok(abs_sum_expr(&mut g, &AbsSum::through(&knots, &vs)?, x))
                    })
                    .collect::<Result<_>>()?;
                let groups = roots.iter().map(|&r| vec![r]).collect();
                (roots, groups, "coordinate")
            }
        };
        check_terms(&g, &roots, &bounds, &hints).map_err(|e| {
            e.in_groups(
                &g,
                &groups,
                |i| match name {
                    "piece" => format!("the single formula, piece {i}"),
                    _ => format!("the single formula, coordinate {}", self.names[i]),
                },
                "the single formula, the sum of its pieces",
            )
        })?;
        Ok(Formula {
            graph: g,
            roots,
            names: self.names.clone(),
            vars: vec![self.var.clone()],
        })
    }

    /// What the construction found worth saying but not refusing: pieces that are not
    /// finite somewhere inside their interval (sampled at 7 interior points; the ends must
    /// be finite). There the function and its single formula are not finite either, and
    /// only there: each piece enters the formula only through its own interval. One
    /// sentence each, naming the piece and the point.
    ///
    /// ```
    /// use geomkit::compose::Piecewise;
    /// let f = Piecewise::function(vec![0.0, 1.0, 2.0], &["1/(x - 0.5)", "x"]).unwrap();
    /// assert!(f.warnings()[0].starts_with("piece 0 coordinate f: the value inf at x = 0.5"));
    /// ```
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

/// One piece per knot interval.
fn check_count(axis: &Axis, got: usize) -> Result<()> {
    if got != axis.cells() {
        return Err(Error::PatchCount {
            what: format!("pieces for {} knots", axis.cells() + 1),
            expected: axis.cells(),
            got,
        });
    }
    Ok(())
}

/// An expression error with its place and message rewritten (others unchanged).
fn reword(
    e: Error,
    place: impl FnOnce(String) -> String,
    text: impl FnOnce(String) -> String,
) -> Error {
    match e {
        Error::Expression {
            what,
            message,
            parse,
        } => Error::Expression {
            what: place(what),
            message: text(message),
            parse,
        },
        e => e,
    }
}

/// An expression error inside piece i.
fn in_piece(e: Error, i: usize) -> Error {
    reword(e, |what| format!("piece {i} {what}"), |m| m)
}

/// Jumps |f_(i-1)(end) - f_i(start)| at the breakpoints, from each piece's (start, end).
fn breakpoint_report<'a>(
    knots: &[f64],
    ends: impl Iterator<Item = (&'a [f64], &'a [f64])>,
) -> Result<ContinuityReport> {
    let ends: Vec<(&[f64], &[f64])> = ends.collect();
    let mut scale = 0.0f64;
    for (a, b) in &ends {
        scale = a.iter().chain(b.iter()).fold(scale, |m, x| m.max(x.abs()));
    }
    let jumps: Vec<Jump> = (1..ends.len())
        .map(|i| Jump {
            line: GridLine::U(i),
            cell: 0,
            max_jump: crate::numeric::distance(ends[i - 1].1, ends[i].0),
            at: knots[i],
        })
        .collect();
    if let Some((i, j)) = jumps
        .iter()
        .enumerate()
        .find(|(_, j)| !j.max_jump.is_finite())
    {
        return Err(Error::Overflow {
            what: format!("breakpoint {} at {}", i + 1, show(j.at)),
            step: format!(
                "the jump between pieces {i} and {} overflows f64: values near the end of its \
                 range",
                i + 1
            ),
        });
    }
    Ok(ContinuityReport {
        max_jump: jumps.iter().fold(0.0f64, |m, j| m.max(j.max_jump)),
        jumps,
        tolerance: 64.0 * f64::EPSILON * scale.max(f64::MIN_POSITIVE),
    })
}

/// Local coordinates of the interior samples of a piece's finiteness check (warnings).
const INTERIOR_SAMPLES: [f64; 7] = [0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875];

/// A piece that is not finite at an end of its interval: why that is refused.
fn at_piece_end(e: Error) -> Error {
    reword(
        e,
        |what| what,
        |m| {
            format!(
                "{m} (an end of its interval: its value there enters the single formula at \
                 every point)"
            )
        },
    )
}

/// The structural evaluator of the single formula of spec/composite-surfaces.md §5, on
/// [x_0, x_n] (beyond the knots the ends are held).
impl Curve for Piecewise {
    fn dim(&self) -> usize {
        self.names.len()
    }

    /// [x_0, x_n].
    fn domain(&self) -> (f64, f64) {
        let k = self.axis.knots();
        (k[0], k[k.len() - 1])
    }

    fn eval_into(&self, t: f64, out: &mut [f64]) {
        Piecewise::eval_into(self, t, out)
    }

    /// The derivative of the piece holding x (the one on the right at a knot; zero beyond
    /// the ends, where the formula holds them; the shifts of §5 are constants). Polylines:
    /// the slope (p_(i+1) - p_i)/(x_(i+1) - x_i), zero from order 2 on. Formula pieces:
    /// the engine's symbolic derivative in the piece's own variable, times
    /// (Δ own / Δx)^order for pieces on a domain of their own. Errors:
    /// [`Error::Expression`] if a symbolic derivative does not compile.
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim(), out)?;
        if order == 0 {
            self.eval_into(t, out);
            return Ok(());
        }
        let k = self.axis.knots();
        if t < k[0] || t > k[k.len() - 1] {
            out.fill(0.0);
            return Ok(());
        }
        let (i, s) = self.axis.locate(t);
        match &self.pieces {
            Pieces::Linear { values } => {
                for (c, o) in out.iter_mut().enumerate() {
                    *o = if order > 1 {
                        0.0
                    } else {
                        (values[i + 1][c] - values[i][c]) / (k[i + 1] - k[i])
                    };
                }
            }
            Pieces::Expr {
                pieces, domains, ..
            } => {
                let (a, b) = domains[i];
                pieces[i]
                    .derivative(order)?
                    .eval_local_many(&[domains[i]], &[&[s]], out);
                let scale = ((b - a) / (k[i + 1] - k[i])).powi(order as i32);
                out.iter_mut().for_each(|x| *x *= scale);
            }
        }
        Ok(())
    }

    /// The inner knots x_1..x_(n-1).
    fn breaks(&self) -> Vec<f64> {
        let k = self.axis.knots();
        k[1..k.len() - 1].to_vec()
    }
}

impl Piecewise {
    /// Largest difference between the single formula (evaluated by the engine's tape) and the
    /// structural evaluator ([`Piecewise::eval`]) at `count` points spread over the knots
    /// widened by a quarter on each side (where the ramps of §5 must hold the end pieces),
    /// plus every knot: the check that the printed formula is the piecewise function.
    ///
    /// Errors: the formula's own errors ([`Piecewise::formula`]).
    ///
    /// ```
    /// use geomkit::compose::Piecewise;
    /// let hat = Piecewise::function(vec![0.0, 1.0, 2.0], &["x", "2 - x"]).unwrap();
    /// assert!(hat.formula_deviation(101).unwrap() < 1e-15);
    /// ```
    pub fn formula_deviation(&self, count: usize) -> Result<f64> {
        let f = self.formula()?;
        let k = self.knots();
        let (a, b) = (k[0], k[k.len() - 1]);
        let mut xs = crate::geom::linspace(a - (b - a) / 4.0, b + (b - a) / 4.0, count);
        xs.extend_from_slice(k);
        let d = self.dim();
        let mut out = vec![0.0; xs.len() * d];
        f.eval_batch(&[&xs], &mut out)?;
        let mut worst = 0.0f64;
        for (x, q) in xs.iter().zip(out.chunks_exact(d)) {
            let s = self.eval(*x);
            worst = (0..d).fold(worst, |w, c| w.max((s[c] - q[c]).abs()));
        }
        Ok(worst)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jumps_are_reported_and_shifted_like_the_formula() {
        let f = Piecewise::function(vec![0.0, 1.0, 2.0], &["x", "x + 2"]).unwrap();
        assert!(!f.continuity().is_continuous());
        assert_eq!(f.continuity().max_jump, 2.0);
        assert!(f.statement().contains("x = 1"), "{}", f.statement());
        for x in [-1.0f64, 0.5, 1.0, 1.5, 2.0, 3.0] {
            let want = x.clamp(0.0, 2.0);
            assert_eq!(f.eval(x), vec![want]);
            assert_eq!(f.eval_formula(x), vec![want]);
        }
        let e = Piecewise::function(vec![0.0, 1.0, 2.0], &["x", "x +"]).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("piece 1 coordinate f: parse error at byte 3"),
            "{e}"
        );
        // The piece's name is added, the span in the piece's formula kept.
        assert_eq!(e.parse_error().map(|p| p.span.clone()), Some(3..3));
        let e = Piecewise::function(vec![0.0, 1.0], &["x", "x"]).unwrap_err();
        assert!(
            matches!(
                e,
                Error::PatchCount {
                    expected: 1,
                    got: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = Piecewise::function(vec![0.0, 1.0], &["1/x"]).unwrap_err();
        assert!(e.to_string().contains("not a finite number"), "{e}");
    }

    #[test]
    fn polygon_is_the_papers_square() {
        let sq = vec![
            vec![1.0, 1.0],
            vec![-1.0, 1.0],
            vec![-1.0, -1.0],
            vec![1.0, -1.0],
        ];
        let p = Piecewise::polyline(sq, None, true).unwrap();
        let f = p.formula().unwrap();
        let text = f.print(crate::expr::Format::Maple).unwrap();
        assert!(
            text.starts_with("x := (t) -> 1 - abs(t) + abs(t - 1) + abs(t - 2) - abs(t - 3)")
                || text
                    .starts_with("x := (t) -> -abs(t) + abs(t - 1) + abs(t - 2) - abs(t - 3) + 1"),
            "{text}"
        );
        assert!(p.continuity().is_continuous());
        assert_eq!(p.eval(2.5), vec![0.0, -1.0]);
        assert_eq!(p.eval_formula(2.5), vec![0.0, -1.0]);
        assert!(Piecewise::polyline(vec![vec![0.0]], None, false).is_err());
        assert!(Piecewise::polyline(vec![vec![0.0], vec![1.0, 2.0]], None, false).is_err());
        assert!(
            Piecewise::polyline(vec![vec![0.0], vec![1.0]], Some(vec![1.0, 0.0]), false).is_err()
        );
    }
}
