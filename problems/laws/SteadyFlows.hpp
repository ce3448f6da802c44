// Steady homogeneous flows of each law (ConstitutiveLaw.hpp) in closed form or by a scalar root,
// in double precision: the states of steady simple shear and of planar and uniaxial extension,
// and the steady shear viscosity. They give inflow conditions and fully developed profiles, and
// tests compare the traced rheometry problems with them.
//
// With W = lambda_eff x rate and tau = M - I (the polymer stress over the modulus for every law
// but the FENE ones):
//   shear, Oldroyd-B/Owens  M_xx = 1 + 2 W^2, M_xy = W, M_yy = M_zz = 1;
//   FENE-P                  f^2 (f - 1) = 2 W^2 / (3 b), M_yy = M_zz = 1/f, M_xy = W/f^2,
//                           M_xx = (1 + 2 W^2/f^2)/f;
//   FENE-CR                 f = (1 + sqrt(1 + 8 W^2 / (3 (b - 1)))) / 2, M_xy = W/f, M_xx = 1 + 2 W^2/f^2;
//   Giesekus                the closed form of Bird, Armstrong and Hassager (1987), in the
//                           cancellation-free form of SteadyFlows.cpp;
//   PTT                     tau_xy = W Y / (Y^2 + W^2 xi (2 - xi)), tau_xx = W (2 - xi) tau_xy / Y,
//                           tau_yy = -W xi tau_xy / Y, Y = Y(tau_xx + tau_yy) a scalar root.
//   extension, rates w_i = lambda_eff L_ii on the diagonal (planar (W, -W, 0), uniaxial
//   (W, -W/2, -W/2)): tau_i = 2 w_i / (1 - 2 w_i) (Oldroyd-B), 2 w_i / (Y - 2 (1 - xi) w_i) (PTT),
//   2 w_i / (f - 2 w_i) (FENE-CR), M_i = 1 / (f - 2 w_i) (FENE-P), the root of
//   alpha tau^2 + (1 - 2 w) tau - 2 w = 0 (Giesekus).
#pragma once

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

struct SteadyConformation {
  double xx = 1, xy = 0, yy = 1, zz = 1;
  double f = 1;  // the law's factor (Relaxation::factor): Peterlin f, PTT's Y, 1 otherwise
};

// Simple shear v = (gdot y, 0) at W = lambda_eff gdot (signed).
SteadyConformation steady_shear(FluidModel model, double W, const LawConstants<double>& c);

enum class Extension { Planar, Uniaxial };
const char* to_string(Extension e);
// Extension along x at W = lambda_eff eps >= 0: planar v = (eps x, -eps y), uniaxial
// v = (eps x, -eps y / 2, -eps z / 2). Throws std::domain_error where the law has no steady state
// (Oldroyd-B at 2 W >= 1, PTT with epsilon = 0 at 2 (1 - xi) W >= 1).
SteadyConformation steady_extension(FluidModel model, Extension kind, double W, const LawConstants<double>& c);

// The polymer's share of the steady shear viscosity, eta_p(W) / eta_p0 (1 at W = 0).
double polymer_shear_ratio(FluidModel model, double W, const LawConstants<double>& c);

// The steady shear viscosity eta(gdot) / eta0 in model units: beta + (1 - beta) g, g the
// polymer_shear_ratio at W = lambda gdot (Owens: the Cross factor eta_p(gdot)/eta_p0); 1 for Newtonian.
double shear_viscosity(FluidModel model, double gdot, double Wi, double Gamma, double beta,
                       const LawConstants<double>& c, const OwensParameters& owens);

}  // namespace keller
