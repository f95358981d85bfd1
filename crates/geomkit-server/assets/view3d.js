// The 3-D view: WebGL2, an orbiting camera (rotate, pan, zoom, fit), shaded triangles with
// per-vertex colour and a headlight, lines (control nets) and round points (vertices).
// Picking projects on the CPU with the same matrices the GPU uses (project()). Every
// position, normal and colour value drawn comes from the server; this module only maps
// them to the screen.

const VERTEX_MESH = `#version 300 es
uniform mat4 uMvp;
uniform mat4 uView;
in vec3 aPos;
in vec3 aNormal;
in vec3 aColor;
out vec3 vNormal;
out vec3 vColor;
out vec3 vEye;
void main() {
  gl_Position = uMvp * vec4(aPos, 1.0);
  vNormal = mat3(uView) * aNormal;
  vEye = -(uView * vec4(aPos, 1.0)).xyz;
  vColor = aColor;
}`;

const FRAGMENT_MESH = `#version 300 es
precision highp float;
in vec3 vNormal;
in vec3 vColor;
in vec3 vEye;
out vec4 outColor;
void main() {
  vec3 e = normalize(vEye);
  vec3 n = length(vNormal) > 1e-6 ? normalize(vNormal) : e;
  if (dot(n, e) < 0.0) n = -n; // two-sided
  // A headlight from the upper left and a fill light: Lambert plus a soft Blinn highlight.
  vec3 l1 = normalize(vec3(-0.35, 0.55, 1.0));
  vec3 l2 = normalize(vec3(0.6, -0.3, 0.5));
  float d = 0.62 * max(dot(n, l1), 0.0) + 0.22 * max(dot(n, l2), 0.0);
  float s = pow(max(dot(n, normalize(l1 + e)), 0.0), 40.0);
  vec3 c = vColor * (0.26 + d) + vec3(0.22) * s;
  outColor = vec4(pow(c, vec3(0.95)), 1.0);
}`;

const VERTEX_FLAT = `#version 300 es
uniform mat4 uMvp;
uniform float uSize;
uniform vec2 uOffset;
uniform float uBias;
in vec3 aPos;
in vec3 aColor;
out vec3 vColor;
void main() {
  gl_Position = uMvp * vec4(aPos, 1.0);
  // Lines and points in front of the surface they lie on.
  gl_Position.z -= uBias * gl_Position.w;
  // Thick lines: the same line drawn again shifted by a pixel (uOffset in clip units).
  gl_Position.xy += uOffset * gl_Position.w;
  gl_PointSize = uSize;
  vColor = aColor;
}`;

const FRAGMENT_FLAT = `#version 300 es
precision highp float;
uniform float uRound;
in vec3 vColor;
out vec4 outColor;
void main() {
  if (uRound > 0.5) {
    vec2 q = gl_PointCoord * 2.0 - 1.0;
    float r = dot(q, q);
    if (r > 1.0) discard;
    // A dark rim around a light disc.
    outColor = vec4(r > 0.55 ? vColor * 0.45 : vColor, 1.0);
  } else {
    outColor = vec4(vColor, 1.0);
  }
}`;

function compile(gl, vs, fs) {
  const program = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(program, s);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  return program;
}

// 4×4 matrices, column-major (as WebGL takes them), in f64 for the CPU.
function multiply(a, b) {
  const o = new Float64Array(16);
  for (let c = 0; c < 4; c++) {
    for (let r = 0; r < 4; r++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
  }
  return o;
}

function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2);
  const o = new Float64Array(16);
  o[0] = f / aspect; o[5] = f;
  o[10] = (far + near) / (near - far); o[11] = -1;
  o[14] = (2 * far * near) / (near - far);
  return o;
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const norm = (a) => { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; };

function lookAt(eye, target, up) {
  const z = norm(sub(eye, target));
  const x = norm(cross(up, z));
  const y = cross(z, x);
  const o = new Float64Array(16);
  o[0] = x[0]; o[4] = x[1]; o[8] = x[2]; o[12] = -dot(x, eye);
  o[1] = y[0]; o[5] = y[1]; o[9] = y[2]; o[13] = -dot(y, eye);
  o[2] = z[0]; o[6] = z[1]; o[10] = z[2]; o[14] = -dot(z, eye);
  o[15] = 1;
  return o;
}

