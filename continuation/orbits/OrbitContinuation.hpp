// Continuation of a branch of periodic orbits in one parameter lambda by pseudo-arclength on
// (u0, T, lambda): a secant predictor, the Newton-Krylov shooting corrector (OrbitCorrector) with
// the arclength row, the phase hyperplane through the last orbit normal to its flow, a fresh grid
// from an adaptive run over each accepted orbit, and the step grown or shrunk by the corrector's
// iterations. Every orbit's Floquet multipliers (from an OrbitMultipliers, which runs/ implements
// with stability/) give its stability and the bifurcations of orbits, located between two orbits
// by the secant method on a test function:
//   fold of cycles / branch point of cycles: a real multiplier other than the trivial one crosses
//     +1 (fold where lambda turns, else a branch point);
//   period doubling: a real multiplier crosses -1;
//   Neimark-Sacker: a complex pair crosses the unit circle (a real pair whose product is 1, a
//     neutral saddle, is none).
// Each orbit is reported as a BranchPoint: u = u0, its tangent the unit secant, the observables period, amplitude (the
// largest max - min over the period of any unknown) and, per problem observable NAME, NAME at u0 and amplitude:NAME;
// the analysis columns are the multipliers.
#pragma once

#include <chrono>
#include <complex>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/orbits/OrbitCorrector.hpp"
#include "continuation/orbits/OrbitDeflation.hpp"
#include "continuation/orbits/OrbitMeasures.hpp"
#include "continuation/orbits/ShootingMap.hpp"
#include "core/Scene.hpp"

namespace keller {

// What the multipliers of an orbit must resolve: each one's residual |M x - mu x| (|x| = 1), on
// the scale of the unit circle (max(1, |mu_1|)), at most the tolerance (<= 0: the analysis's own),
// or, for one at least 1/2 from the unit circle, circle_share times its distance from it
// | |mu| - 1 | where that is larger (stability/FloquetMultipliers.hpp says why).
struct MultiplierAccuracy {
  double tolerance = 0.0;
  double circle_share = 0.0;
};

// The Floquet multipliers of an orbit, by whatever computes eigenvalues (runs/ gives stability's).
class OrbitMultipliers {
 public:
  virtual ~OrbitMultipliers() = default;
  // The multipliers of largest magnitude of the n x n monodromy matrix applied by M, by |mu|
  // descending, the trivial one's index, and where `vectors` is given, an eigenvector of each, to
  // `accuracy`; M's products are accurate to about a thousandth of its tolerance.
  virtual Status compute(int n, const std::function<Status(const Vector&, Vector&)>& M,
                         std::vector<std::complex<double>>& values, int& trivial,
                         std::vector<Eigen::VectorXcd>* vectors, MultiplierAccuracy accuracy) = 0;
};

// A converged orbit.
struct OrbitPoint {
  Vector u0;
  double period = 0.0, lambda = 0.0;
  OrbitGrid grid;              // the grid it was computed on
  Vector flow;                 // du/dt at u0
  std::vector<Vector> states;  // u_0 .. u_m over the period on the grid
  std::vector<double> times;   // their times, 0 .. T
  std::vector<std::complex<double>> multipliers;
  int trivial = -1;
  int iterations = 0;
  long krylov_iterations = 0;
  double residual = 0.0;
  double s = 0.0;  // arclength from the start
  // The largest local error estimate of its integration on the grid it was computed on
  // (ShootingMap::step_error: above 1, a step fails the integrator's error test on this orbit;
  // +inf: not estimated), not on a grid recorded from it afterwards
  double grid_error = std::numeric_limits<double>::infinity();
};

struct OrbitContinuationOptions {
  // Arclength norm |(du0, dT, dlambda)|^2 = theta |du0|^2 / (n s^2) + (1 - theta) (dlambda^2 +
  // (dT / T0)^2), s the state scale (RMS of the first orbit's u0, or 1 where that is 0, as the
  // continuation engine's), T0 the first orbit's period
  double theta = 0.5;
  double state_scale = 0.0;  // 0: automatic
  double step = 0.05;        // arclength of the first step
  double min_step = 1e-6, max_step = 0.5;
  double lambda_min = -std::numeric_limits<double>::infinity();
  double lambda_max = std::numeric_limits<double>::infinity();
  int max_points = 50;
  std::vector<double> stops;  // parameter values where the orbit is located and reported (kind Requested)
  int target_iterations = 4;  // the step grows below, shrinks above
  TimeOptions time;           // the grids' method and tolerance (t_end unused)
  ShootingOptions shooting;
  OrbitCorrectorOptions corrector;
  int multipliers = 6;             // Floquet multipliers per orbit (0: none, no events)
  bool locate = true;              // locate the bifurcations of orbits
  double locate_tolerance = 1e-8;  // |test function| at a located point
  int locate_iterations = 12;
  // where `keller trace --orbit` starts: the first orbit's distance from the Hopf point (or the
  // evolve run's parameter value) in the parameter (0: 1e-2 max(|lambda_H|, 1))
  double start_distance = 0.0;
  int frames = 40;  // of an orbit's animation (keller export --orbit)

