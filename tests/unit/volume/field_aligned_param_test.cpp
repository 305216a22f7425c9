// SPDX-License-Identifier: MIT
#include "core/volume/field_aligned_param.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>
#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/volume/hessian_frames.h"
#include "core/volume/local_cubic_fit.h"

using namespace volspline::volume;

namespace {

Volume ball_volume(int nx, int ny, int nz, double radius) {
  Volume v;
  v.nx = nx;
  v.ny = ny;
  v.nz = nz;
  v.samples.resize(v.num_voxels());
  const Eigen::Vector3d c((nx - 1) / 2.0, (ny - 1) / 2.0, (nz - 1) / 2.0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const double r = (Eigen::Vector3d(x, y, z) - c).norm();
        v.samples[v.index(x, y, z)] = static_cast<float>(100.0 / (1.0 + std::exp(2.0 * (r - radius))));
      }
  return v;
}

MaterialClassification threshold(const Volume& v, const LocalCubicFit& fit) {
  ClassificationOptions options;
  options.iso = 50.0;
  return classify_materials(v, fit, options);
}

double max_identity_error(const Volume& v, const Eigen::MatrixX3d& uvw) {
  double worst = 0.0;
  for (int z = 0; z < v.nz; ++z)
    for (int y = 0; y < v.ny; ++y)
      for (int x = 0; x < v.nx; ++x) {
        const Eigen::RowVector3d expected(static_cast<double>(x) / (v.nx - 1), static_cast<double>(y) / (v.ny - 1),
                                          static_cast<double>(z) / (v.nz - 1));
        worst = std::max(worst, (uvw.row(static_cast<Eigen::Index>(v.index(x, y, z))) - expected).cwiseAbs().maxCoeff());
      }
  return worst;
}

}  // namespace

TEST_CASE("field_aligned_param: a constant axis-aligned field gives the identity map") {
  // Anisotropic dims and spacing, frames that are cube rotations of the identity (the same
  // field modulo the cube group), every corner option: uvw = (x/(nx-1), y/(ny-1), z/(nz-1)).
  Volume v = ball_volume(13, 11, 9, 3.5);
  v.spacing = Eigen::Vector3d(1.0, 0.5, 2.0);
  const LocalCubicFit fit = fit_local_cubics(v);
  const MaterialClassification classes = threshold(v, fit);
  FrameField field{v.nx, v.ny, v.nz, {}};
  for (std::size_t i = 0; i < v.num_voxels(); ++i) field.frames.push_back(cube_group_rotations()[i % 24]);
  for (int step : {1, 2, 0}) {
    for (CornerSelection selection : {CornerSelection::None, CornerSelection::Automatic, CornerSelection::Given}) {
      FieldAlignedOptions options;
      options.grid_step = step;
      options.max_grid_nodes = 300;
      options.corner_selection = selection;
      options.corner_voxels = {v.index(4, 4, 3), v.index(8, 6, 5)};
      const FieldAlignedParam p = compute_field_aligned_param(v, field, classes, options);
      CHECK(p.converged);
      CHECK(max_identity_error(v, p.uvw) < 1e-9);
      CHECK(p.inverted_cells == 0);
      CHECK(p.identity_blend == 0.0);
      CHECK(p.min_jacobian == doctest::Approx(1.0).epsilon(1e-9));
      CHECK(p.alignment_rms_deg < 1e-6);
      if (selection == CornerSelection::Given) CHECK(p.corner_voxels == options.corner_voxels);
      if (step == 0) CHECK(static_cast<long>(p.grid_nx) * p.grid_ny * p.grid_nz <= 300);
    }
  }
}

TEST_CASE("field_aligned_param: a ball's smoothed field gives an injective map inside [0,1]^3, better aligned than the identity") {
  const Volume v = ball_volume(20, 20, 20, 6.0);
  const LocalCubicFit fit = fit_local_cubics(v);
  const MaterialClassification classes = threshold(v, fit);
  const FrameField initial{v.nx, v.ny, v.nz, hessian_frames(fit.hessian)};
  FrameSmoothingOptions smoothing;
  smoothing.active = foreground_mask(classes, 1);
  const FrameField smoothed = smooth_frame_field(initial, classes.constraints, smoothing).field;
  const FieldAlignedParam p = compute_field_aligned_param(v, smoothed, classes);
  CHECK(p.converged);
  // The least-squares solution folds a few hexes at the singularities a ball's frame field must
  // have (measured 8 of 6859); the local identity blend removes them and touches little else.
  CHECK(p.inverted_cells_unblended < 20);
  CHECK(p.identity_blend < 0.1);
  CHECK(p.inverted_cells == 0);
  CHECK(p.min_jacobian > 0);
  CHECK(p.uvw.minCoeff() >= 0.0);
  CHECK(p.uvw.maxCoeff() <= 1.0);
  CHECK(p.alignment_rms_deg <= p.alignment_rms_deg_identity);
  int inverted = -1;
  CHECK(voxel_map_min_jacobian(v.nx, v.ny, v.nz, p.uvw, &inverted) == p.min_jacobian);
  CHECK(inverted == p.inverted_cells);
}

