// SPDX-License-Identifier: MIT
#include "core/io/gpc_json.h"

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/file_bytes.h"

namespace volspline::io {

namespace {

using Json = nlohmann::ordered_json;

Json vec3(const Eigen::Vector3d& x) { return Json::array({x(0), x(1), x(2)}); }

}  // namespace

std::string serialize_gpc_domain(const polycube::GpcDomain& d) {
  Json j;
  j["format"] = "volspline-gpc";
  j["version"] = 1;
  j["genus"] = d.genus;
  j["caps"] = d.caps;
  j["tubes"] = d.tubes;
  j["t_shapes"] = d.t_shapes;
  Json cuboids = Json::array();
  for (const polycube::GpcCuboid& c : d.cuboids) {
    Json cj;
    cj["size"] = c.size;
    cj["nodes"] = c.nodes;
    cj["piece"] = c.piece;
    cj["piece_kind"] = c.piece_kind;
    cj["faces"] = c.face_interface;
    Json corners = Json::array();
    for (const Eigen::Vector3d& x : c.corner_xyz) corners.push_back(vec3(x));
    cj["corners"] = corners;
    cuboids.push_back(cj);
  }
  j["cuboids"] = cuboids;
  Json interfaces = Json::array();
  for (const polycube::GpcInterface& g : d.interfaces) {
    Json gj;
    gj["cuboids"] = g.cuboid;
    gj["faces"] = g.face;
    gj["axis"] = g.transition.axis;
    gj["sign"] = g.transition.sign;
    gj["translation"] = vec3(g.transition.translation);
    gj["cut"] = g.cut;
    interfaces.push_back(gj);
  }
  j["interfaces"] = interfaces;
  Json ill = Json::array();
  for (const polycube::GpcIllPoint& p : d.ill_points) {
    Json pj;
    pj["type"] = p.type;
    pj["cuboids"] = p.cuboids;
    pj["xyz"] = Json::array({vec3(p.xyz[0]), vec3(p.xyz[1])});
    ill.push_back(pj);
  }
  j["ill_points"] = ill;
  return j.dump(1) + "\n";
}

polycube::GpcDomain parse_gpc_domain(const std::string& text, const std::string& source) {
  const std::string where = "GPC file '" + source + "': ";
  Json j;
  try {
    j = Json::parse(text);
  } catch (const std::exception& e) {
    throw Error(where + "not JSON (" + e.what() + ")");
  }
  auto need = [&](const Json& obj, const char* key) -> const Json& {
    if (!obj.is_object() || !obj.contains(key)) throw Error(where + "missing field '" + key + "'");
    return obj[key];
  };
  auto integer = [&](const Json& v, const std::string& what) {
    if (!v.is_number_integer()) throw Error(where + what + " is not an integer");
    return v.get<int>();
  };
  auto number = [&](const Json& v, const std::string& what) {
    if (!v.is_number()) throw Error(where + what + " is not a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) throw Error(where + what + " is not finite");
    return x;
  };
  auto array = [&](const Json& v, std::size_t size, const std::string& what) -> const Json& {
    if (!v.is_array() || v.size() != size)
      throw Error(where + what + " is not an array of " + std::to_string(size));
    return v;
  };
  auto point = [&](const Json& v, const std::string& what) {
    array(v, 3, what);
    return Eigen::Vector3d(number(v[0], what), number(v[1], what), number(v[2], what));
  };
  if (need(j, "format") != "volspline-gpc") throw Error(where + "format is not 'volspline-gpc'");
  if (integer(need(j, "version"), "version") != 1) throw Error(where + "unsupported version");
  polycube::GpcDomain d;
  d.genus = integer(need(j, "genus"), "genus");
  d.caps = integer(need(j, "caps"), "caps");
  d.tubes = integer(need(j, "tubes"), "tubes");
  d.t_shapes = integer(need(j, "t_shapes"), "t_shapes");
  const Json& cuboids = need(j, "cuboids");
  const Json& interfaces = need(j, "interfaces");
  if (!cuboids.is_array() || !interfaces.is_array()) throw Error(where + "cuboids and interfaces must be arrays");
  for (std::size_t c = 0; c < cuboids.size(); ++c) {
    const std::string what = "cuboid " + std::to_string(c);
    const Json& cj = cuboids[c];
    polycube::GpcCuboid cuboid;
    const Json& size = array(need(cj, "size"), 3, what + " size");
    const Json& nodes = array(need(cj, "nodes"), 3, what + " nodes");
    for (int a = 0; a < 3; ++a) {
      cuboid.size[a] = number(size[a], what + " size");
      cuboid.nodes[a] = integer(nodes[a], what + " nodes");
      if (!(cuboid.size[a] > 0.0) || cuboid.nodes[a] < 2) throw Error(where + what + " has an empty axis");
    }
    cuboid.piece = integer(need(cj, "piece"), what + " piece");
    cuboid.piece_kind = integer(need(cj, "piece_kind"), what + " piece_kind");
    const Json& faces = array(need(cj, "faces"), 6, what + " faces");
    for (int f = 0; f < 6; ++f) {
      cuboid.face_interface[f] = integer(faces[f], what + " faces");
      if (cuboid.face_interface[f] < -1 || cuboid.face_interface[f] >= static_cast<int>(interfaces.size()))
        throw Error(where + what + " names an interface that does not exist");
    }
    const Json& corners = array(need(cj, "corners"), 8, what + " corners");
    for (int k = 0; k < 8; ++k) cuboid.corner_xyz[k] = point(corners[k], what + " corner");
    d.cuboids.push_back(cuboid);
  }
  for (std::size_t i = 0; i < interfaces.size(); ++i) {
    const std::string what = "interface " + std::to_string(i);
    const Json& gj = interfaces[i];
    polycube::GpcInterface g;
    const Json& cs = array(need(gj, "cuboids"), 2, what + " cuboids");
    const Json& fs = array(need(gj, "faces"), 2, what + " faces");
    for (int s = 0; s < 2; ++s) {
      g.cuboid[s] = integer(cs[s], what + " cuboids");
      g.face[s] = integer(fs[s], what + " faces");
      if (g.cuboid[s] < 0 || g.cuboid[s] >= static_cast<int>(d.cuboids.size()) || g.face[s] < 0 || g.face[s] > 5)
        throw Error(where + what + " names a cuboid or face that does not exist");
    }
    const Json& axis = array(need(gj, "axis"), 3, what + " axis");
    const Json& sign = array(need(gj, "sign"), 3, what + " sign");
    int seen = 0;
    for (int a = 0; a < 3; ++a) {
      g.transition.axis[a] = integer(axis[a], what + " axis");
      g.transition.sign[a] = integer(sign[a], what + " sign");
      if (g.transition.axis[a] < 0 || g.transition.axis[a] > 2 || std::abs(g.transition.sign[a]) != 1)
        throw Error(where + what + " has an invalid rotation");
      seen |= 1 << g.transition.axis[a];
    }
    if (seen != 7) throw Error(where + what + " has an invalid rotation");
    g.transition.translation = point(need(gj, "translation"), what + " translation");
    g.cut = integer(need(gj, "cut"), what + " cut");
    d.interfaces.push_back(g);
  }
  const Json& ill = need(j, "ill_points");
  if (!ill.is_array()) throw Error(where + "ill_points must be an array");
  for (std::size_t i = 0; i < ill.size(); ++i) {
    const std::string what = "ill-point " + std::to_string(i);
    polycube::GpcIllPoint p;
    p.type = integer(need(ill[i], "type"), what + " type");
    const Json& cs = array(need(ill[i], "cuboids"), 3, what + " cuboids");
    for (int k = 0; k < 3; ++k) p.cuboids[k] = integer(cs[k], what + " cuboids");
    const Json& xyz = array(need(ill[i], "xyz"), 2, what + " xyz");
    for (int k = 0; k < 2; ++k) p.xyz[k] = point(xyz[k], what + " xyz");
    d.ill_points.push_back(p);
  }
  return d;
}

void write_gpc_domain(const std::string& path, const polycube::GpcDomain& domain) {
  write_file_atomic(path, serialize_gpc_domain(domain));
}

polycube::GpcDomain read_gpc_domain(const std::string& path) { return parse_gpc_domain(read_file_bytes(path), path); }

}  // namespace volspline::io
