// SPDX-License-Identifier: MIT
#include "core/io/spline_json.h"

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/json_depth.h"

namespace volspline::io {

namespace {

constexpr const char* kFormat = "volspline-tspline";
constexpr int kVersion = 1;

// Shortest text that parses back to the same double (nlohmann's number dump).
std::string number(double x) { return nlohmann::json(x).dump(); }

void append_array(std::string& out, const double* values, int count) {
  out += '[';
  for (int i = 0; i < count; ++i) {
    if (i) out += ',';
    out += number(values[i]);
  }
  out += ']';
}

}  // namespace

std::string serialize_spline_json(const spline::TSpline& spline) {
  std::string out;
  out += "{\n\"format\": \"";
  out += kFormat;
  out += "\",\n\"version\": " + std::to_string(kVersion) + ",\n";
  out += "\"form\": \"semi-standard\",\n";
  out += "\"dimension\": " + std::to_string(spline.dimension()) + ",\n";
  const Eigen::Vector3d lo = spline.domain_min(), hi = spline.domain_max();
  out += "\"domain_min\": ";
  append_array(out, lo.data(), 3);
  out += ",\n\"domain_max\": ";
  append_array(out, hi.data(), 3);
  out += ",\n\"functions\": [\n";
  for (int i = 0; i < spline.num_functions(); ++i) {
    out += "{\"knots\":[";
    for (int a = 0; a < 3; ++a) {
      if (a) out += ',';
      append_array(out, spline.knots()[i][a].data(), 5);
    }
    out += "],\"weight\":" + number(spline.weights()(i)) + ",\"point\":";
    double point[4];
    for (int d = 0; d < spline.dimension(); ++d) point[d] = spline.points()(i, d);
    append_array(out, point, spline.dimension());
    out += i + 1 < spline.num_functions() ? "},\n" : "}\n";
  }
  out += "]\n}\n";
  return out;
}

spline::TSpline parse_spline_json(const std::string& text, const std::string& name) {
  const std::string prefix = "spline '" + name + "': ";
  check_json_depth(text.data(), text.size(), "spline '" + name + "'");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(prefix + "invalid JSON at byte " + std::to_string(e.byte));
  } catch (const nlohmann::json::exception&) {
    // The parser's other failure: a number beyond the double range (e.g. 1e400).
    throw Error(prefix + "a number is outside the range of doubles");
  }
  if (!doc.is_object()) throw Error(prefix + "top level is not an object");
  if (!doc.contains("format") || doc["format"] != kFormat)
    throw Error(prefix + "\"format\" is not \"" + kFormat + "\"");
  if (!doc.contains("version") || doc["version"] != kVersion)
    throw Error(prefix + "unsupported \"version\" (expected " + std::to_string(kVersion) + ")");
  if (!doc.contains("dimension") || !doc["dimension"].is_number_integer())
    throw Error(prefix + "missing integer \"dimension\"");
  const int dimension = doc["dimension"].get<int>();
  if (dimension < 1 || dimension > 4) throw Error(prefix + "\"dimension\" must be 1..4");
  if (!doc.contains("functions") || !doc["functions"].is_array() || doc["functions"].empty())
    throw Error(prefix + "missing or empty \"functions\" array");
  const auto& functions = doc["functions"];
  const int n = static_cast<int>(functions.size());
  std::vector<spline::BlendingKnots> knots(n);
  Eigen::VectorXd weights(n);
  Eigen::MatrixXd points(n, dimension);
  auto number_at = [&](const nlohmann::json& j, int i, const std::string& field) {
    if (!j.is_number()) throw Error(prefix + "function " + std::to_string(i) + ": \"" + field + "\" has a non-number");
    const double x = j.get<double>();
    if (!std::isfinite(x)) throw Error(prefix + "function " + std::to_string(i) + ": \"" + field + "\" is not finite");
    return x;
  };
  for (int i = 0; i < n; ++i) {
    const auto& f = functions[i];
    const std::string where = prefix + "function " + std::to_string(i) + ": ";
    if (!f.is_object() || !f.contains("knots") || !f.contains("weight") || !f.contains("point"))
      throw Error(where + "needs \"knots\", \"weight\" and \"point\"");
    const auto& k = f["knots"];
    if (!k.is_array() || k.size() != 3) throw Error(where + "\"knots\" must hold 3 knot vectors");
    for (int a = 0; a < 3; ++a) {
      if (!k[a].is_array() || k[a].size() != 5) throw Error(where + "knot vector " + std::to_string(a) + " must hold 5 numbers");
      for (int j = 0; j < 5; ++j) knots[i][a][j] = number_at(k[a][j], i, "knots");
      for (int j = 0; j < 4; ++j)
        if (knots[i][a][j] > knots[i][a][j + 1]) throw Error(where + "knot vector " + std::to_string(a) + " decreases");
    }
    weights(i) = number_at(f["weight"], i, "weight");
    if (!(weights(i) > 0.0)) throw Error(where + "\"weight\" must be positive");
    const auto& p = f["point"];
    if (!p.is_array() || static_cast<int>(p.size()) != dimension)
      throw Error(where + "\"point\" must hold " + std::to_string(dimension) + " numbers");
    for (int d = 0; d < dimension; ++d) {
      points(i, d) = number_at(p[d], i, "point");
      // Eq. 4.3 sums w_i p_i: each product must stay finite.
      if (!std::isfinite(weights(i) * points(i, d))) throw Error(where + "\"weight\" times \"point\" overflows");
    }
  }
  try {
    return spline::TSpline(std::move(knots), std::move(weights), std::move(points));
  } catch (const Error& e) {
    throw Error(prefix + e.what());
  }
}

spline::TSpline read_spline_json(const std::string& path) {
  return parse_spline_json(read_file_bytes(path), path);
}

void write_spline_json(const std::string& path, const spline::TSpline& spline) {
  write_file_atomic(path, serialize_spline_json(spline));
}

}  // namespace volspline::io
