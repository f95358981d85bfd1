//! The schema of every file the geomkit tools read or write: one struct per `"type"`, derived
//! with serde, unknown fields rejected. [`ModelFile`] is any of them.
//!
//! Every file is a JSON object whose `"type"` names its kind. An optional `"version"` (an
//! integer, default 1) names the format version; this reader reads version
//! [`FORMAT_VERSION`] and refuses a higher one with a message saying so. Writers omit it while
//! it is 1, so the files of every earlier geomkit read unchanged; a change of any format
//! that an older reader would misread bumps [`FORMAT_VERSION`].
//!
//! The formats, with an example of each, are documented in `docs/formats.md` of the
//! repository; that page's examples are read by this crate's tests.

use crate::numbers::{self, Net, Points};
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, DeserializeSeed, IntoDeserializer, MapAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// The version of the file formats this crate reads and writes.
pub const FORMAT_VERSION: u32 = 1;

/// `{"type": "bezier_curve", "points": [[x, y], ...], "weights": [...]}`: a Bézier curve in
/// any dimension; with `weights` (one per point, > 0) a rational curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BezierCurveFile {
    /// Control points P_0 .. P_n.
    pub points: Points,
    /// Weights w_0 .. w_n of a rational curve.
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub weights: Option<Vec<f64>>,
    /// The error report of an approximate reduction (`bezier reduce --approx`); read and
    /// kept, not used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<ReductionError>,
}

/// `"error": {"l2": ..., "linf_bound": ...}` of an approximately reduced curve.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReductionError {
    /// L2(0, 1) distance between the original and the reduced curve.
    #[serde(deserialize_with = "numbers::number")]
    pub l2: f64,
    /// Guaranteed upper bound of the largest distance between them.
    #[serde(deserialize_with = "numbers::number")]
    pub linf_bound: f64,
}

/// `{"type": "bezier_surface", "net": [[[x, y, z], ...], ...], "weights": [[w, ...], ...]}`:
/// a tensor-product Bézier surface, `net[i][j]` the control point u_ij (row i along u, column
/// j along v); with `weights` (optional, the net's shape, each finite and > 0) a rational
/// surface.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BezierSurfaceFile {
    /// The control net.
    pub net: Net,
    /// Weights w_ij of a rational surface, `weights[i][j]` that of `net[i][j]`.
    #[serde(
        default,
        deserialize_with = "numbers::optional_number_rows",
        skip_serializing_if = "Option::is_none"
    )]
    pub weights: Option<Vec<Vec<f64>>>,
}

/// `{"type": "bspline_curve", "degree": 3, "knots": [...], "control_points": [[x, y], ...],
/// "parameters": [...]}`: n control points, n + degree + 1 knots, domain
/// `[knots[degree], knots[n]]`; `parameters` (optional) those of the reference points an
/// interpolating curve passes through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BsplineCurveFile {
    /// The degree, 1 to 7.
    pub degree: usize,
    /// The knot vector.
    #[serde(deserialize_with = "numbers::numbers")]
    pub knots: Vec<f64>,
    /// The control points.
    pub control_points: Points,
    /// Parameters of the reference points.
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub parameters: Option<Vec<f64>>,
}

/// `{"type": "bspline_surface", "degree": [3, 3], "knots_u": [...], "knots_v": [...],
/// "net": [[[x, y, z], ...], ...], "parameters_u": [...], "parameters_v": [...]}`: a
/// tensor-product B-spline surface; a height field z(x, y) has 1-D net points `[z]` and its
/// knots in x (u) and y (v).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BsplineSurfaceFile {
    /// Degrees (p, q) in u and v, each 1 to 7.
    pub degree: [usize; 2],
    /// Knots in u.
    #[serde(deserialize_with = "numbers::numbers")]
    pub knots_u: Vec<f64>,
    /// Knots in v.
    #[serde(deserialize_with = "numbers::numbers")]
    pub knots_v: Vec<f64>,
    /// The control net, `net[i][j]` = c_ij.
    pub net: Net,
    /// Grid parameters of the reference points in u (with `parameters_v`).
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub parameters_u: Option<Vec<f64>>,
    /// Grid parameters of the reference points in v (with `parameters_u`).
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub parameters_v: Option<Vec<f64>>,
}

