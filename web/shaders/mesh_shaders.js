// SPDX-License-Identifier: MIT
// @ts-check
// GLSL ES 3.00 shaders of the mesh view (mesh_view.js).

export const VERTEX = `#version 300 es
in vec3 position;
in vec3 uvw;
in float scalar;
in vec3 vertex_colour;
uniform mat4 view_projection;
uniform mat4 view;
uniform float point_size;
out vec3 view_position;
out vec3 v_uvw;
out float v_scalar;
out vec3 v_colour;
void main() {
  view_position = (view * vec4(position, 1.0)).xyz;
  v_uvw = uvw;
  v_scalar = scalar;
  v_colour = vertex_colour;
  gl_PointSize = point_size;
  gl_Position = view_projection * vec4(position, 1.0);
}`;

// Colour from the scalar (use_scalar): with scalar_map 0 the scaled Jacobian (≤ 0, folded, red;
// 0 → 1 from orange through yellow and green to blue), with scalar_map 1 a distance as a fraction
// of its target (0 pale, 0.5 amber, ≥ 1 red); else per vertex (use_vertex_colour: the cuboids of a GPC), else the
// layer's colour.
export const FRAGMENT = `#version 300 es
precision highp float;
in vec3 view_position;
in vec3 v_uvw;
in float v_scalar;
in vec3 v_colour;
uniform vec4 colour;
uniform bool lit;
uniform bool use_scalar;
uniform int scalar_map;
uniform bool use_vertex_colour;
uniform int cut_axis;      // -1: no cut-away
uniform float cut_position;
out vec4 out_colour;
vec3 quality(float q) {
  if (q <= 0.0) return vec3(0.85, 0.1, 0.1);
  vec3 c0 = vec3(0.95, 0.45, 0.1), c1 = vec3(0.98, 0.85, 0.2), c2 = vec3(0.3, 0.75, 0.35), c3 = vec3(0.2, 0.4, 0.85);
  if (q < 0.33) return mix(c0, c1, q / 0.33);
  if (q < 0.67) return mix(c1, c2, (q - 0.33) / 0.34);
  return mix(c2, c3, (q - 0.67) / 0.33);
}
vec3 distance_colour(float d) {
  vec3 c0 = vec3(0.88, 0.9, 0.95), c1 = vec3(0.98, 0.72, 0.25), c2 = vec3(0.8, 0.1, 0.1);
  d = clamp(d, 0.0, 1.0);
  return d < 0.5 ? mix(c0, c1, d / 0.5) : mix(c1, c2, (d - 0.5) / 0.5);
}
void main() {
  if (cut_axis >= 0 && v_uvw[cut_axis] > cut_position + 1e-4) discard;
  vec3 base = use_scalar ? (scalar_map == 1 ? distance_colour(v_scalar) : quality(v_scalar)) : use_vertex_colour ? v_colour : colour.rgb;
  if (!lit) { out_colour = vec4(base, colour.a); return; }
  vec3 n = normalize(cross(dFdx(view_position), dFdy(view_position)));
  vec3 l = normalize(vec3(0.4, 0.6, 1.0));
  float diffuse = abs(dot(n, l));
  out_colour = vec4(base * (0.3 + 0.7 * diffuse), colour.a);
}`;
