// The state block of the shooting Newton matrix's preconditioner (OrbitCorrector; inside
// BorderedDeflation below), from a neighbouring orbit's Floquet multipliers. GMRES on M - I pays
// about one iteration per multiplier away from 0 (OrbitCorrector.hpp); those a neighbouring orbit
// has already computed, with their vectors, give M's action on their invariant subspace for free:
// with Q an orthonormal basis of it and S = Q^T M Q (from the multipliers and vectors, no pass),
//   P = Q (S - I) Q^T - (I - Q Q^T),   P^-1 x = Q (S - I)^-1 Q^T x - (x - Q Q^T x),
// which is M - I on the subspace and -I (where M's damped modes put M - I) off it. Then
// (M - I) P^-1 is the identity on the subspace up to how far the orbit has moved since, and GMRES
// is left with the multipliers the neighbour did not compute. The trivial multiplier (the flow
// direction, which the phase condition handles) stays out, and so does any within kNearOne of 1,
// where (S - I)^-1 would amplify the neighbour's error (a fold of cycles).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <complex>
#include <vector>

#include "core/Types.hpp"

namespace keller {

class OrbitDeflation {
 public:
  static constexpr double kNearOne = 1e-3;
  // Where the basis of the kept vectors is this ill-conditioned (nearly parallel eigenvectors of a
  // non-normal M), no deflation.
  static constexpr double kMaxCondition = 1e8;

  OrbitDeflation() = default;
  // From multipliers (a conjugate pair together), a vector of each (M x = mu x) and the trivial
  // one's index; multipliers without a vector of the right size are left out.
  static OrbitDeflation from(const std::vector<std::complex<double>>& multipliers,
                             const std::vector<Eigen::VectorXcd>& vectors, int trivial);
  bool empty() const { return Q_.cols() == 0; }
  // the dimension of the deflated subspace (a pair counts two)
  int size() const { return static_cast<int>(Q_.cols()); }
  // P^-1 x; where empty, x itself (not -x: BorderedDeflation takes -I for P then)
  Vector apply(const Vector& x) const;

 private:
  Eigen::MatrixXd Q_;
  Eigen::PartialPivLU<Eigen::MatrixXd> shifted_;  // S - I
};

// The shooting Newton matrix's border around the deflation (OrbitCorrector): GMRES's right
// preconditioner
//   P_b = [P, C; B^T, D]
// with P the deflation's (P^-1 = OrbitDeflation::apply; -I, the damped modes' M - I, without one),
// C the columns of the border's unknowns (the period's, T dPhi/dT ~ T f(Phi); lambda's, dPhi/dlambda),
// B^T its rows (the phase, and the row that closes the system), D their corner. The border is
// exact in P_b: (M - I, C; B^T, D) P_b^-1 differs from the identity only where M - I differs from P,
// so GMRES no longer spends iterations on the border's few directions. Block elimination on the
// Schur complement S = D - B^T P^-1 C (k x k, k = 1 or 2): P^-1 C once, then one P^-1 per application.
class BorderedDeflation {
 public:
  // Where S's smallest singular value is below 1 / kMaxCondition of the size of its terms
  // (|D| + |B| |P^-1 C|, which bounds its largest: ill-conditioned or a cancellation), the border is
  // left out: the deflation alone on the state, the identity on the border (as without one).
  // Beyond it the border's elimination would lose more digits than GMRES's products carry
  // (OrbitDeflation's basis has the same bound).
  static constexpr double kMaxCondition = 1e8;
  // deflation (null: none, P = -I) must outlive this object; C: N x k, B: N x k, D: k x k
  BorderedDeflation(const OrbitDeflation* deflation, const Eigen::MatrixXd& C, const Eigen::MatrixXd& B,
                    const Eigen::MatrixXd& D);
  // whether the border is in (S well conditioned)
  bool bordered() const { return bordered_; }
  // P_b^-1 r for r of size N + k
  Vector apply(const Vector& r) const;

 private:
  bool deflated() const { return deflation_ && !deflation_->empty(); }
  Vector deflate(const Vector& x) const { return deflated() ? deflation_->apply(x) : Vector(-x); }
  const OrbitDeflation* deflation_;
  Eigen::MatrixXd W_, B_;  // P^-1 C, B
  Eigen::FullPivLU<Eigen::MatrixXd> schur_;
  bool bordered_ = false;
};

}  // namespace keller
