// The Jacobian of a problem that is an inner sparse problem bordered by a few dense rows and
// columns (an augmented problem: a curve of folds, Hopf points or events):
//   [ K    B ]   K (n_k x n_k, sparse), B and C dense n_k x m, D dense m x m,
//   [ C^T  D ]   the last m unknowns and equations the border,
// so that a solver may factorise K alone and eliminate the border with m more solves.
#pragma once

#include "core/Types.hpp"

namespace keller {

struct BorderedJacobian {
  SparseMatrix K;
  Matrix B, C, D;

  int inner_size() const { return static_cast<int>(K.rows()); }
  int border_size() const { return static_cast<int>(D.rows()); }
  // The whole matrix as one sparse matrix (its border columns and rows dense).
  SparseMatrix assembled() const;
  // eps max_i sum_j |A_ij| |u_j| of the whole matrix A (ConvergenceTest's rounding floor).
  double rounding_floor(const Vector& u) const;
};

}  // namespace keller
