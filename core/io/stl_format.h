// SPDX-License-Identifier: MIT
#pragma once

#include <string>

#include "core/mesh/triangle_mesh.h"

namespace volspline::io {

/// Parses STL, binary (detected by its size 84 + 50·n with n the header's triangle count) or
/// ASCII (`solid` ... `facet` / `outer loop` / 3 × `vertex x y z` / `endloop` / `endfacet`).
/// Corners with exactly equal positions are merged into one vertex; vertices are numbered in
/// order of first appearance, so the result is deterministic.
/// Throws volspline::Error naming `name` and the line or triangle on truncation, a size that
/// fits neither form, bad numbers, NaN/Inf, facets without 3 vertices, no facets.
mesh::TriangleMesh parse_stl(const std::string& bytes, const std::string& name);

}  // namespace volspline::io
