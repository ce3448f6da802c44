// The coupled collapsible channel with a Newtonian fluid on M1: flow rate Gamma through every
// mesh column of the deformed mesh, the solid's area, and force balance at the interface (the
// weak reaction the solid receives against the directly integrated fluid traction, weighted by
// the same test functions: they agree to discretisation error, which falls under refinement).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/Newton.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"

using namespace keller;

namespace {

struct Solved {
  std::unique_ptr<CollapsibleChannelProblem> problem;
  Vector u;
};

Solved solve(const std::string& mesh, double Gamma, double Pe = CollapsibleOptions{}.Pe) {
  CollapsibleOptions o;
  o.mesh = ChannelMeshSpec::preset(mesh);
  o.Gamma = Gamma;
  o.Pe = Pe;
  o.fluid.model = FluidModel::Newtonian;
  Solved s{std::make_unique<CollapsibleChannelProblem>(o), {}};
  s.u = s.problem->initial_guess();
  NewtonSolver newton(*s.problem);
  const NewtonResult r = newton.solve(s.u, [](const NewtonIteration& it) { print_newton_row(it); });
  EXPECT_TRUE(r.converged()) << r.status.describe();
  return s;
}

}  // namespace

TEST(CollapsibleChannel, FlowRateThroughEveryColumnAndSolidArea) {
  for (double Gamma : {4.95e-5, 6.6e-4}) {
    Solved s = solve("M1", Gamma);
    const auto obs = [&](const char* name) { return s.problem->observable(name, s.u); };
    std::printf("Gamma %.3g: dy_max %.6f at dx %.6f, gap %.6f, dP %.6e\n", Gamma, obs("dy_max"), obs("dx_max"),
                obs("gap_min"), obs("dP"));
    double worst = 0;
    for (double q : s.problem->column_flow_rates(s.u)) worst = std::max(worst, std::abs(q - Gamma) / Gamma);
    std::printf("  flow rate: max relative deviation from Gamma over %zu columns %.2e\n",
                s.problem->column_flow_rates(s.u).size(), worst);
    EXPECT_LT(worst, 1e-10);
    EXPECT_LT(std::abs(obs("area_change")), 1e-10 * s.problem->wall().reference_area());
    EXPECT_GT(s.problem->min_mesh_jacobian(s.u), 0.0);
    if (Gamma < 1e-4)
      EXPECT_LT(obs("dy_max"), -0.3);  // collapse
    else
      EXPECT_GT(obs("dy_max"), 0.1);  // bulge
  }
}

// The two pressure drops against Poiseuille's where the wall barely moves: without external
// pressure the wall carries only the flow's own load, whose pressures scale with Gamma (pressures
// are in units of the solid's modulus): its deflection is linear in Gamma, about 1e4 Gamma for
// this long thick-walled section (9.3e-4 at Gamma = 1e-7), 1e-5 at Gamma = 1e-9. Poiseuille flow
// (mean velocity Gamma, width 1, viscosity 1) drops the pressure by 12 Gamma per unit length, which
// Q2-P1disc represents exactly: 12 Gamma (Lu + L + Ld) = 228 Gamma from inlet to outlet, 12 Gamma L
// = 60 Gamma over the deformable section. A height change dh over the section changes its drop by
// about 3 dh / h, so both stay within a few |dy_max| of Poiseuille's (bounds 2 |dy_max| and 6
// |dy_max| relative, plus rounding).
TEST(CollapsibleChannel, PressureDropsArePoiseuillesWhereTheWallBarelyMoves) {
  const double Gamma = 1e-9;
  Solved s = solve("M1", Gamma, 0.0);
  const double dy = std::abs(s.problem->observable("dy_max", s.u));
  const double io = s.problem->observable("dP_inlet_outlet", s.u), section = s.problem->observable("dP", s.u);
  std::printf("Gamma %.1e, Pe 0: dy_max %.3e, dP_inlet_outlet / 228 Gamma - 1 = %.3e, dP / 60 Gamma - 1 = %.3e\n",
              Gamma, dy, io / (228 * Gamma) - 1, section / (60 * Gamma) - 1);
  EXPECT_LT(dy, 1e-4);
  EXPECT_NEAR(io / (228 * Gamma), 1.0, 2 * dy + 1e-9);
  EXPECT_NEAR(section / (60 * Gamma), 1.0, 6 * dy + 1e-9);
}

TEST(CollapsibleChannel, FluidForceOnTheWallIsTheIntegratedTraction) {
  double previous = INFINITY;
  for (const char* mesh : {"M1", "M2"}) {
    Solved s = solve(mesh, 4.95e-5);
    const auto weak = s.problem->fluid_force_on_wall(s.u);
    const auto direct = s.problem->interface_traction_integral(s.u);
    const double scale = std::hypot(weak[0], weak[1]);
    const double diff = std::hypot(weak[0] - direct[0], weak[1] - direct[1]) / scale;
    std::printf(
        "%s: force of the fluid on the wall: weak reaction (%.8e, %.8e), traction integral (%.8e, %.8e), "
        "relative difference %.2e\n",
        mesh, weak[0], weak[1], direct[0], direct[1], diff);
    // the discrete stress at the boundary converges at about second order (Q2 velocity, P1
    // pressure): 4e-5 on M1, 1.5e-5 on M2 (h ratio 1.5)
    EXPECT_LT(diff, 1e-4);
    EXPECT_LT(diff, previous / 2);
    previous = diff;
  }
}
