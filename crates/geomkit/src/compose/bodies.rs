//! Closed bodies as single formulas: piecewise-ruled surfaces (formula (2) of
//! spec/composite-surfaces.md) over a point, one or two contours and a point. The cube is the
//! paper's; the others follow the same pattern. Sizes must be finite and > 0; polygons
//! simple, with at least 3 vertices, and star-shaped about their centroid (the caps are
//! ruled from it). Sizes and polygon coordinates are at most [`MAX_BODY_SIZE`] = 1e100 in
//! absolute value (their squares, in the polygon's area, stay finite).
//!
//! ```
//! use geomkit::compose::bodies;
//! let cube = bodies::cube().unwrap();
//! let p = cube.eval(0.5, 1.5);
//! assert_eq!(p.iter().fold(0.0f64, |m, x| m.max(x.abs())), 1.0);
//! ```

use super::ruled::{RuledCurve, RuledSurface};
use crate::{Error, Result};
use std::f64::consts::TAU;

/// The largest size of a body and the largest |coordinate| of a polygon: the squares of
/// the coordinates (the polygon's area and centroid) stay far inside f64.
pub const MAX_BODY_SIZE: f64 = 1e100;

fn positive(what: &'static str, name: &str, x: f64) -> Result<()> {
    if x.is_finite() && x > 0.0 && x <= MAX_BODY_SIZE {
        Ok(())
    } else {
        Err(Error::InvalidShape {
            what,
            reason: format!(
                "{name} = {} must be finite, > 0 and at most {MAX_BODY_SIZE:e}",
                super::grid::show(x)
            ),
        })
    }
}

fn lift(polygon: &[[f64; 2]], z: f64) -> Vec<[f64; 3]> {
    polygon.iter().map(|p| [p[0], p[1], z]).collect()
}

/// The paper's cube with vertices (±1, ±1, ±1): the ruled surface over the centre of the top
/// face, the top square, the bottom square and the centre of the bottom face, v = 0, 1, 2, 3,
/// u in [0, 4]. Its formula prints as the paper's.
pub fn cube() -> Result<RuledSurface> {
    rectangular_box(2.0, 2.0, 2.0)
}

/// The box [-a/2, a/2] × [-b/2, b/2] × [-c/2, c/2] (the cube for a = b = c = 2).
/// Errors: a size that is not finite and > 0.
pub fn rectangular_box(a: f64, b: f64, c: f64) -> Result<RuledSurface> {
    for (name, x) in [("a", a), ("b", b), ("c", c)] {
        positive("box size", name, x)?;
    }
    let (x, y) = (a / 2.0, b / 2.0);
    prism(&[[x, y], [-x, y], [-x, -y], [x, -y]], c)
}

/// The prism of height h over a polygon (z from -h/2 to h/2) with both caps: the ruled surface
/// over the top centre, the top polygon, the bottom polygon and the bottom centre, u in
/// [0, k] for k vertices. Errors: see [`check_polygon`]; h not > 0.
pub fn prism(polygon: &[[f64; 2]], h: f64) -> Result<RuledSurface> {
    positive("prism", "height", h)?;
    let c = check_polygon(polygon)?;
    let k = polygon.len() as f64;
    RuledSurface::new(
        vec![
            RuledCurve::Point([c[0], c[1], h / 2.0]),
            RuledCurve::polygon(lift(polygon, h / 2.0))?,
            RuledCurve::polygon(lift(polygon, -h / 2.0))?,
            RuledCurve::Point([c[0], c[1], -h / 2.0]),
        ],
        vec![0.0, 1.0, 2.0, 3.0],
        (0.0, k),
    )
}

/// The pyramid over a polygon in z = 0 with its apex at height h above the centroid, base
/// included: apex, base polygon, base centre. Errors: as [`prism`].
pub fn pyramid(polygon: &[[f64; 2]], h: f64) -> Result<RuledSurface> {
    positive("pyramid", "height", h)?;
    let c = check_polygon(polygon)?;
    RuledSurface::new(
        vec![
            RuledCurve::Point([c[0], c[1], h]),
            RuledCurve::polygon(lift(polygon, 0.0))?,
            RuledCurve::Point([c[0], c[1], 0.0]),
        ],
        vec![0.0, 1.0, 2.0],
        (0.0, polygon.len() as f64),
    )
}

/// The square pyramid with base side `a` centred at the origin and height h.
pub fn square_pyramid(a: f64, h: f64) -> Result<RuledSurface> {
    positive("pyramid", "base side", a)?;
    let x = a / 2.0;
    pyramid(&[[x, x], [-x, x], [-x, -x], [x, -x]], h)
}

