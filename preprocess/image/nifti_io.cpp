// NIfTI input and output through nifti_clib's libnifti2 (see nifti_io.hpp).
//
// Reading goes in three steps so that every failure becomes one clear InputError
// and the library never prints or allocates on a bad file:
//   1. the raw header (nifti_read_header, no validity check) is inspected by us:
//      version, dimensions, voxel count, data type, pixdim;
//   2. nifti_image_read(path, 0) builds the nifti_image without data;
//   3. the data size is checked against the file size (uncompressed files), then
//      the voxels are read here through znzlib. Not nifti_image_load: it silently
//      replaces every NaN/Inf of a float image by 0 (FIXED_FLOAT), which would
//      hide NaN fibre vectors and turn a NaN label into label 0.
// nifti_image::nifti_type is not used for the version: nifti_image_read sets it
// to NIFTI_FTYPE_NIFTI1_1 for a NIfTI-2 .nii too; the raw header knows.
// Writing builds a NIfTI-1 header (the library cannot write NIfTI-2) and writes
// header, extender and data through znzlib ourselves, so that every I/O error
// is seen (nifti_image_write returns void and only prints).
#include "preprocess/image/nifti_io.hpp"

#include <fmt/format.h>
#include <nifti2_io.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.hpp"

namespace adamss::preprocess {
namespace {

namespace fs = std::filesystem;

/// Largest number of voxels (nx*ny*nz) accepted by the readers.
constexpr std::int64_t kMaxVoxels = std::int64_t{1} << 31;
/// NIfTI-1 stores dimensions as int16.
constexpr std::int64_t kMaxNifti1Dim = 32767;
/// Bytes of a NIfTI-1 header plus the 4-byte extender: offset of the voxel data.
constexpr int kNifti1VoxOffset = 352;

enum class Kind { kLabels, kVectors, kScalars };

struct NimDeleter {
  void operator()(nifti_image* nim) const {
    if (nim != nullptr) nifti_image_free(nim);
  }
};
using NimPtr = std::unique_ptr<nifti_image, NimDeleter>;

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }  // NOLINT(cppcoreguidelines-no-malloc)
};

[[noreturn]] void fail_read(const fs::path& path, const std::string& why) {
  throw InputError(fmt::format("cannot read NIfTI file '{}': {}", path.string(), why));
}
[[noreturn]] void fail_write(const fs::path& path, const std::string& why) {
  throw InputError(fmt::format("cannot write NIfTI file '{}': {}", path.string(), why));
}

