//! File formats of the CLI: curves and surfaces as JSON.
//!
//! - `{"type":"bezier_curve","points":[[x,y],...],"weights":[...]}`: a curve in any dimension;
//!   with `weights` (one per point, > 0) a rational curve. An `"error"` object (written by an
//!   approximate reduction) is accepted and ignored on reading.
//! - `{"type":"bezier_surface","net":[[[x,y,z],...],...]}`: a tensor-product surface, `net[i][j]`
//!   the control point u_ij (row i along u, column j along v).
//! - `{"type":"bspline_curve","degree":3,"knots":[...],"control_points":[[x,y],...],
//!   "parameters":[...]}`: a B-spline curve (n control points, n + degree + 1 knots, domain
//!   [knots[degree], knots[n]]); the optional `parameters` are those of the reference points an
//!   interpolating curve passes through.
//! - `{"type":"bspline_surface","degree":[3,3],"knots_u":[...],"knots_v":[...],
//!   "net":[[[x,y,z],...],...],"parameters_u":[...],"parameters_v":[...]}`: a tensor-product
//!   B-spline surface, `net[i][j]` the control point c_ij; a height field z(x, y) has 1-D net
//!   points `[z]` and its knots in x (u) and y (v).
//! - A B-spline curve's control points as CSV or `.npy` (one point per row) with its knots in
//!   the sibling file `NAME.knots.EXT` (one knot per row), as `interpolate curve --control`
//!   writes them ([`knots_sibling`]).
//!
//! Reading validates everything and names the place of the first problem (`points[2][1] is the
//! string "NaN"`); the library then checks what is geometry (weights > 0, ...).

use crate::progress::Progress;
use crate::table::{extension, Table};
use anyhow::{anyhow, bail, Context, Result};
use geomkit::bezier::{BezierCurve, BezierSurface, RationalBezierCurve};
use geomkit::bspline::{BsplineCurve, BsplineSurface};
use geomkit::geom::Curve;
use serde_json::{Map, Value};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// A model read from or written to a file.
#[derive(Debug, Clone, PartialEq)]
pub enum Model {
    /// A polynomial Bézier curve.
    Curve(BezierCurve),
    /// A rational Bézier curve.
    Rational(RationalBezierCurve),
    /// A tensor-product Bézier surface.
    Surface(BezierSurface),
}

/// Error report of an approximate reduction, written as `"error":{"l2":...,"linf_bound":...}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorReport {
    /// L2[0,1] distance between the original and the reduced curve.
    pub l2: f64,
    /// Guaranteed upper bound of the largest distance between them.
    pub linf_bound: f64,
}

impl Model {
    /// What the model is, for messages: "Bézier curve of degree 5 in R^2".
    pub fn describe(&self) -> String {
        match self {
            Model::Curve(c) => format!(
                "Bézier curve of degree {} in R^{} ({} control points)",
                c.degree(),
                c.dim(),
                c.degree() + 1
            ),
            Model::Rational(r) => format!(
                "rational Bézier curve of degree {} in R^{} ({} control points)",
                r.degree(),
                Curve::dim(r),
                r.degree() + 1
            ),
            Model::Surface(s) => {
                let (n, m) = s.degrees();
                format!(
                    "Bézier surface of degrees ({n}, {m}) in R^{} ({}×{} net)",
                    s.dim(),
                    n + 1,
                    m + 1
                )
            }
        }
    }
}

/// A B-spline curve and, for an interpolating curve, the parameters of its reference points.
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineCurveModel {
    /// The curve.
    pub curve: BsplineCurve,
    /// Parameters of the reference points, if known.
    pub parameters: Option<Vec<f64>>,
}

/// A B-spline surface and, for an interpolating surface, the grid parameters of its
/// reference points (rows in u, columns in v).
#[derive(Debug, Clone, PartialEq)]
pub struct BsplineSurfaceModel {
    /// The surface.
    pub surface: BsplineSurface,
    /// Parameters of the grid rows (u) and columns (v), if known.
    pub parameters: Option<(Vec<f64>, Vec<f64>)>,
}

/// Any model a file can hold.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyModel {
    /// A Bézier curve or surface.
    Bezier(Model),
    /// A B-spline curve.
    BsplineCurve(BsplineCurveModel),
    /// A B-spline surface.
    BsplineSurface(BsplineSurfaceModel),
}

