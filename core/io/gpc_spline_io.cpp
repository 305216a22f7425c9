// SPDX-License-Identifier: MIT
#include "core/io/gpc_spline_io.h"

#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/gpc_json.h"
#include "core/io/gpc_writers.h"
#include "core/io/json_depth.h"
#include "core/mesh/hex_quality.h"

namespace volspline::io {

namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kFormat = "volspline-gpc-spline";
constexpr int kVersion = 1;
// Knot cells a file may ask for over all cuboids: far above any fit, far below what exhausts memory.
constexpr double kMaxCells = 1 << 24;

}  // namespace

std::string serialize_gpc_spline_json(const spline::GpcSpline& spline) {
  Json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["dimension"] = spline.dimension();
  j["domain"] = Json::parse(serialize_gpc_domain(spline.domain()));
  Json intervals = Json::array();
  for (int c = 0; c < spline.num_cuboids(); ++c) intervals.push_back(spline.intervals(c));
  j["intervals"] = intervals;
  if (!spline.uniform_knots()) {  // written only where it differs from what the intervals give
    Json lines = Json::array();
    for (int c = 0; c < spline.num_cuboids(); ++c) {
      Json triple = Json::array();
      for (int a = 0; a < 3; ++a) triple.push_back(spline.knot_lines(c, a));
      lines.push_back(triple);
    }
    j["knot_lines"] = lines;
  }
  Json clamped = Json::array();
  for (int g = 0; g < static_cast<int>(spline.domain().interfaces.size()); ++g)
    if (spline.interface_join(g) == spline::GpcFaceJoin::Clamped) clamped.push_back(g);
  j["clamped_interfaces"] = clamped;
  if (!spline.splits().empty()) j["splits"] = spline.splits();  // hierarchical refinement steps
  Json points = Json::array();
  for (int i = 0; i < spline.num_functions(); ++i) {
    Json p = Json::array();
    for (int d = 0; d < spline.dimension(); ++d) p.push_back(spline.points()(i, d));
    points.push_back(p);
  }
  j["points"] = points;
  return j.dump(1) + "\n";
}

bool is_gpc_spline_json(const std::string& text) {
  const std::size_t key = text.find("\"format\"");
  if (key == std::string::npos || key > 64) return false;
  const std::size_t value = text.find('"', key + 8);
  const std::string quoted = std::string("\"") + kFormat + "\"";
  return value != std::string::npos && text.compare(value, quoted.size(), quoted) == 0;
}

