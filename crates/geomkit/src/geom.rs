//! The capabilities every curve and surface of the library shares: [`Curve`] and
//! [`Surface`], with one batch entry point each ([`Curve::eval_batch`],
//! [`Surface::eval_batch`]) that picks the fastest kernel of the type itself, and
//! [`BatchOptions`] to run it on the calling thread.
//!
//! Every model type implements them: Bézier curves (formula (1) of spec/bezier-order.md) and
//! rational Bézier curves, B-spline curves (spec/bspline-interpolation.md, formula (1) on
//! uniform knots) and their piecewise-polynomial form, point equations (spec/point-calculus.md
//! §2), composite curves (§5 of spec/composite-surfaces.md) and the curves of ruled
//! surfaces; Bézier surfaces (formula (11)), B-spline surfaces, composite surfaces (formulas
//! (9)/(11)), piecewise-ruled surfaces (formula (2)) and point-calculus surfaces. The
//! tessellation of [`crate::mesh`] takes `&dyn Curve` and `&dyn Surface`.
//!
//! Both traits are object safe and `Send + Sync`, so `Box<dyn Curve>` crosses threads.
//!
//! ```
//! use geomkit::bezier::BezierCurve;
//! use geomkit::bspline::{interpolate_curve, InterpolationOptions};
//! use geomkit::geom::{BatchOptions, Curve, Parallelism};
//!
//! let bezier = BezierCurve::new(vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![2.0, 0.0]])?;
//! let points: Vec<Vec<f64>> = (0..8).map(|k| vec![k as f64, (k * k) as f64]).collect();
//! let bspline = interpolate_curve(&points, &InterpolationOptions::default())?.into_curve();
//! let curves: Vec<Box<dyn Curve>> = vec![Box::new(bezier), Box::new(bspline)];
//! for c in &curves {
//!     let (a, b) = c.domain();
//!     let ts = [a, 0.5 * (a + b), b];
//!     let mut out = vec![0.0; 3 * c.dim()];
//!     c.eval_batch(&ts, &mut out, &BatchOptions::default())?;
//!     assert_eq!(&out[..2], &c.eval(a)[..]);
//!     // The same values on the calling thread only.
//!     let mut seq = vec![0.0; 3 * c.dim()];
//!     let options = BatchOptions::default().with_parallelism(Parallelism::Sequential);
//!     c.eval_batch(&ts, &mut seq, &options)?;
//!     assert_eq!(out, seq);
//! }
//! # Ok::<(), geomkit::Error>(())
//! ```

use crate::points::check_eval_args;
use crate::{Error, Result};

/// Where a batch may run.
///
/// ```
/// use geomkit::geom::{BatchOptions, Parallelism};
/// assert_eq!(Parallelism::default(), Parallelism::Auto);
/// let o = BatchOptions::default().with_parallelism(Parallelism::Sequential);
/// assert_eq!(o.parallelism, Parallelism::Sequential);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Parallelism {
    /// On rayon's global thread pool when the `parallel` feature is on (the default) and the
    /// batch is large enough to pay for it; on the calling thread otherwise.
    #[default]
    Auto,
    /// On the calling thread only (e.g. when the caller already runs batches in parallel).
    Sequential,
}

/// Options of [`Curve::eval_batch`] and [`Surface::eval_batch`].
///
/// ```
/// use geomkit::geom::{BatchOptions, Parallelism};
/// let o = BatchOptions::default().with_parallelism(Parallelism::Sequential);
/// assert_eq!(o.parallelism, Parallelism::Sequential);
/// assert_eq!(BatchOptions::sequential(), o);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct BatchOptions {
    /// Thread pool or calling thread (default [`Parallelism::Auto`]).
    pub parallelism: Parallelism,
    /// Only kernels whose values are those of `eval_into` bit for bit (default false: a
    /// type may switch to a faster form within its documented agreement, such as the
    /// piecewise-polynomial form of B-spline curves).
    pub bit_exact: bool,
}

impl BatchOptions {
    /// Sets where the batch may run.
    ///
    /// ```
    /// use geomkit::geom::{BatchOptions, Parallelism};
    /// let o = BatchOptions::default().with_parallelism(Parallelism::Sequential);
    /// assert_eq!(o, BatchOptions::sequential());
    /// ```
    pub fn with_parallelism(mut self, parallelism: Parallelism) -> Self {
        self.parallelism = parallelism;
        self
    }

