// A problem assembled from terms (element kernels, boundary kernels, strong conditions): it owns
// its named parameters and the Assembler over its terms, and F, J, dF/dp, B and the time terms
// are that Assembler's. A problem built on it adds its parameters to params_, builds its terms
// against them, hands the terms to assemble() once in its constructor, and implements only what
// is its own: the guess, observables, monitors, fields.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "core/Assembler.hpp"
#include "core/ExactDerivatives.hpp"
#include "core/ParameterSet.hpp"
#include "core/Problem.hpp"
#include "core/Term.hpp"

namespace keller {

class AssembledProblem : public Problem, public ExactDerivatives {
 public:
  // The Assembler's number of unknowns.
  int size() const final { return assembler().size(); }
  ParameterSet& parameters() final { return params_; }
  const ParameterSet& parameters() const final { return params_; }
  const SparseMatrix& jacobian_pattern() const final { return assembler().pattern(); }

  Status residual(const Vector& u, Vector& F) final;
  // Exact, from the terms' own Jacobians (no finite differences).
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) final;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) final;
  // Assembled from the terms' time terms; throws (as Problem's default) for a problem assembled
  // with TimeForm::None.
  Status mass_matrix(const Vector& u, SparseMatrix& B) final;
  Status time_residual(const Vector& u, const Vector& udot, Vector& R) final;
  // F(u) + B(u) udot in one pass over the terms (Assembler::time_dependent_residual), what the free
  // time_dependent_residual (core/Problem.hpp) takes for an assembled problem.
  Status time_dependent_residual(const Vector& u, const Vector& udot, Vector& G);

  // Exact, by nested dual numbers through the terms, where every term offers them (kernel terms
  // do; core/ExactDerivatives.hpp).
  bool offers_exact_derivatives() const override { return assembler().has_directional_derivatives(); }
  Status directional_derivative(const Vector& u, const std::vector<Direction>& directions, Vector& out) override;

  // The global assembly (terms, weak residual, timing). Throws std::logic_error before assemble().
  const Assembler& assembler() const;

 protected:
  // Whether the problem has a time-dependent form B du/dt = -F. None: mass_matrix and
  // time_residual throw, as for a problem without dynamics (a wall without inertia), instead of
  // returning the B of terms that carry no time derivatives.
  enum class TimeForm { Assembled, None };

  AssembledProblem() = default;
  AssembledProblem(const AssembledProblem&) = delete;
  AssembledProblem& operator=(const AssembledProblem&) = delete;

  // Builds the Assembler over `size` unknowns from the terms (redirects: as Assembler's; its
  // constructor's std::invalid_argument passes through). Called once, from the constructor of
  // the derived problem; a second call throws std::logic_error.
  void assemble(int size, std::vector<std::shared_ptr<const Term>> terms,
                std::vector<std::pair<int, int>> redirects = {}, TimeForm time_form = TimeForm::Assembled);

  // The problem's parameters, which its terms read by index (declared before any term is built).
  ParameterSet params_;

 private:
  std::unique_ptr<Assembler> assembler_;
  TimeForm time_form_ = TimeForm::Assembled;
};

}  // namespace keller
