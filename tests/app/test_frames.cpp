// Issue 21 item 1 (part): what a frame holds, read back with VTK's own XML reader. A single
// hexahedron (the 1 x 1 x 1 slab phantom, fibre along z, sheet along x) stretched 10 % along z:
// the frame has the reference points and the displacement (ParaView's Warp By Vector then gives
// the deformed element once), and its strain arrays equal E = (F^T F - I)/2 computed here from
// the nodes; a heart scene's frames carry time, cavity pressure, volume and phase as field data.
#include <gtest/gtest.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
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

// The volume terms' hydrostatic stress is in the frames' stresses: one hexahedron of an uncoupled
// neo-Hookean (no volumetric part of its own) with a nearly incompressible volume term, stretched
// 10 % along z with free lateral faces. Traction-free lateral faces need sigma_xx = sigma_yy = 0,
// which holds only when the volume term's q I is added to the law's deviatoric sigma (the law alone
// gives sigma_xx = -q, about -1/3 of sigma_zz). sigma_zz times the current area equals the
// reaction, and pressure = -tr(sigma) / 3. Element (isotropic) and nodal distributions: on one
// homogeneously deformed element both give q = U'(J).
TEST(Frames, TheStressesIncludeTheVolumeTermsPressure) {
  for (const std::string distribution : {"isotropic", "nodal"}) {
    SCOPED_TRACE(distribution);
    const fs::path dir = scratch_dir("frames_stress_volume_" + distribution);
    const fs::path scene = write_scene(dir, R"(
name: one_hex_volume_stress
mesh: {phantom: slab, slab_size: [1, 1, 1], voxel_size: 1 mm, topology: hex, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, uncoupled: true, parameters: {E: 10 kPa, nu: 0.3}}
      - volume: {p: 200 kPa, distribution: )" + distribution +
                                                R"(}
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
    for (const char* name : {"stress_pk2", "stress_pk2_fibre_frame", "stress_cauchy", "volumetric_stress", "pressure"})
      ASSERT_NE(cd->GetArray(name), nullptr) << name;
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
    ASSERT_GT(scale, 500.0);  // ~3.3 kPa: 3 mu (stretch^2 - 1/stretch) at 10 %, mu = 3.85 kPa
    const double q = cd->GetArray("volumetric_stress")->GetTuple1(0);
    EXPECT_GT(std::abs(q), 0.2 * scale) << "the volume term carries about a third of sigma_zz here";
    EXPECT_LT(std::abs(sigma(0, 0)), 1e-6 * scale) << "q = " << q;  // free lateral faces
    EXPECT_LT(std::abs(sigma(1, 1)), 1e-6 * scale);
    EXPECT_LT((sigma - F * S * F.transpose() / F.determinant()).cwiseAbs().maxCoeff(), 1e-9 * scale);
    Eigen::Matrix3d Q;
    Q << 0, 1, 0, 0, 0, 1, 1, 0, 0;
    EXPECT_LT((Sf - Q.transpose() * S * Q).cwiseAbs().maxCoeff(), 1e-9 * scale);
    EXPECT_NEAR(cd->GetArray("pressure")->GetTuple1(0), -sigma.trace() / 3.0, 1e-9 * scale);
    const double area = F(0, 0) * F(1, 1) * h * h;
    const auto summary = read_summary(out);
    double reaction = 0.0;
    for (const auto& entry : summary["reactions"]) {
      if (entry["entry"] == "boundary[3]") reaction = entry["reaction_force_N"][2].get<double>();
    }
    EXPECT_NEAR(reaction, sigma(2, 2) * area, 1e-6 * scale * area) << "reaction " << reaction << " N";
  }
}

// The strain in the cardiac frame on the idealised LV inflated passively to 1 kPa: the long axis
// comes from the LV lid (the phantom's axis is z, apex at -z, so the direction is +z through the
// base centre on the axis), every element's e_c, e_l, e_r are orthonormal with e_l = +z and e_r
// pointing away from the axis, the scalars equal Q^T E Q of the frame's own green_lagrange, and
// the inflated wall stretches circumferentially (mean E_cc > 0) and thins (mean E_rr < 0).
TEST(Frames, AnInflatedLvHasStrainInTheCardiacFrame) {
  const fs::path dir = scratch_dir("frames_cardiac");
  std::ifstream in(std::string(ADAMSS_SOURCE_DIR) + "/cases/quick/lv_isovolumic_static.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto replace = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(text.find(from), std::string::npos) << from;
    text.replace(text.find(from), from.size(), to);
  };
  replace("volume_ratio: 1", "pressure: {ramp: {to: 1 kPa, duration: 1 s}}");
  replace("      - active_tension: {form: stress, tension: {ramp: {to: 20 kPa, duration: 1 s}}}\n", "");
  const fs::path scene = write_scene(dir, text);
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = read_summary(out);
  ASSERT_TRUE(summary.contains("long_axis"));
  EXPECT_EQ(summary["long_axis"]["source"], "lid of cavity lv");
  const Eigen::Vector3d l(summary["long_axis"]["direction"][0].get<double>(),
                          summary["long_axis"]["direction"][1].get<double>(),
                          summary["long_axis"]["direction"][2].get<double>());
  const Eigen::Vector3d c(summary["long_axis"]["point_m"][0].get<double>(),
                          summary["long_axis"]["point_m"][1].get<double>(),
                          summary["long_axis"]["point_m"][2].get<double>());
  EXPECT_NEAR(l.z(), 1.0, 1e-6) << l.transpose();
  EXPECT_LT(std::hypot(c.x(), c.y()), 1e-4) << "the base centre is on the phantom's axis: " << c.transpose();

  const auto grid = read_frame(last_frame(out));
  vtkCellData* cd = grid->GetCellData();
  for (const char* name : {"green_lagrange_cardiac", "strain_circumferential", "strain_longitudinal", "strain_radial",
                           "circumferential", "longitudinal", "radial"})
    ASSERT_NE(cd->GetArray(name), nullptr) << name;
  const vtkIdType ne = grid->GetNumberOfCells();
  double ecc = 0.0, err = 0.0;
  for (vtkIdType e = 0; e < ne; ++e) {
    Eigen::Matrix3d Q, E, El;
    for (int k = 0; k < 3; ++k) {
      Q(k, 0) = cd->GetArray("circumferential")->GetComponent(e, k);
      Q(k, 1) = cd->GetArray("longitudinal")->GetComponent(e, k);
      Q(k, 2) = cd->GetArray("radial")->GetComponent(e, k);
    }
    for (int rr = 0; rr < 3; ++rr) {
      for (int k = 0; k < 3; ++k) {
        E(rr, k) = cd->GetArray("green_lagrange")->GetComponent(e, 3 * rr + k);
        El(rr, k) = cd->GetArray("green_lagrange_cardiac")->GetComponent(e, 3 * rr + k);
      }
    }
    ASSERT_LT((Q.transpose() * Q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12) << e;
    ASSERT_NEAR(Q.determinant(), 1.0, 1e-12) << e;
    ASSERT_LT((Q.col(1) - l).norm(), 1e-12) << e;
    // e_r points away from the axis at the element's reference centroid.
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    vtkIdList* ids = grid->GetCell(e)->GetPointIds();
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
      centre += Eigen::Vector3d(grid->GetPoint(ids->GetId(a))) / static_cast<double>(ids->GetNumberOfIds());
    Eigen::Vector3d d = centre - c;
    d -= d.dot(l) * l;
    if (d.norm() > 1e-4) {
      ASSERT_GT(Q.col(2).dot(d.normalized()), 1.0 - 1e-9) << e;
    }
    ASSERT_LT((El - Q.transpose() * E * Q).cwiseAbs().maxCoeff(), 1e-12) << e;
    ASSERT_DOUBLE_EQ(cd->GetArray("strain_circumferential")->GetTuple1(e), El(0, 0));
    ASSERT_DOUBLE_EQ(cd->GetArray("strain_longitudinal")->GetTuple1(e), El(1, 1));
    ASSERT_DOUBLE_EQ(cd->GetArray("strain_radial")->GetTuple1(e), El(2, 2));
    ecc += El(0, 0) / static_cast<double>(ne);
    err += El(2, 2) / static_cast<double>(ne);
  }
  std::cout << "mean E_cc " << ecc << ", mean E_rr " << err << " over " << ne << " elements\n";
  EXPECT_GT(ecc, 0.01) << "inflation stretches the wall circumferentially";
  EXPECT_LT(err, -0.005) << "and thins it";
}

// output.long_axis overrides the estimate (normalised); a zero direction is refused by key.
TEST(Frames, TheSceneCanGiveTheLongAxis) {
  const fs::path dir = scratch_dir("frames_axis_scene");
  const std::string base = R"(
name: one_hex_axis
mesh: {phantom: slab, slab_size: [1, 1, 1], voxel_size: 1 mm, topology: hex}
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
    control: {axis: x, displacement: {ramp: {to: 0.1 mm, duration: 1 s}}}
integrator: {type: static, dt: 0.5 s}
run: {t_end: 1 s}
output:
  long_axis: {point: [0, 0, 0], direction: )";
  const fs::path scene = write_scene(dir, base + "[0, 0, 2]}\n");
  const fs::path out = dir / "out";
  const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = read_summary(out);
  EXPECT_EQ(summary["long_axis"]["source"], "scene");
  EXPECT_DOUBLE_EQ(summary["long_axis"]["direction"][2].get<double>(), 1.0);
  const auto grid = read_frame(last_frame(out));
  vtkCellData* cd = grid->GetCellData();
  ASSERT_NE(cd->GetArray("strain_circumferential"), nullptr);
  // Simple shear in the x-z plane: e_r is the centroid's direction normal to z (from the axis
  // through the origin), e_l = z, and E_rl = e_r^T E e_l = e_r,x E_xz picks up the shear.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (vtkIdType a = 0; a < 8; ++a) centre += Eigen::Vector3d(grid->GetPoint(a)) / 8.0;
  const Eigen::Vector3d er = Eigen::Vector3d(centre.x(), centre.y(), 0.0).normalized();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(cd->GetArray("radial")->GetComponent(0, k), er[k], 1e-12);
    EXPECT_NEAR(cd->GetArray("longitudinal")->GetComponent(0, k), k == 2 ? 1.0 : 0.0, 1e-12);
  }
  const double exz = cd->GetArray("green_lagrange")->GetComponent(0, 2);
  const double eyz = cd->GetArray("green_lagrange")->GetComponent(0, 5);
  const double erl = cd->GetArray("green_lagrange_cardiac")->GetComponent(0, 3 * 2 + 1);
  ASSERT_GT(std::abs(exz), 0.01);
  EXPECT_NEAR(erl, er.x() * exz + er.y() * eyz, 1e-12);

  const fs::path bad = write_scene(scratch_dir("frames_axis_scene_bad"), base + "[0, 0, 0]}\n");
  const auto rb = run_adamss("run " + bad.string() + " -o " + (dir / "bad_out").string() + cache_arg(dir) + " -q");
  EXPECT_NE(rb.exit_code, 0);
  EXPECT_NE(rb.output.find("output.long_axis.direction"), std::string::npos) << rb.output;
  EXPECT_NE(rb.output.find("non-zero"), std::string::npos) << rb.output;
}

// output.compression (solver/run/results.hpp): the same frame written with zlib, LZ4 and no
// compression holds the same arrays bit for bit, read back by VTK's reader; each file names its
// compressor (none: no compressor attribute). 640 hexahedra, so that the 9-component cell tensors
// span several 32 KiB compression blocks.
TEST(Frames, ZlibLz4AndUncompressedFramesHoldTheSameArrays) {
  const fs::path dir = scratch_dir("frames_compression");
  const std::string scene_text = R"(
name: compression
mesh: {phantom: slab, slab_size: [10, 8, 8], voxel_size: 1 mm, topology: hex, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
  - select: {region: {plane: {point: [0, 0, 8 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    control: {axis: z, displacement: {ramp: {to: 0.4 mm, duration: 1 s}}}
integrator: {type: static, dt: 1 s}
run: {t_end: 1 s}
output: {frame_interval: 1 s, compression: COMPRESSION}
)";
  std::map<std::string, vtkSmartPointer<vtkUnstructuredGrid>> grids;
  std::map<std::string, std::uintmax_t> sizes;
  for (const std::string c : {"zlib", "lz4", "none"}) {
    std::string text = scene_text;
    text.replace(text.find("COMPRESSION"), 11, c);
    fs::create_directories(dir / c);
    const fs::path scene = write_scene(dir / c, text);
    const fs::path out = dir / c / "out";
    const auto r = run_adamss("run " + scene.string() + " -o " + out.string() + cache_arg(dir) + " -q");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const fs::path frame = last_frame(out);
    std::ifstream in(frame, std::ios::binary);
    std::string head(600, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    const std::string want = c == "zlib"  ? "compressor=\"vtkZLibDataCompressor\""
                             : c == "lz4" ? "compressor=\"vtkLZ4DataCompressor\""
                                          : "";
    if (want.empty()) {
      EXPECT_EQ(head.find("compressor="), std::string::npos) << c;
    } else {
      EXPECT_NE(head.find(want), std::string::npos) << c;
    }
    grids[c] = read_frame(frame);
    sizes[c] = fs::file_size(frame);
  }
  EXPECT_LT(sizes["zlib"], sizes["none"]);
  EXPECT_LT(sizes["lz4"], sizes["none"]);
  const auto& ref = grids["none"];
  ASSERT_EQ(ref->GetNumberOfCells(), 640);
  for (const std::string c : {"zlib", "lz4"}) {
    const auto& g = grids[c];
    ASSERT_EQ(g->GetNumberOfPoints(), ref->GetNumberOfPoints()) << c;
    ASSERT_EQ(g->GetNumberOfCells(), ref->GetNumberOfCells()) << c;
    for (vtkIdType p = 0; p < ref->GetNumberOfPoints(); ++p)
      for (int k = 0; k < 3; ++k) ASSERT_EQ(g->GetPoint(p)[k], ref->GetPoint(p)[k]) << c;
    int arrays = 0;
    for (vtkFieldData* fd :
         {static_cast<vtkFieldData*>(ref->GetPointData()), static_cast<vtkFieldData*>(ref->GetCellData())}) {
      vtkFieldData* other = fd == ref->GetPointData() ? static_cast<vtkFieldData*>(g->GetPointData())
                                                      : static_cast<vtkFieldData*>(g->GetCellData());
      for (int a = 0; a < fd->GetNumberOfArrays(); ++a) {
        vtkDataArray* x = fd->GetArray(a);
        if (x == nullptr) continue;
        vtkDataArray* y = other->GetArray(x->GetName());
        ASSERT_NE(y, nullptr) << c << " " << x->GetName();
        ASSERT_EQ(y->GetNumberOfValues(), x->GetNumberOfValues()) << c << " " << x->GetName();
        for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
          ASSERT_EQ(y->GetVariantValue(v).ToDouble(), x->GetVariantValue(v).ToDouble()) << c << " " << x->GetName();
        ++arrays;
      }
    }
    EXPECT_EQ(arrays, 18) << c;  // displacement, force, velocity, label, J, ..., the strain and stress tensors
  }
}

TEST(Frames, AnUnknownCompressionIsRefused) {
  const fs::path dir = scratch_dir("frames_compression_bad");
  const fs::path scene = write_scene(dir, R"(
name: bad_compression
mesh: {phantom: slab, slab_size: [1, 1, 1], voxel_size: 1 mm, topology: hex}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - fem_element: {law: neo_hookean, parameters: {E: 10 kPa, nu: 0.3}}
integrator: {type: static, dt: 1 s}
run: {t_end: 1 s}
output: {compression: bzip2}
)");
  const auto r = run_adamss("run " + scene.string() + " -o " + (dir / "out").string() + cache_arg(dir) + " -q");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("compression"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bzip2"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lz4"), std::string::npos) << r.output;
}
