// The shooting Newton matrix's preconditioner from a neighbouring orbit's multipliers
// (continuation/orbits/OrbitDeflation), on matrices with known eigenpairs.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <complex>
#include <functional>
#include <iostream>
#include <stdexcept>
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

// trivial and damped: the first multiplier and the damped ones' spread; orthonormal: X's columns
// orthonormalised, M normal (with both 0, M - I is the deflation's P exactly)
Known known(int n = 60, double trivial = 1.0, double damped = 0.05, bool orthonormal = false) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Identity(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) X(i, j) += 0.3 * std::sin(1.0 + 0.7 * i + 1.3 * j * j);
  if (orthonormal) X = Eigen::HouseholderQR<Eigen::MatrixXd>(X).householderQ() * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  D(0, 0) = trivial;
  D(1, 1) = 0.95;
  D(2, 2) = 0.4;
  D(3, 3) = 0.3;
  D(3, 4) = 0.2;
  D(4, 3) = -0.2;
  D(4, 4) = 0.3;
  for (int i = 5; i < n; ++i) D(i, i) = damped * std::cos(2.0 * i);
  Known k;
  k.M = X * D * X.inverse();
  // X's columns 3, 4 = a, b with M a = 0.3 a - 0.2 b, M b = 0.2 a + 0.3 b: M (a + i b) = (0.3 + 0.2 i)(a + i b)
  const std::complex<double> i1(0.0, 1.0);
  k.multipliers = {trivial, 0.95, 0.4, {0.3, 0.2}, {0.3, -0.2}};
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

namespace {

// The shooting Newton matrix with a two-column border, as the corrector's on a branch: the
// period's column (the flow f, scaled), lambda's (a fixed vector), the phase row f^T and an
// arclength row with a corner.
struct Border {
  Eigen::MatrixXd C, B, D;
};

Border border_of(const Known& k) {
  const long n = k.M.rows();
  Border b{Eigen::MatrixXd(n, 2), Eigen::MatrixXd(n, 2), Eigen::MatrixXd(2, 2)};
  b.C.col(0) = 3.0 * k.vectors[0].real();
  for (long i = 0; i < n; ++i) {
    b.C(i, 1) = std::sin(0.3 * static_cast<double>(i)) + 0.5;
    b.B(i, 1) = 0.02 * std::cos(0.11 * static_cast<double>(i));
  }
  b.B.col(0) = k.vectors[0].real();
  b.D << 0.0, 0.0, 0.4, 0.7;
  return b;
}

std::function<Vector(const Vector&)> bordered_matrix(const Eigen::MatrixXd& M, const Border& b) {
  const long n = M.rows();
  return [M, b, n](const Vector& z) {
    Vector y(n + 2);
    y.head(n) = M * z.head(n) - z.head(n) + b.C * z.tail(2);
    y.tail(2) = b.B.transpose() * z.head(n) + b.D * z.tail(2);
    return y;
  };
}

}  // namespace

// Where P is M - I (M normal, the trivial and damped multipliers 0, the trivial one left out of the
// deflation as the corrector leaves it: P is -I there too), the bordered preconditioner is the
// Newton matrix's inverse: A P_b^-1 r = r to rounding, GMRES in one iteration.
TEST(BorderedDeflation, IsTheInverseWhereTheDeflationIsExact) {
  const Known k = known(60, 0.0, 0.0, true);
  const long n = k.M.rows();
  const OrbitDeflation d = OrbitDeflation::from(k.multipliers, k.vectors, k.trivial);
  ASSERT_EQ(d.size(), 4);
  const Border b = border_of(known());
  const BorderedDeflation p(&d, b.C, b.B, b.D);
  ASSERT_TRUE(p.bordered());
  const auto A = bordered_matrix(k.M, b);
  Vector r(n + 2);
  for (long i = 0; i < n + 2; ++i) r[i] = std::cos(0.37 * static_cast<double>(i));
  EXPECT_LT((A(p.apply(r)) - r).norm(), 1e-11 * r.norm());
  Vector x;
  const GmresResult g = gmres(
      A, [&](const Vector& z) { return p.apply(z); }, r, x, 1e-10, 10);
  EXPECT_TRUE(g.converged);
  EXPECT_EQ(g.iterations, 1);
}

