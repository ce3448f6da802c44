// The kept factorisation (continuation/engine/KeptFactorisation) on its own, on ScaledLinear
// (F_i = (1 + lambda) (1 + i) u_i - 1, J = diag((1 + lambda)(1 + i))): where it was made, what it
// solves, when the next correction may start on it (ReusePolicy) and when that correction renews
// it, and another one adopting it.
#include <gtest/gtest.h>

#include <memory>

#include "support/ContinuationTestSupport.hpp"

using namespace keller;
using namespace keller::test;

namespace {

Vector exact(double lambda) {
  Vector u(3);
  for (int i = 0; i < 3; ++i) u[i] = 1.0 / ((1 + lambda) * (1 + i));
  return u;
}

// The chord on a kept factorisation under the rate rule alone (a chord slower than 0.25 renews).
ContinuationOptions chord() {
  ContinuationOptions o = kept_chord_options(0.1, 10.0, 30, {});
  o.method = ContinuationOptions::Method::Arclength;
  return o;
}

}  // namespace

// Made at (exact(0), 0) under the parameter row: it knows that point, solves the tangent system
// [J F_p; 0 1] (v, mu) = (0, 1) of this problem exactly (v = -J^-1 F_p = -u, mu = 1) and the sign
// of det of the bordered matrix (det J > 0); the next correction may start on it.
TEST(KeptFactorisation, MadeAtAPointItSolvesThere) {
  ScaledLinear problem(3);
  EngineParts parts(problem, chord());
  KeptFactorisation& kept = parts.kept;
  EXPECT_FALSE(kept.reusable());  // nothing made yet
  ASSERT_TRUE(kept.factorise_at(parts.ev, exact(0.0), 0.0, Constraint::parameter(0.0)).is_ok());
  EXPECT_EQ(kept.count(), 1);
  EXPECT_TRUE(kept.block());
  EXPECT_TRUE(kept.reusable());
  EXPECT_TRUE(kept.made_at(exact(0.0), 0.0));
  EXPECT_FALSE(kept.made_at(exact(0.0), 1e-12));
  EXPECT_NE(kept.j_factorisation_at(exact(0.0), 0.0), nullptr);
  EXPECT_EQ(kept.j_factorisation_at(exact(0.1), 0.1), nullptr);
  EXPECT_EQ(kept.determinant_sign(), 1);
  Vector v;
  double mu = 0.0;
  ASSERT_TRUE(kept.solve(Vector::Zero(3), 1.0, v, mu).is_ok());
  EXPECT_NEAR(mu, 1.0, 1e-15);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(v[i], -exact(0.0)[i], 1e-15);
}

// Reused, then renewed: the corrections at lambda = 0.1 and 0.2 start on the factorisation made
// at 0 (their chords contract by 0.1 and 0.2, faster than 0.25: no new one); the one at 0.5 (its
// chord would contract by 0.5) renews it. A correction that fails leaves it unusable for the
// next, which factorises at its first iteration although the old one would have served.
TEST(KeptFactorisation, ReusedByTheNextCorrectionsThenRenewed) {
  ScaledLinear problem(3);
  EngineParts parts(problem, chord());
  KeptFactorisation& kept = parts.kept;
  ASSERT_TRUE(kept.factorise_at(parts.ev, exact(0.0), 0.0, Constraint::parameter(0.0)).is_ok());
  const auto correct = [&](double lambda) {
    Vector u = exact(0.0);
    const CorrectorResult r = parts.corrector.correct(u, lambda, Constraint::parameter(lambda), Corrector::Kind::Step);
    EXPECT_TRUE(r.status.is_ok()) << lambda << ": " << r.status.describe();
    EXPECT_NEAR(u[2], exact(lambda)[2], 1e-10) << lambda;
    return r;
  };
  EXPECT_FALSE(correct(0.1).refactored);
  EXPECT_FALSE(correct(0.2).refactored);
  EXPECT_EQ(kept.count(), 1);
  EXPECT_TRUE(kept.reusable());
  EXPECT_TRUE(correct(0.5).refactored);
  EXPECT_EQ(kept.count(), 2);
  EXPECT_TRUE(kept.reusable());  // (made at an iterate of a correction that converged)
  // a failed correction: one iteration allowed where 14 are needed
  ContinuationOptions one = chord();
  one.corrector.max_iterations = 1;
  Corrector short_corrector(parts.ev, kept, parts.norm, one, {});
  Vector u = exact(0.5);
  double lambda = 0.6;
  EXPECT_EQ(short_corrector.correct(u, lambda, Constraint::parameter(0.6), Corrector::Kind::Step).status.code(),
            StatusCode::NotConverged);
  EXPECT_EQ(kept.count(), 2);
  EXPECT_FALSE(kept.reusable());
  EXPECT_TRUE(correct(0.5).refactored);  // at its first iteration
  EXPECT_EQ(kept.count(), 3);
  EXPECT_TRUE(kept.reusable());
}

