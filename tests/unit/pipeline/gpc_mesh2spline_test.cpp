// SPDX-License-Identifier: MIT
#include <doctest/doctest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/io/gpc_spline_io.h"
#include "core/pipeline/gpc_mesh2spline.h"
#include "tests/unit/common/test_meshes.h"

using namespace volspline;

namespace {

pipeline::GpcMesh2SplineOptions small_options() {
  pipeline::GpcMesh2SplineOptions o;
  o.gpc.grid.target_nodes = 3000;
  o.measure_lattice = 32;
  o.measure_samples = 16;
  return o;
}

// The genus-2 slab's conversion with small_options, shared by the cases that read it.
const pipeline::GpcMesh2SplineResult& slab_result() {
  static const pipeline::GpcMesh2SplineResult r =
      pipeline::run_gpc_mesh2spline(test::two_hole_slab(3), "slab", small_options());
  return r;
}

}  // namespace

TEST_CASE("gpc mesh2spline: a torus is one cuboid glued to itself, C² across the glued face") {
  const pipeline::GpcMesh2SplineResult r =
      pipeline::run_gpc_mesh2spline(test::torus(64, 24, 1.0, 0.35), "torus", small_options());
  const pipeline::Mesh2SplineStats& s = r.stats;
  CHECK(s.genus == 1);
  CHECK(s.cuboids == 1);
  CHECK(s.ill_points == 0);
  CHECK(s.interfaces == 1);
  CHECK(s.continued_interfaces == 1);
  CHECK(s.rms_rel <= 0.002);
  CHECK(s.hausdorff_rel <= 0.01);
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.interface_gap_rel <= 1e-9);
  CHECK(s.interface_normal_jump_deg <= 1e-6);
  CHECK(s.negative_jacobian_fraction == 0.0);
  CHECK(s.lattice_negative_fraction == 0.0);
  // The spline's points are in model units: the torus's outer radius is 1.35.
  const polycube::GpcCuboid& c = r.spline.domain().cuboids[0];
  double far = 0.0;
  for (int i = 0; i <= 20; ++i)
    for (int f = 0; f < 6; ++f) {
      if (c.face_interface[f] >= 0) continue;
      Eigen::Vector3d uvw(c.size[0] * 0.5, c.size[1] * 0.5, c.size[2] * 0.5);
      uvw(f / 2) = f % 2 ? c.size[f / 2] : 0.0;
      uvw((f / 2 + 1) % 3) = c.size[(f / 2 + 1) % 3] * i / 20.0;
      const Eigen::VectorXd x = r.spline.evaluate(0, uvw);
      far = std::max(far, std::hypot(x(0), x(1)));
    }
  CHECK(far == doctest::Approx(1.35).epsilon(0.01));
}

TEST_CASE("gpc mesh2spline: adaptive knots on a torus keep the glued spline exact and meet both targets") {
  pipeline::GpcMesh2SplineOptions o = small_options();
  o.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Adaptive;
  o.max_rms_rel = 0.001;
  o.max_surface_error_rel = 0.001;
  const pipeline::GpcMesh2SplineResult r = pipeline::run_gpc_mesh2spline(test::torus(64, 24, 1.0, 0.35), "torus", o);
  const pipeline::Mesh2SplineStats& s = r.stats;
  CHECK(s.genus == 1);
  REQUIRE(s.level_history.size() >= 2);
  CHECK(s.rms_rel <= 0.001);
  CHECK(s.level_history.back().surface_max_rel <= 0.001);
  CHECK(s.hausdorff_rel <= 0.01);  // off the samples
  for (std::size_t l = 1; l < s.level_history.size(); ++l)
    CHECK(s.level_history[l].control_points > s.level_history[l - 1].control_points);
  CHECK_FALSE(r.spline.uniform_knots());
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.interface_gap_rel <= 1e-9);
  CHECK(s.interface_normal_jump_deg <= 1e-6);
  CHECK(s.negative_jacobian_fraction == 0.0);
  // The file holds the knot lines: write → read → write is byte-identical.
  const std::string text = io::serialize_gpc_spline_json(r.spline);
  CHECK(text.find("\"knot_lines\"") != std::string::npos);
  CHECK(io::serialize_gpc_spline_json(io::parse_gpc_spline_json(text, "torus")) == text);
}

