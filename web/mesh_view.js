// SPDX-License-Identifier: MIT
// WebGL2 view of a triangle mesh with orbit controls: drag to rotate, wheel to zoom,
// shift-drag or right-drag to pan, double-click to reset. Flat shading from screen-space
// derivatives (no normals needed), optional wireframe overlay.
import { createProgram, mat4 } from './gl_util.js';

const VERTEX = `#version 300 es
in vec3 position;
uniform mat4 view_projection;
uniform mat4 view;
out vec3 view_position;
void main() {
  view_position = (view * vec4(position, 1.0)).xyz;
  gl_Position = view_projection * vec4(position, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
in vec3 view_position;
uniform vec4 colour;
uniform bool lit;
out vec4 out_colour;
void main() {
  if (!lit) { out_colour = colour; return; }
  vec3 n = normalize(cross(dFdx(view_position), dFdy(view_position)));
  vec3 l = normalize(vec3(0.4, 0.6, 1.0));
  float diffuse = abs(dot(n, l));
  out_colour = vec4(colour.rgb * (0.25 + 0.75 * diffuse), colour.a);
}`;

export class MeshView {
  /// `canvas`: the element to draw into. Throws an Error if WebGL2 is unavailable.
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser');
    this.gl = gl;
    this.program = createProgram(gl, VERTEX, FRAGMENT);
    this.uniforms = Object.fromEntries(['view_projection', 'view', 'colour', 'lit'].map((n) => [n, gl.getUniformLocation(this.program, n)]));
    this.vao = gl.createVertexArray();
    this.buffers = { position: gl.createBuffer(), triangles: gl.createBuffer(), lines: gl.createBuffer() };
    this.counts = { triangles: 0, lines: 0 };
    this.wireframe = true;
    this.resetCamera([0, 0, 0], 1);
    this.installControls();
    new ResizeObserver(() => this.draw()).observe(canvas);
  }

  /// Shows a mesh: positions Float32Array (3 per vertex), triangles Uint32Array (3 per face),
  /// bbox_min/bbox_max [x,y,z]. The camera is reset to frame the bounding box.
  setMesh(positions, triangles, bboxMin, bboxMax) {
    const gl = this.gl;
    gl.bindVertexArray(this.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.buffers.position);
    gl.bufferData(gl.ARRAY_BUFFER, positions, gl.STATIC_DRAW);
    const loc = gl.getAttribLocation(this.program, 'position');
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.triangles);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, triangles, gl.STATIC_DRAW);
    this.counts.triangles = triangles.length;
    // Unique edges for the wireframe, keyed by (min, max) vertex pair.
    const seen = new Set();
    const lines = [];
    for (let f = 0; f < triangles.length; f += 3) {
      for (let k = 0; k < 3; k++) {
        const a = triangles[f + k], b = triangles[f + ((k + 1) % 3)];
        const key = a < b ? a * 4294967296 + b : b * 4294967296 + a;
        if (!seen.has(key)) { seen.add(key); lines.push(a, b); }
      }
    }
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.lines);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(lines), gl.STATIC_DRAW);
    this.counts.lines = lines.length;
    const centre = [0, 1, 2].map((k) => 0.5 * (bboxMin[k] + bboxMax[k]));
    const radius = 0.5 * Math.hypot(...[0, 1, 2].map((k) => bboxMax[k] - bboxMin[k])) || 1;
    this.resetCamera(centre, radius);
  }

  resetCamera(target, radius) {
    this.home = { target: [...target], radius };
    this.camera = { target: [...target], radius, distance: 2.8 * radius, yaw: 0.6, pitch: 0.35 };
    this.draw();
  }

  installControls() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener('contextmenu', (e) => e.preventDefault());
    c.addEventListener('pointerdown', (e) => {
      c.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 };
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
    const end = () => { drag = null; };
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

  requestDraw() {
    if (this.pending) return;
    this.pending = requestAnimationFrame(() => { this.pending = 0; this.draw(); });
  }

  draw() {
    const gl = this.gl, c = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(c.clientWidth * dpr)), h = Math.max(1, Math.round(c.clientHeight * dpr));
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.96, 0.97, 0.98, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    if (!this.counts.triangles) return;
    const cam = this.camera;
    const view = mat4.lookAt(this.eye(), cam.target);
    const near = Math.max(cam.distance - 2 * cam.radius, cam.distance * 0.01), far = cam.distance + 2 * cam.radius;
    const projection = mat4.perspective(0.8, w / h, near, far);
    gl.useProgram(this.program);
    gl.uniformMatrix4fv(this.uniforms.view_projection, false, mat4.multiply(projection, view));
    gl.uniformMatrix4fv(this.uniforms.view, false, view);
    gl.bindVertexArray(this.vao);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    gl.uniform1i(this.uniforms.lit, 1);
    gl.uniform4f(this.uniforms.colour, 0.42, 0.62, 0.85, 1);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.triangles);
    gl.drawElements(gl.TRIANGLES, this.counts.triangles, gl.UNSIGNED_INT, 0);
    gl.disable(gl.POLYGON_OFFSET_FILL);
    if (this.wireframe && this.counts.lines) {
      gl.uniform1i(this.uniforms.lit, 0);
      gl.uniform4f(this.uniforms.colour, 0.1, 0.18, 0.3, 1);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, this.buffers.lines);
      gl.drawElements(gl.LINES, this.counts.lines, gl.UNSIGNED_INT, 0);
    }
    gl.bindVertexArray(null);
  }
}
