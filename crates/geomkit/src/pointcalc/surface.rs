//! Point equations of surfaces through a net of source points (spec/point-calculus.md §3).
//!
//! - [`PointSurface`]: "rows first, then across": row i has its own nodes along u,
//!   M_i(u) = Σ_j L_j^(i)(u) A_ij, and M(u, v) = Σ_i L_i(v) M_i(u) with nodes v_i across the
//!   rows. The function-parameters a_ij(u, v) = L_i(v) L_j^(i)(u) sum to 1 and the surface
//!   passes through every A_ij (at u = u_j^(i), v = v_i). When all rows share their nodes this
//!   is the tensor product ([`PointSurface::tensor`]).
//! - [`printed_geomatrix`]: the geomatrix (9) exactly as printed, a_ij = U_ij V_ij with the
//!   placement of row i along u and the placement of column j along v. Kept as a documented
//!   variant: its elements do not sum to 1 (1.156 at the centre) and a_22(1/2, 1/2) = 1, but
//!   a_11(1/2, 1/2) = 1/16 ≠ 0, so the surface misses the centre point.
//!
//! ```
//! use geomkit::pointcalc::{Nodes, PointSurface};
//! let net: Vec<Vec<Vec<f64>>> = (0..3)
//!     .map(|i| (0..3).map(|j| vec![j as f64, i as f64, ((i * j) % 2) as f64]).collect())
//!     .collect();
//! let rows = vec![Nodes::paper_third(), Nodes::paper_half(), Nodes::paper_two_thirds()];
//! let s = PointSurface::rows_then_across(rows, Nodes::paper_half(), net).unwrap();
//! assert_eq!(s.eval(0.5, 0.5), vec![1.0, 1.0, 1.0]); // the centre point A_22
//! let a = s.shares(0.3, 0.8);
//! assert!((a.iter().flatten().sum::<f64>() - 1.0).abs() < 1e-15);
//! ```

use super::equation::{check_lebesgue, PointEquation, PointOptions, Warning};
use super::nodes::Nodes;
use super::wide::{combine_wide, short};
use crate::exact::Rational;
use crate::geom::{check_point, Curve, Surface};
use crate::points::flatten_grid;
use crate::{Error, Result};

/// A surface M(u, v) = Σ_ij a_ij(u, v) A_ij through a net of source points, rows first
/// (each row with its own nodes along u), then across (nodes along v).
#[derive(Debug, Clone, PartialEq)]
pub struct PointSurface {
    across: Nodes,
    rows: Vec<PointEquation>,
    dim: usize,
    warnings: Vec<Warning>,
}

impl PointSurface {
    /// The tensor-product surface: every row of `net` (net\[i\]\[j\], i across along v, j along
    /// the row along u) uses `u_nodes`, the rows sit at `v_nodes`. Errors: ragged or empty
    /// net, mixed dimensions, non-finite coordinates, counts that differ from the nodes.
    pub fn tensor(u_nodes: Nodes, v_nodes: Nodes, net: Vec<Vec<Vec<f64>>>) -> Result<Self> {
        let rows = vec![u_nodes; net.len()];
        PointSurface::rows_then_across(rows, v_nodes, net)
    }

    /// Rows first (row i through its points at `row_nodes[i]`, rows may differ in length),
    /// then across at `across` (one node per row). Default options.
    pub fn rows_then_across(
        row_nodes: Vec<Nodes>,
        across: Nodes,
        net: Vec<Vec<Vec<f64>>>,
    ) -> Result<Self> {
        PointSurface::with_options(row_nodes, across, net, &PointOptions::default())
    }

