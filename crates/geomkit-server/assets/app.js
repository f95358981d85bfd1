// The geomkit editor. The page holds the document (control points, reference points,
// options) and the view; every curve point, degree, error bound, comb and formula comes from
// the server's JSON API (docs/serve-api.md).

import { ApiError, download, get, post, put } from './api.js';
import { View, el } from './view.js';
import { INITIAL as POINTCALC, PointcalcMode } from './pointcalc.js';
import { bodyView } from './body3d.js';

const $ = (id) => document.getElementById(id);
const svg = $('canvas');
const view = new View(svg);
const clone = (x) => JSON.parse(JSON.stringify(x));

// ---------------------------------------------------------------------------------------
// The document (what undo / redo restore) and what the server computed from it.

const initial = {
  mode: 'bezier',
  // Nikulin's Example 2: a quintic of real degree 3.
  bezier: { points: [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]], weights: null },
  bspline: {
    points: [[0, 0], [2, 3], [5, 3.5], [7, 1], [10, 0.5], [12, 3], [14, 4]],
    end: 'not-a-knot',
    param: 'chord',
    closed: false,
    comb: true,
    combScale: 1,
  },
  body: { kind: 'cube' },
  pointcalc: POINTCALC,
};

let doc = clone(initial);
const history = { states: [clone(doc)], at: 0 };

/** What was drawn last: curve samples, polygon, reference points, comb, error band. */
let drawn = { curve: [], t: [], control: [], refs: [], comb: null, band: null, approx: null };
/** The degree report of the Bézier curve. */
let degree = null;
/** A proposed approximate reduction (not yet in the document). */
let proposal = null;
let syntax = 'maple';
let dragging = null;
/** The selected vertex of the Bézier curve (its weight is in the panel). */
let selected = 0;
/** The last weight edit: a run of wheel steps on one vertex is one undo step. */
let weightRun = null;
let filesAvailable = false;
let lastFormulaKey = '';
/** Frame the drawing once the server has answered (after a mode change or a file opened). */
let needFit = 'always';

/** User actions under way (an edit waiting for the server). */
let actions = 0;

/** `fn` as an event handler counted in `actions`. */
function act(fn) {
  return async (...a) => {
    actions++;
    try {
      await fn(...a);
    } finally {
      actions--;
    }
  };
}

// Hooks for the end-to-end test and for scripts in the console.
const frames = [];
window.geomkit = {
  doc: () => clone(doc),
  drawn: () => drawn,
  degree: () => degree,
  proposal: () => proposal,
  toScreen: (p) => view.toScreen(p),
  toWorld: (x, y) => view.toWorld(x, y),
  frames,
  busy: () => actions > 0 || scheduler.busy() || pointcalc.busy(),
  /** Resolves when no user action and no computation is under way. */
  idle: async () => {
    while (actions > 0 || scheduler.busy() || drawQueued || pointcalc.busy()) await new Promise((r) => setTimeout(r, 5));
  },
  setDoc: (d) => { doc = clone(d); commit(); syncControls(); needFit = 'always'; refresh(); },
  /** Opens a model file into its tab (the 3-D tabs' Open hands the 2-D ones over). */
  open: (m, name) => loadModel(m, name),
};

function model() {
  if (doc.mode === 'bezier') {
    const { points, weights } = doc.bezier;
    // With weights: the rational Bézier curve p = Σ w_i b_i P_i / Σ w_i b_i (BezierModel::Rational).
    return weights ? { type: 'bezier_curve', points, weights } : { type: 'bezier_curve', points };
  }
  if (doc.mode === 'pointcalc') return pointcalc.model();
  if (doc.mode === 'bspline') return drawn.model || null;
  return null;
}

// ---------------------------------------------------------------------------------------
// Undo / redo

function commit() {
  history.states.length = history.at + 1;
  history.states.push(clone(doc));
  history.at = history.states.length - 1;
  if (history.states.length > 500) { history.states.shift(); history.at--; }
  updateUndoButtons();
}

/** Restores the document of history entry `at`. */
function restore(at) {
  if (at < 0 || at >= history.states.length) return;
  history.at = at;
  doc = clone(history.states[at]);
  proposal = null;
  hideApprox();
  lastFormulaKey = '';
  syncControls();
  refresh();
  updateUndoButtons();
}

function undo() { restore(history.at - 1); }
function redo() { restore(history.at + 1); }

function updateUndoButtons() {
  $('undo').disabled = history.at === 0;
  $('redo').disabled = history.at >= history.states.length - 1;
}

// ---------------------------------------------------------------------------------------
// Status line

function status(text, isError = false) {
  const s = $('status');
  s.textContent = text;
  s.classList.toggle('error', isError);
  s.title = text;
}

function showError(e) {
  if (e instanceof ApiError) status(e.message, true);
  else status(String(e && e.message ? e.message : e), true);
}

// ---------------------------------------------------------------------------------------
// Requests: at most one computation in flight; edits made meanwhile are sent when it ends
// (so a drag redraws as fast as the server answers, and never shows a stale state last).

const scheduler = {
  inflight: false,
  pending: false,
  waiters: [],
  request() {
    this.pending = true;
    if (!this.inflight) this.pump();
  },
  async pump() {
    this.inflight = true;
    while (this.pending) {
      this.pending = false;
      try {
        await compute();
      } catch (e) {
        showError(e);
      }
    }
    this.inflight = false;
    const w = this.waiters.splice(0);
    w.forEach((f) => f());
  },
  busy() { return this.inflight || this.pending; },
  idle() {
    return this.busy() ? new Promise((r) => this.waiters.push(r)) : Promise.resolve();
  },
};

function refresh() { scheduler.request(); }

/** The point-calculus mode (pointcalc.js): its table lives in doc.pointcalc. */
const pointcalc = new PointcalcMode({ doc: () => doc, commit, status, showError, refresh });
window.geomkit.pointcalc = pointcalc;

function fmt(x, digits = 4) {
  if (x === null || x === undefined) return '–';
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e-3 && a < 1e5 ? String(+x.toPrecision(digits)) : x.toExponential(2);
}

async function compute() {
  if (doc.mode === 'bezier') await computeBezier();
  else if (doc.mode === 'bspline') await computeBspline();
  else if (doc.mode === 'pointcalc') await pointcalc.compute();
  else await computeBody();
  if (dragging) frames.push(performance.now());
  else {
    const fit = needFit;
    needFit = false;
    if (doc.mode !== 'body' && doc.mode !== 'pointcalc' && (fit === 'always' || (fit && !allVisible()))) {
      fitView();
      draw();
    }
    await computeFormula();
  }
}

async function computeBezier() {
  const m = model();
  const [samples, report] = await Promise.all([
    post('/api/samples', { model: m, samples: 400 }),
    post('/api/bezier/degree', { model: m }),
  ]);
  drawn = {
    curve: samples.points,
    t: samples.t,
    control: samples.control,
    refs: [],
    comb: null,
    band: proposal ? proposal.band : null,
    approx: proposal ? proposal.band.reduced : null,
  };
  degree = report;
  drawSoon();
  showDegree();
}

