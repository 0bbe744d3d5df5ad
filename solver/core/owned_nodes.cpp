#include "solver/core/owned_nodes.hpp"

namespace adamss::solver {

namespace {
const OwnedNodes* g_owned = nullptr;
}  // namespace

const OwnedNodes* owned_force_nodes() noexcept {
  return g_owned;
}

OwnedForceScope::OwnedForceScope(const OwnedNodes& owned) noexcept {
  g_owned = &owned;
}

OwnedForceScope::~OwnedForceScope() {
  g_owned = nullptr;
}

}  // namespace adamss::solver
