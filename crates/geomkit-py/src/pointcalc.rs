//! The point calculus of the Python package (issue 23, method 4, spec/point-calculus.md):
//! node sets, k-factor models through a grid of experimental points (fit, eval, shares, the
//! certified optimum, formulas), point-equation curves and surfaces through source points.
//!
//! As the rest of the module: the Python layer (python/geomkit/_pointcalc.py) shapes the
//! arguments and allocates the results; inputs are C-contiguous float64 arrays read in place,
//! results are written into the caller's arrays, the computations over arrays run with the GIL
//! released, the classes are `frozen`, the library's errors are `ValueError`s. Every class
//! converts to the model file the CLI writes (`pointcalc fit`, `pointcalc curve -o X.json`,
//! `pointcalc surface -o X.json`), a [`Model`].

use crate::model::Model;
use crate::{copy_into, matrix, value_error};
use geomkit::exact::{rational_from_f64, Rational};
use geomkit::expr::{Format, Graph, Id};
use geomkit::pointcalc::{
    cardinal_expr, optimize, Factor, Goal, Hypersurface, NodePreset, Nodes, OptimizeOptions,
    PointEquation, PointOptions, PointSurface as RowsSurface, PrintedSurface, Warning,
};
use geomkit_model::schema::{CurveSamplesFile, SurfaceSamplesFile};
use geomkit_model::{AnyModel, ModelFile, PointcalcModel, Points};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray1, PyReadwriteArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyType;

/// The options of a node check: the Lebesgue limit (None: the default of the nodes) and
/// strictness (an error instead of a warning above it).
fn point_options(strict: bool, lebesgue_limit: Option<f64>) -> PointOptions {
    let options = PointOptions::default().with_strict(strict);
    match lebesgue_limit {
        Some(limit) => options.with_lebesgue_limit(limit),
        None => options,
    }
}

/// The warnings as text (what the CLI prints after `warning: `).
fn warning_texts(warnings: &[Warning]) -> Vec<String> {
    warnings.iter().map(ToString::to_string).collect()
}

/// The program text of `pointcalc formula`: the preamble, then one definition per
/// (name, expression) in the parameters `params`.
fn print_formula(
    g: &Graph,
    params: &[&str],
    lines: Vec<(String, Id)>,
    format: Format,
) -> PyResult<String> {
    let mut out = g.print_preamble(params, format);
    for (name, e) in lines {
        let text = g
            .print_definition(&name, params, e, format)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        out.push_str(&text);
        out.push('\n');
    }
    Ok(out)
}

/// The coordinate names of a formula: x, y, z, then x3, x4, ... (as the CLI).
fn coordinate_name(d: usize) -> String {
    ["x", "y", "z"]
        .get(d)
        .map_or(format!("x{d}"), |s| (*s).to_string())
}

/// A rational "1/3", "2", or a decimal (its exact binary value), as the CLI reads `--nodes`.
fn parse_rational(x: &str) -> PyResult<Rational> {
    let x = x.trim();
    if let Ok(r) = x.parse::<Rational>() {
        return Ok(r);
    }
    x.parse::<f64>()
        .ok()
        .and_then(rational_from_f64)
        .ok_or_else(|| {
            PyValueError::new_err(format!("node {x:?} is not a finite number or fraction"))
        })
}

/// A node set of a parameter or factor: positions, exact rationals, a Chebyshev or
/// equispaced preset, or one of the paper's three-point sets. Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
#[derive(Clone)]
pub(crate) struct PointNodes {
    inner: Nodes,
}

#[pymethods]
impl PointNodes {
    /// Nodes at the (distinct, finite) positions `values`, in any order (kept sorted).
    #[new]
    fn new(values: PyReadonlyArray1<'_, f64>) -> PyResult<Self> {
        let inner = Nodes::new(values.as_slice()?.to_vec()).map_err(value_error)?;
        Ok(PointNodes { inner })
    }

    /// Nodes at exact rationals ("1/3", "2", "0.25": a decimal as its exact binary value),
    /// printed exactly in formulas.
    #[classmethod]
    fn exact(_cls: &Bound<'_, PyType>, values: Vec<String>) -> PyResult<Self> {
        let exact = values
            .iter()
            .map(|x| parse_rational(x))
            .collect::<PyResult<Vec<_>>>()?;
        let inner = Nodes::from_rationals(exact).map_err(value_error)?;
        Ok(PointNodes { inner })
    }

