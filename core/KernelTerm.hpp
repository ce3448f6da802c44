// The bridge from an element kernel written once, templated on its scalar types, to a Term
// with an exact Jacobian and exact parameter derivatives by forward-mode dual numbers.
//
// A Kernel provides
//   static constexpr int kSize;                       // local unknowns per item
//   (optional) static constexpr int kRows;            // rows written (the first kRows unknowns'
//                                                     // rows; default kSize), e.g. boundary terms
//   std::string name() const;
//   int num_items() const;
//   void item_dofs(int item, int* dofs) const;
//   template <class T, class P>
//   Status evaluate(int item, const T* u, const P* params, T* r) const;
// where T is the scalar of the unknowns and residual and P that of the parameter values.
// A kernel whose equations carry time derivatives also provides their time terms, written once
// and templated on the scalar of the rates,
//   template <class W> Status rate(int item, const double* u, const W* udot, const double* params, W* r) const;
// r = B(u) udot (kRows), from which the local block of B in B du/dt = -F (row-major kRows x kSize)
// is taken exactly by dual numbers (Dual<kSize>, the rates the variables); or the block itself,
//   Status mass(int item, const double* u, const double* params, double* B) const;
// and optionally both parts of the time-dependent residual at once (residual_with_rate below).
// evaluate is instantiated with (double, double) for residuals, (Dual<kSize>, double) for the
// Jacobian, (Dual<1>, Dual<1>) for dF/dp and (HyperDual<K>, HyperDual<K>) for second and third
// directional derivatives, so kernels must only mix T with P and double in ways that give T, and
// call the functions HyperDual has (exp, log, pow, sqrt, cosh, sinh, tanh, sin, cos, abs)
// unqualified.
#pragma once

#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/AutoDiff.hpp"
#include "core/HyperDual.hpp"
#include "core/ParameterSet.hpp"
#include "core/Term.hpp"

namespace keller {

template <class Kernel>
constexpr int kernel_rows() {
  if constexpr (requires { Kernel::kRows; })
    return Kernel::kRows;
  else
    return Kernel::kSize;
}

template <class Kernel>
class KernelTerm final : public Term {
 public:
  static constexpr int N = Kernel::kSize;
  static constexpr int R = kernel_rows<Kernel>();
  using JacobianScalar = Dual<N>;
  using DerivativeScalar = Dual<1>;

  KernelTerm(Kernel kernel, const ParameterSet& params) : kernel_(std::move(kernel)), params_(&params) {}

  std::string name() const override { return kernel_.name(); }
  int num_items() const override { return kernel_.num_items(); }
  int local_size() const override { return N; }
  int local_rows() const override { return R; }
  void item_dofs(int item, int* dofs) const override { kernel_.item_dofs(item, dofs); }

  Status residual(int item, const double* u, double* r) const override {
    return kernel_.template evaluate<double, double>(item, u, params_->values(), r);
  }

  Status jacobian(int item, const double* u, double* r, double* J) const override {
    std::array<JacobianScalar, N> ud;
    std::array<JacobianScalar, R> rd;
    for (int i = 0; i < N; ++i) ud[i] = make_variable<N>(u[i], i);
    Status st = kernel_.template evaluate<JacobianScalar, double>(item, ud.data(), params_->values(), rd.data());
    for (int i = 0; i < R; ++i) {
      r[i] = rd[i].value();
      for (int j = 0; j < N; ++j) J[i * N + j] = rd[i].derivatives()[j];
    }
    return st;
  }

  Status parameter_derivative(int item, int p, const double* u, double* dr) const override {
    std::array<DerivativeScalar, N> ud;
    std::array<DerivativeScalar, R> rd;
    for (int i = 0; i < N; ++i) ud[i] = DerivativeScalar(u[i]);
    std::vector<DerivativeScalar> pd(params_->values(), params_->values() + params_->size());
    pd[p].derivatives()[0] = 1.0;
    Status st = kernel_.template evaluate<DerivativeScalar, DerivativeScalar>(item, ud.data(), pd.data(), rd.data());
    for (int i = 0; i < R; ++i) dr[i] = rd[i].derivatives()[0];
    return st;
  }