function combPerSpan(n) { return Math.max(1, Math.min(6, Math.ceil(1500 / Math.max(n, 1)))); }
function samplesPerSpan(n) { return Math.max(2, Math.min(16, Math.ceil(4000 / Math.max(n, 1)))); }

async function computeBspline() {
  const b = doc.bspline;
  const n = b.points.length;
  if (n < 2) {
    drawn = { curve: [], t: [], control: [], refs: b.points, comb: null, band: null, model: null };
    draw();
    $('bs-points').textContent = n;
    status('Click to add reference points (at least 2).');
    return;
  }
  const end = b.end === 'outer' ? { kind: 'outer', offset: 1 } : b.end;
  const request = {
    points: b.points,
    end,
    parametrization: b.param,
    closed: b.closed,
    samples_per_span: samplesPerSpan(n),
    comb: { per_span: b.comb ? combPerSpan(n) : 0 },
  };
  // Dragging a point of a long open curve: only the samples and comb near it (the server's
  // window; the rest moves by rounding only), spliced into the last full drawing. Released,
  // the whole curve again.
  const key = JSON.stringify([n, b.end, b.param, b.closed, b.comb]);
  if (dragging && dragging.index >= 0 && n > WINDOW_FROM && !b.closed && drawn.model && drawn.key === key) {
    request.window = { around: dragging.index };
    if (drawn.comb) request.comb.scale = drawn.comb.scale;
    const r = await post('/api/bspline/interpolate', request);
    if (r.window && spliceWindow(r)) {
      drawSoon();
      return;
    }
  }
  delete request.window;
  const r = await post('/api/bspline/interpolate', request);
  drawn = {
    key,
    curve: r.samples.points,
    t: r.samples.t,
    control: r.model.control_points,
    refs: b.points,
    comb: r.comb,
    band: null,
    model: r.model,
    parameters: r.parameters,
  };
  $('bs-points').textContent = n;
  $('bs-control').textContent = r.model.control_points.length;
  $('bs-kmax').textContent = r.comb ? fmt(r.comb.max_curvature) : '–';
  drawSoon();
  if (!dragging) status(`${r.what} through ${n} points.`);
}

/** Above this many reference points a drag asks the server for a window of the drawing. */
const WINDOW_FROM = 200;

/** Puts a window answer's samples and teeth into the drawing; false when they do not fit
 * (the drawing changed meanwhile). */
function spliceWindow(r) {
  const s = r.samples;
  if (drawn.curve.length !== s.total) return false;
  if (r.comb && (!drawn.comb || drawn.comb.tip.length !== r.comb.total)) return false;
  const put = (into, from, at) => { for (let i = 0; i < from.length; i++) into[at + i] = from[i]; };
  put(drawn.curve, s.points, s.first);
  const [a, b] = drawn.dirty || [0, 0];
  drawn.dirty = a === b ? [s.first, s.first + s.points.length] : [Math.min(a, s.first), Math.max(b, s.first + s.points.length)];
  put(drawn.t, s.t, s.first);
  if (r.comb) {
    const [c0, c1] = drawn.combDirty || [0, 0];
    const end = r.comb.first + r.comb.tip.length;
    drawn.combDirty = c0 === c1 ? [r.comb.first, end] : [Math.min(c0, r.comb.first), Math.max(c1, end)];
    put(drawn.comb.base, r.comb.base, r.comb.first);
    put(drawn.comb.tip, r.comb.tip, r.comb.first);
    put(drawn.comb.curvature, r.comb.curvature, r.comb.first);
    put(drawn.comb.t, r.comb.t, r.comb.first);
  }
  drawn.refs = doc.bspline.points;
  return true;
}

/** The body tab's source: one of Dolya's bodies, or a surface opened from a file. */
function bodySource() {
  if (doc.body.model) return { model: doc.body.model };
  const body = { kind: doc.body.kind };
  for (const p of BODY_PARAMS[doc.body.kind] || []) if (doc.body[p] !== undefined) body[p] = doc.body[p];
  return { body };
}

/** The parameters each body takes from the panel (the API's names). */
const BODY_PARAMS = {
  cone: ['height', 'radius'],
  cylinder: ['height', 'radius'],
  frustum: ['height', 'radius'],
  prism: ['height', 'radius', 'ngon'],
  pyramid: ['height', 'radius', 'ngon'],
};
const BODY_DEFAULTS = { height: 2, radius: 1, ngon: 6 };

/** The last /api/body/view answer and what it was for (a syntax change refetches only the
 * formula). */
let bodyAnswer = null;
let bodyKey = '';

async function computeBody() {
  const source = bodySource();
  const key = JSON.stringify(source);
  const fresh = key !== bodyKey;
  const [f, v] = await Promise.all([
    post('/api/formula', { ...source, format: syntax }),
    // 129 points per seam: a circle's rim stays round.
    fresh ? post('/api/body/view', { ...source, seam_samples: 129 }) : Promise.resolve(bodyAnswer),
  ]);
  if (fresh) {
    bodyAnswer = v;
    bodyKey = key;
    // The 3-D view: the mesh with the seams of the formula marked (body3d.js).
    bodyView.show(v, true);
  }
  showFormula(f);
  const counts = v.legend.map((l) => `${l.count} ${l.crease ? 'creases' : l.smoothness}`).join(', ');
  $('body-seams').textContent = v.seams.length ? counts : 'none';
  $('body-continuity').textContent = v.continuity
    ? (v.continuity.continuous ? 'yes' : `no: jump ${fmt(v.continuity.max_jump)}`)
    : '–';
  status(`${v.what}: one formula, ${f.op_count} operations; ${v.seams.length} seam${v.seams.length === 1 ? '' : 's'} marked on the surface.`);
}

/** The body tab's model file: the opened one, or the body's ruled surface. */
function bodyModel() {
  if (doc.body.model) return doc.body.model;
  return bodyAnswer && bodyKey === JSON.stringify(bodySource()) ? bodyAnswer.model : null;
}

async function computeFormula() {
  let request;
  if (doc.mode === 'body') return; // done with the body
  const m = model();
  if (!m) { formulaText = ''; $('formula').textContent = ''; $('formula-info').textContent = ''; return; }
  request = { model: m, format: syntax };
  const key = JSON.stringify(request);
  if (key === lastFormulaKey) return;
  lastFormulaKey = key;
  try {
    showFormula(await post('/api/formula', request));
  } catch (e) {
    $('formula').textContent = '';
    $('formula-info').textContent = e.message;
  }
}

/** The whole formula (the panel shows at most FORMULA_SHOWN characters of it). */
let formulaText = '';
const FORMULA_SHOWN = 20000;

function showFormula(f) {
  formulaText = f.formula;
  $('formula').textContent = f.formula.length > FORMULA_SHOWN
    ? `${f.formula.slice(0, FORMULA_SHOWN)}\n… (${f.formula.length} characters in all: Copy or Export copies the whole formula)`
    : f.formula;
  const parts = [`${f.op_count} operations`, `variables ${f.variables.join(', ')}`];
  if (f.continuity && f.continuity.statement) parts.push(f.continuity.statement);
  $('formula-info').textContent = parts.join(' · ');
}

