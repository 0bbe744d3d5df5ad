#include "solver/time/petsc/single_precision_factor.hpp"

#include <mpi.h>
#include <smumps_c.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "common/error.hpp"
#include "solver/time/petsc/nested_dissection.hpp"
#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/row_ij.hpp"

namespace adamss::solver {

namespace {

/// MUMPS's JOB values (MUMPS 5.5 user guide, sec. 5.1).
constexpr int kInit = -1, kEnd = -2, kAnalyse = 1, kFactorise = 2, kSolve = 3;
/// A readable reason for MUMPS's INFOG(1) < 0 (the codes of the user guide, sec. 8).
std::string mumps_reason(int infog1, int infog2) {
  switch (infog1) {
    case -9:
    case -8:
    case -14:
    case -15:
      return "its workspace was too small";
    case -10:
      return "the operator is numerically singular";
    case -13:
      return "an allocation of " + std::to_string(infog2) + " failed";
    default:
      return "INFOG(1) = " + std::to_string(infog1) + ", INFOG(2) = " + std::to_string(infog2);
  }
}

/// -adamss_pivot_order: "metis" (the default) or "mumps" (MUMPS's own choice: PORD or AMF).
bool metis_order_wanted() {
  return option_choice("-adamss_pivot_order", "metis", {"metis", "mumps"}) == "metis";
}

}  // namespace

struct SinglePrecisionFactor::Mumps {
  SMUMPS_STRUC_C id{};
  bool started = false;
};

SinglePrecisionFactor::SinglePrecisionFactor()
    : mumps_(std::make_unique<Mumps>()), metis_wanted_(metis_order_wanted()) {}

SinglePrecisionFactor::~SinglePrecisionFactor() {
  if (gather_ != nullptr) VecScatterDestroy(&gather_);
  if (whole_ != nullptr) VecDestroy(&whole_);
  end();
}

void SinglePrecisionFactor::end() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized != 0) return;
  if (mumps_->started) {
    mumps_->id.job = kEnd;
    smumps_c(&mumps_->id);
    mumps_->started = false;
  }
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

bool SinglePrecisionFactor::call(int job, const char* what) {
  SMUMPS_STRUC_C& id = mumps_->id;
  id.job = job;
  smumps_c(&id);
  if (id.infog[0] >= 0) return true;
  singular_ = id.infog[0] == -10;
  error_ = std::string("MUMPS's single-precision ") + what + " failed: " + mumps_reason(id.infog[0], id.infog[1]);
  return false;
}

namespace {

/// Appends the entries of one CSR block (rows `row0 + i`, columns through `column`) to the
/// coordinate lists: only those on or above the diagonal when `upper`. `offset` is added to the
/// positions (the off-diagonal block's follow the diagonal block's).
template <class Column>
void append_block(Mat block, PetscInt row0, Column column, bool upper, PetscInt offset, std::vector<PetscInt>& position,
                  std::vector<int>& irn, std::vector<int>& jcn) {
  const RowIJ s(block, false);
  const PetscInt* ia = s.ia;
  const PetscInt* ja = s.ja;
  for (PetscInt i = 0; i < s.n; ++i) {
    for (PetscInt k = ia[i]; k < ia[i + 1]; ++k) {
      const PetscInt j = column(ja[k]);
      if (upper && j < row0 + i) continue;  // L D L^T reads the upper triangle
      position.push_back(offset + k);
      irn.push_back(static_cast<int>(row0 + i + 1));
      jcn.push_back(static_cast<int>(j + 1));
    }
  }
}

/// The stored entries of a MATSEQAIJ block.
PetscInt stored_entries(Mat block) {
  MatInfo info;
  petsc_check(MatGetInfo(block, MAT_LOCAL, &info), "MatGetInfo");
  return static_cast<PetscInt>(info.nz_used);
}

/// ICNTL entries this driver sets itself and refuses to take from the options: the matrix's
/// input format and distribution (5, 18), the right-hand side's and the solution's (20, 21), the
/// transposed solve (9), the Schur complement (19), the null-space and partial solves (25, 26, 30,
/// 32), keeping the factors (31: 1 discards them) and the analysis's sequential or parallel kind
/// (28: the given pivot order needs the sequential one, MUMPS's default on one rank and here).
bool driver_owned(int i) {
  return i == 5 || i == 9 || (i >= 18 && i <= 21) || i == 25 || i == 26 || i == 28 || (i >= 30 && i <= 32);
}

/// MUMPS's controls from PETSc's options of the same names, as PETSc's double-precision MUMPS
/// interface reads them: -mat_mumps_icntl_<i> (i = 4 .. 60; not the driver's own, driver_owned)
/// and -mat_mumps_cntl_<i> (i = 1 .. 15). ICNTL(14), the workspace allowance for delayed pivots, is
/// 100 % unless given, as PETSc sets it for the double factorisation. Output streams (ICNTL(1..3))
/// are MUMPS's standard output when -mat_mumps_icntl_4 asks for messages, none otherwise.
void apply_mumps_options(SMUMPS_STRUC_C& id) {
  id.icntl[3] = 0;  // no messages unless asked
  id.icntl[13] = 100;
  for (int i = 4; i <= 60; ++i) {
    if (driver_owned(i)) continue;
    const std::string name = "-mat_mumps_icntl_" + std::to_string(i);
    PetscInt value = 0;
    PetscBool set = PETSC_FALSE;
    petsc_check(PetscOptionsGetInt(nullptr, nullptr, name.c_str(), &value, &set), "PetscOptionsGetInt");
    if (set == PETSC_TRUE) id.icntl[i - 1] = static_cast<MUMPS_INT>(value);
  }
  for (int i = 1; i <= 15; ++i) {
    const std::string name = "-mat_mumps_cntl_" + std::to_string(i);
    PetscReal value = 0.0;
    PetscBool set = PETSC_FALSE;
    petsc_check(PetscOptionsGetReal(nullptr, nullptr, name.c_str(), &value, &set), "PetscOptionsGetReal");
    if (set == PETSC_TRUE) id.cntl[i - 1] = static_cast<float>(value);
  }
  if (id.icntl[6] == 1) {
    throw InputError(
        "-mat_mumps_icntl_7 1: the single-precision factorisation has no user pivot order to give; "
        "-adamss_pivot_order metis gives METIS's");
  }
  id.icntl[27] = 1;  // ICNTL(28) = 1: sequential analysis, which reads a given pivot order
  const bool talk = id.icntl[3] > 0;
  id.icntl[0] = id.icntl[1] = id.icntl[2] = talk ? 6 : -1;
}

}  // namespace

