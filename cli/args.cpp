// SPDX-License-Identifier: MIT
#include "cli/args.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace volspline::cli {

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = options.find(name);
  return it == options.end() || it->second.empty() ? fallback : it->second.back();
}

std::vector<std::string> Args::get_all(const std::string& name) const {
  auto it = options.find(name);
  return it == options.end() ? std::vector<std::string>{} : it->second;
}

double Args::get_double(const std::string& name, double fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value))
    throw UsageError("--" + name + " expects a number, got '" + text + "'");
  return value;
}

int Args::get_int(const std::string& name, int fallback) const {
  if (!has(name)) return fallback;
  const std::string text = get(name);
  char* end = nullptr;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || value < -2147483647L || value > 2147483647L)
    throw UsageError("--" + name + " expects an integer, got '" + text + "'");
  return static_cast<int>(value);
}

Args parse_args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs) {
  Args args;
  for (size_t i = 0; i < argv.size(); ++i) {
    // "-o" is the one short option: the conventional spelling of "--output".
    const std::string token = argv[i] == "-o" ? std::string("--output") : argv[i];
    if (token == "-h" || token == "--help") {
      args.options["help"].push_back("");
      continue;
    }
    if (token.size() < 2 || token.compare(0, 2, "--") != 0 || token == "--") {
      if (token.size() > 1 && token[0] == '-' && !std::isdigit(static_cast<unsigned char>(token[1])))
        throw UsageError("unknown option '" + token + "'");
      args.positional.push_back(token);
      continue;
    }
    std::string name = token.substr(2);
    std::string value;
    bool has_inline_value = false;
    if (auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_inline_value = true;
    }
    const OptionSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.name == name) spec = &s;
    if (!spec) throw UsageError("unknown option '--" + name + "' (see --help)");
    if (spec->value_name.empty()) {
      if (has_inline_value) throw UsageError("option '--" + name + "' takes no value");
    } else if (!has_inline_value) {
      if (i + 1 >= argv.size()) throw UsageError("option '--" + name + "' needs a value " + spec->value_name);
      value = argv[++i];
    }
    auto& values = args.options[name];
    if (!values.empty() && !spec->repeatable)
      throw UsageError("option '--" + name + "' given more than once");
    values.push_back(value);
  }
  return args;
}

std::string format_help(const std::string& usage, const std::string& description,
                        const std::vector<OptionSpec>& specs) {
  std::ostringstream out;
  out << "usage: " << usage << "\n\n" << description << "\n\noptions:\n";
  for (const auto& s : specs) {
    std::string left = "  --" + s.name + (s.value_name.empty() ? "" : " " + s.value_name);
    if (left.size() < 30) left.resize(30, ' ');
    else left += "  ";
    out << left << s.help << (s.repeatable ? " (repeatable)" : "") << "\n";
  }
  out << "  --help                      show this help\n";
  return out.str();
}

bool print_help_if_asked(const Args& args, const std::string& usage, const std::string& description,
                         const std::vector<OptionSpec>& specs) {
  if (!args.has("help")) return false;
  std::fputs(format_help(usage, description, specs).c_str(), stdout);
  return true;
}

std::vector<OptionSpec> with_job_options(std::vector<OptionSpec> specs, const std::string& threads_help) {
  specs.push_back({"stats-json", "FILE", "write the measures of the run as JSON"});
  specs.push_back({"threads", "N", threads_help});
  specs.push_back({"quiet", "", "no progress bar"});
  return specs;
}

}  // namespace volspline::cli