    /// `n` nodes of a preset ("cheb1", "cheb2", "equi") on [lo, hi].
    #[classmethod]
    fn preset(_cls: &Bound<'_, PyType>, name: &str, n: usize, lo: f64, hi: f64) -> PyResult<Self> {
        let preset = match name {
            "cheb1" => NodePreset::ChebyshevFirst,
            "cheb2" => NodePreset::ChebyshevSecond,
            "equi" => NodePreset::Equispaced,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown node preset {name:?} (cheb1, cheb2, equi)"
                )))
            }
        };
        let inner = Nodes::preset(preset, n, lo, hi).map_err(value_error)?;
        Ok(PointNodes { inner })
    }

    /// The paper's nodes {0, t_C, 1}: "half" (equation (1)), "third" ((2)), "two-thirds"
    /// ((3)).
    #[classmethod]
    fn paper(_cls: &Bound<'_, PyType>, name: &str) -> PyResult<Self> {
        let inner = match name {
            "half" => Nodes::paper_half(),
            "third" => Nodes::paper_third(),
            "two-thirds" => Nodes::paper_two_thirds(),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown paper node set {name:?} (half, third, two-thirds)"
                )))
            }
        };
        Ok(PointNodes { inner })
    }

    /// The number of nodes.
    #[getter]
    fn count(&self) -> usize {
        self.inner.len()
    }

    /// Copies the (increasing) positions into `out` (length `len`).
    fn values_into(&self, mut out: PyReadwriteArray1<'_, f64>) -> PyResult<()> {
        copy_into(self.inner.values(), out.as_slice_mut()?)
    }

    /// The exact positions as "p/q" strings, or None for nodes given as floats.
    fn exact_values(&self) -> Option<Vec<String>> {
        self.inner.is_rational().then(|| {
            self.inner
                .exact_values()
                .iter()
                .map(ToString::to_string)
                .collect()
        })
    }

    /// The Lebesgue constant (max over the node interval of Σ |L_j(t)|).
    fn lebesgue_constant(&self, py: Python<'_>) -> f64 {
        py.detach(|| self.inner.lebesgue_constant())
    }

    /// The cardinal ("b-") functions L_j(t) at every t into `out` (len(t) × len rows).
    fn basis_into(
        &self,
        py: Python<'_>,
        t: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let t = t.as_slice()?;
        let n = self.inner.len();
        let out = out.as_slice_mut()?;
        if out.len() != t.len() * n {
            return Err(value_error(geomkit::Error::BufferSize {
                expected: t.len() * n,
                got: out.len(),
            }));
        }
        py.detach(|| {
            for (x, row) in t.iter().zip(out.chunks_exact_mut(n)) {
                self.inner.basis_into(*x, row);
            }
        });
        Ok(())
    }
}

/// A point-calculus k-factor model through a full grid of experimental points (the model of
/// `pointcalc fit`) and the names of its responses. Immutable.
#[pyclass(frozen, name = "PointcalcModel", module = "geomkit._geomkit")]
pub(crate) struct PcModel {
    inner: PointcalcModel,
}

/// The model's response count check of a scalar search.
fn one_response(m: &PointcalcModel) -> PyResult<()> {
    if m.model.dim() != 1 {
        return Err(PyValueError::new_err(format!(
            "the model has {} responses ({}): the optimum is searched for one; select it \
             with response=",
            m.model.dim(),
            m.response.join(", ")
        )));
    }
    Ok(())
}

