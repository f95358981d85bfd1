// End-to-end test of the editor's 3-D modes (`geomkit serve`, issue 25) in headless
// Chromium (called by tests/e2e/run.sh).
//
//   node tests/e2e/editor-3d.mjs --geomkit target/release/geomkit --out SHOT_DIR [--chromium PATH]
//
// Starts `geomkit serve --port 0 --dir TMP`, opens the Bézier surface tab and, with the real
// mouse: drags a control point in the view plane (it must land under the mouse: projected
// with the page's matrices) and along z, clicks the degree controls (elevation keeps the
// surface, the exact reduction comes back, a refused one offers the best approximation
// with its error colouring), edits a weight, inserts and removes rows and columns, undoes
// and redoes. After each step the mesh the page uploaded to the GPU is compared with tensor
// de Casteljau evaluations of the page's net written here (rational: in homogeneous
// coordinates), and pixels of the canvas where the surface projects are checked to be
// drawn. Then the heights grid: a height dragged with the mouse, the interpolant checked by
// de Boor's algorithm written here, CSV and .npy files loaded. It measures the redraw rate
// while dragging a vertex of a 20 × 20 Bézier surface (performance.now in the page;
// reported) and saves screenshots editor-3d-*.png. Exits 1 on any failure.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { editorArgs, redrawRate, startServe } from './serve.mjs';

const args = await editorArgs('editor-3d.mjs');
const shots = args.out;

const deadline = setTimeout(() => {
  console.error('editor-3d: FAILED: editor-3d.mjs did not finish within 240 s');
  process.exit(1);
}, 240_000);
deadline.unref();

