//! The writer: geometry as B-spline entities, placed in topology OCCT and other CAD systems
//! turn into shapes (curves as edges of a wireframe model, surfaces as faces bounded by their
//! boundary edges in a shell), with the AP214 product structure, units and uncertainty.

use super::approx::Approximation;
use super::nurbs::{knots_mults, NurbsCurve, NurbsSurface};
use super::part21::{real, reals, refs, string, Writer};
use super::{Schema, StepResult, WriteOptions};

/// What a model is as STEP: curves (a wireframe), faces in an open shell, or a closed body.
pub(crate) enum Content {
    /// Curves, each an edge of a wireframe model.
    Curves(Vec<NurbsCurve>),
    /// Surfaces, each a face bounded by its boundary curves, sewn where boundaries coincide.
    Faces(Vec<FaceSpec>),
    /// A closed body: faces that close, as a solid.
    Solid(Vec<FaceSpec>),
}

/// A face: its surface and its boundary loop, or the surface's own boundary.
#[derive(Debug, Clone)]
pub(crate) struct FaceSpec {
    /// The surface.
    pub surface: NurbsSurface,
    /// The outer loop as curves head to tail; `None`: the four boundary curves of the
    /// surface's domain (collapsed ones left out, coinciding ones a seam).
    pub bound: Option<Vec<NurbsCurve>>,
    /// Whether the face's normal is the surface's (∂S/∂u × ∂S/∂v); else the reverse.
    pub same_sense: bool,
}

struct Vertex {
    point: [f64; 3],
    id: u64,
}

struct Edge {
    curve: NurbsCurve,
    id: u64,
}

/// The data section being built, with vertices and edges shared where they coincide.
struct Builder {
    w: Writer,
    tolerance: f64,
    vertices: Vec<Vertex>,
    edges: Vec<Edge>,
}

fn same_points(a: &[[f64; 3]], b: &[[f64; 3]], tolerance: f64) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| (0..3).all(|c| (p[c] - q[c]).abs() <= tolerance))
}

fn same_curve(a: &NurbsCurve, b: &NurbsCurve, tolerance: f64) -> bool {
    let scale = a
        .knots
        .iter()
        .chain(&b.knots)
        .fold(0.0f64, |m, k| m.max(k.abs()))
        .max(1.0);
    a.degree == b.degree
        && a.knots.len() == b.knots.len()
        && a.knots
            .iter()
            .zip(&b.knots)
            .all(|(x, y)| (x - y).abs() <= 1e-14 * scale)
        && same_points(&a.points, &b.points, tolerance)
        && match (&a.weights, &b.weights) {
            (None, None) => true,
            (Some(x), Some(y)) => x.iter().zip(y).all(|(s, t)| (s - t).abs() <= 1e-14 * s),
            _ => false,
        }
}

impl Builder {
    fn point(&mut self, p: [f64; 3]) -> u64 {
        self.w.add(format!("CARTESIAN_POINT('',{})", reals(&p)))
    }

    fn direction(&mut self, d: [f64; 3]) -> u64 {
        self.w.add(format!("DIRECTION('',{})", reals(&d)))
    }

    /// A vertex at `p`, shared with one within the tolerance.
    fn vertex(&mut self, p: [f64; 3]) -> usize {
        let tol = self.tolerance;
        if let Some(k) = self
            .vertices
            .iter()
            .position(|v| (0..3).all(|c| (v.point[c] - p[c]).abs() <= tol))
        {
            return k;
        }
        let point = self.point(p);
        let id = self.w.add(format!("VERTEX_POINT('',#{point})"));
        self.vertices.push(Vertex { point: p, id });
        self.vertices.len() - 1
    }

    fn curve(&mut self, c: &NurbsCurve, closed: bool) -> u64 {
        let pts: Vec<u64> = c.points.iter().map(|&p| self.point(p)).collect();
        let (knots, mults) = knots_mults(&c.knots);
        let mults: Vec<String> = mults.iter().map(|m| m.to_string()).collect();
        let mults = format!("({})", mults.join(","));
        let closed = if closed { ".T." } else { ".F." };
        let spec = knot_spec(c.bezier);
        let p = c.degree;
        match &c.weights {
            None => self.w.add(format!(
                "B_SPLINE_CURVE_WITH_KNOTS('',{p},{},.UNSPECIFIED.,{closed},.F.,{mults},{},{spec})",
                refs(&pts),
                reals(&knots)
            )),
            Some(weights) => self.w.add(format!(
                "(BOUNDED_CURVE()B_SPLINE_CURVE({p},{},.UNSPECIFIED.,{closed},.F.)\
                 B_SPLINE_CURVE_WITH_KNOTS({mults},{},{spec})CURVE()\
                 GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_CURVE({})\
                 REPRESENTATION_ITEM(''))",
                refs(&pts),
                reals(&knots),
                reals(weights)
            )),
        }
    }

