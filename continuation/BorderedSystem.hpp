// The bordered (extended) system of pseudo-arclength continuation,
//   [ J    b ] [x]   [f]
//   [ c^T  d ] [y] = [g],
// solved by one sparse LU factorisation of the (n+1) x (n+1) matrix. Factoring the whole
// matrix keeps it solvable at folds, where J is singular but the bordered matrix is not. The
// extended pattern (J's plus a dense last row and column) is fixed, so UMFPACK's symbolic
// analysis is done once per branch.
#pragma once

#include <vector>

#include "core/SparseLU.hpp"
#include "core/Types.hpp"

namespace keller {

class BorderedSystem {
 public:
  BorderedSystem(const SparseMatrix& jacobian_pattern, SparseLUOptions options);

  int size() const { return n_; }  // n (the extended size is n + 1)
  // Values: J with the pattern given at construction, border column b, row c, corner d.
  void set(const SparseMatrix& J, const Vector& b, const Vector& c, double d);
  Status factorize();
  Status solve(const Vector& f, double g, Vector& x, double& y);
  // Sign of det of the last factorised extended matrix.
  int determinant_sign() const { return lu_.determinant_sign(); }
  const SparseMatrix& matrix() const { return A_; }
  const SparseLU& lu() const { return lu_; }

 private:
  int n_;
  long nnz_j_;
  SparseMatrix A_;
  SparseLU lu_;
};

}  // namespace keller