/// The library prints its own diagnostics to stderr at debug level >= 1 (the
/// default); ours are the ones the user should see.
void quiet_library() {
  nifti_set_debug_level(0);
  nifti_set_allow_upper_fext(1);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string type_name(int datatype) {
  switch (datatype) {
    case NIFTI_TYPE_UINT8:
      return "uint8";
    case NIFTI_TYPE_INT8:
      return "int8";
    case NIFTI_TYPE_INT16:
      return "int16";
    case NIFTI_TYPE_UINT16:
      return "uint16";
    case NIFTI_TYPE_INT32:
      return "int32";
    case NIFTI_TYPE_UINT32:
      return "uint32";
    case NIFTI_TYPE_INT64:
      return "int64";
    case NIFTI_TYPE_UINT64:
      return "uint64";
    case NIFTI_TYPE_FLOAT32:
      return "float32";
    case NIFTI_TYPE_FLOAT64:
      return "float64";
    case NIFTI_TYPE_FLOAT128:
      return "float128";
    case NIFTI_TYPE_COMPLEX64:
      return "complex64";
    case NIFTI_TYPE_COMPLEX128:
      return "complex128";
    case NIFTI_TYPE_COMPLEX256:
      return "complex256";
    case NIFTI_TYPE_RGB24:
      return "rgb24";
    case NIFTI_TYPE_RGBA32:
      return "rgba32";
    case DT_BINARY:
      return "binary (1 bit)";
    default:
      return fmt::format("unknown type code {}", datatype);
  }
}

bool supported_type(int datatype) {
  switch (datatype) {
    case NIFTI_TYPE_UINT8:
    case NIFTI_TYPE_INT8:
    case NIFTI_TYPE_INT16:
    case NIFTI_TYPE_UINT16:
    case NIFTI_TYPE_INT32:
    case NIFTI_TYPE_UINT32:
    case NIFTI_TYPE_INT64:
    case NIFTI_TYPE_UINT64:
    case NIFTI_TYPE_FLOAT32:
    case NIFTI_TYPE_FLOAT64:
      return true;
    default:
      return false;
  }
}

/// The header fields we validate ourselves, from either header version.
struct RawHeader {
  int version = 0;
  std::array<std::int64_t, 8> dim{};
  std::array<double, 8> pixdim{};
  int datatype = 0;
};

std::string dims_text(const RawHeader& h) {
  std::string s = "(";
  for (std::int64_t d = 1; d <= h.dim[0]; ++d) {
    if (d > 1) s += ", ";
    s += std::to_string(h.dim[static_cast<std::size_t>(d)]);
  }
  s += ')';
  return s;
}

/// dim[i] for i > dim[0] counts as 1.
std::int64_t dim_at(const RawHeader& h, int i) {
  return i <= h.dim[0] ? h.dim[static_cast<std::size_t>(i)] : 1;
}

RawHeader read_raw_header(const fs::path& path) {
  const std::string p = path.string();
  {
    // Opening it ourselves first gives the OS reason (permission, ...).
    std::FILE* f = std::fopen(p.c_str(), "rb");
    if (f == nullptr) fail_read(path, std::strerror(errno));
    std::fclose(f);
  }
  // nifti_read_header gives the version, but returns a byte-swapped (big-endian)
  // header unswapped; nifti_read_n1_hdr / nifti_read_n2_hdr swap it.
  int version = -1;
  {
    const std::unique_ptr<void, FreeDeleter> probe(nifti_read_header(p.c_str(), &version, 0));
    if (!probe) {
      fail_read(path,
                "not a NIfTI file (the file is too short for a NIfTI header, or its gzip "
                "stream is corrupt)");
    }
  }
  RawHeader h;
  h.version = version;
  int swapped = 0;
  if (version == 1) {
    const std::unique_ptr<nifti_1_header, FreeDeleter> n1(nifti_read_n1_hdr(p.c_str(), &swapped, 0));
    if (!n1) fail_read(path, "unreadable NIfTI-1 header");
    for (std::size_t i = 0; i < 8; ++i) {
      h.dim[i] = n1->dim[i];
      h.pixdim[i] = n1->pixdim[i];
    }
    h.datatype = n1->datatype;
  } else if (version == 2) {
    const std::unique_ptr<nifti_2_header, FreeDeleter> n2(nifti_read_n2_hdr(p.c_str(), &swapped, 0));
    if (!n2) fail_read(path, "unreadable NIfTI-2 header");
    for (std::size_t i = 0; i < 8; ++i) {
      h.dim[i] = n2->dim[i];
      h.pixdim[i] = n2->pixdim[i];
    }
    h.datatype = n2->datatype;
  } else if (version == 0) {
    fail_read(path,
              "ANALYZE 7.5 header without NIfTI magic; its orientation is ambiguous, "
              "convert it to NIfTI first");
  } else {
    fail_read(path, "not a NIfTI file (the header size field is neither 348 nor 540)");
  }
  return h;
}

/// Dimensions, voxel count and type, before anything is allocated.
void check_raw_header(const fs::path& path, const RawHeader& h, Kind kind) {
  if (h.dim[0] < 1 || h.dim[0] > 7) {
    fail_read(path, fmt::format("invalid number of dimensions dim[0] = {} (must be 1..7)", h.dim[0]));
  }
  for (int i = 1; i <= h.dim[0]; ++i) {
    if (h.dim[static_cast<std::size_t>(i)] <= 0) {
      fail_read(path,
                fmt::format("invalid dimension dim[{}] = {} (must be >= 1)", i, h.dim[static_cast<std::size_t>(i)]));
    }
  }
  if (!supported_type(h.datatype)) {
    fail_read(path, fmt::format("unsupported voxel type {} (code {}); {} images must be stored as "
                                "uint8, int8, int16, uint16, int32, uint32, int64, uint64, "
                                "float32 or float64",
                                type_name(h.datatype), h.datatype,
                                kind == Kind::kLabels ? "label" : (kind == Kind::kScalars ? "scalar" : "vector")));
  }
  // Extra dimensions beyond x, y, z.
  std::array<std::int64_t, 4> extra{};
  for (int i = 4; i <= 7; ++i) extra[static_cast<std::size_t>(i - 4)] = dim_at(h, i);
  if (kind == Kind::kLabels || kind == Kind::kScalars) {
    for (int i = 4; i <= 7; ++i) {
      if (dim_at(h, i) != 1) {
        fail_read(path, fmt::format("a {} image must be 3-D, but the dimensions are {} "
                                    "(dim[{}] = {}; only trailing dimensions of size 1 are "
                                    "accepted)",
                                    kind == Kind::kLabels ? "label" : "scalar", dims_text(h), i, dim_at(h, i)));
      }
    }
  } else {
    const bool nifti_vector = extra == std::array<std::int64_t, 4>{1, 3, 1, 1};  // (nx,ny,nz,1,3)
    const bool volumes = extra == std::array<std::int64_t, 4>{3, 1, 1, 1};       // (nx,ny,nz,3)
    if (!nifti_vector && !volumes) {
      fail_read(path, fmt::format("a vector image must have dimensions (nx, ny, nz, 1, 3) or "
                                  "(nx, ny, nz, 3), but they are {}",
                                  dims_text(h)));
    }
  }
  // Voxel count, overflow-safe: every factor is >= 1 here.
  std::int64_t n = 1;
  for (int i = 1; i <= 3; ++i) {
    const std::int64_t d = dim_at(h, i);
    if (d > kMaxVoxels || n > kMaxVoxels / d) {
      fail_read(path, fmt::format("image too large: {} x {} x {} voxels (limit 2^31)", dim_at(h, 1), dim_at(h, 2),
                                  dim_at(h, 3)));
    }
    n *= d;
  }
}

Eigen::Matrix4d to_eigen(const nifti_dmat44& m) {
  Eigen::Matrix4d a;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) a(r, c) = m.m[r][c];
  }
  return a;
}

