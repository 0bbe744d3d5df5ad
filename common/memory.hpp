#pragma once
// The process's memory as the kernel counts it, for the run summary (a long run whose resident
// size keeps growing leaks) and the soak test (cases/heart/lv_soak.yaml).

namespace adamss {

/// Resident set size now, MB (10^6 bytes): VmRSS of /proc/self/status. -1 where /proc is not
/// available.
[[nodiscard]] double resident_mb();

/// Largest resident set size so far, MB: VmHWM of /proc/self/status (at least resident_mb()).
/// -1 where /proc is not available.
[[nodiscard]] double peak_resident_mb();

}  // namespace adamss
