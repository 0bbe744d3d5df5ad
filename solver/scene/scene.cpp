#include "solver/scene/scene.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "preprocess/mesh/element_faces.hpp"
#include "solver/scene/scene_loads.hpp"
#include "solver/scene/scene_materials.hpp"
#include "solver/scene/scene_mesh.hpp"
#include "solver/terms/loads/gravity.hpp"
#include "solver/terms/loads/node_springs.hpp"

namespace adamss::solver {

namespace fs = std::filesystem;
using common::Dimension;

namespace {

/// Shortest element edge (m), for the critical step; collapsed edges (repeated node indices of a
/// degenerate hexahedron) are not edges.
double shortest_edge(const preprocess::Mesh& mesh) {
  using preprocess::kHexEdges;
  using preprocess::kTetEdges;
  double l = std::numeric_limits<double>::infinity();
  const bool tet = preprocess::is_tetrahedron(mesh.type);
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const preprocess::Index* n = mesh.element(e);
    const int ne = tet ? 6 : 12;
    for (int k = 0; k < ne; ++k) {
      const int a = tet ? kTetEdges[k][0] : kHexEdges[k][0];
      const int b = tet ? kTetEdges[k][1] : kHexEdges[k][1];
      if (n[a] == n[b]) continue;  // a collapsed edge of a degenerate hexahedron
      l = std::min(l, (mesh.nodes.col(n[a]) - mesh.nodes.col(n[b])).norm());
    }
  }
  // Quadratic elements: a quarter of the corner edge. A 1D quadratic element of length L with
  // HRZ masses has omega_max = sqrt(24) c / L, i.e. a critical step 0.41 L / c rather than the
  // 0.5 L / c of its node spacing, and the 3D corners carry only 1/36 of the mass: L / 4 keeps the
  // estimate on the safe side. The hex27 is the same 1D element along each edge (row-sum masses
  // 1/6, 2/3, 1/6 per direction; its corners carry 1/216): the same quarter.
  return preprocess::is_quadratic(mesh.type) ? 0.25 * l : l;
}

std::vector<Index> select(SceneNode sel, const Model& model, const fs::path& base) {
  std::vector<Index> nodes;
  int kinds = 0;
  if (sel.has("region")) {
    ++kinds;
    nodes = select_nodes(model.x_ref, sel.region("region"), sel.at("region"));
  }
  if (sel.has("tag")) {
    ++kinds;
    nodes = select_nodes_by_tag(*model.mesh, sel.text("tag"), sel.at("tag"));
  }
  if (sel.has("cavity_rim")) {
    ++kinds;
    nodes = select_cavity_rim(*model.mesh, sel.text("cavity_rim"), sel.at("cavity_rim"));
  }
  if (sel.has("file")) {
    ++kinds;
    fs::path p = sel.text("file");
    if (p.is_relative()) p = base / p;
    nodes = read_node_file(p.string(), model.node_count(), sel.at("file"));
  }
  if (sel.has("nodes")) {
    ++kinds;
    for (const long long i : sel.integers("nodes")) {
      if (i < 0 || static_cast<std::size_t>(i) >= model.node_count())
        throw InputError(sel.at("nodes") + ": node " + std::to_string(i) + " is outside the mesh");
      nodes.push_back(static_cast<Index>(i));
    }
  }
  if (kinds != 1) throw InputError(sel.path() + ": give exactly one of region, tag, cavity_rim, file, nodes");
  sel.finish();
  return nodes;
}

void load_boundary(std::vector<SceneNode> entries, LoadedScene& sc, const fs::path& base) {
  Model& model = sc.model;
  for (SceneNode& b : entries) {
    const std::vector<Index> nodes = select(b.map("select"), model, base);
    const bool fix = b.has("fix"), ctl = b.has("control"), spring = b.has("spring");
    if (int(fix) + int(ctl) + int(spring) != 1)
      throw InputError(b.path() + ": give exactly one of fix: (axes), control: {...} or spring: {...}");
    if (spring) {
      SceneNode sp = b.map("spring");
      const std::uint8_t axes = parse_axes(sp.text("axis", "xyz"), sp.at("axis"));
      const double k = sp.positive("stiffness", Dimension::Stiffness, 0.0, true);
      const double c = sp.positive("damping", Dimension::Damping, 0.0, true);
      sp.finish();
      model.terms.push_back(make_node_spring_term(b.path(), nodes, model.x_ref, axes, k, c));
      model.boundary_groups.push_back({b.path(), nodes, model.terms.back().get()});
      sc.term_summary.push_back(model.terms.back()->name() + ": " + model.terms.back()->describe());
      b.finish();
      continue;
    }
    if (fix) {
      const std::uint8_t axes = parse_axes(b.text("fix"), b.at("fix"));
      for (const Index n : nodes) model.constraints.fix(n, axes, b.path());
    } else {
      SceneNode c = b.map("control");
      const std::uint8_t axes = parse_axes(c.text("axis"), c.at("axis"));
      const bool disp = c.has("displacement"), vel = c.has("velocity");
      if (disp == vel) throw InputError(c.path() + ": give either displacement: or velocity: (a time course)");
      const TimeCourse course =
          disp ? c.course("displacement", Dimension::Length) : c.course("velocity", Dimension::Velocity);
      c.finish();
      for (int axis = 0; axis < 3; ++axis) {
        if (((axes >> axis) & 1U) == 0) continue;
        for (const Index n : nodes) model.constraints.control(n, axis, course, vel, b.path());
      }
    }
    model.boundary_groups.push_back({b.path(), nodes});
    b.finish();
  }
}

/// `loads:` (gravity, friction, pressures) and `initial_velocity:`; sets the initial state.
void load_loads(SceneNode& root, LoadedScene& sc, const fs::path& base) {
  Model& model = sc.model;
  sc.initial.x = model.x_ref;
  sc.initial.v = Eigen::Matrix3Xd::Zero(3, model.x_ref.cols());
  if (auto loads = root.optional_map("loads")) {
    if (loads->has("gravity")) {
      GravityKernel g{model.mass, loads->vector3("gravity", Dimension::Acceleration)};
      model.terms.push_back(std::make_unique<StencilTerm<GravityKernel, 1>>(std::move(g)));
      sc.term_summary.push_back("gravity: " + std::to_string(model.node_count()) + " particles");
    }
    const std::size_t before = model.terms.size();
    build_loads(*loads, model, base);
    for (std::size_t k = before; k < model.terms.size(); ++k)
      sc.term_summary.push_back(model.terms[k]->name() + ": " + model.terms[k]->describe());
    loads->finish();
  }
  if (root.has("initial_velocity")) {
    const Eigen::Vector3d v0 = root.vector3("initial_velocity", Dimension::Velocity);
    sc.initial.v.colwise() = v0;
  }
}

/// A factorisation-reuse count of the static integrator, `key` in 0 ... max (0: full Newton, the
/// default); InputError outside that or, when nonzero, for another integrator (`how`: the kind).
int reuse_count(SceneNode& integ, const std::string& integrator, const char* key, long long max, const char* how) {
  const long long n = integ.integer(key, 0);
  if (n < 0 || n > max)
    throw InputError(integ.at(key) + ": must be in 0 ... " + std::to_string(max) + " (0: full Newton)");
  if (n > 0 && integrator != "static")
    throw InputError(integ.at(key) + ": only the static integrator reuses its factorisation " + how);
  return static_cast<int>(n);
}

/// `integrator:` into run; returns its check_dt flag.
bool load_integrator(SceneNode integ, RunSettings& run) {
  run.integrator = integ.choice("type", integrator_names());
  run.dt = integ.positive("dt", Dimension::Time);
  run.abm3.error_min = integ.positive("error_min", Dimension::Length, run.abm3.error_min);
  run.abm3.error_max = integ.positive("error_max", Dimension::Length, run.abm3.error_max);
  run.abm3.dt_min = integ.positive("dt_min", Dimension::Time, std::min(run.abm3.dt_min, run.dt));
  run.abm3.dt_max = integ.positive("dt_max", Dimension::Time, std::max(run.abm3.dt_max, run.dt));
  const bool check_dt = integ.flag("check_dt", true);
  ImplicitSettings& imp = run.implicit;
  imp.dt_min = run.abm3.dt_min;
  imp.dt_max = integ.has("dt_max") ? run.abm3.dt_max : 1e30;  // no upper bound unless given
  imp.max_newton = static_cast<int>(integ.integer("max_newton", imp.max_newton));
  imp.newton_rtol = integ.positive("newton_rtol", Dimension::Dimensionless, imp.newton_rtol);
  imp.newton_atol = integ.positive("newton_atol", Dimension::Force, imp.newton_atol);
  imp.newton_xtol = integ.positive("newton_xtol", Dimension::Length, imp.newton_xtol);
  imp.ksp_rtol = integ.positive("ksp_rtol", Dimension::Dimensionless, imp.ksp_rtol);
  imp.ksp_max_it = static_cast<int>(integ.integer("ksp_max_it", imp.ksp_max_it));
  imp.adapt = integ.flag("adapt", imp.adapt);
  imp.static_damping = integ.positive("static_damping", Dimension::Rate, 0.0, true);
  if (imp.static_damping > 0.0 && run.integrator != "static") {
    throw InputError(
        integ.at("static_damping") +
        ": only the static integrator has it (the dynamic ones damp through their masses and damping terms)");
  }
  imp.bfgs_max_updates = reuse_count(integ, run.integrator, "bfgs_max_updates", 1000, "with BFGS updates");
  imp.bordered_max_reuses =
      reuse_count(integ, run.integrator, "bordered_max_reuses", 100, "in the cavity (bordered) steps");
  imp.newton_max_reuses =
      reuse_count(integ, run.integrator, "newton_max_reuses", 100, "in its damped Newton steps (modified Newton)");
  if (imp.newton_max_reuses > 0 && imp.bfgs_max_updates > 0) {
    throw InputError(integ.at("newton_max_reuses") +
                     ": choose one way to reuse the factorisation, BFGS updates (bfgs_max_updates) or modified "
                     "Newton (newton_max_reuses), not both");
  }
  imp.petsc_options = integ.text("petsc_options", "");
  if (imp.max_newton < 1) throw InputError(integ.at("max_newton") + ": must be >= 1");
  if (!(run.abm3.error_min < run.abm3.error_max))
    throw InputError(integ.at("error_min") + ": must be smaller than error_max");
  if (!(run.abm3.dt_min <= run.abm3.dt_max)) throw InputError(integ.at("dt_min") + ": must not exceed dt_max");
  integ.finish();
  return check_dt;
}

/// `run:` (end time, stopping rules) into run.
void load_run(SceneNode r, RunSettings& run) {
  run.t_end = r.positive("t_end", Dimension::Time);
  run.ke_threshold = r.has("ke_threshold") ? r.positive("ke_threshold", Dimension::Energy, std::nullopt, true) : -1.0;
  run.ke_after = r.positive("ke_after", Dimension::Time, 0.0, true);
  run.max_steps = static_cast<std::size_t>(std::max(0LL, r.integer("max_steps", 0)));
  const long long ce = r.integer("check_every", 1);
  if (ce < 1) throw InputError(r.at("check_every") + ": must be >= 1");
  run.check_every = static_cast<std::size_t>(ce);
  run.flat_fraction = r.positive("flat_fraction", Dimension::Dimensionless, run.flat_fraction, true);
  r.finish();
}

/// `output:` (intervals, probes at the nearest node, the long axis); without it a frame every
/// t_end / 10. The long axis is estimated from a cavity lid unless output.long_axis gives it.
void load_output(SceneNode& root, RunSettings& run, Model& model) {
  model.long_axis = estimate_long_axis(*model.mesh);
  auto out = root.optional_map("output");
  if (!out) {
    run.export_interval = run.t_end / 10.0;
    run.globals_interval = 0.0;
    return;
  }
  run.export_interval = out->positive("frame_interval", Dimension::Time, 0.0, true);
  run.globals_interval = out->positive("globals_interval", Dimension::Time, 0.0, true);
  run.checkpoint_interval = out->positive("checkpoint_interval", Dimension::Time, 0.0, true);
  const std::string compression = out->choice("compression", {"zlib", "lz4", "none"}, "zlib");
  run.frame_compression = compression == "lz4"    ? FrameCompression::lz4
                          : compression == "none" ? FrameCompression::none
                                                  : FrameCompression::zlib;
  run.newton_log = out->flag("newton_log", false);
  std::set<std::string> probe_names;
  for (SceneNode& p : out->list("probes")) {
    const std::string pname = p.text("name");
    if (!probe_names.insert(pname).second) throw InputError(p.at("name") + ": a second probe named '" + pname + "'");
    const Eigen::Vector3d pt = p.vector3("point", Dimension::Length);
    Eigen::Index best = 0;
    (model.x_ref.colwise() - pt).colwise().squaredNorm().minCoeff(&best);
    model.probes.push_back({pname, static_cast<Index>(best)});
    p.finish();
  }
  if (auto axis = out->optional_map("long_axis")) {
    LongAxis a;
    a.point = axis->vector3("point", Dimension::Length);
    a.direction = axis->vector3("direction", Dimension::Dimensionless);
    if (!a.direction.allFinite() || !(a.direction.norm() > 0.0))
      throw InputError(axis->at("direction") + ": must be a non-zero vector (from the apex towards the base)");
    a.direction.normalize();
    a.source = "scene";
    model.long_axis = a;
    axis->finish();
  }
  out->finish();
}

/// The critical step (eq. 2.150): h_c = L / c, c = sqrt(M / rho) with max_c2 = max M / rho.
/// A warning when an integrator limited by it takes a larger step; InputError beyond 10 h_c
/// unless check_dt is off.
void check_critical_step(LoadedScene& sc, double max_c2, bool check_dt) {
  const RunSettings& run = sc.run;
  sc.min_edge_length = shortest_edge(*sc.model.mesh);
  if (!(max_c2 > 0.0)) return;
  sc.wave_speed = std::sqrt(max_c2);
  sc.critical_dt = sc.min_edge_length / sc.wave_speed;
  if (!integrator_info(run.integrator).stable_step_limited || !(run.dt > sc.critical_dt)) return;
  std::ostringstream os;
  os << "integrator.dt = " << run.dt << " s exceeds the critical step h_c = L/c = " << sc.critical_dt
     << " s (eq. 2.150; shortest edge L = " << sc.min_edge_length << " m, wave speed c = " << sc.wave_speed
     << " m/s estimated from the stiffest material)";
  if (check_dt && run.dt > 10.0 * sc.critical_dt) {
    throw InputError(os.str() +
                     "; more than 10 h_c is certainly unstable for an explicit integrator. Lower dt, "
                     "use abm3, or set integrator.check_dt: false to run anyway");
  }
  sc.warnings.push_back(os.str());
}

/// Warnings for a model that loads but is likely not what was meant (issue 24): every coordinate
/// of every node fixed or controlled (nothing is free to move), and elements listed twice (the
/// same node set; they double the stiffness and the mass there). The first duplicate pair is named.
void check_model_plausibility(LoadedScene& sc) {
  const Model& m = sc.model;
  const auto& mask = m.constraints.mask();
  if (!mask.empty() && std::all_of(mask.begin(), mask.end(), [](std::uint8_t b) { return (b & 7U) == 7U; })) {
    sc.warnings.push_back("boundary: all " + std::to_string(mask.size()) +
                          " nodes have all three coordinates fixed or controlled: no degree of freedom is free");
  }
  const preprocess::Mesh& mesh = *m.mesh;
  const auto k = static_cast<std::size_t>(preprocess::nodes_per_element(mesh.type));
  const std::size_t n = mesh.element_count();
  std::vector<Index> keys(n * k);
  for (std::size_t e = 0; e < n; ++e) {
    std::copy(mesh.element(e), mesh.element(e) + k, keys.begin() + static_cast<std::ptrdiff_t>(e * k));
    std::sort(keys.begin() + static_cast<std::ptrdiff_t>(e * k),
              keys.begin() + static_cast<std::ptrdiff_t>((e + 1) * k));
  }
  std::vector<std::size_t> order(n);
  for (std::size_t e = 0; e < n; ++e) order[e] = e;
  const auto key = [&](std::size_t e) { return keys.begin() + static_cast<std::ptrdiff_t>(e * k); };
  // Stable: elements with the same node set stay in index order, so the first pair is named lowest first.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::lexicographical_compare(key(a), key(a) + static_cast<std::ptrdiff_t>(k), key(b),
                                        key(b) + static_cast<std::ptrdiff_t>(k));
  });
  std::size_t duplicates = 0;
  std::size_t first_a = 0, first_b = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (!std::equal(key(order[i - 1]), key(order[i - 1]) + static_cast<std::ptrdiff_t>(k), key(order[i]))) continue;
    if (duplicates++ == 0) {
      first_a = order[i - 1];
      first_b = order[i];
    }
  }
  if (duplicates > 0) {
    sc.warnings.push_back("mesh: " + std::to_string(duplicates) +
                          " element(s) repeat another's node set (first: elements " + std::to_string(first_a) +
                          " and " + std::to_string(first_b) + "); each copy adds its stiffness and mass again");
  }
}

