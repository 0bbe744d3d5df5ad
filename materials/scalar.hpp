#pragma once
// Scalar helpers that let one templated energy W<T>(E) run on double and on
// (nested) Eigen::AutoDiffScalar alike, without this header including AutoDiff.
#include <type_traits>

namespace adamss::materials {

/// Plain double value of a scalar: the value itself for arithmetic types, the
/// innermost `.value()` for automatic-differentiation scalars (any nesting depth).
/// Used only for branch decisions (which side of a threshold, which sign), never
/// in a formula, so derivatives keep flowing through the chosen branch.
template <typename T>
constexpr double value_of(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<double>(x);
  } else {
    return value_of(x.value());
  }
}

}  // namespace adamss::materials
