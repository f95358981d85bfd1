//! Demo items of method 3 (spec/composite-surfaces.md): bodies as one formula (the paper's
//! cube, a pyramid, a cone, a capped cylinder) drawn by the structural evaluator with their
//! formulas in the caption, and a composite surface of bicubic patches with its formula size
//! and the formula-vs-structural agreement.

use super::{Check, Context, Item, Report};
use anyhow::Result;
use geomkit::bspline::{interpolate_surface, SurfaceInterpolationOptions};
use geomkit::compose::{bodies, CompositeSurface, ExprPatch, Piecewise, RuledSurface, SurfaceKind};
use geomkit::expr::Format;
use geomkit_plot::figures::linspace;
use geomkit_plot::figures::{piecewise_svg, wireframe_svg};
use geomkit_plot::svg::escape;

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
        Item {
            id: "compose-expr-patches",
            title: "A composite surface of formula patches (plane, quarter cylinder, plane)",
            run: expr_patches,
        },
        Item {
            id: "compose-piecewise",
            title: "A piecewise function plotted from its single formula (§5)",
            run: piecewise,
        },
    ]
}

/// Largest |formula (by the tape) - structural| of a composite on a k×k grid of its domain
/// widened by a quarter, with every knot line.
fn composite_agreement(s: &CompositeSurface, k: usize) -> Result<f64> {
    let f = s.formula()?;
    let ((u0, u1), (v0, v1)) = s.domain();
    let (uk, vk) = s.knots();
    let mut us = linspace(u0 - (u1 - u0) / 4.0, u1 + (u1 - u0) / 4.0, k);
    let mut vs = linspace(v0 - (v1 - v0) / 4.0, v1 + (v1 - v0) / 4.0, k);
    us.extend_from_slice(uk);
    vs.extend_from_slice(vk);
    let (pu, pv): (Vec<f64>, Vec<f64>) = us
        .iter()
        .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
        .unzip();
    let d = s.dim();
    let mut printed = vec![0.0; pu.len() * d];
    f.eval_batch(&[&pu, &pv], &mut printed)?;
    let uv: Vec<f64> = pu.iter().zip(&pv).flat_map(|(&u, &v)| [u, v]).collect();
    let mut structural = vec![0.0; pu.len() * d];
    s.eval_many(&uv, &mut structural)?;
    Ok(printed
        .iter()
        .zip(&structural)
        .fold(0.0f64, |w, (a, b)| w.max((a - b).abs())))
}

fn expr_patches(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "A channel with a rounded corner from three patches given as formulas in u, v: the plane \
         x = 1, a quarter cylinder given on its own domain (angle 0..π/2, height 0..1) and \
         mapped onto its cell by the paper's change of variables, and the plane y = 1; two \
         rows in v. Drawn by the structural evaluator (one compiled tape per cell); the caption \
         holds the single formula (9).",
    );
    let p = |x: &str, y: &str, z: &str, domain: Option<Vec<(f64, f64)>>| {
        ExprPatch::parse(&[("x", x), ("y", y), ("z", z)], &["u", "v"], domain)
    };
    let quarter = Some(vec![(0.0, std::f64::consts::FRAC_PI_2), (0.0, 1.0)]);
    let lower = [
        p("1", "u - 1", "v", None)?,
        p("cos(u)", "sin(u)", "v", quarter.clone())?,
        p("2 - u", "1", "v", None)?,
    ];
    let upper = [
        p("1 + (v - 1)^2/4", "u - 1", "v", None)?,
        p("cos(u)*(1 + v^2/4)", "sin(u)*(1 + v^2/4)", "v + 1", quarter)?,
        p("2 - u", "1 + (v - 1)^2/4", "v", None)?,
    ];
    let rows = (0..3)
        .map(|i| vec![lower[i].clone(), upper[i].clone()])
        .collect();
    let s = CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0, 3.0],
        vec![0.0, 1.0, 2.0],
        rows,
        SurfaceKind::Parametric,
    )?;
    let f = s.formula()?;
    let svg = wireframe_svg(
        &s,
        "formula patches",
        &format!("3×2 patches, {} DAG operations", f.op_count()),
        13,
    )?;
    let text = f.print(Format::Maple)?;
    r.picture(
        ctx,
        "compose-expr-patches.svg",
        &svg,
        &text.replace('\n', "; "),
    )?;
    r.html.push_str(&format!("<pre>{}</pre>\n", escape(&text)));
    r.check(Check::at_most(
        "continuity: largest jump between patches (sampled)",
        s.continuity().max_jump,
        s.continuity().tolerance,
    ));
    r.check(Check::at_most(
        "formula vs structural evaluator (81² points + knot lines, also outside)",
        composite_agreement(&s, 81)?,
        1e-12,
    ));
    let corner = s.eval(1.5, 0.5);
    let a = std::f64::consts::FRAC_PI_4;
    r.check(Check::at_most(
        "middle of the quarter cylinder at (cos π/4, sin π/4, 1/2)",
        (corner[0] - a.cos()).abs() + (corner[1] - a.sin()).abs() + (corner[2] - 0.5).abs(),
        1e-15,
    ));
    // Patches that do not meet: formula (11) shifts them, the structural evaluator agrees.
    let z = |f: &str| ExprPatch::parse(&[("z", f)], &["x", "y"], None);
    let jump = CompositeSurface::from_expr(
        vec![0.0, 1.0, 2.0],
        vec![0.0, 1.0],
        vec![vec![z("x*y")?], vec![z("x*y + 3 + sin(y)")?]],
        SurfaceKind::Explicit,
    )?;
    r.check(Check::equal(
        "height patches jumping by 3 + sin(y): reported not continuous",
        jump.continuity().is_continuous(),
        false,
    ));
    r.check(Check::at_most(
        "…their shifted formula (11) vs structural evaluator",
        composite_agreement(&jump, 81)?,
        1e-12,
    ));
    Ok(r)
}

