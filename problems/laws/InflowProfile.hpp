// Fully developed inflow profiles in a channel between two no-slip walls: parabolic, power-law,
// and the exact profile of the chosen fluid at the requested flow rate. The last is a 1D problem
// solved once per parameter set: in fully developed flow the shear stress is linear across the
// channel, tau(s) = G s (s the distance from the centreline), the shear rate follows from the
// fluid's steady shear viscosity, tau = eta(gdot) gdot, and the pressure gradient G is fixed by
// the mean velocity.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace keller {

enum class ProfileKind { Parabolic, PowerLaw, FullyDeveloped };
const char* to_string(ProfileKind k);
ProfileKind profile_kind_from_string(const std::string& s);  // throws std::invalid_argument

// The fully developed profile of a fluid with steady shear viscosity eta(gdot) (monotone flow
// curve, eta >= eta_min > 0) in a channel of half-width H at mean velocity U. Throws
// std::domain_error where the shear stress eta(g) g falls before the wall's shear rate (no
// unique profile).
class FullyDevelopedProfile {
 public:
  FullyDevelopedProfile(std::function<double(double)> viscosity, double half_width, double mean_velocity);
  double velocity(double s) const;    // u at distance s from the centreline
  double shear_rate(double s) const;  // |du/ds| there
  // Both at many distances at once (one cumulative integration).
  void evaluate(const std::vector<double>& s, std::vector<double>& u, std::vector<double>& shear_rate) const;
  double pressure_gradient() const { return G_; }  // -dP/dx

 private:
  // Shear rate of a shear stress, Newton from `guess` inside a bracket.
  double shear_rate_of_stress(double tau, double guess = -1) const;
  double mean_velocity(double G) const;
  std::function<double(double)> eta_;
  double H_, U_, G_ = 0, eta_min_ = 0;
};

// A profile of any kind: u(y) and du/dy at points of the channel (y_lo, y_hi) for mean velocity U.
struct InflowProfile {
  ProfileKind kind = ProfileKind::Parabolic;
  double y_lo = 0.0, y_hi = 1.0;  // the channel's walls
  double power_index = 0.5;       // power-law index n: u_max / u_mean = (2n + 1) / (n + 1)
  // u and du/dy at each y. For FullyDeveloped, `viscosity` is the fluid's steady shear
  // viscosity at the current parameters (one 1D solve for all points).
  void evaluate(const std::vector<double>& y, double U, const std::function<double(double)>& viscosity,
                std::vector<double>& u, std::vector<double>& dudy) const;
};

}  // namespace keller
