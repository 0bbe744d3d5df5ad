#include "solver/time/petsc/symmetry_probe.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "solver/time/petsc/petsc_env.hpp"
#include "solver/time/petsc/row_ij.hpp"

namespace adamss::solver {

namespace {

/// The largest |a_kl| stored in the MATSEQAIJ `a`.
double largest_entry(Mat a) {
  MatInfo info;
  petsc_check(MatGetInfo(a, MAT_LOCAL, &info), "MatGetInfo");
  const PetscScalar* v = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(a, &v), "MatSeqAIJGetArrayRead");
  double largest = 0.0;
  for (PetscInt k = 0; k < static_cast<PetscInt>(info.nz_used); ++k) largest = std::max(largest, std::abs(v[k]));
  petsc_check(MatSeqAIJRestoreArrayRead(a, &v), "MatSeqAIJRestoreArrayRead");
  return largest;
}

/// MPI_Alltoallv's displacements for `count` items per rank, each `width` values wide.
std::vector<int> displacements(const std::vector<int>& count, int width) {
  std::vector<int> d(count.size(), 0);
  for (std::size_t s = 1; s < count.size(); ++s) d[s] = d[s - 1] + width * count[s - 1];
  return d;
}

}  // namespace

void SymmetryProbe::map(Mat a) {
  const RowIJ s(a, false);
  const PetscInt n = s.n;
  const PetscInt* ia = s.ia;
  const PetscInt* ja = s.ja;
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
  mapped_ = a;
}

void SymmetryProbe::plan_exchange(Mat a, Mat o, const PetscInt* garray) {
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(a));
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  const PetscInt* cranges = nullptr;
  petsc_check(MatGetOwnershipRangesColumn(a, &cranges), "MatGetOwnershipRangesColumn");
  PetscInt r0 = 0;
  petsc_check(MatGetOwnershipRange(a, &r0, nullptr), "MatGetOwnershipRange");
  const RowIJ so(o, false);
  const PetscInt n = so.n;
  const PetscInt* io = so.ia;
  const PetscInt* jo = so.ja;
  // Each off-diagonal entry (i, j) goes to the owner of row j, which compares it with its (j, i).
  const auto owner = [&](PetscInt col) {
    return static_cast<int>(std::upper_bound(cranges, cranges + ranks + 1, col) - cranges) - 1;
  };
  std::vector<std::vector<std::pair<PetscInt, PetscInt>>> by_rank(static_cast<std::size_t>(ranks));  // (q, row)
  for (PetscInt r = 0; r < n; ++r) {
    for (PetscInt q = io[r]; q < io[r + 1]; ++q)
      by_rank[static_cast<std::size_t>(owner(garray[jo[q]]))].emplace_back(q, r);
  }
  send_pos_.clear();
  send_count_.assign(static_cast<std::size_t>(ranks), 0);
  std::vector<PetscInt> pairs;  // (row of the receiver = j, column = i) per entry
  for (int s = 0; s < ranks; ++s) {
    const auto& list = by_rank[static_cast<std::size_t>(s)];
    send_count_[static_cast<std::size_t>(s)] = static_cast<int>(list.size());
    for (const auto& [q, row] : list) {
      send_pos_.push_back(q);
      pairs.push_back(garray[jo[q]]);
      pairs.push_back(r0 + row);
    }
  }
  recv_count_.assign(static_cast<std::size_t>(ranks), 0);
  MPI_Alltoall(send_count_.data(), 1, MPI_INT, recv_count_.data(), 1, MPI_INT, comm);
  send_disp_ = displacements(send_count_, 1);
  recv_disp_ = displacements(recv_count_, 1);
  // Two PetscInt per entry in the index exchange.
  std::vector<int> sc2(send_count_.size()), rc2(recv_count_.size());
  for (std::size_t s = 0; s < sc2.size(); ++s) {
    sc2[s] = 2 * send_count_[s];
    rc2[s] = 2 * recv_count_[s];
  }
  const std::vector<int> sd2 = displacements(send_count_, 2), rd2 = displacements(recv_count_, 2);
  std::vector<PetscInt> got(static_cast<std::size_t>(rd2.back() + rc2.back()));
  MPI_Alltoallv(pairs.data(), sc2.data(), sd2.data(), MPIU_INT, got.data(), rc2.data(), rd2.data(), MPIU_INT, comm);
  // Where each received (j, i) is stored here (row j - r0, global column i: off-diagonal block),
  // -1 if not stored (it then compares with zero). An own entry whose mirror the other rank does
  // not store is compared there, as that rank receives it.
  PetscInt ncompact = 0;
  petsc_check(MatGetSize(o, nullptr, &ncompact), "MatGetSize");
  recv_pos_.assign(got.size() / 2, -1);
  for (std::size_t k = 0; k < recv_pos_.size(); ++k) {
    const PetscInt row = got[2 * k] - r0, col = got[2 * k + 1];
    const PetscInt* c = std::lower_bound(garray, garray + ncompact, col);
    if (c == garray + ncompact || *c != col) continue;
    const auto compact = static_cast<PetscInt>(c - garray);
    const PetscInt* at = std::lower_bound(jo + io[row], jo + io[row + 1], compact);
    if (at == jo + io[row + 1] || *at != compact) continue;
    recv_pos_[k] = static_cast<PetscInt>(at - jo);
  }
  planned_nonzeros_ = io[n];
  planned_ = a;
}

