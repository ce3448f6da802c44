// Global assembly of residuals, Jacobians and parameter derivatives from a list of Terms into
// a sparsity pattern computed once. Strong terms own their rows; weak contributions to an owned
// row are dropped, or added to another row when redirected (redirect_row). The pattern always
// holds the full diagonal, so shifted matrices J - s B and bordered systems share it.
#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "core/Term.hpp"
#include "core/Types.hpp"

namespace keller {

class Assembler {
 public:
  struct Timing {
    double residual_seconds = 0.0;
    double jacobian_seconds = 0.0;
    double parameter_seconds = 0.0;
    long residual_calls = 0;
    long jacobian_calls = 0;
    long parameter_calls = 0;
  };

  // n: number of global unknowns. redirects: (from, to) pairs; the weak contributions to row
  // `from` (which a strong term must own) are added to row `to`. Throws std::invalid_argument on
  // rows owned twice, redirects of unowned rows, or dofs out of range.
  Assembler(int n, std::vector<std::shared_ptr<const Term>> terms, std::vector<std::pair<int, int>> redirects = {});

  int size() const { return n_; }
  // The Jacobian's sparsity pattern (values zero).
  const SparseMatrix& pattern() const { return pattern_; }
  // Position of entry (row, col) in the pattern's value array, or -1.
  int position(int row, int col) const;

  Status residual(const Vector& u, Vector& F) const;
  // J must have been copied from pattern() (same structure).
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) const;
  // dF/dp for parameter index p.
  Status parameter_derivative(int p, const Vector& u, Vector& dF) const;
  // The weak (integrated) terms alone, each row kept where it was assembled (no strong rows,
  // no redirects): at a Dirichlet row this is the reaction, the consistent boundary traction.
  Status weak_residual(const Vector& u, Vector& F) const;
  // Mass matrix B of B du/dt = -F (structure of pattern()); rows owned by strong terms are zero
  // unless the term itself has time terms.
  Status mass_matrix(const Vector& u, SparseMatrix& B) const;
  // The time terms B(u) udot, assembled like the residual (redirects included) from each term's
  // rate(): no matrix is formed.
  Status time_residual(const Vector& u, const Vector& udot, Vector& R) const;
  // G = F(u) + B(u) udot in one pass over the items: residual_with_rate of the terms with time
  // terms (a kernel may share what its residual and its rate both compute), residual of the rest.
  // Equal to residual + time_residual up to the order of the sums.
  Status time_dependent_residual(const Vector& u, const Vector& udot, Vector& G) const;

  // D^k F[d_1, ..., d_k] (k = du.size(), 2 or 3) from the terms' directional derivatives (every
  // term must offer them: has_directional_derivatives()); du[j] over the unknowns, dp[j] over the
  // parameters, each possibly null (no change).
  Status directional_derivative(const Vector& u, const std::vector<const Vector*>& du,
                                const std::vector<const Vector*>& dp, Vector& out) const;
  bool has_directional_derivatives() const;

  const Timing& timing() const { return timing_; }
  void reset_timing() { timing_ = {}; }
  const std::vector<std::shared_ptr<const Term>>& terms() const { return terms_; }
  // Row that receives weak contributions meant for row r (r itself, another row, or -1).
  int row_target(int r) const { return target_[r]; }
  bool row_owned(int r) const { return owned_[r] >= 0; }

 private:
  int destination(bool owns_rows, int dof) const { return owns_rows ? dof : target_[dof]; }
  using LocalVector = std::function<Status(const Term&, int item, const double* u_local, double* r_local)>;
  // Sums a per-item local vector (residual, dF/dp) into out.
  Status assemble_vector(const Vector& u, Vector& out, const LocalVector& local) const;
  int n_;
  std::vector<std::shared_ptr<const Term>> terms_;
  std::vector<int> target_;
  std::vector<int> owned_;  // index of the owning strong term, or -1
  SparseMatrix pattern_;
  // For each term: per item, the value-array position of local entry (i, j) (row-major,
  // local_rows x local_size), -1 where the row is dropped. Costs 4 bytes per local entry and
  // saves a search per entry in every Jacobian assembly.
  std::vector<std::vector<int>> positions_;
  mutable Timing timing_;
};

// Indices of the non-finite entries of a vector (at most `limit`), for error messages.
std::vector<int> non_finite_entries(const Vector& v, int limit = 5);

}  // namespace keller