void check_pixdim(const fs::path& path, const RawHeader& h, const char* why) {
  for (std::size_t i = 1; i <= 3; ++i) {
    const double d = h.pixdim[i];
    if (!std::isfinite(d) || d <= 0.0) {
      fail_read(path, fmt::format("invalid voxel spacing pixdim[{}] = {} (must be finite and > 0; "
                                  "it is used because {})",
                                  i, d, why));
    }
  }
}

/// Index-to-world affine in metres; fills the geometry fields of the notes.
Eigen::Matrix4d read_affine(const fs::path& path, const nifti_image& nim, const RawHeader& h, NiftiNotes& notes) {
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  if (nim.sform_code > 0) {
    a = to_eigen(nim.sto_xyz);
    notes.affine_source = std::string("sform");
  } else if (nim.qform_code > 0) {
    // The library silently takes |pixdim| and replaces 0 by 1 in the qform.
    check_pixdim(path, h, "the qform scales by it");
    a = to_eigen(nim.qto_xyz);
    notes.affine_source = std::string("qform");
  } else {
    check_pixdim(path, h, "neither sform nor qform is set");
    for (Eigen::Index i = 0; i < 3; ++i) a(i, i) = h.pixdim[static_cast<std::size_t>(i + 1)];
    notes.affine_source = std::string("pixdim");
  }
  a.row(3) << 0.0, 0.0, 0.0, 1.0;
  if (!a.allFinite()) {
    fail_read(path, fmt::format("the {} affine contains NaN or Inf", notes.affine_source));
  }
  const Eigen::Matrix3d lin = a.topLeftCorner<3, 3>();
  const Eigen::Vector3d norms = lin.colwise().norm().transpose();
  const double scale = norms.prod();
  if (!(norms.minCoeff() > 0.0) || !(std::abs(lin.determinant()) > 1e-12 * scale)) {
    fail_read(path, fmt::format("the {} affine is singular (a voxel axis has zero length or the "
                                "axes are coplanar)",
                                notes.affine_source));
  }

  // (std::string temporaries: GCC 12 warns falsely (-Wrestrict) on assigning short literals.)
  double factor = 1e-3;
  switch (nim.xyz_units) {
    case NIFTI_UNITS_METER:
      factor = 1.0;
      notes.units = std::string("m");
      break;
    case NIFTI_UNITS_MM:
      notes.units = std::string("mm");
      break;
    case NIFTI_UNITS_MICRON:
      factor = 1e-6;
      notes.units = std::string("um");
      break;
    case NIFTI_UNITS_UNKNOWN:
      notes.units = std::string("unknown (mm assumed)");
      notes.warnings.push_back(
          fmt::format("'{}': spatial unit not set in the header (xyz_units = 0); millimetres assumed", path.string()));
      break;
    default:
      notes.units = fmt::format("invalid code {} (mm assumed)", nim.xyz_units);
      notes.warnings.push_back(
          fmt::format("'{}': invalid spatial unit code {}; millimetres assumed", path.string(), nim.xyz_units));
      break;
  }
  a.topRows<3>() *= factor;
  return a;
}

