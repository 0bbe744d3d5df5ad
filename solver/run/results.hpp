#pragma once
// What a run writes (seed 000 sec. 2.7), all in one output folder:
//   series.pvd            ParaView collection of the frames (rewritten after every frame, so a
//                         run that dies still leaves a readable series)
//   frames/frame_NNNNN.vtu  VTK XML unstructured grid, binary appended: the reference positions,
//                         point data displacement (m; Warp By Vector gives the deformed mesh
//                         once), velocity (m/s), force (N, the total of all terms), cell data
//                         label, J (V/V0), the strain fields of add_strain_fields (Green-Lagrange
//                         strain, in the fibre frame too, fibre/sheet/normal reference and
//                         current, fibre stretch; in the cardiac frame when the model has a long
//                         axis), the stresses (complete_stress_fields), the mesh cell fields (scar)
//                         and the terms' own cell fields (active_tension, Pa); field data TimeValue
//                         (s) and per cavity pressure (Pa, mmHg), volume (ml) and phase
//   globals.csv           one row per logged step: step, t, dt, kinetic energy, total volume,
//                         relative volume change, barycentre, per cavity volume and pressure,
//                         force evaluations, rejected steps, ABM3 error, wall time
//   summary.json          status and the final numbers (see docs/file-formats.md)
//   run.log               the command, model, progress lines and outcome (run_log.hpp)
//   checkpoint.h5         written every output.checkpoint_interval, on SIGINT/SIGTERM and on
//                         failures: /x, /v (n x 3), attributes t and step, and (for a resumable
//                         checkpoint) the run loop's, integrator's, terms' and this writer's
//                         state (solver/core/state_archive.hpp, docs/file-formats.md)
// Every file except globals.csv is written to NAME.tmp and renamed over NAME, so an interrupted
// run never leaves a truncated frame, series, summary or checkpoint. globals.csv is appended one
// flushed row at a time; a resume truncates it to the rows the checkpoint had seen. Every write
// is checked (the stream state after the flush or close): a failure is an IoError naming the file.
// Nothing in the folder changes before open(): a fresh run then moves an earlier run's files into
// OUT/previous/ (replacing an older previous/), so a run that fails to start loses nothing.
#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "solver/core/model.hpp"
#include "solver/core/state_archive.hpp"
#include "solver/run/run_log.hpp"
#include "solver/time/integrator.hpp"

namespace adamss::solver {

/// A row of globals.csv.
struct GlobalsRow {
  std::size_t step = 0;
  double t = 0.0, dt = 0.0;
  double kinetic_energy = 0.0;
  StepReport report;
  double wall_seconds = 0.0;
};

/// How the appended arrays of a frame are compressed (scene key output.compression): zlib level 1
/// (VTK's vtkZLibDataCompressor, every VTK reader), LZ4 (vtkLZ4DataCompressor: ParaView 5.5 on,
/// VTK 8.1 on, meshio with the lz4 module) or none. Measured on biv-inflation.yaml's frames
/// (103 760 tetrahedra, ~90 doubles each, 75 MB raw): zlib 60 MB in ~1.3 s a frame, LZ4 ~70 MB in
/// ~0.05 s (bench/README.md): doubles compress little, so large frames are cheaper in LZ4 or raw.
enum class FrameCompression { zlib, lz4, none };

class ResultsWriter {
 public:
  /// A writer into `out_dir`; nothing on disk changes until open(). With `resume` (the "writer"
  /// part of a checkpoint, see save_state) the folder is checked here (frames, globals.csv
  /// header and rows; InputError naming what does not match).
  ResultsWriter(std::filesystem::path out_dir, const Model& model, const StateArchive* resume = nullptr);

