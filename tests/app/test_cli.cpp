// End-to-end tests of the adamss executable: phantom -> mesh -> info, and the
// one-line errors of bad input.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.hpp"
#include "preprocess/image/nifti_io.hpp"

using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using nlohmann::json;

TEST(Cli, HelpListsSubcommands) {
  const auto r = run_adamss("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* s : {"phantom", "mesh", "info"}) EXPECT_NE(r.output.find(s), std::string::npos) << s;
}

TEST(Cli, PhantomMeshInfoPipeline) {
  const auto dir = scratch_dir("pipeline");
  const std::string img = (dir / "lv.nii.gz").string(), f = (dir / "f.nii.gz").string(),
                    s = (dir / "s.nii.gz").string();
  const std::string mesh = (dir / "lv.h5").string();
  auto r = run_adamss("phantom lv --voxel-size 1mm -o " + img + " --fiber-out " + f + " --sheet-out " + s);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("info " + img + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json ji = json::parse(r.output);
  EXPECT_EQ(ji["kind"], "image");
  EXPECT_NEAR(ji["spacing_m"][0].get<double>(), 1e-3, 1e-12);
  const std::int64_t solid_voxels = ji["labels"]["1"].get<std::int64_t>();
  EXPECT_GT(solid_voxels, 0);

  r = run_adamss("mesh " + img + " --solid 1 --topology tet6m --fiber " + f + " --sheet " + s + " -o " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "lv.vtu"));
  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json jm = json::parse(r.output);
  EXPECT_EQ(jm["kind"], "mesh");
  EXPECT_EQ(jm["element_type"], "tet4");
  EXPECT_EQ(jm["elements"].get<std::int64_t>(), 6 * solid_voxels);
  EXPECT_EQ(jm["labels"]["1"].get<std::int64_t>(), 6 * solid_voxels);
  EXPECT_NEAR(jm["volume_m3"].get<double>(), static_cast<double>(solid_voxels) * 1e-9,
              1e-9 * 1e-9 * static_cast<double>(solid_voxels));
  EXPECT_NEAR(jm["min_dihedral_deg"].get<double>(), 45.0, 1e-6);
  EXPECT_TRUE(jm["has_fibres"].get<bool>());
  for (const char* key : {"nodes", "mean_dihedral_deg", "cavities"}) EXPECT_TRUE(jm.contains(key)) << key;
}

TEST(Cli, ErrorsAreOneLineNamingTheCulprit) {
  const auto dir = scratch_dir("errors");
  struct Case {
    std::string args, must_contain;
  };
  const std::string img = (dir / "slab.nii").string();
  ASSERT_EQ(run_adamss("phantom slab --size 2,2,2 -o " + img).exit_code, 0);
  std::ofstream(dir / "garbage.nii") << "this is not a NIfTI file";
  const Case cases[] = {
      {"mesh " + (dir / "missing.nii.gz").string() + " -o " + (dir / "m.h5").string(), "missing.nii.gz"},
      {"mesh " + (dir / "garbage.nii").string() + " -o " + (dir / "m.h5").string(), "garbage.nii"},
      {"mesh " + img + " --solid 9 -o " + (dir / "m.h5").string(), "--solid"},
      {"mesh " + img + " --topology tet7 -o " + (dir / "m.h5").string(), "tet7"},
      {"mesh " + img + " -o " + (dir / "no_such_dir" / "m.h5").string(), "no_such_dir"},
      {"phantom lv --voxel-size 5ms -o " + (dir / "x.nii").string(), "--voxel-size"},
      {"phantom lv --helix-endo 120 -o " + (dir / "x.nii").string(), "--helix-endo"},
      {"phantom beam --fiber-out " + (dir / "f.nii").string() + " -o " + (dir / "x.nii").string(), "--fiber-out"},
      {"phantom beam --scar-out " + (dir / "s.nii").string() + " -o " + (dir / "x.nii").string(), "--scar-out"},
      {"phantom lv --scar-out " + (dir / "s.nii").string() + " --scar-angle 0 -o " + (dir / "x.nii").string(),
       "--scar-angle"},
      {"phantom lv --scar-out " + (dir / "s.nii").string() + " --scar-direction 0,0,0 -o " + (dir / "x.nii").string(),
       "--scar-direction"},
      {"phantom lv --scar-out " + (dir / "s.nii").string() + " --scar-direction 1,2 -o " + (dir / "x.nii").string(),
       "--scar-direction"},
      {"info " + (dir / "nothing.h5").string(), "nothing.h5"},
  };
  for (const Case& c : cases) {
    const auto r = run_adamss(c.args);
    EXPECT_NE(r.exit_code, 0) << c.args;
    EXPECT_NE(r.output.find(c.must_contain), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << c.args << "\n" << r.output;
  }
}

// The scar segment travels phantom -> image -> mesh cell field: 0/1, some but not most elements.
TEST(Cli, PhantomScarBecomesACellField) {
  const auto dir = scratch_dir("scar");
  const std::string img = (dir / "lv.nii.gz").string(), scar = (dir / "scar.nii.gz").string();
  const std::string mesh = (dir / "lv.h5").string();
  auto r = run_adamss("phantom lv --voxel-size 2.5mm -o " + img + " --scar-out " + scar);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("scar: 18 of 208 wall voxels"), std::string::npos) << r.output;
  r = run_adamss("mesh " + img + " --solid 1 --topology tet6m --cell-field scar=" + scar + " -o " + mesh);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("info " + mesh + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json jm = json::parse(r.output);
  ASSERT_TRUE(jm["cell_fields"].contains("scar")) << jm["cell_fields"].dump();
  EXPECT_EQ(jm["cell_fields"]["scar"]["min"].get<double>(), 0.0) << jm["cell_fields"].dump();
  EXPECT_EQ(jm["cell_fields"]["scar"]["max"].get<double>(), 1.0) << jm["cell_fields"].dump();
}

namespace {
/// Overwrites `bytes.size()` bytes of `file` at `offset` (a NIfTI-1 header field of a .nii).
void patch(const std::filesystem::path& file, std::streamoff offset, const std::string& bytes) {
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  io.seekp(offset);
  io.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}
std::string float_bytes(float v) {
  std::string b(sizeof v, '\0');
  std::memcpy(b.data(), &v, sizeof v);
  return b;
}
}  // namespace

// `mesh` says what `info` says about the header: a unit left unset (xyzt_units = 0, mm assumed)
// is a warning on stderr; labels scaled by scl_slope/scl_inter (NIfTI-1 offsets 112, 116) are
// refused unless --allow-scaled-labels, and then applied with a warning. The LV phantom has
// labels 0 (background), 1 (wall), 2 (cavity); with scl_inter = 1 they become 1, 2, 3, so
// `--solid 1` meshes the background: one hexahedron per background voxel.
TEST(Cli, MeshReportsHeaderWarningsAndRefusesScaledLabels) {
  const auto dir = scratch_dir("mesh_header");
  const std::filesystem::path img = dir / "lv.nii";
  ASSERT_EQ(run_adamss("phantom lv --voxel-size 2.5mm -o " + img.string()).exit_code, 0);
  auto r = run_adamss("info " + img.string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::int64_t background = json::parse(r.output)["labels"]["0"].get<std::int64_t>();
  ASSERT_GT(background, 0);

  patch(img, 123, std::string(1, '\0'));  // xyzt_units: no unit
  r = run_adamss("mesh " + img.string() + " --topology hex -o " + (dir / "a.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("adamss mesh: warning: '" + img.string() + "': spatial unit not set"), std::string::npos)
      << r.output;

  patch(img, 112, float_bytes(1.0F) + float_bytes(1.0F));  // scl_slope = 1, scl_inter = 1
  r = run_adamss("mesh " + img.string() + " --topology hex -o " + (dir / "b.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("0 would become 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--allow-scaled-labels"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.h5"));

  r = run_adamss("mesh " + img.string() + " --topology hex --allow-scaled-labels -o " + (dir / "c.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("adamss mesh: warning: '" + img.string() +
                          "': values scaled by scl_slope = 1 and "
                          "scl_inter = 1"),
            std::string::npos)
      << r.output;
  r = run_adamss("info " + (dir / "c.h5").string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(json::parse(r.output)["elements"].get<std::int64_t>(), background);
}

// The libhdf5 1.10.8 crashes of fuzz/known-libhdf5/ (common/guarded_read.hpp): `info` on them and
// `run` of a scene whose mesh is one of them end with a one-line error and status 2, not a crash.
TEST(Cli, CorruptedHdf5FilesThatCrashTheLibraryAreOneLineErrors) {
  const auto dir = scratch_dir("hdf5_crashes");
  const std::filesystem::path known = std::filesystem::path(ADAMSS_SOURCE_DIR) / "fuzz/known-libhdf5";
  for (const char* name : {"h5aiterate-attr-table-segv.h5", "h5d-contig-read-memcpy-segv.h5"}) {
    const std::string file = (known / name).string();
    auto r = run_adamss("info " + file);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output, "adamss: error: '" + file +
                            "': the HDF5 library crashed (SIGSEGV) reading it, in a child process that reads every "
                            "file first: the file is corrupted\n");
    const std::filesystem::path scene = adamss::test::write_scene(dir, "name: x\nmesh: {file: " + file +
                                                                           "}\nmaterials: []\n"
                                                                           "integrator: {type: static, dt: 1 ms}\n"
                                                                           "run: {t_end: 1 ms}\n");
    r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("HDF5 library crashed"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("Segmentation"), std::string::npos) << r.output;
  }
}

// Mistyped commands, options and choices: one line, status 2, and the name that was meant.
TEST(Cli, MistypedNamesGetADidYouMean) {
  const auto dir = scratch_dir("did_you_mean");
  const std::string img = (dir / "x.nii").string();
  auto r = run_adamss("rnu scene.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output,
            "adamss: error: unknown command 'rnu'; did you mean 'run'? (commands: phantom, mesh, info, run, unload, "
            "fit, verify)\n");
  r = run_adamss("simulate scene.yaml");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output.find("did you mean"), std::string::npos) << r.output;
  r = run_adamss("");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no command given"), std::string::npos) << r.output;
  r = run_adamss("phantom lv -o " + img + " --fibre-out " + (dir / "f.nii").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("adamss phantom: error: unknown option '--fibre-out'; did you mean '--fiber-out'?"),
            std::string::npos)
      << r.output;
  r = run_adamss("phantom lvv -o " + img);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'lvv' is not one of lv, biv, beam, slab; did you mean 'lv'?"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(img));
  r = run_adamss("mesh");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("adamss mesh: error:"), std::string::npos) << r.output;
  r = run_adamss("--version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A length without a unit on the command line: "--voxel-size 0.5" would be 0.5 m, a 6-voxel image
// with no heart in it (it used to be written with status 0). Plain metres below 5 cm are fine, and
// a voxel size that leaves the phantom without a heart voxel is an error even with a unit.
TEST(Cli, LengthsWithoutUnitsAndEmptyPhantomsAreRefused) {
  const auto dir = scratch_dir("bare_lengths");
  const std::string img = (dir / "x.nii").string();
  auto r = run_adamss("phantom lv --voxel-size 0.5 -o " + img);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--voxel-size: '0.5' has no unit and would be 0.5 m; give the unit ('0.5 mm')"),
            std::string::npos)
      << r.output;
  r = run_adamss("phantom lv --voxel-size 500mm -o " + img);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no voxel inside the heart"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(img));
  r = run_adamss("phantom lv --voxel-size 0.004 -o " + img);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("voxels of 4 mm"), std::string::npos) << r.output;
  r = run_adamss("mesh " + img + " --solid 1 --topology cgal --cgal-cell-size 2 -o " + (dir / "m.h5").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--cgal-cell-size: '2' has no unit"), std::string::npos) << r.output;
}

// info reads what phantom writes: the fibre field (a vector image) and the scar (a 0/1 float
// image, read as labels); every wall voxel (label 1) holds a unit fibre vector, the rest none.
TEST(Cli, InfoReadsVectorAndScalarImages) {
  const auto dir = scratch_dir("info_images");
  const std::string img = (dir / "lv.nii.gz").string(), f = (dir / "f.nii.gz").string();
  const std::string scar = (dir / "scar.nii.gz").string(), half = (dir / "half.nii.gz").string();
  auto r = run_adamss("phantom lv --voxel-size 2mm -o " + img + " --fiber-out " + f + " --scar-out " + scar);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_adamss("info " + img + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json ji = json::parse(r.output);
  const std::int64_t wall = ji["labels"]["1"].get<std::int64_t>();
  std::int64_t all = 0;
  for (const auto& [label, n] : ji["labels"].items()) all += n.get<std::int64_t>();
  r = run_adamss("info " + f + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json jf = json::parse(r.output);
  EXPECT_EQ(jf["kind"], "vector_image");
  EXPECT_EQ(jf["dims"], ji["dims"]);
  EXPECT_EQ(jf["vectors"]["voxels_with_vector"].get<std::int64_t>(), wall);
  EXPECT_EQ(jf["vectors"]["unit_length_voxels"].get<std::int64_t>(), wall);
  EXPECT_EQ(jf["vectors"]["zero_voxels"].get<std::int64_t>(), all - wall);
  EXPECT_EQ(jf["vectors"]["nan_voxels"].get<std::int64_t>(), 0);
  EXPECT_NEAR(jf["vectors"]["max_norm"].get<double>(), 1.0, 1e-6);
  r = run_adamss("info " + f);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("vector image"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(std::to_string(wall) + " voxels with a vector"), std::string::npos) << r.output;

  // The scar halved (0 / 0.5): not labels any more, a scalar image.
  r = run_adamss("info " + scar + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::int64_t scarred = json::parse(r.output)["labels"]["1"].get<std::int64_t>();
  adamss::preprocess::ScalarImage s = adamss::preprocess::read_scalar_image(scar);
  for (double& v : s.values) v *= 0.5;
  s.values[0] = std::numeric_limits<double>::quiet_NaN();
  adamss::preprocess::write_scalar_image(half, s);
  r = run_adamss("info " + half + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json js = json::parse(r.output);
  EXPECT_EQ(js["kind"], "scalar_image");
  EXPECT_DOUBLE_EQ(js["values"]["max"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(js["values"]["min"].get<double>(), 0.0);
  EXPECT_EQ(js["values"]["nonzero_voxels"].get<std::int64_t>(), scarred);
  EXPECT_EQ(js["values"]["nan_voxels"].get<std::int64_t>(), 1);
}

// mesh writes an XDMF sidecar beside mesh.h5 (read back by meshio in ctest python.xdmf); a mesh
// name ending in .xdmf would be overwritten by its own sidecar and is refused before any work.
TEST(Cli, MeshWritesAnXdmfSidecarAndRefusesAnXdmfName) {
  const auto dir = scratch_dir("xdmf_sidecar");
  const std::string img = (dir / "lv.nii").string();
  ASSERT_EQ(run_adamss("phantom lv --voxel-size 2.5mm -o " + img).exit_code, 0);
  auto r = run_adamss("mesh " + img + " --solid 1 --topology hex -o " + (dir / "m.h5").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream x(dir / "m.xdmf");
  std::stringstream ss;
  ss << x.rdbuf();
  EXPECT_NE(ss.str().find("TopologyType=\"Hexahedron\""), std::string::npos) << ss.str();
  EXPECT_NE(ss.str().find("m.h5:/nodes"), std::string::npos) << ss.str();
  // The .vtu written beside it is a mesh a scene and info accept (preprocess/mesh/mesh_import.hpp).
  r = run_adamss("info " + (dir / "m.vtu").string() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"element_type\": \"hex8\""), std::string::npos) << r.output;
  const std::filesystem::path scene = adamss::test::write_scene(
      dir,
      "name: v\nmesh: {file: m.vtu}\nmaterials:\n  - name: m\n    labels: [1]\n    density: 1000 kg/m^3\n"
      "    terms:\n      - fem_element: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}\n"
      "boundary:\n  - select: {region: {plane: {point: [0, 0, 5 mm], normal: [0, 0, 1]}}}\n    fix: xyz\n"
      "integrator: {type: static, dt: 1 ms}\nrun: {t_end: 1 ms}\n");
  r = run_adamss("run " + scene.string() + " --check");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("scene v: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" hex8 elements"), std::string::npos) << r.output;
  r = run_adamss("mesh " + img + " --solid 1 --topology hex -o " + (dir / "n.xdmf").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("ends in .xdmf"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "n.xdmf"));
}
