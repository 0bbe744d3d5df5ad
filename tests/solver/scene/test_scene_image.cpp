// `mesh: {image: ...}` (solver/scene/scene_image_mesh.hpp): a scene meshes a label image itself,
// caches it by the image's bytes and options, and selects the rims of the cavity openings
// (`select: {cavity_rim: NAME}`).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "common/error.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "preprocess/image/phantom.hpp"
#include "preprocess/mesh/element_volume.hpp"
#include "scene_fixtures.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;
namespace fs = std::filesystem;

namespace {

/// The lv phantom at 2 mm written as a NIfTI label image (once per test binary).
fs::path lv_image() {
  static const fs::path p = [] {
    const fs::path dir = fs::temp_directory_path() / ("adamss-test-scene-image-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    preprocess::PhantomOptions o;
    o.voxel_size_m = 2e-3;
    const fs::path file = dir / "lv_labels.nii.gz";
    preprocess::write_label_image(file, preprocess::make_phantom("lv", o).image);
    return file;
  }();
  return p;
}

/// A static scene on the image with MESH_EXTRA keys and BOUNDARY selection.
std::string scene(const std::string& mesh_extra, const std::string& select = "{cavity_rim: lv}") {
  return "name: t\nmesh: {image: " + lv_image().string() + mesh_extra +
         "}\n"
         "materials:\n  - {name: m, labels: [1], density: 1000 kg/m^3, terms: [{volume: {p: 1 kPa, "
         "distribution: isotropic}}]}\n"
         "boundary:\n  - {select: " +
         select + ", fix: xyz}\nintegrator: {type: static, dt: 0.1 s}\nrun: {t_end: 1 s}\n";
}

const char* kTet = ", cavities: {lv: 2}, topology: tet6m";

}  // namespace

TEST(SceneImage, MeshesTheImageWithItsCavityAndCachesIt) {
  const auto a = test::load_scene(scene(kTet));
  const preprocess::Mesh& m = *a.model.mesh;
  EXPECT_EQ(m.type, preprocess::ElementType::Tet4);
  ASSERT_EQ(m.cavities.count("lv"), 1u);
  EXPECT_TRUE(m.cavities.at("lv").closed);
  EXPECT_NE(a.mesh_source.find("mesh-image-lv_labels-tet6m-"), std::string::npos) << a.mesh_source;
  EXPECT_TRUE(fs::exists(a.mesh_source));
  // The cavity at rest is the image's label-2 region: the voxel count times 8 mm^3, exactly,
  // because the lattice mesh's wall follows voxel faces and the lid lies on the cut plane.
  preprocess::PhantomOptions o;
  o.voxel_size_m = 2e-3;
  const auto img = preprocess::make_phantom("lv", o).image;
  const auto n2 = std::count(img.labels.begin(), img.labels.end(), preprocess::kLvCavity);
  EXPECT_NEAR(m.cavities.at("lv").volume_m3, static_cast<double>(n2) * 8e-9, 1e-12);
  // Loaded again: the cached file, the same mesh.
  const auto b = test::load_scene(scene(kTet));
  EXPECT_EQ(b.mesh_source, a.mesh_source);
  EXPECT_EQ(b.model.mesh->nodes, m.nodes);
  // Another option is another file.
  const auto c = test::load_scene(scene(", cavities: {lv: 2}, topology: hex"));
  EXPECT_NE(c.mesh_source, a.mesh_source);
  EXPECT_EQ(c.model.mesh->type, preprocess::ElementType::Hex8);
}

TEST(SceneImage, TheCavityRimIsTheLidBoundaryAndIsFixed) {
  const auto s = test::load_scene(scene(kTet));
  const preprocess::Mesh& m = *s.model.mesh;
  std::vector<preprocess::Index> rim;
  for (const auto& t : m.cavities.at("lv").lid) rim.insert(rim.end(), t.begin(), t.end());
  std::sort(rim.begin(), rim.end());
  rim.erase(std::unique(rim.begin(), rim.end()), rim.end());
  ASSERT_GT(rim.size(), 8u);
  // The phantom's cavity is open at the top of its lattice (z = 4 mm at 2 mm voxels): every rim
  // node lies on the highest plane of the cavity wall and is fixed on all three axes.
  double ztop = -1.0;
  for (const auto& f : m.cavities.at("lv").faces)
    for (const auto n : f) ztop = std::max(ztop, m.nodes(2, n));
  EXPECT_NEAR(ztop, 4e-3, 1e-12);
  for (const auto n : rim) {
    EXPECT_NEAR(m.nodes(2, n), ztop, 1e-12);
    EXPECT_TRUE(s.model.constraints.constrained(n, 0) && s.model.constraints.constrained(n, 2));
  }
  ASSERT_EQ(s.model.boundary_groups.size(), 1u);
  EXPECT_EQ(s.model.boundary_groups[0].nodes, rim);
}

TEST(SceneImage, ErrorsNameTheKey) {
  EXPECT_NE(test::scene_error("name: t\nmesh: {image: /nonexistent/x.nii.gz}\nmaterials: []\n"
                              "integrator: {type: static, dt: 0.1 s}\nrun: {t_end: 1 s}\n")
                .find("mesh.image: label image '/nonexistent/x.nii.gz' does not exist"),
            std::string::npos);
  EXPECT_NE(
      test::scene_error(scene(", topology: hex, cgal: {cell_size: 3 mm}")).find("mesh.cgal: only with topology: cgal"),
      std::string::npos);
  EXPECT_NE(test::scene_error(scene(", helix_endo: 50 deg")).find("mesh.helix_endo: only with fibres: rule"),
            std::string::npos);
  EXPECT_NE(test::scene_error(scene(", helix_septum_rv: 20 deg")).find("mesh.helix_septum_rv: only with fibres: rule"),
            std::string::npos);
  EXPECT_NE(test::scene_error(scene(", fibres: rule, helix_epi_rv: 95 deg")).find("mesh.helix_epi_rv: the angle"),
            std::string::npos);
  EXPECT_NE(test::scene_error(scene(", sheet_angle_epi: 25 deg")).find("mesh.sheet_angle_epi: only with fibres: rule"),
            std::string::npos);
  EXPECT_NE(
      test::scene_error(scene(", fibres: rule, sheet_angle_epi: -95 deg")).find("mesh.sheet_angle_epi: the angle"),
      std::string::npos);
  EXPECT_NE(test::scene_error(scene(", cavities: {lv: 0}")).find("mesh.cavities.lv"), std::string::npos);
  const std::string unknown = test::scene_error(scene(kTet, "{cavity_rim: lw}"));
  EXPECT_NE(unknown.find("the mesh has no cavity 'lw'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("lv"), std::string::npos) << unknown;
  EXPECT_NE(test::scene_error(scene(", topology: tet6m")).find("has no cavity 'lv' (it has no cavities)"),
            std::string::npos);
}

// `mesh: {phantom: lv, topology: cgal, cgal: {...}}`: the phantom recipe meshed by CGAL Mesh_3
// (cases/benchmarks/land-p2-cgal.yaml), with its cavity and the base plane z = 5 mm as a tag.
TEST(SceneImage, APhantomRecipeMeshesWithCgalAndTagsItsBase) {
  const std::string scene =
      "name: t\nmesh: {phantom: lv, voxel_size: 1 mm, topology: cgal, cgal: {facet_size: 3 mm, cell_size: 3 mm}}\n"
      "materials:\n  - {name: m, labels: [1], density: 1000 kg/m^3, terms: [{volume: {p: 1 kPa}}]}\n"
      "boundary:\n  - {select: {tag: base}, fix: xyz}\nintegrator: {type: static, dt: 0.1 s}\nrun: {t_end: 1 s}\n";
  const auto s = test::load_scene(scene);
  const preprocess::Mesh& m = *s.model.mesh;
  EXPECT_EQ(m.type, preprocess::ElementType::Tet4);
  EXPECT_NE(s.mesh_source.find("mesh-lv-cgal-"), std::string::npos) << s.mesh_source;
  ASSERT_EQ(m.cavities.count("lv"), 1u);
  EXPECT_TRUE(m.cavities.at("lv").closed);
  // The shell's volume is 3234.6 mm^3 (docs/meshing.md); CGAL inscribes its facets in the
  // labelled surface of 1 mm voxels, so a few per cent less.
  double volume = 0.0;
  for (std::size_t e = 0; e < m.element_count(); ++e) volume += preprocess::element_volume(m, e);
  EXPECT_NEAR(volume, 3234.6e-9, 0.05 * 3234.6e-9);
  // The base tag: nodes within 0.1 voxel of z = 5 mm, spanning the ring from the endocardium
  // (radius 6.69 mm at z = 5 mm) to the epicardium (9.68 mm), each to within a voxel.
  const auto& base = m.node_tags.at("base");
  ASSERT_GT(base.size(), 20u);
  double rmin = 1.0, rmax = 0.0;
  for (const auto n : base) {
    const double r = std::hypot(m.nodes(0, n), m.nodes(1, n));
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
    EXPECT_TRUE(s.model.constraints.constrained(n, 0) && s.model.constraints.constrained(n, 2));
  }
  EXPECT_LT(rmin, 7.69e-3);
  EXPECT_GT(rmax, 8.68e-3);
  // The base is the top of the mesh: no node lies above the plane.
  EXPECT_LE(m.nodes.row(2).maxCoeff(), 5e-3 + 1e-4);
  // At 0.75 mm voxels z = 5 mm is no voxel face (the phantom's top lies at 5.25 mm): no base tag,
  // rather than the few wall nodes CGAL puts near the plane.
  const std::string off = test::scene_error(
      "name: t\nmesh: {phantom: lv, voxel_size: 0.75 mm, topology: cgal, cgal: {facet_size: 3 mm, cell_size: 3 "
      "mm}}\nmaterials:\n  - {name: m, labels: [1], density: 1000 kg/m^3, terms: [{volume: {p: 1 kPa}}]}\n"
      "boundary:\n  - {select: {tag: base}, fix: xyz}\nintegrator: {type: static, dt: 0.1 s}\nrun: {t_end: 1 s}\n");
  EXPECT_NE(off.find("boundary[0].select.tag"), std::string::npos) << off;
  EXPECT_NE(off.find("base"), std::string::npos) << off;
  // `cgal:` belongs to topology cgal.
  EXPECT_NE(test::scene_error("name: t\nmesh: {phantom: lv, topology: tet6m, cgal: {cell_size: 3 mm}}\n"
                              "materials: []\nintegrator: {type: static, dt: 0.1 s}\nrun: {t_end: 1 s}\n")
                .find("mesh.cgal: only with topology: cgal (got topology: tet6m)"),
            std::string::npos);
}
