// The bordered (extended) system of pseudo-arclength continuation,
//   [ J    b ] [x]   [f]
//   [ c^T  d ] [y] = [g],
// in one of two ways.
//  Full:  one sparse LU factorisation of the (n+1) x (n+1) matrix, which stays regular at folds
//         where J is singular. The dense border row and column cost fill, a lot of it with
//         nested-dissection orderings on large coupled problems.
//  Block: block elimination on a factorisation of J alone (x = J^-1 f - y J^-1 b,
//         y = (g - c.J^-1 f) / (d - c.J^-1 b)) with one step of iterative refinement on the whole
//         bordered system; where J is singular (at a fold itself), the Schur complement
//         d - c.J^-1 b vanishes, or a solve leaves a residual of the whole system above 1e-10
//         of its scale (J nearly singular), that factorisation falls back to the full matrix.
// The patterns are fixed, so each UMFPACK symbolic analysis is done once per branch.
#pragma once

#include <vector>

#include "core/SparseLU.hpp"
#include "core/Types.hpp"

namespace keller {

class BorderedSystem {
 public:
  enum class Mode { Full, Block };
  BorderedSystem(const SparseMatrix& jacobian_pattern, SparseLUOptions options, Mode mode = Mode::Full);

  int size() const { return n_; }  // n (the extended size is n + 1)
  // Values: J with the pattern given at construction, border column b, row c, corner d.
  void set(const SparseMatrix& J, const Vector& b, const Vector& c, double d);
  Status factorize();
  // Replaces the border row and corner (c, d) of the factorised system without refactorising J:
  // block mode only (the Schur complement is one dot product away); returns a non-ok status when
  // the system must be refactorised instead (full mode, no factorisation, vanishing Schur
  // complement). The chord corrector uses it to keep J's factorisation across steps.
  Status set_row(const Vector& c, double d);
  // True when a block factorisation is in use (what set_row needs).
  bool block_factorised() const { return block_ok_; }
  // refine: iterative refinement on the whole bordered system until its residual is below
  // 1e-10 of its scale (at most 3 steps; block mode), false: one elimination only (callers that
  // iterate themselves).
  Status solve(const Vector& f, double g, Vector& x, double& y, bool refine = true);
  // Sign of det of the last factorised extended matrix (block: det J times the Schur complement).
  int determinant_sign() const;
  const SparseMatrix& matrix() const { return A_; }
  // The factorisation in use: J's in block mode, the extended matrix's otherwise.
  const SparseLU& lu() const { return mode_ == Mode::Block ? lu_j_ : lu_; }
  // J's own factorisation (block mode, J regular), for others to solve with; null otherwise.
  SparseLU* j_factorisation() { return mode_ == Mode::Block && block_ok_ ? &lu_j_ : nullptr; }
  // Factorisations that fell back from block elimination to the full matrix.
  long fallbacks() const { return fallbacks_; }
  // Cumulative wall time of numeric factorisations and solves (both factorisations).
  double factor_seconds() const { return lu_.statistics().factor_seconds + lu_j_.statistics().factor_seconds; }
  double solve_seconds() const { return lu_.statistics().solve_seconds + lu_j_.statistics().solve_seconds; }
  long solves() const { return lu_.statistics().solves + lu_j_.statistics().solves; }

 private:
  Status solve_block(const Vector& f, double g, Vector& x, double& y);
  int n_;
  long nnz_j_;
  Mode mode_;
  SparseMatrix A_;
  SparseLU lu_;
  // block mode
  SparseMatrix J_;
  Vector b_, c_, x2_;
  double d_ = 0.0, schur_ = 0.0;
  SparseLU lu_j_;
  bool block_ok_ = false;  // the last factorize() took the block path
  long fallbacks_ = 0;
};

}  // namespace keller
