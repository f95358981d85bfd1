//! The Bézier part of the Python bindings (issue 23): `BezierCurveCore` (polynomial or rational)
//! and `BezierSurfaceCore` over `geomkit::bezier`, the unified change of degree of
//! spec/bezier-order.md (formulas (1)-(16)), and the paper's exact matrices
//! (`geomkit::exact`).
//!
//! As in the rest of the module: inputs are C-contiguous float64 arrays read in place, results
//! are written into arrays the Python layer allocates, every computation over arrays runs with
//! the GIL released, the objects are immutable (`frozen`), and the library's errors are
//! `ValueError`s with its message. Reports (degree, deviation, reduction error) are returned as
//! plain tuples; python/geomkit/_bezier.py names their fields.

use crate::model::Model;
use crate::{copy_into, matrix, value_error};
use geomkit::bezier::{
    ApproxOptions, BezierCurve, BezierSurface, DegreeReport, DeviationBound, Direction,
    RationalBezierCurve, RationalBezierSurface, ReductionNorm, MAX_PAPER_DEGREE,
};
use geomkit::exact::{self, ExactBezierCurve, ExactMatrix, Rational};
use geomkit::geom::{BatchOptions, Curve, Surface};
use geomkit_model::schema::ReductionError;
use geomkit_model::{AnyModel, BezierModel, ModelFile};
use numpy::{
    PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3, PyReadwriteArray1, PyReadwriteArray2,
    PyReadwriteArray3, PyReadwriteArrayDyn, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyType;

/// Refuses the paper's exact formula (or its naive program) beyond the library's
/// [`MAX_PAPER_DEGREE`].
fn check_paper_degree(n: usize, n_new: usize, what: &str) -> PyResult<()> {
    geomkit::bezier::degree::check_paper_degree(n, n_new, what).map_err(value_error)
}

/// Most numbers (f64) of a curve or net a change of degree may create: 2^27, 1 GiB. The
/// library bounds the work of an elevation (its weight count), not the size of the result,
/// which also grows with the dimension of the points and, for a surface, with the other
/// direction; without this bound `to=10**7` on a net of 1000 columns would abort the
/// interpreter when the allocation fails.
const MAX_RESULT_NUMBERS: u128 = 1 << 27;

/// Refuses a result of `count` numbers above [`MAX_RESULT_NUMBERS`].
fn check_result_size(count: u128, what: impl FnOnce() -> String) -> PyResult<()> {
    if count > MAX_RESULT_NUMBERS {
        return Err(value_error(geomkit::Error::TooLarge {
            what: what(),
            size: count,
            unit: "number count",
            limit: MAX_RESULT_NUMBERS,
        }));
    }
    Ok(())
}

/// A degree report as (formal degree, real degree, defect, residual, rejected residual,
/// tolerance).
type ReportTuple = (usize, usize, usize, f64, Option<f64>, f64);

fn report_tuple(r: &DegreeReport) -> ReportTuple {
    (
        r.degree,
        r.real_degree,
        r.defect,
        r.residual,
        r.rejected_residual,
        r.tolerance,
    )
}

/// A deviation bound as (largest deviation found, where, guaranteed upper bound).
type DeviationTuple = (f64, f64, f64);

fn deviation_tuple(d: &DeviationBound) -> DeviationTuple {
    (d.max_found, d.at, d.upper_bound)
}

/// An exact rational as its numerator and denominator in hexadecimal (Python's `int(s, 16)`
/// has no digit limit, unlike decimal conversion).
fn hex_pair(q: &Rational) -> (String, String) {
    (q.numer().to_str_radix(16), q.denom().to_str_radix(16))
}

/// An exact matrix as (rows, columns, entries row-major as hexadecimal pairs).
type HexMatrix = (usize, usize, Vec<(String, String)>);

/// `m` as a [`HexMatrix`].
fn hex_matrix(m: &ExactMatrix) -> HexMatrix {
    let mut entries = Vec::with_capacity(m.rows() * m.cols());
    for i in 0..m.rows() {
        for j in 0..m.cols() {
            entries.push(hex_pair(m.get(i, j)));
        }
    }
    (m.rows(), m.cols(), entries)
}

/// Parameters u and v of pairs (u[k], v[k]): of the same length.
fn same_length(u: &[f64], v: &[f64]) -> PyResult<()> {
    if u.len() != v.len() {
        return Err(PyValueError::new_err(format!(
            "u and v must have the same length, got {} and {}",
            u.len(),
            v.len()
        )));
    }
    Ok(())
}

/// A parametric direction named "u" or "v".
fn direction(name: &str) -> PyResult<Direction> {
    match name {
        "u" => Ok(Direction::U),
        "v" => Ok(Direction::V),
        _ => Err(PyValueError::new_err(format!(
            "direction {name:?}: expected \"u\" or \"v\""
        ))),
    }
}

/// A Bézier curve: polynomial, or rational (with weights).
#[derive(Clone)]
enum CurveKind {
    Polynomial(BezierCurve),
    Rational(RationalBezierCurve),
}

/// A Bézier curve in any dimension (formula (1) of spec/bezier-order.md), polynomial or
/// rational, with the error report of the approximate reduction that made it, if any (kept
/// for its model file). Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct BezierCurveCore {
    inner: CurveKind,
    error: Option<ReductionError>,
}

