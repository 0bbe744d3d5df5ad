#include "preprocess/meshers/weak_node_repair.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "preprocess/mesh/face_table.hpp"

namespace adamss::preprocess {
namespace {

constexpr std::int64_t kNone = -1;

/// across[4 e + k]: the element on the far side of local face k (kTetFaces) of element e, or kNone
/// (from the shared face table: faces of two elements sit next to each other).
std::vector<std::int64_t> face_neighbours(const Mesh& mesh) {
  const std::vector<FaceRecord> faces = sorted_face_records(mesh);
  std::vector<std::int64_t> across(4 * mesh.element_count(), kNone);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    if (faces[i].key != faces[i + 1].key) continue;
    const FaceRecord& a = faces[i];
    const FaceRecord& b = faces[i + 1];
    across[4 * std::size_t{a.element} + a.local] = b.element;
    across[4 * std::size_t{b.element} + b.local] = a.element;
  }
  return across;
}

/// One round: marks (removed[e] = true) every kept element holding a node in 1 .. min - 1 kept
/// elements; returns the number of such nodes.
std::size_t mark_weak(const Mesh& mesh, int min_elements, std::vector<bool>& removed) {
  std::vector<int> count(mesh.node_count(), 0);
  const std::size_t n = mesh.element_count();
  for (std::size_t e = 0; e < n; ++e) {
    if (removed[e]) continue;
    for (int j = 0; j < 4; ++j) ++count[static_cast<std::size_t>(mesh.element(e)[j])];
  }
  const auto weak = [&](Index v) {
    const int c = count[static_cast<std::size_t>(v)];
    return c > 0 && c < min_elements;
  };
  std::size_t weak_nodes = 0;
  for (const int c : count) weak_nodes += static_cast<std::size_t>(c > 0 && c < min_elements);
  for (std::size_t e = 0; e < n; ++e) {
    if (removed[e]) continue;
    const Index* t = mesh.element(e);
    if (weak(t[0]) || weak(t[1]) || weak(t[2]) || weak(t[3])) removed[e] = true;
  }
  return weak_nodes;
}

/// The label that takes each removed element's place (header comment); unused for kept ones.
std::vector<std::int32_t> replacement_labels(const Mesh& mesh, const std::vector<SurfacePatchFace>& patches,
                                             const std::vector<bool>& removed,
                                             const std::vector<std::int64_t>& across) {
  const std::size_t n = mesh.element_count();
  std::vector<std::map<std::int32_t, int>> votes(n);
  for (const SurfacePatchFace& f : patches)
    if (removed[f.element]) ++votes[f.element][f.label_out];
  std::vector<std::int32_t> label(n, 0);
  std::vector<bool> known(n, false);
  for (std::size_t e = 0; e < n; ++e) {
    if (votes[e].empty()) continue;
    // Most votes; std::map iterates labels in increasing order, so a tie keeps the smallest.
    const auto best = std::max_element(votes[e].begin(), votes[e].end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    label[e] = best->first;
    known[e] = true;
  }
  // Removed elements with no patch face of their own take a removed neighbour's label.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t e = 0; e < n; ++e) {
      if (!removed[e] || known[e]) continue;
      for (std::size_t k = 0; k < 4; ++k) {
        const std::int64_t o = across[4 * e + k];
        if (o == kNone || !removed[static_cast<std::size_t>(o)] || !known[static_cast<std::size_t>(o)]) continue;
        label[e] = label[static_cast<std::size_t>(o)];
        known[e] = changed = true;
        break;
      }
    }
  }
  return label;
}

/// The patches of the kept elements, with the faces the removal exposed (header comment).
std::vector<SurfacePatchFace> updated_patches(const Mesh& mesh, const std::vector<SurfacePatchFace>& patches,
                                              const std::vector<bool>& removed,
                                              const std::vector<std::int64_t>& across) {
  const std::vector<std::int32_t> repl = replacement_labels(mesh, patches, removed, across);
  std::vector<SurfacePatchFace> out;
  out.reserve(patches.size());
  // Patch faces of kept elements: unchanged unless the far side was removed (a solid-solid interface).
  std::vector<bool> has_patch(4 * mesh.element_count(), false);
  for (const SurfacePatchFace& f : patches) {
    if (removed[f.element]) continue;
    SurfacePatchFace g = f;
    std::array<Index, 3> key = f.nodes;
    std::sort(key.begin(), key.end());
    const Index* t = mesh.element(f.element);
    for (std::size_t k = 0; k < 4; ++k) {
      std::array<Index, 3> fk{t[kTetFaces[k][0]], t[kTetFaces[k][1]], t[kTetFaces[k][2]]};
      std::sort(fk.begin(), fk.end());
      if (fk != key) continue;
      has_patch[4 * f.element + k] = true;
      const std::int64_t o = across[4 * f.element + k];
      if (o != kNone && removed[static_cast<std::size_t>(o)]) g.label_out = repl[static_cast<std::size_t>(o)];
    }
    out.push_back(g);
  }
  // Faces between a kept element and a removed one of the same label: new surface.
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (removed[e]) continue;
    const Index* t = mesh.element(e);
    for (std::size_t k = 0; k < 4; ++k) {
      const std::int64_t o = across[4 * e + k];
      if (o == kNone || !removed[static_cast<std::size_t>(o)] || has_patch[4 * e + k]) continue;
      SurfacePatchFace f;
      f.nodes = {t[kTetFaces[k][0]], t[kTetFaces[k][1]], t[kTetFaces[k][2]]};  // outward of e
      f.element = static_cast<std::uint32_t>(e);
      f.label_in = mesh.labels[e];
      f.label_out = repl[static_cast<std::size_t>(o)];
      out.push_back(f);
    }
  }
  return out;
}

