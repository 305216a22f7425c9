// SPDX-License-Identifier: MIT
#include "core/io/mesh_text_scanner.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "core/common/error.h"

namespace volspline::io {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string shown(token.substr(0, kMaxShown));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + shown + (token.size() > kMaxShown ? "...'" : "'");
}

}  // namespace

MeshTextScanner::MeshTextScanner(std::string_view text, std::string name)
    : text_(text), name_(std::move(name)) {}

bool MeshTextScanner::next_line() {
  if (pos_ >= text_.size()) {
    line_ = {};
    token_pos_ = 0;
    return false;
  }
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line_ = text_.substr(pos_, stop - pos_);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  token_pos_ = 0;
  ++line_number_;
  return true;
}

bool MeshTextScanner::next_content_line() {
  while (next_line()) {
    const std::size_t hash = line_.find('#');
    if (hash != std::string_view::npos) line_ = line_.substr(0, hash);
    if (!line_done()) return true;
  }
  return false;
}

bool MeshTextScanner::line_done() {
  while (token_pos_ < line_.size() && is_space(line_[token_pos_])) ++token_pos_;
  return token_pos_ >= line_.size();
}

bool MeshTextScanner::next_token(std::string_view& token) {
  if (line_done()) return false;
  std::size_t end = token_pos_;
  while (end < line_.size() && !is_space(line_[end])) ++end;
  token = line_.substr(token_pos_, end - token_pos_);
  token_pos_ = end;
  return true;
}

bool MeshTextScanner::next_token_any_line(std::string_view& token) {
  while (!next_token(token))
    if (!next_line()) return false;
  return true;
}

double MeshTextScanner::read_double(const char* what) {
  std::string_view token;
  if (!next_token(token)) fail(std::string("missing ") + what);
  double value = 0.0;
  if (!parse_double_token(token, value)) fail(std::string("bad ") + what + " " + quoted(token));
  if (std::isnan(value)) fail(std::string("NaN ") + what);
  if (std::isinf(value)) fail(std::string("infinite ") + what);
  return value;
}

std::int64_t MeshTextScanner::read_int(const char* what) {
  std::string_view token;
  if (!next_token(token)) fail(std::string("missing ") + what);
  std::int64_t value = 0;
  if (!parse_int_token(token, value)) fail(std::string("bad ") + what + " " + quoted(token));
  return value;
}

void MeshTextScanner::fail(const std::string& message) const {
  throw Error(name_ + ":" + std::to_string(line_number_) + ": " + message);
}

bool parse_double_token(std::string_view token, double& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
#ifdef __EMSCRIPTEN__
  // Emscripten 3.1.6's libc++ has no double from_chars; strtod on a bounded copy rounds the
  // same way (correctly) and the core never changes the C locale.
  (void)end;
  if (token.size() > 400) return false;
  char copy[401];
  token.copy(copy, token.size());
  copy[token.size()] = '\0';
  // strtod also takes hex floats and leading blanks, which from_chars rejects.
  for (const char c : token)
    if (c == 'x' || c == 'X' || std::isspace(static_cast<unsigned char>(c))) return false;
  char* stop = nullptr;
  value = std::strtod(copy, &stop);
  if (stop != copy + token.size()) return false;
  return true;
#else
  const auto result = std::from_chars(token.data(), end, value);
  // Out-of-range magnitudes become ±inf or 0 like strtod, so they are reported as infinite.
  if (result.ec == std::errc::result_out_of_range && result.ptr == end) {
    value = token[0] == '-' ? -HUGE_VAL : HUGE_VAL;
    bool tiny = false;
    for (const char* c = token.data(); c != end; ++c)
      if ((*c == 'e' || *c == 'E') && c + 1 != end && c[1] == '-') tiny = true;
    if (tiny) value = 0.0;
    return true;
  }
  return result.ec == std::errc() && result.ptr == end;
#endif
}

bool parse_int_token(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace volspline::io
