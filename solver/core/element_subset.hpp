#pragma once
// The elements a force term acts on: a material's element subset (scene order), or, when a term
// is built without one (tests, verification), every element of the mesh in order. The one place
// that resolves a null subset and checks the indices against the mesh.

#include <cstddef>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"

namespace adamss::solver {

/// `*subset`, or 0 .. element_count - 1 when `subset` is null. InputError naming `who` for an
/// index past the mesh.
[[nodiscard]] inline std::vector<std::size_t> selected_elements(const preprocess::Mesh& mesh,
                                                                const std::vector<std::size_t>* subset,
                                                                const std::string& who) {
  const std::size_t ne = mesh.element_count();
  std::vector<std::size_t> out;
  if (subset != nullptr) {
    out = *subset;
  } else {
    out.resize(ne);
    for (std::size_t e = 0; e < ne; ++e) out[e] = e;
  }
  for (const std::size_t e : out) {
    if (e >= ne) {
      throw InputError(who + ": element " + std::to_string(e) + " out of range (mesh has " + std::to_string(ne) + ")");
    }
  }
  return out;
}

}  // namespace adamss::solver
