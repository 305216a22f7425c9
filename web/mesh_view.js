// SPDX-License-Identifier: MIT
// WebGL2 view of the mesh tab with orbit controls: drag to rotate, wheel to zoom, shift-drag or
// right-drag to pan, double-click to reset. Layers, each shown or hidden by name:
//   input     the input mesh (lit triangles, translucent over a result) and its wireframe ('wireframe')
//   boundary  the spline's boundary surface and its iso-parameter lines ('lines')
//   control   the control points, and the control lattice joining them ('lattice', off by default)
//   cut       the cut through the volume, coloured by scaled Jacobian
//   folds     points of the spline volume where det J ≤ 0 (setQuality)
//   cuboids   a GPC domain: the surface coloured by cuboid, its poly-edges and corners ('poly_edges')
// The boundary and its lines are cut away on the far side of the cut (uvw[axis] > position), so
// the cut is visible inside the solid; so are the control points when their anchors' uvw are
// given. Flat shading from screen-space derivatives.
// Frames are drawn only when something changed (camera, layers, visibility, size): showing the
// tab again costs no frame. While the camera moves, big layers are drawn from coarse copies
// (vertex clustering) at a fraction of the resolution: software GL's cost follows the triangles
// and pixels, and a frame must stay under ~30 ms for the drag to follow the pointer.
import { VERTEX, FRAGMENT } from './shaders/mesh_shaders.js';
import { createProgram, mat4 } from './gl_util.js';

// Input meshes with more triangles get no wireframe layer (see setMesh).
const WIREFRAME_MAX_TRIANGLES = 20000;
// While the camera moves, frames render at this fraction of the canvas resolution (level of
// detail for software GL, whose cost follows the pixels); the frame after the motion is full size.
const MOTION_SCALE = 0.5;
// While the camera moves, a triangle layer above MOTION_TRIANGLES is drawn from a coarse copy of
// about that many triangles, a point layer above MOTION_POINTS from every k-th point, and a line
// layer above MOTION_SEGMENTS from its polylines with every other vertex dropped (until at most
// that many segments), or not at all if its segments do not chain. SwiftShader draws ~2 µs per
// triangle: 4000 keep a frame near 10 ms; the iso-lines of armadillo's spline (10k segments)
// cost as much as its boundary.
const MOTION_TRIANGLES = 4000;
const MOTION_POINTS = 4000;
const MOTION_SEGMENTS = 4000;
// A wheel step counts as motion for this long (ms), so zooming draws coarse frames too.
const WHEEL_SETTLE_MS = 250;
// The layers of a mesh2spline result and of a gpc result: showing one drops the other.
const SPLINE_LAYERS = ['boundary', 'lines', 'control', 'lattice', 'cut', 'folds'];
const GPC_LAYERS = ['cuboids', 'poly_edges', 'corners'];

// Cuboid colours on a spline's boundary: lightened towards grey, so the cut's saturated scaled
// Jacobian colours stand out against them.
const PASTEL_WEIGHT = 0.6;
const pastel = (colours) => colours.map((c) => PASTEL_WEIGHT * c + (1 - PASTEL_WEIGHT) * 0.85);

/// Legend colours of the scaled Jacobian (CSS), matching the shader.
export const QUALITY_GRADIENT = 'linear-gradient(to right, rgb(217,26,26) 0%, rgb(217,26,26) 12%, rgb(242,115,26) 12%, rgb(250,217,51) 33%, rgb(77,191,89) 67%, rgb(51,102,217) 100%)';

