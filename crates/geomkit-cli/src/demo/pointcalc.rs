//! Demo items of method 4, point equations (Adoniev, Vereshchaga, Naidysh,
//! spec/point-calculus.md): the three b-curves (1)-(3) through the same points, the nine-point
//! surface rows-then-across beside the printed geomatrix (9), and a 3-factor model of a
//! built-in data set with its shares and certified optimum.

use super::{sci, Check, Context, Item, Report};
use anyhow::Result;
use geomkit::exact::Rational;
use geomkit::geom::Curve;
use geomkit::pointcalc::{
    optimize, printed_geomatrix_exact, Goal, Hypersurface, Nodes, OptimizeOptions, PointEquation,
    PointOptions, PointSurface, PrintedSurface,
};
use geomkit_model::PointcalcModel;
use geomkit_plot::figures::point_curves_svg;
use geomkit_plot::figures::{heightmap_figure, linspace, surface_svg, HeightField, Layer};
use geomkit_plot::svg::{palette, Axes, Stroke};
use std::fmt::Write as _;

/// The point-calculus items.
pub fn items() -> Vec<Item> {
    vec![
        Item {
            id: "bcurves",
            title: "Point calculus: the b-curves (1)-(3) through the same three points",
            run: bcurves,
        },
        Item {
            id: "bsurface9",
            title: "Point calculus: the nine-point surface, rows first then across, and the printed geomatrix (9)",
            run: bsurface9,
        },
        Item {
            id: "factors3",
            title: "Point calculus: a 3-factor model with shares and the optimum",
            run: factors3,
        },
    ]
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn q(p: i64, d: i64) -> Rational {
    Rational::new(p.into(), d.into())
}

/// A, C, B of the curves.
const ABC: [[f64; 2]; 3] = [[0.0, 0.0], [2.0, 3.0], [6.0, 0.0]];

fn bcurves(ctx: &Context) -> Result<Report> {
    let points: Vec<Vec<f64>> = ABC.iter().map(|p| p.to_vec()).collect();
    let placements = [
        ("(1), C at t = 1/2", Nodes::paper_half()),
        ("(2), C at t = 1/3", Nodes::paper_third()),
        ("(3), C at t = 2/3", Nodes::paper_two_thirds()),
    ];
    let eqs: Vec<PointEquation> = placements
        .iter()
        .map(|(_, n)| PointEquation::new(n.clone(), points.clone()))
        .collect::<geomkit::Result<_>>()?;
    let mut r = Report::new(
        "Adoniev, Vereshchaga, Naidysh, equations (1)-(3): M = A f_A(t) + C f_C(t) + B f_B(t) \
         with the b-functions of the nodes {0, t_C, 1}. The same source points A, C, B give three \
         curves: the placement t_C of C is a shape parameter. No system is solved; the \
         b-functions are evaluated in the barycentric form and sum to 1.",
    );
    let labelled: Vec<(&PointEquation, String)> = eqs
        .iter()
        .zip(&placements)
        .map(|(e, (name, _))| (e, format!("equation {name}")))
        .collect();
    let svg = point_curves_svg(
        "The b-curves (1), (2), (3) through A, C, B",
        "C placed at t = 1/2, 1/3, 2/3",
        &labelled,
    )?;
    r.picture(
        ctx,
        "bcurves.svg",
        &svg,
        "Three point equations through the same points A(0,0), C(2,3), B(6,0).",
    )?;
    let mut through = 0.0f64;
    let mut sum_dev = 0.0f64;
    for eq in &eqs {
        for (i, &t) in eq.nodes().values().iter().enumerate() {
            through = through.max(dist(&eq.eval(t), eq.point(i)));
        }
        for t in linspace(0.0, 1.0, 1001) {
            sum_dev = sum_dev.max((eq.shares(t).iter().sum::<f64>() - 1.0).abs());
        }
    }
    r.check(Check::at_most(
        "distance from A, C, B at their nodes (all three curves)",
        through,
        0.0,
    ));
    r.check(Check::at_most(
        "|Σ f_i(t) - 1| over 1001 parameters",
        sum_dev,
        4.0 * f64::EPSILON,
    ));
    // The printed coefficients, exactly: (1) C 4tt̄ = 4t - 4t², (2) C 4.5tt̄, B 0.5t(3t-1),
    // (3) A 0.5t̄(2-3t) = 1 - 5/2 t + 3/2 t².
    let p1 = placements[0].1.cardinal_polynomials();
    let p2 = placements[1].1.cardinal_polynomials();
    let p3 = placements[2].1.cardinal_polynomials();
    let exact = p1[1] == vec![q(0, 1), q(4, 1), q(-4, 1)]
        && p2[1] == vec![q(0, 1), q(9, 2), q(-9, 2)]
        && p2[2] == vec![q(0, 1), q(-1, 2), q(3, 2)]
        && p3[0] == vec![q(1, 1), q(-5, 2), q(3, 2)];
    r.check(Check::equal(
        "exact b-function coefficients equal the printed (1)-(3)",
        exact,
        true,
    ));
    let mut text = String::new();
    for ((name, nodes), _) in placements.iter().zip(&eqs) {
        let polys: Vec<String> = nodes
            .cardinal_polynomials()
            .iter()
            .map(|p| {
                let c: Vec<String> = p.iter().map(|x| x.to_string()).collect();
                format!("[{}]", c.join(", "))
            })
            .collect();
        let _ = writeln!(
            text,
            "  {name}: f_A, f_C, f_B power coefficients {}; Lebesgue constant {:.4}",
            polys.join(" "),
            nodes.lebesgue_constant()
        );
    }
    r.text = text;
    Ok(r)
}

/// The nine source points A_ij (row i along v, point j along u).
fn nine_points() -> Vec<Vec<Vec<f64>>> {
    let z = [[0.0, 0.8, 0.2], [0.6, 2.0, 0.9], [0.1, 1.0, 0.3]];
    (0..3)
        .map(|i| {
            (0..3)
                .map(|j| vec![2.0 * j as f64, 2.0 * i as f64, z[i][j]])
                .collect()
        })
        .collect()
}

fn bsurface9(ctx: &Context) -> Result<Report> {
    let net = nine_points();
    let flat: Vec<f64> = net.iter().flatten().flatten().copied().collect();
    let rows = vec![
        Nodes::paper_third(),
        Nodes::paper_half(),
        Nodes::paper_two_thirds(),
    ];
    let across = Nodes::paper_half();
    let good = PointSurface::rows_then_across(rows.clone(), across.clone(), net.clone())?;
    let printed = PrintedSurface::new(net.clone())?;
    let mut r = Report::new(
        "§3: nine points A_ij. The paper combines equations (2), (1), (3) along the rows and the \
         columns into the geomatrix (9), a_ij = U_ij V_ij. As printed it mixes the placements of \
         rows and columns: Σ a_ij = 37/32 ≈ 1.156 at the centre and a_11(1/2, 1/2) = 1/16, so \
         the printed surface depends on the coordinate system and misses the centre point. \
         Rows first (row i with its own placement along u), then across (nodes {0, 1/2, 1} \
         along v) keeps Σ a_ij = 1 and passes through all nine points.",
    );
    let layers = |s: &dyn geomkit::geom::Surface, legend: &str| -> Result<String> {
        Ok(surface_svg(
            legend,
            "nine source points (orange)",
            &[
                Layer::Wireframe {
                    surface: s,
                    count: 12,
                    stroke: Stroke::solid(palette::CURVE.color, 1.0),
                    legend: legend.into(),
                },
                Layer::Points {
                    points: &flat,
                    dim: 3,
                    grid: Some((3, 3)),
                    stroke: None,
                    vertex: palette::NEW_VERTEX,
                    radius: 3.5,
                    legend: "A_ij".into(),
                },
            ],
        )?)
    };
    r.picture(
        ctx,
        "bsurface9_rows.svg",
        &layers(&good, "rows first, then across")?,
        "Rows with placements 1/3, 1/2, 2/3 along u, then across at {0, 1/2, 1}: through all nine points.",
    )?;
    r.picture(
        ctx,
        "bsurface9_printed.svg",
        &layers(&printed, "the geomatrix (9) as printed")?,
        "The printed geomatrix: weights summing to 37/32 at the centre; the surface misses A_22.",
    )?;
    let mut through = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            let p = good.eval(rows[i].values()[j], across.values()[i]);
            through = through.max(dist(&p, &net[i][j]));
        }
    }
    r.check(Check::at_most(
        "rows-then-across: distance from the nine points at their nodes",
        through,
        0.0,
    ));
    let mut sum_dev = 0.0f64;
    for u in linspace(0.0, 1.0, 41) {
        for v in linspace(0.0, 1.0, 41) {
            let s: f64 = good.shares(u, v).iter().flatten().sum();
            sum_dev = sum_dev.max((s - 1.0).abs());
        }
    }
    r.check(Check::at_most(
        "rows-then-across: |Σ a_ij - 1| on a 41×41 grid",
        sum_dev,
        8.0 * f64::EPSILON,
    ));
    let a = printed_geomatrix_exact(&q(1, 2), &q(1, 2));
    let sum: Rational = a.iter().flatten().sum();
    r.check(Check::equal(
        "printed (9): Σ a_ij(1/2, 1/2) (exact)",
        sum.to_string(),
        "37/32".to_string(),
    ));
    r.check(Check::equal(
        "printed (9): a_11(1/2, 1/2) (exact)",
        a[0][0].to_string(),
        "1/16".to_string(),
    ));
    r.check(Check::at_least(
        "printed (9): distance of M(1/2, 1/2) from A_22",
        dist(&printed.eval(0.5, 0.5), &net[1][1]),
        0.1,
    ));
    Ok(r)
}

