//! Rational tensor-product Bézier surfaces:
//! p(u, v) = Σ_i Σ_j w_ij b_ni(u) b_mj(v) u_ij / Σ_i Σ_j w_ij b_ni(u) b_mj(v) (formula (11)
//! of spec/bezier-order.md with weights). As for rational curves, the order changes through
//! homogeneous coordinates (w_ij u_ij, w_ij) ∈ R^(r+1), where the surface is polynomial and
//! every order change of [`BezierSurface`] (formula (14), both directions, up and down)
//! applies unchanged: the rational surface keeps its shape, and its real degrees are those
//! of the homogeneous surface (numerator and denominator over one common denominator).
//!
//! ```
//! use geomkit::bezier::RationalBezierSurface;
//! use geomkit::geom::Surface;
//! // A quarter of a cylinder of radius 1: the quarter circle (rational quadratic) in u,
//! // a straight line in v.
//! let h = std::f64::consts::FRAC_1_SQRT_2;
//! let s = RationalBezierSurface::new(
//!     vec![
//!         vec![vec![1.0, 0.0, 0.0], vec![1.0, 0.0, 2.0]],
//!         vec![vec![1.0, 1.0, 0.0], vec![1.0, 1.0, 2.0]],
//!         vec![vec![0.0, 1.0, 0.0], vec![0.0, 1.0, 2.0]],
//!     ],
//!     vec![vec![1.0, 1.0], vec![h, h], vec![1.0, 1.0]],
//! )
//! .unwrap();
//! let e = s.change_degree(4, 3, None).unwrap();
//! let p = Surface::eval(&e, 0.3, 0.7);
//! assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
//! assert!((p[2] - 1.4).abs() < 1e-15);
//! assert_eq!(e.degree_report(None).unwrap().real_degrees(), (2, 1));
//! ```

use super::rational::{homogeneous_flat, project, split_homogeneous};
use super::surface::{BezierSurface, Direction, SurfaceDegreeReport};
use crate::geom::{check_point, Surface};
use crate::points::{check_eval_args, flatten_grid, unit_normal};
use crate::progress::Progress;
use crate::{Error, Result};

/// A rational tensor-product Bézier surface with positive weights.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalBezierSurface {
    /// Homogeneous net (w_ij u_ij, w_ij), dimension r + 1.
    homogeneous: BezierSurface,
    /// The Cartesian net u_ij as given (row-major, dimension r), kept bit for bit.
    points: Vec<f64>,
    /// The weights as given (row-major).
    weights: Vec<f64>,
}

/// An invalid weight at a row-major net index, named by its row and column.
fn net_weight_error(error: Error, cols: usize) -> Error {
    match error {
        Error::InvalidWeight { index, value } => Error::InvalidNetWeight {
            row: index / cols,
            col: index % cols,
            value,
        },
        other => other,
    }
}

impl RationalBezierSurface {
    /// A surface from its net (`net[i][j]` the control point u_ij) and weights
    /// (`weights[i][j]` = w_ij, finite and > 0, the net's shape). When some w_ij·u_ij would
    /// overflow or underflow f64 the homogeneous net holds the weights scaled by a common
    /// power of two (the same surface).
    ///
    /// Errors: those of [`BezierSurface::new`]; [`Error::WeightCount`] when `weights` has
    /// another number of rows than the net (the counts of all weights and points),
    /// [`Error::WeightRow`] when a row has another length; [`Error::InvalidNetWeight`] naming
    /// the first weight that is not finite and > 0.
    pub fn new(net: Vec<Vec<Vec<f64>>>, weights: Vec<Vec<f64>>) -> Result<Self> {
        let (rows, cols, dim, flat) = flatten_grid("control net", &net)?;
        if weights.len() != rows {
            return Err(Error::WeightCount {
                expected: rows * cols,
                got: weights.iter().map(Vec::len).sum(),
            });
        }
        if let Some(row) = weights.iter().position(|w| w.len() != cols) {
            return Err(Error::WeightRow {
                row,
                expected: cols,
                got: weights[row].len(),
            });
        }
        Self::from_flat(rows, cols, dim, flat, weights.concat())
    }

    /// A surface from a row-major net of `rows`×`cols` points with `dim` coordinates and
    /// its `rows * cols` weights, row-major. Errors as [`RationalBezierSurface::new`].
    pub fn from_flat(
        rows: usize,
        cols: usize,
        dim: usize,
        net: Vec<f64>,
        weights: Vec<f64>,
    ) -> Result<Self> {
        // Validates the net (empty, sizes, finite) before the weights are looked at.
        BezierSurface::from_flat(rows, cols, dim, net.clone())?;
        if weights.len() != rows * cols {
            return Err(Error::WeightCount {
                expected: rows * cols,
                got: weights.len(),
            });
        }
        let h = homogeneous_flat(&net, dim, &weights).map_err(|e| net_weight_error(e, cols))?;
        Ok(RationalBezierSurface {
            homogeneous: BezierSurface::from_flat(rows, cols, dim + 1, h)?,
            points: net,
            weights,
        })
    }

