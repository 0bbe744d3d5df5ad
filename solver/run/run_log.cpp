#include "solver/run/run_log.hpp"

#include <cerrno>
#include <cstring>
#include <ctime>

#include "common/error.hpp"

namespace adamss::solver {

namespace {

/// "2026-11-26 22:51:07  text".
std::string stamped(std::string_view text) {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char when[32];
  const std::size_t n = std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S  ", &local);
  return std::string(when, n) + std::string(text) + "\n";
}

}  // namespace

void RunLog::line(std::string_view text) {
  if (muted_) return;
  if (!open_) {
    pending_.push_back(stamped(text));
    return;
  }
  write(stamped(text));
}

void RunLog::open(bool append) {
  if (open_ || muted_) return;
  out_.open(file_, append ? std::ios::app : std::ios::trunc);
  if (!out_) throw IoError("cannot write " + file_.string() + ": " + std::strerror(errno));
  open_ = true;
  for (const std::string& l : pending_) write(l);
  pending_.clear();
}

void RunLog::write(const std::string& stamped_line) {
  out_ << stamped_line;
  out_.flush();
  if (!out_) throw IoError("cannot write " + file_.string() + " (disk full?)");
}

}  // namespace adamss::solver