  /// Called once the run has been built and is about to start. A fresh run moves an earlier
  /// run's summary.json, globals.csv, series.pvd, frames/ and checkpoint.h5 into out_dir/previous/
  /// (a stale checkpoint cannot be resumed into the new series), creates frames/ and starts
  /// globals.csv. A resumed one keeps globals.csv's header and the rows the checkpoint counted,
  /// removes the frames from the checkpoint's frame count on and rewrites series.pvd. IoError
  /// when the folder cannot be changed.
  void open();
  /// True once open() has moved the earlier run's files aside (or begun a resume): from then
  /// on summary.json in the folder belongs to this run.
  [[nodiscard]] bool started() const { return started_; }
  /// An MPI rank other than 0 (which writes the results): from now on nothing is written; frames
  /// and rows are only counted, as on rank 0.
  void mute() {
    muted_ = true;
    log_.mute();
  }

  /// Writes frame k of the series at state s with total forces f (N).
  void write_frame(const State& s, const Eigen::Matrix3Xd& f);
  /// The frames' compression from now on (default zlib; scene key output.compression).
  void set_compression(FrameCompression c) { compression_ = c; }
  /// Appends one row to globals.csv (flushed).
  void write_globals(const State& s, const GlobalsRow& row);
  /// Writes checkpoint.h5 with positions, velocities, time and step only (a failure snapshot
  /// of the last good state; not resumable).
  void write_checkpoint(const State& s, std::size_t step) const;
  /// Writes checkpoint.h5 from a full archive (the run loop's); t and step become attributes.
  void write_checkpoint(const StateArchive& archive, double t, std::size_t step) const;
  /// The writer's counters: frame times, the number of globals rows, the summary extrema.
  void save_state(StateArchive& archive) const;

  /// Smallest and largest volume (m^3) of each cavity over the logged rows, with their times.
  /// The cavity pressure at those times and its largest value (Pa).
  struct Extremum {
    double min = 0.0, max = 0.0, t_min = 0.0, t_max = 0.0;
    double p_at_min = 0.0, p_at_max = 0.0, p_max = 0.0;
  };
  [[nodiscard]] const std::vector<Extremum>& cavity_extrema() const { return extrema_; }
  /// Smallest and largest element fibre stretch |F f0| over the logged rows (1 without fibres).
  [[nodiscard]] double fibre_stretch_min() const { return stretch_min_; }
  [[nodiscard]] double fibre_stretch_max() const { return stretch_max_; }
  /// Largest |V - V0| / V0 of the whole mesh over the logged rows.
  [[nodiscard]] double max_volume_change() const { return max_volume_change_; }

  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }
  /// run.log of the folder (kept in memory until open(), appended on a resume).
  [[nodiscard]] RunLog& log() { return log_; }
  [[nodiscard]] std::size_t frame_count() const { return frames_.size(); }

 private:
  void write_pvd() const;
  void resume_from(const StateArchive& archive);
  void continue_series();
  void archive_previous();
  [[nodiscard]] std::string globals_header() const;
  std::filesystem::path dir_;
  const Model& model_;
  bool resuming_ = false;
  bool opened_ = false;
  bool started_ = false;
  bool muted_ = false;
  FrameCompression compression_ = FrameCompression::zlib;
  std::string resume_globals_;  ///< globals.csv as the resume will leave it (header + counted rows)
  std::ofstream globals_;
  std::vector<std::pair<double, std::string>> frames_;
  double volume0_ = 0.0;
  std::vector<Extremum> extrema_;
  double max_volume_change_ = 0.0;
  double stretch_min_ = 1.0, stretch_max_ = 1.0;
  bool logged_ = false;
  std::size_t rows_ = 0;  ///< data rows in globals.csv
  std::vector<double> element_volume0_;
  RunLog log_;
};

/// Per-element J = V/V0 at positions x (exact element volumes).
[[nodiscard]] Eigen::VectorXd element_volume_ratio(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x,
                                                   const std::vector<double>& volume0);
