// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bspline_volume.h"
#include "core/spline/gpc_spline.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

/// Two patch sides glued together (the shape of G+Smo's boundaryInterface): side[s] is a cube
/// face 0..5 of patch[s] (polycube/cube_faces.h: plane axis f/2 at its lower (f%2 = 0) or upper
/// end); parameter axis i of patch[0] runs along axis[i] of patch[1], the same way if sign[i] = 1.
struct MultipatchInterface {
  std::array<int, 2> patch{-1, -1};
  std::array<int, 2> side{-1, -1};
  std::array<int, 3> axis{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
};

/// A patch side on the solid's surface.
struct MultipatchBoundary {
  int patch = -1;
  int side = -1;  ///< cube face 0..5
};

/// A spline as a conforming multipatch of clamped tensor-product cubic B-spline volumes (the
/// form G+Smo's gsMultiPatch and MFEM's NURBS meshes hold). Patch p covers the box
/// [box_min[p], box_max[p]] of cuboid cuboid[p] in that cuboid's local coordinates, and its knot
/// vectors run over that box, so a patch evaluates at the same uvw as the spline's cuboid.
/// Glued sides carry the same knot lines (conforming), so their face nets agree.
struct BsplineMultipatch {
  std::vector<BsplineVolume> patches;
  std::vector<int> cuboid;
  std::vector<Eigen::Vector3d> box_min;
  std::vector<Eigen::Vector3d> box_max;
  std::vector<MultipatchInterface> interfaces;  ///< each glued pair once
  std::vector<MultipatchBoundary> boundary;
  /// Per patch, the vertex id of corner c at (c&1, c>>1&1, c>>2&1) of its box: corners that
  /// gluing makes one point share an id (0 .. num_vertices − 1).
  std::vector<std::array<int, 8>> corner_vertex;
  int num_vertices = 0;
};

/// The restriction of a semi-standard TSpline (Eq. 4.3) to the box [box_min, box_max] (inside
/// its domain) as one clamped cubic B-spline volume, exactly (to rounding). Per axis the knot
/// vector is box_min four times, every knot line of the spline strictly inside the box (with the
/// largest multiplicity any local knot vector gives it) and every entry of extra_lines strictly
/// inside (multiplicity at least 1; entries within 1e-9 of the box length of a spline line are
/// that line), box_max four times: every blending function restricted to the box lies in that
/// space (Eq. 4.2: its knots are knot lines). The control points are the blossoms of F's
/// polynomial on a knot interval next to each coefficient's three inner knots (the de Boor–Fix
/// dual functional), so the volume equals Σ w_i p_i B_i on the box. Control point count:
/// Π_a (interior knots with multiplicity + 4). Throws volspline::Error if a local knot vector
/// repeats an interior knot 4 times (a break inside the box) or the box is not inside the domain.
BsplineVolume tspline_box_to_bspline(const TSpline& spline, const Eigen::Vector3d& box_min,
                                     const Eigen::Vector3d& box_max,
                                     const std::array<std::vector<double>, 3>& extra_lines = {});

/// A single-patch TSpline (one cuboid) as one patch over its whole domain, its six sides on the
/// boundary.
BsplineMultipatch multipatch_from_tspline(const TSpline& spline);

/// A GPC spline as one patch per cuboid box (split = 1) or split³ patches per cuboid (the box cut
/// into equal thirds, say, for readers whose topology needs distinct corners), glued per the
/// domain's interfaces. The knot lines of every patch axis are the union of those of all axes
/// glued to it as tangent axes (through the transition maps, Eq. 3.4), so glued sides conform.
/// The GPC spline is C² across Continued interfaces; the multipatch is C⁰ there as a
/// representation (the geometry is the same). Throws volspline::Error if split is not in 1..4.
BsplineMultipatch multipatch_from_gpc_spline(const GpcSpline& spline, int split = 1);

/// True if no patch repeats a vertex id among its corners and no two patch edges or faces with
/// the same vertex ids lie apart (checked on the patches' corner-net midpoints, to 1e-9 of the
/// largest extent): what a reader that identifies edges and faces by their vertices (MFEM) needs.
bool multipatch_topology_is_vertex_based(const BsplineMultipatch& multipatch);

/// multipatch_from_gpc_spline with the smallest split in 1..3 whose topology is vertex based (a
/// cuboid glued to itself, or two cuboids glued along two faces, need 3). Throws volspline::Error
/// if none is.
BsplineMultipatch vertex_based_multipatch(const GpcSpline& spline);

}  // namespace volspline::spline
