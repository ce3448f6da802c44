#include "continuation/time/TimeIntegrator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "continuation/time/TimeStepControl.hpp"

namespace keller {

namespace {
using Clock = std::chrono::steady_clock;
// With 0 in the scene, the first step is this fraction of t_end (the controller doubles it per
// step while the error allows: about 20 steps per factor 1e6 of time scales) ...
constexpr double kFirstStepFraction = 1e-6;
// ... and the step floor this fraction (a step this short is lost in the rounding of t).
constexpr double kStepFloorFraction = 1e-12;
// A step that would leave less than this fraction of itself before t_end is stretched to land on
// t_end (a sliver of a step would only add a solve).
constexpr double kLandingSlack = 0.1;
}  // namespace

void TimeOptions::declare(SceneSchema& s) {
  const TimeOptions d;
  s.section("evolve", "time integration of B du/dt = -F (keller evolve); every key in docs/dynamics.md");
  s.string("evolve.method", "bdf2",
           "bdf2 (one solve per step, second order) or sdirk4 (five solves per step, fourth order: fewer steps at "
           "tight tolerances)",
           {"bdf2", "sdirk4"});
  s.real("evolve.t_end", d.t_end, "the run ends at this time (from the start at t = 0)", Range::positive());
  s.real("evolve.initial_step", d.initial_step,
         "the first step (the two backward Euler half steps of the start span it); 0: 1e-6 t_end",
         Range::non_negative());
  s.real("evolve.min_step", d.min_step, "a step that fails below this ends the run; 0: 1e-12 t_end",
         Range::non_negative());
  s.real("evolve.max_step", d.max_step, "the largest step", Range::positive());
  s.boolean("evolve.fixed_step", d.fixed_step,
            "every step is initial_step and no error is estimated (for convergence studies)");
  s.real("evolve.relative_tolerance", d.relative_tolerance,
         "local error per step: weighted RMS with weights absolute_tolerance + relative_tolerance |u| (with a "
         "perturbation: relative_tolerance times the size of the deviation, max |u - u_steady|, instead of |u|)",
         Range{0.0, 1.0, true, true});
  s.real("evolve.absolute_tolerance", d.absolute_tolerance,
         "absolute part of the error weights (below the size of the dynamics to be followed)", Range::positive());
  s.integer("evolve.max_steps", d.max_steps, "accepted steps before the run ends", Range::at_least(1));
}

TimeOptions TimeOptions::from_scene(const Scene& scene) {
  TimeOptions o;
  o.method = scene.string("evolve.method") == "sdirk4" ? Method::Sdirk4 : Method::Bdf2;
  o.t_end = scene.real("evolve.t_end");
  o.initial_step = scene.real("evolve.initial_step");
  o.min_step = scene.real("evolve.min_step");
  o.max_step = scene.real("evolve.max_step");
  o.fixed_step = scene.boolean("evolve.fixed_step");
  o.relative_tolerance = scene.real("evolve.relative_tolerance");
  o.absolute_tolerance = scene.real("evolve.absolute_tolerance");
  o.max_steps = scene.integer("evolve.max_steps");
  if (o.fixed_step && !(o.initial_step > 0.0))
    throw scene.error("evolve.initial_step", "must be > 0 with evolve.fixed_step = true (it is the step)");
  if (o.max_step < o.step_floor())
    throw scene.error("evolve.max_step", fmt::format("{} is below evolve.min_step ({})", o.max_step, o.step_floor()));
  if (o.first_step() < o.step_floor())
    throw scene.error("evolve.initial_step",
                      fmt::format("{} is below evolve.min_step ({})", o.first_step(), o.step_floor()));
  return o;
}

double TimeOptions::first_step() const {
  const double h = initial_step > 0.0 ? initial_step : kFirstStepFraction * t_end;
  return std::min(h, max_step);
}

double TimeOptions::step_floor() const { return min_step > 0.0 ? min_step : kStepFloorFraction * t_end; }

// G(u) = B(u) (c0 u + w) / h + F(u) and its matrix (c0 / h) B(u) + J(u) (the derivative of B is left
// out: the chord's matrix, exact where B is constant); w = c1 u_n + c2 u_(n-1).
class TimeIntegrator::StepProblem final : public Problem {
 public:
  explicit StepProblem(Problem& inner) : inner_(inner) {}
  void set(const std::array<double, 3>& c, double h, const Vector& u_n, const Vector* u_prev) {
    coefficient_ = c[0] / h;
    w_ = (c[1] / h) * u_n;
    if (u_prev && c[2] != 0.0) w_ += (c[2] / h) * (*u_prev);
  }
  // G(u) = B(u) (coefficient u + w) + F(u) (an SDIRK stage: coefficient 1 / (h gamma))
  void set_affine(double coefficient, Vector w) {
    coefficient_ = coefficient;
    w_ = std::move(w);
  }
  double coefficient() const { return coefficient_; }

