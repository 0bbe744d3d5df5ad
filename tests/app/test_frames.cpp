// Issue 21 item 1 (part): what a frame holds, read back with VTK's own XML reader. A single
// hexahedron (the 1 x 1 x 1 slab phantom, fibre along z, sheet along x) stretched 10 % along z:
// the frame has the reference points and the displacement (ParaView's Warp By Vector then gives
// the deformed element once), and its strain arrays equal E = (F^T F - I)/2 computed here from
// the nodes; a heart scene's frames carry time, cavity pressure, volume and phase as field data.
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Dense>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.hpp"

using adamss::test::cache_arg;
using adamss::test::read_summary;
using adamss::test::run_adamss;
using adamss::test::scratch_dir;
using adamss::test::write_scene;
namespace fs = std::filesystem;

namespace {

vtkSmartPointer<vtkUnstructuredGrid> read_frame(const fs::path& file) {
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkSmartPointer<vtkUnstructuredGrid> grid = reader->GetOutput();
  return grid;
}

/// The last frame of a run's series.
fs::path last_frame(const fs::path& out) {
  fs::path last;
  for (const auto& e : fs::directory_iterator(out / "frames")) last = std::max(last, e.path());
  return last;
}

}  // namespace

TEST(Frames, OneStretchedHexahedronHoldsEveryArrayWithTheRightValues) {
  const fs::path dir = scratch_dir("frames_one_hex");
  const fs::path scene = write_scene(dir, R"(
name: one_hex
mesh: {phantom: slab, slab_size: [1, 1, 1], voxel_size: 1 mm, topology: hex, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
  - select: {region: {plane: {point: [0, 0, 1 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    control: {axis: z, displacement: {ramp: {to: 0.1 mm, duration: 1 s}}}
integrator: {type: static, dt: 0.5 s}
run: {t_end: 1 s}
)");
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto grid = read_frame(last_frame(out));
  ASSERT_EQ(grid->GetNumberOfPoints(), 8);
  ASSERT_EQ(grid->GetNumberOfCells(), 1);
  vtkPointData* pd = grid->GetPointData();
  vtkCellData* cd = grid->GetCellData();
  for (const char* name : {"displacement", "velocity", "force"}) {
    ASSERT_NE(pd->GetArray(name), nullptr) << name;
    EXPECT_EQ(pd->GetArray(name)->GetNumberOfComponents(), 3) << name;
  }
  EXPECT_STREQ(pd->GetVectors()->GetName(), "displacement");  // what Warp By Vector uses
  for (const char* name : {"label", "J", "fibre_stretch"}) ASSERT_NE(cd->GetArray(name), nullptr) << name;
  for (const char* name : {"fibre", "sheet", "normal", "fibre_current", "sheet_current", "normal_current"}) {
    ASSERT_NE(cd->GetArray(name), nullptr) << name;
    EXPECT_EQ(cd->GetArray(name)->GetNumberOfComponents(), 3) << name;
  }
  for (const char* name : {"green_lagrange", "green_lagrange_fibre_frame"}) {
    ASSERT_NE(cd->GetArray(name), nullptr) << name;
    EXPECT_EQ(cd->GetArray(name)->GetNumberOfComponents(), 9) << name;
  }
  ASSERT_NE(grid->GetFieldData()->GetArray("TimeValue"), nullptr);
  EXPECT_DOUBLE_EQ(grid->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), 1.0);
  EXPECT_EQ(cd->GetArray("label")->GetTuple1(0), 1.0);

  // Points are the reference cube [0, 1 mm]^3 (up to the phantom's placement); warped once by the
  // displacement, the top face sits at z + 0.1 mm, the bottom where it was.
  Eigen::Matrix<double, 3, 8> X, x;
  for (int a = 0; a < 8; ++a) {
    for (int c = 0; c < 3; ++c) {
      X(c, a) = grid->GetPoint(a)[c];
      x(c, a) = X(c, a) + pd->GetArray("displacement")->GetComponent(a, c);
    }
  }
  const Eigen::Vector3d lo = X.rowwise().minCoeff(), hi = X.rowwise().maxCoeff();
  EXPECT_NEAR(hi.z() - lo.z(), 1e-3, 1e-12) << "the points are not the reference cube";
  for (int a = 0; a < 8; ++a) {
    const bool top = X(2, a) > lo.z() + 0.5e-3;
    EXPECT_NEAR(x(2, a) - X(2, a), top ? 1e-4 : 0.0, 1e-12) << "node " << a;
  }
  // F at the centre of the trilinear cube: grad_X N_a = xi_a / (4 h), xi_a = +-1 per axis.
  const double h = 1e-3;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 8; ++a) {
    const Eigen::Vector3d xi = (2.0 * (X.col(a) - lo) / h).array() - 1.0;
    F += x.col(a) * xi.transpose() / (4.0 * h);
  }
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  EXPECT_GT(E(2, 2), 0.09);  // 10 % along z: E_zz = (1.1^2 - 1)/2 at the centre
  Eigen::Matrix3d Q;         // columns f0 = z, s0 = x, n0 = f0 x s0 = y
  Q << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  const Eigen::Matrix3d El = Q.transpose() * E * Q;
  for (int rr = 0; rr < 3; ++rr) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(cd->GetArray("green_lagrange")->GetComponent(0, 3 * rr + c), E(rr, c), 1e-12) << rr << c;
      EXPECT_NEAR(cd->GetArray("green_lagrange_fibre_frame")->GetComponent(0, 3 * rr + c), El(rr, c), 1e-12) << rr << c;
    }
  }
  EXPECT_NEAR(cd->GetArray("fibre_stretch")->GetTuple1(0), std::sqrt(2.0 * El(0, 0) + 1.0), 1e-12);
  const Eigen::Vector3d fc = (F * Q.col(0)).normalized(), nc = (F.inverse().transpose() * Q.col(2)).normalized();
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(cd->GetArray("fibre")->GetComponent(0, c), Q(c, 0), 1e-12);
    EXPECT_NEAR(cd->GetArray("sheet")->GetComponent(0, c), Q(c, 1), 1e-12);
    EXPECT_NEAR(cd->GetArray("normal")->GetComponent(0, c), Q(c, 2), 1e-12);
    EXPECT_NEAR(cd->GetArray("fibre_current")->GetComponent(0, c), fc[c], 1e-12);
    EXPECT_NEAR(cd->GetArray("normal_current")->GetComponent(0, c), nc[c], 1e-12);
  }
}

