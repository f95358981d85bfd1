//! Sampled curves and surfaces (the sample files of `geomkit pointcalc curve|surface`) as
//! geometry: the polyline through the samples and the bilinear cells of a sample grid.

use crate::error::{Error, Result};
use crate::numbers::Points;

/// Samples (t_k, P_k) joined by straight segments: P(t) = P_k + (t - t_k)/(t_(k+1) - t_k)
/// (P_(k+1) - P_k) on [t_k, t_(k+1)], the end samples' values outside [t_0, t_n].
#[derive(Debug, Clone, PartialEq)]
pub struct SampledCurve {
    ts: Vec<f64>,
    dim: usize,
    points: Vec<f64>,
}

impl SampledCurve {
    /// The polyline through `points` (row-major, `dim` per point) at increasing `ts`.
    ///
    /// Errors: fewer than 2 samples, no coordinates, a count that does not match, or `ts`
    /// not strictly increasing (naming the sample).
    pub fn new(dim: usize, ts: Vec<f64>, points: Vec<f64>) -> Result<SampledCurve> {
        if ts.len() < 2 || dim == 0 {
            return Err(Error::model(
                "samples",
                "must hold at least 2 samples [t, x, ...]",
            ));
        }
        if points.len() != ts.len() * dim {
            return Err(Error::model(
                "samples",
                format!("has {} values for {} samples", points.len(), ts.len()),
            ));
        }
        if let Some(k) = ts.windows(2).position(|w| w[1] <= w[0]) {
            return Err(Error::model(
                format!("samples[{}]", k + 1),
                "must have a greater t than the sample before it",
            ));
        }
        Ok(SampledCurve { ts, dim, points })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.ts.len()
    }

    /// Never empty (at least 2 samples).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// [t_0, t_n].
    pub fn domain(&self) -> (f64, f64) {
        (self.ts[0], self.ts[self.ts.len() - 1])
    }

    /// The point at `t` into `out` (length [`SampledCurve::dim`]).
    pub fn eval_into(&self, t: f64, out: &mut [f64]) {
        let (k, f) = locate(&self.ts, t);
        let d = self.dim;
        let (a, b) = (&self.points[k * d..], &self.points[(k + 1) * d..]);
        for c in 0..d {
            out[c] = a[c] + f * (b[c] - a[c]);
        }
    }
}

/// The interval k with xs[k] <= x <= xs[k+1] (clamped to the ends) and the fraction of x in
/// it, clamped to [0, 1]; NaN gives the first interval and NaN.
fn locate(xs: &[f64], x: f64) -> (usize, f64) {
    let k = xs.partition_point(|&y| y <= x).clamp(1, xs.len() - 1) - 1;
    let f = ((x - xs[k]) / (xs[k + 1] - xs[k])).clamp(0.0, 1.0);
    (k, f)
}

/// A grid of samples P_ab at (u_a, v_b) joined by bilinear cells.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledSurface {
    us: Vec<f64>,
    vs: Vec<f64>,
    points: Points,
}

impl SampledSurface {
    /// The bilinear surface through `points` (point (a, b) at index a * vs.len() + b).
    ///
    /// Errors: fewer than 2 values of u or v, a point count other than u × v, values not
    /// strictly increasing.
    pub fn new(us: Vec<f64>, vs: Vec<f64>, points: Points) -> Result<SampledSurface> {
        if us.len() < 2 || vs.len() < 2 || points.len() != us.len() * vs.len() {
            return Err(Error::model(
                "",
                format!(
                    "a pointcalc-surface-samples needs u and v with at least 2 values each and \
                     u × v points ({} × {} given, {} points)",
                    us.len(),
                    vs.len(),
                    points.len()
                ),
            ));
        }
        for (name, xs) in [("u", &us), ("v", &vs)] {
            if let Some(k) = xs.windows(2).position(|w| w[1] <= w[0]) {
                return Err(Error::model(
                    format!("{name}[{}]", k + 1),
                    "must be greater than the previous value",
                ));
            }
        }
        Ok(SampledSurface { us, vs, points })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.points.dim
    }

    /// (values of u, values of v).
    pub fn grid_size(&self) -> (usize, usize) {
        (self.us.len(), self.vs.len())
    }

    /// ((u_0, u_m), (v_0, v_n)).
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        (
            (self.us[0], self.us[self.us.len() - 1]),
            (self.vs[0], self.vs[self.vs.len() - 1]),
        )
    }

    /// The point at (u, v) into `out` (length [`SampledSurface::dim`]).
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let (i, f) = locate(&self.us, u);
        let (j, g) = locate(&self.vs, v);
        let (d, nv) = (self.dim(), self.vs.len());
        let p = |i: usize, j: usize, c: usize| self.points.flat[(i * nv + j) * d + c];
        for c in 0..d {
            out[c] = (1.0 - f) * (1.0 - g) * p(i, j, c)
                + f * (1.0 - g) * p(i + 1, j, c)
                + (1.0 - f) * g * p(i, j + 1, c)
                + f * g * p(i + 1, j + 1, c);
        }
    }

    /// Points on the grid `us` × `vs`, point (a, b) at `out[(a * vs.len() + b) * dim ..]`.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> geomkit::Result<()> {
        let d = self.dim();
        if out.len() != us.len() * vs.len() * d {
            return Err(geomkit::Error::BufferSize {
                expected: us.len() * vs.len() * d,
                got: out.len(),
            });
        }
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let k = (a * vs.len() + b) * d;
                self.eval_into(u, v, &mut out[k..k + d]);
            }
        }
        Ok(())
    }
}

impl geomkit::geom::Curve for SampledCurve {
    fn dim(&self) -> usize {
        self.dim
    }
    fn domain(&self) -> (f64, f64) {
        SampledCurve::domain(self)
    }
    fn eval_into(&self, t: f64, out: &mut [f64]) {
        SampledCurve::eval_into(self, t, out)
    }
    /// The samples: the polyline has a corner at each.
    fn breaks(&self) -> Vec<f64> {
        self.ts.clone()
    }
}

impl geomkit::geom::Surface for SampledSurface {
    fn dim(&self) -> usize {
        SampledSurface::dim(self)
    }
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        SampledSurface::domain(self)
    }
    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        SampledSurface::eval_into(self, u, v, out)
    }
    fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> geomkit::Result<()> {
        SampledSurface::eval_grid(self, us, vs, out)
    }
    /// The grid lines: the bilinear cells meet at creases there.
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        (self.us.clone(), self.vs.clone())
    }
}
