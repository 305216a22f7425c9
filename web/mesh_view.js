// SPDX-License-Identifier: MIT
// WebGL2 view of the mesh tab with orbit controls: drag to rotate, wheel to zoom, shift-drag or
// right-drag to pan, double-click to reset. Layers, each shown or hidden by name:
//   input     the input mesh (lit triangles) and its wireframe ('wireframe')
//   boundary  the spline's boundary surface and its iso-parameter lines ('lines')
//   control   the control points (drawn over everything)
//   cut       the cut through the volume, coloured by scaled Jacobian
//   cuboids   a GPC domain: the surface coloured by cuboid, its poly-edges and corners ('poly_edges')
// The boundary and its lines are cut away on the far side of the cut (uvw[axis] > position), so
// the cut is visible inside the solid. Flat shading from screen-space derivatives.
import { VERTEX, FRAGMENT } from './shaders/mesh_shaders.js';
import { createProgram, mat4 } from './gl_util.js';

// Input meshes with more triangles get no wireframe layer (see setMesh).
const WIREFRAME_MAX_TRIANGLES = 20000;
// While the camera moves, frames render at this fraction of the canvas resolution (level of
// detail for software GL, whose cost follows the pixels); the frame after the motion is full size.
const MOTION_SCALE = 0.5;
// The layers of a mesh2spline result and of a gpc result: showing one drops the other.
const SPLINE_LAYERS = ['boundary', 'lines', 'control', 'cut'];
const GPC_LAYERS = ['cuboids', 'poly_edges', 'corners'];

/// Legend colours of the scaled Jacobian (CSS), matching the shader.
export const QUALITY_GRADIENT = 'linear-gradient(to right, rgb(242,115,26) 0%, rgb(250,217,51) 33%, rgb(77,191,89) 67%, rgb(51,102,217) 100%)';

