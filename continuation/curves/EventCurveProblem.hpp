// The zero of a monitor that is a minimum over places (min m1 = 0 over nodes) continued in a
// second parameter p2: an ordinary branch of an augmented problem with unknowns (u, p1) and
// equations F = 0, m_k(u, p) = 0, m_k the monitor's value at the place k where the minimum sits.
// The curve follows k; where another place's value falls below it (the switch margin crosses
// zero) a piece of the curve ends, and the next one follows the new place (EventCurveTracer runs
// the pieces and reports the whole curve as one branch).
#pragma once

#include <string>
#include <vector>

#include "continuation/curves/CurveProblem.hpp"
#include "continuation/engine/ObservablePieces.hpp"
#include "core/MonitorGradients.hpp"
#include "core/Problem.hpp"

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
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& U, std::vector<double>& values) override;
  std::string summary() const override;

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

  // The place followed, and the place where the minimum sits at U (the inner problem's
  // parameters set from U and the present p2).
  int place() const { return place_; }
  Status argmin(const Vector& U, int& place);
  // The place of the smallest value at U but the followed one: where the minimum moves at a
  // switch (the followed place where there is no other).
  Status next_place(const Vector& U, int& place);
  // Follows `place` from now on: its value is the curve's equation.
  void follow(int place);
  // The piece about to be traced starts at the switch U, where the curve left the place `left`:
  // there (and within the run's correction of U) that place is level with the followed one, and
  // the switch margin leaves it out. U empty: the piece starts at no switch (the curve's first).
  void start_piece_at(const Vector& U, int left);
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

  int monitor_;
  int place_ = 0;
  // the state of the switch a piece starts from, and the place it left there
  Vector switched_at_;
  int switched_from_ = -1;
};

}  // namespace keller
