// adamss fit: polynomial axial and torsion springs fitted to a law (verify/spring_fit.hpp).
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "materials/factory.hpp"
#include "verify/spring_fit.hpp"

namespace adamss::app {
namespace {

struct FitArgs {
  std::string law = "hunter_canine";
  double max_strain = 0.2;
  int order = 0;
  std::string powers = "1,3";
  int samples = 40;
  std::string norm = "max";
  std::string error = "full-scale";
};

std::vector<int> parse_powers(const FitArgs& a) {
  std::vector<int> out;
  if (a.order != 0) {
    if (a.order < 1 || a.order > 3) throw InputError("--order must be 1, 2 or 3 (got " + std::to_string(a.order) + ")");
    for (int i = 1; i <= a.order; ++i) out.push_back(i);
    return out;
  }
  std::stringstream ss(a.powers);
  std::string item;
  while (std::getline(ss, item, ',')) {
    int p = 0;
    try {
      p = std::stoi(item);
    } catch (const std::exception&) {
      throw InputError("--powers: '" + item + "' is not an integer (give e.g. 1,3)");
    }
    if (p < 1 || p > 3) throw InputError("--powers: " + item + " is outside 1..3");
    out.push_back(p);
  }
  if (out.empty()) throw InputError("--powers: no power given (e.g. 1,3)");
  return out;
}

void print_row(const char* what, const solver::SpringPolynomial& k, const verify::PolynomialFit& f,
               const solver::SpringPolynomial* table) {
  std::printf("  %-13s k1 %9.1f k2 %9.1f k3 %10.1f Pa  error: full-scale %5.2f %%, pointwise max %6.2f %%", what, k[0],
              k[1], k[2], 100.0 * f.max_fullscale_error, 100.0 * f.max_rel_error);
  if (table != nullptr) std::printf("   | Table 2.2: %8.0f %8.0f %8.0f", (*table)[0], (*table)[1], (*table)[2]);
  std::printf("\n");
}

}  // namespace

void add_fit_command(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  auto* sub = app.add_subcommand("fit", "Fit polynomial axial/torsion springs to a law's uniaxial and shear curves");
  sub->add_option("--law", args->law, "Law name with its default parameters (default hunter_canine)");
  sub->add_option("--max-strain", args->max_strain, "Fit range: strain / shear up to this (default 0.2)");
  sub->add_option("--order", args->order, "Polynomial order 1-3, all powers up to it (overrides --powers)");
  sub->add_option("--powers", args->powers, "Powers to fit, comma separated (default 1,3: odd, like Table 2.2)");
  sub->add_option("--samples", args->samples, "Equally spaced samples in (0, max-strain] (default 40)");
  sub->add_option("--norm", args->norm, "Relative error norm: max (minimax, default) or l2");
  sub->add_option("--error", args->error,
                  "Error minimised: full-scale (|p - y| / max |y|, default) or relative (|p - y| / |y|)");
  sub->callback([args]() {
    verify::FitOptions o;
    o.max_strain = args->max_strain;
    o.samples = args->samples;
    o.powers = parse_powers(*args);
    if (args->norm == "max") {
      o.norm = verify::FitNorm::Max;
    } else if (args->norm == "l2") {
      o.norm = verify::FitNorm::L2;
    } else {
      throw InputError("--norm: '" + args->norm + "' is not one of max, l2");
    }
    if (args->error == "full-scale") {
      o.scale = verify::FitScale::FullScale;
    } else if (args->error == "relative") {
      o.scale = verify::FitScale::Relative;
    } else {
      throw InputError("--error: '" + args->error + "' is not one of full-scale, relative");
    }
    const auto law = materials::make_law(args->law, {});
    const verify::SpringFitResult r = verify::fit_springs(*law, o);
    const bool hunter = args->law == "hunter_canine";
    const solver::SpringSet table = solver::table_2_2_springs();
    std::printf("Springs fitted to %s up to %.3g strain (%d samples, %s norm of the %s error), virtual scaling:\n",
                args->law.c_str(), o.max_strain, o.samples, args->norm.c_str(), args->error.c_str());
    std::printf(" axial (nominal stress P(eps) of uniaxial stress along the axis):\n");
    static const char* const kAxes[3] = {"fibre", "sheet", "normal"};
    static const char* const kPairs[3] = {"fibre_sheet", "fibre_normal", "sheet_normal"};
    for (int l = 0; l < 3; ++l) {
      print_row(kAxes[l], r.set.axial.k[static_cast<std::size_t>(l)], r.axial[static_cast<std::size_t>(l)],
                hunter ? &table.axial.k[static_cast<std::size_t>(l)] : nullptr);
    }
    std::printf(" torsion, cosine form (q(Delta) = S_lm at pure shear E_lm = Delta/2, Delta = 2 E_lm):\n");
    for (int l = 0; l < 3; ++l) {
      print_row(kPairs[l], r.set.torsion.k[static_cast<std::size_t>(l)], r.torsion[static_cast<std::size_t>(l)],
                hunter ? &table.torsion.k[static_cast<std::size_t>(l)] : nullptr);
    }
    std::printf("\nScene terms:\n%s", verify::spring_terms_yaml(r.set, "      ").c_str());
  });
}

}  // namespace adamss::app
