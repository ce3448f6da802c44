#include "core/FillOrdering.hpp"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <functional>
#include <limits>
#include <stdexcept>

#ifdef KELLER_METIS
#include <metis.h>
#endif

namespace keller {

bool nested_dissection_available() {
#ifdef KELLER_METIS
  return true;
#else
  return false;
#endif
}

std::vector<int> nested_dissection_order(int n, const int* outer, const int* inner) {
#ifdef KELLER_METIS
  static_assert(sizeof(idx_t) == sizeof(int), "Debian's METIS has 32-bit indices");
  if (n <= 0) return {};
  // The graph of A + A^T without self-loops, each neighbour once (METIS's contract), in O(nnz):
  // the rows of A's pattern by a counting transpose (sorted, as the columns are walked in
  // order), then each vertex's column and row lists merged. No sort: on W3 (12M entries)
  // sorting the doubled lists took longer than METIS itself.
  const size_t N = static_cast<size_t>(n);
  // the merge needs each column's rows strictly increasing, as Eigen's compressed matrices have
  // them and UMFPACK requires of every matrix keller factorises
  for (int j = 0; j < n; ++j)
    if (std::adjacent_find(inner + outer[j], inner + outer[j + 1], std::greater_equal<int>{}) != inner + outer[j + 1])
      throw std::invalid_argument("nested_dissection_order: the rows of a column are not strictly increasing");
  std::vector<int> row_start(N + 1, 0), row_cols(static_cast<size_t>(outer[n]));
  for (int k = 0; k < outer[n]; ++k) ++row_start[static_cast<size_t>(inner[k]) + 1];
  for (size_t i = 0; i < N; ++i) row_start[i + 1] += row_start[i];
  {
    std::vector<int> next(row_start.begin(), row_start.end() - 1);
    for (int j = 0; j < n; ++j)
      for (int k = outer[j]; k < outer[j + 1]; ++k)
        row_cols[static_cast<size_t>(next[static_cast<size_t>(inner[k])]++)] = j;
  }
  std::vector<idx_t> xadj(N + 1, 0), adjncy;
  adjncy.reserve(static_cast<size_t>(outer[n]) + static_cast<size_t>(outer[n]) / 8);
  for (int v = 0; v < n; ++v) {
    const int* c = inner + outer[v];
    const int* c_end = inner + outer[v + 1];
    const int* r = row_cols.data() + row_start[static_cast<size_t>(v)];
    const int* r_end = row_cols.data() + row_start[static_cast<size_t>(v) + 1];
    while (c != c_end || r != r_end) {
      int w;
      if (r == r_end || (c != c_end && *c < *r))
        w = *c++;
      else if (c == c_end || *r < *c)
        w = *r++;
      else {
        w = *c++;
        ++r;
      }
      if (w != v) adjncy.push_back(w);
    }
    if (adjncy.size() > static_cast<size_t>(std::numeric_limits<idx_t>::max()))
      throw std::runtime_error("the graph of A + A^T has more edges than METIS's 32-bit indices hold");
    xadj[static_cast<size_t>(v) + 1] = static_cast<idx_t>(adjncy.size());
  }
  row_cols = {};
  // METIS fails on a graph without edges (CHOLMOD avoids it too); any order is as good there
  if (adjncy.empty()) {
    std::vector<int> identity(N);
    for (int i = 0; i < n; ++i) identity[static_cast<size_t>(i)] = i;
    return identity;
  }
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  idx_t vertices = n;
  std::vector<idx_t> perm(N), iperm(N);
  // METIS traps SIGTERM (and SIGABRT) for the length of the call to unwind its own errors, and a
  // SIGTERM that arrives then comes back as METIS_ERROR: it is raised again once METIS has put the
  // process's handlers back, so that an interrupt of the run (runs/Interrupts) is not lost. (A
  // signal delivered to another thread of the process inside that window reaches METIS's handler
  // there; keller's factorisations run on one thread unless OpenBLAS has more.)
  const int rc = METIS_NodeND(&vertices, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data());
  if (rc == METIS_ERROR) std::raise(SIGTERM);
  if (rc != METIS_OK)
    throw std::runtime_error(rc == METIS_ERROR_MEMORY ? "METIS's nested dissection ran out of memory"
                                                      : "METIS's nested dissection failed or was interrupted");
  // METIS: row i of the permuted matrix is row perm[i] of A, so iperm[i] is i's pivot position
  return std::vector<int>(iperm.begin(), iperm.end());
#else
  (void)n;
  (void)outer;
  (void)inner;
  return {};
#endif
}

int fewest_flops(const std::vector<OrderingTrial>& trials) {
  int best = -1;
  for (int k = 0; k < static_cast<int>(trials.size()); ++k) {
    const double f = trials[static_cast<size_t>(k)].flops;
    if (std::isnan(f)) continue;
    if (best < 0 || f < trials[static_cast<size_t>(best)].flops) best = k;
  }
  return best;
}

}  // namespace keller
