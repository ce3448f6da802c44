// Fold curves by the minimally augmented system (continuation/curves/FoldCurveProblem): the cusp
// u^3 - mu u - lambda = 0, whose fold curve is known in closed form, and the 1D Bratu problem
// with a linear term, whose curve is checked against folds located on ordinary lambda branches.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "continuation/curves/FoldCurveProblem.hpp"
#include "problems/analytic/ShiftedBratu1DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// F(u; lambda, mu) = u^3 - mu u - lambda: folds where 3 u^2 = mu, i.e. on
// lambda = -2 u^3 = -/+ 2 (mu / 3)^(3/2), with a cusp at u = mu = lambda = 0 (F_uu = 6u = 0).
class CuspProblem final : public Problem {
 public:
  CuspProblem(double lambda, double mu) : pattern_(1, 1) {
    params_.add("lambda", lambda, "load");
    params_.add("mu", mu, "unfolding");
    pattern_.insert(0, 0) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return "cusp"; }
  int size() const override { return 1; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    F = Vector::Constant(1, u[0] * u[0] * u[0] - params_.value(1) * u[0] - params_.value(0));
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    J.valuePtr()[0] = 3.0 * u[0] * u[0] - params_.value(1);
    return {};
  }
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    dF = Vector::Constant(1, p == 0 ? -1.0 : -u[0]);
    return {};
  }
  Vector initial_guess() override { return Vector::Zero(1); }
  std::vector<std::string> observable_names() const override { return {"u"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    v = {u[0]};
    return {};
  }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  ParameterSet params_;
  SparseMatrix pattern_;
};

NewtonOptions tight() {
  NewtonOptions n;
  n.residual_tolerance = 1e-12;  // two orders below the 1e-10 the curve is checked to
  return n;
}

}  // namespace

// From a perturbed fold at mu = 2.7 down through the cusp and up the other half to mu = 3: every
// point on lambda = -2 sign(u) (mu / 3)^(3/2) to 1e-10, the cusp located where the quadratic
// coefficient 6u changes sign, and there the curve turns in mu (a fold of the curve, at mu = 0).
TEST(FoldCurve, CubicFoldCurveFollowsTheCuspInClosedForm) {
  const double mu0 = 2.7, u0 = std::sqrt(mu0 / 3.0);
  CuspProblem p(-2.0 * u0 * u0 * u0, mu0);
  FoldCurveProblem curve(p, "lambda");
  Vector U = curve.state(Vector::Constant(1, u0 + 1e-3), -2.0 * u0 * u0 * u0 + 1e-3);
  ASSERT_TRUE(curve.start(U, Vector::Ones(1), tight()).is_ok());
  EXPECT_NEAR(U[0], u0, 1e-12);
  EXPECT_NEAR(U[1], -2.0 * u0 * u0 * u0, 1e-12);

  ContinuationOptions o;
  o.parameter = "mu";
  o.direction = -1;
  o.stop.upper = 3.0;
  o.step.initial = 0.05;
  o.step.max = 0.2;
  o.events.tolerance = 1e-10;
  Continuation cont(curve, o, tight());
  test::RecordingObserver rec;
  FoldCurveProblem::BorderUpdate borders(curve, rec);
  const ContinuationResult r = cont.run(U, borders);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  ASSERT_GT(rec.points.size(), 20u);
  double worst = 0.0;
  for (const BranchPoint& q : rec.points) {
    const double u = q.u[0], lambda = q.u[1], mu = q.lambda;
    const double expected = -2.0 * (u > 0 ? 1.0 : -1.0) * std::pow(std::max(mu, 0.0) / 3.0, 1.5);
    worst = std::max(worst, std::abs(lambda - expected));
    EXPECT_NEAR(lambda, expected, 1e-10) << "mu = " << mu << ", u = " << u;
    EXPECT_NEAR(q.observables.back(), lambda, 0.0);  // the fold parameter is the last observable
  }
  std::cout << rec.points.size() << " points, largest |lambda - closed form| = " << worst << "\n";
  // it ends on the other half of the curve: u = -1, lambda = 2 at mu = 3
  EXPECT_NEAR(rec.points.back().lambda, 3.0, 1e-12);
  EXPECT_NEAR(rec.points.back().u[0], -1.0, 1e-10);
  EXPECT_NEAR(rec.points.back().u[1], 2.0, 1e-10);

  std::vector<const BranchPoint*> cusps;
  for (const BranchPoint* e : rec.of_kind(PointKind::Event))
    if (e->label == "cusp") cusps.push_back(e);
  ASSERT_EQ(cusps.size(), 1u);
  // located to 1e-10 in mu = 3 u^2: |u| below 1e-5, lambda = -2 u^3 below 1e-14
  EXPECT_NEAR(cusps[0]->lambda, 0.0, 1e-10);
  EXPECT_NEAR(cusps[0]->u[0], 0.0, 1e-5);
  EXPECT_NEAR(cusps[0]->u[1], 0.0, 1e-12);
  const auto turns = rec.of_kind(PointKind::Fold);
  ASSERT_EQ(turns.size(), 1u);
  EXPECT_EQ(turns[0]->label, "min");
  EXPECT_NEAR(turns[0]->lambda, 0.0, 1e-10);
}

