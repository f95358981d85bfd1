//! The geometry as STEP holds it: (rational) B-spline curves and surfaces in R^3 with their
//! full knot vectors, and what the writer needs of them (end points, boundary curves, knots
//! as distinct values and multiplicities).

use super::{StepError, StepResult};
use geomkit::bspline::BsplineCurve;
use geomkit::geom::Curve;

/// A (rational) B-spline curve in R^3: degree, full knot vector (n + p + 1 knots), n
/// control points and, when rational, n weights.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NurbsCurve {
    pub degree: usize,
    pub knots: Vec<f64>,
    pub points: Vec<[f64; 3]>,
    pub weights: Option<Vec<f64>>,
    /// Whether the curve is a Bézier curve (written with `.PIECEWISE_BEZIER_KNOTS.`).
    pub bezier: bool,
}

/// A (rational) tensor-product B-spline surface in R^3: net rows along u (index i),
/// columns along v (index j), point (i, j) at `i * cols + j`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct NurbsSurface {
    pub degrees: (usize, usize),
    pub knots_u: Vec<f64>,
    pub knots_v: Vec<f64>,
    pub rows: usize,
    pub cols: usize,
    pub points: Vec<[f64; 3]>,
    pub weights: Option<Vec<f64>>,
    /// Whether the surface is a Bézier surface (written with `.PIECEWISE_BEZIER_KNOTS.`).
    pub bezier: bool,
}

/// Points of dimension 2 or 3 as R^3 points (z = 0 for plane curves).
pub(crate) fn points3(flat: &[f64], dim: usize, what: &str) -> StepResult<Vec<[f64; 3]>> {
    match dim {
        2 => Ok(flat.chunks_exact(2).map(|p| [p[0], p[1], 0.0]).collect()),
        3 => Ok(flat.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect()),
        d => Err(StepError::Unsupported(format!(
            "{what} in R^{d}: STEP geometry lives in R^3 (points of dimension 2 are written \
             with z = 0)"
        ))),
    }
}

/// Distinct knots and their multiplicities (consecutive equal values grouped exactly).
pub(crate) fn knots_mults(knots: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut values: Vec<f64> = Vec::new();
    let mut mults: Vec<usize> = Vec::new();
    for &k in knots {
        if values.last() == Some(&k) {
            *mults.last_mut().expect("a value was pushed") += 1;
        } else {
            values.push(k);
            mults.push(1);
        }
    }
    (values, mults)
}

/// The full knot vector of distinct knots and multiplicities.
pub(crate) fn expand_knots(values: &[f64], mults: &[usize]) -> Vec<f64> {
    values
        .iter()
        .zip(mults)
        .flat_map(|(&k, &m)| std::iter::repeat_n(k, m))
        .collect()
}

/// Σ_i N_i(t) h_i of control rows `h` (each of the same length): the rows combined by the
/// B-spline basis at t (the library's evaluation of the curve whose points are the rows).
fn combine(knots: &[f64], p: usize, rows: &[Vec<f64>], t: f64) -> StepResult<Vec<f64>> {
    let dim = rows[0].len();
    let curve = BsplineCurve::from_flat(p, knots.to_vec(), dim, rows.concat())
        .map_err(|e| StepError::Unsupported(format!("a B-spline of degree {p}: {e}")))?;
    let mut out = vec![0.0; dim];
    curve.eval_into(t, &mut out);
    Ok(out)
}

/// a · b
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl NurbsCurve {
    /// A curve, with end knots repeated more than p + 1 times dropped with the control
    /// points they leave without influence (STEP allows at most p + 1).
    pub(crate) fn new(
        degree: usize,
        mut knots: Vec<f64>,
        mut points: Vec<[f64; 3]>,
        mut weights: Option<Vec<f64>>,
    ) -> StepResult<Self> {
        while knots.len() > degree + 2 && knots[0] == knots[degree + 1] && points.len() > degree + 1
        {
            knots.remove(0);
            points.remove(0);
            if let Some(w) = &mut weights {
                w.remove(0);
            }
        }
        while knots.len() > degree + 2
            && knots[knots.len() - 1] == knots[knots.len() - degree - 2]
            && points.len() > degree + 1
        {
            knots.pop();
            points.pop();
            if let Some(w) = &mut weights {
                w.pop();
            }
        }
        // Weights all 1: the polynomial curve (a seam line of a rational surface).
        if weights
            .as_ref()
            .is_some_and(|w| w.iter().all(|&x| x == 1.0))
        {
            weights = None;
        }
        let (_, mults) = knots_mults(&knots);
        if let Some(m) = mults.iter().find(|&&m| m > degree + 1) {
            return Err(StepError::Unsupported(format!(
                "a knot of multiplicity {m} inside a curve of degree {degree}: STEP allows at \
                 most degree + 1"
            )));
        }
        Ok(NurbsCurve {
            degree,
            knots,
            points,
            weights,
            bezier: false,
        })
    }

    /// The parameter domain [knots[p], knots[n]].
    pub(crate) fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }

    fn homogeneous_rows(&self) -> Vec<Vec<f64>> {
        self.points
            .iter()
            .enumerate()
            .map(|(i, p)| match &self.weights {
                Some(w) => vec![p[0] * w[i], p[1] * w[i], p[2] * w[i], w[i]],
                None => vec![p[0], p[1], p[2], 1.0],
            })
            .collect()
    }

    /// The point at t.
    pub(crate) fn eval(&self, t: f64) -> StepResult<[f64; 3]> {
        let h = combine(&self.knots, self.degree, &self.homogeneous_rows(), t)?;
        Ok([h[0] / h[3], h[1] / h[3], h[2] / h[3]])
    }

    /// The points at the ends of the domain.
    pub(crate) fn ends(&self) -> StepResult<([f64; 3], [f64; 3])> {
        let (a, b) = self.domain();
        Ok((self.eval(a)?, self.eval(b)?))
    }

    /// Whether every control point is within `tolerance` (per coordinate) of the first (a
    /// curve collapsed to a point).
    pub(crate) fn is_point(&self, tolerance: f64) -> bool {
        let a = self.points[0];
        self.points
            .iter()
            .all(|p| (0..3).all(|c| (p[c] - a[c]).abs() <= tolerance))
    }

    /// The same curve traversed the other way (knots a + b - t reversed).
    pub(crate) fn reversed(&self) -> NurbsCurve {
        let (a, b) = (self.knots[0], self.knots[self.knots.len() - 1]);
        NurbsCurve {
            degree: self.degree,
            knots: self.knots.iter().rev().map(|k| a + b - k).collect(),
            points: self.points.iter().rev().copied().collect(),
            weights: self
                .weights
                .as_ref()
                .map(|w| w.iter().rev().copied().collect()),
            bezier: self.bezier,
        }
    }
}

