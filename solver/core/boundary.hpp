#pragma once
// Boundary conditions of seed 000 sec. 2.6: fixation and control tags per particle
// and global axis.
//
// * fixed on axis c: the coordinate keeps its value at t = 0 and its velocity is 0;
// * displacement-controlled on axis c: x_c(t) = X_c + u(t), v_c(t) = u'(t) with X the
//   reference position and u a TimeCourse (m);
// * velocity-controlled on axis c: v_c(t) = w(t) (m/s); the position follows by
//   integration of the prescribed velocity.
// Fixed and controlled coordinates are removed from the equations of motion: the
// integrators compute accelerations for the free coordinates only and impose the
// constrained ones (the thesis sets the offset of a fixed coordinate to zero; its
// huge-mass trick for the implicit integrator is replaced by elimination there).
// A coordinate carries at most one condition; a second one is an InputError naming
// the node and axis.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "solver/core/region.hpp"
#include "solver/core/time_course.hpp"

namespace adamss::solver {

using preprocess::Index;

/// Bit mask of global axes: 1 = x, 2 = y, 4 = z. parse_axes("xz") == 5.
std::uint8_t parse_axes(const std::string& text, const std::string& what);

struct AxisControl {
  Index node = 0;
  int axis = 0;  ///< 0, 1, 2
  TimeCourse course;
  bool velocity = false;  ///< false: displacement u(t) (m); true: velocity w(t) (m/s)
  /// Equal for consecutive controls with equal courses (one boundary condition's nodes): the
  /// per-step loops evaluate each course once per run of equal ids.
  std::uint32_t course_id = 0;
};

class Constraints {
 public:
  Constraints() = default;
  explicit Constraints(std::size_t node_count) : mask_(node_count, 0) {}

  /// Fixes the axes in `axes` (bit mask) of `node`. `source` names the scene entry for messages.
  void fix(Index node, std::uint8_t axes, const std::string& source);
  /// Prescribes one axis of `node`.
  void control(Index node, int axis, const TimeCourse& course, bool velocity, const std::string& source);

  [[nodiscard]] bool constrained(Index node, int axis) const {
    return ((mask_[static_cast<std::size_t>(node)] >> axis) & 1U) != 0;
  }
  [[nodiscard]] const std::vector<std::uint8_t>& mask() const { return mask_; }
  [[nodiscard]] const std::vector<AxisControl>& controls() const { return controls_; }
  [[nodiscard]] std::size_t fixed_dof_count() const { return fixed_flat_.size(); }
  [[nodiscard]] std::size_t controlled_dof_count() const { return controls_.size(); }
  [[nodiscard]] std::size_t node_count() const { return mask_.size(); }

  /// Sets the constrained coordinates of (x, v) for time t: fixed ones to `x_fixed` and
  /// v = 0, displacement-controlled ones to X + u(t) and u'(t), velocity-controlled
  /// velocities to w(t). `x_ref` is the reference configuration X.
  void impose(Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& v, const Eigen::Matrix3Xd& x_ref, const Eigen::Matrix3Xd& x_fixed,
              double t) const;
  /// Only the velocity-controlled coordinates of impose(): v = w(t). (Symplectic Euler's
  /// mid-step call: the positions and the other velocities are set by the full impose after
  /// x += h v, which overwrites whatever that update did to them.)
  void impose_velocity_controls(Eigen::Matrix3Xd& v, double t) const;
  /// True if some coordinate is velocity-controlled.
  [[nodiscard]] bool has_velocity_controls() const { return velocity_controls_ > 0; }
  /// Sets the accelerations of constrained coordinates: 0 for fixed and displacement-
  /// controlled ones (their motion is imposed after the step), w'(t) for velocity-controlled ones.
  void constrain_acceleration(Eigen::Matrix3Xd& a, double t) const;

 private:
  std::vector<std::uint8_t> mask_;   // bit c: axis c constrained (fixed or controlled)
  std::vector<std::uint8_t> fixed_;  // bit c: axis c fixed (subset of mask_), per node, lazily sized
  std::vector<AxisControl> controls_;
  std::vector<std::int64_t> fixed_flat_;  // fixed coordinates as 3 node + axis (offsets into x.data())
  std::size_t velocity_controls_ = 0;
};

/// Nodes whose reference position lies in `region` (sorted). Throws InputError naming
/// `what` when none does.
std::vector<Index> select_nodes(const Eigen::Matrix3Xd& x_ref, const Region& region, const std::string& what);
/// Nodes of the mesh's node tag `tag`. InputError listing the tags the mesh has when missing or empty.
std::vector<Index> select_nodes_by_tag(const preprocess::Mesh& mesh, const std::string& tag, const std::string& what);
/// The rim of a cavity's openings: the nodes of the lid triangles of mesh cavity `cavity`, i.e. the
/// wall nodes around each valve or base opening (preprocess/surfaces/cavities.hpp: lid triangles
/// use only wall-loop nodes); on quadratic tetrahedra also the mid-edge nodes of the lid edges that
/// are mesh edges. Sorted. InputError naming `what` for an unknown cavity (listing the
/// mesh's cavities) or a cavity without openings.
std::vector<Index> select_cavity_rim(const preprocess::Mesh& mesh, const std::string& cavity, const std::string& what);
/// Node indices (0-based) read from a text file: integers separated by white space or commas,
/// '#' starts a comment. InputError naming the file and line for a missing file, a
/// non-integer or an index outside [0, node_count).
std::vector<Index> read_node_file(const std::string& path, std::size_t node_count, const std::string& what);

}  // namespace adamss::solver