/// Reads a gzip stream to its end, so that zlib checks the CRC-32 and length of the trailer
/// (it only does so when a read reaches the end of the stream; the voxels may stop before it). False
/// when zlib reports an error (a CRC or length mismatch, a damaged stream). Bytes after the voxel
/// data are allowed (NIfTI does not forbid them) and ignored.
bool gzip_trailer_ok(znzFile fp) {
  std::array<unsigned char, 1 << 16> scratch{};
  for (;;) {
    const std::size_t got = znzread(scratch.data(), 1, scratch.size(), fp);
    if (got == static_cast<std::size_t>(-1)) return false;
    if (got < scratch.size()) return true;
  }
}

/// Reads the voxel bytes (step 3 of the file comment) and swaps them to native order.
std::unique_ptr<unsigned char[]> read_voxels(const fs::path& path, const nifti_image& nim, std::int64_t nbytes) {
  const auto n = static_cast<std::size_t>(nbytes);
  std::unique_ptr<unsigned char[]> buf;
  try {
    buf.reset(new unsigned char[n]);
  } catch (const std::bad_alloc&) {
    fail_read(path, fmt::format("not enough memory for {} bytes of voxel data", n));
  }
  const bool gz = nifti_is_gzfile(nim.iname) != 0;
  znzFile fp = znzopen(nim.iname, "rb", gz ? 1 : 0);
  if (znz_isnull(fp)) fail_read(path, fmt::format("cannot open the voxel data file '{}'", nim.iname));
  const bool seek_ok = znzseek(fp, static_cast<znz_off_t>(nim.iname_offset), SEEK_SET) >= 0;
  // znzread returns (size_t)-1 when zlib reports a corrupt stream.
  const std::size_t got = seek_ok ? znzread(buf.get(), 1, n, fp) : 0;
  const bool trailer_ok = got != n || !gz || gzip_trailer_ok(fp);
  znzclose(fp);
  if (got != n) {
    fail_read(path, got > n ? std::string("corrupt compressed voxel data")
                            : fmt::format("truncated or corrupt voxel data (read {} of {} bytes)", got, n));
  }
  if (!trailer_ok) {
    fail_read(path,
              "corrupt gzip file: the CRC-32 or the length in the gzip trailer does not match the data "
              "(`gzip -t` reports the same); the voxels read may be wrong");
  }
  if (nim.swapsize > 1 && nim.byteorder != nifti_short_order()) {
    nifti_swap_Nbytes(nbytes / nim.swapsize, nim.swapsize, buf.get());
  }
  return buf;
}

/// Steps 1-3 of the file comment: a loaded image that passed every header check.
struct Loaded {
  NimPtr nim;                             // header only
  std::unique_ptr<unsigned char[]> data;  // nvox * nbyper bytes, native byte order
  Grid grid;
  NiftiNotes notes;
  bool scaled = false;
  double slope = 1.0;
  double inter = 0.0;
};

