#pragma once
// RAII glue for the HDF5 C API: a handle that closes itself and a scope that silences HDF5's
// automatic error-stack printing. Used by the mesh file (preprocess/mesh/mesh_io_h5.cpp); meant
// for every HDF5 reader and writer of the project.
#include <hdf5.h>

#include <string>
#include <utility>

namespace adamss::preprocess {

/// Owns one hid_t and closes it with the matching H5?close on destruction.
class Hdf5Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Hdf5Handle() = default;
  Hdf5Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Hdf5Handle(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(const Hdf5Handle&) = delete;
  Hdf5Handle(Hdf5Handle&& other) noexcept : id_(std::exchange(other.id_, -1)), closer_(other.closer_) {}
  Hdf5Handle& operator=(Hdf5Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, -1);
      closer_ = other.closer_;
    }
    return *this;
  }
  ~Hdf5Handle() { reset(); }

  [[nodiscard]] hid_t get() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }
  /// Closes now; returns false if HDF5 reported an error (used for the file, where the
  /// close flushes the data and a failure matters).
  bool close() {
    const hid_t id = std::exchange(id_, -1);
    return id < 0 || closer_ == nullptr || closer_(id) >= 0;
  }
  void reset() { (void)close(); }

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Switches HDF5's automatic error-stack printing off for the current scope.
class SilenceHdf5Errors {
 public:
  SilenceHdf5Errors() {
    saved_ok_ = H5Eget_auto2(H5E_DEFAULT, &func_, &data_) >= 0;
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~SilenceHdf5Errors() {
    if (saved_ok_) H5Eset_auto2(H5E_DEFAULT, func_, data_);
  }
  SilenceHdf5Errors(const SilenceHdf5Errors&) = delete;
  SilenceHdf5Errors& operator=(const SilenceHdf5Errors&) = delete;

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
  bool saved_ok_ = false;
};

/// A new HDF5 file that lives in memory only (the core driver, no backing store; `name` is only
/// its label): the library never touches the disk, so a full disk cannot fail inside it (libhdf5
/// 1.10 left a file it could not flush open and crashed at exit). file_image gives the bytes,
/// which replace_file (common/durable.hpp) writes with every error checked. Invalid on failure.
inline Hdf5Handle create_memory_file(const std::string& name) {
  const Hdf5Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.valid() || H5Pset_fapl_core(fapl.get(), std::size_t{1} << 20, 0) < 0) return {};
  return {H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose};
}

/// The bytes of an open (memory) file, flushed first; empty on failure.
inline std::string file_image(hid_t file) {
  if (H5Fflush(file, H5F_SCOPE_LOCAL) < 0) return {};
  const ssize_t n = H5Fget_file_image(file, nullptr, 0);
  if (n <= 0) return {};
  std::string bytes(static_cast<std::size_t>(n), '\0');
  if (H5Fget_file_image(file, bytes.data(), static_cast<std::size_t>(n)) != n) return {};
  return bytes;
}

}  // namespace adamss::preprocess