#[pymethods]
impl PcModel {
    /// The model through `values` (the flat grid, row-major over the factors, first factor
    /// slowest, one number per response) at the levels `nodes` of the factors `names`.
    #[classmethod]
    #[pyo3(signature = (names, nodes, response, values, strict=false, lebesgue_limit=None))]
    fn from_grid(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        names: Vec<String>,
        nodes: Vec<PyRef<'_, PointNodes>>,
        response: Vec<String>,
        values: PyReadonlyArray1<'_, f64>,
        strict: bool,
        lebesgue_limit: Option<f64>,
    ) -> PyResult<Self> {
        if names.len() != nodes.len() {
            return Err(PyValueError::new_err(format!(
                "{} factor names for {} node sets",
                names.len(),
                nodes.len()
            )));
        }
        check_response_names(&response)?;
        let factors: Vec<Factor> = names
            .into_iter()
            .zip(&nodes)
            .map(|(n, s)| Factor::new(n, s.inner.clone()))
            .collect();
        let values = values.as_slice()?;
        let options = point_options(strict, lebesgue_limit);
        let dim = response.len();
        let model = py
            .detach(|| Hypersurface::new(factors, dim, values.to_vec(), &options))
            .map_err(value_error)?;
        Ok(PcModel {
            inner: PointcalcModel { model, response },
        })
    }

    /// The model through experimental records (rows of the k factor values then the
    /// responses), as `pointcalc fit`: the levels of a factor are the distinct values of its
    /// column, or its given nodes (matched within 1e-9 of their span).
    #[classmethod]
    #[pyo3(signature = (names, records, nodes, response, strict=false, lebesgue_limit=None))]
    fn from_records(
        _cls: &Bound<'_, PyType>,
        py: Python<'_>,
        names: Vec<String>,
        records: PyReadonlyArray2<'_, f64>,
        nodes: Vec<Option<PyRef<'_, PointNodes>>>,
        response: Vec<String>,
        strict: bool,
        lebesgue_limit: Option<f64>,
    ) -> PyResult<Self> {
        check_response_names(&response)?;
        let (_, width, flat) = matrix(&records)?;
        if width != names.len() + response.len() {
            return Err(PyValueError::new_err(format!(
                "records have {width} columns, expected {} factors and {} responses",
                names.len(),
                response.len()
            )));
        }
        let given: Vec<Option<Nodes>> = nodes
            .iter()
            .map(|n| n.as_ref().map(|n| n.inner.clone()))
            .collect();
        let options = point_options(strict, lebesgue_limit);
        let model = py
            .detach(|| {
                let rows: Vec<Vec<f64>> = flat
                    .chunks_exact(width.max(1))
                    .map(<[f64]>::to_vec)
                    .collect();
                Hypersurface::from_records(&names, &rows, &given, &options)
            })
            .map_err(value_error)?;
        Ok(PcModel {
            inner: PointcalcModel { model, response },
        })
    }

    /// The model of a `pointcalc-model` file.
    #[classmethod]
    fn from_model(_cls: &Bound<'_, PyType>, model: PyRef<'_, Model>) -> PyResult<Self> {
        match &model.model {
            AnyModel::Pointcalc(m) => Ok(PcModel { inner: m.clone() }),
            other => Err(PyValueError::new_err(format!(
                "this is a {}, not a \"pointcalc-model\"",
                other.describe()
            ))),
        }
    }

    /// The model file (`pointcalc fit`'s output) with its geometry.
    fn to_model(&self) -> PyResult<Model> {
        Model::from_file(self.inner.to_file())
    }

    /// The factor names, in order.
    #[getter]
    fn factor_names(&self) -> Vec<String> {
        self.inner
            .model
            .factors()
            .iter()
            .map(|f| f.name().to_string())
            .collect()
    }

    /// The response names.
    #[getter]
    fn response(&self) -> Vec<String> {
        self.inner.response.clone()
    }

    /// The number of factors k.
    #[getter]
    fn k(&self) -> usize {
        self.inner.model.k()
    }