void SinglePrecisionFactor::map(Mat a, bool symmetric) {
  position_.clear();
  irn_.clear();
  jcn_.clear();
  petsc_check(MatGetSize(a, &rows_, nullptr), "MatGetSize");
  source_ = PetscObjectComm(reinterpret_cast<PetscObject>(a));
  int ranks = 1;
  MPI_Comm_size(source_, &ranks);
  if (ranks == 1) {
    append_block(
        a, 0, [](PetscInt j) { return j; }, symmetric, 0, position_, irn_, jcn_);
  } else {
    Mat d = nullptr, o = nullptr;
    const PetscInt* garray = nullptr;
    petsc_check(MatMPIAIJGetSeqAIJ(a, &d, &o, &garray), "MatMPIAIJGetSeqAIJ");
    PetscInt r0 = 0, c0 = 0;
    petsc_check(MatGetOwnershipRange(a, &r0, nullptr), "MatGetOwnershipRange");
    petsc_check(MatGetOwnershipRangeColumn(a, &c0, nullptr), "MatGetOwnershipRangeColumn");
    diagonal_entries_ = stored_entries(d);
    append_block(
        d, r0, [c0](PetscInt j) { return c0 + j; }, symmetric, 0, position_, irn_, jcn_);
    append_block(
        o, r0, [garray](PetscInt j) { return garray[j]; }, symmetric, diagonal_entries_, position_, irn_, jcn_);
  }
  values_.resize(position_.size());
  petsc_check(PetscObjectGetId(reinterpret_cast<PetscObject>(a), &mapped_id_), "PetscObjectGetId");
  petsc_check(MatGetNonzeroState(a, &mapped_state_), "MatGetNonzeroState");
  symmetric_ = symmetric;
  analysed_ = false;
  if (gather_ != nullptr) petsc_check(VecScatterDestroy(&gather_), "VecScatterDestroy");
  if (whole_ != nullptr) petsc_check(VecDestroy(&whole_), "VecDestroy");
}

