#include "stability/SpectrumEdge.hpp"

#include <algorithm>

namespace keller {

namespace {
// Distances from the shift that agree to this (relative) are one group at the edge.
constexpr double kEdgeGroup = 1e-6;
}  // namespace

bool spectrum_edge_separated(const std::vector<std::complex<double>>& values, std::complex<double> shift,
                             int computed) {
  if (static_cast<int>(values.size()) < computed) return true;
  double unstable = -1.0, stable = -1.0;  // the farthest of each from the shift
  for (const std::complex<double>& v : values) {
    const double d = std::abs(v - shift);
    if (v.real() < 0)
      unstable = std::max(unstable, d);
    else
      stable = std::max(stable, d);
  }
  if (unstable < 0) return true;
  return stable > unstable * (1.0 + kEdgeGroup);
}

int count_to_separate(const std::vector<std::complex<double>>& values, std::complex<double> shift, int computed,
                      int cap) {
  if (computed >= cap || spectrum_edge_separated(values, shift, computed)) return computed;
  return std::min(cap, 2 * computed);
}

}  // namespace keller
