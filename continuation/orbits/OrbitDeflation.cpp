#include "continuation/orbits/OrbitDeflation.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>

namespace keller {

OrbitDeflation OrbitDeflation::from(const std::vector<std::complex<double>>& multipliers,
                                    const std::vector<Eigen::VectorXcd>& vectors, int trivial) {
  OrbitDeflation d;
  if (vectors.size() != multipliers.size() || vectors.empty()) return d;
  const long n = vectors.front().size();
  // X: real columns spanning the kept vectors; L: M's action in them (M X = X L)
  std::vector<Vector> columns;
  std::vector<std::pair<int, std::complex<double>>> blocks;  // first column, multiplier
  for (size_t k = 0; k < multipliers.size(); ++k) {
    const std::complex<double> mu = multipliers[k];
    const Eigen::VectorXcd& x = vectors[k];
    if (static_cast<int>(k) == trivial || x.size() != n || std::abs(mu - 1.0) < kNearOne) continue;
    if (mu.imag() < 0.0) continue;  // a pair is taken whole at its first member (imag > 0)
    const int first = static_cast<int>(columns.size());
    if (mu.imag() > 0.0) {
      // M (a + i b) = (alpha + i beta)(a + i b): M a = alpha a - beta b, M b = beta a + alpha b
      columns.push_back(x.real());
      columns.push_back(x.imag());
    } else {
      // a real multiplier's vector is real up to a complex phase: its larger part
      columns.push_back(x.real().norm() >= x.imag().norm() ? Vector(x.real()) : Vector(x.imag()));
    }
    blocks.emplace_back(first, mu);
  }
  const int p = static_cast<int>(columns.size());
  if (p == 0) return d;
  Eigen::MatrixXd X(n, p), L = Eigen::MatrixXd::Zero(p, p);
  for (int j = 0; j < p; ++j) X.col(j) = columns[static_cast<size_t>(j)];
  for (const auto& [j, mu] : blocks) {
    if (mu.imag() > 0.0) {
      L(j, j) = mu.real();
      L(j + 1, j) = -mu.imag();
      L(j, j + 1) = mu.imag();
      L(j + 1, j + 1) = mu.real();
    } else {
      L(j, j) = mu.real();
    }
  }
  // X = Q R: M Q = Q (R L R^-1)
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(X);
  const Eigen::MatrixXd R = qr.matrixQR().topLeftCorner(p, p).triangularView<Eigen::Upper>();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(R);
  const auto& s = svd.singularValues();
  if (!(s[p - 1] > 0.0) || s[0] / s[p - 1] > kMaxCondition) return d;
  d.Q_ = qr.householderQ() * Eigen::MatrixXd::Identity(n, p);
  const Eigen::MatrixXd S = R * L * R.inverse();
  d.shifted_.compute(S - Eigen::MatrixXd::Identity(p, p));
  return d;
}

Vector OrbitDeflation::apply(const Vector& x) const {
  if (empty()) return x;
  const Vector c = Q_.transpose() * x;
  return Q_ * (shifted_.solve(c) + c) - x;
}

BorderedDeflation::BorderedDeflation(const OrbitDeflation* deflation, const Eigen::MatrixXd& C,
                                     const Eigen::MatrixXd& B, const Eigen::MatrixXd& D)
    : deflation_(deflation), W_(C.rows(), C.cols()), B_(B) {
  const long k = C.cols();
  if (B.cols() != k || D.rows() != k || D.cols() != k || B.rows() != C.rows())
    throw std::invalid_argument("bordered deflation: C, B and D do not fit");
  for (long j = 0; j < k; ++j) W_.col(j) = deflate(C.col(j));
  const Eigen::MatrixXd S = D - B.transpose() * W_;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(S);
  const auto& s = svd.singularValues();
  // S against the size of its terms (|S| <= scale): a cancellation to rounding is singular, whatever k
  const double scale = D.norm() + B.norm() * W_.norm();
  bordered_ = k > 0 && s[k - 1] > 0.0 && s[k - 1] * kMaxCondition >= scale;
  if (bordered_) schur_.compute(S);
}

Vector BorderedDeflation::apply(const Vector& r) const {
  const long n = W_.rows(), k = W_.cols();
  if (r.size() != n + k) throw std::invalid_argument("bordered deflation: a vector of the wrong size");
  Vector y = r;
  if (!bordered_) {  // as without the border
    if (deflated()) y.head(n) = deflation_->apply(r.head(n));
    return y;
  }
  const Vector pu = deflate(r.head(n));
  const Vector yb = schur_.solve(Vector(r.tail(k) - B_.transpose() * pu));
  y.head(n) = pu - W_ * yb;
  y.tail(k) = yb;
  return y;
}

}  // namespace keller
