#pragma once
// Resumable checkpoints of the run loop (docs/file-formats.md, "checkpoint.h5 layout"). One is
// taken at the top of the loop, between two accepted steps, where all that carries over to the
// next step is: the state (/x, /v, /run/t), the positions fixed coordinates are held at
// (/run/x_fixed), the loop's own RunLoopState (/run/..., solver/run/loop_state.hpp), the
// integrator's history (/integrator/...), every force term's internal state (/terms/k/...) and
// the results writer's counters (/writer/...). /run/resumable, node, element and term counts and
// the integrator's index in integrator_table() let a resume refuse a checkpoint of another scene;
// /run/scene_hash and /run/mesh_hash (the files' content hashes) refuse a changed scene by name.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/run/loop_state.hpp"
#include "solver/run/results.hpp"
#include "solver/time/integrator.hpp"

namespace adamss::solver {

struct RunSettings;

/// 64-bit FNV-1a hash of a file's bytes (RunSettings::scene_hash, mesh_hash). IoError if the
/// file cannot be read.
[[nodiscard]] std::uint64_t content_hash(const std::filesystem::path& file);

/// What differs between the scene and mesh `settings` was made from and those the checkpoint
/// was written with, one entry each ("scene changed: ...", "mesh changed: ...", or that the
/// checkpoint holds no hashes); empty when they are the same.
[[nodiscard]] std::vector<std::string> checkpoint_changes(const RunSettings& settings, const StateArchive& checkpoint);

/// InputError (naming the checkpoint) unless `checkpoint` is a resumable checkpoint of this
/// model and integrator: node, element and term counts and the integrator must match, the state
/// and every RunLoopState field must be there with the right sizes, every term must accept its
/// saved state (the terms' state is loaded here already; run_simulation loads it again) and,
/// unless settings.resume_modified, the scene and mesh must be those the checkpoint was written
/// with (checkpoint_changes). Call it before the results writer touches the output folder.
void check_checkpoint(Model& model, const RunSettings& settings, const StateArchive& checkpoint);

/// The parts of a run a checkpoint saves and restores.
struct RunParts {
  Model& model;
  const RunSettings& settings;
  System& system;
  Integrator& integrator;
};

/// Writes a resumable checkpoint.h5 through `writer` (t and step also as root attributes).
/// `loop.wall_seconds` is the run's wall time so far.
void write_resumable_checkpoint(const RunParts& run, const ResultsWriter& writer, const State& s,
                                const RunLoopState& loop);

/// Restores s, the fixed positions, the integrator and the terms from `checkpoint` and returns
/// the loop state it holds. InputError (naming the checkpoint and the missing or malformed
/// field) if it is not a resumable checkpoint of this scene.
[[nodiscard]] RunLoopState restore_checkpoint(const RunParts& run, const StateArchive& checkpoint, State& s);

}  // namespace adamss::solver