function showDegree() {
  if (!degree) return;
  $('degree').textContent = degree.degree;
  $('real-degree').textContent = degree.real_degree;
  $('defect').textContent = degree.defect;
  $('residual').textContent = fmt(degree.residual, 2);
  $('deg-down').disabled = degree.degree === 0;
  showWeight();
  if (!dragging && !proposal) status(`${doc.bezier.weights ? 'Rational ' : ''}Bézier curve of degree ${degree.degree}, real degree ${degree.real_degree} (defect ${degree.defect}).`);
}

// ---------------------------------------------------------------------------------------
// Drawing

/** Redraws at the next animation frame (several requests in one frame draw once). */
let drawQueued = false;
/** Many points on the canvas layer (thousands of SVG shapes would make every frame slow;
 * hit-testing is the page's own, so the canvas needs no events). */
const layer = $('points-layer');
function drawPointsLayer(pts, r) {
  const [w, h] = view.size();
  const ratio = window.devicePixelRatio || 1;
  if (layer.width !== Math.round(w * ratio) || layer.height !== Math.round(h * ratio)) {
    layer.width = Math.round(w * ratio);
    layer.height = Math.round(h * ratio);
  }
  const g = layer.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  if (!pts.length) {
    if (layer.dataset.drawn) { g.clearRect(0, 0, w, h); delete layer.dataset.drawn; }
    return;
  }
  g.clearRect(0, 0, w, h);
  layer.dataset.drawn = '1';
  // The colour of the stylesheet, read once (getComputedStyle in every frame recomputes style).
  if (!refColour) refColour = getComputedStyle(document.documentElement).getPropertyValue('--ref').trim() || '#e0731c';
  const moving = dragging && dragging.index >= 0 ? dragging.index : -1;
  if (moving < 0) {
    dragLayer = null;
    dots(g, pts, -1, r, w, h);
    return;
  }
  // While one point is dragged the others stay: they are drawn once into an image.
  const key = `${view.key()}|${moving}|${pts.length}`;
  if (!dragLayer || dragLayer.key !== key) {
    const image = document.createElement('canvas');
    image.width = layer.width;
    image.height = layer.height;
    const ig = image.getContext('2d');
    ig.setTransform(ratio, 0, 0, ratio, 0, 0);
    dots(ig, pts, moving, r, w, h);
    dragLayer = { key, image };
  }
  g.setTransform(1, 0, 0, 1, 0, 0);
  g.drawImage(dragLayer.image, 0, 0);
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  dots(g, [pts[moving]], -1, r, w, h);
}

/** The other points while one is dragged, as an image (see drawPointsLayer). */
let dragLayer = null;

/** Fills dots of radius r - 1 at the points (but point `skip`) inside the w × h view. */
function dots(g, pts, skip, r, w, h) {
  g.fillStyle = refColour;
  g.beginPath();
  for (let i = 0; i < pts.length; i++) {
    if (i === skip) continue;
    const [x, y] = view.toScreen(pts[i]);
    if (x < -r || y < -r || x > w + r || y > h + r) continue;
    g.moveTo(x + r - 1, y);
    g.arc(x, y, r - 1, 0, 2 * Math.PI);
  }
  g.fill();
}

/** Above this many points, they are drawn on the canvas layer. */
const MANY_POINTS = 300;

/** What the queued frame redraws: 'all', or only 'vertices' (a dragged point before the
 * server's curve arrives). */
let drawWhat = 'vertices';

function drawSoon(what = 'all') {
  if (what === 'all') drawWhat = 'all';
  if (drawQueued) return;
  drawQueued = true;
  requestAnimationFrame(() => {
    drawQueued = false;
    const all = drawWhat === 'all';
    drawWhat = 'vertices';
    if (all) draw();
    else drawVertices();
  });
}

/** The drawing's SVG paths, kept from frame to frame (in this order, below the vertices):
 * a frame sets only the `d` attributes that changed, so a drag of one point of a long
 * B-spline does not rebuild the grid, the legend or the document's elements. */
const SLOTS = [
  ['grid', 'grid-line', null],
  ['axes', 'axis-line', null],
  ['band', 'band', 'band-path'],
  ['comb', 'comb', null],
  ['combEdge', 'comb-edge', null],
  ['polygon', 'polygon', 'polygon-path'],
  ['curve', 'curve', 'curve-path'],
  ['approx', 'curve approx', 'approx-path'],
];
const slots = new Map(SLOTS.map(([name, cls, id]) => {
  const e = el('path', id ? { class: cls, id } : { class: cls });
  return [name, e];
}));
const vertexGroup = el('g', { class: 'vertices' });
svg.append(...slots.values(), vertexGroup);
let legendKey = '';
/** The formatted points of the drawn curve (only a drag's window is formatted again). */
const curveCache = {};
let refColour = null;

/** Sets path `name` to `d`, or takes it out of the drawing when `d` is null. */
function setSlot(name, d) {
  const e = slots.get(name);
  if (d === null) {
    if (e.isConnected) e.remove();
    return;
  }
  if (e.getAttribute('d') !== d) e.setAttribute('d', d);
  if (!e.isConnected) {
    // Before the next slot in the drawing (the order of SLOTS), or the vertices.
    const at = SLOTS.findIndex(([n]) => n === name);
    const next = SLOTS.slice(at + 1).map(([n]) => slots.get(n)).find((x) => x.isConnected);
    svg.insertBefore(e, next || vertexGroup);
  }
}

function draw() {
  if (!vertexGroup.isConnected) svg.append(...slots.values(), vertexGroup);
  const [w, h] = view.size();
  const box = `0 0 ${w} ${h}`;
  if (svg.getAttribute('viewBox') !== box) svg.setAttribute('viewBox', box);
  drawGrid(w, h);
  if (drawn.band && drawn.band.upper) {
    const ring = drawn.band.upper.concat(drawn.band.lower.slice().reverse());
    setSlot('band', view.pathData(ring, true));
  } else setSlot('band', null);
  if (drawn.comb && doc.mode === 'bspline' && doc.bspline.comb) {
    const dirty = drawn.combDirty || [0, Infinity];
    drawn.combDirty = [0, 0];
    const [teeth, edge] = combPaths(dirty);
    setSlot('comb', teeth);
    setSlot('combEdge', edge);
  } else {
    setSlot('comb', null);
    setSlot('combEdge', null);
  }
  setSlot('polygon', doc.mode === 'bezier' && drawn.control ? view.pathData(drawn.control) : null);
  const dirty = drawn.dirty || [0, Infinity];
  drawn.dirty = [0, 0];
  setSlot('curve', view.pathDataCached(drawn.curve, curveCache, dirty[0], dirty[1]));
  setSlot('approx', drawn.approx ? view.pathData(drawn.approx) : null);
  drawVertices();
  drawLegend();
}

/** The formatted teeth and tips of the comb (a drag formats its window only). */
const combCache = { key: '', tips: [], teeth: [], edge: {} };

/** The comb's teeth (at most about 600 drawn) and the line of their tips, as path data;
 * the teeth `dirty[0]..dirty[1]` changed since the last call. */
