//! Demo item of the STEP export (issue 26): every closed body and the 14×14 interpolated
//! B-spline surface as ISO 10303-21 files a CAD system opens, linked from the gallery, with
//! the checks that need no CAD system (the round trip of the surface bit for bit; the closed
//! shells' edges each used by two faces). OpenCASCADE's verdict on the same files is
//! `bash bench/compat_step.sh`.

use super::{Check, Context, Item, Report};
use anyhow::{Context as _, Result};
use geomkit::compose::{bodies, RuledSurface};
use geomkit_model::step::{self, WriteOptions};
use geomkit_model::AnyModel;
use std::collections::BTreeMap;

/// The items, in order.
pub fn items() -> Vec<Item> {
    vec![Item {
        id: "step-export",
        title: "STEP export: the bodies and the 14×14 B-spline surface as exact CAD geometry",
        run: export,
    }]
}

/// How often each EDGE_CURVE is used by an ORIENTED_EDGE, from the file's text.
fn edge_uses(text: &str) -> BTreeMap<u64, usize> {
    let mut uses: BTreeMap<u64, usize> = BTreeMap::new();
    for line in text.lines() {
        if let Some((id, body)) = line.split_once('=') {
            if body.starts_with("EDGE_CURVE(") {
                if let Ok(n) = id.trim_start_matches('#').parse() {
                    uses.entry(n).or_insert(0);
                }
            }
            if let Some(rest) = body.strip_prefix("ORIENTED_EDGE('',*,*,#") {
                let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
                if let Ok(n) = digits.parse() {
                    *uses.entry(n).or_insert(0) += 1;
                }
            }
        }
    }
    uses
}

fn export(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "`geomkit export MODEL -o part.step` writes exact geometry as ISO 10303-21 (AP214): \
         each body a MANIFOLD_SOLID_BREP whose CLOSED_SHELL shares its edges and vertices \
         between faces (planes as degree-1 B-spline surfaces, circles as rational quadratics), \
         surfaces as B_SPLINE_SURFACE_WITH_KNOTS faces bounded by their boundary curves. \
         OpenCASCADE 7.9 reads every file as a valid shape, the bodies as closed solids of \
         the exact volume (cube 8) within 1e-11, the surface's points equal to geomkit's \
         within 1e-15 relative (bash bench/compat_step.sh).",
    );
    let polygon6 = bodies::regular_polygon(6, 1.0)?;
    let shapes: [(&str, &str, RuledSurface); 7] = [
        ("cube", "the paper's cube", bodies::cube()?),
        ("box", "box 1×2×3", bodies::rectangular_box(1.0, 2.0, 3.0)?),
        ("prism", "hexagonal prism", bodies::prism(&polygon6, 2.0)?),
        (
            "pyramid",
            "square pyramid",
            bodies::square_pyramid(2.0, 2.0)?,
        ),
        ("cone", "cone", bodies::cone(1.0, 2.0)?),
        ("cylinder", "capped cylinder", bodies::cylinder(1.0, 2.0)?),
        ("frustum", "frustum", bodies::frustum(1.0, 0.5, 2.0)?),
    ];
    let mut worst_uses = (String::new(), 2usize);
    for (name, what, body) in shapes {
        let text = step::write(
            &AnyModel::Ruled(body),
            &WriteOptions::default().with_name(name),
        )?;
        r.file(
            ctx,
            &format!("step-{name}.step"),
            text.as_bytes(),
            &format!("{what} as a STEP solid"),
        )?;
        for (_, &n) in edge_uses(&text).iter() {
            if n != 2 {
                worst_uses = (name.to_string(), n);
            }
        }
    }
    r.check(Check::equal(
        "closed shells: every edge used by exactly two oriented edges (7 bodies)",
        if worst_uses.0.is_empty() {
            "2".to_string()
        } else {
            format!("{} in {}", worst_uses.1, worst_uses.0)
        },
        "2".to_string(),
    ));
    // The 14×14 surface the B-spline demo wrote, exported and read back.
    let json = std::fs::read_to_string(ctx.dir.join("surf14.json"))
        .context("surf14.json (written by the B-spline demo)")?;
    let model = geomkit_model::parse(&json)?;
    let text = step::write(&model, &WriteOptions::default().with_name("surf14"))?;
    r.file(
        ctx,
        "surf14.step",
        text.as_bytes(),
        "the 14×14 B-spline surface as a STEP face",
    )?;
    let back = step::read(&text)?;
    let same = match (&model, back.models.first().map(|m| &m.file)) {
        (AnyModel::BsplineSurface(m), Some(file)) => {
            let ours = geomkit_model::to_json(&geomkit_model::BsplineSurfaceModel::file_of(
                &m.surface, None,
            ))?;
            ours == geomkit_model::to_json(file)?
        }
        _ => false,
    };
    r.check(Check::equal(
        "surf14.step read back: the same 16×16 net and knots, bit for bit",
        same.to_string(),
        "true".to_string(),
    ));
    Ok(r)
}