/// The cone of base radius r (circle in z = 0) and height h, base included; u in [0, 2π].
pub fn cone(r: f64, h: f64) -> Result<RuledSurface> {
    positive("cone", "radius", r)?;
    positive("cone", "height", h)?;
    RuledSurface::new(
        vec![
            RuledCurve::Point([0.0, 0.0, h]),
            RuledCurve::Circle {
                center: [0.0, 0.0, 0.0],
                radius: r,
            },
            RuledCurve::Point([0.0, 0.0, 0.0]),
        ],
        vec![0.0, 1.0, 2.0],
        (0.0, TAU),
    )
}

/// The cylinder of radius r and height h (z from -h/2 to h/2) with both caps.
pub fn cylinder(r: f64, h: f64) -> Result<RuledSurface> {
    positive("cylinder", "radius", r)?;
    frustum(r, r, h)
}

/// The frustum of a cone with bottom radius r0, top radius r1 and height h (z from -h/2 to
/// h/2), both caps included.
pub fn frustum(r0: f64, r1: f64, h: f64) -> Result<RuledSurface> {
    positive("frustum", "bottom radius", r0)?;
    positive("frustum", "top radius", r1)?;
    positive("frustum", "height", h)?;
    let circle = |r: f64, z: f64| RuledCurve::Circle {
        center: [0.0, 0.0, z],
        radius: r,
    };
    RuledSurface::new(
        vec![
            RuledCurve::Point([0.0, 0.0, h / 2.0]),
            circle(r1, h / 2.0),
            circle(r0, -h / 2.0),
            RuledCurve::Point([0.0, 0.0, -h / 2.0]),
        ],
        vec![0.0, 1.0, 2.0, 3.0],
        (0.0, TAU),
    )
}

/// The most vertices of a body's polygon ([`check_polygon`], [`regular_polygon`]): its
/// formula has a term per vertex and its mesh a grid line per vertex, so 10000 keeps both at
/// about a second; a smoother base is a [`cylinder`] or [`cone`].
pub const MAX_POLYGON_VERTICES: usize = 10_000;

