// SPDX-License-Identifier: MIT
#include "core/io/ply_format.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/common/error.h"
#include "core/io/mesh_builder.h"
#include "core/io/mesh_text_scanner.h"
#include "core/io/number_text.h"

namespace volspline::io {

namespace {

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };
enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // the item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool parse_type(std::string_view word, PlyType& type) {
  struct Named {
    const char* name;
    PlyType type;
  };
  static constexpr Named kTypes[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},
      {"uint8", PlyType::Uint8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::Uint16}, {"uint16", PlyType::Uint16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& named : kTypes) {
    if (word == named.name) {
      type = named.type;
      return true;
    }
  }
  return false;
}

std::size_t type_size(PlyType type) {
  switch (type) {
    case PlyType::Int8:
    case PlyType::Uint8: return 1;
    case PlyType::Int16:
    case PlyType::Uint16: return 2;
    case PlyType::Int32:
    case PlyType::Uint32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 1;
}

// Reads binary values from the data section, checking every read against the end.
class BinaryCursor {
 public:
  BinaryCursor(const std::string& bytes, std::size_t pos, bool big_endian)
      : bytes_(bytes), pos_(pos), big_endian_(big_endian) {}

  bool can_read(std::size_t n) const { return bytes_.size() - pos_ >= n; }
  std::size_t remaining() const { return bytes_.size() - pos_; }

  // Precondition: can_read(type_size(type)).
  double read(PlyType type) {
    unsigned char raw[8];
    const std::size_t n = type_size(type);
    std::memcpy(raw, bytes_.data() + pos_, n);
    pos_ += n;
    if (big_endian_)
      for (std::size_t k = 0; k < n / 2; ++k) std::swap(raw[k], raw[n - 1 - k]);
    switch (type) {
      case PlyType::Int8: return static_cast<double>(static_cast<std::int8_t>(raw[0]));
      case PlyType::Uint8: return static_cast<double>(raw[0]);
      case PlyType::Int16: return static_cast<double>(load<std::int16_t>(raw));
      case PlyType::Uint16: return static_cast<double>(load<std::uint16_t>(raw));
      case PlyType::Int32: return static_cast<double>(load<std::int32_t>(raw));
      case PlyType::Uint32: return static_cast<double>(load<std::uint32_t>(raw));
      case PlyType::Float32: return static_cast<double>(load<float>(raw));
      case PlyType::Float64: return load<double>(raw);
    }
    return 0.0;
  }

 private:
  // Little-endian host assumed (x86-64, wasm32).
  template <typename T>
  static T load(const unsigned char* raw) {
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }

  const std::string& bytes_;
  std::size_t pos_;
  bool big_endian_;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
};

PlyHeader parse_header(MeshTextScanner& scan) {
  const std::string& name = scan.name();
  PlyHeader header;
  if (!scan.next_line()) throw Error(name + ": empty file");
  std::string_view token;
  if (!scan.next_token(token) || token != "ply" || !scan.line_done())
    scan.fail("not a PLY file (first line must be 'ply')");
  bool have_format = false;
  while (true) {
    if (!scan.next_line()) throw Error(name + ": truncated header (no end_header)");
    if (!scan.next_token(token)) continue;
    if (token == "end_header") break;
    if (token == "comment" || token == "obj_info") continue;
    if (token == "format") {
      std::string_view encoding, version;
      if (!scan.next_token(encoding) || !scan.next_token(version)) scan.fail("bad format line");
      if (encoding == "ascii")
        header.encoding = PlyEncoding::Ascii;
      else if (encoding == "binary_little_endian")
        header.encoding = PlyEncoding::BinaryLittle;
      else if (encoding == "binary_big_endian")
        header.encoding = PlyEncoding::BinaryBig;
      else
        scan.fail("unknown PLY format '" + std::string(encoding.substr(0, 30)) + "'");
      if (version != "1.0") scan.fail("unsupported PLY version '" + std::string(version.substr(0, 10)) + "'");
      have_format = true;
    } else if (token == "element") {
      PlyElement element;
      std::string_view element_name;
      if (!scan.next_token(element_name)) scan.fail("element without a name");
      element.name = std::string(element_name);
      element.count = scan.read_int("element count");
      if (element.count < 0)
        scan.fail("negative count " + std::to_string(element.count) + " for element '" + element.name + "'");
      header.elements.push_back(std::move(element));
    } else if (token == "property") {
      if (header.elements.empty()) scan.fail("property before any element");
      PlyProperty property;
      std::string_view type_word;
      if (!scan.next_token(type_word)) scan.fail("property without a type");
      if (type_word == "list") {
        property.is_list = true;
        std::string_view count_word, item_word;
        if (!scan.next_token(count_word) || !parse_type(count_word, property.count_type))
          scan.fail("bad list count type");
        if (!scan.next_token(item_word) || !parse_type(item_word, property.type)) scan.fail("bad list item type");
        if (property.count_type == PlyType::Float32 || property.count_type == PlyType::Float64)
          scan.fail("list count type must be an integer type");
      } else if (!parse_type(type_word, property.type)) {
        scan.fail("unknown property type '" + std::string(type_word.substr(0, 20)) + "'");
      }
      std::string_view property_name;
      if (!scan.next_token(property_name)) scan.fail("property without a name");
      property.name = std::string(property_name);
      header.elements.back().properties.push_back(std::move(property));
    } else {
      scan.fail("unknown header keyword '" + std::string(token.substr(0, 20)) + "'");
    }
  }
  if (!have_format) scan.fail("header has no format line");
  return header;
}

// Smallest number of data bytes one item of the element can take.
std::size_t min_item_bytes(const PlyElement& element, PlyEncoding encoding) {
  std::size_t bytes = 0;
  for (const auto& property : element.properties) {
    if (encoding == PlyEncoding::Ascii)
      bytes += 2;  // one digit and a separator
    else
      bytes += type_size(property.is_list ? property.count_type : property.type);
  }
  return bytes;
}

std::string number_text(double value) {
  std::string text;
  append_number(text, value);
  return text;
}

// Where the mesh data sits in the vertex and face elements.
struct MeshLayout {
  int vertex_element = -1;
  int face_element = -1;
  int x = -1, y = -1, z = -1;  // property ids in the vertex element
  int indices = -1;            // property id in the face element
};

MeshLayout find_layout(const PlyHeader& header, const std::string& name) {
  MeshLayout layout;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.name == "vertex" && layout.vertex_element < 0) {
      layout.vertex_element = static_cast<int>(e);
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (property.is_list) continue;
        if (property.name == "x") layout.x = static_cast<int>(p);
        if (property.name == "y") layout.y = static_cast<int>(p);
        if (property.name == "z") layout.z = static_cast<int>(p);
      }
    }
    if (element.name == "face" && layout.face_element < 0) {
      layout.face_element = static_cast<int>(e);
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (property.is_list && (property.name == "vertex_indices" || property.name == "vertex_index"))
          layout.indices = static_cast<int>(p);
      }
    }
  }
  if (layout.vertex_element < 0) throw Error(name + ": no 'vertex' element in the header");
  if (layout.x < 0 || layout.y < 0 || layout.z < 0)
    throw Error(name + ": vertex element lacks an x, y or z property");
  if (layout.face_element < 0 || header.elements[static_cast<std::size_t>(layout.face_element)].count == 0)
    throw Error(name + ": no faces");
  if (layout.indices < 0) throw Error(name + ": face element lacks a vertex_indices list");
  return layout;
}

