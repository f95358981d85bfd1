// The editor's 3-D modes: Bézier surfaces (rational weights too) and B-spline surfaces
// through a grid of heights, drawn by view3d.js. Every surface point, normal, degree,
// curvature and error comes from the server (/api/surface/*, /api/bezier/*,
// docs/serve-api.md); the page holds the document (the net or the heights) and the camera.
//
// The 3-D modes own the stage while their tab is selected (main.mode-3d shows the WebGL
// view and hides the 2-D drawing, see style.css). The shared controls (undo / redo, open,
// save, export, the keyboard) are the same buttons as in the 2-D modes: while a 3-D mode is
// active, this module answers them first and stops the event.

import { ApiError, download, get, post, put } from './api.js';
import { View3D, colourMaps } from './view3d.js';

const $ = (id) => document.getElementById(id);
const clone = (x) => JSON.parse(JSON.stringify(x));
const MODES = ['surface', 'heights'];
const main = document.querySelector('main');
const canvas = $('view3d');

/** A wavy 4×5 net (degrees 3, 4): the document the surface mode opens on. */
function defaultNet() {
  const z = [
    [0.0, 0.5, 0.8, 0.5, 0.0],
    [0.4, 1.6, 2.2, 1.4, 0.3],
    [0.2, 1.2, -0.6, 1.0, 0.5],
    [0.0, 0.3, 0.6, 0.4, 0.0],
  ];
  return z.map((row, i) => row.map((h, j) => [i * 1.2, j, h]));
}

/** A 9×9 grid of heights over [-2, 2]² (two bumps): the heights mode's first document. */
function defaultHeights() {
  const x = Array.from({ length: 9 }, (_, i) => -2 + 0.5 * i);
  const y = x.slice();
  const z = x.map((a) => y.map((b) => {
    const h = 1.2 * Math.exp(-((a - 0.5) ** 2 + (b + 0.3) ** 2)) - 0.7 * Math.exp(-((a + 0.9) ** 2 + (b - 0.8) ** 2) / 0.6);
    return Math.round(h * 1000) / 1000;
  }));
  return { x, y, z };
}

const initial = {
  mode: 'surface',
  surface: { net: defaultNet(), weights: null, colour: 'none' },
  heights: { ...defaultHeights(), end: 'not-a-knot', colour: 'gaussian' },
};

let doc = clone(initial);
const history = { states: [clone(doc)], at: 0 };
let active = false;
let view = null;
/** What the server answered last: the mesh (and the model of a height field). */
let drawn = { mesh: null, model: null };
let degree = null;
let proposal = null;
let selected = null; // [i, j]
let dragging = null;
let needFit = true;
let filesAvailable = null;
const frames = [];

// ---------------------------------------------------------------------------------------
// Status line (the page's footer)

function status(text, isError = false) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', isError);
  s.title = text;
}

function showError(e) {
  status(e instanceof ApiError ? e.message : String(e && e.message ? e.message : e), true);
}

function fmt(x, digits = 4) {
  if (x === null || x === undefined) return '–';
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e-3 && a < 1e5 ? String(+x.toPrecision(digits)) : x.toExponential(2);
}

// ---------------------------------------------------------------------------------------
// The document and its history

function model() {
  if (doc.mode === 'surface') {
    const m = { type: 'bezier_surface', net: doc.surface.net };
    if (doc.surface.weights) m.weights = doc.surface.weights;
    return m;
  }
  return drawn.model;
}

function commit() {
  history.states.length = history.at + 1;
  history.states.push(clone(doc));
  history.at = history.states.length - 1;
  if (history.states.length > 300) { history.states.shift(); history.at--; }
  updateUndoButtons();
}

function restore(at) {
  if (at < 0 || at >= history.states.length) return;
  history.at = at;
  const mode = doc.mode;
  doc = clone(history.states[at]);
  doc.mode = mode;
  dropProposal();
  selected = null;
  showMode(); // the selectors show the restored options
  refresh();
  updateUndoButtons();
}

function updateUndoButtons() {
  if (!active) return;
  $('undo').disabled = history.at === 0;
  $('redo').disabled = history.at >= history.states.length - 1;
}

// ---------------------------------------------------------------------------------------
// Requests: while a vertex is dragged two computations may be in flight (the server answers
// one while the page draws the other), one at rest; an answer older than the one drawn is
// dropped, so a drag never shows a stale state last.

const scheduler = {
  inflight: 0,
  pending: false,
  sent: 0,
  applied: 0,
  request() {
    this.pending = true;
    this.pump();
  },
  pump() {
    const limit = dragging ? 2 : 1;
    while (this.pending && this.inflight < limit) {
      this.pending = false;
      this.inflight++;
      const seq = ++this.sent;
      compute(seq)
        .catch(showError)
        .finally(() => {
          this.inflight--;
          this.pump();
        });
    }
  },
  busy() { return this.inflight > 0 || this.pending; },
};

