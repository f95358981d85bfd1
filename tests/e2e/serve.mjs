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
