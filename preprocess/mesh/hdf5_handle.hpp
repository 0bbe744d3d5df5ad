#pragma once
// RAII glue for the HDF5 C API: a handle that closes itself and a scope that silences HDF5's
// automatic error-stack printing. Used by the mesh file (preprocess/mesh/mesh_io_h5.cpp); meant
// for every HDF5 reader and writer of the project.
#include <hdf5.h>

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

}  // namespace adamss::preprocess