    /// Sets whether only kernels with the values of `eval_into`, bit for bit, may run.
    ///
    /// ```
    /// use geomkit::bspline::{interpolate_curve, InterpolationOptions};
    /// use geomkit::geom::{BatchOptions, Curve};
    /// let pts: Vec<Vec<f64>> = (0..5).map(|k| vec![k as f64, (k % 2) as f64]).collect();
    /// let c = interpolate_curve(&pts, &InterpolationOptions::default())?.into_curve();
    /// let ts: Vec<f64> = (0..1 << 16).map(|k| k as f64 / 16384.0).collect();
    /// let mut out = vec![0.0; 2 << 16];
    /// // 2^16 parameters on 4 spans would take the piecewise form; not with bit_exact.
    /// c.eval_batch(&ts, &mut out, &BatchOptions::default().with_bit_exact(true))?;
    /// assert_eq!(&out[2 * 1000..2 * 1001], &c.eval(ts[1000])[..]);
    /// # Ok::<(), geomkit::Error>(())
    /// ```
    pub fn with_bit_exact(mut self, bit_exact: bool) -> Self {
        self.bit_exact = bit_exact;
        self
    }

    /// The options of a batch on the calling thread only.
    ///
    /// ```
    /// use geomkit::geom::{BatchOptions, Parallelism};
    /// assert_eq!(BatchOptions::sequential().parallelism, Parallelism::Sequential);
    /// ```
    pub fn sequential() -> Self {
        Self::default().with_parallelism(Parallelism::Sequential)
    }

    /// Whether the batch may use the thread pool.
    pub(crate) fn parallel(&self) -> bool {
        crate::par::allowed(self.parallelism)
    }
}

/// A parametric curve t ↦ p(t) ∈ R^dim over a parameter domain [a, b].
///
/// Required: [`Curve::dim`], [`Curve::domain`], [`Curve::eval_into`]; the rest have
/// defaults that the library's types override with their fast kernels and derivatives.
pub trait Curve: Send + Sync {
    /// Dimension of the points.
    fn dim(&self) -> usize;

    /// The parameter domain (a, b), a < b. Evaluation outside it is defined by each type
    /// (polynomials extrapolate, composite curves hold their ends).
    fn domain(&self) -> (f64, f64);

    /// Writes the point at `t` into `out`, which must have exactly [`Curve::dim`] entries
    /// (unchecked here: the checked ways in are [`Curve::eval_batch`] and
    /// [`Curve::derivative_into`] with order 0).
    fn eval_into(&self, t: f64, out: &mut [f64]);

