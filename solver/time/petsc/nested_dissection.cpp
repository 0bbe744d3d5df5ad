#include "solver/time/petsc/nested_dissection.hpp"

#include <metis.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace adamss::solver {

namespace {

/// The symmetric adjacency of a coordinate pattern (1-based irn, jcn) in METIS's CSR form (xadj:
/// n + 1 row starts, adjncy: 0-based neighbours), without the diagonal, each row sorted and
/// without duplicates. Throws when the adjacency exceeds METIS's 32-bit indices.
void symmetric_adjacency(int n, const std::vector<int>& irn, const std::vector<int>& jcn, std::vector<idx_t>& xadj,
                         std::vector<idx_t>& adjncy) {
  const auto row = [](int one_based) { return static_cast<std::size_t>(one_based - 1); };
  std::vector<std::int64_t> start(static_cast<std::size_t>(n) + 1, 0);  // row i's first slot: start[i]
  for (std::size_t e = 0; e < irn.size(); ++e) {
    if (irn[e] == jcn[e]) continue;
    ++start[row(irn[e]) + 1];
    ++start[row(jcn[e]) + 1];
  }
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) start[i + 1] += start[i];
  if (start.back() > std::numeric_limits<idx_t>::max()) {
    throw std::runtime_error("the pattern's " + std::to_string(start.back()) + " adjacencies exceed METIS's indices");
  }
  adjncy.assign(static_cast<std::size_t>(start.back()), 0);
  std::vector<std::int64_t> end(start.begin(), start.end() - 1);  // row i's next free slot
  for (std::size_t e = 0; e < irn.size(); ++e) {
    if (irn[e] == jcn[e]) continue;
    adjncy[static_cast<std::size_t>(end[row(irn[e])]++)] = jcn[e] - 1;
    adjncy[static_cast<std::size_t>(end[row(jcn[e])]++)] = irn[e] - 1;
  }
  // Sort and deduplicate each row, compacting in place (a row's kept entries never pass its start).
  xadj.assign(static_cast<std::size_t>(n) + 1, 0);
  std::size_t out = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
    const auto b = adjncy.begin() + start[i];
    const auto e = adjncy.begin() + end[i];
    std::sort(b, e);
    const auto last = std::unique(b, e);
    xadj[i] = static_cast<idx_t>(out);
    for (auto it = b; it != last; ++it) adjncy[out++] = *it;
  }
  xadj[static_cast<std::size_t>(n)] = static_cast<idx_t>(out);
  adjncy.resize(out);
}

}  // namespace

std::vector<int> nested_dissection_order(int n, const std::vector<int>& irn, const std::vector<int>& jcn) {
  std::vector<idx_t> xadj, adjncy;
  symmetric_adjacency(n, irn, jcn, xadj, adjncy);
  std::vector<int> order(static_cast<std::size_t>(n));
  if (adjncy.empty()) {  // no off-diagonal entry (or n = 0): nothing fills; METIS refuses such graphs
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
  // METIS: iperm[i] is the 0-based position of vertex i in the elimination; MUMPS wants it 1-based.
  for (int i = 0; i < n; ++i) order[static_cast<std::size_t>(i)] = iperm[static_cast<std::size_t>(i)] + 1;
  return order;
}

}  // namespace adamss::solver
