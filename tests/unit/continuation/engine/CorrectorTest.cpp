// The corrector (continuation/engine/Corrector) on its own, on small problems with closed-form
// solutions: Newton's quadratic convergence, the chord's rate on a kept factorisation, Deuflhard's
// monotonicity test, and a located point's retry on a fresh factorisation.
#include <gtest/gtest.h>

#include <cmath>

#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// F_i = u_i^2 - (1 + i) lambda: u_i = sqrt((1 + i) lambda). Newton from u_k leaves the error
// e_{k+1} = e_k^2 / (2 u_k) in each unknown.
FunctionProblem squares() {
  return FunctionProblem(
      "squares", 2, {{"lambda", 4.0}},
      [](const Vector& u, const Vector& p) {
        return Vector{{u[0] * u[0] - p[0], u[1] * u[1] - 2 * p[0]}};
      },
      [](const Vector& u, const Vector&) {
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2, 2);
        J(0, 0) = 2 * u[0];
        J(1, 1) = 2 * u[1];
        return J;
      },
      [](int, const Vector&, const Vector&) {
        return Vector{{-1.0, -2.0}};
      });
}

// F_i = (1 + lambda) (1 + i) u_i - 1 (ScaledLinear): on a factorisation made at lambda_b the chord
// contracts the residual by exactly |1 - (1 + lambda) / (1 + lambda_b)| per iteration.
ContinuationOptions chord_options() {
  ContinuationOptions o = kept_chord_options(0.1, 10.0, 30, {});
  o.method = ContinuationOptions::Method::Arclength;
  return o;
}

Vector exact_scaled(int n, double lambda) {
  Vector u(n);
  for (int i = 0; i < n; ++i) u[i] = 1.0 / ((1 + lambda) * (1 + i));
  return u;
}

// A factorisation kept from lambda = -0.9999, where the chord at lambda = 0 multiplies the residual
// by 9999.
Status kept_far_away(EngineParts& parts) {
  return parts.kept.factorise_at(parts.ev, exact_scaled(3, -0.9999), -0.9999, Constraint::parameter(-0.9999));
}

}  // namespace

// Newton from (3, 3) at lambda = 4 (solution (2, 2 sqrt 2)): the corrector stopped after k
// iterations holds Newton's k-th iterate, each error the square of the last over twice the
// iterate (to rounding of u), and it converges to the tolerance in five.
TEST(Corrector, NewtonConvergesQuadraticallyToAClosedForm) {
  FunctionProblem problem = squares();
  ContinuationOptions o;
  o.parameter = "lambda";
  o.corrector.method = CorrectorOptions::Method::Newton;
  o.corrector.block_elimination = false;
  const Vector exact{{2.0, 2.0 * std::sqrt(2.0)}};
  Vector newton = Vector::Constant(2, 3.0);  // Newton's iterates, in closed form
  for (int k = 1; k <= 4; ++k) {
    const Vector before = newton;
    for (int i = 0; i < 2; ++i) newton[i] = 0.5 * (before[i] + (1 + i) * 4.0 / before[i]);
    o.corrector.max_iterations = k;
    EngineParts parts(problem, o);
    Vector u = Vector::Constant(2, 3.0);
    double lambda = 4.0;
    parts.corrector.correct(u, lambda, Constraint::parameter(4.0), Corrector::Kind::Step);
    EXPECT_EQ(lambda, 4.0);
    for (int i = 0; i < 2; ++i) {
      const double e = u[i] - exact[i], e_before = before[i] - exact[i];
      EXPECT_NEAR(u[i], newton[i], 1e-15 * exact[i]) << "iteration " << k;
      EXPECT_NEAR(e, e_before * e_before / (2 * before[i]), 2e-15 * exact[i]) << "iteration " << k;
    }
    EXPECT_EQ(parts.kept.count(), k);  // a factorisation per Newton iteration
  }
  o.corrector.max_iterations = 0;  // the default, 10
  EngineParts parts(problem, o);
  Vector u = Vector::Constant(2, 3.0);
  double lambda = 4.0;
  const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(4.0), Corrector::Kind::Step);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_EQ(r.iterations, 5);  // errors 1, 0.17, 0.014, 1e-4, 5e-9, 1e-17 in u_0
  EXPECT_LE(r.residual, 1e-10);
  EXPECT_NEAR(u[0], exact[0], 1e-14);
  EXPECT_NEAR(u[1], exact[1], 1e-14);
}

// On a factorisation kept from lambda = 0, a correction at lambda = 0.2 contracts its residual by
// 0.2 per iteration, below the chord rate 0.25: it stays on that factorisation and needs 14
// iterations from |F| = 0.2 (0.2^15 = 3e-11 <= 1e-10 < 0.2^14).
TEST(Corrector, TheChordContractsAtTheRateOfTheKeptMatrix) {
  ScaledLinear problem(3);
  EngineParts parts(problem, chord_options());
  ASSERT_TRUE(parts.kept.factorise_at(parts.ev, exact_scaled(3, 0.0), 0.0, Constraint::parameter(0.0)).is_ok());
  Vector u = exact_scaled(3, 0.0);
  double lambda = 0.2;
  const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(0.2), Corrector::Kind::Step);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_EQ(r.iterations, 14);
  EXPECT_FALSE(r.refactored);
  EXPECT_EQ(parts.kept.count(), 1);
  EXPECT_LE(r.residual, 1e-10);
  EXPECT_NEAR(r.residual, std::pow(0.2, 15), 1e-3 * std::pow(0.2, 15));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u[i], exact_scaled(3, 0.2)[i], 1e-10);
}