export class MeshView {
  /// `canvas`: the element to draw into. Throws an Error if WebGL2 is unavailable.
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl;
    this.program = createProgram(gl, VERTEX, FRAGMENT);
    this.uniforms = Object.fromEntries(['view_projection', 'view', 'colour', 'lit', 'use_scalar', 'scalar_map', 'use_vertex_colour', 'cut_axis', 'cut_position', 'point_size']
      .map((n) => [n, gl.getUniformLocation(this.program, n)]));
    this.attributes = Object.fromEntries(['position', 'uvw', 'scalar', 'vertex_colour'].map((n) => [n, gl.getAttribLocation(this.program, n)]));
    this.layers = {};   // name -> {vao, buffers, count, mode, indexed}
    this.visible = { input: true, wireframe: true, boundary: true, lines: true, control: true, lattice: false, cut: true, folds: true, cuboids: true, poly_edges: true };
    this.cut = null;    // {axis, position} while a cut is shown
    this.resetCamera([0, 0, 0], 1);
    this.installControls();
    new ResizeObserver(() => this.requestDraw()).observe(canvas);
  }

  /// Replaces layer `name`: positions Float32Array (3 per vertex); optional uvw Float32Array
  /// (3 per vertex, fractions of the domain), scalar Float32Array (1 per vertex), colours
  /// Float32Array (RGB in [0, 1], 3 per vertex), indices Uint32Array; mode 'triangles' | 'lines' |
  /// 'points'. Null positions remove the layer. A big layer also gets its coarse motion copy.
  setLayer(name, { positions, uvw = null, scalar = null, colours = null, indices = null, mode = 'triangles' } = {}) {
    const old = this.layers[name];
    if (old) {
      for (const record of [old, old.motion]) if (record && record !== 'hide') this.freeRecord(record);
      delete this.layers[name];
    }
    this.layersVersion = (this.layersVersion || 0) + 1;
    if (!positions) { this.requestDraw(); return; }
    const data = { positions, uvw, scalar, colours, indices, mode };
    const layer = this.upload(data);
    layer.data = data;  // kept for pick()
    layer.bbox = boundingBox(positions);
    const count = indices ? indices.length : positions.length / 3;
    if (mode === 'triangles' && count / 3 > MOTION_TRIANGLES) layer.motion = this.upload(coarseTriangles(data, MOTION_TRIANGLES));
    else if (mode === 'points' && count > MOTION_POINTS) layer.motion = this.upload(everyKthPoint(data, Math.ceil(count / MOTION_POINTS)));
    else if (mode === 'lines' && count / 2 > MOTION_SEGMENTS) {
      const coarse = coarseLines(data, MOTION_SEGMENTS);
      layer.motion = coarse ? this.upload(coarse) : 'hide';
    }
    this.layers[name] = layer;
    this.requestDraw();
  }

  /// The GL objects of one layer's data: {vao, buffers, count, mode, indexed, hasUvw, hasScalar, hasColours}.
  upload({ positions, uvw, scalar, colours, indices, mode }) {
    const gl = this.gl;
    const vao = gl.createVertexArray();
    const buffers = [];
    gl.bindVertexArray(vao);
    const attribute = (loc, data, size, fallback) => {
      if (loc < 0) return;
      if (data) {
        const b = gl.createBuffer();
        buffers.push(b);
        gl.bindBuffer(gl.ARRAY_BUFFER, b);
        gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
        gl.enableVertexAttribArray(loc);
        gl.vertexAttribPointer(loc, size, gl.FLOAT, false, 0, 0);
      } else {
        gl.disableVertexAttribArray(loc);
        if (size === 3) gl.vertexAttrib3f(loc, ...fallback); else gl.vertexAttrib1f(loc, fallback);
      }
    };
    attribute(this.attributes.position, positions, 3, [0, 0, 0]);
    attribute(this.attributes.uvw, uvw, 3, [0, 0, 0]);
    attribute(this.attributes.scalar, scalar, 1, 0);
    attribute(this.attributes.vertex_colour, colours, 3, [1, 1, 1]);
    if (indices) {
      const b = gl.createBuffer();
      buffers.push(b);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, b);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
    }
    gl.bindVertexArray(null);
    const glMode = { triangles: gl.TRIANGLES, lines: gl.LINES, points: gl.POINTS }[mode];
    return { vao, buffers, count: indices ? indices.length : positions.length / 3, mode: glMode, indexed: !!indices, hasUvw: !!uvw, hasScalar: !!scalar, hasColours: !!colours };
  }

  freeRecord(record) {
    this.gl.deleteVertexArray(record.vao);
    for (const b of record.buffers) this.gl.deleteBuffer(b);
  }

  /// Shows an input mesh (positions Float32Array, triangles Uint32Array) and its wireframe, drops
  /// every spline layer and frames the bounding box bbox_min/bbox_max [x,y,z].
  setMesh(positions, triangles, bboxMin, bboxMax) {
    for (const name of [...SPLINE_LAYERS, ...GPC_LAYERS]) this.setLayer(name, {});
    this.cut = null;
    this.setLayer('input', { positions, indices: triangles });
    // Unique edges for the wireframe, keyed by (min, max) vertex pair. Above WIREFRAME_MAX_TRIANGLES
    // a full wireframe is a solid smear of lines that costs a software renderer most of a frame:
    // none is drawn (wireframeOmitted says so to the page).
    this.wireframeOmitted = triangles.length / 3 > WIREFRAME_MAX_TRIANGLES;
    if (this.wireframeOmitted) {
      this.setLayer('wireframe', {});
    } else {
      const seen = new Set();
      const lines = [];
      for (let f = 0; f < triangles.length; f += 3) {
        for (let k = 0; k < 3; k++) {
          const a = triangles[f + k], b = triangles[f + ((k + 1) % 3)];
          const key = a < b ? a * 4294967296 + b : b * 4294967296 + a;
          if (!seen.has(key)) { seen.add(key); lines.push(a, b); }
        }
      }
      this.setLayer('wireframe', { positions, indices: new Uint32Array(lines), mode: 'lines' });
    }
    const centre = [0, 1, 2].map((k) => 0.5 * (bboxMin[k] + bboxMax[k]));
    const radius = 0.5 * Math.hypot(...[0, 1, 2].map((k) => bboxMax[k] - bboxMin[k])) || 1;
    this.resetCamera(centre, radius);
  }

  /// Shows a mesh2spline result: r.boundary {positions, uvw, triangles, colours?: RGB per point, the
  /// cuboids of a GPC spline}, r.lines {positions, uvw}, r.control_points, r.control_uvw (optional:
  /// the anchors of a GPC spline's control points, so the cut clips them), and r.cut (see setCut);
  /// lattice (optional, splineLattice's {uvw, edges}: the control points' anchors and lattice
  /// edges) lets the cut clip the control points and draws the lattice. The input mesh stays as
  /// faint context.
  setSpline(r, lattice = null) {
    for (const name of GPC_LAYERS) this.setLayer(name, {});
    this.boundarySamples = { positions: r.boundary.positions, uvw: r.boundary.uvw };
    this.cut = null;  // the first cut turns the camera towards it
    this.setLayer('boundary', { positions: r.boundary.positions, uvw: r.boundary.uvw, indices: r.boundary.triangles, colours: r.boundary.colours ? pastel(r.boundary.colours) : null });
    this.setLayer('lines', { positions: r.lines.positions, uvw: r.lines.uvw, mode: 'lines' });
    this.setLayer('control', { positions: r.control_points, uvw: lattice?.uvw ?? r.control_uvw ?? null, mode: 'points' });
    this.setLayer('lattice', lattice ? { positions: r.control_points, uvw: lattice.uvw, indices: lattice.edges, mode: 'lines' } : {});
    this.setCut(r.cut);
  }

  /// Shows a spline's quality views: folded (Float32Array xyz, points with det J ≤ 0) and
  /// boundaryDistance (per boundary vertex, as a fraction of its target, or null: the boundary
  /// stays grey). Call after setSpline.
  setQuality({ folded = null, boundaryDistance = null } = {}) {
    this.setLayer('folds', folded && folded.length ? { positions: folded, mode: 'points' } : {});
    const b = this.layers.boundary?.data;
    if (b) this.setLayer('boundary', { ...b, scalar: boundaryDistance });
  }

  /// Shows a cut {axis, position, positions, triangles, scaled_jacobian}, or none for null.
  setCut(cut) {
    const turn = cut && (!this.cut || this.cut.axis !== cut.axis);
    this.cut = cut ? { axis: cut.axis, position: cut.position } : null;
    this.setLayer('cut', cut ? { positions: cut.positions, scalar: cut.display ?? cut.scaled_jacobian, indices: cut.triangles } : {});
    if (turn) this.faceCut(cut);
  }

  /// Turns the camera to look at the cut from the cut-away side, a little from the side so the
  /// solid still looks solid. Uses the boundary samples kept by setSpline.
  faceCut(cut) {
    const b = this.boundarySamples;
    if (!b) return;
    const mean = (positions, keep) => {
      const m = [0, 0, 0];
      let n = 0;
      for (let i = 0; i < positions.length / 3; i++) {
        if (!keep(i)) continue;
        for (let k = 0; k < 3; k++) m[k] += positions[3 * i + k];
        n++;
      }
      return n ? m.map((x) => x / n) : null;
    };
    const removed = mean(b.positions, (i) => b.uvw[3 * i + cut.axis] > cut.position + 0.05);
    const centre = mean(cut.positions, () => true);
    if (!removed || !centre) return;
    const d = removed.map((x, k) => x - centre[k]);
    if (Math.hypot(...d) < 1e-9 * this.camera.radius) return;
    // About 35–50° off the cut's normal: never straight on, so the cut reads as a section.
    this.camera.yaw = Math.atan2(d[0], d[2]) + 0.6;
    this.camera.pitch = Math.max(-0.9, Math.min(0.9, Math.atan2(d[1], Math.hypot(d[0], d[2])) + 0.3));
    this.requestDraw();
  }

  /// Shows a gpc result: r.surface {positions, colours} (3 points per triangle, coloured by
  /// cuboid), r.poly_edges (line segments) and r.corners (points); drops every spline layer.
  setGpc(r) {
    for (const name of SPLINE_LAYERS) this.setLayer(name, {});
    this.cut = null;
    this.boundarySamples = null;
    this.setLayer('cuboids', { positions: r.surface.positions, colours: r.surface.colours });
    this.setLayer('poly_edges', { positions: r.poly_edges, mode: 'lines' });
    this.setLayer('corners', { positions: r.corners, mode: 'points' });
  }

  get hasSpline() { return !!this.layers.boundary; }
  /// A job's result is shown (a spline or a GPC domain): the input mesh is context only.
  get hasResult() { return !!(this.layers.boundary || this.layers.cuboids); }

  resetCamera(target, radius) {
    this.home = { target: [...target], radius };
    this.camera = { target: [...target], radius, distance: 2.8 * radius, yaw: 0.6, pitch: 0.35 };
    this.requestDraw();
  }

  /// Frames what is shown (the bounding box of the visible layers) from the current direction.
  fitView() {
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (const [name, layer] of Object.entries(this.layers)) {
      if (!this.layerShown(name)) continue;
      for (let k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], layer.bbox.min[k]); hi[k] = Math.max(hi[k], layer.bbox.max[k]); }
    }
    if (!(lo[0] <= hi[0])) return;
    const radius = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || this.home.radius;
    Object.assign(this.camera, { target: [0, 1, 2].map((k) => 0.5 * (lo[k] + hi[k])), radius, distance: 2.8 * radius });
    this.requestDraw();
  }

  /// Looks along an axis: view is '+x' (from +x towards the centre), '-x', '+y', '-y', '+z' or '-z'.
  viewFrom(view) {
    const angles = { '+x': [Math.PI / 2, 0], '-x': [-Math.PI / 2, 0], '+z': [0, 0], '-z': [Math.PI, 0],
                     '+y': [0, 1.55], '-y': [0, -1.55] }[view];  // ±1.55 rad: straight down has no 'up'
    if (!angles) throw new Error(`unknown view '${view}'`);
    [this.camera.yaw, this.camera.pitch] = angles;
    this.requestDraw();
  }

  /// The view as a PNG Blob at full resolution.
  screenshot() {
    this.moving = false;
    this.draw({ force: true });
    return new Promise((resolve, reject) => this.canvas.toBlob((b) => (b ? resolve(b) : reject(new Error('the view could not be encoded'))), 'image/png'));
  }

  /// What is under the canvas point (clientX, clientY): the nearest hit of the cut or the spline
  /// boundary (the part the cut leaves), or the input mesh when no result is shown, as
  /// {layer, xyz, scalar} (scalar interpolated at the hit, null if the layer has none), or null.
  pick(clientX, clientY) {
    const r = this.canvas.getBoundingClientRect();
    if (!r.width || !r.height) return null;
    const x = (2 * (clientX - r.left)) / r.width - 1, y = 1 - (2 * (clientY - r.top)) / r.height;
    const eye = this.eye(), [right, up] = this.screenAxes();
    const t = Math.tan(0.8 / 2);  // the projection's vertical field of view is 0.8 rad
    const forward = [0, 1, 2].map((k) => this.camera.target[k] - eye[k]);
    const f = Math.hypot(...forward);
    const dir = [0, 1, 2].map((k) => forward[k] / f + x * t * (r.width / r.height) * right[k] + y * t * up[k]);
    let best = null;
    const candidates = this.hasResult ? ['cut', 'boundary', 'cuboids'] : ['input'];
    for (const name of candidates) {
      const layer = this.layers[name];
      if (!layer || !this.layerShown(name) || layer.data.mode !== 'triangles') continue;
      const cutAway = name === 'boundary' && this.cut && this.visible.cut ? this.cut : null;
      const hit = rayHit(layer.data, eye, dir, cutAway);
      if (hit && (!best || hit.distance < best.distance)) best = { ...hit, layer: name };
    }
    return best && { layer: best.layer, xyz: best.xyz, scalar: best.scalar };
  }

  /// Whether layer `name` is drawn with the current visibility settings.
  layerShown(name) {
    const v = this.visible, result = this.hasResult;
    switch (name) {
      case 'input': return v.input;
      case 'wireframe': return v.input && v.wireframe;
      case 'lines': return v.boundary && v.lines;
      case 'lattice': return v.control && v.lattice;
      case 'corners': return v.poly_edges;
      default: return v[name] !== false;
    }
  }

  installControls() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    c.addEventListener('pointerdown', (e) => {
      c.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
      clearTimeout(this.settleTimer);
      this.moving = true;
    });
    c.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      drag.x = e.clientX; drag.y = e.clientY;
      const cam = this.camera;
      if (drag.pan) {
        const s = cam.distance / c.clientHeight;
        const [right, up] = this.screenAxes();
        for (let k = 0; k < 3; k++) cam.target[k] += s * (-dx * right[k] + dy * up[k]);
      } else {
        cam.yaw -= 0.01 * dx;
        cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + 0.01 * dy));
      }
      this.requestDraw();
    });
    const end = () => {
      drag = null;
      if (this.moving) { this.moving = false; this.requestDraw(); }
    };
    c.addEventListener('pointerup', end);
    c.addEventListener('pointercancel', end);
    c.addEventListener('wheel', (e) => {
      e.preventDefault();
      this.camera.distance *= Math.exp(0.001 * e.deltaY);
      if (!drag) {
        this.moving = true;
        clearTimeout(this.settleTimer);
        this.settleTimer = setTimeout(end, WHEEL_SETTLE_MS);
      }
      this.requestDraw();
    }, { passive: false });
    c.addEventListener('dblclick', () => this.resetCamera(this.home.target, this.home.radius));
  }

  eye() {
    const { target, distance, yaw, pitch } = this.camera;
    return [target[0] + distance * Math.cos(pitch) * Math.sin(yaw),
            target[1] + distance * Math.sin(pitch),
            target[2] + distance * Math.cos(pitch) * Math.cos(yaw)];
  }

  screenAxes() {
    const { yaw, pitch } = this.camera;
    const right = [Math.cos(yaw), 0, -Math.sin(yaw)];
    const up = [-Math.sin(pitch) * Math.sin(yaw), Math.cos(pitch), -Math.sin(pitch) * Math.cos(yaw)];
    return [right, up];
  }

  /// Coalesces redraws into the next animation frame.
  requestDraw() {
    if (this.pending) return;
    this.pending = requestAnimationFrame(() => { this.pending = 0; this.draw(); });
  }

  drawLayer(name, { colour, lit = false, cutAway = false, pointSize = 1, scalarMap = 0 }) {
    const base = this.layers[name];
    const layer = this.moving && base?.motion ? base.motion : base;
    if (!layer || layer === 'hide' || !layer.count) return;
    const gl = this.gl, u = this.uniforms;
    gl.uniform4f(u.colour, ...colour);
    gl.uniform1i(u.lit, lit ? 1 : 0);
    gl.uniform1i(u.use_scalar, layer.hasScalar ? 1 : 0);
    gl.uniform1i(u.scalar_map, scalarMap);
    gl.uniform1i(u.use_vertex_colour, layer.hasColours ? 1 : 0);
    gl.uniform1i(u.cut_axis, cutAway && this.cut && layer.hasUvw && this.visible.cut ? this.cut.axis : -1);
    gl.uniform1f(u.cut_position, this.cut ? this.cut.position : 0);
    gl.uniform1f(u.point_size, pointSize);
    gl.bindVertexArray(layer.vao);
    if (layer.indexed) gl.drawElements(layer.mode, layer.count, gl.UNSIGNED_INT, 0);
    else gl.drawArrays(layer.mode, 0, layer.count);
  }

  /// Draws a frame if anything shown changed since the last one (force: draw anyway). A hidden
  /// canvas (its tab not shown) keeps its last frame.
  draw({ force = false } = {}) {
    const gl = this.gl, c = this.canvas;
    if (!c.clientWidth || !c.clientHeight) return;
    const dpr = (window.devicePixelRatio || 1) * (this.moving ? MOTION_SCALE : 1);
    const w = Math.max(1, Math.round(c.clientWidth * dpr)), h = Math.max(1, Math.round(c.clientHeight * dpr));
    const state = JSON.stringify([this.camera, this.visible, this.cut, this.layersVersion, w, h, !!this.moving]);
    if (!force && state === this.drawnState) return;
    this.drawnState = state;
    const t0 = performance.now();
    this.draws = (this.draws || 0) + 1;
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    // Still frames are drawn multisampled into their own framebuffer and resolved onto the canvas;
    // moving frames straight onto the canvas (its context has no multisampling: in SwiftShader
    // 4× MSAA makes every frame about 4× slower, vertices included).
    const msaa = !this.moving && this.multisampleTarget(w, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, msaa || null);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.96, 0.97, 0.98, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    if (Object.keys(this.layers).length) this.drawScene(w, h, dpr);
    if (msaa) {
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, msaa);
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
      gl.blitFramebuffer(0, 0, w, h, 0, 0, w, h, gl.COLOR_BUFFER_BIT, gl.NEAREST);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    }
    this.lastDrawMs = performance.now() - t0;
  }

  /// A 4× multisampled framebuffer of w × h (colour and depth), kept between frames; null where
  /// the context offers no multisampling.
  multisampleTarget(w, h) {
    const gl = this.gl;
    const samples = Math.min(4, gl.getParameter(gl.MAX_SAMPLES) || 0);
    if (samples < 2) return null;
    const t = this.msaa;
    if (t && t.w === w && t.h === h) return t.framebuffer;
    if (t) { gl.deleteFramebuffer(t.framebuffer); gl.deleteRenderbuffer(t.colour); gl.deleteRenderbuffer(t.depth); }
    const framebuffer = gl.createFramebuffer(), colour = gl.createRenderbuffer(), depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, colour);
    gl.renderbufferStorageMultisample(gl.RENDERBUFFER, samples, gl.RGBA8, w, h);
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorageMultisample(gl.RENDERBUFFER, samples, gl.DEPTH_COMPONENT24, w, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, colour);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    const complete = gl.checkFramebufferStatus(gl.FRAMEBUFFER) === gl.FRAMEBUFFER_COMPLETE;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.msaa = complete ? { w, h, framebuffer, colour, depth } : null;
    return complete ? framebuffer : null;
  }

  drawScene(w, h, dpr) {
    const gl = this.gl, cam = this.camera;
    const view = mat4.lookAt(this.eye(), cam.target);
    const near = Math.max(cam.distance - 2 * cam.radius, cam.distance * 0.01), far = cam.distance + 2 * cam.radius;
    const projection = mat4.perspective(0.8, w / h, near, far);
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(this.uniforms.view_projection, false, mat4.multiply(projection, view));
    gl.uniformMatrix4fv(this.uniforms.view, false, view);
    gl.enable(gl.DEPTH_TEST);
    const v = this.visible, spline = this.hasResult;
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    if (v.input && !spline) this.drawLayer('input', { colour: [0.42, 0.62, 0.85, 1], lit: true });
    if (v.boundary) this.drawLayer('boundary', { colour: [0.8, 0.8, 0.82, 1], lit: true, cutAway: true, scalarMap: 1 });
    if (v.cut) this.drawLayer('cut', { colour: [1, 1, 1, 1], lit: true });
    if (v.cuboids) this.drawLayer('cuboids', { colour: [1, 1, 1, 1], lit: true });
    gl.disable(gl.POLYGON_OFFSET_FILL);
    if (v.boundary && v.lines) this.drawLayer('lines', { colour: [0.05, 0.05, 0.15, 1], cutAway: true });
    if (v.poly_edges) {
      this.drawLayer('poly_edges', { colour: [0.05, 0.05, 0.1, 1] });
      this.drawLayer('corners', { colour: [1, 1, 1, 1], pointSize: Math.max(5, 7 * dpr) });  // white: visible on every cuboid colour
    }
    if (v.control && v.lattice) this.drawLayer('lattice', { colour: [0.75, 0.2, 0.5, 1], cutAway: true });
    if (v.control) this.drawLayer('control', { colour: [0.85, 0.1, 0.45, 1], pointSize: Math.max(2, 3 * dpr), cutAway: true });
    if (v.folds) {
      // Folded points over everything: they are inside the solid.
      gl.disable(gl.DEPTH_TEST);
      this.drawLayer('folds', { colour: [0.9, 0.05, 0.05, 1], pointSize: Math.max(4, 6 * dpr) });
      gl.enable(gl.DEPTH_TEST);
    }
    if (v.input && spline) {
      // Over a result the input mesh is context: a translucent surface (and its faint wireframe)
      // that hides nothing behind it.
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthMask(false);
      this.drawLayer('input', { colour: [0.42, 0.62, 0.85, 0.25], lit: true });
      if (v.wireframe && !this.moving) this.drawLayer('wireframe', { colour: [0.3, 0.45, 0.7, 0.35] });
      gl.disable(gl.BLEND);
      gl.depthMask(true);
    } else if (v.input && v.wireframe) {
      this.drawLayer('wireframe', { colour: [0.1, 0.18, 0.3, 1] });
    }
    gl.bindVertexArray(null);
  }
}

