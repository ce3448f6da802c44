// The factorisation of the bordered system [J F_p; c^T d] that the corrector and the tangent
// solver share, as an object that knows where J was factorised (the state and parameter), whether
// it may be kept for the next correction (ReusePolicy), how many numeric factorisations were
// made, and what a renewal costs against a chord iteration in the run's own measured times.
#pragma once

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BorderedSystem.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/ReusePolicy.hpp"
#include "core/SparseLU.hpp"

#include <memory>

namespace keller {

// J's factorisation that the solve of the start left (NewtonSolver::factorisation(), jacobian(),
// factorised_at()), or another run's kept one: a branch starts on it instead of factorising J at
// the start again. For a problem with a border (AugmentedProblem::border_size() > 0), its inner
// matrix K.
struct StartFactorisation {
  std::shared_ptr<SparseLU> lu;
  SparseMatrix jacobian;
  Vector at;                  // the iterate where it was made
  double renewal_cost = 0.0;  // the renewal cost the run that made it measured (0: none)
};

class KeptFactorisation {
 public:
  // For the problem's Jacobian pattern, or its inner pattern and border (AugmentedProblem).
  KeptFactorisation(const Problem& problem, SparseLUOptions lu, bool block_elimination);

  // Assembles J and F_p at (u, lambda) (the parameter set there), sets the border row c and
  // factorises; remembers the point.
  Status factorise_at(Evaluator& ev, const Vector& u, double lambda, const Constraint& c);
  // The same with J and F_p already evaluated at (u, lambda) by ev.
  Status factorise_assembled(const Evaluator& ev, const Vector& u, double lambda, const Constraint& c);
  // J's factorisation made elsewhere (the last one of the Newton solve that found the start, at its
  // iterate u_j), with the Jacobian J it factorises and the border F_p, c of the point at lambda:
  // no factorisation (block elimination only; a non-ok status where it cannot be used).
  Status adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& u_j, double lambda, const Vector& Fp,
               const Constraint& c);
  // The same for a problem with a border: J in bordered form, K the factorised inner matrix and
  // the border that of the point.
  Status adopt(std::shared_ptr<SparseLU> lu, const BorderedJacobian& J, const Vector& u_j, double lambda,
               const Vector& Fp, const Constraint& c);
  // near (another run's factorisation) at the point (u, lambda): the parameter set there, F_p and,
  // for a problem with a border, the border evaluated at u (AugmentedProblem::border, not the inner
  // Jacobian), then adopt().
  Status adopt_at(Evaluator& ev, const StartFactorisation& near, const Vector& u, double lambda, const Constraint& c);
  // J's (the inner matrix's) factorisation in use, the matrix and where it was made; empty where
  // block elimination is not in use.
  StartFactorisation inner_factorisation() const;
  // A factorisation of [J F_p; c^T d] with a border row replaced without refactorising (block
  // elimination only); a non-ok status when it must be refactorised instead.
  Status set_row(const Constraint& c) { return system_.set_row(c.cu, c.cl); }
  // Solve with the factorisation (see BorderedSystem::solve).
  Status solve(const Vector& f, double g, Vector& x, double& y, bool refine = true) {
    return system_.solve(f, g, x, y, refine);
  }

  // Made at exactly this point (the same state and parameter).
  bool made_at(const Vector& u, double lambda) const;
  // J's own factorisation if it was made at exactly (u, lambda) (block elimination), else null.
  SparseLU* j_factorisation_at(const Vector& u, double lambda);
  // Whether the next correction may start on this factorisation (ReusePolicy: it belongs to a
  // converged correction or to a point of the branch, not to an iterate that diverged) with the
  // correction's own row (block elimination).
  bool reusable() const { return reuse_.reusable() && system_.block_factorised(); }
  // What happened to it beyond its own factorisations and adoptions (ReusePolicy).
  void record(ReuseEvent e) { reuse_.react(e); }
  // Block elimination on J's factorisation is in use (what set_row and a kept chord need).
  bool block() const { return system_.block_factorised(); }
  // Sign of det of the factorised bordered matrix with its present row.
  int determinant_sign() const { return system_.determinant_sign(); }
  long count() const { return count_; }
  const BorderedSystem& system() const { return system_; }

  // What a renewal (Jacobian, dF/dp, factorisation) costs in chord iterations (residual and solve),
  // from the run's mean times so far; while either is unmeasured, what the run whose factorisation
  // was adopted measured (StartFactorisation::renewal_cost), else 0.
  double measured_renewal_cost(const ContinuationTimings& t) const;

 private:
  double adopted_renewal_cost_ = 0.0;
  Status factorise(const Vector& u, double lambda);
  // Where J was factorised (u, lambda) after a factorisation or adoption that returned st (and
  // for the reuse policy, that it was made or lost).
  Status remember(const Status& st, const Vector& u, double lambda);
  BorderedSystem system_;
  Vector u_;
  double lambda_ = 0.0;
  bool known_ = false;  // u_, lambda_ say where J was factorised
  ReusePolicy reuse_;
  long count_ = 0;
};

}  // namespace keller
