// Hyper-dual numbers for second and third directional derivatives of element kernels (normal
// forms, core/ExactDerivatives.hpp): x = x0 + sum_i x_i e_i + sum_{i<j} x_ij e_i e_j + ... with
// K nilpotent units (e_i^2 = 0), the algebra of K nested dual numbers. A kernel evaluated at
// u + e_1 a + e_2 b (+ e_3 c) returns D^2 f[a, b] (D^3 f[a, b, c]) as the coefficient of e_1 e_2
// (e_1 e_2 e_3): exact, with no step to choose. Eigen's AutoDiffScalar nests poorly (its nested
// scalar does not mix with double), so this is a small type of its own, with the operations and
// functions the kernels use.
#pragma once

#include <array>
#include <cmath>

namespace keller {

template <int K>
class HyperDual {
 public:
  static constexpr int kTerms = 1 << K;  // coefficients, indexed by the set of units (bit mask)
  std::array<double, kTerms> c{};

  HyperDual() = default;
  HyperDual(double v) { c[0] = v; }  // NOLINT: implicit, like a double in kernel code

  double value() const { return c[0]; }

  HyperDual& operator+=(const HyperDual& o) {
    for (int m = 0; m < kTerms; ++m) c[m] += o.c[m];
    return *this;
  }
  HyperDual& operator-=(const HyperDual& o) {
    for (int m = 0; m < kTerms; ++m) c[m] -= o.c[m];
    return *this;
  }
  HyperDual& operator*=(const HyperDual& o) { return *this = *this * o; }
  HyperDual& operator/=(const HyperDual& o) { return *this = *this / o; }

  friend HyperDual operator+(HyperDual a, const HyperDual& b) { return a += b; }
  friend HyperDual operator-(HyperDual a, const HyperDual& b) { return a -= b; }
  friend HyperDual operator-(HyperDual a) {
    for (double& x : a.c) x = -x;
    return a;
  }
  friend HyperDual operator+(const HyperDual& a) { return a; }
  friend HyperDual operator*(const HyperDual& a, const HyperDual& b) {
    HyperDual r;
    for (int s = 0; s < kTerms; ++s) {
      double sum = 0.0;
      // every split of the set s into a subset and its complement
      for (int sub = s;; sub = (sub - 1) & s) {
        sum += a.c[sub] * b.c[s ^ sub];
        if (sub == 0) break;
      }
      r.c[s] = sum;
    }
    return r;
  }
  friend HyperDual operator*(HyperDual a, double b) {
    for (double& x : a.c) x *= b;
    return a;
  }
  friend HyperDual operator*(double b, HyperDual a) { return a * b; }
  friend HyperDual operator/(const HyperDual& a, const HyperDual& b) { return a * reciprocal(b); }
  friend HyperDual operator/(HyperDual a, double b) { return a * (1.0 / b); }
  friend HyperDual operator/(double a, const HyperDual& b) { return a * reciprocal(b); }

  friend bool operator<(const HyperDual& a, const HyperDual& b) { return a.c[0] < b.c[0]; }
  friend bool operator>(const HyperDual& a, const HyperDual& b) { return a.c[0] > b.c[0]; }
  friend bool operator<=(const HyperDual& a, const HyperDual& b) { return a.c[0] <= b.c[0]; }
  friend bool operator>=(const HyperDual& a, const HyperDual& b) { return a.c[0] >= b.c[0]; }
  friend bool operator==(const HyperDual& a, const HyperDual& b) { return a.c[0] == b.c[0]; }
  friend bool operator!=(const HyperDual& a, const HyperDual& b) { return a.c[0] != b.c[0]; }

