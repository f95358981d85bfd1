//! `geomkit._geomkit.Model`: any model of the tools (a file of `geomkit-model`) as one Python
//! object, the common ground of the package's classes: each class converts to a `Model` to be
//! saved, meshed or drawn, and `geomkit.load` turns a `Model` back into the class of its kind.
//!
//! Meshes and pictures of any model go through the model crate's [`Loaded`] shape, exactly as
//! the CLI's `geomkit mesh` and `geomkit render` do: [`Model::tessellate`] gives a [`Mesh`]
//! (the compiled triangle mesh or polyline with the mesher's report, written to OBJ, STL, PLY
//! or glTF by the library's writers), [`Model::picture_svg`] / [`Model::picture_png`] the
//! picture of `geomkit-plot`. Every tessellation and picture runs with the GIL released.

use geomkit::mesh::{self, MeshReport, ObjNormals, Polyline, TriMesh};
use geomkit_model::step;
use geomkit_model::{AnyModel, Loaded, ModelFile, Sampling, Shape, Tessellation};
use geomkit_plot::figures::View;
use geomkit_plot::{picture_svg, svg_to_png, PictureOptions};
use numpy::{
    PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray1, PyReadwriteArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

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

    /// The model as one curve or surface to mesh or draw (errors: a point-calculus model of
    /// 3 or more factors or responses, a formula file without its model).
    fn loaded(&self) -> PyResult<Loaded> {
        Loaded::from_model(self.model.clone()).map_err(model_error)
    }
}

/// A picture's options as the Python layer passes them (checked there and here).
fn picture_options(
    view: (f64, f64),
    size: Option<(u32, u32)>,
    net: bool,
) -> PyResult<PictureOptions> {
    let (azimuth, elevation) = view;
    if !(azimuth.is_finite() && elevation.is_finite() && elevation.abs() <= 90.0) {
        return Err(PyValueError::new_err(format!(
            "view ({azimuth}, {elevation}): azimuth and elevation must be finite degrees, the \
             elevation within -90..90"
        )));
    }
    let mut opts = PictureOptions {
        view: View { azimuth, elevation },
        net,
        ..PictureOptions::default()
    };
    if let Some((w, h)) = size {
        if !((16..=8192).contains(&w) && (16..=8192).contains(&h)) {
            return Err(PyValueError::new_err(format!(
                "size ({w}, {h}): width and height must be from 16 to 8192 pixels"
            )));
        }
        opts.size = (f64::from(w), f64::from(h));
    }
    Ok(opts)
}

