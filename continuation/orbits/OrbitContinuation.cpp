#include "continuation/orbits/OrbitContinuation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace keller {

namespace {
// the step after an accepted one: grown by this where the corrector took fewer iterations than
// the target, shrunk where it took more; halved after a failure
constexpr double kGrow = 1.5, kShrink = 0.7, kFailure = 0.5;
// the two steps that make a guess consistent, each this fraction of the period: long enough that
// their matrices are not dominated by B / h (at 1e-9 T the first step of a moving-mesh problem failed
// to converge from the normal form's guess), short enough that the guess moves along the orbit
// only by that fraction
constexpr double kConsistentStep = 1e-6;

}  // namespace

OrbitContinuation::OrbitContinuation(Problem& problem, int parameter, OrbitContinuationOptions options,
                                     OrbitMultipliers* multipliers)
    : problem_(problem),
      parameter_(parameter),
      options_(std::move(options)),
      multipliers_(multipliers),
      map_(problem, parameter, options_.shooting) {}

OrbitContinuation::~OrbitContinuation() = default;

std::vector<std::string> OrbitContinuation::observable_names(const std::vector<std::string>& problem_observables) {
  std::vector<std::string> names{"period", "amplitude"};
  for (const std::string& o : problem_observables) {
    names.push_back(o);
    names.push_back("amplitude:" + o);
  }
  return names;
}

std::vector<std::string> OrbitContinuation::observable_names() const {
  return observable_names(problem_.observable_names());
}

std::vector<std::string> OrbitContinuation::analysis_columns() const { return analysis_columns(options_.multipliers); }

std::vector<std::string> OrbitContinuation::analysis_columns(int multipliers) {
  std::vector<std::string> c;
  for (int i = 1; i <= multipliers; ++i) {
    c.push_back(fmt::format("mu{}_re", i));
    c.push_back(fmt::format("mu{}_im", i));
  }
  return c;
}

double OrbitContinuation::norm(const Vector& du, double dT, double dlambda) const {
  const double theta = options_.theta, n = static_cast<double>(du.size());
  const double dt = dT / period_scale_;
  return std::sqrt(theta * du.squaredNorm() / (n * state_scale_ * state_scale_) +
                   (1.0 - theta) * (dlambda * dlambda + dt * dt));
}

MultiplierAccuracy OrbitContinuation::multiplier_accuracy(bool exact_passes) {
  if (exact_passes) return {};
  return {kInexactMultiplierTolerance, kInexactCircleShare};
}

double OrbitContinuation::multiplier_pass_tolerance(bool exact_passes) {
  return exact_passes ? ShootingMap::kTightPass : kMultiplierPassShare * kInexactMultiplierTolerance;
}

std::function<Status(const Vector&, Vector&)> OrbitContinuation::monodromy() {
  const double pass = multiplier_pass_tolerance(map_.exact_passes());
  return [this, pass](const Vector& v, Vector& Mv) { return map_.linearised(v, 0.0, 0.0, Mv, pass); };
}

