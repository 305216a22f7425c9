// SPDX-License-Identifier: MIT
#include "cli/corners_file.h"

#include <sstream>

#include "core/common/error.h"
#include "core/io/file_bytes.h"

namespace volspline::cli {

std::vector<int> read_corner_ids(const std::string& path) {
  std::istringstream in(io::read_file_bytes(path));
  std::vector<int> ids;
  std::string token;
  while (in >> token) {
    std::size_t used = 0;
    int id = -1;
    try {
      id = std::stoi(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size() || id < 0) throw Error("corners file '" + path + "': '" + token + "' is not a vertex id");
    ids.push_back(id);
  }
  if (ids.size() != 8)
    throw Error("corners file '" + path + "': expected 8 vertex ids, found " + std::to_string(ids.size()));
  return ids;
}

}  // namespace volspline::cli