  // [orbit]'s keys, and the options from them and [continuation]'s (parameter range, steps, norm,
  // max_steps). Throws SceneError naming a key whose value it refuses.
  static void declare(SceneSchema& schema);
  static OrbitContinuationOptions from_scene(const Scene& scene, const ContinuationOptions& continuation);
};

struct OrbitContinuationResult {
  StopCode code = StopCode::MaxSteps;
  std::string reason;
  int points = 0, rejected = 0;
  std::vector<OrbitPoint> located;  // the located bifurcations, in order
  OrbitPoint last;
  ShootingMap::Counts counts;  // of the map over the run: forward steps, linearised passes, times
  long newton_iterations = 0, krylov_iterations = 0;
  double multiplier_seconds = 0.0, seconds = 0.0;
};

class OrbitContinuation {
 public:
  // parameter: lambda's index in problem.parameters(); multipliers may be null (no multipliers).
  OrbitContinuation(Problem& problem, int parameter, OrbitContinuationOptions options, OrbitMultipliers* multipliers);
  ~OrbitContinuation();

  // The orbit through a guess (u0 near the orbit, T near its period, flow: the direction of
  // motion at u0) at the parameter's present value: a grid from an adaptive run over T from u0,
  // then Newton at fixed lambda, then the multipliers. An empty flow: the rate at the end of a
  // period from u0 (an orbit stored without it).
  Status converge(const Vector& u0, double T, const Vector& flow, OrbitPoint& out);
  // The eigenvector of pd's real multiplier nearest -1 (pd a located period doubling).
  Status period_doubling_vector(const OrbitPoint& pd, Vector& v);
  // The start of the doubled branch at a located period doubling pd, where M v = -v: `first` is pd
  // traversed twice (period 2T on the grid run twice), `second` the orbit of period about 2T whose
  // component along v lies `distance` (arclength norm) from pd's, corrected on the row through it normal to
  // v. run(first, second) then traces the doubled branch.
  Status switch_period_doubling(const OrbitPoint& pd, const Vector& v, double distance, OrbitPoint& first,
                                OrbitPoint& second);
  // Traces the branch from two orbits near each other (the start, and a second giving the
  // direction); every orbit from `first` on is reported to the observer.
  // `stop` is asked between orbits (a signal): the run then ends with StopCode::Interrupted.
  // report_start false: the two are the last rows of an unfinished branch, already written (their
  // arclengths s as stored); the run reports only the orbits after them, numbered from 1.
  OrbitContinuationResult run(const OrbitPoint& first, const OrbitPoint& second, BranchObserver& observer,
                              const std::function<bool()>& stop = {}, bool report_start = true);
  // The scales of the arclength norm: from the first orbit of the branch (run does this unless set),
  // or given (a continued branch takes its first run's).
  void set_scales(const OrbitPoint& first);
  void set_scales(double state_scale, double period_scale);
  double state_scale() const { return state_scale_; }
  // The observables' names of the reported points, and the analysis columns (the multipliers).
  std::vector<std::string> observable_names() const;
  std::vector<std::string> analysis_columns() const;
  // The same for a problem whose observables are `problem_observables`, with `multipliers` per
  // orbit (what a study of orbit branches checks its [collect] names against before any run).
  static std::vector<std::string> observable_names(const std::vector<std::string>& problem_observables);
  static std::vector<std::string> analysis_columns(int multipliers);