impl BezierCurveCore {
    fn polynomial(curve: BezierCurve) -> Self {
        BezierCurveCore {
            inner: CurveKind::Polynomial(curve),
            error: None,
        }
    }

    fn rational(curve: RationalBezierCurve) -> Self {
        BezierCurveCore {
            inner: CurveKind::Rational(curve),
            error: None,
        }
    }

    /// The polynomial curve, or a `ValueError` saying that `operation` needs one.
    fn require_polynomial(&self, operation: &str) -> PyResult<&BezierCurve> {
        match &self.inner {
            CurveKind::Polynomial(c) => Ok(c),
            CurveKind::Rational(_) => Err(PyValueError::new_err(format!(
                "{operation} is available for polynomial Bézier curves only (this curve has \
                 weights)"
            ))),
        }
    }

    /// Refuses a change to degree `to` whose control points would be too many numbers.
    fn check_target(&self, to: usize) -> PyResult<()> {
        let per_point = self.as_curve().dim() + usize::from(self.is_rational());
        check_result_size((to as u128 + 1) * per_point as u128, || {
            format!("a curve of degree {to} in R^{}", self.as_curve().dim())
        })
    }

    /// The change to degree `to` (elevation when `to` >= n, exact reduction otherwise) with
    /// the GIL released, reporting to `progress` when given (`crate::progress::run`: Ctrl-C
    /// interrupts it). The outer error is Python's, the inner one the library's.
    fn changed(
        &self,
        py: Python<'_>,
        to: usize,
        tolerance: Option<f64>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<geomkit::Result<Self>> {
        crate::progress::run(py, progress, |p| match &self.inner {
            CurveKind::Polynomial(c) => c
                .change_degree_with_progress(to, tolerance, p)
                .map(Self::polynomial),
            CurveKind::Rational(r) => r
                .change_degree_with_progress(to, tolerance, p)
                .map(Self::rational),
        })
    }

    /// The library's error of an exact reduction, its advice made the package's: the best
    /// approximation is `reduce_approx`, for polynomial curves only.
    fn exact_reduction_error(&self, e: geomkit::Error) -> PyErr {
        match e {
            geomkit::Error::DegreeDefectTooSmall {
                real_degree,
                requested,
                defect,
            } => {
                let hint = if self.is_rational() {
                    "a rational curve reduces exactly only (reduce_approx takes polynomial \
                     curves)"
                } else {
                    "use reduce_approx for the best approximation of that degree"
                };
                PyValueError::new_err(format!(
                    "cannot reduce exactly to degree {requested}: the real degree is \
                     {real_degree} (degree defect {defect}); {hint}"
                ))
            }
            other => value_error(other),
        }
    }

    fn as_curve(&self) -> &dyn Curve {
        match &self.inner {
            CurveKind::Polynomial(c) => c,
            CurveKind::Rational(r) => r,
        }
    }

    fn model(&self) -> BezierModel {
        match &self.inner {
            CurveKind::Polynomial(c) => BezierModel::Curve(c.clone()),
            CurveKind::Rational(r) => BezierModel::Rational(r.clone()),
        }
    }
}

#[pymethods]
impl BezierCurveCore {
    /// Checks and copies the control points (shape (n+1, dim)) and, for a rational curve, the
    /// weights (length n+1, each finite and > 0).
    #[new]
    #[pyo3(signature = (points, weights=None))]
    fn new(
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        weights: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let (_, dim, flat) = matrix(&points)?;
        match weights {
            None => {
                let c = py
                    .detach(|| BezierCurve::from_flat(dim, flat.to_vec()))
                    .map_err(value_error)?;
                Ok(Self::polynomial(c))
            }
            Some(w) => {
                let w = w.as_slice()?;
                let r = py
                    .detach(|| {
                        let rows = flat.chunks_exact(dim.max(1)).map(<[f64]>::to_vec).collect();
                        RationalBezierCurve::new(rows, w.to_vec())
                    })
                    .map_err(value_error)?;
                Ok(Self::rational(r))
            }
        }
    }

    /// The formal degree n.
    #[getter]
    fn degree(&self) -> usize {
        match &self.inner {
            CurveKind::Polynomial(c) => c.degree(),
            CurveKind::Rational(r) => r.degree(),
        }
    }

    /// The dimension of the (Cartesian) control points.
    #[getter]
    fn dim(&self) -> usize {
        self.as_curve().dim()
    }

    /// Whether the curve has weights.
    #[getter]
    fn is_rational(&self) -> bool {
        matches!(self.inner, CurveKind::Rational(_))
    }

    /// The error report (L2 error, L∞ bound) of the approximate reduction that made this
    /// curve, if it was made so (or loaded from a file that has one).
    #[getter]
    fn reduction_error(&self) -> Option<(f64, f64)> {
        self.error.map(|e| (e.l2, e.linf_bound))
    }