    /// The surface whose homogeneous net is that of `h` (last coordinate the weight).
    /// Errors when `h` has fewer than 2 coordinates or a weight is not > 0
    /// ([`Error::InvalidNetWeight`]).
    pub fn from_homogeneous(h: BezierSurface) -> Result<Self> {
        if h.dim() < 2 {
            return Err(Error::WrongDimension {
                operation: "rational surface from homogeneous points",
                expected: 2,
                got: h.dim(),
            });
        }
        let cols = h.degrees().1 + 1;
        let (points, weights) =
            split_homogeneous(h.net_flat(), h.dim()).map_err(|e| net_weight_error(e, cols))?;
        Ok(RationalBezierSurface {
            homogeneous: h,
            points,
            weights,
        })
    }

    /// Formal degrees (n, m).
    pub fn degrees(&self) -> (usize, usize) {
        self.homogeneous.degrees()
    }

    /// Dimension r of the (Cartesian) points.
    pub fn dim(&self) -> usize {
        self.homogeneous.dim() - 1
    }

    /// The homogeneous (polynomial) surface in R^(r+1).
    pub fn homogeneous(&self) -> &BezierSurface {
        &self.homogeneous
    }

    /// The Cartesian net as `net[i][j]`: the points the surface was made from, bit for bit
    /// ((w u)/w for a surface made from homogeneous points).
    pub fn net(&self) -> Vec<Vec<Vec<f64>>> {
        let (r, cols) = (self.dim(), self.degrees().1 + 1);
        self.points
            .chunks_exact(cols * r)
            .map(|row| row.chunks_exact(r).map(<[f64]>::to_vec).collect())
            .collect()
    }

    /// The Cartesian net, row-major.
    pub fn net_flat(&self) -> &[f64] {
        &self.points
    }

    /// The weights as `weights[i][j]` (as given, bit for bit).
    pub fn weights(&self) -> Vec<Vec<f64>> {
        self.weights
            .chunks_exact(self.degrees().1 + 1)
            .map(<[f64]>::to_vec)
            .collect()
    }

    /// The weights, row-major.
    pub fn weights_flat(&self) -> &[f64] {
        &self.weights
    }

