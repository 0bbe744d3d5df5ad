#pragma once
// Subcommands of the adamss executable. Each add_* registers one CLI11
// subcommand whose callback does the work; errors are thrown as
// adamss::InputError and printed by main() as one line.
#include <CLI/CLI.hpp>
#include <string>

namespace adamss::app {

void add_phantom_command(CLI::App& app);
void add_mesh_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_fit_command(CLI::App& app);
void add_verify_command(CLI::App& app);

/// Parses an angle; a plain number means degrees ("60", "-60deg", "1.0 rad"). Result in radians.
double parse_angle_deg_default(const std::string& text, const std::string& what);

/// Throws InputError if the directory that should hold `path` does not exist.
void require_parent_dir(const std::string& path, const std::string& what);

}  // namespace adamss::app
