//! Composite surfaces and ruled surfaces (the closed bodies) as faces sewn along shared
//! edges: each composite patch a Bézier face; each strip of a ruled surface between two of
//! its curves bilinear patches (polylines), rational quadratic × linear patches (circles),
//! or a plane face (a cap: a point in the plane of a polygon or circle); closed bodies as a
//! solid with every face oriented outwards.

use super::approx::{self, absolute_tolerance, finite, Approximation, SurfacePiece};
use super::convert::{bezier_knots, natural_face};
use super::nurbs::{cross, dot, NurbsCurve, NurbsSurface};
use super::write::{Content, FaceSpec};
use super::{StepError, StepResult};
use geomkit::compose::{CompositeSurface, PolyPatch, RuledCurve, RuledSurface, SurfaceKind};

/// n choose k as f64 (exact for the degrees of patches).
fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// A composite surface of polynomial patches as one Bézier face per patch (on its cell,
/// reparametrized to [0, 1]²), sewn where neighbouring patches share a boundary. Explicit
/// surfaces z(x, y) become the parametric patches (x, y, z(x, y)).
pub(crate) fn composite(
    s: &CompositeSurface,
    tolerance: f64,
) -> StepResult<(Content, Vec<Approximation>)> {
    if s.patch(0, 0).is_none() {
        return formula_composite(s, tolerance);
    }
    let (n, m) = s.cells();
    let (uk, vk) = s.knots();
    let mut faces = Vec::with_capacity(n * m);
    for i in 0..n {
        for j in 0..m {
            let Some(p) = s.patch(i, j) else {
                return Err(StepError::Unsupported(format!(
                    "patch ({i}, {j}) of a composite surface is neither a polynomial nor a formula"
                )));
            };
            let cell = ((uk[i], uk[i + 1]), (vk[j], vk[j + 1]));
            faces.push(natural_face(poly_face(p, s.kind(), cell, (i, j))?));
        }
    }
    Ok((Content::Faces(faces), Vec::new()))
}

/// The Bézier face of polynomial patch (i, j) on its cell: its Bézier net as given when it
/// was made from one (exact), else the Bernstein form of its power coefficients; explicit
/// patches z(x, y) as the points (x, y, z).
fn poly_face(
    p: &PolyPatch,
    kind: SurfaceKind,
    ((u0, u1), (v0, v1)): ((f64, f64), (f64, f64)),
    (i, j): (usize, usize),
) -> StepResult<NurbsSurface> {
    let (du, dv) = p.degrees();
    let dim = p.dim();
    // The Bézier net the patch came from, exactly; else the Bernstein coefficients
    // b_kl = Σ_(a<=k, b<=l) C(k,a)/C(du,a) C(l,b)/C(dv,b) c_ab.
    let mut net = Vec::with_capacity((du + 1) * (dv + 1));
    let given = p.bezier_net();
    if let Some(given) = given {
        net.extend(given.chunks_exact(dim).map(<[f64]>::to_vec));
    }
    for k in (0..=du).filter(|_| given.is_none()) {
        for l in 0..=dv {
            let mut b = vec![0.0; dim];
            for a in 0..=k {
                let wa = binomial(k, a) / binomial(du, a);
                for bb in 0..=l {
                    let w = wa * binomial(l, bb) / binomial(dv, bb);
                    for (x, c) in b.iter_mut().zip(p.coefficient(a, bb)) {
                        *x += w * c;
                    }
                }
            }
            net.push(b);
        }
    }
    let points: Vec<[f64; 3]> = match (kind, dim) {
        (SurfaceKind::Explicit, 1) => net
            .iter()
            .enumerate()
            .map(|(idx, z)| {
                let (k, l) = (idx / (dv + 1), idx % (dv + 1));
                let x = u0 + (u1 - u0) * k as f64 / du.max(1) as f64;
                let y = v0 + (v1 - v0) * l as f64 / dv.max(1) as f64;
                [x, y, z[0]]
            })
            .collect(),
        (_, 2) => net.iter().map(|b| [b[0], b[1], 0.0]).collect(),
        (_, 3) => net.iter().map(|b| [b[0], b[1], b[2]]).collect(),
        (_, d) => {
            return Err(StepError::Unsupported(format!(
                "a composite surface in R^{d}: STEP geometry lives in R^3"
            )))
        }
    };
    if du == 0 || dv == 0 {
        return Err(StepError::Unsupported(format!(
            "patch ({i}, {j}) is constant along one direction (degrees {du}, {dv}): \
             not a surface"
        )));
    }
    Ok(NurbsSurface {
        degrees: (du, dv),
        knots_u: bezier_knots(du),
        knots_v: bezier_knots(dv),
        rows: du + 1,
        cols: dv + 1,
        points,
        weights: None,
        bezier: true,
    })
}

