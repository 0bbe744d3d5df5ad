// adamss run SCENE.yaml -o OUT/: load and validate a scene, integrate, write results.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "solver/run/checkpoint.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"
#include "solver/scene/scene.hpp"

namespace adamss::app {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  std::string scene;
  std::string output;
  std::string cache;
  std::string petsc;
  std::string resume;
  std::size_t stop_after_steps = 0;
  bool check_only = false;
  bool quiet = false;
};

nlohmann::json vec(const Eigen::Vector3d& v) {
  return nlohmann::json::array({v.x(), v.y(), v.z()});
}

void write_summary(const fs::path& file, const solver::LoadedScene& sc, const solver::RunOutcome& out,
                   const solver::State& initial, const solver::ResultsWriter& writer) {
  using nlohmann::json;
  const solver::Model& m = sc.model;
  const solver::State& s = out.final_state;
  const double v0 = solver::total_volume(*m.mesh, m.x_ref);
  const double v1 = solver::total_volume(*m.mesh, s.x);
  json j;
  j["status"] = out.status;
  j["reason"] = out.reason;
  j["scene"] = sc.file.string();
  j["name"] = sc.name;
  j["mesh"] = sc.mesh_source;
  j["nodes"] = m.node_count();
  j["elements"] = m.mesh->element_count();
  j["element_type"] = preprocess::element_type_name(m.mesh->type);
  j["integrator"] = sc.run.integrator;
  j["steps"] = out.steps;
  j["simulated_time_s"] = out.t;
  j["t_end_s"] = sc.run.t_end;
  j["wall_time_s"] = out.wall_seconds;
  j["force_evaluations"] = out.force_evaluations;
  j["rejected_steps"] = out.rejected_steps;
  j["newton_iterations"] = out.newton_iterations;
  j["linear_iterations"] = out.linear_iterations;
  j["dt_s"] = {{"initial", sc.run.dt},
               {"min_used", out.dt_min_used},
               {"max_used", out.dt_max_used},
               {"critical_estimate", sc.critical_dt}};
  const double elem_steps = static_cast<double>(m.mesh->element_count()) * static_cast<double>(out.force_evaluations);
  j["ns_per_element_evaluation"] = elem_steps > 0 ? 1e9 * out.wall_seconds / elem_steps : 0.0;
  j["total_volume_m3"] = {{"initial", v0},
                          {"final", v1},
                          {"relative_change", (v1 - v0) / v0},
                          {"max_abs_relative_change", writer.max_volume_change()}};
  j["kinetic_energy_final_J"] = solver::kinetic_energy(m.mass, s.v);
  j["mass_kg"] = m.mass.sum();
  // "cavities": {NAME: {...}} keyed by the cavity name (`name` repeated inside each entry).
  json cav = json::object();
  for (std::size_t k = 0; k < m.cavities.size(); ++k) {
    const auto& c = m.cavities[k];
    json one = {{"name", c->name()},
                {"volume_initial_m3", c->volume(initial.x)},
                {"volume_final_m3", c->volume(s.x)},
                {"pressure_final_Pa", c->pressure(s.t)}};
    if (k < writer.cavity_extrema().size()) {
      const auto& e = writer.cavity_extrema()[k];
      one["volume_max_m3"] = e.max;
      one["volume_max_t_s"] = e.t_max;
      one["volume_min_m3"] = e.min;
      one["volume_min_t_s"] = e.t_min;
      one["ejection_fraction"] = e.max > 0 ? (e.max - e.min) / e.max : 0.0;
      // Beat metrics: from the volume extrema by default (EDV = largest, ESV = smallest volume,
      // the pressures at those times); a circulation overrides them with its valve-event values.
      one["edv_m3"] = e.max;
      one["esv_m3"] = e.min;
      one["edp_Pa"] = e.p_at_max;
      one["esp_Pa"] = e.p_at_min;
      one["stroke_volume_m3"] = e.max - e.min;
      one["peak_pressure_Pa"] = e.p_max;
    }
    for (const auto& [key, value] : c->metrics()) one[key] = value;
    const auto beats = c->beat_metrics();
    if (!beats.empty()) {
      json per_beat = json::array();
      for (const auto& b : beats) {
        json e = json::object();
        for (const auto& [key, value] : b) e[key] = value;
        per_beat.push_back(e);
      }
      one["per_beat"] = per_beat;
    }
    cav[c->name()] = one;
  }
  j["cavities"] = cav;
  j["fiber_stretch_max"] = writer.fibre_stretch_max();
  j["fiber_stretch_min"] = writer.fibre_stretch_min();
  // "probes": {NAME: [x, y, z]} (final positions, m); the details beside it.
  json probes = json::object(), details = json::object();
  for (const auto& p : m.probes) {
    probes[p.name] = vec(s.x.col(p.node));
    details[p.name] = {{"node", p.node},
                       {"reference_m", vec(m.x_ref.col(p.node))},
                       {"displacement_m", vec(s.x.col(p.node) - m.x_ref.col(p.node))}};
    // Rotation about the z axis (deg, counter-clockwise seen from +z) of the point's (x, y)
    // position: the twist of Land et al. 2015 problem 3. Omitted on the axis itself.
    const Eigen::Vector3d a = m.x_ref.col(p.node), b = s.x.col(p.node);
    if (a.head<2>().norm() > 1e-9 && b.head<2>().norm() > 1e-9) {
      const double cross = a.x() * b.y() - a.y() * b.x(), dot = a.x() * b.x() + a.y() * b.y();
      details[p.name]["twist_about_z_deg"] = std::atan2(cross, dot) * 180.0 / M_PI;
    }
  }
  j["probes"] = probes;
  j["probe_details"] = details;
  // Reactions: what each boundary entry's supports exert on the body in the final state,
  // R = -(sum of all term forces) on its particles (exact at equilibrium; in dynamics it also
  // carries the inertia of those particles), and its moment about the entry's reference centroid.
  {
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, s.x.cols());
    for (const auto& t : m.terms) t->add_forces({s.x, s.v, s.t}, f);
    json groups = json::array();
    for (const auto& g : m.boundary_groups) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero(), mo = Eigen::Vector3d::Zero();
      for (const auto n : g.nodes) c += m.x_ref.col(n);
      if (!g.nodes.empty()) c /= static_cast<double>(g.nodes.size());
      for (const auto n : g.nodes) {
        const Eigen::Vector3d rn = -f.col(n);
        r += rn;
        mo += (s.x.col(n) - c).cross(rn);
      }
      groups.push_back({{"entry", g.name},
                        {"nodes", g.nodes.size()},
                        {"reaction_force_N", vec(r)},
                        {"reaction_moment_Nm", vec(mo)},
                        {"moment_point_m", vec(c)}});
    }
    j["reactions"] = groups;
  }
  if (out.bad_element) j["bad_element"] = *out.bad_element;
  j["terms"] = sc.term_summary;
  j["axis_frame_elements"] = sc.axis_frame_elements;
  j["warnings"] = sc.warnings;
  j["boundary"] = {{"fixed_dofs", m.constraints.fixed_dof_count()},
                   {"controlled_dofs", m.constraints.controlled_dof_count()}};
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream o(tmp);
    o << std::setw(2) << j << "\n";
    if (!o) throw InputError("cannot write " + tmp.string());
  }
  fs::rename(tmp, file);
}

