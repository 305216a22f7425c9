// SPDX-License-Identifier: MIT
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace volspline::cli {

/// A usage error: bad or missing argument. Maps to exit code 2.
class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message) : std::runtime_error(message) {}
};

/// One option a command accepts.
struct OptionSpec {
  std::string name;        ///< long name without dashes, e.g. "stats-json"
  std::string value_name;  ///< e.g. "FILE"; empty for a flag
  std::string help;        ///< one line, with the default and unit
  bool repeatable = false;
};

/// Parsed command line of one command.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> options;  ///< flags map to {""}

  bool has(const std::string& name) const { return options.count(name) != 0; }
  /// Last value of the option, or fallback if absent.
  std::string get(const std::string& name, const std::string& fallback = "") const;
  /// All values of a repeatable option, in command-line order.
  std::vector<std::string> get_all(const std::string& name) const;
  /// Parsed numbers; throw UsageError naming the option if the value is not a number.
  double get_double(const std::string& name, double fallback) const;
  int get_int(const std::string& name, int fallback) const;
};

/// Parses argv (without program and command names) against the specs; "--help"/"-h" sets "help",
/// "-o" stands for "--output".
/// Accepts "--name value" and "--name=value". Throws UsageError on unknown or incomplete options.
Args parse_args(const std::vector<std::string>& argv, const std::vector<OptionSpec>& specs);

/// Formats a help text: usage line, description, then one line per option.
std::string format_help(const std::string& usage, const std::string& description,
                        const std::vector<OptionSpec>& specs);

/// If args has --help: prints format_help(usage, description, specs) to stdout and returns true
/// (the command then exits 0); otherwise returns false.
bool print_help_if_asked(const Args& args, const std::string& usage, const std::string& description,
                         const std::vector<OptionSpec>& specs);

/// A job's own options followed by those every job shares: --stats-json, --threads, --quiet
/// (--help is implicit). `threads_help` is the --threads line: what this job does with threads.
std::vector<OptionSpec> with_job_options(std::vector<OptionSpec> specs, const std::string& threads_help);

}  // namespace volspline::cli
