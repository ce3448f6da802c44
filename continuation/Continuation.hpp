// Pseudo-arclength (Keller) and natural continuation of F(u, lambda) = 0 in one named parameter of
// any Problem: the stepper. Its trace loop reads as the algorithm and delegates each job to a part:
// Predictor (direction, landing on stops and bounds), Corrector (Newton or the chord on a kept
// factorisation, Anderson mixing, Deuflhard's test), TangentSolver, StepController,
// detect_crossings and EventLocator (values, monitors, folds), ZeroLander (a step landed on the
// stop observable's threshold), BranchPointMonitor (branch points from determinant signs),
// SpectrumScheduler (the point analysis every N points), and
// branch_direction (branch switching); KeptFactorisation is the factorisation they share and
// ArclengthNorm the norm and constraints. Every point is reported to a BranchObserver as it is
// accepted. Numerical failures shrink the step; they never end the run except through the
// step-size floor, or a start that fails (StopCode::StartFailed), whose reason is reported.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Corrector.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/KeptFactorisation.hpp"
#include "continuation/engine/Predictor.hpp"
#include "continuation/engine/StepController.hpp"
#include "continuation/engine/StopCode.hpp"
#include "continuation/engine/TangentSolver.hpp"
#include "continuation/events/BranchPointMonitor.hpp"
#include "continuation/events/EventDetector.hpp"
#include "continuation/events/EventLocator.hpp"
#include "continuation/events/RepeatedNotes.hpp"
#include "continuation/events/SpectrumScheduler.hpp"
#include "continuation/events/ZeroLander.hpp"
#include "core/Newton.hpp"
#include "core/PointAnalysis.hpp"
#include "core/Problem.hpp"

namespace keller {

// Receives the branch as it is computed (the branch file, the progress printer, tests).
class BranchObserver {
 public:
  virtual ~BranchObserver() = default;
  // Called once before the first point with the names the points' vectors follow.
  virtual void on_start(const std::vector<std::string>& observable_names,
                        const std::vector<std::string>& monitor_names) {}
  virtual void on_point(const BranchPoint& point) = 0;
  // A step that failed and will be retried with a smaller step.
  virtual void on_rejected(double lambda, double step, const Status& why) {}
  // Something worth telling that is not a point (an event detected but not located).
  virtual void on_note(const std::string& message) {}
  // The run ended: why, and the last point on the branch.
  virtual void on_finish(const std::string& reason, const BranchPoint& last) {}
};

struct ContinuationResult {
  StopCode code = StopCode::MaxSteps;
  std::string reason;           // a sentence for people
  int points = 0;               // rows written
  int rejected = 0;             // rejected step attempts
  long factorisations = 0;      // numeric factorisations of the bordered matrix (corrector, tangents, probes)
  long tangent_iterations = 0;  // solves of tangents by iteration on a kept factorisation
  long probes = 0;              // of the factorisations: determinant probes for branch points (BranchPointMonitor)
  double renewal_cost = 0.0;    // the corrector's renewal cost at the end (chord iterations per factorisation)
  double nnz_lu = 0.0;          // nonzeros of L + U of the last factorisation (J's own under block elimination)
  double lu_peak_bytes = 0.0;   // the LU's peak memory for it (SparseLU::Statistics)
  std::string lu_backend;       // the sparse LU that made it: "umfpack" or "mumps"
  ContinuationTimings timings;
  BranchPoint last;
};

class Continuation {
 public:
  Continuation(Problem& problem, ContinuationOptions options, NewtonOptions newton = {}, SparseLUOptions lu = {});
  ~Continuation();

