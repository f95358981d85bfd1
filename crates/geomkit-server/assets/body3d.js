// The body tab's 3-D view: a body or composite surface shaded (the model crate's mesh) with
// its seams marked on it — every line where the single formula is only C^k, coloured by
// that order, with a legend; hovering a seam names it, clicking pins it. Every position and
// every verdict comes from the server (/api/body/view, docs/serve-api.md); app.js owns the
// document (which body or file) and asks this module to show the answer.

import { View3D } from './view3d.js';

const $ = (id) => document.getElementById(id);
const canvas = $('body3d');

/** The colour and legend text of each kind of seam, worst first. */
export const SEAM_STYLES = [
  { key: 'discontinuous', rgb: [0.86, 0.12, 0.15], text: 'discontinuous: the patches jump (the formula shifts them)' },
  { key: 'crease', rgb: [0.96, 0.50, 0.05], text: 'C0, a crease (the tangent plane turns)' },
  { key: 'C0', rgb: [0.80, 0.66, 0.05], text: 'C0 in the parameters, tangent plane continuous' },
  { key: 'C1', rgb: [0.16, 0.62, 0.30], text: 'C1' },
  { key: 'C2', rgb: [0.14, 0.44, 0.86], text: 'C2' },
  { key: 'smooth', rgb: [0.55, 0.40, 0.75], text: 'smooth (C3 or better where sampled)' },
];
const SURFACE_RGB = [0.80, 0.82, 0.86];

/** The style key of a seam of the answer. */
export function seamKey(seam) {
  if (seam.smoothness === 'C0' && seam.crease) return 'crease';
  return SEAM_STYLES.some((s) => s.key === seam.smoothness) ? seam.smoothness : 'smooth';
}

let view = null;
let answer = null;
let needFit = true;
let dragging = null;
let hovered = -1;
let pinned = -1;
/** The polylines drawn, per seam: flat segment pairs exactly as uploaded. */
let drawnSeams = [];

function ensureView() {
  if (!view) view = new View3D(canvas);
  return view;
}

function status(text) {
  const s = $('status');
  s.textContent = text;
  s.classList.remove('error');
  s.title = text;
}

/** Shows an answer of /api/body/view; `fit`: frame it. */
function show(a, fit = false) {
  answer = a;
  hovered = -1;
  pinned = -1;
  if (fit) needFit = true;
  ensureView();
  const n = a.mesh.positions.length / 3;
  const colors = new Float32Array(n * 3);
  for (let k = 0; k < n; k++) colors.set(SURFACE_RGB, 3 * k);
  view.setTriangles({ positions: a.mesh.positions, normals: a.mesh.normals, colors, triangles: a.mesh.triangles });
  drawnSeams = a.seams.map((s) => {
    const seg = [];
    for (let i = 0; i + 5 < s.points.length; i += 3) seg.push(...s.points.slice(i, i + 6));
    return seg;
  });
  legend();
  draw();
}

function legend() {
  const box = $('body-legend');
  box.replaceChildren();
  if (!answer) { box.hidden = true; return; }
  const head = document.createElement('div');
  head.className = 'legend-head';
  head.textContent = answer.seams.length ? 'Seams of the formula' : 'No seams: one smooth piece';
  box.appendChild(head);
  const counts = new Map();
  for (const s of answer.seams) counts.set(seamKey(s), (counts.get(seamKey(s)) || 0) + 1);
  for (const st of SEAM_STYLES) {
    if (!counts.has(st.key)) continue;
    const row = document.createElement('div');
    row.className = 'seam-row';
    row.dataset.key = st.key;
    const sw = document.createElement('span');
    sw.className = 'swatch';
    sw.style.background = `rgb(${st.rgb.map((x) => Math.round(x * 255)).join(',')})`;
    const t = document.createElement('span');
    t.textContent = `${st.text} · ${counts.get(st.key)}`;
    row.append(sw, t);
    box.appendChild(row);
  }
  box.hidden = false;
}

function draw() {
  if (!view || !answer) return;
  view.scale = dragging ? 1 : 2;
  const groups = new Map();
  answer.seams.forEach((s, i) => {
    const key = seamKey(s);
    if (!groups.has(key)) groups.set(key, []);
    groups.get(key).push(...drawnSeams[i]);
  });
  const list = [];
  for (const st of SEAM_STYLES) if (groups.has(st.key)) list.push({ segments: groups.get(st.key), rgb: st.rgb, width: 3 });
  const hi = pinned >= 0 ? pinned : hovered;
  if (hi >= 0) list.push({ segments: drawnSeams[hi], rgb: [0.08, 0.08, 0.1], width: 6 });
  view.setSeams(list);
  if (needFit) {
    view.fit(answer.mesh.positions);
    needFit = false;
  }
  view.draw();
  tooltip();
}

/** The seam under the screen point (within `radius` px; the nearest to the eye among
 * equals), or -1. */
