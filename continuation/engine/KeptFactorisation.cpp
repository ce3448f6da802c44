#include "continuation/engine/KeptFactorisation.hpp"

namespace keller {

KeptFactorisation::KeptFactorisation(const Problem& problem, SparseLUOptions lu, bool block_elimination)
    : system_(inner_pattern(problem), border_size(problem), lu,
              block_elimination ? BorderedSystem::Mode::Block : BorderedSystem::Mode::Full) {}

Status KeptFactorisation::factorise_at(Evaluator& ev, const Vector& u, double lambda, const Constraint& c) {
  Status st = ev.set_parameter(lambda);
  if (st.is_ok()) st = ev.jacobian(u);
  if (st.is_ok()) st = ev.parameter_derivative(u);
  if (!st.is_ok()) return st;
  return factorise_assembled(ev, u, lambda, c);
}

Status KeptFactorisation::factorise_assembled(const Evaluator& ev, const Vector& u, double lambda,
                                              const Constraint& c) {
  if (ev.bordered())
    system_.set(ev.bordered_jacobian(), ev.parameter_derivative_vector(), c.cu, c.cl);
  else
    system_.set(ev.jacobian_matrix(), ev.parameter_derivative_vector(), c.cu, c.cl);
  return factorise(u, lambda);
}

Status KeptFactorisation::factorise(const Vector& u, double lambda) {
  ++count_;
  return remember(system_.factorize(), u, lambda);
}

Status KeptFactorisation::adopt(std::shared_ptr<SparseLU> lu, const SparseMatrix& J, const Vector& u_j, double lambda,
                                const Vector& Fp, const Constraint& c) {
  return remember(system_.adopt(std::move(lu), J, Fp, c.cu, c.cl), u_j, lambda);
}

Status KeptFactorisation::adopt_at(Evaluator& ev, const StartFactorisation& near, const Vector& u, double lambda,
                                   const Constraint& c) {
  adopted_renewal_cost_ = near.renewal_cost;
  Status st = ev.set_parameter(lambda);
  if (st.is_ok()) st = ev.parameter_derivative(u);
  if (!st.is_ok()) return st;
  if (!ev.bordered()) {
    ev.set_rounding_floor(near.jacobian, u);
    return adopt(near.lu, near.jacobian, near.at, lambda, ev.parameter_derivative_vector(), c);
  }
  BorderedJacobian J;
  J.K = near.jacobian;
  const int nk = static_cast<int>(J.K.rows()), m = border_size(ev.problem());
  J.B = Matrix::Zero(nk, m);
  J.C = Matrix::Zero(nk, m);
  J.D = Matrix::Zero(m, m);
  st = ev.border(u, J);
  if (!st.is_ok()) return st;
  return adopt(near.lu, J, near.at, lambda, ev.parameter_derivative_vector(), c);
}

Status KeptFactorisation::adopt(std::shared_ptr<SparseLU> lu, const BorderedJacobian& J, const Vector& u_j,
                                double lambda, const Vector& Fp, const Constraint& c) {
  return remember(system_.adopt(std::move(lu), J, Fp, c.cu, c.cl), u_j, lambda);
}

Status KeptFactorisation::remember(const Status& st, const Vector& u, double lambda) {
  known_ = st.is_ok();
  reuse_.react(known_ ? ReuseEvent::Factorised : ReuseEvent::Lost);
  if (known_) {
    u_ = u;
    lambda_ = lambda;
  }
  return st;
}

StartFactorisation KeptFactorisation::inner_factorisation() const {
  if (!known_ || !system_.block_factorised()) return {};
  return {system_.inner_lu(), system_.inner_matrix(), u_};
}

bool KeptFactorisation::made_at(const Vector& u, double lambda) const {
  return known_ && lambda_ == lambda && u_.size() == u.size() && u_ == u;
}

SparseLU* KeptFactorisation::j_factorisation_at(const Vector& u, double lambda) {
  return made_at(u, lambda) ? system_.j_factorisation() : nullptr;
}

double KeptFactorisation::measured_renewal_cost(const ContinuationTimings& t) const {
  const BorderedSystem::Totals lu = system_.totals();
  if (lu.factorisations == 0 || lu.solves == 0 || t.jacobians == 0 || t.residuals == 0) return adopted_renewal_cost_;
  const double renewal = t.jacobian / t.jacobians +
                         (t.parameter_derivatives ? t.parameter_derivative / t.parameter_derivatives : 0.0) +
                         lu.factor_seconds / lu.factorisations;
  const double iteration = t.residual / t.residuals + lu.solve_seconds / lu.solves;
  return iteration > 0 ? renewal / iteration : 0.0;
}

}  // namespace keller
