// An optional capability of a problem beyond core/Problem.hpp: gradients of its monitors and
// observables where it has them cheaply, and the places of a monitor that is a minimum over places.
// A problem offers it by deriving from this class as well as from Problem,
//   class MyProblem final : public Problem, public MonitorGradients { ... };
// and overriding what it offers. The algorithms find it in one place (monitor_gradients()); where
// a problem does not offer it, or a part of it, they use the defaults said here.
#pragma once

#include <vector>

#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class Problem;

class MonitorGradients {
 public:
  virtual ~MonitorGradients() = default;

  // --- Gradients ---

  // Gradients in u of a monitor or an observable (at the parameters' present values): the engine
  // then locates their zeros by Newton on F = 0 with the function linearised (a few chord
  // iterations on the kept factorisation) instead of by secant trials along the branch, and lands
  // a step on a stop observable's threshold. has_*: whether one is offered. Default: none.
  virtual bool has_monitor_gradient(int monitor) const;
  // Default: the gradient at the place where the minimum sits (monitor_places,
  // monitor_place_gradient).
  virtual Status monitor_gradient(int monitor, const Vector& u, Vector& gradient);
  virtual bool has_observable_gradient(int observable) const;
  // Default: throws std::logic_error (there is none to call).
  virtual Status observable_gradient(int observable, const Vector& u, Vector& gradient);

  // --- Places ---

  // A monitor that is a minimum over places (nodes, Gauss points, elements), such as the smallest
  // conformation eigenvalue: its value at every place (the monitor is their minimum), so that an
  // event curve can follow the place where the minimum sits. has_places: whether the monitor is
  // one. Default: none (the algorithms then take the monitor itself as its only place).
  virtual bool has_places(int monitor) const;
  // Default: throws std::logic_error (there are none to list).
  virtual Status monitor_places(int monitor, const Vector& u, std::vector<double>& values);
  // The gradient in u of the monitor's value at one place. Default: one-sided differences, unknown
  // by unknown, of monitor_places (one evaluation of the places per unknown: small problems only).
  virtual Status monitor_place_gradient(int monitor, int place, const Vector& u, Vector& gradient);
};

// The problem's MonitorGradients, null where it offers none: where the algorithms find it.
MonitorGradients* monitor_gradients(Problem& problem);

// The places of a monitor of any problem: those the problem offers (MonitorGradients::has_places),
// else one place, the monitor itself, and its gradient by one-sided differences unknown by unknown.
// Throws std::out_of_range for a monitor or a place the problem does not have.
Status places_of(Problem& problem, int monitor, const Vector& u, std::vector<double>& values);
Status place_gradient_of(Problem& problem, int monitor, int place, const Vector& u, Vector& gradient);

}  // namespace keller