/// A composite surface of formula patches: one face per patch, the interpolating B-spline
/// of the patch on its cell (the patch's own domain mapped onto the cell, as geomkit
/// evaluates it; explicit patches z(x, y) as the points (x, y, z)).
fn formula_composite(
    s: &CompositeSurface,
    tolerance: f64,
) -> StepResult<(Content, Vec<Approximation>)> {
    let (n, m) = s.cells();
    let (uk, vk) = s.knots();
    let (dim, kind) = (s.dim(), s.kind());
    if !matches!((kind, dim), (SurfaceKind::Explicit, 1) | (_, 2) | (_, 3)) {
        return Err(StepError::Unsupported(format!(
            "a composite surface in R^{dim}: STEP geometry lives in R^3"
        )));
    }
    let mut pieces = Vec::with_capacity(n * m);
    let mut exact: Vec<Option<NurbsSurface>> = Vec::with_capacity(n * m);
    for i in 0..n {
        for j in 0..m {
            let Some(patch) = s.expr_patch(i, j) else {
                return Err(StepError::Unsupported(format!(
                    "patch ({i}, {j}) of a composite surface is neither a polynomial nor a formula"
                )));
            };
            let cell = ((uk[i], uk[i + 1]), (vk[j], vk[j + 1]));
            if let Some(poly) = patch.poly() {
                // A Bézier or polynomial patch among formulas: exact.
                exact.push(Some(poly_face(poly, kind, cell, (i, j))?));
                continue;
            }
            exact.push(None);
            let own = patch.domain().map(|d| (d[0], d[1]));
            let name = format!("patch ({i}, {j})");
            let label = name.clone();
            let eval = move |u: f64, v: f64| -> StepResult<[f64; 3]> {
                let (a, b) = match own {
                    Some(((a0, a1), (b0, b1))) => {
                        let ((u0, u1), (v0, v1)) = cell;
                        (
                            a0 + (a1 - a0) * ((u - u0) / (u1 - u0)),
                            b0 + (b1 - b0) * ((v - v0) / (v1 - v0)),
                        )
                    }
                    None => (u, v),
                };
                let at = format!("(u, v) = ({u}, {v})");
                let q = patch.eval(&[a, b]).map_err(|e| {
                    StepError::Unsupported(format!("{label}: cannot evaluate at {at}: {e}"))
                })?;
                let p = match (kind, dim) {
                    (SurfaceKind::Explicit, _) => [u, v, q[0]],
                    (_, 2) => [q[0], q[1], 0.0],
                    _ => [q[0], q[1], q[2]],
                };
                finite(&label, &at, p)
            };
            pieces.push(SurfacePiece {
                name,
                domain: cell,
                group: (i, j),
                eval: Box::new(eval),
            });
        }
    }
    let absolute = absolute_tolerance(tolerance, &pieces, &[])?;
    let fitted = approx::surfaces(&pieces, absolute)?;
    let (surfaces, approximations): (Vec<_>, Vec<_>) = fitted.into_iter().unzip();
    let mut surfaces = surfaces.into_iter();
    let faces = exact
        .into_iter()
        .map(|e| e.or_else(|| surfaces.next()).map(natural_face))
        .collect::<Option<Vec<_>>>()
        .expect("one surface per cell");
    Ok((Content::Faces(faces), approximations))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], k: f64) -> [f64; 3] {
    [a[0] * k, a[1] * k, a[2] * k]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The straight segment a -> b as a degree-1 curve.
fn line(a: [f64; 3], b: [f64; 3]) -> StepResult<NurbsCurve> {
    NurbsCurve::new(1, vec![0.0, 0.0, 1.0, 1.0], vec![a, b], None)
}

/// The circle c + r (cos τ, sin τ, 0) as the rational quadratic of 9 control points (four
/// quarter arcs, weights 1, √2/2, 1, ...), knots 0, 1/4, 1/2, 3/4, 1 (each twice inside).
fn circle_parts(c: [f64; 3], r: f64) -> (Vec<[f64; 3]>, Vec<f64>) {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let dirs = [
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (-1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (0.0, -1.0),
        (1.0, -1.0),
        (1.0, 0.0),
    ];
    let points = dirs
        .iter()
        .map(|&(x, y)| [c[0] + r * x, c[1] + r * y, c[2]])
        .collect();
    let weights = (0..9).map(|k| if k % 2 == 1 { h } else { 1.0 }).collect();
    (points, weights)
}

const CIRCLE_KNOTS: [f64; 12] = [
    0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
];

fn circle(c: [f64; 3], r: f64) -> StepResult<NurbsCurve> {
    let (points, weights) = circle_parts(c, r);
    NurbsCurve::new(2, CIRCLE_KNOTS.to_vec(), points, Some(weights))
}

/// One curve of a ruled surface as what a strip is made of.
enum Section {
    Point([f64; 3]),
    /// Vertices of a polyline (closed: the first repeated at the end).
    Polyline(Vec<[f64; 3]>),
    Circle([f64; 3], f64),
}

fn section(c: &RuledCurve) -> StepResult<Section> {
    Ok(match c {
        RuledCurve::Point(p) => Section::Point(*p),
        RuledCurve::Polyline { vertices, closed } => {
            let mut v = vertices.clone();
            if *closed {
                v.push(vertices[0]);
            }
            Section::Polyline(v)
        }
        RuledCurve::Circle { center, radius } => Section::Circle(*center, *radius),
        RuledCurve::Expr(_) => {
            return Err(StepError::Unsupported(
                "a ruled surface over a formula curve has no exact B-spline form (export \
                 ruled surfaces over points, polylines, polygons and circles)"
                    .into(),
            ))
        }
    })
}

/// The bilinear patch (degree 1 × 1 on [0, 1]²) of the net rows [p00, p01], [p10, p11] (u
/// along the rows' index).
fn bilinear(points: [[f64; 3]; 4]) -> NurbsSurface {
    NurbsSurface {
        degrees: (1, 1),
        knots_u: vec![0.0, 0.0, 1.0, 1.0],
        knots_v: vec![0.0, 0.0, 1.0, 1.0],
        rows: 2,
        cols: 2,
        points: points.to_vec(),
        weights: None,
        bezier: false,
    }
}

/// A plane patch (degree 1 × 1) over the square of half-side `r` about `c` in the plane
/// spanned by the unit vectors e1, e2 (its normal e1 × e2).
fn plane_square(c: [f64; 3], e1: [f64; 3], e2: [f64; 3], r: f64) -> NurbsSurface {
    let corner = |a: f64, b: f64| add(c, add(scale(e1, a * r), scale(e2, b * r)));
    bilinear([
        corner(-1.0, -1.0),
        corner(-1.0, 1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
    ])
}

/// A face of the body with a point and a direction to orient it by: `reference` is a point
/// (u, v) of the ruled surface inside the face, whose normal ∂R/∂u × ∂R/∂v the face's
/// normal is compared with.
struct Placed {
    face: FaceSpec,
    /// The face surface's parameters of a point inside the face.
    at: (f64, f64),
    reference: (f64, f64),
}

/// The numeric normal ∂S/∂u × ∂S/∂v of a surface at (u, v) (central differences with steps
/// 1e-6 of the domain).
fn normal_of(
    eval: &impl Fn(f64, f64) -> [f64; 3],
    ((u0, u1), (v0, v1)): ((f64, f64), (f64, f64)),
    u: f64,
    v: f64,
) -> [f64; 3] {
    let (hu, hv) = ((u1 - u0) * 1e-6, (v1 - v0) * 1e-6);
    let su = sub(eval(u + hu, v), eval(u - hu, v));
    let sv = sub(eval(u, v + hv), eval(u, v - hv));
    cross(su, sv)
}

fn ruled_eval(s: &RuledSurface) -> impl Fn(f64, f64) -> [f64; 3] + '_ {
    |u, v| {
        let q = s.eval(u, v);
        [q[0], q[1], q[2]]
    }
}

/// The numeric normal of the ruled surface at (u, v).
fn ruled_normal(s: &RuledSurface, u: f64, v: f64) -> [f64; 3] {
    normal_of(&ruled_eval(s), s.domain(), u, v)
}

/// The normal of a face's surface at (s, t) (central differences on its iso curves).
fn surface_normal(s: &NurbsSurface, a: f64, b: f64) -> StepResult<[f64; 3]> {
    let h = 1e-6;
    let p = |u: f64, v: f64| -> StepResult<[f64; 3]> { s.iso(true, v)?.eval(u) };
    let su = sub(p(a + h, b)?, p(a - h, b)?);
    let sv = sub(p(a, b + h)?, p(a, b - h)?);
    Ok(cross(su, sv))
}

/// The signed volume enclosed by a closed parametric surface, (1/3) ∫∫ S · (S_u × S_v) du dv
/// by the midpoint rule on `nu` × `nv` cells: its sign says whether S_u × S_v points out.
pub(crate) fn signed_volume(
    eval: impl Fn(f64, f64) -> [f64; 3],
    domain: ((f64, f64), (f64, f64)),
    (nu, nv): (usize, usize),
) -> f64 {
    let ((u0, u1), (v0, v1)) = domain;
    let (du, dv) = ((u1 - u0) / nu as f64, (v1 - v0) / nv as f64);
    let mut total = 0.0;
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (u0 + (i as f64 + 0.5) * du, v0 + (j as f64 + 0.5) * dv);
            total += dot(eval(u, v), normal_of(&eval, domain, u, v));
        }
    }
    total
}

