// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/polycube/cube_faces.h"
#include "core/polycube/gpc_domain.h"
#include "core/spline/tspline.h"

namespace volspline::spline {

namespace detail {
struct GpcHierarchy;
}

/// How the spline meets one face of a cuboid.
enum class GpcFaceJoin {
  Surface,    ///< on the solid's surface: clamped (4-fold end knots), no function reaches beyond (§4.3.1)
  Continued,  ///< glued, C²: blending functions cross it, their knot vectors continue into the
              ///< neighbour through the transition map (Eq. 3.4)
  Clamped,    ///< glued, C⁰: both sides clamped (4-fold end knots); the face functions of the two
              ///< sides are one global function, i.e. one shared control point (§4.4.1)
};

/// Options of GpcSpline.
struct GpcSplineOptions {
  /// Uniform knot intervals per cuboid axis (each ≥ 1), one triple per cuboid of the domain: the
  /// knot lines of cuboid c along axis a are k·size[a]/intervals[c][a], k = 0 .. intervals[c][a].
  /// Along the two tangent axes of every glued face both sides need the same count (the same
  /// knot lines, §4.4.1 step 1); gpc_uniform_intervals gives such a set.
  std::vector<std::array<int, 3>> intervals;
  /// Non-uniform knot lines, used instead of intervals when not empty: one triple of increasing
  /// lists per cuboid, knot_lines[c][a] from 0 to size[a] (at least 2 entries, gaps above 1e-9 of
  /// the largest size). Along the tangent axes of every glued face both sides need the same lines
  /// through the transition (x ↦ size − x where the axis flips); gpc_insert_knot_line keeps that.
  std::vector<std::array<std::vector<double>, 3>> knot_lines;
  /// Interfaces (ids into domain.interfaces, any order, repeats allowed) made Clamped whatever
  /// the continuity rule would allow; the rule then runs from there.
  std::vector<int> clamped_interfaces;
  /// Hierarchical local refinement (§4.3.3 over the GPC, see GpcSpline::refined): splits[s] lists
  /// the functions (indices 0 .. n−1 into the spline after steps 0 .. s−1, any order, repeats
  /// allowed) that step s replaces by their children one dyadic level finer. Empty: a plain
  /// B-spline over the knot lines above.
  std::vector<std::vector<int>> splits;
  /// If > 0, construction stops with volspline::Error as soon as a split step holds more functions
  /// (a reader passes the number of control points its file holds).
  long max_functions = 0;
  int dimension = 3;  ///< components D of a control point, 1..4 (3 for geometry)
};

/// Where a global blending function is anchored: its Greville abscissa (the mean of its inner
/// three knots per axis) in the local coordinates of a cuboid whose box holds it.
struct GpcAnchor {
  int cuboid = -1;
  Eigen::Vector3d uvw = Eigen::Vector3d::Zero();
};

/// A cubic T-spline over a generalized poly-cube (GPC-spline, §3.5): global blending functions
/// with global control points and weights, evaluated in any cuboid's local coordinates through
/// the transition maps of Eq. 3.4; every cuboid holds its functions as a TSpline with explicit
/// BlendingKnots. Without options.splits it is a B-spline over the GPC (weights 1).
///
/// Hierarchical refinement (options.splits, refined()): level ℓ is the B-spline over the GPC
/// whose knot lines are the base lines with every interval cut into 2^ℓ equal parts (nested
/// spaces: the same joins on every level). Splitting function B of level ℓ replaces w B by
/// Σ_j (w R_j) B_j over its children of level ℓ + 1 (knot insertion of the midpoints, Eq. 4.8/4.9,
/// per axis; R_j the product of the three factors), adding to the weight of a child already
/// present. So F and Σ w_i B_i are unchanged (Eq. 4.3: semi-standard by construction), supports
/// only shrink (no function reaches beyond the solid, §4.3.1), a split next to an interface
/// splits the function on both sides of it, and a cell of any cuboid can be refined. An
/// unsplit function all of whose children are present would be their combination: it is split
/// too (closure), so the set stays free of that dependence.
///
/// Domain: cuboid c has local coordinates [0, size[0]]×[0, size[1]]×[0, size[2]] (model units
/// over the bbox diagonal, as polycube::GpcCuboid). Its knot lines are uniform (options.intervals).
/// Every glued face is Continued (C²) or Clamped (C⁰), chosen by a fixpoint rule (see the .cpp):
/// a face may be continued only if, at both ends of its two tangent axes, the two sides see the
/// same thing (both clamped, or both continued into two cuboids glued to each other so that the
/// four transitions around the edge close: a regular edge with 4 cuboids around it). At a Type-1
/// ill-point (3 cuboids around a concave edge) this clamps the faces touching it, so the spline
/// is C⁰ there and C² across every regular interface. A cuboid glued to itself (a closed tube)
/// gives a periodic direction.
///
/// Functions: per cuboid and axis, a knot vector that runs over the cuboid's own knot lines and
/// continues through every Continued face into the neighbours (clamped where the chain meets a
/// Surface or Clamped face, closed up for a periodic direction); cuboid c's TSpline (patch(c))
/// holds every tensor-product function of those vectors whose support meets its box, in c's
/// coordinates (knots beyond [0, size] where a face is Continued). A function crossing a
/// Continued face and its copy in the neighbour are one global function; on a Clamped face the
/// face functions of the two sides (non-zero on the face) are one global function. So
/// Σ_i B_i ≡ 1 on every cuboid (Eq. 4.3 with w_i = 1), F is single-valued on every glued face,
/// and no function reaches outside the solid (§4.3.1).
///
/// Evaluation is const and thread-safe; construction is deterministic (global ids in the order
/// of the first cuboid, then the first local function, that holds them).
class GpcSpline {
 public:
  /// Builds the knot vectors, the face joins, the global functions and the patches; control
  /// points all zero (num_functions()×D). The domain is copied.
  /// Throws volspline::Error if the domain is inconsistent (a face_interface entry that does not
  /// name an interface holding that face, an interface whose transition does not map its face
  /// onto the other, a size not finite and positive), options.intervals does not have one triple
  /// per cuboid or holds a count < 1, two sides of a glued face have different knot lines along
  /// a tangent axis (naming the interface and the axes), a clamped_interfaces id is out of
  /// range, D is not in 1..4, the transitions make a continued knot vector decrease, the face
  /// functions of a clamped face cannot be matched even with its tangent faces clamped (a gluing
  /// no GPC builder makes), or a splits entry names no function of its step, goes below kMaxLevel
  /// or gives more than max_functions functions.
  GpcSpline(const polycube::GpcDomain& domain, const GpcSplineOptions& options);

