// SPDX-License-Identifier: MIT
#include "core/io/volume_io.h"

#include "core/common/error.h"
#include "core/io/file_bytes.h"
#include "core/io/metaimage_format.h"
#include "core/io/nifti_format.h"
#include "core/io/nrrd_format.h"
#include "core/io/volume_data.h"
#include "core/io/vti_format.h"
#include "core/io/vtk_volume_format.h"

namespace volspline::io {

namespace {

using volume_data::DataLayout;
using volume_data::decode_data;

DataLayout parse_header(const std::string& bytes, VolumeFormat format, const std::string& name) {
  switch (format) {
    case VolumeFormat::Nrrd: return parse_nrrd_header(bytes, name);
    case VolumeFormat::Vtk: return parse_vtk_volume_header(bytes, name);
    case VolumeFormat::MetaImage: return parse_metaimage_header(bytes, name);
    case VolumeFormat::Raw:
    case VolumeFormat::Vti:
    case VolumeFormat::Nifti: break;
  }
  throw Error(name + ": raw volumes need dims and type (use parse_raw_volume)");
}

std::string sibling_path(const std::string& header_path, const std::string& file) {
  if (!file.empty() && file[0] == '/') return file;
  const auto slash = header_path.find_last_of("/\\");
  if (slash == std::string::npos) return file;
  return header_path.substr(0, slash + 1) + file;
}

}  // namespace

VolumeFormat volume_format_from_path(const std::string& path) {
  const std::string ext = file_extension(path);
  if (ext == "raw") return VolumeFormat::Raw;
  if (ext == "nrrd" || ext == "nhdr") return VolumeFormat::Nrrd;
  if (ext == "vtk") return VolumeFormat::Vtk;
  if (ext == "mhd" || ext == "mha") return VolumeFormat::MetaImage;
  if (ext == "vti") return VolumeFormat::Vti;
  if (ext == "nii") return VolumeFormat::Nifti;
  if (ext == "gz" && path.size() >= 7 && file_extension(path.substr(0, path.size() - 3)) == "nii") return VolumeFormat::Nifti;
  throw Error(path + ": unknown volume file extension '" + ext + "'");
}

volume::Volume parse_volume(const std::string& bytes, VolumeFormat format, const std::string& name,
                            const VolumeReadOptions& options) {
  if (format == VolumeFormat::Vti) return parse_vti(bytes, name, options.max_voxels);
  if (format == VolumeFormat::Nifti) return parse_nifti(bytes, name, options.max_voxels);
  const volume_data::DataLayout layout = parse_header(bytes, format, name);
  volume_data::check_voxel_limit(layout.raw.dims, options.max_voxels, name);
  if (!layout.data_file.empty())
    throw Error(name + ": data is in the detached file '" + layout.data_file + "'; read it with read_volume");
  return decode_data(bytes, layout.data_offset, layout, name);
}

volume::Volume read_volume(const std::string& path, const VolumeReadOptions& options) {
  const VolumeFormat format = volume_format_from_path(path);
  if (format == VolumeFormat::Raw) {
    std::optional<RawVolumeLayout> layout = options.raw_layout;
    if (!layout) layout = raw_layout_from_name(path);
    if (!layout) throw Error(path + ": " + raw_name_problem(path));
    volume_data::check_voxel_limit(layout->dims, options.max_voxels, path);
    return parse_raw_volume(read_file_bytes(path), *layout, path);
  }
  if (format == VolumeFormat::Vti || format == VolumeFormat::Nifti)
    return parse_volume(read_file_bytes(path), format, path, options);
  const std::string bytes = read_file_bytes(path);
  const volume_data::DataLayout layout = parse_header(bytes, format, path);
  volume_data::check_voxel_limit(layout.raw.dims, options.max_voxels, path);
  if (layout.data_file.empty()) return decode_data(bytes, layout.data_offset, layout, path);
  const std::string data_path = sibling_path(path, layout.data_file);
  return decode_data(read_file_bytes(data_path), 0, layout, data_path);
}

}  // namespace volspline::io