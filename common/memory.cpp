#include "common/memory.hpp"

#include <algorithm>
#include <fstream>
#include <string>

namespace adamss {

namespace {

/// A "Name:   123 kB" line of /proc/self/status, in MB (10^6 bytes); -1 when absent.
double status_mb(const std::string& name) {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == name + ":") {
      double kb = -1.0;
      status >> kb;
      return kb >= 0.0 ? kb * 1.024e-3 : -1.0;
    }
    status.ignore(1 << 16, '\n');
  }
  return -1.0;
}

}  // namespace

double resident_mb() {
  return status_mb("VmRSS");
}

double peak_resident_mb() {
  // VmHWM follows counters the kernel syncs lazily: never report a peak below the current size.
  return std::max(status_mb("VmHWM"), status_mb("VmRSS"));
}

}  // namespace adamss