  const polycube::GpcDomain& domain() const { return domain_; }
  int num_cuboids() const { return static_cast<int>(domain_.cuboids.size()); }
  /// Number n of global blending functions (= control points).
  int num_functions() const { return num_functions_; }
  /// Components D of F.
  int dimension() const { return dimension_; }
  /// Knot intervals of cuboid c along u, v, w.
  const std::array<int, 3>& intervals(int cuboid) const { return intervals_[cuboid]; }
  /// Knot lines of cuboid c along axis a (0 .. size[a], intervals(c)[a] + 1 entries).
  const std::vector<double>& knot_lines(int cuboid, int axis) const { return lines_[cuboid][axis]; }
  /// True if every axis has uniform knot lines (k·size/n, as options.intervals gives).
  bool uniform_knots() const;
  /// Hierarchical refinement steps done (options.splits, with the closure's additions).
  const std::vector<std::vector<int>>& splits() const { return splits_; }
  /// Level (0 = the base knot lines) of global function i.
  int function_level(int function_id) const { return level_of_[function_id]; }
  /// Deepest level of any function.
  int max_level() const;
  /// This spline with the given functions (ids, any order, repeats allowed) split into their
  /// children one level finer, and the closure (see the class comment); F and Σ w_i B_i are the
  /// same function before and after (the points are carried over exactly). Throws volspline::Error
  /// if an id is out of range or a function would go below kMaxLevel. The levels are made only
  /// where functions are split (their cost follows the active functions, not the finest grid).
  /// The result shares this spline's cache of the levels, so refined() is not thread-safe
  /// between splines refined from one another.
  GpcSpline refined(const std::vector<int>& split) const;
  static constexpr int kMaxLevel = 6;
  /// How face f (0..5, polycube/cube_faces.h numbering) of cuboid c is joined.
  GpcFaceJoin face_join(int cuboid, int face) const;
  /// Continued or Clamped for an interface of the domain.
  GpcFaceJoin interface_join(int interface_id) const { return interface_join_[interface_id]; }
  /// Number of Continued interfaces.
  int num_continued_interfaces() const;
  /// Faces of cuboid c on the solid's surface (GpcFaceJoin::Surface): what the single-patch fits
  /// take as TSplineFitOptions::exposed_faces.
  polycube::CubeFaceSet exposed_faces(int cuboid) const;