    /// The number of responses.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.model.dim()
    }

    /// The levels per factor (the grid's shape).
    #[getter]
    fn shape(&self) -> Vec<usize> {
        self.inner.model.shape()
    }

    /// The warnings of the fit (large Lebesgue constants).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        warning_texts(self.inner.model.warnings())
    }

    /// The nodes (levels) of factor `f`.
    fn nodes(&self, f: usize) -> PyResult<PointNodes> {
        let factors = self.inner.model.factors();
        factors
            .get(f)
            .map(|x| PointNodes {
                inner: x.nodes().clone(),
            })
            .ok_or_else(|| {
                PyValueError::new_err(format!("factor {f}: the model has {}", factors.len()))
            })
    }

    /// Copies the response values at the grid (row-major, `dim` per cell) into `out`.
    fn values_into(&self, py: Python<'_>, mut out: PyReadwriteArray1<'_, f64>) -> PyResult<()> {
        let out = out.as_slice_mut()?;
        py.detach(|| copy_into(self.inner.model.values(), out))
    }

    /// M(x) at the rows of `x` (shape (n, k)) into `out` (shape (n, dim)).
    fn eval_into(
        &self,
        py: Python<'_>,
        x: PyReadonlyArray2<'_, f64>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let (_, k, xs) = matrix(&x)?;
        if k != self.inner.model.k() {
            return Err(PyValueError::new_err(format!(
                "points have {k} factor values, the model has {} factors",
                self.inner.model.k()
            )));
        }
        let out = out.as_slice_mut()?;
        let model = &self.inner.model;
        py.detach(|| {
            model.eval_many(xs, out).map_err(|e| {
                // The first point that fails, by its row (as the CLI names the line).
                match xs
                    .chunks_exact(k)
                    .enumerate()
                    .find_map(|(i, p)| model.eval(p).err().map(|e| (i, e)))
                {
                    Some((i, e)) => format!("point {i}: {e}"),
                    None => e.to_string(),
                }
            })
        })
        .map_err(PyValueError::new_err)
    }

    /// The shares of every experimental point (cell, row-major) in M(x) into `out`.
    fn shares_into(
        &self,
        py: Python<'_>,
        x: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let x = x.as_slice()?;
        let out = out.as_slice_mut()?;
        let shares = py
            .detach(|| self.inner.model.shares(x))
            .map_err(value_error)?;
        copy_into(&shares, out)
    }

    /// The largest (`maximize`) or smallest response over the factors' box, certified by
    /// branch and bound: (location, value, bound, gap, boxes, certified).
    #[pyo3(signature = (maximize, tolerance=1e-9, max_boxes=4000, max_work=1_000_000_000))]
    fn optimize(
        &self,
        py: Python<'_>,
        maximize: bool,
        tolerance: f64,
        max_boxes: usize,
        max_work: u64,
    ) -> PyResult<(Vec<f64>, f64, f64, f64, usize, bool)> {
        one_response(&self.inner)?;
        if !tolerance.is_finite() || tolerance < 0.0 {
            return Err(PyValueError::new_err(format!(
                "tolerance must be a finite number >= 0, got {tolerance}"
            )));
        }
        let goal = if maximize { Goal::Max } else { Goal::Min };
        let options = OptimizeOptions::default()
            .with_tolerance(tolerance)
            .with_max_boxes(max_boxes)
            .with_max_work(max_work);
        let best = py
            .detach(|| optimize(&self.inner.model, goal, &options))
            .map_err(value_error)?;
        Ok((
            best.at,
            best.value,
            best.bound,
            best.gap,
            best.boxes,
            best.certified,
        ))
    }

    /// The model with `factor` fixed at `x` and removed (the section there).
    fn fix_factor(&self, py: Python<'_>, factor: usize, x: f64) -> PyResult<Self> {
        self.derived(py.detach(|| self.inner.model.fix_factor(factor, x)))
    }

    /// The model with `factor` removed by keeping its level `level`.
    fn remove_factor(&self, py: Python<'_>, factor: usize, level: usize) -> PyResult<Self> {
        self.derived(py.detach(|| self.inner.model.remove_factor(factor, level)))
    }

    /// The model without level `level` of `factor` (nothing else changes).
    fn remove_level(&self, py: Python<'_>, factor: usize, level: usize) -> PyResult<Self> {
        self.derived(py.detach(|| self.inner.model.remove_level(factor, level)))
    }

    /// The model with a new level of `factor` at `value` whose responses are `slice` (the
    /// grid of the other factors, row-major, `dim` per cell).
    fn add_level(
        &self,
        py: Python<'_>,
        factor: usize,
        value: f64,
        slice: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let slice = slice.as_slice()?;
        self.derived(py.detach(|| self.inner.model.add_level(factor, value, slice)))
    }

    /// The model as one formula per response in the syntax `format` (`pointcalc formula`).
    fn formula(&self, py: Python<'_>, format: &str) -> PyResult<String> {
        let format = crate::formula_format(format)?;
        let names = self.factor_names();
        py.detach(|| {
            let mut g = Graph::new();
            let vars: Vec<Id> = names.iter().map(|p| g.var(p)).collect();
            let exprs = self
                .inner
                .model
                .to_expr(&mut g, &vars)
                .map_err(value_error)?;
            let params: Vec<&str> = names.iter().map(String::as_str).collect();
            let lines = self.inner.response.iter().cloned().zip(exprs).collect();
            print_formula(&g, &params, lines, format)
        })
    }
}

