#include "preprocess/mesh/open_edges.hpp"

#include <algorithm>
#include <cstdlib>

namespace adamss::preprocess {
namespace {

template <std::size_t K>
void add_edge_uses(const std::vector<std::array<Index, K>>& polys, std::vector<EdgeUse>& out) {
  for (const auto& p : polys) {
    for (std::size_t i = 0; i < K; ++i) {
      const Index a = p[i], b = p[(i + 1) % K];
      if (a == b) continue;  // the collapsed edge of a degenerate quad (a hex27 apex face) is no edge
      out.push_back(a < b ? EdgeUse{a, b, +1} : EdgeUse{b, a, -1});
    }
  }
}

}  // namespace

std::vector<EdgeUse> sorted_edge_uses(const std::vector<std::array<Index, 3>>& triangles,
                                      const std::vector<std::array<Index, 4>>& quads,
                                      const std::vector<std::array<Index, 3>>& lid) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * (triangles.size() + lid.size()) + 4 * quads.size());
  add_edge_uses(triangles, uses);
  add_edge_uses(quads, uses);
  add_edge_uses(lid, uses);
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.lo != y.lo ? x.lo < y.lo : (x.hi != y.hi ? x.hi < y.hi : x.sign < y.sign);
  });
  return uses;
}

std::vector<DirectedEdge> open_edges(const std::vector<EdgeUse>& sorted_uses) {
  const std::vector<EdgeUse>& uses = sorted_uses;
  std::vector<DirectedEdge> out;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    int net = 0;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) net += uses[j++].sign;
    for (int k = 0; k < std::abs(net); ++k)
      out.push_back(net > 0 ? DirectedEdge{uses[i].lo, uses[i].hi} : DirectedEdge{uses[i].hi, uses[i].lo});
    i = j;
  }
  return out;
}

}  // namespace adamss::preprocess