TEST_CASE("field_aligned_param: the Jacobian check sees a fold") {
  const int n = 4;
  Eigen::MatrixX3d uvw(n * n * n, 3);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) uvw.row(x + n * (y + n * z)) = Eigen::RowVector3d(x, y, z) / (n - 1);
  int inverted = -1;
  CHECK(voxel_map_min_jacobian(n, n, n, uvw, &inverted) == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(inverted == 0);
  uvw(1 + n * (1 + n * 1), 0) = 2.5 / (n - 1);  // voxel (1,1,1) pushed past (2,1,1)
  CHECK(voxel_map_min_jacobian(n, n, n, uvw, &inverted) < 0);
  CHECK(inverted > 0);
}

TEST_CASE("field_aligned_param: bad options and grids are refused with a message") {
  const Volume v = ball_volume(6, 6, 6, 2.0);
  const LocalCubicFit fit = fit_local_cubics(v);
  const MaterialClassification classes = threshold(v, fit);
  const FrameField field{6, 6, 6, std::vector<Eigen::Matrix3d>(v.num_voxels(), Eigen::Matrix3d::Identity())};
  auto error_of = [&](const FieldAlignedOptions& options, const FrameField& f) {
    try {
      compute_field_aligned_param(v, f, classes, options);
    } catch (const volspline::Error& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  FieldAlignedOptions options;
  options.anisotropy = 0.0;
  CHECK(error_of(options, field) == "field-aligned parameterization: anisotropy must be in (0, 1]");
  options = {};
  options.reliability_radius = -1.0;
  CHECK(error_of(options, field) == "field-aligned parameterization: reliability_radius must be >= 0");
  options = {};
  options.identity_weight = std::nan("");
  CHECK(error_of(options, field) == "field-aligned parameterization: identity_weight must be >= 0");
  options = {};
  options.corner_selection = CornerSelection::Given;
  options.corner_voxels = {216};
  CHECK(error_of(options, field) == "field-aligned parameterization: corner voxel 216 is outside the grid of 216 voxels");
  const FrameField small{5, 6, 6, std::vector<Eigen::Matrix3d>(180, Eigen::Matrix3d::Identity())};
  CHECK(error_of({}, small) == "field-aligned parameterization: the frame field does not match the volume's grid");
}

TEST_CASE("field_aligned_param: a constant volume has no foreground and maps to the identity") {
  Volume v;
  v.nx = v.ny = v.nz = 7;
  v.samples.assign(v.num_voxels(), 3.0f);
  const LocalCubicFit fit = fit_local_cubics(v);
  const MaterialClassification classes = classify_materials(v, fit);
  CHECK(classes.num_foreground == 0);
  CHECK(classes.constraints.empty());
  const FrameField initial{7, 7, 7, hessian_frames(fit.hessian)};
  FrameSmoothingOptions smoothing;
  smoothing.active = foreground_mask(classes, 2);
  const FrameSmoothingResult smoothed = smooth_frame_field(initial, classes.constraints, smoothing);
  CHECK(smoothed.final_energy == 0.0);
  const FieldAlignedParam p = compute_field_aligned_param(v, smoothed.field, classes);
  CHECK(max_identity_error(v, p.uvw) < 1e-9);
  CHECK(p.corner_voxels.empty());
}

TEST_CASE("field_aligned_param: untrusted frames are pulled to the identity; trusted ones still bend the map") {
  // A constant field rotated 30 degrees about z, far from any cube rotation: with every
  // foreground frame trusted (reliability_radius 0) the ball's map turns away from the identity;
  // with no constraint to trust (none is left in `untrusted`) and any identity_weight > 0 the map is the identity.
  const Volume v = ball_volume(14, 14, 14, 4.0);
  const LocalCubicFit fit = fit_local_cubics(v);
  const MaterialClassification classes = threshold(v, fit);
  REQUIRE(!classes.constraints.empty());
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(30.0 * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const FrameField field{v.nx, v.ny, v.nz, std::vector<Eigen::Matrix3d>(v.num_voxels(), turn)};
  FieldAlignedOptions options;
  options.corner_selection = CornerSelection::None;
  options.reliability_radius = 0.0;
  const FieldAlignedParam trusted = compute_field_aligned_param(v, field, classes, options);
  CHECK(max_identity_error(v, trusted.uvw) > 0.01);
  CHECK(trusted.alignment_rms_deg < trusted.alignment_rms_deg_identity);
  MaterialClassification untrusted = classes;
  untrusted.constraints.clear();
  options.reliability_radius = 2.0;
  const FieldAlignedParam pulled = compute_field_aligned_param(v, field, untrusted, options);
  CHECK(max_identity_error(v, pulled.uvw) < 1e-9);
  CHECK(pulled.volume_ratio_min == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(pulled.volume_ratio_max == doctest::Approx(1.0).epsilon(1e-9));
  // With the constraints back, the map bends near the surface only, less than fully trusted.
  const FieldAlignedParam near = compute_field_aligned_param(v, field, classes, options);
  CHECK(max_identity_error(v, near.uvw) > 1e-4);
  CHECK(max_identity_error(v, near.uvw) < max_identity_error(v, trusted.uvw));
  CHECK(near.volume_ratio_min > 0.0);
  CHECK(near.volume_ratio_min <= 1.0);
  CHECK(near.volume_ratio_max >= 1.0);
  CHECK(near.alignment_rms_deg_reliable < near.alignment_rms_deg_reliable_identity);
}
