// SPDX-License-Identifier: MIT
#include "core/io/volume_header_text.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "core/common/error.h"

namespace volspline::io::volume_text {

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string trim(const std::string& text) {
  std::size_t begin = 0;
  std::size_t end = text.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(text[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(text[end - 1]))) --end;
  return text.substr(begin, end - begin);
}

std::vector<std::string> split_words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> words;
  std::string word;
  while (in >> word) words.push_back(word);
  return words;
}

bool next_line(const std::string& bytes, std::size_t& pos, std::string& line) {
  if (pos >= bytes.size()) return false;
  const std::size_t end = bytes.find('\n', pos);
  const std::size_t stop = end == std::string::npos ? bytes.size() : end;
  line.assign(bytes, pos, stop - pos);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  pos = end == std::string::npos ? bytes.size() : end + 1;
  return true;
}

long long parse_integer(const std::string& text, const std::string& name, const std::string& what) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(t.c_str(), &end, 10);
  if (t.empty() || *end != '\0' || errno == ERANGE) throw Error(name + ": bad " + what + " '" + t + "'");
  return value;
}

double parse_real(const std::string& text, const std::string& name, const std::string& what) {
  const std::string t = trim(text);
  char* end = nullptr;
  const double value = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(value)) throw Error(name + ": bad " + what + " '" + t + "'");
  return value;
}

std::array<int, 3> parse_dims(const std::vector<std::string>& words, const std::string& name, const std::string& what) {
  if (words.size() != 3) throw Error(name + ": " + what + " needs 3 values, got " + std::to_string(words.size()));
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const long long value = parse_integer(words[a], name, what);
    if (value < 1 || value > std::numeric_limits<int>::max())
      throw Error(name + ": " + what + " value " + words[a] + " is not a positive size");
    dims[a] = static_cast<int>(value);
  }
  return dims;
}

Eigen::Vector3d parse_spacing(const std::vector<std::string>& words, const std::string& name, const std::string& what) {
  if (words.size() != 3) throw Error(name + ": " + what + " needs 3 values, got " + std::to_string(words.size()));
  Eigen::Vector3d spacing;
  for (int a = 0; a < 3; ++a) {
    spacing[a] = parse_real(words[a], name, what);
    if (!(spacing[a] > 0)) throw Error(name + ": " + what + " value " + words[a] + " is not positive");
  }
  return spacing;
}

}  // namespace volspline::io::volume_text