    /// Copies the control points into `out` (shape (n+1, dim)).
    fn points_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        match &self.inner {
            CurveKind::Polynomial(c) => py.detach(|| copy_into(c.points_flat(), out)),
            CurveKind::Rational(r) => {
                let flat: Vec<f64> = r.points().concat();
                copy_into(&flat, out)
            }
        }
    }

    /// Copies the weights into `out` (length n+1); all ones for a polynomial curve.
    fn weights_into(&self, mut out: PyReadwriteArray1<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        match &self.inner {
            CurveKind::Polynomial(c) => copy_into(&vec![1.0; c.degree() + 1], out),
            CurveKind::Rational(r) => copy_into(&r.weights(), out),
        }
    }

    /// The points (`nu` = 0) or derivatives of order `nu` at the parameters `t` into `out`
    /// (shape (len(t), dim)). Polynomial curves: the hodograph of order `nu` by the batched
    /// Bernstein–Horner kernel; rational curves: the quotient rule point by point.
    fn eval_into(
        &self,
        py: Python<'_>,
        t: PyReadonlyArray1<'_, f64>,
        nu: usize,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let t = t.as_slice()?;
        let out = out.as_slice_mut()?;
        py.detach(|| match &self.inner {
            CurveKind::Polynomial(c) => {
                if nu == 0 {
                    c.eval_batch(t, out, &BatchOptions::default())
                } else {
                    let mut h = c.derivative();
                    for _ in 1..nu.min(c.degree() + 1) {
                        h = h.derivative();
                    }
                    h.eval_batch(t, out, &BatchOptions::default())
                }
            }
            CurveKind::Rational(r) => {
                if nu == 0 {
                    return r.eval_batch(t, out, &BatchOptions::default());
                }
                let d = r.dim();
                if out.len() != t.len() * d {
                    return Err(geomkit::Error::BufferSize {
                        expected: t.len() * d,
                        got: out.len(),
                    });
                }
                for (&x, o) in t.iter().zip(out.chunks_exact_mut(d.max(1))) {
                    r.derivative_into(x, nu, o)?;
                }
                Ok(())
            }
        })
        .map_err(value_error)
    }

    /// The hodograph (derivative curve, degree n-1) of a polynomial curve.
    fn derivative(&self) -> PyResult<Self> {
        Ok(Self::polynomial(
            self.require_polynomial("the derivative curve")?
                .derivative(),
        ))
    }

    /// The two halves [0, t] and [t, 1] (de Casteljau); a rational curve is split through its
    /// homogeneous points. `t` must be finite.
    fn split(&self, py: Python<'_>, t: f64) -> PyResult<(Self, Self)> {
        if !t.is_finite() {
            return Err(PyValueError::new_err(format!(
                "the split parameter t = {t} is not a finite number"
            )));
        }
        py.detach(|| match &self.inner {
            CurveKind::Polynomial(c) => {
                let (a, b) = c.split(t)?;
                Ok((Self::polynomial(a), Self::polynomial(b)))
            }
            CurveKind::Rational(r) => {
                let (a, b) = r.homogeneous().split(t)?;
                Ok((
                    Self::rational(RationalBezierCurve::from_homogeneous(a)?),
                    Self::rational(RationalBezierCurve::from_homogeneous(b)?),
                ))
            }
        })
        .map_err(value_error)
    }

    /// The power-form coefficients S_n = U_n H_n (formula (5)) into `out` (shape (n+1, dim)).
    fn power_into(&self, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let c = self.require_polynomial("the power form")?;
        copy_into(&c.to_power(), out.as_slice_mut()?)
    }

    /// The polynomial curve of the power-form coefficients `s` (shape (n+1, dim), row j the
    /// coefficient of t^j): U_n = S_n H_n^-1, (H_n^-1)_ij = C(j,i) / C(n,i) (formula (5)).
    #[classmethod]
    fn from_power(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        s: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        let (_, dim, flat) = matrix(&s)?;
        py.detach(|| BezierCurve::from_power(dim, flat))
            .map(Self::polynomial)
            .map_err(value_error)
    }

    /// Elevation to degree `to` >= n in one step (closed form (8)); the curve is unchanged.
    /// `progress`: a callable `progress(done, total)` told how many new control points are
    /// computed (`crate::progress`; Ctrl-C then interrupts it).
    #[pyo3(signature = (to, progress=None))]
    fn elevate(
        &self,
        py: Python<'_>,
        to: usize,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        self.check_target(to)?;
        if to < self.degree() {
            // The library's refusal (an elevation below the degree).
            return match &self.inner {
                CurveKind::Polynomial(c) => c.elevate_degree(to).map(Self::polynomial),
                CurveKind::Rational(r) => r.elevate_degree(to).map(Self::rational),
            }
            .map_err(value_error);
        }
        self.changed(py, to, None, progress.as_ref())?
            .map_err(value_error)
    }

