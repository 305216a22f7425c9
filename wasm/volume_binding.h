// SPDX-License-Identifier: MIT
#pragma once

#include <emscripten/val.h>

#include <string>

namespace volspline::wasm {

/// JS: loadVolume(bytes, name, layout) -> {ok:true, nx, ny, nz, spacing [x,y,z], origin [x,y,z],
///     direction [9] (column-major: axis a is [3a, 3a+3)), type, min, max,
/// samples: Float32Array (x fastest, nx·ny·nz)} or {ok:false, message}.
///   bytes   Uint8Array|ArrayBuffer of a volume file; format from `name`'s extension: raw, nrrd
///           (attached data, raw/ascii/gzip), vtk (structured points), mha/mhd (raw or zlib), vti, nii/nii.gz;
///           `name` prefixes error messages;
///   layout  for raw files: {dims: [nx, ny, nz], type: 'uint8'|'int8'|'uint16'|'int16'|'uint32'|
///           'int32'|'float32'|'float64', big_endian: boolean}, every key but dims optional; or
///           undefined/null to take the layout from a name like fuel_64x64x64_uint8.raw.
emscripten::val load_volume(const emscripten::val& bytes, const std::string& name, const emscripten::val& layout);

}  // namespace volspline::wasm
