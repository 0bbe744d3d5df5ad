#include "solver/run/stop_signals.hpp"

#include <csignal>

#include "solver/core/stop_flag.hpp"

namespace adamss::solver {

namespace {

extern "C" void on_stop_signal(int sig) {
  request_stop(sig);
}

}  // namespace

struct StopSignals::Saved {
  struct sigaction old_int {};
  struct sigaction old_term {};
};

StopSignals::StopSignals() : saved_(std::make_unique<Saved>()) {
  clear_stop();
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &saved_->old_int);
  sigaction(SIGTERM, &sa, &saved_->old_term);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &saved_->old_int, nullptr);
  sigaction(SIGTERM, &saved_->old_term, nullptr);
}

bool StopSignals::requested() const {
  return stop_requested();
}

std::string StopSignals::name() const {
  return stop_signal() == SIGTERM ? "SIGTERM" : "SIGINT";
}

}  // namespace adamss::solver
