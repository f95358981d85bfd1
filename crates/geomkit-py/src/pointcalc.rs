//! Placeholder: the pointcalc part of the Python bindings (issue 23).

use pyo3::prelude::*;

/// Adds this part's classes and functions to the module.
pub(crate) fn register(_m: &Bound<'_, PyModule>) -> PyResult<()> {
    Ok(())
}