  // The multipliers' accuracy (OrbitMultipliers::compute's; tolerance 0: the analysis's own, 1e-10)
  // and their passes' (ShootingMap::linearised's), for exact passes (every solve's matrix
  // factorised, B constant) or GMRES ones: exact, 1e-10 with passes at kTightPass; GMRES,
  // kInexactMultiplierTolerance, or kInexactCircleShare of the distance from the unit circle for a
  // multiplier at least 1/2 from it, with passes at kMultiplierPassShare of the tolerance. The discrete
  // map's multipliers differ from the flow's by the integrator's error (its rtol, 1e-6 by default)
  // anyway; on docs/periodic_orbits.md's FSI problem a pass at 1e-12 cost 1.8 times a Newton step's,
  // and Arnoldi took 18 passes to resolve its multipliers near 0.2 to 1e-6 against 10 to 12 to 1% of
  // their distance from the circle.
  static constexpr double kInexactMultiplierTolerance = 1e-6, kInexactCircleShare = 1e-2;
  static constexpr double kMultiplierPassShare = 1e-3;
  static MultiplierAccuracy multiplier_accuracy(bool exact_passes);
  static double multiplier_pass_tolerance(bool exact_passes);
  // Whether the branch records a new grid (an adaptive run over the period) from an orbit it has
  // just converged, for the next: where the orbit's own integration on the grid it was computed on
  // fails the integrator's error test somewhere (grid_error above 1, or not estimated). Else the
  // grid already meets the tolerance on it and serves on; the run it saves costs about a period of
  // evolve (on docs/periodic_orbits.md's FSI problem, two orbits in five kept their grid).
  static bool records_grid(double grid_error);

 private:
  // Corrects a predicted orbit on the arclength row through z along d (d: unit secant); fills
  // multipliers and observables.
  Status correct(const OrbitPoint& from, Vector u0, double T, double lambda, const Vector& du, double dT,
                 double dlambda, OrbitPoint& out);
  Status finish(OrbitPoint& p);
  // a correction's counts into `out` and the run's, then finish where it converged
  Status take(const OrbitCorrection& c, OrbitPoint& out);
  Status analyse(OrbitPoint& p);
  std::function<Status(const Vector&, Vector&)> monodromy();
  BranchPoint to_branch_point(const OrbitPoint& p, PointKind kind, const std::string& label, int index,
                              const Vector& tu, double tlambda) const;
  // the orbit at lambda = value between a and b (from their interpolation, at fixed lambda)
  bool land(const OrbitPoint& a, const OrbitPoint& b, double value, OrbitPoint& out);
  // the located zero of the test of `kind` between a and b (secant / Illinois in the arclength)
  bool locate(const OrbitPoint& a, const OrbitPoint& b, PointKind kind, OrbitPoint& out);
  double norm(const Vector& du, double dT, double dlambda) const;

  Problem& problem_;
  int parameter_;
  OrbitContinuationOptions options_;
  OrbitMultipliers* multipliers_;
  double state_scale_ = 1.0, period_scale_ = 1.0;  // of the norm
  bool scales_set_ = false;
  long newton_ = 0, krylov_ = 0;  // iterations of the corrections
  double multiplier_seconds_ = 0.0;
  // from construction: the branch's seconds include its first orbits, corrected before run()
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  ShootingMap map_;
  // from the last orbit analysed: the deflation in the corrections' preconditioner (BorderedDeflation)
  OrbitDeflation deflation_;
};

}  // namespace keller