let actions = 0;
function act(fn) {
  return async (...a) => {
    actions++;
    try { await fn(...a); } catch (e) { showError(e); } finally { actions--; }
  };
}

function refresh() { if (active) scheduler.request(); }

/** Samples per direction: coarse while dragging, fine at rest. */
function samples() { return dragging ? 13 : 41; }

/** Computes what request `seq` asks for (the document as it is now) and shows it, unless a
 * later request was shown already. */
async function compute(seq) {
  const fine = !dragging;
  let next, report = null;
  if (doc.mode === 'surface') {
    const m = clone(model());
    let mesh;
    [mesh, report] = await Promise.all([
      post('/api/surface/mesh', { model: m, samples: samples(), colour: doc.surface.colour || 'none' }),
      fine ? post('/api/bezier/degree', { model: m }) : Promise.resolve(null),
    ]);
    next = { mesh, model: m };
  } else {
    const h = doc.heights;
    const r = await post('/api/surface/heights', {
      z: h.z, x: h.x, y: h.y, end: h.end, colour: h.colour, samples: samples(),
    });
    next = { mesh: r.mesh, model: r.model, what: r.what };
  }
  if (seq < scheduler.applied) return;
  scheduler.applied = seq;
  drawn = next;
  if (report) degree = report;
  if (dragging) {
    // Drawn at the next animation frame with any vertex moved meanwhile (one GL frame).
    meshArrived = true;
    drawSoon();
  } else {
    draw();
    showFacts();
  }
}

/** A mesh came from the server during a drag and is not drawn yet (counted in `frames`). */
let meshArrived = false;

// ---------------------------------------------------------------------------------------
// Drawing

const SURFACE_RGB = [0.47, 0.62, 0.86];
const NET_RGB = [0.36, 0.40, 0.47];
const POINT_RGB = [0.13, 0.31, 0.71];
const SELECTED_RGB = [0.93, 0.45, 0.11];
const HEIGHT_RGB = [0.93, 0.45, 0.11];

/** The control points (surface) or reference points (heights) as a flat array. */
function handles() {
  const out = [];
  if (doc.mode === 'surface') {
    for (const row of doc.surface.net) for (const p of row) out.push(p[0], p[1], p[2]);
  } else {
    const { x, y, z } = doc.heights;
    x.forEach((a, i) => y.forEach((b, j) => out.push(a, b, z[i][j])));
  }
  return out;
}

function gridSize() {
  return doc.mode === 'surface'
    ? [doc.surface.net.length, doc.surface.net[0].length]
    : [doc.heights.x.length, doc.heights.y.length];
}

/** Colours of the mesh's vertices from its values (curvature: diverging about 0; errors:
 * sequential from 0), and the legend. */
function meshColours(mesh) {
  const n = mesh.positions.length / 3;
  const colours = new Float32Array(n * 3);
  const legend = $('legend3d');
  if (!mesh.values || !mesh.range) {
    for (let k = 0; k < n; k++) colours.set(SURFACE_RGB, 3 * k);
    legend.hidden = true;
    return colours;
  }
  const [lo, hi] = mesh.range;
  const signed = mesh.colour === 'gaussian' || mesh.colour === 'mean';
  const span = signed ? Math.max(Math.abs(lo), Math.abs(hi)) || 1 : hi || 1;
  const map = signed ? colourMaps.diverging : colourMaps.sequential;
  const t = (v) => (signed ? 0.5 + 0.5 * (v / span) : v / span);
  for (let k = 0; k < n; k++) colours.set(map(t(mesh.values[k])), 3 * k);
  const stops = Array.from({ length: 11 }, (_, i) => {
    const c = map(i / 10).map((x) => Math.round(x * 255));
    return `rgb(${c.join(',')}) ${i * 10}%`;
  });
  const title = { gaussian: 'Gaussian curvature K', mean: 'mean curvature H', distance: 'distance to the original surface' }[mesh.colour];
  legend.innerHTML = '';
  const head = document.createElement('div');
  head.textContent = title;
  const bar = document.createElement('div');
  bar.className = 'bar3d';
  bar.style.background = `linear-gradient(to right, ${stops.join(', ')})`;
  const ends = document.createElement('div');
  ends.className = 'ends';
  const [a, b] = signed ? [-span, span] : [0, span];
  for (const v of [a, signed ? 0 : span / 2, b]) {
    const s = document.createElement('span');
    s.textContent = fmt(v, 3);
    ends.appendChild(s);
  }
  legend.append(head, bar, ends);
  legend.hidden = false;
  return colours;
}

