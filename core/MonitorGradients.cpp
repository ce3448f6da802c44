#include "core/MonitorGradients.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "core/Problem.hpp"

namespace keller {

namespace {

using PlaceValues = std::function<Status(const Vector& u, std::vector<double>& values)>;

// The gradient of places(u)[place] by one-sided differences, unknown by unknown; `what` names the
// monitor in the message for a place it does not have.
Status place_gradient_by_differences(const PlaceValues& places, int place, const Vector& u, Vector& gradient,
                                     const std::string& what) {
  std::vector<double> v0, v1;
  Status st = places(u, v0);
  if (!st.is_ok()) return st;
  if (place < 0 || place >= static_cast<int>(v0.size()))
    throw std::out_of_range(what + " has no place " + std::to_string(place) + " (it has " + std::to_string(v0.size()) +
                            ")");
  gradient.resize(u.size());
  Vector up = u;
  for (int j = 0; j < u.size(); ++j) {
    const double h = 1e-7 * std::max(1.0, std::abs(u[j]));
    up[j] = u[j] + h;
    st = places(up, v1);
    up[j] = u[j];
    if (!st.is_ok()) return st;
    gradient[j] = (v1[static_cast<size_t>(place)] - v0[static_cast<size_t>(place)]) / h;
  }
  return {};
}

}  // namespace

bool MonitorGradients::has_monitor_gradient(int) const { return false; }

Status MonitorGradients::monitor_gradient(int monitor, const Vector& u, Vector& gradient) {
  std::vector<double> v;
  const Status st = monitor_places(monitor, u, v);
  if (!st.is_ok()) return st;
  const int place = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  return monitor_place_gradient(monitor, place, u, gradient);
}

bool MonitorGradients::has_observable_gradient(int) const { return false; }

Status MonitorGradients::observable_gradient(int observable, const Vector&, Vector&) {
  throw std::logic_error("no gradient of observable " + std::to_string(observable) +
                         " is offered (has_observable_gradient is false)");
}

bool MonitorGradients::has_places(int) const { return false; }

Status MonitorGradients::monitor_places(int monitor, const Vector&, std::vector<double>&) {
  throw std::logic_error("monitor " + std::to_string(monitor) + " is not a minimum over places (has_places is false)");
}

Status MonitorGradients::monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient) {
  return place_gradient_by_differences(
      [&](const Vector& x, std::vector<double>& v) { return monitor_places(monitor, x, v); }, place, u, gradient,
      "monitor " + std::to_string(monitor));
}

MonitorGradients* monitor_gradients(Problem& problem) { return dynamic_cast<MonitorGradients*>(&problem); }

Status places_of(Problem& problem, int monitor, const Vector& u, std::vector<double>& values) {
  MonitorGradients* offered = monitor_gradients(problem);
  if (offered && offered->has_places(monitor)) return offered->monitor_places(monitor, u, values);
  std::vector<double> all;
  const Status st = problem.monitors(u, all);
  if (!st.is_ok()) return st;
  if (monitor < 0 || monitor >= static_cast<int>(all.size()))
    throw std::out_of_range("problem '" + problem.name() + "' has no monitor " + std::to_string(monitor));
  values = {all[static_cast<size_t>(monitor)]};
  return {};
}

Status place_gradient_of(Problem& problem, int monitor, int place, const Vector& u, Vector& gradient) {
  MonitorGradients* offered = monitor_gradients(problem);
  if (offered && offered->has_places(monitor)) return offered->monitor_place_gradient(monitor, place, u, gradient);
  return place_gradient_by_differences(
      [&](const Vector& x, std::vector<double>& v) { return places_of(problem, monitor, x, v); }, place, u, gradient,
      "monitor " + std::to_string(monitor) + " of '" + problem.name() + "'");
}

}  // namespace keller