  /// Cuboid c's functions in its local coordinates (weights 1, control points gathered from
  /// points()). Its TSpline domain can exceed the cuboid box where a face is Continued; only the
  /// box is the cuboid's part of the solid.
  const TSpline& patch(int cuboid) const { return patches_[cuboid]; }
  /// Global function id of each of patch(c)'s functions. Not injective only for a periodic
  /// direction with fewer than 4 intervals, where one function meets the cuboid twice.
  const std::vector<int>& patch_function_ids(int cuboid) const { return patch_ids_[cuboid]; }
  /// Where global function i (0 <= i < n) is anchored (a cuboid holding its Greville abscissa).
  const GpcAnchor& anchor(int function_id) const { return anchors_[function_id]; }

  /// n×D global control points.
  const Eigen::MatrixXd& points() const { return points_; }
  /// Replaces the control points (n×D). Throws volspline::Error if the shape differs or an entry
  /// is not finite.
  void set_points(Eigen::MatrixXd points);

  /// F(uvw) in cuboid c (0 <= c < num_cuboids()), D values, and its D×3 Jacobian with respect to
  /// c's local coordinates, column-major (jacobian[d + D·a] = ∂F_d/∂uvw_a). No allocation.
  /// uvw must lie in c's box; points up to 1e-9·size outside are clamped onto it (rounding of a
  /// transition). Throws volspline::Error if uvw is outside or not finite.
  void evaluate_with_jacobian(int cuboid, const Eigen::Vector3d& uvw, double* value, double* jacobian) const;
  /// F(uvw) in cuboid c written to value[0..D). No allocation. Throws like evaluate_with_jacobian.
  void evaluate_to(int cuboid, const Eigen::Vector3d& uvw, double* value) const;
  /// F(uvw) in cuboid c, D values. Throws like evaluate_with_jacobian.
  Eigen::VectorXd evaluate(int cuboid, const Eigen::Vector3d& uvw) const;
  /// F at m points: row i of uvw (m×3) in cuboid cuboids[i] (m entries). Returns m×D; with
  /// jacobians non-null, also resizes it to m×3D, row i the column-major D×3 Jacobian as
  /// evaluate_with_jacobian writes it. The rows are evaluated grouped by cuboid and knot cell
  /// (TSpline::evaluate_batch), so a large spline's cell polynomials are read once per group;
  /// each row has the bits of evaluate_to / evaluate_with_jacobian. Throws volspline::Error like
  /// evaluate_with_jacobian, naming the row, or if the sizes differ or a cuboid is out of range.
  Eigen::MatrixXd evaluate_batch(const std::vector<int>& cuboids, const Eigen::MatrixX3d& uvw,
                                 Eigen::MatrixXd* jacobians = nullptr) const;
  /// As evaluate_batch, into values (resized to m×D; kept if already that size, as jacobians, so
  /// a caller evaluating many batches reuses its storage).
  void evaluate_batch(const std::vector<int>& cuboids, const Eigen::MatrixX3d& uvw, Eigen::MatrixXd& values,
                      Eigen::MatrixXd* jacobians = nullptr) const;
  /// D×3 Jacobian of F in cuboid c (3×3 for geometry). Throws like evaluate_with_jacobian.
  Eigen::MatrixXd jacobian(int cuboid, const Eigen::Vector3d& uvw) const;
  /// ∂^(o0+o1+o2) F / ∂u^o0 ∂v^o1 ∂w^o2 in cuboid c's coordinates, D values (right derivatives at
  /// a knot line). Throws like evaluate_with_jacobian.
  Eigen::VectorXd derivative(int cuboid, const Eigen::Vector3d& uvw, const std::array<int, 3>& order) const;
  /// Σ_i w_i B_i(uvw) in cuboid c: 1 everywhere (Eq. 4.3). Throws like evaluate_with_jacobian.
  double weight_sum(int cuboid, const Eigen::Vector3d& uvw) const;
  /// Global functions non-zero in the knot cell of uvw in cuboid c: their ids (increasing) and the
  /// partial derivative of the given order of w_i B_i at uvw (order (0,0,0): the value), for
  /// least squares. Throws like evaluate_with_jacobian.
  void basis_at(int cuboid, const Eigen::Vector3d& uvw, const std::array<int, 3>& order,
                std::vector<int>& function_ids, std::vector<double>& values) const;
  /// The knot cell of uvw in patch(c) (TSpline::cell_of): points of one cell share basis_at's
  /// list. Throws like evaluate_with_jacobian.
  int cell_of(int cuboid, const Eigen::Vector3d& uvw) const;

