#pragma once
// The assembled mass-spring system (seed 000 sec. 2.3) and its state.
//
// A Model owns what a scene asked for and nothing else: the particles (reference
// positions X, Voronoi masses m of eq. 2.3), the force terms the scene named, the
// boundary conditions, and the named probes and surfaces whose values are reported.
// The equations of motion are M a = f(x, v, t) (eqs. 2.121-2.126) with a diagonal M.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/boundary.hpp"
#include "solver/core/force_term.hpp"
#include "solver/geometry/long_axis.hpp"

namespace adamss::solver {

/// Positions (m), velocities (m/s), time (s) of every particle; 3 x n.
struct State {
  Eigen::Matrix3Xd x;
  Eigen::Matrix3Xd v;
  double t = 0.0;
};

/// A named point whose position is reported (the particle nearest to a given point).
struct Probe {
  std::string name;
  Index node = 0;
};

/// Something with a volume to report over time (a cavity), evaluated on the positions.
class VolumeMonitor {
 public:
  virtual ~VolumeMonitor() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  [[nodiscard]] virtual double volume(const Eigen::Matrix3Xd& x) const = 0;  ///< m^3
  [[nodiscard]] virtual double pressure(double t) const = 0;                 ///< Pa (0 if none applied)
  /// The cardiac phase of a cavity with a circulation ("filling", "ejection", ...); "" otherwise.
  [[nodiscard]] virtual std::string phase() const { return {}; }
  /// Extra globals.csv columns of the cavity (written as NAME_column after its volume and
  /// pressure): names fixed for the run, values of the last accepted step.
  [[nodiscard]] virtual std::vector<std::string> column_names() const { return {}; }
  [[nodiscard]] virtual std::vector<double> column_values() const { return {}; }
  /// Beat metrics known to the cavity (a circulation's valve-event values, SI, summary.json
  /// keys); empty by default, when summary.json falls back to the volume extrema.
  [[nodiscard]] virtual std::vector<std::pair<std::string, double>> metrics() const { return {}; }
  /// The same per completed beat (summary.json `per_beat`); empty by default.
  [[nodiscard]] virtual std::vector<std::vector<std::pair<std::string, double>>> beat_metrics() const { return {}; }
};

/// The particles of one `boundary:` entry of a scene (for reaction forces in the summary).
struct BoundaryGroup {
  std::string name;  ///< the entry's key path, e.g. "boundary[1]"
  std::vector<Index> nodes;
  /// The entry's spring term (solver/terms/loads/node_springs.hpp) for `spring:` entries, whose
  /// reaction is that term's force on the body; null for fixed and controlled nodes, whose
  /// reaction is minus the sum of every term's force there.
  const ForceTerm* springs = nullptr;
};

struct Model {
  std::shared_ptr<const preprocess::Mesh> mesh;
  Eigen::Matrix3Xd x_ref;  ///< reference positions X (m)
  Eigen::VectorXd mass;    ///< kg per particle
  std::vector<std::unique_ptr<ForceTerm>> terms;
  Constraints constraints;
  std::vector<Probe> probes;
  std::vector<std::unique_ptr<VolumeMonitor>> cavities;
  std::vector<BoundaryGroup> boundary_groups;  ///< one per scene boundary entry, in scene order
  /// The ventricle's long axis for the cardiac-frame strain outputs (output.long_axis, else
  /// estimated from a cavity lid; solver/geometry/long_axis.hpp); none for a mesh without cavities.
  std::optional<LongAxis> long_axis;

  [[nodiscard]] std::size_t node_count() const { return static_cast<std::size_t>(x_ref.cols()); }
};

/// Kinetic energy 1/2 sum m_i |v_i|^2 (J).
[[nodiscard]] double kinetic_energy(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& v);

/// Exact volume of element e at positions x (m^3): tetrahedron (x1-x0).((x2-x0)x(x3-x0))/6,
/// hexahedron the trilinear volume (2x2x2 Gauss on det J, exact).
[[nodiscard]] double element_volume_at(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, std::size_t e);

/// Sum of the signed element volumes of the mesh at positions x (m^3).
[[nodiscard]] double total_volume(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x);

/// Signed-volume test of element e at positions x (m^3), eq. 2.154: for a tetrahedron its signed
/// volume (x1-x0).((x2-x0)x(x3-x0))/6; for a hexahedron the smallest of the eight corner
/// parallelepipeds det(x_nx - x_a, x_ny - x_a, x_nz - x_a), oriented so that it equals the volume of a
/// parallelepiped element (any corner turning inside out makes it <= 0). Corners with a collapsed
/// edge (repeated node indices of a degenerate hexahedron) are skipped; 0 if every corner is. For a
/// quadratic tetrahedron: the least det(dx/dr) / 6 over its 4 law and 5 volume quadrature points.
[[nodiscard]] double element_signed_volume_check(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x,
                                                 std::size_t e);

/// The first element (lowest index) whose element_signed_volume_check at x is not positive
/// (inverted or flat); none if every element is sound.
[[nodiscard]] std::optional<std::size_t> first_inverted_element(const preprocess::Mesh& mesh,
                                                                const Eigen::Matrix3Xd& x);

}  // namespace adamss::solver