let drawQueued = false;
/** One draw at the next animation frame, however many changes come before it. */
function drawSoon() {
  if (drawQueued) return;
  drawQueued = true;
  requestAnimationFrame(() => {
    drawQueued = false;
    draw();
    if (meshArrived && dragging) frames.push(performance.now());
    meshArrived = false;
  });
}

function draw() {
  if (!view) return;
  // Supersampled (2×) at rest for smooth edges; 1× while something moves (software GL).
  view.scale = dragging ? 0.5 : 2;
  const mesh = proposal ? proposal.mesh : drawn.mesh;
  if (mesh) {
    view.setMesh({ rows: mesh.rows, cols: mesh.cols, positions: mesh.positions, normals: mesh.normals, colors: meshColours(mesh) });
  } else {
    view.clearMesh();
  }
  const pts = handles();
  const [rows, cols] = gridSize();
  // The control net's (or grid's) lines.
  const seg = [];
  const P = (i, j) => { const k = 3 * (i * cols + j); return [pts[k], pts[k + 1], pts[k + 2]]; };
  if (doc.mode === 'surface' && !proposal) {
    for (let i = 0; i < rows; i++) for (let j = 0; j + 1 < cols; j++) seg.push(...P(i, j), ...P(i, j + 1));
    for (let j = 0; j < cols; j++) for (let i = 0; i + 1 < rows; i++) seg.push(...P(i, j), ...P(i + 1, j));
  }
  view.setLines(seg, NET_RGB);
  if (proposal) {
    view.setPoints([], []);
  } else {
    const colours = new Float32Array(pts.length);
    const base = doc.mode === 'surface' ? POINT_RGB : HEIGHT_RGB;
    for (let k = 0; k < pts.length / 3; k++) colours.set(base, 3 * k);
    if (selected) colours.set(doc.mode === 'surface' ? SELECTED_RGB : [0.1, 0.1, 0.12], 3 * (selected[0] * cols + selected[1]));
    view.setPoints(pts, colours, doc.mode === 'surface' ? 12 : 9);
  }
  if (needFit) {
    view.fit(mesh ? mesh.positions : null, pts);
    needFit = false;
  }
  view.draw();
}

function showFacts() {
  if (doc.mode === 'surface') {
    const [rows, cols] = gridSize();
    $('su-degree').textContent = rows - 1;
    $('sv-degree').textContent = cols - 1;
    $('s-net').textContent = `${rows} × ${cols}${doc.surface.weights ? ', weighted' : ''}`;
    if (degree) {
      $('s-real').textContent = `${degree.u.real_degree}, ${degree.v.real_degree}`;
      $('s-defect').textContent = `${degree.u.defect}, ${degree.v.defect}`;
    }
    $('s-selected').textContent = selected ? `u[${selected[0]}][${selected[1]}] = (${doc.surface.net[selected[0]][selected[1]].map((x) => fmt(x, 3)).join(', ')})` : 'none';
    const w = $('s-weight');
    w.disabled = !selected;
    w.value = selected ? (doc.surface.weights ? doc.surface.weights[selected[0]][selected[1]] : 1) : 1;
    for (const id of ['s-row-add', 's-col-add', 's-row-del', 's-col-del']) $(id).disabled = !selected;
    status(`${drawn.mesh ? drawn.mesh.what : ''}: degrees (${rows - 1}, ${cols - 1})${degree ? `, real degrees (${degree.u.real_degree}, ${degree.v.real_degree})` : ''}.`);
  } else {
    const h = doc.heights;
    $('h-grid').textContent = `${h.x.length} × ${h.y.length}`;
    $('h-selected').textContent = selected ? `z[${selected[0]}][${selected[1]}] = ${fmt(h.z[selected[0]][selected[1]])}` : '–';
    const r = drawn.mesh && drawn.mesh.range;
    $('h-range').textContent = r ? `${fmt(r[0], 3)} … ${fmt(r[1], 3)}` : '–';
    if (drawn.what) status(`${drawn.what} through ${h.x.length} × ${h.y.length} heights.`);
  }
}

// ---------------------------------------------------------------------------------------
// Mouse: pick and drag a vertex (in the view plane, or along z with Alt / Shift; a height
// always along z), or rotate (drag the background), pan (right or middle drag), zoom (wheel).

function pointOf(index) {
  const [, cols] = gridSize();
  const [i, j] = [Math.floor(index / cols), index % cols];
  return [i, j];
}

function setPoint([i, j], p) {
  if (doc.mode === 'surface') doc.surface.net[i][j] = p;
  else doc.heights.z[i][j] = p[2];
}

function getPoint([i, j]) {
  if (doc.mode === 'surface') return doc.surface.net[i][j].slice();
  return [doc.heights.x[i], doc.heights.y[j], doc.heights.z[i][j]];
}