    /// Exact reduction to degree `to` <= n (formula (9) done stably); errors name the real
    /// degree when the defect does not allow it. `progress` as for `elevate`.
    #[pyo3(signature = (to, tolerance=None, progress=None))]
    fn reduce(
        &self,
        py: Python<'_>,
        to: usize,
        tolerance: Option<f64>,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        if to > self.degree() {
            // The library's refusal (a reduction above the degree).
            return match &self.inner {
                CurveKind::Polynomial(c) => c.reduce_degree(to, tolerance).map(Self::polynomial),
                CurveKind::Rational(r) => r.reduce_degree(to, tolerance).map(Self::rational),
            }
            .map_err(|e| self.exact_reduction_error(e));
        }
        self.changed(py, to, tolerance, progress.as_ref())?
            .map_err(|e| self.exact_reduction_error(e))
    }

    /// The unified change of degree (formula (10) done stably): elevation when `to` >= n,
    /// exact reduction otherwise. `progress` as for `elevate`.
    #[pyo3(signature = (to, tolerance=None, progress=None))]
    fn change_degree(
        &self,
        py: Python<'_>,
        to: usize,
        tolerance: Option<f64>,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        self.check_target(to)?;
        self.changed(py, to, tolerance, progress.as_ref())?
            .map_err(|e| self.exact_reduction_error(e))
    }

    /// Formal degree, real degree, defect and residuals by the residual test (of the
    /// homogeneous curve for a rational one).
    #[pyo3(signature = (tolerance=None))]
    fn degree_report(&self, py: Python<'_>, tolerance: Option<f64>) -> PyResult<ReportTuple> {
        py.detach(|| match &self.inner {
            CurveKind::Polynomial(c) => c.degree_report(tolerance),
            CurveKind::Rational(r) => r.degree_report(tolerance),
        })
        .map(|r| report_tuple(&r))
        .map_err(value_error)
    }

    /// The relative residual of the reduction to degree `k` (0 for k >= n).
    fn reduction_residual(&self, py: Python<'_>, k: usize) -> PyResult<f64> {
        let c = match &self.inner {
            CurveKind::Polynomial(c) => c,
            CurveKind::Rational(r) => r.homogeneous(),
        };
        py.detach(|| c.reduction_residual(k)).map_err(value_error)
    }

