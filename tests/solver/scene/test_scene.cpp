// Scene validation (schema errors name the key path) and assembly (only what is asked for).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/meshers/box_mesh.hpp"
#include "scene_fixtures.hpp"
#include "solver/scene/scene.hpp"

using namespace adamss;

namespace {

const std::string kBase = R"(
name: t
mesh: {phantom: slab, slab_size: [2, 2, 3], voxel_size: 1 mm, topology: tet6m, fibre: [0, 0, 1], sheet: [1, 0, 0]}
materials:
  - name: m
    labels: [1]
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}
boundary:
  - select: {region: {plane: {point: [0, 0, 0], normal: [0, 0, 1]}}}
    fix: xyz
integrator: {type: symplectic_euler, dt: 10 us}
run: {t_end: 1 ms}
)";

using test::replaced;

}  // namespace

TEST(Scene, BaseSceneAssemblesOnlyWhatItNames) {
  const auto sc = test::load_scene(kBase);
  EXPECT_EQ(sc.model.node_count(), 3u * 3u * 4u);
  EXPECT_EQ(sc.model.mesh->element_count(), 2u * 2u * 3u * 6u);
  ASSERT_EQ(sc.model.terms.size(), 1u);
  EXPECT_EQ(sc.model.terms[0]->name(), "virtual_hexahedron");
  EXPECT_EQ(sc.model.constraints.fixed_dof_count(), 3u * 9u);
  EXPECT_NEAR(sc.model.mass.sum(), 1000.0 * 12e-9, 1e-15);
  EXPECT_DOUBLE_EQ(sc.run.dt, 10e-6);
  EXPECT_DOUBLE_EQ(sc.run.t_end, 1e-3);
  EXPECT_EQ(sc.axis_frame_elements, 72u);
  EXPECT_GT(sc.critical_dt, 0.0);
}

TEST(Scene, IsotropicVolumeAloneBuildsNoAxisFrames) {
  const auto sc = test::load_scene(replaced(kBase, "- virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}",
                                            "- volume: {p: 1 kPa, distribution: isotropic}"));
  EXPECT_EQ(sc.axis_frame_elements, 0u);
  EXPECT_EQ(sc.model.terms[0]->name(), "volume_preservation");
}

TEST(Scene, VolumeTakesAnAugmentedLagrangian) {
  const std::string vhex = "- virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}";
  const std::string statik = "integrator: {type: static, dt: 0.25 ms}";
  const std::string al =
      "- volume: {p: 1 kPa, distribution: nodal, augmented_lagrangian: {tolerance: 1e-7, max_updates: 9}}";
  const auto sc =
      test::load_scene(replaced(replaced(kBase, vhex, al), "integrator: {type: symplectic_euler, dt: 10 us}", statik));
  ASSERT_EQ(sc.model.terms.size(), 1u);
  const solver::AugmentedLagrangian got = sc.model.terms[0]->augmented_lagrangian();
  EXPECT_TRUE(got.enabled);
  EXPECT_DOUBLE_EQ(got.tolerance, 1e-7);
  EXPECT_EQ(got.max_updates, 9);
  // Defaults with an empty mapping; element-wise distributions take it too.
  const auto def = test::load_scene(
      replaced(replaced(kBase, vhex, "- volume: {p: 1 kPa, distribution: isotropic, augmented_lagrangian: {}}"),
               "integrator: {type: symplectic_euler, dt: 10 us}", statik));
  EXPECT_DOUBLE_EQ(def.model.terms[0]->augmented_lagrangian().tolerance, 1e-6);
  EXPECT_EQ(def.model.terms[0]->augmented_lagrangian().max_updates, 50);
  // Errors name the key; the explicit integrator is refused when the run is set up (make_integrator).
  const std::string unknown = test::scene_error(replaced(kBase, vhex, replaced(al, "max_updates", "max_update")));
  EXPECT_NE(unknown.find("augmented_lagrangian.max_update: unknown key"), std::string::npos) << unknown;
  const std::string many =
      test::scene_error(replaced(kBase, vhex, replaced(al, "max_updates: 9", "max_updates: 4294967297")));
  EXPECT_NE(many.find("max_updates: must be an integer in [1, 100000]"), std::string::npos) << many;
  const std::string tol = test::scene_error(replaced(kBase, vhex, replaced(al, "1e-7", "0.5")));
  EXPECT_NE(tol.find("augmented_lagrangian: augmented_lagrangian tolerance"), std::string::npos) << tol;
}

