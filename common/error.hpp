#pragma once
// Error types shared by every layer. An error's message is one line that names
// what was wrong and where (file, option, key path, element), so the CLI can
// print it as is and exit non-zero.
#include <stdexcept>
#include <string>

namespace adamss {

/// Bad input supplied by the user: a file, an option value, a scene key.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure during a computation (inverted element, NaN, no convergence).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A failed write or file-system operation on an output (disk full, a read-only or vanished
/// folder): the input was fine but the results could not be kept. Exit status 4 (app/main.cpp).
class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How the command line reports an error (app/main.cpp): its exit status and the words before
/// the message, "adamss: <label>: ...". InputError 2 "error", NumericalError 3 "numerical error",
/// IoError 4 "I/O error", anything else 1 "internal error".
struct ErrorReport {
  int exit_status;
  const char* label;
};

[[nodiscard]] inline ErrorReport error_report(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e) != nullptr) return {2, "error"};
  if (dynamic_cast<const NumericalError*>(&e) != nullptr) return {3, "numerical error"};
  if (dynamic_cast<const IoError*>(&e) != nullptr) return {4, "I/O error"};
  return {1, "internal error"};
}

}  // namespace adamss
