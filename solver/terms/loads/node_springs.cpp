#include "solver/terms/loads/node_springs.hpp"

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "solver/terms/loads/support_term.hpp"

namespace adamss::solver {

std::string NodeSpringKernel::describe() const {
  std::ostringstream os;
  os << nodes.size() << " nodes, axes ";
  for (int c = 0; c < 3; ++c)
    if (axes[c] != 0.0) os << "xyz"[c];
  os << ", k " << stiffness << " N/m, c " << damping << " N s/m per node (total k "
     << stiffness * static_cast<double>(nodes.size()) << " N/m)";
  return os.str();
}

std::unique_ptr<ForceTerm> make_node_spring_term(const std::string& group, const std::vector<Index>& nodes,
                                                 const Eigen::Matrix3Xd& x_ref, std::uint8_t axes, double stiffness,
                                                 double damping) {
  if (nodes.empty()) throw InputError(group + ": no nodes selected for the springs");
  if ((axes & 7U) == 0) throw InputError(group + ": the springs need at least one axis");
  if (!std::isfinite(stiffness) || !std::isfinite(damping) || stiffness < 0.0 || damping < 0.0)
    throw InputError(group + ": spring stiffness and damping must be finite and >= 0");
  if (stiffness == 0.0 && damping == 0.0) throw InputError(group + ": give a spring stiffness or a damping > 0");
  NodeSpringKernel k;
  k.group = group;
  k.nodes = nodes;
  k.stiffness = stiffness;
  k.damping = damping;
  for (int c = 0; c < 3; ++c) k.axes[c] = ((axes >> c) & 1U) != 0 ? 1.0 : 0.0;
  k.x0.resize(3, static_cast<Eigen::Index>(nodes.size()));
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i] < 0 || nodes[i] >= x_ref.cols())
      throw InputError(group + ": node " + std::to_string(nodes[i]) + " is outside the mesh");
    k.x0.col(static_cast<Eigen::Index>(i)) = x_ref.col(nodes[i]);
  }
  return std::make_unique<SupportTerm<NodeSpringKernel>>(std::move(k));
}

}  // namespace adamss::solver