/// The picture of `loaded` as SVG (`geomkit render`'s picture; the subtitle says what it is).
fn svg_of(loaded: &Loaded, title: &str, opts: &PictureOptions) -> PyResult<String> {
    picture_svg(loaded, title, &loaded.what, opts).map_err(|e| PyValueError::new_err(e.to_string()))
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

    /// What the model is drawn and meshed as: "curve" or "surface" (errors: a model that is
    /// neither, e.g. a point-calculus model of three factors).
    #[getter]
    fn shape(&self, py: Python<'_>) -> PyResult<&'static str> {
        let loaded = py.detach(|| self.loaded())?;
        Ok(match loaded.shape {
            Shape::Curve { .. } => "curve",
            Shape::Surface { .. } => "surface",
        })
    }

    /// Tessellates the model as `geomkit mesh` does: adaptive to `tolerance` (model units;
    /// None: 1/1000 of the extent per axis for a surface, 1/2000 of the diagonal for a
    /// curve), or `samples` = (K, L) uniform samples (a curve: K points).
    /// `progress`: a callable `progress(done, total)` told how far a surface's meshing is
    /// (`crate::progress`; Ctrl-C then interrupts it).
    #[pyo3(signature = (tolerance=None, samples=None, progress=None))]
    fn tessellate(
        &self,
        py: Python<'_>,
        tolerance: Option<f64>,
        samples: Option<(usize, usize)>,
        progress: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Mesh> {
        let (sampling, option) = match (tolerance, samples) {
            (Some(_), Some(_)) => {
                return Err(PyValueError::new_err("give tolerance or samples, not both"))
            }
            (Some(t), None) if !(t.is_finite() && t > 0.0) => {
                return Err(PyValueError::new_err(format!(
                    "tolerance={t}: must be finite and > 0"
                )))
            }
            (Some(t), None) => (Sampling::Tolerance(Some(t)), format!("tolerance={t}: ")),
            (None, Some((k, l))) => (Sampling::Samples(k, l), format!("samples=({k}, {l}): ")),
            (None, None) => (Sampling::Tolerance(None), String::new()),
        };
        let meshed = crate::progress::run(py, progress.as_ref(), |p| {
            Ok(self.loaded().and_then(|loaded| {
                loaded
                    .tessellate_with_progress(sampling, p)
                    .map_err(|e| PyValueError::new_err(format!("{option}{e}")))
            }))
        })?;
        let (tessellation, report) = meshed.map_err(crate::value_error)??;
        Ok(Mesh {
            tessellation,
            report,
        })
    }

    /// The picture of the model as SVG text (`geomkit render ... -o OUT.svg`): `view` =
    /// (azimuth, elevation) in degrees, `size` = (width, height) pixels of a shaded surface
    /// (curves size themselves), `net` = draw the control net or polygon.
    #[pyo3(signature = (title, view, size=None, net=true))]
    fn picture_svg(
        &self,
        py: Python<'_>,
        title: &str,
        view: (f64, f64),
        size: Option<(u32, u32)>,
        net: bool,
    ) -> PyResult<String> {
        let opts = picture_options(view, size, net)?;
        py.detach(|| svg_of(&self.loaded()?, title, &opts))
    }

    /// The picture of the model as PNG bytes (`geomkit render ... -o OUT.png`): rasterized at
    /// `scale` times the SVG's size, or fitted into `size` (aspect kept, centred).
    #[pyo3(signature = (title, view, size=None, net=true, scale=2.0))]
    fn picture_png<'py>(
        &self,
        py: Python<'py>,
        title: &str,
        view: (f64, f64),
        size: Option<(u32, u32)>,
        net: bool,
        scale: f64,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let opts = picture_options(view, size, net)?;
        if !(scale.is_finite() && scale > 0.0 && scale <= 16.0) {
            return Err(PyValueError::new_err(format!(
                "scale={scale}: must be finite, > 0 and at most 16"
            )));
        }
        let png = py.detach(|| {
            let svg = svg_of(&self.loaded()?, title, &opts)?;
            svg_to_png(&svg, scale, size).map_err(|e| PyValueError::new_err(e.to_string()))
        })?;
        Ok(PyBytes::new(py, &png))
    }
}

/// The mesh of a model (`Model.tessellate`) or of arrays (`Mesh(vertices, faces)`): a
/// triangle mesh (welded positions, triangles, per-corner normals) or a polyline, and the
/// surface mesher's report. Immutable.
#[pyclass(frozen, module = "geomkit._geomkit")]
pub(crate) struct Mesh {
    tessellation: Tessellation,
    report: Option<MeshReport>,
}

impl Mesh {
    fn triangles(&self) -> PyResult<&TriMesh> {
        match &self.tessellation {
            Tessellation::Mesh(m) => Ok(m),
            Tessellation::Polyline(_) => Err(PyValueError::new_err(
                "a curve's mesh is a polyline: it has points, not triangles",
            )),
        }
    }

    fn line(&self) -> PyResult<&Polyline> {
        match &self.tessellation {
            Tessellation::Polyline(p) => Ok(p),
            Tessellation::Mesh(_) => Err(PyValueError::new_err(
                "a surface's mesh has triangles, not a polyline",
            )),
        }
    }
}

/// `rows` rows of 3 into `out` (a `ValueError` when the length differs).
fn rows_into(rows: &[[f64; 3]], out: &mut [f64]) -> PyResult<()> {
    crate::copy_into(rows.as_flattened(), out)
}

#[pymethods]
impl Mesh {
    /// A triangle mesh of `vertices` (n, 3) and `faces` (m, 3) indices (float64, as the
    /// Python layer converts them): vertices closer than `weld_tolerance` merged, normals
    /// smooth across edges whose faces meet within `crease_degrees` (the mesher's 40).
    #[new]
    #[pyo3(signature = (vertices, faces, weld_tolerance=0.0, crease_degrees=40.0))]
    fn new(
        py: Python<'_>,
        vertices: PyReadonlyArray2<'_, f64>,
        faces: PyReadonlyArray2<'_, i64>,
        weld_tolerance: f64,
        crease_degrees: f64,
    ) -> PyResult<Self> {
        if vertices.shape()[1] != 3 || faces.shape()[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "vertices must have shape (n, 3) and faces (m, 3), not {:?} and {:?}",
                vertices.shape(),
                faces.shape()
            )));
        }
        let v = vertices.as_slice()?;
        let f = faces.as_slice()?;
        let n = v.len() / 3;
        let mesh = py.detach(|| {
            let positions: Vec<[f64; 3]> = v.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
            let mut triangles = Vec::with_capacity(f.len() / 3);
            for (k, t) in f.chunks_exact(3).enumerate() {
                let mut tri = [0u32; 3];
                for (slot, &i) in tri.iter_mut().zip(t) {
                    if i < 0 || i as usize >= n {
                        return Err(PyValueError::new_err(format!(
                            "face {k} refers to vertex {i}, there are {n}"
                        )));
                    }
                    *slot = i as u32;
                }
                triangles.push(tri);
            }
            TriMesh::new(positions, triangles, weld_tolerance, crease_degrees)
                .map_err(crate::value_error)
        })?;
        Ok(Mesh {
            tessellation: Tessellation::Mesh(mesh),
            report: None,
        })
    }

    /// "mesh" (triangles) or "polyline" (a curve's points).
    #[getter]
    fn kind(&self) -> &'static str {
        match self.tessellation {
            Tessellation::Mesh(_) => "mesh",
            Tessellation::Polyline(_) => "polyline",
        }
    }

    /// Triangle mesh: (vertices, faces).
    #[getter]
    fn counts(&self) -> PyResult<(usize, usize)> {
        let m = self.triangles()?;
        Ok((m.positions().len(), m.triangles().len()))
    }

    /// Triangle mesh: the vertices into `out` (shape (n, 3)).
    fn vertices_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let m = self.triangles()?;
        let out = out.as_slice_mut()?;
        py.detach(|| rows_into(m.positions(), out))
    }

    /// Triangle mesh: the faces' vertex indices into `out` (shape (m, 3), int64).
    fn faces_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, i64>) -> PyResult<()> {
        let m = self.triangles()?;
        let out = out.as_slice_mut()?;
        if out.len() != 3 * m.triangles().len() {
            return Err(crate::value_error(geomkit::Error::BufferSize {
                expected: 3 * m.triangles().len(),
                got: out.len(),
            }));
        }
        py.detach(|| {
            for (o, &i) in out.iter_mut().zip(m.triangles().as_flattened()) {
                *o = i64::from(i);
            }
        });
        Ok(())
    }

    /// Triangle mesh: one unit normal per vertex into `out` (shape (n, 3)): the mesh's
    /// normal where the surface is smooth at the vertex; at a crease (several normals at its
    /// corners), the normalized mean of its distinct corner normals.
    fn normals_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let m = self.triangles()?;
        let out = out.as_slice_mut()?;
        py.detach(|| rows_into(&vertex_normals(m), out))
    }

    /// Triangle mesh: the unit normal of each face into `out` (shape (m, 3); zero for a
    /// degenerate face).
    fn face_normals_into(
        &self,
        py: Python<'_>,
        mut out: PyReadwriteArray2<'_, f64>,
    ) -> PyResult<()> {
        let m = self.triangles()?;
        let out = out.as_slice_mut()?;
        py.detach(|| {
            let normals: Vec<[f64; 3]> =
                (0..m.triangles().len()).map(|t| m.face_normal(t)).collect();
            rows_into(&normals, out)
        })
    }

    /// Triangle mesh: its area.
    fn area(&self) -> PyResult<f64> {
        Ok(self.triangles()?.area())
    }

    /// Triangle mesh: the signed volume it encloses (meaningful when watertight).
    fn volume(&self) -> PyResult<f64> {
        Ok(self.triangles()?.volume())
    }

    /// Triangle mesh: every edge shared by exactly two faces, in opposite directions.
    fn is_watertight(&self) -> PyResult<bool> {
        Ok(self.triangles()?.is_watertight())
    }

    /// The bounding box (lower corner, upper corner) of the vertices or points (in R^3; a
    /// polyline's points lifted as the writers lift them).
    fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        let points = match &self.tessellation {
            Tessellation::Mesh(m) => return m.bounding_box(),
            Tessellation::Polyline(p) => p.points3(),
        };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &points {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        (lo, hi)
    }

    /// Polyline: (points, dimension).
    #[getter]
    fn polyline_shape(&self) -> PyResult<(usize, usize)> {
        let p = self.line()?;
        Ok((p.len(), p.dim()))
    }

    /// Polyline: the points into `out` (shape (n, dim)).
    fn points_into(&self, py: Python<'_>, mut out: PyReadwriteArray2<'_, f64>) -> PyResult<()> {
        let p = self.line()?;
        let out = out.as_slice_mut()?;
        py.detach(|| crate::copy_into(p.points(), out))
    }

    /// Polyline: the curve parameter of each point into `out` (length n).
    fn parameters_into(&self, py: Python<'_>, mut out: PyReadwriteArray1<'_, f64>) -> PyResult<()> {
        let p = self.line()?;
        let out = out.as_slice_mut()?;
        py.detach(|| crate::copy_into(p.params(), out))
    }

    /// The surface mesher's report, None for a polyline or a mesh of arrays: (closed,
    /// capped, deviation, relative deviation, weld tolerance per axis).
    #[allow(clippy::type_complexity)]
    #[getter]
    fn report(&self) -> Option<(bool, bool, Option<f64>, Option<f64>, [f64; 3])> {
        self.report.map(|r| {
            (
                r.closed,
                r.capped,
                r.deviation,
                r.relative_deviation,
                r.weld,
            )
        })
    }

    /// The file bytes in `format` ("obj", "stl", "ply", "glb"; the library's writers, as
    /// `geomkit mesh` writes them): `ascii` STL, `obj_normals` = "auto", "indexed",
    /// "per-vertex" or "none". A polyline has no STL.
    #[pyo3(signature = (format, ascii=false, obj_normals="auto"))]
    fn encode<'py>(
        &self,
        py: Python<'py>,
        format: &str,
        ascii: bool,
        obj_normals: &str,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let normals = ObjNormals::from_name(obj_normals).ok_or_else(|| {
            PyValueError::new_err(format!(
                "obj_normals={obj_normals:?}: expected \"auto\", \"indexed\", \"per-vertex\" or \"none\""
            ))
        })?;
        let bytes = py.detach(|| {
            let mut out = Vec::new();
            let written = match (&self.tessellation, format) {
                (Tessellation::Mesh(m), "obj") => mesh::write_obj_with(m, normals, &mut out),
                (Tessellation::Mesh(m), "stl") if ascii => mesh::write_stl_ascii(m, &mut out),
                (Tessellation::Mesh(m), "stl") => mesh::write_stl_binary(m, &mut out),
                (Tessellation::Mesh(m), "ply") => mesh::write_ply(m, &mut out),
                (Tessellation::Mesh(m), "glb") => mesh::write_glb(m, &mut out),
                (Tessellation::Polyline(p), "obj") => mesh::write_obj_polyline(p, &mut out),
                (Tessellation::Polyline(p), "ply") => mesh::write_ply_polyline(p, &mut out),
                (Tessellation::Polyline(p), "glb") => mesh::write_glb_polyline(p, &mut out),
                (Tessellation::Polyline(_), "stl") => {
                    return Err(PyValueError::new_err(
                        "STL holds triangles only: write a curve as .obj, .ply or .glb",
                    ))
                }
                (_, other) => {
                    return Err(PyValueError::new_err(format!(
                    "unknown mesh format {other:?}: expected \"obj\", \"stl\", \"ply\" or \"glb\""
                )))
                }
            };
            written
                .map(|()| out)
                .map_err(|e| PyValueError::new_err(e.to_string()))
        })?;
        Ok(PyBytes::new(py, &bytes))
    }
}