/// A composite surface of patches (formulas (3)-(9) of spec/composite-surfaces.md):
/// `{"type": "composite_surface", "u_knots": [...], "v_knots": [...], "patches": [[P, ...],
/// ...]}`, `patches[i][j]` on the cell [u_i, u_(i+1)] × [v_j, v_(j+1)].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompositeFile {
    /// Knots in u (cell boundaries).
    #[serde(deserialize_with = "numbers::numbers")]
    pub u_knots: Vec<f64>,
    /// Knots in v.
    #[serde(deserialize_with = "numbers::numbers")]
    pub v_knots: Vec<f64>,
    /// One patch per cell, rows along u.
    pub patches: Vec<Vec<Patch>>,
}

/// An explicit composite surface z(x, y) (formulas (10)-(11)): `{"type":
/// "composite_explicit", "x_knots": [...], "y_knots": [...], "patches": [...]}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitFile {
    /// Knots in x.
    #[serde(deserialize_with = "numbers::numbers")]
    pub x_knots: Vec<f64>,
    /// Knots in y.
    #[serde(deserialize_with = "numbers::numbers")]
    pub y_knots: Vec<f64>,
    /// One patch per cell: 1-D Bézier nets, or formulas in x, y.
    pub patches: Vec<Vec<Patch>>,
}

/// A patch of a composite scene.
///
/// - `{"bezier": [[[x, y, z], ...], ...]}`: a Bézier net (1-D points `[z]` in an explicit
///   scene), its [0, 1]² mapped onto the cell;
/// - `{"x": "..", "y": "..", "z": "..", "domain": [[u0, u1], [v0, v1]]}`: formulas in u, v
///   (`z` optional; `domain` optional, mapped linearly onto the cell);
/// - in an explicit scene, `"formula in x, y"` or `{"z": "..", "domain": ...}`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Patch {
    /// A formula z(x, y) of an explicit scene.
    Formula(String),
    /// A Bézier net or formulas per coordinate.
    Object(PatchObject),
}

/// The object form of a [`Patch`].
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatchObject {
    /// A Bézier net.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bezier: Option<Net>,
    /// x as a formula in u, v.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<String>,
    /// y as a formula in u, v.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<String>,
    /// z as a formula (in u, v; in x, y for an explicit scene).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<String>,
    /// The formulas' own domain, mapped linearly onto the cell.
    #[serde(
        default,
        deserialize_with = "numbers::optional_intervals",
        skip_serializing_if = "Option::is_none"
    )]
    pub domain: Option<Vec<[f64; 2]>>,
}

/// A string or an object: the two forms of a patch or a piece.
fn string_or_object<'de, D, T, O>(
    d: D,
    string: fn(String) -> T,
    object: fn(O) -> T,
    expecting: &'static str,
) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    O: Deserialize<'de>,
{
    struct V<T, O> {
        string: fn(String) -> T,
        object: fn(O) -> T,
        expecting: &'static str,
    }
    impl<'de, T, O: Deserialize<'de>> Visitor<'de> for V<T, O> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(self.expecting)
        }
        fn visit_str<E: de::Error>(self, s: &str) -> Result<T, E> {
            Ok((self.string)(s.to_string()))
        }
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
            O::deserialize(MapAccessDeserializer::new(map)).map(self.object)
        }
    }
    d.deserialize_any(V {
        string,
        object,
        expecting,
    })
}

impl<'de> Deserialize<'de> for Patch {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Patch, D::Error> {
        string_or_object(
            d,
            Patch::Formula,
            Patch::Object,
            "a patch: {\"bezier\": net}, {\"x\": \"..\", \"y\": \"..\", \"z\": \"..\"} or a \
             formula in x, y",
        )
    }
}

/// A piecewise-ruled surface (formula (2)): `{"type": "ruled", "curves": [C, ...], "v":
/// [...], "u": [u0, u1]}`, curve k at `v[k]`; `u` defaults to [0, 1].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RuledFile {
    /// Parameter range every curve is mapped onto.
    #[serde(
        default,
        deserialize_with = "deserialize_optional_interval",
        skip_serializing_if = "Option::is_none"
    )]
    pub u: Option<[f64; 2]>,
    /// v of every curve, increasing.
    #[serde(deserialize_with = "numbers::numbers")]
    pub v: Vec<f64>,
    /// The curves.
    pub curves: Vec<RuledCurveFile>,
}