function boundingBox(positions) {
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3)
    for (let k = 0; k < 3; k++) {
      const x = positions[i + k];
      if (x < min[k]) min[k] = x;
      if (x > max[k]) max[k] = x;
    }
  return { min, max };
}

/// A coarse copy of a triangle layer with about `target` triangles, by vertex clustering: the
/// vertices in each cell of a cubic grid over the bounding box merge at their mean (attributes
/// averaged too), triangles with two corners in one cell vanish. The grid is refined or coarsened
/// until the count is within 60–100 % of target. Non-indexed layers cluster the same way.
export function coarseTriangles({ positions, uvw, scalar, colours, indices }, target) {
  const n = positions.length / 3;
  const tri = indices ?? Uint32Array.from({ length: n }, (_, i) => i);
  const { min, max } = boundingBox(positions);
  const extent = Math.max(max[0] - min[0], max[1] - min[1], max[2] - min[2]) || 1;
  const cellOf = new Int32Array(n);
  let cells = Math.max(4, Math.round(Math.sqrt(target)));
  let best = null;
  for (let attempt = 0; attempt < 6; attempt++) {
    const ids = new Map();
    const h = extent / cells;
    for (let i = 0; i < n; i++) {
      const key = ((Math.min(cells - 1, Math.floor((positions[3 * i] - min[0]) / h)) * cells +
                    Math.min(cells - 1, Math.floor((positions[3 * i + 1] - min[1]) / h))) * cells +
                   Math.min(cells - 1, Math.floor((positions[3 * i + 2] - min[2]) / h)));
      let id = ids.get(key);
      if (id === undefined) { id = ids.size; ids.set(key, id); }
      cellOf[i] = id;
    }
    let kept = 0;
    for (let f = 0; f < tri.length; f += 3) {
      const a = cellOf[tri[f]], b = cellOf[tri[f + 1]], c = cellOf[tri[f + 2]];
      if (a !== b && b !== c && a !== c) kept++;
    }
    best = { clusters: ids.size, kept, cellOf: cellOf.slice() };
    if (kept <= target && kept >= 0.6 * target) break;
    cells = Math.max(2, Math.round(cells * Math.sqrt(target / Math.max(kept, 1)) * (kept > target ? 0.95 : 1)));
    if (kept <= target && attempt >= 3) break;
  }
  const { clusters, kept, cellOf: cluster } = best;
  const mean = (data, size) => {
    if (!data) return null;
    const out = new Float32Array(clusters * size), count = new Uint32Array(clusters);
    for (let i = 0; i < n; i++) {
      count[cluster[i]]++;
      for (let k = 0; k < size; k++) out[size * cluster[i] + k] += data[size * i + k];
    }
    for (let c = 0; c < clusters; c++) for (let k = 0; k < size; k++) out[size * c + k] /= count[c];
    return out;
  };
  const out = new Uint32Array(3 * kept);
  let m = 0;
  for (let f = 0; f < tri.length; f += 3) {
    const a = cluster[tri[f]], b = cluster[tri[f + 1]], c = cluster[tri[f + 2]];
    if (a !== b && b !== c && a !== c) { out[m++] = a; out[m++] = b; out[m++] = c; }
  }
  return { positions: mean(positions, 3), uvw: mean(uvw, 3), scalar: mean(scalar, 1), colours: mean(colours, 3), indices: out, mode: 'triangles' };
}