  // Traces the branch from u0, a converged solution at the parameter's current value; with the
  // factorisation the solve of u0 left (block elimination with a kept factorisation only: the
  // start's tangent by iteration on it, a factorisation at u0 only where that does not converge;
  // for a problem with a border, the factorisation of its inner matrix, the border evaluated at u0).
  // near: a point close to u0 whose tangent starts that iteration (the switch an event curve's
  // next piece starts from), or null. A factorisation handed over (moved in, nobody else holding
  // it) is refactorised as the run's own at its first renewal, keeping its symbolic analysis.
  ContinuationResult run(const Vector& u0, BranchObserver& observer, StartFactorisation factorised = {},
                         const BranchPoint* near = nullptr);
  // Continues from a stored point (solution, tangent, step, arclength) of an earlier run.
  ContinuationResult resume(BranchPoint start, BranchObserver& observer);
  // Starts a new branch at a branch point bp (a stored point of an earlier run with the same
  // state scale) along branch_direction(); direction +1 or -1 picks the side. With a prediction
  // (the new branch's normal form, stability/NormalForms), along its tangent instead, the first
  // step predicted on its parabola.
  struct SwitchPrediction {
    Vector tu;        // the new branch's tangent in (u, lambda) as a function of some epsilon
    double tl = 0.0;  //   (any scale: it is normalised in the arclength norm)
    Vector second_u;  // d^2 (u, lambda) / d epsilon^2 (empty: a straight first step)
    double second_l = 0.0;
  };
  ContinuationResult switch_branch(BranchPoint bp, int direction, BranchObserver& observer,
                                   const SwitchPrediction* prediction = nullptr);
  // Analyses accepted points (SpectrumScheduler) and located points (with every = 1), adds its
  // columns, and detects and locates changes of its count (folds, branch points, Hopf points).
  void set_analysis(PointAnalysis* analysis);
  std::vector<std::string> analysis_columns() const {
    return analysis_ ? analysis_->column_names() : std::vector<std::string>{};
  }

  // Asks the run to stop after the current step (safe to call from a signal handler).
  void request_stop() { stop_requested_.store(true); }
  double state_scale() const { return norm_.state_scale(); }
  // The weighted inner product of the arclength norm.
  double dot(const Vector& u1, double l1, const Vector& u2, double l2) const { return norm_.dot(u1, l1, u2, l2); }
  int parameter_index() const { return ev_.parameter(); }
  // The problem's monitors followed by the stop-observable thresholds (the order of
  // BranchPoint::monitors).
  const std::vector<std::string>& monitor_names() const { return monitor_names_; }
  const BorderedSystem& bordered() const { return kept_.system(); }
  // The kept factorisation of J (of the inner matrix, for a problem with a border) where the run
  // ended, for another run to start on (empty where there is none: full mode, a fallback).
  // (with the renewal cost the run measured)
  StartFactorisation factorisation() const;

 private:
  // An attempted step: the point it reached (if any) and what the step controller needs.
  struct Step {
    Status status;
    BranchPoint point;
    std::optional<Landing> land;
    StepOutcome outcome;
    bool sampled = false;        // J was factorised during the step (its determinant sign is known)
    bool zero_at_start = false;  // it landed on the zero it starts on (tried again without landing)
    bool turned = false;         // arclength step rejected only because the tangent turned by more than the angle limit
    double angle = 0.0;          // the turn of the tangent over the step (radians), where it was measured
  };
  struct Finish {
    StopCode code;
    std::string reason;
    BranchPoint last;
  };

