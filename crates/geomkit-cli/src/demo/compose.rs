//! Demo items of method 3 (spec/composite-surfaces.md): bodies as one formula (the paper's
//! cube, a pyramid, a cone, a capped cylinder) drawn by the structural evaluator with their
//! formulas in the caption, and a composite surface of bicubic patches with its formula size
//! and the formula-vs-structural agreement.

use super::{Check, Context, Item, Report};
use crate::commands::compose::{composite_view, picture, ruled_view};
use crate::svg::escape;
use anyhow::Result;
use geomkit::bspline::{interpolate_surface, SurfaceInterpolationOptions};
use geomkit::compose::{bodies, CompositeSurface, RuledSurface};
use geomkit::expr::Format;

/// The items, in order.
pub fn items() -> Vec<Item> {
    vec![
        Item {
            id: "compose-cube",
            title: "The cube as one formula (Dolya, §2)",
            run: cube,
        },
        Item {
            id: "compose-bodies",
            title: "Pyramid, cone and capped cylinder as one formula each",
            run: other_bodies,
        },
        Item {
            id: "compose-bicubic",
            title: "A composite surface of 10×12 bicubic patches as one formula (9)",
            run: bicubic,
        },
    ]
}

/// Largest difference between the printed formula (by the engine's tape) and the structural
/// evaluator on a k×k grid of the domain plus points outside it.
fn agreement(s: &RuledSurface, k: usize) -> Result<f64> {
    let f = s.formula()?;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (mut us, mut vs) = (Vec::new(), Vec::new());
    for a in 0..=k {
        for b in 0..=k {
            us.push(u0 - 0.5 + (u1 - u0 + 1.0) * a as f64 / k as f64);
            vs.push(v0 - 0.5 + (v1 - v0 + 1.0) * b as f64 / k as f64);
        }
    }
    let mut out = vec![0.0; us.len() * 3];
    f.eval_batch(&[&us, &vs], &mut out)?;
    let mut worst = 0.0f64;
    for (i, p) in out.chunks_exact(3).enumerate() {
        let q = s.eval(us[i], vs[i]);
        for c in 0..3 {
            worst = worst.max((p[c] - q[c]).abs());
        }
    }
    Ok(worst)
}

fn body_item(
    ctx: &Context,
    r: &mut Report,
    file: &str,
    name: &str,
    s: &RuledSurface,
) -> Result<()> {
    let f = s.formula()?;
    let text = f.print(Format::Maple);
    let svg = picture(
        &ruled_view(s),
        name,
        text.lines().next().unwrap_or_default(),
        16,
    )?;
    r.picture(
        ctx,
        file,
        &svg,
        &format!("{name}: {}", text.replace('\n', "; ")),
    )?;
    r.html.push_str(&format!("<pre>{}</pre>\n", escape(&text)));
    r.check(Check::at_most(
        format!("{name}: formula vs structural evaluator (max abs, 41² points)"),
        agreement(s, 40)?,
        1e-13,
    ));
    r.check(Check::at_most(
        format!("{name}: formula size (DAG operations)"),
        f.op_count() as f64,
        80.0,
    ));
    Ok(())
}

fn cube(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "The paper's cube with vertices (±1, ±1, ±1): the piecewise-ruled surface (2) over the top \
         centre, the top square, the bottom square and the bottom centre, printed exactly as in \
         the paper.",
    );
    let s = bodies::cube()?;
    body_item(ctx, &mut r, "compose-cube.svg", "cube", &s)?;
    let f = s.formula()?;
    let (mut worst, mut corners) = (0.0f64, std::collections::BTreeSet::new());
    let k = 300; // u = 4a/300 and v = 3b/300 hit every knot (corners at u, v integers)
    let (mut us, mut vs) = (Vec::new(), Vec::new());
    for a in 0..=k {
        for b in 0..=k {
            us.push(4.0 * a as f64 / k as f64);
            vs.push(3.0 * b as f64 / k as f64);
        }
    }
    let mut out = vec![0.0; us.len() * 3];
    f.eval_batch(&[&us, &vs], &mut out)?;
    for p in out.chunks_exact(3) {
        let m = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        worst = worst.max((m - 1.0).abs());
        if p.iter().all(|x| x.abs() == 1.0) {
            corners.insert([p[0] > 0.0, p[1] > 0.0, p[2] > 0.0]);
        }
    }
    r.check(Check::at_most(
        "| max(|x|,|y|,|z|) - 1 | over 301² points of the formula",
        worst,
        1e-15,
    ));
    r.check(Check::equal("corners reached", corners.len(), 8));
    let mut g = f.graph.clone();
    let paper = geomkit::expr::parse(
        &mut g,
        "1/2*(1 - abs(u) + abs(u-1) + abs(u-2) - abs(u-3))*(abs(v) - abs(v-1) - abs(v-2) + abs(v-3))",
    )?;
    r.check(Check::equal(
        "x(u,v) is the paper's formula (same DAG node)",
        paper == f.roots[0],
        true,
    ));
    Ok(r)
}