    /// As [`PointSurface::rows_then_across`], with options.
    pub fn with_options(
        row_nodes: Vec<Nodes>,
        across: Nodes,
        net: Vec<Vec<Vec<f64>>>,
        options: &PointOptions,
    ) -> Result<Self> {
        if net.len() != across.len() {
            return Err(Error::PointCount {
                what: "rows of the net".into(),
                expected: across.len(),
                got: net.len(),
            });
        }
        if row_nodes.len() != net.len() {
            return Err(Error::PointCount {
                what: "node sets of the rows".into(),
                expected: net.len(),
                got: row_nodes.len(),
            });
        }
        let dim = net
            .first()
            .and_then(|r| r.first())
            .map(Vec::len)
            .ok_or(Error::Empty { what: "net" })?;
        let mut warnings: Vec<Warning> = check_lebesgue("the nodes across", &across, options)?
            .into_iter()
            .collect();
        let mut rows = Vec::with_capacity(net.len());
        for (i, (nodes, row)) in row_nodes.into_iter().zip(net).enumerate() {
            if row.len() != nodes.len() {
                return Err(Error::PointCount {
                    what: format!("points of row {i}"),
                    expected: nodes.len(),
                    got: row.len(),
                });
            }
            if let Some(j) = row.iter().position(|p| p.len() != dim) {
                return Err(Error::DimensionMismatch {
                    what: "net point",
                    index: j,
                    expected: dim,
                    got: row[j].len(),
                });
            }
            let eq = PointEquation::with_options(
                nodes,
                row,
                &PointOptions {
                    lebesgue_limit: options.lebesgue_limit,
                    strict: options.strict,
                },
            )
            .map_err(|e| match e {
                Error::LebesgueTooLarge { value, limit, .. } => Error::LebesgueTooLarge {
                    what: format!("row {i}"),
                    value,
                    limit,
                },
                e => e,
            })?;
            for w in eq.warnings() {
                let Warning::LargeLebesgue { value, limit, .. } = w;
                warnings.push(Warning::LargeLebesgue {
                    what: format!("row {i}"),
                    value: *value,
                    limit: *limit,
                });
            }
            rows.push(eq);
        }
        Ok(PointSurface {
            across,
            rows,
            dim,
            warnings,
        })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The nodes across the rows (along v).
    pub fn across(&self) -> &Nodes {
        &self.across
    }

    /// The point equations of the rows (along u).
    pub fn rows(&self) -> &[PointEquation] {
        &self.rows
    }

    /// Warnings found when building.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// ((u0, u1), (v0, v1)): the hull of the rows' node intervals and the nodes across.
    pub fn domain(&self) -> ((f64, f64), (f64, f64)) {
        let u0 = self
            .rows
            .iter()
            .map(|r| r.domain().0)
            .fold(f64::INFINITY, f64::min);
        let u1 = self
            .rows
            .iter()
            .map(|r| r.domain().1)
            .fold(f64::NEG_INFINITY, f64::max);
        ((u0, u1), self.across.domain())
    }

    /// M(u, v) into `out` (length dim). Where the plain sums leave the f64 range, computed
    /// again with the rows' points scaled by a power of two (±infinity only where a row's
    /// point M_i(u) or M(u, v) itself is beyond f64, never NaN).
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let lv = self.across.basis(v);
        let mut row = vec![0.0; self.dim];
        out.fill(0.0);
        for (w, eq) in lv.iter().zip(&self.rows) {
            if *w == 0.0 {
                continue;
            }
            eq.eval_into(u, &mut row);
            for (o, x) in out.iter_mut().zip(&row) {
                *o += w * x;
            }
        }
        if out.iter().any(|x| !x.is_finite()) {
            let rows: Vec<f64> = self.rows.iter().flat_map(|eq| eq.eval(u)).collect();
            self.across_wide(v, &rows, out);
        }
    }

    /// Σ_i L_i(v) M_i with nothing overflowing on the way (`rows`: the rows' points M_i,
    /// row-major).
    fn across_wide(&self, v: f64, rows: &[f64], out: &mut [f64]) {
        let mut lv = vec![0.0; self.across.len()];
        let e = self.across.basis_wide(v, &mut lv);
        combine_wide(&lv, e, rows, out);
    }

    /// M(u, v).
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(u, v, &mut out);
        out
    }

    /// The geomatrix a_ij(u, v) = L_i(v) L_j^(i)(u): the share of every source point
    /// (row i, point j); the shares sum to 1.
    pub fn shares(&self, u: f64, v: f64) -> Vec<Vec<f64>> {
        let lv = self.across.basis(v);
        lv.iter()
            .zip(&self.rows)
            .map(|(w, eq)| eq.shares(u).into_iter().map(|x| w * x).collect())
            .collect()
    }

    /// Points on the grid `us` × `vs` (row-major, u slowest), into `out`
    /// (`us.len() * vs.len() * dim`). Errors: wrong buffer length, non-finite parameters;
    /// [`Error::ResultOverflow`] naming the first point beyond f64.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_grid_args(us, vs, d, out)?;
        // Each row's curve at every u once, then combined across.
        let rows_at_u: Vec<Vec<f64>> = self
            .rows
            .iter()
            .map(|eq| {
                let mut o = vec![0.0; us.len() * d];
                eq.eval_params(us, &mut o).map(|()| o)
            })
            .collect::<Result<_>>()?;
        for (b, &v) in vs.iter().enumerate() {
            let lv = self.across.basis(v);
            for a in 0..us.len() {
                let o = &mut out[(a * vs.len() + b) * d..][..d];
                o.fill(0.0);
                for (w, r) in lv.iter().zip(&rows_at_u) {
                    if *w != 0.0 {
                        for (x, y) in o.iter_mut().zip(&r[a * d..(a + 1) * d]) {
                            *x += w * y;
                        }
                    }
                }
                if o.iter().any(|x| !x.is_finite()) {
                    let rows: Vec<f64> = rows_at_u
                        .iter()
                        .flat_map(|r| r[a * d..(a + 1) * d].iter().copied())
                        .collect();
                    self.across_wide(v, &rows, o);
                    if o.iter().any(|x| !x.is_finite()) {
                        return Err(Error::ResultOverflow {
                            what: format!(
                                "the point of the surface at u={}, v={}",
                                short(us[a]),
                                short(v)
                            ),
                        });
                    }
                }
            }
        }
        Ok(())
    }
}

