// SPDX-License-Identifier: MIT
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/gpc_spline_io.h"
#include "core/io/spline_json.h"

namespace volspline::cli {

int run_eval(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"uvw", "u,v,w", "parameter to evaluate at (repeatable); inside the spline's domain", true},
      {"jacobian", "", "also print the Jacobian rows dF/du dF/dv dF/dw"},
      {"cuboid", "K", "cuboid of a multi-cuboid (GPC) spline whose local u,v,w are given (default 0)"},
  };
  const Args args = parse_args(argv, specs);
  if (print_help_if_asked(args, "volspline eval SPLINE.json [--cuboid K] --uvw u,v,w [--uvw ...] [--jacobian]",
                          "Evaluates a spline JSON file (semi-standard form, Eq. 4.3; or a GPC spline, in\n"
                          "cuboid K's local coordinates) and prints one line 'x y z' per --uvw, at\n"
                          "round-trip precision.",
                          specs))
    return 0;
  if (args.positional.size() != 1) throw UsageError("expects exactly one SPLINE file (see --help)");
  if (!args.has("uvw")) throw UsageError("needs --uvw u,v,w");
  const std::string& path = args.positional[0];
  const std::string bytes = io::read_file_bytes(path);
  std::optional<spline::TSpline> single;
  std::optional<spline::GpcSpline> gpc;
  int cuboid = 0;
  if (io::is_gpc_spline_json(bytes)) {
    gpc.emplace(io::parse_gpc_spline_json(bytes, path));
    cuboid = args.get_int("cuboid", 0);
    if (cuboid < 0 || cuboid >= gpc->num_cuboids())
      throw UsageError("--cuboid must be in 0.." + std::to_string(gpc->num_cuboids() - 1) + ", got " +
                       std::to_string(cuboid));
  } else {
    single.emplace(io::parse_spline_json(bytes, path));
    if (args.has("cuboid") && args.get_int("cuboid", 0) != 0)
      throw UsageError("--cuboid: '" + path + "' is a one-cuboid spline (only --cuboid 0)");
  }
  // All values first, printed together: a refused point prints nothing, not the points before it.
  std::string output;
  char number[32];
  const auto append = [&](double x, bool first) {
    std::snprintf(number, sizeof(number), first ? "%.17g" : " %.17g", x);
    output += number;
  };
  for (const std::string& text : args.get_all("uvw")) {
    Eigen::Vector3d uvw;
    std::istringstream in(text);
    char comma1 = 0, comma2 = 0;
    std::string rest;
    if (!(in >> uvw(0) >> comma1 >> uvw(1) >> comma2 >> uvw(2)) || comma1 != ',' || comma2 != ',' || (in >> rest))
      throw UsageError("--uvw expects three comma-separated numbers, got '" + text + "'");
    const Eigen::VectorXd value = gpc ? gpc->evaluate(cuboid, uvw) : single->evaluate(uvw);
    if (!value.allFinite())
      throw Error("spline '" + path + "': F(" + text + ") is not finite (weights or points too large)");
    for (int d = 0; d < value.size(); ++d) append(value(d), d == 0);
    output += '\n';
    if (args.has("jacobian")) {
      const Eigen::MatrixXd jac = gpc ? gpc->jacobian(cuboid, uvw) : single->jacobian(uvw);
      if (!jac.allFinite())
        throw Error("spline '" + path + "': the Jacobian at " + text + " is not finite");
      for (int a = 0; a < 3; ++a) {
        for (int d = 0; d < jac.rows(); ++d) append(jac(d, a), d == 0);
        output += '\n';
      }
    }
  }
  std::fputs(output.c_str(), stdout);
  return 0;
}

}  // namespace volspline::cli
