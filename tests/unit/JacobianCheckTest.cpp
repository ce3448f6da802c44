// core/JacobianCheck: J v and dF/dp against central differences, on a small problem whose
// Jacobian is right or wrong on purpose. F_i = -(u_{i-1} - 2 u_i + u_{i+1}) / h^2 - lambda (u_i -
// u_i^3) + mu, with dF/dlambda, dF/dmu exact; the wrong variants are the mistakes a user makes.
#include <gtest/gtest.h>

#include <cmath>

#include "core/JacobianCheck.hpp"

namespace keller {
namespace {

enum class Mistake { None, CubicFactor, Coupling, ParameterSign };

class Cubic final : public Problem {
 public:
  explicit Cubic(Mistake mistake, double bound = INFINITY) : mistake_(mistake), bound_(bound) {
    params_.add("lambda", 3.0, "coefficient of u - u^3");
    params_.add("mu", 0.0, "source", 0.0, 1.0);  // at its lower end: dF/dmu one-sided
    params_.add("kappa", 0.0, "fixed at 0: no room for a difference", 0.0, 0.0);
    std::vector<Eigen::Triplet<double, int>> t;
    for (int i = 0; i < kN; ++i)
      for (int j = std::max(0, i - 1); j <= std::min(kN - 1, i + 1); ++j) t.emplace_back(i, j, 0.0);
    pattern_.resize(kN, kN);
    pattern_.setFromTriplets(t.begin(), t.end());
  }
  std::string name() const override { return "cubic"; }
  int size() const override { return kN; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(kN); }
  Status residual(const Vector& u, Vector& F) override {
    if (u.lpNorm<Eigen::Infinity>() > bound_) return {StatusCode::InvalidState, "|u| above the bound"};
    F.resize(kN);
    const double lambda = params_.value(0), mu = params_.value(1);
    for (int i = 0; i < kN; ++i) {
      const double l = i > 0 ? u[i - 1] : 0.0, r = i + 1 < kN ? u[i + 1] : 0.0;
      F[i] = -(l - 2 * u[i] + r) * kIh2 - lambda * (u[i] - u[i] * u[i] * u[i]) + mu;
    }
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    if (Status st = residual(u, F); !st.is_ok()) return st;
    const double lambda = params_.value(0), cubic = mistake_ == Mistake::CubicFactor ? 2.0 : 3.0;
    J = pattern_;
    for (int i = 0; i < kN; ++i) {
      J.coeffRef(i, i) = 2 * kIh2 - lambda * (1 - cubic * u[i] * u[i]);
      if (i > 0) J.coeffRef(i, i - 1) = -kIh2;
      if (i + 1 < kN) J.coeffRef(i, i + 1) = (mistake_ == Mistake::Coupling && i == 5) ? 0.0 : -kIh2;
    }
    return {};
  }
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    if (p == 0) dF = -(u.array() - u.array().cube()).matrix();
    if (p == 1) dF = Vector::Constant(kN, mistake_ == Mistake::ParameterSign ? -1.0 : 1.0);
    if (p == 2) return Problem::parameter_derivative(p, u, dF);  // fails: no room
    return {};
  }

 private:
  static constexpr int kN = 20;
  static constexpr double kIh2 = 21.0 * 21.0;
  Mistake mistake_;
  double bound_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

// An exact Jacobian: the errors of central differences, O(h^2) and O(eps |F| / h), the smallest
// over the steps: 1e-12 for J v, 1e-9 for dF/dlambda (|F| ~ 200 against |dF/dlambda| ~ 0.1), at
// u = 0 and near it.
TEST(JacobianCheck, AnExactJacobianPasses) {
  Cubic p(Mistake::None);
  const JacobianCheckResult r = check_jacobian(p, Vector::Zero(20));
  ASSERT_TRUE(r.status.is_ok());
  ASSERT_EQ(r.state_errors.size(), 2u);
  for (double e : r.state_errors) EXPECT_LT(e, 1e-8);
  ASSERT_EQ(r.parameter_errors.size(), 3u);
  for (double e : r.parameter_errors) EXPECT_LT(e, 1e-8);
  // a parameter fixed by its range ([0, 0]) has no derivative: left out and said so, not failed
  EXPECT_EQ(r.parameter_checked, (std::vector<bool>{true, true, false}));
  EXPECT_NE(r.describe().find("dF/dkappa: not checked"), std::string::npos) << r.describe();
  EXPECT_TRUE(r.passed(1e-6));
  EXPECT_EQ(p.parameters().value(0), 3.0);  // the parameters as they were
  EXPECT_EQ(p.parameters().value(1), 0.0);
}

// A wrong cubic term (2 u^2 for 3 u^2) vanishes at u = 0: only the perturbed state (|u| ~ 0.1)
// shows it, as lambda u^2 v against the Laplacian's 4 v / h^2 in J v: about 3 * 0.01 / 1764, 2e-5,
// where the exact Jacobian's error is 1e-12. A missing coupling entry (1 / h^2 of a row whose
// entries sum to 4 / h^2) shows everywhere; a wrong sign of dF/dmu is an error of 2.
TEST(JacobianCheck, AWrongEntryFails) {
  Cubic cubic(Mistake::CubicFactor);
  JacobianCheckResult r = check_jacobian(cubic, Vector::Zero(20));
  ASSERT_EQ(r.state_errors.size(), 2u);
  EXPECT_LT(r.state_errors[0], 1e-8);  // the cubic's mistake is invisible at u = 0
  EXPECT_GT(r.state_errors[1], 1e-5);
  EXPECT_FALSE(r.passed(1e-6));

  Cubic coupling(Mistake::Coupling);
  r = check_jacobian(coupling, Vector::Zero(20));
  EXPECT_GT(r.state_errors[0], 1e-2);
  EXPECT_FALSE(r.passed(1e-6));

  Cubic sign(Mistake::ParameterSign);
  r = check_jacobian(sign, Vector::Zero(20));
  EXPECT_LT(r.state_errors[0], 1e-8);
  EXPECT_NEAR(r.parameter_errors[1], 2.0, 1e-8);  // |(-1) - 1| / 1 (one-sided at mu's lower end)
  EXPECT_FALSE(r.passed(1e-6));
}

// A perturbed state outside the problem's domain is tried closer, by factors of 10. The steps of
// the differences, |h v|_inf, are 1e-4 to 1e-7 (those out of the domain skipped); |u|_inf of a
// perturbed state is its size times |r|_inf, above 1/2 for 20 uniform samples. Bound 2e-4: 1e-3 of the perturbation 0.1
// is refused, 1e-4 admitted; bound 5e-5 with the perturbation 1: every size down to 1e-4 refused, the perturbed state
// left out.
TEST(JacobianCheck, APerturbedStateOutsideTheDomainIsTriedCloser) {
  Cubic near(Mistake::None, 2e-4);
  JacobianCheckResult r = check_jacobian(near, Vector::Zero(20));
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  ASSERT_EQ(r.states.size(), 2u);
  EXPECT_EQ(r.states[1], "the state perturbed by 1e-04");
  Cubic tight(Mistake::None, 5e-5);
  JacobianCheckOptions o;
  o.perturbation = 1.0;
  r = check_jacobian(tight, Vector::Zero(20), o);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_EQ(r.states.size(), 1u);
  EXPECT_TRUE(r.passed(1e-6));
}

}  // namespace
}  // namespace keller