// Reads the data section; `next_value(type, element, item, what)` returns the next value.
template <typename NextValue>
mesh::TriangleMesh read_data(const PlyHeader& header, const MeshLayout& layout, const std::string& name,
                             NextValue&& next_value) {
  const std::int64_t num_vertices = header.elements[static_cast<std::size_t>(layout.vertex_element)].count;
  MeshBuilder builder;
  builder.reserve(num_vertices, header.elements[static_cast<std::size_t>(layout.face_element)].count);
  std::vector<int> polygon;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const PlyElement& element = header.elements[e];
    if (element.properties.empty()) continue;
    const bool is_vertex = static_cast<int>(e) == layout.vertex_element;
    const bool is_face = static_cast<int>(e) == layout.face_element;
    for (std::int64_t item = 0; item < element.count; ++item) {
      double xyz[3] = {0.0, 0.0, 0.0};
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        const int pid = static_cast<int>(p);
        if (!property.is_list) {
          const double value = next_value(property.type, element, item);
          if (is_vertex && (pid == layout.x || pid == layout.y || pid == layout.z)) {
            const char* axis = pid == layout.x ? "x" : pid == layout.y ? "y" : "z";
            if (std::isnan(value))
              throw Error(name + ": vertex " + std::to_string(item) + ": NaN " + axis + " coordinate");
            if (std::isinf(value))
              throw Error(name + ": vertex " + std::to_string(item) + ": infinite " + axis + " coordinate");
            xyz[pid == layout.x ? 0 : pid == layout.y ? 1 : 2] = value;
          }
          continue;
        }
        const double count_value = next_value(property.count_type, element, item);
        // ASCII data can hold any number here; the largest count type is uint32.
        if (!(count_value >= 0 && count_value <= 4294967295.0) || count_value != std::floor(count_value))
          throw Error(name + ": " + element.name + " " + std::to_string(item) + ": bad list length");
        const auto count = static_cast<std::int64_t>(count_value);
        const bool indices = is_face && pid == layout.indices;
        if (indices && count < 3)
          throw Error(name + ": face " + std::to_string(item) + " has " + std::to_string(count) +
                      " vertices (needs at least 3)");
        if (indices) polygon.clear();
        for (std::int64_t k = 0; k < count; ++k) {
          const double value = next_value(property.type, element, item);
          if (!indices) continue;
          if (!(value >= 0 && value < static_cast<double>(num_vertices)))
            throw Error(name + ": face " + std::to_string(item) + ": index " + number_text(value) +
                        " out of range (" + std::to_string(num_vertices) + " vertices)");
          if (value != std::floor(value))
            throw Error(name + ": face " + std::to_string(item) + ": index is not an integer");
          polygon.push_back(static_cast<int>(value));
        }
        if (indices) builder.add_polygon(polygon.data(), polygon.size());
      }
      if (is_vertex) builder.add_vertex(xyz[0], xyz[1], xyz[2]);
    }
  }
  return builder.finish(name);
}

}  // namespace