    /// The best approximation of degree `to` < n in L2 ("l2") or the Chebyshev-weighted norm
    /// ("chebyshev"), with C^start / C^end continuity at the ends: (curve, L2 error,
    /// (largest deviation found, where, guaranteed L∞ bound)). The curve keeps the report.
    #[pyo3(signature = (to, start=None, end=None, norm="l2"))]
    fn reduce_approx(
        &self,
        py: Python<'_>,
        to: usize,
        start: Option<usize>,
        end: Option<usize>,
        norm: &str,
    ) -> PyResult<(Self, f64, DeviationTuple)> {
        let norm = match norm {
            "l2" => ReductionNorm::L2,
            "chebyshev" => ReductionNorm::Chebyshev,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "norm {norm:?}: expected \"l2\" or \"chebyshev\""
                )))
            }
        };
        let c = self.require_polynomial("approximate reduction")?;
        let options = ApproxOptions::default()
            .with_continuity(start, end)
            .with_norm(norm);
        let r = py
            .detach(|| c.reduce_degree_approx(to, &options))
            .map_err(value_error)?;
        let core = BezierCurveCore {
            inner: CurveKind::Polynomial(r.curve),
            error: Some(ReductionError {
                l2: r.l2_error,
                linf_bound: r.linf.upper_bound,
            }),
        };
        Ok((core, r.l2_error, deviation_tuple(&r.linf)))
    }

    /// The paper's formula (10) as written, with the exact matrix H_n E H_(n')^-1 rounded once
    /// to f64 (for `to` below the real degree: the truncation of the power form at t = 0).
    fn change_degree_paper(&self, py: Python<'_>, to: usize) -> PyResult<Self> {
        let c = self.require_polynomial("the paper's formula (10)")?;
        check_paper_degree(c.degree(), to, "the paper's formula (10)")?;
        self.check_target(to)?;
        py.detach(|| c.change_degree_paper(to))
            .map(Self::polynomial)
            .map_err(value_error)
    }

    /// The paper's formula (10) evaluated naively in f64 (S = U H, truncate or pad, times
    /// H'^-1), into `out` (shape (to+1, dim)); may hold non-finite numbers (kept for
    /// comparison: it loses every digit near degree 20-30).
    fn paper_formula_f64_into(
        &self,
        py: Python<'_>,
        to: usize,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let c = self.require_polynomial("the paper's formula (10)")?;
        check_paper_degree(c.degree(), to, "the paper's formula (10)")?;
        let out = out.as_slice_mut()?;
        py.detach(|| copy_into(&geomkit::bezier::paper_formula_f64(c, to), out))
    }

    /// The exact real degree: the formal degree minus the number of zero power coefficients
    /// at the right end of S_n = U_n H_n (exact rationals, no tolerance).
    fn real_degree_exact(&self, py: Python<'_>) -> PyResult<usize> {
        let c = self.require_polynomial("the exact real degree")?;
        check_paper_degree(c.degree(), c.degree(), "the exact real degree")?;
        Ok(py.detach(|| c.to_exact().real_degree()))
    }

    /// Formula (10) in exact rationals on the exact values of the control points: the new
    /// points row-major as hexadecimal (numerator, denominator) pairs. Errors when `to` is
    /// below the exact real degree.
    fn change_degree_exact(&self, py: Python<'_>, to: usize) -> PyResult<Vec<(String, String)>> {
        let c = self.require_polynomial("the exact change of degree")?;
        check_paper_degree(c.degree(), to, "the exact change of degree")?;
        py.detach(|| {
            let e: ExactBezierCurve = c.to_exact().change_degree(to)?;
            Ok(e.points().iter().map(hex_pair).collect())
        })
        .map_err(value_error)
    }

    /// The distance bound between this curve and `other` over [0, 1] (polynomial curves).
    fn deviation_from(&self, py: Python<'_>, other: &BezierCurveCore) -> PyResult<DeviationTuple> {
        let a = self.require_polynomial("the deviation bound")?;
        let b = other.require_polynomial("the deviation bound")?;
        py.detach(|| a.deviation_from(b))
            .map(|d| deviation_tuple(&d))
            .map_err(value_error)
    }

    /// Removes control point `index`: (curve, index, deviation).
    fn remove_vertex(
        &self,
        py: Python<'_>,
        index: usize,
    ) -> PyResult<(Self, usize, DeviationTuple)> {
        let c = self.require_polynomial("removing a vertex")?;
        let e = py.detach(|| c.remove_vertex(index)).map_err(value_error)?;
        Ok((
            Self::polynomial(e.curve),
            e.index,
            deviation_tuple(&e.deviation),
        ))
    }

    /// Inserts `point` before control point `index`: (curve, index, deviation).
    fn insert_vertex(
        &self,
        py: Python<'_>,
        index: usize,
        point: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<(Self, usize, DeviationTuple)> {
        let c = self.require_polynomial("inserting a vertex")?;
        let point = point.as_slice()?;
        let e = py
            .detach(|| c.insert_vertex(index, point))
            .map_err(value_error)?;
        Ok((
            Self::polynomial(e.curve),
            e.index,
            deviation_tuple(&e.deviation),
        ))
    }

    /// Removes the middle vertex m = round(n/2): (curve, index, deviation).
    fn remove_middle_vertex(&self, py: Python<'_>) -> PyResult<(Self, usize, DeviationTuple)> {
        let c = self.require_polynomial("removing the middle vertex")?;
        let e = py
            .detach(|| c.remove_middle_vertex())
            .map_err(value_error)?;
        Ok((
            Self::polynomial(e.curve),
            e.index,
            deviation_tuple(&e.deviation),
        ))
    }

    /// The model file of the curve (`BezierModel::to_file`), with its reduction error.
    fn to_model(&self) -> PyResult<Model> {
        Model::from_file(self.model().to_file(self.error))
    }

    /// The curve of a model of kind "bezier_curve" (with the file's reduction error).
    #[classmethod]
    fn from_model(_cls: &Bound<'_, PyType>, model: &Model) -> PyResult<Self> {
        let error = match &model.file {
            ModelFile::BezierCurve(f) => f.error,
            _ => None,
        };
        let inner = match &model.model {
            AnyModel::Bezier(BezierModel::Curve(c)) => CurveKind::Polynomial(c.clone()),
            AnyModel::Bezier(BezierModel::Rational(r)) => CurveKind::Rational(r.clone()),
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "a model of kind {:?} is not a Bézier curve",
                    model.file.type_name()
                )))
            }
        };
        Ok(BezierCurveCore { inner, error })
    }
}

enum SurfaceKind {
    Polynomial(BezierSurface),
    Rational(RationalBezierSurface),
}

/// A tensor-product Bézier surface (formula (11)) over an (n+1)×(m+1) net of points in any
/// dimension, polynomial or rational (weights on the net). Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct BezierSurfaceCore {
    inner: SurfaceKind,
}

fn surface(inner: BezierSurface) -> BezierSurfaceCore {
    BezierSurfaceCore {
        inner: SurfaceKind::Polynomial(inner),
    }
}

fn rational_surface(inner: RationalBezierSurface) -> BezierSurfaceCore {
    BezierSurfaceCore {
        inner: SurfaceKind::Rational(inner),
    }
}

impl BezierSurfaceCore {
    fn as_surface(&self) -> &(dyn Surface + Sync) {
        match &self.inner {
            SurfaceKind::Polynomial(s) => s,
            SurfaceKind::Rational(s) => s,
        }
    }

    fn degrees_of(&self) -> (usize, usize) {
        match &self.inner {
            SurfaceKind::Polynomial(s) => s.degrees(),
            SurfaceKind::Rational(s) => s.degrees(),
        }
    }

