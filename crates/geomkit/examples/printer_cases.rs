//! The printed formulas that tests/printers/ checks with independent tools: every formula of a
//! representative set (the cube, a cylinder, a frustum, a composite of interpolated patches, a
//! piecewise function and curve, random expressions, every function) in JavaScript, LaTeX,
//! Desmos and Mathematica, with `Graph::eval`'s values at 200 points of each.
//!
//!   cargo run --release -p geomkit --example printer_cases -- OUT.json
//!
//! tests/printers/check.mjs runs the JavaScript in node against those values, renders the
//! LaTeX and Desmos text with KaTeX and evaluates KaTeX's parse tree against them;
//! tests/printers/mathematica.py parses the Mathematica text with SymPy's
//! `parse_mathematica` and evaluates it against them.

use geomkit::bspline::interpolate_surface;
use geomkit::compose::{bodies, CompositeSurface, Formula, Piecewise};
use geomkit::expr::{fixtures, parse, Format, Graph};
use serde_json::{json, Value};

/// A deterministic random expression in u and v of the given depth, as text for the parser.
fn random_expression(seed: &mut u64, depth: u32) -> String {
    let next = |seed: &mut u64, n: u64| {
        *seed = seed.wrapping_add(1);
        (fixtures::unit(*seed) * n as f64) as u64 % n
    };
    if depth == 0 {
        return match next(seed, 4) {
            0 => "u".into(),
            1 => "v".into(),
            2 => format!("{}", next(seed, 9) + 1),
            _ => format!("{}/{}", next(seed, 9) + 1, next(seed, 7) + 2),
        };
    }
    let k = next(seed, 14);
    let a = random_expression(seed, depth - 1);
    let b = random_expression(seed, depth - 1);
    match k {
        0 => format!("{a} + {b}"),
        1 => format!("{a} - ({b})"),
        2 => format!("({a})*({b})"),
        3 => format!("({a})/(1 + ({b})^2)"),
        4 => format!("-({a})"),
        5 => format!("({a})^{}", next(seed, 4) + 2),
        6 => format!("(2 + ({a})^2)^-{}", next(seed, 3) + 1),
        7 => format!("sin({a})"),
        8 => format!("cos({a}) - {b}"),
        9 => format!("exp(-({a})^2)"),
        10 => format!("sqrt(1 + abs({a}))"),
        11 => format!("atan({a})*tanh({b})"),
        12 => format!("ln(1 + ({a})^2)"),
        _ => format!("u - {a}/(3 + v^2)"),
    }
}

/// One case: the formula's printed forms and values at `points`.
fn case(name: &str, f: &Formula, points: &[Vec<f64>]) -> Value {
    let vars: Vec<&str> = f.vars.iter().map(String::as_str).collect();
    let g: &Graph = &f.graph;
    let outputs: Vec<Value> = f
        .names
        .iter()
        .zip(&f.roots)
        .map(|(n, &r)| {
            let values: Vec<Value> = points
                .iter()
                .map(|p| {
                    let bind: Vec<(&str, f64)> =
                        vars.iter().copied().zip(p.iter().copied()).collect();
                    let x = g.eval(r, &bind).expect("evaluates");
                    if x.is_finite() {
                        json!(x)
                    } else {
                        json!(x.to_string())
                    }
                })
                .collect();
            json!({
                "name": n,
                "js": g.print(r, Format::Js).unwrap(),
                "latex": g.print(r, Format::Latex).unwrap(),
                "desmos": g.print(r, Format::Desmos).unwrap(),
                "mathematica": g.print(r, Format::Mathematica).unwrap(),
                "values": values,
            })
        })
        .collect();
    json!({
        "name": name,
        "vars": vars,
        "names": f.names,
        "points": points,
        "outputs": outputs,
        "js_definitions": f.print(Format::Js).unwrap(),
        "js_program": f.print_program(Format::Js).unwrap(),
        "latex_definitions": f.print(Format::Latex).unwrap(),
        "desmos_definitions": f.print(Format::Desmos).unwrap(),
    })
}