impl PcModel {
    /// A model derived from this one, with its response names.
    fn derived(&self, model: geomkit::Result<Hypersurface>) -> PyResult<Self> {
        Ok(PcModel {
            inner: PointcalcModel {
                model: model.map_err(value_error)?,
                response: self.inner.response.clone(),
            },
        })
    }
}

/// Response names: at least one, no repeats.
fn check_response_names(response: &[String]) -> PyResult<()> {
    if response.is_empty() {
        return Err(PyValueError::new_err(
            "no response: a model has at least one response",
        ));
    }
    let mut seen = std::collections::HashSet::new();
    if let Some(r) = response.iter().find(|r| !seen.insert(r.as_str())) {
        return Err(PyValueError::new_err(format!(
            "response {r:?} is named twice"
        )));
    }
    Ok(())
}

/// The samples file of a curve (`pointcalc curve -o X.json`): `k` samples over the node
/// interval, each [t, x, y, ...].
fn curve_samples(eq: &PointEquation, k: usize) -> PyResult<ModelFile> {
    let (a, b) = eq.domain();
    let ts = geomkit_plot::figures::linspace(a, b, k);
    let d = eq.dim();
    let mut points = vec![0.0; k * d];
    eq.eval_params(&ts, &mut points).map_err(value_error)?;
    let mut flat = Vec::with_capacity(k * (d + 1));
    for (t, p) in ts.iter().zip(points.chunks_exact(d)) {
        flat.push(*t);
        flat.extend_from_slice(p);
    }
    Ok(ModelFile::PointcalcCurve(CurveSamplesFile {
        nodes: Some(eq.nodes().values().to_vec()),
        lebesgue: Some(eq.nodes().lebesgue_constant()),
        samples: Points { dim: d + 1, flat },
    }))
}

/// The most samples of a curve's or surface's model file (the CLI's limits).
const MAX_CURVE_SAMPLES: usize = 1_000_000;
const MAX_SURFACE_SAMPLES: usize = 1_000;

fn check_samples(k: usize, max: usize) -> PyResult<()> {
    if !(2..=max).contains(&k) {
        return Err(PyValueError::new_err(format!(
            "samples must be between 2 and {max}, got {k}"
        )));
    }
    Ok(())
}

/// A point-equation curve M(t) = Σ L_i(t) A_i through source points A_i of any dimension at
/// nodes t_i (equations (1)-(3) of the spec for three points). Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct PointCurve {
    inner: PointEquation,
}

#[pymethods]
impl PointCurve {
    /// The curve through `points` (shape (n, dim)) at `nodes` (n nodes).
    #[new]
    #[pyo3(signature = (nodes, points, strict=false, lebesgue_limit=None))]
    fn new(
        nodes: PyRef<'_, PointNodes>,
        points: PyReadonlyArray2<'_, f64>,
        strict: bool,
        lebesgue_limit: Option<f64>,
    ) -> PyResult<Self> {
        let (_, dim, flat) = matrix(&points)?;
        let inner = PointEquation::from_flat(
            nodes.inner.clone(),
            dim,
            flat.to_vec(),
            &point_options(strict, lebesgue_limit),
        )
        .map_err(value_error)?;
        Ok(PointCurve { inner })
    }

    /// The nodes.
    #[getter]
    fn nodes(&self) -> PointNodes {
        PointNodes {
            inner: self.inner.nodes().clone(),
        }
    }