    /// The point at `t` as a new vector.
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// use geomkit::geom::Curve;
    /// let c = BezierCurve::new(vec![vec![0.0], vec![2.0]]).unwrap();
    /// assert_eq!(c.eval(0.25), vec![0.5]);
    /// ```
    fn eval(&self, t: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim()];
        self.eval_into(t, &mut out);
        out
    }

    /// The VALUE of the `order`-th derivative d^k p / dt^k at `t` into `out` (length dim);
    /// order 0 is the point. Errors: [`Error::BufferSize`] for a wrong `out`,
    /// [`Error::NonFinite`] for a non-finite `t`, [`Error::UnsupportedDerivative`] for an
    /// order the type cannot give (each type documents which; the default gives the point
    /// and no derivative: every curve of the library overrides it).
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// use geomkit::geom::Curve;
    /// // p(t) = (2t, 4t(1-t)): p'(0) = (2, 4), p'' = (0, -8).
    /// let c = BezierCurve::new(vec![vec![0.0, 0.0], vec![1.0, 2.0], vec![2.0, 0.0]]).unwrap();
    /// let mut d = [0.0; 2];
    /// c.derivative_into(0.0, 1, &mut d).unwrap();
    /// assert_eq!(d, [2.0, 4.0]);
    /// c.derivative_into(0.3, 2, &mut d).unwrap();
    /// assert_eq!(d, [0.0, -8.0]);
    /// ```
    fn derivative_into(&self, t: f64, order: usize, out: &mut [f64]) -> Result<()> {
        check_point(&[t], self.dim(), out)?;
        if order > 0 {
            return Err(unsupported(
                "this curve",
                order,
                "the type implements evaluation only",
            ));
        }
        self.eval_into(t, out);
        Ok(())
    }

    /// Parameters inside the domain where the curve may have a corner (knots, piece ends);
    /// polylines and tessellations include them. Default: none.
    fn breaks(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Evaluates at every parameter of `ts` (sorted or not), point k into
    /// `out[k*dim .. (k+1)*dim]`, by the fastest kernel of the type: the blocked Horner
    /// scheme of Bézier curves, the batch kernels of B-splines (and, for large batches of
    /// curves of degree <= 3, their piecewise-polynomial form), the reused basis of point
    /// equations. The values equal [`Curve::eval_into`]'s bit for bit, except where a type
    /// documents otherwise (B-spline curves through the piecewise form: within
    /// 8·eps·max|P| on interpolated curves; [`BatchOptions::bit_exact`] rules that out). Errors: [`Error::BufferSize`] unless `out.len() == ts.len() * dim`,
    /// [`Error::NonFinite`] naming the first non-finite parameter.
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// use geomkit::geom::{BatchOptions, Curve};
    /// let c = BezierCurve::new(vec![vec![0.0], vec![2.0]]).unwrap();
    /// let mut out = [0.0; 2];
    /// c.eval_batch(&[0.25, 1.0], &mut out, &BatchOptions::default()).unwrap();
    /// assert_eq!(out, [0.5, 2.0]);
    /// assert!(c.eval_batch(&[f64::NAN, 1.0], &mut out, &BatchOptions::default()).is_err());
    /// assert!(c.eval_batch(&[0.5], &mut out, &BatchOptions::default()).is_err());
    /// ```
    fn eval_batch(&self, ts: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        let d = self.dim();
        check_eval_args("parameter", ts, ts.len(), d, out)?;
        for_each_point(options.parallel(), ts, 1, out, d, |t, o| {
            self.eval_into(t[0], o)
        });
        Ok(())
    }

    /// `count` points (at least 2) at uniformly spaced parameters over the curve's own
    /// domain [a, b], row-major: t_k = a + k·(b - a)/(count - 1), the last one exactly b.
    /// The points equal [`Curve::eval`] at these parameters, except where a type documents
    /// a faster scheme (B-spline curves of degree <= 3: forward differences, within
    /// [`crate::bspline::FdReport::bound`], both ends exact).
    ///
    /// ```
    /// use geomkit::bezier::BezierCurve;
    /// use geomkit::geom::Curve;
    /// let c = BezierCurve::new(vec![vec![0.0], vec![2.0]]).unwrap();
    /// assert_eq!(c.sample_uniform(3), vec![0.0, 1.0, 2.0]);
    /// ```
    fn sample_uniform(&self, count: usize) -> Vec<f64> {
        let (a, b) = self.domain();
        let ts = uniform_params(a, b, count);
        let mut out = vec![0.0; ts.len() * self.dim()];
        if self
            .eval_batch(&ts, &mut out, &BatchOptions::default())
            .is_err()
        {
            // Only a non-finite domain gets here: its points are not numbers either.
            out.fill(f64::NAN);
        }
        out
    }
}

/// A parametric surface (u, v) ↦ S(u, v) ∈ R^dim over a rectangle of parameters.
///
/// Batches take interleaved pairs `uv = [u0, v0, u1, v1, ...]` ([`Surface::eval_batch`]);
/// grids take the two axes ([`Surface::eval_grid`]).
///
/// Points of dimension 3 mesh as they are, dimension 2 with z = 0, dimension 1 as the
/// height field (u, v, z(u, v)) ([`crate::mesh::tessellate_surface`]).
pub trait Surface: Send + Sync {
    /// Dimension of the points.
    fn dim(&self) -> usize;

    /// ((u0, u1), (v0, v1)).
    fn domain(&self) -> ((f64, f64), (f64, f64));

