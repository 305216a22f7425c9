// SPDX-License-Identifier: MIT
#include "core/spline/tspline_refinement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/spline/knot_insertion.h"

namespace volspline::spline {

namespace {

using detail::kAxisName;

// N_R = Σ c_m N_{R_m} after inserting every knot of `knots` (sorted) that lies strictly inside
// the support of the function being split (Eq. 4.8 applied repeatedly).
std::vector<std::pair<LocalKnots, double>> refine_1d(const LocalKnots& r, const std::vector<double>& knots) {
  std::vector<std::pair<LocalKnots, double>> current = {{r, 1.0}};
  std::vector<std::pair<LocalKnots, double>> next;
  auto add = [&next](const LocalKnots& knots_m, double c) {
    for (auto& item : next) {
      if (item.first == knots_m) {
        item.second += c;
        return;
      }
    }
    next.emplace_back(knots_m, c);
  };
  for (double k : knots) {
    next.clear();
    for (const auto& [knots_m, c] : current) {
      if (k > knots_m[0] && k < knots_m[4]) {
        const KnotInsertion ins = insert_knot(knots_m, k);
        add(ins.first, c * ins.first_coefficient);
        add(ins.second, c * ins.second_coefficient);
      } else {
        add(knots_m, c);
      }
    }
    current.swap(next);
  }
  return current;
}

struct KnotsLess {
  bool operator()(const BlendingKnots& a, const BlendingKnots& b) const { return a < b; }
};

}  // namespace

TSpline refine_blending_functions(const TSpline& spline, const std::vector<NewKnots>& new_knots) {
  const int n = spline.num_functions();
  const int dim = spline.dimension();
  if (static_cast<int>(new_knots.size()) != n) {
    throw Error("T-spline refinement: " + std::to_string(new_knots.size()) + " knot lists for " +
                std::to_string(n) + " blending functions");
  }
  std::map<BlendingKnots, int, KnotsLess> index;
  std::vector<BlendingKnots> knots_out;
  std::vector<double> weight_out;
  std::vector<double> weighted_point_out;  // row-major Σ w c p
  for (int i = 0; i < n; ++i) {
    const BlendingKnots& knots_i = spline.knots()[i];
    std::array<std::vector<std::pair<LocalKnots, double>>, 3> axis_children;
    for (int a = 0; a < 3; ++a) {
      std::vector<double> sorted = new_knots[i][a];
      for (double k : sorted) {
        if (!std::isfinite(k)) {
          throw Error("T-spline refinement: blending function " + std::to_string(i) + ": new " +
                      kAxisName[a] + " knot is not finite");
        }
      }
      std::sort(sorted.begin(), sorted.end());
      axis_children[a] = refine_1d(knots_i[a], sorted);
    }
    const double w = spline.weights()[i];
    // Eq. 4.9 along the three axes: the children are the tensor products of the axis children.
    for (const auto& [ku, cu] : axis_children[0]) {
      for (const auto& [kv, cv] : axis_children[1]) {
        for (const auto& [kw, cw] : axis_children[2]) {
          const BlendingKnots child = {ku, kv, kw};
          const double wc = w * cu * cv * cw;
          auto [it, inserted] = index.emplace(child, static_cast<int>(knots_out.size()));
          if (inserted) {
            knots_out.push_back(child);
            weight_out.push_back(0.0);
            weighted_point_out.resize(weighted_point_out.size() + dim, 0.0);
          }
          const int j = it->second;
          weight_out[j] += wc;
          for (int d = 0; d < dim; ++d) weighted_point_out[size_t(j) * dim + d] += wc * spline.points()(i, d);
        }
      }
    }
  }
  // §4.3.3 step 3: merged function j has weight Σ w c and control point Σ w c p / Σ w c.
  const Eigen::Index m = static_cast<Eigen::Index>(knots_out.size());
  Eigen::VectorXd weights(m);
  Eigen::MatrixXd points(m, dim);
  for (Eigen::Index j = 0; j < m; ++j) {
    weights[j] = weight_out[j];
    for (int d = 0; d < dim; ++d) points(j, d) = weighted_point_out[size_t(j) * dim + d] / weight_out[j];
  }
  return TSpline(std::move(knots_out), std::move(weights), std::move(points));
}

TSpline refine_until_no_new_knot(const TSpline& spline,
                                 const std::function<NewKnots(const BlendingKnots&)>& required_knots,
                                 int max_rounds) {
  TSpline current = spline;
  for (int round = 0; round < max_rounds; ++round) {
    std::vector<NewKnots> new_knots(current.num_functions());
    bool any = false;
    for (int i = 0; i < current.num_functions(); ++i) {
      new_knots[i] = required_knots(current.knots()[i]);
      for (int a = 0; a < 3; ++a) {
        for (double k : new_knots[i][a]) {
          const LocalKnots& r = current.knots()[i][a];
          if (k > r[0] && k < r[4]) any = true;
        }
      }
    }
    if (!any) return current;
    current = refine_blending_functions(current, new_knots);
  }
  throw Error("T-spline refinement: blending functions still need new knots after " +
              std::to_string(max_rounds) + " rounds");
}

}  // namespace volspline::spline