// Under block elimination a new border row replaces the old one without refactorising (the
// arclength row of a step); the whole bordered matrix factorised (no block elimination) cannot
// take another row, and is never reused.
TEST(KeptFactorisation, ANewRowWithoutRefactorisingUnderBlockEliminationOnly) {
  ScaledLinear problem(3);
  for (const bool block : {true, false}) {
    SCOPED_TRACE(block ? "block" : "full");
    ContinuationOptions o = chord();
    o.corrector.block_elimination = block;
    EngineParts parts(problem, o);
    ASSERT_TRUE(parts.kept.factorise_at(parts.ev, exact(0.0), 0.0, Constraint::parameter(0.0)).is_ok());
    EXPECT_EQ(parts.kept.reusable(), block);
    const Constraint row = parts.norm.tangent_row(Vector::Constant(3, 1.0), 0.5);
    EXPECT_EQ(parts.kept.set_row(row).is_ok(), block);
    if (!block) continue;
    // [J F_p; c^T d] (x, y) = (0, 1) under the new row: x = -u y, (c . (-u) + d) y = 1
    Vector x;
    double y = 0.0;
    ASSERT_TRUE(parts.kept.solve(Vector::Zero(3), 1.0, x, y).is_ok());
    const double expected_y = 1.0 / (0.5 * parts.norm.wl() - parts.norm.wu() * exact(0.0).sum());
    EXPECT_NEAR(y, expected_y, 1e-12 * std::abs(expected_y));
    EXPECT_EQ(parts.kept.count(), 1);
  }
}

// Another kept factorisation adopts this one's J (another run starting on it): no factorisation
// of its own, the same solutions, and its next correction may start on it.
TEST(KeptFactorisation, AnotherOneAdoptsIt) {
  ScaledLinear problem(3);
  EngineParts maker(problem, chord());
  ASSERT_TRUE(maker.kept.factorise_at(maker.ev, exact(0.0), 0.0, Constraint::parameter(0.0)).is_ok());
  const StartFactorisation made = maker.kept.inner_factorisation();
  ASSERT_TRUE(made.lu);
  EngineParts taker(problem, chord());
  ASSERT_TRUE(taker.kept.adopt_at(taker.ev, made, exact(0.0), 0.0, Constraint::parameter(0.0)).is_ok());
  EXPECT_EQ(taker.kept.count(), 0);
  EXPECT_TRUE(taker.kept.reusable());
  Vector a, b;
  double ya = 0.0, yb = 0.0;
  const Vector f = Vector::LinSpaced(3, 1.0, 3.0);
  ASSERT_TRUE(maker.kept.solve(f, 0.5, a, ya).is_ok());
  ASSERT_TRUE(taker.kept.solve(f, 0.5, b, yb).is_ok());
  EXPECT_NEAR(ya, yb, 1e-15);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-15);
}
