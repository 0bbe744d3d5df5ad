#pragma once
// Shared fixtures of the explicit-path tests (test_soa_loops.cpp, test_volume_check.cpp).
#include <Eigen/Core>
#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "preprocess/mesh/mesh.hpp"

namespace adamss::testing {

/// Positions of `mesh` moved by a random field of relative size `amp` (fixed seed).
inline Eigen::Matrix3Xd perturbed(const preprocess::Mesh& mesh, double amp, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double h = (mesh.nodes.rowwise().maxCoeff() - mesh.nodes.rowwise().minCoeff()).maxCoeff();
  Eigen::Matrix3Xd x = mesh.nodes;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += amp * h * u(rng);
  return x;
}

/// The same mesh with its nodes renumbered by a random permutation (an "unstructured" order).
inline preprocess::Mesh shuffled(const preprocess::Mesh& mesh, unsigned seed = 3) {
  std::vector<preprocess::Index> perm(mesh.node_count());
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  preprocess::Mesh out = mesh;
  for (std::size_t i = 0; i < perm.size(); ++i) out.nodes.col(perm[i]) = mesh.nodes.col(static_cast<Eigen::Index>(i));
  for (auto& n : out.connectivity) n = perm[static_cast<std::size_t>(n)];
  return out;
}

}  // namespace adamss::testing
