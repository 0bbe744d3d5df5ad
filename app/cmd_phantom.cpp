// adamss phantom KIND -o image.nii.gz: synthetic labelled images.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <sstream>

#include "app/commands.hpp"
#include "common/error.hpp"
#include "common/units.hpp"
#include "preprocess/image/nifti_io.hpp"
#include "preprocess/image/phantom.hpp"

namespace adamss::app {
namespace {

struct PhantomArgs {
  std::string kind;
  std::string output;
  std::string voxel_size = "0.5mm";
  std::string fiber_out;
  std::string sheet_out;
  std::string helix_endo = "60";
  std::string helix_epi = "-60";
  std::string size = "4,4,8";
  std::string scar_out;
  std::string scar_direction = "0,1,-1";
  std::string scar_angle = "30";
};

Eigen::Vector3d parse_direction(const std::string& text, const std::string& option) {
  Eigen::Vector3d out;
  std::stringstream ss(text);
  std::string item;
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n >= 3) throw InputError(option + ": '" + text + "' is not X,Y,Z");
    try {
      std::size_t used = 0;
      out[n] = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(out[n])) throw std::invalid_argument("bad");
    } catch (const std::exception&) {
      throw InputError(option + ": '" + text + "' is not X,Y,Z with three numbers");
    }
    ++n;
  }
  if (n != 3) throw InputError(option + ": '" + text + "' is not X,Y,Z");
  if (!(out.norm() > 0.0)) throw InputError(option + ": the direction must not be zero");
  return out;
}

std::array<std::int64_t, 3> parse_size(const std::string& text) {
  std::array<std::int64_t, 3> out{};
  std::stringstream ss(text);
  std::string item;
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n >= 3) break;
    try {
      std::size_t used = 0;
      const long long v = std::stoll(item, &used);
      if (used != item.size() || v < 1) throw std::invalid_argument("bad");
      out[static_cast<std::size_t>(n)] = v;
    } catch (const std::exception&) {
      throw InputError("--size: '" + text + "' is not NX,NY,NZ with positive integers");
    }
    ++n;
  }
  if (n != 3 || ss.rdbuf()->in_avail() > 0) throw InputError("--size: '" + text + "' is not NX,NY,NZ");
  return out;
}

void run_phantom(const PhantomArgs& a) {
  using namespace preprocess;
  const auto t0 = std::chrono::steady_clock::now();
  PhantomOptions opt;
  opt.voxel_size_m = parse_length(a.voxel_size, "--voxel-size");
  if (!(opt.voxel_size_m > 0.0)) throw InputError("--voxel-size: must be positive, got '" + a.voxel_size + "'");
  opt.helix_endo_rad = parse_angle_deg_default(a.helix_endo, "--helix-endo");
  opt.helix_epi_rad = parse_angle_deg_default(a.helix_epi, "--helix-epi");
  for (auto [v, name] : {std::pair{opt.helix_endo_rad, "--helix-endo"}, std::pair{opt.helix_epi_rad, "--helix-epi"}}) {
    if (std::abs(v) > std::numbers::pi / 2 + 1e-12) {
      throw InputError(std::string(name) + ": helix angle must lie in [-90, 90] degrees");
    }
  }
  if (a.kind == "slab") opt.slab_size = parse_size(a.size);
  const bool wants_fields = !a.fiber_out.empty() || !a.sheet_out.empty();
  if (wants_fields && a.kind != "lv" && a.kind != "biv") {
    throw InputError("--fiber-out/--sheet-out: fibre fields exist only for the lv and biv phantoms, not '" + a.kind +
                     "'");
  }
  ScarCone cone;
  if (!a.scar_out.empty()) {
    if (a.kind != "lv" && a.kind != "biv")
      throw InputError("--scar-out: a scar segment exists only for the lv and biv phantoms, not '" + a.kind + "'");
    cone.direction = parse_direction(a.scar_direction, "--scar-direction");
    cone.half_angle_rad = parse_angle_deg_default(a.scar_angle, "--scar-angle");
    if (!(cone.half_angle_rad > 0.0 && cone.half_angle_rad < std::numbers::pi))
      throw InputError("--scar-angle: the half-angle must lie in (0, 180) degrees");
    require_parent_dir(a.scar_out, "--scar-out");
  }
  require_parent_dir(a.output, "-o");
  if (!a.fiber_out.empty()) require_parent_dir(a.fiber_out, "--fiber-out");
  if (!a.sheet_out.empty()) require_parent_dir(a.sheet_out, "--sheet-out");
  require_distinct_files(
      {}, {{"-o", a.output}, {"--fiber-out", a.fiber_out}, {"--sheet-out", a.sheet_out}, {"--scar-out", a.scar_out}});

  const Phantom ph = make_phantom(a.kind, opt);
  const auto histogram = ph.image.histogram();
  if (std::none_of(histogram.begin(), histogram.end(), [](const auto& lc) { return lc.first != 0 && lc.second > 0; })) {
    throw InputError("--voxel-size: at '" + a.voxel_size + "' the " + a.kind +
                     " phantom has no voxel inside the heart (every voxel is background): use a voxel size "
                     "well below the heart's (the phantoms are meant for 0.5-5 mm)");
  }
  write_label_image(a.output, ph.image);
  if (!a.fiber_out.empty()) write_vector_image(a.fiber_out, *ph.fiber);
  if (!a.sheet_out.empty()) write_vector_image(a.sheet_out, *ph.sheet);
  std::size_t scar_voxels = 0;
  if (!a.scar_out.empty()) {
    const ScalarImage scar = scar_image(ph.image, cone);
    for (double v : scar.values) scar_voxels += v > 0.5 ? 1 : 0;
    write_scalar_image(a.scar_out, scar);
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const auto& d = ph.image.grid.dims;
  std::cout << "phantom " << a.kind << ": " << d[0] << " x " << d[1] << " x " << d[2] << " voxels of "
            << opt.voxel_size_m * 1e3 << " mm\n";
  for (const auto& [label, count] : ph.image.histogram()) {
    std::cout << "  label " << label << ": " << count << " voxels, "
              << static_cast<double>(count) * ph.image.grid.voxel_volume() * 1e9 << " mm^3\n";
  }
  std::cout << "wrote " << a.output;
  if (!a.fiber_out.empty()) std::cout << ", " << a.fiber_out;
  if (!a.sheet_out.empty()) std::cout << ", " << a.sheet_out;
  if (!a.scar_out.empty()) {
    const auto wall = ph.image.histogram().count(kMyocardium) ? ph.image.histogram().at(kMyocardium) : 0;
    std::cout << ", " << a.scar_out << " (scar: " << scar_voxels << " of " << wall << " wall voxels)";
  }
  std::cout << " in " << secs << " s\n";
}

}  // namespace

