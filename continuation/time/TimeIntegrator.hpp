// Time integration of B(u) du/dt = -F(u) for any problem of the interface (core/Problem.hpp),
// B singular allowed (index-1 DAEs: algebraic rows), by variable-step BDF2 with a local-error
// estimate from the miss of a quadratic predictor and adaptive steps (docs/dynamics.md says why
// BDF2). A step solves G(u) = B(u) (c0 u + c1 u_n + c2 u_(n-1)) / h + F(u) = 0 by core's Newton
// solver on the matrix (c0 / h) B + J: a time step is a problem near the last one, so the
// factorisation is kept across steps while c0 / h stays within 30% of its value there and the chord
// contracts (core/RenewalPolicy), and convergence is judged by core/ConvergenceTest.
// The start: two backward Euler half steps, checked against one full step (Richardson); then
// BDF2. The engine sees only the problem interface; observers receive every accepted step.
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "core/SparseLU.hpp"

namespace keller {

struct TimeOptions {
  // BDF2 (the default: one solve per step) or SDIRK4 (continuation/time/TimeStepControl: five
  // solves per step, order 4: fewer, longer steps at tight tolerances, and a one-step map for
  // periodic orbits)
  enum class Method { Bdf2, Sdirk4 };
  Method method = Method::Bdf2;
  double t_end = 1.0;       // the run ends here (the last step lands on it)
  double initial_step = 0;  // the first step (the two half steps of the start span it); 0: 1e-6 t_end
  double min_step = 0;      // a step that fails below this ends the run; 0: 1e-12 t_end
  double max_step = std::numeric_limits<double>::infinity();
  bool fixed_step = false;  // every step initial_step, no error control (convergence studies)
  // The local error of a step, in the weighted RMS norm with weights atol + rtol max(|u_n|, |u_n+1|)
  // per unknown, must be at most 1.
  double relative_tolerance = 1e-4;
  double absolute_tolerance = 1e-8;
  int max_steps = 100000;

  static void declare(SceneSchema& schema);
  static TimeOptions from_scene(const Scene& scene);
  // The start and floor steps after the 0 defaults.
  double first_step() const;
  double step_floor() const;
};

// An accepted state of the run.
struct TimePoint {
  int step = 0;                                             // 0: the start
  double t = 0.0;                                           // time
  double h = 0.0;                                           // the step that led here (0 at the start)
  double next_step = 0.0;                                   // the step proposed next
  double error = std::numeric_limits<double>::quiet_NaN();  // the error estimate (1: the tolerance)
  int order = 0;                                            // 1: backward Euler (the start), 2: BDF2, 4: SDIRK4
  int iterations = 0;                                       // Newton iterations of the step
  int factorisations = 0;                                   // factorisations of the step, its rejected tries included
  int rejected = 0;                                         // tries rejected before it was accepted
  double seconds = 0.0;                                     // wall time since the run (or its resumption) began
  Vector u;
  std::vector<Vector> stages;  // SDIRK4: the stage states U_1..U_5 of the step (run_on_grid with stages only)
};

class TimeObserver {
 public:
  virtual ~TimeObserver() = default;
  virtual void on_step(const TimePoint& point) = 0;
  virtual void on_rejected(double /*t*/, double /*h*/, const std::string& /*why*/) {}
  virtual void on_finish(const std::string& /*reason*/, const TimePoint& /*last*/) {}
};

// Where a run continues from: up to three consecutive accepted states (the last first; BDF2 needs
// two, its error estimate three) and the step proposed next.
struct TimeHistory {
  std::vector<TimePoint> back;
  double next_step = 0.0;
};

// GridStepFailed: a step of run_on_grid did not converge (a given grid has no shorter step to try).
enum class TimeStop { End, MaxSteps, StepFloor, Interrupted, GridStepFailed };

struct TimeResult {
  TimeStop code = TimeStop::End;
  std::string reason;
  int steps = 0, rejected = 0;
  long factorisations = 0, newton_iterations = 0;
  double t = 0.0, seconds = 0.0;
};

class TimeIntegrator {
 public:
  TimeIntegrator(Problem& problem, TimeOptions options, NewtonOptions newton = {}, SparseLUOptions lu = {});
  ~TimeIntegrator();
  TimeIntegrator(const TimeIntegrator&) = delete;
  TimeIntegrator& operator=(const TimeIntegrator&) = delete;

