#pragma once
// A boundary or interface triangle of a CGAL mesh (cgal_mesher.hpp, "Surface patches"): the
// faces cavities and label-pair node tags are built from on CGAL meshes.
#include <array>
#include <cstdint>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::preprocess {

struct SurfacePatchFace {
  std::array<Index, 3> nodes{};  ///< normal (b-a)x(c-a) points from label_in to label_out
  std::uint32_t element = 0;     ///< the element (label label_in) the face belongs to
  std::int32_t label_in = 0;
  std::int32_t label_out = 0;
};

}  // namespace adamss::preprocess
