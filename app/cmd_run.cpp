// adamss run SCENE.yaml -o OUT/: load and validate a scene, integrate, write results.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "common/units.hpp"
#include "solver/core/penalty_continuation.hpp"
#include "solver/run/checkpoint.hpp"
#include "solver/run/output_lock.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"
#include "solver/run/summary.hpp"
#include "solver/scene/scene.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::app {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  std::string scene;
  std::string output;
  std::string cache;
  std::string petsc;
  std::string resume;
  std::string reference;
  std::size_t stop_after_steps = 0;
  bool check_only = false;
  bool quiet = false;
  bool resume_modified = false;
  std::string progress_interval;  ///< --progress-interval (a time; empty: the default, 10 s)
  double t_load = 0.0;            ///< seconds the scene took to load (for the model summary)
  int rank = 0, ranks = 1;        ///< this process's MPI rank and the number of ranks
};

nlohmann::json vec(const Eigen::Vector3d& v) {
  return nlohmann::json::array({v.x(), v.y(), v.z()});
}

/// "cavities": {NAME: {...}} keyed by the cavity name (`name` repeated inside each entry).
nlohmann::json cavities_json(const std::vector<solver::CavitySummary>& cavities) {
  using nlohmann::json;
  json cav = json::object();
  for (const auto& c : cavities) {
    json one = {{"name", c.name}};
    for (const auto& [key, value] : c.values) one[key] = value;
    if (!c.per_beat.empty()) {
      json per_beat = json::array();
      for (const auto& b : c.per_beat) {
        json e = json::object();
        for (const auto& [key, value] : b) e[key] = value;
        per_beat.push_back(e);
      }
      one["per_beat"] = per_beat;
    }
    cav[c.name] = one;
  }
  return cav;
}

/// "probes": {NAME: [x, y, z]} (final positions, m) and "probe_details" beside it.
void add_probes(nlohmann::json& j, const std::vector<solver::ProbeSummary>& probes) {
  using nlohmann::json;
  json positions = json::object(), details = json::object();
  for (const auto& p : probes) {
    positions[p.name] = vec(p.final_position);
    details[p.name] = {{"node", p.node}, {"reference_m", vec(p.reference)}, {"displacement_m", vec(p.displacement)}};
    if (p.twist_about_z_deg) details[p.name]["twist_about_z_deg"] = *p.twist_about_z_deg;
  }
  j["probes"] = positions;
  j["probe_details"] = details;
}

nlohmann::json reactions_json(const std::vector<solver::ReactionSummary>& reactions) {
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& g : reactions) {
    groups.push_back({{"entry", g.entry},
                      {"nodes", g.nodes},
                      {"reaction_force_N", vec(g.force)},
                      {"reaction_moment_Nm", vec(g.moment)},
                      {"moment_point_m", vec(g.moment_point)}});
  }
  return groups;
}

/// summary.json "time_split_s": seconds and calls per kind of work of this process's loop, and the rest.
nlohmann::json time_split_json(const solver::RunOutcome& out) {
  const auto part = [](const solver::TimePart& p) {
    return nlohmann::json{{"seconds", p.seconds}, {"calls", p.count}};
  };
  const solver::TimeSplit& t = out.time_split;
  return {{"loop", out.loop_seconds},       {"forces", part(t.forces)},
          {"jacobians", part(t.jacobians)}, {"factorisations", part(t.factorisations)},
          {"solves", part(t.solves)},       {"other", out.loop_seconds - t.seconds()}};
}

