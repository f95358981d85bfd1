// Checks the demo gallery in headless Chromium (called by tests/e2e/run.sh).
//
//   node tests/e2e/check.mjs --dir DEMO_DIR --out SHOT_DIR [--chromium /usr/bin/chromium]
//
// Serves DEMO_DIR on 127.0.0.1 (a free port, this process: it ends with it), opens
// index.html and asserts: every <img> loaded (complete, naturalWidth > 0); every <a href>,
// <object data>, <embed src>, <iframe src>, <source src>, <link href>, <script src> target
// of this origin answers HTTP 200 and every #fragment names an element; no console error,
// page error or failed request; every demo item (section[id]) has a title, a caption, a
// checks table with at least one row and no failing check, and every figure a caption.
// Saves screenshots to SHOT_DIR: index.png (full page), index-top.png (first screen),
// index-narrow.png (a phone's width) and items/ID.png (each item). Exits 1 on any failure.

import { createServer } from 'node:http';
import { createReadStream } from 'node:fs';
import { mkdir, stat } from 'node:fs/promises';
import path from 'node:path';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const { values: args } = parseArgs({
  options: {
    dir: { type: 'string' },
    out: { type: 'string' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
if (!args.dir || !args.out) {
  console.error('usage: node check.mjs --dir DEMO_DIR --out SHOT_DIR [--chromium PATH]');
  process.exit(2);
}
const root = path.resolve(args.dir);
const shots = path.resolve(args.out);

// The whole check has a deadline of its own, below run.sh's `timeout`.
const deadline = setTimeout(() => {
  console.error('e2e: FAILED: check.mjs did not finish within 240 s');
  process.exit(1);
}, 240_000);
deadline.unref();

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
  '.jpg': 'image/jpeg',
  '.json': 'application/json',
  '.css': 'text/css',
  '.js': 'text/javascript',
  '.txt': 'text/plain; charset=utf-8',
  '.csv': 'text/csv; charset=utf-8',
  '.obj': 'text/plain; charset=utf-8',
  '.stl': 'model/stl',
  '.ply': 'application/octet-stream',
  '.glb': 'model/gltf-binary',
  '.step': 'model/step',
};

// A static file server for `root`, bound to the loopback interface only.
function serve() {
  const server = createServer(async (req, res) => {
    try {
      const url = new URL(req.url, 'http://127.0.0.1');
      let file = path.join(root, decodeURIComponent(url.pathname));
      if (file !== root && !file.startsWith(root + path.sep)) throw new Error('outside');
      if ((await stat(file)).isDirectory()) file = path.join(file, 'index.html');
      await stat(file);
      res.writeHead(200, {
        'content-type': TYPES[path.extname(file).toLowerCase()] ?? 'application/octet-stream',
        'cache-control': 'no-store',
      });
      if (req.method === 'HEAD') return res.end();
      createReadStream(file).pipe(res);
    } catch {
      res.writeHead(404, { 'content-type': 'text/plain' });
      res.end('not found\n');
    }
  });
  return new Promise((resolve, reject) => {
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => resolve(server));
  });
}

const failures = [];
let passed = 0;
const fail = (msg) => failures.push(msg);
// One assertion: counts toward the closing 'N passed, N failed' line.
const expect = (ok, msg) => (ok ? (passed += 1) : fail(msg));

const server = await serve();
const origin = `http://127.0.0.1:${server.address().port}`;
let browser;
try {
  browser = await chromium.launch({
    executablePath: args.chromium,
    headless: true,
    timeout: 60_000,
    // As root Chromium needs --no-sandbox; the rest keeps it off the (closed) network.
    args: [
      ...(process.getuid?.() === 0 ? ['--no-sandbox'] : []),
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
      '--disable-dev-shm-usage',
    ],
  });
  const context = await browser.newContext({ viewport: { width: 1400, height: 900 } });
  const page = await context.newPage();
  page.setDefaultTimeout(30_000);
  page.on('console', (m) => {
    if (m.type() === 'error') fail(`console error: ${m.text()} (${m.location().url || 'page'})`);
  });
  page.on('pageerror', (e) => fail(`page error: ${e.message}`));
  page.on('requestfailed', (r) =>
    fail(`request failed: ${r.url()} (${r.failure()?.errorText ?? 'unknown'})`),
  );
  page.on('response', (r) => {
    if (r.status() >= 400) fail(`HTTP ${r.status()} for ${r.url()}`);
  });

  const index = `${origin}/index.html`;
  const response = await page.goto(index, { waitUntil: 'load', timeout: 60_000 });
  expect(response?.status() === 200, `index.html answered ${response?.status()}`);
  // Lazy images load once scrolled to; make them all load before looking.
  await page.evaluate(() =>
    Promise.all(
      [...document.images].map((img) => {
        img.loading = 'eager';
        return img.decode().catch(() => {});
      }),
    ),
  );

  const facts = await page.evaluate(() => {
    const text = (el) => (el?.textContent ?? '').replace(/\s+/g, ' ').trim();
    return {
      title: document.title,
      images: [...document.images].map((img) => ({
        src: img.currentSrc || img.src,
        complete: img.complete,
        width: img.naturalWidth,
        alt: img.alt,
      })),
      targets: [
        ...[...document.querySelectorAll('a[href]')].map((e) => ['a', e.href]),
        ...[...document.querySelectorAll('object[data]')].map((e) => ['object', e.data]),
        ...[...document.querySelectorAll('embed[src]')].map((e) => ['embed', e.src]),
        ...[...document.querySelectorAll('iframe[src]')].map((e) => ['iframe', e.src]),
        ...[...document.querySelectorAll('source[src]')].map((e) => ['source', e.src]),
        ...[...document.querySelectorAll('link[href]')].map((e) => ['link', e.href]),
        ...[...document.querySelectorAll('script[src]')].map((e) => ['script', e.src]),
      ],
      ids: [...document.querySelectorAll('[id]')].map((e) => e.id),
      items: [...document.querySelectorAll('section[id]')].map((s) => ({
        id: s.id,
        title: text(s.querySelector('h2')),
        caption: text(s.querySelector('.caption') ?? s.querySelector('h2 + p')),
        figures: [...s.querySelectorAll('figure')].map((f) => text(f.querySelector('figcaption'))),
        checks: [...s.querySelectorAll('table.checks tr')]
          .filter((tr) => tr.querySelector('td'))
          .map((tr) => [...tr.querySelectorAll('td')].map(text)),
      })),
    };
  });

  // Images.
  expect(facts.images.length > 0, 'the page shows no image');
  for (const img of facts.images) {
    expect(img.complete && img.width > 0, `image did not load: ${img.src}`);
    expect(img.alt, `image without alt text: ${img.src}`);
  }

  // Links and embedded targets: this origin's must answer 200, fragments must name ids.
  const ids = new Set(facts.ids);
  const seen = new Set();
  let external = 0;
  for (const [tag, href] of facts.targets) {
    const url = new URL(href, index);
    if (url.origin !== origin) {
      if (url.protocol === 'http:' || url.protocol === 'https:') external += 1;
      else if (url.protocol !== 'mailto:' && url.protocol !== 'data:') fail(`<${tag}> with unexpected target ${href}`);
      continue;
    }
    if (url.hash && url.pathname === '/index.html')
      expect(
        ids.has(decodeURIComponent(url.hash.slice(1))),
        `<${tag} href="${url.hash}"> names no element of the page`,
      );
    url.hash = '';
    if (seen.has(url.href)) continue;
    seen.add(url.href);
    const r = await fetch(url, { signal: AbortSignal.timeout(10_000) }).catch((e) => ({
      status: `error ${e.message}`,
    }));
    expect(r.status === 200, `<${tag}> target ${url.pathname} answered ${r.status}`);
    await r.body?.cancel?.();
  }

  // Demo items.
  expect(facts.items.length > 0, 'the page has no demo item (section[id])');
  let checks = 0;
  for (const item of facts.items) {
    expect(item.title, `item ${item.id}: no title (h2)`);
    expect(item.caption, `item ${item.id}: no caption`);
    expect(item.checks.length > 0, `item ${item.id}: no checks table rows`);
    item.figures.forEach((c, i) => expect(c, `item ${item.id}: figure ${i + 1} has no caption`));
    for (const row of item.checks) {
      checks += 1;
      expect(
        !row.some((cell) => /^fail/i.test(cell)),
        `item ${item.id}: check failed: ${row.join(' | ')}`,
      );
    }
  }

  // Screenshots.
  await mkdir(path.join(shots, 'items'), { recursive: true });
  await page.screenshot({ path: path.join(shots, 'index-top.png') });
  await page.screenshot({ path: path.join(shots, 'index.png'), fullPage: true });
  for (const item of facts.items) {
    await page
      .locator(`section[id="${item.id}"]`)
      .screenshot({ path: path.join(shots, 'items', `${item.id}.png`) });
  }
  await page.setViewportSize({ width: 420, height: 900 });
  await page.screenshot({ path: path.join(shots, 'index-narrow.png') });
  await page.waitForTimeout(100); // let late console messages arrive before judging

  console.error(
    `e2e: ${facts.items.length} items, ${checks} checks, ${facts.images.length} images, ` +
      `${seen.size} same-origin targets fetched` +
      (external ? `, ${external} external links not followed (no network)` : ''),
  );
} catch (e) {
  fail(`browser check crashed: ${e.stack ?? e}`);
} finally {
  await browser?.close().catch(() => {});
  server.closeAllConnections?.();
  server.close();
}

for (const f of failures) console.error(`  - ${f}`);
console.log(`e2e: ${passed} passed, ${failures.length} failed`);
if (failures.length) {
  console.error(`e2e: FAILED: ${failures.length} problem(s) in the gallery (listed above)`);
  process.exit(1);
}
console.error(`e2e: gallery ok; screenshots in ${shots}`);