canvas.addEventListener('pointerdown', (ev) => {
  if (!active || !view) return;
  canvas.focus();
  const [sx, sy] = view.eventPoint(ev);
  const hit = ev.button === 0 && !proposal ? view.pick(handles(), sx, sy, 12) : -1;
  canvas.setPointerCapture(ev.pointerId);
  if (hit >= 0) {
    selected = pointOf(hit);
    const p0 = getPoint(selected);
    const alongZ = doc.mode === 'heights' || ev.altKey || ev.shiftKey;
    // Along z: the screen direction of +z at the point, in pixels per world unit.
    const a = view.project(p0), b = view.project([p0[0], p0[1], p0[2] + 1e-3 * view.radius]);
    const axis = [(b[0] - a[0]) / (1e-3 * view.radius), (b[1] - a[1]) / (1e-3 * view.radius)];
    const { right, up } = view.axes();
    dragging = { kind: 'point', start: [sx, sy], p0, alongZ, axis, right, up, size: view.pixelSize(p0), moved: false };
    draw();
    showFacts();
  } else {
    dragging = { kind: ev.button === 0 && !ev.shiftKey ? 'orbit' : 'pan', last: [sx, sy] };
  }
});

canvas.addEventListener('pointermove', (ev) => {
  if (!dragging) return;
  const [sx, sy] = view.eventPoint(ev);
  if (dragging.kind === 'point') {
    const [dx, dy] = [sx - dragging.start[0], sy - dragging.start[1]];
    const { p0 } = dragging;
    let p;
    if (dragging.alongZ) {
      const [ax, ay] = dragging.axis;
      const len2 = ax * ax + ay * ay;
      const t = len2 > 1e-12 ? (dx * ax + dy * ay) / len2 : 0;
      p = [p0[0], p0[1], p0[2] + t];
    } else {
      const { right, up, size } = dragging;
      p = [0, 1, 2].map((c) => p0[c] + (dx * right[c] - dy * up[c]) * size);
    }
    setPoint(selected, p);
    dragging.moved = true;
    drawSoon(); // the vertex follows at once; the surface when the server answers
    refresh();
  } else {
    const [dx, dy] = [sx - dragging.last[0], sy - dragging.last[1]];
    dragging.last = [sx, sy];
    if (dragging.kind === 'orbit') view.orbit(dx, dy);
    else view.pan(dx, dy);
    drawSoon();
  }
});

function endDrag() {
  if (!dragging) return;
  const d = dragging;
  dragging = null;
  if (d.kind === 'point' && d.moved) {
    commit();
    refresh();
  } else {
    drawSoon();
  }
}
canvas.addEventListener('pointerup', endDrag);
canvas.addEventListener('pointercancel', endDrag);
canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
canvas.addEventListener('wheel', (ev) => {
  if (!view) return;
  ev.preventDefault();
  view.zoom(Math.exp(ev.deltaY * 0.0015));
  view.draw();
}, { passive: false });
window.addEventListener('resize', () => { if (active && view) view.draw(); });

// ---------------------------------------------------------------------------------------
// Degrees (spec bezier-order.md: elevation (8)/(14), exact reduction with the defect (16),
// or the best L2 approximation with its error drawn on the surface)

function dropProposal() {
  proposal = null;
  $('s-approx').hidden = true;
  $('s-refusal').hidden = true;
}

function takeSurface(m) {
  doc.surface.net = m.net;
  doc.surface.weights = m.weights || null;
  // The selection stays where it still exists.
  if (selected && !(selected[0] < m.net.length && selected[1] < m.net[0].length)) selected = null;
  commit();
  refresh();
}

async function changeDegree(direction, step) {
  dropProposal();
  const [rows, cols] = gridSize();
  const to = [rows - 1, cols - 1];
  to[direction] += step;
  if (to[direction] < 0) return;
  if (step > 0) {
    takeSurface((await post('/api/bezier/elevate', { model: model(), to })).model);
    status(`Elevated to degrees (${to[0]}, ${to[1]}): the same surface.`);
    return;
  }
  try {
    takeSurface((await post('/api/bezier/reduce', { model: model(), to })).model);
    status(`Reduced exactly to degrees (${to[0]}, ${to[1]}): the same surface.`);
  } catch (e) {
    if (!(e instanceof ApiError) || e.body.reason !== 'real_degree') throw e;
    const notice = $('s-refusal');
    notice.textContent = `No exact reduction to (${to[0]}, ${to[1]}): ${e.message.split(';')[0].replace(/^[^:]*: /, '')}.`;
    notice.hidden = false;
    if (doc.surface.weights) {
      notice.textContent += ' The best approximation is for polynomial nets (this one has weights).';
      return;
    }
    const r = await post('/api/surface/approximate', { model: model(), to, samples: 41 });
    proposal = { ...r, to };
    $('s-approx-to').textContent = `(${to[0]}, ${to[1]})`;
    $('s-approx-l2').textContent = fmt(r.l2_error);
    $('s-approx-linf').textContent = fmt(r.linf_bound);
    $('s-approx-found').textContent = fmt(r.linf_found);
    $('s-approx').hidden = false;
    status(`Best approximation of degrees (${to[0]}, ${to[1]}): L2 error ${fmt(r.l2_error)}, L∞ bound ${fmt(r.linf_bound)} (the colours: distance to the original). Accept or Cancel.`);
    draw();
  }
}