    /// The edge of `c` (shared with an earlier one along the same curve, either way) and
    /// whether it runs the way `c` does. Collapsed curves give `None`.
    fn edge(&mut self, c: &NurbsCurve) -> StepResult<Option<(u64, bool)>> {
        if c.is_point(self.tolerance) {
            return Ok(None);
        }
        let tol = self.tolerance;
        let reversed = c.reversed();
        for e in &self.edges {
            if same_curve(&e.curve, c, tol) {
                return Ok(Some((e.id, true)));
            }
            if same_curve(&e.curve, &reversed, tol) {
                return Ok(Some((e.id, false)));
            }
        }
        let (a, b) = c.ends()?;
        let start = self.vertex(a);
        let end = self.vertex(b);
        let curve = self.curve(c, start == end);
        let (va, vb) = (self.vertices[start].id, self.vertices[end].id);
        let id = self
            .w
            .add(format!("EDGE_CURVE('',#{va},#{vb},#{curve},.T.)"));
        self.edges.push(Edge {
            curve: c.clone(),
            id,
        });
        Ok(Some((id, true)))
    }

    fn surface(&mut self, s: &NurbsSurface, u_closed: bool, v_closed: bool) -> u64 {
        let (p, q) = s.degrees;
        let mut rows = Vec::with_capacity(s.rows);
        for i in 0..s.rows {
            let ids: Vec<u64> = (0..s.cols)
                .map(|j| self.point(s.points[i * s.cols + j]))
                .collect();
            rows.push(refs(&ids));
        }
        let net = format!("({})", rows.join(","));
        let (ku, mu) = knots_mults(&s.knots_u);
        let (kv, mv) = knots_mults(&s.knots_v);
        let ints = |m: &[usize]| {
            let v: Vec<String> = m.iter().map(|x| x.to_string()).collect();
            format!("({})", v.join(","))
        };
        let b = |x: bool| if x { ".T." } else { ".F." };
        let (uc, vc) = (b(u_closed), b(v_closed));
        let spec = knot_spec(s.bezier);
        match &s.weights {
            None => self.w.add(format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{p},{q},{net},.UNSPECIFIED.,{uc},{vc},.F.,{},{},\
                 {},{},{spec})",
                ints(&mu),
                ints(&mv),
                reals(&ku),
                reals(&kv)
            )),
            Some(w) => {
                let wrows: Vec<String> = w.chunks_exact(s.cols).map(reals).collect();
                self.w.add(format!(
                    "(BOUNDED_SURFACE()B_SPLINE_SURFACE({p},{q},{net},.UNSPECIFIED.,{uc},{vc},\
                     .F.)B_SPLINE_SURFACE_WITH_KNOTS({},{},{},{},{spec})\
                     GEOMETRIC_REPRESENTATION_ITEM()RATIONAL_B_SPLINE_SURFACE(({}))\
                     REPRESENTATION_ITEM('')SURFACE())",
                    ints(&mu),
                    ints(&mv),
                    reals(&ku),
                    reals(&kv),
                    wrows.join(",")
                ))
            }
        }
    }

    /// A face: the surface, its loop (the given one or the four sides of the domain) and
    /// its orientation.
    fn face(&mut self, f: &FaceSpec) -> StepResult<u64> {
        let s = &f.surface;
        let ((u0, u1), (v0, v1)) = s.domain();
        let (loop_curves, u_closed, v_closed) = match &f.bound {
            Some(b) => (b.clone(), false, false),
            None => {
                let bottom = s.iso(true, v0)?;
                let right = s.iso(false, u1)?;
                let top = s.iso(true, v1)?;
                let left = s.iso(false, u0)?;
                let tol = self.tolerance;
                let u_closed = !left.is_point(tol) && same_curve(&left, &right, tol);
                let v_closed = !bottom.is_point(tol) && same_curve(&bottom, &top, tol);
                (
                    vec![bottom, right, top.reversed(), left.reversed()],
                    u_closed,
                    v_closed,
                )
            }
        };
        let surface = self.surface(s, u_closed, v_closed);
        let mut oriented = Vec::new();
        for c in &loop_curves {
            if let Some((edge, forward)) = self.edge(c)? {
                oriented.push((edge, forward));
            }
        }
        if !f.same_sense {
            // The loop runs counter-clockwise about the face's normal.
            oriented.reverse();
            for o in &mut oriented {
                o.1 = !o.1;
            }
        }
        let ids: Vec<u64> = oriented
            .iter()
            .map(|&(e, forward)| {
                let sense = if forward { ".T." } else { ".F." };
                self.w.add(format!("ORIENTED_EDGE('',*,*,#{e},{sense})"))
            })
            .collect();
        let edge_loop = self.w.add(format!("EDGE_LOOP('',{})", refs(&ids)));
        let bound = self.w.add(format!("FACE_OUTER_BOUND('',#{edge_loop},.T.)"));
        let sense = if f.same_sense { ".T." } else { ".F." };
        Ok(self
            .w
            .add(format!("ADVANCED_FACE('',(#{bound}),#{surface},{sense})")))
    }
}

