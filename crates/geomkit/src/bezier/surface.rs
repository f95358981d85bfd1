//! Tensor-product Bézier surfaces (spec/bezier-order.md §4, formulas (11)-(16)):
//! p(u, v) = Σ_i Σ_j b_ni(u) b_mj(v) u_ij over an (n+1)×(m+1) characteristic net in R^r
//! (the paper's t is our u, its τ our v).
//!
//! Order change (14) works direction by direction: in u the net is a curve whose "points"
//! are the rows (each (m+1)·r numbers), in v one whose points are the columns, so every
//! stable curve algorithm of [`super::degree`] applies and the defect of each direction
//! (16) is decided jointly for all rows or columns.
//!
//! ```
//! use geomkit::bezier::BezierSurface;
//! // A bilinear patch, elevated to (3, 2): the same surface.
//! let s = BezierSurface::new(vec![
//!     vec![vec![0., 0., 0.], vec![0., 1., 0.]],
//!     vec![vec![1., 0., 0.], vec![1., 1., 1.]],
//! ]).unwrap();
//! let e = s.change_degree(3, 2, None).unwrap();
//! assert_eq!(e.degrees(), (3, 2));
//! assert!((e.eval(0.3, 0.6)[2] - 0.18).abs() < 1e-15);
//! assert_eq!(e.degree_report(None).unwrap().real_degrees(), (1, 1));
//! ```

use super::bound::DeviationBound;
use super::curve::{de_casteljau, validate_points};
use super::degree::{
    check_tolerance, elevate_flat_reporting, paper_change_flat, real_degree_flat,
    reduce_least_squares, DegreeReport,
};
use crate::geom::{check_pairs, check_point, BatchOptions, Surface};
use crate::numeric::{distance, max_norm};
use crate::points::{check_eval_args, flatten_grid, unit_normal};
use crate::progress::Progress;
use crate::{Error, Result};

mod approx;
mod curvature;
pub use approx::SurfaceApproxReduction;

/// A parametric direction of a surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// u (the paper's t), along the first net index i.
    U,
    /// v (the paper's τ), along the second net index j.
    V,
}

impl Direction {
    fn name(self) -> &'static str {
        match self {
            Direction::U => "u",
            Direction::V => "v",
        }
    }
}

/// Real degrees and defects of a surface in both directions (16).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceDegreeReport {
    /// The u direction (rows of S_(n,m)).
    pub u: DegreeReport,
    /// The v direction (columns of S_(n,m)).
    pub v: DegreeReport,
}

impl SurfaceDegreeReport {
    /// (n*, m*).
    pub fn real_degrees(&self) -> (usize, usize) {
        (self.u.real_degree, self.v.real_degree)
    }

    /// (d, δ): formal minus real degree in each direction.
    pub fn defects(&self) -> (usize, usize) {
        (self.u.defect, self.v.defect)
    }
}

/// A row-major net of `rows × cols` points from its transpose (`cols × rows`).
fn untranspose(cols: usize, rows: usize, dim: usize, t: &[f64]) -> Vec<f64> {
    let mut net = vec![0.0; t.len()];
    for j in 0..cols {
        for i in 0..rows {
            let src = (j * rows + i) * dim;
            let dst = (i * cols + j) * dim;
            net[dst..dst + dim].copy_from_slice(&t[src..src + dim]);
        }
    }
    net
}

/// A tensor-product Bézier surface.
#[derive(Debug, Clone, PartialEq)]
pub struct BezierSurface {
    dim: usize,
    rows: usize,
    cols: usize,
    /// net[i][j] at (i * cols + j) * dim.
    net: Vec<f64>,
}

impl BezierSurface {
    /// A surface from its net, `net[i][j]` the control point u_ij. Errors: empty net or row,
    /// ragged rows, points of different dimensions, non-finite coordinates.
    pub fn new(net: Vec<Vec<Vec<f64>>>) -> Result<Self> {
        let (rows, cols, dim, data) = flatten_grid("control net", &net)?;
        Self::from_flat(rows, cols, dim, data)
    }

