#include "solver/run/checkpoint.hpp"

#include <bit>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "solver/run/run.hpp"

namespace adamss::solver {

namespace {

/// The integrator's row in integrator_table(): the checkpoint stores the index.
std::int64_t integrator_code(const std::string& name) {
  const auto& table = integrator_table();
  for (std::size_t i = 0; i < table.size(); ++i)
    if (name == table[i].name) return static_cast<std::int64_t>(i);
  return -1;
}

/// Hashes are stored as int64 datasets: the same 64 bits.
std::int64_t as_stored(std::uint64_t h) {
  return std::bit_cast<std::int64_t>(h);
}

}  // namespace

std::uint64_t content_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError("cannot read " + file.string() + " to hash it");
  std::uint64_t h = 14695981039346656037ULL;  // FNV-1a offset basis
  std::vector<char> buf(1 << 16);
  while (in.read(buf.data(), static_cast<std::streamsize>(buf.size())) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) {
      h ^= static_cast<unsigned char>(buf[static_cast<std::size_t>(i)]);
      h *= 1099511628211ULL;  // FNV-1a prime
    }
  }
  if (in.bad()) throw IoError("error while reading " + file.string());
  return h;
}

std::vector<std::string> checkpoint_changes(const RunSettings& set, const StateArchive& a) {
  if (!a.has("run/scene_hash") || !a.has("run/mesh_hash"))
    return {"the checkpoint holds no scene hash (written before adamss checked them): the scene cannot be compared"};
  std::vector<std::string> changes;
  if (a.integer("run/scene_hash") != as_stored(set.scene_hash))
    changes.emplace_back("scene changed: the scene file's text differs from the one the checkpoint was written with");
  if (a.integer("run/mesh_hash") != as_stored(set.mesh_hash))
    changes.emplace_back("mesh changed: the mesh file's contents differ from those the checkpoint was written with");
  return changes;
}

void check_checkpoint(Model& model, const RunSettings& set, const StateArchive& a) {
  const std::string& src = a.source();
  const auto n = static_cast<Eigen::Index>(model.node_count());
  const preprocess::Mesh& mesh = *model.mesh;
  if (!a.has("run/resumable") || a.integer("run/resumable") == 0)
    throw InputError(src + " is the last good state of a failed or unstable run, not a resumable checkpoint");
  const StateArchive r = a.child("run");
  if (r.integer("node_count") != static_cast<std::int64_t>(n) ||
      r.integer("element_count") != static_cast<std::int64_t>(mesh.element_count())) {
    throw InputError(src + ": the checkpoint has " + std::to_string(r.integer("node_count")) + " nodes and " +
                     std::to_string(r.integer("element_count")) + " elements, the scene " + std::to_string(n) +
                     " and " + std::to_string(mesh.element_count()) + " (a checkpoint of a different scene)");
  }
  if (r.integer("term_count") != static_cast<std::int64_t>(model.terms.size())) {
    throw InputError(src + ": the checkpoint has " + std::to_string(r.integer("term_count")) +
                     " force terms, the scene " + std::to_string(model.terms.size()) + " (a different scene)");
  }
  if (r.integer("integrator") != integrator_code(set.integrator))
    throw InputError(src + ": the checkpoint was written by another integrator than the scene's " + set.integrator);
  // The state and the loop's fields, read here so that a missing or malformed one is refused
  // before the results writer changes anything (restore_checkpoint reads them again).
  (void)a.matrix("x", n);
  (void)a.matrix("v", n);
  (void)r.scalar("t");
  (void)r.matrix("x_fixed", n);
  (void)load_loop_state(r, n);
  for (std::size_t k = 0; k < model.terms.size(); ++k)
    model.terms[k]->load_state(a.child("terms/" + std::to_string(k)));
  // Last: a structural difference above names its cause; a changed scene that still fits the
  // checkpoint (a parameter, a load, dt) is refused here.
  if (!set.resume_modified) {
    const std::vector<std::string> changes = checkpoint_changes(set, a);
    if (!changes.empty()) {
      throw InputError("cannot resume from " + src + ": " + changes.front() +
                       (changes.size() > 1 ? "; " + changes[1] : std::string()) +
                       ". Resume with the scene and mesh it was written with, or give --resume-modified to continue "
                       "with the changed ones");
    }
  }
}

void write_resumable_checkpoint(const RunParts& run, const ResultsWriter& writer, const State& s,
                                const RunLoopState& loop) {
  const Model& model = run.model;
  StateArchive a;
  a.put("x", s.x);
  a.put("v", s.v);
  StateArchive r = a.child("run");
  r.put_int("resumable", 1);
  r.put_int("node_count", static_cast<std::int64_t>(model.node_count()));
  r.put_int("element_count", static_cast<std::int64_t>(model.mesh->element_count()));
  r.put_int("term_count", static_cast<std::int64_t>(model.terms.size()));
  r.put_int("integrator", integrator_code(run.settings.integrator));
  r.put_int("scene_hash", as_stored(run.settings.scene_hash));
  r.put_int("mesh_hash", as_stored(run.settings.mesh_hash));
  r.put("t", s.t);
  r.put("x_fixed", run.system.fixed_positions());
  save_loop_state(loop, r);
  StateArchive ia = a.child("integrator");
  run.integrator.save_state(ia);
  for (std::size_t k = 0; k < model.terms.size(); ++k) {
    StateArchive ta = a.child("terms/" + std::to_string(k));
    model.terms[k]->save_state(ta);
  }
  StateArchive wa = a.child("writer");
  writer.save_state(wa);
  writer.write_checkpoint(a, s.t, loop.steps);
}

RunLoopState restore_checkpoint(const RunParts& run, const StateArchive& a, State& s) {
  const auto n = static_cast<Eigen::Index>(run.model.node_count());
  check_checkpoint(run.model, run.settings, a);  // also loads the terms' state
  const StateArchive r = a.child("run");
  s.x = a.matrix("x", n);
  s.v = a.matrix("v", n);
  s.t = r.scalar("t");
  run.system.set_fixed_positions(r.matrix("x_fixed", n));
  RunLoopState loop = load_loop_state(r, n);
  run.integrator.load_state(a.child("integrator"));
  return loop;
}

}  // namespace adamss::solver
