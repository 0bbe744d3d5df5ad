#include "materials/factory.hpp"

#include <array>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/suggest.hpp"
#include "materials/elastic_constants.hpp"
#include "materials/guccione.hpp"
#include "materials/holzapfel_ogden.hpp"
#include "materials/hunter.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/params.hpp"
#include "materials/svk.hpp"
#include "materials/volumetric.hpp"

namespace adamss::materials {

namespace {

using Builder = std::unique_ptr<Law> (*)(ParamReader&);

/// Reads the 18 Hunter parameters; each falls back to `defaults` when `required` is false.
std::unique_ptr<Law> hunter_from(ParamReader& r, const HunterParams& defaults, bool required) {
  HunterParams p = defaults;
  for (int t = 0; t < 6; ++t) {
    const std::string id(HunterParams::kTerms[t]);
    p.k[t] = required ? r.required("k" + id) : r.optional("k" + id, defaults.k[t]);
    p.a[t] = required ? r.required("a" + id) : r.optional("a" + id, defaults.a[t]);
    p.b[t] = required ? r.required("b" + id) : r.optional("b" + id, defaults.b[t]);
  }
  p.pole_fraction = r.optional("pole_fraction", defaults.pole_fraction);
  r.finish();
  return std::make_unique<LawOf<HunterPoleZero>>(HunterPoleZero(p));
}

std::unique_ptr<Law> guccione_from(ParamReader& r, const GuccioneParams& defaults, bool required) {
  auto get = [&](const char* key, double fallback) { return required ? r.required(key) : r.optional(key, fallback); };
  GuccioneParams p;
  p.C = get("C", defaults.C);
  p.b_f = get("b_f", defaults.b_f);
  p.b_t = get("b_t", defaults.b_t);
  p.b_fs = get("b_fs", defaults.b_fs);
  r.finish();
  return std::make_unique<LawOf<Guccione>>(Guccione(p));
}

/// The eight Holzapfel-Ogden parameters (a.. in Pa); each falls back to `defaults` when
/// `required` is false.
std::unique_ptr<Law> holzapfel_ogden_from(ParamReader& r, const HolzapfelOgdenParams& defaults, bool required) {
  auto get = [&](const char* key, double fallback) { return required ? r.required(key) : r.optional(key, fallback); };
  HolzapfelOgdenParams p;
  p.a = get("a", defaults.a);
  p.b = get("b", defaults.b);
  p.a_f = get("a_f", defaults.a_f);
  p.b_f = get("b_f", defaults.b_f);
  p.a_s = get("a_s", defaults.a_s);
  p.b_s = get("b_s", defaults.b_s);
  p.a_fs = get("a_fs", defaults.a_fs);
  p.b_fs = get("b_fs", defaults.b_fs);
  r.finish();
  return std::make_unique<LawOf<HolzapfelOgden>>(HolzapfelOgden(p));
}

template <typename P>
std::unique_ptr<Law> volumetric_from(ParamReader& r) {
  P penalty;
  penalty.kappa = r.required("kappa");
  r.finish();
  return std::make_unique<LawOf<VolumetricLaw<P>>>(VolumetricLaw<P>(penalty));
}

std::unique_ptr<Law> svk_named(ParamReader& r, std::string_view name) {
  const Lame lame = read_lame(r);
  r.finish();
  return std::make_unique<LawOf<StVenantKirchhoff>>(StVenantKirchhoff(lame, name));
}

struct Entry {
  std::string_view name;
  Builder build;
};

const std::array<Entry, 14> kLaws{{
    {"hunter", [](ParamReader& r) { return hunter_from(r, HunterParams{}, true); }},
    {"hunter_canine", [](ParamReader& r) { return hunter_from(r, hunter_canine(), false); }},
    {"guccione", [](ParamReader& r) { return guccione_from(r, GuccioneParams{}, true); }},
    {"guccione_land_problem1", [](ParamReader& r) { return guccione_from(r, guccione_land_problem1(), false); }},
    {"guccione_land_problem2", [](ParamReader& r) { return guccione_from(r, guccione_land_problem2(), false); }},
    {"guccione_land_problem3", [](ParamReader& r) { return guccione_from(r, guccione_land_problem3(), false); }},
    {"holzapfel_ogden", [](ParamReader& r) { return holzapfel_ogden_from(r, HolzapfelOgdenParams{}, true); }},
    {"holzapfel_ogden_2009", [](ParamReader& r) { return holzapfel_ogden_from(r, holzapfel_ogden_2009(), false); }},
    {"svk", [](ParamReader& r) { return svk_named(r, "svk"); }},
    {"st_venant_kirchhoff", [](ParamReader& r) { return svk_named(r, "svk"); }},
    {"linear_elastic", [](ParamReader& r) { return svk_named(r, "linear_elastic"); }},
    {"neo_hookean",
     [](ParamReader& r) -> std::unique_ptr<Law> {
       const Lame lame = read_lame(r);
       r.finish();
       return std::make_unique<LawOf<NeoHookean>>(NeoHookean(lame));
     }},
    {"volumetric_quadratic", [](ParamReader& r) { return volumetric_from<QuadraticPenalty>(r); }},
    {"volumetric_log", [](ParamReader& r) { return volumetric_from<LogPenalty>(r); }},
}};

}  // namespace

std::unique_ptr<Law> make_law(const std::string& name, const std::map<std::string, double>& params) {
  for (const Entry& entry : kLaws) {
    if (entry.name != name) continue;
    ParamReader reader(name, params);
    return entry.build(reader);
  }
  std::string known;
  std::vector<std::string> names;
  for (const Entry& entry : kLaws) {
    known.append(known.empty() ? "" : ", ").append(entry.name);
    names.emplace_back(entry.name);
  }
  throw InputError("unknown material law '" + name + "'" + did_you_mean(name, names) + " (known: " + known + ")");
}

std::vector<std::string_view> known_laws() {
  std::vector<std::string_view> names;
  names.reserve(kLaws.size());
  for (const Entry& entry : kLaws) names.push_back(entry.name);
  return names;
}

}  // namespace adamss::materials
