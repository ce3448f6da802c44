#include "core/Problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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
  const Parameter& info = ps.info(p);
  const double hi = std::min(v + h, info.upper), lo = std::max(v - h, info.lower);
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
  throw std::logic_error("problem '" + name() + "' has no mass matrix (no time-dependent form)");
}

Status Problem::time_residual(const Vector& u, const Vector& udot, Vector& R) {
  SparseMatrix B;
  Status st = mass_matrix(u, B);
  if (!st.is_ok()) return st;
  R = B * udot;
  return {};
}

Status Problem::observables(const Vector&, std::vector<double>& values) {
  values.clear();
  return {};
}

Status Problem::monitors(const Vector&, std::vector<double>& values) {
  values.clear();
  return {};
}

Status Problem::monitor_places(int monitor, const Vector& u, std::vector<double>& values) {
  std::vector<double> all;
  Status st = monitors(u, all);
  if (!st.is_ok()) return st;
  if (monitor < 0 || monitor >= static_cast<int>(all.size()))
    throw std::out_of_range("problem '" + name() + "' has no monitor " + std::to_string(monitor));
  values = {all[static_cast<size_t>(monitor)]};
  return {};
}

Status Problem::monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) {
  std::vector<double> v0, v1;
  Status st = monitor_places(monitor, u, v0);
  if (!st.is_ok()) return st;
  if (place < 0 || place >= static_cast<int>(v0.size()))
    throw std::out_of_range("monitor " + std::to_string(monitor) + " of '" + name() + "' has no place " +
                            std::to_string(place));
  gradient.resize(u.size());
  Vector up = u;
  for (int j = 0; j < u.size(); ++j) {
    const double h = 1e-7 * std::max(1.0, std::abs(u[j]));
    up[j] = u[j] + h;
    st = monitor_places(monitor, up, v1);
    up[j] = u[j];
    if (!st.is_ok()) return st;
    gradient[j] = (v1[static_cast<size_t>(place)] - v0[static_cast<size_t>(place)]) / h;
  }
  return {};
}

bool Problem::has_monitor_gradient(int) const { return false; }

Status Problem::monitor_gradient(int monitor, const Vector& u, Vector& gradient) {
  std::vector<double> v;
  const Status st = monitor_places(monitor, u, v);
  if (!st.is_ok()) return st;
  const int place = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  return monitor_place_gradient(monitor, place, u, gradient);
}

bool Problem::has_observable_gradient(int) const { return false; }

Status Problem::observable_gradient(int observable, const Vector&, Vector&) {
  throw std::logic_error("problem '" + name() + "' has no gradient of observable " + std::to_string(observable));
}

bool Problem::hold_piece(int, const Vector*) { return false; }

}  // namespace keller
