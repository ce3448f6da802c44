#include "core/JacobianCheck.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace keller {

namespace {

// the central differences' steps, relative: O(h^2) truncation against O(eps / h) rounding, whose
// balance depends on the problem; the error reported is the smallest over the steps, which a
// wrong derivative keeps at every step
constexpr double kSteps[] = {1e-4, 1e-5, 1e-6, 1e-7};

// |a - b|_inf / max(|a|_inf, |b|_inf, floor): 0 where both vanish
double relative_error(const Vector& a, const Vector& b, double floor = 0.0) {
  const double scale = std::max({a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>(), floor});
  if (!(scale > 0)) return 0.0;
  return (a - b).lpNorm<Eigen::Infinity>() / scale;
}

// r_i (1 + |u_i|), r_i uniform in [-1, 1]: each unknown moved relative to its own size (a
// position and a pressure of very different magnitudes each by its own)
Vector random_direction(const Vector& u, std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Vector v(u.size());
  for (Eigen::Index i = 0; i < u.size(); ++i) v[i] = d(rng) * (1.0 + std::abs(u[i]));
  return v;
}

// The largest error of J v over the directions at u; the errors of dF/dp folded into perr, the
// parameters without room for a difference marked in checked.
Status check_at(Problem& problem, const Vector& u, const JacobianCheckOptions& o, std::mt19937& rng, double& error,
                std::vector<double>& perr, std::vector<bool>& checked) {
  Vector F, Fp, Fm;
  SparseMatrix J;
  if (Status st = problem.jacobian(u, F, J); !st.is_ok()) return st;
  error = 0.0;
  double moves = 0.0;  // the largest |J v|_inf: how much F moves with the unknowns
  for (int d = 0; d < o.directions; ++d) {
    const Vector v = random_direction(u, rng), Jv = J * v;
    moves = std::max(moves, Jv.lpNorm<Eigen::Infinity>());
    double best = INFINITY;
    Status last;
    for (double h : kSteps) {
      last = problem.residual(u + h * v, Fp);
      if (last.is_ok()) last = problem.residual(u - h * v, Fm);
      if (last.code() == StatusCode::InvalidState) continue;  // a step out of the domain: the smaller ones
      if (!last.is_ok()) return last;
      best = std::min(best, relative_error(Jv, (Fp - Fm) / (2.0 * h)));
    }
    if (!std::isfinite(best)) return last;
    error = std::max(error, best);
  }
  ParameterSet& ps = problem.parameters();
  for (int p = 0; p < ps.size(); ++p) {
    const double value = ps.value(p);
    // a parameter without room for Problem::parameter_derivative's difference (Re = 0 of a Stokes
    // run, whose range is [0, 0]) has no derivative to check
    if (const auto [lo, hi] = ps.difference_points(p, 1e-6 * std::max(1.0, std::abs(value))); hi == lo) {
      checked[static_cast<size_t>(p)] = false;
      continue;
    }
    Vector dF;
    if (Status st = problem.parameter_derivative(p, u, dF); !st.is_ok()) return st;
    // a derivative in p below 1e-6 of F's in the unknowns (per the same relative move) hardly moves
    // F: its errors count against that scale (dF/dbeta of a fluid at rest is rounding)
    const double floor = 1e-6 * moves / std::max(1.0, std::abs(value));
    double best = INFINITY;
    for (double step : kSteps) {
      const double h = step * std::max(1.0, std::abs(value));
      const auto [lo, hi] = ps.difference_points(p, h);
      if (hi == lo) continue;  // no room for this step
      ps.set(p, hi);
      Status st = problem.residual(u, Fp);
      if (st.is_ok()) {
        ps.set(p, lo);
        st = problem.residual(u, Fm);
      }
      ps.set(p, value);
      if (st.code() == StatusCode::InvalidState) continue;
      if (!st.is_ok()) return st;
      best = std::min(best, relative_error(dF, (Fp - Fm) / (hi - lo), floor));
    }
    if (std::isfinite(best)) perr[static_cast<size_t>(p)] = std::max(perr[static_cast<size_t>(p)], best);
  }
  return {};
}

}  // namespace

bool JacobianCheckResult::passed(double tolerance) const {
  const auto within = [tolerance](double e) { return e <= tolerance; };
  return status.is_ok() && std::all_of(state_errors.begin(), state_errors.end(), within) &&
         std::all_of(parameter_errors.begin(), parameter_errors.end(), within);
}

std::string JacobianCheckResult::describe() const {
  std::string out;
  for (size_t i = 0; i < states.size(); ++i)
    out += fmt::format("  J v at {}: relative error {:.2e} (largest over the random directions)\n", states[i],
                       state_errors[i]);
  for (size_t p = 0; p < parameters.size(); ++p)
    out += parameter_checked[p]
               ? fmt::format("  dF/d{}: relative error {:.2e}\n", parameters[p], parameter_errors[p])
               : fmt::format("  dF/d{}: not checked (no room for a difference inside its range)\n", parameters[p]);
  if (!status.is_ok()) out += "  failed to evaluate: " + status.describe() + "\n";
  return out;
}

JacobianCheckResult check_jacobian(Problem& problem, const Vector& u, const JacobianCheckOptions& o) {
  JacobianCheckResult r;
  std::mt19937 rng(o.seed);
  const ParameterSet& ps = problem.parameters();
  for (int p = 0; p < ps.size(); ++p) r.parameters.push_back(ps.info(p).name);
  r.parameter_errors.assign(r.parameters.size(), 0.0);
  r.parameter_checked.assign(r.parameters.size(), true);
  double error = 0.0;
  r.status = check_at(problem, u, o, rng, error, r.parameter_errors, r.parameter_checked);
  if (!r.status.is_ok()) return r;
  r.states.push_back("the state");
  r.state_errors.push_back(error);
  // a state near u: terms that vanish at u (a cubic at u = 0) are checked there
  const Vector dir = random_direction(u, rng);
  for (double size = o.perturbation; size >= 1e-4 * o.perturbation; size *= 0.1) {
    const Vector near = u + size * dir;
    const Status st = check_at(problem, near, o, rng, error, r.parameter_errors, r.parameter_checked);
    if (st.code() == StatusCode::InvalidState) continue;
    r.status = st;
    if (st.is_ok()) {
      r.states.push_back(fmt::format("the state perturbed by {:.0e}", size));
      r.state_errors.push_back(error);
    }
    break;
  }
  return r;
}

}  // namespace keller
