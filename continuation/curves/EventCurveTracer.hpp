// Traces an event curve (EventCurveProblem) piece by piece: each piece is an ordinary run of the
// Continuation stepper that follows one place and ends where the switch margin crosses zero; the
// next one starts from that switch on the place the minimum moved to, with the factorisation the
// last one ended with. The pieces are reported as one branch, each switch a labelled event.
#pragma once

#include <functional>

#include "continuation/Continuation.hpp"
#include "continuation/curves/EventCurveProblem.hpp"
#include "core/Newton.hpp"
#include "core/SparseLU.hpp"

namespace keller {

class EventCurveTracer {
 public:
  explicit EventCurveTracer(EventCurveProblem& curve) : curve_(curve) {}

  // Follows the minimum's place at U and corrects U by Newton at the present p2.
  Status start(Vector& U, const NewtonOptions& newton, SparseLUOptions lu = {});
  // Traces the curve from U0 (start() done) with options o in p2 (o.stop.observable empty or
  // EventCurveProblem::kMargin: the switch margin is the stop of each piece), as one branch
  // reported to observer. each_run, when given, sees each piece's stepper before it runs (to
  // forward interrupts) and null after.
  ContinuationResult trace(ContinuationOptions o, const NewtonOptions& newton, const SparseLUOptions& lu,
                           const Vector& U0, BranchObserver& observer,
                           const std::function<void(Continuation*)>& each_run = {});

 private:
  // U corrected at the present parameters (CurveProblem::solve_here), the chord on kept_ where
  // there is one; kept_ becomes the factorisation it ended with.
  Status solve_kept(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu);

  EventCurveProblem& curve_;
  // the inner J's factorisation the last solve or piece ended with: the next one starts on it
  StartFactorisation kept_;
  double solve_seconds_ = 0.0;  // in solves at switches (outside the pieces' own timings)
};

}  // namespace keller