/// Above this many projected steps a run needs run.max_steps (an explicit intent to stop early).
constexpr double kMaxPlannedSteps = 1e9;
/// Above this projected output volume (frames + globals.csv) the scene loads with a warning.
constexpr double kLargeOutputBytes = 1e9;

/// What the run is about to do, checked before it starts (issue 24): the time step must advance
/// time at t_end in double precision; t_end / dt above 1e9 steps is an error unless run.max_steps
/// bounds it; a projected output above 1 GB is a warning with the projected size. The output
/// estimate counts 8-byte values: per frame 3 x (positions, displacements, velocities, forces)
/// per node plus the connectivity and ~4 fields per element; per globals row ~20 columns of 17
/// characters, plus 3 per probe and 8 for cavities.
void check_run_plan(LoadedScene& sc) {
  const RunSettings& run = sc.run;
  std::ostringstream os;
  if (!(run.t_end + run.dt > run.t_end) || !(run.dt > 1e-15 * run.t_end)) {
    os << "integrator.dt = " << run.dt << " s is below the time resolution at run.t_end = " << run.t_end
       << " s (relative step < 1e-15: t + dt would not advance t in double precision)";
    throw InputError(os.str());
  }
  const double steps = run.t_end / run.dt;
  if (steps > kMaxPlannedSteps && run.max_steps == 0) {
    os << "run.t_end / integrator.dt = " << steps << " steps (more than " << kMaxPlannedSteps
       << "); raise dt, lower t_end, or set run.max_steps to run a bounded part of it";
    throw InputError(os.str());
  }
  const Model& m = sc.model;
  const double nodes = static_cast<double>(m.node_count());
  const double elements = static_cast<double>(m.mesh->element_count());
  const double frame_bytes = 8.0 * (12.0 * nodes + elements * (preprocess::nodes_per_element(m.mesh->type) + 4.0));
  const double frames = run.export_interval > 0.0 ? run.t_end / run.export_interval + 1.0 : 2.0;
  const double rows = run.globals_interval > 0.0
                          ? run.t_end / run.globals_interval + 1.0
                          : std::min(steps, run.max_steps > 0 ? static_cast<double>(run.max_steps) : steps);
  const double row_bytes = 17.0 * (28.0 + 3.0 * static_cast<double>(m.probes.size()));
  const double total = frames * frame_bytes + rows * row_bytes;
  if (total > kLargeOutputBytes) {
    os << "the run will write about " << total / 1e9 << " GB: " << frames << " frames of ~" << frame_bytes / 1e6
       << " MB (output.frame_interval) and " << rows << " globals.csv rows of ~" << row_bytes
       << " bytes (output.globals_interval; 0 = every step)";
    sc.warnings.push_back(os.str());
  }
}

