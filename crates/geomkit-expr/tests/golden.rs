//! Golden files (insta snapshots) of the LaTeX, Maple, Mathematica and Desmos printers, and
//! precedence cases for every target.

use geomkit_expr::{fixtures, parse, Format, Graph, Id};

fn golden_cases(g: &mut Graph) -> Vec<(&'static str, Vec<Id>)> {
    let cube = fixtures::cube(g).to_vec();
    let coef = fixtures::random_coef(5, (2, 1), (1, 1), 1);
    let uk = fixtures::uniform_knots(2);
    let vk = fixtures::uniform_knots(1);
    let bilinear = fixtures::composite_poly(g, &uk, &vk, (1, 1), 1, |i, j, k, l, c| {
        // Simple exact-looking coefficients: 1/4-steps.
        (coef(i, j, k, l, c) * 4.0).round() / 4.0
    });
    let mixed = [
        "-(u - v)^2/(3*(1 + u^2)) + 2/3*abs(u)^3 - sqrt(u^2 + v^2)",
        "sin(pi*u)*cos(v)^2 - exp(-u^2/2) + ln(1 + abs(v)) - atan(u/v)",
        "-u^-3 + (u*v)^5 - sign(u - 1)*tanh(v)",
    ];
    let mut out = vec![("cube", cube), ("bilinear_2x1", bilinear)];
    for (i, m) in mixed.iter().enumerate() {
        let name: &'static str = ["mixed_1", "mixed_2", "mixed_3"][i];
        out.push((name, vec![parse(g, m).unwrap()]));
    }
    out
}

fn render(f: Format) -> String {
    let mut g = Graph::new();
    let mut s = String::new();
    for (name, roots) in golden_cases(&mut g) {
        s.push_str(&format!("# {name}: inline\n"));
        for r in &roots {
            s.push_str(&g.print(*r, f).unwrap());
            s.push('\n');
        }
        s.push_str(&format!("# {name}: function\n"));
        s.push_str(&g.print_function("f", &["u", "v"], &roots, f).unwrap());
    }
    s
}

#[test]
fn golden_latex() {
    insta::assert_snapshot!(render(Format::Latex));
}

#[test]
fn golden_maple() {
    insta::assert_snapshot!(render(Format::Maple));
}

#[test]
fn golden_mathematica() {
    insta::assert_snapshot!(render(Format::Mathematica));
}

#[test]
fn golden_desmos() {
    insta::assert_snapshot!(render(Format::Desmos));
}

/// The same expressions in every target: precedence-critical spellings.
#[test]
fn precedence_in_every_target() {
    let mut g = Graph::new();
    let e = parse(&mut g, "-(u - 1)^2 + abs(u - 2)/(v*(u + 1)) - 1/3").unwrap();
    let want = [
        (Format::Maple, "-(u - 1)^2 + abs(u - 2)/(v*(u + 1)) - 1/3"),
        (Format::Mathematica, "-(u - 1)^2 + Abs[u - 2]/(v*(u + 1)) - 1/3"),
        (Format::Sympy, "-(u - 1)**2 + Abs(u - 2)/(v*(u + 1)) - Rational(1, 3)"),
        (Format::Numpy, "-(u - 1)**2 + np.abs(u - 2)/(v*(u + 1)) - 1/3"),
        (Format::Matlab, "-(u - 1).^2 + abs(u - 2)./(v.*(u + 1)) - 1/3"),
        (Format::Latex, "-{\\left(u - 1\\right)}^{2} + \\frac{\\left|u - 2\\right|}{v \\left(u + 1\\right)} - \\frac{1}{3}"),
        (Format::C, "-(u - 1.0)*(u - 1.0) + fabs(u - 2.0)/(v*(u + 1.0)) - (1.0/3.0)"),
        (Format::Rust, "-(u - 1.0).powi(2) + (u - 2.0).abs()/(v*(u + 1.0)) - (1.0/3.0)"),
        (Format::Glsl, "-(u - 1.0)*(u - 1.0) + abs(u - 2.0)/(v*(u + 1.0)) - (1.0/3.0)"),
        (Format::Js, "-(u - 1)*(u - 1) + Math.abs(u - 2)/(v*(u + 1)) - (1/3)"),
        (Format::Desmos, "-{\\left(u - 1\\right)}^{2} + \\frac{\\left|u - 2\\right|}{v\\cdot \\left(u + 1\\right)} - \\frac{1}{3}"),
    ];
    for (f, w) in want {
        assert_eq!(g.print(e, f).unwrap(), w, "{f:?}");
        assert_eq!(Format::from_name(f.name()), Some(f));
    }
}
