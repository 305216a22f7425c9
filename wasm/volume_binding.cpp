// SPDX-License-Identifier: MIT
#include "wasm/volume_binding.h"

#include <algorithm>
#include <optional>

#include "core/common/error.h"
#include "core/io/volume_io.h"
#include "wasm/guarded.h"
#include "wasm/js_values.h"

namespace volspline::wasm {

using emscripten::val;

namespace {

std::optional<io::RawVolumeLayout> layout_from_js(const val& layout, const std::string& name) {
  if (layout.isUndefined() || layout.isNull()) return io::raw_layout_from_name(name);
  if (layout.typeOf().as<std::string>() != "object") throw Error("volume layout: expected {dims, type, big_endian}");
  io::RawVolumeLayout out;
  const val dims = layout["dims"];
  if (!dims.isArray() || dims["length"].as<int>() != 3) throw Error("volume layout: 'dims' must be [nx, ny, nz]");
  for (int k = 0; k < 3; ++k) {
    const val d = dims[k];
    if (!d.isNumber() || d.as<double>() < 1 || d.as<double>() > 1 << 20 || d.as<double>() != static_cast<int>(d.as<double>()))
      throw Error("volume layout: dims[" + std::to_string(k) + "] must be a positive integer");
    out.dims[k] = d.as<int>();
  }
  out.type = io::sample_type_from_name(string_option(layout, "type", "uint8"));
  out.big_endian = bool_option(layout, "big_endian", false);
  return out;
}

}  // namespace

val load_volume(const val& bytes, const std::string& name, const val& layout) {
  return guarded([&] {
    const std::string data = bytes_from_js(bytes, "volume '" + name + "'");
    const io::VolumeFormat format = io::volume_format_from_path(name);
    volume::Volume v;
    if (format == io::VolumeFormat::Raw) {
      const std::optional<io::RawVolumeLayout> raw = layout_from_js(layout, name);
      if (!raw)
        throw Error(name + ": a raw volume needs its dims: enter them, or name the file like fuel_64x64x64_uint8.raw");
      v = io::parse_raw_volume(data, *raw, name);
    } else {
      v = io::parse_volume(data, format, name);
    }
    val out = val::object();
    out.set("ok", true);
    out.set("nx", v.nx);
    out.set("ny", v.ny);
    out.set("nz", v.nz);
    val spacing = val::array();
    for (int k = 0; k < 3; ++k) spacing.call<void>("push", v.spacing[k]);
    out.set("spacing", spacing);
    val origin = val::array();
    for (int k = 0; k < 3; ++k) origin.call<void>("push", v.origin[k]);
    out.set("origin", origin);
    val direction = val::array();  // column-major: axis a's direction is [3a, 3a + 3)
    for (int k = 0; k < 9; ++k) direction.call<void>("push", v.direction(k % 3, k / 3));
    out.set("direction", direction);
    out.set("type", volume::sample_type_name(v.original_type));
    const auto [lo, hi] = std::minmax_element(v.samples.begin(), v.samples.end());
    out.set("min", v.samples.empty() ? 0.0 : static_cast<double>(*lo));
    out.set("max", v.samples.empty() ? 0.0 : static_cast<double>(*hi));
    out.set("samples", float32_array(v.samples.data(), v.samples.size()));
    return out;
  });
}

}  // namespace volspline::wasm