Loaded load(const fs::path& path, Kind kind) {
  quiet_library();
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail_read(path, "no such file");
  if (fs::is_directory(st)) fail_read(path, "is a directory");
  const std::string name = lower(path.filename().string());
  if (!ends_with(name, ".nii") && !ends_with(name, ".nii.gz") && !ends_with(name, ".hdr") &&
      !ends_with(name, ".hdr.gz") && !ends_with(name, ".img") && !ends_with(name, ".img.gz")) {
    fail_read(path, "unsupported file name extension (expected .nii or .nii.gz)");
  }

  const RawHeader raw = read_raw_header(path);
  check_raw_header(path, raw, kind);

  Loaded out;
  out.nim.reset(nifti_image_read(path.string().c_str(), 0));
  if (!out.nim) fail_read(path, fmt::format("invalid NIfTI-{} header", raw.version));
  nifti_image& nim = *out.nim;
  if (nim.datatype != raw.datatype || nim.nbyper <= 0) {
    fail_read(path, fmt::format("inconsistent header (data type {})", type_name(nim.datatype)));
  }
  if (nim.nifti_type == NIFTI_FTYPE_ASCII || nim.nifti_type == NIFTI_FTYPE_ANALYZE) {
    fail_read(path, fmt::format("unsupported NIfTI file type {}", nim.nifti_type));
  }
  out.notes.nifti_version = raw.version;
  out.notes.datatype = type_name(nim.datatype);

  // Short data in an uncompressed file: say exactly how short.
  const std::int64_t data_bytes = nim.nvox * nim.nbyper;
  if (nim.iname == nullptr || nim.iname_offset < 0) fail_read(path, "no voxel data offset");
  if (nifti_is_gzfile(nim.iname) == 0) {
    const auto size = fs::file_size(fs::path(nim.iname), ec);
    if (!ec && static_cast<std::int64_t>(size) < nim.iname_offset + data_bytes) {
      fail_read(path, fmt::format("truncated file: {} bytes long, but the header promises {} "
                                  "bytes of voxel data from offset {} ({} bytes in all)",
                                  size, data_bytes, nim.iname_offset, nim.iname_offset + data_bytes));
    }
  }

  out.grid.dims = {nim.nx, nim.ny, nim.nz};
  out.grid.index_to_world = read_affine(path, nim, raw, out.notes);

  out.data = read_voxels(path, nim, data_bytes);

  // scl_slope = 0 means "no scaling" (the library already maps NaN/Inf to 0).
  if (nim.scl_slope != 0.0 && std::isfinite(nim.scl_slope) && std::isfinite(nim.scl_inter) &&
      !(nim.scl_slope == 1.0 && nim.scl_inter == 0.0)) {
    out.scaled = true;
    out.slope = nim.scl_slope;
    out.inter = nim.scl_inter;
    out.notes.warnings.push_back(
        fmt::format("'{}': values scaled by scl_slope = {} and scl_inter = {}", path.string(), out.slope, out.inter));
  }
  return out;
}

std::string voxel_text(const Grid& g, std::size_t v) {
  const auto nx = static_cast<std::size_t>(g.dims[0]);
  const auto ny = static_cast<std::size_t>(g.dims[1]);
  return fmt::format("({}, {}, {})", v % nx, (v / nx) % ny, v / (nx * ny));
}

/// True for integer types whose every value is an int32.
template <typename T>
constexpr bool fits_int32() {
  if constexpr (std::is_integral_v<T>) {
    return std::in_range<std::int32_t>(std::numeric_limits<T>::min()) &&
           std::in_range<std::int32_t>(std::numeric_limits<T>::max());
  } else {
    return false;
  }
}

template <typename T>
void convert_labels(const fs::path& path, const Loaded& in, std::vector<std::int32_t>& labels) {
  const unsigned char* bytes = in.data.get();
  const std::size_t n = labels.size();
  constexpr double kLo = std::numeric_limits<std::int32_t>::min();
  constexpr double kHi = std::numeric_limits<std::int32_t>::max();
  for (std::size_t v = 0; v < n; ++v) {
    T raw;
    std::memcpy(&raw, bytes + v * sizeof(T), sizeof(T));
    if constexpr (fits_int32<T>()) {
      if (!in.scaled) {
        labels[v] = static_cast<std::int32_t>(raw);  // NOLINT(bugprone-signed-char-misuse): DT_INT8 is signed
        continue;
      }
    }
    double x = static_cast<double>(raw);
    if (in.scaled) x = x * in.slope + in.inter;
    if (!std::isfinite(x) || x != std::trunc(x)) {
      fail_read(path, fmt::format("voxel {} holds {}{}, which is not an integral label ({} label "
                                  "images must hold whole numbers)",
                                  voxel_text(in.grid, v), x, in.scaled ? " after scl_slope/scl_inter scaling" : "",
                                  in.notes.datatype));
    }
    if (x < kLo || x > kHi) {
      fail_read(path, fmt::format("voxel {} holds {}{}, outside the int32 label range", voxel_text(in.grid, v), x,
                                  in.scaled ? " after scl_slope/scl_inter scaling" : ""));
    }
    labels[v] = static_cast<std::int32_t>(x);
  }
}

