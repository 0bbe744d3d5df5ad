#pragma once
// One adamss run per output folder at a time: OutputLock holds an exclusive flock(2) on OUT/.lock
// for its lifetime. The kernel drops the lock when the process ends, however it ends, so a
// crashed run never leaves a stale lock behind; the file itself stays (it only holds the PID of
// the last holder, for the message a second run prints).
#include <filesystem>

namespace adamss::solver {

class OutputLock {
 public:
  /// Creates `dir` if needed and locks dir/.lock. InputError naming the folder and the PID of
  /// the holder when another process holds it; IoError when the folder or file cannot be made.
  explicit OutputLock(const std::filesystem::path& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace adamss::solver