Status OrbitContinuation::analyse(OrbitPoint& p) {
  p.multipliers.clear();
  p.trivial = -1;
  if (!multipliers_ || options_.multipliers <= 0) return {};
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<Eigen::VectorXcd> vectors;
  const Status st = multipliers_->compute(problem_.size(), monodromy(), p.multipliers, p.trivial, &vectors,
                                          multiplier_accuracy(map_.exact_passes()));
  if (st.is_ok()) deflation_ = OrbitDeflation::from(p.multipliers, vectors, p.trivial);
  multiplier_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

bool OrbitContinuation::records_grid(double grid_error) { return !(grid_error <= 1.0); }

Status OrbitContinuation::finish(OrbitPoint& p) {
  p.flow = map_.end_rate();
  p.states = map_.states();
  p.grid_error = map_.step_error(options_.time.relative_tolerance, options_.time.absolute_tolerance);
  p.times.assign(1, 0.0);
  for (double f : p.grid.fractions) p.times.push_back(f * p.period);
  return analyse(p);
}

Status OrbitContinuation::converge(const Vector& u0, double T, const Vector& flow, OrbitPoint& out) {
  out = OrbitPoint{};
  out.u0 = u0;
  out.period = T;
  out.lambda = problem_.parameters().value(parameter_);
  {
    // a guess (the normal form's orbit) need not satisfy the algebraic equations (B's zero rows, the
    // constraints a pressure enforces): a backward Euler step of kConsistentStep T makes it do so,
    // but it leaves an index-2 multiplier (a pressure) off by O(1 / h); the BDF2 step after it
    // starts from a consistent state and sets that right. Else the adaptive run's error estimate
    // sees the inconsistency at every step length and the grid cannot start, and Newton starts
    // from a residual the size of that pressure error
    class Last final : public TimeObserver {
     public:
      void on_step(const TimePoint& p) override { u = p.u; }
      Vector u;
    } last;
    TimeOptions be;
    be.t_end = 2.0 * kConsistentStep * T;
    const TimeResult r = TimeIntegrator(problem_, be, options_.shooting.newton, options_.shooting.lu)
                             .run_on_grid(u0, 0.0, {kConsistentStep * T, 2.0 * kConsistentStep * T}, last);
    if (r.code != TimeStop::End) return {StatusCode::NotConverged, "orbit start: " + r.reason};
    out.u0 = last.u;
  }
  try {
    out.grid = record_grid(problem_, out.u0, T, options_.time, options_.shooting.newton, options_.shooting.lu);
  } catch (const std::runtime_error& e) {
    return {StatusCode::NotConverged, e.what()};
  }
  Vector normal = flow;
  if (normal.size() == 0) {  // the flow at u0: the rate at the end of a period from it
    const Status st = map_.integrate(out.u0, T, out.grid);
    if (!st.is_ok()) return st;
    normal = map_.end_rate();
  }
  const Vector ref = out.u0;
  const OrbitCorrection c = OrbitCorrector(map_, options_.corrector, &deflation_)
                                .correct(out.u0, out.period, out.lambda, false, out.grid, ref, normal);
  return take(c, out);
}

Status OrbitContinuation::correct(const OrbitPoint& from, Vector u0, double T, double lambda, const Vector& du,
                                  double dT, double dlambda, OrbitPoint& out) {
  out = OrbitPoint{};
  OrbitRow row;  // the inner product of the norm with the unit direction (du, dT, dlambda)
  const double theta = options_.theta;
  row.a_u = (theta / (static_cast<double>(du.size()) * state_scale_ * state_scale_)) * du;
  row.a_T = (1.0 - theta) * dT / (period_scale_ * period_scale_);
  row.a_lambda = (1.0 - theta) * dlambda;
  row.z_u = u0;
  row.z_T = T;
  row.z_lambda = lambda;
  out.grid = from.grid;
  const OrbitCorrection c = OrbitCorrector(map_, options_.corrector, &deflation_)
                                .correct(u0, T, lambda, true, out.grid, from.u0, from.flow, row);
  out.u0 = std::move(u0);
  out.period = T;
  out.lambda = lambda;
  return take(c, out);
}

Status OrbitContinuation::period_doubling_vector(const OrbitPoint& pd, Vector& v) {
  if (!multipliers_) throw std::logic_error("period doubling: no multipliers");
  problem_.parameters().set(parameter_, pd.lambda);
  Status st = map_.integrate(pd.u0, pd.period, pd.grid);
  if (!st.is_ok()) return st;
  std::vector<std::complex<double>> values;
  std::vector<Eigen::VectorXcd> vectors;
  int trivial = -1;
  st = multipliers_->compute(problem_.size(), monodromy(), values, trivial, &vectors,
                             multiplier_accuracy(map_.exact_passes()));
  if (!st.is_ok()) return st;
  int best = -1;
  for (size_t i = 0; i < values.size(); ++i)
    if (values[i].imag() == 0.0 && static_cast<int>(i) != trivial &&
        (best < 0 || std::abs(values[i] + 1.0) < std::abs(values[static_cast<size_t>(best)] + 1.0)))
      best = static_cast<int>(i);
  if (best < 0 || static_cast<size_t>(best) >= vectors.size())
    return {StatusCode::NotConverged, "period doubling: no real multiplier near -1"};
  v = vectors[static_cast<size_t>(best)].real();
  return {};
}

void OrbitContinuation::set_scales(const OrbitPoint& first) {
  const double rms = first.u0.norm() / std::sqrt(static_cast<double>(std::max<long>(first.u0.size(), 1)));
  set_scales(options_.state_scale > 0.0 ? options_.state_scale : rms > 0.0 ? rms : 1.0, first.period);
}

void OrbitContinuation::set_scales(double state_scale, double period_scale) {
  state_scale_ = state_scale > 0.0 ? state_scale : 1.0;
  period_scale_ = period_scale > 0.0 ? period_scale : 1.0;
  scales_set_ = true;
}

Status OrbitContinuation::switch_period_doubling(const OrbitPoint& pd, const Vector& v, double distance,
                                                 OrbitPoint& first, OrbitPoint& second) {
  set_scales(pd);
  const double size = norm(v, 0.0, 0.0);
  if (!(size > 0.0)) throw std::invalid_argument("period doubling switch: the eigenvector is zero");
  const Vector dir = v / size;
  first = pd;
  first.period = 2.0 * pd.period;
  first.grid.fractions.clear();
  for (int half = 0; half < 2; ++half)
    for (double f : pd.grid.fractions) first.grid.fractions.push_back(0.5 * (half + f));
  problem_.parameters().set(parameter_, pd.lambda);
  Status st = map_.integrate(first.u0, first.period, first.grid);
  if (st.is_ok()) st = finish(first);
  if (!st.is_ok()) return st;
  st = correct(first, pd.u0 + distance * dir, first.period, pd.lambda, dir, 0.0, 0.0, second);
  if (!st.is_ok()) return st;
  second.s = norm(second.u0 - first.u0, second.period - first.period, second.lambda - first.lambda);
  try {
    second.grid =
        record_grid(problem_, second.u0, second.period, options_.time, options_.shooting.newton, options_.shooting.lu);
  } catch (const std::runtime_error&) {
    // keep the doubled grid
  }
  return {};
}

BranchPoint OrbitContinuation::to_branch_point(const OrbitPoint& p, PointKind kind, const std::string& label, int index,
                                               const Vector& tu, double tlambda) const {
  BranchPoint b;
  b.tu = tu;
  b.tlambda = tlambda;
  b.index = index;
  b.kind = kind;
  b.label = label;
  b.s = p.s;
  b.lambda = p.lambda;
  b.u = p.u0;
  b.iterations = p.iterations;
  b.residual = p.residual;
  b.save = true;
  // observables: period, amplitude, then each problem observable at u0 and its amplitude
  // the times of the states, and the range over the period of the unknown that varies most and of
  // each observable (periodic_range)
  const size_t m = p.states.size();
  const std::vector<double>& times = p.times;
  std::vector<double> series(m);
  const bool sampled = m >= 4 && times.size() == m;
  double amplitude = std::numeric_limits<double>::quiet_NaN();
  if (sampled) {
    Vector lo = p.states.front(), hi = p.states.front();
    for (const Vector& u : p.states) {
      lo = lo.cwiseMin(u);
      hi = hi.cwiseMax(u);
    }
    Eigen::Index widest = 0;
    (hi - lo).maxCoeff(&widest);
    for (size_t k = 0; k < m; ++k) series[k] = p.states[k][widest];
    amplitude = periodic_range(times, series);
  }
  b.observables = {p.period, amplitude};
  const size_t n_obs = problem_.observable_names().size();
  if (n_obs > 0) {
    std::vector<double> at0, v;
    if (!problem_.observables(p.u0, at0).is_ok()) at0.assign(n_obs, std::numeric_limits<double>::quiet_NaN());
    std::vector<std::vector<double>> values(n_obs, std::vector<double>(m, std::numeric_limits<double>::quiet_NaN()));
    for (size_t k = 0; sampled && k < m; ++k)
      if (problem_.observables(p.states[k], v).is_ok())
        for (size_t i = 0; i < n_obs; ++i) values[i][k] = v[i];
    for (size_t i = 0; i < n_obs; ++i) {
      b.observables.push_back(at0[i]);
      b.observables.push_back(sampled ? periodic_range(times, values[i]) : std::numeric_limits<double>::quiet_NaN());
    }
  }
  if (options_.multipliers > 0) {
    b.analysed = true;
    b.analysis.assign(2 * static_cast<size_t>(options_.multipliers), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < p.multipliers.size() && static_cast<int>(i) < options_.multipliers; ++i) {
      b.analysis[2 * i] = p.multipliers[i].real();
      b.analysis[2 * i + 1] = p.multipliers[i].imag();
    }
    b.count = MultiplierCounts::of(p.multipliers, p.trivial).unstable;
    b.analysis_width = static_cast<int>(b.analysis.size());
  }
  return b;
}

Status OrbitContinuation::take(const OrbitCorrection& c, OrbitPoint& out) {
  out.iterations = c.iterations;
  out.krylov_iterations = c.krylov_iterations;
  out.residual = c.residual;
  newton_ += c.iterations;
  krylov_ += c.krylov_iterations;
  if (!c.status.is_ok()) return c.status;
  return finish(out);
}

bool OrbitContinuation::land(const OrbitPoint& a, const OrbitPoint& b, double value, OrbitPoint& out) {
  const double t = (value - a.lambda) / (b.lambda - a.lambda);
  OrbitRow fixed;  // lambda = value
  fixed.z_lambda = value;
  Vector u0 = a.u0 + t * (b.u0 - a.u0);
  double T = a.period + t * (b.period - a.period), lambda = value;
  OrbitCorrector corrector(map_, options_.corrector, &deflation_);
  OrbitCorrection c = corrector.correct(u0, T, lambda, true, a.grid, a.u0, a.flow, fixed);
  out = OrbitPoint{};
  out.grid = a.grid;
  if (c.status.is_ok()) {
    // then again on its own grid: a's was adapted to an orbit a step away, and a requested value's
    // orbit is one a user reads (on the Brusselator's branch at rtol 1e-6, the stop at b = 5.5 on
    // the grid of an orbit 0.1 away erred by 1.09e-6 in the period, on its own grid by 8.0e-7, as
    // with steps short enough that the neighbour's grid is nearly its own)
    try {
      out.grid = record_grid(problem_, u0, T, options_.time, options_.shooting.newton, options_.shooting.lu);
      const Vector ref = u0, normal = map_.end_rate();
      const OrbitCorrection again = corrector.correct(u0, T, lambda, true, out.grid, ref, normal, fixed);
      c.status = again.status;
      c.iterations += again.iterations;
      c.krylov_iterations += again.krylov_iterations;
      c.residual = again.residual;
    } catch (const std::runtime_error&) {
      out.grid = a.grid;  // no run over the period from it: the orbit on a's grid
    }
  }
  out.u0 = std::move(u0);
  out.period = T;
  out.lambda = lambda;
  out.s = a.s + t * (b.s - a.s);
  return take(c, out).is_ok();
}

bool OrbitContinuation::locate(const OrbitPoint& a, const OrbitPoint& b, PointKind kind, OrbitPoint& out) {
  double fa = multiplier_test(a.multipliers, a.trivial, kind), fb = multiplier_test(b.multipliers, b.trivial, kind);
  if (std::isnan(fa) || std::isnan(fb) || fa * fb > 0.0) return false;
  const Vector du = b.u0 - a.u0;
  const double dT = b.period - a.period, dl = b.lambda - a.lambda;
  const double length = norm(du, dT, dl);
  if (!(length > 0.0)) return false;
  double sa = 0.0, sb = 1.0;
  int side = 0;  // Illinois: the end kept twice in a row has its value halved
  for (int it = 0; it < options_.locate_iterations; ++it) {
    const double s = sa + (sb - sa) * fa / (fa - fb);
    OrbitPoint p;
    if (!correct(a, a.u0 + s * du, a.period + s * dT, a.lambda + s * dl, du / length, dT / length, dl / length, p)
             .is_ok())
      return false;
    const double f = multiplier_test(p.multipliers, p.trivial, kind);
    if (std::isnan(f)) return false;
    p.s = a.s + s * (b.s - a.s);
    out = std::move(p);
    if (std::abs(f) <= options_.locate_tolerance) return true;
    if ((f > 0.0) == (fa > 0.0)) {
      sa = s;
      fa = f;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      sb = s;
      fb = f;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
  }
  return std::abs(multiplier_test(out.multipliers, out.trivial, kind)) <= 1e3 * options_.locate_tolerance;
}

OrbitContinuationResult OrbitContinuation::run(const OrbitPoint& first, const OrbitPoint& second,
                                               BranchObserver& observer, const std::function<bool()>& stop,
                                               bool report_start) {
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count(); };
  OrbitContinuationResult result;
  observer.on_start(observable_names(), {});
  int index = 0;
  Vector tu;  // the unit secant's state and parameter parts, reported as the tangent
  double tl = 0.0;
  auto report = [&](const OrbitPoint& p, PointKind kind, const std::string& label, double step) {
    BranchPoint b = to_branch_point(p, kind, label, index++, tu, tl);
    b.step = step;
    b.seconds = seconds();
    observer.on_point(b);
    ++result.points;
    return b;
  };
  OrbitPoint a = first, b = second;
  if (!scales_set_) set_scales(a);
  const double ab = norm(b.u0 - a.u0, b.period - a.period, b.lambda - a.lambda);
  if (report_start) {
    a.s = 0.0;
    b.s = ab;
  }
  double ds = report_start ? options_.step : std::clamp(ab, options_.min_step, options_.max_step);
  tu = (b.u0 - a.u0) / ab;
  tl = (b.lambda - a.lambda) / ab;
  BranchPoint last;
  if (report_start) {
    report(a, PointKind::Start, "", ds);
    last = report(b, PointKind::Regular, "", ds);
  } else {
    index = 1;  // the two are rows of the branch already: the next point is the one after them
    last = to_branch_point(b, PointKind::Regular, "", 0, tu, tl);
  }
  auto end = [&](StopCode code, std::string reason) {
    result.code = code;
    result.reason = std::move(reason);
    result.last = b;
    result.counts = map_.counts();
    result.newton_iterations = newton_;
    result.krylov_iterations = krylov_;
    result.multiplier_seconds = multiplier_seconds_;
    result.seconds = seconds();
    observer.on_finish(result.reason, last);
    return result;
  };
  for (;;) {
    if (stop && stop())
      return end(StopCode::Interrupted,
                 fmt::format("interrupted at {} = {:.10g}", problem_.parameters().info(parameter_).name, b.lambda));
    if (result.points >= options_.max_points)
      return end(StopCode::MaxSteps, fmt::format("{} orbits computed", result.points));
    if (b.lambda > options_.lambda_max) return end(StopCode::UpperBound, "passed the upper bound");
    if (b.lambda < options_.lambda_min) return end(StopCode::LowerBound, "passed the lower bound");
    // the secant from a to b, in the arclength norm
    Vector du = b.u0 - a.u0;
    double dT = b.period - a.period, dl = b.lambda - a.lambda;
    const double length = norm(du, dT, dl);
    du /= length;
    dT /= length;
    dl /= length;
    tu = du;
    tl = dl;
    OrbitPoint next;
    Status st = correct(b, b.u0 + ds * du, b.period + ds * dT, b.lambda + ds * dl, du, dT, dl, next);
    if (!st.is_ok()) {
      observer.on_rejected(b.lambda + ds * dl, ds, st);
      ++result.rejected;
      ds *= kFailure;
      if (ds < options_.min_step)
        return end(StopCode::StepFloor, fmt::format("the step fell below {:g}: {}", options_.min_step, st.describe()));
      continue;
    }
    next.s = b.s + norm(next.u0 - b.u0, next.period - b.period, next.lambda - b.lambda);
    // the bifurcations of orbits between b and next, in order along the branch
    std::vector<std::pair<PointKind, std::string>> crossed;
    if (options_.multipliers > 0) {
      const MultiplierCounts cb = MultiplierCounts::of(b.multipliers, b.trivial),
                             cn = MultiplierCounts::of(next.multipliers, next.trivial);
      if (cb.above_plus_one != cn.above_plus_one) {
        const double dl_next = next.lambda - b.lambda;
        crossed.emplace_back(dl_next * dl < 0.0 ? PointKind::Fold : PointKind::BranchPoint,
                             dl_next * dl < 0.0 ? "fold" : "bp");
      }
      if (cb.below_minus_one != cn.below_minus_one) crossed.emplace_back(PointKind::PeriodDoubling, "pd");
      if (cb.pairs_outside != cn.pairs_outside) crossed.emplace_back(PointKind::NeimarkSacker, "ns");
    }
    {
      std::vector<std::pair<OrbitPoint, std::pair<PointKind, std::string>>> found;
      for (const auto& c : crossed) {
        OrbitPoint p;
        const PointKind test = c.first == PointKind::BranchPoint ? PointKind::Fold : c.first;
        if (options_.locate && locate(b, next, test, p))
          found.emplace_back(std::move(p), c);
        else
          observer.on_note(fmt::format("{} between {} = {:.10g} and {:.10g}: detected, not located", c.second,
                                       problem_.parameters().info(parameter_).name, b.lambda, next.lambda));
      }
      for (double value : options_.stops)
        if ((b.lambda - value) * (next.lambda - value) < 0.0) {
          OrbitPoint p;
          if (land(b, next, value, p))
            found.emplace_back(std::move(p), std::make_pair(PointKind::Requested, std::string("stop")));
          else
            observer.on_note(fmt::format("the orbit at {} = {:.10g} was not found",
                                         problem_.parameters().info(parameter_).name, value));
        }
      std::sort(found.begin(), found.end(), [](const auto& x, const auto& y) { return x.first.s < y.first.s; });
      for (auto& [p, c] : found) {
        report(p, c.first, c.second, ds);
        if (c.first != PointKind::Requested) result.located.push_back(std::move(p));
      }
    }
    ds = std::clamp(next.iterations < options_.target_iterations   ? ds * kGrow
                    : next.iterations > options_.target_iterations ? ds * kShrink
                                                                   : ds,
                    options_.min_step, options_.max_step);
    if (records_grid(next.grid_error)) {
      try {
        next.grid =
            record_grid(problem_, next.u0, next.period, options_.time, options_.shooting.newton, options_.shooting.lu);
      } catch (const std::runtime_error&) {
        // keep the grid it converged on
      }
    }
    a = std::move(b);
    b = std::move(next);
    last = report(b, PointKind::Regular, "", ds);
  }
}

}  // namespace keller
