#include "solver/core/state_archive.hpp"

#include <hdf5.h>

#include <algorithm>
#include <system_error>

#include "common/durable.hpp"
#include "common/error.hpp"
#include "common/guarded_read.hpp"
#include "preprocess/mesh/hdf5_handle.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;

StateArchive::StateArchive() : st_(std::make_shared<Storage>()) {}

StateArchive StateArchive::child(const std::string& name) const {
  StateArchive a = *this;
  a.prefix_ = prefix_ + name + "/";
  return a;
}

void StateArchive::put(const std::string& key, double value) {
  put(key, std::vector<double>{value});
}

void StateArchive::put(const std::string& key, const std::vector<double>& values) {
  Entry& e = st_->entries[full(key)];
  e = Entry{};
  e.d = values;
}

void StateArchive::put(const std::string& key, const Eigen::Matrix3Xd& m) {
  Entry& e = st_->entries[full(key)];
  e = Entry{};
  e.d.assign(m.data(), m.data() + m.size());
  e.dims = {static_cast<unsigned long long>(m.cols()), 3ULL};
}

void StateArchive::put_int(const std::string& key, std::int64_t value) {
  put_ints(key, std::vector<std::int64_t>{value});
}

void StateArchive::put_ints(const std::string& key, const std::vector<std::int64_t>& values) {
  Entry& e = st_->entries[full(key)];
  e = Entry{};
  e.is_int = true;
  e.i = values;
}

bool StateArchive::has(const std::string& key) const {
  return st_->entries.count(full(key)) != 0;
}

std::vector<std::string> StateArchive::keys() const {
  std::vector<std::string> out;
  for (const auto& [key, e] : st_->entries)
    if (key.compare(0, prefix_.size(), prefix_) == 0) out.push_back(key.substr(prefix_.size()));
  return out;
}

void StateArchive::erase(const std::string& key) {
  st_->entries.erase(full(key));
}

const std::string& StateArchive::source() const {
  return st_->source;
}

const StateArchive::Entry& StateArchive::entry(const std::string& key, bool is_int) const {
  const auto it = st_->entries.find(full(key));
  if (it == st_->entries.end()) {
    throw InputError(st_->source + ": /" + full(key) +
                     " is missing (a checkpoint of another scene or of an older adamss version?)");
  }
  if (it->second.is_int != is_int) {
    throw InputError(st_->source + ": /" + full(key) + " should be " + (is_int ? "an integer" : "a float64") +
                     " dataset");
  }
  return it->second;
}

const std::vector<double>& StateArchive::doubles(const std::string& key) const {
  return entry(key, false).d;
}

double StateArchive::scalar(const std::string& key) const {
  const auto& d = doubles(key);
  if (d.size() != 1) throw InputError(st_->source + ": /" + full(key) + " should hold one value");
  return d[0];
}

const std::vector<std::int64_t>& StateArchive::integers(const std::string& key) const {
  return entry(key, true).i;
}

std::int64_t StateArchive::integer(const std::string& key) const {
  const auto& i = integers(key);
  if (i.size() != 1) throw InputError(st_->source + ": /" + full(key) + " should hold one value");
  return i[0];
}

Eigen::Matrix3Xd StateArchive::matrix(const std::string& key, Eigen::Index cols) const {
  const auto& d = doubles(key);
  if (d.size() != static_cast<std::size_t>(3 * cols)) {
    throw InputError(st_->source + ": /" + full(key) + " holds " + std::to_string(d.size() / 3) +
                     " rows, the scene has " + std::to_string(cols) +
                     " (the checkpoint belongs to a different scene or mesh)");
  }
  Eigen::Matrix3Xd m(3, cols);
  std::copy(d.begin(), d.end(), m.data());
  return m;
}