/// Checks a polygon for a body and returns its centroid: at least 3 and at most
/// [`MAX_POLYGON_VERTICES`] finite vertices, no two equal, no two edges crossing or touching
/// (simple), non-zero area, and star-shaped about the centroid (every edge seen from it with
/// the same orientation), so that the caps ruled from the centroid do not fold.
///
/// O(k) for a valid polygon: one star-shaped about its centroid that winds around it once is
/// simple (every ray from the centroid meets it once). Only an invalid one is searched for
/// crossing edges (O(k²), up to 4096 vertices) to say why. Computed on the vertices centred
/// on their bounding box and divided per axis by a power of two near the largest
/// |coordinate| along it, so sizes from 1e-300 to 1e300 neither underflow nor overflow and a
/// polygon far from the origin keeps its digits.
pub fn check_polygon(polygon: &[[f64; 2]]) -> Result<[f64; 2]> {
    let k = polygon.len();
    if k < 3 {
        return Err(Error::TooFewPoints {
            what: "polygon vertices",
            got: k,
            min: 3,
        });
    }
    if k > MAX_POLYGON_VERTICES {
        return Err(Error::InvalidShape {
            what: "polygon",
            reason: format!(
                "{k} vertices: at most {MAX_POLYGON_VERTICES} (use a cylinder or cone for a \
                 round base)"
            ),
        });
    }
    if let Some(index) = polygon
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(Error::NonFinite {
            what: "polygon vertex",
            index,
        });
    }
    if let Some(i) = polygon
        .iter()
        .position(|p| p[0].abs().max(p[1].abs()) > MAX_BODY_SIZE)
    {
        return Err(Error::InvalidShape {
            what: "polygon",
            reason: format!(
                "vertex {i} ({}, {}) is beyond ±{MAX_BODY_SIZE:e} (coordinates must be at most \
                 that in absolute value)",
                super::grid::show(polygon[i][0]),
                super::grid::show(polygon[i][1])
            ),
        });
    }
    let bad = |reason: String| Error::InvalidShape {
        what: "polygon",
        reason,
    };
    // Centred on the bounding box (no cancellation in the area of a polygon far from the
    // origin) and each axis scaled by a power of two, coordinates within [-2, 2]: an affine
    // map, which keeps simplicity, the centroid and star-shapedness about it.
    let mid = [0, 1].map(|a| {
        let lo = polygon.iter().fold(f64::INFINITY, |m, p| m.min(p[a]));
        let hi = polygon.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p[a]));
        lo / 2.0 + hi / 2.0
    });
    let s = [0, 1].map(|a| {
        let big = polygon
            .iter()
            .fold(0.0f64, |m, p| m.max((p[a] - mid[a]).abs()));
        if big == 0.0 || !big.is_finite() {
            1.0
        } else {
            big.log2().ceil().clamp(-1022.0, 1023.0).exp2()
        }
    });
    let poly: Vec<[f64; 2]> = polygon
        .iter()
        .map(|p| [(p[0] - mid[0]) / s[0], (p[1] - mid[1]) / s[1]])
        .collect();
    let back = |c: [f64; 2]| [mid[0] + c[0] * s[0], mid[1] + c[1] * s[1]];
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    // Area-weighted centroid.
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..k {
        let (a, b) = (poly[i], poly[(i + 1) % k]);
        let w = a[0] * b[1] - b[0] * a[1];
        area += w;
        cx += (a[0] + b[0]) * w;
        cy += (a[1] + b[1]) * w;
    }
    let c = [cx / (3.0 * area), cy / (3.0 * area)];
    let sign = if area > 0.0 { 1.0 } else { -1.0 };
    let star = area != 0.0
        && c[0].is_finite()
        && c[1].is_finite()
        && (0..k).all(|i| sign * cross(c, poly[i], poly[(i + 1) % k]) > 0.0);
    if star {
        // Each edge turns the same way about c: the angles add up to 2π times the number of
        // turns, and one turn means a simple polygon.
        let turn: f64 = (0..k)
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % k]);
                let (u, v) = ([a[0] - c[0], a[1] - c[1]], [b[0] - c[0], b[1] - c[1]]);
                (sign * (u[0] * v[1] - u[1] * v[0])).atan2(u[0] * v[0] + u[1] * v[1])
            })
            .sum();
        if (turn - std::f64::consts::TAU).abs() < std::f64::consts::PI {
            return Ok(back(c));
        }
    }
    // Invalid: say why.
    let mut seen = std::collections::HashMap::with_capacity(k);
    for (j, p) in polygon.iter().enumerate() {
        if let Some(i) = seen.insert([p[0].to_bits(), p[1].to_bits()], j) {
            return Err(bad(format!("vertices {i} and {j} coincide")));
        }
    }
    // Straddling without multiplying the two crosses (their product may underflow).
    let straddle = |d1: f64, d2: f64| (d1 <= 0.0 && d2 >= 0.0) || (d1 >= 0.0 && d2 <= 0.0);
    if k <= 4096 {
        for i in 0..k {
            let (a, b) = (poly[i], poly[(i + 1) % k]);
            for j in i + 1..k {
                if j == i + 1 || (i == 0 && j == k - 1) {
                    continue; // neighbours share a vertex
                }
                let (c, d) = (poly[j], poly[(j + 1) % k]);
                if straddle(cross(a, b, c), cross(a, b, d))
                    && straddle(cross(c, d, a), cross(c, d, b))
                {
                    return Err(bad(format!(
                        "edges {i} and {j} intersect: the polygon is not simple"
                    )));
                }
            }
        }
    }
    if area == 0.0 {
        return Err(bad("its area is zero".into()));
    }
    match (0..k).find(|&i| sign * cross(c, poly[i], poly[(i + 1) % k]) <= 0.0) {
        Some(i) => Err(bad(format!(
            "it is not star-shaped about its centroid ({}, {}): edge {i} faces away, so the \
             caps ruled from the centroid would fold",
            back(c)[0],
            back(c)[1]
        ))),
        None => Err(bad(
            "it winds more than once around its centroid: the polygon is not simple".into(),
        )),
    }
}

/// The regular n-gon of circumradius r centred at the origin, vertex 0 at (r, 0).
/// Errors: n < 3 or above [`MAX_POLYGON_VERTICES`], r not > 0.
pub fn regular_polygon(n: usize, r: f64) -> Result<Vec<[f64; 2]>> {
    if n < 3 {
        return Err(Error::TooFewPoints {
            what: "polygon vertices",
            got: n,
            min: 3,
        });
    }
    if n > MAX_POLYGON_VERTICES {
        return Err(Error::InvalidShape {
            what: "regular polygon",
            reason: format!("{n} vertices: at most {MAX_POLYGON_VERTICES}"),
        });
    }
    positive("regular polygon", "radius", r)?;
    Ok((0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            [r * a.cos(), r * a.sin()]
        })
        .collect())
}
