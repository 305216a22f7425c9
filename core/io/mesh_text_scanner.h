// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace volspline::io {

/// Walks a text mesh file line by line and token by token (tokens are separated by spaces, tabs
/// and '\r'), counting 1-based line numbers so that errors read "name:line: problem".
class MeshTextScanner {
 public:
  /// `text` must outlive the scanner; `name` is the file name used in error messages.
  MeshTextScanner(std::string_view text, std::string name);

  /// Moves to the next line; false (and no current line) at the end of the text.
  bool next_line();
  /// Moves to the next line that has a token before any '#' comment; false at the end.
  /// The comment part is cut off the current line.
  bool next_content_line();
  /// Next token of the current line; false when the line has no more tokens.
  bool next_token(std::string_view& token);
  /// Next token, moving to later lines when the current one is used up; false at the end.
  bool next_token_any_line(std::string_view& token);
  /// True when the current line has no more tokens.
  bool line_done();

  /// Next token of the current line as a finite double. Throws volspline::Error naming `what`
  /// if it is missing, not a number, NaN or infinite.
  double read_double(const char* what);
  /// Next token of the current line as an integer. Throws volspline::Error naming `what`.
  std::int64_t read_int(const char* what);

  /// 1-based number of the current line (0 before the first next_line()).
  int line_number() const { return line_number_; }
  /// Byte offset just past the current line (where the next line starts).
  std::size_t next_offset() const { return pos_; }
  /// Bytes from the start of the next line to the end of the text.
  std::size_t bytes_left() const { return text_.size() - pos_; }
  const std::string& name() const { return name_; }

  /// Throws volspline::Error "name:line: message".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string_view text_;
  std::string name_;
  std::size_t pos_ = 0;
  std::string_view line_;
  std::size_t token_pos_ = 0;
  int line_number_ = 0;
};

/// Parses a whole token as a double (locale independent, exact round trip of shortest output;
/// a leading '+' is accepted). False if the token is not entirely a number. NaN and infinity
/// parse successfully; callers check finiteness.
bool parse_double_token(std::string_view token, double& value);
/// Parses a whole token as a signed 64-bit integer (a leading '+' is accepted).
bool parse_int_token(std::string_view token, std::int64_t& value);

}  // namespace volspline::io
