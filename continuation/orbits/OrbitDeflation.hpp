// A right preconditioner for the shooting Newton matrix from a neighbouring orbit's Floquet
// multipliers (OrbitCorrector). GMRES on M - I pays about one iteration per multiplier away from 0
// (OrbitCorrector.hpp); those a neighbouring orbit has already computed, with their vectors, give
// M's action on their invariant subspace for free: with Q an orthonormal basis of it and
// S = Q^T M Q (from the multipliers and vectors, no pass),
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
  // P^-1 x (x itself where empty)
  Vector apply(const Vector& x) const;

 private:
  Eigen::MatrixXd Q_;
  Eigen::PartialPivLU<Eigen::MatrixXd> shifted_;  // S - I
};

}  // namespace keller
