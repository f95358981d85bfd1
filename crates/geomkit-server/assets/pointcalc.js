// Point-calculus mode of the editor (spec/point-calculus.md): an experiment table (factors
// with their levels, one response), the model the server fits through it, drawn as a curve
// (1 factor) or a map with contour lines (2 factors; for more, a slice through the selected
// point, the other factors on sliders), the shares of the source points at the hovered point
// and the certified optimum. Every number drawn comes from the server: /api/pointcalc/fit,
// /grid, /shares and /optimum (docs/serve-api.md); the page only maps values to the screen.

import { post } from './api.js';
import { el } from './view.js';

const $ = (id) => document.getElementById(id);

/** The table of a new document: yield over temperature and time, 3 × 3 levels. */
export const INITIAL = {
  factors: [
    { name: 'temp', levels: [60, 75, 90] },
    { name: 'time', levels: [1, 2, 4] },
  ],
  response: 'yield',
  // Row-major over the factors (the first factor slowest), as the model file.
  values: [52, 61, 58, 60, 74, 69, 55, 66, 57],
  at: null,
  free: [0, 1],
  goal: 'max',
};

/** Cells of the full grid: the product of the level counts. */
export function cellCount(factors) {
  return factors.reduce((n, f) => n * f.levels.length, 1);
}

/** The levels of cell `c` (row-major, the first factor slowest). */
export function cellLevels(factors, c) {
  const out = new Array(factors.length);
  for (let i = factors.length - 1; i >= 0; i--) {
    const n = factors[i].levels.length;
    out[i] = factors[i].levels[c % n];
    c = Math.floor(c / n);
  }
  return out;
}

/**
 * A table from CSV text: a header of factor names and the response (last column), then one
 * row per experiment. The rows must cover the full grid of the levels found, each cell once.
 * Throws an Error naming the line or the missing cell.
 */
export function parseCsv(text) {
  const lines = text.split(/\r?\n/).map((l) => l.trim()).filter((l) => l && !l.startsWith('#'));
  if (lines.length < 2) throw new Error('CSV: a header line and at least one row are needed');
  const sep = lines[0].includes(';') ? ';' : lines[0].includes('\t') ? '\t' : ',';
  const head = lines[0].split(sep).map((s) => s.trim());
  if (head.length < 2) throw new Error('CSV: the header needs at least one factor and the response');
  const k = head.length - 1;
  const rows = lines.slice(1).map((l, i) => {
    const cells = l.split(sep).map((s) => s.trim());
    if (cells.length !== head.length) throw new Error(`CSV line ${i + 2}: ${cells.length} values, the header has ${head.length}`);
    return cells.map((s, j) => {
      const x = Number(s);
      if (s === '' || !Number.isFinite(x)) throw new Error(`CSV line ${i + 2}, column "${head[j]}": "${s}" is not a number`);
      return x;
    });
  });
  const factors = head.slice(0, k).map((name, j) => ({
    name,
    levels: [...new Set(rows.map((r) => r[j]))].sort((a, b) => a - b),
  }));
  const n = cellCount(factors);
  const values = new Array(n).fill(null);
  for (const [i, r] of rows.entries()) {
    let c = 0;
    for (let j = 0; j < k; j++) c = c * factors[j].levels.length + factors[j].levels.indexOf(r[j]);
    if (values[c] !== null) throw new Error(`CSV line ${i + 2}: the cell (${r.slice(0, k).join(', ')}) is given twice`);
    values[c] = r[k];
  }
  const missing = values.indexOf(null);
  if (missing >= 0) {
    throw new Error(`CSV: no row for the cell (${cellLevels(factors, missing).join(', ')}); the point equation needs the full grid of levels`);
  }
  return { factors, response: head[k], values };
}

/** A colour of the map for t in [0, 1]: deep blue, teal, yellow (perceptually even enough). */
function colour(t) {
  const stops = [[0.0, [35, 56, 140]], [0.35, [33, 145, 140]], [0.7, [144, 212, 67]], [1.0, [253, 231, 37]]];
  t = Math.max(0, Math.min(1, t));
  for (let i = 1; i < stops.length; i++) {
    if (t <= stops[i][0]) {
      const [a, ca] = stops[i - 1];
      const [b, cb] = stops[i];
      const w = (t - a) / (b - a);
      return `rgb(${ca.map((c, j) => Math.round(c + w * (cb[j] - c))).join(',')})`;
    }
  }
  return 'rgb(253,231,37)';
}

