// Pseudo-arclength (Keller) and natural continuation of F(u, lambda) = 0 in one named parameter
// of any Problem. Tangent or secant predictor; corrector on the bordered system (stays
// solvable at folds); step control by corrector iterations, failures and tangent angle;
// location of requested parameter values, parameter bounds, monitor zeros, folds and branch
// points on the branch by corrector solves; every point reported to a BranchObserver as it is
// accepted. Numerical failures shrink the step; they never end the run except through the
// step-size floor, whose reason is reported.
#pragma once

#include <atomic>
#include <chrono>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "continuation/BorderedSystem.hpp"
#include "continuation/BranchPoint.hpp"
#include "continuation/ContinuationOptions.hpp"
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

enum class StopCode {
  UpperBound,     // reached continuation.upper
  LowerBound,     // reached continuation.lower
  StopObservable, // the stop observable crossed its threshold
  MaxSteps,
  StepFloor,      // the step size fell below min_step after failures
  Interrupted,
};
const char* to_string(StopCode c);

// Where a run's time went (seconds, wall clock): the speed floor is the factorisations.
struct ContinuationTimings {
  double jacobian = 0, parameter_derivative = 0, residual = 0, factorisation = 0, solve = 0, observables = 0,
         output = 0, total = 0, analysis = 0;
  long jacobians = 0, residuals = 0, solves = 0, analyses = 0;
};

struct ContinuationResult {
  StopCode code = StopCode::MaxSteps;
  std::string reason;  // a sentence for people
  int points = 0;      // rows written
  int rejected = 0;    // rejected step attempts
  long factorisations = 0;  // numeric factorisations of the bordered matrix (corrector and tangents)
  long tangent_iterations = 0;  // solves of tangents by iteration on a kept factorisation
  ContinuationTimings timings;
  BranchPoint last;
};

class Continuation {
 public:
  Continuation(Problem& problem, ContinuationOptions options, NewtonOptions newton = {}, SparseLUOptions lu = {});

  // Traces the branch from u0, a converged solution at the parameter's current value.
  ContinuationResult run(const Vector& u0, BranchObserver& observer);
  // Continues from a stored point (solution, tangent, step, arclength) of an earlier run.
  ContinuationResult resume(BranchPoint start, BranchObserver& observer);

  // Starts a new branch at a branch point bp (a stored point of an earlier run with the same
  // state scale): along the null vector phi of J there (inverse iteration on J's factorisation),
  // made orthogonal to bp's tangent; direction +1 or -1 picks the side (+1: the largest entry of
  // the null vector grows).
  ContinuationResult switch_branch(BranchPoint bp, int direction, BranchObserver& observer);
  // Analyses every accepted point (PointAnalysis::every) and every located point, adds its
  // columns, and detects and locates changes of its count (folds, branch points, Hopf points).
  void set_analysis(PointAnalysis* analysis) { analysis_ = analysis; }
  std::vector<std::string> analysis_columns() const {
    return analysis_ ? analysis_->column_names() : std::vector<std::string>{};
  }

  // Asks the run to stop after the current step (safe to call from a signal handler).
  void request_stop() { stop_requested_.store(true); }
  double state_scale() const { return state_scale_; }
  // The weighted inner product of the arclength norm.
  double dot(const Vector& u1, double l1, const Vector& u2, double l2) const;
  int parameter_index() const { return p_; }
  // The problem's monitors followed by the stop-observable thresholds (the order of
  // BranchPoint::monitors plus the stop entries).
  const std::vector<std::string>& monitor_names() const { return monitor_names_; }
  const BorderedSystem& bordered() const { return *bordered_; }

 private:
  // A linear constraint cu . (u - u0) + cl (lambda - l0) = target closing the extended system.
  struct Constraint {
    Vector cu;  // empty: zero
    double cl = 0.0;
    const Vector* u0 = nullptr;
    double l0 = 0.0;
    double target = 0.0;
  };
  struct Segment;  // two consecutive accepted points
  // A stop or a bound that the next step lands on (see ContinuationOptions::land_on_values).
  struct Landing {
    double value;
    double fraction;  // of the planned step
    PointKind kind;
    std::string label;
    bool terminal;
    StopCode code;
  };
  // The nearest stop or bound the step from cur (after prev, if any) would cross, if it may land
  // on it: away from folds.
  std::optional<Landing> landing(const BranchPoint& cur, const BranchPoint* prev, double ds, double dl_dir) const;

