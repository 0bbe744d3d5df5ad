#pragma once
// A PETSc matrix's CSR structure (MatGetRowIJ), released by the destructor.
#include <petscmat.h>

#include "common/error.hpp"
#include "solver/time/petsc/petsc_env.hpp"

namespace adamss::solver {

/// The row structure of `mat` for as long as this lives: ia (n + 1 row starts) and ja (columns);
/// `blocks`: block rows and block columns (MATSEQBAIJ, MATSEQSBAIJ: the stored upper triangle)
/// instead of entries. Throws NumericalError when the type cannot give it.
struct RowIJ {
  RowIJ(Mat m, bool blocks) : mat(m), compressed(blocks ? PETSC_TRUE : PETSC_FALSE) {
    PetscBool done = PETSC_FALSE;
    petsc_check(MatGetRowIJ(mat, 0, PETSC_FALSE, compressed, &n, &ia, &ja, &done), "MatGetRowIJ");
    if (done != PETSC_TRUE) throw NumericalError("the operator's row structure is not available (MatGetRowIJ)");
  }
  ~RowIJ() {
    PetscBool done = PETSC_FALSE;
    MatRestoreRowIJ(mat, 0, PETSC_FALSE, compressed, &n, &ia, &ja, &done);
  }
  RowIJ(const RowIJ&) = delete;
  RowIJ& operator=(const RowIJ&) = delete;
  Mat mat;
  PetscBool compressed;
  PetscInt n = 0;
  const PetscInt* ia = nullptr;
  const PetscInt* ja = nullptr;
};

}  // namespace adamss::solver