/// `count` points of [lo, hi] per variable, pseudo-random, plus the corners.
fn points(lo: &[f64], hi: &[f64], count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut pts = vec![lo.to_vec(), hi.to_vec()];
    let mut k = seed * 1000;
    while pts.len() < count {
        pts.push(
            lo.iter()
                .zip(hi)
                .map(|(a, b)| {
                    k += 1;
                    a + (b - a) * fixtures::unit(k)
                })
                .collect(),
        );
    }
    pts
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .ok_or("usage: printer_cases OUT.json")?;
    let mut cases = Vec::new();
    let surface_points = |lo: [f64; 2], hi: [f64; 2], seed| points(&lo, &hi, 200, seed);

    cases.push(case(
        "cube",
        &bodies::cube()?.formula()?,
        &surface_points([-0.5, -0.5], [4.5, 3.5], 1),
    ));
    cases.push(case(
        "cylinder",
        &bodies::cylinder(1.5, 2.0)?.formula()?,
        &surface_points([0.0, 0.0], [6.3, 3.0], 2),
    ));
    cases.push(case(
        "frustum",
        &bodies::frustum(1.0, 0.5, 2.0)?.formula()?,
        &surface_points([0.0, 0.0], [6.3, 3.0], 3),
    ));
    let heights: Vec<Vec<Vec<f64>>> = (0..5)
        .map(|i| {
            (0..4)
                .map(|j| {
                    let (x, y) = (i as f64, j as f64);
                    vec![x, y, (0.7 * x).sin() * (0.5 * y).cos()]
                })
                .collect()
        })
        .collect();
    let spline = interpolate_surface(&heights, &Default::default())?.surface;
    let composite = CompositeSurface::from_bspline(&spline)?;
    let ((u0, u1), (v0, v1)) = composite.domain();
    cases.push(case(
        "composite_patches",
        &composite.formula()?,
        &surface_points([u0 - 0.2, v0 - 0.2], [u1 + 0.2, v1 + 0.2], 4),
    ));
    let piecewise = Piecewise::function(
        vec![-1.0, 0.0, 0.5, 2.0],
        &["x^2 - 1", "-1 + sin(3*x)", "exp(x) - 2.5"],
    )?;
    cases.push(case(
        "piecewise_function",
        &piecewise.formula()?,
        &points(&[-1.5], &[2.5], 200, 5),
    ));
    let polyline = Piecewise::polyline(
        vec![
            vec![0.0, 0.0],
            vec![1.0, 2.0],
            vec![3.0, 1.0],
            vec![4.0, -1.0],
        ],
        None,
        false,
    )?;
    let (t0, t1) = {
        let k = polyline.knots();
        (k[0], k[k.len() - 1])
    };
    cases.push(case(
        "piecewise_polyline",
        &polyline.formula()?,
        &points(&[t0 - 0.5], &[t1 + 0.5], 200, 6),
    ));
    // Random expressions in u and v, one formula of 8 coordinates per depth.
    for depth in 2..=5u32 {
        let mut graph = Graph::new();
        let mut seed = 1000 * depth as u64;
        let roots = (0..8)
            .map(|_| parse(&mut graph, &random_expression(&mut seed, depth)))
            .collect::<Result<Vec<_>, _>>()?;
        let f = Formula {
            graph,
            names: (0..roots.len()).map(|k| format!("f{k}")).collect(),
            roots,
            vars: vec!["u".into(), "v".into()],
        };
        cases.push(case(
            &format!("random_depth_{depth}"),
            &f,
            &surface_points([-2.0, -2.0], [2.0, 2.0], 10 + depth as u64),
        ));
    }
    // Every function of the parser, the formula of crates/geomkit-expr/tests/compile.rs.
    let mut graph = Graph::new();
    let every = parse(
        &mut graph,
        "sqrt(abs(u) + 1)*sin(v) + cos(u*v)^2 - tan(u/7) + exp(-v^2) + ln(1 + u^2) \
         + atan(u - v) + asin(v/10) - acos(u/5) + sign(u - 1/2)*sinh(u/3) + cosh(v/4) \
         + tanh(u)/(1 + v^2) + u^7 - 3*(1 + v^2)^-3 + pi*u/3 - abs(u - v)^3 + 0.1*u*v^5",
    )?;
    let f = Formula {
        graph,
        roots: vec![every],
        names: vec!["f".into()],
        vars: vec!["u".into(), "v".into()],
    };
    cases.push(case(
        "every_function",
        &f,
        &surface_points([-0.5, -0.5], [4.5, 3.5], 20),
    ));
    std::fs::write(
        &out,
        serde_json::to_string_pretty(&json!({ "cases": cases }))?,
    )?;
    eprintln!("printer_cases: {} cases written to {out}", cases.len());
    Ok(())
}
