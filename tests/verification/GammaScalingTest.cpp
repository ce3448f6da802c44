// The rigid-channel solution scales with Gamma at fixed Wi (model.md's units): lengths scale
// with W, velocities with G W / eta0 and stresses with G, so the dimensional flow at fixed Wi
// and beta does not depend on G, and the dimensionless one at Gamma is Gamma times a fixed
// field: v / Gamma, P / Gamma, L / Gamma and M are the same at every Gamma, for every fluid.
// Every term of the discrete equations keeps this (lambda = Wi / Gamma, the polymer modulus
// (1 - beta) Gamma / Wi, the SUPG time h / |v| with its floor a fraction of Gamma, the Owens
// shear rate gdot U0 / (Gamma W), the inflow profile and state, Re / Gamma with v^2), so the
// discrete solutions must agree to rounding. "Rounding" here: Newton runs to |F| <= 1e-12 Gamma
// and converges quadratically, so its last step leaves each solution within rounding of its
// discrete solution; the scaled fields are compared to 1e-12 relative to their largest value,
// the Newton tolerance itself, which the measured differences (at most 1.5e-14, about 70 units
// of roundoff) stay far below. A term that broke the scaling (a Gamma-independent floor or
// tolerance, lambda or the modulus without their Gamma) would differ by far more.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/Newton.hpp"
#include "problems/channel/ChannelProblem.hpp"

using namespace keller;

namespace {

struct Case {
  FluidModel model;
  bool log_form;
  double Re;
};

// The unknowns with velocity, pressure and gradient divided by Gamma, by field.
std::vector<Vector> scaled_solution(const Case& c, double Gamma) {
  ChannelOptions o;
  o.geometry = {2.0, 2.0, 2.0, 0.4};
  o.mesh.name = "custom";
  o.mesh.nx_upstream = 3;
  o.mesh.nx_deformable = 4;
  o.mesh.nx_downstream = 3;
  o.mesh.ny_fluid = 4;
  o.Gamma = Gamma;
  o.fluid.model = c.model;
  o.fluid.log_conformation = c.log_form;
  o.fluid.Re = c.Re;
  o.fluid.inertia = c.Re > 0;
  o.fluid.Wi = c.model == FluidModel::Owens ? 2.0 : 0.5;
  o.fluid.beta = c.model == FluidModel::Owens ? OwensParameters().beta() : 0.3;
  o.fluid.constants.b = 20.0;
  o.fluid.profile = c.model == FluidModel::Newtonian ? ProfileKind::Parabolic : ProfileKind::FullyDeveloped;
  ChannelProblem p(o);
  Vector u = p.initial_guess();
  NewtonOptions no;
  no.residual_tolerance = 1e-12;
  no.update_tolerance = 1e-14;
  NewtonSolver newton(p, no);
  const NewtonResult r = newton.solve(u);
  EXPECT_TRUE(r.converged()) << r.status.describe();
  const DofMap& d = p.dofs();
  std::vector<Vector> out;
  for (int f = 0; f < d.num_fields(); ++f) {
    std::vector<double> vals;
    const bool scaled = d.field(f).name != "conformation";
    for (int n = 0; n < p.mesh().num_nodes(); ++n)
      for (int k = 0; k < d.num_components(f); ++k)
        if (d.field(f).basis != Basis::P1Disc && d.node_dof(f, n, k) >= 0) vals.push_back(u[d.node_dof(f, n, k)]);
    if (d.field(f).basis == Basis::P1Disc)
      for (int e = 0; e < p.mesh().num_elements(); ++e)
        for (int k = 0; k < 3; ++k) vals.push_back(u[d.element_dof(f, e, k, 0)]);
    Vector v = Eigen::Map<Vector>(vals.data(), static_cast<long>(vals.size()));
    if (scaled) v /= Gamma;
    out.push_back(v);
  }
  return out;
}

void check(const Case& c) {
  const std::vector<Vector> ref = scaled_solution(c, 1.0);
  for (double Gamma : {4.95e-5, 6.6e-4}) {
    const std::vector<Vector> s = scaled_solution(c, Gamma);
    for (size_t f = 0; f < ref.size(); ++f) {
      const double diff = (s[f] - ref[f]).cwiseAbs().maxCoeff() / ref[f].cwiseAbs().maxCoeff();
      std::printf("%s%s%s Gamma = %.3g field %zu: max relative difference %.2e\n", to_string(c.model),
                  c.model == FluidModel::Newtonian ? "" : (c.log_form ? " log" : " conf"), c.Re > 0 ? " Re" : "", Gamma,
                  f, diff);
      EXPECT_LT(diff, 1e-12) << "field " << f << " at Gamma = " << Gamma;
    }
  }
}

}  // namespace

TEST(GammaScaling, Newtonian) {
  check({FluidModel::Newtonian, false, 0.0});
  check({FluidModel::Newtonian, false, 5.0});
}
TEST(GammaScaling, OldroydB) {
  check({FluidModel::OldroydB, false, 0.0});
  check({FluidModel::OldroydB, true, 0.0});
}
TEST(GammaScaling, FeneP) {
  check({FluidModel::FeneP, false, 0.0});
  check({FluidModel::FeneP, true, 0.0});
}
TEST(GammaScaling, Owens) {
  check({FluidModel::Owens, false, 0.0});
  check({FluidModel::Owens, true, 0.0});
}