namespace {

/// All ranks' coordinate lists on rank 0 of `comm` (empty elsewhere). Collective; false on every
/// rank when rank 0 cannot hold them (more than INT_MAX entries, or no memory).
bool gather_pattern(MPI_Comm comm, const std::vector<int>& irn, const std::vector<int>& jcn, std::vector<int>& all_irn,
                    std::vector<int>& all_jcn) {
  int ranks = 1, rank = 0;
  MPI_Comm_size(comm, &ranks);
  MPI_Comm_rank(comm, &rank);
  const int mine = static_cast<int>(irn.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), starts(static_cast<std::size_t>(ranks));
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  int ok = 1;
  if (rank == 0) {
    std::int64_t total = 0;
    for (int r = 0; r < ranks; ++r) {
      starts[static_cast<std::size_t>(r)] = static_cast<int>(std::min<std::int64_t>(total, INT_MAX));
      total += counts[static_cast<std::size_t>(r)];
    }
    try {
      if (total > INT_MAX) throw std::length_error("more entries than MPI's counts");
      all_irn.assign(static_cast<std::size_t>(total), 0);
      all_jcn.assign(static_cast<std::size_t>(total), 0);
    } catch (const std::exception&) {
      ok = 0;
      all_irn.clear();
      all_jcn.clear();
    }
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  if (ok == 0) return false;
  MPI_Gatherv(irn.data(), mine, MPI_INT, all_irn.data(), counts.data(), starts.data(), MPI_INT, 0, comm);
  MPI_Gatherv(jcn.data(), mine, MPI_INT, all_jcn.data(), counts.data(), starts.data(), MPI_INT, 0, comm);
  return true;
}

}  // namespace

std::vector<int> SinglePrecisionFactor::pivot_order(int ranks) {
  metis_order_ = metis_wanted_;
  if (!metis_order_) return {};
  int rank = 0;
  MPI_Comm_rank(comm_, &rank);
  std::vector<int> all_irn, all_jcn;
  int failed = ranks > 1 && !gather_pattern(comm_, irn_, jcn_, all_irn, all_jcn) ? 1 : 0;
  std::vector<int> order;
  if (rank == 0 && failed == 0) {
    try {
      order = nested_dissection_order(static_cast<int>(rows_), ranks > 1 ? all_irn : irn_, ranks > 1 ? all_jcn : jcn_);
    } catch (const std::exception&) {  // out of memory, or past METIS's 32-bit indices
      failed = 1;
    }
  }
  if (ranks > 1) MPI_Bcast(&failed, 1, MPI_INT, 0, comm_);
  if (failed != 0) {  // MUMPS's own order then
    metis_order_ = false;
    order.clear();
  }
  return order;
}

bool SinglePrecisionFactor::factorise(Mat a, bool symmetric) {
  error_.clear();
  singular_ = false;
  PetscInt64 object = -1;
  petsc_check(PetscObjectGetId(reinterpret_cast<PetscObject>(a), &object), "PetscObjectGetId");
  PetscObjectState state = -1;
  petsc_check(MatGetNonzeroState(a, &state), "MatGetNonzeroState");
  if (object != mapped_id_ || state != mapped_state_ || symmetric != symmetric_) map(a, symmetric);
  int ranks = 1;
  MPI_Comm_size(source_, &ranks);
  Mat d = a, o = nullptr;
  if (ranks > 1) petsc_check(MatMPIAIJGetSeqAIJ(a, &d, &o, nullptr), "MatMPIAIJGetSeqAIJ");
  const PetscScalar* vd = nullptr;
  const PetscScalar* vo = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(d, &vd), "MatSeqAIJGetArrayRead");
  if (o != nullptr) petsc_check(MatSeqAIJGetArrayRead(o, &vo), "MatSeqAIJGetArrayRead");
  for (std::size_t e = 0; e < position_.size(); ++e) {
    const PetscInt k = position_[e];
    values_[e] = static_cast<float>(k < diagonal_entries_ || o == nullptr ? vd[k] : vo[k - diagonal_entries_]);
  }
  petsc_check(MatSeqAIJRestoreArrayRead(d, &vd), "MatSeqAIJRestoreArrayRead");
  if (o != nullptr) petsc_check(MatSeqAIJRestoreArrayRead(o, &vo), "MatSeqAIJRestoreArrayRead");
  SMUMPS_STRUC_C& id = mumps_->id;
  if (!analysed_) {
    end();
    MPI_Comm_dup(source_, &comm_);
    id = SMUMPS_STRUC_C{};
    id.par = 1;  // the host works too
    id.sym = symmetric ? 2 : 0;
    id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(comm_));
    mumps_->started = call(kInit, "initialisation");
    if (!mumps_->started) return false;
    apply_mumps_options(id);
    id.n = static_cast<MUMPS_INT>(rows_);
    if (ranks == 1) {
      id.nnz = static_cast<MUMPS_INT8>(values_.size());
      id.irn = irn_.data();
      id.jcn = jcn_.data();
    } else {
      id.icntl[17] = 3;  // ICNTL(18): each rank gives its own entries
      id.nnz_loc = static_cast<MUMPS_INT8>(values_.size());
      id.irn_loc = irn_.data();
      id.jcn_loc = jcn_.data();
    }
    const std::vector<int> order = pivot_order(ranks);
    if (!order.empty()) id.perm_in = const_cast<int*>(order.data());  // MUMPS only reads it
    if (metis_order_) id.icntl[6] = 1;                                // ICNTL(7) = 1: the given pivot order
    const bool analysed = call(kAnalyse, "analysis");
    id.perm_in = nullptr;  // read by the analysis only; `order` ends here
    if (!analysed) return false;
    analysed_ = true;
    ++analyses_;
  }
  if (ranks == 1) {
    id.a = values_.data();
  } else {
    id.a_loc = values_.data();
  }
  return call(kFactorise, "factorisation");
}

