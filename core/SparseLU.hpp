// Sparse LU factorisation by UMFPACK (SuiteSparse): the symbolic analysis (fill-reducing
// ordering) is done once for a sparsity pattern and reused for every numeric factorisation
// with that pattern, the speed floor of one numeric factorisation per Newton step. Failures
// (singular matrix, out of memory) come back as a Status, never as an abort.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Scene.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

struct SparseLUOptions {
  enum class Ordering { Amd, Metis, Cholmod, Best };
  enum class Scaling { None, Sum, Max };
  enum class Strategy { Auto, Unsymmetric, Symmetric };
  Ordering ordering = Ordering::Amd;
  Scaling scaling = Scaling::Sum;
  Strategy strategy = Strategy::Auto;
  double pivot_tolerance = 0.1;  // UMFPACK's threshold partial pivoting
  // UMFPACK's threshold pivoting with a reused symbolic analysis can lose accuracy: on the
  // cylinder mesh C3 an unrefined solve of the bordered system left a relative residual of 0.16
  // (tangents 30 degrees off); two refinement steps bring it to 1.6e-11. A refined solve costs
  // about 5 plain ones, still 2% of the factorisation on C2 (43 ms against 8.5 s).
  int refinement_steps = 2;
};

const char* to_string(SparseLUOptions::Ordering o);
// Scene keys of [linear_solver] and reading them back.
void declare_linear_solver_keys(SceneSchema& schema);
SparseLUOptions sparse_lu_options_from(const Scene& scene);
SparseLUOptions::Ordering ordering_from_string(const std::string& s);  // throws on unknown
SparseLUOptions::Strategy strategy_from_string(const std::string& s);  // throws on unknown

class SparseLU {
 public:
  struct Statistics {
    int n = 0;
    long nnz_matrix = 0;
    double nnz_lu = 0;             // nonzeros in L + U (with diagonals)
    double flops = 0;              // of the last numeric factorisation
    double peak_memory_bytes = 0;  // UMFPACK's peak (symbolic + numeric)
    double numeric_bytes = 0;      // size of the factors
    double rcond = 0;              // UMFPACK's estimate of the reciprocal condition number
    double analyze_seconds = 0, factor_seconds = 0, solve_seconds = 0;  // cumulative wall time
    long analyses = 0, factorisations = 0, solves = 0;
    long analyses_reused = 0;  // symbolic analyses taken from an earlier identical one
    std::string ordering_used;
  };

  explicit SparseLU(SparseLUOptions options = {});
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  // Symbolic analysis of A's pattern (A's values guide UMFPACK's strategy choice).
  Status analyze(const SparseMatrix& A);
  // Numeric factorisation; analyses first if A's pattern differs from the analysed one.
  Status factorize(const SparseMatrix& A);
  // Solves A x = b (or A^T x = b) with the last factorisation; refinement_steps < 0: UMFPACK's
  // iterative refinement as in the options, 0: a plain solve (for callers that refine a larger
  // system themselves).
  Status solve(const Vector& b, Vector& x, bool transpose = false, int refinement_steps = -1);
  bool factorized() const { return numeric_ != nullptr; }
  // Sign (+1, -1) and log|det| of the last factorised matrix.
  int determinant_sign() const { return det_sign_; }
  double log_abs_determinant() const { return log_abs_det_; }
  const Statistics& statistics() const { return stats_; }
  const SparseLUOptions& options() const { return options_; }

 private:
  bool same_pattern(const SparseMatrix& A) const;
  void free_numeric();
  void free_symbolic();
  void set_control();

  SparseLUOptions options_;
  double control_[20];
  double info_[90];
  // shared: the last symbolic analysis is kept process-wide and reused by any SparseLU that
  // analyses the same pattern with the same controls (the first steady state's Newton solver,
  // the continuation's and the eigen-solver's factorisations of J: one analysis per run)
  std::shared_ptr<void> symbolic_;
  void* numeric_ = nullptr;
  std::vector<int> outer_, inner_;  // pattern of the analysed matrix
  std::vector<double> values_;      // values of the factorised matrix (used by refinement)
  int det_sign_ = 0;
  double log_abs_det_ = 0.0;
  Statistics stats_;
};

}  // namespace keller
