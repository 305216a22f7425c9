// SPDX-License-Identifier: MIT
// The volspline command: a thin driver over core/pipeline. Exit codes: 0 ok, 1 failed job,
// 2 bad usage or bad input.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/heap_tuning.h"
#include "cli/messages.h"
#include "cli/output_files.h"
#include "core/common/error.h"
#include "core/common/version.h"

namespace {

const char* kUsage =
    "usage: volspline <command> [options]\n"
    "\n"
    "Turns discrete 3D data into volumetric (trivariate) splines.\n"
    "\n"
    "commands:\n"
    "  info FILE          mesh facts (counts, closed, manifold, genus, bounding box) or volume facts\n"
    "  gpc MESH           closed solid of any genus -> generalized poly-cube domain (thesis ch. 3)\n"
    "  mesh2spline MESH   closed triangle mesh of any genus -> trivariate T-spline (thesis ch. 3, 4)\n"
    "  eval SPLINE        evaluate a spline JSON file at --uvw u,v,w\n"
    "  lens IMAGE         focus+context magnification lens on an image (thesis ch. 6)\n"
    "  vol2spline VOLUME  scalar volume -> trivariate T-spline of (X, Y, Z, density) (thesis ch. 5)\n"
    "\n"
    "Run 'volspline <command> --help' for the options of a command.\n"
    "  --version          print the version\n";

struct Command {
  const char* name;
  int (*run)(const std::vector<std::string>&);
};

const Command kCommands[] = {
    {"info", volspline::cli::run_info},
    {"gpc", volspline::cli::run_gpc},
    {"mesh2spline", volspline::cli::run_mesh2spline},
    {"eval", volspline::cli::run_eval},
    {"lens", volspline::cli::run_lens},
    {"vol2spline", volspline::cli::run_vol2spline},
};

}  // namespace

using volspline::cli::printable;
using volspline::cli::with_flag_names;

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    std::printf("volspline %s\n", volspline::version());
    return 0;
  }
  const std::string name = args[0];
  // VOLSPLINE_HEAP_TUNING=0 keeps glibc's defaults (to measure the tuning, or to rule it out).
  const char* tuning = std::getenv("VOLSPLINE_HEAP_TUNING");
  if (!tuning || std::string(tuning) != "0") volspline::cli::tune_heap();
  for (const auto& command : kCommands) {
    if (name != command.name) continue;
    try {
      return command.run(std::vector<std::string>(args.begin() + 1, args.end()));
    } catch (const volspline::cli::UsageError& e) {
      std::fprintf(stderr, "volspline %s: %s\n", name.c_str(), printable(e.what()).c_str());
      return 2;
    } catch (const volspline::cli::WriteError& e) {
      std::fprintf(stderr, "volspline %s: error: %s\n", name.c_str(), printable(e.what()).c_str());
      return 1;
    } catch (const volspline::Error& e) {
      std::fprintf(stderr, "volspline %s: error: %s\n", name.c_str(), printable(with_flag_names(e.what())).c_str());
      return 2;
    } catch (const volspline::Cancelled&) {
      std::fprintf(stderr, "volspline %s: cancelled\n", name.c_str());
      return 1;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "volspline %s: out of memory\n", name.c_str());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "volspline %s: failed: %s\n", name.c_str(), printable(e.what()).c_str());
      return 1;
    }
  }
  std::fprintf(stderr, "volspline: unknown command '%s' (see 'volspline --help')\n", printable(name).c_str());
  return 2;
}
