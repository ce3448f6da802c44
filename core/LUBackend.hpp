// What a sparse direct solver does for core/SparseLU: analyse a pattern, factorise values on it,
// solve with the factors, and report the determinant and its statistics. SparseLU keeps the
// matrix (pattern and values) alive between the calls and does the checks and the timing; a
// backend (core/UmfpackLU, core/MumpsLU) only talks to its library.
#pragma once

#include "core/SparseLU.hpp"
#include "core/Status.hpp"

namespace keller {

// An n x n matrix in compressed columns, 0-based, as Eigen stores it.
struct CscView {
  int n = 0;
  const int* outer = nullptr;  // n + 1 column starts
  const int* inner = nullptr;  // row of each entry
  const double* values = nullptr;
  long nnz() const { return outer[n]; }
};

class LUBackend {
 public:
  virtual ~LUBackend() = default;
  // Symbolic analysis of A's pattern (its values may guide the choices); `reused` is set where an
  // earlier analysis of the same pattern and options was taken (SparseLU::Statistics).
  virtual Status analyze(const CscView& A, bool& reused) = 0;
  // Numeric factorisation of A, whose pattern is the analysed one. Drops the previous factors.
  virtual Status factorize(const CscView& A) = 0;
  // x = A^-1 b (A^-T b) with the factors of A, the matrix last factorised; refinement_steps at
  // most, stopping where the backward error reaches rounding.
  virtual Status solve(const CscView& A, const double* b, double* x, bool transpose, int refinement_steps) = 0;
  // The plain solves (no refinement) of `count` right-hand sides stored one after another, n
  // entries each: by default one solve each; MUMPS takes them in one pass over its factors.
  virtual Status solve_several(const CscView& A, const double* b, double* x, int count, bool transpose) {
    for (int k = 0; k < count; ++k) {
      const long offset = static_cast<long>(k) * A.n;
      if (Status st = solve(A, b + offset, x + offset, transpose, 0); !st.is_ok()) return st;
    }
    return {};
  }
  virtual bool factorized() const = 0;
  // Sign (+1, -1; 0 where unknown) and log|det| of the last factorised matrix.
  virtual void determinant(int& sign, double& log_abs) const = 0;
  // Fills the backend's fields of the statistics: nnz_lu, flops, memory, rcond, ordering_used.
  virtual void report(SparseLU::Statistics& stats) const = 0;
};

}  // namespace keller