template <typename T>
void convert_vectors(const Loaded& in, Eigen::Matrix3Xf& vectors) {
  const unsigned char* bytes = in.data.get();
  const Eigen::Index n = vectors.cols();
  // Planar storage: all x components, then all y, then all z.
  for (Eigen::Index c = 0; c < 3; ++c) {
    const unsigned char* plane = bytes + static_cast<std::size_t>(c * n) * sizeof(T);
    for (Eigen::Index v = 0; v < n; ++v) {
      T raw;
      std::memcpy(&raw, plane + static_cast<std::size_t>(v) * sizeof(T), sizeof(T));
      double x = static_cast<double>(raw);
      if (in.scaled) x = x * in.slope + in.inter;
      vectors(c, v) = static_cast<float>(x);
    }
  }
}

template <typename T>
void convert_scalars(const Loaded& in, std::vector<double>& values) {
  const unsigned char* bytes = in.data.get();
  for (std::size_t v = 0; v < values.size(); ++v) {
    T raw;
    std::memcpy(&raw, bytes + v * sizeof(T), sizeof(T));
    double x = static_cast<double>(raw);
    if (in.scaled) x = x * in.slope + in.inter;
    values[v] = x;
  }
}

/// Calls f.template operator()<T>() for the C++ type of a supported NIfTI type.
template <typename F>
void dispatch(int datatype, F&& f) {
  switch (datatype) {
    case NIFTI_TYPE_UINT8:
      f(std::uint8_t{});
      break;
    case NIFTI_TYPE_INT8:
      f(std::int8_t{});
      break;
    case NIFTI_TYPE_INT16:
      f(std::int16_t{});
      break;
    case NIFTI_TYPE_UINT16:
      f(std::uint16_t{});
      break;
    case NIFTI_TYPE_INT32:
      f(std::int32_t{});
      break;
    case NIFTI_TYPE_UINT32:
      f(std::uint32_t{});
      break;
    case NIFTI_TYPE_INT64:
      f(std::int64_t{});
      break;
    case NIFTI_TYPE_UINT64:
      f(std::uint64_t{});
      break;
    case NIFTI_TYPE_FLOAT32:
      f(float{});
      break;
    case NIFTI_TYPE_FLOAT64:
      f(double{});
      break;
    default:
      break;  // rejected in check_raw_header
  }
}

// ---------------------------------------------------------------------------
// Writing

struct ZnzCloser {
  void operator()(znzptr* f) const {
    if (f != nullptr) {
      znzFile tmp = f;
      Xznzclose(&tmp);
    }
  }
};

bool is_gz_name(const fs::path& path) {
  const std::string name = lower(path.filename().string());
  if (ends_with(name, ".nii.gz")) return true;
  if (ends_with(name, ".nii")) return false;
  fail_write(path, "the file name must end in .nii or .nii.gz");
}

