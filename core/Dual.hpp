// Forward-mode dual numbers with a fixed-size derivative vector, and the small set of scalar
// helpers (value_of, seeding) that element kernels use so that one templated kernel serves
// double evaluation, exact Jacobians (Dual<N>) and parameter derivatives (Dual<1>).
//
// Why not Eigen::AutoDiffScalar: runs/bench/bench_dual.cpp times both on the Navier-Stokes
// element kernel; the hand-written type is kept only because that benchmark shows it at least
// 2x faster (see README.md, "Automatic differentiation").
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <type_traits>

namespace keller {

template <int N>
struct Dual {
  using Deriv = Eigen::Array<double, N, 1>;
  double v = 0.0;
  Deriv d = Deriv::Zero();

  Dual() = default;
  Dual(double value) : v(value), d(Deriv::Zero()) {}  // NOLINT: implicit constant promotion
  Dual(double value, const Deriv& deriv) : v(value), d(deriv) {}

  Dual& operator+=(const Dual& o) { v += o.v; d += o.d; return *this; }
  Dual& operator-=(const Dual& o) { v -= o.v; d -= o.d; return *this; }
  Dual& operator*=(const Dual& o) { d = d * o.v + o.d * v; v *= o.v; return *this; }
  Dual& operator/=(const Dual& o) { *this = *this / o; return *this; }
  Dual& operator+=(double o) { v += o; return *this; }
  Dual& operator-=(double o) { v -= o; return *this; }
  Dual& operator*=(double o) { v *= o; d *= o; return *this; }
  Dual& operator/=(double o) { v /= o; d /= o; return *this; }

  friend Dual operator-(const Dual& a) { return Dual(-a.v, -a.d); }
  friend Dual operator+(const Dual& a) { return a; }
  friend Dual operator+(const Dual& a, const Dual& b) { return Dual(a.v + b.v, a.d + b.d); }
  friend Dual operator-(const Dual& a, const Dual& b) { return Dual(a.v - b.v, a.d - b.d); }
  friend Dual operator*(const Dual& a, const Dual& b) { return Dual(a.v * b.v, a.d * b.v + b.d * a.v); }
  friend Dual operator/(const Dual& a, const Dual& b) {
    const double inv = 1.0 / b.v;
    const double q = a.v * inv;
    return Dual(q, (a.d - b.d * q) * inv);
  }
  friend Dual operator+(const Dual& a, double b) { return Dual(a.v + b, a.d); }
  friend Dual operator+(double a, const Dual& b) { return Dual(a + b.v, b.d); }
  friend Dual operator-(const Dual& a, double b) { return Dual(a.v - b, a.d); }
  friend Dual operator-(double a, const Dual& b) { return Dual(a - b.v, -b.d); }
  friend Dual operator*(const Dual& a, double b) { return Dual(a.v * b, a.d * b); }
  friend Dual operator*(double a, const Dual& b) { return Dual(a * b.v, b.d * a); }
  friend Dual operator/(const Dual& a, double b) { return Dual(a.v / b, a.d / b); }
  friend Dual operator/(double a, const Dual& b) {
    const double q = a / b.v;
    return Dual(q, b.d * (-q / b.v));
  }

  friend bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend bool operator<(const Dual& a, double b) { return a.v < b; }
  friend bool operator>(const Dual& a, double b) { return a.v > b; }
  friend bool operator<=(const Dual& a, double b) { return a.v <= b; }
  friend bool operator>=(const Dual& a, double b) { return a.v >= b; }
  friend bool operator<(double a, const Dual& b) { return a < b.v; }
  friend bool operator>(double a, const Dual& b) { return a > b.v; }

  // Chain rule helper: f(a) with f' = df.
  static Dual chain(const Dual& a, double f, double df) { return Dual(f, a.d * df); }

  friend Dual exp(const Dual& a) { const double e = std::exp(a.v); return chain(a, e, e); }
  friend Dual log(const Dual& a) { return chain(a, std::log(a.v), 1.0 / a.v); }
  friend Dual sqrt(const Dual& a) {
    const double s = std::sqrt(a.v);
    return chain(a, s, 0.5 / s);
  }
  friend Dual sin(const Dual& a) { return chain(a, std::sin(a.v), std::cos(a.v)); }
  friend Dual cos(const Dual& a) { return chain(a, std::cos(a.v), -std::sin(a.v)); }
  friend Dual tanh(const Dual& a) {
    const double t = std::tanh(a.v);
    return chain(a, t, 1.0 - t * t);
  }
  friend Dual abs(const Dual& a) { return a.v < 0 ? -a : a; }
  friend Dual pow(const Dual& a, double p) {
    const double f = std::pow(a.v, p);
    return chain(a, f, p * std::pow(a.v, p - 1.0));
  }
  friend Dual pow(const Dual& a, const Dual& b) {
    // a^b = exp(b log a); requires a > 0
    const double f = std::pow(a.v, b.v);
    return Dual(f, a.d * (b.v * std::pow(a.v, b.v - 1.0)) + b.d * (f * std::log(a.v)));
  }
  friend bool isfinite(const Dual& a) { return std::isfinite(a.v) && a.d.allFinite(); }
};

// ---- scalar helpers usable on double and Dual<N> alike ----

inline double value_of(double x) { return x; }
template <int N>
double value_of(const Dual<N>& x) { return x.v; }

inline bool is_finite(double x) { return std::isfinite(x); }
template <int N>
bool is_finite(const Dual<N>& x) { return std::isfinite(x.v) && x.d.allFinite(); }

template <class T>
struct ScalarTraits {
  static constexpr int derivatives = 0;
};
template <int N>
struct ScalarTraits<Dual<N>> {
  static constexpr int derivatives = N;
};

// A dual variable with value v and unit derivative in direction i.
template <int N>
Dual<N> make_variable(double v, int i) {
  Dual<N> x(v);
  x.d[i] = 1.0;
  return x;
}

}  // namespace keller
