// Latency of the editor's curve-edit requests (issue 25: p99 <= 10 ms): N requests of each
// kind the page sends while editing a curve, one after another (as the page does: at most
// one computation in flight), against a running `geomkit serve` or one started here.
//
//   node bench/serve_latency.mjs --geomkit target/release/geomkit [--n 200]
//   node bench/serve_latency.mjs --url http://127.0.0.1:8765/ [--n 200]
//
// Prints one line per kind: p50, p90, p99 and max in ms, measured in this process from the
// request sent to the whole answer read (node's fetch over a kept-alive local connection),
// after 10 requests of warm-up. Needs Node.js 20 or newer, nothing else.

import { startServe } from '../tests/e2e/serve.mjs';
import { parseArgs } from 'node:util';

const { values: args } = parseArgs({
  options: {
    geomkit: { type: 'string' },
    url: { type: 'string' },
    n: { type: 'string', default: '200' },
  },
});
if (!args.geomkit && !args.url) {
  console.error('usage: node bench/serve_latency.mjs (--geomkit PATH | --url URL) [--n N]');
  process.exit(2);
}
const n = Math.max(1, parseInt(args.n, 10));

const started = args.url ? null : await startServe(args.geomkit);
const url = args.url || started.url;

async function post(path, body) {
  const r = await fetch(new URL(path, url), { method: 'POST', headers: { 'Content-Type': 'application/json' }, body });
  const text = await r.text();
  // A refused reduction (422) is an answer the page shows: timed like the others.
  if (!r.ok && r.status !== 422) throw new Error(`${path}: ${r.status} ${text}`);
  return text;
}

// The page's requests (app.js): a Bézier drag (samples + degree report), the degree
// controls, vertex edits, and B-spline drags (the whole curve, and the window of a drag).
const quintic = { type: 'bezier_curve', points: [[10, 0], [22, 6], [19, 12], [11, 15], [8, 12], [20, 0]] };
const rational = { ...quintic, weights: [1, 2, 0.5, 1, 3, 1] };
const wave = (count) => Array.from({ length: count }, (_, i) => [i / 100, Math.sin(i / 37) + 0.3 * Math.sin(i / 7)]);
const spline = (points, extra = {}) => ({
  points,
  end: 'not-a-knot',
  parametrization: 'chord',
  closed: false,
  samples_per_span: Math.max(2, Math.min(16, Math.ceil(4000 / points.length))),
  comb: { per_span: Math.max(1, Math.min(6, Math.ceil(1500 / points.length))) },
  ...extra,
});
const kinds = [
  ['bezier drag: samples (400)', '/api/samples', { model: quintic, samples: 400 }],
  ['bezier drag: degree report', '/api/bezier/degree', { model: quintic }],
  ['rational drag: samples (400)', '/api/samples', { model: rational, samples: 400 }],
  ['elevate', '/api/bezier/elevate', { model: quintic, to: 6 }],
  ['reduce (exact)', '/api/bezier/reduce', { model: quintic, to: 4 }],
  ['reduce refused (422)', '/api/bezier/reduce', { model: { type: 'bezier_curve', points: [[0, 0], [1, 3], [2, -1], [3, 2]] }, to: 2 }],
  ['approximate (L2, band 300)', '/api/bezier/approximate', { model: quintic, to: 2, samples: 300 }],
  ['insert a vertex', '/api/bezier/edit', { model: quintic, insert: { index: 3, point: [15, 14] } }],
  ['remove a vertex', '/api/bezier/edit', { model: quintic, remove: 2 }],
  ['B-spline, 7 points', '/api/bspline/interpolate', spline(wave(7))],
  ['B-spline, 2000 points (whole)', '/api/bspline/interpolate', spline(wave(2000))],
  ['B-spline, 2000 points (drag window)', '/api/bspline/interpolate', { ...spline(wave(2000)), window: { around: 1000 } }],
];

function quantile(sorted, q) {
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
}

console.log(`geomkit serve at ${url}; ${n} requests of each kind, one at a time`);
console.log('kind                                   p50 ms   p90 ms   p99 ms   max ms   answer KB');
try {
  for (const [name, path, body] of kinds) {
    const text = JSON.stringify(body);
    let bytes = 0;
    for (let i = 0; i < 10; i++) bytes = (await post(path, text)).length;
    const ms = [];
    for (let i = 0; i < n; i++) {
      const t0 = performance.now();
      await post(path, text);
      ms.push(performance.now() - t0);
    }
    ms.sort((a, b) => a - b);
    const cols = [0.5, 0.9, 0.99].map((q) => quantile(ms, q).toFixed(2).padStart(8));
    console.log(`${name.padEnd(36)} ${cols.join(' ')} ${ms[ms.length - 1].toFixed(2).padStart(8)} ${(bytes / 1024).toFixed(1).padStart(10)}`);
  }
} finally {
  if (started) started.server.kill();
}
