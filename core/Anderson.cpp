#include "core/Anderson.hpp"

#include <Eigen/QR>
#include <cmath>

namespace keller {

void AndersonMixer::reset() {
  dX_.clear();
  dF_.clear();
  x_prev_.resize(0);
  f_prev_.resize(0);
}

Vector AndersonMixer::increment(const Vector& x, const Vector& f) {
  if (depth_ <= 0) return f;
  if (x_prev_.size() != x.size()) {  // a new problem size: the differences of the old one mean nothing
    dX_.clear();
    dF_.clear();
  } else {
    dX_.push_back(x - x_prev_);
    dF_.push_back(f - f_prev_);
    // a least-squares fit over more differences than the dimension has no unique solution (and
    // R has only as many diagonal entries as rows): small problems keep at most n of them
    while (static_cast<int>(dF_.size()) > depth_ || static_cast<Eigen::Index>(dF_.size()) > f.size()) {
      dX_.pop_front();
      dF_.pop_front();
    }
  }
  x_prev_ = x;
  f_prev_ = f;
  // drop the oldest differences while the least-squares matrix is too ill-conditioned for its
  // solution to mean anything (near the solution the updates are rounding and nearly parallel).
  // Its columns are normalised first: they shrink with the updates, and R's diagonal would
  // then measure their lengths, not how nearly they depend on each other.
  while (!dF_.empty()) {
    const int m = static_cast<int>(dF_.size());
    Eigen::MatrixXd A(f.size(), m);
    Eigen::VectorXd norms(m);
    for (int j = 0; j < m; ++j) {
      norms(j) = dF_[j].norm();
      A.col(j) = norms(j) > 0 ? Vector(dF_[j] / norms(j)) : dF_[j];
    }
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(A);
    const Eigen::VectorXd d = qr.matrixQR().diagonal().head(m).cwiseAbs();
    if (d.minCoeff() > 1e-8 && norms.minCoeff() > 0) {
      const Eigen::VectorXd gamma = qr.solve(f).cwiseQuotient(norms);
      Vector step = f;
      for (int j = 0; j < m; ++j) step -= gamma(j) * (dX_[j] + dF_[j]);
      if (step.allFinite()) return step;
      break;
    }
    dX_.pop_front();
    dF_.pop_front();
  }
  return f;
}

void AndersonMixer::mix(const Vector& u, double l, Vector& du, double& dl) {
  if (depth_ <= 0) return;
  const Eigen::Index n = u.size();
  x_.resize(n + 1);
  f_.resize(n + 1);
  x_ << u, l;
  f_ << du, dl;
  const Vector inc = increment(x_, f_);
  du = inc.head(n);
  dl = inc(n);
}

}  // namespace keller
