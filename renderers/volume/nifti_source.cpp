// NIfTI-1 and NIfTI-2 (.nii, .nii.gz) through nifticlib's nifti2_io, which reads both into one
// nifti_image. nifticlib parses the header (byte order, datatype, qform/sform, scaling); the
// voxels then come through svr's own payload reader (volume_source.cpp), which checks sizes,
// gzip streams and the memory budget exactly as for NRRD and can read one brick or a lattice.
#include <fmt/format.h>
#include <nifti/nifti2_io.h>
#include <zlib.h>

#include <array>
#include <cmath>
#include <cstring>
#include <memory>

#include "renderers/volume/volume_source.h"
#include "base/error.h"

namespace svr::detail {

namespace {

// nifti_image::byteorder's "most significant byte first" (nifti2_io.h defines MSB_FIRST only
// for nifticlib's own sources).
constexpr int kMsbFirst = 2;

struct NiftiFree {
  void operator()(nifti_image* image) const { nifti_image_free(image); }
};

// nifticlib says only "cannot read" for a bad header, and trusts dim[0] (a NIfTI-2 header with
// dim[0] = 16777212 overflows its stack: found by fuzz_nifti), so sizeof_hdr and the dims are
// checked here first: sizeof_hdr is 348 (NIfTI-1, int16 dims at byte 40) or 540 (NIfTI-2,
// int64 dims at byte 16), in either byte order. Returns the version.
int checkNiftiHeader(const std::string& path) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) throw Error(fmt::format("{}: cannot open: {}", path, std::strerror(errno)));
  std::array<unsigned char, 80> b{};
  const int got = gzread(file, b.data(), static_cast<unsigned>(b.size()));
  gzclose(file);
  if (got < 80)
    throw Error(fmt::format("{}: holds {} bytes; a NIfTI header needs 348 (NIfTI-1) or 540 "
                            "(NIfTI-2)",
                            path, got < 0 ? 0 : got));
  // The integer of `width` bytes at `at`, little- or big-endian.
  const auto integer = [&](std::size_t at, int width, bool big) {
    std::uint64_t v = 0;
    for (int i = 0; i < width; ++i)
      v |= std::uint64_t{b[at + static_cast<std::size_t>(big ? width - 1 - i : i)]} << (8 * i);
    return width == 2 ? static_cast<std::int64_t>(static_cast<std::int16_t>(v))
           : width == 4 ? static_cast<std::int64_t>(static_cast<std::int32_t>(v))
                        : static_cast<std::int64_t>(v);
  };
  for (const bool big : {false, true}) {
    const std::int64_t size = integer(0, 4, big);
    if (size != 348 && size != 540) continue;
    const int width = size == 348 ? 2 : 8;
    const std::size_t dims_at = size == 348 ? 40 : 16;
    const std::int64_t rank = integer(dims_at, width, big);
    if (rank < 1 || rank > 7)
      throw Error(fmt::format("{}: dim[0] is {}; expected 1 … 7", path, rank));
    for (int a = 1; a <= rank; ++a)
      if (const std::int64_t n = integer(dims_at + static_cast<std::size_t>(a * width), width, big);
          n < 1)
        throw Error(fmt::format("{}: dim[{}] is {}; expected ≥ 1", path, a, n));
    return size == 348 ? 1 : 2;
  }
  throw Error(fmt::format("{}: sizeof_hdr is {}; a NIfTI file starts with 348 (NIfTI-1) or 540 "
                          "(NIfTI-2): is this a NIfTI file?",
                          path, integer(0, 4, false)));
}

ScalarType scalarType(const nifti_image& nim, const std::string& path) {
  switch (nim.datatype) {
    case DT_UINT8: return ScalarType::kUint8;
    case DT_INT8: return ScalarType::kInt8;
    case DT_UINT16: return ScalarType::kUint16;
    case DT_INT16: return ScalarType::kInt16;
    case DT_UINT32: return ScalarType::kUint32;
    case DT_INT32: return ScalarType::kInt32;
    case DT_FLOAT32: return ScalarType::kFloat32;
    case DT_FLOAT64: return ScalarType::kFloat64;
    default:
      throw Error(fmt::format("{}: datatype {} ({}) is not one svr renders; expected uint8, "
                              "int8, uint16, int16, uint32, int32, float32 or float64",
                              path, nim.datatype, nifti_datatype_string(nim.datatype)));
  }
}