fn deserialize_optional_interval<'de, D: Deserializer<'de>>(
    d: D,
) -> Result<Option<[f64; 2]>, D::Error> {
    numbers::interval(d).map(Some)
}

/// One curve of a ruled surface: exactly one of `point`, `polygon`, `polyline`, `circle`,
/// or formulas `x`, `y`, `z` in t with their interval `t`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RuledCurveFile {
    /// A point `[x, y, z]` (an apex or a pole).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point: Option<Points3>,
    /// A closed polygon.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon: Option<Vec<Points3>>,
    /// An open polyline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polyline: Option<Vec<Points3>>,
    /// A circle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<Circle>,
    /// x(t).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<String>,
    /// y(t).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<String>,
    /// z(t), default "0".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<String>,
    /// [t0, t1] of the formulas.
    #[serde(
        default,
        deserialize_with = "deserialize_optional_interval",
        skip_serializing_if = "Option::is_none"
    )]
    pub t: Option<[f64; 2]>,
}

/// A point `[x, y, z]` of finite numbers.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
#[serde(transparent)]
pub struct Points3(pub [f64; 3]);

impl<'de> Deserialize<'de> for Points3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Points3, D::Error> {
        let v = numbers::numbers(d)?;
        match v[..] {
            [x, y, z] => Ok(Points3([x, y, z])),
            _ => Err(de::Error::custom(format!(
                "has {} but a point here is [x, y, z]",
                numbers::count(v.len(), "coordinate")
            ))),
        }
    }
}

/// `{"center": [x, y, z], "radius": r}`: a circle in a plane z = const.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Circle {
    /// Centre.
    pub center: Points3,
    /// Radius.
    #[serde(deserialize_with = "numbers::number")]
    pub radius: f64,
}

/// A piecewise function or composite curve (spec/composite-surfaces.md §5):
/// `{"type": "piecewise", "knots": [x0, ..., xn], "pieces": ["f0(x)", ...]}` for a
/// function, or pieces `{"x": "..", "y": "..", "z": "..", "domain": [t0, t1]}` in t for a
/// curve (`z`, `domain` optional).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PiecewiseFile {
    /// Breakpoints.
    #[serde(deserialize_with = "numbers::numbers")]
    pub knots: Vec<f64>,
    /// One piece per interval.
    pub pieces: Vec<Piece>,
}

/// A piece of a [`PiecewiseFile`].
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Piece {
    /// f(x) of a function.
    Function(String),
    /// Coordinates in t of a curve.
    Curve(CurvePiece),
}

impl<'de> Deserialize<'de> for Piece {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Piece, D::Error> {
        string_or_object(
            d,
            Piece::Function,
            Piece::Curve,
            "a formula in x, or {\"x\": \"..\", \"y\": \"..\"} in t",
        )
    }
}

/// A curve piece: formulas in t and their own domain (default: the knot interval).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurvePiece {
    /// x(t).
    pub x: String,
    /// y(t).
    pub y: String,
    /// z(t), for curves in space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<String>,
    /// [t0, t1], mapped onto the knot interval.
    #[serde(
        default,
        deserialize_with = "deserialize_optional_interval",
        skip_serializing_if = "Option::is_none"
    )]
    pub domain: Option<[f64; 2]>,
}

/// `{"type": "polyline" | "polygon", "points": [[x, y], ...], "knots": [...]}`: a polyline
/// as a piecewise-linear formula (`knots` default 0, 1, 2, ...; one coordinate per point
/// gives a function).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolylineFile {
    /// The vertices.
    pub points: Points,
    /// The parameter of each vertex.
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub knots: Option<Vec<f64>>,
}

/// A formula file (`geomkit compose ... -o OUT.json`): the formula printed in every syntax,
/// and the model it was made from (which `eval`, `mesh` and `render` read back).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FormulaFile {
    /// What the formula describes ("the paper's cube (±1, ±1, ±1)").
    pub what: String,
    /// Its variables ("u", "v").
    pub variables: Vec<String>,
    /// Its coordinates ("x", "y", "z").
    pub coordinates: Vec<String>,
    /// Operations of its DAG.
    pub op_count: usize,
    /// The formula in each syntax, by the syntax's name ("maple", "latex", ...).
    pub formulas: BTreeMap<String, String>,
    /// The continuity report of a composite surface or piecewise formula (free-form).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuity: Option<serde_json::Value>,
    /// The model the formula was made from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<Box<ModelFile>>,
}

