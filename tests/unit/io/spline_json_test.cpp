// SPDX-License-Identifier: MIT
#include "core/io/spline_json.h"

#include <random>

#include <doctest/doctest.h>

#include "core/common/error.h"
#include "core/spline/bspline_volume.h"

using namespace volspline;

namespace {

spline::TSpline sample_spline() {
  const std::vector<double> knots = spline::boundary_restricted_knots({0.0, 0.3, 1.0});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd points(5 * 5 * 5, 3);
  for (int r = 0; r < points.rows(); ++r) points.row(r) << u(rng), u(rng) / 3.0, 1e-300 * u(rng);
  return spline::from_bspline_volume(spline::BsplineVolume({knots, knots, knots}, points));
}

std::string error_of(const std::string& text) {
  try {
    io::parse_spline_json(text, "s.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("spline JSON: write, read, write is byte-identical and evaluates the same") {
  const spline::TSpline a = sample_spline();
  const std::string text = io::serialize_spline_json(a);
  const spline::TSpline b = io::parse_spline_json(text, "mem");
  CHECK(io::serialize_spline_json(b) == text);
  CHECK(b.num_functions() == a.num_functions());
  CHECK(b.points() == a.points());
  CHECK(b.weights() == a.weights());
  const Eigen::Vector3d p(0.2, 0.7, 0.31);
  CHECK(b.evaluate(p) == a.evaluate(p));
  CHECK(text.find("\"format\": \"volspline-tspline\"") != std::string::npos);
}

TEST_CASE("spline JSON: broken documents name the problem") {
  const std::string good = io::serialize_spline_json(sample_spline());
  CHECK(error_of("{").find("invalid JSON") != std::string::npos);
  CHECK(error_of("[]").find("top level is not an object") != std::string::npos);
  CHECK(error_of("{\"format\":\"x\"}").find("\"format\" is not") != std::string::npos);
  std::string wrong_version = good;
  wrong_version.replace(wrong_version.find("\"version\": 1"), 12, "\"version\": 7");
  CHECK(error_of(wrong_version).find("unsupported \"version\"") != std::string::npos);
  std::string bad_weight = good;
  bad_weight.replace(bad_weight.find("\"weight\":1.0"), 12, "\"weight\":-1.0");
  CHECK(error_of(bad_weight).find("function 0: \"weight\" must be positive") != std::string::npos);
  std::string decreasing = good;
  decreasing.replace(decreasing.find("[[0.0,0.0,0.0,0.0,0.3]"), 22, "[[0.0,0.0,0.0,0.5,0.3]");
  CHECK(error_of(decreasing).find("function 0: knot vector 0 decreases") != std::string::npos);
  std::string short_point = good;
  const auto at = short_point.find("\"point\":[");
  short_point.replace(at, short_point.find(']', at) - at + 1, "\"point\":[1,2]");
  CHECK(error_of(short_point).find("\"point\" must hold 3 numbers") != std::string::npos);
  CHECK_THROWS_WITH_AS(io::read_spline_json("/nonexistent/s.json"), doctest::Contains("/nonexistent/s.json"), Error);
}
