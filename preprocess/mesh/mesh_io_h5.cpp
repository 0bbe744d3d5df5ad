// mesh.h5 reader and writer (layout in mesh_io.hpp), plain HDF5 C API.
//
// Works with the serial and the parallel (OpenMPI) HDF5 build alike: the default file-access
// property list selects the POSIX (sec2) driver, so no MPI initialisation is needed.
// Every HDF5 handle lives in an RAII wrapper, HDF5's automatic error printing is switched off
// while we work, and every failure surfaces as adamss::InputError naming the file and the
// dataset or attribute.
#include <hdf5.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "common/durable.hpp"
#include "common/error.hpp"
#include "common/guarded_read.hpp"
#include "preprocess/mesh/hdf5_handle.hpp"
#include "preprocess/mesh/mesh_io.hpp"

namespace adamss::preprocess {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormatName = "adamss-mesh";

static_assert(sizeof(std::array<Index, 3>) == 3 * sizeof(Index), "cavity faces must be contiguous");
static_assert(sizeof(std::array<Index, 4>) == 4 * sizeof(Index), "cavity quads must be contiguous");
static_assert(sizeof(Index) == 4, "Index is stored as int32");

// ---------------------------------------------------------------------------------------------
// HDF5 plumbing

/// Error context: the file name that prefixes every message.
struct Ctx {
  std::string file;
  [[noreturn]] void fail(const std::string& what) const { throw InputError(file + ": " + what); }
};

std::string dims_string(const std::vector<hsize_t>& dims) {
  if (dims.empty()) return "scalar";
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i > 0) s += " x ";
    s += std::to_string(dims[i]);
  }
  return s;
}

/// Whether every component of an absolute path like "/a/b/c" exists as a link.
bool path_exists(hid_t loc, const std::string& path) {
  std::size_t pos = 0;
  while (true) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (H5Lexists(loc, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

std::vector<std::string> link_names(const Ctx& ctx, hid_t group, const std::string& where) {
  H5G_info_t info{};
  if (H5Gget_info(group, &info) < 0) ctx.fail("group " + where + ": cannot list members");
  std::vector<std::string> names;
  names.reserve(info.nlinks);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len = H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) ctx.fail("group " + where + ": cannot read member name");
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    if (H5Lget_name_by_idx(group, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(), H5P_DEFAULT) < 0)
      ctx.fail("group " + where + ": cannot read member name");
    name.resize(static_cast<std::size_t>(len));
    names.push_back(std::move(name));
  }
  return names;
}

herr_t collect_attribute_name(hid_t /*loc*/, const char* name, const H5A_info_t* /*info*/, void* op_data) noexcept {
  try {
    static_cast<std::vector<std::string>*>(op_data)->emplace_back(name);
    return 0;
  } catch (...) {
    return -1;
  }
}

std::vector<std::string> attribute_names(const Ctx& ctx, hid_t obj, const std::string& where) {
  std::vector<std::string> names;
  hsize_t idx = 0;
  if (H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_attribute_name, &names) < 0)
    ctx.fail(where + ": cannot list attributes");
  return names;
}

// ---------------------------------------------------------------------------------------------
// Writing

Hdf5Handle make_space(std::initializer_list<hsize_t> dims) {
  if (dims.size() == 0) return Hdf5Handle(H5Screate(H5S_SCALAR), H5Sclose);
  return Hdf5Handle(H5Screate_simple(static_cast<int>(dims.size()), std::data(dims), nullptr), H5Sclose);
}

Hdf5Handle create_group(const Ctx& ctx, hid_t loc, const std::string& name, const std::string& full) {
  Hdf5Handle g(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) ctx.fail("group " + full + ": cannot create");
  return g;
}