// 1D Bratu with a linear term on 64 intervals: the fold located on the lambda branch at mu = 0,
// continued in mu by the augmented system and stored at mu = 1, 2, 4, 6, agrees with the folds
// located on ordinary lambda branches at those values of mu to 1e-8 (each located to 1e-12).
TEST(FoldCurve, ShiftedBratuFoldCurveMatchesFoldsOfOrdinaryBranches) {
  auto fold_at = [](double mu) {
    ShiftedBratu1DProblem p(64, 0.0, mu);
    Continuation cont(p, test::bratu_fold_options("u_mid", 6.0));
    test::RecordingObserver rec;
    cont.run(p.initial_guess(), rec);
    const auto folds = rec.of_kind(PointKind::Fold);
    EXPECT_EQ(folds.size(), 1u) << "mu = " << mu;
    return folds.empty() ? BranchPoint{} : *folds[0];
  };
  const BranchPoint fold0 = fold_at(0.0);
  ASSERT_GT(fold0.lambda, 3.5);

  ShiftedBratu1DProblem p(64, fold0.lambda, 0.0);
  FoldCurveProblem curve(p, "lambda");
  Vector U = curve.state(fold0.u, fold0.lambda);
  ASSERT_TRUE(curve.start(U, fold0.tu, {}).is_ok());
  ContinuationOptions o;
  o.parameter = "mu";
  o.stop.upper = 6.5;
  o.step.initial = 0.1;
  o.step.max = 0.5;
  o.events.stops = {1.0, 2.0, 4.0, 6.0};
  o.events.tolerance = 1e-10;
  Continuation cont(curve, o);
  test::RecordingObserver rec;
  FoldCurveProblem::BorderUpdate borders(curve, rec);
  const ContinuationResult r = cont.run(U, borders);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  const auto at = rec.of_kind(PointKind::Requested);
  ASSERT_EQ(at.size(), 4u);
  double prev = fold0.lambda;
  for (const BranchPoint* q : at) {
    const double lambda_curve = q->observables.back();
    const BranchPoint f = fold_at(q->lambda);
    std::cout << std::setprecision(14) << "mu = " << q->lambda << ": curve lambda = " << lambda_curve
              << ", fold of the lambda branch " << f.lambda << "\n";
    EXPECT_NEAR(lambda_curve, f.lambda, 1e-8) << "mu = " << q->lambda;
    EXPECT_LT(lambda_curve, prev);  // the fold falls as mu rises towards the first eigenvalue
    prev = lambda_curve;
  }
}

// The augmented Jacobian [J F_p1; g_u^T g_p1] and dF/dmu (g's derivatives by differences of J and
// dF/dp along v) against central differences of the augmented residual, near a fold of the
// shifted Bratu problem: to 1e-6 of the largest entry (differences of differences, h = 1e-5).
TEST(FoldCurve, AugmentedJacobianMatchesDifferencesOfItsResidual) {
  ShiftedBratu1DProblem p(16, 3.0, 1.0);
  FoldCurveProblem curve(p, "lambda");
  Vector u(p.size());
  for (int i = 0; i < u.size(); ++i) u[i] = 3.0 * std::sin(M_PI * (i + 1) / 16.0);
  Vector U = curve.state(u, 3.0);
  ASSERT_TRUE(curve.set_borders(U, u).is_ok());
  Vector F;
  SparseMatrix J;
  ASSERT_TRUE(curve.jacobian(U, F, J).is_ok());
  const Eigen::MatrixXd A(J);
  double worst = 0.0;
  for (int k = 0; k < U.size(); ++k) {
    const double h = 1e-5;
    Vector Up = U, Um = U, Fp, Fm;
    Up[k] += h;
    Um[k] -= h;
    ASSERT_TRUE(curve.residual(Up, Fp).is_ok());
    ASSERT_TRUE(curve.residual(Um, Fm).is_ok());
    worst = std::max(worst, ((Fp - Fm) / (2 * h) - A.col(k)).lpNorm<Eigen::Infinity>());
  }
  const double scale = A.lpNorm<Eigen::Infinity>();
  EXPECT_LT(worst, 1e-6 * scale) << "largest entry " << scale;
  EXPECT_GT(A.row(U.size() - 1).head(p.size()).norm(), 1e-3 * scale);  // g depends on u: the row is there
  Vector dF, Fp, Fm;
  ASSERT_TRUE(curve.parameter_derivative(1, U, dF).is_ok());
  const double h = 1e-5;
  p.parameters().set("mu", 1.0 + h);
  ASSERT_TRUE(curve.residual(U, Fp).is_ok());
  p.parameters().set("mu", 1.0 - h);
  ASSERT_TRUE(curve.residual(U, Fm).is_ok());
  p.parameters().set("mu", 1.0);
  EXPECT_LT(((Fp - Fm) / (2 * h) - dF).lpNorm<Eigen::Infinity>(), 1e-6 * dF.lpNorm<Eigen::Infinity>());
  EXPECT_THROW(curve.parameter_derivative(0, U, dF), std::invalid_argument);
}