/** Colour maps from a value in [0, 1] to RGB in [0, 1]. */
export const colourMaps = {
  // Blue – white – red, for signed values (curvature) scaled so that 0.5 is zero.
  diverging(t) {
    const a = [0.23, 0.30, 0.75], m = [0.87, 0.87, 0.87], b = [0.71, 0.02, 0.15];
    const [p, q, s] = t < 0.5 ? [a, m, t * 2] : [m, b, t * 2 - 1];
    return [p[0] + (q[0] - p[0]) * s, p[1] + (q[1] - p[1]) * s, p[2] + (q[2] - p[2]) * s];
  },
  // Viridis-like (dark blue – green – yellow), for sizes (an error).
  sequential(t) {
    const stops = [[0.27, 0.00, 0.33], [0.23, 0.32, 0.55], [0.13, 0.57, 0.55], [0.37, 0.79, 0.38], [0.99, 0.91, 0.14]];
    const x = Math.min(Math.max(t, 0), 1) * (stops.length - 1);
    const i = Math.min(Math.floor(x), stops.length - 2), s = x - i;
    return [0, 1, 2].map((c) => stops[i][c] + (stops[i + 1][c] - stops[i][c]) * s);
  },
};

export class View3D {
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: false });
    if (!gl) throw new Error('this browser has no WebGL2: the 3-D view cannot draw');
    this.gl = gl;
    this.meshProgram = compile(gl, VERTEX_MESH, FRAGMENT_MESH);
    this.flatProgram = compile(gl, VERTEX_FLAT, FRAGMENT_FLAT);
    this.mesh = null;
    this.lines = [];
    this.seams = [];
    this.points = null;
    // The camera: orbiting `target` at `distance`, yaw about +z, pitch above the xy plane.
    this.target = [0, 0, 0];
    this.distance = 5;
    this.yaw = -0.6;
    this.pitch = 0.55;
    this.radius = 1;
    this.fovy = (35 * Math.PI) / 180;
    this.frames = 0;
    this.updateMatrices();
  }

  /** CSS pixel size of the canvas; resizes the drawing buffer to match. */
  resize() {
    const r = this.canvas.getBoundingClientRect();
    const dpr = (window.devicePixelRatio || 1) * (this.scale || 1);
    const w = Math.max(1, Math.round(r.width * dpr)), h = Math.max(1, Math.round(r.height * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    this.cssSize = [Math.max(r.width, 1), Math.max(r.height, 1)];
    this.origin = [r.left, r.top];
    return this.cssSize;
  }

  eye() {
    const cp = Math.cos(this.pitch);
    return [
      this.target[0] + this.distance * cp * Math.cos(this.yaw),
      this.target[1] + this.distance * cp * Math.sin(this.yaw),
      this.target[2] + this.distance * Math.sin(this.pitch),
    ];
  }

  /** The view and view-projection matrices (the ones the GPU gets, in f64). */
  updateMatrices() {
    const [w, h] = this.cssSize || this.resize();
    this.view = lookAt(this.eye(), this.target, [0, 0, 1]);
    const near = Math.max(this.distance - 4 * this.radius, this.distance * 0.01);
    const far = this.distance + 4 * this.radius;
    this.proj = perspective(this.fovy, w / h, near, far);
    this.mvp = multiply(this.proj, this.view);
  }

  /** Screen position (CSS pixels in the canvas) and depth of a world point. */
  project(p) {
    const m = this.mvp;
    const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    const z = m[2] * p[0] + m[6] * p[1] + m[10] * p[2] + m[14];
    const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    const [cw, ch] = this.cssSize;
    return [((x / w + 1) / 2) * cw, ((1 - y / w) / 2) * ch, z / w];
  }

  /** The camera's right, up and forward unit vectors in world coordinates. */
  axes() {
    const v = this.view;
    return { right: [v[0], v[4], v[8]], up: [v[1], v[5], v[9]], back: [v[2], v[6], v[10]] };
  }

  /** World units per CSS pixel at the depth of point p. */
  pixelSize(p) {
    const { back } = this.axes();
    const depth = dot(sub(this.eye(), p), back);
    return (2 * depth * Math.tan(this.fovy / 2)) / this.cssSize[1];
  }

  /** Frames the bounding box of the flat [x, y, z, ...] arrays given. */
  fit(...arrays) {
    let lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const a of arrays) {
      if (!a) continue;
      for (let i = 0; i + 2 < a.length; i += 3) {
        for (let c = 0; c < 3; c++) { lo[c] = Math.min(lo[c], a[i + c]); hi[c] = Math.max(hi[c], a[i + c]); }
      }
    }
    if (!isFinite(lo[0])) return;
    this.target = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
    this.radius = Math.max(Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2, 1e-9);
    this.resize();
    const aspect = this.cssSize[0] / this.cssSize[1];
    const half = Math.min(this.fovy / 2, Math.atan(Math.tan(this.fovy / 2) * aspect));
    this.distance = (this.radius / Math.sin(half)) * 1.02;
    this.updateMatrices();
  }

  orbit(dx, dy) {
    this.yaw -= dx * 0.008;
    this.pitch = Math.min(Math.max(this.pitch + dy * 0.008, -1.55), 1.55);
    this.updateMatrices();
  }

  pan(dx, dy) {
    const { right, up } = this.axes();
    const s = this.pixelSize(this.target);
    for (let c = 0; c < 3; c++) this.target[c] += (-dx * right[c] + dy * up[c]) * s;
    this.updateMatrices();
  }

  zoom(factor) {
    this.distance = Math.min(Math.max(this.distance * factor, this.radius * 0.05), this.radius * 200);
    this.updateMatrices();
  }

  /** Uploads a grid mesh: rows × cols vertices, flat positions and normals, RGB colours. */
  setMesh({ rows, cols, positions, normals, colors }) {
    const idx = new Uint32Array((rows - 1) * (cols - 1) * 6);
    let k = 0;
    for (let i = 0; i + 1 < rows; i++) {
      for (let j = 0; j + 1 < cols; j++) {
        const a = i * cols + j, b = a + 1, c = a + cols, d = c + 1;
        idx[k++] = a; idx[k++] = c; idx[k++] = b;
        idx[k++] = b; idx[k++] = c; idx[k++] = d;
      }
    }
    this.setTriangles({ positions, normals, colors, triangles: idx });
  }

  /** The mesh's positions read back from the GPU's vertex buffer (for tests). */
  readPositions() {
    if (!this.mesh) return null;
    const gl = this.gl;
    const out = new Float32Array(this.mesh.vertices * 3);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.positionBuffer);
    gl.getBufferSubData(gl.ARRAY_BUFFER, 0, out);
    gl.bindBuffer(gl.ARRAY_BUFFER, null);
    return out;
  }

  clearMesh() { this.mesh = null; }

  /** Uploads an indexed triangle mesh (a grid's, or a tessellation's with split vertices at
   * creases): flat positions, normals and RGB colours per vertex, `triangles` three indices
   * each. */
  setTriangles({ positions, normals, colors, triangles }) {
    const gl = this.gl;
    if (this.mesh) release(gl, this.mesh);
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const buffers = [];
    for (const [name, data] of [['aPos', positions], ['aNormal', normals], ['aColor', colors]]) {
      const b = gl.createBuffer();
      buffers.push(b);
      if (name === 'aPos') this.positionBuffer = b;
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.STATIC_DRAW);
      const loc = gl.getAttribLocation(this.meshProgram, name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
    }
    const ib = gl.createBuffer();
    buffers.push(ib);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, triangles instanceof Uint32Array ? triangles : new Uint32Array(triangles), gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    this.mesh = { vao, buffers, count: triangles.length, vertices: positions.length / 3 };
  }

  /** Lines drawn on the surface (hidden behind it), `width` pixels wide: a list of
   * {segments: flat [x0, y0, z0, x1, y1, z1, ...] pairs, rgb, width}. */
  setSeams(list) {
    for (const l of this.seams) release(this.gl, l);
    this.seams = [];
    for (const { segments, rgb, width = 3 } of list) {
      if (!segments.length) continue;
      const colors = new Float32Array(segments.length);
      for (let i = 0; i < colors.length; i += 3) colors.set(rgb, i);
      this.seams.push(Object.assign(this.flatBuffer(segments, colors), { width }));
    }
  }

  flatBuffer(positions, colors) {
    const gl = this.gl;
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const buffers = [];
    for (const [name, data] of [['aPos', positions], ['aColor', colors]]) {
      const b = gl.createBuffer();
      buffers.push(b);
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.STATIC_DRAW);
      const loc = gl.getAttribLocation(this.flatProgram, name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
    }
    gl.bindVertexArray(null);
    return { vao, buffers, count: positions.length / 3 };
  }

  /** Line segments: flat [x0, y0, z0, x1, y1, z1, ...] pairs, one RGB colour. */
  setLines(segments, rgb) {
    for (const l of this.lines) release(this.gl, l);
    this.lines = [];
    if (segments && segments.length) {
      const colors = new Float32Array(segments.length);
      for (let i = 0; i < colors.length; i += 3) colors.set(rgb, i);
      this.lines.push(this.flatBuffer(segments, colors));
    }
  }

  /** Points: flat positions and per-point RGB colours, drawn `size` CSS pixels wide. */
  setPoints(positions, colors, size = 11) {
    if (this.points) release(this.gl, this.points);
    this.points = positions && positions.length ? this.flatBuffer(positions, colors) : null;
    this.pointSize = size;
  }

  draw() {
    const gl = this.gl;
    this.resize();
    this.updateMatrices();
    gl.viewport(0, 0, this.canvas.width, this.canvas.height);
    gl.clearColor(0.975, 0.98, 0.988, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const mvp = new Float32Array(this.mvp);
    if (this.mesh) {
      gl.useProgram(this.meshProgram);
      gl.uniformMatrix4fv(gl.getUniformLocation(this.meshProgram, 'uMvp'), false, mvp);
      gl.uniformMatrix4fv(gl.getUniformLocation(this.meshProgram, 'uView'), false, new Float32Array(this.view));
      gl.bindVertexArray(this.mesh.vao);
      gl.drawElements(gl.TRIANGLES, this.mesh.count, gl.UNSIGNED_INT, 0);
    }
    gl.useProgram(this.flatProgram);
    gl.uniformMatrix4fv(gl.getUniformLocation(this.flatProgram, 'uMvp'), false, mvp);
    gl.uniform1f(gl.getUniformLocation(this.flatProgram, 'uRound'), 0);
    // Seams: on the surface, behind it hidden; thick by drawing each again a pixel aside.
    const offset = gl.getUniformLocation(this.flatProgram, 'uOffset');
    const bias = gl.getUniformLocation(this.flatProgram, 'uBias');
    // Just in front of the faces they lie on; not enough to show through at the corners.
    gl.uniform1f(bias, 0.0002);
    const px = [2 / this.canvas.width, 2 / this.canvas.height];
    for (const l of this.seams) {
      gl.bindVertexArray(l.vao);
      const r = Math.max(0, (l.width * (this.scale || 1) * (window.devicePixelRatio || 1) - 1) / 2);
      for (const [dx, dy] of [[0, 0], [r, 0], [-r, 0], [0, r], [0, -r], [r / 2, r / 2], [-r / 2, -r / 2], [r / 2, -r / 2], [-r / 2, r / 2]]) {
        gl.uniform2f(offset, dx * px[0], dy * px[1]);
        gl.drawArrays(gl.LINES, 0, l.count);
      }
    }
    gl.uniform2f(offset, 0, 0);
    gl.uniform1f(bias, 0.0015);
    // The net and its vertices stay visible through the surface (they are what one edits).
    gl.disable(gl.DEPTH_TEST);
    for (const l of this.lines) {
      gl.bindVertexArray(l.vao);
      gl.drawArrays(gl.LINES, 0, l.count);
    }
    if (this.points) {
      gl.uniform1f(gl.getUniformLocation(this.flatProgram, 'uRound'), 1);
      gl.uniform1f(gl.getUniformLocation(this.flatProgram, 'uSize'), this.pointSize * (window.devicePixelRatio || 1));
      gl.bindVertexArray(this.points.vao);
      gl.drawArrays(gl.POINTS, 0, this.points.count);
    }
    gl.bindVertexArray(null);
    this.frames++;
  }

  /** Index of the point (flat positions) nearest to the screen position, within `radius` px. */
  pick(positions, sx, sy, radius = 10) {
    let best = -1, bestD = radius * radius, bestZ = Infinity;
    for (let i = 0; i * 3 < positions.length; i++) {
      const [x, y, z] = this.project([positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]]);
      const d = (x - sx) ** 2 + (y - sy) ** 2;
      if (d < bestD - 1e-9 || (Math.abs(d - bestD) < 1e-9 && z < bestZ)) { best = i; bestD = d; bestZ = z; }
    }
    return best;
  }

  /** The screen position of a mouse event inside the canvas. */
  eventPoint(ev) {
    const r = this.canvas.getBoundingClientRect();
    return [ev.clientX - r.left, ev.clientY - r.top];
  }
}

/** Frees the buffers and vertex array of a drawn item. */
function release(gl, item) {
  for (const b of item.buffers) gl.deleteBuffer(b);
  gl.deleteVertexArray(item.vao);
}
