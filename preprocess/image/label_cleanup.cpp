#include "preprocess/image/label_cleanup.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "common/error.hpp"

namespace adamss::preprocess {

namespace {

/// 6-connected components of the voxels where in[v] is set: comp[v] = component index (or -1),
/// and the voxel count of each component.
std::vector<std::int64_t> components(const Grid& g, const std::vector<char>& in, std::vector<std::int64_t>& comp) {
  const auto& d = g.dims;
  comp.assign(in.size(), -1);
  std::vector<std::int64_t> sizes;
  std::vector<std::int64_t> stack;
  const std::array<std::int64_t, 3> stride{1, d[0], d[0] * d[1]};
  for (std::size_t seed = 0; seed < in.size(); ++seed) {
    if (in[seed] == 0 || comp[seed] >= 0) continue;
    const auto id = static_cast<std::int64_t>(sizes.size());
    sizes.push_back(0);
    comp[seed] = id;
    stack.assign(1, static_cast<std::int64_t>(seed));
    while (!stack.empty()) {
      const std::int64_t v = stack.back();
      stack.pop_back();
      ++sizes.back();
      const std::array<std::int64_t, 3> ijk{v % d[0], (v / d[0]) % d[1], v / (d[0] * d[1])};
      for (std::size_t a = 0; a < 3; ++a) {
        for (const int step : {-1, 1}) {
          const std::int64_t n = ijk[a] + step;
          if (n < 0 || n >= d[a]) continue;
          const std::int64_t w = v + step * stride[a];
          const auto uw = static_cast<std::size_t>(w);
          if (in[uw] != 0 && comp[uw] < 0) {
            comp[uw] = id;
            stack.push_back(w);
          }
        }
      }
    }
  }
  return sizes;
}

/// Relabels every voxel of component `id` (in comp) with the label most frequent among the face
/// neighbours outside the component (ties: the smaller label; none: 0).
void relabel(LabelImage& im, const std::vector<std::int64_t>& comp, const std::vector<std::size_t>& voxels) {
  const auto& d = im.grid.dims;
  const std::array<std::int64_t, 3> stride{1, d[0], d[0] * d[1]};
  std::map<std::int32_t, std::int64_t> votes;
  const std::int64_t id = comp[voxels.front()];
  for (const std::size_t v : voxels) {
    const auto vi = static_cast<std::int64_t>(v);
    const std::array<std::int64_t, 3> ijk{vi % d[0], (vi / d[0]) % d[1], vi / (d[0] * d[1])};
    for (std::size_t a = 0; a < 3; ++a) {
      for (const int step : {-1, 1}) {
        const std::int64_t n = ijk[a] + step;
        if (n < 0 || n >= d[a]) continue;
        const auto w = static_cast<std::size_t>(vi + step * stride[a]);
        if (comp[w] != id) ++votes[im.labels[w]];
      }
    }
  }
  std::int32_t best = 0;
  std::int64_t count = -1;
  for (const auto& [label, n] : votes) {
    if (n > count) {
      best = label;
      count = n;
    }
  }
  for (const std::size_t v : voxels) im.labels[v] = best;
}

/// The voxels of each component, by component index.
std::vector<std::vector<std::size_t>> members(const std::vector<std::int64_t>& comp, std::size_t count) {
  std::vector<std::vector<std::size_t>> out(count);
  for (std::size_t v = 0; v < comp.size(); ++v)
    if (comp[v] >= 0) out[static_cast<std::size_t>(comp[v])].push_back(v);
  return out;
}

}  // namespace

LabelCleanupReport clean_labels(LabelImage& image, const std::vector<std::int32_t>& solid_labels) {
  LabelCleanupReport r;
  const Grid& g = image.grid;
  std::vector<char> solid(image.labels.size());
  for (std::size_t v = 0; v < solid.size(); ++v) {
    solid[v] =
        static_cast<char>(std::find(solid_labels.begin(), solid_labels.end(), image.labels[v]) != solid_labels.end());
  }
  std::vector<std::int64_t> comp;
  const std::vector<std::int64_t> sizes = components(g, solid, comp);
  if (sizes.empty()) throw InputError("clean labels: no voxel carries a solid label");
  r.solid_components = sizes.size();
  const auto keep = static_cast<std::int64_t>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  r.largest_voxels = sizes[static_cast<std::size_t>(keep)];
  const auto parts = members(comp, sizes.size());
  for (std::size_t c = 0; c < parts.size(); ++c) {
    if (static_cast<std::int64_t>(c) == keep) continue;
    relabel(image, comp, parts[c]);
    r.relabelled_voxels += static_cast<std::int64_t>(parts[c].size());
  }
  // Holes: background components away from the border.
  std::vector<char> background(image.labels.size());
  for (std::size_t v = 0; v < background.size(); ++v) background[v] = static_cast<char>(image.labels[v] == 0);
  const std::vector<std::int64_t> bsizes = components(g, background, comp);
  std::vector<char> touches(bsizes.size(), 0);
  const auto& d = g.dims;
  for (std::int64_t k = 0; k < d[2]; ++k) {
    for (std::int64_t j = 0; j < d[1]; ++j) {
      for (std::int64_t i = 0; i < d[0]; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == d[0] - 1 || j == d[1] - 1 || k == d[2] - 1;
        const std::int64_t c = comp[g.linear(i, j, k)];
        if (border && c >= 0) touches[static_cast<std::size_t>(c)] = 1;
      }
    }
  }
  const auto holes = members(comp, bsizes.size());
  for (std::size_t c = 0; c < holes.size(); ++c) {
    if (touches[c] != 0) continue;
    relabel(image, comp, holes[c]);
    ++r.holes;
    r.filled_voxels += static_cast<std::int64_t>(holes[c].size());
  }
  return r;
}

}  // namespace adamss::preprocess
