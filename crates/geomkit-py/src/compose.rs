//! `geomkit._geomkit.Composite`: the single formulas of method 3 (spec/composite-surfaces.md)
//! for Python — closed bodies and piecewise-ruled surfaces (formula (2)), composite surfaces of
//! patches (formulas (3)-(11)), piecewise functions and composite curves (§5).
//!
//! A `Composite` is made from a model file (`from_model`: "composite_surface",
//! "composite_explicit", "ruled", "piecewise", "polyline", "polygon", "formula", and the
//! B-spline files the CLI's `compose patches` / `compose piecewise` read) or from a body's
//! name and sizes (`body`, the CLI's `compose body`). It keeps the file it was made from, so
//! that `model()` is exactly the file the CLI reads and writes.
//!
//! - `print(fmt, program)`: the formula in one of the eleven syntaxes of geomkit-expr;
//! - `eval_into(inputs, out, threads)`: the compiled evaluator (geomkit-expr's `Tape`,
//!   `eval_batch`) of the single formula, over C-contiguous float64 arrays, in chunks on
//!   `threads` threads, with the GIL released; `eval_cells_into`: the structural evaluator
//!   (the cell or piece of each point, O(1) per point), equal to the formula within rounding;
//! - `continuity()` and `ruled_report()`: the continuity and consistency reports.

use crate::model::{model_error, Model};
use crate::value_error;
use geomkit::compose::{
    bodies, CompositeSurface, Formula, GridLine, Piecewise, RuledCurve, RuledSurface, SurfaceKind,
};
use geomkit::expr::{Format, Tape};
use geomkit_model::{AnyModel, ModelFile};
use numpy::{PyReadonlyArray1, PyReadwriteArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;
use std::sync::OnceLock;

/// The geometry of a `Composite`.
#[derive(Debug, Clone)]
enum Geometry {
    /// A composite surface (parametric or explicit).
    Surface(CompositeSurface),
    /// A piecewise-ruled surface (a body).
    Ruled(RuledSurface),
    /// A piecewise function or composite curve.
    Piecewise(Piecewise),
}

impl Geometry {
    /// The single formula.
    fn formula(&self) -> geomkit::Result<Formula> {
        match self {
            Geometry::Surface(s) => s.formula(),
            Geometry::Ruled(s) => s.formula(),
            Geometry::Piecewise(p) => p.formula(),
        }
    }

    /// Number of coordinates.
    fn dim(&self) -> usize {
        match self {
            Geometry::Surface(s) => s.dim(),
            Geometry::Ruled(_) => 3,
            Geometry::Piecewise(p) => p.dim(),
        }
    }

    /// Number of variables (2 for surfaces, 1 for functions and curves).
    fn arity(&self) -> usize {
        match self {
            Geometry::Piecewise(_) => 1,
            _ => 2,
        }
    }

    /// The structural evaluator at one point (`x` of `arity` numbers) into `out` (dim).
    fn eval_point(&self, x: &[f64], out: &mut [f64]) {
        match self {
            Geometry::Surface(s) => s.eval_into(x[0], x[1], out),
            Geometry::Ruled(s) => s.eval_into(x[0], x[1], out),
            Geometry::Piecewise(p) => p.eval_into(x[0], out),
        }
    }
}

/// A single formula of method 3 and the model it comes from. Immutable; the formula and its
/// compiled tape are built on first use.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct Composite {
    geometry: Geometry,
    /// The file it was made from (`None` for a body whose ruled file cannot be written).
    file: Option<ModelFile>,
    formula: OnceLock<Formula>,
    tape: OnceLock<Tape>,
}

impl Composite {
    fn new(geometry: Geometry, file: Option<ModelFile>) -> Composite {
        Composite {
            geometry,
            file,
            formula: OnceLock::new(),
            tape: OnceLock::new(),
        }
    }

