#include "preprocess/meshers/locality_order.hpp"

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <tuple>

namespace adamss::preprocess {

namespace {

/// The node graph in CSR form: the neighbours of node i are adj[start[i] .. start[i + 1]),
/// sorted and without i itself.
struct NodeGraph {
  std::vector<std::size_t> start;
  std::vector<Index> adj;
  [[nodiscard]] std::size_t degree(Index i) const {
    const auto u = static_cast<std::size_t>(i);
    return start[u + 1] - start[u];
  }
  /// The order nodes are visited and chosen in: fewer neighbours first, then the lower index.
  [[nodiscard]] bool before(Index a, Index b) const {
    return std::make_pair(degree(a), a) < std::make_pair(degree(b), b);
  }
};

NodeGraph node_graph(const Mesh& mesh) {
  const std::size_t nn = mesh.node_count(), ne = mesh.element_count();
  const int k = nodes_per_element(mesh.type);
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(ne * static_cast<std::size_t>(k * (k - 1)));
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = mesh.element(e);
    for (int a = 0; a < k; ++a) {
      for (int b = 0; b < k; ++b)
        if (n[a] != n[b]) pairs.emplace_back(n[a], n[b]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  NodeGraph g;
  g.start.assign(nn + 1, 0);
  g.adj.reserve(pairs.size());
  for (const auto& [a, b] : pairs) {
    ++g.start[static_cast<std::size_t>(a) + 1];
    g.adj.push_back(b);
  }
  for (std::size_t i = 0; i < nn; ++i) g.start[i + 1] += g.start[i];
  return g;
}

/// One breadth-first search from `root` over the nodes not yet numbered (`done`).
struct Levels {
  std::vector<Index> order;    ///< nodes in visiting order (neighbours by increasing degree, then index)
  int depth = 0;               ///< the last level's number
  std::size_t last_start = 0;  ///< where the last level begins in `order`
};

void bfs(const NodeGraph& g, Index root, const std::vector<char>& done, std::vector<int>& level,
         std::vector<Index>& scratch, Levels& out) {
  std::vector<Index>& order = out.order;
  order.clear();
  order.push_back(root);
  level[static_cast<std::size_t>(root)] = 0;
  for (std::size_t head = 0; head < order.size(); ++head) {
    const auto u = static_cast<std::size_t>(order[head]);
    scratch.clear();
    for (std::size_t p = g.start[u]; p < g.start[u + 1]; ++p) {
      const auto j = static_cast<std::size_t>(g.adj[p]);
      if (done[j] == 0 && level[j] < 0) {
        level[j] = level[u] + 1;
        scratch.push_back(g.adj[p]);
      }
    }
    std::sort(scratch.begin(), scratch.end(), [&](Index a, Index b) { return g.before(a, b); });
    order.insert(order.end(), scratch.begin(), scratch.end());
  }
  out.depth = level[static_cast<std::size_t>(order.back())];
  out.last_start = order.size() - 1;
  while (out.last_start > 0 && level[static_cast<std::size_t>(order[out.last_start - 1])] == out.depth)
    --out.last_start;
  for (const Index i : order) level[static_cast<std::size_t>(i)] = -1;  // ready for the next search
}

/// Reverse Cuthill-McKee: new_node[old]. Nodes of no element keep their order after the others.
std::vector<Index> rcm(const NodeGraph& g, const Mesh& mesh) {
  const std::size_t nn = mesh.node_count();
  std::vector<char> used(nn, 0), done(nn, 0);
  for (const Index i : mesh.connectivity) used[static_cast<std::size_t>(i)] = 1;
  std::vector<Index> by_degree(nn);
  std::iota(by_degree.begin(), by_degree.end(), Index{0});
  std::stable_sort(by_degree.begin(), by_degree.end(), [&](Index a, Index b) { return g.degree(a) < g.degree(b); });
  std::vector<int> level(nn, -1);
  std::vector<Index> cm, scratch;
  cm.reserve(nn);
  Levels best, trial;
  for (const Index start : by_degree) {
    if (done[static_cast<std::size_t>(start)] != 0 || used[static_cast<std::size_t>(start)] == 0) continue;
    // Pseudo-peripheral root (George & Liu): restart from a least-degree node of the last level
    // while that makes the level structure deeper.
    bfs(g, start, done, level, scratch, best);
    for (int pass = 0; pass < 16; ++pass) {
      const auto last = best.order.begin() + static_cast<std::ptrdiff_t>(best.last_start);
      const Index far = *std::min_element(last, best.order.end(), [&](Index a, Index b) { return g.before(a, b); });
      bfs(g, far, done, level, scratch, trial);
      if (trial.depth <= best.depth) break;
      std::swap(best, trial);
    }
    for (const Index i : best.order) {
      done[static_cast<std::size_t>(i)] = 1;
      cm.push_back(i);
    }
  }
  std::vector<Index> new_node(nn, -1);
  Index next = 0;
  for (auto it = cm.rbegin(); it != cm.rend(); ++it) new_node[static_cast<std::size_t>(*it)] = next++;
  for (std::size_t i = 0; i < nn; ++i)
    if (new_node[i] < 0) new_node[i] = next++;
  return new_node;
}

/// new_element[old]: elements sorted by (lowest, highest node, old index).
std::vector<Index> element_order(const Mesh& mesh) {
  const std::size_t ne = mesh.element_count();
  const int k = nodes_per_element(mesh.type);
  std::vector<std::tuple<Index, Index, Index>> key(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = mesh.element(e);
    const auto [lo, hi] = std::minmax_element(n, n + k);
    key[e] = {*lo, *hi, static_cast<Index>(e)};
  }
  std::sort(key.begin(), key.end());
  std::vector<Index> new_element(ne);
  for (std::size_t pos = 0; pos < ne; ++pos)
    new_element[static_cast<std::size_t>(std::get<2>(key[pos]))] = static_cast<Index>(pos);
  return new_element;
}

/// Columns of m moved: column old goes to to[old].
void permute_columns(Eigen::Matrix3Xd& m, const std::vector<Index>& to) {
  if (m.cols() == 0) return;
  Eigen::Matrix3Xd out(3, m.cols());
  for (Eigen::Index c = 0; c < m.cols(); ++c) out.col(to[static_cast<std::size_t>(c)]) = m.col(c);
  m = std::move(out);
}

void permute_elements(Mesh& mesh, const std::vector<Index>& to) {
  const std::size_t ne = mesh.element_count();
  const auto k = static_cast<std::size_t>(nodes_per_element(mesh.type));
  std::vector<Index> conn(mesh.connectivity.size());
  std::vector<std::int32_t> labels(mesh.labels.size());
  for (std::size_t e = 0; e < ne; ++e) {
    const auto t = static_cast<std::size_t>(to[e]);
    std::copy_n(mesh.connectivity.begin() + static_cast<std::ptrdiff_t>(e * k), k,
                conn.begin() + static_cast<std::ptrdiff_t>(t * k));
    if (!labels.empty()) labels[t] = mesh.labels[e];
  }
  mesh.connectivity = std::move(conn);
  mesh.labels = std::move(labels);
  permute_columns(mesh.fiber, to);
  permute_columns(mesh.sheet, to);
  permute_columns(mesh.normal, to);
  for (auto& [name, v] : mesh.cell_scalars) {
    if (static_cast<std::size_t>(v.size()) != ne) continue;
    Eigen::VectorXd out(v.size());
    for (std::size_t e = 0; e < ne; ++e) out[to[e]] = v[static_cast<Eigen::Index>(e)];
    v = std::move(out);
  }
}

void renumber_nodes(Mesh& mesh, const std::vector<Index>& to, std::vector<SurfacePatchFace>* patches) {
  permute_columns(mesh.nodes, to);
  const auto map = [&](Index& i) { i = to[static_cast<std::size_t>(i)]; };
  for (Index& i : mesh.connectivity) map(i);
  for (auto& [name, list] : mesh.node_tags) {
    for (Index& i : list) map(i);
    std::sort(list.begin(), list.end());
  }
  for (auto& [name, c] : mesh.cavities) {
    for (auto& f : c.faces) std::for_each(f.begin(), f.end(), map);
    for (auto& q : c.quads) std::for_each(q.begin(), q.end(), map);
    for (auto& l : c.lid) std::for_each(l.begin(), l.end(), map);
  }
  if (patches != nullptr)
    for (SurfacePatchFace& p : *patches) std::for_each(p.nodes.begin(), p.nodes.end(), map);
}

}  // namespace

LocalityOrder renumber_for_locality(Mesh& mesh, std::vector<SurfacePatchFace>* patches) {
  LocalityOrder out;
  out.new_node = rcm(node_graph(mesh), mesh);
  renumber_nodes(mesh, out.new_node, patches);
  out.new_element = element_order(mesh);  // by the nodes' new numbers
  permute_elements(mesh, out.new_element);
  if (patches != nullptr)
    for (SurfacePatchFace& p : *patches) p.element = static_cast<std::uint32_t>(out.new_element[p.element]);
  mesh.attributes["node_order"] = "rcm";
  return out;
}

double median_element_node_span(const Mesh& mesh) {
  const std::size_t ne = mesh.element_count();
  if (ne == 0) return 0.0;
  const int k = nodes_per_element(mesh.type);
  std::vector<Index> span(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const Index* n = mesh.element(e);
    const auto [lo, hi] = std::minmax_element(n, n + k);
    span[e] = *hi - *lo;
  }
  const auto mid = span.begin() + static_cast<std::ptrdiff_t>(ne / 2);
  std::nth_element(span.begin(), mid, span.end());
  return static_cast<double>(*mid);
}

}  // namespace adamss::preprocess