    /// A surface from a row-major net of `rows`×`cols` points with `dim` coordinates.
    pub fn from_flat(rows: usize, cols: usize, dim: usize, net: Vec<f64>) -> Result<Self> {
        if rows == 0 || cols == 0 {
            return Err(Error::Empty {
                what: "control net",
            });
        }
        validate_points("control net", dim, &net)?;
        if net.len() != rows * cols * dim {
            return Err(Error::BufferSize {
                expected: rows * cols * dim,
                got: net.len(),
            });
        }
        Ok(BezierSurface {
            dim,
            rows,
            cols,
            net,
        })
    }

    /// Formal degrees (n, m).
    pub fn degrees(&self) -> (usize, usize) {
        (self.rows - 1, self.cols - 1)
    }

    /// Dimension r of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Control point u_ij.
    pub fn point(&self, i: usize, j: usize) -> &[f64] {
        let k = (i * self.cols + j) * self.dim;
        &self.net[k..k + self.dim]
    }

    /// The net as `net[i][j]`.
    pub fn net(&self) -> Vec<Vec<Vec<f64>>> {
        (0..self.rows)
            .map(|i| (0..self.cols).map(|j| self.point(i, j).to_vec()).collect())
            .collect()
    }

    /// The net, row-major.
    pub fn net_flat(&self) -> &[f64] {
        &self.net
    }

    /// Largest Euclidean norm of a net point.
    pub fn scale(&self) -> f64 {
        max_norm(&self.net, self.dim)
    }

    /// The net transposed (columns become rows), row-major.
    fn transposed(&self) -> Vec<f64> {
        let mut t = Vec::with_capacity(self.net.len());
        for j in 0..self.cols {
            for i in 0..self.rows {
                t.extend_from_slice(self.point(i, j));
            }
        }
        t
    }

    fn from_transposed(cols: usize, rows: usize, dim: usize, t: &[f64]) -> Result<Self> {
        Self::from_flat(rows, cols, dim, untranspose(cols, rows, dim, t))
    }

    /// The net as a curve in `direction`: (points, point dimension).
    fn as_curve(&self, direction: Direction) -> (Vec<f64>, usize) {
        match direction {
            Direction::U => (self.net.clone(), self.cols * self.dim),
            Direction::V => (self.transposed(), self.rows * self.dim),
        }
    }

    fn rebuild(&self, direction: Direction, pts: &[f64], len: usize) -> Result<Self> {
        match direction {
            Direction::U => Self::from_flat(len, self.cols, self.dim, pts.to_vec()),
            Direction::V => Self::from_transposed(len, self.rows, self.dim, pts),
        }
    }

    /// Writes p(u, v) into `out` (length r), using `row` (length (m+1)·r) and `work` (length
    /// (n+1)·(m+1)·r) as scratch.
    fn eval_with(&self, u: f64, v: f64, work: &mut [f64], row: &mut [f64], out: &mut [f64]) {
        let row_dim = self.cols * self.dim;
        de_casteljau(&self.net, row_dim, u, work, row);
        de_casteljau(row, self.dim, v, &mut work[..row_dim], out);
    }