    /// The polynomial surface, or a `ValueError` saying that `operation` needs one.
    fn require_polynomial(&self, operation: &str) -> PyResult<&BezierSurface> {
        match &self.inner {
            SurfaceKind::Polynomial(s) => Ok(s),
            SurfaceKind::Rational(_) => Err(PyValueError::new_err(format!(
                "{operation} is available for polynomial Bézier surfaces only (this surface \
                 has weights)"
            ))),
        }
    }

    /// Refuses degrees (n, m) whose net would be too many numbers.
    fn check_target(&self, n: usize, m: usize) -> PyResult<()> {
        let dim = self.as_surface().dim();
        let per_point = dim + usize::from(matches!(self.inner, SurfaceKind::Rational(_)));
        check_result_size(
            (n as u128 + 1) * (m as u128 + 1) * per_point as u128,
            || format!("a surface of degrees ({n}, {m}) in R^{dim}"),
        )
    }

    fn model(&self) -> BezierModel {
        match &self.inner {
            SurfaceKind::Polynomial(s) => BezierModel::Surface(s.clone()),
            SurfaceKind::Rational(s) => BezierModel::RationalSurface(s.clone()),
        }
    }

    /// The same surface as a rational one (weights 1 for a polynomial surface).
    fn to_rational(&self) -> geomkit::Result<RationalBezierSurface> {
        match &self.inner {
            SurfaceKind::Polynomial(s) => {
                let (n, m) = s.degrees();
                let w = vec![1.0; (n + 1) * (m + 1)];
                RationalBezierSurface::from_flat(n + 1, m + 1, s.dim(), s.net_flat().to_vec(), w)
            }
            SurfaceKind::Rational(s) => Ok(s.clone()),
        }
    }
}

#[pymethods]
impl BezierSurfaceCore {
    /// Checks and copies the net (shape (n+1, m+1, dim)) and, for a rational surface, the
    /// weights (shape (n+1, m+1), each finite and > 0).
    #[new]
    #[pyo3(signature = (net, weights=None))]
    fn new(
        py: Python<'_>,
        net: PyReadonlyArray3<'_, f64>,
        weights: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Self> {
        let shape = net.shape();
        let (rows, cols, dim) = (shape[0], shape[1], shape[2]);
        let flat = net.as_slice()?;
        match weights {
            None => py
                .detach(|| BezierSurface::from_flat(rows, cols, dim, flat.to_vec()))
                .map(surface)
                .map_err(value_error),
            Some(w) => {
                if w.shape() != [rows, cols] {
                    return Err(PyValueError::new_err(format!(
                        "weights of shape {:?} for a net of {rows}×{cols} points (give one \
                         weight per point: shape ({rows}, {cols}))",
                        w.shape()
                    )));
                }
                let w = w.as_slice()?;
                py.detach(|| {
                    RationalBezierSurface::from_flat(rows, cols, dim, flat.to_vec(), w.to_vec())
                })
                .map(rational_surface)
                .map_err(value_error)
            }
        }
    }

    /// The formal degrees (n, m).
    #[getter]
    fn degrees(&self) -> (usize, usize) {
        self.degrees_of()
    }

    /// The dimension of the net points.
    #[getter]
    fn dim(&self) -> usize {
        self.as_surface().dim()
    }

    /// Whether the surface has weights.
    #[getter]
    fn is_rational(&self) -> bool {
        matches!(self.inner, SurfaceKind::Rational(_))
    }

    /// Copies the (Cartesian) net into `out` (shape (n+1, m+1, dim)).
    fn net_into(&self, py: Python<'_>, mut out: PyReadwriteArray3<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        let net = match &self.inner {
            SurfaceKind::Polynomial(s) => s.net_flat(),
            SurfaceKind::Rational(s) => s.net_flat(),
        };
        py.detach(|| copy_into(net, out))
    }

