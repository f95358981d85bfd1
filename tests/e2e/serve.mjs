// Helpers of the editor's end-to-end scripts and benchmarks: start `geomkit serve` on a free
// port and read its address, and POST to its JSON API.

import { spawn } from 'node:child_process';

/**
 * Starts `geomkit serve --port 0 ...extra` and resolves to `{ url, server }` once it printed
 * its address (the caller ends `server`). Rejects when it exits or is silent for 20 s.
 */
export function startServe(geomkit, extra = []) {
  const server = spawn(geomkit, ['serve', '--port', '0', ...extra], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let text = '';
    server.stdout.on('data', (b) => {
      text += b;
      const m = text.match(/geomkit serve: (http:\/\/\S+)/);
      if (m) resolve({ url: m[1], server });
    });
    server.on('exit', (code) => reject(new Error(`geomkit serve exited with ${code}`)));
    setTimeout(() => reject(new Error('geomkit serve printed no address within 20 s')), 20_000).unref();
  });
}

/** POSTs JSON `body` to `path` of the server at `url`; resolves to the JSON answer, or
 * throws with the server's error (status 4xx/5xx). */
export async function postJson(url, path, body) {
  const r = await fetch(new URL(path, url), { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const j = await r.json();
  if (!r.ok) throw new Error(`${path}: ${r.status} ${j.error}`);
  return j;
}

/**
 * The command line of an editor script: `--geomkit PATH --out SHOT_DIR [--chromium PATH]`
 * (exits 2 with the usage otherwise); the screenshot folder is made.
 */
export async function editorArgs(script) {
  const { parseArgs } = await import('node:util');
  const { mkdir } = await import('node:fs/promises');
  const path = await import('node:path');
  const { values } = parseArgs({
    options: {
      geomkit: { type: 'string' },
      out: { type: 'string' },
      chromium: { type: 'string', default: '/usr/bin/chromium' },
    },
  });
  if (!values.geomkit || !values.out) {
    console.error(`usage: node ${script} --geomkit PATH --out SHOT_DIR [--chromium PATH]`);
    process.exit(2);
  }
  values.out = path.resolve(values.out);
  await mkdir(values.out, { recursive: true });
  return values;
}

/**
 * The redraw rate of a scripted drag in the page: pointerdown on the element with id
 * `element` at (x, y) (client coordinates, or the element's own with `relative`), one
 * pointermove per animation frame for 3 s along x + i·dx, y − amplitude·sin(i/20), then
 * pointerup and `window[hooks].idle()`. Input sent through the DevTools protocol arrives
 * slower than the page redraws (it would measure the protocol), hence in the page. A frame
 * counts when `window[hooks].frames` (the page's drawing times) got one during the drag.
 * Resolves to `{ frames, seconds, moves }`.
 */
export function redrawRate(page, { element, hooks, x, y, dx, amplitude, relative = false }) {
  return page.evaluate(async ({ element, hooks, x, y, dx, amplitude, relative }) => {
    const el = document.getElementById(element);
    const r = relative ? el.getBoundingClientRect() : { left: 0, top: 0 };
    const at = (cx, cy) => ({ clientX: r.left + cx, clientY: r.top + cy, pointerId: 1, button: 0, buttons: 1, bubbles: true });
    const where = (i) => at(x + i * dx, y - amplitude * Math.sin(i / 20));
    window[hooks].frames.length = 0;
    el.dispatchEvent(new PointerEvent('pointerdown', at(x, y)));
    const t0 = performance.now();
    let i = 0;
    await new Promise((done) => {
      function step() {
        i++;
        el.dispatchEvent(new PointerEvent('pointermove', where(i)));
        if (performance.now() - t0 < 3000) requestAnimationFrame(step);
        else done();
      }
      requestAnimationFrame(step);
    });
    const t1 = performance.now();
    el.dispatchEvent(new PointerEvent('pointerup', where(i)));
    await window[hooks].idle();
    const f = window[hooks].frames.filter((t) => t >= t0 && t <= t1);
    return { frames: f.length, seconds: (t1 - t0) / 1000, moves: i };
  }, { element, hooks, x, y, dx, amplitude, relative });
}
