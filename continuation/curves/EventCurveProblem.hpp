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
#include "continuation/curves/CurveProblem.hpp"
#include "continuation/engine/ObservablePieces.hpp"
#include "core/MonitorGradients.hpp"
#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller {

// Observables: the inner problem's, then p1, "place" (the followed place's index) and
// "switch margin" (the smallest value elsewhere minus the followed one: >= 0 while the
// minimum sits at the followed place). Monitors: the inner problem's but the curve's own. The
// places are those the inner problem offers (MonitorGradients::has_places), else the monitor
// itself as one place (places_of()).
class EventCurveProblem final : public CurveProblem, public MonitorGradients, public ObservablePieces {
 public:
  // inner at the event's parameter values; event_parameter: p1 (the parameter of the branch the
  // event was located on, an unknown of the curve); monitor: the inner problem's monitor.
  EventCurveProblem(Problem& inner, const std::string& event_parameter, const std::string& monitor);

  std::string name() const override { return inner_.name() + "-event-curve"; }
  Status residual(const Vector& U, Vector& F) override;
  // [J F_p1; m_k,u^T m_k,p1]: the inner J bordered by one column and row.
  int border_size() const override { return 1; }
  Status bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) override;
  Status border(const Vector& U, Vector& F, BorderedJacobian& J) override;
  std::vector<std::string> observable_names() const override { return curve_observable_names({"place", kMargin}); }
  Status observables(const Vector& U, std::vector<double>& values) override;
  // The switch margin's gradient in U: that of m_j - m_k, j the place of the smallest value
  // elsewhere (its switches are located by Newton).
  bool has_observable_gradient(int observable) const override { return observable == margin_index(); }
  Status observable_gradient(int observable, const Vector& U, Vector& gradient) override;
  // The switch margin's pieces: piece j is m_j - m_k, j a place other than the followed one k;
  // the smallest at U is the margin there.
  bool has_pieces(int observable) const override { return observable == margin_index(); }
  Status smallest_piece(int observable, const Vector& U, int& piece) override;
  Status piece_value(int observable, int piece, const Vector& U, double& value) override;
  Status piece_gradient(int observable, int piece, const Vector& U, Vector& gradient) override;
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& U, std::vector<double>& values) override;
  std::string summary() const override;

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
  Status equations_parameter_derivative(int p, const Vector& U, Vector& d) override;
  Status place_values(const Vector& U, std::vector<double>& values);
  // The place of the smallest value other than the followed one (and than the one just left, at
  // the switch a piece starts from), -1 where there is none.
  int other_place(const Vector& U, const std::vector<double>& values) const;
  int margin_index() const { return static_cast<int>(inner_.observable_names().size()) + 2; }
  // Throw std::logic_error where observable is not the switch margin (or piece not another place).
  void check_margin(int observable) const;
  void check_piece(int observable, int piece) const;
  // F (f the inner residual) and the border of the Jacobian at U.
  Status fill_border(const Vector& U, const Vector& f, Vector& F, BorderedJacobian& J);
  // d m_place / d p at U (p1 set from U) by central differences in the parameter p.
  Status place_parameter_derivative(int p, int place, const Vector& u, double& derivative);
  // U corrected at the present parameters (CurveProblem::solve_here), the chord on kept_ where
  // there is one; kept_ becomes the factorisation it ended with.
  Status solve_kept(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu);

  int monitor_;
  int place_ = 0;
  // the state of the switch a piece starts from, and the place it left there
  Vector switched_at_;
  int switched_from_ = -1;
  // the inner J's factorisation the last solve or piece ended with: the next one starts on it
  StartFactorisation kept_;
  double solve_seconds_ = 0.0;  // in solves at switches (outside the pieces' own timings)
};

}  // namespace keller
