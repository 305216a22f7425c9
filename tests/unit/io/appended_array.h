// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace volspline::test {

// The values of DataArray `name` of an uncompressed VTK XML document with appended raw data and
// UInt64 headers (VtkXmlWriter with compress = false); empty if the array is missing.
template <class T>
std::vector<T> appended_array(const std::string& text, const std::string& name) {
  const std::size_t element = text.find("Name=\"" + name + "\"");
  if (element == std::string::npos) return {};
  const std::size_t at = text.find("offset=\"", element) + 8;
  const std::size_t offset = std::stoull(text.substr(at, text.find('"', at) - at));
  const std::size_t data = text.find("<AppendedData encoding=\"raw\">\n_") + 31 + offset;
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, text.data() + data, 8);
  std::vector<T> values(bytes / sizeof(T));
  std::memcpy(values.data(), text.data() + data + 8, bytes);
  return values;
}

}  // namespace volspline::test