/// summary.json (docs/file-formats.md): the scene's description, the run's counters and the
/// numbers of solver::summarize_run.
nlohmann::json summary_json(const solver::LoadedScene& sc, const solver::RunOutcome& out,
                            const solver::RunSummary& sum) {
  const solver::Model& m = sc.model;
  nlohmann::json j;
  j["status"] = out.status;
  j["reason"] = out.reason;
  j["scene"] = sc.file.string();
  j["name"] = sc.name;
  j["mesh"] = sc.mesh_source;
  if (!sc.reference_file.empty()) j["reference_mesh"] = sc.reference_file.string();
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
  j["reformations"] = out.reformations;
  j["linear_iterations"] = out.linear_iterations;
  j["time_split_s"] = time_split_json(out);
  if (!solver::augmented_terms(m.terms).empty()) {  // also when no update was needed
    j["augmented_lagrangian"] = {{"updates", out.augmentations},
                                 {"max_volume_ratio_violation", out.max_constraint_violation}};
  }
  if (!solver::continued_terms(m.terms).empty()) {
    j["penalty_continuation"] = {{"re_solves", out.continuation_solves}};
  }
  if (sc.run.implicit.static_damping > 0.0) {  // the viscous regularisation (integrator.static_damping)
    j["static_damping"] = {{"zeta_per_s", sc.run.implicit.static_damping}, {"work_J", out.damping_work}};
  }
  // Resident memory (MB; null = not sampled, e.g. a run shorter than a quarter of t_end).
  const auto mb = [](double v) { return v >= 0.0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
  j["resident_memory_MB"] = {{"start", mb(out.resident_mb.start)},
                             {"at_quarter_of_t_end", mb(out.resident_mb.quarter)},
                             {"final", mb(out.resident_mb.final)},
                             {"peak", mb(out.resident_mb.peak)}};
  j["dt_s"] = {{"initial", sc.run.dt},
               {"min_used", out.dt_min_used},
               {"max_used", out.dt_max_used},
               {"critical_estimate", sc.critical_dt}};
  j["ns_per_element_evaluation"] = sum.ns_per_element_evaluation;
  j["total_volume_m3"] = {{"initial", sum.volume_initial},
                          {"final", sum.volume_final},
                          {"relative_change", sum.volume_relative_change},
                          {"max_abs_relative_change", sum.volume_max_abs_relative_change}};
  j["kinetic_energy_final_J"] = sum.kinetic_energy_final;
  j["mass_kg"] = sum.mass;
  j["cavities"] = cavities_json(sum.cavities);
  j["fiber_stretch_max"] = sum.fibre_stretch_max;
  j["fiber_stretch_min"] = sum.fibre_stretch_min;
  add_probes(j, sum.probes);
  j["reactions"] = reactions_json(sum.reactions);
  if (m.long_axis) {
    j["long_axis"] = {{"point_m", vec(m.long_axis->point)},
                      {"direction", vec(m.long_axis->direction)},
                      {"source", m.long_axis->source}};
  }
  if (out.bad_element) j["bad_element"] = *out.bad_element;
  j["terms"] = sc.term_summary;
  j["axis_frame_elements"] = sc.axis_frame_elements;
  j["warnings"] = sc.warnings;
  j["boundary"] = {{"fixed_dofs", m.constraints.fixed_dof_count()},
                   {"controlled_dofs", m.constraints.controlled_dof_count()}};
  return j;
}

/// After an I/O error during the run: summary.json says "failed" with the reason, if it can still
/// be written (the disk may be full); the error itself is then reported by main() (exit 4).
void record_io_failure(const fs::path& dir, const solver::LoadedScene& sc, const std::string& reason) {
  const nlohmann::json j = {{"status", "failed"},        {"reason", "I/O error: " + reason},
                            {"scene", sc.file.string()}, {"name", sc.name},
                            {"mesh", sc.mesh_source},    {"integrator", sc.run.integrator}};
  try {
    write_json(dir / "summary.json", j);
  } catch (const IoError&) {
    std::cerr << "adamss: warning: summary.json could not be written either\n";
  }
}

/// The model summary `adamss run` prints before it runs (and `--check` prints alone), a line each.
std::vector<std::string> model_lines(const solver::LoadedScene& sc, double t_load) {
  const solver::Model& m = sc.model;
  std::vector<std::string> lines;
  std::ostringstream o;
  o << "scene " << sc.name << ": " << m.node_count() << " particles, " << m.mesh->element_count() << " "
    << preprocess::element_type_name(m.mesh->type) << " elements, mass " << m.mass.sum() << " kg (mesh "
    << sc.mesh_source << (sc.reference_file.empty() ? "" : ", node positions from " + sc.reference_file.string())
    << ", loaded in " << std::setprecision(3) << t_load << " s)";
  lines.push_back(o.str());
  for (const auto& t : sc.term_summary) lines.push_back("  term " + t);
  o.str("");
  o << "  boundary: " << m.constraints.fixed_dof_count() << " fixed and " << m.constraints.controlled_dof_count()
    << " controlled coordinates";
  lines.push_back(o.str());
  o.str("");
  o << "  " << sc.run.integrator << ", dt " << sc.run.dt << " s, t_end " << sc.run.t_end << " s";
  if (sc.critical_dt > 0) o << ", critical step estimate " << sc.critical_dt << " s";
  lines.push_back(o.str());
  return lines;
}

void print_model(const solver::LoadedScene& sc, double t_load) {
  for (const std::string& l : model_lines(sc, t_load)) std::cout << l << "\n";
  for (const auto& w : sc.warnings) std::cerr << "adamss: warning: " << w << "\n";
}

/// What run.log starts with: the command, the model summary and the scene's warnings.
void log_header(solver::RunLog& log, const solver::LoadedScene& sc, const RunArgs& a, const fs::path& output) {
  std::string cmd = "adamss run " + a.scene + " -o " + output.string();
  if (!a.resume.empty()) cmd += " --resume " + a.resume + (a.resume_modified ? " --resume-modified" : "");
  if (!a.petsc.empty()) cmd += " --petsc '" + a.petsc + "'";
  if (!a.reference.empty()) cmd += " --reference " + a.reference;
  log.line(cmd);
  for (const std::string& l : model_lines(sc, a.t_load)) log.line(l);
  if (a.ranks > 1) {
    log.line("  MPI: " + std::to_string(a.ranks) +
             " ranks (each holds the model; the Jacobian's rows and the linear solve are distributed)");
  }
  for (const auto& w : sc.warnings) log.line("warning: " + w);
}

/// The results folder: -o, else (with --resume) the checkpoint's folder.
fs::path output_folder(const RunArgs& a) {
  fs::path output = a.output;
  if (output.empty() && !a.resume.empty()) {
    output = fs::path(a.resume).parent_path();
    if (output.empty()) output = ".";
  }
  if (output.empty()) throw InputError("-o/--output is required (the results folder)");
  return output;
}

/// Runs the loaded scene into `output` (locked by the caller) and writes summary.json. Nothing
/// in the folder changes before the run is built (ResultsWriter::open, called by the loop); an
/// I/O error on the way is recorded in summary.json and rethrown.
solver::RunOutcome run_into(solver::LoadedScene& sc, const RunArgs& a, const fs::path& output) {
  // --resume: the whole checkpoint is read (and checked against the scene) before anything in
  // the output folder changes.
  std::optional<solver::StateArchive> checkpoint;
  std::optional<solver::StateArchive> writer_state;
  std::vector<std::string> changes;  // --resume-modified: what differs from the checkpoint's run
  if (!a.resume.empty()) {
    checkpoint = solver::StateArchive::read_hdf5(a.resume);
    solver::check_checkpoint(sc.model, sc.run, *checkpoint);
    writer_state = checkpoint->child("writer");
    changes = solver::checkpoint_changes(sc.run, *checkpoint);
    if (a.rank == 0) {  // every rank reads the checkpoint; one reports what changed
      for (const std::string& c : changes) std::cerr << "adamss: warning: --resume-modified: " << c << "\n";
    }
  }
  solver::ResultsWriter writer(output, sc.model, writer_state ? &*writer_state : nullptr);
  const bool writes = a.rank == 0;  // several MPI ranks: rank 0 writes, the others hold the same state
  if (!writes) writer.mute();
  solver::State s = sc.initial;
  const solver::State initial = s;
  sc.run.progress = !a.quiet;
  sc.run.stop_after_steps = a.stop_after_steps;
  if (!a.progress_interval.empty()) {
    sc.run.progress_interval =
        common::parse_quantity(a.progress_interval, common::Dimension::Time, "--progress-interval");
    if (!(sc.run.progress_interval >= 0.0)) throw InputError("--progress-interval: must be >= 0");
  }
  log_header(writer.log(), sc, a, output);
  for (const std::string& c : changes) writer.log().line("warning: --resume-modified: " + c);
  try {
    solver::RunOutcome out = solver::run_simulation(sc.model, s, sc.run, writer, checkpoint ? &*checkpoint : nullptr);
    if (!writes) {
      solver::barrier_ranks();  // rank 0 writes the summary (and a failed run's last files) first
      return out;
    }
    nlohmann::json j = summary_json(sc, out, solver::summarize_run(sc.model, out, initial, writer));
    if (!changes.empty()) j["resume_modified"] = changes;
    j["mpi_ranks"] = a.ranks;
    write_json(writer.dir() / "summary.json", j);
    std::ostringstream done;
    done << out.status << " (" << out.reason << "): " << out.steps << " steps to t = " << out.t << " s in "
         << out.wall_seconds << " s wall, " << writer.frame_count() << " frames; results in " << output.string();
    writer.log().line(done.str());
    if (!a.quiet) std::cout << done.str() << "\n";
    solver::barrier_ranks();
    return out;
  } catch (const IoError& e) {
    if (writer.started()) record_io_failure(writer.dir(), sc, e.what());
    throw;
  }
}

/// The content hash of the mesh file the scene names; 0 for a mesh the scene builds (a recipe's
/// file in the cache, or no file): the scene's text covers those, and a rebuilt cache file need
/// not be byte-identical (HDF5 object times). Mixed with the reference file's hash when there is one.
std::uint64_t mesh_file_hash(const solver::LoadedScene& sc, const RunArgs& a) {
  std::uint64_t h = 0;
  std::error_code ec;
  if (fs::is_regular_file(sc.mesh_source, ec)) {
    const fs::path cache = fs::weakly_canonical(a.cache.empty() ? solver::default_cache_dir() : fs::path(a.cache), ec);
    const fs::path mesh = fs::weakly_canonical(sc.mesh_source, ec);
    const auto [c, m] = std::mismatch(cache.begin(), cache.end(), mesh.begin(), mesh.end());
    if (c != cache.end()) h = solver::content_hash(mesh);  // outside the cache
  }
  // A reference configuration (mesh.reference, --reference) is part of the mesh: a resume from
  // another one, or without it, is a changed mesh.
  if (!sc.reference_file.empty()) h = h * 1099511628211ULL ^ solver::content_hash(sc.reference_file);
  return h;
}

/// Loads the scene; on several MPI ranks rank 0 first (it may build the scene's mesh into the
/// cache), then the others, which find it there.
solver::LoadedScene load_on_ranks(const RunArgs& a, const solver::SceneOptions& so) {
  if (a.rank > 0) solver::barrier_ranks();
  solver::LoadedScene sc = solver::load_scene(a.scene, so);
  if (a.rank == 0) solver::barrier_ranks();
  return sc;
}

/// On several MPI ranks an error may be this rank's alone (rank 0's disk): it is printed here,
/// naming the rank, and every rank ends (MPI_Abort) with the exit status main() would give it.
/// Nothing happens on one rank (main() reports the error).
void abort_ranks_after(const std::exception& e) {
  if (solver::mpi_size() <= 1) return;
  const ErrorReport r = error_report(e);
  const std::string line = "adamss: " + std::string(r.label) + " (MPI rank " + std::to_string(solver::mpi_rank()) +
                           " of " + std::to_string(solver::mpi_size()) + "): " + e.what() + "\n";
  write_stderr_line(line);
  solver::abort_other_ranks(r.exit_status);
}

int run_scene(RunArgs a) {
  // Under mpirun every rank runs this; rank 0 prints and writes (solver/time/petsc/petsc_env.hpp).
  a.rank = solver::mpi_rank();
  a.ranks = solver::mpi_size();
  if (a.rank > 0) a.quiet = true;
  solver::SceneOptions so;
  so.cache_dir = a.cache;
  so.reference_file = a.reference;
  const auto t0 = std::chrono::steady_clock::now();
  solver::LoadedScene sc = load_on_ranks(a, so);
  const double t_load = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if ((!a.quiet || a.check_only) && a.rank == 0) {
    print_model(sc, t_load);
    if (a.ranks > 1) std::cout << "  MPI: " << a.ranks << " ranks\n";
  }
  a.t_load = t_load;
  if (!a.petsc.empty()) sc.run.implicit.petsc_options += " " + a.petsc;
  if (a.check_only) return 0;
  if (a.resume_modified && a.resume.empty()) throw InputError("--resume-modified: only with --resume FILE");
  sc.run.scene_hash = solver::content_hash(sc.file);
  sc.run.mesh_hash = mesh_file_hash(sc, a);
  sc.run.resume_modified = a.resume_modified;
  const fs::path output = output_folder(a);
  std::optional<solver::OutputLock> lock;  // one run per folder; released when this run ends
  if (a.rank == 0) lock.emplace(output);
  const solver::RunOutcome out = run_into(sc, a, output);
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
      "Keys of the scene file: docs/scene-reference.md. Runs on several MPI ranks under mpirun -np N "
      "(docs/parallel.md).");
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
  sub->add_option("--reference", args->reference,
                  "Start from this reference configuration: a mesh file of the scene's elements whose node "
                  "positions replace the mesh's (OUT/unloaded_mesh.h5 of adamss unload), as the scene key "
                  "mesh.reference");
  sub->add_flag("--resume-modified", args->resume_modified,
                "With --resume: continue although the scene or its mesh file changed since the checkpoint "
                "(refused otherwise); summary.json lists what changed under resume_modified");
  sub->add_option("--stop-after-steps", args->stop_after_steps,
                  "Stop as on SIGINT (checkpoint, status interrupted) once this many steps are done (tests)")
      ->group("");
  sub->add_flag("--check", args->check_only, "Validate the scene and print the model summary, do not run");
  sub->add_flag("-q,--quiet", args->quiet, "No progress line and no summary on stdout (run.log is still written)");
  sub->add_option("--progress-interval", args->progress_interval,
                  "Wall time between progress lines when stderr is not a terminal (batch logs) and between the "
                  "progress lines of OUT/run.log, e.g. 30s; 0: every step (default 10 s)");
  sub->callback([args]() {
    int rc = 0;
    try {
      rc = run_scene(*args);
    } catch (const std::exception& e) {
      abort_ranks_after(e);
      throw;
    }
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace adamss::app