    /// Copies the weights of a rational surface into `out` (shape (n+1, m+1)).
    fn weights_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        match &self.inner {
            SurfaceKind::Rational(s) => py.detach(|| copy_into(s.weights_flat(), out)),
            SurfaceKind::Polynomial(_) => {
                Err(PyValueError::new_err("a polynomial surface has no weights"))
            }
        }
    }

    /// p(u[a], v[b]) into `out[a, b]` (shape (len(u), len(v), dim)).
    fn eval_grid_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray3<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        py.detach(|| self.as_surface().eval_grid(u, v, out))
            .map_err(value_error)
    }

    /// p(u[k], v[k]) into `out[k]` (shape (len(u), dim); `u` and `v` of the same length).
    fn eval_points_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        same_length(u, v)?;
        let out = out.as_slice_mut()?;
        py.detach(|| {
            let uv: Vec<f64> = u.iter().zip(v).flat_map(|(&a, &b)| [a, b]).collect();
            self.as_surface()
                .eval_batch(&uv, out, &BatchOptions::default())
        })
        .map_err(value_error)
    }

    /// The partial derivative ∂^(du+dv) p / ∂u^du ∂v^dv into `out`: on the grid u × v
    /// (`grid`, shape (len(u), len(v), dim)) or at the pairs (u[k], v[k]) (shape (len(u),
    /// dim)). For rational surfaces by the quotient rule; for polynomial ones the hodographs
    /// of formula (11).
    #[allow(clippy::too_many_arguments)]
    fn partials_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        grid: bool,
        du: usize,
        dv: usize,
        mut out: PyReadwriteArrayDyn<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        let s = self.as_surface();
        let pairs = parameter_pairs(u, v, grid, s.dim(), out.len())?;
        py.detach(|| {
            for (&(a, b), o) in pairs.iter().zip(out.chunks_exact_mut(s.dim())) {
                s.derivative_into(a, b, (du, dv), o)?;
            }
            Ok(())
        })
        .map_err(value_error)
    }

    /// Unit normals (∂p/∂u × ∂p/∂v normalized) of a surface in R^3 into `out`: on the grid
    /// u × v (`grid`, shape (len(u), len(v), 3)) or at the pairs (u[k], v[k]) (shape
    /// (len(u), 3)); NaN where the partial derivatives are parallel or vanish.
    fn normals_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        grid: bool,
        mut out: PyReadwriteArrayDyn<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        let pairs = parameter_pairs(u, v, grid, 3, out.len())?;
        py.detach(|| {
            for (&(a, b), o) in pairs.iter().zip(out.chunks_exact_mut(3)) {
                let n = match &self.inner {
                    SurfaceKind::Polynomial(s) => s.normal(a, b),
                    SurfaceKind::Rational(s) => s.normal(a, b),
                }?;
                o.copy_from_slice(&n.unwrap_or([f64::NAN; 3]));
            }
            Ok(())
        })
        .map_err(value_error)
    }

    /// The partial-derivative surface ∂p/∂u ("u", degree n-1 in u) or ∂p/∂v ("v") of a
    /// polynomial surface.
    fn derivative(&self, direction_name: &str) -> PyResult<Self> {
        let s = self.require_polynomial("the derivative surface")?;
        Ok(surface(s.derivative(direction(direction_name)?)))
    }

    /// Real degrees and defects in u and v (16): two degree-report tuples (of the homogeneous
    /// surface for a rational one).
    #[pyo3(signature = (tolerance=None))]
    fn degree_report(
        &self,
        py: Python<'_>,
        tolerance: Option<f64>,
    ) -> PyResult<(ReportTuple, ReportTuple)> {
        py.detach(|| match &self.inner {
            SurfaceKind::Polynomial(s) => s.degree_report(tolerance),
            SurfaceKind::Rational(s) => s.degree_report(tolerance),
        })
        .map(|r| (report_tuple(&r.u), report_tuple(&r.v)))
        .map_err(value_error)
    }

    /// Formula (14) done stably: the same surface with degrees (n', m'), each direction
    /// elevated or exactly reduced (through homogeneous coordinates for a rational surface).
    /// `progress`: a callable `progress(done, total)` told how many new rows and columns of
    /// the net are computed (`crate::progress`; Ctrl-C then interrupts it).
    #[pyo3(signature = (n, m, tolerance=None, progress=None))]
    fn change_degree(
        &self,
        py: Python<'_>,
        n: usize,
        m: usize,
        tolerance: Option<f64>,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        self.check_target(n, m)?;
        crate::progress::run(py, progress.as_ref(), |p| match &self.inner {
            SurfaceKind::Polynomial(s) => s
                .change_degree_with_progress(n, m, tolerance, p)
                .map(surface),
            SurfaceKind::Rational(s) => s
                .change_degree_with_progress(n, m, tolerance, p)
                .map(rational_surface),
        })?
        .map_err(value_error)
    }

    /// Formula (14) exactly as the paper writes it (exact matrices rounded once; on the
    /// homogeneous net for a rational surface).
    fn change_degree_paper(&self, py: Python<'_>, n: usize, m: usize) -> PyResult<Self> {
        let (a, b) = self.degrees_of();
        check_paper_degree(a, n, "the paper's formula (14) in u")?;
        check_paper_degree(b, m, "the paper's formula (14) in v")?;
        self.check_target(n, m)?;
        py.detach(|| match &self.inner {
            SurfaceKind::Polynomial(s) => s.change_degree_paper(n, m).map(surface),
            SurfaceKind::Rational(s) => s
                .homogeneous()
                .change_degree_paper(n, m)
                .and_then(RationalBezierSurface::from_homogeneous)
                .map(rational_surface),
        })
        .map_err(value_error)
    }

    /// Inserts a row ("u", m+1 points) or column ("v", n+1 points) before `index` (13), with
    /// their weights (a polynomial surface given weights becomes rational, its own weights 1;
    /// a rational one given none takes weights 1).
    #[pyo3(signature = (direction_name, index, line, weights=None))]
    fn insert_line(
        &self,
        py: Python<'_>,
        direction_name: &str,
        index: usize,
        line: PyReadonlyArray2<'_, f64>,
        weights: Option<PyReadonlyArray1<'_, f64>>,
    ) -> PyResult<Self> {
        let d = direction(direction_name)?;
        let (count, dim, flat) = matrix(&line)?;
        let weights = weights
            .map(|w| w.as_slice().map(<[f64]>::to_vec))
            .transpose()?;
        py.detach(|| {
            let rows: Vec<Vec<f64>> = flat.chunks_exact(dim.max(1)).map(<[f64]>::to_vec).collect();
            match (&self.inner, weights) {
                (SurfaceKind::Polynomial(s), None) => s.insert_line(d, index, &rows).map(surface),
                (_, w) => self
                    .to_rational()?
                    .insert_line(d, index, &rows, &w.unwrap_or_else(|| vec![1.0; count]))
                    .map(rational_surface),
            }
        })
        .map_err(value_error)
    }

    /// Removes row ("u") or column ("v") `index` (13).
    fn remove_line(&self, py: Python<'_>, direction_name: &str, index: usize) -> PyResult<Self> {
        let d = direction(direction_name)?;
        py.detach(|| match &self.inner {
            SurfaceKind::Polynomial(s) => s.remove_line(d, index).map(surface),
            SurfaceKind::Rational(s) => s.remove_line(d, index).map(rational_surface),
        })
        .map_err(value_error)
    }

    /// The distance between two polynomial surfaces over [0,1]²: (largest found on a 65×65
    /// grid, its u, guaranteed upper bound).
    fn deviation_from(
        &self,
        py: Python<'_>,
        other: &BezierSurfaceCore,
    ) -> PyResult<DeviationTuple> {
        let a = self.require_polynomial("deviation_from")?;
        let b = other.require_polynomial("deviation_from")?;
        py.detach(|| a.deviation_from(b))
            .map(|d| deviation_tuple(&d))
            .map_err(value_error)
    }

    /// The model file of the surface (`BezierModel::to_file`).
    fn to_model(&self) -> PyResult<Model> {
        Model::from_file(self.model().to_file(None))
    }

    /// The surface of a model of kind "bezier_surface".
    #[classmethod]
    fn from_model(_cls: &Bound<'_, PyType>, model: &Model) -> PyResult<Self> {
        match &model.model {
            AnyModel::Bezier(BezierModel::Surface(s)) => Ok(surface(s.clone())),
            AnyModel::Bezier(BezierModel::RationalSurface(s)) => Ok(rational_surface(s.clone())),
            _ => Err(PyTypeError::new_err(format!(
                "a model of kind {:?} is not a Bézier surface",
                model.file.type_name()
            ))),
        }
    }
}