int run_scene(const RunArgs& a) {
  solver::SceneOptions so;
  so.cache_dir = a.cache;
  const auto t0 = std::chrono::steady_clock::now();
  solver::LoadedScene sc = solver::load_scene(a.scene, so);
  const double t_load = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const solver::Model& m = sc.model;
  if (!a.quiet || a.check_only) {
    std::cout << "scene " << sc.name << ": " << m.node_count() << " particles, " << m.mesh->element_count() << " "
              << preprocess::element_type_name(m.mesh->type) << " elements, mass " << m.mass.sum() << " kg (mesh "
              << sc.mesh_source << ", loaded in " << std::setprecision(3) << t_load << " s)\n";
    for (const auto& t : sc.term_summary) std::cout << "  term " << t << "\n";
    std::cout << "  boundary: " << m.constraints.fixed_dof_count() << " fixed and "
              << m.constraints.controlled_dof_count() << " controlled coordinates\n"
              << "  " << sc.run.integrator << ", dt " << sc.run.dt << " s, t_end " << sc.run.t_end << " s";
    if (sc.critical_dt > 0) std::cout << ", critical step estimate " << sc.critical_dt << " s";
    std::cout << "\n";
    for (const auto& w : sc.warnings) std::cerr << "adamss: warning: " << w << "\n";
  }
  if (!a.petsc.empty()) sc.run.implicit.petsc_options += " " + a.petsc;
  if (a.check_only) return 0;
  // --resume: the whole checkpoint is read (and checked against the scene) before anything in
  // the output folder changes; the results continue in the checkpoint's folder by default.
  std::optional<solver::StateArchive> checkpoint;
  std::optional<solver::StateArchive> writer_state;
  fs::path output = a.output;
  if (!a.resume.empty()) {
    checkpoint = solver::StateArchive::read_hdf5(a.resume);
    solver::check_checkpoint(sc.model, sc.run, *checkpoint);
    writer_state = checkpoint->child("writer");
    if (output.empty()) output = fs::path(a.resume).parent_path();
    if (output.empty()) output = ".";
  }
  if (output.empty()) throw InputError("-o/--output is required (the results folder)");

  solver::ResultsWriter writer(output, sc.model, writer_state ? &*writer_state : nullptr);
  solver::State s = sc.initial;
  const solver::State initial = s;
  sc.run.progress = !a.quiet;
  sc.run.stop_after_steps = a.stop_after_steps;
  const solver::RunOutcome out =
      solver::run_simulation(sc.model, s, sc.run, writer, checkpoint ? &*checkpoint : nullptr);
  write_summary(writer.dir() / "summary.json", sc, out, initial, writer);
  if (!a.quiet) {
    std::cout << out.status << " (" << out.reason << "): " << out.steps << " steps to t = " << out.t << " s in "
              << out.wall_seconds << " s wall, " << writer.frame_count() << " frames; results in " << output.string()
              << "\n";
  }
  if (out.status == "unstable" || out.status == "failed") {
    throw NumericalError("run " + out.status + ": " + out.reason);
  }
  if (out.status == "interrupted") return 130;
  return 0;
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* sub = app.add_subcommand(
      "run",
      "Run a scene: build the model it describes (mesh, materials and force terms, loads, boundary conditions), "
      "integrate in time and write OUT/summary.json, OUT/globals.csv, OUT/series.pvd with frames. "
      "Keys of the scene file: docs/scene-reference.md.");
  sub->add_option("scene", args->scene, "Scene file (.yaml)")->required();
  sub->add_option("-o,--output", args->output, "Results folder (created)");
  sub->add_option("--cache", args->cache,
                  "Folder for meshes built from scene recipes (default $ADAMSS_CACHE_DIR or ~/.cache/adamss)");
  sub->add_option("--petsc", args->petsc,
                  "PETSc options for the implicit and static integrators, e.g. \"-ksp_monitor -pc_type gamg\" "
                  "(added after the scene's integrator.petsc_options)");
  sub->add_option("--resume", args->resume,
                  "Continue an interrupted run from its checkpoint (OUT/checkpoint.h5, written on SIGINT/SIGTERM "
                  "and every output.checkpoint_interval): the result equals the uninterrupted run bit for bit. "
                  "The results continue in -o (default: the checkpoint's folder)");
  sub->add_option("--stop-after-steps", args->stop_after_steps,
                  "Stop as on SIGINT (checkpoint, status interrupted) once this many steps are done (tests)")
      ->group("");
  sub->add_flag("--check", args->check_only, "Validate the scene and print the model summary, do not run");
  sub->add_flag("-q,--quiet", args->quiet, "No progress line and no summary on stdout");
  sub->callback([args]() {
    const int rc = run_scene(*args);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace adamss::app