    /// The formula, built once.
    fn formula_ref(&self) -> PyResult<&Formula> {
        if let Some(f) = self.formula.get() {
            return Ok(f);
        }
        let f = self.geometry.formula().map_err(value_error)?;
        Ok(self.formula.get_or_init(|| f))
    }

    /// The compiled tape of the formula, built once.
    fn tape_ref(&self) -> PyResult<&Tape> {
        if let Some(t) = self.tape.get() {
            return Ok(t);
        }
        let f = self.formula_ref()?;
        let vars: Vec<&str> = f.vars.iter().map(String::as_str).collect();
        let tape = Tape::new(&f.graph, &f.roots, &vars)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(self.tape.get_or_init(|| tape))
    }

    /// The geometry of a model, or a `ValueError` naming what it is.
    fn from_any(model: &AnyModel, file: ModelFile) -> PyResult<Composite> {
        let geometry = match model {
            AnyModel::Composite(s) => Geometry::Surface(s.clone()),
            AnyModel::Ruled(s) => Geometry::Ruled(s.clone()),
            AnyModel::Piecewise(p) => Geometry::Piecewise(p.clone()),
            AnyModel::BsplineSurface(m) => {
                Geometry::Surface(CompositeSurface::from_bspline(&m.surface).map_err(value_error)?)
            }
            AnyModel::BsplineCurve(m) => {
                Geometry::Piecewise(Piecewise::from_bspline(&m.curve).map_err(value_error)?)
            }
            AnyModel::Formula(f) => match &f.model {
                Some(m) => return Self::from_any(m, file),
                None => {
                    return Err(PyValueError::new_err(format!(
                        "this formula file ({}) carries no model to rebuild the formula from",
                        f.file.what
                    )))
                }
            },
            other => {
                return Err(PyValueError::new_err(format!(
                    "this is a {}; a composite formula is made from a \"composite_surface\", \
                     \"composite_explicit\", \"bspline_surface\", \"ruled\", \"piecewise\", \
                     \"polyline\", \"polygon\", \"bspline_curve\" or \"formula\" file",
                    other.describe()
                )))
            }
        };
        Ok(Composite::new(geometry, Some(file)))
    }
}

/// Splits `0..n` into at most `threads` chunks of at least `min` points: (start, end) pairs.
fn chunks(n: usize, threads: usize, min: usize) -> Vec<(usize, usize)> {
    let parts = threads.clamp(1, n.div_ceil(min).max(1));
    let size = n.div_ceil(parts).max(1);
    (0..n)
        .step_by(size)
        .map(|a| (a, (a + size).min(n)))
        .collect()
}

/// Runs `work(start, end, outputs)` on disjoint chunks of the rows of `out` (`rows` rows of
/// `n` numbers, row-major), in parallel.
fn run_chunked<F>(out: &mut [f64], rows: usize, n: usize, threads: usize, work: F) -> PyResult<()>
where
    F: Fn(usize, usize, &mut [&mut [f64]]) -> PyResult<()> + Sync,
{
    let parts = chunks(n, threads, 16384);
    if n == 0 {
        return Ok(());
    }
    // Per chunk, the slice of every row.
    let mut per_chunk: Vec<Vec<&mut [f64]>> = parts.iter().map(|_| Vec::new()).collect();
    for row in out.chunks_exact_mut(n).take(rows) {
        let mut rest = row;
        for (c, &(a, b)) in parts.iter().enumerate() {
            let (head, tail) = rest.split_at_mut(b - a);
            per_chunk[c].push(head);
            rest = tail;
        }
    }
    if per_chunk.len() == 1 {
        let (a, b) = parts[0];
        return work(a, b, &mut per_chunk[0]);
    }
    // On rayon's pool (threads kept between calls: spawning two threads per call cost
    // 40-80 µs here, a few percent of a call on 10^6 points).
    parts
        .into_par_iter()
        .zip(per_chunk)
        .map(|((a, b), mut cols)| work(a, b, &mut cols))
        .collect::<PyResult<Vec<()>>>()
        .map(|_| ())
}