    /// Writes S(u, v) into `out`, which must have exactly [`Surface::dim`] entries
    /// (unchecked here; [`Surface::eval_batch`] is the checked way in).
    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]);

    /// S(u, v) as a new vector.
    ///
    /// ```
    /// use geomkit::bezier::BezierSurface;
    /// use geomkit::geom::Surface;
    /// let s = BezierSurface::new(vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]])
    ///     .unwrap();
    /// assert_eq!(Surface::eval(&s, 0.5, 0.5), vec![1.5]);
    /// ```
    fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim()];
        self.eval_into(u, v, &mut out);
        out
    }

    /// Points on the grid `us` × `vs`: point (a, b) at `out[(a * vs.len() + b) * dim ..]`.
    /// Types with a grid kernel share work along rows (their values may then differ from
    /// [`Surface::eval_into`] by rounding). Errors: wrong buffer length, non-finite
    /// parameters.
    ///
    /// ```
    /// use geomkit::bezier::BezierSurface;
    /// use geomkit::geom::Surface;
    /// let s = BezierSurface::new(vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]])
    ///     .unwrap();
    /// let mut out = [0.0; 4];
    /// Surface::eval_grid(&s, &[0.0, 1.0], &[0.0, 1.0], &mut out).unwrap();
    /// assert_eq!(out, [0.0, 1.0, 2.0, 3.0]);
    /// ```
    fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim();
        check_grid(us, vs, d, out)?;
        if vs.is_empty() || d == 0 {
            return Ok(());
        }
        let rows = (CHUNK_POINTS / vs.len()).max(1);
        let parallel = us.len() * vs.len() > CHUNK_POINTS;
        crate::par::zip_chunks(parallel, out, rows * vs.len() * d, us, rows, |o, us| {
            for (&u, row) in us.iter().zip(o.chunks_exact_mut(vs.len() * d)) {
                for (&v, p) in vs.iter().zip(row.chunks_exact_mut(d)) {
                    self.eval_into(u, v, p);
                }
            }
        });
        Ok(())
    }

    /// Evaluates at the pairs `uv = [u0, v0, u1, v1, ...]`, point k into
    /// `out[k*dim .. (k+1)*dim]`, by the fastest kernel of the type, with the values of
    /// [`Surface::eval_into`] bit for bit. Errors: [`Error::BufferSize`] for an odd `uv`
    /// (expected: one more) or unless `out.len() == uv.len() / 2 * dim`,
    /// [`Error::NonFinite`] naming the first non-finite number of `uv`.
    ///
    /// ```
    /// use geomkit::bezier::BezierSurface;
    /// use geomkit::geom::{BatchOptions, Surface};
    /// let s = BezierSurface::new(vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]])
    ///     .unwrap();
    /// let mut out = [0.0; 2];
    /// s.eval_batch(&[0.0, 1.0, 1.0, 0.5], &mut out, &BatchOptions::default()).unwrap();
    /// assert_eq!(out, [1.0, 2.5]);
    /// ```
    fn eval_batch(&self, uv: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        let d = self.dim();
        check_pairs(uv, d, out)?;
        for_each_point(options.parallel(), uv, 2, out, d, |q, o| {
            self.eval_into(q[0], q[1], o)
        });
        Ok(())
    }

    /// The partial derivative ∂^(ku+kv) S / ∂u^ku ∂v^kv at (u, v) into `out` (length
    /// dim); (0, 0) is the point. Errors: [`Error::BufferSize`], [`Error::NonFinite`],
    /// [`Error::UnsupportedDerivative`] for orders the type cannot give (the default gives
    /// the point and no derivative: every surface of the library overrides it).
    ///
    /// ```
    /// use geomkit::bezier::BezierSurface;
    /// use geomkit::geom::Surface;
    /// // S(u, v) = 2u + v: ∂S/∂u = 2, ∂S/∂v = 1.
    /// let s = BezierSurface::new(vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]])
    ///     .unwrap();
    /// let mut d = [0.0];
    /// s.derivative_into(0.3, 0.6, (1, 0), &mut d).unwrap();
    /// assert_eq!(d, [2.0]);
    /// s.derivative_into(0.3, 0.6, (0, 1), &mut d).unwrap();
    /// assert_eq!(d, [1.0]);
    /// ```
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        order: (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim(), out)?;
        if order != (0, 0) {
            return Err(unsupported_partial(
                "this surface",
                order,
                "the type implements evaluation only",
            ));
        }
        self.eval_into(u, v, out);
        Ok(())
    }

    /// Parameters in u and in v where the surface may have a crease (knots, cell
    /// boundaries, polygon vertices); tessellations have grid lines there. Default: none.
    fn breaks(&self) -> (Vec<f64>, Vec<f64>) {
        (Vec::new(), Vec::new())
    }
}

