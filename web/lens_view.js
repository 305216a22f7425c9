// SPDX-License-Identifier: MIT
// View of the lens result. The lens is rendered with WebGL2 (the flattened mesh at output pixel
// positions, textured with the input image) into an off-screen canvas covering only the box of the
// triangles that move content, then copied into the visible 2D canvas (`canvas`, image resolution)
// over the undeformed image; outside the box the deformation is the identity. Each lens (a circle
// or a rectangle) is outlined on its own small 2D canvas (a ring) moved with a CSS transform.
// Why: without a GPU (SwiftShader, headless Chromium) a frame costs the pixels WebGL renders and
// reads back plus the screen area the compositor redraws. Here both are the lens box: a 2D canvas
// reports only the rectangles drawn into it as damaged, a WebGL canvas always the whole canvas. The
// single visible canvas shows the same pixels as one full-image render, without seams between layers.
// During a drag the core answers with the solved lens translated; such frames draw one quad that
// reads the solved mesh's displacement field (rendered once per solve) instead of its triangles.
// (The same frame computed in JavaScript measured no faster under SwiftShader, and its cost grows
// with the box on the main thread, where a GPU's is nil.)
// Pointer input on `overlay` (an empty element over both) selects a lens and moves it (drag inside)
// or resizes it (drag its rim); every change calls onChange(live) so the page can re-run the job.
import { VERTEX, FRAGMENT, DISPLACEMENT_FRAGMENT, DISPLACEMENT_VERTEX, SHIFT_VERTEX, SHIFT_FRAGMENT } from './shaders/lens_shaders.js';
import { createProgram } from './gl_util.js';

// Largest difference (input pixels) between a result's vertices and the field mesh's moved by one
// offset for the result to count as that translation: float32 rounding of the core's doubles.
const TRANSLATION_TOL = 1e-3;

// Image pixels kept around the box of moving triangles (so the field texture's border is zero and
// the box's edge pixels are whole), and the step the WebGL canvas size is rounded up to, so a lens
// moving across the image rarely reallocates it.
const MARGIN = 3;
const SIZE_STEP = 64;

