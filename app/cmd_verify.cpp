// adamss verify [--case NAME | --all] -o OUT/: the verification suite (verify/cases.hpp).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "verify/cases.hpp"

namespace adamss::app {
namespace {

struct VerifyArgs {
  std::vector<std::string> cases;
  bool all = false;
  bool list = false;
  std::string output;
  std::string benchmarks;
  std::string cache;
  int steps = 10;
  bool full_gravity = false;
};

/// verify::write_report with a file-system failure (disk full, folder removed meanwhile) turned
/// into an IoError (exit 4, one line) instead of an internal error.
verify::ReportFiles write_report_checked(const std::vector<verify::CaseResult>& results, const std::string& dir) {
  try {
    return verify::write_report(results, dir);
  } catch (const std::filesystem::filesystem_error& e) {
    throw IoError(std::string("writing the report into ") + dir + ": " + e.what());
  }
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto args = std::make_shared<VerifyArgs>();
  auto* sub = app.add_subcommand("verify", "Run the verification cases of seed 000 sec. 2.8, write verify.json/.md");
  sub->add_option("--case", args->cases, "Case to run (repeatable); --list shows the names");
  sub->add_flag("--all", args->all, "Every case except 'cost'");
  sub->add_flag("--list", args->list, "Print the case names and exit");
  sub->add_option("-o,--output", args->output, "Output folder (created)");
  sub->add_option("--benchmarks", args->benchmarks,
                  "Folder of the gravity-volume-p1e*.yaml scenes (default: cases/benchmarks of the source tree)");
  sub->add_option("--cache", args->cache, "Mesh-recipe cache folder");
  sub->add_option("--steps", args->steps, "Load steps to 20 % strain (default 10)");
  sub->add_flag("--full", args->full_gravity,
                "Expensive rows: the gravity scenes to their own t_end (1 s) instead of 0.08 s; the spring cases at "
                "20 % and the fine beam for every model");
  sub->callback([args]() {
    if (args->list) {
      for (const auto& n : verify::case_names()) std::cout << n << "\n";
      return;
    }
    if (args->all == !args->cases.empty()) throw InputError("give exactly one of --case NAME and --all");
    if (args->output.empty()) throw InputError("-o/--output: the output folder is required");
    if (args->steps < 2) throw InputError("--steps must be >= 2");
    require_writable_folder(args->output, "-o");  // before any case runs
    verify::VerifyOptions o;
    o.steps = args->steps;
    o.full_gravity = args->full_gravity;
    o.full = args->full_gravity;
    o.cache_dir = args->cache;
    o.benchmarks = args->benchmarks.empty() ? std::filesystem::path(ADAMSS_SOURCE_DIR) / "cases" / "benchmarks"
                                            : std::filesystem::path(args->benchmarks);
    const auto names = args->all ? verify::default_cases() : args->cases;
    for (const auto& n : names) {  // validate every name before running anything
      const auto known = verify::case_names();
      if (std::find(known.begin(), known.end(), n) == known.end()) (void)verify::run_case(n, o);  // throws
    }
    std::vector<verify::CaseResult> results;
    for (const auto& n : names) {
      std::cout << "[ " << n << " ]" << std::flush;
      results.push_back(verify::run_case(n, o));
      int failed = 0;
      for (const auto& r : results.back().rows) failed += r.pass ? 0 : 1;
      std::printf(" %zu rows, %d failed, %.1f s\n", results.back().rows.size(), failed, results.back().seconds);
      for (const auto& r : results.back().rows) {
        if (r.comparison == "report") {
          std::printf("    %-4s %-44s %10.4g (report)    %s\n", "info", r.metric.c_str(), r.value, r.note.c_str());
        } else {
          std::printf("    %-4s %-44s %10.4g %s %-8.3g %s\n", r.pass ? "ok" : "FAIL", r.metric.c_str(), r.value,
                      r.comparison.c_str(), r.tolerance, r.note.c_str());
        }
      }
    }
    const auto files = write_report_checked(results, args->output);
    std::cout << "wrote " << files.json.string() << ", " << files.markdown.string() << ", " << files.plots.size()
              << " PNG plots" << (files.gnuplot ? "" : " (gnuplot not found: only the .gp/.dat scripts)") << "\n";
    bool all = true;
    for (const auto& c : results)
      for (const auto& r : c.rows) all = all && r.pass;
    if (!all) throw NumericalError("verification failed: see " + files.markdown.string());
  });
}

}  // namespace adamss::app