/// Checks a grid evaluation's buffer (`us.len() * vs.len() * dim`) and parameters.
fn check_grid_args(us: &[f64], vs: &[f64], dim: usize, out: &[f64]) -> Result<()> {
    if out.len() != us.len() * vs.len() * dim {
        return Err(Error::BufferSize {
            expected: us.len() * vs.len() * dim,
            got: out.len(),
        });
    }
    for (what, ps) in [("u", us), ("v", vs)] {
        if let Some(index) = ps.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFinite { what, index });
        }
    }
    Ok(())
}

/// The placements of the printed geomatrix (9): row/column 1 {0, 1/3, 1} (equation (2)),
/// 2 {0, 1/2, 1} (equation (1)), 3 {0, 2/3, 1} (equation (3)).
fn printed_placements() -> [Nodes; 3] {
    [
        Nodes::paper_third(),
        Nodes::paper_half(),
        Nodes::paper_two_thirds(),
    ]
}

/// The geomatrix (9) of the paper exactly as printed: a_ij(u, v) = U_ij(u) V_ij(v), where
/// U_ij is the j-th b-function of row i's placement along u and V_ij the i-th b-function of
/// column j's placement along v (placements 1, 2, 3 = equations (2), (1), (3)).
///
/// A documented variant only: Σ a_ij ≠ 1 in general (1.156 at u = v = 1/2), so the printed
/// surface depends on the coordinate system and misses points; use [`PointSurface`].
///
/// ```
/// use geomkit::pointcalc::printed_geomatrix;
/// let a = printed_geomatrix(0.5, 0.5);
/// assert!((a[0][0] - 1.0 / 16.0).abs() < 1e-15); // exactly 1/16 in printed_geomatrix_exact
/// let sum: f64 = a.iter().flatten().sum();
/// assert!((sum - 1.15625).abs() < 1e-15);
/// ```
pub fn printed_geomatrix(u: f64, v: f64) -> [[f64; 3]; 3] {
    let p = printed_placements();
    let bu: Vec<Vec<f64>> = p.iter().map(|n| n.basis(u)).collect();
    let bv: Vec<Vec<f64>> = p.iter().map(|n| n.basis(v)).collect();
    let mut a = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            a[i][j] = bu[i][j] * bv[j][i];
        }
    }
    a
}

/// [`printed_geomatrix`] in exact rationals.
pub fn printed_geomatrix_exact(u: &Rational, v: &Rational) -> [[Rational; 3]; 3] {
    let p = printed_placements();
    let bu: Vec<Vec<Rational>> = p.iter().map(|n| n.basis_exact(u)).collect();
    let bv: Vec<Vec<Rational>> = p.iter().map(|n| n.basis_exact(v)).collect();
    std::array::from_fn(|i| std::array::from_fn(|j| &bu[i][j] * &bv[j][i]))
}

/// The surface of the printed geomatrix (9) over a 3×3 net: M = Σ a_ij A_ij (variant for
/// comparison; not affine invariant, see [`printed_geomatrix`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PrintedSurface {
    dim: usize,
    net: Vec<f64>,
}

impl PrintedSurface {
    /// Over a 3×3 net (net\[i\]\[j\]). Errors: not 3×3, mixed dimensions, non-finite.
    pub fn new(net: Vec<Vec<Vec<f64>>>) -> Result<Self> {
        let (rows, cols, dim, data) = flatten_grid("net", &net)?;
        if rows != 3 || cols != 3 {
            return Err(Error::PointCount {
                what: "points of the printed geomatrix net".into(),
                expected: 9,
                got: rows * cols,
            });
        }
        Ok(PrintedSurface { dim, net: data })
    }

    /// Dimension of the points.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// M(u, v) = Σ a_ij(u, v) A_ij with the printed a_ij, into `out` (length dim); computed
    /// again with the points scaled by a power of two where the plain sum leaves the f64
    /// range (±infinity only where M(u, v) itself is beyond f64).
    pub fn eval_into(&self, u: f64, v: f64, out: &mut [f64]) {
        let a = printed_geomatrix(u, v);
        self.combine(&a, out);
        if out.iter().any(|x| !x.is_finite()) {
            let flat: Vec<f64> = a.iter().flatten().copied().collect();
            combine_wide(&flat, 0, &self.net, out);
        }
    }

