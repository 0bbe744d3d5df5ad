// adamss._core: the Python side of adamss (pybind11). Runs a scene in this process and returns
// its results as numpy arrays; reads mesh.h5. The package adamss (python/adamss/__init__.py)
// wraps these two functions with the conveniences (a scene as a dict or a file).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preprocess/mesh/mesh.hpp"
#include "preprocess/mesh/mesh_import.hpp"
#include "preprocess/mesh/mesh_io.hpp"
#include "solver/run/output_lock.hpp"
#include "solver/run/results.hpp"
#include "solver/run/run.hpp"
#include "solver/run/summary.hpp"
#include "solver/scene/scene.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;
using namespace adamss;

namespace {

/// A 3 x n Eigen matrix as a numpy array of shape (n, 3) (copied).
py::array_t<double> rows_of(const Eigen::Matrix3Xd& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.cols()), py::ssize_t{3}});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (int c = 0; c < 3; ++c) w(i, c) = m(c, i);
  return a;
}

py::array_t<double> vec3(const Eigen::Vector3d& v) {
  py::array_t<double> a(3);
  auto w = a.mutable_unchecked<1>();
  for (int c = 0; c < 3; ++c) w(c) = v[c];
  return a;
}

/// globals.csv as {column: numpy array}: every column is numeric.
py::dict read_globals(const fs::path& file) {
  std::ifstream in(file);
  std::string header, line;
  if (!std::getline(in, header)) throw IoError("cannot read " + file.string());
  std::vector<std::string> names;
  for (std::stringstream hs(header); std::getline(hs, line, ',');) names.push_back(line);
  std::vector<std::vector<double>> columns(names.size());
  while (std::getline(in, line)) {
    std::stringstream rs(line);
    std::string cell;
    for (std::size_t c = 0; c < names.size() && std::getline(rs, cell, ','); ++c) columns[c].push_back(std::stod(cell));
  }
  py::dict out;
  for (std::size_t c = 0; c < names.size(); ++c) out[py::str(names[c])] = py::array_t<double>(py::cast(columns[c]));
  return out;
}

/// Runs the scene (YAML text; `origin` resolves its relative paths and names it in errors) into
/// `output` as `adamss run` does, without the summary.json file: returns the outcome, the summary
/// values, globals.csv as arrays and the final state.
py::dict run(const std::string& text, const std::string& origin, const std::string& output, const std::string& cache,
             bool progress) {
  solver::SceneOptions so;
  so.cache_dir = cache;
  solver::LoadedScene sc = solver::load_scene_text(text, origin, so);
  fs::create_directories(output);
  const solver::OutputLock lock(output);
  solver::ResultsWriter writer(output, sc.model);
  solver::State s = sc.initial;
  const solver::State initial = s;
  sc.run.progress = progress;
  solver::RunOutcome out;
  {
    py::gil_scoped_release release;  // a long run does not hold the interpreter
    out = solver::run_simulation(sc.model, s, sc.run, writer, nullptr);
  }
  const solver::RunSummary sum = solver::summarize_run(sc.model, out, initial, writer);
  py::dict r;
  r["name"] = sc.name;
  r["status"] = out.status;
  r["reason"] = out.reason;
  r["steps"] = out.steps;
  r["t"] = out.t;
  r["wall_seconds"] = out.wall_seconds;
  r["newton_iterations"] = out.newton_iterations;
  r["linear_iterations"] = out.linear_iterations;
  r["reformations"] = out.reformations;
  r["rejected_steps"] = out.rejected_steps;
  py::dict split;  // summary.json "time_split_s" (docs/file-formats.md)
  const auto part = [](const solver::TimePart& p) {
    py::dict d;
    d["seconds"] = p.seconds;
    d["calls"] = p.count;
    return d;
  };
  split["loop"] = out.loop_seconds;
  split["forces"] = part(out.time_split.forces);
  split["jacobians"] = part(out.time_split.jacobians);
  split["factorisations"] = part(out.time_split.factorisations);
  split["solves"] = part(out.time_split.solves);
  split["other"] = out.loop_seconds - out.time_split.seconds();
  r["time_split"] = split;
  r["output"] = writer.dir().string();
  r["frames"] = writer.frame_count();
  r["warnings"] = sc.warnings;
  r["volume_relative_change"] = sum.volume_relative_change;
  r["reference_positions"] = rows_of(sc.model.x_ref);
  r["positions"] = rows_of(out.final_state.x);
  r["velocities"] = rows_of(out.final_state.v);
  r["displacement"] = rows_of(out.final_state.x - sc.model.x_ref);
  py::dict probes;
  for (const auto& p : sum.probes) {
    py::dict d;
    d["node"] = p.node;
    d["reference"] = vec3(p.reference);
    d["final_position"] = vec3(p.final_position);
    d["displacement"] = vec3(p.displacement);
    if (p.twist_about_z_deg) d["twist_about_z_deg"] = *p.twist_about_z_deg;
    probes[py::str(p.name)] = d;
  }
  r["probes"] = probes;
  py::dict cavities;
  for (const auto& c : sum.cavities) cavities[py::str(c.name)] = c.values;
  r["cavities"] = cavities;
  r["globals"] = read_globals(writer.dir() / "globals.csv");
  return r;
}

