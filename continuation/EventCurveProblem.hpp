// The zero of a monitor that is a minimum over places (min m1 = 0 over nodes) continued in a
// second parameter p2: an ordinary branch of an augmented problem with unknowns (u, p1) and
// equations F = 0, m_k(u, p) = 0, m_k the monitor's value at the place k where the minimum sits.
// The curve follows k; where another place's value falls below it (the switch margin crosses
// zero) the stepper ends the piece there, and trace() goes on from the located switch with the
// new place, reporting the whole curve as one branch with each switch a labelled event.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/CurveUnknowns.hpp"
#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller {

// Observables: the inner problem's, then p1, "place" (the followed place's index) and
// "switch margin" (the smallest value elsewhere minus the followed one: >= 0 while the
// minimum sits at the followed place). Monitors: the inner problem's but the curve's own.
class EventCurveProblem final : public Problem {
 public:
  // inner at the event's parameter values; event_parameter: p1 (the parameter of the branch the
  // event was located on, an unknown of the curve); monitor: the inner problem's monitor.
  EventCurveProblem(Problem& inner, const std::string& event_parameter, const std::string& monitor);

  std::string name() const override { return inner_.name() + "-event-curve"; }
  int size() const override { return unknowns_.size(); }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return unknowns_.pattern(); }
  Status residual(const Vector& U, Vector& F) override;
  Status jacobian(const Vector& U, Vector& F, SparseMatrix& J) override;
  // [J F_p1; m_k,u^T m_k,p1]: the inner J bordered by one column and row.
  int border_size() const override { return 1; }
  const SparseMatrix& inner_pattern() const override { return inner_.jacobian_pattern(); }
  Status bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) override;
  std::vector<NamedUnknown> turning_unknowns() const override { return unknowns_.turning_unknowns(); }
  Status parameter_derivative(int p, const Vector& U, Vector& dF) override;
  Vector initial_guess() override;
  double residual_scale() const override { return inner_.residual_scale(); }
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& U, std::vector<double>& values) override;
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& U, std::vector<double>& values) override;
  SolutionFields fields(const Vector& U) const override { return inner_.fields(U.head(n_)); }
  std::string summary() const override;

  int event_parameter() const { return unknowns_.p1(); }
  const std::string& event_parameter_name() const { return unknowns_.p1_name(); }
  Vector state(const Vector& u, double p1) const { return unknowns_.state(u, p1); }
  // The place followed, and the place where the minimum sits at U (the inner problem's
  // parameters set from U and the present p2).
  int place() const { return place_; }
  Status argmin(const Vector& U, int& place);
  // Follows the minimum's place at U and corrects U by Newton at the present p2.
  Status start(Vector& U, const NewtonOptions& newton, SparseLUOptions lu = {});
  // Traces the curve from U0 (start() done) with options o in p2 (o.stop.observable empty or
  // kMargin: the switch margin is the stop of each piece), as one branch reported to observer.
  // each_run, when given, sees each piece's stepper before it runs (to forward interrupts).
  ContinuationResult trace(ContinuationOptions o, const NewtonOptions& newton, const SparseLUOptions& lu,
                           const Vector& U0, BranchObserver& observer,
                           const std::function<void(Continuation*)>& each_run = {});
  // The name of the observable whose zero is a switch.
  static constexpr const char* kMargin = "switch margin";

 private:
  Status place_values(const Vector& U, std::vector<double>& values);
  // d m_k / d p at U (p1 set from U) by central differences in the parameter p.
  Status place_parameter_derivative(int p, const Vector& u, double& derivative);
  // Newton at the present parameters by block elimination (FixedParameterSolve).
  Status solve_here(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu);

  Problem& inner_;
  CurveUnknowns unknowns_;
  int n_;
  int monitor_;
  int place_ = 0;
  // the state of a switch the curve restarts from: its margin is zero there (not a new crossing)
  Vector switched_at_;
};

}  // namespace keller
