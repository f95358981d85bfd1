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
//    command, a misplaced `&`) throws. Every expression is also evaluated from KaTeX's parse
//    tree at the same points (texValue below), within the same 1e-13: a dropped bracket or
//    fraction bar that still parses gives other values.
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
const counts = {};
let rendered = 0;

// "NaN", "inf", "-inf" are how the generator writes non-finite values.
const expected = (v) =>
  typeof v === "number" ? v : v === "NaN" ? NaN : v.startsWith("-") ? -Infinity : Infinity;

function compare(what, got, want) {
  const kind = what.split(" ")[0];
  counts[kind] = (counts[kind] ?? 0) + 1;
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

// A LaTeX formula evaluated from KaTeX's own parse tree (katex.__parse), so that a printer
// that drops a bracket or a fraction bar fails on values, not only on syntax: sums of
// products of factors; juxtaposition and \cdot multiply; braces group nothing (they do not
// show), but a power's base must look like one thing; \frac, \sqrt, \left( \right),
// \left| \right| (absolute value), x^{n}, e^{x}, \pi, the functions the printers use
// (\sin ... \tanh, \ln, \arcsin, \arccos, \arctan, \operatorname{sign} / \operatorname{sgn})
// applied to the group that follows; numbers as runs of digits and a point. Anything else
// throws, naming the node.
const FUNCTIONS = {
  "\\sin": Math.sin, "\\cos": Math.cos, "\\tan": Math.tan, "\\sinh": Math.sinh,
  "\\cosh": Math.cosh, "\\tanh": Math.tanh, "\\ln": Math.log, "\\exp": Math.exp,
  "\\arcsin": Math.asin, "\\arccos": Math.acos, "\\arctan": Math.atan,
  sign: Math.sign, sgn: Math.sign,
};

function texValue(tex, env) {
  return evalList(katex.__parse(tex, { strict: "error" }), env);
}

function evalList(list, env) {
  // Braces do not show: a group standing in a list is read as if its content stood there.
  const flat = (l) => l.flatMap((n) => (n.type === "ordgroup" ? flat(n.body) : [n]));
  const nodes = flat(list);
  let i = 0;
  const peekBin = () =>
    i < nodes.length && nodes[i].type === "atom" && nodes[i].family === "bin" ? nodes[i].text : null;
  const number = () => {
    let text = "";
    while (i < nodes.length && nodes[i].type === "textord" && /^[0-9.]$/.test(nodes[i].text)) {
      text += nodes[i].text;
      i += 1;
    }
    // KaTeX makes the last digit of 10^{-17} the base of the power: 1, then 0^{-17}.
    const n = nodes[i];
    if (n?.type === "supsub" && !n.sub && n.base.type === "textord" && /^[0-9]$/.test(n.base.text)) {
      i += 1;
      return Number(text + n.base.text) ** evalList([n.sup], {});
    }
    return Number(text);
  };
  const primary = () => {
    const n = nodes[i];
    if (n.type === "textord" && /^[0-9.]$/.test(n.text)) return number();
    i += 1;
    switch (n.type) {
      case "leftright": {
        const x = evalList(n.body, env);
        if (n.left === "(" && n.right === ")") return x;
        if (n.left === "|" && n.right === "|") return Math.abs(x);
        throw new Error(`delimiters ${n.left} ${n.right}`);
      }
      case "genfrac":
        if (!n.hasBarLine) throw new Error("a fraction without a bar");
        return evalList([n.numer], env) / evalList([n.denom], env);
      case "sqrt":
        if (n.index) throw new Error("a root with an index");
        return Math.sqrt(evalList([n.body], env));
      case "supsub": {
        if (n.sub) {
          // A subscripted name (Desmos: a_{1}).
          const name = `${n.base.text}_${n.sub.body.map((b) => b.text).join("")}`;
          const base = lookup(name, env);
          return n.sup ? base ** evalList([n.sup], env) : base;
        }
        // The base must look like one thing (x, 2, \left(...\right), \sqrt{..}, \sin\left(..\right)):
        // braces do not show, so {a + b}^{2} reads as a + b².
        const inner = n.base.type === "ordgroup" ? n.base.body : [n.base];
        const single =
          inner.length === 1 ||
          (inner.length === 2 && ["op", "operatorname"].includes(inner[0].type) && inner[1].type === "leftright");
        if (!single || inner[0].type === "atom") throw new Error("a power of something that does not look like one thing");
        const base = n.base.type === "mathord" && n.base.text === "e" ? Math.E : evalList(inner, env);
        const power = evalList([n.sup], env);
        return base === Math.E ? Math.exp(power) : base ** power;
      }
      case "mathord":
        if (n.text === "\\pi") return Math.PI;
        if (n.text === "e") return Math.E;
        return lookup(n.text, env);
      case "op":
      case "operatorname": {
        const name = n.type === "op" ? n.name : n.body.map((b) => b.text).join("");
        const f = FUNCTIONS[name];
        if (!f) throw new Error(`unknown function ${name}`);
        return f(factor());
      }
      default:
        throw new Error(`unexpected ${n.type} ${n.text ?? ""}`);
    }
  };
  const factor = () => primary();
  const term = () => {
    let x = factor();
    while (i < nodes.length) {
      const bin = peekBin();
      if (bin === "\\cdot") {
        i += 1;
        x *= factor();
      } else if (bin === null) {
        x *= factor();
      } else {
        break;
      }
    }
    return x;
  };
  let sign = 1;
  if (peekBin() === "-") {
    i += 1;
    sign = -1;
  }
  let total = sign * term();
  while (i < nodes.length) {
    const bin = peekBin();
    if (bin !== "+" && bin !== "-") throw new Error(`unexpected ${nodes[i].type} ${nodes[i].text ?? ""}`);
    i += 1;
    total = bin === "+" ? total + term() : total - term();
  }
  return total;
}

function lookup(name, env) {
  if (!(name in env)) throw new Error(`unknown name ${name}`);
  return env[name];
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
    for (const [format, tex] of [
      ["LaTeX", o.latex],
      ["Desmos", o.desmos],
    ]) {
      try {
        c.points.forEach((p, i) => {
          const env = Object.fromEntries(vars.map((v, k) => [v, p[k]]));
          compare(`${format} ${c.name}.${o.name} at (${p.join(", ")})`, texValue(tex, env), expected(o.values[i]));
        });
      } catch (e) {
        fail(`${format} ${c.name}.${o.name}: not evaluated: ${e.message}\n    ${tex.slice(0, 300)}`);
      }
    }
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

const valued = Object.entries(counts)
  .map(([kind, n]) => `${n} ${kind}`)
  .join(", ");
const summary = `${cases.length} formulas: values against Graph::eval (${valued}), ${rendered} LaTeX/Desmos texts rendered by KaTeX ${katex.version}`;
if (failures.length > 0) {
  console.error(`printers: ${failures.length} failures (${summary})`);
  for (const f of failures.slice(0, 15)) console.error(`  ${f}`);
  process.exit(1);
}
console.log(`printers: ok, ${summary}`);