TEST_CASE("gpc mesh2spline: hierarchical splits on a torus meet the target exactly merged, with fewer functions") {
  pipeline::GpcMesh2SplineOptions o = small_options();
  o.max_rms_rel = 0.0005;
  o.max_surface_error_rel = 0.0;
  const mesh::TriangleMesh torus = test::torus(64, 24, 1.0, 0.35);
  o.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Uniform;
  const pipeline::GpcMesh2SplineResult uniform = pipeline::run_gpc_mesh2spline(torus, "torus", o);
  o.refinement = pipeline::GpcMesh2SplineOptions::Refinement::Hierarchical;
  const pipeline::GpcMesh2SplineResult r = pipeline::run_gpc_mesh2spline(torus, "torus", o);
  const pipeline::Mesh2SplineStats& s = r.stats;
  MESSAGE("uniform " << uniform.stats.control_points << " cp at rms " << uniform.stats.rms_rel << ", hierarchical "
                     << s.control_points << " cp at rms " << s.rms_rel);
  for (const auto& l : s.level_history) MESSAGE(l.control_points << " " << l.rms_rel);
  CHECK(s.rms_rel <= 0.0005);
  CHECK(r.spline.max_level() >= 1);
  CHECK_FALSE(r.spline.splits().empty());
  CHECK(s.control_points < uniform.stats.control_points);
  CHECK(s.hausdorff_rel <= 0.01);
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.interface_gap_rel <= 1e-9);
  CHECK(s.interface_normal_jump_deg <= 1e-6);
  CHECK(s.negative_jacobian_fraction == 0.0);
  const std::string text = io::serialize_gpc_spline_json(r.spline);
  CHECK(text.find("\"splits\"") != std::string::npos);
  CHECK(io::serialize_gpc_spline_json(io::parse_gpc_spline_json(text, "torus")) == text);
}

TEST_CASE("gpc mesh2spline: a two-hole slab (genus 2) converts without folds, one spline over its cuboids") {
  const pipeline::Mesh2SplineStats& s = slab_result().stats;
  CHECK(s.genus == 2);
  CHECK(s.cuboids > 1);
  CHECK(s.ill_points == 4);
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.interface_gap_rel <= 1e-9);
  CHECK(s.interface_normal_jump_deg <= 1e-6);
  CHECK(s.negative_jacobian_fraction == 0.0);
  CHECK(s.rms_rel <= 0.01);
  // Its fit folds: the untangling moves the surface, by less than the fit's own accuracy target.
  CHECK(s.untangle_surface_shift_rel > 0.0);
  CHECK(s.untangle_surface_shift_rel < 0.01);
}

TEST_CASE("gpc mesh2spline: a cube's wireframe (genus 5) converts with the poles off its axis, and says so") {
  pipeline::GpcMesh2SplineOptions o = small_options();
  // The domain is what this case is about: the level-0 spline over it, not untangled (the voxel
  // bars' sharp edges make the untangling the bulk of the job).
  o.max_levels = 0;
  o.untangle = pipeline::GpcMesh2SplineOptions::Untangle::Off;
  const pipeline::GpcMesh2SplineResult r = pipeline::run_gpc_mesh2spline(test::cube_frame(2), "frame", o);
  const pipeline::Mesh2SplineStats& s = r.stats;
  CHECK(s.genus == 5);
  CHECK(s.t_shapes == 8);
  REQUIRE(s.domain_retries.count("off_axis_poles") == 1);
  CHECK(s.domain_retries.at("off_axis_poles").find("pole offset") == 0);
  CHECK(s.semi_standard_max_error <= 1e-12);
  CHECK(s.interface_gap_rel <= 1e-9);
  CHECK(s.untangle_surface_shift_rel == 0.0);
}