export class LensView {
  /// `canvas` the visible 2D canvas, `ring` a 2D canvas for the first lens's outline (copied for the
  /// others), `overlay` the element receiving pointer input; all children of one positioned element
  /// (see the file comment).
  constructor({ canvas, ring, overlay }, onChange) {
    Object.assign(this, { canvas, overlay, onChange });
    this.rings = [ring];
    this.stack = overlay.parentElement;
    this.context = canvas.getContext('2d', { alpha: false });  // opaque: the compositor need not blend it
    this.pristine = document.createElement('canvas');  // the undeformed image
    this.glCanvas = document.createElement('canvas');  // off screen: the lens box
    // No multisampling: under a software renderer it made each 100×100-grid frame ~4× slower.
    // Each frame redraws the whole (small) canvas and copies it out at once: nothing to preserve.
    const gl = this.glCanvas.getContext('webgl2', { antialias: false, alpha: false, preserveDrawingBuffer: false });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl;
    this.program = createProgram(gl, VERTEX, FRAGMENT);
    this.vao = gl.createVertexArray();
    this.buffers = { position: gl.createBuffer(), texcoord: gl.createBuffer(), triangles: gl.createBuffer() };
    this.uploaded = {};  // the arrays last sent to each buffer
    this.uniforms = Object.fromEntries(['size', 'rect', 'image'].map((n) => [n, gl.getUniformLocation(this.program, n)]));
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
    // The live path needs float render targets that filter linearly; without them every frame
    // draws the mesh.
    if (gl.getExtension('EXT_color_buffer_float') && gl.getExtension('OES_texture_float_linear')) {
      this.displacementProgram = createProgram(gl, DISPLACEMENT_VERTEX, DISPLACEMENT_FRAGMENT);
      this.shiftProgram = createProgram(gl, SHIFT_VERTEX, SHIFT_FRAGMENT);
      this.displacementVao = gl.createVertexArray();
      gl.bindVertexArray(this.displacementVao);
      for (const name of ['position', 'texcoord']) {
        gl.bindBuffer(gl.ARRAY_BUFFER, this.buffers[name]);
        const loc = gl.getAttribLocation(this.displacementProgram, name);
        gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
      }
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.triangles);
      this.shiftVao = gl.createVertexArray();
      gl.bindVertexArray(this.shiftVao);
      gl.bindBuffer(gl.ARRAY_BUFFER, gl.createBuffer());
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1]), gl.STATIC_DRAW);
      const loc = gl.getAttribLocation(this.shiftProgram, 'corner');
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
      gl.bindVertexArray(null);
      this.shiftUniforms = Object.fromEntries(['image', 'field', 'size', 'rect', 'fieldRect', 'offset']
        .map((n) => [n, gl.getUniformLocation(this.shiftProgram, n)]));
      this.displacementRectUniform = gl.getUniformLocation(this.displacementProgram, 'rect');
      this.fieldTexture = gl.createTexture();
      this.framebuffer = gl.createFramebuffer();
    }
    this.mesh = null;     // the last result drawn as a mesh: {positions, texture, triangles, box}
    this.field = null;    // image rectangle of the field texture, once rendered for this.mesh
    this.offset = null;   // the current result is this.mesh moved by this offset [dx, dy]
    this.onFrame = null;  // called after each drawn frame
    this.texture = gl.createTexture();
    this.count = 0;
    this.image = null;
    // The lenses, input pixels: {shape: 'circle', cx, cy, r} or {shape: 'rect', cx, cy, w, h}.
    this.rois = [];
    this.active = 0;       // the lens that keys and the page's controls act on
    this.original = false; // show the undeformed image (the before/after toggle)
    this.onSelect = null;  // called when a pointer press selects another lens
    this.rect = null;      // image rectangle [x, y, width, height] of the lens box on screen
    this.scale = 1;        // CSS pixels per image pixel
    ring.style.visibility = 'hidden';
    // The layers' CSS placement depends on the displayed size: follow it.
    new ResizeObserver(() => this.layout()).observe(overlay);
    this.installControls();
  }

  /// Sets the input image {width, height, channels, pixels} and shows it undeformed.
  setImage(image) {
    const gl = this.gl;
    // Transparent pixels are composed over black here: both layers are opaque (the WebGL canvas
    // has no alpha channel, so the compositor need not blend it), and the page behind is black.
    const n = image.width * image.height;
    const rgba = new Uint8ClampedArray(4 * n);
    const p = image.pixels, ch = image.channels;
    for (let i = 0; i < n; i++) {
      const s = i * ch;
      const a = ch === 4 ? p[s + 3] : ch === 2 ? p[s + 1] : 255;
      const k = a / 255;
      if (ch >= 3) { rgba[4 * i] = p[s] * k; rgba[4 * i + 1] = p[s + 1] * k; rgba[4 * i + 2] = p[s + 2] * k; }
      else { rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = p[s] * k; }
      rgba[4 * i + 3] = 255;
    }
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, image.width, image.height, 0, gl.RGBA, gl.UNSIGNED_BYTE, rgba);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    this.image = { width: image.width, height: image.height };
    for (const c of [this.canvas, this.pristine]) {
      c.width = image.width;
      c.height = image.height;
    }
    this.pristine.getContext('2d').putImageData(new ImageData(rgba, image.width, image.height), 0, 0);
    this.context.imageSmoothingEnabled = false;  // every copy is 1:1 at whole pixels
    this.context.drawImage(this.pristine, 0, 0);
    this.stack.style.aspectRatio = `${image.width} / ${image.height}`;
    this.stack.style.setProperty('--aspect', String(image.width / image.height));
    const w = image.width, h = image.height;
    const corners = new Float32Array([0, 0, w, 0, w, h, 0, h]);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.backgroundBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([0, 0, w, 0, w, h, 0, 0, w, h, 0, h]), gl.STATIC_DRAW);
    this.rect = null;
    for (const ring of this.rings) ring.drawn = null;
    this.mesh = null;
    this.field = null;
    this.layout();
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
  /// undeformed image already shows.
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
      // The ring moves with the pointer at most once per frame, together with the image.
      if (this.ringDirty) { this.ringDirty = false; this.placeRing(); }
      if (!this.next) return;
      this.upload(this.next);
      this.next = null;
      this.draw();
      this.onFrame?.();
    });
  }

  /// The offset [dx, dy] by which `next` is `mesh` translated (positions and texture moved alike,
  /// the same triangles), or null.
  static translationOf(next, mesh) {
    if (!mesh || next.triangles.length !== mesh.triangles.length || next.positions.length !== mesh.positions.length) return null;
    const p = next.positions, t = next.texture, p0 = mesh.positions, t0 = mesh.texture;
    if (!p.length) return null;
    const dx = p[0] - p0[0], dy = p[1] - p0[1];
    for (let i = 0; i < p.length; i += 2) {
      if (Math.abs(p[i] - p0[i] - dx) > TRANSLATION_TOL || Math.abs(p[i + 1] - p0[i + 1] - dy) > TRANSLATION_TOL ||
          Math.abs(t[i] - t0[i] - dx) > TRANSLATION_TOL || Math.abs(t[i + 1] - t0[i + 1] - dy) > TRANSLATION_TOL) return null;
    }
    const a = next.triangles, b = mesh.triangles;
    if (a !== b) for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return null;
    return [dx, dy];
  }

  /// Uploads `next`: a translation of the mesh on screen only sets the offset (unless `asMesh`),
  /// anything else becomes the new mesh.
  upload(next, asMesh = false) {
    const offset = this.shiftProgram && !asMesh ? LensView.translationOf(next, this.mesh) : null;
    if (offset) {
      const b = this.mesh.box;
      this.offset = offset;
      this.box = b && [b[0] + offset[0], b[1] + offset[1], b[2] + offset[0], b[3] + offset[1]];
      return;
    }
    this.offset = null;
    this.field = null;
    const { positions, texture, triangles } = next;
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
    this.box = active.box;
    this.mesh = { ...next, box: active.box };
  }

  /// The image rectangle for the WebGL canvas: the box with a margin, its size rounded up to
  /// SIZE_STEP (and kept while it still fits and is not much larger), clamped into the image.
  placeRect(box) {
    const { width, height } = this.image;
    const fit = (lo, hi, size, old) => {
      const need = Math.ceil(hi) - Math.floor(lo) + 2 * MARGIN;
      let s = old && old >= need && old <= need + 2 * SIZE_STEP ? old : Math.ceil(need / SIZE_STEP) * SIZE_STEP;
      s = Math.min(s, size);
      // Centred on the box, then pushed inside the image.
      const start = Math.floor((lo + hi) / 2 - s / 2);
      return [Math.max(0, Math.min(size - s, start)), s];
    };
    const [x, w] = fit(box[0], box[2], width, this.rect?.[2]);
    const [y, h] = fit(box[1], box[3], height, this.rect?.[3]);
    return [x, y, w, h];
  }

  /// The selected lens.
  get roi() { return this.rois[this.active]; }

  /// Sets the lenses (see the constructor) and the selected one without calling onChange.
  setRois(rois, active = 0) {
    this.rois = rois.map((r) => ({ ...r }));
    this.active = Math.max(0, Math.min(active, rois.length - 1));
    this.placeRing();
  }

  /// Before/after: `on` shows the undeformed image (the lens outlines stay), off the lens again.
  setOriginal(on) {
    this.original = on;
    this.draw();
  }

  /// Moves the ring at the next animation frame.
  requestOverlay() { this.ringDirty = true; this.requestDraw(); }

  draw() {
    if (!this.image) return;
    const ctx = this.context;
    if (this.original) {
      ctx.drawImage(this.pristine, 0, 0);
      this.rect = null;
      return;
    }
    // The previous box goes back to the undeformed image; the new box is drawn over it in the same
    // task, so the page never shows the gap.
    if (this.rect) {
      const [x, y, w, h] = this.rect;
      ctx.drawImage(this.pristine, x, y, w, h, x, y, w, h);
    }
    if (!this.box) { this.rect = null; return; }
    const rect = this.placeRect(this.box);
    if (this.glCanvas.width !== rect[2] || this.glCanvas.height !== rect[3]) {
      this.glCanvas.width = rect[2];
      this.glCanvas.height = rect[3];
    }
    this.rect = rect;
    if (this.offset) this.drawShifted(rect);
    else this.drawMesh(rect);
    ctx.drawImage(this.glCanvas, 0, 0, rect[2], rect[3], rect[0], rect[1], rect[2], rect[3]);
  }

  /// The mesh itself: the undeformed image, then the triangles that move content.
  drawMesh(rect) {
    const gl = this.gl;
    gl.viewport(0, 0, rect[2], rect[3]);
    gl.useProgram(this.program);
    gl.uniform2f(this.uniforms.size, this.image.width, this.image.height);
    gl.uniform4f(this.uniforms.rect, rect[0], rect[1], rect[2], rect[3]);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.uniform1i(this.uniforms.image, 0);
    gl.bindVertexArray(this.background);
    gl.drawArrays(gl.TRIANGLES, 0, 6);
    gl.bindVertexArray(this.vao);
    gl.drawElements(gl.TRIANGLES, this.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
  }

  /// The mesh's displacement field over its own rectangle (zero where it does not move content),
  /// rendered once per mesh into the field texture.
  renderField() {
    const gl = this.gl;
    // Not clamped to the image: the border texels must be zero, since lookups outside clamp to them.
    const b = this.mesh.box;
    const x = Math.floor(b[0]) - MARGIN, y = Math.floor(b[1]) - MARGIN;
    const rect = [x, y, Math.ceil(b[2]) + MARGIN - x, Math.ceil(b[3]) + MARGIN - y];
    gl.bindTexture(gl.TEXTURE_2D, this.fieldTexture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG32F, rect[2], rect[3], 0, gl.RG, gl.FLOAT, null);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.framebuffer);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.fieldTexture, 0);
    gl.viewport(0, 0, rect[2], rect[3]);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    gl.useProgram(this.displacementProgram);
    gl.uniform4f(this.displacementRectUniform, rect[0], rect[1], rect[2], rect[3]);
    gl.bindVertexArray(this.displacementVao);
    gl.drawElements(gl.TRIANGLES, this.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.field = rect;
  }

  /// A live frame: the field mesh's result moved by this.offset, one quad (see SHIFT_FRAGMENT).
  drawShifted(rect) {
    const gl = this.gl;
    if (!this.field) this.renderField();
    const f = this.field, u = this.shiftUniforms;
    gl.viewport(0, 0, rect[2], rect[3]);
    gl.useProgram(this.shiftProgram);
    gl.uniform2f(u.size, this.image.width, this.image.height);
    gl.uniform4f(u.rect, rect[0], rect[1], rect[2], rect[3]);
    gl.uniform4f(u.fieldRect, f[0], f[1], f[2], f[3]);
    gl.uniform2f(u.offset, this.offset[0], this.offset[1]);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    gl.uniform1i(u.image, 0);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.fieldTexture);
    gl.uniform1i(u.field, 1);
    gl.bindVertexArray(this.shiftVao);
    gl.drawArrays(gl.TRIANGLES, 0, 6);
    gl.bindVertexArray(null);
    gl.activeTexture(gl.TEXTURE0);
  }

  /// Test hook: draws the live frame on screen both ways, as the field quad and as the translated
  /// mesh, and compares the pixels: {pixels, differ (count more than 2 levels apart), maxDiff}.
  /// Null unless a live frame is shown. Afterwards the translated mesh is on screen.
  compareLivePaths() {
    if (!this.offset || !this.rect) return null;
    const gl = this.gl, rect = this.rect, [w, h] = [rect[2], rect[3]];
    const read = () => { const px = new Uint8Array(4 * w * h); gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px); return px; };
    this.drawShifted(rect);
    const a = read();
    const [dx, dy] = this.offset, m = this.mesh;
    const moved = (v) => v.map((x, i) => x + (i % 2 ? dy : dx));
    this.upload({ positions: moved(m.positions), texture: moved(m.texture), triangles: m.triangles }, true);
    this.drawMesh(rect);
    const b = read();
    this.context.drawImage(this.glCanvas, 0, 0, w, h, rect[0], rect[1], w, h);
    let differ = 0, maxDiff = 0;
    for (let i = 0; i < a.length; i += 4) {
      const d = Math.max(Math.abs(a[i] - b[i]), Math.abs(a[i + 1] - b[i + 1]), Math.abs(a[i + 2] - b[i + 2]));
      if (d > 2) differ++;
      if (d > maxDiff) maxDiff = d;
    }
    return { pixels: w * h, differ, maxDiff };
  }

  /// Rereads the displayed size and places the layers again (after a page resize).
  layout() {
    if (!this.image) return;
    this.scale = (this.overlay.clientWidth || this.image.width) / this.image.width;
    this.placeRing();
  }

  /// The lens outlines: each drawn in device pixels into a canvas just large enough, redrawn only
  /// when its shape, size, selection or the scale changes; a move is a CSS transform.
  placeRing() {
    const s = this.scale, dpr = window.devicePixelRatio || 1;
    while (this.rings.length < this.rois.length) {
      const ring = this.rings[0].cloneNode(false);
      ring.removeAttribute('id');
      ring.drawn = null;
      this.rings[this.rings.length - 1].after(ring);
      this.rings.push(ring);
    }
    this.rings.forEach((ring, i) => {
      const roi = this.rois[i];
      if (!roi || !this.image) { ring.style.visibility = 'hidden'; return; }
      const pad = 8;  // CSS pixels around the outline: the line and the handle dot
      const [hw, hh] = roi.shape === 'rect' ? [roi.w / 2, roi.h / 2] : [roi.r, roi.r];
      const key = `${roi.shape} ${hw} ${hh} ${s} ${dpr} ${i === this.active}`;
      if (ring.drawn !== key) {
        const width = Math.ceil(2 * (hw * s + pad) * dpr), height = Math.ceil(2 * (hh * s + pad) * dpr);
        ring.width = width;
        ring.height = height;
        ring.style.width = `${width / dpr}px`;
        ring.style.height = `${height / dpr}px`;
        const ctx = ring.getContext('2d');
        ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
        ctx.clearRect(0, 0, width, height);
        const cx = width / dpr / 2, cy = height / dpr / 2, a = hw * s, b = hh * s;
        // The selected lens in yellow, the others in white.
        const colour = i === this.active ? 'rgba(255, 200, 0, 0.9)' : 'rgba(255, 255, 255, 0.75)';
        ctx.lineWidth = 2;
        ctx.setLineDash([6, 4]);
        ctx.strokeStyle = colour;
        ctx.beginPath();
        if (roi.shape === 'rect') ctx.rect(cx - a, cy - b, 2 * a, 2 * b);
        else ctx.arc(cx, cy, a, 0, 2 * Math.PI);
        ctx.stroke();
        ctx.setLineDash([]);
        ctx.fillStyle = colour;
        ctx.beginPath();
        ctx.arc(cx + a, cy, 5, 0, 2 * Math.PI);
        ctx.fill();
        ring.drawn = key;
      }
      // At whole device pixels: a fractional offset would make the compositor resample the line.
      const ox = parseFloat(ring.style.width) / 2, oy = parseFloat(ring.style.height) / 2;
      const snap = (v) => Math.round(v * dpr) / dpr;
      ring.style.transform = `translate(${snap(roi.cx * s - ox)}px, ${snap(roi.cy * s - oy)}px)`;
      ring.style.visibility = 'visible';
    });
  }

  /// What a press at image point (x, y) grabs on lens `roi`, `grab` pixels from its rim:
  /// {mode: 'resize', x, y (the dimensions it changes)}, {mode: 'move'} or null.
  static grabbed(roi, x, y, grab) {
    if (roi.shape === 'rect') {
      const dx = Math.abs(x - roi.cx), dy = Math.abs(y - roi.cy), hw = roi.w / 2, hh = roi.h / 2;
      const nearX = Math.abs(dx - hw) <= grab && dy <= hh + grab, nearY = Math.abs(dy - hh) <= grab && dx <= hw + grab;
      if (nearX || nearY) return { mode: 'resize', x: nearX, y: nearY };
      return dx < hw && dy < hh ? { mode: 'move' } : null;
    }
    const d = Math.hypot(x - roi.cx, y - roi.cy);
    if (Math.abs(d - roi.r) <= grab) return { mode: 'resize', x: true, y: true };
    return d < roi.r ? { mode: 'move' } : null;
  }

  /// The lens under image point (x, y): the selected one first, then the newest. {index, ...grabbed}.
  pick(x, y, grab) {
    const order = [this.active, ...this.rois.map((_, i) => this.rois.length - 1 - i).filter((i) => i !== this.active)];
    for (const index of order) {
      const g = this.rois[index] && LensView.grabbed(this.rois[index], x, y, grab);
      if (g) return { index, ...g };
    }
    return null;
  }

  /// Scales the selected lens by `factor` (at least 4 pixels, at most half the image's shorter side
  /// for a circle's radius, the image's side for a rectangle's).
  static resized(roi, width, height, factor) {
    if (roi.shape === 'rect') {
      return { ...roi, w: Math.max(8, Math.min(width, roi.w * factor)), h: Math.max(8, Math.min(height, roi.h * factor)) };
    }
    return { ...roi, r: Math.max(4, Math.min(0.5 * Math.min(width, height), roi.r * factor)) };
  }

  /// Input pixel coordinates of a pointer event; `rect` is the overlay's client rectangle.
  toImage(e, rect) {
    return [(e.clientX - rect.left) / rect.width * this.image.width, (e.clientY - rect.top) / rect.height * this.image.height];
  }

  installControls() {
    const o = this.overlay;
    let drag = null;
    const grabAt = (rect) => 10 * this.image.width / rect.width;
    o.addEventListener('pointerdown', (e) => {
      if (!this.image || !this.rois.length) return;
      // Read once per drag: reading the layout at every move would force a style update per event.
      const rect = o.getBoundingClientRect();
      const [x, y] = this.toImage(e, rect);
      const hit = this.pick(x, y, grabAt(rect));
      if (!hit) return;
      if (hit.index !== this.active) {
        this.active = hit.index;
        this.placeRing();
        this.onSelect?.(hit.index);
      }
      const roi = this.roi;
      drag = { ...hit, rect, dx: roi.cx - x, dy: roi.cy - y };
      o.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    o.addEventListener('pointermove', (e) => {
      if (!this.image || !this.rois.length) return;
      if (!drag) {
        const rect = o.getBoundingClientRect();
        const [x, y] = this.toImage(e, rect);
        const hit = this.pick(x, y, grabAt(rect));
        const cursor = !hit ? 'default' : hit.mode === 'move' ? 'move'
          : hit.x && hit.y && this.rois[hit.index].shape === 'rect' ? 'nwse-resize' : hit.x ? 'ew-resize' : hit.y ? 'ns-resize' : 'ew-resize';
        if (o.style.cursor !== cursor) o.style.cursor = cursor;
        return;
      }
      const [x, y] = this.toImage(e, drag.rect);
      const { width, height } = this.image;
      const roi = this.roi;
      if (drag.mode === 'move') {
        roi.cx = Math.min(width - 1, Math.max(1, x + drag.dx));
        roi.cy = Math.min(height - 1, Math.max(1, y + drag.dy));
      } else if (roi.shape === 'rect') {
        if (drag.x) roi.w = Math.max(8, Math.min(width, 2 * Math.abs(x - roi.cx)));
        if (drag.y) roi.h = Math.max(8, Math.min(height, 2 * Math.abs(y - roi.cy)));
      } else {
        roi.r = Math.max(4, Math.min(0.5 * Math.min(width, height), Math.hypot(x - roi.cx, y - roi.cy)));
      }
      this.requestOverlay();
      this.onChange(true);
    });
    const end = () => {
      if (drag) { drag = null; this.onChange(false); }
    };
    o.addEventListener('pointerup', end);
    o.addEventListener('pointercancel', end);
    // Keyboard: arrows move the selected lens by 2 % of the image (shift: 10 %), + and − resize it;
    // the job runs once per key press, like a released drag.
    o.addEventListener('keydown', (e) => {
      if (!this.image || !this.rois.length) return;
      const { width, height } = this.image;
      const step = (e.shiftKey ? 0.1 : 0.02) * Math.max(width, height);
      const moves = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
      const roi = this.roi;
      if (moves[e.key]) {
        roi.cx = Math.min(width - 1, Math.max(1, roi.cx + moves[e.key][0]));
        roi.cy = Math.min(height - 1, Math.max(1, roi.cy + moves[e.key][1]));
      } else if (e.key === '+' || e.key === '=' || e.key === '-' || e.key === '−') {
        Object.assign(roi, LensView.resized(roi, width, height, e.key === '+' || e.key === '=' ? 1.1 : 1 / 1.1));
      } else {
        return;
      }
      e.preventDefault();
      this.requestOverlay();
      this.onChange(false);
    });
  }
}
