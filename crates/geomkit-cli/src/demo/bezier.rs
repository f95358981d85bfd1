//! Demo items of method 1, the unified change of order of Bézier curves and surfaces
//! (Nikulin 2011, spec/bezier-order.md): Fig. 1 a–c, Fig. 2 / Example 2, Fig. 4, Fig. 5, the
//! approximate reduction, and the precision of the paper's f64 formula against ours.

use super::{sci, Check, Context, Item, Report};
use crate::model::{BezierModel, ErrorReport};
use anyhow::{ensure, Result};
use geomkit::bezier::{
    paper_formula_f64, ApproxOptions, BezierCurve, BezierSurface, Direction, ReductionNorm,
};
use geomkit::exact::{degree_change_matrix, rational_from_f64, ExactBezierCurve};
use geomkit::geom::Curve;
use geomkit_plot::figures::{curve_change_svg, surface_svg, surface_with_net, Layer};
use geomkit_plot::svg::{escape, palette, Axes, Figure, Stroke};
use std::fmt::Write as _;

const EPS: f64 = f64::EPSILON;

/// The Bézier items, in the paper's order.
pub fn items() -> Vec<Item> {
    vec![
        Item {
            id: "fig1a",
            title: "Fig. 1a: elevation 2 → 3",
            run: |ctx| fig1(ctx, "fig1a", "a", &QUADRATIC, 3),
        },
        Item {
            id: "fig1b",
            title: "Fig. 1b: elevation 3 → 4",
            run: |ctx| fig1(ctx, "fig1b", "b", &CUBIC, 4),
        },
        Item {
            id: "fig1c",
            title: "Fig. 1c: elevation 3 → 5 in one step",
            run: |ctx| fig1(ctx, "fig1c", "c", &CUBIC, 5),
        },
        Item {
            id: "fig2",
            title: "Fig. 2 / Example 2: exact reduction 5 → 3",
            run: fig2,
        },
        Item {
            id: "fig4",
            title: "Fig. 4: adding or removing a row of the net changes the surface",
            run: fig4,
        },
        Item {
            id: "fig5",
            title: "Fig. 5: surface order change (4,3) → (3,3) → (3,6)",
            run: fig5,
        },
        Item {
            id: "approx",
            title: "Approximate reduction 12 → 5: L2, C1/C1, Chebyshev",
            run: approx,
        },
        Item {
            id: "precision",
            title: "Precision: the paper's f64 formula against ours, degrees 10–50",
            run: precision,
        },
    ]
}

// ---------------------------------------------------------------------------------------------
// data

const QUADRATIC: [[f64; 2]; 3] = [[0.0, 0.0], [3.5, 6.0], [9.0, 1.0]];
const CUBIC: [[f64; 2]; 4] = [[0.0, 0.0], [1.5, 5.5], [7.0, 6.5], [9.5, 1.0]];
/// The paper's Example 2: a formally quintic curve of real degree 3.
const EXAMPLE2: [[f64; 2]; 6] = [
    [10.0, 0.0],
    [22.0, 6.0],
    [19.0, 12.0],
    [11.0, 15.0],
    [8.0, 12.0],
    [20.0, 0.0],
];
/// Its power coefficients S_5 as the paper prints them (rows x and y).
const EXAMPLE2_S5: [[i64; 6]; 2] = [[10, 60, -150, 100, 0, 0], [0, 30, 0, -30, 0, 0]];
/// The cubic of Example 2, exactly: U_5 H_5 E H_3^-1.
const EXAMPLE2_CUBIC: [[f64; 2]; 4] = [[10.0, 0.0], [30.0, 10.0], [0.0, 20.0], [20.0, 0.0]];

fn curve(points: &[[f64; 2]]) -> Result<BezierCurve> {
    Ok(BezierCurve::new(
        points.iter().map(|p| p.to_vec()).collect(),
    )?)
}