$('su-up').addEventListener('click', act(() => changeDegree(0, 1)));
$('sv-up').addEventListener('click', act(() => changeDegree(1, 1)));
$('su-down').addEventListener('click', act(() => changeDegree(0, -1)));
$('sv-down').addEventListener('click', act(() => changeDegree(1, -1)));
$('s-approx-accept').addEventListener('click', () => {
  if (!proposal) return;
  const m = proposal.model;
  dropProposal();
  takeSurface(m);
  status('Accepted the approximation.');
});
$('s-approx-cancel').addEventListener('click', () => { dropProposal(); draw(); showFacts(); });

// ---------------------------------------------------------------------------------------
// Weights and the rows / columns of the net (Fig. 4: a line inserted or removed)

$('s-weight').addEventListener('change', () => {
  const w = +$('s-weight').value;
  if (!selected) return;
  if (!(w > 0 && isFinite(w))) { status('A weight must be a number > 0.', true); showFacts(); return; }
  const [rows, cols] = gridSize();
  if (!doc.surface.weights) doc.surface.weights = Array.from({ length: rows }, () => Array(cols).fill(1));
  doc.surface.weights[selected[0]][selected[1]] = w;
  if (doc.surface.weights.every((r) => r.every((x) => x === 1))) doc.surface.weights = null;
  dropProposal();
  commit();
  refresh();
});

/** Inserts a row (direction 'u') or column ('v') after the selected vertex's: midway to the
 * next one, or continuing the last one beyond the edge. */
async function insertLine(direction) {
  if (!selected) return;
  const net = doc.surface.net, w = doc.surface.weights;
  const [rows, cols] = gridSize();
  const u = direction === 'u';
  const k = u ? selected[0] : selected[1];
  const count = u ? rows : cols;
  const at = (a, b) => (u ? net[a][b] : net[b][a]);
  const wt = (a, b) => (w ? (u ? w[a][b] : w[b][a]) : 1);
  const len = u ? cols : rows;
  const points = [], weights = [];
  for (let b = 0; b < len; b++) {
    const p = at(k, b);
    const q = k + 1 < count ? at(k + 1, b) : p.map((x, c) => 2 * x - at(k - 1 >= 0 ? k - 1 : k, b)[c]);
    points.push(p.map((x, c) => (x + q[c]) / 2));
    weights.push(k + 1 < count ? (wt(k, b) + wt(k + 1, b)) / 2 : wt(k, b));
  }
  const body = { model: model(), insert: { direction, index: k + 1, points } };
  if (w) body.insert.weights = weights;
  const r = await post('/api/surface/edit', body);
  dropProposal();
  takeSurface(r.model);
  statusEdit(r, `Inserted a ${u ? 'row' : 'column'} at ${k + 1}`);
}

async function removeLine(direction) {
  if (!selected) return;
  const index = direction === 'u' ? selected[0] : selected[1];
  const r = await post('/api/surface/edit', { model: model(), remove: { direction, index } });
  dropProposal();
  takeSurface(r.model);
  statusEdit(r, `Removed ${direction === 'u' ? 'row' : 'column'} ${index}`);
}

function statusEdit(r, what) {
  const d = r.deviation;
  status(`${what}: degrees (${r.degrees[0]}, ${r.degrees[1]})${d ? `; the surface moved by up to ${fmt(d.upper_bound)} (${fmt(d.max_found)} found)` : ''}.`);
}

$('s-row-add').addEventListener('click', act(() => insertLine('u')));
$('s-col-add').addEventListener('click', act(() => insertLine('v')));
$('s-row-del').addEventListener('click', act(() => removeLine('u')));
$('s-col-del').addEventListener('click', act(() => removeLine('v')));

// ---------------------------------------------------------------------------------------
// Heights: options, the default grid, CSV and .npy files

$('h-end').addEventListener('change', () => { doc.heights.end = $('h-end').value; commit(); refresh(); });
$('s-colour').addEventListener('change', () => { doc.surface.colour = $('s-colour').value; commit(); refresh(); });
$('h-colour').addEventListener('change', () => { doc.heights.colour = $('h-colour').value; commit(); refresh(); });
$('h-default').addEventListener('click', () => {
  Object.assign(doc.heights, defaultHeights());
  selected = null;
  needFit = true;
  commit();
  refresh();
});
$('h-load').addEventListener('click', () => $('h-file').click());
$('h-file').addEventListener('change', act(async () => {
  const f = $('h-file').files[0];
  $('h-file').value = '';
  if (!f) return;
  const z = f.name.toLowerCase().endsWith('.npy') ? parseNpy(await f.arrayBuffer(), f.name) : parseCsv(await f.text(), f.name);
  setHeights(z, f.name);
}));