  bool has_directional_derivative() const override { return true; }
  Status directional_derivative(int item, const double* u, int order, const double* const* du, const double* const* dp,
                                double* r) const override {
    if (order == 2) return hyper<2>(item, u, du, dp, r);
    if (order == 3) return hyper<3>(item, u, du, dp, r);
    throw std::invalid_argument("KernelTerm::directional_derivative: order 2 or 3");
  }

  static constexpr bool kHasRate = requires(const Kernel& k, const double* x, double* y) { k.rate(0, x, x, x, y); };
  static constexpr bool kHasMass = requires(const Kernel& k, const double* x, double* y) { k.mass(0, x, x, y); };

  bool has_mass() const override { return kHasRate || kHasMass; }
  Status mass(int item, const double* u, double* B) const override {
    if constexpr (kHasRate) {
      // the rates as the variables: r is linear in them, its derivatives are B's rows
      std::array<JacobianScalar, N> udot;
      std::array<JacobianScalar, R> rd;
      for (int j = 0; j < N; ++j) udot[j] = make_variable<N>(0.0, j);
      Status st = kernel_.template rate<JacobianScalar>(item, u, udot.data(), params_->values(), rd.data());
      for (int i = 0; i < R; ++i)
        for (int j = 0; j < N; ++j) B[i * N + j] = rd[i].derivatives()[j];
      return st;
    } else if constexpr (kHasMass) {
      return kernel_.mass(item, u, params_->values(), B);
    } else {
      return {};
    }
  }
  Status rate(int item, const double* u, const double* udot, double* r) const override {
    if constexpr (kHasRate)
      return kernel_.template rate<double>(item, u, udot, params_->values(), r);
    else
      return Term::rate(item, u, udot, r);
  }

  // A kernel may evaluate its residual and its time terms together,
  //   Status evaluate_with_rate(int item, const double* u, const double* udot, const double* params, double* r) const;
  // r = F + B(u) udot (kRows), sharing what both compute (a moving element's geometry).
  static constexpr bool kHasFused = requires(const Kernel& k, const double* x, double* y) {
    k.evaluate_with_rate(0, x, x, x, y);
  };
  Status residual_with_rate(int item, const double* u, const double* udot, double* r) const override {
    if constexpr (kHasFused)
      return kernel_.evaluate_with_rate(item, u, udot, params_->values(), r);
    else
      return Term::residual_with_rate(item, u, udot, r);
  }

  const Kernel& kernel() const { return kernel_; }

 private:
  // D^k r by one evaluation in hyper-dual numbers (core/HyperDual.hpp)
  template <int K>
  Status hyper(int item, const double* u, const double* const* du, const double* const* dp, double* r) const {
    using S = HyperDual<K>;
    auto seed = [&](double v, const double* const* d, int i) {
      std::array<double, K> along{};
      for (int j = 0; j < K; ++j) along[static_cast<size_t>(j)] = d[j] ? d[j][i] : 0.0;
      return seeded<K>(v, along);
    };
    std::array<S, N> ud;
    std::array<S, R> rd;
    for (int i = 0; i < N; ++i) ud[static_cast<size_t>(i)] = seed(u[i], du, i);
    const int np = params_->size();
    std::vector<S> pd(static_cast<size_t>(np));
    for (int i = 0; i < np; ++i) pd[static_cast<size_t>(i)] = seed(params_->values()[i], dp, i);
    Status st = kernel_.template evaluate<S, S>(item, ud.data(), pd.data(), rd.data());
    for (int i = 0; i < R; ++i) r[i] = mixed_part<K>(rd[static_cast<size_t>(i)]);
    return st;
  }

  Kernel kernel_;
  const ParameterSet* params_;
};

}  // namespace keller