/// Drops the removed elements and the nodes left in none; renumbers the patches to match.
void compact(Mesh& mesh, std::vector<SurfacePatchFace>& patches, const std::vector<bool>& removed,
             WeakNodeReport& report) {
  const std::size_t n = mesh.element_count();
  std::vector<std::int64_t> new_element(n, kNone);
  std::vector<std::int64_t> new_node(mesh.node_count(), kNone);
  std::size_t kept = 0;
  for (std::size_t e = 0; e < n; ++e) {
    if (removed[e]) continue;
    new_element[e] = static_cast<std::int64_t>(kept++);
    for (int j = 0; j < 4; ++j) new_node[static_cast<std::size_t>(mesh.element(e)[j])] = 0;
  }
  Index next = 0;
  for (auto& v : new_node)
    if (v != kNone) v = next++;
  Eigen::Matrix3Xd nodes(3, next);
  for (std::size_t v = 0; v < new_node.size(); ++v)
    if (new_node[v] != kNone) nodes.col(new_node[v]) = mesh.nodes.col(static_cast<Eigen::Index>(v));
  std::vector<Index> connectivity;
  std::vector<std::int32_t> labels;
  connectivity.reserve(4 * kept);
  labels.reserve(kept);
  for (std::size_t e = 0; e < n; ++e) {
    if (removed[e]) continue;
    for (int j = 0; j < 4; ++j)
      connectivity.push_back(static_cast<Index>(new_node[static_cast<std::size_t>(mesh.element(e)[j])]));
    labels.push_back(mesh.labels[e]);
  }
  for (SurfacePatchFace& f : patches) {
    f.element = static_cast<std::uint32_t>(new_element[f.element]);
    for (Index& v : f.nodes) v = static_cast<Index>(new_node[static_cast<std::size_t>(v)]);
  }
  report.nodes_removed = mesh.node_count() - static_cast<std::size_t>(next);
  mesh.nodes = std::move(nodes);
  mesh.connectivity = std::move(connectivity);
  mesh.labels = std::move(labels);
}

}  // namespace

WeakNodeReport remove_weak_nodes(Mesh& mesh, std::vector<SurfacePatchFace>& patches, int min_elements, int max_rounds) {
  if (min_elements < 2 || min_elements > 4) {
    throw InputError("min_node_elements " + std::to_string(min_elements) +
                     ": give 2, 3 or 4 (every node in at least that many elements; 3 removes nodes in one or two)");
  }
  if (mesh.type != ElementType::Tet4 || mesh.has_fibres() || !mesh.node_tags.empty() || !mesh.cavities.empty())
    throw InputError("min_node_elements: only a bare Tet4 mesh (before fibres, tags and cavities) can be repaired");
  WeakNodeReport report;
  report.min_elements = min_elements;
  const std::size_t n = mesh.element_count();
  std::vector<bool> removed(n, false);
  double total = 0.0;
  for (std::size_t e = 0; e < n; ++e) total += std::abs(element_volume(mesh, e));
  for (int round = 0; round < max_rounds; ++round) {
    const std::size_t weak = mark_weak(mesh, min_elements, removed);
    if (weak == 0) break;
    report.weak_nodes += weak;
    ++report.rounds;
  }
  std::vector<bool> probe = removed;
  report.weak_nodes_left = mark_weak(mesh, min_elements, probe);
  for (std::size_t e = 0; e < n; ++e) {
    if (!removed[e]) continue;
    ++report.elements_removed;
    report.volume_removed_m3 += std::abs(element_volume(mesh, e));
  }
  if (report.elements_removed == n)
    throw NumericalError("min_node_elements " + std::to_string(min_elements) + " would remove every element");
  report.volume_fraction = total > 0.0 ? report.volume_removed_m3 / total : 0.0;
  if (report.elements_removed == 0) return report;
  patches = updated_patches(mesh, patches, removed, face_neighbours(mesh));
  compact(mesh, patches, removed, report);
  return report;
}

}  // namespace adamss::preprocess
