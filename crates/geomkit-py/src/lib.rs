//! `geomkit._geomkit`: the compiled core of the Python package `geomkit` (python/geomkit), over
//! geomkit's B-splines in SciPy's representation (issue 23, part 1): `make_interp_spline`,
//! `make_interp_surface` and the calculus of `BsplineCurve` and `BsplineSurface`.
//!
//! The Python layer shapes the arguments (SciPy's signatures, `axis`, array shapes, dtypes) and
//! allocates every result array; this module only converts and computes:
//!
//! - inputs are C-contiguous float64 NumPy arrays, read in place (`PyReadonlyArray`, no copy);
//!   anything else is a `TypeError` from the conversion;
//! - results are written into arrays the caller allocated (`PyReadwriteArray`), so that a
//!   size NumPy cannot allocate is its `MemoryError`, never an abort here;
//! - every computation over arrays runs with the GIL released (`Python::detach`); the
//!   objects are immutable (`frozen`), so one spline may be evaluated from many threads;
//! - the library's errors become `ValueError` with its message.

use geomkit::bspline::{
    interpolate_surface_flat_with_progress, interpolate_surface_tiled_with_progress,
    make_interp_spline_tiled, make_interp_spline_with_progress, make_interp_surface_with_progress,
    BsplineCurve, BsplineSurface, EndCondition, EndSpec, Extrapolate, Parametrization, SplineEnds,
    SplineOptions, SurfaceInterpolationOptions, TileOptions, MIN_TILE_SIZE,
};
use geomkit_model::{AnyModel, BsplineCurveModel, BsplineSurfaceModel};
use numpy::{
    PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray1, PyReadwriteArray2, PyReadwriteArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyType;

mod bezier;
mod compose;
mod model;
mod pointcalc;
mod progress;

/// The library's error as a Python `ValueError` with its message.
fn value_error(e: geomkit::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// SciPy's `extrapolate` as the Python layer passes it: "extend" (True), "nan" (False) or
/// "periodic".
fn extrapolate_mode(name: &str) -> PyResult<Extrapolate> {
    match name {
        "extend" => Ok(Extrapolate::Extend),
        "nan" => Ok(Extrapolate::Nan),
        "periodic" => Ok(Extrapolate::Periodic),
        _ => Err(PyValueError::new_err(format!(
            "extrapolate mode {name:?}: expected \"extend\", \"nan\" or \"periodic\""
        ))),
    }
}

/// A 2-D C-contiguous array as (rows, columns, numbers).
fn matrix<'a>(a: &'a PyReadonlyArray2<'_, f64>) -> PyResult<(usize, usize, &'a [f64])> {
    let shape = a.shape();
    Ok((shape[0], shape[1], a.as_slice()?))
}

/// A B-spline curve: knots t, coefficients c (n rows of `dim` numbers, n = len(t) - k - 1),
/// degree k (0 to 15). Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
struct Curve {
    inner: BsplineCurve,
}

#[pymethods]
impl Curve {
    /// Checks and copies knots `t` and coefficients `c` (shape (n, dim), n = len(t) - k - 1).
    #[new]
    fn new(
        py: Python<'_>,
        k: usize,
        t: PyReadonlyArray1<'_, f64>,
        c: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        let t = t.as_slice()?;
        let (_, dim, c) = matrix(&c)?;
        let inner = py
            .detach(|| BsplineCurve::from_flat(k, t.to_vec(), dim, c.to_vec()))
            .map_err(value_error)?;
        Ok(Curve { inner })
    }

    /// Degree k.
    #[getter]
    fn degree(&self) -> usize {
        self.inner.degree()
    }

    /// Numbers per coefficient.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }

    /// The number of knots.
    #[getter]
    fn n_knots(&self) -> usize {
        self.inner.knots().len()
    }

    /// The number of coefficients n.
    #[getter]
    fn n_coefficients(&self) -> usize {
        self.inner.n_control()
    }

    /// Copies the knots into `out` (length `n_knots`).
    fn knots_into(&self, py: Python<'_>, mut out: PyReadwriteArray1<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        py.detach(|| copy_into(self.inner.knots(), out))
    }

    /// Copies the coefficients into `out` (shape (n_coefficients, dim)).
    fn coefficients_into(
        &self,
        py: Python<'_>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        py.detach(|| copy_into(self.inner.control_flat(), out))
    }

    /// Values (`nu` = 0) or derivatives of order `nu` at `x` into `out` (shape (len(x), dim)),
    /// with SciPy's `BSpline.__call__` semantics: `BsplineCurve::eval_nu_many`, SciPy's
    /// recursion (the same bits), except for the values of cubics of dimension 1 to 3 at
    /// finite `x` with `extrapolate` "extend": `BsplineCurve::eval_many_par`, the batched
    /// cubic kernel (3 to 6 times faster; the same polynomial pieces, rounded differently:
    /// within a few ulp of SciPy).
    fn eval_into(
        &self,
        py: Python<'_>,
        x: PyReadonlyArray1<'_, f64>,
        nu: usize,
        extrapolate: &str,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let mode = extrapolate_mode(extrapolate)?;
        let x = x.as_slice()?;
        let out = out.as_slice_mut()?;
        let curve = &self.inner;
        py.detach(|| {
            if nu == 0 && mode == Extrapolate::Extend && cubic_kernel_applies(curve) {
                // Errors only for a parameter that is not finite (checked before any
                // evaluation): SciPy's NaN or extension for those from eval_nu_many.
                if curve.eval_many_par(x, out).is_ok() {
                    return Ok(());
                }
            }
            curve.eval_nu_many(x, nu, mode, out)
        })
        .map_err(value_error)
    }

    /// The derivative curve of order `nu` (SciPy's `BSpline.derivative`).
    fn derivative(&self, py: Python<'_>, nu: usize) -> PyResult<Curve> {
        let inner = py
            .detach(|| self.inner.derivative_nu(nu))
            .map_err(value_error)?;
        Ok(Curve { inner })
    }

    /// The antiderivative curve of order `nu` (SciPy's `BSpline.antiderivative`).
    fn antiderivative(&self, py: Python<'_>, nu: usize) -> PyResult<Curve> {
        let inner = py
            .detach(|| self.inner.antiderivative(nu))
            .map_err(value_error)?;
        Ok(Curve { inner })
    }

    /// The integral over [a, b] per coordinate into `out` (length dim), SciPy's
    /// `BSpline.integrate`.
    fn integrate_into(
        &self,
        py: Python<'_>,
        a: f64,
        b: f64,
        extrapolate: &str,
        mut out: PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let mode = extrapolate_mode(extrapolate)?;
        let value = py.detach(|| self.inner.integrate(a, b, mode));
        copy_into(&value, out.as_slice_mut()?)
    }

    /// The model file of the curve (`bspline_curve`), for saving, meshing and drawing.
    fn model(&self) -> PyResult<model::Model> {
        model::Model::from_file(BsplineCurveModel::file_of(&self.inner, None))
    }

    /// The curve of a `bspline_curve` model.
    #[classmethod]
    fn from_model(_cls: &Bound<'_, PyType>, m: &model::Model) -> PyResult<Curve> {
        match &m.model {
            AnyModel::BsplineCurve(c) => Ok(Curve {
                inner: c.curve.clone(),
            }),
            _ => Err(PyValueError::new_err(format!(
                "a {} is not a B-spline curve",
                m.model.describe()
            ))),
        }
    }

    /// The curve with the knot `x` inserted `m` times (SciPy's `BSpline.insert_knot`);
    /// `periodic` keeps periodic knots and coefficients periodic.
    fn insert_knot(&self, py: Python<'_>, x: f64, m: usize, periodic: bool) -> PyResult<Curve> {
        let inner = py
            .detach(|| {
                if periodic {
                    self.inner.insert_knot_periodic(x, m)
                } else {
                    self.inner.insert_knot(x, m)
                }
            })
            .map_err(value_error)?;
        Ok(Curve { inner })
    }
}

/// Whether `eval_many_par` gives SciPy's values of `curve` (up to rounding) everywhere: a
/// cubic of dimension 1 to 3 (its batched kernel) whose end intervals [t_3, t_4] and
/// [t_(n-1), t_n] are not empty (SciPy gives 0 on an empty end interval, the batched
/// kernel the neighbouring piece).
fn cubic_kernel_applies(curve: &BsplineCurve) -> bool {
    let t = curve.knots();
    let n = curve.n_control();
    curve.degree() == 3 && (1..=3).contains(&curve.dim()) && t[3] < t[4] && t[n - 1] < t[n]
}

/// A formula syntax by its geomkit-expr name ("sympy", "mathematica", "c", ...); an unknown
/// name is a `ValueError` listing them.
fn formula_format(name: &str) -> PyResult<geomkit::expr::Format> {
    use geomkit::expr::Format;
    Format::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown formula format {name:?}: expected one of {}",
            Format::ALL.map(Format::name).join(", ")
        ))
    })
}