/// The parts to run in parallel: `threads`, or one per core for 0.
fn thread_count(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, usize::from)
    } else {
        threads
    }
}

/// The inputs as slices of one length, and that length (a `ValueError` otherwise).
fn input_slices<'a>(
    inputs: &'a [PyReadonlyArray1<'_, f64>],
    arity: usize,
) -> PyResult<(Vec<&'a [f64]>, usize)> {
    if inputs.len() != arity {
        return Err(PyValueError::new_err(format!(
            "{} inputs given, the formula has {arity} variables",
            inputs.len()
        )));
    }
    let slices = inputs
        .iter()
        .map(|a| a.as_slice())
        .collect::<Result<Vec<_>, _>>()?;
    let n = slices.first().map_or(0, |s| s.len());
    if slices.iter().any(|s| s.len() != n) {
        return Err(PyValueError::new_err("the inputs have different lengths"));
    }
    Ok((slices, n))
}

/// Checks that `out` has shape (dim, n) and returns it as a slice.
fn output_slice<'a>(
    out: &'a mut PyReadwriteArray2<'_, f64>,
    dim: usize,
    n: usize,
) -> PyResult<&'a mut [f64]> {
    let shape = out.shape().to_vec();
    if shape != [dim, n] {
        return Err(PyValueError::new_err(format!(
            "the output has shape {shape:?}, expected [{dim}, {n}]"
        )));
    }
    Ok(out.as_slice_mut()?)
}

