// SPDX-License-Identifier: MIT
// WebGL2 view of the lens result: the flattened mesh (output pixel positions) textured with the
// input image (texture coordinates in input pixels), the ROI circle drawn on an overlay canvas.
// Pointer input moves the ROI (drag inside) or resizes it (drag its rim); every change calls
// onChange(roi) so the page can re-run the job. Until a result arrives the plain image is shown.
import { createProgram } from './gl_util.js';

const VERTEX = `#version 300 es
in vec2 position;   // output pixels
in vec2 texcoord;   // input pixels
uniform vec2 size;  // image width, height
out vec2 uv;
void main() {
  uv = texcoord / size;
  vec2 clip = position / size * 2.0 - 1.0;
  gl_Position = vec4(clip.x, -clip.y, 0.0, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
in vec2 uv;
uniform sampler2D image;
out vec4 colour;
void main() { colour = texture(image, uv); }`;

export class LensView {
  /// `canvas`: WebGL2 canvas; `overlay`: a 2D canvas stacked over it with the same CSS size.
  constructor(canvas, overlay, onChange) {
    this.canvas = canvas;
    this.overlay = overlay;
    this.onChange = onChange;
    // No multisampling: the mesh covers the whole canvas, so MSAA only smooths the canvas border,
    // and under a software renderer (SwiftShader, headless Chromium) it made each 100×100-grid
    // frame ~4× slower (about 10 instead of 37 draws per second).
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl;
    this.program = createProgram(gl, VERTEX, FRAGMENT);
    this.vao = gl.createVertexArray();
    this.buffers = { position: gl.createBuffer(), texcoord: gl.createBuffer(), triangles: gl.createBuffer() };
    this.uploaded = {};  // the arrays last sent to each buffer
    this.uniforms = { size: gl.getUniformLocation(this.program, 'size'), image: gl.getUniformLocation(this.program, 'image') };
    // The attribute layout never changes: set it once on the vertex array.
    gl.bindVertexArray(this.vao);
    for (const name of ['position', 'texcoord']) {
      gl.bindBuffer(gl.ARRAY_BUFFER, this.buffers[name]);
      const loc = gl.getAttribLocation(this.program, name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
    }
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.triangles);
    gl.bindVertexArray(null);
    // The undeformed image under the mesh: a live (translated) lens mesh no longer covers the strip
    // it moved away from, and there the deformation is the identity.
    this.background = gl.createVertexArray();
    this.backgroundBuffer = gl.createBuffer();
    gl.bindVertexArray(this.background);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.backgroundBuffer);
    for (const name of ['position', 'texcoord']) {
      const loc = gl.getAttribLocation(this.program, name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
    }
    gl.bindVertexArray(null);
    this.onFrame = null;  // called after each drawn frame
    this.texture = gl.createTexture();
    this.count = 0;
    this.image = null;
    this.roi = null;
    this.installControls();
  }