/// Every k-th point of a point layer, with its attributes.
/// A coarse copy of a non-indexed line layer (vertex pairs) with at most `target` segments: where a
/// segment starts at the end of the one before, the two become one (their shared vertex dropped),
/// repeated until the count is reached; attributes follow their vertices. Null if the layer is
/// indexed or its segments do not chain enough.
export function coarseLines({ positions, uvw, scalar, colours, indices }, target) {
  if (indices) return null;
  let layer = { positions, uvw, scalar, colours };
  const same = (p, a, b) => p[3 * a] === p[3 * b] && p[3 * a + 1] === p[3 * b + 1] && p[3 * a + 2] === p[3 * b + 2];
  while (layer.positions.length / 6 > target) {
    const p = layer.positions, segments = p.length / 6;
    const keep = [];  // vertex ids of the coarse copy, two per segment
    for (let s = 0; s < segments; s++) {
      if (s + 1 < segments && same(p, 2 * s + 1, 2 * s + 2)) { keep.push(2 * s, 2 * s + 3); s++; } else keep.push(2 * s, 2 * s + 1);
    }
    if (keep.length === 2 * segments) return null;
    const pick = (data, size) => {
      if (!data) return null;
      const out = new Float32Array(keep.length * size);
      keep.forEach((v, i) => { for (let k = 0; k < size; k++) out[size * i + k] = data[size * v + k]; });
      return out;
    };
    layer = { positions: pick(layer.positions, 3), uvw: pick(layer.uvw, 3), scalar: pick(layer.scalar, 1), colours: pick(layer.colours, 3) };
  }
  return { ...layer, indices: null, mode: 'lines' };
}

