#include "core/Grading.hpp"

#include <cmath>
#include <stdexcept>

namespace keller {

std::vector<double> Grading::vertices(int n) const {
  if (n < 1) throw std::invalid_argument("Grading: need at least one element");
  if (!(ratio >= 1.0)) throw std::invalid_argument("Grading: ratio must be >= 1");
  std::vector<double> h(n, 1.0);
  switch (kind) {
    case Kind::Uniform: break;
    case Kind::Start:
    case Kind::End: {
      const double q = n > 1 ? std::pow(ratio, 1.0 / (n - 1)) : 1.0;
      for (int i = 0; i < n; ++i) h[i] = std::pow(q, kind == Kind::Start ? i : n - 1 - i);
      break;
    }
    case Kind::BothEnds: {
      const int half = (n - 1) / 2;  // steps from an end element to the middle one(s)
      const double q = half > 0 ? std::pow(ratio, 1.0 / half) : 1.0;
      for (int i = 0; i < n; ++i) h[i] = std::pow(q, std::min(i, n - 1 - i));
      break;
    }
  }
  std::vector<double> s(n + 1, 0.0);
  for (int i = 0; i < n; ++i) s[i + 1] = s[i] + h[i];
  for (double& v : s) v /= s[n];
  s[n] = 1.0;
  return s;
}

double grading_ratio_for_smallest(int n, double length, double h_min) {
  if (n < 2) return 1.0;
  if (!(h_min > 0.0) || h_min * n >= length) return 1.0;
  // sizes h_min q^i, i = 0..n-1, sum = length: solve sum(q) = length / h_min for q > 1
  const double target = length / h_min;
  auto sum = [n](double q) { return std::abs(q - 1.0) < 1e-14 ? n : (std::pow(q, n) - 1.0) / (q - 1.0); };
  double lo = 1.0, hi = 2.0;
  while (sum(hi) < target) hi *= 2.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sum(mid) < target ? lo : hi) = mid;
  }
  return std::pow(0.5 * (lo + hi), n - 1);
}

}  // namespace keller