#[pymethods]
impl Composite {
    /// "surface" (parametric, in u, v), "explicit" (z in x, y), "ruled" (in u, v),
    /// "function" (f in x) or "curve" (in t).
    #[getter]
    fn kind(&self) -> &'static str {
        match &self.geometry {
            Geometry::Surface(s) => match s.kind() {
                SurfaceKind::Parametric => "surface",
                SurfaceKind::Explicit => "explicit",
            },
            Geometry::Ruled(_) => "ruled",
            Geometry::Piecewise(p) if p.dim() == 1 => "function",
            Geometry::Piecewise(_) => "curve",
        }
    }

    /// The variables of the formula, in order ("u", "v"; "x", "y"; "t"; "x").
    #[getter]
    fn variables(&self) -> PyResult<Vec<String>> {
        Ok(self.formula_ref()?.vars.clone())
    }

    /// The coordinates of the formula ("x", "y", "z"; "z"; "f"; "x0", ...).
    #[getter]
    fn coordinates(&self) -> PyResult<Vec<String>> {
        Ok(self.formula_ref()?.names.clone())
    }

    /// Number of coordinates.
    #[getter]
    fn dim(&self) -> usize {
        self.geometry.dim()
    }

    /// Operations of the formula's DAG after sharing.
    #[getter]
    fn op_count(&self) -> PyResult<usize> {
        Ok(self.formula_ref()?.op_count())
    }

    /// The parameter domain: ((u0, u1), (v0, v1)) or ((x0, xn),).
    #[getter]
    fn domain(&self) -> Vec<(f64, f64)> {
        match &self.geometry {
            Geometry::Surface(s) => {
                let (u, v) = s.domain();
                vec![u, v]
            }
            Geometry::Ruled(s) => {
                let (u, v) = s.domain();
                vec![u, v]
            }
            Geometry::Piecewise(p) => {
                let k = p.knots();
                vec![(k[0], k[k.len() - 1])]
            }
        }
    }

    /// The knots (grid lines) per variable: (u_knots, v_knots), (v values,) of a ruled
    /// surface, (knots,) of a piecewise formula.
    #[getter]
    fn knots(&self) -> Vec<Vec<f64>> {
        match &self.geometry {
            Geometry::Surface(s) => {
                let (u, v) = s.knots();
                vec![u.to_vec(), v.to_vec()]
            }
            Geometry::Ruled(s) => vec![s.v_values().to_vec()],
            Geometry::Piecewise(p) => vec![p.knots().to_vec()],
        }
    }

    /// The formula in the syntax `fmt` (a name of `FORMATS`, or an alias: octave, python,
    /// javascript, wolfram, tex); `program`: with common subexpressions in temporaries.
    #[pyo3(signature = (fmt, program=false))]
    fn print(&self, py: Python<'_>, fmt: &str, program: bool) -> PyResult<String> {
        let format = crate::formula_format(fmt)?;
        let f = self.formula_ref()?;
        py.detach(|| {
            if program {
                f.print_program(format)
            } else {
                f.print(format)
            }
        })
        .map_err(value_error)
    }

    /// The continuity report at the grid lines or breakpoints: (max_jump, tolerance,
    /// continuous, statement, jumps), each jump (line "u"/"v", index, cell, max_jump, at);
    /// `None` for a ruled surface (see `ruled_report`).
    #[allow(clippy::type_complexity)]
    fn continuity(
        &self,
    ) -> Option<(
        f64,
        f64,
        bool,
        String,
        Vec<(&'static str, usize, usize, f64, f64)>,
    )> {
        let (report, statement) = match &self.geometry {
            Geometry::Surface(s) => {
                let (uk, vk) = s.knots();
                let names = match s.kind() {
                    SurfaceKind::Parametric => ("u", "v"),
                    SurfaceKind::Explicit => ("x", "y"),
                };
                let r = s.continuity();
                (r, r.statement(names.0, names.1, (uk, vk)))
            }
            Geometry::Piecewise(p) => (p.continuity(), p.statement()),
            Geometry::Ruled(_) => return None,
        };
        let jumps = report
            .jumps
            .iter()
            .map(|j| {
                let (line, index) = match j.line {
                    GridLine::U(i) => ("u", i),
                    GridLine::V(k) => ("v", k),
                };
                (line, index, j.cell, j.max_jump, j.at)
            })
            .collect();
        Some((
            report.max_jump,
            report.tolerance,
            report.is_continuous(),
            statement,
            jumps,
        ))
    }

    /// Warnings of a piecewise formula (a piece not finite inside its interval).
    fn warnings(&self) -> Vec<String> {
        match &self.geometry {
            Geometry::Piecewise(p) => p.warnings().to_vec(),
            _ => Vec::new(),
        }
    }

    /// The consistency checks of a ruled surface (the CLI's `compose ruled` report): the v
    /// values, the open curves (index, gap between their ends), whether both end curves are
    /// points, and the largest difference between the compiled formula (2) and the
    /// structural evaluator on `samples` × `samples` points of the domain. `None` for other
    /// kinds.
    #[pyo3(signature = (samples=41))]
    #[allow(clippy::type_complexity)]
    fn ruled_report(
        &self,
        py: Python<'_>,
        samples: usize,
    ) -> PyResult<Option<(Vec<f64>, Vec<(usize, f64)>, bool, f64)>> {
        let Geometry::Ruled(s) = &self.geometry else {
            return Ok(None);
        };
        if !(2..=2000).contains(&samples) {
            return Err(PyValueError::new_err(format!(
                "samples = {samples}: expected 2 to 2000"
            )));
        }
        let tape = self.tape_ref()?;
        py.detach(|| {
            let mut open = Vec::new();
            let mut scale = 0.0f64;
            for (k, c) in s.curves().iter().enumerate() {
                let (t0, t1) = c.interval();
                let (a, b) = (c.eval(t0), c.eval(t1));
                scale = a.iter().chain(&b).fold(scale, |m, x| m.max(x.abs()));
                let gap = (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
                if gap > 1e-12 * scale.max(1.0) && !matches!(c, RuledCurve::Point(_)) {
                    open.push((k, gap));
                }
            }
            let curves = s.curves();
            let ends_are_points = matches!(curves[0], RuledCurve::Point(_))
                && matches!(curves[curves.len() - 1], RuledCurve::Point(_));
            let ((u0, u1), (v0, v1)) = s.domain();
            let at = |a: f64, b: f64, i: usize| a + (b - a) * i as f64 / (samples - 1) as f64;
            let (pu, pv): (Vec<f64>, Vec<f64>) = (0..samples)
                .flat_map(|i| (0..samples).map(move |j| (at(u0, u1, i), at(v0, v1, j))))
                .unzip();
            let n = pu.len();
            let mut cols = vec![0.0; 3 * n];
            {
                let mut rows: Vec<&mut [f64]> = cols.chunks_exact_mut(n).collect();
                tape.eval_batch(&[&pu, &pv], &mut rows)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?;
            }
            let mut worst = 0.0f64;
            let mut q = [0.0; 3];
            for i in 0..n {
                s.eval_into(pu[i], pv[i], &mut q);
                for c in 0..3 {
                    worst = worst.max((cols[c * n + i] - q[c]).abs());
                }
            }
            Ok(Some((s.v_values().to_vec(), open, ends_are_points, worst)))
        })
    }

    /// The compiled evaluator: the single formula at the points `inputs[k][i]` (one 1-D
    /// C-contiguous float64 array per variable, all of one length n) into `out` (shape
    /// (dim, n)), by geomkit-expr's `Tape::eval_batch` in `threads` parts (0: one per core)
    /// on rayon's pool, with the GIL released. NaN and infinities follow f64.
    #[pyo3(signature = (inputs, out, threads=0))]
    fn eval_into(
        &self,
        py: Python<'_>,
        inputs: Vec<PyReadonlyArray1<'_, f64>>,
        mut out: PyReadwriteArray2<'_, f64>,
        threads: usize,
    ) -> PyResult<()> {
        let tape = self.tape_ref()?;
        let dim = self.geometry.dim();
        let (xs, n) = input_slices(&inputs, self.geometry.arity())?;
        let out = output_slice(&mut out, dim, n)?;
        let threads = thread_count(threads);
        py.detach(|| {
            run_chunked(out, dim, n, threads, |a, b, cols| {
                let part: Vec<&[f64]> = xs.iter().map(|x| &x[a..b]).collect();
                tape.eval_batch(&part, cols)
                    .map_err(|e| PyValueError::new_err(e.to_string()))
            })
        })
    }

    /// The structural evaluator (the cell or piece of each point, O(1) per point on uniform
    /// knots), equal to the single formula within rounding: arguments as `eval_into`.
    /// Errors: a NaN or infinite input.
    #[pyo3(signature = (inputs, out, threads=0))]
    fn eval_cells_into(
        &self,
        py: Python<'_>,
        inputs: Vec<PyReadonlyArray1<'_, f64>>,
        mut out: PyReadwriteArray2<'_, f64>,
        threads: usize,
    ) -> PyResult<()> {
        let dim = self.geometry.dim();
        let arity = self.geometry.arity();
        let (xs, n) = input_slices(&inputs, arity)?;
        let out = output_slice(&mut out, dim, n)?;
        let threads = thread_count(threads);
        let geometry = &self.geometry;
        py.detach(|| {
            for (k, x) in xs.iter().enumerate() {
                if let Some(i) = x.iter().position(|t| !t.is_finite()) {
                    return Err(PyValueError::new_err(format!(
                        "input {k} at {i} is {}: the structural evaluator takes finite \
                         parameters",
                        x[i]
                    )));
                }
            }
            run_chunked(out, dim, n, threads, |a, b, cols| {
                let mut p = [0.0; 2];
                let mut q = vec![0.0; dim];
                for i in a..b {
                    for (k, x) in xs.iter().enumerate() {
                        p[k] = x[i];
                    }
                    geometry.eval_point(&p[..arity], &mut q);
                    for (c, col) in cols.iter_mut().enumerate() {
                        col[i - a] = q[c];
                    }
                }
                Ok(())
            })
        })
    }

    /// The model: the file it was made from (what `save` writes and the CLI reads).
    fn model(&self) -> PyResult<Model> {
        match &self.file {
            Some(f) => Model::from_file(f.clone()),
            None => Err(PyValueError::new_err(
                "this formula has no model file (a curve given in another variable than t)",
            )),
        }
    }
}

/// A composite formula from a model (see the module's doc for the kinds).
#[pyfunction]
fn composite_from_model(model: &Model) -> PyResult<Composite> {
    Composite::from_any(&model.model, model.file.clone())
}

/// A closed body of the CLI's `compose body`: `name` one of cube, box, pyramid, cone,
/// cylinder, prism, frustum; sizes as the CLI's options (None: the CLI's defaults).
#[pyfunction]
#[pyo3(signature = (name, size=None, height=None, radius=None, top_radius=None, side=None,
                    ngon=None, polygon=None))]