// F = atan(u - lambda^3) from e = u - lambda^3 = 4: Newton's correction is (1 + e^2) atan(e) =
// 22.54 (to e = -18.54), and the simplified one on the same Jacobian there (1 + 16) atan(18.54) =
// 25.79: 1.14 times longer, so the step started outside Newton's region of contraction and is
// rejected after one Jacobian (|F| rose from 1.33 to 1.52 only, far from the divergence factor).
TEST(Corrector, DeuflhardsTestRejectsAStepOutsideTheRegionOfContraction) {
  FunctionProblem problem(
      "atan-cubic", 1, {{"lambda", 1.0}},
      [](const Vector& u, const Vector& p) { return Vector::Constant(1, std::atan(u[0] - std::pow(p[0], 3))); },
      [](const Vector& u, const Vector& p) {
        return Eigen::MatrixXd::Constant(1, 1, 1.0 / (1.0 + std::pow(u[0] - std::pow(p[0], 3), 2)));
      },
      [](int, const Vector& u, const Vector& p) {
        return Vector::Constant(1, -3 * p[0] * p[0] / (1.0 + std::pow(u[0] - std::pow(p[0], 3), 2)));
      });
  EngineParts parts(problem, chord_options());
  Vector u = Vector::Constant(1, 5.0);  // e = 4 at lambda = 1
  double lambda = 1.0;
  const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(1.0), Corrector::Kind::Step);
  EXPECT_EQ(r.status.code(), StatusCode::Diverged);
  EXPECT_NE(r.status.message().find("1.14 times the Newton correction (monotonicity test)"), std::string::npos)
      << r.status.describe();
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(parts.kept.count(), 1);
  EXPECT_FALSE(parts.kept.reusable());  // (made at an iterate far off the branch)
}

// On a factorisation from lambda = -0.9999 the chord at lambda = 0 multiplies the residual by
// 9999, past the divergence factor (1e3), at its first iteration. A step fails at once; a located
// point is corrected again from its prediction on a factorisation made there, which solves this
// linear problem in one iteration: 1 + 1 iterations, one more factorisation.
TEST(Corrector, ALocatedPointIsRetriedOnceOnAFreshFactorisation) {
  for (const Corrector::Kind kind : {Corrector::Kind::Step, Corrector::Kind::Located}) {
    const bool located = kind == Corrector::Kind::Located;
    SCOPED_TRACE(located ? "located" : "step");
    ScaledLinear problem(3);
    EngineParts parts(problem, chord_options());
    ASSERT_TRUE(kept_far_away(parts).is_ok());
    Vector u = exact_scaled(3, 0.0) * 1.1;
    double lambda = 0.0;
    const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(0.0), kind);
    if (located) {
      ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
      EXPECT_EQ(r.iterations, 2);
      EXPECT_TRUE(r.refactored);
      EXPECT_EQ(parts.kept.count(), 2);
      EXPECT_TRUE(parts.kept.reusable());
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(u[i], exact_scaled(3, 0.0)[i], 1e-12);
    } else {
      EXPECT_EQ(r.status.code(), StatusCode::Diverged);
      EXPECT_EQ(r.iterations, 1);
      EXPECT_FALSE(r.refactored);
      EXPECT_EQ(parts.kept.count(), 1);
      EXPECT_FALSE(parts.kept.reusable());
    }
  }
}

// A located point's prediction may already be on the branch (the cubic through two converged
// neighbours; next to a branch point, where J is nearly singular, iterating only adds rounding
// along its null vector). Here the prediction is the solution at lambda = 0 to 1e-13, and the
// chord on the factorisation kept from lambda = -0.9999 multiplies its residual by 9999: the
// located point is the prediction, unchanged, after that one iteration and with no second
// factorisation. A step iterates from its prediction as before (and diverges).
TEST(Corrector, ALocatedPredictionAlreadyOnTheBranchIsThePoint) {
  for (const Corrector::Kind kind : {Corrector::Kind::Step, Corrector::Kind::Located}) {
    const bool located = kind == Corrector::Kind::Located;
    SCOPED_TRACE(located ? "located" : "step");
    ScaledLinear problem(3);
    EngineParts parts(problem, chord_options());
    ASSERT_TRUE(kept_far_away(parts).is_ok());
    const Vector prediction = exact_scaled(3, 0.0) * (1.0 + 1e-13);
    Vector u = prediction;
    double lambda = 0.0;
    const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(0.0), kind);
    if (located) {
      ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
      EXPECT_EQ(r.iterations, 1);
      EXPECT_EQ(parts.kept.count(), 1);
      EXPECT_EQ(lambda, 0.0);
      for (int i = 0; i < 3; ++i) EXPECT_EQ(u[i], prediction[i]);
      EXPECT_LE(r.residual, 1e-12);
    } else {
      EXPECT_EQ(r.status.code(), StatusCode::Diverged);
    }
  }
}
