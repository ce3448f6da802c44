// Anderson acceleration of a fixed-point iteration x <- x + f(x), f = M^{-1} (b - A x) with an
// old matrix M: on a linear problem it is GMRES in exact arithmetic, so with a history as deep as
// the dimension it reaches the solution in at most n + 1 updates, where the plain iteration
// contracts by its spectral radius per update.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

#include "core/Anderson.hpp"

using namespace keller;

namespace {

// A (6 x 6, nonsymmetric) and an old matrix M = A + E whose chord iteration I - M^{-1} A has
// eigenvalues of both signs up to 0.8 in modulus (slow and oscillating modes).
struct LinearCase {
  Eigen::MatrixXd A, M;
  Vector b, x_star;
  LinearCase() {
    const int n = 6;
    A = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) {
      A(i, i) = 2.0 + i;
      if (i + 1 < n) A(i, i + 1) = 0.5;
      if (i > 0) A(i, i - 1) = -0.3;
    }
    // M^{-1} A = I - G with G = S diag(g) S^{-1}: M = A (I - G)^{-1}
    const Eigen::VectorXd g = (Eigen::VectorXd(n) << 0.8, -0.75, 0.6, -0.4, 0.2, 0.05).finished();
    Eigen::MatrixXd S = Eigen::MatrixXd::Identity(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        if (i != j) S(i, j) = 0.1 * std::sin(1.0 + i + 2.0 * j);
    const Eigen::MatrixXd G = S * g.asDiagonal() * S.inverse();
    M = A * (Eigen::MatrixXd::Identity(n, n) - G).inverse();
    x_star = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
    b = A * x_star;
  }
  Vector update(const Vector& x) const { return M.partialPivLu().solve(b - A * x); }
};

double error_after(const LinearCase& c, int depth, int updates) {
  AndersonMixer mixer(depth);
  Vector x = Vector::Zero(c.b.size());
  for (int k = 0; k < updates; ++k) x += mixer.increment(x, c.update(x));
  return (x - c.x_star).lpNorm<Eigen::Infinity>();
}

}  // namespace

TEST(Anderson, IsGmresOnALinearProblem) {
  const LinearCase c;
  const double plain = error_after(c, 0, 8), accelerated = error_after(c, 6, 8);
  std::cout << "error after 8 updates: plain " << plain << ", depth 6 " << accelerated << "\n";
  // n = 6: at most n + 1 = 7 updates in exact arithmetic, one more for rounding
  EXPECT_LT(accelerated, 1e-12);
  EXPECT_GT(plain, 1e-2);  // 0.8^8 = 0.17 of the slowest mode's share
}

// The corrector keeps a few updates (its depth is an option): the two slowest modes (0.8 and
// -0.75) are what a depth of 2 must take out, so it needs less than half the plain updates.
TEST(Anderson, AShallowHistoryStillAccelerates) {
  const LinearCase c;
  auto updates_to = [&](int depth, double tol) {
    for (int k = 1; k < 500; ++k)
      if (error_after(c, depth, k) < tol) return k;
    return 500;
  };
  const int plain = updates_to(0, 1e-10), shallow = updates_to(2, 1e-10);
  std::cout << "updates to an error of 1e-10: plain " << plain << ", depth 2 " << shallow << "\n";
  EXPECT_GE(plain, 90);  // log(1e-10) / log(0.8) = 103, less the slow mode's smaller share
  EXPECT_LT(2 * shallow, plain);
}

// The combination of past updates keeps every linear constraint that each x + f satisfies (the
// corrector's arclength row): c . (x + f) = t for every pair implies c . x = t after each update.
TEST(Anderson, KeepsTheLinearConstraintOfTheUpdates) {
  const int n = 5;
  Vector c(n);
  c << 1.0, -2.0, 0.5, 3.0, 1.0;
  const double t = 0.7;
  AndersonMixer mixer(3);
  Vector x = Vector::Zero(n);
  for (int k = 0; k < 6; ++k) {
    // an update that lands on the constraint from anywhere, with a nonlinear part inside it
    Vector f(n);
    for (int i = 0; i < n; ++i) f[i] = std::cos(1.0 + i * x.sum()) - x[i];
    f -= c * ((c.dot(x + f) - t) / c.squaredNorm());
    x += mixer.increment(x, f);
    EXPECT_NEAR(c.dot(x), t, 1e-13) << "update " << k;
  }
}

// Where the history says nothing (repeated, parallel updates), the plain update comes back, never
// a NaN from a singular least-squares problem.
TEST(Anderson, ASingularHistoryGivesThePlainUpdate) {
  AndersonMixer mixer(3);
  Vector x = Vector::Zero(3), f = Vector::Ones(3);
  EXPECT_EQ(mixer.increment(x, f), f);
  EXPECT_EQ(mixer.increment(x, f), f);  // dX = dF = 0
  EXPECT_EQ(mixer.history(), 0);
  mixer.reset();
  EXPECT_EQ(mixer.increment(x, f), f);
}

// A history deeper than the dimension (depth 5 on a 2-unknown problem, as the chord of a
// one-unknown branch mixes (u, lambda)) keeps at most n differences: the least-squares matrix
// then has full column rank and the fit reaches the linear problem's solution in n + 1 updates.
TEST(Anderson, AHistoryDeeperThanTheDimensionKeepsAtMostNDifferences) {
  Eigen::Matrix2d A, M;
  A << 3.0, 1.0, -0.5, 2.0;
  M << 2.0, 0.0, 0.0, 3.0;  // chord iteration I - M^{-1} A has spectral radius 0.51
  const Eigen::Vector2d b(1.0, 2.0), x_star = A.partialPivLu().solve(b);
  AndersonMixer mixer(5);
  Vector x = Vector::Zero(2);
  for (int k = 0; k < 8; ++k) x += mixer.increment(x, M.partialPivLu().solve(b - A * x));
  EXPECT_LT((x - x_star).lpNorm<Eigen::Infinity>(), 1e-13);  // n + 1 = 3 updates, then rounding
}