function combPaths(dirty) {
  const k = doc.bspline.combScale;
  const { base, tip } = drawn.comb;
  const key = `${view.key()}|${k}|${tip.length}`;
  let [from, to] = dirty;
  if (combCache.key !== key) {
    combCache.key = key;
    combCache.tips = new Array(tip.length);
    combCache.teeth = new Array(tip.length).fill('');
    combCache.edge = {};
    from = 0;
    to = tip.length;
  }
  const { tips, teeth } = combCache;
  const stride = Math.max(1, Math.ceil(tip.length / 600));
  for (let i = Math.max(0, from); i < Math.min(to, tip.length); i++) {
    const t = tip[i], b = base[i];
    tips[i] = [b[0] + (t[0] - b[0]) * k, b[1] + (t[1] - b[1]) * k];
    if (i % stride === 0) {
      const [x0, y0] = view.toScreen(b);
      const [x1, y1] = view.toScreen(tips[i]);
      teeth[i] = `M${x0.toFixed(1)} ${y0.toFixed(1)}L${x1.toFixed(1)} ${y1.toFixed(1)}`;
    }
  }
  return [teeth.join(''), view.pathDataCached(tips, combCache.edge, from, to)];
}

/** The control or reference points: SVG circles (few) or the canvas layer (many). */
function drawVertices() {
  const pts = doc.mode === 'bezier' ? doc.bezier.points : doc.mode === 'bspline' ? doc.bspline.points : [];
  const cls = doc.mode === 'bezier' ? 'vertex' : 'ref';
  const r = doc.mode === 'bezier' ? 6 : 5;
  const shapes = [];
  if (pts.length <= MANY_POINTS) {
    pts.forEach((p, i) => {
      const [x, y] = view.toScreen(p);
      const c = el('circle', { class: cls, cx: x, cy: y, r, 'data-index': i });
      if (dragging && dragging.index === i) c.classList.add('active');
      if (doc.mode === 'bezier' && i === selected) c.classList.add('selected');
      shapes.push(c);
      if (doc.mode === 'bezier' && pts.length <= 40) {
        const label = el('text', { class: 'label', x: x + 9, y: y - 9 });
        const w = doc.bezier.weights ? doc.bezier.weights[i] : 1;
        label.textContent = Math.abs(w - 1) < 1e-9 ? `P${i}` : `P${i} w=${+w.toPrecision(3)}`;
        shapes.push(label);
      }
    });
  }
  if (shapes.length || vertexGroup.firstChild) vertexGroup.replaceChildren(...shapes);
  drawPointsLayer(pts.length > MANY_POINTS ? pts : [], r);
}

function drawGrid(w, h) {
  const step = view.gridStep();
  const [x0, y1] = view.toWorld(0, 0);
  const [x1, y0] = view.toWorld(w, h);
  let d = '';
  for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
    const [sx] = view.toScreen([x, 0]);
    d += `M${sx.toFixed(1)} 0V${h}`;
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
    const [, sy] = view.toScreen([0, y]);
    d += `M0 ${sy.toFixed(1)}H${w}`;
  }
  setSlot('grid', d);
  const [ax, ay] = view.toScreen([0, 0]);
  setSlot('axes', `M${ax.toFixed(1)} 0V${h}M0 ${ay.toFixed(1)}H${w}`);
}

function drawLegend() {
  const items = [];
  if (doc.mode === 'bezier') {
    items.push(['l-curve', 'curve'], ['l-poly', 'control polygon']);
    if (drawn.band) items.push(['l-band', 'error band (± L∞ bound)']);
  } else if (doc.mode === 'bspline') {
    items.push(['l-curve', 'B-spline'], ['l-ref', 'reference points']);
    if (doc.bspline.comb) items.push(['l-comb', 'curvature comb']);
  }
  const key = JSON.stringify(items) + doc.mode;
  if (key === legendKey) return;
  legendKey = key;
  $('legend').replaceChildren(...items.map(([c, t]) => {
    const s = document.createElement('span');
    s.className = c;
    s.textContent = t;
    return s;
  }));
  $('legend').hidden = items.length === 0 || doc.mode === 'body' || doc.mode === 'pointcalc';
}

function fitView() {
  const pts = doc.mode === 'bezier' ? doc.bezier.points : doc.bspline.points;
  let all = pts.concat(drawn.curve || []);
  if (drawn.comb && doc.mode === 'bspline' && doc.bspline.comb) all = all.concat(drawn.comb.tip);
  view.fit(all.length ? all : [[-1, -1], [1, 1]]);
}

/** Whether every control or reference point is inside the view. */
function allVisible() {
  const [w, h] = view.size();
  return points().every((p) => {
    const [x, y] = view.toScreen(p);
    return x >= 0 && x <= w && y >= 0 && y <= h;
  });
}

// ---------------------------------------------------------------------------------------
// Pointer interaction: drag a point, click to add, Alt+click / right-click to remove,
// drag the background to pan, wheel to zoom.

function points() { return doc.mode === 'bezier' ? doc.bezier.points : doc.bspline.points; }

function hit(sx, sy) {
  const pts = points();
  let best = -1, bestD = 10;
  pts.forEach((p, i) => {
    const [x, y] = view.toScreen(p);
    const d = Math.hypot(x - sx, y - sy);
    if (d <= bestD) { bestD = d; best = i; }
  });
  return best;
}

svg.addEventListener('pointerdown', (ev) => {
  if (doc.mode === 'body') return;
  view.measure();
  const [sx, sy] = view.eventPoint(ev);
  const i = hit(sx, sy);
  try {
    svg.setPointerCapture(ev.pointerId);
  } catch {
    // A synthetic event without an active pointer: no capture needed.
  }
  if (ev.button === 2 || (ev.button === 0 && ev.altKey)) {
    if (i >= 0) removePoint(i);
    return;
  }
  if (ev.button !== 0) return;
  // Shift+drag on a vertex of a Bézier curve: its weight (up: heavier), not its place.
  const weight = ev.shiftKey && doc.mode === 'bezier' && i >= 0;
  if (weight && !doc.bezier.weights) doc.bezier.weights = doc.bezier.points.map(() => 1);
  if (i >= 0 && doc.mode === 'bezier') { selected = i; showWeight(); }
  dragging = { index: i, start: [sx, sy], last: [sx, sy], moved: false, weight, w0: weight ? doc.bezier.weights[i] : 1 };
});

svg.addEventListener('pointermove', (ev) => {
  if (!dragging) return;
  const [sx, sy] = view.eventPoint(ev);
  if (Math.hypot(sx - dragging.start[0], sy - dragging.start[1]) > 3) dragging.moved = true;
  if (!dragging.moved) return;
  if (dragging.weight) {
    // Up by 100 px: the weight times e.
    doc.bezier.weights[dragging.index] = clampWeight(dragging.w0 * Math.exp((dragging.start[1] - sy) / 100));
    showWeight();
    if (proposal) { proposal = null; hideApprox(); }
    refresh();
  } else if (dragging.index >= 0) {
    points()[dragging.index] = view.toWorld(sx, sy);
    if (proposal) { proposal = null; hideApprox(); drawSoon(); }
    // The point follows the mouse now; the curve when the server answers (compute draws).
    drawSoon('vertices');
    refresh();
  } else {
    view.panBy(sx - dragging.last[0], sy - dragging.last[1]);
    drawSoon();
  }
  dragging.last = [sx, sy];
});