TEST(Scene, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_NE(test::scene_error(replaced(kBase, "run: {t_end: 1 ms}", "run: {t_end: 1 ms, tend: 2}"))
                .find("run.tend: unknown key"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "{law: svk,", "{lawz: 1, law: svk,"))
                .find("materials[0].terms[0].virtual_hexahedron.lawz: unknown key"),
            std::string::npos);
  EXPECT_NE(test::scene_error(kBase + "extra: 1\n").find("extra: unknown key"), std::string::npos);
  EXPECT_NE(
      test::scene_error(replaced(kBase, "- virtual_hexahedron:", "- virtual_hexahedra:")).find("unknown force term"),
      std::string::npos);
}

// Holzapfel-Ogden in a scene: its stress parameters take pressure units, in the virtual hexahedron
// and in the FEM element, coupled or uncoupled; a length is refused naming the key.
TEST(Scene, HolzapfelOgdenParametersTakePressureUnits) {
  const std::string vhex = "- virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}";
  for (const char* term :
       {"- virtual_hexahedron: {law: holzapfel_ogden_2009, parameters: {a: 0.059 kPa, a_f: 18.472 kPa, b_f: 16.026}}",
        "- fem_element: {law: holzapfel_ogden, parameters: {a: 59, b: 8.023, a_f: 18.472 kPa, b_f: 16.026, a_s: 2.481 "
        "kPa, b_s: 11.12, a_fs: 216 Pa, b_fs: 11.436}, uncoupled: true}\n      - volume: {distribution: nodal, "
        "p: 500 kPa}"}) {
    SCOPED_TRACE(term);
    const std::string text = replaced(kBase, vhex, term);
    EXPECT_EQ(test::scene_error(text), "");
  }
  const std::string bad =
      replaced(kBase, vhex, "- virtual_hexahedron: {law: holzapfel_ogden_2009, parameters: {a_f: 18 mm}}");
  EXPECT_NE(test::scene_error(bad).find("parameters.a_f: unit 'mm' is a length (m), expected a pressure"),
            std::string::npos)
      << test::scene_error(bad);
}

// A mistyped key, force term, choice or unit names what was meant (issue 21); a key far from every
// known one gets no guess.
TEST(Scene, MistypedNamesGetADidYouMean) {
  const auto error = [](const std::string& from, const std::string& to) {
    return test::scene_error(replaced(kBase, from, to));
  };
  EXPECT_NE(
      error("run: {t_end: 1 ms}", "run: {t_end: 1 ms, tend: 2}").find("run.tend: unknown key; did you mean 't_end'?"),
      std::string::npos);
  EXPECT_NE(error("run: {t_end: 1 ms}", "run: {t_end: 1 ms, colour: 2}").find("run.colour: unknown key (this entry"),
            std::string::npos);
  EXPECT_NE(error("- virtual_hexahedron:", "- virtual_hexahedra:")
                .find("unknown force term 'virtual_hexahedra'; did you mean 'virtual_hexahedron'?"),
            std::string::npos);
  EXPECT_NE(error("type: symplectic_euler", "type: symplectic_eulr").find("did you mean 'symplectic_euler'?"),
            std::string::npos);
  EXPECT_NE(error("density: 1000 kg/m^3", "density: 1000 kg/M^3")
                .find("unknown unit 'M' in '1000 kg/M^3'; did you mean 'm'?"),
            std::string::npos);
}

