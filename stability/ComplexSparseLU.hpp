// Sparse LU factorisation of a complex matrix by UMFPACK's umfpack_zi_* routines (real and
// imaginary parts in separate arrays), for shift-invert at a complex shift s, where J - s B is
// complex although J and B are real. Same contract as core/SparseLU: the symbolic analysis is
// kept while the pattern does not change, failures come back as a Status, never as an abort.
// UMFPACK whatever linear_solver.backend says: complex shifts (Hopf points and curves) are a small
// share of a run's factorisations, and MUMPS's complex arithmetic (zmumps) is not wired in.
#pragma once

#include <complex>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/UmfpackLU.hpp"

namespace keller {

class ComplexSparseLU {
 public:
  using ComplexVector = Eigen::VectorXcd;
  using ComplexSparseMatrix = Eigen::SparseMatrix<std::complex<double>, Eigen::ColMajor, int>;

  // Ordering, scaling, strategy, pivot tolerance and refinement steps as for the real LU (the
  // backend is ignored).
  explicit ComplexSparseLU(SparseLUOptions options = {});
  ~ComplexSparseLU();
  ComplexSparseLU(const ComplexSparseLU&) = delete;
  ComplexSparseLU& operator=(const ComplexSparseLU&) = delete;

  // Numeric factorisation of A (compressed, square); analyses first if A's pattern differs from
  // the analysed one.
  Status factorize(const ComplexSparseMatrix& A);
  // Solves A x = b with the last factorisation (with the options' iterative refinement).
  Status solve(const ComplexVector& b, ComplexVector& x);
  bool factorized() const { return numeric_ != nullptr; }
  long analyses() const { return analyses_; }
  long factorisations() const { return factorisations_; }

 private:
  bool same_pattern(const ComplexSparseMatrix& A) const;
  Status analyze(const ComplexSparseMatrix& A);
  void free_numeric();
  void free_symbolic();

  double control_[kUmfpackControlSize];
  double info_[90];
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  int n_ = 0;
  std::vector<int> outer_, inner_;   // pattern of the analysed matrix
  std::vector<double> real_, imag_;  // values of the factorised matrix (used by refinement)
  long analyses_ = 0, factorisations_ = 0;
};

}  // namespace keller
