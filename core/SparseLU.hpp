// Sparse LU factorisation by UMFPACK (SuiteSparse) or, where keller is built with it, MUMPS
// (sequential): the symbolic analysis (fill-reducing ordering) is done once for a sparsity pattern
// and reused for every numeric factorisation with that pattern, the speed floor of one numeric
// factorisation per Newton step. Failures (singular matrix, out of memory) come back as a Status,
// never as an abort.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/FillOrdering.hpp"
#include "core/Scene.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class LUBackend;

struct SparseLUOptions {
  // Auto: MUMPS where keller is built with it (it factorises the flow problems' matrices 2.5 to 4
  // times faster with less fill, docs/performance.md), UMFPACK otherwise or where an option only
  // UMFPACK has is asked for (strategy other than auto, ordering cholmod).
  enum class Backend { Auto, Umfpack, Mumps };
  enum class Ordering { Amd, Metis, Cholmod, Best };
  enum class Scaling { None, Sum, Max };
  enum class Strategy { Auto, Unsymmetric, Symmetric };
  Backend backend = Backend::Auto;
  Ordering ordering = Ordering::Amd;
  Scaling scaling = Scaling::Sum;
  Strategy strategy = Strategy::Auto;  // UMFPACK's; MUMPS factorises every matrix as unsymmetric
  double pivot_tolerance = 0.1;        // threshold partial pivoting (UMFPACK's and MUMPS's CNTL(1))
  // Threshold pivoting with a reused symbolic analysis can lose accuracy: on the cylinder mesh C3
  // an unrefined UMFPACK solve of the bordered system left a relative residual of 0.16 (tangents
  // 30 degrees off); two refinement steps bring it to 1.6e-11. A refined solve costs about 5 plain
  // ones, still 2% of the factorisation on C2 (43 ms against 8.5 s). Both backends stop refining
  // earlier when the componentwise backward error reaches rounding.
  int refinement_steps = 2;
};

const char* to_string(SparseLUOptions::Backend b);
const char* to_string(SparseLUOptions::Ordering o);
// Scene keys of [linear_solver] and reading them back (a SceneError naming linear_solver.backend
// for a combination the backend cannot do, or MUMPS asked for in a build without it).
void declare_linear_solver_keys(SceneSchema& schema);
SparseLUOptions sparse_lu_options_from(const Scene& scene);
SparseLUOptions::Backend backend_from_string(const std::string& s);    // throws on unknown
SparseLUOptions::Ordering ordering_from_string(const std::string& s);  // throws on unknown
SparseLUOptions::Strategy strategy_from_string(const std::string& s);  // throws on unknown
// Whether this build has the MUMPS backend (CMake found libmumps-seq-dev).
bool mumps_available();
// The backend that options.backend stands for in this build: Umfpack or Mumps. Throws
// std::invalid_argument naming the key where MUMPS is asked for but missing, or combined with an
// option only UMFPACK has.
SparseLUOptions::Backend resolved_backend(const SparseLUOptions& options);

class SparseLU {
 public:
  struct Statistics {
    std::string backend;  // "umfpack" or "mumps"
    int n = 0;
    long nnz_matrix = 0;
    double nnz_lu = 0;  // entries of L + U with diagonals (MUMPS: INFOG(29), its fronts' factor blocks)
    double flops = 0;   // of the last numeric factorisation
    // peak of the factorisation (UMFPACK: symbolic + numeric; MUMPS: INFOG(22), or the factors where larger)
    double peak_memory_bytes = 0;
    double numeric_bytes = 0;  // size of the factors
    double rcond = 0;          // UMFPACK's estimate of the reciprocal condition number (NaN: MUMPS makes none)
    double analyze_seconds = 0, factor_seconds = 0, solve_seconds = 0;  // cumulative wall time
    long analyses = 0, factorisations = 0, solves = 0;
    // symbolic analyses taken from an earlier one of the same pattern and options (UMFPACK shares
    // the analysis itself; MUMPS, which cannot share one between instances, repeats the analysis
    // with the ordering the earlier one chose, skipping the search of `best`)
    long analyses_reused = 0;
    std::string ordering_used;
    // the candidates `best` analysed with MUMPS, in turn, with their estimated flops (empty
    // otherwise: one ordering, UMFPACK's search, or an analysis taken from an earlier one)
    std::vector<OrderingTrial> ordering_trials;
  };

  explicit SparseLU(SparseLUOptions options = {});  // throws std::invalid_argument as resolved_backend
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  // Symbolic analysis of A's pattern (A's values guide the backend's strategy and pivoting choices).
  Status analyze(const SparseMatrix& A);
  // Numeric factorisation; analyses first if A's pattern differs from the analysed one.
  Status factorize(const SparseMatrix& A);
  // Solves A x = b (or A^T x = b) with the last factorisation; refinement_steps < 0: iterative
  // refinement as in the options, 0: a plain solve (for callers that refine a larger system
  // themselves).
  Status solve(const Vector& b, Vector& x, bool transpose = false, int refinement_steps = -1);
  // Plain solves (no refinement) of the columns of b at once, as iterative methods that correct
  // their own errors want: MUMPS reads its factors once for all of them, UMFPACK solves each.
  Status solve_columns(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, bool transpose = false);
  bool factorized() const;
  // Sign (+1, -1) and log|det| of the last factorised matrix.
  int determinant_sign() const { return det_sign_; }
  double log_abs_determinant() const { return log_abs_det_; }
  const Statistics& statistics() const { return stats_; }
  const SparseLUOptions& options() const { return options_; }

 private:
  bool same_pattern(const SparseMatrix& A) const;

  SparseLUOptions options_;
  std::unique_ptr<LUBackend> backend_;
  bool analysed_ = false;
  std::vector<int> outer_, inner_;  // pattern of the analysed matrix
  std::vector<double> values_;      // values of the factorised matrix (used by refinement)
  int det_sign_ = 0;
  double log_abs_det_ = 0.0;
  Statistics stats_;
};

}  // namespace keller