LoadedScene assemble(const YAML::Node& root_yaml, const fs::path& origin, const SceneOptions& opt) {
  LoadedScene sc;
  sc.file = origin;
  const fs::path base = origin.has_parent_path() ? origin.parent_path() : fs::path(".");
  SceneNode root(root_yaml, "");
  sc.name = root.text("name", origin.stem().string());
  sc.description = root.text("description", "");

  auto mesh = std::make_shared<preprocess::Mesh>(
      load_scene_mesh(root.map("mesh"), base, opt, sc.mesh_source, sc.reference_file));
  if (opt.reference_nodes) replace_node_positions(*mesh, *opt.reference_nodes, "the reference configuration");
  Model& model = sc.model;
  model.mesh = mesh;
  model.x_ref = mesh->nodes;
  model.constraints = Constraints(mesh->node_count());

  const double max_c2 = load_materials(root.list("materials", true), sc);
  load_loads(root, sc, base);
  load_boundary(root.list("boundary"), sc, base);
  // The terms learn which nodes the boundary fixes; a term whose description changes with it (the
  // nodal volume term's released nodes) gets its summary line updated.
  for (const auto& term : model.terms) {
    const std::string before = term->describe();
    term->set_boundary_mask(model.constraints.mask());
    const std::string after = term->describe();
    if (after == before) continue;
    for (std::string& line : sc.term_summary) {
      const std::string tail = ": " + before;
      if (line.size() >= tail.size() && line.compare(line.size() - tail.size(), tail.size(), tail) == 0) {
        line.replace(line.size() - before.size(), before.size(), after);
        break;
      }
    }
  }
  const bool check_dt = load_integrator(root.map("integrator"), sc.run);
  load_run(root.map("run"), sc.run);
  load_output(root, sc.run, model);
  const IntegratorType type = integrator_info(sc.run.integrator).type;
  if (sc.run.newton_log && type != IntegratorType::Static && type != IntegratorType::BackwardEulerNewton) {
    sc.warnings.push_back("output.newton_log: the " + sc.run.integrator +
                          " integrator takes no Newton iterations, so run.log gets no Newton lines");
  }
  root.finish();
  check_critical_step(sc, max_c2, check_dt);
  check_run_plan(sc);
  check_model_plausibility(sc);
  return sc;
}

}  // namespace

LoadedScene load_scene_text(const std::string& yaml, const fs::path& origin, const SceneOptions& options) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw InputError(origin.string() + ": not valid YAML: " + e.what());
  }
  try {
    check_duplicate_keys(root);
    return assemble(root, origin, options);
  } catch (const InputError& e) {
    throw InputError(origin.string() + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw InputError(origin.string() + ": " + e.what());
  }
}

LoadedScene load_scene(const fs::path& file, const SceneOptions& options) {
  std::ifstream in(file);
  if (!in) throw InputError("cannot open scene file '" + file.string() + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return load_scene_text(ss.str(), file, options);
}

}  // namespace adamss::solver
