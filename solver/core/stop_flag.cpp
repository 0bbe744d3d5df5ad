#include "solver/core/stop_flag.hpp"

#include <atomic>
#include <string>

namespace adamss::solver {

namespace {
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
bool (*g_agree)(bool) = nullptr;
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "the stop flag is written from a signal handler");
}  // namespace

void request_stop(int signal) noexcept {
  g_signal.store(signal);
  g_stop.store(true);
}

void clear_stop() noexcept {
  g_stop.store(false);
  g_signal.store(0);
}

bool stop_requested() noexcept {
  const bool local = g_stop.load();
  if (g_agree == nullptr) return local;
  const bool agreed = g_agree(local);
  if (agreed && !local) g_stop.store(true);  // another rank's signal: this rank stops too
  return agreed;
}

void set_stop_agreement(bool (*agree)(bool)) {
  g_agree = agree;
}

int stop_signal() noexcept {
  return g_signal.load();
}

void throw_if_stop_requested(const char* where) {
  if (stop_requested()) throw StepInterrupted(std::string(where) + ": stop requested, step abandoned");
}

}  // namespace adamss::solver
