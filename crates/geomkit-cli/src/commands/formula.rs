//! The formulas of `geomkit compose`: the `--format` syntax, the printed text, the first
//! line for a picture's subtitle, and the formula file (`-o OUT.json`).

use geomkit::compose::Formula;
use geomkit::expr::Format;
use geomkit_model::schema::FormulaFile;
use geomkit_model::ModelFile;
use serde_json::Value;

pub fn formula_text(f: &Formula, format: Format, program: bool) -> anyhow::Result<String> {
    Ok(if program {
        f.print_program(format)?
    } else {
        f.print(format)?
    })
}

/// The formula file (`-o OUT.json`): the formula in every syntax, its size, the continuity
/// report and the model it was made from, which `geomkit eval`, `mesh` and `render` read
/// back.
pub fn formula_json(
    f: &Formula,
    what: &str,
    continuity: Option<Value>,
    model: Option<ModelFile>,
) -> anyhow::Result<String> {
    Ok(geomkit_model::to_json(&ModelFile::Formula(FormulaFile {
        what: what.to_string(),
        variables: f.vars.clone(),
        coordinates: f.names.clone(),
        op_count: f.op_count(),
        formulas: Format::ALL
            .into_iter()
            .map(|fmt| Ok((fmt.name().to_string(), f.print(fmt)?)))
            .collect::<geomkit::Result<_>>()?,
        continuity,
        model: model.map(Box::new),
    }))?)
}

/// The first line of the Maple formula, shortened to 140 characters (a picture's subtitle).
pub fn formula_line(f: &Formula) -> anyhow::Result<String> {
    let first = f.print(Format::Maple)?;
    let line = first.lines().next().unwrap_or_default();
    Ok(if line.chars().count() > 140 {
        line.chars().take(137).collect::<String>() + "..."
    } else {
        line.to_string()
    })
}
