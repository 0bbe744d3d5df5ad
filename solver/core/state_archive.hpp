#pragma once
// StateArchive: the named numbers a checkpoint holds (checkpoint.h5, docs/file-formats.md).
//
// A checkpoint must let `adamss run --resume` continue a run so that the result equals the
// uninterrupted run bit for bit. Positions and velocities are not enough: the integrators carry
// history (ABM3's past accelerations and step size, the static predictor's previous state), some
// force terms carry state that evolves step by step (the LMS-adaptive volume-spring stiffnesses,
// a cavity's pressure multiplier), and the run loop and the results writer carry counters
// (step, next dt, next frame / globals time, extrema). Every component that has such state
// writes it into an archive under its own prefix (save_state) and reads it back (load_state);
// the values are stored as float64 / int64 exactly, so nothing is rounded on the way.
//
// Keys are slash-separated paths ("integrator/history/0/x"); in the HDF5 file every key is a
// dataset, every prefix a group. A matrix (3 x n in memory) is stored n x 3 like /x and /v.
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace adamss::solver {

class StateArchive {
 public:
  StateArchive();

  /// A view of this archive whose keys are prefixed by `name` + "/" (shares the storage).
  [[nodiscard]] StateArchive child(const std::string& name) const;

  void put(const std::string& key, double value);
  void put(const std::string& key, const std::vector<double>& values);
  void put(const std::string& key, const Eigen::Matrix3Xd& m);
  void put_int(const std::string& key, std::int64_t value);
  void put_ints(const std::string& key, const std::vector<std::int64_t>& values);

  [[nodiscard]] bool has(const std::string& key) const;
  /// The keys under this view's prefix (without it), sorted.
  [[nodiscard]] std::vector<std::string> keys() const;
  /// Removes `key` if present (tests build incomplete checkpoints with it).
  void erase(const std::string& key);
  /// The values under `key`; InputError naming the file and the key if it is missing or has the
  /// wrong type. scalar/integer also require exactly one value.
  [[nodiscard]] const std::vector<double>& doubles(const std::string& key) const;
  [[nodiscard]] double scalar(const std::string& key) const;
  [[nodiscard]] const std::vector<std::int64_t>& integers(const std::string& key) const;
  [[nodiscard]] std::int64_t integer(const std::string& key) const;
  /// A 3 x cols matrix; InputError if the stored one has another size.
  [[nodiscard]] Eigen::Matrix3Xd matrix(const std::string& key, Eigen::Index cols) const;

  /// Where the archive was read from (for messages), "checkpoint" when built in memory.
  [[nodiscard]] const std::string& source() const;

  /// Writes all entries to `file` via `file`.tmp renamed over it (an interrupted write never
  /// leaves a truncated checkpoint). `root_attributes` become float64 attributes of "/".
  void write_hdf5(const std::filesystem::path& file, const std::map<std::string, double>& root_attributes = {}) const;
  /// Reads every dataset of `file`; InputError naming the file if it cannot be read.
  [[nodiscard]] static StateArchive read_hdf5(const std::filesystem::path& file);

  struct Entry {
    bool is_int = false;
    std::vector<double> d;
    std::vector<std::int64_t> i;
    std::vector<unsigned long long> dims;  ///< HDF5 shape; empty: 1-D of the value count
  };

 private:
  /// read_hdf5 without the child process (read_hdf5 runs this in a child first).
  [[nodiscard]] static StateArchive read_hdf5_in_process(const std::filesystem::path& file);

  struct Storage {
    std::map<std::string, Entry> entries;
    std::string source = "checkpoint";
  };
  [[nodiscard]] std::string full(const std::string& key) const { return prefix_ + key; }
  [[nodiscard]] const Entry& entry(const std::string& key, bool is_int) const;
  std::shared_ptr<Storage> st_;
  std::string prefix_;
};

}  // namespace adamss::solver