export class MeshView {
  /// `canvas`: the element to draw into. Throws an Error if WebGL2 is unavailable.
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl;
    this.program = createProgram(gl, VERTEX, FRAGMENT);
    this.uniforms = Object.fromEntries(['view_projection', 'view', 'colour', 'lit', 'use_scalar', 'use_vertex_colour', 'cut_axis', 'cut_position', 'point_size']
      .map((n) => [n, gl.getUniformLocation(this.program, n)]));
    this.attributes = Object.fromEntries(['position', 'uvw', 'scalar', 'vertex_colour'].map((n) => [n, gl.getAttribLocation(this.program, n)]));
    this.layers = {};   // name -> {vao, buffers, count, mode, indexed}
    this.visible = { input: true, wireframe: true, boundary: true, lines: true, control: true, cut: true, cuboids: true, poly_edges: true };
    this.cut = null;    // {axis, position} while a cut is shown
    this.resetCamera([0, 0, 0], 1);
    this.installControls();
    new ResizeObserver(() => this.requestDraw()).observe(canvas);
  }

  /// Replaces layer `name`: positions Float32Array (3 per vertex); optional uvw Float32Array
  /// (3 per vertex, fractions of the domain), scalar Float32Array (1 per vertex), colours
  /// Float32Array (RGB in [0, 1], 3 per vertex), indices Uint32Array; mode 'triangles' | 'lines' |
  /// 'points'. Null positions remove the layer.
  setLayer(name, { positions, uvw = null, scalar = null, colours = null, indices = null, mode = 'triangles' } = {}) {
    const gl = this.gl;
    const old = this.layers[name];
    if (old) {
      gl.deleteVertexArray(old.vao);
      for (const b of old.buffers) gl.deleteBuffer(b);
      delete this.layers[name];
    }
    if (!positions) { this.requestDraw(); return; }
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
    this.layers[name] = { vao, buffers, count: indices ? indices.length : positions.length / 3, mode: glMode, indexed: !!indices, hasUvw: !!uvw, hasScalar: !!scalar, hasColours: !!colours };
    this.requestDraw();
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

  /// Shows a mesh2spline result: r.boundary {positions, uvw, triangles}, r.lines {positions, uvw},
  /// r.control_points, and r.cut (see setCut). The input mesh stays as a faint wireframe.
  setSpline(r) {
    for (const name of GPC_LAYERS) this.setLayer(name, {});
    this.boundarySamples = { positions: r.boundary.positions, uvw: r.boundary.uvw };
    this.cut = null;  // the first cut turns the camera towards it
    this.setLayer('boundary', { positions: r.boundary.positions, uvw: r.boundary.uvw, indices: r.boundary.triangles });
    this.setLayer('lines', { positions: r.lines.positions, uvw: r.lines.uvw, mode: 'lines' });
    this.setLayer('control', { positions: r.control_points, mode: 'points' });
    this.setCut(r.cut);
  }

  /// Shows a cut {axis, position, positions, triangles, scaled_jacobian}, or none for null.
  setCut(cut) {
    const turn = cut && (!this.cut || this.cut.axis !== cut.axis);
    this.cut = cut ? { axis: cut.axis, position: cut.position } : null;
    this.setLayer('cut', cut ? { positions: cut.positions, scalar: cut.scaled_jacobian, indices: cut.triangles } : {});
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

  installControls() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    c.addEventListener('pointerdown', (e) => {
      c.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
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

  drawLayer(name, { colour, lit = false, cutAway = false, pointSize = 1 }) {
    const layer = this.layers[name];
    if (!layer || !layer.count) return;
    const gl = this.gl, u = this.uniforms;
    gl.uniform4f(u.colour, ...colour);
    gl.uniform1i(u.lit, lit ? 1 : 0);
    gl.uniform1i(u.use_scalar, layer.hasScalar ? 1 : 0);
    gl.uniform1i(u.use_vertex_colour, layer.hasColours ? 1 : 0);
    gl.uniform1i(u.cut_axis, cutAway && this.cut && layer.hasUvw && this.visible.cut ? this.cut.axis : -1);
    gl.uniform1f(u.cut_position, this.cut ? this.cut.position : 0);
    gl.uniform1f(u.point_size, pointSize);
    gl.bindVertexArray(layer.vao);
    if (layer.indexed) gl.drawElements(layer.mode, layer.count, gl.UNSIGNED_INT, 0);
    else gl.drawArrays(layer.mode, 0, layer.count);
  }

  draw() {
    const gl = this.gl, c = this.canvas;
    const t0 = performance.now();
    this.draws = (this.draws || 0) + 1;
    const dpr = (window.devicePixelRatio || 1) * (this.moving ? MOTION_SCALE : 1);
    const w = Math.max(1, Math.round(c.clientWidth * dpr)), h = Math.max(1, Math.round(c.clientHeight * dpr));
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.96, 0.97, 0.98, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    if (!Object.keys(this.layers).length) return;
    const cam = this.camera;
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
    // With a spline shown, the input mesh is context only: its wireframe, no surface.
    if (v.input && !spline) this.drawLayer('input', { colour: [0.42, 0.62, 0.85, 1], lit: true });
    if (v.boundary) this.drawLayer('boundary', { colour: [0.8, 0.8, 0.82, 1], lit: true, cutAway: true });
    if (v.cut) this.drawLayer('cut', { colour: [1, 1, 1, 1], lit: true });
    if (v.cuboids) this.drawLayer('cuboids', { colour: [1, 1, 1, 1], lit: true });
    gl.disable(gl.POLYGON_OFFSET_FILL);
    if (v.boundary && v.lines) this.drawLayer('lines', { colour: [0.05, 0.05, 0.15, 1], cutAway: true });
    if (v.poly_edges) {
      this.drawLayer('poly_edges', { colour: [0.05, 0.05, 0.1, 1] });
      this.drawLayer('corners', { colour: [1, 1, 1, 1], pointSize: Math.max(5, 7 * dpr) });  // white: visible on every cuboid colour
    }
    if (v.control) this.drawLayer('control', { colour: [0.85, 0.1, 0.45, 1], pointSize: Math.max(2, 3 * dpr) });
    if (v.input && v.wireframe && !(this.moving && spline)) {
      // Over a spline the input mesh is faint context: blended, and not hiding what is behind.
      if (spline) { gl.enable(gl.BLEND); gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA); gl.depthMask(false); }
      this.drawLayer('wireframe', { colour: spline ? [0.3, 0.45, 0.7, 0.35] : [0.1, 0.18, 0.3, 1] });
      gl.disable(gl.BLEND);
      gl.depthMask(true);
    }
    gl.bindVertexArray(null);
    this.lastDrawMs = performance.now() - t0;
  }
}