// Spacing and orientation: the sform when its code says it is set, else the qform, else pixdim
// in file order (NIfTI's "method 1", for ANALYZE-era files).
void readGeometry(const nifti_image& nim, VolumeSource& source) {
  VolumeHeader& h = source.header;
  const nifti_dmat44* m = nim.sform_code > 0   ? &nim.sto_xyz
                          : nim.qform_code > 0 ? &nim.qto_xyz
                                               : nullptr;
  if (!m) {
    for (int a = 0; a < 3; ++a) {
      const double d = nim.dim[0] > a ? std::abs(nim.pixdim[a + 1]) : 1.0;
      if (!std::isfinite(d) || d <= 0)
        throw Error(fmt::format("{}: pixdim[{}] is {}; spacing must be finite and > 0", h.path,
                                a + 1, nim.pixdim[a + 1]));
      h.spacing[a] = d;
    }
    h.orientation = "none stated (qform_code and sform_code are 0): file order, pixdim spacing";
    return;
  }
  std::array<glm::dvec3, 3> columns;
  for (int c = 0; c < 3; ++c) {
    columns[c] = {m->m[0][c], m->m[1][c], m->m[2][c]};
    h.spacing[c] = std::sqrt(columns[c].x * columns[c].x + columns[c].y * columns[c].y +
                             columns[c].z * columns[c].z);
  }
  const char* which = nim.sform_code > 0 ? "sform" : "qform";
  const OrientedAxes oriented = axesToRas(columns, fmt::format("{}: the {}", h.path, which));
  source.axes = oriented.map;
  h.orientation = fmt::format("{}: file axes i, j, k point {}, {}, {}; turned to RAS", which,
                              oriented.file_axes[0], oriented.file_axes[1], oriented.file_axes[2]);
  if (oriented.oblique_degrees > 0.01)
    h.orientation += fmt::format(" (oblique by {:.2f}°: nearest axes kept, not resampled)",
                                 oriented.oblique_degrees);
}

}  // namespace

VolumeSource readNiftiSource(const std::string& path) {
  const int version = checkNiftiHeader(path);
  nifti_set_debug_level(0);  // errors are reported here, naming the file, not on stderr
  const std::unique_ptr<nifti_image, NiftiFree> nim(nifti_image_read(path.c_str(), 0));
  if (!nim) throw Error(fmt::format("{}: nifticlib cannot read its NIfTI header", path));
  VolumeSource source;
  VolumeHeader& h = source.header;
  h.path = path;
  h.format = fmt::format("nifti-{}", version);
  for (int a = 4; a <= nim->dim[0] && a <= 7; ++a)
    if (nim->dim[a] > 1)
      throw Error(fmt::format("{}: dim[{}] is {}: a {}-D image; svr renders one 3-D volume", path,
                              a, nim->dim[a], nim->dim[0]));
  for (int a = 0; a < 3; ++a) {
    const std::int64_t n = nim->dim[0] > a ? nim->dim[a + 1] : 1;
    if (n < 1 || n > (std::int64_t{1} << 30))
      throw Error(fmt::format("{}: dim[{}] is {}; expected 1 … 2^30", path, a + 1, n));
    h.dims[a] = static_cast<int>(n);
  }
  h.type = scalarType(*nim, path);
  h.data_bytes = volumeBytes({h.dims[0], h.dims[1], h.dims[2]}, h.type, path);
  h.endian = bytesPerVoxel(h.type) == 1 ? nativeEndian()
             : nim->byteorder == kMsbFirst ? Endian::kBig
                                            : Endian::kLittle;
  if (!nim->iname) throw Error(fmt::format("{}: names no image file", path));
  h.data_file = nim->iname;
  h.encoding = nifti_is_gzfile(nim->iname) ? "gzip" : "raw";
  if (nim->iname_offset < 0)
    throw Error(fmt::format("{}: vox_offset is {}; it must be ≥ 0", path, nim->iname_offset));
  (h.encoding == "raw" ? source.offset : source.skip_decompressed) =
      static_cast<std::uint64_t>(nim->iname_offset);
  readGeometry(*nim, source);
  if (!std::isfinite(nim->scl_slope) || !std::isfinite(nim->scl_inter))
    throw Error(fmt::format("{}: scl_slope {} and scl_inter {} must be finite", path,
                            nim->scl_slope, nim->scl_inter));
  // A slope of 0 means "no scaling" (the NIfTI-1 standard).
  if (nim->scl_slope != 0 && (nim->scl_slope != 1 || nim->scl_inter != 0)) {
    source.scale = ValueScale{nim->scl_slope, nim->scl_inter};
    h.values = fmt::format("stored × {} + {} (scl_slope, scl_inter), as float32", nim->scl_slope,
                           nim->scl_inter);
  }
  const std::string description(nim->descrip, strnlen(nim->descrip, sizeof nim->descrip));
  if (!description.empty()) h.comments.push_back(description);
  return source;
}

}  // namespace svr::detail