    /// The point p(u, v), de Casteljau on the homogeneous net, then divided by the weight.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim()];
        Surface::eval_into(self, u, v, &mut out);
        out
    }

    /// Evaluates on the grid `us` × `vs`, writing p(us\[a\], vs\[b\]) to
    /// `out[(a * vs.len() + b) * r ..]` (one de Casteljau in u per row of the grid, on the
    /// homogeneous net). Errors: wrong buffer length, non-finite parameters.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let r = self.dim();
        let count = us.len() * vs.len();
        check_eval_args("parameter u", us, count, r, out)?;
        check_eval_args("parameter v", vs, count, r, out)?;
        let mut h = vec![0.0; count * (r + 1)];
        self.homogeneous.eval_grid(us, vs, &mut h)?;
        for (o, x) in out.chunks_exact_mut(r).zip(h.chunks_exact(r + 1)) {
            project(x, o);
        }
        Ok(())
    }

    /// Real degrees and defects (16) of the homogeneous surface in both directions.
    pub fn degree_report(&self, tolerance: Option<f64>) -> Result<SurfaceDegreeReport> {
        self.homogeneous.degree_report(tolerance)
    }

    /// Formula (14) on the homogeneous net: the same rational surface of degrees
    /// (n', m'), each direction elevated or exactly reduced. Errors as
    /// [`BezierSurface::change_degree`]; [`Error::InvalidNetWeight`] if a reduced weight is
    /// not positive.
    pub fn change_degree(
        &self,
        n_new: usize,
        m_new: usize,
        tolerance: Option<f64>,
    ) -> Result<Self> {
        Self::from_homogeneous(self.homogeneous.change_degree(n_new, m_new, tolerance)?)
    }

    /// [`RationalBezierSurface::change_degree`] reporting to `progress` as
    /// [`BezierSurface::change_degree_with_progress`] does (on the homogeneous net).
    pub fn change_degree_with_progress(
        &self,
        n_new: usize,
        m_new: usize,
        tolerance: Option<f64>,
        progress: &Progress,
    ) -> Result<Self> {
        let h = self
            .homogeneous
            .change_degree_with_progress(n_new, m_new, tolerance, progress)?;
        Self::from_homogeneous(h)
    }

    /// The Cartesian net with each point's weight appended (dimension r + 1, not
    /// homogeneous): the form in which lines of the net are inserted and removed.
    fn weighted_net(&self) -> BezierSurface {
        let r = self.dim();
        let (n, m) = self.degrees();
        let mut flat = Vec::with_capacity(self.weights.len() * (r + 1));
        for (p, w) in self.points.chunks_exact(r).zip(&self.weights) {
            flat.extend_from_slice(p);
            flat.push(*w);
        }
        BezierSurface::from_flat(n + 1, m + 1, r + 1, flat).expect("a valid net with weights")
    }

    /// The surface of a net with weights appended (see [`Self::weighted_net`]).
    fn from_weighted_net(s: &BezierSurface) -> Result<Self> {
        let (n, m) = s.degrees();
        let d = s.dim();
        let flat = s.net_flat();
        let points = flat
            .chunks_exact(d)
            .flat_map(|p| p[..d - 1].iter().copied())
            .collect();
        let weights = flat.chunks_exact(d).map(|p| p[d - 1]).collect();
        Self::from_flat(n + 1, m + 1, d - 1, points, weights)
    }

    /// Manual change (13) with weights: inserts a row (direction U, m+1 points and weights)
    /// or a column (direction V, n+1) before `index`. The shape changes; the other points
    /// and weights are kept bit for bit. Errors as [`BezierSurface::insert_line`], and for
    /// the weights as [`RationalBezierSurface::new`].
    pub fn insert_line(
        &self,
        direction: Direction,
        index: usize,
        line: &[Vec<f64>],
        weights: &[f64],
    ) -> Result<Self> {
        if weights.len() != line.len() {
            return Err(Error::WeightCount {
                expected: line.len(),
                got: weights.len(),
            });
        }
        let r = self.dim();
        let mut weighted = Vec::with_capacity(line.len());
        for (k, (p, w)) in line.iter().zip(weights).enumerate() {
            if p.len() != r {
                return Err(Error::DimensionMismatch {
                    what: "inserted point",
                    index: k,
                    expected: r,
                    got: p.len(),
                });
            }
            weighted.push(p.iter().copied().chain([*w]).collect());
        }
        let s = self
            .weighted_net()
            .insert_line(direction, index, &weighted)?;
        Self::from_weighted_net(&s)
    }

    /// Manual change (13): removes row (U) or column (V) `index` with its weights. The shape
    /// changes. Errors as [`BezierSurface::remove_line`].
    pub fn remove_line(&self, direction: Direction, index: usize) -> Result<Self> {
        Self::from_weighted_net(&self.weighted_net().remove_line(direction, index)?)
    }

    /// The unit normal (∂p/∂u × ∂p/∂v normalized) of a surface in R^3; `Ok(None)` where the
    /// partial derivatives are parallel or vanish.
    pub fn normal(&self, u: f64, v: f64) -> Result<Option<[f64; 3]>> {
        if self.dim() != 3 {
            return Err(Error::WrongDimension {
                operation: "surface normal",
                expected: 3,
                got: self.dim(),
            });
        }
        let (mut a, mut b) = ([0.0; 3], [0.0; 3]);
        self.derivative_into(u, v, (1, 0), &mut a)?;
        self.derivative_into(u, v, (0, 1), &mut b)?;
        Ok(unit_normal(&a, &b))
    }
}

/// p(u, v) = A(u, v) / w(u, v) on [0, 1]², A and w the homogeneous surface's coordinates.
impl Surface for RationalBezierSurface {
    crate::geom::forward_to_inherent!(RationalBezierSurface; dim, eval_grid);