impl AnyModel {
    /// What the model is, for messages.
    pub fn describe(&self) -> String {
        match self {
            AnyModel::Bezier(m) => m.describe(),
            AnyModel::BsplineCurve(m) => format!(
                "B-spline curve of degree {} in R^{} ({} control points)",
                m.curve.degree(),
                m.curve.dim(),
                m.curve.n_control()
            ),
            AnyModel::BsplineSurface(m) => {
                let (p, q) = m.surface.degrees();
                let (a, b) = m.surface.net_size();
                format!(
                    "B-spline surface of degrees ({p}, {q}) in R^{} ({a}×{b} net)",
                    m.surface.dim()
                )
            }
        }
    }
}

/// Reads a Bézier model from a JSON file; errors name the file and the place of the problem.
pub fn read_model(path: &Path) -> Result<Model> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_model(&text).with_context(|| path.display().to_string())
}

/// Reads any model: a JSON file, or a B-spline curve's control points (`.csv`, `.npy`) with
/// its knots in the sibling file ([`knots_sibling`]).
pub fn read_any_model(path: &Path) -> Result<AnyModel> {
    if matches!(extension(path).as_deref(), Some("npy" | "csv")) {
        return read_control_pair(path);
    }
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_any_model(&text).with_context(|| path.display().to_string())
}

/// The file holding the knots of the control points in `control`: `NAME.knots.EXT`.
pub fn knots_sibling(control: &Path) -> PathBuf {
    let stem = control
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = control
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    control.with_file_name(format!("{stem}.knots.{ext}"))
}

fn read_control_pair(path: &Path) -> Result<AnyModel> {
    let progress = Progress::hidden();
    let control = Table::read(path, &progress)?;
    let (n, dim) = control.as_records()?;
    let knots_path = knots_sibling(path);
    if !knots_path.is_file() {
        bail!(
            "{}: control points need their knots in {} (as `interpolate curve --control` \
             writes them); models without a knots file are JSON",
            path.display(),
            knots_path.display()
        );
    }
    let knots = Table::read(&knots_path, &progress)?;
    let (k, one) = knots.as_records()?;
    if one != 1 {
        bail!(
            "{}: expected one knot per row, found {} columns",
            knots_path.display(),
            one
        );
    }
    if k <= n + 1 {
        bail!(
            "{}: {k} knots for {n} control points in {} (need control points + degree + 1)",
            knots_path.display(),
            path.display()
        );
    }
    let curve = BsplineCurve::from_flat(k - n - 1, knots.data, dim, control.data)
        .with_context(|| format!("{} with {}", path.display(), knots_path.display()))?;
    Ok(AnyModel::BsplineCurve(BsplineCurveModel {
        curve,
        parameters: None,
    }))
}

/// Parses a Bézier model from JSON text (the `bezier` commands' input).
pub fn parse_model(text: &str) -> Result<Model> {
    match parse_any_model(text)? {
        AnyModel::Bezier(m) => Ok(m),
        other => bail!(
            "this is a {}; `geomkit bezier` commands take Bézier models (\"bezier_curve\", \
             \"bezier_surface\"); evaluate it with `geomkit eval`",
            other.describe()
        ),
    }
}

/// Parses any model from JSON text.
pub fn parse_any_model(text: &str) -> Result<AnyModel> {
    let value: Value = serde_json::from_str(text).map_err(|e| {
        if e.to_string().starts_with("number out of range") {
            anyhow!("{e} (every number must be a finite f64)")
        } else {
            anyhow!("invalid JSON: {e}")
        }
    })?;
    let obj = value.as_object().ok_or_else(|| {
        anyhow!(
            "expected a JSON object with a \"type\" field, found {}",
            kind(&value)
        )
    })?;
    let ty = match obj.get("type") {
        None => bail!("missing field \"type\" ({TYPES})"),
        Some(Value::String(s)) => s.as_str(),
        Some(other) => bail!("\"type\" must be a string, found {}", kind(other)),
    };
    match ty {
        "bezier_curve" => parse_curve(obj).map(AnyModel::Bezier),
        "bezier_surface" => parse_surface(obj).map(AnyModel::Bezier),
        "bspline_curve" => parse_bspline_curve(obj).map(AnyModel::BsplineCurve),
        "bspline_surface" => parse_bspline_surface(obj).map(AnyModel::BsplineSurface),
        other => bail!(
            "unknown type {}: expected {TYPES}",
            Value::String(other.to_string())
        ),
    }
}