function fmt(x, digits = 4) {
  if (x === null || x === undefined || !Number.isFinite(x)) return '–';
  if (x === 0) return '0';
  const a = Math.abs(x);
  return a >= 1e-3 && a < 1e6 ? String(+x.toPrecision(digits)) : x.toExponential(2);
}

/**
 * The mode. `app` gives the editor's document and services: doc() (the whole document),
 * commit(), status(text, isError), showError(e), refresh() (recompute through the app's
 * scheduler).
 */
export class PointcalcMode {
  constructor(app) {
    this.app = app;
    this.svg = $('pc-plot');
    /** The last fit, grid, optimum and shares (what is drawn). */
    this.fit = null;
    this.grid = null;
    this.optimum = null;
    this.shares = null;
    this.hover = null;
    this.sharesBusy = false;
    this.sharesNext = null;
    this.frame = null;
    this.wire();
  }

  /** The table of the document. */
  get t() { return this.app.doc().pointcalc; }

  /** The fitted model file (for save, export and the tests), or null. */
  model() { return this.fit ? this.fit.model : null; }

  // --- the table -------------------------------------------------------------------------

  wire() {
    $('pc-add-factor').addEventListener('click', () => this.addFactor());
    $('pc-csv-apply').addEventListener('click', () => this.applyCsv());
    $('pc-goal').addEventListener('change', () => { this.t.goal = $('pc-goal').value; this.app.commit(); this.app.refresh(); });
    $('pc-response-name').addEventListener('change', () => { this.t.response = $('pc-response-name').value.trim() || 'y'; this.app.commit(); this.app.refresh(); });
    this.svg.addEventListener('pointermove', (ev) => this.onHover(ev));
    this.svg.addEventListener('pointerleave', () => { this.hover = null; this.requestShares(this.selected()); });
    this.svg.addEventListener('click', (ev) => this.onSelect(ev));
    new ResizeObserver(() => { if (!this.svg.hasAttribute('hidden')) this.draw(); }).observe(this.svg);
  }