    /// [0, 1]².
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        ((0.0, 1.0), (0.0, 1.0))
    }

    fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let mut h = vec![0.0; self.homogeneous.dim()];
        Surface::eval_into(&self.homogeneous, u, v, &mut h);
        project(&h, out);
    }

    /// Every order, by the quotient rule on the homogeneous partial derivatives H^(i,j) =
    /// (A^(i,j), w^(i,j)): p^(k,l) = (A^(k,l) - Σ_((i,j) ≠ (0,0), i ≤ k, j ≤ l) C(k,i) C(l,j)
    /// w^(i,j) p^(k-i,l-j)) / w (Piegl and Tiller, The NURBS Book, (4.20)).
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        let r = self.dim();
        check_point(&[u, v], r, out)?;
        let hd = r + 1;
        let at = |i: usize, j: usize| i * (kv + 1) + j;
        let mut h = vec![0.0; (ku + 1) * (kv + 1) * hd];
        for i in 0..=ku {
            for j in 0..=kv {
                let k = at(i, j) * hd;
                self.homogeneous
                    .derivative_into(u, v, (i, j), &mut h[k..k + hd])?;
            }
        }
        let w = h[r];
        let mut p = vec![0.0; (ku + 1) * (kv + 1) * r];
        for k in 0..=ku {
            for l in 0..=kv {
                let mut acc = h[at(k, l) * hd..at(k, l) * hd + r].to_vec();
                let mut ck = 1.0;
                for i in 0..=k {
                    let mut cl = 1.0;
                    for j in 0..=l {
                        if i + j > 0 {
                            let wij = ck * cl * h[at(i, j) * hd + r];
                            let q = at(k - i, l - j) * r;
                            for (a, x) in acc.iter_mut().zip(&p[q..q + r]) {
                                *a -= wij * x;
                            }
                        }
                        cl = cl * (l - j) as f64 / (j + 1) as f64;
                    }
                    ck = ck * (k - i) as f64 / (i + 1) as f64;
                }
                let q = at(k, l) * r;
                for (o, a) in p[q..q + r].iter_mut().zip(&acc) {
                    *o = a / w;
                }
            }
        }
        out.copy_from_slice(&p[at(ku, kv) * r..]);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder() -> RationalBezierSurface {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        RationalBezierSurface::new(
            vec![
                vec![vec![1.0, 0.0, 0.0], vec![1.0, 0.0, 2.0]],
                vec![vec![1.0, 1.0, 0.0], vec![1.0, 1.0, 2.0]],
                vec![vec![0.0, 1.0, 0.0], vec![0.0, 1.0, 2.0]],
            ],
            vec![vec![1.0, 1.0], vec![h, h], vec![1.0, 1.0]],
        )
        .unwrap()
    }

    #[test]
    fn weights_are_checked_by_position() {
        let net = vec![vec![vec![0.0], vec![1.0]], vec![vec![2.0], vec![3.0]]];
        assert_eq!(
            RationalBezierSurface::new(net.clone(), vec![vec![1.0, 1.0], vec![1.0, 0.0]]),
            Err(Error::InvalidNetWeight {
                row: 1,
                col: 1,
                value: 0.0
            })
        );
        assert_eq!(
            RationalBezierSurface::new(net.clone(), vec![vec![1.0, 1.0], vec![1.0]]),
            Err(Error::WeightRow {
                row: 1,
                expected: 2,
                got: 1
            })
        );
        assert_eq!(
            RationalBezierSurface::new(net, vec![vec![1.0, 1.0]]),
            Err(Error::WeightCount {
                expected: 4,
                got: 2
            })
        );
    }

    #[test]
    fn derivatives_of_the_cylinder_are_those_of_the_circle() {
        // u ↦ (x(u), y(u)) is the rational quarter circle; its angle θ(u) satisfies
        // x = cos θ, y = sin θ, so ∂p/∂u is perpendicular to (x, y) and ∂p/∂v = (0, 0, 2).
        let s = cylinder();
        for &(u, v) in &[(0.0, 0.0), (0.3, 0.7), (1.0, 0.5)] {
            let p = s.eval(u, v);
            let mut du = [0.0; 3];
            let mut dv = [0.0; 3];
            let mut duv = [0.0; 3];
            s.derivative_into(u, v, (1, 0), &mut du).unwrap();
            s.derivative_into(u, v, (0, 1), &mut dv).unwrap();
            s.derivative_into(u, v, (1, 1), &mut duv).unwrap();
            assert!((du[0] * p[0] + du[1] * p[1]).abs() < 1e-14);
            assert_eq!(du[2], 0.0);
            assert!((dv[2] - 2.0).abs() < 1e-15 && dv[0].abs() < 1e-15);
            assert!(duv.iter().all(|x| x.abs() < 1e-14));
        }
    }

    #[test]
    fn insert_then_remove_gives_back_the_surface() {
        let s = cylinder();
        let t = s
            .insert_line(
                Direction::V,
                1,
                &[
                    vec![2.0, 0.0, 1.0],
                    vec![2.0, 2.0, 1.0],
                    vec![0.0, 2.0, 1.0],
                ],
                &[1.0, 0.5, 1.0],
            )
            .unwrap();
        assert_eq!(t.degrees(), (2, 2));
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(
            t.weights(),
            vec![vec![1.0; 3], vec![h, 0.5, h], vec![1.0; 3]]
        );
        assert_eq!(t.net()[1][1], vec![2.0, 2.0, 1.0]);
        let back = t.remove_line(Direction::V, 1).unwrap();
        assert_eq!(back.net(), s.net());
        assert_eq!(back.weights(), s.weights());
    }
}
