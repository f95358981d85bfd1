// End-to-end test of the editor's point-calculus tables and rational Bézier weights
// (`geomkit serve`, issue 25) in headless Chromium (called by tests/e2e/run.sh).
//
//   node tests/e2e/editor-tables.mjs --geomkit target/release/geomkit --out SHOT_DIR [--chromium PATH]
//
// Starts `geomkit serve --port 0 --dir TMP` (this process ends it) and, with the real
// keyboard and mouse: types an experiment table (levels and responses), pastes CSV, adds a
// factor and moves a slice slider, hovers the plot, undoes, saves and opens the model file;
// then drags a vertex weight of a Bézier curve with Shift, turns the wheel on it, elevates
// the rational curve. After each step it checks what is DRAWN (the SVG paths, the share bars)
// against the API's answers mapped by the page, and the API's numbers against references
// computed here: the Lagrange cardinal functions of spec/point-calculus.md equation (1), the
// interpolating polynomials exactly, and the rational Bézier curve as the quotient
// Σ w_i b_i P_i / Σ w_i b_i. Screenshots: editor-tables-*.png. Exits 1 on any failure.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { editorArgs, postJson, startServe } from './serve.mjs';

const args = await editorArgs('editor-tables.mjs');
const shots = args.out;

setTimeout(() => { console.error('editor-tables: FAILED: did not finish within 240 s'); process.exit(1); }, 240_000).unref();