/// The paper's matrices of Example 1, as printed (rows of K = H_n E H_n'^-1).
fn example1_matrix(n: usize, target: usize) -> Option<&'static str> {
    match (n, target) {
        (2, 3) => Some("[1 1/3 0 0]\n[0 2/3 2/3 0]\n[0 0 1/3 1]\n"),
        (3, 4) => Some("[1 1/4 0 0 0]\n[0 3/4 1/2 0 0]\n[0 0 1/2 3/4 0]\n[0 0 0 1/4 1]\n"),
        (3, 5) => Some(
            "[1 2/5 1/10 0 0 0]\n[0 3/5 3/5 3/10 0 0]\n[0 0 3/10 3/5 3/5 0]\n[0 0 0 1/10 2/5 1]\n",
        ),
        _ => None,
    }
}

// ---------------------------------------------------------------------------------------------
// measuring

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// max of NaN-propagating values.
fn nan_max(acc: f64, x: f64) -> f64 {
    if acc.is_nan() || x.is_nan() {
        f64::NAN
    } else {
        acc.max(x)
    }
}

/// Largest distance between corresponding points of two row-major point lists (NaN or inf
/// if either holds such values; inf if the lengths differ).
fn max_point_distance(a: &[f64], b: &[f64], dim: usize) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.chunks_exact(dim)
        .zip(b.chunks_exact(dim))
        .map(|(p, q)| distance(p, q))
        .fold(0.0, nan_max)
}

/// Largest distance between two curves over `count` uniform parameters, and where.
fn sampled_distance(a: &dyn Curve, b: &dyn Curve, count: usize) -> (f64, f64) {
    (0..count)
        .map(|k| {
            let t = k as f64 / (count - 1) as f64;
            (distance(&a.eval(t), &b.eval(t)), t)
        })
        .fold((0.0, 0.0), |acc, x| if x.0 > acc.0 { x } else { acc })
}

/// Largest distance between two surfaces on a `k`×`k` grid.
fn grid_distance(a: &BezierSurface, b: &BezierSurface, k: usize) -> Result<f64> {
    let ts: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
    let d = a.dim();
    let mut ga = vec![0.0; k * k * d];
    let mut gb = ga.clone();
    a.eval_grid(&ts, &ts, &mut ga)?;
    b.eval_grid(&ts, &ts, &mut gb)?;
    Ok(max_point_distance(&ga, &gb, d))
}

/// The exact result of formula (10) for `curve` at `target`, rounded once to f64.
fn exact_change(curve: &BezierCurve, target: usize) -> Result<Vec<f64>> {
    let exact = ExactBezierCurve::from_f64(curve.dim(), curve.points_flat())?;
    Ok(exact.change_degree(target)?.to_f64())
}

fn matrix_html(title: &str, text: &str) -> String {
    format!("<p>{title}</p>\n<pre>{}</pre>\n", escape(text.trim_end()))
}

// ---------------------------------------------------------------------------------------------
// Fig. 1

