#include "core/DirichletTerm.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace keller {

void DirichletTerm::add(int dof, ValueFunction g) {
  if (dof < 0) throw std::invalid_argument(name_ + ": constraint on a non-existent unknown");
  dofs_.push_back(dof);
  values_.push_back(std::move(g));
  constant_.push_back(0);
}

void DirichletTerm::add(int dof, double value) {
  add(dof, [value](const ParameterSet&) { return value; });
  constant_.back() = 1;
}

double DirichletTerm::value(int item) const { return values_[item](*params_); }

bool DirichletTerm::constrains(int dof) const { return std::find(dofs_.begin(), dofs_.end(), dof) != dofs_.end(); }

namespace {

// A boundary value that does not exist at these parameters (std::domain_error from its value
// function: a fully developed inflow of a fluid with no unique profile) is the step's failure,
// with the function's reason, not a crash.
template <class F>
Status guarded(const std::string& name, F&& f) {
  try {
    f();
  } catch (const std::domain_error& e) {
    return {StatusCode::InvalidState, name + ": " + e.what()};
  }
  return {};
}

}  // namespace

Status DirichletTerm::residual(int item, const double* u, double* r) const {
  return guarded(name_, [&] { r[0] = u[0] - value(item); });
}

Status DirichletTerm::jacobian(int item, const double* u, double* r, double* J) const {
  J[0] = 1.0;
  return guarded(name_, [&] { r[0] = u[0] - value(item); });
}

Status DirichletTerm::parameter_derivative(int item, int p, const double*, double* dr) const {
  if (constant_[item]) {
    dr[0] = 0.0;
    return {};
  }
  ParameterSet probe = *params_;
  const double v = probe.value(p);
  const double h = 1e-6 * std::max(1.0, std::abs(v));
  const auto [lo, hi] = probe.difference_points(p, h);
  if (hi == lo)  // as Problem::parameter_derivative: no derivative rather than a zero one
    return {StatusCode::InvalidState,
            name_ + ": d/d" + probe.info(p).name + ": no room for a difference inside its admissible range"};
  return guarded(name_, [&] {
    probe.set(p, hi);
    const double ghi = values_[item](probe);
    probe.set(p, lo);
    const double glo = values_[item](probe);
    dr[0] = -(ghi - glo) / (hi - lo);
  });
}

}  // namespace keller
