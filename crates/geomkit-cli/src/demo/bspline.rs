//! Demo items of method 2, interpolating cubic B-splines (Hoang Thai Ho,
//! spec/bspline-interpolation.md): the paper's trajectory through 6 points and surface through
//! 14×14 points, a closed isoline, a 512×512 terrain, uniform against chord-length parameters,
//! the paper's averaged fragments against our exact tiles, forward differences on a long
//! curve, and evaluation at arbitrary parameters (the B-spline and the piecewise form).

use super::bezier::SplitMix;
use super::{sci, Check, Context, Item, Report};
use crate::model::{bspline_curve_json, bspline_surface_json};
use crate::npy::write_npy;
use anyhow::Result;
use geomkit::bspline::{
    interpolate_curve, interpolate_curve_flat, interpolate_curve_tiled, interpolate_heights,
    interpolate_surface, paper_dense_inner_points, paper_fragments_averaged, BsplineCurve,
    EndCondition, InterpolationOptions, Parametrization, SurfaceInterpolationOptions, TileOptions,
};
use geomkit::geom::Curve;
use geomkit_plot::figures::{
    bspline_curve_figure, curve_on_page, heightmap_svg, linspace, surface_svg, Layer, Projection,
    REFERENCE,
};
use geomkit_plot::svg::{palette, Axes, Figure, Stroke};
use std::fmt::Write as _;
use std::time::Instant;

const EPS: f64 = f64::EPSILON;

/// The B-spline items.
pub fn items() -> Vec<Item> {
    vec![
        Item {
            id: "traj6",
            title: "B-spline: the paper's trajectory through 6 points",
            run: trajectory,
        },
        Item {
            id: "surf14",
            title: "B-spline: the paper's surface through 14×14 points",
            run: surface14,
        },
        Item {
            id: "isoline",
            title: "B-spline: a closed isoline (periodic ends)",
            run: isoline,
        },
        Item {
            id: "terrain",
            title: "B-spline: a 512×512 terrain",
            run: terrain,
        },
        Item {
            id: "param",
            title: "B-spline: uniform against chord-length parameters",
            run: parametrizations,
        },
        Item {
            id: "tiles",
            title: "B-spline: the paper's averaged fragments against exact tiles",
            run: tiles,
        },
        Item {
            id: "fd",
            title: "B-spline: forward differences on a long curve",
            run: forward_differences,
        },
        Item {
            id: "arbitrary",
            title: "B-spline: evaluation at arbitrary parameters",
            run: arbitrary_parameters,
        },
    ]
}

// ---------------------------------------------------------------------------------------------
// measuring

/// Largest absolute coordinate.
fn max_abs(values: &[f64]) -> f64 {
    values.iter().fold(0.0, |m, v| m.max(v.abs()))
}

/// Largest coordinate difference between two equally long lists (inf if they differ in
/// length; NaN propagates).
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter().zip(b).fold(0.0, |m: f64, (x, y)| {
        let d = (x - y).abs();
        if d.is_nan() || m.is_nan() {
            f64::NAN
        } else {
            m.max(d)
        }
    })
}

/// max |C(t_i) - k_i| / max |k|: how exactly the curve passes through its reference points.
fn curve_residual(curve: &BsplineCurve, points: &[f64], parameters: &[f64]) -> Result<f64> {
    let mut at = vec![0.0; points.len()];
    curve.eval_many_par(parameters, &mut at)?;
    Ok(max_diff(&at, points) / max_abs(points))
}

fn flat(points: &[Vec<f64>]) -> Vec<f64> {
    points.iter().flatten().copied().collect()
}

/// Samples of the curve by forward differences and by direct evaluation at the same
/// parameters: (largest difference, the library's bound, longest run without restart).
fn fd_against_direct(curve: &BsplineCurve, count: usize) -> Result<(f64, f64, usize)> {
    let d = curve.dim();
    let mut fd = vec![0.0; count * d];
    let report = curve.sample_uniform_fd(count, &mut fd)?;
    let (a, b) = curve.domain();
    let step = (b - a) / (count - 1) as f64;
    let ts: Vec<f64> = (0..count).map(|k| a + k as f64 * step).collect();
    let mut direct = vec![0.0; count * d];
    curve.eval_many_par(&ts, &mut direct)?;
    Ok((max_diff(&fd, &direct), report.bound, report.max_steps))
}