fn piecewise(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "A function of four pieces — (x + 2)², 1 − x(x + 1), cos(πx/2), (x − 1)(3 − x) on [−2, −1], \
         [−1, 0], [0, 1], [1, 2] — as one formula F(x) = F_0(x) + Σ (F_i(x) − F_i(x_i)) with \
         F_i(x) = f_i(x_i + (x_(i+1) − x_i) P(x, x_i, x_(i+1) − x_i)) (spec §5), plotted from \
         the formula; the dots are the breakpoints by the structural evaluator.",
    );
    let pieces = [
        "(x + 2)^2",
        "1 - x*(x + 1)",
        "cos(pi*x/2)",
        "(x - 1)*(3 - x)",
    ];
    let p = Piecewise::function(vec![-2.0, -1.0, 0.0, 1.0, 2.0], &pieces)?;
    let f = p.formula()?;
    let text = f.print(Format::Maple)?;
    let svg = piecewise_svg(&p, "piecewise function", "four pieces, one formula")?;
    r.picture(ctx, "compose-piecewise.svg", &svg, text.trim())?;
    r.html.push_str(&format!("<pre>{}</pre>\n", escape(&text)));
    r.check(Check::at_most(
        "formula vs piecewise evaluation (2001 points and every breakpoint, also outside)",
        p.formula_deviation(2001)?,
        1e-14,
    ));
    let direct = |x: f64| match x {
        x if x <= -1.0 => (x + 2.0).powi(2),
        x if x <= 0.0 => 1.0 - x * (x + 1.0),
        x if x <= 1.0 => (std::f64::consts::PI * x / 2.0).cos(),
        x => (x - 1.0) * (3.0 - x),
    };
    let worst = linspace(-2.0, 2.0, 401)
        .into_iter()
        .fold(0.0f64, |w, x| w.max((p.eval(x)[0] - direct(x)).abs()));
    r.check(Check::at_most(
        "piecewise evaluation vs the pieces themselves (401 points)",
        worst,
        1e-15,
    ));
    r.check(Check::at_most(
        "continuity: largest jump at a breakpoint",
        p.continuity().max_jump,
        p.continuity().tolerance,
    ));
    r.text = format!("{} DAG operations", f.op_count());
    Ok(r)
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
    let text = f.print(Format::Maple)?;
    let svg = wireframe_svg(s, name, text.lines().next().unwrap_or_default(), 16)?;
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
    let svg = wireframe_svg(
        &s,
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
        75.0,
    ));
    r.text = format!("{n}×{m} bicubic patches: {} DAG operations", f.op_count());
    Ok(r)
}