/// A point-calculus model (`geomkit pointcalc fit`): `{"type": "pointcalc-model",
/// "factors": [{"name": "temp", "nodes": [...], "exact": ["1/3", ...]}, ...], "response":
/// ["yield"], "values": [...]}`, values row-major over the factors (first factor slowest),
/// one number per response.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointcalcModelFile {
    /// The factors and their levels.
    pub factors: Vec<FactorFile>,
    /// Names of the responses.
    pub response: Vec<String>,
    /// Response values at the grid of levels.
    #[serde(deserialize_with = "numbers::numbers")]
    pub values: Vec<f64>,
}

/// A factor of a [`PointcalcModelFile`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FactorFile {
    /// Its name.
    pub name: String,
    /// Its levels (nodes).
    #[serde(deserialize_with = "numbers::numbers")]
    pub nodes: Vec<f64>,
    /// The levels as exact rationals ("1/3"), when they are.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact: Option<Vec<String>>,
}

/// Samples of a point-equation curve (`geomkit pointcalc curve -o X.json`):
/// `{"type": "pointcalc-curve", "nodes": [...], "lebesgue": L, "samples": [[t, x, ...],
/// ...]}`, read back as the polyline through the samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSamplesFile {
    /// Nodes of the equation.
    #[serde(
        default,
        deserialize_with = "numbers::optional_numbers",
        skip_serializing_if = "Option::is_none"
    )]
    pub nodes: Option<Vec<f64>>,
    /// Lebesgue constant of the nodes.
    #[serde(
        default,
        deserialize_with = "optional_number",
        skip_serializing_if = "Option::is_none"
    )]
    pub lebesgue: Option<f64>,
    /// Rows [t, x, y, ...], t increasing.
    pub samples: Points,
}

fn optional_number<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    numbers::number(d).map(Some)
}

/// Samples of a point-equation surface (`geomkit pointcalc surface -o X.json`):
/// `{"type": "pointcalc-surface-samples", "u": [...], "v": [...], "points": [...]}`, point
/// (a, b) at `points[a * v.len() + b]`; read back as bilinear cells.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSamplesFile {
    /// Increasing u of the grid.
    #[serde(deserialize_with = "numbers::numbers")]
    pub u: Vec<f64>,
    /// Increasing v of the grid.
    #[serde(deserialize_with = "numbers::numbers")]
    pub v: Vec<f64>,
    /// The points, row-major.
    pub points: Points,
}

