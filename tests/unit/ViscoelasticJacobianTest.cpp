// Exact Jacobians of the viscoelastic equations: every fluid (Giesekus alpha = 0.3, PTT epsilon =
// 0.25 with xi = 0.1 in the conformation form, FENE-CR b = 20), both formulations, both SUPG time
// scales, FENE-P with M_zz eliminated and as an unknown, on curved distorted elements, at random
// states and at M = I exactly (where the log-conformation algebra takes its series branches);
// multi-mode fluids (two modes of different times and shares: PolymerModeKernel); and every dF/dp
// (the law's constants and the modes' times among them). Fails above a relative error of 1e-6.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <random>

#include "problems/channel/ChannelProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

struct Case {
  FluidModel model;
  bool log_form;
  bool dynamic_zz;
  bool supg_local;
  bool at_identity;  // conformation exactly I (Psi = 0)
  bool two_modes = false;
};

std::string label(const Case& c) {
  return std::string(to_string(c.model)) + (c.log_form ? " log" : " conf") + (c.dynamic_zz ? " zz" : "") +
         (c.supg_local ? " local" : " global") + (c.at_identity ? " M=I" : "") + (c.two_modes ? " two modes" : "");
}

void check(const Case& c) {
  SCOPED_TRACE(label(c));
  ChannelOptions o;
  o.mesh.name = "custom";
  o.mesh.nx_upstream = 1;
  o.mesh.nx_deformable = 2;
  o.mesh.nx_downstream = 1;
  o.mesh.ny_fluid = 2;
  o.Gamma = 0.5;
  o.fluid.model = c.model;
  o.fluid.log_conformation = c.log_form;
  o.fluid.dynamic_zz = c.dynamic_zz;
  o.fluid.kernel.supg.local = c.supg_local;
  o.fluid.Wi = 0.7;
  o.fluid.beta = 0.3;
  o.fluid.constants.b = 20.0;
  o.fluid.constants.alpha = 0.3;
  o.fluid.constants.epsilon = 0.25;
  o.fluid.constants.xi = c.log_form ? 0.0 : 0.1;  // the log form has no slip
  o.fluid.Re = 2.0;
  o.fluid.inertia = true;
  o.fluid.profile = c.model == FluidModel::Newtonian ? ProfileKind::Parabolic : ProfileKind::FullyDeveloped;
  if (c.two_modes) o.fluid.modes = {{"slow", 1.3, 0.6}, {"fast", 0.2, 0.4}};
  Mesh mesh = build_channel_mesh(o.geometry, o.mesh, false);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<int> ends = mesh.boundary_nodes("inflow"), outflow = mesh.boundary_nodes("outflow");
  ends.insert(ends.end(), outflow.begin(), outflow.end());
  std::sort(ends.begin(), ends.end());
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    auto p = mesh.node(n);
    const double dx = 0.06 * U(rng);
    // the inflow and outflow stay lines x = const (fully developed flow needs them): their nodes slide along them
    if (!std::binary_search(ends.begin(), ends.end(), n)) p[0] += dx;
    p[1] += 0.03 * U(rng);
    mesh.set_node(n, p);
  }
  ChannelProblem problem(o, mesh);
  Vector u = problem.initial_guess();
  const DofMap& d = problem.dofs();
  for (int i = 0; i < u.size(); ++i) u[i] += 0.2 * U(rng) * (std::abs(u[i]) + 0.1);
  // a symmetric positive definite conformation (or its log) at every node, in every mode
  for (int fm = 0; fm < d.num_fields(); ++fm)
    if (d.field(fm).name.rfind("conformation", 0) == 0) {
      ASSERT_TRUE(fm == d.field_index("conformation") || c.two_modes);
      for (int n = 0; n < mesh.num_nodes(); ++n) {
        if (d.node_dof(fm, n, 0) < 0) continue;
        const int nc = d.num_components(fm);
        for (int k = 0; k < nc; ++k) {
          double v = 0;
          if (!c.at_identity)
            v = c.log_form ? 0.4 * U(rng) : (k == 1 ? 0.3 * U(rng) : 1.2 + 0.4 * U(rng));
          else
            v = c.log_form ? 0.0 : (k == 1 ? 0.0 : 1.0);
          u[d.node_dof(fm, n, k)] = v;
        }
      }
    }
  const auto jc = test::check_problem_jacobian(problem, u);
  std::cout << label(c) << ": Jacobian max relative error " << jc.max_relative_error << " (row "
            << d.describe(jc.worst_row) << ")\n";
  EXPECT_LT(jc.max_relative_error, 1e-6);
  for (const Parameter& p : problem.parameters().list()) {
    const double e = test::check_parameter_derivative(problem, problem.parameters().index(p.name), u);
    EXPECT_LT(e, 1e-6) << "dF/d" << p.name;
  }
}

}  // namespace

const FluidModel kLaws[] = {FluidModel::OldroydB,  FluidModel::FeneP,          FluidModel::Owens, FluidModel::Giesekus,
                            FluidModel::PttLinear, FluidModel::PttExponential, FluidModel::FeneCr};

TEST(ViscoelasticJacobian, EveryFluidAndFormulation) {
  for (FluidModel m : kLaws)
    for (bool log_form : {false, true}) check({m, log_form, false, true, false});
}

TEST(ViscoelasticJacobian, FenePWithDynamicZz) {
  for (bool log_form : {false, true}) check({FluidModel::FeneP, log_form, true, true, false});
}

TEST(ViscoelasticJacobian, TwoModesOfEveryFluidAndFormulation) {
  for (FluidModel m : kLaws)
    for (bool log_form : {false, true}) check({m, log_form, false, true, false, true});
  check({FluidModel::FeneP, false, true, true, false, true});
}

TEST(ViscoelasticJacobian, GlobalSupg) { check({FluidModel::OldroydB, false, false, false, false}); }

TEST(ViscoelasticJacobian, LogConformationAtIdentity) {
  for (FluidModel m : kLaws) check({m, true, false, true, true});
  check({FluidModel::FeneP, true, true, true, true});
}
