//! `geomkit export MODEL -o part.step` and `geomkit import part.step -o DIR_OR_FILE`: the
//! model crate's STEP writer and reader ([`geomkit_model::step`]) with atomic writes.

use crate::cli::{ExportArgs, ImportArgs, SchemaArg};
use crate::model::read_any_model;
use crate::output::{ensure_dir, write_atomic};
use crate::table::extension;
use anyhow::{bail, Context, Result};
use geomkit_model::step::{self, Schema, WriteOptions};
use std::io::Write;
use std::path::PathBuf;

/// Runs `geomkit export`.
pub fn export(args: ExportArgs) -> Result<()> {
    if !matches!(extension(&args.output).as_deref(), Some("step" | "stp")) {
        bail!(
            "cannot tell the format of {}: name it .step or .stp",
            args.output.display()
        );
    }
    let model = read_any_model(&args.model)?;
    let name = args.name.clone().unwrap_or_else(|| {
        args.model
            .file_stem()
            .map_or("geomkit".into(), |s| s.to_string_lossy().into_owned())
    });
    let schema = match args.schema {
        SchemaArg::Ap214 => Schema::Ap214,
        SchemaArg::Ap242 => Schema::Ap242,
    };
    let options = WriteOptions::default()
        .with_name(name)
        .with_schema(schema)
        .with_tolerance(args.tolerance);
    let export = step::export(&model, &options)
        .with_context(|| format!("{}: cannot export", args.model.display()))?;
    let text = export.text;
    write_atomic(&args.output, text.as_bytes())?;
    let mut err = std::io::stderr();
    for a in &export.approximations {
        let _ = writeln!(err, "warning: approximated {}", a.describe());
    }
    let _ = writeln!(
        err,
        "wrote {}: {} as STEP ({} entities, {} bytes)",
        args.output.display(),
        model.describe(),
        text.lines().filter(|l| l.starts_with('#')).count(),
        text.len()
    );
    Ok(())
}

/// Runs `geomkit import`.
pub fn import(args: ImportArgs) -> Result<()> {
    let name = args.input.display().to_string();
    let text = std::fs::read(&args.input).with_context(|| format!("cannot read {name}"))?;
    // STEP is ASCII; other bytes (in strings) are read leniently.
    let text = String::from_utf8_lossy(&text);
    let import = step::read(&text).with_context(|| name.clone())?;
    // Everything is computed before anything is written.
    let mut outputs: Vec<(PathBuf, String, String)> = Vec::new();
    let single = extension(&args.output).as_deref() == Some("json");
    if single && import.models.len() != 1 {
        bail!(
            "{name} holds {} models: give a folder (-o DIR) to receive one file each",
            import.models.len()
        );
    }
    for m in &import.models {
        let json = geomkit_model::to_json(&m.file).with_context(|| format!("{name}: #{}", m.id))?;
        let path = if single {
            args.output.clone()
        } else {
            let span: String = m.span.iter().map(|k| format!("-{k}")).collect();
            args.output
                .join(format!("{}-{}{span}.json", m.file.type_name(), m.id))
        };
        let model = geomkit_model::AnyModel::from_file(m.file.clone())
            .with_context(|| format!("{name}: #{}", m.id))?;
        let mut line = format!(
            "wrote {}: {} from #{} {}",
            path.display(),
            model.describe(),
            m.id,
            m.entity
        );
        if !m.name.is_empty() {
            line.push_str(&format!(" '{}'", m.name));
        }
        if let Some(note) = &m.note {
            line.push_str(&format!(" ({note})"));
        }
        outputs.push((path, json, line));
    }
    if !single {
        ensure_dir(&args.output)?;
    }
    let mut err = std::io::stderr();
    for (path, json, line) in &outputs {
        write_atomic(path, json.as_bytes())?;
        let _ = writeln!(err, "{line}");
    }
    if let Some(unit) = import
        .length_unit
        .as_deref()
        .filter(|u| *u != "MILLI METRE")
    {
        let _ = writeln!(
            err,
            "note: lengths are in the file's unit ({unit}), as written"
        );
    }
    for t in &import.trimmed {
        let holes = match t.loops {
            0 | 1 => String::new(),
            n => format!(" and {} hole(s)", n - 1),
        };
        let _ = writeln!(
            err,
            "warning: face #{} is trimmed (its outline{holes}): imported as the whole surface \
             #{}, the trimming is not kept",
            t.face, t.surface
        );
    }
    if !import.skipped.is_empty() {
        let _ = writeln!(err, "skipped: {}", import.skipped_summary());
    }
    Ok(())
}