TEST_CASE("gpc spline JSON: write, read, write is byte-identical and evaluates the same") {
  const pipeline::GpcMesh2SplineResult& r = slab_result();
  const std::string text = io::serialize_gpc_spline_json(r.spline);
  CHECK(io::is_gpc_spline_json(text));
  // The cuboids' untangling on two threads gives the same bytes.
  pipeline::GpcMesh2SplineOptions two = small_options();
  two.threads = 2;
  CHECK(io::serialize_gpc_spline_json(pipeline::run_gpc_mesh2spline(test::two_hole_slab(3), "slab", two).spline) == text);
  const spline::GpcSpline back = io::parse_gpc_spline_json(text, "slab.json");
  CHECK(io::serialize_gpc_spline_json(back) == text);
  REQUIRE(back.num_functions() == r.spline.num_functions());
  for (int c = 0; c < back.num_cuboids(); ++c) {
    const auto& size = back.domain().cuboids[c].size;
    const Eigen::Vector3d uvw(0.3 * size[0], 0.6 * size[1], 0.9 * size[2]);
    CHECK((back.evaluate(c, uvw) - r.spline.evaluate(c, uvw)).norm() == 0.0);
  }
  // Bad files are refused naming the file and the problem.
  std::string wrong = text;
  wrong.replace(wrong.find("\"points\""), 8, "\"pointz\"");
  CHECK_THROWS_WITH_AS(io::parse_gpc_spline_json(wrong, "w.json"), doctest::Contains("w.json"), Error);
  CHECK_THROWS_WITH_AS(io::parse_gpc_spline_json(wrong, "w.json"), doctest::Contains("\"points\""), Error);
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(text);
  doc["intervals"][0] = {200, 200, 200};  // 8·10⁶ cells, under the 2^24 cap
  const std::string huge = doc.dump();
  // More knot cells than points is refused before any function is built (a few bytes cannot ask
  // for gigabytes).
  CHECK_THROWS_WITH_AS(io::parse_gpc_spline_json(huge, "h.json"), doctest::Contains("knot cells, more than the"), Error);
  CHECK_FALSE(io::is_gpc_spline_json("{\"format\": \"volspline-spline\"}"));
}

TEST_CASE("gpc mesh2spline: the untangling reports its cuboids and certificate rounds and stops in each") {
  pipeline::GpcMesh2SplineOptions o = small_options();
  o.threads = 2;  // the cuboids' reports come from their threads
  o.untangle_start = pipeline::GpcMesh2SplineOptions::UntangleStart::PassesFirst;
  std::vector<std::pair<std::string, double>> reports;
  const Progress record([&reports](const std::string& stage, double fraction) {
    reports.emplace_back(stage, fraction);
    return true;
  });
  const mesh::TriangleMesh torus = test::torus(64, 24, 1.0, 0.35);
  pipeline::run_gpc_mesh2spline(torus, "torus", o, record);
  // The torus's fit folds slightly along the tube's 4 edges: a certificate round runs. Each kind
  // of report, the count at which a second run cancels.
  const std::vector<std::pair<std::string, int>> kinds = {{"untangle: cuboids", 2}, {"untangle: certificate round ", 1}};
  double previous = 0.9;
  for (const auto& entry : kinds) {
    const std::string& kind = entry.first;  // not a structured binding: CAPTURE's lambda reads it
    const int at = entry.second;
    CAPTURE(kind);
    int seen = 0;
    for (const auto& [stage, fraction] : reports) {
      if (stage.rfind(kind, 0) != 0) continue;
      ++seen;
      CHECK(fraction >= previous);  // no step back within the untangling
      CHECK(fraction <= 0.91);
      previous = fraction;
    }
    CHECK(seen >= at);
    // A cancel request at that report stops the job there.
    int count = 0;
    std::string last;
    const Progress stop([&](const std::string& stage, double) {
      last = stage;
      return !(stage.rfind(kind, 0) == 0 && ++count == at);
    });
    CHECK_THROWS_AS(pipeline::run_gpc_mesh2spline(torus, "torus", o, stop), Cancelled);
    CHECK(last.rfind(kind, 0) == 0);
  }
  // The rounds name the cells they start from.
  for (const auto& [stage, fraction] : reports)
    if (stage.rfind("untangle: certificate round ", 0) == 0) CHECK(stage.find(" cells uncertified") != std::string::npos);
  // certificate_rounds 0: the untangling runs no round; out of [0, 64] it is refused.
  o.certificate_rounds = 0;
  reports.clear();
  pipeline::run_gpc_mesh2spline(torus, "torus", o, record);
  int rounds = 0;
  for (const auto& [stage, fraction] : reports) rounds += stage.rfind("untangle: certificate round ", 0) == 0;
  CHECK(rounds == 0);
  o.certificate_rounds = 65;
  CHECK_THROWS_WITH_AS(pipeline::run_gpc_mesh2spline(torus, "torus", o), doctest::Contains("`certificate_rounds`"), Error);
}

