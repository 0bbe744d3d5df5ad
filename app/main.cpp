// adamss: anisotropic mass-spring cardiac mechanics. Thin CLI over the libraries.
#include <CLI/CLI.hpp>
#include <iostream>

#include "app/commands.hpp"
#include "common/error.hpp"

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
  adamss::app::add_fit_command(app);
  adamss::app::add_verify_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const adamss::InputError& e) {
    std::cerr << "adamss: error: " << e.what() << "\n";
    return 2;
  } catch (const adamss::NumericalError& e) {
    std::cerr << "adamss: numerical error: " << e.what() << "\n";
    return 3;
  } catch (const adamss::IoError& e) {
    std::cerr << "adamss: I/O error: " << e.what() << "\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "adamss: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
