// SPDX-License-Identifier: MIT
#include <cstdio>
#include <sstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/common/error.h"
#include "core/io/spline_json.h"

namespace volspline::cli {

int run_eval(const std::vector<std::string>& argv) {
  const std::vector<OptionSpec> specs = {
      {"uvw", "u,v,w", "parameter to evaluate at (repeatable); inside the spline's domain", true},
      {"jacobian", "", "also print the Jacobian rows dF/du dF/dv dF/dw"},
  };
  const Args args = parse_args(argv, specs);
  if (args.has("help")) {
    std::fputs(format_help("volspline eval SPLINE.json --uvw u,v,w [--uvw ...] [--jacobian]",
                           "Evaluates a spline JSON file (semi-standard form, Eq. 4.3) and prints one line\n"
                           "'x y z' per --uvw, at round-trip precision.",
                           specs)
                   .c_str(),
               stdout);
    return 0;
  }
  if (args.positional.size() != 1) throw UsageError("expects exactly one SPLINE file (see --help)");
  if (!args.has("uvw")) throw UsageError("needs --uvw u,v,w");
  const spline::TSpline spline = io::read_spline_json(args.positional[0]);
  for (const std::string& text : args.get_all("uvw")) {
    Eigen::Vector3d uvw;
    std::istringstream in(text);
    char comma1 = 0, comma2 = 0;
    std::string rest;
    if (!(in >> uvw(0) >> comma1 >> uvw(1) >> comma2 >> uvw(2)) || comma1 != ',' || comma2 != ',' || (in >> rest))
      throw UsageError("--uvw expects three comma-separated numbers, got '" + text + "'");
    const Eigen::VectorXd value = spline.evaluate(uvw);
    if (!value.allFinite())
      throw Error("spline '" + args.positional[0] + "': F(" + text + ") is not finite (weights or points too large)");
    for (int d = 0; d < value.size(); ++d) std::printf(d ? " %.17g" : "%.17g", value(d));
    std::printf("\n");
    if (args.has("jacobian")) {
      const Eigen::MatrixXd jac = spline.jacobian(uvw);
      if (!jac.allFinite())
        throw Error("spline '" + args.positional[0] + "': the Jacobian at " + text + " is not finite");
      for (int a = 0; a < 3; ++a) {
        for (int d = 0; d < jac.rows(); ++d) std::printf(d ? " %.17g" : "%.17g", jac(d, a));
        std::printf("\n");
      }
    }
  }
  return 0;
}

}  // namespace volspline::cli
