// Second and third directional derivatives of the time-dependent residual of a problem,
//   R(u, lambda, udot) = F(u, lambda) + B(u, lambda) udot,
// at a steady state u0 (udot = 0), in directions of the unknowns, of one parameter lambda and of
// the rates: the derivatives normal forms take (stability/NormalForms.hpp). The rates enter
// because B may depend on u (a moving mesh): D^2 R[(x, xdot), (y, ydot)] = D^2 F[x, y] +
// B'[x] ydot + B'[y] xdot.
//
// F's part is exact where the problem offers ExactDerivatives (an assembled problem: hyper-dual
// numbers through its kernels), else central differences of F: D^2 from 4 residuals, D^3 from 8,
// with each direction scaled to a step h relative to the state (and to lambda), h = 1e-3 for D^2
// and 1e-2 for D^3. The truncation error is O(h^2) relative to F's fourth and fifth derivatives
// (zero for polynomial F); the rounding error is eps S / h^2 (D^2) and eps S / h^3 (D^3), with S
// the size of the terms a residual sums (not of F, which cancels them): in the collapsible
// channel's residual it swamps D^3 below a relative step of 1e-2 (tests/unit/NormalFormsTest.cpp
// measures both regimes), which is why a problem of that kind should offer exact derivatives.
// The part of B's dependence is always central differences of time_residual (linear in
// the rates, so exact in them) at relative steps 1e-5 (first differences) and 1e-4 (mixed second
// differences), and is skipped where no direction has rates. Each derivative is evaluated once per
// object: the parts along the same directions (equal up to sign) are kept and reused.
#pragma once

#include <chrono>

#include <complex>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/Problem.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class ExactDerivatives;

class HigherDerivatives {
 public:
  using ComplexVector = Eigen::VectorXcd;
  // A direction: a change of the unknowns, of the parameter and of the rates (empty: zero).
  struct Direction {
    Vector u;
    double lambda = 0.0;
    Vector rate;
    Direction() = default;
    Direction(Vector u_, double lambda_ = 0.0, Vector rate_ = {})  // NOLINT: {phi} is a direction
        : u(std::move(u_)), lambda(lambda_), rate(std::move(rate_)) {}
  };
  struct ComplexDirection {
    ComplexVector u;
    std::complex<double> lambda = 0.0;
    ComplexVector rate;
    ComplexDirection() = default;
    ComplexDirection(ComplexVector u_, std::complex<double> lambda_ = 0.0, ComplexVector rate_ = {})  // NOLINT
        : u(std::move(u_)), lambda(lambda_), rate(std::move(rate_)) {}
  };
  enum class Method { Exact, Differences };

  // At the steady state u0 at the parameters' present values; `parameter` is lambda's index in
  // the problem's ParameterSet. force_differences: differences even where the problem offers
  // exact derivatives (to compare them).
  HigherDerivatives(Problem& problem, int parameter, Vector u0, bool force_differences = false);

  Method method() const { return method_; }
  // What the output says of how they were taken.
  std::string method_name() const;
  // D^2 R[a, b] and D^3 R[a, b, c] (real and complex: multilinear, expanded in real parts).
  Status second(const Direction& a, const Direction& b, Vector& out);
  Status third(const Direction& a, const Direction& b, const Direction& c, Vector& out);
  Status second(const ComplexDirection& a, const ComplexDirection& b, ComplexVector& out);
  Status third(const ComplexDirection& a, const ComplexDirection& b, const ComplexDirection& c, ComplexVector& out);
  // Evaluations of F or of its exact derivatives, and of the time terms, so far.
  long evaluations() const { return evaluations_; }
  // Seconds spent in them.
  double seconds() const { return seconds_; }

 private:
  // a complex multilinear derivative from the real ones, each distinct one once
  Status expand(const std::vector<const ComplexDirection*>& dirs, ComplexVector& out);
  Status f_part(const Direction* const* d, int order, Vector& out);
  Status f_differences(const Direction* const* d, int order, Vector& out);
  Status real(const std::vector<const Direction*>& dirs, Vector& out);
  Status rate_term(const Vector& rate, const Direction* const* others, int order, Vector& out);
  // the real derivative along distinct_[ids] (sorted), from the caches or evaluated into them
  Status cached(const std::vector<int>& ids, Vector& out);
  // F (or the time terms, with rate) at u0 + sum s_i d_i, lambda0 + sum s_i d_i.lambda
  Status shifted(const Direction* const* d, const double* s, int order, const Vector* rate, Vector& out);
  double step(const Direction& d, int order, bool rate) const;
  template <class Evaluate>
  Status timed(const Evaluate& evaluate) {
    const auto t0 = std::chrono::steady_clock::now();
    Status st = evaluate();
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return st;
  }

  Problem& problem_;
  int parameter_;
  Vector u0_;
  double lambda0_;
  ExactDerivatives* exact_ = nullptr;
  Method method_;
  bool has_time_form_;
  long evaluations_ = 0;
  double seconds_ = 0;
  // every derivative's real parts, each once: the distinct real directions (up to sign), F's part by the multiset of
  // their indices, the time terms' by the index of the one whose rate and the others'
  std::vector<Direction> distinct_;
  std::map<std::vector<int>, Vector> f_cache_, rate_cache_;
};

}  // namespace keller
