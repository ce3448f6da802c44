// Location of a point on the segment between two converged points a and b of a branch: a requested
// parameter value (a fixed-parameter correction, with root finding along the arclength where that
// fails at a fold), or a zero of a function along the branch: a monitor, the parameter part of the
// tangent (a fold) or an unknown's part (a turn in it), the sign of det of the bordered Jacobian (a branch point), or
// the locator of a change of the point analysis's count (stability). Illinois secant steps (bisection for signs) on
// trial points predicted by the cubic Hermite interpolant of the bracket and corrected under the arclength row through
// a (natural continuation: at the trial parameter value).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Corrector.hpp"
#include "continuation/engine/TangentSolver.hpp"

namespace keller {

// What a located point is the zero of.
enum class EventTarget {
  Value,            // lambda - value
  Monitor,          // a monitor (the problem's, then the stop thresholds), by index
  Fold,             // the parameter part of the unit tangent
  BranchPoint,      // the sign of det of the bordered Jacobian
  StabilityChange,  // the point analysis's locator, bracketed by its count
  Turn,             // one unknown's part of the unit tangent (a turn of the branch in that unknown)
};
const char* to_string(EventTarget t);

struct Target {
  EventTarget kind = EventTarget::Value;
  int monitor = -1;    // Monitor: its index in BranchPoint::monitors; Turn: the unknown's index
  double value = 0.0;  // Value: the parameter value
  // g at a point of the branch (the function whose zero is located)
  double of(const BranchPoint& p) const;
  // Fold and branch point need J factorised at each trial point (the tangent's and the
  // determinant's signs there); the stability change needs the point analysed.
  bool needs_exact_tangent() const {
    return kind == EventTarget::Fold || kind == EventTarget::BranchPoint || kind == EventTarget::Turn;
  }
};

class EventLocator {
 public:
  // The observables and monitors of a corrected point, and its analysis where asked; the note
  // the analysis left when it failed.
  using Evaluate = std::function<Status(BranchPoint& p, bool analyse)>;
  using AnalysisNote = std::function<std::string()>;

  EventLocator(Corrector& corrector, TangentSolver& tangents, KeptFactorisation& kept, const ArclengthNorm& norm,
               const ContinuationOptions& options, Evaluate evaluate, AnalysisNote analysis_note);

  // The point of the segment a -> b where the parameter equals value (exactly); or, where the
  // fixed-parameter corrector fails, its root along the arclength. Nothing (and a note) where
  // neither converges.
  std::optional<BranchPoint> locate_value(const BranchPoint& a, const BranchPoint& b, double value, std::string& note);
  // The zero of target on the segment a -> b (ga = g(a), gb = g(b) of opposite signs, or counts
  // that differ for a stability change); iterations of the result: the corrector solves spent.
  std::optional<BranchPoint> locate_root(const BranchPoint& a, const BranchPoint& b, const Target& target, double ga,
                                         double gb, std::string& note);
  // Whether the last locate_root of a stability change found the count changing with no eigenvalue
  // at the axis (one left or entered the set of those computed).
  bool found_no_crossing() const { return no_crossing_; }
  // The zero of g on the segment a -> b (ga = g(a), gb = g(b) of opposite signs) by Newton on
  // F = 0, g = 0: from the zero of g's cubic Hermite interpolant along the segment, corrected onto
  // the branch under the arclength row, each correction solves F = 0 under g linearised at the
  // last point (a border row of the kept factorisation, as the arclength row), until the next
  // move in lambda would be below 1e-2 of the event tolerance. Nothing (and a note) where a
  // correction fails, it does not settle in a few corrections, it finds the zero a starts on, or
  // it leaves the segment: the caller then falls back to locate_root.
  std::optional<BranchPoint> locate_by_newton(const BranchPoint& a, const BranchPoint& b, const GradientFunction& g,
                                              double ga, double gb, std::string& note);
  // The branch's point whose tangent predicts the moves of settle's corrections from p.
  using NearerPoint = std::function<const BranchPoint&(const BranchPoint& p)>;
  // Newton on F = 0, g = 0 from p, a converged point of the branch: each correction solves F = 0
  // under g linearised at the last point (a border row of the kept factorisation), from the move
  // predicted along nearer(p)'s tangent, until the next move in lambda would be below 1e-2 of the
  // event tolerance (true: settled). h: the difference step in lambda for g's derivative; floor:
  // the corrector's residual floor; solves counts the corrector's iterations, r is the last
  // correction's result (its status ok on entry), st the failure of g's evaluation.
  bool settle(BranchPoint& p, const GradientFunction& g, double h, const NearerPoint& nearer, double floor, int& solves,
              CorrectorResult& r, Status& st);
  // The point of the segment a -> b at fraction tau of its arclength (natural: of its parameter
  // change), corrected, predicted from the known points lo and hi around it; exact_tangent: its
  // tangent and the determinant from a factorisation at the point itself.
  BranchPoint point_on_segment(const BranchPoint& a, const BranchPoint& b, double tau, Status& st,
                               const BranchPoint& lo, const BranchPoint& hi, bool exact_tangent, bool analyse);

 private:
  Corrector& corrector_;
  TangentSolver& tangents_;
  KeptFactorisation& kept_;
  const ArclengthNorm& norm_;
  const ContinuationOptions& options_;
  Evaluate evaluate_;
  AnalysisNote analysis_note_;
  bool no_crossing_ = false;
};

}  // namespace keller