  std::string name() const override { return inner_.name(); }
  int size() const override { return inner_.size(); }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  double residual_scale() const override { return inner_.residual_scale(); }
  Vector initial_guess() override { return inner_.initial_guess(); }
  SolutionFields fields(const Vector& u) const override { return inner_.fields(u); }

  Status residual(const Vector& u, Vector& G) override {
    return time_dependent_residual(inner_, u, coefficient_ * u + w_, G);
  }
  Status jacobian(const Vector& u, Vector& G, SparseMatrix& M) override {
    Status st = inner_.jacobian(u, G, M);
    if (st.is_ok()) st = inner_.mass_matrix(u, B_);
    if (!st.is_ok()) return st;
    G += B_ * (coefficient_ * u + w_);
    const bool same = B_.nonZeros() == M.nonZeros() && B_.outerSize() == M.outerSize() &&
                      std::equal(M.outerIndexPtr(), M.outerIndexPtr() + M.outerSize() + 1, B_.outerIndexPtr()) &&
                      std::equal(M.innerIndexPtr(), M.innerIndexPtr() + M.nonZeros(), B_.innerIndexPtr());
    if (same) {
      Eigen::Map<Vector>(M.valuePtr(), M.nonZeros()) +=
          coefficient_ * Eigen::Map<const Vector>(B_.valuePtr(), B_.nonZeros());
    } else {
      const SparseMatrix sum = M + coefficient_ * B_;
      M = sum;
    }
    return {};
  }