/// A built-in data set: the yield (%) of a batch process at 3 temperatures (°C), 3 pressures
/// (bar) and 3 catalyst loadings (%), a synthetic response with an interior optimum
/// (y = 90 - 0.02(T - 84)² - 6(p - 2.3)² - 20(c - 1.1)² + 0.05(T - 80)(c - 1)).
fn yield_data() -> (Vec<String>, Vec<Vec<f64>>) {
    let names = vec!["T".to_string(), "p".to_string(), "c".to_string()];
    let f = |t: f64, p: f64, c: f64| {
        90.0 - 0.02 * (t - 84.0).powi(2) - 6.0 * (p - 2.3).powi(2) - 20.0 * (c - 1.1).powi(2)
            + 0.05 * (t - 80.0) * (c - 1.0)
    };
    let mut records = Vec::new();
    for t in [60.0, 80.0, 100.0] {
        for p in [1.0, 2.0, 3.0] {
            for c in [0.5, 1.0, 1.5] {
                records.push(vec![t, p, c, f(t, p, c)]);
            }
        }
    }
    (names, records)
}

fn factors3(ctx: &Context) -> Result<Report> {
    let (names, records) = yield_data();
    let model = Hypersurface::from_records(&names, &records, &[], &PointOptions::default())?;
    let mut r = Report::new(
        "§1, §4: a process with three factors, temperature T ∈ {60, 80, 100} °C, pressure \
         p ∈ {1, 2, 3} bar and catalyst c ∈ {0.5, 1, 1.5} %, each with its own nodes (levels); \
         27 experiments (a built-in synthetic data set, quadratic in each factor). The point \
         equation of the hypersurface passes through every experiment without solving a \
         system; the share of every experiment in a modeled point is a result of its own; the \
         best setting is found globally (Bernstein branch and bound, certified gap).",
    );
    let csv: String = std::iter::once("T,p,c,yield\n".to_string())
        .chain(
            records
                .iter()
                .map(|x| format!("{},{},{},{}\n", x[0], x[1], x[2], x[3])),
        )
        .collect();
    r.file(ctx, "factors3.csv", csv.as_bytes(), "the 27 experiments")?;
    r.file(
        ctx,
        "factors3_model.json",
        geomkit_model::to_json(&PointcalcModel::file_of(&model, &["yield".to_string()]))?
            .as_bytes(),
        "the model (geomkit pointcalc eval/shares/optimize/formula read it)",
    )?;
    let worst = records
        .iter()
        .map(|x| (model.eval(&x[..3]).map(|v| v[0]).unwrap_or(f64::NAN) - x[3]).abs())
        .fold(0.0, f64::max);
    r.check(Check::at_most(
        "|model - yield| at the 27 experiments",
        worst,
        0.0,
    ));
    // The data is quadratic per factor: the model reproduces it everywhere.
    let at = [75.0, 2.6, 1.2];
    let f = 90.0
        - 0.02 * (at[0] - 84.0f64).powi(2)
        - 6.0 * (at[1] - 2.3f64).powi(2)
        - 20.0 * (at[2] - 1.1f64).powi(2)
        + 0.05 * (at[0] - 80.0) * (at[2] - 1.0);
    let m = model.eval(&at)?[0];
    r.check(Check::at_most(
        "|model - response| at (75, 2.6, 1.2) (quadratic data: exact up to rounding)",
        (m - f).abs(),
        1e-12,
    ));
    let shares = model.shares(&at)?;
    let sum: f64 = shares.iter().sum();
    r.check(Check::at_most(
        "|Σ shares - 1| at (75, 2.6, 1.2)",
        (sum - 1.0).abs(),
        1e-14,
    ));
    let mut order: Vec<usize> = (0..shares.len()).collect();
    order.sort_by(|&a, &b| shares[b].abs().total_cmp(&shares[a].abs()));
    let mut text = format!("  modeled yield at T=75, p=2.6, c=1.2: {m:.6}; largest shares:\n");
    for &c in order.iter().take(5) {
        let l = model.cell_levels(c);
        let _ = writeln!(
            text,
            "    T={}, p={}, c={}: share {:+.5}",
            l[0], l[1], l[2], shares[c]
        );
    }
    let best = optimize(&model, Goal::Max, &OptimizeOptions::default())?;
    let _ = writeln!(
        text,
        "  optimum: yield {:.6} at T={:.4}, p={:.4}, c={:.4} (bound {:.6}, gap {}, {} boxes)",
        best.value,
        best.at[0],
        best.at[1],
        best.at[2],
        best.bound,
        sci(best.gap),
        best.boxes
    );
    r.text = text;
    // The model's slice through the optimum: yield over (T, p) at its catalyst level, with
    // the experiments' (T, p) levels and the optimum.
    let c_best = best.at[2];
    let slice = |ts: &[f64], ps: &[f64], z: &mut [f64]| -> geomkit::Result<()> {
        let pts: Vec<f64> = ts
            .iter()
            .flat_map(|&t| ps.iter().flat_map(move |&p| [t, p, c_best]))
            .collect();
        model.eval_many(&pts, z)
    };
    let field = HeightField {
        domain: ((60.0, 100.0), (1.0, 3.0)),
        grid: &slice,
    };
    let mut fig = heightmap_figure(
        &format!("Modeled yield over T and p at the optimal catalyst c = {c_best:.3} %"),
        "the point equation through 27 experiments, evaluated on an 80×80 grid",
        &field,
        80,
        10,
        Axes::Chart {
            x: "temperature T (°C)".into(),
            y: "pressure p (bar)".into(),
        },
    )?;
    let levels: Vec<[f64; 2]> = [60.0, 80.0, 100.0]
        .iter()
        .flat_map(|&t| [1.0, 2.0, 3.0].map(|p| [t, p]))
        .collect();
    fig.dots(levels, 3.5, "#222222");
    fig.legend(
        Stroke::solid("#222222", 0.0),
        Some("#222222"),
        "experiment levels (T, p)",
    );
    fig.dots(vec![[best.at[0], best.at[1]]], 6.0, palette::NEW_VERTEX);
    fig.legend(
        Stroke::solid(palette::NEW_VERTEX, 0.0),
        Some(palette::NEW_VERTEX),
        format!(
            "certified optimum {:.3} at T = {:.2}, p = {:.3}",
            best.value, best.at[0], best.at[1]
        ),
    );
    r.picture(
        ctx,
        "factors3.svg",
        &fig.render(),
        "The model's slice through its optimum: every experiment is reproduced exactly, and \
         the maximum found by the certified branch and bound lies inside the grid of levels.",
    )?;
    r.check(Check::equal("optimum certified", best.certified, true));
    let brute = {
        let mut m = f64::NEG_INFINITY;
        for t in linspace(60.0, 100.0, 41) {
            for p in linspace(1.0, 3.0, 41) {
                for c in linspace(0.5, 1.5, 41) {
                    m = m.max(model.eval(&[t, p, c])?[0]);
                }
            }
        }
        m
    };
    r.check(Check::at_most(
        "41³ grid scan maximum minus the certified bound",
        brute - best.bound,
        0.0,
    ));
    r.check(Check::at_most(
        "certified gap (bound - value)",
        best.gap,
        1e-9 * 60.0,
    ));
    // Removing the level p = 2 and adding it back gives the same model.
    let slice = model.level_slice(1, 1)?;
    let back = model.remove_level(1, 1)?.add_level(1, 2.0, &slice)?;
    r.check(Check::equal(
        "remove level p = 2 and add it back: the same model",
        back == model,
        true,
    ));
    Ok(r)
}
