#include "problems/InflowProfile.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

namespace keller {

const char* to_string(ProfileKind k) {
  switch (k) {
    case ProfileKind::Parabolic: return "parabolic";
    case ProfileKind::PowerLaw: return "power-law";
    case ProfileKind::FullyDeveloped: return "fully-developed";
  }
  return "?";
}

ProfileKind profile_kind_from_string(const std::string& s) {
  for (auto k : {ProfileKind::Parabolic, ProfileKind::PowerLaw, ProfileKind::FullyDeveloped})
    if (s == to_string(k)) return k;
  throw std::invalid_argument("unknown inflow profile '" + s + "' (parabolic, power-law, fully-developed)");
}

namespace {

// 8-point Gauss-Legendre on [0, 1]
constexpr double kGx[8] = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355, 0.4082826787521751,
                           0.5917173212478249, 0.7627662049581645, 0.8983332387068134, 0.9801449282487681};
constexpr double kGw[8] = {0.05061426814518813, 0.11119051722668724, 0.15685332293894363, 0.18134189168918100,
                           0.18134189168918100, 0.15685332293894363, 0.11119051722668724, 0.05061426814518813};
constexpr int kPanels = 64;

template <class F>
double integrate(double a, double b, F&& f) {
  if (b <= a) return 0.0;
  const double h = (b - a) / kPanels;
  double sum = 0;
  for (int p = 0; p < kPanels; ++p)
    for (int k = 0; k < 8; ++k) sum += kGw[k] * f(a + h * (p + kGx[k]));
  return sum * h;
}

}  // namespace

FullyDevelopedProfile::FullyDevelopedProfile(std::function<double(double)> viscosity, double half_width, double U)
    : eta_(std::move(viscosity)), H_(half_width), U_(U) {
  if (!(H_ > 0) || !(U_ > 0)) throw std::invalid_argument("fully developed profile: needs H > 0 and U > 0");
  // bounds of the viscosity over the shear rates that matter, for brackets
  eta_min_ = INFINITY;
  double eta_max = 0;
  for (double g = 1e-12; g < 1e12; g *= 10) {
    eta_min_ = std::min(eta_min_, eta_(g * U_ / H_));
    eta_max = std::max(eta_max, eta_(g * U_ / H_));
  }
  // U(G) increases with G; for a Newtonian fluid U = G H^2 / (3 eta)
  double lo = 3.0 * U_ * eta_min_ / (H_ * H_) * 0.5, hi = 3.0 * U_ * eta_max / (H_ * H_) * 2.0;
  while (mean_velocity(lo) > U_) lo *= 0.5;
  while (mean_velocity(hi) < U_) hi *= 2.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = std::sqrt(lo * hi);
    (mean_velocity(mid) < U_ ? lo : hi) = mid;
  }
  G_ = 0.5 * (lo + hi);
}

double FullyDevelopedProfile::shear_rate_of_stress(double tau) const {
  if (tau <= 0) return 0.0;
  // tau = eta(g) g is increasing in g; eta >= eta_min bounds g above
  double lo = 0.0, hi = tau / eta_min_;
  double g = tau / eta_(tau / eta_min_ * 1e-3 + 1e-300);
  g = std::clamp(g, lo, hi);
  for (int it = 0; it < 200; ++it) {
    const double r = eta_(g) * g - tau;
    if (r > 0) hi = g;
    else lo = g;
    // Newton on r(g) with a numerical slope, kept inside the bracket
    const double dg = 1e-7 * std::max(g, 1e-12);
    const double slope = (eta_(g + dg) * (g + dg) - eta_(g) * g) / dg;
    double next = g - r / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - g) <= 1e-15 * std::max(g, 1e-300) || hi - lo <= 1e-15 * hi) {
      g = next;
      break;
    }
    g = next;
  }
  return g;
}

double FullyDevelopedProfile::mean_velocity(double G) const {
  // int_0^H u ds = int_0^H s gdot(G s) ds (by parts, u(H) = 0)
  return integrate(0.0, H_, [&](double s) { return s * shear_rate_of_stress(G * s); }) / H_;
}

double FullyDevelopedProfile::velocity(double s) const {
  s = std::abs(s);
  return integrate(s, H_, [&](double t) { return shear_rate_of_stress(G_ * t); });
}

double FullyDevelopedProfile::shear_rate(double s) const { return shear_rate_of_stress(G_ * std::abs(s)); }

void InflowProfile::evaluate(const std::vector<double>& ys, double U, const std::function<double(double)>& viscosity,
                             std::vector<double>& u, std::vector<double>& dudy) const {
  const double H = 0.5 * (y_hi - y_lo), yc = 0.5 * (y_hi + y_lo);
  u.resize(ys.size());
  dudy.resize(ys.size());
  std::optional<FullyDevelopedProfile> fd;
  if (kind == ProfileKind::FullyDeveloped) fd.emplace(viscosity, H, U);
  for (size_t i = 0; i < ys.size(); ++i) {
    const double s = ys[i] - yc, xi = std::min(std::abs(s) / H, 1.0);
    const double sign = s > 0 ? -1.0 : 1.0;  // du/dy = -sign(s) |du/ds|
    switch (kind) {
      case ProfileKind::Parabolic:
        u[i] = 1.5 * U * (1.0 - xi * xi);
        dudy[i] = sign * 3.0 * U * xi / H;
        break;
      case ProfileKind::PowerLaw: {
        const double n = power_index;
        u[i] = U * (2 * n + 1) / (n + 1) * (1.0 - std::pow(xi, (n + 1) / n));
        dudy[i] = sign * U * (2 * n + 1) / n * std::pow(xi, 1.0 / n) / H;
        break;
      }
      case ProfileKind::FullyDeveloped:
        u[i] = fd->velocity(xi * H);
        dudy[i] = sign * fd->shear_rate(xi * H);
        break;
    }
  }
}

}  // namespace keller
