#pragma once
// Subcommands of the adamss executable. Each add_* registers one CLI11
// subcommand whose callback does the work; errors are thrown as
// adamss::InputError and printed by main() as one line.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace adamss::app {

void add_phantom_command(CLI::App& app);
void add_mesh_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_verify_command(CLI::App& app);
void add_unload_command(CLI::App& app);

/// Parses an angle; a plain number means degrees ("60", "-60deg", "1.0 rad"). Result in radians.
double parse_angle_deg_default(const std::string& text, const std::string& what);

/// A bare number at or above this (m) is not taken as metres on the command line: 5 cm is larger
/// than any voxel or element size of a heart, so "--voxel-size 0.5" means a forgotten "mm".
inline constexpr double kLargestBareLength = 0.05;

/// Parses a length given on the command line: a number with a unit ("0.5 mm", "1cm"), or a plain
/// number of metres below kLargestBareLength ("0.0005"). InputError naming `what` otherwise.
double parse_length(const std::string& text, const std::string& what);

/// Writes `j` (indented by 2) to `file` via `file`.tmp renamed over it (replace_file,
/// common/durable.hpp: IoError on failure): summary.json, unload.json.
void write_json(const std::filesystem::path& file, const nlohmann::json& j);

/// Writes `line` (its newline included) to stderr in one write(2) where the kernel allows. Under
/// mpirun each write of a rank is forwarded as one piece: a message sent in several pieces (as
/// std::cerr's operator<< chain does) can be cut by another rank's lines or by mpirun's own
/// MPI_ABORT notice.
void write_stderr_line(const std::string& line);

/// Throws InputError if the directory that should hold `path` does not exist.
void require_parent_dir(const std::string& path, const std::string& what);

/// Creates the folder `dir` if needed and checks that a file can be written into it (a probe file,
/// written, closed and removed), so that a command fails before its work rather than after it.
/// InputError naming `option`, the folder and the reason.
void require_writable_folder(const std::string& dir, const std::string& option);

/// A file named on the command line: the option (or positional argument) that named it and the path.
struct NamedFile {
  std::string option;
  std::string path;
};

/// True when `a` and `b` name the same file: the same path once made absolute and normalised
/// (std::filesystem::weakly_canonical, so `./a` and `a` or a symbolic link match), or the same
/// existing file (std::filesystem::equivalent, hard links).
[[nodiscard]] bool same_file(const std::string& a, const std::string& b);

/// InputError, before anything is written, when an output names the same file as an input
/// (it would overwrite the input) or as another output (one would overwrite the other). The
/// message names both options and the path. Empty paths are ignored.
void require_distinct_files(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs);

}  // namespace adamss::app