    /// Coordinates per point.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.dim()
    }

    /// The warnings (a large Lebesgue constant).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        warning_texts(self.inner.warnings())
    }

    /// Copies the source points into `out` (shape (n, dim)).
    fn points_into(&self, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        copy_into(self.inner.points_flat(), out.as_slice_mut()?)
    }

    /// M(t) at every t into `out` (shape (len(t), dim)).
    fn eval_into(
        &self,
        py: Python<'_>,
        t: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let t = t.as_slice()?;
        let out = out.as_slice_mut()?;
        py.detach(|| self.inner.eval_params(t, out))
            .map_err(value_error)
    }

    /// The curve as one formula per coordinate in the parameter t (`pointcalc formula`).
    fn formula(&self, py: Python<'_>, format: &str) -> PyResult<String> {
        let format = crate::formula_format(format)?;
        py.detach(|| {
            let mut g = Graph::new();
            let t = g.var("t");
            let exprs = self.inner.to_expr(&mut g, t).map_err(value_error)?;
            let lines = exprs
                .into_iter()
                .enumerate()
                .map(|(d, e)| (coordinate_name(d), e))
                .collect();
            print_formula(&g, &["t"], lines, format)
        })
    }

    /// The samples file `pointcalc curve -o X.json --samples k` writes.
    fn samples_model(&self, py: Python<'_>, k: usize) -> PyResult<Model> {
        check_samples(k, MAX_CURVE_SAMPLES)?;
        let file = py.detach(|| curve_samples(&self.inner, k))?;
        Model::from_file(file)
    }
}

/// A point-equation surface through a net of source points: rows first (each row with its
/// own nodes along u), then across the rows (nodes along v); or the paper's geomatrix (9) as
/// printed (3×3 nets). Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct PointSurface {
    inner: AnySurface,
}

enum AnySurface {
    Rows(RowsSurface),
    Printed(PrintedSurface),
}

impl AnySurface {
    fn view(&self) -> &(dyn geomkit::geom::Surface + Sync) {
        match self {
            AnySurface::Rows(s) => s,
            AnySurface::Printed(s) => s,
        }
    }
}