void write_dataset(const Ctx& ctx, hid_t loc, const std::string& name, const std::string& full, hid_t file_type,
                   hid_t mem_type, std::initializer_list<hsize_t> dims, const void* data) {
  const Hdf5Handle space = make_space(dims);
  if (!space.valid())
    ctx.fail("dataset " + full + ": cannot create dataspace " + dims_string(std::vector<hsize_t>(dims)));
  const Hdf5Handle ds(H5Dcreate2(loc, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                      H5Dclose);
  if (!ds.valid()) ctx.fail("dataset " + full + ": cannot create");
  hsize_t count = 1;
  for (const hsize_t d : dims) count *= d;
  if (count > 0 && H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    ctx.fail("dataset " + full + ": cannot write (out of memory?)");
}

void write_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& where, hid_t file_type,
                     hid_t mem_type, const void* data) {
  const Hdf5Handle space = make_space({});
  const Hdf5Handle attr(H5Acreate2(obj, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) ctx.fail("attribute " + where + name + ": cannot create");
  if (H5Awrite(attr.get(), mem_type, data) < 0) ctx.fail("attribute " + where + name + ": cannot write");
}

void write_string_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& where,
                            const std::string& value) {
  if (value.find('\0') != std::string::npos) ctx.fail("attribute " + where + name + ": value contains a NUL character");
  // Fixed-length (NUL-padded) UTF-8: no variable-length data, so the file has no global heap.
  // (Fuzzing found that libhdf5 1.10 can loop forever reading a variable-length attribute whose
  // global-heap entry is corrupted; files we write never take that path. fuzz/README.md.)
  const Hdf5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!type.valid() || H5Tset_size(type.get(), std::max<std::size_t>(value.size(), 1)) < 0 ||
      H5Tset_strpad(type.get(), H5T_STR_NULLPAD) < 0 || H5Tset_cset(type.get(), H5T_CSET_UTF8) < 0)
    ctx.fail("attribute " + where + name + ": cannot create string type");
  std::string padded = value;
  if (padded.empty()) padded.push_back('\0');
  write_attribute(ctx, obj, name, where, type.get(), type.get(), padded.data());
}

void write_int_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& where, int value) {
  write_attribute(ctx, obj, name, where, H5T_STD_I32LE, H5T_NATIVE_INT, &value);
}

