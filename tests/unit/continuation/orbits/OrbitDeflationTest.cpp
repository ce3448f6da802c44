// The shooting Newton matrix's preconditioner from a neighbouring orbit's multipliers
// (continuation/orbits/OrbitDeflation), on matrices with known eigenpairs.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <vector>

#include "continuation/orbits/OrbitDeflation.hpp"
#include "core/Gmres.hpp"

using namespace keller;

namespace {

// M = X D X^-1, n = 60: the trivial multiplier 1, a real 0.95 (an amplitude's, near a Hopf
// point), 0.4, a pair 0.3 +- 0.2i in a 2 x 2 block, and 55 damped ones in [-0.05, 0.05]; X a fixed
// non-orthogonal basis (M is not normal).
struct Known {
  Eigen::MatrixXd M;
  std::vector<std::complex<double>> multipliers;
  std::vector<Eigen::VectorXcd> vectors;
  int trivial = 0;
};

Known known(int n = 60) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) X(i, j) += 0.3 * std::sin(1.0 + 0.7 * i + 1.3 * j * j);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  D(0, 0) = 1.0;
  D(1, 1) = 0.95;
  D(2, 2) = 0.4;
  D(3, 3) = 0.3;
  D(3, 4) = 0.2;
  D(4, 3) = -0.2;
  D(4, 4) = 0.3;
  for (int i = 5; i < n; ++i) D(i, i) = 0.05 * std::cos(2.0 * i);
  Known k;
  k.M = X * D * X.inverse();
  // X's columns 3, 4 = a, b with M a = 0.3 a - 0.2 b, M b = 0.2 a + 0.3 b: M (a + i b) = (0.3 + 0.2 i)(a + i b)
  const std::complex<double> i1(0.0, 1.0);
  k.multipliers = {1.0, 0.95, 0.4, {0.3, 0.2}, {0.3, -0.2}};
  k.vectors = {X.col(0).cast<std::complex<double>>(), (i1 * X.col(1)).normalized(),  // a real one's phase
               X.col(2).cast<std::complex<double>>(),
               (X.col(3).cast<std::complex<double>>() + i1 * X.col(4)).normalized(),
               (X.col(3).cast<std::complex<double>>() - i1 * X.col(4)).normalized()};
  k.trivial = 0;
  return k;
}

}  // namespace

// (M - I) P^-1 is the identity on the deflated subspace (0.95, 0.4 and the pair: 4 dimensions),
// and P^-1 is -I off it; the trivial multiplier is left out.
TEST(OrbitDeflation, MMinusIOnTheSubspaceAndMinusIOffIt) {
  const Known k = known();
  const OrbitDeflation d = OrbitDeflation::from(k.multipliers, k.vectors, k.trivial);
  ASSERT_EQ(d.size(), 4);
  const long n = k.M.rows();
  const Eigen::MatrixXd A = k.M - Eigen::MatrixXd::Identity(n, n);
  for (int j : {1, 2}) {  // the real multipliers' vectors
    const Vector x = k.vectors[static_cast<size_t>(j)].real() + k.vectors[static_cast<size_t>(j)].imag();
    EXPECT_LT((A * d.apply(x) - x).norm(), 1e-12 * x.norm()) << j;
  }
  for (const Vector& x : {Vector(k.vectors[3].real()), Vector(k.vectors[3].imag())})
    EXPECT_LT((A * d.apply(x) - x).norm(), 1e-12 * x.norm());
  // off the subspace: the trivial vector's component orthogonal to it
  Eigen::MatrixXd basis(n, 4);
  basis << k.vectors[1].imag(), k.vectors[2].real(), k.vectors[3].real(), k.vectors[3].imag();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(basis);
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, 4);
  Vector z = k.vectors[0].real();
  z -= Q * (Q.transpose() * z);
  EXPECT_LT((d.apply(z) + z).norm(), 1e-12 * z.norm());
}