/// A mesh file (mesh.h5, .vtu, gmsh .msh or .xdmf: preprocess::read_mesh_file) as numpy arrays: nodes (m),
/// connectivity, labels, the fibre frame, cell fields, node tags, cavities (volume, closed).
py::dict read_mesh(const std::string& path) {
  const preprocess::Mesh mesh = preprocess::read_mesh_file(path);
  py::dict r;
  r["element_type"] = preprocess::element_type_name(mesh.type);
  r["nodes"] = rows_of(mesh.nodes);
  const int k = preprocess::nodes_per_element(mesh.type);
  py::array_t<std::int64_t> conn({static_cast<py::ssize_t>(mesh.element_count()), static_cast<py::ssize_t>(k)});
  auto w = conn.mutable_unchecked<2>();
  for (std::size_t e = 0; e < mesh.element_count(); ++e)
    for (int a = 0; a < k; ++a) w(static_cast<py::ssize_t>(e), a) = mesh.element(e)[a];
  r["connectivity"] = conn;
  r["labels"] = py::array_t<std::int32_t>(py::cast(mesh.labels));
  if (mesh.has_fibres()) {
    r["fiber"] = rows_of(mesh.fiber);
    r["sheet"] = rows_of(mesh.sheet);
    r["normal"] = rows_of(mesh.normal);
  }
  py::dict fields;
  for (const auto& [name, v] : mesh.cell_scalars) {
    fields[py::str(name)] = py::array_t<double>(v.size(), v.data());
  }
  r["cell_fields"] = fields;
  py::dict tags;
  for (const auto& [name, nodes] : mesh.node_tags) {
    std::vector<std::int64_t> idx(nodes.begin(), nodes.end());
    tags[py::str(name)] = py::array_t<std::int64_t>(py::cast(idx));
  }
  r["node_tags"] = tags;
  py::dict cavities;
  for (const auto& [name, c] : mesh.cavities) {
    py::dict d;
    d["volume_m3"] = c.volume_m3;
    d["closed"] = c.closed;
    cavities[py::str(name)] = d;
  }
  r["cavities"] = cavities;
  return r;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "adamss: cardiac mechanics (the compiled part; use the adamss package)";
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<NumericalError>(m, "NumericalError", PyExc_ArithmeticError);
  py::register_exception<IoError>(m, "IoError", PyExc_OSError);
  m.def("run", &run, py::arg("text"), py::arg("origin"), py::arg("output"), py::arg("cache") = "",
        py::arg("progress") = false, "Run a scene given as YAML text; see adamss.run");
  m.def("read_mesh", &read_mesh, py::arg("path"),
        "Read a mesh file (.h5, .vtu, .msh, .xdmf) into numpy arrays; see adamss.read_mesh");
}
