// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include <Eigen/Core>

namespace volspline::io {

/// A flat triangle mesh with texture coordinates over an image, to be written as a textured GLB.
struct TexturedPlane {
  Eigen::MatrixX2d positions;  ///< n×2 positions in pixels of the output, y down (image rows)
  Eigen::MatrixX2d texture;    ///< n×2 positions in pixels of the texture image, y down
  Eigen::MatrixX3i triangles;  ///< m×3 vertex ids, positive signed area in (x, y) pixels (as the lens writes them)
  int output_height = 0;       ///< output rows (y-up positions are output_height − y)
  int texture_width = 0;       ///< texture image size in pixels (> 0)
  int texture_height = 0;
  std::string texture_png;     ///< PNG bytes of the texture image, embedded in the GLB
};

/// GLB (binary glTF 2.0) of the plane: one scene, one node, one triangle primitive with
/// POSITION (x, output_height − y, 0) in pixels, y up as glTF expects, NORMAL +z, TEXCOORD_0
/// (x / texture_width, y / texture_height: glTF's UV origin is the image's top-left corner) and
/// the PNG as the material's base colour texture, so it opens textured in Blender and three.js.
/// Triangles face +z. Throws volspline::Error on an empty mesh, an id out of range or a missing
/// texture.
std::string serialize_textured_glb(const TexturedPlane& plane);

}  // namespace volspline::io