/// A polyline of `points` (n, dim) at strictly increasing `parameters` (n).
#[pyfunction]
fn mesh_polyline(
    py: Python<'_>,
    points: PyReadonlyArray2<'_, f64>,
    parameters: PyReadonlyArray1<'_, f64>,
) -> PyResult<Mesh> {
    let dim = points.shape()[1];
    let p = points.as_slice()?;
    let t = parameters.as_slice()?;
    let line = py
        .detach(|| Polyline::new(dim, t.to_vec(), p.to_vec()))
        .map_err(crate::value_error)?;
    Ok(Mesh {
        tessellation: Tessellation::Polyline(line),
        report: None,
    })
}

/// One unit normal per vertex: its corners' normal where they agree, the normalized mean of
/// their distinct normals at a crease.
fn vertex_normals(m: &TriMesh) -> Vec<[f64; 3]> {
    let mut seen: Vec<Vec<u32>> = vec![Vec::new(); m.positions().len()];
    for (t, n) in m.triangles().iter().zip(m.normal_indices()) {
        for k in 0..3 {
            let list = &mut seen[t[k] as usize];
            if !list.contains(&n[k]) {
                list.push(n[k]);
            }
        }
    }
    let normals = m.normals();
    seen.iter()
        .map(|list| match list[..] {
            [one] => normals[one as usize],
            _ => {
                let s = list.iter().fold([0.0; 3], |a, &i| {
                    let n = normals[i as usize];
                    [a[0] + n[0], a[1] + n[1], a[2] + n[2]]
                });
                let len = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
                if len > 0.0 {
                    s.map(|x| x / len)
                } else {
                    [0.0; 3]
                }
            }
        })
        .collect()
}