svg.addEventListener('pointerup', (ev) => {
  if (!dragging) return;
  const d = dragging;
  dragging = null;
  const [sx, sy] = view.eventPoint(ev);
  if (!d.moved && d.index >= 0) {
    draw();
  } else if (d.moved && d.index >= 0) {
    commit();
    lastFormulaKey = '';
    refresh();
  } else if (!d.moved && d.index < 0) {
    addPoint(view.toWorld(sx, sy), sx, sy);
  } else {
    draw();
  }
});

svg.addEventListener('contextmenu', (ev) => ev.preventDefault());

svg.addEventListener('wheel', (ev) => {
  ev.preventDefault();
  const [sx, sy] = view.eventPoint(ev);
  // The wheel over a vertex of a Bézier curve: its weight (up: heavier).
  const on = doc.mode === 'bezier' ? hit(sx, sy) : -1;
  if (on >= 0) {
    selected = on;
    setWeight(on, weightOf(on) * Math.exp(-ev.deltaY * 0.002), 'wheel');
    return;
  }
  view.zoomAt(sx, sy, Math.exp(-ev.deltaY * 0.0015));
  drawSoon();
}, { passive: false });

new ResizeObserver(() => { view.measure(); draw(); }).observe(svg);
// The drawing's place on the page moves when the page scrolls (narrow windows).
window.addEventListener('scroll', () => view.measure(), { passive: true });

/** Distance from screen point (px, py) to segment a-b and the segment parameter. */
function segmentDistance(px, py, a, b) {
  const [ax, ay] = view.toScreen(a);
  const [bx, by] = view.toScreen(b);
  const dx = bx - ax, dy = by - ay;
  const len2 = dx * dx + dy * dy;
  const s = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0;
  const c = Math.max(0, Math.min(1, s));
  return [Math.hypot(ax + c * dx - px, ay + c * dy - py), s];
}

const addPoint = act(async (p, sx, sy) => {
  try {
    if (doc.mode === 'bezier') {
      const pts = doc.bezier.points;
      let index = pts.length;
      const rational = !!doc.bezier.weights;
      if (pts.length >= 2) {
        let best = Infinity;
        for (let i = 0; i + 1 < pts.length; i++) {
          const [d, s] = segmentDistance(sx, sy, pts[i], pts[i + 1]);
          if (d < best) {
            best = d;
            index = s <= 0 && i === 0 ? 0 : s >= 1 && i === pts.length - 2 ? pts.length : i + 1;
          }
        }
      }
      proposal = null;
      hideApprox();
      if (rational) {
        // A rational curve: the vertex goes in with weight 1 (the server draws the result).
        pts.splice(index, 0, p);
        doc.bezier.weights.splice(index, 0, 1);
        selected = index;
        commit();
        status(`Inserted vertex ${index} with weight 1: degree ${pts.length - 1}.`);
        lastFormulaKey = '';
        refresh();
        return;
      }
      const r = await post('/api/bezier/edit', { model: model(), insert: { index, point: p } });
      doc.bezier.points = r.model.points;
      commit();
      status(`Inserted vertex ${index}: degree ${r.degree.degree}; the curve moved by up to ${fmt(r.deviation.upper_bound)} (found ${fmt(r.deviation.max_found)} at t = ${fmt(r.deviation.at, 3)}).`);
    } else {
      const pts = doc.bspline.points;
      let index = pts.length;
      // Near the curve: insert between the reference points around that parameter.
      if (drawn.curve.length && drawn.parameters) {
        let best = Infinity, at = -1;
        drawn.curve.forEach((q, i) => {
          const [x, y] = view.toScreen(q);
          const d = Math.hypot(x - sx, y - sy);
          if (d < best) { best = d; at = i; }
        });
        if (best < 8) {
          const t = drawn.t[at];
          index = drawn.parameters.findIndex((u) => u > t);
          if (index < 0) index = pts.length;
        }
      }
      pts.splice(index, 0, p);
      commit();
    }
    lastFormulaKey = '';
    refresh();
  } catch (e) {
    showError(e);
  }
});

const removePoint = act(async (i) => {
  try {
    if (doc.mode === 'bezier') {
      if (doc.bezier.points.length <= 1) { status('A Bézier curve keeps at least one vertex.', true); return; }
      if (doc.bezier.weights) {
        proposal = null;
        hideApprox();
        doc.bezier.points.splice(i, 1);
        doc.bezier.weights.splice(i, 1);
        selected = Math.min(selected, doc.bezier.points.length - 1);
        status(`Removed vertex ${i}: degree ${doc.bezier.points.length - 1}.`);
        commit();
        lastFormulaKey = '';
        refresh();
        return;
      }
      const r = await post('/api/bezier/edit', { model: model(), remove: i });
      proposal = null;
      hideApprox();
      doc.bezier.points = r.model.points;
      status(`Removed vertex ${i}: degree ${r.degree.degree}; the curve moved by up to ${fmt(r.deviation.upper_bound)}.`);
    } else {
      doc.bspline.points.splice(i, 1);
    }
    commit();
    lastFormulaKey = '';
    refresh();
  } catch (e) {
    showError(e);
  }
});

// ---------------------------------------------------------------------------------------
// Rational weights: the selected vertex's weight (a field, Shift+drag, the wheel, W / Shift+W)


function weightOf(i) { return doc.bezier.weights ? doc.bezier.weights[i] : 1; }
function clampWeight(w) { return Math.min(1e6, Math.max(1e-6, w)); }

function showWeight() {
  const n = doc.bezier.points.length;
  if (selected >= n) selected = n - 1;
  $('weight-name').textContent = `P${selected}`;
  if (document.activeElement !== $('weight')) $('weight').value = +weightOf(selected).toPrecision(6);
  $('weight-reset').disabled = !doc.bezier.weights;
  $('rational-kind').textContent = doc.bezier.weights ? 'rational' : 'polynomial (all weights 1)';
}

/** Sets the weight of vertex i (> 0); `how` groups wheel steps into one undo step. */
function setWeight(i, w, how = 'field') {
  if (!(Number.isFinite(w) && w > 0)) {
    status(`The weight of P${i} must be a number > 0 (got ${w}).`, true);
    showWeight();
    return;
  }
  if (!doc.bezier.weights) doc.bezier.weights = doc.bezier.points.map(() => 1);
  doc.bezier.weights[i] = clampWeight(w);
  if (proposal) { proposal = null; hideApprox(); }
  const run = `${how}:${i}`;
  if (how !== 'wheel' || weightRun !== run) commit();
  else history.states[history.at] = clone(doc);
  weightRun = how === 'wheel' ? run : null;
  showWeight();
  lastFormulaKey = '';
  refresh();
}

$('weight').addEventListener('change', () => setWeight(selected, Number($('weight').value)));
$('weight-reset').addEventListener('click', () => {
  doc.bezier.weights = null;
  proposal = null;
  hideApprox();
  commit();
  showWeight();
  lastFormulaKey = '';
  refresh();
  status('All weights 1: a polynomial Bézier curve again.');
});

// ---------------------------------------------------------------------------------------
// Degree controls

