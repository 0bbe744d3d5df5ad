#include "solver/terms/fem/active_stress_gauss.hpp"

#include <string>
#include <utility>

#include "common/error.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/terms/fem/fem_element.hpp"

namespace adamss::solver {

namespace {

template <int K>
std::unique_ptr<ForceTerm> make_term(const preprocess::Mesh& mesh, const ActiveTensionParams& params,
                                     const std::vector<std::size_t>* element_subset) {
  GaussPoints<K> gp = make_gauss_points<K>(mesh, element_subset, "active_tension");
  ActiveStressKernel<K> kern;
  kern.fraction = active_fractions(params);
  const auto points = static_cast<std::size_t>(gp.points);
  for (std::size_t j = 0; j < gp.elements.size(); ++j) {
    for (std::size_t q = 0; q < points; ++q) {
      kern.elements.push_back(gp.elements[j]);
      kern.element.push_back(gp.element_index[j]);
    }
  }
  kern.gradient = std::move(gp.gradient);
  kern.frame = std::move(gp.frame);
  kern.volume0 = std::move(gp.volume0);
  ActiveTensionParams per_item = params;
  if (!params.delay.empty()) {
    per_item.delay.clear();
    for (const std::size_t e : kern.element) per_item.delay.push_back(params.delay[e]);
  }
  kern.schedule = make_activation_schedule(per_item, kern.element);
  return std::make_unique<StencilTerm<ActiveStressKernel<K>, K>>(std::move(kern));
}

}  // namespace

std::unique_ptr<ForceTerm> make_gauss_active_stress_term(const preprocess::Mesh& mesh,
                                                         const ActiveTensionParams& params,
                                                         const std::vector<std::size_t>* element_subset) {
  if (params.form != ActiveTensionParams::Form::Stress) {
    throw InputError(std::string("active_tension: on quadratic ") + preprocess::element_type_name(mesh.type) +
                     " elements only form stress is available (the tension and force forms act on the axis frames "
                     "of linear elements)");
  }
  if (mesh.type != preprocess::ElementType::Tet10 && mesh.type != preprocess::ElementType::Hex27)
    throw InputError("active_tension: the Gauss-point active stress is built for tet10 and hex27 meshes");
  if (!params.delay.empty() && params.delay.size() != mesh.element_count()) {
    throw InputError("active_tension.delay: has " + std::to_string(params.delay.size()) + " entries but the mesh has " +
                     std::to_string(mesh.element_count()) + " elements");
  }
  if (mesh.type == preprocess::ElementType::Hex27) return make_term<27>(mesh, params, element_subset);
  return make_term<10>(mesh, params, element_subset);
}

}  // namespace adamss::solver
