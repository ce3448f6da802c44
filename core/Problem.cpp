#include "core/Problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "core/AssembledProblem.hpp"

namespace keller {

Status Problem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  Status st = residual(u, F);
  if (!st.is_ok()) return st;
  J = jacobian_pattern();
  Vector up = u, Fp;
  for (int c = 0; c < J.outerSize(); ++c) {
    const double h = 1e-7 * std::max(1.0, std::abs(u[c]));
    up[c] = u[c] + h;
    st = residual(up, Fp);
    up[c] = u[c];
    if (!st.is_ok()) return st;
    for (SparseMatrix::InnerIterator it(J, c); it; ++it) it.valueRef() = (Fp[it.row()] - F[it.row()]) / h;
  }
  return {};
}

Status Problem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  ParameterSet& ps = parameters();
  const double v = ps.value(p);
  const double h = 1e-6 * std::max(1.0, std::abs(v));
  const auto [lo, hi] = ps.difference_points(p, h);
  if (hi == lo)
    return {StatusCode::InvalidState,
            fmt::format("dF/d{}: no room for a difference inside its admissible range", ps.info(p).name)};
  Vector Fhi, Flo;
  ps.set(p, hi);
  Status st = residual(u, Fhi);
  if (st.is_ok()) {
    ps.set(p, lo);
    st = residual(u, Flo);
  }
  ps.set(p, v);
  if (!st.is_ok()) return st;
  dF = (Fhi - Flo) / (hi - lo);
  return {};
}

Status Problem::mass_matrix(const Vector&, SparseMatrix&) {
  throw NoTimeForm("problem '" + name() + "' has no mass matrix (no time-dependent form)");
}

bool has_time_form(Problem& problem, const Vector& u) {
  SparseMatrix B;
  try {
    (void)problem.mass_matrix(u, B);
  } catch (const NoTimeForm&) {
    return false;
  }
  return true;
}

bool has_time_form(Problem& problem) { return has_time_form(problem, problem.initial_guess()); }

namespace {
std::string refusal(Problem& problem, bool has) {
  if (!has)
    return "problem '" + problem.name() +
           "' has no time-dependent form as this scene sets it up (no row has a time derivative)";
  return problem.why_no_time_derivative();
}
}  // namespace

std::string time_form_refusal(Problem& problem) { return refusal(problem, has_time_form(problem)); }

std::string time_form_refusal(Problem& problem, const Vector& u) { return refusal(problem, has_time_form(problem, u)); }

Status Problem::time_residual(const Vector& u, const Vector& udot, Vector& R) {
  SparseMatrix B;
  Status st = mass_matrix(u, B);
  if (!st.is_ok()) return st;
  R = B * udot;
  return {};
}

Status time_dependent_residual(Problem& problem, const Vector& u, const Vector& udot, Vector& G) {
  if (auto* assembled = dynamic_cast<AssembledProblem*>(&problem))
    return assembled->time_dependent_residual(u, udot, G);
  Vector R;
  Status st = problem.time_residual(u, udot, R);
  if (st.is_ok()) st = problem.residual(u, G);
  if (st.is_ok()) G += R;
  return st;
}

Status Problem::observables(const Vector&, std::vector<double>& values) {
  values.clear();
  return {};
}

Status Problem::monitors(const Vector&, std::vector<double>& values) {
  values.clear();
  return {};
}

SolutionFields Problem::fields(const Vector&) const { return {}; }

}  // namespace keller
