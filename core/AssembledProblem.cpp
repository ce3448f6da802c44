#include "core/AssembledProblem.hpp"

#include <stdexcept>

namespace keller {

void AssembledProblem::assemble(int size, std::vector<std::shared_ptr<const Term>> terms,
                                std::vector<std::pair<int, int>> redirects, TimeForm time_form) {
  if (assembler_) throw std::logic_error("problem '" + name() + "': its terms are assembled once, in its constructor");
  assembler_ = std::make_unique<Assembler>(size, std::move(terms), std::move(redirects));
  time_form_ = time_form;
}

const Assembler& AssembledProblem::assembler() const {
  if (!assembler_)
    throw std::logic_error("problem '" + name() +
                           "' used before its terms were assembled (its constructor must call assemble())");
  return *assembler_;
}

Status AssembledProblem::residual(const Vector& u, Vector& F) { return assembler().residual(u, F); }

Status AssembledProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) { return assembler().jacobian(u, F, J); }

Status AssembledProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  return assembler().parameter_derivative(p, u, dF);
}

Status AssembledProblem::mass_matrix(const Vector& u, SparseMatrix& B) {
  if (time_form_ == TimeForm::None) return Problem::mass_matrix(u, B);
  return assembler().mass_matrix(u, B);
}

Status AssembledProblem::time_residual(const Vector& u, const Vector& udot, Vector& R) {
  if (time_form_ == TimeForm::None) return Problem::time_residual(u, udot, R);
  return assembler().time_residual(u, udot, R);
}

Status AssembledProblem::time_dependent_residual(const Vector& u, const Vector& udot, Vector& G) {
  if (time_form_ != TimeForm::None) return assembler().time_dependent_residual(u, udot, G);
  Vector R;
  Status st = time_residual(u, udot, R);  // throws NoTimeForm, as for a problem without dynamics
  if (st.is_ok()) st = residual(u, G);
  if (st.is_ok()) G += R;
  return st;
}

Status AssembledProblem::directional_derivative(const Vector& u, const std::vector<Direction>& directions,
                                                Vector& out) {
  std::vector<const Vector*> du, dp;
  for (const Direction& d : directions) {
    if (d.parameters && d.parameters->size() != params_.size())
      throw std::invalid_argument("directional_derivative: a parameter direction has one entry per parameter");
    du.push_back(d.u);
    dp.push_back(d.parameters);
  }
  return assembler().directional_derivative(u, du, dp, out);
}

}  // namespace keller