void write_nifti1(const fs::path& path, const Grid& grid, const std::array<std::int64_t, 8>& dims, int datatype,
                  int intent, const void* data, std::size_t nbytes) {
  quiet_library();
  const bool gz = is_gz_name(path);
  for (int i = 1; i <= dims[0]; ++i) {
    const std::int64_t d = dims[static_cast<std::size_t>(i)];
    if (d < 1 || d > kMaxNifti1Dim) {
      fail_write(path, fmt::format("dimension {} = {} is outside the NIfTI-1 range 1..{}", i, d, kMaxNifti1Dim));
    }
  }
  const Eigen::Matrix4d& si = grid.index_to_world;
  if (!si.allFinite()) fail_write(path, "the affine contains NaN or Inf");
  const Eigen::Matrix3d lin = si.topLeftCorner<3, 3>();
  const Eigen::Vector3d norms = lin.colwise().norm().transpose();
  if (!(norms.minCoeff() > 0.0) || !(std::abs(lin.determinant()) > 1e-12 * norms.prod())) {
    fail_write(path, "the affine is singular");
  }

  // Millimetres on disk.
  nifti_dmat44 r{};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) r.m[i][j] = (i < 3 ? 1000.0 : 1.0) * si(i, j);
  }
  r.m[3][0] = r.m[3][1] = r.m[3][2] = 0.0;
  r.m[3][3] = 1.0;

  const std::unique_ptr<nifti_1_header, FreeDeleter> hdr(nifti_make_new_n1_header(dims.data(), datatype));
  if (!hdr) fail_write(path, "could not create a NIfTI-1 header");
  nifti_1_header& h = *hdr;
  h.vox_offset = static_cast<float>(kNifti1VoxOffset);
  h.intent_code = static_cast<short>(intent);
  h.scl_slope = 1.0f;
  h.scl_inter = 0.0f;
  h.xyzt_units = static_cast<char>(SPACE_TIME_TO_XYZT(NIFTI_UNITS_MM, 0));
  std::snprintf(h.descrip, sizeof(h.descrip), "adamss");
  for (int i = 1; i <= 3; ++i) h.pixdim[i] = static_cast<float>(1000.0 * norms(i - 1));

  // sform: the affine as is.
  h.sform_code = NIFTI_XFORM_SCANNER_ANAT;
  for (int j = 0; j < 4; ++j) {
    h.srow_x[j] = static_cast<float>(r.m[0][j]);
    h.srow_y[j] = static_cast<float>(r.m[1][j]);
    h.srow_z[j] = static_cast<float>(r.m[2][j]);
  }
  // qform: only when the affine is rotation x positive scaling (x optional flip of k).
  double qb = 0, qc = 0, qd = 0, qx = 0, qy = 0, qz = 0, dx = 0, dy = 0, dz = 0, qfac = 1;
  nifti_dmat44_to_quatern(r, &qb, &qc, &qd, &qx, &qy, &qz, &dx, &dy, &dz, &qfac);
  const nifti_dmat44 back = nifti_quatern_to_dmat44(qb, qc, qd, qx, qy, qz, dx, dy, dz, qfac);
  double err = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) err = std::max(err, std::abs(back.m[i][j] - r.m[i][j]));
  }
  const bool rigid = err <= 1e-6 * 1000.0 * norms.maxCoeff();
  h.pixdim[0] = 1.0f;
  if (rigid) {
    h.qform_code = NIFTI_XFORM_SCANNER_ANAT;
    h.quatern_b = static_cast<float>(qb);
    h.quatern_c = static_cast<float>(qc);
    h.quatern_d = static_cast<float>(qd);
    h.qoffset_x = static_cast<float>(qx);
    h.qoffset_y = static_cast<float>(qy);
    h.qoffset_z = static_cast<float>(qz);
    h.pixdim[0] = qfac < 0 ? -1.0f : 1.0f;
  } else {
    h.qform_code = NIFTI_XFORM_UNKNOWN;
    h.quatern_b = h.quatern_c = h.quatern_d = 0.0f;
    h.qoffset_x = h.qoffset_y = h.qoffset_z = 0.0f;
  }

  const std::string p = path.string();
  errno = 0;
  std::unique_ptr<znzptr, ZnzCloser> fp(znzopen(p.c_str(), "wb", gz ? 1 : 0));
  if (!fp) fail_write(path, errno != 0 ? std::strerror(errno) : "cannot open for writing");
  const char extender[4] = {0, 0, 0, 0};
  bool ok = znzwrite(&h, 1, sizeof(h), fp.get()) == sizeof(h) &&
            znzwrite(extender, 1, sizeof(extender), fp.get()) == sizeof(extender) &&
            znzwrite(data, 1, nbytes, fp.get()) == nbytes;
  znzFile raw = fp.release();
  ok = (Xznzclose(&raw) == 0) && ok;
  if (!ok) {
    std::error_code ec;
    fs::remove(path, ec);
    fail_write(path, "write error (disk full?)");
  }
}

}  // namespace

LabelImage read_label_image(const std::filesystem::path& path, NiftiNotes* notes, LabelScaling scaling) {
  Loaded in = load(path, Kind::kLabels);
  if (in.scaled && scaling == LabelScaling::kRefuse) {
    fail_read(path, fmt::format("the header scales the stored values (scl_slope = {}, scl_inter = {}), which would "
                                "change every label (0 would become {}); reset scl_slope to 0 or 1 and scl_inter to "
                                "0, or ask for the scaling (adamss mesh --allow-scaled-labels)",
                                in.slope, in.inter, in.inter));
  }
  LabelImage image;
  image.grid = in.grid;
  image.labels.resize(in.grid.voxel_count());
  dispatch(in.nim->datatype, [&](auto tag) { convert_labels<decltype(tag)>(path, in, image.labels); });
  if (notes != nullptr) *notes = std::move(in.notes);
  return image;
}

VectorImage read_vector_image(const std::filesystem::path& path, NiftiNotes* notes) {
  Loaded in = load(path, Kind::kVectors);
  VectorImage image;
  image.grid = in.grid;
  image.vectors.resize(3, static_cast<Eigen::Index>(in.grid.voxel_count()));
  dispatch(in.nim->datatype, [&](auto tag) { convert_vectors<decltype(tag)>(in, image.vectors); });
  if (notes != nullptr) *notes = std::move(in.notes);
  return image;
}

