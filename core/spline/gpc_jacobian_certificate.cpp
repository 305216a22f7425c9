// SPDX-License-Identifier: MIT
#include "core/spline/gpc_jacobian_certificate.h"

#include <algorithm>

namespace volspline::spline {

JacobianCertificateOptions gpc_certificate_options() {
  JacobianCertificateOptions options;
  options.max_depth = 24;
  return options;
}

JacobianCertificate certify_gpc_jacobian(const GpcSpline& spline, const JacobianCertificateOptions& options,
                                         JacobianCertificateCache* cache) {
  JacobianCertificate out;
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const auto& size = spline.domain().cuboids[c].size;
    const JacobianCertificate part = certify_jacobian_in_box(spline.patch(c), Eigen::Vector3d::Zero(),
                                                             Eigen::Vector3d(size[0], size[1], size[2]), options, c, cache);
    out.cells += part.cells;
    out.certified_cells += part.certified_cells;
    out.det_j_lower_bound_rel = std::min(out.det_j_lower_bound_rel, part.det_j_lower_bound_rel);
    out.cell_bound_rel.insert(out.cell_bound_rel.end(), part.cell_bound_rel.begin(), part.cell_bound_rel.end());
    out.uncertified.insert(out.uncertified.end(), part.uncertified.begin(), part.uncertified.end());
  }
  out.jacobian_certified_fraction = out.cells ? double(out.certified_cells) / out.cells : 1.0;
  return out;
}

}  // namespace volspline::spline