fn other_bodies(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "Bodies built like the cube: a square pyramid (apex, base square, base centre), a cone \
         (apex, base circle, base centre) and a cylinder with both caps (centre, circle, circle, \
         centre). Each picture is drawn by the structural evaluator; the caption holds its \
         single formula.",
    );
    body_item(
        ctx,
        &mut r,
        "compose-pyramid.svg",
        "pyramid",
        &bodies::square_pyramid(2.0, 1.5)?,
    )?;
    body_item(
        ctx,
        &mut r,
        "compose-cone.svg",
        "cone",
        &bodies::cone(1.0, 2.0)?,
    )?;
    body_item(
        ctx,
        &mut r,
        "compose-cylinder.svg",
        "cylinder",
        &bodies::cylinder(1.0, 2.0)?,
    )?;
    Ok(r)
}

fn bicubic(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "A bicubic B-spline surface interpolating z = sin(x) cos(y) on a 13×15 grid, split into \
         its 10×12 polynomial cells and written as one formula (9): each cell's patch in Horner \
         form in the ramps of its row and column.",
    );
    let grid: Vec<Vec<Vec<f64>>> = (0..13)
        .map(|i| {
            (0..15)
                .map(|j| {
                    let (x, y) = (i as f64 * 0.5, j as f64 * 0.45);
                    vec![x, y, x.sin() * y.cos()]
                })
                .collect()
        })
        .collect();
    let fit = interpolate_surface(&grid, &SurfaceInterpolationOptions::default())?;
    let s = CompositeSurface::from_bspline(&fit.surface)?;
    let f = s.formula()?;
    let (n, m) = s.cells();
    let svg = picture(
        &composite_view(&s),
        "composite of bicubic patches",
        &format!("{n}×{m} patches, {} DAG operations", f.op_count()),
        25,
    )?;
    r.picture(
        ctx,
        "compose-bicubic.svg",
        &svg,
        "structural evaluator, 25 iso-lines per direction",
    )?;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (mut us, mut vs) = (Vec::new(), Vec::new());
    let k = 120;
    for a in 0..=k {
        for b in 0..=k {
            us.push(u0 + (u1 - u0) * a as f64 / k as f64);
            vs.push(v0 + (v1 - v0) * b as f64 / k as f64);
        }
    }
    let mut out = vec![0.0; us.len() * 3];
    f.eval_batch(&[&us, &vs], &mut out)?;
    let mut worst = 0.0f64;
    for (i, p) in out.chunks_exact(3).enumerate() {
        let q = s.eval(us[i], vs[i]);
        for c in 0..3 {
            worst = worst.max((p[c] - q[c]).abs());
        }
    }
    r.check(Check::at_most(
        "formula vs structural evaluator (121² points incl. knot lines)",
        worst,
        1e-12,
    ));
    r.check(Check::at_most(
        "continuity: largest jump between patches",
        s.continuity().max_jump,
        s.continuity().tolerance,
    ));
    r.check(Check::at_most(
        "formula size per patch (DAG operations)",
        f.op_count() as f64 / (n * m) as f64,
        81.0,
    ));
    r.text = format!("{n}×{m} bicubic patches: {} DAG operations", f.op_count());
    Ok(r)
}
