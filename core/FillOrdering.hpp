// Fill-reducing orderings keller computes itself for a sparse direct solver, and how `best`
// chooses among candidate orderings. METIS's nested dissection (METIS_NodeND, Debian's
// libmetis-dev) of the pattern of A + A^T is handed to MUMPS as a given ordering (ICNTL(7) = 1):
// Debian's sequential MUMPS is built without METIS and would otherwise fall back to SCOTCH.
// Built with METIS where CMake found it (KELLER_METIS); without it nested_dissection_order
// returns an empty order.
#pragma once

#include <string>
#include <vector>

namespace keller {

// Whether this build has METIS.
bool nested_dissection_available();

// METIS's nested-dissection ordering of the n x n pattern given in compressed columns (0-based
// `outer`, n + 1 column starts, and `inner`, the row of each entry, strictly increasing within a
// column; the diagonal and the values play no part): position[i] is the place of variable i in
// the pivot order, 0-based. Empty where METIS is missing. Throws std::invalid_argument for rows
// out of order or repeated, std::runtime_error where METIS fails (out of memory, interrupted).
std::vector<int> nested_dissection_order(int n, const int* outer, const int* inner);

// One candidate ordering a symbolic analysis tried: its name and the factorisation's estimated
// floating-point operations (NaN where its analysis failed).
struct OrderingTrial {
  std::string name;
  double flops = 0;
};

// The candidate `best` keeps: the fewest estimated flops (flops, not fill, set the factorisation's
// time on the flow matrices), the earlier one on a tie; -1 where every analysis failed.
int fewest_flops(const std::vector<OrderingTrial>& trials);

}  // namespace keller