    /// Σ a_ij A_ij into `out`.
    fn combine(&self, a: &[[f64; 3]; 3], out: &mut [f64]) {
        out.fill(0.0);
        for (k, p) in self.net.chunks_exact(self.dim).enumerate() {
            let w = a[k / 3][k % 3];
            for (o, x) in out.iter_mut().zip(p) {
                *o += w * x;
            }
        }
    }

    /// M(u, v) = Σ a_ij(u, v) A_ij with the printed a_ij.
    pub fn eval(&self, u: f64, v: f64) -> Vec<f64> {
        let mut out = vec![0.0; self.dim];
        self.eval_into(u, v, &mut out);
        out
    }

    /// Points on the grid `us` × `vs` (row-major, u slowest). Errors: wrong buffer length,
    /// non-finite parameters; [`Error::ResultOverflow`] naming the first point beyond f64.
    pub fn eval_grid(&self, us: &[f64], vs: &[f64], out: &mut [f64]) -> Result<()> {
        let d = self.dim;
        check_grid_args(us, vs, d, out)?;
        for (a, &u) in us.iter().enumerate() {
            for (b, &v) in vs.iter().enumerate() {
                let o = &mut out[(a * vs.len() + b) * d..][..d];
                self.eval_into(u, v, o);
                if o.iter().any(|x| !x.is_finite()) {
                    return Err(Error::ResultOverflow {
                        what: format!("the point of the surface at u={}, v={}", short(u), short(v)),
                    });
                }
            }
        }
        Ok(())
    }
}

/// "Rows first, then across" of spec/point-calculus.md §3.
impl Surface for PointSurface {
    crate::geom::forward_to_inherent!(PointSurface; dim, surface_domain, surface_eval_into, eval_grid);

    /// Σ_i L_i^(kv)(v) M_i^(ku)(u), every order (the cardinal functions' derivatives of
    /// [`Curve::derivative_into`] of point equations, in each direction).
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim, out)?;
        let lv = self.across.basis_derivative(v, kv);
        let mut row = vec![0.0; self.dim];
        out.fill(0.0);
        for (w, eq) in lv.iter().zip(&self.rows) {
            if *w == 0.0 {
                continue;
            }
            eq.derivative_into(u, ku, &mut row)?;
            for (o, x) in out.iter_mut().zip(&row) {
                *o += w * x;
            }
        }
        Ok(())
    }
}

/// The printed geomatrix (9) of spec/point-calculus.md over its 3×3 net, on [0, 1]².
impl Surface for PrintedSurface {
    crate::geom::forward_to_inherent!(PrintedSurface; dim, surface_eval_into, eval_grid);

    /// [0, 1]².
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        ((0.0, 1.0), (0.0, 1.0))
    }

    /// Σ U_ij^(ku)(u) V_ij^(kv)(v) A_ij: every order (the b-functions are quadratics).
    fn derivative_into(
        &self,
        u: f64,
        v: f64,
        (ku, kv): (usize, usize),
        out: &mut [f64],
    ) -> Result<()> {
        check_point(&[u, v], self.dim, out)?;
        let p = printed_placements();
        let bu: Vec<Vec<f64>> = p.iter().map(|n| n.basis_derivative(u, ku)).collect();
        let bv: Vec<Vec<f64>> = p.iter().map(|n| n.basis_derivative(v, kv)).collect();
        let a: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| bu[i][j] * bv[j][i]));
        self.combine(&a, out);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pointcalc::nodes::ratio;

    #[test]
    fn printed_geomatrix_matches_formula_9() {
        // a_12 = 4.5uū·v̄(1-2v), a_31 = 0.5ū(2-3u)·0.5v(3v-1) at (0.2, 0.7).
        let (u, v) = (0.2f64, 0.7f64);
        let a = printed_geomatrix(u, v);
        let (ub, vb) = (1.0 - u, 1.0 - v);
        assert!((a[0][1] - 4.5 * u * ub * vb * (1.0 - 2.0 * v)).abs() < 1e-15);
        assert!((a[2][0] - 0.5 * ub * (2.0 - 3.0 * u) * 0.5 * v * (3.0 * v - 1.0)).abs() < 1e-15);
        let e = printed_geomatrix_exact(&ratio(1, 2), &ratio(1, 2));
        assert_eq!(e[0][0], ratio(1, 16));
        assert_eq!(e[1][1], ratio(1, 1));
    }
}