  /** Rebuilds the table editor from the document (after undo, open, paste). */
  sync() {
    const t = this.t;
    $('pc-goal').value = t.goal;
    $('pc-response-name').value = t.response;
    const list = $('pc-factors');
    list.replaceChildren();
    t.factors.forEach((f, i) => {
      const row = document.createElement('div');
      row.className = 'pc-factor';
      const name = document.createElement('input');
      name.value = f.name;
      name.className = 'pc-name';
      name.setAttribute('aria-label', `name of factor ${i + 1}`);
      name.addEventListener('change', () => {
        const v = name.value.trim();
        if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(v)) { this.app.status(`Factor ${i + 1}: a name is a letter then letters, digits or _ ("${v}")`, true); name.value = f.name; return; }
        f.name = v;
        this.app.commit();
        this.sync();
        this.app.refresh();
      });
      const levels = document.createElement('input');
      levels.value = f.levels.join(', ');
      levels.className = 'pc-levels';
      levels.setAttribute('aria-label', `levels of ${f.name}`);
      levels.addEventListener('change', () => this.setLevels(i, levels.value, levels));
      const remove = document.createElement('button');
      remove.textContent = '×';
      remove.title = `Remove factor ${f.name} (its middle level is kept as a slice)`;
      remove.disabled = t.factors.length <= 1;
      remove.addEventListener('click', () => this.removeFactor(i));
      row.append(name, levels, remove);
      list.appendChild(row);
    });
    this.syncTable();
    this.syncSliders();
  }

  /** The response table: one row per grid cell, the levels and an editable value. */
  syncTable() {
    const t = this.t;
    const table = $('pc-table');
    const head = document.createElement('tr');
    for (const f of t.factors) {
      const th = document.createElement('th');
      th.textContent = f.name;
      head.appendChild(th);
    }
    const th = document.createElement('th');
    th.textContent = t.response;
    th.className = 'pc-resp';
    head.appendChild(th);
    const rows = [head];
    const n = cellCount(t.factors);
    for (let c = 0; c < n; c++) {
      const tr = document.createElement('tr');
      tr.dataset.cell = c;
      for (const v of cellLevels(t.factors, c)) {
        const td = document.createElement('td');
        td.textContent = fmt(v, 6);
        tr.appendChild(td);
      }
      const td = document.createElement('td');
      const input = document.createElement('input');
      input.type = 'text';
      input.inputMode = 'decimal';
      input.value = t.values[c];
      input.dataset.cell = c;
      input.setAttribute('aria-label', `${t.response} at ${cellLevels(t.factors, c).join(', ')}`);
      input.addEventListener('change', () => this.setValue(c, input));
      input.addEventListener('keydown', (ev) => {
        if (ev.key === 'Enter' || ev.key === 'ArrowDown' || ev.key === 'ArrowUp') {
          ev.preventDefault();
          input.dispatchEvent(new Event('change'));
          const next = table.querySelector(`input[data-cell="${c + (ev.key === 'ArrowUp' ? -1 : 1)}"]`);
          if (next) { next.focus(); next.select(); }
        }
      });
      td.appendChild(input);
      tr.appendChild(td);
      rows.push(tr);
    }
    table.replaceChildren(...rows);
    $('pc-cells').textContent = `${n} experiments (${t.factors.map((f) => f.levels.length).join(' × ')} levels)`;
  }

  setValue(c, input) {
    const x = Number(input.value.trim());
    if (input.value.trim() === '' || !Number.isFinite(x)) {
      this.app.status(`${this.t.response} at (${cellLevels(this.t.factors, c).join(', ')}): "${input.value}" is not a number`, true);
      input.classList.add('bad');
      return;
    }
    input.classList.remove('bad');
    if (this.t.values[c] === x) return;
    this.t.values[c] = x;
    this.app.commit();
    this.app.refresh();
  }

  /** New levels of factor i: the values of the cells kept are kept, new cells start at the
   * mean of the responses. */
  setLevels(i, text, input) {
    const levels = text.split(/[\s,;]+/).filter(Boolean).map(Number);
    if (levels.length < 1 || levels.some((x) => !Number.isFinite(x))) {
      this.app.status(`Levels of ${this.t.factors[i].name}: numbers separated by commas ("${text}")`, true);
      input.value = this.t.factors[i].levels.join(', ');
      return;
    }
    const sorted = [...levels].sort((a, b) => a - b);
    if (sorted.some((x, j) => j > 0 && x === sorted[j - 1])) {
      this.app.status(`Levels of ${this.t.factors[i].name}: a level is given twice`, true);
      input.value = this.t.factors[i].levels.join(', ');
      return;
    }
    const old = this.t.factors[i].levels;
    if (sorted.length === old.length) {
      // As many levels: the responses stay in their rows (the i-th level is renamed).
      this.t.factors[i].levels = sorted;
      this.t.at = null;
      this.app.commit();
      this.sync();
      this.app.refresh();
      return;
    }
    this.reshape((factors) => { factors[i] = { ...factors[i], levels: sorted }; });
  }

  addFactor() {
    const names = new Set(this.t.factors.map((f) => f.name));
    let k = this.t.factors.length + 1;
    while (names.has(`x${k}`)) k++;
    this.reshape((factors) => { factors.push({ name: `x${k}`, levels: [0, 1] }); });
  }

  removeFactor(i) {
    if (this.t.factors.length <= 1) return;
    // The slice at the factor's middle level is what is left.
    const f = this.t.factors[i];
    const keep = f.levels[Math.floor((f.levels.length - 1) / 2)];
    this.reshape((factors) => { factors.splice(i, 1); }, { factor: i, level: keep });
  }

  /** Changes the factors by `change` and moves every response to its cell in the new grid
   * (cells that are new get the mean response; `drop` names the factor removed and the
   * level whose slice stays). */
  reshape(change, drop = null) {
    const t = this.t;
    const old = t.factors.map((f) => ({ ...f, levels: [...f.levels] }));
    const factors = t.factors.map((f) => ({ ...f, levels: [...f.levels] }));
    change(factors);
    const byKey = new Map();
    for (let c = 0; c < t.values.length; c++) {
      const lv = cellLevels(old, c);
      if (drop) {
        if (lv[drop.factor] !== drop.level) continue;
        lv.splice(drop.factor, 1);
      }
      byKey.set(JSON.stringify(lv), t.values[c]);
    }
    const mean = t.values.reduce((s, v) => s + v, 0) / Math.max(t.values.length, 1);
    const n = cellCount(factors);
    if (n > 20000) { this.app.status(`${n} experiments: the table editor takes at most 20000 (open or fit larger models with the CLI)`, true); this.sync(); return; }
    const values = new Array(n);
    for (let c = 0; c < n; c++) {
      // A new factor's cells: the value of the same cell without it.
      const lv = cellLevels(factors, c);
      const key = JSON.stringify(lv.slice(0, old.length === factors.length - 1 ? old.length : lv.length));
      values[c] = byKey.has(key) ? byKey.get(key) : +mean.toPrecision(6);
    }
    t.factors = factors;
    t.values = values;
    t.at = null;
    t.free = factors.length === 1 ? [0] : [0, 1];
    this.app.commit();
    this.sync();
    this.app.refresh();
  }

  applyCsv() {
    try {
      const r = parseCsv($('pc-csv').value);
      Object.assign(this.t, r, { at: null, free: r.factors.length === 1 ? [0] : [0, 1] });
      this.app.commit();
      this.sync();
      this.app.refresh();
      this.app.status(`Pasted ${r.values.length} experiments over ${r.factors.map((f) => f.name).join(', ')}.`);
      $('pc-csv-box').open = false;
    } catch (e) {
      this.app.showError(e);
    }
  }

  /** A model file opened (pointcalc-model): its table. */
  load(m) {
    const t = this.t;
    t.factors = m.factors.map((f) => ({ name: f.name, levels: [...f.nodes] }));
    const dim = (m.response || ['y']).length;
    t.response = (m.response || ['y'])[0];
    t.values = dim === 1 ? [...m.values] : m.values.filter((_, i) => i % dim === 0);
    t.at = null;
    t.free = t.factors.length === 1 ? [0] : [0, 1];
    return dim;
  }

  // --- sliders of the fixed factors (k > 2) and the choice of the free ones ------------------

  syncSliders() {
    const t = this.t;
    const box = $('pc-slices');
    box.replaceChildren();
    const k = t.factors.length;
    $('pc-slice-card').hidden = k <= 2;
    if (k <= 2) return;
    const at = this.point();
    for (const axis of [0, 1]) {
      const label = document.createElement('label');
      label.textContent = axis === 0 ? 'across' : 'up';
      const sel = document.createElement('select');
      sel.id = `pc-free-${axis}`;
      t.factors.forEach((f, i) => {
        const o = document.createElement('option');
        o.value = i;
        o.textContent = f.name;
        sel.appendChild(o);
      });
      sel.value = t.free[axis];
      sel.addEventListener('change', () => {
        const v = +sel.value;
        const other = t.free[1 - axis];
        t.free[axis] = v;
        if (v === other) t.free[1 - axis] = t.free.includes(0) && v !== 0 ? 0 : [...Array(k).keys()].find((j) => j !== v);
        this.app.commit();
        this.syncSliders();
        this.app.refresh();
      });
      label.appendChild(sel);
      box.appendChild(label);
    }
    t.factors.forEach((f, i) => {
      if (t.free.includes(i)) return;
      const lo = f.levels[0], hi = f.levels[f.levels.length - 1];
      const label = document.createElement('label');
      label.className = 'pc-slider';
      const name = document.createElement('span');
      name.textContent = f.name;
      const range = document.createElement('input');
      range.type = 'range';
      range.min = lo;
      range.max = hi;
      range.step = (hi - lo) / 200 || 1;
      range.value = at[i];
      range.id = `pc-slider-${i}`;
      const out = document.createElement('output');
      out.textContent = fmt(at[i]);
      range.addEventListener('input', () => {
        const p = this.point();
        p[i] = +range.value;
        t.at = p;
        out.textContent = fmt(p[i]);
        this.app.refresh();
      });
      range.addEventListener('change', () => this.app.commit());
      label.append(name, range, out);
      box.appendChild(label);
    });
  }

  /** The selected point (default: the centre of the box of the levels). */
  point() {
    const t = this.t;
    if (t.at && t.at.length === t.factors.length) return [...t.at];
    return t.factors.map((f) => (f.levels[0] + f.levels[f.levels.length - 1]) / 2);
  }

  selected() { return this.point(); }

  // --- computing -------------------------------------------------------------------------

  /** Fits the table, samples the model along the free factors through the selected point,
   * finds the optimum, and the shares at the hovered or selected point. */
  async compute() {
    const t = this.t;
    if (this.hover && this.hover.length !== t.factors.length) this.hover = null;
    const fit = await post('/api/pointcalc/fit', {
      factors: t.factors.map((f) => ({ name: f.name, nodes: f.levels })),
      response: [t.response],
      values: t.values,
    });
    const free = t.factors.length === 1 ? [0] : t.free;
    const [grid, optimum] = await Promise.all([
      post('/api/pointcalc/grid', { model: fit.model, at: this.point(), free, contours: 12 }),
      post('/api/pointcalc/optimum', { model: fit.model, goal: t.goal }),
    ]);
    this.fit = fit;
    this.grid = grid;
    this.optimum = optimum;
    this.shares = await post('/api/pointcalc/shares', { model: fit.model, at: this.hover || this.point() });
    this.draw();
    this.showFacts();
    const warn = fit.warnings.length ? ` Warning: ${fit.warnings.join('; ')}` : '';
    this.app.status(`${fit.what}: ${t.goal} ${fmt(optimum.value, 6)} at (${optimum.at.map((x) => fmt(x)).join(', ')})${optimum.certified ? ', certified' : ''}.${warn}`, !!warn);
  }

  /** Shares at `at`, at most one request in flight (hovering sends the latest point). */
  requestShares(at) {
    if (!this.fit || at.length !== this.t.factors.length) return;
    this.sharesNext = at;
    if (this.sharesBusy) return;
    this.sharesBusy = true;
    (async () => {
      while (this.sharesNext) {
        const p = this.sharesNext;
        this.sharesNext = null;
        try {
          this.shares = await post('/api/pointcalc/shares', { model: this.fit.model, at: p });
          this.drawShares();
        } catch (e) { this.app.showError(e); }
      }
      this.sharesBusy = false;
    })();
  }

  busy() { return this.sharesBusy; }

  // --- drawing ---------------------------------------------------------------------------

  /** The plot's frame: screen rectangle of the axes and the mapping of factor values. */
  layout() {
    const r = this.svg.getBoundingClientRect();
    const w = Math.max(r.width, 1), h = Math.max(r.height, 1);
    const m = { left: 70, right: 90, top: 56, bottom: 56 };
    const g = this.grid;
    const xs = g.axes[0];
    const [x0, x1] = [xs[0], xs[xs.length - 1]];
    let y0, y1;
    if (g.axes.length === 2) {
      [y0, y1] = [g.axes[1][0], g.axes[1][g.axes[1].length - 1]];
    } else {
      // The curve's values and the source points, with a margin.
      const vals = g.values.concat(this.sourcePoints().map((p) => p.value));
      y0 = Math.min(...vals);
      y1 = Math.max(...vals);
      const pad = (y1 - y0) * 0.08 || 1;
      y0 -= pad;
      y1 += pad;
    }
    const pw = Math.max(w - m.left - m.right, 10), ph = Math.max(h - m.top - m.bottom, 10);
    const sx = (x) => m.left + ((x - x0) / (x1 - x0 || 1)) * pw;
    const sy = (y) => m.top + ph - ((y - y0) / (y1 - y0 || 1)) * ph;
    const wx = (px) => x0 + ((px - m.left) / pw) * (x1 - x0);
    const wy = (py) => y0 + ((m.top + ph - py) / ph) * (y1 - y0);
    return { w, h, m, pw, ph, x0, x1, y0, y1, sx, sy, wx, wy };
  }

  /** The source points as drawn: for 1 factor (level, value); for 2 or more the cells
   * projected on the free factors, with the cells' indices. */
  sourcePoints() {
    const t = this.t;
    const free = t.factors.length === 1 ? [0] : t.free;
    const out = new Map();
    const n = cellCount(t.factors);
    for (let c = 0; c < n; c++) {
      const lv = cellLevels(t.factors, c);
      const key = free.map((f) => lv[f]).join(',');
      if (!out.has(key)) out.set(key, { at: free.map((f) => lv[f]), cells: [], value: t.values[c] });
      out.get(key).cells.push(c);
    }
    return [...out.values()];
  }

  draw() {
    const svg = this.svg;
    if (!this.grid || svg.hasAttribute('hidden')) return;
    const L = this.layout();
    this.frame = L;
    svg.setAttribute('viewBox', `0 0 ${L.w} ${L.h}`);
    svg.replaceChildren();
    const g = this.grid;
    const t = this.t;
    const free = t.factors.length === 1 ? [0] : t.free;
    const [lo, hi] = g.range;
    if (g.axes.length === 2) {
      // The map: one rectangle per sample, centred on it (the colour of the model's value).
      const [xs, ys] = g.axes;
      const cell = el('g', { id: 'pc-map' }, svg);
      const half = (a, i) => (i === 0 ? 0 : (a[i] - a[i - 1]) / 2);
      for (let i = 0; i < xs.length; i++) {
        const xa = L.sx(xs[i] - half(xs, i)), xb = L.sx(xs[i] + (i + 1 < xs.length ? (xs[i + 1] - xs[i]) / 2 : 0));
        for (let j = 0; j < ys.length; j++) {
          const ya = L.sy(ys[j] + (j + 1 < ys.length ? (ys[j + 1] - ys[j]) / 2 : 0)), yb = L.sy(ys[j] - half(ys, j));
          el('rect', {
            x: xa.toFixed(2), y: ya.toFixed(2), width: (xb - xa + 0.6).toFixed(2), height: (yb - ya + 0.6).toFixed(2),
            fill: colour((g.values[i][j] - lo) / (hi - lo || 1)),
          }, cell);
        }
      }
      let d = '';
      for (const c of g.contours) {
        for (const [[ax, ay], [bx, by]] of c.segments) {
          d += `M${L.sx(ax).toFixed(2)} ${L.sy(ay).toFixed(2)}L${L.sx(bx).toFixed(2)} ${L.sy(by).toFixed(2)}`;
        }
      }
      el('path', { class: 'pc-contour', d, id: 'pc-contours' }, svg);
      this.drawColourBar(L, lo, hi);
    } else {
      const d = g.axes[0].map((x, i) => `${i ? 'L' : 'M'}${L.sx(x).toFixed(2)} ${L.sy(g.values[i]).toFixed(2)}`).join('');
      el('path', { class: 'curve', d, id: 'pc-curve' }, svg);
    }
    this.drawAxes(L, free);
    // The source points (sized by their share at the hovered point: drawShares).
    const pts = el('g', { id: 'pc-points' }, svg);
    for (const p of this.sourcePoints()) {
      const [x, y] = g.axes.length === 2 ? [L.sx(p.at[0]), L.sy(p.at[1])] : [L.sx(p.at[0]), L.sy(p.value)];
      const c = el('circle', { class: 'pc-source', cx: x.toFixed(2), cy: y.toFixed(2), r: 5, 'data-cells': p.cells.join(',') }, pts);
      el('title', {}, c).textContent = `${p.at.join(', ')}: ${t.response} = ${p.value}`;
    }
    this.drawOptimum(L);
    el('g', { id: 'pc-cursor' }, svg);
    this.drawShares();
  }

  drawAxes(L, free) {
    const svg = this.svg;
    const t = this.t;
    const ax = el('g', { class: 'pc-axes' }, svg);
    el('rect', { x: L.m.left, y: L.m.top, width: L.pw, height: L.ph, class: 'pc-frame' }, ax);
    const ticks = (a, b, n) => {
      const raw = (b - a) / n;
      const p = Math.pow(10, Math.floor(Math.log10(raw || 1)));
      const step = [1, 2, 5, 10].map((k) => k * p).find((s) => s >= raw) || raw;
      const out = [];
      for (let v = Math.ceil(a / step - 1e-9) * step; v <= b + step * 1e-9; v += step) out.push(+v.toPrecision(12));
      return out;
    };
    for (const v of ticks(L.x0, L.x1, 6)) {
      const x = L.sx(v);
      el('line', { x1: x, x2: x, y1: L.m.top + L.ph, y2: L.m.top + L.ph + 5, class: 'pc-tick' }, ax);
      el('text', { x, y: L.m.top + L.ph + 18, class: 'pc-tick-label', 'text-anchor': 'middle' }, ax).textContent = fmt(v);
    }
    for (const v of ticks(L.y0, L.y1, 5)) {
      const y = L.sy(v);
      el('line', { x1: L.m.left - 5, x2: L.m.left, y1: y, y2: y, class: 'pc-tick' }, ax);
      el('text', { x: L.m.left - 8, y: y + 4, class: 'pc-tick-label', 'text-anchor': 'end' }, ax).textContent = fmt(v);
    }
    el('text', { x: L.m.left + L.pw / 2, y: L.m.top + L.ph + 40, class: 'pc-axis-label', 'text-anchor': 'middle' }, ax).textContent = t.factors[free[0]].name;
    const yName = free.length === 2 ? t.factors[free[1]].name : t.response;
    el('text', { x: 18, y: L.m.top + L.ph / 2, class: 'pc-axis-label', 'text-anchor': 'middle', transform: `rotate(-90 18 ${L.m.top + L.ph / 2})` }, ax).textContent = yName;
    const fixed = t.factors.map((f, i) => (free.includes(i) ? null : `${f.name} = ${fmt(this.grid.at[i])}`)).filter(Boolean);
    const title = free.length === 2
      ? `${t.response} over ${t.factors[free[0]].name}, ${t.factors[free[1]].name}${fixed.length ? ` (slice: ${fixed.join(', ')})` : ''}`
      : `${t.response} over ${t.factors[free[0]].name}`;
    el('text', { x: L.m.left, y: 30, class: 'pc-title' }, ax).textContent = title;
  }

  drawColourBar(L, lo, hi) {
    const svg = this.svg;
    const x = L.m.left + L.pw + 24, w = 14;
    const bar = el('g', { class: 'pc-colourbar' }, svg);
    const n = 48;
    for (let i = 0; i < n; i++) {
      const y = L.m.top + L.ph * (1 - (i + 1) / n);
      el('rect', { x, y: y.toFixed(2), width: w, height: (L.ph / n + 0.6).toFixed(2), fill: colour((i + 0.5) / n) }, bar);
    }
    el('rect', { x, y: L.m.top, width: w, height: L.ph, class: 'pc-frame' }, bar);
    for (const [v, y] of [[hi, L.m.top + 4], [lo, L.m.top + L.ph]]) {
      el('text', { x: x + w + 4, y, class: 'pc-tick-label' }, bar).textContent = fmt(v);
    }
  }

  drawOptimum(L) {
    const o = this.optimum;
    if (!o) return;
    const t = this.t;
    const free = t.factors.length === 1 ? [0] : t.free;
    const g = el('g', { id: 'pc-optimum' }, this.svg);
    const x = L.sx(o.at[free[0]]);
    const y = free.length === 2 ? L.sy(o.at[free[1]]) : L.sy(o.value);
    const s = 9;
    el('path', { class: 'pc-star', d: `M${x - s} ${y}L${x + s} ${y}M${x} ${y - s}L${x} ${y + s}M${x - s * 0.7} ${y - s * 0.7}L${x + s * 0.7} ${y + s * 0.7}M${x - s * 0.7} ${y + s * 0.7}L${x + s * 0.7} ${y - s * 0.7}` }, g);
    const onSlice = free.length === t.factors.length || t.factors.every((_, i) => free.includes(i) || Math.abs(o.at[i] - this.grid.at[i]) < 1e-9);
    const label = `${t.goal} ${fmt(o.value, 6)}${o.certified ? ' ✓' : ''}${onSlice ? '' : ' (off this slice)'}`;
    const right = x < L.m.left + L.pw - 120;
    el('text', { x: right ? x + 12 : x - 12, y: y - 10, class: 'pc-opt-label', 'text-anchor': right ? 'start' : 'end' }, g).textContent = label;
  }

  /** Source points sized by |share| (orange: positive, purple: negative), the cursor, and
   * the bar list of the panel. */
  drawShares() {
    const s = this.shares;
    const L = this.frame;
    if (!s || !L) return;
    const t = this.t;
    const byCell = s.shares.map((x) => x.share);
    for (const c of this.svg.querySelectorAll('.pc-source')) {
      const sum = c.dataset.cells.split(',').reduce((a, i) => a + byCell[+i], 0);
      c.setAttribute('r', (3 + 14 * Math.sqrt(Math.min(Math.abs(sum), 1.5))).toFixed(2));
      c.classList.toggle('negative', sum < 0);
      c.dataset.share = sum;
    }
    const cursor = this.svg.querySelector('#pc-cursor');
    if (cursor) {
      cursor.replaceChildren();
      const at = this.hover || this.point();
      const free = t.factors.length === 1 ? [0] : t.free;
      const x = L.sx(at[free[0]]);
      const y = free.length === 2 ? L.sy(at[free[1]]) : L.sy(s.value[0]);
      el('circle', { cx: x, cy: y, r: 4, class: 'pc-cursor' }, cursor);
    }
    // The bar list: the largest shares first (at most 12), and their sum.
    const list = $('pc-shares');
    const items = s.shares.map((x, i) => ({ ...x, i })).sort((a, b) => Math.abs(b.share) - Math.abs(a.share));
    const most = Math.max(...items.map((x) => Math.abs(x.share)), 1e-300);
    const rows = items.slice(0, 12).map((x) => {
      const li = document.createElement('li');
      li.dataset.cell = x.i;
      li.dataset.share = x.share;
      const name = document.createElement('span');
      name.className = 'pc-share-name';
      name.textContent = `(${x.levels.map((v) => fmt(v)).join(', ')})`;
      const bar = document.createElement('span');
      bar.className = `pc-bar${x.share < 0 ? ' negative' : ''}`;
      bar.style.width = `${(100 * Math.abs(x.share)) / most}%`;
      const track = document.createElement('span');
      track.className = 'pc-track';
      track.appendChild(bar);
      const value = document.createElement('span');
      value.className = 'pc-share-value';
      value.textContent = fmt(x.share, 3);
      li.append(name, track, value);
      return li;
    });
    list.replaceChildren(...rows);
    const at = this.hover || this.point();
    $('pc-at').textContent = `at (${at.map((v) => fmt(v)).join(', ')}): ${t.response} = ${fmt(s.value[0], 6)}`;
    $('pc-sum').textContent = `${s.shares.length} shares, sum ${fmt(s.sum, 15)}${s.shares.length > 12 ? ' (the 12 largest shown)' : ''}`;
  }

  showFacts() {
    const o = this.optimum;
    $('pc-opt').textContent = `${fmt(o.value, 8)} at (${o.at.map((x) => fmt(x, 6)).join(', ')})`;
    $('pc-bound').textContent = `${fmt(o.bound, 8)}${o.certified ? ' (certified)' : ' (not certified)'}`;
    $('pc-gap').textContent = `${fmt(o.gap, 2)} after ${o.boxes} boxes`;
  }

  /** The factor point under the mouse (the others at the selected point), or null. */
  pointAt(ev) {
    const L = this.frame;
    if (!L) return null;
    const r = this.svg.getBoundingClientRect();
    const px = ev.clientX - r.left, py = ev.clientY - r.top;
    if (px < L.m.left || px > L.m.left + L.pw || py < L.m.top || py > L.m.top + L.ph) return null;
    const t = this.t;
    const p = this.point();
    const free = t.factors.length === 1 ? [0] : t.free;
    p[free[0]] = L.wx(px);
    if (free.length === 2) p[free[1]] = L.wy(py);
    return p;
  }

  onHover(ev) {
    const p = this.pointAt(ev);
    if (!p) return;
    this.hover = p;
    this.requestShares(p);
  }

  onSelect(ev) {
    const p = this.pointAt(ev);
    if (!p) return;
    this.t.at = p;
    this.app.commit();
    this.syncSliders();
    this.app.refresh();
  }

  /** Screen position (in the plot element) of a point in factor coordinates (the free
   * factors), for the tests. */
  toScreen(x, y) {
    const L = this.frame;
    return [L.sx(x), L.sy(y)];
  }
}
