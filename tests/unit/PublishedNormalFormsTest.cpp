// Normal forms against values published by other tools (NormalFormsTest.cpp has the closed forms).
//
// The adaptive-control (Lur'e) system of MatCont's manual ("Adaptive control example", testrun
// adaptx; also BifurcationKit's test/periodic_orbits_function_sh4_and_collocation/testLure.jl):
//   x' = y, y' = z, z' = -alpha z - beta y - x + x^2, beta = 1,
// written as B u' = -F with B = I. At the equilibrium 0 the characteristic polynomial is
// lambda^3 + alpha lambda^2 + lambda + 1: a Hopf point at alpha = 1 with omega = 1 (period 2 pi),
// and d lambda / d alpha = -lambda^2 / (3 lambda^2 + 2 alpha lambda + 1) = -(1 + i) / 4 there, so the
// growth rate falls as alpha grows (g' = -1/4) and the orbits, supercritical, exist for alpha < 1.
// MatCont prints "First Lyapunov coefficient = -3.000001e-001" at its located point alpha =
// 1.000002, for q of unit 2-norm; keller's q has unit largest entry (q = (1, i, -1), |q|_2^2 = 3),
// so its l1 is MatCont's times 3. The tolerance 2e-6 is MatCont's printed digits and its point's
// distance from alpha = 1. The same problem's period doubling of the orbits (alpha = 0.6303020,
// T = 6.364071 in the manual) is the test case for continuing periodic orbits.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "stability/NormalForms.hpp"

using namespace keller;

namespace {

class AdaptiveControl final : public Problem {
 public:
  AdaptiveControl() {
    params_.add("alpha", 1.0, "damping");
    pattern_.resize(3, 3);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) pattern_.insert(i, j) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return "adaptive-control"; }
  int size() const override { return 3; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(3); }
  // F = -(y, z, -alpha z - y - x + x^2)
  Status residual(const Vector& u, Vector& F) override {
    const double alpha = params_.value(0);
    F.resize(3);
    F << -u[1], -u[2], alpha * u[2] + u[1] + u[0] - u[0] * u[0];
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    J.coeffRef(0, 1) = -1.0;
    J.coeffRef(1, 2) = -1.0;
    J.coeffRef(2, 0) = 1.0 - 2.0 * u[0];
    J.coeffRef(2, 1) = 1.0;
    J.coeffRef(2, 2) = params_.value(0);
    return {};
  }

 private:
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace

TEST(PublishedNormalForms, AdaptiveControlHopfPointAgainstMatCont) {
  AdaptiveControl problem;
  NormalForm nf;
  ASSERT_TRUE(NormalForms().hopf(problem, 0, Vector::Zero(3), 1.02, nullptr, nf).is_ok());
  EXPECT_NEAR(nf.omega, 1.0, 1e-12);
  EXPECT_NEAR(nf.period, 2.0 * std::numbers::pi, 1e-11);
  EXPECT_NEAR(nf.q.squaredNorm(), 3.0, 1e-12);
  const double matcont_l1 = -3.000001e-1;
  EXPECT_NEAR(nf.l1 / nf.q.squaredNorm(), matcont_l1, 2e-6) << nf.summary();
  EXPECT_NEAR(nf.growth_rate_derivative, -0.25, 1e-9);
  EXPECT_EQ(nf.side, -1);  // the orbits exist below alpha = 1
  EXPECT_EQ(nf.type, "Hopf (supercritical)");
}