/// Exact element volumes (tet: signed volume; hex: trilinear, 2x2x2 Gauss), m^3.
[[nodiscard]] std::vector<double> element_volumes(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x);
/// Fibre stretch |F f0| per element, F at the element centre from its shape functions.
[[nodiscard]] Eigen::VectorXd fibre_stretch(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x);

/// The deformation gradient F = dx/dX of each element at its centre (tet: exact; hex: at the
/// centre, from the trilinear shape functions).
[[nodiscard]] std::vector<Eigen::Matrix3d> element_deformation_gradients(const preprocess::Mesh& mesh,
                                                                         const Eigen::Matrix3Xd& x);

/// The arrays of one frame: point vectors (3 x nodes), cell scalars (elements), cell vectors
/// (3 x elements), cell tensors (9 x elements, a 3 x 3 tensor row by row, as ParaView reads a
/// 9-component array) and field data (one value per frame: numbers and strings).
struct VtuArrays {
  std::map<std::string, Eigen::Matrix3Xd> point_vectors;
  std::map<std::string, Eigen::VectorXd> cell_scalars;
  std::map<std::string, Eigen::Matrix3Xd> cell_vectors;
  std::map<std::string, Eigen::Matrix<double, 9, Eigen::Dynamic>> cell_tensors;
  std::map<std::string, double> field_scalars;
  std::map<std::string, std::string> field_strings;
};

/// The strain fields of a frame at positions x, per element from F at its centre:
///   green_lagrange               E = (F^T F - I) / 2, global x, y, z components (9 x elements)
///   green_lagrange_fibre_frame   Q^T E Q with Q = [f0 s0 n0]: E_ff, E_fs, ... (with fibres)
///   fibre_stretch                |F f0| (with fibres)
///   fibre, sheet, normal         f0, s0, n0 of the mesh (with fibres)
///   fibre_current, sheet_current F f0 / |F f0|, F s0 / |F s0|
///   normal_current               F^-T n0 / |F^-T n0| (the normal of the deformed fibre-sheet plane)
void add_strain_fields(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, VtuArrays& arrays);

/// Completes the stress arrays that the terms wrote (ForceTerm::add_cell_tensors: the laws'
/// stress_pk2 and stress_cauchy) with the volume terms' hydrostatic stress q
/// (cell scalar "volumetric_stress", Pa, positive in tension; with an uncoupled law it is the
/// whole hydrostatic part):
///   stress_cauchy += q I,   stress_pk2 += q J C^-1   (F, J, C = F^T F at the element centre),
/// then writes, for the totals,
///   stress_pk2_fibre_frame   B^T S B, B = [f s n] of the mesh (the identity without fibres)
///   pressure                 -tr(sigma) / 3 (Pa)
/// Does nothing when no term wrote a stress or a volumetric stress.
void complete_stress_fields(const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& x, VtuArrays& arrays);

/// The strain in the cardiac frame (solver/geometry/long_axis.hpp: Q = [e_c e_l e_r] at each
/// element's reference centroid) from the green_lagrange array already in `arrays`:
///   green_lagrange_cardiac       Q^T E Q (E_cc, E_cl, E_cr; E_lc, ...; 9 x elements)
///   strain_circumferential, strain_longitudinal, strain_radial   E_cc, E_ll, E_rr
///   circumferential, longitudinal, radial                        e_c, e_l, e_r (reference)
void add_cardiac_strain_fields(const preprocess::Mesh& mesh, const LongAxis& axis, VtuArrays& arrays);

/// Writes a VTK XML unstructured grid (binary appended, via a temporary file renamed over `path`)
/// with `points` as its points, the cell label and the given arrays; "displacement", if given, is
/// the active point vector. Arrays compressed as `compression` says.
void write_vtu(const std::filesystem::path& path, const preprocess::Mesh& mesh, const Eigen::Matrix3Xd& points,
               const VtuArrays& arrays, FrameCompression compression = FrameCompression::zlib);

}  // namespace adamss::solver
