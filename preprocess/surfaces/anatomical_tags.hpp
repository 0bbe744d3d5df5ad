#pragma once
// Anatomical node tags and the long axis of a ventricular mesh with cavities (issue 20 item 2),
// from what the mesh already knows: the label-pair surfaces ("surface:A-B") and the cavities with
// their lids. For the cavities NAME (label L) of the request and the solid labels S:
//   NAME_endocardium   the nodes of surface:s-L for every s in S (the cavity's wall)
//   NAME_rim           the nodes of the cavity's lid triangles: the rims of its openings (the
//                      valve rings of an image with valve caps, the base cut of a truncated LV)
//   epicardium         the nodes of surface:s-0 for every s in S (myocardium against background)
//   apex               one node: of the epicardium, the farthest from the base along the long axis
//                      (of equally far nodes, within 1e-9 m, the nearest to the axis)
// and mesh.attributes["long_axis"] = "px,py,pz,dx,dy,dz" (m; unit direction from the apex to the
// base) with ["long_axis_source"] = "lid of cavity NAME": the axis through the centre of the
// lid of cavity "lv" (else the first cavity with a lid), normal to it, as
// solver/geometry/long_axis.hpp estimates it. A tag name that the mesh already has (e.g. a plane
// tag) is left as it is and reported.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "preprocess/mesh/mesh.hpp"
#include "preprocess/surfaces/cavities.hpp"

namespace adamss::preprocess {

/// A long axis from a cavity lid: the lid's vector area A points into the cavity, towards the
/// apex, so the direction (apex to base) is l = -A / |A|, through the area-weighted lid centre.
struct LidAxis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       ///< m
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  ///< unit, apex to base
  std::string cavity;                                    ///< the cavity whose lid gave it
};

/// The axis of the lid of cavity "lv", else of the first cavity (in name order) with a lid of
/// non-zero area; nullopt when there is none. The one estimate behind the mesh attribute
/// long_axis and the solver's run-time axis (solver/geometry/long_axis.hpp).
[[nodiscard]] std::optional<LidAxis> lid_long_axis(const Mesh& mesh);

struct AnatomicalTagReport {
  std::vector<std::string> added;    ///< tag names added
  std::vector<std::string> skipped;  ///< names the mesh already had
  bool long_axis = false;            ///< the axis (and the apex) could be estimated
};

/// Adds the tags above to `mesh` (cavities already built). `solid_labels` are the meshed labels.
AnatomicalTagReport add_anatomical_tags(Mesh& mesh, const std::vector<CavitySpec>& cavities,
                                        const std::vector<std::int32_t>& solid_labels);

}  // namespace adamss::preprocess