ScalarImage read_scalar_image(const std::filesystem::path& path, NiftiNotes* notes) {
  Loaded in = load(path, Kind::kScalars);
  ScalarImage image;
  image.grid = in.grid;
  image.values.resize(in.grid.voxel_count());
  dispatch(in.nim->datatype, [&](auto tag) { convert_scalars<decltype(tag)>(in, image.values); });
  if (notes != nullptr) *notes = std::move(in.notes);
  return image;
}

void write_scalar_image(const std::filesystem::path& path, const ScalarImage& image) {
  const Grid& g = image.grid;
  if (g.dims[0] < 1 || g.dims[1] < 1 || g.dims[2] < 1) {
    fail_write(path, fmt::format("invalid dimensions {} x {} x {}", g.dims[0], g.dims[1], g.dims[2]));
  }
  if (image.values.size() != g.voxel_count()) {
    fail_write(path, fmt::format("{} values for {} voxels", image.values.size(), g.voxel_count()));
  }
  const std::array<std::int64_t, 8> dims{3, g.dims[0], g.dims[1], g.dims[2], 1, 1, 1, 1};
  const std::vector<float> buf(image.values.begin(), image.values.end());
  write_nifti1(path, g, dims, NIFTI_TYPE_FLOAT32, NIFTI_INTENT_NONE, buf.data(), buf.size() * sizeof(float));
}

void write_label_image(const std::filesystem::path& path, const LabelImage& image) {
  const Grid& g = image.grid;
  if (g.dims[0] < 1 || g.dims[1] < 1 || g.dims[2] < 1) {
    fail_write(path, fmt::format("invalid dimensions {} x {} x {}", g.dims[0], g.dims[1], g.dims[2]));
  }
  if (image.labels.size() != g.voxel_count()) {
    fail_write(path, fmt::format("{} labels for {} voxels", image.labels.size(), g.voxel_count()));
  }
  const std::array<std::int64_t, 8> dims{3, g.dims[0], g.dims[1], g.dims[2], 1, 1, 1, 1};
  std::int32_t lo = 0;
  std::int32_t hi = 0;
  if (!image.labels.empty()) {
    const auto [mn, mx] = std::minmax_element(image.labels.begin(), image.labels.end());
    lo = *mn;
    hi = *mx;
  }
  if (lo >= 0 && hi <= 255) {
    const std::vector<std::uint8_t> buf(image.labels.begin(), image.labels.end());
    write_nifti1(path, g, dims, NIFTI_TYPE_UINT8, NIFTI_INTENT_LABEL, buf.data(), buf.size());
  } else if (lo >= std::numeric_limits<std::int16_t>::min() && hi <= std::numeric_limits<std::int16_t>::max()) {
    const std::vector<std::int16_t> buf(image.labels.begin(), image.labels.end());
    write_nifti1(path, g, dims, NIFTI_TYPE_INT16, NIFTI_INTENT_LABEL, buf.data(), buf.size() * sizeof(std::int16_t));
  } else {
    write_nifti1(path, g, dims, NIFTI_TYPE_INT32, NIFTI_INTENT_LABEL, image.labels.data(),
                 image.labels.size() * sizeof(std::int32_t));
  }
}

void write_vector_image(const std::filesystem::path& path, const VectorImage& image) {
  const Grid& g = image.grid;
  if (g.dims[0] < 1 || g.dims[1] < 1 || g.dims[2] < 1) {
    fail_write(path, fmt::format("invalid dimensions {} x {} x {}", g.dims[0], g.dims[1], g.dims[2]));
  }
  if (static_cast<std::size_t>(image.vectors.cols()) != g.voxel_count()) {
    fail_write(path, fmt::format("{} vectors for {} voxels", image.vectors.cols(), g.voxel_count()));
  }
  const std::array<std::int64_t, 8> dims{5, g.dims[0], g.dims[1], g.dims[2], 1, 3, 1, 1};
  // Planar: all x components, then all y, then all z (the transpose of the column layout).
  const std::size_t n = g.voxel_count();
  std::vector<float> buf(3 * n);
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t v = 0; v < n; ++v) {
      buf[c * n + v] = image.vectors(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(v));
    }
  }
  write_nifti1(path, g, dims, NIFTI_TYPE_FLOAT32, NIFTI_INTENT_VECTOR, buf.data(), buf.size() * sizeof(float));
}

}  // namespace adamss::preprocess
