// Independent checks of geomkit's printed formulas (tests/printers/run.sh runs this).
//
//   node tests/printers/check.mjs CASES.json
//
// CASES.json comes from `cargo run -p geomkit --example printer_cases -- CASES.json`: for
// every formula of a representative set, its JavaScript, LaTeX and Desmos text and the values
// of `Graph::eval` at 200 points. Checks:
// 1. JavaScript, three ways (the inline expression, the pasted definitions
//    `const x = (u, v) => ...;`, the program with temporaries), run by node: every value
//    within 1e-13 relative (to max(1, |value|)) of `Graph::eval`; NaN where eval gives NaN.
// 2. LaTeX and Desmos (its LaTeX dialect), every expression and every definition line,
//    rendered by KaTeX with throwOnError: a syntax error (unbalanced braces, an unknown
//    command, a misplaced `&`) throws.
// Exits 1 with the first failures listed.
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";

const require = createRequire(import.meta.url);
const katex = require("katex");

const path = process.argv[2];
if (!path) {
  console.error("usage: node check.mjs CASES.json");
  process.exit(2);
}
const { cases } = JSON.parse(readFileSync(path, "utf8"));

const failures = [];
const fail = (msg) => failures.push(msg);
let values = 0;
let rendered = 0;

// "NaN", "inf", "-inf" are how the generator writes non-finite values.
const expected = (v) =>
  typeof v === "number" ? v : v === "NaN" ? NaN : v.startsWith("-") ? -Infinity : Infinity;

function compare(what, got, want) {
  values += 1;
  if (Number.isNaN(want)) {
    if (!Number.isNaN(got)) fail(`${what}: ${got}, eval gives NaN`);
    return;
  }
  if (!Number.isFinite(want)) {
    if (got !== want) fail(`${what}: ${got}, eval gives ${want}`);
    return;
  }
  const tol = 1e-13 * Math.max(1, Math.abs(want));
  if (!(Math.abs(got - want) <= tol)) fail(`${what}: ${got}, eval gives ${want}`);
}

function render(what, tex) {
  rendered += 1;
  try {
    const html = katex.renderToString(tex, { throwOnError: true, strict: "error" });
    if (html.includes("katex-error")) fail(`${what}: KaTeX reports an error`);
  } catch (e) {
    fail(`${what}: KaTeX: ${e.message}\n    ${tex.slice(0, 300)}`);
  }
}

for (const c of cases) {
  const vars = c.vars;
  const names = c.names;
  // A syntax error in the printed JavaScript is a failure of its own, not a crash.
  const compile = (what, body) => {
    try {
      return new Function(...vars, body);
    } catch (e) {
      fail(`${what}: node: ${e.message}\n    ${body.slice(0, 300)}`);
      return null;
    }
  };
  const inline = c.outputs.map((o) => compile(`JS inline ${c.name}.${o.name}`, `return (${o.js});`));
  const definitions = compile(
    `JS definitions ${c.name}`,
    `${c.js_definitions}\nreturn [${names.join(", ")}].map((f) => f(${vars.join(", ")}));`,
  );
  const program = compile(`JS program ${c.name}`, `${c.js_program}\nreturn [${names.join(", ")}];`);
  c.points.forEach((p, i) => {
    const defs = definitions?.(...p);
    const prog = program?.(...p);
    c.outputs.forEach((o, k) => {
      const want = expected(o.values[i]);
      const at = `${c.name}.${o.name} at (${p.join(", ")})`;
      if (inline[k]) compare(`JS inline ${at}`, inline[k](...p), want);
      if (defs) compare(`JS definition ${at}`, defs[k], want);
      if (prog) compare(`JS program ${at}`, prog[k], want);
    });
  });
  for (const o of c.outputs) {
    render(`LaTeX ${c.name}.${o.name}`, o.latex);
    render(`Desmos ${c.name}.${o.name}`, o.desmos);
  }
  for (const [format, text] of [
    ["LaTeX", c.latex_definitions],
    ["Desmos", c.desmos_definitions],
  ]) {
    text
      .split("\n")
      .filter((line) => line.trim() !== "")
      .forEach((line, k) => render(`${format} definition ${c.name} line ${k + 1}`, line));
  }
}

const summary = `${cases.length} formulas: ${values} JavaScript values against Graph::eval, ${rendered} LaTeX/Desmos texts through KaTeX ${katex.version}`;
if (failures.length > 0) {
  console.error(`printers: ${failures.length} failures (${summary})`);
  for (const f of failures.slice(0, 15)) console.error(`  ${f}`);
  process.exit(1);
}
console.log(`printers: ok, ${summary}`);
