//! The reader: the B-spline and Bézier curves and surfaces of an exchange structure (and
//! plane faces bounded by straight edges) as model files.

use super::nurbs::{cross, dot, expand_knots};
use super::part21::{parse, Exchange, Instance, Param};
use super::split;
use super::{StepError, StepResult};
use crate::numbers::{Net, Points};
use crate::schema::{
    BezierCurveFile, BezierSurfaceFile, BsplineCurveFile, BsplineSurfaceFile, ModelFile,
};
use crate::AnyModel;
use std::collections::{BTreeMap, BTreeSet};

/// One model read from a STEP file.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Imported {
    /// The entity number (`#123`) of the curve, surface or face it was read from.
    pub id: u64,
    /// The entity's type (`B_SPLINE_SURFACE_WITH_KNOTS`, a complex instance's records
    /// joined by `+`).
    pub entity: String,
    /// The entity's name in the file (may be empty).
    pub name: String,
    /// The model file (checked: [`AnyModel::from_file`] accepts it).
    pub file: ModelFile,
    /// What changed on the way, if anything (a reparametrization, a trimming not kept).
    pub note: Option<String>,
    /// For a piece of a rational B-spline of several spans (imported as rational Bézier
    /// pieces): its span, `[k]` along a curve, `[i, j]` of a surface (u, v); empty for a
    /// whole entity.
    pub span: Vec<usize>,
}

/// A face whose boundary is not its surface's own (a trimmed face): its surface is imported
/// whole, the trimming loops are not (model files have no trimming).
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub struct TrimmedFace {
    /// The face's entity number.
    pub face: u64,
    /// The entity number of its surface.
    pub surface: u64,
    /// Its bounds (loops): the outer one and one per hole.
    pub loops: usize,
}

/// What a STEP file held.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct Import {
    /// The models, in the order of their entity numbers.
    pub models: Vec<Imported>,
    /// Entities not imported, counted by reason ("LINE (unsupported)", ...).
    pub skipped: BTreeMap<String, usize>,
    /// The schemas of the file's header.
    pub schemas: Vec<String>,
    /// The file's length unit (`"MILLI METRE"`, `"METRE"`, `"INCH"`, ...), when it names one:
    /// coordinates are imported as written, in that unit.
    pub length_unit: Option<String>,
    /// The trimmed faces whose surfaces were imported (each as its whole surface: the
    /// trimming loops are not kept), in the order of their entity numbers.
    pub trimmed: Vec<TrimmedFace>,
}

impl Import {
    /// The skipped entities in one phrase: "3 LINE (unsupported), 12 edge curves of faces".
    pub fn skipped_summary(&self) -> String {
        let parts: Vec<String> = self
            .skipped
            .iter()
            .map(|(what, n)| format!("{n} {what}"))
            .collect();
        parts.join(", ")
    }
}

/// Curve and surface types a reader may meet that are not imported (counted as skipped).
const OTHER_GEOMETRY: &[&str] = &[
    "LINE",
    "CIRCLE",
    "ELLIPSE",
    "PARABOLA",
    "HYPERBOLA",
    "POLYLINE",
    "TRIMMED_CURVE",
    "COMPOSITE_CURVE",
    "OFFSET_CURVE_3D",
    "UNIFORM_CURVE",
    "QUASI_UNIFORM_CURVE",
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
    "RECTANGULAR_TRIMMED_SURFACE",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
];

/// Reads the curves and surfaces of a STEP file (ISO 10303-21 text of any schema).
///
/// Taken: `B_SPLINE_CURVE_WITH_KNOTS`, `BEZIER_CURVE`, `B_SPLINE_SURFACE_WITH_KNOTS`,
/// `BEZIER_SURFACE` (simple or complex instances; rational ones too: one span as a rational
/// Bézier file, several spans as one rational Bézier file per span, split exactly by knot
/// insertion in homogeneous coordinates ([`Imported::span`] says which; the file's own
/// points and weights wherever a span's knots already have multiplicity p), rational
/// B-splines whose weights are all equal as polynomial ones), and faces on a `PLANE` as the
/// degree-1 patch of the rectangle around their vertices. Faces whose outline is not their
/// surface's boundary (trimmed faces: a vertex off the surface's corners, or holes) are
/// imported as their whole surface and listed in [`Import::trimmed`]. Curves that
/// bound faces are the faces' edges and are not given separately; curves in the plane
/// (parameter-space curves) are skipped. A single clamped span on [0, 1] becomes a Bézier
/// file when the entity says so (`BEZIER_*`, `.PIECEWISE_BEZIER_KNOTS.`) or is rational;
/// other curves and surfaces B-spline files with their knots as written.
///
/// Errors, one line naming the entity (`#12: ...`) or the line: syntax (a truncated file,
/// an unclosed string), a reference to an entity not in the file, a cycle of references, an
/// entity with the wrong number or kind of parameters, knots that do not fit the control
/// points, and a file with no curve or surface to import.
pub fn read(text: &str) -> StepResult<Import> {
    let x = parse(text)?;
    check_references(&x)?;
    let reader = Reader {
        x: &x,
        bounds: face_bounds(&x),
        trimmed: std::cell::RefCell::new(BTreeMap::new()),
    };
    let mut import = Import {
        schemas: x.schemas.clone(),
        length_unit: length_unit(&x),
        ..Import::default()
    };
    for (&id, inst) in &x.instances {
        match reader.instance(id, inst)? {
            Outcome::Model(m) => import.models.push(*m),
            Outcome::Models(ms) => import.models.extend(ms),
            Outcome::Skipped(reason) => *import.skipped.entry(reason).or_insert(0) += 1,
            Outcome::Other => {}
        }
    }
    // Faces with holes are trimmed whatever their outer loop.
    for (&face, inst) in &x.instances {
        let Some(p) = inst.record("ADVANCED_FACE").or(inst.record("FACE_SURFACE")) else {
            continue;
        };
        let (Some(Param::List(bounds)), Some(Param::Ref(surface))) = (p.get(1), p.get(2)) else {
            continue;
        };
        let imported = import
            .models
            .iter()
            .any(|m| m.id == *surface || m.id == face);
        if bounds.len() > 1 && imported {
            reader.trimmed.borrow_mut().insert(face, *surface);
        }
    }
    for (face, surface) in reader.trimmed.take() {
        let inst = &x.instances[&face];
        let p = inst.record("ADVANCED_FACE").or(inst.record("FACE_SURFACE"));
        let loops = match p.and_then(|p| p.get(1)) {
            Some(Param::List(l)) => l.len(),
            _ => 1,
        };
        import.trimmed.push(TrimmedFace {
            face,
            surface,
            loops,
        });
    }
    if import.models.is_empty() {
        let found = if import.skipped.is_empty() {
            "no curve or surface entity".to_string()
        } else {
            import.skipped_summary()
        };
        return Err(StepError::Unsupported(format!(
            "no B-spline or Bézier curve or surface to import (found: {found})"
        )));
    }
    Ok(import)
}