impl NurbsSurface {
    /// The domain ((u0, u1), (v0, v1)).
    pub(crate) fn domain(&self) -> ((f64, f64), (f64, f64)) {
        let (p, q) = self.degrees;
        (
            (self.knots_u[p], self.knots_u[self.rows]),
            (self.knots_v[q], self.knots_v[self.cols]),
        )
    }

    fn weight(&self, i: usize, j: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[i * self.cols + j])
    }

    /// The boundary curve at u = `u` (a curve in v) or v = `v` (a curve in u), exact for
    /// clamped ends (the net's first or last row or column) and the combination of rows
    /// by the basis at the end parameter otherwise.
    pub(crate) fn iso(&self, along_u: bool, at: f64) -> StepResult<NurbsCurve> {
        let (p, q) = self.degrees;
        let rational = self.weights.is_some();
        // Rows of homogeneous points across the direction that is fixed.
        let (knots, degree, lines, other_knots, other_degree) = if along_u {
            // Fixed v: combine columns j for each row i.
            let lines: Vec<Vec<Vec<f64>>> = (0..self.rows)
                .map(|i| (0..self.cols).map(|j| self.homogeneous(i, j)).collect())
                .collect();
            (&self.knots_v, q, lines, &self.knots_u, p)
        } else {
            let lines: Vec<Vec<Vec<f64>>> = (0..self.cols)
                .map(|j| (0..self.rows).map(|i| self.homogeneous(i, j)).collect())
                .collect();
            (&self.knots_u, p, lines, &self.knots_v, q)
        };
        let combined: Vec<Vec<f64>> = lines
            .iter()
            .map(|line| combine(knots, degree, line, at))
            .collect::<StepResult<_>>()?;
        let points = combined
            .iter()
            .map(|h| [h[0] / h[3], h[1] / h[3], h[2] / h[3]])
            .collect();
        let weights = rational.then(|| combined.iter().map(|h| h[3]).collect());
        NurbsCurve::new(other_degree, other_knots.clone(), points, weights)
    }

    fn homogeneous(&self, i: usize, j: usize) -> Vec<f64> {
        let w = self.weight(i, j);
        let p = self.points[i * self.cols + j];
        vec![p[0] * w, p[1] * w, p[2] * w, w]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knots_group_into_values_and_multiplicities() {
        let k = [0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0];
        let (v, m) = knots_mults(&k);
        assert_eq!(v, vec![0.0, 0.5, 1.0]);
        assert_eq!(m, vec![3, 1, 3]);
        assert_eq!(expand_knots(&v, &m), k.to_vec());
    }

    #[test]
    fn surplus_end_knots_are_dropped_with_their_dead_control_points() {
        // Degree 1 with the first knot 3 times: N_0 is zero everywhere.
        let c = NurbsCurve::new(
            1,
            vec![0.0, 0.0, 0.0, 1.0, 1.0],
            vec![[9.0, 9.0, 9.0], [0.0, 0.0, 0.0], [1.0, 2.0, 3.0]],
            None,
        )
        .unwrap();
        assert_eq!(c.knots, vec![0.0, 0.0, 1.0, 1.0]);
        assert_eq!(c.points, vec![[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]]);
        assert_eq!(c.eval(0.5).unwrap(), [0.5, 1.0, 1.5]);
    }

    #[test]
    fn a_rational_quadratic_quarter_circle_evaluates_on_the_circle() {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let c = NurbsCurve::new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            vec![[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            Some(vec![1.0, h, 1.0]),
        )
        .unwrap();
        for k in 0..=10 {
            let p = c.eval(k as f64 / 10.0).unwrap();
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
        }
        let r = c.reversed();
        let (a, b) = (r.eval(0.25).unwrap(), c.eval(0.75).unwrap());
        assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-15));
    }
}