// On the matrix of the tests above (damped multipliers in [-0.05, 0.05], the trivial one 1), the
// border in the preconditioner saves GMRES the border's directions: at least two iterations fewer
// than the deflation alone (block-diagonal), to the same true residual. Without the deflation
// (P = -I) the border alone saves them too.
TEST(BorderedDeflation, SavesGmresTheBordersIterations) {
  const Known k = known();
  const long n = k.M.rows();
  const OrbitDeflation d = OrbitDeflation::from(k.multipliers, k.vectors, k.trivial);
  const Border b = border_of(k);
  const auto A = bordered_matrix(k.M, b);
  Vector r(n + 2);
  for (long i = 0; i < n + 2; ++i) r[i] = std::cos(0.37 * static_cast<double>(i));
  auto iterations = [&](const std::function<Vector(const Vector&)>& P) {
    Vector x;
    const GmresResult g = gmres(A, P, r, x, 1e-10, 60);
    EXPECT_TRUE(g.converged);
    EXPECT_LT((A(x) - r).norm(), 1e-9 * r.norm());
    return g.iterations;
  };
  const int diagonal = iterations([&](const Vector& z) {
    Vector y = z;
    y.head(n) = d.apply(z.head(n));
    return y;
  });
  const BorderedDeflation with(&d, b.C, b.B, b.D);
  ASSERT_TRUE(with.bordered());
  const int bordered = iterations([&](const Vector& z) { return with.apply(z); });
  const BorderedDeflation alone(nullptr, b.C, b.B, b.D);
  const int plain = iterations([](const Vector& z) { return z; });
  const int border_only = iterations([&](const Vector& z) { return alone.apply(z); });
  std::cout << "GMRES iterations: " << plain << " plain, " << border_only << " border only, " << diagonal
            << " deflated, " << bordered << " deflated and bordered\n";
  EXPECT_LE(bordered, diagonal - 2);
  EXPECT_LE(border_only, plain - 2);
}

// A singular Schur complement leaves the border out: the deflation's block-diagonal preconditioner,
// exactly (and the identity on the state without a deflation, as before the border). Singular to
// rounding with k = 1 (the border's row orthogonal to what P^-1 makes of its column, a zero
// corner), and of rank 1 with k = 2 (two equal columns: the smallest singular value decides, not
// the largest).
TEST(BorderedDeflation, ASingularSchurComplementLeavesTheBorderOut) {
  const Known k = known();
  const long n = k.M.rows();
  const OrbitDeflation d = OrbitDeflation::from(k.multipliers, k.vectors, k.trivial);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 1), B(n, 1), D = Eigen::MatrixXd::Zero(1, 1);
  C(0, 0) = 1.0;
  const Vector w = d.apply(C.col(0));
  B.col(0) = Vector::Ones(n) - (w.dot(Vector::Ones(n)) / w.squaredNorm()) * w;
  const BorderedDeflation p(&d, C, B, D);
  EXPECT_FALSE(p.bordered());
  Vector r(n + 1);
  for (long i = 0; i <= n; ++i) r[i] = std::sin(0.9 * static_cast<double>(i));
  const Vector y = p.apply(r);
  EXPECT_EQ(y.head(n), d.apply(r.head(n)));
  EXPECT_EQ(y[n], r[n]);
  // without a deflation: the identity
  const OrbitDeflation none;
  const Vector w0 = -C.col(0);
  B.col(0) = Vector::Ones(n) - (w0.dot(Vector::Ones(n)) / w0.squaredNorm()) * w0;
  const BorderedDeflation q(&none, C, B, D);
  EXPECT_FALSE(q.bordered());
  EXPECT_EQ(q.apply(r), r);
  // k = 2, rank 1
  const Border b = border_of(k);
  Eigen::MatrixXd C2 = b.C;
  C2.col(1) = C2.col(0);
  const BorderedDeflation rank1(&d, C2, b.B, Eigen::MatrixXd::Zero(2, 2));
  EXPECT_FALSE(rank1.bordered());
  EXPECT_TRUE(BorderedDeflation(&d, b.C, b.B, Eigen::MatrixXd::Zero(2, 2)).bordered());
  EXPECT_THROW(p.apply(Vector::Zero(n)), std::invalid_argument);
  EXPECT_THROW(BorderedDeflation(&d, C, Eigen::MatrixXd::Zero(n, 2), D), std::invalid_argument);
}