/// The name of the first LENGTH_UNIT: an SI unit with its prefix, or a conversion-based
/// unit's name.
fn length_unit(x: &Exchange) -> Option<String> {
    let unit = x.instances.values().find(|i| i.is("LENGTH_UNIT"))?;
    if let Some(si) = unit.record("SI_UNIT") {
        let word = |p: Option<&Param>| match p {
            Some(Param::Enum(e)) => Some(e.clone()),
            _ => None,
        };
        let name = word(si.get(1))?;
        return Some(match word(si.first()) {
            Some(prefix) => format!("{prefix} {name}"),
            None => name,
        });
    }
    match unit.record("CONVERSION_BASED_UNIT")?.first() {
        Some(Param::Str(s)) => Some(s.to_ascii_uppercase()),
        _ => None,
    }
}

enum Outcome {
    Model(Box<Imported>),
    /// The rational Bézier pieces of one entity.
    Models(Vec<Imported>),
    Skipped(String),
    Other,
}

fn refs_of(p: &Param, out: &mut Vec<u64>) {
    match p {
        Param::Ref(r) => out.push(*r),
        Param::List(l) => l.iter().for_each(|q| refs_of(q, out)),
        Param::Typed(_, q) => refs_of(q, out),
        _ => {}
    }
}

fn instance_refs(inst: &Instance) -> Vec<u64> {
    let mut out = Vec::new();
    for (_, params) in &inst.records {
        params.iter().for_each(|p| refs_of(p, &mut out));
    }
    out
}

/// Every reference names an instance of the file, and no instance reaches itself.
fn check_references(x: &Exchange) -> StepResult<()> {
    let mut edges: BTreeMap<u64, Vec<u64>> = BTreeMap::new();
    for (&id, inst) in &x.instances {
        let refs = instance_refs(inst);
        if let Some(r) = refs.iter().find(|r| !x.instances.contains_key(r)) {
            return Err(StepError::Entity {
                id,
                message: format!("refers to #{r}, which is not in the file"),
            });
        }
        edges.insert(id, refs);
    }
    // Depth-first search with colours (0 new, 1 on the path, 2 done), without recursion.
    let mut colour: BTreeMap<u64, u8> = BTreeMap::new();
    for &root in x.instances.keys() {
        if colour.get(&root).copied().unwrap_or(0) != 0 {
            continue;
        }
        let mut stack: Vec<(u64, usize)> = vec![(root, 0)];
        colour.insert(root, 1);
        while let Some(&mut (node, ref mut next)) = stack.last_mut() {
            let children = &edges[&node];
            if *next < children.len() {
                let child = children[*next];
                *next += 1;
                match colour.get(&child).copied().unwrap_or(0) {
                    0 => {
                        colour.insert(child, 1);
                        stack.push((child, 0));
                    }
                    1 => {
                        let start = stack.iter().position(|&(n, _)| n == child).unwrap_or(0);
                        let path: Vec<String> = stack[start..]
                            .iter()
                            .map(|(n, _)| format!("#{n}"))
                            .collect();
                        return Err(StepError::Entity {
                            id: child,
                            message: format!(
                                "is part of a cycle of references ({} -> #{child})",
                                path.join(" -> ")
                            ),
                        });
                    }
                    _ => {}
                }
            } else {
                colour.insert(node, 2);
                stack.pop();
            }
        }
    }
    Ok(())
}

/// Everything reachable from the bounds of faces: their edges, vertices and edge curves.
fn face_bounds(x: &Exchange) -> BTreeSet<u64> {
    let mut seen = BTreeSet::new();
    let mut stack = Vec::new();
    for inst in x.instances.values() {
        for name in ["ADVANCED_FACE", "FACE_SURFACE"] {
            if let Some(params) = inst.record(name) {
                if let Some(bounds) = params.get(1) {
                    refs_of(bounds, &mut stack);
                }
            }
        }
    }
    while let Some(id) = stack.pop() {
        if seen.insert(id) {
            if let Some(inst) = x.instances.get(&id) {
                stack.extend(instance_refs(inst));
            }
        }
    }
    seen
}

