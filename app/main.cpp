// adamss: anisotropic mass-spring cardiac mechanics. Thin CLI over the libraries.
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "common/suggest.hpp"

namespace {

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// "--name" and "-n" of every option of `app` (the subcommand the user chose).
std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::Option* opt : app.get_options()) {
    for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
    for (const auto& s : opt->get_snames()) names.push_back("-" + s);
  }
  return names;
}

/// One line for a command-line mistake CLI11 found, with a "did you mean" where a name was
/// mistyped: an unknown option (CLI11: "The following arguments were not expected: ...") or a
/// value outside a fixed set ("kind: lvv not in {lv,biv,beam,slab}").
std::string describe_parse_error(const CLI::ParseError& e, const CLI::App& sub) {
  std::string msg = e.what();
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    const auto colon = msg.find(": ");
    std::istringstream extras(colon == std::string::npos ? std::string() : msg.substr(colon + 2));
    std::string word, options, others, hint;
    while (extras >> word) {
      if (word.size() > 1 && word[0] == '-') {
        options += (options.empty() ? "'" : ", '") + word + "'";
        if (hint.empty()) hint = adamss::did_you_mean(word, option_names(sub));
      } else {
        others += (others.empty() ? "'" : ", '") + word + "'";
      }
    }
    if (!options.empty()) return "unknown option " + options + hint;
    if (!others.empty()) return "unexpected argument " + others;
  }
  static const std::regex kNotIn(R"(^(.*): (.*) not in \{(.*)\}$)");
  std::smatch m;
  if (std::regex_match(msg, m, kNotIn)) {
    std::vector<std::string> choices;
    std::istringstream list(m[3].str());
    for (std::string c; std::getline(list, c, ',');) choices.push_back(c);
    return m[1].str() + ": '" + m[2].str() + "' is not one of " + joined(choices) +
           adamss::did_you_mean(m[2].str(), choices);
  }
  return msg;
}

/// True when a launcher started this process as one of several ranks (Open MPI, MPICH/Hydra,
/// Slurm's PMI): read from the environment, without starting MPI.
bool launched_on_several_ranks() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    if (const char* s = std::getenv(v); s != nullptr && std::atoi(s) > 1) return true;
  }
  return false;
}

}  // namespace

// NOLINTNEXTLINE(bugprone-exception-escape): outside the try only building the option tables throws (a bug: abort)
int main(int argc, char** argv) {
  CLI::App app{
      "adamss - anisotropic mass-spring system for cardiac mechanics.\n"
      "Turns labelled voxel images into meshes and simulates them (adamss run SCENE.yaml -o OUT/).\n"
      "Run 'adamss SUBCOMMAND --help' for the options of each step."};
  app.set_version_flag("--version", "adamss 0.1.0");
  app.require_subcommand(1);
  adamss::app::add_phantom_command(app);
  adamss::app::add_mesh_command(app);
  adamss::app::add_info_command(app);
  adamss::app::add_run_command(app);
  adamss::app::add_unload_command(app);
  adamss::app::add_fit_command(app);
  adamss::app::add_verify_command(app);
  const std::vector<std::string> commands = subcommand_names(app);
  if (argc < 2) {
    adamss::app::write_stderr_line("adamss: error: no command given (commands: " + joined(commands) +
                                   "; adamss --help)\n");
    return 2;
  }
  if (const std::string first = argv[1]; first.empty() || first[0] != '-') {
    if (std::find(commands.begin(), commands.end(), first) == commands.end()) {
      adamss::app::write_stderr_line("adamss: error: unknown command '" + first + "'" +
                                     adamss::did_you_mean(first, commands) + " (commands: " + joined(commands) + ")\n");
      return 2;
    }
  }
  if (const std::string first = argv[1]; first != "run" && first[0] != '-' && launched_on_several_ranks()) {
    adamss::app::write_stderr_line("adamss " + first + ": error: only 'adamss run' runs on several MPI ranks " +
                                   "(docs/parallel.md); run 'adamss " + first + "' without mpirun\n");
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a command's own status (run_scene's), its message already printed
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::vector<CLI::App*> chosen = app.get_subcommands();
    const CLI::App& sub = chosen.empty() ? app : *chosen.back();
    const std::string who = chosen.empty() ? "adamss" : "adamss " + sub.get_name();
    adamss::app::write_stderr_line(who + ": error: " + describe_parse_error(e, sub) + " (" + who +
                                   " --help lists the options)\n");
    return 2;
  } catch (const std::exception& e) {
    const adamss::ErrorReport r = adamss::error_report(e);
    adamss::app::write_stderr_line("adamss: " + std::string(r.label) + ": " + e.what() + "\n");
    return r.exit_status;
  }
  return 0;
}