  void set_norm(const Vector& u0, double scale);
  ContinuationResult trace(BranchPoint start, BranchObserver& observer);
  // The start's residual, observables, bordered determinant sign and analysis.
  Status begin(BranchPoint& start);
  // The end of a restarted branch at its start: where the start lies on a stop (a bound, the stop
  // observable's threshold) or beyond it and the tangent goes on beyond it.
  std::optional<Finish> end_at_start(BranchPoint& start);
  // Predicts, corrects and takes the tangent of a step of size ds from cur (the step_number-th);
  // landing_allowed: false after this step's landing failed.
  Step attempt(const BranchPoint& cur, const BranchPoint* prev, double ds, int step_number, bool landing_allowed);
  // Everything located on the segment cur -> nxt, in order along the branch (last_step: the
  // branch ends after it at the latest).
  std::vector<LocatedPoint> locate_on(BranchPoint& cur, BranchPoint& nxt, const Step& step, bool last_step,
                                      BranchObserver& observer);
  void locate_crossings(const BranchPoint& cur, const BranchPoint& nxt, const Step& step,
                        std::vector<LocatedPoint>& located, BranchObserver& observer);
  // The zero of a monitor or stop threshold crossed on cur -> nxt: by Newton where it has a
  // gradient, else by secant; a stop observable with smooth pieces (ObservablePieces) piece by
  // piece, from the one smallest at nxt back to the first that crosses.
  std::optional<BranchPoint> locate_zero(const BranchPoint& cur, const BranchPoint& nxt, const Crossing& c,
                                         std::string& note);
  // The zero of one piece of the stop observable of c on cur -> end (by Newton, else by secant),
  // with the piece's value there (at_zero); nothing where the piece does not change sign on it or
  // it is not located.
  std::optional<BranchPoint> locate_on_piece(const BranchPoint& cur, const BranchPoint& end, const Crossing& c,
                                             int piece, double& at_zero, std::string& note);
  // a located branch point keeps the old branch's tangent, interpolated from the bracketing points
  void keep_bracket_tangent(const BranchPoint& a, const BranchPoint& b, BranchPoint& p) const;
  // last: the branch ends on this step (its determinant sign is then probed if unknown)
  void locate_branch_points(const BranchPoint& cur, BranchPoint& nxt, bool last, std::vector<LocatedPoint>& located,
                            BranchObserver& observer);
  void locate_stability_change(BranchPoint& cur, BranchPoint& nxt, std::vector<LocatedPoint>& located,
                               BranchObserver& observer);
  // Adds a located point (or a note where it was not located, after row after.index).
  void add_located(std::optional<BranchPoint> p, PointKind kind, std::string label, std::optional<StopCode> end,
                   const BranchPoint& after, std::vector<LocatedPoint>& located, BranchObserver& observer,
                   std::string& note);
  // Reports the located points and nxt's own row in order; the branch's end if it ends there.
  std::optional<Finish> report_segment(const BranchPoint& cur, BranchPoint& nxt, const Step& step,
                                       std::vector<LocatedPoint>& located, BranchObserver& observer);
  // The sign of det of the bordered Jacobian at p from a factorisation made there, under a row
  // along p's tangent (0: the factorisation failed).
  int probe_determinant(BranchPoint& p);
  Status evaluate(BranchPoint& p, bool analyse_point);
  void analyse(BranchPoint& p);
  void report(BranchObserver& observer, BranchPoint& p);
  ContinuationResult finish(StopCode code, std::string reason, const BranchPoint& last, BranchObserver& observer);

  Problem& problem_;
  ContinuationOptions options_;
  NewtonOptions newton_;
  SparseLUOptions lu_options_;
  int stop_index_ = -1;  // index of the stop observable in the problem's observables
  std::vector<std::string> monitor_names_;
  std::vector<AugmentedProblem::NamedUnknown> turning_;  // the problem's turning unknowns
  std::vector<int> partial_;                             // and its partial monitors
  ArclengthNorm norm_;
  Evaluator ev_;
  KeptFactorisation kept_;
  Corrector corrector_;
  TangentSolver tangents_;
  Predictor predictor_;
  StepController steps_;
  EventLocator locator_;
  ZeroLander lander_;
  BranchPointMonitor branch_points_;
  PointAnalysis* analysis_ = nullptr;
  std::unique_ptr<SpectrumScheduler> spectra_;
  std::string analysis_note_;
  std::string last_analysis_note_;  // the note said after the last analysed point (not said again while it lasts)
  struct Unlocated {
    PointKind kind;
    std::string label, note;
  };
  std::vector<Unlocated> unlocated_;  // this step's points detected but not located
  RepeatedNotes unlocated_notes_;     // what is said of them, a run of the same at successive steps once
  // folds and branch points the engine located (by the tangent or the determinant, not by the
  // analysis's count) since the last analysed point of a step, and those before it: where that
  // point's count is found wrong later, they are changes it missed that were located after all
  std::vector<double> engine_located_pending_, engine_located_before_analysed_;
  // a resumed branch starts on a point located as this kind (its first step does not locate it again)
  std::optional<PointKind> start_on_;
  // the first step's second-order term along the unit tangent (d^2 (u, lambda) / ds^2 at the start of
  // a switched branch), added to its prediction; empty: none
  Vector first_curvature_u_;
  double first_curvature_l_ = 0.0;
  double first_step_ = 0.0;  // a switched branch's first step from its normal form's curvature (0: the initial step)
  bool resumed_ = false;     // the branch continues from a stored point (resume)
  bool adopted_ = false;     // the start's factorisation came from the solve of the start
  double shared_solve_seconds_ = 0.0;  // solves of the analysis with the continuation's factorisation
  long shared_solves_ = 0;
  ContinuationResult result_;
  std::atomic<bool> stop_requested_{false};
  std::chrono::steady_clock::time_point t_start_;
  int next_index_ = 0;
};

}  // namespace keller