/// Trait methods of [`Surface`] (or [`Curve`]) that forward to the type's inherent method of
/// the same name: `forward_to_inherent!(Type; dim, domain, ...)` inside the trait impl.
/// (A type without that inherent method would recurse: rustc's `unconditional_recursion`
/// lint catches it.)
macro_rules! forward_to_inherent {
    ($t:ty; $($m:ident),+) => {
        $(crate::geom::forward_to_inherent!(@ $t, $m);)+
    };
    (@ $t:ty, dim) => {
        fn dim(&self) -> usize {
            <$t>::dim(self)
        }
    };
    (@ $t:ty, surface_domain) => {
        fn domain(&self) -> ((f64, f64), (f64, f64)) {
            <$t>::domain(self)
        }
    };
    (@ $t:ty, surface_eval_into) => {
        fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
            <$t>::eval_into(self, u, v, out)
        }
    };
    (@ $t:ty, eval_grid) => {
        fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> crate::Result<()> {
            <$t>::eval_grid(self, us, vs, out)
        }
    };
}
pub(crate) use forward_to_inherent;

/// Points per parallel task of the default batch loops.
const CHUNK_POINTS: usize = 4096;

/// Runs `f(params of point k, out of point k)` over the points of `params` (`stride`
/// numbers each) and `out` (`d` each), in chunks on the thread pool when `parallel` and the
/// batch is large, else in order.
pub(crate) fn for_each_point<F>(
    parallel: bool,
    params: &[f64],
    stride: usize,
    out: &mut [f64],
    d: usize,
    f: F,
) where
    F: Fn(&[f64], &mut [f64]) + Sync + Send,
{
    let n = params.len() / stride;
    if d == 0 || n == 0 {
        return;
    }
    let run = |o: &mut [f64], p: &[f64]| {
        for (q, x) in p.chunks_exact(stride).zip(o.chunks_exact_mut(d)) {
            f(q, x);
        }
    };
    crate::par::zip_chunks(
        parallel && n > CHUNK_POINTS,
        out,
        CHUNK_POINTS * d,
        params,
        CHUNK_POINTS * stride,
        run,
    );
}

/// t_k = a + k·((b - a)/(count - 1)), k < count (at least 2), the last one exactly b: the
/// parameters of [`Curve::sample_uniform`], computed as NumPy's `linspace` computes them.
///
/// ```
/// let t = geomkit::geom::uniform_params(0.0, 7.3, 4);
/// assert_eq!(t.len(), 4);
/// assert_eq!((t[0], t[3]), (0.0, 7.3));
/// ```
pub fn uniform_params(a: f64, b: f64, count: usize) -> Vec<f64> {
    let count = count.max(2);
    let step = (b - a) / (count - 1) as f64;
    (0..count)
        .map(|k| {
            if k + 1 == count {
                b
            } else {
                a + k as f64 * step
            }
        })
        .collect()
}

/// Values from `a` to `b` in `count` (at least 2) equal steps, both ends exact:
/// a + (b - a)·(k/(count - 1)), so that values symmetric about the middle are symmetric
/// (for grids of pictures and tessellations).
///
/// ```
/// assert_eq!(geomkit::geom::linspace(-1.0, 1.0, 5), [-1.0, -0.5, 0.0, 0.5, 1.0]);
/// ```
pub fn linspace(a: f64, b: f64, count: usize) -> Vec<f64> {
    let last = (count.max(2) - 1) as f64;
    (0..count.max(2))
        .map(|k| {
            if k as f64 == last {
                b
            } else {
                a + (b - a) * (k as f64 / last)
            }
        })
        .collect()
}

/// The checks of a single-point derivative: `out` of length `dim`, finite parameters.
pub(crate) fn check_point(params: &[f64], dim: usize, out: &[f64]) -> Result<()> {
    check_eval_args("parameter", params, 1, dim, out)
}

/// The checks of [`Surface::eval_batch`]: whole pairs, `out` of `uv.len() / 2 * dim`,
/// finite parameters.
pub(crate) fn check_pairs(uv: &[f64], dim: usize, out: &[f64]) -> Result<()> {
    if !uv.len().is_multiple_of(2) {
        return Err(Error::BufferSize {
            expected: uv.len() + 1,
            got: uv.len(),
        });
    }
    check_eval_args("parameter", uv, uv.len() / 2, dim, out)
}

/// The checks of [`Surface::eval_grid`]: `out` of `us.len() * vs.len() * dim`, finite
/// parameters.
pub(crate) fn check_grid(us: &[f64], vs: &[f64], dim: usize, out: &[f64]) -> Result<()> {
    check_eval_args("parameter u", us, us.len() * vs.len(), dim, out)?;
    check_eval_args("parameter v", vs, 0, dim, &[])
}

/// [`Error::UnsupportedDerivative`] of a surface.
pub(crate) fn unsupported_partial(
    what: &'static str,
    (ku, kv): (usize, usize),
    reason: &'static str,
) -> Error {
    Error::UnsupportedDerivative {
        what,
        order: format!("({ku}, {kv})"),
        reason,
    }
}

