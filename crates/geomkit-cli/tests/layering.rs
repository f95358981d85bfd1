//! The CLI's modules are layered: no module imports one that imports it back (directly or
//! through others), the clap types (`cli`) and the demo import no command module, and the
//! shared modules (model, output, table, npy, progress) import neither commands nor the demo.
//! Read from the source files' `crate::` and `super::` paths (test modules left out).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// `commands/eval.rs` -> `commands::eval`, `cli/mod.rs` -> `cli`.
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts.join("::")
}

/// The modules a source text names through `crate::a::b` and `super::b` (to the depth of a
/// command or demo module), outside its test module.
fn imports(module: &str, text: &str) -> BTreeSet<String> {
    let code = text.split("#[cfg(test)]").next().unwrap();
    let mut out = BTreeSet::new();
    let names = |rest: &str| -> Vec<String> {
        rest.split("::")
            .take(2)
            .map(|p| {
                p.chars()
                    .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                    .collect::<String>()
            })
            .take_while(|p| !p.is_empty())
            .collect()
    };
    for (k, _) in code.match_indices("crate::") {
        let parts = names(&code[k + 7..]);
        let Some(first) = parts.first() else { continue };
        let target = match (first.as_str(), parts.get(1)) {
            ("commands" | "demo", Some(sub)) => format!("{first}::{sub}"),
            _ => first.clone(),
        };
        out.insert(target);
    }
    for (k, _) in code.match_indices("super::") {
        let parts = names(&code[k + 7..]);
        let Some(first) = parts.first() else { continue };
        let parent = module.rsplit_once("::").map_or("", |(p, _)| p);
        out.insert(if parent.is_empty() {
            first.clone()
        } else {
            format!("{parent}::{first}")
        });
    }
    out.remove(module);
    out
}

#[test]
fn modules_are_layered_without_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let graph: BTreeMap<String, BTreeSet<String>> = files
        .iter()
        .map(|f| {
            let m = module_of(&src, f);
            let deps = imports(&m, &fs::read_to_string(f).unwrap());
            (m, deps)
        })
        .collect();
    assert!(graph.contains_key("commands::eval") && graph.contains_key("demo::gallery"));

    // Depth-first search for a module that reaches itself.
    fn visit<'a>(
        m: &'a str,
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<&'a str>,
        done: &mut BTreeSet<&'a str>,
    ) {
        if let Some(k) = path.iter().position(|p| *p == m) {
            panic!("import circle: {} -> {m}", path[k..].join(" -> "));
        }
        if !done.insert(m) {
            return;
        }
        path.push(m);
        for d in graph.get(m).into_iter().flatten() {
            visit(d, graph, path, done);
        }
        path.pop();
    }
    let mut done = BTreeSet::new();
    for m in graph.keys() {
        visit(m, &graph, &mut Vec::new(), &mut done);
    }

    for (m, deps) in &graph {
        let top = m.split("::").next().unwrap();
        if top == "commands" || m == "main" {
            continue;
        }
        let bad: Vec<&String> = deps
            .iter()
            .filter(|d| d.starts_with("commands") || (top != "demo" && d.starts_with("demo")))
            .collect();
        assert!(bad.is_empty(), "{m} imports {bad:?}");
    }
}

#[test]
fn the_checker_sees_a_circle() {
    // The parser reads both kinds of path, so a circle would not go unseen.
    let a = imports("commands::a", "use super::b::run;\nuse crate::output::x;");
    assert_eq!(
        a,
        ["commands::b", "output"]
            .map(String::from)
            .into_iter()
            .collect()
    );
    let b = imports(
        "commands::b",
        "use crate::commands::a::f;\n#[cfg(test)]\nuse super::c;",
    );
    assert_eq!(b, ["commands::a"].map(String::from).into_iter().collect());
}