  // f(x) from f and its first K derivatives at the value, d[k] = f^(k)(x0): the Taylor series in
  // the nilpotent part n = x - x0 ends at n^K.
  friend HyperDual taylor(const HyperDual& x, const std::array<double, K + 1>& d) {
    HyperDual n = x;
    n.c[0] = 0.0;
    HyperDual r(d[0]), power(1.0);
    double factorial = 1.0;
    for (int k = 1; k <= K; ++k) {
      power = power * n;
      factorial *= k;
      r += power * (d[k] / factorial);
    }
    return r;
  }
  friend HyperDual reciprocal(const HyperDual& x) {
    const double v = 1.0 / x.c[0];
    std::array<double, K + 1> d{};
    double t = v;
    for (int k = 0; k <= K; ++k) {  // (1/x)^(k) = (-1)^k k! / x^(k+1)
      d[k] = t;
      t *= -(k + 1) * v;
    }
    return taylor(x, d);
  }
  friend HyperDual exp(const HyperDual& x) {
    std::array<double, K + 1> d;
    d.fill(std::exp(x.c[0]));
    return taylor(x, d);
  }
  friend HyperDual log(const HyperDual& x) {
    std::array<double, K + 1> d{};
    d[0] = std::log(x.c[0]);
    double t = 1.0 / x.c[0];
    for (int k = 1; k <= K; ++k) {  // log^(k) = (-1)^(k-1) (k-1)! / x^k
      d[k] = t;
      t *= -k / x.c[0];
    }
    return taylor(x, d);
  }
  friend HyperDual pow(const HyperDual& x, double a) {
    std::array<double, K + 1> d{};
    double coefficient = 1.0;
    for (int k = 0; k <= K; ++k) {  // a (a-1) ... (a-k+1) x^(a-k)
      d[k] = coefficient * std::pow(x.c[0], a - k);
      coefficient *= a - k;
    }
    return taylor(x, d);
  }
  friend HyperDual sqrt(const HyperDual& x) { return pow(x, 0.5); }
  friend HyperDual cosh(const HyperDual& x) {
    std::array<double, K + 1> d{};
    for (int k = 0; k <= K; ++k) d[k] = k % 2 == 0 ? std::cosh(x.c[0]) : std::sinh(x.c[0]);
    return taylor(x, d);
  }
  friend HyperDual sinh(const HyperDual& x) {
    std::array<double, K + 1> d{};
    for (int k = 0; k <= K; ++k) d[k] = k % 2 == 0 ? std::sinh(x.c[0]) : std::cosh(x.c[0]);
    return taylor(x, d);
  }
  friend HyperDual tanh(const HyperDual& x) {
    const double t = std::tanh(x.c[0]), s = 1.0 - t * t;
    const std::array<double, 4> all{t, s, -2.0 * t * s, s * (6.0 * t * t - 2.0)};
    std::array<double, K + 1> d{};
    for (int k = 0; k <= K; ++k) d[k] = all[k];
    return taylor(x, d);
  }
  friend HyperDual sin(const HyperDual& x) {
    const double s = std::sin(x.c[0]), co = std::cos(x.c[0]);
    const std::array<double, 4> all{s, co, -s, -co};
    std::array<double, K + 1> d{};
    for (int k = 0; k <= K; ++k) d[k] = all[k];
    return taylor(x, d);
  }
  friend HyperDual cos(const HyperDual& x) {
    const double s = std::sin(x.c[0]), co = std::cos(x.c[0]);
    const std::array<double, 4> all{co, -s, -co, s};
    std::array<double, K + 1> d{};
    for (int k = 0; k <= K; ++k) d[k] = all[k];
    return taylor(x, d);
  }
  friend HyperDual abs(const HyperDual& x) { return x.c[0] < 0.0 ? -x : x; }
  friend double value_of(const HyperDual& x) { return x.c[0]; }
  friend bool is_finite(const HyperDual& x) {
    for (double v : x.c)
      if (!std::isfinite(v)) return false;
    return true;
  }
};

// x0 + e_1 a + e_2 b (+ e_3 c): a variable seeded along K directions
template <int K>
HyperDual<K> seeded(double x0, const std::array<double, K>& along) {
  HyperDual<K> x(x0);
  for (int i = 0; i < K; ++i) x.c[1 << i] = along[static_cast<size_t>(i)];
  return x;
}
// The coefficient of e_1 ... e_K: D^K f[d_1, ..., d_K]
template <int K>
double mixed_part(const HyperDual<K>& x) {
  return x.c[(1 << K) - 1];
}

}  // namespace keller