/// [`Error::UnsupportedDerivative`] of a curve.
pub(crate) fn unsupported(what: &'static str, order: usize, reason: &'static str) -> Error {
    Error::UnsupportedDerivative {
        what,
        order: order.to_string(),
        reason,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bspline::{interpolate_curve, InterpolationOptions};

    /// A plane through the defaults only: S(u, v) = (u, v, u v).
    struct Saddle;

    impl Surface for Saddle {
        fn dim(&self) -> usize {
            3
        }
        fn domain(&self) -> ((f64, f64), (f64, f64)) {
            ((-1.0, 1.0), (0.0, 2.0))
        }
        fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
            out.copy_from_slice(&[u, v, u * v]);
        }
    }

    /// A line through the defaults only.
    struct Line;

    impl Curve for Line {
        fn dim(&self) -> usize {
            1
        }
        fn domain(&self) -> (f64, f64) {
            (2.0, 4.0)
        }
        fn eval_into(&self, t: f64, out: &mut [f64]) {
            out[0] = 3.0 * t;
        }
    }

    #[test]
    fn defaults_evaluate_and_refuse_derivatives() {
        let s = Saddle;
        let (us, vs) = ([-1.0, 0.5, 1.0], [0.0, 2.0]);
        let mut grid = [0.0; 18];
        s.eval_grid(&us, &vs, &mut grid).unwrap();
        assert_eq!(&grid[6..9], &[0.5, 0.0, 0.0]);
        assert_eq!(&grid[15..], &[1.0, 2.0, 2.0]);
        let big: Vec<f64> = (0..5000).map(|k| k as f64 * 1e-3).collect();
        let mut out = vec![0.0; 3 * 5000 * 2];
        s.eval_grid(&big, &[0.25, 0.5], &mut out).unwrap();
        assert_eq!(&out[3 * (2 * 4999 + 1)..], &[4.999, 0.5, 4.999 * 0.5]);
        assert!(s.eval_grid(&us, &vs, &mut grid[..17]).is_err());
        let mut p = [0.0; 3];
        s.derivative_into(0.5, 1.0, (0, 0), &mut p).unwrap();
        assert_eq!(p, [0.5, 1.0, 0.5]);
        assert!(matches!(
            s.derivative_into(0.5, 1.0, (1, 0), &mut p),
            Err(Error::UnsupportedDerivative { .. })
        ));
        let c = Line;
        assert_eq!(c.sample_uniform(3), vec![6.0, 9.0, 12.0]);
        assert!(c.breaks().is_empty() && s.breaks() == (Vec::new(), Vec::new()));
        assert!(matches!(
            c.derivative_into(3.0, 1, &mut [0.0]),
            Err(Error::UnsupportedDerivative { .. })
        ));
    }

    #[test]
    fn uniform_params_end_exactly() {
        let ts = uniform_params(0.0, 7.3, 4);
        assert_eq!(ts.len(), 4);
        assert_eq!((ts[0], ts[3]), (0.0, 7.3));
        assert_eq!(uniform_params(1.0, 2.0, 0), vec![1.0, 2.0]);
    }

    #[test]
    fn both_parallelisms_give_the_same_bits() {
        let pts: Vec<Vec<f64>> = (0..50)
            .map(|k| vec![(k as f64 * 0.3).sin(), k as f64])
            .collect();
        let c = interpolate_curve(&pts, &InterpolationOptions::default())
            .unwrap()
            .into_curve();
        let (a, b) = Curve::domain(&c);
        let ts: Vec<f64> = (0..10_000)
            .map(|k| a + (b - a) * ((k * 7919) % 10_000) as f64 / 10_000.0)
            .collect();
        let mut auto = vec![0.0; 20_000];
        let mut seq = vec![0.0; 20_000];
        c.eval_batch(&ts, &mut auto, &BatchOptions::default())
            .unwrap();
        c.eval_batch(&ts, &mut seq, &BatchOptions::sequential())
            .unwrap();
        assert_eq!(auto, seq);
        for (t, p) in ts.iter().zip(seq.chunks_exact(2)) {
            assert_eq!(p, &c.eval(*t)[..]);
        }
        assert_eq!(
            crate::par::allowed(Parallelism::Auto),
            cfg!(feature = "parallel")
        );
        assert!(!crate::par::allowed(Parallelism::Sequential));
    }
}