/** Takes the API's answer of an exact change of degree as the new curve (one undo step). */
async function takeDegreeChange(r, message) {
  proposal = null;
  hideApprox();
  doc.bezier.points = r.model.points;
  doc.bezier.weights = r.model.weights || null;
  selected = Math.min(selected, r.model.points.length - 1);
  commit();
  lastFormulaKey = '';
  needFit = 'if-hidden';
  refresh();
  await scheduler.idle();
  status(message);
}

$('deg-up').addEventListener('click', act(async () => {
  try {
    const n = doc.bezier.points.length - 1;
    const r = await post('/api/bezier/elevate', { model: model(), to: n + 1 });
    await takeDegreeChange(r, `Elevated to degree ${n + 1}: the same curve, one more control point${doc.bezier.weights ? ' and weight' : ''}.`);
  } catch (e) { showError(e); }
}));

$('deg-down').addEventListener('click', act(async () => {
  const n = doc.bezier.points.length - 1;
  if (n === 0) return;
  try {
    const r = await post('/api/bezier/reduce', { model: model(), to: n - 1 });
    await takeDegreeChange(r, `Reduced exactly to degree ${n - 1}: the same curve.`);
  } catch (e) {
    if (e instanceof ApiError && e.body.reason === 'real_degree') {
      showRefusal(e, n - 1);
      if (doc.bezier.weights) {
        $('refusal').textContent = `Cannot reduce exactly to degree ${n - 1}: the real degree of the rational curve is ${e.body.real_degree}. The best approximation of lower degree is for polynomial curves (all weights 1).`;
        status($('refusal').textContent, true);
        return;
      }
      try {
        await propose(n - 1);
      } catch (e2) { showError(e2); }
    } else showError(e);
  }
}));

function showRefusal(e, to) {
  const r = $('refusal');
  r.hidden = false;
  r.textContent = `Cannot reduce exactly to degree ${to}: the real degree is ${e.body.real_degree} (defect ${e.body.defect}). The best approximation is shown in red.`;
}

async function propose(to) {
  const r = await post('/api/bezier/approximate', { model: model(), to, norm: $('approx-norm').value, samples: 300 });
  proposal = { to, ...r };
  $('approx').hidden = false;
  $('approx-to').textContent = to;
  $('approx-l2').textContent = fmt(r.l2_error);
  $('approx-linf').textContent = fmt(r.linf_bound);
  $('approx-found').textContent = `${fmt(r.linf_found)} at t = ${fmt(r.linf_at, 3)}`;
  status(`Approximation of degree ${to}: L2 error ${fmt(r.l2_error)}, the curves are at most ${fmt(r.linf_bound)} apart.`);
  drawn.band = r.band;
  drawn.approx = r.band.reduced;
  draw();
}

function hideApprox() {
  $('approx').hidden = true;
  $('refusal').hidden = true;
  drawn.band = null;
  drawn.approx = null;
}

$('approx-norm').addEventListener('change', () => { if (proposal) propose(proposal.to).catch(showError); });
$('approx-accept').addEventListener('click', () => {
  if (!proposal) return;
  doc.bezier.points = proposal.model.points;
  doc.bezier.weights = proposal.model.weights || null;
  proposal = null;
  hideApprox();
  commit();
  lastFormulaKey = '';
  refresh();
});
$('approx-cancel').addEventListener('click', () => { proposal = null; hideApprox(); draw(); showDegree(); });

// ---------------------------------------------------------------------------------------
// B-spline and body options

function syncControls() {
  const b = doc.bspline;
  $('end').value = b.end;
  $('param').value = b.param;
  $('closed').checked = b.closed;
  $('end').disabled = b.closed;
  $('comb').checked = b.comb;
  $('comb-scale').value = b.combScale;
  syncBodyKind();
  pointcalc.sync();
  setMode(doc.mode, false);
}

for (const [id, key, prop] of [['end', 'end', 'value'], ['param', 'param', 'value'], ['closed', 'closed', 'checked'], ['comb', 'comb', 'checked']]) {
  $(id).addEventListener('change', () => {
    doc.bspline[key] = $(id)[prop];
    $('end').disabled = doc.bspline.closed;
    commit();
    lastFormulaKey = '';
    refresh();
  });
}
$('comb-scale').addEventListener('input', () => { doc.bspline.combScale = +$('comb-scale').value; draw(); });
$('comb-scale').addEventListener('change', () => commit());
$('body-kind').addEventListener('change', () => {
  if ($('body-kind').value === 'file') return;
  const { height, radius, ngon } = doc.body;
  doc.body = { kind: $('body-kind').value, height, radius, ngon };
  syncBodyKind();
  commit();
  refresh();
});

/** The kind selector, with an entry for a surface opened from a file. */
function syncBodyKind() {
  const sel = $('body-kind');
  let opt = sel.querySelector('option[value="file"]');
  if (doc.body.model) {
    if (!opt) {
      opt = document.createElement('option');
      opt.value = 'file';
      sel.appendChild(opt);
    }
    opt.textContent = `file: ${doc.body.name || 'model'}`;
  } else if (opt) {
    opt.remove();
  }
  sel.value = doc.body.model ? 'file' : doc.body.kind;
  const takes = doc.body.model ? [] : BODY_PARAMS[doc.body.kind] || [];
  for (const p of ['height', 'radius', 'ngon']) {
    const input = $(`body-${p}`);
    input.disabled = !takes.includes(p);
    input.value = doc.body[p] ?? BODY_DEFAULTS[p];
  }
}

for (const p of ['height', 'radius', 'ngon']) {
  $(`body-${p}`).addEventListener('change', () => {
    const x = +$(`body-${p}`).value;
    if (!(Number.isFinite(x) && x > 0)) { status(`The ${p} must be a number > 0.`, true); syncBodyKind(); return; }
    doc.body[p] = p === 'ngon' ? Math.round(x) : x;
    commit();
    refresh();
  });
}

function setMode(mode, record = true) {
  const changed = doc.mode !== mode;
  doc.mode = mode;
  for (const b of document.querySelectorAll('.tabs button')) b.setAttribute('aria-selected', String(b.dataset.mode === mode));
  $('bezier-panel').hidden = mode !== 'bezier';
  $('bspline-panel').hidden = mode !== 'bspline';
  $('body-panel').hidden = mode !== 'body';
  const pc = mode === 'pointcalc';
  for (const id of ['pointcalc-panel', 'pc-result-card']) $(id).hidden = !pc;
  $('pc-plot').toggleAttribute('hidden', !pc); // an SVG element: no .hidden property
  $('pc-slice-card').hidden = !pc || doc.pointcalc.factors.length <= 2;
  $('picture').hidden = true;
  document.querySelector('main').classList.toggle('mode-body', mode === 'body');
  const flat = mode === 'body' || pc;
  layer.hidden = flat;
  svg.style.visibility = flat ? 'hidden' : 'visible';
  $('fit').hidden = flat;
  $('legend').hidden = flat;
  $('hint').textContent = flat ? '' : 'Wheel: zoom · drag the background: pan · F: fit · ?: shortcuts';
  if (changed) {
    proposal = null;
    hideApprox();
    drawn = { curve: [], t: [], control: [], refs: [], comb: null, band: null };
    lastFormulaKey = '';
    if (record) commit();
    needFit = 'always';
    refresh();
  }
}