/// Newell's normal of a closed polygon (first vertex repeated at the end).
fn newell(v: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for w in v.windows(2) {
        let (a, b) = (w[0], w[1]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

/// A cap: the plane face of a polygon or circle whose centre point is in its plane.
fn cap(p: [f64; 3], other: &Section, reference: (f64, f64)) -> StepResult<Option<Placed>> {
    let (normal, radius, start, bound) = match other {
        Section::Polyline(v) => {
            let n = newell(v);
            let r = v.iter().map(|q| norm(sub(*q, p))).fold(0.0, f64::max);
            let mut bound = Vec::new();
            for w in v.windows(2) {
                bound.push(line(w[0], w[1])?);
            }
            (n, r, v[0], bound)
        }
        Section::Circle(c, r) => {
            if norm(sub(*c, p)) > 1e-12 * (r + norm(*c)) {
                return Ok(None);
            }
            (
                [0.0, 0.0, 1.0],
                *r,
                add(*c, [*r, 0.0, 0.0]),
                vec![circle(*c, *r)?],
            )
        }
        Section::Point(_) => return Ok(None),
    };
    let len = norm(normal);
    if len.is_nan() || len <= 0.0 || radius.is_nan() || radius <= 0.0 {
        return Ok(None);
    }
    let n = scale(normal, 1.0 / len);
    // In the plane: every vertex within 1e-12 of the extent.
    if let Section::Polyline(v) = other {
        if v.iter()
            .any(|q| dot(sub(*q, p), n).abs() > 1e-12 * radius.max(norm(p)))
        {
            return Ok(None);
        }
    }
    let d = sub(start, p);
    let e1 = scale(d, 1.0 / norm(d));
    let e2 = cross(n, e1);
    // A little larger than the outline, so that no edge runs along the patch's border.
    let surface = plane_square(p, e1, e2, radius * 1.25);
    Ok(Some(Placed {
        face: FaceSpec {
            surface,
            bound: Some(bound),
            same_sense: true,
        },
        at: (0.5, 0.5),
        reference,
    }))
}

/// A ruled surface as faces: the strips between consecutive curves. A body whose first and
/// last curves are points (the caps' centres or an apex) is a closed solid.
pub(crate) fn ruled(s: &RuledSurface, tolerance: f64) -> StepResult<(Content, Vec<Approximation>)> {
    if s.curves().iter().any(|c| matches!(c, RuledCurve::Expr(_))) {
        return formula_ruled(s, tolerance);
    }
    let sections = s
        .curves()
        .iter()
        .map(section)
        .collect::<StepResult<Vec<_>>>()?;
    let ((u0, u1), _) = s.domain();
    let vs = s.v_values();
    let mut placed: Vec<Placed> = Vec::new();
    for k in 1..sections.len() {
        let (a, b) = (&sections[k - 1], &sections[k]);
        let v_mid = 0.5 * (vs[k - 1] + vs[k]);
        match (a, b) {
            (Section::Point(_), Section::Point(_)) => {}
            (Section::Point(p), other) | (other, Section::Point(p)) => {
                // A cap when the point lies in the curve's plane; else a cone or pyramid.
                let reference = (u0 + 0.37 * (u1 - u0), v_mid);
                // Discs are ruled from their centre (a rational patch with one side
                // collapsed, bounded by its own sides: no trimming curve to approximate).
                let disc = matches!(other, Section::Circle(..));
                if let Some(c) = cap(*p, other, reference)?.filter(|_| !disc) {
                    placed.push(c);
                    continue;
                }
                strip(s, k, a, b, &mut placed)?;
            }
            _ => strip(s, k, a, b, &mut placed)?,
        }
    }
    let closed = matches!(sections.first(), Some(Section::Point(_)))
        && matches!(sections.last(), Some(Section::Point(_)));
    let strips = s.v_values().len().max(2) - 1;
    let outward = signed_volume(ruled_eval(s), s.domain(), (256, 16 * strips)) > 0.0;
    let mut faces = Vec::with_capacity(placed.len());
    for p in placed {
        let nf = surface_normal(&p.face.surface, p.at.0, p.at.1)?;
        let nr = ruled_normal(s, p.reference.0, p.reference.1);
        let along = dot(nf, nr) > 0.0;
        let mut face = p.face;
        face.same_sense = if closed { along == outward } else { along };
        faces.push(face);
    }
    let content = if closed {
        Content::Solid(faces)
    } else {
        Content::Faces(faces)
    };
    Ok((content, Vec::new()))
}

/// A ruled surface over formula curves: each strip between consecutive curves the
/// interpolating B-spline of the surface on [u0, u1] × [v_(k-1), v_k] (all strips with the
/// same samples in u, so that consecutive strips share their curve as one edge); a closed
/// solid when the first and last curves are points.
fn formula_ruled(s: &RuledSurface, tolerance: f64) -> StepResult<(Content, Vec<Approximation>)> {
    let ((u0, u1), _) = s.domain();
    let vs = s.v_values();
    let pieces: Vec<SurfacePiece<'_>> = vs
        .windows(2)
        .enumerate()
        .map(|(k, w)| {
            let name = format!("strip {} (v in [{}, {}])", k + 1, w[0], w[1]);
            let label = name.clone();
            let (v0, v1) = (w[0], w[1]);
            let eval = move |u: f64, v: f64| -> StepResult<[f64; 3]> {
                let mut q = [0.0; 3];
                s.eval_into(u, v.clamp(v0, v1), &mut q);
                finite(&label, &format!("(u, v) = ({u}, {v})"), q)
            };
            SurfacePiece {
                name,
                domain: ((u0, u1), (v0, v1)),
                group: (0, k),
                eval: Box::new(eval) as approx::SurfaceEval<'_>,
            }
        })
        .collect();
    let absolute = absolute_tolerance(tolerance, &pieces, &[])?;
    let fitted = approx::surfaces(&pieces, absolute)?;
    let closed = matches!(s.curves().first(), Some(RuledCurve::Point(_)))
        && matches!(s.curves().last(), Some(RuledCurve::Point(_)));
    let strips = vs.len().max(2) - 1;
    // The faces have the ruled surface's parameters: their normals are its normals.
    let outward = signed_volume(ruled_eval(s), s.domain(), (256, 16 * strips)) > 0.0;
    let mut faces = Vec::with_capacity(fitted.len());
    let mut approximations = Vec::with_capacity(fitted.len());
    for (surface, a) in fitted {
        let mut face = natural_face(surface);
        face.same_sense = !closed || outward;
        faces.push(face);
        approximations.push(a);
    }
    let content = if closed {
        Content::Solid(faces)
    } else {
        Content::Faces(faces)
    };
    Ok((content, approximations))
}

/// The strip between sections a (at v_(k-1)) and b (at v_k) of `s`.
fn strip(
    s: &RuledSurface,
    k: usize,
    a: &Section,
    b: &Section,
    out: &mut Vec<Placed>,
) -> StepResult<()> {
    let ((u0, u1), _) = s.domain();
    let vs = s.v_values();
    let v_mid = 0.5 * (vs[k - 1] + vs[k]);
    match (a, b) {
        (Section::Circle(..) | Section::Point(_), Section::Circle(..) | Section::Point(_)) => {
            // Rational quadratic in u, linear in v: rows along u, columns a then b.
            let parts = |x: &Section| match x {
                Section::Circle(c, r) => circle_parts(*c, *r),
                Section::Point(p) => (vec![*p; 9], circle_parts([0.0; 3], 1.0).1),
                Section::Polyline(_) => unreachable!("circles and points only"),
            };
            let (pa, w) = parts(a);
            let (pb, _) = parts(b);
            let mut points = Vec::with_capacity(18);
            let mut weights = Vec::with_capacity(18);
            for i in 0..9 {
                points.push(pa[i]);
                points.push(pb[i]);
                weights.push(w[i]);
                weights.push(w[i]);
            }
            let surface = NurbsSurface {
                degrees: (2, 1),
                knots_u: CIRCLE_KNOTS.to_vec(),
                knots_v: vec![0.0, 0.0, 1.0, 1.0],
                rows: 9,
                cols: 2,
                points,
                weights: Some(weights),
                bezier: false,
            };
            out.push(Placed {
                face: natural_face(surface),
                at: (0.37, 0.5),
                reference: (u0 + 0.37 * (u1 - u0), v_mid),
            });
        }
        (Section::Polyline(_) | Section::Point(_), Section::Polyline(_) | Section::Point(_)) => {
            // Breakpoints: the vertices of either polyline on the common u.
            let params = |x: &Section| -> Vec<f64> {
                match x {
                    Section::Polyline(v) => {
                        let n = (v.len() - 1) as f64;
                        (0..v.len()).map(|i| i as f64 / n).collect()
                    }
                    _ => vec![0.0, 1.0],
                }
            };
            let mut breaks: Vec<f64> = params(a);
            breaks.extend(params(b));
            breaks.sort_by(f64::total_cmp);
            breaks.dedup();
            let at = |x: &Section, f: f64| -> [f64; 3] {
                match x {
                    Section::Point(p) => *p,
                    Section::Polyline(v) => {
                        let n = (v.len() - 1) as f64;
                        let t = f * n;
                        let i = (t.floor() as usize).min(v.len() - 2);
                        let g = t - i as f64;
                        if g == 0.0 {
                            v[i]
                        } else {
                            add(v[i], scale(sub(v[i + 1], v[i]), g))
                        }
                    }
                    Section::Circle(..) => unreachable!("polylines and points only"),
                }
            };
            for w in breaks.windows(2) {
                let (f0, f1) = (w[0], w[1]);
                let (a0, a1, b0, b1) = (at(a, f0), at(a, f1), at(b, f0), at(b, f1));
                let reference = (u0 + (0.5 * (f0 + f1)) * (u1 - u0), v_mid);
                if a0 == a1 || b0 == b1 {
                    // A triangle (one side is a point): a plane face bounded by its edges.
                    let (apex, q0, q1) = if a0 == a1 { (a0, b0, b1) } else { (b0, a0, a1) };
                    // u from the apex to q0, v from the apex to q1.
                    let surface = bilinear([apex, q1, q0, add(q0, sub(q1, apex))]);
                    let bound = vec![line(apex, q0)?, line(q0, q1)?, line(q1, apex)?];
                    out.push(Placed {
                        face: FaceSpec {
                            surface,
                            bound: Some(bound),
                            same_sense: true,
                        },
                        at: (1.0 / 3.0, 1.0 / 3.0),
                        reference,
                    });
                    continue;
                }
                let surface = bilinear([a0, b0, a1, b1]);
                out.push(Placed {
                    face: natural_face(surface),
                    at: (0.5, 0.5),
                    reference,
                });
            }
        }
        _ => {
            return Err(StepError::Unsupported(
                "a ruled strip between a polyline and a circle has no exact form here".into(),
            ))
        }
    }
    Ok(())
}