const TYPES: &str =
    "\"bezier_curve\", \"bezier_surface\", \"bspline_curve\" or \"bspline_surface\"";

fn field<'a>(obj: &'a Map<String, Value>, name: &str, ty: &str) -> Result<&'a Value> {
    obj.get(name)
        .ok_or_else(|| anyhow!("missing field \"{name}\" of a {ty}"))
}

/// A B-spline degree (1..=7) at `place`.
fn degree_value(value: &Value, place: &str) -> Result<usize> {
    match value.as_u64() {
        Some(p) if (1..=7).contains(&p) => Ok(p as usize),
        _ => bail!(
            "{place} must be an integer from 1 to 7, found {}",
            kind(value)
        ),
    }
}

/// An array of finite numbers at `place`.
fn number_list(value: &Value, place: &str) -> Result<Vec<f64>> {
    let arr = value.as_array().ok_or_else(|| {
        anyhow!(
            "\"{place}\" must be an array of numbers, found {}",
            kind(value)
        )
    })?;
    arr.iter()
        .enumerate()
        .map(|(k, x)| number(x, &format!("{place}[{k}]")))
        .collect()
}

fn optional_list(obj: &Map<String, Value>, name: &str) -> Result<Option<Vec<f64>>> {
    match obj.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => number_list(v, name).map(Some),
    }
}

/// A `"bspline_curve"` object (the output of `geomkit interpolate curve -o fit.json`).
pub fn parse_bspline_curve(obj: &Map<String, Value>) -> Result<BsplineCurveModel> {
    const TY: &str = "bspline_curve";
    check_fields(
        obj,
        TY,
        &["degree", "knots", "control_points", "parameters"],
    )?;
    let degree = degree_value(field(obj, "degree", TY)?, "\"degree\"")?;
    let knots = number_list(field(obj, "knots", TY)?, "knots")?;
    let points = point_list(field(obj, "control_points", TY)?, "control_points")?;
    if points.is_empty() {
        bail!("\"control_points\" is empty");
    }
    check_same_dim(&points, |k| format!("control_points[{k}]"))?;
    let parameters = optional_list(obj, "parameters")?;
    Ok(BsplineCurveModel {
        curve: BsplineCurve::new(degree, knots, points)?,
        parameters,
    })
}

/// A `"bspline_surface"` object (the output of `geomkit interpolate surface -o fit.json`).
pub fn parse_bspline_surface(obj: &Map<String, Value>) -> Result<BsplineSurfaceModel> {
    const TY: &str = "bspline_surface";
    check_fields(
        obj,
        TY,
        &[
            "degree",
            "knots_u",
            "knots_v",
            "net",
            "parameters_u",
            "parameters_v",
        ],
    )?;
    let degree = field(obj, "degree", TY)?;
    let degrees = match degree.as_array().map(Vec::as_slice) {
        Some([p, q]) => (degree_value(p, "degree[0]")?, degree_value(q, "degree[1]")?),
        _ => bail!(
            "\"degree\" of a {TY} must be a pair [p, q], found {}",
            kind(degree)
        ),
    };
    let knots_u = number_list(field(obj, "knots_u", TY)?, "knots_u")?;
    let knots_v = number_list(field(obj, "knots_v", TY)?, "knots_v")?;
    let (rows, cols, dim, flat) = net_points(field(obj, "net", TY)?)?;
    let parameters = match (
        optional_list(obj, "parameters_u")?,
        optional_list(obj, "parameters_v")?,
    ) {
        (Some(u), Some(v)) => Some((u, v)),
        (None, None) => None,
        _ => bail!("give both \"parameters_u\" and \"parameters_v\" or neither"),
    };
    Ok(BsplineSurfaceModel {
        surface: BsplineSurface::from_flat(degrees, knots_u, knots_v, rows, cols, dim, flat)?,
        parameters,
    })
}