fn fig1(
    ctx: &Context,
    id: &str,
    letter: &str,
    points: &[[f64; 2]],
    target: usize,
) -> Result<Report> {
    let old = curve(points)?;
    let n = old.degree();
    let new = old.elevate_degree(target)?;
    let scale = old.scale();
    let one_step = target == n + 1;
    let mut r = Report::new(format!(
        "Nikulin (2011), Fig. 1{letter}: a Bézier curve of degree {n} with its control polygon \
         u0…u{n} (dashed) and the polygon u′0…u′{target} of the same curve elevated to degree \
         {target}{} by formula (8), U′ = U·H{n}·E·H{target}⁻¹. The curve does not move; the \
         new polygon lies inside the old one's convex hull{}.",
        if one_step { "" } else { " in one step" },
        if one_step {
            ", its vertices on the old edges (the classic step (6))"
        } else {
            ""
        }
    ));
    let svg = curve_change_svg(
        &format!("Fig. 1{letter}: degree elevation {n} → {target}"),
        &format!("{} → {} control points, same curve", n + 1, target + 1),
        (&old, &old.points()),
        (None, &new.points()),
    )?;
    r.picture(
        ctx,
        &format!("{id}.svg"),
        &svg,
        "Old polygon (grey, dashed), new polygon (orange), the curve (blue).",
    )?;
    r.model(
        ctx,
        &format!("{id}_degree{n}.json"),
        &BezierModel::Curve(old.clone()),
        None,
        "input",
    )?;
    r.model(
        ctx,
        &format!("{id}_degree{target}.json"),
        &BezierModel::Curve(new.clone()),
        None,
        "elevated",
    )?;

    let (d, _) = sampled_distance(&old, &new, 1001);
    r.check(Check::at_most(
        "old and new curve: max distance at 1001 points",
        d,
        1e-14 * scale,
    ));
    let exact = exact_change(&old, target)?;
    r.check(Check::at_most(
        "new control points vs exact rationals (max distance)",
        max_point_distance(new.points_flat(), &exact, 2),
        4.0 * EPS * scale,
    ));
    let m = degree_change_matrix(n, target);
    if let Some(paper) = example1_matrix(n, target) {
        r.check(Check::equal(
            format!("exact H{n}·E·H{target}⁻¹ equals the paper's Example 1 matrix"),
            if m.to_string() == paper {
                "identical"
            } else {
                "differs"
            },
            "identical",
        ));
    }
    r.html = matrix_html(
        &format!(
            "The exact matrix K = H<sub>{n}</sub> E H<sub>{target}</sub><sup>−1</sup> of \
             formula (8) (row i holds the weights of u<sub>i</sub> in the new points):"
        ),
        &m.to_string(),
    );
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// Fig. 2 / Example 2

fn fig2(ctx: &Context) -> Result<Report> {
    let quintic = curve(&EXAMPLE2)?;
    let scale = quintic.scale();
    let report = quintic.degree_report(None)?;
    let cubic = quintic.reduce_degree(report.real_degree, None)?;
    let back = cubic.elevate_degree(5)?;
    let exact = ExactBezierCurve::from_f64(2, quintic.points_flat())?;

    let mut r = Report::new(format!(
        "Nikulin (2011), Example 2 and Fig. 2: the six points u0…u5 define a curve of formal \
         degree 5 whose power coefficients S5 = U5·H5 end in two zero columns, so its real degree \
         is 3 (defect 2). Formula (9)/(10) gives the cubic with the same curve; elevating the \
         cubic back gives the six points again. The residual test finds the same without the \
         power form: relative residual {} at degree 3, {} at degree 2 (tolerance {}).",
        sci(report.residual),
        report.rejected_residual.map_or("-".into(), sci),
        sci(report.tolerance),
    ));
    let svg = curve_change_svg(
        "Fig. 2 / Example 2: exact reduction 5 → 3",
        "six points of real degree 3 and the cubic of the same curve",
        (&quintic, &quintic.points()),
        (None, &cubic.points()),
    )?;
    r.picture(
        ctx,
        "fig2.svg",
        &svg,
        "The quintic's polygon (grey, dashed), the cubic's polygon (orange), the common curve.",
    )?;
    r.model(
        ctx,
        "fig2_degree5.json",
        &BezierModel::Curve(quintic.clone()),
        None,
        "Example 2",
    )?;
    r.model(
        ctx,
        "fig2_degree3.json",
        &BezierModel::Curve(cubic.clone()),
        None,
        "the cubic",
    )?;

    r.check(Check::equal(
        "degree report (n, n*, d)",
        format!(
            "({}, {}, {})",
            report.degree, report.real_degree, report.defect
        ),
        "(5, 3, 2)".to_string(),
    ));
    let s = exact.to_power();
    let mismatches = (0..6)
        .flat_map(|j| (0..2).map(move |k| (j, k)))
        .filter(|&(j, k)| {
            Some(&s[j * 2 + k]) != rational_from_f64(EXAMPLE2_S5[k][j] as f64).as_ref()
        })
        .count();
    r.check(Check::equal(
        "exact S5 = U5·H5 vs the paper's (entries that differ)",
        mismatches,
        0,
    ));
    r.check(Check::equal(
        "exact real degree (zero columns of S5)",
        exact.real_degree(),
        3,
    ));
    let want: Vec<f64> = EXAMPLE2_CUBIC.iter().flatten().copied().collect();
    r.check(Check::at_most(
        "f64 cubic vs the exact cubic (10,0),(30,10),(0,20),(20,0)",
        max_point_distance(cubic.points_flat(), &want, 2),
        4.0 * EPS * scale,
    ));
    r.check(Check::at_most(
        "f64 cubic re-elevated to degree 5 vs the six points",
        max_point_distance(back.points_flat(), quintic.points_flat(), 2),
        1e-13,
    ));
    let exact_cubic = exact.change_degree(3)?;
    r.check(Check::equal(
        "exact cubic elevated back to degree 5 equals Example 2",
        if exact_cubic.change_degree(5)? == exact {
            "identical"
        } else {
            "differs"
        },
        "identical",
    ));
    let (d, _) = sampled_distance(&quintic, &cubic, 1001);
    r.check(Check::at_most(
        "quintic and cubic: max distance at 1001 points",
        d,
        1e-13 * scale,
    ));

    let mut s_text = String::new();
    for k in 0..2 {
        let row: Vec<String> = (0..6).map(|j| s[j * 2 + k].to_string()).collect();
        let _ = writeln!(s_text, "[{}]", row.join(" "));
    }
    r.html = matrix_html(
        "Power coefficients S<sub>5</sub> = U<sub>5</sub> H<sub>5</sub> (exact; rows x and y):",
        &s_text,
    );
    r.html += &matrix_html(
        "The reduction matrix H<sub>5</sub> E H<sub>3</sub><sup>−1</sup> of formula (9) (exact):",
        &degree_change_matrix(5, 3).to_string(),
    );
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// Fig. 4

/// A 7×3 net u_00 … u_62: a wavy strip, arched across.
fn fig4_net() -> Vec<Vec<Vec<f64>>> {
    (0..7)
        .map(|i| {
            (0..3)
                .map(|j| {
                    let x = 1.6 * i as f64;
                    let y = 2.6 * j as f64;
                    let wave = 1.7 * (std::f64::consts::PI * i as f64 / 3.0).sin();
                    let arch = if j == 1 { 1.2 } else { 0.0 };
                    vec![x, y, wave + arch + 0.15 * i as f64]
                })
                .collect()
        })
        .collect()
}

fn fig4(ctx: &Context) -> Result<Report> {
    let surface = BezierSurface::new(fig4_net())?;
    let scale = surface.scale();
    let (n, m) = surface.degrees();
    // Add a row between rows 2 and 3, on the net itself (their midpoints): a "harmless"
    // refinement by hand, which still changes the surface.
    let mid: Vec<Vec<f64>> = (0..=m)
        .map(|j| {
            let (a, b) = (surface.point(2, j), surface.point(3, j));
            a.iter().zip(b).map(|(x, y)| 0.5 * (x + y)).collect()
        })
        .collect();
    let added = surface.insert_line(Direction::U, 3, &mid)?;
    let middle = n.div_ceil(2);
    let removed = surface.remove_line(Direction::U, middle)?;
    let elevated = surface.change_degree(n + 1, m, None)?;
    let dev_added = surface.deviation_from(&added)?;
    let dev_removed = surface.deviation_from(&removed)?;
    let dev_elevated = surface.deviation_from(&elevated)?;

    let mut r = Report::new(format!(
        "Nikulin (2011), Fig. 4 and formula (13): changing a {}×{} net u00…u{n}{m} by hand. \
         Inserting a row (here the midpoints of rows 2 and 3, lying on the net) or removing the \
         middle row re-weights every point and changes the surface: by up to {} and {} \
         (relative to the net size {}). The algorithmic elevation to ({}, {}) by formula (14) \
         keeps it (deviation {}).",
        n + 1,
        m + 1,
        sci(dev_added.max_found),
        sci(dev_removed.max_found),
        sci(scale),
        n + 1,
        m,
        sci(dev_elevated.upper_bound),
    ));
    let ghost = Stroke::solid(palette::GHOST.color, 0.9).with_opacity(0.8);
    let [wire, net] = surface_with_net(&surface, palette::OLD_POLYGON, palette::OLD_VERTEX);
    let svg = surface_svg(
        &format!("Fig. 4: the original surface, degrees ({n}, {m})"),
        "7×3 net u00 … u62 (azimuth 35°, elevation 25°)",
        &[wire, net],
    )?;
    r.picture(
        ctx,
        "fig4_original.svg",
        &svg,
        "The original 7×3 net and its surface.",
    )?;
    for (file, s, what, caption) in [
        (
            "fig4_row_added.svg",
            &added,
            "a row added",
            "A row inserted between rows 2 and 3: the new surface (blue) against the original (light).",
        ),
        (
            "fig4_row_removed.svg",
            &removed,
            "the middle row removed",
            "The middle row u30…u32 removed: the new surface (blue) against the original (light).",
        ),
    ] {
        let (a, b) = s.degrees();
        let [wire, net] = surface_with_net(s, palette::NEW_POLYGON, palette::NEW_VERTEX);
        let svg = surface_svg(
            &format!("Fig. 4: {what}, degrees ({a}, {b})"),
            "manual change (13): the shape changes",
            &[
                Layer::Wireframe {
                    surface: &surface,
                    count: 10,
                    stroke: ghost,
                    legend: "original surface".into(),
                },
                wire,
                net,
            ],
        )?;
        r.picture(ctx, file, &svg, caption)?;
    }
    r.model(
        ctx,
        "fig4_original.json",
        &BezierModel::Surface(surface.clone()),
        None,
        "7×3 net",
    )?;
    r.model(
        ctx,
        "fig4_row_added.json",
        &BezierModel::Surface(added),
        None,
        "8×3 net",
    )?;
    r.model(
        ctx,
        "fig4_row_removed.json",
        &BezierModel::Surface(removed),
        None,
        "6×3 net",
    )?;

    r.check(Check::at_least(
        "adding a row changes the surface (max distance found)",
        dev_added.max_found,
        0.01 * scale,
    ));
    r.check(Check::at_least(
        "removing the middle row changes the surface (max distance found)",
        dev_removed.max_found,
        0.01 * scale,
    ));
    r.check(Check::at_most(
        "elevation (14) to (7, 2) keeps the surface (distance bound)",
        dev_elevated.upper_bound,
        1e-13 * scale,
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// Fig. 5

/// A bicubic 4×4 net: a skewed dome.
fn bicubic_net() -> Vec<Vec<Vec<f64>>> {
    const Z: [[f64; 4]; 4] = [
        [0.0, 1.2, 0.8, 0.2],
        [1.0, 3.0, 2.6, 1.4],
        [0.6, 2.8, 3.2, 1.0],
        [0.2, 0.8, 1.4, 0.4],
    ];
    (0..4)
        .map(|i| {
            (0..4)
                .map(|j| vec![2.0 * i as f64 + 0.3 * j as f64, 2.0 * j as f64, Z[i][j]])
                .collect()
        })
        .collect()
}

fn fig5(ctx: &Context) -> Result<Report> {
    let bicubic = BezierSurface::new(bicubic_net())?;
    // The paper's (4,3) surface: a 5×4 net whose S has a zero bottom row.
    let s43 = bicubic.change_degree(4, 3, None)?;
    let scale = s43.scale();
    let report = s43.degree_report(None)?;
    let s33 = s43.change_degree(3, 3, None)?;
    let s36 = s33.change_degree(3, 6, None)?;

    let mut r = Report::new(format!(
        "Nikulin (2011), Fig. 5 and formulas (14)-(16): a surface of degrees (4, 3) on a 5×4 net \
         whose power-coefficient matrix S = H4ᵀ·U·H3 has a zero bottom row: real degrees (3, 3), \
         defects (1, 0) (relative residuals {} / {}; one degree lower {} / {}). The same surface on \
         a 4×4 net, then at once on a 4×7 net (degree 3 in u, 6 in v).",
        sci(report.u.residual),
        sci(report.v.residual),
        report.u.rejected_residual.map_or("-".into(), sci),
        report.v.rejected_residual.map_or("-".into(), sci),
    ));
    let steps: [(&str, &BezierSurface, Option<&BezierSurface>, &str); 3] = [
        ("fig5_43", &s43, None, "The (4,3) surface on its 5×4 net."),
        (
            "fig5_33",
            &s33,
            Some(&s43),
            "Reduced exactly to (3,3): the 4×4 net (orange) and the 5×4 net (grey, dashed).",
        ),
        (
            "fig5_36",
            &s36,
            Some(&s33),
            "Changed to (3,6): the 4×7 net (orange) and the 4×4 net (grey, dashed).",
        ),
    ];
    for (id, s, previous, caption) in steps {
        let (a, b) = s.degrees();
        let [wire, net] = surface_with_net(s, palette::NEW_POLYGON, palette::NEW_VERTEX);
        let mut layers = vec![wire];
        if let Some(p) = previous {
            let (pa, pb) = p.degrees();
            layers.push(Layer::Net {
                surface: p,
                stroke: palette::OLD_POLYGON,
                vertex: palette::OLD_VERTEX,
                corners: None,
                legend: format!("previous net, degrees ({pa}, {pb})"),
            });
        }
        layers.push(net);
        let svg = surface_svg(
            &format!("Fig. 5: degrees ({a}, {b}), {}×{} net", a + 1, b + 1),
            "the same surface; formula (14) done stably",
            &layers,
        )?;
        r.picture(ctx, &format!("{id}.svg"), &svg, caption)?;
        r.model(
            ctx,
            &format!("{id}.json"),
            &BezierModel::Surface((*s).clone()),
            None,
            &format!("({a}, {b})"),
        )?;
    }

    r.check(Check::equal(
        "degree report: real degrees and defects",
        format!("{:?}, {:?}", report.real_degrees(), report.defects()),
        "(3, 3), (1, 0)".to_string(),
    ));
    let d1 = grid_distance(&s43, &s33, 33)?;
    let d2 = grid_distance(&s43, &s36, 33)?;
    r.check(Check::at_most(
        "(4,3) vs (3,3): max distance on a 33×33 grid",
        d1,
        1e-13 * scale,
    ));
    r.check(Check::at_most(
        "(4,3) vs (3,6): max distance on a 33×33 grid",
        d2,
        1e-13 * scale,
    ));
    r.check(Check::at_most(
        "the (3,3) net vs the bicubic net it came from",
        max_point_distance(s33.net_flat(), bicubic.net_flat(), 3),
        1e-13 * scale,
    ));
    let impossible = s43.change_degree(2, 3, None).is_err();
    r.check(Check::equal(
        "reducing to (2,3), below the real degree, is refused",
        if impossible { "refused" } else { "accepted" },
        "refused",
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// approximate reduction

/// A degree-12 curve: a widening spiral arc.
fn spiral12() -> Result<BezierCurve> {
    let points = (0..=12)
        .map(|i| {
            let a = 0.52 * i as f64;
            let r = 2.0 + 0.45 * i as f64;
            vec![r * a.cos(), r * a.sin()]
        })
        .collect();
    Ok(BezierCurve::new(points)?)
}

fn approx(ctx: &Context) -> Result<Report> {
    let original = spiral12()?;
    let target = 5;
    let methods = [
        ("l2", "L2", ApproxOptions::default()),
        (
            "c1",
            "L2 with C1/C1 ends",
            ApproxOptions::default().with_continuity(Some(1), Some(1)),
        ),
        (
            "chebyshev",
            "Chebyshev",
            ApproxOptions::default().with_norm(ReductionNorm::Chebyshev),
        ),
    ];
    let mut r = Report::new(
        "Reduction below the real degree (spec §5): the paper's formula (10) would truncate the \
         power form; we compute the best approximation of degree 5 to a curve of degree 12, in \
         L2[0,1], in L2 with C1 continuity at both ends (same end points and tangents), and in \
         the Chebyshev-weighted norm (near-minimax). Each reports its L2 error and a guaranteed \
         bound on the largest distance; the checks compare that bound with the distance \
         measured at 1001 points.",
    );
    r.model(
        ctx,
        "approx_degree12.json",
        &BezierModel::Curve(original.clone()),
        None,
        "input",
    )?;
    let mut rows = String::new();
    let mut chart = Figure::new(
        "Distance |p(t) − q(t)| to the degree-12 curve",
        Axes::Chart {
            x: "t".into(),
            y: "distance".into(),
        },
    );
    for (k, (id, name, options)) in methods.iter().enumerate() {
        let red = original.reduce_degree_approx(target, options)?;
        let (sampled, at) = sampled_distance(&original, &red.curve, 1001);
        let bound = red.linf.upper_bound;
        let svg = curve_change_svg(
            &format!("Approximate reduction 12 → 5 ({name})"),
            &format!(
                "L2 error {:.3e}, max distance ≤ {:.3e}",
                red.l2_error, bound
            ),
            (&original, &original.points()),
            (Some(&red.curve), &red.curve.points()),
        )?;
        r.picture(
            ctx,
            &format!("approx_{id}.svg"),
            &svg,
            &format!("{name}: the degree-12 curve (light) and its degree-5 approximation (blue)."),
        )?;
        let error = ErrorReport {
            l2: red.l2_error,
            linf_bound: bound,
        };
        r.model(
            ctx,
            &format!("approx_{id}.json"),
            &BezierModel::Curve(red.curve.clone()),
            Some(&error),
            name,
        )?;
        r.check(Check::at_least(
            format!("{name}: L∞ bound ≥ max distance at 1001 points"),
            bound,
            sampled,
        ));
        r.check(Check::at_most(
            format!("{name}: L∞ bound ≤ 3 × max distance at 1001 points"),
            bound,
            3.0 * sampled,
        ));
        if options.start_continuity.is_some() {
            let ends = distance(&original.eval(0.0), &red.curve.eval(0.0))
                .max(distance(&original.eval(1.0), &red.curve.eval(1.0)));
            let (d0, d1) = (original.derivative(), red.curve.derivative());
            let tangents =
                distance(&d0.eval(0.0), &d1.eval(0.0)).max(distance(&d0.eval(1.0), &d1.eval(1.0)));
            r.check(Check::at_most(
                format!("{name}: end points and end derivatives kept"),
                ends.max(tangents),
                1e-12 * original.scale() * 12.0,
            ));
        }
        let _ = writeln!(
            rows,
            "<tr><td>{name}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{at:.3}</td><td class=\"num\">{}</td></tr>",
            sci(red.l2_error),
            sci(sampled),
            sci(bound)
        );
        let series: Vec<[f64; 2]> = (0..=400)
            .map(|a| {
                let t = a as f64 / 400.0;
                [t, distance(&original.eval(t), &red.curve.eval(t))]
            })
            .collect();
        let color = palette::SERIES[k % palette::SERIES.len()];
        chart.line(series, Stroke::solid(color, 1.8));
        chart.legend(Stroke::solid(color, 1.8), None, *name);
    }
    r.picture(
        ctx,
        "approx_error.svg",
        &chart.render(),
        "The distance along t: C1 ends pin it to zero at t = 0 and 1; Chebyshev levels the peaks.",
    )?;
    r.html = format!(
        "<table><tr><th>method</th><th>L2 error</th><th>max distance (1001 points)</th>\
         <th>at t</th><th>guaranteed bound</th></tr>\n{rows}</table>\n"
    );
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// precision

/// splitmix64: a fixed pseudo-random sequence, so the table is the same on every run.
pub(super) struct SplitMix(pub(super) u64);

impl SplitMix {
    /// The next number, uniform in [-1, 1).
    pub(super) fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        // Uniform in [-1, 1).
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The fixed pseudo-random plane curve of degree `n` with coordinates in [-1, 1).
fn random_curve(n: usize) -> Result<BezierCurve> {
    let mut rng = SplitMix(2011 + n as u64);
    Ok(BezierCurve::from_flat(
        2,
        (0..2 * (n + 1)).map(|_| rng.next_f64()).collect(),
    )?)
}

/// One column of the precision table.
type Column = fn(&PrecisionRow) -> f64;

struct PrecisionRow {
    n: usize,
    paper_elevate: f64,
    ours_elevate: f64,
    paper_round_trip: f64,
    ours_round_trip: f64,
}

fn precision_row(n: usize) -> Result<PrecisionRow> {
    let c = random_curve(n)?;
    let up = n + 10;
    let scale = c.scale();
    let exact = exact_change(&c, up)?;
    let paper = paper_formula_f64(&c, up);
    let ours = c.elevate_degree(up)?;
    let paper_back = match BezierCurve::from_flat(2, paper.clone()) {
        Ok(p) => max_point_distance(&paper_formula_f64(&p, n), c.points_flat(), 2),
        Err(_) => f64::INFINITY,
    };
    let ours_back = ours.reduce_degree(n, None)?;
    Ok(PrecisionRow {
        n,
        paper_elevate: max_point_distance(&paper, &exact, 2) / scale,
        ours_elevate: max_point_distance(ours.points_flat(), &exact, 2) / scale,
        paper_round_trip: paper_back / scale,
        ours_round_trip: max_point_distance(ours_back.points_flat(), c.points_flat(), 2) / scale,
    })
}

fn precision(ctx: &Context) -> Result<Report> {
    let rows = [10, 20, 30, 40, 50]
        .into_iter()
        .map(precision_row)
        .collect::<Result<Vec<_>>>()?;
    ensure!(!rows.is_empty(), "no degrees");
    let mut r = Report::new(
        "Spec §5: S = U·H and H⁻¹ are badly conditioned. For a fixed pseudo-random plane curve \
         of each degree n (coordinates in [-1, 1]), elevation to n+10 (a) by the paper's formula \
         (10) evaluated naively in f64 through the power form (paper_formula_f64) and (b) by our \
         elevate_degree (closed form (8) in double-double), both compared with the exact result \
         (exact rationals, rounded once); then the round trip n → n+10 → n against the original. \
         Errors are max point distance / max|P|.",
    );
    let mut text = format!(
        "{:>4} {:>5} {:>16} {:>16} {:>18} {:>18}\n",
        "n", "n+10", "elevate: paper", "elevate: ours", "round trip: paper", "round trip: ours"
    );
    let mut html = String::from(
        "<table><tr><th>n</th><th>n+10</th><th>elevate: paper f64</th><th>elevate: ours</th>\
         <th>round trip: paper f64</th><th>round trip: ours</th></tr>\n",
    );
    for row in &rows {
        let _ = writeln!(
            text,
            "{:>4} {:>5} {:>16} {:>16} {:>18} {:>18}",
            row.n,
            row.n + 10,
            sci(row.paper_elevate),
            sci(row.ours_elevate),
            sci(row.paper_round_trip),
            sci(row.ours_round_trip)
        );
        let _ = writeln!(
            html,
            "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            row.n,
            row.n + 10,
            sci(row.paper_elevate),
            sci(row.ours_elevate),
            sci(row.paper_round_trip),
            sci(row.ours_round_trip)
        );
        r.check(Check::at_most(
            format!(
                "n = {}: our elevation to {} vs exact (relative)",
                row.n,
                row.n + 10
            ),
            row.ours_elevate,
            4.0 * EPS,
        ));
        r.check(Check::at_most(
            format!(
                "n = {}: our round trip via {} (relative)",
                row.n,
                row.n + 10
            ),
            row.ours_round_trip,
            1e-13,
        ));
    }
    html.push_str("</table>\n");
    r.text = text;
    r.html = html;

    // Chart: log10 of the errors against n (zero errors drawn at 1e-17, overflow left out).
    let mut chart = Figure::new(
        "Relative error against the degree (log10)",
        Axes::Chart {
            x: "degree n (elevated to n + 10)".into(),
            y: "log10(error / max|P|)".into(),
        },
    );
    let series: [(&str, Column); 4] = [
        ("elevate: paper f64", |r| r.paper_elevate),
        ("elevate: ours", |r| r.ours_elevate),
        ("round trip: paper f64", |r| r.paper_round_trip),
        ("round trip: ours", |r| r.ours_round_trip),
    ];
    for (k, (name, value)) in series.iter().enumerate() {
        let pts: Vec<[f64; 2]> = rows
            .iter()
            .map(|row| [row.n as f64, value(row).max(1e-17).log10()])
            .filter(|p| p[1].is_finite())
            .collect();
        let color = palette::SERIES[k % palette::SERIES.len()];
        let stroke = if k % 2 == 0 {
            Stroke::dashed(color, 1.8)
        } else {
            Stroke::solid(color, 1.8)
        };
        chart.line(pts.clone(), stroke);
        chart.dots(pts, 3.0, color);
        chart.legend(stroke, Some(color), *name);
    }
    r.picture(
        ctx,
        "precision.svg",
        &chart.render(),
        "The paper's f64 route loses digits exponentially with the degree; ours stays at rounding level.",
    )?;
    Ok(r)
}