bool SinglePrecisionFactor::solve_gathered(PetscScalar* rhs, PetscInt n, int columns) {
  // Each column scaled by its largest entry (a zero column by 1: its solution is zero).
  std::vector<double> scale(static_cast<std::size_t>(columns), 0.0);
  for (int j = 0; j < columns; ++j) {
    const PetscScalar* col = rhs + static_cast<std::ptrdiff_t>(j) * n;
    for (PetscInt i = 0; i < n; ++i)
      scale[static_cast<std::size_t>(j)] = std::max(scale[static_cast<std::size_t>(j)], std::abs(col[i]));
  }
  MPI_Bcast(scale.data(), columns, MPI_DOUBLE, 0, comm_);
  if (std::all_of(scale.begin(), scale.end(), [](double s) { return s == 0.0; })) return true;  // zero solutions
  std::replace(scale.begin(), scale.end(), 0.0, 1.0);
  rhs_.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(columns));
  const auto size = static_cast<std::size_t>(n);
  for (std::size_t k = 0; k < rhs_.size(); ++k) rhs_[k] = static_cast<float>(rhs[k] / scale[k / size]);
  SMUMPS_STRUC_C& id = mumps_->id;
  id.rhs = rhs_.data();
  id.nrhs = columns;
  id.lrhs = static_cast<MUMPS_INT>(rows_);
  if (!call(kSolve, "solve")) return false;
  for (std::size_t k = 0; k < rhs_.size(); ++k) rhs[k] = scale[k / size] * static_cast<double>(rhs_[k]);
  return true;
}

bool SinglePrecisionFactor::solve(Vec in, Vec out) {
  return solve_many({in}, {out});
}

bool SinglePrecisionFactor::solve_many(const std::vector<Vec>& in, const std::vector<Vec>& out) {
  if (in.size() != out.size()) throw std::logic_error("SinglePrecisionFactor::solve_many: as many outputs as inputs");
  if (in.empty()) return true;
  const int columns = static_cast<int>(in.size());
  int ranks = 1;
  MPI_Comm_size(comm_, &ranks);
  if (ranks > 1 && gather_ == nullptr)
    petsc_check(VecScatterCreateToZero(in[0], &gather_, &whole_), "VecScatterCreateToZero");
  // The columns side by side (column-major, n rows: all of them on rank 0, none elsewhere).
  PetscInt n = rows_;
  if (ranks > 1) petsc_check(VecGetLocalSize(whole_, &n), "VecGetLocalSize");
  many_.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(columns));
  const auto column = [this, n](int j) { return many_.data() + static_cast<std::ptrdiff_t>(j) * n; };
  for (int j = 0; j < columns; ++j) {
    Vec source = in[static_cast<std::size_t>(j)];
    if (ranks > 1) {
      petsc_check(VecScatterBegin(gather_, source, whole_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterBegin");
      petsc_check(VecScatterEnd(gather_, source, whole_, INSERT_VALUES, SCATTER_FORWARD), "VecScatterEnd");
      source = whole_;
    }
    const PetscScalar* v = nullptr;
    petsc_check(VecGetArrayRead(source, &v), "VecGetArrayRead");
    std::copy(v, v + n, column(j));
    petsc_check(VecRestoreArrayRead(source, &v), "VecRestoreArrayRead");
  }
  const bool ok = solve_gathered(many_.data(), n, columns);
  for (int j = 0; j < columns; ++j) {
    Vec target = ranks > 1 ? whole_ : out[static_cast<std::size_t>(j)];
    PetscScalar* v = nullptr;
    petsc_check(VecGetArray(target, &v), "VecGetArray");
    std::copy(column(j), column(j) + n, v);
    petsc_check(VecRestoreArray(target, &v), "VecRestoreArray");
    if (ranks > 1) {
      petsc_check(VecScatterBegin(gather_, whole_, out[static_cast<std::size_t>(j)], INSERT_VALUES, SCATTER_REVERSE),
                  "VecScatterBegin");
      petsc_check(VecScatterEnd(gather_, whole_, out[static_cast<std::size_t>(j)], INSERT_VALUES, SCATTER_REVERSE),
                  "VecScatterEnd");
    }
  }
  return ok;
}

}  // namespace adamss::solver
