#include "solver/time/petsc/petsc_matrix.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

class BlockMatrix::Sink final : public JacobianSink {
 public:
  explicit Sink(Mat a) : a_(a) {}
  void add_block(Index a, Index b, const Eigen::Matrix3d& dfdx, const Eigen::Matrix3d& dfdv) override {
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> blk = cx * dfdx + cv * dfdv;
    const PetscInt r = a, c = b;
    petsc_check(MatSetValuesBlocked(a_, 1, &r, 1, &c, blk.data(), ADD_VALUES), "MatSetValuesBlocked");
  }
  double cx = 0.0, cv = 0.0;

 private:
  Mat a_;
};

BlockMatrix::BlockMatrix(const preprocess::Mesh& mesh, const std::vector<std::unique_ptr<ForceTerm>>* terms)
    : n_(static_cast<PetscInt>(mesh.node_count())) {
  ensure_petsc();
  // Node adjacency from the elements (sorted, unique), for the block preallocation.
  const int k = preprocess::nodes_per_element(mesh.type);
  std::vector<std::vector<Index>> adj(static_cast<std::size_t>(n_));
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const Index* en = mesh.element(e);
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) adj[static_cast<std::size_t>(en[a])].push_back(en[b]);
  }
  if (terms != nullptr) {
    for (const auto& t : *terms) t->add_couplings(adj);
  }
  std::vector<PetscInt> nnz(static_cast<std::size_t>(n_));
  for (PetscInt i = 0; i < n_; ++i) {
    auto& row = adj[static_cast<std::size_t>(i)];
    row.push_back(i);
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    nnz[static_cast<std::size_t>(i)] = static_cast<PetscInt>(row.size());
  }
  petsc_check(MatCreate(PETSC_COMM_WORLD, &a_), "MatCreate");
  petsc_check(MatSetSizes(a_, PETSC_DECIDE, PETSC_DECIDE, 3 * n_, 3 * n_), "MatSetSizes");
  petsc_check(MatSetType(a_, MATAIJ), "MatSetType");
  petsc_check(MatSetBlockSize(a_, 3), "MatSetBlockSize");
  petsc_check(MatXAIJSetPreallocation(a_, 3, nnz.data(), nnz.data(), nullptr, nullptr), "MatXAIJSetPreallocation");
  petsc_check(MatSetOption(a_, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  // Insert explicit zeros on the whole pattern so that it is fixed from the first assembly on.
  std::vector<double> zeros;
  for (PetscInt i = 0; i < n_; ++i) {
    const auto& row = adj[static_cast<std::size_t>(i)];
    zeros.assign(9 * row.size(), 0.0);
    std::vector<PetscInt> cols(row.begin(), row.end());
    petsc_check(
        MatSetValuesBlocked(a_, 1, &i, static_cast<PetscInt>(cols.size()), cols.data(), zeros.data(), INSERT_VALUES),
        "MatSetValuesBlocked");
  }
  assemble();
  sink_ = std::make_unique<Sink>(a_);
}

BlockMatrix::~BlockMatrix() {
  if (a_ != nullptr) MatDestroy(&a_);
}

void BlockMatrix::zero() {
  petsc_check(MatZeroEntries(a_), "MatZeroEntries");
}

JacobianSink& BlockMatrix::sink(double cx, double cv) {
  sink_->cx = cx;
  sink_->cv = cv;
  return *sink_;
}

void BlockMatrix::add_diagonal(const Eigen::VectorXd& mass, double c) {
  for (PetscInt i = 0; i < n_; ++i) {
    for (PetscInt d = 0; d < 3; ++d) {
      const PetscInt r = 3 * i + d;
      const double v = c * mass[i];
      petsc_check(MatSetValues(a_, 1, &r, 1, &r, &v, ADD_VALUES), "MatSetValues");
    }
  }
}

void BlockMatrix::assemble() {
  petsc_check(MatAssemblyBegin(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  petsc_check(MatAssemblyEnd(a_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
}

void BlockMatrix::eliminate(const std::vector<PetscInt>& dofs, Vec x, Vec b) {
  petsc_check(MatZeroRowsColumns(a_, static_cast<PetscInt>(dofs.size()), dofs.data(), 1.0, x, b), "MatZeroRowsColumns");
}

std::vector<PetscInt> constrained_dofs(const std::vector<std::uint8_t>& mask) {
  std::vector<PetscInt> out;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    for (int c = 0; c < 3; ++c)
      if ((mask[i] >> c) & 1U) out.push_back(static_cast<PetscInt>(3 * i + static_cast<std::size_t>(c)));
  }
  return out;
}

}  // namespace adamss::solver