  /// Sets the input image {width, height, channels, pixels} and shows it undeformed.
  setImage(image) {
    const gl = this.gl;
    const n = image.width * image.height;
    const rgba = new Uint8Array(4 * n);
    for (let i = 0; i < n; i++) {
      const s = i * image.channels, p = image.pixels;
      if (image.channels >= 3) { rgba[4 * i] = p[s]; rgba[4 * i + 1] = p[s + 1]; rgba[4 * i + 2] = p[s + 2]; }
      else { rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = p[s]; }
      rgba[4 * i + 3] = image.channels === 4 ? p[s + 3] : image.channels === 2 ? p[s + 1] : 255;
    }
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, image.width, image.height, 0, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    this.image = { width: image.width, height: image.height };
    this.fullDirty = true;
    this.box = null;
    for (const c of [this.canvas, this.overlay]) { c.width = image.width; c.height = image.height; }
    this.canvas.parentElement.style.aspectRatio = `${image.width} / ${image.height}`;
    this.canvas.parentElement.style.setProperty('--aspect', String(image.width / image.height));
    const w = image.width, h = image.height;
    const corners = new Float32Array([0, 0, w, 0, w, h, 0, h]);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.backgroundBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([0, 0, w, 0, w, h, 0, 0, w, h, 0, h]), gl.STATIC_DRAW);
    this.setMesh(corners, corners, new Uint32Array([0, 1, 2, 0, 2, 3]));
  }

  /// Shows a deformation: positions and texture Float32Array (2 per vertex, pixels), triangles
  /// Uint32Array. Drawn at the next animation frame (several calls in one frame draw once); only
  /// the arrays that changed are uploaded, in place when their size is unchanged.
  setMesh(positions, texture, triangles) {
    this.next = { positions, texture, triangles };
    this.requestDraw();
  }

  /// The triangles that move their content (some vertex with position ≠ texture) and the box of
  /// their output positions [x0, y0, x1, y1]; the others show the image in place, which the
  /// background quad already draws.
  static activeTriangles(positions, texture, triangles) {
    const moved = (v) => positions[2 * v] !== texture[2 * v] || positions[2 * v + 1] !== texture[2 * v + 1];
    const out = new Uint32Array(triangles.length);
    let n = 0, x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let t = 0; t < triangles.length; t += 3) {
      const a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
      if (!moved(a) && !moved(b) && !moved(c)) continue;
      out[n++] = a; out[n++] = b; out[n++] = c;
      for (const v of [a, b, c]) {
        const x = positions[2 * v], y = positions[2 * v + 1];
        if (x < x0) x0 = x; if (x > x1) x1 = x; if (y < y0) y0 = y; if (y > y1) y1 = y;
      }
    }
    return { triangles: out.subarray(0, n), box: n ? [x0, y0, x1, y1] : null };
  }

  requestDraw() {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      // Under a software renderer every changed layer costs a composite: the overlay is redrawn
      // here, at most once per frame and together with the image, not at every pointer event.
      if (this.overlayDirty) { this.overlayDirty = false; this.drawOverlay(); }
      if (!this.next && !this.redraw) return;
      if (this.next) { this.upload(this.next); this.next = null; }
      this.redraw = false;
      this.draw();
      this.onFrame?.();
    });
  }

  upload({ positions, texture, triangles }) {
    const gl = this.gl;
    const same = (a, b) => {
      if (!a || a.length !== b.length) return false;
      for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
      return true;
    };
    gl.bindVertexArray(this.vao);
    const put = (target, name, data) => {
      const old = this.uploaded[name];
      if (same(old, data)) return;
      gl.bindBuffer(target, this.buffers[name]);
      if (old && old.length === data.length) gl.bufferSubData(target, 0, data);
      else gl.bufferData(target, data, gl.DYNAMIC_DRAW);
      this.uploaded[name] = data;
    };
    const active = LensView.activeTriangles(positions, texture, triangles);
    put(gl.ARRAY_BUFFER, 'position', positions);
    put(gl.ARRAY_BUFFER, 'texcoord', texture);
    put(gl.ELEMENT_ARRAY_BUFFER, 'triangles', active.triangles);
    gl.bindVertexArray(null);
    this.count = active.triangles.length;
    // Only the pixels under the lens now or in the previous frame change (the drawing buffer is
    // preserved): the next draw is clipped to their box, which matters under software rendering.
    const previous = this.box;
    this.box = active.box;
    this.dirty = this.fullDirty || !previous || !active.box ? null
      : [Math.min(previous[0], active.box[0]), Math.min(previous[1], active.box[1]),
         Math.max(previous[2], active.box[2]), Math.max(previous[3], active.box[3])];
    this.fullDirty = false;
  }

  /// Sets the ROI circle {cx, cy, r} (input pixels) without calling onChange.
  setRoi(roi) { this.roi = { ...roi }; this.drawOverlay(); }

  /// Redraws the overlay at the next animation frame.
  requestOverlay() { this.overlayDirty = true; this.requestDraw(); }

  draw() {
    const gl = this.gl;
    if (!this.image) return;
    gl.viewport(0, 0, this.canvas.width, this.canvas.height);
    const d = this.dirty;
    this.dirty = null;  // a later plain redraw (e.g. a resize of the page) draws everything
    if (d) {
      // Canvas pixels equal image pixels; GL's y runs upwards. Two pixels of margin for the edges.
      const x0 = Math.max(0, Math.floor(d[0]) - 2), x1 = Math.min(this.canvas.width, Math.ceil(d[2]) + 2);
      const y0 = Math.max(0, Math.floor(d[1]) - 2), y1 = Math.min(this.canvas.height, Math.ceil(d[3]) + 2);
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(x0, this.canvas.height - y1, Math.max(0, x1 - x0), Math.max(0, y1 - y0));
    }
    gl.useProgram(this.program);
    gl.uniform2f(this.uniforms.size, this.image.width, this.image.height);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.uniform1i(this.uniforms.image, 0);
    gl.bindVertexArray(this.background);
    gl.drawArrays(gl.TRIANGLES, 0, 6);
    gl.bindVertexArray(this.vao);
    gl.drawElements(gl.TRIANGLES, this.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
    gl.disable(gl.SCISSOR_TEST);
  }

  drawOverlay() {
    const ctx = this.overlay.getContext('2d');
    ctx.clearRect(0, 0, this.overlay.width, this.overlay.height);
    if (!this.roi || !this.image) return;
    const scale = this.image.width / (this.overlay.clientWidth || this.image.width);
    ctx.lineWidth = 2 * scale;
    ctx.setLineDash([6 * scale, 4 * scale]);
    ctx.strokeStyle = 'rgba(255, 200, 0, 0.9)';
    ctx.beginPath();
    ctx.arc(this.roi.cx, this.roi.cy, this.roi.r, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = 'rgba(255, 200, 0, 0.9)';
    ctx.beginPath();
    ctx.arc(this.roi.cx + this.roi.r, this.roi.cy, 5 * scale, 0, 2 * Math.PI);
    ctx.fill();
  }

  /// Input pixel coordinates of a pointer event.
  toImage(e) {
    const rect = this.overlay.getBoundingClientRect();
    return [(e.clientX - rect.left) / rect.width * this.image.width, (e.clientY - rect.top) / rect.height * this.image.height];
  }

  installControls() {
    const o = this.overlay;
    let drag = null;
    o.addEventListener('pointerdown', (e) => {
      if (!this.image || !this.roi) return;
      const [x, y] = this.toImage(e);
      const d = Math.hypot(x - this.roi.cx, y - this.roi.cy);
      const grab = 10 * this.image.width / o.getBoundingClientRect().width;
      if (Math.abs(d - this.roi.r) <= grab) drag = { mode: 'resize' };
      else if (d < this.roi.r) drag = { mode: 'move', dx: this.roi.cx - x, dy: this.roi.cy - y };
      else return;
      o.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    o.addEventListener('pointermove', (e) => {
      if (!this.image || !this.roi) return;
      const [x, y] = this.toImage(e);
      if (!drag) {
        const d = Math.hypot(x - this.roi.cx, y - this.roi.cy);
        const grab = 10 * this.image.width / o.getBoundingClientRect().width;
        o.style.cursor = Math.abs(d - this.roi.r) <= grab ? 'ew-resize' : d < this.roi.r ? 'move' : 'default';
        return;
      }
      const { width, height } = this.image;
      if (drag.mode === 'move') {
        this.roi.cx = Math.min(width - 1, Math.max(1, x + drag.dx));
        this.roi.cy = Math.min(height - 1, Math.max(1, y + drag.dy));
      } else {
        this.roi.r = Math.max(4, Math.min(0.5 * Math.min(width, height), Math.hypot(x - this.roi.cx, y - this.roi.cy)));
      }
      this.requestOverlay();
      this.onChange({ ...this.roi }, true);
    });
    const end = () => {
      if (drag) { drag = null; this.onChange({ ...this.roi }, false); }
    };
    o.addEventListener('pointerup', end);
    o.addEventListener('pointercancel', end);
  }
}
