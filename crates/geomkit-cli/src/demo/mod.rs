//! `geomkit demo`: every method contributes items; each item writes its pictures and model
//! files into the output directory and returns a caption and a list of checks. The demo
//! writes `index.html` showing everything, prints a table of all checks, and fails (exit
//! code 1) if any check fails.
//!
//! Adding a method: write `demo/NAME.rs` with `pub fn items() -> Vec<Item>` and add
//! `NAME::items` to [`MODULES`].

mod bezier;
mod bspline;
mod compose;
mod gallery;
mod pointcalc;
mod step;

use crate::cli::DemoArgs;
use crate::model::{to_json, BezierModel, ErrorReport};
use crate::output::{ensure_dir, write_atomic, write_stdout};
use anyhow::{bail, Result};
use geomkit_plot::svg::escape;
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Every method's list of demo items, in the order shown.
const MODULES: &[fn() -> Vec<Item>] = &[
    bezier::items,
    bspline::items,
    compose::items,
    pointcalc::items,
    gallery::items,
    step::items,
];

/// One demo item: a figure or table of a paper, reproduced.
pub struct Item {
    /// Short id, also the prefix of its files ("fig1a").
    pub id: &'static str,
    /// Title shown in index.html.
    pub title: &'static str,
    /// Computes, writes the item's files and reports.
    pub run: fn(&Context) -> Result<Report>,
}

/// Where an item writes its files.
pub struct Context {
    dir: PathBuf,
}

impl Context {
    /// Writes `contents` to the file `name` of the output directory, atomically.
    pub fn write(&self, name: &str, contents: &str) -> Result<()> {
        self.write_bytes(name, contents.as_bytes())
    }

    /// Writes binary `contents` to the file `name` of the output directory, atomically.
    pub fn write_bytes(&self, name: &str, contents: &[u8]) -> Result<()> {
        write_atomic(&self.dir.join(name), contents)
    }
}

/// One check of a demo item: what was checked, the measured value, the limit, pass or fail.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// What was checked.
    pub name: String,
    /// The measured value, formatted.
    pub measured: String,
    /// The limit it was held to ("≤ 4.4e-16").
    pub limit: String,
    /// Whether it passed.
    pub passed: bool,
}

/// A number in the checks table.
pub fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.is_nan() {
        "NaN".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:.2e}")
    }
}

impl Check {
    /// Passes when `value <= limit` (NaN fails).
    pub fn at_most(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Check {
            name: name.into(),
            measured: sci(value),
            limit: format!("≤ {}", sci(limit)),
            passed: value <= limit,
        }
    }

    /// Passes when `value >= limit` (NaN fails).
    pub fn at_least(name: impl Into<String>, value: f64, limit: f64) -> Self {
        Check {
            name: name.into(),
            measured: sci(value),
            limit: format!("≥ {}", sci(limit)),
            passed: value >= limit,
        }
    }

    /// Passes when `got == want`.
    pub fn equal<T: PartialEq + std::fmt::Display>(
        name: impl Into<String>,
        got: T,
        want: T,
    ) -> Self {
        Check {
            name: name.into(),
            measured: got.to_string(),
            limit: format!("= {want}"),
            passed: got == want,
        }
    }
}

/// A picture of an item.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// File name in the output directory.
    pub file: String,
    /// Caption under the picture.
    pub caption: String,
}

/// What an item reports.
#[derive(Debug, Clone, Default)]
pub struct Report {
    /// Paper, figure and what it shows (plain text).
    pub caption: String,
    /// Pictures written.
    pub pictures: Vec<Picture>,
    /// Model files written, with a description.
    pub files: Vec<(String, String)>,
    /// Extra HTML (tables, matrices) shown after the pictures.
    pub html: String,
    /// Extra text printed to stdout before the checks table.
    pub text: String,
    /// The checks.
    pub checks: Vec<Check>,
}