/// Reads a model from the JSON text of a model file.
#[pyfunction]
fn parse_model(text: &str) -> PyResult<Model> {
    Model::from_file(geomkit_model::parse_file(text).map_err(model_error)?)
}

/// One approximated piece of a STEP export: (piece, samples per direction, deviation,
/// tolerance), the deviation and tolerance in the model's units.
type StepApproximation = (String, Vec<usize>, f64, f64);

/// The model as a STEP file (ISO 10303-21 text, `geomkit_model::step::export`): `name` the
/// product's name, `schema` "ap214" or "ap242", `tolerance` the relative tolerance of
/// formulas written as interpolating B-splines. Returns the text and the approximated
/// pieces. Errors (`ValueError`): a model with no B-spline form, an unknown schema, a
/// tolerance that is not finite and > 0 or cannot be reached.
#[pyfunction]
#[pyo3(signature = (model, name="geomkit", schema="ap214", tolerance=1e-6))]
fn step_write(
    py: Python<'_>,
    model: &Model,
    name: &str,
    schema: &str,
    tolerance: f64,
) -> PyResult<(String, Vec<StepApproximation>)> {
    let schema = match schema {
        "ap214" => step::Schema::Ap214,
        "ap242" => step::Schema::Ap242,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown STEP schema {other:?}: give \"ap214\" or \"ap242\""
            )))
        }
    };
    let options = step::WriteOptions::default()
        .with_name(name)
        .with_schema(schema)
        .with_tolerance(tolerance);
    let export = py
        .detach(|| step::export(&model.model, &options))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let report = export
        .approximations
        .into_iter()
        .map(|a| (a.piece, a.samples, a.deviation, a.tolerance))
        .collect();
    Ok((export.text, report))
}

