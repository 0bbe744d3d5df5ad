#include "solver/run/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "common/error.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;

namespace {

/// The PID text the holder wrote into the lock file ("unknown" if it cannot be read).
std::string holder_pid(int fd) {
  char buf[32] = {};
  const ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
  std::string pid = n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.empty() ? "unknown" : pid;
}

}  // namespace

OutputLock::OutputLock(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw IoError("cannot create the output folder " + dir.string() + ": " + ec.message());
  const fs::path file = dir / ".lock";
  fd_ = open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw IoError("cannot open the lock file " + file.string() + ": " + std::strerror(errno));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    const std::string pid = holder_pid(fd_);
    close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) {
      throw InputError("the output folder " + dir.string() + " is in use by another adamss run (PID " + pid +
                       " holds " + file.string() + "); wait for it to end or choose another -o");
    }
    throw IoError("cannot lock " + file.string() + ": " + std::strerror(err));
  }
  const std::string pid = std::to_string(getpid()) + "\n";
  if (ftruncate(fd_, 0) != 0 || pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    close(fd_);
    fd_ = -1;
    throw IoError("cannot write " + file.string() + ": " + std::strerror(errno));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) close(fd_);
}

}  // namespace adamss::solver