void write_double_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& where,
                            double value) {
  write_attribute(ctx, obj, name, where, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

/// A name that becomes one HDF5 link (no path separators, not "." or empty).
void check_link_name(const Ctx& ctx, const std::string& name, const std::string& what) {
  if (name.empty() || name == "." || name.find('/') != std::string::npos || name.find('\0') != std::string::npos)
    ctx.fail(what + " name '" + name + "' is not usable as an HDF5 name (empty, '.', or contains '/')");
}

// ---------------------------------------------------------------------------------------------
// Content checks shared by reader and writer

void check_nodes_finite(const Ctx& ctx, const Eigen::Matrix3Xd& nodes) {
  const double* p = nodes.data();
  const auto n = static_cast<std::size_t>(nodes.cols());
  for (std::size_t i = 0; i < 3 * n; ++i) {
    if (!std::isfinite(p[i])) {
      const std::size_t node = i / 3;
      std::ostringstream msg;
      msg << "dataset /nodes: node " << node << " has a non-finite coordinate (" << p[3 * node] << ", "
          << p[3 * node + 1] << ", " << p[3 * node + 2] << ")";
      ctx.fail(msg.str());
    }
  }
}

void check_connectivity(const Ctx& ctx, const std::vector<Index>& conn, int k, std::size_t node_count) {
  const auto n = static_cast<std::int64_t>(node_count);
  for (std::size_t i = 0; i < conn.size(); ++i) {
    if (conn[i] < 0 || conn[i] >= n) {
      ctx.fail("dataset /elements/connectivity: element " + std::to_string(i / static_cast<std::size_t>(k)) +
               " references node " + std::to_string(conn[i]) + " but the mesh has " + std::to_string(node_count) +
               " nodes");
    }
  }
}

void check_indices(const Ctx& ctx, const Index* idx, std::size_t count, std::size_t node_count,
                   const std::string& dataset, std::size_t per_row, const char* row_word) {
  const auto n = static_cast<std::int64_t>(node_count);
  for (std::size_t i = 0; i < count; ++i) {
    if (idx[i] < 0 || idx[i] >= n) {
      std::string where = "entry " + std::to_string(i);
      if (per_row > 1) where = std::string(row_word) + " " + std::to_string(i / per_row);
      ctx.fail("dataset " + dataset + ": " + where + " references node " + std::to_string(idx[i]) +
               " but the mesh has " + std::to_string(node_count) + " nodes");
    }
  }
}

bool is_reserved_root_attribute(const std::string& name) {
  return name == "format" || name == "version" || name == "voxel_size_m";
}

void check_mesh_for_writing(const Ctx& ctx, const Mesh& mesh) {
  const int k = nodes_per_element(mesh.type);
  if (mesh.connectivity.size() % static_cast<std::size_t>(k) != 0) {
    ctx.fail("connectivity has " + std::to_string(mesh.connectivity.size()) + " entries, not a multiple of " +
             std::to_string(k) + " (" + element_type_name(mesh.type) + ")");
  }
  const std::size_t E = mesh.element_count();
  const std::size_t N = mesh.node_count();
  if (mesh.labels.size() != E) {
    ctx.fail("dataset /elements/label: " + std::to_string(mesh.labels.size()) + " labels for " + std::to_string(E) +
             " elements");
  }
  if (mesh.has_fibres() || mesh.sheet.cols() > 0 || mesh.normal.cols() > 0) {
    const std::pair<const char*, const Eigen::Matrix3Xd*> fields[] = {
        {"fiber", &mesh.fiber}, {"sheet", &mesh.sheet}, {"normal", &mesh.normal}};
    for (const auto& [name, m] : fields) {
      if (static_cast<std::size_t>(m->cols()) != E) {
        ctx.fail(std::string("dataset /elements/") + name + ": " + std::to_string(m->cols()) + " vectors for " +
                 std::to_string(E) + " elements");
      }
    }
  }
  for (const auto& [name, values] : mesh.cell_scalars) {
    check_link_name(ctx, name, "cell scalar");
    if (static_cast<std::size_t>(values.size()) != E) {
      ctx.fail("dataset /elements/scalars/" + name + ": " + std::to_string(values.size()) + " values for " +
               std::to_string(E) + " elements");
    }
  }
  check_nodes_finite(ctx, mesh.nodes);
  check_connectivity(ctx, mesh.connectivity, k, N);
  for (const auto& [name, tag] : mesh.node_tags) {
    check_link_name(ctx, name, "node tag");
    check_indices(ctx, tag.data(), tag.size(), N, "/node_tags/" + name, 1, "");
  }
  for (const auto& [name, cavity] : mesh.cavities) {
    check_link_name(ctx, name, "cavity");
    check_indices(ctx, reinterpret_cast<const Index*>(cavity.faces.data()), 3 * cavity.faces.size(), N,
                  "/cavities/" + name + "/faces", 3, "face");
    check_indices(ctx, reinterpret_cast<const Index*>(cavity.quads.data()), 4 * cavity.quads.size(), N,
                  "/cavities/" + name + "/quads", 4, "quad");
    check_indices(ctx, reinterpret_cast<const Index*>(cavity.lid.data()), 3 * cavity.lid.size(), N,
                  "/cavities/" + name + "/lid", 3, "face");
  }
  for (const auto& [name, value] : mesh.attributes) {
    if (name.empty() || name.find('\0') != std::string::npos)
      ctx.fail("attribute '" + name + "': not a usable attribute name");
    if (is_reserved_root_attribute(name)) {
      ctx.fail("attribute " + name +
               ": the name is reserved for the file format (format, version, voxel_size_m); "
               "rename the Mesh::attributes entry");
    }
  }
}

void write_contents(const Ctx& ctx, hid_t file, const Mesh& mesh) {
  const auto N = static_cast<hsize_t>(mesh.node_count());
  const auto E = static_cast<hsize_t>(mesh.element_count());
  const auto k = static_cast<hsize_t>(nodes_per_element(mesh.type));

  // Root attributes.
  {
    const std::string fmt = kFormatName;
    write_string_attribute(ctx, file, "format", "/", fmt);
    write_int_attribute(ctx, file, "version", "/", kMeshFormatVersion);
    write_double_attribute(ctx, file, "voxel_size_m", "/", mesh.voxel_size_m);
    for (const auto& [name, value] : mesh.attributes) write_string_attribute(ctx, file, name, "/", value);
  }

  // Nodes: Matrix3Xd is column-major, i.e. exactly an N x 3 row-major block.
  write_dataset(ctx, file, "nodes", "/nodes", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {N, 3}, mesh.nodes.data());

  // Elements.
  {
    const Hdf5Handle elements = create_group(ctx, file, "elements", "/elements");
    write_string_attribute(ctx, elements.get(), "type", "/elements/", element_type_name(mesh.type));
    write_dataset(ctx, elements.get(), "connectivity", "/elements/connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32,
                  {E, k}, mesh.connectivity.data());
    write_dataset(ctx, elements.get(), "label", "/elements/label", H5T_STD_I32LE, H5T_NATIVE_INT32, {E},
                  mesh.labels.data());
    if (mesh.has_fibres()) {
      write_dataset(ctx, elements.get(), "fiber", "/elements/fiber", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {E, 3},
                    mesh.fiber.data());
      write_dataset(ctx, elements.get(), "sheet", "/elements/sheet", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {E, 3},
                    mesh.sheet.data());
      write_dataset(ctx, elements.get(), "normal", "/elements/normal", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {E, 3},
                    mesh.normal.data());
    }
    const Hdf5Handle scalars = create_group(ctx, elements.get(), "scalars", "/elements/scalars");
    for (const auto& [name, values] : mesh.cell_scalars) {
      write_dataset(ctx, scalars.get(), name, "/elements/scalars/" + name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, {E},
                    values.data());
    }
  }

  // Node tags.
  {
    const Hdf5Handle tags = create_group(ctx, file, "node_tags", "/node_tags");
    for (const auto& [name, tag] : mesh.node_tags) {
      write_dataset(ctx, tags.get(), name, "/node_tags/" + name, H5T_STD_I32LE, H5T_NATIVE_INT32, {tag.size()},
                    tag.data());
    }
  }

  // Cavities.
  {
    const Hdf5Handle cavities = create_group(ctx, file, "cavities", "/cavities");
    for (const auto& [name, cavity] : mesh.cavities) {
      const std::string where = "/cavities/" + name;
      const Hdf5Handle g = create_group(ctx, cavities.get(), name, where);
      write_dataset(ctx, g.get(), "faces", where + "/faces", H5T_STD_I32LE, H5T_NATIVE_INT32, {cavity.faces.size(), 3},
                    cavity.faces.data());
      if (!cavity.quads.empty()) {  // hexahedral walls only: tetrahedral files stay as they were
        write_dataset(ctx, g.get(), "quads", where + "/quads", H5T_STD_I32LE, H5T_NATIVE_INT32,
                      {cavity.quads.size(), 4}, cavity.quads.data());
      }
      write_dataset(ctx, g.get(), "lid", where + "/lid", H5T_STD_I32LE, H5T_NATIVE_INT32, {cavity.lid.size(), 3},
                    cavity.lid.data());
      write_double_attribute(ctx, g.get(), "volume_m3", where + "/", cavity.volume_m3);
      write_int_attribute(ctx, g.get(), "closed", where + "/", cavity.closed ? 1 : 0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Reading

struct DatasetInfo {
  Hdf5Handle dataset;
  Hdf5Handle type;
  H5T_class_t type_class = H5T_NO_CLASS;
  std::size_t type_size = 0;
  bool is_signed = true;
  std::vector<hsize_t> dims;

  [[nodiscard]] std::string type_string() const {
    switch (type_class) {
      case H5T_INTEGER:
        return std::string(is_signed ? "int" : "uint") + std::to_string(8 * type_size);
      case H5T_FLOAT:
        return "float" + std::to_string(8 * type_size);
      case H5T_STRING:
        return "string";
      case H5T_COMPOUND:
        return "compound";
      default:
        return "non-numeric";
    }
  }
  [[nodiscard]] std::string found() const {
    return "found rank " + std::to_string(dims.size()) + " (" + dims_string(dims) + ") " + type_string();
  }
};

DatasetInfo open_dataset(const Ctx& ctx, hid_t file, const std::string& path) {
  if (!path_exists(file, path)) ctx.fail("dataset " + path + ": missing");
  DatasetInfo info;
  info.dataset = Hdf5Handle(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!info.dataset.valid()) ctx.fail("dataset " + path + ": cannot open (not a dataset?)");
  info.type = Hdf5Handle(H5Dget_type(info.dataset.get()), H5Tclose);
  const Hdf5Handle space(H5Dget_space(info.dataset.get()), H5Sclose);
  if (!info.type.valid() || !space.valid()) ctx.fail("dataset " + path + ": cannot query type and shape");
  info.type_class = H5Tget_class(info.type.get());
  info.type_size = H5Tget_size(info.type.get());
  if (info.type_class == H5T_INTEGER) info.is_signed = H5Tget_sign(info.type.get()) != H5T_SGN_NONE;
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) ctx.fail("dataset " + path + ": cannot query shape");
  info.dims.resize(static_cast<std::size_t>(rank));
  if (rank > 0 && H5Sget_simple_extent_dims(space.get(), info.dims.data(), nullptr) < 0)
    ctx.fail("dataset " + path + ": cannot query shape");
  // A corrupted or hostile file can claim any shape, and the readers below allocate the claimed
  // size before reading (a fuzzed mesh.h5 of 10 kB claimed enough to throw std::bad_alloc). The
  // values must come from the file, and deflate, the only filter in practice, compresses at most
  // ~1032:1, so a dataset claiming more than that (8 bytes per value in memory) is refused first.
  double values = 1.0;
  for (const hsize_t d : info.dims) values *= static_cast<double>(d);
  hsize_t file_size = 0;
  const Hdf5Handle file_id(H5Iget_file_id(info.dataset.get()), H5Fclose);
  if (!file_id.valid() || H5Fget_filesize(file_id.get(), &file_size) < 0) ctx.fail("cannot query the file size");
  if (values * 8.0 > 1100.0 * static_cast<double>(file_size) + 1048576.0) {
    ctx.fail("dataset " + path + ": claims " + dims_string(info.dims) + " values, more than a file of " +
             std::to_string(file_size) + " bytes can hold (corrupted?)");
  }
  return info;
}

/// Checks rank and shape: `cols` == 0 means a 1-D dataset of `rows` entries; rows < 0 = any.
void check_shape(const Ctx& ctx, const DatasetInfo& info, const std::string& path, std::int64_t rows, hsize_t cols,
                 H5T_class_t cls, const std::string& expected_desc) {
  const std::size_t rank = cols == 0 ? 1 : 2;
  bool ok = info.type_class == cls && info.dims.size() == rank;
  if (ok && rows >= 0) ok = info.dims[0] == static_cast<hsize_t>(rows);
  if (ok && cols > 0) ok = info.dims[1] == cols;
  if (!ok) ctx.fail("dataset " + path + ": expected " + expected_desc + ", " + info.found());
}

std::string shape_desc(const std::string& rows_name, std::int64_t rows, hsize_t cols, const char* type) {
  std::string r = rows >= 0 ? std::to_string(rows) : rows_name;
  if (rows >= 0 && !rows_name.empty()) r = rows_name + "=" + r;
  return cols == 0 ? r + " " + type : r + " x " + std::to_string(cols) + " " + type;
}

/// Reads an integer dataset into int32, rejecting values that do not fit.
std::vector<Index> read_ints(const Ctx& ctx, const DatasetInfo& info, const std::string& path) {
  hsize_t count = 1;
  for (const hsize_t d : info.dims) count *= d;
  std::vector<Index> out(count);
  if (count == 0) return out;
  if (info.type_size <= 4 && (info.is_signed || info.type_size < 4)) {
    if (H5Dread(info.dataset.get(), H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      ctx.fail("dataset " + path + ": cannot read");
    return out;
  }
  // 64-bit (e.g. numpy's default int64) or uint32: read wide, then narrow with a range check.
  const bool wide_signed = info.is_signed;
  std::vector<std::int64_t> wide_s;
  std::vector<std::uint64_t> wide_u;
  herr_t status = 0;
  if (wide_signed) {
    wide_s.resize(count);
    status = H5Dread(info.dataset.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, wide_s.data());
  } else {
    wide_u.resize(count);
    status = H5Dread(info.dataset.get(), H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, wide_u.data());
  }
  if (status < 0) ctx.fail("dataset " + path + ": cannot read");
  constexpr auto kLo = std::numeric_limits<Index>::min();
  constexpr auto kHi = std::numeric_limits<Index>::max();
  for (hsize_t i = 0; i < count; ++i) {
    if (wide_signed) {
      if (wide_s[i] < kLo || wide_s[i] > kHi) {
        ctx.fail("dataset " + path + ": entry " + std::to_string(i) + " = " + std::to_string(wide_s[i]) +
                 " does not fit in int32");
      }
      out[i] = static_cast<Index>(wide_s[i]);
    } else {
      if (wide_u[i] > static_cast<std::uint64_t>(kHi)) {
        ctx.fail("dataset " + path + ": entry " + std::to_string(i) + " = " + std::to_string(wide_u[i]) +
                 " does not fit in int32");
      }
      out[i] = static_cast<Index>(wide_u[i]);
    }
  }
  return out;
}

void read_doubles(const Ctx& ctx, const DatasetInfo& info, const std::string& path, double* out) {
  hsize_t count = 1;
  for (const hsize_t d : info.dims) count *= d;
  if (count == 0) return;
  if (H5Dread(info.dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
    ctx.fail("dataset " + path + ": cannot read");
}

/// Reads an E x 3 (or N x 3) float64 dataset into a 3 x E matrix.
Eigen::Matrix3Xd read_vectors(const Ctx& ctx, hid_t file, const std::string& path, std::int64_t rows,
                              const char* rows_name) {
  const DatasetInfo info = open_dataset(ctx, file, path);
  check_shape(ctx, info, path, rows, 3, H5T_FLOAT, shape_desc(rows_name, rows, 3, "float64"));
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(info.dims[0]));
  read_doubles(ctx, info, path, m.data());
  return m;
}

struct AttributeInfo {
  Hdf5Handle attr;
  Hdf5Handle type;
  H5T_class_t type_class = H5T_NO_CLASS;
};

/// Opens obj's attribute `name`; returns an invalid handle when it does not exist.
AttributeInfo open_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& full,
                             bool required) {
  AttributeInfo a;
  const htri_t exists = H5Aexists(obj, name.c_str());
  if (exists < 0) ctx.fail("attribute " + full + ": cannot query");
  if (exists == 0) {
    if (required) ctx.fail("attribute " + full + ": missing");
    return a;
  }
  a.attr = Hdf5Handle(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose);
  if (!a.attr.valid()) ctx.fail("attribute " + full + ": cannot open");
  a.type = Hdf5Handle(H5Aget_type(a.attr.get()), H5Tclose);
  const Hdf5Handle space(H5Aget_space(a.attr.get()), H5Sclose);
  if (!a.type.valid() || !space.valid()) ctx.fail("attribute " + full + ": cannot query type");
  a.type_class = H5Tget_class(a.type.get());
  if (H5Sget_simple_extent_npoints(space.get()) != 1) {
    ctx.fail("attribute " + full + ": expected a single value, found " +
             std::to_string(H5Sget_simple_extent_npoints(space.get())));
  }
  return a;
}

std::string read_string_value(const Ctx& ctx, const AttributeInfo& a, const std::string& full) {
  if (a.type_class != H5T_STRING) ctx.fail("attribute " + full + ": expected a string");
  const htri_t is_vlen = H5Tis_variable_str(a.type.get());
  if (is_vlen < 0) ctx.fail("attribute " + full + ": cannot query string type");
  if (is_vlen > 0) {
    const Hdf5Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    if (!mem.valid() || H5Tset_size(mem.get(), H5T_VARIABLE) < 0 ||
        H5Tset_cset(mem.get(), H5Tget_cset(a.type.get())) < 0)
      ctx.fail("attribute " + full + ": cannot create string type");
    char* buf = nullptr;
    if (H5Aread(a.attr.get(), mem.get(), &buf) < 0) ctx.fail("attribute " + full + ": cannot read");
    std::string value = buf != nullptr ? std::string(buf) : std::string();
    if (buf != nullptr) H5free_memory(buf);
    return value;
  }
  const std::size_t size = H5Tget_size(a.type.get());
  std::string value(size, '\0');
  if (size > 0 && H5Aread(a.attr.get(), a.type.get(), value.data()) < 0)
    ctx.fail("attribute " + full + ": cannot read");
  if (const auto nul = value.find('\0'); nul != std::string::npos) value.resize(nul);
  if (H5Tget_strpad(a.type.get()) == H5T_STR_SPACEPAD) {
    while (!value.empty() && value.back() == ' ') value.pop_back();
  }
  return value;
}

std::string read_string_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& full) {
  const AttributeInfo a = open_attribute(ctx, obj, name, full, true);
  return read_string_value(ctx, a, full);
}

std::int64_t read_int_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& full,
                                bool required, std::int64_t fallback) {
  const AttributeInfo a = open_attribute(ctx, obj, name, full, required);
  if (!a.attr.valid()) return fallback;
  if (a.type_class != H5T_INTEGER) ctx.fail("attribute " + full + ": expected an integer");
  std::int64_t value = 0;
  if (H5Aread(a.attr.get(), H5T_NATIVE_INT64, &value) < 0) ctx.fail("attribute " + full + ": cannot read");
  return value;
}

double read_double_attribute(const Ctx& ctx, hid_t obj, const std::string& name, const std::string& full, bool required,
                             double fallback) {
  const AttributeInfo a = open_attribute(ctx, obj, name, full, required);
  if (!a.attr.valid()) return fallback;
  if (a.type_class != H5T_FLOAT && a.type_class != H5T_INTEGER) ctx.fail("attribute " + full + ": expected a number");
  double value = 0.0;
  if (H5Aread(a.attr.get(), H5T_NATIVE_DOUBLE, &value) < 0) ctx.fail("attribute " + full + ": cannot read");
  return value;
}

Hdf5Handle open_group(const Ctx& ctx, hid_t loc, const std::string& path) {
  Hdf5Handle g(H5Gopen2(loc, path.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) ctx.fail("group " + path + ": cannot open (not a group?)");
  return g;
}

template <std::size_t K>
std::vector<std::array<Index, K>> read_polygons(const Ctx& ctx, hid_t file, const std::string& path,
                                                std::size_t node_count) {
  const DatasetInfo info = open_dataset(ctx, file, path);
  check_shape(ctx, info, path, -1, K, H5T_INTEGER, "F x " + std::to_string(K) + " int32");
  const std::vector<Index> flat = read_ints(ctx, info, path);
  check_indices(ctx, flat.data(), flat.size(), node_count, path, K, K == 3 ? "face" : "quad");
  std::vector<std::array<Index, K>> tris(flat.size() / K);
  if (!flat.empty()) std::memcpy(tris.data(), flat.data(), flat.size() * sizeof(Index));
  return tris;
}

/// Checks /format and /version (the identification comes first: nothing else means anything in a
/// foreign file) and reads /voxel_size_m.
void read_format(const Ctx& ctx, hid_t file, Mesh& mesh) {
  const AttributeInfo a = open_attribute(ctx, file, "format", "/format", false);
  if (!a.attr.valid()) ctx.fail("attribute /format: missing (not an adamss mesh file)");
  const std::string fmt = read_string_value(ctx, a, "/format");
  if (fmt != kFormatName)
    ctx.fail("attribute /format: expected \"" + std::string(kFormatName) + "\", found \"" + fmt + "\"");
  const std::int64_t version = read_int_attribute(ctx, file, "version", "/version", true, 0);
  if (version > kMeshFormatVersion) {
    ctx.fail("attribute /version: file format version " + std::to_string(version) +
             " is newer than the supported version " + std::to_string(kMeshFormatVersion) + " (upgrade adamss)");
  }
  if (version < 1) ctx.fail("attribute /version: invalid format version " + std::to_string(version));
  mesh.voxel_size_m = read_double_attribute(ctx, file, "voxel_size_m", "/voxel_size_m", false, 0.0);
}

/// The element type named by the attribute /elements/type.
ElementType read_element_type(const Ctx& ctx, hid_t elements) {
  const std::string type = read_string_attribute(ctx, elements, "type", "/elements/type");
  if (type == "tet4") return ElementType::Tet4;
  if (type == "hex8") return ElementType::Hex8;
  if (type == "tet10") return ElementType::Tet10;
  if (type == "hex27") return ElementType::Hex27;
  ctx.fail("attribute /elements/type: unknown element type \"" + type +
           "\" (expected \"tet4\", \"hex8\", \"tet10\" or \"hex27\")");
}

/// /elements/connectivity and /elements/label into mesh (type and nodes already read); returns the
/// element count E.
std::int64_t read_connectivity_and_labels(const Ctx& ctx, hid_t file, Mesh& mesh) {
  const int k = nodes_per_element(mesh.type);
  std::int64_t E = 0;
  {
    const std::string path = "/elements/connectivity";
    const DatasetInfo info = open_dataset(ctx, file, path);
    check_shape(ctx, info, path, -1, static_cast<hsize_t>(k), H5T_INTEGER,
                "E x " + std::to_string(k) + " int32 (" + element_type_name(mesh.type) + ")");
    E = static_cast<std::int64_t>(info.dims[0]);
    mesh.connectivity = read_ints(ctx, info, path);
    check_connectivity(ctx, mesh.connectivity, k, mesh.node_count());
  }
  {
    const std::string path = "/elements/label";
    const DatasetInfo info = open_dataset(ctx, file, path);
    check_shape(ctx, info, path, E, 0, H5T_INTEGER, shape_desc("E", E, 0, "int32 (one label per element)"));
    mesh.labels = read_ints(ctx, info, path);
  }
  return E;
}

/// /elements/{fiber,sheet,normal}: all three or none.
void read_fibres(const Ctx& ctx, hid_t file, std::int64_t E, Mesh& mesh) {
  const char* names[] = {"fiber", "sheet", "normal"};
  int present = 0;
  for (const char* n : names) present += path_exists(file, std::string("/elements/") + n) ? 1 : 0;
  if (present != 0 && present != 3) {
    std::string missing;
    for (const char* n : names) {
      if (!path_exists(file, std::string("/elements/") + n)) missing += std::string(missing.empty() ? "" : ", ") + n;
    }
    ctx.fail("group /elements: fibre fields are partial (missing " + missing + "; need fiber, sheet and normal)");
  }
  if (present == 3) {
    mesh.fiber = read_vectors(ctx, file, "/elements/fiber", E, "E");
    mesh.sheet = read_vectors(ctx, file, "/elements/sheet", E, "E");
    mesh.normal = read_vectors(ctx, file, "/elements/normal", E, "E");
  }
}

/// The extra per-element scalars of /elements/scalars, if any.
void read_cell_scalars(const Ctx& ctx, hid_t file, std::int64_t E, Mesh& mesh) {
  if (!path_exists(file, "/elements/scalars")) return;
  const Hdf5Handle g = open_group(ctx, file, "/elements/scalars");
  for (const std::string& name : link_names(ctx, g.get(), "/elements/scalars")) {
    const std::string path = "/elements/scalars/" + name;
    const DatasetInfo info = open_dataset(ctx, file, path);
    check_shape(ctx, info, path, E, 0, H5T_FLOAT, shape_desc("E", E, 0, "float64"));
    Eigen::VectorXd values(static_cast<Eigen::Index>(E));
    read_doubles(ctx, info, path, values.data());
    mesh.cell_scalars.emplace(name, std::move(values));
  }
}

/// The node tags of /node_tags, if any.
void read_node_tags(const Ctx& ctx, hid_t file, Mesh& mesh) {
  if (!path_exists(file, "/node_tags")) return;
  const Hdf5Handle g = open_group(ctx, file, "/node_tags");
  for (const std::string& name : link_names(ctx, g.get(), "/node_tags")) {
    const std::string path = "/node_tags/" + name;
    const DatasetInfo info = open_dataset(ctx, file, path);
    check_shape(ctx, info, path, -1, 0, H5T_INTEGER, "1-D int32 node indices");
    std::vector<Index> tag = read_ints(ctx, info, path);
    check_indices(ctx, tag.data(), tag.size(), mesh.node_count(), path, 1, "");
    mesh.node_tags.emplace(name, std::move(tag));
  }
}

/// The cavities of /cavities, if any.
void read_cavities(const Ctx& ctx, hid_t file, Mesh& mesh) {
  if (!path_exists(file, "/cavities")) return;
  const std::size_t N = mesh.node_count();
  const Hdf5Handle g = open_group(ctx, file, "/cavities");
  for (const std::string& name : link_names(ctx, g.get(), "/cavities")) {
    const std::string where = "/cavities/" + name;
    const Hdf5Handle cg = open_group(ctx, file, where);
    Cavity cavity;
    cavity.faces = read_polygons<3>(ctx, file, where + "/faces", N);
    if (path_exists(file, where + "/quads")) cavity.quads = read_polygons<4>(ctx, file, where + "/quads", N);
    if (path_exists(file, where + "/lid")) cavity.lid = read_polygons<3>(ctx, file, where + "/lid", N);
    cavity.volume_m3 = read_double_attribute(ctx, cg.get(), "volume_m3", where + "/volume_m3", false, 0.0);
    cavity.closed = read_int_attribute(ctx, cg.get(), "closed", where + "/closed", false, 0) != 0;
    mesh.cavities.emplace(name, std::move(cavity));
  }
}

/// The free-form string attributes of the root group (foreign numeric attributes are ignored).
void read_root_attributes(const Ctx& ctx, hid_t file, Mesh& mesh) {
  for (const std::string& name : attribute_names(ctx, file, "group /")) {
    if (is_reserved_root_attribute(name)) continue;
    const AttributeInfo a = open_attribute(ctx, file, name, "/" + name, true);
    if (a.type_class != H5T_STRING) continue;
    mesh.attributes.emplace(name, read_string_value(ctx, a, "/" + name));
  }
}

Mesh read_contents(const Ctx& ctx, hid_t file) {
  Mesh mesh;
  read_format(ctx, file, mesh);
  if (!path_exists(file, "/elements")) ctx.fail("group /elements: missing");
  const Hdf5Handle elements = open_group(ctx, file, "/elements");
  mesh.type = read_element_type(ctx, elements.get());
  mesh.nodes = read_vectors(ctx, file, "/nodes", -1, "N");
  check_nodes_finite(ctx, mesh.nodes);
  const std::int64_t E = read_connectivity_and_labels(ctx, file, mesh);
  read_fibres(ctx, file, E, mesh);
  read_cell_scalars(ctx, file, E, mesh);
  read_node_tags(ctx, file, mesh);
  read_cavities(ctx, file, mesh);
  read_root_attributes(ctx, file, mesh);
  return mesh;
}

bool is_hdf5_file(const std::string& name) {
#if H5_VERSION_GE(1, 12, 0)
  return H5Fis_accessible(name.c_str(), H5P_DEFAULT) > 0;
#else
  return H5Fis_hdf5(name.c_str()) > 0;
#endif
}

}  // namespace

void write_mesh_h5(const std::filesystem::path& path, const Mesh& mesh) {
  const Ctx ctx{path.string()};
  check_mesh_for_writing(ctx, mesh);

  const fs::path parent = path.parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    ctx.fail("cannot write: directory " + parent.string() + " does not exist");

  // The file is built in memory and written in one checked, durable replace (hdf5_handle.hpp).
  std::string image;
  {
    const SilenceHdf5Errors silence;
    Hdf5Handle file = create_memory_file(path.string());
    if (!file.valid()) throw IoError(ctx.file + ": cannot create the HDF5 file in memory");
    write_contents(ctx, file.get(), mesh);
    image = file_image(file.get());
    if (image.empty() || !file.close()) throw IoError(ctx.file + ": cannot assemble the HDF5 file in memory");
  }
  replace_file(path, {image}, true);
}

namespace {

/// The whole read in this process (read_mesh_h5 runs it in a child first).
Mesh read_in_process(const Ctx& ctx) {
  const SilenceHdf5Errors silence;
  if (!is_hdf5_file(ctx.file)) ctx.fail("cannot read: not an HDF5 file");
  const Hdf5Handle file(H5Fopen(ctx.file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!file.valid()) ctx.fail("cannot open as HDF5 (corrupt or locked by another process?)");
  return read_contents(ctx, file.get());
}

}  // namespace

Mesh read_mesh_h5(const std::filesystem::path& path) {
  const Ctx ctx{path.string()};
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) ctx.fail("cannot read: file not found");
  if (!fs::is_regular_file(status)) ctx.fail("cannot read: not a regular file");
  // libhdf5 1.10 crashes or hangs on some corrupted object headers (common/guarded_read.hpp).
  guarded_read(path, "HDF5", [&] { (void)read_in_process(ctx); });
  return read_in_process(ctx);
}

}  // namespace adamss::preprocess
