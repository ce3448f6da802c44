// Constitutive laws of model.md, pointwise and templated on the scalar type: the Peterlin
// factor f(M) (FENE-P), the Owens relaxation factor eta_p(gdot) / eta_p0 (Cross model of blood),
// the polymer stress, and the closed forms of steady simple shear and planar elongation used for
// inflow conditions, fully developed profiles and tests. Laws never see meshes.
//
// Units (model.md): stresses in G, velocities in G W / eta0, so eta0 = 1, the solvent
// viscosity is beta, lambda = Wi / Gamma and the polymer modulus is (1 - beta) Gamma / Wi.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace keller {

enum class FluidModel { Newtonian, OldroydB, FeneP, Owens };
const char* to_string(FluidModel m);
FluidModel fluid_model_from_string(const std::string& s);  // throws std::invalid_argument

// Cross model of blood (Fang and Owens): eta_p(gdot) = eta_p0 (1 + theta1 gdot^m) / (1 + theta2 gdot^m)
// with the dimensional shear rate gdot_dim = gdot * rate_scale / Gamma (rate_scale = U0 / W).
struct OwensParameters {
  double eta_p0 = 0.197;    // Pa s
  double eta_pinf = 0.003;  // Pa s
  double eta_s = 0.001;     // Pa s
  double theta2 = 8.0;      // s^m
  double m = 0.75;
  double rate_scale = 100.0;  // U0 / W in 1/s (U0 = 0.01 m/s, W = 100 micrometres)
  // The Cross model's gdot^m has an infinite slope at gdot = 0 (centrelines, stagnation
  // points): gdot_dim is replaced by sqrt(gdot_dim^2 + floor^2), which lowers eta_p by 0.025%
  // at gdot_dim = 0 (theta2 floor^m = 2.5e-4), less elsewhere, and keeps the Jacobian finite.
  double rate_floor = 1e-6;  // 1/s
  double theta1() const { return theta2 * eta_pinf / eta_p0; }
  double beta() const { return eta_s / (eta_s + eta_p0); }
};

// Peterlin factor of FENE-P, f = (b - 1) / (b - tr M / 3) over the full 3x3 tensor. With the
// out-of-plane component eliminated by f M_zz = 1 (steady flow): f = (b - 2/3) / (b - (M_xx + M_yy)/3).
template <class T, class P>
T peterlin_eliminated(const T& mxx, const T& myy, const P& b) {
  return (b - 2.0 / 3.0) / (b - (mxx + myy) / 3.0);
}
template <class T, class P>
T peterlin_full(const T& mxx, const T& myy, const T& mzz, const P& b) {
  return (b - 1.0) / (b - (mxx + myy + mzz) / 3.0);
}

// Owens: eta_p(gdot) / eta_p0, with gdot2 = 2 D:D of the (interpolated) velocity gradient in
// model units and Gamma the velocity scale.
template <class T, class P>
T owens_factor(const T& gdot2, const P& Gamma, const OwensParameters& o) {
  using std::pow;
  using std::sqrt;
  const double s = o.rate_scale;
  const T rate2 = gdot2 * (s * s) / (Gamma * Gamma) + o.rate_floor * o.rate_floor;
  const T x = pow(rate2, 0.5 * o.m);  // gdot_dim^m
  return (1.0 + o.theta1() * x) / (1.0 + o.theta2 * x);
}

// The conformation tensor as the constitutive equation sees it: in-plane components and zz.
template <class T>
struct Conformation {
  T xx, xy, yy, zz;
};

// Peterlin factor of the model (1 except FENE-P); dynamic_zz: M_zz is an unknown.
template <class T, class P>
T peterlin(FluidModel model, bool dynamic_zz, const Conformation<T>& M, const P& b) {
  if (model != FluidModel::FeneP) return T(1.0);
  return dynamic_zz ? peterlin_full(M.xx, M.yy, M.zz, b) : peterlin_eliminated(M.xx, M.yy, b);
}

// Upper-convected rate without convection: R = -(L M + M L^T) + (f M - I) / lambda_eff
// (components xx, xy, yy, zz; zz has no stretching in planar flow). A steady homogeneous
// state has R = 0. L[i][j] = d v_i / d x_j.
template <class T, class G, class I>
Conformation<T> conformation_rate(const Conformation<T>& M, const G (&L)[2][2], const T& f, const I& inv_lambda) {
  const T sxx = 2.0 * (L[0][0] * M.xx + L[0][1] * M.xy);
  const T sxy = L[0][0] * M.xy + L[0][1] * M.yy + M.xx * L[1][0] + M.xy * L[1][1];
  const T syy = 2.0 * (L[1][0] * M.xy + L[1][1] * M.yy);
  return {inv_lambda * (f * M.xx - 1.0) - sxx, inv_lambda * (f * M.xy) - sxy, inv_lambda * (f * M.yy - 1.0) - syy,
          inv_lambda * (f * M.zz - 1.0)};
}

// Polymer stress tau_p = modulus (f M - I), modulus = (1 - beta) Gamma / Wi.
template <class T, class P>
Conformation<T> polymer_stress(const Conformation<T>& M, const T& f, const P& modulus) {
  return {modulus * (f * M.xx - 1.0), modulus * (f * M.xy), modulus * (f * M.yy - 1.0), modulus * (f * M.zz - 1.0)};
}

// Closed forms of steady homogeneous flows (double precision).
struct SteadyConformation {
  double xx = 1, xy = 0, yy = 1, zz = 1;
  double f = 1;  // Peterlin factor (1 except FENE-P)
};
// Simple shear v = (gdot y, 0) at Weissenberg number W = lambda_eff gdot (signed).
// Oldroyd-B/Owens: M_xx = 1 + 2 W^2, M_xy = W, M_yy = M_zz = 1. FENE-P: f solves
// f^2 (f - 1) = 2 W^2 / (3 b), M_yy = M_zz = 1/f, M_xy = W/f^2, M_xx = (1 + 2 W^2/f^2)/f.
SteadyConformation steady_shear(FluidModel model, double W, double b);
// Planar elongation v = (eps x, -eps y) at W = lambda eps: M_xx = 1/(f - 2W), M_yy = 1/(f + 2W),
// M_zz = 1/f; f from its definition (Oldroyd-B: f = 1, needs W < 1/2).
SteadyConformation planar_elongation(FluidModel model, double W, double b);

// The steady shear viscosity eta(gdot) / eta0 in model units: beta + (1 - beta) * g, g = 1
// (Oldroyd-B), 1/f(lambda gdot) (FENE-P), eta_p(gdot)/eta_p0 (Owens); 1 for Newtonian.
double shear_viscosity(FluidModel model, double gdot, double Wi, double Gamma, double beta, double b,
                       const OwensParameters& owens);

}  // namespace keller