mesh::TriangleMesh parse_ply(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error(name + ": empty file");
  MeshTextScanner scan(bytes, name);
  const PlyHeader header = parse_header(scan);
  const MeshLayout layout = find_layout(header, name);

  // Hostile headers: reject counts the remaining bytes cannot hold before allocating anything.
  const std::size_t data_bytes = scan.bytes_left();
  std::uint64_t needed = 0;
  for (const auto& element : header.elements) {
    const std::size_t item_bytes = min_item_bytes(element, header.encoding);
    if (item_bytes == 0) continue;
    const std::uint64_t limit = data_bytes / item_bytes + 1;
    if (static_cast<std::uint64_t>(element.count) > limit ||
        (needed += static_cast<std::uint64_t>(element.count) * item_bytes) > data_bytes + 1)
      throw Error(name + ": header claims " + std::to_string(element.count) + " " + element.name +
                  " elements but only " + std::to_string(data_bytes) + " bytes of data follow");
  }
  const std::int64_t num_vertices = header.elements[static_cast<std::size_t>(layout.vertex_element)].count;
  if (num_vertices > kMaxMeshElements) throw Error(name + ": too many vertices (" + std::to_string(num_vertices) + ")");

  if (header.encoding == PlyEncoding::Ascii) {
    return read_data(header, layout, name, [&](PlyType, const PlyElement& element, std::int64_t item) {
      std::string_view token;
      if (!scan.next_token_any_line(token))
        throw Error(name + ": ascii " + element.name + " data truncated at " + element.name + " " +
                    std::to_string(item) + " of " + std::to_string(element.count));
      double value = 0.0;
      if (!parse_double_token(token, value))
        scan.fail("bad number '" + std::string(token.substr(0, 40)) + "' in " + element.name + " " +
                  std::to_string(item));
      return value;
    });
  }
  BinaryCursor cursor(bytes, scan.next_offset(), header.encoding == PlyEncoding::BinaryBig);
  return read_data(header, layout, name, [&](PlyType type, const PlyElement& element, std::int64_t item) {
    if (!cursor.can_read(type_size(type)))
      throw Error(name + ": binary " + element.name + " data truncated at " + element.name + " " +
                  std::to_string(item) + " of " + std::to_string(element.count));
    return cursor.read(type);
  });
}

std::string serialize_ply(const mesh::TriangleMesh& mesh) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\ncomment volspline\nelement vertex ";
  append_number(out, static_cast<long long>(mesh.num_vertices()));
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  append_number(out, static_cast<long long>(mesh.num_faces()));
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
  const std::size_t header_size = out.size();
  out.resize(header_size + static_cast<std::size_t>(mesh.num_vertices()) * 24 +
             static_cast<std::size_t>(mesh.num_faces()) * 13);
  char* data = out.data() + header_size;
  // Little-endian host assumed (x86-64, wasm32), so the bytes are copied as they are.
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      const double value = mesh.positions(v, k);
      std::memcpy(data, &value, 8);
      data += 8;
    }
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    *data++ = 3;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t id = mesh.triangles(f, k);
      std::memcpy(data, &id, 4);
      data += 4;
    }
  }
  return out;
}

}  // namespace volspline::io
