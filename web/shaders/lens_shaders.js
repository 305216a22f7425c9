// SPDX-License-Identifier: MIT
// @ts-check
// GLSL ES 3.00 shaders of the lens view (lens_view.js).

export const VERTEX = `#version 300 es
in vec2 position;   // output pixels
in vec2 texcoord;   // input pixels
uniform vec2 size;  // image width, height
uniform vec4 rect;  // the canvas's image rectangle: x, y, width, height (pixels)
out vec2 uv;
void main() {
  uv = texcoord / size;
  vec2 clip = (position - rect.xy) / rect.zw * 2.0 - 1.0;
  gl_Position = vec4(clip.x, -clip.y, 0.0, 1.0);
}`;

export const FRAGMENT = `#version 300 es
precision highp float;
in vec2 uv;
uniform sampler2D image;
out vec4 colour;
void main() { colour = texture(image, uv); }`;

// The displacement field of a mesh, texcoord − position (input pixels), rendered into an RG32F
// texture: the lens of a live drag is a solved lens translated, whose field is the same one read
// at an offset, so a live frame draws one quad instead of the mesh's triangles.
export const DISPLACEMENT_FRAGMENT = `#version 300 es
precision highp float;
in vec2 displacement;
out vec4 colour;
void main() { colour = vec4(displacement, 0.0, 1.0); }`;

export const DISPLACEMENT_VERTEX = `#version 300 es
in vec2 position;
in vec2 texcoord;
uniform vec4 rect;
out vec2 displacement;
void main() {
  displacement = texcoord - position;
  vec2 clip = (position - rect.xy) / rect.zw * 2.0 - 1.0;
  gl_Position = vec4(clip.x, -clip.y, 0.0, 1.0);
}`;

// A live frame: output pixel x shows the input at x + D(x − offset), D read bilinearly from the
// field texture (zero at its border, clamped: the identity outside) and the input sampled like the
// mesh's texture. Two texture reads per pixel; branches and texelFetch cost SwiftShader ~4× more.
export const SHIFT_VERTEX = `#version 300 es
in vec2 corner;
void main() { gl_Position = vec4(corner, 0.0, 1.0); }`;

export const SHIFT_FRAGMENT = `#version 300 es
precision highp float;
uniform sampler2D image;
uniform highp sampler2D field;
uniform vec2 size;        // image width, height
uniform vec4 rect;        // this canvas's image rectangle
uniform vec4 fieldRect;   // the field texture's image rectangle
uniform vec2 offset;      // translation of the lens since the field's mesh (input pixels)
out vec4 colour;
void main() {
  vec2 x = vec2(rect.x + gl_FragCoord.x, rect.y + rect.w - gl_FragCoord.y);  // image pixels, y down
  vec2 q = (x - offset - fieldRect.xy) / fieldRect.zw;
  vec2 d = texture(field, vec2(q.x, 1.0 - q.y)).rg;  // the field's rows run upwards
  colour = texture(image, (x + d) / size);
}`;
