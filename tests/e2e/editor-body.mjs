// End-to-end test of the editor's body tab in 3-D and of every file round trip (`geomkit
// serve`, issue 25) in headless Chromium (called by tests/e2e/run.sh).
//
//   node tests/e2e/editor-body.mjs --geomkit target/release/geomkit --out SHOT_DIR [--chromium PATH]
//
// Starts `geomkit serve --port 0 --dir TMP` and, with the real mouse:
// - the body tab: the cube shaded in 3-D with its seams. Every drawn seam polyline is
//   checked against the body's single formula printed in JavaScript by the server and
//   evaluated here (node), and, projected with the view's own matrices, against the pixels
//   of the canvas (the seam's colour where the nearest seam runs); hovering a seam names
//   it, clicking pins it in the status line; a drag rotates, the wheel zooms; another body
//   and undo / redo;
// - composite and ruled surfaces opened from the folder: the composite's jump marked as
//   discontinuous where the continuity report says;
// - save -> open of every file type the editor saves, each back in its own tab with its
//   state: a body (ruled), a Bézier curve with weights, a B-spline curve with non-default
//   options, a Bézier surface, a heights grid with a non-default end condition;
// - the Bézier surface tab coloured by Gaussian curvature: a sphere octant opened from the
//   folder has K = 1/R² at every vertex but the pole.
// Screenshots: editor-body-*.png. Exits 1 on any failure.

import { mkdtemp, readFile, writeFile } from 'node:fs/promises';
import os from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';
import { editorArgs, postJson, startServe } from './serve.mjs';

const args = await editorArgs('editor-body.mjs');
const shots = args.out;

const deadline = setTimeout(() => {
  console.error('editor-body: FAILED: editor-body.mjs did not finish within 240 s');
  process.exit(1);
}, 240_000);
deadline.unref();

let failures = 0;
function check(ok, what) {
  if (ok) console.log(`editor-body: ok   ${what}`);
  else {
    console.error(`editor-body: FAIL ${what}`);
    failures++;
  }
}

const dir = await mkdtemp(path.join(os.tmpdir(), 'geomkit-editor-body-'));
const { url, server } = await startServe(args.geomkit, ['--dir', dir]);
console.log(`editor-body: server at ${url}`);

// Files to open: the composite surface of docs/formats.md with its second patch lifted by
// 0.5 (its patches jump along u = 1), the ruled example of docs/formats.md, and an octant of
// the sphere of radius 2 as a rational biquadratic Bézier patch.
const composite = {
  type: 'composite_surface', u_knots: [0, 1, 2], v_knots: [0, 1],
  patches: [
    [{ bezier: [[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]] }],
    [{ x: '1 + u', y: 'v', z: 'v*(1 - u) + 0.5', domain: [[0, 1], [0, 1]] }],
  ],
};
await writeFile(path.join(dir, 'composite.json'), JSON.stringify(composite));
const ruled = {
  type: 'ruled', u: [0, 4], v: [0, 1, 2, 3],
  curves: [
    { point: [0, 0, -1] },
    { polygon: [[1, 1, -1], [-1, 1, -1], [-1, -1, -1], [1, -1, -1]] },
    { circle: { center: [0, 0, 1], radius: 1 } },
    { x: '0', y: '0', z: '1 + t', t: [0, 1] },
  ],
};
await writeFile(path.join(dir, 'ruled.json'), JSON.stringify(ruled));
const R = 2, h = Math.SQRT1_2;
const profile = [[[R, 0], 1], [[R, R], h], [[0, R], 1]];
const turn = [[[1, 0], 1], [[1, 1], h], [[0, 1], 1]];
const octant = {
  type: 'bezier_surface',
  net: profile.map(([p]) => turn.map(([t]) => [p[0] * t[0], p[0] * t[1], p[1]])),
  weights: profile.map(([, a]) => turn.map(([, b]) => a * b)),
};
await writeFile(path.join(dir, 'octant.json'), JSON.stringify(octant));