spline::GpcSpline parse_gpc_spline_json(const std::string& text, const std::string& source) {
  const std::string prefix = "spline '" + source + "': ";
  check_json_depth(text.data(), text.size(), "spline '" + source + "'");
  Json doc;
  try {
    doc = Json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(prefix + "invalid JSON at byte " + std::to_string(e.byte));
  } catch (const nlohmann::json::exception&) {
    throw Error(prefix + "a number is outside the range of doubles");
  }
  if (!doc.is_object()) throw Error(prefix + "top level is not an object");
  if (!doc.contains("format") || doc["format"] != kFormat) throw Error(prefix + "\"format\" is not \"" + kFormat + "\"");
  if (!doc.contains("version") || doc["version"] != kVersion)
    throw Error(prefix + "unsupported \"version\" (expected " + std::to_string(kVersion) + ")");
  for (const char* field : {"dimension", "domain", "intervals", "clamped_interfaces", "points"})
    if (!doc.contains(field)) throw Error(prefix + "missing \"" + field + "\"");
  if (!doc["dimension"].is_number_integer()) throw Error(prefix + "\"dimension\" is not an integer");
  spline::GpcSplineOptions options;
  options.dimension = doc["dimension"].get<int>();
  if (options.dimension < 1 || options.dimension > 4) throw Error(prefix + "\"dimension\" must be 1..4");
  if (!doc["domain"].is_object()) throw Error(prefix + "\"domain\" is not an object");
  const polycube::GpcDomain domain = parse_gpc_domain(doc["domain"].dump(), source + " (domain)");
  const Json& intervals = doc["intervals"];
  if (!intervals.is_array() || intervals.size() != domain.cuboids.size())
    throw Error(prefix + "\"intervals\" must hold one triple per cuboid (" + std::to_string(domain.cuboids.size()) + ")");
  double cells = 0.0;
  for (std::size_t c = 0; c < intervals.size(); ++c) {
    const Json& t = intervals[c];
    if (!t.is_array() || t.size() != 3) throw Error(prefix + "\"intervals\"[" + std::to_string(c) + "] is not a triple");
    std::array<int, 3> n{};
    double product = 1.0;
    for (int a = 0; a < 3; ++a) {
      if (!t[a].is_number_integer() || t[a].get<long long>() < 1 || t[a].get<long long>() > 4096)
        throw Error(prefix + "\"intervals\"[" + std::to_string(c) + "] must hold integers in 1..4096");
      n[a] = t[a].get<int>();
      product *= n[a];
    }
    cells += product;
    options.intervals.push_back(n);
  }
  if (cells > kMaxCells) throw Error(prefix + "\"intervals\" ask for more than 2^24 knot cells");
  // A spline has at least as many functions as knot cells (n intervals give n + 3 functions, n if
  // periodic; gluing shares at most the extra ones), so a file cannot ask for more work than it
  // holds points: checked before the functions are built.
  if (!doc["points"].is_array() || static_cast<double>(doc["points"].size()) < cells)
    throw Error(prefix + "\"intervals\" ask for " + std::to_string(static_cast<long long>(cells)) +
                " knot cells, more than the " +
                std::to_string(doc["points"].is_array() ? doc["points"].size() : 0) + " points");
  if (doc.contains("knot_lines")) {
    const Json& lines = doc["knot_lines"];
    if (!lines.is_array() || lines.size() != domain.cuboids.size())
      throw Error(prefix + "\"knot_lines\" must hold one triple of lists per cuboid");
    for (std::size_t c = 0; c < lines.size(); ++c) {
      const std::string at = prefix + "\"knot_lines\"[" + std::to_string(c) + "]";
      if (!lines[c].is_array() || lines[c].size() != 3) throw Error(at + " is not a triple of lists");
      std::array<std::vector<double>, 3> triple;
      for (int a = 0; a < 3; ++a) {
        const Json& list = lines[c][a];
        if (!list.is_array() || static_cast<int>(list.size()) != options.intervals[c][a] + 1)
          throw Error(at + "[" + std::to_string(a) + "] must hold intervals + 1 = " +
                      std::to_string(options.intervals[c][a] + 1) + " numbers");
        for (const Json& x : list) {
          if (!x.is_number() || !std::isfinite(x.get<double>())) throw Error(at + " holds a value that is not a finite number");
          triple[a].push_back(x.get<double>());
        }
      }
      options.knot_lines.push_back(std::move(triple));
    }
  }
  const Json& clamped = doc["clamped_interfaces"];
  if (!clamped.is_array()) throw Error(prefix + "\"clamped_interfaces\" is not an array");
  for (const Json& g : clamped) {
    if (!g.is_number_integer() || g.get<long long>() < 0 ||
        g.get<long long>() >= static_cast<long long>(domain.interfaces.size()))
      throw Error(prefix + "\"clamped_interfaces\" holds an entry that is not an interface id");
    options.clamped_interfaces.push_back(g.get<int>());
  }
  if (doc.contains("splits")) {
    const Json& splits = doc["splits"];
    if (!splits.is_array() || splits.size() > 64)
      throw Error(prefix + "\"splits\" must be an array of at most 64 refinement steps");
    for (const Json& step : splits) {
      if (!step.is_array()) throw Error(prefix + "\"splits\" holds a step that is not an array of function ids");
      std::vector<int> ids;
      for (const Json& id : step) {
        if (!id.is_number_integer() || id.get<long long>() < 0 || id.get<long long>() > (1LL << 30))
          throw Error(prefix + "\"splits\" holds an entry that is not a function id");
        ids.push_back(id.get<int>());
      }
      options.splits.push_back(std::move(ids));
    }
    options.max_functions = static_cast<long>(doc["points"].size());  // an array: checked above
  }
  std::optional<spline::GpcSpline> spline;
  try {
    spline.emplace(domain, options);
  } catch (const Error& e) {
    throw Error(prefix + e.what());
  }
  const Json& points = doc["points"];
  if (!points.is_array() || static_cast<int>(points.size()) != spline->num_functions())
    throw Error(prefix + "\"points\" must hold " + std::to_string(spline->num_functions()) +
                " points (the functions of the domain and intervals)");
  Eigen::MatrixXd p(spline->num_functions(), options.dimension);
  for (int i = 0; i < spline->num_functions(); ++i) {
    const Json& row = points[i];
    if (!row.is_array() || static_cast<int>(row.size()) != options.dimension)
      throw Error(prefix + "point " + std::to_string(i) + " must hold " + std::to_string(options.dimension) + " numbers");
    for (int d = 0; d < options.dimension; ++d) {
      if (!row[d].is_number() || !std::isfinite(row[d].get<double>()))
        throw Error(prefix + "point " + std::to_string(i) + " has a value that is not a finite number");
      p(i, d) = row[d].get<double>();
    }
  }
  spline->set_points(std::move(p));
  return std::move(*spline);
}