TEST(Scene, MissingRequiredKeysAndWrongTypes) {
  EXPECT_NE(test::scene_error(replaced(kBase, "run: {t_end: 1 ms}", "run: {}")).find("run.t_end: missing required key"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "density: 1000 kg/m^3", "density: [1, 2]")).find("materials[0].density"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "type: symplectic_euler", "type: leapfrog")).find("integrator.type"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "fix: xyz", "fix: xw")).find("boundary[0].fix"), std::string::npos);
}

TEST(Scene, ImpossibleValuesAndWrongUnits) {
  EXPECT_NE(test::scene_error(replaced(kBase, "density: 1000 kg/m^3", "density: -5"))
                .find("materials[0].density: must be > 0"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "dt: 10 us", "dt: 0")).find("integrator.dt: must be > 0"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "dt: 10 us", "dt: 10 mm")).find("expected a time"), std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "E: 10 kPa", "E: -10 kPa")).find("virtual_hexahedron"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "- virtual_hexahedron: {law: svk, parameters: {E: 10 kPa, nu: 0.3}}",
                                       "- volume: {p: -1 kPa}"))
                .find("materials[0].terms[0].volume.p: must be > 0"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "labels: [1]", "labels: [7]")).find("materials[0].labels"),
            std::string::npos);
  // The static regularisation: a rate, static only.
  EXPECT_NE(test::scene_error(replaced(kBase, "dt: 10 us}", "dt: 10 us, static_damping: 50 /s}"))
                .find("integrator.static_damping: only the static integrator has it"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "type: symplectic_euler, dt: 10 us}",
                                       "type: static, dt: 1 ms, "
                                       "static_damping: 50 Pa}"))
                .find("expected a rate"),
            std::string::npos);
  // The factorisation-reuse counts, BFGS updates (0 ... 1000), modified Newton in the cavity
  // (bordered) steps and in the damped Newton steps (0 ... 100): static only, 0 by default.
  struct Reuse {
    const char* key;
    int solver::ImplicitSettings::*field;
    const char* too_big;
    const char* range;
  };
  for (const Reuse& k : {Reuse{"bfgs_max_updates", &solver::ImplicitSettings::bfgs_max_updates, "1001", "1000"},
                         Reuse{"bordered_max_reuses", &solver::ImplicitSettings::bordered_max_reuses, "101", "100"},
                         Reuse{"newton_max_reuses", &solver::ImplicitSettings::newton_max_reuses, "101", "100"}}) {
    SCOPED_TRACE(k.key);
    const std::string key = k.key;
    const std::string on =
        replaced(kBase, "type: symplectic_euler, dt: 10 us}", "type: static, dt: 1 ms, " + key + ": 8}");
    EXPECT_EQ(test::load_scene(on).run.implicit.*k.field, 8);
    EXPECT_EQ(test::load_scene(replaced(kBase, "type: symplectic_euler, dt: 10 us}", "type: static, dt: 1 ms}"))
                      .run.implicit.*
                  k.field,
              0);
    EXPECT_NE(test::scene_error(replaced(on, "type: static", "type: backward_euler_newton"))
                  .find("integrator." + key + ": only the static integrator"),
              std::string::npos);
    for (const std::string& bad : {key + ": -1", key + ": " + k.too_big}) {
      EXPECT_NE(
          test::scene_error(replaced(on, key + ": 8", bad)).find("integrator." + key + ": must be in 0 ... " + k.range),
          std::string::npos)
          << bad;
    }
  }
  EXPECT_NE(test::scene_error(replaced(kBase, "type: symplectic_euler, dt: 10 us}",
                                       "type: static, dt: 1 ms, bfgs_max_updates: 10, newton_max_reuses: 5}"))
                .find("integrator.newton_max_reuses: choose one way to reuse the factorisation"),
            std::string::npos);
}