/// The knot type: `.PIECEWISE_BEZIER_KNOTS.` for Bézier geometry (read back as Bézier).
fn knot_spec(bezier: bool) -> &'static str {
    if bezier {
        ".PIECEWISE_BEZIER_KNOTS."
    } else {
        ".UNSPECIFIED."
    }
}

/// 1e-12 of the largest |coordinate| of `points` (the tolerance of shared vertices and
/// edges).
fn points_tolerance(points: &[[f64; 3]]) -> f64 {
    let m = points.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    1e-12 * m.max(f64::MIN_POSITIVE)
}

/// Whether a surface's sides close it: each collapsed to a point or equal to its opposite
/// side (a seam), and not all four collapsed.
pub(crate) fn closes(s: &NurbsSurface) -> StepResult<bool> {
    let tol = points_tolerance(&s.points);
    let ((u0, u1), (v0, v1)) = s.domain();
    let (bottom, top) = (s.iso(true, v0)?, s.iso(true, v1)?);
    let (left, right) = (s.iso(false, u0)?, s.iso(false, u1)?);
    let pair = |a: &NurbsCurve, b: &NurbsCurve| {
        (a.is_point(tol) && b.is_point(tol)) || same_curve(a, b, tol)
    };
    let all_collapsed = [&bottom, &top, &left, &right]
        .iter()
        .all(|c| c.is_point(tol));
    Ok(!all_collapsed && pair(&bottom, &top) && pair(&left, &right))
}

/// The tolerance of shared vertices and edges: 1e-12 of the largest |coordinate|.
fn tolerance(content: &Content) -> f64 {
    let mut m = 0.0f64;
    let mut take = |ps: &[[f64; 3]]| {
        for p in ps {
            for x in p {
                m = m.max(x.abs());
            }
        }
    };
    match content {
        Content::Curves(cs) => cs.iter().for_each(|c| take(&c.points)),
        Content::Faces(fs) | Content::Solid(fs) => fs.iter().for_each(|f| {
            take(&f.surface.points);
            for c in f.bound.iter().flatten() {
                take(&c.points);
            }
        }),
    }
    1e-12 * m.max(f64::MIN_POSITIVE)
}

/// The header's description: the options' one, then one line per approximated piece (the
/// default description no longer says "exact" when there are some).
fn description(options: &WriteOptions, approximations: &[Approximation]) -> String {
    let mut lines = vec![options.description.clone()];
    if !approximations.is_empty() {
        if options.description == WriteOptions::default().description {
            lines[0] = format!(
                "geometry written by geomkit: exact except {} approximated piece(s) below",
                approximations.len()
            );
        }
        lines.extend(
            approximations
                .iter()
                .map(|a| format!("approximated {}", a.describe())),
        );
    }
    let strings: Vec<String> = lines.iter().map(|l| string(l)).collect();
    strings.join(",")
}

