#include "continuation/orbits/OrbitMeasures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace keller {

namespace {
std::vector<std::complex<double>> real_and_nontrivial(const std::vector<std::complex<double>>& m, int trivial,
                                                      bool real) {
  std::vector<std::complex<double>> out;
  for (size_t i = 0; i < m.size(); ++i)
    if (static_cast<int>(i) != trivial && (m[i].imag() == 0.0) == real) out.push_back(m[i]);
  return out;
}
}  // namespace

double periodic_range(const std::vector<double>& t, const std::vector<double>& x) {
  const size_t m = x.size() - 1;  // x[m] repeats x[0]
  if (x.size() < 4 || t.size() != x.size()) throw std::invalid_argument("periodic_range: at least 3 samples and times");
  const double T = t[m] - t[0];
  auto extreme = [&](bool largest) {
    size_t k = 0;
    for (size_t i = 1; i < m; ++i)
      if (largest ? x[i] > x[k] : x[i] < x[k]) k = i;
    // neighbours round the period: before k = 0 lies x[m - 1] at t[m - 1] - T
    const size_t before = k == 0 ? m - 1 : k - 1, after = k + 1;
    const double ta = (k == 0 ? t[before] - T : t[before]) - t[k], tb = t[after] - t[k];
    const double xa = x[before] - x[k], xb = x[after] - x[k];
    // the parabola through (ta, xa), (0, 0), (tb, xb): x = c1 s + c2 s^2, its vertex value -c1^2 / (4 c2)
    const double c2 = (xa / ta - xb / tb) / (ta - tb), c1 = xa / ta - c2 * ta;
    if (c2 == 0.0 || (largest ? c2 > 0.0 : c2 < 0.0)) return x[k];
    const double vertex = -c1 / (2.0 * c2);
    if (vertex < ta || vertex > tb) return x[k];
    return x[k] - c1 * c1 / (4.0 * c2);
  };
  return extreme(true) - extreme(false);
}

MultiplierCounts MultiplierCounts::of(const std::vector<std::complex<double>>& m, int trivial) {
  MultiplierCounts c;
  for (size_t i = 0; i < m.size(); ++i) {
    if (static_cast<int>(i) == trivial) continue;
    const double size = std::abs(m[i]);
    if (size > 1.0) ++c.unstable;
    if (m[i].imag() == 0.0) {
      if (m[i].real() > 1.0) ++c.above_plus_one;
      if (m[i].real() < -1.0) ++c.below_minus_one;
    } else if (m[i].imag() > 0.0 && size > 1.0) {
      ++c.pairs_outside;
    }
  }
  return c;
}

double multiplier_test(const std::vector<std::complex<double>>& m, int trivial, PointKind kind) {
  double best = std::numeric_limits<double>::quiet_NaN();
  auto consider = [&](double value) {
    if (std::isnan(best) || std::abs(value) < std::abs(best)) best = value;
  };
  if (kind == PointKind::NeimarkSacker) {
    for (const auto& mu : real_and_nontrivial(m, trivial, false))
      if (mu.imag() > 0.0) consider(std::abs(mu) - 1.0);
    return best;
  }
  const double target = kind == PointKind::PeriodDoubling ? -1.0 : 1.0;
  for (const auto& mu : real_and_nontrivial(m, trivial, true)) consider(mu.real() - target);
  return best;
}

std::optional<double> oscillation_period(const std::vector<double>& t, const std::vector<double>& y) {
  if (t.size() != y.size() || t.size() < 4) return std::nullopt;
  const double half = 0.5 * (t.front() + t.back());
  size_t first = 0;
  while (first < t.size() && t[first] < half) ++first;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t k = first; k < y.size(); ++k) {
    lo = std::min(lo, y[k]);
    hi = std::max(hi, y[k]);
  }
  if (!(hi > lo)) return std::nullopt;
  const double level = 0.5 * (lo + hi);
  std::vector<double> up;
  for (size_t k = std::max<size_t>(first, 1); k < y.size(); ++k)
    if (y[k - 1] < level && y[k] >= level)
      up.push_back(t[k - 1] + (t[k] - t[k - 1]) * (level - y[k - 1]) / (y[k] - y[k - 1]));
  if (up.size() < 3) return std::nullopt;
  const size_t n = std::min<size_t>(up.size() - 1, 5);
  return (up.back() - up[up.size() - 1 - n]) / static_cast<double>(n);
}

}  // namespace keller