#[allow(clippy::too_many_arguments)]
fn body(
    name: &str,
    size: Option<[f64; 3]>,
    height: Option<f64>,
    radius: Option<f64>,
    top_radius: Option<f64>,
    side: Option<f64>,
    ngon: Option<usize>,
    polygon: Option<Vec<[f64; 2]>>,
) -> PyResult<Composite> {
    let h = height.unwrap_or(2.0);
    let r = radius.unwrap_or(1.0);
    if let Some(n) = ngon {
        if !(3..=10000).contains(&n) {
            return Err(PyValueError::new_err(format!(
                "ngon = {n}: expected 3 to 10000 vertices"
            )));
        }
    }
    if let Some(p) = &polygon {
        if !(3..=10000).contains(&p.len()) {
            return Err(PyValueError::new_err(format!(
                "a polygon of {} vertices: expected 3 to 10000",
                p.len()
            )));
        }
    }
    let base = || -> geomkit::Result<Vec<[f64; 2]>> {
        match &polygon {
            Some(p) => Ok(p.clone()),
            None => bodies::regular_polygon(ngon.unwrap_or(6), r),
        }
    };
    let surface = match name {
        "cube" => bodies::cube(),
        "box" => {
            let [a, b, c] = size.unwrap_or([2.0; 3]);
            bodies::rectangular_box(a, b, c)
        }
        "pyramid" if ngon.is_some() || polygon.is_some() => {
            base().and_then(|p| bodies::pyramid(&p, h))
        }
        "pyramid" => bodies::square_pyramid(side.unwrap_or(2.0), h),
        "cone" => bodies::cone(r, h),
        "cylinder" => bodies::cylinder(r, h),
        "prism" => base().and_then(|p| bodies::prism(&p, h)),
        "frustum" => bodies::frustum(r, top_radius.unwrap_or(r / 2.0), h),
        _ => {
            return Err(PyValueError::new_err(format!(
                "unknown body {name:?}: expected cube, box, pyramid, cone, cylinder, prism or \
                 frustum"
            )))
        }
    }
    .map_err(value_error)?;
    let file = geomkit_model::ruled_file(&surface).map(ModelFile::Ruled);
    // The file must read back as this body.
    if let Some(f) = &file {
        AnyModel::from_file(f.clone()).map_err(model_error)?;
    }
    Ok(Composite::new(Geometry::Ruled(surface), file))
}

/// The names of the formula syntaxes, in geomkit-expr's order.
#[pyfunction]
fn formula_formats() -> Vec<&'static str> {
    Format::ALL.map(Format::name).to_vec()
}

/// Adds `Composite`, `composite_from_model`, `body` and `formula_formats` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Composite>()?;
    m.add_function(wrap_pyfunction!(composite_from_model, m)?)?;
    m.add_function(wrap_pyfunction!(body, m)?)?;
    m.add_function(wrap_pyfunction!(formula_formats, m)?)?;
    Ok(())
}
