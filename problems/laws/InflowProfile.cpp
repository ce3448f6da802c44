#include "problems/laws/InflowProfile.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

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
                           0.5917173212478249,   0.7627662049581645,  0.8983332387068134, 0.9801449282487681};
constexpr double kGw[8] = {0.05061426814518813, 0.11119051722668724, 0.15685332293894363, 0.18134189168918100,
                           0.18134189168918100, 0.15685332293894363, 0.11119051722668724, 0.05061426814518813};
constexpr int kPanels = 32;  // over the half-width; shorter stretches get proportionally fewer

}  // namespace

FullyDevelopedProfile::FullyDevelopedProfile(std::function<double(double)> viscosity, double half_width, double U)
    : eta_(std::move(viscosity)), H_(half_width), U_(U) {
  if (!(H_ > 0) || !(U_ > 0)) throw std::invalid_argument("fully developed profile: needs H > 0 and U > 0");
  eta_min_ = INFINITY;
  for (double g = 1e-9; g < 1e12; g *= 10) eta_min_ = std::min(eta_min_, eta_(g * U_ / H_));
  // U(G) increases with G; iterate on log G with the local slope d log U / d log G (1 for a
  // Newtonian fluid, smaller for shear-thinning ones), safeguarded by a bracket
  double G = 3.0 * U_ * eta_(U_ / H_) / (H_ * H_);
  double lo = 0, hi = INFINITY, Um = mean_velocity(G);
  for (int it = 0; it < 100; ++it) {
    if (Um < U_)
      lo = G;
    else
      hi = G;
    if (std::abs(Um - U_) <= 1e-14 * U_) break;
    const double dG = G * 1e-6, slope = std::log(mean_velocity(G + dG) / Um) / std::log1p(1e-6);
    double next = G * std::exp(std::log(U_ / Um) / std::max(slope, 0.05));
    if (!(next > lo && next < hi)) next = std::isfinite(hi) ? (lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi) : 2.0 * G;
    G = next;
    Um = mean_velocity(G);
  }
  G_ = G;
  // a flow curve with a gap (a shear stress whose maximum the profile would have to pass) has no
  // pressure gradient of this mean velocity: U(G) jumps over it
  if (!(std::abs(Um - U_) <= 1e-6 * U_))  // a jump, not the iteration's last digits
    throw std::domain_error("no fully developed profile of mean velocity " + std::to_string(U_) +
                            ": the fluid's flow rate jumps from " + std::to_string(Um) +
                            " as the pressure gradient grows (a shear stress with a maximum; docs/fluids.md)");
  // the construction needs every shear stress up to the wall's to have one shear rate: tau =
  // eta(g) g must not come back down to a value <= tau_wall after rising above it (a maximum,
  // as PTT's with a slip xi and small epsilon and beta has), or the bracketed roots above pick
  // one silently. Beyond tau_wall / eta_min every tau exceeds tau_wall: the scan ends there.
  const double tau_wall = G_ * H_, top = tau_wall / eta_min_;
  double highest = 0.0;
  for (double g = 1e-6 * U_ / H_; g < top; g *= 1.02) {
    const double tau = eta_(g) * g;
    if (tau <= tau_wall && tau < highest * (1.0 - 1e-12))  // rounding aside: a plateau is monotone
      throw std::domain_error(
          "the fluid's steady shear stress falls as the shear rate passes " + std::to_string(g) +
          " (model units), below the wall's: no unique fully developed profile (a shear stress "
          "with a maximum, as PTT's with a slip xi and small epsilon and beta has; docs/fluids.md)");
    highest = std::max(highest, tau);
  }
}

double FullyDevelopedProfile::shear_rate_of_stress(double tau, double guess) const {
  if (tau <= 0) return 0.0;
  // tau = eta(g) g is increasing in g; eta >= eta_min bounds g above
  double lo = 0.0, hi = tau / eta_min_;
  double g = guess > 0 ? std::min(guess, hi) : tau / eta_(tau);
  g = std::clamp(g, 1e-300, hi);
  for (int it = 0; it < 100; ++it) {
    const double r = eta_(g) * g - tau;
    if (r > 0)
      hi = g;
    else
      lo = g;
    const double dg = 1e-7 * g;
    const double slope = (eta_(g + dg) * (g + dg) - eta_(g) * g) / dg;
    double next = g - r / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - g) <= 1e-15 * g;
    g = next;
    if (done || hi - lo <= 1e-15 * hi) break;
  }
  return g;
}

double FullyDevelopedProfile::mean_velocity(double G) const {
  // int_0^H u ds = int_0^H s gdot(G s) ds (by parts, u(H) = 0)
  const double h = H_ / kPanels;
  double sum = 0, guess = -1;
  for (int p = 0; p < kPanels; ++p)
    for (int k = 0; k < 8; ++k) {
      const double s = h * (p + kGx[k]);
      guess = shear_rate_of_stress(G * s, guess);
      sum += kGw[k] * s * guess;
    }
  return sum * h / H_;
}

void FullyDevelopedProfile::evaluate(const std::vector<double>& s_in, std::vector<double>& u,
                                     std::vector<double>& rate) const {
  // u(s) = int_s^H gdot(G t) dt: integrate from the wall inwards through the sorted distances
  std::vector<size_t> order(s_in.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return std::abs(s_in[a]) > std::abs(s_in[b]); });
  u.assign(s_in.size(), 0.0);
  rate.assign(s_in.size(), 0.0);
  double edge = H_, acc = 0.0, guess = -1;
  for (size_t i : order) {
    const double s = std::min(std::abs(s_in[i]), H_);
    const int panels = std::max(1, static_cast<int>(std::ceil((edge - s) / H_ * kPanels)));
    const double h = (edge - s) / panels;
    for (int p = 0; p < panels && h > 0; ++p)
      for (int k = 0; k < 8; ++k) {
        guess = shear_rate_of_stress(G_ * (edge - h * (p + kGx[k])), guess);
        acc += kGw[k] * h * guess;
      }
    edge = s;
    u[i] = acc;
    rate[i] = shear_rate_of_stress(G_ * s, guess);
  }
}

double FullyDevelopedProfile::velocity(double s) const {
  std::vector<double> u, r;
  evaluate({s}, u, r);
  return u[0];
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
      case ProfileKind::FullyDeveloped: break;  // all points at once below
    }
  }
  if (fd) {
    std::vector<double> s(ys.size()), rate;
    for (size_t i = 0; i < ys.size(); ++i) s[i] = std::min(std::abs(ys[i] - yc), H);
    fd->evaluate(s, u, rate);
    for (size_t i = 0; i < ys.size(); ++i) dudy[i] = (ys[i] - yc > 0 ? -1.0 : 1.0) * rate[i];
  }
}

}  // namespace keller