let failures = 0;
function check(ok, what) {
  if (ok) console.log(`editor-3d: ok   ${what}`);
  else {
    console.error(`editor-3d: FAIL ${what}`);
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

/** p(u, v) of a net (with weights: in homogeneous coordinates, then divided). */
function surfacePoint(net, weights, u, v) {
  const h = net.map((row, i) => row.map((p, j) => {
    const w = weights ? weights[i][j] : 1;
    return [p[0] * w, p[1] * w, p[2] * w, w];
  }));
  const cols = h[0].map((_, j) => deCasteljau(h.map((row) => row[j]), u));
  const q = deCasteljau(cols, v);
  return [q[0] / q[3], q[1] / q[3], q[2] / q[3]];
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

/** A scalar B-spline surface file at (x, y), by de Boor in v then in u. */
function heightAt(model, x, y) {
  const rows = model.net.map((row) => deBoor(model.degree[1], model.knots_v, row, y));
  return deBoor(model.degree[0], model.knots_u, rows, x)[0];
}

const dist3 = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

// --- the server ----------------------------------------------------------------------------
const dir = await mkdtemp(path.join(os.tmpdir(), 'geomkit-editor-3d-'));
const { url, server } = await startServe(args.geomkit, ['--dir', dir]);
console.log(`editor-3d: server at ${url}`);

// A 20 × 20 net (degrees 19, 19) for the redraw rate, opened from the --dir folder.
const big = Array.from({ length: 20 }, (_, i) => Array.from({ length: 20 }, (_, j) => {
  const [x, y] = [i / 19, j / 19];
  return [4 * x, 4 * y, Math.sin(3 * x) * Math.cos(4 * y) + 0.3 * Math.sin(9 * x * y)];
}));
await writeFile(path.join(dir, 'surface-20x20.json'), JSON.stringify({ type: 'bezier_surface', net: big }));

// --- the page -------------------------------------------------------------------------------
const browser = await chromium.launch({
  executablePath: args.chromium,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const consoleErrors = [];
page.on('console', (m) => {
  // A refused exact reduction is a 422 answer the page shows; the browser logs it.
  if (m.type() === 'error' && !/status of 422/.test(m.text())) consoleErrors.push(m.text());
});
page.on('pageerror', (e) => consoleErrors.push(e.message));

const idle = () => page.evaluate(() => window.geomkit3d.idle());
const doc = () => page.evaluate(() => window.geomkit3d.doc());

/** Page coordinates of a world point, by the view's own matrices. */
async function screenOf(p) {
  return page.evaluate((q) => {
    const r = document.getElementById('view3d').getBoundingClientRect();
    const [x, y, z] = window.geomkit3d.project(q);
    return [r.left + x, r.top + y, z];
  }, p);
}

/** The mesh the page drew (the arrays it uploaded to the GPU) against the net's surface
 * by de Casteljau here, at every vertex. */
async function checkMesh(what) {
  const [d, mesh] = await Promise.all([
    doc(),
    page.evaluate(() => {
      const m = window.geomkit3d.drawn().mesh;
      const gpu = window.geomkit3d.view().readPositions();
      return { u: m.u, v: m.v, positions: m.positions, uploaded: gpu ? Array.from(gpu) : null };
    }),
  ]);
  const { net, weights } = d.surface;
  let worst = 0, worstGpu = 0, scale = 0;
  mesh.u.forEach((u, a) => mesh.v.forEach((v, b) => {
    const k = 3 * (a * mesh.v.length + b);
    const want = surfacePoint(net, weights, u, v);
    scale = Math.max(scale, Math.hypot(...want));
    worst = Math.max(worst, dist3(mesh.positions.slice(k, k + 3), want));
    worstGpu = Math.max(worstGpu, dist3(mesh.uploaded.slice(k, k + 3), want));
  }));
  // The API's mesh to rounding; the GPU's vertex buffer (float32, read back) to 2^-23.
  check(worst < 1e-12 * scale && worstGpu < 2e-7 * scale, `${what}: the mesh drawn (${mesh.u.length}×${mesh.v.length}; the vertex buffer read back) is the net's surface by de Casteljau (API off by ${worst.toExponential(1)}, GPU by ${worstGpu.toExponential(1)})`);
  // Where the surface's middle projects, the canvas shows the surface, not the background.
  const mid = surfacePoint(net, weights, 0.5, 0.5);
  const [sx, sy] = await screenOf(mid);
  const px = await page.evaluate(([x, y]) => {
    const c = document.getElementById('view3d');
    const r = c.getBoundingClientRect();
    const gl = c.getContext('webgl2');
    const scale = c.width / r.width; // drawing buffer pixels per CSS pixel
    // Drawn now, read in the same task (the buffer is not preserved once composited).
    window.geomkit3d.view().draw();
    const out = new Uint8Array(4);
    gl.readPixels(Math.round((x - r.left) * scale), Math.round(c.height - (y - r.top) * scale), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, out);
    return Array.from(out);
  }, [sx, sy]);
  const background = [249, 250, 252];
  check(Math.hypot(px[0] - background[0], px[1] - background[1], px[2] - background[2]) > 20, `${what}: the pixel where p(0.5, 0.5) projects is drawn (rgb ${px.slice(0, 3).join(', ')})`);
}

async function drag(from, to, { steps = 12, alt = false } = {}) {
  await page.mouse.move(from[0], from[1]);
  if (alt) await page.keyboard.down('Alt');
  await page.mouse.down();
  await page.mouse.move(to[0], to[1], { steps });
  await page.mouse.up();
  if (alt) await page.keyboard.up('Alt');
  await idle();
}

try {
  await page.goto(url);
  await page.click('button[data-mode="surface"]');
  await page.waitForFunction(() => window.geomkit3d && window.geomkit3d.drawn().mesh);
  await idle();
  check(await page.isVisible('#view3d') && !(await page.isVisible('#canvas')), 'the surface tab shows the 3-D view instead of the 2-D one');
  check((await page.textContent('#su-degree')) === '3' && (await page.textContent('#sv-degree')) === '4', 'it opens on a net of degrees (3, 4)');
  await checkMesh('opening');
  await page.screenshot({ path: path.join(shots, 'editor-3d-surface.png') });

  // 1. Drag vertex (2, 2) in the view plane: it ends under the mouse.
  let d = await doc();
  const p0 = d.surface.net[2][2];
  const s0 = await screenOf(p0);
  const down = [Math.round(s0[0]), Math.round(s0[1])];
  const target = [down[0] + 60, down[1] - 45];
  await drag(down, target);
  d = await doc();
  const p1 = d.surface.net[2][2];
  const s1 = await screenOf(p1);
  check(dist3(p0, p1) > 0.1, `the dragged vertex moved (${p0.map((x) => x.toFixed(2))} → ${p1.map((x) => x.toFixed(2))})`);
  // It moved on the screen exactly as the mouse did (projected with the view's matrices).
  const off = Math.hypot(s1[0] - s0[0] - 60, s1[1] - s0[1] + 45);
  check(off < 0.05, `it follows the mouse: moved (60, -45) px on the screen (off by ${off.toFixed(4)} px)`);
  check(Math.abs(s1[2] - s0[2]) < 1e-6, 'in the view plane: its depth stayed');
  await checkMesh('after a drag');

  // 2. Alt+drag vertex (1, 3) along z: x and y stay.
  const q0 = d.surface.net[1][3];
  const t0 = await screenOf(q0);
  await drag(t0, [t0[0], t0[1] - 50], { alt: true });
  d = await doc();
  const q1 = d.surface.net[1][3];
  check(q1[0] === q0[0] && q1[1] === q0[1] && q1[2] > q0[2] + 0.1, `Alt+drag moves a vertex along z only (z ${q0[2].toFixed(2)} → ${q1[2].toFixed(2)})`);
  await checkMesh('after an Alt+drag');

  // 3. Degrees: + in u elevates (same surface), − comes back exactly, − again is refused
  //    (real degree 3 in u) with the best approximation offered.
  const before = await page.evaluate(() => window.geomkit3d.drawn().mesh.positions);
  await page.click('#su-up');
  await idle();
  check((await page.textContent('#su-degree')) === '4' && (await doc()).surface.net.length === 5, '+ in u: degrees (4, 4)');
  const after = await page.evaluate(() => window.geomkit3d.drawn().mesh.positions);
  let moved = 0;
  for (let k = 0; k < before.length; k++) moved = Math.max(moved, Math.abs(before[k] - after[k]));
  check(moved < 1e-12, `elevation keeps the surface (moved ${moved.toExponential(1)})`);
  check((await page.textContent('#s-real')).trim() === '3, 4', `real degrees shown: ${await page.textContent('#s-real')}`);
  await checkMesh('after elevation');
  await page.click('#su-down');
  await idle();
  check((await page.textContent('#su-degree')) === '3', '− in u: back to degree 3 exactly');
  await page.click('#su-down');
  await idle();
  check(await page.isVisible('#s-refusal') && /real u-degree is 3/.test(await page.textContent('#s-refusal')), `below the real degree the reduction is refused with the reason: "${(await page.textContent('#s-refusal')).trim()}"`);
  check(await page.isVisible('#s-approx'), 'and the best approximation is offered');
  const api = await (await fetch(new URL('/api/surface/approximate', url), {
    method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ model: { type: 'bezier_surface', net: (await doc()).surface.net }, to: [2, 4] }),
  })).json();
  const shownL2 = +(await page.textContent('#s-approx-l2'));
  check(Math.abs(shownL2 - api.l2_error) <= 1e-3 * api.l2_error, `its L2 error ${shownL2} is the API's ${api.l2_error}`);
  const colours = await page.evaluate(() => window.geomkit3d.proposal().mesh);
  check(colours.colour === 'distance' && Math.max(...colours.values) > 0 && Math.max(...colours.values) <= api.linf_bound, `the error colouring: distances up to ${Math.max(...colours.values).toExponential(2)} <= the L∞ bound ${api.linf_bound.toExponential(2)}`);
  check(await page.isVisible('#legend3d'), 'with a legend');
  await page.screenshot({ path: path.join(shots, 'editor-3d-approx.png') });
  await page.click('#s-approx-accept');
  await idle();
  check((await page.textContent('#su-degree')) === '2', 'Accept: degrees (2, 4)');
  await checkMesh('after the approximation');

  // 4. A weight: select vertex (1, 2), weight 3.
  const w0 = await screenOf((await doc()).surface.net[1][2]);
  await page.mouse.click(w0[0], w0[1]);
  await idle();
  check((await page.evaluate(() => window.geomkit3d.selected())).join() === '1,2', 'a click selects the vertex under the mouse');
  await page.fill('#s-weight', '3');
  await page.press('#s-weight', 'Enter');
  await page.evaluate(() => document.getElementById('s-weight').dispatchEvent(new Event('change')));
  await idle();
  d = await doc();
  check(d.surface.weights && d.surface.weights[1][2] === 3, 'the weight is in the model');
  await checkMesh('rational, weight 3');

  // 5. Rows and columns where the selected vertex is.
  await page.click('#s-row-add');
  await idle();
  d = await doc();
  check(d.surface.net.length === 4 && d.surface.weights.length === 4, `+ row: ${d.surface.net.length} rows (with weights)`);
  await checkMesh('after + row');
  await page.click('#s-col-del');
  await idle();
  d = await doc();
  check(d.surface.net[0].length === 4, `− column: ${d.surface.net[0].length} columns`);
  await checkMesh('after − column');

  // 6. Undo, redo.
  const netNow = JSON.stringify(d.surface.net);
  await page.keyboard.press('Control+z');
  await idle();
  check((await doc()).surface.net[0].length === 5, 'Ctrl+Z brings the column back');
  await page.click('#redo');
  await idle();
  check(JSON.stringify((await doc()).surface.net) === netNow, 'redo removes it again');
  await checkMesh('after undo and redo');

  // 7. Save into the folder: the file is the page's net with its weights.
  page.once('dialog', (dlg) => dlg.accept('edited.json'));
  await page.click('#save');
  await idle();
  const saved = JSON.parse(await readFile(path.join(dir, 'edited.json'), 'utf8'));
  d = await doc();
  check(saved.type === 'bezier_surface' && JSON.stringify(saved.net) === JSON.stringify(d.surface.net) && JSON.stringify(saved.weights) === JSON.stringify(d.surface.weights), 'Save writes the net and its weights to the folder (bezier_surface)');
  // From a 2-D tab, Open takes a surface file to the surface tab.
  await page.click('button[data-mode="bezier"]');
  await page.click('#open');
  await page.click('#file-list >> text=edited.json');
  await page.waitForFunction(() => window.geomkit3d.active());
  await idle();
  check(await page.isVisible('#view3d') && JSON.stringify((await doc()).surface.weights) === JSON.stringify(saved.weights), 'opened from the Bézier curve tab, it shows in the surface tab with its weights');

  // 8. Open the 20 × 20 net from the folder; the redraw rate while dragging one vertex.
  await page.click('#open');
  await page.click('#file-list >> text=surface-20x20.json');
  await page.waitForFunction(() => window.geomkit3d.doc().surface.net.length === 20);
  await idle();
  await checkMesh('20 × 20 net');
  const [gx, gy] = await screenOf(big[10][9]);
  const rate = await redrawRate(page, { element: 'view3d', hooks: 'geomkit3d', x: gx, y: gy, dx: 0.4, amplitude: 50 });
  const fps = rate.frames / rate.seconds;
  console.log(`editor-3d: redraw rate while dragging a vertex of a 20 × 20 Bézier surface: ${fps.toFixed(1)} frames/s (${rate.frames} meshes drawn for ${rate.moves} pointer moves in ${rate.seconds.toFixed(2)} s; each a round trip to the server, a 13 × 13 mesh; 41 × 41 at rest)`);
  await writeFile(path.join(shots, 'editor-3d-fps.txt'), `${fps.toFixed(1)}\n`);
  check(rate.frames > 10, 'the surface was redrawn during the drag');
  await checkMesh('20 × 20 after the drag');
  await page.screenshot({ path: path.join(shots, 'editor-3d-20x20.png') });

  // 9. Heights: the tab, a height dragged with the mouse, the interpolant through them.
  await page.click('button[data-mode="heights"]');
  await page.waitForFunction(() => window.geomkit3d.drawn().model && window.geomkit3d.drawn().model.type === 'bspline_surface');
  await idle();
  async function checkHeights(what) {
    const [h, model] = await Promise.all([doc(), page.evaluate(() => window.geomkit3d.drawn().model)]);
    let worst = 0;
    h.heights.x.forEach((x, i) => h.heights.y.forEach((y, j) => {
      worst = Math.max(worst, Math.abs(heightAt(model, x, y) - h.heights.z[i][j]));
    }));
    check(worst < 1e-11, `${what}: the surface passes through every height (de Boor: off by ${worst.toExponential(1)})`);
  }
  await checkHeights('default grid');
  check(/Gaussian/.test(await page.textContent('#legend3d')), 'curvature colouring with its legend');
  await page.screenshot({ path: path.join(shots, 'editor-3d-heights.png') });
  d = await doc();
  const hp = [d.heights.x[4], d.heights.y[5], d.heights.z[4][5]];
  const hs = await screenOf(hp);
  await drag(hs, [hs[0], hs[1] - 40]);
  const z1 = (await doc()).heights.z[4][5];
  check(z1 > hp[2] + 0.1, `dragging a point up raises its height (${hp[2]} → ${z1.toFixed(3)})`);
  await checkHeights('after dragging a height');
  await page.selectOption('#h-colour', 'mean');
  await idle();
  check(/mean curvature/.test(await page.textContent('#legend3d')), 'mean curvature on request');

  // 10. Files of heights: CSV and .npy (float64, little-endian, C order).
  const csv = path.join(dir, 'heights.csv');
  await writeFile(csv, '# z\n0, 1, 2, 1\n1, 2, 3, 2\n0, 1, 4, 1\n');
  await page.setInputFiles('#h-file', csv);
  await page.waitForFunction(() => window.geomkit3d.doc().heights.x.length === 3);
  await idle();
  check((await doc()).heights.z[2][2] === 4, 'a CSV grid loads (3 × 4)');
  await checkHeights('CSV grid');
  const rows = 5, cols = 6;
  const values = new Float64Array(rows * cols).map((_, k) => Math.sin(k / 3));
  let header = `{'descr': '<f8', 'fortran_order': False, 'shape': (${rows}, ${cols}), }`;
  header += ' '.repeat(64 - ((10 + header.length + 1) % 64)) + '\n';
  const npy = Buffer.concat([
    Buffer.from([0x93]), Buffer.from('NUMPY'), Buffer.from([1, 0]),
    Buffer.from(new Uint16Array([header.length]).buffer), Buffer.from(header, 'latin1'),
    Buffer.from(values.buffer),
  ]);
  const npyPath = path.join(dir, 'heights.npy');
  await writeFile(npyPath, npy);
  await page.setInputFiles('#h-file', npyPath);
  await page.waitForFunction(() => window.geomkit3d.doc().heights.x.length === 5);
  await idle();
  check((await doc()).heights.z[4][5] === values[29], 'an .npy grid loads (5 × 6)');
  await checkHeights('.npy grid');
  await writeFile(csv, '1, 2\n3, x\n');
  await page.setInputFiles('#h-file', csv);
  await page.waitForFunction(() => /line 2, column 2/.test(document.getElementById('status').textContent));
  check(true, `a bad CSV is a clear error: "${await page.textContent('#status')}"`);

  // 11. Back to a 2-D tab: the 2-D editor is there again.
  await page.click('button[data-mode="bezier"]');
  check(await page.isVisible('#canvas') && !(await page.isVisible('#view3d')), 'the Bézier curve tab brings the 2-D view back');

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? ': ' + consoleErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(`editor-3d: FAIL ${e.stack || e}`);
  failures++;
  await page.screenshot({ path: path.join(shots, 'editor-3d-failure.png') }).catch(() => {});
} finally {
  await browser.close();
  server.kill();
}

if (failures) {
  console.error(`editor-3d: FAILED (${failures} checks)`);
  process.exit(1);
}
console.log(`editor-3d: all checks passed; screenshots in ${shots}`);
