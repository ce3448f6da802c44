#include "core/HigherDerivatives.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "core/ExactDerivatives.hpp"

namespace keller {

namespace {

// of the state and the parameter, for second and third derivatives (the header says the accuracy)
constexpr double kRelativeStep[2] = {1e-3, 1e-2};
// of the time terms' dependence on the state (B(u) udot, linear in udot: first and mixed second
// differences in u alone, where the optimal steps are eps^(1/3) and eps^(1/4))
constexpr double kRateStep[2] = {1e-5, 1e-4};

bool is_zero(const HigherDerivatives::Direction& d) {
  return d.lambda == 0.0 && (d.u.size() == 0 || d.u.isZero(0.0)) && (d.rate.size() == 0 || d.rate.isZero(0.0));
}
bool has_rate(const HigherDerivatives::Direction& d) { return d.rate.size() > 0 && !d.rate.isZero(0.0); }
bool moves_state(const HigherDerivatives::Direction& d) {
  return d.lambda != 0.0 || (d.u.size() > 0 && !d.u.isZero(0.0));
}

// the real (part 0) or imaginary (part 1) part of a complex direction
HigherDerivatives::Direction part(const HigherDerivatives::ComplexDirection& d, int which) {
  HigherDerivatives::Direction r;
  if (d.u.size() > 0) r.u = which == 0 ? Vector(d.u.real()) : Vector(d.u.imag());
  r.lambda = which == 0 ? d.lambda.real() : d.lambda.imag();
  if (d.rate.size() > 0) r.rate = which == 0 ? Vector(d.rate.real()) : Vector(d.rate.imag());
  return r;
}

}  // namespace

HigherDerivatives::HigherDerivatives(Problem& problem, int parameter, Vector u0, bool force_differences)
    : problem_(problem), parameter_(parameter), u0_(std::move(u0)) {
  if (parameter < 0 || parameter >= problem.parameters().size())
    throw std::invalid_argument("HigherDerivatives: no parameter with that index");
  if (u0_.size() != problem.size()) throw std::invalid_argument("HigherDerivatives: the state has the wrong size");
  lambda0_ = problem.parameters().value(parameter);
  exact_ = dynamic_cast<ExactDerivatives*>(&problem);
  if (exact_ && (force_differences || !exact_->offers_exact_derivatives())) exact_ = nullptr;
  method_ = exact_ ? Method::Exact : Method::Differences;
  has_time_form_ = has_time_form(problem, u0_);
}

std::string HigherDerivatives::method_name() const {
  return method_ == Method::Exact ? "exact (hyper-dual numbers)" : "central differences of the residual";
}

double HigherDerivatives::step(const Direction& d, int order, bool rate) const {
  const double su = std::max(1.0, u0_.lpNorm<Eigen::Infinity>());
  const double sl = lambda0_ != 0.0 ? std::abs(lambda0_) : 1.0;
  double size = std::abs(d.lambda) / sl;
  if (d.u.size() > 0) size = std::max(size, d.u.lpNorm<Eigen::Infinity>() / su);
  return size > 0.0 ? (rate ? kRateStep : kRelativeStep)[order == 2 ? 0 : 1] / size : 0.0;
}

Status HigherDerivatives::shifted(const Direction* const* d, const double* s, int order, const Vector* rate,
                                  Vector& out) {
  Vector u = u0_;
  double lambda = lambda0_;
  for (int i = 0; i < order; ++i) {
    if (s[i] == 0.0) continue;
    if (d[i]->u.size() > 0) u += s[i] * d[i]->u;
    lambda += s[i] * d[i]->lambda;
  }
  ParameterSet& params = problem_.parameters();
  Status st;
  try {
    params.set(parameter_, lambda);
    ++evaluations_;
    st = rate ? problem_.time_residual(u, *rate, out) : problem_.residual(u, out);
  } catch (const std::out_of_range& e) {
    st = Status(StatusCode::InvalidState, fmt::format("a difference step leaves the parameter's range: {}", e.what()));
  }
  params.set(parameter_, lambda0_);
  return st;
}

Status HigherDerivatives::f_differences(const Direction* const* d, int order, Vector& out) {
  std::array<double, 3> t{};
  double scale = 1.0;
  for (int i = 0; i < order; ++i) {
    t[static_cast<size_t>(i)] = step(*d[i], order, false);
    if (t[static_cast<size_t>(i)] == 0.0) {  // along the rates alone: F does not change
      out.setZero(problem_.size());
      return {};
    }
    scale *= 2.0 * t[static_cast<size_t>(i)];
  }
  out.setZero(problem_.size());
  Vector r;
  for (int signs = 0; signs < (1 << order); ++signs) {
    std::array<double, 3> s{};
    double sign = 1.0;
    for (int i = 0; i < order; ++i) {
      const bool minus = (signs >> i) & 1;
      s[static_cast<size_t>(i)] = minus ? -t[static_cast<size_t>(i)] : t[static_cast<size_t>(i)];
      if (minus) sign = -sign;
    }
    Status st = shifted(d, s.data(), order, nullptr, r);
    if (!st.is_ok()) return st;
    out += sign * r;
  }
  out /= scale;
  return {};
}

Status HigherDerivatives::f_part(const Direction* const* d, int order, Vector& out) {
  if (!exact_) return f_differences(d, order, out);
  std::vector<Vector> parameter_changes(static_cast<size_t>(order));
  std::vector<ExactDerivatives::Direction> dirs(static_cast<size_t>(order));
  for (int i = 0; i < order; ++i) {
    auto& dir = dirs[static_cast<size_t>(i)];
    if (d[i]->u.size() > 0) dir.u = &d[i]->u;
    if (d[i]->lambda != 0.0) {
      Vector& p = parameter_changes[static_cast<size_t>(i)];
      p.setZero(problem_.parameters().size());
      p[parameter_] = d[i]->lambda;
      dir.parameters = &p;
    }
  }
  ++evaluations_;
  return exact_->directional_derivative(u0_, dirs, out);
}

// D^(order-1)_u (B(u) rate)[others]: central differences of time_residual; zero where one of the
// others does not move the state.
Status HigherDerivatives::rate_term(const Vector& rate, const Direction* const* others, int order, Vector& out) {
  const int n = order - 1;
  out.setZero(problem_.size());
  std::array<double, 2> t{};
  double scale = 1.0;
  for (int i = 0; i < n; ++i) {
    if (!moves_state(*others[i])) return {};
    t[static_cast<size_t>(i)] = step(*others[i], order, true);
    scale *= 2.0 * t[static_cast<size_t>(i)];
  }
  Vector r;
  for (int signs = 0; signs < (1 << n); ++signs) {
    std::array<double, 2> s{};
    double sign = 1.0;
    for (int i = 0; i < n; ++i) {
      const bool minus = (signs >> i) & 1;
      s[static_cast<size_t>(i)] = minus ? -t[static_cast<size_t>(i)] : t[static_cast<size_t>(i)];
      if (minus) sign = -sign;
    }
    Status st = shifted(others, s.data(), n, &rate, r);
    if (!st.is_ok()) return st;
    out += (sign / scale) * r;
  }
  return {};
}

// Every derivative, real or complex, is evaluated once per multiset of distinct real directions
// (equal up to sign) and kept for the later derivatives of this object. Complex ones are
// multilinear: the sum over choosing the real or the imaginary part of each, times i^(number of
// imaginary parts); q and conj q share their parts: D^3 R[Q, Q,
// conj Q] takes 4 real derivatives instead of 8, and D^2 R[Q, Q] none after D^2 R[Q, conj Q]. So
// are the time terms' parts D^k (B(u) r)[...], which several multisets share.
namespace {

bool same(const Vector& a, const Vector& b, double sign) {
  if (a.size() != b.size()) return a.size() == 0 ? b.isZero(0.0) : (b.size() == 0 && a.isZero(0.0));
  return a.size() == 0 || (a - sign * b).isZero(0.0);
}

// Distinct real directions up to sign: the index of d among them (added if new) and its sign.
int distinct_index(std::vector<HigherDerivatives::Direction>& distinct, const HigherDerivatives::Direction& d,
                   double& sign) {
  for (size_t k = 0; k < distinct.size(); ++k)
    for (double s : {1.0, -1.0})
      if (d.lambda == s * distinct[k].lambda && same(d.u, distinct[k].u, s) && same(d.rate, distinct[k].rate, s)) {
        sign = s;
        return static_cast<int>(k);
      }
  distinct.push_back(d);
  sign = 1.0;
  return static_cast<int>(distinct.size()) - 1;
}

}  // namespace

// A real derivative: its directions among the distinct ones (up to sign), from the caches.
Status HigherDerivatives::real(const std::vector<const Direction*>& dirs, Vector& out) {
  std::vector<int> ids;
  double sign = 1.0;
  for (const Direction* d : dirs) {
    if (is_zero(*d)) {
      out.setZero(problem_.size());
      return {};
    }
    double s = 1.0;
    ids.push_back(distinct_index(distinct_, *d, s));
    sign *= s;
  }
  std::sort(ids.begin(), ids.end());
  Status st = cached(ids, out);
  if (sign < 0) out = -out;
  return st;
}

Status HigherDerivatives::second(const Direction& a, const Direction& b, Vector& out) { return real({&a, &b}, out); }

Status HigherDerivatives::third(const Direction& a, const Direction& b, const Direction& c, Vector& out) {
  return real({&a, &b, &c}, out);
}

Status HigherDerivatives::expand(const std::vector<const ComplexDirection*>& dirs, ComplexVector& out) {
  const int order = static_cast<int>(dirs.size());
  std::vector<std::array<Direction, 2>> parts;
  for (const ComplexDirection* d : dirs) parts.push_back({part(*d, 0), part(*d, 1)});
  out.setZero(problem_.size());
  const std::complex<double> unit[4] = {1.0, {0.0, 1.0}, -1.0, {0.0, -1.0}};
  Vector r;
  for (int choice = 0; choice < (1 << order); ++choice) {
    std::vector<const Direction*> chosen;
    int imaginary = 0;
    for (int i = 0; i < order; ++i) {
      const int which = (choice >> i) & 1;
      chosen.push_back(&parts[static_cast<size_t>(i)][static_cast<size_t>(which)]);
      imaginary += which;
    }
    if (Status st = real(chosen, r); !st.is_ok()) return st;
    out += unit[imaginary] * r.cast<std::complex<double>>();
  }
  return {};
}

Status HigherDerivatives::cached(const std::vector<int>& ids, Vector& out) {
  const int order = static_cast<int>(ids.size());
  std::array<const Direction*, 3> d{};
  for (int i = 0; i < order; ++i)
    d[static_cast<size_t>(i)] = &distinct_[static_cast<size_t>(ids[static_cast<size_t>(i)])];
  auto f = f_cache_.find(ids);
  if (f == f_cache_.end()) {
    Vector v;
    if (Status st = timed([&] { return f_part(d.data(), order, v); }); !st.is_ok()) return st;
    f = f_cache_.emplace(ids, std::move(v)).first;
  }
  out = f->second;
  if (!has_time_form_) return {};
  for (int k = 0; k < order; ++k) {
    if (!has_rate(*d[static_cast<size_t>(k)])) continue;
    // key: the direction whose rate, then the others (sorted, as ids are)
    std::vector<int> key{ids[static_cast<size_t>(k)]};
    std::array<const Direction*, 2> others{};
    for (int i = 0; i < order; ++i)
      if (i != k) {
        others[key.size() - 1] = d[static_cast<size_t>(i)];
        key.push_back(ids[static_cast<size_t>(i)]);
      }
    auto t = rate_cache_.find(key);
    if (t == rate_cache_.end()) {
      Vector v;
      const Vector& rate = d[static_cast<size_t>(k)]->rate;
      if (Status st = timed([&] { return rate_term(rate, others.data(), order, v); }); !st.is_ok()) return st;
      t = rate_cache_.emplace(std::move(key), std::move(v)).first;
    }
    out += t->second;
  }
  return {};
}

Status HigherDerivatives::second(const ComplexDirection& a, const ComplexDirection& b, ComplexVector& out) {
  return expand({&a, &b}, out);
}

Status HigherDerivatives::third(const ComplexDirection& a, const ComplexDirection& b, const ComplexDirection& c,
                                ComplexVector& out) {
  return expand({&a, &b, &c}, out);
}

}  // namespace keller