/// One model read from a STEP file: (entity number, entity type, name, model, note).
type StepModel = (u64, String, String, Model, Option<String>);

/// The curves and surfaces of a STEP file's text (`geomkit_model::step::read`): the models in
/// the order of their entity numbers, the skipped entities in one phrase, the file's length
/// unit. Errors (`ValueError`): the file's first problem, naming the entity (`#12: ...`).
#[pyfunction]
fn step_read(py: Python<'_>, text: &str) -> PyResult<(Vec<StepModel>, String, Option<String>)> {
    let import = py
        .detach(|| step::read(text))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let summary = import.skipped_summary();
    let models = import
        .models
        .into_iter()
        .map(|m| Ok((m.id, m.entity, m.name, Model::from_file(m.file)?, m.note)))
        .collect::<PyResult<Vec<_>>>()?;
    Ok((models, summary, import.length_unit))
}

/// Adds `Model`, `parse_model` and the STEP functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_class::<Mesh>()?;
    m.add_function(wrap_pyfunction!(mesh_polyline, m)?)?;
    m.add_function(wrap_pyfunction!(parse_model, m)?)?;
    m.add_function(wrap_pyfunction!(step_write, m)?)?;
    m.add_function(wrap_pyfunction!(step_read, m)?)?;
    Ok(())
}