const browser = await chromium.launch({
  executablePath: args.chromium,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
const consoleErrors = [];
page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
page.on('pageerror', (e) => consoleErrors.push(e.message));
let saveAs = 'x.json';
page.on('dialog', (d) => d.accept(saveAs));

const idle = () => page.evaluate(async () => { await window.geomkit.idle(); await window.geomkit3d.idle(); });
const doc = () => page.evaluate(() => window.geomkit.doc());
const doc3 = () => page.evaluate(() => window.geomkit3d.doc());
const bodyAnswer = () => page.evaluate(() => window.geomkitBody.answer());

/** A file of the folder once the page's Save wrote it (the click's handler is not awaited). */
async function savedFile(name) {
  for (let i = 0; i < 100; i++) {
    try { return JSON.parse(await readFile(path.join(dir, name), 'utf8')); } catch { await new Promise((r) => setTimeout(r, 50)); }
  }
  throw new Error(`the page saved no ${name}`);
}

/** The single formula of the body tab's source printed in JavaScript by the server, as
 * functions evaluated here. */
async function formulaOf(source) {
  const f = await postJson(url, '/api/formula', { ...source, format: 'js' });
  const names = f.coordinates;
  // eslint-disable-next-line no-new-func
  return { fns: new Function(`${f.formula}\nreturn [${names.join(', ')}];`)(), vars: f.variables };
}

/** Page coordinates and depth of a world point, by the body view's matrices. */
async function screenOf(p) {
  return page.evaluate((q) => {
    const r = document.getElementById('body3d').getBoundingClientRect();
    const [x, y, z] = window.geomkitBody.project(q);
    return [r.left + x, r.top + y, z];
  }, p);
}

/** RGB of the body view's canvas at page point (x, y) and the 5 × 5 drawing-buffer pixels
 * around it (a line of 3 CSS pixels rounds either way), drawn in the same task. */
async function pixelsAt([x, y]) {
  return page.evaluate(([px, py]) => {
    const c = document.getElementById('body3d');
    const r = c.getBoundingClientRect();
    const gl = c.getContext('webgl2');
    const scale = c.width / r.width;
    window.geomkitBody.view().draw();
    const out = new Uint8Array(4 * 25);
    gl.readPixels(Math.round((px - r.left) * scale) - 2, Math.round(c.height - (py - r.top) * scale) - 2, 5, 5, gl.RGBA, gl.UNSIGNED_BYTE, out);
    const rgb = [];
    for (let k = 0; k < 25; k++) rgb.push(Array.from(out.slice(4 * k, 4 * k + 3)));
    return rgb;
  }, [x, y]);
}

/** The drawn seams against the formula evaluated here, and the front-most seam's pixel
 * against its colour. Returns the drawn seams. */
async function checkSeams(what, source) {
  const answer = await bodyAnswer();
  const drawn = await page.evaluate(() => window.geomkitBody.drawnSeams());
  const { fns } = await formulaOf(source);
  const graph = answer.parameters[0] === 'x';
  let worst = 0, scale = 0, count = 0;
  answer.seams.forEach((s, i) => {
    // Each drawn segment's ends are the seam's points in order; each point is the formula
    // at the seam's (u, v).
    const seg = drawn[i].segments;
    for (let k = 0; k < s.params.length; k++) {
      const [u, v] = s.params[k];
      const want = graph ? [u, v, fns[0](u, v)] : fns.map((f) => f(u, v));
      const at = k === 0 ? 0 : 6 * (k - 1) + 3;
      const got = seg.slice(at, at + 3);
      worst = Math.max(worst, Math.hypot(got[0] - want[0], got[1] - want[1], got[2] - want[2]));
      scale = Math.max(scale, Math.hypot(...want));
      count++;
    }
  });
  check(answer.seams.length > 0 && worst <= 1e-12 * Math.max(scale, 1), `${what}: ${answer.seams.length} seams drawn, their ${count} points on the single formula printed in JavaScript and run here (off by ${worst.toExponential(1)})`);
  // The seam nearest the eye at its middle (of those in the picture): its colour on the
  // canvas there.
  const box = await page.locator('#body3d').boundingBox();
  let best = null;
  for (const [i, s] of answer.seams.entries()) {
    const mid = Math.floor(s.points.length / 6) * 3;
    const p = s.points.slice(mid, mid + 3);
    const [x, y, z] = await screenOf(p);
    const inside = x > box.x + 10 && x < box.x + box.width - 10 && y > box.y + 10 && y < box.y + box.height - 10;
    if (inside && (!best || z < best.z)) best = { i, x, y, z };
  }
  const colour = await page.evaluate((i) => {
    const key = window.geomkitBody.drawnSeams()[i].key;
    return window.geomkitBody.styles.find((s) => s.key === key).rgb.map((c) => Math.round(c * 255));
  }, best.i);
  const px = await pixelsAt([best.x, best.y]);
  const near = px.map((p) => Math.hypot(p[0] - colour[0], p[1] - colour[1], p[2] - colour[2]));
  const k = near.indexOf(Math.min(...near));
  check(near[k] < 40, `${what}: where the front seam's middle projects, the canvas has its colour (rgb ${px[k].join(', ')} vs ${colour.join(', ')})`);
  return { answer, best };
}

try {
  await page.goto(url);
  await page.click('button[data-mode="body"]');
  await page.waitForFunction(() => window.geomkitBody && window.geomkitBody.answer());
  await idle();
  check(await page.isVisible('#body3d') && !(await page.isVisible('#picture')) && !(await page.isVisible('#view3d')), 'the body tab shows its 3-D view');

  // 1. The cube: 12 creases (its edges) and 8 C0 lines inside the flat caps.
  let { answer, best } = await checkSeams('the cube', { body: { kind: 'cube' } });
  const legend = await page.textContent('#body-legend');
  check(/turns\) · 12/.test(legend) && /tangent plane continuous · 8/.test(legend), `the legend counts the kinds of seams: ${legend.replace(/\s+/g, ' ')}`);
  check((await page.textContent('#formula')).length > 50, 'the formula panel shows the cube\'s single formula');
  await page.screenshot({ path: path.join(shots, 'editor-body-cube.png') });

  // Hover the front seam: the tooltip names it; click: pinned in the status line.
  await page.mouse.move(best.x, best.y);
  await page.waitForFunction(() => !document.getElementById('body-tip').hidden);
  const tip = await page.textContent('#body-tip');
  check(tip === answer.seams[best.i].label, `hovering a seam names it: "${tip}"`);
  await page.mouse.click(best.x, best.y);
  check((await page.textContent('#status')) === answer.seams[best.i].label && (await page.evaluate(() => window.geomkitBody.pinned())) === best.i, 'clicking it pins it and names it in the status line');
  await page.screenshot({ path: path.join(shots, 'editor-body-hover.png') });
  await page.mouse.click(best.x, best.y); // unpin

  // Rotate (drag) and zoom (wheel): the view moves, the seams stay on the formula.
  const box = await page.locator('#body3d').boundingBox();
  const yaw0 = await page.evaluate(() => window.geomkitBody.view().yaw);
  await page.mouse.move(box.x + 60, box.y + box.height - 60);
  await page.mouse.down();
  await page.mouse.move(box.x + 200, box.y + box.height - 100, { steps: 8 });
  await page.mouse.up();
  const d0 = await page.evaluate(() => window.geomkitBody.view().distance);
  await page.mouse.wheel(0, -150);
  const [yaw1, d1] = await page.evaluate(() => [window.geomkitBody.view().yaw, window.geomkitBody.view().distance]);
  check(yaw1 !== yaw0 && d1 < d0, `a drag rotates (yaw ${yaw0.toFixed(2)} → ${yaw1.toFixed(2)}), the wheel zooms (distance ${d0.toFixed(2)} → ${d1.toFixed(2)})`);
  await checkSeams('the cube rotated', { body: { kind: 'cube' } });
  await page.keyboard.press('f');

  // Another body, then undo / redo.
  await page.selectOption('#body-kind', 'cylinder');
  await idle();
  answer = await bodyAnswer();
  check(/cylinder/.test(answer.what) && answer.seams.every((s) => s.smoothness !== 'discontinuous'), `the cylinder: ${answer.seams.length} seams (${answer.legend.map((l) => `${l.count} ${l.crease ? 'creases' : l.smoothness}`).join(', ')})`);
  await page.screenshot({ path: path.join(shots, 'editor-body-cylinder.png') });
  // Its radius from the panel: the rims are circles of radius 1.5 about the axis.
  await page.fill('#body-radius', '1.5');
  await page.press('#body-radius', 'Enter');
  await idle();
  answer = await bodyAnswer();
  const rims = answer.seams.filter((s) => s.crease);
  const radii = rims.flatMap((s) => { const r = []; for (let k = 0; k < s.points.length; k += 3) r.push(Math.hypot(s.points[k], s.points[k + 1])); return r; });
  check(rims.length === 2 && radii.every((r) => Math.abs(r - 1.5) < 1e-12), `the radius field makes a cylinder of radius 1.5: its ${rims.length} rims at radius 1.5 (${radii.length} points)`);
  await page.click('#undo');
  await idle();
  check((await doc()).body.radius === undefined && (await page.inputValue('#body-radius')) === '1', 'undo the radius');
  await page.click('#undo');
  await idle();
  check((await doc()).body.kind === 'cube' && /cube/.test((await bodyAnswer()).what), 'undo brings the cube back');
  await page.click('#redo');
  await idle();
  check((await doc()).body.kind === 'cylinder' && (await page.isDisabled('#body-ngon')) && !(await page.isDisabled('#body-radius')), 'redo the cylinder (radius and height apply, sides do not)');

  // 2. Save the body: its ruled model file; reopen it into the body tab.
  saveAs = 'cylinder.json';
  await page.click('#save');
  await idle();
  const savedBody = await savedFile('cylinder.json');
  check(savedBody.type === 'ruled', 'Save in the body tab writes the body\'s ruled model file');
  // Export from the body tab: its mesh as GLB, its formula as text.
  const [glb] = await Promise.all([page.waitForEvent('download'), page.selectOption('#export', 'glb')]);
  const glbBytes = await readFile(await glb.path());
  check(glbBytes.subarray(0, 4).toString('latin1') === 'glTF' && glbBytes.length > 1000, `Export GLB in the body tab: a glTF binary of ${glbBytes.length} bytes`);
  const [txt] = await Promise.all([page.waitForEvent('download'), page.selectOption('#export', 'formula')]);
  const text = await readFile(await txt.path(), 'utf8');
  check(text.length > 50 && text === (await page.textContent('#formula')), `Export formula in the body tab: the ${text.length} characters of the formula panel`);
  const openFile = async (name) => {
    await page.click('#open');
    await page.click(`#file-list button:has-text("${name}")`);
    await idle();
  };
  await page.click('button[data-mode="bezier"]');
  await idle();
  await openFile('cylinder.json');
  let d = await doc();
  answer = await bodyAnswer();
  check(d.mode === 'body' && d.body.name === 'cylinder.json' && (await page.inputValue('#body-kind')) === 'file' && answer.seams.length > 0, `cylinder.json reopens in the body tab (${answer.seams.length} seams)`);

  // 3. Composite and ruled surfaces from the folder.
  await openFile('composite.json');
  await checkSeams('composite.json', { model: composite });
  answer = await bodyAnswer();
  const jump = answer.seams.find((s) => s.smoothness === 'discontinuous');
  check(jump && Math.abs(jump.patch_jump - 0.5) < 1e-12 && /jump by 0\.5/.test(await page.textContent('#body-legend') + jump.label), 'composite.json: the jump of 0.5 along u = 1 (its continuity report) is marked discontinuous');
  check((await page.textContent('#body-continuity')).startsWith('no'), 'the panel says its patches do not meet');
  await page.screenshot({ path: path.join(shots, 'editor-body-composite.png') });
  await openFile('ruled.json');
  await checkSeams('ruled.json', { model: ruled });
  await page.screenshot({ path: path.join(shots, 'editor-body-ruled.png') });

  // 4. Save -> open of the 2-D curves, each back in its tab with its state.
  await page.click('button[data-mode="bezier"]');
  await idle();
  await page.evaluate(() => {
    const d = window.geomkit.doc();
    d.mode = 'bezier';
    d.bezier.weights = d.bezier.points.map((_, i) => (i === 2 ? 2.5 : 1));
    window.geomkit.setDoc(d);
  });
  await idle();
  const bez = (await doc()).bezier;
  saveAs = 'curve.json';
  await page.click('#save');
  await savedFile('curve.json');
  await page.click('button[data-mode="bspline"]');
  await idle();
  await page.selectOption('#end', 'natural');
  await page.selectOption('#param', 'centripetal');
  await idle();
  const bs = (await doc()).bspline;
  saveAs = 'spline.json';
  await page.click('#save');
  await savedFile('spline.json');
  await page.selectOption('#end', 'not-a-knot');
  await page.selectOption('#param', 'chord');
  await idle();
  await openFile('curve.json');
  d = await doc();
  check(d.mode === 'bezier' && JSON.stringify(d.bezier) === JSON.stringify(bez), 'curve.json (a rational Bézier curve) reopens in the Bézier tab with its points and weights');
  await openFile('spline.json');
  d = await doc();
  const samePoints = d.bspline.points.length === bs.points.length && d.bspline.points.every((p, i) => Math.hypot(p[0] - bs.points[i][0], p[1] - bs.points[i][1]) < 1e-9);
  check(d.mode === 'bspline' && samePoints && d.bspline.end === 'natural' && d.bspline.param === 'centripetal' && (await page.inputValue('#end')) === 'natural', 'spline.json reopens in the B-spline tab with its points, end condition (natural) and parametrization (centripetal)');

  // A closed curve (periodic).
  await page.click('button[data-mode="bspline"]');
  await idle();
  await page.check('#closed');
  await idle();
  const closedPoints = (await doc()).bspline.points;
  saveAs = 'closed.json';
  await page.click('#save');
  await savedFile('closed.json');
  await page.uncheck('#closed');
  await idle();
  await openFile('closed.json');
  d = await doc();
  const sameClosed = d.bspline.points.length === closedPoints.length && d.bspline.points.every((p, i) => Math.hypot(p[0] - closedPoints[i][0], p[1] - closedPoints[i][1]) < 1e-9);
  check(d.mode === 'bspline' && d.bspline.closed && sameClosed && await page.isChecked('#closed'), `closed.json reopens as the closed curve through its ${closedPoints.length} points`);

  // 5. The 3-D tabs: a Bézier surface and a heights grid (end condition natural).
  await page.click('button[data-mode="surface"]');
  await idle();
  const net = (await doc3()).surface.net;
  saveAs = 'surface.json';
  await page.click('#save');
  await savedFile('surface.json');
  await page.click('button[data-mode="heights"]');
  await idle();
  await page.selectOption('#h-end', 'natural');
  await idle();
  const hd = (await doc3()).heights;
  saveAs = 'heights.json';
  await page.click('#save');
  await savedFile('heights.json');
  await page.selectOption('#h-end', 'not-a-knot');
  await idle();
  await page.click('button[data-mode="bezier"]');
  await idle();
  await openFile('heights.json');
  let d3 = await doc3();
  const sameZ = d3.heights.z.every((row, i) => row.every((z, j) => Math.abs(z - hd.z[i][j]) < 1e-9));
  check(await page.evaluate(() => window.geomkit3d.active()) && d3.mode === 'heights' && sameZ && d3.heights.end === 'natural' && JSON.stringify(d3.heights.x) === JSON.stringify(hd.x) && (await page.inputValue('#h-end')) === 'natural', 'heights.json (a height field) reopens in the heights tab: its grid, its heights and its end condition (natural)');
  await openFile('surface.json');
  d3 = await doc3();
  check(d3.mode === 'surface' && JSON.stringify(d3.surface.net) === JSON.stringify(net), 'surface.json reopens in the Bézier surface tab');
  // From a 3-D tab, a 2-D file goes to its own tab.
  await openFile('curve.json');
  check(!(await page.evaluate(() => window.geomkit3d.active())) && (await doc()).mode === 'bezier' && await page.isVisible('#canvas'), 'curve.json opened from the surface tab goes back to the Bézier curve tab');

  // 6. Curvature colouring of a Bézier surface: the sphere octant, K = 1/R².
  await openFile('octant.json');
  await page.selectOption('#s-colour', 'gaussian');
  await idle();
  const mesh = await page.evaluate(() => window.geomkit3d.drawn().mesh);
  let worstK = 0;
  mesh.u.forEach((u, a) => mesh.v.forEach((v, b) => {
    if (u < 1) worstK = Math.max(worstK, Math.abs(mesh.values[a * mesh.v.length + b] - 1 / (R * R)));
  }));
  check(mesh.colour === 'gaussian' && worstK < 1e-10, `the sphere octant of radius 2 coloured by Gaussian curvature: K = 1/4 at every vertex off the pole (off by ${worstK.toExponential(1)})`);
  check(/Gaussian/.test(await page.textContent('#legend3d')), 'with its legend');
  await page.screenshot({ path: path.join(shots, 'editor-body-octant-curvature.png') });
  await page.click('#undo');
  await idle();
  check((await doc3()).surface.colour === 'none' && (await page.inputValue('#s-colour')) === 'none', 'undo takes the colouring back (the selector follows)');

  check(consoleErrors.length === 0, `no console errors${consoleErrors.length ? `: ${consoleErrors.join(' | ')}` : ''}`);
} catch (e) {
  console.error(`editor-body: FAIL ${e.stack || e}`);
  failures++;
} finally {
  await browser.close();
  server.kill();
}

if (failures) {
  console.error(`editor-body: FAILED: ${failures} check(s)`);
  process.exit(1);
}
console.log('editor-body: all checks passed');
