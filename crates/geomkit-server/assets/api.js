// The JSON API of geomkit serve (docs/serve-api.md), as the page uses it.

/** An error answer of the server: its status and JSON body ({"error": ..., ...}). */
export class ApiError extends Error {
  constructor(status, body) {
    super(body && body.error ? body.error : `HTTP ${status}`);
    this.status = status;
    this.body = body || {};
  }
}

async function answer(r) {
  const type = r.headers.get('content-type') || '';
  if (!r.ok) {
    let body;
    try {
      body = type.includes('json') ? await r.json() : { error: await r.text() };
    } catch {
      body = { error: `HTTP ${r.status}` };
    }
    throw new ApiError(r.status, body);
  }
  return type.includes('application/json') ? r.json() : r.blob();
}

/** POST a JSON body; resolves to the JSON answer (or a Blob for exports). */
export async function post(path, body) {
  const r = await fetch(path, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  return answer(r);
}

/** GET a JSON answer. */
export async function get(path) {
  return answer(await fetch(path));
}

/** PUT a JSON body. */
export async function put(path, body) {
  const r = await fetch(path, {
    method: 'PUT',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  return answer(r);
}

/** Saves a Blob as a download named `name`. */
export function download(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