/// The parameter pairs of a grid u × v (`grid`) or of the pairs (u[k], v[k]), checked
/// (finite; the same length for pairs) against an output of `out_len` numbers of `dim` each.
fn parameter_pairs(
    u: &[f64],
    v: &[f64],
    grid: bool,
    dim: usize,
    out_len: usize,
) -> PyResult<Vec<(f64, f64)>> {
    let pairs: Vec<(f64, f64)> = if grid {
        u.iter()
            .flat_map(|&a| v.iter().map(move |&b| (a, b)))
            .collect()
    } else {
        same_length(u, v)?;
        u.iter().copied().zip(v.iter().copied()).collect()
    };
    if out_len != pairs.len() * dim {
        return Err(value_error(geomkit::Error::BufferSize {
            expected: pairs.len() * dim,
            got: out_len,
        }));
    }
    if let Some(k) = pairs
        .iter()
        .position(|(a, b)| !(a.is_finite() && b.is_finite()))
    {
        return Err(value_error(geomkit::Error::NonFinite {
            what: "parameter pair",
            index: k,
        }));
    }
    Ok(pairs)
}

/// The paper's unified degree-change matrix H_n E_(n+1,n'+1) H_(n')^-1 (formula (10); for
/// n' >= n the elevation matrix (8)), exact: (rows, columns, entries as hexadecimal pairs).
#[pyfunction]
fn degree_change_matrix(py: Python<'_>, n: usize, n_new: usize) -> PyResult<HexMatrix> {
    check_paper_degree(n, n_new, "the degree-change matrix")?;
    Ok(py.detach(|| hex_matrix(&exact::degree_change_matrix(n, n_new))))
}

/// H_n of formula (4) (B_n(t) = H_n T_n(t)), exact: (rows, columns, hexadecimal pairs).
#[pyfunction]
fn h_matrix(py: Python<'_>, n: usize) -> PyResult<HexMatrix> {
    check_paper_degree(n, n, "the matrix H_n")?;
    Ok(py.detach(|| hex_matrix(&exact::h_matrix(n))))
}

/// Adds this part's classes and functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<BezierCurveCore>()?;
    m.add_class::<BezierSurfaceCore>()?;
    m.add_function(wrap_pyfunction!(degree_change_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(h_matrix, m)?)?;
    m.add("MAX_PAPER_DEGREE", MAX_PAPER_DEGREE)?;
    Ok(())
}