void add_phantom_command(CLI::App& app) {
  auto args = std::make_shared<PhantomArgs>();
  CLI::App* sub = app.add_subcommand(
      "phantom",
      "Write a synthetic labelled image: lv (Land 2015 truncated ellipsoid: 1 myocardium, 2 LV cavity), "
      "biv (bi-ventricle: 1 myocardium, 2 LV, 3 RV cavity), beam (Land problem-1 10x1x1 mm beam), "
      "slab (a cuboid of --size voxels).");
  sub->add_option("kind", args->kind, "Phantom kind")->required()->check(CLI::IsMember({"lv", "biv", "beam", "slab"}));
  sub->add_option("-o,--output", args->output, "Output NIfTI file (.nii or .nii.gz)")->required();
  sub->add_option("--voxel-size", args->voxel_size, "Voxel edge length, with unit (e.g. 0.5mm)")->capture_default_str();
  sub->add_option("--fiber-out", args->fiber_out, "lv/biv: also write the analytic fibre field (vector NIfTI)");
  sub->add_option("--sheet-out", args->sheet_out, "lv/biv: also write the analytic sheet field (vector NIfTI)");
  sub->add_option("--helix-endo", args->helix_endo,
                  "Fibre helix angle at the endocardium, degrees unless a unit is given (Land problem 3: 90)")
      ->capture_default_str();
  sub->add_option("--helix-epi", args->helix_epi,
                  "Fibre helix angle at the epicardium, degrees unless a unit is given (Land problem 3: -90)")
      ->capture_default_str();
  sub->add_option("--size", args->size, "slab: NX,NY,NZ voxels")->capture_default_str();
  sub->add_option("--scar-out", args->scar_out,
                  "lv/biv: also write a 0/1 scar image (float NIfTI, same grid): the wall voxels inside a cone from "
                  "the LV centre along --scar-direction with half-angle --scar-angle (default: apical-anterior)");
  sub->add_option("--scar-direction", args->scar_direction, "Axis X,Y,Z of the scar cone (from the LV centre)")
      ->capture_default_str();
  sub->add_option("--scar-angle", args->scar_angle, "Half-angle of the scar cone, degrees unless a unit is given")
      ->capture_default_str();
  sub->callback([args]() { run_phantom(*args); });
}

}  // namespace adamss::app