/** A matrix of heights as the document (unit spacing). */
function setHeights(z, name) {
  if (z.length < 2 || z[0].length < 2) throw new Error(`${name}: a heights grid needs at least 2 rows and 2 columns (got ${z.length} × ${z[0] ? z[0].length : 0})`);
  doc.heights.z = z;
  doc.heights.x = z.map((_, i) => i);
  doc.heights.y = z[0].map((_, j) => j);
  selected = null;
  needFit = true;
  commit();
  refresh();
  status(`Loaded ${name}: ${z.length} × ${z[0].length} heights.`);
}

/** CSV or whitespace-separated text: one row of numbers per line ('#' comments). */
export function parseCsv(text, name = 'the file') {
  const rows = [];
  text.split(/\r?\n/).forEach((line, li) => {
    const t = line.replace(/#.*/, '').trim();
    if (!t) return;
    const cells = t.split(/\s*[,;\t ]\s*/);
    const row = cells.map((c, ci) => {
      const v = Number(c);
      if (c === '' || !Number.isFinite(v)) throw new Error(`${name}, line ${li + 1}, column ${ci + 1}: "${c}" is not a finite number`);
      return v;
    });
    if (rows.length && row.length !== rows[0].length) throw new Error(`${name}, line ${li + 1}: ${row.length} numbers, the first row has ${rows[0].length}`);
    rows.push(row);
  });
  if (!rows.length) throw new Error(`${name}: no numbers`);
  return rows;
}

/** A 2-D NumPy .npy array (float64/32, int64/32, either byte order, C or Fortran order). */
export function parseNpy(buffer, name = 'the file') {
  const bytes = new Uint8Array(buffer);
  const magic = [0x93, 0x4e, 0x55, 0x4d, 0x50, 0x59];
  if (bytes.length < 10 || magic.some((b, i) => bytes[i] !== b)) throw new Error(`${name}: not a .npy file (no \\x93NUMPY magic)`);
  const dv = new DataView(buffer);
  const major = bytes[6];
  const headerLen = major === 1 ? dv.getUint16(8, true) : dv.getUint32(8, true);
  const start = major === 1 ? 10 : 12;
  const header = new TextDecoder('latin1').decode(bytes.subarray(start, start + headerLen));
  const descr = /'descr':\s*'([<>|=]?)([fi])(\d)'/.exec(header);
  const shape = /'shape':\s*\(([^)]*)\)/.exec(header);
  const fortran = /'fortran_order':\s*True/.test(header);
  if (!descr) throw new Error(`${name}: element type not supported (${header.trim()}); use float64, float32, int64 or int32`);
  if (!shape) throw new Error(`${name}: no shape in the header`);
  const dims = shape[1].split(',').map((s) => s.trim()).filter(Boolean).map(Number);
  if (dims.length !== 2) throw new Error(`${name}: shape (${dims.join(', ')}): heights need a 2-D array`);
  const [r, c] = dims;
  const little = descr[1] !== '>';
  const size = +descr[3];
  const kind = descr[2] + size;
  if (!['f8', 'f4', 'i8', 'i4'].includes(kind)) throw new Error(`${name}: element type ${kind} not supported`);
  const data = start + headerLen;
  if (buffer.byteLength < data + r * c * size) throw new Error(`${name}: ${r * c} elements announced, the file is too short`);
  const read = (k) => {
    const at = data + k * size;
    if (kind === 'f8') return dv.getFloat64(at, little);
    if (kind === 'f4') return dv.getFloat32(at, little);
    if (kind === 'i8') return Number(dv.getBigInt64(at, little));
    return dv.getInt32(at, little);
  };
  const z = [];
  for (let i = 0; i < r; i++) {
    const row = [];
    for (let j = 0; j < c; j++) {
      const v = read(fortran ? j * r + i : i * c + j);
      if (!Number.isFinite(v)) throw new Error(`${name}: element [${i}, ${j}] is not finite`);
      row.push(v);
    }
    z.push(row);
  }
  return z;
}

// ---------------------------------------------------------------------------------------
// Open, save, export (the model files of the CLI), undo / redo, keys: the shared buttons

async function filesOn() {
  if (filesAvailable === null) {
    try { filesAvailable = (await get('/api/version')).files; } catch { filesAvailable = false; }
  }
  return filesAvailable;
}

/** The heights tab's end conditions, in the order a file's is looked for. */
const HEIGHT_ENDS = ['not-a-knot', 'natural', 'clamped', 'bessel'];

