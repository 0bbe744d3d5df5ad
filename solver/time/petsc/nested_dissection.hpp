#pragma once
// A fill-reducing pivot order for a sparse factorisation from METIS's nested dissection
// (METIS_NodeND: multilevel vertex separators, George 1973; Karypis and Kumar 1998).
//
// Debian's MUMPS is built without METIS and SCOTCH, so its own choice is PORD (or AMF on small
// operators). Handed as MUMPS's given pivot order (ICNTL(7) = 1, PERM_IN), METIS's order is
// computed once per analysis, on the graph of the operator's stored entries.
#include <vector>

namespace adamss::solver {

/// The pivot order of nested dissection on the symmetric graph of an n x n sparse pattern given
/// in coordinates (1-based rows `irn` and columns `jcn`; one triangle or both, duplicates and the
/// diagonal allowed). Returns MUMPS's PERM_IN: entry i (0-based variable i) is the 1-based
/// position of variable i in the pivot order. Throws std::runtime_error when METIS fails (out of
/// memory) or the graph has more adjacencies than METIS's 32-bit indices hold (Debian's build).
std::vector<int> nested_dissection_order(int n, const std::vector<int>& irn, const std::vector<int>& jcn);

}  // namespace adamss::solver