  // Integrates from u0 at time t0 to options.t_end; the start is reported as step 0. `stop` is asked
  // between steps (a signal): the run then ends with TimeStop::Interrupted after its last step.
  TimeResult run(const Vector& u0, double t0, TimeObserver& observer, const std::function<bool()>& stop = {});
  // Integrates from u0 at time t0 through the given times (increasing, after t0) with no error
  // control: the first two steps by backward Euler (the start of run), the others by BDF2 from the
  // quadratic predictor, each a Newton solve on the kept factorisation as in run. The steps of a
  // grid recorded from an adaptive run (periodic orbits, continuation/orbits) reproduce its states
  // to the Newton tolerance. A step whose Newton fails ends the run (TimeStop::GridStepFailed, the
  // reason naming the step); t_end, the step bounds and max_steps are not consulted.
  // With SDIRK4 every step is an SDIRK4 step, and with `stages` each reported point carries its
  // step's stage states.
  TimeResult run_on_grid(const Vector& u0, double t0, const std::vector<double>& times, TimeObserver& observer,
                         const std::function<bool()>& stop = {}, bool stages = false);
  // Continues a run from its history (the last state is not reported again).
  TimeResult resume(const TimeHistory& history, TimeObserver& observer, const std::function<bool()>& stop = {});

  // Errors relative to the size of the deviation from a reference state instead of to the state
  // itself (weights atol + rtol max(|u_n - r|_inf, |u_n+1 - r|_inf), the same for every unknown: the
  // deviation's entries pass through zero as it turns): for a small perturbation of a steady state
  // r, whose dynamics a tolerance relative to |u| would not see.
  void set_error_reference(Vector reference) { reference_ = std::move(reference); }

  // The weighted RMS norm of a local error e (weights atol + rtol max(|a_i|, |b_i|)) over the
  // unknowns where `counted` is nonzero (empty: all).
  static double error_norm(const Vector& e, const Vector& a, const Vector& b, double rtol, double atol,
                           const std::vector<char>& counted = {});
  // The unknowns the error test counts: those whose column of B(u) has a nonzero entry, whose time
  // derivative appears in some row. The algebraic ones (no time derivative anywhere: a pressure,
  // the positions of a quasi-static part) follow the others; an index-2 one (the pressure of incompressible flow
  // with inertia) errs by O(1/h) times the start's inconsistency, which no step size cures, so they
  // are left out of the test as DASPK's and IDA's option suppresses them.
  static std::vector<char> differential_unknowns(const SparseMatrix& B);

 private:
  class StepProblem;
  struct Attempt;
  TimeResult integrate(TimeHistory history, TimeObserver& observer, const std::function<bool()>& stop);
  // One solve of G(u) = 0 from `u` (the predictor) for the coefficients c over step h.
  bool solve_step(const std::array<double, 3>& c, double h, const Vector& u_n, const Vector* u_prev, Vector& u,
                  Attempt& attempt);
  // Newton on the step problem as set, from u, on the kept factorisation while its coefficient
  // serves (the try's counts into attempt)
  bool newton_solve(Vector& u, Attempt& attempt);
  // One SDIRK4 step of h from u_n: u (in: ignored; out: u_(n+1)), the embedded error estimate, the
  // stage states where `stages` is given; k_guess is the last stage rate of the step before (the
  // stages' predictor; empty: none), and is set to this step's.
  bool sdirk_step(double h, const Vector& u_n, Vector& k_guess, Vector& u, Vector& error, Attempt& attempt,
                  std::vector<Vector>* stages);

  Problem& problem_;
  TimeOptions options_;
  std::unique_ptr<StepProblem> step_problem_;
  std::unique_ptr<NewtonSolver> newton_;
  double factorised_coefficient_ = 0.0;  // c0 / h of the kept factorisation (0: none)
  Vector reference_;                     // set_error_reference (empty: none)
  std::vector<char> counted_;            // differential_unknowns of B at the start
};

}  // namespace keller
