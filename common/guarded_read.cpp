#include "common/guarded_read.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/error.hpp"

namespace adamss {

namespace {

constexpr int kChildOk = 0;
constexpr int kChildInputError = 3;
constexpr int kChildOtherError = 4;

/// Child side: run `read`, report an InputError's message through `fd`, never return.
[[noreturn]] void run_child(int fd, const std::function<void()>& read) {
  // A crash must kill the child by its signal, whatever handler the parent had installed (our
  // stop handler leaves these alone, but a sanitizer or libFuzzer turns SIGSEGV into a report and
  // exit code 1, which the parent could not tell from a sanitizer report about our own code).
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
  int code = kChildOk;
  try {
    read();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    std::size_t done = 0;
    while (done < msg.size()) {
      const ssize_t n = ::write(fd, msg.data() + done, msg.size() - done);
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    code = kChildInputError;
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
    run_child(fds[1], read);
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
  // Exit 0, kChildOtherError or another code (a sanitizer's report on our own code in the child):
  // the caller's real read succeeds or reproduces the failure in this process.
}

}  // namespace adamss
