// core/Gmres: a nonsymmetric system solved to the tolerance asked, the preconditioner applied once
// per iteration (its preconditioned basis kept: the solution is their combination, with no further
// application at the end, which for the shooting passes' few-iteration solves was a fifth of the
// sparse LU's solves).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "core/Gmres.hpp"
#include "core/Types.hpp"

using namespace keller;

TEST(Gmres, ReachesItsToleranceApplyingThePreconditionerOncePerIteration) {
  const int n = 40;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    A(i, i) = 4.0 + 0.1 * i;
    if (i + 1 < n) A(i, i + 1) = -1.0;
    if (i > 0) A(i, i - 1) = -2.0;  // nonsymmetric
  }
  const Eigen::VectorXd d = A.diagonal();
  Vector b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(1.0 + i);
  int applications = 0;
  auto apply = [&](const Vector& x) { return Vector(A * x); };
  auto jacobi = [&](const Vector& x) {
    ++applications;
    return Vector(x.cwiseQuotient(d));
  };
  for (double tol : {1e-4, 1e-10}) {
    applications = 0;
    Vector x;
    const GmresResult r = gmres(apply, jacobi, b, x, tol, 60);
    ASSERT_TRUE(r.converged) << tol;
    EXPECT_EQ(applications, r.iterations) << tol;
    // the estimate is the true residual up to rounding
    EXPECT_LE((b - A * x).norm(), tol * b.norm() * (1.0 + 1e-6)) << tol;
    EXPECT_NEAR((b - A * x).norm(), r.residual, 1e-12 * b.norm()) << tol;
  }
}