for (const b of document.querySelectorAll('.tabs button')) b.addEventListener('click', () => setMode(b.dataset.mode));

// ---------------------------------------------------------------------------------------
// Formula panel

async function initSyntaxes() {
  const v = await get('/api/version');
  filesAvailable = v.files;
  const sel = $('syntax');
  for (const f of v.formats) {
    const o = document.createElement('option');
    o.value = f;
    o.textContent = f;
    sel.appendChild(o);
  }
  sel.value = syntax;
}

$('syntax').addEventListener('change', () => { syntax = $('syntax').value; lastFormulaKey = ''; refresh(); });
$('copy').addEventListener('click', async () => {
  const text = formulaText;
  try {
    await navigator.clipboard.writeText(text);
    status('Formula copied.');
  } catch {
    const r = document.createRange();
    r.selectNodeContents($('formula'));
    const s = getSelection();
    s.removeAllRanges();
    s.addRange(r);
    document.execCommand('copy');
    status('Formula selected and copied (the part shown).');
  }
});

// ---------------------------------------------------------------------------------------
// Open, save, export

function currentModelOrBody() {
  if (doc.mode === 'body') return bodyModel();
  return model();
}

/** Model files the body tab opens. */
const BODY_TYPES = ['composite_surface', 'composite_explicit', 'ruled', 'bspline_surface', 'formula'];

/** A heights grid as the heights tab saves it: a B-spline surface in R^1 with its grid. */
function isHeights(m) {
  return m.type === 'bspline_surface' && Array.isArray(m.net) && m.net[0] && m.net[0][0] && m.net[0][0].length === 1
    && Array.isArray(m.parameters_u) && Array.isArray(m.parameters_v);
}

/** Whether two numbers' lists (nested) agree within rounding. */
function sameNumbers(a, b) {
  const flat = (x) => (Array.isArray(x) ? x.flatMap(flat) : [x]);
  const [p, q] = [flat(a ?? []), flat(b ?? [])];
  const scale = Math.max(1, ...p.map(Math.abs));
  return p.length === q.length && p.every((v, i) => Math.abs(v - q[i]) <= 1e-9 * scale);
}

/** The B-spline tab's options (end condition, parametrization, closed) that interpolate
 * `points` into the curve of file `m`, the current ones tried first; null if none does. */
async function bsplineOptionsOf(m, points) {
  const b = doc.bspline;
  const ends = ['not-a-knot', 'natural', 'clamped', 'bessel', 'repeat', 'outer'];
  const params = ['chord', 'centripetal', 'uniform'];
  const tries = [{ end: b.end, param: b.param, closed: b.closed }];
  for (const param of params) tries.push({ end: b.end, param, closed: true });
  for (const end of ends) for (const param of params) tries.push({ end, param, closed: false });
  for (const t of tries) {
    const end = t.end === 'outer' ? { kind: 'outer', offset: 1 } : t.end;
    let r;
    try {
      r = await post('/api/bspline/interpolate', { points, end, parametrization: t.param, closed: t.closed, samples_per_span: 1, comb: { per_span: 0 } });
    } catch { continue; }
    if (sameNumbers(r.model.knots, m.knots) && sameNumbers(r.model.control_points, m.control_points)) return t;
  }
  return null;
}

async function loadModel(m, name) {
  if (m.type === 'bezier_curve') {
    doc.mode = 'bezier';
    doc.bezier.points = m.points.map((p) => [p[0], p[1] ?? 0]);
    doc.bezier.weights = m.weights ? [...m.weights] : null;
    selected = 0;
  } else if (m.type === 'bspline_curve' && m.parameters) {
    // Its reference points: the curve at the parameters of its points.
    const s = await post('/api/samples', { model: m, samples: 2 });
    doc.mode = 'bspline';
    doc.bspline.points = s.references.map((r) => [r.point[0], r.point[1] ?? 0]);
    // Its options: those whose interpolant through the points is this curve.
    const found = await bsplineOptionsOf(m, doc.bspline.points);
    if (found) Object.assign(doc.bspline, found);
    else status(`${name}: not made with the tab's options; re-interpolated with the current ones`, true);
  } else if (m.type === 'pointcalc-model') {
    doc.mode = 'pointcalc';
    const dim = pointcalc.load(m);
    if (dim > 1) status(`${name}: ${dim} responses; the table edits the first`);
  } else if ((m.type === 'bezier_surface' || isHeights(m)) && window.geomkit3d) {
    return window.geomkit3d.open(m, name); // the 3-D tabs (surface.js)
  } else if (BODY_TYPES.includes(m.type)) {
    // Composite, ruled and B-spline surfaces: the body tab, in 3-D with their seams.
    doc.mode = 'body';
    doc.body = { kind: 'file', model: m, name };
  } else {
    throw new Error(`${name}: the editor opens Bézier and B-spline curves, point-calculus models, Bézier surfaces, heights grids and composite, ruled or B-spline surfaces (this is a ${m.type})`);
  }
  window.geomkit3d?.deactivate();
  proposal = null;
  hideApprox();
  commit();
  syncControls();
  needFit = 'always';
  lastFormulaKey = '';
  refresh();
  status(`Opened ${name}.`);
}

$('open').addEventListener('click', async () => {
  const list = $('file-list');
  list.replaceChildren();
  if (filesAvailable) {
    try {
      const { files } = await get('/api/files');
      if (!files.length) list.innerHTML = '<li class="empty">No .json files in the folder.</li>';
      for (const f of files) {
        const li = document.createElement('li');
        const b = document.createElement('button');
        b.type = 'button';
        b.textContent = f.name;
        b.addEventListener('click', act(async () => {
          $('open-dialog').close();
          try {
            const r = await get(`/api/files/${encodeURIComponent(f.name)}`);
            await loadModel(r.model, f.name);
          } catch (e) { showError(e); }
        }));
        li.appendChild(b);
        list.appendChild(li);
      }
    } catch (e) { showError(e); }
  } else {
    list.innerHTML = '<li class="empty">Start the server with --dir FOLDER to open its files here.</li>';
  }
  $('open-dialog').showModal();
});

$('open-local').addEventListener('click', (ev) => { ev.preventDefault(); $('open-dialog').close(); $('file-input').click(); });
$('file-input').addEventListener('change', async () => {
  const f = $('file-input').files[0];
  if (!f) return;
  try {
    await loadModel(JSON.parse(await f.text()), f.name);
  } catch (e) { showError(e); }
  $('file-input').value = '';
});

async function save() {
  const m = currentModelOrBody();
  if (!m) { status('Nothing to save yet: wait for the drawing.', true); return; }
  try {
    if (filesAvailable) {
      const suggested = doc.mode === 'body' ? (doc.body.name || `${doc.body.kind}.json`) : `${doc.mode}.json`;
      const name = prompt('Save as (a .json name in the server\'s folder):', suggested);
      if (!name) return;
      const r = await put(`/api/files/${encodeURIComponent(name)}`, { model: m });
      status(`Saved ${r.name} (${r.what}, ${r.bytes} bytes).`);
    } else {
      download(await post('/api/export', { model: m, format: 'json' }), 'model.json');
      status('Downloaded model.json (start the server with --dir FOLDER to save into a folder).');
    }
  } catch (e) { showError(e); }
}
$('save').addEventListener('click', save);

