#include "continuation/start/StartSolver.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "continuation/Continuation.hpp"
#include "continuation/start/ResidualHomotopy.hpp"

namespace keller {

namespace {

// A stage's first step, its largest and its floor, as fractions of the distance to its target
// (in the arclength norm, which the parameter dominates where the state moves little).
constexpr double kFirstStepFraction = 0.1;
constexpr double kMaxStepFraction = 1.0;
constexpr double kMinStepFraction = 1e-7;

// Counts a stage's points and keeps its last.
class StageObserver final : public BranchObserver {
 public:
  void on_point(const BranchPoint&) override { ++points; }
  int points = 0;
};

const char* to_string(StartOptions::Path p) {
  switch (p) {
    case StartOptions::Path::Auto: return "auto";
    case StartOptions::Path::Parameters: return "parameters";
    case StartOptions::Path::Residual: return "residual";
    case StartOptions::Path::Off: return "off";
  }
  return "?";
}

}  // namespace

void StartOptions::declare(SceneSchema& s) {
  s.section("start",
            "the first steady state: Newton from the initial guess, else by continuation (docs/continuation.md)");
  s.string("start.homotopy", "auto",
           "auto: where Newton fails from the initial guess, continue from an easy state (the problem's homotopy "
           "parameters from their easy values, then the residual homotopy F(u) - (1 - s) F(guess)); parameters / "
           "residual: that path at once; off: Newton from the guess only",
           {"auto", "parameters", "residual", "off"});
  s.integer("start.max_steps", 200, "continuation steps allowed per stage of the path", Range::at_least(1));
}

StartOptions StartOptions::from_scene(const Scene& sc) {
  StartOptions o;
  const std::string& p = sc.string("start.homotopy");
  o.path = p == "parameters" ? Path::Parameters
           : p == "residual" ? Path::Residual
           : p == "off"      ? Path::Off
                             : Path::Auto;
  o.max_steps = static_cast<int>(sc.integer("start.max_steps"));
  return o;
}

StartSolver::StartSolver(Problem& problem, NewtonOptions newton, SparseLUOptions lu, StartOptions options, Say say)
    : problem_(problem), newton_(newton), lu_(lu), options_(options), say_(std::move(say)) {}

void StartSolver::say(const std::string& line) const {
  if (say_) say_(line);
}

bool StartSolver::newton(Vector& u, StartResult& r, const NewtonSolver::Observer& observer) {
  NewtonSolver solver(problem_, newton_, lu_);
  Vector v = u;
  const NewtonResult nr = solver.solve(v, observer);
  r.newton_iterations += nr.iterations;
  r.factorisations += nr.factorisations;
  r.status = nr.status;
  r.factorisation.reset();
  if (nr.converged()) {
    u = std::move(v);
    if (nr.factorisations > 0) {
      r.factorisation = solver.factorisation();
      r.jacobian = solver.jacobian();
      r.factorised_at = solver.factorised_at();
    }
  }
  return nr.converged();
}

StartResult StartSolver::solve(Vector& u, const NewtonSolver::Observer& first_newton) {
  const auto t0 = std::chrono::steady_clock::now();
  StartResult r;
  const bool first = options_.path == StartOptions::Path::Auto || options_.path == StartOptions::Path::Off;
  if (first && newton(u, r, first_newton)) {
    r.path = "Newton from the initial guess";
  } else if (options_.path != StartOptions::Path::Off) {
    if (first)
      say(fmt::format("first steady state: Newton from the initial guess failed ({}); continuing from an easier state",
                      r.status.describe()));
    const StartResult c = reach(u);
    r.status = c.status;
    r.path = c.path;
    r.by_continuation = c.by_continuation;
    r.newton_iterations += c.newton_iterations;
    r.factorisations += c.factorisations;
    r.steps = c.steps;
    r.factorisation = c.factorisation;
    r.jacobian = c.jacobian;
    r.factorised_at = c.factorised_at;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (r.status.is_ok() && r.by_continuation)
    say(fmt::format(
        "first steady state by continuation: {} ({} points, {} factorisations, {} Newton iterations, {:.1f} s)", r.path,
        r.steps, r.factorisations, r.newton_iterations, r.seconds));
  return r;
}

StartResult StartSolver::reach(Vector& u) {
  StartResult r;
  const Vector guess = u;
  const bool parameters = options_.path != StartOptions::Path::Residual && options_.path != StartOptions::Path::Off;
  const bool residual = options_.path != StartOptions::Path::Parameters && options_.path != StartOptions::Path::Off;
  const bool ok = (parameters && by_parameters(guess, u, r)) || (residual && by_residual(guess, u, r));
  if (ok)
    r.status = {};
  else if (r.status.is_ok())
    r.status = {StatusCode::NotConverged, fmt::format("no path found (start.homotopy = {})", to_string(options_.path))};
  return r;
}

bool StartSolver::continue_parameter(Problem& problem, const std::string& name, double target, Vector& u,
                                     StartResult& r, std::string& why) {
  ParameterSet& ps = problem.parameters();
  const double from = ps.get(name);
  const double distance = std::abs(target - from);
  if (!(distance > 0)) return true;
  ContinuationOptions o;
  o.parameter = name;
  o.direction = target > from ? +1 : -1;
  (o.direction > 0 ? o.stop.upper : o.stop.lower) = target;
  o.step.initial = kFirstStepFraction * distance;
  o.step.max = kMaxStepFraction * distance;
  o.step.min = kMinStepFraction * distance;
  o.stop.max_steps = options_.max_steps;
  o.events.branch_points = false;  // (a path to a state, not a branch to analyse)
  o.save_every = options_.max_steps + 1;
  Continuation stage(problem, o, newton_, lu_);
  StageObserver points;
  const ContinuationResult cr = stage.run(u, points);
  r.factorisations += cr.factorisations;
  r.steps += points.points;
  if (cr.code != StopCode::UpperBound && cr.code != StopCode::LowerBound) {
    why = fmt::format("{} from {:.6g} to {:.6g}: {}", name, from, target, cr.reason);
    ps.set(name, from);
    return false;
  }
  u = cr.last.u;
  ps.set(name, target);
  return true;
}

bool StartSolver::by_parameters(const Vector& guess, Vector& u, StartResult& r) {
  const std::vector<Problem::Homotopy> declared = problem_.homotopies();
  ParameterSet& ps = problem_.parameters();
  std::vector<Problem::Homotopy> used;  // set to their easy values, in order
  std::vector<double> targets;
  Vector easy = guess;
  bool solved = false, remade = false;
  for (const Problem::Homotopy& h : declared) {
    if (!ps.has(h.parameter) || ps.get(h.parameter) == h.easy_value) continue;
    used.push_back(h);
    targets.push_back(ps.get(h.parameter));
    ps.set(h.parameter, h.easy_value);
    easy = guess;
    if (newton(easy, r)) {
      solved = true;
      break;
    }
    // the problem's own guess at the easy values, where it depends on them (a guess made for the
    // scene's load or flow may be further from the easy state than one made for it)
    easy = problem_.initial_guess();
    if (easy.size() == guess.size() && easy != guess && newton(easy, r)) {
      solved = remade = true;
      break;
    }
  }
  auto restore = [&]() {
    for (size_t k = 0; k < used.size(); ++k) ps.set(used[k].parameter, targets[k]);
  };
  if (!solved) {
    restore();
    if (!used.empty())
      say("first steady state: Newton fails at the easy values of the problem's homotopy parameters too");
    return false;
  }
  // back to the set values, the last one set easy first
  std::string path, why;
  for (size_t k = used.size(); k-- > 0;) {
    path += fmt::format("{}{} from {:.6g} to {:.6g}", path.empty() ? "" : ", then ", used[k].parameter,
                        used[k].easy_value, targets[k]);
    if (!continue_parameter(problem_, used[k].parameter, targets[k], easy, r, why)) {
      restore();
      say("first steady state: continuation in " + why);
      return false;
    }
  }
  if (!newton(easy, r)) return false;
  u = std::move(easy);
  r.by_continuation = true;
  r.path = "continuation in " + path + (remade ? " (from the initial guess made at the easy values)" : "");
  return true;
}

bool StartSolver::by_residual(const Vector& guess, Vector& u, StartResult& r) {
  ResidualHomotopy h(problem_, guess);
  if (!h.status().is_ok()) {
    r.status = {h.status().code(), "the initial guess cannot be evaluated: " + h.status().message()};
    return false;
  }
  Vector v = guess;
  std::string why;
  if (!continue_parameter(h, "homotopy", 1.0, v, r, why)) {
    say("first steady state: continuation in the " + why);
    return false;
  }
  if (!newton(v, r)) return false;
  u = std::move(v);
  r.by_continuation = true;
  r.path = "the residual homotopy F(u) - (1 - s) F(guess) from s = 0 to 1";
  return true;
}

}  // namespace keller
