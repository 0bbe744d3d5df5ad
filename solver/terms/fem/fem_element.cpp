#include "solver/terms/fem/fem_element.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "solver/core/element_subset.hpp"
#include "solver/core/stencil_term.hpp"
#include "solver/geometry/element_rules.hpp"

namespace adamss::solver {

namespace {

/// The element's fibre frame B = [f s n] (orthonormal, right-handed), identity without fibres.
Eigen::Matrix3d element_frame(const preprocess::Mesh& mesh, std::size_t e, const std::string& label) {
  if (!mesh.has_fibres()) return Eigen::Matrix3d::Identity();
  const auto c = static_cast<Eigen::Index>(e);
  Eigen::Vector3d f = mesh.fiber.col(c);
  Eigen::Vector3d s = mesh.sheet.col(c);
  if (!f.allFinite() || !s.allFinite() || f.norm() < 1e-12) {
    std::ostringstream os;
    os << label << ": element " << e << " has a non-finite or zero fibre/sheet direction";
    throw InputError(os.str());
  }
  f.normalize();
  s -= s.dot(f) * f;
  if (s.norm() < 1e-6) {
    std::ostringstream os;
    os << label << ": element " << e << " has its sheet direction parallel to its fibre";
    throw InputError(os.str());
  }
  s.normalize();
  Eigen::Matrix3d b;
  b << f, s, f.cross(s);
  return b;
}

}  // namespace

template <int K>
GaussPoints<K> make_gauss_points(const preprocess::Mesh& mesh, const std::vector<std::size_t>* element_subset,
                                 const std::string& label) {
  if (preprocess::nodes_per_element(mesh.type) != K)
    throw InputError(label + ": mesh element type does not match the kernel");
  constexpr int kPoints = K == 8 ? 8 : (K == 10 ? 4 : (K == 27 ? 27 : 1));
  GaussPoints<K> gp;
  gp.points = kPoints;
  const std::vector<std::size_t> elements = selected_elements(mesh, element_subset, label);
  gp.elements.reserve(elements.size());
  for (const std::size_t e : elements) {
    const Index* n = mesh.element(e);
    std::array<Index, K> st{};
    Eigen::Matrix<double, 3, K> x0;
    for (int a = 0; a < K; ++a) {
      st[static_cast<std::size_t>(a)] = n[a];
      x0.col(a) = mesh.nodes.col(n[a]);
    }
    const Eigen::Matrix3d b = element_frame(mesh, e, label);
    gp.elements.push_back(st);
    gp.element_index.push_back(e);
    for (int q = 0; q < kPoints; ++q) {
      Eigen::Matrix<double, K, 3> gamma;
      double w = 0.0;
      if constexpr (K == 8) {
        gamma = hex_gauss_gradients()[static_cast<std::size_t>(q)];
        w = kHexGaussWeight;
      } else if constexpr (K == 27) {
        gamma = preprocess::hex27_gauss_gradients()[static_cast<std::size_t>(q)];
        w = preprocess::hex27_gauss_weight(q);
      } else if constexpr (K == 10) {
        static const auto kGrads = preprocess::tet10_rule_gradients(preprocess::tet10_law_rule());
        gamma = kGrads[static_cast<std::size_t>(q)];
        w = preprocess::tet10_law_rule()[static_cast<std::size_t>(q)].w;
      } else {
        gamma = tet_shape_gradients();
        w = kTetWeight;
      }
      const Eigen::Matrix3d j0 = x0 * gamma;
      const double det = j0.determinant();
      if (!(det > 0.0)) {
        std::ostringstream os;
        os << label << ": element " << e << " is inverted or flat at Gauss point " << q << " (det J = " << det << ")";
        throw InputError(os.str());
      }
      gp.gradient.push_back(gamma * j0.inverse());
      gp.frame.push_back(b);
      gp.volume0.push_back(w * det);
    }
  }
  return gp;
}

template GaussPoints<4> make_gauss_points<4>(const preprocess::Mesh&, const std::vector<std::size_t>*,
                                             const std::string&);
template GaussPoints<8> make_gauss_points<8>(const preprocess::Mesh&, const std::vector<std::size_t>*,
                                             const std::string&);
template GaussPoints<10> make_gauss_points<10>(const preprocess::Mesh&, const std::vector<std::size_t>*,
                                               const std::string&);
template GaussPoints<27> make_gauss_points<27>(const preprocess::Mesh&, const std::vector<std::size_t>*,
                                               const std::string&);

template <int K>
GradientLawKernel<K> make_gauss_point_kernel(const preprocess::Mesh& mesh,
                                             const std::shared_ptr<const materials::Law>& law,
                                             const std::vector<std::size_t>* element_subset, const std::string& label) {
  if (!law) throw InputError(label + ": no constitutive law given");
  GaussPoints<K> gp = make_gauss_points<K>(mesh, element_subset, label);
  GradientLawKernel<K> kern;
  kern.law = law;
  kern.label = label;
  kern.points = gp.points;
  kern.elements = std::move(gp.elements);
  kern.element_index = std::move(gp.element_index);
  kern.gradient = std::move(gp.gradient);
  kern.frame = std::move(gp.frame);
  kern.volume0 = std::move(gp.volume0);
  return kern;
}

template GradientLawKernel<4> make_gauss_point_kernel<4>(const preprocess::Mesh&,
                                                         const std::shared_ptr<const materials::Law>&,
                                                         const std::vector<std::size_t>*, const std::string&);
template GradientLawKernel<8> make_gauss_point_kernel<8>(const preprocess::Mesh&,
                                                         const std::shared_ptr<const materials::Law>&,
                                                         const std::vector<std::size_t>*, const std::string&);
template GradientLawKernel<10> make_gauss_point_kernel<10>(const preprocess::Mesh&,
                                                           const std::shared_ptr<const materials::Law>&,
                                                           const std::vector<std::size_t>*, const std::string&);
template GradientLawKernel<27> make_gauss_point_kernel<27>(const preprocess::Mesh&,
                                                           const std::shared_ptr<const materials::Law>&,
                                                           const std::vector<std::size_t>*, const std::string&);

std::unique_ptr<ForceTerm> make_gauss_point_term(const preprocess::Mesh& mesh,
                                                 const std::shared_ptr<const materials::Law>& law,
                                                 const std::vector<std::size_t>* element_subset,
                                                 const std::string& label) {
  if (mesh.type == preprocess::ElementType::Tet4) {
    return std::make_unique<StencilTerm<GradientLawKernel<4>, 4>>(
        make_gauss_point_kernel<4>(mesh, law, element_subset, label));
  }
  if (mesh.type == preprocess::ElementType::Tet10) {
    return std::make_unique<StencilTerm<GradientLawKernel<10>, 10>>(
        make_gauss_point_kernel<10>(mesh, law, element_subset, label));
  }
  if (mesh.type == preprocess::ElementType::Hex27) {
    return std::make_unique<StencilTerm<GradientLawKernel<27>, 27>>(
        make_gauss_point_kernel<27>(mesh, law, element_subset, label));
  }
  return std::make_unique<StencilTerm<GradientLawKernel<8>, 8>>(
      make_gauss_point_kernel<8>(mesh, law, element_subset, label));
}

}  // namespace adamss::solver