struct Reader<'a> {
    x: &'a Exchange,
    bounds: BTreeSet<u64>,
    /// Trimmed faces found on the way (face -> its surface).
    trimmed: std::cell::RefCell<BTreeMap<u64, u64>>,
}

fn entity_err(id: u64, message: impl Into<String>) -> StepError {
    StepError::Entity {
        id,
        message: message.into(),
    }
}

/// The parameters of record `name` of `inst`, exactly `count` of them.
fn params<'p>(id: u64, inst: &'p Instance, name: &str, count: usize) -> StepResult<&'p [Param]> {
    let p = inst
        .record(name)
        .ok_or_else(|| entity_err(id, format!("has no {name} record")))?;
    if p.len() != count {
        return Err(entity_err(
            id,
            format!("{name} has {} parameters, expected {count}", p.len()),
        ));
    }
    Ok(p)
}

fn list<'p>(id: u64, p: &'p Param, what: &str) -> StepResult<&'p [Param]> {
    match p {
        Param::List(l) => Ok(l),
        _ => Err(entity_err(id, format!("{what} is not a list"))),
    }
}

fn integer(id: u64, p: &Param, what: &str) -> StepResult<usize> {
    match p {
        Param::Int(n) if *n >= 0 && *n <= 1 << 20 => Ok(*n as usize),
        _ => Err(entity_err(
            id,
            format!("{what} is not a non-negative integer"),
        )),
    }
}

fn reals(id: u64, p: &Param, what: &str) -> StepResult<Vec<f64>> {
    list(id, p, what)?
        .iter()
        .enumerate()
        .map(|(k, q)| {
            q.as_real()
                .ok_or_else(|| entity_err(id, format!("{what}[{k}] is not a number")))
        })
        .collect()
}

fn integers(id: u64, p: &Param, what: &str) -> StepResult<Vec<usize>> {
    list(id, p, what)?
        .iter()
        .enumerate()
        .map(|(k, q)| integer(id, q, &format!("{what}[{k}]")))
        .collect()
}

fn enumeration(p: &Param) -> Option<&str> {
    match p {
        Param::Enum(e) => Some(e),
        _ => None,
    }
}

/// The B-spline data of a curve or surface entity, directions in one struct.
struct Spline {
    degrees: Vec<usize>,
    /// Rows of control point references (one row for a curve).
    net: Vec<Vec<u64>>,
    /// Full knot vectors per direction.
    knots: Vec<Vec<f64>>,
    weights: Option<Vec<Vec<f64>>>,
    bezier: bool,
}

