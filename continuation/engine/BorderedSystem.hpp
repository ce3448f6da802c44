// The bordered (extended) system of pseudo-arclength continuation,
//   [ J    b ] [x]   [f]
//   [ c^T  d ] [y] = [g],
// in one of two ways.
//  Full:  one sparse LU factorisation of the (N+1) x (N+1) matrix, which stays regular at folds
//         where J is singular. The dense border row and column cost fill, a lot of it with
//         nested-dissection orderings on large coupled problems.
//  Block: block elimination on a factorisation of the inner sparse matrix alone with one step of
//         iterative refinement on the whole bordered system; where that matrix is singular, the
//         Schur complement of the borders vanishes, or a solve leaves a residual of the whole
//         system above 1e-10 of its scale (a nearly singular inner matrix), that factorisation
//         falls back to the full matrix.
// J is the problem's Jacobian or, for a problem with a border of its own (an augmented problem,
// core/BorderedJacobian.hpp: J = [K B; C^T D]), K bordered by m dense columns and rows. Then all
// k = m + 1 borders (the problem's and the continuation's row) are eliminated together on K's
// factorisation: X = K^-1 [B b_K] (k solves per factorisation), the k x k Schur complement
// S = [D b_m; c_m^T d] - [C c_K]^T X, and one solve with K per right-hand side:
//   x_K = K^-1 f_K - X z,   z = S^-1 ((f_m, g) - [C c_K]^T K^-1 f_K),   (x_m, y) = z.
// The patterns are fixed, so each UMFPACK symbolic analysis is done once per branch.
#pragma once

#include <Eigen/LU>
#include <memory>
#include <vector>

#include "core/BorderedJacobian.hpp"
#include "core/SparseLU.hpp"
#include "core/Types.hpp"

namespace keller {

class BorderedSystem {
 public:
  enum class Mode { Full, Block };
  // inner_pattern: the pattern of J (a problem without a border of its own, borders = 0) or of K
  // (an augmented problem with borders = m > 0 border unknowns).
  BorderedSystem(const SparseMatrix& inner_pattern, int borders, SparseLUOptions options, Mode mode = Mode::Full);
  BorderedSystem(const SparseMatrix& jacobian_pattern, SparseLUOptions options, Mode mode = Mode::Full)
      : BorderedSystem(jacobian_pattern, 0, options, mode) {}

  int size() const { return n_; }  // N, the problem's unknowns (the extended size is N + 1)
  int problem_borders() const { return m_; }
  // Values: J with the pattern given at construction (no border of its own), border column b, row
  // c (empty: zero), corner d.
  void set(const SparseMatrix& J, const Vector& b, const Vector& c, double d);
  // The same for a problem with a border of its own: J in bordered form (K with the inner pattern).
  void set(const BorderedJacobian& J, const Vector& b, const Vector& c, double d);
  Status factorize();
  // Block mode, no border of the problem's own: takes J's factorisation made elsewhere (lu
  // factorises J, a Jacobian with the pattern given at construction, e.g. the last one of the
  // Newton solve that found the start) with border b, c, d; no numeric factorisation. A non-ok
  // status where it cannot be used (full mode, a problem border, a vanishing Schur complement).
  Status adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& b, const Vector& c, double d);
  // The same for a problem with a border: lu factorises J.K (another point's inner matrix, kept
  // as the system's), the border J.B, J.C, J.D is the new point's.
  Status adopt(std::shared_ptr<SparseLU> lu, const BorderedJacobian& J, const Vector& b, const Vector& c, double d);
  // The inner matrix's factorisation in use and the matrix (block mode; for another system to adopt).
  std::shared_ptr<SparseLU> inner_lu() const { return lu_j_; }
  const SparseMatrix& inner_matrix() const { return K_; }
  // Replaces the border row and corner (c, d) of the factorised system without refactorising J:
  // block mode only (the Schur complement is k dot products away); returns a non-ok status when
  // the system must be refactorised instead (full mode, no factorisation, vanishing Schur
  // complement). The chord corrector uses it to keep J's factorisation across steps.
  Status set_row(const Vector& c, double d);
  // True when a block factorisation is in use (what set_row needs).
  bool block_factorised() const { return block_ok_; }
  // refine: iterative refinement on the whole bordered system until its residual is below
  // 1e-10 of its scale (at most 3 steps; block mode), false: one elimination only (callers that
  // iterate themselves).
  Status solve(const Vector& f, double g, Vector& x, double& y, bool refine = true);
  // Sign of det of the last factorised extended matrix (block: det of the inner matrix times
  // det of the Schur complement).
  int determinant_sign() const;
  // The whole extended matrix (kept up to date in both modes).
  const SparseMatrix& matrix() const { return A_; }
  // The factorisation in use: the inner matrix's in block mode, the extended matrix's otherwise.
  const SparseLU& lu() const { return mode_ == Mode::Block ? *lu_j_ : lu_; }
  // J's own factorisation (block mode, J regular, no border of the problem's own), for others to
  // solve with; null otherwise.
  SparseLU* j_factorisation() { return mode_ == Mode::Block && block_ok_ && m_ == 0 ? lu_j_.get() : nullptr; }
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
  // A_'s values from K_, Bt_, Ct_, Dt_.
  void fill();
  // The continuation's row (c, d) into Ct_ and Dt_ (c empty: zero).
  void set_last_row(const Vector& c, double d);
  // The Schur complement from X_ and its LU; false where it vanishes (block elimination unusable).
  bool schur();
  // Takes lu as the inner factorisation (the values set already) and eliminates the borders on it.
  Status adopt_inner(std::shared_ptr<SparseLU> lu);
  // X_ = K^-1 Bt_ on the inner factorisation in use.
  Status solve_borders();
  Status solve_block(const Vector& f, double g, Vector& x, double& y);
  // Back to J's own factorisation object (its adopted statistics kept).
  // take_over: the adopted one becomes our own instead.
  void release_adopted(bool take_over = false);
  int nk_, m_, n_;  // inner size, the problem's borders, nk_ + m_
  long nnz_k_;
  Mode mode_;
  SparseMatrix A_;
  SparseLU lu_;
  // the blocks: K_ inner, Bt_ = [B b_K], Ct_ = [C c_K] (nk x k), Dt_ = [D b_m; c_m^T d] (k x k)
  SparseMatrix K_;
  Matrix Bt_, Ct_, Dt_;
  // block mode: X_ = K^-1 Bt_, the Schur complement S_ = Dt_ - Ct_^T X_ and its factors
  Matrix X_, S_;
  Eigen::FullPivLU<Matrix> S_lu_;
  // J's factorisation in use: its own (own_j_), or one adopted, whose statistics count from the
  // adoption on (adopted_base_; solves only: it is refactorised as our own). An adopted one that
  // nobody else holds any more becomes our own at the next factorisation (its symbolic analysis
  // kept), its statistics counted from then on (own_base_).
  std::shared_ptr<SparseLU> own_j_, lu_j_;
  SparseLU::Statistics adopted_base_, own_base_;
  long adopted_solves_ = 0;  // solves with earlier adopted factorisations (and an earlier own one's)
  double adopted_solve_seconds_ = 0;
  long earlier_own_factorisations_ = 0;  // with own factorisation objects given up for one taken over
  double earlier_own_factor_seconds_ = 0;
  bool block_ok_ = false;  // the last factorize() took the block path
  long fallbacks_ = 0;
};

}  // namespace keller
