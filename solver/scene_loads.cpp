#include "solver/scene_loads.hpp"

namespace adamss::solver {

void build_loads(SceneNode& /*loads*/, Model& /*model*/, const std::filesystem::path& /*base*/) {}

}  // namespace adamss::solver