function seamAt(sx, sy, radius = 8) {
  if (!answer) return -1;
  let best = -1, bestD = radius * radius, bestZ = Infinity;
  answer.seams.forEach((s, i) => {
    const p = s.points;
    let prev = null;
    for (let k = 0; k + 2 < p.length; k += 3) {
      const q = view.project([p[k], p[k + 1], p[k + 2]]);
      if (prev) {
        const [ax, ay] = prev, [bx, by] = q;
        const dx = bx - ax, dy = by - ay;
        const len2 = dx * dx + dy * dy || 1e-12;
        const t = Math.min(1, Math.max(0, ((sx - ax) * dx + (sy - ay) * dy) / len2));
        const d = (ax + t * dx - sx) ** 2 + (ay + t * dy - sy) ** 2;
        const z = prev[2] + t * (q[2] - prev[2]);
        if (d < bestD - 1e-6 || (Math.abs(d - bestD) <= 1e-6 && z < bestZ)) { best = i; bestD = d; bestZ = z; }
      }
      prev = q;
    }
  });
  return best;
}

function tooltip() {
  const tip = $('body-tip');
  const i = pinned >= 0 ? pinned : hovered;
  if (i < 0 || !answer) { tip.hidden = true; return; }
  const s = answer.seams[i];
  tip.textContent = s.label;
  const mid = Math.floor(s.points.length / 6) * 3;
  const [x, y] = view.project([s.points[mid], s.points[mid + 1], s.points[mid + 2]]);
  const [w] = view.cssSize;
  tip.style.left = `${Math.min(Math.max(x + 12, 8), w - 300)}px`;
  tip.style.top = `${Math.max(y - 36, 8)}px`;
  tip.hidden = false;
}

canvas.addEventListener('pointerdown', (ev) => {
  if (!view) return;
  canvas.focus();
  canvas.setPointerCapture(ev.pointerId);
  const [sx, sy] = view.eventPoint(ev);
  dragging = { kind: ev.button === 0 && !ev.shiftKey ? 'orbit' : 'pan', last: [sx, sy], start: [sx, sy], moved: false };
});

canvas.addEventListener('pointermove', (ev) => {
  if (!view) return;
  const [sx, sy] = view.eventPoint(ev);
  if (!dragging) {
    const h = seamAt(sx, sy);
    if (h !== hovered) { hovered = h; draw(); }
    return;
  }
  const [dx, dy] = [sx - dragging.last[0], sy - dragging.last[1]];
  dragging.last = [sx, sy];
  if (Math.hypot(sx - dragging.start[0], sy - dragging.start[1]) > 3) dragging.moved = true;
  if (dragging.kind === 'orbit') view.orbit(dx, dy);
  else view.pan(dx, dy);
  draw();
});

canvas.addEventListener('pointerup', (ev) => {
  if (!dragging) return;
  const d = dragging;
  dragging = null;
  if (!d.moved && ev.button === 0) {
    // A click: pin the seam under it (or unpin), and name it in the status line.
    const [sx, sy] = view.eventPoint(ev);
    const i = seamAt(sx, sy);
    pinned = i === pinned ? -1 : i;
    if (pinned >= 0) status(answer.seams[pinned].label);
  }
  draw();
});
canvas.addEventListener('pointerleave', () => { if (hovered >= 0 && !dragging) { hovered = -1; draw(); } });
canvas.addEventListener('contextmenu', (ev) => ev.preventDefault());
canvas.addEventListener('wheel', (ev) => {
  if (!view) return;
  ev.preventDefault();
  view.zoom(Math.exp(ev.deltaY * 0.0015));
  draw();
}, { passive: false });
$('body-fit').addEventListener('click', () => { needFit = true; draw(); });

/** The view's keys while the body tab is shown (app.js forwards them): F fit, arrows
 * rotate (Shift: pan), + / − zoom. True when the key was one of them. */
function key(ev) {
  if (!view || !answer) return false;
  if (ev.key === 'f' || ev.key === 'F') { needFit = true; draw(); return true; }
  if (ev.key === '+' || ev.key === '=') { view.zoom(1 / 1.2); draw(); return true; }
  if (ev.key === '-') { view.zoom(1.2); draw(); return true; }
  const d = { ArrowLeft: [-20, 0], ArrowRight: [20, 0], ArrowUp: [0, -20], ArrowDown: [0, 20] }[ev.key];
  if (!d) return false;
  if (ev.shiftKey) view.pan(d[0], d[1]); else view.orbit(d[0], d[1]);
  draw();
  return true;
}

window.addEventListener('resize', () => { if (answer && !canvas.hidden) draw(); });

// Hooks for app.js, the end-to-end test (tests/e2e/editor-body.mjs) and the console.
export const bodyView = {
  show,
  key,
  draw,
  answer: () => answer,
  project: (p) => view.project(p),
  view: () => view,
  /** The seams as drawn: per seam its style key and flat segment pairs. */
  drawnSeams: () => (answer ? answer.seams.map((s, i) => ({ key: seamKey(s), segments: drawnSeams[i], label: s.label })) : []),
  hovered: () => hovered,
  pinned: () => pinned,
  styles: SEAM_STYLES,
};
window.geomkitBody = bodyView;