function everyKthPoint({ positions, uvw, scalar, colours }, k) {
  const pick = (data, size) => {
    if (!data) return null;
    const n = Math.ceil(data.length / size / k), out = new Float32Array(n * size);
    for (let i = 0; i < n; i++) for (let s = 0; s < size; s++) out[size * i + s] = data[size * i * k + s];
    return out;
  };
  return { positions: pick(positions, 3), uvw: pick(uvw, 3), scalar: pick(scalar, 1), colours: pick(colours, 3), indices: null, mode: 'points' };
}

/// The nearest triangle of a layer hit by the ray eye + s·dir (s > 0), Möller–Trumbore, skipping
/// triangles whose corners all lie beyond cutAway {axis, position} in uvw: {distance, xyz, scalar}.
function rayHit({ positions, uvw, scalar, indices }, eye, dir, cutAway) {
  const n = indices ? indices.length : positions.length / 3;
  let best = null;
  const p = (i, k) => positions[3 * i + k];
  for (let f = 0; f < n; f += 3) {
    const a = indices ? indices[f] : f, b = indices ? indices[f + 1] : f + 1, c = indices ? indices[f + 2] : f + 2;
    if (cutAway && uvw && [a, b, c].every((i) => uvw[3 * i + cutAway.axis] > cutAway.position + 1e-4)) continue;
    const e1 = [p(b, 0) - p(a, 0), p(b, 1) - p(a, 1), p(b, 2) - p(a, 2)];
    const e2 = [p(c, 0) - p(a, 0), p(c, 1) - p(a, 1), p(c, 2) - p(a, 2)];
    const h = [dir[1] * e2[2] - dir[2] * e2[1], dir[2] * e2[0] - dir[0] * e2[2], dir[0] * e2[1] - dir[1] * e2[0]];
    const det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
    if (Math.abs(det) < 1e-20) continue;
    const s = [eye[0] - p(a, 0), eye[1] - p(a, 1), eye[2] - p(a, 2)];
    const u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
    if (u < 0 || u > 1) continue;
    const q = [s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]];
    const v = (dir[0] * q[0] + dir[1] * q[1] + dir[2] * q[2]) / det;
    if (v < 0 || u + v > 1) continue;
    const d = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (d <= 0 || (best && d >= best.distance)) continue;
    best = { distance: d, xyz: [0, 1, 2].map((k) => p(a, k) + u * e1[k] + v * e2[k]),
             scalar: scalar ? (1 - u - v) * scalar[a] + u * scalar[b] + v * scalar[c] : null };
  }
  return best;
}
