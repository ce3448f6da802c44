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

std::vector<size_t> values_to_merge(const std::vector<std::complex<double>>& merged,
                                    const std::vector<std::complex<double>>& found) {
  auto same = [](std::complex<double> a, std::complex<double> b) {
    return std::abs(a - b) <= 1e-8 * (1.0 + std::abs(b));
  };
  std::vector<size_t> out;
  for (size_t i = 0; i < found.size(); ++i) {
    // the i-th copy of this value in found is new where merged holds fewer than i + 1 copies
    const auto copies_found = std::count_if(found.begin(), found.begin() + static_cast<long>(i) + 1,
                                            [&](std::complex<double> v) { return same(v, found[i]); });
    const auto copies_held =
        std::count_if(merged.begin(), merged.end(), [&](std::complex<double> v) { return same(v, found[i]); });
    if (copies_found > copies_held) out.push_back(i);
  }
  return out;
}

bool unstable_mode_lost(const std::vector<Eigen::VectorXcd>& previous, const std::vector<Eigen::VectorXcd>& now) {
  for (const Eigen::VectorXcd& v : previous) {
    const double vv = v.squaredNorm();
    if (!(vv > 0)) continue;
    double share = 0.0;
    for (const Eigen::VectorXcd& w : now)
      if (w.size() == v.size() && w.squaredNorm() > 0) share += std::norm(v.dot(w)) / (vv * w.squaredNorm());
    if (share < 0.5) return true;
  }
  return false;
}

bool needs_moved_shift(bool ok, bool inaccurate, bool singular, int found, int asked) {
  return singular || (!ok && inaccurate) || (ok && found < asked);
}

double shift_move(const std::vector<std::complex<double>>& values, std::complex<double> shift, double last_spread) {
  double spread = 0.0;
  for (std::complex<double> v : values) spread = std::max(spread, std::abs(v - shift));
  spread = std::max(spread, last_spread);
  return spread > 0 ? 0.25 * spread : 1.0;
}

}  // namespace keller