    /// The point p(u, v) (formula (11)), by de Casteljau in u then in v.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        let mut work = vec![0.0; self.net.len()];
        let mut row = vec![0.0; self.cols * self.dim];
        self.eval_with(u, v, &mut work, &mut row, &mut out);
        out
    }

    /// Evaluates on the grid `us` × `vs`, writing p(us\[a\], vs\[b\]) to
    /// `out[(a * vs.len() + b) * r ..]`. Each row of the grid costs one de Casteljau in u.
    /// Errors: wrong buffer length, non-finite parameters.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_eval_args("parameter u", us, us.len() * vs.len(), d, out)?;
        check_eval_args("parameter v", vs, us.len() * vs.len(), d, out)?;
        let row_dim = self.cols * d;
        let mut work = vec![0.0; self.net.len()];
        let mut row = vec![0.0; row_dim];
        for (a, &u) in us.iter().enumerate() {
            de_casteljau(&self.net, row_dim, u, &mut work, &mut row);
            for (b, &v) in vs.iter().enumerate() {
                let k = (a * vs.len() + b) * d;
                de_casteljau(&row, d, v, &mut work[..row_dim], &mut out[k..k + d]);
            }
        }
        Ok(())
    }

    /// The partial-derivative surface ∂p/∂u (degree n-1 in u) or ∂p/∂v.
    pub fn derivative(&self, direction: Direction) -> BezierSurface {
        let (pts, pd) = self.as_curve(direction);
        let len = pts.len() / pd;
        let n = len - 1;
        let deriv: Vec<f64> = if n == 0 {
            vec![0.0; pd]
        } else {
            (0..n)
                .flat_map(|i| (0..pd).map(move |k| (i, k)))
                .map(|(i, k)| n as f64 * (pts[(i + 1) * pd + k] - pts[i * pd + k]))
                .collect()
        };
        // Built directly: differences of huge coordinates may overflow to ±inf, which the
        // validating constructor would refuse; the derivative is still the derivative.
        let len = n.max(1);
        match direction {
            Direction::U => BezierSurface {
                dim: self.dim,
                rows: len,
                cols: self.cols,
                net: deriv,
            },
            Direction::V => BezierSurface {
                dim: self.dim,
                rows: self.rows,
                cols: len,
                net: untranspose(len, self.rows, self.dim, &deriv),
            },
        }
    }

    /// The unit normal (∂p/∂u × ∂p/∂v normalized) of a surface in R^3. `Ok(None)` where the
    /// partial derivatives are parallel or vanish (a degenerate point, e.g. a collapsed edge).
    pub fn normal(&self, u: f64, v: f64) -> Result<Option<[f64; 3]>> {
        if self.dim != 3 {
            return Err(Error::WrongDimension {
                operation: "surface normal",
                expected: 3,
                got: self.dim,
            });
        }
        let a = self.derivative(Direction::U).eval(u, v);
        let b = self.derivative(Direction::V).eval(u, v);
        Ok(unit_normal(&a, &b))
    }

    /// Real degrees and defects in both directions (16), by the residual test with a relative
    /// tolerance (default [`super::DEFAULT_TOLERANCE`]) on all rows / columns jointly.
    pub fn degree_report(&self, tolerance: Option<f64>) -> Result<SurfaceDegreeReport> {
        let tol = check_tolerance(tolerance)?;
        let report = |dir| {
            let (pts, pd) = self.as_curve(dir);
            real_degree_flat(&pts, pd, self.dim, tol)
        };
        Ok(SurfaceDegreeReport {
            u: report(Direction::U)?,
            v: report(Direction::V)?,
        })
    }

    fn change_direction(
        &self,
        direction: Direction,
        target: usize,
        tol: f64,
        progress: &Progress,
    ) -> Result<Self> {
        let (pts, pd) = self.as_curve(direction);
        let n = pts.len() / pd - 1;
        let new = if target >= n {
            elevate_flat_reporting(&pts, pd, target, progress)?
        } else {
            let (x, res) = reduce_least_squares(&pts, pd, self.dim, target)?;
            if res > tol {
                let r = real_degree_flat(&pts, pd, self.dim, tol)?;
                return Err(Error::SurfaceDefectTooSmall {
                    direction: direction.name(),
                    real_degree: r.real_degree,
                    requested: target,
                    defect: r.defect,
                });
            }
            progress.advance((target + 1) as u64)?;
            x
        };
        self.rebuild(direction, &new, target + 1)
    }

    /// Formula (14) done stably: the same surface on an (n'+1)×(m'+1) net, each direction
    /// elevated or exactly reduced independently (all eight problems of the paper). Errors
    /// with [`Error::SurfaceDefectTooSmall`] naming the direction when a reduction is
    /// impossible at this tolerance.
    pub fn change_degree(
        &self,
        n_new: usize,
        m_new: usize,
        tolerance: Option<f64>,
    ) -> Result<Self> {
        self.change_degree_with_progress(n_new, m_new, tolerance, &Progress::none())
    }

    /// [`BezierSurface::change_degree`] reporting to `progress` ([`crate::progress`]): the
    /// units are the n' + 1 new rows of the net, then its m' + 1 new columns, reported as
    /// an elevation computes them (about once per 2^18 multiply-adds) or at the end of a
    /// reduction. The same surface, bit for bit, as without it; [`Error::Cancelled`] when
    /// the callback asks to stop.
    pub fn change_degree_with_progress(
        &self,
        n_new: usize,
        m_new: usize,
        tolerance: Option<f64>,
        progress: &Progress,
    ) -> Result<Self> {
        let tol = check_tolerance(tolerance)?;
        progress.add_total((n_new + 1 + m_new + 1) as u64)?;
        let s = self
            .change_direction(Direction::U, n_new, tol, progress)?
            .change_direction(Direction::V, m_new, tol, progress)?;
        progress.finish()?;
        Ok(s)
    }

    /// Formula (14) exactly as the paper writes it, with the exact matrices
    /// H_n E H_(n')^-1 rounded once to f64: for a reduction below the real degree it
    /// truncates the power form at (0, 0). Errors if the result overflows, and with
    /// [`Error::TooLarge`] for degrees above [`super::MAX_PAPER_DEGREE`].
    pub fn change_degree_paper(&self, n_new: usize, m_new: usize) -> Result<Self> {
        let (pts, pd) = self.as_curve(Direction::U);
        let s = self.rebuild(
            Direction::U,
            &paper_change_flat(&pts, pd, n_new)?,
            n_new + 1,
        )?;
        let (pts, pd) = s.as_curve(Direction::V);
        s.rebuild(
            Direction::V,
            &paper_change_flat(&pts, pd, m_new)?,
            m_new + 1,
        )
    }

    /// Manual change (13): inserts a whole row (direction U, a polyline of m+1 points) or
    /// column (direction V, n+1 points) before `index`. The shape changes.
    pub fn insert_line(
        &self,
        direction: Direction,
        index: usize,
        line: &[Vec<f64>],
    ) -> Result<Self> {
        let (mut pts, pd) = self.as_curve(direction);
        let len = pts.len() / pd;
        if index > len {
            return Err(Error::IndexOutOfRange {
                what: "insertion position",
                index,
                len: len + 1,
            });
        }
        if line.len() * self.dim != pd {
            return Err(Error::TooFewPoints {
                what: "points in the inserted line",
                got: line.len(),
                min: pd / self.dim,
            });
        }
        let mut flat = Vec::with_capacity(pd);
        for (k, p) in line.iter().enumerate() {
            if p.len() != self.dim {
                return Err(Error::DimensionMismatch {
                    what: "inserted point",
                    index: k,
                    expected: self.dim,
                    got: p.len(),
                });
            }
            flat.extend_from_slice(p);
        }
        pts.splice(index * pd..index * pd, flat);
        self.rebuild(direction, &pts, len + 1)
    }

    /// Manual change (13): removes row (U) or column (V) `index`. The shape changes.
    pub fn remove_line(&self, direction: Direction, index: usize) -> Result<Self> {
        let (mut pts, pd) = self.as_curve(direction);
        let len = pts.len() / pd;
        if index >= len {
            return Err(Error::IndexOutOfRange {
                what: "net line",
                index,
                len,
            });
        }
        if len == 1 {
            return Err(Error::TooFewPoints {
                what: "net lines after removal",
                got: 0,
                min: 1,
            });
        }
        pts.drain(index * pd..(index + 1) * pd);
        self.rebuild(direction, &pts, len - 1)
    }

    /// Distance between two surfaces of the same dimension over \[0,1\]²: the largest distance
    /// found on a 65×65 grid, and a guaranteed upper bound (both elevated to common degrees;
    /// the largest difference of net points bounds the difference surface).
    pub fn deviation_from(&self, other: &BezierSurface) -> Result<DeviationBound> {
        if self.dim != other.dim {
            return Err(Error::WrongDimension {
                operation: "deviation",
                expected: self.dim,
                got: other.dim,
            });
        }
        let (n, m) = self.degrees();
        let (p, q) = other.degrees();
        let (nn, mm) = (n.max(p), m.max(q));
        let a = self.change_degree(nn, mm, None)?;
        let b = other.change_degree(nn, mm, None)?;
        let diff: Vec<f64> = a.net.iter().zip(&b.net).map(|(x, y)| x - y).collect();
        let slack = 4.0 * f64::EPSILON * (nn + mm + 2) as f64 * a.scale().max(b.scale());
        let ts: Vec<f64> = (0..65).map(|k| k as f64 / 64.0).collect();
        let mut ga = vec![0.0; 65 * 65 * self.dim];
        let mut gb = ga.clone();
        self.eval_grid(&ts, &ts, &mut ga)?;
        other.eval_grid(&ts, &ts, &mut gb)?;
        let (mut best, mut at) = (0.0, 0.0);
        for (k, (x, y)) in ga
            .chunks_exact(self.dim)
            .zip(gb.chunks_exact(self.dim))
            .enumerate()
        {
            let d = distance(x, y);
            if d > best {
                best = d;
                at = ts[k / 65];
            }
        }
        Ok(DeviationBound {
            max_found: best,
            at,
            upper_bound: max_norm(&diff, self.dim).max(best) + slack,
        })
    }
}