$('export').addEventListener('change', async () => {
  const format = $('export').value;
  $('export').value = '';
  if (!format) return;
  try {
    if (doc.mode === 'body' && format === 'formula') {
      download(new Blob([formulaText], { type: 'text/plain' }), `${doc.body.kind}.txt`);
      status(`Exported ${doc.body.kind}.txt (${formulaText.length} characters).`);
      return;
    }
    const m = currentModelOrBody();
    if (!m) { status('Nothing to export yet: wait for the drawing.', true); return; }
    const blob = await post('/api/export', { model: m, format, syntax });
    download(blob, `model.${format === 'formula' ? 'txt' : format}`);
    status(`Exported model.${format === 'formula' ? 'txt' : format}.`);
  } catch (e) { showError(e); }
});

// ---------------------------------------------------------------------------------------
// Keyboard

/** Every shortcut: [keys, what, mode or null for all, action]. The help overlay (?) lists them. */
const SHORTCUTS = [
  ['Ctrl+Z', 'undo', null, () => undo()],
  ['Ctrl+Shift+Z, Ctrl+Y', 'redo', null, () => redo()],
  ['Ctrl+S', 'save the model', null, () => save()],
  ['Ctrl+O', 'open a model file', null, () => $('open').click()],
  ['1 2 3 4 5 6', 'the tabs: Bézier, B-spline, bodies, point calculus, Bézier surface, heights grid', null, null],
  ['F', 'fit the drawing to the view', null, () => { fitView(); draw(); }],
  ['+', 'raise the degree (the same curve)', 'bezier', () => $('deg-up').click()],
  ['−', 'lower the degree (exact, or the best approximation)', 'bezier', () => $('deg-down').click()],
  ['Enter, Esc', 'accept / cancel the proposed approximation', 'bezier', null],
  ['Tab, Shift+Tab', 'select the next / previous vertex', 'bezier', null],
  ['W, Shift+W', 'the selected vertex\'s weight × 1.25 / ÷ 1.25', 'bezier', null],
  ['Delete', 'remove the selected vertex', 'bezier', () => removePoint(selected)],
  ['C', 'curvature comb on / off', 'bspline', () => $('comb').click()],
  ['L', 'closed curve on / off', 'bspline', () => $('closed').click()],
  ['M', 'optimum: maximum / minimum', 'pointcalc', () => { const g = $('pc-goal'); g.value = g.value === 'max' ? 'min' : 'max'; g.dispatchEvent(new Event('change')); }],
  ['←, →, ↑, ↓', 'rotate a 3-D view (the bodies, surfaces and heights tabs; with Shift: pan; + / −: zoom)', null, null],
  ['?', 'this list', null, () => showHelp()],
];

function showHelp() {
  const rows = SHORTCUTS.map(([keys, what, mode]) => {
    const tr = document.createElement('tr');
    const k = document.createElement('td');
    for (const [i, part] of keys.split(', ').entries()) {
      if (i) k.append(' or ');
      const kbd = document.createElement('kbd');
      kbd.textContent = part;
      k.appendChild(kbd);
    }
    const w = document.createElement('td');
    w.textContent = mode ? `${what} (${mode === 'bspline' ? 'B-spline' : mode === 'pointcalc' ? 'point calculus' : 'Bézier'})` : what;
    tr.append(k, w);
    return tr;
  });
  const mouse = [
    ['drag a point', 'move it; drag the background: pan; wheel: zoom'],
    ['click', 'insert a vertex / add a reference point'],
    ['Alt+click, right-click', 'remove the point'],
    ['Shift+drag, wheel on a vertex', 'its weight (a rational Bézier curve)'],
    ['hover, click a seam', 'its continuity (bodies tab); drag: rotate, right-drag: pan, wheel: zoom'],
  ].map(([keys, what]) => {
    const tr = document.createElement('tr');
    const k = document.createElement('td');
    k.textContent = keys;
    const w = document.createElement('td');
    w.textContent = what;
    tr.append(k, w);
    return tr;
  });
  $('help-keys').replaceChildren(...rows, ...mouse);
  if (!$('help-dialog').open) $('help-dialog').showModal();
}

window.addEventListener('keydown', (ev) => {
  const mod = ev.ctrlKey || ev.metaKey;
  if (ev.target instanceof HTMLInputElement || ev.target instanceof HTMLSelectElement || ev.target instanceof HTMLTextAreaElement) return;
  if ($('help-dialog').open || $('open-dialog').open) return;
  const key = ev.key.length === 1 ? ev.key.toLowerCase() : ev.key;
  const bezier = doc.mode === 'bezier';
  const run = (fn) => { ev.preventDefault(); fn(); };
  if (mod && key === 'z') run(ev.shiftKey ? redo : undo);
  else if (mod && key === 'y') run(redo);
  else if (mod && key === 's') run(save);
  else if (mod && key === 'o') run(() => $('open').click());
  else if (mod || ev.altKey) return;
  else if (key === '?') run(showHelp);
  // The tabs in their order (the 3-D ones are surface.js's: it takes their clicks).
  else if (/^[1-6]$/.test(key)) run(() => document.querySelectorAll('.tabs button[data-mode]')[+key - 1].click());
  else if (window.geomkit3d?.active()) return; // the 3-D tabs' own keys: surface.js
  else if (doc.mode === 'body' && bodyView.key(ev)) ev.preventDefault(); // the body's 3-D view
  else if (key === 'f' && doc.mode !== 'body' && doc.mode !== 'pointcalc') run(() => { fitView(); draw(); });
  else if ((key === '+' || key === '=') && bezier) run(() => $('deg-up').click());
  else if (key === '-' && bezier) run(() => $('deg-down').click());
  else if (key === 'Enter' && bezier && proposal) run(() => $('approx-accept').click());
  else if (key === 'Escape' && bezier && proposal) run(() => $('approx-cancel').click());
  else if (key === 'Tab' && bezier && ev.target === svg) {
    run(() => {
      const n = doc.bezier.points.length;
      selected = (selected + (ev.shiftKey ? n - 1 : 1)) % n;
      showWeight();
      draw();
    });
  } else if (key === 'w' && bezier) run(() => setWeight(selected, weightOf(selected) * (ev.shiftKey ? 1 / 1.25 : 1.25), 'key'));
  else if ((key === 'Delete' || key === 'Backspace') && bezier) run(() => removePoint(selected));
  else if (key === 'c' && doc.mode === 'bspline') run(() => $('comb').click());
  else if (key === 'l' && doc.mode === 'bspline') run(() => $('closed').click());
  else if (key === 'm' && doc.mode === 'pointcalc') run(SHORTCUTS.find((s) => s[0] === 'M')[3]);
});
$('help').addEventListener('click', showHelp);
$('undo').addEventListener('click', undo);
$('redo').addEventListener('click', redo);
$('fit').addEventListener('click', () => { fitView(); draw(); });

// ---------------------------------------------------------------------------------------

async function start() {
  try {
    await initSyntaxes();
  } catch (e) { showError(e); }
  syncControls();
  fitView();
  updateUndoButtons();
  refresh();
}
start();