/// The net as rows of points (each row an (m_i, dim) array).
fn net_of(net: &[PyReadonlyArray2<'_, f64>]) -> PyResult<Vec<Vec<Vec<f64>>>> {
    net.iter()
        .map(|row| {
            let (_, dim, flat) = matrix(row)?;
            Ok(flat.chunks_exact(dim.max(1)).map(<[f64]>::to_vec).collect())
        })
        .collect()
}

#[pymethods]
impl PointSurface {
    /// Rows first (row i through its points at `row_nodes[i]`), then across at `across`.
    #[classmethod]
    #[pyo3(signature = (row_nodes, across, net, strict=false, lebesgue_limit=None))]
    fn rows_then_across(
        _cls: &Bound<'_, PyType>,
        row_nodes: Vec<PyRef<'_, PointNodes>>,
        across: PyRef<'_, PointNodes>,
        net: Vec<PyReadonlyArray2<'_, f64>>,
        strict: bool,
        lebesgue_limit: Option<f64>,
    ) -> PyResult<Self> {
        let net = net_of(&net)?;
        let rows = row_nodes.iter().map(|n| n.inner.clone()).collect();
        let s = RowsSurface::with_options(
            rows,
            across.inner.clone(),
            net,
            &point_options(strict, lebesgue_limit),
        )
        .map_err(value_error)?;
        Ok(PointSurface {
            inner: AnySurface::Rows(s),
        })
    }

    /// The paper's geomatrix (9) as printed, over a 3×3 net (not affine invariant).
    #[classmethod]
    fn printed(_cls: &Bound<'_, PyType>, net: Vec<PyReadonlyArray2<'_, f64>>) -> PyResult<Self> {
        let s = PrintedSurface::new(net_of(&net)?).map_err(value_error)?;
        Ok(PointSurface {
            inner: AnySurface::Printed(s),
        })
    }

    /// Coordinates per point.
    #[getter]
    fn dim(&self) -> usize {
        self.inner.view().dim()
    }

    /// ((u0, u1), (v0, v1)).
    #[getter]
    fn domain(&self) -> ((f64, f64), (f64, f64)) {
        self.inner.view().domain()
    }

    /// The warnings (large Lebesgue constants).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        match &self.inner {
            AnySurface::Rows(s) => warning_texts(s.warnings()),
            AnySurface::Printed(_) => Vec::new(),
        }
    }

    /// M(u[i], v[i]) into `out` (shape (len(u), dim)).
    fn eval_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        let d = self.dim();
        if u.len() != v.len() || out.len() != u.len() * d {
            return Err(value_error(geomkit::Error::BufferSize {
                expected: u.len() * d,
                got: out.len(),
            }));
        }
        py.detach(|| {
            for (i, o) in out.chunks_exact_mut(d).enumerate() {
                // One point is the 1 × 1 grid: the checks and the overflow-safe combination.
                self.inner
                    .view()
                    .eval_grid(&u[i..=i], &v[i..=i], o)
                    .map_err(value_error)?;
            }
            Ok(())
        })
    }

    /// M on the grid u × v (u slowest) into `out` (len(u) · len(v) · dim numbers).
    fn eval_grid_into(
        &self,
        py: Python<'_>,
        u: PyReadonlyArray1<'_, f64>,
        v: PyReadonlyArray1<'_, f64>,
        mut out: PyReadwriteArray1<'_, f64>,
    ) -> PyResult<()> {
        let (u, v) = (u.as_slice()?, v.as_slice()?);
        let out = out.as_slice_mut()?;
        py.detach(|| self.inner.view().eval_grid(u, v, out))
            .map_err(value_error)
    }

    /// The share of every source point (row i, point j) in M(u, v): a_ij(u, v).
    fn shares(&self, u: f64, v: f64) -> PyResult<Vec<Vec<f64>>> {
        if !u.is_finite() || !v.is_finite() {
            return Err(PyValueError::new_err(format!(
                "(u, v) = ({u}, {v}) must be finite"
            )));
        }
        Ok(match &self.inner {
            AnySurface::Rows(s) => s.shares(u, v),
            AnySurface::Printed(_) => geomkit::pointcalc::printed_geomatrix(u, v)
                .iter()
                .map(|r| r.to_vec())
                .collect(),
        })
    }

    /// The surface as one formula per coordinate in (u, v): M(u, v) = Σ_i L_i(v) M_i(u).
    fn formula(&self, py: Python<'_>, format: &str) -> PyResult<String> {
        let format = crate::formula_format(format)?;
        let AnySurface::Rows(s) = &self.inner else {
            return Err(PyValueError::new_err(
                "the printed geomatrix (9) has no formula here: build the surface rows first \
                 (printed=False)",
            ));
        };
        py.detach(|| {
            let mut g = Graph::new();
            let (u, v) = (g.var("u"), g.var("v"));
            let rows = s
                .rows()
                .iter()
                .map(|eq| eq.to_expr(&mut g, u))
                .collect::<geomkit::Result<Vec<_>>>()
                .map_err(value_error)?;
            let across = (0..s.across().len())
                .map(|i| cardinal_expr(&mut g, s.across(), i, v))
                .collect::<geomkit::Result<Vec<_>>>()
                .map_err(value_error)?;
            let lines = (0..s.dim())
                .map(|d| {
                    let terms: Vec<Id> = across
                        .iter()
                        .zip(&rows)
                        .map(|(l, row)| g.mul(*l, row[d]))
                        .collect();
                    (coordinate_name(d), g.sum(&terms))
                })
                .collect();
            print_formula(&g, &["u", "v"], lines, format)
        })
    }

    /// The samples file `pointcalc surface -o X.json --samples k` writes: a k × k grid.
    fn samples_model(&self, py: Python<'_>, k: usize) -> PyResult<Model> {
        check_samples(k, MAX_SURFACE_SAMPLES)?;
        let view = self.inner.view();
        let file = py
            .detach(|| {
                let ((u0, u1), (v0, v1)) = view.domain();
                let us = geomkit_plot::figures::linspace(u0, u1, k);
                let vs = geomkit_plot::figures::linspace(v0, v1, k);
                let d = view.dim();
                let mut flat = vec![0.0; k * k * d];
                view.eval_grid(&us, &vs, &mut flat)?;
                Ok(ModelFile::PointcalcSurfaceSamples(SurfaceSamplesFile {
                    u: us,
                    v: vs,
                    points: Points { dim: d, flat },
                }))
            })
            .map_err(value_error)?;
        Model::from_file(file)
    }
}

/// Adds the point-calculus classes to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PointNodes>()?;
    m.add_class::<PcModel>()?;
    m.add_class::<PointCurve>()?;
    m.add_class::<PointSurface>()?;
    m.add("MAX_NODES", Nodes::MAX_LEN)?;
    m.add("MAX_MODEL_VALUES", Hypersurface::MAX_VALUES)?;
    Ok(())
}
