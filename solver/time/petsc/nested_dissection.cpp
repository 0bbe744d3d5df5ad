#include "solver/time/petsc/nested_dissection.hpp"

#include <metis.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace adamss::solver {

std::vector<int> nested_dissection_order(int n, const std::vector<int>& irn, const std::vector<int>& jcn) {
  // Adjacency in CSR, both directions, without the diagonal; duplicates removed per row.
  std::vector<idx_t> degree(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t e = 0; e < irn.size(); ++e) {
    if (irn[e] == jcn[e]) continue;
    ++degree[static_cast<std::size_t>(irn[e])];
    ++degree[static_cast<std::size_t>(jcn[e])];
  }
  std::vector<idx_t> xadj(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i)
    xadj[static_cast<std::size_t>(i) + 1] = xadj[static_cast<std::size_t>(i)] + degree[static_cast<std::size_t>(i) + 1];
  std::vector<idx_t> adjncy(static_cast<std::size_t>(xadj.back()));
  std::vector<idx_t> fill(xadj.begin(), xadj.end() - 1);
  for (std::size_t e = 0; e < irn.size(); ++e) {
    const int i = irn[e] - 1, j = jcn[e] - 1;
    if (i == j) continue;
    adjncy[static_cast<std::size_t>(fill[static_cast<std::size_t>(i)]++)] = j;
    adjncy[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)]++)] = i;
  }
  // Sort and deduplicate each row, compacting in place.
  idx_t out = 0;
  for (int i = 0; i < n; ++i) {
    const auto b = adjncy.begin() + xadj[static_cast<std::size_t>(i)];
    const auto e = adjncy.begin() + fill[static_cast<std::size_t>(i)];
    std::sort(b, e);
    const auto last = std::unique(b, e);
    const idx_t start = out;
    for (auto it = b; it != last; ++it) adjncy[static_cast<std::size_t>(out++)] = *it;
    xadj[static_cast<std::size_t>(i)] = start;
  }
  xadj[static_cast<std::size_t>(n)] = out;
  adjncy.resize(static_cast<std::size_t>(out));
  if (out == 0) {  // no off-diagonal entry (or n = 0): nothing to fill, METIS refuses such graphs
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = i + 1;
    return order;
  }
  idx_t nv = n;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  std::vector<idx_t> perm(static_cast<std::size_t>(n)), iperm(static_cast<std::size_t>(n));
  const int status = METIS_NodeND(&nv, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  if (status != METIS_OK) throw std::runtime_error("METIS_NodeND failed (status " + std::to_string(status) + ")");
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    order[static_cast<std::size_t>(i)] = static_cast<int>(iperm[static_cast<std::size_t>(i)]) + 1;
  return order;
}

}  // namespace adamss::solver
