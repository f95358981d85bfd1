//! `geomkit._geomkit.Model`: any model of the tools (a file of `geomkit-model`) as one Python
//! object, the common ground of the package's classes: each class converts to a `Model` to be
//! saved, meshed or drawn, and `geomkit.load` turns a `Model` back into the class of its kind.

use geomkit_model::{AnyModel, ModelFile};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A model file's error (schema or geometry, with the JSON path) as a `ValueError`.
pub(crate) fn model_error(e: geomkit_model::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A model: the file that saves it and the geometry it describes (checked by the library).
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct Model {
    /// The file (what `save` writes).
    pub(crate) file: ModelFile,
    /// Its geometry.
    pub(crate) model: AnyModel,
}

impl Model {
    /// The model of a file: every check of the library (errors at the JSON path).
    pub(crate) fn from_file(file: ModelFile) -> PyResult<Model> {
        let model = AnyModel::from_file(file.clone()).map_err(model_error)?;
        Ok(Model { file, model })
    }
}

#[pymethods]
impl Model {
    /// The file's `"type"`: "bezier_curve", "bspline_surface", "composite_surface", "ruled",
    /// "formula", "pointcalc-model", ... (`geomkit_model::schema::TYPES`).
    #[getter]
    fn kind(&self) -> &'static str {
        self.file.type_name()
    }

    /// What the model is: "Bézier curve of degree 5 in R^2 (6 control points)".
    fn describe(&self) -> String {
        self.model.describe()
    }

    /// The model file as JSON text (the CLI's layout; errors: a number that is not finite).
    fn to_json(&self) -> PyResult<String> {
        geomkit_model::to_json(&self.file).map_err(model_error)
    }
}

/// Reads a model from the JSON text of a model file.
#[pyfunction]
fn parse_model(text: &str) -> PyResult<Model> {
    Model::from_file(geomkit_model::parse_file(text).map_err(model_error)?)
}

/// Adds `Model` and `parse_model` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_function(wrap_pyfunction!(parse_model, m)?)?;
    Ok(())
}
