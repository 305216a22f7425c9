// SPDX-License-Identifier: MIT
// libFuzzer target: parse_spline_json (or parse_gpc_spline_json for a "volspline-gpc-spline"
// file) on arbitrary bytes must return a spline or throw volspline::Error; a spline it returns
// must evaluate at its domain's centre and corners (a GPC spline: at every cuboid's centre and
// corners) without a crash (the value may only be non-finite if the file's sums overflow).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/common/error.h"
#include "core/io/gpc_spline_io.h"
#include "core/io/spline_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volspline;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    if (io::is_gpc_spline_json(text)) {
      const spline::GpcSpline g = io::parse_gpc_spline_json(text, "fuzz.json");
      for (int c = 0; c < g.num_cuboids(); ++c) {
        const auto& size = g.domain().cuboids[c].size;
        const Eigen::Vector3d hi(size[0], size[1], size[2]);
        const Eigen::Vector3d points[3] = {0.5 * hi, Eigen::Vector3d::Zero(), hi};
        for (const Eigen::Vector3d& uvw : points) {
          if (g.evaluate(c, uvw).size() != g.dimension()) __builtin_trap();
          (void)g.jacobian(c, uvw);
        }
      }
      return 0;
    }
    const spline::TSpline s = io::parse_spline_json(text, "fuzz.json");
    const Eigen::Vector3d lo = s.domain_min(), hi = s.domain_max();
    for (const Eigen::Vector3d& uvw : {Eigen::Vector3d(0.5 * (lo + hi)), lo, hi}) {
      const Eigen::VectorXd value = s.evaluate(uvw);
      if (value.size() != s.dimension()) __builtin_trap();
      (void)s.jacobian(uvw);
    }
  } catch (const Error&) {
  }
  return 0;
}