let failures = 0;
/** Prints one check; a failed one fails the run. */
const check = (ok, what) => {
  console[ok ? 'log' : 'error'](`editor-tables: ${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures++;
};

// --- references written here ---------------------------------------------------------------
/** The Lagrange cardinal functions of `nodes` at t (spec §2: the function-parameters). */
function cardinal(nodes, t) {
  return nodes.map((xj, j) => nodes.reduce((p, xm, m) => (m === j ? p : (p * (t - xm)) / (xj - xm)), 1));
}

function binomial(n, k) {
  let r = 1;
  for (let i = 0; i < k; i++) r = (r * (n - i)) / (i + 1);
  return r;
}

/** The rational Bézier curve at t: Σ w_i B_i(t) P_i / Σ w_i B_i(t) (Bernstein sums). */
function rationalBezier(points, weights, t) {
  const n = points.length - 1;
  let [x, y, w] = [0, 0, 0];
  for (let i = 0; i <= n; i++) {
    const b = binomial(n, i) * t ** i * (1 - t) ** (n - i) * weights[i];
    x += b * points[i][0];
    y += b * points[i][1];
    w += b;
  }
  return [x / w, y / w];
}

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);
const maxGap = (a, b) => (a.length !== b.length ? Infinity : a.reduce((m, p, i) => Math.max(m, dist(p, b[i])), 0));
/** Path data "M x y L x y ..." as points. */
const pathPoints = (d) => (d || '').split(/[MLZ]/).filter((s) => s.trim()).map((s) => s.trim().split(/\s+/).map(Number));

// --- the server ----------------------------------------------------------------------------
const dir = await mkdtemp(path.join(os.tmpdir(), 'geomkit-tables-'));
const { url, server } = await startServe(args.geomkit, ['--dir', dir]);
console.log(`editor-tables: server at ${url}`);
const api = (p, body) => postJson(url, p, body);

// --- the page -------------------------------------------------------------------------------
const browser = await chromium.launch({ executablePath: args.chromium, args: ['--no-sandbox'] });
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const consoleErrors = [];
page.on('console', (m) => {
  // Refusals (422: a reduction below the real degree) are
  // answers the page shows; the browser logs them.
  if (m.type() === 'error' && !/status of 422/.test(m.text())) consoleErrors.push(m.text());
});
page.on('pageerror', (e) => consoleErrors.push(e.message));
/** The name the page's Save prompt is answered with. */
let saveAs = 'experiment.json';
page.on('dialog', (d) => d.accept(saveAs));

const idle = () => page.evaluate(() => window.geomkit.idle());
const doc = () => page.evaluate(() => window.geomkit.doc());
const pc = (expr, arg) => page.evaluate(expr, arg);

/** Types `text` into `selector` and commits it (Enter). */
async function type(selector, text) {
  await page.fill(selector, String(text));
  await page.press(selector, 'Enter');
  await idle();
}

/** The fitted model, grid and frame of the page, and the drawn path `id` in plot pixels. */
async function drawnState(id) {
  const s = await pc(() => {
    const p = window.geomkit.pointcalc;
    return { model: p.model(), grid: p.grid, optimum: p.optimum, shares: p.shares, hover: p.hover, doc: window.geomkit.doc().pointcalc };
  });
  s.path = id ? pathPoints(await page.getAttribute(`#${id}`, 'd')) : [];
  return s;
}

/** Plot pixels of factor-space points, by the page's frame. */
const toPlot = (pts) => pc((q) => q.map(([x, y]) => window.geomkit.pointcalc.toScreen(x, y)), pts);

try {
  await page.goto(url);
  await page.waitForSelector('#curve-path');
  await idle();

  // 1. Point calculus: key 4, the default 3 × 3 table, a certified optimum drawn.
  await page.locator('#canvas').focus();
  await page.keyboard.press('4');
  await page.waitForSelector('#pc-map');
  await idle();
  let s = await drawnState();
  check(s.model && s.model.type === 'pointcalc-model' && s.model.values.length === 9, 'key 4 opens the point-calculus table: 9 experiments fitted');
  check(s.optimum.certified === true, `the optimum is certified (${s.optimum.value} at ${s.optimum.at})`);

  // 2. One factor, typed: remove "time", then levels 0, 0.5, 1 and responses 1, 3, 2.
  await page.click('#pc-factors .pc-factor:nth-child(2) button');
  await idle();
  check((await doc()).pointcalc.factors.length === 1, 'removing a factor leaves one');
  await type('#pc-factors .pc-levels', '0, 0.5, 1');
  for (const [c, v] of [[0, 1], [1, 3], [2, 2]]) await type(`#pc-table input[data-cell="${c}"]`, v);
  s = await drawnState('pc-curve');
  check(JSON.stringify(s.model.values) === '[1,3,2]' && JSON.stringify(s.model.factors[0].nodes) === '[0,0.5,1]', `the typed table is the model (${JSON.stringify(s.model.values)} at ${JSON.stringify(s.model.factors[0].nodes)})`);
  // The API's curve against the interpolating polynomial 1 + 7t − 6t² (exact for 3 nodes).
  const poly = (t) => 1 + 7 * t - 6 * t * t;
  const apiWorst = s.grid.axes[0].reduce((m, t, i) => Math.max(m, Math.abs(s.grid.values[i] - poly(t))), 0);
  check(apiWorst < 1e-13, `API curve = 1 + 7t − 6t² (max ${apiWorst.toExponential(1)} over ${s.grid.values.length} samples)`);
  const expected = await toPlot(s.grid.axes[0].map((t, i) => [t, s.grid.values[i]]));
  check(maxGap(s.path, expected) < 0.01, `drawn curve = API samples (max ${maxGap(s.path, expected).toFixed(4)} px)`);
  // The maximum of 1 + 7t − 6t² is 73/24 at t = 7/12.
  check(Math.abs(s.optimum.value - 73 / 24) < 1e-9 && Math.abs(s.optimum.at[0] - 7 / 12) < 1e-6 && s.optimum.certified, `certified maximum ${s.optimum.value} at ${s.optimum.at[0]} (exact 73/24 at 7/12)`);
  const star = pathPoints(await page.getAttribute('#pc-optimum path', 'd'));
  const [ox, oy] = (await toPlot([[7 / 12, 73 / 24]]))[0];
  check(dist([(star[0][0] + star[1][0]) / 2, star[0][1]], [ox, oy]) < 0.5, 'the optimum is marked at (7/12, 73/24)');
  check(/max 3\.04167/.test(await page.textContent('#pc-optimum text')), `its label: "${await page.textContent('#pc-optimum text')}"`);

  // The formula panel: the point equation in JavaScript, run here, is 1 + 7t − 6t².
  await page.selectOption('#syntax', 'js');
  await idle();
  const js = await page.textContent('#formula');
  const y = new Function(`${js}\nreturn ${s.doc.response};`)();
  const jsWorst = [0, 0.1, 0.3, 7 / 12, 0.9, 1].reduce((m, u) => Math.max(m, Math.abs(y(u) - poly(u))), 0);
  check(jsWorst < 1e-13, `the formula panel's JavaScript point equation = 1 + 7t − 6t² (max ${jsWorst.toExponential(1)})`);
  await page.selectOption('#syntax', 'maple');
  await idle();

  // 3. Hover at t ≈ 0.3: the bars are the API's shares and equation (1)'s functions.
  const plot = await page.locator('#pc-plot').boundingBox();
  const [hx, hy] = (await toPlot([[0.3, 2]]))[0];
  await page.mouse.move(plot.x + hx, plot.y + hy);
  await page.waitForFunction(() => window.geomkit.pointcalc.hover !== null);
  await idle();
  s = await drawnState();
  const t = s.hover[0];
  const bars = await page.$$eval('#pc-shares li', (li) => li.map((l) => [+l.dataset.cell, +l.dataset.share]));
  const sum = bars.reduce((a, [, v]) => a + v, 0);
  check(bars.length === 3 && Math.abs(sum - 1) < 1e-12, `the hovered point's ${bars.length} share bars sum to 1 (${sum})`);
  const apiShares = (await api('/api/pointcalc/shares', { model: s.model, at: [t] })).shares.map((x) => x.share);
  const ref = [(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)];
  check(bars.every(([c, v]) => Math.abs(v - apiShares[c]) < 1e-15), 'the bars are the API\'s shares at the hovered point');
  check(bars.every(([c, v]) => Math.abs(v - ref[c]) < 1e-12) && Math.abs(t - 0.3) < 0.01, `shares at t = ${t.toFixed(4)} = t̄(1−2t), 4tt̄, t(2t−1) of equation (1)`);
  const sized = await page.$$eval('.pc-source', (cs) => cs.map((c) => [+c.dataset.cells, +c.dataset.share, +c.getAttribute('r')]));
  check(sized.every(([c, v]) => Math.abs(v - apiShares[c]) < 1e-15) && sized[1][2] > sized[0][2], 'the source points are sized by their shares');
  await page.screenshot({ path: path.join(shots, 'editor-tables-1d.png') });

  // 4. Undo: the last response back to its old value; redo.
  await page.locator('#pc-plot').click({ position: { x: 5, y: 5 } });
  await page.keyboard.press('Control+z');
  await idle();
  check((await doc()).pointcalc.values[2] !== 2, `undo: the last typed response undone (${(await doc()).pointcalc.values[2]})`);
  await page.keyboard.press('Control+Shift+z');
  await idle();
  check((await doc()).pointcalc.values[2] === 2 && (await pc(() => window.geomkit.pointcalc.model().values[2])) === 2, 'redo: 2 again, refitted');

  // M: the minimum instead — 1 at t = 0 (1 + 7t − 6t² is concave); M again: the maximum.
  await page.locator('#pc-plot').click({ position: { x: 5, y: 5 } });
  await page.keyboard.press('m');
  await idle();
  let o = (await drawnState()).optimum;
  check((await page.inputValue('#pc-goal')) === 'min' && o.certified && Math.abs(o.value - 1) < 1e-9 && Math.abs(o.at[0]) < 1e-6, `M: certified minimum ${o.value} at ${o.at[0]} (exact 1 at 0)`);
  await page.keyboard.press('m');
  await idle();
  o = (await drawnState()).optimum;
  check((await page.inputValue('#pc-goal')) === 'max' && Math.abs(o.value - 73 / 24) < 1e-9, 'M again: the maximum');

  // 5. Two factors from pasted CSV (rows in any order): f(a, b) = 1 + 2a + 3b + ab.
  const f = (a, b) => 1 + 2 * a + 3 * b + a * b;
  const rows = [];
  for (const b of [1, 0]) for (const a of [2, 0, 1]) rows.push(`${a},${b},${f(a, b)}`);
  await page.click('#pc-csv-box summary');
  await page.fill('#pc-csv', `a,b,y\n${rows.join('\n')}\n`);
  await page.click('#pc-csv-apply');
  await idle();
  await page.mouse.move(plot.x + plot.width * 0.4, plot.y + plot.height * 0.45);
  await page.waitForFunction(() => window.geomkit.pointcalc.hover && window.geomkit.pointcalc.hover.length === 2);
  await idle();
  s = await drawnState('pc-contours');
  check(JSON.stringify(s.model.factors.map((x) => x.nodes)) === '[[0,1,2],[0,1]]' && JSON.stringify(s.model.values) === JSON.stringify([0, 1, 2].flatMap((a) => [0, 1].map((b) => f(a, b)))), 'the pasted CSV is the grid (levels sorted, values in row-major order)');
  const [xs, ys] = s.grid.axes;
  let gridWorst = 0;
  xs.forEach((x, i) => ys.forEach((y, j) => { gridWorst = Math.max(gridWorst, Math.abs(s.grid.values[i][j] - f(x, y))); }));
  check(gridWorst < 1e-12, `API map = f on the ${xs.length} × ${ys.length} samples (max ${gridWorst.toExponential(1)})`);
  check((await page.$$('#pc-map rect')).length === xs.length * ys.length, 'the map has one cell per sample');
  const segs = s.grid.contours.flatMap((c) => c.segments.map((sg) => [c.level, sg]));
  const onLevel = segs.reduce((m, [h, sg]) => Math.max(m, ...sg.map(([x, y]) => Math.abs(f(x, y) - h))), 0);
  check(segs.length > 0 && onLevel < 1e-10, `API contour points lie on their levels (${segs.length} segments, max |f − h| ${onLevel.toExponential(1)})`);
  const contourScreen = await toPlot(segs.flatMap(([, sg]) => sg));
  check(maxGap(s.path, contourScreen) < 0.01, `drawn contours = API segments (max ${maxGap(s.path, contourScreen).toFixed(4)} px, ${s.path.length} points)`);
  const bars2 = await page.$$eval('#pc-shares li', (li) => li.map((l) => [+l.dataset.cell, +l.dataset.share]));
  const [u, v] = s.hover;
  const la = cardinal([0, 1, 2], u), lb = cardinal([0, 1], v);
  const sum2 = bars2.reduce((a, [, x]) => a + x, 0);
  check(bars2.length === 6 && Math.abs(sum2 - 1) < 1e-12 && bars2.every(([c, x]) => Math.abs(x - la[Math.floor(c / 2)] * lb[c % 2]) < 1e-12), `shares at (${u.toFixed(3)}, ${v.toFixed(3)}) are L_i(a)·L_j(b) and sum to 1 (${sum2})`);
  check(s.optimum.certified && Math.abs(s.optimum.value - 10) < 1e-9, `certified maximum ${s.optimum.value} (f(2, 1) = 10)`);
  await page.screenshot({ path: path.join(shots, 'editor-tables-2d.png') });

  // 6. A third factor: the map is a slice; the slider moves it.
  await page.click('#pc-add-factor');
  await idle();
  check(await page.isVisible('#pc-slice-card') && (await doc()).pointcalc.factors.length === 3, 'a third factor: the slice card with its slider');
  await page.fill('#pc-table input[data-cell="1"]', '20');
  await page.press('#pc-table input[data-cell="1"]', 'Enter');
  await idle();
  const slider = page.locator('#pc-slider-2');
  await slider.focus();
  for (let i = 0; i < 50; i++) await page.keyboard.press('ArrowRight');
  await idle();
  s = await drawnState();
  const x3 = s.grid.at[2];
  check(Math.abs(x3 - 0.75) < 1e-9, `the slider sets x3 = ${x3} for the slice`);
  const sliceRef = await api('/api/pointcalc/grid', { model: s.model, at: [0, 0, x3], free: [0, 1], contours: 12 });
  check(JSON.stringify(sliceRef.values) === JSON.stringify(s.grid.values), 'the drawn slice is the API\'s slice at the slider');
  // The model is linear in x3 (2 levels): the slice is (1 − x3)·(slice at 0) + x3·(slice at 1).
  const [s0, s1] = await Promise.all([0, 1].map((z) => api('/api/pointcalc/grid', { model: s.model, at: [0, 0, z], free: [0, 1], contours: 0 })));
  let lin = 0;
  s.grid.values.forEach((row, i) => row.forEach((z, j) => { lin = Math.max(lin, Math.abs(z - ((1 - x3) * s0.values[i][j] + x3 * s1.values[i][j]))); }));
  check(lin < 1e-12, `the slice is linear in the 2-level factor (max ${lin.toExponential(1)})`);
  await page.screenshot({ path: path.join(shots, 'editor-tables-3d.png') });

  // 7. Save into --dir and open it again.
  await page.click('#save');
  await page.waitForSelector('#status:has-text("Saved experiment.json")');
  const saved = JSON.parse(await readFile(path.join(dir, 'experiment.json'), 'utf8'));
  check(saved.type === 'pointcalc-model' && saved.values.length === 12 && saved.values[1] === 20, `saved experiment.json: a pointcalc-model of ${saved.values.length} values`);
  await page.keyboard.press('1');
  await idle();
  await page.click('#open');
  await page.click('#file-list button:has-text("experiment.json")');
  await idle();
  const reopened = await doc();
  check(reopened.mode === 'pointcalc' && reopened.pointcalc.factors.length === 3 && reopened.pointcalc.values[1] === 20, 'opened experiment.json: the table is back');

  // 8. Rational weights: Shift+drag P2 up, the wheel on P1, the field; the drawn curve is
  // the quotient at the API's parameters.
  await page.keyboard.press('1');
  await idle();
  async function checkRational(what) {
    const d = (await doc()).bezier;
    const samples = await api('/api/samples', { model: { type: 'bezier_curve', points: d.points, weights: d.weights }, samples: 400 });
    const exact = samples.t.map((u) => rationalBezier(d.points, d.weights, u));
    const apiErr = samples.points.reduce((m, p, i) => Math.max(m, dist(p, exact[i])), 0);
    check(apiErr < 1e-12, `${what}: API samples = Σ w b P / Σ w b (max ${apiErr.toExponential(1)})`);
    const drawn = pathPoints(await page.getAttribute('#curve-path', 'd'));
    const want = await page.evaluate((p) => p.map((q) => window.geomkit.toScreen(q)), exact);
    check(maxGap(drawn, want) < 0.01, `${what}: drawn curve = exact quotient (max ${maxGap(drawn, want).toFixed(4)} px)`);
    return d;
  }
  const canvas = await page.locator('#canvas').boundingBox();
  const before = (await doc()).bezier;
  const at2 = await page.evaluate((p) => window.geomkit.toScreen(p), before.points[2]);
  await page.mouse.move(canvas.x + at2[0], canvas.y + at2[1]);
  await page.keyboard.down('Shift');
  await page.mouse.down();
  await page.mouse.move(canvas.x + at2[0], canvas.y + at2[1] - 100, { steps: 10 });
  await page.mouse.up();
  await page.keyboard.up('Shift');
  await idle();
  let d = await checkRational('Shift+drag P2 up 100 px');
  check(Math.abs(d.weights[2] - Math.E) < 0.05 && d.points[2].every((x, i) => x === before.points[2][i]), `P2's weight is e (${d.weights[2].toFixed(4)}) and P2 did not move`);
  check(/P2/.test(await page.textContent('#weight-name')) && Math.abs(+(await page.inputValue('#weight')) - d.weights[2]) < 1e-5, 'the weight field shows P2\'s weight');
  const at1 = await page.evaluate((p) => window.geomkit.toScreen(p), d.points[1]);
  await page.mouse.move(canvas.x + at1[0], canvas.y + at1[1]);
  await page.mouse.wheel(0, -200);
  await idle();
  d = await checkRational('the wheel on P1');
  check(Math.abs(d.weights[1] - Math.exp(0.4)) < 1e-9, `the wheel up 200 on P1: weight e^0.4 (${d.weights[1]})`);
  await type('#weight', '0.25');
  d = await checkRational('weight 0.25 typed for P1');
  check(d.weights[1] === 0.25, 'the field sets the weight');
  const deg = await page.textContent('#degree');
  await page.click('#deg-up');
  await idle();
  const up = (await doc()).bezier;
  let same = 0;
  for (let i = 0; i <= 200; i++) same = Math.max(same, dist(rationalBezier(up.points, up.weights, i / 200), rationalBezier(d.points, d.weights, i / 200)));
  check(up.points.length === d.points.length + 1 && up.weights.length === up.points.length && same < 1e-12, `+ elevates the rational curve to degree ${+deg + 1}: the same curve (max ${same.toExponential(1)})`);
  await checkRational('elevated');
  await page.screenshot({ path: path.join(shots, 'editor-tables-rational.png') });
  // Saved as the CLI's rational bezier_curve file, and a rational quarter circle opened.
  saveAs = 'rational.json';
  await page.locator('#canvas').focus();
  await page.keyboard.press('Control+s');
  await page.waitForSelector('#status:has-text("Saved rational.json")');
  const savedCurve = JSON.parse(await readFile(path.join(dir, 'rational.json'), 'utf8'));
  check(savedCurve.type === 'bezier_curve' && JSON.stringify(savedCurve.weights) === JSON.stringify(up.weights) && savedCurve.points.length === up.points.length, 'Ctrl+S saved rational.json: a bezier_curve with its weights');
  await writeFile(path.join(dir, 'quarter.json'), JSON.stringify({ type: 'bezier_curve', points: [[1, 0], [1, 1], [0, 1]], weights: [1, Math.SQRT1_2, 1] }));
  await page.click('#open');
  await page.click('#file-list button:has-text("quarter.json")');
  await idle();
  const quarter = await checkRational('opened quarter.json');
  const circle = await api('/api/samples', { model: { type: 'bezier_curve', points: quarter.points, weights: quarter.weights }, samples: 50 });
  check(circle.points.every((q) => Math.abs(Math.hypot(q[0], q[1]) - 1) < 1e-14), 'the opened quarter circle is drawn on the unit circle');
  await page.keyboard.press('Control+z');
  await idle();
  check((await doc()).bezier.points.length === up.points.length, 'undo: the elevated curve again');
  await page.click('#deg-down');
  await idle();
  const down = (await doc()).bezier;
  check(down.points.length === d.points.length && down.weights.every((w, i) => Math.abs(w - d.weights[i]) < 1e-9 * Math.max(1, d.weights[i])), '− reduces it back exactly (the weights again)');
  await page.click('#deg-down');
  await idle();
  check(!(await page.isHidden('#refusal')) && /rational/.test(await page.textContent('#refusal')), `below the real degree: "${await page.textContent('#refusal')}"`);

  // 9. The shortcuts overlay.
  await page.locator('#canvas').focus();
  await page.keyboard.press('?');
  await page.waitForSelector('#help-dialog[open]');
  const keys = await page.$$eval('#help-keys tr', (r) => r.length);
  check(keys >= 15, `? shows the shortcuts (${keys} rows)`);
  await page.screenshot({ path: path.join(shots, 'editor-tables-help.png') });
  await page.keyboard.press('Escape');

  // The README's picture (docs/images/editor-tables.png is a copy): the default 2-factor
  // table, hovered, tall enough for the share bars.
  await page.evaluate(() => {
    const d = window.geomkit.doc();
    d.mode = 'pointcalc';
    d.pointcalc = { factors: [{ name: 'temp', levels: [60, 75, 90] }, { name: 'time', levels: [1, 2, 4] }], response: 'yield', values: [52, 61, 58, 60, 74, 69, 55, 66, 57], at: null, free: [0, 1], goal: 'max' };
    window.geomkit.setDoc(d);
  });
  await page.setViewportSize({ width: 1280, height: 1080 });
  await idle();
  const tall = await page.locator('#pc-plot').boundingBox();
  await page.mouse.move(tall.x + tall.width * 0.3, tall.y + tall.height * 0.62);
  await page.waitForTimeout(200);
  await idle();
  await page.screenshot({ path: path.join(shots, 'editor-tables-readme.png') });

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(`editor-tables: FAIL ${e.stack || e}`);
  failures++;
  await page.screenshot({ path: path.join(shots, 'editor-tables-failure.png') }).catch(() => {});
} finally {
  await browser.close();
  server.kill();
}

if (failures) {
  console.error(`editor-tables: FAILED (${failures} checks)`);
  process.exit(1);
}
console.log(`editor-tables: all checks passed; screenshots in ${shots}`);
