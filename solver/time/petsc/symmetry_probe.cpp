#include "solver/time/petsc/symmetry_probe.hpp"

#include <algorithm>
#include <cmath>

#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

void SymmetryProbe::map(Mat a) {
  PetscInt n = 0;
  const PetscInt* ia = nullptr;
  const PetscInt* ja = nullptr;
  PetscBool done = PETSC_FALSE;
  petsc_check(MatGetRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done), "MatGetRowIJ");
  mirror_.assign(static_cast<std::size_t>(ia[n]), -1);
  for (PetscInt i = 0; i < n; ++i) {
    for (PetscInt k = ia[i]; k < ia[i + 1]; ++k) {
      const PetscInt j = ja[k];
      const PetscInt* lo = ja + ia[j];
      const PetscInt* hi = ja + ia[j + 1];
      const PetscInt* at = std::lower_bound(lo, hi, i);
      if (at != hi && *at == i) mirror_[static_cast<std::size_t>(k)] = static_cast<PetscInt>(at - ja);
    }
  }
  rows_ = n;
  nonzeros_ = ia[n];
  petsc_check(MatRestoreRowIJ(a, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done), "MatRestoreRowIJ");
  mapped_ = a;
}

bool SymmetryProbe::symmetric_distributed(Mat a) {
  // The largest |a_kl| over both blocks of every rank (MatNorm's NORM_MAX is the largest row sum).
  Mat d = nullptr, o = nullptr;
  petsc_check(MatMPIAIJGetSeqAIJ(a, &d, &o, nullptr), "MatMPIAIJGetSeqAIJ");
  double largest = 0.0;
  for (Mat part : {d, o}) {
    MatInfo info;
    petsc_check(MatGetInfo(part, MAT_LOCAL, &info), "MatGetInfo");
    const PetscScalar* v = nullptr;
    petsc_check(MatSeqAIJGetArrayRead(part, &v), "MatSeqAIJGetArrayRead");
    for (PetscInt k = 0; k < static_cast<PetscInt>(info.nz_used); ++k) largest = std::max(largest, std::abs(v[k]));
    petsc_check(MatSeqAIJRestoreArrayRead(part, &v), "MatSeqAIJRestoreArrayRead");
  }
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(a));
  MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  // PETSc compares the diagonal blocks and, through a gather of the other ranks' rows, the
  // off-diagonal ones (|a_ij - a_ji| <= tol); each rank sees only its own off-diagonal pairs, so
  // the answers are joined (every rank must choose the same factorisation).
  PetscBool same = PETSC_FALSE;
  petsc_check(MatIsSymmetric(a, kTolerance * largest, &same), "MatIsSymmetric");
  int all = same == PETSC_TRUE ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, comm);
  return all == 1;
}

bool SymmetryProbe::symmetric(Mat a) {
  PetscBool seq = PETSC_FALSE;
  petsc_check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(a), MATSEQAIJ, &seq), "PetscObjectTypeCompare");
  if (seq != PETSC_TRUE) return symmetric_distributed(a);
  PetscInt n = 0;
  petsc_check(MatGetSize(a, &n, nullptr), "MatGetSize");
  MatInfo info;
  petsc_check(MatGetInfo(a, MAT_LOCAL, &info), "MatGetInfo");
  if (a != mapped_ || n != rows_ || static_cast<PetscInt>(info.nz_used) != nonzeros_) map(a);
  const PetscScalar* v = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(a, &v), "MatSeqAIJGetArrayRead");
  double largest = 0.0;
  for (PetscInt k = 0; k < nonzeros_; ++k) largest = std::max(largest, std::abs(v[k]));
  const double tol = kTolerance * largest;
  bool same = true;
  for (PetscInt k = 0; k < nonzeros_ && same; ++k) {
    const PetscInt m = mirror_[static_cast<std::size_t>(k)];
    same = std::abs(v[k] - (m >= 0 ? v[m] : 0.0)) <= tol;
  }
  petsc_check(MatSeqAIJRestoreArrayRead(a, &v), "MatSeqAIJRestoreArrayRead");
  return same;
}

}  // namespace adamss::solver