/// The whole exchange structure.
pub(crate) fn write(
    content: &Content,
    options: &WriteOptions,
    approximations: &[Approximation],
) -> StepResult<String> {
    let mut b = Builder {
        w: Writer::default(),
        tolerance: tolerance(content),
        vertices: Vec::new(),
        edges: Vec::new(),
    };
    let name = string(&options.name);
    // Product structure (AP214 / AP242 "part").
    let app = match options.schema {
        Schema::Ap214 => b.w.add("APPLICATION_CONTEXT('automotive design')"),
        Schema::Ap242 => {
            b.w.add("APPLICATION_CONTEXT('managed model based 3d engineering')")
        }
    };
    match options.schema {
        Schema::Ap214 => b.w.add(format!(
            "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',\
             2000,#{app})"
        )),
        Schema::Ap242 => b.w.add(format!(
            "APPLICATION_PROTOCOL_DEFINITION('international standard',\
             'ap242_managed_model_based_3d_engineering',2011,#{app})"
        )),
    };
    let pc = b.w.add(format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let product = b.w.add(format!("PRODUCT({name},{name},'',(#{pc}))"));
    b.w.add(format!(
        "PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,(#{product}))"
    ));
    let pdf =
        b.w.add(format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"));
    let pdc = b.w.add(format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let pd =
        b.w.add(format!("PRODUCT_DEFINITION('design','',#{pdf},#{pdc})"));
    let pds = b.w.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"));
    // Units and uncertainty.
    let length =
        b.w.add("(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.))");
    let angle =
        b.w.add("(NAMED_UNIT(*)PLANE_ANGLE_UNIT()SI_UNIT($,.RADIAN.))");
    let solid =
        b.w.add("(NAMED_UNIT(*)SI_UNIT($,.STERADIAN.)SOLID_ANGLE_UNIT())");
    let uncertainty = b.w.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),#{length},'distance_accuracy_value',\
         'maximum distance of points taken as one')",
        real(options.uncertainty)
    ));
    let context = b.w.add(format!(
        "(GEOMETRIC_REPRESENTATION_CONTEXT(3)GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{uncertainty}))\
         GLOBAL_UNIT_ASSIGNED_CONTEXT((#{length},#{angle},#{solid}))\
         REPRESENTATION_CONTEXT('','3D'))"
    ));
    let origin = b.point([0.0, 0.0, 0.0]);
    let z = b.direction([0.0, 0.0, 1.0]);
    let x = b.direction([1.0, 0.0, 0.0]);
    let axis =
        b.w.add(format!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    let rep = match content {
        Content::Curves(curves) => {
            let mut sets = Vec::new();
            for c in curves {
                if let Some((edge, _)) = b.edge(c)? {
                    sets.push(edge);
                }
            }
            if sets.is_empty() {
                return Err(super::StepError::Unsupported(
                    "every curve is a single point: there is no edge to write".into(),
                ));
            }
            let set = b.w.add(format!("CONNECTED_EDGE_SET('',{})", refs(&sets)));
            let model = b.w.add(format!("EDGE_BASED_WIREFRAME_MODEL('',(#{set}))"));
            b.w.add(format!(
                "EDGE_BASED_WIREFRAME_SHAPE_REPRESENTATION({name},(#{model},#{axis}),#{context})"
            ))
        }
        Content::Faces(faces) => {
            let ids = faces
                .iter()
                .map(|f| b.face(f))
                .collect::<StepResult<Vec<u64>>>()?;
            let shell = b.w.add(format!("OPEN_SHELL('',{})", refs(&ids)));
            let model = b.w.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
            b.w.add(format!(
                "MANIFOLD_SURFACE_SHAPE_REPRESENTATION({name},(#{model},#{axis}),#{context})"
            ))
        }
        Content::Solid(faces) => {
            let ids = faces
                .iter()
                .map(|f| b.face(f))
                .collect::<StepResult<Vec<u64>>>()?;
            let shell = b.w.add(format!("CLOSED_SHELL('',{})", refs(&ids)));
            let brep = b.w.add(format!("MANIFOLD_SOLID_BREP({name},#{shell})"));
            b.w.add(format!(
                "ADVANCED_BREP_SHAPE_REPRESENTATION({name},(#{brep},#{axis}),#{context})"
            ))
        }
    };
    b.w.add(format!("SHAPE_DEFINITION_REPRESENTATION(#{pds},#{rep})"));
    let schema = match options.schema {
        Schema::Ap214 => "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }",
        Schema::Ap242 => "AP242_MANAGED_MODEL_BASED_3D_ENGINEERING_MIM_LF { 1 0 10303 442 1 1 4 }",
    };
    let stamp = options
        .timestamp
        .as_deref()
        .unwrap_or("1970-01-01T00:00:00");
    let mut out = String::new();
    out.push_str("ISO-10303-21;\nHEADER;\n");
    out.push_str(&format!(
        "FILE_DESCRIPTION(({}),'2;1');\n",
        description(options, approximations)
    ));
    out.push_str(&format!(
        "FILE_NAME({name},{},(''),(''),{},'geomkit','');\n",
        string(stamp),
        string(&format!("geomkit {}", env!("CARGO_PKG_VERSION")))
    ));
    out.push_str(&format!("FILE_SCHEMA(('{schema}'));\nENDSEC;\nDATA;\n"));
    out.push_str(&b.w.finish());
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok(out)
}
