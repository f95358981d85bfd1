// The 2-D view: world coordinates (y up) on an SVG element, with fit, zoom and pan.
// Only the mapping between world and screen lives here; every curve point drawn comes from
// the server.

const NS = 'http://www.w3.org/2000/svg';

/** Creates an SVG element with attributes. */
export function el(name, attrs = {}, parent = null) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}

export class View {
  constructor(svg) {
    this.svg = svg;
    this.cx = 0;
    this.cy = 0;
    this.scale = 100; // pixels per world unit
    this.measured = null;
  }

  /** Reads the element's size (a layout): once per drawing, not once per point. */
  measure() {
    const r = this.svg.getBoundingClientRect();
    this.origin = [r.left, r.top];
    this.measured = [Math.max(r.width, 1), Math.max(r.height, 1)];
    return this.measured;
  }

  size() {
    return this.measured || this.measure();
  }

  /** Frames the points (a list of [x, y]) with a margin. */
  fit(points) {
    if (!points.length) return;
    this.measure();
    let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
    for (const [x, y] of points) {
      x0 = Math.min(x0, x); x1 = Math.max(x1, x);
      y0 = Math.min(y0, y); y1 = Math.max(y1, y);
    }
    const [w, h] = this.size();
    const dx = Math.max(x1 - x0, 1e-9), dy = Math.max(y1 - y0, 1e-9);
    this.cx = (x0 + x1) / 2;
    this.cy = (y0 + y1) / 2;
    this.scale = Math.min((w * 0.8) / dx, (h * 0.8) / dy);
    if (!isFinite(this.scale) || this.scale <= 0) this.scale = 100;
  }

  toScreen(p) {
    const [w, h] = this.size();
    return [(p[0] - this.cx) * this.scale + w / 2, (this.cy - p[1]) * this.scale + h / 2];
  }

  toWorld(sx, sy) {
    const [w, h] = this.size();
    return [(sx - w / 2) / this.scale + this.cx, this.cy - (sy - h / 2) / this.scale];
  }

  /** The screen position of a mouse event inside the SVG. */
  eventPoint(ev) {
    if (!this.measured) this.measure();
    return [ev.clientX - this.origin[0], ev.clientY - this.origin[1]];
  }

  zoomAt(sx, sy, factor) {
    const before = this.toWorld(sx, sy);
    this.scale *= factor;
    const after = this.toWorld(sx, sy);
    this.cx += before[0] - after[0];
    this.cy += before[1] - after[1];
  }

  panBy(dsx, dsy) {
    this.cx -= dsx / this.scale;
    this.cy += dsy / this.scale;
  }

  /** A key of the mapping: equal keys map every world point to the same screen point. */
  key() {
    const [w, h] = this.size();
    return `${this.cx} ${this.cy} ${this.scale} ${w} ${h}`;
  }

  /**
   * SVG path data of a polyline whose points `from..to` (exclusive) changed since the last
   * call with the same `cache` object: only those are formatted again (a drag of one point
   * of a long curve changes a window of its samples).
   */
  pathDataCached(points, cache, from = 0, to = points.length) {
    const key = this.key();
    if (!cache.parts || cache.parts.length !== points.length || cache.key !== key) {
      cache.parts = new Array(points.length);
      cache.key = key;
      from = 0;
      to = points.length;
    }
    const parts = cache.parts;
    for (let i = Math.max(0, from); i < Math.min(to, points.length); i++) {
      const [x, y] = this.toScreen(points[i]);
      parts[i] = (i ? 'L' : 'M') + x.toFixed(2) + ' ' + y.toFixed(2);
    }
    return parts.join('');
  }

  /** SVG path data of a polyline of world points (closed: back to the first). */
  pathData(points, closed = false) {
    if (!points || !points.length) return '';
    const parts = new Array(points.length);
    for (let i = 0; i < points.length; i++) {
      const [x, y] = this.toScreen(points[i]);
      parts[i] = (i ? 'L' : 'M') + x.toFixed(2) + ' ' + y.toFixed(2);
    }
    return parts.join('') + (closed ? 'Z' : '');
  }

  /** Grid step in world units: 1, 2 or 5 times a power of ten, about 80 px apart. */
  gridStep() {
    const raw = 80 / this.scale;
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
    return 10 * p;
  }
}
