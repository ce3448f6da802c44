// The shooting map's grid (OrbitGrid, record_grid) and its options' policies (ShootingOptions),
// declared in ShootingMap.hpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "continuation/orbits/ShootingMap.hpp"
#include "continuation/time/TimeIntegrator.hpp"

namespace keller {

OrbitGrid OrbitGrid::from_times(double t0, const std::vector<double>& times, TimeOptions::Method method) {
  const size_t least = method == TimeOptions::Method::Bdf2 ? 3 : 1;
  if (times.size() < least)
    throw std::invalid_argument(fmt::format("orbit grid: {} steps (at least {})", times.size(), least));
  const double period = times.back() - t0;
  OrbitGrid g;
  g.method = method;
  double before = t0;
  for (double t : times) {
    if (!(t > before)) throw std::invalid_argument("orbit grid: the times do not increase");
    g.fractions.push_back((t - t0) / period);
    before = t;
  }
  g.fractions.back() = 1.0;
  return g;
}

OrbitGrid record_grid(Problem& problem, const Vector& u0, double period, const TimeOptions& options,
                      const NewtonOptions& newton, const SparseLUOptions& lu) {
  class Times final : public TimeObserver {
   public:
    void on_step(const TimePoint& p) override {
      if (p.step > 0) times.push_back(p.t);
    }
    void on_rejected(double, double, const std::string& why) override { last_rejection = why; }
    std::vector<double> times;
    std::string last_rejection;
  };
  TimeOptions o = options;
  o.t_end = period;
  SparseLUOptions small = ShootingOptions::chord_lu(lu);
  small.backend = ShootingOptions::backend_for(lu.backend, problem.size());
  TimeIntegrator integrator(problem, o, newton, small);
  Times times;
  const TimeResult r = integrator.run(u0, 0.0, times);
  if (r.code != TimeStop::End)
    throw std::runtime_error(
        "orbit grid: the run over one period ended early: " + r.reason +
        (times.last_rejection.empty() ? "" : " (the last rejected step: " + times.last_rejection + ")"));
  return OrbitGrid::from_times(0.0, times.times, options.method);
}

NewtonOptions ShootingOptions::tight_newton() {
  NewtonOptions o;
  o.residual_tolerance = 1e-13;
  o.update_tolerance = 1e-14;
  o.max_iterations = 30;
  return o;
}

ShootingOptions::Linearisation ShootingOptions::linearisation_for(Linearisation asked, int n, bool mass_varies,
                                                                  double bytes, long solves, double budget) {
  if (asked != Linearisation::Auto) return asked;
  if (n > kFactorisedSize || mass_varies) return Linearisation::Preconditioned;
  return bytes * static_cast<double>(solves) <= budget ? Linearisation::Factorised : Linearisation::Preconditioned;
}

double ShootingOptions::anchor_drift(const Vector& u0_then, const Vector& u0_now, const std::vector<double>& then,
                                     const std::vector<double>& now) {
  if (u0_then.size() != u0_now.size() || then.size() != now.size()) return std::numeric_limits<double>::infinity();
  double drift = 0.0;
  auto take = [&drift](double change, double size) {
    const double d = change / std::max(1.0, size);
    drift = d <= drift ? drift : d;  // a NaN, not <=, wins
  };
  if (u0_then.size() > 0) take((u0_now - u0_then).lpNorm<Eigen::Infinity>(), u0_then.lpNorm<Eigen::Infinity>());
  for (size_t i = 0; i < then.size(); ++i) take(std::abs(now[i] - then[i]), std::abs(then[i]));
  return std::isnan(drift) ? std::numeric_limits<double>::infinity() : drift;
}

SparseLUOptions ShootingOptions::chord_lu(SparseLUOptions lu) {
  lu.refinement_steps = 0;
  return lu;
}

SparseLUOptions::Backend ShootingOptions::backend_for(SparseLUOptions::Backend asked, int n) {
  return asked == SparseLUOptions::Backend::Auto && n <= kUmfpackSize ? SparseLUOptions::Backend::Umfpack : asked;
}

}  // namespace keller