TEST(Scene, TimeStepFarBeyondTheCriticalStepIsAnError) {
  const std::string big = replaced(kBase, "dt: 10 us", "dt: 50 ms");
  EXPECT_NE(test::scene_error(big).find("critical step"), std::string::npos);
  // Allowed when asked for; a warning is kept.
  const auto sc = test::load_scene(replaced(big, "dt: 50 ms}", "dt: 50 ms, check_dt: false}"));
  ASSERT_FALSE(sc.warnings.empty());
  EXPECT_NE(sc.warnings[0].find("h_c"), std::string::npos);
}

TEST(Scene, TheRunPlanIsCheckedBeforeTheRun) {
  // dt below the time resolution at t_end: time would never advance.
  EXPECT_NE(test::scene_error(replaced(kBase, "dt: 10 us", "dt: 1e-320 s")).find("time resolution"), std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "dt: 10 us", "dt: 1e-19 s")).find("time resolution"), std::string::npos);
  // 10^12 steps: an error naming the count, unless run.max_steps bounds the run.
  const std::string huge = replaced(kBase, "t_end: 1 ms", "t_end: 1e7 s");
  const std::string err = test::scene_error(huge);
  EXPECT_NE(err.find("1e+12 steps"), std::string::npos) << err;
  EXPECT_NE(err.find("run.max_steps"), std::string::npos) << err;
  EXPECT_EQ(test::scene_error(replaced(huge, "t_end: 1e7 s}", "t_end: 1e7 s, max_steps: 1000}")), "");
  // 10^6 frames of this 36-node mesh (~10 kB each) and a globals row per step: ~10 GB, a warning
  // with the projected size; the base scene (100 steps, default frames) has none.
  const auto big = test::load_scene(replaced(huge, "t_end: 1e7 s}", "t_end: 10 s, max_steps: 1000}") +
                                    "output: {frame_interval: 10 us}\n");
  ASSERT_EQ(big.warnings.size(), 1u);
  EXPECT_NE(big.warnings[0].find("GB"), std::string::npos) << big.warnings[0];
  EXPECT_NE(big.warnings[0].find("frame_interval"), std::string::npos) << big.warnings[0];
  EXPECT_TRUE(test::load_scene(kBase).warnings.empty());
}

TEST(Scene, EveryNodeFixedIsAWarning) {
  const auto all = test::load_scene(replaced(kBase, "{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}",
                                             "{box: {min: [-1 mm, -1 mm, -1 mm], max: [5 mm, 5 mm, 5 mm]}}"));
  ASSERT_EQ(all.warnings.size(), 1u);
  EXPECT_NE(all.warnings[0].find("all 36 nodes"), std::string::npos) << all.warnings[0];
  EXPECT_TRUE(test::load_scene(kBase).warnings.empty());  // the bottom face only
}

TEST(Scene, ARepeatedElementIsAWarningNamingIt) {
  // A 1 x 1 x 2 hexahedral box whose first element is listed again as element 2.
  preprocess::Mesh mesh = preprocess::make_box_mesh({1e-3, 1e-3, 2e-3}, {1, 1, 2}, "hex");
  const std::vector<preprocess::Index> first(mesh.element(0), mesh.element(0) + 8);
  mesh.connectivity.insert(mesh.connectivity.end(), first.begin(), first.end());
  mesh.labels.push_back(mesh.labels[0]);
  const auto file = std::filesystem::temp_directory_path() / "adamss-test-repeated-element.h5";
  preprocess::write_mesh_h5(file, mesh);
  std::string text = replaced(
      kBase,
      "{phantom: slab, slab_size: [2, 2, 3], voxel_size: 1 mm, topology: tet6m, fibre: [0, 0, 1], sheet: [1, 0, 0]}",
      "{file: " + file.string() + "}");
  text = replaced(text, "virtual_hexahedron: {law: svk,", "fem_element: {law: svk,");
  const auto sc = test::load_scene(text);
  ASSERT_EQ(sc.warnings.size(), 1u);
  EXPECT_NE(sc.warnings[0].find("1 element(s) repeat"), std::string::npos) << sc.warnings[0];
  EXPECT_NE(sc.warnings[0].find("elements 0 and 2"), std::string::npos) << sc.warnings[0];
  std::filesystem::remove(file);
}

