// End-to-end test of the editor (`geomkit serve`, issue 25) in headless Chromium (called by
// tests/e2e/run.sh).
//
//   node tests/e2e/editor.mjs --geomkit target/release/geomkit --out SHOT_DIR [--chromium PATH]
//
// Starts `geomkit serve --port 0 --dir TMP` (this process ends it), opens the page, and with
// the real mouse: drags control points, clicks the degree controls, adds and removes
// vertices, undoes and redoes, adds and drags reference points of a B-spline. After each
// step it reads the DRAWN shape (the d attribute of the curve's SVG path) and checks it
// against the API's evaluation of the same model mapped by the page's view, and the models
// against references computed here (de Casteljau, de Boor). Then it measures the redraw rate
// while dragging a reference point of a 2000-point B-spline (performance.now in the page;
// reported, not asserted) and saves screenshots (editor-*.png). Exits 1 on any failure.

import { mkdtemp, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { editorArgs, redrawRate, startServe } from './serve.mjs';

const args = await editorArgs('editor.mjs');
const shots = args.out;

const deadline = setTimeout(() => {
  console.error('editor: FAILED: editor.mjs did not finish within 240 s');
  process.exit(1);
}, 240_000);
deadline.unref();

let failures = 0;
function check(ok, what) {
  if (ok) console.log(`editor: ok   ${what}`);
  else {
    console.error(`editor: FAIL ${what}`);
    failures++;
  }
}

// --- references written here ---------------------------------------------------------------
function deCasteljau(pts, t) {
  const w = pts.map((p) => p.slice());
  for (let r = 1; r < pts.length; r++) {
    for (let i = 0; i < pts.length - r; i++) {
      for (let c = 0; c < w[i].length; c++) w[i][c] = (1 - t) * w[i][c] + t * w[i + 1][c];
    }
  }
  return w[0];
}

function deBoor(p, knots, ctrl, t) {
  const n = ctrl.length;
  let k = p;
  while (k + 1 < n && knots[k + 1] <= t) k++;
  const d = [];
  for (let j = 0; j <= p; j++) d.push(ctrl[j + k - p].slice());
  for (let r = 1; r <= p; r++) {
    for (let j = p; j >= r; j--) {
      const i = j + k - p;
      const den = knots[i + p + 1 - r] - knots[i];
      const a = den === 0 ? 0 : (t - knots[i]) / den;
      for (let c = 0; c < d[j].length; c++) d[j][c] = (1 - a) * d[j - 1][c] + a * d[j][c];
    }
  }
  return d[p];
}

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

// --- the server ----------------------------------------------------------------------------
const dir = await mkdtemp(path.join(os.tmpdir(), 'geomkit-editor-'));
const { url, server } = await startServe(args.geomkit, ['--dir', dir]);
console.log(`editor: server at ${url}`);

async function api(p, body) {
  const r = await fetch(new URL(p, url), {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  const j = await r.json();
  if (!r.ok) throw new Error(`${p}: ${r.status} ${j.error}`);
  return j;
}

// --- the page -------------------------------------------------------------------------------
const browser = await chromium.launch({ executablePath: args.chromium, args: ['--no-sandbox'] });
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const consoleErrors = [];
page.on('console', (m) => {
  // A refused exact reduction is a 422 answer the page shows; the browser logs it.
  if (m.type() === 'error' && !/status of 422/.test(m.text())) consoleErrors.push(m.text());
});
page.on('pageerror', (e) => consoleErrors.push(e.message));

const idle = () => page.evaluate(() => window.geomkit.idle());
const doc = () => page.evaluate(() => window.geomkit.doc());

/** The drawn path `id` as screen points. */
async function drawnPath(id) {
  const d = await page.getAttribute(`#${id}`, 'd');
  return (d || '').split(/[MLZ]/).filter((s) => s.trim()).map((s) => s.trim().split(/\s+/).map(Number));
}

/** World points to screen by the page's view. */
const toScreen = (pts) => page.evaluate((p) => p.map((q) => window.geomkit.toScreen(q)), pts);

/** Largest distance (px) between two polylines of the same length. */
function maxGap(a, b) {
  if (a.length !== b.length) return Infinity;
  return a.reduce((m, p, i) => Math.max(m, dist(p, b[i])), 0);
}

/** Screen position of vertex / reference point i, in page coordinates. */
async function pointOnPage(world) {
  const box = await page.locator('#canvas').boundingBox();
  const [x, y] = await page.evaluate((p) => window.geomkit.toScreen(p), world);
  return [box.x + x, box.y + y];
}

async function drag(from, to, steps = 12) {
  await page.mouse.move(from[0], from[1]);
  await page.mouse.down();
  await page.mouse.move(to[0], to[1], { steps });
  await page.mouse.up();
  await idle();
}

/** The drawn Bézier curve against the API's samples and de Casteljau of the document. */
async function checkBezierDrawn(what) {
  const d = await doc();
  const samples = await api('/api/samples', { model: { type: 'bezier_curve', points: d.bezier.points }, samples: 400 });
  const drawn = await drawnPath('curve-path');
  const expected = await toScreen(samples.points);
  check(maxGap(drawn, expected) < 0.01, `${what}: drawn curve = API samples (max ${maxGap(drawn, expected).toFixed(4)} px over ${drawn.length} points)`);
  const ref = samples.t.map((t) => deCasteljau(d.bezier.points, t));
  const worst = samples.points.reduce((m, p, i) => Math.max(m, dist(p, ref[i])), 0);
  check(worst < 1e-9, `${what}: API samples = de Casteljau (max ${worst.toExponential(1)})`);
  return { d, samples, drawn };
}

try {
  await page.goto(url);
  await page.waitForSelector('#curve-path');
  await idle();

  // 1. The paper's Example 2: degree 5, real degree 3.
  const start = await checkBezierDrawn('start');
  check((await page.textContent('#degree')) === '5' && (await page.textContent('#real-degree')) === '3'
    && (await page.textContent('#defect')) === '2', 'Example 2 shows degree 5, real degree 3, defect 2');
  await page.screenshot({ path: path.join(shots, 'editor-bezier.png') });

  // 2. Degree down twice: exact, the drawn shape unchanged.
  for (const n of [4, 3]) {
    await page.click('#deg-down');
    await idle();
    const now = await checkBezierDrawn(`reduced to ${n}`);
    check((await page.textContent('#degree')) === String(n), `degree shows ${n}`);
    check(now.d.bezier.points.length === n + 1, `polygon has ${n + 1} vertices`);
    const moved = maxGap(now.samples.points, start.samples.points);
    check(moved < 1e-12 * 30, `reduced to ${n}: the same curve (max ${moved.toExponential(1)} in world units)`);
  }
  const cubic = (await doc()).bezier.points;
  const paper = [[10, 0], [30, 10], [0, 20], [20, 0]];
  check(cubic.every((p, i) => dist(p, paper[i]) < 1e-9), `the paper's cubic ${JSON.stringify(cubic)}`);

  // 3. Below the real degree: the refusal with its reason, the approximation and its band.
  await page.click('#deg-down');
  await page.waitForSelector('#approx:not([hidden])');
  await page.waitForSelector('#band-path');
  const refusal = await page.textContent('#refusal');
  check(/real degree is 3/.test(refusal), `refusal shown: "${refusal}"`);
  const proposal = await page.evaluate(() => window.geomkit.proposal());
  let most = 0;
  for (let i = 0; i <= 2000; i++) {
    const t = i / 2000;
    most = Math.max(most, dist(deCasteljau(cubic, t), deCasteljau(proposal.model.points, t)));
  }
  check(most <= proposal.linf_bound * (1 + 1e-12) && proposal.linf_bound <= most * 1.011 + 1e-9,
    `L∞ bound ${proposal.linf_bound} holds (largest distance here ${most})`);
  const approxDrawn = await drawnPath('approx-path');
  check(maxGap(approxDrawn, await toScreen(proposal.band.reduced)) < 0.01, 'the approximation is drawn where the API puts it');
  await page.screenshot({ path: path.join(shots, 'editor-approx.png') });
  await page.click('#approx-cancel');

  // 4. Undo twice back to the quintic, redo once.
  await page.locator('#canvas').focus();
  await page.keyboard.press('Control+z');
  await page.keyboard.press('Control+z');
  await idle();
  const undone = await doc();
  check(undone.bezier.points.length === 6 && undone.bezier.points.every((p, i) => dist(p, start.d.bezier.points[i]) < 1e-9), 'undo twice: the six points of Example 2');
  await page.keyboard.press('Control+Shift+z');
  await idle();
  check((await doc()).bezier.points.length === 5 && (await page.textContent('#degree')) === '4', 'redo: degree 4 again');
  await page.keyboard.press('Control+z');
  await idle();

  // 5. Degree up: the same drawn curve, one more vertex.
  await page.click('#deg-up');
  await idle();
  const up = await checkBezierDrawn('elevated to 6');
  const upMoved = maxGap(up.samples.points, start.samples.points);
  check(up.d.bezier.points.length === 7 && upMoved < 1e-12 * 30, `elevated: 7 vertices, the same curve (max ${upMoved.toExponential(1)})`);
  await page.keyboard.press('Control+z');
  await idle();

  // 6. Drag vertex P2 with the mouse: it lands under the mouse, the curve follows.
  const p2 = start.d.bezier.points[2];
  const from = await pointOnPage(p2);
  const to = [from[0] + 90, from[1] + 70];
  await drag(from, to);
  const moved = await checkBezierDrawn('after dragging P2');
  const box = await page.locator('#canvas').boundingBox();
  const under = await page.evaluate(([x, y]) => window.geomkit.toWorld(x, y), [to[0] - box.x, to[1] - box.y]);
  // Within a pixel (the browser reports the mouse at whole or half pixels).
  const p2Now = await pointOnPage(moved.d.bezier.points[2]);
  check(dist(p2Now, to) <= 1, `P2 is under the mouse (${moved.d.bezier.points[2].map((x) => x.toFixed(3))}; the mouse at ${under.map((x) => x.toFixed(3))})`);
  check(maxGap(moved.samples.points, start.samples.points) > 0.5, 'the curve changed shape');
  check((await page.textContent('#real-degree')) === '5', 'moving P2 breaks the defect: real degree 5');

  // 7. Click empty canvas: a vertex is inserted (degree 6); right-click it: removed.
  await page.mouse.click(box.x + 60, box.y + box.height - 60);
  await idle();
  const added = await checkBezierDrawn('after inserting a vertex');
  check(added.d.bezier.points.length === 7, 'click inserts a vertex');
  const newIndex = added.d.bezier.points.findIndex((p) => !moved.d.bezier.points.some((q) => dist(p, q) < 1e-12));
  const at = await pointOnPage(added.d.bezier.points[newIndex]);
  await page.mouse.click(at[0], at[1], { button: 'right' });
  await idle();
  const removed = await checkBezierDrawn('after removing it');
  check(removed.d.bezier.points.length === 6 && maxGap(removed.samples.points, moved.samples.points) < 1e-12 * 30, 'right-click removes it: the curve is back');

  // 8. B-spline through points: add three by clicks, drag one, closed curve.
  await page.click('button[data-mode=bspline]');
  await idle();
  let b = await doc();
  const n0 = b.bspline.points.length;
  for (const [fx, fy] of [[0.2, 0.85], [0.5, 0.9], [0.8, 0.85]]) {
    await page.mouse.click(box.x + fx * box.width, box.y + fy * box.height);
    await idle();
  }
  b = await doc();
  check(b.bspline.points.length === n0 + 3, `three clicks add three reference points (${b.bspline.points.length})`);
  async function checkSpline(what) {
    const d = await doc();
    const drawn = await page.evaluate(() => window.geomkit.drawn());
    const m = drawn.model;
    const through = d.bspline.points.reduce((w, p, i) => Math.max(w, dist(p, deBoor(m.degree, m.knots, m.control_points, drawn.parameters[i]))), 0);
    check(through < 1e-9, `${what}: the curve passes through its ${d.bspline.points.length} points (de Boor, max ${through.toExponential(1)})`);
    const path = await drawnPath('curve-path');
    const exp = await toScreen(drawn.t.map((t) => deBoor(m.degree, m.knots, m.control_points, t)));
    check(maxGap(path, exp) < 0.01, `${what}: drawn curve = de Boor of the API's model (max ${maxGap(path, exp).toFixed(4)} px)`);
    return { d, drawn, path };
  }
  await checkSpline('after adding');
  const q = b.bspline.points[1];
  const qFrom = await pointOnPage(q);
  await drag(qFrom, [qFrom[0] - 40, qFrom[1] + 60]);
  const afterDrag = await checkSpline('after dragging a point');
  check(dist(afterDrag.d.bspline.points[1], q) > 0.1, 'the dragged point moved');
  await page.selectOption('#end', 'natural');
  await idle();
  await checkSpline('natural ends');
  await page.check('#closed');
  await idle();
  const closed = await checkSpline('closed');
  check(dist(closed.path[0], closed.path[closed.path.length - 1]) < 0.01, 'the closed curve closes');
  await page.screenshot({ path: path.join(shots, 'editor-bspline.png') });

  // 9. Open / save through --dir.
  await writeFile(path.join(dir, 'example2.json'), JSON.stringify({ type: 'bezier_curve', points: start.d.bezier.points }));
  await page.click('#open');
  await page.click('#file-list button:has-text("example2.json")');
  await idle();
  check((await doc()).mode === 'bezier' && (await page.textContent('#degree')) === '5', 'opened example2.json from the folder');

  // 10. Redraw rate while dragging a point of a 2000-point B-spline.
  const big = [];
  for (let i = 0; i < 2000; i++) big.push([i / 100, Math.sin(i / 37) + 0.3 * Math.sin(i / 7)]);
  await page.evaluate((pts) => {
    const d = window.geomkit.doc();
    d.mode = 'bspline';
    d.bspline.points = pts;
    d.bspline.closed = false;
    window.geomkit.setDoc(d);
  }, big);
  await idle();
  await page.waitForTimeout(300);
  await idle();
  // A frame counts when the curve computed by the server is drawn (serve.mjs: redrawRate).
  const [gx, gy] = await page.evaluate((p) => window.geomkit.toScreen(p), big[1000]);
  const rate = await redrawRate(page, { element: 'canvas', hooks: 'geomkit', x: gx, y: gy, dx: 0.5, amplitude: 40, relative: true });
  const fps = rate.frames / rate.seconds;
  console.log(`editor: redraw rate while dragging a point of a 2000-point B-spline: ${fps.toFixed(1)} frames/s (${rate.frames} curves drawn for ${rate.moves} pointer moves in ${rate.seconds.toFixed(2)} s; each a round trip to the server: the interpolation and the window of samples and comb near the point)`);
  await checkSpline('2000 points after the drag');
  await writeFile(path.join(shots, 'editor-fps.txt'), `${fps.toFixed(1)}\n`);

  // 11. The README's picture: a quintic of real degree 5 and its best quartic with the
  // error band (docs/images/editor.png is a copy).
  await page.evaluate(() => {
    const d = window.geomkit.doc();
    d.mode = 'bezier';
    d.bezier.points = [[0, 0], [2, 5], [4, -1], [6, 6], [8, 0], [10, 3]];
    window.geomkit.setDoc(d);
  });
  await idle();
  await page.click('#deg-down');
  await page.waitForSelector('#band-path');
  await idle();
  await page.screenshot({ path: path.join(shots, 'editor-readme.png') });

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(`editor: FAIL ${e.stack || e}`);
  failures++;
  await page.screenshot({ path: path.join(shots, 'editor-failure.png') }).catch(() => {});
} finally {
  await browser.close();
  server.kill();
}

if (failures) {
  console.error(`editor: FAILED (${failures} checks)`);
  process.exit(1);
}
console.log(`editor: all checks passed; screenshots in ${shots}`);