macro_rules! model_files {
    ($( $(#[$doc:meta])* $tag:literal => $variant:ident($file:ty), )*) => {
        /// Any file of the geomkit tools, by its `"type"`.
        #[derive(Debug, Clone, PartialEq, Serialize)]
        #[serde(tag = "type")]
        #[allow(clippy::large_enum_variant)]
        pub enum ModelFile {
            $( $(#[$doc])* #[serde(rename = $tag)] $variant($file), )*
        }

        /// Every `"type"` a file can have.
        pub const TYPES: &[&str] = &[$($tag),*];

        impl ModelFile {
            /// The file's `"type"`.
            pub fn type_name(&self) -> &'static str {
                match self { $( ModelFile::$variant(_) => $tag, )* }
            }

            /// Reads the rest of an object whose `"type"` is `tag`.
            fn read_variant<'de, A: MapAccess<'de>>(tag: &str, map: A) -> Result<ModelFile, A::Error> {
                let d = MapAccessDeserializer::new(VersionFilter(map));
                match tag {
                    $( $tag => <$file>::deserialize(d).map(ModelFile::$variant), )*
                    other => Err(de::Error::custom(unknown_type(other))),
                }
            }
        }
    };
}

model_files! {
    /// A Bézier curve (rational with weights).
    "bezier_curve" => BezierCurve(BezierCurveFile),
    /// A Bézier surface.
    "bezier_surface" => BezierSurface(BezierSurfaceFile),
    /// A B-spline curve.
    "bspline_curve" => BsplineCurve(BsplineCurveFile),
    /// A B-spline surface.
    "bspline_surface" => BsplineSurface(BsplineSurfaceFile),
    /// A composite parametric surface of patches.
    "composite_surface" => CompositeSurface(CompositeFile),
    /// An explicit composite surface z(x, y).
    "composite_explicit" => CompositeExplicit(ExplicitFile),
    /// A piecewise-ruled surface.
    "ruled" => Ruled(RuledFile),
    /// A piecewise function or composite curve.
    "piecewise" => Piecewise(PiecewiseFile),
    /// An open polyline as a piecewise formula.
    "polyline" => Polyline(PolylineFile),
    /// A closed polygon as a piecewise formula.
    "polygon" => Polygon(PolylineFile),
    /// A formula file with its model.
    "formula" => Formula(FormulaFile),
    /// A point-calculus k-factor model.
    "pointcalc-model" => PointcalcModel(PointcalcModelFile),
    /// Samples of a point-equation curve.
    "pointcalc-curve" => PointcalcCurve(CurveSamplesFile),
    /// Samples of a point-equation surface.
    "pointcalc-surface-samples" => PointcalcSurfaceSamples(SurfaceSamplesFile),
}

fn unknown_type(tag: &str) -> String {
    format!(
        "unknown type {}: expected {}",
        serde_json::Value::String(tag.to_string()),
        TYPES
            .iter()
            .map(|t| format!("\"{t}\""))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// A map whose `"version"` entries are checked and skipped.
struct VersionFilter<A>(A);

impl<'de, A: MapAccess<'de>> MapAccess<'de> for VersionFilter<A> {
    type Error = A::Error;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, A::Error> {
        loop {
            let Some(key) = self.0.next_key::<String>()? else {
                return Ok(None);
            };
            if key == "version" {
                check_version(self.0.next_value()?)?;
                continue;
            }
            return seed.deserialize(key.into_deserializer()).map(Some);
        }
    }
    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, A::Error> {
        self.0.next_value_seed(seed)
    }
}

fn check_version<E: de::Error>(version: u32) -> Result<(), E> {
    match version {
        0 => Err(E::custom("\"version\" starts at 1")),
        v if v > FORMAT_VERSION => Err(E::custom(format!(
            "this file has format version {v}, written by a newer geomkit; this one reads \
             version {FORMAT_VERSION}"
        ))),
        _ => Ok(()),
    }
}

impl<'de> Deserialize<'de> for ModelFile {
    /// Reads `"type"` first and then the fields of that type straight from the reader, so
    /// errors keep their JSON path and line; a file whose `"type"` is not its first field
    /// is buffered once.
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<ModelFile, D::Error> {
        d.deserialize_map(ModelFileVisitor)
    }
}

struct ModelFileVisitor;

impl<'de> Visitor<'de> for ModelFileVisitor {
    type Value = ModelFile;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON object with a \"type\" field")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ModelFile, A::Error> {
        let Some(first) = map.next_key::<String>()? else {
            return Err(de::Error::custom(missing_type()));
        };
        if first == "type" {
            let tag: String = map.next_value()?;
            return ModelFile::read_variant(&tag, map);
        }
        // "type" later: buffer the object once and read it from the buffer.
        let mut object = serde_json::Map::new();
        object.insert(first, map.next_value()?);
        while let Some((k, v)) = map.next_entry::<String, serde_json::Value>()? {
            object.insert(k, v);
        }
        let tag = match object.remove("type") {
            Some(serde_json::Value::String(tag)) => tag,
            Some(other) => {
                return Err(de::Error::custom(format!(
                    "\"type\" must be a string, found {other}"
                )))
            }
            None => return Err(de::Error::custom(missing_type())),
        };
        let rest = serde_json::Value::Object(object);
        let mut track = serde_path_to_error::Track::new();
        let tracked = serde_path_to_error::Deserializer::new(rest.into_deserializer(), &mut track);
        tracked.deserialize_map(TaggedVisitor(&tag)).map_err(|e| {
            let path = track.path().to_string();
            let msg = e.to_string();
            de::Error::custom(if path == "." {
                msg
            } else {
                format!("{path}: {msg}")
            })
        })
    }
}

/// Reads the fields of the type `.0` (the buffered path of [`ModelFileVisitor`]).
struct TaggedVisitor<'a>(&'a str);

impl<'de> Visitor<'de> for TaggedVisitor<'_> {
    type Value = ModelFile;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON object")
    }
    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<ModelFile, A::Error> {
        ModelFile::read_variant(self.0, map)
    }
}

fn missing_type() -> String {
    format!(
        "missing field \"type\" ({})",
        TYPES
            .iter()
            .map(|t| format!("\"{t}\""))
            .collect::<Vec<_>>()
            .join(", ")
    )
}