/** Whether two bspline_surface files hold the same surface (knots and net within
 * rounding). */
function sameSurface(a, b) {
  const flat = (x) => (Array.isArray(x) ? x.flatMap(flat) : [x]);
  const pairs = [[a.knots_u, b.knots_u], [a.knots_v, b.knots_v], [a.net, b.net]];
  return pairs.every(([x, y]) => {
    const [p, q] = [flat(x), flat(y)];
    const scale = Math.max(1, ...p.map(Math.abs));
    return p.length === q.length && p.every((v, i) => Math.abs(v - q[i]) <= 1e-9 * scale);
  });
}

/** A heights grid saved by the heights tab (a bspline_surface in R^1 with its grid
 * `parameters_u`, `parameters_v`): its heights are the surface at the grid (the server's
 * samples); its end condition, the one of the tab whose interpolant is this surface. */
async function openHeights(m, name) {
  const x = m.parameters_u, y = m.parameters_v;
  if (!Array.isArray(x) || !Array.isArray(y)) throw new Error(`${name}: a B-spline surface without its grid (parameters_u, parameters_v) is not a heights grid`);
  const s = await post('/api/samples', { model: m, samples: 2 });
  if (s.references.length !== x.length * y.length) throw new Error(`${name}: ${s.references.length} reference points for a ${x.length} × ${y.length} grid`);
  const z = x.map((_, i) => y.map((_, j) => s.references[i * y.length + j][2]));
  let end = null;
  for (const e of HEIGHT_ENDS) {
    const r = await post('/api/surface/heights', { z, x, y, end: e, samples: 2, colour: 'none' });
    if (sameSurface(r.model, m)) { end = e; break; }
  }
  doc.heights = { x, y, z, end: end || 'not-a-knot', colour: doc.heights.colour };
  activate('heights');
  selected = null;
  needFit = true;
  dropProposal();
  commit();
  refresh();
  status(`Opened ${name}: ${x.length} × ${y.length} heights, ${end ? `end condition ${end}` : 'an end condition the tab does not offer (drawn not-a-knot)'}.`);
}

/** Whether a model file opens in a 3-D tab here (else in app.js's tabs). */
function ours(m) {
  return m.type === 'bezier_surface'
    || (m.type === 'bspline_surface' && Array.isArray(m.parameters_u) && m.net?.[0]?.[0]?.length === 1);
}

async function openModel(m, name) {
  if (m.type === 'bspline_surface') return openHeights(m, name);
  if (m.type !== 'bezier_surface') {
    throw new Error(`${name} is a ${m.type}: the 3-D tabs open bezier_surface files and heights grids (bspline_surface in R^1 with its grid)`);
  }
  doc.surface = { net: m.net, weights: m.weights || null, colour: doc.surface.colour || 'none' };
  activate('surface');
  selected = null;
  needFit = true;
  dropProposal();
  commit();
  refresh();
  status(`Opened ${name}.`);
}

async function openDialog() {
  if (!(await filesOn())) { $('s-file').click(); return; }
  const list = $('file-list');
  list.innerHTML = '';
  const { files } = await get('/api/files');
  if (!files.length) {
    const li = document.createElement('li');
    li.className = 'empty';
    li.textContent = 'No .json files in the folder.';
    list.appendChild(li);
  }
  for (const f of files) {
    const li = document.createElement('li');
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = `${f.name} (${f.bytes} bytes)`;
    b.addEventListener('click', act(async () => {
      $('open-dialog').close();
      const r = await get(`/api/files/${encodeURIComponent(f.name)}`);
      if (ours(r.model)) await openModel(r.model, f.name);
      else await window.geomkit.open(r.model, f.name); // the other tabs (app.js)
    }));
    li.appendChild(b);
    list.appendChild(li);
  }
  $('open-dialog').showModal();
}

$('s-file').addEventListener('change', act(async () => {
  const f = $('s-file').files[0];
  $('s-file').value = '';
  if (!f) return;
  const m = JSON.parse(await f.text());
  if (ours(m)) await openModel(m, f.name);
  else await window.geomkit.open(m, f.name);
}));

async function save() {
  const m = model();
  if (!m) return;
  if (await filesOn()) {
    const name = prompt('Save as (a .json name in the server\'s folder):', doc.mode === 'surface' ? 'surface.json' : 'heights.json');
    if (!name) return;
    const r = await put(`/api/files/${encodeURIComponent(name)}`, { model: m });
    status(`Saved ${r.name} (${r.bytes} bytes): ${r.what}.`);
  } else {
    download(await post('/api/export', { model: m, format: 'json' }), 'model.json');
    status('Downloaded model.json (start the server with --dir FOLDER to save into a folder).');
  }
}

async function exportAs(format) {
  const m = model();
  if (!format || !m) return;
  const blob = await post('/api/export', { model: m, format });
  download(blob, `model.${format === 'formula' ? 'txt' : format}`);
  status(`Exported model.${format === 'formula' ? 'txt' : format}.`);
}