// GMRES on M - I (bordered by a phase row, as the corrector's) needs an iteration for each of the
// four multipliers away from 0 besides the damped cluster; with the deflation from the exact
// vectors it needs at least three fewer, and with vectors of a neighbouring M (the multipliers 2%
// off, the vectors perturbed by 1e-3) still at least two fewer, to the same residual.
TEST(OrbitDeflation, GmresOnTheBorderedShootingMatrixTakesFewerIterations) {
  const Known k = known();
  const long n = k.M.rows();
  const Vector f = k.vectors[0].real();  // the flow: M f = f
  auto bordered = [&](const Eigen::MatrixXd& M) {
    return [&, M](const Vector& z) {
      Vector y(n + 1);
      y.head(n) = M * z.head(n) - z.head(n) + z[n] * Vector::Ones(n);
      y[n] = f.dot(z.head(n));
      return y;
    };
  };
  Vector b(n + 1);
  for (long i = 0; i <= n; ++i) b[i] = std::cos(0.37 * static_cast<double>(i));
  auto with = [&](const OrbitDeflation& d) {
    return [&d, n](const Vector& z) {
      Vector y = z;
      y.head(n) = d.apply(z.head(n));
      return y;
    };
  };
  const auto A = bordered(k.M);
  Vector x;
  const GmresResult plain = gmres(
      A, [](const Vector& z) { return z; }, b, x, 1e-10, 60);
  ASSERT_TRUE(plain.converged);
  const OrbitDeflation exact = OrbitDeflation::from(k.multipliers, k.vectors, k.trivial);
  Vector xe;
  const GmresResult deflated = gmres(A, with(exact), b, xe, 1e-10, 60);
  ASSERT_TRUE(deflated.converged);
  EXPECT_LT((A(xe) - b).norm(), 1e-9 * b.norm());
  // a neighbour's
  std::vector<std::complex<double>> moved = k.multipliers;
  for (size_t i = 1; i < moved.size(); ++i) moved[i] *= 1.02;
  std::vector<Eigen::VectorXcd> near = k.vectors;
  for (size_t i = 0; i < near.size(); ++i)
    for (long r = 0; r < n; ++r) near[i][r] += 1e-3 * std::sin(3.0 * static_cast<double>(r + i));
  const OrbitDeflation neighbour = OrbitDeflation::from(moved, near, k.trivial);
  Vector xn;
  const GmresResult nearby = gmres(A, with(neighbour), b, xn, 1e-10, 60);
  ASSERT_TRUE(nearby.converged);
  EXPECT_LT((A(xn) - b).norm(), 1e-9 * b.norm());
  std::cout << "GMRES iterations: " << plain.iterations << " plain, " << deflated.iterations << " deflated, "
            << nearby.iterations << " deflated by a neighbour's\n";
  EXPECT_LE(deflated.iterations, plain.iterations - 3);
  EXPECT_LE(nearby.iterations, plain.iterations - 2);
}

// What is left out: the trivial multiplier, one within kNearOne of 1 (a fold of cycles, where
// (S - I)^-1 would amplify the neighbour's error), vectors missing; a pair counts two.
TEST(OrbitDeflation, LeavesOutTheTrivialAndThoseNearOne) {
  const Known k = known();
  std::vector<std::complex<double>> mu = k.multipliers;
  mu[1] = 1.0 - 0.5 * OrbitDeflation::kNearOne;
  EXPECT_EQ(OrbitDeflation::from(mu, k.vectors, k.trivial).size(), 3);
  mu[1] = 1.0 - 2.0 * OrbitDeflation::kNearOne;
  EXPECT_EQ(OrbitDeflation::from(mu, k.vectors, k.trivial).size(), 4);
  EXPECT_EQ(OrbitDeflation::from(k.multipliers, k.vectors, 2).size(), 3);  // 0.4 named trivial: 0.95 and the pair
  EXPECT_TRUE(OrbitDeflation::from(k.multipliers, {}, k.trivial).empty());
  const std::vector<std::complex<double>> only_trivial = {1.0};
  EXPECT_TRUE(OrbitDeflation::from(only_trivial, {k.vectors[0]}, 0).empty());
  // parallel vectors: no deflation rather than a singular basis
  std::vector<Eigen::VectorXcd> parallel = k.vectors;
  parallel[2] = parallel[1];
  EXPECT_TRUE(OrbitDeflation::from(k.multipliers, parallel, k.trivial).empty());
  const Vector x = Vector::LinSpaced(k.M.rows(), -1.0, 1.0);
  EXPECT_EQ(OrbitDeflation().apply(x), x);  // empty: the identity
}
