// The 1D Brusselator (problems/analytic/Brusselator1DProblem) with exact second and third
// derivatives (core/ExactDerivatives.hpp), for the tests that compare what is computed from the
// derivatives by different paths: with differences, the rounding of D^3 at its step (eps S / h^3,
// S the diffusion terms a residual sums, 1600 |u| at 40 intervals) is 1e-9 of l1, and it is a
// different draw for inputs that differ by rounding, so two paths' q that agree to 1e-12 give l1
// that differ by that much. Exact: F = -(D lap(w) + a - (b + 1) u + u^2 v, D lap(v) + b u - u^2 v)
// is bilinear in (parameters, state) but for u^2 v, so
//   D^2 F[x, y] = -(x_Du lap(y_u) + y_Du lap(x_u) - x_b y_u - y_b x_u + D^2(u^2 v), ...),
//   D^2(u^2 v)[x, y] = 2 v x_u y_u + 2 u (x_u y_v + x_v y_u),
//   D^3(u^2 v)[x, y, z] = 2 (x_u y_u z_v + x_u y_v z_u + x_v y_u z_u).
// guess_throws: initial_guess() throws, as a problem's algebraic guess may where it does not exist
// at the present parameters: a computation at a given state must not ask for it.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "core/ExactDerivatives.hpp"
#include "core/Problem.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"

namespace keller::test {

class ExactBrusselator final : public Problem, public ExactDerivatives {
 public:
  explicit ExactBrusselator(const Brusselator1DOptions& o) : inner_(o) {}
  bool guess_throws = false;

  std::string name() const override { return "brusselator1d-exact"; }
  int size() const override { return inner_.size(); }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override { return inner_.residual(u, F); }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override { return inner_.jacobian(u, F, J); }
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    return inner_.parameter_derivative(p, u, dF);
  }
  Status mass_matrix(const Vector& u, SparseMatrix& B) override { return inner_.mass_matrix(u, B); }
  Vector initial_guess() override {
    if (guess_throws) throw std::runtime_error("brusselator1d-exact: no initial guess at these parameters");
    return inner_.initial_guess();
  }

  Status directional_derivative(const Vector& w, const std::vector<Direction>& d, Vector& out) override {
    const int n = inner_.intervals(), order = static_cast<int>(d.size());
    if (order != 2 && order != 3)
      return {StatusCode::InvalidState, "brusselator1d-exact: derivatives of order 2 and 3"};
    const Vector zero_u = Vector::Zero(w.size()), zero_p = Vector::Zero(inner_.parameters().size());
    auto state = [&](int k) -> const Vector& {
      return d[static_cast<size_t>(k)].u ? *d[static_cast<size_t>(k)].u : zero_u;
    };
    auto param = [&](int k, int p) {
      const Vector* v = d[static_cast<size_t>(k)].parameters;
      return v ? (*v)[p] : zero_p[p];
    };
    const double hh = inner_.h() * inner_.h();
    auto lap = [&](const Vector& x, int c, int i) {  // the ghost-point Laplacian of Brusselator1DProblem
      const double l = x[2 * (i > 0 ? i - 1 : 1) + c], r = x[2 * (i < n ? i + 1 : n - 1) + c];
      return (l - 2.0 * x[2 * i + c] + r) / hh;
    };
    out = Vector::Zero(w.size());
    for (int i = 0; i <= n; ++i) {
      const double u = w[2 * i], v = w[2 * i + 1];
      auto xu = [&](int k) { return state(k)[2 * i]; };
      auto xv = [&](int k) { return state(k)[2 * i + 1]; };
      double ru = 0.0, rv = 0.0, uuv = 0.0;
      if (order == 2) {
        uuv = 2.0 * v * xu(0) * xu(1) + 2.0 * u * (xu(0) * xv(1) + xv(0) * xu(1));
        ru = param(0, kDu) * lap(state(1), 0, i) + param(1, kDu) * lap(state(0), 0, i) -
             (param(0, kB) * xu(1) + param(1, kB) * xu(0));
        rv = param(0, kDv) * lap(state(1), 1, i) + param(1, kDv) * lap(state(0), 1, i) +
             (param(0, kB) * xu(1) + param(1, kB) * xu(0));
      } else {
        uuv = 2.0 * (xu(0) * xu(1) * xv(2) + xu(0) * xv(1) * xu(2) + xv(0) * xu(1) * xu(2));
      }
      out[2 * i] = -(ru + uuv);
      out[2 * i + 1] = -(rv - uuv);
    }
    return {};
  }

 private:
  static constexpr int kB = 1, kDu = 2, kDv = 3;  // Brusselator1DProblem's parameter indices
  Brusselator1DProblem inner_;
};

}  // namespace keller::test