/// `src` into `out` of the same length (a `ValueError` otherwise). The callers release the
/// GIL around copies that can be large (coefficients: a 10^7-point curve's are 240 MB).
fn copy_into(src: &[f64], out: &mut [f64]) -> PyResult<()> {
    if src.len() != out.len() {
        return Err(value_error(geomkit::Error::BufferSize {
            expected: src.len(),
            got: out.len(),
        }));
    }
    out.copy_from_slice(src);
    Ok(())
}

/// One end of SciPy's `bc_type` as the Python layer passes it: `None` (no condition) or a list
/// of (order, values) with orders >= 0 and values a 1-D float64 array (one per coordinate,
/// or one for all).
fn end_spec(end: Option<Vec<(usize, PyReadonlyArray1<'_, f64>)>>) -> PyResult<EndSpec> {
    let Some(list) = end else {
        return Ok(EndSpec::NotAKnot);
    };
    let mut derivatives = Vec::with_capacity(list.len());
    for (order, values) in list {
        derivatives.push((order, values.as_slice()?.to_vec()));
    }
    Ok(EndSpec::Derivatives(derivatives))
}

/// The interpolating B-spline of degree `k` through (x_i, y_i) (`y` of shape (len(x), dim)) in
/// SciPy's representation: `geomkit::bspline::make_interp_spline` with the knots `t` (or
/// SciPy's placement) and the ends `left`, `right` (see `end_spec`), or periodic ends.
/// `progress`: a callable `progress(done, total)` told how far the build is (see
/// `progress.rs`; Ctrl-C then interrupts it). `tile`: solve in tiles of that many
/// coefficients (`geomkit::bspline::make_interp_spline_tiled`, its default halo; the whole
/// system where the tiler refuses), at least `MIN_TILE_SIZE`.
#[pyfunction]
#[pyo3(signature = (x, y, k, t=None, left=None, right=None, periodic=false, progress=None, tile=None))]
fn make_interp_spline_curve(
    py: Python<'_>,
    x: PyReadonlyArray1<'_, f64>,
    y: PyReadonlyArray2<'_, f64>,
    k: usize,
    t: Option<PyReadonlyArray1<'_, f64>>,
    left: Option<Vec<(usize, PyReadonlyArray1<'_, f64>)>>,
    right: Option<Vec<(usize, PyReadonlyArray1<'_, f64>)>>,
    periodic: bool,
    progress: Option<Bound<'_, PyAny>>,
    tile: Option<usize>,
) -> PyResult<Curve> {
    let tiles = tile_options(tile)?;
    let ends = if periodic {
        SplineEnds::Periodic
    } else {
        SplineEnds::Open {
            left: end_spec(left)?,
            right: end_spec(right)?,
        }
    };
    let mut options = SplineOptions::new(k).with_ends(ends);
    if let Some(t) = t {
        options = options.with_knots(t.as_slice()?.to_vec());
    }
    let x = x.as_slice()?;
    let (_, dim, y) = matrix(&y)?;
    let inner = progress::run(py, progress.as_ref(), |p| match &tiles {
        Some(tiles) => make_interp_spline_tiled(x, y, dim, &options, tiles, p),
        None => make_interp_spline_with_progress(x, y, dim, &options, p),
    })?
    .map_err(value_error)?;
    Ok(Curve { inner })
}

/// The tiles of `tile` points each (the library's default halo), `None` without tiles;
/// a `ValueError` below [`MIN_TILE_SIZE`] (the Python layer checks first, in its words).
fn tile_options(tile: Option<usize>) -> PyResult<Option<TileOptions>> {
    match tile {
        None => Ok(None),
        Some(t) if t < MIN_TILE_SIZE => Err(PyValueError::new_err(format!(
            "tile must be at least {MIN_TILE_SIZE} points (got {t})"
        ))),
        Some(t) => Ok(Some(TileOptions::default().with_tile_size(t))),
    }
}

/// A tensor-product B-spline surface of heights (FITPACK's tck of `RectBivariateSpline`):
/// knots tx, ty, coefficients c (shape (len(tx) - kx - 1, len(ty) - ky - 1)), degrees 1 to 7.
/// Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
struct Surface {
    inner: BsplineSurface,
}

#[pymethods]
impl Surface {
    /// Checks and copies FITPACK's tck: knots `tx`, `ty`, coefficients `c` (shape
    /// (len(tx) - kx - 1, len(ty) - ky - 1)), degrees `kx`, `ky`.
    #[new]
    fn new(
        py: Python<'_>,
        tx: PyReadonlyArray1<'_, f64>,
        ty: PyReadonlyArray1<'_, f64>,
        c: PyReadonlyArray2<'_, f64>,
        kx: usize,
        ky: usize,
    ) -> PyResult<Self> {
        let (tx, ty) = (tx.as_slice()?, ty.as_slice()?);
        let (rows, cols, c) = matrix(&c)?;
        let inner = py
            .detach(|| {
                BsplineSurface::from_flat(
                    (kx, ky),
                    tx.to_vec(),
                    ty.to_vec(),
                    rows,
                    cols,
                    1,
                    c.to_vec(),
                )
            })
            .map_err(value_error)?;
        Ok(Surface { inner })
    }

    /// Degrees (kx, ky).
    #[getter]
    fn degrees(&self) -> (usize, usize) {
        self.inner.degrees()
    }

    /// The numbers of knots in x and y.
    #[getter]
    fn n_knots(&self) -> (usize, usize) {
        let (tx, ty) = self.inner.knots();
        (tx.len(), ty.len())
    }

    /// The net size (coefficients in x, in y).
    #[getter]
    fn net_size(&self) -> (usize, usize) {
        self.inner.net_size()
    }

    /// Copies the knots in x and in y into `tx`, `ty`.
    fn knots_into(
        &self,
        mut tx: PyReadwriteArray1<'_, f64>,
        mut ty: PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let (kx, ky) = self.inner.knots();
        copy_into(kx, tx.as_slice_mut()?)?;
        copy_into(ky, ty.as_slice_mut()?)
    }

    /// Copies the coefficients (row-major, x first: FITPACK's c) into `out`.
    fn coefficients_into(
        &self,
        py: Python<'_>,
        mut out: PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        py.detach(|| copy_into(self.inner.control_flat(), out))
    }

    /// ∂^(dx+dy) S / ∂x^dx ∂y^dy into `out`: on the grid x × y (`grid`; `out` of len(x) ×
    /// len(y) numbers, SciPy's `RectBivariateSpline.__call__(x, y, dx, dy, grid=True)`) or
    /// at the points (x[i], y[i]) (`out` of len(x) numbers, SciPy's `ev`).
    fn eval_into(
        &self,
        py: Python<'_>,
        x: PyReadonlyArray1<'_, f64>,
        y: PyReadonlyArray1<'_, f64>,
        dx: usize,
        dy: usize,
        grid: bool,
        mut out: PyReadwriteArrayDyn<'_, f64>,
    ) -> PyResult<()> {
        let (x, y) = (x.as_slice()?, y.as_slice()?);
        let out = out.as_slice_mut()?;
        py.detach(|| {
            if grid {
                self.inner.eval_partial_grid(x, y, dx, dy, out)
            } else {
                self.inner.eval_partial_many(x, y, dx, dy, out)
            }
        })
        .map_err(value_error)
    }

    /// The model file of the surface (`bspline_surface`), with the parameters of the grid
    /// of points it passes through if given, for saving, meshing and drawing.
    #[pyo3(signature = (params_u=None, params_v=None))]
    fn model(
        &self,
        params_u: Option<Vec<f64>>,
        params_v: Option<Vec<f64>>,
    ) -> PyResult<model::Model> {
        let params = params_u.as_deref().zip(params_v.as_deref());
        model::Model::from_file(BsplineSurfaceModel::file_of(&self.inner, params))
    }

    /// The surface of any `bspline_surface` model.
    #[classmethod]
    fn from_model_any(_cls: &Bound<'_, PyType>, m: &model::Model) -> PyResult<Surface> {
        match &m.model {
            AnyModel::BsplineSurface(s) => Ok(Surface {
                inner: s.surface.clone(),
            }),
            _ => Err(PyValueError::new_err(format!(
                "a {} is not a B-spline surface",
                m.model.describe()
            ))),
        }
    }

    /// The surface of a `bspline_surface` model of heights (dimension 1, degrees 1 to 7).
    #[classmethod]
    fn from_model(_cls: &Bound<'_, PyType>, m: &model::Model) -> PyResult<Surface> {
        let AnyModel::BsplineSurface(s) = &m.model else {
            return Err(PyValueError::new_err(format!(
                "a {} is not a B-spline surface",
                m.model.describe()
            )));
        };
        let (kx, ky) = s.surface.degrees();
        if s.surface.dim() != 1 || !(1..=7).contains(&kx) || !(1..=7).contains(&ky) {
            return Err(PyValueError::new_err(format!(
                "a {} is not a surface of heights of degrees 1 to 7 (RectBivariateSpline's)",
                m.model.describe()
            )));
        }
        Ok(Surface {
            inner: s.surface.clone(),
        })
    }

    /// The dimension of the points (1: heights).
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }

    /// Points S(u, v) into `out`: on the grid u × v (`grid`; `out` of len(u)·len(v)·dim
    /// numbers, `BsplineSurface::eval_grid`) or at the pairs (u[i], v[i]) (`eval_many_par`).
    /// Outside the domain the end patches continue. Errors: non-finite parameters, lengths.
    fn eval_points_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        grid: bool,
        mut out: PyReadwriteArrayDyn<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        py.detach(|| {
            if grid {
                self.inner.eval_grid(u, v, out)
            } else {
                self.inner.eval_many_par(u, v, out)
            }
        })
        .map_err(value_error)
    }

    /// The integral over [xa, xb] × [ya, yb] (SciPy's `RectBivariateSpline.integral`).
    fn integral(&self, py: Python<'_>, xa: f64, xb: f64, ya: f64, yb: f64) -> f64 {
        py.detach(|| self.inner.integral(xa, xb, ya, yb)[0])
    }
}

/// The interpolating surface of degrees (kx, ky) through the heights z (shape (len(x),
/// len(y))) over the grid x × y: SciPy's `RectBivariateSpline(x, y, z, kx=kx, ky=ky, s=0)`
/// (`geomkit::bspline::make_interp_surface`).
#[pyfunction]
#[pyo3(signature = (x, y, z, kx, ky, progress=None))]
fn make_interp_surface_heights(
    py: Python<'_>,
    x: PyReadonlyArray1<'_, f64>,
    y: PyReadonlyArray1<'_, f64>,
    z: PyReadonlyArray2<'_, f64>,
    kx: usize,
    ky: usize,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Surface> {
    let (x, y) = (x.as_slice()?, y.as_slice()?);
    let (rows, cols, z) = matrix(&z)?;
    let inner = progress::run(py, progress.as_ref(), |p| {
        make_interp_surface_with_progress(x, y, z, (rows, cols), (kx, ky), p)
    })?
    .map_err(value_error)?;
    Ok(Surface { inner })
}

/// An end condition of a direction of a parametric surface by name.
fn surface_end(name: &str) -> PyResult<EndCondition> {
    Ok(match name {
        "not-a-knot" => EndCondition::NotAKnot,
        "natural" => EndCondition::Natural,
        "bessel" => EndCondition::Bessel,
        "periodic" => EndCondition::Periodic,
        _ => {
            return Err(PyValueError::new_err(format!(
                "end condition {name:?}: expected \"not-a-knot\", \"natural\", \"bessel\" \
                 or \"periodic\""
            )))
        }
    })
}

/// The bicubic surface through a rows × cols grid of points (`points`: rows·cols rows of
/// `dim` numbers, row-major), with parameters by `param` ("chord", "centripetal",
/// "uniform", averaged over the grid lines) and an end condition per direction
/// (`geomkit::bspline::interpolate_surface_flat`). Returns the surface and the parameters of
/// the grid rows and columns. `tile`: solve in square blocks of that many points a side
/// (`geomkit::bspline::interpolate_surface_tiled`, its default halo), which refuses periodic
/// ends.
#[pyfunction]
#[pyo3(signature = (points, rows, cols, end_u, end_v, param, progress=None, tile=None))]
fn interpolate_grid(
    py: Python<'_>,
    points: PyReadonlyArray2<'_, f64>,
    rows: usize,
    cols: usize,
    end_u: &str,
    end_v: &str,
    param: &str,
    progress: Option<Bound<'_, PyAny>>,
    tile: Option<usize>,
) -> PyResult<(Surface, Vec<f64>, Vec<f64>)> {
    let tiles = tile_options(tile)?;
    let parametrization = match param {
        "chord" => Parametrization::ChordLength,
        "centripetal" => Parametrization::Centripetal,
        "uniform" => Parametrization::Uniform,
        _ => {
            return Err(PyValueError::new_err(format!(
                "param {param:?}: expected \"chord\", \"centripetal\" or \"uniform\""
            )))
        }
    };
    let options = SurfaceInterpolationOptions::default()
        .with_ends(surface_end(end_u)?, surface_end(end_v)?)
        .with_parametrization(parametrization);
    let (n, dim, flat) = matrix(&points)?;
    if Some(n) != rows.checked_mul(cols) {
        return Err(PyValueError::new_err(format!(
            "{n} points do not make a {rows} x {cols} grid"
        )));
    }
    let fit = progress::run(py, progress.as_ref(), |p| match &tiles {
        Some(tiles) => {
            interpolate_surface_tiled_with_progress(rows, cols, dim, flat, &options, tiles, p)
        }
        None => interpolate_surface_flat_with_progress(rows, cols, dim, flat, &options, p),
    })?
    .map_err(value_error)?;
    Ok((Surface { inner: fit.surface }, fit.params_u, fit.params_v))
}

/// The parameters of the grid rows and columns a `bspline_surface` model passes through, if
/// its file has them.
#[pyfunction]
fn surface_grid_parameters(m: &model::Model) -> Option<(Vec<f64>, Vec<f64>)> {
    match &m.model {
        AnyModel::BsplineSurface(s) => s.parameters.clone(),
        _ => None,
    }
}

/// The module `geomkit._geomkit`.
#[pymodule]
fn _geomkit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Curve>()?;
    m.add_class::<Surface>()?;
    m.add_function(wrap_pyfunction!(make_interp_spline_curve, m)?)?;
    m.add_function(wrap_pyfunction!(make_interp_surface_heights, m)?)?;
    m.add_function(wrap_pyfunction!(interpolate_grid, m)?)?;
    m.add_function(wrap_pyfunction!(surface_grid_parameters, m)?)?;
    m.add("MAX_SPLINE_DEGREE", geomkit::bspline::MAX_SPLINE_DEGREE)?;
    m.add("MAX_DEGREE", BsplineCurve::MAX_DEGREE)?;
    m.add("MIN_TILE_SIZE", MIN_TILE_SIZE)?;
    model::register(m)?;
    bezier::register(m)?;
    compose::register(m)?;
    pointcalc::register(m)?;
    Ok(())
}