  Status set_parameter(double lambda);
  // step: the correction of a continuation step (true) or of a located point (false: a kept
  // factorisation is renewed only when the chord would not converge; see correct_iterations)
  Status correct(Vector& u, double& lambda, const Constraint& c, int& iterations, bool step = false);
  Status correct_iterations(Vector& u, double& lambda, const Constraint& c, int& iterations, bool step);
  // A located point's correction by the chord on a factorisation kept across steps (its own
  // renewal, floor and retry rules).
  bool located_on_kept_factorisation(bool step) const {
    return !step && options_.corrector == ContinuationOptions::Corrector::Chord && options_.reuse_factorisation;
  }
  // Unit tangent at the point of the last factorisation, oriented along (tu_prev, tl_prev).
  Status tangent_from_factorisation(const Vector& tu_prev, double tl_prev, Vector& tu, double& tl, int& det_sign);
  // Normalises (v, mu) in the arclength norm, oriented along (tu_prev, tl_prev) when given; the sign
  // of det J from mu and the bordered determinant.
  Status unit_tangent(Vector v, double mu, const Vector& tu_prev, double tl_prev, Vector& tu, double& tl,
                      int& det_sign) const;
  Status initial_tangent(const Vector& u, double lambda, Vector& tu, double& tl, int& det_sign);
  // Unit tangent at the converged point p (border row of constraint c): from the last
  // factorisation, or with reuse_factorisation by iterating on the exact tangent system at p
  // with the kept factorisation (a new factorisation at p when that does not converge).
  Status point_tangent(BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev,
                       bool refresh = false);
  Status factorize_at(const Vector& u, double lambda, const Constraint& c);
  // bordered_->factorize() on the system set up at (u, lambda), remembering where
  Status factorise(const Vector& u, double lambda);
  // J's factorisation if it was made at exactly p (else null), for the point analysis
  SparseLU* factorisation_at(const BranchPoint& p);
  Status evaluate(BranchPoint& p, bool analyse_point = true);
  void analyse(BranchPoint& p);  // the PointAnalysis of p (analysis_ set)
  Status timed_jacobian(const Vector& u);  // into F_, J_
  Status timed_parameter_derivative(const Vector& u);  // into Fp_
  void report(BranchObserver& observer, const BranchPoint& p);
  Constraint arclength_constraint(const BranchPoint& from, const Vector& tu, double tl, double sigma) const;
  Constraint lambda_constraint(double lambda) const;
  ContinuationResult trace(BranchPoint start, BranchObserver& observer);

  // Location on the segment a -> b; each returns the located point or nothing (with a note).
  std::optional<BranchPoint> locate_value(const BranchPoint& a, const BranchPoint& b, double value);
  std::optional<BranchPoint> locate_root(const BranchPoint& a, const BranchPoint& b, int which, double ga, double gb);
  // The point of the segment a -> b at fraction tau of its arclength (natural: of its parameter
  // change), corrected, predicted from the known points lo and hi (default a and b) around it;
  // exact_tangent: tangent and determinant from a factorisation at the point itself.
  BranchPoint point_on_segment(const BranchPoint& a, const BranchPoint& b, double tau, Status& st,
                               const BranchPoint* lo = nullptr, const BranchPoint* hi = nullptr,
                               bool exact_tangent = false, bool analyse = false);
  std::vector<double> monitor_values(const BranchPoint& p) const;

  Problem& problem_;
  ContinuationOptions options_;
  NewtonOptions newton_;
  SparseLUOptions lu_options_;
  int p_ = -1;
  int stop_index_ = -1;  // index of the stop observable in the problem's observables
  double state_scale_ = 1.0;
  double wu_ = 0.0, wl_ = 0.0;  // weights of the inner product
  std::unique_ptr<BorderedSystem> bordered_;
  long factorisations_ = 0;
  long tangent_iterations_ = 0;  // solves spent on tangents by iteration (reuse_factorisation)
  bool reusable_ = false;
  PointAnalysis* analysis_ = nullptr;
  int last_count_ = -1, last_count_index_ = -1;  // the last analysed point's count and row
  // where the bordered system's J was last factorised (NaN lambda: nowhere known)
  Vector j_u_;
  double shared_solve_seconds_ = 0.0;  // solves of the analysis with the continuation's factorisation
  long shared_solves_ = 0;
  double j_lambda_ = std::numeric_limits<double>::quiet_NaN();
  // analysis every N > 1 points: the last analysed point and the accepted points after it, so
  // that a change of the count is bracketed by bisection over them and located
  std::optional<BranchPoint> last_analysed_;
  std::vector<BranchPoint> unanalysed_;
  bool refactored_ = false;      // the last corrector call made a factorisation
  double last_residual_ = 0.0;   // |F|_inf where the last corrector call converged
  // |F|_inf the corrector reached at the points around a located point (twice the larger): where
  // the rounding floor lies for its chord; 0 outside location
  // The rounding floor two neighbouring points show: twice their larger residual where that is
  // above the tolerance (they stalled there), else 0.
  double residual_floor(double r0, double r1) const;
  bool landing_failed_ = false;  // the present step's landing was rejected: retries do not land
  double located_floor_ = 0.0;
  double step_floor_ = 0.0;  // twice the residual the last two points reached (chord on a kept factorisation)
  ContinuationTimings timings_;        // the kept factorisation belongs to a converged corrector
  SparseMatrix J_;
  Vector F_, Fp_;
  std::vector<std::string> monitor_names_;
  std::atomic<bool> stop_requested_{false};
  std::chrono::steady_clock::time_point t_start_;
  int next_index_ = 0;
  std::string location_note_;
  std::string analysis_note_;
};

}  // namespace keller