/** Runs `fn` instead of the 2-D handlers while a 3-D mode is active. */
function intercept(id, type, fn) {
  $(id).addEventListener(type, (ev) => {
    if (!active) return;
    ev.stopImmediatePropagation();
    ev.preventDefault();
    act(fn)(ev);
  }, true);
}

intercept('undo', 'click', () => restore(history.at - 1));
intercept('redo', 'click', () => restore(history.at + 1));
intercept('open', 'click', openDialog);
intercept('save', 'click', save);
intercept('export', 'change', async () => {
  const format = $('export').value;
  $('export').value = '';
  await exportAs(format);
});
$('fit3d').addEventListener('click', () => { needFit = true; draw(); });

window.addEventListener('keydown', (ev) => {
  if (!active) return;
  if (ev.target instanceof HTMLInputElement || ev.target instanceof HTMLSelectElement || $('open-dialog').open) return;
  const mod = ev.ctrlKey || ev.metaKey;
  const key = ev.key.toLowerCase();
  let done = true;
  if (mod && key === 'z') { if (ev.shiftKey) restore(history.at + 1); else restore(history.at - 1); }
  else if (mod && key === 'y') restore(history.at + 1);
  else if (mod && key === 's') act(save)();
  else if (mod) done = false;
  else if (key === 'f') { needFit = true; draw(); }
  else if (ev.key === '+' || ev.key === '=') { view.zoom(1 / 1.2); view.draw(); }
  else if (ev.key === '-') { view.zoom(1.2); view.draw(); }
  else if (ev.key.startsWith('Arrow')) {
    const d = { ArrowLeft: [-20, 0], ArrowRight: [20, 0], ArrowUp: [0, -20], ArrowDown: [0, 20] }[ev.key];
    if (ev.shiftKey) view.pan(d[0], d[1]); else view.orbit(d[0], d[1]);
    view.draw();
  } else done = false;
  if (done) { ev.preventDefault(); ev.stopImmediatePropagation(); }
}, true);

// ---------------------------------------------------------------------------------------
// Mode switching: the tabs of the 3-D modes; any other tab hands the stage back.

function showMode() {
  for (const b of document.querySelectorAll('.tabs button')) b.setAttribute('aria-selected', String(b.dataset.mode === doc.mode));
  $('surface-panel').hidden = doc.mode !== 'surface';
  $('heights-panel').hidden = doc.mode !== 'heights';
  $('h-end').value = doc.heights.end;
  $('h-colour').value = doc.heights.colour;
  $('s-colour').value = doc.surface.colour || 'none';
  $('legend3d').hidden = true;
  $('hint3d').textContent = 'Drag: rotate · right-drag: pan · wheel: zoom · F: fit' + (doc.mode === 'surface' ? ' · Alt+drag a vertex: along z' : ' · drag a point: its height');
}

function activate(mode) {
  if (!view) {
    try {
      view = new View3D(canvas);
    } catch (e) {
      showError(e);
      return;
    }
  }
  if (!active || doc.mode !== mode) { needFit = true; selected = null; dropProposal(); }
  active = true;
  doc.mode = mode;
  main.classList.add('mode-3d');
  showMode();
  updateUndoButtons();
  drawn = { mesh: null, model: null };
  refresh();
}

function deactivate() {
  active = false;
  main.classList.remove('mode-3d');
  $('surface-panel').hidden = true;
  $('heights-panel').hidden = true;
}

document.querySelector('.tabs').addEventListener('click', (ev) => {
  const b = ev.target.closest('button[data-mode]');
  if (!b) return;
  if (MODES.includes(b.dataset.mode)) {
    ev.stopPropagation();
    activate(b.dataset.mode);
  } else if (active) {
    deactivate();
    // The 2-D mode redraws itself when its tab differs from its last mode; when it is the
    // same one, its drawing is still there.
  }
}, true);

// Hooks for the end-to-end test (tests/e2e/editor-3d.mjs) and scripts in the console.
window.geomkit3d = {
  doc: () => clone(doc),
  drawn: () => drawn,
  degree: () => degree,
  proposal: () => proposal,
  selected: () => selected,
  project: (p) => view.project(p),
  view: () => view,
  frames,
  active: () => active,
  parseCsv,
  parseNpy,
  /** Opens a bezier_surface file in the surface tab, a heights grid in the heights tab
   * (app.js's Open uses it). */
  open: (m, name) => openModel(m, name),
  /** Hands the stage back to the 2-D tabs (app.js opening a file into one of them). */
  deactivate: () => { if (active) deactivate(); },
  idle: async () => {
    while (actions > 0 || scheduler.busy()) await new Promise((r) => setTimeout(r, 5));
  },
};
