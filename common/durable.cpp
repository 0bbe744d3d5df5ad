#include "common/durable.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "common/error.hpp"

namespace adamss {

namespace {

void sync_path(const std::filesystem::path& p, int flags, const char* what) {
  const int fd = ::open(p.c_str(), flags | O_CLOEXEC);
  if (fd < 0)
    throw IoError(std::string("cannot open ") + what + " " + p.string() + " to sync it: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw IoError(std::string("cannot sync ") + what + " " + p.string() + " to disk: " + std::strerror(err));
}

}  // namespace

void sync_file(const std::filesystem::path& file) {
  sync_path(file, O_RDONLY, "file");
}

void sync_directory(const std::filesystem::path& dir) {
  sync_path(dir.empty() ? std::filesystem::path(".") : dir, O_RDONLY | O_DIRECTORY, "folder");
}

int write_all(int fd, std::initializer_list<std::string_view> parts) {
  for (const std::string_view part : parts) {
    std::size_t done = 0;
    while (done < part.size()) {
      const ssize_t n = ::write(fd, part.data() + done, part.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return n < 0 ? errno : EIO;
      done += static_cast<std::size_t>(n);
    }
  }
  return 0;
}

void replace_file(const std::filesystem::path& path, std::initializer_list<std::string_view> parts, bool durable) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  std::error_code ec;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError("cannot create " + tmp.string() + ": " + std::strerror(errno));
  int err = write_all(fd, parts);
  if (err == 0 && durable && ::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;  // NFS and friends report a full disk here
  if (err != 0) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot write " + tmp.string() + ": " + std::strerror(err));
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError("cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  }
  if (durable) sync_directory(path.parent_path());
}

}  // namespace adamss