/// Formula (11) of spec/bezier-order.md on [0, 1]², by de Casteljau in u then in v.
impl Surface for BezierSurface {
    crate::geom::forward_to_inherent!(BezierSurface; dim, eval_grid);

    /// [0, 1]².
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        ((0.0, 1.0), (0.0, 1.0))
    }

    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let mut work = vec![0.0; self.net.len()];
        let mut row = vec![0.0; self.cols * self.dim];
        self.eval_with(u, v, &mut work, &mut row, out);
    }

    /// De Casteljau with scratch reused over chunks of points (in parallel for large
    /// batches): the values of [`Surface::eval_into`], bit for bit.
    fn eval_batch(&self, uv: &[f64], out: &mut [f64], options: &BatchOptions) -> Result<()> {
        let d = self.dim;
        check_pairs(uv, d, out)?;
        let parallel = options.parallel() && uv.len() / 2 > 1024;
        crate::par::zip_chunks(parallel, out, 1024 * d, uv, 2048, |o, q| {
            let mut work = vec![0.0; self.net.len()];
            let mut row = vec![0.0; self.cols * d];
            for (p, x) in q.chunks_exact(2).zip(o.chunks_exact_mut(d)) {
                self.eval_with(p[0], p[1], &mut work, &mut row, x);
            }
        });
        Ok(())
    }

    /// Every order: the ku-th hodograph in u of the kv-th in v (formula (11) differentiated
    /// term by term), zero above the degrees.
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim, out)?;
        let (n, m) = self.degrees();
        if ku > n || kv > m {
            out.fill(0.0);
            return Ok(());
        }
        let mut s = std::borrow::Cow::Borrowed(self);
        for _ in 0..ku {
            s = std::borrow::Cow::Owned(s.derivative(Direction::U));
        }
        for _ in 0..kv {
            s = std::borrow::Cow::Owned(s.derivative(Direction::V));
        }
        Surface::eval_into(s.as_ref(), u, v, out);
        Ok(())
    }
}