fn fd_check(r: &mut Report, curve: &BsplineCurve, count: usize) -> Result<()> {
    let (drift, bound, steps) = fd_against_direct(curve, count)?;
    r.check(Check::at_most(
        format!("forward differences vs direct evaluation, {count} samples (≤ the reported bound, {steps} steps per run)"),
        drift,
        bound,
    ));
    Ok(())
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

fn points_html(title: &str, header: &[&str], rows: &[Vec<String>]) -> String {
    let mut h = format!("<p>{title}</p>\n<table><tr>");
    for c in header {
        let _ = write!(h, "<th>{c}</th>");
    }
    h.push_str("</tr>\n");
    for row in rows {
        h.push_str("<tr>");
        for c in row {
            let _ = write!(h, "<td class=\"num\">{c}</td>");
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
    h
}

fn fmt_point(p: &[f64]) -> String {
    let c: Vec<String> = p.iter().map(|x| format!("{x:.6}")).collect();
    format!("({})", c.join(", "))
}

// ---------------------------------------------------------------------------------------------
// the paper's trajectory

/// Six reference points of a trajectory (the paper shows one through 6 points).
const TRAJECTORY: [[f64; 2]; 6] = [
    [1.0, 1.0],
    [3.0, 4.0],
    [6.0, 4.5],
    [8.0, 2.0],
    [11.0, 2.5],
    [13.0, 5.0],
];

fn trajectory(ctx: &Context) -> Result<Report> {
    let points: Vec<Vec<f64>> = TRAJECTORY.iter().map(|p| p.to_vec()).collect();
    let k = flat(&points);
    let n = points.len();
    let options = InterpolationOptions::default()
        .with_end(EndCondition::Repeat)
        .with_parametrization(Parametrization::Uniform);
    let fit = interpolate_curve(&points, &options)?;
    let curve = fit.curve();
    let control = curve.control_flat();
    let dense = paper_dense_inner_points(&points)?;
    let inner = &control[3 * 2..(n + 1) * 2];

    let mut r = Report::new(format!(
        "Hoang Thai Ho, §2 and the paper's program: a uniform cubic B-spline through {n} \
         reference points k0…k5. The paper replaces the reference points by new control points \
         p*1…p*4 from the tridiagonal system (2), M1·P* = M2 (4p*i + p*i+1 = 6ki − ki−1 …), and \
         repeats the first and last reference points three times (\"multiple points\", N+4 = \
         {} control points) so that the curve starts and ends on them. Each segment i starts at \
         (pi−1 + 4pi + pi+1)/6 = ki. We solve (2) as a banded system in O(N); the paper's dense \
         Gauss route (3) gives the same points.",
        curve.n_control()
    ));
    let fig = bspline_curve_figure(
        "The paper's trajectory through 6 points",
        "repeated end points (p0 = p1 = p2 = k0), uniform parameters",
        curve,
        &k,
        fit.parameters(),
    )?;
    r.picture(
        ctx,
        "traj6.svg",
        &fig.render(),
        "Reference points (black), the new control polygon (orange) and the curve (blue).",
    )?;
    r.file(
        ctx,
        "traj6.json",
        bspline_curve_json(curve, Some(fit.parameters()))?.as_bytes(),
        "bspline_curve",
    )?;
    let csv: String = std::iter::once("x,y\n".to_string())
        .chain(TRAJECTORY.iter().map(|p| format!("{},{}\n", p[0], p[1])))
        .collect();
    r.file(
        ctx,
        "traj6_points.csv",
        csv.as_bytes(),
        "the 6 reference points",
    )?;

    r.check(Check::at_most(
        "residual at the 6 reference points (relative to max|k|)",
        curve_residual(curve, &k, fit.parameters())?,
        1e-14,
    ));
    let dense_flat = flat(&dense);
    r.check(Check::at_most(
        "banded solve vs the paper's dense Gauss route (3), p*1…p*4 (relative)",
        max_diff(inner, &dense_flat) / max_abs(&k),
        1e-14,
    ));
    let ends = max_diff(&curve.eval(0.0), &k[..2])
        .max(max_diff(&curve.eval(curve.domain().1), &k[(n - 1) * 2..]));
    r.check(Check::at_most(
        "the curve starts at k0 and ends at k5 (repeated end points)",
        ends,
        4.0 * EPS * max_abs(&k),
    ));
    fd_check(&mut r, curve, 1001)?;

    // The whole curve as one formula (method 3), for a symbolic system.
    let formula = geomkit::compose::Piecewise::from_bspline(curve)?;
    let printed = formula.formula()?;
    r.file(
        ctx,
        "traj6.m",
        printed
            .print(geomkit::expr::Format::Mathematica)?
            .as_bytes(),
        "the curve as one formula x(t), y(t) (Mathematica)",
    )?;
    let (a, b) = curve.domain();
    let ts: Vec<f64> = (0..=1000)
        .map(|i| a + (b - a) * i as f64 / 1000.0)
        .collect();
    let mut values = vec![0.0; ts.len() * 2];
    printed.eval_batch(&[&ts], &mut values)?;
    let off = ts
        .iter()
        .zip(values.chunks_exact(2))
        .fold(0.0f64, |m, (&t, v)| m.max(max_diff(v, &curve.eval(t))));
    r.check(Check::at_most(
        "the printed single formula (spec §5) vs the B-spline at 1001 parameters (relative)",
        off / max_abs(&k),
        1e-13,
    ));

    // Cost of the two routes.
    let mut cost = String::new();
    let mut worst = 0.0f64;
    for m in [100usize, 200, 400, 800] {
        let mut rng = SplitMix(0x7ad + m as u64);
        let pts: Vec<Vec<f64>> = (0..m)
            .map(|i| vec![i as f64 + 0.4 * rng.next_f64(), 3.0 * rng.next_f64()])
            .collect();
        let t0 = Instant::now();
        let banded = interpolate_curve(&pts, &options)?;
        let t_banded = ms(t0);
        let t0 = Instant::now();
        let dense = paper_dense_inner_points(&pts)?;
        let t_dense = ms(t0);
        let diff = max_diff(
            &banded.curve().control_flat()[6..(m + 1) * 2],
            &flat(&dense),
        ) / max_abs(&flat(&pts));
        worst = worst.max(diff);
        let _ = writeln!(
            cost,
            "<tr><td>{m}</td><td class=\"num\">{t_banded:.3}</td><td class=\"num\">{t_dense:.3}\
             </td><td class=\"num\">{}</td></tr>",
            sci(diff)
        );
    }
    r.check(Check::at_most(
        "banded vs dense route for N = 100…800 (relative)",
        worst,
        1e-14,
    ));
    let rows: Vec<Vec<String>> = (0..n)
        .map(|i| {
            let p = if i == 0 || i == n - 1 {
                "(k repeated)".to_string()
            } else {
                fmt_point(&inner[(i - 1) * 2..i * 2])
            };
            vec![
                format!("{i}"),
                fmt_point(&k[i * 2..i * 2 + 2]),
                format!("{}", fit.parameters()[i]),
                p,
            ]
        })
        .collect();
    r.html = points_html(
        "Reference points k<sub>i</sub>, their parameters and the new points p*<sub>i</sub> \
         (banded solve):",
        &["i", "k<sub>i</sub>", "t<sub>i</sub>", "p*<sub>i</sub>"],
        &rows,
    );
    let _ = write!(
        r.html,
        "<p>Cost of the two routes (ms): the banded O(N) solve against the dense O(N³) Gauss \
         elimination of the paper's (3).</p>\n<table><tr><th>N</th><th>banded</th><th>dense \
         Gauss</th><th>max difference / max|k|</th></tr>\n{cost}</table>\n"
    );
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// the paper's surface

/// A smooth spatial form sampled on the 14×14 grid.
fn form(x: f64, y: f64) -> f64 {
    1.6 * (0.45 * x).sin() * (0.35 * y).cos()
        + 2.2 * (-((x - 9.0).powi(2) + (y - 4.0).powi(2)) / 6.0).exp()
}

fn surface14(ctx: &Context) -> Result<Report> {
    let (m, n) = (14usize, 14usize);
    let grid: Vec<Vec<Vec<f64>>> = (0..m)
        .map(|i| {
            (0..n)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    vec![x, y, form(x, y)]
                })
                .collect()
        })
        .collect();
    let offset = 0.5;
    let options = SurfaceInterpolationOptions::default()
        .with_end(EndCondition::OuterPoints { offset })
        .with_parametrization(Parametrization::Uniform);
    let t0 = Instant::now();
    let fit = interpolate_surface(&grid, &options)?;
    let solve_ms = ms(t0);
    let s = &fit.surface;
    let (nu, nv) = s.net_size();
    let reference: Vec<f64> = grid.iter().flatten().flatten().copied().collect();

    let mut r = Report::new(format!(
        "Hoang Thai Ho, §3 and the paper's second program: a bicubic B-spline surface through \
         {m}×{n} reference points. Extra points are added just outside the edges (diagonals \
         included; here {offset} of the end interval beyond the boundary), so the {m}×{n} \
         reference points give a {nu}×{nv} control net, the paper's (M+2)×(N+2). The system \
         for the net is separable: every row, then every column, each a tridiagonal solve \
         ({solve_ms:.2} ms)."
    ));
    let [wire, net, refs] = [
        Layer::Wireframe {
            surface: s,
            count: 14,
            stroke: Stroke::solid(palette::CURVE.color, 1.0),
            legend: "surface".into(),
        },
        Layer::Points {
            points: s.control_flat(),
            dim: 3,
            grid: Some((nu, nv)),
            stroke: Some(palette::NEW_POLYGON.with_opacity(0.55)),
            vertex: palette::NEW_VERTEX,
            radius: 1.6,
            legend: format!("control net {nu}×{nv}"),
        },
        Layer::Points {
            points: &reference,
            dim: 3,
            grid: None,
            stroke: None,
            vertex: REFERENCE,
            radius: 2.2,
            legend: format!("reference points {m}×{n}"),
        },
    ];
    let svg = surface_svg(
        "The paper's surface through 14×14 points",
        "outer points: a 16×16 control net (azimuth 35°, elevation 25°)",
        &[wire, net, refs],
    )?;
    r.picture(
        ctx,
        "surf14.svg",
        &svg,
        "The surface (blue wireframe), its 16×16 net (orange) and the reference points (black).",
    )?;
    r.file(
        ctx,
        "surf14.json",
        bspline_surface_json(s, Some((&fit.params_u, &fit.params_v)))?.as_bytes(),
        "bspline_surface",
    )?;

    r.check(Check::equal(
        "control net size for 14×14 points: (M+2)×(N+2)",
        format!("{nu}×{nv}"),
        "16×16".to_string(),
    ));
    let mut at = vec![0.0; m * n * 3];
    s.eval_grid(&fit.params_u, &fit.params_v, &mut at)?;
    r.check(Check::at_most(
        "residual at the 196 reference points (relative)",
        max_diff(&at, &reference) / max_abs(&reference),
        1e-14,
    ));
    // The outer points continue the boundary: along u at v = v_j, the first control column
    // of every row solve lies `offset` intervals beyond the edge.
    let mut edge = vec![0.0; 3];
    s.eval_into(fit.params_u[0], fit.params_v[5], &mut edge);
    r.check(Check::at_most(
        "a boundary point of the surface is the reference point k(0,5)",
        max_diff(&edge, &grid[0][5]),
        1e-14 * max_abs(&reference),
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// isoline

/// A smooth landscape of three hills; its level set at [`ISO_LEVEL`] around the main hill is
/// a closed curve.
fn hills(x: f64, y: f64) -> f64 {
    let g =
        |cx: f64, cy: f64, s: f64, h: f64| h * (-((x - cx).powi(2) + (y - cy).powi(2)) / s).exp();
    g(0.0, 0.0, 1.0, 1.0)
        + g(0.9, 0.5, 0.35, 0.55)
        + g(-0.7, -0.6, 0.25, 0.45)
        + 0.05 * (3.0 * x).sin() * (2.0 * y).cos()
}

const ISO_LEVEL: f64 = 0.35;

/// The point of the level set on the ray from the origin at angle `a` (the first crossing
/// outward, by bisection).
fn iso_point(a: f64) -> [f64; 2] {
    let (c, s) = (a.cos(), a.sin());
    let f = |r: f64| hills(r * c, r * s) - ISO_LEVEL;
    let mut lo = 0.0;
    let mut hi = 0.02;
    while f(hi) > 0.0 && hi < 10.0 {
        lo = hi;
        hi += 0.02;
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = 0.5 * (lo + hi);
    [r * c, r * s]
}

fn isoline(ctx: &Context) -> Result<Report> {
    let count = 20;
    let points: Vec<Vec<f64>> = (0..count)
        .map(|k| iso_point(std::f64::consts::TAU * k as f64 / count as f64).to_vec())
        .collect();
    let k = flat(&points);
    let options = InterpolationOptions::default()
        .with_end(EndCondition::Periodic)
        .with_parametrization(Parametrization::ChordLength);
    let fit = interpolate_curve(&points, &options)?;
    let curve = fit.curve();
    let (a, b) = curve.domain();

    // Distance of the spline to the true level set: |f - c| / |∇f| at dense samples.
    let h = 1e-6;
    let deviation = linspace(a, b, 2000)
        .into_iter()
        .map(|t| {
            let p = curve.eval(t);
            let (x, y) = (p[0], p[1]);
            let gx = (hills(x + h, y) - hills(x - h, y)) / (2.0 * h);
            let gy = (hills(x, y + h) - hills(x, y - h)) / (2.0 * h);
            (hills(x, y) - ISO_LEVEL).abs() / gx.hypot(gy)
        })
        .fold(0.0, f64::max);
    let size = max_abs(&k);

    let mut r = Report::new(format!(
        "Spec §1 and §6: isolines are closed, and the paper's open end conditions cannot close \
         them smoothly. {count} points on the contour hills(x, y) = {ISO_LEVEL} of a smooth \
         landscape, interpolated by a periodic cubic B-spline (a cyclic tridiagonal system, \
         chord-length parameters): C2 everywhere, the seam included. Its largest distance to \
         the true contour is {} ({:.2}% of the curve's size).",
        sci(deviation),
        100.0 * deviation / size
    ));
    let mut fig = bspline_curve_figure(
        "A closed isoline through 20 contour points",
        "periodic ends, chord-length parameters",
        curve,
        &k,
        fit.parameters(),
    )?;
    let truth: Vec<[f64; 2]> = (0..=720)
        .map(|i| iso_point(std::f64::consts::TAU * i as f64 / 720.0))
        .collect();
    fig.line(truth, palette::GHOST.with_opacity(0.9));
    fig.legend(palette::GHOST, None, "the true contour");
    r.picture(
        ctx,
        "isoline.svg",
        &fig.render(),
        "The closed spline (blue) over the true contour (light), its closed control polygon \
         and the 20 contour points.",
    )?;
    r.file(
        ctx,
        "isoline.json",
        bspline_curve_json(curve, Some(fit.parameters()))?.as_bytes(),
        "bspline_curve",
    )?;

    r.check(Check::at_most(
        "residual at the 20 contour points (relative)",
        curve_residual(curve, &k, fit.parameters())?,
        1e-14,
    ));
    for (order, what) in [
        (0, "position"),
        (1, "first derivative"),
        (2, "second derivative"),
    ] {
        let (mut at_a, mut at_b) = ([0.0; 2], [0.0; 2]);
        curve.eval_derivative(a, order, &mut at_a);
        curve.eval_derivative(b, order, &mut at_b);
        let scale = linspace(a, b, 400)
            .into_iter()
            .map(|t| {
                let mut v = [0.0; 2];
                curve.eval_derivative(t, order, &mut v);
                v[0].hypot(v[1])
            })
            .fold(0.0, f64::max);
        r.check(Check::at_most(
            format!("seam: jump of the {what} at the closing point (relative)"),
            max_diff(&at_a, &at_b) / scale,
            1e-13,
        ));
    }
    r.check(Check::at_most(
        "distance to the true contour (relative to the curve's size)",
        deviation / size,
        0.01,
    ));
    fd_check(&mut r, curve, 2001)?;
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// terrain

/// A synthetic terrain over [0, 1]², in metres: hills, a winding ridge, a valley and ripples.
fn terrain_height(x: f64, y: f64) -> f64 {
    let bump = |cx: f64, cy: f64, r: f64, h: f64| {
        h * (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp()
    };
    let ridge_line = 0.62 + 0.12 * (5.0 * x).sin();
    let ridge = 520.0 * (1.0 - 0.5 * x) * (-((y - ridge_line) / 0.045).powi(2)).exp();
    let valley =
        -260.0 * (-((x - 0.35 - 0.1 * (4.0 * y).sin()) / 0.06).powi(2)).exp() * (1.0 - y).max(0.0);
    300.0
        + bump(0.25, 0.3, 0.16, 700.0)
        + bump(0.7, 0.25, 0.12, 520.0)
        + bump(0.82, 0.8, 0.1, 430.0)
        + ridge
        + valley
        + 25.0 * (31.0 * x).sin() * (23.0 * y).cos()
}

fn terrain(ctx: &Context) -> Result<Report> {
    let size = 512usize;
    let spacing = 20.0;
    let z: Vec<f64> = (0..size * size)
        .map(|k| {
            let (i, j) = (k / size, k % size);
            terrain_height(i as f64 / (size - 1) as f64, j as f64 / (size - 1) as f64)
        })
        .collect();
    let t0 = Instant::now();
    let surface = interpolate_heights(
        &z,
        size,
        size,
        (0.0, 0.0),
        (spacing, spacing),
        &EndCondition::NotAKnot,
    )?;
    let solve_ms = ms(t0);
    let xs: Vec<f64> = (0..size).map(|i| i as f64 * spacing).collect();
    let mut at = vec![0.0; size * size];
    let t0 = Instant::now();
    surface.eval_grid(&xs, &xs, &mut at)?;
    let eval_ms = ms(t0);
    let residual = max_diff(&at, &z) / max_abs(&z);
    let t0 = Instant::now();
    let svg = heightmap_svg(
        "A 512×512 terrain",
        &format!(
            "bicubic B-spline through 262 144 heights ({:.1} km square), 128×128 cells, 12 \
             contour lines",
            (size - 1) as f64 * spacing / 1e3
        ),
        &surface,
        128,
        12,
    )?;
    let draw_ms = ms(t0);
    let (nu, nv) = surface.net_size();

    let mut r = Report::new(format!(
        "Spec §1: terrain relief, the distribution of a quantity over a region. A built-in \
         synthetic data set (hills, a winding ridge, a valley and ripples; deterministic) of \
         {size}×{size} heights on a {spacing} m grid, interpolated by a bicubic B-spline height \
         field z(x, y) (not-a-knot ends, {nu}×{nv} net). The separable banded solve takes \
         {solve_ms:.1} ms; evaluating all 262 144 reference points {eval_ms:.1} ms; the \
         picture {draw_ms:.0} ms ({} kB). The heights are in terrain_heights.npy: try \
         `geomkit interpolate surface terrain_heights.npy --heights --dx 20 --dy 20 -o \
         terrain.obj --samples 257`.",
        svg.len() / 1024
    ));
    r.picture(
        ctx,
        "terrain.svg",
        &svg,
        "Heights coloured from low (blue) to high (white), with contour lines of the spline.",
    )?;
    let mut npy = Vec::new();
    write_npy(&mut npy, &[size, size], &z)?;
    r.file(
        ctx,
        "terrain_heights.npy",
        &npy,
        "the 512×512 heights, float64",
    )?;
    r.text = format!(
        "512×512 heights: solve {solve_ms:.1} ms, evaluation of 262 144 points {eval_ms:.1} ms, \
         picture {} kB\n",
        svg.len() / 1024
    );
    r.check(Check::at_most(
        "residual at all 262 144 reference heights (relative)",
        residual,
        1e-14,
    ));
    r.check(Check::at_most(
        "height-map picture size (bytes)",
        svg.len() as f64,
        2e6,
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// parametrizations

/// Unevenly spaced points: long strides with close pairs at two sharp turns.
const UNEVEN: [[f64; 2]; 7] = [
    [0.0, 0.0],
    [4.0, 5.0],
    [4.5, 5.2],
    [5.0, 5.0],
    [9.0, 0.0],
    [9.3, -0.3],
    [12.0, 4.0],
];

/// Proper crossings of non-adjacent segments of a polyline: its self-intersections.
fn self_intersections(line: &[[f64; 2]]) -> usize {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut count = 0;
    for i in 0..line.len().saturating_sub(1) {
        for j in i + 2..line.len() - 1 {
            let (p, q, r, s) = (line[i], line[i + 1], line[j], line[j + 1]);
            let (d1, d2) = (cross(p, q, r), cross(p, q, s));
            let (d3, d4) = (cross(r, s, p), cross(r, s, q));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                count += 1;
            }
        }
    }
    count
}

fn parametrizations(ctx: &Context) -> Result<Report> {
    let points: Vec<Vec<f64>> = UNEVEN.iter().map(|p| p.to_vec()).collect();
    let k = flat(&points);
    let kinds = [
        ("uniform", Parametrization::Uniform, palette::SERIES[1]),
        (
            "chord length",
            Parametrization::ChordLength,
            palette::SERIES[0],
        ),
        (
            "centripetal",
            Parametrization::Centripetal,
            palette::SERIES[2],
        ),
    ];
    let mut r = Report::new(
        "Spec §6: the paper spaces the reference points uniformly in t. With unevenly spaced \
         points (long strides, close pairs at two sharp turns) the uniform spline must cover \
         a long stride and a short one in the same parameter time: it overshoots and loops \
         at the turns. Chord-length and centripetal parameters (non-uniform knots) follow the \
         points. Natural ends throughout.",
    );
    let mut fig = Figure::new("Uniform against chord-length parameters", Axes::Equal)
        .subtitle("7 unevenly spaced points, natural ends");
    let mut rows = Vec::new();
    for (name, kind, color) in kinds {
        let options = InterpolationOptions::default()
            .with_end(EndCondition::Natural)
            .with_parametrization(kind);
        let fit = interpolate_curve(&points, &options)?;
        let line = curve_on_page(Projection::Plane, fit.curve());
        let loops = self_intersections(&line);
        // Overshoot: how far the curve strays outside the bounding box of its points.
        let (x0, x1, y0, y1) = UNEVEN.iter().fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |(a, b, c, d), p| (a.min(p[0]), b.max(p[0]), c.min(p[1]), d.max(p[1])),
        );
        let overshoot = line
            .iter()
            .map(|p| {
                (x0 - p[0])
                    .max(p[0] - x1)
                    .max(y0 - p[1])
                    .max(p[1] - y1)
                    .max(0.0)
            })
            .fold(0.0, f64::max);
        let stroke = if kind == Parametrization::Uniform {
            Stroke::solid(color, 2.2)
        } else {
            Stroke::solid(color, 1.8)
        };
        fig.line(line, stroke);
        fig.legend(stroke, None, format!("{name}: {loops} self-intersections"));
        r.check(Check::at_most(
            format!("{name}: residual at the 7 points (relative)"),
            curve_residual(fit.curve(), &k, fit.parameters())?,
            1e-14,
        ));
        let want = if kind == Parametrization::Uniform {
            2
        } else {
            0
        };
        r.check(Check::equal(
            format!("{name}: self-intersections of the curve (loops)"),
            loops,
            want,
        ));
        rows.push(vec![
            name.to_string(),
            loops.to_string(),
            format!("{overshoot:.3}"),
        ]);
        r.file(
            ctx,
            &format!("param_{}.json", name.split(' ').next().unwrap_or(name)),
            bspline_curve_json(fit.curve(), Some(fit.parameters()))?.as_bytes(),
            name,
        )?;
    }
    fig.dots(UNEVEN.to_vec(), 4.2, REFERENCE);
    fig.legend(
        Stroke::solid(REFERENCE, 0.0),
        Some(REFERENCE),
        "reference points",
    );
    r.picture(
        ctx,
        "param.svg",
        &fig.render(),
        "Uniform parameters (orange) loop at both close pairs; chord length (blue) and \
         centripetal (green) do not.",
    )?;
    r.html = points_html(
        "Loops and overshoot beyond the points' bounding box:",
        &["parameters", "self-intersections", "overshoot"],
        &rows,
    );
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// tiles against the paper's fragments

/// A long wiggly path of `n` points (deterministic).
fn long_path(n: usize, seed: u64) -> Vec<f64> {
    let mut rng = SplitMix(seed);
    let (mut x, mut y, mut heading) = (0.0f64, 0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(2 * n);
    for _ in 0..n {
        out.extend_from_slice(&[x, y]);
        heading += 0.35 * rng.next_f64();
        let step = 1.0 + 0.5 * rng.next_f64();
        x += step * heading.cos();
        y += step * heading.sin();
    }
    out
}

fn tiles(ctx: &Context) -> Result<Report> {
    let n = 4096;
    let points = long_path(n, 2024);
    let scale = max_abs(&points);
    let spacing = points
        .chunks_exact(2)
        .zip(points.chunks_exact(2).skip(1))
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .sum::<f64>()
        / (n - 1) as f64;
    let uniform = |end: EndCondition| {
        InterpolationOptions::default()
            .with_end(end)
            .with_parametrization(Parametrization::Uniform)
    };
    // The paper's numbering p_0..p_(N-1): the repeated-ends solution without its extra copies.
    let global_repeat = interpolate_curve_flat(2, &points, &uniform(EndCondition::Repeat))?;
    let paper_global = &global_repeat.curve().control_flat()[2 * 2..(n + 2) * 2];
    let nak = uniform(EndCondition::NotAKnot);
    let global = interpolate_curve_flat(2, &points, &nak)?;
    let fragment = 256;
    let overlaps = [4usize, 8, 16, 32, 64, 128];
    let mut rows = String::new();
    let mut text = format!(
        "{:>8} {:>22} {:>22}\n",
        "overlap", "paper: averaged", "ours: tiles (halo)"
    );
    let (mut paper_series, mut ours_series) = (Vec::new(), Vec::new());
    let mut paper_last = 0.0;
    for &o in &overlaps {
        let averaged = paper_fragments_averaged(2, &points, fragment, o)?;
        let paper_err = max_diff(&averaged, paper_global) / spacing;
        let tiled = interpolate_curve_tiled(
            2,
            &points,
            &nak,
            &TileOptions::default()
                .with_tile_size(fragment)
                .with_halo(o / 2),
        )?;
        let ours_err =
            max_diff(tiled.curve().control_flat(), global.curve().control_flat()) / spacing;
        paper_last = paper_err;
        paper_series.push([o as f64, paper_err.max(1e-17).log10()]);
        ours_series.push([o as f64, ours_err.max(1e-17).log10()]);
        let _ = writeln!(
            rows,
            "<tr><td>{o}</td><td class=\"num\">{}</td><td class=\"num\">{} (halo {})</td></tr>",
            sci(paper_err),
            sci(ours_err),
            o / 2
        );
        let _ = writeln!(
            text,
            "{o:>8} {:>22} {:>22}",
            sci(paper_err),
            format!("{} ({})", sci(ours_err), o / 2)
        );
    }
    let tiled = interpolate_curve_tiled(
        2,
        &points,
        &nak,
        &TileOptions::default().with_tile_size(fragment),
    )?;
    let default_err = max_diff(tiled.curve().control_flat(), global.curve().control_flat());

    // Timing at a larger size: global O(N) solve against parallel tiles.
    let big_n = 500_000;
    let big = long_path(big_n, 7);
    let chord = InterpolationOptions::default();
    let t0 = Instant::now();
    let big_global = interpolate_curve_flat(2, &big, &chord)?;
    let t_global = ms(t0);
    let t0 = Instant::now();
    let big_tiled = interpolate_curve_tiled(2, &big, &chord, &TileOptions::default())?;
    let t_tiled = ms(t0);
    let big_err = max_diff(
        big_tiled.curve().control_flat(),
        big_global.curve().control_flat(),
    );

    let mut r = Report::new(format!(
        "Spec §5–6: all reference points enter one system, so the paper splits large data into \
         overlapping fragments, solves each with its own ends, and averages the shared points; \
         the error then depends on the overlap but does not vanish, because every fragment's \
         artificial ends are wrong by O(1) and the average keeps half of that. The influence of \
         one reference point decays like (2 − √3)^k ≈ 0.268^k, so our tiles solve a halo of h \
         extra points on each side, discard it, and equal the global solve to rounding once \
         0.268^h < eps (h ≈ 27; default 32). {n} points of a wiggly path, fragments / tiles of \
         {fragment} points; errors are the largest distance of a control point from the global \
         solve's, in units of the mean spacing of the points. At {big_n} points: global solve \
         {t_global:.0} ms, parallel tiles {t_tiled:.0} ms."
    ));
    r.text = text;
    r.html = format!(
        "<table><tr><th>overlap (points shared by neighbours)</th><th>paper: fragments \
         averaged</th><th>ours: tiles with halo = overlap/2</th></tr>\n{rows}</table>\n"
    );
    let mut chart = Figure::new(
        "Error against the global solve (log10, in point spacings; 0 drawn at 10⁻¹⁷)",
        Axes::Chart {
            x: "overlap of neighbouring fragments / tiles (points)".into(),
            y: "log10(max error / mean spacing)".into(),
        },
    );
    for (series, name, color) in [
        (
            paper_series,
            "paper: fragments averaged",
            palette::SERIES[1],
        ),
        (ours_series, "ours: tiles with halos", palette::SERIES[0]),
    ] {
        let stroke = Stroke::solid(color, 1.8);
        chart.line(series.clone(), stroke);
        chart.dots(series, 3.0, color);
        chart.legend(stroke, Some(color), name);
    }
    r.picture(
        ctx,
        "tiles.svg",
        &chart.render(),
        "The paper's averaged fragments level off far from the global solution; tiles with \
         halos converge like 0.268^h to rounding.",
    )?;
    r.check(Check::at_most(
        "tiles (halo 32) vs global solve, 4096 points (absolute)",
        default_err,
        4.0 * EPS * scale,
    ));
    r.check(Check::at_most(
        format!("tiles vs global solve, {big_n} points, chord length (absolute)"),
        big_err,
        4.0 * EPS * max_abs(&big),
    ));
    r.check(Check::at_least(
        "the paper's averaged fragments at overlap 128 stay off (error / mean spacing)",
        paper_last,
        0.01,
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// forward differences

fn forward_differences(ctx: &Context) -> Result<Report> {
    let n = 4096;
    let points = long_path(n, 99);
    let fit = interpolate_curve_flat(2, &points, &InterpolationOptions::default())?;
    let count = 1_000_000;
    let t0 = Instant::now();
    let mut fd = vec![0.0; count * 2];
    let report = fit.curve().sample_uniform_fd(count, &mut fd)?;
    let t_fd = ms(t0);
    let (a, b) = fit.curve().domain();
    let step = (b - a) / (count - 1) as f64;
    let ts: Vec<f64> = (0..count).map(|k| a + k as f64 * step).collect();
    let mut direct = vec![0.0; count * 2];
    let t0 = Instant::now();
    fit.curve().eval_many_par(&ts, &mut direct)?;
    let t_direct = ms(t0);
    let drift = max_diff(&fd, &direct);
    let mut r = Report::new(format!(
        "Spec §4: at equal steps each next point of a cubic piece costs three additions per \
         coordinate. Forward differencing accumulates round-off over long runs, so the library \
         restarts at every knot span (at most {} steps per run here) and reports a bound on \
         the drift. {count} samples of a {n}-point curve: forward differences {t_fd:.0} ms, \
         direct evaluation {t_direct:.0} ms; largest difference {} against the bound {}.",
        report.max_steps,
        sci(drift),
        sci(report.bound)
    ));
    // The difference along the curve: its largest value per block of samples (log10, 0 at
    // 10^-17) against the reported bound.
    let scale = max_abs(&direct);
    let block = count / 500;
    let series: Vec<[f64; 2]> = fd
        .chunks(2 * block)
        .zip(direct.chunks(2 * block))
        .enumerate()
        .map(|(k, (p, q))| {
            let t = a + ((k * block) as f64 + 0.5 * block as f64) * step;
            [t, (max_diff(p, q) / scale).max(1e-17).log10()]
        })
        .collect();
    let mut chart = Figure::new(
        "Forward differences against direct evaluation",
        Axes::Chart {
            x: "curve parameter t".into(),
            y: "log10(largest difference / max|p|)".into(),
        },
    )
    .subtitle(format!(
        "{count} samples, {n}-point curve; largest difference per {block} samples"
    ));
    let ours = Stroke::solid(palette::SERIES[0], 1.4);
    chart.line(series, ours);
    chart.legend(ours, None, "forward differences vs direct evaluation");
    let bound = Stroke::dashed(palette::SERIES[1], 1.6);
    let level = (report.bound / scale).log10();
    chart.line(vec![[a, level], [b, level]], bound);
    chart.legend(bound, None, "the reported drift bound");
    r.picture(
        ctx,
        "forward-differences.svg",
        &chart.render(),
        "The difference stays at rounding along the whole curve, below the bound the library \
         reports, because every knot span restarts the recurrence; it grows slowly with t \
         because the direct evaluation's parameters a + k·h are themselves rounded (by up to \
         ulp(t)/2).",
    )?;
    r.check(Check::at_most(
        format!("{count} forward-differenced samples vs direct evaluation (≤ reported bound)"),
        drift,
        report.bound,
    ));
    r.check(Check::at_most(
        "the bound itself, relative to max|k|",
        report.bound / max_abs(&points),
        1e-10,
    ));
    Ok(r)
}

// ---------------------------------------------------------------------------------------------
// arbitrary parameters

fn arbitrary_parameters(_ctx: &Context) -> Result<Report> {
    let n = 100_000;
    let points = long_path(n, 7);
    let opts = InterpolationOptions::default().with_parametrization(Parametrization::ChordLength);
    let curve = interpolate_curve_flat(2, &points, &opts)?.into_curve();
    let t0 = Instant::now();
    let pp = curve.to_piecewise()?;
    let t_build = ms(t0);
    let (a, b) = curve.domain();
    let mut rng = SplitMix(11);
    let count = 1_000_000;
    let ts: Vec<f64> = (0..count)
        .map(|_| a + (b - a) * (rng.next_f64() + 1.0) / 2.0)
        .collect();
    let (mut bs, mut pw) = (vec![0.0; 2 * count], vec![0.0; 2 * count]);
    // The second of two calls each (the first also maps the output's fresh pages).
    let (mut t_bs, mut t_pw) = (0.0, 0.0);
    for _ in 0..2 {
        let t0 = Instant::now();
        curve.eval_many_par(&ts, &mut bs)?;
        t_bs = ms(t0);
        let t0 = Instant::now();
        pp.eval_many_par(&ts, &mut pw)?;
        t_pw = ms(t0);
    }
    // Point by point at every 97th parameter: the batches' own bits.
    let (mut same_bs, mut same_pw) = (true, true);
    for (k, &t) in ts.iter().enumerate().step_by(97) {
        same_bs &= curve.eval(t) == bs[2 * k..2 * k + 2];
        same_pw &= pp.eval(t) == pw[2 * k..2 * k + 2];
    }
    let scale = max_abs(curve.control_flat());
    let gap = max_diff(&bs, &pw) / scale;
    let mut r = Report::new(format!(
        "Not in the paper: evaluation at {count} random, unsorted parameters of a \
         {n}-point chord-length curve. eval_many_par evaluates the B-spline (a bucket table \
         finds the spans, then the basis on six knots and four control points), {t_bs:.1} ms \
         here; the piecewise polynomial form (one cubic per span, as SciPy's \
         PPoly.from_spline: one table bucket and one record of two cache lines per point), \
         built once in {t_build:.1} ms, {t_pw:.1} ms. The two agree to {} of max|P|.",
        sci(gap)
    ));
    r.check(Check::at_most(
        "piecewise form vs B-spline, 10^6 random parameters (relative to max|P|, ≤ 8 eps)",
        gap,
        8.0 * EPS,
    ));
    r.check(Check::equal(
        "batched B-spline evaluation = single points, bit for bit",
        same_bs,
        true,
    ));
    r.check(Check::equal(
        "batched piecewise evaluation = single points, bit for bit",
        same_pw,
        true,
    ));
    Ok(r)
}
