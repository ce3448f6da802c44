// The eigenvalues of the linear stability problem J phi = sigma B phi nearest a shift s, by
// shift-invert Arnoldi (ARPACK, reverse communication). B du/dt = -F(u), so the growth rate is
// -sigma and a state is unstable when some eigenvalue has Re(sigma) < 0. B may be singular
// (algebraic rows: constraints, Dirichlet rows); its infinite eigenvalues are never reported.
#pragma once

#include <complex>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class ComplexSparseLU;

struct EigenOptions {
  int count = 6;                     // eigenvalues wanted, those nearest the shift
  std::complex<double> shift = 0.0;  // s; a complex s (Hopf detection) switches to complex arithmetic
  int ncv = 0;                       // Arnoldi basis size; 0: max(2 count + 1, 20) capped by n
  double tolerance = 1e-12;          // ARPACK's relative accuracy of the Ritz values of OP
  int max_restarts = 500;            // ARPACK's limit on implicit restarts
  // Relative residual ||J phi - sigma B phi|| / ((||J|| + |sigma| ||B||) ||phi||) above which a pair
  // is flagged (EigenPair::accurate false and a NotConverged status); matrix norms are
  // sqrt(||A||_1 ||A||_inf), an upper bound of the 2-norm.
  double residual_tolerance = 1e-8;
  bool vectors = false;  // return the eigenvectors (they are computed for the residuals anyway)
  // Vectors to start Arnoldi from (warm start), e.g. the eigenvectors of a nearby point: their sum
  // (real and imaginary parts) plus the fixed pseudo-random vector at `start_random_weight` of its
  // norm, so that directions outside them are still in the Krylov space. Empty: the random vector.
  std::vector<Eigen::VectorXcd> start;
  double start_random_weight = 0.1;
};

struct EigenPair {
  std::complex<double> value;  // sigma
  double residual = 0;         // relative residual as in EigenOptions::residual_tolerance
  bool accurate = true;        // residual <= residual_tolerance
  // phi (only when EigenOptions::vectors): unit 2-norm, largest entry real and positive
  Eigen::VectorXcd vector;
};

// Orders a spectrum by Re(sigma) ascending (the most unstable first); values whose real parts
// agree to rounding (a conjugate pair computed apart, whose real parts may differ in the last
// bits) by Im(sigma) ascending, so that a pair always reads (x - i omega, x + i omega).
void order_spectrum(std::vector<EigenPair>& pairs);

struct EigenResult {
  // Finite eigenvalues by Re(sigma) ascending, ties by Im(sigma): the most unstable first. Usually
  // `count` of them; one more when the real solver completes a conjugate pair at the end, fewer
  // when some converged Ritz values were infinite eigenvalues (the pencil may have fewer finite
  // eigenvalues than asked for) or when ARPACK did not converge.
  std::vector<EigenPair> pairs;
  int requested = 0;           // count
  int converged = 0;           // Ritz values ARPACK accepted (finite and infinite)
  int infinite_discarded = 0;  // converged Ritz values of OP at 0: infinite sigma, not in pairs
  int restarts = 0;            // Arnoldi update iterations ARPACK took
  long factorisations = 0;     // numeric LU factorisations done in this call
  long solves = 0;             // applications of (J - s B)^-1
  double seconds = 0;          // wall time of the call
};

// Shift-invert: OP = (J - s B)^-1 B in ARPACK's regular mode (bmat = 'I'), whose eigenvalues
// nu = 1 / (sigma - s) are largest for the sigma nearest s (which = "LM"); infinite sigma of a
// singular B are nu = 0, the end of the spectrum the iteration leaves alone. The start vector is
// OP applied to a fixed pseudo-random vector (the run is reproducible) so that it lies in the range
// of OP, and every Ritz vector is purified by one more application of OP (phi <- OP phi / nu),
// which removes components along the generalised null vectors of index-2 constraints. Ritz values
// with |nu| <= 1e3 eps max|nu| are infinite eigenvalues and are dropped.
// A real s uses dnaupd/dneupd and a real LU (core/SparseLU); a complex s uses znaupd/zneupd and a
// complex LU (UMFPACK's zi routines). The LUs keep their symbolic analyses between calls while the
// pattern of J - s B (the union of J's and B's patterns) does not change.
// ARPACK keeps state in Fortran SAVE variables: one solve at a time per process.
class EigenSolver {
 public:
  explicit EigenSolver(SparseLUOptions lu = {});
  ~EigenSolver();
  EigenSolver(const EigenSolver&) = delete;
  EigenSolver& operator=(const EigenSolver&) = delete;

  // The options.count eigenvalues of J phi = sigma B phi nearest options.shift (J, B: n x n,
  // B's zero rows are algebraic equations). If `factorised_j` is given, holds a factorisation of
  // this J (the caller's promise; e.g. Newton's last one) and the shift is 0, it is used for OP
  // instead of a new factorisation (out.factorisations == 0); it is ignored for a nonzero shift.
  // Returns a non-ok status, never aborts, for: bad sizes or options (InvalidState; count must be
  // in [1, n - 2], ncv in [count + 2, n]), a shift at an eigenvalue (SingularMatrix), ARPACK
  // errors and non-convergence (NotConverged: `out` holds the pairs that did converge) and pairs
  // whose residual is above options.residual_tolerance (NotConverged: the pairs are all in `out`);
  // B = 0 (InvalidState: there is no finite eigenvalue to start from).
  Status solve(const SparseMatrix& J, const SparseMatrix& B, const EigenOptions& options, EigenResult& out,
               SparseLU* factorised_j = nullptr);

 private:
  SparseLUOptions lu_options_;
  SparseLU real_lu_;
  std::unique_ptr<ComplexSparseLU> complex_lu_;  // made at the first complex shift
};

}  // namespace keller