bool SymmetryProbe::symmetric_distributed(Mat a) {
  // The largest |a_kl| over both blocks of every rank (MatNorm's NORM_MAX is the largest row sum).
  Mat d = nullptr, o = nullptr;
  const PetscInt* garray = nullptr;
  petsc_check(MatMPIAIJGetSeqAIJ(a, &d, &o, &garray), "MatMPIAIJGetSeqAIJ");
  double largest = std::max(largest_entry(d), largest_entry(o));
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(a));
  MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, comm);
  const double tol = kTolerance * largest;
  // The diagonal block through its mirror map; the off-diagonal entries against the mirrors their
  // column's owner sends (the pattern's exchange planned once, then only values travel). Each rank
  // sees only its own pairs, so the answers are joined: every rank chooses the same factorisation.
  bool same = compare(d, tol);
  MatInfo info;
  petsc_check(MatGetInfo(o, MAT_LOCAL, &info), "MatGetInfo");
  // A new plan on every rank or on none (it exchanges messages).
  int replan = a != planned_ || static_cast<PetscInt>(info.nz_used) != planned_nonzeros_ ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &replan, 1, MPI_INT, MPI_LOR, comm);
  if (replan == 1) plan_exchange(a, o, garray);
  const PetscScalar* ov = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(o, &ov), "MatSeqAIJGetArrayRead");
  std::vector<double> out(send_pos_.size()), in(recv_pos_.size());
  for (std::size_t k = 0; k < send_pos_.size(); ++k) out[k] = ov[send_pos_[k]];
  MPI_Alltoallv(out.data(), send_count_.data(), send_disp_.data(), MPI_DOUBLE, in.data(), recv_count_.data(),
                recv_disp_.data(), MPI_DOUBLE, comm);
  for (std::size_t k = 0; k < in.size() && same; ++k) {
    const PetscInt q = recv_pos_[k];
    same = std::abs(in[k] - (q >= 0 ? ov[q] : 0.0)) <= tol;
  }
  petsc_check(MatSeqAIJRestoreArrayRead(o, &ov), "MatSeqAIJRestoreArrayRead");
  int all = same ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, comm);
  return all == 1;
}

bool SymmetryProbe::compare(Mat a, double tol) {
  PetscInt n = 0;
  petsc_check(MatGetSize(a, &n, nullptr), "MatGetSize");
  MatInfo info;
  petsc_check(MatGetInfo(a, MAT_LOCAL, &info), "MatGetInfo");
  if (a != mapped_ || n != rows_ || static_cast<PetscInt>(info.nz_used) != nonzeros_) map(a);
  const PetscScalar* v = nullptr;
  petsc_check(MatSeqAIJGetArrayRead(a, &v), "MatSeqAIJGetArrayRead");
  bool same = true;
  for (PetscInt k = 0; k < nonzeros_ && same; ++k) {
    const PetscInt m = mirror_[static_cast<std::size_t>(k)];
    same = std::abs(v[k] - (m >= 0 ? v[m] : 0.0)) <= tol;
  }
  petsc_check(MatSeqAIJRestoreArrayRead(a, &v), "MatSeqAIJRestoreArrayRead");
  return same;
}

bool SymmetryProbe::symmetric(Mat a) {
  PetscBool seq = PETSC_FALSE;
  petsc_check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(a), MATSEQAIJ, &seq), "PetscObjectTypeCompare");
  if (seq != PETSC_TRUE) return symmetric_distributed(a);
  return compare(a, kTolerance * largest_entry(a));
}

}  // namespace adamss::solver
