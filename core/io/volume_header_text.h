// SPDX-License-Identifier: MIT
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

/// Text helpers shared by the volume header parsers (NRRD, legacy VTK, MetaImage, VTI, NIfTI).
/// Every parse_* throws volspline::Error "name: bad <what> '<text>'" (or names the count or sign
/// problem); `name` is the file named in messages, `what` the field.
namespace volspline::io::volume_text {

/// ASCII lower case.
std::string lower(std::string text);
/// Text without leading and trailing white space.
std::string trim(const std::string& text);
/// White-space separated words.
std::vector<std::string> split_words(const std::string& text);
/// Reads the line starting at pos (without '\n' or a trailing '\r') and moves pos past it.
/// Returns false at end of input.
bool next_line(const std::string& bytes, std::size_t& pos, std::string& line);
/// A whole decimal integer.
long long parse_integer(const std::string& text, const std::string& name, const std::string& what);
/// A whole finite real number.
double parse_real(const std::string& text, const std::string& name, const std::string& what);
/// Three positive sizes.
std::array<int, 3> parse_dims(const std::vector<std::string>& words, const std::string& name, const std::string& what);
/// Three positive spacings.
Eigen::Vector3d parse_spacing(const std::vector<std::string>& words, const std::string& name, const std::string& what);

}  // namespace volspline::io::volume_text
