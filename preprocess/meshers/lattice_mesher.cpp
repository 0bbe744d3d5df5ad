#include "preprocess/meshers/lattice_mesher.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"

namespace adamss::preprocess {
namespace {

// Voxel corners are addressed by a bit code: bit 0 = +x, bit 1 = +y, bit 2 = +z.
using Tet = std::array<int, 4>;

Eigen::Vector3i corner(int code) {
  return {code & 1, (code >> 1) & 1, (code >> 2) & 1};
}

int orientation(const Tet& t) {
  const Eigen::Vector3i a = corner(t[0]);
  const Eigen::Vector3i b = corner(t[1]) - a, c = corner(t[2]) - a, d = corner(t[3]) - a;
  return b.dot(c.cross(d));
}

/// Makes the tet positively oriented in index space (swaps two vertices if needed).
Tet oriented(Tet t) {
  if (orientation(t) < 0) std::swap(t[1], t[2]);
  return t;
}

std::vector<Tet> kuhn_six() {
  std::vector<Tet> out;
  std::array<int, 3> axes{0, 1, 2};
  do {
    const int a = 1 << axes[0], b = a | (1 << axes[1]);
    out.push_back(oriented({0, a, b, 7}));
  } while (std::next_permutation(axes.begin(), axes.end()));
  return out;
}

std::vector<Tet> five_even() {
  // Central tet on the even-parity corners 0, 3, 5, 6; a corner tet at each odd corner.
  return {oriented({0, 3, 5, 6}), oriented({1, 0, 3, 5}), oriented({2, 0, 3, 6}), oriented({4, 0, 5, 6}),
          oriented({7, 3, 5, 6})};
}

std::vector<Tet> reflect(const std::vector<Tet>& tets, int mask) {
  std::vector<Tet> out;
  out.reserve(tets.size());
  for (const Tet& t : tets) out.push_back(oriented({t[0] ^ mask, t[1] ^ mask, t[2] ^ mask, t[3] ^ mask}));
  return out;
}

/// The eight split templates of a topology, indexed by the voxel's reflection/parity class.
std::array<std::vector<Tet>, 8> templates(Topology t) {
  std::array<std::vector<Tet>, 8> out;
  for (int cls = 0; cls < 8; ++cls) {
    switch (t) {
      case Topology::Tet6:
        out[static_cast<std::size_t>(cls)] = kuhn_six();
        break;
      case Topology::Tet6m:
        out[static_cast<std::size_t>(cls)] = reflect(kuhn_six(), cls);
        break;
      case Topology::Tet5m:
        out[static_cast<std::size_t>(cls)] = reflect(five_even(), cls);
        break;
      case Topology::Tet5: {
        const int parity = ((cls & 1) + ((cls >> 1) & 1) + ((cls >> 2) & 1)) & 1;
        out[static_cast<std::size_t>(cls)] = parity ? reflect(five_even(), 1) : five_even();
        break;
      }
      default:
        break;
    }
  }
  return out;
}

struct Box {
  std::array<std::int64_t, 3> lo{std::numeric_limits<std::int64_t>::max(), std::numeric_limits<std::int64_t>::max(),
                                 std::numeric_limits<std::int64_t>::max()};
  std::array<std::int64_t, 3> hi{-1, -1, -1};
};

std::string describe_labels(const LabelImage& image) {
  std::ostringstream os;
  bool first = true;
  for (const auto& [label, count] : image.histogram()) {
    os << (first ? "" : ", ") << label << " (" << count << " voxels)";
    first = false;
  }
  return os.str();
}

/// Marks the voxels carrying a solid label (solid[v] = 1), grows box around them and returns
/// their number; InputError listing the labels present when there is none.
std::size_t mark_solid(const LabelImage& image, const LatticeMeshOptions& options, std::vector<std::uint8_t>& solid,
                       Box& box) {
  const Grid& g = image.grid;
  std::size_t n_solid = 0;
  for (std::int64_t k = 0; k < g.dims[2]; ++k) {
    for (std::int64_t j = 0; j < g.dims[1]; ++j) {
      for (std::int64_t i = 0; i < g.dims[0]; ++i) {
        const std::size_t v = g.linear(i, j, k);
        if (std::find(options.solid_labels.begin(), options.solid_labels.end(), image.labels[v]) ==
            options.solid_labels.end())
          continue;
        solid[v] = 1;
        ++n_solid;
        const std::array<std::int64_t, 3> ijk{i, j, k};
        for (int a = 0; a < 3; ++a) {
          box.lo[static_cast<std::size_t>(a)] =
              std::min(box.lo[static_cast<std::size_t>(a)], ijk[static_cast<std::size_t>(a)]);
          box.hi[static_cast<std::size_t>(a)] =
              std::max(box.hi[static_cast<std::size_t>(a)], ijk[static_cast<std::size_t>(a)]);
        }
      }
    }
  }
  if (n_solid == 0) {
    std::ostringstream os;
    os << "--solid: no voxel carries the solid label(s) ";
    for (std::size_t i = 0; i < options.solid_labels.size(); ++i) os << (i ? "," : "") << options.solid_labels[i];
    os << "; labels present: " << describe_labels(image);
    throw InputError(os.str());
  }
  return n_solid;
}

/// The corner lattice over the solid bounding box: corner (a, b, c) sits at voxel index
/// (a - 1/2, b - 1/2, c - 1/2); node_of holds the node of each used corner, -1 elsewhere.
struct CornerLattice {
  Box box;
  std::array<std::int64_t, 3> cd{};
  std::vector<Index> node_of;
  [[nodiscard]] std::size_t id(std::int64_t a, std::int64_t b, std::int64_t c) const {
    return static_cast<std::size_t>((a - box.lo[0]) + cd[0] * ((b - box.lo[1]) + cd[1] * (c - box.lo[2])));
  }
  /// Node of corner c (bit code) of voxel (i, j, k).
  [[nodiscard]] Index node(std::int64_t i, std::int64_t j, std::int64_t k, int c) const {
    return node_of[id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
  }
};

/// Numbers the corners of the solid voxels in lattice order (x fastest), which keeps the node
/// numbering deterministic and spatially coherent. Returns the lattice and the node count.
CornerLattice number_corners(const Grid& g, const std::vector<std::uint8_t>& solid, const Box& box, Index& n_nodes) {
  CornerLattice lat;
  lat.box = box;
  lat.cd = {box.hi[0] - box.lo[0] + 2, box.hi[1] - box.lo[1] + 2, box.hi[2] - box.lo[2] + 2};
  lat.node_of.assign(static_cast<std::size_t>(lat.cd[0] * lat.cd[1] * lat.cd[2]), -1);
  for (std::int64_t k = box.lo[2]; k <= box.hi[2]; ++k) {
    for (std::int64_t j = box.lo[1]; j <= box.hi[1]; ++j) {
      for (std::int64_t i = box.lo[0]; i <= box.hi[0]; ++i) {
        if (!solid[g.linear(i, j, k)]) continue;
        for (int c = 0; c < 8; ++c) lat.node_of[lat.id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] = 0;
      }
    }
  }
  n_nodes = 0;
  for (Index& id : lat.node_of) {
    if (id == 0) {
      id = n_nodes++;
    } else {
      id = -1;  // untouched corners stay -1 (the marker 0 was only "used")
    }
  }
  return lat;
}

/// World positions of the used corners.
void place_corner_nodes(const Grid& g, const CornerLattice& lat, Index n_nodes, Mesh& mesh) {
  const Box& box = lat.box;
  mesh.nodes.resize(3, n_nodes);
  for (std::int64_t c = box.lo[2]; c <= box.hi[2] + 1; ++c) {
    for (std::int64_t b = box.lo[1]; b <= box.hi[1] + 1; ++b) {
      for (std::int64_t a = box.lo[0]; a <= box.hi[0] + 1; ++a) {
        const Index id = lat.node_of[lat.id(a, b, c)];
        if (id < 0) continue;
        mesh.nodes.col(id) = g.to_world(
            Eigen::Vector3d(static_cast<double>(a) - 0.5, static_cast<double>(b) - 0.5, static_cast<double>(c) - 0.5));
      }
    }
  }
}

/// The elements of one solid voxel with corner nodes cn (bit code order) and label `label`: one
/// hexahedron in VTK order, or the voxel class's tetrahedra; flip mirrors each element.
void emit_voxel(const std::array<Index, 8>& cn, const std::vector<Tet>& tets, bool flip, std::int32_t label,
                Mesh& mesh) {
  if (mesh.type == ElementType::Hex8) {
    std::array<Index, 8> h{};
    for (int a = 0; a < 8; ++a)
      h[static_cast<std::size_t>(a)] = cn[static_cast<std::size_t>(kHexCornerCode[static_cast<std::size_t>(a)])];
    if (flip) {  // mirror the VTK ordering: swap 1<->3 and 5<->7
      std::swap(h[1], h[3]);
      std::swap(h[5], h[7]);
    }
    mesh.connectivity.insert(mesh.connectivity.end(), h.begin(), h.end());
    mesh.labels.push_back(label);
    return;
  }
  for (const Tet& t : tets) {
    std::array<Index, 4> tn{cn[static_cast<std::size_t>(t[0])], cn[static_cast<std::size_t>(t[1])],
                            cn[static_cast<std::size_t>(t[2])], cn[static_cast<std::size_t>(t[3])]};
    if (flip) std::swap(tn[1], tn[2]);
    mesh.connectivity.insert(mesh.connectivity.end(), tn.begin(), tn.end());
    mesh.labels.push_back(label);
  }
}

}  // namespace

Topology parse_topology(const std::string& name) {
  if (name == "hex") return Topology::Hex;
  if (name == "tet5") return Topology::Tet5;
  if (name == "tet5m") return Topology::Tet5m;
  if (name == "tet6") return Topology::Tet6;
  if (name == "tet6m") return Topology::Tet6m;
  if (name == "cgal") return Topology::Cgal;
  throw InputError("--topology: unknown topology '" + name + "' (valid: hex, tet5, tet5m, tet6, tet6m, cgal)");
}

const char* topology_name(Topology t) {
  switch (t) {
    case Topology::Hex:
      return "hex";
    case Topology::Tet5:
      return "tet5";
    case Topology::Tet5m:
      return "tet5m";
    case Topology::Tet6:
      return "tet6";
    case Topology::Tet6m:
      return "tet6m";
    case Topology::Cgal:
      return "cgal";
  }
  return "?";
}

int elements_per_voxel(Topology t) {
  switch (t) {
    case Topology::Hex:
      return 1;
    case Topology::Tet5:
    case Topology::Tet5m:
      return 5;
    case Topology::Tet6:
    case Topology::Tet6m:
      return 6;
    case Topology::Cgal:
      return 0;
  }
  return 0;
}

Mesh mesh_lattice(const LabelImage& image, const LatticeMeshOptions& options) {
  if (options.topology == Topology::Cgal) {
    throw InputError("mesh_lattice: 'cgal' is not a lattice topology");
  }
  if (options.solid_labels.empty()) throw InputError("--solid: no solid label given");
  const Grid& g = image.grid;
  std::vector<std::uint8_t> solid(image.labels.size(), 0);
  Box box;
  const std::size_t n_solid = mark_solid(image, options, solid, box);
  const int per_voxel = elements_per_voxel(options.topology);
  const int npe = options.topology == Topology::Hex ? 8 : 4;
  if (n_solid * static_cast<std::size_t>(per_voxel) > static_cast<std::size_t>(std::numeric_limits<Index>::max())) {
    throw InputError("mesh_lattice: " + std::to_string(n_solid) + " solid voxels exceed the element index range");
  }
  Index n_nodes = 0;
  const CornerLattice lat = number_corners(g, solid, box, n_nodes);

  Mesh mesh;
  mesh.type = options.topology == Topology::Hex ? ElementType::Hex8 : ElementType::Tet4;
  place_corner_nodes(g, lat, n_nodes, mesh);

  // A negative affine determinant mirrors the lattice: flip every element.
  const bool flip = g.index_to_world.topLeftCorner<3, 3>().determinant() < 0.0;
  const auto tets = templates(options.topology);
  mesh.connectivity.reserve(n_solid * static_cast<std::size_t>(per_voxel * npe));
  mesh.labels.reserve(n_solid * static_cast<std::size_t>(per_voxel));
  for (std::int64_t k = box.lo[2]; k <= box.hi[2]; ++k) {
    for (std::int64_t j = box.lo[1]; j <= box.hi[1]; ++j) {
      for (std::int64_t i = box.lo[0]; i <= box.hi[0]; ++i) {
        const std::size_t v = g.linear(i, j, k);
        if (!solid[v]) continue;
        std::array<Index, 8> cn{};
        for (int c = 0; c < 8; ++c) cn[static_cast<std::size_t>(c)] = lat.node(i, j, k, c);
        const int cls = static_cast<int>((i & 1) | ((j & 1) << 1) | ((k & 1) << 2));
        emit_voxel(cn, tets[static_cast<std::size_t>(cls)], flip, image.labels[v], mesh);
      }
    }
  }

  const Eigen::Vector3d h = g.spacing();
  mesh.voxel_size_m = h.minCoeff();
  mesh.attributes["topology"] = topology_name(options.topology);
  return mesh;
}

}  // namespace adamss::preprocess
