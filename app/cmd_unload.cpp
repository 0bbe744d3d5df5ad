// adamss unload SCENE.yaml -o OUT/: the reference configuration of a mesh imaged under the scene's
// loads (solver/run/unload.hpp), written as a mesh file that a scene takes with mesh.reference.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "preprocess/mesh/mesh_quality.hpp"
#include "solver/run/output_lock.hpp"
#include "solver/run/run_log.hpp"
#include "solver/run/unload.hpp"

namespace adamss::app {
namespace {

namespace fs = std::filesystem;

struct UnloadArgs {
  std::string scene;
  std::string output;
  std::string cache;
  std::string petsc;
  std::string tolerance = "10 um";
  int max_iterations = 20;
  double relaxation = 1.0;
  bool quiet = false;
};

/// One line per iteration, for the terminal and unload.log.
std::string iteration_line(const solver::UnloadIteration& it) {
  std::ostringstream o;
  o << "iteration " << it.k;
  if (it.k > 0) o << " (step factor " << it.omega << ")";
  if (it.status != "completed") {
    o << ": loading " << it.status << " (" << it.reason << ")";
    return o.str();
  }
  o << std::setprecision(4) << ": max |x(X) - x*| " << it.max_error * 1e3 << " mm (node " << it.worst_node << "), rms "
    << it.rms_error * 1e3 << " mm; " << it.steps << " load steps, " << it.newton_iterations << " Newton ("
    << it.reformations << " factorised), " << it.wall_seconds << " s";
  for (const auto& c : it.cavities)
    o << "; " << c.name << " " << c.reference * 1e6 << " -> " << c.loaded * 1e6 << " ml";
  return o.str();
}

nlohmann::json result_json(const solver::UnloadResult& r, const UnloadArgs& a, double tolerance) {
  using nlohmann::json;
  json its = json::array();
  for (const auto& it : r.iterations) {
    json cav = json::object();
    for (const auto& c : it.cavities) cav[c.name] = {{"reference_m3", c.reference}, {"loaded_m3", c.loaded}};
    json worst = nullptr;  // where the largest distance is: the node and its imaged position
    if (it.worst_node >= 0) {
      const Eigen::Vector3d p = r.mesh->nodes.col(it.worst_node);
      worst = {{"node", it.worst_node}, {"image_position_m", {p.x(), p.y(), p.z()}}};
    }
    const bool done = it.status == "completed";  // a failed loading has no distances
    its.push_back({{"iteration", it.k},
                   {"max_error_at", worst},
                   {"step_factor", it.omega},
                   {"status", it.status},
                   {"reason", it.reason},
                   {"max_error_m", done ? json(it.max_error) : json(nullptr)},
                   {"rms_error_m", done ? json(it.rms_error) : json(nullptr)},
                   {"steps", it.steps},
                   {"newton_iterations", it.newton_iterations},
                   {"reformations", it.reformations},
                   {"wall_time_s", it.wall_seconds},
                   {"cavities", cav}});
  }
  json imaged = json::object();
  for (const auto& [name, v] : r.imaged_volumes) imaged[name] = v;
  json j = {{"scene", a.scene},         {"converged", r.converged}, {"stop", r.stop},
            {"tolerance_m", tolerance}, {"best_iteration", r.best}, {"imaged_cavity_volumes_m3", imaged},
            {"iterations", its}};
  if (r.best >= 0) {
    j["max_error_m"] = r.iterations[static_cast<std::size_t>(r.best)].max_error;
    j["unloaded_mesh"] = "unloaded_mesh.h5";
  }
  return j;
}

/// unloaded_mesh.h5 (and .vtu for linear elements): the scene's mesh at the best reference found.
void write_unloaded_mesh(const fs::path& dir, const solver::UnloadResult& r) {
  preprocess::Mesh m = *r.mesh;
  m.nodes = r.reference;
  m.attributes["unloaded_from"] = "adamss unload";
  preprocess::write_mesh_h5(dir / "unloaded_mesh.h5", m);
  if (m.type == preprocess::ElementType::Tet4 || m.type == preprocess::ElementType::Hex8) {
    const preprocess::QualitySummary q = preprocess::summarize_quality(m);
    preprocess::write_mesh_vtu(dir / "unloaded_mesh.vtu", m, q.element_volume, q.element_min_dihedral);
  }
}

/// An earlier unloading's outputs in `out` go to out/previous/ (replacing an older one), so that
/// nothing stale sits beside the new ones and nothing is deleted.
void move_previous(const fs::path& out) {
  const char* names[] = {"unload.json", "unload.log", "unloaded_mesh.h5", "unloaded_mesh.vtu", "iterations"};
  std::error_code ec;
  bool any = false;
  for (const char* n : names) any = any || fs::exists(out / n, ec);
  if (!any) return;
  const fs::path prev = out / "previous";
  fs::remove_all(prev, ec);
  fs::create_directories(prev, ec);
  for (const char* n : names) {
    if (!fs::exists(out / n, ec)) continue;
    fs::rename(out / n, prev / n, ec);
    if (ec) throw IoError("cannot move " + (out / n).string() + " into " + prev.string() + ": " + ec.message());
  }
}

int run_unload(const UnloadArgs& a) {
  if (a.output.empty()) throw InputError("-o/--output is required (the results folder)");
  solver::UnloadSettings set;
  set.tolerance = parse_length(a.tolerance, "--tolerance");
  set.max_iterations = a.max_iterations;
  set.relaxation = a.relaxation;
  set.petsc_options = a.petsc;
  set.cache_dir = a.cache;
  solver::check_unload_settings(set);  // before anything is written
  if (!fs::exists(a.scene)) throw InputError("cannot open scene file '" + a.scene + "'");
  const fs::path out = a.output;
  const solver::OutputLock lock(out);
  move_previous(out);
  solver::RunLog log(out / "unload.log");
  log.open(false);
  log.line("adamss unload " + a.scene + " -o " + a.output + " --tolerance " + a.tolerance);
  const auto report = [&](const solver::UnloadIteration& it) {
    const std::string line = iteration_line(it);
    log.line(line);
    if (!a.quiet) std::cout << line << std::endl;
  };
  const solver::UnloadResult r = solver::unload(a.scene, set, out, report);
  if (r.best >= 0) write_unloaded_mesh(out, r);
  write_json(out / "unload.json", result_json(r, a, set.tolerance));
  std::ostringstream done;
  done << (r.converged ? "converged" : "not converged") << " (" << r.stop << ") after " << r.iterations.size()
       << " iterations";
  if (r.best >= 0) {
    done << "; best: iteration " << r.best << ", max |x(X) - x*| "
         << r.iterations[static_cast<std::size_t>(r.best)].max_error * 1e3 << " mm; "
         << (out / "unloaded_mesh.h5").string();
  }
  log.line(done.str());
  if (!a.quiet) std::cout << done.str() << "\n";
  if (!r.iterations.empty() && r.iterations.back().status == "interrupted") return 130;
  if (!r.converged) throw NumericalError("unload: " + done.str());
  return 0;
}

}  // namespace

void add_unload_command(CLI::App& app) {
  auto args = std::make_shared<UnloadArgs>();
  CLI::App* sub = app.add_subcommand(
      "unload",
      "Find the unloaded reference configuration of a mesh imaged under load (e.g. a heart at end-diastole): "
      "backward-displacement iterations X <- X - (x(X) - x*), each a static run of the scene from X to t_end. "
      "Writes OUT/unloaded_mesh.h5 (use it with mesh: {..., reference: OUT/unloaded_mesh.h5}), "
      "OUT/unloaded_mesh.vtu, OUT/unload.json, OUT/unload.log and each iteration's run in OUT/iterations/NN.");
  sub->add_option("scene", args->scene, "Scene file (.yaml) whose loads at t_end are those of the image")->required();
  sub->add_option("-o,--output", args->output, "Results folder (created)");
  sub->add_option("--tolerance", args->tolerance,
                  "Largest node distance accepted between the re-loaded reference and the image, e.g. 10um "
                  "(default 10 um)");
  sub->add_option("--max-iterations", args->max_iterations,
                  "Iteration limit, counting iteration 0, the loading of the image itself (default 20)");
  sub->add_option("--relaxation", args->relaxation,
                  "Step factor omega in (0, 1] of X <- X - omega (x(X) - x*) (default 1; halved automatically when "
                  "the error grows)");
  sub->add_option("--cache", args->cache, "Folder for meshes built from scene recipes (as for adamss run)");
  sub->add_option("--petsc", args->petsc, "PETSc options for the static solves (as for adamss run)");
  sub->add_flag("-q,--quiet", args->quiet, "No lines on stdout (unload.log is still written)");
  sub->callback([args]() {
    const int rc = run_unload(*args);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace adamss::app