impl Reader<'_> {
    fn inst(&self, id: u64) -> &Instance {
        // References were checked.
        &self.x.instances[&id]
    }

    /// A CARTESIAN_POINT's coordinates.
    fn point(&self, owner: u64, id: u64) -> StepResult<Vec<f64>> {
        let inst = self.inst(id);
        let Some(p) = inst.record("CARTESIAN_POINT") else {
            return Err(entity_err(
                owner,
                format!(
                    "control point #{id} is a {}, not a CARTESIAN_POINT",
                    inst.type_name()
                ),
            ));
        };
        if p.len() != 2 {
            return Err(entity_err(
                id,
                format!("CARTESIAN_POINT has {} parameters, expected 2", p.len()),
            ));
        }
        let c = reals(id, &p[1], "coordinates")?;
        if !(1..=3).contains(&c.len()) {
            return Err(entity_err(
                id,
                format!("a point of {} coordinates", c.len()),
            ));
        }
        Ok(c)
    }

    fn ref_list(&self, id: u64, p: &Param, what: &str) -> StepResult<Vec<u64>> {
        list(id, p, what)?
            .iter()
            .enumerate()
            .map(|(k, q)| match q {
                Param::Ref(r) => Ok(*r),
                _ => Err(entity_err(id, format!("{what}[{k}] is not a reference"))),
            })
            .collect()
    }

    fn name(inst: &Instance) -> String {
        let named = inst
            .records
            .iter()
            .find(|(n, _)| n == "REPRESENTATION_ITEM")
            .or_else(|| inst.records.first());
        match named.and_then(|(_, p)| p.first()) {
            Some(Param::Str(s)) => s.clone(),
            _ => String::new(),
        }
    }

    /// The curve entity's spline data, or `None` when it is no B-spline or Bézier curve.
    fn curve(&self, id: u64, inst: &Instance) -> StepResult<Option<Spline>> {
        let simple = inst.records.len() == 1;
        let (degree, points, knots, bezier) = if simple && inst.is("B_SPLINE_CURVE_WITH_KNOTS") {
            let p = params(id, inst, "B_SPLINE_CURVE_WITH_KNOTS", 9)?;
            let degree = integer(id, &p[1], "degree")?;
            let mults = integers(id, &p[6], "knot_multiplicities")?;
            let values = reals(id, &p[7], "knots")?;
            let bezier = enumeration(&p[8]) == Some("PIECEWISE_BEZIER_KNOTS");
            (degree, &p[2], Some((mults, values)), bezier)
        } else if simple && inst.is("BEZIER_CURVE") {
            let p = params(id, inst, "BEZIER_CURVE", 6)?;
            (integer(id, &p[1], "degree")?, &p[2], None, true)
        } else if !simple && inst.is("B_SPLINE_CURVE") {
            let p = params(id, inst, "B_SPLINE_CURVE", 5)?;
            let degree = integer(id, &p[0], "degree")?;
            if inst.is("B_SPLINE_CURVE_WITH_KNOTS") {
                let k = params(id, inst, "B_SPLINE_CURVE_WITH_KNOTS", 3)?;
                let mults = integers(id, &k[0], "knot_multiplicities")?;
                let values = reals(id, &k[1], "knots")?;
                let bezier = enumeration(&k[2]) == Some("PIECEWISE_BEZIER_KNOTS");
                (degree, &p[1], Some((mults, values)), bezier)
            } else if inst.is("BEZIER_CURVE") {
                (degree, &p[1], None, true)
            } else {
                return Ok(None);
            }
        } else {
            return Ok(None);
        };
        let refs = self.ref_list(id, points, "control_points_list")?;
        let knots = self.knots(id, degree, refs.len(), knots)?;
        let weights = if inst.is("RATIONAL_B_SPLINE_CURVE") {
            let w = params(id, inst, "RATIONAL_B_SPLINE_CURVE", 1)?;
            Some(vec![reals(id, &w[0], "weights_data")?])
        } else {
            None
        };
        Ok(Some(Spline {
            degrees: vec![degree],
            net: vec![refs],
            knots: vec![knots],
            weights,
            bezier,
        }))
    }

    /// The full knot vector from distinct knots and multiplicities (or the Bézier knots).
    fn knots(
        &self,
        id: u64,
        degree: usize,
        n: usize,
        knots: Option<(Vec<usize>, Vec<f64>)>,
    ) -> StepResult<Vec<f64>> {
        if degree == 0 {
            return Err(entity_err(id, "degree 0"));
        }
        match knots {
            None => {
                if n < degree + 1 || !(n - 1).is_multiple_of(degree) {
                    return Err(entity_err(
                        id,
                        format!("a Bézier curve of degree {degree} with {n} control points"),
                    ));
                }
                // Pieces of degree p on [0, 1], [1, 2], ... (ISO 10303-42 bezier_curve).
                let pieces = (n - 1) / degree;
                let mut k = vec![0.0; degree + 1];
                for i in 1..pieces {
                    k.extend(std::iter::repeat_n(i as f64, degree));
                }
                k.extend(std::iter::repeat_n(pieces as f64, degree + 1));
                Ok(k)
            }
            Some((mults, values)) => {
                if mults.len() != values.len() {
                    return Err(entity_err(
                        id,
                        format!(
                            "{} knot multiplicities for {} knots",
                            mults.len(),
                            values.len()
                        ),
                    ));
                }
                let total: usize = mults.iter().sum();
                if total != n + degree + 1 {
                    return Err(entity_err(
                        id,
                        format!(
                            "the knot multiplicities sum to {total}, but {n} control points of \
                             degree {degree} need {} knots",
                            n + degree + 1
                        ),
                    ));
                }
                if let Some(k) = values.windows(2).position(|w| w[1] <= w[0]) {
                    return Err(entity_err(
                        id,
                        format!(
                            "the knots must increase: knot {} = {} after {}",
                            k + 1,
                            values[k + 1],
                            values[k]
                        ),
                    ));
                }
                Ok(expand_knots(&values, &mults))
            }
        }
    }

    /// The surface entity's spline data, or `None` when it is no B-spline or Bézier
    /// surface.
    fn surface(&self, id: u64, inst: &Instance) -> StepResult<Option<Spline>> {
        let simple = inst.records.len() == 1;
        type Knots = Option<((Vec<usize>, Vec<f64>), (Vec<usize>, Vec<f64>))>;
        let (du, dv, net, knots, bezier): (usize, usize, &Param, Knots, bool) =
            if simple && inst.is("B_SPLINE_SURFACE_WITH_KNOTS") {
                let p = params(id, inst, "B_SPLINE_SURFACE_WITH_KNOTS", 13)?;
                let k = (
                    (
                        integers(id, &p[8], "u_multiplicities")?,
                        reals(id, &p[10], "u_knots")?,
                    ),
                    (
                        integers(id, &p[9], "v_multiplicities")?,
                        reals(id, &p[11], "v_knots")?,
                    ),
                );
                let bezier = enumeration(&p[12]) == Some("PIECEWISE_BEZIER_KNOTS");
                (
                    integer(id, &p[1], "u_degree")?,
                    integer(id, &p[2], "v_degree")?,
                    &p[3],
                    Some(k),
                    bezier,
                )
            } else if simple && inst.is("BEZIER_SURFACE") {
                let p = params(id, inst, "BEZIER_SURFACE", 8)?;
                (
                    integer(id, &p[1], "u_degree")?,
                    integer(id, &p[2], "v_degree")?,
                    &p[3],
                    None,
                    true,
                )
            } else if !simple && inst.is("B_SPLINE_SURFACE") {
                let p = params(id, inst, "B_SPLINE_SURFACE", 7)?;
                let (du, dv) = (
                    integer(id, &p[0], "u_degree")?,
                    integer(id, &p[1], "v_degree")?,
                );
                if inst.is("B_SPLINE_SURFACE_WITH_KNOTS") {
                    let q = params(id, inst, "B_SPLINE_SURFACE_WITH_KNOTS", 5)?;
                    let k = (
                        (
                            integers(id, &q[0], "u_multiplicities")?,
                            reals(id, &q[2], "u_knots")?,
                        ),
                        (
                            integers(id, &q[1], "v_multiplicities")?,
                            reals(id, &q[3], "v_knots")?,
                        ),
                    );
                    let bezier = enumeration(&q[4]) == Some("PIECEWISE_BEZIER_KNOTS");
                    (du, dv, &p[2], Some(k), bezier)
                } else if inst.is("BEZIER_SURFACE") {
                    (du, dv, &p[2], None, true)
                } else {
                    return Ok(None);
                }
            } else {
                return Ok(None);
            };
        let rows = list(id, net, "control_points_list")?;
        let net: Vec<Vec<u64>> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| self.ref_list(id, r, &format!("control_points_list[{i}]")))
            .collect::<StepResult<_>>()?;
        let cols = net.first().map_or(0, Vec::len);
        if net.is_empty() || net.iter().any(|r| r.len() != cols) {
            return Err(entity_err(
                id,
                "control_points_list is not a rectangular net",
            ));
        }
        let (ku, kv) = match knots {
            Some((u, v)) => (Some(u), Some(v)),
            None => (None, None),
        };
        let knots_u = self.knots(id, du, net.len(), ku)?;
        let knots_v = self.knots(id, dv, cols, kv)?;
        let weights = if inst.is("RATIONAL_B_SPLINE_SURFACE") {
            let w = params(id, inst, "RATIONAL_B_SPLINE_SURFACE", 1)?;
            let rows = list(id, &w[0], "weights_data")?;
            let w: Vec<Vec<f64>> = rows
                .iter()
                .enumerate()
                .map(|(i, r)| reals(id, r, &format!("weights_data[{i}]")))
                .collect::<StepResult<_>>()?;
            if w.len() != net.len() || w.iter().any(|r| r.len() != cols) {
                return Err(entity_err(id, "weights_data does not match the net's size"));
            }
            Some(w)
        } else {
            None
        };
        Ok(Some(Spline {
            degrees: vec![du, dv],
            net,
            knots: vec![knots_u, knots_v],
            weights,
            bezier,
        }))
    }

    fn instance(&self, id: u64, inst: &Instance) -> StepResult<Outcome> {
        if let Some(s) = self.curve(id, inst)? {
            if self.bounds.contains(&id) {
                return Ok(Outcome::Skipped("edge curves of faces".into()));
            }
            return self.curve_model(id, inst, s);
        }
        if let Some(s) = self.surface(id, inst)? {
            return self.surface_model(id, inst, s);
        }
        if inst.is("ADVANCED_FACE") || inst.is("FACE_SURFACE") {
            return self.plane_face(id, inst);
        }
        let name = inst.type_name();
        if OTHER_GEOMETRY.contains(&name.as_str()) && !self.bounds.contains(&id) {
            if name == "PLANE" {
                // Planes are read through their faces.
                return Ok(Outcome::Other);
            }
            return Ok(Outcome::Skipped(format!("{name} (not imported)")));
        }
        Ok(Outcome::Other)
    }

    /// The control points as rows of coordinates, all of one dimension.
    fn net_points(&self, id: u64, net: &[Vec<u64>]) -> StepResult<(usize, Vec<f64>)> {
        let mut dim = 0;
        let mut flat = Vec::new();
        for row in net {
            for &r in row {
                let p = self.point(id, r)?;
                if dim == 0 {
                    dim = p.len();
                } else if p.len() != dim {
                    return Err(entity_err(
                        id,
                        format!(
                            "control point #{r} has {} coordinates, others {dim}",
                            p.len()
                        ),
                    ));
                }
                flat.extend(p);
            }
        }
        Ok((dim, flat))
    }

    fn checked(
        &self,
        id: u64,
        inst: &Instance,
        file: ModelFile,
        note: Option<String>,
    ) -> StepResult<Outcome> {
        AnyModel::from_file(file.clone()).map_err(|e| entity_err(id, e.to_string()))?;
        Ok(Outcome::Model(Box::new(Imported {
            id,
            entity: inst.type_name(),
            name: Self::name(inst),
            file,
            note,
            span: Vec::new(),
        })))
    }

    fn curve_model(&self, id: u64, inst: &Instance, s: Spline) -> StepResult<Outcome> {
        let p = s.degrees[0];
        let knots = &s.knots[0];
        let (dim, flat) = self.net_points(id, &s.net)?;
        // geomkit writes plane curves with z = 0: a 2-D point list is another system's
        // parameter-space curve (or a 2-D sketch), not a curve of the model.
        if dim < 3 {
            return Ok(Outcome::Skipped(
                "2-D curves (parameter-space curves)".into(),
            ));
        }
        let n = s.net[0].len();
        let weights = match s.weights {
            Some(w) => {
                let w = w.concat();
                if w.len() != n {
                    return Err(entity_err(
                        id,
                        format!("{} weights for {n} control points", w.len()),
                    ));
                }
                if let Some(k) = w.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
                    return Err(entity_err(id, format!("weight {k} = {} is not > 0", w[k])));
                }
                // Equal weights are a common factor: the polynomial curve.
                (!w.iter().all(|&x| x == w[0])).then_some(w)
            }
            None => None,
        };
        let single_span = knots[..=p].iter().all(|&k| k == knots[0])
            && knots[n..].iter().all(|&k| k == knots[n])
            && n == p + 1;
        let (a, b) = (knots[p], knots[n]);
        let points = Points { dim, flat };
        match weights {
            Some(w) if single_span => {
                let note = ((a, b) != (0.0, 1.0)).then(|| {
                    format!("parameter t in [{a}, {b}] is (t - {a}) / ({b} - {a}) in [0, 1]")
                });
                let file = ModelFile::BezierCurve(BezierCurveFile {
                    points,
                    weights: Some(w),
                    error: None,
                });
                self.checked(id, inst, file, note)
            }
            Some(w) => self.curve_spans(id, inst, p, knots, &points.flat, &w),
            None if single_span && s.bezier && (a, b) == (0.0, 1.0) => {
                let file = ModelFile::BezierCurve(BezierCurveFile {
                    points,
                    weights: None,
                    error: None,
                });
                self.checked(id, inst, file, None)
            }
            None => {
                if p > geomkit::bspline::BsplineCurve::MAX_DEGREE {
                    return Ok(Outcome::Skipped(
                        "B-spline curves of degree above 15 (geomkit's limit)".into(),
                    ));
                }
                let file = ModelFile::BsplineCurve(BsplineCurveFile {
                    degree: p,
                    knots: knots.clone(),
                    control_points: points,
                    parameters: None,
                });
                self.checked(id, inst, file, None)
            }
        }
    }

    fn surface_model(&self, id: u64, inst: &Instance, s: Spline) -> StepResult<Outcome> {
        let (du, dv) = (s.degrees[0], s.degrees[1]);
        let (rows, cols) = (s.net.len(), s.net[0].len());
        let (dim, flat) = self.net_points(id, &s.net)?;
        let (ku, kv) = (&s.knots[0], &s.knots[1]);
        // One span in each direction over [0, 1]²: a Bézier surface.
        let single_span = rows == du + 1
            && cols == dv + 1
            && ku.iter().all(|&k| k == 0.0 || k == 1.0)
            && kv.iter().all(|&k| k == 0.0 || k == 1.0);
        let bezier = s.bezier && single_span;
        let net = Net {
            rows,
            cols,
            dim,
            flat,
        };
        if let Some(w) = &s.weights {
            if let Some(bad) = w.iter().flatten().find(|x| !(x.is_finite() && **x > 0.0)) {
                return Err(entity_err(id, format!("weight {bad} is not > 0")));
            }
            let first = w[0][0];
            if !w.iter().flatten().all(|&x| x == first) {
                if !single_span {
                    return self.surface_spans(id, inst, (du, dv), (ku, kv), &net, w);
                }
                let file = ModelFile::BezierSurface(BezierSurfaceFile {
                    net,
                    weights: Some(w.clone()),
                });
                let note = self.trimming_note(id, &file)?;
                return self.checked(id, inst, file, note);
            }
        }
        if bezier {
            let file = ModelFile::BezierSurface(BezierSurfaceFile { net, weights: None });
            let note = self.trimming_note(id, &file)?;
            return self.checked(id, inst, file, note);
        }
        if du > 7 || dv > 7 {
            return Ok(Outcome::Skipped(
                "B-spline surfaces of degree above 7 (geomkit's limit)".into(),
            ));
        }
        let file = ModelFile::BsplineSurface(BsplineSurfaceFile {
            degree: [du, dv],
            knots_u: ku.clone(),
            knots_v: kv.clone(),
            net,
            parameters_u: None,
            parameters_v: None,
        });
        let note = self.trimming_note(id, &file)?;
        self.checked(id, inst, file, note)
    }

    /// A rational B-spline curve of several spans as its rational Bézier pieces (knot
    /// insertion in homogeneous coordinates; the file's own points and weights where a span
    /// boundary already has multiplicity p).
    fn curve_spans(
        &self,
        id: u64,
        inst: &Instance,
        p: usize,
        knots: &[f64],
        flat: &[f64],
        w: &[f64],
    ) -> StepResult<Outcome> {
        let rows: Vec<Vec<f64>> = flat
            .chunks_exact(3)
            .zip(w)
            .map(|(q, &w)| vec![q[0] * w, q[1] * w, q[2] * w, w])
            .collect();
        let spans = split::spans(p, knots, &rows);
        let total = spans.len();
        let mut out = Vec::with_capacity(total);
        for (k, s) in spans.iter().enumerate() {
            let mut pts = Vec::with_capacity(3 * (p + 1));
            let mut ws = Vec::with_capacity(p + 1);
            for (r, o) in s.rows.iter().zip(&s.origin) {
                match o {
                    Some(i) => {
                        pts.extend_from_slice(&flat[3 * i..3 * i + 3]);
                        ws.push(w[*i]);
                    }
                    None => {
                        pts.extend([r[0] / r[3], r[1] / r[3], r[2] / r[3]]);
                        ws.push(r[3]);
                    }
                }
            }
            let file = ModelFile::BezierCurve(BezierCurveFile {
                points: Points { dim: 3, flat: pts },
                weights: Some(ws),
                error: None,
            });
            let note = format!(
                "span {} of {total}: t in [{}, {}] is (t - {}) / ({} - {}) in [0, 1]",
                k + 1,
                s.from,
                s.to,
                s.from,
                s.to,
                s.from
            );
            out.push(self.piece(id, inst, file, note, vec![k])?);
        }
        Ok(Outcome::Models(out))
    }

    /// One piece of an entity, checked.
    fn piece(
        &self,
        id: u64,
        inst: &Instance,
        file: ModelFile,
        note: String,
        span: Vec<usize>,
    ) -> StepResult<Imported> {
        match self.checked(id, inst, file, Some(note))? {
            Outcome::Model(m) => Ok(Imported { span, ..*m }),
            _ => unreachable!("checked gives one model"),
        }
    }

    /// A rational B-spline surface of several spans as its rational Bézier patches: the
    /// rows split along u, then each piece's columns along v.
    fn surface_spans(
        &self,
        id: u64,
        inst: &Instance,
        (du, dv): (usize, usize),
        (ku, kv): (&[f64], &[f64]),
        net: &Net,
        w: &[Vec<f64>],
    ) -> StepResult<Outcome> {
        let (cols, d) = (net.cols, net.dim);
        let point = |i: usize, j: usize| &net.flat[(i * cols + j) * d..(i * cols + j + 1) * d];
        let rows: Vec<Vec<f64>> = (0..net.rows)
            .map(|i| {
                (0..cols)
                    .flat_map(|j| {
                        let wt = w[i][j];
                        point(i, j)
                            .iter()
                            .map(move |x| x * wt)
                            .chain(std::iter::once(wt))
                    })
                    .collect()
            })
            .collect();
        let h = d + 1;
        let u_spans = split::spans(du, ku, &rows);
        let mut out = Vec::new();
        let total = u_spans.len();
        for (a, su) in u_spans.iter().enumerate() {
            // Columns of this u piece: (du + 1) homogeneous points each.
            let columns: Vec<Vec<f64>> = (0..cols)
                .map(|j| {
                    su.rows
                        .iter()
                        .flat_map(|r| r[j * h..(j + 1) * h].to_vec())
                        .collect()
                })
                .collect();
            let v_spans = split::spans(dv, kv, &columns);
            let total_v = v_spans.len();
            for (b, sv) in v_spans.iter().enumerate() {
                let mut flat = Vec::with_capacity((du + 1) * (dv + 1) * d);
                let mut weights = vec![Vec::with_capacity(dv + 1); du + 1];
                for (r, weight_row) in weights.iter_mut().enumerate() {
                    for (c, col) in sv.rows.iter().enumerate() {
                        match (su.origin[r], sv.origin[c]) {
                            (Some(i), Some(j)) => {
                                flat.extend_from_slice(point(i, j));
                                weight_row.push(w[i][j]);
                            }
                            _ => {
                                let hp = &col[r * h..(r + 1) * h];
                                flat.extend(hp[..d].iter().map(|x| x / hp[d]));
                                weight_row.push(hp[d]);
                            }
                        }
                    }
                }
                let file = ModelFile::BezierSurface(BezierSurfaceFile {
                    net: Net {
                        rows: du + 1,
                        cols: dv + 1,
                        dim: d,
                        flat,
                    },
                    weights: Some(weights),
                });
                let note = format!(
                    "span ({}, {}) of {total} × {total_v}: u in [{}, {}], v in [{}, {}] mapped \
                     onto [0, 1]²",
                    a + 1,
                    b + 1,
                    su.from,
                    su.to,
                    sv.from,
                    sv.to
                );
                out.push(self.piece(id, inst, file, note, vec![a, b])?);
            }
        }
        Ok(Outcome::Models(out))
    }

    /// A note when a face on `surface` has a vertex away from the surface's four corners:
    /// the face is trimmed, and the whole surface is what is imported.
    fn trimming_note(&self, surface: u64, file: &ModelFile) -> StepResult<Option<String>> {
        let model =
            AnyModel::from_file(file.clone()).map_err(|e| entity_err(surface, e.to_string()))?;
        let s: &dyn geomkit::geom::Surface = match &model {
            AnyModel::Bezier(crate::BezierModel::Surface(b)) => b,
            AnyModel::BsplineSurface(m) => &m.surface,
            _ => return Ok(None),
        };
        let ((u0, u1), (v0, v1)) = s.domain();
        let mut corners = Vec::new();
        let mut scale = 0.0f64;
        for (u, v) in [(u0, v0), (u0, v1), (u1, v0), (u1, v1)] {
            let mut p = vec![0.0; s.dim()];
            s.eval_into(u, v, &mut p);
            scale = p.iter().fold(scale, |m, x| m.max(x.abs()));
            corners.push(p);
        }
        for (&face, inst) in &self.x.instances {
            let Some(p) = inst.record("ADVANCED_FACE").or(inst.record("FACE_SURFACE")) else {
                continue;
            };
            if p.len() != 4 || p[2] != Param::Ref(surface) {
                continue;
            }
            let tolerance = 1e-9 * scale.max(1e-300);
            let trimmed = self.face_vertices(face, &p[1])?.iter().any(|v| {
                !corners
                    .iter()
                    .any(|c| c.iter().zip(v).all(|(a, b)| (a - b).abs() <= tolerance))
            });
            if trimmed {
                self.trimmed.borrow_mut().insert(face, surface);
            }
        }
        let faces: Vec<String> = self
            .trimmed
            .borrow()
            .iter()
            .filter(|(_, &s)| s == surface)
            .map(|(f, _)| format!("#{f}"))
            .collect();
        Ok((!faces.is_empty()).then(|| {
            format!(
                "the whole surface of the trimmed face {}: its outline is not kept",
                faces.join(", ")
            )
        }))
    }

    /// The vertices of a face's bounds, in loop order.
    fn face_vertices(&self, face: u64, bounds: &Param) -> StepResult<Vec<[f64; 3]>> {
        let mut out = Vec::new();
        let mut ids = Vec::new();
        refs_of(bounds, &mut ids);
        let mut seen = BTreeSet::new();
        let mut stack: Vec<u64> = ids.into_iter().rev().collect();
        while let Some(id) = stack.pop() {
            if !seen.insert(id) {
                continue;
            }
            let inst = self.inst(id);
            if inst.is("VERTEX_POINT") {
                let p = params(id, inst, "VERTEX_POINT", 2)?;
                let Param::Ref(r) = p[1] else {
                    return Err(entity_err(id, "vertex_geometry is not a reference"));
                };
                let c = self.point(id, r)?;
                if c.len() != 3 {
                    return Err(entity_err(face, "a vertex of a face is not a 3-D point"));
                }
                out.push([c[0], c[1], c[2]]);
                continue;
            }
            if inst.is("EDGE_CURVE") {
                // The vertices only: the curve is the face's business.
                let p = params(id, inst, "EDGE_CURVE", 5)?;
                for q in [&p[1], &p[2]] {
                    if let Param::Ref(r) = q {
                        stack.push(*r);
                    }
                }
                continue;
            }
            let mut children = instance_refs(inst);
            children.reverse();
            stack.extend(children);
        }
        Ok(out)
    }

    /// A face on a PLANE: the degree-1 Bézier patch of the rectangle around its vertices in
    /// the plane's axes.
    fn plane_face(&self, id: u64, inst: &Instance) -> StepResult<Outcome> {
        let record = if inst.is("ADVANCED_FACE") {
            "ADVANCED_FACE"
        } else {
            "FACE_SURFACE"
        };
        let p = params(id, inst, record, 4)?;
        let Param::Ref(surface) = p[2] else {
            return Err(entity_err(id, "face_geometry is not a reference"));
        };
        let plane = self.inst(surface);
        if plane.type_name() != "PLANE" {
            return Ok(Outcome::Other);
        }
        let q = params(surface, plane, "PLANE", 2)?;
        let Param::Ref(axis) = q[1] else {
            return Err(entity_err(surface, "position is not a reference"));
        };
        let (origin, z, x) = self.placement(axis)?;
        let y = cross(z, x);
        let vertices = self.face_vertices(id, &p[1])?;
        if vertices.len() < 3 {
            return Ok(Outcome::Skipped(
                "plane faces without 3 vertices (bounded by closed curves)".into(),
            ));
        }
        let local: Vec<[f64; 2]> = vertices
            .iter()
            .map(|v| {
                let d = [v[0] - origin[0], v[1] - origin[1], v[2] - origin[2]];
                [dot(d, x), dot(d, y)]
            })
            .collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for l in &local {
            for c in 0..2 {
                lo[c] = lo[c].min(l[c]);
                hi[c] = hi[c].max(l[c]);
            }
        }
        let at = |a: f64, b: f64| -> Vec<f64> {
            (0..3).map(|c| origin[c] + a * x[c] + b * y[c]).collect()
        };
        // u along x, v along y.
        let mut flat = Vec::new();
        for a in [lo[0], hi[0]] {
            for b in [lo[1], hi[1]] {
                flat.extend(at(a, b));
            }
        }
        let corners = vertices.len() == 4
            && local
                .iter()
                .all(|l| (l[0] == lo[0] || l[0] == hi[0]) && (l[1] == lo[1] || l[1] == hi[1]));
        if !corners {
            self.trimmed.borrow_mut().insert(id, surface);
        }
        let note = (!corners).then(|| {
            "the plane's rectangle around the face's vertices (the face's own outline is not \
             kept)"
                .to_string()
        });
        let file = ModelFile::BezierSurface(BezierSurfaceFile {
            net: Net {
                rows: 2,
                cols: 2,
                dim: 3,
                flat,
            },
            weights: None,
        });
        self.checked(id, inst, file, note)
    }

    /// An AXIS2_PLACEMENT_3D: origin, unit z and unit x (x made orthogonal to z).
    fn placement(&self, id: u64) -> StepResult<([f64; 3], [f64; 3], [f64; 3])> {
        let inst = self.inst(id);
        let p = params(id, inst, "AXIS2_PLACEMENT_3D", 4)?;
        let Param::Ref(o) = p[1] else {
            return Err(entity_err(id, "location is not a reference"));
        };
        let o = self.point(id, o)?;
        if o.len() != 3 {
            return Err(entity_err(id, "location is not a 3-D point"));
        }
        let direction = |q: &Param, default: [f64; 3]| -> StepResult<[f64; 3]> {
            match q {
                Param::Null => Ok(default),
                Param::Ref(r) => {
                    let d = params(*r, self.inst(*r), "DIRECTION", 2)?;
                    let v = reals(*r, &d[1], "direction_ratios")?;
                    if v.len() != 3 {
                        return Err(entity_err(*r, "a direction of other than 3 ratios"));
                    }
                    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if !(n.is_finite() && n > 0.0) {
                        return Err(entity_err(*r, "a zero direction"));
                    }
                    Ok([v[0] / n, v[1] / n, v[2] / n])
                }
                _ => Err(entity_err(id, "a direction is not a reference")),
            }
        };
        let z = direction(&p[2], [0.0, 0.0, 1.0])?;
        let x0 = direction(
            &p[3],
            if z[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            },
        )?;
        let d = dot(x0, z);
        let x = [x0[0] - d * z[0], x0[1] - d * z[1], x0[2] - d * z[2]];
        let n = dot(x, x).sqrt();
        if n.is_nan() || n <= 0.0 {
            return Err(entity_err(id, "ref_direction is parallel to axis"));
        }
        Ok(([o[0], o[1], o[2]], z, [x[0] / n, x[1] / n, x[2] / n]))
    }
}