 private:
  Problem& inner_;
  double coefficient_ = 0.0;
  Vector w_;
  SparseMatrix B_;
};

// What one try of a step cost.
struct TimeIntegrator::Attempt {
  int iterations = 0, factorisations = 0;
  Status status;
};

TimeIntegrator::TimeIntegrator(Problem& problem, TimeOptions options, NewtonOptions newton, SparseLUOptions lu)
    : problem_(problem), options_(options), step_problem_(std::make_unique<StepProblem>(problem)) {
  if (!(options_.t_end > 0.0)) throw std::invalid_argument("time integration: t_end must be > 0");
  if (options_.fixed_step && !(options_.initial_step > 0.0))
    throw std::invalid_argument("time integration: a fixed step needs initial_step > 0");
  newton_ = std::make_unique<NewtonSolver>(*step_problem_, newton, lu);
}

TimeIntegrator::~TimeIntegrator() = default;

double TimeIntegrator::error_norm(const Vector& e, const Vector& a, const Vector& b, double rtol, double atol,
                                  const std::vector<char>& counted) {
  double sum = 0.0;
  long n = 0;
  for (long i = 0; i < e.size(); ++i) {
    if (!counted.empty() && !counted[static_cast<size_t>(i)]) continue;
    const double w = atol + rtol * std::max(std::abs(a[i]), std::abs(b[i]));
    sum += (e[i] / w) * (e[i] / w);
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

std::vector<char> TimeIntegrator::differential_unknowns(const SparseMatrix& B) {
  std::vector<char> out(static_cast<size_t>(B.cols()), 0);
  for (int c = 0; c < B.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(B, c); it; ++it)
      if (it.value() != 0.0) out[static_cast<size_t>(c)] = 1;
  return out;
}

bool TimeIntegrator::solve_step(const std::array<double, 3>& c, double h, const Vector& u_n, const Vector* u_prev,
                                Vector& u, Attempt& attempt) {
  step_problem_->set(c, h, u_n, u_prev);
  return newton_solve(u, attempt);
}

bool TimeIntegrator::newton_solve(Vector& u, Attempt& attempt) {
  const bool kept = keeps_factorisation(step_problem_->coefficient(), factorised_coefficient_);
  const NewtonResult r = newton_->solve(u, {}, kept);
  attempt.iterations += r.iterations;
  attempt.factorisations += r.factorisations;
  if (r.factorisations > 0) factorised_coefficient_ = step_problem_->coefficient();
  attempt.status = r.status;
  return r.converged();
}

bool TimeIntegrator::sdirk_step(double h, const Vector& u_n, Vector& k_guess, Vector& u, Vector& error,
                                Attempt& attempt, std::vector<Vector>* stages) {
  const SdirkTableau& t = sdirk4();
  const double hg = h * t.gamma;
  std::array<Vector, SdirkTableau::kStages> K;
  if (stages) stages->clear();
  for (int i = 0; i < SdirkTableau::kStages; ++i) {
    Vector sum = u_n;  // u_n + h sum_(j < i) a_ij K_j
    for (int j = 0; j < i; ++j) sum += (h * t.a[i][j]) * K[j];
    const Vector& guess_rate = i > 0 ? K[i - 1] : k_guess;
    u = guess_rate.size() == u_n.size() ? Vector(sum + hg * guess_rate) : sum;
    step_problem_->set_affine(1.0 / hg, -sum / hg);  // K_i = (U_i - sum) / (h gamma)
    if (!newton_solve(u, attempt)) return false;
    K[i] = (u - sum) / hg;
    if (stages) stages->push_back(u);
  }
  std::array<const Vector*, SdirkTableau::kStages> rates;
  for (size_t j = 0; j < rates.size(); ++j) rates[j] = &K[j];
  error = t.embedded_error(h, rates);
  k_guess = K[SdirkTableau::kStages - 1];
  return true;
}

TimeResult TimeIntegrator::run(const Vector& u0, double t0, TimeObserver& observer, const std::function<bool()>& stop) {
  if (u0.size() != problem_.size())
    throw std::invalid_argument(
        fmt::format("time integration: the start has {} unknowns, the problem {}", u0.size(), problem_.size()));
  TimeHistory h;
  TimePoint start;
  start.t = t0;
  start.u = u0;
  start.next_step = options_.first_step();
  observer.on_step(start);
  h.back = {start};
  h.next_step = start.next_step;
  return integrate(std::move(h), observer, stop);
}

TimeResult TimeIntegrator::run_on_grid(const Vector& u0, double t0, const std::vector<double>& times,
                                       TimeObserver& observer, const std::function<bool()>& stop, bool stages) {
  if (u0.size() != problem_.size())
    throw std::invalid_argument(
        fmt::format("time integration: the start has {} unknowns, the problem {}", u0.size(), problem_.size()));
  for (size_t k = 0; k < times.size(); ++k)
    if (!(times[k] > (k == 0 ? t0 : times[k - 1])))
      throw std::invalid_argument(
          fmt::format("time integration: grid time {} ({}) does not follow the one before", k, times[k]));
  const auto t_start = Clock::now();
  TimeResult result;
  factorised_coefficient_ = 0.0;
  std::vector<TimePoint> back(1);  // the last accepted states, the newest first
  Vector k_guess;                  // SDIRK4: the last stage rate of the step before
  back[0].t = t0;
  back[0].u = u0;
  observer.on_step(back[0]);
  for (size_t k = 0; k < times.size(); ++k) {
    const TimePoint& now = back.front();
    if (stop && stop()) {
      result.code = TimeStop::Interrupted;
      result.reason = fmt::format("interrupted at t = {:.10g}", now.t);
      break;
    }
    const double h = times[k] - now.t;
    const bool sdirk = options_.method == TimeOptions::Method::Sdirk4;
    const int order = sdirk ? 4 : k < 2 ? 1 : 2;
    Attempt attempt;
    Vector u;
    std::vector<Vector> stage_states;
    bool ok = false;
    if (sdirk) {
      Vector error;
      ok = sdirk_step(h, now.u, k_guess, u, error, attempt, stages ? &stage_states : nullptr);
    } else {
      const double h1 = back.size() > 1 ? now.t - back[1].t : h;
      std::array<double, 3> x{1.0, 0.0, 0.0};  // the predictor: constant at the start, else quadratic
      if (order == 2) x = extrapolation_weights(3, h, h1, back[1].t - back[2].t);
      u = x[0] * now.u;
      for (size_t j = 1; j < back.size(); ++j) u += x[j] * back[j].u;
      ok = solve_step(bdf_coefficients(order, h, h1), h, now.u, order == 2 ? &back[1].u : nullptr, u, attempt);
    }
    result.factorisations += attempt.factorisations;
    result.newton_iterations += attempt.iterations;
    if (!ok) {
      result.code = TimeStop::GridStepFailed;
      result.reason = fmt::format("the step to t = {:.10g} (step {} of the grid) failed: Newton: {}", times[k], k + 1,
                                  attempt.status.describe());
      break;
    }
    TimePoint p;
    p.step = now.step + 1;
    p.t = times[k];
    p.h = h;
    p.next_step = k + 1 < times.size() ? times[k + 1] - times[k] : h;
    p.order = order;
    p.iterations = attempt.iterations;
    p.factorisations = attempt.factorisations;
    p.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    p.u = std::move(u);
    p.stages = std::move(stage_states);
    back.insert(back.begin(), std::move(p));
    if (back.size() > 3) back.pop_back();
    ++result.steps;
    observer.on_step(back.front());
    back.front().stages.clear();
  }
  if (result.reason.empty()) result.reason = "reached the end of the grid";
  result.t = back.front().t;
  result.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  observer.on_finish(result.reason, back.front());
  return result;
}

TimeResult TimeIntegrator::resume(const TimeHistory& history, TimeObserver& observer,
                                  const std::function<bool()>& stop) {
  if (history.back.empty()) throw std::invalid_argument("time integration: nothing to resume from");
  for (const TimePoint& p : history.back)
    if (p.u.size() != problem_.size())
      throw std::invalid_argument(
          fmt::format("time integration: a stored state has {} unknowns, the problem {}", p.u.size(), problem_.size()));
  return integrate(history, observer, stop);
}

TimeResult TimeIntegrator::integrate(TimeHistory history, TimeObserver& observer, const std::function<bool()>& stop) {
  const auto t_start = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - t_start).count(); };
  TimeResult result;
  std::vector<TimePoint>& back = history.back;  // the last accepted states, the newest first
  if (back.size() > 3) back.resize(3);
  const double floor = options_.step_floor();
  const double rtol = options_.relative_tolerance, atol = options_.absolute_tolerance;
  const bool relative_to_reference = reference_.size() == problem_.size();
  {
    SparseMatrix B;
    const Status st = problem_.mass_matrix(back.front().u, B);
    counted_ = st.is_ok() ? differential_unknowns(B) : std::vector<char>{};
  }
  auto error_of = [&](const Vector& e, const Vector& a, const Vector& b) {
    if (!relative_to_reference) return error_norm(e, a, b, rtol, atol, counted_);
    // the size of the deviation as a whole: its entries pass through zero as it turns
    const double size =
        std::max((a - reference_).lpNorm<Eigen::Infinity>(), (b - reference_).lpNorm<Eigen::Infinity>());
    const Vector scale = Vector::Constant(e.size(), size);
    return error_norm(e, scale, scale, rtol, atol, counted_);
  };
  double h = options_.fixed_step ? options_.initial_step : std::clamp(history.next_step, floor, options_.max_step);
  int rejected = 0, factorisations = 0;  // of the step under way
  Vector k_guess;                        // SDIRK4: the last stage rate of the last accepted step
  factorised_coefficient_ = 0.0;         // a resumed run starts on a factorisation of its own
  auto finish = [&](TimeStop code, const std::string& reason) {
    result.code = code;
    result.reason = reason;
    result.t = back.front().t;
    result.seconds = seconds();
    observer.on_finish(reason, back.front());
    return result;
  };
  bool at_floor = false;  // a step of the floor's length was rejected: no shorter one is allowed
  auto reject = [&](double t, double tried, const std::string& why, double next) {
    observer.on_rejected(t, tried, why);
    ++rejected;
    ++result.rejected;
    at_floor = tried <= floor;
    h = next;
  };
  // a try's cost; a failed one is rejected and retried with a shorter step
  auto tried = [&](bool ok, const Attempt& attempt, double t_next, double tried_step) {
    factorisations += attempt.factorisations;
    result.factorisations += attempt.factorisations;
    result.newton_iterations += attempt.iterations;
    if (!ok) reject(t_next, tried_step, "Newton: " + attempt.status.describe(), kNewtonFailureShrink * tried_step);
    return ok;
  };
  // the error test of a step of the given order from its local error e (between states a and b):
  // the next step, or nothing where the step is rejected (and retried shorter); without error
  // control the same step again
  auto judged = [&](const Vector& e, const Vector& a, const Vector& b, int order, double t_next, double tried_step,
                    double& error) -> std::optional<double> {
    error = std::numeric_limits<double>::quiet_NaN();
    if (options_.fixed_step) return options_.initial_step;
    error = error_of(e, a, b);
    const StepDecision d = decide_step(error, tried_step, order, floor, options_.max_step);
    if (!d.accept) {
      reject(t_next, tried_step, fmt::format("error estimate {:.3g}{}", error, order == 1 ? " of the start" : ""),
             d.next);
      return std::nullopt;
    }
    return d.next;
  };
  auto point = [](double t, double step, double next, double error, int order, int iterations, Vector u) {
    TimePoint p;
    p.t = t;
    p.h = step;
    p.next_step = next;
    p.error = error;
    p.order = order;
    p.iterations = iterations;
    p.u = std::move(u);
    return p;
  };
  auto accept = [&](TimePoint p) {
    p.step = back.front().step + 1;
    p.rejected = rejected;
    p.factorisations = factorisations;
    p.seconds = seconds();
    rejected = 0;
    factorisations = 0;
    back.insert(back.begin(), std::move(p));
    if (back.size() > 3) back.pop_back();
    ++result.steps;
    observer.on_step(back.front());
  };

  for (;;) {
    const TimePoint& now = back.front();
    const double remaining = options_.t_end - now.t;
    if (!(remaining > kStepFloorFraction * options_.t_end)) return finish(TimeStop::End, "reached t_end");
    if (now.step >= options_.max_steps)
      return finish(TimeStop::MaxSteps,
                    fmt::format("max_steps ({}) reached at t = {:.10g}", options_.max_steps, now.t));
    if (stop && stop()) return finish(TimeStop::Interrupted, fmt::format("interrupted at t = {:.10g}", now.t));
    if (h < floor || at_floor)
      return finish(TimeStop::StepFloor,
                    fmt::format("the step fell below min_step ({:.3e}) at t = {:.10g}", floor, now.t));
    bool lands = false;
    if (h >= remaining * (1.0 - kLandingSlack)) {
      h = remaining;
      lands = true;
    }
    const double t_next = lands ? options_.t_end : now.t + h;
    Attempt attempt;

    if (options_.method == TimeOptions::Method::Sdirk4) {
      Vector u, e;
      if (!tried(sdirk_step(h, now.u, k_guess, u, e, attempt, nullptr), attempt, t_next, h)) continue;
      double error = 0.0;
      const std::optional<double> next = judged(e, now.u, u, 3, t_next, h, error);
      if (!next) continue;
      accept(point(t_next, t_next - now.t, *next, error, 4, attempt.iterations, std::move(u)));
      h = *next;
      continue;
    }

    if (back.size() < 3) {
      // the start: two backward Euler half steps, and (adaptive) one full step to estimate their error
      const TimePoint origin = back.back();  // the start itself (a resumed start that had not got further)
      back.assign(1, origin);
      const double half = 0.5 * h;
      Vector ua = origin.u, ub, uf = origin.u;
      bool ok = solve_step(bdf_coefficients(1, half, half), half, origin.u, nullptr, ua, attempt);
      if (ok) {
        ub = ua;
        ok = solve_step(bdf_coefficients(1, half, half), half, ua, nullptr, ub, attempt);
      }
      if (ok && !options_.fixed_step) ok = solve_step(bdf_coefficients(1, h, h), h, origin.u, nullptr, uf, attempt);
      if (!tried(ok, attempt, t_next, h)) continue;
      double error = 0.0;
      const std::optional<double> next = judged(kStartErrorFactor * (ub - uf), origin.u, ub, 1, t_next, h, error);
      if (!next) continue;
      accept(point(origin.t + half, half, half, std::numeric_limits<double>::quiet_NaN(), 1, attempt.iterations,
                   std::move(ua)));
      accept(point(t_next, t_next - (origin.t + half), *next, error, 1, 0, std::move(ub)));
      h = *next;
      continue;
    }

    // BDF2 from the quadratic predictor through the last three states
    const double h1 = now.t - back[1].t, h2 = back[1].t - back[2].t;
    const std::array<double, 3> x = extrapolation_weights(3, h, h1, h2);
    const Vector predicted = x[0] * now.u + x[1] * back[1].u + x[2] * back[2].u;
    Vector u = predicted;
    if (!tried(solve_step(bdf_coefficients(2, h, h1), h, now.u, &back[1].u, u, attempt), attempt, t_next, h)) continue;
    double error = 0.0;
    const std::optional<double> next =
        judged(bdf2_error_factor(h, h1, h2) * (u - predicted), now.u, u, 2, t_next, h, error);
    if (!next) continue;
    accept(point(t_next, t_next - now.t, *next, error, 2, attempt.iterations, std::move(u)));
    h = *next;
  }
}

}  // namespace keller