impl Report {
    /// A report with a caption.
    pub fn new(caption: impl Into<String>) -> Self {
        Report {
            caption: caption.into(),
            ..Report::default()
        }
    }

    /// Writes an SVG picture and shows it with `caption`.
    ///
    /// A `.svg` picture is also rasterized to the PNG beside it (`NAME.png`, twice the SVG's
    /// size, embedded font): the page shows the PNG and links the SVG under "files".
    pub fn picture(&mut self, ctx: &Context, file: &str, svg: &str, caption: &str) -> Result<()> {
        ctx.write(file, svg)?;
        let shown = match file.strip_suffix(".svg") {
            Some(stem) => {
                let png = format!("{stem}.png");
                ctx.write_bytes(&png, &geomkit_plot::svg_to_png(svg, 2.0, None)?)?;
                self.files.push((file.into(), "the picture as SVG".into()));
                png
            }
            None => file.into(),
        };
        self.pictures.push(Picture {
            file: shown,
            caption: caption.into(),
        });
        Ok(())
    }

    /// Writes a model file (readable by `geomkit bezier ...`) and links it.
    pub fn model(
        &mut self,
        ctx: &Context,
        file: &str,
        model: &BezierModel,
        error: Option<&ErrorReport>,
        what: &str,
    ) -> Result<()> {
        ctx.write(file, &to_json(model, error)?)?;
        self.files.push((file.into(), what.into()));
        Ok(())
    }

    /// Writes any other file (a B-spline model, input data) and links it.
    pub fn file(&mut self, ctx: &Context, file: &str, contents: &[u8], what: &str) -> Result<()> {
        ctx.write_bytes(file, contents)?;
        self.files.push((file.into(), what.into()));
        Ok(())
    }

    /// Adds a check.
    pub fn check(&mut self, check: Check) {
        self.checks.push(check);
    }
}

struct Outcome {
    id: &'static str,
    title: &'static str,
    report: Report,
    time: Duration,
}

/// Runs the demo into `args.out`.
pub fn run(args: &DemoArgs) -> Result<()> {
    let started = Instant::now();
    let dir = args.out.clone();
    ensure_dir(&dir)?;
    let ctx = Context { dir: dir.clone() };
    let items: Vec<Item> = MODULES.iter().flat_map(|m| m()).collect();

    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new(items.len() as u64);
        if let Ok(style) = ProgressStyle::with_template("{bar:32.cyan/blue} {pos}/{len} {msg}") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let mut outcomes = Vec::with_capacity(items.len());
    for item in &items {
        bar.set_message(item.title);
        let t0 = Instant::now();
        let report = match (item.run)(&ctx) {
            Ok(r) => r,
            Err(e) => {
                let mut r = Report::new("The item failed to run.");
                r.check(Check {
                    name: "item runs without error".into(),
                    measured: format!("{e:#}"),
                    limit: "no error".into(),
                    passed: false,
                });
                r
            }
        };
        outcomes.push(Outcome {
            id: item.id,
            title: item.title,
            report,
            time: t0.elapsed(),
        });
        bar.inc(1);
    }
    bar.finish_and_clear();

    let elapsed = started.elapsed();
    let total: usize = outcomes.iter().map(|o| o.report.checks.len()).sum();
    let failed: usize = outcomes
        .iter()
        .flat_map(|o| &o.report.checks)
        .filter(|c| !c.passed)
        .count();
    write_atomic(&dir.join("favicon.svg"), FAVICON.as_bytes())?;
    write_atomic(
        &dir.join("index.html"),
        index_html(&outcomes, total, failed, elapsed).as_bytes(),
    )?;
    write_stdout(text_summary(&outcomes, total, failed, elapsed, &dir).as_bytes())?;
    if failed > 0 {
        bail!("{failed} of {total} demo checks failed (see the table above)");
    }
    Ok(())
}