std::string serialize_gpc_spline_vtu(const spline::GpcSpline& spline, int cells) {
  const polycube::GpcDomain& domain = spline.domain();
  double longest = 0.0;
  for (const polycube::GpcCuboid& c : domain.cuboids)
    for (double s : c.size) longest = std::max(longest, s);
  mesh::Positions xyz;
  std::vector<Eigen::RowVector3d> nodes;
  std::vector<std::array<int, 8>> hexes;
  std::vector<int> cuboid;
  std::vector<double> quality;
  // The 2×2×2 Gauss points of a cell: interior points (on a cuboid edge any map onto a smooth
  // surface is degenerate, so corner values would flag every edge cell).
  const double g0 = 0.5 - 0.5 / std::sqrt(3.0), g1 = 0.5 + 0.5 / std::sqrt(3.0);
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    std::array<int, 3> n;
    Eigen::Vector3d size;
    for (int a = 0; a < 3; ++a) {
      size(a) = domain.cuboids[c].size[a];
      n[a] = std::max(1, static_cast<int>(std::lround(cells * size(a) / longest)));
    }
    const int base = static_cast<int>(nodes.size());
    for (int k = 0; k <= n[2]; ++k)
      for (int j = 0; j <= n[1]; ++j)
        for (int i = 0; i <= n[0]; ++i) {
          const Eigen::Vector3d uvw(size(0) * i / n[0], size(1) * j / n[1], size(2) * k / n[2]);
          const Eigen::VectorXd f = spline.evaluate(c, uvw);
          nodes.push_back(Eigen::RowVector3d(f(0), f(1), f(2)));
        }
    auto id = [&](int i, int j, int k) { return base + i + (n[0] + 1) * (j + (n[1] + 1) * k); };
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          std::array<int, 8> hex;
          for (int q = 0; q < 8; ++q) hex[q] = id(i + (q & 1), j + (q >> 1 & 1), k + (q >> 2 & 1));
          hexes.push_back(hex);
          cuboid.push_back(c);
          double q_min = 1.0;
          for (int q = 0; q < 8; ++q) {
            const Eigen::Vector3d uvw(size(0) * (i + ((q & 1) ? g1 : g0)) / n[0],
                                      size(1) * (j + ((q >> 1 & 1) ? g1 : g0)) / n[1],
                                      size(2) * (k + ((q >> 2 & 1) ? g1 : g0)) / n[2]);
            q_min = std::min(q_min, mesh::scaled_jacobian(spline.jacobian(c, uvw)));
          }
          quality.push_back(q_min);
        }
  }
  xyz.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t v = 0; v < nodes.size(); ++v) xyz.row(static_cast<Eigen::Index>(v)) = nodes[v];
  HexMeshView view;
  view.xyz = &xyz;
  view.hexes = &hexes;
  view.cuboid = &cuboid;
  view.scaled_jacobian = &quality;
  return serialize_hex_mesh_vtu(view);
}

std::string serialize_gpc_spline_glb(const spline::GpcSpline& spline, int samples, int lines) {
  const polycube::GpcDomain& domain = spline.domain();
  std::vector<Eigen::RowVector3d> points;
  std::vector<Eigen::RowVector3i> triangles;
  std::vector<int> face_cuboid;
  std::vector<std::vector<Eigen::Vector3d>> polylines;
  const int s = std::max(2, samples);
  for (int c = 0; c < spline.num_cuboids(); ++c) {
    const Eigen::Vector3d size(domain.cuboids[c].size[0], domain.cuboids[c].size[1], domain.cuboids[c].size[2]);
    for (int f = 0; f < 6; ++f) {
      if (domain.cuboids[c].face_interface[f] >= 0) continue;
      // (a, b, e) cyclic, so e_b × e_e = e_a: counter-clockwise in (b, e) faces +a; flipped on
      // the lower face so every triangle faces out of the solid.
      const int a = f / 2, b = (a + 1) % 3, e = (a + 2) % 3;
      auto at = [&](double tb, double te) {
        Eigen::Vector3d uvw;
        uvw(a) = f % 2 ? size(a) : 0.0;
        uvw(b) = tb * size(b);
        uvw(e) = te * size(e);
        const Eigen::VectorXd x = spline.evaluate(c, uvw);
        return Eigen::Vector3d(x(0), x(1), x(2));
      };
      const int base = static_cast<int>(points.size());
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) points.push_back(at(double(i) / (s - 1), double(j) / (s - 1)).transpose());
      for (int j = 0; j + 1 < s; ++j)
        for (int i = 0; i + 1 < s; ++i) {
          const int v00 = base + i + s * j, v10 = v00 + 1, v01 = v00 + s, v11 = v01 + 1;
          if (f % 2) {
            triangles.push_back({v00, v10, v11});
            triangles.push_back({v00, v11, v01});
          } else {
            triangles.push_back({v00, v11, v10});
            triangles.push_back({v00, v01, v11});
          }
          face_cuboid.push_back(c);
          face_cuboid.push_back(c);
        }
      for (int l = 0; l < lines; ++l) {
        const double t = (l + 0.5) / lines;
        std::vector<Eigen::Vector3d> along_b, along_e;
        for (int i = 0; i < s; ++i) {
          along_b.push_back(at(double(i) / (s - 1), t));
          along_e.push_back(at(t, double(i) / (s - 1)));
        }
        polylines.push_back(std::move(along_b));
        polylines.push_back(std::move(along_e));
      }
    }
  }
  mesh::TriangleMesh surface;
  surface.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t v = 0; v < points.size(); ++v) surface.positions.row(static_cast<Eigen::Index>(v)) = points[v];
  surface.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) surface.triangles.row(static_cast<Eigen::Index>(t)) = triangles[t];
  return serialize_segmented_glb(surface, face_cuboid, polylines, {});
}

}  // namespace volspline::io
