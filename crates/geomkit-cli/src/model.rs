//! File formats of the CLI: Bézier curves and surfaces as JSON.
//!
//! - `{"type":"bezier_curve","points":[[x,y],...],"weights":[...]}`: a curve in any dimension;
//!   with `weights` (one per point, > 0) a rational curve. An `"error"` object (written by an
//!   approximate reduction) is accepted and ignored on reading.
//! - `{"type":"bezier_surface","net":[[[x,y,z],...],...]}`: a tensor-product surface, `net[i][j]`
//!   the control point u_ij (row i along u, column j along v).
//!
//! Reading validates everything and names the place of the first problem (`points[2][1] is the
//! string "NaN"`); the library then checks what is geometry (weights > 0, ...).

use anyhow::{anyhow, bail, Context, Result};
use geomkit::bezier::{BezierCurve, BezierSurface, ParamCurve, RationalBezierCurve};
use serde_json::{Map, Value};
use std::fmt::Write as _;
use std::path::Path;

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
                ParamCurve::dim(r),
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

/// Reads a model from a JSON file; errors name the file and the place of the problem.
pub fn read_model(path: &Path) -> Result<Model> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    parse_model(&text).with_context(|| path.display().to_string())
}

/// Parses a model from JSON text.
pub fn parse_model(text: &str) -> Result<Model> {
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
        None => bail!("missing field \"type\" (\"bezier_curve\" or \"bezier_surface\")"),
        Some(Value::String(s)) => s.as_str(),
        Some(other) => bail!("\"type\" must be a string, found {}", kind(other)),
    };
    match ty {
        "bezier_curve" => parse_curve(obj),
        "bezier_surface" => parse_surface(obj),
        other => bail!(
            "unknown type {}: expected \"bezier_curve\" or \"bezier_surface\"",
            Value::String(other.to_string())
        ),
    }
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
    let net = obj
        .get("net")
        .ok_or_else(|| anyhow!("missing field \"net\" of a bezier_surface"))?;
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
    let flat: Vec<(usize, usize, &Vec<f64>)> = rows
        .iter()
        .enumerate()
        .flat_map(|(i, row)| row.iter().enumerate().map(move |(j, p)| (i, j, p)))
        .collect();
    let dim = rows[0][0].len();
    for (i, j, p) in flat {
        if p.len() != dim {
            bail!(
                "net[{i}][{j}] has {} but net[0][0] has {dim}",
                count(p.len(), "coordinate")
            );
        }
    }
    Ok(Model::Surface(BezierSurface::new(rows)?))
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