TEST(Scene, BoundaryConditionsAndCourses) {
  const auto sc = test::load_scene(replaced(kBase, "    fix: xyz\n", R"(    fix: xyz
  - select: {region: {plane: {point: [0, 0, 3 mm], normal: [0, 0, 1], tolerance: 0.001 mm}}}
    control: {axis: z, displacement: {table: {times: [0, 1 ms], values: [0, 0.3 mm]}}}
  - select: {nodes: [13]}
    control: {axis: xy, velocity: {ramp: {to: 2 mm/s, duration: 1 ms}}}
)"));
  const auto& c = sc.model.constraints;
  EXPECT_EQ(c.controlled_dof_count(), 9u + 2u);
  EXPECT_NEAR(c.controls()[0].course(0.5e-3), 0.15e-3, 1e-15);
  EXPECT_TRUE(c.controls().back().velocity);
  EXPECT_NEAR(c.controls().back().course(1e-3), 2e-3, 1e-15);
  // The same coordinate twice is an error naming the entry.
  EXPECT_NE(test::scene_error(replaced(kBase, "    fix: xyz\n", R"(    fix: xyz
  - select: {nodes: [0]}
    control: {axis: z, displacement: 1 mm}
)"))
                .find("boundary[1]"),
            std::string::npos);
}

TEST(Scene, MeshRecipeIsCached) {
  const auto a = test::load_scene(kBase);
  ASSERT_TRUE(std::filesystem::exists(a.mesh_source));
  const auto t = std::filesystem::last_write_time(a.mesh_source);
  const auto b = test::load_scene(kBase);
  EXPECT_EQ(a.mesh_source, b.mesh_source);
  EXPECT_EQ(std::filesystem::last_write_time(b.mesh_source), t);
  EXPECT_NE(test::scene_error(replaced(kBase, "mesh: {phantom: slab,", "mesh: {file: nothing.h5, phantom: slab,"))
                .find("exactly one of file:, image:"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase,
                                       "mesh: {phantom: slab, slab_size: [2, 2, 3], voxel_size: 1 mm, topology: tet6m, "
                                       "fibre: [0, 0, 1], sheet: [1, 0, 0]}",
                                       "mesh: {file: nothing.h5}"))
                .find("does not exist"),
            std::string::npos);
}

TEST(Scene, InvalidYamlIsAnInputError) {
  EXPECT_NE(test::scene_error("mesh: [unclosed").find("not valid YAML"), std::string::npos);
  EXPECT_THROW(solver::load_scene("/nonexistent/scene.yaml"), InputError);
}

// A scar segment on the lv recipe (cell field `scar`, 0/1) splits the wall into two materials by
// `cell_field: {name, min, max}`; every element must belong to exactly one.
// Issue 24: a key given twice in one mapping is an error naming the key path and both lines
// (yaml-cpp would silently use the first, PyYAML the last), at the top level, in a nested block
// mapping, inside a list and in a flow mapping; the same key in two different mappings is fine.
TEST(Scene, DuplicateKeysAreErrorsNamingBothLines) {
  // kBase: line 1 is empty, "name: t" is line 2, "run: {t_end: 1 ms}" line 14.
  std::string e = test::scene_error(kBase + "run: {t_end: 2 ms}\n");
  EXPECT_NE(e.find("run: duplicate key 'run' on line 14 and line 15"), std::string::npos) << e;
  e = test::scene_error(
      replaced(kBase, "    density: 1000 kg/m^3\n", "    density: 1000 kg/m^3\n    density: 2000 kg/m^3\n"));
  EXPECT_NE(e.find("materials[0].density: duplicate key 'density' on line 7 and line 8"), std::string::npos) << e;
  e = test::scene_error(replaced(kBase, "{E: 10 kPa, nu: 0.3}", "{E: 10 kPa, nu: 0.3, E: 20 kPa}"));
  EXPECT_NE(e.find("materials[0].terms[0].virtual_hexahedron.parameters.E: duplicate key 'E' on line 9 and line 9"),
            std::string::npos)
      << e;
  EXPECT_EQ(test::scene_error(kBase), "");
  // An alias bomb (each level doubles the uses of the one below) is refused, not walked for ever.
  std::ostringstream bomb;
  bomb << "a0: &a0 [x, x]\n";
  for (int k = 1; k <= 25; ++k) bomb << 'a' << k << ": &a" << k << " [*a" << k - 1 << ", *a" << k - 1 << "]\n";
  e = test::scene_error(bomb.str());
  EXPECT_NE(e.find("YAML nodes"), std::string::npos) << e;
}

TEST(Scene, MaterialsSplitByACellField) {
  const std::string scene = R"(
name: scar
mesh: {phantom: lv, voxel_size: 2.5 mm, topology: tet6m, scar: {direction: [0, 1, -1], angle: 30 deg}}
materials:
  - name: healthy
    labels: [1]
    cell_field: {name: scar, max: 0.5}
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: hunter_canine}
      - active_tension: {tension: 10 kPa}
  - name: scar
    labels: [1]
    cell_field: {name: scar, min: 0.5}
    density: 1000 kg/m^3
    terms:
      - virtual_hexahedron: {law: hunter_canine, parameters: {k11: 28 kPa}}
boundary:
  - select: {tag: base}
    fix: xyz
integrator: {type: static, dt: 10 ms}
run: {t_end: 10 ms}
)";
  const auto sc = test::load_scene(scene);
  const auto& f = sc.model.mesh->cell_scalars.at("scar");
  const auto n_scar = (f.array() > 0.5).count();
  EXPECT_GT(n_scar, 0);
  EXPECT_LT(n_scar, f.size() / 4);
  EXPECT_EQ((f.array() * (1.0 - f.array())).abs().maxCoeff(), 0.0);  // 0/1 only
  int healthy = 0, scar = 0;
  for (const auto& line : sc.term_summary) {
    healthy += line.find("[material healthy]") != std::string::npos ? 1 : 0;
    scar += line.find("[material scar]") != std::string::npos ? 1 : 0;
  }
  EXPECT_EQ(healthy, 2);
  EXPECT_EQ(scar, 1);
  // Overlapping ranges, a missing field, a range with no element, a scar on a slab.
  EXPECT_NE(
      test::scene_error(replaced(scene, "{name: scar, min: 0.5}", "{name: scar, min: 0}")).find("already belongs"),
      std::string::npos);
  EXPECT_NE(test::scene_error(replaced(scene, "{name: scar, min: 0.5}", "{name: infarct, min: 0.5}"))
                .find("materials[1].cell_field.name: the mesh has no cell field 'infarct'"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(scene, "{name: scar, min: 0.5}", "{name: scar, min: 2}")).find("no element"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(scene, "{name: scar, min: 0.5}", "{name: scar, min: 1, max: 0}"))
                .find("min must be <= max"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(scene, "    cell_field: {name: scar, min: 0.5}\n", "")).find("already belongs"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(scene, "angle: 30 deg", "angle: 0 deg")).find("mesh.scar.angle"),
            std::string::npos);
  EXPECT_NE(test::scene_error(replaced(kBase, "voxel_size: 1 mm,", "voxel_size: 1 mm, scar: {},")).find("lv and biv"),
            std::string::npos);
}