 private:
  Eigen::Vector3d checked(int cuboid, const Eigen::Vector3d& uvw) const;
  // Replays options.splits from the level-0 functions and builds the patches.
  void build_hierarchy(const std::vector<std::vector<int>>& steps, long max_functions, double tol);
  // refined(split) of a hierarchical spline: from's levels and active functions, one more step.
  GpcSpline(const GpcSpline& from, const std::vector<int>& split);
  // The functions, anchors and patches of the active functions (active_, hierarchy_).
  void build_patches(double tol);

  polycube::GpcDomain domain_;
  int dimension_ = 3;
  int num_functions_ = 0;
  std::vector<std::array<int, 3>> intervals_;
  std::vector<std::array<std::vector<double>, 3>> lines_;
  std::vector<GpcFaceJoin> interface_join_;
  std::vector<TSpline> patches_;
  std::vector<std::vector<int>> patch_ids_;
  std::vector<GpcAnchor> anchors_;
  Eigen::MatrixXd points_;
  std::vector<std::vector<int>> splits_;
  std::vector<int> level_of_;  // per global function
  std::vector<long long> level_id_;  // per global function: its id among the functions of its level
  std::vector<int> clamped_option_;  // options.clamped_interfaces
  // Per function: the functions before the last split step it draws on, with their factors.
  std::vector<std::vector<std::pair<int, double>>> last_step_from_;
  // Hierarchical splines: the levels and their refinement relation (a cache that only grows, the
  // same for every spline refined from one base, so refined() shares it instead of replaying the
  // split steps), and the active functions (level, id) → weight.
  std::shared_ptr<detail::GpcHierarchy> hierarchy_;
  std::map<std::pair<int, long long>, double> active_;
};

/// Knot intervals for GpcSplineOptions::intervals: per class of axes glued together as tangent
/// axes of some face (union–find over the interfaces) one count, ceil(mean length/knot_spacing)
/// (at least 1), so the two sides of every glued face share their knot lines. knot_spacing in
/// the units of the cuboid sizes, > 0. `lengths` (one triple per cuboid, ≥ 0, e.g. the mean
/// length of the map's grid lines along each axis) are counted instead of the sizes if given, so
/// the knots follow the solid rather than the domain's proportions.
/// Throws volspline::Error if knot_spacing is not finite and positive, two glued axes differ
/// in size (by more than 1e-9 relative), naming the interface, or lengths are malformed.
std::vector<std::array<int, 3>> gpc_uniform_intervals(const polycube::GpcDomain& domain, double knot_spacing,
                                                      const std::vector<std::array<double, 3>>* lengths = nullptr);

/// Uniform knot lines (GpcSplineOptions::knot_lines) for the given intervals: k·size[a]/n.
/// Throws volspline::Error if intervals does not hold one triple of counts ≥ 1 per cuboid.
std::vector<std::array<std::vector<double>, 3>> gpc_uniform_knot_lines(const polycube::GpcDomain& domain,
                                                                       const std::vector<std::array<int, 3>>& intervals);

/// Inserts knot line x (0 < x < size[axis]) into cuboid c's axis and its image into every axis
/// glued to it as a tangent axis of some face, through the transitions (Eq. 3.4) and repeated
/// until nothing new appears (a tube glued to itself under a half turn gets x and size − x), so
/// that valid knot_lines stay valid. A line within 1e-9 of the largest size of one already there
/// is not inserted again. Returns how many lines were inserted over all axes.
/// Throws volspline::Error if c, axis or x is out of range or lines does not fit the domain.
int gpc_insert_knot_line(const polycube::GpcDomain& domain, std::vector<std::array<std::vector<double>, 3>>& lines,
                         int cuboid, int axis, double x);

}  // namespace volspline::spline