// The law's stresses in the frame (FEM element, 8 Gauss points, all equal here): a single hexahedron stretched
// 10 % along z with its lateral faces free (bottom face held in z only, two corners pinned
// against rigid motion) deforms homogeneously, so sigma = F S F^T / J with F from the nodes,
// S_fibre = Q^T S Q, the lateral Cauchy stresses vanish, and sigma_zz times the current face
// area equals the reaction force that summary.json reports on the pulled face (the support pulls
// the face up: + z).
TEST(Frames, TheLawStressesAgreeWithTheReactionOfAUniaxialStretch) {
  const fs::path dir = scratch_dir("frames_stress");
  const fs::path scene = write_scene(dir, R"(
name: one_hex_stress
mesh: {phantom: slab, slab_size: [1, 1, 1], voxel_size: 1 mm, topology: hex, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: z
  - select: {region: {box: {min: [-0.1 mm, -0.1 mm, -0.1 mm], max: [0.1 mm, 0.1 mm, 0.1 mm]}}}
    fix: xyz
  - select: {region: {box: {min: [0.9 mm, -0.1 mm, -0.1 mm], max: [1.1 mm, 0.1 mm, 0.1 mm]}}}
    fix: y
  - select: {region: {plane: {point: [0, 0, 1 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    control: {axis: z, displacement: {ramp: {to: 0.1 mm, duration: 1 s}}}
integrator: {type: static, dt: 0.5 s, newton_rtol: 1e-12}
run: {t_end: 1 s}
)");
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto grid = read_frame(last_frame(out));
  vtkCellData* cd = grid->GetCellData();
  for (const char* name : {"stress_pk2", "stress_pk2_fibre_frame", "stress_cauchy"}) {
    ASSERT_NE(cd->GetArray(name), nullptr) << name;
    ASSERT_EQ(cd->GetArray(name)->GetNumberOfComponents(), 9) << name;
  }
  const auto tensor = [&](const char* name) {
    Eigen::Matrix3d m;
    for (int rr = 0; rr < 3; ++rr)
      for (int c = 0; c < 3; ++c) m(rr, c) = cd->GetArray(name)->GetComponent(0, 3 * rr + c);
    return m;
  };
  const Eigen::Matrix3d S = tensor("stress_pk2"), Sf = tensor("stress_pk2_fibre_frame"),
                        sigma = tensor("stress_cauchy");
  Eigen::Matrix<double, 3, 8> X, x;
  vtkPointData* pd = grid->GetPointData();
  for (int a = 0; a < 8; ++a) {
    for (int c = 0; c < 3; ++c) {
      X(c, a) = grid->GetPoint(a)[c];
      x(c, a) = X(c, a) + pd->GetArray("displacement")->GetComponent(a, c);
    }
  }
  const double h = 1e-3;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 8; ++a) F += x.col(a) * ((2.0 * X.col(a) / h).array() - 1.0).matrix().transpose() / (4.0 * h);
  const double scale = std::abs(sigma(2, 2));
  ASSERT_GT(scale, 100.0);  // ~1 kPa at 10 % with E = 10 kPa
  EXPECT_LT((sigma - F * S * F.transpose() / F.determinant()).cwiseAbs().maxCoeff(), 1e-9 * scale);
  Eigen::Matrix3d Q;
  Q << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  EXPECT_LT((Sf - Q.transpose() * S * Q).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_LT(std::abs(sigma(0, 0)), 1e-6 * scale);  // free lateral faces
  EXPECT_LT(std::abs(sigma(1, 1)), 1e-6 * scale);
  const double area = F(0, 0) * F(1, 1) * h * h;  // current top face (homogeneous, no shear)
  const auto summary = read_summary(out);
  double reaction = 0.0;
  for (const auto& entry : summary["reactions"]) {
    if (entry["entry"] == "boundary[3]") reaction = entry["reaction_force_N"][2].get<double>();
  }
  EXPECT_NEAR(reaction, sigma(2, 2) * area, 1e-6 * scale * area) << "reaction " << reaction << " N";
}

// The LV with a circulation: every frame has the time and the cavity's pressure (Pa and mmHg),
// volume (ml) and phase as field data, equal to globals.csv's last row in the last frame.
TEST(Frames, HeartFramesCarryTimeAndTheCavityAsFieldData) {
  const fs::path dir = scratch_dir("frames_cavity");
  std::ifstream in(std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::string held = "volume_ratio: 1";
  text.replace(text.find(held), held.size(),
               "circulation: {atrial_pressure: 1 kPa, contraction_onset: 0.2 s, windkessel: {initial_pressure: 4 "
               "kPa}}");
  const fs::path scene = write_scene(dir, text);
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto grid = read_frame(last_frame(out));
  vtkFieldData* fd = grid->GetFieldData();
  for (const char* name : {"TimeValue", "lv_pressure_Pa", "lv_pressure_mmHg", "lv_volume_ml"}) {
    ASSERT_NE(fd->GetArray(name), nullptr) << name;
  }
  EXPECT_DOUBLE_EQ(fd->GetArray("TimeValue")->GetTuple1(0), 1.0);
  const double p = fd->GetArray("lv_pressure_Pa")->GetTuple1(0);
  EXPECT_NEAR(fd->GetArray("lv_pressure_mmHg")->GetTuple1(0), p / 133.322387415, 1e-9 * std::abs(p));
  auto* phase = vtkStringArray::SafeDownCast(fd->GetAbstractArray("lv_phase"));
  ASSERT_NE(phase, nullptr);
  const std::string ph = phase->GetValue(0);
  EXPECT_TRUE(ph == "filling" || ph == "isovolumic_contraction" || ph == "ejection" || ph == "isovolumic_relaxation")
      << ph;
  // The last globals.csv row: lv_volume and lv_pressure columns.
  std::ifstream g(out / "globals.csv");
  std::string header, row, line;
  std::getline(g, header);
  while (std::getline(g, line)) row = line;
  std::vector<std::string> names, values;
  for (std::stringstream hs(header); std::getline(hs, line, ',');) names.push_back(line);
  for (std::stringstream rs(row); std::getline(rs, line, ',');) values.push_back(line);
  ASSERT_EQ(names.size(), values.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == "lv_volume") {
      EXPECT_NEAR(fd->GetArray("lv_volume_ml")->GetTuple1(0), std::stod(values[i]) * 1e6, 1e-6);
    }
    if (names[i] == "lv_pressure") {
      EXPECT_NEAR(p, std::stod(values[i]), 1e-6 * std::max(1.0, std::abs(p)));
    }
  }
}