fn text_summary(
    outcomes: &[Outcome],
    total: usize,
    failed: usize,
    elapsed: Duration,
    dir: &Path,
) -> String {
    let mut s = String::new();
    for o in outcomes {
        if !o.report.text.is_empty() {
            let _ = writeln!(s, "{} — {}\n{}", o.id, o.title, o.report.text);
        }
    }
    let rows: Vec<[String; 5]> = outcomes
        .iter()
        .flat_map(|o| {
            o.report.checks.iter().map(move |c| {
                [
                    o.id.to_string(),
                    c.name.clone(),
                    c.measured.clone(),
                    c.limit.clone(),
                    if c.passed { "pass" } else { "FAIL" }.to_string(),
                ]
            })
        })
        .collect();
    let header = ["item", "check", "measured", "limit", "result"].map(String::from);
    let mut widths = [0usize; 5];
    for row in std::iter::once(&header).chain(&rows) {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |row: &[String; 5]| {
        let cells: Vec<String> = row
            .iter()
            .zip(widths)
            .map(|(c, w)| format!("{c}{}", " ".repeat(w - c.chars().count())))
            .collect();
        cells.join("  ").trim_end().to_string()
    };
    let _ = writeln!(s, "{}", line(&header));
    let _ = writeln!(s, "{}", "-".repeat(widths.iter().sum::<usize>() + 8));
    for row in &rows {
        let _ = writeln!(s, "{}", line(row));
    }
    let _ = writeln!(
        s,
        "\n{} items, {total} checks: {} in {:.2} s; open {}",
        outcomes.len(),
        if failed == 0 {
            "all passed".to_string()
        } else {
            format!("{failed} FAILED")
        },
        elapsed.as_secs_f64(),
        dir.join("index.html").display()
    );
    s
}

/// The page's icon (a cubic Bézier arc over its control polygon), written beside index.html.
const FAVICON: &str = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 32 32\">\
<rect width=\"32\" height=\"32\" rx=\"6\" fill=\"#1f4e9c\"/>\
<path d=\"M5 26 L9 6 L23 6 L27 26\" fill=\"none\" stroke=\"#f0a060\" stroke-width=\"1.6\"/>\
<path d=\"M5 26 C9 6 23 6 27 26\" fill=\"none\" stroke=\"#fff\" stroke-width=\"3\"/></svg>\n";

const CSS: &str = "*{box-sizing:border-box}\
body{font-family:system-ui,-apple-system,'Segoe UI',Helvetica,Arial,sans-serif;margin:0;\
color:#1f2328;background:#f4f5f7;line-height:1.45}\
.wrap{max-width:1380px;margin:0 auto;padding:0 1.2em}\
header.top{background:#fff;border-bottom:1px solid #e1e4e8;padding:1.4em 0 1.1em}\
h1{margin:0 0 .25em;font-size:1.9em}.lead{margin:.2em 0 .7em;color:#444;max-width:70em}\
.stats{display:flex;flex-wrap:wrap;gap:.5em}\
.stat{background:#eef1f4;border-radius:999px;padding:.2em .8em;font-size:.92em}\
.stat.ok{background:#dff3e4;color:#14632d;font-weight:600}\
.stat.bad{background:#fde2e0;color:#a1160d;font-weight:600}\
.note{font-size:.88em;color:#666;margin:.7em 0 0}\
.overview{display:grid;grid-template-columns:repeat(auto-fill,minmax(205px,1fr));gap:.8em;\
margin:1.2em 0 .6em}\
.card{display:flex;flex-direction:column;background:#fff;border:1px solid #e1e4e8;\
border-radius:8px;overflow:hidden;color:inherit;text-decoration:none}\
.card:hover{border-color:#0969da;box-shadow:0 2px 8px rgba(0,0,0,.08)}\
.card img,.card .noimg{width:100%;height:132px;object-fit:contain;background:#fff;\
border-bottom:1px solid #eee;padding:4px}\
.card .noimg{display:flex;align-items:center;justify-content:center;color:#999;font-size:.85em}\
.card .t{padding:.4em .6em 0;font-size:.84em;font-weight:600;line-height:1.3;flex:1}\
.card .b{padding:.3em .6em .5em;font-size:.78em}\
.ok{color:#1d7a3a;font-weight:600}.bad{color:#b3261e;font-weight:600}\
section.item{background:#fff;border:1px solid #e1e4e8;border-radius:10px;margin:1.4em 0;\
padding:.4em 1.4em 1em;scroll-margin-top:1em}\
section.item h2{font-size:1.35em;margin:.6em 0 .3em;display:flex;flex-wrap:wrap;\
align-items:baseline;gap:.3em .8em}\
h2 .id{font-size:.6em;font-weight:normal;color:#888;font-family:ui-monospace,Menlo,Consolas,monospace}\
h2 .badge{font-size:.6em;margin-left:auto}\
.caption{margin:.2em 0 1em;color:#333;max-width:75em}\
.pics{display:grid;grid-template-columns:repeat(auto-fill,minmax(400px,1fr));gap:1em;\
align-items:start}\
figure{margin:0;background:#fff;border:1px solid #e8e8e8;border-radius:6px;padding:.5em}\
figure img{display:block;width:100%;height:auto}\
figcaption{font-size:.86em;color:#555;margin-top:.4em}\
table{border-collapse:collapse;margin:.8em 0;font-size:.9em}\
th,td{border:1px solid #ddd;padding:.25em .6em;text-align:left}th{background:#f5f5f5}\
td.num{font-family:ui-monospace,Menlo,Consolas,monospace;text-align:right}\
pre{background:#f7f7f7;padding:.6em;overflow-x:auto;font-size:.85em;border-radius:4px}\
.files{font-size:.88em;color:#555}\
details.checks{margin-top:.6em}details.checks summary{cursor:pointer;font-size:.92em}\
details.checks table{margin:.5em 0 0}\
footer{color:#777;font-size:.85em;padding:1em 0 2em}\
@media (max-width:600px){.pics{grid-template-columns:1fr}\
.overview{grid-template-columns:repeat(auto-fill,minmax(150px,1fr))}section.item{padding:.3em .8em}}";

/// "5 checks passed" or "1 of 5 checks FAILED", with the CSS class to show it in.
fn checks_badge(checks: &[Check]) -> (&'static str, String) {
    let failed = checks.iter().filter(|c| !c.passed).count();
    let plural = if checks.len() == 1 { "" } else { "s" };
    if failed == 0 {
        ("ok", format!("✓ {} check{plural} passed", checks.len()))
    } else {
        (
            "bad",
            format!("✗ {failed} of {} check{plural} FAILED", checks.len()),
        )
    }
}

fn index_html(outcomes: &[Outcome], total: usize, failed: usize, elapsed: Duration) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <link rel=\"icon\" href=\"favicon.svg\">\n\
         <title>geomkit demo</title>\n<style>{CSS}</style>\n</head>\n<body>\n\
         <header class=\"top\"><div class=\"wrap\">\n<h1>geomkit demo</h1>\n\
         <p class=\"lead\">The figures and worked examples of the papers, recomputed by \
         geomkit; each item says which paper and figure it reproduces, what was checked and \
         the measured error.</p>\n"
    );
    let status = if failed == 0 {
        format!("<span class=\"stat ok\">✓ all {total} checks passed</span>")
    } else {
        format!("<span class=\"stat bad\">✗ {failed} of {total} checks FAILED</span>")
    };
    let _ = writeln!(
        h,
        "<div class=\"stats\">{status}<span class=\"stat\">{} items</span>\
         <span class=\"stat\">{:.2} s</span><span class=\"stat\">geomkit {}</span></div>\n\
         <p class=\"note\">Generated by <code>geomkit demo</code>. Every model file here can be \
         fed back to <code>geomkit eval</code> (and the Bézier ones to \
         <code>geomkit bezier …</code>).</p>\n</div></header>\n<div class=\"wrap\">",
        outcomes.len(),
        elapsed.as_secs_f64(),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(h, "<nav class=\"overview\">");
    for o in outcomes {
        let (class, badge) = checks_badge(&o.report.checks);
        let thumb = match o.report.pictures.first() {
            Some(p) => format!(
                "<img src=\"{}\" alt=\"{}\">",
                escape(&p.file),
                escape(o.title)
            ),
            None => format!("<span class=\"noimg\">{}</span>", escape(o.id)),
        };
        let _ = writeln!(
            h,
            "<a class=\"card\" href=\"#{}\">{thumb}<span class=\"t\">{}</span>\
             <span class=\"b {class}\">{badge}</span></a>",
            o.id,
            escape(o.title)
        );
    }
    let _ = writeln!(h, "</nav>\n<main>");
    for o in outcomes {
        let r = &o.report;
        let (class, badge) = checks_badge(&r.checks);
        let _ = writeln!(
            h,
            "<section class=\"item\" id=\"{id}\">\n<h2>{}<span class=\"id\">{id}</span>\
             <span class=\"badge {class}\">{badge}</span></h2>\n<p class=\"caption\">{}</p>",
            escape(o.title),
            escape(&r.caption),
            id = o.id,
        );
        if !r.pictures.is_empty() {
            let _ = writeln!(h, "<div class=\"pics\">");
            for p in &r.pictures {
                let _ = writeln!(
                    h,
                    "<figure><a href=\"{f}\"><img src=\"{f}\" alt=\"{c}\"></a>\
                     <figcaption>{c}</figcaption></figure>",
                    f = escape(&p.file),
                    c = escape(&p.caption)
                );
            }
            let _ = writeln!(h, "</div>");
        }
        h.push_str(&r.html);
        if !r.files.is_empty() {
            let links: Vec<String> = r
                .files
                .iter()
                .map(|(f, what)| {
                    format!(
                        "<a href=\"{}\">{}</a> ({})",
                        escape(f),
                        escape(f),
                        escape(what)
                    )
                })
                .collect();
            let _ = writeln!(
                h,
                "<p class=\"files\">Model files: {}</p>",
                links.join(", ")
            );
        }
        let _ = writeln!(
            h,
            "<details class=\"checks\"{}><summary><span class=\"{class}\">{badge}</span> \
             <span class=\"files\">({:.0} ms)</span></summary>\n\
             <table class=\"checks\"><tr><th>check</th><th>measured</th><th>limit</th>\
             <th>result</th></tr>",
            if class == "ok" { "" } else { " open" },
            o.time.as_secs_f64() * 1e3
        );
        for c in &r.checks {
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
                 <td class=\"{}\">{}</td></tr>",
                escape(&c.name),
                escape(&c.measured),
                escape(&c.limit),
                if c.passed { "ok" } else { "bad" },
                if c.passed { "pass" } else { "FAIL" }
            );
        }
        let _ = writeln!(h, "</table>\n</details>\n</section>");
    }
    let _ = writeln!(
        h,
        "</main>\n<footer>geomkit {} · {} items · {total} checks</footer>\n</div>",
        env!("CARGO_PKG_VERSION"),
        outcomes.len()
    );
    h.push_str("</body>\n</html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_compare_and_format() {
        assert!(Check::at_most("a", 1e-16, 2e-16).passed);
        assert!(!Check::at_most("a", f64::NAN, 2e-16).passed);
        assert!(Check::at_least("a", 0.5, 0.1).passed);
        let c = Check::equal("degrees", "(5, 3, 2)", "(5, 3, 2)");
        assert!(c.passed);
        assert_eq!(c.limit, "= (5, 3, 2)");
        assert_eq!(sci(0.0), "0");
        assert_eq!(sci(1.5e-16), "1.50e-16");
    }
}
