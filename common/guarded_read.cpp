#include "common/guarded_read.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <string>

#include "common/durable.hpp"
#include "common/error.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define ADAMSS_GUARD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ADAMSS_GUARD_ASAN 1
#endif
#endif
#if defined(ADAMSS_GUARD_ASAN)
#include <sanitizer/asan_interface.h>
#endif

namespace adamss {

namespace {

constexpr int kChildOk = 0;
constexpr int kChildInputError = 3;
constexpr int kChildOtherError = 4;
constexpr int kChildLibraryReport = 5;
constexpr int kChildOutOfMemory = 6;

/// The process's virtual address space now, bytes (VmSize of /proc/self/status); 0 if unknown.
unsigned long long address_space_bytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmSize:") {
      unsigned long long kb = 0;
      status >> kb;
      return kb * 1024ULL;
    }
    status.ignore(1 << 16, '\n');
  }
  return 0;
}

/// In the child: no new mapping beyond `limit` bytes of address space (RLIMIT_AS). malloc then
/// returns NULL and operator new throws std::bad_alloc instead of the child growing to what a
/// corrupted header claims. Never raises an existing, lower limit (a fuzzer's -rss_limit_mb).
void cap_address_space(unsigned long long limit) {
  if (limit == 0) return;
  rlimit current{};
  if (::getrlimit(RLIMIT_AS, &current) != 0) return;
  if (current.rlim_cur != RLIM_INFINITY && current.rlim_cur <= limit) return;
  rlimit capped = current;
  capped.rlim_cur = static_cast<rlim_t>(limit);
  ::setrlimit(RLIMIT_AS, &capped);
}

#if defined(ADAMSS_GUARD_ASAN)
/// The library's shared-object name ("libhdf5") for the report callback below.
char g_library[64] = {0};

/// In a sanitized child: an AddressSanitizer report whose first two frames (the access itself,
/// or an intercepted memcpy/malloc and its caller) lie in the library is the library's fault on
/// a corrupted file (libhdf5 1.10 over-reads heap buffers on some): exit kChildLibraryReport.
/// A report with our code there exits as ASan does, and the parent reproduces it in-process.
void on_asan_report(const char* report) {
  for (const char* frame : {"\n    #0 ", "\n    #1 "}) {
    const char* at = std::strstr(report, frame);
    const char* end = at != nullptr ? std::strchr(at + 1, '\n') : nullptr;
    if (at == nullptr || end == nullptr) continue;
    const std::string line(at, end);
    if (line.find(g_library) != std::string::npos) ::_exit(kChildLibraryReport);
  }
}
#endif

/// Child side: run `read`, report an InputError's message through `fd`, never return.
[[noreturn]] void run_child(int fd, const std::string& what, unsigned long long address_limit,
                            const std::function<void()>& read) {
#if defined(ADAMSS_GUARD_ASAN)
  std::string lib = "lib";
  for (const char c : what) lib += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::snprintf(g_library, sizeof g_library, "%s", lib.c_str());
  __asan_set_error_report_callback(on_asan_report);
#else
  (void)what;
#endif
  // A crash must kill the child by its signal, whatever handler the parent had installed (our
  // stop handler leaves these alone, but a sanitizer or libFuzzer turns SIGSEGV into a report and
  // exit code 1, which the parent could not tell from a sanitizer report about our own code).
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
  // Nothing the child would print is for the user (the parent reports the outcome, and reproduces
  // a sanitizer report about our own code in-process): its stderr goes to /dev/null.
  if (const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC); null >= 0) {
    ::dup2(null, STDERR_FILENO);
    ::close(null);
  }
  cap_address_space(address_limit);
  int code = kChildOk;
  try {
    read();
  } catch (const InputError& e) {
    (void)write_all(fd, {e.what()});  // the parent reports what arrived
    code = kChildInputError;
  } catch (const std::bad_alloc&) {
    code = kChildOutOfMemory;
  } catch (...) {
    code = kChildOtherError;
  }
  ::close(fd);
  ::_exit(code);  // no atexit handlers, no stdio flush of the parent's buffers
}

std::string signal_name(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return abbrev != nullptr ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

/// Parent side: collect the child's message until it closes the pipe (exits) or time runs out.
/// Returns false on timeout (the child is killed and reaped).
bool collect(pid_t pid, int fd, double seconds, std::string& message, int& status) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  char buf[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return false;
    }
    pollfd p{fd, POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) {
      message.append(buf, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    break;  // EOF: the child has exited (or closed the pipe just before)
  }
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return true;
}

}  // namespace

double guard_megabytes(const std::filesystem::path& file) {
  if (const char* env = std::getenv("ADAMSS_HDF5_GUARD_MB")) {
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    if (end != env && v > 0.0) return v;
  }
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return 2048.0 + (ec ? 0.0 : 64.0 * static_cast<double>(size) / 1048576.0);
}

double guard_seconds(const std::filesystem::path& file) {
  if (const char* env = std::getenv("ADAMSS_HDF5_GUARD_SECONDS")) {
    char* end = nullptr;
    const double v = std::strtod(env, &end);
    if (end != env && v > 0.0) return v;
  }
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  return 60.0 + (ec ? 0.0 : static_cast<double>(size) / 1e7);
}

void guarded_read(const std::filesystem::path& file, const std::string& what, const std::function<void()>& read) {
  if (const char* env = std::getenv("ADAMSS_HDF5_GUARD"); env != nullptr && std::string(env) == "0") return;
  const double megabytes = guard_megabytes(file);
  const unsigned long long here = address_space_bytes();
  const unsigned long long address_limit =
      here == 0 ? 0 : here + static_cast<unsigned long long>(megabytes * 1048576.0);
  int fds[2];
  if (::pipe(fds) != 0) return;
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return;
  }
  if (pid == 0) {
    ::close(fds[0]);
    run_child(fds[1], what, address_limit, read);
  }
  ::close(fds[1]);
  std::string message;
  int status = 0;
  const double seconds = guard_seconds(file);
  const bool finished = collect(pid, fds[0], seconds, message, status);
  ::close(fds[0]);
  std::string name(1, '\'');  // (not "'" + ...: GCC 12 warns -Wrestrict on that operator+)
  name += file.string();
  name += '\'';
  if (!finished) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", seconds);
    throw InputError(name + ": reading it did not finish in " + limit + " s (the " + what +
                     " library loops forever on some corrupted files; ADAMSS_HDF5_GUARD_SECONDS "
                     "sets the limit): the file is corrupted, or too large for the limit");
  }
  if (WIFSIGNALED(status)) {
    throw InputError(name + ": the " + what + " library crashed (" + signal_name(WTERMSIG(status)) +
                     ") reading it, in a child process that reads every file first: the file is corrupted");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildInputError) throw InputError(message);
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildLibraryReport) {
    throw InputError(name + ": the " + what + " library made an invalid memory access reading it (AddressSanitizer " +
                     "report in a child process that reads every file first): the file is corrupted");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildOutOfMemory) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.0f", megabytes);
    throw InputError(name + ": reading it needed more than " + limit +
                     " MB of memory in a child process that reads every file first (the " + what +
                     " library allocates what a corrupted header claims; ADAMSS_HDF5_GUARD_MB sets the limit): " +
                     "the file is corrupted, or too large for the limit");
  }
  // Exit 0, kChildOtherError or another code (a sanitizer's report on our own code in the child):
  // the caller's real read succeeds or reproduces the failure in this process.
}

}  // namespace adamss