void StateArchive::write_hdf5(const fs::path& file, const std::map<std::string, double>& root_attributes) const {
  const preprocess::SilenceHdf5Errors quiet;  // a failure is one IoError line, not HDF5's diagnostic stack on stderr
  // Built in memory (preprocess/mesh/hdf5_handle.hpp: libhdf5 never touches the disk), then
  // written with every error checked, fsync'ed and renamed into place (replace_file).
  preprocess::Hdf5Handle memory_file = preprocess::create_memory_file(file.string());
  const hid_t f = memory_file.get();
  if (f < 0) throw IoError("cannot create the HDF5 file " + file.string() + " in memory");
  const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  bool ok = true;
  for (const auto& [key, e] : st_->entries) {
    std::vector<hsize_t> dims;
    if (e.dims.empty()) {
      dims.push_back(e.is_int ? e.i.size() : e.d.size());
    } else {
      dims.assign(e.dims.begin(), e.dims.end());
    }
    const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
    const hid_t ds =
        H5Dcreate2(f, key.c_str(), e.is_int ? H5T_STD_I64LE : H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
    if (ds < 0) {
      ok = false;
    } else {
      const bool empty = e.is_int ? e.i.empty() : e.d.empty();
      if (!empty) {
        const herr_t st = e.is_int ? H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.i.data())
                                   : H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.d.data());
        ok = ok && st >= 0;
      }
      H5Dclose(ds);
    }
    H5Sclose(space);
  }
  for (const auto& [name, v] : root_attributes) {
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(f, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT);
    ok = ok && a >= 0 && H5Awrite(a, H5T_NATIVE_DOUBLE, &v) >= 0;
    if (a >= 0) H5Aclose(a);
    H5Sclose(space);
  }
  H5Pclose(lcpl);
  const std::string image = ok ? preprocess::file_image(f) : std::string();
  ok = memory_file.close() && ok;
  if (!ok || image.empty()) throw IoError("cannot assemble the HDF5 file " + file.string() + " in memory");
  replace_file(file, {image}, true);  // the last good checkpoint stays as it was on failure
}

namespace {

struct VisitData {
  std::map<std::string, StateArchive::Entry>* entries;
  bool ok = true;
};

herr_t visit_link(hid_t group, const char* name, const H5L_info_t* /*info*/, void* data) {
  auto* vd = static_cast<VisitData*>(data);
  const hid_t obj = H5Oopen(group, name, H5P_DEFAULT);
  if (obj < 0) return 0;  // a dangling link: nothing of ours
  if (H5Iget_type(obj) != H5I_DATASET) {
    H5Oclose(obj);
    return 0;
  }
  StateArchive::Entry e;
  const hid_t type = H5Dget_type(obj);
  e.is_int = H5Tget_class(type) == H5T_INTEGER;
  H5Tclose(type);
  const hid_t space = H5Dget_space(obj);
  const int rank = H5Sget_simple_extent_ndims(space);
  std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
  if (rank > 0) H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  const auto count = static_cast<std::size_t>(H5Sget_simple_extent_npoints(space));
  H5Sclose(space);
  if (rank > 1) e.dims.assign(dims.begin(), dims.end());
  if (count > 0) {
    herr_t st = 0;
    if (e.is_int) {
      e.i.resize(count);
      st = H5Dread(obj, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.i.data());
    } else {
      e.d.resize(count);
      st = H5Dread(obj, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.d.data());
    }
    vd->ok = vd->ok && st >= 0;
  }
  H5Oclose(obj);
  (*vd->entries)[name] = std::move(e);
  return 0;
}

}  // namespace

StateArchive StateArchive::read_hdf5(const fs::path& file) {
  if (!fs::exists(file)) throw InputError("checkpoint " + file.string() + " does not exist");
  // libhdf5 1.10 crashes or hangs on some corrupted object headers (common/guarded_read.hpp).
  guarded_read(file, "HDF5", [&] { (void)read_hdf5_in_process(file); });
  return read_hdf5_in_process(file);
}

StateArchive StateArchive::read_hdf5_in_process(const fs::path& file) {
  H5E_auto2_t old_func = nullptr;
  void* old_data = nullptr;
  H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Eset_auto2(H5E_DEFAULT, old_func, old_data);
  if (f < 0) throw InputError("cannot open checkpoint " + file.string() + " (not an HDF5 file?)");
  StateArchive a;
  a.st_->source = file.string();
  VisitData vd{&a.st_->entries};
  const herr_t st = H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, visit_link, &vd);
  H5Fclose(f);
  if (st < 0 || !vd.ok) throw InputError("error while reading checkpoint " + file.string());
  return a;
}

}  // namespace adamss::solver
