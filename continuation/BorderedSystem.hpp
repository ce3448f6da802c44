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

#include <memory>
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
  // Block mode: takes J's factorisation made elsewhere (lu factorises J, a Jacobian with the
  // pattern given at construction, e.g. the last one of the Newton solve that found the start) with
  // border b, c, d; no numeric factorisation. A non-ok status where it cannot be used (full mode, a
  // vanishing Schur complement).
  Status adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& b, const Vector& c, double d);
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
  const SparseLU& lu() const { return mode_ == Mode::Block ? *lu_j_ : lu_; }
  // J's own factorisation (block mode, J regular), for others to solve with; null otherwise.
  SparseLU* j_factorisation() { return mode_ == Mode::Block && block_ok_ ? lu_j_.get() : nullptr; }
  // Factorisations that fell back from block elimination to the full matrix.
  long fallbacks() const { return fallbacks_; }
  // Cumulative wall time of numeric factorisations and solves made through this system (both
  // factorisations, and solves with an adopted one; not what that one did before).
  double factor_seconds() const { return totals().factor_seconds; }
  double solve_seconds() const { return totals().solve_seconds; }
  long solves() const { return totals().solves; }
  // Numeric factorisations, factorisation and solve seconds and solves made or used here (for the
  // mean times of the renewal cost).
  struct Totals {
    long factorisations = 0, solves = 0;
    double factor_seconds = 0, solve_seconds = 0;
  };
  Totals totals() const;

 private:
  Status solve_block(const Vector& f, double g, Vector& x, double& y);
  // Back to J's own factorisation object (its adopted statistics kept).
  void release_adopted();
  int n_;
  long nnz_j_;
  Mode mode_;
  SparseMatrix A_;
  SparseLU lu_;
  // block mode
  SparseMatrix J_;
  Vector b_, c_, x2_;
  double d_ = 0.0, schur_ = 0.0;
  // J's factorisation in use: its own (own_j_), or one adopted, whose statistics count from the
  // adoption on (adopted_base_; solves only: it is refactorised as our own)
  std::shared_ptr<SparseLU> own_j_, lu_j_;
  SparseLU::Statistics adopted_base_;
  long adopted_solves_ = 0;  // solves with earlier adopted factorisations
  double adopted_solve_seconds_ = 0;
  bool block_ok_ = false;  // the last factorize() took the block path
  long fallbacks_ = 0;
};

}  // namespace keller