fn check_fields(obj: &Map<String, Value>, ty: &str, allowed: &[&str]) -> Result<()> {
    for key in obj.keys() {
        if key != "type" && !allowed.contains(&key.as_str()) {
            bail!(
                "unknown field {} in a {ty} (expected {})",
                Value::String(key.clone()),
                allowed
                    .iter()
                    .map(|k| format!("\"{k}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
    Ok(())
}

fn parse_curve(obj: &Map<String, Value>) -> Result<Model> {
    check_fields(obj, "bezier_curve", &["points", "weights", "error"])?;
    let points = obj
        .get("points")
        .ok_or_else(|| anyhow!("missing field \"points\" of a bezier_curve"))?;
    let points = point_list(points, "points")?;
    if points.is_empty() {
        bail!("\"points\" is empty: a curve needs at least one control point");
    }
    check_same_dim(&points, |k| format!("points[{k}]"))?;
    match obj.get("weights") {
        None | Some(Value::Null) => Ok(Model::Curve(BezierCurve::new(points)?)),
        Some(w) => {
            let arr = w.as_array().ok_or_else(|| {
                anyhow!("\"weights\" must be an array of numbers, found {}", kind(w))
            })?;
            let weights = arr
                .iter()
                .enumerate()
                .map(|(k, x)| number(x, &format!("weights[{k}]")))
                .collect::<Result<Vec<_>>>()?;
            if weights.len() != points.len() {
                bail!(
                    "{} weights for {} control points (give one weight per point)",
                    weights.len(),
                    points.len()
                );
            }
            Ok(Model::Rational(RationalBezierCurve::new(points, weights)?))
        }
    }
}

fn parse_surface(obj: &Map<String, Value>) -> Result<Model> {
    check_fields(obj, "bezier_surface", &["net"])?;
    let net = field(obj, "net", "bezier_surface")?;
    let (rows, cols, dim, flat) = net_points(net)?;
    Ok(Model::Surface(BezierSurface::from_flat(
        rows, cols, dim, flat,
    )?))
}

/// A control net: rows of points of one dimension, as (rows, cols, dim, row-major points).
fn net_points(net: &Value) -> Result<(usize, usize, usize, Vec<f64>)> {
    let rows = net.as_array().ok_or_else(|| {
        anyhow!(
            "\"net\" must be an array of rows of points, found {}",
            kind(net)
        )
    })?;
    if rows.is_empty() {
        bail!("\"net\" is empty: a surface needs at least one row of control points");
    }
    let rows = rows
        .iter()
        .enumerate()
        .map(|(i, row)| point_list(row, &format!("net[{i}]")))
        .collect::<Result<Vec<_>>>()?;
    let cols = rows[0].len();
    if cols == 0 {
        bail!("net[0] is empty: every row needs at least one control point");
    }
    for (i, row) in rows.iter().enumerate() {
        if row.len() != cols {
            bail!(
                "ragged net: row {i} has {} but row 0 has {cols} (every row of \"net\" needs \
                 the same number of points)",
                count(row.len(), "point")
            );
        }
    }
    let dim = rows[0][0].len();
    let mut flat = Vec::with_capacity(rows.len() * cols * dim);
    for (i, row) in rows.iter().enumerate() {
        for (j, p) in row.iter().enumerate() {
            if p.len() != dim {
                bail!(
                    "net[{i}][{j}] has {} but net[0][0] has {dim}",
                    count(p.len(), "coordinate")
                );
            }
            flat.extend_from_slice(p);
        }
    }
    Ok((rows.len(), cols, dim, flat))
}

/// An array of points (arrays of finite numbers) at `place`.
fn point_list(value: &Value, place: &str) -> Result<Vec<Vec<f64>>> {
    let arr = value.as_array().ok_or_else(|| {
        anyhow!(
            "\"{place}\" must be an array of points, found {}",
            kind(value)
        )
    })?;
    arr.iter()
        .enumerate()
        .map(|(k, p)| {
            let here = format!("{place}[{k}]");
            let coords = p.as_array().ok_or_else(|| {
                anyhow!(
                    "{here} must be an array of coordinates like [x, y], found {}",
                    kind(p)
                )
            })?;
            if coords.is_empty() {
                bail!("{here} has no coordinates");
            }
            coords
                .iter()
                .enumerate()
                .map(|(c, x)| number(x, &format!("{here}[{c}]")))
                .collect()
        })
        .collect()
}

fn check_same_dim(points: &[Vec<f64>], name: impl Fn(usize) -> String) -> Result<()> {
    let dim = points[0].len();
    for (k, p) in points.iter().enumerate() {
        if p.len() != dim {
            bail!(
                "{} has {} but {} has {dim}",
                name(k),
                count(p.len(), "coordinate"),
                name(0)
            );
        }
    }
    Ok(())
}

/// A finite number at `place`.
fn number(value: &Value, place: &str) -> Result<f64> {
    match value {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            _ => bail!("{place} is {n}, which is not a finite f64"),
        },
        Value::String(s) => bail!(
            "{place} is the string {}; coordinates and weights must be finite JSON numbers",
            Value::String(s.clone())
        ),
        other => bail!("{place} must be a finite number, found {}", kind(other)),
    }
}

/// "1 point", "3 points".
fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

fn kind(value: &Value) -> String {
    match value {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("the boolean {b}"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("the string {}", Value::String(s.clone())),
        Value::Array(a) if a.is_empty() => "an empty array".into(),
        Value::Array(_) => "an array".into(),
        Value::Object(_) => "an object".into(),
    }
}

/// One number as JSON (shortest representation that reads back to the same f64).
pub fn json_number(x: f64) -> String {
    serde_json::to_string(&x).unwrap_or_else(|_| "null".into())
}

fn json_point(p: &[f64]) -> String {
    let coords: Vec<String> = p.iter().map(|&x| json_number(x)).collect();
    format!("[{}]", coords.join(", "))
}

/// The model as JSON text, one control point per line (readable and diff-friendly), with an
/// optional `"error"` object for approximate reductions. Ends with a newline.
pub fn to_json(model: &Model, error: Option<&ErrorReport>) -> String {
    let mut s = String::from("{\n");
    match model {
        Model::Curve(c) => {
            s.push_str("  \"type\": \"bezier_curve\",\n");
            push_points(&mut s, &c.points());
        }
        Model::Rational(r) => {
            s.push_str("  \"type\": \"bezier_curve\",\n");
            push_points(&mut s, &r.points());
            s.push_str(",\n  \"weights\": ");
            s.push_str(&json_point(&r.weights()));
        }
        Model::Surface(surface) => {
            s.push_str("  \"type\": \"bezier_surface\",\n  \"net\": [\n");
            let net = surface.net();
            for (i, row) in net.iter().enumerate() {
                let pts: Vec<String> = row.iter().map(|p| json_point(p)).collect();
                let _ = write!(s, "    [{}]", pts.join(", "));
                s.push_str(if i + 1 < net.len() { ",\n" } else { "\n" });
            }
            s.push_str("  ]");
        }
    }
    if let Some(e) = error {
        let _ = write!(
            s,
            ",\n  \"error\": {{\"l2\": {}, \"linf_bound\": {}}}",
            json_number(e.l2),
            json_number(e.linf_bound)
        );
    }
    s.push_str("\n}\n");
    s
}

fn push_points(s: &mut String, points: &[Vec<f64>]) {
    s.push_str("  \"points\": [\n");
    for (k, p) in points.iter().enumerate() {
        s.push_str("    ");
        s.push_str(&json_point(p));
        s.push_str(if k + 1 < points.len() { ",\n" } else { "\n" });
    }
    s.push_str("  ]");
}

fn write_numbers(w: &mut dyn Write, values: &[f64]) -> io::Result<()> {
    w.write_all(b"[")?;
    for (k, &x) in values.iter().enumerate() {
        if k > 0 {
            w.write_all(b", ")?;
        }
        w.write_all(json_number(x).as_bytes())?;
    }
    w.write_all(b"]")
}

fn write_point_rows(w: &mut dyn Write, flat: &[f64], dim: usize, indent: &str) -> io::Result<()> {
    let n = flat.len() / dim;
    for (k, p) in flat.chunks_exact(dim).enumerate() {
        w.write_all(indent.as_bytes())?;
        write_numbers(w, p)?;
        w.write_all(if k + 1 < n { b",\n" } else { b"\n" })?;
    }
    Ok(())
}

/// Writes a B-spline curve as JSON (one control point per line), with the parameters of its
/// reference points if given.
pub fn write_bspline_curve_json(
    w: &mut dyn Write,
    curve: &BsplineCurve,
    parameters: Option<&[f64]>,
) -> io::Result<()> {
    write!(
        w,
        "{{\n  \"type\": \"bspline_curve\",\n  \"degree\": {},\n  \"knots\": ",
        curve.degree()
    )?;
    write_numbers(w, curve.knots())?;
    w.write_all(b",\n  \"control_points\": [\n")?;
    write_point_rows(w, curve.control_flat(), curve.dim(), "    ")?;
    w.write_all(b"  ]")?;
    if let Some(t) = parameters {
        w.write_all(b",\n  \"parameters\": ")?;
        write_numbers(w, t)?;
    }
    w.write_all(b"\n}\n")
}

/// Writes a B-spline surface as JSON (one net row per line), with the grid parameters of its
/// reference points if given.
pub fn write_bspline_surface_json(
    w: &mut dyn Write,
    surface: &BsplineSurface,
    parameters: Option<(&[f64], &[f64])>,
) -> io::Result<()> {
    let (p, q) = surface.degrees();
    let (ku, kv) = surface.knots();
    let (rows, cols) = surface.net_size();
    let d = surface.dim();
    write!(
        w,
        "{{\n  \"type\": \"bspline_surface\",\n  \"degree\": [{p}, {q}],\n  \"knots_u\": "
    )?;
    write_numbers(w, ku)?;
    w.write_all(b",\n  \"knots_v\": ")?;
    write_numbers(w, kv)?;
    w.write_all(b",\n  \"net\": [\n")?;
    for (i, row) in surface.control_flat().chunks_exact(cols * d).enumerate() {
        w.write_all(b"    [")?;
        for (j, pt) in row.chunks_exact(d).enumerate() {
            if j > 0 {
                w.write_all(b", ")?;
            }
            write_numbers(w, pt)?;
        }
        w.write_all(if i + 1 < rows { b"],\n" } else { b"]\n" })?;
    }
    w.write_all(b"  ]")?;
    if let Some((u, v)) = parameters {
        w.write_all(b",\n  \"parameters_u\": ")?;
        write_numbers(w, u)?;
        w.write_all(b",\n  \"parameters_v\": ")?;
        write_numbers(w, v)?;
    }
    w.write_all(b"\n}\n")
}

/// [`write_bspline_curve_json`] into a string.
pub fn bspline_curve_json(curve: &BsplineCurve, parameters: Option<&[f64]>) -> String {
    let mut out = Vec::new();
    let _ = write_bspline_curve_json(&mut out, curve, parameters);
    String::from_utf8_lossy(&out).into_owned()
}

/// [`write_bspline_surface_json`] into a string.
pub fn bspline_surface_json(
    surface: &BsplineSurface,
    parameters: Option<(&[f64], &[f64])>,
) -> String {
    let mut out = Vec::new();
    let _ = write_bspline_surface_json(&mut out, surface, parameters);
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        format!("{:#}", parse_model(text).unwrap_err())
    }

    #[test]
    fn reads_all_three_kinds() {
        let c = parse_model(r#"{"type":"bezier_curve","points":[[0,0],[1,2],[3,1]]}"#).unwrap();
        assert!(matches!(c, Model::Curve(ref c) if c.degree() == 2));
        let r =
            parse_model(r#"{"type":"bezier_curve","points":[[0],[1]],"weights":[1,2]}"#).unwrap();
        assert!(matches!(r, Model::Rational(_)));
        let s =
            parse_model(r#"{"type":"bezier_surface","net":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#)
                .unwrap();
        assert!(matches!(s, Model::Surface(ref s) if s.degrees() == (1, 1)));
    }

    #[test]
    fn round_trips_through_json() {
        for text in [
            r#"{"type":"bezier_curve","points":[[0.1,0],[1,2e-30],[3,1e300]]}"#,
            r#"{"type":"bezier_curve","points":[[0],[1]],"weights":[1,0.7]}"#,
            r#"{"type":"bezier_surface","net":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#,
        ] {
            let m = parse_model(text).unwrap();
            assert_eq!(parse_model(&to_json(&m, None)).unwrap(), m);
        }
        let m = parse_model(r#"{"type":"bezier_curve","points":[[1,2]]}"#).unwrap();
        let e = ErrorReport {
            l2: 0.5,
            linf_bound: 1.25,
        };
        let text = to_json(&m, Some(&e));
        let v: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["error"]["linf_bound"], 1.25);
        assert_eq!(parse_model(&text).unwrap(), m);
    }

    #[test]
    fn bspline_models_round_trip() {
        let curve = BsplineCurve::new(
            3,
            vec![-3.0, -2.0, -1.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0],
            vec![
                vec![0.0, 1.0],
                vec![1.0, 2.5],
                vec![2.0, 0.1],
                vec![3.0, 1e-300],
                vec![4.0, 7.0],
            ],
        )
        .unwrap();
        let text = bspline_curve_json(&curve, Some(&[0.0, 0.5, 1.0]));
        let back = parse_any_model(&text).unwrap();
        assert_eq!(
            back,
            AnyModel::BsplineCurve(BsplineCurveModel {
                curve: curve.clone(),
                parameters: Some(vec![0.0, 0.5, 1.0])
            })
        );
        let knots: Vec<f64> = (0..8).map(|k| k as f64 - 3.0).collect();
        let net: Vec<f64> = (0..16).map(|k| (k * k) as f64 * 0.25).collect();
        let s = BsplineSurface::from_flat((3, 3), knots.clone(), knots, 4, 4, 1, net).unwrap();
        let text = bspline_surface_json(&s, None);
        assert!(text.contains("[[0.0], [0.25], [1.0], [2.25]]"), "{text}");
        match parse_any_model(&text).unwrap() {
            AnyModel::BsplineSurface(m) => assert_eq!(m.surface, s),
            other => panic!("{other:?}"),
        }
        let e = format!("{:#}", parse_model(&text).unwrap_err());
        assert!(
            e.contains("B-spline surface") && e.contains("geomkit eval"),
            "{e}"
        );
    }

    #[test]
    fn bspline_errors_name_the_place() {
        let e = |t: &str| format!("{:#}", parse_any_model(t).unwrap_err());
        assert!(
            e(r#"{"type":"bspline_curve","degree":0,"knots":[],"control_points":[[0]]}"#)
                .contains("\"degree\" must be an integer from 1 to 7")
        );
        assert!(
            e(r#"{"type":"bspline_curve","degree":1,"knots":[0,"a"],"control_points":[[0]]}"#)
                .contains("knots[1] is the string \"a\"")
        );
        assert!(e(
            r#"{"type":"bspline_curve","degree":1,"knots":[0,1,2],"control_points":[[0],[1]]}"#
        )
        .contains("invalid knot vector"));
        assert!(
            e(r#"{"type":"bspline_curve","degree":1,"knots":[0,1,2,3]}"#)
                .contains("missing field \"control_points\"")
        );
        assert!(
            e(r#"{"type":"bspline_surface","degree":3,"knots_u":[],"knots_v":[],"net":[]}"#)
                .contains("pair [p, q]")
        );
    }

    #[test]
    fn clear_messages_for_bad_input() {
        assert!(err(r#"{"type":"bezier_curve","points":[[0,0],[1,"NaN"]]}"#)
            .contains("points[1][1] is the string \"NaN\""));
        assert!(
            err(r#"{"type":"bezier_curve","points":[[0,1e999]]}"#).contains("number out of range")
        );
        assert!(err(r#"{"type":"bezier_curve","points":[]}"#).contains("\"points\" is empty"));
        assert!(err(r#"{"type":"bezier_curve"}"#).contains("missing field \"points\""));
        assert!(err(r#"{"type":"circle"}"#).contains("unknown type \"circle\""));
        assert!(err(r#"{"points":[]}"#).contains("missing field \"type\""));
        assert!(err(r#"[1,2]"#).contains("expected a JSON object"));
        assert!(err(r#"{"type":"bezier_curve","points":[[0,0],[1]]}"#)
            .contains("points[1] has 1 coordinate but points[0] has 2"));
        assert!(
            err(r#"{"type":"bezier_curve","points":[[0,0]],"weight":[1]}"#)
                .contains("unknown field \"weight\"")
        );
        assert!(
            err(r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1]}"#)
                .contains("1 weights for 2 control points")
        );
        assert!(
            err(r#"{"type":"bezier_curve","points":[[0,0],[1,1]],"weights":[1,-1]}"#)
                .contains("weight 1 is -1")
        );
        assert!(
            err(r#"{"type":"bezier_surface","net":[[[0,0,0],[1,0,0]],[[0,1,0]]]}"#)
                .contains("ragged net: row 1 has 1 point but row 0 has 2")
        );
        assert!(err(r#"{"type":"bezier_surface","net":[]}"#).contains("\"net\" is empty"));
        assert!(err(r#"{"type":"bezier_surface","net":[[]]}"#).contains("net[0] is empty"));
        assert!(err("{").contains("invalid JSON"));
    }
}