TEST_CASE("gpc mesh2spline: the untangling starts with the certificate rounds and restores the fit exactly") {
  pipeline::GpcMesh2SplineOptions o = small_options();
  std::vector<std::string> stages;
  const Progress record([&stages](const std::string& stage, double) {
    stages.push_back(stage);
    return true;
  });
  auto count = [&stages](const std::string& prefix) {
    int n = 0;
    for (const std::string& s : stages) n += s.rfind(prefix, 0) == 0;
    return n;
  };
  const mesh::TriangleMesh torus = test::torus(64, 24, 1.0, 0.35);
  // The torus's fit folds slightly along the tube's 4 edges, which the rounds alone certify: no
  // per-cuboid pass runs.
  const pipeline::GpcMesh2SplineResult rounds_first = pipeline::run_gpc_mesh2spline(torus, "torus", o, record);
  CHECK(rounds_first.stats.jacobian_certified_fraction == 1.0);
  CHECK(count("untangle: certificate round ") >= 1);
  CHECK(count("untangle: cuboids") == 0);
  CHECK(rounds_first.stats.untangle_path == "rounds");
  CHECK(rounds_first.stats.certificate_passes >= 1);
  CHECK(rounds_first.stats.local_certificate_passes <= rounds_first.stats.certificate_passes);
  // On the genus-2 slab one round leaves cells uncertified: the fit is restored and the passes,
  // then one round, run, to the bytes of PassesFirst (the cell polynomials rebuilt exactly, not
  // rounded back).
  o.certificate_rounds = 1;
  o.refit_folded_nodes = false;  // one untangling to compare
  stages.clear();
  const mesh::TriangleMesh slab = test::two_hole_slab(3);
  const pipeline::GpcMesh2SplineResult restored = pipeline::run_gpc_mesh2spline(slab, "slab", o, record);
  CHECK(restored.stats.jacobian_certified_fraction < 1.0);
  CHECK(count("untangle: certificate round ") >= 2);  // the rounds first, then after the passes
  CHECK(count("untangle: cuboids") >= 1);
  CHECK(restored.stats.untangle_path == "passes");
  o.untangle_start = pipeline::GpcMesh2SplineOptions::UntangleStart::PassesFirst;
  const pipeline::GpcMesh2SplineResult passes_first = pipeline::run_gpc_mesh2spline(slab, "slab", o);
  CHECK(io::serialize_gpc_spline_json(passes_first.spline) == io::serialize_gpc_spline_json(restored.spline));
  CHECK(passes_first.stats.untangle_path == "passes");
  // The rounds-first attempt's passes are counted too.
  CHECK(restored.stats.certificate_passes > passes_first.stats.certificate_passes);
}
